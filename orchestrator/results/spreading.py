"""How far debris tracks spread sideways, and the measured spreading they are set against.

Pure functions over plan-view tracks (x along the flow, y across, metres), used by the
spreading page (:mod:`orchestrator.studies.spreading`, docs/results/spreading/).

Definitions
-----------
A track is one body's centre in plan view over time, ``(x_m, y_m)``, starting at ``(x0, y0)``
(its first point: the realisation's perturbed start).

* **Crossing of a station** ``x_s``: the first time the track reaches ``x >= x_s``; its lateral
  position ``y(x_s)`` is interpolated linearly between the two track points either side
  (:func:`station_crossing`). A track that never reaches ``x_s`` has none (NaN).
* **Spreading angle at a station** (:func:`angle_at_station`):
  ``theta(x_s) = atan2(y(x_s) - y0, x_s - x0)`` in degrees, positive towards +y; NaN when the
  track does not reach ``x_s`` or when ``x_s - x0`` is less than ``min_run_m`` (a station the body
  started next to says nothing about a direction).
* **Angle of a displacement** (:func:`displacement_angle`): ``atan2(y - y0, x - x0)`` of the
  displacement from the start to one point of the track: to the farthest-downstream point (the
  "max" position) and to the last point (the "rest" position, the end of the run or where the
  body left the record), as the measured spreading below is plotted (Goseberg et al. 2016 as
  HydroUQ digitised it: "Max & Rest Debris Position"). NaN when the displacement's streamwise
  part is under ``min_run_m``.
* **Lateral spread at a station** (:func:`lateral_spread`): over all tracks that cross ``x_s``, the
  sample standard deviation (ddof 1) and the interquartile range (75th minus 25th percentile,
  linear interpolation) of the lateral displacement ``y(x_s) - y0``, and the ratio of the standard
  deviation to the mean streamwise run ``x_s - x0``: the figure that the JSCE 2021 experiments
  below give as 0.04.
* **Direction of the recorded flow along the path** (:func:`flow_direction`): over the record's
  points in a plan box (the bodies' path) at one level above the bed, at every frame where the
  water there is at least 1.5 times that level deep, the mean streamwise velocity u, the RMS
  of the lateral velocity v, their ratio, and percentiles of the flow's angle atan2(v, u). A
  body carried one-way by a flow whose direction scatters by a given angle can spread only by
  about as much, unless its own dynamics add to it.
* **Box statistics** (:func:`box_stats`): median, quartiles and whiskers at the most extreme data
  within 1.5 IQR of the box (Tukey's rule, matplotlib's default, which the HydroUQ plot also
  draws).

The measured spreading (:data:`GOSEBERG_2016_BOXES`, :data:`LATERAL_SPREAD_RATE`) and the
design envelopes (:data:`orchestrator.results.compare.SPREADING_ANGLES_DEG`) carry their sources.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "GOSEBERG_2016_BOXES",
    "GOSEBERG_2016_SOURCE",
    "LATERAL_SPREAD_RATE",
    "angle_at_station",
    "box_stats",
    "displacement_angle",
    "flow_direction",
    "lateral_spread",
    "station_crossing",
    "station_key",
    "track_angles",
]

GOSEBERG_2016_SOURCE = (
    "Goseberg, N., Stolle, J., Nistor, I. & Shibayama, T. (2016). Experimental analysis of debris motion due the "
    "obstruction from fixed obstacles in tsunami-like flow conditions. Coastal Engineering 118, 35-49, "
    "doi:10.1016/j.coastaleng.2016.08.012 (Waseda University tsunami wave basin, 1:40 container models on a "
    "harbour apron). The boxes are read off the experiment's boxes in HydroUQ's benchmark hdro-0004, figure "
    "Benchmark4_Debris_Spread_BoxAndWhiskers_2024.04.27.png (NHERI-SimCenter/HydroUQ, Examples/hdro-0004/figures, "
    "commit 1d3d30e6), by the pixel rows of the box edges, whisker caps and median lines against the plot's "
    "+-22.5 degree lines (about 25 px a degree: read to +-0.1 degree)"
)
"""Where :data:`GOSEBERG_2016_BOXES` come from."""

GOSEBERG_2016_BOXES: dict[str, dict[str, float]] = {
    "0x0 obstacles (Up)": {"whislo": -12.5, "q1": -3.3, "med": 1.7, "q3": 4.7, "whishi": 7.2},
    "5x1 obstacles (Up)": {"whislo": -9.4, "q1": -2.5, "med": 0.4, "q3": 3.3, "whishi": 6.0},
    "5x2 obstacles (Up)": {"whislo": -15.8, "q1": -4.8, "med": 0.1, "q3": 4.2, "whishi": 15.2},
    "0x0 obstacles (Down)": {"whislo": -16.7, "q1": -2.9, "med": 0.0, "q3": 3.9, "whishi": 10.0},
    "5x2 obstacles (Down)": {"whislo": -8.8, "q1": -2.3, "med": 0.5, "q3": 2.2, "whishi": 9.6},
}
"""Measured spreading angles (degrees, + and - either side of the flow) of Goseberg et al. 2016's
containers, one box per experimental case as HydroUQ's benchmark labels them (rows of five
obstacles, "Up"/"Down" the debris's start position upstream or downstream in the basin): the
angle of each container's displacement to its farthest and to its rest position
(:data:`GOSEBERG_2016_SOURCE`). The same plot draws the Nistor envelope at 15 degrees
(labelled "Nistor (2016)"), not at the 16.8 this package draws."""

LATERAL_SPREAD_RATE = {
    "sigma_over_run": 0.04,
    "source": "J. JSCE Ser. B3 (Ocean Engineering) 77(2), I_115-I_120 (2021), jstage article jscejoe/77/2/77_I_115: "
              "rectangular objects carried by a tsunami-like flow over horizontal land at initial angles up to 30 "
              "degrees; the standard deviation of the lateral movement modelled as 0.04 x the distance travelled "
              "down the flow, independent of the initial angle (largest single direction 16.7 degrees); from the "
              "abstract only, the paper itself was not retrieved",
}
"""A measured lateral spread: standard deviation of the lateral displacement over the streamwise run."""


def station_crossing(x_m, y_m, station_x_m: float) -> float:
    """The track's lateral position (m) where it first reaches ``x >= station_x_m``, linear between
    the two points either side; NaN if it never does. A track starting at or past the station
    crosses it at its first point."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    if x.size == 0 or x.shape != y.shape:
        return math.nan
    past = np.flatnonzero(x >= station_x_m)
    if past.size == 0:
        return math.nan
    i = int(past[0])
    if i == 0:
        return float(y[0])
    x_a, x_b = x[i - 1], x[i]
    frac = (station_x_m - x_a) / (x_b - x_a) if x_b != x_a else 1.0
    return float(y[i - 1] + frac * (y[i] - y[i - 1]))


def angle_at_station(x_m, y_m, station_x_m: float, min_run_m: float = 0.25) -> float:
    """Spreading angle (degrees) at the station: ``atan2(y(x_s) - y0, x_s - x0)`` (module notes);
    NaN when the track does not reach the station or starts less than ``min_run_m`` before it."""
    x = np.asarray(x_m, dtype=float)
    if x.size == 0:
        return math.nan
    run = station_x_m - float(x[0])
    if run < min_run_m:
        return math.nan
    y_s = station_crossing(x_m, y_m, station_x_m)
    if not math.isfinite(y_s):
        return math.nan
    return math.degrees(math.atan2(y_s - float(np.asarray(y_m, dtype=float)[0]), run))


def displacement_angle(x0_m: float, y0_m: float, x_m: float, y_m: float, min_run_m: float = 0.25) -> float:
    """Angle (degrees) of the displacement from (x0, y0) to (x, y) from the +x direction,
    positive towards +y; NaN when its streamwise part is under ``min_run_m``."""
    run = float(x_m) - float(x0_m)
    if not math.isfinite(run) or run < min_run_m:
        return math.nan
    return math.degrees(math.atan2(float(y_m) - float(y0_m), run))


def track_angles(x_m, y_m, stations_m, min_run_m: float = 0.25) -> dict[str, Any]:
    """One track's figures: its start, its lateral position and angle at each station
    (``y_at_<x>`` and ``angle_at_<x>``, x in mm), its farthest-downstream ("max") and last
    ("rest") points and the angles of the displacements to them (module notes)."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    out: dict[str, Any] = {"x0_m": float(x[0]), "y0_m": float(y[0])}
    for xs in stations_m:
        key = station_key(xs)
        out[f"y_at_{key}"] = station_crossing(x, y, xs)
        out[f"angle_at_{key}"] = angle_at_station(x, y, xs, min_run_m)
    i = int(np.argmax(x))
    out.update(x_max_m=float(x[i]), y_at_x_max_m=float(y[i]), x_rest_m=float(x[-1]), y_rest_m=float(y[-1]))
    out["angle_max_deg"] = displacement_angle(x[0], y[0], x[i], y[i], min_run_m)
    out["angle_rest_deg"] = displacement_angle(x[0], y[0], x[-1], y[-1], min_run_m)
    return out


def station_key(station_x_m: float) -> str:
    """The column suffix of a station: its x in whole millimetres, e.g. ``4600mm``."""
    return f"{round(float(station_x_m) * 1000):d}mm"


def lateral_spread(y0_m, y_station_m, x0_m, station_x_m: float) -> dict[str, float]:
    """The lateral spread at a station over tracks (arrays: each track's start and its lateral
    position at the station, NaN where it did not reach it): the count, the mean, sample standard
    deviation (ddof 1) and interquartile range of ``y(x_s) - y0`` (m), the mean run ``x_s - x0``
    and the standard deviation over it (module notes)."""
    y0 = np.asarray(y0_m, dtype=float)
    ys = np.asarray(y_station_m, dtype=float)
    x0 = np.asarray(x0_m, dtype=float)
    keep = np.isfinite(ys) & np.isfinite(y0) & np.isfinite(x0)
    dy = ys[keep] - y0[keep]
    out = {"tracks": int(dy.size), "mean_dy_m": math.nan, "std_dy_m": math.nan, "iqr_dy_m": math.nan,
           "mean_run_m": math.nan, "std_over_run": math.nan}
    if dy.size:
        out["mean_dy_m"] = float(dy.mean())
        q1, q3 = np.percentile(dy, [25.0, 75.0])
        out["iqr_dy_m"] = float(q3 - q1)
        out["mean_run_m"] = float(np.mean(station_x_m - x0[keep]))
    if dy.size > 1:
        out["std_dy_m"] = float(dy.std(ddof=1))
        if out["mean_run_m"] > 0:
            out["std_over_run"] = out["std_dy_m"] / out["mean_run_m"]
    return out


def box_stats(values) -> dict[str, float]:
    """Tukey box statistics of the finite values: ``med``, ``q1``, ``q3`` (linear percentiles),
    ``whislo``/``whishi`` (the most extreme values within 1.5 IQR of the box), the count ``n``
    and how many lie outside the whiskers (``outliers``); NaNs when there is no value."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return {k: math.nan for k in ("med", "q1", "q3", "whislo", "whishi")} | {"n": 0, "outliers": 0}
    q1, med, q3 = np.percentile(v, [25.0, 50.0, 75.0])
    iqr = q3 - q1
    inside = v[(v >= q1 - 1.5 * iqr) & (v <= q3 + 1.5 * iqr)]
    return {"med": float(med), "q1": float(q1), "q3": float(q3), "whislo": float(inside.min()),
            "whishi": float(inside.max()), "n": int(v.size), "outliers": int(v.size - inside.size)}


def flow_direction(t_s, x_m, y_m, z_m, bed_z_m: float, eta_m, velocity_m_s, x_range_m, y_range_m,
                   level_m: float) -> dict[str, float]:
    """The recorded flow's direction along a path (module notes): arrays as
    :class:`~orchestrator.transport.flow.FlowField` holds them (``eta_m`` (t, x, y), ``velocity_m_s``
    (t, x, y, z, 3)); the plan box ``x_range_m`` x ``y_range_m``; the level nearest ``level_m``
    above the bed. Returns the count of wet samples, the level used, mean u and RMS v (m/s), RMS v
    over mean u, and the 5th, 25th, 75th and 95th percentiles of atan2(v, u) in degrees (NaN
    without a wet sample)."""
    x = np.asarray(x_m, dtype=float)
    y = np.asarray(y_m, dtype=float)
    z = np.asarray(z_m, dtype=float)
    ix = np.flatnonzero((x >= x_range_m[0]) & (x <= x_range_m[1]))
    iy = np.flatnonzero((y >= y_range_m[0]) & (y <= y_range_m[1]))
    k = int(np.argmin(np.abs(z - (bed_z_m + level_m))))
    level = float(z[k] - bed_z_m)
    out = {"samples": 0, "level_m": level, "mean_u_m_s": math.nan, "rms_v_m_s": math.nan, "rms_v_over_u": math.nan,
           "angle_p5_deg": math.nan, "angle_p25_deg": math.nan, "angle_p75_deg": math.nan, "angle_p95_deg": math.nan}
    if ix.size == 0 or iy.size == 0:
        return out
    depth = np.asarray(eta_m, dtype=float)[:, ix][:, :, iy] - bed_z_m
    vel = np.asarray(velocity_m_s)[:, ix][:, :, iy][..., k, :2].astype(float)
    wet = depth >= 1.5 * level
    if not wet.any():
        return out
    u, v = vel[..., 0][wet], vel[..., 1][wet]
    angle = np.degrees(np.arctan2(v, u))
    p5, p25, p75, p95 = np.percentile(angle, [5.0, 25.0, 75.0, 95.0])
    rms_v = float(np.sqrt(np.mean(v ** 2)))
    out.update(samples=int(u.size), mean_u_m_s=float(u.mean()), rms_v_m_s=rms_v,
               rms_v_over_u=rms_v / float(u.mean()) if u.mean() > 0 else math.nan, angle_p5_deg=float(p5),
               angle_p25_deg=float(p25), angle_p75_deg=float(p75), angle_p95_deg=float(p95))
    return out
