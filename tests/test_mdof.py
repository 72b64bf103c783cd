"""Tests of analytical.mdof: Timoshenko elements, the cantilever model, modal and Newmark base shear.

References used as independent checks: closed-form Timoshenko element matrices (Przemieniecki
1968; Friedman & Kosmatka 1993), Timoshenko cantilever statics, the Euler-Bernoulli cantilever
frequency, and the exact continuous Timoshenko cantilever frequencies found here by shooting.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import linalg
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from analytical import mdof
from analytical.column import Column
from analytical.errors import InputError
from analytical.pulses import HalfSine, Rectangular, Tabulated
from tests.conftest import input_error

STUDY = Column()
CALIBRATED = Column(base="calibrated")
#: The study's Table 1 MDOF pulse.
MDOF_PULSE = HalfSine(236.93, 4.7e-3)
BETA1 = 1.87510406871196  # first root of cos(x) cosh(x) = -1


def _strain_energy_stiffness(L, EI, kGA):
    """Element stiffness from the shape functions' strain energy (independent of the closed form)."""
    phi = 12 * EI / (kGA * L * L)
    x, w = np.polynomial.legendre.leggauss(6)
    xi, wq = 0.5 * (x + 1), 0.5 * w
    h = 1e-6
    nw_p, nt_p = mdof.shape_functions(xi + h, L, phi)
    nw_m, nt_m = mdof.shape_functions(xi - h, L, phi)
    _, nt = mdof.shape_functions(xi, L, phi)
    dw = (nw_p - nw_m) / (2 * h * L)  # d/dz
    dt = (nt_p - nt_m) / (2 * h * L)
    gamma = dw - nt
    return L * (EI * np.einsum("g,gi,gj->ij", wq, dt, dt) + kGA * np.einsum("g,gi,gj->ij", wq, gamma, gamma))


def _timoshenko_frequencies(column, k_theta=None, f_max=1500.0):
    """Exact natural frequencies (Hz) of the continuous Timoshenko cantilever by shooting.

    -w^2 rho A W = kGA (W'' - T');  -w^2 rho I T = EI T'' + kGA (W' - T); W(0) = 0 and
    T(0) = 0 (rigid) or EI T'(0) = k_theta T(0); free tip: EI T' = 0, kGA (W' - T) = 0.
    """
    EI, kGA = column.bending_stiffness_Nm2, column.shear_stiffness_N
    rA, rI, H = column.mass_per_length_kg_m, column.rotary_inertia_kg_m, column.height_m

    def det(f):
        w2 = (2 * math.pi * f) ** 2

        def rhs(_z, y):
            W, Wp, T, Tp = y
            return [Wp, Tp - w2 * rA * W / kGA, Tp, (-w2 * rI * T - kGA * (Wp - T)) / EI]

        starts = [[0, 1, 0, 0], [0, 0, 0, 1]] if k_theta is None else [[0, 1, 0, 0], [0, 0, 1, k_theta / EI]]
        cols = []
        for y0 in starts:
            W, Wp, T, Tp = solve_ivp(rhs, (0, H), y0, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
            cols.append([EI * Tp, kGA * (Wp - T)])
        return np.linalg.det(np.array(cols))

    grid = np.linspace(10.0, f_max, 120)
    values = [det(f) for f in grid]
    return [
        brentq(det, a, b, xtol=1e-11)
        for a, b, da, db in zip(grid[:-1], grid[1:], values[:-1], values[1:])
        if np.sign(da) != np.sign(db)
    ]


# --------------------------------------------------------------------------- element
def test_element_stiffness_by_hand():
    # L = 0.5, EI = 2, kGA = 48  ->  phi = 12*2/(48*0.25) = 2, EI/((1+phi) L^3) = 16/3.
    k, _ = mdof.timoshenko_element(0.5, 2.0, 48.0, 1.0, 0.0)
    c = 16.0 / 3.0
    expected = c * np.array(
        [
            [12, 3, -12, 3],
            [3, 6 * 0.25, -3, 0 * 0.25],
            [-12, -3, 12, -3],
            [3, 0, -3, 6 * 0.25],
        ]
    )
    np.testing.assert_allclose(k, expected, rtol=1e-14, atol=1e-13)
    assert k[0, 0] == pytest.approx(64.0) and k[1, 1] == pytest.approx(8.0) and k[1, 3] == pytest.approx(0.0, abs=1e-13)


def test_element_stiffness_equals_strain_energy_of_the_shape_functions():
    L, EI, kGA = 0.37, 3.1, 7.0
    k, _ = mdof.timoshenko_element(L, EI, kGA, 1.0, 0.0)
    np.testing.assert_allclose(k, _strain_energy_stiffness(L, EI, kGA), rtol=1e-7, atol=1e-7 * np.abs(k).max())
    # Rigid-body modes: translation and rotation produce no force.
    np.testing.assert_allclose(k @ [1, 0, 1, 0], 0, atol=1e-12)
    np.testing.assert_allclose(k @ [0, 1, L, 1], 0, atol=1e-12)


def test_element_mass_euler_bernoulli_limit_by_hand():
    # phi = 0, no rotary inertia: the classical rho A L / 420 matrix.
    L, rhoA = 0.5, 3.0
    _, m = mdof.timoshenko_element(L, 2.0, math.inf, rhoA, 0.0)
    expected = rhoA * L / 420 * np.array(
        [
            [156, 22 * L, 54, -13 * L],
            [22 * L, 4 * L * L, 13 * L, -3 * L * L],
            [54, 13 * L, 156, -22 * L],
            [-13 * L, -3 * L * L, -22 * L, 4 * L * L],
        ]
    )
    np.testing.assert_allclose(m, expected, rtol=1e-13, atol=1e-15)
    assert m[[0, 0, 2, 2], [0, 2, 0, 2]].sum() == pytest.approx(rhoA * L)  # total translational mass


def test_element_mass_against_friedman_kosmatka_closed_form():
    L, EI, kGA, rA, rI = 0.37, 3.1, 7.0, 2.3, 0.011
    f = 12 * EI / (kGA * L * L)
    _, m = mdof.timoshenko_element(L, EI, kGA, rA, rI)
    a = 13 / 35 + 7 * f / 10 + f * f / 3
    b = (11 / 210 + 11 * f / 120 + f * f / 24) * L
    c = 9 / 70 + 3 * f / 10 + f * f / 6
    d = (13 / 420 + 3 * f / 40 + f * f / 24) * L
    e = (1 / 105 + f / 60 + f * f / 120) * L * L
    g = (1 / 140 + f / 60 + f * f / 120) * L * L
    trans = rA * L / (1 + f) ** 2 * np.array([[a, b, c, -d], [b, e, d, -g], [c, d, a, -b], [-d, -g, -b, e]])
    p = (1 / 10 - f / 2) * L
    q = (2 / 15 + f / 6 + f * f / 3) * L * L
    r = (-1 / 30 - f / 6 + f * f / 6) * L * L
    rot = rI / ((1 + f) ** 2 * L) * np.array([[6 / 5, p, -6 / 5, p], [p, q, -p, r], [-6 / 5, -p, 6 / 5, -p], [p, r, -p, q]])
    np.testing.assert_allclose(m, trans + rot, rtol=1e-12)


def test_element_rejects_bad_arguments():
    with pytest.raises(InputError, match="length_m"):
        mdof.timoshenko_element(0.0, 1, 1, 1, 0)
    with pytest.raises(InputError, match="shear_stiffness_N"):
        mdof.timoshenko_element(1.0, 1, -1, 1, 0)
    with pytest.raises(InputError, match="rotary_inertia_kg_m"):
        mdof.timoshenko_element(1.0, 1, 1, 1, -1)
    with pytest.raises(InputError, match="elements"):
        mdof.assemble_beam(0, 1.0, 1, 1, 1, 0)


# --------------------------------------------------------------------------- statics
@pytest.mark.parametrize("column", [STUDY, Column(elements=7), CALIBRATED], ids=["study", "7 elements", "calibrated"])
def test_static_deflection_matches_timoshenko_closed_form(column):
    EI, kGA, H = column.bending_stiffness_Nm2, column.shear_stiffness_N, column.height_m
    k_theta = mdof.column_model(column).base_spring_Nm_rad
    P = 236.93
    # Loads at the tip, at a node, mid-element and inside the first element: the nodal
    # displacements are exact wherever the load acts (exact static shape functions).
    for a in (H, 0.40, 0.4031, 0.0021):
        base_rot = 0.0 if k_theta is None else P * a / k_theta
        tip = P * a * a * (3 * H - a) / (6 * EI) + P * a / kGA + base_rot * H
        assert mdof.static_deflection(column, a, H, P) == pytest.approx(tip, rel=1e-6)
        on_node = abs(a * column.elements / H - round(a * column.elements / H)) < 1e-9
        if on_node:
            at_load = P * a**3 / (3 * EI) + P * a / kGA + base_rot * a
            assert mdof.static_deflection(column, a, a, P) == pytest.approx(at_load, rel=1e-6)
    assert mdof.lateral_stiffness(column, H) == pytest.approx(
        1.0 / (H**3 / (3 * EI) + H / kGA + (0.0 if k_theta is None else H * H / k_theta)), rel=1e-6
    )


def test_static_reciprocity():
    for column in (STUDY, CALIBRATED, Column(elements=9)):
        for z1, z2 in ((0.16, 0.8), (0.4031, 0.123), (0.0021, 0.79)):
            d12 = mdof.static_deflection(column, z1, z2)
            d21 = mdof.static_deflection(column, z2, z1)
            assert d12 == pytest.approx(d21, rel=1e-10)


# --------------------------------------------------------------------------- modes
def test_euler_bernoulli_limit_frequency_converges_to_closed_form():
    EI, rA, H = STUDY.bending_stiffness_Nm2, STUDY.mass_per_length_kg_m, STUDY.height_m
    exact = BETA1**2 * math.sqrt(EI / (rA * H**4)) / (2 * math.pi)  # 100.50 Hz
    errors = []
    for n in (2, 4, 8, 16):
        k, m = mdof.assemble_beam(n, H, EI, math.inf, rA, 0.0)
        w2 = linalg.eigh(k.toarray()[2:, 2:], m.toarray()[2:, 2:], eigvals_only=True)[0]
        errors.append(math.sqrt(w2) / (2 * math.pi) / exact - 1)
    assert all(e > 0 for e in errors)  # consistent mass: an upper bound
    assert all(b < a / 10 for a, b in zip(errors, errors[1:]))  # ~ h^4
    assert errors[-1] < 1e-6
    # A Column with a huge kappa G A keeps its rotary inertia, which lowers f1 a little
    # (a Rayleigh beam); shear deformation (the study's kappa = 0.5) lowers it much more.
    stiff = mdof.modes(Column(shear_coefficient=1e9, elements=40))[0]
    assert 0.95 * exact < stiff < exact
    assert mdof.modes(STUDY)[0] < 0.9 * stiff


def test_study_rigid_base_frequencies_match_exact_timoshenko_cantilever():
    f = mdof.modes(STUDY)
    exact = _timoshenko_frequencies(STUDY, f_max=1200.0)  # 88.357, 360.27, 762.32, 1117.97 Hz
    assert f[0] == pytest.approx(88.36, abs=0.01)  # the rigid-base beam: about 88 Hz (analytical/mdof.py)
    assert f[0] == pytest.approx(exact[0], rel=1e-5)
    np.testing.assert_allclose(f[:4], exact[:4], rtol=2e-4)
    assert np.all(np.diff(f) > 0) and not f.flags.writeable


def test_calibrated_base_reaches_the_measured_frequency():
    model = mdof.column_model(CALIBRATED)
    assert model.frequencies_Hz[0] == pytest.approx(70.0, rel=1e-6)
    assert model.base_spring_Nm_rad is not None and model.base_spring_Nm_rad > 0
    assert mdof.column_model(STUDY).base_spring_Nm_rad is None
    exact = _timoshenko_frequencies(CALIBRATED, model.base_spring_Nm_rad, f_max=800.0)
    np.testing.assert_allclose(model.frequencies_Hz[:3], exact[:3], rtol=1e-4)
    # A spring softens every mode a little.
    assert np.all(model.frequencies_Hz[:4] < mdof.modes(STUDY)[:4])


def test_calibrated_target_above_the_rigid_frequency_is_refused():
    with pytest.raises(InputError) as info:
        mdof.column_model(Column(base="calibrated", natural_frequency_Hz=95.0))
    assert info.value.field == "column.natural_frequency_Hz"


def test_modes_are_mass_normalised_and_rayleigh_damping_is_on_modes_1_and_2():
    model = mdof.column_model(Column(elements=20, base="calibrated"))
    phi = model.mode_shapes
    m, k = model.mass.toarray(), model.stiffness.toarray()
    np.testing.assert_allclose(phi.T @ m @ phi, np.eye(len(phi)), atol=1e-9)
    np.testing.assert_allclose(phi.T @ k @ phi, np.diag(model.circular_frequencies_rad_s**2), rtol=1e-8, atol=1e-3)
    np.testing.assert_allclose(model.damping_ratios[:2], 0.045, rtol=1e-12)
    c = model.damping.toarray()
    np.testing.assert_allclose(c, model.rayleigh_a0_1_s * m + model.rayleigh_a1_s * k, rtol=1e-12, atol=1e-12)
    assert np.all(model.damping_ratios[2:] > 0.045)


def test_model_is_cached_per_column():
    assert mdof.column_model(Column()) is mdof.column_model(STUDY)
    with pytest.raises(InputError, match="column"):
        mdof.column_model("study")


# --------------------------------------------------------------------------- dynamics
@pytest.mark.parametrize("column", [STUDY, CALIBRATED], ids=["rigid", "calibrated"])
@pytest.mark.parametrize("pulse", [MDOF_PULSE, Rectangular(322.83, 1.4e-3)], ids=["half-sine", "rectangular"])
def test_modal_and_newmark_base_shear_agree(pulse, column):
    t = np.arange(0.0, 0.03, 1e-5) + 0.5e-5  # samples off the pulse's jumps
    modal = mdof.mdof_response(pulse, column, 0.40, t)
    newmark = mdof.mdof_response(pulse, column, 0.40, t, method="newmark")
    assert newmark.peak_N == pytest.approx(modal.peak_N, rel=2e-3)
    rms = np.sqrt(np.mean((modal.response_N - newmark.response_N) ** 2))
    assert rms < 2e-3 * modal.peak_N
    assert modal.peak_N > 100.0  # a real response, not two zeros agreeing


@pytest.mark.parametrize("column", [STUDY, CALIBRATED], ids=["rigid", "calibrated"])
def test_long_sampled_pulse_modal_recurrence_against_newmark(column):
    # An impact pulse as the contact integration gives it: 1,500 samples with a kink at each.
    # Modal superposition carries every mode over the samples by the exact recurrence
    # (analytical.oscillator.piecewise_linear_response); fine-step Newmark is independent.
    times = np.linspace(1e-3, 1e-3 + 4.7e-3, 1500)
    rng = np.random.default_rng(5)
    forces = 236.93 * np.sin(np.pi * (times - times[0]) / 4.7e-3) * (1.0 + 0.02 * rng.standard_normal(times.size))
    forces[[0, -1]] = 0.0
    pulse = Tabulated(times, forces)
    t = np.concatenate([times, times[-1] + np.arange(1, 2001) * 1e-5])
    modal = mdof.mdof_response(pulse, column, 0.40, t)
    newmark = mdof.mdof_response(pulse, column, 0.40, t, method="newmark", dt=4.7e-3 / 6000)
    assert modal.peak_N > 100.0
    assert modal.peak_N == pytest.approx(newmark.peak_N, rel=1e-4)
    assert np.abs(modal.response_N - newmark.response_N).max() < 1e-3 * modal.peak_N


def test_short_rectangular_pulse_low_on_the_column_needs_every_mode():
    # The ASCE (k_d) pulse of the study's Table 1 at 0.16 m: the jumps excite the overdamped
    # high modes (zeta > 1 above about 10 kHz); leaving them out of the modal sum puts a
    # spurious 2 % spike at the end of the pulse.
    pulse = Rectangular(822.34, 0.6e-3)
    t = np.arange(0.0, 3e-3, 1e-6)
    modal = mdof.mdof_response(pulse, STUDY, 0.16, t)
    newmark = mdof.newmark_history(pulse, STUDY, 0.16, 3e-3, dt=2e-7)
    assert modal.peak_N == pytest.approx(newmark.base_shear_N.max(), rel=2e-4)
    near_end = (t > 0.59e-3) & (t < 0.7e-3)
    reference = np.interp(t[near_end], newmark.time_s, newmark.base_shear_N)
    np.testing.assert_allclose(modal.response_N[near_end], reference, atol=1e-3 * modal.peak_N)


def test_study_mdof_pulse_peak_base_shear():
    # The study's Table 1 MDOF pulse at the mean impact height; the measured peak of that record
    # is about 225 N and the study's fit underestimated it by 8.7 %: about 205 N.
    t = np.linspace(0.0, 0.05, 50001)
    r = mdof.mdof_response(MDOF_PULSE, STUDY, 0.40, t)
    assert r.peak_N == pytest.approx(207.63, abs=0.02)
    assert 0.004 < r.time_of_peak_s < 0.005


def test_modal_number_of_modes_converges():
    t = np.linspace(0.0, 0.02, 2001)
    auto = mdof.mdof_response(MDOF_PULSE, STUDY, 0.40, t).response_N
    every = mdof.mdof_response(MDOF_PULSE, STUDY, 0.40, t, n_modes=len(mdof.modes(STUDY))).response_N
    np.testing.assert_allclose(auto, every, atol=1e-5 * np.abs(every).max())
    errors = [
        abs(mdof.mdof_response(MDOF_PULSE, STUDY, 0.40, t, n_modes=n).peak_N - every.max()) for n in (1, 3, 10)
    ]
    assert errors[0] > errors[1] > errors[2] and errors[0] > 0.01 * every.max()


def test_overdamped_modal_responses_against_numerical_integration():
    pulse = Rectangular(1.0, 2e-4, start_s=1e-4)
    omega, zeta = np.array([3e4, 8e4]), np.array([1.0, 4.0])
    t = np.linspace(0.0, 6e-4, 61)
    qd, qdd = mdof._overdamped_response(tuple(pulse.atoms()), t, omega, zeta)
    for k in range(2):
        w, z = omega[k], zeta[k]

        def rhs(s, y):
            return [y[1], float(pulse.force(s)) - 2 * z * w * y[1] - w * w * y[0]]

        sol = solve_ivp(rhs, (0, 6e-4), [0, 0], t_eval=t, method="Radau", rtol=1e-10, atol=1e-16,
                        max_step=1e-6)
        np.testing.assert_allclose(qd[k], sol.y[1], atol=1e-6 * np.abs(sol.y[1]).max())
        after = (t > 1e-4 + 1e-6) & (np.abs(t - 3e-4) > 1e-6)
        accel = np.array([rhs(s, y)[1] for s, y in zip(t, sol.y.T)])
        np.testing.assert_allclose(qdd[k][after], accel[after], atol=1e-5 * np.abs(accel).max())


def test_slowly_applied_load_gives_base_shear_equal_to_the_load():
    # A 1 s ramp to 100 N, then held. After the start-up transient (decay time 1/(zeta w) of
    # about 0.04 s) the response is quasi-static: during the ramp the base shear trails the
    # load only by the (mass-proportional) damping force, about 0.01 N; once the load is
    # held it equals the load.
    pulse = Tabulated([0.0, 1.0, 2.0], [0.0, 100.0, 100.0])
    ramp = np.linspace(0.3, 0.99, 70)
    hold = np.linspace(1.4, 1.99, 60)
    t = np.concatenate([ramp, hold])
    for column in (STUDY, CALIBRATED):
        for method in ("modal", "newmark"):
            kwargs = {"dt": 1e-4} if method == "newmark" else {}
            r = mdof.mdof_response(pulse, column, 0.55, t, method=method, **kwargs)
            v = r.response_N
            np.testing.assert_allclose(v[: ramp.size], pulse.force(ramp), atol=0.05)
            np.testing.assert_allclose(v[ramp.size :], 100.0, atol=1e-3)


def test_linearity_and_time_invariance():
    t = np.linspace(0.0, 0.02, 801)
    base = mdof.mdof_response(MDOF_PULSE, STUDY, 0.3, t).response_N
    doubled = mdof.mdof_response(MDOF_PULSE.scaled(-2.0), STUDY, 0.3, t)
    np.testing.assert_allclose(doubled.response_N, -2.0 * base, rtol=1e-10, atol=1e-9)
    assert doubled.peak_N == pytest.approx(-2.0 * base.max(), rel=1e-10)  # peak in the load's direction
    later = mdof.mdof_response(MDOF_PULSE.shifted(0.002), STUDY, 0.3, t + 0.002).response_N
    np.testing.assert_allclose(later, base, atol=1e-8 * base.max())


def test_newmark_is_linear_and_time_invariant():
    t = np.linspace(0.0, 0.01, 201)
    a = mdof.mdof_response(MDOF_PULSE, STUDY, 0.2, t, method="newmark", dt=2e-5).response_N
    b = mdof.mdof_response(MDOF_PULSE.scaled(3.0), STUDY, 0.2, t, method="newmark", dt=2e-5).response_N
    np.testing.assert_allclose(b, 3.0 * a, rtol=1e-9, atol=1e-9)
    later = mdof.mdof_response(MDOF_PULSE.shifted(0.0031), STUDY, 0.2, t + 0.0031, method="newmark", dt=2e-5)
    np.testing.assert_allclose(later.response_N, a, atol=1e-7 * np.abs(a).max())


@pytest.mark.parametrize("height", [0.40, 0.0021, 0.80], ids=["0.40 m", "first element", "tip"])
def test_base_shear_reaction_and_equilibrium_forms_agree(height):
    for column in (STUDY, CALIBRATED):
        h = mdof.newmark_history(Rectangular(322.83, 1.4e-3), column, height, 0.01, dt=5e-6)
        scale = np.abs(h.base_shear_N).max()
        np.testing.assert_allclose(h.base_shear_reaction_N, h.base_shear_N, atol=1e-7 * scale)
        assert scale > 100.0


def test_newmark_conserves_energy_without_damping():
    column = Column(damping_ratio=0.0, elements=40)
    pulse = HalfSine(200.0, 5e-4)
    h = mdof.newmark_history(pulse, column, 0.6, 0.02, dt=2e-5, energy=True)
    after = h.energy_J[h.time_s >= pulse.end_s + 2e-5]
    assert after.mean() > 1e-4
    assert np.ptp(after) < 1e-9 * after.mean()
    # With damping the energy can only go down once the load has gone.
    d = mdof.newmark_history(pulse, Column(elements=40), 0.6, 0.02, dt=2e-5, energy=True)
    tail = d.energy_J[d.time_s >= pulse.end_s + 2e-5]
    assert np.all(np.diff(tail) <= 1e-12 * tail[0]) and tail[-1] < 0.5 * tail[0]
    with pytest.raises(InputError) as info:  # the exact modal responses need damped modes
        mdof.mdof_response(pulse, column, 0.6, np.linspace(0, 0.01, 11), method="modal")
    assert info.value.field == "column.damping_ratio"
    # by default an undamped column is integrated by Newmark: its peak agrees with the exact
    # modal response of a column with almost no damping
    t = np.linspace(0, 0.005, 501)
    undamped = mdof.mdof_response(pulse, column, 0.6, t)
    nearly = mdof.mdof_response(pulse, Column(damping_ratio=1e-6, elements=40), 0.6, t)
    assert undamped.peak_N == pytest.approx(nearly.peak_N, rel=2e-3)


def test_peak_base_shear_converges_with_elements_and_time_step():
    t = np.linspace(0.0, 0.01, 2001)
    peaks = [mdof.mdof_response(MDOF_PULSE, Column(elements=n), 0.40, t).peak_N for n in (20, 40, 80, 160, 320)]
    errors = [abs(p - peaks[-1]) for p in peaks[:-1]]
    assert all(b < a for a, b in zip(errors, errors[1:]))
    assert errors[-1] < 1e-4 * peaks[-1]  # 160 elements: converged to far better than 0.1 %

    reference = mdof.mdof_response(MDOF_PULSE, STUDY, 0.40, np.linspace(0.0, 0.01, 100001)).peak_N
    dt_errors = []
    for dt in (4.7e-5, 2.35e-5, 1.175e-5):
        h = mdof.newmark_history(MDOF_PULSE, STUDY, 0.40, 0.01, dt=dt)
        dt_errors.append(abs(h.base_shear_N.max() - reference))
    assert all(b < a / 2.5 for a, b in zip(dt_errors, dt_errors[1:]))  # second order
    default = mdof.newmark_history(MDOF_PULSE, STUDY, 0.40, 0.01)
    assert default.dt_s < 1e-5
    assert default.base_shear_N.max() == pytest.approx(reference, rel=1e-4)


# --------------------------------------------------------------------------- input checks
@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"height_m": 0.0}, "height_m"),
        ({"height_m": 0.81}, "height_m"),
        ({"height_m": float("nan")}, "height_m"),
        ({"method": "euler"}, "method"),
        ({"n_modes": 0}, "n_modes"),
        ({"n_modes": 10_000}, "n_modes"),
        ({"n_modes": 2.5}, "n_modes"),
        ({"method": "newmark", "dt": -1e-6}, "dt"),
        ({"method": "newmark", "n_modes": 5}, "n_modes"),
        ({"dt": 1e-6}, "dt"),
        ({"t": [0.0, 0.002, 0.001]}, "t"),
        ({"t": [[0.0, 1.0]]}, "t"),
    ],
)
def test_bad_response_arguments_name_the_argument(kwargs, field):
    args = {"height_m": 0.4, "t": np.linspace(0, 0.01, 11)}
    args.update(kwargs)
    input_error(field, mdof.mdof_response, MDOF_PULSE, STUDY, **args)


def test_static_deflection_rejects_heights_outside_the_column():
    with pytest.raises(InputError, match="at_height_m"):
        mdof.static_deflection(STUDY, 0.4, 0.9)
    with pytest.raises(InputError, match="height_m"):
        mdof.static_deflection(STUDY, -0.1, 0.4)
