"""The runner's view of contact geometry: its body states against the case's obstacles.

`orchestrator.contact.geometry` works on `bodystate.BodyState` with the body's box (size, mass,
inertia: `geometry.box_state`); the runner's states (what the solver reports) carry no box.
`Geometry` adds the plan's box to them for one case: it builds the scene's obstacles for the modelled
domain, finds every contact within a reach (the bed too) with the closing speed of the
contact point (`Contact`), resolves an impact (`contact.resolve`) and lifts a body out of
the bed (`contact.clamp_to_bed`). `resting_contact` stops a slow contact's closing motion
with a plastic impulse instead of an impact.

Units: seconds, metres, kg, N.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from orchestrator.case import bodystate
from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import CaseFolder
from orchestrator.contact import geometry as geo
from orchestrator.contact.resolution import resolve
from orchestrator.contact.settings import ContactSettings
from orchestrator.run.case_info import CaseInfo

__all__ = ["Contact", "Geometry", "resting_contact"]


@dataclass(frozen=True)
class Contact:
    """A body near an obstacle, another body or the bed: signed `distance_m` (< 0:
    overlapping), the contact point, the unit `normal` from the other thing into the body,
    and the closing speed of the contact point along it (> 0: approaching). `source` is
    orchestrator.contact.geometry's BoxContact (None for the bed)."""

    body: str
    other: str
    kind: str  # "column", "wall", "body" or "bed"
    distance_m: float
    point_m: tuple[float, float, float]
    normal: tuple[float, float, float]
    approach_m_s: float
    source: Any = field(default=None, compare=False, repr=False)


class Geometry:
    """The case's obstacles (from scene.yaml and plan.json) and its bodies, for orchestrator.contact.geometry."""

    def __init__(self, info: CaseInfo):
        self.scene = CaseFolder(info.case).scene()
        # the modelled domain's walls: where the CFD has them (its upstream end is a wall
        # also when the reservoir is cut short; the downstream end only if it is a wall)
        self.obstacles = geo.scene_obstacles(
            self.scene, geo.ModelledDomain(info.domain_m, info.downstream_type))
        self.bodies = {b.name: b for b in info.bodies}  # the plan's: mass and inertia
        self.sizes = info.body_sizes_m

    def state(self, s: BodyState) -> BodyState:
        """``s`` with the plan's box, as orchestrator.contact.geometry takes it (orientation made orthonormal)."""
        p = self.bodies[s.name]
        return geo.box_state(s.name, s.centre_of_mass_m, np.asarray(bodystate.orthonormal(s.orientation)).reshape(3, 3),
                             s.velocity_m_s, s.angular_velocity_rad_s, self.sizes[s.name], p.mass_kg,
                             p.moment_of_inertia_kg_m2, s.time_s)

    @staticmethod
    def back(new, old: BodyState) -> BodyState:
        """orchestrator.contact.geometry's state as the runner's (velocities changed: acceleration unknown)."""
        moved = not np.allclose(new.velocity_m_s, old.velocity_m_s, rtol=0, atol=1e-15) or not np.allclose(
            new.angular_velocity_rad_s, old.angular_velocity_rad_s, rtol=0, atol=1e-15)
        return old.with_changes(
            centre_of_mass_m=tuple(float(v) for v in new.centre_of_mass_m),
            orientation=tuple(float(v) for v in np.asarray(new.orientation).ravel()),
            velocity_m_s=tuple(float(v) for v in new.velocity_m_s),
            angular_velocity_rad_s=tuple(float(v) for v in new.angular_velocity_rad_s),
            acceleration_m_s2=(0.0, 0.0, 0.0) if moved else old.acceleration_m_s2)

    def contacts(self, states: Sequence[BodyState], reach_m: float, bed: bool = True) -> list[Contact]:
        """Every pair closer than `reach_m` (the bed too, if `bed`), with closing speeds."""
        cs = {s.name: self.state(s) for s in states}
        out = []
        for c in geo.find_contacts(list(cs.values()), self.obstacles, reach_m):
            u = geo.point_velocity(cs[c.body], c.point)
            if c.kind == "body":
                u = u - geo.point_velocity(cs[c.other], c.point)
            n = np.asarray(c.normal, dtype=float)
            out.append(Contact(c.body, c.other, c.kind, float(c.distance_m), tuple(float(v) for v in c.point),
                               tuple(float(v) for v in n), float(-(u @ n)), c))
        if bed:
            plane = self.obstacles.bed
            n = np.asarray(plane.normal, dtype=float)
            for name, c in cs.items():
                corners = geo.corners(c)
                heights = (corners - np.asarray(plane.point_m, dtype=float)) @ n
                d = float(heights.min())
                if d < reach_m:
                    low = corners[heights <= d + 1e-9].mean(axis=0)
                    out.append(Contact(name, "bed", "bed", d, tuple(float(v) for v in low), tuple(float(v) for v in n),
                                       float(-(geo.point_velocity(c, low) @ n))))
        return out

    def resolve(self, contact: Contact, states: dict[str, BodyState], settings: ContactSettings):
        """The impact of `contact` (orchestrator.contact.resolution.resolve): (result or None, new states by body)."""
        cs = [self.state(s) for s in states.values()]
        result, new = resolve(contact.source, cs, self.scene,
                              added_mass_coefficient=settings.added_mass_coefficient, **settings.impact)
        return result, {n.name: self.back(n, states[n.name]) for n in new}

    def clamp_to_bed(self, state: BodyState) -> BodyState:
        """The body lifted out of the bed, its velocity into the bed removed (unchanged if above it)."""
        c = self.state(state)
        clamped = geo.clamp_to_bed(c, self.obstacles)
        return state if clamped is c else self.back(clamped, state)


def resting_contact(geometry: Geometry, contact: Contact, states: dict[str, BodyState],
                    separation_m: float = 0.0) -> tuple[dict, float]:
    """A slow contact: the impulse through the contact point that stops the closing motion
    (perfectly plastic, no force history), and the bodies moved apart along the normal until
    they are `separation_m` apart (0: only an overlap removed). The move is a position
    correction: velocities and so momentum are those after the impulse; between two bodies
    the lighter one moves more, and the pair's centre of mass stays where it was.
    Returns (new states by body, impulse in N s)."""
    n, point = np.asarray(contact.normal), np.asarray(contact.point_m)
    sides = [(contact.body, 1.0)] + ([(contact.other, -1.0)] if contact.kind == "body" else [])
    bodies = {name: geometry.state(states[name]) for name, _ in sides}

    def compliance(b) -> np.ndarray:  # velocity change of the contact point per unit impulse there
        r = point - np.asarray(b.centre_of_mass_m, float)
        rx = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
        return np.eye(3) / b.mass_kg + rx.T @ geo.inverse_inertia(b) @ rx

    k = sum(compliance(b) for b in bodies.values())
    j = max(contact.approach_m_s, 0.0) / float(n @ k @ n)  # N s along n, on the body
    depth = max(separation_m - contact.distance_m, 0.0)
    total_mass = sum(b.mass_kg for b in bodies.values())
    new = {}
    for name, sign in sides:
        b = bodies[name]
        impulse = sign * j * n
        com = np.asarray(b.centre_of_mass_m, float)
        v = np.asarray(b.velocity_m_s, float) + impulse / b.mass_kg
        w = np.asarray(b.angular_velocity_rad_s, float) + geo.inverse_inertia(b) @ np.cross(point - com, impulse)
        share = 1.0 if len(sides) == 1 else 1.0 - b.mass_kg / total_mass  # the lighter body moves more
        centre = com + sign * share * depth * n
        new[name] = states[name].with_changes(centre_of_mass_m=tuple(float(x) for x in centre),
                                              velocity_m_s=tuple(float(x) for x in v),
                                              angular_velocity_rad_s=tuple(float(x) for x in w),
                                              acceleration_m_s2=(0.0, 0.0, 0.0))
    return new, float(j)
