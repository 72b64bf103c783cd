"""Empirical impact formulas: hand values, scaling, dimensional consistency, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytical.errors import InputError
from analytical.formulas import (
    MATSUTOMI_CMA_BORE,
    MATSUTOMI_CMA_STEADY,
    haehnel_daly,
    hertz_effective_modulus,
    ikeno,
    matsutomi,
)

LOG = dict(diameter_m=0.1, length_m=1.0, unit_weight_N_m3=600 * 9.81, yield_stress_Pa=2e7)


# ============================================================== Haehnel and Daly (2004)


def test_haehnel_daly_hand_value():
    # the study's debris on the study's column: 1.5 * sqrt(4.685e5 * 0.236) = 498.772 N
    assert haehnel_daly(1.5, 0.236, 4.685e5) == pytest.approx(498.772, abs=1e-3)


def test_haehnel_daly_series_stiffness():
    # 1/k = 1/4.685e5 + 1/3.04e6 -> k = 405 939.86 N/m -> F = 464.278 N
    f = haehnel_daly(1.5, 0.236, 3.04e6, structure_stiffness_N_m=4.685e5)
    assert f == pytest.approx(464.278, abs=1e-3)
    assert f < haehnel_daly(1.5, 0.236, 4.685e5) and f < haehnel_daly(1.5, 0.236, 3.04e6)


def test_haehnel_daly_scaling():
    f = haehnel_daly(1.0, 1.0, 1.0)
    assert f == 1.0
    assert haehnel_daly(3.0, 1.0, 1.0) == pytest.approx(3.0 * f)  # F ~ u
    assert haehnel_daly(1.0, 4.0, 1.0) == pytest.approx(2.0 * f)  # F ~ sqrt(m)
    assert haehnel_daly(1.0, 1.0, 9.0) == pytest.approx(3.0 * f)  # F ~ sqrt(k)
    assert haehnel_daly(1.0, 2.0, 8.0) == pytest.approx(4.0 * f)  # F ~ sqrt(k m)


def test_haehnel_daly_energy_balance():
    # the spring stores the kinetic energy: F^2 / (2 k) = m u^2 / 2
    u, m, k = 2.3, 0.236, 4.685e5
    f = haehnel_daly(u, m, k)
    assert f**2 / (2 * k) == pytest.approx(0.5 * m * u**2, rel=1e-14)


def test_haehnel_daly_arrays():
    u = np.array([1.0, 1.5, 2.0])
    f = haehnel_daly(u, 0.236, 4.685e5)
    assert isinstance(f, np.ndarray) and f.shape == (3,)
    np.testing.assert_allclose(f, u * math.sqrt(0.236 * 4.685e5))
    assert isinstance(haehnel_daly(1.5, 0.236, 4.685e5), float)


# ======================================================================= Matsutomi (2009)


def test_matsutomi_hand_value():
    # 1.6 * 1.7 * (1.5/sqrt(9.81*0.1))^1.2 * (2e7/(5886*1))^0.4 * 5886 * 0.1^2 * 1
    #   = 2.72 * 1.5145^1.2 * 3397.9^0.4 * 58.86 = 6810.53 N
    assert matsutomi(1.5, **LOG) == pytest.approx(6810.53, abs=0.01)
    assert MATSUTOMI_CMA_BORE == 1.7 and MATSUTOMI_CMA_STEADY == 1.9


def test_matsutomi_scaling():
    f = matsutomi(1.0, **LOG)
    assert matsutomi(2.0, **LOG) / f == pytest.approx(2.0**1.2, rel=1e-12)  # F ~ u^1.2
    assert matsutomi(1.0, **LOG, added_mass_coefficient=1.9) / f == pytest.approx(1.9 / 1.7, rel=1e-12)
    assert matsutomi(1.0, **{**LOG, "yield_stress_Pa": 2 * LOG["yield_stress_Pa"]}) / f == pytest.approx(2**0.4)


def test_matsutomi_froude_scaling():
    """Geometric scale lambda with Froude velocity (u ~ sqrt(lambda)) and sigma ~ lambda: F ~ lambda^3."""
    lam = 40.0
    small = matsutomi(1.5, **LOG)
    big = matsutomi(
        1.5 * math.sqrt(lam),
        diameter_m=LOG["diameter_m"] * lam,
        length_m=LOG["length_m"] * lam,
        unit_weight_N_m3=LOG["unit_weight_N_m3"],
        yield_stress_Pa=LOG["yield_stress_Pa"] * lam,
    )
    assert big / small == pytest.approx(lam**3, rel=1e-12)


def test_matsutomi_is_dimensionally_consistent():
    """The same impact in CGS units (cm, g, s; force in dyn = 1e-5 N) gives the same force."""
    si = matsutomi(1.5, **LOG)
    cgs = matsutomi(
        150.0,
        diameter_m=10.0,  # cm
        length_m=100.0,  # cm
        unit_weight_N_m3=LOG["unit_weight_N_m3"] * 1e5 / 1e6,  # dyn/cm^3
        yield_stress_Pa=LOG["yield_stress_Pa"] * 10.0,  # dyn/cm^2
        g=981.0,
    )
    assert cgs * 1e-5 == pytest.approx(si, rel=1e-12)


# ================================================================ Ikeno et al. (2013, 2016)


def test_ikeno_hand_value():
    # 0.243 * (1.7*0.236)^0.6 * 1.5^1.2 * 0.06^0.2 * (1e9)^0.4
    #   = 0.243 * 0.5781 * 1.6266 * 0.5697 * 3981.07 = 518.278 N
    assert ikeno(1.5, 0.236, 0.06, 1e9) == pytest.approx(518.278, abs=1e-3)


def test_ikeno_scaling():
    f = ikeno(1.0, 1.0, 1.0, 1.0)
    assert ikeno(2.0, 1.0, 1.0, 1.0) / f == pytest.approx(2.0**1.2, rel=1e-12)  # F ~ u^1.2
    assert ikeno(1.0, 2.0, 1.0, 1.0) / f == pytest.approx(2.0**0.6, rel=1e-12)
    assert ikeno(1.0, 1.0, 2.0, 1.0) / f == pytest.approx(2.0**0.2, rel=1e-12)
    assert ikeno(1.0, 1.0, 1.0, 2.0) / f == pytest.approx(2.0**0.4, rel=1e-12)
    assert ikeno(1.0, 1.0, 1.0, 1.0, added_mass_coefficient=1.0, kappa=0.243) == pytest.approx(0.243)
    # (C_MA m)^0.6 u^1.2 = (2 x kinetic energy of the virtual mass)^0.6
    assert ikeno(1.0, 2.0, 1.0, 1.0, added_mass_coefficient=1.0) == pytest.approx(
        ikeno(math.sqrt(2.0), 1.0, 1.0, 1.0, added_mass_coefficient=1.0)
    )


def test_ikeno_is_dimensionally_consistent():
    si = ikeno(1.5, 0.236, 0.06, 1e9)
    cgs = ikeno(150.0, 236.0, 6.0, 1e10)  # cm/s, g, cm, dyn/cm^2
    assert cgs * 1e-5 == pytest.approx(si, rel=1e-12)


def test_hertz_effective_modulus():
    # steel (200 GPa, 0.3) on a 1 GPa, 0.4 plastic: 1/E* = 0.91/2e11 + 0.84/1e9
    assert hertz_effective_modulus(200e9, 0.3, 1e9, 0.4) == pytest.approx(1.18406e9, rel=1e-5)
    assert hertz_effective_modulus(1e9, 0.0, 1e9, 0.0) == pytest.approx(0.5e9)


# =============================================================================== bad input


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: haehnel_daly(0.0, 1.0, 1.0), "velocity_m_s"),
        (lambda: haehnel_daly(1.0, -1.0, 1.0), "mass_kg"),
        (lambda: haehnel_daly(1.0, 1.0, float("nan")), "stiffness_N_m"),
        (lambda: haehnel_daly(1.0, 1.0, 1.0, structure_stiffness_N_m=0.0), "structure_stiffness_N_m"),
        (lambda: haehnel_daly("fast", 1.0, 1.0), "velocity_m_s"),
        (lambda: haehnel_daly(np.array([1.0, -2.0]), 1.0, 1.0), "velocity_m_s"),
        (lambda: matsutomi(-1.5, **LOG), "velocity_m_s"),
        (lambda: matsutomi(1.5, **{**LOG, "diameter_m": 0.0}), "diameter_m"),
        (lambda: matsutomi(1.5, **{**LOG, "length_m": np.inf}), "length_m"),
        (lambda: matsutomi(1.5, **{**LOG, "unit_weight_N_m3": -1.0}), "unit_weight_N_m3"),
        (lambda: matsutomi(1.5, **{**LOG, "yield_stress_Pa": 0.0}), "yield_stress_Pa"),
        (lambda: matsutomi(1.5, **LOG, added_mass_coefficient=0.0), "added_mass_coefficient"),
        (lambda: matsutomi(1.5, **LOG, g=0.0), "g"),
        (lambda: ikeno(1.5, 0.0, 0.06, 1e9), "mass_kg"),
        (lambda: ikeno(1.5, 0.236, -0.06, 1e9), "diameter_m"),
        (lambda: ikeno(1.5, 0.236, 0.06, 0.0), "effective_modulus_Pa"),
        (lambda: ikeno(1.5, 0.236, 0.06, 1e9, kappa=-0.243), "kappa"),
        (lambda: hertz_effective_modulus(1e9, 0.5, 1e9, 0.3), "nu1"),
        (lambda: hertz_effective_modulus(1e9, 0.3, -1e9, 0.3), "E2_Pa"),
    ],
)
def test_bad_input_names_the_argument(call, field):
    with pytest.raises(InputError) as e:
        call()
    assert e.value.field == field
