"""The impact figures of a run: the column impacts' pulses against the predicted and fitted
ones, and the study's fits to the simulated base shear.

``impacts.png``   per column impact (up to four, a row each): the contact model's pulse
                  against the ASCE 7-22 (k_d, k_s) pulses from the impact velocity, over the
                  band of the study's MDOF pulses (Table 2: magnitude and duration within one
                  standard deviation of the mean), and beside it the SDOF/MDOF pulses fitted to
                  the base shear that contact pulse caused (study Fig. 4b), dashed and apart, so
                  that a fit matching the pulse reads as a check of the fit; a missing pulse
                  says why; below, the peak force of every method at the simulated impact
                  velocity;
``study_fits.png`` the simulated base shear of each impact with the SDOF and MDOF fits (study
                  Fig. 4a) and every pulse's response on the MDOF column (Fig. 5).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from analytical.study import STUDY_TABLE2_MDOF
from analytical.mdof import mdof_response
from orchestrator.report.figures import SMALL, WIDTH_IN, empty, legend, legend_axes, note, pyplot, save_figure

__all__ = ["figure_impacts", "figure_study_fits", "plot_impacts", "plot_study_fits"]

#: The colour of each method's pulse, on both impact figures.
_METHOD_COLOURS = {
    "contact model (simulated)": "#d7191c",
    "ASCE 7-22, k_d": "#2c7bb6",
    "ASCE 7-22, k_s": "#74add1",
    "SDOF fit": "#e66101",
    "MDOF fit": "#1a9641",
}
#: The study's fitted pulses: fitted to the base shear a run's contact pulse caused, so drawn
#: dashed and labelled as fits, apart from the pulses predicted from the impact velocity.
_FITS = ("SDOF fit", "MDOF fit")
_FIT_LABEL = "{} (fitted to this run's base shear)"
#: One colour per impact event where several share the formula panel.
_EVENT_COLOURS = ("#d7191c", "#2c7bb6", "#1a9641", "#7b3294")


def _events(comp, limit: int = 4) -> list[int]:
    """The column impacts drawn (the first ``limit`` with fit records)."""
    return sorted(comp.fit_records)[:limit]


def _study_pulse_band(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The band of half-sines with the study's MDOF magnitudes and durations, each within one
    standard deviation of its Table 2 mean: the lowest and highest such pulse at each time."""
    (f_mean, f_std), (d_mean, d_std) = STUDY_TABLE2_MDOF["peak_force_N"], STUDY_TABLE2_MDOF["duration_s"]
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
    """Time axis (s) on which every pulse in ``pulses`` shows whole, with the x limits set.
    A fitted SDOF pulse starts no earlier than where the base shear leaves zero, after the
    contact (`analytical.fitting.fit_sdof`); a fitted pulse may last longer than the contact."""
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
    d_mean, d_std = STUDY_TABLE2_MDOF["duration_s"]
    tt = _pulse_axes(ax, predicted, t0, extra_end_s=d_mean + d_std)
    low, high = _study_pulse_band(tt - t0)
    ax.fill_between((tt - t0) * 1e3, low, high, color="0.85", lw=0,
                    label="study's MDOF pulses (Table 2: mean +- std)")
    for method, pulse in predicted.items():
        _draw_pulse(ax, tt, t0, method, pulse)
    ax.set_title(f"event {event}, t = {t0:.4f} s: simulated and ASCE 7-22 pulses", fontsize=10, loc="left")
    note(ax, [m for m in _missing_pulses(rec, comp, event) if "ASCE" in m], width=45)
    tt = _pulse_axes(ax_fit, {"contact model (simulated)": contact, **fitted}, t0)
    _draw_pulse(ax_fit, tt, t0, "contact model (simulated)", contact)
    for method, pulse in fitted.items():
        _draw_pulse(ax_fit, tt, t0, method, pulse)
    ax_fit.set_title(f"event {event}: the study's fits to this run's base shear", fontsize=10, loc="left")
    # the fitted pulses peak mid-panel; the note goes where the long SDOF pulse is still low
    note(ax_fit, [m for m in _missing_pulses(rec, comp, event) if "fit" in m], width=40, left=True)


def _formula_panel(ax, comp, events: list[int]) -> None:
    rows = comp.impact_formulas[comp.impact_formulas["event"].isin(events)] \
        if not comp.impact_formulas.empty else comp.impact_formulas
    if rows.empty:
        empty(ax, "no impact formulas to evaluate (the body's mass or impact velocity is unknown)")
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
                    ax.text(v + 0.01 * top, yy, f"{v:.0f} N", va="center", fontsize=SMALL)
            ax.set_title(f"peak impact force of each formula at the simulated impact velocity u = {u:.2f} m/s "
                         f"(event {event})", fontsize=10, loc="left")
        else:
            ax.plot(values, y - 0.3 + 0.6 * (k + 0.5) / len(shown), ls="none", marker="os^D"[k % 4], ms=7,
                    color=_EVENT_COLOURS[k % len(_EVENT_COLOURS)], label=f"event {event}, u = {u:.2f} m/s")
    if len(shown) > 1:
        ax.set_title("peak impact force of each formula at each impact's simulated velocity", fontsize=10,
                     loc="left")
        legend(ax, loc="lower right")
    ax.set_yticks(y, methods, fontsize=SMALL)
    ax.invert_yaxis()
    ax.set_xlim(0, 1.12 * top)
    ax.set_xlabel("peak impact force (N)")
    ax.grid(alpha=0.3, axis="x")


def figure_impacts(results, comp):
    """Per column impact (up to four, a row each) the simulated pulse against the predicted ones
    and, apart, the fitted ones; one shared legend; below, the peak force of every formula."""
    plt = pyplot()
    events = _events(comp)
    if not events:
        fig, ax = plt.subplots(figsize=(WIDTH_IN, 4.0), layout="constrained")
        why = "no debris in this scene" if results.data.scene is not None and not results.data.scene.debris \
            else "no impact on the column in this run"
        empty(ax, f"{why}:\nno impact pulses to compare, no impact formulas to evaluate")
        return fig
    row_in = 2.9 if len(events) <= 2 else 2.1
    n_methods = max(len(set(comp.impact_formulas["method"])) if not comp.impact_formulas.empty else 1, 1)
    bars_in = (0.35 if len(events) <= 2 else 0.26) * n_methods + 0.9
    fig = plt.figure(figsize=(WIDTH_IN, row_in * len(events) + 1.2 + bars_in), layout="constrained")
    grid = fig.add_gridspec(len(events) + 2, 2, height_ratios=[row_in] * len(events) + [0.65, bars_in])
    panels = []
    for j, event in enumerate(events):
        ax, ax_fit = fig.add_subplot(grid[j, 0]), fig.add_subplot(grid[j, 1])
        _pulse_panels(ax, ax_fit, comp.fit_records[event], comp, event)
        panels += [ax, ax_fit]
    legend_axes(fig.add_subplot(grid[len(events), :]), panels)
    _formula_panel(fig.add_subplot(grid[len(events) + 1, :]), comp, events)
    fig.suptitle("Impact pulses on the column (cf. the study's Fig. 4b). Left: the contact model's pulse and the "
                 "ASCE 7-22 pulses from the\nimpact velocity. Right: the study's SDOF and MDOF pulses, fitted to "
                 "the base shear that the contact pulse caused.", fontsize=10)
    return fig


def plot_impacts(results, comp, path: Path) -> Path:
    return save_figure(figure_impacts(results, comp), path)


def figure_study_fits(results, comp):
    """Per impact (up to four, a row each): the fits to the simulated base shear, and every
    pulse's response on the MDOF column, over one shared legend."""
    plt = pyplot()
    events = _events(comp)
    if not events:
        fig, ax = plt.subplots(figsize=(WIDTH_IN, 4.0), layout="constrained")
        empty(ax, "no impact on the column in this run:\nno response to fit (the study's section 3.3), "
                   "no pulses to apply to the MDOF column")
        return fig
    row_in = 3.0 if len(events) <= 2 else 2.5
    fig = plt.figure(figsize=(WIDTH_IN, row_in * len(events) + 1.8), layout="constrained")
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
        note(ax, [m for m in _missing_pulses(rec, comp, event) if "fit" in m], width=45)
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
    legend_axes(fig.add_subplot(grid[len(events), :]), panels, ncol=2)
    fig.suptitle("Left: the study's SDOF and MDOF fits to the simulated base shear (cf. the study's Fig. 4a). "
                 "Right: the response of the\nMDOF column to every pulse (cf. the study's Fig. 5), fitted ones dashed.",
                 fontsize=10)
    return fig


def plot_study_fits(results, comp, path: Path) -> Path:
    return save_figure(figure_study_fits(results, comp), path)
