"""Post-processing: parsers on real function-object output, metrics on closed forms, whole cases.

The cases under tests/data/post/ are real (tiny) OpenFOAM v1912 runs; see its README.md.
Tests marked `openfoam` run a tiny case for real (a few seconds) and post-process it.
"""

from __future__ import annotations

import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.errors import InputError
from orchestrator.case.outputs import (
    atmosphere_loss,
    read_force_series,
    read_vector_table,
    read_water_balance,
    water_balance_summary,
)
from orchestrator.report.postprocess import PostSummary, post_case
from orchestrator.results.impact_table import AFLOAT_CLEARANCE_M
from orchestrator.results.metrics import arrival_time, column_response, gauge_elevation, impact_metrics
from orchestrator.results.readers import read_body_tracks, read_gauge_samples
from orchestrator.results.tables import tables
from orchestrator.report.plots import PLOTS
from tests.conftest import run_cli

DATA = Path(__file__).parent / "data" / "post"
ROOT = Path(__file__).resolve().parent.parent


def _copy(name: str, tmp_path: Path) -> Path:
    """A writable copy of a committed case (post_case writes results/ inside it)."""
    dst = tmp_path / name
    shutil.copytree(DATA / name, dst)
    return dst


@pytest.fixture(scope="module")
def debris_case(tmp_path_factory) -> tuple[Path, PostSummary]:
    case = _copy("tiny-1debris", tmp_path_factory.mktemp("post"))
    return case, post_case(case)


@pytest.fixture(scope="module")
def nodebris_case(tmp_path_factory) -> tuple[Path, PostSummary]:
    case = _copy("tiny-nodebris", tmp_path_factory.mktemp("post"))
    return case, post_case(case)


# --------------------------------------------------------------------------- parsers


def _data_lines(path: Path) -> list[str]:
    return [line for line in path.read_text().splitlines() if line.strip() and not line.startswith("#")]


def test_force_dat_is_parsed_with_its_header_names():
    path = DATA / "tiny-nodebris/postProcessing/columnForces/0/force.dat"
    frame, meta = read_vector_table(path)
    assert list(frame.columns) == ["time", "total_x", "total_y", "total_z", "pressure_x", "pressure_y", "pressure_z",
                                   "viscous_x", "viscous_y", "viscous_z"]
    lines = _data_lines(path)
    assert len(frame) == len(lines)
    first = [float(v) for v in lines[0].replace("(", " ").replace(")", " ").split()]
    assert frame.iloc[0].tolist() == first
    assert meta["CofR"] == (1.0, 0.0, 0.0)  # the column's base centre (scene x = 1.0)
    # total = pressure + viscous, as v1912 writes it
    np.testing.assert_allclose(frame["total_x"], frame["pressure_x"] + frame["viscous_x"], rtol=1e-8, atol=1e-12)


def test_a_line_cut_short_is_skipped(tmp_path):
    src = DATA / "tiny-nodebris/postProcessing/columnForces/0/force.dat"
    text = src.read_text()
    cut = tmp_path / "force.dat"
    cut.write_text(text + "0.51 \t(1.0 2.0")  # a write interrupted by a kill
    frame, _ = read_vector_table(cut)
    assert len(frame) == len(_data_lines(src))


def test_force_pieces_of_restarts_are_joined_in_time_order():
    frame, _ = read_force_series(DATA / "tiny-1debris", "columnForces", "force")
    pieces = sorted(p.name for p in (DATA / "tiny-1debris/postProcessing/columnForces").iterdir())
    assert pieces == ["0", "0.03", "0.05"]
    total = sum(len(_data_lines(DATA / f"tiny-1debris/postProcessing/columnForces/{p}/force.dat")) for p in pieces)
    assert len(frame) == total  # nothing overlaps in this run: every row kept
    assert np.all(np.diff(frame["time"]) > 0)
    assert frame["time"].iloc[-1] == pytest.approx(0.06)


def test_a_later_piece_replaces_what_an_abandoned_attempt_wrote(tmp_path):
    base = tmp_path / "postProcessing/columnForces"
    header = "# Time (total_x total_y total_z) (pressure_x pressure_y pressure_z) (viscous_x viscous_y viscous_z)\n"
    rows = lambda ts, v: "".join(f"{t} ({v} 0 0) ({v} 0 0) (0 0 0)\n" for t in ts)  # noqa: E731
    (base / "0").mkdir(parents=True)
    (base / "0/force.dat").write_text(header + rows([0.1, 0.2, 0.3, 0.4], 1.0))  # diverged after 0.2
    (base / "0.2").mkdir()
    (base / "0.2/force.dat").write_text(header + rows([0.25, 0.35], 2.0))  # the rerun from 0.2
    frame, _ = read_force_series(tmp_path, "columnForces", "force")
    assert frame["time"].tolist() == [0.1, 0.2, 0.25, 0.35]
    assert frame["total_x"].tolist() == [1.0, 1.0, 2.0, 2.0]


def test_gauge_samples_are_read_per_gauge_and_time():
    samples = read_gauge_samples(DATA / "tiny-nodebris")
    assert sorted(samples) == ["WG1", "WG2", "WG4"]
    times = [t for t, _, _ in samples["WG2"]]
    assert times == sorted(times) and len(times) == 20 and times[0] == pytest.approx(0.025)
    t, z, alpha = samples["WG2"][-1]
    raw = np.loadtxt(DATA / "tiny-nodebris/postProcessing/gauges/0.5/WG2_alpha.water.xy")
    np.testing.assert_array_equal(z, raw[:, 0])
    np.testing.assert_array_equal(alpha, raw[:, 1])


def test_body_tracks_from_three_solver_segments():
    tracks = read_body_tracks(DATA / "tiny-1debris", "overInterDyMFoam", ["debris1"])
    logs = [DATA / "tiny-1debris" / f for f in ("log.overInterDyMFoam.1", "log.overInterDyMFoam.2",
                                                 "log.overInterDyMFoam")]
    steps = sum(len(re.findall(r"^Time = ", p.read_text(), re.M)) for p in logs)
    assert len(tracks) == steps == 23
    assert np.all(np.diff(tracks["time_s"]) > 0)
    # the first report of the first log, as printed
    text = logs[0].read_text()
    centre = [float(v) for v in re.search(r"Centre of mass: \(([^)]*)\)", text).group(1).split()]
    assert tracks[["x_m", "y_m", "z_m"]].iloc[0].tolist() == centre
    # the rebound of the contact at 0.03 s shows in the next segment: moving away from the column
    assert tracks.loc[tracks["time_s"] < 0.03, "u_m_s"].iloc[-1] > 0.5
    assert tracks.loc[tracks["time_s"] > 0.03, "u_m_s"].iloc[0] < 0.0
    # the same values the runner wrote to its own bodies.csv
    runner = pd.read_csv(DATA / "tiny-1debris/bodies.csv")
    np.testing.assert_allclose(tracks["x_m"], runner["x_m"], rtol=0, atol=0)
    np.testing.assert_allclose(tracks["u_m_s"], runner["u_m_s"], rtol=0, atol=0)
    # orientation: a rotation matrix, yaw/pitch/roll consistent with it
    q = tracks[[f"q_{a}{b}" for a in "xyz" for b in "xyz"]].to_numpy().reshape(-1, 3, 3)
    np.testing.assert_allclose(q @ q.transpose(0, 2, 1), np.broadcast_to(np.eye(3), q.shape), atol=1e-8)
    np.testing.assert_allclose(np.sin(np.radians(tracks["pitch_deg"])), -q[:, 2, 0], atol=1e-9)


def test_body_tracks_fall_back_on_the_runners_table(tmp_path):
    case = _copy("tiny-1debris", tmp_path)
    for log in case.glob("log.*"):
        log.unlink()
    tracks = read_body_tracks(case, "overInterDyMFoam", ["debris1"])
    assert len(tracks) == 23 and tracks["speed_m_s"].iloc[0] == pytest.approx(
        math.hypot(tracks["u_m_s"].iloc[0], tracks["w_m_s"].iloc[0]), rel=1e-6)


# --------------------------------------------------------------------------- gauge elevation and arrival


def test_gauge_elevation_of_a_step_is_exact():
    z = np.linspace(0.0, 0.30, 31)  # 1 cm apart, the line from the bed to the top
    for wet in (3, 10, 24):
        alpha = (np.arange(31) <= wet).astype(float)  # water up to sample `wet`, air above
        # the trapezoids put the step midway between the last wet and the first dry sample
        h, coverage = gauge_elevation(z, alpha, 0.0, 0.30)
        assert h == pytest.approx(0.01 * wet + 0.005, abs=1e-15) and coverage == 1.0
    assert gauge_elevation(z, np.ones(31), 0.0, 0.30) == (pytest.approx(0.30, abs=1e-15), 1.0)
    assert gauge_elevation(z, np.zeros(31), 0.0, 0.30) == (0.0, 1.0)


def test_gauge_elevation_of_cell_values_integrates_cell_by_cell():
    """Samples that are cell values (the `cell` scheme): a 15 mm bed layer full of water under
    a 38.5 mm cell with alpha 0.3 and air above. Expected: 15 + 0.3 x 38.5 mm, the water in the
    cells' column, exact with the faces, off by up to half a sample spacing without them."""
    faces = np.array([0.0, 0.015, 0.0535, 0.092, 0.3])
    z = np.linspace(0.0003, 0.2997, 51)  # 6 mm apart: no face falls on a sample
    alpha = np.select([z < 0.015, z < 0.0535], [1.0, 0.3], 0.0)
    h, coverage = gauge_elevation(z, alpha, 0.0, 0.30, faces_m=faces)
    assert h == pytest.approx(0.015 + 0.3 * 0.0385, abs=1e-12) and coverage == pytest.approx(1.0)
    trapezoid, _ = gauge_elevation(z, alpha, 0.0, 0.30)
    assert abs(trapezoid - h) > 1e-4  # the same samples without the faces
    # two faces between two samples: no single step to place, trapezoid as before
    sparse = z[::10]
    coarse = gauge_elevation(sparse, alpha[::10], 0.0, 0.30, faces_m=faces)[0]
    assert coarse == pytest.approx(gauge_elevation(sparse, alpha[::10], 0.0, 0.30)[0])


def _write_fo(case: Path, name: str, stem: str, column: str, rows) -> None:
    """A function object's .dat as v1912 writes it (header, then time and value)."""
    folder = case / "postProcessing" / name / "0"
    folder.mkdir(parents=True)
    lines = ["# Region type : patch x", f"# Time            \t{column}"]
    lines += [f"{t:<18.8g}\t{v:.10e}" for t, v in rows]
    (folder / f"{stem}.dat").write_text("\n".join(lines) + "\n")


def test_water_balance_books_each_open_patch_apart(tmp_path):
    """100 steps of 0.01 s: 1e-4 m3/s leaves through the outlet, 2e-5 m3/s over the top, from a
    1.0 m3 start. Expected: outflow_downstream_m3 and outflow_atmosphere_m3 add up to outflow_m3;
    the atmosphere's 0.2 % of the water passes the 0.1 % warning at t = 0.5 s (1e-3 m3)."""
    t = np.round(np.arange(1, 101) * 0.01, 10)
    volume = 1.0 - (1e-4 + 2e-5) * t
    _write_fo(tmp_path, "waterVolume", "volFieldValue", "volIntegrate(alpha.water)", zip(t, volume))
    _write_fo(tmp_path, "waterOut_downstream", "surfaceFieldValue", "sum(alphaPhi0.water)", ((x, 1e-4) for x in t))
    _write_fo(tmp_path, "waterOut_atmosphere", "surfaceFieldValue", "sum(alphaPhi0.water)", ((x, 2e-5) for x in t))
    b = read_water_balance(tmp_path)
    assert b["outflow_downstream_m3"].iloc[-1] == pytest.approx(1e-4)
    assert b["outflow_atmosphere_m3"].iloc[-1] == pytest.approx(2e-5)
    np.testing.assert_allclose(b["outflow_downstream_m3"] + b["outflow_atmosphere_m3"], b["outflow_m3"], rtol=1e-12)
    assert b["error"].abs().max() < 1e-12
    summary = water_balance_summary(b)
    assert summary["outflow_by_patch_m3"] == {"atmosphere": pytest.approx(2e-5), "downstream": pytest.approx(1e-4)}
    assert summary["atmosphere_outflow_fraction"] == pytest.approx(2e-5, rel=1e-3)
    assert summary["atmosphere_warning_time_s"] is None  # 0.002 % of the water: no warning
    # 100 times as much over the top: 0.2 % by the end, past 0.1 % at t = 0.51 s
    shutil.rmtree(tmp_path / "postProcessing" / "waterOut_atmosphere")
    _write_fo(tmp_path, "waterOut_atmosphere", "surfaceFieldValue", "sum(alphaPhi0.water)", ((x, 2e-3) for x in t))
    fraction, when = atmosphere_loss(read_water_balance(tmp_path))
    assert fraction == pytest.approx(2e-3, rel=1e-2) and when == pytest.approx(0.51)


def test_gauge_elevation_holds_the_end_samples_to_the_bed_and_top():
    z = np.linspace(0.0005, 0.2995, 300)  # line starting just above the bed, as rendered
    alpha = (z < 0.1).astype(float)
    h, coverage = gauge_elevation(z, alpha, 0.0, 0.30)
    assert h == pytest.approx(0.1, abs=1e-12) and coverage == pytest.approx(1.0)


def test_gauge_gaps_are_bridged_only_when_clear():
    z = np.linspace(0.0, 0.30, 31)
    alpha = (z <= 0.10 + 1e-12).astype(float)
    # a body in the water: samples 0.03..0.06 missing, water on both sides -> still 0.105
    keep = (z < 0.025) | (z > 0.065)
    assert gauge_elevation(z[keep], alpha[keep], 0.0, 0.30) == (pytest.approx(0.105), 1.0)
    # samples missing across the free surface: that stretch is left out
    keep = (z < 0.065) | (z > 0.145)
    h, coverage = gauge_elevation(z[keep], alpha[keep], 0.0, 0.30)
    assert coverage == pytest.approx(1 - 0.09 / 0.30) and h == pytest.approx(0.06)
    # nothing above the last (dry) sample, nothing below the first (wet) one: air and water
    keep = (z > 0.035) & (z < 0.205)
    assert gauge_elevation(z[keep], alpha[keep], 0.0, 0.30) == (pytest.approx(0.105), 1.0)
    assert gauge_elevation([], [], 0.0, 0.3)[1] == 0.0


def test_arrival_time_interpolates_the_threshold_crossing():
    t = np.array([0.1, 0.2, 0.3, 0.4])
    e = np.array([0.015, 0.015, 0.035, 0.055])
    # threshold 0.01 above 0.015: crossing 0.025 between 0.2 (0.015) and 0.3 (0.035) -> 0.25
    assert arrival_time(t, e, 0.015, 0.01) == pytest.approx(0.25)
    assert math.isnan(arrival_time(t, e, 0.015, 0.05))
    # before the first sample the level is the initial one at t = 0
    assert arrival_time([0.1, 0.2], [0.05, 0.05], 0.0, 0.01) == pytest.approx(0.02)
    # a falling level (upstream of the gate) never arrives; NaN samples are skipped
    assert math.isnan(arrival_time(t, [0.4, 0.3, 0.2, 0.1], 0.4, 0.008))
    assert arrival_time(t, [0.0, np.nan, 0.02, 0.02], 0.0, 0.01) == pytest.approx(0.2)


def test_arrival_at_the_committed_gauges():
    results = tables(DATA / "tiny-nodebris")
    g = results.gauge_summary.set_index("gauge")
    assert math.isnan(g.loc["WG1", "arrival_s"])  # upstream of the gate: the level only falls
    assert g.loc["WG2", "initial_level_from"] == "first sample"
    assert 0.2 < g.loc["WG2", "arrival_s"] < 0.25 < g.loc["WG4", "arrival_s"] < 0.5
    assert g.loc["WG2", "threshold_m"] == pytest.approx(0.02 * 0.2)
    elevation = results.gauges.set_index("time_s")["WG2_elevation_m"]
    level = g.loc["WG2", "initial_level_m"] + g.loc["WG2", "threshold_m"]
    before, after = elevation[elevation.index < g.loc["WG2", "arrival_s"]], elevation[
        elevation.index > g.loc["WG2", "arrival_s"]]
    assert before.max() <= level < after.iloc[0]


# --------------------------------------------------------------------------- impact metrics


@pytest.mark.parametrize("dt", [1e-6, 2e-5])
def test_impact_metrics_of_an_analytic_half_sine(dt):
    peak, duration, t0 = 523.0, 0.88e-3, 0.37e-3
    t = np.arange(0.0, 3e-3, dt)
    f = np.where((t >= t0) & (t <= t0 + duration), peak * np.sin(np.pi * (t - t0) / duration), 0.0)
    f = np.clip(f, 0.0, None)
    m = impact_metrics(t, f)
    assert m.peak_N == pytest.approx(peak, rel=0.01)
    assert m.duration_s == pytest.approx(duration, rel=0.01)
    assert m.impulse_Ns == pytest.approx(2 * peak * duration / np.pi, rel=0.01)
    assert m.start_s == pytest.approx(t0, abs=dt) and m.time_of_peak_s == pytest.approx(t0 + duration / 2, abs=dt)


def test_impact_metrics_of_two_contact_phases_span_both():
    t = np.linspace(0.0, 4e-3, 4001)
    f = np.clip(np.sin(2 * np.pi * t / 2e-3), 0.0, None) * 100.0  # two half-sines, 1 ms each, 1 ms apart
    m = impact_metrics(t, f)
    assert m.duration_s == pytest.approx(3e-3, rel=1e-3)  # first rise to the final separation
    assert m.impulse_Ns == pytest.approx(2 * (2 * 100 * 1e-3 / np.pi), rel=1e-4)


def test_impact_metrics_refuse_bad_records():
    with pytest.raises(InputError, match="time_s"):
        impact_metrics([0.0, 0.0, 1.0], [0.0, 1.0, 0.0])
    with pytest.raises(InputError, match="force_N"):
        impact_metrics([0.0, 1.0], [0.0, np.nan])


def test_impact_rows_agree_with_the_runners_event():
    results = tables(DATA / "tiny-1debris")
    event = json.loads((DATA / "tiny-1debris/contacts.json").read_text())[0]
    row = results.impacts.iloc[0]
    assert row["peak_force_N"] == pytest.approx(event["peak_force_N"], rel=1e-12)
    assert row["impulse_Ns"] == pytest.approx(event["impulse_Ns"], rel=1e-3)
    assert row["duration_s"] == pytest.approx(event["duration_s"], rel=1e-3)
    assert row["normal_velocity_in_m_s"] == pytest.approx(-event["normal_velocity_in_m_s"])
    assert row["impact_velocity_m_s"] == pytest.approx(event["velocity_in_m_s"][0])  # normal (-1, 0, 0)
    # obliquity: tan = tangential / normal incoming speed
    assert math.degrees(math.atan2(row["tangential_velocity_in_m_s"], row["normal_velocity_in_m_s"])) == \
        pytest.approx(event["obliquity_deg"])
    assert row["rebound_u_m_s"] == pytest.approx(event["velocity_out_m_s"][0])


def test_a_wall_strike_without_a_height_gets_its_row_and_no_column_pulse(tmp_path):
    """A one-way wall strike is written with a null height (JSON's NaN: the height above the bed is
    the column's figure); post-processing keeps its row and applies no pulse to the column."""
    case = tmp_path / "case"
    shutil.copytree(DATA / "tiny-1debris", case)
    events = json.loads((case / "contacts.json").read_text())
    wall = {**events[0], "event": len(events) + 1, "time_s": events[0]["time_s"] + 0.01, "other": "wall_y0",
            "kind": "wall", "height_m": None, "face_water_level_m": None, "force_history": ""}
    (case / "contacts.json").write_text(json.dumps([*events, wall]))
    results = tables(case)
    rows = results.impacts.set_index("kind")
    assert list(results.impacts["kind"]) == ["column", "wall"]
    assert math.isnan(rows.loc["wall", "height_m"]) and rows.loc["wall", "peak_force_N"] == pytest.approx(
        wall["peak_force_N"], rel=1e-3)
    assert rows.loc["column", "height_m"] == pytest.approx(events[0]["height_m"])


# --------------------------------------------------------------------------- whole cases


def test_debris_case_tables(debris_case):
    case, summary = debris_case
    res = case / "results"
    for name in ("gauges", "gauge_summary", "column_forces", "bodies", "impacts", "column_response"):
        assert summary.tables[name] == res / f"{name}.csv" and (res / f"{name}.csv").is_file()
    forces = pd.read_csv(res / "column_forces.csv")
    assert {"time_s", "hydro_force_x_N", "pressure_force_x_N", "viscous_force_x_N", "impact_force_x_N",
            "total_force_x_N", "hydro_moment_y_Nm"} <= set(forces.columns)
    np.testing.assert_allclose(forces["total_force_x_N"], forces["hydro_force_x_N"] + forces["impact_force_x_N"])
    # the impact pulse on the column: along +x (the body hit the upstream face), its impulse conserved
    pulse = forces[forces["impact_force_x_N"] > 0]
    impulse = np.trapezoid(forces["impact_force_x_N"], forces["time_s"])
    assert impulse == pytest.approx(pd.read_csv(res / "impacts.csv")["impulse_Ns"].iloc[0], rel=1e-9)
    assert pulse["time_s"].min() >= 0.03
    response = pd.read_csv(res / "column_response.csv")
    assert {"base_shear_x_N", "hydro_base_shear_x_N", "impact_base_shear_x_N"} <= set(response.columns)
    np.testing.assert_allclose(response["base_shear_x_N"],
                               response["hydro_base_shear_x_N"].fillna(0) + response["impact_base_shear_x_N"])
    head = json.loads((res / "summary.json").read_text())
    assert head["impacts"]["first"]["time_s"] == pytest.approx(0.03)
    assert head["cells"] == 4481 and head["wall_time_s"]["total_s"] > 0
    assert head["column_response"]["peak_base_shear_N"] > head["impacts"]["first"]["peak_force_N"] * 0.5
    assert head["status"] == "finished" and head["complete"]


def test_column_response_of_a_pulse_matches_the_mdof_model():
    from analytical.column import Column
    from analytical.mdof import mdof_response
    from analytical.pulses import HalfSine

    column = Column()
    t = np.linspace(0.0, 1e-3, 101)
    force = 200.0 * np.sin(np.pi * t / 1e-3)
    pulses = {1: (0.5 + t, np.column_stack([force, np.zeros_like(t), np.zeros_like(t)]))}
    table, heights = column_response(column, None, pulses, {1: 0.4})
    expected = mdof_response(HalfSine(200.0, 1e-3, 0.5), column, 0.4, table["time_s"].to_numpy())
    np.testing.assert_allclose(table["impact_base_shear_x_N"], expected.response_N, rtol=0, atol=2e-3 * 200)
    assert not heights and np.all(table["base_shear_y_N"] == 0)


def test_partly_finished_run_is_post_processed_up_to_where_it_got(tmp_path):
    case = _copy("tiny-nodebris-stopped", tmp_path)
    summary = post_case(case)
    assert summary.status == "interrupted"
    assert summary.reached_time_s == pytest.approx(0.24166667)
    assert summary.end_time_s == pytest.approx(0.5)
    gauges = pd.read_csv(case / "results/gauges.csv")
    assert gauges["time_s"].max() == pytest.approx(0.225)
    # the bore had not reached WG2's threshold yet: no arrival, and no error against the models
    arrivals = pd.read_csv(case / "results/arrivals.csv")
    assert arrivals[arrivals["gauge"] == "WG2"]["simulated_arrival_s"].isna().all()
    report = (case / "results/report.md").read_text()
    assert "post-processed up to t = 0.2417 s of 0.5 s" in report
    assert all((case / "results" / f).is_file() for f in PLOTS.values())


def test_a_case_without_outputs_is_reported_not_crashed_on(tmp_path):
    case = tmp_path / "bare"  # it ran (run.json) but wrote none of its outputs
    case.mkdir()
    shutil.copy(DATA / "tiny-1debris/plan.json", case)
    shutil.copy(DATA / "tiny-1debris/run.json", case)
    summary = post_case(case)
    missing = " ".join(summary.missing)
    assert "no gauge output" in missing and "no column force output" in missing
    assert "no scene.yaml" in missing and "no contact events" in missing
    assert all((case / "results" / f).is_file() for f in PLOTS.values())


def test_not_a_case_is_bad_input(tmp_path):
    with pytest.raises(InputError, match="not a debrisfoam case") as err:
        post_case(tmp_path)
    assert str(tmp_path) in str(err.value)
    proc = run_cli("post", str(tmp_path))
    assert proc.returncode == 2 and str(tmp_path) in proc.stderr and "Traceback" not in proc.stderr
    proc = run_cli("post", str(tmp_path / "missing"))
    assert proc.returncode == 2 and "missing" in proc.stderr


def test_cli_prints_where_the_results_are_and_the_headline(tmp_path):
    case = _copy("tiny-1debris", tmp_path)
    proc = run_cli("post", str(case), "--tables-only")
    assert proc.returncode == 0, proc.stderr
    assert str(case / "results") in proc.stdout
    assert "first impact" in proc.stdout and "521.6 N" in proc.stdout and "peak base shear" in proc.stdout
    assert not (case / "results/report.md").exists()


# --------------------------------------------------------------------------- real OpenFOAM


@pytest.mark.openfoam
def test_a_real_tiny_run_post_processes_with_every_plot(tmp_path, openfoam):
    from orchestrator.pipeline import render_from_file
    from orchestrator.run.runner import run_case

    case = tmp_path / "tiny"
    render_from_file(ROOT / "cases" / "tiny-nodebris.yaml", case)
    run_case(case, np=1, quiet=True)
    summary = post_case(case)
    assert summary.status == "finished"
    for name, file in PLOTS.items():
        assert summary.plots[name] == case / "results" / file and summary.plots[name].stat().st_size > 10_000
    # a real 3D view, not a placeholder (drawn at the nearest written time is still a real view)
    assert not any(m.startswith("snapshot") and "drawn at the nearest written time" not in m for m in summary.missing)
    g = pd.read_csv(case / "results/gauge_summary.csv").set_index("gauge")
    assert 0.15 < g.loc["WG2", "arrival_s"] < 0.3
    report = (case / "results/report.md").read_text()
    for file in PLOTS.values():
        assert f"]({file})" in report


def test_impacts_carry_the_water_level_at_the_column_face_and_whether_the_body_floated():
    """The study's impact height is the water level at the column's face: the face gauge (WG4,
    10 mm upstream of it) interpolated at the impact; the body's lowest point comes from its
    track and orientation, and a body that far above the bed is afloat."""
    results = tables(DATA / "tiny-1debris")
    row = results.impacts.iloc[0]
    g = results.gauges[["time_s", "WG4_elevation_m"]].dropna()
    assert row["face_water_level_m"] == pytest.approx(np.interp(row["time_s"], g["time_s"], g["WG4_elevation_m"]))
    track = results.bodies[results.bodies["body"] == row["body"]]
    at = track.iloc[int(np.argmin(np.abs(track["time_s"] - row["time_s"])))]
    half = np.array(results.data.plan.bodies[0].size_m) / 2
    q_z = np.abs([at["q_zx"], at["q_zy"], at["q_zz"]])
    assert row["body_clearance_m"] == pytest.approx(at["z_m"] - q_z @ half - results.data.bed_z_m)
    assert row["body_clearance_m"] > AFLOAT_CLEARANCE_M and row["afloat"]


def test_case_report_puts_the_first_impact_beside_the_study(debris_case, tmp_path):
    from tests.conftest import run_cli

    case, _ = debris_case
    proc = run_cli("report", "case", str(case), "-o", str(tmp_path / "page"))
    assert proc.returncode == 0, proc.stderr
    text = (tmp_path / "page" / "report.md").read_text()
    impact = pd.read_csv(case / "results" / "impacts.csv").iloc[0]
    speed = impact["impact_speed_m_s"]
    assert (f"| impact speed (along the contact normal, obliquity) | {speed:.2f} m/s "
            f"({impact['impact_velocity_m_s']:.2f} m/s, {impact['obliquity_deg']:.0f} degrees) | 1.6 +- 0.13 m/s | "
            "below |") in text
    assert "| afloat at the impact | yes" in text
    assert f"| the contact law's pulse: magnitude | {impact['peak_force_N']:.0f} N | not tabulated" in text
    # one strike: its z against the study's speeds, no Welch test; no base-shear history, no study fit
    z = (speed - 1.60) / 0.13
    assert (f"| speed of the centre (m/s) | 1 | {speed:.3g} | - | {speed:.3g} | - | 1.6 | 0.13 | 22 | z = {z:+.2f} | - |"
            in text) and "outside the study's scatter" in text
    assert "| study-fit peak force (N) | 0 | - |" in text and "Welch's unequal-variance t test" in text
    # the ASCE 7-22 table: the governing stiffness named, the design value at the impact speed (a
    # two-way run records no flow velocity: said), the k_d force as context
    design = 0.65 * speed * (4.685e5 * 0.236) ** 0.5
    assert "## ASCE 7-22 6.11: the design impact force" in text and "**the column's lateral stiffness k_s governs**" in text
    assert f"Design value: **F_i = {design:.0f} N** (k_s governs; the body's impact speed" in text
    assert "u_max, the flow's maximum velocity at the column (what the standard's formula takes): not recorded" in text
    assert "full-scale bound: not applied" in text
    for plot in ("gauges.png", "impacts.png", "summary.json"):
        assert (tmp_path / "page" / plot).is_file()
    missing = run_cli("report", "case", str(tmp_path), "-o", str(tmp_path / "x"))
    assert missing.returncode == 2 and "summary.json" in missing.stderr
