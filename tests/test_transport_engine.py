"""orchestrator/transport/engine.py on real MuJoCo, against closed forms.

Each test names the expected value and a tolerance that the model could miss. The flat box
(0.20 x 0.20 x 0.02 m, 0.4 kg: draft 10 mm, metacentric height 0.33 m) is the floating test
body: the study's container (square section, relative density 0.44) is unstable upright in roll.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytical.added_mass import box_added_mass
from analytical.contact_law import column_impact, contact_law
from analytical.hydrodynamics import HydroCoefficients, archimedes_draft, drag_time_constant, heave_period
from orchestrator.transport.engine import BODY_COLUMNS, TransportSettings, run_transport
from orchestrator.transport.events import IMPACT_COLUMNS
from orchestrator.transport.flow import FlowCoverageError, FlowField
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn
from tests.conftest import debris

RHO, G = 998.0, 9.81
PLATE = dict(size_m=(0.2, 0.2, 0.02), mass_kg=0.4)
CONTAINER_BOX = dict(size_m=(0.15, 0.06, 0.06), mass_kg=0.236, wall_thickness_m=0.005)
FLUME = FlumeBounds((-1.0, 3.0), (-0.5, 0.5))
ELASTIC_KEYS = {"damping_ratio": 0.0}  # the container's spring without its dashpot: closed forms
ELASTIC = contact_law(**ELASTIC_KEYS)


def _still(depth=0.1, **kw):
    return FlowField.still_water(depth, x_m=(-1.0, 3.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0), **kw)


def test_a_box_in_still_water_floats_level_at_archimedes_draft():
    """Expected draft m / (rho A) = 10.02 mm within 2 %; level within 0.01 degrees."""
    run = run_transport([debris("plate", centre_m=(0.0, 0.0, 0.1), **PLATE)], FLUME, 2.0, _still())
    track = run.track("plate")
    assert list(run.tracks.columns) == BODY_COLUMNS
    late = track[track["time_s"] > 1.5]
    draft = 0.1 - (late["z_m"].mean() - 0.01)
    assert draft == pytest.approx(archimedes_draft(0.4, 0.04, RHO), rel=0.02)
    assert late["pitch_deg"].abs().max() < 0.01 and late["roll_deg"].abs().max() < 0.01


@pytest.mark.parametrize("coefficient", [None, 1.0], ids=["own", "isotropic_1"])
def test_heave_period_with_the_added_mass_of_the_displaced_water(coefficient):
    """Expected 2 pi sqrt((m + m_a) / (rho g A)) within 10 %, m_a the model's heave added mass:
    the plate's own (analytical.added_mass, 2.21 kg: a thin plate carries 5.5 times the water it
    displaces; 0.513 s) or C_a rho V_sub with C_a = 1 (0.4 kg; 0.284 s). Without added mass it
    would be 0.201 s."""
    settings = TransportSettings(hydro=HydroCoefficients(added_mass_coefficient=coefficient))
    run = run_transport([debris("plate", centre_m=(0.0, 0.0, 0.103), **PLATE)], FLUME, 2.0, _still(),
                        settings=settings)
    track = run.track("plate")
    z = track["z_m"].to_numpy() - 0.1
    t = track["time_s"].to_numpy()
    up = np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0]
    crossings = t[up] - z[up] * (t[up + 1] - t[up]) / (z[up + 1] - z[up])
    assert len(crossings) >= 4
    m_a = 0.4 if coefficient else box_added_mass((0.2, 0.2, 0.02), 0.4, RHO).masses_kg[2]
    assert np.diff(crossings).mean() == pytest.approx(heave_period(0.4, m_a, 0.04, RHO, G), rel=0.10)


def test_on_a_sloped_surface_a_thin_box_tilts_with_it():
    """eta = h + s x, s = 0.05: the plate pitches nose-up (pitch < 0 in Rz Ry Rx) by
    atan(s) BM / GM = 2.91 degrees (BM = L^2 / (12 T), GM = T/2 + BM - H/2; small angles),
    within 10 %, mean over the last second; no roll, no drift (the record has no velocity)."""
    s = 0.05
    flow = FlowField.sloped_surface(0.1, s, x_m=(-1.0, 3.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0))
    run = run_transport([debris("plate", centre_m=(0.0, 0.0, 0.1), **PLATE)], FLUME, 3.0, flow)
    late = run.track("plate").query("time_s > 2.0")
    draft = archimedes_draft(0.4, 0.04, RHO)
    bm = 0.2 ** 2 / (12 * draft)
    gm = draft / 2 + bm - 0.01
    expected = -math.degrees(math.atan(s)) * bm / gm
    assert late["pitch_deg"].mean() == pytest.approx(expected, rel=0.10)
    assert late["roll_deg"].abs().max() < 0.01
    assert abs(late["x_m"].iloc[-1]) < 1e-3


def test_in_a_uniform_current_a_floating_box_drifts_up_to_the_current_speed():
    """(m + m_a) dv/dt = 0.5 rho C_d A (U - v)^2 from rest: v = U (t/tau) / (1 + t/tau), tau =
    (m + m_a) / (0.5 rho C_d A U) (A = width x draft, m_a the plate's own surge added mass,
    0.05 kg; 0.86 s at the default C_d = 1.05). Expected v(tau) = U/2 and v(2 tau) = 2U/3 within 5 %."""
    U = 0.5
    flow = FlowField.uniform_current(0.1, U, x_m=(-1.0, 3.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0))
    run = run_transport([debris("plate", centre_m=(-0.8, 0.0, 0.1), **PLATE)], FLUME, 3.2, flow)
    track = run.track("plate")
    area = 0.2 * archimedes_draft(0.4, 0.04, RHO)
    m_a = box_added_mass((0.2, 0.2, 0.02), 0.4, RHO).masses_kg[0]
    tau = drag_time_constant(0.4 + m_a, HydroCoefficients().drag_coefficient, area, U, RHO)
    assert np.interp(tau, track["time_s"], track["u_m_s"]) == pytest.approx(U / 2, rel=0.05)
    assert np.interp(2 * tau, track["time_s"], track["u_m_s"]) == pytest.approx(2 * U / 3, rel=0.05)


def _deceleration(track) -> float:
    sliding = track[(track["time_s"] > 0.02) & (track["u_m_s"] > 0.1)]
    return -float(np.polyfit(sliding["time_s"], sliding["u_m_s"], 1)[0])


def test_a_box_sliding_on_a_dry_bed_stops_at_mu_g():
    """Expected deceleration mu g = 2.943 m/s^2 within 3 %, the box staying on the bed (no hops)."""
    body = debris("box", centre_m=(0.0, 0.0, 0.03), velocity_m_s=(1.0, 0.0, 0.0), friction=0.3,
                  **CONTAINER_BOX)
    run = run_transport([body], FLUME, 0.45, settings=TransportSettings(output_interval_s=0.005))
    track = run.track("box")
    assert _deceleration(track) == pytest.approx(0.3 * G, rel=0.03)
    assert track["z_m"].max() < 0.0301
    assert track["u_m_s"].iloc[-1] == pytest.approx(0.0, abs=1e-3)


def test_a_partly_submerged_box_slides_at_mu_g_less_its_buoyancy():
    """15 mm of still water (the study's wet bed), drag and added mass off to isolate friction:
    expected mu g (1 - rho V_sub / m) = 1.263 m/s^2 within 3 %."""
    body = debris("box", centre_m=(0.0, 0.0, 0.03), velocity_m_s=(1.0, 0.0, 0.0), friction=0.3,
                  **CONTAINER_BOX)
    settings = TransportSettings(output_interval_s=0.005,
                                 hydro=HydroCoefficients(drag_coefficient=0.0, added_mass_coefficient=0.0))
    run = run_transport([body], FLUME, 0.5, _still(0.015), settings=settings)
    v_sub = 0.15 * 0.06 * 0.015
    assert _deceleration(run.track("box")) == pytest.approx(0.3 * G * (1 - RHO * v_sub / 0.236), rel=0.03)


@pytest.mark.parametrize("keys", [{}, {"restitution": 0.5}], ids=["container", "restitution_0.5"])
def test_a_box_launched_at_the_column(keys):
    """At 1.5 m/s head-on (frictionless bed): the recorded impact velocity 1.5 m/s within 2 %;
    the pulse equals column_impact's at that velocity and height (rel 1e-6: the same call);
    the rebound speed over the impact speed equals the law's rigid-wall restitution within 10 %."""
    body = debris("box", centre_m=(0.5, 0.0, 0.03), velocity_m_s=(1.5, 0.0, 0.0), friction=0.0,
                  contact=keys, **CONTAINER_BOX)
    law = contact_law(**keys)
    run = run_transport([body], FLUME, 0.5, column=PlacedColumn(1.0, 0.0))
    assert set(IMPACT_COLUMNS) <= set(run.impacts.columns)
    column = run.impacts[run.impacts["kind"] == "column"]
    assert len(column) == 1
    hit = column.iloc[0]
    assert hit["impact_velocity_m_s"] == pytest.approx(1.5, rel=0.02)
    assert hit["normal_x"] == pytest.approx(-1.0)
    assert hit["obliquity_deg"] < 1.0
    ref = column_impact(law, hit["impact_velocity_m_s"], hit["height_m"], obliquity_deg=hit["obliquity_deg"],
                        mass_kg=0.236, size_m=(0.15, 0.06, 0.06), wall_thickness_m=0.005, friction_coefficient=0.0,
                        added_mass_coefficient=0.0)  # dry: no water carried
    assert hit["peak_force_N"] == pytest.approx(ref.peak_force_N, rel=1e-6)
    assert hit["impulse_Ns"] == pytest.approx(ref.impulse_Ns, rel=1e-6)
    assert hit["duration_s"] == pytest.approx(ref.duration_s, rel=1e-6)
    assert hit["peak_base_shear_N"] == pytest.approx(abs(ref.base_shear.peak_N), rel=1e-6)
    assert hit["rebound_speed_m_s"] / hit["impact_velocity_m_s"] == pytest.approx(law.wall_restitution, rel=0.10)
    assert hit["restitution"] == pytest.approx(law.wall_restitution, rel=0.10)


def test_two_boxes_colliding_conserve_momentum():
    """0.236 kg at +1 m/s meets 0.4 kg at -0.5 m/s on a frictionless bed: m1 v1 + m2 v2 conserved
    within 1 %; one body-body event; elastic law: separation / approach speed 1 within 5 %, and
    its pulse the half-sine of the two springs in series on the two-body mass within 3 %."""
    a = debris("a", centre_m=(0.0, 0.0, 0.03), velocity_m_s=(1.0, 0.0, 0.0), friction=0.0,
               size_m=(0.15, 0.06, 0.06), mass_kg=0.236, contact=ELASTIC_KEYS)
    b = debris("b", centre_m=(0.3, 0.0, 0.03), velocity_m_s=(-0.5, 0.0, 0.0), friction=0.0,
               size_m=(0.15, 0.06, 0.06), mass_kg=0.4, contact=ELASTIC_KEYS)
    run = run_transport([a, b], FLUME, 0.3, settings=TransportSettings(output_interval_s=0.005))
    ta, tb = run.track("a"), run.track("b")
    before = 0.236 * ta["u_m_s"].iloc[0] + 0.4 * tb["u_m_s"].iloc[0]
    after = 0.236 * ta["u_m_s"].iloc[-1] + 0.4 * tb["u_m_s"].iloc[-1]
    assert after == pytest.approx(before, rel=0.01)
    assert ta["u_m_s"].iloc[-1] < 0.0 < tb["u_m_s"].iloc[-1]
    assert len(run.body_contacts) == 1
    event = run.body_contacts.iloc[0]
    assert (event["body"], event["other"]) == ("a", "b")
    assert event["approach_velocity_m_s"] == pytest.approx(1.5, rel=0.02)
    assert event["restitution"] == pytest.approx(1.0, rel=0.05)
    # the pulse: the undamped container springs in series (k / 2) on the two-body mass, head on
    k, m = ELASTIC.stiffness_N_m / 2.0, 0.236 * 0.4 / (0.236 + 0.4)
    assert event["peak_force_N"] == pytest.approx(1.5 * math.sqrt(k * m), rel=0.03)
    assert event["duration_s"] == pytest.approx(math.pi * math.sqrt(m / k), rel=0.03)
    assert event["impulse_Ns"] == pytest.approx(2.0 * m * 1.5, rel=0.03)


def test_a_box_launched_at_a_side_wall_gets_the_half_sine_of_its_law():
    """The container broadside into the side wall at 1.5 m/s (frictionless), its spring undamped:
    one wall impact with its pulse, the half-sine on the whole mass: peak v sqrt(k m), duration
    pi sqrt(m / k), impulse 2 m v, each within 3 %."""
    body = debris("box", centre_m=(0.5, 0.3, 0.03), velocity_m_s=(0.0, 1.5, 0.0), friction=0.0,
                  contact=ELASTIC_KEYS, **CONTAINER_BOX)
    run = run_transport([body], FLUME, 0.3)
    walls = run.impacts[run.impacts["kind"] == "wall"]
    assert len(walls) == 1
    hit = walls.iloc[0]
    k, m = ELASTIC.stiffness_N_m, 0.236
    assert hit["impact_velocity_m_s"] == pytest.approx(1.5, rel=0.02)
    assert hit["peak_force_N"] == pytest.approx(1.5 * math.sqrt(k * m), rel=0.03)
    assert hit["duration_s"] == pytest.approx(math.pi * math.sqrt(m / k), rel=0.03)
    assert hit["impulse_Ns"] == pytest.approx(2.0 * m * 1.5, rel=0.03)
    assert math.isnan(hit["peak_base_shear_N"])


def test_a_run_longer_than_the_record_is_refused():
    body = debris("plate", centre_m=(0.0, 0.0, 0.1), **PLATE)
    with pytest.raises(FlowCoverageError, match=r"flow\.t"):
        run_transport([body], FLUME, 12.0, _still())


def _afloat(name, x, y=0.0, u=0.0, v=0.0):
    """The flat test box afloat at its draft in 0.1 m of still water, moving at (u, v)."""
    return debris(name, centre_m=(x, y, 0.1 - 0.01 + 0.01), velocity_m_s=(u, v, 0.0), friction=0.0,
                  **PLATE)


@pytest.mark.parametrize("kind", ["column", "wall", "body"])
def test_a_strike_takes_from_body_and_water_the_momentum_the_other_side_receives(kind):
    """Afloat (its water carried with it as added mass), drag off so nothing but the strike
    changes the motion along the normal: across a column, an end-wall and a body-body strike,
    the impulse the other side receives (the pulse's integral) equals the change of the
    normal momentum of the body and its added mass, (m + m_a,n) dv_n, within 2 %; for two
    bodies, each one's change, with opposite signs."""
    settings = TransportSettings(hydro=HydroCoefficients(drag_coefficient=0.0), output_interval_s=0.002)
    column = None
    if kind == "column":
        bodies = [_afloat("box", 0.4, u=1.2)]
        column = PlacedColumn(1.0, 0.0)
    elif kind == "wall":
        bodies = [_afloat("box", 2.6, u=1.2)]
    else:
        bodies = [_afloat("a", 0.0, u=1.2), _afloat("b", 0.5, u=-0.3)]
    run = run_transport(bodies, FLUME, 0.6, _still(), column=column, settings=settings)
    if kind == "body":
        assert len(run.body_contacts) == 1
        event = run.body_contacts.iloc[0]
        ta, tb = run.track("a"), run.track("b")
        t = event["time_s"]
        before = [tr[tr["time_s"] <= t].iloc[-1]["u_m_s"] for tr in (ta, tb)]
        after = [tr[tr["time_s"] > t + 0.01].iloc[0]["u_m_s"] for tr in (ta, tb)]
        # afloat, each plate carries its own surge added mass (analytical.added_mass)
        m_t = 0.4 + box_added_mass((0.2, 0.2, 0.02), 0.4, RHO).masses_kg[0]
        assert m_t * (before[0] - after[0]) == pytest.approx(event["impulse_Ns"], rel=0.02)
        assert m_t * (after[1] - before[1]) == pytest.approx(event["impulse_Ns"], rel=0.02)
        return
    hits = run.impacts[run.impacts["kind"] == kind]
    hit = hits.iloc[0]
    # afloat: the plate's own added mass along the normal (x for the column and the end wall)
    assert hit["added_mass_along_normal_kg"] == pytest.approx(box_added_mass((0.2, 0.2, 0.02), 0.4, RHO).masses_kg[0],
                                                             rel=0.03)
    m_t = 0.4 + hit["added_mass_along_normal_kg"]
    n = np.array([hit["normal_x"], hit["normal_y"], hit["normal_z"]])
    v_in = -hit["normal_velocity_in_m_s"]
    v_out = np.array([hit["rebound_u_m_s"], hit["rebound_v_m_s"], hit["rebound_w_m_s"]]) @ n
    assert m_t * (v_out - v_in) == pytest.approx(hit["impulse_Ns"], rel=0.02)
    assert hit["effective_mass_kg"] == pytest.approx(m_t, rel=0.02)


@pytest.mark.parametrize("open_end", [True, False], ids=["open", "closed"])
def test_a_body_reaching_an_open_end_leaves_the_run_and_a_closed_end_is_a_wall(open_end):
    """Dry and frictionless at 1.5 m/s towards the downstream end 1.4 m away: open, the body
    leaves when its nose passes it (after (1.4 - 0.075) / 1.5 = 0.883 s, to one forcing interval),
    at 1.5 m/s, its track ends there and nothing strikes; closed, it strikes the end wall."""
    body = debris("box", centre_m=(1.5, 0.0, 0.03), velocity_m_s=(1.5, 0.0, 0.0), friction=0.0,
                  **CONTAINER_BOX)
    flume = FlumeBounds((-1.0, 2.9), (-0.5, 0.5), open_ends=(False, open_end))
    run = run_transport([body], flume, 1.5)
    if not open_end:
        assert list(run.impacts["other"]) == ["wall_x1"]
        assert run.departures.empty
        return
    assert run.impacts.empty
    (gone,) = run.departures.to_dict("records")
    assert (gone["body"], gone["end"]) == ("box", "downstream")
    assert gone["time_s"] == pytest.approx((1.4 - 0.075) / 1.5, abs=2e-3)
    assert gone["speed_m_s"] == pytest.approx(1.5, rel=1e-3)
    track = run.track("box")
    assert track["time_s"].max() <= gone["time_s"] and track["x_m"].max() < 2.9


def test_in_a_batch_each_realisation_keeps_its_own_departure():
    """Two realisations in one model, both heading for the open downstream end at different
    speeds: each leaves once, at its own time, under its own name."""
    from orchestrator.transport.batch import run_batch

    starts = [[debris("box", centre_m=(1.5, y, 0.03), velocity_m_s=(u, 0.0, 0.0), friction=0.0,
                      **CONTAINER_BOX)] for y, u in ((-0.2, 1.5), (0.2, 1.0))]
    flume = FlumeBounds((-1.0, 2.9), (-0.5, 0.5), open_ends=(False, True))
    first, second = run_batch(starts, flume, 1.6)
    for run, u in ((first, 1.5), (second, 1.0)):
        (gone,) = run.departures.to_dict("records")
        assert gone["body"] == "box" and gone["time_s"] == pytest.approx((1.4 - 0.075) / u, abs=2e-3)


@pytest.mark.parametrize("yaw_deg", [0.0, 25.0])
def test_a_container_afloat_in_still_water_stays_where_it_is(yaw_deg):
    """The study's container at rest at its draft in still water, its forcing complete (the
    carried water per axis, drag along the flow, the Munk moment): over 2 s it moves under 1 mm
    and turns under 1 degree, whatever its heading (nothing moves past it to turn it)."""
    draft = 0.236 / (RHO * 0.15 * 0.06)
    body = debris("box", centre_m=(0.5, 0.0, 0.1 - draft + 0.03), yaw_deg=yaw_deg, **CONTAINER_BOX)
    track = run_transport([body], FLUME, 2.0, _still()).track("box")
    moved = (track[["x_m", "y_m", "z_m"]] - track[["x_m", "y_m", "z_m"]].iloc[0]).abs().to_numpy().max()
    assert moved < 1e-3
    for angle, start in (("yaw_deg", yaw_deg), ("pitch_deg", 0.0), ("roll_deg", 0.0)):
        assert (track[angle] - start).abs().max() < 1.0, angle


def test_the_still_water_before_the_bore_is_skipped_and_changes_nothing():
    """Ritter's bore (0.3 m, dry bed: its tip runs at 2 sqrt(g h0) = 3.43 m/s) reaches the
    container's upstream sub-volumes (x = 1.94 m) at 0.566 s. With ``still_start_m_s`` the run
    begins at the last frame before the water there moves (within two frames of it) and carries
    the body as the whole run does, to 1e-6 m; a body started moving is not skipped."""
    flow = FlowField.ritter(0.3, np.linspace(-1.0, 3.0, 81), np.arange(0.0, 1.21, 0.02))
    body = debris("box", centre_m=(2.0, 0.0, 0.03), **CONTAINER_BOX)
    whole = run_transport([body], FLUME, 1.2, flow)
    skipped = run_transport([body], FLUME, 1.2, flow, settings=TransportSettings(still_start_m_s=0.005))
    arrival = 1.94 / (2.0 * math.sqrt(9.81 * 0.3))
    begin = skipped.track("box")["time_s"].iloc[0]
    assert arrival - 0.04 - 0.05 / 3.43 <= begin <= arrival
    assert skipped.steps < 0.6 * whole.steps
    a, b = whole.track("box"), skipped.track("box")
    late = a[a["time_s"] >= begin - 1e-9]  # the two clocks agree to rounding
    assert len(late) == len(b)
    np.testing.assert_allclose(b[["x_m", "y_m", "z_m"]].to_numpy(), late[["x_m", "y_m", "z_m"]].to_numpy(), atol=1e-6)
    assert a["x_m"].iloc[-1] - a["x_m"].iloc[0] > 0.3  # the bore carried it
    moving = debris("box", centre_m=(2.0, 0.0, 0.03), velocity_m_s=(0.1, 0.0, 0.0), **CONTAINER_BOX)
    run = run_transport([moving], FLUME, 0.2, flow, settings=TransportSettings(still_start_m_s=0.005))
    assert run.track("box")["time_s"].iloc[0] == 0.0


def test_a_strike_carried_by_the_bore_states_how_long_after_the_front_it_came():
    """A box on Ritter's dry bed, carried to a column by the bore behind the front: its strike comes
    after the front reached the column's face; time_since_front_s is the strike's time less the
    flow's front arrival at the face (1 cm upstream of it), on the run's clock."""
    flow = FlowField.ritter(0.3, np.linspace(-1.0, 3.0, 81), np.arange(0.0, 1.61, 0.02))
    body = debris("box", centre_m=(1.8, 0.0, 0.03), **CONTAINER_BOX)
    column = PlacedColumn(2.6, 0.0)
    run = run_transport([body], FLUME, 1.6, flow, column=column)
    strikes = run.impacts[run.impacts["kind"] == "column"]
    assert len(strikes) >= 1
    first = strikes.iloc[0]
    front = flow.front_arrival_s(2.6 - column.column.size_x_m / 2 - 0.01, 0.0)
    assert 0.0 < front < first["time_s"]
    assert first["time_since_front_s"] == pytest.approx(first["time_s"] - front, abs=1e-9)
    walls = run.impacts[run.impacts["kind"] != "column"]
    assert walls["time_since_front_s"].isna().all()
