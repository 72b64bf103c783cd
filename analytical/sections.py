"""Prototype columns by section: reinforced concrete and steel, turned into the MDOF column model.

:func:`column_section` takes a section kind, its dimensions, a height, a catalogued material and
a base, and returns the :class:`analytical.column.Column` the MDOF model (:mod:`analytical.column_fem`)
and the SDOF and ASCE 7-22 paths take, with its first natural frequency and its lateral stiffness
at the top computed from that model (a prototype column has no measured values).
:func:`section_properties` gives the section's area, second moment, shear coefficient and footprint.

Kinds (``size_m``; the load acts along x, the flow):

* ``rc-rectangular`` [x, y], ``rc-square`` [b], ``rc-circular`` [D]: solid reinforced concrete,
  gross section, flexural rigidity times the cracked-section factor (default ACI 318-19 Table
  6.6.3.1.1(a): 0.70 I_g for columns); the reinforcement's own stiffness is not added.
* ``steel-hss-rectangular`` [x, y], ``steel-hss-square`` [b] (wall ``wall_thickness_m``),
  ``steel-pipe`` [D] (wall ``wall_thickness_m``): hollow steel sections by their design wall.
* ``steel-w`` [d, b_f] with ``flange_thickness_m`` and ``web_thickness_m``: a W-shape bending
  about its strong axis (``axis: strong``, web along the flow, the default) or its weak axis.

Shear coefficients: Cowper (1966) for solid rectangles 10(1+nu)/(12+11nu), solid circles
6(1+nu)/(7+6nu) and thin circular tubes 2(1+nu)/(4+3nu); hollow rectangles and W-shapes by the
shear area of the walls along the load over the whole area (webs 2 t b_x; a W's web d t_w strong,
flanges 2 b_f t_f weak, as AISC 360-16 G2 and G6 take them), which gives the study's 0.5 for its
acrylic box.

Bases: ``rigid`` (fixed), ``spring`` (a rotational spring ``base_spring_Nm_rad``), ``calibrated``
(a spring tuned to a given ``natural_frequency_Hz``). ``ends`` holds the top as well
(:attr:`analytical.column.Column.ends`: ``fixed-fixed``, ``pinned``; with a rigid base only); such a
member's ``stiffness_N_m`` is its point stiffness at mid-height, its softest point.

Materials: :data:`MATERIALS`, each value with its source.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from analytical.column import BASES, Column
from analytical.column_fem import lateral_stiffness, modes
from analytical.errors import InputError, require_positive

__all__ = ["KINDS", "MATERIALS", "Material", "SectionProperties", "column_section", "list_materials",
           "material", "section_properties"]

RC_CRACKED_FACTOR = 0.70
"""ACI 318-19 Table 6.6.3.1.1(a): moment of inertia of columns 0.70 I_g for the elastic analysis."""

_DAMPING_SOURCE = ("Chopra (2017), Dynamics of Structures, Table 11.2.1 (Newmark & Hall's recommended damping): "
                   "{}")


@dataclass(frozen=True)
class Material:
    """A column material: E (Pa), density (kg/m^3), Poisson's ratio, damping ratio, and sources."""

    name: str
    family: str
    youngs_modulus_Pa: float
    density_kg_m3: float
    poisson_ratio: float
    damping_ratio: float
    sources: dict


def _concrete(fc_MPa: float) -> Material:
    return Material(
        name=f"concrete-{fc_MPa:g}mpa", family="rc",
        youngs_modulus_Pa=4700.0 * math.sqrt(fc_MPa) * 1e6, density_kg_m3=2400.0, poisson_ratio=0.2,
        damping_ratio=0.05,
        sources={"youngs_modulus_Pa": f"ACI 318-19 19.2.2.1(b): E_c = 4700 sqrt(f'c) MPa, normalweight, "
                                      f"f'c = {fc_MPa:g} MPa",
                 "density_kg_m3": "ASCE 7-22 Table C3.1-2: reinforced stone concrete 150 lb/ft^3 (2,400 kg/m^3)",
                 "poisson_ratio": "EN 1992-1-1 3.1.3(4): 0.2 for uncracked concrete",
                 "damping_ratio": _DAMPING_SOURCE.format("reinforced concrete with considerable cracking 3-5 %; "
                                                         "5 % taken, the value design spectra assume")})


MATERIALS = {m.name: m for m in (
    _concrete(28.0),
    _concrete(35.0),
    Material(name="steel", family="steel", youngs_modulus_Pa=200e9, density_kg_m3=7850.0, poisson_ratio=0.3,
             damping_ratio=0.02,
             sources={"youngs_modulus_Pa": "AISC 360-16: E = 29,000 ksi (200,000 MPa)",
                      "density_kg_m3": "AISC Steel Construction Manual: 490 lb/ft^3 (7,850 kg/m^3)",
                      "poisson_ratio": "AISC 360-16: G = 11,200 ksi (77,200 MPa), nu = E / 2G - 1 = 0.3",
                      "damping_ratio": _DAMPING_SOURCE.format("welded steel at working stress 2-3 %; 2 % taken")}),
)}
"""The catalogued column materials by name."""

KINDS = {
    "rc-rectangular": ("rc", 2, ()), "rc-square": ("rc", 1, ()), "rc-circular": ("rc", 1, ()),
    "steel-hss-rectangular": ("steel", 2, ("wall_thickness_m",)),
    "steel-hss-square": ("steel", 1, ("wall_thickness_m",)),
    "steel-pipe": ("steel", 1, ("wall_thickness_m",)),
    "steel-w": ("steel", 2, ("flange_thickness_m", "web_thickness_m")),
}
"""Section kinds: (material family, number of sizes, the thickness fields it needs)."""

_DEFAULT_MATERIAL = {"rc": "concrete-28mpa", "steel": "steel"}


def list_materials() -> tuple[str, ...]:
    """The catalogued material names."""
    return tuple(MATERIALS)


def material(name: str | None, kind: str = "rc-square") -> Material:
    """The catalogued material ``name`` (None: the kind's default); InputError on ``material`` otherwise."""
    family = _kind(kind)[0]
    name = _DEFAULT_MATERIAL[family] if name is None else name
    m = MATERIALS.get(name) if isinstance(name, str) else None
    if m is None:
        raise InputError("material", f"unknown material {name!r}; the catalogue has {', '.join(MATERIALS)}")
    if m.family != family:
        raise InputError("material", f"{name} is {m.family}, but a {kind} section needs a {family} material "
                                      f"({', '.join(n for n, x in MATERIALS.items() if x.family == family)})")
    return m


def _kind(kind: str) -> tuple:
    if kind not in KINDS:
        raise InputError("kind", f"unknown section kind {kind!r}; known: {', '.join(KINDS)}")
    return KINDS[kind]


@dataclass(frozen=True)
class SectionProperties:
    """A section's footprint (x along the load, y across), the box wall the scene's column takes
    (half the smaller size for a solid), area A (m^2), second moment I about the bending axis (m^4),
    Timoshenko shear coefficient and effective-stiffness factor."""

    kind: str
    size_x_m: float
    size_y_m: float
    wall_thickness_m: float
    area_m2: float
    second_moment_m4: float
    shear_coefficient: float
    stiffness_factor: float


def section_properties(kind: str, size_m, poisson_ratio: float, wall_thickness_m: float | None = None,
                       flange_thickness_m: float | None = None, web_thickness_m: float | None = None,
                       axis: str = "strong", cracked_factor: float | None = None) -> SectionProperties:
    """Area, second moment, shear coefficient and footprint of a section (see the module docstring).

    ``cracked_factor`` applies to reinforced concrete only (default 0.70, ACI 318-19); a steel
    section's factor is 1. InputError names the argument at fault.
    """
    family, count, needs = _kind(kind)
    sizes = [size_m] if isinstance(size_m, (int, float)) else list(size_m)
    if len(sizes) != count:
        raise InputError("size_m", f"{kind} takes {count} size(s) "
                                   f"({'[x, y]' if count == 2 else '[b]' if 'circ' not in kind else '[D]'}), "
                                   f"got {len(sizes)}")
    sizes = [require_positive("size_m", s) for s in sizes]
    given = {"wall_thickness_m": wall_thickness_m, "flange_thickness_m": flange_thickness_m,
             "web_thickness_m": web_thickness_m}
    for name, value in given.items():
        if name in needs and value is None:
            raise InputError(name, f"required for a {kind} section")
        if name not in needs and value is not None:
            raise InputError(name, f"not used by a {kind} section")
        if value is not None:
            require_positive(name, value)
    if family == "steel" and cracked_factor is not None:
        raise InputError("cracked_factor", "applies to reinforced concrete only")
    factor = RC_CRACKED_FACTOR if cracked_factor is None and family == "rc" else (cracked_factor or 1.0)
    if not 0.0 < factor <= 1.0:
        raise InputError("cracked_factor", f"must be in (0, 1], got {cracked_factor!r}")
    if axis not in ("strong", "weak") or (axis == "weak" and kind != "steel-w"):
        raise InputError("axis", f"must be 'strong' or 'weak' (weak only for steel-w), got {axis!r}")
    nu = poisson_ratio
    bx = by = sizes[0]
    if count == 2:
        bx, by = sizes
    t = wall_thickness_m
    if kind in ("rc-rectangular", "rc-square"):
        area, inertia, kappa, wall = bx * by, by * bx**3 / 12.0, 10 * (1 + nu) / (12 + 11 * nu), min(bx, by) / 2
    elif kind == "rc-circular":
        d = bx
        area, inertia, kappa, wall = math.pi * d**2 / 4, math.pi * d**4 / 64, 6 * (1 + nu) / (7 + 6 * nu), d / 2
    elif kind in ("steel-hss-rectangular", "steel-hss-square"):
        _thin(t, min(bx, by))
        area = bx * by - (bx - 2 * t) * (by - 2 * t)
        inertia = (by * bx**3 - (by - 2 * t) * (bx - 2 * t) ** 3) / 12.0
        kappa, wall = 2 * t * bx / area, t
    elif kind == "steel-pipe":
        d = bx
        _thin(t, d)
        di = d - 2 * t
        area, inertia = math.pi * (d**2 - di**2) / 4, math.pi * (d**4 - di**4) / 64
        kappa, wall = 2 * (1 + nu) / (4 + 3 * nu), t
    else:  # steel-w: size [d, b_f]
        d, bf, tf, tw = bx, by, flange_thickness_m, web_thickness_m
        _thin(tf, d, "flange_thickness_m")
        if tw >= bf:
            raise InputError("web_thickness_m", f"must be below the flange width {bf:g} m, got {tw!r}")
        area = 2 * bf * tf + (d - 2 * tf) * tw
        if axis == "strong":
            inertia = (bf * d**3 - (bf - tw) * (d - 2 * tf) ** 3) / 12.0
            kappa, bx, by = d * tw / area, d, bf
        else:
            inertia = 2 * tf * bf**3 / 12.0 + (d - 2 * tf) * tw**3 / 12.0
            kappa, bx, by = 2 * bf * tf / area, bf, d
        wall = min(tf, min(bx, by) / 2)
    return SectionProperties(kind, bx, by, wall, area, inertia, kappa, factor)


def _thin(t: float, size: float, name: str = "wall_thickness_m") -> None:
    if not 2 * t < size:
        raise InputError(name, f"must be below half the section size ({size / 2:g} m), got {t!r}")


def column_section(kind: str, size_m, height_m: float, material_name: str | None = None, *,
                   wall_thickness_m: float | None = None, flange_thickness_m: float | None = None,
                   web_thickness_m: float | None = None, axis: str = "strong", cracked_factor: float | None = None,
                   base: str = "rigid", base_spring_Nm_rad: float | None = None,
                   natural_frequency_Hz: float | None = None, damping_ratio: float | None = None,
                   elements: int = 160, ends: str = "cantilever", **material_overrides) -> Column:
    """The MDOF :class:`~analytical.column.Column` of a prototype column by section.

    ``material_name`` is a catalogued material (None: the kind's default, concrete-28mpa or steel);
    ``youngs_modulus_Pa``, ``density_kg_m3`` or ``poisson_ratio`` in ``material_overrides`` and
    ``damping_ratio`` replace its values. The returned column's ``natural_frequency_Hz`` is its MDOF
    model's first frequency and ``stiffness_N_m`` the model's static lateral stiffness at the top
    (mid-height for a member held at its top; what the SDOF model takes), unless ``base="calibrated"``, where the given
    ``natural_frequency_Hz`` is the target of the base spring.

    >>> c = column_section("rc-square", [0.6], 4.0)
    >>> round(c.natural_frequency_Hz, 1), c.stiffness_factor
    (16.1, 0.7)
    """
    mat = material(material_name, kind)
    unknown = set(material_overrides) - {"youngs_modulus_Pa", "density_kg_m3", "poisson_ratio"}
    if unknown:
        raise InputError(sorted(unknown)[0], "not a material property (youngs_modulus_Pa, density_kg_m3, "
                                             "poisson_ratio)")
    values = {"youngs_modulus_Pa": mat.youngs_modulus_Pa, "density_kg_m3": mat.density_kg_m3,
              "poisson_ratio": mat.poisson_ratio, **material_overrides}
    props = section_properties(kind, size_m, values["poisson_ratio"], wall_thickness_m, flange_thickness_m,
                               web_thickness_m, axis, cracked_factor)
    if base not in BASES:
        raise InputError("base", f"must be one of {', '.join(BASES)} (a pinned base on a cantilever has no "
                                 f"lateral stiffness); got {base!r}")
    if (base == "calibrated") != (natural_frequency_Hz is not None):
        raise InputError("natural_frequency_Hz", "is the target of base='calibrated', and only of it")
    column = Column(
        size_x_m=props.size_x_m, size_y_m=props.size_y_m, height_m=height_m, wall_thickness_m=props.wall_thickness_m,
        shear_coefficient=props.shear_coefficient, section_area_m2=props.area_m2,
        section_second_moment_m4=props.second_moment_m4, stiffness_factor=props.stiffness_factor,
        damping_ratio=mat.damping_ratio if damping_ratio is None else damping_ratio, base="rigid" if base ==
        "calibrated" else base, base_spring_Nm_rad=base_spring_Nm_rad, elements=elements, ends=ends, **values)
    where = column.height_m if ends == "cantilever" else 0.5 * column.height_m
    if base == "calibrated":
        column = replace(column, base="calibrated", natural_frequency_Hz=natural_frequency_Hz)
        return replace(column, stiffness_N_m=lateral_stiffness(column, where))
    return replace(column, natural_frequency_Hz=float(modes(column)[0]), stiffness_N_m=lateral_stiffness(column, where))
