"""The simulated bore against Stoker's wet-bed dam break: front speed and bore depth.

Stoker's solution (``analytical.dambreak.StokerSolution``) is a frictionless, depth-averaged
bore of constant speed S and depth h2 running into still water h1. A run is read at its gauges:

* the front's arrival at each gauge is the package's (:func:`orchestrator.results.metrics.arrival_time`:
  the level rising 2 % of h0 above the still water), and the front speed is the least-squares slope
  of gauge position against arrival over the gauges at least :data:`DEVELOPED_X_FACTOR` h0 past the
  gate (closer to it the flow is still leaving the reservoir as a jet, which Stoker's self-similar
  solution does not have); the speeds over successive reaches say whether the front speeds up;
* the same slope with the arrival read where the level has risen half way from h1 to Stoker's h2
  (the front's mid-height): Stoker's front is a step, so both readings of his solution agree, while
  a simulated front rising over a few tenths of a second reads slower at its mid-height;
* the bore depth at a gauge is the median level between :data:`SETTLE_S` after Stoker's bore has
  passed it and the arrival of the rarefaction's tail (or the run's end), where Stoker's level is h2;
  a gauge counts only when that window lasts :data:`MIN_PLATEAU_S` at least: the simulated fronts rise
  over 0.5-0.8 s, so a shorter window (the far gauges near the run's end) reads the rise, not the bore.
  The run's bore depth is the mean over the gauges that count; each gauge's is kept beside it.

The sweep ``cases/sweeps/wet-bed.yaml`` runs the 2D frictionless flume of ``cases/stoker-wet-bed.yaml``
laminar and RANS, with the wet bed as one cell layer and resolved, at the study's h1/h0 = 0.0375 and
a deeper one; ``debrisfoam report bore`` writes the page (docs/results/wet-bed/).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from analytical.dambreak import StokerSolution
from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.results.metrics import ARRIVAL_FRACTION, arrival_time
from orchestrator.studies.sweep.store import member_dirs

__all__ = ["BoreCheck", "DEVELOPED_X_FACTOR", "MIN_PLATEAU_S", "SETTLE_S", "bore_check", "check_run", "sweep_checks",
           "write_bore_report"]

#: Gauges closer to the gate than this many impoundment depths are left out of the front speed.
DEVELOPED_X_FACTOR = 5.0
#: The bore depth is read from this long after Stoker's bore has passed a gauge (s).
SETTLE_S = 0.25
#: A gauge's bore depth counts when Stoker's plateau lasts this long past SETTLE_S within the run (s).
MIN_PLATEAU_S = 0.5


@dataclass(frozen=True)
class BoreCheck:
    """One run's front and bore beside Stoker's: speeds in m/s, depths in m, errors in %."""

    h0_m: float
    h1_m: float
    front_speed_m_s: float
    stoker_speed_m_s: float
    speed_error_pct: float
    bore_depth_m: float
    stoker_depth_m: float
    depth_error_pct: float
    reach_speeds_m_s: tuple[float, ...]
    gauges_used: tuple[str, ...]
    #: the front speed with each arrival read at the front's mid-height, h1 + (h2 - h1) / 2
    mid_speed_m_s: float = math.nan
    mid_speed_error_pct: float = math.nan
    #: each used gauge's bore depth against h2 (%), NaN where its plateau is shorter than MIN_PLATEAU_S
    gauge_depth_errors_pct: tuple[float, ...] = ()

    @property
    def front_speeds_up(self) -> bool:
        """True when the front runs faster over a reach than over the one before it (by 5 %)."""
        s = self.reach_speeds_m_s
        return any(b > 1.05 * a for a, b in zip(s, s[1:]))


def bore_check(time_s, levels: dict[str, np.ndarray], gauge_x_m: dict[str, float], h0_m: float, h1_m: float,
               g: float = 9.81) -> BoreCheck:
    """The front speed and bore depth of the gauge records ``levels`` (name -> elevation, m, on
    ``time_s``) at positions ``gauge_x_m`` beside Stoker's for ``h0_m`` over ``h1_m``."""
    if not 0.0 < h1_m < h0_m:
        raise InputError("bed.wet_depth_m", f"Stoker's bore needs 0 < h1 < h0 = {h0_m:g} m, got {h1_m:g} m")
    stoker = StokerSolution(h0_m, h1_m, g)
    st = stoker.state
    t = np.asarray(time_s, dtype=float)
    used = sorted((x, name) for name, x in gauge_x_m.items() if x >= DEVELOPED_X_FACTOR * h0_m)
    if len(used) < 2:
        raise InputError("gauges", f"needs two gauges at least {DEVELOPED_X_FACTOR:g} h0 = "
                         f"{DEVELOPED_X_FACTOR * h0_m:g} m past the gate, got {len(used)}")
    xs, arrivals, mids, depths = [], [], [], []
    for x, name in used:
        e = np.asarray(levels[name], dtype=float)
        ta = arrival_time(t, e, h1_m, ARRIVAL_FRACTION * h0_m)
        mids.append(arrival_time(t, e, h1_m, 0.5 * (st.h2_m - h1_m)))
        start = x / st.shock_speed_m_s + SETTLE_S
        tail = st.rarefaction_tail_speed_m_s
        end = min(x / tail, t[-1]) if tail > 0 else t[-1]
        window = (t >= start) & (t <= end)
        xs.append(x)
        arrivals.append(ta)
        depths.append(float(np.nanmedian(e[window])) if end - start >= MIN_PLATEAU_S and window.any() else math.nan)
    xs_a, ta_a = np.array(xs), np.array(arrivals)
    ok = np.isfinite(ta_a)
    speed = float(np.polyfit(ta_a[ok], xs_a[ok], 1)[0]) if ok.sum() >= 2 else math.nan
    mid_a = np.array(mids)
    ok_mid = np.isfinite(mid_a)
    mid = float(np.polyfit(mid_a[ok_mid], xs_a[ok_mid], 1)[0]) if ok_mid.sum() >= 2 else math.nan
    reaches = tuple(float((xs_a[i + 1] - xs_a[i]) / (ta_a[i + 1] - ta_a[i]))
                    for i in range(len(xs_a) - 1) if ok[i] and ok[i + 1] and ta_a[i + 1] > ta_a[i])
    finite = [d for d in depths if math.isfinite(d)]
    depth = float(np.mean(finite)) if finite else math.nan
    return BoreCheck(h0_m, h1_m, speed, st.shock_speed_m_s, 100.0 * (speed / st.shock_speed_m_s - 1.0),
                     depth, st.h2_m, 100.0 * (depth / st.h2_m - 1.0), reaches, tuple(n for _, n in used),
                     mid, 100.0 * (mid / st.shock_speed_m_s - 1.0),
                     tuple(100.0 * (d / st.h2_m - 1.0) for d in depths))


def check_run(case_dir: str | Path) -> BoreCheck:
    """:func:`bore_check` of a post-processed run (its results/gauges.csv, plan.json and scene.yaml)."""

    case = Path(case_dir)
    table = case / "results" / "gauges.csv"
    if not table.is_file():
        raise InputError(str(table), "missing: run `debrisfoam post` on the case first")
    for name in ("scene.yaml", "plan.json"):
        if not (case / name).is_file():
            raise InputError(str(case / name), "missing: not a case folder that `debrisfoam render` wrote")
    scene = CaseFolder(case).scene()
    frame = pd.read_csv(table)
    gauges = {gg.name: float(gg.x_m) for gg in scene.gauges}
    levels = {name: frame[f"{name}_elevation_m"].to_numpy() for name in gauges}
    return bore_check(frame["time_s"].to_numpy(), levels, gauges, float(scene.reservoir.depth_m),
                      float(scene.bed.wet_depth_m), float(scene.fluids.gravity_m_s2))


def sweep_checks(sweep_dir: str | Path) -> pd.DataFrame:
    """One row per finished member of a sweep: its model, cells, wall time and :func:`check_run`."""
    rows = []
    for case in member_dirs(sweep_dir, "results/gauges.csv"):
        check = check_run(case)
        folder = CaseFolder(case)
        plan, mesh = folder.require_plan(), folder.scene().mesh
        row = {"member": case.name, "turbulence": plan.turbulence, "wet_bed_cells": int(mesh.wet_bed_cells),
               "cell_size_m": float(mesh.cell_size_m), "cells": int(plan.cell_count),
               "wall_time_s": folder.run_state().runner.get("solver_wall_s"), **asdict(check)}
        rows.append(row)
    if not rows:
        raise InputError(str(sweep_dir), "holds no post-processed member (no */results/gauges.csv)")
    return pd.DataFrame(rows)


def _plot(table: pd.DataFrame, sweep_dir: Path, out: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = []
    for h1, group in table.groupby("h1_m"):
        first = sweep_dir / group["member"].iloc[0]
        scene = CaseFolder(first).scene()
        h0 = float(scene.reservoir.depth_m)
        gauges = [gg for gg in scene.gauges if gg.x_m >= DEVELOPED_X_FACTOR * h0]
        stoker = StokerSolution(h0, float(h1))
        fig, axes = plt.subplots(len(gauges), 1, figsize=(7.5, 1.7 * len(gauges) + 0.6), sharex=True)
        axes = np.atleast_1d(axes)
        t = np.linspace(0.0, float(scene.run.end_time_s), 700)
        for ax, gg in zip(axes, gauges):
            ax.plot(t, [float(stoker.profile(gg.x_m, tt)[0]) for tt in t], "k--", lw=1.2, label="Stoker")
            for row in group.itertuples():
                frame = pd.read_csv(sweep_dir / row.member / "results" / "gauges.csv")
                ax.plot(frame["time_s"], frame[f"{gg.name}_elevation_m"], lw=1,
                        label=f"{row.turbulence}, {row.wet_bed_cells} cell(s) across the wet bed, "
                              f"{row.cell_size_m * 100:g} cm")
            ax.set_ylabel(f"x = {gg.x_m:g} m\nlevel (m)", fontsize=8)
        axes[0].legend(fontsize=7, loc="upper left")
        axes[-1].set_xlabel("time (s)")
        fig.suptitle(f"h0 = {stoker.h0_m:g} m over a {h1:g} m wet bed (h1/h0 = {h1 / stoker.h0_m:.4g})", fontsize=9)
        fig.tight_layout()
        name = f"gauges-h1-{h1 * 1000:g}mm.png"
        fig.savefig(out / name, dpi=90)
        plt.close(fig)
        names.append(name)
    return names


def write_bore_report(sweep_dir: str | Path, out_dir: str | Path) -> dict[str, Path]:
    """The page: every member's front speed and bore depth against Stoker's, a table, the gauges."""
    sweep = Path(sweep_dir)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    table = sweep_checks(sweep).sort_values(["h1_m", "cell_size_m", "turbulence", "wet_bed_cells"],
                                            ascending=[True, False, True, True])
    flat = table.drop(columns=["reach_speeds_m_s", "gauges_used", "gauge_depth_errors_pct"]).assign(
        reach_speeds_m_s=[" ".join(f"{v:.2f}" for v in r) for r in table["reach_speeds_m_s"]],
        gauge_depth_errors_pct=[" ".join(f"{v:.1f}" for v in r) for r in table["gauge_depth_errors_pct"]])
    flat.to_csv(out / "bore_check.csv", index=False)
    figures = _plot(table, sweep, out)
    lines = [
        "# The bore against Stoker's wet-bed dam break",
        "",
        "Generated by `make wet-bed` (`debrisfoam sweep cases/sweeps/wet-bed.yaml`, then "
        "`debrisfoam report bore`): a frictionless 2D flume (a slip bed, `bed.slip`), the impoundment released at once over a still wet "
        "bed, run laminar and with RANS k-omega SST, the wet bed one cell layer or resolved by several, at the "
        "table's cell sizes. "
        f"Front speed: the slope of gauge position against the front's arrival (a {ARRIVAL_FRACTION:.0%} h0 rise) "
        f"over the gauges at least {DEVELOPED_X_FACTOR:g} h0 past the gate, and the same with each arrival read at "
        "the front's mid-height (half way from h1 to Stoker's h2); bore depth: the median level from "
        f"{SETTLE_S:g} s after Stoker's bore has passed each of them to the rarefaction's tail or the run's end, "
        f"averaged over the gauges where that lasts {MIN_PLATEAU_S:g} s at least (by gauge: each one's, downstream; "
        "'-' too short). Reach speeds: the front over successive gauge reaches, downstream.",
        "",
        "| h1/h0 | closure | cells across the wet bed | cell size (m) | cells | solver wall time (s) | front speed (m/s) | Stoker (m/s) "
        "| error | at mid-height | error | bore depth (m) | Stoker (m) | error | by gauge (%) | reach speeds (m/s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in table.itertuples():
        wall = "-" if r.wall_time_s is None or not math.isfinite(r.wall_time_s) else f"{r.wall_time_s:.0f}"
        lines.append(
            f"| {r.h1_m / r.h0_m:.4g} | {r.turbulence} | {r.wet_bed_cells} | {r.cell_size_m:g} | {r.cells:,} | {wall} "
            f"| {r.front_speed_m_s:.3f} | {r.stoker_speed_m_s:.3f} | {r.speed_error_pct:+.1f} % "
            f"| {r.mid_speed_m_s:.3f} | {r.mid_speed_error_pct:+.1f} % "
            f"| {r.bore_depth_m:.4f} | {r.stoker_depth_m:.4f} | {r.depth_error_pct:+.1f} % "
            f"| {' '.join('-' if not math.isfinite(v) else f'{v:+.0f}' for v in r.gauge_depth_errors_pct)} "
            f"| {' '.join(f'{v:.2f}' for v in r.reach_speeds_m_s)} |")
    lines += ["", *[f"![gauges]({name})" for name in figures], ""]
    (out / "report.md").write_text("\n".join(lines))
    return {"report": out / "report.md", "table": out / "bore_check.csv", **{n: out / n for n in figures}}
