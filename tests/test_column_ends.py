"""The member as struck: point stiffness and reactions of a column with its end conditions
(analytical.column.Column.ends) against the closed forms of a prismatic beam (Roark's Formulas
for Stress and Strain, 8th ed., Table 8.1, cases 1a, 1e and 1d; Euler-Bernoulli, shear off)."""

import math

import numpy as np
import pytest

from analytical.column import Column
from analytical.column_demand import column_demands
from analytical.column_fem import column_model, lateral_stiffness
from analytical.errors import InputError
from analytical.newmark import newmark_history
from analytical.pulses import Rectangular, Tabulated

L = 5.0  # the street's column: 1.0 m square, 5.0 m between its base and the first floor


def member(ends: str, shear_coefficient: float = 1e9, elements: int = 160) -> Column:
    """1.0 m solid square of cracked concrete (E 2.487e10 Pa x 0.70); shear off by default."""
    return Column(size_x_m=1.0, size_y_m=1.0, height_m=L, wall_thickness_m=0.5, youngs_modulus_Pa=2.487e10,
                  density_kg_m3=2400.0, poisson_ratio=0.2, shear_coefficient=shear_coefficient, damping_ratio=0.05,
                  stiffness_factor=0.70, ends=ends, elements=elements)


def closed_form(ends: str, ei: float, a: float) -> float:
    b = L - a
    return {"cantilever": 3 * ei / a**3, "fixed-fixed": 3 * ei * L**3 / (a**3 * b**3),
            "pinned": 3 * ei * L / (a**2 * b**2)}[ends]


@pytest.mark.parametrize("ends", ["cantilever", "fixed-fixed", "pinned"])
@pytest.mark.parametrize("a", [1.0, 2.5, 3.0, 4.0])
def test_point_stiffness_matches_the_closed_form(ends, a):
    column = member(ends)
    k = lateral_stiffness(column, a)
    assert k == pytest.approx(closed_form(ends, column.bending_stiffness_Nm2, a), rel=1e-7)


def test_street_figures():
    # E I = 2.487e10 x 0.70 / 12 = 1.4508e9 N m2; struck at the 3.0 m flow depth
    column = member("fixed-fixed")
    assert column.bending_stiffness_Nm2 == pytest.approx(1.45075e9, rel=1e-5)
    assert lateral_stiffness(member("cantilever"), 3.0) == pytest.approx(1.6120e8, rel=1e-4)
    assert lateral_stiffness(column, 3.0) == pytest.approx(2.5188e9, rel=1e-4)
    assert lateral_stiffness(member("pinned"), 3.0) == pytest.approx(6.0448e8, rel=1e-4)
    # the cantilever's top, the stiffness ASCE's k_s took before the strike point: 3 E I / L^3
    assert lateral_stiffness(member("cantilever"), L) == pytest.approx(3.4818e7, rel=1e-4)


def test_cantilever_with_shear_adds_the_shear_flexibility():
    column = member("cantilever", shear_coefficient=10 * 1.2 / (12 + 11 * 0.2))
    a = 3.0
    flexibility = a**3 / (3 * column.bending_stiffness_Nm2) + a / column.shear_stiffness_N
    assert lateral_stiffness(column, a) == pytest.approx(1.0 / flexibility, rel=1e-9)
    assert lateral_stiffness(column, a) < lateral_stiffness(member("cantilever"), a)


def test_fixed_fixed_softest_at_mid_height():
    column = member("fixed-fixed")
    ks = [lateral_stiffness(column, z) for z in (1.25, 2.5, 3.75)]
    assert ks[1] == pytest.approx(192 * column.bending_stiffness_Nm2 / L**3, rel=1e-7)
    assert ks[1] < ks[0] and ks[1] < ks[2]


@pytest.mark.parametrize("ends", ["fixed-fixed", "pinned"])
def test_slow_load_gives_the_static_reactions(ends):
    a, b, p = 3.0, 2.0, 1000.0
    column = member(ends, elements=40)
    d = column_demands(Tabulated([0.0, 2.0, 4.0], [0.0, p, p]), column, a, t=[3.9])
    shear = p * b**2 * (3 * a + b) / L**3 if ends == "fixed-fixed" else p * b / L
    moment = p * a * b**2 / L**2 if ends == "fixed-fixed" else 0.0
    assert d.base_shear_N[0] == pytest.approx(shear, rel=1e-6)
    assert d.base_moment_Nm[0] == pytest.approx(moment, rel=1e-6, abs=1e-9)
    # the displacement at the load: P / k there
    assert d.top_displacement_m[0] == pytest.approx(p / closed_form(ends, column.bending_stiffness_Nm2, a), rel=1e-6)


def test_restrained_top_modal_and_newmark_agree():
    column = member("fixed-fixed", elements=40)
    pulse = Rectangular(1.0e6, 0.01)
    hist = newmark_history(pulse, column, 3.0, 0.05)
    # the base's reaction row and the equilibrium (mode-acceleration) form are one number
    assert np.max(np.abs(hist.base_shear_N - hist.base_shear_reaction_N)) < 1e-6 * np.max(np.abs(hist.base_shear_N))
    modal = column_demands(pulse, column, 3.0, t=hist.time_s[1:])
    assert modal.peak_base_shear_N == pytest.approx(float(np.max(np.abs(hist.base_shear_N))), rel=1e-4)


def test_fixed_fixed_first_frequency_near_the_euler_bernoulli_beam():
    column = member("fixed-fixed")
    m = column.mass_per_length_kg_m
    f1 = 4.7300**2 / (2 * math.pi * L**2) * math.sqrt(column.bending_stiffness_Nm2 / m)
    # rotary inertia lowers it a little (a 1.0 m deep section on 5 m)
    assert 0.95 * f1 < column_model(column).frequencies_Hz[0] < f1


def test_bad_ends_are_named():
    with pytest.raises(InputError) as err:
        member("hinged")
    assert err.value.field == "column.ends"
    with pytest.raises(InputError) as err:
        Column(ends="fixed-fixed", base="spring", base_spring_Nm_rad=1e6)
    assert err.value.field == "column.base"
    with pytest.raises(InputError) as err:
        member("fixed-fixed", elements=1)
    assert err.value.field == "column.elements"
    # two elements: the mid-node alone, still the closed form there (192 E I / L^3)
    two = member("fixed-fixed", elements=2)
    assert lateral_stiffness(two, L / 2) == pytest.approx(192 * two.bending_stiffness_Nm2 / L**3, rel=1e-7)
