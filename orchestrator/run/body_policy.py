"""What the runner does to a body through its six-DoF coefficients in constant/dynamicMeshDict.

Each policy is a sixDoF constraint or restraint the runner adds or removes between segments
(`orchestrator.case.bodystate` is the dictionary's format and its edits):

- hold: the planner's on-bed plane, until the water the runner measures lifts the body
  (`release_holds`, `orchestrator.run.bedwatch`);
- pin: a body pressed against the column or a wall again and again stays there
  (`pin_bodies`, `orchestrator.run.contact_book`);
- rest: a body the flow keeps pulling into the bed is kept on it (`rest_on_bed`);
- stick: static bed friction, a body at rest on the bed whose load the friction can bear
  (`stick_bodies`), and the sliding friction's dampers (`set_bed_friction`);
- still: every body stuck or pinned, so the motion solvers can be set aside
  (`still_bodies`, `orchestrator.run.held`).

Every edit returns the bodies it changed, so calling it again on a resumed run does nothing.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from orchestrator.case.bodystate import edit_motion_entries, motion_entries, read_mesh_poses
from orchestrator.case.dictionary import edit_dictionary, plain, read_dictionary

__all__ = [
    "BED_FRICTION",
    "BED_FRICTION_AXES",
    "BED_FRICTION_YAW",
    "REST_ON_BED",
    "STICK_KEYS",
    "bed_constraints",
    "lift_rest_on_bed",
    "pin_bodies",
    "pinned_bodies",
    "release_holds",
    "rest_on_bed",
    "rest_to_hold",
    "set_bed_friction",
    "set_pimple_entry",
    "still_bodies",
    "stick_bodies",
    "stuck_bodies",
    "unstick_bodies",
]

Vec = tuple[float, float, float]
_PLANE_Z = {"sixDoFRigidBodyMotionConstraint": "plane", "normal": [0.0, 0.0, 1.0]}


def _edit_constraints(case_dir: str | Path, names: Sequence[str], edit) -> list[str]:
    """Change the sixDoF constraints of the named bodies: `edit` gets a body's constraints (a dict,
    empty when it has none) and returns the new ones, or None to leave that body as it is."""
    return edit_motion_entries(case_dir, names, "constraints", lambda _name, entry: edit(entry))


def _constraint_keys(case_dir: str | Path) -> dict[str, set[str]]:
    return {name: set(entry) for name, entry in motion_entries(case_dir, "constraints").items()}


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
    velocity and the angular velocity of a fully constrained body to zero, so it stays
    still. Returns the bodies pinned now (already pinned ones are skipped).
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
    through the centre of mass the restart writes), so each slides and yaws but does not
    move vertically. For a body the flow keeps pulling into the bed (ContactBook). Returns
    the bodies constrained now (pinned or already resting ones are skipped)."""
    def rest(constraints: dict) -> dict | None:
        if REST_ON_BED in constraints or "pinnedPoint" in constraints:
            return None
        return {**constraints, REST_ON_BED: dict(_PLANE_Z)}

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
        return {**kept, "holdOnBedPlane": dict(_PLANE_Z)}

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
    return {name for name, keys in _constraint_keys(case_dir).items() if STICK_KEYS[0] in keys}


def bed_constraints(case_dir: str | Path) -> dict[str, str]:
    """How the runner keeps each body on the bed now: "pinned", "hold" (the planner's initial
    hold), "rest" (`rest_on_bed`) or "" (free)."""
    out = {}
    for name, keys in _constraint_keys(case_dir).items():
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
    return {name: {"sixDoFRigidBodyMotionRestraint": "linearSpring", "anchor": [float(v) for v in anchor],
                   "refAttachmentPt": [float(v) for v in centre0], "stiffness": 0.0, "damping": float(coeff),
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
    centres = {p.name: p.centre_of_mass_m for p in read_mesh_poses(case_dir)}

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

    return edit_motion_entries(case_dir, list(coefficients), "restraints", edit)


def _restraint_text(restraints: dict) -> dict[str, dict[str, str]]:
    """Restraints compared by value (numbers and vectors to 1e-9 relative, words by their text)."""
    def value(v: Any) -> str:
        if isinstance(v, (list, tuple)):
            return " ".join(value(x) for x in v)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return f"{float(v):.9e}"
        return str(v)
    return {k: {kk: value(vv) for kk, vv in dict(v).items()} for k, v in restraints.items()}


def set_pimple_entry(case_dir: str | Path, key: str, value: str) -> bool:
    """Set `key value;` in the PIMPLE dictionary of the case's system/fvSolution, which the
    solver reads when it (re)starts (the contact book asks for `oversetAdjustPhi yes` once every
    body is pinned). Returns False if it already had that value (or the case has no PIMPLE
    dictionary)."""
    path = Path(case_dir) / "system" / "fvSolution"
    pimple = plain(read_dictionary(path).get("PIMPLE"))
    if not isinstance(pimple, dict) or _same_word(pimple.get(key, ""), value):
        return False
    word = value.lower()
    with edit_dictionary(path) as parsed:  # a switch as a bool: foamlib writes it yes or no
        parsed["PIMPLE"][key] = True if word in ("yes", "on", "true") else False if word in (
            "no", "off", "false") else value
    return True


def _same_word(current: Any, value: str) -> bool:
    """Whether an entry read (foamlib reads yes/on/true as True) says `value`."""
    if isinstance(current, bool):
        return value.lower() in (("yes", "on", "true") if current else ("no", "off", "false"))
    return str(current).lower() == value.lower()


def pinned_bodies(case_dir: str | Path) -> set[str]:
    """The bodies that `pin_bodies` froze."""
    return {name for name, keys in _constraint_keys(case_dir).items() if "pinnedPoint" in keys}


def still_bodies(case_dir: str | Path) -> set[str]:
    """The bodies that cannot move now: stuck by static friction (`stick_bodies`) or pinned
    against an obstacle (`pin_bodies`), from one reading of the dictionary."""
    return {name for name, keys in _constraint_keys(case_dir).items() if keys & {STICK_KEYS[0], "pinnedPoint"}}
