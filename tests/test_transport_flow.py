"""orchestrator/transport/flow.py: the recorded flow, its sampling, its file and its limits."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytical.dambreak import RitterSolution
from analytical.errors import InputError
from orchestrator.transport.flow import FlowCoverageError, FlowField


def _linear_field() -> FlowField:
    """u = (1 + 0.5 x + 0.2 t, -0.3 y, 0.1 z): trilinear-in-time interpolation reproduces it exactly."""
    t = np.linspace(0.0, 1.0, 5)
    x = np.linspace(-1.0, 1.0, 9)
    y = np.linspace(-0.5, 0.5, 5)
    z = np.array([0.0, 0.05, 0.1, 0.2])
    tt, xx, yy, zz = np.meshgrid(t, x, y, z, indexing="ij")
    u = np.stack([1.0 + 0.5 * xx + 0.2 * tt, -0.3 * yy, 0.1 * zz], axis=-1)
    eta = np.full((t.size, x.size, y.size), 0.15)
    return FlowField(t, x, y, z, 0.0, eta, u, meta={"case": "linear"})


def test_round_trip_through_npz(tmp_path):
    flow = _linear_field()
    path = flow.save(tmp_path / "flow.npz")
    back = FlowField.load(path)
    for name in ("t_s", "x_m", "y_m", "z_m", "eta_m", "velocity_m_s"):
        np.testing.assert_array_equal(getattr(back, name), getattr(flow, name))
    assert back.meta == {"case": "linear"}
    assert (back.bed_z_m, back.water_density_kg_m3, back.gravity_m_s2) == (0.0, 998.0, 9.81)
    assert back.nbytes == flow.nbytes == sum(a.nbytes for a in (flow.t_s, flow.x_m, flow.y_m, flow.z_m,
                                                                  flow.eta_m, flow.velocity_m_s))
    assert path.stat().st_size < flow.nbytes


def test_linear_field_and_its_material_acceleration_are_exact():
    """Expected Du/Dt = du/dt + (u . grad) u = (0.2 + 0.5 u, -0.3 v, 0.1 w), to rounding."""
    flow = _linear_field()
    pts = np.array([[0.13, 0.21, 0.07], [-0.77, -0.4, 0.01], [0.5, 0.0, 0.149]])
    t = 0.37
    s = flow.sample(pts, t)
    x, y, z = pts.T
    u = np.stack([1.0 + 0.5 * x + 0.2 * t, -0.3 * y, 0.1 * z], axis=1)
    np.testing.assert_allclose(s.velocity_m_s, u, rtol=1e-12, atol=1e-12)
    accel = np.stack([0.2 + u[:, 0] * 0.5, u[:, 1] * -0.3, u[:, 2] * 0.1], axis=1)
    np.testing.assert_allclose(s.material_acceleration_m_s2, accel, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(s.eta_m, 0.15)


def test_points_above_the_surface_are_sampled_at_the_surface():
    flow = _linear_field()
    above = flow.sample([[0.0, 0.0, 0.19]], 0.5).velocity_m_s
    at = flow.sample([[0.0, 0.0, 0.15]], 0.5).velocity_m_s
    np.testing.assert_allclose(above, at)


def test_outside_the_record_raises_a_named_coverage_error():
    flow = _linear_field()
    with pytest.raises(FlowCoverageError, match=r"flow\.x: 1\.5 m is outside the recorded x range \[-1, 1\]"):
        flow.sample([[1.5, 0.0, 0.05]], 0.5)
    with pytest.raises(FlowCoverageError, match=r"flow\.y"):
        flow.surface(0.0, -0.6, 0.5)
    with pytest.raises(FlowCoverageError, match=r"flow\.t: 1\.2 s is outside the recorded t range \[0, 1\] s"):
        flow.sample([[0.0, 0.0, 0.05]], 1.2)
    assert issubclass(FlowCoverageError, InputError)


def test_synthetic_fields():
    still = FlowField.still_water(0.1)
    s = still.sample([[0.2, 0.1, 0.05]], 3.0)
    assert s.eta_m[0] == pytest.approx(0.1)
    np.testing.assert_allclose(s.velocity_m_s, 0.0)
    current = FlowField.uniform_current(0.1, 0.4)
    np.testing.assert_allclose(current.sample([[0.2, 0.1, 0.05]], 3.0).velocity_m_s, [[0.4, 0.0, 0.0]])
    sloped = FlowField.sloped_surface(0.1, 0.05)
    assert sloped.surface(0.6, 0.0, 1.0) == pytest.approx(0.13)


def test_ritter_field_follows_the_dam_break_solution():
    """At grid nodes the depth and velocity are Ritter's; between them, within the
    interpolation error; its material acceleration Du/Dt = -2x/(3t^2) + u 2/(3t) within 10 %."""
    x = np.linspace(-1.0, 6.0, 281)
    t = np.linspace(0.0, 2.0, 201)
    flow = FlowField.ritter(0.4, x, t)
    sol = RitterSolution(0.4)
    prof = sol.profile(2.0, 1.0)
    s = flow.sample([[2.0, 0.0, 0.01]], 1.0)
    assert s.eta_m[0] == pytest.approx(prof.depth_m, rel=1e-9)
    assert s.velocity_m_s[0, 0] == pytest.approx(prof.velocity_m_s, rel=1e-6)
    u = prof.velocity_m_s
    expected = -2 * 2.0 / 3.0 + u * 2.0 / 3.0
    assert s.material_acceleration_m_s2[0, 0] == pytest.approx(expected, rel=0.10)
    c0 = math.sqrt(9.81 * 0.4)
    assert flow.surface(2 * c0 * 1.0 + 0.1, 0.0, 1.0) == pytest.approx(0.0, abs=1e-12)


def test_invalid_records_are_rejected():
    flow = _linear_field()
    with pytest.raises(InputError, match="eta_m"):
        FlowField(flow.t_s, flow.x_m, flow.y_m, flow.z_m, 0.0, flow.eta_m + 1.0, flow.velocity_m_s)
    with pytest.raises(InputError, match="increasing"):
        FlowField(flow.t_s[::-1], flow.x_m, flow.y_m, flow.z_m, 0.0, flow.eta_m, flow.velocity_m_s)
    with pytest.raises(InputError, match="velocity_m_s"):
        FlowField(flow.t_s, flow.x_m, flow.y_m, flow.z_m, 0.0, flow.eta_m, flow.velocity_m_s[..., :2])


def test_the_front_reaches_a_point_when_ritters_depth_there_passes_the_rise():
    """Ritter's dry-bed depth (2 c0 - x/t)^2 / 9g passes 1 cm at x/t = 2 c0 - 3 sqrt(0.01 g): at
    x = 2 m behind a 0.4 m impoundment, t = 0.559 s; the record's frames (0.01 s) interpolated give
    it within 2 ms. A point the front never reaches within the record gives NaN."""
    flow = FlowField.ritter(0.4, np.linspace(-1.0, 6.0, 281), np.linspace(0.0, 2.0, 201))
    c0 = math.sqrt(9.81 * 0.4)
    expected = 2.0 / (2 * c0 - 3 * math.sqrt(9.81 * 0.01))
    assert flow.front_arrival_s(2.0, 0.0) == pytest.approx(expected, abs=2e-3)
    assert flow.front_arrival_s(2.0, 0.0, rise_m=0.05) == pytest.approx(
        2.0 / (2 * c0 - 3 * math.sqrt(9.81 * 0.05)), abs=2e-3)
    assert math.isnan(flow.front_arrival_s(5.9, 0.0, rise_m=0.2))
