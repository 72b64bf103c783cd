"""The debris catalogue: prototype debris a designer names by type, every value with its source.

A :class:`DebrisType` is a shipping container (20-ft or 40-ft, empty or loaded) or the
reference study's 1:40 model container: its outer size, mass, rotational inertia, a wall
figure, and its contact properties for the two contact laws of :mod:`analytical.contact_law`.
``debris_type(name)`` returns one, ``list_debris()`` names them all, ``mass_range_kg(family)``
gives the empty and loaded masses of a container family (what ``debrisfoam design`` samples
between). Columns by section are :mod:`analytical.sections`.

Inertia
-------
A container is modelled as a closed thin shell (its frame, corrugated walls, floor and roof
spread uniformly over the six faces of its outer box) carrying the tare mass, plus, when
loaded, its cargo as a uniform block filling ISO 668's minimum internal dimensions, centred.
:func:`container_inertia` does it for any mass, so a mass between empty and loaded gets a
consistent inertia. The model is this package's; no published container inertia was found.

Contact
-------
The full-size containers carry no contact law and no k_d: no full-scale source for either was
found (docs/fullscale-sources.md), and Froude similarity, which keeps gravity and inertia, does not
scale elasticity, so the study's 1:40 polyethylene law (:data:`analytical.contact_law.CONTAINER_STIFFNESS_N_M`,
:data:`~analytical.contact_law.CONTAINER_DAMPING_RATIO`) times 40^2 is no full-scale value. Those
fields are None, their source "not found" (``lawless``); a scene with such a body states them
(orchestrator/scene/validation.py). The study's 1:40 model container keeps its laboratory law.
ASCE 7-22 Table 6.11-2's container stiffness and masses could not be retrieved either
(``asce_kd_N_m`` is None and says so): docs/catalogue.md.

References
----------
ISO 668 (Series 1 freight containers: classification, dimensions and ratings), as summarised at
    howlingpixel.com/i-en/ISO_668 (from Wikipedia "ISO 668").
Joynt et al., the reference study (study sections 3.1, 3.2.3; Table 2) and
    :mod:`analytical.contact_law` (its calibration, docs/contact-law.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from analytical.contact_law import CONTAINER_DAMPING_RATIO, CONTAINER_STIFFNESS_N_M, box_inertia
from analytical.errors import InputError, require_positive
from analytical.study import STUDY_CONTAINER_SIZE_M, STUDY_CONTAINER_WALL_M, STUDY_DEBRIS_MASS_KG, STUDY_DEBRIS_STIFFNESS_N_M

__all__ = [
    "FAMILIES",
    "LAB_SCALE",
    "SOURCES",
    "DebrisType",
    "container_inertia",
    "debris_type",
    "list_debris",
    "mass_range_kg",
    "shell_inertia",
]

LAB_SCALE = 40.0
"""Length scale of the reference study's flume model (study 3.1: 1:40 shipping containers)."""

SOURCES = {
    "iso668": "ISO 668 (Series 1 freight containers), external and minimum internal dimensions and maximum "
              "gross mass of 1CC (20-ft) and 1AA (40-ft), as tabulated at howlingpixel.com/i-en/ISO_668 "
              "(from Wikipedia 'ISO 668'): 1CC 6.058 x 2.438 x 2.591 m outside, 5.867 m internal length; 1AA "
              "12.192 x 2.438 x 2.591 m, 11.998 m; minimum internal width 2.330 m, height 2.350 m; "
              "1AA 30,480 kg",
    "tare20": "20-ft tare: 2,300 kg in Advances in Structural Engineering, doi:10.1177/1369433216668361 "
              "(introduction: 'Standard 6.10 m (20 ft) shipping containers have a tare weight of 2300 kg'); "
              "carriers list 2,080-2,200 kg (ungertgz.com 20GP 2,080 kg; oceanichaulage.blogspot.com "
              "2,160 kg; dimensionsinfo.com 4,850 lb = 2,200 kg): the largest is taken",
    "gross20": "20-ft maximum gross mass 30,480 kg (oceanichaulage.blogspot.com 'Shipping container "
               "weights': 30,480 kg, 'the most common alternative for 20fts is 24,000kg'; "
               "containertracking.how/Iso668: 24,000 kg): the larger rating is taken as 'loaded'",
    "tare40": "40-ft tare: 3,750 kg (oceanichaulage.blogspot.com); 3,720-3,740 kg (containermod.ro), "
              "3,800 kg (dimensionsinfo.com), 'maximum tare weight of 3.730 tonnes' (shipinspection.eu)",
    "gross40": "40-ft (1AA) maximum gross mass 30,480 kg: ISO 668 as tabulated at "
               "howlingpixel.com/i-en/ISO_668",
    "wall": "the side allowance ISO 668 leaves, (2.438 - 2.330) / 2 = 0.054 m (outside width less minimum "
            "internal width); information only: the inertia model does not use it",
    "inertia": "this package's model (module docstring): tare as a uniform closed thin shell on the outer box, "
               "cargo as a uniform block filling ISO 668's minimum internal dimensions, centred",
    "lawless": "not found: no full-scale source gives a container's contact stiffness, damping or k_d "
               "(docs/fullscale-sources.md), and Froude similarity does not scale elasticity, so the study's "
               "1:40 polyethylene law x 40^2 is no full-scale value; a scene with this body states "
               "contact.stiffness_N_m, contact.damping_ratio and design.debris_stiffness_N_m",
    "kd": "the study's k_d, backed out of its Table 1 ASCE rows (analytical.asce7)",
    "asce_kd": "ASCE 7-22 Table 6.11-2 (container mass and debris stiffness): not retrievable here "
               "(docs/catalogue.md); give contact.stiffness_N_m from the printed standard",
    "study": "the reference study, section 3.1: 1:40 20-ft container, 0.15 x 0.06 x 0.06 m, 5 mm "
            "polyethylene wall, 0.236 kg; contact law calibrated on its Table 2 (analytical.contact_law)",
}
"""Every source the catalogue cites, by key; each entry's ``sources`` maps its fields to these."""

FAMILIES = {"container-20ft": ("container-20ft-empty", "container-20ft-loaded"),
            "container-40ft": ("container-40ft-empty", "container-40ft-loaded")}
"""Container families: (empty, loaded) entry names."""


@dataclass(frozen=True)
class DebrisType:
    """One catalogued debris type. Lengths m, masses kg, stiffnesses N/m.

    Attributes
    ----------
    name, description:
        The name a scene uses (``type: container-20ft-empty``) and one line on what it is.
    size_m:
        Outer [length, width, height]; the length lies along the flow at zero yaw.
    mass_kg:
        Mass (the container and what it carries).
    tare_kg:
        Mass of the empty container (the shell of the inertia model).
    inner_size_m:
        The cargo block's [length, width, height] (ISO 668 minimum internal dimensions).
    wall_thickness_m:
        A wall figure for information (see ``sources``); None where it means nothing.
    moment_of_inertia_kg_m2:
        Principal moments about the body axes through the centre (:func:`container_inertia`).
    contact_stiffness_N_m, contact_damping_ratio:
        The ``container`` (damped-spring) law at this scale; None where no source gives it.
    kd_N_m:
        The ``asce7_kd`` (rigid, undamped) law's stiffness at this scale; None where no source gives it.
    asce_kd_N_m:
        ASCE 7-22 Table 6.11-2's debris stiffness; None when it could not be sourced.
    scale:
        Length scale against the study's 1:40 model (40 for prototypes, 1 for the model).
    sources:
        Field name -> key of :data:`SOURCES`.
    """

    name: str
    description: str
    size_m: tuple[float, float, float]
    mass_kg: float
    tare_kg: float
    inner_size_m: tuple[float, float, float] | None
    wall_thickness_m: float | None
    contact_stiffness_N_m: float | None
    contact_damping_ratio: float | None
    kd_N_m: float | None
    scale: float
    asce_kd_N_m: float | None = None
    sources: dict = field(default_factory=dict, compare=False)

    @property
    def moment_of_inertia_kg_m2(self) -> tuple[float, float, float]:
        """Principal moments (kg m^2) of this entry at its own mass."""
        return container_inertia(self, self.mass_kg)

    @property
    def family(self) -> str | None:
        """The container family (``container-20ft``) this entry belongs to, or None."""
        return next((f for f, names in FAMILIES.items() if self.name in names), None)

    def scene_fields(self) -> dict:
        """The entry as a scene debris body's fields: size, mass, inertia and, where it has one, contact."""
        out = {"size_m": list(self.size_m), "mass_kg": self.mass_kg,
               "moment_of_inertia_kg_m2": list(self.moment_of_inertia_kg_m2)}
        if self.contact_stiffness_N_m is not None:
            out["contact"] = {"law": "container", "stiffness_N_m": self.contact_stiffness_N_m,
                              "damping_ratio": self.contact_damping_ratio}
        return out

    def to_dict(self) -> dict:
        """Plain data: every value, the derived inertia and each field's source text."""
        return {"name": self.name, "description": self.description, "size_m": list(self.size_m),
                "mass_kg": self.mass_kg, "tare_kg": self.tare_kg,
                "inner_size_m": None if self.inner_size_m is None else list(self.inner_size_m),
                "wall_thickness_m": self.wall_thickness_m,
                "moment_of_inertia_kg_m2": list(self.moment_of_inertia_kg_m2),
                "contact_stiffness_N_m": self.contact_stiffness_N_m,
                "contact_damping_ratio": self.contact_damping_ratio, "kd_N_m": self.kd_N_m,
                "asce_kd_N_m": self.asce_kd_N_m, "scale": self.scale, "family": self.family,
                "sources": {k: SOURCES[v] for k, v in self.sources.items()}}


def shell_inertia(size_m, mass_kg: float) -> tuple[float, float, float]:
    """Principal moments (kg m^2) of a closed thin shell: ``mass_kg`` spread uniformly over the
    six faces of a box ``size_m`` = [a, b, c] (per unit area, every face alike)."""
    a, b, c = (require_positive("size_m", s) for s in size_m)
    mass_kg = require_positive("mass_kg", mass_kg)
    area = 2.0 * (a * b + b * c + a * c)
    # two plates of each pair; a plate normal to axis n at distance d/2 from the centre adds
    # m_p (its in-plane sizes squared) / 12 about n and m_p (one size^2 / 12 + d^2 / 4) about the others
    m_bc, m_ac, m_ab = (2.0 * mass_kg * s / area for s in (b * c, a * c, a * b))
    ix = m_bc * (b * b + c * c) / 12 + m_ac * (c * c / 12 + b * b / 4) + m_ab * (b * b / 12 + c * c / 4)
    iy = m_ac * (a * a + c * c) / 12 + m_bc * (c * c / 12 + a * a / 4) + m_ab * (a * a / 12 + c * c / 4)
    iz = m_ab * (a * a + b * b) / 12 + m_bc * (b * b / 12 + a * a / 4) + m_ac * (a * a / 12 + b * b / 4)
    return (ix, iy, iz)


def container_inertia(entry: DebrisType, mass_kg: float) -> tuple[float, float, float]:
    """Principal moments (kg m^2) of ``entry`` carrying ``mass_kg`` in all.

    The tare is a closed thin shell on the outer box; the rest, ``mass_kg - tare_kg``, a uniform
    block of the entry's inner size, centred. Below the tare the shell alone carries the mass.
    An entry without an inner size (the 1:40 model) is a closed box of its wall thickness.
    """
    mass_kg = require_positive("mass_kg", mass_kg)
    if entry.inner_size_m is None:
        return box_inertia(entry.size_m, mass_kg, entry.wall_thickness_m)
    shell = shell_inertia(entry.size_m, min(mass_kg, entry.tare_kg))
    cargo = mass_kg - entry.tare_kg
    if cargo <= 0.0:
        return shell
    a, b, c = entry.inner_size_m
    block = (cargo * (b * b + c * c) / 12, cargo * (a * a + c * c) / 12, cargo * (a * a + b * b) / 12)
    return tuple(s + k for s, k in zip(shell, block))


# ------------------------------------------------------------------------------ the entries
_ISO20 = (6.058, 2.438, 2.591)
_ISO40 = (12.192, 2.438, 2.591)
_INNER20 = (5.867, 2.330, 2.350)
_INNER40 = (11.998, 2.330, 2.350)
_WALL = (2.438 - 2.330) / 2.0


def _container(name, description, size, inner, mass, mass_key, tare, tare_key) -> DebrisType:
    return DebrisType(
        name=name, description=description, size_m=size, mass_kg=mass, tare_kg=tare, inner_size_m=inner,
        wall_thickness_m=_WALL, contact_stiffness_N_m=None, contact_damping_ratio=None,
        kd_N_m=None, scale=LAB_SCALE, asce_kd_N_m=None,
        sources={"size_m": "iso668", "inner_size_m": "iso668", "mass_kg": mass_key, "tare_kg": tare_key,
                 "wall_thickness_m": "wall", "moment_of_inertia_kg_m2": "inertia",
                 "contact_stiffness_N_m": "lawless", "contact_damping_ratio": "lawless", "kd_N_m": "lawless",
                 "asce_kd_N_m": "asce_kd"})


_ENTRIES = (
    _container("container-20ft-empty", "ISO 1CC 20-ft general-purpose container, empty", _ISO20, _INNER20,
               2300.0, "tare20", 2300.0, "tare20"),
    _container("container-20ft-loaded", "ISO 1CC 20-ft container at its maximum gross mass", _ISO20, _INNER20,
               30480.0, "gross20", 2300.0, "tare20"),
    _container("container-40ft-empty", "ISO 1AA 40-ft general-purpose container, empty", _ISO40, _INNER40,
               3750.0, "tare40", 3750.0, "tare40"),
    _container("container-40ft-loaded", "ISO 1AA 40-ft container at its maximum gross mass", _ISO40, _INNER40,
               30480.0, "gross40", 3750.0, "tare40"),
    DebrisType(
        name="container-20ft-study-1to40", description="the reference study's 1:40 polyethylene model container",
        size_m=tuple(STUDY_CONTAINER_SIZE_M), mass_kg=STUDY_DEBRIS_MASS_KG, tare_kg=STUDY_DEBRIS_MASS_KG,
        inner_size_m=None, wall_thickness_m=STUDY_CONTAINER_WALL_M, contact_stiffness_N_m=CONTAINER_STIFFNESS_N_M,
        contact_damping_ratio=CONTAINER_DAMPING_RATIO, kd_N_m=STUDY_DEBRIS_STIFFNESS_N_M, scale=1.0,
        sources={"size_m": "study", "mass_kg": "study", "tare_kg": "study", "wall_thickness_m": "study",
                 "moment_of_inertia_kg_m2": "study", "contact_stiffness_N_m": "study",
                 "contact_damping_ratio": "study", "kd_N_m": "kd", "asce_kd_N_m": "asce_kd"}),
)
_BY_NAME = {e.name: e for e in _ENTRIES}


def list_debris() -> tuple[str, ...]:
    """The catalogue's debris names, in catalogue order."""
    return tuple(_BY_NAME)


def debris_type(name: str) -> DebrisType:
    """The catalogued debris ``name``; InputError (field ``type``) naming the known ones otherwise."""
    entry = _BY_NAME.get(name) if isinstance(name, str) else None
    if entry is None:
        raise InputError("type", f"unknown debris type {name!r}; the catalogue has {', '.join(_BY_NAME)} "
                                 "(`debrisfoam catalogue`)")
    return entry


def mass_range_kg(family_or_name: str) -> tuple[float, float]:
    """(empty, loaded) mass in kg of a container family (``container-20ft``) or of any of its entries."""
    family = family_or_name if family_or_name in FAMILIES else debris_type(family_or_name).family
    if family is None:
        raise InputError("type", f"{family_or_name!r} has no empty and loaded entries; families: "
                                 f"{', '.join(FAMILIES)}")
    empty, loaded = (debris_type(n) for n in FAMILIES[family])
    return (empty.mass_kg, loaded.mass_kg)


def _check() -> None:
    """Every entry's numeric fields carry a source, a missing one says "not found", and no full-size
    entry carries the laboratory law (import-time guard; tests call it too)."""
    for e in _ENTRIES:
        for name in ("size_m", "mass_kg", "moment_of_inertia_kg_m2", "contact_stiffness_N_m",
                     "contact_damping_ratio", "kd_N_m"):
            if e.sources.get(name) not in SOURCES:
                raise AssertionError(f"{e.name}.{name} has no source")
            if getattr(e, name) is None and not SOURCES[e.sources[name]].startswith("not found"):
                raise AssertionError(f"{e.name}.{name} is missing without saying so")
        if e.scale > 1.0 and (e.contact_stiffness_N_m, e.contact_damping_ratio, e.kd_N_m) != (None, None, None):
            raise AssertionError(f"{e.name}: a full-size entry with a contact law needs a full-scale source")


_check()
