"""vcuts: precomputed visibility cuts from Python.

Scenes and environment maps open as the ``vcuts`` command line opens them; a precompute writes a
``.vcuts`` file (progress to a callback or tqdm, Ctrl-C keeps a resumable partial file); ``open``
gives a ``Frame`` that moves objects, edits BRDFs and lighting and shades per vertex into numpy
arrays; the exact and Monte Carlo references, the screen-space and plant-leaf renderers come
along. Errors raise ``VcutsError`` with the message naming the file, key or object.

See docs/python.md for a walkthrough.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable, Optional, Union

from ._vcuts import EnvMap, Frame, Leaves, Scene, VcutsError, __version__, errors, open
from ._vcuts import _options, _precompute

__all__ = [
    "EnvMap",
    "Frame",
    "Leaves",
    "Scene",
    "VcutsError",
    "__version__",
    "errors",
    "leaves",
    "open",
    "precompute",
    "read_report",
]


def _argv(command: str, options: dict[str, Any], unknown_as_set: bool) -> list[str]:
    """The command line of ``vcuts COMMAND`` for keyword ``options``: each the command's
    ``--long-option`` (its flags from booleans, lists joined by commas). Another keyword is a
    ``--set key=value`` parameter when ``unknown_as_set``, else passed on as an option, for the
    command's parser to refuse by name."""
    flags = dict(_options(command))
    argv: list[str] = []
    for key, value in options.items():
        if value is None:
            continue
        if unknown_as_set and key not in flags:
            argv += ["--set", f"{key}={value}"]
            continue
        name = "--" + key.replace("_", "-")
        if flags.get(key, False):
            if value:
                argv.append(name)
            continue
        if isinstance(value, (tuple, list)):
            value = ",".join(str(v) for v in value)
        argv += [name, str(value)]
    return argv


class _Tqdm:
    """Progress through tqdm: one bar per stage."""

    def __init__(self, tqdm: Any) -> None:
        self._tqdm = tqdm
        self._bar: Any = None
        self._stage: Optional[str] = None

    def __call__(self, stage: str, done: int, total: int) -> None:
        if stage != self._stage:
            self.close()
            unit = {"svc": "vertices", "fields": "field points"}.get(stage, "steps")
            self._bar = self._tqdm(total=total, desc=stage, unit=f" {unit}")
            self._stage = stage
        self._bar.update(done - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None


def precompute(
    scene: str,
    preset: str = "fast",
    output: Union[str, Path, None] = None,
    *,
    progress: Union[Callable[[str, int, int], Any], bool, None] = None,
    **params: Any,
) -> dict[str, Any]:
    """Precomputes `scene` (``builtin:teapot``, a ``.toml`` scene file, a mesh) into a
    ``.vcuts`` file, exactly as ``vcuts precompute`` does; returns its summary as a dict
    (``output``, ``seconds``, ``file_bytes``, ``stages``, ...).

    ``preset``: ``fast``, ``balanced`` or ``paper``; ``output`` defaults to
    ``target/vcuts/<scene>-<preset>.vcuts``. Keywords: the command's options (``env``,
    ``directions``, ``svc_max_error``, ``field_spheres``, ``field_resolution``,
    ``field_max_error``, ``cache_dir``, ``fresh``, ``shard``, ``estimate_seconds``, ``force``)
    and any parameter by name (``svc_chunk=512``, as ``--set``).

    ``progress``: a callable ``(stage, done, total)``; ``None`` uses tqdm when it is installed;
    ``False`` reports nothing. Ctrl-C stops the run with the finished sections kept in
    ``<output>.partial`` and raises ``KeyboardInterrupt``; calling again resumes.
    """
    argv = _argv("precompute", {"scene": scene, "preset": preset, "output": output, **params}, True)
    bar = None
    if progress is None:
        try:
            from tqdm.auto import tqdm  # type: ignore[import-not-found]

            bar = _Tqdm(tqdm)
            progress = bar
        except ImportError:
            progress = False
    try:
        return _precompute(argv, progress if callable(progress) else None)
    finally:
        if bar is not None:
            bar.close()


def leaves(env: str = "builtin:sky", **plant: Any) -> Leaves:
    """The plant-leaf renderer: a plant as ``vcuts leaves`` builds it (keywords: its options,
    e.g. ``leaf_count=24``, ``vertices=20000``, ``plant="asset"``, ``sun="40,120"``,
    ``reflectance="0.1,0.3,0.05"``, ``no_maps=True``) lit by ``env``, its leaf data computed or
    loaded from ``leaf_data`` (default ``target/vleaf/...``)."""
    return Leaves(_argv("leaves", plant, False), env)


# The bench report's keys that every report has (vcuts::report::Report); sections are optional.
_REPORT_KEYS = ("quick", "machine", "directions", "scenes", "bench_s")


def read_report(path: Union[str, Path]) -> dict[str, Any]:
    """The bench report (``report.json`` of ``cargo xtask bench``) as a dict; a file that is not
    one raises ``VcutsError`` naming it."""
    path = Path(path)
    try:
        report = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise VcutsError(f"{path}: {e}") from None
    missing = [k for k in _REPORT_KEYS if not isinstance(report, dict) or k not in report]
    if missing:
        raise VcutsError(f"{path}: not a bench report (no {', '.join(missing)})")
    return report

