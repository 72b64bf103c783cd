"""A gate that opens over a time: ``reservoir.opening_time_s`` (T) on a swing gate.

The gate is modelled as lifting from the reservoir's floor at a constant rate, clearing the
impoundment's depth H (the level above the bed downstream plus the sill) in T. The cells just
upstream of the gate (x = 0) are cut into bands, one per cell layer below the impoundment
level; system/fvOptions blocks each with a Darcy-Forchheimer porosity (:data:`BLOCK_F_PER_M`)
until the gate's edge passes the band's top: a layer whose top stands z' above the floor opens
at T z' / H. The bands are a staircase of the lift one cell layer high, and the gate's plate is
the cell column's width. How the study's swing gate moved is not in the study; the scene says
what it assumes (docs/bed-friction.md).
"""

from __future__ import annotations

from orchestrator.plan.grading import cell_edges
from orchestrator.plan.grid import Segment
from orchestrator.plan.model import GateBand
from orchestrator.scene.schema import Scene

__all__ = ["BLOCK_F_PER_M", "gate_bands"]

#: The Forchheimer coefficient F (1/m) of a closed band: its drag rho F |U| U / 2 holds the
#: impoundment's head rho g H across one cell dx with a leak of sqrt(2 g H / (F dx)), 4 mm/s
#: for 0.4 m over 4 cm cells.
BLOCK_F_PER_M = 1.0e7


def gate_bands(scene: Scene, xs: tuple[Segment, ...], zs: tuple[Segment, ...],
               y_span_m: tuple[float, float]) -> tuple[GateBand, ...]:
    """The gate's bands, bottom up (none when the gate opens at once): the cell column just
    upstream of x = 0 across ``y_span_m``, one band per cell layer of ``zs`` below the level."""
    res = scene.reservoir
    if res.opening_time_s <= 0:
        return ()
    x_edges = cell_edges(xs)
    x0 = float(max(e for e in x_edges if e < -1e-9))
    z_edges = cell_edges(zs)
    floor = float(z_edges[0])
    height = res.depth_m - floor
    y0, y1 = y_span_m
    bands = []
    for k, (lo, hi) in enumerate(zip(z_edges[:-1], z_edges[1:])):
        if lo >= res.depth_m - 1e-9:
            break
        release = res.opening_time_s * min(1.0, (float(hi) - floor) / height)
        bands.append(GateBand(f"gate{k:02d}", (x0, y0 - 1.0, float(lo)), (0.0, y1 + 1.0, float(hi)), release))
    return tuple(bands)
