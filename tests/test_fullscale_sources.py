"""Full-scale debris from full-scale sources (issue 48 item 1): the published figures as read, the
design's Froude-scaled law beside them, and the calibration the sources do (not) allow.

Each literal below is written a second time from the source text it cites, so a typo in
analytical/fullscale_sources.py fails here.
"""
from __future__ import annotations

import math

import pytest

from analytical.catalogue import debris_type
from analytical.contact_law import CONTAINER_DAMPING_RATIO, CONTAINER_STIFFNESS_N_M, ContactLaw, contact_law
from analytical.errors import InputError
from analytical.fullscale_check import (
    agreeing_test,
    calibration_possible,
    compare,
    fit_law,
    froude_scaled_design_law,
    held_out_check,
    law_strike,
    lehigh_series_bound,
)
from analytical.fullscale_sources import (
    CITATIONS,
    FULL_SCALE_TESTS,
    NOT_FOUND,
    SOURCE_RECORDS,
    FullScaleTest,
    fullscale_test,
    record,
)
from orchestrator.scene.scenefile import load_scene
from tests.conftest import ROOT

# (key, printed value, printed unit, source key): as read in the cited text.
PUBLISHED = [
    # the reference study, Sec. 3.2.3: "following Clause 6.11.6, the orientation is equal to 0.65 for shipping containers"
    ("asce_Co_container", 0.65, "1", "study"),
    # the reference study, Sec. 3.2.3: "the importance factor was selected to be one, ... Tsunami Risk Category of II"
    ("asce_Itsu_II", 1.0, "1", "study"),
    # the reference study, eqs. [8]-[10] and Clause 6.11.8
    ("asce_Fi", "F_i = I_tsu C_o F_ni", "N", "study"),
    ("asce_Fni", "F_ni = u_max sqrt(k m_d)", "N", "study"),
    ("asce_td", "t_d = 2 m_d u_max / F_ni", "s", "study"),
    # the reference study, Sec. 2.1 on Clause 6.11.2
    ("asce_k", "the lesser of the debris' effective stiffness and the lateral stiffness of the impacted structural "
               "element", "N/m", "study"),
    ("asce_pulse", "rectangular pulse of F_i over t_d", "N", "study"),
    # Riggs et al. (2014) JOMAE 136(4) 041603, abstract: "a 1:5 scale shipping container model was used for in-water tests"
    ("riggs_model_scale", 5.0, "1", "riggs2014"),
    # Lehigh Resolve vol. 2 (2012): "a standard, 3.5-ton, 20-foot intermodal shipping container on 30-foot cables"
    ("lehigh_container_weight", 3.5, "short ton", "lehigh2012"),
    ("lehigh_pendulum_length", 30.0, "ft", "lehigh2012"),
    # ibid.: "impact events that were low velocity, 2 to 4 mph"
    ("lehigh_speed_low", 2.0, "mph", "lehigh2012"),
    ("lehigh_speed_high", 4.0, "mph", "lehigh2012"),
    # ibid.: "fully loaded, one container can weigh 53,000 pounds"
    ("lehigh_loaded_weight", 53000.0, "lb", "lehigh2012"),
    # NSF Science Nation (2014): "a five thousand pound shipping container"; "forces as high as half a million
    # pounds"; "maybe 100th of a second"
    ("nsf_container_weight", 5000.0, "lb", "nsf2014"),
    ("nsf_peak_force", 500000.0, "lbf", "nsf2014"),
    ("nsf_duration", 0.01, "s", "nsf2014"),
    # Adv. Struct. Eng. doi:10.1177/1369433216668361, introduction: "a tare weight of 2300 kg"
    ("ase_tare_20ft", 2300.0, "kg", "ase2017"),
    # Purdue release, ScienceDaily 2013-02-05: "60,000-pound fully loaded"; "1,000-pound default log"
    ("purdue_loaded_container", 60000.0, "lb", "purdue2013"),
    ("purdue_default_log", 1000.0, "lb", "purdue2013"),
    # Haehnel & Daly (2002) ERDC/CRREL TR-02-2, abstract: "an effective contact stiffness of 2.4 MN/m"
    ("haehnel_log_stiffness", 2.4, "MN/m", "haehnel2002"),
]


@pytest.mark.parametrize("key, value, unit, source", PUBLISHED, ids=[p[0] for p in PUBLISHED])
def test_the_published_figures_are_held_as_read(key, value, unit, source):
    r = record(key)
    assert (r.value, r.unit, r.source) == (value, unit, source)
    assert r.found and r.citation == CITATIONS[source] and r.where


def test_every_record_is_published_or_said_not_found():
    assert {r.key for r in SOURCE_RECORDS if r.found} == {p[0] for p in PUBLISHED}
    for r in SOURCE_RECORDS:
        if not r.found:
            assert r.source is None and r.where.startswith("not found"), r.key
    # what a prototype scene must state itself: ASCE 7-22 Table 6.11-2 (8 values), the simplified
    # static load, FEMA P-646 (2019) and the three full-scale papers' data
    assert len(NOT_FOUND) == 13
    assert sum(k.startswith("asce_table_6_11_2_") for k in NOT_FOUND) == 8
    assert {"asce_simplified_static_load", "fema_p646_2019", "piran_aghl_2014_2015_tests", "riggs_2014_tests",
            "ko_2015_tests"} <= set(NOT_FOUND)


def test_si_conversions_are_exact():
    assert record("nsf_container_weight").si == pytest.approx(2267.96185, rel=1e-12)
    assert record("lehigh_container_weight").si == pytest.approx(3175.146590, rel=1e-12)
    assert record("nsf_peak_force").si == pytest.approx(2.2241108076e6, rel=1e-10)
    assert record("lehigh_speed_high").si == pytest.approx(1.78816, rel=1e-12)
    assert record("haehnel_log_stiffness").si == 2.4e6
    assert record("asce_td").si is None and record("fema_p646_2019").si is None


def test_no_full_scale_test_record_is_complete():
    """None of the sources pairs a speed, a mass and a peak force from one test: nothing to calibrate on."""
    assert [t.name for t in FULL_SCALE_TESTS if t.complete] == []
    press = fullscale_test("lehigh-20ft-pendulum-series (press reports)")
    assert press.missing == ("velocity_m_s", "mass_kg")
    assert press.peak_force_N == pytest.approx(500000 * 4.4482216152605) and press.duration_s == 0.01
    assert not calibration_possible()


def test_the_stand_in_is_the_lab_law_froude_scaled_and_the_catalogue_carries_none():
    law = froude_scaled_design_law()
    assert law.stiffness_N_m == pytest.approx(CONTAINER_STIFFNESS_N_M * 40 ** 2) == pytest.approx(1.0144e8)
    assert law.damping_ratio == CONTAINER_DAMPING_RATIO  # dimensionless: Froude scaling keeps it
    assert froude_scaled_design_law(10.0).stiffness_N_m == pytest.approx(CONTAINER_STIFFNESS_N_M * 100)
    for name in ("container-20ft-empty", "container-40ft-loaded"):
        assert debris_type(name).contact_stiffness_N_m is None and debris_type(name).kd_N_m is None


def _street_law() -> ContactLaw:
    """The contact law cases/design-street.yaml states for its container (an assumed stand-in)."""
    c = load_scene(ROOT / "cases" / "design-street.yaml").debris[0].contact
    return contact_law(c.law, c.stiffness_N_m, c.damping_ratio, c.restitution)


def test_the_design_law_cannot_be_checked_against_a_full_scale_test():
    """(b) The check the issue asks for is refused: the only full-scale force found has no speed or mass."""
    press = fullscale_test("lehigh-20ft-pendulum-series (press reports)")
    with pytest.raises(InputError, match="gives no velocity_m_s, mass_kg: it cannot check a law"):
        compare(_street_law(), press)
    assert agreeing_test(_street_law()) is None and agreeing_test(froude_scaled_design_law()) is None


def test_the_design_law_beside_the_lehigh_series_bound():
    """(b) What can be said: at the top of Lehigh's elastic speeds (4 mph) the street scene's stated law peaks at
    48-57 % of the programme's largest quoted force (half a million pounds), its duration 11-13 ms against
    'maybe 100th of a second'. A bound, not a calibration: the quoted force is tied to no speed or mass."""
    rows = {(r["mass_source"], round(r["velocity_m_s"], 5)): r for r in lehigh_series_bound(_street_law())}
    top_light, top_heavy = rows[("nsf_container_weight", 1.78816)], rows[("lehigh_container_weight", 1.78816)]
    assert top_light["law_peak_N"] == pytest.approx(1.0635e6, rel=1e-3)
    assert top_heavy["law_peak_N"] == pytest.approx(1.2584e6, rel=1e-3)
    assert top_light["ratio"] == pytest.approx(0.478, abs=1e-3) and top_heavy["ratio"] == pytest.approx(0.566, abs=1e-3)
    assert top_light["law_duration_s"] == pytest.approx(0.0109, abs=1e-4)
    assert top_heavy["law_duration_s"] == pytest.approx(0.0129, abs=1e-4)
    # below the quoted largest force at every stated speed and mass: the law does not exceed it
    assert all(r["ratio"] < 1.0 for r in rows.values())


def test_no_held_out_check_is_possible_with_the_sources_found():
    """(c) Two complete records are needed (fit one, hold out one); the sources give none."""
    a, b = FULL_SCALE_TESTS[0], FULL_SCALE_TESTS[1]
    with pytest.raises(InputError, match="needs two complete full-scale records"):
        held_out_check(a, b)
    with pytest.raises(InputError, match="nothing to fit"):
        fit_law(a)


def test_the_calibration_machinery_recovers_a_known_law():
    """The fit and hold-out run on SYNTHETIC records (not published data), made by a known spring and
    dashpot: a record typed in from the papers goes through the same code."""
    truth = ContactLaw(5.0e7, 0.2, "synthetic")
    s1, s2 = law_strike(truth, 1.5, 2300.0), law_strike(truth, 1.0, 20000.0)
    one = FullScaleTest("synthetic-1", (), "synthetic", 1.5, 2300.0, s1.peak_force_N, s1.duration_s)
    two = FullScaleTest("synthetic-2", (), "synthetic", 1.0, 20000.0, s2.peak_force_N, s2.duration_s)
    law, check = held_out_check(one, two, damped=True)
    assert law.stiffness_N_m == pytest.approx(5.0e7, rel=1e-6) and law.damping_ratio == pytest.approx(0.2, abs=1e-6)
    assert check.ratio == pytest.approx(1.0, abs=1e-6) and check.within()
    # a linear spring through the peak: k = (F / v)^2 / m, the undamped half-sine's v sqrt(k m)
    spring = fit_law(one)
    assert spring.stiffness_N_m == pytest.approx((s1.peak_force_N / 1.5) ** 2 / 2300.0)
    assert law_strike(spring, 1.5, 2300.0).peak_force_N == pytest.approx(s1.peak_force_N, rel=1e-6)
    # the Froude-scaled law against the synthetic record: named off when beyond 30 %
    off = compare(froude_scaled_design_law(), one)
    assert not off.within() and "it is off" in off.outcome()
    # what lets a page print P(exceed): a law within 30 % of a complete record's peak
    assert agreeing_test(truth, [one, two]).test == "synthetic-1" and agreeing_test(froude_scaled_design_law(), [one]) is None
    assert math.isclose(off.ratio, off.law_peak_N / s1.peak_force_N)
    with pytest.raises(InputError, match="must differ"):
        held_out_check(one, one)
