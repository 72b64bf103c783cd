"""The scene's cross-field rules: what a resolved scene must satisfy beyond each field's range.

Each field's own range is checked by the models (:mod:`orchestrator.scene.schema`); the
rules here relate fields to one another (a body inside the flume and clear of the column,
the mesh fine enough for the smallest thing it must resolve). The first broken rule raises
an :class:`~orchestrator.core.errors.InputError` naming the dotted field the user has to change.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np

from orchestrator.core.errors import InputError
from orchestrator.scene.geometry import TOLERANCE_M as TOL
from orchestrator.scene.geometry import body_rotation, box_corners, boxes_overlap, flume_extent
from orchestrator.scene.schema import DebrisBody, Scene

__all__ = [
    "DENSITY_PLAUSIBLE_KG_M3",
    "DENSITY_POSSIBLE_KG_M3",
    "MAX_COLUMN_HEIGHT_M",
    "MIN_CELLS_ACROSS_COLUMN",
    "MIN_CELLS_ACROSS_DEBRIS",
    "MIN_CELLS_OVER_DEPTH",
    "body_density_kg_m3",
    "full_scale_body",
    "plausibility_warnings",
    "validate_scene",
]

#: The finest cell may be at most 1/1.5 of the smallest debris dimension: every body
#: then covers at least one background cell centre across each of its dimensions
#: wherever it sits, so it always cuts a hole in the background mesh (overset).
MIN_CELLS_ACROSS_DEBRIS = 1.5
#: At least this many finest cells across each horizontal side of the column.
MIN_CELLS_ACROSS_COLUMN = 2.0
#: At least this many finest cells over the impoundment depth.
MIN_CELLS_OVER_DEPTH = 4.0

#: A body's bulk density (its mass over its outer box, hollow or not) outside this range cannot be
#: a real object: above the densest element (osmium, 22,590 kg/m3; CRC Handbook of Chemistry and
#: Physics) or below the air around it (1.2 kg/m3 at 20 C), which it would float in. Refused.
DENSITY_POSSIBLE_KG_M3 = (1.0, 25_000.0)
#: Outside this range a body is possible but unlike floating debris (the study's container is
#: about 440 kg/m3; timber 400-800, steel 7,850): a warning, in case a mass or a size is mistyped.
DENSITY_PLAUSIBLE_KG_M3 = (50.0, 3_000.0)

_NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def validate_scene(scene: Scene, source: str | None = None, origins: Sequence[dict] | None = None) -> None:
    """The cross-field rules; raises the first broken one as an InputError.

    Rules: reservoir shorter than the flume; impoundment not above the flume walls; wet
    bed shallower than the impoundment; column inside the flume; every body inside the
    flume, clear of the column and of every other body; unique OpenFOAM-safe body names;
    body wall thinner than half its smallest dimension; gauges inside the flume and not
    inside the column; ``mesh.cell_size_m`` fine enough for the impoundment, the column
    and the debris; ``mesh.top_m`` between the impoundment and the flume height.

    ``origins`` says where each body came from in the YAML (``path``, and ``layout``: made
    by a layout), so an error names the key the user wrote; default: one item per body.
    """
    _check_water(scene, source)
    _check_gate(scene, source)
    _check_column(scene, source)
    origins = list(origins) if origins is not None else [
        {"path": f"debris.{i}", "layout": False} for i in range(len(scene.debris))
    ]
    _check_bodies(scene, origins, source)
    _check_gauges(scene, source)
    _check_mesh(scene, source)
    _check_design(scene, source)


def _check_water(scene: Scene, source: str | None) -> None:
    """Reservoir shorter than the flume, impoundment below the walls, wet bed below the impoundment."""
    fl, res, bed = scene.flume, scene.reservoir, scene.bed
    if res.length_m >= fl.length_m - TOL:
        raise InputError(
            "reservoir.length_m",
            f"must be shorter than the flume ({fl.length_m:g} m) so water has somewhere to go, got {res.length_m:g}",
            source,
        )
    if res.depth_m > fl.height_m + TOL:
        raise InputError(
            "reservoir.depth_m",
            f"impoundment {res.depth_m:g} m is above the flume walls ({fl.height_m:g} m)",
            source,
        )
    if bed.wet_depth_m > res.depth_m + TOL:
        raise InputError(
            "bed.wet_depth_m",
            f"must be shallower than the impoundment ({res.depth_m:g} m) for a dam break (or equal to it: "
            f"still water), got {bed.wet_depth_m:g}",
            source,
        )
    if bed.slip and bed.friction_factor > 0:
        raise InputError(
            "bed.slip",
            f"a slip bed has no friction, but bed.friction_factor is {bed.friction_factor:g}: set it to 0 or "
            "leave bed.slip false",
            source,
        )


def _check_gate(scene: Scene, source: str | None) -> None:
    """The gate's opening inside the flume, its walls clear of the column, bodies and gauges;
    no body behind the gate over a sill (bodies stand on the bed downstream's level)."""
    res, (y0, y1) = scene.reservoir, flume_extent(scene)[1]
    if res.opening_time_s > 0 and res.gate == "instant":
        raise InputError("reservoir.opening_time_s", f"an instant gate has no opening time ({res.opening_time_s:g} s "
                         "given): set reservoir.gate to swing-gate, or the time to 0", source)
    if res.opening_time_s >= scene.run.end_time_s:
        raise InputError("reservoir.opening_time_s", f"the gate would still be opening when the run ends "
                         f"({res.opening_time_s:g} s against run.end_time_s {scene.run.end_time_s:g} s)", source)
    if res.sill_height_m > 0:
        behind = [i for i, b in enumerate(scene.debris) if b.centre_m[0] < 0]
        if behind:
            raise InputError("reservoir.sill_height_m", f"debris.{behind[0]} stands behind the gate, where the sill "
                             "lowers the floor; bodies stand on the bed downstream's level: start it at x >= 0 m "
                             "or set the sill to 0", source)
    if res.opening_width_m is None:
        return
    lo, hi = res.opening_y_m - res.opening_width_m / 2, res.opening_y_m + res.opening_width_m / 2
    if lo < y0 - TOL or hi > y1 + TOL:
        raise InputError("reservoir.opening_width_m", f"the opening (y {lo:g}..{hi:g} m) must lie inside the "
                         f"flume's width (y {y0:g}..{y1:g} m); move reservoir.opening_y_m or narrow it", source)

    def in_wall(x: float, y: float, half_x: float = 0.0, half_y: float = 0.0) -> bool:
        return x + half_x > TOL and x - half_x < res.opening_length_m - TOL and (
            y - half_y < lo - TOL or y + half_y > hi + TOL)

    col = scene.column
    if col is not None and in_wall(col.x_m, col.y_m, col.size_x_m / 2, col.size_y_m / 2):
        raise InputError("reservoir.opening_length_m", f"the walls beside the gate's opening (to x = "
                         f"{res.opening_length_m:g} m) reach the column", source)
    for i, b in enumerate(scene.debris):
        half = 0.5 * max(b.size_m)
        if in_wall(b.centre_m[0], b.centre_m[1], half, half):
            raise InputError(f"debris.{i}.centre_m", f"body {b.name!r} overlaps the walls beside the gate's opening "
                             f"(x 0..{res.opening_length_m:g} m, outside y {lo:g}..{hi:g} m)", source)
    for i, g in enumerate(scene.gauges):
        if in_wall(g.x_m, g.y_m):
            raise InputError(f"gauges.{i}.x_m", f"gauge {g.name!r} is inside the walls beside the gate's opening",
                             source)


#: The tallest column a scene may have (m). The tool's column is a fixed-base member struck by
#: debris near the flow depth: a ground-storey building column is 3-6 m tall, a pier standing in
#: a harbour or a river some tens of metres; the tallest shipped is the 1-debris scene at 40:1,
#: 32 m (cases/prototype-1debris.yaml). Above 100 m it is a slip of units (mm given as m).
MAX_COLUMN_HEIGHT_M = 100.0


def _check_column_size(scene: Scene, source: str | None) -> None:
    """The column's height plausible (:data:`MAX_COLUMN_HEIGHT_M`); a footprint wider than the flume
    is its size's fault: the size field is named (the section's when the column is given by
    section), not its position (a footprint that would fit elsewhere names the position)."""
    col = scene.column
    if col.height_m > MAX_COLUMN_HEIGHT_M:
        raise InputError("column.height_m", f"{col.height_m:g} m is taller than any column a debris strike loads: "
                         f"at most {MAX_COLUMN_HEIGHT_M:g} m (a ground-storey column is 3-6 m, the 1-debris scene at "
                         "40:1 has 32 m); a height in mm?", source)
    (x0, x1), (y0, y1), _ = flume_extent(scene)
    for axis, centre, size, lo, hi in (("x", col.x_m, col.size_x_m, x0, x1), ("y", col.y_m, col.size_y_m, y0, y1)):
        if size > hi - lo + TOL:  # no position holds it: the size is at fault
            field = "column.section.size_m" if col.section is not None else f"column.size_{axis}_m"
            raise InputError(field, f"a column {size:g} m across along {axis}, centred at {axis} = {centre:g} m, spans "
                             f"{centre - size / 2:g}..{centre + size / 2:g} m: wider than the flume "
                             f"({lo:g}..{hi:g} m)", source)


def _check_column(scene: Scene, source: str | None) -> None:
    """The column inside the flume, its wall at most half its smaller side."""
    col = scene.column
    if col is None:
        return
    _check_column_size(scene, source)
    (x0, x1), (y0, y1), _ = flume_extent(scene)
    for axis, centre, size, (lo, hi) in (("x", col.x_m, col.size_x_m, (x0, x1)), ("y", col.y_m, col.size_y_m, (y0, y1))):
        if centre - size / 2 < lo - TOL or centre + size / 2 > hi + TOL:
            raise InputError(
                f"column.{axis}_m",
                f"column spans {axis} = {centre - size / 2:g}..{centre + size / 2:g} m, outside the "
                f"flume ({lo:g}..{hi:g} m)",
                source,
            )
    if col.x_m - col.size_x_m / 2 < -TOL:
        raise InputError(
            "column.x_m",
            f"column spans x = {col.x_m - col.size_x_m / 2:g}..{col.x_m + col.size_x_m / 2:g} m: it must stand "
            "downstream of the gate (x >= 0 m; the reservoir is x < 0), where the bore reaches it",
            source,
        )
    if 2 * col.wall_thickness_m > min(col.size_x_m, col.size_y_m) + TOL:
        raise InputError(
            "column.wall_thickness_m",
            f"must be at most half the smaller side ({min(col.size_x_m, col.size_y_m) / 2:g} m), "
            f"got {col.wall_thickness_m:g}",
            source,
        )


def _check_bodies(scene: Scene, origins: Sequence[dict], source: str | None) -> None:
    """Each body well formed, inside the flume, clear of the column and of the bodies before it."""
    col = scene.column
    names: dict[str, int] = {}
    placed: list[tuple[DebrisBody, np.ndarray]] = []
    for i, body in enumerate(scene.debris):
        path = origins[i]["path"]
        if not _NAME_RE.match(body.name):
            raise InputError(f"{path}.name", f"{body.name!r} is not an identifier (letters, digits, _)", source)
        if body.name in names or (col is not None and body.name == "column"):
            raise InputError(
                f"{path}.name" if not origins[i]["layout"] else f"{path}.name_prefix",
                f"body name {body.name!r} is used twice",
                source,
            )
        names[body.name] = i
        _check_body_shape(body, path, origins[i]["layout"], source)
        _check_body_density(body, path, origins[i]["layout"], source)
        _check_full_scale_contact(scene, body, path, origins[i]["layout"], source)
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
        _check_body_inside(scene, body, rot, f"{path}.centre_m", source)
        for j, (other, orot) in enumerate(placed):
            if boxes_overlap(body.centre_m, rot, body.size_m, other.centre_m, orot, other.size_m):
                same_layout = origins[i]["layout"] and origins[j]["path"] == path
                raise InputError(
                    f"{path}.spacing_m" if same_layout else f"{path}.centre_m",
                    f"body {body.name!r} overlaps body {other.name!r}",
                    source,
                )
        placed.append((body, rot))


def _check_body_shape(body: DebrisBody, path: str, from_layout: bool, source: str | None) -> None:
    """Sizes and principal moments positive; a wall thinner than half the smallest size, or inertia, not both."""
    if body.wall_thickness_m is not None and body.moment_of_inertia_kg_m2 is not None:
        raise InputError(
            f"{path}.moment_of_inertia_kg_m2",
            "give wall_thickness_m or moment_of_inertia_kg_m2, not both",
            source,
        )
    t_field = f"{path}.body.wall_thickness_m" if from_layout else f"{path}.wall_thickness_m"
    if body.wall_thickness_m is not None and 2 * body.wall_thickness_m >= min(body.size_m):
        raise InputError(
            t_field,
            f"must be less than half the smallest dimension ({min(body.size_m) / 2:g} m), got "
            f"{body.wall_thickness_m:g}",
            source,
        )
    if min(body.size_m) <= 0:
        k = int(np.argmin(body.size_m))
        size_field = f"{path}.body.size_m" if from_layout else f"{path}.size_m"
        raise InputError(f"{size_field}.{k}", f"must be > 0, got {body.size_m[k]:g}", source)
    if body.moment_of_inertia_kg_m2 is not None and min(body.moment_of_inertia_kg_m2) <= 0:
        raise InputError(
            f"{path}.moment_of_inertia_kg_m2",
            f"principal moments must be > 0, got {list(body.moment_of_inertia_kg_m2)}",
            source,
        )


def body_density_kg_m3(body: DebrisBody) -> float:
    """A body's bulk density: its mass over its outer box (kg/m3)."""
    lx, ly, lz = body.size_m
    return body.mass_kg / (lx * ly * lz)


def _check_body_density(body: DebrisBody, path: str, from_layout: bool, source: str | None) -> None:
    """The body's bulk density within :data:`DENSITY_POSSIBLE_KG_M3`."""
    rho = body_density_kg_m3(body)
    lo, hi = DENSITY_POSSIBLE_KG_M3
    if not lo <= rho <= hi:
        why = (f"denser than any material (osmium, the densest, is 22,590 kg/m3); at most {hi:,.0f}" if rho > hi
               else f"lighter than air (1.2 kg/m3); at least {lo:g}")
        raise InputError(
            f"{path}.body.mass_kg" if from_layout else f"{path}.mass_kg",
            f"body {body.name!r}: {body.mass_kg:g} kg in a {' x '.join(f'{s:g}' for s in body.size_m)} m box is a "
            f"bulk density of {rho:.4g} kg/m3, {why}",
            source,
        )


def full_scale_body(scene: Scene, body: DebrisBody) -> str | None:
    """Why ``body`` is full-scale debris, or None: a full-size catalogue entry, ``design.prototype``,
    or a mass (its own, or ``design.mass_kg``'s upper end) of
    :data:`analytical.asce7.FULL_SCALE_MIN_MASS_KG` or more."""
    from analytical.asce7 import FULL_SCALE_MIN_MASS_KG
    from analytical.catalogue import debris_type

    if body.type is not None and debris_type(body.type).scale > 1.0:
        return f"the catalogue's full-size {body.type}"
    if scene.design.prototype:
        return "design.prototype is set"
    heaviest = max(body.mass_kg, scene.design.mass_kg[1] if scene.design.mass_kg else 0.0)
    if heaviest >= FULL_SCALE_MIN_MASS_KG:
        return f"up to {heaviest:,.0f} kg, full scale from {FULL_SCALE_MIN_MASS_KG:g} kg"
    return None


def _check_full_scale_contact(scene: Scene, body: DebrisBody, path: str, from_layout: bool,
                              source: str | None) -> None:
    """A full-scale body states its contact law: no full-scale source gives one
    (docs/fullscale-sources.md) and the laboratory law's defaults are not full-scale values
    (Froude similarity does not scale elasticity). Its ``contact.stiffness_N_m``, and under the
    damped ``container`` law its ``damping_ratio`` or ``restitution``."""
    reason = full_scale_body(scene, body)
    if reason is None:
        return
    c = body.contact
    where = f"{path}.body.contact" if from_layout else f"{path}.contact"
    why = (f"body {body.name!r} is full-scale debris ({reason}) and no full-scale source gives a contact law "
           "(docs/fullscale-sources.md); the laboratory law's is no full-scale value: state")
    if c.stiffness_N_m is None:
        raise InputError(f"{where}.stiffness_N_m", f"{why} the contact stiffness (N/m) and its source", source)
    if c.law == "container" and c.damping_ratio is None and c.restitution is None:
        raise InputError(f"{where}.damping_ratio", f"{why} the contact's damping ratio (or restitution) and its "
                         "source", source)


#: Without ``design.heading_deg`` a body turns about its own yaw by the ensemble's placement
#: tolerance (normal, 12 degrees): its start area is checked for headings within three of those.
UNDRAWN_HEADING_SPREAD_DEG = 36.0


def _half_extents(body: DebrisBody, headings_deg: tuple[float, float]) -> tuple[float, float]:
    """The largest half-extents along x and y of ``body``'s footprint over yaws in ``headings_deg``."""
    length, width = body.size_m[0], body.size_m[1]
    yaw = np.radians(np.linspace(headings_deg[0], headings_deg[1], 181))
    hx = 0.5 * (length * np.abs(np.cos(yaw)) + width * np.abs(np.sin(yaw)))
    hy = 0.5 * (length * np.abs(np.sin(yaw)) + width * np.abs(np.cos(yaw)))
    return float(hx.max()), float(hy.max())


def _check_design(scene: Scene, source: str | None) -> None:
    """``design``'s draws give real bodies that start inside the flume and upstream of the column:
    every body's bulk density at both ends of ``mass_kg`` within :data:`DENSITY_POSSIBLE_KG_M3`; a
    start area (``start_x_m``, ``start_y_m``) that keeps every body's footprint, at every heading it
    may draw, between the walls, inside the flume and clear of the column's upstream face."""
    design = scene.design
    if design.debris_stiffness_N_m is not None:
        from analytical.asce7 import check_debris_stiffness

        try:
            check_debris_stiffness(design.debris_stiffness_N_m, "design.debris_stiffness_N_m")
        except InputError as err:
            raise InputError(err.field, err.rule, source) from None
    if design.heading_deg is not None:
        a, b = design.heading_deg
        if min(a, b) < -360.0 or max(a, b) > 360.0 or b - a > 360.0:
            raise InputError("design.heading_deg", f"[{a:g}, {b:g}] degrees: a yaw range is at most a full turn, "
                             "each end within -360..360 degrees (degrees, not radians or hundredths?)", source)
    lo, hi = DENSITY_POSSIBLE_KG_M3
    for body in scene.debris:
        volume = body.size_m[0] * body.size_m[1] * body.size_m[2]
        for mass in design.mass_kg or ():
            rho = mass / volume
            if not lo <= rho <= hi:
                raise InputError("design.mass_kg", f"{mass:g} kg in body {body.name!r}'s "
                                 f"{' x '.join(f'{s:g}' for s in body.size_m)} m box is a bulk density of "
                                 f"{rho:.4g} kg/m3, outside {lo:g}-{hi:,.0f} kg/m3 (masses in kg, not tonnes?)",
                                 source)
    if design.start_x_m is None and design.start_y_m is None:
        return
    (x0, x1), (y0, y1), _ = flume_extent(scene)
    col = scene.column
    for body in scene.debris:
        spread = UNDRAWN_HEADING_SPREAD_DEG
        headings = design.heading_deg or (body.yaw_deg - spread, body.yaw_deg + spread)
        hx, hy = _half_extents(body, headings)
        if design.start_y_m is not None:
            a, b = design.start_y_m
            if a - hy < y0 - TOL or b + hy > y1 + TOL:
                raise InputError("design.start_y_m", f"[{a:g}, {b:g}] m puts body {body.name!r} (up to {hy:.3g} m "
                                 f"either side of its centre at the headings it draws) across y {a - hy:.4g}.."
                                 f"{b + hy:.4g} m, beyond the walls at y {y0:g}..{y1:g} m", source)
        if design.start_x_m is not None:
            a, b = design.start_x_m
            face = col.x_m - col.size_x_m / 2 if col is not None else x1
            what = "the column's upstream face" if col is not None else "the flume's downstream end"
            if a - hx < x0 - TOL:
                raise InputError("design.start_x_m", f"[{a:g}, {b:g}] m puts body {body.name!r} upstream of the "
                                 f"flume's upstream end (x = {x0:g} m): its footprint reaches x = {a - hx:.4g} m",
                                 source)
            if b + hx > face + TOL:
                raise InputError("design.start_x_m", f"[{a:g}, {b:g}] m puts body {body.name!r} (up to {hx:.3g} m "
                                 f"ahead of its centre) at or past {what} (x = {face:g} m): a body must start "
                                 "upstream of it", source)


def plausibility_warnings(scene: Scene) -> list[str]:
    """Possible but unlikely values, one sentence each: bodies' bulk densities outside
    :data:`DENSITY_PLAUSIBLE_KG_M3` (against the water's density)."""
    out = []
    lo, hi = DENSITY_PLAUSIBLE_KG_M3
    water = scene.fluids.water_density_kg_m3
    for body in scene.debris:
        rho = body_density_kg_m3(body)
        if not lo <= rho <= hi:
            out.append(f"debris {body.name!r}: bulk density {rho:.4g} kg/m3 ({rho / water:.3g} x the water's) is "
                       f"outside {lo:g}-{hi:,.0f} kg/m3: check its mass_kg and size_m")
    approach = scene.mesh.column_approach_cell_size_m
    if approach is not None and scene.column is None:
        out.append("mesh.column_approach_cell_size_m is set but the scene has no column: the mesh has no "
                   "refinement box")
    elif approach is not None and approach >= scene.mesh.cell_size_m:
        out.append(f"mesh.column_approach_cell_size_m ({approach:g} m) is no finer than mesh.cell_size_m "
                   f"({scene.mesh.cell_size_m:g} m): the mesh has no refinement box at the column")
    return out


def _check_body_inside(scene: Scene, body: DebrisBody, rot: np.ndarray, pos_field: str, source: str | None) -> None:
    """Every corner of the body inside the flume; the body clear of the column."""
    (x0, x1), (y0, y1), (_, z1) = flume_extent(scene)
    corners = box_corners(body.centre_m, rot, body.size_m)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    if lo[0] < x0 - TOL or hi[0] > x1 + TOL or lo[1] < y0 - TOL or hi[1] > y1 + TOL or lo[2] < -1e-7 or hi[2] > z1 + TOL:
        raise InputError(
            pos_field,
            f"body {body.name!r} spans x {lo[0]:.4g}..{hi[0]:.4g}, y {lo[1]:.4g}..{hi[1]:.4g}, "
            f"z {lo[2]:.4g}..{hi[2]:.4g} m: outside the flume (x {x0:g}..{x1:g}, y {y0:g}..{y1:g}, "
            f"z 0..{z1:g} m)",
            source,
        )
    col = scene.column
    if col is not None and boxes_overlap(
        body.centre_m, rot, body.size_m, (col.x_m, col.y_m, col.height_m / 2), np.eye(3),
        (col.size_x_m, col.size_y_m, col.height_m),
    ):
        raise InputError(pos_field, f"body {body.name!r} overlaps the column", source)


def _check_gauges(scene: Scene, source: str | None) -> None:
    """Gauge names unique identifiers; every gauge inside the flume and outside the column."""
    (x0, x1), (y0, y1), _ = flume_extent(scene)
    col = scene.column
    for i, g in enumerate(scene.gauges):
        if not _NAME_RE.match(g.name):
            raise InputError(f"gauges.{i}.name", f"{g.name!r} is not an identifier (letters, digits, _)", source)
        if any(other.name == g.name for other in scene.gauges[:i]):
            raise InputError(f"gauges.{i}.name", f"gauge name {g.name!r} is used twice", source)
        if not x0 - TOL <= g.x_m <= x1 + TOL:
            raise InputError(f"gauges.{i}.x_m", f"gauge {g.name!r} at x = {g.x_m:g} m is outside the flume ({x0:g}..{x1:g} m)", source)
        if not y0 - TOL <= g.y_m <= y1 + TOL:
            raise InputError(f"gauges.{i}.y_m", f"gauge {g.name!r} at y = {g.y_m:g} m is outside the flume ({y0:g}..{y1:g} m)", source)
        if col is not None and abs(g.x_m - col.x_m) < col.size_x_m / 2 - TOL and abs(g.y_m - col.y_m) < col.size_y_m / 2 - TOL:
            raise InputError(f"gauges.{i}.x_m", f"gauge {g.name!r} is inside the column", source)


def still_water(scene: Scene) -> bool:
    """The impoundment is the wet bed: no dam break, the flume's water at rest (a test of what
    holds still; the dam-break resolution rule does not apply)."""
    return abs(scene.reservoir.depth_m - scene.bed.wet_depth_m) <= TOL


def _check_mesh(scene: Scene, source: str | None) -> None:
    """The finest cell fine enough for the impoundment, the column and every body; mesh.top_m in range."""
    res, col, h = scene.reservoir, scene.column, scene.mesh.cell_size_m
    if h > res.depth_m / MIN_CELLS_OVER_DEPTH + TOL and not still_water(scene):
        raise InputError(
            "mesh.cell_size_m",
            f"{h:g} m cannot resolve the impoundment: at least {MIN_CELLS_OVER_DEPTH:g} cells over "
            f"reservoir.depth_m ({res.depth_m:g} m) needs <= {res.depth_m / MIN_CELLS_OVER_DEPTH:g} m",
            source,
        )
    if col is not None:
        side = min(col.size_x_m, col.size_y_m)
        if h > side / MIN_CELLS_ACROSS_COLUMN + TOL:
            raise InputError(
                "mesh.cell_size_m",
                f"{h:g} m cannot resolve the column: at least {MIN_CELLS_ACROSS_COLUMN:g} cells across its "
                f"{side:g} m side needs <= {side / MIN_CELLS_ACROSS_COLUMN:g} m",
                source,
            )
    for body in scene.debris:
        small = min(body.size_m)
        if h > small / MIN_CELLS_ACROSS_DEBRIS + TOL:
            raise InputError(
                "mesh.cell_size_m",
                f"{h:g} m cannot resolve debris {body.name!r}: at least {MIN_CELLS_ACROSS_DEBRIS:g} cells across "
                f"its smallest dimension ({small:g} m) needs <= {small / MIN_CELLS_ACROSS_DEBRIS:.4g} m "
                "(else a body may cut no hole in the background mesh)",
                source,
            )
    _check_mesh_top(scene, source)
    _check_refine_box(scene, source)


def _check_refine_box(scene: Scene, source: str | None) -> None:
    """mesh.refine_box_m and mesh.refine_cell_size_m given together, the cells finer than cell_size_m."""
    mesh = scene.mesh
    if (mesh.refine_box_m is None) != (mesh.refine_cell_size_m is None):
        missing = "mesh.refine_cell_size_m" if mesh.refine_cell_size_m is None else "mesh.refine_box_m"
        raise InputError(missing, "a refinement box needs both mesh.refine_box_m and mesh.refine_cell_size_m",
                         source)
    if mesh.refine_cell_size_m is not None and mesh.refine_cell_size_m >= mesh.cell_size_m:
        raise InputError("mesh.refine_cell_size_m", f"{mesh.refine_cell_size_m:g} m must be finer than "
                         f"mesh.cell_size_m ({mesh.cell_size_m:g} m)", source)
    if mesh.column_approach_cell_size_m is not None and mesh.refine_box_m is not None:
        raise InputError("mesh.column_approach_cell_size_m", "one refinement box at a time: set "
                         "mesh.refine_box_m and mesh.refine_cell_size_m to null, or this to null", source)


def _check_mesh_top(scene: Scene, source: str | None) -> None:
    """mesh.top_m (when given) above every body, above the impoundment and at most the flume height."""
    top_m, res, fl = scene.mesh.top_m, scene.reservoir, scene.flume
    if top_m is None:
        return
    for body in scene.debris:
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
        top = float(box_corners(body.centre_m, rot, body.size_m)[:, 2].max())
        if top > top_m + TOL:
            raise InputError(
                "mesh.top_m",
                f"{top_m:g} m is below the top of body {body.name!r} ({top:.4g} m)",
                source,
            )
    if not res.depth_m < top_m <= fl.height_m + TOL:
        raise InputError(
            "mesh.top_m",
            f"must be above the impoundment ({res.depth_m:g} m) and at most the flume height ({fl.height_m:g} m), "
            f"got {top_m:g}",
            source,
        )
