"""Where a case samples the flow, and the last numbers its dictionaries need, decided once.

* Gauge lines: each gauge a vertical line from the bed to its top (or the domain's), two points
  per bed cell height (at most 1,000), both ends a thousandth of a bed cell inside the mesh: a
  line ending exactly on the bed or the top boundary starts "outside of the mesh" in v1912.
* Probes: one at the centre of the bed cell under each gauge, and four up the column's upstream
  face (a quarter of the smallest cell in front of it, at 1/5 to 4/5 of the deepest water).
* The bed friction's Forchheimer coefficient: the bed shear rho (f / 8) |U| U spread over the
  friction zone's height dz is a Darcy-Forchheimer drag with F = f / (4 dz), times the scene's
  calibration (bed.friction_calibration).
* The six-DoF motion's inner and outer distances: points are moved by a body only if connected
  to its wall patch, and body meshes are disconnected from the background and from each other,
  so a distance beyond the whole domain moves each body mesh rigidly and nothing else.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from orchestrator.plan.grid import BoxGrid
from orchestrator.plan.model import Box, GaugeLine, GaugePlan, Probe

__all__ = ["bed_friction_per_m", "motion_distance_m", "sampling"]

#: most points on a gauge line
MAX_GAUGE_POINTS = 1000
#: probes up the column's upstream face
COLUMN_FACE_PROBES = 4


def _corners(background: BoxGrid) -> tuple[np.ndarray, np.ndarray]:
    lo = np.array([background.planes(a)[0] for a in "xyz"])
    hi = np.array([background.planes(a)[-1] for a in "xyz"])
    return lo, hi


def sampling(background: BoxGrid, gauges: Sequence[GaugePlan], *, two_d: bool, bed_cell_m: float,
             min_cell_m: float, water_depth_m: float,
             column_box_m: Box | None) -> tuple[tuple[GaugeLine, ...], tuple[Probe, ...]]:
    """The gauge lines and the probes (module notes)."""
    lo, hi = _corners(background)
    lo[2] = max(lo[2], 0.0)  # the bed downstream of the gate; a sill puts the reservoir's floor below it
    y_mid = float((lo[1] + hi[1]) / 2)
    eps = 1e-3 * bed_cell_m
    lines, probes = [], []
    for g in gauges:
        y = y_mid if two_d else float(g.y)
        top = min(float(g.z_top), float(hi[2]))
        n_points = int(min(MAX_GAUGE_POINTS, math.ceil((top - lo[2]) / (bed_cell_m / 2)) + 1))
        lines.append(GaugeLine(g.name, (float(g.x), y, float(lo[2] + eps)), (float(g.x), y, top - eps), n_points))
        probes.append(Probe(f"{g.name}_bed", (float(g.x), y, float(lo[2] + bed_cell_m / 2))))
    if column_box_m is not None:
        c_lo, c_hi = column_box_m
        x_face = float(c_lo[0] - min_cell_m / 4)
        yc = float((c_lo[1] + c_hi[1]) / 2)
        n = COLUMN_FACE_PROBES + 1
        for i in range(1, n):
            probes.append(Probe(f"column_face_{i}", (x_face, yc, float(lo[2] + water_depth_m * i / n))))
    return tuple(lines), tuple(probes)


def bed_friction_per_m(friction_factor: float, calibration: float, layer_m: float) -> float:
    """The Forchheimer coefficient F (1/m) of the bed-friction zone; 0 without bed friction."""
    if friction_factor <= 0:
        return 0.0
    return float(calibration * friction_factor / (4 * layer_m))


def motion_distance_m(background: BoxGrid) -> tuple[float, float]:
    """(inner, outer) distance of the bodies' point displacement: beyond the whole domain."""
    lo, hi = _corners(background)
    diag = float(np.linalg.norm(hi - lo))
    return max(100.0, 10 * diag), max(101.0, 10 * diag + 1)
