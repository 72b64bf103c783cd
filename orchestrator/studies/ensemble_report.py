"""An ensemble's report: ``report.md`` with its histograms and its tracks' envelope.

* ``histograms.png``: each struck body's first column strike over the ensemble, like for like
  with the study: the centre's speed and its part along the normal, the study-fit pulse's peak
  force, duration and impulse (the base shear fitted as the study fitted its records; the
  contact law's pulse drawn beside as an outline) and the fit's load height (the water level at
  the face), with the study's mean and one standard deviation (speed 1.60 +- 0.13 m/s; Table 2's
  MDOF row: 171 +- 63 N, 4.7 +- 0.5 ms, 0.52 +- 0.22 N s; heights 0.16-0.50 m).
* ``envelope.png``: every track in plan view, their envelope (the lowest and highest y reached in
  each x interval), the starts, the column, the flume's side walls and the spreading areas'
  edges of ASCE 7-22 6.11.5.1 (Naito et al. 2014, and Nistor et al. 2017b:
  :data:`~orchestrator.results.compare.SPREADING_ANGLES_DEG`) from the nominal start line.
* ``report.md``: what was run, the impact probability, the like-for-like table with Welch's
  test (:mod:`orchestrator.report.study_table`), the law's figures beside the study's, the
  figures.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.patches import Rectangle

from analytical.study import STUDY_IMPACT_HEIGHTS_M
from orchestrator.core.files import write_text_atomic
from orchestrator.report.figures import SMALL, WIDTH_IN, empty, legend, note, pyplot, save_figure
from orchestrator.report.study_table import comparison_markdown, comparison_note
from orchestrator.results.compare import SPREADING_ANGLES_DEG, spreading_area

__all__ = ["HISTOGRAMS", "figure_envelope", "figure_histograms", "markdown", "write_report"]

#: (column of ensemble.csv, axis label, key of the study's figures or None, the law's column drawn
#: beside or None)
HISTOGRAMS = [
    ("impact_speed_m_s", "impact speed of the centre (m/s)", "impact_velocity_m_s", None),
    ("impact_velocity_m_s", "its part along the normal (m/s)", "impact_velocity_m_s", None),
    ("study_fit_peak_N", "study-fit peak force (N)", "peak_force_N", "peak_force_N"),
    ("study_fit_duration_s", "study-fit duration (s)", "duration_s", "duration_s"),
    ("study_fit_impulse_Ns", "study-fit impulse (N s)", "impulse_Ns", "impulse_Ns"),
    ("study_fit_height_m", "load height of the fit (m)", None, "impact_height_m"),
]


def figure_histograms(table, summary: dict[str, Any]):
    """Six histograms of the first strikes (module notes)."""
    plt = pyplot()
    fig, axes = plt.subplots(2, 3, figsize=(WIDTH_IN, 6.2), layout="constrained")
    struck = table[table["struck"].astype(bool)] if len(table) else table
    study = summary.get("study", {})
    for ax, (column, label, study_key, law) in zip(axes.ravel(), HISTOGRAMS):
        values = struck[column].dropna().to_numpy(float) if len(struck) and column in struck else np.array([])
        if not values.size:
            empty(ax, "no column strike")
            ax.set_title(label, fontsize=10, loc="left")
            continue
        beside = struck[law].dropna().to_numpy(float) if law and law in struck else np.array([])
        lo_edge = min(values.min(), beside.min()) if beside.size else values.min()
        hi_edge = max(values.max(), beside.max()) if beside.size else values.max()
        bins = np.linspace(lo_edge, hi_edge if hi_edge > lo_edge else lo_edge + 1e-9,
                           max(5, min(30, int(math.sqrt(values.size)) + 3)) + 1)
        ax.hist(values, bins=bins, color="#2b83ba", alpha=0.8, label=f"ensemble ({values.size} strikes)")
        ax.axvline(float(values.mean()), color="#2b83ba", lw=2.0, ls="--", label="ensemble mean")
        if beside.size:
            ax.hist(beside, bins=bins, histtype="step", color="0.25", lw=1.2,
                    label="contact point" if law == "impact_height_m" else "the contact law's pulse")
        ref = study.get(study_key) if study_key else None
        if ref:
            lo, hi = ref["mean"] - ref["std"], ref["mean"] + ref["std"]
            ax.axvspan(lo, hi, color="#d7191c", alpha=0.15, label="study mean +- 1 std")
            ax.axvline(ref["mean"], color="#d7191c", lw=1.6, label="study mean")
        if column == "study_fit_height_m":
            ax.axvspan(STUDY_IMPACT_HEIGHTS_M[0], STUDY_IMPACT_HEIGHTS_M[1], color="#d7191c", alpha=0.12,
                       label="the study's impact heights")
        ax.set_xlabel(label)
        ax.set_ylabel("strikes")
        ax.grid(alpha=0.3)
        legend(ax, loc="best")
    fig.suptitle(f"First column strike of each body over {summary['realisations']} realisations "
                 f"(impact probability {_pct(summary.get('impact_probability'))})", fontsize=11)
    return fig


def _pct(value) -> str:
    return "-" if value is None else f"{100 * value:.0f} %"


def _dense(tracks, per_segment: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Every track's points with ``per_segment`` points along each segment, so that each x
    interval of the envelope sees the lines, not only the points written every output interval."""
    xs, ys = [], []
    for _, track in tracks.groupby(["realisation", "body"], sort=False):
        x, y = track["x_m"].to_numpy(float), track["y_m"].to_numpy(float)
        s = np.linspace(0.0, x.size - 1.0, max(1, (x.size - 1) * per_segment + 1))
        xs.append(np.interp(s, np.arange(x.size), x))
        ys.append(np.interp(s, np.arange(y.size), y))
    return np.concatenate(xs), np.concatenate(ys)


def figure_envelope(tracks, table, bodies, flume_y, column, x_end_m: float):
    """Plan view: every track, their envelope, starts, column, walls and the spreading areas' edges."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(WIDTH_IN, 6.4), layout="constrained")
    if tracks is None or not len(tracks):
        empty(ax, "no tracks")
        return fig
    for (_, _), track in tracks.groupby(["realisation", "body"], sort=False):
        ax.plot(track["x_m"], track["y_m"], lw=0.6, color="0.35", alpha=0.25, label="a realisation's track")
    x, y = _dense(tracks)
    edges = np.linspace(x.min(), x.max(), 61)
    bins = np.clip(np.digitize(x, edges) - 1, 0, edges.size - 2)
    mids, lows, highs = [], [], []
    for k in range(edges.size - 1):
        inside = bins == k
        if inside.any():
            mids.append(0.5 * (edges[k] + edges[k + 1]))
            lows.append(y[inside].min())
            highs.append(y[inside].max())
    ax.fill_between(mids, lows, highs, color="#fdae61", alpha=0.35, lw=0, label="envelope of the tracks")
    ax.plot(mids, lows, color="#e66101", lw=1.2)
    ax.plot(mids, highs, color="#e66101", lw=1.2)
    ax.scatter(table["start_x_m"], table["start_y_m"], s=8, color="#2b83ba", zorder=4, label="perturbed starts")
    src = np.array([b.centre_m[:2] for b in bodies], dtype=float)
    ax.scatter(src[:, 0], src[:, 1], marker="s", s=40, color="k", zorder=5, label="nominal starts")
    for (name, spec), colour in zip(SPREADING_ANGLES_DEG.items(), ["#2b83ba", "#7b3294"]):
        poly = spreading_area(src, spec["half_angle_deg"], x_end_m)
        flag = "" if spec["verified"] else " (unverified)"
        for a, b in ((0, 1), (3, 2)):
            ax.plot(poly[[a, b], 0], poly[[a, b], 1], color=colour, lw=1.4, ls="--",
                    label=f"spreading area edge, {name}, {spec['half_angle_deg']:g} deg{flag}")
    if column is not None:
        c = column.column
        ax.add_patch(Rectangle((column.x_m - c.size_x_m / 2, column.y_m - c.size_y_m / 2), c.size_x_m, c.size_y_m,
                               color="#5f6b73", label="column", zorder=3))
    for wall in flume_y:
        ax.axhline(wall, color="0.2", lw=1.4, label="side walls")
    pad = 0.05 * (flume_y[1] - flume_y[0])
    ax.set_ylim(flume_y[0] - pad, flume_y[1] + pad)
    x_lo = min(float(x.min()), float(src[:, 0].min()))
    x_hi = max(float(x.max()), column.x_m + column.column.size_x_m if column is not None else float(x.max()))
    ax.set_xlim(x_lo - 0.1 * (x_hi - x_lo + 0.2), x_hi + 0.1 * (x_hi - x_lo + 0.2))
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x along the flume (m)")
    ax.set_ylabel("y across (m)")
    ax.set_title("All tracks (centre of mass) in plan view, their envelope, and the spreading areas\n"
                 "(ASCE 7-22 6.11.5.1) from the nominal start line", fontsize=10, loc="left")
    ax.grid(alpha=0.3)
    legend(ax, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, fontsize=SMALL)
    note(ax, [f"{tracks.groupby(['realisation', 'body']).ngroups} tracks"], left=True)
    return fig


def _figure(stats: dict[str, Any] | None, digits: int = 3) -> str:
    if not stats or stats.get("mean") is None:
        return "-"
    std = stats.get("std")
    text = f"{stats['mean']:.{digits}g}" + (f" +- {std:.{digits}g}" if std is not None else "")
    return text + (f" ({stats['count']})" if "count" in stats else "")


def markdown(summary: dict[str, Any], figures: dict[str, Path]) -> str:
    """report.md's text."""
    p = summary.get("perturbation", {})
    study = summary.get("study", {})
    lines = [
        f"# Ensemble of {summary['realisations']} realisations: {Path(summary.get('scene', '')).name}", "",
        f"One recorded flow ({summary.get('flow_case')}), {summary['realisations']} perturbed starts of "
        f"{summary['bodies']} bod{'y' if summary['bodies'] == 1 else 'ies'} carried through it on MuJoCo for "
        f"{summary.get('end_time_s', 0):g} s (seed {summary.get('seed')}, {summary.get('executor')} executor, "
        f"{summary.get('workers')} worker(s)).", "",
        *([f"The flow's scene: {Path(summary.get('scene', '')).name} with "
           + ", ".join(f"`{o}`" for o in summary["overrides"]) + ".", ""] if summary.get("overrides") else []),
        f"Starts: position offsets in x and y normal with a standard deviation of "
        f"{p.get('position_sigma_fraction', 0):g} x the body's length, yaw offsets normal with "
        f"{p.get('yaw_sigma_deg', 0):g} deg, both clipped at {p.get('clip_sigmas', 0):g} standard deviations; every "
        f"start at least {p.get('min_gap_m', 0):g} m from the walls, the column and the other bodies (docs/ensembles.md).", "",
        f"**Impact probability: {_pct(summary.get('impact_probability'))}** of the (realisation, body) pairs "
        "struck the column. Pulses: "
        f"{summary.get('pulses')}.", "",
        "## The first strikes beside the study's 22, like for like", "",
        *comparison_markdown(summary.get("comparison", {})), "",
        comparison_note(), "",
        "## The first strikes' other figures", "",
        "| first column strike | ensemble mean +- std (strikes) | study mean +- std (22 impacts) |",
        "|---|---|---|",
    ]
    for key, label in (("peak_force_N", "the contact law's peak force (N)"),
                       ("duration_s", "the contact law's duration (s)"),
                       ("impulse_Ns", "the contact law's impulse (N s)"),
                       ("study_fit_start_s", "study-fit start from the contact (s)"),
                       ("study_fit_nrmse", "study-fit residual / record peak"),
                       ("impact_time_s", "time (s)"), ("impact_height_m", "contact height above the bed (m)"),
                       ("face_water_level_m", "water level at the face (m)"),
                       ("time_since_front_s", "time since the front reached the face (s; negative: ahead of it)"),
                       ("obliquity_deg", "obliquity (deg)"), ("peak_base_shear_N", "peak base shear (N)"),
                       ("effective_mass_kg", "effective mass at the contact, added mass included (kg)")):
        ref = study.get(key) if key in ("peak_force_N", "duration_s", "impulse_Ns") else None
        study_text = _figure(ref) if ref else ("0.16-0.50, mean 0.40" if key == "face_water_level_m" else "-")
        lines.append(f"| {label} | {_figure(summary.get(key))} | {study_text} |")
    lines += [
        "", "The study's figures are its 22 single-container releases: speeds backed out of Table 2's ASCE "
        "rows, loads from Table 2's MDOF row (the study's fits of its measured base shear, which the law's pulse "
        "is not: the like-for-like table above sets the tool's fits against them). Their scatter comes from every "
        "difference between releases (the start, the gate, the bore); the ensemble's only from the start, through "
        "one flow.", "",
        f"Strikes per struck body: {_figure(summary.get('strikes_per_struck_body'))}. Wall time: "
        f"{summary.get('wall_time_s')} s for the flow (run or loaded) and the realisations, {summary.get('transport_wall_time_s')} s of transport "
        f"(a realisation {_figure(summary.get('realisation_wall_time_s'))} s, of which the study fit of its first "
        f"strike {_figure(summary.get('study_fit_wall_s'))} s).", "",
    ]
    for name, path in figures.items():
        lines += [f"![{name}]({path.name})", ""]
    lines += ["Tables: ensemble.csv (one row per realisation and body), tracks.csv, ensemble.json.", ""]
    return "\n".join(lines)


def write_report(out_dir: str | Path, result, scene, bodies, column) -> dict[str, Path]:
    """histograms.png, envelope.png and report.md in ``out_dir``; their paths by name."""
    out = Path(out_dir)
    figures = {"histograms": save_figure(figure_histograms(result.table, result.summary), out / "histograms.png")}
    half = scene.flume.width_m / 2.0
    x_end = float(result.tracks["x_m"].max()) if len(result.tracks) else 0.0
    if column is not None:
        x_end = max(x_end, column.x_m + column.column.size_x_m)
    figures["envelope"] = save_figure(figure_envelope(result.tracks, result.table, bodies, (-half, half), column,
                                                      x_end), out / "envelope.png")
    report = write_text_atomic(out / "report.md", markdown(result.summary, figures))
    return {**figures, "report": report}
