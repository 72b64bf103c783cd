"""analytical/hydrodynamics.py: the sub-volume forcing against its closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytical.added_mass import box_added_mass
from analytical.errors import InputError
from analytical.hydrodynamics import (
    HydroCoefficients,
    archimedes_draft,
    drag_time_constant,
    heave_period,
    hydro_loads,
    sub_volumes,
)

RHO, G = 998.0, 9.81
SIZE = np.array([0.15, 0.06, 0.06])


def _loads(centre, rot, eta, u=(0.0, 0.0, 0.0), a=(0.0, 0.0, 0.0), vel=(0.0, 0.0, 0.0), omega=(0.0, 0.0, 0.0),
           coeffs=None, size=SIZE):
    coeffs = HydroCoefficients() if coeffs is None else coeffs
    sv = sub_volumes(size, coeffs.sub_volumes)
    pts = np.asarray(centre) + sv.centres_m @ np.asarray(rot).T
    n = pts.shape[0]
    eta_arr = np.array([eta(p) if callable(eta) else eta for p in pts])[None, :]
    return hydro_loads([centre], [rot], [vel], [omega], [size], pts[None], eta_arr,
                       np.broadcast_to(np.asarray(u, float), (1, n, 3)), np.broadcast_to(np.asarray(a, float), (1, n, 3)),
                       coeffs)


def test_sub_volumes_fill_the_box_symmetrically():
    sv = sub_volumes(SIZE, (5, 3, 3))
    assert sv.centres_m.shape == (45, 3)
    assert sv.volume_m3 * 45 == pytest.approx(float(np.prod(SIZE)), rel=1e-12)
    np.testing.assert_allclose(sv.centres_m.mean(axis=0), 0.0, atol=1e-15)
    np.testing.assert_allclose(np.abs(sv.centres_m).max(axis=0), SIZE / 2 - sv.size_m / 2, rtol=1e-12)


def test_level_box_in_a_level_surface_displaces_footprint_times_depth():
    """Expected: V_sub = L W (eta - bottom) exactly, buoyancy rho g V_sub, no moment."""
    centre = (0.0, 0.0, 0.03)
    for depth in (0.005, 0.026, 0.045, 0.07):
        out = _loads(centre, np.eye(3), depth)
        wet = min(depth, 0.06) * 0.15 * 0.06
        assert out.submerged_volume_m3[0] == pytest.approx(wet, rel=1e-12)
        np.testing.assert_allclose(out.force_N[0], [0.0, 0.0, RHO * G * wet], atol=1e-12)
        np.testing.assert_allclose(out.moment_Nm[0], 0.0, atol=1e-12)
        # the box's own added mass at that draft (tabulated at 41 drafts, interpolated)
        own = box_added_mass(tuple(SIZE), RHO * wet, RHO)
        np.testing.assert_allclose(out.added_mass_kg[0], own.masses_kg, rtol=0.03)
        np.testing.assert_allclose(out.added_inertia_kg_m2[0], own.inertias_kg_m2, rtol=0.05, atol=2e-7)
        iso = _loads(centre, np.eye(3), depth, coeffs=HydroCoefficients(added_mass_coefficient=1.0))
        np.testing.assert_allclose(iso.added_mass_kg[0], RHO * wet, rtol=1e-12)


@pytest.mark.parametrize("yaw_deg, axis", [(0.0, 0), (90.0, 1)])
def test_accelerating_water_pushes_with_the_added_mass_along_the_body_axis_it_meets(yaw_deg, axis):
    """Fully submerged and held, in water accelerating at 1 m/s^2 along x: F_x = rho V (1 + C)
    a, with C the box's lengthwise coefficient end-on and its sideways one turned 90 degrees;
    no force across."""
    a = math.radians(yaw_deg)
    rot = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])
    out = _loads((0.0, 0.0, 0.03), rot, 1.0, a=(1.0, 0.0, 0.0), coeffs=HydroCoefficients(drag_coefficient=0.0))
    volume = float(np.prod(SIZE))
    own = box_added_mass(tuple(SIZE), RHO * volume, RHO)
    assert out.force_N[0][0] == pytest.approx(RHO * volume + own.masses_kg[axis], rel=0.01)
    assert abs(out.force_N[0][1]) < 1e-9


def test_drag_of_a_submerged_box_in_a_stream_is_half_rho_cd_a_u_squared():
    """Expected: F_x = 0.5 rho C_d (W H) U^2 on the frontal area, and along y on (L H)."""
    c = HydroCoefficients(drag_coefficient=1.05, added_mass_coefficient=0.0)
    out = _loads((0.0, 0.0, 0.03), np.eye(3), 1.0, u=(0.8, 0.0, 0.0), coeffs=c)
    buoy = RHO * G * float(np.prod(SIZE))
    np.testing.assert_allclose(out.force_N[0], [0.5 * RHO * 1.05 * 0.06 * 0.06 * 0.64, 0.0, buoy], rtol=1e-12)
    out = _loads((0.0, 0.0, 0.03), np.eye(3), 1.0, u=(0.0, -0.5, 0.0), coeffs=c)
    assert out.force_N[0, 1] == pytest.approx(-0.5 * RHO * 1.05 * 0.15 * 0.06 * 0.25, rel=1e-12)


def test_partly_submerged_drag_uses_the_wetted_share_of_the_frontal_area():
    c = HydroCoefficients(drag_coefficient=1.05, added_mass_coefficient=0.0)
    out = _loads((0.0, 0.0, 0.03), np.eye(3), 0.02, u=(1.0, 0.0, 0.0), coeffs=c)
    assert out.force_N[0, 0] == pytest.approx(0.5 * RHO * 1.05 * 0.06 * 0.02 * 1.0, rel=1e-12)


def test_froude_krylov_and_added_mass_scale_with_the_water_acceleration():
    """Expected: (1 + C_a) rho V a for a submerged body in a uniformly accelerating stream."""
    c = HydroCoefficients(drag_coefficient=0.0, added_mass_coefficient=0.7)
    out = _loads((0.0, 0.0, 0.03), np.eye(3), 1.0, a=(2.0, 0.0, 0.0), coeffs=c)
    assert out.force_N[0, 0] == pytest.approx(1.7 * RHO * float(np.prod(SIZE)) * 2.0, rel=1e-12)


def test_a_surface_rising_along_x_turns_the_body_nose_up():
    """Buoyancy is larger where the surface is higher: the moment about y is negative (the
    +x end lifts), and rotation in a still stream is damped by drag."""
    out = _loads((0.0, 0.0, 0.03), np.eye(3), lambda p: 0.03 + 0.1 * p[0])
    assert out.moment_Nm[0, 1] < 0.0
    spin = _loads((0.0, 0.0, 0.03), np.eye(3), 1.0, omega=(0.0, 0.0, 3.0))
    assert spin.moment_Nm[0, 2] < 0.0


def test_closed_forms():
    assert archimedes_draft(0.236, 0.15 * 0.06, RHO) == pytest.approx(0.236 / (RHO * 0.009))
    assert heave_period(0.4, 0.4, 0.04, RHO, G) == pytest.approx(2 * math.pi * math.sqrt(0.8 / (RHO * G * 0.04)))
    assert drag_time_constant(0.8, 1.05, 0.004, 0.5, RHO) == pytest.approx(0.8 / (0.5 * RHO * 1.05 * 0.004 * 0.5))


def test_coefficients_are_validated():
    with pytest.raises(InputError, match="drag_coefficient"):
        HydroCoefficients(drag_coefficient=-1.0)
    with pytest.raises(InputError, match="sub_volumes"):
        HydroCoefficients(sub_volumes=(3, 0, 3))
    with pytest.raises(InputError, match="water_density"):
        HydroCoefficients(water_density_kg_m3=0.0)


def _yaw(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("yaw_deg", [0.0, 12.0, 30.0, 90.0])
def test_drag_acts_along_the_flow_on_the_area_the_box_shows_it(yaw_deg):
    """Held fully submerged in a 0.8 m/s stream along x, yawed: F = 0.5 rho C_d A_p U^2 along
    the stream, A_p = W H |cos| + L H |sin| (the box's projection normal to the flow), no force
    across it. The per-axis (cross-flow) drag instead pushes a yawed box sideways."""
    U, cd = 0.8, 1.05
    base = dict(drag_coefficient=cd, added_mass_coefficient=0.0, munk_moment=False)
    out = _loads((0.0, 0.0, 0.03), _yaw(yaw_deg), 1.0, u=(U, 0.0, 0.0), coeffs=HydroCoefficients(**base))
    a = math.radians(yaw_deg)
    projected = SIZE[1] * SIZE[2] * abs(math.cos(a)) + SIZE[0] * SIZE[2] * abs(math.sin(a))
    assert out.force_N[0][0] == pytest.approx(0.5 * RHO * cd * projected * U**2, rel=1e-9)
    assert abs(out.force_N[0][1]) < 1e-9
    per_axis = _loads((0.0, 0.0, 0.03), _yaw(yaw_deg), 1.0, u=(U, 0.0, 0.0),
                      coeffs=HydroCoefficients(**base, drag_area="per_axis"))
    if 0.0 < yaw_deg < 90.0:
        assert abs(per_axis.force_N[0][1]) > 0.1 * abs(per_axis.force_N[0][0])  # it 'sails'


@pytest.mark.parametrize("yaw_deg", [0.0, 20.0, 45.0, 90.0])
def test_the_munk_moment_turns_a_box_broadside_to_the_flow(yaw_deg):
    """Held fully submerged, yawed by a in a stream U along x, drag off: the yaw moment is
    (A_y - A_x) U^2 sin a cos a (Newman 1977, 4.13), positive for a > 0: it turns the box
    further from the stream, broadside; zero end-on and broadside."""
    U = 0.8
    out = _loads((0.0, 0.0, 0.03), _yaw(yaw_deg), 1.0, u=(U, 0.0, 0.0),
                 coeffs=HydroCoefficients(drag_coefficient=0.0))
    ax, ay, _ = out.added_mass_kg[0]
    a = math.radians(yaw_deg)
    expected = (ay - ax) * U**2 * math.sin(a) * math.cos(a)
    assert out.moment_Nm[0][2] == pytest.approx(expected, rel=1e-9, abs=1e-12)
    if 0.0 < yaw_deg < 90.0:
        assert out.moment_Nm[0][2] > 0.0
    off = _loads((0.0, 0.0, 0.03), _yaw(yaw_deg), 1.0, u=(U, 0.0, 0.0),
                 coeffs=HydroCoefficients(drag_coefficient=0.0, munk_moment=False))
    assert abs(off.moment_Nm[0][2]) < 1e-12
