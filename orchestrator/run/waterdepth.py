"""The water depth around each body while the solver runs: when a body on the bed can float.

The runner frees a body it keeps on the bed (the planner's initial hold, `rest_on_bed`) once
the water *measured* around it can carry it, and sets the bed friction of a resting body from
the weight the water does not carry. Both read this module's measurement:

- `install(case, axis, around)` writes `system/bodyDepth`, included once in controlDict's
  `functions`: a `forces` function object on every body's wall (`lift_<body>`, every step: the
  runner reads its vertical part, `read_lift`), and, when bodies are on or near the bed (kept
  there by the runner, or with their underside less than their height above it), a `sets`
  function object with one `cloud` set: vertical columns a background cell apart around those
  bodies (the ring read around each, widened by `TRAVEL_CELLS` both ways), one point per
  background cell layer (`ZAxis`) from the bed to the highest still water plus a cell. The runner
  writes it at every restart (the solver reads it when it starts). It samples `alpha.water` (the
  containing cell's value, `interpolationScheme cell`: the sum of alpha times the layer heights
  is the water volume of the column's cells per unit area; `cellPoint` smeared the 15 mm wet
  bed's surface into the 4 cm cell above it and read 19.5-20 mm) every `SAMPLE_INTERVAL_S` of
  simulated time into `postProcessing/bodyDepth/<time>/depth_alpha.water.xy` (x y z alpha). A
  point in two meshes is sampled in the first one found, the background (merged first); points
  in no cell (inside the column) are left out by OpenFOAM.
- `read_latest` / `read_at` read a sample: each column's water depth.
- `depth_around(sample, ring, ...)`: the depth all around a body, the `DEPTH_QUANTILE` (10 %)
  quantile over the columns whose horizontal distance from the body's footprint lies between one
  background cell and `RING_CELLS` more (a median reads deep water while a bore's front stands at
  the body's middle). The inner limit keeps the ring off the background cells that the body's
  overset cuts as holes (they keep stale values: docs/openfoam-notes.md, "A gauge line through an
  overset region"), and off those of every other body.

Cost: v1912's `sets` searches every point's cell again whenever the mesh moves, i.e. at every
time step of an overset run, whatever its write interval. A grid over the whole tiny flume (380
columns of 25 points, 7,000 cells) made its steps 2.5 times slower (0.27-0.36 s against 0.13-0.14 s
of CPU; 23.3 s against 9.1 s for 0.2 s); hence columns only around the bodies on or near the bed,
one point per layer, and none while every body is clear of it. Every sample is a new file; `prune` keeps the newest
`KEEP_SAMPLES`.
"""

from __future__ import annotations

import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from orchestrator.case.folder import CaseFolder
from orchestrator.case.outputs import numeric_dirs, read_force_series
from orchestrator.core.errors import InputError
from orchestrator.plan.model import ModelPlan

#: the function object's name, its file in system/ and its folder in postProcessing/
NAME = "bodyDepth"
#: simulated seconds between samples (the runner acts on the newest one)
SAMPLE_INTERVAL_S = 0.01
#: the ring of columns read around a body: from one background cell off its footprint to this many
#: more
RING_CELLS = 1.5
#: the columns reach this many background cells beyond the ring both ways; a body that slides
#: farther from where they were placed stops the solver so that the restart places them again
TRAVEL_CELLS = 1.5
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
class ZAxis:
    """The background's cell layers from the bed up to the highest still water plus a cell: each
    layer's centre and height. A column samples one point per layer, so its depth is the water
    volume of its cells per unit area."""

    z: np.ndarray  # (k,) centres
    dz: np.ndarray  # (k,) heights
    cell_m: float  # the background's cell size (mesh.cell_size_m)

    @property
    def ring_m(self) -> tuple[float, float]:
        """The ring of columns read around a body: its inner and outer distance from the footprint."""
        return self.cell_m, (1.0 + RING_CELLS) * self.cell_m

    def layer(self, z: np.ndarray) -> np.ndarray:
        return np.clip(np.searchsorted(self.z[:-1] + 0.5 * np.diff(self.z), z), 0, len(self.z) - 1)


@dataclass(frozen=True)
class Grid:
    """The sampled columns (x, y) and their layers."""

    xy: np.ndarray  # (n, 2)
    axis: ZAxis

    def points(self) -> np.ndarray:
        xy = np.repeat(self.xy, len(self.axis.z), axis=0)
        z = np.tile(self.axis.z, len(self.xy))
        return np.column_stack([xy, z])


@dataclass(frozen=True)
class Sample:
    """One sample: the simulated time and each column's water depth (m)."""

    time_s: float
    xy: np.ndarray  # (n, 2)
    depth_m: np.ndarray  # (n,)


def z_axis(plan: ModelPlan, cell_size_m: float) -> ZAxis:
    """The background's layers up to the highest still water (the reservoir) plus a cell of the
    scene's ``cell_size_m`` (mesh.cell_size_m)."""
    h = float(cell_size_m)
    (z0, z1) = (float(v) for v in plan.domain_m[2])
    water_top = max((float(w.max_m[2]) for w in plan.water), default=z1)
    planes = {round(z0, 12)}
    for seg in plan.background.z:
        start, end, n = float(seg.start_m), float(seg.end_m), int(seg.cells)
        first, last = seg.cell_sizes_m()
        q = (last / first) ** (1.0 / (n - 1)) if n > 1 else 1.0
        sizes = first * q ** np.arange(n)  # blockMesh's geometric progression
        planes.update(round(v, 12) for v in start + np.cumsum(sizes) * (end - start) / sizes.sum())
    planes = np.array(sorted(planes))
    top = np.searchsorted(planes, min(water_top + h, z1) - 1e-9) + 1
    planes = planes[: max(2, top + 1)]
    return ZAxis(0.5 * (planes[1:] + planes[:-1]), np.diff(planes), h)


def grid_for(plan: ModelPlan, axis: ZAxis,
             around: Sequence[tuple[Sequence[float], Sequence[float], Sequence[float]]]) -> Grid:
    """Columns a background cell apart around the bodies `around` ((centre, orientation, size) each):
    the ring `axis.ring_m` off each footprint, widened by `TRAVEL_CELLS` both ways so that it still
    covers the ring of a body that has slid that far."""
    (x0, x1), (y0, y1), _ = (tuple(float(v) for v in a) for a in plan.domain_m)
    h = axis.cell_m
    inner, outer = axis.ring_m
    travel = TRAVEL_CELLS * h
    cols: set[tuple[int, int]] = set()
    for centre, orientation, size in around:
        reach = outer + travel + 0.5 * math.hypot(size[0], size[1])
        ix = np.arange(math.floor((centre[0] - reach - x0) / h), math.ceil((centre[0] + reach - x0) / h) + 1)
        iy = np.arange(math.floor((centre[1] - reach - y0) / h), math.ceil((centre[1] + reach - y0) / h) + 1)
        gx, gy = np.meshgrid(ix, iy, indexing="ij")
        xy = np.column_stack([x0 + (gx.ravel() + 0.5) * h, y0 + (gy.ravel() + 0.5) * h])
        d = footprint_distance(xy, centre, orientation, size)
        keep = ((d >= inner - travel) & (d <= outer + travel) & (xy[:, 0] > x0) & (xy[:, 0] < x1)
                & (xy[:, 1] > y0) & (xy[:, 1] < y1))
        cols.update(zip(gx.ravel()[keep].tolist(), gy.ravel()[keep].tolist()))
    ij = np.array(sorted(cols), dtype=float).reshape(-1, 2)
    return Grid(np.column_stack([x0 + (ij[:, 0] + 0.5) * h, y0 + (ij[:, 1] + 0.5) * h]), axis)


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
    lifts = "".join(_lift_object(b) for b in bodies)
    text = ("// written by the runner (orchestrator/run/waterdepth.py) at every restart: alpha.water on vertical\n"
            "// columns around the bodies it keeps on the bed, and the fluid force on every body\n")
    if len(grid.xy):
        pts = "\n".join(f"                ({x:.6g} {y:.6g} {z:.6g})" for x, y, z in grid.points())
        text += (
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
        )
    return text + lifts


def install(case_dir: str | Path, axis: ZAxis,
            around: Sequence[tuple[Sequence[float], Sequence[float], Sequence[float]]] = ()) -> Grid:
    """Write system/bodyDepth (the columns around the bodies `around`, the lift of every body) and
    include it in controlDict's functions (once). The solver reads it when it (re)starts."""
    case = Path(case_dir)
    plan = CaseFolder(case).require_plan()
    grid = grid_for(plan, axis, around)
    path = case / "system" / NAME
    text = _function_object(grid, [b.name for b in plan.bodies])
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)
    control = case / "system" / "controlDict"
    body = control.read_text()
    if f'#include "{NAME}"' not in body:
        new, n = re.subn(r"(\nfunctions\s*\n?\s*\{)", rf'\1\n    #include "{NAME}"', body, count=1)
        if n != 1:
            raise InputError("functions", f"no functions dictionary to include {NAME} in", str(control))
        control.write_text(new)
    return grid


def _sample_dirs(case: Path) -> list[tuple[float, Path]]:
    """The sampler's folders (one per solver segment) with their start times, oldest first."""
    return numeric_dirs(case / "postProcessing" / NAME)


def read_sample(path: Path, axis: ZAxis, time_s: float) -> Sample | None:
    """One sample folder's column depths; None if its file is missing or being written."""
    f = path / "depth_alpha.water.xy"
    try:
        data = np.loadtxt(f, ndmin=2)
    except (OSError, ValueError):
        return None
    if data.size == 0 or data.shape[1] < 4:
        return None
    # one point per layer; a point outside the mesh (inside the column) is left out. A point in a
    # body's overset mesh as well as the background, the two on different ranks, is written by both
    # ("seems to be on multiple domains" in the log): its value is their mean, else the column
    # reads that layer twice (80 mm of still water around a floating container read 160 mm)
    points = np.round(data[:, :3] / (0.01 * axis.cell_m)).astype(np.int64)
    points, at_point = np.unique(points, axis=0, return_inverse=True)
    at_point = at_point.ravel()
    alpha = np.bincount(at_point, weights=np.clip(data[:, 3], 0.0, 1.0)) / np.bincount(at_point)
    z = points[:, 2] * 0.01 * axis.cell_m
    uniq, inverse = np.unique(points[:, :2], axis=0, return_inverse=True)
    depth = np.bincount(inverse.ravel(), weights=alpha * axis.dz[axis.layer(z)])
    return Sample(time_s, uniq * 0.01 * axis.cell_m, depth)


def read_latest(case_dir: str | Path, axis: ZAxis, after_s: float = -math.inf) -> Sample | None:
    """The newest complete sample later than `after_s` (None if none)."""
    for t, path in reversed(_sample_dirs(Path(case_dir))):
        if t <= after_s:
            return None
        sample = read_sample(path, axis, t)
        if sample is not None:
            return sample
    return None


def read_at(case_dir: str | Path, axis: ZAxis, time_s: float, tolerance_s: float | None = None) -> Sample | None:
    """The newest sample at or before `time_s` (within `tolerance_s`, default one sample interval)."""
    tol = SAMPLE_INTERVAL_S * 1.01 if tolerance_s is None else tolerance_s
    for t, path in reversed(_sample_dirs(Path(case_dir))):
        if t > time_s + 1e-9:
            continue
        if t < time_s - tol:
            return None
        sample = read_sample(path, axis, t)
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
                 orientation: Sequence[Sequence[float]], size: Sequence[float],
                 others: Sequence[tuple[Sequence[float], Sequence[Sequence[float]], Sequence[float]]] = ()
                 ) -> tuple[float, int] | None:
    """The water depth (m) all around a body: the `DEPTH_QUANTILE` quantile over the ring of
    columns `ring_m` (inner, outer distance) off its footprint, and how many columns.

    `others`: the other bodies (centre, orientation, size). The ring's columns nearer than its
    inner limit to another body's footprint are left out, for the reason the inner limit keeps the
    ring off the body's own: the background cells there are that body's overset holes and keep
    stale values. In the 3x1 layout two-way (three containers 0.10 m apart in a line) a third of
    the middle body's ring lies there; at 2.14 s those columns read 19-53 mm against 61 mm (10 %
    quantile) for the rest of its ring. Read with them, the rings read 12-30 mm from 1.3 to 1.6 s,
    about the 15 mm wet bed's, after the fluid's lift had passed each body's weight (by 1.30-1.52
    s), and held the bodies on the bed until 1.55-1.89 s, 0.16-0.52 s after the one-way bodies
    floated. If no column is left, the whole ring is read."""
    dist = footprint_distance(sample.xy, centre, orientation, size)
    ring = (dist >= ring_m[0] * 0.999) & (dist <= ring_m[1] * (1 + 1e-9))
    if not ring.any():
        return None
    clear = ring.copy()
    for c, rot, extent in others:
        clear &= footprint_distance(sample.xy, c, rot, extent) >= ring_m[0] * 0.999
    use = clear if clear.any() else ring
    return float(np.quantile(sample.depth_m[use], DEPTH_QUANTILE)), int(use.sum())


def read_lift(case_dir: str | Path, body: str, until_s: float = math.inf,
              window_s: float = SAMPLE_INTERVAL_S) -> float | None:
    """The mean vertical fluid force (N) on a body's wall over the last `window_s` of simulated time
    up to `until_s` (the forces function object `lift_<body>`), from the newest segment that has
    steps more than `LIFT_SETTLE_S` after its start; None if there is none yet."""
    force = _read_mean(case_dir, body, "force.dat", until_s, window_s)
    return None if force is None else float(force[2])


def read_load(case_dir: str | Path, body: str, until_s: float = math.inf,
              window_s: float = SAMPLE_INTERVAL_S) -> tuple[np.ndarray, np.ndarray] | None:
    """The mean fluid force (N) and moment (N m, about the origin, as `lift_<body>` writes it) on a
    body's wall over the same window as `read_lift`; None if either is not there yet."""
    force = _read_mean(case_dir, body, "force.dat", until_s, window_s)
    moment = _read_mean(case_dir, body, "moment.dat", until_s, window_s)
    return None if force is None or moment is None else (force, moment)


def _segments(case_dir: str | Path, body: str) -> list[tuple[float, Path]]:
    """The folders of `lift_<body>` (one per solver segment) with their start times, oldest first."""
    return numeric_dirs(Path(case_dir) / "postProcessing" / f"{LIFT_PREFIX}{body}")


def _settled_rows(start: float, path: Path, until_s: float = math.inf) -> list[tuple[float, tuple[float, float, float]]]:
    """(time, total (x, y, z)) of a forces file of one segment, from `LIFT_SETTLE_S` after its start
    (not the first steps after a restart) to `until_s`; a line being written is left out."""
    try:
        lines = path.read_text().splitlines()
    except OSError:
        return []
    rows = []
    for line in lines:
        if not line or line.startswith("#"):
            continue
        parts = line.replace("(", " ").replace(")", " ").split()
        if len(parts) < 4:
            continue  # a line being written
        try:
            t, v = float(parts[0]), (float(parts[1]), float(parts[2]), float(parts[3]))
        except ValueError:
            continue
        if start + LIFT_SETTLE_S < t <= until_s + 1e-9:
            rows.append((t, v))
    return rows


def _read_mean(case_dir: str | Path, body: str, file: str, until_s: float, window_s: float) -> np.ndarray | None:
    """The mean total (x, y, z) of a forces file of `lift_<body>` over the window (see read_lift)."""
    for start, p in reversed(_segments(case_dir, body)):
        if start >= until_s - 1e-9:
            continue
        rows = _settled_rows(start, p / file, until_s)
        if rows:
            last = rows[-1][0]
            return np.mean([v for t, v in rows if t > last - window_s - 1e-12], axis=0)
    return None


def read_force_history(case_dir: str | Path, body: str) -> np.ndarray:
    """The fluid force on a body's wall at every solver step of the whole run, (N, 4): time (s) and
    total x, y, z (N), from `lift_<body>`, its segments joined over restarts as every function
    object's are (`read_force_series`), less each segment's first `LIFT_SETTLE_S` (see read_lift)."""
    table, _ = read_force_series(case_dir, f"{LIFT_PREFIX}{body}")
    if table is None or table.empty:
        return np.zeros((0, 4))
    t = table["time"].to_numpy(float)
    starts = np.array([start for start, _ in _segments(case_dir, body)])
    newest = starts[np.clip(np.searchsorted(starts, t, side="left") - 1, 0, None)]
    keep = t > newest + LIFT_SETTLE_S
    return np.column_stack([t, table.iloc[:, 1:4].to_numpy(float)])[keep]  # the total force: the first vector
