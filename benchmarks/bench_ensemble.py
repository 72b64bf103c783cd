"""Ensembles through one recorded flow: what N realisations cost after the flow, beside the flow
and a coupled run. Writes benchmarks/ensemble.md.

    nice .venv/bin/python benchmarks/bench_ensemble.py [-n 100]

For each scene (the study's 1-debris and 2x3 six-debris layouts) it runs
``debrisfoam ensemble SCENE -n N -o runs/ensemble-<name> --force`` (the flow in
runs/ensemble-<name>/flow is reused when finished; a finished one-way case of the same scene
copied there serves), then tables the realisations' wall time against the flow's solver wall
time and against the coupled (two-way) 1-debris run of docs/results/case-1debris-two-way.
Targets (issue: ensembles): 100 realisations of 6 bodies after the flow in at most 10 min on 2
cores.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = {"1debris": ROOT / "cases" / "1debris.yaml", "6debris-2x3": ROOT / "cases" / "6debris-2x3.yaml"}
TARGET_S = {"6debris-2x3": 600.0}
COUPLED = ROOT / "docs" / "results" / "case-1debris-two-way" / "summary.json"


def run(name: str, n: int) -> dict:
    out = ROOT / "runs" / f"ensemble-{name}"
    exe = Path(sys.executable).parent / "debrisfoam"
    subprocess.run([str(exe), "ensemble", str(SCENES[name]), "-n", str(n), "-o", str(out), "--force", "--json"],
                   check=True, cwd=ROOT, stdout=subprocess.DEVNULL)
    summary = json.loads((out / "ensemble.json").read_text())
    flow_run = json.loads((out / "flow" / "run.json").read_text())
    summary["flow_solver_wall_s"] = (flow_run.get("runner") or {}).get("solver_wall_s")
    return summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=100, help="realisations per scene")
    args = parser.parse_args()
    coupled = json.loads(COUPLED.read_text())["wall_time_s"]["total_s"] if COUPLED.is_file() else None
    rows = []
    for name in SCENES:
        s = run(name, args.n)
        wall, per = s["realisations_wall_s"], s["realisation_wall_time_s"]
        body_seconds = s["realisations"] * s["bodies"] * s["end_time_s"]
        target = TARGET_S.get(name)
        rows.append(
            f"| {name} | {s['bodies']} | {s['realisations']} | {s['workers']} | "
            f"{s['flow_solver_wall_s'] / 60:.1f} min | {wall:.0f} s | {per['mean']:.2f} +- {per['std']:.2f} s | "
            f"{s['transport_wall_time_s'] / body_seconds:.3f} | {wall / s['flow_solver_wall_s']:.2f} | "
            + (f"{wall / coupled:.3f} | " if coupled else "- | ")
            + (f"{target / 60:.0f} min: {'met' if wall <= target else 'missed'} |" if target else "- |"))
        print(rows[-1], flush=True)
    load = os.getloadavg()
    text = "\n".join([
        "# Ensembles through one recorded flow", "",
        "`nice .venv/bin/python benchmarks/bench_ensemble.py`: `debrisfoam ensemble SCENE -n N` on the local executor "
        "(a process pool of 2 workers), the scene's one-way flow reused, every body's first column strike resolved "
        "with the contact law and the MDOF column. Wall time: the realisations, after the flow; the flow's own "
        "solver wall time is the cost paid once; the coupled run is `make case-1debris COUPLING=two-way` "
        f"({coupled / 60:.1f} min, docs/results/case-1debris-two-way)." if coupled else "", "",
        f"Machine: 2 cores; load average at the end {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min).", "",
        "| scene | bodies | realisations | workers | the flow, once (solver) | realisations' wall | a realisation "
        "| realisation s per body-second | realisations / flow | realisations / one coupled run | target |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
        *rows, ""])
    path = ROOT / "benchmarks" / "ensemble.md"
    kept = path.read_text().partition("## Batched realisations") if path.is_file() else ("", "", "")
    path.write_text(text + (f"\n{kept[1]}{kept[2]}" if kept[1] else ""))  # bench_batch.py's section stays
    print("wrote benchmarks/ensemble.md")


if __name__ == "__main__":
    main()
