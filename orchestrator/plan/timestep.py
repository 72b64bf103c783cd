"""Time steps and cost: the step the Courant limit allows, its cap, the first step, and the
wall time a plan is expected to take.

The estimate of the step is the Courant limit at Ritter's front speed ``2 sqrt(g h0)`` (no
flow in a dam break is faster) on the smallest horizontal cell, over a measured factor
(:data:`STEP_FACTOR`), at most maxDeltaT. The wall time is cells x steps x a measured cost
per cell-step (:data:`US_PER_CELL_STEP`).
"""

from __future__ import annotations

import math

from orchestrator.plan.grading import min_cell_m
from orchestrator.plan.grid import BoxGrid
from orchestrator.plan.model import BodyPlan, ModelPlan
from orchestrator.plan.scale import time_scale
from orchestrator.scene.schema import Scene

__all__ = [
    "MEASURED_CORES",
    "STEP_FACTOR",
    "US_PER_CELL_STEP",
    "estimate_wall_time_s",
    "estimated_steps",
    "first_delta_t_s",
    "max_delta_t_s",
    "time_step_estimate_s",
]

#: Wall time per cell per time step on 2 cores (s; docs/openfoam-notes.md, "Cost"): interFoam
#: 2-5 us (mid value). overInterDyMFoam: whole coupled runs with the runner's restarts (contact,
#: release, friction refresh: 19-31 segments each), 12.1 us on the study's 1-debris scene at 4 cm
#: (140,749 cells, 1,478 steps to 3.5 s in 42 min) and 16.7 us on the short flume at 4 cm
#: (95,548 cells, 1,431 steps to 2.1 s in 38 min): 14 us.
US_PER_CELL_STEP = {"interFoam": 3.5e-6, "overInterDyMFoam": 14.0e-6}
#: The default maxDeltaT (s) at the study's 0.40 m impoundment (x sqrt(lambda) deeper: plan.scale).
MAX_DELTA_T_S = 0.01
#: The cap on the first time step (s) at the study's 0.40 m impoundment (x sqrt(lambda) deeper).
FIRST_DELTA_T_CAP_S = 1e-3
#: Cores at which US_PER_CELL_STEP was measured.
MEASURED_CORES = 2
#: Measured time steps over the steps the Courant limit at Ritter's front speed predicts
#: (run.max_courant x smallest horizontal cell / 2 sqrt(g h0)), where maxDeltaT does not bind.
#: interFoam: 1.11 and 1.39 (the no-debris mesh study at 4 and 3 cm, README). overInterDyMFoam:
#: 3.7 (the 1-debris scene at 4 cm), 6.0, 8.1 and 5.4 (the debris mesh study's short flume at 4,
#: 3.5 and 3 cm), 5.5 their geometric mean: v1912 counts hole and fringe faces in its Courant
#: number, the flow past a body is faster than the front, and each restart begins with short
#: steps, so a run whose body strikes the column more often takes more (11 strikes at 3.5 cm).
STEP_FACTOR = {"interFoam": 1.25, "overInterDyMFoam": 5.5}


def max_delta_t_s(max_delta_t: float | None, write_interval_s: float, water_depth_m: float = 0.0,
                  record_interval_s: float | None = None) -> float:
    """The largest time step the case allows (maxDeltaT): the scene's run.max_delta_t_s, else
    min(0.01 s x sqrt(lambda), the write interval, the one-way flow record's frame interval),
    lambda the scene's Froude factor over the study's flume (:func:`~orchestrator.plan.scale.froude_factor`
    of ``water_depth_m``, the impoundment depth; 0 or less: 1), so a scene 40 times larger takes the
    same steps, and a record at more than 100 Hz gets a frame at every interval."""
    factor = time_scale(water_depth_m) if water_depth_m > 0 else 1.0
    return float(max_delta_t or min(MAX_DELTA_T_S * factor, write_interval_s, record_interval_s or math.inf))


def first_delta_t_s(max_courant: float, min_cell: float, water_depth_m: float, gravity_m_s2: float) -> float:
    """The first time step (deltaT, two significant digits): a tenth of the Courant limit on the
    smallest cell at Ritter's front speed for the deepest water, at most 1 ms x sqrt(lambda)."""
    wave_speed = 2 * math.sqrt(gravity_m_s2 * max(water_depth_m, 1e-3))
    cap = FIRST_DELTA_T_CAP_S * (time_scale(water_depth_m) if water_depth_m > 0 else 1.0)
    return float(f"{min(cap, 0.1 * max_courant * min_cell / wave_speed):.2g}")


def time_step_estimate_s(scene: Scene, solver: str, background: BoxGrid, bodies: tuple[BodyPlan, ...],
                         two_d: bool, reasons: dict[str, str], record_interval_s: float | None = None) -> float:
    """The time step the solver is expected to take (s), with its reason."""
    u_ref = 2.0 * math.sqrt(scene.fluids.gravity_m_s2 * scene.reservoir.depth_m)
    horizontal = [min_cell_m(background.x)] + ([] if two_d else [min_cell_m(background.y)])
    for b in bodies:
        # the gap's flat layers under a resting body (BedGap), and the mesh's cells grading
        # down to them below the bed, carry horizontal flow or none: their Courant number is
        # set by their width, not their height; the body's own and upper segments count
        tall = tuple(s for s in b.grid.z if s.start_m >= -0.5 * b.size_m[2] - 1e-9)
        horizontal += [min_cell_m(b.grid.x), min_cell_m(b.grid.y), min_cell_m(tall)]
    h_step = min(horizontal)
    dt_courant = scene.run.max_courant * h_step / u_ref
    cap = max_delta_t_s(scene.run.max_delta_t_s, scene.run.write_interval_s, scene.reservoir.depth_m,
                        record_interval_s)
    dt = min(dt_courant / STEP_FACTOR[solver], cap)
    reasons["time_step"] = (
        f"about {dt:.3g} s: Co = {scene.run.max_courant:g} on the smallest horizontal cell ({h_step:.3g} m) at "
        f"U = 2 sqrt(g h0) = {u_ref:.3g} m/s (Ritter's front speed) gives {dt_courant:.3g} s, over "
        f"{STEP_FACTOR[solver]:g} (the measured steps of {solver} over that estimate), at most maxDeltaT = {cap:.3g} s"
    )
    return dt


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
    per = US_PER_CELL_STEP[plan.solver] * MEASURED_CORES / plan.cores
    return plan.cell_count * steps * per
