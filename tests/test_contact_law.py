"""The contact law: its rigid-wall restitution against the integrated impact, its calibration on
the study's Table 1 event, the held-out Table 2 comparison, bad input, and that the runner's
contact resolution uses each body's own law."""

import math

import numpy as np
import pytest

from analytical.asce7 import SEED_DEBRIS_STIFFNESS_N_M
from analytical.contact_law import (
    ASCE7_KD,
    CONTAINER,
    SEED_TABLE1_EVENT,
    SEED_TABLE2_MDOF,
    ContactLaw,
    box_inertia,
    calibrate,
    column_impact,
    contact_law,
    damping_for_restitution,
    held_out,
    wall_restitution,
)
from analytical.errors import InputError
from analytical.impact import Body, RigidWall, impact


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2, 0.5, 0.8])
def test_wall_restitution_closed_form_matches_the_integrated_impact(zeta):
    body = Body.particle(0.236, (-1.6, 0.0, 0.0))
    result = impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), stiffness_N_m=1.08e5, damping_ratio=zeta)
    assert result.restitution == pytest.approx(wall_restitution(zeta), abs=2e-4)


def test_undamped_wall_strike_is_haehnel_and_dalys_half_sine():
    m, v, k = 0.236, 1.5, CONTAINER.stiffness_N_m
    body = Body.particle(m, (-v, 0.0, 0.0))
    result = impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), **CONTAINER.options())
    assert result.peak_force_N == pytest.approx(v * math.sqrt(k * m), rel=1e-3)
    assert result.duration_s == pytest.approx(math.pi * math.sqrt(m / k), rel=1e-3)
    assert result.impulse_Ns == pytest.approx(2 * m * v, rel=1e-3)


@pytest.mark.parametrize("e", [1.0, 0.9, 0.5, 0.2])
def test_restitution_and_damping_ratio_invert_each_other(e):
    assert wall_restitution(damping_for_restitution(e)) == pytest.approx(e, abs=1e-10)


def test_calibration_on_table_1_reproduces_its_pulse_and_the_shipped_defaults():
    cal = calibrate()
    assert abs(cal.errors["peak_force"]) < 0.10 and abs(cal.errors["duration"]) < 0.10
    assert abs(cal.errors["impulse"]) < 0.10
    assert cal.law.stiffness_N_m == pytest.approx(CONTAINER.stiffness_N_m, rel=0.01)
    assert cal.law.damping_ratio == pytest.approx(CONTAINER.damping_ratio, abs=1e-3)
    # about 30 times softer than the rigid debris stiffness of the study's ASCE rows
    assert 20 < SEED_DEBRIS_STIFFNESS_N_M / cal.law.stiffness_N_m < 40


def test_the_container_law_gives_table_1s_pulse_within_ten_percent():
    r = column_impact(CONTAINER, SEED_TABLE1_EVENT.velocity_m_s, SEED_TABLE1_EVENT.height_m)
    assert r.peak_force_N == pytest.approx(SEED_TABLE1_EVENT.peak_force_N, rel=0.10)
    assert r.duration_s == pytest.approx(SEED_TABLE1_EVENT.duration_s, rel=0.10)
    # the rigid k_d law is the ASCE upper bound: five times the peak, a fifth of the duration
    kd = column_impact(ASCE7_KD, SEED_TABLE1_EVENT.velocity_m_s, SEED_TABLE1_EVENT.height_m)
    assert kd.peak_force_N > 4 * r.peak_force_N and kd.duration_s < r.duration_s / 4


def test_held_out_table_2_means_lie_within_two_of_the_studys_standard_deviations():
    h = held_out(CONTAINER, count=22)
    assert np.mean(h.velocity_m_s) == pytest.approx(1.60, abs=1e-9)
    for name in ("peak_force_N", "duration_s", "impulse_Ns"):
        mean, _ = h.stats(name)
        seed_mean, seed_std = SEED_TABLE2_MDOF[name]
        assert abs(mean - seed_mean) < 2 * seed_std, name
    # elastic: the mean pulse is stronger than the study's (it lost energy on average)
    assert h.stats("impulse_Ns")[0] > SEED_TABLE2_MDOF["impulse_Ns"][0]


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
     ({"velocity_m_s": 1.5, "height_m": -0.1}, "--height"), ({"velocity_m_s": 1.5, "obliquity_deg": 90}, "--obliquity")],
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


def test_box_inertia_of_a_thin_walled_box_exceeds_the_solid_box():
    solid = box_inertia((0.15, 0.06, 0.06), 0.236, None)
    hollow = box_inertia((0.15, 0.06, 0.06), 0.236, 0.005)
    assert solid[0] == pytest.approx(0.236 * (0.06**2 + 0.06**2) / 12)
    assert all(h > s for h, s in zip(hollow, solid))


def test_law_validation_rejects_damping_at_one():
    with pytest.raises(InputError):
        ContactLaw(1e5, 1.0)


def test_contact_law_report_writes_its_files(tmp_path):
    import json

    from tests.conftest import run_cli

    proc = run_cli("analytical", "contact-law", "-o", str(tmp_path / "cl"), "--strikes", "4", "--json")
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["stiffness_N_m"] == pytest.approx(CONTAINER.stiffness_N_m, rel=0.01)
    for name in ("calibration.json", "held_out.csv", "held_out.md", "contact_law.png", "summary.json", "report.md"):
        assert (tmp_path / "cl" / name).stat().st_size > 0, name
    assert run_cli("analytical", "contact-law", "-o", str(tmp_path / "x"), "--strikes", "1").returncode == 2
