"""One strike, two paths: the one-way transport (MuJoCo finds the contact, the engine resolves it
while it steps) and the coupled runner's resolution (orchestrator.contact.resolution.resolve on
the body's state) give the same pulse and base shear for the same body state."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from analytical.added_mass import box_added_mass
from analytical.contact_law import box_inertia
from analytical.hydrodynamics import HydroCoefficients
from orchestrator.contact.geometry import box_state, find_contacts, scene_obstacles
from orchestrator.contact.resolution import resolve
from orchestrator.scene.schema import column_for_analysis
from orchestrator.scene.scenefile import load_scene
from orchestrator.transport.engine import TransportSettings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn, with_start

ROOT = Path(__file__).resolve().parents[1]
DEPTH_M = 0.1  # still water: the container afloat at its draft


@pytest.mark.parametrize("yaw_deg, offset_m", [(0.0, 0.0), (20.0, 0.04)], ids=["end_on", "yawed_off_centre"])
def test_the_same_state_struck_one_way_and_two_way_gives_the_same_pulse_and_base_shear(yaw_deg, offset_m):
    """Expected: peak force, duration, impulse and peak base shear within 2 % (the one-way body
    carries the added mass tabulated at 41 drafts, the coupled one the exact value at its
    floating draft; MuJoCo's contact point is the mean of its contact points)."""
    scene = load_scene(ROOT / "cases" / "1debris.yaml")
    debris = scene.debris[0]
    column = column_for_analysis(scene)
    face = scene.column.x_m - scene.column.size_x_m / 2
    rho = scene.fluids.water_density_kg_m3
    draft = debris.mass_kg / (rho * debris.size_m[0] * debris.size_m[1])
    z = DEPTH_M - draft + debris.size_m[2] / 2
    friction = debris.contact.friction_coefficient
    body = with_start(debris, name="box", centre_m=(face - 0.3, scene.column.y_m + offset_m, z), yaw_deg=yaw_deg,
                      pitch_deg=0.0, roll_deg=0.0, velocity_m_s=(1.5, 0.0, 0.0),
                      contact=debris.contact.model_copy(update={"bed_friction_coefficient": friction}))
    flow = FlowField.still_water(DEPTH_M, x_m=(face - 1.0, face + 1.0), y_m=(-0.75, 0.75), t_s=(0.0, 1.0),
                                 water_density_kg_m3=rho)
    settings = TransportSettings(hydro=HydroCoefficients(drag_coefficient=0.0))
    run = run_transport([body], FlumeBounds((face - 1.0, face + 1.0), (-0.75, 0.75)), 0.4, flow,
                        column=PlacedColumn(scene.column.x_m, scene.column.y_m, column), settings=settings)
    strikes = run.impacts[run.impacts["kind"] == "column"]
    assert len(strikes) >= 1
    first = strikes.iloc[0]
    one_way = run.pulses[int(first["event"])]
    centre, rotation, velocity, omega = run.strike_states[int(first["event"])]

    state = box_state(debris.name, centre, rotation, velocity, omega, debris.size_m, debris.mass_kg,
                      box_inertia(debris.size_m, debris.mass_kg, debris.wall_thickness_m))
    contacts = find_contacts([state], scene_obstacles(scene), 0.002)
    (contact,) = [c for c in contacts if c.kind == "column"]
    two_way, _ = resolve(contact, [state], scene)
    assert two_way is not None
    for name in ("peak_force_N", "duration_s", "impulse_Ns", "effective_mass_kg"):
        assert getattr(one_way, name) == pytest.approx(getattr(two_way, name), rel=0.02), name
    assert abs(one_way.base_shear.peak_N) == pytest.approx(abs(two_way.base_shear.peak_N), rel=0.02)
    np.testing.assert_allclose(one_way.normal, two_way.normal, atol=0.02)
    # the water along the normal (the normal in the body's axes), less what the spin takes
    along = box_added_mass(debris.size_m, debris.mass_kg, rho).along(rotation.T @ one_way.normal)
    assert first["added_mass_along_normal_kg"] == pytest.approx(along, rel=0.03)
    if yaw_deg:
        assert one_way.effective_mass_kg < 0.99 * (debris.mass_kg + along)  # off-centre: it turns
    else:
        assert one_way.effective_mass_kg == pytest.approx(debris.mass_kg + along, rel=0.03)
