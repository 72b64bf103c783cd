"""Contact events of a transport run: onsets found in MuJoCo's contact list, loads from the analytical model.

After every step the engine hands MuJoCo's contacts to :class:`EventBook`. Contacts with the
bed are not events (a body resting or sliding on it is in contact all the time). Every other
contact is keyed by (body, other): the column, a wall, or another body (the lower index
first). A key that was out of contact for at least ``separation_s`` (default 5 ms, about one
contact duration of the container law) and is in contact now is an **onset**; if the body
approaches at ``min_impact_velocity_m_s`` (default 0.05 m/s) or faster along the normal, an event is
opened with the body's state *before* the step that found the contact (its centre-of-mass
velocity ``v_in`` and angular velocity), the mean contact point and the normal from the
other thing into the body (slower onsets are touches: a body held against the column by
the flow makes and breaks contact every few milliseconds). While the key stays in contact (or comes back within
``separation_s``: chatter of a rocking body) it is the same event; whenever the key is found
out of contact after being in contact, the event's rebound is (re)written from the body's
velocity at that step, so it holds the velocity just after the last separation. The engine
calls :meth:`EventBook.observe` after every step with a contact or with pairs still touching.

Velocities are the centre of mass's: ``impact_velocity_m_s = normal_velocity_in_m_s =
-(v_in . n)``, the tangential part ``|v_in - (v_in . n) n|``, the obliquity ``atan2(tangential,
normal)``; the rebound's normal velocity ``v_out . n`` and ``restitution = (v_out . n) /
impact_velocity`` (for a body pair, of the relative velocity ``v_body - v_other``).

Column strikes: the pulse (peak force, time of peak, duration, impulse) and the peak base
shear come from :func:`analytical.contact_law.column_impact` with the body's contact law,
mass, size, wall thickness and friction, at the horizontal speed of its centre, the
obliquity of that velocity from the face's normal and the contact height above the bed: the
same model the coupled path resolves its strikes with, so a one-way and a two-way strike at
the same velocity give the same load. MuJoCo's own contact (the same spring and dashpot
against a rigid column) sets the rebound the body carries on with; its restitution is the
law's rigid-wall restitution. The pulses are computed at the end of the run
(:meth:`EventBook.finish`), so their cost is reported apart from the stepping (about 20 ms for
a column strike, benchmarks/analytical.md). With ``first_pulse_only`` a body's later
column strikes (its rebound sequence) are tabled with their velocities, heights and
obliquities but without a pulse (NaN loads), which is all an ensemble of starts reads.

Wall and body-body strikes: as on the coupled path, a wall strike is
:func:`analytical.impact.impact` on a rigid wall and a body-body strike
:func:`analytical.impact.pair_impact` (the two springs in series, the mean friction), each body
at its centre, orientation, velocity and angular velocity before the step that found the
contact, struck at the contact point along the contact normal. A wall strike's pulse is in
results/impacts.csv and its files; a body-body strike's peak force, duration and impulse are in the
body events table. Neither is computed with ``first_pulse_only``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import pandas as pd

from analytical.contact_law import column_impact
from analytical.errors import InputError
from analytical.impact import impact, pair_impact
from analytical.impact_bodies import Body, RigidWall, inverse_inertia_tensor
from orchestrator.contact.events import IMPACT_COLUMNS as RESULTS_IMPACT_COLUMNS
from orchestrator.contact.resolution import pair_contact_law

__all__ = ["AFLOAT_CLEARANCE_M", "BODY_EVENT_COLUMNS", "IMPACT_COLUMNS", "EventBook"]

IMPACT_COLUMNS = RESULTS_IMPACT_COLUMNS + ["peak_base_shear_N", "pulse_restitution"]
"""results/impacts.csv's columns (orchestrator.contact.events.IMPACT_COLUMNS) and two more: the
column model's peak base shear and its restitution (the column's vibration takes energy a rigid
MuJoCo column does not)."""

BODY_EVENT_COLUMNS = [
    "event", "time_s", "body", "other", "point_x_m", "point_y_m", "point_z_m", "normal_x", "normal_y", "normal_z",
    "approach_velocity_m_s", "separation_velocity_m_s", "restitution", "peak_force_N", "duration_s", "impulse_Ns",
]

AFLOAT_CLEARANCE_M = 0.005
"""A body is afloat at an impact when its lowest point is this far above the bed (the coupled
path's threshold, over its bed gap)."""


@dataclass
class _Event:
    number: int
    time_s: float
    body: int
    other: object  # body index (int) or the static geom's name (str)
    kind: str
    point: np.ndarray
    normal: np.ndarray
    v_in: np.ndarray
    v_other_in: np.ndarray | None
    clearance_m: float
    face_water_level_m: float
    v_out: np.ndarray | None = None
    v_other_out: np.ndarray | None = None
    # each body's centre, body-to-world rotation and world angular velocity before the step
    # (a wall or body-body pulse's inputs; the other's are None for a wall)
    state: tuple | None = None
    other_state: tuple | None = None


class EventBook:
    """Finds contact onsets step by step (module notes) and turns them into tables.

    ``owner`` maps each MuJoCo geom to a body index (>= 0) or a static kind (-1 bed, -2 wall,
    -3 column); ``geom_names`` names them; ``bodies`` are the :class:`TransportBody` list;
    ``body_ids`` their MuJoCo body ids, ``dof_adr`` their free joints' first dof;
    ``column`` the :class:`PlacedColumn` or None; ``surface(x, y, t)`` gives the water level
    (or None when there is no flow).
    """

    def __init__(self, owner, geom_names, bodies, body_ids, dof_adr, column=None, bed_z_m: float = 0.0,
                 separation_s: float = 0.005, surface=None, min_impact_velocity_m_s: float = 0.05,
                 first_pulse_only: bool = False):
        self.owner = np.asarray(owner)
        self.body_ids = np.asarray(body_ids)
        self.geom_names = list(geom_names)
        self.bodies = list(bodies)
        self.dof_adr = np.asarray(dof_adr)
        self.column = column
        self.bed_z_m = float(bed_z_m)
        self.separation_s = float(separation_s)
        self.surface = surface
        self.min_impact_velocity_m_s = float(min_impact_velocity_m_s)
        self.first_pulse_only = bool(first_pulse_only)
        self.last_seen: dict[tuple, float] = {}
        self.open: dict[tuple, _Event] = {}
        self.touching: set[tuple] = set()
        self.events: list[_Event] = []
        self.pulse_wall_s = 0.0
        self.pulses: dict = {}

    # ------------------------------------------------------------------ stepping
    def observe(self, time_s: float, data, qvel_before: np.ndarray, xmat: np.ndarray) -> None:
        """Read the contacts MuJoCo found at ``time_s`` (the state before the step)."""
        n = data.ncon
        current: dict[tuple, list[int]] = {}
        if n:
            geoms = data.contact.geom
            own = self.owner[geoms]
            keep = np.nonzero((own[:, 0] != -1) & (own[:, 1] != -1))[0]
            for r in keep:
                a, b = own[r]
                if a >= 0 and b >= 0:
                    key = (min(a, b), int(max(a, b)))
                elif a >= 0:
                    key = (int(a), self.geom_names[geoms[r, 1]])
                else:
                    key = (int(b), self.geom_names[geoms[r, 0]])
                current.setdefault(key, []).append(int(r))
        for key, rows in current.items():
            last = self.last_seen.get(key)
            if last is None or time_s - last > self.separation_s:
                self._open(key, rows, time_s, data, qvel_before, xmat)
            self.last_seen[key] = time_s
        for key in self.touching - current.keys():  # separated during this step
            event = self.open.get(key)
            if event is not None:
                event.v_out = self._velocity(data.qvel, key[0])
                if isinstance(key[1], int):
                    event.v_other_out = self._velocity(data.qvel, key[1])
        self.touching = set(current)

    def _velocity(self, qvel, body: int) -> np.ndarray:
        adr = self.dof_adr[body]
        return np.array(qvel[adr:adr + 3], dtype=float)

    def _state(self, data, qvel, xmat, body: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(centre, rotation, world angular velocity): a free joint's rates are body-frame."""
        rot = np.array(xmat[body], dtype=float).reshape(3, 3)
        adr = self.dof_adr[body]
        return (np.array(data.xpos[self.body_ids[body]], dtype=float), rot,
                rot @ np.asarray(qvel[adr + 3:adr + 6], dtype=float))

    def _open(self, key, rows, time_s, data, qvel_before, xmat) -> None:
        body, other = key
        geom1_owner = self.owner[data.contact.geom[rows[0], 0]]
        normal = np.array(data.contact.frame[rows[0], :3], dtype=float)  # from geom1 into geom2
        if geom1_owner == body:
            normal = -normal
        point = np.asarray(data.contact.pos[rows], dtype=float).mean(axis=0)
        if isinstance(other, int):
            kind, v_other = "body", self._velocity(qvel_before, other)
        else:
            kind = "column" if other == "column" else "wall"
            v_other = None
        adr = self.dof_adr[body]
        v_in = np.array(qvel_before[adr:adr + 3], dtype=float)
        if -float((v_in - (v_other if v_other is not None else 0.0)) @ normal) < self.min_impact_velocity_m_s:
            self.open.pop(key, None)  # the earlier strike's rebound is final
            return  # a touch, not a strike: a body pressed against the column by the flow
        rot = xmat[body].reshape(3, 3)
        half = np.asarray(self.bodies[body].size_m) / 2.0
        centre_z = float(data.xpos[self.body_ids[body]][2])
        clearance = centre_z - float(np.abs(rot[2, :]) @ half) - self.bed_z_m
        level = math.nan
        if kind == "column" and self.surface is not None:
            c = self.column
            try:
                level = float(self.surface(c.x_m - c.column.size_x_m / 2.0 - 0.01, c.y_m, time_s))
            except InputError:
                level = math.nan
        event = _Event(len(self.events) + 1, time_s, body, other, kind, point, normal, v_in, v_other, clearance,
                       level, state=self._state(data, qvel_before, xmat, body),
                       other_state=self._state(data, qvel_before, xmat, other) if kind == "body" else None)
        self.events.append(event)
        self.open[key] = event

    # ------------------------------------------------------------------ tables
    def finish(self) -> tuple[pd.DataFrame, pd.DataFrame]:
        """The impacts table (column and wall strikes, :data:`IMPACT_COLUMNS`) and the body-body
        events (:data:`BODY_EVENT_COLUMNS`); computes the column pulses."""
        start = time.perf_counter()
        impacts, pairs = [], []
        struck: set[int] = set()
        for e in self.events:  # in time order
            if e.kind == "body":
                pairs.append(self._pair_row(e))
            else:
                # first_pulse_only: a pulse for each body's first column strike only
                pulse = not self.first_pulse_only or (e.kind == "column" and e.body not in struck)
                impacts.append(self._impact_row(e, pulse=pulse))
                if e.kind == "column":
                    struck.add(e.body)
        self.pulse_wall_s = time.perf_counter() - start
        return (pd.DataFrame(impacts, columns=IMPACT_COLUMNS), pd.DataFrame(pairs, columns=BODY_EVENT_COLUMNS))

    def _pair_row(self, e: _Event) -> dict:
        n = e.normal
        rel_in = e.v_in - e.v_other_in
        approach = float(-(rel_in @ n))
        sep = math.nan
        if e.v_out is not None and e.v_other_out is not None:
            sep = float((e.v_out - e.v_other_out) @ n)
        loads = {} if self.first_pulse_only else self._pair_pulse(e)
        return {"event": e.number, "time_s": e.time_s, "body": self.bodies[e.body].name,
                "other": self.bodies[e.other].name, "point_x_m": e.point[0], "point_y_m": e.point[1],
                "point_z_m": e.point[2], "normal_x": n[0], "normal_y": n[1], "normal_z": n[2],
                "approach_velocity_m_s": approach, "separation_velocity_m_s": sep,
                "restitution": sep / approach if approach > 0 else math.nan,
                "peak_force_N": loads.get("peak_force_N", math.nan), "duration_s": loads.get("duration_s", math.nan),
                "impulse_Ns": loads.get("impulse_Ns", math.nan)}

    def _impact_row(self, e: _Event, pulse: bool = True) -> dict:
        n = e.normal
        v = e.v_in
        vn = float(-(v @ n))
        tangential = float(np.linalg.norm(v + vn * n))
        obliquity = math.degrees(math.atan2(tangential, vn)) if vn > 0 else math.nan
        height = float(e.point[2]) - self.bed_z_m
        loads = {} if not pulse else self._pulse(e, height) if e.kind == "column" else self._wall_pulse(e)
        v_out = e.v_out if e.v_out is not None else np.full(3, math.nan)
        rebound = float(v_out @ n)
        return {
            "event": e.number, "time_s": e.time_s, "body": self.bodies[e.body].name, "other": e.other,
            "kind": e.kind, "height_m": height if e.kind == "column" else math.nan,
            "face_water_level_m": e.face_water_level_m, "body_clearance_m": e.clearance_m,
            "afloat": bool(e.clearance_m > AFLOAT_CLEARANCE_M),
            "point_x_m": e.point[0], "point_y_m": e.point[1], "point_z_m": e.point[2],
            "normal_x": n[0], "normal_y": n[1], "normal_z": n[2], "impact_velocity_m_s": vn,
            "normal_velocity_in_m_s": vn, "tangential_velocity_in_m_s": tangential, "obliquity_deg": obliquity,
            "peak_force_N": loads.get("peak_force_N", math.nan), "time_of_peak_s": loads.get("time_of_peak_s", math.nan),
            "duration_s": loads.get("duration_s", math.nan), "impulse_Ns": loads.get("impulse_Ns", math.nan),
            "rebound_normal_velocity_m_s": rebound, "rebound_u_m_s": v_out[0], "rebound_v_m_s": v_out[1],
            "rebound_w_m_s": v_out[2], "rebound_speed_m_s": float(np.linalg.norm(v_out)),
            "restitution": rebound / vn if vn > 0 else math.nan, "force_history": "",
            "peak_base_shear_N": loads.get("peak_base_shear_N", math.nan),
            "pulse_restitution": loads.get("restitution", math.nan),
        }

    def _pulse(self, e: _Event, height_m: float) -> dict:
        """column_impact at the horizontal speed of the centre and its obliquity from the face normal."""
        body = self.bodies[e.body]
        col = self.column.column
        n_h = np.array([e.normal[0], e.normal[1], 0.0])
        v_h = np.array([e.v_in[0], e.v_in[1], 0.0])
        speed = float(np.linalg.norm(v_h))
        if speed <= 0.0 or np.linalg.norm(n_h) == 0.0:
            return {}
        n_h /= np.linalg.norm(n_h)
        obliquity = math.degrees(math.acos(max(-1.0, min(1.0, float(-(v_h @ n_h)) / speed))))
        if obliquity >= 89.0:
            return {}
        height = min(max(height_m, 1e-6 * col.height_m), col.height_m)
        result = column_impact(body.contact, speed, height, column=col, obliquity_deg=obliquity,
                               mass_kg=body.mass_kg, size_m=body.size_m, wall_thickness_m=body.wall_thickness_m,
                               friction_coefficient=body.friction_coefficient)
        self.pulses[e.number] = result
        shear = result.base_shear
        return {**_loads(result), "peak_base_shear_N": abs(shear.peak_N) if shear is not None else math.nan}

    def _body(self, index: int, state: tuple, velocity: np.ndarray) -> Body:
        """An analytical impact body from a transport body's state at the event."""
        body = self.bodies[index]
        centre, rot, omega = state
        return Body(body.mass_kg, inverse_inertia_tensor(body.inertia_kg_m2, rot), centre, velocity, omega)

    def _wall_pulse(self, e: _Event) -> dict:
        """:func:`analytical.impact.impact` on a rigid wall with the body's own law and friction (the
        coupled path's wall strikes)."""
        body = self.bodies[e.body]
        try:
            result = impact(self._body(e.body, e.state, e.v_in), e.point, e.normal, RigidWall(),
                            friction_coefficient=body.friction_coefficient, **body.contact.options())
        except InputError:  # the contact point is not approaching the wall (a spinning body's glance)
            return {}
        self.pulses[e.number] = result
        return _loads(result)

    def _pair_pulse(self, e: _Event) -> dict:
        """:func:`analytical.impact.pair_impact`: the two bodies' springs in series, their mean
        friction (the coupled path's body-body strikes)."""
        a, b = self.bodies[e.body], self.bodies[e.other]
        law = pair_contact_law(a.contact, b.contact)
        try:
            result = pair_impact(self._body(e.body, e.state, e.v_in), self._body(e.other, e.other_state, e.v_other_in),
                                 e.point, e.normal, friction_coefficient=0.5 * (a.friction_coefficient +
                                                                                b.friction_coefficient),
                                 **law.options())
        except InputError:
            return {}
        return _loads(result)


def _loads(result) -> dict:
    """Peak force, time of peak, duration and impulse of an analytical impact."""
    hist = result.history
    return {"peak_force_N": result.peak_force_N,
            "time_of_peak_s": float(hist.time_s[int(np.argmax(hist.force_N))]) if len(hist.time_s) else math.nan,
            "duration_s": result.duration_s, "impulse_Ns": result.impulse_Ns, "restitution": result.restitution}
