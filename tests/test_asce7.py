"""ASCE 7-22 Section 6.11 debris impact, the study's Tables 1-2, and the dynamic response ratio."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytical.asce7 import (
    IMPORTANCE_FACTORS,
    ORIENTATION_CONTAINER,
    AsceImpact,
    asce7_impact,
    dynamic_response_ratio,
    effective_stiffness,
    importance_factor,
)
from analytical.study import (
    STUDY_DEBRIS_MASS_KG,
    STUDY_DEBRIS_STIFFNESS_N_M,
    STUDY_STRUCTURE_STIFFNESS_N_M,
    STUDY_TABLE1_VELOCITY_M_S,
)
from analytical.errors import InputError
from analytical.pulses import Rectangular, make_pulse
from analytical.sdof import half_sine_closed_form, rectangular_closed_form

KS, M = STUDY_STRUCTURE_STIFFNESS_N_M, STUDY_DEBRIS_MASS_KG


# ===================================================================== the formulas


def test_formulas_by_hand():
    imp = asce7_impact(2.0, 4.0, 100.0, importance=1.25, orientation=0.65)
    assert imp.nominal_force_N == pytest.approx(2.0 * 20.0)  # u sqrt(k m) = 2 * sqrt(400)
    assert imp.force_N == pytest.approx(1.25 * 0.65 * 40.0)
    assert imp.duration_s == pytest.approx(2 * 4.0 * 2.0 / 40.0)  # 2 m u / F_ni = 0.4 s
    assert imp.duration_s == pytest.approx(2 * math.sqrt(4.0 / 100.0))  # = 2 sqrt(m/k)
    assert imp.impulse_Ns == pytest.approx(2 * 1.25 * 0.65 * 4.0 * 2.0)


def test_pulse_is_the_rectangular_design_load():
    imp = asce7_impact(1.5, M, KS)
    p = imp.pulse
    assert isinstance(p, Rectangular)
    assert (p.magnitude_N, p.duration_s, p.start_s) == (imp.force_N, imp.duration_s, 0.0)
    assert p.impulse_Ns == pytest.approx(imp.impulse_Ns, rel=1e-15)


def test_impulse_is_independent_of_stiffness():
    """The study's finding: k_d and k_s give the same impulse; in fact any k does."""
    impulses = [asce7_impact(1.5, M, k).impulse_Ns for k in np.logspace(2, 9, 15)]
    np.testing.assert_allclose(impulses, 2 * 1.0 * ORIENTATION_CONTAINER * M * 1.5, rtol=1e-14)
    assert asce7_impact(1.5, M, KS).impulse_Ns == pytest.approx(asce7_impact(1.5, M, STUDY_DEBRIS_STIFFNESS_N_M).impulse_Ns)


def test_duration_is_independent_of_velocity():
    durations = [asce7_impact(u, M, KS).duration_s for u in (0.5, 1.5, 3.0)]
    np.testing.assert_allclose(durations, 2 * math.sqrt(M / KS), rtol=1e-14)


def test_effective_stiffness_in_series():
    assert effective_stiffness(2.0, 2.0) == pytest.approx(1.0)
    assert effective_stiffness(3.0, 6.0) == pytest.approx(2.0)
    assert effective_stiffness(KS, 1e12) == pytest.approx(KS, rel=1e-6)
    k = effective_stiffness(KS, STUDY_DEBRIS_STIFFNESS_N_M)
    assert k < KS and k == pytest.approx(effective_stiffness(STUDY_DEBRIS_STIFFNESS_N_M, KS))
    assert 1 / k == pytest.approx(1 / KS + 1 / STUDY_DEBRIS_STIFFNESS_N_M)


def test_importance_factors():
    assert importance_factor("II") == 1.0
    assert importance_factor("iii") == 1.25 and importance_factor(4) == 1.25
    assert importance_factor("vertical_evacuation_refuge") == 1.25
    assert IMPORTANCE_FACTORS["II"] == 1.0
    with pytest.raises(InputError) as e:
        importance_factor("V")
    assert e.value.field == "risk_category"


def test_result_object_is_frozen_and_serialisable():
    imp = asce7_impact(1.5, M, KS)
    with pytest.raises(dataclasses.FrozenInstanceError):
        imp.velocity_m_s = 2.0
    d = imp.to_dict()
    assert set(d) >= {"force_N", "nominal_force_N", "duration_s", "impulse_Ns", "stiffness_N_m"}
    assert all(isinstance(v, float) for v in d.values())
    assert AsceImpact(**{k: d[k] for k in ("velocity_m_s", "mass_kg", "stiffness_N_m", "importance", "orientation")}) == imp


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(velocity_m_s=0.0), "velocity_m_s"),
        (dict(velocity_m_s=-1.0), "velocity_m_s"),
        (dict(mass_kg=float("nan")), "mass_kg"),
        (dict(stiffness_N_m=0.0), "stiffness_N_m"),
        (dict(importance=0.0), "importance"),
        (dict(orientation=1.2), "orientation"),
        (dict(orientation=-0.65), "orientation"),
    ],
)
def test_bad_input_names_the_argument(kwargs, field):
    args = dict(velocity_m_s=1.5, mass_kg=M, stiffness_N_m=KS)
    args.update(kwargs)
    with pytest.raises(InputError) as e:
        asce7_impact(**args)
    assert e.value.field == field


def test_effective_stiffness_bad_input():
    with pytest.raises(InputError) as e:
        effective_stiffness(KS, -1.0)
    assert e.value.field == "debris_stiffness_N_m"


# ================================================================= the study's numbers


def test_study_debris_stiffness_backed_out_of_table_1():
    assert STUDY_DEBRIS_STIFFNESS_N_M == pytest.approx(3.04e6, rel=1e-3)
    assert math.sqrt(STUDY_DEBRIS_STIFFNESS_N_M / KS) == pytest.approx(822.34 / 322.83, rel=1e-12)
    assert 822.34 / 322.83 == pytest.approx(2.5473, abs=1e-4)


@pytest.mark.parametrize(
    "stiffness, magnitude_N, duration_s, impulse_Ns",
    [(KS, 322.83, 0.0014, 0.46), (STUDY_DEBRIS_STIFFNESS_N_M, 822.34, 0.0006, 0.46)],
    ids=["k_s", "k_d"],
)
def test_study_table_1_rows(stiffness, magnitude_N, duration_s, impulse_Ns):
    imp = asce7_impact(STUDY_TABLE1_VELOCITY_M_S, M, stiffness)  # I_tsu = 1.0, C_o = 0.65
    assert imp.force_N == pytest.approx(magnitude_N, rel=0.005)
    assert round(imp.duration_s, 4) == duration_s
    assert round(imp.impulse_Ns, 2) == impulse_Ns


def test_study_table_1_printed_magnitudes_imply_u_1_4936():
    """With u = 1.50 exactly the k_s row is 0.43 % above print; u = 1.4936 m/s reproduces both rows."""
    at_150 = asce7_impact(1.50, M, KS).force_N
    assert at_150 == pytest.approx(324.20, abs=0.01)
    assert at_150 / 322.83 - 1 == pytest.approx(0.0043, abs=0.0001)
    u = 322.83 / (0.65 * math.sqrt(KS * M))
    assert u == pytest.approx(1.4937, abs=1e-4)
    assert asce7_impact(u, M, KS).force_N == pytest.approx(322.83, abs=1e-9)
    assert asce7_impact(u, M, STUDY_DEBRIS_STIFFNESS_N_M).force_N == pytest.approx(822.34, abs=1e-9)


def test_study_table_2_means_imply_a_mean_velocity_of_1_59():
    # F is linear in u, so the mean force is the force at the mean velocity
    u_mean = 343.60 / (0.65 * math.sqrt(KS * M))
    assert u_mean == pytest.approx(1.59, abs=0.005)
    ks_row = asce7_impact(u_mean, M, KS)
    kd_row = asce7_impact(u_mean, M, STUDY_DEBRIS_STIFFNESS_N_M)
    assert ks_row.force_N == pytest.approx(343.60, rel=1e-12)
    assert kd_row.force_N == pytest.approx(875.25, rel=0.005)
    assert round(ks_row.duration_s, 4) == 0.0014 and round(kd_row.duration_s, 4) == 0.0006
    assert round(ks_row.impulse_Ns, 2) == 0.49 == round(kd_row.impulse_Ns, 2)
    # the standard deviations scale the same way: 70.22 / 27.57 = sqrt(k_d / k_s)
    assert 70.22 / 27.57 == pytest.approx(math.sqrt(STUDY_DEBRIS_STIFFNESS_N_M / KS), rel=0.005)
    u_std = 27.57 / (0.65 * math.sqrt(KS * M))
    assert u_std == pytest.approx(0.13, abs=0.005)


# ============================================================ dynamic response ratio


def _half_sine_spectrum(r):
    """Undamped half-sine shock spectrum, derived independently (Chopra 2017 Sec. 4.8)."""
    beta = 1 / (2 * r)  # Omega / omega
    if abs(beta - 1) < 1e-12:
        free = math.pi / 2
    else:
        free = 2 * beta * abs(math.cos(math.pi * r)) / abs(1 - beta**2)
    forced, n = 0.0, 1
    while beta < 1 and n / (1 + beta) <= r:  # forced-phase maxima at t_n = n T / (1 + beta)
        forced = max(forced, math.sin(2 * math.pi * n * beta / (1 + beta)) / (1 - beta))
        n += 1
    return max(free, forced)


@pytest.mark.parametrize("r", [0.02, 0.1, 0.25, 0.4, 0.5, 0.6, 1.0, 1.6, 3.0, 8.0])
def test_undamped_rectangular_spectrum(r):
    expected = 2 * math.sin(math.pi * r) if r <= 0.5 else 2.0
    assert dynamic_response_ratio(r * 0.02, 0.02, "rectangular") == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("r", [0.02, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.81, 1.0, 1.5, 2.5, 5.0])
def test_undamped_half_sine_spectrum(r):
    assert dynamic_response_ratio(r * 0.02, 0.02, "half-sine") == pytest.approx(_half_sine_spectrum(r), rel=1e-9)


def test_half_sine_spectrum_landmarks():
    assert dynamic_response_ratio(0.5, 1.0, "half-sine") == pytest.approx(math.pi / 2, rel=1e-12)
    grid = np.linspace(0.6, 1.0, 81)
    values = [dynamic_response_ratio(r, 1.0, "half-sine") for r in grid]
    assert max(values) == pytest.approx(1.768, abs=0.001)
    assert grid[int(np.argmax(values))] == pytest.approx(0.81, abs=0.01)


@pytest.mark.parametrize("shape", ["rectangular", "half-sine", "triangular"])
def test_short_pulse_limit_is_the_impulse(shape):
    # t_d << T_n: R_max = omega * impulse / F
    Tn, td = 1.0, 1e-3
    p = make_pulse(shape, 1.0, td)
    expected = 2 * math.pi / Tn * p.impulse_Ns
    assert dynamic_response_ratio(td, Tn, shape) == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("shape, closed_form", [("rectangular", rectangular_closed_form), ("half-sine", half_sine_closed_form)])
@pytest.mark.parametrize("r", [0.1, 0.5, 1.0, 2.5])
def test_damped_ratio_equals_the_closed_form_maximum(shape, closed_form, r):
    z = 0.045
    t = np.linspace(0.0, r + 2.0, 400001)
    ref = np.max(closed_form(t, 1.0, r, 1.0, z))
    got = dynamic_response_ratio(r, 1.0, shape, damping_ratio=z)
    assert got == pytest.approx(ref, rel=1e-8)
    assert got < dynamic_response_ratio(r, 1.0, shape)  # damping lowers it


def test_study_asce_pulses_on_the_study_sdof():
    # t_d/T_n = 0.0014 * 70 ~ 0.1 for k_s: far below 1/2, the response is impulse-like
    imp = asce7_impact(1.5, M, KS)
    r = dynamic_response_ratio(imp.duration_s, 1 / 70.0, "rectangular", 0.045)
    assert 0.5 < r < 2 * math.sin(math.pi * imp.duration_s * 70.0)


def test_dynamic_response_ratio_bad_input():
    with pytest.raises(InputError) as e:
        dynamic_response_ratio(0.01, 0.02, "sawtooth")
    assert e.value.field == "pulse"
    with pytest.raises(InputError) as e:
        dynamic_response_ratio(0.01, 0.0)
    assert e.value.field == "natural_period_s"
    with pytest.raises(InputError) as e:
        dynamic_response_ratio(0.01, 0.02, damping_ratio=1.0)
    assert e.value.field == "zeta"


# --------------------------------------------------------------------------- the design value


def test_the_lesser_stiffness_governs_and_the_other_is_context():
    from analytical.asce7 import asce7_design

    d = asce7_design(1.5, 0.236)  # the study's container (k_d 3.04e6) on its column (k_s 4.685e5)
    assert d.governing == "k_s" and d.design.stiffness_N_m == 4.685e5
    assert d.force_N == pytest.approx(0.65 * 1.5 * math.sqrt(4.685e5 * 0.236))  # 324.2 N
    assert d.other.force_N == pytest.approx(0.65 * 1.5 * math.sqrt(STUDY_DEBRIS_STIFFNESS_N_M * 0.236))
    assert d.force_N < d.other.force_N
    stiff = asce7_design(1.5, 0.236, debris_stiffness_N_m=1e5)  # a soft body on the same column: k_d governs
    assert stiff.governing == "k_d" and stiff.force_N == pytest.approx(0.65 * 1.5 * math.sqrt(1e5 * 0.236))
    assert d.to_dict()["governing_stiffness"] == "k_s" and d.to_dict()["other_force_N"] == d.other.force_N


def test_the_simplified_static_load_bounds_only_a_prototype():
    from analytical.asce7 import SIMPLIFIED_STATIC_LOAD_N, asce7_design

    assert SIMPLIFIED_STATIC_LOAD_N == 1.47e6  # 330 kips = 1,470 kN, times C_o I_tsu
    # a full-scale 20 ft container (about 2,200 kg empty) at 5 m/s on a stiff element: F_i over the bound
    big = dict(velocity_m_s=5.0, mass_kg=2200.0, debris_stiffness_N_m=8.5e7, structure_stiffness_N_m=2e8)
    lab = asce7_design(**big)
    proto = asce7_design(**big, prototype=True)
    assert lab.design.force_N > lab.cap_N == pytest.approx(1.47e6 * 0.65)
    assert lab.force_N == lab.design.force_N and not lab.capped  # laboratory scale: never capped
    assert proto.capped and proto.force_N == pytest.approx(proto.cap_N)
    assert "not applied" in lab.cap_note() and "applied" in proto.cap_note()
    small = asce7_design(1.5, 0.236, prototype=True)
    assert not small.capped and small.force_N == small.design.force_N
