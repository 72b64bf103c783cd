"""Scenes: the validated, immutable description of one dam-break debris-impact set-up.

A scene is read from YAML (:func:`load_scene`), optionally changed by dotted overrides
(``mesh.cell_size_m=0.02``, the same syntax as ``--set``), resolved (debris layouts
expanded into bodies, bodies placed on the bed, gauges placed at the column) and
validated. Every problem is an :class:`~analytical.errors.InputError` naming the dotted
field, the rule and the file; nothing downstream sees an invalid scene.

Coordinates (also in docs/scene.md): ``x`` along the flume, 0 at the gate, positive
downstream; ``y`` across, 0 on the centreline; ``z`` up from the floor. The flume runs
from ``x = -reservoir.length_m`` (its upstream wall) to
``x = flume.length_m - reservoir.length_m`` (its downstream end). Lengths in metres,
masses in kilograms, times in seconds, angles in degrees.

A scene file may start from another: ``extends: ../1debris.yaml`` takes that file's
sections as defaults and lays this file's keys over them (mappings merge key by key,
lists such as ``debris`` are replaced whole); ``cases/hard/`` is written that way.

Sections (see the models below for every field and default): ``flume``, ``reservoir``,
``bed``, ``column`` (null = none), ``debris`` (a list; empty = none; items are bodies or
layout generators), ``gauges``, ``fluids``, ``mesh``, ``run``, ``outputs``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from analytical.errors import InputError

__all__ = [
    "Bed",
    "Column",
    "DebrisBody",
    "DebrisContact",
    "DebrisLayout",
    "DebrisTemplate",
    "Flume",
    "Fluids",
    "Gauge",
    "Mesh",
    "MIN_CELLS_ACROSS_DEBRIS",
    "MIN_CELLS_ACROSS_COLUMN",
    "MIN_CELLS_OVER_DEPTH",
    "Outputs",
    "Reservoir",
    "Run",
    "Scene",
    "apply_overrides",
    "body_rotation",
    "boxes_overlap",
    "column_for_analysis",
    "default_column",
    "dump_scene_yaml",
    "flume_extent",
    "draft_m",
    "half_extent_z",
    "load_scene",
    "parse_override",
    "scene_from_dict",
    "scene_to_dict",
    "validate_scene",
]

#: The finest cell may be at most 1/1.5 of the smallest debris dimension: every body
#: then covers at least one background cell centre across each of its dimensions
#: wherever it sits, so it always cuts a hole in the background mesh (overset).
MIN_CELLS_ACROSS_DEBRIS = 1.5
#: At least this many finest cells across each horizontal side of the column.
MIN_CELLS_ACROSS_COLUMN = 2.0
#: At least this many finest cells over the impoundment depth.
MIN_CELLS_OVER_DEPTH = 4.0

_TOL = 1e-9
_NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_LAYOUT_RE = re.compile(r"^\s*(\d+)\s*[xX]\s*(\d+)\s*$")

#: A float that must be > 0 (inside tuples, so the error names the component).
Pos = Annotated[float, Field(gt=0)]
#: A float that must be >= 0.
NonNeg = Annotated[float, Field(ge=0)]


class _Model(BaseModel):
    """Base of every scene section: unknown keys are errors, instances are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)


# ---------------------------------------------------------------------------- sections


class Flume(_Model):
    """The tank or flume: a rectangular box of floor length x width, walls height high."""

    length_m: float = Field(gt=0, description="total length, reservoir included (m)")
    width_m: float = Field(gt=0, description="inside width (m)")
    height_m: float = Field(gt=0, description="wall height above the floor (m)")
    downstream_end: Literal["closed", "open"] = Field(
        "closed", description="closed: an end wall; open: water leaves (free outfall)"
    )


class Reservoir(_Model):
    """The impoundment at the upstream end, from the upstream wall to the gate at x = 0."""

    length_m: float = Field(gt=0, description="from the upstream wall to the gate (m)")
    depth_m: float = Field(gt=0, description="impoundment depth h0 (m)")
    gate: Literal["swing-gate", "instant"] = Field(
        "instant", description="how the water is released; both are modelled as instant removal"
    )


class Bed(_Model):
    """The flume floor downstream of the gate."""

    wet_depth_m: float = Field(0.0, ge=0, description="still-water depth downstream of the gate; 0 = dry (m)")
    friction_factor: float = Field(0.0293, ge=0, description="Darcy friction factor f of the bed (-)")
    friction_calibration: float = Field(
        2.2, gt=0,
        description="multiplier on the bed-friction drag of the cell layers next to the bed (they under-brake the "
        "thin bore tip); the default 2.2 makes the arrivals at 2.40 m and 3.20 m match Chanson's solution with "
        "f = 0.0293 within 0.012 s at 4 cm cells (docs/bed-friction.md)",
    )


class Column(_Model):
    """The obstacle: a rectangular box standing on the floor, centred at (x_m, y_m).

    The structural fields match :class:`analytical.column.Column` (same names, same
    defaults for the measured values) so :func:`column_for_analysis` can build one.
    """

    x_m: float = Field(description="centre of the column's footprint along the flume (m)")
    y_m: float = Field(0.0, description="centre of the footprint across the flume (m)")
    size_x_m: float = Field(gt=0, description="footprint along the flow (m)")
    size_y_m: float = Field(gt=0, description="footprint across the flow (m)")
    height_m: float = Field(gt=0, description="height above the floor (m)")
    wall_thickness_m: float = Field(gt=0, description="wall of the hollow section (m)")
    youngs_modulus_Pa: float = Field(gt=0, description="Young's modulus of the column's material (Pa)")
    density_kg_m3: float = Field(gt=0, description="density of the column's material (kg/m3)")
    poisson_ratio: float = Field(gt=-1, lt=0.5, description="Poisson's ratio (-)")
    shear_coefficient: float = Field(gt=0, description="Timoshenko shear coefficient of the section (-)")
    natural_frequency_Hz: float = Field(70.0, gt=0, description="measured first frequency (Hz)")
    stiffness_N_m: float = Field(4.685e5, gt=0, description="measured lateral stiffness (N/m)")
    damping_ratio: float = Field(0.045, ge=0, lt=1, description="measured damping ratio (-); 0 = undamped")
    base: Literal["rigid", "calibrated"] = Field(
        "rigid", description="rigid: the study's MDOF (geometry only, f1 88 Hz); calibrated: a base spring tuned "
        "to natural_frequency_Hz")
    elements: int = Field(160, ge=1, description="Timoshenko elements of the MDOF model")


class DebrisContact(_Model):
    """How a debris body strikes the column, a wall or another body, and how it slides on the bed.

    ``law: container`` (default) is the contact law calibrated on the study's Table 1 event
    (analytical.contact_law, docs/contact-law.md): a spring of the container's own compliance,
    far softer than a rigid box. ``law: asce7_kd`` is the rigid debris stiffness k_d backed out
    of the study's ASCE 7-22 rows (3.0e6 N/m), undamped: ASCE 7-22's own assumption, an upper
    bound. ``stiffness_N_m``, ``damping_ratio`` or ``restitution`` override the law's values;
    give at most one of the last two.
    """

    law: Literal["container", "asce7_kd"] = Field(
        "container", description="container: calibrated on the study's Table 1 event; asce7_kd: rigid debris "
        "stiffness k_d, undamped (docs/contact-law.md)")
    stiffness_N_m: float | None = Field(None, gt=0, description="contact stiffness k (N/m); null = the law's")
    damping_ratio: float | None = Field(
        None, ge=0, lt=1, description="contact dashpot as a fraction of 2 sqrt(k m_eff) (-); null = the law's")
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


class DebrisTemplate(_Model):
    """A debris body's shape, mass and pose, without its name and position.

    Body axes: x along ``size_m[0]`` (length), y along ``size_m[1]`` (width), z along
    ``size_m[2]`` (height). With zero angles the length lies along the flow. The
    orientation is yaw about z, then pitch about the new y, then roll about the newest x
    (intrinsic z-y'-x''), in degrees.

    Inertia: a closed box with walls ``wall_thickness_m`` thick (uniform material), or
    ``moment_of_inertia_kg_m2`` given (principal, body axes), or neither: a solid box.
    """

    size_m: tuple[Pos, Pos, Pos] = Field(description="[length, width, height] (m)")
    mass_kg: float = Field(gt=0, description="mass (kg)")
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
        DebrisContact(), description="contact law, its energy loss and friction (see DebrisContact)")
    upright: bool | None = Field(
        None,
        description="keep the body upright (it yaws, it does not pitch or roll): v1912 has no bed contact, so a "
        "tipping body digs a corner into the floor. null = upright if it starts on the bed",
    )


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


class DebrisLayout(_Model):
    """A generator of identical bodies on a grid: ``layout: RxC``.

    ``R`` rows follow one another along the flow (x) and ``C`` columns sit side by side
    across it (y); the seed's layouts are ``1x1``, ``3x1`` (three in a line along the
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


class Gauge(_Model):
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


class Fluids(_Model):
    """Water and air properties (defaults: fresh water and air at 20 C)."""

    water_density_kg_m3: float = Field(998.2, gt=0, description="(kg/m3)")
    water_viscosity_m2_s: float = Field(1.0e-6, gt=0, description="kinematic viscosity (m2/s)")
    air_density_kg_m3: float = Field(1.0, gt=0, description="(kg/m3)")
    air_viscosity_m2_s: float = Field(1.48e-5, gt=0, description="kinematic viscosity (m2/s)")
    surface_tension_N_m: float = Field(0.07, ge=0, description="water-air surface tension (N/m)")
    gravity_m_s2: float = Field(9.81, gt=0, description="gravitational acceleration (m/s2)")


class Mesh(_Model):
    """Mesh resolution: the finest cell where the scene needs it, coarser elsewhere."""

    cell_size_m: float = Field(gt=0, description="finest cell size: bed and bore, column, debris path (m)")
    coarsening_ratio: float = Field(4.0, ge=1, description="largest cell / finest cell (-)")
    growth_ratio: float = Field(1.15, gt=1, le=2, description="largest size ratio of neighbouring cells (-)")
    body_cells_across: float = Field(
        4.0, gt=0,
        description="body-mesh cells across the smallest debris dimension (-); with 2 at 4 cm cells the body "
        "mesh drove 12-16 m/s spurious air jets, or (margin 2) had no calculated cell beside the body and the "
        "flow passed it by (docs/openfoam-notes.md)",
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
    trim_domain: bool = Field(
        True,
        description="false: model the whole reservoir, the whole flume to its downstream end and its full height, "
        "as a hand-made set-up would (with coarsening_ratio 1: uniform cells; the speed-error baseline)",
    )


class Run(_Model):
    """Simulated time and solver controls."""

    end_time_s: float = Field(gt=0, description="simulated time from the gate's release (s)")
    cores: int = Field(2, ge=1, description="MPI ranks")
    write_interval_s: float = Field(0.1, gt=0, description="interval between field writes (s)")
    max_courant: float = Field(
        0.9, gt=0, le=5, description="maxCo and maxAlphaCo (-); with debris it also picks the PIMPLE correctors: "
        "<= 1 the careful ones (2 outer, 3 pressure), above 1 the fast ones (1 outer, 2 pressure; "
        "benchmarks/runner_settings.md)")
    max_delta_t_s: float | None = Field(
        None, gt=0, description="largest time step (s); null = min(0.01 s, write interval), which also caps "
                                "the Courant number on coarse meshes")
    stall_limit_s: float | None = Field(
        None, gt=0, description="wall seconds without solver output after which the runner stops the run as "
                                "stalled; null = 600 s (or 20 x the slowest time step, when longer)")
    water_balance_limit: float | None = Field(
        None, gt=0, description="fraction of the initial water a run may create or lose (its water balance, "
                                "results/water_balance.csv) before the runner stops it with a diagnosis; "
                                "null = 0.01, the stability check's 1 % (docs/stability.md)")


class Outputs(_Model):
    """What the run records besides the fields."""

    probe_interval_s: float | None = Field(
        0.01, gt=0, description="sampling interval of gauges and forces; null = every time step (s)"
    )
    fields: tuple[str, ...] = Field(("alpha.water", "U", "p_rgh"), description="fields written at each write "
                                    "interval")
    preview: bool = Field(True, description="draw the scene to preview.png when rendering")


class Scene(_Model):
    """A resolved, validated scene (every body placed, every gauge positioned)."""

    name: str = Field("scene", description="the scene's name (run folders and reports)")
    description: str = Field("", description="one line on what the scene is")
    flume: Flume
    reservoir: Reservoir
    bed: Bed = Bed()
    column: Column | None = None
    debris: tuple[DebrisBody, ...] = ()
    gauges: tuple[Gauge, ...] = ()
    fluids: Fluids = Fluids()
    mesh: Mesh
    run: Run
    outputs: Outputs = Outputs()


# ------------------------------------------------------------------------- helpers


def default_column(x_m: float = 5.0, y_m: float = 0.0) -> Column:
    """The reference study's acrylic column (:class:`analytical.column.Column`'s defaults) at (x_m, y_m).

    0.20 x 0.20 x 0.80 m hollow section, 5 mm wall, E = 2.50 GPa, rho = 1200 kg/m^3,
    nu = 0.375, shear coefficient 0.50, measured 70 Hz, 4.685e5 N/m, damping 0.045.
    The default x (5.0 m) is this project's choice; see cases/1debris.yaml.
    """
    return Column(
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


def column_for_analysis(scene: Scene):
    """The scene's column as an :class:`analytical.column.Column` (structural fields only)."""
    if scene.column is None:
        raise InputError("column", "the scene has no column to analyse")
    from analytical.column import Column as AnalysisColumn  # lazy: analytical is optional here
    import dataclasses
    import inspect

    if dataclasses.is_dataclass(AnalysisColumn):
        names = {f.name for f in dataclasses.fields(AnalysisColumn)}
    else:
        names = set(inspect.signature(AnalysisColumn).parameters)
    values = scene.column.model_dump()
    return AnalysisColumn(**{k: v for k, v in values.items() if k in names})


def flume_extent(scene: Scene) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
    """((x_min, x_max), (y_min, y_max), (z_min, z_max)) of the flume in scene coordinates."""
    x0 = -scene.reservoir.length_m
    x1 = scene.flume.length_m - scene.reservoir.length_m
    w = scene.flume.width_m / 2.0
    return (x0, x1), (-w, w), (0.0, scene.flume.height_m)


def body_rotation(yaw_deg: float, pitch_deg: float, roll_deg: float) -> np.ndarray:
    """3x3 rotation from body axes to scene axes: Rz(yaw) @ Ry(pitch) @ Rx(roll)."""
    y, p, r = (math.radians(a) for a in (yaw_deg, pitch_deg, roll_deg))
    rz = np.array([[math.cos(y), -math.sin(y), 0.0], [math.sin(y), math.cos(y), 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[math.cos(p), 0.0, math.sin(p)], [0.0, 1.0, 0.0], [-math.sin(p), 0.0, math.cos(p)]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, math.cos(r), -math.sin(r)], [0.0, math.sin(r), math.cos(r)]])
    return rz @ ry @ rx


def draft_m(body: DebrisTemplate, water_density_kg_m3: float) -> float:
    """Draft of the upright box afloat (m): its mass over the water its footprint displaces per metre."""
    return body.mass_kg / (water_density_kg_m3 * body.size_m[0] * body.size_m[1])


def half_extent_z(body: DebrisTemplate) -> float:
    """Half the vertical extent of the rotated box (m)."""
    rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
    return float(np.sum(np.abs(rot[2, :]) * np.asarray(body.size_m) / 2.0))


# ------------------------------------------------------------------- error translation


def _dotted(loc: Iterable[Any]) -> str:
    return ".".join(str(p) for p in loc)


def _from_validation_error(err: ValidationError, prefix: Sequence[Any], source: str | None) -> InputError:
    """The first pydantic error as an InputError with the dotted location."""
    errors = err.errors(include_url=False)
    first = errors[0]
    loc = list(first["loc"])
    kind = first["type"]
    short_list = kind == "missing" and loc and isinstance(loc[-1], int)
    if short_list:  # a list with too few items: name the list, not the missing slot
        loc = loc[:-1]
    field = _dotted([*prefix, *loc]) or "scene"
    if kind == "extra_forbidden":
        rule = "unknown key"
    elif short_list:
        rule = f"too few values: item {first['loc'][-1]} is missing"
    elif kind == "missing":
        rule = "required, but missing"
    else:
        rule = f"{first['msg']}, got {first.get('input')!r}"
    if len(errors) > 1:
        rule += f" (and {len(errors) - 1} more problem(s))"
    return InputError(field, rule, source)


def _validate(model: type[_Model], data: Any, prefix: Sequence[Any], source: str | None):
    try:
        return model.model_validate(data)
    except ValidationError as err:
        raise _from_validation_error(err, prefix, source) from None


# ------------------------------------------------------------------------ overrides


def parse_override(text: str) -> tuple[list[str], Any]:
    """``"a.b.c=value"`` -> (["a", "b", "c"], value parsed as a YAML scalar/list)."""
    if "=" not in text:
        raise InputError(text, "an override must look like key.path=value")
    key, _, raw = text.partition("=")
    key = key.strip()
    if not key or any(not part for part in key.split(".")):
        raise InputError(key or text, "an override key must be a dotted path such as mesh.cell_size_m")
    try:
        value = yaml.safe_load(raw) if raw.strip() else None
    except yaml.YAMLError as err:
        raise InputError(key, f"value {raw!r} is not a YAML value: {err}") from None
    return key.split("."), value


def _known_keys(model: type[_Model]) -> set[str]:
    return set(model.model_fields)


def _section_model(path: Sequence[str], container: Any) -> type[_Model] | None:
    """The model that a dict reached by ``path`` is validated with (for unknown-key checks)."""
    top = {
        "flume": Flume,
        "reservoir": Reservoir,
        "bed": Bed,
        "column": Column,
        "fluids": Fluids,
        "mesh": Mesh,
        "run": Run,
        "outputs": Outputs,
    }
    if len(path) == 0:
        return Scene
    if len(path) == 1 and path[0] in top:
        return top[path[0]]
    if len(path) == 2 and path[0] == "debris":
        return DebrisLayout if isinstance(container, dict) and "layout" in container else DebrisBody
    if len(path) == 3 and path[0] == "debris" and path[2] == "body":
        return DebrisTemplate
    if len(path) == 2 and path[0] == "gauges":
        return Gauge
    return None


def apply_overrides(data: dict, overrides: Iterable[str], source: str | None = None) -> dict:
    """A copy of the raw scene mapping with each ``key.path=value`` applied in order.

    Missing sections are created; list items are addressed by index (``debris.0.mass_kg``).
    A key the schema does not know raises InputError naming the key.
    """
    import copy

    data = copy.deepcopy(data)
    for text in overrides:
        try:
            path, value = parse_override(text)
        except InputError as err:
            raise err.with_source(source) if source else err from None
        key = ".".join(path)
        node: Any = data
        for depth, part in enumerate(path):
            last = depth == len(path) - 1
            if isinstance(node, list):
                if not part.lstrip("-").isdigit() or not -len(node) <= int(part) < len(node):
                    raise InputError(key, f"no item {part!r} in a list of {len(node)} (override {text!r})", source)
                idx = int(part)
                if last:
                    node[idx] = value
                else:
                    if node[idx] is None:
                        node[idx] = {}
                    node = node[idx]
                continue
            if not isinstance(node, dict):
                raise InputError(key, f"{'.'.join(path[:depth]) or 'scene'} is not a mapping (override {text!r})", source)
            model = _section_model(path[:depth], node)
            if model is not None and part not in _known_keys(model):
                raise InputError(key, f"unknown key {part!r} (override {text!r})", source)
            if last:
                node[part] = value
            else:
                if node.get(part) is None:
                    node[part] = {}
                node = node[part]
    return data


# ------------------------------------------------------------------------- loading


def read_yaml(path: str | Path, field: str) -> Any:
    """The YAML document in ``path``; InputError (``field``, the file) if unreadable or not YAML."""
    try:
        text = Path(path).read_text()
    except OSError as err:
        raise InputError(field, f"cannot read the file: {err.strerror or err}", str(path)) from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as err:
        raise InputError(field, f"not valid YAML: {err}", str(path)) from None


def load_scene(path: str | Path, overrides: Iterable[str] = ()) -> Scene:
    """Read, override, resolve and validate the scene in ``path``.

    Raises InputError (field = dotted key, source = the file) on any problem: unreadable
    or non-YAML file, unknown keys, out-of-range values, and the cross-field rules
    listed in :func:`validate_scene`.
    """
    source = str(path)
    data = _scene_data(Path(path), "scene", ())
    data.setdefault("name", Path(path).stem)
    overrides = list(overrides)
    data = apply_overrides(data, overrides, source)
    try:
        return scene_from_dict(data, source)
    except InputError as err:
        if any(o.partition("=")[0].strip() and err.field.startswith(o.partition("=")[0].strip()) for o in overrides):
            raise InputError(err.field, f"{err.rule} (value set by an override)", err.source) from None
        raise


def _merged(base: dict, changes: dict) -> dict:
    """``base`` with ``changes`` laid over it: mappings merge key by key, anything else is replaced."""
    out = dict(base)
    for key, value in changes.items():
        out[key] = _merged(out[key], value) if isinstance(value, dict) and isinstance(out.get(key), dict) else value
    return out


def _scene_data(path: Path, field: str, chain: tuple[Path, ...]) -> dict:
    """The raw mapping of a scene file, with ``extends: OTHER.yaml`` resolved.

    A scene may start from another (``extends``, a path relative to its own file): the
    other's sections are the defaults and this file's keys are laid over them (mappings
    merge key by key; lists such as ``debris`` and ``gauges`` are replaced whole). The
    other's ``name`` and ``description`` are not inherited.
    """
    data = read_yaml(path, field)
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise InputError(field, f"must be a mapping of sections, got a {type(data).__name__}", str(path))
    parent = data.pop("extends", None)
    if parent is None:
        return data
    if not isinstance(parent, str) or not parent.strip():
        raise InputError("extends", "must be the path of another scene file, relative to this one", str(path))
    here = path.resolve()
    target = (here.parent / parent).resolve()
    if target in (*chain, here):
        raise InputError("extends", f"{parent} extends this file again (a cycle)", str(path))
    if not target.is_file():
        raise InputError("extends", f"no such scene file: {target}", str(path))
    base = _scene_data(target, "extends", (*chain, here))
    base.pop("name", None)
    base.pop("description", None)
    return _merged(base, data)


def scene_from_dict(data: dict, source: str | None = None) -> Scene:
    """Resolve and validate a raw scene mapping (as read from YAML) into a Scene."""
    if not isinstance(data, dict):
        raise InputError("scene", f"must be a mapping of sections, got a {type(data).__name__}", source)
    data = dict(data)
    raw_debris = data.pop("debris", None)
    raw_gauges = data.pop("gauges", None)
    base = _validate(Scene, data, (), source)

    bodies, origins = _expand_debris(raw_debris, base, source)
    gauges = _resolve_gauges(raw_gauges, base, source)
    scene = base.model_copy(update={"debris": tuple(bodies), "gauges": tuple(gauges)})
    validate_scene(scene, source, origins)
    return scene


def _expand_debris(raw: Any, base: Scene, source: str | None) -> tuple[list[DebrisBody], list[dict]]:
    """Bodies from the raw ``debris`` list; each with where it came from in the YAML."""
    if raw is None:
        return [], []
    if not isinstance(raw, list):
        raise InputError("debris", f"must be a list of bodies or layouts, got {type(raw).__name__}", source)
    bodies: list[DebrisBody] = []
    origins: list[dict] = []
    for i, item in enumerate(raw):
        if not isinstance(item, dict):
            raise InputError(f"debris.{i}", "must be a mapping (a body or a layout)", source)
        if "layout" in item:
            lay = _validate(DebrisLayout, item, ("debris", i), source)
            text = str(lay.layout)
            m = _LAYOUT_RE.match(text)
            if text.strip() == "1":
                rows, cols = 1, 1
            elif m:
                rows, cols = int(m.group(1)), int(m.group(2))
            else:
                raise InputError(f"debris.{i}.layout", f"must look like RxC (e.g. 2x3) or 1, got {text!r}", source)
            if rows < 1 or cols < 1:
                raise InputError(f"debris.{i}.layout", f"needs at least one row and one column, got {text!r}", source)
            if (rows > 1 and lay.spacing_m[0] <= 0) or (cols > 1 and lay.spacing_m[1] <= 0):
                raise InputError(f"debris.{i}.spacing_m", f"must be > 0, got {list(lay.spacing_m)}", source)
            n = 0
            for r in range(rows):
                for c in range(cols):
                    n += 1
                    x = lay.centre_m[0] + (r - (rows - 1) / 2.0) * lay.spacing_m[0]
                    y = lay.centre_m[1] + (c - (cols - 1) / 2.0) * lay.spacing_m[1]
                    fields = lay.body.model_dump()
                    fields.update(name=f"{lay.name_prefix}{n}", centre_m=(x, y))
                    body = _validate(DebrisBody, fields, ("debris", i, "body"), source)
                    bodies.append(_place(body, base, f"debris.{i}", source))
                    origins.append({"path": f"debris.{i}", "layout": True})
        else:
            item = dict(item)
            if "name" not in item:
                item["name"] = f"debris{len(bodies) + 1}"
            body = _validate(DebrisBody, item, ("debris", i), source)
            bodies.append(_place(body, base, f"debris.{i}", source))
            origins.append({"path": f"debris.{i}", "layout": False})
    return bodies, origins


def _place(body: DebrisBody, scene: Scene, path: str, source: str | None) -> DebrisBody:
    """The body with a 3-component centre: z from its placement rule."""
    placement = body.placement or ("given" if len(body.centre_m) == 3 else "on_bed")
    x, y = body.centre_m[0], body.centre_m[1]
    if placement == "given":
        if len(body.centre_m) != 3:
            raise InputError(f"{path}.centre_m", "placement 'given' needs [x, y, z]", source)
        z = body.centre_m[2]
    else:
        half_z = half_extent_z(body)
        z = half_z
        if placement == "floating":
            if abs(body.pitch_deg) > _TOL or abs(body.roll_deg) > _TOL:
                raise InputError(f"{path}.placement", "floating needs pitch_deg = roll_deg = 0", source)
            water = scene.reservoir.depth_m if x < 0 else scene.bed.wet_depth_m
            draft = draft_m(body, scene.fluids.water_density_kg_m3)
            if draft < water:
                z = water - draft + body.size_m[2] / 2.0
    return body.model_copy(update={"centre_m": (float(x), float(y), float(z)), "placement": placement})


def _resolve_gauges(raw: Any, base: Scene, source: str | None) -> list[Gauge]:
    if raw is None:
        return []
    if not isinstance(raw, list):
        raise InputError("gauges", f"must be a list, got {type(raw).__name__}", source)
    out = []
    for i, item in enumerate(raw):
        g = _validate(Gauge, item, ("gauges", i), source)
        if g.at == "column_upstream_face":
            if base.column is None:
                raise InputError(f"gauges.{i}.at", "column_upstream_face needs a column", source)
            col = base.column
            g = g.model_copy(update={"x_m": col.x_m - col.size_x_m / 2.0 - g.offset_m, "y_m": col.y_m})
        elif g.x_m is None or g.y_m is None:
            missing = "x_m" if g.x_m is None else "y_m"
            raise InputError(f"gauges.{i}.{missing}", "required unless `at` places the gauge", source)
        out.append(g)
    return out


# ---------------------------------------------------------------------- validation


def _corners(centre: Sequence[float], rot: np.ndarray, size: Sequence[float]) -> np.ndarray:
    half = np.asarray(size, dtype=float) / 2.0
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    return np.asarray(centre, dtype=float) + (signs * half) @ rot.T


def boxes_overlap(
    c1: Sequence[float], r1: np.ndarray, s1: Sequence[float],
    c2: Sequence[float], r2: np.ndarray, s2: Sequence[float],
    tol: float = _TOL,
) -> bool:
    """Whether two oriented boxes (centre, body->scene rotation, full sizes) share volume.

    Separating-axis test over the 15 candidate axes; boxes that only touch (gap >= -tol)
    do not overlap.
    """
    a = np.asarray(r1, dtype=float)
    b = np.asarray(r2, dtype=float)
    ha = np.asarray(s1, dtype=float) / 2.0
    hb = np.asarray(s2, dtype=float) / 2.0
    d = np.asarray(c2, dtype=float) - np.asarray(c1, dtype=float)
    axes = [a[:, i] for i in range(3)] + [b[:, i] for i in range(3)]
    for i in range(3):
        for j in range(3):
            cross = np.cross(a[:, i], b[:, j])
            norm = np.linalg.norm(cross)
            if norm > 1e-9:
                axes.append(cross / norm)
    for axis in axes:
        ra = np.sum(ha * np.abs(a.T @ axis))
        rb = np.sum(hb * np.abs(b.T @ axis))
        if abs(float(d @ axis)) >= ra + rb - tol:
            return False
    return True


def validate_scene(scene: Scene, source: str | None = None, origins: Sequence[dict] | None = None) -> None:
    """The cross-field rules; raises the first broken one as an InputError.

    Rules: reservoir shorter than the flume; impoundment not above the flume walls; wet
    bed shallower than the impoundment; column inside the flume; every body inside the
    flume, clear of the column and of every other body; unique OpenFOAM-safe body names;
    body wall thinner than half its smallest dimension; gauges inside the flume and not
    inside the column; ``mesh.cell_size_m`` fine enough for the impoundment, the column
    and the debris; ``mesh.top_m`` between the impoundment and the flume height.
    """
    fl, res, bed, col = scene.flume, scene.reservoir, scene.bed, scene.column
    (x0, x1), (y0, y1), (_, z1) = flume_extent(scene)

    if res.length_m >= fl.length_m - _TOL:
        raise InputError(
            "reservoir.length_m",
            f"must be shorter than the flume ({fl.length_m:g} m) so water has somewhere to go, got {res.length_m:g}",
            source,
        )
    if res.depth_m > fl.height_m + _TOL:
        raise InputError(
            "reservoir.depth_m",
            f"impoundment {res.depth_m:g} m is above the flume walls ({fl.height_m:g} m)",
            source,
        )
    if bed.wet_depth_m >= res.depth_m:
        raise InputError(
            "bed.wet_depth_m",
            f"must be shallower than the impoundment ({res.depth_m:g} m) for a dam break, got {bed.wet_depth_m:g}",
            source,
        )

    if col is not None:
        if col.x_m - col.size_x_m / 2 < x0 - _TOL or col.x_m + col.size_x_m / 2 > x1 + _TOL:
            raise InputError(
                "column.x_m",
                f"column spans x = {col.x_m - col.size_x_m / 2:g}..{col.x_m + col.size_x_m / 2:g} m, outside the "
                f"flume ({x0:g}..{x1:g} m)",
                source,
            )
        if col.y_m - col.size_y_m / 2 < y0 - _TOL or col.y_m + col.size_y_m / 2 > y1 + _TOL:
            raise InputError(
                "column.y_m",
                f"column spans y = {col.y_m - col.size_y_m / 2:g}..{col.y_m + col.size_y_m / 2:g} m, outside the "
                f"flume ({y0:g}..{y1:g} m)",
                source,
            )
        if 2 * col.wall_thickness_m > min(col.size_x_m, col.size_y_m) + _TOL:
            raise InputError(
                "column.wall_thickness_m",
                f"must be at most half the smaller side ({min(col.size_x_m, col.size_y_m) / 2:g} m), "
                f"got {col.wall_thickness_m:g}",
                source,
            )

    origins = list(origins) if origins is not None else [
        {"path": f"debris.{i}", "layout": False} for i in range(len(scene.debris))
    ]
    names: dict[str, int] = {}
    placed = []
    for i, body in enumerate(scene.debris):
        path = origins[i]["path"]
        pos_field = f"{path}.centre_m"
        if not _NAME_RE.match(body.name):
            raise InputError(f"{path}.name", f"{body.name!r} is not an identifier (letters, digits, _)", source)
        if body.name in names or (col is not None and body.name == "column"):
            raise InputError(
                f"{path}.name" if not origins[i]["layout"] else f"{path}.name_prefix",
                f"body name {body.name!r} is used twice",
                source,
            )
        names[body.name] = i
        if body.wall_thickness_m is not None and body.moment_of_inertia_kg_m2 is not None:
            raise InputError(
                f"{path}.moment_of_inertia_kg_m2",
                "give wall_thickness_m or moment_of_inertia_kg_m2, not both",
                source,
            )
        t_field = f"{path}.body.wall_thickness_m" if origins[i]["layout"] else f"{path}.wall_thickness_m"
        if body.wall_thickness_m is not None and 2 * body.wall_thickness_m >= min(body.size_m):
            raise InputError(
                t_field,
                f"must be less than half the smallest dimension ({min(body.size_m) / 2:g} m), got "
                f"{body.wall_thickness_m:g}",
                source,
            )
        if min(body.size_m) <= 0:
            k = int(np.argmin(body.size_m))
            size_field = f"{path}.body.size_m" if origins[i]["layout"] else f"{path}.size_m"
            raise InputError(f"{size_field}.{k}", f"must be > 0, got {body.size_m[k]:g}", source)
        if body.moment_of_inertia_kg_m2 is not None and min(body.moment_of_inertia_kg_m2) <= 0:
            raise InputError(
                f"{path}.moment_of_inertia_kg_m2",
                f"principal moments must be > 0, got {list(body.moment_of_inertia_kg_m2)}",
                source,
            )
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
        corners = _corners(body.centre_m, rot, body.size_m)
        lo, hi = corners.min(axis=0), corners.max(axis=0)
        if lo[0] < x0 - _TOL or hi[0] > x1 + _TOL or lo[1] < y0 - _TOL or hi[1] > y1 + _TOL or lo[2] < -1e-7 or hi[2] > z1 + _TOL:
            raise InputError(
                pos_field,
                f"body {body.name!r} spans x {lo[0]:.4g}..{hi[0]:.4g}, y {lo[1]:.4g}..{hi[1]:.4g}, "
                f"z {lo[2]:.4g}..{hi[2]:.4g} m: outside the flume (x {x0:g}..{x1:g}, y {y0:g}..{y1:g}, "
                f"z 0..{z1:g} m)",
                source,
            )
        if col is not None and boxes_overlap(
            body.centre_m, rot, body.size_m, (col.x_m, col.y_m, col.height_m / 2), np.eye(3),
            (col.size_x_m, col.size_y_m, col.height_m),
        ):
            raise InputError(pos_field, f"body {body.name!r} overlaps the column", source)
        for j, (other, orot) in enumerate(placed):
            if boxes_overlap(body.centre_m, rot, body.size_m, other.centre_m, orot, other.size_m):
                same_layout = origins[i]["layout"] and origins[j]["path"] == path
                raise InputError(
                    f"{path}.spacing_m" if same_layout else pos_field,
                    f"body {body.name!r} overlaps body {other.name!r}",
                    source,
                )
        placed.append((body, rot))

    for i, g in enumerate(scene.gauges):
        if not _NAME_RE.match(g.name):
            raise InputError(f"gauges.{i}.name", f"{g.name!r} is not an identifier (letters, digits, _)", source)
        if any(other.name == g.name for other in scene.gauges[:i]):
            raise InputError(f"gauges.{i}.name", f"gauge name {g.name!r} is used twice", source)
        if not x0 - _TOL <= g.x_m <= x1 + _TOL:
            raise InputError(f"gauges.{i}.x_m", f"gauge {g.name!r} at x = {g.x_m:g} m is outside the flume ({x0:g}..{x1:g} m)", source)
        if not y0 - _TOL <= g.y_m <= y1 + _TOL:
            raise InputError(f"gauges.{i}.y_m", f"gauge {g.name!r} at y = {g.y_m:g} m is outside the flume ({y0:g}..{y1:g} m)", source)
        if col is not None and abs(g.x_m - col.x_m) < col.size_x_m / 2 - _TOL and abs(g.y_m - col.y_m) < col.size_y_m / 2 - _TOL:
            raise InputError(f"gauges.{i}.x_m", f"gauge {g.name!r} is inside the column", source)

    mesh = scene.mesh
    h = mesh.cell_size_m
    if h > res.depth_m / MIN_CELLS_OVER_DEPTH + _TOL:
        raise InputError(
            "mesh.cell_size_m",
            f"{h:g} m cannot resolve the impoundment: at least {MIN_CELLS_OVER_DEPTH:g} cells over "
            f"reservoir.depth_m ({res.depth_m:g} m) needs <= {res.depth_m / MIN_CELLS_OVER_DEPTH:g} m",
            source,
        )
    if col is not None:
        side = min(col.size_x_m, col.size_y_m)
        if h > side / MIN_CELLS_ACROSS_COLUMN + _TOL:
            raise InputError(
                "mesh.cell_size_m",
                f"{h:g} m cannot resolve the column: at least {MIN_CELLS_ACROSS_COLUMN:g} cells across its "
                f"{side:g} m side needs <= {side / MIN_CELLS_ACROSS_COLUMN:g} m",
                source,
            )
    for body in scene.debris:
        small = min(body.size_m)
        if h > small / MIN_CELLS_ACROSS_DEBRIS + _TOL:
            raise InputError(
                "mesh.cell_size_m",
                f"{h:g} m cannot resolve debris {body.name!r}: at least {MIN_CELLS_ACROSS_DEBRIS:g} cells across "
                f"its smallest dimension ({small:g} m) needs <= {small / MIN_CELLS_ACROSS_DEBRIS:.4g} m "
                "(else a body may cut no hole in the background mesh)",
                source,
            )
    if mesh.top_m is not None:
        for i, body in enumerate(scene.debris):
            rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
            top = float(_corners(body.centre_m, rot, body.size_m)[:, 2].max())
            if top > mesh.top_m + _TOL:
                raise InputError(
                    "mesh.top_m",
                    f"{mesh.top_m:g} m is below the top of body {body.name!r} ({top:.4g} m)",
                    source,
                )
    if mesh.top_m is not None and not res.depth_m < mesh.top_m <= fl.height_m + _TOL:
        raise InputError(
            "mesh.top_m",
            f"must be above the impoundment ({res.depth_m:g} m) and at most the flume height ({fl.height_m:g} m), "
            f"got {mesh.top_m:g}",
            source,
        )


# ------------------------------------------------------------------------- output


def scene_to_dict(scene: Scene) -> dict:
    """The resolved scene as plain data (lists, numbers, strings): reloadable as-is."""
    return scene.model_dump(mode="json")


def dump_scene_yaml(scene: Scene, overrides: Sequence[str] = ()) -> str:
    """The resolved scene as YAML, headed by the overrides that produced it."""
    head = "# Resolved scene written by debrisfoam: layouts expanded, bodies and gauges placed.\n"
    if overrides:
        head += "# Overrides applied: " + " ".join(overrides) + "\n"
    return head + yaml.safe_dump(scene_to_dict(scene), sort_keys=False, default_flow_style=None)
