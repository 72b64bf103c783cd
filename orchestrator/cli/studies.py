"""The study verbs: ``sweep`` (a parameter sweep, resumable), ``ensemble`` (one recorded flow,
many perturbed debris starts) and ``report`` (across runs: ``speed-error``, ``case``, ``layouts``,
``stability``, ``approach``, ``forcing-variants``...).

``sweep --dry-run`` prints the members, their cell counts and estimated wall times and runs
nothing. A sweep with failed members exits 1 and lists them; an interrupted one exits
128 + the signal, as ``run`` does. Each verb imports its stage when it runs.
"""

from __future__ import annotations

import argparse
import math
import json
import sys
from pathlib import Path
from typing import Any

from orchestrator.core.errors import InputError
from orchestrator.cli.common import (
    EXIT_FAILURE,
    EXIT_OK,
    FOLDER_FORCE_HELP,
    SCENE_HELP,
    ArgParser,
    Flags,
    closing_options,
    confirm_large,
    emit,
    output_path,
    plan_scene,
    pool_options,
    study_folder,
    warn,
    writable_folder,
)
from orchestrator.scene.shipped import resolve_scene, resolve_sweep

__all__ = [
    "add_study_parsers",
    "cmd_ensemble",
    "cmd_report_approach",
    "cmd_report_case",
    "cmd_report_coupling",
    "cmd_report_flow_pair",
    "cmd_report_forcing_variants",
    "cmd_report_layouts",
    "cmd_report_speed_error",
    "cmd_report_spreading",
    "cmd_report_stability",
    "cmd_sweep",
]


def _duration(seconds: float | None) -> str:
    if seconds is None:
        return "-"
    if seconds < 10:
        return f"{seconds:.1f} s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def _print_dry_run(plan: dict[str, Any], out=sys.stdout) -> None:
    params = plan["parameters"]
    out.write(f"sweep {plan['sweep']} ({plan['sweep_file']}): {len(plan['members'])} member(s), mode {plan['mode']}; "
              f"output {plan['out_dir']}\n")
    head = ["#", "id", *params, "solver", "cores", "cells", "est. wall", "state"]
    rows = []
    for m in plan["members"]:
        values = [json.dumps(m["params"].get(p)) if isinstance(m["params"].get(p), (list, dict))
                  else str(m["params"].get(p)) for p in params]
        rows.append([str(m["member"]), m["id"], *values, m["solver"] + (" 2D" if m["two_d"] else ""),
                     str(m["cores"]), f"{m['cells']:,}", _duration(m["estimated_wall_time_s"]), m["state"]])
    widths = [max(len(r[i]) for r in [head, *rows]) for i in range(len(head))]
    for r in [head, *rows]:
        out.write("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() + "\n")
    sweep_wall = plan["estimated_sweep_wall_time_s"]
    on = f"{plan['executor']}, {plan['workers']} member(s) at a time" if sweep_wall is not None else plan["executor"]
    out.write(f"total: {plan['total_cells']:,} cells; estimated solver time of the members still to run "
              f"{_duration(plan['estimated_wall_time_s'])}"
              + (f", about {_duration(sweep_wall)} on {on}" if sweep_wall is not None else "") + "\n")
    out.write(f"({plan['note']})\n")


def _sweep_resources(sweep, scheduler: str | None, confirmed: bool) -> list[str]:
    """Every member's plan against this machine (the resource guard), unless the members run on
    another cluster (``--scheduler``): the soft limits' warnings, each naming its member."""
    from orchestrator.plan.resources import Demand, LargeRunError, check_resources

    if scheduler:
        return []
    large = []
    for m in sweep.members:
        where = f"member {m.index} ({', '.join(m.axis_overrides) or 'the base scene'})"
        demand = Demand(int(m.plan.cell_count), m.plan.solver, sweep.member_cores(m), m.estimated_wall_time_s)
        try:
            large += [f"{where}: {w}" for w in check_resources(demand, str(sweep.path), confirmed=True)]
        except InputError as err:
            raise InputError(err.field, f"{where}: {err.rule}", str(sweep.path)) from None
    if large and not confirmed:
        raise LargeRunError(large, str(sweep.path))
    return large


def cmd_sweep(args: argparse.Namespace) -> int:
    from orchestrator.studies.sweep.spec import default_sweep_dir, load_sweep

    sweep = load_sweep(args.sweep)  # every member planned: bad input, or an impossible mesh, is refused here
    if args.dry_run:
        from orchestrator.studies.sweep.run import dry_run

        warn(_sweep_resources(sweep, args.scheduler, confirmed=True))  # a dry run runs nothing: warnings only
        plan = dry_run(sweep, args.out, executor=args.executor, scheduler=args.scheduler, workers=args.workers)
        if args.json:
            emit(plan, True)
        else:
            _print_dry_run(plan)
        for m in plan["members"]:
            warn(m["warnings"], f"member {m['member']} ({m['id']}): ")
        return EXIT_OK
    progress_stream = sys.stderr if args.json else sys.stdout

    def progress(line: str) -> None:
        print(f"debrisfoam: {line}", file=progress_stream, flush=True)

    warn(confirm_large(lambda yes: _sweep_resources(sweep, args.scheduler, yes), args.yes))
    writable_folder(args.out if args.out is not None else default_sweep_dir(sweep), "-o/--out")
    from orchestrator.studies.sweep.run import run_sweep

    result = run_sweep(sweep, args.out, executor=args.executor, scheduler=args.scheduler, workers=args.workers,
                       retry_failed=args.retry_failed, progress=progress)
    if args.json:
        emit(result.to_dict(), True)
    if result.interrupted and result.unfinished:
        print(f"debrisfoam: sweep interrupted; {len(result.unfinished)} member(s) not finished: run the same command "
              "again to resume", file=sys.stderr)
        return 128 + (result.signum or 2)  # 130 for Ctrl-C, 143 for SIGTERM, as `debrisfoam run`
    if result.failed:
        _print_failures(result)
        return EXIT_FAILURE
    if result.unfinished:  # e.g. a member not started because the sweep was stopped
        print(f"debrisfoam: error: {len(result.unfinished)} member(s) did not finish: run the same command again",
              file=sys.stderr)
        return EXIT_FAILURE
    return EXIT_OK


def _print_failures(result) -> None:
    """The failed members of a sweep (a SweepResult) on stderr: each one's error and case folder."""
    lines = [f"debrisfoam: error: {len(result.failed)} of {len(result.rows)} sweep member(s) failed "
             f"(store {result.store}):"]
    for row in result.failures():
        error = (row.get("error") or "no error recorded").replace("\n", "\n      ")
        lines.append(f"  member {row['member']} {row['member_id']} ({row['overrides'] or 'base scene'}): {error}")
        lines.append(f"    case: {row['case_dir']}")
    lines.append("  (fix the cause, then run again with --retry-failed; finished members are skipped)")
    print("\n".join(lines), file=sys.stderr)


def _ensemble_out(path: str, force: bool) -> Path:
    """The ensemble's folder: new, or holding only its flow/ (reused), or anything with --force."""
    return study_folder(path, force, "flow", "ensemble")


def _study_fit(args: argparse.Namespace, column_height_m: float | None = None) -> bool | float | str:
    """--no-study-fit: False; --study-fit-height M: M (> 0 m, at most the column's height) or
    "contact"; else True."""
    if args.study_fit_height is None:
        return not args.no_study_fit
    if args.no_study_fit:
        raise InputError("--study-fit-height", "has no fit to load with --no-study-fit")
    if args.study_fit_height == "contact":
        return "contact"
    try:
        height = float(args.study_fit_height)
    except ValueError:
        height = math.nan
    if not height > 0:
        raise InputError("--study-fit-height", f"must be a height above the bed > 0 m or 'contact', got "
                         f"{args.study_fit_height!r}")
    if column_height_m is not None and height > column_height_m:
        raise InputError("--study-fit-height", f"{height:g} m is above the column's top: the fit loads the column, "
                         f"so it must be at most its height, column.height_m = {column_height_m:g} m")
    return height


def cmd_ensemble(args: argparse.Namespace) -> int:
    if args.n <= 0:
        raise InputError("-n", f"must be a whole number > 0 of realisations, got {args.n}")
    if args.workers is not None and args.workers <= 0:
        raise InputError("--workers", f"must be > 0, got {args.workers}")
    if args.batch_size is not None and args.batch_size <= 0:
        raise InputError("--batch-size", f"must be a whole number > 0, got {args.batch_size}")
    out = _ensemble_out(args.out, args.force)
    plan_scene(args.scene, args.set)
    from orchestrator.cli.design import confirm_realisations
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.studies.ensemble import DEFAULT_BATCH_SIZE, Perturbation, ensemble

    scene = load_scene(args.scene, list(args.set or []))
    study_fit = _study_fit(args, scene.column.height_m if scene.column is not None else None)
    confirm_realisations([(scene, args.n)], args.workers, args.yes, args.scene,
                         fit_strikes=bool(study_fit) and scene.column is not None)

    with Flags(position_sigma_fraction="--position-sigma", yaw_sigma_deg="--yaw-sigma"):
        perturbation = Perturbation(**{k: v for k, v in (("position_sigma_fraction", args.position_sigma),
                                                          ("yaw_sigma_deg", args.yaw_sigma)) if v is not None})
    bar = []

    def progress(done: int, total: int) -> None:
        if args.json:
            return
        if not bar:  # made at the first completion: the local pool has forked its workers by then
            from tqdm import tqdm

            bar.append(tqdm(total=total, desc="realisations", unit="run", file=sys.stderr))
        bar[0].update(done - bar[0].n)
        if done == total:
            bar[0].close()

    say = (lambda _: None) if args.json else (lambda m: print(m, flush=True))
    try:
        result = confirm_large(lambda yes: ensemble(
            args.scene, out, args.n, seed=args.seed, executor=args.executor, sets=list(args.set or []),
            workers=args.workers, perturbation=perturbation, progress=progress, quiet=args.json, say=say,
            confirmed=yes, batch_size=args.batch_size or DEFAULT_BATCH_SIZE, study_fit=study_fit),
            args.yes)
    finally:
        if bar:
            bar[0].close()
    if args.json:
        emit(result.headline(), True)
        return EXIT_OK
    head = result.headline()
    lines = {"realisations": head["realisations"], "impact_probability": head["impact_probability"]}
    for key in ("impact_velocity_m_s", "peak_force_N"):
        stats = head[key]
        lines[key] = "-" if stats["mean"] is None else (
            f"{stats['mean']:.4g}" + (f" +- {stats['std']:.3g}" if stats["std"] is not None else ""))
    lines["wall_time_s"] = head["wall_time_s"]
    lines.update({name: str(path) for name, path in result.files.items() if name in ("table", "summary", "report")})
    emit(lines, False)
    return EXIT_OK


def cmd_report_speed_error(args: argparse.Namespace) -> int:
    from orchestrator.studies.speed_error import speed_error
    from orchestrator.studies.speed_error_report import markdown, write_report

    extrapolate = args.extrapolate_to if args.extrapolate_to and args.extrapolate_to > 0 else None
    study = speed_error(args.sweep_dir, list(args.baseline or []), reference=args.reference, time=args.time,
                        extrapolate_to_m=extrapolate)
    if args.out:
        output_path(args.out, "-o/--out", args.force, folder=True)
    files = write_report(study, args.out)
    if args.json:
        emit(study.headline(), True)
        return EXIT_OK
    print(markdown(study))
    for kind, path in files.items():
        print(f"debrisfoam: {kind}: {path}")
    return EXIT_OK


def cmd_report_case(args: argparse.Namespace) -> int:
    from orchestrator.report.case_report import write_case_report

    if not (Path(args.case_dir) / "results" / "summary.json").is_file():
        raise InputError("case_dir", f"no results/summary.json: run `debrisfoam post {args.case_dir}` first",
                         str(args.case_dir))
    path = write_case_report(args.case_dir, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({"report": str(path)}, args.json)
    return EXIT_OK


def cmd_report_layouts(args: argparse.Namespace) -> int:
    from orchestrator.report.layouts import write_layouts_report

    out = output_path(args.out, "-o/--out", args.force, folder=True)
    files = write_layouts_report(args.runs, out)
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_spreading(args: argparse.Namespace) -> int:
    from orchestrator.studies.spreading import spreading_study

    out = output_path(args.out, "-o/--out", args.force, folder=True)
    files = spreading_study(args.ensembles, out)
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_flow_pair(args: argparse.Namespace) -> int:
    from orchestrator.report.flow_pair import read_flow_pair, write_flow_pair_report

    pair = read_flow_pair(args.first, args.second)
    files = write_flow_pair_report(pair, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_coupling(args: argparse.Namespace) -> int:
    from orchestrator.report.coupling import (compare_coupling, drive_runs, one_way_record, scan_runs,
                                              write_coupling_report)

    comparison = compare_coupling(args.one_way, args.two_way, allow_stopped=args.allow_stopped)
    if args.drag_scan:
        flow = one_way_record(comparison)
        scan_runs(comparison, flow=flow)
        drive_runs(comparison, flow=flow)
    files = write_coupling_report(comparison, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_scale(args: argparse.Namespace) -> int:
    from orchestrator.studies.froude_scale import compare_scales, write_scale_report

    comparison = compare_scales(args.lab, args.prototype)
    files = write_scale_report(comparison, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({"within_target": comparison.within_target(), **{kind: str(path) for kind, path in files.items()}}, args.json)
    return EXIT_OK


def cmd_report_bore(args: argparse.Namespace) -> int:
    from orchestrator.studies.bore_check import write_bore_report

    files = write_bore_report(args.sweep_dir, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_flume(args: argparse.Namespace) -> int:
    from orchestrator.studies.flume_report import write_flume_report

    files = write_flume_report(args.sweep_dir, output_path(args.out, "-o/--out", args.force, folder=True))
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_approach(args: argparse.Namespace) -> int:
    from orchestrator.studies.approach_report import COUPLED_RUNS, write_approach_report

    if not (Path(args.case_dir) / "results" / "flow_record.npz").is_file():
        raise InputError("case_dir", "no results/flow_record.npz: not a one-way run (run `make case-1debris` first)",
                         str(args.case_dir))
    out = output_path(args.out, "-o/--out", args.force, folder=True)
    say = (lambda _: None) if args.json else (lambda m: print(f"debrisfoam: {m}", file=sys.stderr, flush=True))
    files = write_approach_report(args.case_dir, args.runs, out, say=say,
                                  coupled=COUPLED_RUNS if args.coupled is None else tuple(args.coupled))
    emit({kind: str(path) for kind, path in files.items()}, args.json)
    return EXIT_OK


def cmd_report_forcing_variants(args: argparse.Namespace) -> int:
    from orchestrator.core.files import write_text_atomic
    from orchestrator.studies.forcing_variants import forcing_variants

    out = output_path(args.out, "-o/--out", args.force, folder=False)
    say = (lambda _: None) if args.json else (lambda m: print(f"debrisfoam: {m}", file=sys.stderr, flush=True))
    text = forcing_variants(args.case_dir, say=say)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_text_atomic(out, text)
    emit({"report": str(out)}, args.json)
    return EXIT_OK


def cmd_report_stability(args: argparse.Namespace) -> int:
    from orchestrator.studies.stability import markdown, stability_table

    table = stability_table(args.sweep_dir)
    text = markdown(table)
    if args.out:
        out = output_path(args.out, "-o/--out", args.force, folder=False)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text)
    if args.json:
        emit({"members": table.to_dict(orient="records")}, True)
        return EXIT_OK
    print(text, end="")
    if args.out:
        print(f"debrisfoam: stability table: {args.out}")
    insane = table[(table["outcome"] == "finished") & (table["sane"] == False)]  # noqa: E712 (pandas)
    unexplained = table[~table["outcome"].isin(["finished", "diverged", "stalled", "contact"])]
    for r in insane.itertuples():
        print(f"debrisfoam: {r.scene}: finished but failed: {'; '.join(r.failed_checks)}", file=sys.stderr)
    for r in unexplained.itertuples():
        print(f"debrisfoam: {r.scene}: {r.outcome}: {r.diagnosis or 'no diagnosis'}", file=sys.stderr)
    return EXIT_OK


def add_study_parsers(verbs) -> None:
    """The ``sweep`` and ``report`` verbs, on the top parser's ``verbs``."""
    p = verbs.add_parser("sweep", help="run a parameter sweep (a base scene and axes; see docs/sweeps.md); "
                                       "run it again to resume")
    p.add_argument("sweep", type=resolve_sweep, help="sweep YAML, or a shipped sweep by name (e.g. tiny-mesh-study; "
                                                     "`debrisfoam scenes` lists them)")
    p.add_argument("-o", "--out", default=None, help="sweep folder (default: runs/sweeps/<sweep name>)")
    p.add_argument("--executor", choices=["local", "dask"], default=None,
                   help="local: a thread pool here; dask: a Dask LocalCluster, or --scheduler's cluster "
                        "(default: the sweep file's, else local)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="address of a running Dask scheduler (tcp://host:8786); implies --executor dask")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="members at once (local, LocalCluster); default: cores // cores per member")
    p.add_argument("--dry-run", action="store_true", help="list the members, cell counts and estimated wall times; "
                                                          "run nothing")
    p.add_argument("--retry-failed", action="store_true", help="run failed members again (they resume)")
    closing_options(p, cmd_sweep, yes=True)

    p = verbs.add_parser("ensemble", help="one one-way flow, then N realisations of the debris from perturbed "
                                          "starts carried through it: impact probability and load statistics "
                                          "beside the study's (docs/ensembles.md)")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP + "; it must plan one-way (run.debris_coupling auto "
                                                                  "or one-way)")
    p.add_argument("-n", type=int, required=True, metavar="N", help="number of realisations")
    p.add_argument("-o", "--out", required=True, metavar="DIR",
                   help="ensemble folder: the flow case in DIR/flow (reused when finished), ensemble.csv, "
                        "ensemble.json, tracks.csv, report.md")
    p.add_argument("--seed", type=int, default=0, help="seed of the starts (realisation r draws from (seed, r))")
    pool_options(p, workers="realisations at once (default: this machine's cores)",
                 batch_size="at most B realisations stepped together in one model (default 128; fewer when the "
                            "workers would not each get a batch; 1: one model each)")
    p.add_argument("--no-study-fit", action="store_true",
                   help="leave out the study's fit of each first strike (about 0.27 s of CPU a strike): for "
                        "design-scale ensembles; the like-for-like comparison then has no pulse rows")
    p.add_argument("--study-fit-height", default=None, metavar="M",
                   help="load the study's fit at M above the bed, or at each strike's contact point ('contact'), "
                        "instead of the water level at the face the flow gives at each strike (the study's own "
                        "load heights: 0.16-0.50 m, mean 0.40)")
    p.add_argument("--position-sigma", type=float, default=None, metavar="FRACTION",
                   help="standard deviation of the start's x and y offsets over the body's length (default 0.25)")
    p.add_argument("--yaw-sigma", type=float, default=None, metavar="DEG",
                   help="standard deviation of the start's yaw offset (default 12)")
    closing_options(p, cmd_ensemble, overrides="scene override (repeatable)",
                    force="replace an ensemble already in DIR (its flow is reused)", yes=True,
                    json="print JSON (no progress)")

    rp = verbs.add_parser("report", help="results pages across runs: case (one run beside the study), layouts "
                                         "(debris layouts side by side), spreading (tracks against measured "
                                         "spreading), coupling (one-way against two-way), "
                                         "speed-error (a sweep's cost against its errors), scale (a scene and its "
                                         "Froude-scaled twin), stability (a sweep's "
                                         "runs checked), bore (a sweep's bores against Stoker's), approach "
                                         "(the strike speed against the flow record near the column), "
                                         "forcing-variants (the one-way forcing's variants), flow-pair (an "
                                         "ensemble's Table 2 test with the flow's own uncertainty)")
    rp_verbs = rp.add_subparsers(dest="report_verb", required=True, parser_class=ArgParser)
    p = rp_verbs.add_parser("speed-error", help="wall time against error for every member of a sweep (and of "
                                                "baseline sweeps): table and Pareto plot in SWEEP_DIR/report/")
    p.add_argument("sweep_dir", help="a sweep folder (runs/sweeps/<name>); its finest member is the reference")
    p.add_argument("--baseline", action="append", metavar="SWEEP_DIR",
                   help="another sweep folder whose members join the table, e.g. the hand-made set-up "
                        "(repeatable)")
    p.add_argument("-o", "--out", default=None, help="output folder (default: SWEEP_DIR/report)")
    p.add_argument("--force", action="store_true", help="overwrite a folder that holds files already")
    p.add_argument("--reference", default=None, metavar="MEMBER_ID",
                   help="member to measure the others against (default: the finest finished member)")
    p.add_argument("--time", choices=["cpu", "solver", "wall"], default="cpu",
                   help="time of the plot and the speed-ups: the solver's CPU time (default; its wall time on an "
                        "idle machine, without other jobs' turns on a shared one), the solver's wall time, or "
                        "the member's whole wall time")
    p.add_argument("--extrapolate-to", type=float, default=0.015, metavar="M",
                   help="extrapolate both set-ups to this cell size (default 0.015, the study's; 0: none)")
    closing_options(p, cmd_report_speed_error)
    p = rp_verbs.add_parser("case", help="one post-processed run beside the study's figures: a results page "
                                         "with its plots (make results-1debris)")
    p.add_argument("case_dir", help="a run folder with results/ (debrisfoam post has run)")
    closing_options(p, cmd_report_case, out="output folder (report.md, plots, summary.json)", force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("layouts", help="debris layouts of one scene side by side: gauges and column force "
                                           "overlaid, tracks in plan view, strikes, body-body contacts "
                                           "(make results-layouts)")
    p.add_argument("runs", nargs="+", metavar="RUN",
                   help="post-processed case folders, or sweep folders (their members in member order)")
    closing_options(p, cmd_report_layouts, out="output folder (report.md, tables, plots)", force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("spreading", help="finished ensembles' tracks against measured debris spreading "
                                              "(Goseberg et al. 2016) and the ASCE 7-22 6.11.5.1 envelopes: "
                                              "angles, lateral spread, plots (make spreading)")
    p.add_argument("ensembles", nargs="+", metavar="ENSEMBLE_DIR",
                   help="folders written by debrisfoam ensemble (ensemble.csv, tracks.csv, ensemble.json, flow/)")
    closing_options(p, cmd_report_spreading, out="output folder (report.md, spreading.csv, summary.json, plots)",
                    force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("flow-pair", help="one ensemble through two meshes' flows: the study comparison with "
                                              "the flow's own uncertainty (make ensemble-flow-pair)")
    p.add_argument("first", metavar="FIRST", help="the ensemble folder compared (debrisfoam ensemble)")
    p.add_argument("second", metavar="SECOND", help="the same starts through another mesh's flow")
    closing_options(p, cmd_report_flow_pair, out="output folder (report.md, summary.json)", force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("coupling", help="one scene run one-way and two-way on the same mesh, side by side: "
                                             "the tracks' difference until the first strike, the strikes, the "
                                             "cost (make compare-coupling)")
    p.add_argument("one_way", metavar="ONE_WAY", help="the one-way run's folder (post-processed)")
    p.add_argument("two_way", metavar="TWO_WAY", help="the two-way run's folder (post-processed)")
    p.add_argument("--drag-scan", action="store_true",
                   help="also carry the bodies through the one-way record at several drag coefficients and measure "
                        "each against the two-way track (seconds each), and set the fluid force the two-way solver "
                        "measures on each body afloat beside the one-way forcing on the same track (drive.csv)")
    p.add_argument("--allow-stopped", action="store_true",
                   help="compare a run that stopped before its end (interrupted, diverged, a contact it could not "
                        "follow; post-processed as far as it got) up to where it stopped; the page says so")
    closing_options(p, cmd_report_coupling, out="output folder (report.md, tables, figure)", force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("scale", help="a scene and its Froude-scaled twin side by side: arrivals, gauges, "
                                          "the first strike, forces, each lab figure scaled (make prototype-1debris)")
    p.add_argument("lab", metavar="LAB", help="the laboratory-scale run's folder (post-processed)")
    p.add_argument("prototype", metavar="PROTOTYPE", help="the same scene's run at another scale (post-processed)")
    closing_options(p, cmd_report_scale, out="output folder (report.md, comparison.csv, gauges.png)",
                    force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("stability", help="for every member of a sweep: finished with sane physics (water "
                                              "conserved, no body inside a wall, finite forces) or stopped with "
                                              "a diagnosis (the table of docs/stability.md)")
    p.add_argument("sweep_dir", help="a sweep folder, e.g. runs/sweeps/hard-cases")
    closing_options(p, cmd_report_stability, out="also write the Markdown table to this file", out_required=False,
                    force="overwrite an existing -o file")

    p = rp_verbs.add_parser("bore", help="every member of a wet-bed sweep against Stoker's dam break: front speed "
                                         "and bore depth (make wet-bed; docs/results/wet-bed/)")
    p.add_argument("sweep_dir", help="a sweep folder of post-processed 2D wet-bed runs, e.g. runs/sweeps/wet-bed")
    closing_options(p, cmd_report_bore, out="output folder (report.md, bore_check.csv, gauge plots)",
                    force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("flume", help="every member of a flume-as-built sweep (the gate's sill and opening, "
                                          "the wet bed, the column's position): arrivals at WG2, WG3 and the "
                                          "column's face against the measured and the scene as shipped (make "
                                          "flume-as-built; docs/results/flume-as-built/)")
    p.add_argument("sweep_dir", help="a sweep folder of post-processed runs, e.g. runs/sweeps/flume-as-built")
    closing_options(p, cmd_report_flume, out="output folder (report.md, flume.csv, arrivals.png)",
                    force=FOLDER_FORCE_HELP)

    p = rp_verbs.add_parser("approach", help="a one-way run's container carried through its flow record and the "
                                             "study's finer ones: the strike speed against the record's cell size "
                                             "near the column, its frame rate and the forcing near the face, with "
                                             "the force budget (make approach; docs/results/approach/)")
    p.add_argument("case_dir", metavar="RUN", help="the one-way run of the 1-debris scene (runs/1debris: make "
                                                  "case-1debris), with results/flow_record.npz")
    p.add_argument("--runs", default="runs", help="folder of the study's own runs (1debris-4cm, approach-*; each "
                                                  "missing one is named on the page with the command that makes it)")
    p.add_argument("--coupled", nargs="*", default=None, metavar="TWO_WAY",
                   help="two-way runs of the same scene set beside the carries, those with results (default: "
                        "runs/1debris-two-way and runs/coupling-1debris-{3,2}cm/two-way; none: give no folder)")
    closing_options(p, cmd_report_approach, out="output folder (report.md, approach.csv, budget.csv, plots)",
                    force=FOLDER_FORCE_HELP, json="print JSON (no progress)")

    p = rp_verbs.add_parser("forcing-variants", help="a one-way run's container carried through its flow record "
                                                     "under each variant of the one-way forcing (drag per axis or "
                                                     "along the flow, the Munk moment, three drag coefficients): "
                                                     "the table docs/one-way.md quotes (make forcing-variants)")
    p.add_argument("case_dir", metavar="RUN", help="the one-way run of the 1-debris scene (runs/1debris: make "
                                                  "case-1debris)")
    closing_options(p, cmd_report_forcing_variants, out="the Markdown page to write (benchmarks/forcing_variants.md)",
                    force="overwrite an existing file", json="print JSON (no progress)")
