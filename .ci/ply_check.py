"""Reads a PLY written by `vcuts render --export-ply` with plyfile (a reader other than ours):
float `red green blue` beside positions and normals, finite, every vertex shaded (a vertex is
black only where no light reaches it: at most the share given as the second argument)."""
import sys

import numpy as np
from plyfile import PlyData

path, most_black = sys.argv[1], float(sys.argv[2])
vertex = PlyData.read(path)["vertex"]
kinds = {p.name: p.val_dtype for p in vertex.properties}
for name in ["x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"]:
    assert name in kinds, f"{path}: no vertex property {name} (has {sorted(kinds)})"
for name in ["red", "green", "blue"]:
    assert np.dtype(kinds[name]).kind == "f", f"{path}: {name} is {kinds[name]}, not a float"
rgb = np.stack([vertex["red"], vertex["green"], vertex["blue"]], axis=1)
assert np.isfinite(rgb).all() and (rgb >= 0).all(), f"{path}: a colour is negative or not finite"
black = int((rgb.max(axis=1) <= 0).sum())
print(f"{path}: {len(rgb)} vertices, {black} black, mean radiance {rgb.mean(axis=0)}")
assert black <= most_black * len(rgb), f"{path}: {black} of {len(rgb)} vertices are black"
