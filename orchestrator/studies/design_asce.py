"""ASCE 7-22 Section 6.11's inputs for a scene: one answer for `analytical asce7 --scene`,
`analytical impact --scene` and `design` (docs/design.md, "ASCE 7-22 beside the curves").

:func:`scene_asce_inputs` reads a scene's column, debris and ``design`` section once, and every verb
builds its :class:`analytical.asce7.AsceDesign` from what it returns (:meth:`AsceInputs.design`), so
the same scene and speed give the same F_i whichever verb is asked:

* ``m_d``: the heaviest mass the design section draws for the bodies (``design.mass_kg``'s upper
  end; else a catalogued container family's loaded mass; else the body's own mass);
* ``k_d``: ``design.debris_stiffness_N_m``; else a catalogued body's (docs/catalogue.md); else, at
  laboratory scale only, the study's 1:40 container (:data:`analytical.asce7.SEED_DEBRIS_STIFFNESS_N_M`);
* ``k_s``: the column's lateral stiffness (its section's MDOF model, or ``column.stiffness_N_m``);
* ``I_tsu`` from ``design.risk_category`` (Table 6.8-1), ``C_o`` from ``design.orientation_coefficient``;
* full scale (:func:`full_scale`): the simplified static load bounds F_i.

A full-scale scene never falls back to a laboratory value: with no k_d of its own (an uncatalogued
body and no ``design.debris_stiffness_N_m``) or no stiffness of its own for its column (no
``column.section`` and no ``column.stiffness_N_m``), it is an InputError naming that field.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from analytical import catalogue
from analytical.asce7 import (
    FULL_SCALE_MIN_MASS_KG,
    SEED_DEBRIS_STIFFNESS_N_M,
    SEED_STRUCTURE_STIFFNESS_N_M,
    AsceDesign,
    asce7_design,
    importance_factor,
)
from orchestrator.core.errors import InputError
from orchestrator.scene.schema import Design, Scene, column_for_analysis
from orchestrator.studies.design_table import debris_types, mass_range

__all__ = ["AsceInputs", "full_scale", "scene_asce_inputs"]


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
    if spec.mass_kg is not None:
        m_src = "the upper end of the scene's design.mass_kg"
    elif any(t.family is not None for t in typed):
        m_src = "the loaded mass of the debris catalogue's " + ", ".join(sorted({t.family for t in typed if t.family}))
    else:
        m_src = "the heaviest body's own mass"
    untyped = [b.name for b in chosen if types.get(b.name) is None]
    if spec.debris_stiffness_N_m is not None:
        k_d, kd_src = float(spec.debris_stiffness_N_m), "the scene's design.debris_stiffness_N_m"
    elif typed and not untyped:
        e = max(typed, key=lambda t: t.kd_N_m)
        k_d = float(e.kd_N_m)
        kd_src = (f"the debris catalogue's for {e.name}: the study's 1:{e.scale:g} container's k_d "
                  f"({SEED_DEBRIS_STIFFNESS_N_M:.3g} N/m) Froude-scaled by {e.scale:g}^2 (a stand-in: ASCE 7-22 "
                  "Table 6.11-2's value is not in the tool, docs/catalogue.md)") if e.scale > 1 else \
            f"the debris catalogue's for {e.name} (the study's 1:40 container)"
    elif prototype:
        raise InputError("design.debris_stiffness_N_m", f"the scene is at full scale ({reason}) and body "
                         f"{untyped[0]} has no catalogued type: give the debris' stiffness k_d (N/m) from ASCE 7-22 "
                         f"Table 6.11-2 or a test (the default, {SEED_DEBRIS_STIFFNESS_N_M:.3g} N/m, is the study's "
                         "1:40 polyethylene box)", source)
    else:
        k_d = SEED_DEBRIS_STIFFNESS_N_M
        kd_src = f"the study's 1:40 container's k_d, {SEED_DEBRIS_STIFFNESS_N_M:.3g} N/m (analytical/asce7.py)"
    col = scene.column
    if col.section is None and "stiffness_N_m" not in col.model_fields_set and prototype:
        raise InputError("column.stiffness_N_m", f"the scene is at full scale ({reason}): give the column's lateral "
                         "stiffness k_s (N/m), or column.section to have it from the section (the default, "
                         f"{SEED_STRUCTURE_STIFFNESS_N_M:.4g} N/m, is the study's 0.2 m acrylic laboratory column)",
                         source)
    k_s = float(column_for_analysis(scene).stiffness_N_m)
    section = col.section
    ks_src = ("the column's MDOF model's lateral stiffness at its top, from its catalogued section "
              f"({section.kind} {'x'.join(f'{v:g}' for v in section.size_m)} m, docs/catalogue.md)" if section is not None
              else "the scene's column.stiffness_N_m" if "stiffness_N_m" in col.model_fields_set
              else f"the study's laboratory column, {SEED_STRUCTURE_STIFFNESS_N_M:.4g} N/m (column.stiffness_N_m's "
                   "default)")
    importance = importance_factor(spec.risk_category)
    sources = {"k_d": kd_src, "m_d": m_src, "k_s": ks_src,
               "C_o": "design.orientation_coefficient (0.65: ASCE 7-22 6.11's value for containers, logs and poles, "
                      "the default)",
               "I_tsu": f"ASCE 7-22 Table 6.8-1 for the scene's design.risk_category ({spec.risk_category})",
               "scale": ("full scale: the simplified static load bounds F_i (" + reason + ")") if prototype
               else reason}
    return AsceInputs(mass, k_d, k_s, importance, float(spec.orientation_coefficient), spec.risk_category,
                      prototype, reason, sources)
