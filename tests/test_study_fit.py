"""Each column strike's base shear fitted as the study fitted its records
(orchestrator/results/study_fit.py), on the committed tiny-1debris case with a base-shear
history written from a known half-sine: the fit recovers it at the face gauge's water level,
at the one-way flow's level without a gauge, and says so when no level is known."""
from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.mdof import mdof_response
from analytical.pulses import make_pulse
from orchestrator.results.study_fit import STUDY_FIT_COLUMNS, centre_speed
from orchestrator.results.tables import tables

DATA = Path(__file__).resolve().parent / "data" / "post"
PEAK_N, DURATION_S = 180.0, 0.0045


def _case(tmp_path: Path, height_m: float | None, gauge: bool = True, flow_level_m: float | None = None) -> Path:
    """tiny-1debris with a base-shear history of a PEAK_N, DURATION_S half-sine at ``height_m``
    (the face gauge's level at the strike when None); without its face gauge when not ``gauge``;
    the event carrying ``flow_level_m`` as the one-way transport writes it."""
    case = tmp_path / "case"
    shutil.copytree(DATA / "tiny-1debris", case)
    if not gauge:
        plan = json.loads((case / "plan.json").read_text())
        plan["gauges"] = [g for g in plan["gauges"] if g["name"] != "WG4"]
        (case / "plan.json").write_text(json.dumps(plan))
    events = json.loads((case / "contacts.json").read_text())
    events[0]["face_water_level_m"] = flow_level_m
    (case / "contacts.json").write_text(json.dumps(events))
    if height_m is None:
        height_m = float(tables(DATA / "tiny-1debris").impacts.iloc[0]["face_water_level_m"])
    data = tables(case).data
    t = np.concatenate([np.linspace(0.0, DURATION_S, 150, endpoint=False), np.arange(DURATION_S, 0.05, 1e-5)])
    shear = mdof_response(make_pulse("half-sine", PEAK_N, DURATION_S), data.column, height_m, t).response_N
    pd.DataFrame({"time_s": t, "base_shear_x_N": shear}).to_csv(case / "contacts/event0001-base-shear.csv",
                                                                 index=False)
    return case


def _check_recovered(row):
    # tolerance: 0.5 % in peak, duration and impulse, the start within 0.05 ms of the contact
    assert row["study_fit_peak_N"] == pytest.approx(PEAK_N, rel=5e-3)
    assert row["study_fit_duration_s"] == pytest.approx(DURATION_S, rel=5e-3)
    assert row["study_fit_impulse_Ns"] == pytest.approx(2 * PEAK_N * DURATION_S / math.pi, rel=5e-3)
    assert abs(row["study_fit_start_s"]) < 5e-5 and row["study_fit_nrmse"] < 0.01


def test_the_fit_loads_the_column_at_the_face_gauges_level(tmp_path):
    case = _case(tmp_path, None)
    results = tables(case)
    row = results.impacts.iloc[0]
    assert list(results.impacts.columns[-len(STUDY_FIT_COLUMNS):]) == STUDY_FIT_COLUMNS
    assert row["study_fit_height_source"] == "face gauge"
    assert row["study_fit_height_m"] == row["face_water_level_m"]  # WG4 at the strike time
    assert row["study_fit_height_m"] != pytest.approx(row["height_m"], abs=0.01)  # not the contact point
    _check_recovered(row)
    # the law's pulse stays beside the fit
    assert row["peak_force_N"] == pytest.approx(521.5553766198371)
    event = json.loads((case / "contacts.json").read_text())[0]
    assert row["impact_speed_m_s"] == pytest.approx(np.linalg.norm(event["velocity_in_m_s"]))


def test_without_a_face_gauge_the_one_way_flows_level_is_used(tmp_path):
    level = 0.15  # an elevation; the tiny case's bed is at z = 0
    case = _case(tmp_path, level, gauge=False, flow_level_m=level)
    results = tables(case)
    row = results.impacts.iloc[0]
    assert results.data.bed_z_m == 0.0
    assert row["study_fit_height_source"] == "flow at the face" and row["study_fit_height_m"] == level
    assert row["face_water_level_m"] == level
    _check_recovered(row)


def test_without_any_water_level_the_contact_height_is_used_and_said(tmp_path):
    case = _case(tmp_path, 0.1222296529318889, gauge=False)
    row = tables(case).impacts.iloc[0]
    assert row["study_fit_height_source"] == "contact height"
    assert row["study_fit_height_m"] == pytest.approx(row["height_m"])
    assert "no water level at the face known" in row["study_fit_note"]
    _check_recovered(row)


def test_a_strike_without_a_base_shear_history_is_noted():
    results = tables(DATA / "tiny-1debris")
    row = results.impacts.iloc[0]
    assert math.isnan(row["study_fit_peak_N"]) and row["study_fit_note"] == "no base-shear history"
    assert any("no base-shear history" in m for m in results.missing)


def test_the_centre_speed_of_a_one_way_event_adds_its_tangential_part():
    assert centre_speed({"velocity_in_m_s": [1.2, 0.0, 0.0], "tangential_velocity_in_m_s": 0.5}) == pytest.approx(1.3)
    assert centre_speed({"velocity_in_m_s": [0.3, 0.4, 0.0]}) == pytest.approx(0.5)
