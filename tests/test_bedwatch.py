"""The runner's watch over bodies on the bed: the depth read around a body, when it is freed, its
bed friction, and the dictionary edits that carry them (no solver run; tests/test_float_carry.py
and tests/test_bed_friction.py run the real thing)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import ROOT, run_cli
from orchestrator.case import bodystate
from orchestrator.case.folder import CaseFolder
from orchestrator.run import body_policy, waterdepth
from orchestrator.run.bedwatch import BedWatch, breakaway_ratio, footprint_mean_radius, underside_m
from orchestrator.case.bodystate import BodyState

SCENE = ROOT / "tests" / "data" / "scenes" / "float-carry.yaml"
SIZE = (0.15, 0.06, 0.06)
RING = (0.04, 0.10)  # the ring read around a body at 4 cm cells and columns


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    out = tmp_path_factory.mktemp("bedwatch") / "case"
    proc = run_cli("render", str(SCENE), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    return out


def _sample(depth_of) -> waterdepth.Sample:
    xs, ys = np.arange(0.02, 1.0, 0.04), np.arange(-0.18, 0.2, 0.04)
    xy = np.array([(x, y) for x in xs for y in ys])
    return waterdepth.Sample(0.3, xy, np.array([depth_of(x, y) for x, y in xy]))


def test_the_depth_around_a_body_is_the_water_all_round_it():
    centre, rot = (0.4, 0.0, 0.0375), np.eye(3)
    still = _sample(lambda x, y: 0.080)
    assert waterdepth.depth_around(still, RING, centre, rot, SIZE)[0] == pytest.approx(0.080)
    # a bore whose front stands at the body's middle: deep upstream, the wet bed downstream. A
    # median would call it deep; the water is not under all of the body yet
    front = _sample(lambda x, y: 0.080 if x < 0.4 else 0.016)
    depth, columns = waterdepth.depth_around(front, RING, centre, rot, SIZE)
    assert depth == pytest.approx(0.016) and columns > 10
    # the ring starts a background cell off the footprint: the body's own hole cells are not read
    inside = _sample(lambda x, y: 0.0 if waterdepth.footprint_distance(
        np.array([[x, y]]), centre, rot, SIZE)[0] < 0.04 else 0.05)
    assert waterdepth.depth_around(inside, RING, centre, rot, SIZE)[0] == pytest.approx(0.05)


def test_the_ring_is_kept_off_the_other_bodies_overset_holes():
    """Three containers 0.10 m apart in a line (the 3x1 layout): the middle one's ring reaches into
    its neighbours' hole cells, whose stale values (the 15 mm wet bed) set the 10 % quantile; left
    out, the ring reads the water round the body. With nothing left it reads the whole ring."""
    rot = np.eye(3)
    centres = [(0.15 + 0.25 * k, 0.0, 0.0375) for k in range(3)]

    def depth(x, y):
        near = [waterdepth.footprint_distance(np.array([[x, y]]), c, rot, SIZE)[0] for c in centres]
        return 0.015 if min(near) < 0.04 else 0.060  # stale holes next to every body, water elsewhere

    sample = _sample(depth)
    middle, others = centres[1], [(c, rot, SIZE) for c in (centres[0], centres[2])]
    alone = waterdepth.depth_around(sample, RING, middle, rot, SIZE)
    assert alone[0] == pytest.approx(0.015)  # the neighbours' holes read as the wet bed
    kept_off, columns = waterdepth.depth_around(sample, RING, middle, rot, SIZE, others)
    assert kept_off == pytest.approx(0.060) and 0 < columns < alone[1]
    # a body boxed in on every side by others: the whole ring, not nothing
    boxed = [((middle[0] + dx, middle[1] + dy, 0.0375), rot, (0.3, 0.3, 0.06)) for dx, dy in ((0.3, 0), (-0.3, 0))]
    boxed += [((middle[0], dy, 0.0375), rot, (0.6, 0.1, 0.06)) for dy in (0.12, -0.12)]
    assert waterdepth.depth_around(sample, RING, middle, rot, SIZE, boxed) == alone


def test_the_columns_ring_the_bodies_kept_on_the_bed_one_point_per_layer(case):
    plan = CaseFolder(case).require_plan()
    axis = waterdepth.z_axis(plan, CaseFolder(case).scene().mesh.cell_size_m)
    assert axis.z.max() > max(w.max_m[2] for w in plan.water)  # up to the reservoir's level
    assert axis.dz[:4] == pytest.approx([plan.bed_gap_m / 4] * 4)  # the gap's four layers
    # a still 25 mm wet bed read through its layers: exactly 25 mm
    wet = axis.z < 0.025
    assert float(axis.dz[wet].sum()) == pytest.approx(0.025)
    grid = waterdepth.install(case, axis)  # every body free: no columns, only the lift
    assert len(grid.xy) == 0 and "cloud" not in (case / "system" / "bodyDepth").read_text()
    centre = (0.3, 0.0, 0.0375)
    grid = waterdepth.install(case, axis, [(centre, np.eye(3), SIZE)])
    d = waterdepth.footprint_distance(grid.xy, centre, np.eye(3), SIZE)
    inner, outer = axis.ring_m
    travel = waterdepth.TRAVEL_CELLS * axis.cell_m
    assert d.min() >= inner - travel - 1e-9 and d.max() <= outer + travel + 1e-9
    assert 30 < len(grid.xy) < 200
    text = (case / "system" / "bodyDepth").read_text()
    assert "cloud" in text and "lift_debris1" in text
    control = (case / "system" / "controlDict").read_text()
    assert control.count('#include "bodyDepth"') == 1
    waterdepth.install(case, axis)  # once only
    assert (case / "system" / "controlDict").read_text().count('#include "bodyDepth"') == 1


def test_a_point_sampled_in_a_body_mesh_as_well_counts_once(case, tmp_path):
    # v1912's sets writes a point that lies in a body's overset mesh once per mesh: a still 25 mm
    # bed read through such a column must still be 25 mm, not twice that
    axis = waterdepth.z_axis(CaseFolder(case).require_plan(), CaseFolder(case).scene().mesh.cell_size_m)
    wet = axis.z < 0.025
    rows = [(x, 0.0, z, 1.0 if w else 0.0) for x in (0.1, 0.5) for z, w in zip(axis.z, wet)]
    rows += [(0.5, 0.0, z, 1.0 if w else 0.0) for z, w in zip(axis.z, wet)]  # x = 0.5: in a body mesh on the other rank too
    folder = tmp_path / "0.3"
    folder.mkdir()
    np.savetxt(folder / "depth_alpha.water.xy", np.array(rows), delimiter="\t")
    sample = waterdepth.read_sample(folder, axis, 0.3)
    assert sample.xy.tolist() == [[0.1, 0.0], [0.5, 0.0]]
    assert sample.depth_m == pytest.approx([0.025, 0.025])


def _state(z=0.0375, u=(0.0, 0.0, 0.0)) -> BodyState:
    return BodyState("debris1", 0.0, (0.4, 0.0, z), velocity_m_s=u)


def test_a_body_is_freed_when_the_water_all_round_exceeds_its_underside_draft_and_margin(case):
    watch = BedWatch.for_case(case, 0.005, lambda m: None)
    draft = 0.236 / (998.2 * 0.15 * 0.06)
    standing = _state()  # on the 7.5 mm gap
    assert underside_m(standing, SIZE) == pytest.approx(0.0075)
    assert watch.float_depth_m(standing) == pytest.approx(0.0075 + draft + 0.005)
    # a body that sank onto the bed is raised onto the gap when freed: it floats from there
    assert watch.float_depth_m(_state(z=0.03)) == pytest.approx(0.0075 + draft + 0.005)
    # put back on the bed at 40 mm of water: freed again only 5 mm deeper than that
    watch.rested_at_depth["debris1"] = 0.045
    assert watch.float_depth_m(standing) == pytest.approx(0.050)


def test_bed_friction_is_mu_times_weight_less_buoyancy(case):
    watch = BedWatch.for_case(case, 0.005, lambda m: None)
    g, weight = 9.81, 0.236 * 9.81
    assert watch.normal_force_N(_state(), 0.0) == pytest.approx(weight)
    # 15 mm of water, 7.5 mm of it above the gap's top: 0.66 N of buoyancy
    assert watch.normal_force_N(_state(), 0.015) == pytest.approx(weight - 998.2 * g * 0.15 * 0.06 * 0.0075)
    assert watch.normal_force_N(_state(), 0.2) == 0.0  # the water carries it


def test_the_runner_edits_the_bed_constraints_and_the_friction_damper(case):
    assert body_policy.bed_constraints(case) == {"debris1": "hold"}
    assert body_policy.set_bed_friction(case, {"debris1": 2.5}) == ["debris1"]
    assert body_policy.set_bed_friction(case, {"debris1": 2.5}) == []  # unchanged
    text = (case / "constant" / "dynamicMeshDict").read_text()
    # two zero-stiffness springs through the centre (v1912's linearDamper would act at the origin)
    assert "linearDamper" not in text and text.count("linearSpring") == 2
    restraints = bodystate.motion_entries(case, "restraints")["debris1"]
    centre0 = bodystate.read_mesh_poses(case)[0].centre_of_mass_m
    for name, anchor in body_policy.BED_FRICTION_AXES.items():
        spring = restraints[name]
        assert float(spring["damping"]) == 2.5 and float(spring["stiffness"]) == 0.0
        assert spring["refAttachmentPt"] == pytest.approx(centre0) and spring["anchor"] == pytest.approx(anchor)
    # the other bodies' entries and the rendered comments are kept as rendered
    assert "// held on the bed" in text and "keepUpright    { sixDoFRigidBodyMotionConstraint axis; axis (0 0 1); }" in text
    assert body_policy.set_bed_friction(case, {"debris1": 2.5}, {"debris1": 0.01}) == ["debris1"]
    assert body_policy.set_bed_friction(case, {"debris1": 2.5}, {"debris1": 0.01}) == []
    assert "sphericalAngularDamper" in (case / "constant" / "dynamicMeshDict").read_text()
    assert body_policy.release_holds(case, ["debris1"]) == ["debris1"]
    assert body_policy.bed_constraints(case) == {"debris1": ""}
    assert body_policy.rest_on_bed(case, ["debris1"]) == ["debris1"]
    assert body_policy.bed_constraints(case) == {"debris1": "rest"}
    assert body_policy.lift_rest_on_bed(case, ["debris1"]) == ["debris1"]
    assert body_policy.set_bed_friction(case, {"debris1": None}) == ["debris1"]
    text = (case / "constant" / "dynamicMeshDict").read_text()
    assert "linearSpring" not in text and "restOnBedPlane" not in text
    assert "sphericalAngularDamper" in text  # the yaw damper is set (or removed) on its own


def test_the_friction_lever_arm_is_the_footprints_mean_distance_from_its_centre():
    # a unit square: (sqrt(2) + ln(1 + sqrt(2))) / 6 = 0.3826 (the classic mean distance to the centre)
    assert footprint_mean_radius(1.0, 1.0) == pytest.approx((np.sqrt(2) + np.log(1 + np.sqrt(2))) / 6, rel=1e-12)
    # the study's container against a midpoint-rule integration of its 0.15 x 0.06 m footprint
    n = 1500
    x = (np.arange(n) + 0.5) / n * 0.15 - 0.075
    y = (np.arange(n) + 0.5) / n * 0.06 - 0.03
    numeric = float(np.hypot(*np.meshgrid(x, y)).mean())
    assert footprint_mean_radius(0.15, 0.06) == pytest.approx(numeric, rel=1e-5)
    assert footprint_mean_radius(0.15, 0.06) == pytest.approx(footprint_mean_radius(0.06, 0.15), rel=1e-12)


def test_static_friction_bears_a_load_inside_its_limit_ellipse():
    mu, normal, r = 0.3, 1.65, 0.042
    assert breakaway_ratio((0.3 * 1.65, 0.0), 0.0, mu, normal, r) == pytest.approx(1.0)  # F = mu N
    assert breakaway_ratio((0.0, 0.0), mu * normal * r, mu, normal, r) == pytest.approx(1.0)  # M = mu N r
    # half the force and half the moment together: inside (0.25 + 0.25)
    assert breakaway_ratio((0.0, 0.5 * mu * normal), -0.5 * mu * normal * r, mu, normal, r) == pytest.approx(0.5)
    # the spurious yaw moment of the overset solver around the 1-debris container (up to 8e-4 N m)
    # is far inside what friction bears on the 15 mm wet bed
    assert breakaway_ratio((0.02, 0.0), 8e-4, mu, normal, footprint_mean_radius(0.15, 0.06)) < 0.1
    assert breakaway_ratio((0.0, 0.0), 0.0, mu, 0.0, r) == float("inf")  # afloat: nothing to bear


def test_a_body_at_rest_on_the_bed_is_stuck_and_a_sliding_one_gets_a_yaw_damper(tmp_path):
    case = tmp_path / "case"
    proc = run_cli("render", str(ROOT / "tests" / "data" / "scenes" / "still-water-resting.yaml"), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    watch = BedWatch.for_case(case, 0.005, lambda m: None)
    [state] = bodystate.coefficient_states(case)
    assert body_policy.bed_constraints(case)["debris1"] == "hold"
    _, out = watch.at_restart("0", [state])
    assert body_policy.stuck_bodies(case) == {"debris1"} and watch.stuck == {"debris1"}
    assert out[0].velocity_m_s == (0.0, 0.0, 0.0)
    text = (case / "constant" / "dynamicMeshDict").read_text()
    assert "stickPoint" in text and "stickOrientation" in text and "sphericalAngularDamper" in text
    # the yaw damper is mu N r over the floor's yaw rate: the same time constant as the linear one
    radius = footprint_mean_radius(0.15, 0.06)
    assert watch.friction_radius_m("debris1") == pytest.approx(radius)
    assert watch.friction_spin["debris1"] == pytest.approx(0.05 / radius)
    # a body sliding at 0.2 m/s is not stuck; ending the stick leaves its hold
    assert body_policy.unstick_bodies(case, ["debris1"]) == ["debris1"]
    sliding = state.with_changes(velocity_m_s=(0.2, 0.0, 0.0))
    watch.at_restart("0.1", [sliding])
    assert body_policy.stuck_bodies(case) == set() and body_policy.bed_constraints(case)["debris1"] == "hold"
    assert watch.friction_speed["debris1"] == pytest.approx(0.2)
    assert watch.bed_friction["debris1"] > 0
    # freed from the bed, a stuck body loses its stick with its hold
    assert body_policy.stick_bodies(case, ["debris1"]) == ["debris1"]
    assert body_policy.release_holds(case, ["debris1"]) == ["debris1"]
    assert body_policy.stuck_bodies(case) == set()
