"""What the run stage knows of a rendered case: `CaseInfo`, read by `load_case_info`.

The runner, the segment watch and the contact book all work from one `CaseInfo`: the
solver, the ranks, the end time and write interval, the time-step controls, the modelled
domain and its walls, and the bodies (their properties, sizes and holds on the bed). It is
read once, from plan.json, system/controlDict and constant/dynamicMeshDict.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from orchestrator.case import bodystate
from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.plan.model import BodyPlan, ModelPlan
from orchestrator.run.control import read_control

__all__ = ["CaseInfo", "load_case_info"]


@dataclass(frozen=True)
class CaseInfo:
    """What the runner needs to know of a rendered case (plan.json, controlDict, dynamicMeshDict);
    `domain_m` and `downstream_type` say where the modelled flume has walls.
    """

    case: Path
    solver: str
    #: the case's plan.json, its bodies those of constant/dynamicMeshDict (what foam.mesh_steps /
    #: solve_steps read)
    plan: ModelPlan
    ranks: int
    planned_cells: int
    end_time_s: float
    write_interval_s: float
    velocity_scale_m_s: float
    adjustable_time_step: bool
    max_courant: float
    delta_t_s: float
    #: the case's own largest time step (controlDict maxDeltaT; the runner lowers it near contacts)
    max_delta_t_s: float
    domain_m: tuple[tuple[float, float], ...]
    two_d: bool
    downstream_type: str
    #: the plan's bodies in constant/dynamicMeshDict's order (the solver's)
    bodies: tuple[BodyPlan, ...]
    body_sizes_m: dict[str, tuple[float, float, float]]
    #: (body, time) of bodies held on the bed until that time (plan.json hold_until_s)
    holds: tuple[tuple[str, float], ...] = ()
    #: plan.json stall_limit_s (scene run.stall_limit_s): None = the runner's default
    stall_limit_s: float | None = None
    #: plan.json water_balance_limit (scene run.water_balance_limit): None = the runner's default
    water_balance_limit: float | None = None
    #: plan.json water_depth_m (the impoundment): the scene's Froude scale (orchestrator.plan.scale)
    water_depth_m: float = 0.0

    @property
    def body_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bodies)


def load_case_info(case_dir: str | Path, np_override: int | None = None) -> CaseInfo:
    """Read plan.json, system/controlDict and constant/dynamicMeshDict of a rendered case."""
    case = Path(case_dir).resolve()
    folder = CaseFolder(case)
    plan = folder.require_plan()
    control = read_control(case)
    ranks = int(np_override) if np_override else plan.cores
    if ranks < 1:
        raise InputError("--np", f"must be >= 1, got {ranks}")
    try:  # a file foamlib cannot parse raises its DictionaryError, a ValueError
        bodies = tuple(bodystate.read_mesh_poses(case))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(str(bodystate.DYNAMIC_MESH_DICT), f"not the dictionary `debrisfoam render` writes ({exc!r})",
                         str(case)) from None
    planned = {b.name: b for b in plan.bodies}
    missing = [b.name for b in bodies if b.name not in planned]
    if missing:
        raise InputError("bodies", f"no size for bodies {missing} of constant/dynamicMeshDict", str(folder.plan_path))
    return CaseInfo(
        case=case,
        solver=plan.solver,
        plan=replace(plan, bodies=tuple(planned[b.name] for b in bodies)),
        ranks=ranks,
        planned_cells=int(plan.cell_count),
        end_time_s=float(control["endTime"]),
        write_interval_s=float(control["writeInterval"]),
        velocity_scale_m_s=float(plan.velocity_scale_m_s or 5.0),
        water_depth_m=float(plan.water_depth_m or 0.0),
        adjustable_time_step=str(control["adjustTimeStep"]).lower() in ("yes", "on", "true", "1")
        if "adjustTimeStep" in control else False,
        max_courant=float(control["maxCo"]) if "maxCo" in control else 1.0,
        delta_t_s=float(control["deltaT"]),
        max_delta_t_s=float(control["maxDeltaT"]) if "maxDeltaT" in control else float(
            plan.max_delta_t_s or control["deltaT"]),
        domain_m=tuple(tuple(float(v) for v in a) for a in plan.domain_m),
        two_d=bool(plan.two_d),
        downstream_type=str(plan.downstream_type),
        bodies=tuple(planned[b.name] for b in bodies),
        body_sizes_m={b.name: tuple(float(v) for v in b.size_m) for b in plan.bodies},
        holds=tuple((b.name, float(b.hold_until_s)) for b in plan.bodies if float(b.hold_until_s or 0.0) > 0.0),
        stall_limit_s=float(plan.stall_limit_s) if plan.stall_limit_s else None,
        water_balance_limit=float(plan.water_balance_limit) if plan.water_balance_limit else None,
    )
