"""The claims the Rust tests make, at small sizes, through Python."""

from __future__ import annotations

import math

import numpy as np
import pytest

import vcuts


def test_open_plane_under_constant_map_reflects_its_albedo(plane) -> None:
    # An open Lambertian plane under radiance 1 everywhere: E = π, B = kd/π · E = kd.
    f = vcuts.open(plane, env="builtin:constant")
    (rad,) = f.shade([0.3, 5.0, 0.2])
    assert rad.shape == (25, 3) and rad.dtype == np.float32
    np.testing.assert_allclose(rad, np.broadcast_to([0.25, 0.5, 0.75], rad.shape), rtol=2e-3)


def test_move_and_back_restores_radiance_bit_for_bit(balls) -> None:
    f = vcuts.open(balls)
    f.deferred_merges = False
    eye = f.camera()["position"]
    before = f.shade(eye)
    merged = f.translate("ball", (0.8, 0.0, 0.3))
    assert merged > 0
    moved = f.shade(eye)
    assert not all(np.array_equal(a, b) for a, b in zip(before, moved)), "the move changed nothing"
    f.translate("ball", (0.0, 0.0, 0.0))
    after = f.shade(eye)
    for a, b in zip(before, after):
        assert np.array_equal(a, b)


def test_a_turn_snaps_its_cuts_and_turning_back_is_bit_for_bit(turnable_balls, balls) -> None:
    f = vcuts.open(turnable_balls)
    f.deferred_merges = False
    eye = f.camera()["position"]
    before = f.shade(eye)
    made = f.turn("ball", 37.0)
    assert made["wedges"] == 16 and made["steps"] == 2 and made["merged"] > 0
    assert made["snap_error_deg"] == pytest.approx(45.0 - 37.0, abs=1e-4)
    assert f.yaw("ball") == pytest.approx(37.0, abs=1e-4)
    # The geometry turned about the ball's vertical axis: its centre stayed.
    assert np.allclose(f.positions("ball").mean(axis=0), [0.0, 1.0, 0.0], atol=0.05)
    assert f.turn("ball", -360.0)["steps"] == 0
    for a, b in zip(before, f.shade(eye)):
        assert np.array_equal(a, b)
    assert f.turn("ball", 90.0, wait=False) is None
    assert f.wait()["moves"] == 1
    with pytest.raises(vcuts.VcutsError, match="finite"):
        f.turn("ball", math.nan)
    with pytest.raises(vcuts.VcutsError, match="static"):
        f.turn("ground", 10.0)
    # A file without a symmetric set refuses, naming the option that makes one.
    with pytest.raises(vcuts.VcutsError, match="turn_steps"):
        vcuts.open(balls).turn("ball", 30.0)


def test_a_drag_settles_to_the_translation_bit_for_bit(balls) -> None:
    dragged, moved = vcuts.open(balls), vcuts.open(balls)
    eye = dragged.camera()["position"]
    for k in range(1, 4):
        assert dragged.drag("ball", (0.2 * k, 0.0, 0.1 * k)) > 0
    assert dragged.dragging == "ball"
    stats = dragged.stats()
    assert stats["drag_prepared_vertices"] > 0 and stats["frame_memory_drag_mb"] > 0
    assert stats["move_on_rest_vertices"] > 0
    moved.translate("ball", (0.6, 0.0, 0.3))
    for a, b in zip(dragged.shade(eye), moved.shade(eye)):
        np.testing.assert_allclose(a, b, rtol=1e-5, atol=1e-6)
    assert dragged.settle() > 0 and dragged.dragging is None
    assert dragged.stats()["drag_settled_vertices"] > 0
    for a, b in zip(dragged.shade(eye), moved.shade(eye)):
        assert np.array_equal(a, b)


def test_moves_posted_without_waiting_end_where_waited_ones_do(balls) -> None:
    posted, waited = vcuts.open(balls), vcuts.open(balls)
    eye = posted.camera()["position"]
    for k in range(1, 6):
        assert posted.drag("ball", (0.1 * k, 0.0, 0.05 * k), wait=False) is None
    assert posted.settle(wait=False) is None
    done = posted.wait()
    assert not posted.busy
    assert done["moves"] + done["dropped"] == 6 and done["merged"] > 0
    waited.translate("ball", (0.5, 0.0, 0.25))
    for a, b in zip(posted.shade(eye), waited.shade(eye)):
        assert np.array_equal(a, b)
    # A move the frame refuses is raised by wait(), naming it; the ball stays.
    posted.translate("ball", (1e30, 0.0, 0.0), wait=False)
    with pytest.raises(vcuts.VcutsError, match="ball"):
        posted.wait()
    assert posted.translation("ball") == [0.5, 0.0, 0.25]


def test_refine_brings_the_frame_toward_the_exact_reference(balls) -> None:
    f = vcuts.open(balls)
    eye = f.camera()["position"]
    f.translate("ball", (0.2, 0.0, 0.1))

    def error() -> float:
        got = np.concatenate(f.shade(eye))
        ref = np.concatenate(f.exact_reference(eye))
        return float(np.linalg.norm(got - ref) / np.linalg.norm(ref))

    before = error()
    done = f.refine(reach=math.inf)
    assert done["refine_complete"] and done["refine_factors_cast"] > 0, done
    assert error() < before
    assert f.stats()["refine_exact_pairs"] == done["refine_exact_pairs"]
    # Posted, then cancelled by a move; a bad budget is refused naming it.
    assert f.refine(wait=False) is None
    f.translate("ball", (0.0, 0.0, 0.0))
    with pytest.raises(vcuts.VcutsError, match="seconds"):
        f.refine(seconds=0.0)


def test_a_grounds_edges_estimated_change_the_balls_and_exact_again_is_bit_for_bit(balls) -> None:
    f = vcuts.open(balls)
    eye = f.camera()["position"]
    assert f.flat_edge_leaves == 1
    exact = f.shade(eye)
    f.flat_edge_leaves = 4
    assert f.flat_edge_leaves == 4
    assert not all(np.array_equal(a, b) for a, b in zip(exact, f.shade(eye))), "the estimate changed nothing"
    # The interactive setting is 1/256 of the directions: at these 256, the exact cut.
    f.flat_edge_leaves = "interactive"
    assert f.flat_edge_leaves == 1
    for a, b in zip(exact, f.shade(eye)):
        assert np.array_equal(a, b)
    with pytest.raises(vcuts.VcutsError, match="flat_edge_leaves = 3"):
        f.flat_edge_leaves = 3
    with pytest.raises(vcuts.VcutsError, match="interactive"):
        f.flat_edge_leaves = "fine"


def test_positions_follow_the_translation(balls) -> None:
    f = vcuts.open(balls)
    rest = f.positions("small")
    f.translate("small", (0.5, 0.0, -0.25))
    np.testing.assert_allclose(f.positions("small") - rest, np.broadcast_to([0.5, 0.0, -0.25], rest.shape), atol=1e-6)
    assert f.translation("small") == pytest.approx([0.5, 0.0, -0.25])
    tris = f.indices("small")
    assert tris.dtype == np.uint32 and tris.shape[1] == 3 and tris.max() < len(rest)
    n = f.normals("small")
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)


def test_brdf_and_lighting_edits_make_no_merge(balls) -> None:
    f = vcuts.open(balls)
    eye = f.camera()["position"]
    before = f.shade(eye)
    merges = f.stats()["merges"]
    f.set_brdf("ball", "ggx:roughness=0.2,ks=0.04")
    assert f.material("ball")["model"] == "ggx"
    edited = f.shade(eye)
    f.set_environment("builtin:studio")
    relit = f.shade(eye)
    assert f.stats()["merges"] == merges
    assert not np.array_equal(before[0], edited[0])
    assert not np.array_equal(edited[0], relit[0])
    # The ground's BRDF did not change: only the light did.
    assert np.array_equal(before[2], edited[2])


def test_arrays_are_handed_over_without_a_copy(balls) -> None:
    f = vcuts.open(balls)
    rad = f.shade(f.camera()["position"])[0]
    # A reshaped view of the 1-D array that owns the Rust allocation.
    assert not rad.flags["OWNDATA"] and rad.base is not None and rad.base.flags["OWNDATA"] is False
    assert rad.flags["C_CONTIGUOUS"] and rad.flags["WRITEABLE"]


def test_cuts_against_the_references(balls) -> None:
    f = vcuts.open(balls)
    eye = f.camera()["position"]
    got = f.shade(eye)
    exact = f.exact_reference(eye)
    rel, worst = vcuts.errors(got, exact)
    assert 0.0 < rel < 0.1 and worst >= rel
    mc = f.monte_carlo_reference(eye, rel_error=0.05, max_samples=2048)
    rel_mc, _ = vcuts.errors(exact, mc)
    assert rel_mc < 0.1


def test_images(balls) -> None:
    f = vcuts.open(balls)
    img = f.image(width=80, height=60)
    assert img.shape == (60, 80, 3) and img.dtype == np.float32 and np.isfinite(img).all() and img.mean() > 0
    cam = dict(f.camera("main"), position=[0.0, 6.0, 0.01])
    top = f.image(cam, width=40, height=30)
    assert top.shape == (30, 40, 3) and not np.array_equal(top, img[:30, :40])
    for mode in ("ssao", "ssdo"):
        s = f.screen_space(mode, width=64, height=48)
        assert s.shape == (48, 64, 3) and np.isfinite(s).all() and s.mean() > 0


def test_stats_report_the_move_and_memory(balls) -> None:
    f = vcuts.open(balls)
    f.deferred_merges = False
    n = f.translate(0, (0.2, 0.0, 0.0))
    s = f.stats()
    assert s["last_move"]["vertices"] == n > 0
    assert s["memory"]["total"] == sum(v for k, v in s["memory"].items() if k != "total")
    assert s["light"]["target_error"] > 0


def test_stats_keys_are_renders(balls) -> None:
    f = vcuts.open(balls, deferred_merges=False)
    f.translate(0, (0.2, 0.0, 0.0))
    s = f.stats()
    for key in ["frame_caches", "vertices", "sun_leaves", "merges", "setup_merges", "move_keys_ms",
                "move_merge_only_ms", "frame_memory_mb", "frame_memory_merged_mb", "light_error_target"]:
        assert key in s, key
    assert s["setup_merges"] == s["vertices"]
    assert s["frame_memory_mb"] == pytest.approx(s["memory"]["total"] / 1e6)


def test_settings_are_keywords_of_open_and_reconfigure(balls) -> None:
    f = vcuts.open(balls, field_reach="outermost", caches={"merged": False}, flat_edge_leaves=4)
    s = f.settings
    assert s["field_reach"] == "outermost" and s["flat_edge_leaves"] == 4
    assert s["caches"] == {"stored": True, "svc": True, "cells": True, "merged": False}
    assert f.stats()["frame_caches"] == "stored,svc,cells"
    eye = f.camera()["position"]
    before = f.shade(eye)
    merged = f.reconfigure(field_reach=6.0, flat_edge_leaves=1, caches={"merged": True})
    assert merged > 0 and f.settings["caches"]["merged"]
    fresh = vcuts.open(balls)
    for a, b in zip(f.shade(eye), fresh.shade(eye)):
        assert np.array_equal(a, b)
    assert not all(np.array_equal(a, b) for a, b in zip(before, fresh.shade(eye)))
    for bad, word in [({"field_rech": 3}, "field_rech"), ({"light_error": 2.0}, "light_error"),
                      ({"field_reach": float("nan")}, "field_reach"), ({"inside_samples": "in"}, "inside_samples")]:
        with pytest.raises(vcuts.VcutsError, match=word):
            f.reconfigure(**bad)
    assert f.settings["field_reach"] == 6.0
