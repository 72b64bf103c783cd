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
    assert d.strike_displacement_m[0] == pytest.approx(p / closed_form(ends, column.bending_stiffness_Nm2, a), rel=1e-6)


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


def largest_deflection(ends: str, ei: float, p: float, a: float) -> float:
    """Roark's largest deflection of the member under P at a from its base (a > L / 2), Euler-Bernoulli:
    fixed-fixed 2 P a^3 b^2 / (3 EI (3a + b)^2), pinned P b (L^2 - b^2)^1.5 / (9 sqrt(3) EI L), a
    cantilever's top P a^2 (3L - a) / (6 EI)."""
    b = L - a
    return {"cantilever": p * a**2 * (3 * L - a) / (6 * ei),
            "fixed-fixed": 2 * p * a**3 * b**2 / (3 * ei * (3 * a + b) ** 2),
            "pinned": p * b * (L**2 - b**2) ** 1.5 / (9 * math.sqrt(3) * ei * L)}[ends]


@pytest.mark.parametrize("ends", ["cantilever", "fixed-fixed", "pinned"])
def test_the_displacement_is_the_members_largest_not_its_tops(ends):
    """Held slowly at 3.0 m: the design's displacement is the member's largest (a cantilever's top;
    a member held at its top moves most between the load and mid-height, its top not at all), the
    strike point's is P / k_s there, and every node's is the MDOF model's static deflection."""
    from analytical.column_fem import static_deflection

    a, p = 3.0, 1000.0
    column = member(ends)
    d = column_demands(Tabulated([0.0, 2.0, 4.0], [0.0, p, p]), column, a, t=[3.9])
    ei = column.bending_stiffness_Nm2
    assert d.peak_displacement_m == pytest.approx(largest_deflection(ends, ei, p, a), rel=1e-4)
    assert d.peak_strike_displacement_m == pytest.approx(p / closed_form(ends, ei, a), rel=1e-6)
    assert d.peak_top_displacement_m == (pytest.approx(d.peak_displacement_m, rel=1e-9) if ends == "cantilever"
                                         else pytest.approx(0.0, abs=1e-15))
    if ends != "cantilever":
        assert d.peak_displacement_m > 1.01 * d.peak_strike_displacement_m
    nodes = d.displacement_height_m[:-1]
    static = [static_deflection(column, a, z, p) for z in nodes[::16]]
    assert d.displacement_m[:-1:16, 0] == pytest.approx(static, rel=1e-6, abs=1e-6 * max(static))


def test_the_largest_displacement_under_a_short_pulse_is_the_mdof_models_integrated_directly():
    """A 10 ms rectangular pulse on the fixed-fixed member at 3.0 m: the largest displacement over
    the member and time (modal superposition) against M u'' + C u' + K u = f integrated directly on
    the same MDOF model's matrices (Newmark, average acceleration, 2e-6 s)."""
    from scipy import linalg

    from analytical.column_demand import strike_demands

    column = member("fixed-fixed", elements=40)
    model = column_model(column)
    pulse, a = Rectangular(1.0e6, 0.01), 3.0
    dt, t_end = 2.0e-6, 0.03
    times = np.arange(1, int(round(t_end / dt)) + 1) * dt
    d = column_demands(pulse, column, a, t=times)
    k, m, c = (x.toarray() for x in (model.stiffness, model.mass, model.damping))
    f = model.load_vector(a)[model.free_dofs] * 1.0e6
    lu = linalg.lu_factor(k + 2.0 / dt * c + 4.0 / dt**2 * m)
    u, v, acc = np.zeros(f.size), np.zeros(f.size), np.zeros(f.size)
    lateral = np.asarray(model.free_dofs) % 2 == 0
    peak = 0.0
    for t in times:
        load = f if t <= pulse.end_s else 0.0 * f
        rhs = load + m @ (4.0 / dt**2 * u + 4.0 / dt * v + acc) + c @ (2.0 / dt * u + v)
        u_new = linalg.lu_solve(lu, rhs)
        v_new = 2.0 / dt * (u_new - u) - v
        acc = 4.0 / dt**2 * (u_new - u) - 4.0 / dt * v - acc
        u, v = u_new, v_new
        peak = max(peak, float(np.max(np.abs(u[lateral]))))
    assert d.peak_displacement_m == pytest.approx(peak, rel=2e-3)
    # a strike along the face's normal: the design row's displacement is that peak
    assert strike_demands(pulse, (-1.0, 0.0, 0.0), column, a)["displacement_m"] == pytest.approx(
        column_demands(pulse, column, a).peak_displacement_m, rel=1e-12)
