"""The `debrisfoam` command line.

Exit codes (as in the README): 0 success; 2 bad input (the message names the
file and the field); 1 anything else, with a message saying what failed and where
its log is. `--debug` re-raises instead, for a full traceback.

Every verb is a thin shell over a library call; library code raises, only this
module prints messages and chooses exit codes.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any, Sequence

from analytical.errors import DebrisfoamError, InputError
from orchestrator.core.jsonio import json_default

EXIT_OK, EXIT_FAILURE, EXIT_BAD_INPUT = 0, 1, 2
#: A fit whose RMSE exceeds this fraction of the measured peak is reported as poor.
POOR_FIT_RMSE_FRACTION = 0.20


class _HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Help that states every option's default (unless it is None or the help says it already)."""

    def _get_help_string(self, action):
        text = action.help or ""
        if action.default in (None, False, argparse.SUPPRESS) or "default" in text:
            return text
        return super()._get_help_string(action)


class _ArgParser(argparse.ArgumentParser):
    """argparse that reports usage errors as InputError (exit 2 through our handler)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> None:  # noqa: D401 - argparse API
        raise InputError("arguments", f"{message} (see `{self.prog} --help`)")


# --------------------------------------------------------------------------- helpers


def output_path(path: str | Path, flag: str, force: bool, folder: bool) -> Path:
    """Check an output path before anything is computed: a folder that can be made and holds
    nothing yet (or `--force`), or a file whose folder exists and which is not there yet (or
    `--force`). Bad paths are bad input naming the flag: nothing already computed is touched."""
    out = Path(path)
    if folder:
        if out.exists() and not out.is_dir():
            raise InputError(flag, f"{out} is a file, not a folder")
        if out.is_dir() and any(out.iterdir()) and not force:
            raise InputError(flag, f"{out} holds files already: give --force to overwrite them, or another folder")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(flag, f"cannot create the folder {out}: {exc.strerror}") from None
        return out
    if out.is_dir():
        raise InputError(flag, f"{out} is a folder; give a file name")
    if out.exists() and not force:
        raise InputError(flag, f"{out} exists: give --force to overwrite it, or another name")
    if not out.parent.is_dir():
        try:
            out.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(flag, f"cannot create the folder {out.parent}: {exc.strerror}") from None
    return out


class _Flags:
    """Rename the fields of InputErrors raised inside to the flags the user typed."""

    def __init__(self, **flags: str):
        self.flags = flags

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and exc.field in self.flags:
            raise InputError(self.flags[exc.field], exc.rule, exc.source) from None
        return False


def warn(messages, where: str = "") -> None:
    """Each planner or check warning on stderr, one line each (also in --json output)."""
    for message in messages or ():
        print(f"debrisfoam: warning: {where}{message}", file=sys.stderr)


def _emit(result: dict[str, Any], as_json: bool, out=sys.stdout) -> None:
    if as_json:
        json.dump(result, out, indent=2, default=json_default)
        out.write("\n")
    else:
        width = max(len(k) for k in result) if result else 0
        for key, value in result.items():
            if isinstance(value, float):
                value = f"{value:.6g}"
            elif isinstance(value, list):
                value = ", ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in value)
            elif isinstance(value, dict):
                value = json.dumps(value, default=json_default)
            out.write(f"{key:<{width}}  {value}\n")


def column_from_args(args: argparse.Namespace):
    """The column for analytical verbs: the scene's (with --set) or the study's."""
    if getattr(args, "scene", None):
        from orchestrator.scene.scenefile import load_scene
        from orchestrator.scene.schema import column_for_analysis

        return column_for_analysis(load_scene(args.scene, list(args.set or [])))
    from dataclasses import fields, replace

    from analytical.column import Column

    from orchestrator.scene.overrides import parse_override

    column = Column()
    names = {f.name for f in fields(Column)}
    changes = {}
    for item in args.set or []:
        path, value = parse_override(item)
        key = ".".join(path)
        if len(path) != 2 or path[0] != "column" or path[1] not in names:
            raise InputError(
                key,
                "unknown key for the analytical column (without --scene only column.<field> "
                f"may be set; fields: {', '.join(sorted(names))})",
            )
        changes[path[1]] = value
    return replace(column, **changes) if changes else column


def _time_axis(t_end: float, dt: float):
    import numpy as np

    n = int(round(t_end / dt))
    return np.linspace(0.0, n * dt, n + 1)


# --------------------------------------------------------------------------- analytical verbs


def cmd_asce7(args: argparse.Namespace) -> int:
    from analytical.asce7 import asce7_impact

    with _Flags(velocity_m_s="--velocity", mass_kg="--mass", stiffness_N_m="--stiffness", importance="--importance",
                orientation="--orientation"):
        r = asce7_impact(
            velocity_m_s=args.velocity,
            mass_kg=args.mass,
            stiffness_N_m=args.stiffness,
            importance=args.importance,
            orientation=args.orientation,
        )
    _emit(
        {
            "force_N": r.force_N,
            "nominal_force_N": r.nominal_force_N,
            "duration_s": r.duration_s,
            "impulse_Ns": r.impulse_Ns,
            "orientation_C_o": args.orientation,
            "importance_I_tsu": args.importance,
            "note": "force_N is the design force I_tsu C_o F_ni; nominal_force_N is F_ni = u sqrt(k m)",
        },
        args.json,
    )
    return EXIT_OK


def impact_inputs(args: argparse.Namespace):
    """(contact law, column, body keywords) for `analytical impact`: the scene's first (or
    --body) debris body and column, or the study's container and column; --set changes
    scene keys, or without --scene column.<field> and contact.<field>."""
    from analytical.column import Column

    from orchestrator.run.contact import body_contact_law
    from orchestrator.scene.overrides import parse_override
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.scene.schema import DebrisContact, column_for_analysis

    if getattr(args, "scene", None):
        scene = load_scene(args.scene, list(args.set or []))
        if scene.column is None:
            raise InputError("column", "the scene has no column to strike", args.scene)
        if not scene.debris:
            raise InputError("debris", "the scene has no debris body", args.scene)
        bodies = {b.name: b for b in scene.debris}
        body = bodies.get(args.body) if args.body else scene.debris[0]
        if body is None:
            raise InputError("--body", f"no debris body {args.body!r} in the scene (bodies: {', '.join(bodies)})")
        keywords = {"mass_kg": body.mass_kg, "size_m": body.size_m, "wall_thickness_m": body.wall_thickness_m,
                    "friction_coefficient": body.contact.friction_coefficient}
        return body_contact_law(body.contact), column_for_analysis(scene), keywords
    if args.body:
        raise InputError("--body", "needs --scene")
    from dataclasses import fields, replace

    column_fields = {f.name for f in fields(Column)}
    contact_fields = set(DebrisContact.model_fields)
    column_changes, contact_changes = {}, {}
    for item in args.set or []:
        path, value = parse_override(item)
        key = ".".join(path)
        if len(path) == 2 and path[0] == "column" and path[1] in column_fields:
            column_changes[path[1]] = value
        elif len(path) == 2 and path[0] == "contact" and path[1] in contact_fields:
            contact_changes[path[1]] = value
        else:
            raise InputError(key, "unknown key for `analytical impact` without --scene: column.<field> ("
                             f"{', '.join(sorted(column_fields))}) or contact.<field> ({', '.join(sorted(contact_fields))})")
    try:
        contact = DebrisContact(**contact_changes)
    except Exception as exc:  # pydantic's ValidationError: name the first field it found wrong
        errors = getattr(exc, "errors", lambda: [])()
        field = "contact." + ".".join(str(x) for x in errors[0]["loc"]) if errors else "contact"
        raise InputError(field, errors[0]["msg"] if errors else str(exc)) from None
    column = replace(Column(), **column_changes) if column_changes else Column()
    return body_contact_law(contact), column, {"friction_coefficient": contact.friction_coefficient}


def cmd_impact(args: argparse.Namespace) -> int:
    from analytical.asce7 import SEED_DEBRIS_STIFFNESS_N_M, asce7_impact
    from analytical.contact_law import column_impact

    law, column, body = impact_inputs(args)
    r = column_impact(law, args.velocity, args.height, column=column, obliquity_deg=args.obliquity, **body)
    asce = asce7_impact(args.velocity, body.get("mass_kg", 0.236), SEED_DEBRIS_STIFFNESS_N_M)
    _emit(
        {
            "peak_force_N": r.peak_force_N,
            "duration_s": r.duration_s,
            "impulse_Ns": r.impulse_Ns,
            "restitution": r.restitution,
            "peak_base_shear_N": abs(r.base_shear.peak_N),
            "contact_law": law.name,
            "stiffness_N_m": law.stiffness_N_m,
            "damping_ratio": law.damping_ratio,
            "height_m": args.height,
            "obliquity_deg": args.obliquity,
            "asce7_kd_design_force_N": asce.force_N,
        },
        args.json,
    )
    return EXIT_OK


def cmd_contact_law(args: argparse.Namespace) -> int:
    from orchestrator.report.contact_report import write_contact_law_report

    if args.strikes < 2:
        raise InputError("--strikes", f"must be >= 2, got {args.strikes}")
    summary = write_contact_law_report(output_path(args.out, "-o/--out", args.force, folder=True), count=args.strikes)
    cal = summary["calibration"]
    _emit({"stiffness_N_m": cal["fitted_law"]["stiffness_N_m"], "damping_ratio": cal["fitted_law"]["damping_ratio"],
           "table1_peak_force_N": cal["fitted_pulse"]["peak_force_N"],
           "table1_duration_s": cal["fitted_pulse"]["duration_s"], "out": str(args.out)}, args.json)
    return EXIT_OK


def cmd_modes(args: argparse.Namespace) -> int:
    from analytical.mdof import column_model

    column = column_from_args(args)
    model = column_model(column)
    result: dict[str, Any] = {"frequencies_Hz": [float(f) for f in model.frequencies_Hz[: args.count]]}
    result["base"] = column.base
    if model.base_spring_Nm_rad is not None:
        result["base_spring_Nm_per_rad"] = float(model.base_spring_Nm_rad)
    _emit(result, args.json)
    return EXIT_OK


def cmd_response(args: argparse.Namespace) -> int:
    from analytical.errors import require_positive
    from analytical.pulses import make_pulse

    magnitude = require_positive("--magnitude", args.magnitude)
    duration = require_positive("--duration", args.duration)
    t_end = require_positive("--t-end", args.t_end)
    column = column_from_args(args)
    pulse = make_pulse(args.pulse, magnitude, duration)
    t = _time_axis(t_end, min(1e-5, duration / 50))
    if args.model == "sdof":
        from analytical.sdof import SDOF, sdof_response

        sdof = SDOF(column.stiffness_N_m, column.natural_frequency_Hz, column.damping_ratio)
        response = sdof_response(pulse, sdof, t)
    else:
        from analytical.mdof import mdof_response

        height = require_positive("--height", args.height)
        if height > column.height_m:
            raise InputError("--height", f"must be <= the column height {column.height_m} m, got {height}")
        response = mdof_response(pulse, column, height, t)
    if args.out:
        import pandas as pd

        out = output_path(args.out, "--out", args.force, folder=False)
        pd.DataFrame({"time_s": response.time_s, "response_N": response.response_N}).to_csv(out, index=False)
    _emit({"peak_N": float(response.peak_N), "time_of_peak_s": float(response.time_of_peak_s)}, args.json)
    return EXIT_OK


def cmd_fit(args: argparse.Namespace) -> int:
    from analytical.fitting import fit_mdof, fit_sdof

    from orchestrator.results.records import read_force_record

    time_s, force_N = read_force_record(args.record)
    column = column_from_args(args)
    try:
        if args.model == "sdof":
            fit = fit_sdof(time_s, force_N, column=column, shape=args.pulse)
        else:
            fit = fit_mdof(time_s, force_N, column=column, height_m=args.height, shape=args.pulse)
    except InputError as exc:
        raise exc.with_source(str(args.record)) from None
    result = {
        "magnitude_N": fit.magnitude_N,
        "duration_s": fit.duration_s,
        "impulse_Ns": fit.impulse_Ns,
        "rmse_N": fit.rmse_N,
        "peak_measured_N": fit.peak_measured_N,
        "peak_model_N": fit.peak_model_N,
        "offset_removed_N": fit.offset_N,
        "start_s": fit.start_s,
        "natural_frequency_Hz": fit.natural_frequency_Hz,
        "damping_ratio": fit.damping_ratio,
        "stiffness_N_m": fit.stiffness_N_m,
        "height_m": fit.height_m,
    }
    _emit({k: v for k, v in result.items() if v is not None}, args.json)
    if fit.rmse_N > POOR_FIT_RMSE_FRACTION * fit.peak_measured_N:
        warn([f"poor fit: RMSE {fit.rmse_N:.3g} N is {100 * fit.rmse_N / fit.peak_measured_N:.0f} % of the measured "
              f"peak {fit.peak_measured_N:.4g} N (over {100 * POOR_FIT_RMSE_FRACTION:.0f} %): the {args.model} model "
              "does not describe this record well"])
    return EXIT_OK


def cmd_dambreak(args: argparse.Namespace) -> int:
    import numpy as np

    from analytical.dambreak import dam_break

    solution = dam_break(args.model, args.h0, hr_m=args.hr, friction=args.friction)
    if args.arrival is not None:
        if not args.arrival > 0:
            raise InputError("--arrival", f"must be downstream of the gate (x > 0 m, where the front arrives), got "
                                          f"{args.arrival}")
        _emit({"arrival_s": float(solution.arrival_time_s(args.arrival))}, args.json)
        return EXIT_OK
    if args.profile is None or not args.out:
        raise InputError("--arrival/--profile", "give --arrival X, or --profile T with --out CSV")
    t = args.profile
    x_front = float(solution.front_position_m(t))
    x_back = -np.sqrt(9.81 * args.h0) * t
    x = np.linspace(min(x_back * 1.2, -0.1), max(x_front * 1.2, 0.1), args.points)
    depth, velocity = solution.profile(x, t)
    import pandas as pd

    out = output_path(args.out, "--out", args.force, folder=False)
    pd.DataFrame({"x_m": x, "depth_m": depth, "velocity_m_s": velocity}).to_csv(out, index=False)
    _emit({"front_position_m": x_front, "csv": str(out)}, args.json)
    return EXIT_OK


def cmd_study(args: argparse.Namespace) -> int:
    from orchestrator.studies.synthetic import run_synthetic_study

    if args.records < 2:
        raise InputError("--records", f"must be >= 2 (a mean and a spread need two records), got {args.records}")
    out = output_path(args.out, "-o/--out", args.force, folder=True)
    summary = run_synthetic_study(out, seed=args.seed, n_records=args.records, column_base=args.base)
    _emit(summary, args.json)
    return EXIT_OK


# --------------------------------------------------------------------------- CFD verbs


def _missing(what: str, issue: int) -> int:
    from orchestrator.core.errors import MissingFeatureError

    raise MissingFeatureError(f"{what} is not built yet (tracked in issue {issue}); the analytical verbs work today")


def cmd_scenes(args: argparse.Namespace) -> int:
    from orchestrator.scene.reference import scenes_dir, shipped_scenes

    scenes = shipped_scenes()
    if args.json:
        _emit({"folder": str(scenes_dir()), "scenes": [{"path": str(p), "description": d} for p, d in scenes]}, True)
        return EXIT_OK
    root = scenes_dir()
    width = max(len(str(p.relative_to(root))) for p, _ in scenes)
    print(f"shipped scenes in {root}:")
    for path, text in scenes:
        print(f"  {str(path.relative_to(root)):<{width}}  {text}")
    return EXIT_OK


def cmd_validate(args: argparse.Namespace) -> int:
    from orchestrator.plan.planner import plan_case
    from orchestrator.scene.scenefile import load_scene

    scene = load_scene(args.scene, list(args.set or []))
    plan = plan_case(scene)
    result = {"scene": args.scene, "valid": True, "name": scene.name, "bodies": len(scene.debris),
              "solver": plan.solver, "planned_cells": int(plan.cell_count), "warnings": list(plan.warnings)}
    _emit({k: v for k, v in result.items() if args.json or k != "warnings"}, args.json)
    warn(plan.warnings)
    return EXIT_OK


def cmd_schema(args: argparse.Namespace) -> int:
    from orchestrator.scene.reference import markdown, schema_rows, select

    rows = select(schema_rows(), args.key)
    if args.markdown:
        print(markdown(rows), end="")
    elif args.json:
        from dataclasses import asdict

        _emit({"keys": [asdict(r) for r in rows]}, True)
    else:
        for r in rows:
            extra = ", ".join(x for x in (r.type, f"default {r.default}", r.range) if x)
            print(f"{r.key}  ({extra})" + (f"\n    {r.description}" if r.description else ""))
    return EXIT_OK


def cmd_render(args: argparse.Namespace) -> int:
    try:
        from orchestrator.pipeline import render_from_file
    except ImportError:
        return _missing("`render` (scene schema, planner and templates)", 3)
    out = Path(args.out)
    if not out.exists():
        output_path(out, "-o/--out", False, folder=True)
        out.rmdir()  # only checked: render makes it when the scene is valid
    summary = render_from_file(args.scene, out, list(args.set or []), force=args.force, mesh=args.mesh)
    _emit({k: v for k, v in summary.items() if args.json or k != "warnings"}, args.json)
    warn(summary["warnings"])
    return EXIT_OK


def cmd_preview(args: argparse.Namespace) -> int:
    try:
        from orchestrator.report.preview import preview_scene_file
    except ImportError:
        return _missing("`preview`", 3)
    if Path(args.out).suffix.lower() != ".png":
        raise InputError("-o/--out", f"must name a .png file (the preview is a PNG image), got {args.out}")
    out = output_path(args.out, "-o/--out", args.force, folder=False)
    warnings = preview_scene_file(args.scene, out, list(args.set or []), warnings=True)
    if args.json:
        _emit({"preview": str(out), "warnings": warnings}, True)
    else:
        print(f"preview written to {out}")
    warn(warnings)
    return EXIT_OK


def cmd_run(args: argparse.Namespace) -> int:
    from orchestrator.run.monitor import DivergenceLimits
    from orchestrator.run.runner import RunInterrupted, run_case

    if args.stall_limit is not None and not args.stall_limit > 0:
        raise InputError("--stall-limit", f"must be > 0 seconds, got {args.stall_limit}")
    if not Path(args.case_dir).is_dir():
        raise InputError("case_dir", "no such folder: render a case into it first (debrisfoam render SCENE -o DIR)",
                         str(args.case_dir))

    try:
        limits = DivergenceLimits(stall_s=args.stall_limit) if args.stall_limit is not None else None
        summary = run_case(args.case_dir, np=args.np, quiet=args.quiet, reconstruct=args.reconstruct, limits=limits)
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
    _emit(result, args.json)
    return EXIT_OK


def cmd_post(args: argparse.Namespace) -> int:
    from orchestrator.results.post import post_case

    summary = post_case(args.case_dir, comparisons=not args.tables_only, snapshot=not args.no_snapshot,
                        arrival_threshold_m=args.arrival_threshold)
    if args.json:
        _emit(summary.to_dict(), True)
        return EXIT_OK
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
                         if ref.startswith(("Chanson", "seed")))
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
    _emit(result, False)
    return EXIT_OK


def cmd_case(args: argparse.Namespace) -> int:
    from orchestrator.pipeline import run_full_case
    from orchestrator.run.runner import RunInterrupted

    try:
        summary = run_full_case(args.scene, args.out, list(args.set or []), np=args.np, quiet=args.quiet)
    except RunInterrupted as exc:  # resumable: the same command continues the run
        if args.debug:
            raise
        print(f"debrisfoam: {exc} (or run the same `debrisfoam case` command again)", file=sys.stderr)
        return exc.exit_code
    if not args.json:
        print("\n== summary ==")
    _emit(summary, args.json)
    return EXIT_OK


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


def cmd_sweep(args: argparse.Namespace) -> int:
    from orchestrator.studies.sweep import dry_run, run_sweep

    if args.dry_run:
        plan = dry_run(args.sweep, args.out, executor=args.executor, scheduler=args.scheduler, workers=args.workers)
        if args.json:
            _emit(plan, True)
        else:
            _print_dry_run(plan)
        for m in plan["members"]:
            warn(m["warnings"], f"member {m['member']} ({m['id']}): ")
        return EXIT_OK
    progress_stream = sys.stderr if args.json else sys.stdout

    def progress(line: str) -> None:
        print(f"debrisfoam: {line}", file=progress_stream, flush=True)

    result = run_sweep(args.sweep, args.out, executor=args.executor, scheduler=args.scheduler, workers=args.workers,
                       retry_failed=args.retry_failed, progress=progress)
    if args.json:
        _emit(result.to_dict(), True)
    if result.interrupted and result.unfinished:
        print(f"debrisfoam: sweep interrupted; {len(result.unfinished)} member(s) not finished: run the same command "
              "again to resume", file=sys.stderr)
        return 128 + (result.signum or 2)  # 130 for Ctrl-C, 143 for SIGTERM, as `debrisfoam run`
    if result.failed:
        lines = [f"debrisfoam: error: {len(result.failed)} of {len(result.rows)} sweep member(s) failed "
                 f"(store {result.store}):"]
        for row in result.failures():
            error = (row.get("error") or "no error recorded").replace("\n", "\n      ")
            lines.append(f"  member {row['member']} {row['member_id']} ({row['overrides'] or 'base scene'}): {error}")
            lines.append(f"    case: {row['case_dir']}")
        lines.append("  (fix the cause, then run again with --retry-failed; finished members are skipped)")
        print("\n".join(lines), file=sys.stderr)
        return EXIT_FAILURE
    if result.unfinished:  # e.g. a member not started because the sweep was stopped
        print(f"debrisfoam: error: {len(result.unfinished)} member(s) did not finish: run the same command again",
              file=sys.stderr)
        return EXIT_FAILURE
    return EXIT_OK


def cmd_report_speed_error(args: argparse.Namespace) -> int:
    from orchestrator.studies.speed_error import markdown, speed_error, write_report

    extrapolate = args.extrapolate_to if args.extrapolate_to and args.extrapolate_to > 0 else None
    study = speed_error(args.sweep_dir, list(args.baseline or []), reference=args.reference, time=args.time,
                        extrapolate_to_m=extrapolate)
    if args.out:
        output_path(args.out, "-o/--out", args.force, folder=True)
    files = write_report(study, args.out)
    if args.json:
        _emit(study.headline(), True)
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
    _emit({"report": str(path)}, args.json)
    return EXIT_OK


def cmd_report_stability(args: argparse.Namespace) -> int:
    from orchestrator.studies.stability import markdown, stability_table

    table = stability_table(args.sweep_dir)
    text = markdown(table)
    if args.out:
        output_path(args.out, "-o/--out", args.force, folder=False).write_text(text)
    if args.json:
        _emit({"members": table.to_dict(orient="records")}, True)
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


# --------------------------------------------------------------------------- parser


def _add_column_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scene", help="scene YAML whose column to use (default: the study's column)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a dotted scene key (repeatable)")


def _version() -> str:
    """The installed package's version (pyproject.toml), or 'unknown' when run from a bare tree."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("debrisfoam")
    except PackageNotFoundError:
        return "unknown (not installed)"


def build_parser() -> argparse.ArgumentParser:
    parser = _ArgParser(prog="debrisfoam", description=__doc__.splitlines()[0])
    parser.add_argument("--debug", action="store_true", help="re-raise errors with a full traceback")
    parser.add_argument("--version", action="version", version=f"debrisfoam {_version()}")
    verbs = parser.add_subparsers(dest="verb", required=True, parser_class=_ArgParser)

    # analytical
    an = verbs.add_parser("analytical", help="analytical models (ASCE 7-22, SDOF, MDOF, fitting, dam break)")
    an_verbs = an.add_subparsers(dest="analytical_verb", required=True, parser_class=_ArgParser)

    p = an_verbs.add_parser("asce7", help="ASCE 7-22 6.11 debris impact force, duration and impulse")
    p.add_argument("--velocity", type=float, required=True, help="impact (max flow) velocity, m/s")
    p.add_argument("--mass", type=float, required=True, help="debris mass, kg")
    p.add_argument("--stiffness", type=float, required=True, help="stiffness k (lesser of debris and structure), N/m")
    p.add_argument("--importance", type=float, default=1.0, help="I_tsu (1.0 for tsunami risk category II)")
    p.add_argument("--orientation", type=float, default=0.65, help="C_o (0.65 for logs, poles, containers)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_asce7)

    p = an_verbs.add_parser("impact", help="one debris strike on the column by the contact law: pulse, rebound, "
                                           "base shear (docs/contact-law.md)")
    p.add_argument("--velocity", type=float, required=True, help="the body's speed at the strike, m/s")
    p.add_argument("--height", type=float, default=0.40,
                   help="contact height above the column's base, m (default 0.40, the study's mean)")
    p.add_argument("--obliquity", type=float, default=0.0,
                   help="angle of the body's velocity from the face's normal, degrees (default 0, head on)")
    p.add_argument("--scene", help="scene YAML whose debris body and column to use (default: the study's "
                                   "0.236 kg container and acrylic column)")
    p.add_argument("--body", help="which debris body of --scene (default: its first)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key (repeatable); without --scene: column.<field> or "
                        "contact.<field>, e.g. contact.law=asce7_kd, contact.restitution=0.5")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_impact)

    p = an_verbs.add_parser("contact-law", help="calibrate the container's contact law on the study's Table 1 "
                                                "event and check it on Table 2's held-out statistics, to files")
    p.add_argument("-o", "--out", default="docs/results/contact-law",
                   help="output folder (default docs/results/contact-law)")
    p.add_argument("--strikes", type=int, default=22, help="held-out strikes (default 22, as the study's impacts)")
    p.add_argument("--force", action="store_true", help="overwrite a folder that holds files already")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_contact_law)

    p = an_verbs.add_parser("modes", help="natural frequencies of the MDOF column")
    _add_column_args(p)
    p.add_argument("--count", type=int, default=6, help="how many frequencies to print (default 6)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_modes)

    p = an_verbs.add_parser("response", help="force response (SDOF R = k u, or MDOF base shear) to a pulse")
    p.add_argument("--model", choices=["sdof", "mdof"], required=True,
                   help="sdof: R = k u of the study's oscillator; mdof: base shear of the Timoshenko column")
    p.add_argument("--pulse", choices=["half-sine", "rectangular", "triangular"], default="half-sine",
                   help="pulse shape")
    p.add_argument("--magnitude", type=float, required=True, help="pulse peak force, N")
    p.add_argument("--duration", type=float, required=True, help="pulse duration, s")
    p.add_argument("--height", type=float, default=0.40, help="impact height above the column base, m (mdof)")
    p.add_argument("--t-end", type=float, default=0.05, help="length of the response record, s (default 0.05)")
    p.add_argument("--out", help="write the response to this CSV (time_s,response_N)")
    p.add_argument("--force", action="store_true", help="overwrite an existing --out file")
    _add_column_args(p)
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_response)

    p = an_verbs.add_parser("fit", help="fit an impact pulse to a measured force-response record (CSV time_s,force_N)")
    p.add_argument("--model", choices=["sdof", "mdof"], required=True,
                   help="sdof: fit magnitude, duration, damping, stiffness, frequency within the study's bounds; "
                        "mdof: magnitude and duration on the column model")
    p.add_argument("record", help="CSV with columns time_s,force_N")
    p.add_argument("--pulse", choices=["half-sine", "rectangular", "triangular"], default="half-sine",
                   help="pulse shape fitted")
    p.add_argument("--height", type=float, default=0.40, help="impact height above the column base, m (mdof)")
    _add_column_args(p)
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_fit)

    p = an_verbs.add_parser("dambreak", help="dam-break solutions: Ritter, Stoker, Chanson")
    p.add_argument("--model", choices=["ritter", "stoker", "chanson"], required=True,
                   help="ritter: dry bed; stoker: wet bed (--hr); chanson: dry bed with friction (--friction)")
    p.add_argument("--h0", type=float, required=True, help="impoundment depth, m")
    p.add_argument("--hr", type=float, default=0.0, help="downstream depth (stoker), m")
    p.add_argument("--friction", type=float, default=None, help="Darcy friction factor f (chanson)")
    p.add_argument("--arrival", type=float, default=None, help="x of a gauge, m: print the arrival time")
    p.add_argument("--profile", type=float, default=None, help="time, s: write the profile to --out")
    p.add_argument("--points", type=int, default=401, help="profile points (default 401)")
    p.add_argument("--out", help="CSV for --profile (x_m,depth_m,velocity_m_s)")
    p.add_argument("--force", action="store_true", help="overwrite an existing --out file")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_dambreak)

    p = an_verbs.add_parser("study", help="the study's SDOF/MDOF/ASCE analysis on synthetic records (Table 2, Fig. 7)")
    p.add_argument("-o", "--out", default="docs/results/synthetic-study", help="output folder (tables and plots)")
    p.add_argument("--records", type=int, default=22, help="number of synthetic records (default 22, as the study)")
    p.add_argument("--seed", type=int, default=2019, help="random seed")
    p.add_argument("--base", choices=["rigid", "calibrated"], default="rigid", help="column base model of the records")
    p.add_argument("--force", action="store_true", help="overwrite a folder that holds files already")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_study)

    # scenes
    p = verbs.add_parser("scenes", help="list the shipped example scenes, one line each")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_scenes)

    p = verbs.add_parser("validate", help="check a scene (schema and planner) without writing anything: exit 0 "
                                          "or 2")
    p.add_argument("scene", help="scene YAML")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a dotted scene key (repeatable)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_validate)

    p = verbs.add_parser("schema", help="the scene's keys: types, defaults, allowed ranges, meanings "
                                        "(docs/scene.md is generated from it)")
    p.add_argument("key", nargs="?", default=None, help="a section or key, e.g. debris or run.max_courant")
    p.add_argument("--markdown", action="store_true", help="print the reference page (docs/scene.md)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_schema)

    # CFD
    p = verbs.add_parser("render", help="render an OpenFOAM case from a scene YAML")
    p.add_argument("scene", help="scene YAML (debrisfoam scenes lists the shipped ones; docs/scene.md)")
    p.add_argument("-o", "--out", required=True, help="case folder to write (new or empty, or --force)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key, value as YAML (repeatable), e.g. mesh.cell_size_m=0.03")
    p.add_argument("--force", action="store_true", help="overwrite a non-empty output folder")
    p.add_argument("--mesh", action="store_true", help="also build the mesh and print checkMesh's verdict")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_render)

    p = verbs.add_parser("preview", help="draw the scene (flume, column, debris, gauges) to a PNG")
    p.add_argument("scene", help="scene YAML (debrisfoam scenes lists the shipped ones; docs/scene.md)")
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
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_run)

    p = verbs.add_parser("post", help="post-process a run (finished or not) into DIR/results/: tables, "
                                      "comparisons, plots, report.md")
    p.add_argument("case_dir", help="a rendered case folder (debrisfoam render)")
    p.add_argument("--tables-only", action="store_true", help="only the tables and summary.json (no comparisons, "
                                                              "plots or report)")
    p.add_argument("--no-snapshot", action="store_true", help="skip the pyvista 3D snapshot")
    p.add_argument("--arrival-threshold", type=float, default=None, metavar="M",
                   help="rise above the initial level (m) that marks the bore's arrival (default 2 %% of h0)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_post)

    p = verbs.add_parser("case", help="render + run + post in one go (run it again to resume)")
    p.add_argument("scene", help="scene YAML (debrisfoam scenes lists the shipped ones; docs/scene.md)")
    p.add_argument("-o", "--out", default=None, help="case folder (default: runs/<scene name>)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key, value as YAML (repeatable), e.g. mesh.cell_size_m=0.03")
    p.add_argument("--np", type=int, default=None, help="MPI ranks (default: the scene's run.cores)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_case)

    p = verbs.add_parser("sweep", help="run a parameter sweep (a base scene and axes; see docs/sweeps.md); "
                                       "run it again to resume")
    p.add_argument("sweep", help="sweep YAML")
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
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_sweep)

    rp = verbs.add_parser("report", help="reports across runs: speed-error (a sweep's cost against its errors), "
                                                 "stability (a sweep's runs checked)")
    rp_verbs = rp.add_subparsers(dest="report_verb", required=True, parser_class=_ArgParser)
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
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_report_speed_error)
    p = rp_verbs.add_parser("case", help="one post-processed run beside the study's figures: a results page "
                                         "with its plots (make results-1debris)")
    p.add_argument("case_dir", help="a run folder with results/ (debrisfoam post has run)")
    p.add_argument("-o", "--out", required=True, help="output folder (report.md, plots, summary.json)")
    p.add_argument("--force", action="store_true", help="overwrite a folder that holds files already")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_report_case)

    p = rp_verbs.add_parser("stability", help="for every member of a sweep: finished with sane physics (water "
                                              "conserved, no body inside a wall, finite forces) or stopped with "
                                              "a diagnosis (the table of docs/stability.md)")
    p.add_argument("sweep_dir", help="a sweep folder, e.g. runs/sweeps/hard-cases")
    p.add_argument("-o", "--out", default=None, help="also write the Markdown table to this file")
    p.add_argument("--force", action="store_true", help="overwrite an existing -o file")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_report_stability)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    if debug:  # accepted anywhere on the line, as the first option or after the verb
        argv = ["--debug", *(a for a in argv if a != "--debug")]
    try:
        args = build_parser().parse_args(argv)
        return int(args.func(args) or EXIT_OK)
    except InputError as exc:
        if debug:
            raise
        print(f"debrisfoam: bad input: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except DebrisfoamError as exc:
        if debug:
            raise
        print(f"debrisfoam: error: {exc}", file=sys.stderr)
        return EXIT_FAILURE
    except KeyboardInterrupt:
        print("debrisfoam: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # the contract: never a bare traceback without --debug
        if debug:
            raise
        print(f"debrisfoam: unexpected error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return EXIT_FAILURE


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
