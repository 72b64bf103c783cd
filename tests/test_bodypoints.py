"""The body meshes' points follow a pose the runner sets at a restart (orchestrator.run.bodypoints),
on a hand-made merged mesh: a background of four points and a body of three, decomposed on two
ranks the way decomposePar writes it. The end-to-end check with the solver is
tests/test_still_water.py (a container set 2 mm aside between segments)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from orchestrator.run.bodypoints import TOLERANCE_M, BodyPoints, read_points, write_points
from orchestrator.case.bodystate import BodyState
from orchestrator.core.errors import InputError

HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    object      {obj};
}}
// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //

"""
DYNAMIC_MESH_DICT = """FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      dynamicMeshDict;
}
dynamicFvMesh dynamicOversetFvMesh;
solvers
{
    debris1
    {
        motionSolver sixDoFRigidBodyMotion;
        cellZone debris1;
        sixDoFRigidBodyMotionCoeffs
        {
            mass 0.236;
            centreOfMass (1 0 0.05);
            momentOfInertia (1e-4 6e-4 6e-4);
            orientation (1 0 0 0 1 0 0 0 1);
        }
    }
}
"""
BACKGROUND = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 1.0, 0.2]])
BODY = np.array([[0.9, -0.03, 0.02], [1.1, -0.03, 0.02], [1.1, 0.03, 0.08]])


def _vectors(path: Path, points: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = "\n".join(f"({x:.10g} {y:.10g} {z:.10g})" for x, y, z in points)
    path.write_text(HEADER.format(cls="vectorField", obj="points") + f"{len(points)}\n(\n{rows}\n)\n")


def _labels(path: Path, labels) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(HEADER.format(cls="labelList", obj="pointProcAddressing")
                    + f"{len(labels)}\n(\n" + "\n".join(map(str, labels)) + "\n)\n")


@pytest.fixture
def case(tmp_path) -> Path:
    """The merged mesh (background, then the body, as mergeMeshes appends it) on two ranks that
    share the body's first point; every rank has written time 0.5 with the body where it started."""
    merged = np.vstack([BACKGROUND, BODY])
    _vectors(tmp_path / "constant" / "polyMesh" / "points", merged)
    _vectors(tmp_path / "bodies" / "debris1" / "constant" / "polyMesh" / "points", BODY)
    (tmp_path / "constant" / "dynamicMeshDict").write_text(DYNAMIC_MESH_DICT)
    for rank, labels in enumerate(([0, 1, 4, 5], [2, 3, 4, 6])):
        proc = tmp_path / f"processor{rank}"
        _labels(proc / "constant" / "polyMesh" / "pointProcAddressing", labels)
        _vectors(proc / "constant" / "polyMesh" / "points", merged[labels])
        _vectors(proc / "0.5" / "polyMesh" / "points", merged[labels])
    return tmp_path


def _moved(angle_deg: float, shift) -> BodyState:
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    return BodyState("debris1", 0.5, tuple(np.add((1.0, 0.0, 0.05), shift)), (c, -s, 0, s, c, 0, 0, 0, 1))


def test_points_round_trip_through_the_file_keeping_its_header(tmp_path):
    path = tmp_path / "points"
    _vectors(path, BODY)
    write_points(path, BODY + 1e-11)
    assert read_points(path) == pytest.approx(BODY + 1e-11, abs=1e-12)
    assert "class       vectorField;" in path.read_text()


def test_a_turned_and_shifted_body_takes_its_points_along_and_nothing_else(case):
    points = BodyPoints.for_case(case)
    state = _moved(30.0, (0.002, -0.001, 0.0))
    assert points.follow("0.5", [state]) == ["debris1"]
    c, s = math.cos(math.radians(30.0)), math.sin(math.radians(30.0))
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    expected = (BODY - (1.0, 0.0, 0.05)) @ turn.T + (1.002, -0.001, 0.05)  # c + R (p0 - c0)
    rank0 = read_points(case / "processor0" / "0.5" / "polyMesh" / "points")
    rank1 = read_points(case / "processor1" / "0.5" / "polyMesh" / "points")
    assert rank0[:2] == pytest.approx(BACKGROUND[:2], abs=0) and rank1[:2] == pytest.approx(BACKGROUND[2:], abs=0)
    assert rank0[2:] == pytest.approx(expected[:2], abs=1e-11)
    assert rank1[2:] == pytest.approx(expected[[0, 2]], abs=1e-11)  # the shared point moved alike on both
    # already where its pose puts it: nothing is written again
    assert points.follow("0.5", [state]) == []
    # a pose within the written points' rounding is left alone
    assert points.follow("0.5", [_moved(30.0, (0.002 + 0.5 * TOLERANCE_M, -0.001, 0.0))]) == []


def test_a_case_whose_merged_mesh_lacks_a_body_says_which(case):
    _vectors(case / "bodies" / "debris1" / "constant" / "polyMesh" / "points", BODY + 0.5)
    with pytest.raises(InputError, match="points: bodies/debris1: its points are not in the merged mesh"):
        BodyPoints.for_case(case)


def test_a_serial_case_moves_the_points_it_wrote(case):
    import shutil

    for proc in ("processor0", "processor1"):
        shutil.rmtree(case / proc)
    _vectors(case / "0.5" / "polyMesh" / "points", np.vstack([BACKGROUND, BODY]))
    assert BodyPoints.for_case(case).follow("0.5", [_moved(0.0, (0.0, 0.003, 0.0))]) == ["debris1"]
    written = read_points(case / "0.5" / "polyMesh" / "points")
    assert written == pytest.approx(np.vstack([BACKGROUND, BODY + (0.0, 0.003, 0.0)]), abs=1e-12)
