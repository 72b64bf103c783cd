"""The plan of a case: what the planner decided, as plain frozen dataclasses.

:class:`ModelPlan` is the contract between the planner (which decides every number) and
the renderer (which only formats it). ``ModelPlan.to_json()`` is the case's plan.json;
:meth:`ModelPlan.from_json` reads it back into an equal plan (the estimated wall time is
written to 0.1 s). Lengths in m, times in s, masses in kg.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any, Literal

from orchestrator.core.errors import InputError
from orchestrator.plan.grid import BoxGrid, Segment

__all__ = ["BodyPlan", "FlowRecordPlan", "GateBand", "GaugeLine", "GaugePlan", "ModelPlan", "Probe", "WaterBox", "grid_from_dict",
           "grid_to_dict"]

Vector = tuple[float, float, float]
Box = tuple[Vector, Vector]


@dataclass(frozen=True)
class WaterBox:
    """An axis-aligned box to fill with water (setFields boxToCell), corners in m."""

    name: str
    min_m: Vector
    max_m: Vector


@dataclass(frozen=True)
class GaugePlan:
    """A wave gauge: a vertical sampling line at (x, y) from the bed to z_top (m)."""

    name: str
    x: float
    y: float
    z_top: float


@dataclass(frozen=True)
class GaugeLine:
    """A gauge's sampling line in the case: ``n_points`` evenly from ``start_m`` to ``end_m``."""

    name: str
    start_m: Vector
    end_m: Vector
    n_points: int


@dataclass(frozen=True)
class GateBand:
    """A horizontal band of the gate's cells (a box of cell centres, m), blocked from the start
    until ``release_s`` (s): a lifting gate as a staircase of porous bands."""

    name: str
    min_m: Vector
    max_m: Vector
    release_s: float


@dataclass(frozen=True)
class Probe:
    """A point where the case samples the fields (p, p_rgh, alpha.water, U)."""

    name: str
    point_m: Vector


@dataclass(frozen=True)
class FlowRecordPlan:
    """The flow a one-way run records for its bodies: alpha.water and U on a regular grid.

    ``x_m``, ``y_m``: evenly spaced sample positions along and across the flume; ``z_m``: the
    background's cell centres from the bed to ``z_faces_m[-1]``, between the faces
    ``z_faces_m`` (so each sample is its cell's value and the water column is
    ``sum(alpha dz)``, as the gauges integrate it). One frame every ``interval_s``, written
    by the ``sets`` function object ``name`` to ``postProcessing/<name>/``.
    ``bodies_region_m``: ((x0, x1), (y0, y1)) of the bodies' footprints at the start, which
    the record must cover.
    """

    name: str
    interval_s: float
    x_m: tuple[float, ...]
    y_m: tuple[float, ...]
    z_m: tuple[float, ...]
    z_faces_m: tuple[float, ...]
    bodies_region_m: tuple[tuple[float, float], tuple[float, float]]

    @property
    def points(self) -> int:
        """Sample points per frame (those inside the column's hole included)."""
        return len(self.x_m) * len(self.y_m) * len(self.z_m)

    @property
    def region_m(self) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
        """((x0, x1), (y0, y1), (bed, top)) the record spans."""
        return ((self.x_m[0], self.x_m[-1]), (self.y_m[0], self.y_m[-1]), (self.z_faces_m[0], self.z_faces_m[-1]))

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "interval_s": self.interval_s, "points": self.points,
                "region_m": [list(a) for a in self.region_m], "x_m": list(self.x_m), "y_m": list(self.y_m),
                "z_m": list(self.z_m), "z_faces_m": list(self.z_faces_m),
                "bodies_region_m": [list(a) for a in self.bodies_region_m]}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "FlowRecordPlan":
        return cls(data["name"], data["interval_s"], tuple(data["x_m"]), tuple(data["y_m"]), tuple(data["z_m"]),
                   tuple(data["z_faces_m"]), _pairs(data["bodies_region_m"]))


@dataclass(frozen=True)
class BodyPlan:
    """One six-DoF debris body on its own overset mesh.

    ``grid`` is in body coordinates (centred on the body, axes along its length, width,
    height) and placed by its ``origin`` (the centre of mass) and ``rotation``
    (= ``orientation``). Patches: every outer side ``<name>Overset``, the body ``<name>``.
    ``moment_of_inertia_kg_m2`` are the principal moments about the body axes through
    the centre of mass; ``orientation`` maps body axes to scene axes (columns = body axes).
    """

    name: str
    grid: BoxGrid
    mass_kg: float
    centre_of_mass_m: Vector
    moment_of_inertia_kg_m2: Vector
    orientation: tuple[Vector, ...]
    size_m: Vector
    on_bed: bool = False
    cell_size_m: float = 0.0
    velocity_m_s: Vector = (0.0, 0.0, 0.0)
    #: > 0: the body is held on the bed (sixDoF constraints: it slides and yaws, but cannot
    #: sink or tip) until this time, when the bore is deep enough to lift it (s)
    hold_until_s: float = 0.0
    #: the body may only yaw (a sixDoF `axis` constraint, for the whole run)
    upright: bool = False

    def to_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "mass_kg": self.mass_kg,
            "centre_of_mass_m": list(self.centre_of_mass_m),
            "moment_of_inertia_kg_m2": list(self.moment_of_inertia_kg_m2),
            "orientation": [list(r) for r in self.orientation],
            "size_m": list(self.size_m),
            "on_bed": self.on_bed,
            "hold_until_s": self.hold_until_s,
            "cell_size_m": self.cell_size_m,
            "velocity_m_s": list(self.velocity_m_s),
            "upright": self.upright,
            "grid": grid_to_dict(self.grid),
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "BodyPlan":
        return cls(
            name=data["name"],
            grid=grid_from_dict(data["grid"]),
            mass_kg=data["mass_kg"],
            centre_of_mass_m=_vector(data["centre_of_mass_m"]),
            moment_of_inertia_kg_m2=_vector(data["moment_of_inertia_kg_m2"]),
            orientation=tuple(_vector(r) for r in data["orientation"]),
            size_m=_vector(data["size_m"]),
            on_bed=data["on_bed"],
            cell_size_m=data["cell_size_m"],
            velocity_m_s=_vector(data["velocity_m_s"]),
            hold_until_s=data["hold_until_s"],
            upright=data["upright"],
        )


@dataclass(frozen=True)
class ModelPlan:
    """What the case will model. Lengths m, times s; ``reasons`` says why for each choice.

    Beside the grids, the plan holds every number the case's dictionaries need, so the
    renderer only formats: the bed's first cell layer (``bed_cell_m``), the smallest first
    cell (``min_cell_m``), the still water downstream (``still_water_m``, the case's hRef)
    and the top of the bed-friction zone above it (``friction_layer_m``), the deepest water
    (``water_depth_m``), the column's box in scene coordinates (``column_box_m``), the first
    time step and the largest one (``first_delta_t_s``, ``max_delta_t_s``), the gauges' sampling
    lines and the probes (``gauge_lines``, ``probes``), the bed friction's Forchheimer
    coefficient (``bed_friction_per_m``) and the overset bodies' motion distances
    (``motion_distance_m``).
    """

    scene_name: str
    solver: Literal["interFoam", "overInterDyMFoam"]
    two_d: bool
    background: BoxGrid
    bodies: tuple[BodyPlan, ...]
    water: tuple[WaterBox, ...]
    gauges: tuple[GaugePlan, ...]
    cell_count: int
    decomposition: tuple[int, int, int]
    end_time_s: float
    write_interval_s: float
    max_courant: float
    domain_m: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    fine_region_m: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    downstream_type: Literal["wall", "outlet"]
    bed_friction_factor: float
    velocity_scale_m_s: float
    time_step_estimate_s: float
    reasons: dict[str, str]
    warnings: tuple[str, ...] = ()
    estimated_wall_time_s: float = field(default=0.0)
    #: multiplier on the bed-friction drag coefficient (scene bed.friction_calibration)
    bed_friction_calibration: float = 1.0
    #: the runner's stall limit (scene run.stall_limit_s; None: the runner's default)
    stall_limit_s: float | None = None
    #: the runner's water-balance stop (scene run.water_balance_limit; None: the runner's default)
    water_balance_limit: float | None = None
    #: height of the water gap under bodies resting on the bed (BedGap; 0: none rests)
    bed_gap_m: float = 0.0
    #: height of the background's first cell layer above the bed
    bed_cell_m: float = field(kw_only=True)
    #: the smallest first cell of the background along x, y (3D only) and at the bed
    min_cell_m: float = field(kw_only=True)
    #: the still water's surface downstream of the gate above the bed (0: dry bed): hRef
    still_water_m: float = field(kw_only=True)
    #: top of the bed-friction zone above the bed (plan.setup.friction_layer_top_m)
    friction_layer_m: float = field(kw_only=True)
    #: the highest water surface above the bed at the start
    water_depth_m: float = field(kw_only=True)
    #: (min, max) corners of the column's hole in the background, scene coordinates; None: no column
    column_box_m: Box | None = field(kw_only=True)
    #: the first time step (deltaT)
    first_delta_t_s: float = field(kw_only=True)
    #: the largest time step the case allows (maxDeltaT)
    max_delta_t_s: float = field(kw_only=True)
    #: each gauge's sampling line (bed to top, a hair inside the mesh)
    gauge_lines: tuple[GaugeLine, ...] = field(kw_only=True)
    #: the probes: the bed under each gauge, up the column's upstream face
    probes: tuple[Probe, ...] = field(kw_only=True)
    #: the Forchheimer coefficient F (1/m) of the bed-friction zone (0: no bed friction)
    bed_friction_per_m: float = field(kw_only=True)
    #: (inner, outer) distance of the six-DoF motion's point displacement from each body
    motion_distance_m: tuple[float, float] = field(kw_only=True)
    #: how the debris meets the flow: "none" (no debris), "two-way" (the bodies on overset
    #: meshes in the flow) or "one-way" (the flow without them, recorded in ``flow_record``)
    debris_coupling: Literal["none", "one-way", "two-way"] = field(default="none", kw_only=True)
    #: the flow record of a one-way plan (None otherwise)
    flow_record: FlowRecordPlan | None = field(default=None, kw_only=True)
    #: the flow's closure (scene fluids.turbulence): "laminar" or "kOmegaSST"
    turbulence: Literal["laminar", "kOmegaSST"] = field(default="laminar", kw_only=True)
    #: the bed's Nikuradse sand roughness k_s for the RANS wall function (m; 0: smooth or laminar)
    bed_roughness_m: float = field(default=0.0, kw_only=True)
    #: the bed a slip wall (scene bed.slip: a frictionless bed, no shear); False = no-slip
    bed_slip: bool = field(default=False, kw_only=True)
    #: the gate's bands, bottom up, when it opens over a time (scene reservoir.opening_time_s; none: at once)
    gate_bands: tuple[GateBand, ...] = field(default=(), kw_only=True)

    def __post_init__(self) -> None:
        for i, box in enumerate(self.water):
            if not all(hi > lo for lo, hi in zip(box.min_m, box.max_m)):
                raise InputError(f"plan.water.{i}", f"box max {tuple(box.max_m)} must exceed min {tuple(box.min_m)}")
        if (self.debris_coupling == "one-way") != (self.flow_record is not None):
            raise InputError("plan.flow_record", "a one-way plan, and only a one-way plan, records the flow")
        if self.debris_coupling == "one-way" and self.bodies:
            raise InputError("plan.bodies", "a one-way plan models no bodies in the flow")
        n = tuple(self.decomposition)
        if len(n) != 3 or min(n) < 1:
            raise InputError("plan.decomposition", f"hierarchical n must be 3 counts >= 1, got {n}")

    @property
    def cores(self) -> int:
        nx, ny, nz = self.decomposition
        return nx * ny * nz

    def to_dict(self) -> dict[str, Any]:
        return {
            "scene_name": self.scene_name,
            "solver": self.solver,
            "two_d": self.two_d,
            "cell_count": self.cell_count,
            "estimated_wall_time_s": round(self.estimated_wall_time_s, 1),
            "time_step_estimate_s": self.time_step_estimate_s,
            "velocity_scale_m_s": self.velocity_scale_m_s,
            "decomposition": {"method": "hierarchical", "n": list(self.decomposition)},
            "end_time_s": self.end_time_s,
            "write_interval_s": self.write_interval_s,
            "max_courant": self.max_courant,
            "domain_m": [list(a) for a in self.domain_m],
            "fine_region_m": [list(a) for a in self.fine_region_m],
            "downstream_type": self.downstream_type,
            "bed_friction_factor": self.bed_friction_factor,
            "bed_friction_calibration": self.bed_friction_calibration,
            "stall_limit_s": self.stall_limit_s,
            "water_balance_limit": self.water_balance_limit,
            "bed_gap_m": self.bed_gap_m,
            "bed_cell_m": self.bed_cell_m,
            "min_cell_m": self.min_cell_m,
            "still_water_m": self.still_water_m,
            "friction_layer_m": self.friction_layer_m,
            "water_depth_m": self.water_depth_m,
            "column_box_m": None if self.column_box_m is None else [list(c) for c in self.column_box_m],
            "first_delta_t_s": self.first_delta_t_s,
            "max_delta_t_s": self.max_delta_t_s,
            "bed_friction_per_m": self.bed_friction_per_m,
            "motion_distance_m": list(self.motion_distance_m),
            "gauge_lines": [{"name": g.name, "start_m": list(g.start_m), "end_m": list(g.end_m), "n_points": g.n_points}
                            for g in self.gauge_lines],
            "probes": [{"name": p.name, "point_m": list(p.point_m)} for p in self.probes],
            "debris_coupling": self.debris_coupling,
            "flow_record": None if self.flow_record is None else self.flow_record.to_dict(),
            "turbulence": self.turbulence,
            "bed_roughness_m": self.bed_roughness_m,
            "bed_slip": self.bed_slip,
            "gate_bands": [{"name": b.name, "min_m": list(b.min_m), "max_m": list(b.max_m), "release_s": b.release_s}
                           for b in self.gate_bands],
            "background": grid_to_dict(self.background),
            "bodies": [b.to_dict() for b in self.bodies],
            "water": [{"name": w.name, "min_m": list(w.min_m), "max_m": list(w.max_m)} for w in self.water],
            "gauges": [{"name": g.name, "x": g.x, "y": g.y, "z_top": g.z_top} for g in self.gauges],
            "reasons": dict(self.reasons),
            "warnings": list(self.warnings),
        }

    def to_json(self) -> str:
        """plan.json: every choice, the grids and a reason for each decision."""
        return json.dumps(self.to_dict(), indent=2)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> "ModelPlan":
        """The plan of :meth:`to_dict`; InputError naming the first missing key (a plan.json
        written before the key existed)."""
        try:
            return cls(
                **{k: data[k] for k in _PLAIN_KEYS},
                decomposition=tuple(data["decomposition"]["n"]),
                domain_m=_pairs(data["domain_m"]),
                fine_region_m=_pairs(data["fine_region_m"]),
                column_box_m=None if data["column_box_m"] is None else tuple(_vector(c) for c in data["column_box_m"]),
                background=grid_from_dict(data["background"]),
                bodies=tuple(BodyPlan.from_dict(b) for b in data["bodies"]),
                water=tuple(WaterBox(w["name"], _vector(w["min_m"]), _vector(w["max_m"])) for w in data["water"]),
                gauges=tuple(GaugePlan(g["name"], g["x"], g["y"], g["z_top"]) for g in data["gauges"]),
                # what only the renderer used: a plan.json written before the plan held it has none,
                # and a case's readers (post, transport) do not need it
                gauge_lines=tuple(GaugeLine(g["name"], _vector(g["start_m"]), _vector(g["end_m"]), g["n_points"])
                                  for g in data.get("gauge_lines", ())),
                probes=tuple(Probe(p["name"], _vector(p["point_m"])) for p in data.get("probes", ())),
                motion_distance_m=tuple(data.get("motion_distance_m", (0.0, 0.0))),
                bed_friction_per_m=data.get("bed_friction_per_m", 0.0),
                reasons=dict(data["reasons"]),
                warnings=tuple(data["warnings"]),
                # plan.json written before the coupling choice: bodies meant the overset path
                debris_coupling=data.get("debris_coupling", "two-way" if data["bodies"] else "none"),
                turbulence=data.get("turbulence", "laminar"),
                bed_roughness_m=data.get("bed_roughness_m", 0.0),
                bed_slip=bool(data.get("bed_slip", False)),
                gate_bands=tuple(GateBand(b["name"], _vector(b["min_m"]), _vector(b["max_m"]), float(b["release_s"]))
                                 for b in data.get("gate_bands", ())),
                flow_record=None if data.get("flow_record") is None else FlowRecordPlan.from_dict(data["flow_record"]),
            )
        except KeyError as missing:
            raise InputError("plan.json", f"has no {missing.args[0]!r} (written by an older debrisfoam?)") from None

    @classmethod
    def from_json(cls, text: str) -> "ModelPlan":
        """The plan written as plan.json (:meth:`to_json`)."""
        return cls.from_dict(json.loads(text))


#: ModelPlan fields that plan.json holds as they are.
_PLAIN_KEYS = (
    "scene_name", "solver", "two_d", "cell_count", "estimated_wall_time_s", "time_step_estimate_s",
    "velocity_scale_m_s", "end_time_s", "write_interval_s", "max_courant", "downstream_type",
    "bed_friction_factor", "bed_friction_calibration", "stall_limit_s", "water_balance_limit", "bed_gap_m",
    "bed_cell_m", "min_cell_m", "still_water_m", "friction_layer_m", "water_depth_m", "first_delta_t_s",
    "max_delta_t_s",
)


def grid_to_dict(grid: BoxGrid) -> dict[str, Any]:
    """A BoxGrid as plan.json holds it (with its cell count, for readers)."""

    def segs(axis):
        return [
            {"start_m": s.start_m, "end_m": s.end_m, "cells": s.cells, "grading": s.grading}
            for s in getattr(grid, axis)
        ]

    return {
        "name": grid.name,
        "cell_count": grid.cell_count(),
        "x": segs("x"),
        "y": segs("y"),
        "z": segs("z"),
        "holes": sorted(list(h) for h in grid.holes),
        "patch_names": dict(grid.patch_names),
        "hole_sides": [[*h, side] for h, side in sorted(grid.hole_sides.items())],
        "origin": list(grid.origin),
        "rotation": [list(r) for r in grid.rotation],
    }


def grid_from_dict(data: dict[str, Any]) -> BoxGrid:
    """The BoxGrid of :func:`grid_to_dict`."""

    def segs(axis):
        return tuple(Segment(s["start_m"], s["end_m"], s["cells"], s["grading"]) for s in data[axis])

    return BoxGrid(
        data["name"], segs("x"), segs("y"), segs("z"),
        holes=frozenset(tuple(h) for h in data["holes"]),
        patch_names=dict(data["patch_names"]),
        hole_sides={tuple(h[:3]): h[3] for h in data.get("hole_sides", [])},
        origin=_vector(data["origin"]),
        rotation=tuple(_vector(r) for r in data["rotation"]),
    )


def _vector(values) -> Vector:
    return tuple(values)


def _pairs(values) -> tuple[tuple[float, float], ...]:
    return tuple(tuple(v) for v in values)
