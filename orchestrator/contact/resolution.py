"""Resolving a contact as an impact: the column's MDOF model, a rigid wall, or two bodies.

The contact watch (`orchestrator.contact.geometry`) finds a body within the gap of an obstacle;
`resolve` turns that contact into an impact with `analytical.impact` and gives the bodies'
rebound states. The contact law and friction are the scene bodies' own (`body_contact_law`;
two bodies: their springs in series, `pair_contact_law`).

Units: m, s, kg, N.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from analytical.contact_law import ContactLaw, contact_law
from analytical.errors import InputError
from analytical.impact import impact, pair_impact
from analytical.impact_bodies import DEFAULT_ADDED_MASS_COEFFICIENT, Body, ColumnTarget, RigidWall
from analytical.impact_results import ImpactResult
from orchestrator.contact.geometry import BoxContact, BoxState
from orchestrator.scene.schema import Scene, column_for_analysis

__all__ = ["body_contact_law", "pair_contact_law", "resolve"]


def resolve(
    contact: BoxContact,
    states: Sequence[BoxState],
    scene: Scene,
    *,
    added_mass_coefficient: float = DEFAULT_ADDED_MASS_COEFFICIENT,
    **impact_options,
) -> tuple[ImpactResult | None, tuple[BoxState, ...]]:
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


def _impact_body(state: BoxState, added_mass_coefficient: float) -> Body:
    return Body(
        mass_kg=state.mass_kg,
        inverse_inertia=state.inverse_inertia(),
        centre_of_mass_m=state.centre_of_mass_m,
        velocity_m_s=state.velocity_m_s,
        angular_velocity_rad_s=state.angular_velocity_rad_s,
        added_mass_coefficient=added_mass_coefficient,
    )
