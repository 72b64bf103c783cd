"""The impacts table of a run: one row per contact event that was an impact.

From the runner's contact events (contacts.json) and each event's force history: where it
struck (``height_m``, the contact point's height on the column), the velocities in and out,
the pulse's metrics (:func:`orchestrator.results.metrics.impact_metrics`); then, from the
gauge and body tables, the water level at the column's face at that moment
(``face_water_level_m``, the study's definition of impact height), the body's lowest point
above the bed and whether it was ``afloat``. The column impacts' pulses, as force vectors on
the column, feed the column forces and response.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from orchestrator.contact.events import IMPACT_COLUMNS
from orchestrator.results.metrics import PulseMetrics, impact_metrics
from orchestrator.results.readers import CaseData, read_force_history

__all__ = ["AFLOAT_CLEARANCE_M", "FACE_GAUGE_REACH_M", "IMPACT_COLUMNS", "impact_context", "impact_rows"]

#: The pulses of column impacts: event number -> (time_s, force on the column (n, 3) N).
Pulses = dict[int, tuple[np.ndarray, np.ndarray]]


def impact_rows(data: CaseData, events: list[dict], missing: list[str]) -> tuple[pd.DataFrame, Pulses]:
    """(impacts.csv without the context columns, the column impacts' pulses) of the contact
    events; what is missing (a force history, a body unknown to the plan) goes to ``missing``."""
    rows, pulses = [], {}
    masses = data.body_masses_kg
    for e in events:
        if e.get("type", "impact") != "impact":
            continue
        history, metrics = _pulse(data, e, missing)
        n = np.asarray(e.get("normal", (0.0, 0.0, 0.0)), dtype=float)
        if history is not None and e.get("kind") == "column":
            # force on the column: along -n (n points from the column into the body)
            pulses[int(e["event"])] = (float(e["time_s"]) + history[0], np.outer(history[1], -n))
        rows.append(_impact_row(e, n, metrics, len(rows) + 1))
        if e.get("body") not in masses and masses:
            missing.append(f"impact event {e.get('event')}: body {e.get('body')!r} is not in plan.json")
    return pd.DataFrame(rows, columns=IMPACT_COLUMNS), pulses


def _pulse(data: CaseData, e: dict, missing: list[str]) -> tuple[tuple[np.ndarray, np.ndarray] | None, PulseMetrics]:
    """The event's force history (time from contact, force) and its metrics; a half-sine of the
    recorded peak and duration stands in for a missing history."""
    history_path = data.case / str(e.get("force_history", ""))
    history = read_force_history(history_path) if e.get("force_history") else None
    if history is not None:
        return history, impact_metrics(*history)
    missing.append(f"impact event {e.get('event')}: no force history ({history_path.name}); a half-sine of "
                   f"the recorded peak and duration stands in for it")
    peak, duration = float(e.get("peak_force_N", 0.0)), float(e.get("duration_s", 0.0))
    if peak > 0 and duration > 0:
        tt = np.linspace(0.0, duration, 201)
        history = (tt, peak * np.sin(np.pi * tt / duration))
        return history, impact_metrics(*history)
    return None, PulseMetrics(peak, 0.0, 0.0, duration, duration, float(e.get("impulse_Ns", 0.0)))


def _number(e: dict, key: str) -> float:
    """An event's number, NaN where it is absent or null (JSON's NaN: a wall strike's height)."""
    value = e.get(key)
    return np.nan if value is None else float(value)


def _impact_row(e: dict, n: np.ndarray, metrics: PulseMetrics, number: int) -> dict:
    """An impact's row of impacts.csv (the context columns left empty)."""
    point = np.asarray(e.get("point_m", (np.nan,) * 3), dtype=float)
    v_in = np.asarray(e.get("velocity_in_m_s", (np.nan,) * 3), dtype=float)
    v_out = np.asarray(e.get("velocity_out_m_s", (np.nan,) * 3), dtype=float)
    vn_in = abs(_number(e, "normal_velocity_in_m_s"))
    obliquity = _number(e, "obliquity_deg")
    return {
        "event": int(e.get("event", number)), "time_s": float(e["time_s"]), "body": e.get("body"),
        "other": e.get("other"), "kind": e.get("kind"), "height_m": _number(e, "height_m"),
        "face_water_level_m": np.nan, "body_clearance_m": np.nan, "afloat": None,
        "point_x_m": point[0], "point_y_m": point[1], "point_z_m": point[2],
        "normal_x": n[0], "normal_y": n[1], "normal_z": n[2],
        "impact_velocity_m_s": float(-(v_in @ n)),
        "normal_velocity_in_m_s": vn_in,
        "tangential_velocity_in_m_s": vn_in * math.tan(math.radians(obliquity)) if obliquity < 90 else np.nan,
        "obliquity_deg": obliquity, "peak_force_N": metrics.peak_N, "time_of_peak_s": metrics.time_of_peak_s,
        "duration_s": metrics.duration_s, "impulse_Ns": metrics.impulse_Ns,
        "rebound_normal_velocity_m_s": _number(e, "normal_velocity_out_m_s"),
        "rebound_u_m_s": v_out[0], "rebound_v_m_s": v_out[1], "rebound_w_m_s": v_out[2],
        "rebound_speed_m_s": float(np.linalg.norm(v_out)), "restitution": _number(e, "restitution"),
        "force_history": e.get("force_history", ""),
        "time_since_front_s": _number(e, "time_since_front_s"),  # a one-way strike's (the flow record's front)
    }


#: A body is afloat at an impact when its lowest point is this far above the gap it rests on.
AFLOAT_CLEARANCE_M = 0.005
#: The column-face gauge: on the column's width, at most this far upstream of its face (m).
FACE_GAUGE_REACH_M = 0.10


def _face_gauge(data: CaseData) -> str | None:
    """The gauge at the column's upstream face (the study's impact height is its water level)."""
    scene = data.scene
    if scene is None or scene.column is None or not data.plan:
        return None
    col = scene.column
    face = col.x_m - col.size_x_m / 2
    best = None
    for g in data.plan.gauges:
        dx = face - float(g.x)
        if 0.0 <= dx <= FACE_GAUGE_REACH_M and abs(float(g.y) - col.y_m) <= col.size_y_m / 2:
            if best is None or dx < best[0]:
                best = (dx, g.name)
    return best[1] if best else None


def impact_context(data: CaseData, impacts: pd.DataFrame, gauges: pd.DataFrame, bodies: pd.DataFrame,
                   missing: list[str]) -> pd.DataFrame:
    """Each impact's water level at the column's face (its gauge, interpolated at the impact time:
    the study's impact height), the body's lowest point above the bed, and whether it was afloat
    (lowest point more than AFLOAT_CLEARANCE_M above the gap a resting body stands on)."""
    if impacts.empty:
        return impacts
    out = impacts.copy()
    gauge = _face_gauge(data)
    column = f"{gauge}_elevation_m" if gauge else None
    if column and column in gauges:
        g = gauges[["time_s", column]].dropna()
        if len(g):
            out["face_water_level_m"] = np.interp(out["time_s"].to_numpy(float), g["time_s"], g[column])
    elif data.scene is not None and data.scene.column is not None:
        missing.append("no gauge at the column's upstream face: impacts.csv's water level there is the one-way "
                       "flow record's where there is one, else none (add a gauge with `at: column_upstream_face`)")
    sizes = {b.name: np.asarray(b.size_m, float) for b in data.debris}
    if bodies.empty or not sizes:
        return out
    gap = float(data.plan.bed_gap_m or 0.0) if data.plan else 0.0
    clearances = [_clearance(data, bodies, sizes, r.body, float(r.time_s)) for r in out.itertuples()]
    out["body_clearance_m"] = [np.nan if c is None else c for c in clearances]
    out["afloat"] = [None if c is None else bool(c > gap + AFLOAT_CLEARANCE_M) for c in clearances]
    return out


def _clearance(data: CaseData, bodies: pd.DataFrame, sizes: dict, body: str, time_s: float) -> float | None:
    """Height (m) of the body's lowest point above the bed at the track's row nearest ``time_s``
    (None when the body has no size in the plan or no track)."""
    track = bodies[bodies["body"] == body]
    if body not in sizes or track.empty:
        return None
    i = int(np.argmin(np.abs(track["time_s"].to_numpy(float) - time_s)))
    row = track.iloc[i]
    q_z = np.array([row["q_zx"], row["q_zy"], row["q_zz"]], dtype=float)
    return float(row["z_m"]) - float(np.abs(q_z) @ (sizes[body] / 2)) - data.bed_z_m
