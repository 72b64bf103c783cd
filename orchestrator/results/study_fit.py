"""Every column strike's base shear fitted as the study fitted its records, beside the law's pulse.

The contact law gives each column strike a pulse at the contact point
(``peak_force_N``, ``duration_s``, ``impulse_Ns`` of impacts.csv) and the column's base shear
under it (``contacts/eventNNNN-base-shear.csv``). The study never saw its pulses: it fitted a
half-sine on its MDOF column, loaded at the water level at the column's face, to each measured
base-shear record (its section 3.2.2), and Table 2 is the statistics of those fits. So
each strike's base-shear history is fitted the same way
(:func:`analytical.study_comparison.fit_like_the_study`) and the fitted pulse is what is set
against Table 2 (:data:`STUDY_FIT_COLUMNS`):

* the history fitted is the base shear along the strike (the horizontal load direction; the
  along-flume shear for a strike on the upstream face);
* the load height is the water level at the column's face at the strike time: the face gauge's
  (``face_water_level_m``, :func:`orchestrator.results.impact_table.impact_context`) when the
  scene has one, else the level the one-way transport read from its flow record beside the
  face (the event's ``face_water_level_m``, an elevation: the bed's is taken off), else the
  contact height, and ``study_fit_height_source`` says which;
* ``study_fit_start_s`` is the fitted pulse's start from the first contact (negative: the fit
  put the pulse before the contact), ``study_fit_nrmse`` its residual over the history's peak.
* the fit's column is the column the strike's base shear was computed on: a record and a model
  that ring at different frequencies do not fit (the study's Table 1 pulse struck on the 70 Hz
  column and fitted on the 88.4 Hz rigid-base one reads 129 N over 12.4 ms, the reverse 118 N over
  5.2 ms). The study's column rang at 70 Hz and Table 1 favours a 70 Hz MDOF model
  (docs/fitting.md), so a comparison with Table 2 wants the scene's ``column.base: calibrated``.

``impact_speed_m_s`` is the body's centre's speed at the strike: the study measured the
debris's speed, not its part along the contact normal (``impact_velocity_m_s``).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from analytical.study_comparison import StudyComparison, compare_table, fit_like_the_study, strike_component

__all__ = ["COMPARISON_ROWS", "HEIGHT_SOURCES", "STUDY_FIT_COLUMNS", "add_study_fits", "base_shear_path",
           "centre_speed", "compare_strikes", "read_base_shear", "study_fit_figures"]

STUDY_FIT_COLUMNS = [
    "impact_speed_m_s", "study_fit_peak_N", "study_fit_duration_s", "study_fit_impulse_Ns", "study_fit_start_s",
    "study_fit_height_m", "study_fit_height_source", "study_fit_rmse_N", "study_fit_nrmse", "study_fit_note",
]
"""Columns post-processing adds to impacts.csv after the law's (module notes); NaN and an empty
source where a strike has no fit, and the reason in ``study_fit_note``."""

COMPARISON_ROWS = [
    ("impact_speed_m_s", "speed_m_s", "speed of the centre (m/s)"),
    ("impact_velocity_m_s", "normal_speed_m_s", "its part along the contact normal (m/s)"),
    ("study_fit_peak_N", "peak_force_N", "study-fit peak force (N)"),
    ("study_fit_duration_s", "duration_s", "study-fit duration (s)"),
    ("study_fit_impulse_Ns", "impulse_Ns", "study-fit impulse (N s)"),
]
"""The like-for-like comparison's rows: (column of impacts.csv and ensemble.csv, quantity of
:data:`analytical.study_comparison.STUDY_FIGURES`, label). The speeds are set against the
study's measured speed (1.60 +- 0.13 m/s), the study-fit pulse against Table 2's MDOF row."""

#: Where a fit's load height came from, best first.
HEIGHT_SOURCES = ("face gauge", "flow at the face", "contact height", "set by --study-fit-height")


def base_shear_path(case: Path, force_history: str) -> Path:
    """The base-shear history written beside an event's force history
    (``contacts/eventNNNN-force.csv`` -> ``contacts/eventNNNN-base-shear.csv``)."""
    return Path(case) / str(force_history).replace("-force.csv", "-base-shear.csv")


def read_base_shear(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None] | None:
    """(time_s from first contact, base_shear_x_N, base_shear_y_N or None) of a base-shear
    history; None when the file is missing or too short."""
    if not Path(path).is_file():
        return None
    frame = pd.read_csv(path)
    if "time_s" not in frame or "base_shear_x_N" not in frame or len(frame) < 2:
        return None
    y = frame["base_shear_y_N"].to_numpy(float) if "base_shear_y_N" in frame else None
    return frame["time_s"].to_numpy(float), frame["base_shear_x_N"].to_numpy(float), y


def centre_speed(event: dict) -> float:
    """The body's centre's speed at a strike (m/s): ``|velocity_in_m_s|``; the one-way transport
    writes only the normal part there and the rest as ``tangential_velocity_in_m_s``."""
    v = np.asarray(event.get("velocity_in_m_s") or (math.nan,) * 3, dtype=float)
    speed = float(np.linalg.norm(v))
    tangential = event.get("tangential_velocity_in_m_s")
    return math.hypot(speed, float(tangential)) if tangential is not None else speed


def study_fit_figures(time_s, shear_x_N, shear_y_N, normal, column, height_m: float, source: str) -> dict:
    """The :data:`STUDY_FIT_COLUMNS` (but the speed) of one strike's base-shear history, fitted
    at ``height_m`` (m above the column's base) from ``source``; a history the fit cannot take
    gives NaN figures and the reason."""
    out = {"study_fit_peak_N": math.nan, "study_fit_duration_s": math.nan, "study_fit_impulse_Ns": math.nan,
           "study_fit_start_s": math.nan, "study_fit_height_m": float(height_m), "study_fit_height_source": source,
           "study_fit_rmse_N": math.nan, "study_fit_nrmse": math.nan, "study_fit_note": ""}
    if source == HEIGHT_SOURCES[2]:
        out["study_fit_note"] = "no water level at the face known: loaded at the contact height"
    try:
        fit = fit_like_the_study(time_s, strike_component(shear_x_N, shear_y_N, normal), height_m, column)
    except InputError as err:
        out["study_fit_note"] = f"no fit: {err.rule}"
        return out
    out.update(study_fit_peak_N=fit.peak_N, study_fit_duration_s=fit.duration_s, study_fit_impulse_Ns=fit.impulse_Ns,
               study_fit_start_s=fit.start_s, study_fit_rmse_N=fit.rmse_N, study_fit_nrmse=fit.nrmse)
    return out


def _height(row, event: dict, bed_z_m: float) -> tuple[float, str]:
    """The strike's load height above the bed and where it came from (module notes)."""
    gauge = float(row.face_water_level_m) if row.face_water_level_m is not None else math.nan
    if math.isfinite(gauge):
        return gauge, HEIGHT_SOURCES[0]
    flow = event.get("face_water_level_m")
    if flow is not None and math.isfinite(float(flow)):
        return float(flow) - bed_z_m, HEIGHT_SOURCES[1]
    return float(row.height_m), HEIGHT_SOURCES[2]


def add_study_fits(data, impacts: pd.DataFrame, events: list[dict], missing: list[str]) -> pd.DataFrame:
    """impacts.csv with :data:`STUDY_FIT_COLUMNS` after its own: each column strike's base shear
    fitted at the water level at the face (module notes). ``data`` is the case's
    :class:`~orchestrator.results.readers.CaseData`; a strike without a base-shear history or a
    fit goes to ``missing``; where the water level comes from the flow, not a face gauge,
    ``face_water_level_m`` takes it too."""
    out = impacts.copy()
    for name in STUDY_FIT_COLUMNS:
        out[name] = "" if name in ("study_fit_height_source", "study_fit_note") else math.nan
    if out.empty:
        return out
    by_number = {int(e.get("event", 0)): e for e in events}
    for i, row in zip(out.index, out.itertuples()):
        event = by_number.get(int(row.event), {})
        out.at[i, "impact_speed_m_s"] = centre_speed(event)
        if row.kind != "column" or data.column is None:
            continue
        history = read_base_shear(base_shear_path(data.case, event.get("force_history", ""))) \
            if event.get("force_history") else None
        if history is None:
            out.at[i, "study_fit_note"] = "no base-shear history"
            missing.append(f"impact event {row.event}: no base-shear history under contacts/: no study fit")
            continue
        height, source = _height(row, event, data.bed_z_m)
        if source == HEIGHT_SOURCES[1]:
            out.at[i, "face_water_level_m"] = height
        normal = (row.normal_x, row.normal_y, row.normal_z)
        for name, value in study_fit_figures(*history, normal, data.column, height, source).items():
            out.at[i, name] = value
        if not math.isfinite(out.at[i, "study_fit_peak_N"]):
            missing.append(f"impact event {row.event}: {out.at[i, 'study_fit_note']}")
    return out


def compare_strikes(frame: pd.DataFrame) -> dict[str, StudyComparison]:
    """The :data:`COMPARISON_ROWS` of a table of strikes (one strike a row) against the study's
    figures (:func:`analytical.study_comparison.compare_with_study`), by column name."""
    samples = {quantity: pd.to_numeric(frame[column], errors="coerce").to_numpy(float) if column in frame
               else np.array([]) for column, quantity, _ in COMPARISON_ROWS}
    table = compare_table(samples)
    return {column: table[quantity] for column, quantity, _ in COMPARISON_ROWS}
