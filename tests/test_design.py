"""Design studies (`debrisfoam design`): the exceedance estimator and its intervals against known
distributions, inundation cases combined by their weights as a closed-form mixture, the column's
base moment and displacement against the static cantilever, the draws, the realisations'
demands on a synthetic flow, the page, the verb's bad input (exit 2 naming the file and the
field), and the verb end to end on the tiny one-way scene with OpenFOAM."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.asce7 import STUDY_DEBRIS_STIFFNESS_N_M, asce7_design
from analytical.column import Column
from analytical.column_demand import column_demands, rigid_rotation, strike_demands
from analytical.column_fem import column_model, static_deflection
from analytical.exceedance import clopper_pearson, exceedance
from analytical.mdof import mdof_response
from analytical.pulses import HalfSine, Tabulated
from orchestrator.scene.schema import Design
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.design import DEMANDS, DESIGN_COLUMNS, DesignCase, DesignResult, allocate, design_batch, \
    design_starts
from orchestrator.studies.design_report import write_report
from orchestrator.transport.engine import TransportSettings, run_transport
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn
from tests.conftest import debris
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parent.parent
TINY = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"
FLUME = FlumeBounds((0.0, 2.0), (-0.3, 0.3), 0.0)
COLUMN = PlacedColumn(1.0, 0.0, Column(size_x_m=0.1, size_y_m=0.1, height_m=0.3, wall_thickness_m=0.005))
BODY = debris("debris1", (0.15, 0.06, 0.06), 0.236, (0.6, 0.0, 0.03), wall_thickness_m=0.005)


# --------------------------------------------------------------------------- the estimator
def test_the_curve_and_its_bands_cover_an_exponentials_truth_at_the_stated_rate():
    """400 samples of 200 from Exp(1): the pointwise Clopper-Pearson interval covers S(x) = e^-x
    at x = ln 2 and ln 10 in at least 95 % of them (it is exact-conservative), the DKW band covers
    the whole curve as often, and the P90 interval covers ln 10 as often (less the Monte Carlo
    scatter of 400 trials, about 1 %)."""
    rng = np.random.default_rng(7)
    trials, n = 400, 200
    cover = {"ln2": 0, "ln10": 0, "dkw": 0, "p90": 0}
    grid = np.linspace(0.0, 6.0, 601)
    for _ in range(trials):
        exc = exceedance([rng.exponential(1.0, n)])
        for name, x in (("ln2", math.log(2)), ("ln10", math.log(10))):
            lo, hi = exc.interval(exc.probability(x))
            cover[name] += bool(lo[0] <= math.exp(-x) <= hi[0])
        cover["dkw"] += bool(np.max(np.abs(exc.probability(grid) - np.exp(-grid))) <= exc.dkw())
        q = exc.quantile(0.9)
        cover["p90"] += bool(q.lower <= math.log(10) <= q.upper)
    for name, hits in cover.items():
        assert hits / trials >= 0.93, (name, hits / trials)
    # and the estimate itself converges: 20,000 samples put S(ln 10) within 3 standard errors of 0.1
    big = exceedance([rng.exponential(1.0, 20000)])
    assert big.probability(math.log(10))[0] == pytest.approx(0.1, abs=3 * math.sqrt(0.09 / 20000))


def test_quantiles_are_order_statistics_and_the_p99_of_a_small_sample_has_no_upper_end():
    values = np.arange(1.0, 101.0)  # 1 .. 100
    exc = exceedance([values])
    assert exc.quantile(0.5).value == 50.0 and exc.quantile(0.9).value == 90.0
    q = exc.quantile(0.5)
    assert q.lower < 50.0 < q.upper
    # the order-statistic interval for the median of 100 at 95 %: ranks 40 and 61 (binomial 0.5)
    assert 38.0 <= q.lower <= 41.0 and 60.0 <= q.upper <= 63.0
    assert exceedance([values[:50]]).quantile(0.99).upper is None  # 50 samples cannot bound P99 from above
    # exceedance beside a value, with Clopper-Pearson's interval on 10 of 100
    e = exc.exceeds(90.0)
    lo, hi = clopper_pearson(10, 100)
    assert e["probability"] == pytest.approx(0.10) and (e["lower"], e["upper"]) == pytest.approx((float(lo), float(hi)))


def test_non_strikes_are_zero_demands_in_the_curve():
    exc = exceedance([[0.0, 0.0, 0.0, 5.0, 10.0]])
    curve = exc.curve()
    assert list(curve["level"]) == [5.0, 10.0]
    assert curve["probability"] == pytest.approx([0.4, 0.2])
    assert exc.quantile(0.5).value == 0.0  # P50 falls among the realisations that never struck


def test_weights_combine_inundation_cases_as_a_mixture():
    # exactly: case A (weight 1) [1, 2, 3, 4], case B (weight 3) [10, 20]: P(X > 2.5) = 0.25 * 0.5 + 0.75 * 1
    exc = exceedance([[1, 2, 3, 4], [10, 20]], [1.0, 3.0])
    assert exc.probability(2.5)[0] == pytest.approx(0.875)
    assert exc.probability(15.0)[0] == pytest.approx(0.375)
    assert exc.sample_weights.sum() == pytest.approx(1.0)
    # the closed-form mixture 0.3 Exp(1) + 0.7 Exp(1/4), sampled 4,000 and 1,000 (not in proportion)
    rng = np.random.default_rng(3)
    exc = exceedance([rng.exponential(1.0, 4000), rng.exponential(4.0, 1000)], [0.3, 0.7])
    n_eff = 1.0 / (0.3 ** 2 / 4000 + 0.7 ** 2 / 1000)
    assert exc.n_eff == pytest.approx(n_eff)
    for x in (0.5, 2.0, 6.0):
        truth = 0.3 * math.exp(-x) + 0.7 * math.exp(-x / 4.0)
        se = math.sqrt(0.3 ** 2 * math.exp(-x) * (1 - math.exp(-x)) / 4000
                       + 0.7 ** 2 * math.exp(-x / 4) * (1 - math.exp(-x / 4)) / 1000)
        assert exc.probability(x)[0] == pytest.approx(truth, abs=4 * se)
        lo, hi = exc.interval(exc.probability(x))
        assert lo[0] <= truth <= hi[0]
    # realisations shared in proportion to the weights: the pooled sample's n_eff is its size
    counts = allocate(1000, [1.0, 3.0])
    assert counts == [250, 750]
    assert exceedance([np.ones(c) for c in counts], [1.0, 3.0]).n_eff == pytest.approx(1000)
    assert sum(allocate(7, [1, 1, 1])) == 7 and min(allocate(3, [100, 1, 1])) == 1


# --------------------------------------------------------------------------- column demands
@pytest.mark.parametrize("base", ["rigid", "calibrated"])
def test_a_slow_load_gives_the_static_cantilever(base):
    """Held for many periods: base shear P, base moment P h, top displacement the static
    deflection (rigid base: Timoshenko's closed form P h^2 (3H - h) / 6EI + P h / kGA)."""
    column = Column(base=base)
    h = float(column_model(column).node_height_m[60])
    d = column_demands(Tabulated([0.0, 2.0, 4.0], [0.0, 100.0, 100.0]), column, h, t=[3.5, 3.9])
    assert d.base_shear_N == pytest.approx(100.0, rel=1e-6)
    assert d.base_moment_Nm == pytest.approx(100.0 * h, rel=1e-6)
    static = static_deflection(column, h, column.height_m, 100.0)
    assert d.top_displacement_m == pytest.approx(static, rel=1e-5)
    if base == "rigid":
        H, EI, kGA = column.height_m, column.bending_stiffness_Nm2, column.shear_stiffness_N
        assert static == pytest.approx(100 * h * h * (3 * H - h) / (6 * EI) + 100 * h / kGA, rel=1e-9)


def test_the_codes_rectangular_pulse_is_read_through_its_duration_where_the_column_peaks():
    """A rectangular pulse of F lasting 2.5 first periods: the column's first mode swings to
    about (1 + e^(-zeta pi)) F halfway through a period and back to F at each whole one, so a
    response read only at the pulse's start and end sees F where the peak is nearly 2 F
    (Chopra 2017, section 4.7). The dense reading agrees with the MDOF response on a fine grid."""
    from analytical.pulses import Rectangular

    column = Column()
    period = 1.0 / float(column_model(column).frequencies_Hz[0])
    pulse = Rectangular(100.0, 2.5 * period)
    d = column_demands(pulse, column, 0.4)
    assert d.peak_base_shear_N > 1.7 * 100.0
    fine = np.linspace(0.0, 4.0 * period, 4001)
    assert d.peak_base_shear_N == pytest.approx(np.max(np.abs(mdof_response(pulse, column, 0.4, fine).response_N)),
                                                rel=2e-3)


def test_the_rigid_rotation_strains_nothing_and_the_shear_is_mdofs():
    column = Column()
    model = column_model(column)
    k = model.beam_stiffness_full
    assert np.max(np.abs(k @ rigid_rotation(model))) <= 1e-12 * np.max(np.abs(k.toarray()))
    pulse = HalfSine(171.0, 0.0047)
    d = column_demands(pulse, column, 0.3)
    shear = mdof_response(pulse, column, 0.3, d.time_s).response_N
    assert np.max(np.abs(d.base_shear_N - shear)) <= 1e-4 * np.max(np.abs(shear))
    # linear in the load; a load turned 90 degrees on a square column gives the same resultants
    twice = strike_demands(Tabulated(d.time_s[:50], 2 * pulse.force(d.time_s[:50])), (-1, 0, 0), column, 0.3)
    once = strike_demands(Tabulated(d.time_s[:50], pulse.force(d.time_s[:50])), (-1, 0, 0), column, 0.3)
    sideways = strike_demands(Tabulated(d.time_s[:50], pulse.force(d.time_s[:50])), (0, 1, 0), column, 0.3)
    for key in once:
        assert twice[key] == pytest.approx(2 * once[key], rel=1e-9)
        assert sideways[key] == pytest.approx(once[key], rel=1e-9)


# --------------------------------------------------------------------------- draws and realisations
def test_draws_are_reproducible_and_inside_the_ranges():
    spec = Design(mass_kg=(0.2, 0.4), heading_deg=(-30.0, 30.0), start_x_m=(0.4, 0.7), start_y_m=(-0.15, 0.15))
    starts = [design_starts([BODY], FLUME, COLUMN, spec, 0, r)[0] for r in range(200)]
    assert design_starts([BODY], FLUME, COLUMN, spec, 0, 17)[0] == starts[17]
    assert design_starts([BODY], FLUME, COLUMN, spec, 1, 17)[0] != starts[17]  # another case, other draws
    mass = np.array([b.mass_kg for b in starts])
    yaw = np.array([b.yaw_deg for b in starts])
    x = np.array([b.centre_m[0] for b in starts])
    assert mass.min() >= 0.2 and mass.max() <= 0.4 and mass.std() == pytest.approx(0.2 / math.sqrt(12), rel=0.15)
    assert yaw.min() >= -30 and yaw.max() <= 30 and x.min() >= 0.4 and x.max() <= 0.7
    assert all(b.centre_m[2] == BODY.centre_m[2] for b in starts)
    # without ranges: the body's own mass, its start about its own by the placement tolerance
    own = design_starts([BODY], FLUME, COLUMN, Design(), 0, 0)[0]
    assert own.mass_kg == BODY.mass_kg and abs(own.centre_m[0] - 0.6) <= 2 * 0.25 * 0.15 + 1e-12


def test_a_batch_gives_each_strikes_demands_and_zero_without_a_strike(current):
    flow, npz = current
    spec = Design(mass_kg=(0.2, 0.4))
    starts = [design_starts([BODY], FLUME, COLUMN, spec, 0, r) for r in range(2)]
    # a third realisation far downstream of the column never strikes it
    starts.append([debris("debris1", (0.15, 0.06, 0.06), 0.3, (1.6, 0.0, 0.03), wall_thickness_m=0.005)])
    settings = TransportSettings(first_pulse_only=True)
    rows = pd.DataFrame(design_batch([0, 1, 2], starts, FLUME, COLUMN, 1.3, npz, settings))
    assert list(rows.drop_duplicates("realisation")["realisation"]) == [0, 1, 2]
    assert rows.groupby("realisation")["struck"].first().tolist() == [True, True, False]
    none = rows[rows["realisation"] == 2]
    assert len(none) == 1 and none["strike"].iloc[0] == 0 and (none[list(DEMANDS)] == 0.0).all(axis=None)
    alone = run_transport(starts[0], FLUME, 1.3, flow=flow, column=COLUMN,
                          settings=TransportSettings(first_pulse_only=True, every_column_pulse=True))
    first = alone.impacts[alone.impacts["kind"] == "column"].iloc[0]
    mine = rows[rows["realisation"] == 0].reset_index(drop=True)
    assert mine.loc[0, "strike"] == 1
    assert mine.loc[0, "peak_force_N"] == pytest.approx(first["peak_force_N"], rel=1e-3)  # batched: to rounding
    pulse = alone.pulses[int(first["event"])]
    expected = strike_demands(pulse.force, pulse.normal, COLUMN.column, pulse.contact_height_m)
    for key, value in expected.items():
        assert mine.loc[0, key] == pytest.approx(value, rel=1e-3)
    assert mine.loc[0, "mass_kg"] == starts[0][0].mass_kg


def test_the_page_sets_asce_beside_the_curves(tmp_path):
    """A page from a hand-made table (no flow record: u_max falls back to the largest impact speed)."""
    scene = load_scene(TINY)
    rng = np.random.default_rng(0)
    rows = []
    for case, weight, n in (("deep", 0.75, 30), ("shallow", 0.25, 10)):
        for r in range(n):
            struck = r % 5 != 0
            f = float(rng.uniform(50, 200)) if struck else 0.0
            rows.append({"case": case, "realisation": r, "case_weight": weight, "sample_weight": weight / n,
                         "body": "debris1", "mass_kg": 0.236, "carried": True, "struck": struck, "strikes": int(struck),
                         "strike": int(struck), "face": "upstream" if struck else math.nan,
                         "impact_speed_m_s": 0.9 if struck else math.nan, "impact_height_m": 0.05 if struck else
                         math.nan, "peak_force_N": f, "base_shear_N": 1.2 * f, "base_moment_Nm": 0.05 * f,
                         "displacement_m": 1e-7 * f, "wall_time_s": 0.1})
    table = pd.DataFrame(rows, columns=DESIGN_COLUMNS)
    cases = [DesignCase("deep", [], 0.75, 30, scene), DesignCase("shallow", [], 0.25, 10, scene)]
    result = DesignResult(table, cases, {})
    spec = Design(risk_category="III")
    files = write_report(tmp_path, result, TINY, [], spec, {"wall_time_s": 1.0, "flow_phase_wall_s": 0.0,
                                                          "workers": 1, "executor": "local", "batch_size": 32})
    summary = json.loads((tmp_path / "design.json").read_text())
    assert set(files) == {"summary", "figure", "report"} and (tmp_path / "exceedance.png").stat().st_size > 10000
    assert summary["strike_probability"]["probability"] == pytest.approx(0.8)
    code = asce7_design(0.9, 0.236, STUDY_DEBRIS_STIFFNESS_N_M, scene.column.stiffness_N_m, 1.25)
    asce = summary["asce"]
    assert asce["importance_I_tsu"] == 1.25 and asce["governing"] == code.governing
    assert asce["values"][code.governing]["peak_force_N"] == pytest.approx(code.force_N)
    assert asce["load_height_m"] == pytest.approx(0.05)
    force = summary["demands"]["peak_force_N"]
    assert set(force["quantiles"]) == {"P50", "P90", "P99"} and set(force["asce"]) == {"k_s", "k_d"}
    expected = (0.75 * (table[table.case == "deep"].peak_force_N > code.force_N).mean()
                + 0.25 * (table[table.case == "shallow"].peak_force_N > code.force_N).mean())
    assert force["asce"][code.governing]["probability"] == pytest.approx(expected)
    page = (tmp_path / "design.md").read_text()
    assert "not a probabilistic tsunami hazard analysis" in page and "![exceedance](exceedance.png)" in page
    # each ASCE input says where it comes from: an untyped body, the study's k_d and its own mass
    assert "- k_d: the study's 1:40 container's k_d, 3.04e+06 N/m" in page and "- m_d: the heaviest body's own mass" in page
    assert "Table 6.8-1 (analytical/asce7.py) for design.risk_category III (the scene, the scene author's" in page
    # at laboratory scale the law is the study's, and P(exceed) is printed
    assert "- law: body debris1: container law" in page and "P(exceed k_s value)" in page
    assert "mass each body's own" in page  # one mass throughout: nothing was drawn
    # masses that were drawn (a catalogued body without design.mass_kg) are said with their range
    table.loc[table.index[::2], "mass_kg"] = 2300.0
    table.loc[table.index[1::2], "mass_kg"] = 30480.0
    write_report(tmp_path, DesignResult(table, cases, {}), TINY, [], spec,
                 {"wall_time_s": 1.0, "flow_phase_wall_s": 0.0, "workers": 1, "executor": "local", "batch_size": 32})
    assert "empty-to-loaded range (drawn 2,300 to 30,480 kg)" in (tmp_path / "design.md").read_text()


# --------------------------------------------------------------------------- the verb
@pytest.mark.parametrize("sets, field", [
    (["design.mass_kg=[0.4, 0.2]"], "design.mass_kg"),
    (["design.realisations=0"], "design.realisations"),
    (["design.colour=red"], "design.colour"),
    (["design.risk_category=V"], "design.risk_category"),
    (["design.inundation=[{set: {reservoir.depth_m: -1}}]"], "design.inundation.0.set: reservoir.depth_m"),
    (["design.inundation=[{weight: 0}]"], "design.inundation.0.weight"),
])
def test_a_bad_design_section_is_exit_2_naming_the_file_and_field(tmp_path, sets, field):
    args = [a for s in sets for a in ("--set", s)]
    proc = run_cli("design", str(TINY), "-o", str(tmp_path / "study"), *args)
    assert proc.returncode == 2, proc.stderr
    assert field in proc.stderr and "tiny-oneway-strike.yaml" in proc.stderr, proc.stderr
    assert not (tmp_path / "study").exists()  # nothing rendered


def test_a_study_folder_is_not_replaced_without_force(tmp_path):
    out = tmp_path / "study"
    out.mkdir()
    (out / "design.csv").write_text("x\n")
    proc = run_cli("design", str(TINY), "-o", str(out))
    assert proc.returncode == 2 and "--force" in proc.stderr


def test_the_design_value_in_design_json_and_on_the_page_agree(tmp_path, monkeypatch, capfd, current):
    """`design --json` end to end on a synthetic current (no OpenFOAM, as tests/test_design_guards.py
    runs it): design.json holds the recommended design value with its band, fractile, units, strike
    count and what binds F_i; the page prints the same figures and --json the same value."""
    import orchestrator.studies.design as design_module
    from orchestrator.cli import main
    from orchestrator.studies.design_advice import fmt_demand

    flow, npz = current
    scene = load_scene(TINY)
    monkeypatch.setattr(design_module, "ensemble_flow", lambda path, folder, sets, **kw: (scene, folder, flow, npz))
    monkeypatch.setattr(design_module, "site_flow_speed", lambda case, scene: None)
    out = tmp_path / "study"
    (out / "flows").mkdir(parents=True)  # where the flows would be (a study folder may hold them already)
    code = main(["design", str(TINY), "-n", "6", "-o", str(out), "--workers", "1", "--batch-size", "6", "--json",
                 "--set", "design.risk_category=III"])
    assert code == 0
    head = json.loads(capfd.readouterr().out)
    summary = json.loads((out / "design.json").read_text())
    page, table = (out / "design.md").read_text(), pd.read_csv(out / "design.csv")
    rec, asce = summary["recommended"], summary["asce"]
    strikes = int((table["strike"] > 0).sum())
    assert strikes > 0 and rec["strikes"] == summary["strikes"]["strikes"] == strikes
    assert rec["striking_realisations"] == table.groupby("realisation")["struck"].any().sum()
    assert rec["fractile"] == "P90" and rec["given"] == "a strike" and rec["importance_I_tsu"] == 1.25
    assert rec["asce_binds"] == asce["binding"] and rec["asce_force_N"] == asce["force_N"]
    assert {k: d["unit"] for k, d in rec["demands"].items()} == {k: unit for k, (_, unit) in DEMANDS.items()}
    force = rec["demands"]["peak_force_N"]
    struck = table.loc[table["strike"] > 0, "peak_force_N"]
    tol = 1e-9 * struck.abs().max()  # design.csv and design.json round to 10 significant digits
    assert struck.min() - tol <= force["quantile"] <= struck.max() + tol
    assert force["value"] == pytest.approx(1.25 * force["quantile"], rel=1e-12)
    assert force["lower"] <= force["value"] and (force["upper"] is None or force["upper"] >= force["value"])
    # the page: the same value, band and fractile, the same strike count, the same binding
    assert "**Recommended: P90 given a strike x I_tsu (1.25).**" in page
    for key, d in rec["demands"].items():
        upper = fmt_demand(d["upper"], d["unit"]) if d["upper"] is not None else "(more realisations needed)"
        assert (f"| {summary['demands'][key]['label']} | {fmt_demand(d['quantile'], d['unit'])} | "
                f"**{fmt_demand(d['value'], d['unit'])}** | {fmt_demand(d['lower'], d['unit'])} to {upper} |") in page
    assert f"- {strikes} column strikes in {rec['striking_realisations']} striking realisations" in page
    binds = {"k_s": "the k_s line", "k_d": "the k_d line"}.get(asce["binding"], f"the {asce['binding']}")
    assert f"bound by {binds}" in page
    assert "member's largest displacement" in page and "top displacement" not in page
    # the band's limits: a laboratory scene's law is the calibrated one; a full-scale scene states its
    # own, whose uncertainty no published test gives
    from orchestrator.studies.design_advice import STATED_LAW_UNKNOWN, advice_lines
    assert not asce["prototype"] and "a full-scale law's difference from the laboratory one" in page
    assert STATED_LAW_UNKNOWN not in page
    assert STATED_LAW_UNKNOWN in "\n".join(advice_lines({**summary, "asce": {**asce, "prototype": True}}))
    # --json prints design.json's value
    assert head["recommended"]["demands"] == {k: {n: d[n] for n in ("value", "lower", "upper", "unit")}
                                              for k, d in rec["demands"].items()}
    assert head["recommended"]["strikes"] == strikes and head["recommended"]["asce_binds"] == asce["binding"]


@pytest.mark.openfoam
def test_the_verb_runs_each_inundation_case_once_and_writes_the_page(tmp_path, openfoam):
    out = tmp_path / "study"
    cases = "design.inundation=[{name: base, weight: 3}, {name: deep, set: {reservoir.depth_m: 0.18}, weight: 1}]"
    proc = run_cli("design", str(TINY), "-n", "8", "-o", str(out), "--set", cases, "--set",
                   "design.mass_kg=[0.2, 0.3]", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    head = json.loads(proc.stdout)
    table = pd.read_csv(out / "design.csv")
    assert list(table.columns) == DESIGN_COLUMNS and head["realisations"] == 8
    assert table.groupby("case").size().to_dict() == {"base": 6, "deep": 2}
    assert table["mass_kg"].between(0.2, 0.3).all() and table["struck"].any()
    summary = json.loads((out / "design.json").read_text())
    assert [c["name"] for c in summary["cases"]] == ["base", "deep"]
    assert summary["asce"]["values"] is not None and summary["asce"]["cases"][0]["u_max_m_s"] > 0
    for name in ("design.md", "exceedance.png"):
        assert (out / name).is_file()
    run_json = (out / "flows" / "deep" / "run.json").read_text()
    proc = run_cli("design", str(TINY), "-n", "8", "-o", str(out), "--set", cases, "--set",
                   "design.mass_kg=[0.2, 0.3]", "--force", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (out / "flows" / "deep" / "run.json").read_text() == run_json  # the flows are reused
    again = pd.read_csv(out / "design.csv")
    pd.testing.assert_frame_equal(again.drop(columns="wall_time_s"), table.drop(columns="wall_time_s"))


def test_a_catalogued_container_is_drawn_between_its_empty_and_loaded_masses():
    from analytical.catalogue import mass_range_kg
    from orchestrator.studies.design_table import mass_range

    body = debris(name="c", size_m=(6.058, 2.438, 2.591), mass_kg=2300.0, centre_m=(0.0, 0.0, 1.3))
    empty, loaded = mass_range_kg("container-20ft")
    assert mass_range(body, Design(), "container-20ft-empty") == (empty, loaded)
    assert loaded > 10 * empty  # 2,300 kg empty to 30,480 kg at the maximum gross mass
    # the design section's own range wins; an untyped body keeps its mass
    assert mass_range(body, Design(mass_kg=[3000.0, 4000.0]), "container-20ft-empty") == (3000.0, 4000.0)
    assert mass_range(body, Design(), None) == (2300.0, 2300.0)
    # the study's 1:40 model has no empty and loaded pair: its own mass
    assert mass_range(body, Design(), "container-20ft-study-1to40") == (2300.0, 2300.0)


def test_the_shipped_street_scene_plans_every_case_near_the_lab_scenes_cells_and_draws_20ft_masses():
    """cases/design-street.yaml (issue 32's design example): each inundation case loads, plans
    one-way on the order of the 1-debris scene's 136k cells, keeps the mesh rules (2 cells across
    the column, 1.5 across the container, 4 over the impoundment), and its draws stay between the
    20-ft container's empty and loaded masses."""
    from analytical import catalogue
    from analytical.catalogue import mass_range_kg
    from orchestrator.plan.planner import plan_case
    from orchestrator.studies.design_report import input_sources
    from orchestrator.studies.design import design_cases
    from orchestrator.studies.design_table import debris_types
    from orchestrator.transport.case_transport import scene_bodies
    from orchestrator.scene.schema import column_for_analysis

    path = ROOT / "cases" / "design-street.yaml"
    spec = load_scene(path).design
    cases = design_cases(path, [], spec)
    assert [c.name for c in cases] == ["low", "nominal", "high"]
    assert sum(c.realisations for c in cases) == spec.realisations
    empty, loaded = mass_range_kg("container-20ft")
    for k, case in enumerate(cases):
        scene = case.scene
        plan = plan_case(scene, str(path))
        assert plan.debris_coupling == "one-way" and plan.cell_count < 300_000
        cell = scene.mesh.cell_size_m
        assert scene.column.size_x_m / cell >= 2 and min(scene.debris[0].size_m[1:]) / cell >= 1.5
        assert scene.reservoir.depth_m / cell >= 4
        # the bore the case asks for sized its reservoir: Stoker's plateau depth above the wet bed
        assert scene.reservoir.depth_m > scene.inundation.depth_m > scene.bed.wet_depth_m
        bodies = scene_bodies(scene)
        column = PlacedColumn(scene.column.x_m, scene.column.y_m, column_for_analysis(scene))
        half = scene.flume.width_m / 2
        flume = FlumeBounds((-1.0, scene.column.x_m + 20.0), (-half, half), 0.0)
        masses = np.array([design_starts(bodies, flume, column, scene.design, k, r, types=debris_types(scene))[0].mass_kg
                           for r in range(200)])
        assert masses.min() >= empty and masses.max() <= loaded
        assert masses.max() - masses.min() > 0.8 * (loaded - empty)  # drawn across the range, not at one mass
    # the page's ASCE inputs: the scene's own k_d and contact law (no full-scale source) and the loaded 20-ft mass
    sources = input_sources(cases[0].scene, spec, [catalogue.debris_type("container-20ft-empty")])
    assert sources["k_d"] == "the scene's design.debris_stiffness_N_m (the scene author's statement)"
    assert "container-20ft" in sources["m_d"] and catalogue.SOURCES["gross20"] in sources["m_d"]
    assert "contact.stiffness_N_m, contact.damping_ratio (the scene author's statement; no full-scale" in sources["law"]
    assert "rc-square 1 m" in sources["k_s"]
