"""The tracks figure of a run (``tracks.png``): debris tracks in plan view with the column,
the gauges and the spreading areas of Naito et al. (2014) and Nistor et al. (2017b) cut at the
flume walls (study Fig. 14), and below them the bodies' speeds; the plan's height follows the
framed region's aspect.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.patches import PathPatch, Rectangle
from matplotlib.path import Path as MplPath
from matplotlib.transforms import Bbox

from orchestrator.report.figures import SMALL, WIDTH_IN, empty, legend, pyplot, save_figure
from orchestrator.results.compare import SPREADING_ANGLES_DEG
from orchestrator.scene.geometry import flume_extent

__all__ = ["clipped_area", "draw_column", "draw_spreading_areas", "figure_tracks", "label_speed_axes", "mark_strikes",
           "plot_tracks", "set_plan_view"]


def label_speed_axes(axv) -> None:
    """The speed panel under a plan view: labels, title, grid and its legend at the right."""
    axv.set_xlabel("time (s)")
    axv.set_ylabel("speed (m/s)")
    axv.set_title("speed of each body (centre of mass)", fontsize=10, loc="left")
    axv.grid(alpha=0.3)
    legend(axv, loc="upper left", bbox_to_anchor=(1.01, 1.0))


def mark_strikes(ax, axv, strikes, label: str, time_label: str, alpha: float) -> None:
    """A red star at each column strike's point (``point_x_m``, ``point_y_m``) in the plan view
    ``ax``, and a line at its ``time_s`` on the speed panel ``axv`` (none without strikes)."""
    if len(strikes):
        ax.plot(strikes["point_x_m"], strikes["point_y_m"], marker="*", ms=12, ls="none", color="#d7191c",
                label=label, zorder=5)
        for t in strikes["time_s"]:
            axv.axvline(t, color="#d7191c", lw=0.8, alpha=alpha, label=time_label)


def set_plan_view(ax, xlim, ylim, adjustable: str = "datalim") -> None:
    """A plan view's limits (when given), equal aspect and axis labels."""
    if xlim:
        ax.set_xlim(*xlim)
    if ylim:
        ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable=adjustable)
    ax.set_xlabel("x along the flume (m)")
    ax.set_ylabel("y across (m)")


def clipped_area(poly: np.ndarray, box: tuple[float, float, float, float] | None):
    """The polygon as a matplotlib path, cut at the flume walls (x0, x1, y0, y1) if given."""
    path = MplPath(np.vstack([poly, poly[:1]]), closed=True)
    if box is None:
        return path
    x0, x1, y0, y1 = box
    return path.clip_to_bbox(Bbox([[x0, y0], [x1, y1]]), inside=True)


def draw_spreading_areas(ax, areas: dict[str, np.ndarray], box: tuple[float, float, float, float] | None) -> None:
    """The spreading areas (name -> polygon of :func:`orchestrator.results.compare.spreading_area`),
    cut at the walls ``box``, and their source line when it is a line (more than one body)."""
    colours = ["#2b83ba", "#fdae61"]
    for (name, poly), colour in zip(areas.items(), colours):
        spec = SPREADING_ANGLES_DEG[name]
        flag = "" if spec["verified"] else " (unverified)"
        ax.add_patch(PathPatch(clipped_area(poly, box), alpha=0.22, color=colour, lw=0,
                               label=f"{name}, {spec['half_angle_deg']:g} deg{flag}"))
    if areas:
        poly = next(iter(areas.values()))
        if abs(poly[3, 1] - poly[0, 1]) > 1e-9:  # one body: the source line is a point
            ax.plot(poly[[0, 3], 0], poly[[0, 3], 1], color="0.2", lw=2.0, label="source line of the areas")


def draw_column(ax, column) -> None:
    """The scene's column (``scene.column``) in plan view."""
    ax.add_patch(Rectangle((column.x_m - column.size_x_m / 2, column.y_m - column.size_y_m / 2), column.size_x_m,
                           column.size_y_m, color="#5f6b73", label="column", zorder=2))


def figure_tracks(results, comp):
    """Plan view of the tracks over the speeds; the plan's height follows the framed region's
    aspect (equal scales), so the figure has no empty band above or below it."""
    plt = pyplot()
    data = results.data
    scene = data.scene
    bodies = results.bodies
    x_lo, x_hi, y_lo, y_hi = None, None, None, None
    if data.plan:
        (x_lo, x_hi), (y_lo, y_hi) = data.plan.domain_m[0], data.plan.domain_m[1]
    elif scene is not None:
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
    fig = plt.figure(figsize=(WIDTH_IN, plan_in + speeds_in + 1.1), layout="constrained")
    ax, axv = fig.subplots(2, 1, height_ratios=[plan_in + 0.7, speeds_in])
    box = None
    if x_lo is not None:
        ax.add_patch(Rectangle((x_lo, y_lo), x_hi - x_lo, y_hi - y_lo, fill=False, lw=1.2, color="0.3",
                               label="walls of the simulated domain"))
        box = (x_lo, x_hi, y_lo, y_hi)
    draw_spreading_areas(ax, comp.areas, box)
    if scene is not None and scene.column is not None:
        draw_column(ax, scene.column)
    for r in results.gauge_summary.itertuples():
        if np.isfinite(r.x_m):
            ax.plot(r.x_m, r.y_m, marker="o", ms=6, color="#1a9641", ls="none", label="gauge", zorder=4)
            # upstream of and above the gauge: a gauge sits just upstream of the column's face
            ax.annotate(r.gauge, (r.x_m, r.y_m), xytext=(-5, 5), textcoords="offset points", ha="right",
                        va="bottom", fontsize=SMALL, color="#1a9641", zorder=6,
                        bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none",
                              "alpha": 0.8})
    if bodies.empty:
        why = "no debris in this scene" if scene is not None and not scene.debris else "no body tracks in this run"
        empty(axv, f"{why}: no tracks, no speeds")
    else:
        starts = []
        for body, track in bodies.groupby("body"):
            line, = ax.plot(track["x_m"], track["y_m"], lw=1.6, label=body, zorder=3)
            starts.append((track["x_m"].iloc[0], track["y_m"].iloc[0], line.get_color()))
            axv.plot(track["time_s"], track["speed_m_s"], lw=1.2, color=line.get_color(), label=body)
        ax.scatter([s[0] for s in starts], [s[1] for s in starts], marker="s", s=30, c=[s[2] for s in starts],
                   edgecolors="k", linewidths=0.6, zorder=4, label="start of a track")
        mark_strikes(ax, axv, results.impacts, "impacts", "impact", alpha=0.7)
        label_speed_axes(axv)
    set_plan_view(ax, xlim, ylim)
    ax.set_title("Debris tracks (centre of mass) in plan view, and the spreading areas (ASCE 7-22 6.11.5.1)\n"
                 "from the debris's start line (cf. the study's Fig. 14)", fontsize=10, loc="left")
    legend(ax, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(alpha=0.3)
    return fig


def plot_tracks(results, comp, path: Path) -> Path:
    return save_figure(figure_tracks(results, comp), path)
