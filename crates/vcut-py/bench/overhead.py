"""What Python adds to a move and a shade: the same drag (eager moves of one object, each
followed by a shade towards the camera) through `Frame.translate` / `Frame.shade` on one frame
and through `vcuts._vcuts._native_drag`, which times the same calls in Rust, on a second frame
of the same file; the two take turns step by step. Also what handing a frame's arrays to numpy
costs.

    python crates/vcut-py/bench/overhead.py FILE.vcuts [OBJECT] [ROUNDS]

Prints key=value lines: medians in ms and the overhead ratios (goal: ≤ 1.05).
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np

import vcuts
from vcuts._vcuts import _native_drag

path = sys.argv[1]
obj = sys.argv[2] if len(sys.argv) > 2 else None
rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 6
STEPS = 8
STEP = np.array([0.04, 0.0, 0.02], dtype=np.float32)

py_frame = vcuts.open(path)
rust_frame = vcuts.open(path)
obj = obj or py_frame.objects[0]
eye = py_frame.camera()["position"]
for f in (py_frame, rust_frame):
    f.deferred_merges = False


def python_step(f: vcuts.Frame, to: np.ndarray) -> tuple[float, float]:
    t0 = time.perf_counter()
    f.translate(obj, to)
    t1 = time.perf_counter()
    f.shade(eye)
    t2 = time.perf_counter()
    return (t1 - t0) * 1e3, (t2 - t1) * 1e3


def back(f: vcuts.Frame) -> None:
    f.translate(obj, (0.0, 0.0, 0.0))
    f.shade(eye)


# Step by step, the two frames take turns, who goes first alternating, so drift in the
# machine's speed falls on both alike.
py, rust = [], []
for r in range(rounds + 1):
    for k in range(1, STEPS + 1):
        turns = [0, 1] if (r * STEPS + k) % 2 else [1, 0]
        for who in turns:
            if who == 0:
                a = python_step(py_frame, STEP * k)
            else:
                (b,) = _native_drag(rust_frame, obj, STEP, 1, eye)
        if r > 0:  # the first round warms caches
            py.append(a)
            rust.append(b)
    back(py_frame)
    back(rust_frame)

py_move = statistics.median(m for m, _ in py)
py_shade = statistics.median(s for _, s in py)
rust_move = statistics.median(m for m, _ in rust)
rust_shade = statistics.median(s for _, s in rust)

# Handing arrays over: shade's are the Rust vectors themselves (no copy); a copy of them costs
# what np.copy measures. Positions, normals and triangles are made for the call.
arrays = py_frame.shade(eye)
t0 = time.perf_counter()
for _ in range(20):
    [np.copy(a) for a in arrays]
copy_ms = (time.perf_counter() - t0) * 1e3 / 20
t0 = time.perf_counter()
for _ in range(20):
    for o in py_frame.objects:
        py_frame.positions(o), py_frame.normals(o), py_frame.indices(o)
geometry_ms = (time.perf_counter() - t0) * 1e3 / 20

print(f"file={path}")
print(f"object={obj}")
print(f"vertices={sum(len(a) for a in arrays)}")
print(f"steps={len(py)}")
print(f"python_move_ms={py_move:.3f}")
print(f"rust_move_ms={rust_move:.3f}")
print(f"move_overhead={py_move / rust_move:.3f}")
print(f"python_shade_ms={py_shade:.3f}")
print(f"rust_shade_ms={rust_shade:.3f}")
print(f"shade_overhead={py_shade / rust_shade:.3f}")
print(f"step_overhead={(py_move + py_shade) / (rust_move + rust_shade):.3f}")
print(f"radiance_copy_ms={copy_ms:.3f}")
print(f"geometry_arrays_ms={geometry_ms:.3f}")
