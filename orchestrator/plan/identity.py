"""Is this the same case? One answer, for a case folder being resumed and for a sweep's members.

A case's inputs are its resolved scene (:func:`orchestrator.scene.scenefile.scene_to_dict`: layouts
expanded, defaults filled in) as canonical JSON, less two kinds of keys that cannot change what
the case computes:

* keys the case's coupling never reads (:data:`ONE_WAY_ONLY`): a two-way or no-debris case
  ignores the one-way transport and the flow record's rate, so changing their defaults leaves a
  finished coupled run the same case;
* the ``design`` section (what ``debrisfoam design`` samples over a case's flow; no case reads it);
* keys added to the scene after runs were made, at the value that means "as before the key
  existed" (:data:`LATE_KEYS`, :data:`LATE_SECTIONS`): adding a key leaves existing cases, and the
  ids of existing sweep members, as they were.

:func:`case_key` hashes those inputs (a sweep member's id is its first :data:`ID_LENGTH` hex
digits); :func:`same_case` compares two scenes by it. ``debrisfoam case`` resumes a folder only
when :func:`same_case` says its scene.yaml is the scene asked for.
"""

from __future__ import annotations

import hashlib
import json

from orchestrator.core.jsonio import json_default
from orchestrator.scene.scenefile import scene_to_dict
from orchestrator.scene.schema import Scene, Transport

__all__ = ["ID_LENGTH", "LATE_BODY_KEYS", "LATE_KEYS", "LATE_SECTIONS", "ONE_WAY_ONLY", "carried_as", "case_inputs", "case_key", "same_case",
           "same_flow"]

#: Length of a sweep member's id (hex digits of :func:`case_key`).
ID_LENGTH = 12
#: What only a one-way case reads: a section (None: all of it) or some of its keys.
ONE_WAY_ONLY = {"transport": None, "outputs": ("flow_record_hz",)}
#: Scene keys added after the first runs, with the value they are left out at. run.debris_coupling
#: is left out (at auto) only for a scene without debris: with debris, auto picks one-way where a
#: case made before it ran two-way, so it must count.
LATE_KEYS = ((("run", "max_delta_t_s"), None), (("run", "stall_limit_s"), None), (("run", "water_balance_limit"), None),
             (("outputs", "flow_record_hz"), 50.0), (("mesh", "refine_box_m"), None),
             (("mesh", "refine_cell_size_m"), None),
             (("mesh", "column_approach_cell_size_m"), None), (("column", "section"), None), (("column", "section_area_m2"), None),
             (("column", "section_second_moment_m4"), None), (("column", "stiffness_factor"), 1.0),
             (("column", "base_spring_Nm_rad"), None), (("mesh", "wet_bed_cells"), 1),
             (("fluids", "turbulence"), "laminar"), (("bed", "slip"), False),
             (("column", "ends"), "cantilever"), (("column", "strike_height_m"), None), (("column", "heading_deg"), 0.0),
             (("reservoir", "sill_height_m"), 0.0), (("reservoir", "opening_width_m"), None),
             (("reservoir", "opening_y_m"), 0.0), (("reservoir", "opening_length_m"), 0.1),
             (("reservoir", "opening_time_s"), 0.0))
#: Keys of every debris body added after the first runs, with the value they are left out at.
LATE_BODY_KEYS = (("type", None),)
#: Scene sections added after the first runs: left out when at their defaults.
LATE_SECTIONS = {"transport": Transport().model_dump(mode="json"), "inundation": None}


def case_inputs(scene: Scene, coupling: str) -> dict:
    """The resolved scene as the identity of a case's inputs (module notes). ``coupling`` is the
    case's (its plan's ``debris_coupling``)."""
    data = scene_to_dict(scene)
    data.pop("design", None)  # what `debrisfoam design` samples: never read by a case
    if coupling != "one-way":
        for section, keys in ONE_WAY_ONLY.items():
            if keys is None:
                data.pop(section, None)
            elif isinstance(data.get(section), dict):
                data[section] = {k: v for k, v in data[section].items() if k not in keys}
    late = LATE_KEYS + (((("run", "debris_coupling"), "auto"),) if not scene.debris else ())
    for (section, key), unhashed in late:
        if isinstance(data.get(section), dict) and key in data[section] and data[section][key] == unhashed:
            data[section].pop(key)
    for body in data.get("debris") or []:
        for key, unhashed in LATE_BODY_KEYS:
            if isinstance(body, dict) and key in body and body[key] == unhashed:
                body.pop(key)
    for section, default in LATE_SECTIONS.items():
        if section in data and data[section] == default:
            data.pop(section)
    return data


def case_key(scene: Scene, coupling: str) -> str:
    """SHA-256 (hex) of :func:`case_inputs` as canonical JSON: the same inputs, the same key."""
    text = json.dumps(case_inputs(scene, coupling), sort_keys=True, separators=(",", ":"), default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()


def same_case(a: Scene, b: Scene, coupling: str) -> bool:
    """Do ``a`` and ``b`` make the same case (for a case of ``coupling``)?"""
    return case_key(a, coupling) == case_key(b, coupling)


def carried_as(existing: Scene, scene: Scene) -> Scene:
    """``existing`` with what a one-way case's transport reads taken from ``scene``: its
    ``transport`` section and each debris body's ``contact`` law (bodies matched by order; a scene
    with other bodies is returned with its own)."""
    update: dict = {"transport": scene.transport}
    if len(existing.debris) == len(scene.debris):
        update["debris"] = tuple(e.model_copy(update={"contact": s.contact}) for e, s in zip(existing.debris, scene.debris))
    return existing.model_copy(update=update)


def same_flow(a: Scene, b: Scene) -> bool:
    """Do ``a`` and ``b`` make the same one-way flow, whatever their transport sections and their
    bodies' contact laws? The bodies are carried through a recorded flow afterwards, so a changed
    ``transport`` section or contact law re-carries them through the same record instead of running
    the flow again."""
    return same_case(carried_as(a, b), b, "one-way")
