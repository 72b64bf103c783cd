"""Planning: decide what a scene needs to be modelled, and say why.

:func:`plan_case` is a pure function ``Scene -> ModelPlan``. It chooses the solver
(interFoam on a static mesh without debris, overInterDyMFoam with one six-DoF body per
debris otherwise), 2D or 3D, how much of the reservoir and of the downstream flume to
model, where cells are fine and how they coarsen, the body meshes, the water to fill,
the gauges and the domain decomposition. Every choice has a sentence in
``ModelPlan.reasons``; ``ModelPlan.to_json()`` is written to ``plan.json`` in a case.

Physics used for the extents (shallow-water characteristics, ``c0 = sqrt(g h0)``):

* Reservoir. The negative wave leaves the gate at t = 0 and runs upstream at ``c0``;
  it reflects at the upstream wall and its head comes back along a C+ characteristic of
  the simple wave, at ``u + c = (4 c0 + x/t)/3 <= 4/3 c0`` upstream of the gate. So with
  ``L`` modelled and a guarded region reaching ``d`` upstream of the gate, the reflection
  arrives no earlier than ``L/c0 + (L - d)/(4/3 c0)``; ``L`` is the smallest length that
  keeps this after ``SAFETY x end_time``, never more than the scene's reservoir.
* Downstream. A disturbance from the downstream boundary can only start when the bore
  front gets there (front speed ``S``: Stoker's bore on a wet bed, ``2 c0`` on a dry one,
  both upper bounds because friction slows the front) and then has to travel back
  against the flow. Behind a supercritical front nothing travels upstream, so an outlet
  need only clear the column's wake; a wall reflects a bore that runs back at no more
  than ``c0``.
* Top. The air space is trimmed to 1.5 ``h0`` unless the front (at most ``2 c0``) can reach
  a closed end or a column across at least :data:`RUNUP_BLOCKAGE` of the width within the
  run: the bore then runs up it to about the stagnation head of Ritter's front,
  ``(2 c0)^2 / 2g = 2 h0`` (:data:`RUNUP_DEPTHS`), and the air space goes up to the walls.

Cell sizes: ``mesh.cell_size_m`` (h) inside the fine region, then growing by at most
``mesh.growth_ratio`` per cell up to ``h x mesh.coarsening_ratio``.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from itertools import product
from typing import Any, Literal

import numpy as np

from analytical.contact_law import box_inertia
from orchestrator.plan.grid import BoxGrid, Segment, graded_segment
from orchestrator.scene.geometry import body_rotation, draft_m, flume_extent, half_extent_z
from orchestrator.scene.schema import DebrisBody, Scene

__all__ = [
    "BodyPlan",
    "GaugePlan",
    "ModelPlan",
    "REASON_KEYS",
    "SAFETY",
    "US_PER_CELL_STEP",
    "WaterBox",
    "body_inertia",
    "estimate_wall_time_s",
    "estimated_steps",
    "max_delta_t_s",
    "plan_case",
]

#: Multiplier on the simulated time when sizing the domain (10 % margin).
SAFETY = 1.10
#: Wall time per cell per time step on 2 cores (s; docs/openfoam-notes.md, "Cost"): interFoam
#: 2-5 us (mid value). overInterDyMFoam measured on the seed's 1-debris scene at 4 cm
#: (111k cells, 3,760 of them the body's): 374 steps to t = 1.19 s in 413 s of solver CPU,
#: 10 us per cell-step (5.9 us with a coarser 1,280-cell body mesh).
US_PER_CELL_STEP = {"interFoam": 3.5e-6, "overInterDyMFoam": 10.0e-6}
#: Cores at which US_PER_CELL_STEP was measured.
_MEASURED_CORES = 2
#: Measured time steps over the steps the Courant limit at Ritter's front speed predicts
#: (run.max_courant x smallest horizontal cell / 2 sqrt(g h0)), where maxDeltaT does not bind.
#: interFoam: 1.11 and 1.39 (the no-debris mesh study at 4 and 3 cm, README). overInterDyMFoam:
#: 2.3-4.3, median 2.8, over six debris hard cases of docs/stability.md (runs before the gap under resting bodies):
#: v1912 counts hole and fringe faces in its Courant number, and the flow past a body is
#: faster than the front. Before this factor the planner's debris estimates were 3-4x short.
STEP_FACTOR = {"interFoam": 1.25, "overInterDyMFoam": 2.8}
#: The trimmed air space: this many impoundment depths (mesh.top_m null, trim_domain true).
TOP_TRIM = 1.5
#: Run-up of the bore against a closed end or an obstacle, in impoundment depths: the stagnation
#: head u^2/2g of the fastest water a dam break makes, Ritter's front at u = 2 sqrt(g h0), plus its
#: depth (none at Ritter's tip): 2 h0. A wet bed and bed friction only slow the front. Measured on
#: a 2D closed tank at 2 cm cells (0.4 m reservoir, end wall 0.8 m past the gate, 1 s): over a
#: 1.5 h0 top at the end wall 1.8 % of the water left on a dry bed, 1.3 and 1.5 % on 15 and 40 mm
#: wet beds (h0 = 0.2 m), and the water ran up the wall to 1.8 h0 under h0 = 0.4 m on a 15 mm bed:
#: the wet bed's own front (Stoker: its depth plus its u^2/2g, 0.7 h0) is no bound for a wall.
RUNUP_DEPTHS = 2.0
#: An obstacle sends its run-up over the trimmed top only when it blocks this fraction of the
#: flume's width or more; a narrower one sends up a jet over its face and the bore passes round it.
#: Measured on the tiny flume of tests/data/post/tiny-nodebris.yaml (dry bed, h0 = 0.2 m, 2.5 cm
#: cells, open end, 1 s) under a 1.5 h0 top: a column across a third of the width let 0.008 % of
#: the water over the top, half 0.19 %, two thirds 0.39 %, the whole width 1.9 %.
RUNUP_BLOCKAGE = 0.4
#: Every decision the plan records a reason for.
REASON_KEYS = (
    "solver",
    "two_d",
    "gate",
    "reservoir_length",
    "domain_end",
    "downstream_type",
    "domain_top",
    "fine_region",
    "grading",
    "bodies",
    "water",
    "bed_friction",
    "gauges",
    "decomposition",
    "time_step",
    "cell_count",
    "run_controls",
)

_BG_PATCHES = {
    "xmin": "upstreamWall",
    "xmax": "downstream",
    "ymin": "sideWalls",
    "ymax": "sideWalls",
    "zmin": "bed",
    "zmax": "atmosphere",
    "hole": "column",
}
_SIDES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")


# -------------------------------------------------------------------------- results


@dataclass(frozen=True)
class WaterBox:
    """An axis-aligned box to fill with water (setFields boxToCell), corners in m."""

    name: str
    min_m: tuple[float, float, float]
    max_m: tuple[float, float, float]


@dataclass(frozen=True)
class GaugePlan:
    """A wave gauge: a vertical sampling line at (x, y) from the bed to z_top (m)."""

    name: str
    x: float
    y: float
    z_top: float


@dataclass(frozen=True)
class BodyPlan:
    """One six-DoF debris body on its own overset mesh.

    ``grid`` is in body coordinates (centred on the body, axes along its length, width,
    height) and placed by its ``origin`` (the centre of mass) and ``rotation``
    (= ``orientation``). Patches: every outer side ``<name>Overset``, the body ``<name>``.
    ``moment_of_inertia_kg_m2`` are the principal moments about the body axes through
    the centre of mass; ``orientation`` maps body axes to scene axes (columns = body axes).
    """

    name: str
    grid: BoxGrid
    mass_kg: float
    centre_of_mass_m: tuple[float, float, float]
    moment_of_inertia_kg_m2: tuple[float, float, float]
    orientation: tuple[tuple[float, float, float], ...]
    size_m: tuple[float, float, float]
    on_bed: bool = False
    cell_size_m: float = 0.0
    velocity_m_s: tuple[float, float, float] = (0.0, 0.0, 0.0)
    #: > 0: the body is held on the bed (sixDoF constraints: it slides and yaws, but cannot
    #: sink or tip) until this time, when the bore is deep enough to lift it (s)
    hold_until_s: float = 0.0
    #: the body may only yaw (a sixDoF `axis` constraint, for the whole run)
    upright: bool = False


@dataclass(frozen=True)
class ModelPlan:
    """What the case will model. Lengths m, times s; ``reasons`` says why for each choice."""

    scene_name: str
    solver: Literal["interFoam", "overInterDyMFoam"]
    two_d: bool
    background: BoxGrid
    bodies: tuple[BodyPlan, ...]
    water: tuple[WaterBox, ...]
    gauges: tuple[GaugePlan, ...]
    cell_count: int
    decomposition: tuple[int, int, int]
    end_time_s: float
    write_interval_s: float
    max_courant: float
    domain_m: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    fine_region_m: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    downstream_type: Literal["wall", "outlet"]
    bed_friction_factor: float
    velocity_scale_m_s: float
    time_step_estimate_s: float
    reasons: dict[str, str]
    warnings: tuple[str, ...] = ()
    estimated_wall_time_s: float = field(default=0.0)
    #: multiplier on the bed-friction drag coefficient (scene bed.friction_calibration)
    bed_friction_calibration: float = 1.0
    #: the runner's stall limit (scene run.stall_limit_s; None: the runner's default)
    stall_limit_s: float | None = None
    #: the runner's water-balance stop (scene run.water_balance_limit; None: the runner's default)
    water_balance_limit: float | None = None
    #: height of the water gap under bodies resting on the bed (BedGap; 0: none rests)
    bed_gap_m: float = 0.0

    @property
    def cores(self) -> int:
        nx, ny, nz = self.decomposition
        return nx * ny * nz

    def to_dict(self) -> dict[str, Any]:
        return {
            "scene_name": self.scene_name,
            "solver": self.solver,
            "two_d": self.two_d,
            "cell_count": self.cell_count,
            "estimated_wall_time_s": round(self.estimated_wall_time_s, 1),
            "time_step_estimate_s": self.time_step_estimate_s,
            "velocity_scale_m_s": self.velocity_scale_m_s,
            "decomposition": {"method": "hierarchical", "n": list(self.decomposition)},
            "end_time_s": self.end_time_s,
            "write_interval_s": self.write_interval_s,
            "max_courant": self.max_courant,
            "domain_m": [list(a) for a in self.domain_m],
            "fine_region_m": [list(a) for a in self.fine_region_m],
            "downstream_type": self.downstream_type,
            "bed_friction_factor": self.bed_friction_factor,
            "bed_friction_calibration": self.bed_friction_calibration,
            "stall_limit_s": self.stall_limit_s,
            "water_balance_limit": self.water_balance_limit,
            "bed_gap_m": self.bed_gap_m,
            "background": _grid_dict(self.background),
            "bodies": [
                {
                    "name": b.name,
                    "mass_kg": b.mass_kg,
                    "centre_of_mass_m": list(b.centre_of_mass_m),
                    "moment_of_inertia_kg_m2": list(b.moment_of_inertia_kg_m2),
                    "orientation": [list(r) for r in b.orientation],
                    "size_m": list(b.size_m),
                    "on_bed": b.on_bed,
                    "hold_until_s": b.hold_until_s,
                    "cell_size_m": b.cell_size_m,
                    "grid": _grid_dict(b.grid),
                }
                for b in self.bodies
            ],
            "water": [{"name": w.name, "min_m": list(w.min_m), "max_m": list(w.max_m)} for w in self.water],
            "gauges": [{"name": g.name, "x": g.x, "y": g.y, "z_top": g.z_top} for g in self.gauges],
            "reasons": dict(self.reasons),
            "warnings": list(self.warnings),
        }

    def to_json(self) -> str:
        """plan.json: every choice, the grids and a reason for each decision."""
        return json.dumps(self.to_dict(), indent=2)


def _grid_dict(grid: BoxGrid) -> dict[str, Any]:
    def segs(axis):
        return [
            {"start_m": s.start_m, "end_m": s.end_m, "cells": s.cells, "grading": s.grading}
            for s in getattr(grid, axis)
        ]

    return {
        "name": grid.name,
        "cell_count": grid.cell_count(),
        "x": segs("x"),
        "y": segs("y"),
        "z": segs("z"),
        "holes": sorted(list(h) for h in grid.holes),
        "patch_names": dict(grid.patch_names),
        "origin": list(grid.origin),
        "rotation": [list(r) for r in grid.rotation],
    }


# -------------------------------------------------------------------------- physics


def body_inertia(
    size_m: tuple[float, float, float], mass_kg: float, wall_thickness_m: float | None
) -> tuple[float, float, float]:
    """Principal moments of inertia (kg m^2) of a closed box about its body axes
    (:func:`analytical.contact_law.box_inertia`: uniform walls, or solid)."""
    return box_inertia(size_m, mass_kg, wall_thickness_m)


@dataclass(frozen=True)
class _Front:
    """The flow behind the dam-break front: front speed, depth and velocity behind it."""

    speed_m_s: float
    depth_m: float
    velocity_m_s: float
    wet: bool
    g: float

    @property
    def froude(self) -> float:
        return math.inf if self.depth_m <= 0 else self.velocity_m_s / math.sqrt(self.g * self.depth_m)


def _front(h0: float, wet_depth: float, g: float) -> _Front:
    """Ritter's dry-bed front, or Stoker's wet-bed intermediate state (no friction)."""
    c0 = math.sqrt(g * h0)
    if wet_depth <= 0:
        return _Front(speed_m_s=2 * c0, depth_m=0.0, velocity_m_s=2 * c0, wet=False, g=g)
    from analytical.dambreak import stoker_state

    st = stoker_state(h0, wet_depth, g)
    return _Front(speed_m_s=st.shock_speed_m_s, depth_m=st.h2_m, velocity_m_s=st.u2_m_s, wet=True, g=g)


def _reservoir_length(end_time_s: float, h0: float, guard_m: float, g: float) -> float:
    """Shortest reservoir whose reflected negative wave reaches ``guard_m`` upstream of the
    gate no earlier than SAFETY x end_time (see the module docstring)."""
    c0 = math.sqrt(g * h0)
    return (SAFETY * end_time_s * c0 + 0.75 * guard_m) / 1.75


def _length_before_return(end_time_s: float, x_roi: float, front_speed: float, back_speed: float) -> float:
    """Smallest x_end with x_end/front + (x_end - x_roi)/back >= SAFETY x end_time."""
    t = SAFETY * end_time_s
    return (t + x_roi / back_speed) / (1.0 / front_speed + 1.0 / back_speed)


# ---------------------------------------------------------------------------- grids


def _pick_planes(lo: float, hi: float, wanted: list[tuple[float, int]], h: float) -> list[float]:
    """Planes lo..hi plus the wanted ones, by priority (2 hard, 1 useful, 0 soft).

    A useful plane closer than h/2 to a kept one, or a soft plane closer than one cell,
    is dropped (no slivers); hard planes are always kept.
    """
    kept = [lo, hi]
    gaps = {2: 1e-9, 1: 0.5 * h, 0: h}
    for pos, prio in sorted(wanted, key=lambda p: -p[1]):
        if not lo < pos < hi:
            continue
        if all(abs(pos - k) >= gaps[prio] for k in kept):
            kept.append(pos)
    return sorted(kept)


def _rests_on_bed(body: DebrisBody) -> bool:
    """Whether the body's lowest corner is on the bed."""
    return body.centre_m[2] - half_extent_z(body) <= 1e-6


def _body_cell_m(scene: Scene, body: DebrisBody, h: float) -> float:
    """The cell size of a body's mesh at the body: mesh.body_cells_across its smallest side, at most h."""
    return min(h, min(body.size_m) / scene.mesh.body_cells_across)


#: Cell layers in the gap left under a body resting on the bed (_bed_gap).
GAP_LAYERS = 4


@dataclass(frozen=True)
class BedGap:
    """The water gap left under bodies resting on the bed, in ``layers`` layers of ``layer_m``.

    v1912's overset (cellVolumeWeight) makes every body-mesh cell that overlaps a background
    cell touching the bed a hole, and every background cell that overlaps a body cell touching
    the body a hole. A body standing on the bed therefore has nothing valid under it: its
    underside kept a stale pressure and it never floated (docs/stability.md, "A container
    resting on the bed"). With a gap of four layers, both meshes sharing the planes, every
    layer has a valid donor: the body mesh's first layer (holes, over the background's bed
    cells), its second (interpolated from the background's calculated second layer), its third
    and fourth (calculated; the fourth touches the body). The background's fourth layer under the
    body is a hole and its third is interpolated from the body's calculated third.
    """

    layer_m: float
    layers: int = GAP_LAYERS

    @property
    def height_m(self) -> float:
        return self.layer_m * self.layers

    def planes(self) -> list[float]:
        return [self.layer_m * k for k in range(1, self.layers + 1)]


def _bed_gap(scene: Scene, h: float) -> BedGap | None:
    """The gap under resting bodies: layers an eighth of the finest resting body's cell.

    The gap (half a body cell: 7.5 mm under the seed's container at 1.5 cm body cells) delays
    the float-off until the water is that much deeper than the draft (``_hold_until_s``).

    A wet bed shallower than the gap sets the layer so that its surface is one of the planes
    (setFields fills whole cells by their centres: the bed must be a layer boundary).
    """
    resting = [b for b in scene.debris if _rests_on_bed(b)]
    if not resting:
        return None
    layer = min(_body_cell_m(scene, b, h) for b in resting) / (2 * GAP_LAYERS)
    wet = scene.bed.wet_depth_m
    if 0 < wet < GAP_LAYERS * layer:
        layer = wet / math.ceil(wet / layer - 1e-9)
    return BedGap(layer)


def _axis_segments(
    lo: float,
    hi: float,
    fine: tuple[float, float],
    wanted: list[tuple[float, int]],
    h: float,
    h_max: float,
    growth: float,
) -> tuple[Segment, ...]:
    """Segments lo..hi: cells h inside ``fine``, growing by ``growth`` per cell outside, to h_max."""
    planes = _pick_planes(lo, hi, wanted + [(fine[0], 0), (fine[1], 0)], h)
    s_sat = (h_max - h) / (growth - 1.0) if h_max > h else 0.0

    def dist(x: float) -> float:
        return max(fine[0] - x, x - fine[1], 0.0)

    def size(s: float) -> float:
        return min(h_max, h + (growth - 1.0) * s)

    segs: list[Segment] = []
    for a, b in zip(planes, planes[1:]):
        if a >= fine[0] - 1.01 * h and b <= fine[1] + 1.01 * h:
            segs.append(Segment(a, b, max(1, math.ceil((b - a) / h - 1e-9))))
            continue
        sa, sb = dist(a), dist(b)
        if min(sa, sb) >= s_sat - 1e-12:
            segs.append(Segment(a, b, max(1, math.ceil((b - a) / h_max - 1e-9))))
            continue
        if max(sa, sb) <= s_sat + 1e-12:
            segs.append(graded_segment(a, b, size(sa), size(sb)))
            continue
        # split where the cells reach h_max: graded near the fine region, uniform beyond
        cut = fine[1] + s_sat if sa < sb else fine[0] - s_sat
        if cut - a < 0.5 * h_max or b - cut < 0.5 * h_max:
            segs.append(graded_segment(a, b, size(sa), size(sb)))
        else:
            segs.append(graded_segment(a, cut, size(sa), size(dist(cut))))
            segs.append(graded_segment(cut, b, size(dist(cut)), size(sb)))
    return tuple(segs)


def _indices_within(segs: tuple[Segment, ...], lo: float, hi: float) -> list[int]:
    return [i for i, s in enumerate(segs) if lo - 1e-9 <= 0.5 * (s.start_m + s.end_m) <= hi + 1e-9]


def _cell_centres(seg: Segment) -> np.ndarray:
    n, r = seg.cells, seg.grading
    if n == 1 or abs(r - 1.0) < 1e-12:
        edges = np.linspace(seg.start_m, seg.end_m, n + 1)
    else:
        q = r ** (1.0 / (n - 1))
        sizes = q ** np.arange(n)
        edges = seg.start_m + np.concatenate([[0.0], np.cumsum(sizes)]) / sizes.sum() * seg.length_m
    return 0.5 * (edges[:-1] + edges[1:])


def _min_cell(segs: tuple[Segment, ...]) -> float:
    return min(min(s.cell_sizes_m()) for s in segs)


# ----------------------------------------------------------------------- the planner


def plan_case(scene: Scene) -> ModelPlan:
    """What ``scene`` needs: solver, dimensions, extents, grids, bodies, water, gauges.

    Pure: reads nothing, writes nothing. See the module docstring for the physics.
    """
    reasons: dict[str, str] = {}
    warnings: list[str] = []
    g = scene.fluids.gravity_m_s2
    h0 = scene.reservoir.depth_m
    c0 = math.sqrt(g * h0)
    T = scene.run.end_time_s
    h = scene.mesh.cell_size_m
    h_max = h * scene.mesh.coarsening_ratio
    growth = scene.mesh.growth_ratio
    col = scene.column
    (fx0, fx1), (fy0, fy1), _ = flume_extent(scene)
    width = scene.flume.width_m
    front = _front(h0, scene.bed.wet_depth_m, g)
    u_ref = 2.0 * c0  # Ritter's dry-bed front speed: no flow in a dam break is faster

    # ---- solver and dimensions
    has_debris = len(scene.debris) > 0
    solver = "overInterDyMFoam" if has_debris else "interFoam"
    if has_debris:
        reasons["solver"] = (
            f"{len(scene.debris)} debris bod{'y' if len(scene.debris) == 1 else 'ies'}: overInterDyMFoam with one "
            "six-DoF solver per body, each body on its own overset mesh"
        )
    else:
        reasons["solver"] = "no debris: interFoam on a static mesh (about 4x cheaper per cell-step than overset)"
    full_width_col = col is not None and col.size_y_m >= width - 1e-9 and abs(col.y_m) <= 1e-9
    two_d = not has_debris and (col is None or full_width_col)
    if two_d:
        reasons["two_d"] = (
            "2D: no debris and "
            + ("no column" if col is None else "the obstacle spans the full width")
            + ", so nothing varies across the flume; one cell across, frontAndBack empty"
        )
    else:
        why = []
        if has_debris:
            why.append("debris bodies move in 3D")
        if col is not None and not full_width_col:
            why.append("the column does not span the flume's width")
        reasons["two_d"] = "3D: " + " and ".join(why)
    reasons["gate"] = (
        f"gate '{scene.reservoir.gate}' modelled as instantaneous removal at t = 0"
        + (
            " (the swing gate's opening time and its supports, which the seed says constrict the flow, are not modelled)"
            if scene.reservoir.gate == "swing-gate"
            else ""
        )
    )

    # ---- body geometry (needed for the extents)
    margin_body = scene.mesh.body_margin_cells * h
    gap = _bed_gap(scene, h)
    lift = gap.height_m if gap is not None else 0.0
    centres = []  # each body's centre as modelled: resting bodies stand on the gap (BedGap)
    body_boxes = []  # AABB of each body's overset mesh, scene coordinates
    for body in scene.debris:
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
        half = np.asarray(body.size_m) / 2.0 + margin_body
        ext = np.abs(rot) @ half
        c = np.asarray(body.centre_m, float) + (0.0, 0.0, lift if _rests_on_bed(body) else 0.0)
        centres.append(c)
        body_boxes.append((c - ext, c + ext))
    bed_layer = scene.bed.wet_depth_m if scene.bed.wet_depth_m > 0 else None

    # ---- region of interest along x
    col_x0 = col.x_m - col.size_x_m / 2 if col else None
    col_x1 = col.x_m + col.size_x_m / 2 if col else None
    mc = max(0.5 * max(col.size_x_m, col.size_y_m), 3 * h) if col else 3 * h
    upstream_marks = [-h0] + [gg.x_m for gg in scene.gauges if gg.x_m < 0]
    upstream_marks += [lo[0] for lo, _ in body_boxes]
    if col:
        upstream_marks.append(col_x0 - mc)
    guard = max(0.0, -min(upstream_marks))

    # ---- reservoir length
    res_needed = _reservoir_length(T, h0, guard, g)
    res_floor = guard + max(h0, 4 * h)
    res_len = min(scene.reservoir.length_m, max(res_needed, res_floor))
    if not scene.mesh.trim_domain:
        res_len = scene.reservoir.length_m
    x_lo = -res_len
    t_return = res_len / c0 + max(res_len - guard, 0.0) / (4.0 / 3.0 * c0)
    if res_len < scene.reservoir.length_m - 1e-9:
        reasons["reservoir_length"] = (
            f"reservoir truncated to {res_len:.3g} m of {scene.reservoir.length_m:g} m: the negative wave "
            f"(c0 = sqrt(g h0) = {c0:.3g} m/s upstream, back at <= 4/3 c0) reflected from the upstream wall "
            f"reaches x = {-guard:.3g} m (gate region, upstream gauges and bodies) no earlier than "
            f"{t_return:.3g} s >= {SAFETY:g} x end_time ({T:g} s)"
        )
    else:
        reasons["reservoir_length"] = (
            f"whole reservoir ({res_len:g} m) modelled: a shorter one would let the reflected negative wave reach "
            f"x = {-guard:.3g} m before {SAFETY:g} x end_time"
            + (
                f" (with the full reservoir it arrives at about {t_return:.3g} s, within the run: that is the "
                "scene's own physics)"
                if t_return < T
                else ""
            )
        )
    if not scene.mesh.trim_domain:
        reasons["reservoir_length"] = f"whole reservoir ({res_len:g} m) modelled: mesh.trim_domain is false"

    # ---- downstream end
    if col:
        path_end = col_x1 + mc
    else:
        path_end = max([hi[0] + u_ref * T for _, hi in body_boxes], default=-math.inf)
        path_end = min(path_end, fx1)
    roi_end = max([path_end] + [gg.x_m for gg in scene.gauges] + [hi[0] for _, hi in body_boxes] + [0.0])
    wake = max(5 * col.size_y_m if col else 0.0, 2 * h0, 2 * max((max(b.size_m) for b in scene.debris), default=0.0))
    supercritical = front.froude > 1.0
    if supercritical:
        open_need = roi_end + wake
        open_why = (
            f"behind the front the flow is supercritical (Fr = {front.froude:.2g}"
            f"{', Stoker wet bed' if front.wet else ', Ritter dry bed'}), so nothing travels upstream from an outlet; "
            f"the domain ends {wake:.3g} m past the region of interest (x = {roi_end:.3g} m) to clear the column's "
            "wake and passing debris"
        )
    else:
        back = max(math.sqrt(g * front.depth_m) - front.velocity_m_s, 1e-6)
        open_need = max(roi_end + wake, _length_before_return(T, roi_end, front.speed_m_s, back))
        open_why = (
            f"subcritical flow behind the front (Fr = {front.froude:.2g}): a disturbance from the outlet, starting when "
            f"the front (S = {front.speed_m_s:.3g} m/s) arrives and travelling back at c - u = {back:.3g} m/s, "
            f"must not reach x = {roi_end:.3g} m before {SAFETY:g} x end_time"
        )
    wall_need = max(roi_end + wake, _length_before_return(T, roi_end, front.speed_m_s, c0))
    if not scene.mesh.trim_domain:
        x_hi = fx1
        downstream_type = "outlet" if scene.flume.downstream_end == "open" else "wall"
        reasons["domain_end"] = f"domain runs to the flume's end (x = {x_hi:.3g} m): mesh.trim_domain is false"
        reasons["downstream_type"] = f"{downstream_type}: the flume's downstream end is {scene.flume.downstream_end}"
    elif scene.flume.downstream_end == "open":
        x_hi = min(fx1, open_need)
        downstream_type = "outlet"
        reasons["domain_end"] = (
            f"domain ends at x = {x_hi:.3g} m"
            + (" (the flume's open end)" if x_hi >= fx1 - 1e-9 else f" of the flume's {fx1:.3g} m: " + open_why)
        )
        reasons["downstream_type"] = "outlet: the flume's downstream end is open (free outfall)"
    else:
        if wall_need >= fx1 - 1e-9:
            x_hi = fx1
            downstream_type = "wall"
            reasons["domain_end"] = (
                f"domain runs to the closed end wall (x = {fx1:.3g} m): a bore reflected from it (front at "
                f"<= {front.speed_m_s:.3g} m/s, back at <= c0 = {c0:.3g} m/s) could reach x = {roi_end:.3g} m "
                f"before {SAFETY:g} x end_time"
            )
            reasons["downstream_type"] = "wall: the flume's closed end is inside the modelled time's reach"
        else:
            x_hi = min(fx1, open_need)
            downstream_type = "outlet"
            reasons["domain_end"] = (
                f"domain ends at x = {x_hi:.3g} m, short of the closed end wall ({fx1:.3g} m), whose reflection "
                f"cannot reach x = {roi_end:.3g} m before {SAFETY:g} x end_time (it needs {wall_need:.3g} m); " + open_why
            )
            reasons["downstream_type"] = (
                "outlet: the domain is cut short of the closed end, whose reflection arrives after the run"
            )

    # ---- top: what can run up, and to where (RUNUP_DEPTHS)
    runup = RUNUP_DEPTHS * h0
    runup_from = []  # what the fastest front (2 c0) reaches within the run
    if downstream_type == "wall" and x_hi / u_ref < T:
        runup_from.append(f"the closed end wall (x = {x_hi:.3g} m, reached from {x_hi / u_ref:.2g} s)")
    blockage = 0.0
    if col:
        blockage = 1.0 if full_width_col else max(0.0, min(col.y_m + col.size_y_m / 2, fy1)
                                                   - max(col.y_m - col.size_y_m / 2, fy0)) / width
    if col and 0.0 < col_x0 and col_x0 / u_ref < T and blockage >= RUNUP_BLOCKAGE:
        runup_from.append(f"the column across {blockage:.0%} of the width (x = {col_x0:.3g} m, reached from "
                          f"{col_x0 / u_ref:.2g} s)")
    runup_why = (
        f"the bore can run up {' and '.join(runup_from)} to about {runup:.3g} m ({RUNUP_DEPTHS:g} h0: the stagnation "
        f"head u^2/2g of Ritter's front, u = 2 sqrt(g h0) = {u_ref:.3g} m/s, the fastest water of the dam break)"
    ) if runup_from else ""
    if scene.mesh.top_m is not None:
        z_hi = scene.mesh.top_m
        reasons["domain_top"] = f"air space up to mesh.top_m = {z_hi:g} m (set in the scene)"
        if runup_from and runup > z_hi + 1e-9 and z_hi < scene.flume.height_m - 1e-9:
            reasons["domain_top"] += f": below the run-up ({runup_why})"
            warnings.append(
                f"mesh.top_m = {z_hi:g} m is below the run-up the bore can reach ({runup:.3g} m at "
                f"{' and '.join(runup_from)}): water may leave through the top of the air space (post reports it "
                f"apart from the outlet's and warns past 0.1 %)"
            )
    elif not scene.mesh.trim_domain:
        z_hi = scene.flume.height_m
        reasons["domain_top"] = f"air space up to the flume's wall height ({z_hi:g} m): mesh.trim_domain is false"
    else:
        body_top = max((hi[2] for _, hi in body_boxes), default=0.0)
        trim = max(TOP_TRIM * h0, body_top)
        if runup_from and runup > trim:
            z_hi = scene.flume.height_m
            reasons["domain_top"] = (
                f"air space up to the walls (z = {z_hi:g} m, the flume's height), not trimmed to {trim:.3g} m: "
                + runup_why + ", above the trim; water that rises over the walls leaves the flume there too"
            )
        else:
            z_hi = min(scene.flume.height_m, trim)
            reasons["domain_top"] = (
                f"air space up to z = {z_hi:.3g} m = min(flume height {scene.flume.height_m:g} m, {TOP_TRIM:g} x impoundment"
                + (", the top of the highest body mesh" if body_top > TOP_TRIM * h0 else "")
                + "): "
                + (runup_why + ", within it" if runup_from else
                   "no closed end, and no obstacle across {:.0%} of the width or more, within the bore's reach "
                   "during the run: nothing runs up above the trim".format(RUNUP_BLOCKAGE)
                   + (f" (the column, across {blockage:.0%} of the width, sends up a jet over its face: splash-up "
                      "that mostly falls back)" if col else ""))
                + "; water above leaves through the open atmosphere patch (post reports it apart)"
            )

    # ---- fine region
    fine_x0 = min([-h0] + [lo[0] for lo, _ in body_boxes] + ([col_x0 - mc] if col else []))
    if col:
        fine_x1 = col_x1 + mc
        travel_end = col_x0
    else:
        fine_x1 = x_hi if has_debris else h0  # debris without a column drift to the domain end
        travel_end = x_hi
    # the bore's path also reaches every gauge downstream of the gate
    downstream_gauges = [gg.x_m + 3 * h for gg in scene.gauges if gg.x_m >= 0]
    fine_x1 = max([fine_x1] + [hi[0] for _, hi in body_boxes] + downstream_gauges)
    fine_x0, fine_x1 = max(fine_x0, x_lo), min(fine_x1, x_hi)
    tan_spread = math.tan(math.radians(scene.mesh.debris_spread_deg))
    ys = []
    if col:
        ys += [col.y_m - col.size_y_m / 2 - mc, col.y_m + col.size_y_m / 2 + mc]
    for lo, hi in body_boxes:
        travel = max(travel_end - lo[0], 0.0)
        ys += [lo[1] - tan_spread * travel, hi[1] + tan_spread * travel]
    fine_y0 = max(fy0, min(ys)) if ys else fy0
    fine_y1 = min(fy1, max(ys)) if ys else fy1
    fine_z1 = min(z_hi, max([h0] + [hi[2] for _, hi in body_boxes]))
    fine = ((fine_x0, fine_x1), (fine_y0, fine_y1), (0.0, fine_z1))
    reasons["fine_region"] = (
        f"cells of {h:g} m in x {fine_x0:.3g}..{fine_x1:.3g}, y {fine_y0:.3g}..{fine_y1:.3g}, z 0..{fine_z1:.3g} m: "
        "the gate region and the bore's path to the furthest gauge"
        + (", around the column" if col else "")
        + (
            f", and the debris paths (each body's mesh, spreading at {scene.mesh.debris_spread_deg:g} deg to "
            + ("the column" if col else "the domain end")
            + ")"
            if has_debris
            else ""
        )
        + "; in z the bed and the bore layer up to the impoundment depth"
    )

    # ---- background grid
    # setFields fills whole cells by their centres (boxToCell): the water is the scene's only where
    # every face of its boxes is a cell face. So the gate, the impoundment level and the wet-bed
    # surface are kept even when thin (a plane of the column's top 1 cm above a 0.39 m impoundment
    # would otherwise drop the impoundment's and fill the reservoir to 0.40 m, 2.6 % too much water)
    wx: list[tuple[float, int]] = [(0.0, 2)]
    wy: list[tuple[float, int]] = []
    wz: list[tuple[float, int]] = [(h0, 2)]
    if bed_layer is not None:
        wz.append((bed_layer, 2))
    if gap is not None:
        wz += [(z, 2) for z in gap.planes()]
    thinnest = min([bed_layer or h] + ([gap.layer_m] if gap else []))
    if thinnest < 0.2 * h:
        warnings.append(
            f"bed layer {thinnest:.3g} m thick under {h:g} m cells (aspect ratio {h / thinnest:.0f}): "
            + (f"the {gap.layers} layers of the gap under resting bodies" if gap else "the wet bed's own layer")
        )
    if col:
        wx += [(col_x0, 2), (col_x1, 2)]
        if not full_width_col:
            wy += [(col.y_m - col.size_y_m / 2, 2), (col.y_m + col.size_y_m / 2, 2)]
        if col.height_m < z_hi:
            wz.append((col.height_m, 2))
    xs = _axis_segments(x_lo, x_hi, fine[0], wx, h, h_max, growth)
    if two_d:
        ysegs = (Segment(fy0, fy1, 1),)
    else:
        ysegs = _axis_segments(fy0, fy1, fine[1], wy, h, h_max, growth)
    zs = _axis_segments(0.0, z_hi, fine[2], wz, h, h_max, growth)
    holes: frozenset = frozenset()
    if col:
        ii = _indices_within(xs, col_x0, col_x1)
        jj = list(range(len(ysegs))) if (two_d or full_width_col) else _indices_within(
            ysegs, col.y_m - col.size_y_m / 2, col.y_m + col.size_y_m / 2
        )
        kk = _indices_within(zs, 0.0, min(col.height_m, z_hi))
        holes = frozenset(product(ii, jj, kk))
    patches = dict(_BG_PATCHES)
    if two_d:
        patches["ymin"] = patches["ymax"] = "frontAndBack"
    background = BoxGrid("background", xs, ysegs, zs, holes, patches)
    reasons["grading"] = (
        f"outside the fine region cells grow by at most {growth:g} per cell up to {h_max:.3g} m "
        f"({scene.mesh.coarsening_ratio:g} x the finest); planes kept at the gate (x = 0), the impoundment level"
        + (", the wet-bed surface" if bed_layer is not None else "")
        + (f", {gap.layers} layers of {gap.layer_m:.3g} m at the bed (the gap under resting bodies)" if gap else "")
        + (" and the column's faces" if col else "")
        + f"; background {len(xs)} x {len(ysegs)} x {len(zs)} blocks"
    )

    # ---- bodies
    bodies = []
    holds: list[str] = []
    for body, centre, (lo, hi) in zip(scene.debris, centres, body_boxes):
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
        hb = _body_cell_m(scene, body, h)
        on_bed = _rests_on_bed(body)
        segs_by_axis = []
        for d in range(3):
            half = body.size_m[d] / 2.0
            inner = Segment(-half, half, max(1, math.ceil(2 * half / hb - 1e-9)))
            if d == 2 and on_bed and gap is not None and abs(rot[2, 2]) > 1 - 1e-9:
                # an upright resting body's mesh shares the gap's planes (BedGap)
                bed = -half - gap.height_m
                rows = tuple(Segment(bed + k * gap.layer_m, bed + (k + 1) * gap.layer_m, 1) for k in range(gap.layers))
                # below the bed: holes while the body rests, water under it once it floats
                below = (graded_segment(min(-half - margin_body, bed - h), bed, h, hb),)
                before = below + rows
            else:
                before = (graded_segment(-half - margin_body, -half, h, hb),)
            after = graded_segment(half, half + margin_body, hb, h)
            segs_by_axis.append((*before, inner, after))
        kz = len(segs_by_axis[2]) - 2  # the body's own z segment
        grid = BoxGrid(
            body.name,
            segs_by_axis[0],
            segs_by_axis[1],
            segs_by_axis[2],
            frozenset({(1, 1, kz)}),
            {**{s: f"{body.name}Overset" for s in _SIDES}, "hole": body.name},
            origin=tuple(float(v) for v in centre),
            rotation=tuple(tuple(float(v) for v in row) for row in rot),
        )
        if body.moment_of_inertia_kg_m2 is not None:
            inertia = tuple(float(v) for v in body.moment_of_inertia_kg_m2)
        else:
            inertia = body_inertia(body.size_m, body.mass_kg, body.wall_thickness_m)
        hold = _hold_until_s(scene, body, lift) if on_bed else 0.0
        if hold > 0:
            holds.append(f"{body.name} until {hold:.3g} s")
        bodies.append(
            BodyPlan(
                name=body.name,
                grid=grid,
                mass_kg=body.mass_kg,
                centre_of_mass_m=tuple(float(v) for v in centre),
                moment_of_inertia_kg_m2=inertia,
                orientation=tuple(tuple(float(v) for v in row) for row in rot),
                size_m=tuple(float(v) for v in body.size_m),
                on_bed=on_bed,
                cell_size_m=hb,
                velocity_m_s=tuple(float(v) for v in body.velocity_m_s),
                hold_until_s=hold,
                upright=on_bed if body.upright is None else bool(body.upright),
            )
        )
        outside = []
        if lo[2] < 0:
            outside.append(f"{-lo[2]:.3g} m below the bed")
        if lo[1] < fy0 or hi[1] > fy1:
            outside.append(f"{max(fy0 - lo[1], hi[1] - fy1):.3g} m through a side wall")
        if outside:
            warnings.append(
                f"{body.name}: its overset mesh reaches {' and '.join(outside)} at the start; cells there have no donors"
            )
    for i, (lo_a, hi_a) in enumerate(body_boxes):
        for j in range(i):
            lo_b, hi_b = body_boxes[j]
            if np.all(lo_a < hi_b) and np.all(lo_b < hi_a):
                warnings.append(
                    f"the overset meshes of {scene.debris[j].name} and {scene.debris[i].name} overlap at the start: "
                    "OpenFOAM v1912 may then never finish the overset addressing of the first step (the seed's "
                    "2x3 layout at 4 cm cells: over 17 min; docs/stability.md, six-debris)"
                )
    if bodies:
        reasons["hold_on_bed"] = (
            "held on the bed by sixDoF constraints (free to slide and yaw, not to sink or tip: v1912 has no "
            "contact, so a body heavier than its buoyancy would sink through the floor) until the analytical "
            "dam-break depth at the body's centre (Chanson with the scene's f; Ritter if f = 0) reaches its "
            "draft" + (f" plus the {lift:.3g} m gap it stands on" if lift else "")
            + " (the estimate here: the runner frees each body once the water it measures all round the body "
            "floats it and lifts it by its weight, orchestrator/run/bedwatch.py): " + ", ".join(holds)
            if holds else "no body rests on the bed: none is held"
        )
        if gap is not None:
            reasons["bed_gap"] = (
                f"bodies resting on the bed stand on a {lift:.3g} m gap of {gap.layers} cell layers of "
                f"{gap.layer_m:.3g} m that the background and their meshes share: v1912's overset holes the cells of "
                "one mesh over the other's wall-adjacent cells, so a body standing on the bed has no valid cell "
                "under it and its underside keeps a stale pressure (it never floats: docs/stability.md); "
                "the runner's bed stays the flume's: a released body that settles again sinks into the gap"
            )
        b0 = bodies[0]
        reasons["bodies"] = (
            f"{len(bodies)} overset body mesh(es): each box extends {scene.mesh.body_margin_cells} finest cells "
            f"({margin_body:.3g} m) beyond its body so donors lie in fine background cells and calculated body cells "
            "surround the body (thinner meshes let the flow pass the body by: docs/openfoam-notes.md); cells of "
            f"{b0.cell_size_m:.3g} m at the body ({scene.mesh.body_cells_across:g} across its smallest side), "
            f"{h:g} m at the mesh edge; inertia from the box walls (wall_thickness_m) or as given"
        )
    else:
        reasons["bodies"] = "no debris: no body meshes"

    # ---- water, gauges
    water = [WaterBox("reservoir", (x_lo, fy0, 0.0), (0.0, fy1, h0))]
    if scene.bed.wet_depth_m > 0:
        water.append(WaterBox("wetBed", (0.0, fy0, 0.0), (x_hi, fy1, scene.bed.wet_depth_m)))
    reasons["water"] = (
        f"water up to {h0:g} m behind the gate"
        + (f" and a {scene.bed.wet_depth_m:g} m wet bed downstream" if scene.bed.wet_depth_m > 0 else "; dry bed")
    )
    reasons["bed_friction"] = (
        f"Darcy f = {scene.bed.friction_factor:g} as a drag rho (f/8)|U|U on the first cell layer above the bed: "
        "without friction the front arrives 15-30 % early (docs/openfoam-notes.md); the drag is multiplied by "
        f"bed.friction_calibration = {scene.bed.friction_calibration:g}, calibrated against Chanson's arrival "
        "times (docs/bed-friction.md)"
    )
    gauges = tuple(GaugePlan(gg.name, gg.x_m, gg.y_m, z_hi) for gg in scene.gauges)
    reasons["gauges"] = (
        f"{len(gauges)} gauge line(s) from the bed to z = {z_hi:.3g} m; depth from alpha.water along each"
        if gauges
        else "no gauges"
    )

    # ---- cells, time step
    cells = background.cell_count() + sum(b.grid.cell_count() for b in bodies)
    horizontal = [_min_cell(xs)] + ([] if two_d else [_min_cell(ysegs)])
    for b in bodies:
        # the gap's flat layers under a resting body (BedGap), and the mesh's cells grading
        # down to them below the bed, carry horizontal flow or none: their Courant number is
        # set by their width, not their height; the body's own and upper segments count
        tall = tuple(s for s in b.grid.z if s.start_m >= -0.5 * b.size_m[2] - 1e-9)
        horizontal += [_min_cell(b.grid.x), _min_cell(b.grid.y), _min_cell(tall)]
    h_step = min(horizontal)
    dt_courant = scene.run.max_courant * h_step / u_ref
    cap = max_delta_t_s(scene.run.max_delta_t_s, scene.run.write_interval_s)
    dt = min(dt_courant / STEP_FACTOR[solver], cap)
    reasons["time_step"] = (
        f"about {dt:.3g} s: Co = {scene.run.max_courant:g} on the smallest horizontal cell ({h_step:.3g} m) at "
        f"U = 2 sqrt(g h0) = {u_ref:.3g} m/s (Ritter's front speed) gives {dt_courant:.3g} s, over "
        f"{STEP_FACTOR[solver]:g} (the measured steps of {solver} over that estimate), at most maxDeltaT = {cap:.3g} s"
    )
    reasons["cell_count"] = (
        f"{cells} cells: background {background.cell_count()}"
        + (f" + bodies {', '.join(str(b.grid.cell_count()) for b in bodies)}" if bodies else "")
    )
    reasons["run_controls"] = (
        f"end time {T:g} s, writes every {scene.run.write_interval_s:g} s, maxCo = maxAlphaCo = "
        f"{scene.run.max_courant:g} (from the scene's run section)"
    )

    decomposition, dreason = _decompose(scene.run.cores, background, bodies, body_boxes, travel_end, tan_spread, fine_z1, two_d, fy0, fy1)
    reasons["decomposition"] = dreason

    plan = ModelPlan(
        scene_name=scene.name,
        solver=solver,
        two_d=two_d,
        background=background,
        bodies=tuple(bodies),
        water=tuple(water),
        gauges=gauges,
        cell_count=cells,
        decomposition=decomposition,
        end_time_s=T,
        write_interval_s=scene.run.write_interval_s,
        max_courant=scene.run.max_courant,
        domain_m=((x_lo, x_hi), (fy0, fy1), (0.0, z_hi)),
        fine_region_m=fine,
        downstream_type=downstream_type,
        bed_friction_factor=scene.bed.friction_factor,
        bed_friction_calibration=scene.bed.friction_calibration,
        stall_limit_s=scene.run.stall_limit_s,
        water_balance_limit=scene.run.water_balance_limit,
        bed_gap_m=lift,
        velocity_scale_m_s=u_ref,
        time_step_estimate_s=dt,
        reasons=reasons,
        warnings=tuple(warnings),
    )
    wall = estimate_wall_time_s(plan)
    reasons["cell_count"] += (
        f"; about {estimated_steps(plan)} steps x {US_PER_CELL_STEP[solver] * 1e6:g} us/cell-step on "
        f"{_MEASURED_CORES} cores -> about {wall / 60:.1f} min on {plan.cores} core(s)"
    )
    return _replace(plan, estimated_wall_time_s=wall)


def _replace(plan: ModelPlan, **changes) -> ModelPlan:
    from dataclasses import replace

    return replace(plan, **changes)


def max_delta_t_s(max_delta_t: float | None, write_interval_s: float) -> float:
    """The largest time step the case allows (maxDeltaT): the scene's run.max_delta_t_s, else
    min(0.01 s, the write interval)."""
    return float(max_delta_t or min(0.01, write_interval_s))


def estimated_steps(plan: ModelPlan) -> int:
    """Time steps to the end time at the plan's time-step estimate."""
    return math.ceil(plan.end_time_s / plan.time_step_estimate_s) if plan.time_step_estimate_s > 0 else 0


def estimate_wall_time_s(plan: ModelPlan) -> float:
    """Solver wall time (s): cells x steps x the measured per-cell-step cost (US_PER_CELL_STEP).

    Steps = end time / the plan's time-step estimate (with STEP_FACTOR); the cost per cell-step was
    measured on 2 cores and is scaled as 2 / cores (ideal speed-up, optimistic above 2).
    Meshing, decomposition and writing are not included.
    """
    steps = estimated_steps(plan)
    per = US_PER_CELL_STEP[plan.solver] * _MEASURED_CORES / plan.cores
    return plan.cell_count * steps * per


def _weighted_centres(grid: BoxGrid, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Cell-centre coordinates along ``axis`` and how many cells sit at each."""
    segs = (grid.x, grid.y, grid.z)
    counts: dict[int, float] = {}
    for i, j, k in grid.blocks():
        idx = (i, j, k)
        others = 1
        for d in range(3):
            if d != axis:
                others *= segs[d][idx[d]].cells
        counts[idx[axis]] = counts.get(idx[axis], 0) + others
    pos, wts = [], []
    for s_idx, w in counts.items():
        c = _cell_centres(segs[axis][s_idx])
        pos.append(c)
        wts.append(np.full(c.size, float(w)))
    return np.concatenate(pos), np.concatenate(wts)


def _quantile_cuts(pos: np.ndarray, wts: np.ndarray, n: int) -> list[float]:
    order = np.argsort(pos)
    p, w = pos[order], wts[order]
    cum = np.cumsum(w) / w.sum()
    return [float(p[np.searchsorted(cum, k / n)]) for k in range(1, n)]


def _decompose(cores, background, bodies, body_boxes, travel_end, tan_spread, fine_z1, two_d, fy0, fy1):
    """hierarchical (nx ny nz) with nx ny nz = cores.

    decomposePar keeps every body mesh whole on one rank whatever the cuts (a
    preserveFaceZones constraint, templates/system/decomposeParDict.j2): it lumps the
    body's cells into one point before cutting, which costs balance where a cut would have
    crossed the body. Cut planes are estimated as cell-count quantiles per axis (hierarchical
    balances cell counts). Candidates are scored by the bodies their cuts cross at the
    start, then the bodies whose path (to the column) they cross, then the
    processor-boundary area.
    """
    if cores == 1:
        return (1, 1, 1), "1 core: no decomposition"
    cands = [
        (nx, ny, cores // (nx * ny))
        for nx in range(1, cores + 1)
        for ny in range(1, cores + 1)
        if cores % (nx * ny) == 0 and (not two_d or ny == 1)
    ]
    (x0, x1), (y0, y1), (z0, z1) = [(g[0].start_m, g[-1].end_m) for g in (background.x, background.y, background.z)]
    dist = []
    for axis in range(3):
        pos, wts = _weighted_centres(background, axis)
        extra_p = [b.centre_of_mass_m[axis] for b in bodies]
        extra_w = [float(b.grid.cell_count()) for b in bodies]
        dist.append((np.concatenate([pos, extra_p]), np.concatenate([wts, extra_w])))
    paths = []
    for lo, hi in body_boxes:
        travel = max(travel_end - lo[0], 0.0)
        paths.append(
            (
                np.array([lo[0], max(lo[1] - tan_spread * travel, fy0), 0.0]),
                np.array([max(hi[0], travel_end), min(hi[1] + tan_spread * travel, fy1), max(fine_z1, hi[2])]),
            )
        )
    best = None
    for cand in cands:
        cuts = [_quantile_cuts(*dist[a], cand[a]) for a in range(3)]
        split_now = sum(any(lo[a] < c < hi[a] for a in range(3) for c in cuts[a]) for lo, hi in body_boxes)
        split_path = sum(any(lo[a] < c < hi[a] for a in range(3) for c in cuts[a]) for lo, hi in paths)
        area = (cand[0] - 1) * (y1 - y0) * (z1 - z0) + (cand[1] - 1) * (x1 - x0) * (z1 - z0) + (cand[2] - 1) * (x1 - x0) * (y1 - y0)
        score = (split_now, split_path, area)
        if best is None or score < best[0]:
            best = (score, cand, cuts)
    (split_now, split_path, _), cand, cuts = best
    where = "; ".join(
        f"{'xyz'[a]} cut at {', '.join(f'{c:.3g}' for c in cuts[a])} m" for a in range(3) if cuts[a]
    )
    text = f"hierarchical ({cand[0]} {cand[1]} {cand[2]}) over {cores} cores ({where})"
    if bodies:
        text += (
            f": every body mesh on one rank (decomposePar's preserveFaceZones constraint); "
            f"{len(bodies) - split_now} of {len(bodies)} body meshes start clear of the balanced cuts and "
            f"{len(bodies) - split_path} keep their path to the column on one rank (a split body mesh costs about 19 % "
            "per step, docs/openfoam-notes.md)"
        )
    else:
        text += ": the smallest processor boundary"
    return cand, text


def _hold_until_s(scene, body, gap_m: float = 0.0) -> float:
    """When a body resting on the bed should float off (s; 0 = it floats from the start): an estimate.

    The runner frees a held body on what it measures (the depth all round the body and the
    fluid's lift on it, orchestrator/run/bedwatch.py); this estimate says when the bore should let it,
    and whether the body is held at all. The estimate is the time the dam-break depth at its
    centre reaches its draft (its
    mass over the water displaced per metre of immersion by its footprint) plus ``gap_m``,
    the gap it stands on (BedGap). The depth
    is the analytical dry-bed solution: Chanson with the scene's friction factor, or
    Ritter without friction; the thin wet bed is neglected (it only makes the release
    earlier). The simulated bore can be later: over a 15 mm wet bed its steep front reached
    the far end of a container 0.4 m from the gate after 0.35 s, where Ritter's depth reached
    draft plus gap at 0.285 s (docs/stability.md). Bodies behind the gate (x < 0) float or not at once: no hold when the
    still water already floats them. Capped at the end time (held throughout).
    """
    from analytical.dambreak import dam_break
    from scipy.optimize import brentq

    draft = draft_m(body, scene.fluids.water_density_kg_m3) + gap_m
    x, h0, end = float(body.centre_m[0]), float(scene.reservoir.depth_m), float(scene.run.end_time_s)
    if x < 0 or draft <= scene.bed.wet_depth_m:
        return 0.0 if (h0 if x < 0 else scene.bed.wet_depth_m) >= draft else end
    f = scene.bed.friction_factor
    solution = dam_break("chanson", h0, friction=f) if f > 0 else dam_break("ritter", h0)

    def excess(t: float) -> float:
        return float(solution.profile(np.array([x]), t).depth_m[0]) - draft

    t_arrive = float(solution.arrival_time_s(x))
    if not np.isfinite(t_arrive) or t_arrive >= end or excess(end) < 0:
        return end
    lo = max(t_arrive, 1e-6)
    return float(brentq(excess, lo, end)) if excess(lo) < 0 else lo
