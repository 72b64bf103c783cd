"""Six-DoF body states: save every body's state, and restore all of them on a restart.

OpenFOAM v1912 keeps one body's state only: `<t>/uniform/sixDoFRigidBodyMotionState`
(in every processor directory) holds the first body of dynamicMeshDict's `solvers`,
and on a restart *every* body reads that file (docs/openfoam-notes.md: both bodies
jumped to the first body's place and the run died). The recipe verified there, and
used here (`prepare_restart`):

1. delete `processor*/<t>/uniform/sixDoFRigidBodyMotionState` (and `<t>/uniform/...`
   of a serial run), so that each body falls back to its own coefficients;
2. write into each body's `sixDoFRigidBodyMotionCoeffs` in `constant/dynamicMeshDict`
   its current `centreOfMass`, `orientation`, `velocity`, `angularMomentum` (body
   frame) and `acceleration`, beside `initialCentreOfMass` / `initialOrientation`:
   the pose the body mesh was built in (its points0), taken from the coefficients
   the first time and kept from then on.

Where the states come from: the solver's per-step report in the log (`monitor`), the
last report of each body at the time the run restarts from; after a contact event,
the impact model's rebound state. Every restart's states are also recorded in
`bodystate.json` (time name -> source and states) so that a resumed run uses the
rebound state of a contact it resolved, and so that a restart can be checked.

This module is the format: the states, the bodies' coefficients and the record. What the
runner does to a body through those coefficients (pin it, stick it, rest it on the bed,
release its hold, its bed friction) is `orchestrator.run.body_policy`.

Units: m, kg, s, rad. Orientation: the 3x3 rotation from body axes to global axes,
row-major, as OpenFOAM prints and reads it.
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from orchestrator.case.dictionary import edit_dictionary, plain, read_dictionary
from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic

__all__ = [
    "BodyState",
    "DYNAMIC_MESH_DICT",
    "HELD_SOLVERS",
    "STATE_FILE",
    "angular_momentum_body",
    "body_coefficients",
    "coefficient_states",
    "edit_motion_entries",
    "forget_after",
    "motion_entries",
    "orthonormal",
    "prepare_restart",
    "read_mesh_bodies",
    "read_mesh_poses",
    "read_record",
    "read_state_file",
    "record_states",
    "recorded_states",
    "remove_state_files",
    "state_file_paths",
    "write_states",
]

DYNAMIC_MESH_DICT = Path("constant") / "dynamicMeshDict"
STATE_FILE = Path("uniform") / "sixDoFRigidBodyMotionState"
RECORD_FILE = "bodystate.json"
_COEFFS = "sixDoFRigidBodyMotionCoeffs"
HELD_SOLVERS = "heldSolvers"  # the solvers while every body is held still (orchestrator.run.held)
_IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)

Vec = tuple[float, float, float]
_BOX = ("size_m", "mass_kg", "inertia_kg_m2")  # BodyState's box: written only when set


@dataclass(frozen=True)
class BodyState:
    """A rigid body's state at `time_s`: pose, linear and angular velocity (global frame).

    `orientation` is row-major (xx xy xz yx ... zz), body axes -> global axes.
    `centre_of_rotation_m` is None when it is the centre of mass (always so here).
    `size_m`, `mass_kg` and `inertia_kg_m2` (principal, body axes) are the body's box, set where
    a stage needs them (contact: :func:`orchestrator.contact.geometry.box_state`), else None.
    """

    name: str
    time_s: float
    centre_of_mass_m: Vec
    orientation: tuple[float, ...] = _IDENTITY
    velocity_m_s: Vec = (0.0, 0.0, 0.0)
    angular_velocity_rad_s: Vec = (0.0, 0.0, 0.0)
    centre_of_rotation_m: Vec | None = None
    acceleration_m_s2: Vec = (0.0, 0.0, 0.0)
    size_m: Vec | None = None
    mass_kg: float | None = None
    inertia_kg_m2: Vec | None = None

    @property
    def rotation(self) -> np.ndarray:
        return np.asarray(self.orientation, dtype=float).reshape(3, 3)

    @property
    def speed_m_s(self) -> float:
        return float(math.sqrt(sum(v * v for v in self.velocity_m_s)))

    def to_dict(self) -> dict[str, Any]:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()
                if not (k in _BOX and v is None)}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "BodyState":
        values = dict(data)
        for key in ("centre_of_mass_m", "orientation", "velocity_m_s", "angular_velocity_rad_s",
                    "centre_of_rotation_m", "acceleration_m_s2", "size_m", "inertia_kg_m2"):
            if values.get(key) is not None:
                values[key] = tuple(float(v) for v in values[key])
        return cls(**values)

    def with_changes(self, **changes) -> "BodyState":
        return replace(self, **changes)


# --------------------------------------------------------------------------- dictionaries


def _floats(values: Iterable[float]) -> list[float]:
    """A vector/tensor to write: Python floats, which foamlib writes with every digit."""
    return [float(v) for v in values]


def _vec(value: Any, default: Sequence[float] | None = None) -> tuple[float, ...]:
    if value is None:
        if default is None:
            raise KeyError("missing vector")  # internal: every caller gives a default or a value it read
        return tuple(float(v) for v in default)
    if isinstance(value, str):
        return tuple(float(v) for v in value.strip().strip("()").split())
    return tuple(float(v) for v in value)


def body_coefficients(parsed) -> list[tuple[str, Any]]:
    """(name, sixDoFRigidBodyMotionCoeffs) of every body of a parsed dynamicMeshDict, in `solvers`
    order; the solvers set aside under `heldSolvers` (orchestrator.run.held) count too."""
    solvers = next((parsed[k] for k in ("solvers", HELD_SOLVERS) if k in parsed and parsed[k]), None)
    if solvers is None:
        if _COEFFS in parsed:  # a single-body dictionary without `solvers`
            return [("body", parsed[_COEFFS])]
        return []
    return [(str(name), solvers[name][_COEFFS]) for name in solvers.keys() if _COEFFS in solvers[name]]


def read_mesh_bodies(case_dir: str | Path) -> list[tuple[BodyState, Vec]]:
    """Every six-DoF body of `constant/dynamicMeshDict`, in `solvers` order ([] if none): the pose
    its mesh was built in (`initialCentreOfMass` / `initialOrientation`, the pose of the points in
    constant/polyMesh; before a restart writes them, the coefficients' own) as a BodyState at
    t = 0, and its principal moments of inertia (kg m^2). Mass and size are the plan's (BodyPlan)."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    if not path.is_file():
        return []
    bodies = []
    for name, coeffs in body_coefficients(read_dictionary(path)):
        c = plain(coeffs)  # a dict: a missing entry is KeyError('mass'), as in any dict
        float(c["mass"])  # what render writes, so a dictionary without it is not one of its cases
        centre = _vec(c.get("initialCentreOfMass"), _vec(c["centreOfMass"]))
        orient = _vec(c.get("initialOrientation"), _vec(c.get("orientation"), _IDENTITY))
        bodies.append((BodyState(name, 0.0, centre, orient), _vec(c["momentOfInertia"])))
    return bodies


def read_mesh_poses(case_dir: str | Path) -> list[BodyState]:
    """Each body's pose its mesh was built in, at t = 0 (:func:`read_mesh_bodies`)."""
    return [pose for pose, _ in read_mesh_bodies(case_dir)]


def motion_entries(case_dir: str | Path, key: str) -> dict[str, dict[str, Any]]:
    """One sub-dictionary (`constraints` or `restraints`) of every body's six-DoF coefficients, as
    plain dicts ({} for a body without it)."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    return {name: plain(coeffs.get(key)) or {} for name, coeffs in body_coefficients(read_dictionary(path))}


def edit_motion_entries(case_dir: str | Path, names: Sequence[str], key: str,
                        edit: Callable[[str, dict], dict | None]) -> list[str]:
    """Change one sub-dictionary (`constraints` or `restraints`) of the named bodies' six-DoF
    coefficients: `edit(name, entry)` gets the entry as a plain dict ({} if absent) and returns
    the new one (empty: removed) or None to leave the body as it is. Only the entries that
    differ are written, so the rendered comments of the others stay; the file is replaced once,
    if anything changed. Returns the bodies changed."""
    if not names:
        return []
    changed = []
    with edit_dictionary(Path(case_dir) / DYNAMIC_MESH_DICT) as parsed:
        for name, coeffs in body_coefficients(parsed):
            if name not in names:
                continue
            old = plain(coeffs.get(key)) or {}
            new = edit(name, dict(old))
            if new is None:
                continue
            if not new:
                if key in coeffs:
                    del coeffs[key]
            elif key not in coeffs:
                coeffs[key] = new
            else:
                entry = coeffs[key]
                for k in [k for k in old if k not in new]:
                    del entry[k]
                for k, v in new.items():
                    if k not in old or old[k] != v:
                        entry[k] = v
            changed.append(name)
    return changed


def orthonormal(orientation: Sequence[float]) -> tuple[float, ...]:
    """The rotation matrix nearest to `orientation` (polar decomposition), row-major.

    The log prints 10 significant digits; this removes the rounding before the matrix
    is written back, so OpenFOAM is given a proper rotation.
    """
    m = np.asarray(orientation, dtype=float).reshape(3, 3)
    u, _, vt = np.linalg.svd(m)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return tuple(float(v) for v in r.ravel())


def angular_momentum_body(inertia_kg_m2: Sequence[float], state: BodyState) -> Vec:
    """OpenFOAM's `angularMomentum`: pi = I (Q^T omega), in the body frame (kg m^2/s).

    OpenFOAM reports the angular velocity omega = Q I^-1 pi in the global frame.
    """
    q = np.asarray(state.orientation, dtype=float).reshape(3, 3)
    local = q.T @ np.asarray(state.angular_velocity_rad_s, dtype=float)
    return tuple(float(v) for v in np.asarray(inertia_kg_m2, dtype=float) * local)


def coefficient_states(case_dir: str | Path, time_s: float = 0.0) -> list[BodyState]:
    """Every body's state as its coefficients in constant/dynamicMeshDict give it (the start
    of a run): centreOfMass, orientation, velocity, angularMomentum (-> angular velocity),
    acceleration."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    inertias = {pose.name: inertia for pose, inertia in read_mesh_bodies(case_dir)}
    states = []
    for name, coeffs in body_coefficients(read_dictionary(path)):
        c = plain(coeffs)
        q = np.asarray(_vec(c.get("orientation"), _IDENTITY)).reshape(3, 3)
        pi = np.asarray(_vec(c.get("angularMomentum"), (0.0, 0.0, 0.0)))
        omega = q @ (pi / np.asarray(inertias[name]))
        states.append(BodyState(name, time_s, _vec(c["centreOfMass"]), tuple(float(v) for v in q.ravel()),
                                _vec(c.get("velocity"), (0.0, 0.0, 0.0)), tuple(float(v) for v in omega), None,
                                _vec(c.get("acceleration"), (0.0, 0.0, 0.0))))
    return states


def write_states(case_dir: str | Path, states: Sequence[BodyState]) -> None:
    """Write each body's state into its coefficients in constant/dynamicMeshDict.

    `initialCentreOfMass` / `initialOrientation` are set once, from the coefficients as rendered (the pose the
    body mesh was built in), and never changed afterwards. Raises InputError naming a body it lacks.
    """
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    mesh = {pose.name: (pose, inertia) for pose, inertia in read_mesh_bodies(case_dir)}
    with edit_dictionary(path) as parsed:
        coeffs = dict(body_coefficients(parsed))
        for state in states:
            if state.name not in coeffs:
                raise InputError("solvers", f"no body {state.name!r} (bodies: {', '.join(coeffs)})", str(path))
            c = coeffs[state.name]
            pose, inertia = mesh[state.name]
            c["initialCentreOfMass"] = _floats(pose.centre_of_mass_m)
            c["initialOrientation"] = _floats(pose.orientation)
            c["centreOfMass"] = _floats(state.centre_of_mass_m)
            if "centreOfRotation" in c:
                del c["centreOfRotation"]
            c["orientation"] = _floats(orthonormal(state.orientation))
            c["velocity"] = _floats(state.velocity_m_s)
            c["acceleration"] = _floats(state.acceleration_m_s2)
            c["angularMomentum"] = _floats(angular_momentum_body(inertia, state))


def state_file_paths(case_dir: str | Path, time_name: str) -> list[Path]:
    """`<t>/uniform/sixDoFRigidBodyMotionState` of the case and of every processor directory."""
    case = Path(case_dir)
    paths = [case / time_name / STATE_FILE]
    paths += sorted(p / time_name / STATE_FILE for p in case.glob("processor*") if p.is_dir())
    return [p for p in paths if p.is_file()]


def read_state_file(path: str | Path) -> dict[str, tuple[float, ...]]:
    """The state OpenFOAM wrote (the first body's): centreOfRotation, orientation, velocity..."""
    parsed = read_dictionary(path)
    return {str(k): _vec(parsed[k]) for k in parsed.keys()
            if k in ("centreOfRotation", "orientation", "velocity", "acceleration", "angularMomentum", "torque")}


def remove_state_files(case_dir: str | Path, time_name: str) -> list[Path]:
    """Delete every copy of the (first body's) state file at time `time_name`."""
    removed = state_file_paths(case_dir, time_name)
    for p in removed:
        p.unlink()
    return removed


# --------------------------------------------------------------------------- records


def _record_path(case_dir: str | Path) -> Path:
    return Path(case_dir) / RECORD_FILE


def read_record(case_dir: str | Path) -> dict[str, Any]:
    path = _record_path(case_dir)
    if not path.is_file():
        return {}
    return json.loads(path.read_text())


def record_states(case_dir: str | Path, time_name: str, states: Sequence[BodyState], source: str) -> None:
    """Remember the states a restart at `time_name` uses, and where they came from
    ("log": the solver's report; "contact": an impact model's rebound)."""
    record = read_record(case_dir)
    record[time_name] = {"source": source, "bodies": [s.to_dict() for s in states]}
    write_text_atomic(_record_path(case_dir), json.dumps(record, indent=1))


def recorded_states(case_dir: str | Path, time_name: str) -> tuple[list[BodyState], str] | None:
    """The states recorded for a restart at `time_name` and their source, or None."""
    entry = read_record(case_dir).get(time_name)
    if entry is None:
        return None
    return [BodyState.from_dict(b) for b in entry["bodies"]], str(entry["source"])


def forget_after(case_dir: str | Path, time_s: float) -> None:
    """Drop the records of restarts later than `time_s` (a run going back to `time_s`
    will compute that stretch again; its old states must not be reused)."""
    record = read_record(case_dir)
    keep = {k: v for k, v in record.items() if float(k) <= time_s * (1 + 1e-12) + 1e-12}
    if len(keep) != len(record):
        write_text_atomic(_record_path(case_dir), json.dumps(keep, indent=1))


def prepare_restart(case_dir: str | Path, time_name: str, states: Sequence[BodyState], source: str) -> None:
    """Make a restart at `time_name` start every body from `states` (the v1912 recipe above)."""
    names = [p.name for p in read_mesh_poses(case_dir)]
    missing = sorted(set(names) - {s.name for s in states})
    if missing:
        raise InputError("bodies", f"no state at t = {time_name} for {', '.join(missing)}", str(case_dir))
    record_states(case_dir, time_name, states, source)
    remove_state_files(case_dir, time_name)
    write_states(case_dir, states)
