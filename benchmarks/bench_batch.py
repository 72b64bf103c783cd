"""Batched realisations against one model per realisation, through the 1-debris flow record.
Writes the "Batched realisations" section of benchmarks/ensemble.md.

    nice .venv/bin/python benchmarks/bench_batch.py [--flow runs/ensemble-1debris] [-n 256] [--single 32]
        [--batch 1 32 128] [--large 10000]

The flow is the one `make ensemble-1debris` (or any `debrisfoam ensemble cases/1debris.yaml -o
DIR`) ran into DIR/flow; the record is loaded once, outside the timings. For each batch size B
the same N realisations (seed 0) run on the local executor with 2 workers (B = 1, one
at a time, on the first ``--single`` of them only: it costs ten times as much)
(:func:`orchestrator.studies.ensemble.run_ensemble`), without the study's fit (timed apart: the
fit's cost per strike does not depend on B); B = 1 is one MuJoCo model per realisation, the
path `--batch-size 1` keeps. Every batched table is set against B = 1's on the realisations
both ran: whether the same realisations struck, and the largest relative difference of a first
strike's time, velocity, speed and peak force. CPU is the figure to compare on a shared
machine (the parent's and the workers' together). ``--large N`` then runs N realisations at the default batch size and
tables their wall time (the issue's target: 10,000 in at most 10 min on 2 cores, the flow
excluded).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from orchestrator.scene.scenefile import load_scene  # noqa: E402
from orchestrator.studies.ensemble import (  # noqa: E402
    DEFAULT_BATCH_SIZE,
    TABLE_COLUMNS,
    Perturbation,
    ensemble_starts,
    run_ensemble,
)
from orchestrator.transport.case_transport import case_flow, scene_settings, transport_setup  # noqa: E402

MARK = "## Batched realisations"
PROFILE = "## Where a realisation's time goes"
FIRST = ["impact_time_s", "impact_velocity_m_s", "impact_speed_m_s", "peak_force_N"]


def timed(starts, setup, flow, npz, batch: int, study_fit: bool = False, workers: int = 2):
    bodies, flume, column, t_end, settings = setup
    t0, c0 = time.perf_counter(), os.times()
    runs = run_ensemble(starts, flume, column, t_end, flow, npz, "local", workers, settings, batch_size=batch,
                        study_fit=study_fit)
    wall, c1 = time.perf_counter() - t0, os.times()
    cpu = (c1.children_user + c1.children_system + c1.user + c1.system) - (c0.children_user + c0.children_system
                                                                           + c0.user + c0.system)
    return pd.DataFrame([row for r in runs for row in r.rows], columns=TABLE_COLUMNS), wall, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--flow", default=str(ROOT / "runs" / "ensemble-1debris"), help="ensemble folder with flow/")
    parser.add_argument("-n", type=int, default=256, help="realisations per batch size")
    parser.add_argument("--single", type=int, default=32, help="realisations at B = 1 (the first of the n)")
    parser.add_argument("--batch", type=int, nargs="+", default=[1, 32, 128])
    parser.add_argument("--large", type=int, default=0, help="then this many at the default batch size")
    args = parser.parse_args()
    scene = load_scene(ROOT / "cases" / "1debris.yaml")
    flow, npz = case_flow(Path(args.flow) / "flow", say=lambda _: None)
    bodies, flume, column = transport_setup(scene, flow)
    setup = (bodies, flume, column, float(scene.run.end_time_s), scene_settings(scene))
    starts = ensemble_starts(bodies, flume, column, Perturbation(), 0, args.n)
    rows, base = [], None
    for b in args.batch:
        n = min(args.single, args.n) if b == 1 else args.n
        table, wall, cpu = timed(starts[:n], setup, flow, npz, b)
        if base is None:
            base = (table, cpu / n)
        both = min(len(base[0]), n)
        mine, ref = table.iloc[:both], base[0].iloc[:both]
        same = np.asarray(mine["struck"]) == np.asarray(ref["struck"])
        counts = int(np.sum(np.asarray(mine["strikes"]) != np.asarray(ref["strikes"])))
        first = same & np.asarray(ref["struck"], bool)  # first strikes both have
        a, r = mine[FIRST].to_numpy(float)[first], ref[FIRST].to_numpy(float)[first]
        diff = float(np.max(np.abs(a - r) / np.abs(r))) if first.any() else math.nan
        rows.append(f"| {b} | {n} | {wall:.1f} s | {cpu:.1f} s | {cpu / n:.3f} s | {n / wall:.2f} | "
                    f"{base[1] / (cpu / n):.2f} | {int(same.sum())} of {both} | {counts} of {both} | {diff:.1g} |")
        print(rows[-1], flush=True)
    # the study's fit, timed on the first strikes of a batched run (its cost does not depend on B)
    _, wall_fit, _ = timed(starts[:16], setup, flow, npz, DEFAULT_BATCH_SIZE, study_fit=True)
    table_fit, wall_nofit, _ = timed(starts[:16], setup, flow, npz, DEFAULT_BATCH_SIZE)
    fit = table_fit  # the struck count of the 16
    fit_line = (f"The study's fit on top, 16 realisations at B = {DEFAULT_BATCH_SIZE}: {wall_fit:.1f} s with it, "
                f"{wall_nofit:.1f} s without ({int(fit['struck'].sum())} first strikes fitted).")
    print(fit_line, flush=True)
    large = []
    if args.large:
        many = ensemble_starts(bodies, flume, column, Perturbation(), 0, args.large)
        table, wall, cpu = timed(many, setup, flow, npz, DEFAULT_BATCH_SIZE)
        large = [f"{args.large:,} realisations at B = {DEFAULT_BATCH_SIZE} on 2 workers, without the study's fit: "
                 f"{wall / 60:.1f} min of wall time ({args.large / wall:.1f} realisations/s, {cpu:.0f} s of CPU), "
                 f"impact probability {table['struck'].mean():.3f}; target 10 min for 10,000: "
                 f"{'met' if wall * 10000 / args.large <= 600 else 'missed'}.", ""]
        print(large[0], flush=True)
    load = os.getloadavg()
    section = [
        MARK, "",
        f"`nice .venv/bin/python benchmarks/bench_batch.py -n {args.n} --single {args.single} --batch "
        f"{' '.join(map(str, args.batch))}{f' --large {args.large}' if args.large else ''}`: the same realisations "
        "(cases/1debris.yaml, seed 0) through the 1-debris flow record on the local executor with 2 workers, B "
        "realisations stepped together in one MuJoCo model (at most B: a batch is smaller when the realisations "
        "would not give each worker one; B = 1: one model each, the one-at-a-time path, on the first "
        f"{args.single} only); the flow loaded once, outside the timings; without the study's fit (below). CPU is "
        "the parent's and the workers' together.", "",
        f"Machine: 2 cores shared with other work; load average at the end {load[0]:.1f} / {load[1]:.1f} / "
        f"{load[2]:.1f}.", "",
        "| batch size B | realisations | wall | CPU | CPU a realisation | realisations / s | speed-up over B = 1 "
        "(CPU) | struck as at B = 1 | strike count differs from B = 1 "
        "| first strikes: largest relative difference |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows, "", fit_line, "", *large]
    path = ROOT / "benchmarks" / "ensemble.md"
    text = path.read_text() if path.is_file() else ""
    head = text.split(MARK)[0].rstrip("\n")
    kept = "".join(text.partition(PROFILE)[1:])  # the profile's section after this one stays
    path.write_text((head + "\n\n" if head else "") + "\n".join(section) + (f"\n{kept}" if kept else ""))
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
