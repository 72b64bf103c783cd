"""ModelPlan -> OpenFOAM v1912 case directory, through Jinja templates.

One template per OpenFOAM file under `templates/` (mirroring the case layout:
`templates/system/controlDict.j2` -> `<case>/system/controlDict`). Templates see
one *render context* (`build_context`), a plain dict of numbers, words and
`BoxGrid`s, so they hold layout only. Every number is decided by the planner and read
here from the plan (`ModelPlan`): the renderer formats, it does not choose.

The environment uses delimiters that cannot clash with OpenFOAM's braces and `#`
directives: blocks `<% %>`, variables `<< >>`, comments `<# #>`; undefined names
raise (StrictUndefined). Filters format numbers, vectors, lists and tensors the
way OpenFOAM reads them.

A rendered case holds, beside `system/`, `constant/` and `0/`:
`bodies/<name>/` (one blockMesh sub-case per debris body, merged into the
background by `mergeMeshes`), `scene.yaml` (resolved scene), `plan.json` and a
`README.md` with the exact commands to run it by hand.

Lengths in metres, masses in kg, times in seconds.
"""

from __future__ import annotations

import math
import shutil
from dataclasses import asdict, dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np
import yaml
from jinja2 import ChoiceLoader, Environment, FileSystemLoader, StrictUndefined

from orchestrator.core.errors import InputError
from orchestrator.case import foam
from orchestrator.case.folder import BED_LAYER_ZONE, BODIES_DIR, PLAN_JSON, SCENE_YAML
from orchestrator.core.files import bundled_dir, write_text_atomic
from orchestrator.plan.gate_opening import BLOCK_F_PER_M
from orchestrator.plan.grading import BACKGROUND_PATCHES, COLUMN_PATCH
from orchestrator.plan.grid import BoxGrid
from orchestrator.plan.model import ModelPlan
from orchestrator.scene.scenefile import dump_scene_yaml
from orchestrator.scene.schema import Fluids, Outputs, Scene

TEMPLATE_DIR = bundled_dir("templates", "templates")

#: Background patches and what they are, by the planner's patch names.
BACKGROUND_PATCH_KINDS = {
    "upstreamWall": "wall",
    "downstream": "wall",  # or "outlet": the plan's downstream_type
    "sideWalls": "wall",
    "frontAndBack": "empty",
    "bed": "wall",
    "atmosphere": "atmosphere",
    "column": "wall",
}
#: blockMesh patch type of each patch kind.
BLOCKMESH_TYPES = {"wall": "wall", "slip": "wall", "body": "wall", "atmosphere": "patch", "outlet": "patch",
                   "empty": "empty", "overset": "overset"}
#: Name of the empty overset patch put first in the background mesh (as the v1912
#: floatingBody tutorial does) so that overset interpolation is set up before any
#: other boundary condition is evaluated.
OVERSET_DUMMY_PATCH = "oversetPatch"

# --------------------------------------------------------------------------- numerics


#: maxCo at or below which overInterDyMFoam gets the careful correctors (Numerics.for_solver)
CAREFUL_COURANT = 1.0


@dataclass(frozen=True)
class Numerics:
    """Linear solvers, PIMPLE and overset settings (the levers of benchmarks/runner_settings.md).

    Defaults: interFoam as the v1912 damBreak tutorial (GAMG for p_rgh); overset as
    measured in docs/openfoam-notes.md ("Overset: setting up six-DoF bodies"): cellVolumeWeight, PBiCGStab/DILU for p_rgh at
    tolerance 1e-7 / relTol 0.05 (GAMG fails with overset); the PIMPLE correctors depend on
    the scene's maxCo (`for_solver`).
    """

    p_rgh_solver: str
    p_rgh_tolerance: float = 1e-7
    p_rgh_rel_tol: float = 0.05
    #: relTol of the final p_rgh solve; with one outer and one inner corrector the
    #: only solve is the final one, so this is the one that decides the cost.
    p_rgh_final_rel_tol: float = 0.0
    n_outer_correctors: int = 1
    n_correctors: int = 3
    momentum_predictor: bool = False
    n_alpha_correctors: int = 2
    n_alpha_subcycles: int = 1
    overset_interpolation: str = "cellVolumeWeight"
    #: PIMPLE `oversetAdjustPhi`: scale the flux leaving each mesh's fringe to what enters it
    #: before the pressure solve. Off: it cut the water lost around a container pinned at the
    #: column (1.18 to 0.39 % a second) but created water around one sliding fast along the
    #: bed (+2.1 % a second against -0.1 % without, short flume 1.1-1.2 s;
    #: docs/openfoam-notes.md, "Water balance: where the overset loses water").
    overset_adjust_phi: bool = False
    #: The pcorr solve v1912's overInterDyMFoam runs on the flux it reads at every (re)start
    #: (its correctPhi.H, unconditional there). It bypasses the overset coupling, so it pushes
    #: every fringe cell's imbalance through the gaps between a body mesh and a wall or the
    #: column: maxCo read 24-180 at restarts of `make case-1debris` (1.1-2.5 before them),
    #: deltaT fell 20-70 fold and the column force jumped (103 N against 18.9 N the step
    #: before, 3.5 s). Off (the default): a pcorr tolerance above any normalised residual
    #: (<= 1) makes that solve a no-op, and the restart goes on from the flux the solver
    #: wrote: 17.1 N, maxCo 1.5 (docs/openfoam-notes.md, "Restarts: the start-up flux projection"). pcorr is used nowhere
    #: else (correctPhi is off).
    restart_flux_projection: bool = False
    #: sixDoFRigidBodyMotion relaxation/damping of the body acceleration (tutorial values)
    acceleration_relaxation: float = 0.6
    acceleration_damping: float = 0.9

    @classmethod
    def for_solver(cls, solver: str, max_courant: float | None = None) -> "Numerics":
        """The settings for `solver` at the scene's maxCo (None: the fast overset setting).

        overInterDyMFoam, from benchmarks/runner_settings.md (1-debris case, 1.0 s):
        - maxCo <= CAREFUL_COURANT: two outer correctors, three pressure correctors, final
          p_rgh solve to relTol 0 ("ref-tol"): the cheapest setting within 2 % of the most
          careful one in debris track and column force (0.00 %, 0.92x its cost), and cheaper
          than the fast setting at this Courant number (one outer corrector fails the column
          force by 10-12 % here and takes more time steps);
        - above: one outer and two pressure correctors (relTol 0.05 throughout). With one
          corrector the flux left after the only solve is far from divergence-free and MULES
          creates water (+3.9 % in 0.8 s on the short flume); two keep it to 0.17 % at 1.25x
          the cost (docs/stability.md). At maxCo 2.5 no corrector setting brings the column
          force within 15 % of the careful one: the time step is the lever there.
        """
        if solver == "overInterDyMFoam":
            if max_courant is not None and max_courant <= CAREFUL_COURANT:
                return cls(p_rgh_solver="PBiCGStab", n_outer_correctors=2, n_correctors=3)
            return cls(p_rgh_solver="PBiCGStab", p_rgh_final_rel_tol=0.05, n_correctors=2)
        if solver == "interFoam":
            return cls(p_rgh_solver="GAMG")
        raise InputError("solver", f"must be interFoam or overInterDyMFoam, got {solver!r}")


# --------------------------------------------------------------------------- environment


def _number(value: Any) -> str:
    """A number as OpenFOAM reads it: integers plain, floats with 10 significant digits.

    Values within 1e-12 of zero are written as 0 (rotated vertices otherwise carry
    round-off such as -1.2e-17 into golden files). Booleans and non-finite values are
    refused: OpenFOAM would read them as words or garbage.
    """
    if isinstance(value, (bool, np.bool_)):
        # The scene refuses a boolean where a number belongs (scene.base) and the plan's switches go
        # through foam_switch: a boolean here is a template's mistake.
        raise TypeError(f"not a number: {value!r}")  # internal: no scene reaches it (above)
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    v = float(value)
    if not math.isfinite(v):
        # The scene refuses infinity and NaN in every field (scene.base) and the planner derives
        # finite numbers from finite ones: a non-finite number here is a planner's mistake.
        raise ValueError(f"not a finite number: {value!r}")  # internal: no scene reaches it (above)
    if abs(v) < 1e-12:
        return "0"
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    return f"{v:.10g}"


def _vector(values: Iterable[Any]) -> str:
    vals = list(np.asarray(values, dtype=float).ravel())
    if len(vals) != 3:
        raise ValueError(f"a vector needs 3 components, got {len(vals)}")  # internal: the plan's vectors are 3-tuples
    return "(" + " ".join(_number(v) for v in vals) + ")"


def _tensor(values: Any) -> str:
    """A 3x3 tensor (nested or flat, row-major) as OpenFOAM's (xx xy xz yx ... zz)."""
    vals = list(np.asarray(values, dtype=float).ravel())
    if len(vals) != 9:
        raise ValueError(f"a tensor needs 9 components, got {len(vals)}")  # internal: the plan's tensors are 3x3
    return "(" + " ".join(_number(v) for v in vals) + ")"


def _list(values: Iterable[Any]) -> str:
    """A list of numbers or words: (a b c)."""
    return "(" + " ".join(v if isinstance(v, str) else _number(v) for v in values) + ")"


def _switch(value: bool) -> str:
    return "yes" if value else "no"


def template_environment(extra_dirs: Sequence[str | Path] = ()) -> Environment:
    """The Jinja environment for OpenFOAM files; `extra_dirs` override bundled templates."""
    loaders = [FileSystemLoader(str(d)) for d in extra_dirs] + [FileSystemLoader(str(TEMPLATE_DIR))]
    env = Environment(
        loader=ChoiceLoader(loaders),
        undefined=StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
        block_start_string="<%",
        block_end_string="%>",
        variable_start_string="<<",
        variable_end_string=">>",
        comment_start_string="<#",
        comment_end_string="#>",
    )
    env.filters.update(foam_number=_number, foam_vector=_vector, foam_tensor=_tensor,
                       foam_list=_list, foam_switch=_switch)
    return env


# --------------------------------------------------------------------------- context


def _mesh_context(grid: BoxGrid, patch_kinds: dict[str, str], zone: str | None,
                  leading: Sequence[tuple[str, str]] = ()) -> dict[str, Any]:
    """What blockMeshDict.j2 needs for one BoxGrid."""
    names = list(grid.boundary_faces())
    unknown = [n for n in names if n not in patch_kinds]
    if unknown:
        raise InputError(f"{grid.name}.patch_names", f"no boundary condition known for patch(es) {unknown}")
    return {
        "grid": grid,
        "zone": zone,
        "patch_types": {n: BLOCKMESH_TYPES[patch_kinds[n]] for n in names},
        "leading_patches": [{"name": n, "type": BLOCKMESH_TYPES[k]} for n, k in leading],
        "patch_names": names,
    }


def _version() -> str:
    try:
        return version("debrisfoam")
    except PackageNotFoundError:  # running from a source tree that is not installed
        return "0+unknown"


def build_context(scene, plan, numerics: Numerics | None = None) -> dict[str, Any]:
    """The render context: everything every template may use, from the scene and its plan.

    `scene` supplies fluid properties and the sampling interval (None: the scene
    defaults); everything else comes from `plan`. Keys (lengths m, times s):

    - generator_version; case: solver, overset, two_d, cell_count, bodies_dir
    - background: a mesh (below) for system/blockMeshDict, with the empty
      `oversetPatch` first when overset and cell zone "background"
    - bodies: per body name, zone_id (1..), subcase ("bodies/<name>"), mesh,
      wall_patch, overset_patch, mass_kg, centre_of_mass_m, moment_of_inertia_kg_m2
      (principal, body axes), orientation (3x3, body -> global), size_m
    - mesh = grid (the BoxGrid), zone, patch_types (blockMesh types), leading_patches
    - patches: [{name, kind}] of the merged mesh in order; kind is one of wall,
      body, atmosphere, outlet, empty, overset and picks each field's boundary condition
    - water_boxes: [{name, min, max}]; bed_friction: None or {darcy_f, layer_m, zone,
      calibration, forchheimer_per_m, box_min, box_max}; gate: None or {forchheimer_per_m,
      bands: [{name, box_min, box_max, release_s}]}; domain: {min, max}
    - gauges: [{name, start, end, n_points}] (vertical lines, bed to top);
      probes: [{name, point}]; column: None or {patch, min, max, centre_of_rotation}
    - time: end_s, write_interval_s, delta_t_s (first step), max_delta_t_s,
      max_courant, max_alpha_courant, sample_interval_s (None = every step)
    - decomposition: {n, n_subdomains}; fluid: water/air rho and nu, sigma, g;
      numerics: `Numerics` as a dict; motion: inner/outer distance; reasons: lines
    - flow_record: None, or (a one-way plan) {name, interval_s, points}: the plan's sample
      grid as points, x outermost, z innermost
    """
    solver = plan.solver
    numerics = numerics or Numerics.for_solver(solver, float(plan.max_courant))
    overset = solver == "overInterDyMFoam"
    if overset and plan.two_d:
        raise InputError("plan.two_d", "a 2D case cannot carry six-DoF debris bodies (overset needs 3D)")
    if overset != bool(plan.bodies):
        raise InputError("plan.solver", f"{solver} with {len(plan.bodies)} debris bodies")

    # scene None: the scene defaults (golden files and tests render plans directly)
    fluids = getattr(scene, "fluids", None) or Fluids()
    outputs = getattr(scene, "outputs", None) or Outputs()
    bg: BoxGrid = plan.background
    if plan.downstream_type not in ("wall", "outlet"):
        raise InputError("plan.downstream_type", f"must be 'wall' or 'outlet', got {plan.downstream_type!r}")
    kinds = dict(BACKGROUND_PATCH_KINDS, downstream=plan.downstream_type)
    if plan.bed_slip:  # a frictionless bed: a wall the flow slips along
        kinds[BACKGROUND_PATCHES["zmin"]] = "slip"
    leading = [(OVERSET_DUMMY_PATCH, "overset")] if overset else []
    background = _mesh_context(bg, kinds, "background" if overset else None, leading)
    patches = [{"name": n, "kind": k} for n, k in leading]
    patches += [{"name": n, "kind": kinds[n]} for n in background["patch_names"]]

    bodies = _bodies_context(plan, patches)
    lo = np.array([bg.planes(a)[0] for a in "xyz"])
    hi = np.array([bg.planes(a)[-1] for a in "xyz"])
    column = _column_context(plan)
    gauges, probes = _sampling_context(plan)
    n = tuple(int(v) for v in plan.decomposition)
    return {
        "generator_version": _version(),
        "case": {"solver": solver, "overset": overset, "two_d": bool(plan.two_d),
                 "cell_count": int(plan.cell_count), "bodies_dir": BODIES_DIR},
        "background": background,
        "bodies": bodies,
        "patches": patches,
        "water_boxes": [{"name": box.name, "min": tuple(float(v) for v in box.min_m),
                         "max": tuple(float(v) for v in box.max_m)} for box in plan.water],
        "bed_friction": _friction_context(plan, lo, hi),
        "gate": _gate_context(plan),
        "turbulence": _turbulence_context(plan),
        "domain": {"min": tuple(lo), "max": tuple(hi)},
        "gauges": gauges,
        "probes": probes,
        "column": column,
        "time": _time_context(plan, outputs),
        "flow_record": _flow_record_context(plan),
        "decomposition": {"n": n, "n_subdomains": int(np.prod(n))},
        "fluid": {"water_rho": fluids.water_density_kg_m3, "water_nu": fluids.water_viscosity_m2_s,
                  "air_rho": fluids.air_density_kg_m3, "air_nu": fluids.air_viscosity_m2_s,
                  "sigma": fluids.surface_tension_N_m, "g": (0.0, 0.0, -fluids.gravity_m_s2),
                  # p_rgh = p - rho g (z - hRef): with hRef at the still-water level downstream
                  # (the wet bed's surface), water and air at rest there both have p_rgh = 0, so
                  # one p_rgh = 0 condition on the open boundaries is hydrostatic for both phases.
                  "h_ref_m": float(plan.still_water_m)},
        "numerics": asdict(numerics),
        # the plan's distances: beyond the domain, so each body mesh moves rigidly (plan.sampling)
        "motion": {"inner_distance_m": plan.motion_distance_m[0], "outer_distance_m": plan.motion_distance_m[1]},
        "reasons": [f"{k}: {v}" for k, v in plan.reasons.items()],
    }


def _bodies_context(plan: ModelPlan, patches: list[dict[str, str]]) -> list[dict[str, Any]]:
    """Each body's entry of the context; its two patches are appended to ``patches``."""
    bodies = []
    for zone_id, body in enumerate(plan.bodies, start=1):
        wall, outer = body.name, f"{body.name}Overset"
        body_kinds = {wall: "body", outer: "overset"}
        mesh = _mesh_context(body.grid, body_kinds, body.name)
        if set(mesh["patch_names"]) != {wall, outer}:
            raise InputError(f"plan.bodies[{zone_id - 1}].grid",
                             f"body mesh patches must be {outer!r} and {wall!r}, got {mesh['patch_names']}")
        patches += [{"name": outer, "kind": "overset"}, {"name": wall, "kind": "body"}]
        bodies.append({
            "name": body.name,
            "zone_id": zone_id,
            "subcase": f"{BODIES_DIR}/{body.name}",
            "mesh": mesh,
            "wall_patch": wall,
            "overset_patch": outer,
            "mass_kg": float(body.mass_kg),
            "centre_of_mass_m": tuple(float(v) for v in body.centre_of_mass_m),
            "moment_of_inertia_kg_m2": tuple(float(v) for v in body.moment_of_inertia_kg_m2),
            "orientation": tuple(tuple(float(v) for v in row) for row in np.asarray(body.orientation, dtype=float)),
            "size_m": tuple(float(v) for v in body.size_m),
            "velocity_m_s": tuple(float(v) for v in body.velocity_m_s),
            "hold_until_s": float(body.hold_until_s),
            "upright": bool(body.upright),
        })
    return bodies


def _column_context(plan: ModelPlan) -> dict[str, Any] | None:
    """The column's patch and box, and the centre of its base (the forces' centre of rotation)."""
    if plan.column_box_m is None:
        return None
    c_lo, c_hi = plan.column_box_m
    base = ((c_lo[0] + c_hi[0]) / 2, (c_lo[1] + c_hi[1]) / 2, c_lo[2])
    return {"patch": COLUMN_PATCH, "min": tuple(c_lo), "max": tuple(c_hi), "centre_of_rotation": base}


def _sampling_context(plan: ModelPlan):
    """The plan's gauge lines and probes as the sampling templates take them."""
    gauges = [{"name": g.name, "start": tuple(g.start_m), "end": tuple(g.end_m), "n_points": int(g.n_points)}
              for g in plan.gauge_lines]
    probes = [{"name": p.name, "point": tuple(p.point_m)} for p in plan.probes]
    return gauges, probes


def _flow_record_context(plan: ModelPlan) -> dict[str, Any] | None:
    """The flow record's sampling (a one-way plan): every point of its grid, z fastest."""
    record = plan.flow_record
    if record is None:
        return None
    points = [(x, y, z) for x in record.x_m for y in record.y_m for z in record.z_m]
    return {"name": record.name, "interval_s": float(record.interval_s), "points": points}


def _time_context(plan: ModelPlan, outputs) -> dict[str, Any]:
    max_co = float(plan.max_courant)
    return {
        "end_s": float(plan.end_time_s),
        "write_interval_s": float(plan.write_interval_s),
        "delta_t_s": float(plan.first_delta_t_s),
        "max_delta_t_s": float(plan.max_delta_t_s),
        "max_courant": max_co,
        "max_alpha_courant": max_co,
        # gauges, forces and probes: every time step when the scene says null
        "sample_interval_s": None if outputs.probe_interval_s is None else float(outputs.probe_interval_s),
    }


def _friction_context(plan: ModelPlan, lo: np.ndarray, hi: np.ndarray) -> dict[str, Any] | None:
    """Bed friction (Darcy f): the plan's quadratic drag on its friction layer next to the bed, a
    Darcy-Forchheimer porosity with only the Forchheimer term, horizontal only, on every cell
    below the layer's top. With a sill (the grid below z = 0) only downstream of the gate: the
    layer's top is above the bed there, and the reservoir's nearly still water needs none."""
    if float(plan.bed_friction_per_m) <= 0:
        return None
    layer = float(plan.friction_layer_m)
    x_min = lo[0] - 1 if lo[2] >= 0 else 0.0
    return {"darcy_f": float(plan.bed_friction_factor), "layer_m": layer, "zone": BED_LAYER_ZONE,
            "calibration": float(plan.bed_friction_calibration), "forchheimer_per_m": float(plan.bed_friction_per_m),
            "box_min": (x_min, lo[1] - 1, lo[2] - 1), "box_max": (hi[0] + 1, hi[1] + 1, max(lo[2], 0.0) + layer)}


def _gate_context(plan: ModelPlan) -> dict[str, Any] | None:
    """A gate opening over a time: its bands (plan.gate_opening), each a cell zone system/fvOptions
    blocks until its release; None when the gate opens at once."""
    if not plan.gate_bands:
        return None
    return {"forchheimer_per_m": BLOCK_F_PER_M,
            "bands": [{"name": b.name, "box_min": tuple(b.min_m), "box_max": tuple(b.max_m), "release_s": b.release_s}
                      for b in plan.gate_bands]}


#: A RANS flow's start: still water and air, nearly free of turbulence (k in m2/s2, omega in 1/s);
#: the bore makes its own.
QUIESCENT_K_M2_S2 = 1.0e-6
QUIESCENT_OMEGA_1_S = 1.0


def _turbulence_context(plan: ModelPlan) -> dict[str, Any] | None:
    """A RANS plan's model, its quiescent start and the bed's sand roughness (the bed patch's
    rough wall function); None for a laminar plan."""
    if plan.turbulence == "laminar":
        return None
    return {"model": plan.turbulence, "k": QUIESCENT_K_M2_S2, "omega": QUIESCENT_OMEGA_1_S,
            "bed_patch": BACKGROUND_PATCHES["zmin"], "bed_roughness_m": float(plan.bed_roughness_m)}


# --------------------------------------------------------------------------- files


def case_files(context: dict[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    """(template, output path relative to the case, extra variables) for every file."""
    overset = context["case"]["overset"]
    files: list[tuple[str, str, dict[str, Any]]] = [
        ("system/blockMeshDict.j2", "system/blockMeshDict", {"mesh": context["background"]}),
        ("system/controlDict.j2", "system/controlDict", {}),
        ("system/fvSchemes.j2", "system/fvSchemes", {}),
        ("system/fvSolution.j2", "system/fvSolution", {}),
        ("system/decomposeParDict.j2", "system/decomposeParDict", {}),
        ("system/setFieldsDict.j2", "system/setFieldsDict", {}),
        ("constant/g.j2", "constant/g", {}),
        ("constant/hRef.j2", "constant/hRef", {}),
        ("constant/transportProperties.j2", "constant/transportProperties", {}),
        ("constant/turbulenceProperties.j2", "constant/turbulenceProperties", {}),
        ("0/alpha.water.j2", "0/alpha.water", {}),
        ("0/U.j2", "0/U", {}),
        ("0/p_rgh.j2", "0/p_rgh", {}),
    ]
    if context["turbulence"]:
        files += [("0/k.j2", "0/k", {}), ("0/omega.j2", "0/omega", {}), ("0/nut.j2", "0/nut", {})]
    if context.get("flow_record"):
        files.append(("system/flowRecord.j2", f"system/{context['flow_record']['name']}", {}))
    if overset or context["bed_friction"] or context["gate"]:
        files.append(("system/topoSetDict.j2", "system/topoSetDict", {}))
    if context["bed_friction"] or context["gate"]:
        files.append(("system/fvOptions.j2", "system/fvOptions", {}))
    if overset:
        files += [
            ("constant/dynamicMeshDict.j2", "constant/dynamicMeshDict", {}),
            ("0/pointDisplacement.j2", "0/pointDisplacement", {}),
            ("0/zoneID.j2", "0/zoneID", {}),
        ]
        for body in context["bodies"]:
            files += [
                ("system/blockMeshDict.j2", f"{body['subcase']}/system/blockMeshDict", {"mesh": body["mesh"]}),
                ("body/system/controlDict.j2", f"{body['subcase']}/system/controlDict", {"body": body}),
            ]
    return files


def render_files(context: dict[str, Any], env: Environment | None = None) -> dict[str, str]:
    """Every OpenFOAM file of the case as text, keyed by path relative to the case."""
    env = env or template_environment()
    out = {}
    for template, path, extra in case_files(context):
        out[path] = env.get_template(template).render(**context, **extra)
    return out


def _is_empty_dir(path: Path) -> bool:
    return not path.exists() or (path.is_dir() and not any(path.iterdir()))


def render_case(scene, plan, out_dir: str | Path, force: bool = False, overrides: Sequence[str] = ()) -> Path:
    """Write the OpenFOAM case for `plan` (from `scene`) into `out_dir`; return its path.

    Refuses a non-empty `out_dir` unless `force` (InputError naming "out_dir"). With
    `force`, a previous debrisfoam case there (it has a plan.json) is removed first so
    that no stale mesh or results survive; other files are overwritten in place.
    `overrides` (the `--set` items that produced `scene`) head scene.yaml.
    """
    column = getattr(scene, "column", None)  # tests render a plan beside a stand-in scene (a dict)
    if column is not None and column.heading_deg != 0.0:
        raise InputError("column.heading_deg", "must be 0 for an OpenFOAM case: the mesh cuts the column as a box "
                         "along the flume's axes (a turned column is for ASCE 7-22's k_s, docs/scene.md)")
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError("out_dir", f"{out} exists and is not a directory")
    if not _is_empty_dir(out):
        if not force:
            raise InputError("out_dir", f"{out} is not empty (use --force to overwrite it)")
        if (out / PLAN_JSON).is_file():
            shutil.rmtree(out)
    context = build_context(scene, plan)
    env = template_environment()
    files = render_files(context, env)
    files[SCENE_YAML] = _scene_yaml(scene, overrides)
    files[PLAN_JSON] = _plan_json(plan)
    steps = foam.mesh_steps(out, plan) + foam.solve_steps(out, plan)
    files["README.md"] = env.get_template("README.md.j2").render(
        **context, commands=[{"name": s.name, "shell": s.shell(), "what": s.what} for s in steps],
        env_exports=foam.ENV_EXPORTS)
    for rel, text in files.items():
        path = out / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, text)
    return out


def _scene_yaml(scene, overrides: Sequence[str] = ()) -> str:
    """The resolved scene as YAML (a plain dict, e.g. in tests, is dumped as it is)."""
    if isinstance(scene, Scene):
        return dump_scene_yaml(scene, list(overrides))
    if isinstance(scene, dict):
        return yaml.safe_dump(dict(scene), sort_keys=False)
    # A caller's mistake: the CLI and the pipeline pass the Scene they loaded.
    raise TypeError(  # internal: no scene reaches it (above)
        f"render_case needs an orchestrator.scene.schema.Scene, got {type(scene).__name__}")


def _plan_json(plan: ModelPlan) -> str:
    text = plan.to_json()
    return text if text.endswith("\n") else text + "\n"
