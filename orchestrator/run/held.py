"""The bodies' motion solvers set aside while every body is held still.

v1912's dynamicOversetFvMesh rebuilds its overset addressing (cellVolumeWeight's mesh-to-mesh maps
between every pair of meshes) at every time step while any six-DoF motion solver runs, even for
bodies whose constraints keep them still. With an empty `solvers {}` in constant/dynamicMeshDict
it builds the addressing at a segment's first step and then reuses it. The runner does so while
every body is stuck on the bed or pinned at an obstacle (`ContactSettings.hold_still_solvers`),
keeping the solvers under `heldSolvers` (which v1912 ignores and every reader in
`orchestrator.case.bodystate` also looks in) and the bodies' states itself. Measured:
benchmarks/held_solvers.md; docs/openfoam-notes.md, "Cost".
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from orchestrator.case.bodystate import DYNAMIC_MESH_DICT, HELD_SOLVERS, BodyState, read_record, recorded_states
from orchestrator.case.dictionary import edit_dictionary, read_dictionary
from orchestrator.case.folder import processor_dirs, time_names
from orchestrator.core.files import write_text_atomic

__all__ = ["MOTION_FILES", "fill_motion_files", "hold_solvers", "recorded_before", "solvers_held", "still_state"]


def hold_solvers(case_dir: str | Path, held: bool) -> bool:
    """With ``held``, move the bodies' motion solvers from `solvers` to `heldSolvers` and leave
    `solvers` empty; without, put them back. Returns whether the dictionary changed.

    v1912's dynamicOversetFvMesh rebuilds its overset addressing (cellVolumeWeight's
    mesh-to-mesh maps between every pair of meshes) at every time step while any motion solver
    runs, even for bodies whose constraints keep them still: about 5.5 of each 6 s step for
    three containers on the bed, 2.5 of 3.0 s for one held at the column. With no solvers it
    builds the addressing once and then reuses it (0.03 s a step), and the flow sees the same
    still body meshes. The runner asks for it only when every body is held still
    (`body_policy.still_bodies`), and keeps their states itself; every reader of the bodies
    here finds them in either key.
    """
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    if not path.is_file():
        return False
    with edit_dictionary(path) as parsed:
        parked = HELD_SOLVERS in parsed
        if bool(held) == parked or (held and not ("solvers" in parsed and parsed["solvers"])):
            return False
        if held:
            parsed[HELD_SOLVERS] = parsed["solvers"].as_dict()
            parsed["solvers"] = {}
        else:
            parsed["solvers"] = parsed[HELD_SOLVERS].as_dict()
            del parsed[HELD_SOLVERS]
    return True


#: What a time written while the motion solvers were set aside lacks: the six-DoF solvers'
#: point displacement, and the moved mesh's points that v1912 writes for a moving mesh.
MOTION_FILES = ("pointDisplacement", "polyMesh/points")


def fill_motion_files(case_dir: str | Path) -> list[Path]:
    """Give every written time that lacks them the files of :data:`MOTION_FILES` from the latest
    earlier time that has them: a time written while the motion solvers were set aside
    (`hold_solvers`) has neither, and v1912's six-DoF solvers will not restart without
    `pointDisplacement`, nor reconstructPar gather a moved mesh without its points. The bodies
    did not move in between, so neither did the points. Returns the files written (in the
    case's root and each processor folder)."""
    case = Path(case_dir)
    written = []
    for root in [case, *processor_dirs(case)]:
        times = time_names(root)
        for name in MOTION_FILES:
            last = None
            for _, t in times:
                f = root / t / name
                if f.is_file():
                    last = f
                elif last is not None:
                    f.parent.mkdir(parents=True, exist_ok=True)
                    write_text_atomic(f, last.read_text())
                    written.append(f)
    return written


def solvers_held(case_dir: str | Path) -> bool:
    """Whether the bodies' motion solvers are set aside now (`hold_solvers`)."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    return path.is_file() and HELD_SOLVERS in read_dictionary(path)


def still_state(state: BodyState) -> BodyState:
    """`state` at rest: its pose, no velocity, angular velocity or acceleration (a body its
    constraints hold still)."""
    zero = (0.0, 0.0, 0.0)
    return replace(state, velocity_m_s=zero, angular_velocity_rad_s=zero, acceleration_m_s2=zero)


def recorded_before(case_dir: str | Path, time_name: str) -> tuple[list[BodyState], str] | None:
    """The latest states recorded for a restart at or before `time_name`, and that time's name."""
    t = float(time_name)
    earlier = [k for k in read_record(case_dir) if float(k) <= t * (1 + 1e-12) + 1e-12]
    if not earlier:
        return None
    name = max(earlier, key=float)
    return recorded_states(case_dir, name)[0], name
