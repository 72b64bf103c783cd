"""The debris bodies: where each one's overset mesh sits, how it is graded, what the body weighs,
whether it rests on the bed and until when it is held there.

Each body gets a box mesh in body coordinates, ``mesh.body_margin_cells`` finest cells
beyond the body on every side, cells of ``mesh.body_cells_across`` across its smallest side
at the body growing to the background's cell size at the mesh edge. Bodies resting on the
bed stand on a thin water gap (:class:`BedGap`) that the background and their meshes share.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from orchestrator.plan.grid import BoxGrid, Segment, graded_segment
from orchestrator.plan.model import BodyPlan
from orchestrator.scene.geometry import draft_m
from orchestrator.scene.schema import DebrisBody, Scene

__all__ = [
    "GAP_LAYERS",
    "BedGap",
    "BodyLayout",
    "bed_gap",
    "body_cell_m",
    "body_inertia",
    "body_layout",
    "body_plans",
    "hold_until_s",
    "meshes_stop_at_bed",
    "still_water_m",
]

#: Cell layers in the gap left under a body resting on the bed (bed_gap).
GAP_LAYERS = 4
_SIDES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")


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


@dataclass(frozen=True)
class BodyLayout:
    """Where the bodies' meshes are at the start: each body's centre as modelled (resting
    bodies stand on the gap), the AABB of its overset mesh, the mesh's margin and the gap."""

    centres: tuple[np.ndarray, ...]
    boxes: tuple[tuple[np.ndarray, np.ndarray], ...]
    margin_m: float
    gap: BedGap | None
    #: whether the meshes of upright resting bodies end at the bed (:func:`meshes_stop_at_bed`)
    stop_at_bed: bool = False
    #: each body's rotation (body axes -> scene axes; :func:`orchestrator.scene.geometry.body_rotation`)
    rotations: tuple[np.ndarray, ...] = ()
    #: whether each body rests on the bed (:func:`orchestrator.plan.facts.rests_on_bed`)
    on_bed: tuple[bool, ...] = ()

    @property
    def lift_m(self) -> float:
        """How far resting bodies are raised: the gap's height (0 without one)."""
        return self.gap.height_m if self.gap is not None else 0.0


def body_inertia(
    size_m: tuple[float, float, float], mass_kg: float, wall_thickness_m: float | None
) -> tuple[float, float, float]:
    """Principal moments of inertia (kg m^2) of a closed box about its body axes
    (:func:`analytical.contact_law.box_inertia`: uniform walls, or solid)."""
    # imported here: the contact law's module loads scipy.stats, a second of start-up that
    # planning a scene (validate, a sweep's dry run) otherwise never needs
    from analytical.contact_law import box_inertia

    return box_inertia(size_m, mass_kg, wall_thickness_m)


def body_cell_m(scene: Scene, body: DebrisBody, h: float) -> float:
    """The cell size of a body's mesh at the body: mesh.body_cells_across its smallest side, at most h."""
    return min(h, min(body.size_m) / scene.mesh.body_cells_across)


def bed_gap(scene: Scene, on_bed: Sequence[bool], h: float) -> BedGap | None:
    """The gap under resting bodies: layers an eighth of the finest resting body's cell.

    The gap (half a body cell: 7.5 mm under the study's container at 1.5 cm body cells) delays
    the float-off until the water is that much deeper than the draft (:func:`hold_until_s`).

    A wet bed shallower than the gap sets the layer so that its surface is one of the planes
    (setFields fills whole cells by their centres: the bed must be a layer boundary).
    """
    resting = [b for b, rests in zip(scene.debris, on_bed) if rests]
    if not resting:
        return None
    layer = min(body_cell_m(scene, b, h) for b in resting) / (2 * GAP_LAYERS)
    wet = scene.bed.wet_depth_m
    if 0 < wet < GAP_LAYERS * layer:
        layer = wet / math.ceil(wet / layer - 1e-9)
    return BedGap(layer)


def meshes_stop_at_bed(on_bed: Sequence[bool]) -> bool:
    """Whether the meshes of upright resting bodies end at the bed instead of reaching a margin below it.

    Below the bed a body mesh has no background donor. With one body there, its cells are a dead end;
    with two or more, their meshes overlap below the bed wherever the bodies come within two margins of
    each other, and there v1912's cellVolumeWeight takes each mesh's donors from the other (it prefers
    the nearest zone number, and there is no other). In the study's 3x1 and 1x3 layouts two-way the
    velocities in those cells grew to 4.8e4 m/s (3x1, 2.0887 s) and 340 m/s (1x3, 1.9708 s), every cell
    faster than 10 m/s was below the bed, and the time step collapsed to 1e-6 s and less at a Courant
    number held at 2.7-2.8 (docs/stability.md, "Several coupled bodies"). So with two or more resting
    bodies each resting body's mesh starts at the bed plane: its lowest gap layer is then its edge.
    A single body keeps the margin below the bed (its validated pages were measured with it). A resting
    body that is pitched or rolled keeps it too (its mesh does not share the gap's planes); where two such
    meshes meet below the bed the plan warns (`_placement_warnings`).
    """
    return sum(on_bed) >= 2


def body_layout(scene: Scene, rotations: tuple[np.ndarray, ...], on_bed: tuple[bool, ...]) -> BodyLayout:
    """Each body's modelled centre and the AABB of its overset mesh (scene coordinates), from
    each body's rotation and whether it rests on the bed (:class:`orchestrator.plan.facts.SceneFacts`)."""
    h = scene.mesh.cell_size_m
    margin = scene.mesh.body_margin_cells * h
    gap = bed_gap(scene, on_bed, h)
    lift = gap.height_m if gap is not None else 0.0
    stop = meshes_stop_at_bed(on_bed)
    centres, boxes = [], []
    for body, rot, rests in zip(scene.debris, rotations, on_bed):
        ext = np.abs(rot) @ (np.asarray(body.size_m) / 2.0 + margin)
        c = np.asarray(body.centre_m, float) + (0.0, 0.0, lift if rests else 0.0)
        lo, hi = c - ext, c + ext
        if stop and _cut_at_bed(rot, rests):
            lo[2] = 0.0
        centres.append(c)
        boxes.append((lo, hi))
    return BodyLayout(tuple(centres), tuple(boxes), margin, gap, stop, rotations, on_bed)


def _cut_at_bed(rot: np.ndarray, on_bed: bool) -> bool:
    """An upright resting body: its mesh shares the gap's planes (BedGap) and may end at the bed."""
    return on_bed and abs(rot[2, 2]) > 1 - 1e-9


def hold_until_s(scene: Scene, body: DebrisBody, gap_m: float, bed_flow) -> float:
    """When a body resting on the bed should float off (s; 0 = it floats from the start): an estimate.

    The runner frees a held body on what it measures (the depth all round the body and the
    fluid's lift on it, orchestrator/run/bedwatch.py); this estimate says when the bore should let it,
    and whether the body is held at all. The estimate is the time the dam-break depth at its
    centre reaches its draft (its mass over the water displaced per metre of immersion by its
    footprint) plus ``gap_m``, the gap it stands on (BedGap). The depth is the analytical
    dry-bed solution: Chanson with the scene's friction factor, or Ritter without friction;
    the thin wet bed is neglected (it only makes the release earlier); ``bed_flow`` is that
    solution (:attr:`orchestrator.plan.facts.SceneFacts.bed_flow`). The simulated bore can
    be later: over a 15 mm wet bed its steep front reached the far end of a container 0.4 m
    from the gate after 0.35 s, where Ritter's depth reached draft plus gap at 0.285 s
    (docs/stability.md). Bodies behind the gate (x < 0) float or not at once: no hold when the
    still water already floats them. Capped at the end time (held throughout).
    """
    draft = draft_m(body, scene.fluids.water_density_kg_m3) + gap_m
    x, h0, end = float(body.centre_m[0]), float(scene.reservoir.depth_m), float(scene.run.end_time_s)
    if x < 0 or draft <= scene.bed.wet_depth_m:
        return 0.0 if (h0 if x < 0 else scene.bed.wet_depth_m) >= draft else end

    def excess(t: float) -> float:
        return float(bed_flow.profile(np.array([x]), t).depth_m[0]) - draft

    t_arrive = float(bed_flow.arrival_time_s(x))
    if not np.isfinite(t_arrive) or t_arrive >= end or excess(end) < 0:
        return end
    lo = max(t_arrive, 1e-6)
    return float(brentq(excess, lo, end)) if excess(lo) < 0 else lo


def still_water_m(scene: Scene, body: DebrisBody) -> float:
    """The still-water level where the body starts: the impoundment behind the gate, the wet bed
    downstream of it (the level the placement puts a floating body's waterline at)."""
    return float(scene.reservoir.depth_m if body.centre_m[0] < 0 else scene.bed.wet_depth_m)


def _split_at(segs: tuple[Segment, ...], level_m: float, max_cell_m: float) -> tuple[Segment, ...]:
    """``segs`` with a plane at ``level_m`` (body coordinates) when it falls inside one of them.

    setFields fills whole cells by their centres, so the body mesh's own still water is right only
    where its surface is a plane of that mesh (as the background's is): without the plane, the study's
    container afloat at its draft (the waterline 3.7 mm under a 15 mm cell's top face) had the water
    in its mesh's waterline row filled up to that face, 3.7 mm above the background's, and heaved
    +-1 mm for 2 s (docs/openfoam-notes.md, "A floating body in still water"). A uniform segment is cut
    into two uniform ones of cells at most ``max_cell_m``; a graded one into two graded from the
    size the grading has at the level.
    """
    out: list[Segment] = []
    for s in segs:
        if not (s.start_m + 1e-4 < level_m < s.end_m - 1e-4):
            out.append(s)
            continue
        if s.cells == 1 or abs(s.grading - 1.0) < 1e-12:
            size = max(max_cell_m, s.length_m / s.cells)
            out += [Segment(s.start_m, level_m, max(1, math.ceil((level_m - s.start_m) / size - 1e-9))),
                    Segment(level_m, s.end_m, max(1, math.ceil((s.end_m - level_m) / size - 1e-9)))]
        else:
            first, last = s.cell_sizes_m()
            mid = first + (last - first) * (level_m - s.start_m) / s.length_m
            out += [graded_segment(s.start_m, level_m, first, mid), graded_segment(level_m, s.end_m, mid, last)]
    return tuple(out)


def _body_grid(scene: Scene, body: DebrisBody, centre: np.ndarray, rot: np.ndarray, on_bed: bool,
               layout: BodyLayout) -> BoxGrid:
    """The body's overset mesh in body coordinates, placed on its centre and rotation."""
    h = scene.mesh.cell_size_m
    hb = body_cell_m(scene, body, h)
    gap, margin = layout.gap, layout.margin_m
    segs_by_axis = []
    for d in range(3):
        half = body.size_m[d] / 2.0
        inner = Segment(-half, half, max(1, math.ceil(2 * half / hb - 1e-9)))
        if d == 2 and _cut_at_bed(rot, on_bed) and gap is not None:
            # an upright resting body's mesh shares the gap's planes (BedGap)
            bed = -half - gap.height_m
            rows = tuple(Segment(bed + k * gap.layer_m, bed + (k + 1) * gap.layer_m, 1) for k in range(gap.layers))
            if layout.stop_at_bed:
                before = rows  # nothing below the bed for another body's mesh to meet (meshes_stop_at_bed)
            else:
                # below the bed: holes while the body rests, water under it once it floats
                before = (graded_segment(min(-half - margin, bed - h), bed, h, hb), *rows)
        else:
            before = (graded_segment(-half - margin, -half, h, hb),)
        after = graded_segment(half, half + margin, hb, h)
        segs = (*before, inner, after)
        if d == 2 and not on_bed and abs(rot[2, 2]) > 1 - 1e-9:
            # a floating upright body's mesh has a plane at the still water (still_water_plane)
            segs = _split_at(segs, still_water_m(scene, body) - float(centre[2]), hb)
        segs_by_axis.append(segs)
    half_z = body.size_m[2] / 2.0
    own = [k for k, s in enumerate(segs_by_axis[2]) if s.start_m >= -half_z - 1e-12 and s.end_m <= half_z + 1e-12]
    return BoxGrid(
        body.name,
        segs_by_axis[0],
        segs_by_axis[1],
        segs_by_axis[2],
        frozenset((1, 1, k) for k in own),
        {**{s: f"{body.name}Overset" for s in _SIDES}, "hole": body.name},
        origin=tuple(float(v) for v in centre),
        rotation=tuple(tuple(float(v) for v in row) for row in rot),
    )


def _body_plan(scene: Scene, body: DebrisBody, centre: np.ndarray, rot: np.ndarray, on_bed: bool,
               layout: BodyLayout, bed_flow) -> BodyPlan:
    if body.moment_of_inertia_kg_m2 is not None:
        inertia = tuple(float(v) for v in body.moment_of_inertia_kg_m2)
    else:
        inertia = body_inertia(body.size_m, body.mass_kg, body.wall_thickness_m)
    return BodyPlan(
        name=body.name,
        grid=_body_grid(scene, body, centre, rot, on_bed, layout),
        mass_kg=body.mass_kg,
        centre_of_mass_m=tuple(float(v) for v in centre),
        moment_of_inertia_kg_m2=inertia,
        orientation=tuple(tuple(float(v) for v in row) for row in rot),
        size_m=tuple(float(v) for v in body.size_m),
        on_bed=on_bed,
        cell_size_m=body_cell_m(scene, body, scene.mesh.cell_size_m),
        velocity_m_s=tuple(float(v) for v in body.velocity_m_s),
        hold_until_s=hold_until_s(scene, body, layout.lift_m, bed_flow) if on_bed else 0.0,
        upright=on_bed if body.upright is None else bool(body.upright),
    )


def _placement_warnings(scene: Scene, layout: BodyLayout, flume_y: tuple[float, float]) -> list[str]:
    """Body meshes that reach out of the flume (its side walls at ``flume_y``) or overlap each other
    at the start."""
    fy0, fy1 = flume_y
    warnings = []
    for body, (lo, hi) in zip(scene.debris, layout.boxes):
        outside = []
        if lo[2] < 0:
            outside.append(f"{-lo[2]:.3g} m below the bed")
        if lo[1] < fy0 or hi[1] > fy1:
            outside.append(f"{max(fy0 - lo[1], hi[1] - fy1):.3g} m through a side wall")
        if outside:
            warnings.append(
                f"{body.name}: its overset mesh reaches {' and '.join(outside)} at the start; cells there have no donors"
            )
    below = [(body.name, lo, hi) for body, (lo, hi) in zip(scene.debris, layout.boxes) if lo[2] < 0]
    for i, (a, lo_a, hi_a) in enumerate(below):
        for b, lo_b, hi_b in below[i + 1:]:
            if all(lo_a[k] < hi_b[k] and lo_b[k] < hi_a[k] for k in (0, 1)):
                warnings.append(
                    f"{a} and {b}: their overset meshes overlap below the bed, where each takes its donors from "
                    "the other (v1912's cellVolumeWeight); in the 3x1 and 1x3 layouts two-way such cells ran away "
                    "and collapsed the time step (docs/stability.md). Only an upright resting body's mesh ends at "
                    "the bed (meshes_stop_at_bed)")
    return warnings


def body_plans(scene: Scene, layout: BodyLayout, flume_y: tuple[float, float], reasons: dict[str, str],
               warnings: list[str], bed_flow) -> tuple[BodyPlan, ...]:
    """One BodyPlan per debris body, with the reasons for the meshes, the gap and the holds
    (``flume_y``: the flume's side walls; ``bed_flow``: the dam-break solution of
    :func:`hold_until_s`)."""
    bodies = tuple(_body_plan(scene, body, c, rot, rests, layout, bed_flow)
                   for body, c, rot, rests in zip(scene.debris, layout.centres, layout.rotations, layout.on_bed))
    warnings += _placement_warnings(scene, layout, flume_y)
    if not bodies:
        reasons["bodies"] = "no debris: no body meshes"
        return bodies
    lift, gap, h = layout.lift_m, layout.gap, scene.mesh.cell_size_m
    holds = [f"{b.name} until {b.hold_until_s:.3g} s" for b in bodies if b.hold_until_s > 0]
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
            + ("; with several resting bodies each one's mesh ends at the bed, so that no two body meshes meet "
               "below it, where each would take its donors from the other (meshes_stop_at_bed)"
               if layout.stop_at_bed else "")
        )
    reasons["bodies"] = (
        f"{len(bodies)} overset body mesh(es): each box extends {scene.mesh.body_margin_cells} finest cells "
        f"({layout.margin_m:.3g} m) beyond its body so donors lie in fine background cells and calculated body cells "
        "surround the body (thinner meshes let the flow pass the body by: docs/openfoam-notes.md); cells of "
        f"{bodies[0].cell_size_m:.3g} m at the body ({scene.mesh.body_cells_across:g} across its smallest side), "
        f"{h:g} m at the mesh edge; inertia from the box walls (wall_thickness_m) or as given"
    )
    return bodies
