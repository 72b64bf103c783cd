"""The gauge tables of a run: the water elevation at every gauge over time, and one summary
row per gauge (position, initial level, bore arrival, peak).

The elevations come from the gauges' ``sets`` samples through
:func:`orchestrator.results.metrics.gauge_elevation`, the arrival through
:func:`~orchestrator.results.metrics.arrival_time`; this module supplies what those need from
the case: the gauge's line and position (plan.json), the mesh's cell faces along it, and the
level before the bore arrived.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd

from orchestrator.plan.model import GaugePlan
from orchestrator.results.metrics import (
    ARRIVAL_FRACTION,
    ARRIVAL_THRESHOLD_FALLBACK_M,
    MIN_GAUGE_COVERAGE,
    arrival_time,
    gauge_elevation,
)
from orchestrator.results.readers import CaseData, read_gauge_samples

__all__ = ["GAUGE_SUMMARY_COLUMNS", "gauge_tables"]

#: Columns of gauge_summary.csv, in order.
GAUGE_SUMMARY_COLUMNS = ["gauge", "x_m", "y_m", "initial_level_m", "initial_level_from", "threshold_m", "arrival_s",
                         "peak_elevation_m", "time_of_peak_s", "samples", "obstructed_samples"]


def gauge_tables(data: CaseData, threshold_m: float | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(gauges.csv: time_s and one ``<gauge>_elevation_m`` column per gauge, gauge_summary.csv).

    threshold_m: the rise above the initial level that marks the bore's arrival (default
    :data:`~orchestrator.results.metrics.ARRIVAL_FRACTION` of the impoundment depth).
    """
    samples = read_gauge_samples(data.case)
    plan_gauges = {g.name: g for g in data.plan.gauges} if data.plan else {}
    faces = _gauge_cell_faces(data)
    threshold = threshold_m
    if threshold is None:
        threshold = ARRIVAL_FRACTION * data.depth_m if data.depth_m else ARRIVAL_THRESHOLD_FALLBACK_M
    names = sorted(samples, key=lambda n: (list(plan_gauges).index(n) if n in plan_gauges else 1e9, n))
    series: dict[str, pd.Series] = {}
    rows = []
    for name in names:
        records = samples[name]
        g = plan_gauges.get(name)
        t, e, obstructed = _elevations(records, data.bed_z_m, g, faces)
        series[name] = pd.Series(e, index=t)
        rows.append(_summary_row(data, name, g, t, e, threshold) | {
            "samples": len(records), "obstructed_samples": obstructed})
    if series:
        wide = pd.DataFrame({f"{n}_elevation_m": s for n, s in series.items()})
        wide.index.name = "time_s"
        wide = wide.sort_index().reset_index()
    else:
        wide = pd.DataFrame(columns=["time_s"])
    return wide, pd.DataFrame(rows, columns=GAUGE_SUMMARY_COLUMNS)


def _elevations(records, bed: float, gauge: GaugePlan | None, faces) -> tuple[np.ndarray, np.ndarray, int]:
    """(times, elevations, obstructed samples) of one gauge's samples; NaN where obstructed."""
    diffs = [np.diff(np.sort(z)) for _, z, _ in records if z.size > 1]
    positive = np.concatenate(diffs) if diffs else np.empty(0)
    positive = positive[positive > 0]
    spacing = float(positive.min()) if positive.size else None
    top = float(gauge.z_top if gauge else max((float(z.max()) for _, z, _ in records if z.size), default=bed))
    values, obstructed = [], 0
    for _, z, a in records:
        h, coverage = gauge_elevation(z, a, bed, top, spacing, faces)
        if coverage < MIN_GAUGE_COVERAGE:
            h = float("nan")
            obstructed += 1
        values.append(h)
    return np.array([r[0] for r in records]), np.array(values), obstructed


def _summary_row(data: CaseData, name: str, gauge: GaugePlan | None, t: np.ndarray, e: np.ndarray, threshold: float) -> dict:
    """A gauge's position, initial level, arrival and peak."""
    x, y = (gauge.x, gauge.y) if gauge else (float("nan"), float("nan"))
    finite = np.isfinite(e)
    first = float(e[finite][0]) if finite.any() else float("nan")
    t_first = float(t[finite][0]) if finite.any() else float("nan")
    initial, source = _initial_level(data, float(x) if math.isfinite(x) else 1.0, t_first, first)
    i_peak = int(np.nanargmax(e)) if finite.any() else None
    return {
        "gauge": name, "x_m": x, "y_m": y, "initial_level_m": initial, "initial_level_from": source,
        "threshold_m": threshold,
        "arrival_s": arrival_time(t, e, initial, threshold),
        "peak_elevation_m": float(e[i_peak]) if i_peak is not None else float("nan"),
        "time_of_peak_s": float(t[i_peak]) if i_peak is not None else float("nan"),
    }


def _initial_level(data: CaseData, x_m: float, t_first: float, first: float) -> tuple[float, str]:
    """The gauge's level before the bore, and where it came from.

    The first sample, when it was taken before any disturbance could reach the gauge (the
    dry-bed front runs at 2 sqrt(g h0), the negative wave upstream at sqrt(g h0)): this is
    the still water as the mesh represents it. Otherwise the scene's still water there.
    """
    scene = data.scene
    if scene is None:
        return (first, "first sample") if math.isfinite(first) else (0.0, "none (no scene, no sample)")
    c0 = math.sqrt(scene.fluids.gravity_m_s2 * scene.reservoir.depth_m)
    reach_s = (x_m / (2.0 * c0)) if x_m >= 0 else (-x_m / c0)
    if math.isfinite(first) and math.isfinite(t_first) and t_first < reach_s:
        return first, "first sample"
    if -scene.reservoir.length_m <= x_m < 0.0:
        return float(scene.reservoir.depth_m), "scene (impoundment)"
    return float(scene.bed.wet_depth_m), "scene (bed)"


def _gauge_cell_faces(data: CaseData) -> np.ndarray | None:
    """The background mesh's z planes (every cell face a vertical gauge line crosses) when the
    gauges sample cell values (``interpolationScheme cell`` in system/controlDict); None when
    they interpolate (cellPoint: cases rendered before the gauges sampled cells) or the plan
    is missing."""
    try:
        control = (data.case / "system" / "controlDict").read_text(errors="replace")
    except OSError:
        return None
    scheme = re.search(r"\bgauges\s*\{[^}]*?interpolationScheme\s+(\w+)\s*;", control)
    segments = data.plan.background.z if data.plan else ()
    if not scheme or scheme.group(1) != "cell" or not segments:
        return None
    faces = [float(segments[0].start_m)]
    for seg in segments:  # blockMesh's simpleGrading: geometric cells, last over first = grading
        a, b, n, r = float(seg.start_m), float(seg.end_m), int(seg.cells), float(seg.grading)
        sizes = np.ones(n) if n == 1 or abs(r - 1.0) < 1e-12 else (r ** (1.0 / (n - 1))) ** np.arange(n)
        faces += list(a + np.cumsum(sizes) / sizes.sum() * (b - a))
    return np.array(faces)
