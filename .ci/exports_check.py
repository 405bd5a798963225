"""Reads what `vcuts render --exr F --exr-passes all --export-glb G` wrote with readers other than
ours: the EXR with OpenEXR (R G B A and every pass's channels; diffuse + specular = the image where
alpha is 1), the .glb with pygltflib (a mesh per object with POSITION, NORMAL and COLOR_0 in
[0, 1], the unlit material, a camera)."""
import struct
import sys

import numpy as np
import OpenEXR
import pygltflib

exr_path, glb_path = sys.argv[1], sys.argv[2]
with OpenEXR.File(exr_path, separate_channels=True) as f:
    ch = {name: np.asarray(c.pixels, dtype=np.float32) for name, c in f.channels().items()}
want = {"R", "G", "B", "A", "albedo.R", "normal.X", "depth.Z", "diffuse.R", "specular.R"}
assert want <= set(ch), f"{exr_path}: channels {sorted(ch)} lack {sorted(want - set(ch))}"
alpha = ch["A"] == 1.0
assert alpha.any() and not alpha.all(), f"{exr_path}: alpha covers {alpha.mean():.3f} of the image"
for c in "RGB":
    total = ch[f"diffuse.{c}"] + ch[f"specular.{c}"]
    err = np.abs(total - ch[c])[alpha].max() / max(np.abs(ch[c][alpha]).max(), 1e-6)
    assert err < 1e-4, f"{exr_path}: diffuse + specular differs from {c} by {err}"
print(f"{exr_path}: {len(ch)} channels, {int(alpha.sum())} covered pixels")

gltf = pygltflib.GLTF2().load(glb_path)
blob = gltf.binary_blob()
assert "KHR_materials_unlit" in (gltf.extensionsUsed or []), f"{glb_path}: no unlit material"
assert gltf.cameras, f"{glb_path}: no camera"
for mesh in gltf.meshes:
    attrs = mesh.primitives[0].attributes
    for name in ["POSITION", "NORMAL", "COLOR_0"]:
        assert getattr(attrs, name) is not None, f"{glb_path}: mesh {mesh.name} has no {name}"
    acc = gltf.accessors[attrs.COLOR_0]
    view = gltf.bufferViews[acc.bufferView]
    start = view.byteOffset + (acc.byteOffset or 0)
    colour = np.array(struct.unpack_from(f"<{acc.count * 3}f", blob, start))
    assert ((colour >= 0) & (colour <= 1)).all(), f"{glb_path}: mesh {mesh.name} has COLOR_0 outside [0, 1]"
print(f"{glb_path}: {len(gltf.meshes)} meshes, {len(gltf.cameras)} camera")
