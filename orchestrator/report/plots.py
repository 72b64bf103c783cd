"""The comparison plots of a run, as PNG files in DIR/results/ (matplotlib, Agg; pyvista off-screen).

:func:`make_plots` draws, from :mod:`orchestrator.results.post`'s tables and
:mod:`orchestrator.results.compare`'s comparisons:

``gauges.png``          elevation at every gauge against Ritter, Stoker and Chanson, with the
                        simulated, analytical and seed arrival times marked (seed Fig. 10);
``column_forces.png``   the hydrodynamic force on the column (pressure, viscous, total) and the base
                        shear it causes, each on a linear axis of its own; below them, when the run
                        has impacts, the impact pulses with the sum, and the base shear from them
                        with the total (tens of newtons and hundreds do not share one axis);
``impacts.png``         per column impact (up to four, a row each): the contact model's pulse
                        against the ASCE 7-22 (k_d, k_s) pulses from the impact velocity, over the
                        band of the study's MDOF pulses (Table 2: magnitude and duration within
                        one standard deviation of the mean), and beside it the SDOF/MDOF pulses
                        fitted to the base shear that contact pulse caused (seed Fig. 4b), dashed
                        and apart, so that a fit matching the pulse reads as a check of the fit;
                        a missing pulse says why; below, the peak force of every method at the
                        simulated impact velocity;
``seed_fits.png``       the simulated base shear of each impact with the SDOF and MDOF fits
                        (seed Fig. 4a) and every pulse's response on the MDOF column (Fig. 5);
``tracks.png``          debris tracks in plan view with the column, the gauges and the
                        spreading areas of Naito et al. (2014) and Nistor et al. (2017b) cut at
                        the flume walls (seed Fig. 14), and the bodies' speeds; the plan's height
                        follows the framed region's aspect;
``snapshot.png``        a 3D view at the first impact (else at the peak hydrodynamic force):
                        free surface (alpha.water = 0.5), column, debris, read from the written
                        fields (decomposed or reconstructed) with pyvista.

Every PNG is at most 10.5 in wide at 150 dpi (1,575 px, a report page at 100 %), no text under
9 pt, every drawn line in a legend; tests/test_plots.py checks these on the figures that the
``figure_*`` functions return (``plot_*`` save them).

Every PNG is written for every run: a plot with nothing to show says so on its face (no
debris, no impacts, a run stopped before the bore arrived), so a report never links to a
missing file. Only the snapshot needs fields on disk; without them it says why.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from analytical.contact_law import SEED_TABLE2_MDOF

__all__ = ["PLOTS", "make_plots", "snapshot"]

#: The PNGs make_plots writes (name -> file).
PLOTS = {
    "gauges": "gauges.png",
    "column_forces": "column_forces.png",
    "impacts": "impacts.png",
    "seed_fits": "seed_fits.png",
    "tracks": "tracks.png",
    "snapshot": "snapshot.png",
}
_MODEL_STYLE = {"ritter": ("Ritter", "--"), "stoker": ("Stoker", "-."), "chanson": ("Chanson", ":")}
_METHOD_COLOURS = {
    "contact model (simulated)": "#d7191c",
    "ASCE 7-22, k_d": "#2c7bb6",
    "ASCE 7-22, k_s": "#74add1",
    "SDOF fit": "#e66101",
    "MDOF fit": "#1a9641",
}
#: The seed's fitted pulses: fitted to the base shear a run's contact pulse caused, so drawn
#: dashed and labelled as fits, apart from the pulses predicted from the impact velocity.
_FITS = ("SDOF fit", "MDOF fit")
_FIT_LABEL = "{} (fitted to this run's base shear)"
#: Every PNG at _DPI from a figure at most _WIDTH_IN wide: 1,575 px, a report's page width
#: at 100 %; no text smaller than _SMALL points (legends, ticks, notes).
_DPI = 150
_WIDTH_IN = 10.5
_SMALL = 9
_EVENT_COLOURS = ("#d7191c", "#2c7bb6", "#1a9641", "#7b3294")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path: Path) -> Path:
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.png")
    fig.savefig(tmp, dpi=_DPI)
    _pyplot().close(fig)
    os.replace(tmp, path)
    return path


def _empty(ax, message: str) -> None:
    ax.text(0.5, 0.5, message, ha="center", va="center", transform=ax.transAxes, fontsize=11, wrap=True)
    ax.set_xticks([])
    ax.set_yticks([])


def _handles(*axes) -> dict:
    """Each label of the axes' lines, patches and collections once, with its first artist."""
    out: dict = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            out.setdefault(label, handle)
    return out


def _legend(ax, **kwargs):
    """A legend with each label once (repeated markers such as impact times share one entry)."""
    kwargs.setdefault("fontsize", _SMALL)
    entries = _handles(ax)
    return ax.legend(list(entries.values()), list(entries), **kwargs) if entries else None


def _legend_axes(ax, sources, ncol: int = 3) -> None:
    """A legend alone in ``ax`` (its frame hidden) for the lines of every axes in ``sources``."""
    ax.axis("off")
    entries = _handles(*sources)
    if entries:
        ax.legend(list(entries.values()), list(entries), loc="center", ncol=ncol, fontsize=_SMALL, frameon=False)


def _note(ax, lines: list[str], width: int = 60, left: bool = False) -> None:
    """What a panel lacks and why, in an upper corner (the right one unless ``left``)."""
    import textwrap

    if lines:
        text = "\n".join(textwrap.fill(line, width) for line in lines)
        ax.text(0.01 if left else 0.99, 0.97, text, transform=ax.transAxes, ha="left" if left else "right",
                va="top", fontsize=_SMALL,
                bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.6", "alpha": 0.9}, zorder=6)


# --------------------------------------------------------------------------- gauges


def figure_gauges(results, comp):
    plt = _pyplot()
    summary = results.gauge_summary
    n = max(len(summary), 1)
    row_in = max(1.7, min(2.4, 10.0 / n))
    fig, axes = plt.subplots(n, 1, figsize=(_WIDTH_IN, row_in * n + 0.9), sharex=True, squeeze=False,
                             layout="constrained")
    axes = axes[:, 0]
    if summary.empty:
        _empty(axes[0], "no gauge output in this run")
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
            if a.reference.startswith("seed"):
                marker = "v" if "experiment" in a.reference else "^"
                ax.plot([a.reference_arrival_s], [0.0], marker=marker, ms=8, ls="none",
                        color="#7b3294" if "experiment" in a.reference else "#c2a5cf", label=a.reference)
        ax.set_ylabel("elevation (m)")
        ax.set_title(f"{r.gauge} at x = {r.x_m:.2f} m, y = {r.y_m:.2f} m", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
        _legend(ax, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes[-1].set_xlabel("time since the gate opened (s)")
    fig.suptitle("Water surface elevation at the gauges", fontsize=11)
    return fig


def plot_gauges(results, comp, path: Path) -> Path:
    return _save(figure_gauges(results, comp), path)


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
    plt = _pyplot()
    cf, cr = results.column_forces, results.column_response
    has_forces = not cf.empty and "time_s" in cf and len(cf) > 0
    has_impacts = has_forces and "impact_force_x_N" in cf and float(cf["impact_force_x_N"].abs().max()) > 0
    nrows = 2 if has_impacts else 1
    fig, axes = plt.subplots(nrows, 2, figsize=(_WIDTH_IN, 3.3 * nrows + 0.7), sharex=True, squeeze=False,
                             layout="constrained")
    hydro, shear = axes[0]
    hydro.set_label("hydrodynamic force")
    shear.set_label("hydrodynamic base shear")
    impact_times = _column_impact_times(results)
    if not has_forces:
        _empty(hydro, "no column forces in this run")
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
        _legend(hydro, loc="best")
    if cr.empty or "base_shear_x_N" not in cr:
        _empty(shear, "no column response (no column, or no loads)")
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
        _legend(shear, loc="best")
    if has_impacts:
        pulses, total = axes[1]
        t = cf["time_s"]
        pulses.plot(t, cf["impact_force_x_N"], color="#d7191c", lw=1.4, label="impact pulses (contact model)")
        pulses.plot(t, cf["total_force_x_N"], color="k", lw=0.8, alpha=0.7, label="sum: hydrodynamic + impacts")
        pulses.set_ylabel("force on the column, x (N)")
        pulses.set_title("impact pulses on the column", fontsize=10, loc="left")
        pulses.grid(alpha=0.3)
        _legend(pulses, loc="best")
        if not cr.empty and "impact_base_shear_x_N" in cr:
            t = cr["time_s"]
            total.plot(t, cr["impact_base_shear_x_N"], lw=1.2, color="#d7191c", label="from the impacts")
            total.plot(t, cr["base_shear_x_N"], lw=0.8, color="k", alpha=0.7, label="total")
            total.set_title("base shear from the impacts, and the total", fontsize=10, loc="left")
            total.set_ylabel("MDOF column base shear, x (N)")
            total.grid(alpha=0.3)
            _legend(total, loc="best")
        else:
            _empty(total, "no column response to the impacts")
    for ax in axes[-1]:
        ax.set_xlabel("time (s)")
    return fig


def plot_column_forces(results, path: Path) -> Path:
    return _save(figure_column_forces(results), path)


# --------------------------------------------------------------------------- impacts


def _events(comp, limit: int = 4) -> list[int]:
    return sorted(comp.fit_records)[:limit]


def _seed_pulse_band(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The band of half-sines with the study's MDOF magnitudes and durations, each within one
    standard deviation of its Table 2 mean: the lowest and highest such pulse at each time."""
    (f_mean, f_std), (d_mean, d_std) = SEED_TABLE2_MDOF["peak_force_N"], SEED_TABLE2_MDOF["duration_s"]
    curves = [f * np.where((t >= 0) & (t <= d), np.sin(np.pi * np.clip(t, 0, None) / d), 0.0)
              for f in (f_mean - f_std, f_mean + f_std) for d in np.linspace(d_mean - d_std, d_mean + d_std, 5)]
    return np.min(curves, axis=0), np.max(curves, axis=0)


def _missing_pulses(rec, comp, event: int) -> list[str]:
    """Why a pulse an impact panel would show is not there (from compare's notes)."""
    pulses, lines = rec["pulses"], []
    if "ASCE 7-22, k_d" not in pulses:
        lines.append("no ASCE 7-22 pulses: the body's mass or its impact velocity is unknown")
    for name in _FITS:
        if name in pulses:
            continue
        prefix = f"impact event {event}: the {name} failed ("
        why = next((n[len(prefix):] for n in comp.notes if n.startswith(prefix)), None)
        if why is not None:
            lines.append(f"no {name}: the fit failed ({why.removesuffix(')')})")
        else:
            lines.append(f"no {name}: not computed for this impact")
    return lines


def _pulse_axes(ax, pulses: dict, t0: float, extra_end_s: float = 0.0) -> np.ndarray:
    """Time axis (s) on which every pulse in ``pulses`` shows whole, with the x limits set:
    a fit may start before the contact and last ten times longer."""
    starts = [t0] + [p.start_s for p in pulses.values() if np.isfinite(p.start_s)]
    ends = [t0 + extra_end_s] + [p.end_s for p in pulses.values() if np.isfinite(p.end_s)]
    lo, hi = min(starts), max(ends)
    pad = 0.05 * (hi - lo)
    ax.set_xlim((lo - pad - t0) * 1e3, (hi + pad - t0) * 1e3)
    ax.set_xlabel("time from impact (ms)")
    ax.set_ylabel("impact force (N)")
    ax.grid(alpha=0.3)
    return np.linspace(lo - pad, hi + pad, 3000)


def _draw_pulse(ax, tt: np.ndarray, t0: float, method: str, pulse) -> None:
    fitted, contact = method in _FITS, "contact" in method
    ax.plot((tt - t0) * 1e3, pulse.force(tt), color=_METHOD_COLOURS.get(method), lw=2.6 if contact else 1.6,
            ls="--" if fitted else "-", alpha=0.75 if contact else 1.0, zorder=3 if fitted else 2,
            label=_FIT_LABEL.format(method) if fitted else method)


def _pulse_panels(ax, ax_fit, rec, comp, event: int) -> None:
    """Left: the simulated contact pulse against the pulses ASCE 7-22 predicts from the impact
    velocity, over the band of the study's MDOF pulses. Right: the study's SDOF and MDOF pulses,
    fitted to the base shear this contact pulse caused, beside that pulse: a fit close to it
    shows the inverse procedure works, not that the contact model is right."""
    pulses = rec["pulses"]
    contact = pulses["contact model (simulated)"]
    t0 = contact.start_s
    predicted = {m: p for m, p in pulses.items() if m not in _FITS}
    fitted = {m: p for m, p in pulses.items() if m in _FITS}
    d_mean, d_std = SEED_TABLE2_MDOF["duration_s"]
    tt = _pulse_axes(ax, predicted, t0, extra_end_s=d_mean + d_std)
    low, high = _seed_pulse_band(tt - t0)
    ax.fill_between((tt - t0) * 1e3, low, high, color="0.85", lw=0,
                    label="study's MDOF pulses (Table 2: mean +- std)")
    for method, pulse in predicted.items():
        _draw_pulse(ax, tt, t0, method, pulse)
    ax.set_title(f"event {event}, t = {t0:.4f} s: simulated and ASCE 7-22 pulses", fontsize=10, loc="left")
    _note(ax, [m for m in _missing_pulses(rec, comp, event) if "ASCE" in m], width=45)
    tt = _pulse_axes(ax_fit, {"contact model (simulated)": contact, **fitted}, t0)
    _draw_pulse(ax_fit, tt, t0, "contact model (simulated)", contact)
    for method, pulse in fitted.items():
        _draw_pulse(ax_fit, tt, t0, method, pulse)
    ax_fit.set_title(f"event {event}: the study's fits to this run's base shear", fontsize=10, loc="left")
    # the fitted pulses peak mid-panel; the note goes where the long SDOF pulse is still low
    _note(ax_fit, [m for m in _missing_pulses(rec, comp, event) if "fit" in m], width=40, left=True)


def _formula_panel(ax, comp, events: list[int]) -> None:
    rows = comp.impact_formulas[comp.impact_formulas["event"].isin(events)] \
        if not comp.impact_formulas.empty else comp.impact_formulas
    if rows.empty:
        _empty(ax, "no impact formulas to evaluate (the body's mass or impact velocity is unknown)")
        return
    methods = list(dict.fromkeys(rows["method"]))
    y = np.arange(len(methods))
    shown = [e for e in events if (rows["event"] == e).any()]
    top = float(rows["peak_force_N"].max())
    for k, event in enumerate(shown):
        r = rows[rows["event"] == event].set_index("method")
        values = np.array([float(r.loc[m, "peak_force_N"]) if m in r.index else np.nan for m in methods])
        u = float(r["impact_velocity_m_s"].iloc[0])
        if len(shown) == 1:
            colours = ["#d7191c" if "contact" in m else "#7f7f7f" for m in methods]
            ax.barh(y, values, height=0.7, color=colours)
            for yy, v in zip(y, values):
                if np.isfinite(v):
                    ax.text(v + 0.01 * top, yy, f"{v:.0f} N", va="center", fontsize=_SMALL)
            ax.set_title(f"peak impact force of each formula at the simulated impact velocity u = {u:.2f} m/s "
                         f"(event {event})", fontsize=10, loc="left")
        else:
            ax.plot(values, y - 0.3 + 0.6 * (k + 0.5) / len(shown), ls="none", marker="os^D"[k % 4], ms=7,
                    color=_EVENT_COLOURS[k % len(_EVENT_COLOURS)], label=f"event {event}, u = {u:.2f} m/s")
    if len(shown) > 1:
        ax.set_title("peak impact force of each formula at each impact's simulated velocity", fontsize=10,
                     loc="left")
        _legend(ax, loc="lower right")
    ax.set_yticks(y, methods, fontsize=_SMALL)
    ax.invert_yaxis()
    ax.set_xlim(0, 1.12 * top)
    ax.set_xlabel("peak impact force (N)")
    ax.grid(alpha=0.3, axis="x")


def figure_impacts(results, comp):
    """Per column impact (up to four, a row each) the simulated pulse against the predicted ones
    and, apart, the fitted ones; one shared legend; below, the peak force of every formula."""
    plt = _pyplot()
    events = _events(comp)
    if not events:
        fig, ax = plt.subplots(figsize=(_WIDTH_IN, 4.0), layout="constrained")
        why = "no debris in this scene" if results.data.scene is not None and not results.data.scene.debris \
            else "no impact on the column in this run"
        _empty(ax, f"{why}:\nno impact pulses to compare, no impact formulas to evaluate")
        return fig
    row_in = 2.9 if len(events) <= 2 else 2.1
    n_methods = max(len(set(comp.impact_formulas["method"])) if not comp.impact_formulas.empty else 1, 1)
    bars_in = (0.35 if len(events) <= 2 else 0.26) * n_methods + 0.9
    fig = plt.figure(figsize=(_WIDTH_IN, row_in * len(events) + 1.2 + bars_in), layout="constrained")
    grid = fig.add_gridspec(len(events) + 2, 2, height_ratios=[row_in] * len(events) + [0.65, bars_in])
    panels = []
    for j, event in enumerate(events):
        ax, ax_fit = fig.add_subplot(grid[j, 0]), fig.add_subplot(grid[j, 1])
        _pulse_panels(ax, ax_fit, comp.fit_records[event], comp, event)
        panels += [ax, ax_fit]
    _legend_axes(fig.add_subplot(grid[len(events), :]), panels)
    _formula_panel(fig.add_subplot(grid[len(events) + 1, :]), comp, events)
    fig.suptitle("Impact pulses on the column (cf. the study's Fig. 4b). Left: the contact model's pulse and the "
                 "ASCE 7-22 pulses from the\nimpact velocity. Right: the study's SDOF and MDOF pulses, fitted to "
                 "the base shear that the contact pulse caused.", fontsize=10)
    return fig


def plot_impacts(results, comp, path: Path) -> Path:
    return _save(figure_impacts(results, comp), path)


def figure_seed_fits(results, comp):
    """Per impact (up to four, a row each): the fits to the simulated base shear, and every
    pulse's response on the MDOF column, over one shared legend."""
    from analytical.mdof import mdof_response

    plt = _pyplot()
    events = _events(comp)
    if not events:
        fig, ax = plt.subplots(figsize=(_WIDTH_IN, 4.0), layout="constrained")
        _empty(ax, "no impact on the column in this run:\nno response to fit (the study's section 3.3), "
                   "no pulses to apply to the MDOF column")
        return fig
    row_in = 3.0 if len(events) <= 2 else 2.5
    fig = plt.figure(figsize=(_WIDTH_IN, row_in * len(events) + 1.8), layout="constrained")
    grid = fig.add_gridspec(len(events) + 1, 2, height_ratios=[row_in] * len(events) + [0.8])
    column = results.data.column
    panels = []
    for j, event in enumerate(events):
        rec = comp.fit_records[event]
        t, r = rec["time_s"], rec["record_N"]
        t0 = rec["pulses"]["contact model (simulated)"].start_s
        ax = fig.add_subplot(grid[j, 0])
        ax.plot((t - t0) * 1e3, r, color="0.4", lw=2.0, label="simulated base shear (impact part)")
        for key, name in (("sdof", "SDOF fit"), ("mdof", "MDOF fit")):
            if rec.get(f"{key}_N") is not None:
                ax.plot((rec[f"{key}_time_s"] - t0) * 1e3, rec[f"{key}_N"], color=_METHOD_COLOURS[name], lw=1.3,
                        ls="--", label=f"{name}'s response (fitted to the simulated base shear)")
        _note(ax, [m for m in _missing_pulses(rec, comp, event) if "fit" in m], width=45)
        ax.set_ylabel("base shear (N)")
        ax.set_title(f"event {event}: fits to the simulated response", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
        panels.append(ax)
        ax = fig.add_subplot(grid[j, 1], sharex=panels[-1])
        tf = np.arange(t[0], t[-1], 2e-5)
        ax.plot((t - t0) * 1e3, r, color="0.4", lw=2.0, label="simulated base shear (impact part)")
        for method, pulse in rec["pulses"].items():
            if "contact" in method:
                continue
            resp = mdof_response(pulse, column, rec["height_m"], tf).response_N
            ax.plot((tf - t0) * 1e3, resp, lw=1.1, color=_METHOD_COLOURS.get(method),
                    ls="--" if method in _FITS else "-", label=f"{method} pulse on the MDOF column")
        ax.set_ylabel("MDOF base shear (N)")
        ax.set_title(f"event {event}: every pulse on the MDOF column, z = {rec['height_m']:.3f} m", fontsize=10,
                     loc="left")
        ax.grid(alpha=0.3)
        panels.append(ax)
    for ax in panels[-2:]:
        ax.set_xlabel("time from impact (ms)")
    _legend_axes(fig.add_subplot(grid[len(events), :]), panels, ncol=2)
    fig.suptitle("Left: the study's SDOF and MDOF fits to the simulated base shear (cf. the study's Fig. 4a). "
                 "Right: the response of the\nMDOF column to every pulse (cf. the study's Fig. 5), fitted ones dashed.",
                 fontsize=10)
    return fig


def plot_seed_fits(results, comp, path: Path) -> Path:
    return _save(figure_seed_fits(results, comp), path)


# --------------------------------------------------------------------------- tracks


def _clipped(poly: np.ndarray, box: tuple[float, float, float, float] | None):
    """The polygon as a matplotlib path, cut at the flume walls (x0, x1, y0, y1) if given."""
    from matplotlib.path import Path as MplPath
    from matplotlib.transforms import Bbox

    path = MplPath(np.vstack([poly, poly[:1]]), closed=True)
    if box is None:
        return path
    x0, x1, y0, y1 = box
    return path.clip_to_bbox(Bbox([[x0, y0], [x1, y1]]), inside=True)


def figure_tracks(results, comp):
    """Plan view of the tracks over the speeds; the plan's height follows the framed region's
    aspect (equal scales), so the figure has no empty band above or below it."""
    plt = _pyplot()
    from matplotlib.patches import PathPatch, Rectangle

    from orchestrator.results.compare import SPREADING_ANGLES_DEG

    data = results.data
    scene = data.scene
    bodies = results.bodies
    x_lo, x_hi, y_lo, y_hi = None, None, None, None
    if data.plan and data.plan.get("domain_m"):
        (x_lo, x_hi), (y_lo, y_hi) = data.plan["domain_m"][0], data.plan["domain_m"][1]
    elif scene is not None:
        from orchestrator.scene.geometry import flume_extent

        (x_lo, x_hi), (y_lo, y_hi), _ = flume_extent(scene)
    # frame: the debris path, the column, the gauges and the start of the spreading areas
    xs = [] if bodies.empty else [float(bodies["x_m"].min()), float(bodies["x_m"].max())]
    if scene is not None and scene.column is not None:
        xs += [scene.column.x_m - scene.column.size_x_m, scene.column.x_m + scene.column.size_x_m]
    xs += [r.x_m for r in results.gauge_summary.itertuples() if np.isfinite(r.x_m)]
    xs += [float(poly[0, 0]) for poly in comp.areas.values()]
    xlim = ylim = None
    if xs:
        pad = 0.1 * (max(xs) - min(xs) + 0.5)
        xlim = (min(xs) - pad, max(xs) + pad)
    if y_lo is not None:
        ylim = (y_lo - 0.05 * (y_hi - y_lo), y_hi + 0.05 * (y_hi - y_lo))
    elif not bodies.empty:
        ylim = (float(bodies["y_m"].min()) - 0.5, float(bodies["y_m"].max()) + 0.5)
    plan_in = 3.0
    if xlim and ylim:  # the plan axes are about 6.8 in wide beside their legend
        plan_in = float(np.clip(6.8 * (ylim[1] - ylim[0]) / (xlim[1] - xlim[0]), 1.6, 6.5))
    speeds_in = 1.0 if bodies.empty else 2.3  # without tracks the lower panel only says why
    fig = plt.figure(figsize=(_WIDTH_IN, plan_in + speeds_in + 1.1), layout="constrained")
    ax, axv = fig.subplots(2, 1, height_ratios=[plan_in + 0.7, speeds_in])
    box = None
    if x_lo is not None:
        ax.add_patch(Rectangle((x_lo, y_lo), x_hi - x_lo, y_hi - y_lo, fill=False, lw=1.2, color="0.3",
                               label="walls of the simulated domain"))
        box = (x_lo, x_hi, y_lo, y_hi)
    colours = ["#2b83ba", "#fdae61"]
    for (name, poly), colour in zip(comp.areas.items(), colours):
        spec = SPREADING_ANGLES_DEG[name]
        flag = "" if spec["verified"] else " (unverified)"
        ax.add_patch(PathPatch(_clipped(poly, box), alpha=0.22, color=colour, lw=0,
                               label=f"{name}, {spec['half_angle_deg']:g} deg{flag}"))
    if comp.areas:
        poly = next(iter(comp.areas.values()))
        if abs(poly[3, 1] - poly[0, 1]) > 1e-9:  # one body: the source line is a point
            ax.plot(poly[[0, 3], 0], poly[[0, 3], 1], color="0.2", lw=2.0, label="source line of the areas")
    if scene is not None and scene.column is not None:
        c = scene.column
        ax.add_patch(Rectangle((c.x_m - c.size_x_m / 2, c.y_m - c.size_y_m / 2), c.size_x_m, c.size_y_m,
                               color="#5f6b73", label="column", zorder=2))
    for r in results.gauge_summary.itertuples():
        if np.isfinite(r.x_m):
            ax.plot(r.x_m, r.y_m, marker="o", ms=6, color="#1a9641", ls="none", label="gauge", zorder=4)
            # upstream of and above the gauge: a gauge sits just upstream of the column's face
            ax.annotate(r.gauge, (r.x_m, r.y_m), xytext=(-5, 5), textcoords="offset points", ha="right",
                        va="bottom", fontsize=_SMALL, color="#1a9641", zorder=6,
                        bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none",
                              "alpha": 0.8})
    if bodies.empty:
        why = "no debris in this scene" if scene is not None and not scene.debris else "no body tracks in this run"
        _empty(axv, f"{why}: no tracks, no speeds")
    else:
        starts = []
        for body, track in bodies.groupby("body"):
            line, = ax.plot(track["x_m"], track["y_m"], lw=1.6, label=body, zorder=3)
            starts.append((track["x_m"].iloc[0], track["y_m"].iloc[0], line.get_color()))
            axv.plot(track["time_s"], track["speed_m_s"], lw=1.2, color=line.get_color(), label=body)
        ax.scatter([s[0] for s in starts], [s[1] for s in starts], marker="s", s=30, c=[s[2] for s in starts],
                   edgecolors="k", linewidths=0.6, zorder=4, label="start of a track")
        imp = results.impacts
        if len(imp):
            ax.plot(imp["point_x_m"], imp["point_y_m"], marker="*", ms=12, ls="none", color="#d7191c",
                    label="impacts", zorder=5)
            for t in imp["time_s"]:
                axv.axvline(t, color="#d7191c", lw=0.8, alpha=0.7, label="impact")
        axv.set_xlabel("time (s)")
        axv.set_ylabel("speed (m/s)")
        axv.set_title("speed of each body (centre of mass)", fontsize=10, loc="left")
        axv.grid(alpha=0.3)
        _legend(axv, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    if xlim:
        ax.set_xlim(*xlim)
    if ylim:
        ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x along the flume (m)")
    ax.set_ylabel("y across (m)")
    ax.set_title("Debris tracks (centre of mass) in plan view, and the spreading areas (ASCE 7-22 6.11.5.1)\n"
                 "from the debris's start line (cf. the study's Fig. 14)", fontsize=10, loc="left")
    _legend(ax, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(alpha=0.3)
    return fig


def plot_tracks(results, comp, path: Path) -> Path:
    return _save(figure_tracks(results, comp), path)


# --------------------------------------------------------------------------- snapshot



def _snapshot_time(results) -> tuple[float | None, str]:
    imp = results.impacts
    if len(imp):
        first = imp.sort_values("time_s").iloc[0]
        return float(first["time_s"]), f"first impact ({first['body']} on {first['other']})"
    cf = results.column_forces
    if "hydro_force_x_N" in cf and cf["hydro_force_x_N"].notna().any():
        i = int(cf["hydro_force_x_N"].abs().idxmax())
        return float(cf.loc[i, "time_s"]), "peak hydrodynamic force on the column (no impact in this run)"
    return None, "latest written time"


def _placeholder(path: Path, message: str) -> Path:
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 5.5))
    _empty(ax, message)
    return _save(fig, path)


def snapshot(results, path: Path) -> tuple[Path, str | None]:
    """3D view at the first impact (else the peak hydrodynamic force, else the latest time).

    Returns (png, note): the note says why a placeholder was drawn instead, or which
    written time stands in for the wanted one.
    """
    case = results.data.case
    wanted, what = _snapshot_time(results)
    try:
        import pyvista as pv
    except ImportError as exc:  # a declared dependency
        note = f"snapshot: pyvista is not installed ({exc})"
        return _placeholder(path, note), note
    if not (case / "system" / "controlDict").is_file():
        note = "snapshot: the case has no system/controlDict, so its fields cannot be read"
        return _placeholder(path, note), note
    decomposed = any(p.is_dir() for p in case.glob("processor*"))
    from orchestrator.report.preview import _quiet_vtk

    with _quiet_vtk():
        try:
            reader = pv.POpenFOAMReader(str(case / "system" / "controlDict"))
            times: list[float] = []
            for kind in (("decomposed", "reconstructed") if decomposed else ("reconstructed",)):
                reader.case_type = kind
                reader.reader.UpdateInformation()
                times = [t for t in reader.time_values if t > 0] or list(reader.time_values)
                if times and (wanted is None or min(abs(t - wanted) for t in times) < 1e-6 or kind == "reconstructed"):
                    break
        except Exception as exc:  # VTK raises plain errors for unreadable cases
            note = f"snapshot: the case's fields could not be read ({exc})"
            return _placeholder(path, note), note
        if not times:
            note = "snapshot: no written time directory with fields in the case"
            return _placeholder(path, note), note
        t = min(times, key=lambda v: abs(v - wanted)) if wanted is not None else max(times)
        note = None
        if wanted is not None and abs(t - wanted) > 1e-6:
            note = f"snapshot: no fields written at t = {wanted:.6g} s ({what}); drawn at the nearest written time"
        reader.set_active_time_value(t)
        reader.cell_to_point_creation = True
        reader.enable_all_patch_arrays()
        mesh = reader.read()
        internal = mesh["internalMesh"]
        if "cellTypes" in internal.cell_data:  # overset: leave out the hole cells (type 2)
            internal = internal.threshold(value=(-0.5, 1.5), scalars="cellTypes", preference="cell")
        surface = internal.contour([0.5], scalars="alpha.water") if "alpha.water" in internal.point_data else None
        boundary = mesh["boundary"] if "boundary" in mesh.keys() else None
        plotter = pv.Plotter(off_screen=True, window_size=(1400, 900))
        plotter.set_background("white")
        if surface is not None and surface.n_points:
            plotter.add_mesh(surface, color="#1f6fd1", opacity=0.75, smooth_shading=True)
        patches = set(boundary.keys()) if boundary is not None else set()
        if "bed" in patches:
            plotter.add_mesh(boundary["bed"], color="#e6e2da", opacity=0.6)
        if "column" in patches:
            plotter.add_mesh(boundary["column"], color="#5f6b73")
        for name in results.data.body_names:
            if name in patches:
                plotter.add_mesh(boundary[name], color="#d7191c")
        for r in results.gauge_summary.itertuples():
            if np.isfinite(r.x_m):
                top = internal.bounds[5]
                plotter.add_mesh(pv.Line((r.x_m, r.y_m, 0.0), (r.x_m, r.y_m, top)), color="#1a9641", line_width=3)
        focus = _focus(results, internal.bounds)
        scene = results.data.scene
        size = 2.5 * scene.column.height_m if scene is not None and scene.column is not None else \
            0.5 * (internal.bounds[3] - internal.bounds[2])
        plotter.camera.focal_point = focus
        plotter.camera.position = (focus[0] - 0.9 * size, focus[1] - 1.3 * size, focus[2] + 0.8 * size)
        plotter.camera.up = (0.0, 0.0, 1.0)
        plotter.add_text(f"t = {t:.4g} s: {what}", font_size=11, color="black")
        tmp = path.with_name(f".{path.stem}.{os.getpid()}.tmp.png")
        plotter.screenshot(str(tmp))
        plotter.close()
    os.replace(tmp, path)
    return path, note


def _focus(results, bounds) -> tuple[float, float, float]:
    scene = results.data.scene
    if results.impacts is not None and len(results.impacts):
        first = results.impacts.sort_values("time_s").iloc[0]
        return float(first["point_x_m"]), float(first["point_y_m"]), float(first["point_z_m"])
    if scene is not None and scene.column is not None:
        return float(scene.column.x_m), float(scene.column.y_m), 0.1 * float(scene.column.height_m)
    return (0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), bounds[4])


# --------------------------------------------------------------------------- entry point


def make_plots(results, comp, out_dir: str | Path, snapshot_3d: bool = True) -> tuple[dict[str, Path], list[str]]:
    """Every PNG of :data:`PLOTS` in out_dir; returns ({name: path}, notes)."""
    out = Path(out_dir)
    notes: list[str] = []
    written = {
        "gauges": plot_gauges(results, comp, out / PLOTS["gauges"]),
        "column_forces": plot_column_forces(results, out / PLOTS["column_forces"]),
        "impacts": plot_impacts(results, comp, out / PLOTS["impacts"]),
        "seed_fits": plot_seed_fits(results, comp, out / PLOTS["seed_fits"]),
        "tracks": plot_tracks(results, comp, out / PLOTS["tracks"]),
    }
    if snapshot_3d:
        written["snapshot"], note = snapshot(results, out / PLOTS["snapshot"])
        if note:
            notes.append(note)
    return written, notes
