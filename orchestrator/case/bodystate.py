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

Units: m, kg, s, rad. Orientation: the 3x3 rotation from body axes to global axes,
row-major, as OpenFOAM prints and reads it.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic

__all__ = [
    "BodyProperties",
    "BodyState",
    "DYNAMIC_MESH_DICT",
    "STATE_FILE",
    "angular_momentum_body",
    "coefficient_states",
    "orthonormal",
    "prepare_restart",
    "read_body_properties",
    "read_state_file",
    "recorded_states",
    "remove_state_files",
    "rest_on_bed",
    "set_pimple_entry",
    "write_dictionary",
    "write_states",
    "forget_after",
]

DYNAMIC_MESH_DICT = Path("constant") / "dynamicMeshDict"
STATE_FILE = Path("uniform") / "sixDoFRigidBodyMotionState"
RECORD_FILE = "bodystate.json"
_COEFFS = "sixDoFRigidBodyMotionCoeffs"
HELD_SOLVERS = "heldSolvers"  # the solvers while every body is held still (orchestrator.case.held)
_IDENTITY = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)

Vec = tuple[float, float, float]


@dataclass(frozen=True)
class BodyState:
    """A rigid body's state at `time_s`: pose, linear and angular velocity (global frame).

    `orientation` is row-major (xx xy xz yx ... zz), body axes -> global axes.
    `centre_of_rotation_m` is None when it is the centre of mass (always so here).
    """

    name: str
    time_s: float
    centre_of_mass_m: Vec
    orientation: tuple[float, ...] = _IDENTITY
    velocity_m_s: Vec = (0.0, 0.0, 0.0)
    angular_velocity_rad_s: Vec = (0.0, 0.0, 0.0)
    centre_of_rotation_m: Vec | None = None
    acceleration_m_s2: Vec = (0.0, 0.0, 0.0)

    @property
    def rotation(self) -> np.ndarray:
        return np.asarray(self.orientation, dtype=float).reshape(3, 3)

    @property
    def speed_m_s(self) -> float:
        return float(math.sqrt(sum(v * v for v in self.velocity_m_s)))

    def to_dict(self) -> dict[str, Any]:
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "BodyState":
        values = dict(data)
        for key in ("centre_of_mass_m", "orientation", "velocity_m_s", "angular_velocity_rad_s",
                    "centre_of_rotation_m", "acceleration_m_s2"):
            if values.get(key) is not None:
                values[key] = tuple(float(v) for v in values[key])
        return cls(**values)

    def with_changes(self, **changes) -> "BodyState":
        return replace(self, **changes)


@dataclass(frozen=True)
class BodyProperties:
    """What dynamicMeshDict says of a body: mass, principal inertia, and the pose its
    mesh was built in (`initial_*`: the pose of the points in constant/polyMesh)."""

    name: str
    mass_kg: float
    moment_of_inertia_kg_m2: Vec
    initial_centre_of_mass_m: Vec
    initial_orientation: tuple[float, ...]


# --------------------------------------------------------------------------- dictionaries


def _text(values: Iterable[float]) -> str:
    """A vector/tensor as OpenFOAM reads it, with every digit (repr of each float)."""
    return "(" + " ".join(repr(float(v)) for v in values) + ")"


def _full_precision(node: Any) -> Any:
    """Replace PyFoam Vector/Tensor/SymmTensor values by full-precision text, in place.

    PyFoam prints those with %g (6 significant digits): rewriting a dictionary it read
    would silently round every vector in it (inertia, gauge lines...).
    """
    from PyFoam.Basics.DataStructures import DictProxy, SymmTensor, Tensor, Vector

    if isinstance(node, (dict, DictProxy)):
        for key in list(node.keys()):
            value = node[key]
            if isinstance(value, (Vector, Tensor, SymmTensor)):
                node[key] = _text(value.vals)
            else:
                _full_precision(value)
    elif isinstance(node, list):
        for i, value in enumerate(node):
            if isinstance(value, (Vector, Tensor, SymmTensor)):
                node[i] = _text(value.vals)
            else:
                _full_precision(value)
    return node


def write_dictionary(parsed, path: str | Path | None = None) -> None:
    """Write a PyFoam ParsedParameterFile atomically and without loss of precision.

    Atomic (a temporary file renamed over the old one): a running solver re-reads
    run-time modified files (controlDict) at any moment and must never see half a file.
    PyFoam's own `writeFile` truncates the file in place and rounds vectors.
    """
    target = Path(path or parsed.name)
    _full_precision(parsed.content)
    text = str(parsed)
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def parsed_dict(path: Path):
    """An OpenFOAM dictionary file, parsed (PyFoam)."""
    from PyFoam.RunDictionary.ParsedParameterFile import ParsedParameterFile

    return ParsedParameterFile(str(path))


def _vec(value: Any, default: Sequence[float] | None = None) -> tuple[float, ...]:
    if value is None:
        if default is None:
            raise KeyError("missing vector")  # internal: every caller gives a default or a value it read
        return tuple(float(v) for v in default)
    if hasattr(value, "vals"):
        return tuple(float(v) for v in value.vals)
    if isinstance(value, str):
        return tuple(float(v) for v in value.strip().strip("()").split())
    return tuple(float(v) for v in value)


def _body_dicts(parsed) -> list[tuple[str, Any]]:
    solvers = next((parsed[k] for k in ("solvers", HELD_SOLVERS) if k in parsed and parsed[k]), None)
    if solvers is None:
        if _COEFFS in parsed:  # a single-body dictionary without `solvers`
            return [("body", parsed[_COEFFS])]
        return []
    return [(str(name), solvers[name][_COEFFS]) for name in solvers.keys() if _COEFFS in solvers[name]]


def read_body_properties(case_dir: str | Path) -> list[BodyProperties]:
    """Every six-DoF body of `constant/dynamicMeshDict`, in `solvers` order ([] if none)."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    if not path.is_file():
        return []
    bodies = []
    for name, c in _body_dicts(parsed_dict(path)):
        centre = _vec(c.get("initialCentreOfMass"), _vec(c["centreOfMass"]))
        orient = _vec(c.get("initialOrientation"), _vec(c.get("orientation"), _IDENTITY))
        bodies.append(BodyProperties(name, float(c["mass"]), _vec(c["momentOfInertia"]), centre, orient))
    return bodies


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


def angular_momentum_body(props: BodyProperties, state: BodyState) -> Vec:
    """OpenFOAM's `angularMomentum`: pi = I (Q^T omega), in the body frame (kg m^2/s).

    OpenFOAM reports the angular velocity omega = Q I^-1 pi in the global frame.
    """
    q = np.asarray(state.orientation, dtype=float).reshape(3, 3)
    local = q.T @ np.asarray(state.angular_velocity_rad_s, dtype=float)
    return tuple(float(v) for v in np.asarray(props.moment_of_inertia_kg_m2) * local)


def coefficient_states(case_dir: str | Path, time_s: float = 0.0) -> list[BodyState]:
    """Every body's state as its coefficients in constant/dynamicMeshDict give it (the start
    of a run): centreOfMass, orientation, velocity, angularMomentum (-> angular velocity),
    acceleration."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    props = {p.name: p for p in read_body_properties(case_dir)}
    states = []
    for name, c in _body_dicts(parsed_dict(path)):
        p = props[name]
        q = np.asarray(_vec(c.get("orientation"), _IDENTITY)).reshape(3, 3)
        pi = np.asarray(_vec(c.get("angularMomentum"), (0.0, 0.0, 0.0)))
        omega = q @ (pi / np.asarray(p.moment_of_inertia_kg_m2))
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
    parsed = parsed_dict(path)
    coeffs = dict(_body_dicts(parsed))
    props = {p.name: p for p in read_body_properties(case_dir)}
    for state in states:
        if state.name not in coeffs:
            raise InputError("solvers", f"no body {state.name!r} (bodies: {', '.join(coeffs)})", str(path))
        c = coeffs[state.name]
        p = props[state.name]
        c["initialCentreOfMass"] = _text(p.initial_centre_of_mass_m)
        c["initialOrientation"] = _text(p.initial_orientation)
        c["centreOfMass"] = _text(state.centre_of_mass_m)
        if "centreOfRotation" in c:
            del c["centreOfRotation"]
        c["orientation"] = _text(orthonormal(state.orientation))
        c["velocity"] = _text(state.velocity_m_s)
        c["acceleration"] = _text(state.acceleration_m_s2)
        c["angularMomentum"] = _text(angular_momentum_body(p, state))
    write_dictionary(parsed, path)


def state_file_paths(case_dir: str | Path, time_name: str) -> list[Path]:
    """`<t>/uniform/sixDoFRigidBodyMotionState` of the case and of every processor directory."""
    case = Path(case_dir)
    paths = [case / time_name / STATE_FILE]
    paths += sorted(p / time_name / STATE_FILE for p in case.glob("processor*") if p.is_dir())
    return [p for p in paths if p.is_file()]


def read_state_file(path: str | Path) -> dict[str, tuple[float, ...]]:
    """The state OpenFOAM wrote (the first body's): centreOfRotation, orientation, velocity..."""
    parsed = parsed_dict(Path(path))
    return {str(k): _vec(parsed[k]) for k in parsed.content.keys()
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
    names = [p.name for p in read_body_properties(case_dir)]
    missing = sorted(set(names) - {s.name for s in states})
    if missing:
        raise InputError("bodies", f"no state at t = {time_name} for {', '.join(missing)}", str(case_dir))
    record_states(case_dir, time_name, states, source)
    remove_state_files(case_dir, time_name)
    write_states(case_dir, states)


def _edit_constraints(case_dir: str | Path, names: Sequence[str],
                      edit: Callable[[dict], dict | None]) -> list[str]:
    """Change the sixDoF constraints of the named bodies in constant/dynamicMeshDict.

    `edit` gets a body's constraints (a dict, empty when it has none) and returns the new
    ones, or None to leave that body as it is; the file is written once, if anything
    changed. Returns the bodies changed.
    """
    return _edit_motion_entry(case_dir, names, "constraints", lambda _name, entry: edit(entry))


def _edit_motion_entry(case_dir: str | Path, names, key: str,
                       edit: Callable[[str, dict], dict | None]) -> list[str]:
    """Change one sub-dictionary (`constraints` or `restraints`) of the named bodies' sixDoF
    coefficients: `edit(name, entry)` returns the new entry (empty: removed) or None to leave
    the body as it is. The file is written once, if anything changed; returns the bodies changed."""
    if not names:
        return []
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    parsed = parsed_dict(path)
    changed = []
    for name, coeffs in _body_dicts(parsed):
        if name not in names:
            continue
        new = edit(name, dict(coeffs.get(key) or {}))
        if new is None:
            continue
        if new:
            coeffs[key] = new
        elif key in coeffs:
            del coeffs[key]
        changed.append(name)
    if changed:
        write_dictionary(parsed, path)
    return changed


#: The planner's on-bed hold: the bed plane (and, for a body free to tip, its axis); an
#: upright body keeps its keepUpright axis for the whole run.
_HOLD_KEYS = ("holdOnBedPlane", "holdOnBedAxis")
#: Static bed friction: a body at rest on the bed whose load the friction can bear does not move
#: (`stick_bodies`; `orchestrator.run.bedwatch` decides when it sticks and when it breaks away).
STICK_KEYS = ("stickPoint", "stickOrientation")
#: The constraint `rest_on_bed` adds (not the planner's initial hold, which `release_holds` removes).
REST_ON_BED = "restOnBedPlane"


def release_holds(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Remove the on-bed hold constraints of the named bodies from constant/dynamicMeshDict.

    Returns the bodies released now (already free ones are skipped), so calling it again
    on a resumed run does nothing.
    """
    def release(constraints: dict) -> dict | None:
        if "holdOnBedPlane" not in constraints:
            return None
        return {k: v for k, v in constraints.items() if k not in (*_HOLD_KEYS, *STICK_KEYS)}

    return _edit_constraints(case_dir, names, release)


def pin_bodies(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Freeze the named bodies where they are (sixDoF `point` + `orientation` constraints).

    A body pressed against the column or a wall by the flow (a resting contact that keeps
    coming back) stays there: debris damming against the obstacle. v1912 projects the
    velocity and the angular velocity of a fully constrained body to zero, so it no longer
    moves. Returns the bodies pinned now (already pinned ones are skipped).
    """
    def pin(constraints: dict) -> dict | None:
        if "pinnedPoint" in constraints:
            return None
        kept = {k: v for k, v in constraints.items()
                if k not in (*_HOLD_KEYS, *STICK_KEYS, "keepUpright", REST_ON_BED)}
        return {**kept, "pinnedPoint": {"sixDoFRigidBodyMotionConstraint": "point"},
                "pinnedOrientation": {"sixDoFRigidBodyMotionConstraint": "orientation"}}

    return _edit_constraints(case_dir, names, pin)


def rest_on_bed(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Keep the named bodies on the bed from now on: a sixDoF `plane` constraint (normal z,
    through the centre of mass the restart writes), so each slides and yaws but no longer
    moves vertically. For a body the flow keeps pulling into the bed (ContactBook). Returns
    the bodies constrained now (pinned or already resting ones are skipped)."""
    def rest(constraints: dict) -> dict | None:
        if REST_ON_BED in constraints or "pinnedPoint" in constraints:
            return None
        return {**constraints, REST_ON_BED: {"sixDoFRigidBodyMotionConstraint": "plane", "normal": [0.0, 0.0, 1.0]}}

    return _edit_constraints(case_dir, names, rest)


def lift_rest_on_bed(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Remove the `rest_on_bed` constraint of the named bodies (the water can carry them again).
    Returns the bodies freed now."""
    def lift(constraints: dict) -> dict | None:
        if REST_ON_BED not in constraints:
            return None
        return {k: v for k, v in constraints.items() if k != REST_ON_BED}

    return _edit_constraints(case_dir, names, lift)


def rest_to_hold(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Turn the `rest_on_bed` constraint of the named bodies into the planner's hold (the same
    plane, named `holdOnBedPlane`): the runner raises such a body onto the gap's top, where its
    underside has overset donors, and holds it there until the water lifts it
    (`orchestrator.run.bedwatch`). Returns the bodies changed."""
    def to_hold(constraints: dict) -> dict | None:
        if REST_ON_BED not in constraints:
            return None
        kept = {k: v for k, v in constraints.items() if k != REST_ON_BED}
        return {**kept, "holdOnBedPlane": {"sixDoFRigidBodyMotionConstraint": "plane", "normal": [0.0, 0.0, 1.0]}}

    return _edit_constraints(case_dir, names, to_hold)


def stick_bodies(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """Hold the named bodies still on the bed (sixDoF `point` + `orientation` beside their bed
    constraint): static friction. Returns the bodies stuck now (stuck or pinned ones are skipped)."""
    def stick(constraints: dict) -> dict | None:
        if STICK_KEYS[0] in constraints or "pinnedPoint" in constraints:
            return None
        return {**constraints, STICK_KEYS[0]: {"sixDoFRigidBodyMotionConstraint": "point"},
                STICK_KEYS[1]: {"sixDoFRigidBodyMotionConstraint": "orientation"}}

    return _edit_constraints(case_dir, names, stick)


def unstick_bodies(case_dir: str | Path, names: Sequence[str]) -> list[str]:
    """End the static friction of the named bodies (they slide from now on). Returns those changed."""
    def unstick(constraints: dict) -> dict | None:
        if STICK_KEYS[0] not in constraints:
            return None
        return {k: v for k, v in constraints.items() if k not in STICK_KEYS}

    return _edit_constraints(case_dir, names, unstick)


def stuck_bodies(case_dir: str | Path) -> set[str]:
    """The bodies held by static friction now (`stick_bodies`)."""
    return {name for name, coeffs in _body_dicts(parsed_dict(Path(case_dir) / DYNAMIC_MESH_DICT))
            if STICK_KEYS[0] in (coeffs.get("constraints") or {})}


def bed_constraints(case_dir: str | Path) -> dict[str, str]:
    """How the runner keeps each body on the bed now: "pinned", "hold" (the planner's initial
    hold), "rest" (`rest_on_bed`) or "" (free)."""
    out = {}
    for name, coeffs in _body_dicts(parsed_dict(Path(case_dir) / DYNAMIC_MESH_DICT)):
        keys = set((coeffs.get("constraints") or {}).keys())
        out[name] = ("pinned" if "pinnedPoint" in keys else "hold" if "holdOnBedPlane" in keys
                     else "rest" if REST_ON_BED in keys else "")
    return out


#: The restraints that carry a resting body's sliding bed friction (`set_bed_friction`): along the
#: bed (two zero-stiffness `linearSpring` dampers through its centre, along x and along y) and
#: against its yaw (a `sphericalAngularDamper`).
BED_FRICTION = "bedFriction"
BED_FRICTION_YAW = "bedFrictionYaw"
#: the two horizontal dampers' names, and where their anchors are: far out along -x and -y, so
#: that each pulls along its axis (at 3 m from the flume's axis a 1e5 m spring turns by 3e-5 rad)
BED_FRICTION_AXES = {BED_FRICTION + "X": (-1e5, 0.0, 0.0), BED_FRICTION + "Y": (0.0, -1e5, 0.0)}


def _bed_friction_springs(coeff: float, centre0: Vec) -> dict[str, dict]:
    """The sliding bed friction as v1912 restraints that act at the body's centre.

    v1912's `linearDamper` gives the force -coeff v but no position, and the motion solver adds a
    restraint's moment about its centre of rotation as (position - centre) ^ force with the
    position left at the origin (sixDoFRigidBodyMotion::applyRestraints): a yaw moment
    coeff (x v_y - y v_x) of a body x metres down the flume. A `linearSpring` sets its position to
    its attachment point, here the body's centre (`refAttachmentPt` is in the pose the mesh was
    built in, `centre0`), so the force -damping (r.v) r of a zero-stiffness spring along x and one
    along y is -coeff v_h with no moment."""
    return {name: {"sixDoFRigidBodyMotionRestraint": "linearSpring", "anchor": _text(anchor),
                   "refAttachmentPt": _text(centre0), "stiffness": 0.0, "damping": float(coeff),
                   "restLength": 1e5}
            for name, anchor in BED_FRICTION_AXES.items()}


def set_bed_friction(case_dir: str | Path, coefficients: dict[str, float | None],
                     yaw: dict[str, float | None] | None = None) -> list[str]:
    """Set (a number) or remove (None) the friction dampers of the named bodies: a horizontal
    force -coeff * velocity at the centre of mass (N s/m; `_bed_friction_springs`), and, for the
    bodies in `yaw`, `bedFrictionYaw`, a moment -coeff * angular velocity (N m s) (v1912's sixDoF
    restraints). The runner sizes them to the Coulomb friction of a body sliding on the bed
    (`orchestrator.run.bedwatch`). Returns the bodies changed."""
    yaw = yaw or {}
    centres = {p.name: p.initial_centre_of_mass_m for p in read_body_properties(case_dir)}

    def edit(name: str, restraints: dict) -> dict | None:
        new = {k: v for k, v in restraints.items() if k not in (BED_FRICTION, *BED_FRICTION_AXES)}
        if coefficients[name] is not None:
            new.update(_bed_friction_springs(coefficients[name], centres[name]))
        if name in yaw:
            new.pop(BED_FRICTION_YAW, None)
            if yaw[name] is not None:
                new[BED_FRICTION_YAW] = {"sixDoFRigidBodyMotionRestraint": "sphericalAngularDamper",
                                         "coeff": float(yaw[name])}
        return new if _restraint_text(new) != _restraint_text(restraints) else None

    return _edit_motion_entry(case_dir, list(coefficients), "restraints", edit)


def _restraint_text(restraints: dict) -> dict[str, dict[str, str]]:
    """Restraints compared by value (numbers to 1e-9 relative, vectors by their text)."""
    def value(v: Any) -> str:
        text = " ".join(str(v).split())
        try:
            if text.startswith("("):
                return " ".join(f"{float(x):.9e}" for x in text.strip("()").split())
            return f"{float(text):.9e}"
        except ValueError:
            return text
    return {k: {kk: value(vv) for kk, vv in dict(v).items()} for k, v in restraints.items()}


def set_pimple_entry(case_dir: str | Path, key: str, value: str) -> bool:
    """Set `key value;` in the PIMPLE dictionary of the case's system/fvSolution, which the
    solver reads when it (re)starts. Returns False if it already had that value (or the case
    has no PIMPLE dictionary)."""
    path = Path(case_dir) / "system" / "fvSolution"
    parsed = parsed_dict(path)
    pimple = parsed["PIMPLE"] if "PIMPLE" in parsed else None
    if pimple is None or str(pimple.get(key, "")).lower() == value.lower():
        return False
    pimple[key] = value
    write_dictionary(parsed, path)
    return True


def pinned_bodies(case_dir: str | Path) -> set[str]:
    """The bodies that `pin_bodies` froze."""
    path = Path(case_dir) / DYNAMIC_MESH_DICT
    return {name for name, coeffs in _body_dicts(parsed_dict(path))
            if "pinnedPoint" in (coeffs.get("constraints") or {})}
