"""The spreading definitions against closed forms, and the spreading page on a small synthetic
ensemble (orchestrator/results/spreading.py, orchestrator/studies/spreading.py)."""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pandas as pd
import pytest

from orchestrator.core.errors import InputError
from orchestrator.results.spreading import (GOSEBERG_2016_BOXES, angle_at_station, box_stats, displacement_angle,
                                            flow_direction, lateral_spread, station_crossing, track_angles)
from orchestrator.studies.spreading import read_ensemble, spreading_study, stations
from orchestrator.scene.scenefile import load_scene
from tests.conftest import ROOT, run_cli


def _straight(angle_deg: float, x0: float = 3.2, y0: float = 0.0, length: float = 1.8, n: int = 37):
    """A straight track from (x0, y0) at ``angle_deg``, unevenly sampled along x."""
    s = np.sort(np.concatenate([[0.0, length], np.random.default_rng(1).uniform(0.0, length, n - 2)]))
    x = x0 + s
    return x, y0 + s * math.tan(math.radians(angle_deg))


@pytest.mark.parametrize("angle", [-22.5, -7.0, 0.0, 3.3, 16.8])
def test_straight_track_angle_at_every_station_is_its_heading(angle):
    x, y = _straight(angle, y0=0.1)
    for xs in (3.6, 4.1, 4.6):
        assert angle_at_station(x, y, xs) == pytest.approx(angle, abs=1e-9)
        assert station_crossing(x, y, xs) == pytest.approx(0.1 + (xs - 3.2) * math.tan(math.radians(angle)))
    out = track_angles(x, y, [4.6])
    assert out["angle_at_4600mm"] == pytest.approx(angle, abs=1e-9)
    assert out["angle_max_deg"] == pytest.approx(angle, abs=1e-9)
    assert out["angle_rest_deg"] == pytest.approx(angle, abs=1e-9)


def test_station_crossing_takes_the_first_crossing_and_interpolates():
    # out to x = 2, back to 0.5, out again: the first crossing of x = 1.5 is on the way out
    x = np.array([0.0, 1.0, 2.0, 0.5, 3.0])
    y = np.array([0.0, 0.2, 0.4, 9.0, 9.0])
    assert station_crossing(x, y, 1.5) == pytest.approx(0.3)
    assert math.isnan(station_crossing(x, y, 3.5))  # never reached
    assert station_crossing(x, y, -1.0) == 0.0  # started past it


def test_no_angle_without_enough_run_or_without_a_crossing():
    x, y = _straight(10.0)
    assert math.isnan(angle_at_station(x, y, 3.3))  # 0.1 m from the start, under 0.25 m
    assert math.isnan(angle_at_station(x, y, 5.5))  # the track ends at 5.0
    assert math.isnan(displacement_angle(0.0, 0.0, 0.1, 0.5))
    assert displacement_angle(1.0, 1.0, 2.0, 0.0) == pytest.approx(-45.0)


def test_max_and_rest_angles_of_a_track_deflected_at_its_end():
    # straight on to (5, 0), then pushed sideways and back to (4.5, 1): max at the farthest x, rest at the end
    x = np.array([3.0, 4.0, 5.0, 4.5])
    y = np.array([0.0, 0.0, 0.0, 1.0])
    out = track_angles(x, y, [4.0])
    assert out["angle_max_deg"] == pytest.approx(0.0)
    assert out["angle_rest_deg"] == pytest.approx(math.degrees(math.atan2(1.0, 1.5)))
    assert (out["x_max_m"], out["x_rest_m"]) == (5.0, 4.5)


def test_symmetric_fan_closed_forms():
    # 4k+1 tracks at evenly spaced angles in [-beta, beta]: median 0, quartiles at +-beta/2 exactly
    beta, k = 12.0, 10
    angles = np.linspace(-beta, beta, 4 * k + 1)
    xs, run = 4.6, 1.4
    tracks = [_straight(a, x0=xs - run) for a in angles]
    measured = np.array([angle_at_station(x, y, xs) for x, y in tracks])
    stats = box_stats(measured)
    assert stats["med"] == pytest.approx(0.0, abs=1e-9)
    assert (stats["q1"], stats["q3"]) == (pytest.approx(-beta / 2), pytest.approx(beta / 2))
    assert (stats["whislo"], stats["whishi"]) == (pytest.approx(-beta), pytest.approx(beta))
    assert stats["n"] == angles.size and stats["outliers"] == 0
    y_at = np.array([station_crossing(x, y, xs) for x, y in tracks])
    spread = lateral_spread(np.zeros(angles.size), y_at, np.full(angles.size, xs - run), xs)
    dy = run * np.tan(np.radians(angles))
    assert spread["tracks"] == angles.size
    assert spread["mean_dy_m"] == pytest.approx(0.0, abs=1e-12)
    assert spread["std_dy_m"] == pytest.approx(dy.std(ddof=1))
    assert spread["iqr_dy_m"] == pytest.approx(2 * run * math.tan(math.radians(beta / 2)))
    assert spread["std_over_run"] == pytest.approx(dy.std(ddof=1) / run)


def test_lateral_spread_leaves_out_tracks_that_did_not_reach_the_station():
    spread = lateral_spread([0.0, 0.1, 0.2], [0.05, math.nan, 0.25], [3.0, 3.0, 3.5], 4.0)
    assert spread["tracks"] == 2
    assert spread["std_dy_m"] == pytest.approx(0.0)
    assert spread["mean_run_m"] == pytest.approx(0.75)
    none = lateral_spread([0.0], [math.nan], [3.0], 4.0)
    assert none["tracks"] == 0 and math.isnan(none["std_dy_m"])


def test_box_whiskers_stop_at_the_last_value_within_one_and_a_half_iqr():
    values = [0.0, 1.0, 2.0, 3.0, 4.0, 40.0]  # q1 1.25, q3 3.75, IQR 2.5: 40 is out, 4 is the top whisker
    stats = box_stats(values + [math.nan])
    assert (stats["q1"], stats["q3"]) == (pytest.approx(1.25), pytest.approx(3.75))
    assert stats["whishi"] == 4.0 and stats["whislo"] == 0.0 and stats["outliers"] == 1 and stats["n"] == 6


def test_measured_boxes_are_ordered_as_boxes():
    for name, b in GOSEBERG_2016_BOXES.items():
        assert b["whislo"] < b["q1"] <= b["med"] <= b["q3"] < b["whishi"], name


def test_flow_direction_of_a_uniform_flow_at_a_known_angle():
    # a uniform flow at 3 deg to the axis, 0.2 m deep over half the record: every wet sample at 3 deg
    t, x, y, z = np.arange(4.0), np.linspace(0.0, 2.0, 11), np.linspace(-0.5, 0.5, 11), np.array([0.01, 0.03, 0.1])
    eta = np.zeros((t.size, x.size, y.size))
    eta[:, :6, :] = 0.2  # wet for x <= 1.0
    u, a = 1.5, math.radians(3.0)
    vel = np.zeros((t.size, x.size, y.size, z.size, 3))
    vel[..., 0], vel[..., 1] = u * math.cos(a), u * math.sin(a)
    out = flow_direction(t, x, y, z, 0.0, eta, vel, (0.0, 2.0), (-0.25, 0.25), 0.03)
    assert out["samples"] == t.size * 6 * 5  # x <= 1.0 wet (6 points), |y| <= 0.25 (5 points)
    assert out["level_m"] == pytest.approx(0.03)
    assert out["mean_u_m_s"] == pytest.approx(u * math.cos(a))
    assert out["rms_v_over_u"] == pytest.approx(math.tan(a))
    assert out["angle_p5_deg"] == pytest.approx(3.0) and out["angle_p95_deg"] == pytest.approx(3.0)
    dry = flow_direction(t, x, y, z, 0.0, eta, vel, (1.5, 2.0), (-0.2, 0.2), 0.03)
    assert dry["samples"] == 0 and math.isnan(dry["rms_v_over_u"])


def test_stations_stop_short_of_the_column_face():
    scene = load_scene(ROOT / "cases" / "1debris.yaml")
    face = scene.column.x_m - scene.column.size_x_m / 2
    assert stations(scene) == pytest.approx([face - 1.3, face - 0.8, face - 0.3])


# --------------------------------------------------------------------------- the page
def _ensemble(folder, angles_deg, yaw_per_angle: float = 0.5):
    """A synthetic ensemble of the 1-debris scene: one straight track per realisation at each
    angle, struck at the column when it reaches x = 4.8 m (then its track ends)."""
    (folder / "flow").mkdir(parents=True)
    shutil.copy(ROOT / "cases" / "1debris.yaml", folder / "flow" / "scene.yaml")
    rows, tracks = [], []
    for r, a in enumerate(angles_deg):
        x, y = _straight(a, x0=3.2, y0=0.01 * r, length=1.6)
        t = np.linspace(0.0, 3.0, x.size)
        tracks.append(pd.DataFrame({"realisation": r, "body": "debris1", "time_s": t, "x_m": x, "y_m": y,
                                    "speed_m_s": 1.0}))
        rows.append({"realisation": r, "body": "debris1", "start_x_m": 3.2, "start_y_m": 0.01 * r,
                     "start_yaw_deg": yaw_per_angle * a, "struck": True, "impact_time_s": 2.9})
    pd.DataFrame(rows).to_csv(folder / "ensemble.csv", index=False)
    pd.concat(tracks).to_csv(folder / "tracks.csv", index=False)
    perturbation = {"position_sigma_fraction": 0.25, "yaw_sigma_deg": 12.0, "clip_sigmas": 2.0}
    (folder / "ensemble.json").write_text(json.dumps({"realisations": len(angles_deg), "seed": 0,
                                                      "perturbation": perturbation, "scene": "cases/1debris.yaml"}))
    return folder


def test_page_from_a_synthetic_ensemble(tmp_path):
    angles = np.linspace(-20.0, 20.0, 9)  # +-20 deg: two tracks past 16.8, none past 22.5
    ens = _ensemble(tmp_path / "ens", angles)
    files = spreading_study([ens], tmp_path / "page")
    for kind in ("table", "summary", "report", "angles", "tracks", "lateral"):
        assert files[kind].is_file() and files[kind].stat().st_size > 0, kind
    table = pd.read_csv(files["table"])
    assert len(table) == angles.size
    assert table["angle_at_4600mm"].to_numpy() == pytest.approx(angles, abs=1e-9)
    assert table["angle_max_deg"].to_numpy() == pytest.approx(angles, abs=1e-9)
    # from its own start (a point): the ASCE angle is the track's own |angle|
    assert table["asce_angle_deg"].to_numpy() == pytest.approx(np.abs(angles), abs=1e-9)
    summary = json.loads(files["summary"].read_text())["scenes"][0]
    assert summary["tracks"] == angles.size
    assert summary["stations"]["4600mm"]["angle_deg"]["q1"] == pytest.approx(-10.0)
    assert summary["stations"]["4600mm"]["angle_deg"]["q3"] == pytest.approx(10.0)
    dy = 1.4 * np.tan(np.radians(angles))  # the run from 3.2 m to the 4.6 m station
    assert summary["per_body_last_station"]["debris1"]["std_dy_m"] == pytest.approx(dy.std(ddof=1), rel=1e-4)
    assert summary["asce"]["Nistor et al. (2017b)"]["outside"] == 2
    assert summary["asce"]["Naito et al. (2014)"]["outside"] == 0
    # the start yaw was drawn as half the angle: the fit gives slope 2 and r = 1
    assert summary["start_yaw"]["slope"] == pytest.approx(2.0)
    assert summary["start_yaw"]["r"] == pytest.approx(1.0)
    text = files["report"].read_text()
    for phrase in ("## Assumptions", "## Definitions", "Goseberg, N., Stolle, J., Nistor, I. & Shibayama, T. (2016)",
                   "hdro-0004", "0.04 x", "16.8", "22.5", "2 of 9"):
        assert phrase in text, phrase


def test_page_says_when_the_transport_spreads_less_than_measured(tmp_path):
    narrow = _ensemble(tmp_path / "narrow", np.linspace(-0.5, 0.5, 9))
    files = spreading_study([narrow], tmp_path / "page")
    text = files["report"].read_text()
    assert "spreads the tracks less than the measured containers spread" in text
    wide = _ensemble(tmp_path / "wide", np.linspace(-12.0, 12.0, 9))
    text = spreading_study([wide], tmp_path / "page2")["report"].read_text()
    assert "less than the measured containers" not in text


def test_missing_ensemble_file_is_bad_input_naming_it(tmp_path):
    ens = _ensemble(tmp_path / "ens", [0.0, 1.0])
    (ens / "tracks.csv").unlink()
    with pytest.raises(InputError, match="tracks.csv"):
        read_ensemble(ens)
    proc = run_cli("report", "spreading", str(ens), "-o", str(tmp_path / "page"))
    assert proc.returncode == 2
    assert "tracks.csv" in proc.stderr


def test_the_page_says_how_the_tracks_spread_against_the_flow_they_travel_in():
    """The tracks' std / run against the flow's RMS v / u: of the order (within a factor of 2),
    more (the bodies' own spread), or less (they do not follow the flow's turning)."""
    from orchestrator.studies.spreading_report import _flow_against_tracks
    assert "of the order" in _flow_against_tracks(0.006, 0.008)
    assert "3.0 times more" in _flow_against_tracks(0.01, 0.03)
    assert "4.8 times less" in _flow_against_tracks(0.0287, 0.006) and "of the order" not in _flow_against_tracks(0.0287, 0.006)
    assert _flow_against_tracks(None, 0.01) == "."
