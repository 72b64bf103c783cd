"""ASCE 7-22 Section 6.11's inputs for a scene: one answer for `analytical asce7 --scene`,
`analytical impact --scene` and `design` (docs/design.md, "ASCE 7-22 beside the curves").

:func:`scene_asce_inputs` reads a scene's column, debris and ``design`` section once, and every verb
builds its :class:`analytical.asce7.AsceDesign` from what it returns (:meth:`AsceInputs.design`), so
the same scene and speed give the same F_i whichever verb is asked:

* ``m_d``: the heaviest mass the design section draws for the bodies (``design.mass_kg``'s upper
  end; else a catalogued container family's loaded mass; else the body's own mass);
* ``k_d``: ``design.debris_stiffness_N_m``; else, at laboratory scale only, the study's 1:40
  container's (:data:`analytical.asce7.STUDY_DEBRIS_STIFFNESS_N_M`);
* ``k_s``: the member's stiffness along the flow where the debris strikes (:func:`struck_stiffness`:
  its MDOF model with its ``column.ends``, at :func:`strike_point`, turned by ``column.heading_deg``);
* ``I_tsu`` from ``design.risk_category`` (Table 6.8-1), ``C_o`` from ``design.orientation_coefficient``;
* full scale (:func:`full_scale`): the simplified static load bounds F_i.

A full-scale scene never falls back to a laboratory value: with no ``design.debris_stiffness_N_m``
(no full-scale k_d was found, docs/fullscale-sources.md) or no stiffness of its own for its column
(no ``column.section`` and no ``column.stiffness_N_m``), it is an InputError naming that field; its
bodies' contact laws are the scene's own (:func:`orchestrator.scene.validation.full_scale_body`).
``sources`` says where each input, and each body's contact law (``law``), comes from: a scene field
(the scene author's statement) or a cited source.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from analytical.column_fem import lateral_stiffness
from analytical.sections import section_properties

from analytical import catalogue
import dataclasses
import math

from analytical.contact_law import contact_law
from analytical.asce7 import (
    FULL_SCALE_MIN_MASS_KG,
    STUDY_DEBRIS_STIFFNESS_N_M,
    STUDY_STRUCTURE_STIFFNESS_N_M,
    AsceDesign,
    asce7_design,
    importance_factor,
)
from orchestrator.core.errors import InputError
from orchestrator.scene.schema import Design, Scene, column_for_analysis
from orchestrator.studies.design_table import debris_types, mass_range

__all__ = ["AsceInputs", "face_obliquity_deg", "full_scale", "scene_asce_inputs", "strike_point", "struck_stiffness"]


def strike_point(scene: Scene) -> tuple[float | None, str]:
    """(height above the floor where the code's debris load strikes the member, why): the scene's
    ``column.strike_height_m``; else its inundation depth (ASCE 7-22 6.11 loads the member up to it),
    the top of a cantilever the flow overtops, mid-height (the softest point) of a member held at a
    floor the flow reaches; else None for a cantilever (its top stiffness, ``column.stiffness_N_m``)
    and mid-height for a member held at its top."""
    col = scene.column
    length, cantilever = col.height_m, col.ends == "cantilever"
    if col.strike_height_m is not None:
        return float(col.strike_height_m), "the scene's column.strike_height_m"
    if scene.inundation is not None:
        depth = float(scene.inundation.depth_m)
        if depth < length:
            return depth, "the scene's inundation depth, inundation.depth_m"
        if cantilever:
            return length, f"the column's top ({length:g} m; the inundation depth, {depth:g} m, is over it)"
        return 0.5 * length, (f"mid-height, the member's softest point (the inundation depth, {depth:g} m, reaches "
                              "the floor above)")
    if cantilever:
        return None, "the cantilever's top (no column.strike_height_m or inundation.depth_m in the scene)"
    return 0.5 * length, "mid-height, the member's softest point (no column.strike_height_m or inundation.depth_m)"


def face_obliquity_deg(heading_deg: float) -> float:
    """Angle (deg, 0-45) between the flow and the normal of the turned column's face nearest to
    facing it: the x face's for a heading within 45 degrees, else the y face's."""
    h = abs(float(heading_deg)) % 90.0
    return min(h, 90.0 - h)


def struck_stiffness(scene: Scene, height_m: float, source: str | None = None) -> float:
    """The member's lateral stiffness (N/m) along the flow at ``height_m``: its MDOF model with its
    ends (:func:`analytical.column_fem.lateral_stiffness`). A column turned by ``column.heading_deg``
    bends about both principal axes, free across the flow: ``1/k = cos^2 h / k_x + sin^2 h / k_y``
    (``k_y`` the section turned by 90 degrees). Without ``column.section``, a cantilever's stated or
    measured ``column.stiffness_N_m`` (its top's) is carried to ``height_m`` by the model's shape,
    ``k_model(h) / k_model(top)``."""
    col = scene.column
    column = column_for_analysis(scene)
    k_x = lateral_stiffness(column, height_m)
    if col.section is None and col.ends == "cantilever":
        k_x *= column.stiffness_N_m / lateral_stiffness(column, column.height_m)
    h = math.radians(col.heading_deg)
    if abs(math.sin(h)) < 1e-12:
        return k_x
    k_y = k_x * lateral_stiffness(_turned(scene, column, source), height_m) / lateral_stiffness(column, height_m)
    return 1.0 / (math.cos(h) ** 2 / k_x + math.sin(h) ** 2 / k_y)


def _turned(scene: Scene, column, source):
    """``column`` bent about its other principal axis (the section turned by 90 degrees)."""
    spec = scene.column.section
    if spec is not None:
        sizes = tuple(reversed(spec.size_m)) if spec.kind != "steel-w" else spec.size_m
        axis = {"strong": "weak", "weak": "strong"}[spec.axis] if spec.kind == "steel-w" else spec.axis
        p = section_properties(spec.kind, sizes, column.poisson_ratio, spec.wall_thickness_m, spec.flange_thickness_m,
                               spec.web_thickness_m, axis, spec.cracked_factor)
        return dataclasses.replace(column, size_x_m=p.size_x_m, size_y_m=p.size_y_m, section_area_m2=p.area_m2,
                                   section_second_moment_m4=p.second_moment_m4, shear_coefficient=p.shear_coefficient)
    if column.section_second_moment_m4 is not None and column.size_x_m != column.size_y_m:
        raise InputError("column.heading_deg", "a turned column bends about both axes: give column.section (the "
                         "scene's section_second_moment_m4 is about one)", source)
    return dataclasses.replace(column, size_x_m=column.size_y_m, size_y_m=column.size_x_m)


def full_scale(scene: Scene, bodies=None, spec: Design | None = None) -> tuple[bool, str]:
    """(whether ``scene`` is at full scale, why): ``design.prototype``; or a debris body the
    design draws at :data:`~analytical.asce7.FULL_SCALE_MIN_MASS_KG` or more (no laboratory
    flume carries debris that heavy; the lightest debris ASCE 7-22 6.11 designs for, a log, is
    heavier still); or a catalogued full-size body. Laboratory scenes (the study's 0.236 kg
    containers) are none of these. ``spec``: the design section (None: the scene's)."""
    spec = scene.design if spec is None else spec
    if spec.prototype:
        return True, "design.prototype is set"
    types = debris_types(scene)
    chosen = [b for b in scene.debris if bodies is None or b.name in bodies]
    for b in chosen:
        t = types.get(b.name)
        if t is not None and catalogue.debris_type(t).scale > 1.0:
            return True, f"body {b.name} is the catalogue's full-size {t}"
    for b in chosen:
        heaviest = mass_range(b, spec, types.get(b.name))[1]
        if heaviest >= FULL_SCALE_MIN_MASS_KG:
            return True, (f"body {b.name} is drawn up to {heaviest:,.0f} kg (full-scale debris: "
                          f">= {FULL_SCALE_MIN_MASS_KG:,.0f} kg)")
    return False, "laboratory scale (no body of full-scale mass, design.prototype not set)"


@dataclass(frozen=True)
class AsceInputs:
    """F_i's inputs for a scene, each with where it comes from (``sources``)."""

    mass_kg: float
    debris_stiffness_N_m: float
    structure_stiffness_N_m: float
    importance: float
    orientation: float
    risk_category: str
    prototype: bool
    scale_reason: str
    sources: dict[str, str] = field(default_factory=dict)
    strike_height_m: float | None = None
    stated_speed_m_s: float | None = None

    def design(self, velocity_m_s: float, velocity_basis: str = "u_max") -> AsceDesign:
        """The code's design force at ``velocity_m_s`` (u_max)."""
        return asce7_design(velocity_m_s, self.mass_kg, self.debris_stiffness_N_m, self.structure_stiffness_N_m,
                            self.importance, self.orientation, prototype=self.prototype,
                            velocity_basis=velocity_basis)


def scene_asce_inputs(scene: Scene, bodies=None, source: str | None = None, spec: Design | None = None) -> AsceInputs:
    """ASCE 7-22 6.11's inputs of ``scene`` for the bodies named in ``bodies`` (None: all), module
    notes, with the design section ``spec`` (None: the scene's); InputError (naming the field,
    ``source`` the scene file) where a full-scale scene would take a laboratory value."""
    if scene.column is None:
        raise InputError("column", "the scene has no column: ASCE 7-22 6.11 needs the struck element", source)
    chosen = [b for b in scene.debris if bodies is None or b.name in bodies]
    if not chosen:
        raise InputError("debris", "the scene has no debris body: ASCE 7-22 6.11 needs its mass", source)
    spec = scene.design if spec is None else spec
    types = debris_types(scene)
    prototype, reason = full_scale(scene, bodies, spec)
    mass = max(mass_range(b, spec, types.get(b.name))[1] for b in chosen)
    typed = [catalogue.debris_type(types[b.name]) for b in chosen if types.get(b.name) is not None]
    stated = "the scene author's statement"
    if spec.mass_kg is not None:
        m_src = f"the upper end of the scene's design.mass_kg ({stated})"
    elif any(t.family is not None for t in typed):
        loaded = [catalogue.debris_type(catalogue.FAMILIES[f][1]) for f in sorted({t.family for t in typed if t.family})]
        m_src = "; ".join(f"the loaded mass of the debris catalogue's {e.family}, {e.mass_kg:,.0f} kg (docs/catalogue.md: "
                          f"{catalogue.SOURCES[e.sources['mass_kg']]})" for e in loaded)
    else:
        heavy = max(chosen, key=lambda b: b.mass_kg)
        m_src = f"the heaviest body's own mass, the scene's debris {heavy.name} ({stated}, or its catalogue type's)"
    untyped = [b.name for b in chosen if types.get(b.name) is None]
    if spec.debris_stiffness_N_m is not None:
        k_d, kd_src = float(spec.debris_stiffness_N_m), f"the scene's design.debris_stiffness_N_m ({stated})"
    elif prototype:
        raise InputError("design.debris_stiffness_N_m", f"the scene is at full scale ({reason}): give the debris' "
                         "stiffness k_d (N/m) and its source: no full-scale k_d was found (ASCE 7-22 Table 6.11-2 is not "
                         f"in the tool, docs/fullscale-sources.md), and the laboratory's, {STUDY_DEBRIS_STIFFNESS_N_M:.3g} "
                         "N/m, is the study's 1:40 polyethylene box", source)
    elif typed and not untyped:
        e = max(typed, key=lambda t: t.kd_N_m)
        k_d, kd_src = float(e.kd_N_m), f"the debris catalogue's for {e.name} (the study's 1:40 container)"
    else:
        k_d = STUDY_DEBRIS_STIFFNESS_N_M
        kd_src = f"the study's 1:40 container's k_d, {STUDY_DEBRIS_STIFFNESS_N_M:.3g} N/m (analytical/asce7.py)"
    col = scene.column
    if col.section is None and "stiffness_N_m" not in col.model_fields_set and prototype:
        raise InputError("column.stiffness_N_m", f"the scene is at full scale ({reason}): give the column's lateral "
                         "stiffness k_s (N/m), or column.section to have it from the section (the default, "
                         f"{STUDY_STRUCTURE_STIFFNESS_N_M:.4g} N/m, is the study's 0.2 m acrylic laboratory column)",
                         source)
    height, where = strike_point(scene)
    section = col.section
    stated_k = "stiffness_N_m" in col.model_fields_set and section is None
    if stated_k and col.ends != "cantilever":
        raise InputError("column.stiffness_N_m", f"is a cantilever's top stiffness; a {col.ends} member's k_s comes "
                         "from its model: leave it out (or give column.section)", source)
    member = (f"its catalogued section ({section.kind} {'x'.join(f'{v:g}' for v in section.size_m)} m, "
              "docs/catalogue.md)" if section is not None else "the scene's column.stiffness_N_m" if stated_k
              else f"the study's laboratory column ({STUDY_STRUCTURE_STIFFNESS_N_M:.4g} N/m at its top)")
    if height is None and col.heading_deg == 0.0:
        k_s = float(column_for_analysis(scene).stiffness_N_m)
        ks_src = f"the cantilever's lateral stiffness at its top, from {member}; {where}"
    else:
        height = col.height_m if height is None else height
        k_s = struck_stiffness(scene, height, source)
        ks_src = (f"the {col.ends} member's lateral stiffness along the flow at {height:.3g} m ({where}), its MDOF "
                  f"model from {member}" + (f"; turned {col.heading_deg:g} deg (the face struck {face_obliquity_deg(col.heading_deg):.3g} "
                                          "deg off its normal)" if col.heading_deg else ""))
    if section is not None or stated_k:
        ks_src += f" (the scene's column, {stated}" + ("; its material's values cited in docs/catalogue.md)"
                                                        if section is not None else ")")
    importance = importance_factor(spec.risk_category)
    set_by_scene = spec.model_fields_set
    sources = {"k_d": kd_src, "m_d": m_src, "k_s": ks_src, "law": _law_sources(chosen, prototype),
               "C_o": (f"the scene's design.orientation_coefficient ({stated})" if "orientation_coefficient" in
                       set_by_scene else "0.65, ASCE 7-22 6.11.6's for shipping containers (the reference study, Sec. "
                       "3.2.3; docs/fullscale-sources.md)"),
               "I_tsu": f"ASCE 7-22 Table 6.8-1 (analytical/asce7.py) for design.risk_category {spec.risk_category} "
                        f"({f'the scene, {stated}' if 'risk_category' in set_by_scene else 'the default'})",
               "scale": ("full scale: the simplified static load bounds F_i (" + reason + ")") if prototype
               else reason}
    stated_speed = float(scene.inundation.speed_m_s) if scene.inundation is not None else None
    return AsceInputs(mass, k_d, k_s, importance, float(spec.orientation_coefficient), spec.risk_category,
                      prototype, reason, sources, height, stated_speed)


def _law_sources(bodies, prototype: bool) -> str:
    """Each body's contact law (its pulses' spring and dashpot) and where it comes from."""
    out = []
    for b in bodies:
        c = b.contact
        law = contact_law(c.law, c.stiffness_N_m, c.damping_ratio, c.restitution)
        given = [f for f in ("stiffness_N_m", "damping_ratio", "restitution") if getattr(c, f) is not None]
        lab = contact_law(c.law)
        where = (f"the scene's debris {b.name} contact.{', contact.'.join(given)} (the scene author's statement"
                 + ("; no full-scale source was found, docs/fullscale-sources.md)" if prototype else ")"))
        if not given or (not prototype and (law.stiffness_N_m, law.damping_ratio) == (lab.stiffness_N_m,
                                                                                     lab.damping_ratio)):
            where = (f"the study's 1:40 {c.law} law (analytical/contact_law.py"
                     + (", calibrated on its Table 2; docs/contact-law.md)" if c.law == "container" else ")"))
        out.append(f"body {b.name}: {c.law} law, k = {law.stiffness_N_m:.5g} N/m, zeta = {law.damping_ratio:.3g}, "
                   f"from {where}")
    return "; ".join(out)
