"""Benchmark of the one-way transport engine: 1, 6 and 50 containers over 3.5 s of a dam break.

The flow is Ritter's dam break of the study's 0.40 m reservoir (:meth:`FlowField.ritter`, gate at
x = 0) recorded every 0.02 s on a 0.05 m grid over x = -1..6 m, across the study flume's 1.5 m;
the column (0.20 x 0.20 x 0.80 m) stands at x = 5 m as in cases/1debris.yaml. The containers
(0.15 x 0.06 x 0.06 m, 0.236 kg, the calibrated contact law) start at rest on the bed around
x = 3.2 m: one on the centreline, six in two rows, fifty in five rows of ten.

The issue's targets: 6 bodies over 3.5 s in at most 10 s on one core; 50 bodies complete.
``wall_s`` is the stepping (MuJoCo plus the forcing); the column pulses (column_impact, after
the run) are timed apart. Run: ``nice .venv/bin/python benchmarks/bench_transport.py``;
it writes benchmarks/transport.md.
"""

from __future__ import annotations

import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from orchestrator.transport.engine import run_transport  # noqa: E402
from orchestrator.transport.flow import FlowField  # noqa: E402
from orchestrator.scene.schema import DebrisBody  # noqa: E402
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn  # noqa: E402

T_END_S = 3.5
SIZE = (0.15, 0.06, 0.06)


def layout(count: int) -> list[tuple[float, float]]:
    if count == 1:
        return [(3.2, 0.0)]
    if count == 6:
        return [(x, y) for x in (3.0, 3.4) for y in (-0.3, 0.0, 0.3)]
    xs = np.linspace(2.4, 3.6, 5)
    ys = np.linspace(-0.6, 0.6, 10)
    return [(float(x), float(y)) for x in xs for y in ys][:count]


def bodies(count: int) -> list[DebrisBody]:
    return [DebrisBody(name=f"debris{i + 1}", size_m=SIZE, mass_kg=0.236, centre_m=(x, y, 0.03), wall_thickness_m=0.005)
            for i, (x, y) in enumerate(layout(count))]


def main() -> None:
    flow = FlowField.ritter(0.40, np.linspace(-1.0, 6.0, 141), np.linspace(0.0, T_END_S, 176),
                            y_m=np.linspace(-0.75, 0.75, 4), levels=5)
    flume = FlumeBounds((-1.0, 6.0), (-0.75, 0.75))
    column = PlacedColumn(5.0, 0.0)
    rows = []
    for count in (1, 6, 50):
        start = time.perf_counter()
        result = run_transport(bodies(count), flume, T_END_S, flow, column)
        total = time.perf_counter() - start
        last = result.tracks[result.tracks["time_s"] == result.tracks["time_s"].max()]
        rows.append({
            "bodies": count, "steps": result.steps, "dt_s": result.timestep_s, "wall_s": result.wall_s,
            "per_body_s": result.wall_s / (count * T_END_S), "pulse_s": result.pulse_wall_s, "total_s": total,
            "column_impacts": int((result.impacts["kind"] == "column").sum()) if len(result.impacts) else 0,
            "wall_impacts": int((result.impacts["kind"] == "wall").sum()) if len(result.impacts) else 0,
            "body_contacts": len(result.body_contacts), "mean_x_end": float(last["x_m"].mean()),
            "max_speed": float(result.tracks["speed_m_s"].max()),
        })
        print(rows[-1], flush=True)
    load = os.getloadavg()
    lines = [
        "# One-way transport benchmark (MuJoCo)",
        "",
        "`nice .venv/bin/python benchmarks/bench_transport.py`: containers (0.15 x 0.06 x 0.06 m, 0.236 kg,",
        "calibrated contact law) carried over 3.5 s through Ritter's dam break of a 0.40 m reservoir",
        f"(record: {flow.t_s.size} frames x {flow.x_m.size} x {flow.y_m.size} x {flow.z_m.size} points, "
        f"{flow.nbytes / 1e6:.1f} MB), column at x = 5 m.",
        "One process, one thread. Hydrodynamic forcing every 1 ms, 5 x 3 x 3 sub-volumes per body.",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores shared with other jobs;",
        f"load average at the end {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} (1 / 5 / 15 min), so wall times are",
        "upper bounds of an idle core's.",
        "",
        "| bodies | steps | dt (s) | wall, stepping (s) | s per body-second | pulses (s) | column impacts "
        "| wall impacts | body-body contacts | mean x at 3.5 s (m) | max speed (m/s) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['bodies']} | {r['steps']} | {r['dt_s']:.3g} | {r['wall_s']:.2f} | {r['per_body_s']:.3f} "
                     f"| {r['pulse_s']:.2f} | {r['column_impacts']} | {r['wall_impacts']} | {r['body_contacts']} "
                     f"| {r['mean_x_end']:.2f} | {r['max_speed']:.2f} |")
    six = next(r for r in rows if r["bodies"] == 6)
    six_total = six["wall_s"] + six["pulse_s"]
    six_events = six["column_impacts"] + six["wall_impacts"] + six["body_contacts"]
    lines += [
        "",
        f"Targets: 6 bodies over 3.5 s in at most 10 s on one core: the stepping {six['wall_s']:.1f} s "
        f"({'met' if six['wall_s'] <= 10.0 else 'not met'}); with the pulses of its {six['column_impacts']} "
        "column strikes and its wall and body-body contacts "
        f"{six_total:.1f} s ({'met' if six_total <= 10.0 else 'not met'}: "
        "this flow holds the bodies at the column, which they strike again and again; the study's 6-debris "
        "layout, with a few strikes, is in docs/results/layouts/report.md). 50 bodies: completed.",
        "",
        "Reading the table: the column-impact counts are strike sequences, not noise. A body the flow holds at "
        "the column strikes it again and again, each strike rebounding at the contact law's restitution while the "
        "flow pushes it back; onsets slower than 0.05 m/s count as touches, not impacts. The pulses are resolved "
        "after the run and timed apart: for the 6 bodies, "
        f"{six_events} events (column strikes on the 160-element MDOF column, wall strikes and body-body "
        f"contacts) in {six['pulse_s']:.2f} s, {1000.0 * six['pulse_s'] / max(six_events, 1):.0f} ms each on average.",
        "",
    ]
    (ROOT / "benchmarks" / "transport.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
