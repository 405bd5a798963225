"""Rust errors come back as `vcuts.VcutsError` with the same message (file, key, object)."""

from __future__ import annotations

import numpy as np
import pytest

import vcuts


def test_missing_and_damaged_files(tmp_path, balls) -> None:
    with pytest.raises(vcuts.VcutsError, match="nothing.vcuts"):
        vcuts.open(tmp_path / "nothing.vcuts")
    bad = tmp_path / "cut.vcuts"
    data = balls.read_bytes()
    bad.write_bytes(data[: len(data) // 2])
    with pytest.raises(vcuts.VcutsError, match="cut.vcuts"):
        vcuts.open(bad)


def test_bad_scene_values_name_the_key(tmp_path) -> None:
    scene = tmp_path / "bad.toml"
    scene.write_text('[[object]]\nsource = "builtin:sphere"\nsize = -1.0\n')
    with pytest.raises(vcuts.VcutsError, match="size"):
        vcuts.Scene(str(scene))
    with pytest.raises(vcuts.VcutsError, match="bad.toml"):
        vcuts.precompute(str(scene), progress=False, output=tmp_path / "x.vcuts")


def test_bad_parameters_name_the_option(tmp_path) -> None:
    with pytest.raises(vcuts.VcutsError, match="directions"):
        vcuts.precompute("builtin:spheres", output=tmp_path / "x.vcuts", progress=False, directions=100)
    with pytest.raises(vcuts.VcutsError, match="no_such_key"):
        vcuts.precompute("builtin:spheres", output=tmp_path / "x.vcuts", progress=False, no_such_key=3)
    with pytest.raises(vcuts.VcutsError, match="preset"):
        vcuts.precompute("builtin:spheres", "fastest", output=tmp_path / "x.vcuts", progress=False)


def test_bad_edits_name_the_object_and_value(balls) -> None:
    f = vcuts.open(balls)
    with pytest.raises(vcuts.VcutsError, match="no object 'teapot'"):
        f.translate("teapot", (0, 0, 0))
    with pytest.raises(vcuts.VcutsError, match="object 7"):
        f.translate(7, (0, 0, 0))
    with pytest.raises(vcuts.VcutsError, match="kd"):
        f.set_brdf("ball", "lambert:kd=2")
    with pytest.raises(vcuts.VcutsError, match="roughness"):
        f.set_brdf("ball", "ggx:roughness=7")
    with pytest.raises(vcuts.VcutsError, match="finite"):
        f.translate("ball", (float("nan"), 0, 0))
    before = f.translation("ball")
    with pytest.raises(vcuts.VcutsError, match=r"\(ball\) moved to .*f32 holds"):
        f.translate("ball", (1e8, 1e8, 1e8))
    assert f.translation("ball") == before
    with pytest.raises(vcuts.VcutsError, match="builtin:nowhere"):
        f.set_environment("builtin:nowhere")
    with pytest.raises(vcuts.VcutsError, match="camera 'side'"):
        f.image("side")
    with pytest.raises(vcuts.VcutsError, match="mode"):
        f.screen_space("rtx")
    with pytest.raises(vcuts.VcutsError, match=r"\(N, 3\)"):
        vcuts.errors([np.zeros((4, 2))], [np.zeros((4, 2))])


def test_unreadable_map_names_the_file(tmp_path) -> None:
    bad = tmp_path / "broken.hdr"
    bad.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x02\x02")
    with pytest.raises(vcuts.VcutsError, match="broken.hdr"):
        vcuts.EnvMap(str(bad))
    with pytest.raises(vcuts.VcutsError, match="finite"):
        vcuts.EnvMap.constant((float("inf"), 0, 0))


def test_report(tmp_path) -> None:
    good = tmp_path / "report.json"
    good.write_text('{"quick": true, "machine": {}, "directions": {}, "scenes": {}, "bench_s": 1.5}')
    assert vcuts.read_report(good)["bench_s"] == 1.5
    bad = tmp_path / "other.json"
    bad.write_text('{"quick": true}')
    with pytest.raises(vcuts.VcutsError, match="other.json.*machine"):
        vcuts.read_report(bad)
