"""Scene preview benchmark: the time to draw a shipped scene (target: under 5 s each).

    .venv/bin/python benchmarks/bench_preview.py   (make bench runs it)

Each scene is planned and drawn off-screen three times in one process; the first draw also
loads VTK. Writes benchmarks/preview.md.
"""

from __future__ import annotations

import platform
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from orchestrator.report.preview import preview_scene_file  # noqa: E402

SCENES = ("1debris", "6debris-2x3", "nodebris")
TARGET_S = 5.0


def main() -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        first = None
        for name in SCENES:
            times = []
            for i in range(3):
                t0 = time.perf_counter()
                preview_scene_file(ROOT / "cases" / f"{name}.yaml", Path(tmp) / f"{name}-{i}.png")
                times.append(time.perf_counter() - t0)
            first = first if first is not None else times[0]
            rows.append((name, min(times), max(times[1:])))
    lines = ["# Scene preview", "",
             f"`benchmarks/bench_preview.py` on {platform.node() or 'this machine'} ({platform.machine()}, "
             f"Python {platform.python_version()}): plan and draw each shipped scene three times in one process.", "",
             "| scene | best (s) | worst after the first (s) | target |", "|---|---:|---:|---|"]
    lines += [f"| {n} | {b:.2f} | {w:.2f} | < {TARGET_S:g} s |" for n, b, w in rows]
    lines += ["", f"The first draw in a process, which also loads VTK: {first:.2f} s.", ""]
    (ROOT / "benchmarks" / "preview.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
