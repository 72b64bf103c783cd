"""docs/catalogue.md, generated from the catalogue itself (`debrisfoam catalogue --markdown`).

Every number on the page is read from :mod:`analytical.catalogue` and :mod:`analytical.sections`
(or computed by them), so the page cannot drift from the data; tests/test_catalogue.py checks that
the committed page is what this module writes.
"""

from __future__ import annotations

import math

from analytical.catalogue import LAB_SCALE, SOURCES, debris_type, list_debris
from analytical.sections import KINDS, MATERIALS, RC_CRACKED_FACTOR, column_section

__all__ = ["catalogue_data", "markdown"]

_EXAMPLE = {"kind": "rc-square", "size_m": [0.6], "height_m": 8.0}


def catalogue_data() -> dict:
    """The catalogue as plain data (`debrisfoam catalogue --json`)."""
    return {"debris": [debris_type(n).to_dict() for n in list_debris()],
            "materials": [{"name": m.name, "family": m.family, "youngs_modulus_Pa": m.youngs_modulus_Pa,
                           "density_kg_m3": m.density_kg_m3, "poisson_ratio": m.poisson_ratio,
                           "damping_ratio": m.damping_ratio, "sources": m.sources} for m in MATERIALS.values()],
            "section_kinds": {k: {"material": v[0], "sizes": v[1], "thicknesses": list(v[2])}
                              for k, v in KINDS.items()}}


def _g(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def _law(e) -> str:
    if e.contact_stiffness_N_m is None:
        return "not found"
    return f"{_g(e.contact_stiffness_N_m)}, {e.contact_damping_ratio:g}"


def markdown() -> str:
    """The catalogue page."""
    out = ["# Debris and column catalogue", "",
           "Generated from `analytical/catalogue.py` and `analytical/sections.py` by `make catalogue-doc`",
           "(`debrisfoam catalogue --markdown`); never edited by hand. `debrisfoam catalogue` lists it.", "",
           "A scene names an entry: a debris body `type: container-20ft-empty` (its size, mass and inertia",
           "are filled in; fields written beside it override them), a column",
           "`section: {kind: rc-square, size_m: [0.6]}` (docs/scene.md). An unknown name or a missing",
           "property is exit 2 naming the file and the field.", "",
           "## Debris", "",
           "| type | size L x W x H (m) | mass (kg) | tare (kg) | I_xx, I_yy, I_zz (kg m^2) | container law k (N/m), "
           "zeta | k_d (N/m) | ASCE 7-22 k_d |",
           "|---|---|---|---|---|---|---|---|"]
    for name in list_debris():
        e = debris_type(name)
        inertia = ", ".join(_g(v, 3) for v in e.moment_of_inertia_kg_m2)
        out.append(f"| `{name}` | {' x '.join(f'{s:g}' for s in e.size_m)} | {e.mass_kg:g} | {e.tare_kg:g} | "
                   f"{inertia} | {_law(e)} | {'not found' if e.kd_N_m is None else _g(e.kd_N_m)} | "
                   f"{'not found' if e.asce_kd_N_m is None else _g(e.asce_kd_N_m)} |")
    out += ["", "`debrisfoam design` samples a container's mass between its empty and loaded entries",
            "(`analytical.catalogue.mass_range_kg('container-20ft')`).", "", "### Sources", ""]
    used = sorted({key for n in list_debris() for key in debris_type(n).sources.values()})
    for key in used:
        fields = sorted({f for n in list_debris() for f, k in debris_type(n).sources.items() if k == key})
        out.append(f"- **{key}** ({', '.join(fields)}): {SOURCES[key]}.")
    out += ["", "### Inertia", "",
            "A container is a closed thin shell carrying its tare, spread uniformly over the six faces of its",
            "outer box, plus its cargo (mass less tare) as a uniform block filling ISO 668's minimum internal",
            "dimensions, centred. No published container inertia was found; this is the package's model,",
            "and a mass given in a scene gets the same model at that mass.", "",
            "### Contact at full scale", "",
            "The full-size entries have no contact law and no k_d (`not found`): no full-scale source gives them",
            "(docs/fullscale-sources.md), and Froude similarity does not scale elasticity, so the study's 1:40",
            f"polyethylene law times {LAB_SCALE:g}^2 is no full-scale value. A scene with such a body states",
            "`contact.stiffness_N_m`, `contact.damping_ratio` (or `restitution`) and `design.debris_stiffness_N_m`,",
            "else exit 2 naming the field. The ASCE 7-22 k_d column (Table 6.11-2) is empty: not retrievable here.",
            "Logs, poles and vehicles are not catalogued: no source for their size, mass and stiffness was",
            "retrievable."]
    out += ["", "## Columns", "",
            "`analytical.sections.column_section` gives a prototype column's MDOF model (`analytical.column.Column`),",
            "its first frequency and lateral stiffness (top, or mid-height with a held top). Reinforced concrete:",
            f"the gross section, E I times {RC_CRACKED_FACTOR:g} (ACI 318-19 Table 6.6.3.1.1(a), columns);",
            "steel, its design dimensions. A circular column meets the flow as its bounding square.",
            "Bases: `rigid` (fixed), `spring` (a rotational spring `base_spring_Nm_rad`), `calibrated`",
            "(a spring tuned to a given frequency); `column.ends` fixed-fixed or pinned holds the top too.", "",
            "| kind | material | sizes | thicknesses |", "|---|---|---|---|"]
    for kind, (family, count, needs) in KINDS.items():
        sizes = "[x, y]" if count == 2 else ("[D]" if "circular" in kind or "pipe" in kind else "[b]")
        if kind == "steel-w":
            sizes = "[depth, flange width]"
        out.append(f"| `{kind}` | {family} | {sizes} | {', '.join(needs) or '-'} |")
    out += ["", "Shear coefficients: Cowper (1966) for solid rectangles, solid circles and thin circular tubes;",
            "hollow rectangles and W-shapes by the shear area of the walls along the load (AISC 360-16 G2, G6).",
            "", "### Materials", "",
            "| material | E (GPa) | density (kg/m^3) | Poisson | damping |", "|---|---|---|---|---|"]
    for m in MATERIALS.values():
        out.append(f"| `{m.name}` | {m.youngs_modulus_Pa / 1e9:.4g} | {m.density_kg_m3:g} | {m.poisson_ratio:g} | "
                   f"{m.damping_ratio:g} |")
    out.append("")
    for m in MATERIALS.values():
        out.append(f"- `{m.name}`: " + "; ".join(f"{k}: {v}" for k, v in m.sources.items()) + ".")
    c = column_section(_EXAMPLE["kind"], _EXAMPLE["size_m"], _EXAMPLE["height_m"])
    ei, rho_a, h = c.bending_stiffness_Nm2, c.mass_per_length_kg_m, c.height_m
    f_eb = 1.8751**2 / (2 * math.pi * h**2) * math.sqrt(ei / rho_a)
    out += ["", "### Example", "",
            f"A {_EXAMPLE['size_m'][0]:g} m square concrete-28mpa column {h:g} m high on a rigid base: "
            f"E I = {_g(ei)} N m^2 (cracked), rho A = {_g(rho_a)} kg/m;",
            f"its MDOF model's f1 = {c.natural_frequency_Hz:.3f} Hz (Euler-Bernoulli 3.516 / (2 pi L^2) "
            f"sqrt(E I / rho A) = {f_eb:.3f} Hz; shear and rotary inertia lower it),",
            f"lateral stiffness at the top {_g(c.stiffness_N_m)} N/m (3 E I / L^3 = {_g(3 * ei / h**3)} N/m), "
            f"damping {c.damping_ratio:g}.", ""]
    return "\n".join(out)
