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

Strikes (column, wall and body-body onsets at ``min_impact_velocity_m_s`` or faster) are
resolved by the engine the moment they are found, from the bodies' own state before the step:
centre, orientation, velocity and spin, mass and rotational inertia, and the added mass of the
water each carries along the contact normal (anisotropic: a container struck end-on carries
far less water than one struck broadside, :mod:`analytical.added_mass`). The resolution is the
coupled path's (:func:`orchestrator.contact.resolution.resolve_bodies`): a column strike is
:func:`analytical.impact.impact` on the column's MDOF model at the contact point's height, a
wall strike the same on a rigid wall, a body-body strike :func:`analytical.impact.pair_impact`
(the two springs in series, the mean friction). The engine then sets the bodies' velocities to
the resolved rebound, so the impulse the column (wall, other body) takes is exactly the
momentum the body and its water lose: one law on one effective mass. :meth:`EventBook.strike`
keeps each result; the column's base shear (about 15 ms a strike) is computed at the end
(:meth:`EventBook.finish`) for the strikes that are reported, so its cost is counted apart from
the stepping. With ``first_pulse_only`` a body's later column strikes (its rebound sequence)
and the wall and body-body strikes are tabled without loads (NaN), which is all an ensemble of
starts reads; they are resolved all the same. ``every_column_pulse`` (the design study) gives
every column strike its pulse and still none to the walls and body pairs.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from analytical.impact import ColumnTarget, with_base_shear
from orchestrator.contact.events import IMPACT_COLUMNS as RESULTS_IMPACT_COLUMNS

__all__ = ["AFLOAT_CLEARANCE_M", "BODY_EVENT_COLUMNS", "IMPACT_COLUMNS", "EventBook"]

IMPACT_COLUMNS = RESULTS_IMPACT_COLUMNS + ["peak_base_shear_N", "pulse_restitution", "effective_mass_kg",
                                           "added_mass_along_normal_kg"]
"""results/impacts.csv's columns (orchestrator.contact.events.IMPACT_COLUMNS, among them a column
strike's time since the front reached the column's face, negative when the body struck ahead of
it) and four more: the column model's peak base shear, the strike's restitution, the body's
effective mass at the contact point along the normal (its mass, the water it carries and its
rotation) and the added mass of that water along the normal."""

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
    depth_m: float = 0.0  # penetration found at the onset (m)
    added_mass_normal_kg: float = math.nan  # the body's added mass along the normal at the strike
    v_out: np.ndarray | None = None
    v_other_out: np.ndarray | None = None
    # each body's centre, body-to-world rotation and world angular velocity before the step
    # (a wall or body-body pulse's inputs; the other's are None for a wall)
    state: tuple | None = None
    other_state: tuple | None = None
    result: object = None  # the resolved analytical.impact.ImpactResult (None: not approaching)


class EventBook:
    """Finds contact onsets step by step (module notes) and turns them into tables.

    ``owner`` maps each MuJoCo geom to a body index (>= 0) or a static kind (-1 bed, -2 wall,
    -3 column); ``geom_names`` names them; ``bodies`` are the carried :class:`~orchestrator.scene.schema.DebrisBody` list;
    ``body_ids`` their MuJoCo body ids, ``dof_adr`` their free joints' first dof;
    ``column`` the :class:`PlacedColumn` or None; ``surface(x, y, t)`` gives the water level
    (or None when there is no flow); ``front_at_face_s`` when the flow's front reached the
    column's face (NaN: no flow, no column, or it never did).
    """

    def __init__(self, owner, geom_names, bodies, body_ids, dof_adr, column=None, bed_z_m: float = 0.0,
                 separation_s: float = 0.005, surface=None, min_impact_velocity_m_s: float = 0.05,
                 first_pulse_only: bool = False, front_at_face_s: float = math.nan,
                 every_column_pulse: bool = False):
        self.owner = np.asarray(owner)
        self.front_at_face_s = float(front_at_face_s)
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
        self.every_column_pulse = bool(every_column_pulse)
        self.last_seen: dict[tuple, float] = {}
        self.open: dict[tuple, _Event] = {}
        self.touching: set[tuple] = set()
        self.events: list[_Event] = []
        self.pulse_wall_s = 0.0
        self.pulses: dict = {}

    # ------------------------------------------------------------------ stepping
    def observe(self, time_s: float, data, qvel_before: np.ndarray, xmat: np.ndarray) -> list["_Event"]:
        """Read the contacts MuJoCo found at ``time_s`` (the state before the step); return the
        strikes that begin in it (for the engine to resolve, :meth:`strike`)."""
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
        opened = []
        for key, rows in current.items():
            last = self.last_seen.get(key)
            if last is None or time_s - last > self.separation_s:
                event = self._open(key, rows, time_s, data, qvel_before, xmat)
                if event is not None:
                    opened.append(event)
            self.last_seen[key] = time_s
        for key in self.touching - current.keys():  # separated during this step
            event = self.open.get(key)
            if event is not None:
                event.v_out = self._velocity(data.qvel, key[0])
                if isinstance(key[1], int):
                    event.v_other_out = self._velocity(data.qvel, key[1])
        self.touching = set(current)
        return opened

    def strike(self, event: "_Event", result) -> None:
        """Keep the resolved impact of ``event`` (None: its contact point was not approaching)."""
        event.result = result
        if result is not None:
            event.v_out = np.array(result.velocity_out_m_s, dtype=float)
            if event.kind == "body" and result.other_velocity_out_m_s is not None:
                event.v_other_out = np.array(result.other_velocity_out_m_s, dtype=float)

    def _velocity(self, qvel, body: int) -> np.ndarray:
        adr = self.dof_adr[body]
        return np.array(qvel[adr:adr + 3], dtype=float)

    def _state(self, data, qvel, xmat, body: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(centre, rotation, world angular velocity): a free joint's rates are body-frame."""
        rot = np.array(xmat[body], dtype=float).reshape(3, 3)
        adr = self.dof_adr[body]
        return (np.array(data.xpos[self.body_ids[body]], dtype=float), rot,
                rot @ np.asarray(qvel[adr + 3:adr + 6], dtype=float))

    def _open(self, key, rows, time_s, data, qvel_before, xmat) -> "_Event | None":
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
            return None  # a touch, not a strike: a body pressed against the column by the flow
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
        event.depth_m = max(0.0, -float(np.min(data.contact.dist[rows])))
        self.events.append(event)
        self.open[key] = event
        return event

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
                # first_pulse_only: a pulse for each body's first column strike only (every
                # column strike's with every_column_pulse), none for the walls
                pulse = not self.first_pulse_only or (e.kind == "column" and (self.every_column_pulse
                                                                             or e.body not in struck))
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

    def strike_states(self) -> dict:
        """Each strike's body state before it, by event number: (centre, rotation, velocity,
        angular velocity), world frame (the inputs its resolution took)."""
        return {e.number: (e.state[0], e.state[1], e.v_in, e.state[2]) for e in self.events if e.state is not None}

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
            "effective_mass_kg": e.result.effective_mass_kg if e.result is not None else math.nan,
            "added_mass_along_normal_kg": e.added_mass_normal_kg,
            "time_since_front_s": e.time_s - self.front_at_face_s if e.kind == "column" else math.nan,
        }

    def _pulse(self, e: _Event, height_m: float) -> dict:
        """The resolved column strike's pulse with the column's base shear at the load cell."""
        if e.result is None:
            return {}
        col = self.column.column
        height = min(max(height_m, 1e-6 * col.height_m), col.height_m)
        result = with_base_shear(e.result, ColumnTarget(col, height))
        self.pulses[e.number] = result
        shear = result.base_shear
        return {**_loads(result), "peak_base_shear_N": abs(shear.peak_N) if shear is not None else math.nan}

    def _wall_pulse(self, e: _Event) -> dict:
        """The resolved wall strike's pulse (a rigid wall)."""
        if e.result is None:
            return {}
        self.pulses[e.number] = e.result
        return _loads(e.result)

    def _pair_pulse(self, e: _Event) -> dict:
        """The resolved body-body strike's pulse."""
        return {} if e.result is None else _loads(e.result)


def _loads(result) -> dict:
    """Peak force, time of peak, duration and impulse of an analytical impact."""
    hist = result.history
    return {"peak_force_N": result.peak_force_N,
            "time_of_peak_s": float(hist.time_s[int(np.argmax(hist.force_N))]) if len(hist.time_s) else math.nan,
            "duration_s": result.duration_s, "impulse_Ns": result.impulse_Ns, "restitution": result.restitution}
