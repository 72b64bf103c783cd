"""The water at the column's face and the front's speed along the centreline, read from a run's gauges.

The face (``FaceReading``): the face gauge's (WG4, 1 cm upstream of the column's upstream face)
level over time, two ways: its elevation (the alpha.water integral along its line,
``results/gauges.csv``) and its highest wet point (the highest sample on its line with alpha.water
above 0.5, from the raw profiles in ``postProcessing/gauges/``; a sheet of water thrown up the face
counts there but hardly in the integral). Each is read at its peak over the run and at
:data:`AFTER_ARRIVAL_S` after the front reached the face (the gauge's arrival), to set beside the
study's load points: the water surface at the face at impact (``STUDY_IMPACT_HEIGHTS_M``).

The reaches (``reach_speeds``): the centreline gauges (y = 0) between the gate and the face other
than the study's (their arrivals have their own columns), in x order; the front's speed over each
successive reach is its length over the difference of the arrivals. An arrival is read from samples
``outputs.probe_interval_s`` (dt) apart, so it is taken as uncertain by dt / 2 and a reach's time
by dt; its speed v over a time T by v dt / T. A reach speeds up when it is faster than the reach
before by more than the two speeds' uncertainties together (:func:`reach_verdict`; without a probe
interval, the gauges sampled every time step, by any margin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.case.folder import CaseFolder
from orchestrator.results.readers import read_gauge_samples

__all__ = ["AFTER_ARRIVAL_S", "WET_ALPHA", "FaceReading", "MemberFlow", "Reach", "face_reading",
           "face_series", "highest_wet_points", "member_flow", "reach_speeds", "reach_verdict", "value_at"]

#: Times after the front reached the face at which the face's level is read (s).
AFTER_ARRIVAL_S = (0.1, 0.3)
#: A sample is wet above this water fraction.
WET_ALPHA = 0.5


@dataclass(frozen=True)
class FaceReading:
    """The face gauge's elevation and highest wet point (m above the bed): peak, time of peak and the
    values :data:`AFTER_ARRIVAL_S` after the front reached the face (nan: not in the record)."""

    elevation_peak_m: float
    elevation_peak_s: float
    elevation_after_m: tuple[float, ...]
    wet_peak_m: float
    wet_peak_s: float
    wet_after_m: tuple[float, ...]
    record_end_s: float


@dataclass(frozen=True)
class Reach:
    """The front between two centreline gauges: x from, x to (m), arrivals (s), speed and its uncertainty (m/s)."""

    x0_m: float
    x1_m: float
    t0_s: float
    t1_s: float
    speed_m_s: float
    uncertainty_m_s: float


def value_at(t: np.ndarray, v: np.ndarray, when_s: float) -> float:
    """``v`` at ``when_s``, linear between the samples around it; nan outside the record or where nan."""
    t, v = np.asarray(t, dtype=float), np.asarray(v, dtype=float)
    keep = np.isfinite(t) & np.isfinite(v)
    t, v = t[keep], v[keep]
    if not math.isfinite(when_s) or t.size == 0 or when_s < t[0] or when_s > t[-1]:
        return math.nan
    return float(np.interp(when_s, t, v))


def highest_wet_points(case: str | Path, gauge: str) -> tuple[np.ndarray, np.ndarray]:
    """(times, the highest z with alpha.water > :data:`WET_ALPHA` on the gauge's line: 0 when none is wet)
    from the raw profiles; z is above the bed downstream of the gate (z = 0, where every line starts)."""
    records = read_gauge_samples(case).get(gauge, [])
    times, tops = [], []
    for t, z, a in records:
        wet = z[a > WET_ALPHA] if z.size else z
        times.append(t)
        tops.append(float(wet.max()) if wet.size else 0.0)
    return np.array(times, dtype=float), np.array(tops, dtype=float)


def _peak(t: np.ndarray, v: np.ndarray) -> tuple[float, float]:
    finite = np.isfinite(v)
    if not finite.any():
        return math.nan, math.nan
    i = int(np.nanargmax(np.where(finite, v, -np.inf)))
    return float(v[i]), float(t[i])


def face_series(case: str | Path, gauge: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(times, elevations) from ``results/gauges.csv`` and (times, highest wet points) from the raw
    profiles of the gauge in a post-processed case; empty arrays where the case keeps neither."""
    case = Path(case)
    table = case / "results" / "gauges.csv"
    column = f"{gauge}_elevation_m"
    t_e = v_e = np.empty(0)
    if table.is_file():
        frame = pd.read_csv(table)
        if column in frame:
            t_e, v_e = frame["time_s"].to_numpy(float), frame[column].to_numpy(float)
    return (t_e, v_e, *highest_wet_points(case, gauge))


def face_reading(series: tuple[np.ndarray, ...], arrival_s: float) -> FaceReading | None:
    """The readings of :func:`face_series`'s records, the front having reached the face at ``arrival_s``;
    None when both records are empty."""
    t_e, v_e, t_w, v_w = series
    if t_e.size == 0 and t_w.size == 0:
        return None
    (pe, pe_t), (pw, pw_t) = _peak(t_e, v_e), _peak(t_w, v_w)
    end = max((float(x[-1]) for x in (t_e, t_w) if x.size), default=math.nan)
    return FaceReading(pe, pe_t, tuple(value_at(t_e, v_e, arrival_s + d) for d in AFTER_ARRIVAL_S),
                       pw, pw_t, tuple(value_at(t_w, v_w, arrival_s + d) for d in AFTER_ARRIVAL_S), end)


def reach_speeds(summary: pd.DataFrame, face_x_m: float, probe_interval_s: float | None,
                 skip: tuple[str, ...] = ()) -> list[Reach]:
    """The front's speed over each reach between successive centreline gauges downstream of the gate and
    upstream of the face (``gauge_summary.csv`` rows: gauge, x_m, y_m, arrival_s), the gauges in ``skip``
    left out; the uncertainty nan without a probe interval."""
    if not {"gauge", "x_m", "y_m", "arrival_s"} <= set(summary.columns):
        return []
    rows = summary[(summary["y_m"].abs() < 1e-9) & (summary["x_m"] > 0) & (summary["x_m"] < face_x_m)
                   & ~summary["gauge"].isin(skip)].sort_values("x_m")
    x, t = rows["x_m"].to_numpy(float), rows["arrival_s"].to_numpy(float)
    dt = math.nan if probe_interval_s is None else float(probe_interval_s)
    reaches = []
    for i in range(len(x) - 1):
        time = t[i + 1] - t[i]
        ok = math.isfinite(time) and time > 0
        speed = (x[i + 1] - x[i]) / time if ok else math.nan
        reaches.append(Reach(float(x[i]), float(x[i + 1]), float(t[i]), float(t[i + 1]), speed,
                             speed * dt / time if ok else math.nan))
    return reaches


def reach_verdict(reaches: list[Reach]) -> str:
    """"falls or holds", "speeds up (x0-x1 m, ...)" naming each reach faster than the one before by more
    than both speeds' uncertainties, or "-" with fewer than two reaches read."""
    read = [r for r in reaches if math.isfinite(r.speed_m_s)]
    if len(read) < 2:
        return "-"
    faster = []
    for before, r in zip(read, read[1:]):
        margin = before.uncertainty_m_s + r.uncertainty_m_s
        if not math.isfinite(margin):
            margin = 0.0
        if r.speed_m_s - before.speed_m_s > margin:
            faster.append(f"{r.x0_m:g}-{r.x1_m:g} m")
    return f"speeds up ({', '.join(faster)})" if faster else "falls or holds"


@dataclass(frozen=True)
class MemberFlow:
    """A member's face reading (None: no gauge record) and :func:`face_series` records, its centreline
    reaches, its gauges' sampling interval (s; None: every time step), its cell count (0: no plan.json)."""

    face: FaceReading | None
    series: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    reaches: tuple[Reach, ...]
    probe_interval_s: float | None
    cells: int


def member_flow(case: str | Path, face_gauge: str, face_x_m: float, face_s: float,
                skip: tuple[str, ...] = ()) -> MemberFlow:
    """:func:`face_reading` and :func:`reach_speeds` of a post-processed member (its results/, scene.yaml
    and plan.json), the gauges in ``skip`` left out of the reaches."""
    folder = CaseFolder(case)
    case = folder.path
    interval = folder.scene().outputs.probe_interval_s
    interval = None if interval is None else float(interval)
    summary = pd.read_csv(case / "results" / "gauge_summary.csv")
    plan = folder.model_plan()
    cells = int(plan.cell_count) if plan is not None else 0
    series = face_series(case, face_gauge)
    return MemberFlow(face_reading(series, face_s), series, tuple(reach_speeds(summary, face_x_m, interval, skip)),
                      interval, cells)
