"""Comparisons with the analytical models and the study, on closed forms and committed real runs."""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.asce7 import asce7_impact
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M
from orchestrator.results import compare
from orchestrator.report.postprocess import post_case
from orchestrator.results.tables import tables
from orchestrator.report.plots import PLOTS
from orchestrator.scene.scenefile import load_scene

DATA = Path(__file__).parent / "data" / "post"
ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def debris():
    results = tables(DATA / "tiny-1debris")
    return results, compare.compare(results)


# --------------------------------------------------------------------------- spreading areas


def test_spreading_area_from_one_centroid_is_a_cone():
    poly = compare.spreading_area([[3.2, 0.0]], 22.5, 5.2)
    w = 2.0 * math.tan(math.radians(22.5))
    np.testing.assert_allclose(poly, [[3.2, 0.0], [5.2, -w], [5.2, w], [3.2, 0.0]])


def test_spreading_area_starts_from_the_source_line():
    # a 2 x 3 layout: rows along the flow at x = 3.075, 3.325; columns across at y = -0.15, 0, 0.15
    src = [[x, y] for x in (3.075, 3.325) for y in (-0.15, 0.0, 0.15)]
    poly = compare.spreading_area(src, 16.8, 5.075)
    w = 2.0 * math.tan(math.radians(16.8))
    np.testing.assert_allclose(poly, [[3.075, -0.15], [5.075, -0.15 - w], [5.075, 0.15 + w], [3.075, 0.15]])
    angles = compare.spreading_angle_deg(src, [[4.075, 0.0], [4.075, 0.15 + math.tan(math.radians(10.0))],
                                               [3.0, 0.0], [3.0, 0.5]])
    assert angles[0] == 0.0 and angles[1] == pytest.approx(10.0) and angles[2] == 0.0 and math.isnan(angles[3])


def test_spreading_angles_name_their_sources():
    for name, spec in compare.SPREADING_ANGLES_DEG.items():
        assert name.split()[0] in spec["source"] and 0 < spec["half_angle_deg"] < 45
    assert compare.SPREADING_ANGLES_DEG["Naito et al. (2014)"]["half_angle_deg"] == 22.5
    # the study finds the Nistor et al. area the narrower of the two (its Fig. 14)
    assert compare.SPREADING_ANGLES_DEG["Nistor et al. (2017b)"]["half_angle_deg"] < 22.5


def test_spreading_table_of_the_committed_run(debris):
    _, comp = debris
    row = comp.spreading.iloc[0]
    assert row["body"] == "debris1" and row["track_points"] == 23
    assert row["inside_naito"] and row["inside_nistor"] and row["max_spread_deg"] < 1.0
    assert set(comp.areas) == set(compare.SPREADING_ANGLES_DEG)


# --------------------------------------------------------------------------- arrivals


def test_arrivals_against_chanson_and_the_study():
    scene = load_scene(ROOT / "cases/nodebris.yaml")
    summary = pd.DataFrame({"gauge": ["WG1", "WG2", "WG3"], "x_m": [-0.10, 2.40, 3.20], "y_m": [0.0, 0.0, 0.5],
                            "arrival_s": [np.nan, 0.95, 1.30]})
    table = compare.arrival_table(scene, summary).set_index(["gauge", "reference"])
    assert "WG1" not in table.index.get_level_values(0)  # upstream of the gate: no front to arrive
    # Chanson with the study's f = 0.0293 (docs/bed-friction.md: 0.871 s and 1.201 s)
    assert table.loc[("WG2", "Chanson"), "reference_arrival_s"] == pytest.approx(0.871, abs=1e-3)
    assert table.loc[("WG3", "Chanson"), "reference_arrival_s"] == pytest.approx(1.201, abs=1e-3)
    assert table.loc[("WG2", "study experiment (WG2)"), "reference_arrival_s"] == 0.91
    assert table.loc[("WG3", "study model (WG3)"), "reference_arrival_s"] == 1.20
    assert table.loc[("WG3", "study experiment (WG3)"), "error_s"] == pytest.approx(1.30 - 1.39)
    assert table.loc[("WG2", "study model (WG2)"), "error_percent"] == pytest.approx(100 * (0.95 - 0.88) / 0.88)
    # a 15 mm wet bed: Stoker too; Ritter is the fastest front
    assert table.loc[("WG2", "Ritter"), "reference_arrival_s"] < table.loc[("WG2", "Chanson"), "reference_arrival_s"]
    assert ("WG2", "Stoker") in table.index


def test_gauge_models_start_from_the_still_water():
    scene = load_scene(ROOT / "cases" / "tiny-nodebris.yaml")
    summary = pd.DataFrame({"gauge": ["A", "B"], "x_m": [-0.05, 0.4], "y_m": [0.0, 0.0]})
    models = compare.gauge_models(scene, summary, 0.5, n=51)
    assert set(models["A"].columns) == {"time_s", "ritter_m", "chanson_m"}  # dry bed: no Stoker
    assert models["A"]["ritter_m"].iloc[0] == pytest.approx(0.2) and models["B"]["ritter_m"].iloc[0] == 0.0
    assert models["B"]["ritter_m"].iloc[-1] > 0.0 and models["B"]["chanson_m"].iloc[-1] > 0.0


# --------------------------------------------------------------------------- impacts


def test_formulas_at_the_simulated_velocity(debris):
    results, comp = debris
    rows = comp.impact_formulas.set_index("method")
    u = results.impacts["impact_velocity_m_s"].iloc[0]
    assert rows.loc["ASCE 7-22, k_d", "impact_velocity_m_s"] == u
    kd = asce7_impact(u, 0.236, STUDY_DEBRIS_STIFFNESS_N_M)
    assert rows.loc["ASCE 7-22, k_d", "peak_force_N"] == pytest.approx(kd.force_N)
    assert rows.loc["ASCE 7-22, k_s", "peak_force_N"] == pytest.approx(asce7_impact(u, 0.236, 4.685e5).force_N)
    # ASCE's impulse does not depend on the stiffness (the study's remark on its Table 1)
    assert rows.loc["ASCE 7-22, k_d", "impulse_Ns"] == pytest.approx(rows.loc["ASCE 7-22, k_s", "impulse_Ns"])
    assert rows.loc["Haehnel & Daly, k_d", "peak_force_N"] == pytest.approx(u * math.sqrt(STUDY_DEBRIS_STIFFNESS_N_M
                                                                                         * 0.236))
    assert rows.loc["contact model (simulated)", "peak_ratio"] == 1.0
    assert {"Matsutomi (C_MA 1.7)", "Ikeno (C_MA 1.7)", "Haehnel & Daly, k_d + k_s in series"} <= set(rows.index)


def test_the_study_procedure_recovers_the_contact_pulse(debris):
    """Fitting an MDOF half-sine to the column's response (the study's 3.2.2) on our own output
    gives back the pulse the contact model produced: the fit is only as good as the model."""
    results, comp = debris
    table = comp.table1.set_index("method")
    assert list(comp.table1["method"]) == ["ASCE 7-22, k_d", "ASCE 7-22, k_s", "SDOF fit", "MDOF fit",
                                           "contact model (simulated)"]
    contact = table.loc["contact model (simulated)"]
    mdof = table.loc["MDOF fit"]
    assert mdof["magnitude_N"] == pytest.approx(contact["magnitude_N"], rel=0.05)
    assert mdof["duration_s"] == pytest.approx(contact["duration_s"], rel=0.05)
    assert mdof["impulse_Ns"] == pytest.approx(contact["impulse_Ns"], rel=0.01)
    assert contact["ratio_to_simulated"] == pytest.approx(1.0, abs=1e-3)  # one impact: it is the whole response
    assert mdof["ratio_to_simulated"] == pytest.approx(1.0, abs=0.05)
    assert table.loc["ASCE 7-22, k_d", "study_magnitude_N"] == 822.34
    assert table.loc["MDOF fit", "study_duration_s"] == 0.0047
    fits = comp.study_fits.set_index("model")
    assert fits.loc["MDOF fit", "height_m"] == pytest.approx(results.impacts["height_m"].iloc[0])
    record = comp.fit_records[1]
    assert record["record_N"].max() == pytest.approx(contact["peak_base_shear_N"], rel=0.01)


def test_headline(debris):
    _, comp = debris
    head = comp.headline()
    assert head["table1_event"] == 1
    assert head["impact_peak_ratio"]["contact model (simulated)"] == 1.0
    assert head["spreading"]["debris1"]["Naito et al. (2014)"] is True


# --------------------------------------------------------------------------- a run without debris


def test_no_debris_run_gets_every_plot_and_the_report(tmp_path):
    case = tmp_path / "case"
    shutil.copytree(DATA / "tiny-nodebris", case)
    summary = post_case(case)
    for name, file in PLOTS.items():
        assert (case / "results" / file).stat().st_size > 5_000, name
    report = (case / "results/report.md").read_text()
    for file in PLOTS.values():
        assert f"]({file})" in report
    assert "No impact events in this run" in report and "Chanson" in report
    for table in ("arrivals", "impact_formulas", "study_fits", "table1", "spreading"):
        assert (case / "results" / f"{table}.csv").is_file()
    arrivals = pd.read_csv(case / "results/arrivals.csv")
    assert set(arrivals["reference"]) == {"Ritter", "Chanson"}  # dry bed, and none of the study's gauge positions here
    assert arrivals["error_s"].notna().all()
    assert "comparisons" in summary.headline and any("snapshot" in m for m in summary.missing)


# --------------------------------------------------------------------------- ASCE 7-22: one answer


def test_u_max_at_the_column_is_ritters_speed_at_the_floating_depth():
    """Ritter's dam break at a fixed x: the speed falls as the depth rises behind the front, so the
    largest speed where the water floats a body of draft h_d is where h = h_d: u = 2 (sqrt(g h0) -
    sqrt(g h_d)), whatever x."""
    from orchestrator.results.asce_design import flow_speed_at
    from orchestrator.transport.flow import FlowField

    g, h0, h_d = 9.81, 0.4, 0.02
    field = FlowField.ritter(h0, x_m=np.linspace(0.0, 2.0, 21), t_s=np.linspace(0.2, 2.0, 1801), gravity_m_s2=g)
    site = flow_speed_at(field, 1.05, (-0.1, 0.1), h_d)
    assert site.x_m == pytest.approx(1.0)
    assert site.u_max_m_s == pytest.approx(2 * (math.sqrt(g * h0) - math.sqrt(g * h_d)), rel=2e-3)
    assert site.depth_m >= h_d
    assert flow_speed_at(field, 1.05, (-0.1, 0.1), 1.0) is None  # never that deep


def test_the_run_names_one_design_value_as_the_analytical_verbs_do(debris):
    """The report's ASCE table: k_s governs, the design force at the impact speed (the committed
    two-way run records no flow velocity), the same figure `analytical asce7` and `analytical impact`
    give for that speed and mass."""
    from tests.conftest import cli_json

    results, comp = debris
    row = comp.asce.iloc[0]
    speed = row["impact_speed_m_s"]
    assert comp.site_flow is None and math.isnan(row["u_max_m_s"]) and "impact speed" in row["design_basis"]
    assert row["governing_stiffness"] == "k_s" and row["other_stiffness"] == "k_d"
    assert row["design_force_N"] == pytest.approx(0.65 * speed * math.sqrt(4.685e5 * 0.236))
    assert row["other_force_N"] == pytest.approx(0.65 * speed * math.sqrt(STUDY_DEBRIS_STIFFNESS_N_M * 0.236))
    verb = cli_json("analytical", "asce7", "--velocity", repr(float(speed)), "--mass", "0.236")
    strike = cli_json("analytical", "impact", "--velocity", repr(float(speed)))
    assert verb["force_N"] == pytest.approx(row["design_force_N"], rel=1e-12)
    assert strike["asce7_design_force_N"] == pytest.approx(row["design_force_N"], rel=1e-12)
    assert verb["governing_stiffness"].startswith("k_s") and strike["asce7_governing_stiffness"].startswith("k_s")
    assert verb["force_with_k_d_N"] == pytest.approx(row["other_force_N"], rel=1e-12)
    head = comp.headline()["asce7"]
    assert head["governing_stiffness"] == "k_s" and head["design_force_N"] == pytest.approx(row["design_force_N"],
                                                                                             abs=1e-3)


def test_a_one_way_run_takes_u_max_from_its_flow_record(debris, tmp_path):
    """With a flow record at the column the design force is at u_max, and the study's way (the
    impact speed) stays beside it."""
    from orchestrator.results.asce_design import asce_design_table, site_flow_speed
    from orchestrator.transport.flow import FlowField

    results, _ = debris
    scene = results.data.scene
    col = scene.column
    (tmp_path / "results").mkdir()
    FlowField.uniform_current(0.1, 1.25, x_m=(col.x_m - 0.5, col.x_m + 0.5), y_m=(-0.15, 0.15)).save(
        tmp_path / "results" / "flow_record.npz")
    site = site_flow_speed(tmp_path, scene)
    assert site.u_max_m_s == pytest.approx(1.25) and "flow record" in site.source
    table = asce_design_table(results.impacts, results.data.body_masses_kg, col_stiffness := 4.685e5, site)
    row = table.iloc[0]
    assert row["design_force_N"] == pytest.approx(0.65 * 1.25 * math.sqrt(col_stiffness * 0.236))
    assert row["force_at_impact_speed_N"] == pytest.approx(0.65 * row["impact_speed_m_s"] * math.sqrt(col_stiffness
                                                                                                      * 0.236))
    assert row["design_basis"].startswith("u_max")


def test_the_depth_average_weighs_each_level_by_the_water_it_stands_for():
    """Levels dense near the bed (a slow friction layer) and sparse above: u = 0.2 m/s below
    10 mm and 2 m/s above, water 0.1 m deep, air above it at 5 m/s: the depth average is
    (0.01 x 0.2 + 0.09 x 2) / 0.1 = 1.82 m/s within the trapezoids' error at the step, not the
    mean of the levels, and the air does not count."""
    import numpy as np

    from orchestrator.results.asce_design import _depth_averaged_speed

    z = np.array([0.0, 0.001, 0.002, 0.004, 0.006, 0.009, 0.011, 0.05, 0.099, 0.15])
    u = np.where(z < 0.01, 0.2, 2.0)
    u[z > 0.1] = 5.0
    velocity = np.stack([u, np.zeros_like(u)], axis=1)
    assert _depth_averaged_speed(z, velocity, 0.0, 0.1) == pytest.approx(1.82, abs=0.02)
