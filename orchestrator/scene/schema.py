"""The scene schema: the pydantic models of every scene section, validated and immutable.

A scene is the description of one dam-break debris-impact set-up. Its sections are
``flume``, ``reservoir``, ``bed``, ``column`` (null = none), ``debris`` (a list; empty =
none; items are bodies or layout generators), ``gauges``, ``fluids``, ``mesh``, ``run``,
``outputs``, ``transport`` and ``design``; the models below give every field, its default and its range. They are
the single source of the scene reference (docs/scene.md, :mod:`orchestrator.scene.reference`).
Reading a scene file is :mod:`orchestrator.scene.scenefile`; resolving layouts, placements
and gauges is :mod:`orchestrator.scene.resolve`; the cross-field rules are
:mod:`orchestrator.scene.validation`.

Coordinates (also in docs/scene.md): ``x`` along the flume, 0 at the gate, positive
downstream; ``y`` across, 0 on the centreline; ``z`` up from the floor. The flume runs
from ``x = -reservoir.length_m`` (its upstream wall) to
``x = flume.length_m - reservoir.length_m`` (its downstream end). Lengths in metres,
masses in kilograms, times in seconds, angles in degrees.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Literal

import yaml
from pydantic import Field, ValidationError, field_validator, model_validator

from analytical.catalogue import list_debris
from analytical.column import ENDS, MAX_ELEMENTS
from analytical.column import Column as AnalysisColumn
from orchestrator.core.errors import InputError
from analytical.hydrodynamics import DEFAULT_ADDED_MASS_COEFFICIENT, DEFAULT_DRAG_COEFFICIENT
from orchestrator.scene.base import NonNeg, Pos, SceneSection
from orchestrator.scene.flume import Bed, Flume, Reservoir
from orchestrator.scene.catalogued import (GEOMETRY_FIELDS, ColumnSectionSpec, column_from_section,
                                           debris_from_catalogue, section_geometry)

__all__ = [
    "Bed",
    "ColumnSection",
    "ColumnSectionSpec",
    "DebrisBody",
    "DebrisContact",
    "DebrisLayout",
    "DebrisTemplate",
    "Design",
    "DesignInundation",
    "Flume",
    "Fluids",
    "Gauge",
    "Inundation",
    "Mesh",
    "Outputs",
    "Reservoir",
    "Run",
    "Scene",
    "SceneSection",
    "column_for_analysis",
    "default_column",
]

# ---------------------------------------------------------------------------- sections


class ColumnSection(SceneSection):
    """The obstacle: a box on the floor centred at (x_m, y_m).

    The structural fields match :class:`analytical.column.Column` (same names, same
    defaults for the measured values) so :func:`column_for_analysis` can build one. With
    ``section`` (a prototype column by section) the footprint, wall, section properties and
    material come from the section and the frequency and stiffness from its MDOF model; a
    circular section stands in the flow as the square box around it.
    """

    x_m: float = Field(description="centre of the column's footprint along the flume (m)")
    y_m: float = Field(0.0, description="centre of the footprint across the flume (m)")
    section: ColumnSectionSpec | None = Field(
        None, description="a prototype column by section; null = the fields below as given")
    size_x_m: float = Field(gt=0, description="footprint along the flow (m); from `section` when given")
    size_y_m: float = Field(gt=0, description="footprint across the flow (m); from `section` when given")
    height_m: float = Field(gt=0, description="height above the floor (m), at most 100 m")
    wall_thickness_m: float = Field(gt=0, description="wall of the hollow section (m); from `section` when given")
    section_area_m2: float | None = Field(None, gt=0, description="section area A (m2); null = the box's")
    section_second_moment_m4: float | None = Field(
        None, gt=0, description="second moment about the bending axis (m4); null = the box's")
    stiffness_factor: float = Field(1.0, gt=0, le=1, description="effective-stiffness factor on E I (-); "
                                    "a cracked concrete section's")
    youngs_modulus_Pa: float = Field(gt=0, description="Young's modulus (Pa); from `section` when not given")
    density_kg_m3: float = Field(gt=0, description="material density (kg/m3); from `section` when not given")
    poisson_ratio: float = Field(gt=-1, lt=0.5, description="Poisson's ratio (-); from `section` when not given")
    shear_coefficient: float = Field(gt=0, description="Timoshenko shear coefficient of the section (-); from `section` when given")
    natural_frequency_Hz: float = Field(70.0, gt=0, description="measured first frequency (Hz); with a section "
                                        "its MDOF model's (base: calibrated: the target, required)")
    stiffness_N_m: float = Field(4.685e5, gt=0, description="measured lateral stiffness (N/m); with a section, "
                                 "its MDOF model's at the top (mid-height with a held top)")
    damping_ratio: float = Field(0.045, ge=0, lt=1, description="measured damping ratio (-); 0 = undamped; "
                                 "with a section, its material's")
    base: Literal["rigid", "calibrated", "spring"] = Field(
        "rigid", description="rigid (fixed), calibrated (a rotational spring tuned to natural_frequency_Hz) or "
        "spring (of base_spring_Nm_rad)")
    base_spring_Nm_rad: float | None = Field(
        None, gt=0, validate_default=True, description="rotational base spring (N m/rad); with base: spring only")
    elements: int = Field(
        160, ge=1, le=MAX_ELEMENTS, description="Timoshenko elements of the MDOF model (time grows as their cube)")
    ends: Literal[ENDS] = Field("cantilever", description="cantilever (free top), fixed-fixed (the floor above "
                                "holds its top), pinned (translation held at both ends); base: rigid")
    strike_height_m: float | None = Field(None, gt=0, description="where ASCE 7-22's load strikes (m): its k_s "
                                          "and pulse; null = inundation.depth_m")
    heading_deg: float = Field(0.0, ge=-90, le=90, description="section turned from the flow (deg), for ASCE's k_s; "
                               "OpenFOAM cases take 0")

    @model_validator(mode="before")
    @classmethod
    def _from_section(cls, data: Any) -> Any:
        if not isinstance(data, dict) or data.get("section") is None:
            return data
        try:
            section = ColumnSectionSpec.model_validate(data["section"])
        except ValidationError:
            return data  # the section field reports it
        return column_from_section(data, section)

    @field_validator(*GEOMETRY_FIELDS)
    @classmethod
    def _as_section(cls, value, info):
        section = info.data.get("section")
        if section is not None:
            fixed = section_geometry(section)[info.field_name]
            if value is None or abs(value - fixed) > 1e-9 * abs(fixed):
                raise ValueError(f"is fixed by column.section ({fixed:.6g}); leave it out or change the section")
        return value

    @field_validator("natural_frequency_Hz", mode="before")
    @classmethod
    def _target(cls, value):
        if value is None:
            raise ValueError("required with column.section and base: calibrated (the base spring's target)")
        return value

    @field_validator("base_spring_Nm_rad")
    @classmethod
    def _spring(cls, value, info):
        if (info.data.get("base") == "spring") != (value is not None):
            raise ValueError("required with base: spring, and only with it")
        return value

    @field_validator("ends")
    @classmethod
    def _ends(cls, value, info):
        if value != "cantilever" and info.data.get("base", "rigid") != "rigid":
            raise ValueError(f"{value} needs base: rigid (a base spring is a cantilever's)")
        return value

    @field_validator("strike_height_m")
    @classmethod
    def _strike(cls, value, info):
        height, ends = info.data.get("height_m"), info.data.get("ends")
        if value is not None and height is not None and (value > height or (value == height and ends != "cantilever")):
            raise ValueError(f"must be {'at most' if ends == 'cantilever' else 'below'} the column's height_m "
                             f"({height:g} m: a {ends} member)")
        return value


class DebrisContact(SceneSection):
    """How a debris body strikes the column, a wall or another body, and how it slides on the bed.

    ``law: container`` (default) is the contact law calibrated on the study's 22 impacts (its
    Table 2, through the study's own fit; analytical.contact_law, docs/contact-law.md): a damped
    spring of the container's own compliance, far softer than a rigid box, that loses energy. ``law: asce7_kd`` is the rigid debris stiffness k_d backed out
    of the study's ASCE 7-22 rows (3.0e6 N/m), undamped: ASCE 7-22's own assumption, an upper
    bound. ``stiffness_N_m``, ``damping_ratio`` or ``restitution`` override the law's values;
    give at most one of the last two. Full-scale debris states them (no full-scale source).
    """

    law: Literal["container", "asce7_kd"] = Field(
        "container", description="container: a damped spring calibrated on the study's 22 impacts (Table 2); "
        "asce7_kd: rigid debris "
        "stiffness k_d, undamped (docs/contact-law.md)")
    stiffness_N_m: float | None = Field(None, gt=0, description="contact stiffness k (N/m); null = the law's "
                                        "(the study's 1:40); full-scale debris must state it")
    damping_ratio: float | None = Field(
        None, ge=0, lt=1, description="contact dashpot as a fraction of 2 sqrt(k m_eff) (-); null = the law's; "
        "full-scale debris must state it (or restitution)")
    restitution: float | None = Field(
        None, gt=0, le=1, description="coefficient of restitution against a rigid wall (-), turned into the "
        "damping ratio that gives it; null = from damping_ratio or the law")
    friction_coefficient: float = Field(
        0.3, ge=0, description="Coulomb coefficient at the contact point during an impact (-); polyethylene on "
        "a smooth hard surface")
    bed_friction_coefficient: float = Field(
        0.3, ge=0, description="Coulomb coefficient while the body rests on the bed (-); polyethylene on the "
        "flume's bed")

    @field_validator("restitution")
    @classmethod
    def _one_loss(cls, value, info):
        if value is not None and info.data.get("damping_ratio") is not None:
            raise ValueError("give damping_ratio or restitution, not both")
        return value


class DebrisTemplate(SceneSection):
    """A debris body's shape, mass and pose, without its name and position.

    Body axes: x along ``size_m[0]`` (length), y along ``size_m[1]`` (width), z along
    ``size_m[2]`` (height). With zero angles the length lies along the flow. The
    orientation is yaw about z, then pitch about the new y, then roll about the newest x
    (intrinsic z-y'-x''), in degrees.

    Inertia: a closed box with walls ``wall_thickness_m`` thick (uniform material), or
    ``moment_of_inertia_kg_m2`` given (principal, body axes), or neither: a solid box.

    ``type`` names a catalogued debris (analytical.catalogue, docs/catalogue.md): its size, mass,
    inertia (and the 1:40 model's contact stiffness) are filled in, and fields written beside it
    override them. Full-scale debris states its contact law (docs/fullscale-sources.md).
    """

    type: str | None = Field(None, description="a catalogued debris type (`debrisfoam catalogue`: "
                             + ", ".join(list_debris()) + "); its size, mass and inertia fill the fields not "
                             "given; null = every field as given")
    size_m: tuple[Pos, Pos, Pos] = Field(description="[length, width, height] (m); from `type` when not given")
    mass_kg: float = Field(gt=0, description="mass (kg); from `type` when not given")
    wall_thickness_m: float | None = Field(None, gt=0, description="null = solid or inertia given")
    moment_of_inertia_kg_m2: tuple[Pos, Pos, Pos] | None = Field(
        None, description="principal moments about the body axes through the centre (kg m^2)"
    )
    placement: Literal["on_bed", "floating", "given"] | None = Field(
        None,
        description="on_bed: resting on the floor; floating: at its equilibrium draft if the "
        "local water is deep enough, else on the bed; given: centre_m[2] as written. "
        "Default: given when centre_m has z, else on_bed",
    )
    yaw_deg: float = Field(0.0, description="turn about z (degrees; 0: length along the flow)")
    pitch_deg: float = Field(0.0, description="then about the new y (degrees)")
    roll_deg: float = Field(0.0, description="then about the newest x (degrees)")
    velocity_m_s: tuple[float, float, float] = Field(
        (0.0, 0.0, 0.0), description="initial velocity [u, v, w] of the centre of mass (m/s); default at rest"
    )
    contact: DebrisContact = Field(
        DebrisContact(), description="contact law, its energy loss and friction (docs/contact-law.md)")
    upright: bool | None = Field(
        None,
        description="keep the body upright (it yaws, it does not pitch or roll): v1912 has no bed contact, so a "
        "tipping body digs a corner into the floor. null = upright if it starts on the bed",
    )

    @model_validator(mode="before")
    @classmethod
    def _from_catalogue(cls, data: Any) -> Any:
        return debris_from_catalogue(data)

    @field_validator("type")
    @classmethod
    def _known_type(cls, value):
        if value is not None and value not in list_debris():
            raise ValueError(f"unknown debris type {value!r}; the catalogue has {', '.join(list_debris())} "
                             "(`debrisfoam catalogue`)")
        return value


class DebrisBody(DebrisTemplate):
    """One rigid debris body (a six-DoF body on its own overset mesh)."""

    name: str = Field(description="OpenFOAM-safe identifier: letters, digits, _")
    centre_m: tuple[float, ...] = Field(
        description="[x, y, z] of the centre of mass, or [x, y] with z from the placement (m)"
    )

    @field_validator("centre_m")
    @classmethod
    def _two_or_three(cls, value: tuple[float, ...]) -> tuple[float, ...]:
        if len(value) not in (2, 3):
            raise ValueError(f"needs [x, y] or [x, y, z], got {len(value)} values")
        return value


class DebrisLayout(SceneSection):
    """A generator of identical bodies on a grid: ``layout: RxC``.

    ``R`` rows follow one another along the flow (x) and ``C`` columns sit side by side
    across it (y); the study's layouts are ``1x1``, ``3x1`` (three in a line along the
    flow), ``1x3`` (three abreast) and ``2x3``. ``layout: 1`` means ``1x1``.
    Bodies are named ``<name_prefix><n>``, n = 1.. row by row from upstream, and across
    each row from -y to +y.
    """

    layout: str | int = Field(description="RxC: rows along the flow x columns across it; 1 = 1x1")
    centre_m: tuple[float, float] = Field(description="[x, y] of the layout's centre (m)")
    spacing_m: tuple[NonNeg, NonNeg] = Field(
        (0.25, 0.15), description="centre-to-centre spacing [along the flow, across] (m)"
    )
    name_prefix: str = Field("debris", description="bodies are named <name_prefix>1, 2, ...")
    body: DebrisTemplate


class Gauge(SceneSection):
    """A wave gauge: the water depth on a vertical line at (x_m, y_m).

    ``at: column_upstream_face`` places it on the column's centreline, ``offset_m``
    upstream of the upstream face (x_m and y_m are then computed).
    """

    name: str = Field(description="the gauge's name in the results (e.g. WG2)")
    x_m: float | None = Field(None, description="x of the gauge (m); null with `at`")
    y_m: float | None = Field(None, description="y of the gauge (m); null with `at`")
    at: Literal["column_upstream_face"] | None = Field(
        None, description="place it on the column's centreline, offset_m upstream of its upstream face")
    offset_m: float = Field(0.01, ge=0, description="upstream distance from the face when `at` is used (m)")


class Fluids(SceneSection):
    """Water and air properties (defaults: fresh water and air at 20 C)."""

    water_density_kg_m3: float = Field(998.2, gt=0, description="(kg/m3)")
    water_viscosity_m2_s: float = Field(1.0e-6, gt=0, description="kinematic viscosity (m2/s)")
    air_density_kg_m3: float = Field(1.0, gt=0, description="(kg/m3)")
    air_viscosity_m2_s: float = Field(1.48e-5, gt=0, description="kinematic viscosity (m2/s)")
    surface_tension_N_m: float = Field(0.07, ge=0, description="water-air surface tension (N/m)")
    gravity_m_s2: float = Field(9.81, gt=0, description="gravitational acceleration (m/s2)")
    turbulence: Literal["laminar", "kOmegaSST"] = Field(
        "laminar", description="the flow's closure: laminar (bed friction as a drag on the layers next to the bed, "
        "bed.friction_calibration), or RANS k-omega SST with wall functions, the bed rough with the sand roughness "
        "that gives bed.friction_factor in the bore (analytical/roughness.py; no drag layer, no calibration)")


class Mesh(SceneSection):
    """Mesh resolution: the finest cell where the scene needs it, coarser elsewhere."""

    cell_size_m: float = Field(gt=0, description="finest cell size: bed and bore, column, debris path (m)")
    coarsening_ratio: float = Field(4.0, ge=1, description="largest cell / finest cell (-)")
    growth_ratio: float = Field(1.15, gt=1, le=2, description="largest size ratio of neighbouring cells (-)")
    wet_bed_cells: int = Field(
        1, ge=1, le=20,
        description="cells across the wet bed's depth, growing by growth_ratio a cell above it up to cell_size_m "
        "(-); 1 = the wet bed is one layer (docs/bed-friction.md)")
    body_cells_across: float = Field(
        4.0, gt=0,
        description="body-mesh cells across the smallest debris dimension (-); fewer drive spurious air jets "
        "onto the body (docs/openfoam-notes.md)",
    )
    body_margin_cells: int = Field(
        3, ge=1, description="finest cells between a body and the edge of its overset mesh"
    )
    debris_spread_deg: float = Field(
        22.5, ge=0, lt=90, description="half-angle of the debris path's lateral spread (ASCE 7-22 6.11)"
    )
    top_m: float | None = Field(
        None, gt=0, description="top of the modelled air space; null = min(flume height, 1.5 depth) (m)"
    )
    refine_box_m: tuple[float, float, float, float, float, float] | None = Field(
        None, description="x0, x1, y0, y1, z0, z1 of a box of finer cells (refine_cell_size_m) inside the fine "
        "region; the block grid refines the slabs through it (orchestrator/plan/refine.py); null = none (m)")
    refine_cell_size_m: float | None = Field(
        None, gt=0, description="cell size inside refine_box_m, finer than cell_size_m (m); null = none")
    column_approach_cell_size_m: float | None = Field(
        None, gt=0, description="cells of this size where bodies close on the column: a refinement box that "
        "follows the column and scales with the bodies (its extent: orchestrator/plan/refine.py); no finer than "
        "cell_size_m: no box; null = none (m)")
    trim_domain: bool = Field(
        True,
        description="false: model the whole reservoir, the whole flume to its downstream end and its full height, "
        "as a hand-made set-up would (with coarsening_ratio 1: uniform cells; the speed-error baseline)",
    )


class Run(SceneSection):
    """Simulated time and solver controls."""

    end_time_s: float = Field(gt=0, description="simulated time from the gate's release (s)")
    cores: int = Field(2, ge=1, description="MPI ranks")
    write_interval_s: float = Field(0.1, gt=0, description="interval between field writes (s)")
    max_courant: float = Field(
        0.9, gt=0, le=5, description="maxCo and maxAlphaCo (-); with debris it also picks the PIMPLE correctors: "
        "<= 1 the careful ones (2 outer, 3 pressure), above 1 the fast ones (1 outer, 2 pressure; "
        "benchmarks/runner_settings.md)")
    max_delta_t_s: float | None = Field(
        None, gt=0, description="largest time step (s); null = min(0.01 s x sqrt(lambda), write interval), lambda = max(1, h0 / 0.40 m) (the Froude scale over the study's flume, docs/prototype.md), which also caps "
                                "the Courant number on coarse meshes")
    stall_limit_s: float | None = Field(
        None, gt=0, description="wall seconds without solver output after which the runner stops the run as "
                                "stalled; null = 600 s (or 20 x the slowest time step, when longer)")
    water_balance_limit: float | None = Field(
        None, gt=0, description="fraction of the initial water a run may create or lose (its water balance, "
                                "results/water_balance.csv) before the runner stops it with a diagnosis; "
                                "null = 0.01, the stability check's 1 % (docs/stability.md)")
    debris_coupling: Literal["auto", "one-way", "two-way"] = Field(
        "auto", description="how the debris meets the flow: two-way: six-DoF bodies on overset meshes in the "
        "flow (overInterDyMFoam); one-way: the flow once without them (interFoam), recorded, the bodies carried "
        "through the record afterwards; auto: one-way when the bodies displace under 0.1 % of the reservoir's "
        "water and block under 40 % of the width, else two-way (plan.json says which and why)")


class Outputs(SceneSection):
    """What the run records besides the fields."""

    probe_interval_s: float | None = Field(
        0.01, gt=0, description="sampling interval of gauges and forces; null = every time step (s)"
    )
    fields: tuple[str, ...] = Field(("alpha.water", "U", "p_rgh"), description="fields written at each write "
                                    "interval")
    preview: bool = Field(True, description="draw the scene to preview.png when rendering")
    flow_record_hz: float = Field(
        50.0, gt=0, le=1000, description="frames per second of a one-way run's flow record (Hz); 50 Hz is 10 "
        "frames over the bore's passage in the study's flume, 50 / sqrt(lambda) at Froude scale lambda")


class Transport(SceneSection):
    """The hydrodynamic forcing of one-way transport (run.debris_coupling one-way: the bodies
    carried through the recorded flow; docs/one-way.md). Each body is split into sub-volumes; each
    submerged one takes buoyancy, the water's inertia (Froude-Krylov and the box's own added mass
    along its axes), drag along the water's motion past it, and the Munk moment of its
    anisotropic added mass."""

    drag_coefficient: float = Field(
        DEFAULT_DRAG_COEFFICIENT, ge=0, le=5, description="C_d of a body on the area it shows the water moving "
        "past it (transport.drag_area); 0 switches drag off. The default is Hoerner's (1965, ch. 3) free-stream "
        "value for a box face-on, 1.05 (a cube; rectangular blocks 1.0-1.2), not a fitted one (docs/one-way.md)")
    added_mass_coefficient: float | None = Field(
        DEFAULT_ADDED_MASS_COEFFICIENT, ge=0, le=5, description="C_a of the submerged volume on every body axis, "
        "added to the water's inertia force and to the body's inertia; null (the default): each box's own along "
        "and about its axes at its current draft (the container afloat: 0.28 lengthwise, 0.84 sideways, 1.04 "
        "vertically; DNV-RP-H103 4.6.3.3 and Lamb's ellipsoid, analytical/added_mass.py); 0 switches it off")
    sub_volumes: tuple[int, int, int] = Field(
        (5, 3, 3), description="sub-volumes along the body's length, width and height over which the water is "
        "sampled, so that heave, pitch and roll answer the surface across the body")
    drag_area: Literal["projected", "per_axis"] = Field(
        "projected", description="projected: drag along the water's motion past the body, on the box's area seen "
        "along it (a bluff body); per_axis: on each body axis with that axis's face (the cross-flow principle of "
        "slender bodies, which pushes a yawed box sideways)")
    munk_moment: bool = Field(
        True, description="the yaw and pitch moment of the body's anisotropic added mass as it moves through the "
        "water, -U x (A U) (Newman 1977): it turns an elongated body broadside to its motion through the water")

    @field_validator("sub_volumes")
    @classmethod
    def _counts(cls, value):
        if any(n < 1 for n in value):
            raise ValueError("must be three integers >= 1")
        return value


class DesignInundation(SceneSection):
    """One inundation case of a design study (``debrisfoam design``, docs/design.md): the scene
    with these overrides is one flow, run once; its realisations weigh ``weight``."""

    name: str | None = Field(None, description="the case's name in the tables (null: case<k>, k from 1)")
    set: tuple[str, ...] = Field(
        (), description="scene overrides of this case, a mapping of dotted keys to values (e.g. "
        "{reservoir.depth_m: 0.35}) or a list of key=value strings, as --set takes them")
    weight: float = Field(1.0, gt=0, description="the case's weight; the weights are normalised to sum to 1 (-)")

    @field_validator("set", mode="before")
    @classmethod
    def _overrides(cls, value):
        if isinstance(value, dict):
            value = [f"{k}={yaml.safe_dump(v, default_flow_style=True).strip().removesuffix('...').strip()}"
                     for k, v in value.items()]
        if not isinstance(value, (list, tuple)) or not all(isinstance(v, str) and "=" in v for v in value):
            raise ValueError("must be a mapping of dotted scene keys to values, or a list of key=value strings")
        if any(v.partition("=")[0].strip().split(".")[0] == "design" for v in value):
            raise ValueError("an inundation case cannot override the design section itself")
        return tuple(v.strip() for v in value)


class Design(SceneSection):
    """What ``debrisfoam design`` samples (docs/design.md): each realisation draws every body's
    start, heading and mass over the ranges below, and an inundation case by its weight. Not
    read by a flow: changing it never makes another case."""

    realisations: int = Field(2000, ge=1, description="realisations over all inundation cases")
    seed: int = Field(0, ge=0, description="seed of the draws (realisation r draws from (seed, case, r))")
    mass_kg: tuple[Pos, Pos] | None = Field(
        None, description="[least, greatest] mass of every body (kg; e.g. empty and loaded), drawn uniformly; "
        "null: each body's own mass")
    heading_deg: tuple[float, float] | None = Field(
        None, description="[least, greatest] yaw of every body (degrees), drawn uniformly; null: the "
        "ensemble's placement tolerance about each body's own yaw (normal, 12 degrees)")
    start_x_m: tuple[float, float] | None = Field(
        None, description="[least, greatest] x of a body's centre at the start (m), drawn uniformly; null "
        "(with start_y_m null): the ensemble's placement tolerance about each body's own centre")
    start_y_m: tuple[float, float] | None = Field(
        None, description="[least, greatest] y of a body's centre at the start (m), drawn uniformly; null: "
        "each body's own y (with start_x_m) or the placement tolerance (without)")
    inundation: tuple[DesignInundation, ...] = Field(
        (DesignInundation(),), description="the inundation cases: each a flow of the scene with its overrides, "
        "weighted; default one case, the scene as it is")
    risk_category: Literal["II", "III", "IV", "vertical-evacuation-refuge"] = Field(
        "II", description="Tsunami Risk Category, for ASCE 7-22's importance factor I_tsu (Table 6.8-1)")
    orientation_coefficient: float = Field(
        0.65, gt=0, le=1, description="ASCE 7-22 6.11's orientation coefficient C_o (0.65: containers, logs, poles)")
    debris_stiffness_N_m: float | None = Field(
        None, gt=0, description="ASCE 7-22 6.11's debris stiffness k_d (N/m), 1e5 to 1e11; null: at laboratory "
        "scale the study's 1:40 container's (analytical/asce7.py); required at full scale")
    prototype: bool = Field(
        False, description="full-scale inputs even when light: ASCE 7-22's simplified static load 1,470 C_o I_tsu kN "
        "bounds F_i; a scene with a body of 100 kg or more, or a catalogued full-size one, is full scale without it")
    confidence: float = Field(0.95, gt=0, lt=1, description="level of every interval (-)")

    @field_validator("start_x_m", "start_y_m", "mass_kg", "heading_deg")
    @classmethod
    def _ordered(cls, value):
        if value is not None and not value[0] <= value[1]:
            raise ValueError("must be [least, greatest]")
        return value

    @field_validator("inundation")
    @classmethod
    def _cases(cls, value):
        if not value:
            raise ValueError("give at least one inundation case")
        names = [c.name for c in value if c.name is not None]
        if len(set(names)) != len(names):
            raise ValueError(f"case names must be unique, got {names}")
        return value


class Inundation(SceneSection):
    """The bore a scene asks for at its column, instead of a reservoir: ASCE 7-22's inundation
    depth and flow speed at the site. The planner sizes the dam break that makes it
    (:mod:`orchestrator.scene.inundation`, Stoker's frictionless wet-bed solution): the
    impoundment depth ``reservoir.depth_m``, the wet bed ``bed.wet_depth_m`` (a given wet bed
    allows one speed at a given depth) and, when not given, ``reservoir.length_m`` (long enough
    that the negative wave reflected from the upstream wall reaches the column after
    ``run.end_time_s``). Bed friction slows the real bore: docs/prototype.md gives the measured
    difference."""

    depth_m: float = Field(gt=0, description="flow depth behind the bore at the column, without the column (m)")
    speed_m_s: float = Field(gt=0, description="depth-averaged flow speed behind the bore at the column (m/s)")


class Scene(SceneSection):
    """A resolved, validated scene (every body placed, every gauge positioned)."""

    name: str = Field("scene", description="the scene's name (run folders and reports)")
    description: str = Field("", description="one line on what the scene is")
    flume: Flume
    reservoir: Reservoir
    bed: Bed = Bed()
    column: ColumnSection | None = None
    debris: tuple[DebrisBody, ...] = ()
    gauges: tuple[Gauge, ...] = ()
    fluids: Fluids = Fluids()
    mesh: Mesh
    run: Run
    outputs: Outputs = Outputs()
    transport: Transport = Transport()
    design: Design = Design()
    inundation: Inundation | None = Field(
        None, description="the bore wanted at the column (depth, speed); the reservoir and wet bed are then sized "
        "for it (docs/prototype.md, 'Scenes that state their bore'); null: the reservoir as given")


# ------------------------------------------------------------------------ the column


def default_column(x_m: float = 5.0, y_m: float = 0.0) -> ColumnSection:
    """The reference study's acrylic column (:class:`analytical.column.Column`'s defaults) at (x_m, y_m).

    0.20 x 0.20 x 0.80 m hollow section, 5 mm wall, E = 2.50 GPa, rho = 1200 kg/m^3,
    nu = 0.375, shear coefficient 0.50, measured 70 Hz, 4.685e5 N/m, damping 0.045.
    The default x (5.0 m) is this project's choice; see cases/1debris.yaml.
    """
    return ColumnSection(
        x_m=x_m,
        y_m=y_m,
        size_x_m=0.20,
        size_y_m=0.20,
        height_m=0.80,
        wall_thickness_m=0.005,
        youngs_modulus_Pa=2.50e9,
        density_kg_m3=1200.0,
        poisson_ratio=0.375,
        shear_coefficient=0.50,
    )


def column_for_analysis(scene: Scene) -> AnalysisColumn:
    """The scene's column as an :class:`analytical.column.Column` (structural fields only)."""
    if scene.column is None:
        raise InputError("column", "the scene has no column to analyse")
    names = {f.name for f in dataclasses.fields(AnalysisColumn)}
    values = scene.column.model_dump()
    return AnalysisColumn(**{k: v for k, v in values.items() if k in names})
