"""Planning: decide what a scene needs to be modelled, and say why.

:func:`plan_case` is a pure function ``Scene -> ModelPlan``. It first takes what the scene's
geometry and the analytical dam-break flow give (:mod:`~orchestrator.plan.facts`), once, and hands
those values down. From the bodies' placement (:mod:`~orchestrator.plan.bodies`) it chooses how the debris meets
the flow (:mod:`~orchestrator.plan.coupling`), the solver (interFoam on a static mesh without
debris or for a one-way flow record, overInterDyMFoam with one six-DoF body per debris for
two-way) and 2D or 3D here, then asks each stage of the plan in turn: how much of the reservoir
and of the downstream flume to model and where cells are fine (:mod:`~orchestrator.plan.domain`), the
background mesh and its grading (:mod:`~orchestrator.plan.grading`), the body meshes, the
water to fill and the gauges, the time step and its cost (:mod:`~orchestrator.plan.timestep`),
the domain decomposition (:mod:`~orchestrator.plan.decompose`), the numbers the case's
dictionaries need (:mod:`~orchestrator.plan.case_numbers`) and, one-way, the flow record.
A one-way plan keeps the background mesh a two-way plan of the scene would have (the gap
layers under resting bodies included), so the two flows compare cell for cell. Every choice has a sentence in
``ModelPlan.reasons``; ``ModelPlan.to_json()`` is written to ``plan.json`` in a case.
"""

from __future__ import annotations

import math
from dataclasses import replace

from orchestrator.plan.bodies import BodyLayout, body_inertia, body_layout, body_plans
from orchestrator.plan.case_numbers import WET_BED, case_numbers
from orchestrator.plan.coupling import ONE_WAY_MAX_COURANT, choose_coupling, flow_record_plan
from orchestrator.plan.decompose import decompose
from orchestrator.plan.domain import SAFETY, Domain, column_spans_width, plan_domain
from orchestrator.plan.facts import SceneFacts, scene_facts
from orchestrator.plan.gate import opening_span_m, reservoir_floor_m
from orchestrator.plan.gate_opening import BLOCK_F_PER_M, gate_bands
from orchestrator.plan.grading import background_grid
from orchestrator.plan.model import BodyPlan, GaugePlan, ModelPlan, WaterBox
from orchestrator.plan.resources import require_labels
from orchestrator.plan.timestep import (
    MEASURED_CORES,
    STEP_FACTOR,
    US_PER_CELL_STEP,
    estimate_wall_time_s,
    estimated_steps,
    max_delta_t_s,
    time_step_estimate_s,
)
from orchestrator.scene.inundation import inundation_reason
from orchestrator.scene.schema import Scene
from orchestrator.scene.scenefile import load_scene

__all__ = [
    "BodyPlan",
    "GaugePlan",
    "ModelPlan",
    "REASON_KEYS",
    "SAFETY",
    "STEP_FACTOR",
    "US_PER_CELL_STEP",
    "WaterBox",
    "body_inertia",
    "estimate_wall_time_s",
    "estimated_steps",
    "load_and_plan",
    "max_delta_t_s",
    "plan_case",
]

#: Every decision the plan records a reason for.
REASON_KEYS = (
    "debris_coupling",
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


def load_and_plan(scene_path, sets=()) -> tuple[Scene, ModelPlan]:
    """The scene file ``scene_path`` with the overrides ``sets``, loaded and planned: what a
    command does once, handing both down to render, run and report."""
    scene = load_scene(scene_path, list(sets or []))
    return scene, plan_case(scene, str(scene_path))


def plan_case(scene: Scene, source: str | None = None) -> ModelPlan:
    """What ``scene`` needs: solver, dimensions, extents, grids, bodies, water, gauges.

    Pure: reads nothing, writes nothing. Raises InputError on ``mesh.cell_size_m`` (attributed to
    ``source``, the scene file) when the mesh needs more cells than OpenFOAM's labels can number
    (:func:`~orchestrator.plan.resources.require_labels`): checked on the counts of the grids'
    segments, before anything is built cell by cell, so even an absurd cell size is refused at once.
    """
    facts = scene_facts(scene)  # what the scene's geometry and the analytical flow give, once
    reasons: dict[str, str] = {}
    warnings: list[str] = []
    layout = body_layout(scene, facts.rotations, facts.on_bed)
    coupling = choose_coupling(scene, layout.rotations, reasons, warnings)
    solver, two_d = _choose_model(scene, coupling, reasons)
    domain = plan_domain(scene, facts.flume, facts.stoker, list(layout.boxes), reasons, warnings)
    background = background_grid(scene, domain, layout.gap, two_d, reasons, warnings, one_way=coupling == "one-way")
    require_labels(background.cell_count(), source)
    warnings += facts.warnings
    gate = gate_bands(scene, background.x, background.z, domain.y)
    if gate:
        reasons["gate_opening"] = (
            f"the gate lifts over {scene.reservoir.opening_time_s:g} s: {len(gate)} bands of the cells upstream of "
            f"x = 0 blocked (Forchheimer F = {BLOCK_F_PER_M:g} 1/m) until the gate's edge passes each band's top")
    flow_record = None
    if coupling == "one-way":
        scene, layout, bodies, flow_record = _one_way(scene, layout, background, domain, reasons)
    else:
        bodies = body_plans(scene, layout, domain.y, reasons, warnings, facts.bed_flow)
    water = _water(scene, domain, facts, reasons)
    gauges = _gauges(scene, domain, reasons)
    record_interval = flow_record.interval_s if flow_record is not None else None
    dt = time_step_estimate_s(scene, solver, background, bodies, two_d, reasons, record_interval)
    cells = background.cell_count() + sum(b.grid.cell_count() for b in bodies)
    require_labels(cells, source)
    reasons["cell_count"] = (
        f"{cells} cells: background {background.cell_count()}"
        + (f" + bodies {', '.join(str(b.grid.cell_count()) for b in bodies)}" if bodies else "")
    )
    run = scene.run
    reasons["run_controls"] = (
        f"end time {run.end_time_s:g} s, writes every {run.write_interval_s:g} s, maxCo = maxAlphaCo = "
        f"{run.max_courant:g} (from the scene's run section)"
    )
    decomposition, reasons["decomposition"] = decompose(run.cores, background, bodies, layout, domain, two_d)
    plan = ModelPlan(
        scene_name=scene.name,
        solver=solver,
        two_d=two_d,
        background=background,
        bodies=bodies,
        water=water,
        gauges=gauges,
        cell_count=cells,
        decomposition=decomposition,
        end_time_s=run.end_time_s,
        write_interval_s=run.write_interval_s,
        max_courant=run.max_courant,
        domain_m=domain.extent_m,
        fine_region_m=domain.fine,
        downstream_type=domain.downstream_type,
        bed_friction_factor=scene.bed.friction_factor,
        bed_friction_calibration=scene.bed.friction_calibration,
        stall_limit_s=run.stall_limit_s,
        water_balance_limit=run.water_balance_limit,
        bed_gap_m=layout.lift_m if bodies else 0.0,
        velocity_scale_m_s=2.0 * math.sqrt(scene.fluids.gravity_m_s2 * scene.reservoir.depth_m),
        time_step_estimate_s=dt,
        reasons=reasons,
        warnings=tuple(warnings),
        debris_coupling=coupling,
        flow_record=flow_record,
        turbulence=scene.fluids.turbulence,
        bed_roughness_m=facts.bed_roughness_m,
        bed_slip=scene.bed.slip,
        gate_bands=gate,
        # the drag layer is the laminar model's bed friction; a RANS flow feels the bed's roughness
        **case_numbers(background, water, gauges, two_d=two_d, max_courant=run.max_courant,
                       write_interval_s=run.write_interval_s, max_delta_t=run.max_delta_t_s,
                       gravity_m_s2=scene.fluids.gravity_m_s2,
                       bed_friction_factor=scene.bed.friction_factor if scene.fluids.turbulence == "laminar" else 0.0,
                       bed_friction_calibration=scene.bed.friction_calibration,
                       record_interval_s=record_interval),
    )
    return _with_wall_time(plan)


def _one_way(scene: Scene, layout: BodyLayout, background, domain: Domain, reasons: dict[str, str]):
    """A one-way plan's scene (its Courant limit for interFoam), body layout (none in the flow),
    bodies (none) and flow record."""
    n = len(scene.debris)
    record = flow_record_plan(scene, layout.rotations, background, domain, reasons)
    reasons["bodies"] = (
        f"one-way: none of the {n} bod{'y' if n == 1 else 'ies'} in the flow (no body meshes); they are carried "
        f"through the flow record afterwards"
    )
    run = scene.run
    if run.max_courant > ONE_WAY_MAX_COURANT:
        reasons["max_courant"] = (
            f"maxCo = maxAlphaCo = {ONE_WAY_MAX_COURANT:g}, not the scene's {run.max_courant:g}: that value is for "
            "the overset solver, which counts hole and fringe faces in its Courant number; interFoam's explicit "
            "MULES keeps alpha bounded only up to an alpha Courant number of 1"
        )
        scene = scene.model_copy(update={"run": run.model_copy(update={"max_courant": ONE_WAY_MAX_COURANT})})
    return scene, BodyLayout((), (), layout.margin_m, layout.gap), (), record


def _choose_model(scene: Scene, coupling: str, reasons: dict[str, str]) -> tuple[str, bool]:
    """The solver (overset for two-way debris) and whether the case is 2D (nothing varies across)."""
    n, col = len(scene.debris), scene.column
    if coupling == "one-way":
        solver = "interFoam"
        reasons["solver"] = (
            f"one-way: interFoam on a static mesh without the {n} debris bod{'y' if n == 1 else 'ies'}, "
            "the flow recorded for them (flow_record)"
        )
    elif n:
        solver = "overInterDyMFoam"
        reasons["solver"] = (
            f"{n} debris bod{'y' if n == 1 else 'ies'}: overInterDyMFoam with one "
            "six-DoF solver per body, each body on its own overset mesh"
        )
    else:
        solver = "interFoam"
        reasons["solver"] = "no debris: interFoam on a static mesh (about 4x cheaper per cell-step than overset)"
    full_width_col = column_spans_width(scene)
    narrowed = opening_span_m(scene) is not None
    two_d = not n and not narrowed and (col is None or full_width_col)
    if two_d:
        reasons["two_d"] = (
            "2D: no debris and "
            + ("no column" if col is None else "the obstacle spans the full width")
            + ", so nothing varies across the flume; one cell across, frontAndBack empty"
        )
    else:
        why = []
        if n:
            why.append("debris bodies move in 3D")
        if col is not None and not full_width_col:
            why.append("the column does not span the flume's width")
        if narrowed:
            why.append("the gate's opening is narrower than the flume")
        reasons["two_d"] = "3D: " + " and ".join(why)
    res = scene.reservoir
    reasons["gate"] = (
        (f"gate '{res.gate}' lifting off the reservoir's floor over {res.opening_time_s:g} s"
         if res.opening_time_s > 0 else f"gate '{res.gate}' removed at once at t = 0")
        + ("" if res.sill_height_m > 0 or narrowed else "; no sill, the opening the flume's width")
    )
    return solver, two_d


def _water(scene: Scene, domain: Domain, facts: SceneFacts, reasons: dict[str, str]) -> tuple[WaterBox, ...]:
    """The reservoir behind the gate and the wet bed downstream, and the bed friction's reason
    (a RANS flow's bed roughness from ``facts``)."""
    h0, wet = scene.reservoir.depth_m, scene.bed.wet_depth_m
    (fy0, fy1) = domain.y
    water = [WaterBox("reservoir", (domain.x_lo, fy0, reservoir_floor_m(scene)), (0.0, fy1, h0))]
    if wet > 0:
        water.append(WaterBox(WET_BED, (0.0, fy0, 0.0), (domain.x_hi, fy1, wet)))
    reasons["water"] = (
        f"water up to {h0:g} m behind the gate"
        + (f" and a {wet:g} m wet bed downstream" if wet > 0 else "; dry bed")
        + (f"; {inundation_reason(scene)}" if scene.inundation is not None else "")
    )
    if scene.bed.slip:
        reasons["bed_friction"] = "none: bed.slip makes the bed a slip wall (frictionless, no shear)"
    elif scene.fluids.turbulence != "laminar":
        ks = facts.bed_roughness_m
        reasons["bed_friction"] = (
            f"{scene.fluids.turbulence} with wall functions: the bed rough with sand roughness k_s = {ks:.3g} m, "
            f"which gives Darcy f = {scene.bed.friction_factor:g} at the depth the flow runs at, "
            f"{facts.bore_depth_m:.3g} m (Colebrook, analytical/roughness.py); "
            "no drag layer" if ks > 0 else f"{scene.fluids.turbulence} with wall functions on a smooth bed")
    elif scene.bed.friction_factor <= 0:
        reasons["bed_friction"] = "none: bed.friction_factor is 0 (a laminar flow over a no-slip bed)"
    else:
        reasons["bed_friction"] = (
            f"Darcy f = {scene.bed.friction_factor:g} as a drag rho (f/8)|U|U on the cell layers next to the bed: "
            "without friction the front arrives 15-30 % early (docs/openfoam-notes.md); the drag is multiplied by "
            f"bed.friction_calibration = {scene.bed.friction_calibration:g}, calibrated against Chanson's dry-bed "
            "arrival times, not the study's gauges (docs/bed-friction.md)"
        )
    return tuple(water)


def _gauges(scene: Scene, domain: Domain, reasons: dict[str, str]) -> tuple[GaugePlan, ...]:
    """One vertical gauge line per scene gauge, from the bed to the domain's top."""
    gauges = tuple(GaugePlan(gg.name, gg.x_m, gg.y_m, domain.z_hi) for gg in scene.gauges)
    reasons["gauges"] = (
        f"{len(gauges)} gauge line(s) from the bed to z = {domain.z_hi:.3g} m; depth from alpha.water along each"
        if gauges
        else "no gauges"
    )
    return gauges


def _with_wall_time(plan: ModelPlan) -> ModelPlan:
    """The plan with its estimated wall time, and the estimate in its cell-count reason."""
    wall = estimate_wall_time_s(plan)
    plan.reasons["cell_count"] += (
        f"; about {estimated_steps(plan)} steps x {US_PER_CELL_STEP[plan.solver] * 1e6:g} us/cell-step on "
        f"{MEASURED_CORES} cores -> about {wall / 60:.1f} min on {plan.cores} core(s)"
    )
    return replace(plan, estimated_wall_time_s=wall)
