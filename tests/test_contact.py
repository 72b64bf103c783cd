"""Contact geometry, event detection and resolution (orchestrator.contact.geometry).

Distances, points and normals against hand values for face, edge and vertex configurations;
exactness against brute-force surface sampling and consistency with the scene's
separating-axis overlap test on random boxes; the scene's obstacles; time to contact;
resolve() leaving bodies outside and moving away.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from analytical.added_mass import box_added_mass
from analytical.impact_bodies import Body
import pytest
from scipy.spatial import cKDTree

from analytical.errors import InputError
from orchestrator.contact.boxes import box_box_proximity, box_plane_proximity
from orchestrator.contact.geometry import (
    BoxObstacle,
    Obstacles,
    PlaneObstacle,
    bed_clearance,
    box_state,
    clamp_to_bed,
    find_contacts,
    inverse_inertia,
    moved,
    plan_state,
    point_velocity,
    scene_obstacles,
    time_to_contact,
)
from orchestrator.contact.resolution import resolve
from orchestrator.plan.planner import plan_case
from orchestrator.scene.geometry import body_rotation, boxes_overlap
from orchestrator.scene.scenefile import load_scene

ROOT = Path(__file__).resolve().parent.parent
I3 = np.eye(3)
SIZE = (0.15, 0.06, 0.06)
MASS = 0.236


@pytest.fixture(scope="module")
def scene():
    """The study's 1-debris scene on the coupled (overset) path, whose runner these contacts serve."""
    return load_scene(ROOT / "cases" / "1debris.yaml", ["run.debris_coupling=two-way"])


@pytest.fixture(scope="module")
def obstacles(scene):
    return scene_obstacles(scene)


def state(
    name="b", centre=(0.0, 0.0, 0.03), yaw=0.0, pitch=0.0, roll=0.0, velocity=(0, 0, 0), omega=(0, 0, 0), size=SIZE, mass=MASS
):
    sx, sy, sz = size
    inertia = [mass * (sy**2 + sz**2) / 12, mass * (sx**2 + sz**2) / 12, mass * (sx**2 + sy**2) / 12]
    return box_state(name, centre, body_rotation(yaw, pitch, roll), velocity, omega, size, mass, inertia)


def face_x(scene) -> float:
    return scene.column.x_m - scene.column.size_x_m / 2


def prox_to_column(s, scene):
    col = scene.column
    return box_box_proximity(
        s.centre_of_mass_m, s.rotation, s.size_m,
        (col.x_m, col.y_m, col.height_m / 2), I3, (col.size_x_m, col.size_y_m, col.height_m),
    )


def random_rotation(rng) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    return q


# ----------------------------------------------------------------------------- hand values
def test_face_face_distance_point_normal():
    p = box_box_proximity((0, 0, 0), I3, (1, 1, 1), (1.5, 0.3, 0), I3, (1, 1, 1))
    assert p.distance_m == pytest.approx(0.5)
    np.testing.assert_allclose(p.normal, [-1, 0, 0], atol=1e-12)
    # the facing patch is y in [-0.2, 0.5], z in [-0.5, 0.5], halfway across the gap
    np.testing.assert_allclose(p.point, [0.75, 0.15, 0.0], atol=1e-12)


def test_edge_face_distance_point_normal():
    # a 1 m cube yawed 45 degrees presents a vertical edge at x = sqrt(1/2)
    p = box_box_proximity((0, 0, 0), body_rotation(45, 0, 0), (1, 1, 1), (2.0, 0, 0), I3, (1, 1, 1))
    assert p.distance_m == pytest.approx(1.5 - math.sqrt(0.5), rel=1e-12)
    np.testing.assert_allclose(p.normal, [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p.point, [(math.sqrt(0.5) + 1.5) / 2, 0, 0], atol=1e-12)


def test_vertex_face_distance_point_normal():
    # rotate the cube so its (+1, +1, +1) corner points along +x: it sits at x = sqrt(3)/2
    rot = body_rotation(0, math.degrees(math.atan(1 / math.sqrt(2))), 0) @ body_rotation(-45, 0, 0)
    np.testing.assert_allclose(rot @ np.ones(3) / math.sqrt(3), [1, 0, 0], atol=1e-12)
    p = box_box_proximity((0, 0, 0), rot, (1, 1, 1), (2.0, 0.1, -0.2), I3, (1, 1, 1))
    assert p.distance_m == pytest.approx(1.5 - math.sqrt(3) / 2, rel=1e-12)
    np.testing.assert_allclose(p.normal, [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p.point, [(math.sqrt(3) / 2 + 1.5) / 2, 0, 0], atol=1e-12)


def test_edge_edge_distance_point_normal():
    # a vertical edge (cube yawed 45) facing a horizontal edge along y (cube pitched 45)
    p = box_box_proximity((0, 0, 0), body_rotation(45, 0, 0), (1, 1, 1), (2, 0, 0), body_rotation(0, 45, 0), (1, 1, 1))
    assert p.distance_m == pytest.approx(2 - 2 * math.sqrt(0.5), rel=1e-12)
    np.testing.assert_allclose(p.normal, [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(p.point, [1.0, 0, 0], atol=1e-12)
    # skew edges off-axis: the normal is along their common perpendicular
    p = box_box_proximity((0, 0, 0), body_rotation(45, 0, 0), (1, 1, 1), (2, 0, 0.3), body_rotation(0, 45, 0), (1, 1, 1))
    assert p.distance_m == pytest.approx(2 - 2 * math.sqrt(0.5), rel=1e-12)
    np.testing.assert_allclose(p.point, [1.0, 0, 0.3], atol=1e-12)


def test_plane_face_edge_vertex():
    # face: lowest face at z = 0.5 - 0.5
    p = box_plane_proximity((0, 0, 1.0), I3, (1, 1, 1), (0, 0, 0), (0, 0, 1))
    assert p.distance_m == pytest.approx(0.5)
    np.testing.assert_allclose(p.point, [0, 0, 0.25], atol=1e-12)
    # edge: rolled 45 degrees, a horizontal edge at z = 1 - sqrt(1/2)
    p = box_plane_proximity((0, 0, 1.0), body_rotation(0, 0, 45), (1, 1, 1), (0, 0, 0), (0, 0, 1))
    assert p.distance_m == pytest.approx(1 - math.sqrt(0.5), rel=1e-12)
    np.testing.assert_allclose(p.point[:2], [0, 0], atol=1e-12)
    # vertex below the plane: penetration
    rot = body_rotation(0, math.degrees(math.atan(1 / math.sqrt(2))), 0) @ body_rotation(-45, 0, 0)
    p = box_plane_proximity((0.0, 0, 0.5), rot, (1, 1, 1), (0.6, 0, 0), (-1, 0, 0))
    assert p.distance_m == pytest.approx(0.6 - math.sqrt(3) / 2, rel=1e-12)
    assert p.distance_m < 0


def test_overlap_depth_normal_and_point():
    p = box_box_proximity((0, 0, 0), I3, (1, 1, 1), (0.9, 0.2, 0), I3, (1, 1, 1))
    assert p.distance_m == pytest.approx(-0.1)
    np.testing.assert_allclose(p.normal, [-1, 0, 0], atol=1e-12)
    # the overlap is x in [0.4, 0.5], y in [-0.3, 0.5], z in [-0.5, 0.5]
    np.testing.assert_allclose(p.point, [0.45, 0.1, 0.0], atol=1e-12)
    touching = box_box_proximity((0, 0, 0), I3, (1, 1, 1), (1.0, 0.2, 0), I3, (1, 1, 1))
    assert touching.distance_m == 0.0
    np.testing.assert_allclose(touching.point, [0.5, 0.1, 0.0], atol=1e-12)


# ----------------------------------------------------------------------------- exactness
def _surface_points(centre, rot, size, n=25):
    half = np.asarray(size) / 2
    g = np.linspace(-1, 1, n)
    u, v = np.meshgrid(g, g)
    u, v = u.ravel(), v.ravel()
    pts = []
    for k in range(3):
        a, b = (k + 1) % 3, (k + 2) % 3
        for s in (-1, 1):
            local = np.zeros((u.size, 3))
            local[:, k] = s
            local[:, a] = u
            local[:, b] = v
            pts.append(local * half)
    return np.asarray(centre) + np.vstack(pts) @ rot.T


def test_distance_is_exact_against_brute_force_sampling():
    rng = np.random.default_rng(3)
    checked = 0
    while checked < 25:
        ra, rb = random_rotation(rng), random_rotation(rng)
        sa, sb = rng.uniform(0.05, 0.3, 3), rng.uniform(0.05, 0.3, 3)
        cb = rng.normal(size=3) * 0.25
        p = box_box_proximity((0, 0, 0), ra, sa, cb, rb, sb)
        if p.distance_m <= 0.0:
            continue
        checked += 1
        pa, pb = _surface_points((0, 0, 0), ra, sa), _surface_points(cb, rb, sb)
        sampled, _ = cKDTree(pb).query(pa)
        est = float(sampled.min())
        spacing = max(np.max(sa), np.max(sb)) / 24
        assert p.distance_m <= est + 1e-12  # exact is a lower bound of any sample
        assert est - p.distance_m <= 1.5 * spacing  # and the samples approach it
        # the contact point is halfway between the surfaces, the normal separates them
        half_gap = p.distance_m / 2
        # (the normal points from b into a: a's surface is at +half_gap, b's at -half_gap)
        on_a, on_b = p.point + half_gap * p.normal, p.point - half_gap * p.normal
        assert box_box_proximity(on_a, I3, (1e-9,) * 3, (0, 0, 0), ra, sa).distance_m == pytest.approx(0.0, abs=1e-8)
        assert box_box_proximity(on_b, I3, (1e-9,) * 3, cb, rb, sb).distance_m == pytest.approx(0.0, abs=1e-8)


def test_overlap_verdict_agrees_with_the_scene_test_and_is_symmetric():
    rng = np.random.default_rng(11)
    for _ in range(200):
        ra, rb = random_rotation(rng), random_rotation(rng)
        sa, sb = rng.uniform(0.05, 0.3, 3), rng.uniform(0.05, 0.3, 3)
        ca, cb = rng.normal(size=3) * 0.1, rng.normal(size=3) * 0.1
        ab = box_box_proximity(ca, ra, sa, cb, rb, sb)
        ba = box_box_proximity(cb, rb, sb, ca, ra, sa)
        assert (ab.distance_m < 0) == boxes_overlap(ca, ra, sa, cb, rb, sb)
        assert ba.distance_m == pytest.approx(ab.distance_m, abs=1e-12)
        np.testing.assert_allclose(ba.normal, -ab.normal, atol=1e-9)
        np.testing.assert_allclose(ba.point, ab.point, atol=1e-9)


def test_no_false_contacts_at_zero_gap():
    rng = np.random.default_rng(5)
    states = []
    while len(states) < 6:
        s = state(f"b{len(states)}", centre=(rng.uniform(0, 1), rng.uniform(-0.5, 0.5), 0.1), yaw=rng.uniform(0, 180))
        if not any(
            boxes_overlap(s.centre_of_mass_m, s.rotation, s.size_m, o.centre_of_mass_m, o.rotation, o.size_m)
            for o in states
        ):
            states.append(s)
    assert find_contacts(states, [], 0.0) == []
    # and pairs really within 5 mm are all found, each once
    found = find_contacts(states, [], 0.005)
    pairs = [(c.body, c.other) for c in found]
    assert len(pairs) == len(set(pairs))
    for c in found:
        assert c.kind == "body" and 0.0 < c.distance_m < 0.005


def test_obb_pair_contact_is_symmetric():
    a = state("a", centre=(0, 0, 0.03), yaw=20)
    b = state("b", centre=(0.16, 0.05, 0.03), yaw=-35)
    (ab,) = find_contacts([a, b], [], 0.05)
    (ba,) = find_contacts([b, a], [], 0.05)
    assert (ab.body, ab.other, ba.body, ba.other) == ("a", "b", "b", "a")
    assert ab.distance_m == pytest.approx(ba.distance_m, abs=1e-12)
    np.testing.assert_allclose(ab.normal, -ba.normal, atol=1e-12)
    np.testing.assert_allclose(ab.point, ba.point, atol=1e-12)
    assert ab.normal @ np.subtract(a.centre_of_mass_m, b.centre_of_mass_m) > 0  # from the other into the body


# ----------------------------------------------------------------------------- the scene
def test_scene_obstacles(scene):
    obs = scene_obstacles(scene)
    assert obs.column == BoxObstacle("column", "column", (5.0, 0.0, 0.4), (0.2, 0.2, 0.8))
    names = {w.name: w for w in obs.walls}
    assert set(names) == {"side_wall_right", "side_wall_left", "upstream_wall"}  # the end is open
    assert names["side_wall_right"].point_m[1] == -0.75 and names["side_wall_right"].normal == (0.0, 1.0, 0.0)
    assert names["upstream_wall"].point_m[0] == -21.55
    assert obs.bed.kind == "bed" and obs.bed not in obs.targets
    closed = load_scene(ROOT / "cases" / "1debris.yaml", ["flume.downstream_end=closed"])
    walls = {w.name: w for w in scene_obstacles(closed).walls}
    assert walls["downstream_wall"].point_m[0] == pytest.approx(30.0 - 21.55)
    assert walls["downstream_wall"].normal == (-1.0, 0.0, 0.0)
    # with the plan, the modelled domain's walls (reservoir cut short, outlet downstream)
    plan = plan_case(scene)
    walls = {w.name: w for w in scene_obstacles(scene, plan).walls}
    assert walls["upstream_wall"].point_m[0] == pytest.approx(plan.domain_m[0][0])
    assert "downstream_wall" not in walls


def test_head_on_approach_to_the_column(scene, obstacles):
    fx = face_x(scene)
    s = state("debris1", centre=(fx - 0.075 - 0.005, 0.0, 0.03), velocity=(1.5, 0, 0))
    assert find_contacts([s], obstacles, 0.0) == []
    (c,) = find_contacts([s], obstacles, 0.01)
    assert (c.body, c.other, c.kind) == ("debris1", "column", "column")
    assert c.distance_m == pytest.approx(0.005, rel=1e-9)
    np.testing.assert_allclose(c.normal, [-1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(c.point, [fx - 0.0025, 0.0, 0.03], atol=1e-12)
    assert time_to_contact(s, obstacles.column, 1.0) == pytest.approx(0.005 / 1.5, rel=1e-9)
    assert time_to_contact(s, obstacles.column, 1.0, gap_m=0.002) == pytest.approx(0.003 / 1.5, rel=1e-9)
    assert time_to_contact(s, obstacles.column, 0.001) == math.inf
    assert time_to_contact(moved(s, velocity_m_s=(-1.0, 0, 0)), obstacles.column, 10.0) == math.inf
    assert time_to_contact(s, obstacles.column, 1.0, gap_m=0.01) == 0.0


def test_yawed_body_hits_off_centre(scene, obstacles):
    fx = face_x(scene)
    yaw = 30.0
    c, s_ = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    reach = 0.075 * c + 0.03 * s_  # the leading vertical edge, (L/2, -W/2) in body axes
    body = state("d", centre=(fx - reach - 0.004, 0.0, 0.03), yaw=yaw)
    (con,) = find_contacts([body], obstacles, 0.01)
    assert con.distance_m == pytest.approx(0.004, rel=1e-9)
    np.testing.assert_allclose(con.normal, [-1, 0, 0], atol=1e-12)
    edge_y = 0.075 * s_ - 0.03 * c
    np.testing.assert_allclose(con.point, [fx - 0.002, edge_y, 0.03], atol=1e-12)
    # near the column's vertical corner edge the normal itself is oblique
    col = scene.column
    corner = np.array([fx, col.y_m + col.size_y_m / 2])
    body = state("d", centre=(fx - 0.075 - 0.01, corner[1] + 0.03 + 0.02, 0.03))
    (con,) = find_contacts([body], obstacles, 0.05)
    assert con.distance_m == pytest.approx(math.hypot(0.01, 0.02), rel=1e-9)
    np.testing.assert_allclose(con.normal, np.array([-0.01, 0.02, 0]) / math.hypot(0.01, 0.02), atol=1e-12)
    np.testing.assert_allclose(con.point, [fx - 0.005, corner[1] + 0.01, 0.03], atol=1e-12)


def test_walls_and_bed(scene, obstacles):
    s = state("d", centre=(3.2, -0.75 + 0.03 + 0.004, 0.03), velocity=(0, -0.5, 0))
    (c,) = find_contacts([s], obstacles, 0.01)
    assert (c.other, c.kind) == ("side_wall_right", "wall")
    assert c.distance_m == pytest.approx(0.004, rel=1e-9)
    np.testing.assert_allclose(c.normal, [0, 1, 0])
    assert time_to_contact(s, next(w for w in obstacles.walls if w.name == "side_wall_right"), 1.0) == pytest.approx(0.008)
    # resting on the bed is not a contact; sinking into it is corrected separately
    on_bed = state("d", centre=(3.2, 0.0, 0.03))
    assert find_contacts([on_bed], obstacles, 0.01) == []
    assert bed_clearance(on_bed, obstacles) == pytest.approx(0.0, abs=1e-15)
    sunk = state("d", centre=(3.2, 0.0, 0.02), yaw=10, velocity=(1.0, 0.0, -0.2))
    assert bed_clearance(sunk, obstacles.bed) == pytest.approx(-0.01)
    lifted = clamp_to_bed(sunk, obstacles)
    assert bed_clearance(lifted, obstacles) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(lifted.velocity_m_s, [1.0, 0.0, 0.0])
    assert clamp_to_bed(on_bed, obstacles) is on_bed


def test_time_to_contact_between_bodies_and_with_spin(scene, obstacles):
    a = state("a", centre=(0, 0, 0.03), velocity=(1.0, 0, 0))
    b = state("b", centre=(0.25, 0, 0.03), velocity=(-1.0, 0, 0))
    assert time_to_contact(a, b, 1.0) == pytest.approx(0.1 / 2.0, rel=1e-9)
    assert time_to_contact(a, b, 1.0, gap_m=0.02) == pytest.approx(0.08 / 2.0, rel=1e-9)
    # a body at rest but spinning about z next to the column: watched earlier than never
    fx = face_x(scene)
    spinning = state("s", centre=(fx - 0.075 - 0.01, 0, 0.03), omega=(0, 0, 20.0))
    t = time_to_contact(spinning, obstacles.column, 1.0)
    assert 0.0 < t < 0.01 / (20.0 * 0.03)  # no later than its corner's own speed would take


def test_body_state_checks_and_plan():
    with pytest.raises(InputError) as err:
        box_state("b", (0, 0, 0), np.diag([1, 1, -1]), (0, 0, 0), (0, 0, 0), SIZE, MASS, (1, 1, 1))
    assert err.value.field == "b.orientation"
    with pytest.raises(InputError):
        state(mass=0.0)
    plan = plan_case(load_scene(ROOT / "cases" / "1debris.yaml", ["run.debris_coupling=two-way"]))
    s = plan_state(plan.bodies[0], velocity_m_s=(1.5, 0, 0))
    assert s.name == "debris1" and s.mass_kg == pytest.approx(0.236)
    np.testing.assert_allclose(s.inertia_kg_m2, plan.bodies[0].moment_of_inertia_kg_m2)
    np.testing.assert_allclose(inverse_inertia(s), np.diag(1 / np.asarray(plan.bodies[0].moment_of_inertia_kg_m2)))
    with pytest.raises(InputError):
        find_contacts([s, s], [], 0.01)  # names must be unique


# ----------------------------------------------------------------------------- resolve
def _relative_normal_velocity(contact, new_states, states):
    by = {s.name: s for s in new_states}
    body = by[contact.body]
    u = point_velocity(body, contact.point)
    if contact.kind == "body":
        u = u - point_velocity(by[contact.other], contact.point)
    return float(np.asarray(contact.normal) @ u)


@pytest.mark.parametrize("yaw, distance", [(0.0, 0.003), (25.0, 0.002), (0.0, -0.002), (25.0, -0.001)])
def test_resolve_column_rebounds_outside(scene, obstacles, yaw, distance):
    fx = face_x(scene)
    c, s_ = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    reach = 0.075 * c + 0.03 * s_
    body = state("debris1", centre=(fx - reach - distance, 0.02, 0.03), yaw=yaw, velocity=(1.6, 0.1, 0))
    (contact,) = find_contacts([body], obstacles, 0.01)
    assert contact.distance_m == pytest.approx(distance, abs=1e-12)
    result, new = resolve(contact, [body], scene)
    assert result is not None and result.target == "column"
    assert result.contact_height_m == pytest.approx(0.03)
    (after,) = new
    assert _relative_normal_velocity(contact, new, [body]) > 0  # moving away
    assert prox_to_column(after, scene).distance_m >= -1e-12  # never inside
    assert after.velocity_m_s[0] < 0
    if yaw:
        assert abs(after.angular_velocity_rad_s[2]) > 0  # an off-centre blow spins it
    np.testing.assert_allclose(after.size_m, body.size_m)


def test_resolve_wall_and_receding(scene, obstacles):
    s = state("d", centre=(3.2, -0.75 + 0.03 - 0.001, 0.03), yaw=5, velocity=(1.0, -0.4, 0))
    (contact,) = find_contacts([s], obstacles, 0.01)
    result, (after,) = resolve(contact, [s], scene)
    assert result.target == "wall"
    assert _relative_normal_velocity(contact, [after], [s]) > 0
    wall = box_plane_proximity(after.centre_of_mass_m, after.rotation, after.size_m, (0, -0.75, 0), (0, 1, 0))
    assert wall.distance_m >= -1e-12
    receding = moved(s, velocity_m_s=(1.0, 0.4, 0))
    result, (after,) = resolve(contact, [receding], scene)
    assert result is None
    np.testing.assert_allclose(after.velocity_m_s, receding.velocity_m_s)
    assert contact.distance_m < 0  # it was pushed out by the penetration, along the normal
    assert after.centre_of_mass_m[1] == pytest.approx(receding.centre_of_mass_m[1] - contact.distance_m, abs=1e-15)


def test_resolve_two_bodies(scene):
    a = state("a", centre=(2.0, 0.0, 0.03), yaw=10, velocity=(1.5, 0.1, 0))
    b = state("b", centre=(2.153, 0.01, 0.03), yaw=-5, velocity=(0.2, 0, 0), mass=0.3)
    (contact,) = find_contacts([a, b], [], 0.01)
    result, new = resolve(contact, [a, b], scene)
    assert result.target == "body"
    na, nb = new
    assert (na.name, nb.name) == ("a", "b")
    assert _relative_normal_velocity(contact, new, [a, b]) > 0
    # afloat, each carries its own added mass (anisotropic, turned with the body): the momentum
    # of bodies and water is conserved
    def momentum(s):
        own = box_added_mass(tuple(s.size_m), s.mass_kg, scene.fluids.water_density_kg_m3)
        return Body.box(s.mass_kg, s.inertia_kg_m2, s.rotation, s.centre_of_mass_m, s.velocity_m_s,
                        added_mass_kg=own.masses_kg).momentum()

    np.testing.assert_allclose(momentum(na) + momentum(nb), momentum(a) + momentum(b), atol=1e-12)
    # without water, the bodies' own
    _, (da, db) = resolve(contact, [a, b], scene, added_mass_coefficient=0.0)
    def own(s):
        return s.mass_kg * np.asarray(s.velocity_m_s)

    np.testing.assert_allclose(own(da) + own(db), own(a) + own(b), atol=1e-12)
    apart = box_box_proximity(
        na.centre_of_mass_m, na.rotation, na.size_m, nb.centre_of_mass_m, nb.rotation, nb.size_m
    )
    assert apart.distance_m >= -1e-12


def test_resolve_rejects_unknown_bodies(scene, obstacles):
    s = state("d", centre=(3.2, -0.75 + 0.03 + 0.004, 0.03), velocity=(0, -0.5, 0))
    (contact,) = find_contacts([s], obstacles, 0.01)
    with pytest.raises(InputError) as err:
        resolve(contact, [s.with_changes(name="other")], scene)
    assert err.value.field == "contact.body"


def test_obstacles_container(obstacles):
    assert isinstance(obstacles, Obstacles)
    assert obstacles.targets[0] is obstacles.column
    assert all(isinstance(w, PlaneObstacle) for w in obstacles.targets[1:])


def test_a_hair_of_tilt_keeps_a_bed_contact_centred():
    # a body rolled by ~1.7e-6 rad meets the bed with its whole face, not with one edge:
    # no spurious moment when it is put back onto the bed
    rolled = body_rotation(0, 0, 1e-4)  # degrees
    w = box_plane_proximity((0, 0, 0.1), rolled, (0.15, 0.06, 0.06), (0, 0, 0), (0, 0, 1))
    assert abs(w.point[1]) < 1e-4


def test_resolve_uses_each_bodys_contact_law_from_the_scene():
    """The same column strike with the scene's default (container) law and with asce7_kd: the
    rigid law gives a pulse about five times stronger and shorter; body pairs put the two
    bodies' springs in series."""
    from analytical.contact_law import ASCE7_KD, CONTAINER
    from orchestrator.contact.resolution import pair_contact_law

    base = load_scene(ROOT / "cases" / "1debris.yaml")
    rigid = load_scene(ROOT / "cases" / "1debris.yaml", ["debris.0.contact.law=asce7_kd"])
    name = base.debris[0].name
    body = state(name, centre=(face_x(base) - 0.075 - 0.002, 0.0, 0.2), velocity=(1.5, 0.0, 0.0))
    figures = {}
    for label, scene in (("container", base), ("kd", rigid)):
        (contact,) = find_contacts([body], scene_obstacles(scene), 0.005)
        result, _ = resolve(contact, [body], scene)
        figures[label] = (result.peak_force_N, result.duration_s, result.stiffness_N_m)
    assert figures["container"][2] == pytest.approx(CONTAINER.stiffness_N_m)
    assert figures["kd"][2] == pytest.approx(ASCE7_KD.stiffness_N_m)
    assert figures["kd"][0] > 4 * figures["container"][0]
    assert figures["kd"][1] < figures["container"][1] / 4
    assert pair_contact_law(CONTAINER, CONTAINER).stiffness_N_m == pytest.approx(CONTAINER.stiffness_N_m / 2)
