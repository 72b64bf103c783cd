"""`debrisfoam case SCENE`: render + run + post in one resumable command.

The case folder is the unit of work. Running the command again on the same scene
and overrides resumes where it stopped (rendering and meshing are skipped, the
solver restarts from its latest written time, post-processing is redone). A folder
that holds a *different* case is never overwritten: that is bad input (exit 2).
"""

from __future__ import annotations

import math
import sys
import threading
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any, Sequence

from orchestrator.core.errors import InputError
from orchestrator.case import foam
from orchestrator.case.folder import CaseFolder
from orchestrator.case.render import render_case
from orchestrator.plan.identity import carried_as, same_case, same_flow
from orchestrator.plan.model import ModelPlan
from orchestrator.plan.planner import load_and_plan
from orchestrator.plan.resources import Demand, check_resources
from orchestrator.report.postprocess import post_case
from orchestrator.report.preview import preview_scene
from orchestrator.run import openfoam
from orchestrator.run.runner import run_case
from orchestrator.scene.schema import Scene
from orchestrator.transport.case_transport import TransportSummary, contact_laws, transport_case

#: Post-processing draws with matplotlib's pyplot (and pyvista), which are not thread-safe:
#: cases run in threads of one process (a sweep's local executor) post-process one at a time.
_POST_LOCK = threading.Lock()


def default_case_dir(scene_path: str | Path) -> Path:
    """runs/<scene file stem>, relative to the current directory."""
    return Path("runs") / Path(scene_path).stem


def folder_scene(folder: CaseFolder) -> Scene | None:
    """The scene.yaml of a case folder, loaded; None when it has none or it is no valid scene."""
    if not folder.scene_path.is_file():
        return None
    try:
        return folder.scene()
    except InputError:
        return None


def holds_case(case: Path, scene: Scene) -> bool:
    """Does the folder ``case`` hold this scene's case? Its scene.yaml and ``scene`` compared by
    :func:`orchestrator.plan.identity.same_case` for the case's coupling (plan.json): the answer a
    sweep's member ids give too."""
    folder = CaseFolder(case)
    existing = folder_scene(folder)
    return existing is not None and same_case(existing, scene, folder.debris_coupling())


def _plan_warnings(case: Path) -> list[str]:
    """The planner's warnings recorded in the case's plan.json."""
    plan = CaseFolder(case).model_plan()
    return list(plan.warnings) if plan else []


def prepare_case(scene: Scene, plan: ModelPlan, scene_path: str | Path, out_dir: str | Path,
                 sets: Sequence[str] = (), confirmed: bool = False) -> tuple[Path, bool]:
    """Render the scene into out_dir unless that folder already holds this very case.

    ``scene`` and ``plan``: the scene file ``scene_path`` with ``sets``, loaded and planned once
    by the caller (:func:`orchestrator.plan.planner.load_and_plan`). Returns (case folder,
    rendered now?). Raises InputError when out_dir holds something else, and the resource
    guard's errors when rendering (``confirmed``: see :func:`render_from_file`); a case already
    rendered is resumed without asking again.
    """
    out = Path(out_dir)
    if out.is_dir() and any(out.iterdir()):
        folder = CaseFolder(out)
        try:
            existing = folder.scene() if folder.scene_path.is_file() else None
        except InputError as exc:  # written under rules it does not pass today
            raise InputError("-o/--out", f"{out} holds a case whose scene.yaml today's checks refuse ({exc}), so "
                             "it cannot be resumed; choose another folder, or remove it to start again") from exc
        coupling = folder.debris_coupling()
        if existing is not None and same_case(existing, scene, coupling):
            return out, False
        if existing is not None and coupling == "one-way" and same_flow(existing, scene):
            carried = carried_as(existing, scene)
            _retransport(folder, carried, sets)
            return out, False
        raise InputError(
            "-o/--out",
            f"{out} already holds a different case (its scene.yaml differs from {scene_path} with these "
            "overrides); choose another folder, or remove it to start again",
        )
    render_planned(scene, plan, scene_path, out, list(sets), confirmed=confirmed)
    return out, True


def _retransport(folder: CaseFolder, carried: Scene, sets: Sequence[str]) -> None:
    """A one-way case whose flow is the scene's and whose transport section or contact laws are
    not: write ``carried`` (the folder's scene with the asked-for ones,
    :func:`orchestrator.plan.identity.carried_as`) as its scene.yaml and forget its transport
    record, so that the bodies are carried again through the recorded flow (:func:`carry_debris`)."""
    folder.write_scene(carried, sets)
    run = folder.run_record() or {}
    if run.pop("transport", None) is not None:
        run.pop("transport_wall_s", None)
        folder.write_run_record(run)
    print(f"debrisfoam: {folder.path}: the transport settings or contact laws changed; the bodies are carried "
          "again through its recorded flow", file=sys.stderr, flush=True)


def run_full_case(scene: Scene, plan: ModelPlan, scene_path: str | Path, out_dir: str | Path | None = None,
                  sets: Sequence[str] = (), np: int | None = None, quiet: bool = False,
                  stop_event: threading.Event | None = None, confirmed: bool = False) -> dict[str, Any]:
    """Render (if needed), run (resuming), post-process; returns the final summary.

    ``scene``, ``plan``: see :func:`prepare_case`. stop_event: set it (from another thread) to
    stop the run as Ctrl-C would; the run raises RunInterrupted and resumes when called again.
    confirmed: go ahead over the resource guard's soft limits (:func:`render_from_file`).
    """
    t0 = time.perf_counter()
    out_dir = out_dir or default_case_dir(scene_path)
    case, rendered = prepare_case(scene, plan, scene_path, out_dir, sets, confirmed=confirmed)
    if not quiet:
        print(f"debrisfoam: {'rendered' if rendered else 'resuming'} {case}", flush=True)
    warnings = _plan_warnings(case)  # the case's own plan.json: a resumed case keeps what it was planned with
    for message in warnings:  # before anything runs, on every start
        print(f"debrisfoam: warning: {message}", file=sys.stderr, flush=True)
    run = run_case(case, np=np, quiet=quiet, stop_event=stop_event)
    carry_debris(case, already=run.already_finished, quiet=quiet)
    with _POST_LOCK:
        post = post_case(case)
    summary = final_summary(post.headline)
    summary["results"] = str(post.results_dir)
    summary["report"] = str(post.report) if post.report else None
    summary["warnings"] = warnings
    summary["wall_time_s"] = round(time.perf_counter() - t0, 1)
    summary["solver_wall_s"] = round(run.solver_wall_s, 1)
    return summary


def carry_debris(case: str | Path, already: bool = False, quiet: bool = False) -> TransportSummary | None:
    """A one-way case's transport after its flow run (None for any other case).

    Skipped when the flow run had already finished and run.json records a transport with the
    contact laws the scene's bodies have today: the bodies were carried through this very record
    before. A record of other laws (the shipped law recalibrated, or none recorded) is carried again.
    """
    folder = CaseFolder(case)
    if folder.debris_coupling() != "one-way":
        return None
    done = folder.run_state().transport if already else None
    if done is not None:
        laws = contact_laws(folder.scene())
        if done.get("contact_laws") == laws:
            return None
        if not quiet:
            today = ", ".join(f"{n}: k {v['stiffness_N_m']:.4g} N/m, zeta {v['damping_ratio']:.3g}"
                              for n, v in laws.items())
            print(f"debrisfoam: {case}: its bodies were carried with other contact laws than today's ({today}); "
                  "they are carried again through its recorded flow", flush=True)
    return transport_case(case, say=(lambda _: None) if quiet else (lambda m: print(m, flush=True)))


def _num(value: Any, fmt: str = ".3f") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return format(value, fmt)


def final_summary(headline: dict[str, Any]) -> dict[str, Any]:
    """The figures `make case-1debris` ends with (from post's summary.json), flat for printing."""
    out: dict[str, Any] = {
        "status": headline.get("status"),
        "cells": headline.get("cells"),
        "reached_time_s": headline.get("reached_time_s"),
    }
    impacts = headline.get("impacts") or {}
    first = impacts.get("first") or {}
    if first:
        out["first_impact"] = (f"{first.get('body')} on the {first.get('other')} at t = {_num(first.get('time_s'))} s, "
                               f"{_num(first.get('height_m'), '.2f')} m up")
        out["impact_velocity_m_s"] = first.get("impact_velocity_m_s")
        out["peak_impact_force_N"] = first.get("peak_force_N")
        out["impact_duration_s"] = first.get("duration_s")
        out["impact_impulse_Ns"] = first.get("impulse_Ns")
    else:
        out["first_impact"] = "none: no debris reached the column in the simulated time"
    for pin in impacts.get("pinned") or []:
        out[f"{pin['body']}_pinned"] = (f"held against the {pin['other']} by the flow from t = "
                                        f"{_num(pin.get('time_s'))} s (debris damming: frozen there)")
    for rest in impacts.get("rest_on_bed") or []:
        out[f"{rest['body']}_on_bed"] = (f"kept on the bed from t = {_num(rest.get('time_s'))} s (the flow kept "
                                         "pulling it into the bed: it slides and yaws, but no longer sinks or floats)")
    response = headline.get("column_response") or {}
    if response.get("peak_base_shear_N") is not None:
        out["peak_base_shear_N"] = response["peak_base_shear_N"]
    for gauge, row in (headline.get("gauges") or {}).items():
        if row.get("arrival_s") is not None:
            out[f"{gauge}_arrival_s"] = row["arrival_s"]
    for gauge, errors in ((headline.get("comparisons") or {}).get("arrival_errors_s") or {}).items():
        out[f"{gauge}_arrival_error_s"] = ", ".join(f"{k} {v:+.3f}" for k, v in errors.items())
    return out


def render_from_file(scene_path: str | Path, out_dir: Path, sets: Sequence[str] = (), force: bool = False,
                     mesh: bool = False, confirmed: bool = False) -> dict[str, Any]:
    """The `debrisfoam render` verb: load and plan the scene, check the plan against this
    machine, render, optionally mesh.

    Returns a summary for the CLI: case path, solver, planned cell count and, with
    `mesh`, checkMesh's verdict, cell count and quality figures. Before anything is written:
    InputError over a hard resource limit, LargeRunError over a soft one unless ``confirmed``
    (:mod:`orchestrator.plan.resources`); confirmed, the soft limits join the warnings.
    """
    scene, plan = load_and_plan(scene_path, sets)
    return render_planned(scene, plan, scene_path, out_dir, sets, force=force, mesh=mesh, confirmed=confirmed)


def render_planned(scene: Scene, plan: ModelPlan, scene_path: str | Path, out_dir: Path, sets: Sequence[str] = (),
                   force: bool = False, mesh: bool = False, confirmed: bool = False) -> dict[str, Any]:
    """:func:`render_from_file` of the scene file ``scene_path`` with ``sets``, already loaded
    (``scene``) and planned (``plan``)."""
    large = check_resources(Demand.of_plan(plan), str(scene_path), confirmed=confirmed)
    case = render_case(scene, plan, out_dir, force=force, overrides=sets)
    summary: dict[str, Any] = {"case": str(case), "solver": plan.solver, "planned_cells": int(plan.cell_count),
                               "warnings": list(plan.warnings) + large}
    if scene.outputs.preview:
        try:
            summary["preview"] = str(preview_scene(scene, plan, case / "preview.png"))
        except Exception as exc:  # a picture must never cost the user the case: say so and go on
            summary["preview"] = f"not drawn ({type(exc).__name__}: {exc}); the case is complete"
    if mesh:
        for step in foam.mesh_steps(case, plan):
            openfoam.run_step(step.name, step.argv, case, np=step.np, done=step.done)
        check = openfoam.check_mesh_summary(case / "log.checkMesh")
        summary.update({f"mesh_{k}": v for k, v in asdict(check).items()})
    return summary
