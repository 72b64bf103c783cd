"""Body mesh points that follow a pose the runner sets between segments.

When the runner moves a body between two solver segments (two bodies set apart, a body taken
out of an overlap or lifted out of the bed), it writes the new pose into dynamicMeshDict
(`bodystate.prepare_restart`). v1912 restarts from the points written at that time
(`<t>/polyMesh/points`), and its first step moves them to where the six-DoF solver puts the
body (the rigid transform of the mesh's points0 to the new pose): the whole correction becomes
mesh motion in one time step. Set 2.5 mm apart at steps of 4e-4 s, two pressed containers
moved at 6 m/s for that step; the walls' water followed (movingWallVelocity), its pressure
threw each body back at the other, and the next contact came three steps later, closing
faster every time (the 3-debris layouts two-way, docs/stability.md).

`BodyPoints.follow` writes each corrected body's points at the restart time where the new pose
puts them, so the first step moves the mesh only as far as the body moves in it. The points
of a body are found by the mesh's own bookkeeping: mergeMeshes appends each body mesh
(`bodies/<name>`) to the background's points, and decomposePar's pointProcAddressing maps a
processor's points to those. The transform is the one v1912's sixDoFRigidBodyMotion applies
(`transform`): ``c + R R0^T (p0 - c0)``, ``c0, R0`` the pose the mesh was built in
(initialCentreOfMass, initialOrientation), ``c, R`` the new centre of mass and orientation.

Units: m.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np

from orchestrator.case.bodystate import BodyState, read_mesh_poses
from orchestrator.case.folder import processor_dirs
from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic

__all__ = ["BodyPoints", "TOLERANCE_M", "read_points", "write_points"]

#: a body whose written points are further than this from its pose is moved (m): ten times the
#: rounding of points written at writePrecision 10, far below any correction the runner makes
TOLERANCE_M = 1e-7
_POINTS = Path("polyMesh") / "points"


def read_points(path: str | Path) -> np.ndarray:
    """A vectorField (polyMesh/points) as an (n, 3) array (foamlib reads it)."""
    from foamlib import FoamFile

    return np.asarray(FoamFile(path)[None], dtype=float).reshape(-1, 3)


def read_labels(path: str | Path) -> np.ndarray:
    """A labelList (pointProcAddressing) as an integer array (foamlib reads it)."""
    from foamlib import FoamFile

    return np.asarray(FoamFile(path)[None], dtype=np.int64)


def write_points(path: str | Path, points: np.ndarray) -> None:
    """Write `points` into the vectorField file `path`, keeping its FoamFile header (12 significant
    digits: finer than the solver's writePrecision 10). Written here rather than through foamlib,
    which takes about 2.5 s for a processor's 88,000 points, at every restart that moves a body."""
    path = Path(path)
    text = path.read_text()
    close = text.find("}", text.find("FoamFile"))
    if close < 0:
        raise InputError("FoamFile", "no FoamFile header: not an OpenFOAM points file", str(path))
    rows = "\n".join(f"({x:.12g} {y:.12g} {z:.12g})" for x, y, z in np.asarray(points, float))
    write_text_atomic(path, f"{text[:close + 1]}\n\n{len(points)}\n(\n{rows}\n)\n\n")


@dataclass
class _Part:
    """One mesh part (the serial case or a processor): where its points live and which are whose."""

    root: Path
    points0: np.ndarray  # constant/polyMesh/points: the pose each mesh was built in
    owners: dict[str, np.ndarray]  # body -> indices of its points in this part


class BodyPoints:
    """The body meshes' points of a case, found once (`for_case`), moved at restarts (`follow`)."""

    def __init__(self, case: str | Path, parts: list[_Part]):
        self.case = Path(case)
        self.parts = parts

    @classmethod
    def for_case(cls, case: str | Path) -> "BodyPoints":
        """Find each body's points in the merged mesh (its `bodies/<name>` mesh appended by
        mergeMeshes) and in every processor's (pointProcAddressing)."""
        case = Path(case)
        merged = read_points(case / "constant" / _POINTS)
        ranges = {}
        for pose in read_mesh_poses(case):
            own = read_points(case / "bodies" / pose.name / "constant" / _POINTS)
            starts = np.flatnonzero(np.all(merged == own[0], axis=1))
            start = next((int(s) for s in starts if s + len(own) <= len(merged)
                          and np.array_equal(merged[s:s + len(own)], own)), None)
            if start is None:
                raise InputError(f"bodies/{pose.name}", "its points are not in the merged mesh (mergeMeshes "
                                 "appends them)", f"{case}/constant/polyMesh/points")
            ranges[pose.name] = (start, start + len(own))
        procs = processor_dirs(case)
        if not procs:
            return cls(case, [_Part(case, merged, {n: np.arange(a, b) for n, (a, b) in ranges.items()})])
        parts = []
        for proc in procs:
            address = read_labels(proc / "constant" / "polyMesh" / "pointProcAddressing")
            owners = {n: np.flatnonzero((address >= a) & (address < b)) for n, (a, b) in ranges.items()}
            parts.append(_Part(proc, read_points(proc / "constant" / _POINTS), owners))
        return cls(case, parts)

    def follow(self, time_name: str, states: Sequence[BodyState]) -> list[str]:
        """Move the points written at `time_name` of every body whose pose in `states` is not
        where they are (by more than TOLERANCE_M) to that pose; return the bodies moved."""
        poses = {p.name: p for p in read_mesh_poses(self.case)}
        moved: set[str] = set()
        for part in self.parts:
            path = part.root / time_name / _POINTS
            if not path.is_file():
                continue  # a time written without mesh points: the solver starts from points0
            points = read_points(path)
            changed = False
            for state in states:
                index = part.owners.get(state.name)
                if index is None or index.size == 0:
                    continue
                pose = poses[state.name]
                turn = state.rotation @ pose.rotation.T
                target = (part.points0[index] - np.asarray(pose.centre_of_mass_m)) @ turn.T
                target += np.asarray(state.centre_of_mass_m)
                if np.abs(points[index] - target).max() > TOLERANCE_M:
                    points[index] = target
                    changed = True
                    moved.add(state.name)
            if changed:
                write_points(path, points)
        return sorted(moved)
