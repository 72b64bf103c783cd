"""The contact-event record of a case: contacts.json, the runner's impacts.csv and each
impact's pulse files under contacts/.

Both ways of carrying debris write it: the coupled runner's contact book for every contact it
resolves, and the one-way transport for every strike its engine finds. Post-processing reads it
back (orchestrator.results.readers), whichever wrote it.

Each impact event is a JSON object in contacts.json (``type`` "impact", its number, time, bodies,
point, normal pointing from the obstacle into the body, velocities in and out, restitution,
obliquity, height, peak force, duration, impulse and ``force_history``, the path of its pulse
relative to the case). The pulse is ``contacts/eventNNNN-force.csv`` (``time_s,force_N``, time
from first contact) and, for a column strike, ``contacts/eventNNNN-base-shear.csv``.
"""
from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

from orchestrator.core.files import write_text_atomic

__all__ = ["CONTACTS_DIR", "CONTACTS_JSON", "IMPACTS_CSV", "IMPACT_COLUMNS", "read_events", "write_events",
           "write_pulse_files"]

CONTACTS_JSON = "contacts.json"
IMPACTS_CSV = "impacts.csv"
CONTACTS_DIR = "contacts"

#: Columns of post-processing's results/impacts.csv, in order (the one-way transport's table adds
#: its own at the end).
IMPACT_COLUMNS = [
    "event", "time_s", "body", "other", "kind", "height_m", "face_water_level_m", "body_clearance_m", "afloat",
    "point_x_m", "point_y_m", "point_z_m",
    "normal_x", "normal_y", "normal_z", "impact_velocity_m_s", "normal_velocity_in_m_s",
    "tangential_velocity_in_m_s", "obliquity_deg", "peak_force_N", "time_of_peak_s", "duration_s",
    "impulse_Ns", "rebound_normal_velocity_m_s", "rebound_u_m_s", "rebound_v_m_s", "rebound_w_m_s",
    "rebound_speed_m_s", "restitution", "force_history",
]


def read_events(case: str | Path) -> list[dict]:
    """The case's contact events, [] when it has none (no contacts.json, or one that holds no list)."""
    path = Path(case) / CONTACTS_JSON
    if not path.is_file():
        return []
    events = json.loads(path.read_text())
    return events if isinstance(events, list) else []


def write_events(case: str | Path, events: list[dict[str, Any]]) -> None:
    """Replace the case's contact events (atomically)."""
    write_text_atomic(Path(case) / CONTACTS_JSON, json.dumps(events, indent=2))


def write_pulse_files(case: str | Path, number: int, result) -> Path:
    """Write event ``number``'s pulse (an analytical ImpactResult: ``force``, ``base_shear``,
    ``base_shear_y``) under contacts/; returns the force history's path relative to the case."""
    case = Path(case)
    (case / CONTACTS_DIR).mkdir(exist_ok=True)
    history = case / CONTACTS_DIR / f"event{number:04d}-force.csv"
    with open(history, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["time_s", "force_N"])
        for t, f in zip(result.force.time_s, result.force.force_N):
            w.writerow([repr(float(t)), repr(float(f))])
    if result.base_shear is not None:
        shear = case / CONTACTS_DIR / f"event{number:04d}-base-shear.csv"
        ys = result.base_shear_y.response_N if result.base_shear_y is not None else None
        with open(shear, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["time_s", "base_shear_x_N"] + (["base_shear_y_N"] if ys is not None else []))
            for i, (t, v) in enumerate(zip(result.base_shear.time_s, result.base_shear.response_N)):
                w.writerow([repr(float(t)), repr(float(v))] + ([repr(float(ys[i]))] if ys is not None else []))
    return history.relative_to(case)
