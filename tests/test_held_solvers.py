"""The bodies' motion solvers set aside while every body is held still (held.hold_solvers).

v1912 rebuilds the overset addressing at every step while any motion solver runs; with none it
builds it once (docs/openfoam-notes.md, "Cost"). These tests check the dictionary's round trip on a
rendered two-way case (no OpenFOAM run), that every reader and editor of the bodies finds them while
they are set aside, and the motion files a time written meanwhile is given. The runs themselves:
tests/test_still_water.py (a resting container held throughout: addressing built once a segment),
tests/test_float_off.py (held, then freed: the solvers come back and move it).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import ROOT, run_cli
from orchestrator.case import bodystate
from orchestrator.run import held
from orchestrator.run import body_policy

SCENE = ROOT / "tests" / "data" / "scenes" / "three-debris-two-way.yaml"


@pytest.fixture(scope="module")
def rendered(tmp_path_factory) -> Path:
    case = tmp_path_factory.mktemp("held") / "three"
    proc = run_cli("render", str(SCENE), "-o", str(case))
    assert proc.returncode == 0, proc.stderr[-2000:]
    return case


def test_the_solvers_go_aside_and_come_back_with_every_body_and_its_edits(rendered, tmp_path):
    case = tmp_path / "case"
    (case / "constant").mkdir(parents=True)
    source = rendered / bodystate.DYNAMIC_MESH_DICT
    (case / bodystate.DYNAMIC_MESH_DICT).write_text(source.read_text())
    before = bodystate.read_mesh_poses(case)
    names = [b.name for b in before]
    assert len(names) == 3 and not held.solvers_held(case)

    assert body_policy.stick_bodies(case, names[:2]) == names[:2]
    assert body_policy.still_bodies(case) == set(names[:2])  # one body still free to move
    assert held.hold_solvers(case, True) and held.solvers_held(case)
    assert not held.hold_solvers(case, True)  # already aside
    text = (case / bodystate.DYNAMIC_MESH_DICT).read_text()
    assert "heldSolvers" in text
    # every reader and editor finds the bodies while their solvers are aside
    assert bodystate.read_mesh_poses(case) == before
    assert body_policy.stick_bodies(case, [names[2]]) == [names[2]]
    assert body_policy.still_bodies(case) == set(names)
    assert held.hold_solvers(case, False) and not held.solvers_held(case)
    assert body_policy.stuck_bodies(case) == set(names)  # the edit made while aside is kept
    assert bodystate.read_mesh_poses(case) == before


def test_a_case_without_bodies_or_dictionary_is_left_alone(tmp_path):
    assert not held.hold_solvers(tmp_path, True)
    assert not held.solvers_held(tmp_path)


def test_times_written_while_held_get_the_motion_files_of_the_time_before(tmp_path):
    proc = tmp_path / "processor0"
    (proc / "0").mkdir(parents=True)
    (proc / "0" / "pointDisplacement").write_text("displacement at 0")
    (proc / "0.05").mkdir()
    (proc / "0.1" / "polyMesh").mkdir(parents=True)
    (proc / "0.1" / "pointDisplacement").write_text("displacement at 0.1")
    (proc / "0.1" / "polyMesh" / "points").write_text("points at 0.1")
    (proc / "0.2").mkdir()
    (proc / "constant").mkdir()
    written = held.fill_motion_files(tmp_path)
    assert (proc / "0.05" / "pointDisplacement").read_text() == "displacement at 0"
    assert not (proc / "0.05" / "polyMesh").exists()  # the mesh had not moved yet: constant's points
    assert (proc / "0.2" / "pointDisplacement").read_text() == "displacement at 0.1"
    assert (proc / "0.2" / "polyMesh" / "points").read_text() == "points at 0.1"
    assert len(written) == 3 and not held.fill_motion_files(tmp_path)


def test_the_states_of_the_latest_restart_at_or_before_a_time(tmp_path):
    state = bodystate.BodyState("debris1", 0.0, (1.0, 0.0, 0.03), velocity_m_s=(0.2, 0.0, 0.0))
    bodystate.record_states(tmp_path, "0", [state], "initial")
    bodystate.record_states(tmp_path, "0.1", [held.still_state(state)], "log")
    states, name = held.recorded_before(tmp_path, "0.15")
    assert name == "0.1" and states[0].velocity_m_s == (0.0, 0.0, 0.0)
    assert held.recorded_before(tmp_path, "0.1")[1] == "0.1"
    assert held.recorded_before(tmp_path, "0.05")[1] == "0"
