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

from analytical.column import Column
from analytical.contact_law import CONTAINER, ContactLaw, contact_law
from orchestrator.core.errors import InputError
from analytical.impact import DEFAULT_FRICTION_COEFFICIENT, impact, pair_impact
from analytical.added_mass import box_added_mass
from analytical.impact_bodies import Body, ColumnTarget, RigidWall
from analytical.impact_results import ImpactResult
from orchestrator.case.bodystate import BodyState
from orchestrator.contact.geometry import BoxContact, moved
from orchestrator.scene.schema import Scene, column_for_analysis

__all__ = ["body_contact_law", "pair_contact_law", "resolve", "resolve_bodies"]


def resolve(
    contact: BoxContact,
    states: Sequence[BodyState],
    scene: Scene,
    *,
    added_mass_coefficient: float | None = None,
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

    The water a body carries: None (the default) gives each body its own added mass along and
    about its axes at its floating draft (:func:`analytical.added_mass.box_added_mass`; the
    coupled path's bodies strike afloat), the same the one-way transport gives a body afloat at
    its draft; a number ``C_a`` gives ``m C_a`` on every axis (0: none).

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
    other = None
    if contact.kind == "body":
        other = by_name.get(contact.other)
        if other is None:
            raise InputError("contact.other", f"no state for body {contact.other!r}")
    elif contact.kind not in ("column", "wall"):
        raise InputError("contact.kind", f"must be 'column', 'wall' or 'body', got {contact.kind!r}")
    options = {**_scene_options(scene, body.name, other.name if other is not None else None), **impact_options}
    law = ContactLaw(options.pop("stiffness_N_m", CONTAINER.stiffness_N_m), options.pop("damping_ratio", 0.0))
    friction = options.pop("friction_coefficient", DEFAULT_FRICTION_COEFFICIENT)
    result, (move, other_move) = resolve_bodies(
        contact.kind, contact.point, contact.normal, max(-float(contact.distance_m), 0.0),
        _impact_body(body, added_mass_coefficient, scene), law, friction,
        other=_impact_body(other, added_mass_coefficient, scene) if other is not None else None,
        column=column_for_analysis(scene) if contact.kind == "column" else None, **options)
    out = moved(body, centre_of_mass_m=np.asarray(body.centre_of_mass_m, float) + move)
    if other is None:
        if result is None:
            return None, (out,)
        return result, (moved(out, velocity_m_s=result.velocity_out_m_s,
                              angular_velocity_rad_s=result.angular_velocity_out_rad_s),)
    out_other = moved(other, centre_of_mass_m=np.asarray(other.centre_of_mass_m, float) + other_move)
    if result is None:
        return None, (out, out_other)
    return result, (
        moved(out, velocity_m_s=result.velocity_out_m_s, angular_velocity_rad_s=result.angular_velocity_out_rad_s),
        moved(out_other, velocity_m_s=result.other_velocity_out_m_s,
              angular_velocity_rad_s=result.other_angular_velocity_out_rad_s),
    )


def resolve_bodies(kind: str, point_m, normal, depth_m: float, body: Body, law: ContactLaw,
                   friction_coefficient: float, *, other: Body | None = None, column: Column | None = None,
                   bed_z_m: float = 0.0, **impact_options) -> tuple[ImpactResult | None, tuple]:
    """One strike from the bodies' state: the resolution both coupling paths share.

    ``kind`` is ``"column"`` (``column`` struck at the contact point's height above
    ``bed_z_m``), ``"wall"`` (rigid) or ``"body"`` (``other``, the two springs of ``law``
    already in series: :func:`pair_contact_law`); ``normal`` points from the obstacle (or
    ``other``) into ``body``; ``depth_m`` >= 0 is the penetration found. Each body is an
    :class:`analytical.impact_bodies.Body` with its mass, rotational inertia and the added
    mass of the water it carries (anisotropic, :meth:`~analytical.impact_bodies.Body.box`), so
    the effective mass at the contact point along the normal is the body's own.

    Returns ``(result, (move, other_move))``: the impact (None when the contact point is not
    approaching) and the shift (m, 3-vectors) that takes each body out of the penetration
    (a pair shares it in inverse proportion to mass; ``other_move`` None without ``other``).
    ``impact_options`` go to :func:`analytical.impact.impact` / ``pair_impact``
    (``base_shear=False`` leaves the column's base shear for later).
    """
    n = np.asarray(normal, float)
    depth = max(float(depth_m), 0.0)
    if kind == "body":
        if other is None:
            raise InputError("other", "a body-body strike needs the other body")
        share = other.mass_kg / (body.mass_kg + other.mass_kg)
        moves = (share * depth * n, -(1.0 - share) * depth * n)
        u_rel = body.point_velocity(point_m) - other.point_velocity(point_m)
        if not float(n @ u_rel) < 0.0:
            return None, moves
        impact_options.pop("base_shear", None)
        return pair_impact(body, other, point_m, n, friction_coefficient=friction_coefficient, **law.options(),
                           **impact_options), moves
    moves = (depth * n, None)
    if not float(n @ body.point_velocity(point_m)) < 0.0:
        return None, moves
    if kind == "column":
        if column is None:
            raise InputError("column", "a column strike needs the column")
        height = min(max(float(point_m[2]) - bed_z_m, 1e-6 * column.height_m), column.height_m)
        target: RigidWall | ColumnTarget = ColumnTarget(column, height)
    elif kind == "wall":
        target = RigidWall()
        impact_options.pop("base_shear", None)
    else:
        raise InputError("contact.kind", f"must be 'column', 'wall' or 'body', got {kind!r}")
    return impact(body, point_m, n, target, friction_coefficient=friction_coefficient, **law.options(),
                  **impact_options), moves


def body_contact_law(contact) -> ContactLaw:
    """The contact law of a scene body's ``contact`` section (:class:`orchestrator.scene.schema.DebrisContact`)."""
    return contact_law(contact.law, contact.stiffness_N_m, contact.damping_ratio, contact.restitution)


def pair_contact_law(a: ContactLaw, b: ContactLaw) -> ContactLaw:
    """Two bodies' contact springs in series (``1/k = 1/k_a + 1/k_b``) with the mean of their
    damping ratios: two of the study's containers give ``k / 2`` and their own damping."""
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


def _impact_body(state: BodyState, added_mass_coefficient: float | None, scene: Scene) -> Body:
    if added_mass_coefficient is None:
        own = box_added_mass(tuple(state.size_m), state.mass_kg, scene.fluids.water_density_kg_m3)
        masses, inertias = own.masses_kg, own.inertias_kg_m2
    else:
        masses, inertias = np.full(3, state.mass_kg * added_mass_coefficient), np.zeros(3)
    return Body.box(state.mass_kg, np.asarray(state.inertia_kg_m2, float), state.rotation,
                    np.asarray(state.centre_of_mass_m, float), np.asarray(state.velocity_m_s, float),
                    np.asarray(state.angular_velocity_rad_s, float), added_mass_kg=masses,
                    added_inertia_kg_m2=inertias)
