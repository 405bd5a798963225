"""The walkthrough of docs/python.md, as one script: the teapot scene and its arrays, a precompute,
the teapot dragged along a path with each step's move time and error against the exact
reference plotted, and per-vertex radiance compared with a reference array.

    python crates/vcut-py/examples/walkthrough.py [OUT_DIR]    (default target/python-walkthrough)

Needs numpy and matplotlib (and uses tqdm for progress when it is installed).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import vcuts

out = Path(sys.argv[1] if len(sys.argv) > 1 else "target/python-walkthrough")
out.mkdir(parents=True, exist_ok=True)

# 1. A scene opens as the command line opens it; its objects are numpy arrays.
scene = vcuts.Scene("builtin:teapot")
for o in scene.objects:
    print(f"{o['name']:8s} {len(o['positions']):6d} vertices {len(o['indices']):6d} triangles  {o['material']['model']}")

# 2. The precompute writes a .vcuts file (a tqdm bar per stage when tqdm is installed; Ctrl-C
#    keeps the finished sections in a .partial file that the same call resumes).
summary = vcuts.precompute("builtin:teapot", "fast", out / "teapot-fast.vcuts", cache_dir=str(out / "cache"))
print(f"precompute: {summary['seconds']:.1f} s, {summary['file_bytes'] / 1e6:.2f} MB")

# 3. A frame: drag the teapot along a path, shading from the file's camera after each step.
frame = vcuts.open(out / "teapot-fast.vcuts")
eye = frame.camera()["position"]
frame.deferred_merges = False  # eager: each move merges every vertex it changes
path = [(0.12 * k, 0.0, 0.06 * k) for k in range(1, 11)]
rows = []
for t in path:
    t0 = time.perf_counter()
    merged = frame.translate("teapot", t)
    move_ms = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    radiance = frame.shade(eye)
    shade_ms = (time.perf_counter() - t0) * 1e3
    reference = frame.exact_reference(eye)
    rel_l2, worst = vcuts.errors(radiance, reference)
    rows.append((move_ms, shade_ms, merged, rel_l2))
    print(f"step to {t}: {merged} vertices re-merged in {move_ms:.1f} ms, shaded in {shade_ms:.1f} ms, rel. L2 {100 * rel_l2:.2f} %")

# 4. Plot the move time and the error per step.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

steps = np.arange(1, len(rows) + 1)
moves, shades, merged, errs = (np.array(c) for c in zip(*rows))
fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.4))
left.plot(steps, moves, "o-", label="move")
left.plot(steps, shades, "s-", label="shade")
left.set_xlabel("step")
left.set_ylabel("ms")
left.legend()
right.plot(steps, 100 * errs, "o-", color="C3")
right.set_xlabel("step")
right.set_ylabel("rel. L2 vs exact, %")
fig.suptitle("the teapot dragged, fast preset")
fig.tight_layout()
fig.savefig(out / "drag.png", dpi=100)
print(f"plot: {out / 'drag.png'}")

# 5. Per-vertex radiance against a reference array: here the exact reference of the last step,
#    saved and read back as another renderer's output would be.
np.save(out / "reference-teapot.npy", reference[frame.objects.index("teapot")])
theirs = np.load(out / "reference-teapot.npy")
ours = radiance[frame.objects.index("teapot")]
luminance = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
lit = theirs @ luminance > 1e-6
rel = np.abs(ours - theirs)[lit] @ luminance / (theirs[lit] @ luminance)
print(f"teapot vertices: {lit.sum()} lit; per-vertex relative error median {100 * np.median(rel):.2f} %, "
      f"95th percentile {100 * np.percentile(rel, 95):.2f} %, worst {100 * rel.max():.2f} %")

# 6. The image as `vcuts render` draws it, tone-mapped for display.
image = frame.image(width=480, height=360)
plt.imsave(out / "frame.png", np.clip(image / (image.mean() * 4.0), 0.0, 1.0) ** (1 / 2.2))
print(f"image: {out / 'frame.png'}")
print(f"walkthrough_mean_move_ms={moves.mean():.2f}")
print(f"walkthrough_mean_rel_l2={errs.mean():.4f}")
