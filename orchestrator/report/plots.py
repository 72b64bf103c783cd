"""The comparison plots of a run, as PNG files in DIR/results/ (matplotlib, Agg; pyvista off-screen).

:func:`make_plots` draws, from the tables of :func:`orchestrator.results.tables.tables` and
the comparisons of :mod:`orchestrator.results.compare`:

``gauges.png``          elevation at every gauge against Ritter, Stoker and Chanson, with the
                        simulated, analytical and the study's arrival times marked (study Fig. 10);
``column_forces.png``   the hydrodynamic force on the column (pressure, viscous, total) and the base
                        shear it causes, each on a linear axis of its own; below them, when the run
                        has impacts, the impact pulses with the sum, and the base shear from them
                        with the total (tens of newtons and hundreds do not share one axis); then
                        each impact zoomed to milliseconds, its peaks marked and written out;
``impacts.png``,        the impact pulses against the predicted and fitted ones, and the study's
``study_fits.png``       fits to the simulated base shear (:mod:`orchestrator.report.impact_plots`);
``tracks.png``          debris tracks in plan view with the spreading areas, and the bodies'
                        speeds (:mod:`orchestrator.report.track_plots`);
``snapshot.png``        a 3D view at the first impact (:mod:`orchestrator.report.snapshot`).

The gauge and column-force figures are drawn here. Every PNG follows
:mod:`orchestrator.report.figures` (at most 10.5 in wide at 150 dpi, no text under 9 pt, every
drawn line in a legend); tests/test_plots.py checks these on the figures that the ``figure_*``
functions return (``plot_*`` save them).

Every PNG is written for every run: a plot with nothing to show says so on its face (no
debris, no impacts, a run stopped before the bore arrived), so a report never links to a
missing file. Only the snapshot needs fields on disk; without them it says why.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from orchestrator.report.figures import WIDTH_IN, empty, legend, pyplot, save_figure
from orchestrator.report.impact_plots import figure_impacts, figure_study_fits, plot_impacts, plot_study_fits
from orchestrator.report.snapshot import snapshot
from orchestrator.report.track_plots import figure_tracks, plot_tracks

__all__ = ["PLOTS", "figure_column_forces", "figure_gauges", "figure_impacts", "figure_study_fits", "figure_tracks",
           "make_plots", "snapshot"]

#: The PNGs make_plots writes (name -> file).
PLOTS = {
    "gauges": "gauges.png",
    "column_forces": "column_forces.png",
    "impacts": "impacts.png",
    "study_fits": "study_fits.png",
    "tracks": "tracks.png",
    "snapshot": "snapshot.png",
}
#: Label and line style of each analytical dam-break model on the gauge plot.
_MODEL_STYLE = {"ritter": ("Ritter", "--"), "stoker": ("Stoker", "-."), "chanson": ("Chanson", ":")}


# --------------------------------------------------------------------------- gauges


def figure_gauges(results, comp):
    """Elevation at each gauge (a row each) against the analytical models, with the arrivals marked."""
    plt = pyplot()
    summary = results.gauge_summary
    n = max(len(summary), 1)
    row_in = max(1.7, min(2.4, 10.0 / n))
    fig, axes = plt.subplots(n, 1, figsize=(WIDTH_IN, row_in * n + 0.9), sharex=True, squeeze=False,
                             layout="constrained")
    axes = axes[:, 0]
    if summary.empty:
        empty(axes[0], "no gauge output in this run")
        return fig
    g = results.gauges
    for ax, r in zip(axes, summary.itertuples()):
        col = f"{r.gauge}_elevation_m"
        if col in g:
            ax.plot(g["time_s"], g[col], color="k", lw=1.6, label="simulated")
        model = comp.gauge_models.get(r.gauge)
        if model is not None:
            for key, (label, style) in _MODEL_STYLE.items():
                if f"{key}_m" in model:
                    ax.plot(model["time_s"], model[f"{key}_m"], ls=style, lw=1.2, label=label)
        if np.isfinite(r.arrival_s):
            ax.axvline(r.arrival_s, color="k", lw=0.8, alpha=0.6, label="simulated arrival")
        arr = comp.arrivals[comp.arrivals["gauge"] == r.gauge]
        for a in arr.itertuples():
            if a.reference.startswith("study"):
                marker = "v" if "experiment" in a.reference else "^"
                ax.plot([a.reference_arrival_s], [0.0], marker=marker, ms=8, ls="none",
                        color="#7b3294" if "experiment" in a.reference else "#c2a5cf", label=a.reference)
        ax.set_ylabel("elevation (m)")
        ax.set_title(f"{r.gauge} at x = {r.x_m:.2f} m, y = {r.y_m:.2f} m", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
        legend(ax, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[-1].set_xlabel("time since the gate opened (s)")
    fig.suptitle("Water surface elevation at the gauges", fontsize=11)
    return fig


def plot_gauges(results, comp, path: Path) -> Path:
    """gauges.png: :func:`figure_gauges` saved."""
    return save_figure(figure_gauges(results, comp), path)


# --------------------------------------------------------------------------- column forces


def _column_impact_times(results) -> list[float]:
    imp = results.impacts
    if imp is None or not len(imp):
        return []
    if "kind" in imp:
        imp = imp[imp["kind"] == "column"]
    return [float(t) for t in imp["time_s"]]


def figure_column_forces(results):
    """Hydrodynamic force and impact pulses on linear axes of their own.

    The CFD force on the column is tens of newtons at most in the flume, an impact pulse
    hundreds: one axis would flatten the one or (symlog) distort it, so the force and the
    base shear each get a panel for the hydrodynamic part and, when the run has impacts,
    one below for the impact part and the total.
    """
    plt = pyplot()
    cf, cr = results.column_forces, results.column_response
    has_forces = not cf.empty and "time_s" in cf and len(cf) > 0
    has_impacts = has_forces and "impact_force_x_N" in cf and float(cf["impact_force_x_N"].abs().max()) > 0
    nrows = 2 if has_impacts else 1
    windows = _impact_windows(results) if has_impacts else []
    height = 3.3 * nrows + 0.7 + (2.9 if windows else 0.0)
    fig = plt.figure(figsize=(WIDTH_IN, height), layout="constrained")
    if windows:
        top, bottom = fig.subfigures(2, 1, height_ratios=[3.3 * nrows + 0.7, 2.9])
    else:
        top, bottom = fig, None
    axes = top.subplots(nrows, 2, sharex=True, squeeze=False)
    hydro, shear = axes[0]
    hydro.set_label("hydrodynamic force")
    shear.set_label("hydrodynamic base shear")
    impact_times = _column_impact_times(results)
    if not has_forces:
        empty(hydro, "no column forces in this run")
    else:
        t = cf["time_s"]
        for name, label, style in (("pressure_force_x_N", "pressure", ":"), ("viscous_force_x_N", "viscous", "--"),
                                   ("hydro_force_x_N", "hydrodynamic (CFD) = pressure + viscous", "-")):
            if name in cf:
                hydro.plot(t, cf[name], ls=style, lw=1.4, label=label)
        for ti in impact_times:
            hydro.axvline(ti, color="#d7191c", lw=0.8, ls=(0, (2, 3)), label="impact (pulse below)")
        hydro.set_ylabel("force on the column, x (N)")
        hydro.set_title("hydrodynamic force on the column (CFD)", fontsize=10, loc="left")
        hydro.grid(alpha=0.3)
        legend(hydro, loc="best")
    if cr.empty or "base_shear_x_N" not in cr:
        empty(shear, "no column response (no column, or no loads)")
    else:
        t = cr["time_s"]
        shear.plot(t, cr["hydro_base_shear_x_N"], lw=1.4, label="from the hydrodynamic force")
        for ti in impact_times:
            shear.axvline(ti, color="#d7191c", lw=0.8, ls=(0, (2, 3)), label="impact (response below)")
        z = results.hydro_heights_m.get("x")
        shear.set_title("base shear from the CFD force" + (f" (load at z = {z:.3f} m)" if z else ""),
                        fontsize=10, loc="left")
        shear.set_ylabel("MDOF column base shear, x (N)")
        shear.grid(alpha=0.3)
        legend(shear, loc="best")
    if has_impacts:
        pulses, total = axes[1]
        t = cf["time_s"]
        pulses.plot(t, cf["impact_force_x_N"], color="#d7191c", lw=1.4, label="impact pulses (contact model)")
        pulses.plot(t, cf["total_force_x_N"], color="k", lw=0.8, alpha=0.7, label="sum: hydrodynamic + impacts")
        pulses.set_ylabel("force on the column, x (N)")
        pulses.set_title("impact pulses on the column", fontsize=10, loc="left")
        pulses.grid(alpha=0.3)
        legend(pulses, loc="best")
        if not cr.empty and "impact_base_shear_x_N" in cr:
            t = cr["time_s"]
            total.plot(t, cr["impact_base_shear_x_N"], lw=1.2, color="#d7191c", label="from the impacts")
            total.plot(t, cr["base_shear_x_N"], lw=0.8, color="k", alpha=0.7, label="total")
            total.set_title("base shear from the impacts, and the total", fontsize=10, loc="left")
            total.set_ylabel("MDOF column base shear, x (N)")
            total.grid(alpha=0.3)
            legend(total, loc="best")
        else:
            empty(total, "no column response to the impacts")
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    if bottom is not None:
        _zoom_panels(bottom, results, windows)
    return fig


#: At most this many impacts get a zoom panel (the rest are named in the last panel's title).
MAX_ZOOMS = 4


def _impact_windows(results) -> list[tuple[int, float, float, float]]:
    """(event, start, end, duration) of each column impact's zoom: from half a pulse before its
    start to two and a half pulses after (the pulse is milliseconds on an axis of seconds)."""
    imp = results.impacts
    if imp is None or not len(imp):
        return []
    if "kind" in imp:
        imp = imp[imp["kind"] == "column"]
    out = []
    for r in imp.itertuples():
        duration = float(getattr(r, "duration_s", np.nan))
        duration = duration if np.isfinite(duration) and duration > 0 else 0.005
        t0 = float(r.time_s)
        out.append((int(getattr(r, "event", len(out) + 1)), t0 - 0.5 * duration, t0 + 2.5 * duration, duration))
    return out


def _zoom_panels(sub, results, windows) -> None:
    """One panel per impact (at most MAX_ZOOMS): its pulse and the base shear it causes, in ms
    from the impact, each peak marked and written out."""
    cf, cr = results.column_forces, results.column_response
    shown = windows[:MAX_ZOOMS]
    axes = sub.subplots(1, len(shown), squeeze=False)[0]
    for ax, (event, start, end, duration) in zip(axes, shown):
        t_ref = start + 0.5 * duration
        peaks = []
        for frame, column, label, colour in ((cf, "impact_force_x_N", "impact pulse", "#d7191c"),
                                             (cr, "impact_base_shear_x_N", "base shear from it", "#2c7bb6")):
            if frame is None or frame.empty or column not in frame:
                continue
            part = frame[(frame["time_s"] >= start) & (frame["time_s"] <= end)]
            if part.empty:
                continue
            ms = 1e3 * (part["time_s"].to_numpy() - t_ref)
            values = part[column].to_numpy()
            ax.plot(ms, values, color=colour, lw=1.3, label=label)
            k = int(np.argmax(np.abs(values)))
            ax.scatter([ms[k]], [values[k]], color=colour, s=16, zorder=3)  # the peak, written out in the box
            peaks.append(f"{label}: peak {values[k]:.0f} N at {ms[k]:+.2f} ms")
        ax.set_title(f"impact {event} at t = {t_ref:.4f} s, {1e3 * duration:.2f} ms", fontsize=9, loc="left")
        ax.text(0.98, 0.97, "\n".join(peaks), transform=ax.transAxes, ha="right", va="top", fontsize=9,
                bbox={"boxstyle": "round", "fc": "white", "ec": "0.8", "alpha": 0.9})
        ax.set_xlabel("time from the impact (ms)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("x (N)")
    legend(axes[0], loc="lower right")
    if len(windows) > len(shown):
        axes[-1].set_title(axes[-1].get_title() + f" (+{len(windows) - len(shown)} more)", fontsize=9, loc="left")
    sub.suptitle("each impact, zoomed: the pulse and the base shear it causes", fontsize=10, x=0.01,
                 ha="left")


def plot_column_forces(results, path: Path) -> Path:
    """column_forces.png: :func:`figure_column_forces` saved."""
    return save_figure(figure_column_forces(results), path)


# --------------------------------------------------------------------------- entry point


def make_plots(results, comp, out_dir: str | Path, snapshot_3d: bool = True) -> tuple[dict[str, Path], list[str]]:
    """Every PNG of :data:`PLOTS` in out_dir; returns ({name: path}, notes)."""
    out = Path(out_dir)
    notes: list[str] = []
    written = {
        "gauges": plot_gauges(results, comp, out / PLOTS["gauges"]),
        "column_forces": plot_column_forces(results, out / PLOTS["column_forces"]),
        "impacts": plot_impacts(results, comp, out / PLOTS["impacts"]),
        "study_fits": plot_study_fits(results, comp, out / PLOTS["study_fits"]),
        "tracks": plot_tracks(results, comp, out / PLOTS["tracks"]),
    }
    if snapshot_3d:
        written["snapshot"], note = snapshot(results, out / PLOTS["snapshot"])
        if note:
            notes.append(note)
    return written, notes
