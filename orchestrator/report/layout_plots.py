"""The figures of the layouts page (:mod:`orchestrator.report.layouts`), in the manner of the
study's Figs. 12-16:

``flow.png``
    the gauges WG1-WG4 and the column's hydrodynamic force along the flow, every layout overlaid
    (the study's Figs. 12-13);
``<layout>-tracks.png``
    the layout's tracks in plan view with the column, the gauges, the spreading areas of
    ASCE 7-22 6.11.5.1 from the debris's start line, the strikes and the body-body contacts, and
    the bodies' speeds below (the study's Fig. 14);
``<layout>-impacts.png``
    the force of every strike on the column and the base shear it causes at the load cell, against
    the time from contact (the study's Fig. 15);
``impact_summary.png``
    every strike's velocity along the contact normal and the body's yaw at the strike, per layout
    (the study's Fig. 16).

The layouts are read by :func:`orchestrator.report.layouts.load_layout`; a layout without
results is left out.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.patches import Rectangle

from orchestrator.report.figures import SMALL, WIDTH_IN, empty, legend, pyplot, save_figure
from orchestrator.report.track_plots import draw_column, draw_spreading_areas, label_speed_axes, mark_strikes, \
    set_plan_view

__all__ = ["draw_all", "figure_flow", "figure_impact_summary", "figure_layout_impacts", "figure_layout_tracks"]

#: Line styles that keep coinciding records visible: each layout drawn with its own dashes.
STYLES = [{"ls": "-", "lw": 2.4, "alpha": 0.55}, {"ls": (0, (6, 3)), "lw": 1.5}, {"ls": (0, (2, 2)), "lw": 1.5},
          {"ls": (0, (8, 2, 2, 2)), "lw": 1.2}]
GAUGES = ("WG1", "WG2", "WG3", "WG4")


def _style(i: int) -> dict:
    return STYLES[i % len(STYLES)]


def figure_flow(layouts):
    """WG1-WG4 and the column's hydrodynamic force of every layout, overlaid."""
    plt = pyplot()
    fig, axes = plt.subplots(5, 1, figsize=(WIDTH_IN, 11.5), sharex=True, layout="constrained")
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, lay in enumerate(layouts):
        style, colour = _style(i), colours[i % len(colours)]
        for ax, gauge in zip(axes[:4], GAUGES):
            col = f"{gauge}_elevation_m"
            if col in lay.gauges:
                ax.plot(lay.gauges["time_s"], lay.gauges[col], color=colour, label=lay.name, **style)
        if not lay.hydro.empty:
            axes[4].plot(lay.hydro["time_s"], lay.hydro["hydro_force_x_N"], color=colour, label=lay.name, **style)
    for ax, gauge in zip(axes[:4], GAUGES):
        ax.set_ylabel(f"{gauge} (m)")
        ax.set_title(f"water level at {gauge}", fontsize=10, loc="left")
        ax.grid(alpha=0.3)
    axes[4].set_ylabel("force (N)")
    axes[4].set_title("hydrodynamic force on the column along the flow (forces function object)", fontsize=10,
                      loc="left")
    axes[4].set_xlabel("time (s)")
    axes[4].grid(alpha=0.3)
    legend(axes[0], loc="upper right")
    return fig


def _frame(lay):
    """(xlim, ylim, walls box) of a layout's plan view: its tracks, the column, the gauges near
    them, the flume's walls across."""
    xs = [] if lay.bodies.empty else [float(lay.bodies["x_m"].min()), float(lay.bodies["x_m"].max())]
    scene = lay.scene
    if scene is not None and scene.column is not None:
        xs += [scene.column.x_m - scene.column.size_x_m, scene.column.x_m + scene.column.size_x_m]
    region = lay.record_region_m
    if xs and region:
        xs += list(region[0])
    domain = lay.domain_m
    box = None
    if domain:
        (x0, x1), (y0, y1) = domain[0], domain[1]
        box = (x0, x1, y0, y1)
    elif scene is not None:
        box = (-scene.reservoir.length_m, scene.flume.length_m - scene.reservoir.length_m,
               -scene.flume.width_m / 2, scene.flume.width_m / 2)
    if not xs:
        return None, None, box
    pad = 0.3
    xlim = (min(xs) - pad, max(xs) + pad)
    ylim = (box[2] - 0.05, box[3] + 0.05) if box else None
    return xlim, ylim, box


def figure_layout_tracks(lay):
    """The layout's tracks in plan view over the bodies' speeds."""
    plt = pyplot()
    xlim, ylim, box = _frame(lay)
    plan_in = 3.0
    if xlim and ylim:  # the plan spans the page's width, its legend below it
        plan_in = float(np.clip(8.2 * (ylim[1] - ylim[0]) / (xlim[1] - xlim[0]), 1.6, 6.5))
    fig = plt.figure(figsize=(WIDTH_IN, plan_in + 4.2), layout="constrained")
    ax, axv = fig.subplots(2, 1, height_ratios=[plan_in + 1.2, 2.3])
    if box is not None:
        ax.add_patch(Rectangle((box[0], box[2]), box[1] - box[0], box[3] - box[2], fill=False, lw=1.2, color="0.3",
                               label="walls of the simulated domain"))
    draw_spreading_areas(ax, lay.areas(), box)
    region = lay.record_region_m
    if region and box is not None:  # the transport closes the record's ends with walls
        for x in region[0]:
            ax.plot([x, x], [box[2], box[3]], color="#7b3294", lw=1.2, ls="--", label="ends of the flow record")
    if lay.scene is not None and lay.scene.column is not None:
        draw_column(ax, lay.scene.column)
    for r in lay.gauge_summary.itertuples():
        if xlim and xlim[0] <= r.x_m <= xlim[1]:
            ax.plot(r.x_m, r.y_m, marker="o", ms=6, color="#1a9641", ls="none", label="gauge", zorder=4)
            ax.annotate(r.gauge, (r.x_m, r.y_m), xytext=(-5, 5), textcoords="offset points", ha="right",
                        fontsize=SMALL, color="#1a9641")
    if lay.bodies.empty:
        empty(axv, "no body tracks in this run")
    else:
        for body, track in lay.bodies.groupby("body", sort=False):
            line, = ax.plot(track["x_m"], track["y_m"], lw=1.4, label=body, zorder=3)
            ax.plot(track["x_m"].iloc[0], track["y_m"].iloc[0], marker="s", ms=6, mec="k", mew=0.6,
                    color=line.get_color(), ls="none", label="start of a track", zorder=4)
            axv.plot(track["time_s"], track["speed_m_s"], lw=1.1, color=line.get_color(), label=body)
        mark_strikes(ax, axv, lay.strikes, "strike on the column", "strike on the column", alpha=0.6)
        bc = lay.body_contacts
        if len(bc):
            ax.plot(bc["point_x_m"], bc["point_y_m"], marker="x", ms=7, ls="none", color="k",
                    label="contact between two bodies", zorder=5)
        label_speed_axes(axv)
    # the limits are fixed (the tracks' reach, the walls), so the axes box takes the equal aspect
    set_plan_view(ax, xlim, ylim, "box" if (xlim and ylim) else "datalim")
    ax.set_title(f"{lay.name}: tracks (centre of mass) in plan view and the spreading areas (ASCE 7-22 6.11.5.1) "
                 "from the debris's start line", fontsize=10, loc="left")
    legend(ax, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=4)
    ax.grid(alpha=0.3)
    return fig


def figure_layout_impacts(lay):
    """Force on the column and base shear of every strike, against the time from contact."""
    plt = pyplot()
    fig, (axf, axs) = plt.subplots(2, 1, figsize=(WIDTH_IN, 6.5), layout="constrained")
    strikes = lay.strikes
    if not len(strikes) or not lay.pulses:
        empty(axf, f"{lay.name}: no strike on the column in the simulated time")
        axs.axis("off")
        return fig
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    body_colour = {b: colours[i % len(colours)] for i, b in enumerate(lay.body_names)}
    for r in strikes.itertuples():
        pulse = lay.pulses.get(int(r.event))
        if pulse is None:
            continue
        (t, force), shear = pulse
        label = f"{r.body} #{r.strike} at {r.time_s:.3f} s, {r.impact_velocity_m_s:.2f} m/s"
        style = {"color": body_colour.get(r.body), "lw": 1.3, "ls": ["-", "--", ":", "-."][(r.strike - 1) % 4]}
        axf.plot(1e3 * t, force, label=label, **style)
        if shear is not None:
            axs.plot(1e3 * shear[0], shear[1], label=label, **style)
    axf.set_ylabel("force on the column (N)")
    axf.set_title(f"{lay.name}: contact force of each strike (contact law in series with the column's MDOF model)",
                  fontsize=10, loc="left")
    axs.set_ylabel("base shear (N)")
    axs.set_title("base shear at the load cell caused by each strike (magnitude)", fontsize=10, loc="left")
    axf.set_xlabel("time from contact (ms)")
    axs.set_xlabel("time from contact (ms)")
    for ax in (axf, axs):
        ax.grid(alpha=0.3)
    legend(axf, loc="upper right")
    return fig


def figure_impact_summary(layouts):
    """Every strike's velocity along the contact normal and the body's yaw, per layout."""
    plt = pyplot()
    fig, (axv, axy) = plt.subplots(1, 2, figsize=(WIDTH_IN, 4.2), layout="constrained")
    names = [lay.name for lay in layouts]
    any_strike = False
    for i, lay in enumerate(layouts):
        s = lay.strikes
        if not len(s):
            continue
        any_strike = True
        first = s["strike"].to_numpy() == 1
        jitter = np.linspace(-0.15, 0.15, len(s)) if len(s) > 1 else np.zeros(1)
        for mask, marker, label in ((first, "o", "first strike of a body"), (~first, "^", "later strike")):
            if mask.any():
                axv.plot(i + jitter[mask], s["impact_velocity_m_s"].to_numpy()[mask], marker=marker, ls="none",
                         color="#2b83ba" if marker == "o" else "#d7191c", label=label)
                axy.plot(i + jitter[mask], s["yaw_deg"].to_numpy()[mask], marker=marker, ls="none",
                         color="#2b83ba" if marker == "o" else "#d7191c", label=label)
    if not any_strike:
        empty(axv, "no strike on the column in any layout")
        axy.axis("off")
        return fig
    for ax, label in ((axv, "velocity along the contact normal (m/s)"),
                      (axy, "yaw at the strike (deg; 0: long axis along the flow)")):
        ax.set_xticks(range(len(names)), names, rotation=15)
        ax.set_xlim(-0.5, len(names) - 0.5)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axv.set_title("impact velocities", fontsize=10, loc="left")
    axy.set_title("orientation at the strike", fontsize=10, loc="left")
    legend(axv, loc="best")
    return fig


def draw_all(layouts, out: Path) -> dict[str, Path]:
    """Every figure of the page into ``out``; name -> path (the finished layouts only)."""
    done = [lay for lay in layouts if lay.ok]
    written: dict[str, Path] = {}
    if not done:
        return written
    written["flow"] = save_figure(figure_flow(done), out / "flow.png")
    written["impact_summary"] = save_figure(figure_impact_summary(done), out / "impact_summary.png")
    for lay in done:
        written[f"{lay.slug}-tracks"] = save_figure(figure_layout_tracks(lay), out / f"{lay.slug}-tracks.png")
        written[f"{lay.slug}-impacts"] = save_figure(figure_layout_impacts(lay), out / f"{lay.slug}-impacts.png")
    return written
