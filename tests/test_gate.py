"""The gate as the flume was built: a sill (the reservoir's floor below the bed downstream) and walls
beside a gate opening narrower than the flume, planned as holes of the background grid, checked
as the scene's cross-field rules, and meshed and filled by OpenFOAM."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from analytical.errors import InputError
from orchestrator.plan.case_numbers import column_box_m
from orchestrator.plan.grading import cell_edges
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import load_scene
from tests.conftest import render_and_run, run_cli

CASES = Path(__file__).resolve().parent.parent / "cases"
TINY = CASES / "tiny-nodebris.yaml"
SILL, OPENING, POSTS_TO = 0.05, 0.18, 0.10  # tiny flume: 0.3 m wide, 0.2 m impoundment


def _plan(*sets: str):
    return plan_case(load_scene(TINY, list(sets)))


def test_a_sill_puts_the_reservoir_floor_below_the_bed_and_leaves_the_bed_downstream_where_it_was():
    plain, sill = _plan(), _plan(f"reservoir.sill_height_m={SILL}")
    grid = sill.background
    assert grid.planes("z")[0] == pytest.approx(-SILL)
    assert 0.0 in [round(z, 12) for z in grid.planes("z")]
    xs, zs = grid.planes("x"), grid.planes("z")
    below = {h for h, side in grid.hole_sides.items() if side == "zmin"}
    # every block below the bed downstream of the gate is sill, and nothing else is
    expected = {(i, j, k) for i in range(len(xs) - 1) for j in range(len(grid.y)) for k in range(len(zs) - 1)
                if xs[i] >= 0 and zs[k + 1] <= 1e-12}
    assert below == expected and expected
    # the reservoir's water fills down to its own floor; the bed downstream, the column and the
    # gauges stay where they were
    reservoir = next(b for b in sill.water if b.name == "reservoir")
    assert reservoir.min_m[2] == pytest.approx(-SILL) and reservoir.max_m[2] == pytest.approx(0.2)
    assert np.allclose(column_box_m(grid), column_box_m(plain.background))
    assert [g.start_m[2] for g in sill.gauge_lines] == pytest.approx([g.start_m[2] for g in plain.gauge_lines])
    assert sill.bed_cell_m == pytest.approx(plain.bed_cell_m)


def test_the_sill_faces_join_the_bed_patch_the_step_included():
    grid = _plan(f"reservoir.sill_height_m={SILL}").background
    faces = grid.boundary_faces()
    pts = grid.vertices()
    area = sum(_area(pts[list(f)]) for f in faces["bed"])
    width = grid.planes("y")[-1] - grid.planes("y")[0]
    length = grid.planes("x")[-1] - grid.planes("x")[0]
    col_lo, col_hi = column_box_m(grid)
    footprint = (col_hi[0] - col_lo[0]) * (col_hi[1] - col_lo[1])
    # the floor, less the column, plus the step's face at the gate (width x sill)
    assert area == pytest.approx(width * length - footprint + width * SILL, rel=1e-9)


def _area(quad: np.ndarray) -> float:
    return 0.5 * float(np.linalg.norm(np.cross(quad[2] - quad[0], quad[3] - quad[1])))


def test_an_opening_narrower_than_the_flume_walls_off_the_rest_for_its_length_and_makes_the_flow_3d():
    plan = _plan(f"reservoir.opening_width_m={OPENING}", f"reservoir.opening_length_m={POSTS_TO}")
    grid = plan.background
    assert not plan.two_d
    walls = [h for h, side in grid.hole_sides.items() if side == "ymin"]
    xs, ys = grid.planes("x"), grid.planes("y")
    # the walls' footprint: from the gate to opening_length_m, the flume's width less the opening
    area = sum((xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j]) for i, j in {(h[0], h[1]) for h in walls})
    assert area == pytest.approx(POSTS_TO * (0.3 - OPENING), rel=1e-9)
    assert all(abs(0.5 * (ys[h[1]] + ys[h[1] + 1])) > OPENING / 2 for h in walls)
    # the x-planes of the walls' ends are cell faces
    edges = cell_edges(grid.x)
    assert np.min(np.abs(edges - POSTS_TO)) < 1e-12 and np.min(np.abs(edges)) < 1e-12


@pytest.mark.parametrize("sets, field", [
    (["reservoir.opening_width_m=0.2", "reservoir.opening_y_m=0.1"], "reservoir.opening_width_m"),
    (["reservoir.opening_width_m=0.06", "reservoir.opening_length_m=1.2"], "reservoir.opening_length_m"),
    (["reservoir.opening_width_m=0.1", "gauges.1.x_m=0.05", "gauges.1.y_m=0.12"], "gauges.1.x_m"),
])
def test_a_gate_opening_that_does_not_fit_names_its_field(sets, field):
    with pytest.raises(InputError) as err:
        load_scene(TINY, sets)
    assert err.value.field == field


def test_a_body_behind_the_gate_over_a_sill_is_refused_through_the_cli(tmp_path):
    proc = run_cli("validate", str(CASES / "1debris.yaml"), "--set", "reservoir.sill_height_m=0.05",
                   "--set", "debris.0.centre_m=[-1.0, 0.0]")
    assert proc.returncode == 2, proc.stderr
    assert "reservoir.sill_height_m" in proc.stderr and "1debris.yaml" in proc.stderr


@pytest.mark.openfoam
def test_openfoam_meshes_the_sill_and_the_walls_and_fills_the_reservoir_to_its_floor(tmp_path, openfoam):
    pv = pytest.importorskip("pyvista")
    case = tmp_path / "gate"
    plan = render_and_run(TINY, case, f"reservoir.sill_height_m={SILL}", f"reservoir.opening_width_m={OPENING}",
                   "run.end_time_s=0.1", "run.write_interval_s=0.1")
    (case / "case.foam").touch()
    reader = pv.POpenFOAMReader(str(case / "case.foam"))
    reader.case_type = "reconstructed"
    reader.set_active_time_value(0.0)
    mesh = reader.read()["internalMesh"]
    volumes = mesh.compute_cell_sizes(length=False, area=False)["Volume"]
    water = float(np.sum(mesh.cell_data["alpha.water"] * volumes))
    length = -plan["background"]["x"][0]["start_m"]  # the modelled reservoir
    # the reservoir holds 0.2 m above the bed downstream plus the sill's depth below it, over the
    # modelled reservoir's length and the flume's width; the bed downstream is dry
    assert water == pytest.approx((0.2 + SILL) * 0.3 * length, rel=1e-6)
    assert float(mesh.bounds[4]) == pytest.approx(-SILL)


# --------------------------------------------------------------------------- the gate opening over a time
OPENING_S = 0.2


def test_a_gate_opening_over_a_time_blocks_the_cells_upstream_of_it_in_bands_released_bottom_up():
    assert _plan().gate_bands == ()  # an instant gate has none
    plan = _plan("reservoir.gate=swing-gate", f"reservoir.opening_time_s={OPENING_S}", f"reservoir.sill_height_m={SILL}")
    bands = plan.gate_bands
    x_edges = cell_edges(plan.background.x)
    floor, level = -SILL, 0.2
    for band in bands:
        # the cell column just upstream of the gate, across the flume, one cell layer high
        assert band.min_m[0] == pytest.approx(max(x_edges[x_edges < 0])) and band.max_m[0] == 0.0
        assert band.min_m[1] < -0.15 and band.max_m[1] > 0.15
        # released when the lifting edge, at (z - floor) = H t / T, passes the band's top
        assert band.release_s == pytest.approx(OPENING_S * min(1.0, (band.max_m[2] - floor) / (level - floor)))
    assert bands[0].min_m[2] == pytest.approx(floor) and bands[-1].release_s == pytest.approx(OPENING_S)
    assert bands[-1].min_m[2] < level <= bands[-1].max_m[2] + 1e-9
    assert all(a.release_s < b.release_s for a, b in zip(bands, bands[1:]))
    assert plan.gate_bands == type(plan).from_json(plan.to_json()).gate_bands


@pytest.mark.parametrize("sets, words", [
    ([f"reservoir.opening_time_s={OPENING_S}"], "instant gate"),
    (["reservoir.gate=swing-gate", "reservoir.opening_time_s=0.5"], "still be opening"),
])
def test_an_opening_time_an_instant_gate_or_the_run_cannot_have_is_refused(sets, words):
    proc = run_cli("validate", str(TINY), *[a for s in sets for a in ("--set", s)])
    assert proc.returncode == 2, proc.stderr
    assert "reservoir.opening_time_s" in proc.stderr and words in proc.stderr


def test_the_gate_bands_are_cell_zones_blocked_by_fvoptions_until_their_release(tmp_path):
    # RANS: no bed friction, so fvOptions and topoSetDict are there for the gate alone
    proc = run_cli("render", str(TINY), "-o", str(tmp_path / "c"), "--set", "reservoir.gate=swing-gate",
                   "--set", f"reservoir.opening_time_s={OPENING_S}", "--set", "fluids.turbulence=kOmegaSST")
    assert proc.returncode == 0, proc.stderr
    plan = plan_case(load_scene(TINY, ["reservoir.gate=swing-gate", f"reservoir.opening_time_s={OPENING_S}",
                                       "fluids.turbulence=kOmegaSST"]))
    options = (tmp_path / "c" / "system" / "fvOptions").read_text()
    topo = (tmp_path / "c" / "system" / "topoSetDict").read_text()
    assert "bedFriction" not in options
    for band in plan.gate_bands:
        assert f"cellZone        {band.name};" in options and f"set     {band.name};" in topo
    assert f"duration        {OPENING_S:g};" in options and options.count("timeStart       0;") == len(plan.gate_bands)


@pytest.mark.openfoam
def test_a_gate_opening_over_a_time_delays_the_front_by_less_than_the_opening_time(tmp_path, openfoam):
    arrivals = []
    for opening in (0.0, OPENING_S):
        case = tmp_path / f"gate-{opening:g}"
        proc = run_cli("case", str(TINY), "-o", str(case), "--set", "column=null", "--set", "reservoir.gate=swing-gate",
                       "--set", f"reservoir.opening_time_s={opening}", "--set", "gauges=[{name: WG2, x_m: 0.4, y_m: 0.0}]")
        assert proc.returncode == 0, proc.stderr[-2000:]
        table = (case / "results" / "gauge_summary.csv").read_text().splitlines()
        arrivals.append(float(next(r for r in table if r.startswith("WG2")).split(",")[table[0].split(",").index(
            "arrival_s")]))
    first_band = plan_case(load_scene(TINY, ["reservoir.gate=swing-gate", f"reservoir.opening_time_s={OPENING_S}"])
                           ).gate_bands[0].release_s
    # no water passes before the bottom band opens; once the gate is clear the flow is the instant
    # gate's at most OPENING_S late
    assert first_band < arrivals[1] - arrivals[0] < OPENING_S, arrivals


def test_with_bodies_on_overset_meshes_the_gate_bands_are_the_background_s_cells_alone(tmp_path):
    scene = Path(__file__).resolve().parent / "data" / "scenes" / "float-carry.yaml"
    sets = ["reservoir.gate=swing-gate", "reservoir.opening_time_s=0.1", "run.debris_coupling=two-way"]
    proc = run_cli("render", str(scene), "-o", str(tmp_path / "c"), *[a for s in sets for a in ("--set", s)])
    assert proc.returncode == 0, proc.stderr
    plan = plan_case(load_scene(scene, sets))
    assert plan.bodies and plan.gate_bands
    topo = (tmp_path / "c" / "system" / "topoSetDict").read_text()
    for band in plan.gate_bands:  # the box's cells, then only those of the background's zone
        block = topo[topo.index(f"the gate's band {band.name},"):]
        assert block.index("source  boxToCell;") < block.index("action  subset;") < block.index("zone    background;")
