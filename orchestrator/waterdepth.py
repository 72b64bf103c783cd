"""The water depth around each body while the solver runs: when a body on the bed can float.

The runner frees a body it keeps on the bed (the planner's initial hold, `rest_on_bed`) once
the water *measured* around it can carry it, and sets the bed friction of a resting body from
the weight the water does not carry. Both read this module's measurement:

- `install(case)` writes `system/bodyDepth`, a `sets` function object with one `cloud` set:
  vertical columns of points on a regular grid (`COLUMN_SPACING_CELLS` background cells
  apart, wider if that would make more than `MAX_COLUMNS`) covering the flume from the most upstream body's tail to the domain's downstream end,
  the full width, from the bed to the highest still water (the reservoir) plus a cell, every
  `POINT_SPACING_CELLS` of a background cell. `#include "bodyDepth"` goes into controlDict's
  `functions`. It samples `alpha.water` (the containing cell's value, `cell`: the
  sum over a column is then the water volume of its cells per unit area; `cellPoint` smeared the
  15 mm wet bed's surface into a 4 cm cell and read it 19.5-20 mm) every `SAMPLE_INTERVAL_S` of simulated
  time into `postProcessing/bodyDepth/<time>/depth_alpha.water.xy` (x y z alpha). A point
  in two meshes is sampled in the first one found, the background (merged first); points in
  no cell (inside the column) are left out by OpenFOAM.
- `read_latest(case)` reads the newest complete sample: each column's water depth, the sum
  of alpha times the point spacing.
- `depth_around(sample, state, size)`: the depth all around a body, the `DEPTH_QUANTILE` (10 %)
  quantile over the columns whose horizontal distance from the body's footprint lies between one
  background cell plus `RING_SPACINGS` column spacings (a median reads deep water while a bore's
  front stands at the body's middle). The
  inner limit keeps the ring off the background cells that the body's overset cuts as holes
  (they keep stale values: docs/openfoam-notes.md, "A gauge line through an overset region").

Cost: on the tiny flume (360 columns of 36 points) the runs took no longer than without it as
far as the shared machine shows. On the seed's flume at 4 cm cells the grid is 1,500 columns of
55 points (82,500 points, about 3 MB a sample; not timed there); every sample is a new file, and
`prune` keeps only the newest `KEEP_SAMPLES` while the run goes on.
"""

from __future__ import annotations

import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np

#: the function object's name, its file in system/ and its folder in postProcessing/
NAME = "bodyDepth"
#: simulated seconds between samples (the runner acts on the newest one)
SAMPLE_INTERVAL_S = 0.01
#: columns this many background cells apart, in x and in y, or wider so that there are at most
#: MAX_COLUMNS of them (the seed's flume at 4 cm: 2,997 columns at one cell, 1,500 at 1.41 cells)
COLUMN_SPACING_CELLS = 1.0
MAX_COLUMNS = 1500
#: points this fraction of a background cell apart along each column
POINT_SPACING_CELLS = 0.2
#: the ring of columns read around a body: from one background cell off its footprint to that plus
#: this many column spacings
RING_SPACINGS = 1.5
#: the depth around a body is this quantile of its ring's columns: the water must be deep all round
#: it. The median read 73-78 mm around the float-carry container while the bore's front stood
#: at its middle, 15 mm of wet bed still under its downstream half (docs/stability.md)
DEPTH_QUANTILE = 0.1
#: the forces function object of each body (its wall patch): postProcessing/lift_<body>/<start>/force.dat
LIFT_PREFIX = "lift_"
#: the lift read after a restart skips this much simulated time: the first line of a segment's
#: force.dat is written before its first step (-0.18 N at a restart where the steps around read
#: 0.02-0.26 N), and a body raised 5 mm onto its gap read 305 N over the next 0.01 s
LIFT_SETTLE_S = 0.005
#: sample folders kept in postProcessing/bodyDepth while the run goes on (the runner reads the newest)
KEEP_SAMPLES = 10


@dataclass(frozen=True)
class Grid:
    """The sampled columns: their (x, y), the point heights, the background cell size, the columns' spacing."""

    xy: np.ndarray  # (n, 2)
    z: np.ndarray  # (k,)
    dz: float
    cell_m: float
    spacing_m: float = 0.0

    @property
    def ring_m(self) -> tuple[float, float]:
        """The ring of columns read around a body: its inner and outer distance from the footprint."""
        return self.cell_m, self.cell_m + RING_SPACINGS * (self.spacing_m or self.cell_m)

    def points(self) -> np.ndarray:
        xy = np.repeat(self.xy, len(self.z), axis=0)
        z = np.tile(self.z, len(self.xy))
        return np.column_stack([xy, z])


@dataclass(frozen=True)
class Sample:
    """One sample: the simulated time and each column's water depth (m)."""

    time_s: float
    xy: np.ndarray  # (n, 2)
    depth_m: np.ndarray  # (n,)


def _scene(case: Path) -> dict[str, Any]:
    import yaml

    return yaml.safe_load((case / "scene.yaml").read_text())


def grid_for(plan: dict[str, Any], scene: dict[str, Any]) -> Grid | None:
    """The columns for a case's plan.json and resolved scene.yaml (None without bodies)."""
    bodies = plan.get("bodies") or []
    if not bodies:
        return None
    (x0, x1), (y0, y1), (z0, z1) = (tuple(float(v) for v in a) for a in plan["domain_m"])
    h = float(scene["mesh"]["cell_size_m"])
    tail = min(float(b["centre_of_mass_m"][0]) - max(float(s) for s in b["size_m"]) for b in bodies)
    start = max(x0, tail - 2 * h)
    step = max(COLUMN_SPACING_CELLS * h, math.sqrt((x1 - start) * (y1 - y0) / MAX_COLUMNS))
    xs = np.arange(start + step / 2, x1 - 1e-3 * h, step)
    ys = np.arange(y0 + step / 2, y1 - 1e-3 * h, step)
    water_top = max((float(w["max_m"][2]) for w in plan.get("water") or []), default=z1 - z0)
    dz = POINT_SPACING_CELLS * h
    top = min(z1, water_top + h)
    zs = np.arange(z0 + dz / 2, top, dz)
    xy = np.array([(x, y) for x in xs for y in ys], dtype=float)
    return Grid(xy, zs, dz, h, step)


def _lift_object(body: str) -> str:
    return (
        f"{LIFT_PREFIX}{body}\n{{\n"
        "    type            forces;\n"
        "    libs            (forces);\n"
        "    writeControl    timeStep;\n"
        "    writeInterval   1;\n"
        f"    patches         ({body});\n"
        "    rho             rho;\n"
        "    CofR            (0 0 0);\n"
        "    log             false;\n"
        "}\n"
    )


def _function_object(grid: Grid, bodies: Sequence[str] = ()) -> str:
    pts = "\n".join(f"                ({x:.6g} {y:.6g} {z:.6g})" for x, y, z in grid.points())
    lifts = "".join(_lift_object(b) for b in bodies)
    return (
        "// written by the runner (orchestrator/waterdepth.py): alpha.water on vertical columns, for the\n"
        "// water depth around each body (when a body on the bed can float, its bed friction)\n"
        f"{NAME}\n{{\n"
        "    type            sets;\n"
        "    libs            (sampling);\n"
        "    writeControl    runTime;\n"
        f"    writeInterval   {SAMPLE_INTERVAL_S:g};\n"
        "    setFormat       raw;\n"
        "    interpolationScheme cell;\n"
        "    fields          (alpha.water);\n"
        "    sets\n    (\n"
        "        depth\n        {\n"
        "            type    cloud;\n"
        "            axis    xyz;\n"
        "            points\n            (\n"
        f"{pts}\n"
        "            );\n"
        "        }\n"
        "    );\n"
        "}\n"
        "// the fluid force on each body's wall, every time step (the runner reads its vertical part)\n"
        f"{lifts}"
    )


def install(case_dir: str | Path) -> Grid | None:
    """Write system/bodyDepth and include it in controlDict's functions (once). Returns the grid."""
    case = Path(case_dir)
    import json

    plan = json.loads((case / "plan.json").read_text())
    grid = grid_for(plan, _scene(case))
    if grid is None:
        return None
    path = case / "system" / NAME
    text = _function_object(grid, [b["name"] for b in plan["bodies"]])
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)
    control = case / "system" / "controlDict"
    body = control.read_text()
    if f'#include "{NAME}"' not in body:
        new, n = re.subn(r"(\nfunctions\s*\n?\s*\{)", rf'\1\n    #include "{NAME}"', body, count=1)
        if n != 1:
            raise ValueError(f"{control}: no functions dictionary to include {NAME} in")
        control.write_text(new)
    return grid


def _sample_dirs(case: Path) -> list[tuple[float, Path]]:
    base = case / "postProcessing" / NAME
    if not base.is_dir():
        return []
    out = []
    for p in base.iterdir():
        try:
            out.append((float(p.name), p))
        except ValueError:
            continue
    return sorted(out)


def read_sample(path: Path, grid: Grid, time_s: float) -> Sample | None:
    """One sample folder's column depths; None if its file is missing or being written."""
    f = path / "depth_alpha.water.xy"
    try:
        data = np.loadtxt(f, ndmin=2)
    except (OSError, ValueError):
        return None
    if data.size == 0 or data.shape[1] < 4:
        return None
    # the columns' points are written in order; a point outside the mesh is left out
    keys = np.round(data[:, :2] / (0.01 * grid.cell_m)).astype(np.int64)
    uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
    depth = np.bincount(inverse.ravel(), weights=np.clip(data[:, 3], 0.0, 1.0)) * grid.dz
    return Sample(time_s, uniq * 0.01 * grid.cell_m, depth)


def read_latest(case_dir: str | Path, grid: Grid, after_s: float = -math.inf) -> Sample | None:
    """The newest complete sample later than `after_s` (None if none)."""
    for t, path in reversed(_sample_dirs(Path(case_dir))):
        if t <= after_s:
            return None
        sample = read_sample(path, grid, t)
        if sample is not None:
            return sample
    return None


def read_at(case_dir: str | Path, grid: Grid, time_s: float, tolerance_s: float | None = None) -> Sample | None:
    """The newest sample at or before `time_s` (within `tolerance_s`, default one sample interval)."""
    tol = SAMPLE_INTERVAL_S * 1.01 if tolerance_s is None else tolerance_s
    for t, path in reversed(_sample_dirs(Path(case_dir))):
        if t > time_s + 1e-9:
            continue
        if t < time_s - tol:
            return None
        sample = read_sample(path, grid, t)
        if sample is not None:
            return sample
    return None


def prune(case_dir: str | Path, keep: int = KEEP_SAMPLES) -> None:
    """Delete all but the newest `keep` sample folders (each sample is one file of the whole grid)."""
    for _, path in _sample_dirs(Path(case_dir))[:-keep]:
        shutil.rmtree(path, ignore_errors=True)


def footprint_distance(xy: np.ndarray, centre: Sequence[float], orientation: Sequence[Sequence[float]],
                       size: Sequence[float]) -> np.ndarray:
    """Horizontal distance from each point of `xy` to a body's footprint (0 inside it)."""
    rot = np.asarray(orientation, dtype=float).reshape(3, 3)
    ax = rot[:2, 0] / (np.linalg.norm(rot[:2, 0]) or 1.0)  # the body's length axis, horizontal
    ay = np.array([-ax[1], ax[0]])
    d = np.asarray(xy, dtype=float) - np.asarray(centre[:2], dtype=float)
    lx, ly = np.abs(d @ ax) - size[0] / 2, np.abs(d @ ay) - size[1] / 2
    return np.hypot(np.maximum(lx, 0.0), np.maximum(ly, 0.0))


def depth_around(sample: Sample, ring_m: tuple[float, float], centre: Sequence[float],
                 orientation: Sequence[Sequence[float]], size: Sequence[float]) -> tuple[float, int] | None:
    """The water depth (m) all around a body: the `DEPTH_QUANTILE` quantile over the ring of
    columns `ring_m` (inner, outer distance) off its footprint, and how many columns."""
    dist = footprint_distance(sample.xy, centre, orientation, size)
    ring = (dist >= ring_m[0] * 0.999) & (dist <= ring_m[1] * (1 + 1e-9))
    if not ring.any():
        return None
    return float(np.quantile(sample.depth_m[ring], DEPTH_QUANTILE)), int(ring.sum())


def read_lift(case_dir: str | Path, body: str, until_s: float = math.inf,
              window_s: float = SAMPLE_INTERVAL_S) -> float | None:
    """The mean vertical fluid force (N) on a body's wall over the last `window_s` of simulated time
    up to `until_s` (the forces function object `lift_<body>`), from the newest segment that has
    steps more than `LIFT_SETTLE_S` after its start; None if there is none yet."""
    base = Path(case_dir) / "postProcessing" / f"{LIFT_PREFIX}{body}"
    if not base.is_dir():
        return None
    starts = []
    for p in base.iterdir():
        try:
            starts.append((float(p.name), p))
        except ValueError:
            continue
    for start, p in sorted(starts, reverse=True):
        if start >= until_s - 1e-9:
            continue
        rows = []
        try:
            lines = (p / "force.dat").read_text().splitlines()
        except OSError:
            continue
        for line in lines:
            if not line or line.startswith("#"):
                continue
            parts = line.replace("(", " ").replace(")", " ").split()
            if len(parts) < 4:
                continue  # a line being written
            try:
                t, fz = float(parts[0]), float(parts[3])
            except ValueError:
                continue
            if start + LIFT_SETTLE_S < t <= until_s + 1e-9:  # not the first steps after a restart
                rows.append((t, fz))
        if rows:
            last = rows[-1][0]
            recent = [fz for t, fz in rows if t > last - window_s - 1e-12]
            return float(np.mean(recent))
    return None
