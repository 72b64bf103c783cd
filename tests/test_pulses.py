"""Pulses: values, exact properties, atom decomposition, registry, validation."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from analytical.errors import InputError
from analytical.pulses import (
    PULSES,
    Atom,
    HalfSine,
    Rectangular,
    Tabulated,
    Triangular,
    atoms_force,
    make_pulse,
)

SAMPLE_PULSES = [
    HalfSine(300.0, 0.003),
    HalfSine(-120.0, 0.0025, start_s=0.01),
    Rectangular(324.2, 0.0014),
    Rectangular(50.0, 0.2, start_s=-0.05),
    Triangular(200.0, 0.004),
    Triangular(200.0, 0.004, peak_fraction=0.2, start_s=0.001),
    Triangular(80.0, 0.004, peak_fraction=0.0),
    Triangular(80.0, 0.004, peak_fraction=1.0),
    Tabulated([0.0, 0.001, 0.002, 0.004], [0.0, 150.0, 90.0, 0.0]),
    Tabulated([0.002, 0.003, 0.005], [40.0, -60.0, 25.0]),  # jumps at both ends, sign change
]


def dense(p, n=20001):
    return np.linspace(p.start_s - 0.3 * p.duration_s, p.end_s + 0.3 * p.duration_s, n)


# ----------------------------------------------------------------------------------- values


def test_half_sine_values():
    p = HalfSine(300.0, 0.004, start_s=0.01)
    assert p.force(0.01) == 0.0
    assert p.force(0.012) == pytest.approx(300.0, rel=1e-15)
    assert p.force(0.011) == pytest.approx(300.0 * math.sin(math.pi / 4), rel=1e-14)
    assert p.force(0.0099) == 0.0 and p.force(0.014) == 0.0 and p.force(1.0) == 0.0
    assert (p.start_s, p.end_s, p.duration_s, p.peak_N) == (0.01, 0.014, 0.004, 300.0)
    assert p.omega_rad_s == pytest.approx(math.pi / 0.004)


def test_rectangular_values_and_half_open_support():
    p = Rectangular(10.0, 0.5, start_s=1.0)
    np.testing.assert_array_equal(p.force([0.999, 1.0, 1.2, 1.4999, 1.5, 2.0]), [0, 10, 10, 10, 0, 0])


def test_triangular_values():
    p = Triangular(100.0, 2.0, peak_fraction=0.25)
    np.testing.assert_allclose(p.force([0.0, 0.25, 0.5, 1.25, 2.0]), [0, 50, 100, 50, 0], atol=1e-12)
    assert p.peak_time_s == 0.5
    assert Triangular(100.0, 2.0, peak_fraction=0.0).force(0.0) == 100.0
    assert Triangular(100.0, 2.0, peak_fraction=1.0).force(1.0) == pytest.approx(50.0)


def test_tabulated_values_interpolate_and_vanish_outside():
    p = Tabulated([1.0, 2.0, 4.0], [10.0, 30.0, 20.0])
    np.testing.assert_allclose(p.force([0.5, 1.0, 1.5, 2.0, 3.0, 3.999, 4.0, 5.0]), [0, 10, 20, 30, 25, 20.005, 0, 0])
    assert (p.start_s, p.end_s, p.duration_s, p.peak_N) == (1.0, 4.0, 3.0, 30.0)
    assert Tabulated([0, 1], [5.0, -8.0]).peak_N == -8.0


def test_force_is_vectorised_and_scalar_in_scalar_out():
    p = HalfSine(1.0, 1.0)
    assert isinstance(p.force(0.5), float)
    assert p.force(np.zeros((3, 4))).shape == (3, 4)


# --------------------------------------------------------------------------------- impulses


@pytest.mark.parametrize("p", SAMPLE_PULSES, ids=repr)
def test_impulse_equals_integral_of_force(p):
    knots = sorted({p.start_s, p.end_s, *[a.t0 for a in p.atoms()]})
    total = sum(quad(p.force, a, b, epsabs=0, epsrel=1e-13, limit=200)[0] for a, b in zip(knots[:-1], knots[1:]))
    assert p.impulse_Ns == pytest.approx(total, rel=1e-10, abs=1e-14)


def test_impulse_closed_forms():
    assert HalfSine(300.0, 0.003).impulse_Ns == pytest.approx(2 * 300 * 0.003 / math.pi)
    assert Rectangular(300.0, 0.003).impulse_Ns == pytest.approx(0.9)
    assert Triangular(300.0, 0.003, 0.7).impulse_Ns == pytest.approx(0.45)
    tri = Triangular(300.0, 0.003, 0.3)
    tab = Tabulated([0, 0.0009, 0.003], [0, 300, 0])
    assert tab.impulse_Ns == pytest.approx(tri.impulse_Ns, rel=1e-15)


# ------------------------------------------------------------------------------------ atoms


@pytest.mark.parametrize("p", SAMPLE_PULSES, ids=repr)
def test_atoms_reproduce_force(p):
    t = dense(p)
    t = np.concatenate([t, [a.t0 for a in p.atoms()]])  # exactly at every switch-on time too
    scale = max(abs(p.peak_N), 1.0)
    np.testing.assert_allclose(atoms_force(p.atoms(), t), p.force(t), rtol=0, atol=1e-12 * scale)


def test_atom_counts_match_the_decomposition():
    assert len(HalfSine(1, 1).atoms()) == 2
    assert all(a.c != 0 and a.a == 0 and a.b == 0 for a in HalfSine(1, 1).atoms())
    assert [a.a for a in Rectangular(2.0, 1.0).atoms()] == [2.0, -2.0]
    tri = Triangular(1.0, 1.0).atoms()
    assert len(tri) == 3 and all(a.a == 0.0 and a.b != 0.0 for a in tri)
    # tabulated: a step at a jump, a ramp at every knot
    tab = Tabulated([0, 1, 2], [3.0, 4.0, 0.0]).atoms()
    assert [(a.t0, a.a, a.b) for a in tab] == [(0, 3.0, 1.0), (1, 0.0, -5.0), (2, 0.0, 4.0)]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(-1e3, 1e3), min_size=2, max_size=12),
    st.lists(st.floats(1e-4, 1.0), min_size=11, max_size=11),
    st.floats(-5.0, 5.0),
)
def test_atoms_reproduce_random_tabulated_load(forces, gaps, start):
    t = start + np.concatenate([[0.0], np.cumsum(gaps[: len(forces) - 1])])
    p = Tabulated(t, forces)
    probe = np.concatenate([np.linspace(t[0] - 0.1, t[-1] + 0.1, 997), t])
    # rounding of the ramp sums grows with |slope| * elapsed time
    scale = max(1.0, np.max(np.abs(forces))) * (1.0 + (t[-1] - t[0]) / np.min(np.diff(t)))
    np.testing.assert_allclose(atoms_force(p.atoms(), probe), p.force(probe), rtol=0, atol=1e-12 * scale)


def test_atom_force_and_transforms():
    a = Atom(1.0, a=2.0, b=3.0, c=4.0, d=5.0, omega=6.0)
    assert a.force(0.5) == 0.0
    assert a.force(1.0) == pytest.approx(2.0 + 5.0)
    tau = 0.3
    assert a.force(1.3) == pytest.approx(2 + 3 * tau + 4 * math.sin(6 * tau) + 5 * math.cos(6 * tau))
    assert a.shifted(1.0).force(2.3) == pytest.approx(a.force(1.3))
    assert a.scaled(-2.0).force(1.3) == pytest.approx(-2.0 * a.force(1.3))
    with pytest.raises(InputError) as e:
        Atom(0.0, omega=-1.0)
    assert e.value.field == "omega"


# --------------------------------------------------------------------- scaled and shifted


@pytest.mark.parametrize("p", SAMPLE_PULSES, ids=repr)
def test_scaled_and_shifted(p):
    t = dense(p, 2001)
    np.testing.assert_allclose(p.scaled(-2.5).force(t), -2.5 * p.force(t), rtol=1e-12, atol=1e-300)
    # away from the support's ends, where rounding of t + dt may cross the half-open boundary
    knots = np.array([a.t0 for a in p.atoms()])
    t = t[np.min(np.abs(t[:, None] - knots[None, :]), axis=1) > 1e-9]
    s = p.shifted(0.75)
    assert s.start_s == pytest.approx(p.start_s + 0.75) and s.duration_s == pytest.approx(p.duration_s)
    np.testing.assert_allclose(s.force(t + 0.75), p.force(t), rtol=1e-9, atol=1e-9 * abs(p.peak_N))
    assert p.scaled(3.0).impulse_Ns == pytest.approx(3.0 * p.impulse_Ns)


def test_pulses_are_frozen():
    p = HalfSine(1.0, 1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.magnitude_N = 2.0
    tab = Tabulated([0, 1], [0, 1])
    with pytest.raises(ValueError):
        tab.force_N[0] = 3.0  # read-only arrays


def test_tabulated_equality():
    assert Tabulated([0, 1], [0, 1]) == Tabulated(np.array([0.0, 1.0]), [0.0, 1.0])
    assert Tabulated([0, 1], [0, 1]) != Tabulated([0, 1], [0, 2])


# ---------------------------------------------------------------------------------- registry


def test_registry_and_make_pulse():
    assert set(PULSES) == {"half-sine", "rectangular", "triangular"}
    for name, cls in PULSES.items():
        p = make_pulse(name, 10.0, 0.5, start_s=1.0)
        assert isinstance(p, cls) and (p.peak_N, p.duration_s, p.start_s) == (10.0, 0.5, 1.0)
    assert isinstance(make_pulse("Half_Sine", 1.0, 1.0), HalfSine)


def test_unknown_shape_names_pulse():
    with pytest.raises(InputError) as e:
        make_pulse("sawtooth", 1.0, 1.0)
    assert e.value.field == "pulse" and "sawtooth" in e.value.rule


# -------------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "build, field",
    [
        (lambda: HalfSine(1.0, 0.0), "duration_s"),
        (lambda: HalfSine(1.0, -1.0), "duration_s"),
        (lambda: Rectangular(float("nan"), 1.0), "magnitude_N"),
        (lambda: Rectangular(1.0, 1.0, start_s=float("inf")), "start_s"),
        (lambda: Triangular(1.0, 1.0, peak_fraction=1.5), "peak_fraction"),
        (lambda: Triangular(1.0, 1.0, peak_fraction=-0.1), "peak_fraction"),
        (lambda: Tabulated([0.0], [1.0]), "time_s"),
        (lambda: Tabulated([0.0, 1.0, 1.0], [1.0, 2.0, 3.0]), "time_s"),
        (lambda: Tabulated([1.0, 0.0], [1.0, 2.0]), "time_s"),
        (lambda: Tabulated([0.0, float("nan")], [1.0, 2.0]), "time_s"),
        (lambda: Tabulated([0.0, 1.0], [1.0, float("inf")]), "force_N"),
        (lambda: Tabulated([0.0, 1.0], [1.0, 2.0, 3.0]), "force_N"),
        (lambda: HalfSine(1.0, 1.0).scaled(float("nan")), "factor"),
        (lambda: HalfSine(1.0, 1.0).shifted("soon"), "dt"),
    ],
)
def test_bad_input_names_the_argument(build, field):
    with pytest.raises(InputError) as e:
        build()
    assert e.value.field == field
