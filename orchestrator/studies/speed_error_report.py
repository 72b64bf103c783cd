"""The speed-against-error study written out: its table, its page and its Pareto plot.

:func:`write_report` writes, for a :class:`~orchestrator.studies.speed_error.SpeedError`
(default folder ``SWEEP_DIR/report/``):

``speed_error.csv``   one row per member, every figure (units in the column names);
``speed_error.md``    the tables, the speed-ups and the extrapolation, with the definitions
                      (:func:`markdown`, also what `debrisfoam report speed-error` prints);
``speed_error.png``   the Pareto plot (:func:`plot`): time against error (log axes), every
                      member labelled, the front drawn; left against the finest member,
                      right against Chanson's arrival times;
``speed_error.json``  the headline: reference, speed-ups, extrapolation, notes.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import Any

from analytical.study import STUDY_ARRIVALS
from orchestrator.core.files import write_bytes_atomic, write_json_atomic, write_text_atomic
from orchestrator.core.numbers import finite_or_none
from orchestrator.studies.speed_error import COLUMN_CLEARANCE, REPORT_DIR, TIME_LABELS, SpeedError
from orchestrator.studies.speedup import EQUAL_ERROR_REACH

__all__ = ["markdown", "plot", "write_report"]


def _fmt(value: Any, fmt: str) -> str:
    v = finite_or_none(value)
    return "-" if v is None else format(v, fmt)


def _duration(seconds: Any) -> str:
    s = finite_or_none(seconds)
    if s is None:
        return "-"
    if s < 100:
        return f"{s:.0f} s"
    if s < 6000:
        return f"{s / 60:.1f} min"
    return f"{s / 3600:.1f} h"


def _markdown_table(head: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def _impact_cells(r: dict) -> list[str]:
    """The first impact's time and velocity, and their errors against the reference."""
    ref = bool(r.get("reference"))
    err_v = finite_or_none(r.get("impact_velocity_error_vs_finest_percent"))
    return [
        _fmt(r.get("first_impact_time_s"), ".3f"),
        "reference" if ref else _fmt(r.get("impact_time_error_vs_finest_s"), "+.3f"),
        _fmt(r.get("impact_velocity_m_s"), ".2f"),
        "reference" if ref else (_fmt(err_v, "+.1f") + " %" if err_v is not None else "-"),
    ]


def markdown(study: SpeedError) -> str:
    """speed_error.md: the tables, the speed-ups and the extrapolation."""
    t = study.table
    tcol = study.time_column
    ref = study.reference
    study_gauges = [g for g in ("WG2", "WG3") if f"{g}_arrival_s" in t]
    impacts = "first_impact_time_s" in t and t["first_impact_time_s"].notna().any()
    head = ["member", "cell", "cells", "steps", "cell-steps (M)", "wall", "solver", "solver CPU",
            "gauge RMSE vs finest (mm)", "peak force vs finest", *[f"{g} arrival (s)" for g in study_gauges],
            *[f"{g} vs Chanson (s)" for g in study_gauges], *[f"{g} vs experiment (s)" for g in study_gauges],
            "depth RMSE vs Chanson (mm)",
            *(["first impact (s)", "vs finest (s)", "impact velocity (m/s)", "vs finest"] if impacts else []),
            "Pareto"]
    rows = []
    for r in t.to_dict("records"):
        pareto = ", ".join(n for n, c in (("finest", "pareto_vs_finest"), ("Chanson", "pareto_vs_chanson")) if r.get(c))
        name = f"**{r['label']}**" if r.get("reference") else r["label"]
        if r.get("status") != "finished":
            name += f" ({r.get('status')})"
        rows.append([
            name, _fmt(r.get("cell_size_m"), ".3g"), _fmt(r.get("cells"), ",.0f"), _fmt(r.get("time_steps"), ".0f"),
            _fmt(r["cell_steps"] / 1e6, ".1f") if finite_or_none(r.get("cell_steps")) is not None else "-",
            _duration(r.get("wall_time_s")), _duration(r.get("solver_wall_s")), _duration(r.get("solver_cpu_s")),
            "reference" if r.get("reference") else _fmt(1e3 * r["gauge_rmse_vs_finest_m"], ".2f")
            if finite_or_none(r.get("gauge_rmse_vs_finest_m")) is not None else "-",
            "reference" if r.get("reference") else (_fmt(r.get("peak_force_error_vs_finest_percent"), "+.1f") + " %"
                                                    if finite_or_none(r.get("peak_force_error_vs_finest_percent")) is not None
                                                    else "-"),
            *[_fmt(r.get(f"{g}_arrival_s"), ".3f") for g in study_gauges],
            *[_fmt(r.get(f"{g}_arrival_error_chanson_s"), "+.3f") for g in study_gauges],
            *[_fmt(r.get(f"{g}_arrival_error_study_experiment_s"), "+.3f") for g in study_gauges],
            _fmt(1e3 * r["depth_rmse_vs_chanson_m"], ".1f") if finite_or_none(r.get("depth_rmse_vs_chanson_m")) is not None else "-",
            *(_impact_cells(r) if impacts else []),
            pareto or "-",
        ])
    out = [f"# Speed against error: {study.sweep_dir.name}", ""]
    if ref:
        out.append(f"Reference (the finest member): **{ref['label']}** ({ref['member_id']}, "
                   f"{_fmt(ref['cells'], ',.0f')} cells). Times: {TIME_LABELS[tcol]} for the plot and the speed-ups.")
        out.append("")
    out += [_markdown_table(head, rows), ""]
    out += [
        "- *cell*: finest cell (m); *planner*: the planner's graded cells and trimmed domain; *hand*: uniform "
        "cells, the whole reservoir and flume (`mesh.trim_domain: false`, `mesh.coarsening_ratio: 1`).",
        "- *cell-steps*: cells x time steps, the work (independent of the machine's load); *wall*: the member's "
        "whole session (render, mesh, solve, post); *solver*: the solver's wall time; *solver CPU*: the master "
        "rank's CPU time (`ExecutionTime`), less sensitive to other jobs on the machine.",
        "- *gauge RMSE vs finest*: water level at every gauge against the reference on its time base, RMS over "
        "the gauges; *peak force*: the peak column force along the flume against the reference's.",
        "- *vs Chanson*: simulated minus Chanson's (f = the scene's) arrival time; *vs experiment*: minus the "
        "study's measured arrivals ("
        + ", ".join(f"{measured:.2f} s at {gauge}" for gauge, measured, _ in STUDY_ARRIVALS.values())
        + "). Arrival = the level rising 2 % of h0 above its initial value.",
        f"- *depth RMSE vs Chanson*: gauges downstream of the gate and more than {COLUMN_CLEARANCE:g} column widths "
        "upstream of the column, from Chanson's arrival to the end of the run.",
        "- *Pareto*: on the front of time against gauge RMSE vs finest (*finest*) or against the mean |arrival "
        "error| vs Chanson (*Chanson*).",
        "",
    ]
    if study.speedups:
        out += ["## The planner against the hand-made set-up", "",
                f"Times: {TIME_LABELS[tcol]}. *Work ratio*: the cell-steps of the hand-made set-up over the "
                "planner's. *At equal error*: the planner's time at the baseline's gauge RMSE, interpolated "
                "(log-log) between the planner's members other than the reference (its end segments extended "
                f"up to a factor {EQUAL_ERROR_REACH:g} in error, marked *extrapolated*).", ""]
        head = ["baseline", "cells (hand / planner)", "steps (hand / planner)", "time (hand / planner)",
                "speed-up, same cell", "work ratio, same cell", "gauge RMSE vs finest, mm (hand / planner)",
                "planner time at equal error", "speed-up at equal error"]
        rows = []
        for s in study.speedups:
            rows.append([
                s["baseline"], f"{_fmt(s.get('baseline_cells'), ',.0f')} / {_fmt(s.get('planner_cells'), ',.0f')}",
                f"{_fmt(s.get('baseline_steps'), '.0f')} / {_fmt(s.get('planner_steps'), '.0f')}",
                f"{_duration(s.get('baseline_time_s'))} / {_duration(s.get('planner_time_s'))}",
                _fmt(s.get("speedup_same_cell"), ".1f") + "x" if s.get("speedup_same_cell") else "-",
                _fmt(s.get("work_ratio"), ".1f") + "x" if s.get("work_ratio") else "-",
                f"{_fmt(1e3 * s['baseline_gauge_rmse_vs_finest_m'], '.2f') if s.get('baseline_gauge_rmse_vs_finest_m') is not None else '-'}"
                f" / {_fmt(1e3 * s['planner_gauge_rmse_vs_finest_m'], '.2f') if s.get('planner_gauge_rmse_vs_finest_m') is not None else '-'}",
                _duration(s.get("planner_time_at_equal_error_s"))
                + (" (extrapolated)" if s.get("equal_error_extrapolated") else ""),
                _fmt(s.get("speedup_equal_error"), ".1f") + "x" if s.get("speedup_equal_error") else
                "- (outside the planner's range)",
            ])
        out += [_markdown_table(head, rows), ""]
    if study.extrapolation:
        cell = study.extrapolation[0]["cell_size_m"]
        out += [f"## Extrapolation to {1000 * cell:g} mm cells (not measured)", "",
                "Cells from the planner (exact). Time steps from the finest measured member of each set-up, "
                "scaled as 1 / cell size (a Courant-limited step): a lower bound where that member's step was "
                "still capped by maxDeltaT; *p* is the measured exponent of the steps (steps ~ cell size^-p) "
                f"between the set-up's two finest members. Cost per cell-step ({TIME_LABELS[tcol]}) as "
                "measured on that member. **An extrapolation, not a measurement.**", ""]
        head = ["set-up", "cells", "steps (extrapolated; measured p)", "cell-steps (extrapolated)",
                "us per cell-step (from)", "time (extrapolated)", "planner speed-up: work / time (extrapolated)"]
        rows = []
        for e in study.extrapolation:
            if "error" in e:
                rows.append([e["setup"], "-", "-", "-", "-", f"cannot plan: {e['error']}", "-"])
                continue
            p_text = "" if e.get("steps_local_exponent") is None else f"; p = {e['steps_local_exponent']:.2f}"
            speedup = "-"
            if e.get("speedup_of_planner_extrapolated"):
                speedup = f"{e['work_ratio_extrapolated']:.1f}x / {e['speedup_of_planner_extrapolated']:.1f}x"
            rows.append([e["setup"], f"{e['cells']:,}", f"{e['steps_extrapolated']:,}{p_text}",
                         f"{e['cell_steps_extrapolated'] / 1e9:.2f} G",
                         f"{e['us_per_cell_step']:.2f} ({e['from_member']})", _duration(e["time_s_extrapolated"]),
                         speedup])
        out += [_markdown_table(head, rows), ""]
    if study.notes:
        out += ["## Notes", ""] + [f"- {n}" for n in study.notes] + [""]
    return "\n".join(out)


def plot(study: SpeedError, path: str | Path) -> Path:
    """The Pareto plot: time against error, log axes, every member labelled, the front drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = study.table
    tcol = study.time_column
    ref_id = (study.reference or {}).get("member_id")
    panels = [("gauge_rmse_vs_finest_m", 1e3, "gauge RMSE against the finest member (mm)", "pareto_vs_finest"),
              ("chanson_arrival_mae_s", 1.0, "mean |arrival error| against Chanson (s)", "pareto_vs_chanson")]
    styles = {"planner": ("o", "#2c7bb6"), "hand": ("s", "#d7191c"), "custom": ("^", "#1a9641"),
              "unknown": ("x", "grey")}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, (metric, scale, ylabel, front_col) in zip(axes, panels):
        done = t[(t["status"] == "finished")]
        if metric not in t:
            ax.text(0.5, 0.5, "no data", ha="center", va="center", transform=ax.transAxes)
            continue
        pts = done[done[tcol].notna() & done[metric].notna()]
        pts = pts[(pts[tcol].astype(float) > 0) & (pts[metric].astype(float) > 0)]
        for setup, group in pts.groupby("setup"):
            marker, colour = styles.get(setup, styles["unknown"])
            ax.scatter(group[tcol].astype(float), scale * group[metric].astype(float), marker=marker, s=50,
                       color=colour, label=setup, zorder=3)
        for r in pts.itertuples():
            ax.annotate(r.label, (float(getattr(r, tcol)), scale * float(getattr(r, metric))),
                        textcoords="offset points", xytext=(6, 4), fontsize=8)
        front = pts[pts[front_col].astype(bool)].sort_values(tcol)
        if len(front):
            xs = front[tcol].astype(float).to_numpy()
            ys = scale * front[metric].astype(float).to_numpy()
            # the front as a staircase: each member holds until a costlier one is closer
            sx, sy = [xs[0]], [ys[0]]
            for x, y in zip(xs[1:], ys[1:]):
                sx += [x, x]
                sy += [sy[-1], y]
            ax.plot(sx, sy, "k--", lw=1, label="Pareto front", zorder=2)
        if metric.endswith("finest_m") and ref_id is not None:
            rr = t[t["member_id"] == ref_id]
            if len(rr) and finite_or_none(rr[tcol].iloc[0]):
                ax.axvline(float(rr[tcol].iloc[0]), color="grey", ls=":", lw=1)
                ax.annotate(f"reference: {rr['label'].iloc[0]}", (float(rr[tcol].iloc[0]), 0.02),
                            xycoords=("data", "axes fraction"), rotation=90, fontsize=8, color="grey",
                            xytext=(-10, 0), textcoords="offset points")
        if len(pts):
            from matplotlib.ticker import FuncFormatter

            ax.set_xscale("log")
            ax.set_yscale("log")
            def label(v: float, _pos) -> str:  # 1, 2, 3, 5 of each decade: readable, never crowded
                lead = round(v / 10 ** math.floor(math.log10(v) + 1e-9), 6) if v > 0 else 0
                return f"{v:g}" if lead in (1.0, 2.0, 3.0, 5.0) else ""

            for axis in (ax.xaxis, ax.yaxis):
                axis.set_major_formatter(FuncFormatter(label))
                axis.set_minor_formatter(FuncFormatter(label))
            ax.margins(x=0.12, y=0.08)
        else:
            ax.text(0.5, 0.5, "no finished member with this error", ha="center", va="center", transform=ax.transAxes)
        ax.set_xlabel(TIME_LABELS[tcol])
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Speed against error: {study.sweep_dir.name}")
    fig.tight_layout()
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=110)
    plt.close(fig)
    return write_bytes_atomic(path, png.getvalue())


def write_report(study: SpeedError, out_dir: str | Path | None = None) -> dict[str, Path]:
    """speed_error.csv, .md, .png and .json in out_dir (default SWEEP_DIR/report/)."""
    out = Path(out_dir) if out_dir is not None else study.sweep_dir / REPORT_DIR
    out.mkdir(parents=True, exist_ok=True)
    files = {"csv": out / "speed_error.csv", "markdown": out / "speed_error.md", "plot": out / "speed_error.png",
             "json": out / "speed_error.json"}
    study.table.to_csv(files["csv"], index=False, float_format="%.10g")
    write_text_atomic(files["markdown"], markdown(study))
    plot(study, files["plot"])
    study.files = files
    write_json_atomic(files["json"], study.headline())
    return files
