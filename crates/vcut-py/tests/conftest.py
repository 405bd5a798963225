"""Fixtures: small scenes precomputed once per session into a temporary folder."""

from __future__ import annotations

from pathlib import Path

import pytest

import vcuts

# Two spheres over a ground, both movable: small enough to precompute in seconds.
SCENE = """
[environment]
source = "builtin:sky"
resolution = 128

[[object]]
name = "ball"
source = "builtin:sphere"
resolution = 10
translation = [0.0, 1.0, 0.0]
moves = true
material = { model = "blinn-phong", kd = [0.6, 0.4, 0.3], ks = [0.3, 0.3, 0.3], exponent = 20.0 }

[[object]]
name = "small"
source = "builtin:sphere"
size = 0.5
resolution = 8
translation = [1.6, 0.5, 0.4]
moves = true

[[object]]
name = "ground"
source = "builtin:plane"
size = 6.0
resolution = 12
material = { model = "lambert", kd = [0.5, 0.5, 0.5] }

[[camera]]
name = "main"
position = [3.0, 4.0, 6.0]
target = [0.0, 0.6, 0.0]
"""

# One open plane facing up, Lambertian.
PLANE = """
[environment]
source = "builtin:constant"

[[object]]
name = "plane"
source = "builtin:plane"
size = 2.0
resolution = 4
material = { model = "lambert", kd = [0.25, 0.5, 0.75] }
"""

# The parameters every test precompute uses: the `fast` preset with fewer directions.
SMALL = {"directions": 256}


@pytest.fixture(scope="session")
def workdir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("vcuts")
    (d / "balls.toml").write_text(SCENE)
    (d / "plane.toml").write_text(PLANE)
    return d


@pytest.fixture(scope="session")
def balls(workdir: Path) -> Path:
    out = workdir / "balls.vcuts"
    vcuts.precompute(str(workdir / "balls.toml"), "fast", out, progress=False, cache_dir=str(workdir / "cache"), **SMALL)
    return out


@pytest.fixture(scope="session")
def plane(workdir: Path) -> Path:
    out = workdir / "plane.vcuts"
    vcuts.precompute(str(workdir / "plane.toml"), "fast", out, progress=False, cache_dir=str(workdir / "cache"), **SMALL)
    return out


@pytest.fixture(scope="session")
def turnable_balls(workdir: Path) -> Path:
    """The balls with a direction set symmetric in 16 wedges about +Y: objects can turn."""
    out = workdir / "balls-turnable.vcuts"
    params = {**SMALL, "turn_steps": 16}
    vcuts.precompute(str(workdir / "balls.toml"), "fast", out, progress=False, cache_dir=str(workdir / "cache"), **params)
    return out
