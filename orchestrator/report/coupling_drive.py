"""What drives each body afloat: the fluid force a two-way run measures on it against the one-way
forcing on the same body moving along the same track (``debrisfoam report coupling --drag-scan``,
:mod:`orchestrator.report.coupling`).

:func:`fluid_drive` reads both runs (:class:`~orchestrator.report.layouts.Layout`) and the one-way
run's record. Once every body floats two-way it sets, along x, y and z, the mean fluid force the
two-way solver measures on each body's wall (`lift_<body>`, joined over restarts) beside the one-way
forcing on the same body moving along the same two-way track through the flow without the bodies
(:func:`~orchestrator.transport.budget.force_budget`: buoyancy, Froude-Krylov, the water's added
mass and drag, less the added mass's reaction to the body's own acceleration, the part of the
fluid force the wall feels). :func:`drive_lines` and :func:`drive_figure` put it on the page.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from orchestrator.report.figures import legend, pyplot, save_figure
from orchestrator.report.layout_page import figure_text
from orchestrator.report.layouts import Layout
from orchestrator.run.waterdepth import read_force_history
from orchestrator.transport.budget import force_budget
from orchestrator.transport.case_transport import scene_settings, transport_setup
from orchestrator.transport.flow import FlowField

__all__ = ["AFLOAT_RISE_M", "DRIVE_INTERVAL_S", "DRIVE_SETTLE_S", "Drive", "afloat_s", "body_track", "drive_figure",
           "drive_lines", "fluid_drive"]

#: a body counts as afloat once its centre has risen this much above where it started (m): the
#: study's container floats 26 mm deep, so afloat in the bore its centre rises by centimetres
AFLOAT_RISE_M = 0.005
#: the drive (:func:`fluid_drive`) is averaged from this long after the last body is afloat two-way
#: to the comparison's end (s): the release's own transient left out
DRIVE_SETTLE_S = 0.05
#: the drive's sampling of the two-way tracks (s)
DRIVE_INTERVAL_S = 0.01


def body_track(lay: Layout, body: str) -> pd.DataFrame:
    """One body's rows of a run's bodies table, once per time, in time order."""
    t = lay.bodies[lay.bodies["body"] == body]
    return t.drop_duplicates("time_s", keep="last").sort_values("time_s").reset_index(drop=True)


def afloat_s(track: pd.DataFrame) -> float:
    """When a body's centre first stood AFLOAT_RISE_M above where it started (NaN: never)."""
    z = track["z_m"].to_numpy(float)
    up = np.nonzero(z - z[0] >= AFLOAT_RISE_M)[0] if len(z) else []
    return float(track["time_s"].iloc[up[0]]) if len(up) else float("nan")


def _drive_window(two: Layout, until_s: float) -> tuple[float, float] | None:
    """From DRIVE_SETTLE_S after the last body is afloat two-way to `until_s` (the comparison's end);
    None when some body never floats two-way or that leaves less than two samples."""
    afloat = [afloat_s(body_track(two, b)) for b in two.body_names]
    if not afloat or not np.all(np.isfinite(afloat)):
        return None
    start = max(afloat) + DRIVE_SETTLE_S
    return (start, until_s) if until_s - start >= 2 * DRIVE_INTERVAL_S else None


def _resampled(track: pd.DataFrame, times: np.ndarray) -> pd.DataFrame:
    """A track's numeric columns interpolated to `times` (the rotation entry by entry: the samples
    are close enough that the result stays a rotation to the budget's accuracy)."""
    cols = [c for c in track.columns if c != "body" and pd.api.types.is_numeric_dtype(track[c])]
    out = pd.DataFrame({c: np.interp(times, track["time_s"], track[c]) for c in cols})
    out["time_s"] = times
    return out


def _time_mean(t: np.ndarray, v: np.ndarray) -> float:
    """The mean of v over time (trapezoids; the solver's steps are uneven, shortest near contacts)."""
    if len(t) < 2:
        return float(v[0]) if len(t) else float("nan")
    return float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(t)) / (t[-1] - t[0]))


def _bin_means(t: np.ndarray, v: np.ndarray, centres: np.ndarray, width: float) -> np.ndarray:
    """The time mean of v over [c - width/2, c + width/2] at each centre c (trapezoids)."""
    if len(t) < 2:
        return np.full(len(centres), np.nan)
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    lo, hi = np.clip(centres - width / 2, t[0], t[-1]), np.clip(centres + width / 2, t[0], t[-1])
    span = hi - lo
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(span > 0, (np.interp(hi, t, integral) - np.interp(lo, t, integral)) / span, np.nan)


class Drive(NamedTuple):
    """:func:`fluid_drive`'s answer: the means (a row per body, and "all") and the series they
    are the means of (a row per body and sample)."""

    table: pd.DataFrame
    series: pd.DataFrame


def fluid_drive(one: Layout, two: Layout, until_s: float, flow: FlowField) -> Drive:
    """What moves each body of the one-way run ``one`` and the two-way run ``two`` of a scene once every
    body is afloat two-way (:func:`_drive_window`, up to ``until_s``), along x, y
    and z: the mean over time of the fluid force the two-way solver measures on the body's wall
    (`lift_<body>`), and the mean the one-way forcing gives on the same body moving along the same
    two-way track through the one-way record ``flow`` (buoyancy, Froude-Krylov, the water's added
    mass and drag, less the added mass's reaction to the body's own acceleration: the part of the
    fluid force the wall feels; :func:`~orchestrator.transport.budget.force_budget`), with the
    body's mass times its mean acceleration (x, y) and its weight; a last row sums the bodies. The
    series: the streamwise forces every DRIVE_INTERVAL_S (the measured one averaged over the
    interval around each sample). Where the two agree the one-way forcing drives the body as the
    coupled flow does; where the measured drive is smaller the body meets slower water than the
    undisturbed record's, as a body in another's wake does. Both empty when the window is (see
    _drive_window)."""
    window = _drive_window(two, until_s)
    if window is None:
        return Drive(pd.DataFrame(), pd.DataFrame())
    bodies, _, _ = transport_setup(one.scene, flow)
    hydro = scene_settings(one.scene).hydro
    # the budget drops the first and last samples (central differences): none past the window's end, where
    # a strike turns the body back
    times = np.arange(window[0] - DRIVE_INTERVAL_S, window[1] + 1e-9, DRIVE_INTERVAL_S)
    times = times[times <= float(body_track(two, bodies[0].name)["time_s"].iloc[-1])]
    rows, series = [], []
    for body in bodies:
        track = _resampled(body_track(two, body.name), times)
        budget = force_budget(track, flow, body.size_m, body.mass_kg, hydro, flow_start_s=0.0)
        budget = budget[(budget["time_s"] >= window[0] - 1e-9) & (budget["time_s"] <= window[1] + 1e-9)]
        accel = {a: budget[f"inertia_{a}"] / (body.mass_kg + budget[f"added_mass_{a}_kg"]) for a in "xyz"}
        wall = {a: (budget[f"buoyancy_{a}"] + budget[f"froude_krylov_{a}"] + budget[f"added_mass_flow_{a}"]
                    + budget[f"drag_{a}"] - budget[f"added_mass_{a}_kg"] * accel[a]) for a in "xyz"}
        force = read_force_history(two.case, body.name)
        inside = (force[:, 0] >= window[0]) & (force[:, 0] <= window[1])
        rows.append({"body": body.name, "from_s": window[0], "to_s": window[1],
                     "x_mean_m": float(budget["x_m"].mean()), "y_mean_m": float(budget["y_m"].mean()),
                     "u_mean_m_s": float(budget["u_m_s"].mean()),
                     "two_way_fx_N": _time_mean(force[inside, 0], force[inside, 1]),
                     "one_way_forcing_fx_N": float(wall["x"].mean()), "one_way_drag_x_N": float(budget["drag_x"].mean()),
                     "mass_times_accel_x_N": float(body.mass_kg * accel["x"].mean()),
                     "two_way_fy_N": _time_mean(force[inside, 0], force[inside, 2]),
                     "one_way_forcing_fy_N": float(wall["y"].mean()),
                     "mass_times_accel_y_N": float(body.mass_kg * accel["y"].mean()),
                     "two_way_fz_N": _time_mean(force[inside, 0], force[inside, 3]),
                     "one_way_forcing_fz_N": float(wall["z"].mean()), "weight_N": float(-budget["weight_z"].mean()),
                     "z_mean_m": float(budget["z_m"].mean()), "samples": int(inside.sum())})
        at = budget["time_s"].to_numpy(float)
        series.append(pd.DataFrame({
            "time_s": at, "body": body.name, "x_m": budget["x_m"].to_numpy(float),
            "two_way_fx_N": _bin_means(force[inside, 0], force[inside, 1], at, DRIVE_INTERVAL_S),
            "one_way_forcing_fx_N": wall["x"].to_numpy(float), "one_way_drag_x_N": budget["drag_x"].to_numpy(float)}))
    table = pd.DataFrame(rows)
    total = {"body": "all", "from_s": window[0], "to_s": window[1], "x_mean_m": float("nan"),
             "y_mean_m": float("nan"), "z_mean_m": float("nan"), "u_mean_m_s": float("nan"),
             "samples": int(table["samples"].min())}
    for col in ("two_way_fx_N", "one_way_forcing_fx_N", "one_way_drag_x_N", "mass_times_accel_x_N",
                "two_way_fy_N", "one_way_forcing_fy_N", "mass_times_accel_y_N", "two_way_fz_N",
                "one_way_forcing_fz_N", "weight_N"):
        total[col] = float(table[col].sum())
    if len(table) > 1:
        table = pd.concat([table, pd.DataFrame([total])], ignore_index=True)
    return Drive(table, pd.concat(series, ignore_index=True))


def drive_lines(table: pd.DataFrame, series: pd.DataFrame) -> list[str]:
    """The page's section on the drive (:func:`fluid_drive`'s table and, when there is one, the
    figure `drive.png` of its series)."""
    first = table.iloc[0]
    lines = ["## What drives the bodies afloat", "",
             f"The mean streamwise force of the water on each body from t = {first['from_s']:.3f} to "
             f"{first['to_s']:.3f} s (every body afloat two-way, from {DRIVE_SETTLE_S:g} s after the last one "
             "rose): measured on the body's wall by the two-way solver, and as the one-way forcing gives it on the "
             "same body moving along the same two-way track through the one-way run's record, the flow without the "
             "bodies (its drag part apart); and the body's mass times its mean acceleration, two-way (the fluid's "
             "force plus what the other bodies and the walls push it with). `drive.csv`.", "",
             "| body | mean x | mean speed | fluid force, two-way | one-way forcing on the same track | its drag | "
             "mass x acceleration |", "|---|---|---|---|---|---|---|"]
    for r in table.to_dict("records"):
        lines.append(f"| {r['body']} | {figure_text(r['x_mean_m'], '.2f', ' m')} | "
                     f"{figure_text(r['u_mean_m_s'], '.2f', ' m/s')} | {figure_text(r['two_way_fx_N'], '+.2f', ' N')} | "
                     f"{figure_text(r['one_way_forcing_fx_N'], '+.2f', ' N')} | {figure_text(r['one_way_drag_x_N'], '+.2f', ' N')} | "
                     f"{figure_text(r['mass_times_accel_x_N'], '+.2f', ' N')} |")
    lines += ["", "Where the measured force is smaller than the one-way forcing's, the body meets slower water "
                  "than the undisturbed record's where it is (a body in another's wake); the one-way forcing "
                  "drives every body by the undisturbed flow at its own place.", "",
              "Across the flow over the same time (+: towards +y):", "",
              "| body | mean y | fluid force, two-way | one-way forcing on the same track | mass x acceleration |",
              "|---|---|---|---|---|"]
    for r in table.to_dict("records"):
        lines.append(f"| {r['body']} | {figure_text(r['y_mean_m'], '+.3f', ' m')} | "
                     f"{figure_text(r['two_way_fy_N'], '+.2f', ' N')} | {figure_text(r['one_way_forcing_fy_N'], '+.2f', ' N')} | "
                     f"{figure_text(r['mass_times_accel_y_N'], '+.2f', ' N')} |")
    lines += ["", "Up, over the same time, beside the body's weight (the one-way forcing here with the buoyancy of "
                  "the recorded water at the body's place):", "",
              "| body | mean height of the centre | fluid force, two-way | one-way forcing on the same track | weight |",
              "|---|---|---|---|---|"]
    for r in table.to_dict("records"):
        lines.append(f"| {r['body']} | {figure_text(r['z_mean_m'], '.3f', ' m')} | "
                     f"{figure_text(r['two_way_fz_N'], '+.2f', ' N')} | {figure_text(r['one_way_forcing_fz_N'], '+.2f', ' N')} | "
                     f"{figure_text(r['weight_N'], '.2f', ' N')} |")
    lines += [""]
    if not series.empty:
        lines += ["![drive](drive.png)", "", "Each body's streamwise fluid force against time: measured two-way "
                  f"(averaged over {DRIVE_INTERVAL_S:g} s), the one-way forcing on the same track, and its drag.", ""]
    return lines


#: the drive figure draws at most this many bodies, a panel each
DRIVE_PANELS = 6


def drive_figure(series: pd.DataFrame, path: Path) -> Path:
    """Each body's streamwise fluid force against time (:func:`fluid_drive`): measured two-way, and
    the one-way forcing on the same track (its drag part dotted)."""
    plt = pyplot()
    names = list(dict.fromkeys(series["body"]))[:DRIVE_PANELS]
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 1.2 + 2.2 * len(names)), sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        d = series[series["body"] == name]
        ax.plot(d["time_s"], d["two_way_fx_N"], "-", color="C0", label="two-way, measured on its wall")
        ax.plot(d["time_s"], d["one_way_forcing_fx_N"], "--", color="C3", label="one-way forcing on the same track")
        ax.plot(d["time_s"], d["one_way_drag_x_N"], ":", color="C3", label="its drag")
        ax.axhline(0.0, color="0.5", linewidth=0.8)
        ax.set_ylabel(f"{name}\nx force (N)")
        ax.grid(alpha=0.3)
    legend(axes[0, 0], fontsize=8)
    axes[-1, 0].set_xlabel("time (s)")
    fig.tight_layout()
    return save_figure(fig, path)
