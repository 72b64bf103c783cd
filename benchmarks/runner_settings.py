"""overInterDyMFoam settings on a small one-debris case: cost against the debris track and column force.

A small dam break (0.5 m x 0.25 m reservoir, 0.12 m wet bed, 0.4 m wide flume, 0.1 m column at
x = 1.2 m, 4 cm cells, about 6k cells) carries one 1:40 container (0.15 x 0.06 x 0.06 m,
0.236 kg) floating at x = 0.35 m towards the column; 0.6 s simulated, 2 ranks, run by
`orchestrator.run.run_case`. Each setting changes the rendered case before the run:

- overset interpolation (fvSchemes oversetInterpolation method): cellVolumeWeight,
  inverseDistance, leastSquares (trackingInverseDistance crashes in parallel, DESIGN.md 3);
- PIMPLE nOuterCorrectors / nCorrectors;
- p_rgh tolerance / relTol (PBiCGStab + DILU; GAMG fails with overset);
- body mesh size (scene mesh.body_cells_across: cells across the body's smallest side).

Errors against the most careful setting ("reference"): the debris track (the largest
distance between the two centres of mass at the same time, over the reference's largest
displacement) and the column force (x, pressure + viscous: peak, and RMS of the
difference over the reference's peak, at the reference's samples).

Also measured: the runner's own cost (its CPU time over the solver's wall time, and the
solver wall time of a bare `mpirun` against `run_case` with the progress bar drawn).

Run:  .venv/bin/python benchmarks/runner_settings.py [--only NAME ...] [--from DIR] [--keep]   (30-60 min on 2 cores)
Writes benchmarks/runner_settings.md next to this script (and prints it).
"""

from __future__ import annotations

import argparse
import io
import json
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

from orchestrator import bodystate, foam  # noqa: E402
from orchestrator.render import render_from_file  # noqa: E402
from orchestrator.run import load_case_info, run_case  # noqa: E402

HERE = Path(__file__).resolve().parent
OUT = HERE / "runner_settings.md"
END_TIME_S = 0.6
#: simulated time of the overhead runs (bare mpirun against run_case, alternated)
OVERHEAD_END_S = 0.3
OVERHEAD_REPEATS = 2
TOLERANCE = 0.02

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
    "mesh": {"cell_size_m": 0.04, "coarsening_ratio": 1, "body_margin_cells": 1, "body_cells_across": 3},
    "run": {"end_time_s": END_TIME_S, "cores": 2, "write_interval_s": 0.1, "max_courant": 0.9},
    "outputs": {"probe_interval_s": None, "preview": False},
}


@dataclass(frozen=True)
class Setting:
    name: str
    interpolation: str = "cellVolumeWeight"
    n_outer: int = 2
    n_corr: int = 3
    tolerance: float = 1e-8
    rel_tol: float = 0.0
    final_rel_tol: float = 0.0
    body_cells_across: float = 3.0

    def describe(self) -> str:
        return (f"{self.interpolation}, outer {self.n_outer}, corr {self.n_corr}, p_rgh {self.tolerance:g}/"
                f"{self.rel_tol:g} (final {self.final_rel_tol:g}), body {self.body_cells_across:g} cells")


FAST = dict(n_outer=1, n_corr=1, tolerance=1e-7, rel_tol=0.05, final_rel_tol=0.05)
SETTINGS = [
    Setting("reference"),
    Setting("reference-body2", body_cells_across=2.0),
    Setting("outer1", n_outer=1),
    Setting("outer1-corr2", n_outer=1, n_corr=2),
    Setting("outer1-corr1", n_outer=1, n_corr=1),
    Setting("fast-tol", **FAST),
    Setting("fast-tol-body2", **FAST, body_cells_across=2.0),  # = the templates' defaults
    Setting("inverseDistance", interpolation="inverseDistance", **FAST),
    Setting("leastSquares", interpolation="leastSquares", **FAST),
    # the body mesh of 2 cells across (the templates' default) with each lever
    Setting("outer1-body2", n_outer=1, body_cells_across=2.0),
    Setting("outer1-corr1-body2", n_outer=1, n_corr=1, body_cells_across=2.0),
    Setting("inverseDistance-body2", interpolation="inverseDistance", **FAST, body_cells_across=2.0),
    Setting("leastSquares-body2", interpolation="leastSquares", **FAST, body_cells_across=2.0),
]


def prepare(setting: Setting, root: Path) -> Path:
    scene = json.loads(json.dumps(SCENE))
    scene["mesh"]["body_cells_across"] = setting.body_cells_across
    root.mkdir(parents=True, exist_ok=True)
    path = root / f"{setting.name}.yaml"
    path.write_text(yaml.safe_dump(scene))
    case = root / setting.name
    render_from_file(path, case)
    from PyFoam.RunDictionary.ParsedParameterFile import ParsedParameterFile

    sol = ParsedParameterFile(str(case / "system" / "fvSolution"))
    sol["PIMPLE"]["nOuterCorrectors"] = setting.n_outer
    sol["PIMPLE"]["nCorrectors"] = setting.n_corr
    sol["solvers"]["p_rgh"]["tolerance"] = setting.tolerance
    sol["solvers"]["p_rgh"]["relTol"] = setting.rel_tol
    sol["solvers"]["p_rghFinal"]["relTol"] = setting.final_rel_tol
    bodystate.write_dictionary(sol, case / "system" / "fvSolution")
    schemes = ParsedParameterFile(str(case / "system" / "fvSchemes"))
    schemes["oversetInterpolation"]["method"] = setting.interpolation
    bodystate.write_dictionary(schemes, case / "system" / "fvSchemes")
    return case


def track(case: Path) -> tuple[np.ndarray, np.ndarray]:
    import pandas as pd

    df = pd.read_csv(case / "bodies.csv")
    df = df[df.body == "debris1"].drop_duplicates("time_s", keep="last").sort_values("time_s")
    return df.time_s.to_numpy(), df[["x_m", "y_m", "z_m"]].to_numpy()


def force_x(case: Path) -> tuple[np.ndarray, np.ndarray]:
    rows = {}
    for path in sorted((case / "postProcessing" / "columnForces").glob("*/force.dat"),
                       key=lambda p: float(p.parent.name)):
        for line in path.read_text().splitlines():
            if line.startswith("#") or not line.strip():
                continue
            parts = line.replace("(", " ").replace(")", " ").split()
            rows[float(parts[0])] = float(parts[1])
    t = np.array(sorted(rows))
    return t, np.array([rows[v] for v in t])


def compare(case: Path, ref: Path) -> dict[str, float]:
    t_ref, p_ref = track(ref)
    t, p = track(case)
    common = t_ref[(t_ref >= t[0]) & (t_ref <= t[-1])]
    p_ref_c = np.column_stack([np.interp(common, t_ref, p_ref[:, i]) for i in range(3)])
    p_c = np.column_stack([np.interp(common, t, p[:, i]) for i in range(3)])
    travel = np.linalg.norm(p_ref - p_ref[0], axis=1).max()
    track_err = np.linalg.norm(p_c - p_ref_c, axis=1).max() / travel
    tf_ref, f_ref = force_x(ref)
    tf, f = force_x(case)
    f_on_ref = np.interp(tf_ref, tf, f)
    peak = np.abs(f_ref).max()
    return {
        "travel_m": float(travel),
        "track_err": float(track_err),
        "end_dx_m": float(p_c[-1, 0] - p_ref_c[-1, 0]),
        "force_peak_N": float(np.abs(f).max()),
        "force_peak_err": float((np.abs(f).max() - peak) / peak),
        "force_rms_err": float(np.sqrt(np.mean((f_on_ref - f_ref) ** 2)) / peak),
    }


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
        "us_per_cell_step": 1e6 * cpu / (cells * steps),
        "segments": len(record["segments"]),
        "contacts": int(record.get("contacts", 0)),
        "overhead": float(record["runner"]["overhead_fraction"]),
        "load": float(record.get("benchmark_load", float("nan"))),
    }


def run_setting(setting: Setting, root: Path) -> dict:
    """Run one setting (a failure is a result: its row says why)."""
    from analytical.errors import DebrisfoamError

    case = prepare(setting, root)
    try:
        run_case(case, quiet=True, reconstruct="none")
    except DebrisfoamError as exc:
        (case / "failed.txt").write_text(str(exc))
    return load_result(setting, case)


def load_result(setting: Setting, case: Path) -> dict:
    failed = case / "failed.txt"
    if failed.is_file():
        return {"setting": setting, "case": case, "failed": failed.read_text().splitlines()[0]}
    return collect(setting, case)


def _bare_run(case: Path) -> float:
    """Solver wall time of a bare `mpirun -np 2 overInterDyMFoam -parallel` (no runner)."""
    info = load_case_info(case)
    for step in foam.mesh_steps(case, info.plan) + foam.solve_steps(case, info.plan, 2)[:1]:
        foam.run_step(step.name, step.argv, case, np=step.np, done=step.done)
    env = foam.foam_env()
    env["PWD"] = str(case)
    t0 = time.perf_counter()
    with open(case / "log.bare", "w") as out:
        subprocess.run(foam.parallel_argv(["overInterDyMFoam"], 2), cwd=case, stdout=out, stderr=subprocess.STDOUT,
                       env=env, check=True)
    wall = time.perf_counter() - t0
    (case / "bare.json").write_text(json.dumps({"solver_wall_s": wall, "load": os.getloadavg()[0]}))
    return wall


def overhead_runs(setting: Setting, root: Path) -> list[dict]:
    """Bare mpirun, run_case quiet and run_case with the bar drawn, alternated, on a short run."""
    out = []
    for k in range(OVERHEAD_REPEATS):
        for mode in ("bare", "quiet", "bar"):
            case = prepare(setting, root / f"overhead-{mode}-{k}")
            _set_end(case, OVERHEAD_END_S)
            if mode == "bare":
                _bare_run(case)
            else:
                run_case(case, quiet=mode == "quiet", reconstruct="none", stream=io.StringIO())
            out.append(overhead_figures(case, mode))
    return out


def overhead_figures(case: Path, mode: str) -> dict:
    if mode == "bare":
        bare = json.loads((case / "bare.json").read_text())
        return {"mode": mode, "solver_wall_s": bare["solver_wall_s"], "overhead": None, "load": bare["load"]}
    record = json.loads((case / "run.json").read_text())
    return {"mode": mode, "solver_wall_s": sum(seg["wall_s"] for seg in record["segments"]),
            "overhead": float(record["runner"]["overhead_fraction"]), "load": float("nan")}


def _set_end(case: Path, end_s: float) -> None:
    from PyFoam.RunDictionary.ParsedParameterFile import ParsedParameterFile

    control = ParsedParameterFile(str(case / "system" / "controlDict"))
    control["endTime"] = end_s
    bodystate.write_dictionary(control, case / "system" / "controlDict")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="setting names to run (default all)")
    parser.add_argument("--keep", action="store_true", help="keep the cases (printed)")
    parser.add_argument("--from", dest="source", help="a folder of an earlier run: reuse its finished cases, run the rest")
    args = parser.parse_args()
    settings = [s for s in SETTINGS if not args.only or s.name in args.only or s.name == "reference"]
    load0 = os.getloadavg()[0]
    results = []
    root = Path(args.source) if args.source else Path(tempfile.mkdtemp(prefix="runner-settings-"))
    for s in settings:
        case = root / s.name
        done = (case / "failed.txt").is_file() or (
            (case / "run.json").is_file() and json.loads((case / "run.json").read_text()).get("status") == "finished")
        if done:
            results.append(load_result(s, case))
            continue
        if case.exists():
            shutil.rmtree(case)
        print(f"running {s.name}: {s.describe()}", flush=True)
        r = run_setting(s, root)
        print(f"  {r.get('failed') or ''}{r.get('steps', '')} steps, solver CPU {r.get('solver_cpu_s', 0):.1f} s",
              flush=True)
        results.append(r)
    ref = results[0]["case"]
    for r in results:
        if "failed" not in r:
            r.update(compare(r["case"], ref))

    ok = [r for r in results if "failed" not in r and r["track_err"] <= TOLERANCE
          and abs(r["force_peak_err"]) <= TOLERANCE and r["force_rms_err"] <= TOLERANCE]
    # the cost of simulating the same time: fewer correctors can mean smaller (Courant-limited) steps
    chosen = min(ok, key=lambda r: r["solver_cpu_s"])

    kept = [root / f"overhead-{mode}-{k}" / chosen["setting"].name
            for k in range(OVERHEAD_REPEATS) for mode in ("bare", "quiet", "bar")]
    if all((p / "bare.json").is_file() or (p / "run.json").is_file() for p in kept):
        overhead = [overhead_figures(p, p.parent.name.split("-")[1]) for p in kept]
    else:
        print("measuring the runner's overhead (bare mpirun, run_case quiet, run_case with the bar)", flush=True)
        overhead = overhead_runs(chosen["setting"], root)

    lines = [
        "# overInterDyMFoam settings and the runner's overhead",
        "",
        f"Generated by `benchmarks/runner_settings.py` (OpenFOAM v1912, 2 ranks, Python {platform.python_version()}, "
        f"{platform.machine()}). The machine has 2 cores and was shared with other OpenFOAM runs (load average "
        f"{load0:.1f} when this page was written; 3-4 during most runs), so wall times scatter. The cost compared is the "
        "solver's CPU time for the whole simulated time (ExecutionTime of rank 0, all segments): settings with "
        "fewer correctors are cheaper per step but can need many more (Courant-limited) steps.",
        "",
        f"Case: a {SCENE['reservoir']['length_m']} m x {SCENE['reservoir']['depth_m']} m reservoir released over a "
        f"{SCENE['bed']['wet_depth_m']} m wet bed in a {SCENE['flume']['width_m']} m wide flume, column "
        f"{SCENE['column']['size_x_m']} m square at x = {SCENE['column']['x_m']} m, one container "
        "(0.15 x 0.06 x 0.06 m, 0.236 kg) floating at x = 0.35 m, 4 cm background cells, "
        f"{END_TIME_S} s simulated, run by `run_case` (contact on).",
        "",
        "Errors against `reference` (the most careful setting): track = largest distance between the "
        "centres of mass at equal times / the reference's largest displacement; force = the column's "
        "x force (pressure + viscous), peak difference and RMS of the difference, both / the reference peak.",
        "",
        "| setting | settings | cells | steps | solver CPU (s) | solver wall (s) | us/cell-step | track err | "
        "end dx (mm) | force peak (N) | peak err | RMS err | within 2 % |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in results:
        within = r in ok
        if "failed" in r:
            lines.append(f"| {r['setting'].name} | {r['setting'].describe()} | | | | | | failed: {r['failed']} "
                         "| | | | | no |")
            continue
        lines.append(
            f"| {r['setting'].name} | {r['setting'].describe()} | {r['cells']} | {r['steps']} | "
            f"{r['solver_cpu_s']:.1f} | {r['solver_wall_s']:.1f} | {r['us_per_cell_step']:.1f} | "
            f"{100 * r['track_err']:.2f} % | "
            f"{1000 * r['end_dx_m']:+.2f} | {r['force_peak_N']:.3f} | {100 * r['force_peak_err']:+.2f} % | "
            f"{100 * r['force_rms_err']:.2f} % | {'yes' if within else 'no'} |")
    lines += [
        "",
        f"Reference travel of the debris: {results[0]['travel_m']:.3f} m; reference peak column force "
        f"{results[0]['force_peak_N']:.3f} N.",
        "",
        (f"**Chosen: `{chosen['setting'].name}`** ({chosen['setting'].describe()}): the cheapest setting within "
         f"{100 * TOLERANCE:g} % of the reference on the track, the force peak and the force RMS, "
         f"{results[0]['solver_cpu_s'] / chosen['solver_cpu_s']:.2f}x cheaper than the reference.")
        if chosen is not results[0] else
        (f"**No cheaper setting keeps the debris track and the column force within {100 * TOLERANCE:g} % of the "
         "reference: keep the reference's settings for this mesh.** Failed settings: "
         + (", ".join(r["setting"].name for r in results if "failed" in r) or "none") + "."),
        "",
        f"Time steps for the same {END_TIME_S} s: "
        + ", ".join(f"{r['setting'].name} {r['steps']}" for r in results if "failed" not in r)
        + " (adjustable deltaT at maxCo "
        f"{SCENE['run']['max_courant']}: the step is set by the largest Courant number, which the settings change).",
        "",
        "## The runner's own cost",
        "",
        f"The chosen setting, {OVERHEAD_END_S} s simulated, run alternately by a bare `mpirun -np 2 overInterDyMFoam "
        "-parallel`, by `run_case(quiet=True)` and by `run_case` drawing the progress bar "
        f"({OVERHEAD_REPEATS} rounds). Runner CPU = the runner process's user + system time (getrusage) "
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
