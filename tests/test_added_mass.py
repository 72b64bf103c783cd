"""Added mass of a floating box: DNV's tables, Lamb's ellipsoid, the limiting cases, and the
study's container."""

import math

import numpy as np
import pytest

from analytical.added_mass import (
    DNV_SQUARE_PRISM_TABLE,
    STUDY_CONTAINER_ADDED_MASS,
    box_added_mass,
    dnv_block_added_mass,
    ellipsoid_coefficients,
    ellipsoid_integrals,
)
from analytical.errors import InputError


@pytest.mark.parametrize("ratio, tabulated", list(zip(*DNV_SQUARE_PRISM_TABLE)))
def test_block_formula_reproduces_dnvs_square_prisms(ratio, tabulated):
    # DNV-RP-C205 Table A-2: a square prism a x a x b moving along b carries C_A rho a^2 b
    computed = dnv_block_added_mass(ratio, (1.0, 1.0), 1.0) / ratio
    assert computed == pytest.approx(tabulated, rel=0.06)


def test_ellipsoid_integrals_sum_to_two_and_give_the_sphere_and_lambs_spheroid():
    assert sum(ellipsoid_integrals(3.0, 1.3, 0.4)) == pytest.approx(2.0, abs=1e-12)
    assert ellipsoid_coefficients(1.0, 1.0, 1.0) == pytest.approx((0.5, 0.5, 0.5, 0.0, 0.0, 0.0), abs=1e-12)
    # Lamb (1932) sec. 115, prolate spheroid of axis ratio 2: k1 = 0.210, k2 = 0.704, k' = 0.240
    k1, k2, k3, k_roll, k_pitch, k_yaw = ellipsoid_coefficients(2.0, 1.0, 1.0)
    assert (k1, k2, k_pitch) == pytest.approx((0.210, 0.704, 0.240), abs=1.5e-3)
    assert k2 == pytest.approx(k3) and k_yaw == pytest.approx(k_pitch) and k_roll == 0.0


def test_a_slender_box_carries_little_water_lengthwise_and_much_sideways():
    slender = box_added_mass((2.0, 0.1, 0.1), 0.5 * 1000.0 * 2.0 * 0.1 * 0.1, water_density_kg_m3=1000.0)
    surge, sway, heave = slender.coefficients[:3]
    assert surge < 0.06
    assert sway > 10 * surge and heave > 10 * surge
    # a long strip: sway and heave tend to the 2-D values, ~1 per unit displaced mass or more
    assert sway > 0.7 and heave > 0.7


def test_a_floating_cube_half_submerged_is_half_the_tabulated_cube():
    # a cube of side a floating at half its height: double body = cube, floating body = half
    a, rho = 0.1, 1000.0
    am = box_added_mass((a, a, a), rho * a * a * a / 2.0, water_density_kg_m3=rho)
    assert am.draft_m == pytest.approx(a / 2)
    for c in am.coefficients[:3]:
        # relative to the displaced half-cube: DNV's cube 0.68 (the formula gives 0.704)
        assert c == pytest.approx(0.68, rel=0.05)
    assert am.coefficients[0] == pytest.approx(am.coefficients[1]) == pytest.approx(am.coefficients[2])
    assert am.inertias_kg_m2 == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)  # a sphere-like ellipsoid


def test_the_studys_container():
    am = STUDY_CONTAINER_ADDED_MASS
    assert am.floating and am.draft_m == pytest.approx(0.236 / (998.0 * 0.15 * 0.06))
    assert am.displaced_mass_kg == pytest.approx(0.236)
    surge, sway, heave = am.coefficients[:3]
    assert sway > surge and heave > surge
    assert surge == pytest.approx(0.280, abs=0.005) and sway == pytest.approx(0.840, abs=0.005)
    assert am.masses_kg[0] == pytest.approx(surge * 0.236)
    # along a direction: n^T A n, the axes' values at the axes, their mean at 45 degrees
    assert am.along((1, 0, 0)) == pytest.approx(am.masses_kg[0])
    assert am.along((1, 1, 0)) == pytest.approx(0.5 * (am.masses_kg[0] + am.masses_kg[1]))
    assert am.coefficient_along((-2.0, 0, 0)) == pytest.approx(surge)
    assert am.diagonal.shape == (6,) and np.all(am.diagonal >= 0.0)


def test_a_body_that_would_sink_is_treated_deep():
    am = box_added_mass((0.1, 0.1, 0.1), 2.0, water_density_kg_m3=1000.0)
    assert not am.floating and am.draft_m == pytest.approx(0.1)
    assert am.coefficients[0] == pytest.approx(0.704, abs=0.005)  # the whole cube, DNV formula


@pytest.mark.parametrize("kwargs, field", [
    ({"size_m": (0.1, 0.1), "mass_kg": 0.1}, "size_m"),
    ({"size_m": (0.1, -0.1, 0.1), "mass_kg": 0.1}, "size_m"),
    ({"size_m": (0.1, 0.1, 0.1), "mass_kg": 0.0}, "mass_kg"),
])
def test_bad_input_names_the_field(kwargs, field):
    with pytest.raises(InputError) as err:
        box_added_mass(**kwargs)
    assert err.value.field == field


def test_direction_must_be_nonzero():
    with pytest.raises(InputError):
        STUDY_CONTAINER_ADDED_MASS.along((0.0, 0.0, 0.0))
    assert math.isfinite(STUDY_CONTAINER_ADDED_MASS.along((0.0, 0.0, -1.0)))
