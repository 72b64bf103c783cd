"""The one-way path end to end with real OpenFOAM: `debrisfoam case` on a tiny one-way scene runs
interFoam without the body, records the flow, carries the container through the record on
MuJoCo, and leaves the results a coupled run leaves (contacts.json, pulses, results/impacts.csv,
bodies.csv, report), so post-processing reads both paths alike."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pandas as pd
import pytest

from analytical.added_mass import box_added_mass
from orchestrator.scene.scenefile import load_scene
from orchestrator.transport.flow import FlowField
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"
LAUNCH_M_S = 0.8
#: from the container's nose (x = 1.0 + 0.075) to the column's face (1.2 - 0.05)
GAP_M = 0.075


@pytest.fixture(scope="module")
def one_way_case(tmp_path_factory):
    case = tmp_path_factory.mktemp("oneway") / "case"
    proc = run_cli("case", str(SCENE), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    return case, proc


@pytest.mark.openfoam
def test_a_one_way_case_runs_the_flow_without_the_body_and_records_it(one_way_case, openfoam):
    case, _ = one_way_case
    plan = json.loads((case / "plan.json").read_text())
    assert (plan["debris_coupling"], plan["solver"], plan["bodies"]) == ("one-way", "interFoam", [])
    assert not (case / "constant" / "dynamicMeshDict").exists()
    run = json.loads((case / "run.json").read_text())
    assert run["status"] == "finished"
    transport = run["transport"]
    assert transport["engine"] == "mujoco" and transport["bodies"] == 1 and transport["steps"] > 0
    assert run["transport_wall_s"] == pytest.approx(transport["wall_s"] + transport["pulse_wall_s"], abs=2e-3)
    assert (case / transport["flow_record"]).is_file() and transport["flow_record_bytes"] > 0


@pytest.mark.openfoam
def test_the_container_strikes_the_column_with_the_coupled_paths_contact_law(one_way_case, openfoam):
    case, _ = one_way_case
    events = json.loads((case / "contacts.json").read_text())
    strikes = [e for e in events if e["type"] == "impact"]
    assert [e["kind"] for e in strikes][:1] == ["column"]
    impacts = pd.read_csv(case / "results" / "impacts.csv")
    first = impacts.iloc[0]
    # launched at U = 0.8 m/s through still water (the bore is still upstream), slowed by quadratic
    # drag: (m + m_a) dv/dt = -0.5 rho C_d A v^2 gives s = U tau ln(1 + t / tau), v = U / (1 + t / tau),
    # tau = (m + m_a) / (0.5 rho C_d A U), A = width x draft, m_a the container's own surge added mass
    scene = load_scene(SCENE)
    body = scene.debris[0]
    rho, (_, width, _) = scene.fluids.water_density_kg_m3, body.size_m
    draft = body.mass_kg / (rho * body.size_m[0] * width)
    inertia = body.mass_kg + box_added_mass(body.size_m, body.mass_kg, rho).masses_kg[0]
    tau = inertia / (0.5 * rho * scene.transport.drag_coefficient * width * draft * LAUNCH_M_S)
    arrival = tau * math.expm1(GAP_M / (LAUNCH_M_S * tau))
    assert first["time_s"] == pytest.approx(arrival, rel=0.1)
    assert first["impact_velocity_m_s"] == pytest.approx(LAUNCH_M_S / (1 + arrival / tau), rel=0.1)
    # the pulse is the contact law's in series with the column's MDOF model at that strike: the
    # impulse the column takes is the normal momentum body and water lose, (m + m_a,n) dv_n
    event = next(e for e in strikes if e["kind"] == "column")
    assert event["added_mass_along_normal_kg"] > 0.0  # afloat: it carries water into the strike
    carried = body.mass_kg + event["added_mass_along_normal_kg"]
    expected = carried * (event["normal_velocity_out_m_s"] - event["normal_velocity_in_m_s"])
    assert event["impulse_Ns"] == pytest.approx(expected, rel=0.02)
    assert first["impulse_Ns"] == pytest.approx(event["impulse_Ns"], rel=1e-9)
    assert (case / first["force_history"]).is_file()
    # its phase: the strike's time less the record's front arrival 1 cm upstream of the face, read
    # here from the record itself; launched ahead of the bore, this body strikes before the front
    # reaches the face within the 0.2 s record, so the phase is empty (null in contacts.json)
    record = FlowField.load(case / "results" / "flow_record.npz")
    col = scene.column
    front = record.front_arrival_s(col.x_m - col.size_x_m / 2 - 0.01, col.y_m)
    assert math.isnan(front) and math.isnan(first["time_since_front_s"]) and event["time_since_front_s"] is None


@pytest.mark.openfoam
def test_post_processing_reads_the_one_way_results_as_a_coupled_runs(one_way_case, openfoam):
    case, _ = one_way_case
    tracks = pd.read_csv(case / "results" / "bodies.csv")
    start = tracks.sort_values("time_s").iloc[0]
    assert start["body"] == "debris1" and start["x_m"] == pytest.approx(1.0, abs=1e-6)
    assert tracks["time_s"].max() == pytest.approx(0.2, abs=0.011)
    summary = json.loads((case / "results" / "summary.json").read_text())
    assert summary["impacts"]["first"]["other"] == "column"
    assert summary["impacts"]["first"]["peak_force_N"] > 0
    for name in ("report.md", "tracks.png", "impacts.png"):
        assert (case / "results" / name).is_file(), name


@pytest.mark.openfoam
def test_running_a_finished_one_way_case_again_does_not_carry_the_bodies_again(one_way_case, openfoam):
    case, _ = one_way_case
    before = json.loads((case / "run.json").read_text())["transport"]
    proc = run_cli("case", str(SCENE), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    assert "transport:" not in proc.stdout
    assert json.loads((case / "run.json").read_text())["transport"] == before


@pytest.mark.openfoam
def test_a_finished_case_carried_with_another_contact_law_is_carried_again(one_way_case, openfoam):
    """run.json keeps the contact laws the bodies were carried with; when the tool's law is not
    that one (the shipped law recalibrated), running the case again carries the bodies again
    through the same flow record, and says so."""
    from analytical.contact_law import CONTAINER

    case, _ = one_way_case
    run = json.loads((case / "run.json").read_text())
    assert run["transport"]["contact_laws"]["debris1"]["stiffness_N_m"] == CONTAINER.stiffness_N_m
    run["transport"]["contact_laws"]["debris1"]["stiffness_N_m"] = 7.59e4
    (case / "run.json").write_text(json.dumps(run))
    proc = run_cli("case", str(SCENE), "-o", str(case))
    assert proc.returncode == 0, proc.stderr
    assert "carried again" in proc.stdout and "transport:" in proc.stdout
    again = json.loads((case / "run.json").read_text())["transport"]
    assert again["contact_laws"]["debris1"]["stiffness_N_m"] == CONTAINER.stiffness_N_m
    assert again["flow_record"] == run["transport"]["flow_record"]


def test_the_scenes_transport_section_sets_the_forcing():
    """transport.* reaches the engine's hydrodynamic coefficients; the defaults are the engine's."""
    from orchestrator.transport.case_transport import scene_settings
    from orchestrator.transport.engine import TransportSettings

    default = scene_settings(load_scene(SCENE))
    assert default.hydro == TransportSettings().hydro
    custom = scene_settings(load_scene(SCENE, ["transport.drag_coefficient=0", "transport.added_mass_coefficient=0.5",
                                               "transport.sub_volumes=[3, 2, 2]"]))
    assert (custom.hydro.drag_coefficient, custom.hydro.added_mass_coefficient, custom.hydro.sub_volumes) == (
        0.0, 0.5, (3, 2, 2))


def test_a_bad_transport_coefficient_is_refused_naming_the_field():
    proc = run_cli("validate", str(SCENE), "--set", "transport.drag_coefficient=-1")
    assert proc.returncode == 2 and "transport.drag_coefficient" in proc.stderr


def test_the_record_ends_are_walls_only_where_the_flume_has_them():
    """The study's scene: the record stops at 6.2 m of a flume that runs on to its free outfall
    at 8.45 m: both ends open (the upstream one stops short of the reservoir's back wall). A record
    reaching the closed back wall keeps it as a wall; a closed downstream end reached is a wall."""
    from orchestrator.transport.case_transport import open_record_ends

    scene = load_scene(ROOT / "cases" / "1debris.yaml")
    back, end = -scene.reservoir.length_m, scene.flume.length_m - scene.reservoir.length_m
    assert open_record_ends(scene, (-2.0, 6.2), 0.04) == (True, True)
    assert open_record_ends(scene, (back + 0.02, end - 0.02), 0.04) == (False, True)  # outfall: open
    closed = load_scene(ROOT / "cases" / "1debris.yaml", ["flume.downstream_end=closed"])
    assert open_record_ends(closed, (back + 0.02, end - 0.02), 0.04) == (False, False)
    assert open_record_ends(closed, (back + 0.02, 6.2), 0.04) == (False, True)


def test_a_changed_transport_section_carries_the_bodies_again_through_the_same_flow(tmp_path):
    """A rendered one-way case asked for again with other transport settings is the same flow:
    it is resumed, its scene.yaml takes the new transport section and its transport record is
    forgotten (so the bodies are carried again); another flow setting is a different case."""
    from analytical.errors import InputError
    from orchestrator.case.folder import CaseFolder
    from orchestrator.pipeline import prepare_case as prepare_planned
    from orchestrator.plan.planner import load_and_plan

    def prepare_case(scene_path, out, sets=()):
        return prepare_planned(*load_and_plan(scene_path, sets), scene_path, out, sets)

    case, rendered = prepare_case(SCENE, tmp_path / "case")
    assert rendered
    folder = CaseFolder(case)
    folder.write_run_record({"transport": {"wall_s": 1.0}, "transport_wall_s": 1.0, "status": "finished"})
    again, rendered = prepare_case(SCENE, case, ["transport.drag_coefficient=2.5", "transport.munk_moment=false"])
    assert again == case and not rendered
    scene = load_scene(folder.scene_path)
    assert (scene.transport.drag_coefficient, scene.transport.munk_moment) == (2.5, False)
    assert "transport" not in folder.run_record() and folder.run_record()["status"] == "finished"
    with pytest.raises(InputError, match="different case"):
        prepare_case(SCENE, case, ["reservoir.depth_m=0.3"])
