"""The contact law: its rigid-wall restitution against the integrated impact, the strike's
geometry and added mass, its calibration on the study's Table 2 through the study's own fit
(a test that can fail), Table 1 as the check, bad input, and the report."""

import math

import numpy as np
import pytest

from analytical.added_mass import STUDY_CONTAINER_ADDED_MASS
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M, STUDY_TABLE2_MDOF
from analytical.column import Column
from analytical.contact_calibration import (
    FIGURES,
    STUDY_COLUMN,
    contact_drop,
    lowered,
    scatter,
    strike_population,
    table2_standard_errors,
    unit_figures,
)
from analytical.contact_law import (
    ASCE7_KD,
    CONTAINER,
    STUDY_TABLE1_EVENT,
    ContactLaw,
    box_inertia,
    column_impact,
    contact_law,
    damping_for_restitution,
    study_fit,
    wall_restitution,
)
from analytical.errors import InputError
from analytical.impact import Body, RigidWall, impact


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2, 0.5, 0.8])
def test_wall_restitution_closed_form_matches_the_integrated_impact(zeta):
    body = Body.particle(0.236, (-1.6, 0.0, 0.0))
    result = impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), stiffness_N_m=CONTAINER.stiffness_N_m,
                    damping_ratio=zeta)
    assert result.restitution == pytest.approx(wall_restitution(zeta), abs=2e-4)


def test_undamped_wall_strike_is_haehnel_and_dalys_half_sine():
    m, v, k = 0.236, 1.5, CONTAINER.stiffness_N_m
    body = Body.particle(m, (-v, 0.0, 0.0))
    result = impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), stiffness_N_m=k)
    assert result.peak_force_N == pytest.approx(v * math.sqrt(k * m), rel=1e-3)
    assert result.duration_s == pytest.approx(math.pi * math.sqrt(m / k), rel=1e-3)
    assert result.impulse_Ns == pytest.approx(2 * m * v, rel=1e-3)


@pytest.mark.parametrize("e", [1.0, 0.9, 0.5, 0.2])
def test_restitution_and_damping_ratio_invert_each_other(e):
    assert wall_restitution(damping_for_restitution(e)) == pytest.approx(e, abs=1e-10)


def test_an_end_on_strike_carries_the_lengthwise_added_mass_and_an_eccentric_one_less():
    head_on = column_impact(CONTAINER, 1.5, 0.4)
    # m_eff head-on = m (1 + C_a surge); the rotation does not enter at the nose's centre
    assert head_on.effective_mass_kg == pytest.approx(0.236 + STUDY_CONTAINER_ADDED_MASS.masses_kg[0], rel=1e-9)
    bare = column_impact(CONTAINER, 1.5, 0.4, added_mass_coefficient=0.0)
    assert bare.effective_mass_kg == pytest.approx(0.236, rel=1e-9)
    corner = column_impact(CONTAINER, 1.5, 0.4, lateral_offset_m=0.03, vertical_offset_m=0.03)
    assert corner.effective_mass_kg < 0.7 * head_on.effective_mass_kg
    # a lighter contact: a shorter pulse (duration ~ sqrt(m_eff))
    assert corner.duration_s < head_on.duration_s
    # linear law: the pulse scales with the speed, its duration does not change
    double = column_impact(CONTAINER, 3.0, 0.4)
    assert double.peak_force_N == pytest.approx(2 * head_on.peak_force_N, rel=1e-6)
    assert double.duration_s == pytest.approx(head_on.duration_s, rel=1e-9)


def test_the_studys_fit_of_a_strikes_base_shear_recovers_an_undamped_half_sine():
    # an undamped contact on the stiff column is nearly a half-sine: the fit gives it back
    law = ContactLaw(1.1e5, 0.0)
    r = column_impact(law, 1.5, 0.4)
    f = study_fit(r, 0.4)
    assert f.magnitude_N == pytest.approx(r.peak_force_N, rel=0.01)
    assert f.duration_s == pytest.approx(r.duration_s, rel=0.01)
    assert f.impulse_Ns == pytest.approx(r.impulse_Ns, rel=0.01)
    assert abs(f.start_s) < 1e-4


def test_table2_standard_errors():
    se = table2_standard_errors()
    assert se["peak_force_N"] == pytest.approx(math.hypot(62.91 / math.sqrt(22), 171.07 * 0.0294 / 1.6), rel=0.02)
    assert se["duration_s"] == pytest.approx(math.hypot(0.0005 / math.sqrt(22), 1e-4 / math.sqrt(12)), rel=1e-9)


def test_population_has_the_studys_water_levels():
    p = strike_population(64)
    assert p.water_level_m.min() >= 0.16 and p.water_level_m.max() <= 0.50
    assert np.mean(p.water_level_m) == pytest.approx(0.40, abs=0.01)
    assert np.all(np.abs(p.lateral_offset_m) <= 0.03) and np.all(np.abs(p.obliquity_deg) <= 15.0)
    flat = strike_population(8, geometry=False)
    assert np.all(flat.lateral_offset_m == 0.0) and np.all(flat.obliquity_deg == 0.0)


#: The rigid-base column (88.4 Hz), for the scatter test.
RIGID = Column()


@pytest.mark.slow
def test_the_shipped_law_reproduces_table_2_through_the_studys_fit_and_is_the_calibrations_minimum():
    """The stored constants, struck over the calibration population and fitted as the study
    did on the study's column (its base tuned to the measured 70 Hz, STUDY_COLUMN), give Table 2's
    three means within 2 standard errors each, with the calibration's chi-square (1.21); a
    stiffness 13 % either side at the same damping (off the valley the -1.00 correlation draws) is
    worse by more than 2. (The objective jumps where a strike's fit changes local minimum, so a
    local Gauss-Newton step is no test of the minimum; the bracket is.)"""
    population = strike_population()

    def chi2(law):
        means = unit_figures(law, population, STUDY_COLUMN).means()
        se = table2_standard_errors(means)
        z = np.array([(means[k] - STUDY_TABLE2_MDOF[k][0]) / se[k] for k in FIGURES])
        return z, float(z @ z)

    z, best = chi2(CONTAINER)
    assert np.all(np.abs(z) < 2.0), z
    assert best < 2.0
    for factor in (0.87, 1.13):
        _, other = chi2(ContactLaw(CONTAINER.stiffness_N_m * factor, CONTAINER.damping_ratio))
        assert other > best + 2.0, (factor, other, best)
    # an undamped law cannot: with the same stiffness its impulse is far above Table 2's
    elastic, _ = chi2(ContactLaw(CONTAINER.stiffness_N_m, 0.0))
    assert elastic[2] > 3.0


@pytest.mark.slow
def test_table_1s_event_lies_in_the_upper_tail_of_the_laws_scatter():
    figures = unit_figures(CONTAINER, strike_population(16, seed=7), RIGID)
    sc = scatter(figures, draws=20_000)
    # the study's elastic event: stronger than most of the law's strikes at its speed
    assert sc.table1_percentiles["impulse_Ns"] > 90.0
    assert sc.means["duration_s"] == pytest.approx(STUDY_TABLE2_MDOF["duration_s"][0], rel=0.05)
    # the law's spread is narrower than the study's (speed and geometry alone)
    assert sc.stds["peak_force_N"] < STUDY_TABLE2_MDOF["peak_force_N"][1]


def test_the_rigid_kd_law_is_the_asce_upper_bound():
    r = column_impact(CONTAINER, STUDY_TABLE1_EVENT.velocity_m_s, STUDY_TABLE1_EVENT.height_m)
    kd = column_impact(ASCE7_KD, STUDY_TABLE1_EVENT.velocity_m_s, STUDY_TABLE1_EVENT.height_m)
    assert kd.peak_force_N > 4 * r.peak_force_N and kd.duration_s < r.duration_s / 4
    assert 20 < STUDY_DEBRIS_STIFFNESS_N_M / CONTAINER.stiffness_N_m < 80


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"stiffness_N_m": 0.0}, "contact.stiffness_N_m"),
        ({"damping_ratio": -0.1}, "contact.damping_ratio"),
        ({"restitution": 0.0}, "contact.restitution"),
        ({"restitution": 1.2}, "contact.restitution"),
        ({"damping_ratio": 0.1, "restitution": 0.5}, "contact.restitution"),
        ({"law": "rubber"}, "contact.law"),
    ],
)
def test_bad_contact_law_names_the_field(kwargs, field):
    with pytest.raises(InputError) as err:
        contact_law(**kwargs)
    assert err.value.field == field


@pytest.mark.parametrize(
    "kwargs, field",
    [({"velocity_m_s": 0.0}, "--velocity"), ({"velocity_m_s": 1.5, "height_m": 0.81}, "--height"),
     ({"velocity_m_s": 1.5, "height_m": -0.1}, "--height"), ({"velocity_m_s": 1.5, "obliquity_deg": 90}, "--obliquity"),
     ({"velocity_m_s": 1.5, "lateral_offset_m": 0.04}, "lateral_offset_m")],
)
def test_bad_strike_names_the_flag(kwargs, field):
    with pytest.raises(InputError) as err:
        column_impact(CONTAINER, **kwargs)
    assert err.value.field == field


def test_restitution_key_gives_that_restitution_on_a_wall():
    law = contact_law(restitution=0.4)
    body = Body.particle(0.236, (-1.0, 0.0, 0.0))
    r = impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), **law.options())
    assert r.restitution == pytest.approx(0.4, abs=2e-4)
    assert law.stiffness_N_m == CONTAINER.stiffness_N_m


def test_the_shipped_law_is_damped_and_soft():
    assert 0.0 < CONTAINER.wall_restitution < 0.8
    assert CONTAINER.to_dict()["law"] == "container"
    assert CONTAINER.pair().stiffness_N_m == pytest.approx(CONTAINER.stiffness_N_m / 2)


def test_box_inertia_of_a_thin_walled_box_exceeds_the_solid_box():
    solid = box_inertia((0.15, 0.06, 0.06), 0.236, None)
    hollow = box_inertia((0.15, 0.06, 0.06), 0.236, 0.005)
    assert solid[0] == pytest.approx(0.236 * (0.06**2 + 0.06**2) / 12)
    assert all(h > s for h, s in zip(hollow, solid))


def test_law_validation_rejects_damping_at_one():
    with pytest.raises(InputError):
        ContactLaw(1e5, 1.0)


@pytest.mark.slow
def test_contact_law_report_writes_its_files(tmp_path):
    import json

    from tests.conftest import run_cli

    proc = run_cli("analytical", "contact-law", "-o", str(tmp_path / "cl"), "--strikes", "4", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["stiffness_N_m"] > 0 and 0 < out["damping_ratio"] < 1
    for name in ("calibration.json", "scatter.csv", "scatter.md", "contact_law.png", "summary.json", "report.md"):
        assert (tmp_path / "cl" / name).stat().st_size > 0, name
    summary = json.loads((tmp_path / "cl" / "summary.json").read_text())
    shipped = summary["calibration"]["shipped_on_population"]
    assert shipped["law"]["stiffness_N_m"] == CONTAINER.stiffness_N_m and shipped["dof"] == 3
    assert f"k = {CONTAINER.stiffness_N_m:.3g} N/m" in (tmp_path / "cl" / "report.md").read_text()
    assert run_cli("analytical", "contact-law", "-o", str(tmp_path / "x"), "--strikes", "1").returncode == 2


def test_the_population_is_a_deterministic_function_of_its_seed():
    a, b, c = strike_population(5, seed=3), strike_population(5, seed=3), strike_population(5, seed=4)
    np.testing.assert_array_equal(a.lateral_offset_m, b.lateral_offset_m)
    assert not np.array_equal(a.lateral_offset_m, c.lateral_offset_m)


@pytest.mark.slow
def test_the_studys_fit_reads_a_strike_below_its_load_point_as_a_shorter_pulse():
    """Loaded at the water level while the contact is 10 cm lower (a container afloat under the
    run-up at the face), the study's fit reads the calibrated law's strikes as pulses more than
    1 ms shorter, which Table 2's 4.7 ms (SE 0.11 ms) rejects; with no drop it is the
    calibration's own figures."""
    population = strike_population(8)
    level, low = contact_drop(CONTAINER, population, drops_m=(0.0, 0.10), column=RIGID)
    assert level["means"] == pytest.approx(unit_figures(CONTAINER, population, RIGID).means(), rel=1e-12)
    assert low["means"]["duration_s"] < level["means"]["duration_s"] - 1e-3
    assert low["z"]["duration_s"] < -2.0 and low["p_value"] < 0.05


def test_a_lowered_contact_keeps_the_load_point_and_stays_on_the_column():
    population = strike_population(8)
    low = lowered(population, 0.5)
    np.testing.assert_array_equal(low.water_level_m, population.water_level_m)
    assert np.all(low.contact_height_m == pytest.approx(0.03))
    with pytest.raises(InputError, match="drop_m"):
        lowered(population, -0.01)
