"""The MuJoCo model of a transport run: flume, column and debris bodies, written as MJCF in code.

Why MuJoCo
----------
MuJoCo is a maintained rigid-body engine (Google DeepMind, Apache 2.0, wheels for every
platform, no display needed) with full six-degree-of-freedom free bodies, box-box, box-plane
collision with several contact points per patch, Coulomb friction cones, and, the reason it
fits this problem, contacts whose **stiffness and damping can be set directly**: a negative
``solref = (-k, -b)`` makes the contact's reference acceleration ``-k r - b v`` (``r`` the
penetration, ``v`` its rate), scaled so that it holds independently of the impedance
``d``. MuJoCo's constraint dynamics then give, along a contact normal,
``a = (1 - d) a0 - k r - b v`` (``a0`` the unconstrained acceleration). With a constant
impedance ``d`` close to 1 (``solimp = (d, d, ...)``, here 0.99) and no other force along the
normal (the column struck by a body: ``a0`` horizontal is zero), this is the spring-dashpot
``m_eff r'' + c r' + K r = 0`` of the contact law with ``k = K / m_eff`` and
``b = c / m_eff = 2 zeta sqrt(K / m_eff)``. The acceleration, not the force, is prescribed
per contact point, so a face contact of four points has the same total stiffness ``K`` as one
point. ``m_eff`` is the body's translational mass (its structural mass plus the added mass
of the water it displaces, refreshed during the run), i.e. the effective mass of an end-on
strike through the centre; the column's pulse itself comes from
:func:`analytical.contact_law.column_impact`, as on the coupled path (see engine.py).

Contact parameters by pair
--------------------------
Every contact is an explicit ``<pair>`` (the geoms' own collision flags are off, so MuJoCo
checks exactly these pairs), because MuJoCo's combination of two geoms' direct solrefs takes
the stiffer one, and the friction reference must be set per pair (below).

* body - walls, column: the body's contact law over its mass; its friction coefficient.
* body - bed: the body's stiffness over its mass, critically damped (:data:`BED_DAMPING_RATIO`).
* body - body: the two springs in series
  (:meth:`~analytical.contact_law.ContactLaw.pair` for two equal laws), the mean damping
  ratio, over the two-body mass ``m1 m2 / (m1 + m2)``, and the mean friction coefficient
  (the coupled path's rule).
* Friction: condim 3 (sliding friction, elliptic cone, Newton solver), with its own reference
  ``solreffriction``: a damping ``b`` on the sliding velocity (the normal law's damping may be
  zero, and friction would then not slow a slide at all). In MuJoCo's convex model a sliding
  contact's force sits on the friction cone with a size that grows with the tangential
  demand ``b |v_t|``, and so does the *normal* force: a stiff friction reference (``b`` of
  order ``1 / dt``) makes a box sliding at 1 m/s hop off the bed every few centimetres (found
  here: 0.28 m/s upward in one step). The engine therefore sets, per pair and at every
  forcing update, ``b = mu g / max(|v|, 0.01 m/s)`` (``|v|`` the body's speed relative to
  the other): the demand is the Coulomb deceleration ``mu g`` while sliding, and a stiff
  damper (time constant about 1 ms) once nearly at rest, which holds a body stuck.

Time step: ``min(2 pi sqrt(m_eff / K)) / steps_per_contact_period`` over every contact pair
(at least 40 steps per contact period; the default contact law gives about 2.3e-4 s).

The constraint solver starts every step from the unconstrained acceleration (MuJoCo's warm
start is off). MuJoCo solves bodies that share no constraint as separate islands, each to its
own tolerance, but it chooses between the warm and the cold start for the whole model at once
(the lower total cost): with the warm start on, a body's motion depends at the solver's
tolerance (about 1e-10 m a second) on the other bodies in its model, and an ensemble's
rebound sequences amplify that to a different strike in a few realisations in a hundred, so a
realisation stepped in a batch would not be the realisation stepped alone
(:mod:`~orchestrator.transport.batch`). Off, they give the same first strikes to rounding
(1e-13 relative on the 1-debris record); the cost is within the machine's noise (the Newton
solver from the cold start takes a few more iterations, and skips the comparison).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from analytical.column import Column
from analytical.contact_law import ContactLaw, box_inertia
from orchestrator.core.errors import InputError
from orchestrator.contact.resolution import body_contact_law, pair_contact_law
from orchestrator.scene.geometry import body_rotation
from orchestrator.scene.schema import DebrisBody

__all__ = [
    "BED_DAMPING_RATIO",
    "CONTACT_IMPEDANCE",
    "FRICTION_DEMAND",
    "STICK_SPEED_M_S",
    "BuiltModel",
    "FlumeBounds",
    "PlacedColumn",
    "angles_deg",
    "build_model",
    "contact_law_of",
    "contact_period_s",
    "contact_solref",
    "friction_of",
    "inertia_kg_m2",
    "rotation",
    "with_start",
]

CONTACT_IMPEDANCE = 0.99
"""Constant impedance ``d`` of every contact (solimp dmin = dmax): the share of the
unconstrained acceleration the contact cancels outright; 1 - d is the error of the
spring-dashpot picture under a sustained load (none in a horizontal strike)."""


BED_DAMPING_RATIO = 1.0
"""Damping ratio of every body's contact with the bed (its stiffness is the body's law):
critical, so a body set down or landing on the bed neither rings nor bounces. The bed is not
an impact target (as on the coupled path); an undamped bed contact would keep a sliding box
rocking on its edges, which the friction then decelerates at less than ``mu g``."""


FRICTION_DEMAND = 1.0
"""Friction's reference deceleration over ``mu g`` (see the module notes on friction)."""

STICK_SPEED_M_S = 0.01
"""Below this sliding speed the friction reference is a stiff damper (``b = mu g / 0.01``,
a time constant of a few steps): the body sticks."""


def rotation(body: DebrisBody) -> np.ndarray:
    """A debris body's rotation at its start, body axes to world: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    return body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)


def inertia_kg_m2(body: DebrisBody) -> tuple[float, float, float]:
    """A debris body's principal moments of inertia for the transport: the box of its size and mass,
    closed with walls ``wall_thickness_m`` thick (None: solid)."""
    return box_inertia(body.size_m, body.mass_kg, body.wall_thickness_m)


def contact_law_of(body: DebrisBody) -> ContactLaw:
    """A debris body's contact law (its ``contact`` section)."""
    return body_contact_law(body.contact)


def friction_of(body: DebrisBody) -> float:
    """A debris body's Coulomb coefficient in the transport, on the bed and in a strike alike: its
    ``contact.bed_friction_coefficient``."""
    return float(body.contact.bed_friction_coefficient)


def with_start(body: DebrisBody, **changes) -> DebrisBody:
    """``body`` with its start changed (``centre_m``, ``yaw_deg``, ``mass_kg``, ``name`` ...), the
    numbers as Python floats."""
    def number(value):
        if isinstance(value, (tuple, list, np.ndarray)):
            return tuple(float(x) for x in value)
        return float(value) if isinstance(value, (int, float, np.number)) and not isinstance(value, bool) else value

    return body.model_copy(update={k: number(v) for k, v in changes.items()})


@dataclass(frozen=True)
class FlumeBounds:
    """The flume: bed plane at ``bed_z_m``, side walls at ``y_m`` and the ends at ``x_m``.

    ``open_ends`` (upstream, downstream): an open end is no wall but where the bodies' world
    ends (the flow record stops short of the flume's end, or the flume's end is a free
    outfall): a body reaching it leaves the run (:class:`~orchestrator.transport.engine.TransportResult`
    ``departures``). A closed end is a wall."""

    x_m: tuple[float, float]
    y_m: tuple[float, float]
    bed_z_m: float = 0.0
    open_ends: tuple[bool, bool] = (False, False)

    def __post_init__(self):
        for name in ("x_m", "y_m"):
            lo, hi = (float(v) for v in getattr(self, name))
            if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
                raise InputError(f"flume.{name}", f"must be (low, high) with high > low, got {getattr(self, name)!r}")
            object.__setattr__(self, name, (lo, hi))
        ends = tuple(self.open_ends)
        if len(ends) != 2 or not all(isinstance(e, (bool, np.bool_)) for e in ends):
            raise InputError("flume.open_ends", f"must be two booleans (upstream, downstream), got {self.open_ends!r}")
        object.__setattr__(self, "open_ends", tuple(bool(e) for e in ends))


@dataclass(frozen=True)
class PlacedColumn:
    """The column (:class:`~analytical.column.Column`: footprint, height, structure) with the
    centre of its footprint at ``(x_m, y_m)``, standing on the bed."""

    x_m: float
    y_m: float = 0.0
    column: Column = field(default_factory=Column)


@dataclass
class BuiltModel:
    """The compiled model and the index maps the engine needs."""

    xml: str
    model: mujoco.MjModel
    timestep_s: float
    body_ids: np.ndarray  # MuJoCo body id per transport body
    geom_ids: np.ndarray  # MuJoCo geom id per transport body
    dof_adr: np.ndarray  # first dof of each body's free joint
    qpos_adr: np.ndarray
    geom_owner: np.ndarray  # per MuJoCo geom: body index >= 0, or -1 bed, -2 wall, -3 column
    geom_names: list[str]
    pair_bodies: np.ndarray  # (P, 2) body indices of each explicit pair; -1 second: a static geom
    pair_stiffness_N_m: np.ndarray  # (P,) the pair's contact law
    pair_damping_ratio: np.ndarray  # (P,)
    pair_friction: np.ndarray  # (P,) Coulomb coefficient
    gravity_m_s2: float = 9.81

    def friction_solref(self, speed_m_s) -> np.ndarray:
        """Every pair's ``solreffriction`` (P, 2) for the pairs' current sliding speeds (P,):
        damping ``b = FRICTION_DEMAND mu g / max(speed, STICK_SPEED_M_S)`` (module notes)."""
        speed = np.maximum(np.asarray(speed_m_s, float), STICK_SPEED_M_S)
        b = FRICTION_DEMAND * np.maximum(self.pair_friction, 1e-5) * self.gravity_m_s2 / speed
        return np.stack([np.zeros_like(b), -b], axis=-1)

    def pair_solref(self, body_mass_kg) -> np.ndarray:
        """Every pair's solref (P, 2) for the bodies' current translational masses (B,)."""
        mass = np.asarray(body_mass_kg, float)
        i, j = self.pair_bodies[:, 0], self.pair_bodies[:, 1]
        mi = mass[i]
        mj = np.where(j >= 0, mass[np.maximum(j, 0)], np.inf)
        m_eff = np.where(j >= 0, mi * mj / (mi + np.where(j >= 0, mj, 0.0)), mi)
        k = self.pair_stiffness_N_m / m_eff
        return np.stack([-k, -2.0 * self.pair_damping_ratio * np.sqrt(k)], axis=-1)


BED, WALL, COLUMN = -1, -2, -3


def angles_deg(rotation) -> tuple[float, float, float]:
    """(yaw, pitch, roll) in degrees of ``R = Rz(yaw) Ry(pitch) Rx(roll)``."""
    q = np.asarray(rotation, float).reshape(3, 3)
    pitch = math.asin(max(-1.0, min(1.0, -q[2, 0])))
    return math.degrees(math.atan2(q[1, 0], q[0, 0])), math.degrees(pitch), math.degrees(math.atan2(q[2, 1], q[2, 2]))


def contact_solref(law: ContactLaw, mass_kg) -> np.ndarray:
    """MuJoCo direct ``solref = (-K / m, -2 zeta sqrt(K / m))`` for a law over an effective mass
    (arrays broadcast; the last axis holds the pair)."""
    k = law.stiffness_N_m / np.asarray(mass_kg, float)
    return np.stack([-k, -2.0 * law.damping_ratio * np.sqrt(k)], axis=-1)


def contact_period_s(law: ContactLaw, mass_kg: float) -> float:
    return 2.0 * math.pi * math.sqrt(mass_kg / law.stiffness_N_m)


def _f(values) -> str:
    return " ".join(f"{float(v):.12g}" for v in values)


def build_model(bodies, flume: FlumeBounds, column: PlacedColumn | None = None, *, gravity_m_s2: float = 9.81,
                steps_per_contact_period: int = 40, max_timestep_s: float = 1e-3, groups=None) -> BuiltModel:
    """The MJCF of the flume, the column and ``bodies`` (the scene's
    :class:`~orchestrator.scene.schema.DebrisBody`, at their starts), compiled.
    ``groups`` (one label per body; None: one group) says which bodies can touch: body-body
    pairs exist only within a group, so bodies of different groups pass through each other
    (independent realisations in one model, :mod:`~orchestrator.transport.batch`)."""
    bodies = list(bodies)
    if not bodies:
        raise InputError("bodies", "give at least one body")
    groups = [0] * len(bodies) if groups is None else list(groups)
    if len(groups) != len(bodies):
        raise InputError("groups", f"must give one group per body ({len(bodies)}), got {len(groups)}")
    touching = [(i, j) for i in range(len(bodies)) for j in range(i + 1, len(bodies)) if groups[i] == groups[j]]
    names = [b.name for b in bodies]
    if len(set(names)) != len(names):
        raise InputError("bodies", f"names must be unique, got {names}")
    if steps_per_contact_period < 40:
        raise InputError("steps_per_contact_period", f"must be >= 40, got {steps_per_contact_period}")
    laws = [contact_law_of(b) for b in bodies]
    mu = [friction_of(b) for b in bodies]
    mass = [float(b.mass_kg) for b in bodies]
    periods = [contact_period_s(law, m) for law, m in zip(laws, mass)]
    dt_bound = min(periods) / steps_per_contact_period
    for i, j in touching:
        periods.append(contact_period_s(pair_contact_law(laws[i], laws[j]), mass[i] * mass[j] / (mass[i] + mass[j])))
    dt = min(min(periods) / steps_per_contact_period, max_timestep_s, dt_bound)
    imp = f"{CONTACT_IMPEDANCE} {CONTACT_IMPEDANCE} 0.001 0.5 2"
    fric_ref = f"0 {-FRICTION_DEMAND * gravity_m_s2 / STICK_SPEED_M_S!r}"  # at rest; rescaled in the run
    bed = flume.bed_z_m
    (x0, x1), (y0, y1) = flume.x_m, flume.y_m
    off = 'contype="0" conaffinity="0"'
    statics = ["bed", "wall_y0", "wall_y1"]
    world = [
        f'<geom name="bed" type="plane" pos="0 0 {bed}" size="0 0 1" {off}/>',
        f'<geom name="wall_y0" type="plane" pos="0 {y0} 0" zaxis="0 1 0" size="0 0 1" {off}/>',
        f'<geom name="wall_y1" type="plane" pos="0 {y1} 0" zaxis="0 -1 0" size="0 0 1" {off}/>',
    ]
    for end, (x, axis) in enumerate(((x0, 1), (x1, -1))):
        if not flume.open_ends[end]:  # an open end has no wall: a body reaching it leaves the run
            statics.append(f"wall_x{end}")
            world.append(f'<geom name="wall_x{end}" type="plane" pos="{x} 0 0" zaxis="{axis} 0 0" size="0 0 1" {off}/>')
    if column is not None:
        c = column.column
        statics.append("column")
        world.append(f'<geom name="column" type="box" pos="{column.x_m} {column.y_m} {bed + c.height_m / 2}" '
                     f'size="{c.size_x_m / 2} {c.size_y_m / 2} {c.height_m / 2}" {off}/>')
    for b, m in zip(bodies, mass):
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, rotation(b).ravel())
        world.append(
            f'<body name="{b.name}" pos="{_f(b.centre_m)}" quat="{_f(quat)}">'
            f'<joint name="{b.name}_free" type="free" armature="0"/>'
            f'<inertial pos="0 0 0" mass="{m!r}" diaginertia="{_f(inertia_kg_m2(b))}"/>'
            f'<geom name="{b.name}_box" type="box" size="{_f(np.asarray(b.size_m) / 2)}" {off} density="0"/></body>')
    pairs, stiffness, damping, friction, contact = [], [], [], [], []

    def add_pair(i, j, geom2, law, coefficient, m_eff, damping_ratio=None):
        zeta = law.damping_ratio if damping_ratio is None else damping_ratio
        k = law.stiffness_N_m / m_eff
        pairs.append((i, j))
        stiffness.append(law.stiffness_N_m)
        damping.append(zeta)
        coefficient = max(coefficient, 1e-5)
        friction.append(coefficient)
        contact.append(f'<pair geom1="{bodies[i].name}_box" geom2="{geom2}" condim="3" '
                       f'friction="{coefficient!r} {coefficient!r} 0 0 0" solref="{-k!r} {-2.0 * zeta * math.sqrt(k)!r}" '
                       f'solimp="{imp}" solreffriction="{fric_ref}"/>')

    for i in range(len(bodies)):
        for name in statics:
            add_pair(i, -1, name, laws[i], mu[i], mass[i], BED_DAMPING_RATIO if name == "bed" else None)
    for i, j in touching:
        add_pair(i, j, f"{bodies[j].name}_box", pair_contact_law(laws[i], laws[j]), 0.5 * (mu[i] + mu[j]),
                 mass[i] * mass[j] / (mass[i] + mass[j]))
    xml = (f'<mujoco model="transport"><option timestep="{dt!r}" gravity="0 0 {-gravity_m_s2!r}" '
           f'density="0" viscosity="0" cone="elliptic" solver="Newton" integrator="Euler">'
           '<flag warmstart="disable"/></option>'
           f'<worldbody>{"".join(world)}</worldbody>'
           + (f'<contact>{"".join(contact)}</contact>' if contact else "") + "</mujoco>")
    model = mujoco.MjModel.from_xml_string(xml)
    body_ids = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, b.name) for b in bodies])
    geom_ids = np.array([mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, f"{b.name}_box") for b in bodies])
    owner = np.full(model.ngeom, WALL, dtype=int)
    geom_names = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in range(model.ngeom)]
    owner[geom_names.index("bed")] = BED
    if column is not None:
        owner[geom_names.index("column")] = COLUMN
    owner[geom_ids] = np.arange(len(bodies))
    joints = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{b.name}_free") for b in bodies]
    return BuiltModel(xml, model, dt, body_ids, geom_ids, model.jnt_dofadr[joints].copy(),
                      model.jnt_qposadr[joints].copy(), owner, geom_names, np.array(pairs, dtype=int).reshape(-1, 2),
                      np.array(stiffness, float), np.array(damping, float), np.array(friction, float), gravity_m_s2)
