"""How the debris meets the flow (scene ``run.debris_coupling``), and the flow a one-way run records.

* two-way: every body a six-DoF body on its own overset mesh inside the flow (overInterDyMFoam):
  the flow moves the bodies and the bodies change the flow.
* one-way: the flow once without the bodies (interFoam on the same background mesh), recorded on
  a regular grid (:class:`~orchestrator.plan.model.FlowRecordPlan`), then any number of bodies
  carried through the record (:mod:`orchestrator.transport`): the bodies feel the flow, the flow
  does not feel them. The flume study this project reproduces found the debris barely changes
  the flow; a one-way run costs the flow once instead of an overset run per layout.

``auto`` picks one-way when the bodies cannot change the flow much, by two numbers:

* the displaced volume: the bodies' total box volume (what they push aside when submerged; an
  upper bound for a floating body) over the water impounded in the reservoir (its length x the
  flume's width x its depth). One-way under :data:`VOLUME_LIMIT` = 0.1 %: a tenth of the 1 %
  water balance a run is held to (run.water_balance_limit's default), so the water the bodies
  push aside is less than the solver's own conservation may miss.
* the frontal blockage: the sum of the bodies' widths across the flow (each footprint's extent
  in y; bodies behind one another each count) over the flume's width. One-way under
  :data:`BLOCKAGE_LIMIT` = :data:`~orchestrator.plan.domain.RUNUP_BLOCKAGE` (0.4): narrower
  obstacles let the bore pass round them (measured on the tiny flume: a column across a third
  of the width sent 0.008 % of the water over a 1.5 h0 top, half the width 0.19 %, the whole
  width 1.9 %).

The study's four layouts (cases/1debris, 3debris-3x1, 3debris-1x3, 6debris-2x3: 0.15 x 0.06 x
0.06 m containers, a 21.55 x 1.5 x 0.4 m reservoir) displace 0.0042-0.025 % of the reservoir
and block 4-24 % of the width: one-way. The tiny test flumes (one container, a 0.5-0.8 m x
0.4 m x 0.16 m reservoir) displace 1-1.7 %: two-way.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

from orchestrator.plan.domain import RUNUP_BLOCKAGE, Domain
from orchestrator.plan.grading import cell_edges
from orchestrator.plan.refine import record_axis, refine_span, refinement
from orchestrator.plan.grid import BoxGrid
from orchestrator.plan.model import FlowRecordPlan
from orchestrator.scene.schema import Scene

__all__ = [
    "BLOCKAGE_LIMIT",
    "ONE_WAY_MAX_COURANT",
    "RECORD_MAX_POINTS",
    "RECORD_NAME",
    "VOLUME_LIMIT",
    "DebrisLoad",
    "choose_coupling",
    "debris_load",
    "flow_record_plan",
    "lee_warnings",
]

#: One-way under this displaced volume, as a fraction of the reservoir's water.
VOLUME_LIMIT = 1e-3
#: One-way under this frontal blockage (sum of the bodies' widths over the flume's width).
BLOCKAGE_LIMIT = RUNUP_BLOCKAGE
#: maxCo and maxAlphaCo of a one-way flow run at most: the study's scenes ask 2.5 for the overset
#: solver, which counts hole and fringe faces in its Courant number (cases/1debris.yaml);
#: interFoam's explicit MULES keeps alpha bounded only up to an alpha Courant number of 1.
ONE_WAY_MAX_COURANT = 1.0
#: The sampling function object and its postProcessing/ folder.
RECORD_NAME = "flowRecord"
#: Sample points per frame at most: the x, y spacing grows by whole cell sizes until the grid fits
#: (100k points: 1.2 MB of float32 velocity per frame, 60 MB a second at 50 Hz before compression).
RECORD_MAX_POINTS = 100_000


class DebrisLoad(NamedTuple):
    """The numbers of the coupling criterion for a scene's debris."""

    #: the bodies' total box volume (m^3)
    volume_m3: float
    #: the water impounded in the reservoir (m^3)
    reservoir_m3: float
    #: the sum of the bodies' widths across the flow over the flume's width (-)
    blockage: float

    @property
    def volume_fraction(self) -> float:
        return self.volume_m3 / self.reservoir_m3


def _footprints(scene: Scene, rotations: Sequence[np.ndarray]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each body's (centre, half extent) in x, y at the start (its box turned by its rotation,
    ``rotations`` in the scene's order: the body layout's, :class:`~orchestrator.plan.bodies.BodyLayout`)."""
    out = []
    for body, rot in zip(scene.debris, rotations):
        half = np.abs(rot) @ (np.asarray(body.size_m, float) / 2.0)
        out.append((np.asarray(body.centre_m[:2], float), half[:2]))
    return out


def lee_warnings(scene: Scene, rotations: Sequence[np.ndarray]) -> list[str]:
    """A warning for each body that starts in another's lane downstream of it (their extents across
    the flow overlap; the flow runs along +x), naming its nearest such neighbour and the gap
    between them: one-way transport has no wake, so it drives such a body by the flow without
    bodies at its own place as if it were alone."""
    feet = _footprints(scene, rotations)
    warnings = []
    for j, (cj, hj) in enumerate(feet):
        ahead = []
        for i, (ci, hi) in enumerate(feet):
            lane = min(ci[1] + hi[1], cj[1] + hj[1]) - max(ci[1] - hi[1], cj[1] - hj[1]) > 1e-9
            gap = (cj[0] - hj[0]) - (ci[0] + hi[0])
            if i != j and lane and gap >= -1e-9:
                ahead.append((gap, scene.debris[i].name))
        if ahead:
            gap, name = min(ahead)
            warnings.append(
                f"{scene.debris[j].name} starts in {name}'s lane {gap:.3g} m downstream of it: one-way transport has "
                "no wake, it drives every body by the flow without bodies at its own place, as if alone; two-way, the "
                "3x1 layout's three containers in line, pressed together, were driven with about a tenth of the "
                "one-way forcing on the same tracks (docs/one-way.md)")
    return warnings


def debris_load(scene: Scene, rotations: Sequence[np.ndarray]) -> DebrisLoad:
    """The two numbers of the coupling criterion (module docstring); ``rotations``: the bodies'."""
    volume = sum(math.prod(b.size_m) for b in scene.debris)
    reservoir = scene.reservoir.length_m * scene.flume.width_m * scene.reservoir.depth_m
    widths = sum(2.0 * half[1] for _, half in _footprints(scene, rotations))
    return DebrisLoad(float(volume), float(reservoir), float(widths / scene.flume.width_m))


def choose_coupling(scene: Scene, rotations: Sequence[np.ndarray], reasons: dict[str, str],
                    warnings: list[str]) -> str:
    """"none", "one-way" or "two-way" for ``scene`` whose bodies are turned by ``rotations``, with its
    reason (module docstring)."""
    asked = scene.run.debris_coupling
    n = len(scene.debris)
    if not n:
        reasons["debris_coupling"] = "none: the scene has no debris"
        return "none"
    load = debris_load(scene, rotations)
    small_volume = load.volume_fraction < VOLUME_LIMIT
    narrow = load.blockage < BLOCKAGE_LIMIT
    one = n == 1
    numbers = (
        f"the {n} bod{'y' if one else 'ies'} displace{'s' if one else ''} {load.volume_m3:.3g} m^3, "
        f"{100 * load.volume_fraction:.2g} % of the reservoir's {load.reservoir_m3:.3g} m^3 of water "
        f"({'under' if small_volume else 'not under'} {100 * VOLUME_LIMIT:g} %, a tenth of the 1 % water balance a "
        f"run is held to), and block{'s' if one else ''} {100 * load.blockage:.3g} % of the flume's width with "
        f"{'its width' if one else 'their widths'} across the flow ({'under' if narrow else 'not under'} {100 * BLOCKAGE_LIMIT:g} %, below which the bore passes round "
        "an obstacle)"
    )
    auto = "one-way" if small_volume and narrow else "two-way"
    if (auto if asked == "auto" else asked) == "one-way":
        warnings += lee_warnings(scene, rotations)
    if asked == "auto":
        choice = auto
        why = ("so they barely change the flow: the flow once without them, recorded, the bodies carried through "
               "the record" if choice == "one-way" else
               "so they may change the flow: the bodies on overset meshes in the flow")
        reasons["debris_coupling"] = f"{choice} (run.debris_coupling auto): {numbers}; {why}"
        return choice
    reasons["debris_coupling"] = f"{asked} (run.debris_coupling): {numbers}; auto would choose {auto}"
    if asked == "one-way" and auto == "two-way":
        warnings.append(f"run.debris_coupling one-way although {numbers}: the record is of a flow the bodies "
                        "would change")
    return asked


def _refined_record(scene: Scene, background: BoxGrid, xs: np.ndarray, ys: np.ndarray):
    """The record's x and y samples with the refinement box's cell centres inside it (plan/refine.py)."""
    refined = refinement(scene)
    if refined is None:
        return xs, ys
    box = refined[0]
    cx, cy = (0.5 * (e[:-1] + e[1:]) for e in (cell_edges(background.x), cell_edges(background.y)))
    return record_axis(xs, cx, refine_span(box, 0)), record_axis(ys, cy, refine_span(box, 1))


def flow_record_plan(scene: Scene, rotations: Sequence[np.ndarray], background: BoxGrid, domain: Domain,
                     reasons: dict[str, str]) -> FlowRecordPlan:
    """The flow a one-way run records: region, sample grid and rate, with the reason.

    Region: from the bodies' start footprints, less a margin (the largest body's diagonal, so a
    body may turn round where it starts, plus two cells for the interpolation), to the domain's
    downstream end: bodies pass beside the column and on, and the transport closes the record's
    ends with walls, so a record ending just past the column would hold them there and push
    them back into it; with a sill, from the gate. The full width; from the bed (downstream of the gate) to the
    domain's top (no water is higher). x and y evenly spaced at the
    finest cell size, or whole multiples of it to keep :data:`RECORD_MAX_POINTS`; z at the
    background's cell centres, so the water column is exactly ``sum(alpha dz)``.
    """
    h = scene.mesh.cell_size_m
    feet = _footprints(scene, rotations)
    lo = np.min([c - e for c, e in feet], axis=0)
    hi = np.max([c + e for c, e in feet], axis=0)
    margin = max(2.0 * float(np.hypot(*e)) for _, e in feet) + 2 * h
    x0 = max(domain.x_lo, lo[0] - margin)
    x1 = domain.x_hi
    (y0, y1), inset = domain.y, 1e-3 * h  # a hair inside the walls: a point on a boundary face may be lost
    faces = cell_edges(background.z)
    if scene.reservoir.sill_height_m > 0:
        # the grid below the downstream bed is the reservoir's alone: the record starts at the gate and
        # at the bed (a body's region upstream of the gate is then refused by the record's check)
        x0 = max(x0, 0.0)
        faces = faces[faces >= -1e-9 * h]
    zc = 0.5 * (faces[:-1] + faces[1:])
    k = 1
    while True:
        nx = max(1, math.floor((x1 - x0) / (k * h) + 1e-9))
        ny = max(1, math.floor((y1 - y0 - 2 * inset) / (k * h) + 1e-9))
        if (nx + 1) * (ny + 1) * zc.size <= RECORD_MAX_POINTS or (nx == 1 and ny == 1):
            break
        k += 1
    xs = np.linspace(x0, x1, nx + 1)
    ys = np.linspace(y0 + inset, y1 - inset, ny + 1)
    step_x, step_y = (x1 - x0) / nx, (y1 - y0 - 2 * inset) / ny
    xs, ys = _refined_record(scene, background, xs, ys)
    nx, ny = xs.size - 1, ys.size - 1
    interval = 1.0 / scene.outputs.flow_record_hz
    record = FlowRecordPlan(
        RECORD_NAME, float(f"{interval:.10g}"), tuple(float(v) for v in xs), tuple(float(v) for v in ys),
        tuple(float(v) for v in zc), tuple(float(v) for v in faces),
        ((float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))))
    frames = math.floor(scene.run.end_time_s / interval + 1e-9) + 1
    per_frame = record.points * 3 * 4 + (nx + 1) * (ny + 1) * 8
    reasons["flow_record"] = (
        f"{RECORD_NAME}: alpha.water and U every {interval:.4g} s ({scene.outputs.flow_record_hz:g} Hz, "
        f"outputs.flow_record_hz) on {nx + 1} x {ny + 1} x {zc.size} = {record.points} points: "
        f"x {x0:.4g}..{x1:.4g} m every {step_x:.4g} m (the bodies' start footprints, less a "
        f"{margin:.3g} m margin: the largest body's diagonal and two cells, to the domain's downstream end: the "
        "record's ends are walls for the bodies, so it reaches past the column as far as the flow is modelled), the full width every "
        f"{step_y:.4g} m"
        + (" (at the cell centres inside the refinement box)" if refinement(scene) is not None else "")
        + (f" ({k} cell sizes: at most {RECORD_MAX_POINTS} points)" if k > 1 else "")
        + f", z at the background's {zc.size} cell centres from the bed to the domain's top {faces[-1]:.3g} m "
        "(no water is higher), so sum(alpha dz) is each cell column's water; "
        f"{per_frame / 1e6:.2g} MB a frame as float32 before compression, {frames} frames to the end time"
    )
    return record
