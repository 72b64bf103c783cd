"""The case verbs: ``render`` a scene into an OpenFOAM case, ``preview`` it as a PNG, ``run``
the case, ``post``-process it, or ``case`` (render, run and post in one go); ``split-bodies`` is
one of a case's steps (listed in its README), which ``run`` takes in turn.

Runs are resumable: an interrupted ``run`` or ``case`` exits 128 + the signal (130 for
Ctrl-C) and the same command continues it. Each verb imports its stage when it runs.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from orchestrator.core.errors import InputError
from orchestrator.cli.common import (
    EXIT_OK,
    SCENE_HELP,
    closing_options,
    confirm_large,
    emit,
    missing_feature,
    output_path,
    planned_scene,
    warn,
    writable_folder,
)
from orchestrator.scene.shipped import resolve_scene

__all__ = ["add_case_parsers", "cmd_case", "cmd_post", "cmd_preview", "cmd_render", "cmd_run",
           "cmd_split_bodies"]

def cmd_render(args: argparse.Namespace) -> int:
    out = writable_folder(args.out, "-o/--out")  # only checked: render makes it when the scene is valid
    scene, plan = planned_scene(args.scene, args.set)
    try:
        from orchestrator.pipeline import render_planned
    except ImportError:
        return missing_feature("`render` (scene schema, planner and templates)", 3)
    summary = confirm_large(lambda yes: render_planned(scene, plan, args.scene, out, list(args.set or []),
                                                       force=args.force, mesh=args.mesh, confirmed=yes), args.yes)
    emit({k: v for k, v in summary.items() if args.json or k != "warnings"}, args.json)
    warn(summary["warnings"])
    return EXIT_OK


def cmd_preview(args: argparse.Namespace) -> int:
    try:
        from orchestrator.report.preview import preview_scene_file
    except ImportError:
        return missing_feature("`preview`", 3)
    if Path(args.out).suffix.lower() != ".png":
        raise InputError("-o/--out", f"must name a .png file (the preview is a PNG image), got {args.out}")
    out = output_path(args.out, "-o/--out", args.force, folder=False)  # checked; made once the scene is valid
    warnings = preview_scene_file(args.scene, out, list(args.set or []), warnings=True)
    if args.json:
        emit({"preview": str(out), "warnings": warnings}, True)
    else:
        print(f"preview written to {out}")
    warn(warnings)
    return EXIT_OK


def cmd_run(args: argparse.Namespace) -> int:
    from orchestrator.case.folder import CaseFolder
    from orchestrator.pipeline import carry_debris
    from orchestrator.plan.resources import Demand, check_resources
    from orchestrator.run.monitor import DivergenceLimits
    from orchestrator.run.runner import RunInterrupted, run_case

    if args.stall_limit is not None and not args.stall_limit > 0:
        raise InputError("--stall-limit", f"must be > 0 seconds, got {args.stall_limit}")
    if args.np is not None and args.np < 1:
        raise InputError("--np", f"must be a whole number >= 1 of MPI ranks, got {args.np}")
    folder = CaseFolder(args.case_dir)
    if not folder.path.is_dir():
        raise InputError("case_dir", "no such folder: render a case into it first (debrisfoam render SCENE -o DIR)",
                         str(args.case_dir))
    if not folder.is_case():
        raise InputError("case_dir", "not a debrisfoam case: it has neither plan.json nor system/controlDict "
                                     "(render one with `debrisfoam render SCENE -o DIR`)", str(args.case_dir))
    writable_folder(folder.path, "case_dir")
    plan = folder.model_plan()  # unreadable: run_case says why
    if plan and not folder.run_state().finished:
        ranks = args.np or plan.cores  # the planner's solver time, spread over the ranks it runs on
        demand = Demand(int(plan.cell_count), plan.solver, ranks, float(plan.estimated_wall_time_s) * plan.cores / ranks)
        large = confirm_large(lambda yes: check_resources(demand, str(folder.plan_path), confirmed=yes), args.yes)
        warn(large)

    try:
        limits = DivergenceLimits(stall_s=args.stall_limit) if args.stall_limit is not None else None
        summary = run_case(args.case_dir, np=args.np, quiet=args.quiet, reconstruct=args.reconstruct, limits=limits)
        carry_debris(args.case_dir, already=summary.already_finished, quiet=args.quiet or args.json)
    except RunInterrupted as exc:  # resumable: say how, exit 128 + signal (130 for Ctrl-C)
        if args.debug:
            raise
        print(f"debrisfoam: {exc}", file=sys.stderr)
        return exc.exit_code
    result = summary.to_dict()
    if not args.json:
        result = {k: result[k] for k in ("case", "status", "reached_time_s", "time_steps", "segments", "contacts",
                                         "solver_wall_s", "overhead_fraction", "run_json")}
        if summary.already_finished:
            result["status"] = "finished (already; nothing to do)"
    emit(result, args.json)
    return EXIT_OK


def cmd_post(args: argparse.Namespace) -> int:
    from orchestrator.case.folder import CaseFolder
    from orchestrator.report.postprocess import post_case

    folder = CaseFolder(args.case_dir)
    if folder.path.is_dir() and folder.is_case():
        writable_folder(folder.results_dir, "case_dir")
    summary = post_case(args.case_dir, comparisons=not args.tables_only, snapshot=not args.no_snapshot,
                        arrival_threshold_m=args.arrival_threshold)
    if args.json:
        emit(summary.to_dict(), True)
        return EXIT_OK
    emit(_post_lines(summary), False)
    return EXIT_OK


def _post_lines(summary) -> dict[str, Any]:
    """The headline of a post-processed run (a PostSummary) as the lines `post` prints without --json."""
    h = summary.headline
    result: dict[str, Any] = {"results": str(summary.results_dir)}
    if summary.report:
        result["report"] = str(summary.report)
    reached, end = h.get("reached_time_s"), h.get("end_time_s")
    result["status"] = h["status"] if h.get("complete") else f"{h['status']} (post-processed up to t = {reached} s of {end} s)"
    wall = (h.get("wall_time_s") or {}).get("total_s")
    result["cells, wall time"] = f"{h.get('cells')}, {wall} s" if wall is not None else f"{h.get('cells')}, unknown"
    errors = (h.get("comparisons") or {}).get("arrival_errors_s", {})
    for gauge, g in (h.get("gauges") or {}).items():
        if g.get("arrival_s") is None:
            continue
        text = f"{g['arrival_s']:.3f} s"
        errs = ", ".join(f"{ref} {err:+.3f} s" for ref, err in errors.get(gauge, {}).items()
                         if ref.startswith(("Chanson", "study")))
        result[f"arrival {gauge} (x = {g['x_m']:g} m)"] = f"{text}; error vs {errs}" if errs else text
    first = (h.get("impacts") or {}).get("first")
    if first:
        result["first impact"] = (f"t = {first['time_s']:.4f} s, {first['body']} on {first['other']} at "
                                  f"{first['impact_velocity_m_s']:.3f} m/s, peak {first['peak_force_N']:.4g} N, "
                                  f"{1e3 * first['duration_s']:.3g} ms, {first['impulse_Ns']:.3g} N s")
    result["impacts"] = (h.get("impacts") or {}).get("count", 0)
    if h.get("hydro_force"):
        result["peak hydrodynamic force"] = f"{h['hydro_force']['peak_x_N']:.4g} N"
    if h.get("column_response"):
        result["peak base shear"] = f"{h['column_response']['peak_base_shear_N']:.4g} N"
    if summary.missing:
        result["missing"] = f"{len(summary.missing)} item(s), listed in summary.json and the report"
    return result


def cmd_case(args: argparse.Namespace) -> int:
    if args.out is not None:
        writable_folder(args.out, "-o/--out")  # only checked, before anything is computed (as render)
    scene, plan = planned_scene(args.scene, args.set)
    from orchestrator.pipeline import run_full_case
    from orchestrator.run.runner import RunInterrupted

    try:
        summary = confirm_large(lambda yes: run_full_case(scene, plan, args.scene, args.out, list(args.set or []),
                                                          np=args.np, quiet=args.quiet, confirmed=yes), args.yes)
    except RunInterrupted as exc:  # resumable: the same command continues the run
        if args.debug:
            raise
        print(f"debrisfoam: {exc} (or run the same `debrisfoam case` command again)", file=sys.stderr)
        return exc.exit_code
    if not args.json:
        print("\n== summary ==")
    emit(summary, args.json)
    return EXIT_OK


def cmd_split_bodies(args: argparse.Namespace) -> int:
    from orchestrator.case import split_bodies

    case = Path(args.case_dir)
    if args.ranks < 2:
        raise InputError("--ranks", f"a split needs 2 or more ranks, got {args.ranks}")
    if not (case / "0" / "cellDist").is_file():
        raise InputError("case_dir", "has no 0/cellDist: run `decomposePar -cellDist -dry-run` in it first",
                         str(case))
    counts = split_bodies.split(case, args.ranks)
    emit({"case": str(case), **{f"body zone {z}: cells per rank": v for z, v in counts.items()},
          "written": f"{split_bodies.TABLE}, {split_bodies.DICT}"}, args.json)
    return EXIT_OK


def add_case_parsers(verbs) -> None:
    """The ``render``, ``preview``, ``run``, ``split-bodies``, ``post`` and ``case`` verbs, on the top
    parser's ``verbs``."""
    p = verbs.add_parser("render", help="render an OpenFOAM case from a scene YAML")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP)
    p.add_argument("-o", "--out", required=True, help="case folder to write (new or empty, or --force)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key, value as YAML (repeatable), e.g. mesh.cell_size_m=0.03")
    p.add_argument("--force", action="store_true", help="overwrite a non-empty output folder")
    p.add_argument("--mesh", action="store_true", help="also build the mesh and print checkMesh's verdict")
    closing_options(p, cmd_render, yes=True)

    p = verbs.add_parser("preview", help="draw the scene (flume, column, debris, gauges) to a PNG")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP)
    p.add_argument("-o", "--out", required=True, help="the .png file to write")
    p.add_argument("--force", action="store_true", help="overwrite an existing file")
    p.add_argument("--json", action="store_true", help="print JSON (the file and the planner's warnings)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key, value as YAML (repeatable), e.g. mesh.cell_size_m=0.03")
    p.set_defaults(func=cmd_preview)

    p = verbs.add_parser("run", help="run a rendered case (resumable: run it again to resume)")
    p.add_argument("case_dir", help="a rendered case folder (debrisfoam render)")
    p.add_argument("--np", type=int, default=None, help="MPI ranks (default: the plan's decomposition)")
    p.add_argument("--quiet", action="store_true", help="no progress bar or messages (CI, sweeps)")
    p.add_argument("--reconstruct", choices=["latest", "all", "none"], default="latest",
                   help="written times gathered by reconstructPar at the end (default: latest)")
    p.add_argument("--stall-limit", type=float, default=None, metavar="S",
                   help="stop the run as stalled after S wall seconds without solver output (default: the "
                        "scene's run.stall_limit_s, else 600 s)")
    closing_options(p, cmd_run, yes=True)

    p = verbs.add_parser("split-bodies", help="a case step with several body meshes on several ranks: move half "
                                              "of each body mesh that decomposePar -cellDist keeps on one rank to "
                                              "the next (`run` does it between its decomposePar steps)")
    p.add_argument("case_dir", help="a rendered case folder, after `decomposePar -cellDist -dry-run`")
    p.add_argument("--ranks", type=int, required=True, help="the number of subdomains (2 or more)")
    p.set_defaults(func=cmd_split_bodies)
    p.add_argument("--json", action="store_true", help="print JSON")

    p = verbs.add_parser("post", help="post-process a run (finished or not) into DIR/results/: tables, "
                                      "comparisons, plots, report.md")
    p.add_argument("case_dir", help="a rendered case folder (debrisfoam render)")
    p.add_argument("--tables-only", action="store_true", help="only the tables and summary.json (no comparisons, "
                                                              "plots or report)")
    p.add_argument("--no-snapshot", action="store_true", help="skip the pyvista 3D snapshot")
    p.add_argument("--arrival-threshold", type=float, default=None, metavar="M",
                   help="rise above the initial level (m) that marks the bore's arrival (default 2 %% of h0)")
    closing_options(p, cmd_post)

    p = verbs.add_parser("case", help="render + run + post in one go (run it again to resume)")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP)
    p.add_argument("-o", "--out", default=None, help="case folder (default: runs/<the scene file's name without .yaml>, e.g. runs/1debris)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key, value as YAML (repeatable), e.g. mesh.cell_size_m=0.03")
    p.add_argument("--np", type=int, default=None, help="MPI ranks (default: the scene's run.cores)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    closing_options(p, cmd_case, yes=True)
