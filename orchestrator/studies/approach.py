"""The approach to the column: how the one-way strike speed depends on the record and the forcing.

The one-way container slows in the last few centimetres before the column, in the column's
stagnation zone, where the recorded flow (no body in it) is least like the flow the body meets.
This study carries the 1-debris scene's container through its flow records and measures the
first column strike (time, total speed, its normal part, heading) and the speed against the
nose's distance to the face, for:

* the record's frame rate: a record written at 200 Hz, and the same record thinned to 100 and
  50 Hz (:func:`thinned`: the frame nearest each multiple of the interval, as a recorder at that
  rate writes the first step at or past it);
* the record's cell size near the column: flows with a refinement box round the approach
  (``mesh.refine_box_m``, :mod:`orchestrator.plan.refine`), each its own run;
* the forcing near the face (:class:`ApproachFlow`): the undisturbed flow at the body's
  sub-volumes (the default), or the approach flow frozen at a reach upstream of the face, so
  that the body does not feel the column's stagnation zone in the flow without it (the bound
  for a body that carries its own flow into the gap it closes);

and writes the force budget (:mod:`orchestrator.transport.budget`) of the default run over the
last 0.3 m. ``python -m orchestrator.studies.approach`` (``make approach``) writes
docs/results/approach/ (:mod:`orchestrator.studies.approach_report`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.case.folder import CaseFolder
from orchestrator.core.errors import InputError
from orchestrator.scene.scenefile import load_scene
from orchestrator.transport.budget import force_budget
from orchestrator.transport.case_transport import scene_settings, transport_setup
from orchestrator.transport.engine import run_transport
from orchestrator.transport.flow import FlowField

__all__ = ["ApproachFlow", "ApproachRun", "Strike", "carry", "coupled_run", "face_distance", "strike_of", "thinned"]

#: The budget and the plots reach this far upstream of the face (m).
APPROACH_REACH_M = 0.3
#: A body has begun to slow for the column once it has lost this share of its speed 0.3 m out.
SLOWED = 0.05


class ApproachFlow:
    """A record whose flow near the column's upstream face is the flow ``reach_m`` upstream of it.

    A point closer than ``reach_m`` to the face (``x > x_face - reach_m``) and within
    ``reach_m`` of the column's sides across the flume is sampled at ``x_face - reach_m``, same
    y and z: the body is carried by the approach flow, not by the stagnation zone the column
    makes in a flow without the body. Everything else is the record's (attributes pass through).
    """

    def __init__(self, flow: FlowField, x_face_m: float, y_column_m: tuple[float, float], reach_m: float):
        if reach_m <= 0:
            raise InputError("reach_m", f"must be > 0, got {reach_m}")
        self._flow = flow
        self.x_stop = float(x_face_m) - float(reach_m)
        self.y_band = (float(y_column_m[0]) - reach_m, float(y_column_m[1]) + reach_m)

    def __getattr__(self, name):
        return getattr(self._flow, name)

    def _moved(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        near = (x > self.x_stop) & (y >= self.y_band[0]) & (y <= self.y_band[1])
        return np.where(near, self.x_stop, x)

    def locate(self, x_m, y_m, t_s):
        """The record's `locate` of the moved points: what `surface` and `sample` take."""
        return self._flow.locate(self._moved(x_m, y_m), y_m, t_s)

    def surface(self, x_m, y_m, t_s, located=None):
        return self._flow.surface(self._moved(x_m, y_m), y_m, t_s, located=located)

    def sample(self, points_m, t_s, acceleration=True, eta_m=None, located=None):
        p = np.array(points_m, float).reshape(-1, 3)
        p[:, 0] = self._moved(p[:, 0], p[:, 1])
        return self._flow.sample(p, t_s, acceleration=acceleration, eta_m=eta_m, located=located)


def thinned(flow: FlowField, rate_hz: float) -> FlowField:
    """``flow`` with only the frame nearest each multiple of ``1 / rate_hz`` (and its first)."""
    t = flow.t_s
    targets = np.arange(t[0], t[-1] + 1e-9, 1.0 / rate_hz)
    keep = np.unique(np.concatenate([[0], np.abs(t[None, :] - targets[:, None]).argmin(axis=1), [t.size - 1]]))
    if keep.size < 2:
        raise InputError("rate_hz", f"{rate_hz:g} Hz leaves fewer than two frames of the record")
    return FlowField(t[keep], flow.x_m, flow.y_m, flow.z_m, flow.bed_z_m, flow.eta_m[keep], flow.velocity_m_s[keep],
                     flow.water_density_kg_m3, flow.gravity_m_s2, {**flow.meta, "thinned_to_hz": rate_hz})


def face_distance(track: pd.DataFrame, size_m, x_face_m: float) -> np.ndarray:
    """The gap between the body's most downstream corner and the face (m) at each row of ``track``."""
    half = np.asarray(size_m, float) / 2.0
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    rot = track[[f"q_{a}{b}" for a in "xyz" for b in "xyz"]].to_numpy(float).reshape(-1, 3, 3)
    x = track["x_m"].to_numpy(float)[:, None] + np.einsum("tij,nj->tni", rot, corners)[:, :, 0]
    return x_face_m - x.max(axis=1)


@dataclass(frozen=True)
class Strike:
    """The first column strike: time (s), total and normal speed (m/s), heading (yaw, deg),
    obliquity (deg), the body's speed when its nose was 0.1 and 0.3 m from the face (m/s), and
    the nose's distance to the face (m) where the body had first lost `SLOWED` of its speed 0.3 m out."""

    time_s: float
    speed_m_s: float
    normal_m_s: float
    yaw_deg: float
    obliquity_deg: float
    speed_at_0p1_m_s: float
    speed_at_0p3_m_s: float
    slowed_at_gap_m: float = float("nan")


@dataclass(frozen=True)
class ApproachRun:
    """One carry: its label, what it varies, its strike (None: no column strike) and its track
    up to the strike with the nose's distance to the face (``gap_m``)."""

    label: str
    cell_m: float
    rate_hz: float
    forcing: str
    strike: Strike | None
    track: pd.DataFrame


def strike_of(impacts: pd.DataFrame, track: pd.DataFrame) -> Strike | None:
    """The first column strike of ``impacts`` (the engine's table) with the track's speeds before it."""
    hits = impacts[impacts["kind"] == "column"].sort_values("time_s")
    if hits.empty:
        return None
    hit = hits.iloc[0]
    before = track[track["time_s"] <= float(hit["time_s"])]
    then = before.iloc[-1]

    def speed_at(gap: float) -> float:
        far = before[before["gap_m"] >= gap]
        return float(far.iloc[-1]["speed_m_s"]) if len(far) else float("nan")

    normal = float(hit["normal_velocity_in_m_s"])
    far = speed_at(APPROACH_REACH_M)
    near = before[(before["gap_m"] < APPROACH_REACH_M) & (before["speed_m_s"] < (1.0 - SLOWED) * far)]
    return Strike(float(hit["time_s"]), float(np.hypot(normal, hit["tangential_velocity_in_m_s"])), normal,
                  float(then["yaw_deg"]), float(hit["obliquity_deg"]), speed_at(0.1), far,
                  float(near.iloc[0]["gap_m"]) if len(near) else float("nan"))


def _to_strike(track: pd.DataFrame, impacts: pd.DataFrame, size_m, x_face_m: float
               ) -> tuple[pd.DataFrame, Strike | None]:
    """A body's track with the nose's gap to the face (``gap_m``), cut at its first column strike."""
    track = track.assign(gap_m=face_distance(track, size_m, x_face_m))
    strike = strike_of(impacts, track)
    if strike is not None:
        track = track[track["time_s"] <= strike.time_s].reset_index(drop=True)
    return track, strike


def carry(scene_path: Path, flow, *, label: str, cell_m: float, rate_hz: float, forcing: str = "undisturbed",
          end_time_s: float | None = None, output_interval_s: float = 0.002,
          budget: bool = False) -> tuple[ApproachRun, pd.DataFrame | None]:
    """Carry the scene's bodies through ``flow`` (a FlowField or an :class:`ApproachFlow`); the first
    body's strike and track, and with ``budget`` its force budget over the last 0.3 m."""
    scene = load_scene(scene_path)
    bodies, flume, column = transport_setup(scene, flow)
    if column is None:
        raise InputError(str(scene_path), "the scene has no column to approach")
    settings = dataclasses.replace(scene_settings(scene), output_interval_s=output_interval_s)
    t_end = float(end_time_s or min(scene.run.end_time_s, flow.t_s[-1] - flow.t_s[0]))
    result = run_transport(bodies, flume, t_end, flow=flow, column=column, settings=settings)
    body = bodies[0]
    x_face = scene.column.x_m - scene.column.size_x_m / 2
    track, strike = _to_strike(result.track(body.name), result.impacts, body.size_m, x_face)
    table = None
    if budget:
        near = track[track["gap_m"] <= APPROACH_REACH_M + 0.05]
        near = track.iloc[max(0, near.index[0] - 1):] if len(near) else track.iloc[-3:]
        table = force_budget(near, flow, body.size_m, body.mass_kg, settings.hydro)
        table = table.assign(gap_m=face_distance(near.iloc[1:-1].reset_index(drop=True), body.size_m, x_face))
    return ApproachRun(label, cell_m, rate_hz, forcing, strike, track), table


def coupled_run(case: Path, *, label: str, cell_m: float) -> ApproachRun | None:
    """A finished or stopped two-way run of the same scene (its results/bodies.csv and impacts.csv,
    `debrisfoam post`) as a carry: the body in the flow it changes. None if it has no tables."""
    bodies, impacts = case / "results" / "bodies.csv", case / "results" / "impacts.csv"
    if not (bodies.is_file() and impacts.is_file()):
        return None
    scene = CaseFolder(case).scene()
    body = scene.debris[0]
    track = pd.read_csv(bodies).query("body == @body.name").reset_index(drop=True)
    track, strike = _to_strike(track, pd.read_csv(impacts).query("body == @body.name"), body.size_m,
                               scene.column.x_m - scene.column.size_x_m / 2)
    rate = round(1.0 / float(np.median(np.diff(track["time_s"])))) if len(track) > 2 else float("nan")
    return ApproachRun(label, cell_m, rate, "two-way (the body in the flow)", strike, track)
