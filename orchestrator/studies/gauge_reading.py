"""The front between WG2 and WG3 read at several rises: can the gauges' reading threshold explain the
measured front?

An arrival is the first time a gauge's level stands a given rise above its starting level
(:func:`~orchestrator.results.metrics.arrival_time`). The study gives its arrivals ("approximately
0.91 s and 1.39 s") without the rise it read them at, and a bore's toe is not a step: a higher rise
reads a later arrival, later still where the toe has stretched. So each member is read here at
:data:`RISES_M` (the post-processor's own threshold is 2 % of the impoundment depth, 8 mm at 0.40 m),
and at the one rise that puts WG2 on its measured arrival: one coefficient taken from one gauge and
checked on the other (:func:`rise_for_arrival`).

The front's shape at WG2 (:func:`front_shelf`): the study saw a step in WG2's record and puts it down
to the gate's support columns, whose cross-waves reach the gauge ahead of the bore. A step is a shelf:
from the arrival until the level first stands half Stoker's bore depth above the bed, the longest time
the level holds within :data:`SHELF_BAND_M`, and the time that rise takes.

Levels are the alpha.water integrals of ``results/gauges.csv``; a gauge's starting level is its first
sample.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.results.metrics import arrival_time

__all__ = ["RISES_M", "SHELF_BAND_M", "RiseReading", "Shelf", "front_shelf", "rise_for_arrival", "rise_reading"]

#: The rises above a gauge's starting level at which its arrival is read (m).
RISES_M = (0.002, 0.008, 0.015, 0.025, 0.04)
#: A level that stays within this band (m) is held: a shelf in the front's rise.
SHELF_BAND_M = 0.01
#: The smallest rise :func:`rise_for_arrival` tries (m): below it a level's noise is the arrival.
MIN_RISE_M = 1e-4


@dataclass(frozen=True)
class Shelf:
    """The front's rise at one gauge: from its arrival to ``until_m`` (s; nan: not within the record), and
    the longest span (s) in between that the level holds within :data:`SHELF_BAND_M`, at its mean level (m)."""

    rise_s: float
    held_s: float
    level_m: float


def front_shelf(time_s, elevation_m, arrival_s: float, until_m: float, band_m: float = SHELF_BAND_M) -> Shelf:
    """The front's rise and its longest shelf between ``arrival_s`` and the level's first reaching ``until_m``
    (the record's end when it never does). The shelf is found over the samples with a sliding window whose
    highest and lowest levels are kept in monotone queues."""
    t, e = np.asarray(time_s, dtype=float), np.asarray(elevation_m, dtype=float)
    keep = np.isfinite(t) & np.isfinite(e)
    t, e = t[keep], e[keep]
    if not math.isfinite(arrival_s) or t.size == 0:
        return Shelf(math.nan, math.nan, math.nan)
    reached = arrival_time(t, e, 0.0, until_m)
    end = reached if math.isfinite(reached) else float(t[-1])
    inside = (t >= arrival_s) & (t <= end)
    tw, ew = t[inside], e[inside]
    best, level = 0.0, math.nan
    highs: deque[int] = deque()
    lows: deque[int] = deque()
    first = 0
    for j, v in enumerate(ew):
        while highs and ew[highs[-1]] <= v:
            highs.pop()
        highs.append(j)
        while lows and ew[lows[-1]] >= v:
            lows.pop()
        lows.append(j)
        while ew[highs[0]] - ew[lows[0]] > band_m:
            first += 1
            if highs[0] < first:
                highs.popleft()
            if lows[0] < first:
                lows.popleft()
        if tw[j] - tw[first] > best:
            best, level = float(tw[j] - tw[first]), float(np.mean(ew[first:j + 1]))
    return Shelf(float(reached - arrival_s) if math.isfinite(reached) else math.nan, best, level)


@dataclass(frozen=True)
class RiseReading:
    """One member's WG2 and WG3 arrivals (s; nan: never) at each of ``rises_m``, and at the rise fitted to
    WG2's measured arrival (nan: no rise in the record reaches it)."""

    rises_m: tuple[float, ...]
    wg2_s: tuple[float, ...]
    wg3_s: tuple[float, ...]
    distance_m: float
    fitted_rise_m: float
    wg2_at_fitted_s: float
    wg3_at_fitted_s: float
    wg2_shelf: Shelf | None = None

    def speeds_m_s(self) -> tuple[float, ...]:
        """The front's speed between the gauges at each rise (m/s)."""
        return tuple(_speed(self.distance_m, b - a) for a, b in zip(self.wg2_s, self.wg3_s))

    @property
    def speed_at_fitted_m_s(self) -> float:
        return _speed(self.distance_m, self.wg3_at_fitted_s - self.wg2_at_fitted_s)


def _speed(distance_m: float, time_s: float) -> float:
    return distance_m / time_s if math.isfinite(time_s) and time_s > 0 else math.nan


def rise_for_arrival(time_s, elevation_m, target_s: float) -> float:
    """The rise (m) above the first sample at which the level's arrival is ``target_s``; nan when even
    :data:`MIN_RISE_M` arrives after it or the highest level before it.

    The arrival grows with the rise, so the rise is found by bisection. Where the level steps (it rises,
    holds or dips, and rises again) the arrival jumps, and the rise found is the one at the jump: the
    arrival there (:func:`~orchestrator.results.metrics.arrival_time`) need not be ``target_s``.
    """
    t, e = np.asarray(time_s, dtype=float), np.asarray(elevation_m, dtype=float)
    keep = np.isfinite(t) & np.isfinite(e)
    t, e = t[keep], e[keep]
    if e.size < 2:
        return math.nan
    start = float(e[0])
    lo, hi = MIN_RISE_M, float(np.max(e)) - start

    def arrives(rise: float) -> float:
        return arrival_time(t, e, start, rise)

    if hi <= lo or arrives(lo) > target_s or not arrives(hi * (1 - 1e-9)) >= target_s:
        return math.nan
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if arrives(mid) < target_s:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def rise_reading(case: str | Path, wg2: tuple[float, float], wg3: tuple[float, float],
                 rises_m: tuple[float, ...] = RISES_M, shelf: tuple[float, float] | None = None) -> RiseReading | None:
    """WG2 and WG3 of one run read at ``rises_m`` and at the rise fitted to WG2's measured arrival.

    ``wg2``, ``wg3``: (x m, measured arrival s). ``shelf``: (WG2's arrival s, the level m that ends its
    rise) to read WG2's shelf (:func:`front_shelf`). None when ``results/gauges.csv`` or either gauge's
    column is missing.
    """
    table = Path(case) / "results" / "gauges.csv"
    if not table.is_file():
        return None
    data = pd.read_csv(table)
    cols = ("WG2_elevation_m", "WG3_elevation_m")
    if "time_s" not in data or any(c not in data for c in cols):
        return None
    t = data["time_s"].to_numpy(dtype=float)
    e2, e3 = (data[c].to_numpy(dtype=float) for c in cols)
    s2, s3 = float(e2[0]), float(e3[0])
    rise = rise_for_arrival(t, e2, wg2[1])
    fitted = (arrival_time(t, e2, s2, rise), arrival_time(t, e3, s3, rise)) if math.isfinite(rise) else (
        math.nan, math.nan)
    return RiseReading(
        rises_m=tuple(rises_m), wg2_s=tuple(arrival_time(t, e2, s2, r) for r in rises_m),
        wg3_s=tuple(arrival_time(t, e3, s3, r) for r in rises_m), distance_m=wg3[0] - wg2[0],
        fitted_rise_m=rise, wg2_at_fitted_s=fitted[0], wg3_at_fitted_s=fitted[1],
        wg2_shelf=None if shelf is None else front_shelf(t, e2, shelf[0], shelf[1]))
