"""Precompute from Python: progress, interruption (a callback's exception and a real SIGINT), a
resumed file byte-identical to an uninterrupted one; scenes and maps as arrays."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import vcuts
from conftest import SMALL


def test_progress_reaches_every_stage(workdir, tmp_path) -> None:
    calls = []
    summary = vcuts.precompute(
        str(workdir / "balls.toml"),
        output=tmp_path / "p.vcuts",
        cache_dir=str(workdir / "cache"),
        progress=lambda stage, done, total: calls.append((stage, done, total)),
        **SMALL,
    )
    stages = {c[0] for c in calls}
    assert {"svc", "fields"} <= stages
    assert all(0 <= d <= t for _, d, t in calls)
    assert summary["file_bytes"] == (tmp_path / "p.vcuts").stat().st_size
    assert [s["name"] for s in summary["stages"]] == ["directions", "svc", "fields"]


class Stop(Exception):
    pass


def test_an_interrupted_run_resumes_byte_identical(workdir, balls, tmp_path) -> None:
    out = tmp_path / "r.vcuts"

    def stop(stage: str, done: int, total: int) -> None:
        if stage == "fields":
            raise Stop()

    # svc_chunk small: many sections, so the stop leaves some done and some to do.
    params = dict(SMALL, svc_chunk=64, cache_dir=str(workdir / "cache"))
    with pytest.raises(Stop):
        vcuts.precompute(str(workdir / "balls.toml"), output=out, progress=stop, **params)
    assert not out.exists() and (tmp_path / "r.vcuts.partial").exists()
    summary = vcuts.precompute(str(workdir / "balls.toml"), output=out, progress=False, **params)
    assert sum(s["sections_resumed"] for s in summary["stages"]) > 0
    whole = tmp_path / "whole.vcuts"
    vcuts.precompute(str(workdir / "balls.toml"), output=whole, progress=False, **params)
    assert out.read_bytes() == whole.read_bytes()


def test_ctrl_c_keeps_a_resumable_partial_file(workdir, tmp_path) -> None:
    # A real SIGINT to a Python process in a precompute, sent when the SVC stage is first
    # reported (progress is polled ten times a second, so the scene is the teapot, whose SVC
    # stage takes seconds): KeyboardInterrupt naming the partial file, which stays; a run that
    # stops so is resumed as in the test above (the same interrupt flag).
    out = tmp_path / "c.vcuts"
    script = textwrap.dedent(
        f"""
        import os, signal, vcuts
        # Python's own Ctrl-C handler, whatever this process inherited: a shell that starts a
        # job in the background without job control (CI's) starts it with SIGINT ignored, and
        # Python then leaves it ignored.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        sent = []
        def interrupt(stage, done, total):
            if stage == "svc" and not sent:
                sent.append(1)
                os.kill(os.getpid(), signal.SIGINT)
        try:
            vcuts.precompute("builtin:teapot", output={str(out)!r}, progress=interrupt,
                             cache_dir={str(workdir / "cache")!r}, svc_chunk=64)
        except KeyboardInterrupt as e:
            print("interrupted:", e, flush=True)
        """
    )
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    said = [line for line in r.stdout.splitlines() if line.startswith("interrupted:")]
    assert said and "c.vcuts.partial" in said[0] and "resume" in said[0], r.stdout[-2000:]
    assert (tmp_path / "c.vcuts.partial").exists() and not out.exists()


def test_scenes_and_maps_as_arrays(workdir) -> None:
    s = vcuts.Scene(str(workdir / "balls.toml"))
    assert s.names == ["ball", "small", "ground"]
    objs = s.objects
    assert sum(len(o["positions"]) for o in objs) == s.vertex_count
    for o in objs:
        p, n, t = o["positions"], o["normals"], o["indices"]
        assert p.shape == n.shape and p.dtype == np.float32 and t.dtype == np.uint32 and t.max() < len(p)
    assert objs[0]["movable"] and not objs[2]["movable"]
    assert objs[2]["material"]["model"] == "lambert"
    assert s.cameras[0]["name"] == "main"
    env = s.environment
    tex = env.texels()
    assert env.layout == "latlong" and tex.shape == (64, 128, 3) and (tex >= 0).all()
    up = env.radiance(np.array([[0.0, 1.0, 0.0]]))
    assert up.shape == (1, 3) and (up > 0).all()
    c = vcuts.EnvMap.constant((1.0, 2.0, 3.0))
    np.testing.assert_allclose(c.total_power, 4 * np.pi * np.array([1.0, 2.0, 3.0]), rtol=1e-9)
    assert vcuts.Scene("builtin:teapot").names == ["teapot", "sphere", "ground"]


def test_leaves(tmp_path) -> None:
    leaves = vcuts.leaves(leaf_count=3, prt_rays=16, lvc_resolution=8, leaf_data=str(tmp_path / "p.vleaf"))
    n = leaves.vertex_count
    rad = leaves.shade()
    assert rad.shape == (n, 2, 3) and np.isfinite(rad).all() and rad.mean() > 0
    sh = leaves.shade(method="sh")
    assert not np.array_equal(rad, sh)
    img = leaves.image(width=48, height=36)
    assert img.shape == (36, 48, 3) and img.mean() > 0
    cmp = leaves.compare(paths=16, vertices=200)
    assert 0 < cmp["rel_l2_lvc_prt"] < 1 and cmp["vertices"] == 200
    # The same plant again loads its leaf data.
    again = vcuts.leaves(leaf_count=3, prt_rays=16, lvc_resolution=8, leaf_data=str(tmp_path / "p.vleaf"))
    assert again.data_file[1] is True
    with pytest.raises(vcuts.VcutsError, match="leaf-count"):
        vcuts.leaves(leaf_count="many")
    with pytest.raises(vcuts.VcutsError, match="leaf-cont"):
        vcuts.leaves(leaf_cont=3)
    # Keywords are the command's own options, read from its parser: flags and valued options.
    options = dict(vcuts._vcuts._options("leaves"))
    assert options["no_maps"] is True and options["leaf_count"] is False
    assert dict(vcuts._vcuts._options("precompute"))["fresh"] is True
    with pytest.raises(vcuts.VcutsError, match="method"):
        leaves.shade(method="rt")


def test_module_is_typed() -> None:
    here = os.path.dirname(vcuts.__file__)
    assert os.path.exists(os.path.join(here, "py.typed")) and os.path.exists(os.path.join(here, "_vcuts.pyi"))
