"""Debris contact: the obstacles of a scene, finding contacts and watching them (no OpenFOAM here).

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
* decide how closely to watch (:func:`time_to_contact`).

The box geometry (exact box-box and box-plane distances) is `orchestrator.contact.boxes`'s;
resolving a contact as an impact is `orchestrator.contact.resolution`'s.

Units: m, s, kg, rad. Normals point from the obstacle (or the other body) into the body.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from orchestrator.core.errors import InputError
from analytical.impact_bodies import inverse_inertia_tensor
from orchestrator.case.bodystate import BodyState
from orchestrator.contact.boxes import Box, box_box, box_plane, sat_axes, sat_lower_bound, vec3
from orchestrator.scene.geometry import flume_extent
from orchestrator.scene.schema import Scene

__all__ = [
    "Obstacle",
    "BoxObstacle",
    "PlaneObstacle",
    "Obstacles",
    "BoxContact",
    "ModelledDomain",
    "scene_obstacles",
    "find_contacts",
    "time_to_contact",
    "bed_clearance",
    "box_state",
    "clamp_to_bed",
    "corners",
    "inverse_inertia",
    "moved",
    "plan_state",
    "point_velocity",
]

ContactKind = Literal["column", "wall", "body"]


# ------------------------------------------------------------------------------ states
def _floats(value) -> tuple[float, ...]:
    return tuple(float(v) for v in np.asarray(value, float).ravel())


def box_state(name: str, centre_of_mass_m, orientation, velocity_m_s, angular_velocity_rad_s, size_m, mass_kg,
              inertia_kg_m2, time_s: float = 0.0) -> BodyState:
    """One debris body's rigid-body state with its box, as this stage needs it (global frame).

    ``orientation`` is the 3x3 rotation from body to global axes (columns: the body's length,
    width and height directions); ``size_m`` the box along the body axes [length, width,
    height] (m); ``inertia_kg_m2`` the principal moments about the body axes through the centre
    of mass. Every value is checked (InputError naming the body and the field).
    """
    if not isinstance(name, str) or not name:
        raise InputError("name", f"must be a non-empty string, got {name!r}")
    vectors = {f: vec3(f"{name}.{f}", v) for f, v in (("centre_of_mass_m", centre_of_mass_m),
                                                       ("velocity_m_s", velocity_m_s),
                                                       ("angular_velocity_rad_s", angular_velocity_rad_s))}
    size = vec3(f"{name}.size_m", size_m)
    if np.any(size <= 0.0):
        raise InputError(f"{name}.size_m", f"must all be > 0, got {size.tolist()}")
    inertia = vec3(f"{name}.inertia_kg_m2", inertia_kg_m2)
    if np.any(inertia <= 0.0):
        raise InputError(f"{name}.inertia_kg_m2", f"must all be > 0, got {inertia.tolist()}")
    rot = np.array(orientation, dtype=float)
    if rot.shape != (3, 3) or not np.all(np.isfinite(rot)):
        raise InputError(f"{name}.orientation", "must be a finite 3x3 matrix")
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) <= 0.0:
        raise InputError(f"{name}.orientation", "must be a rotation matrix (orthonormal, det +1)")
    try:
        mass = float(mass_kg)
    except (TypeError, ValueError):
        raise InputError(f"{name}.mass_kg", f"must be a number, got {mass_kg!r}") from None
    if not math.isfinite(mass) or mass <= 0.0:
        raise InputError(f"{name}.mass_kg", f"must be > 0, got {mass_kg!r}")
    return BodyState(name, float(time_s), _floats(vectors["centre_of_mass_m"]), _floats(rot),
                     _floats(vectors["velocity_m_s"]), _floats(vectors["angular_velocity_rad_s"]),
                     size_m=_floats(size), mass_kg=mass, inertia_kg_m2=_floats(inertia))


def plan_state(body, velocity_m_s=(0.0, 0.0, 0.0), angular_velocity_rad_s=(0.0, 0.0, 0.0)) -> BodyState:
    """The :func:`box_state` of a planned body (:class:`orchestrator.plan.model.BodyPlan`) at its
    start, with the given motion."""
    return box_state(body.name, body.centre_of_mass_m, body.orientation, velocity_m_s, angular_velocity_rad_s,
                     body.size_m, body.mass_kg, body.moment_of_inertia_kg_m2)


def moved(state: BodyState, **changes) -> BodyState:
    """``state`` with some of its vectors changed (given as arrays or sequences)."""
    return state.with_changes(**{k: _floats(v) for k, v in changes.items()})


def corners(state: BodyState) -> np.ndarray:
    """The 8 corners (8x3, m) of a body's box, corner ``i`` at body signs ``(bit0, bit1, bit2)`` of ``i``."""
    return Box.of(state).corners()


def inverse_inertia(state: BodyState) -> np.ndarray:
    """Inverse inertia tensor of a body's box in the global frame (1/(kg m^2))."""
    return inverse_inertia_tensor(np.asarray(state.inertia_kg_m2, float), state.rotation)


def point_velocity(state: BodyState, point_m) -> np.ndarray:
    """Velocity (m/s) of the body point at ``point_m``."""
    r = np.asarray(point_m, float) - np.asarray(state.centre_of_mass_m, float)
    return np.asarray(state.velocity_m_s, float) + np.cross(np.asarray(state.angular_velocity_rad_s, float), r)


# ------------------------------------------------------------------------------ obstacles
@dataclass(frozen=True)
class Obstacle:
    """What every obstacle has: its ``name`` and ``kind`` (column, wall, bed)."""

    name: str
    kind: str


@dataclass(frozen=True)
class BoxObstacle(Obstacle):
    """An oriented box obstacle (the column: axis-aligned, from the floor to its top)."""

    centre_m: tuple[float, float, float]
    size_m: tuple[float, float, float]
    orientation: tuple[tuple[float, float, float], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@dataclass(frozen=True)
class PlaneObstacle(Obstacle):
    """A plane through ``point_m``; ``normal`` (unit) points into the flume (the bodies' side)."""

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


@dataclass(frozen=True)
class ModelledDomain:
    """Where the CFD has walls: the modelled domain (``((x0, x1), (y0, y1), (z0, z1))``, m) and
    what its downstream end is (``"wall"`` or ``"outlet"``), as a :class:`~orchestrator.plan.model.ModelPlan`
    has them."""

    domain_m: tuple
    downstream_type: str


def scene_obstacles(scene: Scene, plan=None) -> Obstacles:
    """The column, walls and bed of ``scene``.

    Without ``plan`` the walls are the flume's: side walls at ``y = +-width/2``, the upstream
    wall at ``x = -reservoir.length_m``, and the downstream end wall when
    ``flume.downstream_end == "closed"``. With a :class:`~orchestrator.plan.planner.ModelPlan`, the
    modelled domain's boundaries are used instead (``plan.domain_m``; its upstream end is a
    wall also when the reservoir is cut short, and the downstream end is a wall only if
    ``plan.downstream_type == "wall"``): those are where the CFD has walls. Any object with
    ``domain_m`` and ``downstream_type`` serves (:class:`ModelledDomain`).
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
class BoxContact:
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
) -> list[BoxContact]:
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
    found: list[BoxContact] = []
    for state in states:
        box = Box.of(state)
        for obs in targets:
            if isinstance(obs, PlaneObstacle):
                prox = box_plane(box, np.asarray(obs.point_m, float), np.asarray(obs.normal, float))
            else:
                other = Box.of_obstacle(obs)
                if sat_lower_bound(box, other) >= gap:
                    continue
                prox = box_box(box, other)
            if prox.distance_m < gap:
                kind = "column" if obs.kind == "column" else "wall"
                found.append(BoxContact(state.name, obs.name, prox.point, prox.normal, prox.distance_m, kind))
    for i, a in enumerate(states):
        box_a = Box.of(a)
        for b in states[i + 1 :]:
            box_b = Box.of(b)
            if sat_lower_bound(box_a, box_b) >= gap:
                continue
            prox = box_box(box_a, box_b)
            if prox.distance_m < gap:
                found.append(BoxContact(a.name, b.name, prox.point, prox.normal, prox.distance_m, "body"))
    return found


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
    box = Box.of(state)
    if isinstance(obstacle, PlaneObstacle):
        n = np.asarray(obstacle.normal, float)
        corners = box.corners()
        dist = (corners - np.asarray(obstacle.point_m, float)) @ n - gap
        if dist.min() <= 0.0:
            return 0.0
        rates = np.array([n @ point_velocity(state, c) for c in corners])
        closing = rates < 0.0
        if not closing.any():
            return math.inf
        t = float(np.min(dist[closing] / -rates[closing]))
        return t if t <= horizon else math.inf
    velocity, omega = np.asarray(state.velocity_m_s, float), np.asarray(state.angular_velocity_rad_s, float)
    if isinstance(obstacle, BodyState):
        other = Box.of(obstacle)
        v_rel = velocity - np.asarray(obstacle.velocity_m_s, float)
        spin = np.linalg.norm(omega) * np.linalg.norm(box.half) + np.linalg.norm(
            np.asarray(obstacle.angular_velocity_rad_s, float)
        ) * np.linalg.norm(other.half)
    else:
        other = Box.of_obstacle(obstacle)
        v_rel = velocity
        spin = np.linalg.norm(omega) * np.linalg.norm(box.half)
    start, end = 0.0, horizon
    d = box.centre - other.centre  # separation of the body from the obstacle, moving with v_rel
    for axis in sat_axes(box, other):
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
    return float(np.min((corners(state) - np.asarray(plane.point_m, float)) @ n))


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
    v = np.asarray(state.velocity_m_s, float)
    vn = float(v @ n)
    return moved(state, centre_of_mass_m=np.asarray(state.centre_of_mass_m, float) - clearance * n,
                 velocity_m_s=v - min(vn, 0.0) * n)


