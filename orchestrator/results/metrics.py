"""The measures post-processing takes of a run: gauge elevation, bore arrival, impact pulse
metrics and the column's response. Pure functions of arrays and frames; no files.

Definitions (units: s, m, N, N m, m/s, rad/s, degrees):

* Gauge elevation (:func:`gauge_elevation`): the integral of the sampled alpha.water over
  the line, with the first and last samples held to the bed and to the top of the line. The
  gauges sample each cell's value (``interpolationScheme cell``), so between two samples
  that straddle one cell face of the background mesh (its z planes, from plan.json) each
  value holds up to the face: the elevation is the water in the cells' column, and a still
  wet bed reads its depth whatever the cells above it (interpolated to the points,
  ``cellPoint``, a 15 mm bed layer under 4 cm cells read 20-21 mm). Elsewhere, and for
  cases sampled with ``cellPoint``, trapezoids between samples. Samples are missing where
  the line runs outside the fluid mesh (inside a debris body's hole, or a cell the sampler
  could not find); a gap longer than :data:`GAP_FACTOR` sample spacings is integrated only
  when its content is clear (water on both sides, air on both sides, water below the lowest
  sample, air above the highest), and a line covered over less than
  :data:`MIN_GAUGE_COVERAGE` of its length gives no elevation (NaN, counted as obstructed).
* Arrival time (:func:`arrival_time`): the first time the elevation exceeds the gauge's
  initial level (the scene's still water there: the impoundment upstream of the gate, the
  wet bed downstream) by :data:`ARRIVAL_FRACTION` of the impoundment depth (8 mm for the
  study's 0.40 m), linearly interpolated between samples (from the initial level at t = 0
  before the first sample). A gauge whose level never rises that much (e.g. upstream of the
  gate) has none (NaN).
* Impact pulse metrics (:func:`impact_metrics`): peak force; duration from the first rise
  above zero to the last return to it (edges located inside their sample interval);
  impulse, the trapezoidal integral of the force.
* Column response (:func:`column_response`): the total load on the column's MDOF model and
  the base shear at the load cell it causes, split into its hydrodynamic and impact parts.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from analytical.mdof import mdof_response
from analytical.pulses import Tabulated
from orchestrator.case.folder import EPS_T

__all__ = [
    "ARRIVAL_FRACTION",
    "ARRIVAL_THRESHOLD_FALLBACK_M",
    "GAP_FACTOR",
    "MIN_GAUGE_COVERAGE",
    "PulseMetrics",
    "arrival_time",
    "column_response",
    "gauge_elevation",
    "impact_metrics",
    "pulse_sum",
]

#: Bore arrival: a rise of this fraction of the impoundment depth above the initial level.
ARRIVAL_FRACTION = 0.02
#: Arrival threshold (m) when the scene (and so the impoundment depth) is unknown.
ARRIVAL_THRESHOLD_FALLBACK_M = 0.01
#: A gauge line covered over less than this fraction of its length gives no elevation.
MIN_GAUGE_COVERAGE = 0.95
#: Samples further apart than this many sample spacings leave a gap (an obstruction).
GAP_FACTOR = 1.5
#: Time step (s) of the column response around each impact, and the window around it (s).
RESPONSE_DT_S = 1.0e-5
RESPONSE_PRE_S = 2.0e-3
RESPONSE_POST_S = 0.10
#: At most this many samples of the hydrodynamic force go into its (quasi-static) base shear.
HYDRO_RESPONSE_SAMPLES = 1000
#: alpha.water at or above _WET is water, at or below _DRY is air (gauge gaps).
_WET, _DRY = 0.99, 0.01


@dataclass(frozen=True)
class PulseMetrics:
    """Peak (N) and its time (s), start, end and duration (s), impulse (N s) of a force pulse."""

    peak_N: float
    time_of_peak_s: float
    start_s: float
    end_s: float
    duration_s: float
    impulse_Ns: float


# --------------------------------------------------------------------------- gauges


def gauge_elevation(z_m, alpha, bed_m: float, top_m: float,
                    spacing_m: float | None = None, faces_m=None) -> tuple[float, float]:
    """Water height (m) on a vertical gauge line and the fraction of the line covered.

    ``integral of alpha dz`` from ``bed_m`` to ``top_m``: trapezoids between samples, the first
    and last samples held down to the bed and up to the top. A gap wider than
    :data:`GAP_FACTOR` x ``spacing_m`` (default: the smallest sample spacing) is integrated
    only when what it holds is clear: water on both sides (alpha >= 0.99), air on both sides
    (alpha <= 0.01), water below the lowest sample down to the bed, air above the highest
    up to the top; otherwise it is left out. The coverage is the integrated length over
    ``top_m - bed_m``.

    ``faces_m``: the mesh's cell faces along the line, for samples that are cell values (the
    ``cell`` interpolation): between two samples with exactly one face between them each
    value holds up to the face, so the integral is the water in the cells' column, whatever
    the spacing (a trapezoid there is off by up to half a spacing). Elsewhere, trapezoids.
    """
    z = np.asarray(z_m, dtype=float)
    a = np.clip(np.asarray(alpha, dtype=float), 0.0, 1.0)
    length = float(top_m) - float(bed_m)
    if z.size == 0 or length <= 0:
        return float("nan"), 0.0
    order = np.argsort(z, kind="stable")
    z, a = z[order], a[order]
    dz = np.diff(z)
    if spacing_m is None:
        positive = dz[dz > 0]
        spacing_m = float(positive.min()) if positive.size else length
    max_gap = GAP_FACTOR * float(spacing_m)
    wet, dry = a >= _WET, a <= _DRY
    ok = (dz <= max_gap) | (wet[1:] & wet[:-1]) | (dry[1:] & dry[:-1])
    piece = 0.5 * (a[1:] + a[:-1]) * dz
    if faces_m is not None and z.size > 1:
        f = np.sort(np.asarray(faces_m, dtype=float))
        first = np.searchsorted(f, z[:-1], side="right")  # the first face above each sample
        one = np.searchsorted(f, z[1:], side="left") - first == 1  # exactly one face inside
        face = f[np.minimum(first, f.size - 1)] if f.size else z[:-1]
        step = a[:-1] * (face - z[:-1]) + a[1:] * (z[1:] - face)
        piece = np.where(one, step, piece)
    total = float(np.sum(piece * ok))
    covered = float(np.sum(dz * ok))
    below, above = max(z[0] - bed_m, 0.0), max(top_m - z[-1], 0.0)
    if below <= max_gap or wet[0]:
        total += a[0] * below
        covered += below
    if above <= max_gap or dry[-1]:
        total += a[-1] * above
        covered += above
    return total, min(covered / length, 1.0)


def arrival_time(time_s, elevation_m, initial_m: float, threshold_m: float) -> float:
    """First time (s) the elevation exceeds ``initial_m + threshold_m``; NaN if never.

    Interpolated linearly between the samples around the crossing; before the first
    sample the level is taken as ``initial_m`` at t = 0. NaN samples are skipped.
    """
    t = np.asarray(time_s, dtype=float)
    e = np.asarray(elevation_m, dtype=float)
    keep = np.isfinite(t) & np.isfinite(e)
    t, e = t[keep], e[keep]
    level = float(initial_m) + float(threshold_m)
    above = np.flatnonzero(e > level)
    if above.size == 0:
        return float("nan")
    i = int(above[0])
    t0, e0 = (t[i - 1], e[i - 1]) if i > 0 else (0.0, float(initial_m))
    if e[i] == e0 or t[i] <= t0:
        return float(t[i])
    return float(t0 + (level - e0) / (e[i] - e0) * (t[i] - t0))


# --------------------------------------------------------------------------- impacts


def impact_metrics(time_s, force_N) -> PulseMetrics:
    """Peak, duration and impulse of a compressive force pulse (force >= 0).

    Duration: from where the force first rises from zero to where it last returns to zero.
    Each edge is found inside its sample interval by extending the line through the pulse's
    first (last) two samples down to zero (exact for a linear edge; a half-sine sampled 44
    times is then within 0.1 %); where that line does not fall inside the interval (a step
    edge), the interval's zero sample is taken. The record's ends count as edges when the
    force is not zero there. Impulse: trapezoidal integral over the whole record.
    """
    t = np.asarray(time_s, dtype=float)
    f = np.asarray(force_N, dtype=float)
    if t.ndim != 1 or t.shape != f.shape or t.size < 2:
        raise InputError("force_N", f"need 1-D time and force of equal length >= 2, got {t.shape}, {f.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
        raise InputError("force_N", "the record holds NaN or infinite values")
    if np.any(np.diff(t) <= 0):
        raise InputError("time_s", "must increase strictly")
    i_peak = int(np.argmax(f))
    peak = float(f[i_peak])
    impulse = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)))
    if peak <= 0.0:
        return PulseMetrics(peak, float(t[i_peak]), float("nan"), float("nan"), 0.0, impulse)
    active = np.flatnonzero(f > 1e-9 * peak)
    first, last = int(active[0]), int(active[-1])

    def edge(zero: int, inner: int, next_: int) -> float:
        """Zero of the line through samples inner and next_, kept between zero and inner."""
        lo, hi = sorted((float(t[zero]), float(t[inner])))
        if 0 <= next_ < t.size and f[next_] > f[inner]:
            x = float(t[inner] - f[inner] * (t[next_] - t[inner]) / (f[next_] - f[inner]))
            if lo <= x <= hi:
                return x
        return float(t[zero])

    start = edge(first - 1, first, first + 1) if first > 0 else float(t[0])
    end = edge(last + 1, last, last - 1) if last < t.size - 1 else float(t[-1])
    return PulseMetrics(peak, float(t[i_peak]), start, end, end - start, impulse)


# --------------------------------------------------------------------------- the column


def pulse_sum(pulses: dict[int, tuple[np.ndarray, np.ndarray]], t: np.ndarray) -> np.ndarray:
    """Sum of the impact pulses' force vectors at times t (zero outside each pulse), (n, 3)."""
    out = np.zeros((t.size, 3))
    for times, force in pulses.values():
        inside = (t >= times[0]) & (t <= times[-1])
        if inside.any():
            for i in range(3):
                out[inside, i] += np.interp(t[inside], times, force[:, i])
    return out


def _effective_height(force: np.ndarray, moment_arm: np.ndarray, column_height: float) -> float:
    """Least-squares height z with moment = z * force, clipped to the column (m above the base)."""
    ok = np.isfinite(force) & np.isfinite(moment_arm)
    denom = float(np.sum(force[ok] ** 2))
    z = float(np.sum(force[ok] * moment_arm[ok]) / denom) if denom > 0 else 0.5 * column_height
    return min(max(z, 1e-3 * column_height), column_height)


def column_response(column, hydro: pd.DataFrame | None, pulses: dict[int, tuple[np.ndarray, np.ndarray]],
                    impact_heights_m: dict[int, float]) -> tuple[pd.DataFrame, dict[str, float]]:
    """Total load on the MDOF column and the base shear at the load cell (N).

    Hydrodynamic force: each horizontal component applied at one effective height, the
    least-squares centre of pressure over the run from the moment about the base
    (``M_y = z F_x``, ``M_x = -z F_y``), clipped to the column; its base shear is computed
    at the solver's output times and interpolated between them (the force varies over
    tenths of a second, the column's period is about 11 ms: quasi-static). Impact pulses:
    each at its own contact height; base shear on a 10 microsecond grid from 2 ms before to
    0.1 s after each impact (the ringing has decayed to about 1 % by then with the study's
    4.5 % damping at 88 Hz). y loads bend the column with its section turned by 90 degrees.
    Linear superposition: ``base_shear = hydro part + impact part``.

    Returns (table, effective hydrodynamic heights {"x": z, "y": z}).
    """
    columns = {"x": column, "y": replace(column, size_x_m=column.size_y_m, size_y_m=column.size_x_m)}
    t = _response_times(hydro, pulses)
    if t is None:
        return pd.DataFrame(columns=["time_s"]), {}
    out = pd.DataFrame({"time_s": t})
    heights: dict[str, float] = {}
    impact = pulse_sum(pulses, t)
    for i, a in enumerate("xy"):
        col = columns[a]
        hydro_force, hydro_shear = np.zeros_like(t), np.zeros_like(t)
        if hydro is not None and len(hydro) >= 2 and f"hydro_force_{a}_N" in hydro:
            heights[a], hydro_force, hydro_shear = _hydro_response(hydro, a, col, t)
        impact_shear = _impact_shear(pulses, i, col, impact_heights_m, t)
        out[f"hydro_force_{a}_N"] = hydro_force
        out[f"impact_force_{a}_N"] = impact[:, i]
        out[f"total_force_{a}_N"] = np.where(np.isnan(hydro_force), 0.0, hydro_force) + impact[:, i]
        out[f"hydro_base_shear_{a}_N"] = hydro_shear
        out[f"impact_base_shear_{a}_N"] = impact_shear
        out[f"base_shear_{a}_N"] = np.where(np.isnan(hydro_shear), 0.0, hydro_shear) + impact_shear
    return out, heights


def _response_times(hydro: pd.DataFrame | None, pulses: dict) -> np.ndarray | None:
    """The response's time axis: the solver's output times and a fine grid around each impact,
    from 0 to the last hydrodynamic sample (None when there is no load at all)."""
    axis_times = []
    if hydro is not None and len(hydro) >= 2:
        axis_times.append(hydro["time_s"].to_numpy(float))
    for times, _ in pulses.values():
        t0 = times[0]
        axis_times.append(np.arange(t0 - RESPONSE_PRE_S, t0 + RESPONSE_POST_S, RESPONSE_DT_S))
    if not axis_times:
        return None
    t = np.unique(np.concatenate(axis_times))
    t_last = float(hydro["time_s"].max()) if hydro is not None and len(hydro) else float(t[-1])
    return t[(t >= 0.0) & (t <= t_last + EPS_T)]


def _hydro_response(hydro: pd.DataFrame, a: str, col, t: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """(effective height, force, base shear) of the hydrodynamic load along axis ``a`` at times t
    (NaN outside the solver's output times)."""
    th = hydro["time_s"].to_numpy(float)
    fh = hydro[f"hydro_force_{a}_N"].to_numpy(float)
    other = "y" if a == "x" else "x"
    sign = 1.0 if a == "x" else -1.0
    if f"hydro_moment_{other}_Nm" in hydro:
        arm = sign * hydro[f"hydro_moment_{other}_Nm"].to_numpy(float)
        z = _effective_height(fh, arm, col.height_m)
    else:
        z = 0.5 * col.height_m
    hydro_shear = np.zeros_like(t)
    ok = np.isfinite(fh)
    if ok.sum() >= 2 and np.any(fh[ok] != 0.0):
        ts, fs = th[ok], fh[ok]
        if ts.size > HYDRO_RESPONSE_SAMPLES:  # quasi-static: a coarser copy is enough
            grid = np.linspace(ts[0], ts[-1], HYDRO_RESPONSE_SAMPLES)
            ts, fs = grid, np.interp(grid, ts, fs)
        shear = mdof_response(Tabulated(ts, fs), col, z, ts).response_N
        hydro_shear = np.interp(t, ts, shear)
    hydro_force = np.interp(t, th, np.where(np.isfinite(fh), fh, 0.0))
    outside = (t < th[0]) | (t > th[-1])
    hydro_force[outside] = np.nan
    hydro_shear[outside] = np.nan
    return z, hydro_force, hydro_shear


def _impact_shear(pulses: dict, i: int, col, impact_heights_m: dict[int, float], t: np.ndarray) -> np.ndarray:
    """Base shear at times t from the impact pulses' component i, each at its contact height."""
    impact_shear = np.zeros_like(t)
    for event, (times, force) in pulses.items():
        if np.any(force[:, i] != 0.0):
            height = min(max(impact_heights_m.get(event, 0.5 * col.height_m), 1e-6), col.height_m)
            after = t >= times[0]
            impact_shear[after] += mdof_response(Tabulated(times, force[:, i]), col, height, t[after]).response_N
    return impact_shear
