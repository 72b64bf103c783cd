"""Debris contact: geometry, event detection and resolution (no OpenFOAM here).

OpenFOAM v1912 has no contact: a body on an overset mesh passes through the column and the
walls silently (docs/openfoam-notes.md, "Contact: v1912 has none"). The runner watches every body's pose from the
solver's per-step report and uses this module to

* build the obstacles of a scene (:func:`scene_obstacles`): the column as an axis-aligned
  box from the floor to its top, the flume's side walls, its end walls (the upstream wall,
  and the downstream one when it is closed) as planes, and the bed separately: touching the
  bed is not an impact, but a body must not sink through it (:func:`bed_clearance`,
  :func:`clamp_to_bed`);
* find contacts (:func:`find_contacts`): for each body (an oriented box) against each
  obstacle and each other body, the minimum distance (negative: penetration depth), the
  contact point and the unit normal, when the distance is below a gap;
* decide how closely to watch (:func:`time_to_contact`);
* resolve a contact (:func:`resolve`) with :mod:`analytical.impact`: the column's MDOF model
  for column impacts, a rigid wall otherwise, two-body effective mass between bodies; the
  result is the impact (force history, restitution, ...) and the bodies' rebound states.

Box-box geometry. Overlap is decided by the separating-axis test over the 15 axes (the
boxes' face normals and the 9 cross products of their edges). For separated boxes the
distance is exact: the closest points of two convex polyhedra lie on a vertex-face or an
edge-edge pair (degenerate cases such as vertex-vertex are limits of these), so the minimum
over the 16 vertex-to-box distances (vertex clamped into the other box's frame) and the 144
edge-edge segment distances is the distance. The contact point is the midpoint of the
closest pair; when a whole patch is closest (parallel faces, parallel edges) it is the
mean of the closest pairs found at the patch corners. For touching or overlapping boxes the
normal is the axis of least penetration (face axes preferred on ties), the distance is minus
that depth, and the point is the centroid of the vertices of the intersection polytope
(each box's faces clipped by the other's six half-spaces).

Units: m, s, kg, rad. Normals point from the obstacle (or the other body) into the body.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from analytical.contact_law import ContactLaw, contact_law
from analytical.errors import InputError
from analytical.impact import (
    DEFAULT_ADDED_MASS_COEFFICIENT,
    Body,
    ColumnTarget,
    ImpactResult,
    RigidWall,
    impact,
    inverse_inertia_tensor,
    pair_impact,
)
from orchestrator.scene.geometry import flume_extent
from orchestrator.scene.schema import Scene, column_for_analysis

__all__ = [
    "BodyState",
    "BoxObstacle",
    "PlaneObstacle",
    "Obstacles",
    "Contact",
    "Proximity",
    "scene_obstacles",
    "find_contacts",
    "box_box_proximity",
    "box_plane_proximity",
    "time_to_contact",
    "bed_clearance",
    "clamp_to_bed",
    "resolve",
    "body_contact_law",
    "pair_contact_law",
]

#: Relative tolerance on lengths (times the larger box size) for coincident points.
_REL_TOL = 1e-9
#: Box-plane contacts (bed, walls): corners closer than the nearest by less than this (times
#: the box size) share the contact, so a face within 0.1 % of parallel is a face contact, not
#: a corner contact (a body rolled by 1e-6 rad must not pick up a spurious yaw from one
#: corner). Box-box contacts stay exact (their point lies on both surfaces).
_FEATURE_REL_TOL = 1e-3

ContactKind = Literal["column", "wall", "body"]


# ------------------------------------------------------------------------------ states
@dataclass(frozen=True)
class BodyState:
    """One debris body's rigid-body state (global frame; arrays are read-only).

    Attributes
    ----------
    name:
        The body's name (as in the scene and the solver dictionaries).
    centre_of_mass_m:
        Centre of mass (m), also the box centre.
    orientation:
        3x3 rotation from body to global axes (columns: the body's length, width and
        height directions).
    velocity_m_s, angular_velocity_rad_s:
        Linear velocity of the centre of mass (m/s) and angular velocity (rad/s).
    size_m:
        Box size along the body axes [length, width, height] (m).
    mass_kg:
        Mass (kg).
    inertia_kg_m2:
        Principal moments of inertia about the body axes through the centre of mass (kg m^2).
    """

    name: str
    centre_of_mass_m: np.ndarray
    orientation: np.ndarray
    velocity_m_s: np.ndarray
    angular_velocity_rad_s: np.ndarray
    size_m: np.ndarray
    mass_kg: float
    inertia_kg_m2: np.ndarray

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise InputError("name", f"must be a non-empty string, got {self.name!r}")
        for field_name in ("centre_of_mass_m", "velocity_m_s", "angular_velocity_rad_s"):
            _freeze(self, field_name, _vec3(f"{self.name}.{field_name}", getattr(self, field_name)))
        size = _vec3(f"{self.name}.size_m", self.size_m)
        if np.any(size <= 0.0):
            raise InputError(f"{self.name}.size_m", f"must all be > 0, got {size.tolist()}")
        _freeze(self, "size_m", size)
        inertia = _vec3(f"{self.name}.inertia_kg_m2", self.inertia_kg_m2)
        if np.any(inertia <= 0.0):
            raise InputError(f"{self.name}.inertia_kg_m2", f"must all be > 0, got {inertia.tolist()}")
        _freeze(self, "inertia_kg_m2", inertia)
        rot = np.array(self.orientation, dtype=float)
        if rot.shape != (3, 3) or not np.all(np.isfinite(rot)):
            raise InputError(f"{self.name}.orientation", "must be a finite 3x3 matrix")
        if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) <= 0.0:
            raise InputError(f"{self.name}.orientation", "must be a rotation matrix (orthonormal, det +1)")
        _freeze(self, "orientation", rot)
        try:
            mass = float(self.mass_kg)
        except (TypeError, ValueError):
            raise InputError(f"{self.name}.mass_kg", f"must be a number, got {self.mass_kg!r}") from None
        if not math.isfinite(mass) or mass <= 0.0:
            raise InputError(f"{self.name}.mass_kg", f"must be > 0, got {self.mass_kg!r}")
        object.__setattr__(self, "mass_kg", mass)

    @classmethod
    def from_plan(cls, body, velocity_m_s=(0.0, 0.0, 0.0), angular_velocity_rad_s=(0.0, 0.0, 0.0)) -> "BodyState":
        """The state of a planned body (:class:`orchestrator.plan.planner.BodyPlan`) with the given motion."""
        return cls(
            name=body.name,
            centre_of_mass_m=body.centre_of_mass_m,
            orientation=body.orientation,
            velocity_m_s=velocity_m_s,
            angular_velocity_rad_s=angular_velocity_rad_s,
            size_m=body.size_m,
            mass_kg=body.mass_kg,
            inertia_kg_m2=body.moment_of_inertia_kg_m2,
        )

    def replace(self, **changes) -> "BodyState":
        """A copy with some fields changed."""
        return dataclasses.replace(self, **changes)

    @property
    def half_size_m(self) -> np.ndarray:
        return self.size_m / 2.0

    def corners(self) -> np.ndarray:
        """The 8 corners (8x3, m), corner ``i`` at body signs ``(bit0, bit1, bit2)`` of ``i``."""
        return _Box.of(self).corners()

    def inverse_inertia(self) -> np.ndarray:
        """Inverse inertia tensor in the global frame (1/(kg m^2))."""
        return inverse_inertia_tensor(self.inertia_kg_m2, self.orientation)

    def point_velocity(self, point_m) -> np.ndarray:
        """Velocity (m/s) of the body point at ``point_m``."""
        r = np.asarray(point_m, float) - self.centre_of_mass_m
        return self.velocity_m_s + np.cross(self.angular_velocity_rad_s, r)


# ------------------------------------------------------------------------------ obstacles
@dataclass(frozen=True)
class BoxObstacle:
    """An oriented box obstacle (the column: axis-aligned, from the floor to its top)."""

    name: str
    kind: str
    centre_m: tuple[float, float, float]
    size_m: tuple[float, float, float]
    orientation: tuple[tuple[float, float, float], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@dataclass(frozen=True)
class PlaneObstacle:
    """A plane through ``point_m``; ``normal`` (unit) points into the flume (the bodies' side)."""

    name: str
    kind: str
    point_m: tuple[float, float, float]
    normal: tuple[float, float, float]


@dataclass(frozen=True)
class Obstacles:
    """A scene's obstacles: ``column`` (or None) and ``walls`` are impact targets; ``bed`` is not."""

    column: BoxObstacle | None
    walls: tuple[PlaneObstacle, ...]
    bed: PlaneObstacle

    @property
    def targets(self) -> tuple[BoxObstacle | PlaneObstacle, ...]:
        """Impact targets: the column (if any), then the walls."""
        return ((self.column,) if self.column is not None else ()) + self.walls


def scene_obstacles(scene: Scene, plan=None) -> Obstacles:
    """The column, walls and bed of ``scene``.

    Without ``plan`` the walls are the flume's: side walls at ``y = +-width/2``, the upstream
    wall at ``x = -reservoir.length_m``, and the downstream end wall when
    ``flume.downstream_end == "closed"``. With a :class:`~orchestrator.plan.planner.ModelPlan`, the
    modelled domain's boundaries are used instead (``plan.domain_m``; its upstream end is a
    wall also when the reservoir is cut short, and the downstream end is a wall only if
    ``plan.downstream_type == "wall"``): those are where the CFD has walls.
    """
    if plan is not None:
        (x0, x1), (y0, y1), _ = plan.domain_m
        downstream_wall = plan.downstream_type == "wall"
    else:
        (x0, x1), (y0, y1), _ = flume_extent(scene)
        downstream_wall = scene.flume.downstream_end == "closed"
    walls = [
        PlaneObstacle("side_wall_right", "wall", (0.0, float(y0), 0.0), (0.0, 1.0, 0.0)),
        PlaneObstacle("side_wall_left", "wall", (0.0, float(y1), 0.0), (0.0, -1.0, 0.0)),
        PlaneObstacle("upstream_wall", "wall", (float(x0), 0.0, 0.0), (1.0, 0.0, 0.0)),
    ]
    if downstream_wall:
        walls.append(PlaneObstacle("downstream_wall", "wall", (float(x1), 0.0, 0.0), (-1.0, 0.0, 0.0)))
    column = None
    if scene.column is not None:
        col = scene.column
        column = BoxObstacle(
            "column",
            "column",
            (col.x_m, col.y_m, col.height_m / 2.0),
            (col.size_x_m, col.size_y_m, col.height_m),
        )
    bed = PlaneObstacle("bed", "bed", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
    return Obstacles(column, tuple(walls), bed)


# ------------------------------------------------------------------------------ contacts
@dataclass(frozen=True)
class Proximity:
    """Closest approach of a body to something: signed distance (m; < 0 = penetration
    depth), contact point (m) and unit normal from the other thing into the body."""

    distance_m: float
    point: np.ndarray
    normal: np.ndarray


@dataclass(frozen=True)
class Contact:
    """A body within the gap of an obstacle or another body.

    ``body`` and ``other`` are names (``other`` is the obstacle's name for column and
    walls); ``normal`` points from ``other`` into ``body``; ``distance_m`` < 0 is a
    penetration depth; ``kind`` is ``"column"``, ``"wall"`` or ``"body"``.
    """

    body: str
    other: str
    point: np.ndarray
    normal: np.ndarray
    distance_m: float
    kind: ContactKind


def find_contacts(
    states: Sequence[BodyState],
    obstacles: Obstacles | Iterable[BoxObstacle | PlaneObstacle],
    gap_m: float,
) -> list[Contact]:
    """Every body-obstacle and body-body pair closer than ``gap_m`` (distance < gap_m).

    ``obstacles`` is an :class:`Obstacles` (its :attr:`~Obstacles.targets`: the bed is not an
    impact target) or any iterable of obstacles. Body pairs are reported once, the earlier
    state in ``states`` as ``body``. Boxes whose separating-axis lower bound on the distance
    is already >= ``gap_m`` are skipped before the exact distance is computed.
    """
    gap = float(gap_m)
    if not math.isfinite(gap):
        raise InputError("gap_m", f"must be finite, got {gap_m!r}")
    targets = obstacles.targets if isinstance(obstacles, Obstacles) else tuple(obstacles)
    states = list(states)
    names = [s.name for s in states]
    if len(set(names)) != len(names):
        raise InputError("states", f"body names must be unique, got {names}")
    found: list[Contact] = []
    for state in states:
        box = _Box.of(state)
        for obs in targets:
            if isinstance(obs, PlaneObstacle):
                prox = _box_plane(box, np.asarray(obs.point_m, float), np.asarray(obs.normal, float))
            else:
                other = _Box.of_obstacle(obs)
                if _sat_lower_bound(box, other) >= gap:
                    continue
                prox = _box_box(box, other)
            if prox.distance_m < gap:
                kind = "column" if obs.kind == "column" else "wall"
                found.append(Contact(state.name, obs.name, prox.point, prox.normal, prox.distance_m, kind))
    for i, a in enumerate(states):
        box_a = _Box.of(a)
        for b in states[i + 1 :]:
            box_b = _Box.of(b)
            if _sat_lower_bound(box_a, box_b) >= gap:
                continue
            prox = _box_box(box_a, box_b)
            if prox.distance_m < gap:
                found.append(Contact(a.name, b.name, prox.point, prox.normal, prox.distance_m, "body"))
    return found


def box_box_proximity(
    centre_a, orientation_a, size_a, centre_b, orientation_b, size_b
) -> Proximity:
    """Signed distance, contact point and normal (from box b into box a) of two oriented boxes.

    Sizes are full edge lengths along each box's axes (the columns of its orientation).
    """
    return _box_box(_Box.make(centre_a, orientation_a, size_a), _Box.make(centre_b, orientation_b, size_b))


def box_plane_proximity(centre, orientation, size, plane_point, plane_normal) -> Proximity:
    """Signed distance of an oriented box from a plane (normal into the box's side)."""
    n = np.asarray(plane_normal, float)
    n = n / np.linalg.norm(n)
    return _box_plane(_Box.make(centre, orientation, size), np.asarray(plane_point, float), n)


# ------------------------------------------------------------------------------ watching
def time_to_contact(
    state: BodyState,
    obstacle: BoxObstacle | PlaneObstacle | BodyState,
    horizon_s: float,
    gap_m: float = 0.0,
) -> float:
    """Earliest time (s) within ``horizon_s`` at which ``state`` comes within ``gap_m`` of
    ``obstacle``, extrapolating the present motion linearly; ``math.inf`` if not before the
    horizon, 0 if it already is.

    Planes: each corner moves with its present velocity ``v + omega x r``. Boxes (the column,
    another body): the separating-axis test swept along the relative translation (exact for
    translation), with each axis's overlap allowance grown by ``|omega| R t`` (``R`` the
    half-diagonal) so a rotating corner is not missed; the gap widens each axis's slab, which
    errs early at corners. The runner can watch ``state`` closely from then on.
    """
    horizon = float(horizon_s)
    if not horizon >= 0.0:
        raise InputError("horizon_s", f"must be >= 0, got {horizon_s!r}")
    gap = float(gap_m)
    box = _Box.of(state)
    if isinstance(obstacle, PlaneObstacle):
        n = np.asarray(obstacle.normal, float)
        corners = box.corners()
        dist = (corners - np.asarray(obstacle.point_m, float)) @ n - gap
        if dist.min() <= 0.0:
            return 0.0
        rates = np.array([n @ state.point_velocity(c) for c in corners])
        closing = rates < 0.0
        if not closing.any():
            return math.inf
        t = float(np.min(dist[closing] / -rates[closing]))
        return t if t <= horizon else math.inf
    if isinstance(obstacle, BodyState):
        other = _Box.of(obstacle)
        v_rel = state.velocity_m_s - obstacle.velocity_m_s
        spin = np.linalg.norm(state.angular_velocity_rad_s) * np.linalg.norm(box.half) + np.linalg.norm(
            obstacle.angular_velocity_rad_s
        ) * np.linalg.norm(other.half)
    else:
        other = _Box.of_obstacle(obstacle)
        v_rel = state.velocity_m_s
        spin = np.linalg.norm(state.angular_velocity_rad_s) * np.linalg.norm(box.half)
    start, end = 0.0, horizon
    d = box.centre - other.centre  # separation of the body from the obstacle, moving with v_rel
    for axis in _sat_axes(box, other):
        reach = box.radius(axis) + other.radius(axis) + gap
        a, b = float(d @ axis), float(v_rel @ axis)
        # |a + b t| <= reach + spin t  <=>  (b - spin) t <= reach - a  and  (-b - spin) t <= reach + a
        for coef, rhs in ((b - spin, reach - a), (-b - spin, reach + a)):
            if abs(coef) < 1e-300:
                if rhs < 0.0:
                    return math.inf
            elif coef > 0.0:
                end = min(end, rhs / coef)
            else:
                start = max(start, rhs / coef)
        if start > end:
            return math.inf
    return start


# ------------------------------------------------------------------------------ bed
def bed_clearance(state: BodyState, bed: PlaneObstacle | Obstacles) -> float:
    """Signed distance (m) of the body's lowest corner above the bed (< 0: sunk into it)."""
    plane = bed.bed if isinstance(bed, Obstacles) else bed
    n = np.asarray(plane.normal, float)
    return float(np.min((state.corners() - np.asarray(plane.point_m, float)) @ n))


def clamp_to_bed(state: BodyState, bed: PlaneObstacle | Obstacles) -> BodyState:
    """``state`` lifted out of the bed if it has sunk into it, its velocity into the bed removed.

    A body resting on or above the bed is returned unchanged. Otherwise it is moved along
    the bed normal by the penetration and the centre of mass's velocity component into the
    bed is set to zero (the bed is not an impact target: this only stops a body sinking).
    """
    plane = bed.bed if isinstance(bed, Obstacles) else bed
    clearance = bed_clearance(state, plane)
    if clearance >= 0.0:
        return state
    n = np.asarray(plane.normal, float)
    v = state.velocity_m_s
    vn = float(v @ n)
    return state.replace(
        centre_of_mass_m=state.centre_of_mass_m - clearance * n,
        velocity_m_s=v - min(vn, 0.0) * n,
    )


# ------------------------------------------------------------------------------ resolve
def resolve(
    contact: Contact,
    states: Sequence[BodyState],
    scene: Scene,
    *,
    added_mass_coefficient: float = DEFAULT_ADDED_MASS_COEFFICIENT,
    **impact_options,
) -> tuple[ImpactResult | None, tuple[BodyState, ...]]:
    """Resolve ``contact`` with :mod:`analytical.impact`; return the impact and the new states.

    The impact inputs come from the states: the inverse inertia tensor in the global frame
    from the principal moments and the orientation; for a column contact, the column of
    ``scene`` (:func:`~orchestrator.scene.schema.column_for_analysis`) struck at the contact
    point's height; a rigid wall for walls; for two bodies, their two-body effective mass on
    one contact spring (no column). The contact law and the friction coefficient are the
    body's (its scene ``contact`` section, :func:`body_contact_law`; a body pair: the two
    springs in series, :func:`pair_contact_law`); ``impact_options`` go to
    :func:`~analytical.impact.impact` / :func:`~analytical.impact.pair_impact` on top of
    them (stiffness, friction, damping, ...).

    Returns ``(result, new_states)``: ``new_states`` holds the bodies involved (``contact.body``,
    then ``contact.other`` for body pairs) with their post-impact velocities. A body that
    penetrates is first moved out along the normal to touching (a pair shares the move in
    inverse proportion to mass). If the contact point is not approaching (already separating),
    there is no impact: ``result`` is None and only the penetration, if any, is removed.
    The impact is taken as instantaneous on the flow's time scale: positions are not advanced.
    """
    by_name = {s.name: s for s in states}
    body = by_name.get(contact.body)
    if body is None:
        raise InputError("contact.body", f"no state for body {contact.body!r}")
    n = np.asarray(contact.normal, float)
    point = np.asarray(contact.point, float)
    depth = max(-float(contact.distance_m), 0.0)

    if contact.kind == "body":
        other = by_name.get(contact.other)
        if other is None:
            raise InputError("contact.other", f"no state for body {contact.other!r}")
        share = other.mass_kg / (body.mass_kg + other.mass_kg)
        moved_body = body.replace(centre_of_mass_m=body.centre_of_mass_m + share * depth * n)
        moved_other = other.replace(centre_of_mass_m=other.centre_of_mass_m - (1.0 - share) * depth * n)
        u_rel = body.point_velocity(contact.point) - other.point_velocity(contact.point)
        if not float(n @ u_rel) < 0.0:
            return None, (moved_body, moved_other)
        result = pair_impact(
            _impact_body(body, added_mass_coefficient),
            _impact_body(other, added_mass_coefficient),
            contact.point,
            n,
            **{**_scene_options(scene, body.name, other.name), **impact_options},
        )
        return result, (
            moved_body.replace(
                velocity_m_s=result.velocity_out_m_s, angular_velocity_rad_s=result.angular_velocity_out_rad_s
            ),
            moved_other.replace(
                velocity_m_s=result.other_velocity_out_m_s,
                angular_velocity_rad_s=result.other_angular_velocity_out_rad_s,
            ),
        )

    moved = body.replace(centre_of_mass_m=body.centre_of_mass_m + depth * n)
    if not float(n @ body.point_velocity(contact.point)) < 0.0:
        return None, (moved,)
    if contact.kind == "column":
        column = column_for_analysis(scene)
        height = min(max(float(point[2]), 1e-6 * column.height_m), column.height_m)
        target: RigidWall | ColumnTarget = ColumnTarget(column, height)
    elif contact.kind == "wall":
        target = RigidWall()
    else:
        raise InputError("contact.kind", f"must be 'column', 'wall' or 'body', got {contact.kind!r}")
    result = impact(_impact_body(body, added_mass_coefficient), contact.point, n, target,
                    **{**_scene_options(scene, body.name), **impact_options})
    return result, (
        moved.replace(velocity_m_s=result.velocity_out_m_s, angular_velocity_rad_s=result.angular_velocity_out_rad_s),
    )


def body_contact_law(contact) -> ContactLaw:
    """The contact law of a scene body's ``contact`` section (:class:`orchestrator.scene.schema.DebrisContact`)."""
    return contact_law(contact.law, contact.stiffness_N_m, contact.damping_ratio, contact.restitution)


def pair_contact_law(a: ContactLaw, b: ContactLaw) -> ContactLaw:
    """Two bodies' contact springs in series (``1/k = 1/k_a + 1/k_b``) with the mean of their
    damping ratios: two seed containers give ``k / 2`` and their own damping."""
    k = 1.0 / (1.0 / a.stiffness_N_m + 1.0 / b.stiffness_N_m)
    name = a.name if a.name == b.name else f"{a.name} + {b.name}"
    return ContactLaw(k, 0.5 * (a.damping_ratio + b.damping_ratio), f"{name}, body-body")


def _scene_options(scene: Scene, name: str, other: str | None = None) -> dict:
    """Impact keywords from the scene bodies' contact sections (empty for unknown bodies)."""
    bodies = {b.name: b for b in scene.debris}
    if name not in bodies or (other is not None and other not in bodies):
        return {}
    first = bodies[name].contact
    law = body_contact_law(first)
    friction = first.friction_coefficient
    if other is not None:
        second = bodies[other].contact
        law = pair_contact_law(law, body_contact_law(second))
        friction = 0.5 * (friction + second.friction_coefficient)
    return {**law.options(), "friction_coefficient": friction}


def _impact_body(state: BodyState, added_mass_coefficient: float) -> Body:
    return Body(
        mass_kg=state.mass_kg,
        inverse_inertia=state.inverse_inertia(),
        centre_of_mass_m=state.centre_of_mass_m,
        velocity_m_s=state.velocity_m_s,
        angular_velocity_rad_s=state.angular_velocity_rad_s,
        added_mass_coefficient=added_mass_coefficient,
    )


# ------------------------------------------------------------------------------ geometry
# Corner i has body signs ((i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1) -> -1/+1.
_SIGNS = np.array([[1.0 if (i >> k) & 1 else -1.0 for k in range(3)] for i in range(8)])
# The 12 edges: corner pairs that differ in one sign.
_EDGES = np.array([(i, i | (1 << k)) for k in range(3) for i in range(8) if not (i >> k) & 1])
# The 6 faces as corner loops (outward normal along axis k, sign s).
_FACES = []
for _k in range(3):
    _a, _b = (_k + 1) % 3, (_k + 2) % 3
    for _s in (0, 1):
        _base = _s << _k
        _loop = [_base, _base | (1 << _a), _base | (1 << _a) | (1 << _b), _base | (1 << _b)]
        _FACES.append(_loop)
_FACES = np.array(_FACES)


@dataclass(frozen=True)
class _Box:
    centre: np.ndarray
    rot: np.ndarray  # columns: the box axes
    half: np.ndarray

    @classmethod
    def make(cls, centre, rot, size) -> "_Box":
        c = _vec3("centre", centre)
        r = np.array(rot, dtype=float)
        if r.shape != (3, 3):
            raise InputError("orientation", f"must be 3x3, got shape {r.shape}")
        s = _vec3("size", size)
        if np.any(s <= 0.0):
            raise InputError("size", f"must all be > 0, got {s.tolist()}")
        return cls(c, r, s / 2.0)

    @classmethod
    def of(cls, state: BodyState) -> "_Box":
        return cls(state.centre_of_mass_m, state.orientation, state.size_m / 2.0)

    @classmethod
    def of_obstacle(cls, obs: BoxObstacle) -> "_Box":
        return cls.make(obs.centre_m, obs.orientation, obs.size_m)

    def corners(self) -> np.ndarray:
        return self.centre + (_SIGNS * self.half) @ self.rot.T

    def radius(self, axis: np.ndarray) -> float:
        """Half-extent of the box's projection on a unit axis."""
        return float(np.sum(self.half * np.abs(self.rot.T @ axis)))

    def closest_point(self, p: np.ndarray) -> np.ndarray:
        """Closest point of the (solid) box to each row of ``p``."""
        local = (p - self.centre) @ self.rot
        return self.centre + np.clip(local, -self.half, self.half) @ self.rot.T

    def scale(self) -> float:
        return float(2.0 * np.max(self.half))


def _sat_axes(a: _Box, b: _Box) -> list[np.ndarray]:
    axes = [a.rot[:, i] for i in range(3)] + [b.rot[:, i] for i in range(3)]
    for i in range(3):
        for j in range(3):
            cross = np.cross(a.rot[:, i], b.rot[:, j])
            norm = np.linalg.norm(cross)
            if norm > 1e-9:
                axes.append(cross / norm)
    return axes


def _sat_separations(a: _Box, b: _Box):
    """(axis, separation along it) for the 15 axes; separation > 0 means a separating axis."""
    d = b.centre - a.centre
    out = []
    for k, axis in enumerate(_sat_axes(a, b)):
        out.append((k < 6, axis, abs(float(d @ axis)) - a.radius(axis) - b.radius(axis)))
    return out


def _sat_lower_bound(a: _Box, b: _Box) -> float:
    """A lower bound on the distance between the boxes (the largest axis separation)."""
    return max(sep for _, _, sep in _sat_separations(a, b))


def _box_plane(box: _Box, point: np.ndarray, n: np.ndarray) -> Proximity:
    corners = box.corners()
    dist = (corners - point) @ n
    d = float(dist.min())
    near = dist <= d + _FEATURE_REL_TOL * box.scale()
    feature = corners[near].mean(axis=0)  # a vertex, an edge midpoint or a face centre
    p = feature - 0.5 * d * n
    return _proximity(d, p, n)


def _box_box(a: _Box, b: _Box) -> Proximity:
    """Proximity of box ``a`` (the body) to box ``b``; normal from b into a."""
    scale = max(a.scale(), b.scale())
    tol = _REL_TOL * scale
    seps = _sat_separations(a, b)
    best = max(seps, key=lambda s: s[2])
    if best[2] > tol:
        return _separated(a, b, tol)
    # Touching or overlapping: the axis of least penetration, face axes preferred on ties.
    face = max((s for s in seps if s[0]), key=lambda s: s[2])
    edges = [s for s in seps if not s[0]]
    chosen = face
    if edges:
        edge = max(edges, key=lambda s: s[2])
        if edge[2] > face[2] + tol:
            chosen = edge
    _, axis, sep = chosen
    normal = axis if float((a.centre - b.centre) @ axis) >= 0.0 else -axis
    point = _intersection_centroid(a, b, normal, tol)
    return _proximity(min(sep, 0.0), point, normal)


def _separated(a: _Box, b: _Box, tol: float) -> Proximity:
    """Exact distance of separated boxes: vertex-box and edge-edge candidates."""
    ca, cb = a.corners(), b.corners()
    pa = [ca, b.closest_point(ca)]  # a's vertices and their closest points on b
    qb = [a.closest_point(cb), cb]  # points on a closest to b's vertices, and the vertices
    p_a = np.vstack([pa[0], qb[0]])
    p_b = np.vstack([pa[1], qb[1]])
    ea, eb = _segment_pairs(ca[_EDGES[:, 0]], ca[_EDGES[:, 1]], cb[_EDGES[:, 0]], cb[_EDGES[:, 1]])
    p_a = np.vstack([p_a, ea])
    p_b = np.vstack([p_b, eb])
    gaps = np.linalg.norm(p_a - p_b, axis=1)
    d = float(gaps.min())
    best = int(np.argmin(gaps))
    normal = (p_a[best] - p_b[best]) / d
    near = gaps <= d + tol
    mids = 0.5 * (p_a[near] + p_b[near])
    point = _unique_rows(mids, tol).mean(axis=0)
    return _proximity(d, point, normal)


def _segment_pairs(p0, p1, q0, q1):
    """Closest points of every segment ``p0[i]-p1[i]`` to every ``q0[j]-q1[j]`` (flattened)."""
    P0 = np.repeat(p0, len(q0), axis=0)
    D1 = np.repeat(p1 - p0, len(q0), axis=0)
    Q0 = np.tile(q0, (len(p0), 1))
    D2 = np.tile(q1 - q0, (len(p0), 1))
    r = P0 - Q0
    a = np.einsum("ij,ij->i", D1, D1)
    e = np.einsum("ij,ij->i", D2, D2)
    b = np.einsum("ij,ij->i", D1, D2)
    c = np.einsum("ij,ij->i", D1, r)
    f = np.einsum("ij,ij->i", D2, r)
    denom = a * e - b * b
    parallel = denom <= 1e-12 * a * e
    # Unconstrained minimiser of |P0 + s D1 - Q0 - t D2|^2 for s, clamped; then t for that s.
    s = np.where(parallel, 0.0, np.clip((b * f - c * e) / np.where(parallel, 1.0, denom), 0.0, 1.0))
    t = (b * s + f) / e
    # t outside [0, 1]: clamp it and recompute s for that t.
    low, high = t < 0.0, t > 1.0
    t = np.clip(t, 0.0, 1.0)
    s = np.where(low, np.clip(-c / a, 0.0, 1.0), s)
    s = np.where(high, np.clip((b - c) / a, 0.0, 1.0), s)
    return P0 + s[:, None] * D1, Q0 + t[:, None] * D2


def _intersection_centroid(a: _Box, b: _Box, normal: np.ndarray, tol: float) -> np.ndarray:
    """Centroid of the intersection of two touching/overlapping boxes.

    The intersection polytope's vertices come from each box's faces clipped by the other's
    six half-spaces; the centroid is that of its volume, or, when it is flat (touching
    boxes), of its area seen along ``normal``, or of its extent when it is a segment or a point.
    """
    points = []
    for clip, by in ((a, b), (b, a)):
        corners = clip.corners()
        for face in _FACES:
            poly = corners[face]
            for k in range(3):
                axis = by.rot[:, k]
                centre = float(by.centre @ axis)
                poly = _clip(poly, axis, centre + by.half[k] + tol)
                if len(poly) == 0:
                    break
                poly = _clip(poly, -axis, -centre + by.half[k] + tol)
                if len(poly) == 0:
                    break
            if len(poly):
                points.append(poly)
    if not points:  # numerically touching at a point the clipping lost: the closest corner pair
        ca = a.corners()
        pa = b.closest_point(ca)
        ia = int(np.argmin(np.linalg.norm(ca - pa, axis=1)))
        return 0.5 * (ca[ia] + pa[ia])
    pts = _unique_rows(np.vstack(points), tol)
    return _centroid(pts, normal, tol)


def _centroid(pts: np.ndarray, normal: np.ndarray, tol: float) -> np.ndarray:
    """Volume centroid of the convex hull of ``pts``; area centroid across ``normal`` if flat."""
    mean = pts.mean(axis=0)
    heights = pts @ normal
    flat = float(heights.max() - heights.min()) <= 100.0 * tol  # touching: a patch, not a volume
    if len(pts) >= 4 and not flat:
        try:
            hull = ConvexHull(pts)
        except QhullError:
            hull = None
        if hull is not None and hull.volume > tol**3:
            tri = pts[hull.simplices]  # (m, 3, 3) boundary triangles
            # tetrahedra from an interior point (the vertex mean) to each boundary triangle;
            # qhull does not orient its simplices, hence the absolute value
            vols = np.abs(np.einsum("ij,ij->i", tri[:, 0] - mean, np.cross(tri[:, 1] - mean, tri[:, 2] - mean))) / 6.0
            cents = (tri.sum(axis=1) + mean) / 4.0
            return (vols[:, None] * cents).sum(axis=0) / vols.sum()
    if len(pts) >= 3:
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(normal, helper)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        uv = np.column_stack([(pts - mean) @ e1, (pts - mean) @ e2])
        try:
            hull = ConvexHull(uv)
        except QhullError:
            hull = None
        if hull is not None and hull.volume > tol**2:  # in 2-D, volume is the area
            ring = uv[hull.vertices]
            x, y = ring[:, 0], ring[:, 1]
            xn, yn = np.roll(x, -1), np.roll(y, -1)
            cross = x * yn - xn * y
            area = cross.sum() / 2.0
            cx = ((x + xn) * cross).sum() / (6.0 * area)
            cy = ((y + yn) * cross).sum() / (6.0 * area)
            depth = float(((pts - mean) @ normal).mean())
            return mean + cx * e1 + cy * e2 + depth * normal
    # a segment or a point: the middle of its extent
    return 0.5 * (pts.min(axis=0) + pts.max(axis=0)) if len(pts) > 1 else pts[0]


def _clip(poly: np.ndarray, n: np.ndarray, offset: float) -> np.ndarray:
    """Sutherland-Hodgman: the part of polygon ``poly`` with ``x . n <= offset``."""
    out = []
    m = len(poly)
    dist = poly @ n - offset
    for i in range(m):
        cur, nxt = poly[i], poly[(i + 1) % m]
        dc, dn = dist[i], dist[(i + 1) % m]
        if dc <= 0.0:
            out.append(cur)
        if (dc < 0.0 < dn) or (dn < 0.0 < dc):
            out.append(cur + (dc / (dc - dn)) * (nxt - cur))
    return np.array(out).reshape(-1, 3)


def _unique_rows(points: np.ndarray, tol: float) -> np.ndarray:
    kept: list[np.ndarray] = []
    for p in points:
        if not any(np.linalg.norm(p - q) <= tol for q in kept):
            kept.append(p)
    return np.array(kept)


def _proximity(d: float, point: np.ndarray, normal: np.ndarray) -> Proximity:
    point = np.array(point, dtype=float)
    normal = np.array(normal, dtype=float) / np.linalg.norm(normal)
    point.setflags(write=False)
    normal.setflags(write=False)
    return Proximity(float(d), point, normal)


def _vec3(name: str, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be 3 numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise InputError(name, f"must be 3 finite numbers, got {value!r}")
    return arr


def _freeze(obj, name: str, arr: np.ndarray) -> None:
    arr = np.array(arr, dtype=float)
    arr.setflags(write=False)
    object.__setattr__(obj, name, arr)
