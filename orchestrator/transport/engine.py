"""One-way coupled transport: debris boxes carried through a recorded flow on MuJoCo.

The flume study found that the debris barely changes the flow, so the flow is computed once
without bodies and recorded (:class:`~orchestrator.transport.flow.FlowField`), and any number
of bodies is then carried through the record by a rigid-body engine. This module runs that
engine: :func:`run_transport` builds the MuJoCo model (:mod:`~orchestrator.transport.mujoco_model`:
why MuJoCo, and how a contact law's stiffness and damping become MuJoCo's ``solref``), steps
it at a fixed time step to ``t_end_s``, applies the hydrodynamic forcing of
:mod:`analytical.hydrodynamics` and records tracks and contact events
(:mod:`~orchestrator.transport.events`).

The step
--------
* Time step: from the stiffest contact, at least 40 steps per contact period
  (``2 pi sqrt(m_eff / K)``; 2.3e-4 s for the 0.236 kg container on the calibrated law).
  Bodies have full six degrees of freedom (free joints), no upright constraint.
* Hydrodynamic forcing every ``hydro_interval_s`` (default 1 ms, a whole number of steps),
  held between updates (zero-order hold) in ``data.xfrc_applied`` (force and moment about the
  centre of mass, world frame). Its fastest time scales, a floating container's heave period
  (about 0.3 s) and the drag time constant (over 0.05 s at 4 m/s), are resolved by hundreds of
  updates, while the contact, 20 times faster, is resolved by the step itself.
* At each update the body's added mass ``C_a rho V_sub`` becomes the armature of its three
  translational degrees of freedom (an implicit added inertia: see
  :mod:`analytical.hydrodynamics` for why it is not a lagged force), and the contact
  ``solref`` of the body and of its pairs is rescaled to the new translational mass, so the
  contact stiffness stays the law's ``K`` afloat as well as dry.
* Flow time: ``flow_start_s + t`` (``flow_start_s`` defaults to the record's first time); the
  record must cover the run's whole time span, and every sub-volume's plan position at every
  update (else :class:`~orchestrator.transport.flow.FlowCoverageError`). Without a flow the
  bodies move in air (no forcing): the dry tests and launches.

Output: :class:`TransportResult`: ``tracks`` (bodies.csv's columns, every
``output_interval_s``), ``impacts`` (column and wall strikes), ``body_contacts`` (body-body
onsets), ``wall_s`` (the stepping), ``pulse_wall_s`` (the column pulses after it), the
resolved impacts by event number (``pulses``) and each strike's state before it
(``strike_states``: the body's centre, rotation, velocity and angular velocity, world frame).
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import mujoco
import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError, require_positive
from analytical.hydrodynamics import (
    HydroCoefficients,
    added_mass_table,
    hydro_loads,
    sub_volumes,
    submerged_fraction,
)
from analytical.impact_bodies import Body
from orchestrator.contact.resolution import pair_contact_law, resolve_bodies
from orchestrator.transport.events import EventBook
from orchestrator.transport.flow import FlowCoverageError, FlowField
from orchestrator.transport.mujoco_model import (
    FlumeBounds,
    PlacedColumn,
    angles_deg,
    build_model,
    contact_law_of,
    friction_of,
    inertia_kg_m2,
    rotation,
)
from orchestrator.scene.schema import DebrisBody

__all__ = ["BODY_COLUMNS", "DEPARTURE_COLUMNS", "TransportResult", "TransportSettings", "run_transport"]

BODY_COLUMNS = ["time_s", "body", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s", "speed_m_s",
                "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s", "yaw_deg", "pitch_deg", "roll_deg"] + [
                   f"q_{a}{b}" for a in "xyz" for b in "xyz"]
"""bodies.csv's columns (the coupled path's, orchestrator.results.post): world frame, the
angular velocity too; ``q_ab`` the body-to-world rotation."""

DEPARTURE_COLUMNS = ["body", "time_s", "end", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s", "speed_m_s"]
"""A body that reached an open end of the flume (:class:`~orchestrator.transport.mujoco_model.FlumeBounds`)
and left the run: when, which end, where and how fast."""


PARKING_HEIGHT_M = 1.0e3
"""Where a body that left the run waits, above the flume (each 10 m above the last)."""


@dataclass(frozen=True)
class TransportSettings:
    """How to run: output and forcing intervals (s), steps per contact period (>= 40), the
    largest step, the flow time of ``t = 0``, the re-arm time of contact events, the slowest
    approach that counts as an impact (m/s), whether only each body's first column strike gets
    its pulse (:class:`~orchestrator.transport.events.EventBook`) and the
    hydrodynamic coefficients (their density and gravity are replaced by the flow's)."""

    output_interval_s: float = 0.01
    hydro_interval_s: float = 1e-3
    steps_per_contact_period: int = 40
    max_timestep_s: float = 1e-3
    flow_start_s: float | None = None
    separation_s: float = 0.005
    min_impact_velocity_m_s: float = 0.05
    first_pulse_only: bool = False
    #: with ``first_pulse_only``: every column strike gets its pulse, not only a body's first
    #: (the design study: a realisation's demand is its largest strike); walls and pairs none
    every_column_pulse: bool = False
    hydro: HydroCoefficients = field(default_factory=HydroCoefficients)
    #: None: the run starts at t = 0. A speed (m/s): bodies that all start at rest begin at the
    #: last record frame up to which the water at every sub-volume of every body moves slower
    #: than it (:meth:`_Forcing.still_until`; the tracks begin there). A body at rest in its
    #: start pose (on the bed, or afloat at its draft) in water that slow stays where it is:
    #: what the skipped steps would compute is that it does not move.
    still_start_m_s: float | None = None

    def __post_init__(self):
        for name in ("output_interval_s", "hydro_interval_s", "max_timestep_s", "separation_s"):
            require_positive(f"transport.{name}", getattr(self, name))


#: the ensembles' still-water speed, as a fraction of the slowest approach that counts as an
#: impact (0.05 m/s at the study's flume, Froude-scaled): 5 mm/s there
STILL_WATER_FRACTION = 0.1


def ensemble_settings(settings: TransportSettings) -> TransportSettings:
    """``settings`` as the ensembles and the design study run them: only each body's first column
    strike gets its pulse, and the still water before the flow reaches the bodies is skipped
    (``still_start_m_s``, unless set: a tenth of ``min_impact_velocity_m_s``)."""
    still = settings.still_start_m_s
    if still is None:
        still = STILL_WATER_FRACTION * settings.min_impact_velocity_m_s
    return dataclasses.replace(settings, first_pulse_only=True, still_start_m_s=still)


@dataclass(frozen=True)
class TransportResult:
    """A transport run: tables (pandas), the step, and the wall-clock cost (s)."""

    tracks: pd.DataFrame
    impacts: pd.DataFrame
    body_contacts: pd.DataFrame
    wall_s: float
    pulse_wall_s: float
    timestep_s: float
    steps: int
    hydro_interval_s: float
    output_interval_s: float
    pulses: dict = field(default_factory=dict, repr=False)
    strike_states: dict = field(default_factory=dict, repr=False)
    departures: pd.DataFrame = field(default_factory=lambda: pd.DataFrame(columns=DEPARTURE_COLUMNS))

    def track(self, body: str) -> pd.DataFrame:
        """One body's rows, in time order."""
        return self.tracks[self.tracks["body"] == body].reset_index(drop=True)


class _Forcing:
    """The hydrodynamic forcing of all bodies at one flow time (vectorised over bodies)."""

    def __init__(self, flow: FlowField, bodies, coefficients: HydroCoefficients):
        self.flow = flow
        self.coeffs = coefficients
        self.size = np.array([b.size_m for b in bodies], dtype=float)
        self.local = np.stack([sub_volumes(b.size_m, coefficients.sub_volumes).centres_m for b in bodies])
        self.cell = self.size / np.asarray(coefficients.sub_volumes, float)
        self.names = [b.name for b in bodies]
        self.tables = None
        if coefficients.added_mass_coefficient is None:
            self.tables = np.stack([added_mass_table(b.size_m, coefficients.water_density_kg_m3) for b in bodies])

    def __call__(self, t_flow: float, com, rot, vel, omega, active=None):
        """Loads on the bodies ``active`` (indices; all when None), in that order."""
        if active is not None and len(active) < len(self.names):
            part = _Forcing.__new__(_Forcing)
            part.flow, part.coeffs = self.flow, self.coeffs
            part.size, part.local, part.cell = self.size[active], self.local[active], self.cell[active]
            part.names = [self.names[i] for i in active]
            part.tables = None if self.tables is None else self.tables[active]
            return part(t_flow, com[active], rot[active], vel[active], omega[active])
        pts = self._points(com, rot)
        flat = pts.reshape(-1, 3)
        try:
            located = self.flow.locate(flat[:, 0], flat[:, 1], t_flow)  # once, for the surface and the sample
            eta = self.flow.surface(flat[:, 0], flat[:, 1], t_flow, located).reshape(pts.shape[:2])
        except FlowCoverageError as err:
            outside = [n for n, p in zip(self.names, pts) if not self._inside(p)]
            raise FlowCoverageError(err.field, f"{err.rule} (t = {t_flow:.4g} s; bodies {outside})") from None
        half_z = 0.5 * np.einsum("bk,bk->b", np.abs(rot[:, 2, :]), self.cell)
        wet = submerged_fraction(pts[:, :, 2], half_z[:, None], eta) > 0.0
        if np.all(wet):  # the usual case once the water has come: no gather of the wet points
            sample = self.flow.sample(flat, t_flow, eta_m=eta.reshape(-1), located=located)
            u = sample.velocity_m_s.reshape(pts.shape)
            a = sample.material_acceleration_m_s2.reshape(pts.shape)
        else:
            u = np.zeros_like(pts)
            a = np.zeros_like(pts)
            if np.any(wet):
                w = wet.reshape(-1)
                part = located[:3] + tuple(field[w] for field in located[3:])
                sample = self.flow.sample(pts[wet], t_flow, eta_m=eta[wet], located=part)
                u[wet] = sample.velocity_m_s
                a[wet] = sample.material_acceleration_m_s2
        return hydro_loads(com, rot, vel, omega, self.size, pts, eta, u, a, self.coeffs, self.tables, self.local)

    def _points(self, com, rot) -> np.ndarray:
        """The sub-volume centres in the world (B, N, 3) of bodies posed at ``com``, ``rot``."""
        pts = np.matmul(self.local, rot.transpose(0, 2, 1).copy())  # contiguous: 2-3x faster
        pts += com[:, None, :]
        return pts

    def still_until(self, com, rot, t0: float, t_end: float, speed_m_s: float) -> float:
        """The last flow time of the record's frames in ``[t0, t0 + t_end]`` up to which the
        water at every sub-volume of the bodies posed at ``com``, ``rot`` moves slower than
        ``speed_m_s`` at every frame (``t0`` if it already moves at ``t0``). Between two frames
        the record's velocity is linear in time, so it is slower than that in between too."""
        pts = self._points(com, rot).reshape(-1, 3)
        frames = self.flow.t_s[(self.flow.t_s >= t0) & (self.flow.t_s <= t0 + t_end)]
        still = t0
        for t in frames:
            u = self.flow.sample(pts, float(t), acceleration=False).velocity_m_s
            if np.max(np.einsum("pk,pk->p", u, u)) >= speed_m_s * speed_m_s:
                break
            still = float(t)
        return still

    def outside(self, com, rot, x_range) -> np.ndarray:
        """Bodies (B,) with a sub-volume beyond ``x_range`` (the open ends' x; +-inf if closed)."""
        pts = com[:, None, :] + np.einsum("bij,bnj->bni", rot, self.local)
        return np.any((pts[:, :, 0] < x_range[0]) | (pts[:, :, 0] > x_range[1]), axis=1)

    def _inside(self, pts) -> bool:
        (x0, x1), (y0, y1), _ = self.flow.extent_m
        return bool(np.all((pts[:, 0] >= x0) & (pts[:, 0] <= x1) & (pts[:, 1] >= y0) & (pts[:, 1] <= y1)))


def run_transport(bodies, flume: FlumeBounds, t_end_s: float, flow: FlowField | None = None,
                  column: PlacedColumn | None = None, settings: TransportSettings | None = None,
                  groups=None) -> TransportResult:
    """Carry ``bodies`` (the scene's :class:`~orchestrator.scene.schema.DebrisBody`, or dicts of
    their fields, at their starts) through ``flow`` (None: dry) for ``t_end_s``
    seconds in ``flume`` with ``column``; see the module notes. ``groups`` (one label per body,
    None: one group): only bodies of one group can strike each other
    (:func:`~orchestrator.transport.mujoco_model.build_model`)."""
    settings = TransportSettings() if settings is None else settings
    bodies = [b if isinstance(b, DebrisBody) else DebrisBody(**b) for b in bodies]
    for b in bodies:
        if len(b.centre_m) != 3:
            raise InputError(f"{b.name}.centre_m", f"must be three numbers (x, y, z) to carry it, got {b.centre_m!r}")
    t_end = require_positive("t_end_s", t_end_s)
    coeffs = settings.hydro
    gravity = coeffs.gravity_m_s2
    t0 = 0.0
    if flow is not None:
        coeffs = dataclasses.replace(coeffs, water_density_kg_m3=flow.water_density_kg_m3,
                                     gravity_m_s2=flow.gravity_m_s2)
        gravity = flow.gravity_m_s2
        t0 = flow.t_s[0] if settings.flow_start_s is None else float(settings.flow_start_s)
        lo, hi = flow.time_span_s
        if t0 < lo or t0 + t_end > hi + 1e-9 * max(1.0, hi):
            raise FlowCoverageError("flow.t", f"the run needs flow times [{t0:.6g}, {t0 + t_end:.6g}] s, the record "
                                              f"covers [{lo:.6g}, {hi:.6g}] s")
        if abs(flow.bed_z_m - flume.bed_z_m) > 1e-9:
            raise InputError("flume.bed_z_m", f"must equal the flow's bed ({flow.bed_z_m} m), got {flume.bed_z_m}")
    built = build_model(bodies, flume, column, gravity_m_s2=gravity,
                        steps_per_contact_period=settings.steps_per_contact_period,
                        max_timestep_s=settings.max_timestep_s, groups=groups)
    m, dt = built.model, built.timestep_s
    d = mujoco.MjData(m)
    for i, b in enumerate(bodies):
        q, v = built.qpos_adr[i], built.dof_adr[i]
        d.qpos[q:q + 3] = b.centre_m
        mujoco.mju_mat2Quat(d.qpos[q + 3:q + 7], rotation(b).ravel())
        d.qvel[v:v + 3] = b.velocity_m_s  # a start without spin
    mujoco.mj_forward(m, d)

    n_hydro = max(1, int(round(settings.hydro_interval_s / dt)))
    n_out = max(1, int(round(settings.output_interval_s / dt)))
    forcing = _Forcing(flow, bodies, coeffs) if flow is not None else None
    t_begin = 0.0
    at_rest = not np.any(d.qvel)
    if settings.still_start_m_s is not None and forcing is not None and at_rest:
        xmat = d.xmat[built.body_ids].reshape(-1, 3, 3)
        still = forcing.still_until(d.xpos[built.body_ids], xmat, t0, t_end, float(settings.still_start_m_s)) - t0
        t_begin = math.floor(still / (n_out * dt) + 1e-9) * n_out * dt  # on the output grid
        d.time = t_begin
    steps = int(round((t_end - t_begin) / dt))
    surface = (lambda x, y, t: flow.surface(x, y, t0 + t)) if flow is not None else None
    book = EventBook(built.geom_owner, built.geom_names, bodies, built.body_ids, built.dof_adr, column,
                     flume.bed_z_m, settings.separation_s, surface, settings.min_impact_velocity_m_s,
                     settings.first_pulse_only, _front_at_face_s(flow, column, t0), settings.every_column_pulse)
    mass = np.array([b.mass_kg for b in bodies])
    inertia = np.array([inertia_kg_m2(b) for b in bodies])
    # the water each body carries (body axes): translation (kg) and rotation (kg m^2), as the
    # forcing last set it; dry, none
    added_mass = np.zeros((len(bodies), 3))
    added_inertia = np.zeros((len(bodies), 3))
    lin = built.dof_adr[:, None] + np.arange(3)[None, :]
    ang = built.dof_adr[:, None] + np.arange(3, 6)[None, :]
    rows: list[np.ndarray] = []
    times: list[float] = []

    def state():
        rot = d.xmat[built.body_ids].reshape(-1, 3, 3).copy()
        vel = d.qvel[lin].copy()
        omega = np.einsum("bij,bj->bi", rot, d.qvel[ang])
        return d.xpos[built.body_ids].copy(), rot, vel, omega

    def record():
        com, rot, vel, omega = state()
        times.append(d.time)
        rows.append(np.concatenate([com, vel, omega, rot.reshape(-1, 9)], axis=1))

    pair_i, pair_j = built.pair_bodies[:, 0], built.pair_bodies[:, 1]

    def update_friction():
        vel = d.qvel[lin]
        other = np.where((pair_j >= 0)[:, None], vel[np.maximum(pair_j, 0)], 0.0)
        m.pair_solreffriction[:] = built.friction_solref(np.linalg.norm(vel[pair_i] - other, axis=1))

    # the open ends: a body whose corner passes one leaves the run (FlumeBounds)
    ends_x = (flume.x_m[0] if flume.open_ends[0] else -np.inf, flume.x_m[1] if flume.open_ends[1] else np.inf)
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    half_sizes = np.array([b.size_m for b in bodies]) / 2.0
    active = np.ones(len(bodies), dtype=bool)
    departures: list[dict] = []
    departed_at = np.full(len(bodies), np.inf)

    def check_departures():
        com, rot, vel, _ = state()
        pts = com[:, None, :] + np.einsum("bij,bnj->bni", rot, corners[None, :, :] * half_sizes[:, None, :])
        x = pts[:, :, 0]
        gone = active & (np.any(x < ends_x[0], axis=1) | np.any(x > ends_x[1], axis=1))
        for i in np.nonzero(gone)[0]:
            departures.append({"body": bodies[i].name, "time_s": float(d.time),
                               "end": "upstream" if x[i].min() < ends_x[0] else "downstream",
                               "x_m": com[i, 0], "y_m": com[i, 1], "z_m": com[i, 2], "u_m_s": vel[i, 0],
                               "v_m_s": vel[i, 1], "w_m_s": vel[i, 2], "speed_m_s": float(np.linalg.norm(vel[i]))})
            departed_at[i] = d.time
            active[i] = False
            # parked far above the flume, held there against gravity and out of every contact
            q, v = built.qpos_adr[i], built.dof_adr[i]
            d.qpos[q:q + 3] = (com[i, 0], com[i, 1], flume.bed_z_m + PARKING_HEIGHT_M + 10.0 * i)
            d.qvel[v:v + 6] = 0.0
            d.xfrc_applied[built.body_ids[i], :] = 0.0
            m.body_gravcomp[built.body_ids[i]] = 1.0
        if np.any(gone):
            mujoco.mj_forward(m, d)

    def apply_forcing():
        com, rot, vel, omega = state()
        idx = np.nonzero(active)[0]
        if not len(idx):
            return
        loads = forcing(t0 + d.time, com, rot, vel, omega, active=idx)
        ids = built.body_ids[idx]
        d.xfrc_applied[ids, :3] = loads.force_N
        d.xfrc_applied[ids, 3:] = loads.moment_Nm
        added_mass[idx] = loads.added_mass_kg
        added_inertia[idx] = loads.added_inertia_kg_m2
        # translations are along the world axes: the world-diagonal of R diag(M_a) R^T
        # (analytical.hydrodynamics); rotations about the body's: exact
        world = np.einsum("bik,bk->bi", rot * rot, added_mass)
        m.dof_armature[lin] = world
        m.dof_armature[ang] = added_inertia
        # MuJoCo keeps a free body's diagonal mass in dof_M0, fixed at compile time: the armature
        # changed at run time only counts once dof_M0 carries it as well (MuJoCo 4.0).
        m.dof_M0[lin] = mass[:, None] + world
        m.dof_M0[ang] = inertia + added_inertia
        m.pair_solref[:] = built.pair_solref(mass + world.mean(axis=1))

    def impact_body(i: int) -> Body:
        com, rot, vel, omega = (x[i] for x in state())
        return Body.box(mass[i], inertia[i], rot, com, vel, omega, added_mass[i], added_inertia[i])

    def resolve(event) -> None:
        """Resolve a strike found in the step just undone, from the state before it, and set
        the bodies' velocities to its rebound (module notes of events.py)."""
        i = event.body
        other = event.other if event.kind == "body" else None
        body, b = bodies[i], impact_body(i)
        event.added_mass_normal_kg = b.translational_mass_along(event.normal) - mass[i]
        if other is None:
            result, moves = resolve_bodies(event.kind, event.point, event.normal, event.depth_m, b, contact_law_of(body),
                                           friction_of(body), column=column.column if column else None,
                                           bed_z_m=flume.bed_z_m, base_shear=False)
        else:
            result, moves = resolve_bodies("body", event.point, event.normal, event.depth_m, b,
                                           pair_law(i, other), pair_friction(i, other), other=impact_body(other),
                                           base_shear=False)
        book.strike(event, result)
        for index, move, res in ((i, moves[0], result), (other, moves[1] if other is not None else None, result)):
            if index is None:
                continue
            q, v = built.qpos_adr[index], built.dof_adr[index]
            d.qpos[q:q + 3] += move
            if res is None:
                continue
            first = index == i
            vel = res.velocity_out_m_s if first else res.other_velocity_out_m_s
            omega = res.angular_velocity_out_rad_s if first else res.other_angular_velocity_out_rad_s
            rot = d.xmat[built.body_ids[index]].reshape(3, 3)
            d.qvel[v:v + 3] = vel
            d.qvel[v + 3:v + 6] = rot.T @ omega  # free joint: body-frame rates

    def pair_law(i: int, j: int):
        return pair_contact_law(contact_law_of(bodies[i]), contact_law_of(bodies[j]))

    def pair_friction(i: int, j: int) -> float:
        return 0.5 * (friction_of(bodies[i]) + friction_of(bodies[j]))

    start = time.perf_counter()
    for k in range(steps):
        if k % n_hydro == 0:
            if flume.open_ends[0] or flume.open_ends[1]:
                check_departures()
            update_friction()
            if forcing is not None:
                apply_forcing()
        if k % n_out == 0:
            record()
        qpos_before = d.qpos.copy()
        before = d.qvel.copy()
        t_before = d.time
        mujoco.mj_step(m, d)
        if d.ncon or book.touching:
            strikes = book.observe(t_before, d, before, d.xmat[built.body_ids])
            for _ in range(3):  # a strike resolved; the step taken again may find another
                if not strikes:
                    break
                d.qpos[:], d.qvel[:], d.time = qpos_before, before, t_before
                mujoco.mj_forward(m, d)
                for event in strikes:
                    resolve(event)
                mujoco.mj_forward(m, d)
                qpos_before, before = d.qpos.copy(), d.qvel.copy()
                mujoco.mj_step(m, d)
                strikes = book.observe(t_before, d, before, d.xmat[built.body_ids])
    record()
    wall = time.perf_counter() - start
    impacts, body_contacts = book.finish()
    tracks = _tracks(bodies, np.array(times), rows)
    if departures:  # a body's track ends where it left
        gone_at = tracks["body"].map({b.name: departed_at[i] for i, b in enumerate(bodies)})
        tracks = tracks[tracks["time_s"] <= gone_at].reset_index(drop=True)
    return TransportResult(tracks, impacts, body_contacts, wall, book.pulse_wall_s,
                           dt, steps, n_hydro * dt, n_out * dt, dict(book.pulses),
                           book.strike_states(), pd.DataFrame(departures, columns=DEPARTURE_COLUMNS))


def _front_at_face_s(flow: FlowField | None, column, t0_s: float) -> float:
    """When the flow's front reached the column's upstream face, on the transport's clock (the
    face as the strikes' water level reads it, 1 cm upstream); NaN without a flow or a column, or
    when the record does not cover the face."""
    if flow is None or column is None:
        return math.nan
    try:
        return flow.front_arrival_s(column.x_m - column.column.size_x_m / 2.0 - 0.01, column.y_m) - float(t0_s)
    except InputError:
        return math.nan


def _tracks(bodies, times: np.ndarray, rows: list[np.ndarray]) -> pd.DataFrame:
    data = np.stack(rows)  # (T, B, 18)
    frames = []
    for i, b in enumerate(bodies):
        x = data[:, i, :]
        angles = np.array([angles_deg(q) for q in x[:, 9:18]]).reshape(-1, 3)
        frame = {"time_s": times, "body": b.name, "x_m": x[:, 0], "y_m": x[:, 1], "z_m": x[:, 2],
                 "u_m_s": x[:, 3], "v_m_s": x[:, 4], "w_m_s": x[:, 5], "speed_m_s": np.linalg.norm(x[:, 3:6], axis=1),
                 "omega_x_rad_s": x[:, 6], "omega_y_rad_s": x[:, 7], "omega_z_rad_s": x[:, 8],
                 "yaw_deg": angles[:, 0], "pitch_deg": angles[:, 1], "roll_deg": angles[:, 2]}
        for n, (a, c) in enumerate((a, c) for a in "xyz" for c in "xyz"):
            frame[f"q_{a}{c}"] = x[:, 9 + n]
        frames.append(pd.DataFrame(frame, columns=BODY_COLUMNS))
    return pd.concat(frames, ignore_index=True)
