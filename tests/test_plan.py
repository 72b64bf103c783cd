"""The planner: what each scene needs, and that every choice is explained.

Closed-form checks (inertia, the reservoir's reflection time, the wall-time formula),
structural checks on the grids the templates will write, and hypothesis properties:
the reservoir grows with the end time and is capped, the cell count falls as cells
grow, the fine region always holds the column and the debris, every decision has a
reason.
"""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from analytical.errors import InputError
from orchestrator.plan.bodies import hold_until_s as _hold_until_s
from orchestrator.plan.facts import scene_facts
from orchestrator.plan.planner import (
    REASON_KEYS,
    SAFETY,
    STEP_FACTOR,
    US_PER_CELL_STEP,
    body_inertia,
    estimate_wall_time_s,
    estimated_steps,
    plan_case,
)
from orchestrator.scene.geometry import body_rotation
from orchestrator.scene.overrides import apply_overrides
from orchestrator.scene.resolve import scene_from_dict
from orchestrator.scene.scenefile import load_scene

from tests.conftest import CASES, ROOT, closed_tank

VALID = ROOT / "tests" / "data" / "bad_scenes" / "_valid_base.yaml"
CASE_NAMES = ["nodebris", "1debris", "3debris-3x1", "3debris-1x3", "6debris-2x3"]
G = 9.81


def case(name: str, *overrides: str):
    """A shipped scene planned on the coupled (overset) path, which these tests check body by body
    (auto sends the shipped layouts one-way: tests/test_coupling.py)."""
    return load_scene(CASES / f"{name}.yaml", ["run.debris_coupling=two-way", *overrides])


def valid(*overrides: str):
    """The valid base scene on the coupled (overset) path (see case())."""
    return load_scene(VALID, ["run.debris_coupling=two-way", *overrides])


def all_cell_sizes(segs) -> list[float]:
    out = []
    for s in segs:
        n, r = s.cells, s.grading
        if n == 1 or abs(r - 1) < 1e-12:
            out += [s.length_m / n] * n
        else:
            q = r ** (1 / (n - 1))
            sizes = q ** np.arange(n)
            out += list(sizes / sizes.sum() * s.length_m)
    return out


# ------------------------------------------------------------------ model choices


def test_no_debris_is_interfoam_on_a_static_3d_mesh_when_the_column_is_narrow():
    p = plan_case(case("nodebris"))
    assert p.solver == "interFoam" and p.bodies == () and not p.two_d
    assert "no debris" in p.reasons["solver"]


@pytest.mark.parametrize("name, n", [("1debris", 1), ("3debris-3x1", 3), ("3debris-1x3", 3), ("6debris-2x3", 6)])
def test_debris_is_overset_with_one_body_each(name, n):
    s = case(name)
    p = plan_case(s)
    assert p.solver == "overInterDyMFoam" and not p.two_d
    assert [b.name for b in p.bodies] == [b.name for b in s.debris]
    assert len(p.bodies) == n


def test_laterally_uniform_scene_is_2d():
    p = plan_case(valid("column=null", "debris=[]"))
    assert p.two_d and p.solver == "interFoam"
    assert len(p.background.y) == 1 and p.background.y[0].cells == 1
    faces = p.background.boundary_faces()
    assert "frontAndBack" in faces and "sideWalls" not in faces and "column" not in faces


def test_fine_region_reaches_the_furthest_downstream_gauge():
    p = plan_case(valid("column=null", "debris=[]", "gauges.1.x_m=4.0"))
    assert p.fine_region_m[0][1] >= 4.0
    assert p.fine_region_m[0][0] == pytest.approx(-0.3)  # one impoundment depth upstream of the gate


def test_full_width_obstacle_is_2d_with_a_hole_through_the_width():
    p = plan_case(valid("debris=[]", "column.size_y_m=1.0", "column.height_m=0.1", "gauges=[]"))
    assert p.two_d
    assert p.background.holes and all(j == 0 for _, j, _ in p.background.holes)
    faces = p.background.boundary_faces()
    assert "column" in faces and "frontAndBack" in faces


def test_background_patch_names():
    p = plan_case(case("1debris"))
    assert set(p.background.boundary_faces()) == {
        "upstreamWall", "downstream", "sideWalls", "bed", "atmosphere", "column",
    }


def test_column_hole_matches_the_column():
    s = case("1debris")
    p = plan_case(s)
    g = p.background
    col = s.column
    for i, j, k in g.holes:
        assert col.x_m - 0.1 - 1e-9 <= g.x[i].start_m and g.x[i].end_m <= col.x_m + 0.1 + 1e-9
        assert -0.1 - 1e-9 <= g.y[j].start_m and g.y[j].end_m <= 0.1 + 1e-9
    xs = {g.x[i].start_m for i, _, _ in g.holes} | {g.x[i].end_m for i, _, _ in g.holes}
    assert min(xs) == pytest.approx(4.9) and max(xs) == pytest.approx(5.1)
    zs = {g.z[k].end_m for _, _, k in g.holes}
    assert max(zs) == pytest.approx(p.domain_m[2][1])  # the 0.8 m column reaches above the 0.6 m top


# ------------------------------------------------------------------------ bodies


def test_body_grid_patches_and_hole():
    p = plan_case(case("3debris-1x3"))
    for b in p.bodies:  # resting bodies: the hole is the body's block, above the gap's four rows
        assert b.grid.holes == frozenset({(1, 1, len(b.grid.z) - 2)})
        assert len(b.grid.z) == 4 + 1 + 1  # several resting bodies: nothing below the bed (meshes_stop_at_bed)
        faces = b.grid.boundary_faces()
        assert set(faces) == {f"{b.name}Overset", b.name}
        assert len(faces[b.name]) > 0


def test_body_grid_is_placed_on_the_rotated_body():
    s = valid("debris.0.yaw_deg=30", "debris.0.pitch_deg=20", "debris.0.roll_deg=10", "debris.0.centre_m=[2.0, 0.0, 0.2]")
    p = plan_case(s)
    b = p.bodies[0]
    rot = body_rotation(30, 20, 10)
    assert np.allclose(b.orientation, rot)
    g = b.grid
    verts = g.vertices()
    # the hole block's corners are the body's corners in the scene
    hole_corners = verts[list(g.hex_vertices(1, 1, 1))]
    half = np.asarray(b.size_m) / 2
    signs = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]])
    expected = np.asarray(b.centre_of_mass_m) + (signs * half) @ rot.T
    assert np.allclose(hole_corners, expected)


def test_body_mesh_extends_the_margin_and_is_fine_at_the_body():
    s = case("1debris")
    p = plan_case(s)
    b = p.bodies[0]
    h = s.mesh.cell_size_m
    margin = s.mesh.body_margin_cells * h
    assert b.grid.x[0].start_m == pytest.approx(-0.075 - margin)
    assert b.grid.z[-1].end_m == pytest.approx(0.03 + margin)
    assert b.cell_size_m == pytest.approx(min(h, 0.06 / s.mesh.body_cells_across))
    assert max(all_cell_sizes(b.grid.y)) <= h * (1 + 1e-9)


@pytest.mark.parametrize("wet", [0.002, 0.0, 0.015, 0.03])
def test_a_resting_body_stands_on_a_gap_whose_layers_both_meshes_share(wet):
    # v1912 holes the body cells over the background's bed-adjacent cells and the background
    # cells over the body's wall-adjacent cells: a body standing on the bed has no valid cell
    # under it. Four shared layers leave a valid donor in each (plan.BedGap).
    s = case("1debris", f"bed.wet_depth_m={wet}")
    p = plan_case(s)
    b = p.bodies[0]
    gap = p.bed_gap_m
    layer = gap / 4
    assert 0 < gap <= b.cell_size_m / 2 + 1e-12
    bg = np.asarray(p.background.planes("z"))
    for k in range(5):  # the background's first planes are the gap's, and the wet bed's surface one of its planes
        assert np.any(np.isclose(bg, k * layer))
    if wet:
        assert np.any(np.isclose(bg, wet))
        assert wet >= gap - 1e-12 or np.isclose(wet / layer, round(wet / layer))
    # the body stands on the gap, and its mesh has the same four planes under it
    half = b.size_m[2] / 2
    assert b.centre_of_mass_m[2] == pytest.approx(half + gap)
    faces = np.asarray(b.grid.planes("z")) + b.centre_of_mass_m[2]
    for k in range(5):
        assert np.any(np.isclose(faces, k * layer))
    assert np.all(np.diff(faces) > 0)
    # the body's hole is its own block, nothing else
    (i, j, k), = b.grid.holes
    assert (i, j) == (1, 1)
    assert b.grid.z[k].start_m == pytest.approx(-half) and b.grid.z[k].end_m == pytest.approx(half)
    assert b.grid.cell_count() == sum(
        b.grid.x[i].cells * b.grid.y[j].cells * b.grid.z[k].cells for i, j, k in b.grid.blocks()
    )
    # released when the water reaches its draft above the gap (26 mm + gap), later than without it
    assert b.hold_until_s > _hold_until_s(s, s.debris[0], 0.0, scene_facts(s).bed_flow)
    assert any("bed layer" in w for w in p.warnings) == (layer < 0.2 * s.mesh.cell_size_m)


@pytest.mark.parametrize("name", ["3debris-3x1", "3debris-1x3", "6debris-2x3"])
def test_the_meshes_of_several_resting_bodies_end_at_the_bed(name):
    """Below the bed two body meshes can take donors only from each other: in the 3x1 and 1x3 layouts
    two-way such cells reached 4.8e4 and 340 m/s and the time step collapsed (plan.meshes_stop_at_bed).
    With several resting bodies each mesh's lowest plane is the bed, under the gap's four layers."""
    p = plan_case(case(name, "run.debris_coupling=two-way"))
    assert len(p.bodies) >= 3
    layer = p.bed_gap_m / 4
    for b in p.bodies:
        faces = np.asarray(b.grid.planes("z")) + b.centre_of_mass_m[2]
        assert faces[0] == pytest.approx(0.0, abs=1e-12)
        assert np.allclose(faces[:5], layer * np.arange(5))
    assert not any("below the bed" in w for w in p.warnings)
    assert "ends at the bed" in p.reasons["bed_gap"]


def test_tilted_resting_bodies_whose_meshes_meet_below_the_bed_are_warned_of():
    """Only upright resting bodies' meshes end at the bed; three rolled containers in a line keep
    their margin below it, and each neighbouring pair's meshes overlap there (not the two ends)."""
    p = plan_case(case("3debris-3x1", "run.debris_coupling=two-way", "debris.0.body.roll_deg=10"))
    meet = [w for w in p.warnings if "overlap below the bed" in w]
    assert [w.split(":")[0] for w in meet] == ["debris1 and debris2", "debris2 and debris3"]
    upright = plan_case(case("3debris-3x1", "run.debris_coupling=two-way"))
    assert not any("overlap below the bed" in w for w in upright.warnings)


def test_a_single_resting_body_keeps_its_margin_below_the_bed():
    s = case("1debris", "run.debris_coupling=two-way")
    p = plan_case(s)
    (b,) = p.bodies
    bottom = b.grid.planes("z")[0] + b.centre_of_mass_m[2]
    margin = s.mesh.body_margin_cells * s.mesh.cell_size_m
    assert bottom == pytest.approx(b.centre_of_mass_m[2] - b.size_m[2] / 2 - margin)
    assert bottom < -p.bed_gap_m
    assert "ends at the bed" not in p.reasons["bed_gap"]
    assert any("below the bed" in w for w in p.warnings)


def test_a_floating_body_on_a_dry_bed_needs_no_bed_layer():
    p = plan_case(case("1debris", "bed.wet_depth_m=0", "debris.0.placement=given", "debris.0.centre_m=[3.2, 0.0, 0.2]"))
    assert p.background.planes("z")[1] > 0.03
    assert p.bodies[0].grid.holes == frozenset({(1, 1, 1)})


@pytest.mark.parametrize("x", [-0.5, 3.2])
def test_a_floating_bodys_mesh_has_a_plane_at_the_still_water(x):
    # setFields fills whole cells by their centres: without the plane, the study's container afloat
    # had its mesh's waterline row filled 3.7 mm above the background's water and heaved +-1 mm
    s = case("1debris", "bed.wet_depth_m=0.08", "debris.0.placement=floating", f"debris.0.centre_m=[{x}, 0.0]")
    b = plan_case(s).bodies[0]
    water = s.reservoir.depth_m if x < 0 else 0.08
    assert b.centre_of_mass_m[2] - 0.03 == pytest.approx(water - 0.236 / (998.2 * 0.15 * 0.06))  # at its draft
    faces = np.asarray(b.grid.planes("z")) + b.centre_of_mass_m[2]
    assert np.any(np.isclose(faces, water, rtol=0, atol=1e-12))
    assert max(all_cell_sizes(b.grid.z)) <= s.mesh.cell_size_m * (1 + 1e-9)
    assert min(all_cell_sizes(b.grid.z)) >= 0.5 * b.cell_size_m
    # the hole is the body, split at its waterline: both its blocks and nothing else
    assert {k for _, _, k in b.grid.holes} == {1 + len(b.grid.z) - 4, 2 + len(b.grid.z) - 4}
    lo = min(b.grid.z[k].start_m for _, _, k in b.grid.holes)
    hi = max(b.grid.z[k].end_m for _, _, k in b.grid.holes)
    assert (lo, hi) == (pytest.approx(-0.03), pytest.approx(0.03))
    # a body resting on the bed keeps its mesh as it was (the gap's planes, BedGap)
    assert len(plan_case(case("1debris")).bodies[0].grid.z) == 1 + 4 + 1 + 1


def plate_inertia(a, b, c, t, rho):
    """Closed box as six plates (parallel-axis theorem): an independent route."""
    plates = []  # ((size x, y, z), centre offset)
    for s in (-1, 1):
        plates.append(((t, b, c), (s * (a - t) / 2, 0, 0)))
        plates.append(((a - 2 * t, t, c), (0, s * (b - t) / 2, 0)))
        plates.append(((a - 2 * t, b - 2 * t, t), (0, 0, s * (c - t) / 2)))
    ixx = iyy = izz = 0.0
    for (sx, sy, sz), (dx, dy, dz) in plates:
        m = rho * sx * sy * sz
        ixx += m * (sy**2 + sz**2) / 12 + m * (dy**2 + dz**2)
        iyy += m * (sx**2 + sz**2) / 12 + m * (dx**2 + dz**2)
        izz += m * (sx**2 + sy**2) / 12 + m * (dx**2 + dy**2)
    return ixx, iyy, izz


def test_inertia_of_the_study_container_matches_six_plates():
    a, b, c, t, m = 0.15, 0.06, 0.06, 0.005, 0.236
    rho = m / (a * b * c - (a - 2 * t) * (b - 2 * t) * (c - 2 * t))
    assert body_inertia((a, b, c), m, t) == pytest.approx(plate_inertia(a, b, c, t, rho), rel=1e-12)


def test_inertia_solid_and_given():
    assert body_inertia((0.3, 0.2, 0.1), 6.0, None) == pytest.approx(
        (6 * (0.04 + 0.01) / 12, 6 * (0.09 + 0.01) / 12, 6 * (0.09 + 0.04) / 12)
    )
    p = plan_case(valid("debris.0.wall_thickness_m=null", "debris.0.moment_of_inertia_kg_m2=[1e-4, 2e-4, 3e-4]"))
    assert p.bodies[0].moment_of_inertia_kg_m2 == (1e-4, 2e-4, 3e-4)


def test_hollow_box_has_more_inertia_than_the_solid_one_of_equal_mass():
    hollow = body_inertia((0.15, 0.06, 0.06), 0.236, 0.005)
    solid = body_inertia((0.15, 0.06, 0.06), 0.236, None)
    assert all(h > s for h, s in zip(hollow, solid))


# ------------------------------------------------------------ extents and water


def test_reservoir_truncation_keeps_the_reflection_out_of_the_gate_region():
    s = case("1debris")
    p = plan_case(s)
    L = -p.domain_m[0][0]
    c0 = math.sqrt(G * 0.4)
    guard = 0.4  # the gate region: one impoundment depth upstream (WG1 is at -0.10 m)
    assert L < s.reservoir.length_m
    assert L / c0 + (L - guard) / (4 / 3 * c0) == pytest.approx(SAFETY * s.run.end_time_s)
    assert "truncated" in p.reasons["reservoir_length"]


def test_reservoir_is_whole_when_the_run_is_long():
    s = case("1debris", "run.end_time_s=60")
    p = plan_case(s)
    assert p.domain_m[0][0] == pytest.approx(-21.55)
    assert "whole reservoir" in p.reasons["reservoir_length"]


def test_open_end_with_supercritical_flow_ends_past_the_column_wake():
    p = plan_case(case("1debris"))
    assert p.downstream_type == "outlet"
    assert p.domain_m[0][1] == pytest.approx(5.1 + 0.12 + 1.0)  # column face + margin + 5 widths
    assert "supercritical" in p.reasons["domain_end"]


def test_closed_end_is_a_wall_when_its_reflection_could_matter():
    long = plan_case(case("1debris", "flume.downstream_end=closed", "run.end_time_s=6"))
    assert long.downstream_type == "wall" and long.domain_m[0][1] == pytest.approx(8.45)
    short = plan_case(case("1debris", "flume.downstream_end=closed", "run.end_time_s=0.5", "flume.length_m=40"))
    assert short.downstream_type == "outlet" and short.domain_m[0][1] < 18.45


@pytest.mark.parametrize("end", ["open", "closed"])
def test_untrimmed_domain_is_the_whole_flume_and_coarsening_1_is_uniform(end):
    # the hand-made baseline of the speed-error study (cases/sweeps/mesh-study-hand.yaml)
    s = case("nodebris", "mesh.trim_domain=false", "mesh.coarsening_ratio=1", f"flume.downstream_end={end}",
             "mesh.cell_size_m=0.06")
    p = plan_case(s)
    assert p.domain_m[0] == pytest.approx((-21.55, 8.45)) and p.domain_m[2][1] == pytest.approx(0.8)
    assert p.downstream_type == ("outlet" if end == "open" else "wall")
    assert all("trim_domain is false" in p.reasons[k] for k in ("reservoir_length", "domain_end", "domain_top"))
    h = s.mesh.cell_size_m
    for axis in (p.background.x, p.background.y):
        assert max(all_cell_sizes(axis)) <= h * (1 + 1e-9)
        assert min(all_cell_sizes(axis)) >= 0.5 * h - 1e-9  # only the column's faces cut a cell
    z = all_cell_sizes(p.background.z)
    assert z[0] == pytest.approx(0.015) and max(z) <= h * (1 + 1e-9)  # the wet bed keeps its plane
    trimmed = plan_case(case("nodebris", "mesh.cell_size_m=0.06"))
    assert p.cell_count > 3 * trimmed.cell_count
    # the default trims, and the knob changes nothing else
    assert case("nodebris").mesh.trim_domain is True
    assert trimmed.domain_m[0][0] > -21.55 and trimmed.domain_m[2][1] == pytest.approx(0.6)


def test_domain_holds_every_gauge_body_and_the_column():
    for name in CASE_NAMES:
        s = case(name)
        p = plan_case(s)
        (x0, x1), (y0, y1), (z0, z1) = p.domain_m
        for g in s.gauges:
            assert x0 <= g.x_m <= x1 and y0 <= g.y_m <= y1
        assert x0 < s.column.x_m - 0.1 and s.column.x_m + 0.1 < x1
        for b in s.debris:
            assert x0 < b.centre_m[0] < x1


def test_water_boxes_and_gauges():
    s = case("1debris")
    p = plan_case(s)
    res, bed = p.water
    assert res.name == "reservoir" and res.max_m[0] == 0.0 and res.max_m[2] == 0.4
    assert res.min_m[0] == pytest.approx(p.domain_m[0][0])
    assert bed.name == "wetBed" and bed.max_m[2] == 0.015 and bed.max_m[0] == pytest.approx(p.domain_m[0][1])
    assert [g.name for g in p.gauges] == ["WG1", "WG2", "WG3", "WG4"]
    assert all(g.z_top == pytest.approx(p.domain_m[2][1]) for g in p.gauges)
    dry = plan_case(case("1debris", "bed.wet_depth_m=0"))
    assert [w.name for w in dry.water] == ["reservoir"]


def test_grid_has_planes_at_the_gate_the_impoundment_and_the_wet_bed():
    p = plan_case(case("1debris"))
    assert 0.0 in p.background.planes("x")
    zs = p.background.planes("z")
    assert 0.4 in zs and 0.015 in zs


@pytest.mark.parametrize("name, overrides", [
    ("1debris", ()),
    ("nodebris", ()),
    # the column's top 1 cm above the impoundment: a useful plane there would be dropped for the
    # column's hard one, and setFields would fill the reservoir's top cells to 0.40 m (2.6 % too much)
    ("1debris", ("reservoir.depth_m=0.39", "column.height_m=0.4")),
    ("nodebris", ("reservoir.depth_m=0.41", "column.height_m=0.4", "mesh.top_m=0.7")),
])
def test_every_face_of_every_water_box_is_a_cell_face(name, overrides):
    """setFields fills whole cells by their centres: the water put in is the scene's only when
    each box face is a plane of the background mesh. Expected: all six faces of each box are."""
    p = plan_case(case(name, *overrides))
    planes = {a: np.array(p.background.planes(a)) for a in "xyz"}
    for box in p.water:
        for d, axis in enumerate("xyz"):
            for v in (box.min_m[d], box.max_m[d]):
                assert np.abs(planes[axis] - v).min() < 1e-9, f"{box.name}: {axis} = {v} is not a cell face"


def tank(*overrides: str):
    """A 2D closed tank: 0.4 m reservoir 0.2 m deep, the end wall 0.8 m past the gate, 0.6 m walls."""
    return scene_from_dict(apply_overrides(closed_tank(("WG1", 0.6)), list(overrides), "tank"), "tank")


def test_a_closed_end_the_bore_reaches_keeps_the_air_space_up_to_the_walls():
    """Expected: the bore reaches the end wall (0.8 m at 2 sqrt(g h0) = 2.8 m/s: from 0.29 s) within
    the 1 s run and can run up 2 h0 = 0.4 m, above the 1.5 h0 = 0.3 m trim: the air space goes up
    to the walls (0.6 m) and the plan says why."""
    p = plan_case(tank())
    assert p.downstream_type == "wall" and p.domain_m[2][1] == pytest.approx(0.6)
    why = p.reasons["domain_top"]
    assert "up to the walls" in why and "closed end wall" in why and "0.4 m" in why and "2 h0" in why
    assert 0.6 in [round(z, 9) for z in p.background.planes("z")]


def test_a_closed_end_out_of_reach_keeps_the_trim():
    """0.2 s: the front (at most 2.8 m/s) cannot reach the end wall 0.8 m away. Expected: trimmed
    to 1.5 h0 = 0.3 m, the reason saying nothing runs up."""
    p = plan_case(tank("run.end_time_s=0.2"))
    assert p.domain_m[2][1] == pytest.approx(0.3)
    assert "nothing runs up" in p.reasons["domain_top"]


def test_run_up_at_the_column_depends_on_how_much_of_the_width_it_blocks():
    """The study's column blocks 13 % of the flume: its splash-up is left to the atmosphere patch
    (the air space stays at 1.5 h0 = 0.6 m). Across the whole width (2D) it acts as a wall: the air
    space goes up to the 0.8 m walls."""
    narrow = plan_case(case("1debris"))
    assert narrow.domain_m[2][1] == pytest.approx(0.6)
    assert "13% of the width" in narrow.reasons["domain_top"]
    wide = plan_case(case("nodebris", "column.size_y_m=1.5"))
    assert wide.two_d and wide.domain_m[2][1] == pytest.approx(0.8)
    assert "the column across 100% of the width" in wide.reasons["domain_top"]
    half = plan_case(case("nodebris", "column.size_y_m=0.75"))
    assert half.domain_m[2][1] == pytest.approx(0.8)


def test_a_top_set_below_the_run_up_is_a_warning():
    p = plan_case(tank("mesh.top_m=0.3"))
    assert p.domain_m[2][1] == pytest.approx(0.3)
    assert any("mesh.top_m = 0.3 m is below the run-up" in w for w in p.warnings)
    assert not any("mesh.top_m" in w for w in plan_case(tank("mesh.top_m=0.5")).warnings)


def test_cells_are_fine_in_the_fine_region_and_never_coarser_than_the_limit():
    s = case("1debris")
    p = plan_case(s)
    h = s.mesh.cell_size_m
    h_max = h * s.mesh.coarsening_ratio
    for axis, (lo, hi) in zip("xyz", p.fine_region_m):
        for seg in getattr(p.background, axis):
            sizes = all_cell_sizes([seg])
            assert max(sizes) <= h_max * (1 + 1e-9)
            if lo - 1e-9 <= seg.start_m and seg.end_m <= hi + 1e-9:
                assert max(sizes) <= h * (1 + 1e-9)


def test_cell_count_is_the_sum_of_the_grids():
    p = plan_case(case("6debris-2x3"))
    assert p.cell_count == p.background.cell_count() + sum(b.grid.cell_count() for b in p.bodies)


# ------------------------------------------------------------ decomposition, cost


@pytest.mark.parametrize("name", CASE_NAMES)
@pytest.mark.parametrize("cores", [1, 2, 3, 4])
def test_decomposition_uses_every_core_and_keeps_bodies_whole(name, cores):
    s = case(name, f"run.cores={cores}")
    p = plan_case(s)
    assert p.cores == cores
    n = len(s.debris)
    if n and cores > 1:  # decomposePar's constraint keeps them whole (tests/test_render.py)
        assert "on one rank (decomposePar's preserveFaceZones" in p.reasons["decomposition"]
    if n >= 2 and cores > 1:  # then the runner splits each (orchestrator/case/split_bodies.py)
        assert "moved to the next rank" in p.reasons["decomposition"]
    # on 2 ranks the balanced cut clears the study's one-body layout
    if n == 1 and cores == 2:
        assert "1 of 1 body meshes start clear of the balanced cuts" in p.reasons["decomposition"]
        assert "1 keep their path to the column on one rank" in p.reasons["decomposition"]


def test_two_d_decomposition_never_splits_the_single_cell_across():
    p = plan_case(valid("column=null", "debris=[]", "run.cores=4"))
    assert p.decomposition[1] == 1


def test_wall_time_estimate_is_cells_times_steps_times_cost():
    p = plan_case(case("1debris"))
    steps = math.ceil(p.end_time_s / p.time_step_estimate_s)
    assert estimate_wall_time_s(p) == pytest.approx(p.cell_count * steps * US_PER_CELL_STEP["overInterDyMFoam"])
    assert p.estimated_wall_time_s == pytest.approx(estimate_wall_time_s(p))
    p4 = plan_case(case("1debris", "run.cores=4"))
    assert p4.estimated_wall_time_s == pytest.approx(p.estimated_wall_time_s / 2)


#: Whole coupled runs with the current contact law and runner: (scene, overrides, time steps,
#: solver wall time on 2 idle cores or None where the machine was shared), from
#: docs/results/case-1debris-two-way and docs/results/speed-error-debris.
COUPLED_RUNS = [
    ("1debris", ("mesh.column_approach_cell_size_m=null",), 1478, 2513.5),  # run at 4 cm throughout
    ("hard/short-flume", ("mesh.cell_size_m=0.04", "run.end_time_s=2.1"), 1431, 2288.8),
    ("hard/short-flume", ("mesh.cell_size_m=0.035", "run.end_time_s=2.1"), 2062, None),
    ("hard/short-flume", ("mesh.cell_size_m=0.03", "run.end_time_s=2.1"), 1451, None),
]


@pytest.mark.parametrize("name, overrides, steps, solver_s", COUPLED_RUNS)
def test_coupled_estimates_are_within_the_spread_of_whole_runs(name, overrides, steps, solver_s):
    """A coupled run's steps depend on how often its body strikes (each strike restarts the
    solver on short steps): the four runs took 0.67-1.48 times the estimate. A wrong factor or
    cost per cell-step moves every estimate outside this band."""
    p = plan_case(case(name, *overrides))
    assert steps / 1.5 < estimated_steps(p) < steps * 1.5
    if solver_s is not None:
        assert solver_s / 2 < p.estimated_wall_time_s < solver_s * 2


def test_time_step_estimate_is_capped_by_max_delta_t():
    """A large Courant number on a coarse mesh: the step is maxDeltaT's, as in the runs (the
    hard case coarse-large-courant took 365 steps to 3.5 s at maxDeltaT 0.01 s, 89 at 0.05 s)."""
    capped = plan_case(case("nodebris", "mesh.cell_size_m=0.08", "run.max_courant=5", "run.end_time_s=3.5"))
    assert capped.time_step_estimate_s == pytest.approx(0.01)
    assert estimated_steps(capped) == 350
    free = plan_case(case("nodebris", "mesh.cell_size_m=0.08", "run.max_courant=5", "run.end_time_s=3.5",
                          "run.max_delta_t_s=0.05"))
    assert 89 / 1.5 < estimated_steps(free) < 89 * 1.5


def test_overset_steps_carry_the_measured_factor():
    """Ritter's front speed alone predicts about 400 steps for the coupled 1-debris scene; it took
    1,478 (COUPLED_RUNS)."""
    s = case("1debris")
    p = plan_case(s)
    h_body = min(b.cell_size_m for b in p.bodies)
    courant_dt = s.run.max_courant * min(h_body, s.mesh.cell_size_m) / p.velocity_scale_m_s
    assert p.time_step_estimate_s <= courant_dt / STEP_FACTOR["overInterDyMFoam"]
    assert s.run.end_time_s / courant_dt < 500 < estimated_steps(p)


def test_time_step_uses_the_ritter_front_speed():
    s = case("nodebris")
    p = plan_case(s)
    assert p.velocity_scale_m_s == pytest.approx(2 * math.sqrt(G * 0.4))
    assert p.time_step_estimate_s <= s.run.max_courant * s.mesh.cell_size_m / p.velocity_scale_m_s + 1e-12


# --------------------------------------------------------------------- reasons, json


@pytest.mark.parametrize("name", CASE_NAMES)
def test_every_decision_has_a_reason_and_the_json_is_complete(name):
    p = plan_case(case(name))
    assert set(REASON_KEYS) <= set(p.reasons)
    assert all(isinstance(v, str) and len(v) > 10 for v in p.reasons.values())
    data = json.loads(p.to_json())
    assert data["solver"] == p.solver and data["cell_count"] == p.cell_count
    assert data["background"]["cell_count"] == p.background.cell_count()
    assert data["decomposition"] == {"method": "hierarchical", "n": list(p.decomposition)}
    assert set(data["reasons"]) == set(p.reasons)
    for b, jb in zip(p.bodies, data["bodies"]):
        assert jb["grid"]["patch_names"]["hole"] == b.name
        assert len(jb["orientation"]) == 3


def test_plan_holds_bodies_resting_on_the_bed():
    p = plan_case(case("1debris"))
    assert p.bodies[0].on_bed and p.bodies[0].hold_until_s > 0
    assert "sink through the floor" in p.reasons["hold_on_bed"]


def test_plan_is_pure_and_repeatable():
    s = case("3debris-3x1")
    assert plan_case(s).to_json() == plan_case(s).to_json()


# ------------------------------------------------------------------- properties

BASE = yaml.safe_load(VALID.read_text())


def build(**changes) -> dict:
    data = copy.deepcopy(BASE)
    for key, value in changes.items():
        node = data
        parts = key.split("__")
        for part in parts[:-1]:
            node = node[part]
        node[parts[-1]] = value
    return data


@settings(max_examples=60, deadline=None)
@given(
    st.floats(0.05, 20.0),
    st.floats(0.05, 20.0),
    st.floats(0.15, 0.55),  # >= 4 cells of the base scene's 0.03 m, below its 0.6 m walls
)
def test_reservoir_length_grows_with_end_time_and_is_capped(t1, t2, depth):
    t1, t2 = sorted((t1, t2))
    s1 = scene_from_dict(build(run__end_time_s=t1, reservoir__depth_m=depth))
    s2 = scene_from_dict(build(run__end_time_s=t2, reservoir__depth_m=depth))
    l1, l2 = -plan_case(s1).domain_m[0][0], -plan_case(s2).domain_m[0][0]
    assert l1 <= l2 + 1e-12
    assert l2 <= s2.reservoir.length_m + 1e-12


@settings(max_examples=40, deadline=None)
@given(st.floats(0.012, 0.04), st.floats(1.1, 3.0), st.sampled_from(["nodebris", "1debris", "3debris-1x3"]))
def test_cell_count_falls_when_cells_grow(h1, factor, name):
    h2 = h1 * factor
    assume(h2 <= 0.04)
    n1 = plan_case(case(name, f"mesh.cell_size_m={h1}")).cell_count
    n2 = plan_case(case(name, f"mesh.cell_size_m={h2}")).cell_count
    assert n2 < n1


scenes = st.fixed_dictionaries(
    {
        "col": st.one_of(st.none(), st.tuples(st.floats(-3.0, 5.5), st.floats(-0.35, 0.35), st.floats(0.1, 0.4))),
        "bodies": st.lists(
            st.tuples(st.floats(-5.5, 5.8), st.floats(-0.4, 0.4), st.floats(0, 180), st.floats(-20, 20)),
            max_size=3,
        ),
        "end": st.floats(0.2, 8.0),
        "cell": st.floats(0.02, 0.04),
        "wet": st.sampled_from([0.0, 0.01]),
        "end_kind": st.sampled_from(["open", "closed"]),
        "cores": st.integers(1, 4),
    }
)


def random_scene(d):
    data = build(
        run__end_time_s=d["end"], mesh__cell_size_m=d["cell"], bed__wet_depth_m=d["wet"],
        flume__downstream_end=d["end_kind"], run__cores=d["cores"],
    )
    if d["col"] is None:
        data["column"] = None
        data["gauges"] = [{"name": "WG1", "x_m": -0.1, "y_m": 0.0}]
    else:
        data["column"].update(x_m=d["col"][0], y_m=d["col"][1], size_x_m=d["col"][2])
        data["gauges"] = [{"name": "WG1", "x_m": -0.1, "y_m": 0.45}]
    data["debris"] = [
        {"name": f"b{i}", "size_m": [0.15, 0.06, 0.06], "mass_kg": 0.236, "wall_thickness_m": 0.005,
         "centre_m": [x, y], "yaw_deg": yaw, "pitch_deg": pitch}
        for i, (x, y, yaw, pitch) in enumerate(d["bodies"])
    ]
    try:
        return scene_from_dict(data)
    except InputError:
        assume(False)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(scenes)
def test_fine_region_always_holds_the_column_and_the_debris(d):
    s = random_scene(d)
    p = plan_case(s)
    (fx0, fx1), (fy0, fy1), (fz0, fz1) = p.fine_region_m
    eps = 1e-9
    if s.column is not None:
        c = s.column
        assert fx0 - eps <= c.x_m - c.size_x_m / 2 and c.x_m + c.size_x_m / 2 <= fx1 + eps
        assert fy0 - eps <= c.y_m - c.size_y_m / 2 and c.y_m + c.size_y_m / 2 <= fy1 + eps
    for b in s.debris:
        rot = body_rotation(b.yaw_deg, b.pitch_deg, b.roll_deg)
        ext = np.abs(rot) @ (np.asarray(b.size_m) / 2)
        lo, hi = np.asarray(b.centre_m) - ext, np.asarray(b.centre_m) + ext
        assert fx0 - eps <= lo[0] and hi[0] <= fx1 + eps
        assert fy0 - eps <= lo[1] and hi[1] <= fy1 + eps
        assert fz0 - eps <= lo[2] and hi[2] <= fz1 + eps
    # and the fine region's cells really are the finest
    h = s.mesh.cell_size_m
    for axis, (lo_, hi_) in zip("xyz", p.fine_region_m):
        for seg in getattr(p.background, axis):
            if lo_ - eps <= seg.start_m and seg.end_m <= hi_ + eps and not (axis == "y" and p.two_d):
                assert max(all_cell_sizes([seg])) <= h * (1 + 1e-9)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
@given(scenes)
def test_every_decision_has_a_reason_for_any_scene(d):
    s = random_scene(d)
    p = plan_case(s)
    assert set(REASON_KEYS) <= set(p.reasons)
    assert all(p.reasons[k].strip() for k in REASON_KEYS)
    assert p.cores == s.run.cores
    assert p.cell_count == p.background.cell_count() + sum(b.grid.cell_count() for b in p.bodies)
    assert (p.solver == "interFoam") == (not s.debris or p.debris_coupling == "one-way")
    json.loads(p.to_json())


def test_bodies_on_the_bed_are_held_until_the_bore_can_lift_them():
    from analytical.dambreak import dam_break

    scene = case("1debris")
    plan = plan_case(scene)
    body, debris = plan.bodies[0], scene.debris[0]
    assert body.on_bed and 0 < body.hold_until_s < scene.run.end_time_s
    # it stands on the gap (plan.BedGap): the water must reach its draft above the gap
    draft = debris.mass_kg / (scene.fluids.water_density_kg_m3 * debris.size_m[0] * debris.size_m[1]) + plan.bed_gap_m
    chanson = dam_break("chanson", scene.reservoir.depth_m, friction=scene.bed.friction_factor)
    depth = chanson.profile(np.array([debris.centre_m[0]]), body.hold_until_s).depth_m[0]
    assert depth == pytest.approx(draft, rel=1e-6)  # released exactly when the bore reaches its draft
    assert body.hold_until_s > float(chanson.arrival_time_s(debris.centre_m[0]))
    assert "hold_on_bed" in plan.reasons and body.name in plan.reasons["hold_on_bed"]
    floating = plan_case(case("1debris", "bed.wet_depth_m=0.05"))
    assert floating.bodies[0].hold_until_s == 0.0  # 5 cm of water float the 26 mm draft + 7.5 mm gap: no hold


def test_several_bodies_are_planned_split_across_ranks_and_one_body_whole():
    # v1912's overset deadlocks when two overlapping body meshes share a rank (docs/stability.md):
    # the 2x3 layout's 0.12 m margins overlap across its 0.15 m spacing
    six = plan_case(case("6debris-2x3"))
    assert "moved to the next rank" in six.reasons["decomposition"]
    assert not any("overlap" in w for w in six.warnings)
    one = plan_case(case("1debris"))
    assert "every body mesh on one rank" in one.reasons["decomposition"]
    assert "moved to the next rank" not in one.reasons["decomposition"]


# ------------------------------------------------------------- plan.json round trip

#: The numbers the case's dictionaries need, decided by the planner and written to plan.json.
CASE_NUMBER_KEYS = ("bed_cell_m", "min_cell_m", "still_water_m", "friction_layer_m", "water_depth_m",
                    "column_box_m", "first_delta_t_s", "max_delta_t_s")


@pytest.mark.parametrize("name", CASE_NAMES)
def test_plan_json_carries_the_numbers_the_case_needs(name):
    from orchestrator.plan.case_numbers import friction_layer_top_m

    s = case(name)
    p = plan_case(s)
    data = json.loads(p.to_json())
    for key in CASE_NUMBER_KEYS:
        assert key in data, key
    assert data["bed_cell_m"] == p.background.z[0].cell_sizes_m()[0]
    assert 0 < data["min_cell_m"] <= min(data["bed_cell_m"], s.mesh.cell_size_m)
    assert data["still_water_m"] == s.bed.wet_depth_m
    assert data["friction_layer_m"] == friction_layer_top_m(p.background.z, s.bed.wet_depth_m)
    assert data["friction_layer_m"] > data["still_water_m"]
    assert data["water_depth_m"] == pytest.approx(s.reservoir.depth_m)
    lo, hi = data["column_box_m"]
    assert lo == pytest.approx([s.column.x_m - s.column.size_x_m / 2, s.column.y_m - s.column.size_y_m / 2, 0.0])
    assert hi[0] == pytest.approx(s.column.x_m + s.column.size_x_m / 2)
    assert 0 < data["first_delta_t_s"] <= 1e-3
    assert data["max_delta_t_s"] == min(0.01, s.run.write_interval_s)


def test_plan_json_has_no_column_box_without_a_column():
    p = plan_case(valid("column=null", "debris=[]"))
    assert p.column_box_m is None and json.loads(p.to_json())["column_box_m"] is None


def test_max_delta_t_follows_the_scene_into_the_plan():
    assert plan_case(valid("run.max_delta_t_s=0.05")).max_delta_t_s == 0.05


@pytest.mark.parametrize("name, overrides", [(n, ()) for n in CASE_NAMES] + [
    ("1debris", ("run.cores=4",)), ("2d", ())])
def test_plan_json_reads_back_into_an_equal_plan(name, overrides):
    from dataclasses import replace

    from orchestrator.plan.model import ModelPlan

    p = plan_case(valid("column=null", "debris=[]") if name == "2d" else case(name, *overrides))
    back = ModelPlan.from_json(p.to_json())
    # plan.json holds the wall-time estimate to 0.1 s
    assert back == replace(p, estimated_wall_time_s=round(p.estimated_wall_time_s, 1))
    assert ModelPlan.from_json(back.to_json()) == back
    assert back.to_json() == p.to_json()


def test_a_plan_json_without_a_field_is_refused_by_name():
    from orchestrator.plan.model import ModelPlan

    data = json.loads(plan_case(case("nodebris")).to_json())
    del data["first_delta_t_s"]
    with pytest.raises(InputError, match="first_delta_t_s"):
        ModelPlan.from_dict(data)


def test_the_plan_places_the_gauge_lines_and_probes_inside_the_mesh():
    """Gauge lines from a hair above the bed to a hair under the top, two points per bed cell;
    a probe at the centre of the bed cell under each gauge; four up the column's upstream face,
    in front of it, at 1/5 to 4/5 of the deepest water."""
    p = plan_case(case("1debris"))
    z0, z1 = p.background.planes("z")[0], p.background.planes("z")[-1]
    assert [g.name for g in p.gauge_lines] == [g.name for g in p.gauges]
    for line, gauge in zip(p.gauge_lines, p.gauges):
        assert line.start_m[:2] == line.end_m[:2] == (gauge.x, gauge.y)
        assert z0 < line.start_m[2] < z0 + p.bed_cell_m / 100
        assert min(gauge.z_top, z1) - p.bed_cell_m / 100 < line.end_m[2] < min(gauge.z_top, z1)
        assert line.n_points == math.ceil((min(gauge.z_top, z1) - z0) / (p.bed_cell_m / 2)) + 1
    bed = {pr.name: pr.point_m for pr in p.probes if pr.name.endswith("_bed")}
    assert bed == {f"{g.name}_bed": (g.x, g.y, z0 + p.bed_cell_m / 2) for g in p.gauges}
    face = [pr.point_m for pr in p.probes if pr.name.startswith("column_face_")]
    (cx0, cy0, _), (_, cy1, _) = p.column_box_m
    assert [pt[0] for pt in face] == pytest.approx([cx0 - p.min_cell_m / 4] * 4)
    assert [pt[1] for pt in face] == pytest.approx([(cy0 + cy1) / 2] * 4)
    assert [pt[2] for pt in face] == pytest.approx([z0 + p.water_depth_m * n / 5 for n in range(1, 5)])
    # the bodies' point motion reaches past the whole domain, so their meshes move rigidly
    diag = math.dist([p.background.planes(a)[0] for a in "xyz"], [p.background.planes(a)[-1] for a in "xyz"])
    inner, outer = p.motion_distance_m
    assert diag < inner < outer


def test_the_bed_friction_coefficient_is_f_over_4_dz_times_the_calibration():
    p = plan_case(case("1debris", "bed.friction_calibration=2.0"))
    f = p.bed_friction_factor
    assert f > 0
    assert p.bed_friction_per_m == pytest.approx(2.0 * f / (4 * p.friction_layer_m))
    assert plan_case(case("1debris", "bed.friction_factor=0")).bed_friction_per_m == 0.0


@pytest.mark.parametrize("hz, cap", [(50.0, 0.01), (100.0, 0.01), (200.0, 0.005), (400.0, 0.0025)])
def test_a_one_way_record_gets_a_frame_at_every_interval(hz, cap):
    # maxDeltaT is at most the record's frame interval: a 200 Hz record with 0.01 s steps would
    # get a frame only every other interval
    scene = load_scene(CASES / "1debris.yaml", [f"outputs.flow_record_hz={hz}"])
    plan = plan_case(scene)
    assert plan.flow_record is not None and plan.flow_record.interval_s == pytest.approx(1 / hz)
    assert plan.max_delta_t_s == pytest.approx(cap)
    assert plan.time_step_estimate_s <= cap + 1e-12
