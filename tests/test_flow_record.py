"""The one-way flow record: the rendered case records it, the reader grids it into a FlowField.

The OpenFOAM test runs a tiny one-way scene (tests/data/tiny-oneway.yaml below, from
cases/hard/small/tiny-flume.yaml: one container just past the gate, so the record reaches into the
reservoir) for 0.2 s (seconds on 2 cores) through `debrisfoam run` and `post`, then reads the
record. Measured (2,870 points, 2,842 written: 28 in the column's hole): frames at 0, 0.02, ..., 0.2 s;
the reservoir's first recorded column 0.9 mm under the 0.16 m impoundment at 0.02 s; the wet bed
ahead of the bore within 0.04 mm of 0.030 m; each recorded column's water equal to its cells'
sum(alpha V)/A within 1e-6 m (0.83 um: the reader clips alpha's overshoots to [0, 1]); the region's
water from eta within 2 % of the cells whose centres lie in it (1.2 % under: the region's ends cut
cells, and a trapezoid over the record is no cell sum); 32 kB a frame in the .npz against 379 kB of
raw text.
The other tests write synthetic frames into a rendered (not run) one-way case.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from orchestrator.run.openfoam import foam_env, run_step
from orchestrator.plan.model import ModelPlan
from orchestrator.transport.flow import FlowField
from orchestrator.transport.flow_record import FLOW_RECORD_NPZ, FlowRecordError, read_flow_record
from tests.conftest import render_and_run, run_cli

ROOT = Path(__file__).resolve().parent.parent

TINY = {
    "name": "tiny-oneway",
    "description": "Tiny one-way dam break: one container just past the gate, the flow recorded.",
    "flume": {"length_m": 2.4, "width_m": 0.4, "height_m": 0.3, "downstream_end": "open"},
    "reservoir": {"length_m": 0.8, "depth_m": 0.16},
    "bed": {"wet_depth_m": 0.03, "friction_factor": 0.0},
    "column": {"x_m": 1.2, "y_m": 0.0, "size_x_m": 0.1, "size_y_m": 0.1, "height_m": 0.3,
               "wall_thickness_m": 0.005, "youngs_modulus_Pa": 2.5e9, "density_kg_m3": 1200,
               "poisson_ratio": 0.375, "shear_coefficient": 0.5},
    "debris": [{"name": "debris1", "size_m": [0.15, 0.06, 0.06], "mass_kg": 0.236, "wall_thickness_m": 0.005,
                "centre_m": [0.2, 0.0], "placement": "floating"}],
    "gauges": [{"name": "WG1", "x_m": 0.5, "y_m": 0.0}],
    "mesh": {"cell_size_m": 0.04, "coarsening_ratio": 1},
    # one-way asked for: the tiny reservoir is small enough that auto would go two-way
    "run": {"end_time_s": 0.2, "cores": 2, "write_interval_s": 0.1, "debris_coupling": "one-way"},
    "outputs": {"probe_interval_s": 0.01, "preview": False},
}
H0, WET = 0.16, 0.03


@pytest.fixture
def tiny_scene(tmp_path) -> Path:
    path = tmp_path / "tiny-oneway.yaml"
    path.write_text(yaml.safe_dump(TINY, sort_keys=False))
    return path


def _render(scene: Path, case: Path) -> ModelPlan:
    proc = run_cli("render", str(scene), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    return ModelPlan.from_json((case / "plan.json").read_text())


def _write_still_frames(case: Path, plan: ModelPlan, times, depth: float, skip=()) -> None:
    """Frames of still water ``depth`` deep (alpha 1 in cells whose centre is under it), the
    column's hole left out as OpenFOAM does; points in ``skip`` (indices of the flat list) left out too."""
    rec = plan.flow_record
    (c0, c1) = plan.column_box_m
    pts = np.array([(x, y, z) for x in rec.x_m for y in rec.y_m for z in rec.z_m])
    keep = ~np.all((pts >= c0) & (pts <= c1), axis=1)
    keep[list(skip)] = False
    pts = pts[keep]
    alpha = (pts[:, 2] < depth).astype(float)
    for t in times:
        folder = case / "postProcessing" / rec.name / f"{t:g}"
        folder.mkdir(parents=True, exist_ok=True)
        np.savetxt(folder / f"{rec.name}_alpha.water.xy", np.column_stack([pts, alpha]), delimiter="\t")
        np.savetxt(folder / f"{rec.name}_U.xy", np.column_stack([pts, np.zeros((len(pts), 3))]), delimiter="\t")


def test_reader_grids_still_water_and_deletes_the_raw_text(tiny_scene, tmp_path):
    case = tmp_path / "case"
    plan = _render(tiny_scene, case)
    faces = np.asarray(plan.flow_record.z_faces_m)
    depth = float(faces[2])  # a cell face: the integral is exact
    _write_still_frames(case, plan, [0.02 * k for k in range(1, 11)], depth)
    out = read_flow_record(case, delete_raw=True)
    field = out.field
    assert out.path == case / "results" / FLOW_RECORD_NPZ and out.path.is_file()
    assert out.frames == 11 and np.allclose(field.t_s, np.arange(11) * 0.02)
    assert out.points == plan.flow_record.points and out.raw_deleted
    assert not (case / "postProcessing" / "flowRecord").exists()
    assert out.bytes_total == out.path.stat().st_size and out.bytes_per_frame == out.bytes_total / 11
    assert np.allclose(field.eta_m[1:], depth)  # every recorded frame, the column's hole included
    # t = 0: the plan's water boxes (reservoir 0.16 m upstream of the gate, the 0.03 m wet bed)
    x = np.asarray(field.x_m)
    assert np.allclose(field.eta_m[0][x < 0], H0) and np.allclose(field.eta_m[0][x > 0.01], WET)
    assert float(np.abs(field.velocity_m_s).max()) == 0.0
    back = FlowField.load(out.path)
    assert np.array_equal(back.eta_m, field.eta_m) and back.velocity_m_s.dtype == np.float32


def test_a_missing_frame_or_end_is_named(tiny_scene, tmp_path):
    case = tmp_path / "case"
    plan = _render(tiny_scene, case)
    _write_still_frames(case, plan, [0.02, 0.04, 0.08, 0.1, 0.12, 0.14, 0.16, 0.18, 0.2], 0.05)
    with pytest.raises(FlowRecordError, match=r"1 frame\(s\) missing, first at 0.06 s"):
        read_flow_record(case)
    with pytest.raises(FlowRecordError, match=r"the record ends at 0.2 s, the run.s end time is 0.3 s; 1 frame\(s\)"):
        read_flow_record(case, end_time_s=0.3)


def test_a_point_lost_outside_the_column_is_named(tiny_scene, tmp_path):
    case = tmp_path / "case"
    plan = _render(tiny_scene, case)
    _write_still_frames(case, plan, [0.02 * k for k in range(1, 11)], 0.05, skip=[0])
    rec = plan.flow_record
    with pytest.raises(FlowRecordError, match=rf"1 point\(s\) outside the column's hole were not recorded, "
                                              rf"first \({rec.x_m[0]:.4g}, {rec.y_m[0]:.4g}, {rec.z_m[0]:.4g}\) m"):
        read_flow_record(case)


def test_a_two_way_case_records_no_flow(tmp_path):
    case = tmp_path / "case"
    proc = run_cli("render", str(ROOT / "tests/data/post/tiny-1debris.yaml"), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    with pytest.raises(FlowRecordError, match="two-way case: it records no flow"):
        read_flow_record(case)


def _cells(case: Path, time: str):
    """alpha.water, cell centres and volumes of a written time (postProcess writes C and V)."""
    from foamlib import FoamCase

    for func in ("writeCellCentres", "writeCellVolumes"):
        run_step(f"postProcess.{func}", ["postProcess", "-func", func, "-time", time], case, env=foam_env())
    fields = FoamCase(case)[float(time)]
    return (np.asarray(fields["alpha.water"].internal_field, float), np.asarray(fields["C"].internal_field, float),
            np.asarray(fields["V"].internal_field, float))


@pytest.mark.openfoam
def test_tiny_one_way_run_records_the_flow(tiny_scene, tmp_path, openfoam):
    case = tmp_path / "case"
    plan = render_and_run(tiny_scene, case)
    assert plan["solver"] == "interFoam" and plan["debris_coupling"] == "one-way" and plan["bodies"] == []
    assert not (case / "bodies").exists()
    post = run_cli("post", str(case))
    assert post.returncode == 0, post.stderr

    out = read_flow_record(case)
    field = out.field
    # one frame per 0.02 s, each within half a step (at most 0.01 s) of its multiple; the last at
    # the end time itself (the step that reaches it is the one whose midpoint passes 0.2 s)
    assert field.t_s.size == 11 and field.t_s[0] == 0.0
    assert np.all(np.abs(field.t_s - np.arange(11) * 0.02) <= 0.005 + 1e-9)
    assert field.t_s[-1] == pytest.approx(0.2, abs=1e-9) and field.meta["last_frame_held_s"] == 0.0
    assert out.bytes_per_frame < 0.2 * out.raw_bytes / (out.frames - 1)  # the .npz is far smaller than the text
    x, eta = np.asarray(field.x_m), field.eta_m
    # the reservoir: the impoundment at t = 0 and, at its upstream end, at the first recorded frame
    # (the negative wave, at sqrt(g h0) = 1.25 m/s, has gone 2.5 cm upstream of the gate by 0.02 s)
    assert np.all(np.abs(eta[0][x < 0] - H0) < 2e-3)
    assert np.all(np.abs(eta[1][0] - H0) < 2e-3)
    # the still wet bed where the bore has not arrived (it reaches about 0.45 m by 0.2 s)
    ahead = x > 0.8
    assert np.all(np.abs(eta[:, ahead] - WET) < 2e-3)
    assert np.abs(eta[-1][x < 0.3] - WET).max() > 0.02  # and the bore has come

    # each recorded column is its cells' water, sum(alpha V) / A, exactly (t = 0.2 s is a written time)
    alpha, centres, volumes = _cells(case, "0.2")
    rec = ModelPlan.from_dict(plan).flow_record
    top = rec.z_faces_m[-1]
    cx, cy = np.unique(np.round(centres[:, 0], 9)), np.unique(np.round(centres[:, 1], 9))
    worst = 0.0
    for i, xi in enumerate(field.x_m):
        ix = cx[np.argmin(np.abs(cx - xi))]
        for j, yj in enumerate(field.y_m):
            iy = cy[np.argmin(np.abs(cy - yj))]
            col = (np.abs(centres[:, 0] - ix) < 1e-6) & (np.abs(centres[:, 1] - iy) < 1e-6)
            if col.sum() < len(rec.z_m):  # the column's hole
                continue
            area = volumes[col].sum() / top
            worst = max(worst, abs((alpha[col] * volumes[col]).sum() / area - (eta[-1, i, j] - field.bed_z_m)))
    assert worst < 1e-6

    # the region's water: eta integrated over the record against the cells whose centres lie in it
    inside = (centres[:, 0] >= x[0]) & (centres[:, 0] <= x[-1])
    cells_water = float((alpha * volumes)[inside].sum())
    xs, ys = np.linspace(x[0], x[-1], 801), np.linspace(field.y_m[0], field.y_m[-1], 201)
    grid_x, grid_y = np.meshgrid(xs, ys, indexing="ij")
    depth = field.surface(grid_x, grid_y, 0.2) - field.bed_z_m
    width = 0.4  # the record's y span is the width less two hairs
    record_water = float(np.trapezoid(np.trapezoid(depth, ys, axis=1), xs)) * width / (ys[-1] - ys[0])
    assert record_water == pytest.approx(cells_water, rel=0.02)


def test_with_a_sill_the_record_starts_at_the_downstream_bed_and_the_gate():
    """A sill puts the reservoir's floor below the downstream bed: the background's grid reaches under
    z = 0 at the reservoir alone, so a record from the reservoir's floor would ask for points in the
    solid under the flume (each one lost, and the conversion refused). With a sill the record's
    cells start at the downstream bed and its region at the gate."""
    from orchestrator.plan.planner import load_and_plan
    from orchestrator.plan.grading import cell_edges

    sets = ["reservoir.sill_height_m=0.05", "reservoir.depth_m=0.35", "run.debris_coupling=one-way"]
    _, plan = load_and_plan(ROOT / "cases" / "1debris.yaml", sets)
    record = plan.flow_record
    assert min(cell_edges(plan.background.z)) == pytest.approx(-0.05)  # the reservoir's floor
    assert record.z_faces_m[0] == pytest.approx(0.0, abs=1e-9) and min(record.z_m) > 0.0
    assert record.x_m[0] >= 0.0
    _, flat = load_and_plan(ROOT / "cases" / "1debris.yaml", ["run.debris_coupling=one-way"])
    assert flat.flow_record.z_faces_m[0] == pytest.approx(0.0, abs=1e-9)
