"""Every strike of a design realisation, as it strikes (issue 48 items 4 and 5), on a synthetic
flow (no OpenFOAM): the strike count and the largest-strike demand against the engine alone,
the face, obliquity, eccentricity and torsion of a constructed strike of known geometry, a
container too heavy to float left out and counted, the quantiles given a strike against numpy
on the same data, and the page's recommended design value with its band."""
from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from analytical.column import Column
from orchestrator.scene.schema import Design
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.design import DEMANDS, DESIGN_COLUMNS, DesignCase, DesignResult, design_batch, design_starts
from orchestrator.studies.design_advice import LAW_FORCE_SE, band, given_strike, strike_summary
from orchestrator.studies.design_report import QUANTILES, write_report
from orchestrator.studies.design_strikes import draft_m, strike_geometry
from orchestrator.studies.design_table import realisation_demands
from orchestrator.transport.engine import TransportSettings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn
from orchestrator.scene.schema import DebrisBody
from tests.conftest import debris
from tests.test_design import TINY

FLUME = FlumeBounds((0.0, 2.0), (-0.3, 0.3), 0.0)
COLUMN = PlacedColumn(1.0, 0.0, Column(size_x_m=0.1, size_y_m=0.1, height_m=0.3, wall_thickness_m=0.005))
SIZE = (0.15, 0.06, 0.06)
DEPTH = 0.1  # the depth of the current (conftest)


def _body(mass=0.236, y=0.0) -> DebrisBody:
    return debris("debris1", SIZE, mass, (0.6, y, 0.03), wall_thickness_m=0.005)


@pytest.fixture(scope="module")
def batch(current):
    """Three realisations: a drawn start (0.33 kg, 4 mm off the centreline, turned 8 degrees: a
    rebound sequence against the column), the study's box 30 mm off the centreline (square on,
    half its width on the face) and a 2 kg box that cannot float in 0.1 m of water."""
    _, npz = current
    drawn = design_starts([_body()], FLUME, COLUMN, Design(mass_kg=(0.2, 0.4)), 0, 0)
    starts = [drawn, [_body(0.236, 0.03)], [_body(2.0)]]
    rows = pd.DataFrame(design_batch([0, 1, 2], starts, FLUME, COLUMN, 2.5, npz, TransportSettings()))
    return starts, rows


def test_every_strike_counts_and_the_demand_is_the_largest(current, batch):
    """The drawn start alone (a batch's rebound sequences can differ from a lone run's after the
    first strike, orchestrator/transport/batch.py): one row per column strike the engine found,
    each with its pulse, and the realisation's demand the largest of them."""
    flow, npz = current
    starts, rows = batch
    assert list(rows.columns) == [c for c in DESIGN_COLUMNS if c not in ("case", "case_weight", "sample_weight")]
    assert (rows.loc[rows["realisation"] == 0, "strike"] > 0).sum() >= 3
    alone = run_transport(starts[0], FLUME, 2.5, flow=flow, column=COLUMN,
                          settings=TransportSettings(first_pulse_only=True, every_column_pulse=True))
    on_column = alone.impacts[alone.impacts["kind"] == "column"]
    rows = pd.DataFrame(design_batch([0], starts[:1], FLUME, COLUMN, 2.5, npz, TransportSettings()))
    mine = rows[rows["realisation"] == 0]
    assert len(on_column) >= 3  # pushed back onto the column after each rebound
    assert len(mine) == len(on_column) and (mine["strikes"] == len(on_column)).all()
    assert mine["strike"].tolist() == list(range(1, len(on_column) + 1))
    assert mine["peak_force_N"].to_numpy() == pytest.approx(on_column["peak_force_N"].to_numpy(), rel=1e-3)
    assert mine["peak_force_N"].notna().all() and (mine["peak_force_N"] > 0).all()  # every strike has its pulse
    per = realisation_demands(rows.assign(case="a", case_weight=1.0, sample_weight=1 / 3))
    first = per.iloc[0]
    assert first["strikes"] == len(on_column)
    for key in DEMANDS:  # the realisation's demand is its largest strike, not its first
        assert first[key] == pytest.approx(mine[key].max())
    assert first["peak_force_N"] == pytest.approx(on_column["peak_force_N"].max(), rel=1e-3)


def test_a_constructed_strike_gives_its_face_obliquity_eccentricity_and_torsion():
    column = PlacedColumn(10.0, 2.0, Column(size_x_m=1.0, size_y_m=1.0, height_m=5.0))
    # the upstream face (x = 9.5), 0.3 m to +y of its centre, at 45 degrees in plan (a climb is not obliquity)
    g = strike_geometry((9.5, 2.3, 1.0), (-1.0, 0.0, 0.0), (3.0, 3.0, 0.5), column, 2.0e6)
    assert g["face"] == "upstream" and g["obliquity_deg"] == pytest.approx(45.0)
    # along z x n = (0, -1): -0.3 m; the force +x at y = +0.3 m turns the column clockwise seen from above
    assert g["eccentricity_m"] == pytest.approx(-0.3) and g["torsion_Nm"] == pytest.approx(-0.6e6)
    # a side face, square on; a corner's contact normal goes to the nearer face's
    g = strike_geometry((10.2, 1.5, 1.0), (0.1, -1.0, 0.0), (0.0, 2.0, 0.0), column, 1.0)
    assert g["face"] == "side -y" and g["obliquity_deg"] == pytest.approx(0.0)
    assert g["eccentricity_m"] == pytest.approx(0.2) and g["torsion_Nm"] == pytest.approx(0.2)


def test_a_strike_off_the_centreline_is_eccentric_by_its_overlap(batch):
    """The study's box 30 mm off the centreline, carried square on: its 60 mm width covers the
    face from y = 0 to 0.05 m, so the contact's centre is 25 mm off the face's (along z x n,
    -y for the upstream face), and the torsion is the peak force times that."""
    _, rows = batch
    first = rows[(rows["realisation"] == 1) & (rows["strike"] == 1)].iloc[0]
    assert first["face"] == "upstream" and first["obliquity_deg"] < 1.0
    assert first["eccentricity_m"] == pytest.approx(-0.025, abs=2e-3)
    assert first["torsion_Nm"] == pytest.approx(first["peak_force_N"] * first["eccentricity_m"])
    assert first["flow_speed_m_s"] == pytest.approx(0.6) and first["flow_speed_max_m_s"] == pytest.approx(0.6)
    assert first["impact_speed_m_s"] <= 1.05 * first["flow_speed_max_m_s"]


def test_a_container_too_heavy_to_float_is_not_carried_and_is_counted(batch):
    _, rows = batch
    heavy = rows[rows["realisation"] == 2]
    assert len(heavy) == 1
    row = heavy.iloc[0]
    assert row["draft_m"] == pytest.approx(2.0 / (998.0 * 0.15 * 0.06)) and row["draft_m"] > DEPTH
    assert row["start_depth_m"] == pytest.approx(DEPTH)
    assert not row["carried"] and not row["struck"] and row["strike"] == 0 and row["wall_time_s"] < 0.05
    assert (heavy[list(DEMANDS)] == 0.0).all(axis=None)
    assert rows.loc[rows["realisation"] < 2, "carried"].all()
    assert draft_m(_body(0.236), 998.0) < DEPTH
    table = rows.assign(case="a", case_weight=1.0, sample_weight=1 / 3)
    summary = strike_summary(table, realisation_demands(table), {"a": 0.6})
    assert summary["grounded"] == 1 and summary["grounded_realisations"] == 1 and summary["bodies"] == 3
    assert summary["grounded_largest_draft_m"] == pytest.approx(row["draft_m"])
    assert summary["striking_realisations"] == 2


def _per(values: dict[str, list[float]], weights: dict[str, float]) -> tuple[pd.DataFrame, list[DesignCase]]:
    rows = []
    for case, vals in values.items():
        for r, v in enumerate(vals):
            rows.append({"case": case, "realisation": r, "struck": v > 0, "sample_weight": weights[case] / len(vals),
                         "case_weight": weights[case], **{k: v * s for k, s in zip(DEMANDS, (1, 2, 3, 1e-6))}})
    return pd.DataFrame(rows), [DesignCase(c, [], w, len(values[c])) for c, w in weights.items()]


def test_quantiles_given_a_strike_are_numpys_on_the_strikes():
    rng = np.random.default_rng(5)
    vals = np.where(rng.uniform(size=400) < 0.3, 0.0, rng.lognormal(1.0, 0.5, 400))
    per, cases = _per({"a": list(vals)}, {"a": 1.0})
    given = given_strike(per, cases, 0.95, QUANTILES)
    struck = vals[vals > 0]
    assert given["strikes"] == struck.size
    for name, p in QUANTILES.items():
        assert given["peak_force_N"][name]["value"] == pytest.approx(np.quantile(struck, p, method="inverted_cdf"))
        assert given["base_moment_Nm"][name]["value"] == pytest.approx(3 * np.quantile(struck, p, method="inverted_cdf"))
    # two cases of equal weight, 5 of 10 and 8 of 10 struck: given a strike each strike weighs the same
    a, b = [0, 0, 0, 0, 0, 1, 2, 3, 4, 5], [0, 0, 6, 7, 8, 9, 10, 11, 12, 13]
    per, cases = _per({"a": a, "b": b}, {"a": 0.5, "b": 0.5})
    given = given_strike(per, cases, 0.95, QUANTILES)
    pooled = np.array([v for v in a + b if v > 0], dtype=float)
    for name, p in QUANTILES.items():
        assert given["peak_force_N"][name]["value"] == pytest.approx(np.quantile(pooled, p, method="inverted_cdf"))
    # nothing struck: no quantile given a strike
    per, cases = _per({"a": [0.0, 0.0]}, {"a": 1.0})
    assert given_strike(per, cases, 0.95, QUANTILES)["peak_force_N"] is None


def test_the_band_scales_the_interval_by_the_law_and_the_flow():
    q = {"value": 10.0, "lower": 9.0, "upper": 11.0}
    b = band(q, [1.1, 1.2, None], 0.95)
    law = 1.959964 * LAW_FORCE_SE
    assert LAW_FORCE_SE == pytest.approx(62.91 / math.sqrt(22) / 171.07)
    assert b["lower"] == pytest.approx(9.0 * (1 - law), rel=1e-5) and b["upper"] == pytest.approx(11.0 * (1 + law) * 1.2,
                                                                                                  rel=1e-5)
    assert band(q, [], 0.95)["flow_stated"] is False


def test_the_page_recommends_p90_given_a_strike_times_i_tsu_in_kn(tmp_path):
    scene = load_scene(TINY)
    rng = np.random.default_rng(2)
    rows = []
    for r in range(60):
        struck = r % 3 != 0
        for k in range(1, (1 + r % 4 if struck else 0) + 1) if struck else [0]:
            f = float(rng.uniform(2e3, 9e3)) if struck else 0.0
            rows.append({"case": "c", "realisation": r, "case_weight": 1.0, "sample_weight": 1 / 60, "body": "b",
                         "mass_kg": 0.236, "carried": True, "struck": struck, "strikes": 1 + r % 4 if struck else 0,
                         "strike": k, "impact_speed_m_s": 0.9 if struck else math.nan,
                         "impact_height_m": 0.05 if struck else math.nan, "face": "upstream" if struck else math.nan,
                         "obliquity_deg": 40.0 * (k == 2) if struck else math.nan,
                         "eccentricity_m": 0.01 if struck else math.nan, "torsion_Nm": 0.01 * f if struck else math.nan,
                         "peak_force_N": f, "base_shear_N": 1.2 * f, "base_moment_Nm": 0.05 * f,
                         "displacement_m": 1e-7 * f, "wall_time_s": 0.1})
    table = pd.DataFrame(rows, columns=DESIGN_COLUMNS)
    result = DesignResult(table, [DesignCase("c", [], 1.0, 60, scene)], {})
    write_report(tmp_path, result, TINY, [], Design(risk_category="III"),
                 {"wall_time_s": 1.0, "flow_phase_wall_s": 0.0, "workers": 1, "executor": "local", "batch_size": 8})
    summary = json.loads((tmp_path / "design.json").read_text())
    per = table.groupby("realisation")["peak_force_N"].max()
    p90 = np.quantile(per[per > 0], 0.9, method="inverted_cdf")
    rec = summary["recommended"]
    assert rec["fractile"] == "P90" and rec["importance_I_tsu"] == 1.25
    assert rec["demands"]["peak_force_N"]["quantile"] == pytest.approx(p90)
    assert rec["demands"]["peak_force_N"]["value"] == pytest.approx(1.25 * p90)
    strikes = summary["strikes"]
    assert strikes["strikes"] == len(table[table["strike"] > 0]) and strikes["striking_realisations"] == 40
    assert strikes["strikes_per_striking_realisation"]["max"] == 4
    assert strikes["oblique_share"] == pytest.approx((table["obliquity_deg"] > 30).sum() / strikes["strikes"])
    page = (tmp_path / "design.md").read_text()
    assert "**Recommended: P90 given a strike x I_tsu (1.25).**" in page and "the tool's convention" in page.lower()
    assert f"**{1.25 * p90 / 1e3:.3g} kN**" in page and "| | given a strike |" in page
    assert "e+0" not in page.split("## ASCE")[0]  # forces in kN or MN, not in raw newtons


def test_the_front_celerity_is_stokers_bore_speed_on_a_stoker_record():
    """Stoker's bore (5.62 m impoundment on a 1.29 m wet bed, the street example's nominal case)
    sampled as a record: the front's speed 3 to 8 column widths upstream of the face is the
    bore's celerity S (7.0 m/s), 1.75 times the 4.0 m/s water behind it."""
    from analytical.dambreak import StokerSolution
    from orchestrator.studies.design_strikes import front_celerity

    sol = StokerSolution(5.62, 1.29)
    x, y, t = np.arange(-1.0, 40.01, 0.25), np.linspace(-10.0, 10.0, 3), np.arange(2.0, 6.0, 0.005)
    depth = np.array([sol.profile(x, max(tk, 1e-9)).depth_m for tk in t])
    eta = np.broadcast_to(depth[:, :, None], (t.size, x.size, y.size)).copy()
    flow = FlowField(t, x, y, np.linspace(0.0, 5.62, 3), 0.0, eta, np.zeros((t.size, x.size, y.size, 3, 3)))
    column = PlacedColumn(35.0, 0.0, Column(size_x_m=1.0, size_y_m=1.0, height_m=5.0))
    speed = sol.state.shock_speed_m_s
    assert front_celerity(flow, column) == pytest.approx(speed, rel=0.02)
    assert speed / sol.state.u2_m_s == pytest.approx(1.75, abs=0.01)
    far = PlacedColumn(80.0, 0.0, column.column)  # beyond the record: not measured
    assert front_celerity(flow, far) is None


def test_strikes_faster_than_their_water_are_counted_with_their_masses():
    """Three striking realisations: one struck at its water's speed, one at twice the fastest
    water it came in with, one ahead of the front (still water, 0 m/s) whose largest strike is
    the fast one; the summary counts the two, their median mass and the governing share."""
    rows = []
    for r, mass, strikes in ((0, 20000.0, [(1, 4.0, 4.0, 5e6)]), (1, 8000.0, [(1, 8.0, 4.0, 9e6)]),
                             (2, 3000.0, [(1, 8.5, 0.0, 9e6), (2, 1.0, 4.0, 1e6)])):
        for k, speed, water, force in strikes:
            rows.append({"case": "c", "realisation": r, "case_weight": 1.0, "sample_weight": 1 / 3, "body": "b",
                         "mass_kg": mass, "carried": True, "struck": True, "strikes": len(strikes), "strike": k,
                         "impact_speed_m_s": speed, "flow_speed_m_s": water, "flow_speed_max_m_s": water,
                         "face": "upstream", "obliquity_deg": 0.0, "eccentricity_m": 0.0, "torsion_Nm": 0.0,
                         "peak_force_N": force, "base_shear_N": force, "base_moment_Nm": force,
                         "displacement_m": 1e-9 * force})
    table = pd.DataFrame(rows, columns=DESIGN_COLUMNS)
    s = strike_summary(table, realisation_demands(table), {"c": 3.5})
    assert s["faster_than_the_water"] == 2 and s["faster_mass_kg"] == pytest.approx(5500.0)
    assert s["other_mass_kg"] == pytest.approx(3000.0 / 2 + 20000.0 / 2)
    assert s["largest_faster_than_the_water"] == pytest.approx(2 / 3)
    assert s["speed_over_fastest_water"]["max"] == pytest.approx(2.0)  # the still water's ratio left out
