"""Catalogue entries in a scene: a debris body's ``type`` and a column's ``section`` filled in.

A debris body may say ``type: container-20ft-empty`` (:mod:`analytical.catalogue`): its size,
mass and rotational inertia come from the catalogue, and any of them written in the scene
overrides the catalogue's. A mass written in the scene keeps the catalogue's inertia model (shell
plus cargo) at that mass; a size written in the scene drops it (the body's inertia is then that of
its walls, or of a solid box). The contact's stiffness is the catalogue's for the body's law
(``container``: the damped spring; ``asce7_kd``: k_d) where the entry has one (the study's 1:40
model) and the scene gives none; a full-size entry has none (no full-scale source), so the scene
states it (:mod:`orchestrator.scene.validation`).

A column may say ``section: {kind: rc-square, size_m: [0.6], ...}`` (:mod:`analytical.sections`):
its footprint, box wall, area, second moment, effective-stiffness factor, shear coefficient and
material come from the section; its first frequency and lateral stiffness from its MDOF model.
Material values, damping, frequency or stiffness written in the scene override the section's;
a footprint or section property written in the scene must agree with it.

These run before pydantic validates the fields (the schema's ``mode="before"`` validators), so
an unknown name or a missing value is reported by the field it belongs to.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from analytical.catalogue import container_inertia, debris_type, list_debris
from orchestrator.core.errors import InputError
from analytical.sections import KINDS, MATERIALS, column_section, material, section_properties
from orchestrator.scene.base import Pos, SceneSection

__all__ = ["GEOMETRY_FIELDS", "ColumnSectionSpec", "debris_from_catalogue", "column_from_section", "section_geometry"]

#: Column fields a section fixes: a scene may repeat them only with the section's values.
GEOMETRY_FIELDS = ("size_x_m", "size_y_m", "wall_thickness_m", "section_area_m2", "section_second_moment_m4",
                   "stiffness_factor")
_MATERIAL_FIELDS = ("youngs_modulus_Pa", "density_kg_m3", "poisson_ratio")


class ColumnSectionSpec(SceneSection):
    """A prototype column by section (analytical.sections, docs/catalogue.md): its kind, sizes, material.

    The column's footprint, box wall, area, second moment, cracked-section factor, shear coefficient
    and material values come from it, and its first frequency and lateral stiffness from its MDOF
    model; see ColumnSection.
    """

    kind: Literal[tuple(KINDS)] = Field(description="solid reinforced concrete (rc-*) or steel (steel-*)")
    size_m: tuple[Pos, ...] = Field(description="[x, y] (rectangular; a W-shape's [depth, flange width]), [b] "
                                                "(square) or [D] (circular) (m)")
    material: str | None = Field(None, validate_default=True, description="a catalogued material; null = "
                                 "concrete-28mpa for rc-*, steel for steel-*")
    axis: Literal["strong", "weak"] = Field("strong", description="steel-w: the bending axis (strong: web along "
                                                                  "the flow)")
    cracked_factor: float | None = Field(None, gt=0, le=1, description="rc-*: effective-stiffness factor on E I; "
                                         "null = 0.70 (ACI 318-19 Table 6.6.3.1.1(a), columns)")
    wall_thickness_m: float | None = Field(None, gt=0, validate_default=True, description="steel-hss-*, "
                                           "steel-pipe: design wall thickness (m)")
    flange_thickness_m: float | None = Field(None, gt=0, validate_default=True, description="steel-w (m)")
    web_thickness_m: float | None = Field(None, gt=0, validate_default=True, description="steel-w (m)")

    @field_validator("size_m")
    @classmethod
    def _size_count(cls, value, info):
        count = KINDS[info.data["kind"]][1] if "kind" in info.data else len(value)
        if len(value) != count:
            raise ValueError(f"{info.data.get('kind')} takes {count} size(s), got {len(value)}")
        return value

    @field_validator("material")
    @classmethod
    def _material(cls, value, info):
        family = KINDS[info.data["kind"]][0] if "kind" in info.data else None
        if value is not None and value not in MATERIALS:
            raise ValueError(f"unknown material {value!r}; the catalogue has {', '.join(MATERIALS)}")
        if value is not None and family and MATERIALS[value].family != family:
            raise ValueError(f"{value} is not a {family} material")
        return value

    @field_validator("wall_thickness_m", "flange_thickness_m", "web_thickness_m")
    @classmethod
    def _needed(cls, value, info):
        kind = info.data.get("kind")
        if kind is None:
            return value
        needed = info.field_name in KINDS[kind][2]
        if needed and value is None:
            raise ValueError(f"required for a {kind} section")
        if not needed and value is not None:
            raise ValueError(f"not used by a {kind} section")
        return value

    @model_validator(mode="after")
    def _consistent(self):
        try:
            section_geometry(self)
        except InputError as err:
            raise ValueError(f"{err.field}: {err.rule}") from None
        return self


def debris_from_catalogue(data: Any) -> Any:
    """``data`` (a raw debris body mapping) with its catalogue ``type`` filled in; unchanged when
    it has no type or an unknown one (the ``type`` field's own check reports that)."""
    if not isinstance(data, dict) or data.get("type") not in list_debris():
        return data
    entry = debris_type(data["type"])
    out = dict(data)
    size_given = out.get("size_m") is not None
    for name, value in (("size_m", list(entry.size_m)), ("mass_kg", entry.mass_kg)):
        if out.get(name) is None:
            out[name] = value
    if not size_given and out.get("moment_of_inertia_kg_m2") is None and out.get("wall_thickness_m") is None:
        try:
            out["moment_of_inertia_kg_m2"] = list(container_inertia(entry, out["mass_kg"]))
        except (InputError, TypeError):
            pass  # a bad mass: the mass field reports it
    contact = out.get("contact")
    if contact is None or isinstance(contact, dict):
        contact = dict(contact or {})
        law = contact.get("law", "container")
        catalogued = entry.kd_N_m if law == "asce7_kd" else entry.contact_stiffness_N_m
        if contact.get("stiffness_N_m") is None and catalogued is not None:
            contact["stiffness_N_m"] = catalogued
        out["contact"] = contact
    return out


def section_geometry(section: Any) -> dict:
    """The fields a validated column ``section`` fixes (:data:`GEOMETRY_FIELDS`), by name."""
    p = section_properties(section.kind, section.size_m, 0.3, section.wall_thickness_m,
                           section.flange_thickness_m, section.web_thickness_m, section.axis,
                           section.cracked_factor)
    return {"size_x_m": p.size_x_m, "size_y_m": p.size_y_m, "wall_thickness_m": p.wall_thickness_m,
            "section_area_m2": p.area_m2, "section_second_moment_m4": p.second_moment_m4,
            "stiffness_factor": p.stiffness_factor}


def column_from_section(data: Any, section: Any) -> Any:
    """``data`` (a raw column mapping) with the fields of its validated ``section`` filled in.

    The footprint, section properties and material come first; the frequency and stiffness need a
    whole column, and stay unfilled when the column's own values cannot make one yet (a missing
    height, a bad override): the fields' own checks report those.
    """
    out = dict(data)
    for name, value in section_geometry(section).items():
        out.setdefault(name, value)
    mat = material(section.material, section.kind)
    for name in _MATERIAL_FIELDS:
        out.setdefault(name, getattr(mat, name))
    out.setdefault("damping_ratio", mat.damping_ratio)
    try:
        out.setdefault("shear_coefficient", section_properties(
            section.kind, section.size_m, out["poisson_ratio"], section.wall_thickness_m, section.flange_thickness_m,
            section.web_thickness_m, section.axis, section.cracked_factor).shear_coefficient)
    except (InputError, TypeError):
        return out
    base = out.get("base", "rigid")
    if base == "calibrated" and out.get("natural_frequency_Hz") is None:
        out["natural_frequency_Hz"] = None  # required: the field's check says so
        return out
    try:
        column = column_section(
            section.kind, section.size_m, out["height_m"], section.material,
            wall_thickness_m=section.wall_thickness_m, flange_thickness_m=section.flange_thickness_m,
            web_thickness_m=section.web_thickness_m, axis=section.axis, cracked_factor=section.cracked_factor,
            base=base, base_spring_Nm_rad=out.get("base_spring_Nm_rad"),
            natural_frequency_Hz=out.get("natural_frequency_Hz") if base == "calibrated" else None,
            damping_ratio=out["damping_ratio"], elements=out.get("elements", 160), ends=out.get("ends", "cantilever"),
            **{k: out[k] for k in _MATERIAL_FIELDS})
    except (InputError, KeyError, TypeError):
        return out
    out.setdefault("natural_frequency_Hz", column.natural_frequency_Hz)
    out.setdefault("stiffness_N_m", column.stiffness_N_m)
    return out
