"""Every column strike of a design realisation as it strikes, and which debris the inundation carries.

**Carried or grounded.** A body floats when its draft, ``mass / (rho_w L W)`` (its plan area
``L W`` upright, the flow's water density), is less than the deepest water at its start (the
record's surface over the bed at its centre's plan position, over the run's frames): the
inundation there can lift it. One that cannot (a loaded container in a shallow case) is not
carried: it stays out of the transport, its row says ``carried`` False with its draft and that
depth, its demands are 0, and the page counts it (:func:`carried`).

**Each strike.** A body's every column strike (the engine gives each its pulse,
``every_column_pulse``) is one row of design.csv (:func:`strike_rows`), with:

* ``face``: the column's face struck, the one whose outward normal is nearest the contact
  normal (``upstream``: facing -x, the flow's way in; ``downstream``; ``side +y``; ``side -y``);
* ``obliquity_deg``: the angle in plan between the body's centre velocity just before the
  strike and the face's inward normal (0: square on; 90: grazing), ``atan2(|v_t|, v_n)``;
* ``eccentricity_m``: the contact point's offset from the face's centre line along the face,
  signed along ``z x n`` (``n`` the face's outward normal), and ``torsion_Nm`` the torsion the
  strike's peak force gives the member about its axis, ``peak force x eccentricity`` (positive
  counter-clockwise seen from above);
* ``flow_speed_m_s`` and ``flow_speed_max_m_s``: the water the body came in with: over the
  last body length it travelled before the strike (its track, every output interval), the
  largest depth-averaged horizontal speed at its centre's plan position, and the fastest
  horizontal speed anywhere over that depth (:func:`approach_flow`). A floating body is carried
  by the water at its draft, near the surface, which can be faster than the depth average: a
  strike faster than ``flow_speed_max_m_s`` is one the water around it does not explain.

**The front.** A body the bore's front picks up can ride it at the front's own speed, faster than
the water behind it; :func:`front_celerity` measures that speed in each case's record.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from orchestrator.transport.flow import FlowCoverageError, FlowField
from orchestrator.scene.schema import DebrisBody
from orchestrator.transport.mujoco_model import PlacedColumn

__all__ = ["FACES", "FLOW_LEVELS", "approach_flow", "carried", "draft_m", "front_celerity", "start_depth_m",
           "strike_geometry", "strike_rows"]

#: The column's faces by their outward normal (plan): the flow comes from -x.
FACES = {"upstream": (-1.0, 0.0), "downstream": (1.0, 0.0), "side +y": (0.0, 1.0), "side -y": (0.0, -1.0)}

#: Levels over the depth at which the water's speed is sampled (mid-points of equal slices).
FLOW_LEVELS = 8

#: Times along the approach (the last body length) at which the water is sampled, at most.
APPROACH_SAMPLES = 12


def draft_m(body: DebrisBody, density_kg_m3: float) -> float:
    """A body's draft upright: its mass over the water of its plan area, ``m / (rho L W)``."""
    return float(body.mass_kg) / (float(density_kg_m3) * float(body.size_m[0]) * float(body.size_m[1]))


def start_depth_m(flow: FlowField, points: Sequence[tuple[float, float]], t0_s: float, t_end_s: float) -> np.ndarray:
    """The deepest water at each plan point over the record's frames in ``[t0, t0 + t_end]``."""
    xy = np.asarray(points, dtype=float).reshape(-1, 2)
    frames = flow.t_s[(flow.t_s >= t0_s - 1e-12) & (flow.t_s <= t0_s + t_end_s + 1e-12)]
    deepest = np.full(len(xy), -np.inf)
    for t in frames:
        deepest = np.maximum(deepest, flow.surface(xy[:, 0], xy[:, 1], float(t)))
    return np.maximum(deepest - flow.bed_z_m, 0.0)


def carried(starts: Sequence[Sequence[DebrisBody]], flow: FlowField, t0_s: float,
            t_end_s: float) -> list[list[tuple[float, float, bool]]]:
    """For each realisation's bodies: (draft, deepest water at the start, floats) (module notes)."""
    flat = [b for bodies in starts for b in bodies]
    depths = start_depth_m(flow, [b.centre_m[:2] for b in flat], t0_s, t_end_s) if flat else np.zeros(0)
    out, k = [], 0
    for bodies in starts:
        row = []
        for b in bodies:
            draft = draft_m(b, flow.water_density_kg_m3)
            row.append((draft, float(depths[k]), bool(draft < depths[k])))
            k += 1
        out.append(row)
    return out


def strike_geometry(point, normal, velocity, column: PlacedColumn, peak_force_N: float) -> dict[str, Any]:
    """The face struck, the obliquity of the centre velocity to its normal, the contact point's
    eccentricity on it and the torsion the peak force gives the member (module notes).
    ``normal``: the contact normal out of the column towards the body."""
    n = np.asarray(normal, dtype=float)[:2]
    face = max(FACES, key=lambda k: float(np.dot(FACES[k], n)))
    nf = np.array(FACES[face])
    v = np.asarray(velocity, dtype=float)
    vn = -float(v[:2] @ nf)
    vt = abs(float(v[:2] @ np.array([-nf[1], nf[0]])))  # along the face
    obliquity = math.degrees(math.atan2(vt, vn)) if (vn != 0.0 or vt != 0.0) else math.nan
    tangent = np.array([-nf[1], nf[0]])  # z x n
    offset = np.asarray(point, dtype=float)[:2] - np.array([column.x_m, column.y_m])
    eccentricity = float(offset @ tangent)
    force = float(peak_force_N) if math.isfinite(float(peak_force_N)) else math.nan
    return {"face": face, "obliquity_deg": obliquity, "eccentricity_m": eccentricity,
            "torsion_Nm": force * eccentricity}


def water_column(flow: FlowField, x_m: float, y_m: float, t_s: float) -> tuple[float, float]:
    """(depth-averaged horizontal speed, fastest horizontal speed over the depth) at a plan point."""
    eta = float(flow.surface(np.array([x_m]), np.array([y_m]), t_s)[0])
    depth = eta - flow.bed_z_m
    if depth <= 0.0:
        return 0.0, 0.0
    z = flow.bed_z_m + (np.arange(FLOW_LEVELS) + 0.5) / FLOW_LEVELS * depth
    pts = np.column_stack([np.full(FLOW_LEVELS, x_m), np.full(FLOW_LEVELS, y_m), z])
    u = flow.sample(pts, t_s, acceleration=False).velocity_m_s[:, :2]
    return float(np.hypot(*u.mean(axis=0))), float(np.max(np.hypot(u[:, 0], u[:, 1])))


def approach_flow(flow: FlowField, track, time_s: float, speed_m_s: float, length_m: float,
                  t0_s: float) -> tuple[float, float]:
    """The water the body came in with (module notes): over its last ``length_m`` of travel
    before ``time_s`` (``track``: its rows of the tracks table), the largest depth-averaged
    horizontal speed at its centre and the fastest anywhere over the depth; NaN off the record."""
    window = length_m / max(float(speed_m_s), 1e-9)
    rows = track[(track["time_s"] <= time_s + 1e-12) & (track["time_s"] >= time_s - window)]
    if not len(rows):
        return math.nan, math.nan
    rows = rows.iloc[np.unique(np.linspace(0, len(rows) - 1, min(len(rows), APPROACH_SAMPLES)).round().astype(int))]
    mean, fastest = 0.0, 0.0
    try:
        for x, y, t in zip(rows["x_m"], rows["y_m"], rows["time_s"]):
            a, b = water_column(flow, float(x), float(y), t0_s + float(t))
            mean, fastest = max(mean, a), max(fastest, b)
    except FlowCoverageError:
        return math.nan, math.nan
    return mean, fastest


def front_celerity(flow: FlowField, column: PlacedColumn) -> float | None:
    """The flow's front speed on the column's line, from its arrivals 8 and 3 column widths
    upstream of the face (out of the column's reflected wave); None where the record does not
    cover them or the front does not pass both."""
    width = column.column.size_x_m
    face = column.x_m - width / 2.0
    x0, x1 = face - 8.0 * width, face - 3.0 * width
    try:
        t0, t1 = flow.front_arrival_s(x0, column.y_m), flow.front_arrival_s(x1, column.y_m)
    except FlowCoverageError:
        return None
    if not (math.isfinite(t0) and math.isfinite(t1)) or t1 <= t0:
        return None
    return (x1 - x0) / (t1 - t0)


def strike_rows(result, body: DebrisBody, column: PlacedColumn, flow: FlowField | None,
                t0_s: float) -> list[dict[str, Any]]:
    """One dict per column strike of ``body`` in ``result`` (a transport of its realisation), in
    time order: the strike's speed and geometry (module notes), its pulse (None: not resolved)."""
    imp = result.impacts
    if not len(imp):
        return []
    mine = imp[(imp["kind"] == "column") & (imp["body"] == body.name)].sort_values("time_s", kind="stable")
    track = result.track(body.name) if flow is not None and len(mine) else None
    rows = []
    for k, (_, e) in enumerate(mine.iterrows(), start=1):
        state = result.strike_states.get(int(e["event"]))
        velocity = state[2] if state is not None else np.full(3, math.nan)
        speed = float(np.linalg.norm(velocity))
        pulse = result.pulses.get(int(e["event"]))
        peak = float(pulse.peak_force_N) if pulse is not None else math.nan
        point = (float(e["point_x_m"]), float(e["point_y_m"]))
        normal = (float(e["normal_x"]), float(e["normal_y"]), float(e["normal_z"]))
        mean, fastest = (approach_flow(flow, track, float(e["time_s"]), speed, float(body.size_m[0]), t0_s)
                         if track is not None else (math.nan, math.nan))
        rows.append({"strike": k, "impact_time_s": float(e["time_s"]), "impact_speed_m_s": speed,
                     "impact_velocity_m_s": float(e["normal_velocity_in_m_s"]), "flow_speed_m_s": mean,
                     "flow_speed_max_m_s": fastest, "impact_height_m": float(e["height_m"]),
                     **strike_geometry(point, normal, velocity, column, peak),
                     "duration_s": float(e["duration_s"]), "impulse_Ns": float(e["impulse_Ns"]), "pulse": pulse})
    return rows
