"""The `debrisfoam analytical` verbs: the study's analytical models from the command line.

ASCE 7-22 debris impact (``asce7``), one strike by the contact law (``impact``), the contact
law's calibration (``contact-law``), the column's modes (``modes``), SDOF/MDOF response to a
pulse (``response``), pulse fitting to a force record (``fit``), the dam-break solutions
(``dambreak``) and the study's analysis on synthetic records (``study``). The column is the
study's, or a scene's (``--scene``), changed by ``--set``. Each verb imports its models when
it runs, so the command line starts without loading every stage.
"""

from __future__ import annotations

import argparse
from typing import Any

from analytical.asce7 import FULL_SCALE_MIN_MASS_KG
from orchestrator.core.errors import InputError
from orchestrator.cli.common import EXIT_OK, FOLDER_FORCE_HELP, ArgParser, Flags, closing_options, emit, output_path, warn
from orchestrator.scene.shipped import resolve_scene

__all__ = ["POOR_FIT_RMSE_FRACTION", "add_analytical_parser", "column_from_args", "impact_inputs"]

#: A fit whose RMSE exceeds this fraction of the measured peak is reported as poor.
POOR_FIT_RMSE_FRACTION = 0.20
#: Peak memory per sample of a `response` record (bytes), SDOF and MDOF alike: measured here with
#: /usr/bin/time -v between --t-end 2 and 8 s at 1e-5 s steps (23 MB more for 600,000 samples).
BYTES_PER_SAMPLE = 40


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
    """The record's times, 0..t_end every dt; InputError on --t-end when the record would take over
    half the memory available now (:data:`BYTES_PER_SAMPLE`)."""
    import numpy as np

    from orchestrator.plan.resources import SOFT_MEMORY_FRACTION, Machine

    n = int(round(t_end / dt))
    limit = int(SOFT_MEMORY_FRACTION * Machine.here().available_memory_B / BYTES_PER_SAMPLE)
    if n + 1 > limit:
        raise InputError("--t-end", f"{t_end:g} s at {dt:.3g} s steps is {n + 1:,} samples (about "
                                    f"{(n + 1) * BYTES_PER_SAMPLE / 1e9:.3g} GB): over the limit of {limit:,} samples, "
                                    "half the memory available now; give a shorter --t-end")
    return np.linspace(0.0, n * dt, n + 1)

#: What every ASCE 7-22 answer says about its velocity.
VELOCITY_NOTE = ("ASCE 7-22 6.11.2's u_max is the flow's maximum velocity at the site (deep enough to float the "
                 "debris); the study put each record's measured impact speed there; the velocity given here is used "
                 "as u_max")


def asce7_lines(design, prefix: str = "") -> dict[str, Any]:
    """The ASCE 7-22 answer of an :class:`~analytical.asce7.AsceDesign`, keyed for a verb's output:
    the design value with its governing stiffness first, the other stiffness's force as context."""
    d = design.to_dict()
    other = d["other_stiffness"]
    keys = {
        "design_force_N": d["force_N"],
        "binds": d["binding"],
        "governing_stiffness": f"{d['governing_stiffness']} = {d['stiffness_N_m']:.4g} N/m (the lesser of k_d "
                               f"{d['debris_stiffness_N_m']:.4g} and k_s {d['structure_stiffness_N_m']:.4g} N/m)",
        "duration_s": d["duration_s"],
        "impulse_Ns": d["impulse_Ns"],
        "nominal_force_N": d["nominal_force_N"],
        f"force_with_{other}_N": d["other_force_N"],
        "velocity_m_s": d["velocity_m_s"],
        "velocity_note": VELOCITY_NOTE,
        "cap_N": d["cap_N"],
        "cap_note": design.cap_note(),
    }
    return {f"{prefix}{k}": v for k, v in keys.items()}


def _scene_asce(scene_path, sets, body: str | None = None):
    """(ASCE inputs, scene) of a scene (:func:`~orchestrator.studies.design_asce.scene_asce_inputs`):
    what `design` reads, for ``body`` (None: every body)."""
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.studies.design_asce import scene_asce_inputs

    scene = load_scene(scene_path, list(sets or []))
    if body is not None and body not in {b.name for b in scene.debris}:
        raise InputError("--body", f"no debris body {body!r} in the scene (bodies: "
                                   f"{', '.join(b.name for b in scene.debris)})")
    return scene_asce_inputs(scene, None if body is None else [body], str(scene_path)), scene


def cmd_asce7(args: argparse.Namespace) -> int:
    from analytical.asce7 import (
        DEBRIS_STIFFNESS_RANGE_N_M,
        IMPORTANCE_FACTORS,
        STRUCTURE_STIFFNESS_RANGE_N_M,
        asce7_design,
        check_debris_mass,
        check_debris_stiffness,
        check_flow_speed,
        check_full_scale_mass,
        check_structure_stiffness,
    )
    from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M, STUDY_STRUCTURE_STIFFNESS_N_M

    check_flow_speed(args.velocity, "--velocity")
    if args.importance is not None and args.importance not in set(IMPORTANCE_FACTORS.values()):
        raise InputError("--importance", "ASCE 7-22 Table 6.8-1 gives I_tsu = 1.0 (Tsunami Risk Category II) or "
                         f"1.25 (III, IV and vertical evacuation refuges), got {args.importance:g}")
    sources: dict[str, str] = {}
    if args.scene:  # the scene's inputs, as `design` and `analytical impact --scene` read them; flags override
        inputs, _ = _scene_asce(args.scene, args.set, args.body)
        mass = inputs.mass_kg if args.mass is None else args.mass
        k_d = inputs.debris_stiffness_N_m if args.debris_stiffness is None else args.debris_stiffness
        k_s = inputs.structure_stiffness_N_m if args.structure_stiffness is None else args.structure_stiffness
        importance = inputs.importance if args.importance is None else args.importance
        orientation = inputs.orientation if args.orientation is None else args.orientation
        prototype, scale = inputs.prototype or args.prototype, inputs.scale_reason
        sources = {k: v for k, v in inputs.sources.items() if k in ("m_d", "k_d", "k_s", "I_tsu")}
        for key, flag in (("m_d", args.mass), ("k_d", args.debris_stiffness), ("k_s", args.structure_stiffness),
                          ("I_tsu", args.importance)):
            if flag is not None:
                sources[key] = "given on the command line"
    else:
        if args.body:
            raise InputError("--body", "needs --scene")
        if args.set:
            raise InputError("--set", "needs --scene (the scene's keys to change)")
        if args.mass is None:
            raise InputError("--mass", "the debris mass m_d (kg) is needed (or --scene, whose design section gives it)")
        mass = check_debris_mass(args.mass, "--mass")
        if args.prototype:
            check_full_scale_mass(mass, "--mass")
        importance = 1.0 if args.importance is None else args.importance
        orientation = 0.65 if args.orientation is None else args.orientation
        prototype = args.prototype or mass >= FULL_SCALE_MIN_MASS_KG
        scale = ("--prototype" if args.prototype else f"a {mass:,.0f} kg body is full-scale debris (>= "
                 f"{FULL_SCALE_MIN_MASS_KG:g} kg)") if prototype else "laboratory scale (under 100 kg, no --prototype)"
        k_d, k_s = args.debris_stiffness, args.structure_stiffness
        if args.stiffness is None:
            for value, flag, lab, what in ((k_s, "--structure-stiffness", STUDY_STRUCTURE_STIFFNESS_N_M,
                                            "the struck element's lateral stiffness k_s"),
                                           (k_d, "--debris-stiffness", STUDY_DEBRIS_STIFFNESS_N_M,
                                            "the debris' stiffness k_d")):
                if value is None and prototype:
                    raise InputError(flag, f"{scale}: give {what} (N/m), or --stiffness; the default, {lab:.4g} N/m, "
                                           "is the study's laboratory value and no full-scale one")
        sources = {"k_s": "--structure-stiffness" if k_s is not None else
                   f"the study's laboratory column ({STUDY_STRUCTURE_STIFFNESS_N_M:.4g} N/m, the default)",
                   "k_d": "--debris-stiffness" if k_d is not None else
                   f"the study's 1:40 container ({STUDY_DEBRIS_STIFFNESS_N_M:.4g} N/m, the default)"}
        k_d = STUDY_DEBRIS_STIFFNESS_N_M if k_d is None else k_d
        k_s = STUDY_STRUCTURE_STIFFNESS_N_M if k_s is None else k_s
    stiffness_flags = {"debris_stiffness_N_m": "--debris-stiffness", "structure_stiffness_N_m": "--structure-stiffness"}
    if args.stiffness is not None:  # one k, chosen by the user: it governs, there is nothing to compare
        k_d = k_s = args.stiffness
        stiffness_flags = {"debris_stiffness_N_m": "--stiffness", "structure_stiffness_N_m": "--stiffness"}
        sources = {"k": "--stiffness"}
        lo = min(DEBRIS_STIFFNESS_RANGE_N_M[0], STRUCTURE_STIFFNESS_RANGE_N_M[0])
        hi = max(DEBRIS_STIFFNESS_RANGE_N_M[1], STRUCTURE_STIFFNESS_RANGE_N_M[1])
        if not lo <= args.stiffness <= hi:
            raise InputError("--stiffness", f"{args.stiffness:g} N/m is neither a debris nor a struck element's "
                                            f"stiffness: the plausible range is {lo:.0e}-{hi:.0e} N/m")
    else:
        if args.debris_stiffness is not None:
            check_debris_stiffness(args.debris_stiffness, "--debris-stiffness")
        if args.structure_stiffness is not None:
            check_structure_stiffness(args.structure_stiffness, "--structure-stiffness")
    if args.mass is not None:
        check_debris_mass(args.mass, "--mass")
    with Flags(velocity_m_s="--velocity", mass_kg="--mass", stiffness_N_m="--stiffness", importance="--importance",
               orientation="--orientation", **stiffness_flags):
        design = asce7_design(args.velocity, mass, k_d, k_s, importance, orientation, prototype=prototype)
    out = asce7_lines(design)
    out = {"force_N": out.pop("design_force_N"), **out, "orientation_C_o": orientation,
           "importance_I_tsu": importance, "scale": scale,
           **{f"source_{k}": v for k, v in sources.items()},
           "note": "force_N is the design force F_i = I_tsu C_o u_max sqrt(k m_d) with the governing k, bounded at "
                   "full scale by the simplified static load; binds says which sets it"}
    if args.stiffness is not None:
        out["governing_stiffness"] = f"k = {args.stiffness:.4g} N/m (given with --stiffness)"
        out.pop("force_with_k_d_N", None)
    emit(out, args.json)
    return EXIT_OK


def impact_inputs(args: argparse.Namespace):
    """(contact law, column, body keywords, scene or None) for `analytical impact`: the scene's first
    (or --body) debris body and column, or the study's container and column; --set changes
    scene keys, or without --scene column.<field> and contact.<field>."""
    if getattr(args, "scene", None):
        return _scene_impact_inputs(args)
    if args.body:
        raise InputError("--body", "needs --scene")
    return _study_impact_inputs(args)


def _scene_impact_inputs(args: argparse.Namespace):
    """impact_inputs from --scene: its column and its first (or --body) debris body."""
    from orchestrator.contact.resolution import body_contact_law
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.scene.schema import column_for_analysis

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
    return body_contact_law(body.contact), column_for_analysis(scene), keywords, scene


def _study_impact_inputs(args: argparse.Namespace):
    """impact_inputs without a scene: the study's column and container, changed by column.<field> and
    contact.<field> overrides."""
    from dataclasses import fields, replace

    from analytical.column import Column

    from orchestrator.contact.resolution import body_contact_law
    from orchestrator.scene.overrides import parse_override
    from orchestrator.scene.schema import DebrisContact

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
    return body_contact_law(contact), column, {"friction_coefficient": contact.friction_coefficient}, None


def cmd_impact(args: argparse.Namespace) -> int:
    from analytical.asce7 import asce7_design, check_flow_speed
    from analytical.study import STUDY_DEBRIS_MASS_KG, STUDY_DEBRIS_STIFFNESS_N_M, STUDY_MEAN_HEIGHT_M
    from analytical.contact_law import column_impact

    check_flow_speed(args.velocity, "--velocity")
    law, column, body, scene = impact_inputs(args)
    height, height_source = (args.height, "--height") if args.height is not None else (None, "")
    if scene is not None:  # the scene's ASCE inputs and strike point, as `design` and `analytical asce7 --scene` read them
        from orchestrator.studies.design_asce import scene_asce_inputs, strike_point

        inputs = scene_asce_inputs(scene, [args.body or scene.debris[0].name], str(args.scene))
        if height is None:
            height, height_source = strike_point(scene)
        asce = inputs.design(args.velocity)
        code = {"asce7_mass_kg": inputs.mass_kg, "asce7_scale": inputs.scale_reason,
                **{f"asce7_source_{k}": v for k, v in inputs.sources.items() if k in ("m_d", "k_d", "k_s", "I_tsu")}}
    else:
        asce = asce7_design(args.velocity, body.get("mass_kg", STUDY_DEBRIS_MASS_KG), STUDY_DEBRIS_STIFFNESS_N_M,
                            column.stiffness_N_m)
        code = {"asce7_scale": "the study's laboratory container and column"}
    if height is None:
        height, height_source = STUDY_MEAN_HEIGHT_M, f"the study's mean contact height ({STUDY_MEAN_HEIGHT_M:g} m)"
    r = column_impact(law, args.velocity, height, column=column, obliquity_deg=args.obliquity, **body)
    emit(
        {
            "peak_force_N": r.peak_force_N,
            "duration_s": r.duration_s,
            "impulse_Ns": r.impulse_Ns,
            "restitution": r.restitution,
            "peak_base_shear_N": abs(r.base_shear.peak_N),
            "contact_law": law.name,
            "stiffness_N_m": law.stiffness_N_m,
            "damping_ratio": law.damping_ratio,
            "height_m": height,
            "height_source": height_source,
            "obliquity_deg": args.obliquity,
            **asce7_lines(asce, "asce7_"),
            **code,
        },
        args.json,
    )
    return EXIT_OK


def cmd_contact_law(args: argparse.Namespace) -> int:
    from orchestrator.report.contact_report import write_contact_law_report

    if args.strikes < 2:
        raise InputError("--strikes", f"must be >= 2, got {args.strikes}")
    if args.workers < 1:
        raise InputError("--workers", f"must be >= 1, got {args.workers}")
    out = output_path(args.out, "-o/--out", args.force, folder=True)
    summary = write_contact_law_report(out, count=args.strikes, ensemble=args.ensemble, workers=args.workers)
    cal = summary["calibration"]
    emit({"stiffness_N_m": cal["fitted_law"]["stiffness_N_m"], "damping_ratio": cal["fitted_law"]["damping_ratio"],
           "table1_peak_force_N": cal["fitted_pulse"]["peak_force_N"],
           "table1_duration_s": cal["fitted_pulse"]["duration_s"], "out": str(args.out)}, args.json)
    return EXIT_OK


def cmd_modes(args: argparse.Namespace) -> int:
    from analytical.mdof import column_model

    if args.count < 1:
        raise InputError("--count", f"must be a whole number >= 1 of frequencies, got {args.count}")
    column = column_from_args(args)
    model = column_model(column)
    result: dict[str, Any] = {"frequencies_Hz": [float(f) for f in model.frequencies_Hz[: args.count]]}
    result["base"] = column.base
    if model.base_spring_Nm_rad is not None:
        result["base_spring_Nm_per_rad"] = float(model.base_spring_Nm_rad)
    emit(result, args.json)
    return EXIT_OK


def cmd_response(args: argparse.Namespace) -> int:
    from orchestrator.core.errors import require_positive
    from analytical.pulses import make_pulse

    magnitude = require_positive("--magnitude", args.magnitude)
    duration = require_positive("--duration", args.duration)
    t_end = require_positive("--t-end", args.t_end)
    out = output_path(args.out, "--out", args.force, folder=False) if args.out else None
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
    if out is not None:
        import pandas as pd

        out.parent.mkdir(parents=True, exist_ok=True)
        pd.DataFrame({"time_s": response.time_s, "response_N": response.response_N}).to_csv(out, index=False)
    emit({"peak_N": float(response.peak_N), "time_of_peak_s": float(response.time_of_peak_s)}, args.json)
    return EXIT_OK


def cmd_fit(args: argparse.Namespace) -> int:
    from analytical.fitting import fit_mdof, fit_sdof

    from orchestrator.results.force_records import read_force_record

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
        "baseline_N": fit.baseline_N,
        "start_s": fit.start_s,
        "earliest_start_s": fit.earliest_start_s,
        "natural_frequency_Hz": fit.natural_frequency_Hz,
        "damping_ratio": fit.damping_ratio,
        "stiffness_N_m": fit.stiffness_N_m,
        "height_m": fit.height_m,
    }
    ident = fit.duration_identifiability
    if ident is not None:
        result["duration_identifiable"] = ident.identifiable
        result["duration_interval_95_s"] = list(ident.interval_s)
        result["jacobian_condition_number"] = ident.condition_number
    emit({k: v for k, v in result.items() if v is not None}, args.json)
    peak = fit.peak_measured_N - fit.offset_N  # the record's peak above the fitted offset
    if fit.rmse_N > POOR_FIT_RMSE_FRACTION * peak:
        warn([f"poor fit: RMSE {fit.rmse_N:.3g} N is {100 * fit.rmse_N / peak:.0f} % of the record's peak above the "
              f"fitted offset, {peak:.4g} N (over {100 * POOR_FIT_RMSE_FRACTION:.0f} %): the {args.model} model "
              "does not describe this record well"])
    if ident is not None and not ident.identifiable:
        lo, hi = ident.interval_s
        from analytical.fitting import DURATION_BOUNDS_S

        ends = [f"{1e3 * v:.3g} ms" + (" (the search limit)" if v in (lo, hi) and abs(v - b) < 1e-12 * b + 1e-9 else "")
                for v, b in ((lo, DURATION_BOUNDS_S[0]), (hi, DURATION_BOUNDS_S[1]))]
        warn([f"the duration is not fixed by this record: durations from {ends[0]} to {ends[1]} fit within the 95 % "
              "profile interval (the record fixes the impulse; magnitude and duration only together)"])
    return EXIT_OK


def cmd_dambreak(args: argparse.Namespace) -> int:
    import numpy as np

    from analytical.dambreak import dam_break

    if args.points < 2:
        raise InputError("--points", f"must be >= 2 (a profile needs two points at least), got {args.points}")
    out = output_path(args.out, "--out", args.force, folder=False) if args.out and args.arrival is None else None
    solution = dam_break(args.model, args.h0, hr_m=args.hr, friction=args.friction)
    if args.arrival is not None:
        if not args.arrival > 0:
            raise InputError("--arrival", f"must be downstream of the gate (x > 0 m, where the front arrives), got "
                                          f"{args.arrival}")
        emit({"arrival_s": float(solution.arrival_time_s(args.arrival))}, args.json)
        return EXIT_OK
    if args.profile is None or out is None:
        raise InputError("--arrival/--profile", "give --arrival X, or --profile T with --out CSV")
    t = args.profile
    x_front = float(solution.front_position_m(t))
    x_back = -np.sqrt(9.81 * args.h0) * t
    x = np.linspace(min(x_back * 1.2, -0.1), max(x_front * 1.2, 0.1), args.points)
    depth, velocity = solution.profile(x, t)
    import pandas as pd

    out.parent.mkdir(parents=True, exist_ok=True)
    pd.DataFrame({"x_m": x, "depth_m": depth, "velocity_m_s": velocity}).to_csv(out, index=False)
    emit({"front_position_m": x_front, "csv": str(out)}, args.json)
    return EXIT_OK


def cmd_study(args: argparse.Namespace) -> int:
    from orchestrator.studies.synthetic import run_synthetic_study

    if args.records < 2:
        raise InputError("--records", f"must be >= 2 (a mean and a spread need two records), got {args.records}")
    out = output_path(args.out, "-o/--out", args.force, folder=True)
    summary = run_synthetic_study(out, seed=args.seed, n_records=args.records, column_base=args.base)
    emit(summary, args.json)
    return EXIT_OK


def _add_column_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scene", type=resolve_scene, help="scene YAML (or a shipped scene's name) whose column to use "
                                                       "(default: the study's column)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a dotted scene key (repeatable)")


def add_analytical_parser(verbs) -> None:
    """The ``analytical`` verb and its sub-verbs, on the top parser's ``verbs``."""
    from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M as STUDY_KD
    from analytical.study import STUDY_STRUCTURE_STIFFNESS_N_M as STUDY_KS

    an = verbs.add_parser("analytical", help="analytical models (ASCE 7-22, SDOF, MDOF, fitting, dam break)")
    an_verbs = an.add_subparsers(dest="analytical_verb", required=True, parser_class=ArgParser)

    p = an_verbs.add_parser("asce7", help="ASCE 7-22 6.11 debris impact force, duration and impulse")
    p.add_argument("--velocity", type=float, required=True,
                   help="u_max, the flow's maximum velocity at the site, m/s (the study used the impact speed; at most "
                        "30 m/s)")
    p.add_argument("--mass", type=float, default=None,
                   help="debris mass m_d, kg (required without --scene; with it, the heaviest its design draws)")
    p.add_argument("--debris-stiffness", type=float, default=None, metavar="K_D",
                   help=f"k_d, the debris' effective stiffness, N/m (default: the scene's; without --scene at "
                        f"laboratory scale {STUDY_KD:.4g}, the study's 1:40 container; required at full scale)")
    p.add_argument("--structure-stiffness", type=float, default=None, metavar="K_S",
                   help=f"k_s, the struck element's lateral stiffness, N/m (default: the scene's column; without "
                        f"--scene at laboratory scale {STUDY_KS:.4g}, the study's column; required at full scale); "
                        "the lesser of k_d and k_s governs")
    p.add_argument("--stiffness", type=float, default=None,
                   help="one stiffness k, N/m, used as it is (instead of the lesser of k_d and k_s)")
    p.add_argument("--importance", type=float, default=None,
                   help="I_tsu: 1.0 (tsunami risk category II, the default without --scene) or 1.25 (III, IV); with "
                        "--scene, its design.risk_category's")
    p.add_argument("--orientation", type=float, default=None,
                   help="C_o (default 0.65, logs, poles, containers; with --scene, its design.orientation_coefficient)")
    p.add_argument("--prototype", action="store_true",
                   help="the inputs are full scale (also implied by a mass of 100 kg or more, or a full-scale "
                        "--scene): F_i is bounded by the simplified static load 1,470 C_o I_tsu kN, and k_s and k_d "
                        "must be given")
    p.add_argument("--scene", type=resolve_scene,
                   help="scene YAML (or a shipped scene's name): its column, debris and design section give m_d, k_d, "
                        "k_s, I_tsu, C_o and the scale, as `debrisfoam design` reads them; flags override")
    p.add_argument("--body", help="which debris body of --scene (default: all; the heaviest governs)")
    closing_options(p, cmd_asce7, overrides="override a dotted scene key (with --scene)")

    p = an_verbs.add_parser("impact", help="one debris strike on the column by the contact law: pulse, rebound, "
                                           "base shear (docs/contact-law.md)")
    p.add_argument("--velocity", type=float, required=True, help="the body's speed at the strike, m/s")
    p.add_argument("--height", type=float, default=None,
                   help="contact height above the column's base, m (default: with --scene its "
                        "column.strike_height_m or inundation.depth_m, as `design` reads them; else 0.40, the study's mean)")
    p.add_argument("--obliquity", type=float, default=0.0,
                   help="angle of the body's velocity from the face's normal, degrees (default 0, head on)")
    p.add_argument("--scene", type=resolve_scene, help="scene YAML (or a shipped scene's name) whose debris body and "
                                                       "column to use (default: the study's "
                                   "0.236 kg container and acrylic column)")
    p.add_argument("--body", help="which debris body of --scene (default: its first)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a dotted scene key (repeatable); without --scene: column.<field> or "
                        "contact.<field>, e.g. contact.law=asce7_kd, contact.restitution=0.5")
    closing_options(p, cmd_impact)

    p = an_verbs.add_parser("contact-law", help="calibrate the container's contact law on the study's Table 2 "
                                                "(22 impacts) and check it on its Table 1 event, to files")
    p.add_argument("-o", "--out", default="docs/results/contact-law",
                   help="output folder (default docs/results/contact-law)")
    p.add_argument("--strikes", type=int, default=32, help="strikes of the calibration (default 32)")
    p.add_argument("--ensemble", help="ensemble.csv: calibrate on its first strikes' effective masses and heights")
    p.add_argument("--workers", type=int, default=2, help="processes running the fit's starts (default 2)")
    closing_options(p, cmd_contact_law, force=FOLDER_FORCE_HELP)

    p = an_verbs.add_parser("modes", help="natural frequencies of the MDOF column")
    _add_column_args(p)
    p.add_argument("--count", type=int, default=6, help="how many frequencies to print (default 6)")
    closing_options(p, cmd_modes)

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
    closing_options(p, cmd_response)

    p = an_verbs.add_parser("fit", help="fit an impact pulse to a measured force-response record (CSV time_s,force_N "
                                        "or time_s,response_N)")
    p.add_argument("--model", choices=["sdof", "mdof"], required=True,
                   help="sdof: fit magnitude, duration, damping, stiffness, frequency within the study's bounds; "
                        "mdof: magnitude and duration on the column model")
    p.add_argument("record", help="CSV with columns time_s,force_N (or time_s,response_N, as response --out "
                                  "writes)")
    p.add_argument("--pulse", choices=["half-sine", "rectangular", "triangular"], default="half-sine",
                   help="pulse shape fitted")
    p.add_argument("--height", type=float, default=0.40, help="impact height above the column base, m (mdof)")
    _add_column_args(p)
    closing_options(p, cmd_fit)

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
    closing_options(p, cmd_dambreak, force="overwrite an existing --out file")

    p = an_verbs.add_parser("study", help="the study's SDOF/MDOF/ASCE analysis on synthetic records (Table 2, Fig. 7)")
    p.add_argument("-o", "--out", default="docs/results/synthetic-study", help="output folder (tables and plots)")
    p.add_argument("--records", type=int, default=22, help="number of synthetic records (default 22, as the study)")
    p.add_argument("--seed", type=int, default=2019, help="random seed")
    p.add_argument("--base", choices=["rigid", "calibrated"], default="rigid", help="column base model of the records")
    closing_options(p, cmd_study, force=FOLDER_FORCE_HELP)
