"""overInterDyMFoam settings on a small one-debris case: cost against the debris track, column force and water balance.

A small dam break (0.5 m x 0.25 m reservoir, 0.12 m wet bed, 0.4 m wide flume, 0.1 m column at
x = 1.2 m, 4 cm cells) carries one 1:40 container (0.15 x 0.06 x 0.06 m, 0.236 kg) floating at
x = 0.35 m towards the column; 1.0 s simulated (--end-time; the bore reaches the column at about
0.55 s, so its force peaks inside the run), 2 ranks, run by
`orchestrator.run.runner.run_case`. The body mesh is the scene defaults' (4 cells across the body's
smallest side, a 3-cell margin) and debris scenes run at maxCo 2.5 (v1912's overset Courant
number counts hole/fringe faces). Each setting changes the rendered case before the run:

- overset interpolation (fvSchemes oversetInterpolation method): cellVolumeWeight or
  inverseDistance (trackingInverseDistance crashes in parallel: docs/openfoam-notes.md);
- PIMPLE nOuterCorrectors / nCorrectors;
- p_rgh tolerance / relTol and p_rghFinal relTol (PBiCGStab + DILU; GAMG fails with overset);
- body mesh size (scene mesh.body_cells_across: cells across the body's smallest side);
- maxCo (scene run.max_courant: maxCo and maxAlphaCo).

Errors against the most careful setting ("reference"): the debris track (the largest
distance between the two centres of mass at the same time, over the reference's largest
displacement), the column force (x, pressure + viscous: peak, and RMS of the difference over
the reference's peak, at the reference's samples); and, on its own, the water balance of each
run (`orchestrator.case.outputs.read_water_balance`: the largest relative water created (+) or lost (-)).

Also measured: the runner's own cost (its CPU time over the solver's wall time, and the
solver wall time of a bare `mpirun` against `run_case` with the progress bar drawn).

Run:  nice -n 15 .venv/bin/python benchmarks/runner_settings.py [--only NAME ...] [--from DIR] [--keep] [--end-time S]
      (1.0 s: about 20 min on an idle 2-core machine, twice that sharing it; --keep or --from DIR lets an
      interrupted run be resumed with --from)
Writes benchmarks/runner_settings.md next to this script (and prints it).
"""

from __future__ import annotations

import argparse
import dataclasses
import io
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from orchestrator.case.dictionary import edit_dictionary  # noqa: E402
from orchestrator.case import foam  # noqa: E402
from orchestrator.case.outputs import read_force_series, read_water_balance, water_balance_summary  # noqa: E402
from orchestrator.pipeline import render_from_file  # noqa: E402
from orchestrator.run import openfoam  # noqa: E402
from orchestrator.run.runner import RunInterrupted, load_case_info, run_case  # noqa: E402

HERE = Path(__file__).resolve().parent
OUT = HERE / "runner_settings.md"
END_TIME_S = 1.0
#: simulated time of the overhead runs (bare mpirun against run_case, alternated; at most --end-time)
OVERHEAD_END_S = 0.3
OVERHEAD_REPEATS = 2
#: track, force peak and force RMS errors against the reference (fractions of the reference's figures)
TOLERANCE = 0.02
#: |water created or lost| / the water at the start, at its largest over the run
WATER_TOLERANCE = 0.01

SCENE = {
    "name": "bench1",
    "flume": {"length_m": 2.4, "width_m": 0.4, "height_m": 0.3, "downstream_end": "closed"},
    "reservoir": {"length_m": 0.5, "depth_m": 0.25},
    "bed": {"wet_depth_m": 0.12, "friction_factor": 0.0},
    "column": {"x_m": 1.2, "y_m": 0.0, "size_x_m": 0.1, "size_y_m": 0.1, "height_m": 0.3, "wall_thickness_m": 0.005,
               "youngs_modulus_Pa": 2.5e9, "density_kg_m3": 1200, "poisson_ratio": 0.375, "shear_coefficient": 0.5},
    "debris": [{"name": "debris1", "size_m": [0.15, 0.06, 0.06], "mass_kg": 0.236, "wall_thickness_m": 0.005,
                "centre_m": [0.35, 0.0], "placement": "floating"}],
    "gauges": [{"name": "WG1", "x_m": 0.8, "y_m": 0.1}],
    # the scene defaults, written out: 4 body cells across the smallest side, a 3-cell margin
    "mesh": {"cell_size_m": 0.04, "coarsening_ratio": 1, "body_margin_cells": 3, "body_cells_across": 4},
    "run": {"end_time_s": END_TIME_S, "cores": 2, "write_interval_s": 0.1, "max_courant": 2.5},
    "outputs": {"probe_interval_s": None, "preview": False},
}


@dataclass(frozen=True)
class Setting:
    """One set of levers; the field defaults are the reference (the most careful setting)."""

    name: str
    interpolation: str = "cellVolumeWeight"
    n_outer: int = 2
    n_corr: int = 3
    tolerance: float = 1e-8
    rel_tol: float = 0.0
    final_rel_tol: float = 0.0
    body_cells_across: float = 4.0
    max_courant: float = 0.9

    def describe(self) -> str:
        return (f"{self.interpolation}, outer {self.n_outer}, corr {self.n_corr}, p_rgh {self.tolerance:g}/"
                f"{self.rel_tol:g} (final {self.final_rel_tol:g}), body {self.body_cells_across:g} cells, "
                f"maxCo {self.max_courant:g}")


REFERENCE = Setting("reference")
#: what the templates render for overInterDyMFoam (Numerics.for_solver), at the debris scenes' maxCo
DEFAULT = Setting("default", n_outer=1, n_corr=2, tolerance=1e-7, rel_tol=0.05, final_rel_tol=0.05,
                  body_cells_across=4.0, max_courant=2.5)
SETTINGS = [
    REFERENCE,
    DEFAULT,
    dataclasses.replace(DEFAULT, name="corr1", n_corr=1),  # the old default: creates water
    dataclasses.replace(DEFAULT, name="corr1-final0", n_corr=1, final_rel_tol=0.0),
    dataclasses.replace(DEFAULT, name="maxco0.9", max_courant=0.9),
    dataclasses.replace(DEFAULT, name="body3", body_cells_across=3.0),
    dataclasses.replace(DEFAULT, name="outer2", n_outer=2),
    dataclasses.replace(DEFAULT, name="inverseDistance", interpolation="inverseDistance"),
    # one lever of the reference made cheaper (the default's levers all moved the force by more than 2 %)
    dataclasses.replace(REFERENCE, name="ref-outer1", n_outer=1),
    dataclasses.replace(REFERENCE, name="ref-corr2", n_corr=2),
    dataclasses.replace(REFERENCE, name="ref-tol", tolerance=1e-7, rel_tol=0.05),
]


def prepare(setting: Setting, root: Path, end_time_s: float = END_TIME_S) -> Path:
    scene = json.loads(json.dumps(SCENE))
    scene["mesh"]["body_cells_across"] = setting.body_cells_across
    scene["run"]["max_courant"] = setting.max_courant
    scene["run"]["end_time_s"] = end_time_s
    root.mkdir(parents=True, exist_ok=True)
    path = root / f"{setting.name}.yaml"
    path.write_text(yaml.safe_dump(scene))
    case = root / setting.name
    render_from_file(path, case)
    with edit_dictionary(case / "system" / "fvSolution") as sol:
        sol["PIMPLE"]["nOuterCorrectors"] = setting.n_outer
        sol["PIMPLE"]["nCorrectors"] = setting.n_corr
        sol["solvers"]["p_rgh"]["tolerance"] = setting.tolerance
        sol["solvers"]["p_rgh"]["relTol"] = setting.rel_tol
        sol["solvers"]["p_rghFinal"]["relTol"] = setting.final_rel_tol
    with edit_dictionary(case / "system" / "fvSchemes") as schemes:
        schemes["oversetInterpolation"]["method"] = setting.interpolation
    return case


def track(case: Path) -> tuple[np.ndarray, np.ndarray]:
    import pandas as pd

    df = pd.read_csv(case / "bodies.csv")
    df = df[df.body == "debris1"].drop_duplicates("time_s", keep="last").sort_values("time_s")
    return df.time_s.to_numpy(), df[["x_m", "y_m", "z_m"]].to_numpy()


def force_x(case: Path) -> tuple[np.ndarray, np.ndarray]:
    """The column's x force (pressure + viscous) over every segment of the run."""
    frame, _ = read_force_series(case)
    if frame is None or frame.empty:
        return np.array([]), np.array([])
    return frame["time"].to_numpy(float), frame["total_x"].to_numpy(float)


def compare(case: Path, ref: Path) -> dict[str, float]:
    """Track and column-force errors of `case` against `ref` (NaN where a run has too little to compare)."""
    nan = float("nan")
    out = {"travel_m": nan, "track_err": nan, "end_dx_m": nan, "force_peak_N": nan, "force_peak_err": nan,
           "force_rms_err": nan}
    t_ref, p_ref = track(ref)
    t, p = track(case)
    if len(t) and len(t_ref):
        common = t_ref[(t_ref >= t[0]) & (t_ref <= t[-1])]
        travel = np.linalg.norm(p_ref - p_ref[0], axis=1).max()
        out["travel_m"] = float(travel)
        if len(common):
            p_ref_c = np.column_stack([np.interp(common, t_ref, p_ref[:, i]) for i in range(3)])
            p_c = np.column_stack([np.interp(common, t, p[:, i]) for i in range(3)])
            dist = np.linalg.norm(p_c - p_ref_c, axis=1).max()
            out["track_err"] = float(dist / travel) if travel > 0 else (0.0 if dist == 0 else nan)
            out["end_dx_m"] = float(p_c[-1, 0] - p_ref_c[-1, 0])
    tf_ref, f_ref = force_x(ref)
    tf, f = force_x(case)
    if len(tf) and len(tf_ref):
        f_on_ref = np.interp(tf_ref, tf, f)
        peak = np.abs(f_ref).max()
        out["force_peak_N"] = float(np.abs(f).max())
        if peak > 0:
            out["force_peak_err"] = float((np.abs(f).max() - peak) / peak)
            out["force_rms_err"] = float(np.sqrt(np.mean((f_on_ref - f_ref) ** 2)) / peak)
    return out


def solver_cpu_s(case: Path, solver: str = "overInterDyMFoam") -> float:
    """The solver's own time over all segments: the last ExecutionTime (rank 0 CPU s) of each log.

    Less sensitive than wall time to other jobs sharing the 2 cores (MPI waits spin, so it
    still includes some of the load)."""
    total = 0.0
    for log in [*case.glob(f"log.{solver}.*"), case / f"log.{solver}"]:
        if log.is_file():
            times = [float(ln.split()[2]) for ln in log.read_text(errors="replace").splitlines()
                     if ln.startswith("ExecutionTime = ")]
            total += times[-1] if times else 0.0
    return total


def water_error(case: Path) -> float:
    """The run's largest relative water error (signed: > 0 created), NaN without a water balance."""
    summary = water_balance_summary(read_water_balance(case))
    return float(summary["max_error"]) if summary else float("nan")


def bench_record(case: Path) -> dict:
    """What run_setting noted about the run (the load average at its start)."""
    path = case / "bench.json"
    return json.loads(path.read_text()) if path.is_file() else {}


def collect(setting: Setting, case: Path) -> dict:
    """A finished setting's figures, from its case directory."""
    record = json.loads((case / "run.json").read_text())
    cells = int(record["cells"]["total"])
    steps = int(record["time_steps"])
    wall = sum(seg["wall_s"] for seg in record["segments"])
    cpu = solver_cpu_s(case)
    return {
        "setting": setting,
        "case": case,
        "cells": cells,
        "steps": steps,
        "solver_wall_s": wall,
        "solver_cpu_s": cpu,
        "us_per_cell_step": 1e6 * cpu / (cells * steps) if steps else float("nan"),
        "segments": len(record["segments"]),
        "contacts": int(record.get("contacts", 0)),
        "overhead": float(record["runner"]["overhead_fraction"]),
        "load": float(bench_record(case).get("load_start", float("nan"))),
        "water_err": water_error(case),
    }


def run_setting(setting: Setting, root: Path, end_time_s: float) -> dict:
    """Run one setting (a failure is a result: its row says why)."""
    from analytical.errors import DebrisfoamError

    case = prepare(setting, root, end_time_s)
    (case / "bench.json").write_text(json.dumps({"load_start": os.getloadavg()[0], "started": time.time()}))
    try:
        run_case(case, quiet=True, reconstruct="none")
    except RunInterrupted:
        raise
    except DebrisfoamError as exc:
        (case / "failed.txt").write_text(str(exc))
    return load_result(setting, case)


def load_result(setting: Setting, case: Path) -> dict:
    failed = case / "failed.txt"
    if failed.is_file():
        return {"setting": setting, "case": case, "failed": failed.read_text().splitlines()[0],
                "load": float(bench_record(case).get("load_start", float("nan"))), "water_err": water_error(case)}
    return collect(setting, case)


def finished(case: Path, end_time_s: float) -> bool:
    """A setting's case from an earlier run that can be reused: failed, or finished at this end time."""
    if (case / "failed.txt").is_file():
        return True
    if not (case / "run.json").is_file():
        return False
    record = json.loads((case / "run.json").read_text())
    return record.get("status") == "finished" and abs(float(record.get("end_time_s", -1)) - end_time_s) < 1e-9


def _bare_run(case: Path) -> float:
    """Solver wall time of a bare `mpirun -np 2 overInterDyMFoam -parallel` (no runner)."""
    info = load_case_info(case)
    for step in foam.mesh_steps(case, info.plan) + foam.solve_steps(case, info.plan, 2)[:1]:
        openfoam.run_step(step.name, step.argv, case, np=step.np, done=step.done)
    env = openfoam.foam_env()
    env["PWD"] = str(case)
    t0 = time.perf_counter()
    with open(case / "log.bare", "w") as out:
        subprocess.run(foam.parallel_argv(["overInterDyMFoam"], 2), cwd=case, stdout=out, stderr=subprocess.STDOUT,
                       env=env, check=True)
    wall = time.perf_counter() - t0
    (case / "bare.json").write_text(json.dumps({"solver_wall_s": wall, "load": os.getloadavg()[0],
                                                "end_time_s": info.end_time_s}))
    return wall


def overhead_runs(setting: Setting, root: Path, end_s: float) -> list[dict]:
    """Bare mpirun, run_case quiet and run_case with the bar drawn, alternated, on a short run."""
    out = []
    for k in range(OVERHEAD_REPEATS):
        for mode in ("bare", "quiet", "bar"):
            case = prepare(setting, root / f"overhead-{mode}-{k}")
            _set_end(case, end_s)
            if mode == "bare":
                _bare_run(case)
            else:
                run_case(case, quiet=mode == "quiet", reconstruct="none", stream=io.StringIO())
            out.append(overhead_figures(case, mode))
    return out


def overhead_done(case: Path, end_s: float) -> bool:
    """An overhead run from an earlier run of this script, at this end time, that can be reused."""
    if (case / "bare.json").is_file():
        return abs(float(json.loads((case / "bare.json").read_text()).get("end_time_s", -1)) - end_s) < 1e-9
    return finished(case, end_s) and not (case / "failed.txt").is_file()


def overhead_figures(case: Path, mode: str) -> dict:
    if mode == "bare":
        bare = json.loads((case / "bare.json").read_text())
        return {"mode": mode, "solver_wall_s": bare["solver_wall_s"], "overhead": None, "load": bare["load"]}
    record = json.loads((case / "run.json").read_text())
    return {"mode": mode, "solver_wall_s": sum(seg["wall_s"] for seg in record["segments"]),
            "overhead": float(record["runner"]["overhead_fraction"]), "load": float("nan")}


def _set_end(case: Path, end_s: float) -> None:
    with edit_dictionary(case / "system" / "controlDict") as control:
        control["endTime"] = end_s


def templates_default_note() -> str:
    """'' when DEFAULT is what the templates render for overInterDyMFoam, else a sentence saying how they differ."""
    from orchestrator.case.render import Numerics

    n = Numerics.for_solver("overInterDyMFoam", DEFAULT.max_courant)
    rendered = Setting("templates", interpolation=n.overset_interpolation, n_outer=n.n_outer_correctors,
                       n_corr=n.n_correctors, tolerance=n.p_rgh_tolerance, rel_tol=n.p_rgh_rel_tol,
                       final_rel_tol=n.p_rgh_final_rel_tol, body_cells_across=DEFAULT.body_cells_across,
                       max_courant=DEFAULT.max_courant)
    if rendered == dataclasses.replace(DEFAULT, name="templates"):
        return ""
    return (f"Note: when this ran, the templates rendered {rendered.describe()} for overInterDyMFoam "
            "(`Numerics.for_solver`), not `default`'s numerics.")


def within(r: dict, reference: dict) -> bool:
    """Within the tolerances: track, force peak and force RMS <= TOLERANCE, and a water balance no
    further than WATER_TOLERANCE from the reference's (the overset interpolation itself is not
    conservative: the reference loses water too, so a setting is judged on what it adds).

    A NaN figure (nothing to compare) is not within."""
    if "failed" in r:
        return False
    figures = [r["track_err"], abs(r["force_peak_err"]), r["force_rms_err"]]
    water = r["water_err"] - reference["water_err"]
    return (all(math.isfinite(v) and v <= TOLERANCE for v in figures)
            and math.isfinite(water) and abs(water) <= WATER_TOLERANCE)


def _pct(value: float, fmt: str = ".2f") -> str:
    return "-" if not math.isfinite(value) else f"{100 * value:{fmt}} %"


def _num(value: float, fmt: str) -> str:
    return "-" if not math.isfinite(value) else f"{value:{fmt}}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="setting names to run (default all; the reference always runs)")
    parser.add_argument("--keep", action="store_true", help="keep the cases (printed)")
    parser.add_argument("--from", dest="source", help="a folder of an earlier run: reuse its finished cases, run the rest")
    parser.add_argument("--end-time", type=float, default=END_TIME_S, metavar="S",
                        help=f"simulated time of each setting (s, default {END_TIME_S}); the overhead runs take "
                        f"the smaller of this and {OVERHEAD_END_S} s")
    args = parser.parse_args()
    end_time = float(args.end_time)
    overhead_end = min(OVERHEAD_END_S, end_time)
    names = {s.name for s in SETTINGS}
    unknown = sorted(set(args.only or ()) - names)
    if unknown:
        parser.error(f"unknown setting(s) {', '.join(unknown)}; known: {', '.join(s.name for s in SETTINGS)}")
    settings = [s for s in SETTINGS if not args.only or s.name in args.only or s.name == "reference"]
    note = templates_default_note()
    if note:
        print(note, flush=True)
    t_start = time.time()
    results = []
    root = Path(args.source) if args.source else Path(tempfile.mkdtemp(prefix="runner-settings-"))
    print(f"cases in {root}; load average {os.getloadavg()[0]:.1f}", flush=True)
    for s in settings:
        case = root / s.name
        if finished(case, end_time):
            results.append(load_result(s, case))
            continue
        if case.exists():
            shutil.rmtree(case)
        print(f"running {s.name}: {s.describe()} (load average {os.getloadavg()[0]:.1f})", flush=True)
        r = run_setting(s, root, end_time)
        head = f"failed: {r['failed']}" if "failed" in r else (
            f"{r['steps']} steps, solver CPU {r['solver_cpu_s']:.1f} s")
        print(f"  {head}, water {_pct(r.get('water_err', float('nan')), '+.3f')}", flush=True)
        results.append(r)
    reference = results[0]
    if "failed" in reference:
        raise SystemExit(f"the reference failed ({reference['failed']}): nothing to compare against; cases in {root}")
    ref = reference["case"]
    for r in results:
        if "failed" not in r:
            r.update(compare(r["case"], ref))

    ok = [r for r in results if within(r, reference)]
    # the cost of simulating the same time: fewer correctors can mean smaller (Courant-limited) steps
    # the reference is within its own criteria unless a figure of it is missing (NaN)
    chosen = min(ok, key=lambda r: r["solver_cpu_s"]) if ok else reference

    kept = [root / f"overhead-{mode}-{k}" / chosen["setting"].name
            for k in range(OVERHEAD_REPEATS) for mode in ("bare", "quiet", "bar")]
    if all(overhead_done(p, overhead_end) for p in kept):
        overhead = [overhead_figures(p, p.parent.name.split("-")[1]) for p in kept]
    else:
        print("measuring the runner's overhead (bare mpirun, run_case quiet, run_case with the bar)", flush=True)
        for p in kept:
            shutil.rmtree(p, ignore_errors=True)
        overhead = overhead_runs(chosen["setting"], root, overhead_end)

    load_end = os.getloadavg()[0]
    loads = [r["load"] for r in results if math.isfinite(r.get("load", float("nan")))]
    load_text = (f"the 1-minute load average was {min(loads):.1f}-{max(loads):.1f} at the settings' starts (column "
                 f"`load`) and {load_end:.1f} when this page was written" if loads else
                 f"the 1-minute load average was {load_end:.1f} when this page was written (not recorded at the "
                 "settings' starts)")
    lines = [
        "# overInterDyMFoam settings and the runner's overhead",
        "",
        f"Generated by `benchmarks/runner_settings.py` (OpenFOAM v1912, 2 ranks, Python {platform.python_version()}, "
        f"{platform.machine()}) on {time.strftime('%Y-%m-%d', time.localtime(t_start))}. The machine has "
        f"{os.cpu_count()} cores and was shared with other OpenFOAM runs: {load_text}. A load above about 2 means "
        "the ranks shared the cores with other work, so wall times scatter and CPU times are inflated by MPI's "
        "busy waits. The cost compared is the solver's CPU time for the whole simulated time (ExecutionTime of "
        "rank 0, all segments): settings with fewer correctors are cheaper per step but can need more "
        "(Courant-limited) steps.",
        "",
        f"Case: a {SCENE['reservoir']['length_m']} m x {SCENE['reservoir']['depth_m']} m reservoir released over a "
        f"{SCENE['bed']['wet_depth_m']} m wet bed in a {SCENE['flume']['width_m']} m wide flume, column "
        f"{SCENE['column']['size_x_m']} m square at x = {SCENE['column']['x_m']} m, one container "
        "(0.15 x 0.06 x 0.06 m, 0.236 kg) floating at x = 0.35 m, 4 cm background cells, an overset body mesh "
        f"{SCENE['mesh']['body_cells_across']:g} cells across the container's smallest side (unless the setting "
        f"says otherwise) with a {SCENE['mesh']['body_margin_cells']}-cell margin (the scene defaults), "
        f"{end_time:g} s simulated, run by `run_case` (contact on).",
        "",
        "Settings: `reference` is the most careful; `default` is what the templates render for overInterDyMFoam "
        f"(`Numerics.for_solver`) at the debris scenes' maxCo {SCENE['run']['max_courant']:g}; every other setting "
        "is `default` with one lever changed (`corr1`, one pressure corrector, creates water: docs/openfoam-notes.md, \"Pressure and flux\"), "
        "and each `ref-*` setting is `reference` with one lever made cheaper."
        + (" " + note if note else ""),
        "",
        "Criteria (a setting is \"within\" when all four hold):",
        "",
        f"- track err <= {100 * TOLERANCE:g} %: the largest distance between the debris' centre of mass and the "
        "reference's at equal times, over the reference's largest displacement;",
        f"- |peak err| <= {100 * TOLERANCE:g} %: the column's peak x force (pressure + viscous) minus the "
        "reference's, over the reference's peak;",
        f"- RMS err <= {100 * TOLERANCE:g} %: the RMS of the column-force difference at the reference's samples, "
        "over the reference's peak;",
        f"- |water err - the reference's| <= {100 * WATER_TOLERANCE:g} % of the water: water err is the run's own "
        "water balance, (water volume + water let out - water at the start) / water at the start, at its largest "
        "magnitude over the run, signed (> 0: water created). It is judged against the reference's because the "
        "overset interpolation is not conservative: the most careful setting loses water too (see below).",
        "",
        "The chosen setting is the cheapest (solver CPU) of those within.",
        "",
        "| setting | settings | load | cells | steps | solver CPU (s) | solver wall (s) | us/cell-step | track err | "
        "end dx (mm) | force peak (N) | peak err | RMS err | water err | within |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in results:
        load = _num(r.get("load", float("nan")), ".1f")
        if "failed" in r:
            lines.append(f"| {r['setting'].name} | {r['setting'].describe()} | {load} | | | | | | "
                         f"failed: {r['failed']} | | | | | {_pct(r['water_err'], '+.3f')} | no |")
            continue
        lines.append(
            f"| {r['setting'].name} | {r['setting'].describe()} | {load} | {r['cells']} | {r['steps']} | "
            f"{r['solver_cpu_s']:.1f} | {r['solver_wall_s']:.1f} | {_num(r['us_per_cell_step'], '.1f')} | "
            f"{_pct(r['track_err'])} | {_num(1000 * r['end_dx_m'], '+.2f')} | {_num(r['force_peak_N'], '.3f')} | "
            f"{_pct(r['force_peak_err'], '+.2f')} | {_pct(r['force_rms_err'])} | {_pct(r['water_err'], '+.3f')} | "
            f"{'yes' if r in ok else 'no'} |")
    failed = ", ".join(r["setting"].name for r in results if "failed" in r) or "none"
    if chosen is reference:
        verdict = ("**No cheaper setting is within the criteria: keep the reference's settings for this mesh.** "
                   f"Failed settings: {failed}.")
    else:
        verdict = (f"**Chosen: `{chosen['setting'].name}`** ({chosen['setting'].describe()}): the cheapest setting "
                   f"within the criteria, {reference['solver_cpu_s'] / chosen['solver_cpu_s']:.2f}x cheaper than the "
                   f"reference in solver CPU. Failed settings: {failed}.")
    lines += [
        "",
        f"Reference travel of the debris: {_num(reference['travel_m'], '.3f')} m; reference peak column force "
        f"{_num(reference['force_peak_N'], '.3f')} N; reference water balance {_pct(reference['water_err'], '+.2f')}"
        + (" (beyond the 1 % that post-processing flags: on this case no setting of the solver's controls "
           "closes the balance; the loss comes with the container crossing the free surface as the reservoir "
           "empties, which the overset mesh's non-conservative interpolation does not carry exactly)."
           if abs(reference["water_err"]) > WATER_TOLERANCE else "."),
        "",
        verdict,
        "",
        f"Time steps for the same {end_time:g} s: "
        + ", ".join(f"{r['setting'].name} {r['steps']}" for r in results if "failed" not in r)
        + " (adjustable deltaT at each setting's maxCo: the step is set by the largest Courant number, which the "
        "settings change).",
        "",
        "## The runner's own cost",
        "",
        f"The chosen setting, {overhead_end:g} s simulated, run alternately by a bare "
        "`mpirun -np 2 overInterDyMFoam -parallel`, by `run_case(quiet=True)` and by `run_case` drawing the progress "
        f"bar ({OVERHEAD_REPEATS} rounds). Runner CPU = the runner process's user + system time (getrusage) "
        "over the solver segments: log tailing, parsing, health and contact checks, the bar.",
        "",
        "| round | mode | solver wall (s) | runner CPU / solver wall |",
        "|---:|---|---:|---:|",
    ]
    for i, r in enumerate(overhead):
        share = "-" if r["overhead"] is None else f"{100 * r['overhead']:.2f} %"
        lines.append(f"| {i // 3 + 1} | {r['mode']} | {r['solver_wall_s']:.1f} | {share} |")
    bare = [r["solver_wall_s"] for r in overhead if r["mode"] == "bare"]
    watched = [r["solver_wall_s"] for r in overhead if r["mode"] != "bare"]
    lines += [
        "",
        f"Median solver wall: bare {np.median(bare):.1f} s, under the runner {np.median(watched):.1f} s "
        f"({100 * (np.median(watched) / np.median(bare) - 1):+.1f} %); the runner's CPU share over all runs of this "
        f"benchmark: at most {100 * max(r['overhead'] for r in results + overhead if r.get('overhead')):.2f} %.",
        "",
        f"Whole benchmark: {(time.time() - t_start) / 60:.0f} min wall.",
        "",
    ]
    text = "\n".join(lines)
    OUT.write_text(text)
    print(text)
    if args.keep or args.source:
        print(f"cases kept in {root}")
    else:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main()
