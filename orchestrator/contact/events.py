"""A case's contact-event files: contacts.json, the runner's impact_events.csv and each impact's
pulse files under contacts/. Every read and write of them goes through this module.

Both ways of carrying debris write contacts.json and the pulses: the coupled runner's contact
book for every contact it resolves, and the one-way transport for every strike its engine finds.
Post-processing, reports and studies read the events back with :func:`read_events`, whichever
wrote them.

Each impact event is a JSON object in contacts.json (``type`` "impact", its number, time, bodies,
point, normal pointing from the obstacle into the body, velocities in and out, restitution,
obliquity, height, peak force, duration, impulse and ``force_history``, the path of its pulse
relative to the case). The pulse is ``contacts/eventNNNN-force.csv`` (``time_s,force_N``, time
from first contact) and, for a column strike, ``contacts/eventNNNN-base-shear.csv``.

The coupled runner also keeps ``impact_events.csv`` at the case root, one row per impact as it
resolves it (:data:`IMPACT_EVENT_COLUMNS`). It is not post-processing's ``results/impacts.csv``
(:data:`IMPACT_COLUMNS`, the user-facing table built from contacts.json). Run folders written
before the runner's table had its own name hold it as ``impacts.csv`` at the case root; the
runner keeps using that file in such a folder (:func:`impact_events_path`).
"""
from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

from orchestrator.core.files import write_text_atomic

__all__ = ["CONTACTS_DIR", "CONTACTS_JSON", "IMPACT_COLUMNS", "IMPACT_EVENTS_CSV", "IMPACT_EVENT_COLUMNS",
           "append_impact_event", "forget_impact_events_after", "impact_events_path", "read_events", "write_events",
           "write_pulse_files"]

CONTACTS_JSON = "contacts.json"
CONTACTS_DIR = "contacts"
#: The runner's table of impacts at the case root.
IMPACT_EVENTS_CSV = "impact_events.csv"
#: The name older run folders hold the runner's table under (see the module notes).
_OLD_IMPACT_EVENTS_CSV = "impacts.csv"

#: Columns of the runner's impact_events.csv, in order.
IMPACT_EVENT_COLUMNS = [
    "event", "time_s", "body", "other", "kind", "point_x_m", "point_y_m", "point_z_m", "normal_x", "normal_y",
    "normal_z", "u_in_m_s", "v_in_m_s", "w_in_m_s", "u_out_m_s", "v_out_m_s", "w_out_m_s", "normal_velocity_in_m_s",
    "normal_velocity_out_m_s", "restitution", "obliquity_deg", "height_m", "peak_force_N", "duration_s",
    "impulse_Ns", "force_history",
]

#: Columns of post-processing's results/impacts.csv, in order (the one-way transport's table adds
#: its own at the end).
IMPACT_COLUMNS = [
    "event", "time_s", "body", "other", "kind", "height_m", "face_water_level_m", "body_clearance_m", "afloat",
    "point_x_m", "point_y_m", "point_z_m",
    "normal_x", "normal_y", "normal_z", "impact_velocity_m_s", "normal_velocity_in_m_s",
    "tangential_velocity_in_m_s", "obliquity_deg", "peak_force_N", "time_of_peak_s", "duration_s",
    "impulse_Ns", "rebound_normal_velocity_m_s", "rebound_u_m_s", "rebound_v_m_s", "rebound_w_m_s",
    "rebound_speed_m_s", "restitution", "force_history", "time_since_front_s",
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


def impact_events_path(case: str | Path) -> Path:
    """The runner's impact table of the case: impact_events.csv, or the case root's impacts.csv in
    a run folder that holds only that (the table's older name), so its rows stay in one file."""
    case = Path(case)
    path, old = case / IMPACT_EVENTS_CSV, case / _OLD_IMPACT_EVENTS_CSV
    return old if old.is_file() and not path.is_file() else path


def append_impact_event(case: str | Path, event: dict[str, Any]) -> None:
    """Append an impact event of contacts.json as a row of the runner's table (the header first
    when the table is new)."""
    e = event
    row = [e["event"], e["time_s"], e["body"], e["other"], e["kind"], *e["point_m"], *e["normal"],
           *e["velocity_in_m_s"], *e["velocity_out_m_s"], e["normal_velocity_in_m_s"], e["normal_velocity_out_m_s"],
           e["restitution"], e["obliquity_deg"], e["height_m"], e["peak_force_N"], e["duration_s"], e["impulse_Ns"],
           e["force_history"]]
    path = impact_events_path(case)
    new = not path.is_file()
    with open(path, "a", newline="") as fh:
        w = csv.writer(fh)
        if new:
            w.writerow(IMPACT_EVENT_COLUMNS)
        w.writerow(row)


def forget_impact_events_after(case: str | Path, time_s: float) -> None:
    """Drop the rows of the runner's table later than `time_s` (a stretch being computed again)."""
    path = impact_events_path(case)
    if not path.is_file():
        return
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh)]
    kept = [rows[0]] + [r for r in rows[1:] if float(r[1]) <= time_s]
    with open(path, "w", newline="") as fh:
        csv.writer(fh).writerows(kept)
