"""The numbers a case's dictionaries need beyond the grids, decided once for the plan.

From the background grid and the water: the bed's first cell layer, the smallest first
cell, the still water downstream (the case's hRef) and the top of the bed-friction zone
above it with its drag coefficient, the deepest water, the column's box, the first time step
and its cap, the gauges' lines and the probes, the bodies' motion distances
(:mod:`~orchestrator.plan.sampling`). The renderer writes them as they are
(:class:`orchestrator.plan.model.ModelPlan` fields).
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from orchestrator.plan.grading import COLUMN_PATCH, cell_edges, min_cell_m
from orchestrator.plan.grid import BoxGrid, Segment
from orchestrator.plan.model import GaugePlan, WaterBox
from orchestrator.plan.sampling import bed_friction_per_m, motion_distance_m, sampling
from orchestrator.plan.timestep import first_delta_t_s, max_delta_t_s

__all__ = ["WET_BED", "case_numbers", "column_box_m", "friction_layer_top_m"]

#: The water box of the still water downstream of the gate.
WET_BED = "wetBed"


def friction_layer_top_m(z_segments: tuple[Segment, ...], still_water_m: float) -> float:
    """Height above the bed of the bed-friction zone's top: the cell layers from the bed up to
    the first layer whose top lies above the still water downstream (still_water_m, m above the
    bed; 0 on a dry bed).

    On a dry bed that is the first cell layer. A wet bed filling its own layers stays almost
    still under a laminar bore, which runs over it in the layer above (no turbulence couples
    them); drag on the still layers alone would never reach the bore (docs/bed-friction.md).
    """
    edges = cell_edges(z_segments) - z_segments[0].start_m
    above = edges[edges > still_water_m + 1e-9]
    return float(above[0]) if above.size else float(edges[-1])


def column_box_m(grid: BoxGrid) -> tuple[tuple[float, ...], tuple[float, ...]] | None:
    """(min, max) corners of the union of the grid's holes in scene coordinates, when the holes
    are the column; None otherwise."""
    column = [h for h in grid.holes if h not in grid.hole_sides]  # not the gate's sill and walls
    if not column or grid.patch_names.get("hole", "hole") != COLUMN_PATCH:
        return None
    xs, ys, zs = grid.planes("x"), grid.planes("y"), grid.planes("z")
    lo = np.array([[xs[i], ys[j], zs[k]] for i, j, k in column]).min(axis=0)
    hi = np.array([[xs[i + 1], ys[j + 1], zs[k + 1]] for i, j, k in column]).max(axis=0)
    c_lo, c_hi = (v @ np.asarray(grid.rotation).T + np.asarray(grid.origin) for v in (lo, hi))
    return tuple(float(v) for v in c_lo), tuple(float(v) for v in c_hi)


def case_numbers(background: BoxGrid, water: Sequence[WaterBox], gauges: Sequence[GaugePlan], *, two_d: bool,
                 max_courant: float, write_interval_s: float, max_delta_t: float | None, gravity_m_s2: float,
                 bed_friction_factor: float, bed_friction_calibration: float,
                 record_interval_s: float | None = None) -> dict[str, Any]:
    """The ModelPlan fields of this module's docstring (keyword arguments of ModelPlan).

    ``max_delta_t``: the scene's run.max_delta_t_s (None: the default cap); ``record_interval_s``:
    the one-way flow record's frame interval (None: no record).
    """
    # the bed downstream of the gate is z = 0; a sill puts the reservoir's floor below it
    above_bed = tuple(seg for seg in background.z if seg.start_m >= -1e-12)
    z0, z1 = background.planes("z")[0], background.planes("z")[-1]
    bed_cell = above_bed[0].cell_sizes_m()[0]
    min_cell = min(min_cell_m(background.x), min_cell_m(background.y) if not two_d else np.inf, bed_cell)
    depth = max((box.max_m[2] - z0 for box in water), default=z1 - z0)
    still = max((box.max_m[2] for box in water if box.name == WET_BED), default=0.0)
    layer = friction_layer_top_m(above_bed, still)
    column = column_box_m(background)
    lines, probes = sampling(background, gauges, two_d=two_d, bed_cell_m=float(bed_cell), min_cell_m=float(min_cell),
                             water_depth_m=float(depth), column_box_m=column)
    return {
        "bed_cell_m": float(bed_cell),
        "min_cell_m": float(min_cell),
        "still_water_m": float(still),
        "friction_layer_m": layer,
        "water_depth_m": float(depth),
        "column_box_m": column,
        "first_delta_t_s": first_delta_t_s(max_courant, min_cell, depth, gravity_m_s2),
        "max_delta_t_s": max_delta_t_s(max_delta_t, write_interval_s, float(depth), record_interval_s),
        "gauge_lines": lines,
        "probes": probes,
        "bed_friction_per_m": bed_friction_per_m(bed_friction_factor, bed_friction_calibration, layer),
        "motion_distance_m": motion_distance_m(background),
    }
