"""The modelled part of the flume: how much reservoir, how far downstream, how high, where fine.

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
* Fine region. The gate region, the bore's path to the furthest gauge, the column and the
  paths of the debris (each body's mesh spreading at ``mesh.debris_spread_deg``).

Every choice adds its sentence to the plan's reasons.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytical.dambreak import StokerState
from orchestrator.scene.schema import Scene

__all__ = [
    "RUNUP_BLOCKAGE",
    "RUNUP_DEPTHS",
    "SAFETY",
    "TOP_TRIM",
    "Domain",
    "Front",
    "column_spans_width",
    "dam_break_front",
    "plan_domain",
]

#: Multiplier on the simulated time when sizing the domain (10 % margin).
SAFETY = 1.10
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
#: Measured on the tiny flume of cases/tiny-nodebris.yaml (dry bed, h0 = 0.2 m, 2.5 cm
#: cells, open end, 1 s) under a 1.5 h0 top: a column across a third of the width let 0.008 % of
#: the water over the top, half 0.19 %, two thirds 0.39 %, the whole width 1.9 %.
RUNUP_BLOCKAGE = 0.4

BodyBox = tuple[np.ndarray, np.ndarray]
#: ((x0, x1), (y0, y1), (z0, z1)) of the flume (:func:`orchestrator.scene.geometry.flume_extent`)
Extent = tuple[tuple[float, float], tuple[float, float], tuple[float, float]]


@dataclass(frozen=True)
class Front:
    """The flow behind the dam-break front: front speed, depth and velocity behind it."""

    speed_m_s: float
    depth_m: float
    velocity_m_s: float
    wet: bool
    g: float

    @property
    def froude(self) -> float:
        return math.inf if self.depth_m <= 0 else self.velocity_m_s / math.sqrt(self.g * self.depth_m)


def dam_break_front(h0: float, wet_depth: float, g: float, stoker: StokerState | None) -> Front:
    """Ritter's dry-bed front, Stoker's wet-bed intermediate state (no friction; ``stoker``, given
    for a wet bed shallower than ``h0``), or still water (the impoundment no deeper than the wet bed)."""
    c0 = math.sqrt(g * h0)
    if wet_depth <= 0:
        return Front(speed_m_s=2 * c0, depth_m=0.0, velocity_m_s=2 * c0, wet=False, g=g)
    if wet_depth >= h0:  # still water: no dam break
        return Front(speed_m_s=0.0, depth_m=h0, velocity_m_s=0.0, wet=True, g=g)
    return Front(speed_m_s=stoker.shock_speed_m_s, depth_m=stoker.h2_m, velocity_m_s=stoker.u2_m_s, wet=True, g=g)


@dataclass(frozen=True)
class Domain:
    """The modelled box (x_lo..x_hi, the flume's width, 0..z_hi) and its fine region.

    ``travel_end`` is where the debris paths end (the column's face, else the domain end);
    ``tan_spread`` the tangent of their lateral spread.
    """

    x_lo: float
    x_hi: float
    y: tuple[float, float]
    z_hi: float
    downstream_type: str
    fine: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    travel_end: float
    tan_spread: float

    @property
    def extent_m(self) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
        return (self.x_lo, self.x_hi), self.y, (0.0, self.z_hi)


def column_spans_width(scene: Scene) -> bool:
    """Whether the column blocks the flume's whole width (a 2D obstacle)."""
    col = scene.column
    return col is not None and col.size_y_m >= scene.flume.width_m - 1e-9 and abs(col.y_m) <= 1e-9


def plan_domain(scene: Scene, flume: Extent, stoker: StokerState | None, body_boxes: list[BodyBox],
                reasons: dict[str, str], warnings: list[str]) -> Domain:
    """The domain for ``scene`` in the flume's extent ``flume`` with its bodies' overset meshes at
    ``body_boxes`` (AABBs); ``stoker``: the wet bed's flow behind the bore (:func:`dam_break_front`)."""
    h0, h = scene.reservoir.depth_m, scene.mesh.cell_size_m
    col = scene.column
    margin_col = max(0.5 * max(col.size_x_m, col.size_y_m), 3 * h) if col else 3 * h
    upstream_marks = [-h0] + [gg.x_m for gg in scene.gauges if gg.x_m < 0] + [lo[0] for lo, _ in body_boxes]
    if col:
        upstream_marks.append(col.x_m - col.size_x_m / 2 - margin_col)
    guard = max(0.0, -min(upstream_marks))
    x_lo = -_reservoir_length(scene, guard, reasons)
    x_hi, downstream_type = _downstream_end(scene, flume, stoker, body_boxes, margin_col, reasons)
    z_hi = _top(scene, flume, body_boxes, x_hi, downstream_type, reasons, warnings)
    fine, travel_end, tan_spread = _fine_region(scene, flume, body_boxes, margin_col, x_lo, x_hi, z_hi, reasons)
    return Domain(x_lo, x_hi, flume[1], z_hi, downstream_type, fine, travel_end, tan_spread)


def reservoir_length_needed(end_time_s: float, h0: float, guard_m: float, g: float) -> float:
    """Shortest reservoir whose reflected negative wave reaches ``guard_m`` upstream of the
    gate no earlier than SAFETY x end_time (see the module docstring)."""
    c0 = math.sqrt(g * h0)
    return (SAFETY * end_time_s * c0 + 0.75 * guard_m) / 1.75


def length_before_return(end_time_s: float, x_roi: float, front_speed: float, back_speed: float) -> float:
    """Smallest x_end with x_end/front + (x_end - x_roi)/back >= SAFETY x end_time."""
    t = SAFETY * end_time_s
    return (t + x_roi / back_speed) / (1.0 / front_speed + 1.0 / back_speed)


def _reservoir_length(scene: Scene, guard: float, reasons: dict[str, str]) -> float:
    """The modelled reservoir: the shortest whose reflection misses the guarded region."""
    g, T, h = scene.fluids.gravity_m_s2, scene.run.end_time_s, scene.mesh.cell_size_m
    h0 = scene.reservoir.depth_m + scene.reservoir.sill_height_m  # the reservoir's own depth sets its waves
    c0 = math.sqrt(g * h0)
    full = scene.reservoir.length_m
    res_len = min(full, max(reservoir_length_needed(T, h0, guard, g), guard + max(h0, 4 * h)))
    if not scene.mesh.trim_domain:
        res_len = full
    t_return = res_len / c0 + max(res_len - guard, 0.0) / (4.0 / 3.0 * c0)
    if not scene.mesh.trim_domain:
        reasons["reservoir_length"] = f"whole reservoir ({res_len:g} m) modelled: mesh.trim_domain is false"
    elif res_len < full - 1e-9:
        reasons["reservoir_length"] = (
            f"reservoir truncated to {res_len:.3g} m of {full:g} m: the negative wave "
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
    return res_len


def _downstream_end(scene: Scene, flume: Extent, stoker: StokerState | None, body_boxes: list[BodyBox],
                    margin_col: float, reasons: dict[str, str]) -> tuple[float, str]:
    """Where the domain ends downstream, and whether that end is a wall or an outlet."""
    g, h0, T = scene.fluids.gravity_m_s2, scene.reservoir.depth_m, scene.run.end_time_s
    c0 = math.sqrt(g * h0)
    col = scene.column
    (_, fx1), _, _ = flume
    front = dam_break_front(h0, scene.bed.wet_depth_m, g, stoker)
    if front.speed_m_s <= 0.0:  # still water: nothing comes, nothing to trim against
        kind = "outlet" if scene.flume.downstream_end == "open" else "wall"
        reasons["domain_end"] = f"domain runs to the flume's end (x = {fx1:.3g} m): still water, no dam break"
        reasons["downstream_type"] = f"{kind}: the flume's downstream end is {scene.flume.downstream_end}"
        return fx1, kind
    if col:
        path_end = col.x_m + col.size_x_m / 2 + margin_col
    else:
        path_end = min(max([hi[0] + 2.0 * c0 * T for _, hi in body_boxes], default=-math.inf), fx1)
    roi_end = max([path_end] + [gg.x_m for gg in scene.gauges] + [hi[0] for _, hi in body_boxes] + [0.0])
    wake = max(5 * col.size_y_m if col else 0.0, 2 * h0, 2 * max((max(b.size_m) for b in scene.debris), default=0.0))
    if front.froude > 1.0:
        open_need = roi_end + wake
        open_why = (
            f"behind the front the flow is supercritical (Fr = {front.froude:.2g}"
            f"{', Stoker wet bed' if front.wet else ', Ritter dry bed'}), so nothing travels upstream from an outlet; "
            f"the domain ends {wake:.3g} m past the region of interest (x = {roi_end:.3g} m) to clear the column's "
            "wake and passing debris"
        )
    else:
        back = max(math.sqrt(g * front.depth_m) - front.velocity_m_s, 1e-6)
        open_need = max(roi_end + wake, length_before_return(T, roi_end, front.speed_m_s, back))
        open_why = (
            f"subcritical flow behind the front (Fr = {front.froude:.2g}): a disturbance from the outlet, starting when "
            f"the front (S = {front.speed_m_s:.3g} m/s) arrives and travelling back at c - u = {back:.3g} m/s, "
            f"must not reach x = {roi_end:.3g} m before {SAFETY:g} x end_time"
        )
    wall_need = max(roi_end + wake, length_before_return(T, roi_end, front.speed_m_s, c0))
    end = scene.flume.downstream_end
    if not scene.mesh.trim_domain:
        kind = "outlet" if end == "open" else "wall"
        reasons["domain_end"] = f"domain runs to the flume's end (x = {fx1:.3g} m): mesh.trim_domain is false"
        reasons["downstream_type"] = f"{kind}: the flume's downstream end is {end}"
        return fx1, kind
    if end == "open":
        x_hi = min(fx1, open_need)
        reasons["domain_end"] = (
            f"domain ends at x = {x_hi:.3g} m"
            + (" (the flume's open end)" if x_hi >= fx1 - 1e-9 else f" of the flume's {fx1:.3g} m: " + open_why)
        )
        reasons["downstream_type"] = "outlet: the flume's downstream end is open (free outfall)"
        return x_hi, "outlet"
    if wall_need >= fx1 - 1e-9:
        reasons["domain_end"] = (
            f"domain runs to the closed end wall (x = {fx1:.3g} m): a bore reflected from it (front at "
            f"<= {front.speed_m_s:.3g} m/s, back at <= c0 = {c0:.3g} m/s) could reach x = {roi_end:.3g} m "
            f"before {SAFETY:g} x end_time"
        )
        reasons["downstream_type"] = "wall: the flume's closed end is inside the modelled time's reach"
        return fx1, "wall"
    x_hi = min(fx1, open_need)
    reasons["domain_end"] = (
        f"domain ends at x = {x_hi:.3g} m, short of the closed end wall ({fx1:.3g} m), whose reflection "
        f"cannot reach x = {roi_end:.3g} m before {SAFETY:g} x end_time (it needs {wall_need:.3g} m); " + open_why
    )
    reasons["downstream_type"] = "outlet: the domain is cut short of the closed end, whose reflection arrives after the run"
    return x_hi, "outlet"


def _runup_sources(scene: Scene, flume: Extent, x_hi: float, downstream_type: str) -> tuple[list[str], float]:
    """What the fastest front (2 c0) reaches within the run and the bore runs up, and the
    fraction of the width the column blocks."""
    T, col = scene.run.end_time_s, scene.column
    u_ref = 2.0 * math.sqrt(scene.fluids.gravity_m_s2 * scene.reservoir.depth_m)
    _, (fy0, fy1), _ = flume
    sources = []
    if downstream_type == "wall" and x_hi / u_ref < T:
        sources.append(f"the closed end wall (x = {x_hi:.3g} m, reached from {x_hi / u_ref:.2g} s)")
    blockage = 0.0
    if col:
        blockage = 1.0 if column_spans_width(scene) else max(
            0.0, min(col.y_m + col.size_y_m / 2, fy1) - max(col.y_m - col.size_y_m / 2, fy0)) / scene.flume.width_m
        col_x0 = col.x_m - col.size_x_m / 2
        if 0.0 < col_x0 and col_x0 / u_ref < T and blockage >= RUNUP_BLOCKAGE:
            sources.append(f"the column across {blockage:.0%} of the width (x = {col_x0:.3g} m, reached from "
                           f"{col_x0 / u_ref:.2g} s)")
    return sources, blockage


def _top(scene: Scene, flume: Extent, body_boxes: list[BodyBox], x_hi: float, downstream_type: str,
         reasons: dict[str, str], warnings: list[str]) -> float:
    """The top of the air space: trimmed unless the bore can run up above the trim (RUNUP_DEPTHS)."""
    h0 = scene.reservoir.depth_m
    u_ref = 2.0 * math.sqrt(scene.fluids.gravity_m_s2 * h0)
    runup = RUNUP_DEPTHS * h0
    runup_from, blockage = _runup_sources(scene, flume, x_hi, downstream_type)
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
        return z_hi
    if not scene.mesh.trim_domain:
        z_hi = scene.flume.height_m
        reasons["domain_top"] = f"air space up to the flume's wall height ({z_hi:g} m): mesh.trim_domain is false"
        return z_hi
    body_top = max((hi[2] for _, hi in body_boxes), default=0.0)
    trim = max(TOP_TRIM * h0, body_top)
    if runup_from and runup > trim:
        z_hi = scene.flume.height_m
        reasons["domain_top"] = (
            f"air space up to the walls (z = {z_hi:g} m, the flume's height), not trimmed to {trim:.3g} m: "
            + runup_why + ", above the trim; water that rises over the walls leaves the flume there too"
        )
        return z_hi
    z_hi = min(scene.flume.height_m, trim)
    reasons["domain_top"] = (
        f"air space up to z = {z_hi:.3g} m = min(flume height {scene.flume.height_m:g} m, {TOP_TRIM:g} x impoundment"
        + (", the top of the highest body mesh" if body_top > TOP_TRIM * h0 else "")
        + "): "
        + (runup_why + ", within it" if runup_from else
           "no closed end, and no obstacle across {:.0%} of the width or more, within the bore's reach "
           "during the run: nothing runs up above the trim".format(RUNUP_BLOCKAGE)
           + (f" (the column, across {blockage:.0%} of the width, sends up a jet over its face: splash-up "
              "that mostly falls back)" if scene.column else ""))
        + "; water above leaves through the open atmosphere patch (post reports it apart)"
    )
    return z_hi


def _fine_region(scene: Scene, flume: Extent, body_boxes: list[BodyBox], margin_col: float, x_lo: float, x_hi: float,
                 z_hi: float, reasons: dict[str, str]):
    """((x0, x1), (y0, y1), (0, z1)) of the fine cells, where the debris paths end, their spread."""
    h0, h, col = scene.reservoir.depth_m, scene.mesh.cell_size_m, scene.column
    has_debris = len(scene.debris) > 0
    _, (fy0, fy1), _ = flume
    fine_x0 = min([-h0] + [lo[0] for lo, _ in body_boxes] + ([col.x_m - col.size_x_m / 2 - margin_col] if col else []))
    if col:
        fine_x1 = col.x_m + col.size_x_m / 2 + margin_col
        travel_end = col.x_m - col.size_x_m / 2
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
        ys += [col.y_m - col.size_y_m / 2 - margin_col, col.y_m + col.size_y_m / 2 + margin_col]
    for lo, hi in body_boxes:
        travel = max(travel_end - lo[0], 0.0)
        ys += [lo[1] - tan_spread * travel, hi[1] + tan_spread * travel]
    fine_y0 = max(fy0, min(ys)) if ys else fy0
    fine_y1 = min(fy1, max(ys)) if ys else fy1
    fine_z1 = min(z_hi, max([h0] + [hi[2] for _, hi in body_boxes]))
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
    return ((fine_x0, fine_x1), (fine_y0, fine_y1), (0.0, fine_z1)), travel_end, tan_spread
