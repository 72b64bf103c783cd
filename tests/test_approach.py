"""The approach study's pieces: the refinement box (orchestrator/plan/refine.py), the force budget
(orchestrator/transport/budget.py, a conservation check on real MuJoCo) and the study's flow
variants (orchestrator/studies/approach.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from analytical.hydrodynamics import HydroCoefficients, hydro_loads, sub_volumes
from orchestrator.core.errors import InputError
from orchestrator.plan.grading import cell_edges
from orchestrator.plan.grid import Segment
from orchestrator.plan.planner import plan_case
from orchestrator.plan.refine import record_axis, refine_axis, transition_m
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.approach import ApproachFlow, face_distance, thinned
from orchestrator.transport.budget import BUDGET_TERMS, force_budget
from orchestrator.transport.engine import TransportSettings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.transport.mujoco_model import FlumeBounds
from tests.conftest import debris

CASE = Path(__file__).resolve().parents[1] / "cases" / "1debris.yaml"
BOX = "mesh.refine_box_m=[4.3,5.05,-0.16,0.16,0,0.24]"


def _sizes(segs):
    edges = cell_edges(tuple(segs))
    return edges, np.diff(edges)


def test_refine_axis_puts_fine_cells_in_the_box_grows_by_the_ratio_and_keeps_every_plane():
    """Cells of 0.02 m in 1.0..1.5, at most x 1.15 from cell to cell, back to 0.04 m; the planes
    0.0 (hard) and 1.26 (inside the box) kept."""
    segs = (Segment(-1.0, 0.0, 25), Segment(0.0, 1.26, 32), Segment(1.26, 3.0, 44))
    out = refine_axis(segs, (1.0, 1.5), (-1.0, 3.0), 0.04, 0.02, 1.15)
    edges, sizes = _sizes(out)
    planes = [out[0].start_m] + [s.end_m for s in out]
    assert 0.0 in planes and 1.26 in planes and planes[0] == -1.0 and planes[-1] == 3.0
    mid = 0.5 * (edges[:-1] + edges[1:])
    assert np.all(sizes[(mid > 1.0) & (mid < 1.5)] <= 0.02 + 1e-9)
    assert np.max(sizes) <= 0.04 + 1e-9
    assert np.all(sizes[1:] / sizes[:-1] <= 1.15 + 0.03) and np.all(sizes[:-1] / sizes[1:] <= 1.15 + 0.03)
    far = (mid < 1.0 - transition_m(0.04, 0.02, 1.15) - 0.05) | (mid > 1.5 + transition_m(0.04, 0.02, 1.15) + 0.05)
    assert np.all((sizes[far] > 0.035) & (sizes[far] <= 0.04 + 1e-9))


def test_refine_axis_refuses_a_box_whose_transitions_leave_the_fine_region():
    segs = (Segment(0.0, 2.0, 50),)
    with pytest.raises(InputError, match="mesh.refine_box_m"):
        refine_axis(segs, (1.5, 1.7), (0.0, 1.8), 0.04, 0.02, 1.15)
    with pytest.raises(InputError, match="mesh.refine_cell_size_m"):
        refine_axis(segs, (0.5, 0.9), (0.0, 2.0), 0.04, 0.05, 1.15)


def test_record_axis_takes_the_cell_centres_inside_the_span_only():
    base = np.linspace(0.0, 1.0, 11)
    centres = np.arange(0.41, 0.6, 0.02)
    out = record_axis(base, centres, (0.4, 0.6))
    assert np.all(np.diff(out) > 0)
    assert set(np.round(out[(out > 0.4) & (out < 0.6)], 6)) == set(np.round(centres, 6))
    assert {0.0, 0.3, 0.7, 1.0} <= set(np.round(out, 6))


def test_the_1debris_plan_with_a_2cm_box_refines_the_mesh_and_the_record_there_and_nothing_without():
    plain = plan_case(load_scene(CASE, ["run.end_time_s=2.5", "mesh.column_approach_cell_size_m=null"]))
    boxed = plan_case(load_scene(CASE, ["run.end_time_s=2.5", BOX, "mesh.refine_cell_size_m=0.02",
                                        "mesh.column_approach_cell_size_m=null"]))
    assert plain.background.cell_count() < boxed.background.cell_count() < 2.5 * plain.background.cell_count()
    x = np.array(boxed.flow_record.x_m)
    inside = x[(x > 4.32) & (x < 5.03)]
    assert np.allclose(np.diff(inside), 0.02, rtol=0.07)
    assert np.allclose(np.diff(np.array(plain.flow_record.x_m)), 0.0402, rtol=0.01)
    assert "refine_box" in boxed.reasons and "refine_box" not in plain.reasons


def test_the_column_approach_box_is_the_1debris_box_and_follows_the_column():
    """mesh.column_approach_cell_size_m puts the box the approach study measured (x 4.3..5.05,
    y -0.16..0.16, z 0..0.24 m) at the 1-debris column, moves with the column and scales with the scene."""
    from orchestrator.plan.refine import refinement
    scene = load_scene(CASE)
    box, cell, field = refinement(scene)
    assert box == pytest.approx((4.3, 5.05, -0.16, 0.16, 0.0, 0.24)) and cell == 0.03
    assert field == "mesh.column_approach_cell_size_m"
    explicit = load_scene(CASE, [BOX, "mesh.refine_cell_size_m=0.03", "mesh.column_approach_cell_size_m=null"])
    assert plan_case(scene).background.cell_count() == plan_case(explicit).background.cell_count()
    moved, _, _ = refinement(load_scene(CASE, ["column.x_m=4.0", "column.y_m=0.2"]))
    assert moved == pytest.approx((3.3, 4.05, 0.04, 0.36, 0.0, 0.24))
    proto, cell, _ = refinement(load_scene(CASE.parent / "prototype-1debris.yaml"))
    assert proto == pytest.approx(tuple(40 * v for v in box)) and cell == pytest.approx(40 * 0.03)


def test_a_column_approach_size_no_finer_than_the_mesh_is_no_box_with_a_warning_and_two_boxes_are_bad_input():
    from orchestrator.plan.refine import refinement
    from orchestrator.scene.validation import plausibility_warnings
    coarse = load_scene(CASE, ["mesh.cell_size_m=0.03"])
    assert refinement(coarse) is None and "refine_box" not in plan_case(coarse).reasons
    assert any("mesh.column_approach_cell_size_m" in w for w in plausibility_warnings(coarse))
    assert not any("column_approach" in w for w in plausibility_warnings(load_scene(CASE)))
    columnless = load_scene(CASE, ["column=null", "gauges=[]"])  # an inherited box with no column: no box, a warning
    assert refinement(columnless) is None and any("no column" in w for w in plausibility_warnings(columnless))
    with pytest.raises(InputError, match="mesh.column_approach_cell_size_m"):
        load_scene(CASE, [BOX, "mesh.refine_cell_size_m=0.03"])


def test_a_refine_box_without_its_cell_size_is_bad_input_naming_the_field():
    with pytest.raises(InputError, match="mesh.refine_cell_size_m"):
        load_scene(CASE, [BOX, "mesh.column_approach_cell_size_m=null"])


def _floating_in_a_current():
    flow = FlowField.uniform_current(0.1, 0.5, x_m=(-1.0, 3.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0))
    body = debris("plate", centre_m=(-0.8, 0.0, 0.1), size_m=(0.2, 0.2, 0.02), mass_kg=0.4)
    settings = TransportSettings(output_interval_s=0.002)
    run = run_transport([body], FlumeBounds((-1.0, 3.0), (-0.5, 0.5)), 1.0, flow, settings=settings)
    return flow, body, settings, run.track("plate")


def test_the_budget_of_a_box_drifting_in_a_current_balances_its_acceleration():
    """No contact afloat: what the budget leaves over ((m + m_a) a less every force) stays under
    3 % of the drag that drives the body, and drag and buoyancy carry the motion."""
    flow, body, settings, track = _floating_in_a_current()
    budget = force_budget(track[track["time_s"] > 0.05], flow, body.size_m, body.mass_kg, settings.hydro)
    assert set(f"{t}_x" for t in BUDGET_TERMS) <= set(budget.columns)
    drag = budget["drag_x"].abs().max()
    assert drag > 0.01
    assert budget["contact_x"].abs().max() < 0.03 * drag
    assert np.median(np.abs(budget["inertia_x"] - budget["drag_x"])) < 0.03 * drag
    assert budget["buoyancy_z"].median() == pytest.approx(0.4 * 9.81, rel=0.02)


def test_the_budget_terms_add_up_to_the_engine_force_function():
    """weight + buoyancy + Froude-Krylov + added mass + drag = hydro_loads' force - m g, in a flow that
    accelerates (Ritter's dam break), to rounding."""
    flow = FlowField.ritter(0.4, x_m=np.linspace(-1.0, 3.0, 81), t_s=np.linspace(0.0, 2.0, 41))
    rot = np.eye(3)
    track = {"time_s": [0.4, 0.5, 0.6], "x_m": [0.3] * 3, "y_m": [0.0] * 3, "z_m": [0.03] * 3,
             "u_m_s": [0.5, 0.6, 0.7], "v_m_s": [0.0] * 3, "w_m_s": [0.0] * 3}
    track.update({f"omega_{a}_rad_s": [0.0] * 3 for a in "xyz"})
    track.update({f"q_{a}{b}": [rot["xyz".index(a), "xyz".index(b)]] * 3 for a in "xyz" for b in "xyz"})
    import pandas as pd
    coeffs = HydroCoefficients()
    budget = force_budget(pd.DataFrame(track), flow, (0.15, 0.06, 0.06), 0.236, coeffs)
    pts = np.array([0.3, 0.0, 0.03]) + sub_volumes((0.15, 0.06, 0.06)).centres_m
    eta = flow.surface(pts[:, 0], pts[:, 1], 0.5)
    s = flow.sample(pts, 0.5, eta_m=eta)
    loads = hydro_loads([[0.3, 0, 0.03]], rot[None], [[0.6, 0, 0]], [[0, 0, 0]], [[0.15, 0.06, 0.06]], pts[None],
                        eta[None], s.velocity_m_s[None], s.material_acceleration_m_s2[None],
                        dataclasses.replace(coeffs, water_density_kg_m3=flow.water_density_kg_m3))
    forces = [t for t in BUDGET_TERMS if t not in ("contact", "inertia")]
    total = np.array([sum(budget[f"{t}_{a}"].iloc[0] for t in forces) for a in "xyz"])
    assert abs(loads.force_N[0, 0]) > 0.05  # the flow does push
    assert np.allclose(total, loads.force_N[0] - [0, 0, 0.236 * 9.81], atol=1e-9)
    assert budget["inertia_x"].iloc[0] > 0.236 * 1.0  # (m + m_a) a, a = 1 m/s^2


def test_thinned_keeps_the_frames_nearest_each_multiple():
    flow = FlowField.uniform_current(0.1, 0.5, t_s=np.arange(0.0, 1.0001, 0.005))
    half = thinned(flow, 50.0)
    assert np.allclose(np.diff(half.t_s), 0.02)
    assert half.t_s[0] == 0.0 and half.t_s[-1] == pytest.approx(1.0)


def test_approach_flow_samples_the_flow_upstream_of_the_face_near_the_column_only():
    flow = FlowField.ritter(0.4, x_m=np.linspace(-1.0, 3.0, 81), t_s=np.linspace(0.0, 2.0, 41))
    frozen = ApproachFlow(flow, 2.0, (-0.1, 0.1), 0.2)
    near = np.array([[1.95, 0.0, 0.02]])
    assert np.allclose(frozen.sample(near, 1.5).velocity_m_s, flow.sample([[1.8, 0.0, 0.02]], 1.5).velocity_m_s)
    aside = np.array([[1.95, 0.5, 0.02]])
    assert np.allclose(frozen.sample(aside, 1.5).velocity_m_s, flow.sample(aside, 1.5).velocity_m_s)
    assert frozen.t_s is flow.t_s


def test_the_engine_carries_a_body_through_an_approach_flow_on_the_moved_points():
    """The engine locates its points once and hands the location to `surface` and `sample`:
    through an ApproachFlow that location is the moved points' (Ritter's surface near the face is
    the one `reach` upstream), and a body carried through a frozen uniform current moves exactly as
    through the current itself."""
    ritter = FlowField.ritter(0.4, x_m=np.linspace(-1.0, 3.0, 81), t_s=np.linspace(0.0, 2.0, 41))
    frozen = ApproachFlow(ritter, 2.0, (-0.1, 0.1), 0.2)
    x, y = np.array([1.0, 1.95, 1.95]), np.array([0.0, 0.0, 0.5])
    moved = np.array([1.0, 1.8, 1.95])
    assert np.allclose(frozen.surface(x, y, 1.5, frozen.locate(x, y, 1.5)), ritter.surface(moved, y, 1.5))
    assert not np.allclose(ritter.surface(x, y, 1.5), ritter.surface(moved, y, 1.5))

    current = FlowField.uniform_current(0.1, 0.5, x_m=(-1.0, 3.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0))
    body = debris("plate", centre_m=(-0.8, 0.0, 0.1), size_m=(0.2, 0.2, 0.02), mass_kg=0.4)
    settings = TransportSettings(output_interval_s=0.01)
    bounds = FlumeBounds((-1.0, 3.0), (-0.5, 0.5))
    plain = run_transport([body], bounds, 1.0, current, settings=settings).track("plate")
    through = run_transport([body], bounds, 1.0, ApproachFlow(current, -0.55, (-0.1, 0.1), 0.15),
                            settings=settings).track("plate")
    assert plain["x_m"].iloc[-1] > -0.7  # it drifted into the frozen stretch (x > -0.7 m)
    assert np.allclose(through[["x_m", "u_m_s"]].to_numpy(), plain[["x_m", "u_m_s"]].to_numpy(), atol=1e-12)


def test_face_distance_is_the_gap_from_the_nose_of_a_yawed_box():
    import pandas as pd
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    row = {"x_m": [1.0]}
    row.update({f"q_{a}{b}": [rot["xyz".index(a), "xyz".index(b)]] for a in "xyz" for b in "xyz"})
    gap = face_distance(pd.DataFrame(row), (0.15, 0.06, 0.06), 1.2)
    assert gap[0] == pytest.approx(0.2 - (0.075 * c + 0.03 * s))


def test_the_approach_page_calls_the_strike_speed_converged_only_when_the_two_finest_cells_agree():
    """The page's verdict on the cell size near the column: converged when the two finest cell
    sizes' mean strike speeds differ by at most CONVERGED, named with the default's error."""
    import pandas as pd

    from orchestrator.studies.approach_report import CONVERGED, _resolution_findings

    def rows(speeds):
        return pd.DataFrame({"carry": [f"run{k} at 50 Hz" for k in range(len(speeds))],
                             "record_hz": [50.0] * len(speeds),
                             "cell_near_column_m": [0.04, 0.03, 0.02][:len(speeds)],
                             "speed_m_s": speeds})

    agreed = " ".join(_resolution_findings(rows([1.30, 1.60, 1.58])))
    assert "converged within 5 % at 3 cm" in agreed and "and 4 cm is -18 % off the finest" in agreed
    apart = " ".join(_resolution_findings(rows([1.30, 1.60, 1.60 * (1 + 2 * CONVERGED)])))
    assert "not converged" in apart


def test_a_coupled_run_is_read_as_a_carry_with_its_strike(tmp_path):
    """A two-way run's tables (bodies.csv, impacts.csv) become a carry: the nose's gap to the face
    from the track, the strike's total speed from its normal and tangential parts, the track cut
    at the strike; a run without tables is None."""
    import shutil

    import pandas as pd

    from orchestrator.studies.approach import coupled_run

    case = tmp_path / "two-way"
    (case / "results").mkdir(parents=True)
    shutil.copy(CASE, case / "scene.yaml")
    assert coupled_run(case, label="c", cell_m=0.04) is None
    scene = load_scene(CASE)
    x_face = scene.column.x_m - scene.column.size_x_m / 2
    t = np.arange(0.0, 1.0, 0.01)
    x = x_face - 0.6 - 0.075 + 0.6 * t  # the nose reaches the face at t = 1 s
    eye = {f"q_{a}{b}": float(a == b) for a in "xyz" for b in "xyz"}
    track = pd.DataFrame({"time_s": t, "body": "debris1", "x_m": x, "y_m": 0.0, "z_m": 0.05,
                          "speed_m_s": np.where(t > 0.835, 0.5, 0.6), "yaw_deg": 0.0, **eye})
    track.to_csv(case / "results" / "bodies.csv", index=False)
    pd.DataFrame({"time_s": [0.9], "body": ["debris1"], "kind": ["column"], "normal_velocity_in_m_s": [0.3],
                  "tangential_velocity_in_m_s": [0.4], "obliquity_deg": [53.1]}).to_csv(
        case / "results" / "impacts.csv", index=False)
    run = coupled_run(case, label="c", cell_m=0.04)
    assert run.forcing.startswith("two-way") and run.rate_hz == 100
    assert run.strike.speed_m_s == pytest.approx(0.5) and run.strike.time_s == pytest.approx(0.9)
    assert run.track["time_s"].max() <= 0.9
    assert run.track["gap_m"].iloc[0] == pytest.approx(0.6)
    assert run.strike.slowed_at_gap_m == pytest.approx(0.6 - 0.6 * 0.84)  # the first row 5 % slower


# --------------------------------------------------------------------------- the verbs: report approach, report forcing-variants

@pytest.fixture(scope="module")
def one_way_run(tmp_path_factory):
    """The tiny 1-debris scene rendered one-way, 0.3 s, with a 1 m/s current 0.1 m deep saved as its
    flow record (what `debrisfoam case` leaves in results/ once the flow has run)."""
    from orchestrator.cli import main

    case = tmp_path_factory.mktemp("approach") / "run"
    scene = Path(__file__).resolve().parent / "data" / "post" / "tiny-1debris" / "scene.yaml"
    assert main(["render", str(scene), "-o", str(case), "--set", "run.debris_coupling=one-way",
                 "--set", "run.end_time_s=0.3"]) == 0
    (case / "results").mkdir()
    FlowField.uniform_current(0.1, 1.0, x_m=np.linspace(-0.5, 2.4, 30), y_m=np.linspace(-0.2, 0.2, 9),
                              t_s=np.linspace(0.0, 0.3, 7)).save(case / "results" / "flow_record.npz")
    return case


def test_report_forcing_variants_writes_the_table_of_each_variant(one_way_run, tmp_path, monkeypatch, capsys):
    from orchestrator.cli import main
    from orchestrator.studies import forcing_variants

    monkeypatch.setattr(forcing_variants, "VARIANTS", forcing_variants.VARIANTS[-1:])  # the default alone: fast
    out = tmp_path / "variants.md"
    assert main(["report", "forcing-variants", str(one_way_run), "-o", str(out), "--json"]) == 0
    text = out.read_text()
    assert f"Written by `debrisfoam report forcing-variants {one_way_run}`" in text
    rows = [line for line in text.splitlines() if line.startswith("| along the flow + Munk (default) | 1.05 |")]
    assert len(rows) == len(forcing_variants.YAWS_DEG) and "none" not in rows[0]  # the current carries it to the column
    assert main(["report", "forcing-variants", str(one_way_run), "-o", str(out)]) == 2  # no --force
    assert "exists: give --force" in capsys.readouterr().err


def test_report_approach_writes_the_page_and_names_the_runs_it_lacks(one_way_run, tmp_path):
    from orchestrator.cli import main

    out = tmp_path / "approach"
    assert main(["report", "approach", str(one_way_run), "--runs", str(tmp_path / "none"), "--coupled",
                 "-o", str(out), "--json"]) == 0
    assert {p.name for p in out.iterdir()} == {"report.md", "approach.csv", "budget.csv", "speed_vs_gap.png",
                                               "budget.png"}
    page = (out / "report.md").read_text()
    assert "| default (" in page and "## Not run" in page and "`approach-2cm-box`" in page
