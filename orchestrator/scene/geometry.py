"""Scene geometry: the flume's extent, a body's orientation, draft and height, box overlap.

These are the derived quantities that the scene's own rules (placement, validation) and the
later stages (planner, contact, preview) compute from a scene in the same way. Coordinates
and units are the scene's (:mod:`orchestrator.scene.schema`): metres, degrees, ``x`` along
the flume from the gate, ``y`` across from the centreline, ``z`` up from the floor.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from orchestrator.scene.schema import DebrisTemplate, Scene

__all__ = [
    "TOLERANCE_M",
    "body_rotation",
    "box_corners",
    "boxes_overlap",
    "draft_m",
    "flume_extent",
    "half_extent_z",
]

#: Slack of the scene's geometric comparisons (m): touching is not overlapping.
TOLERANCE_M = 1e-9


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


def half_extent_z(body: DebrisTemplate, rot: np.ndarray | None = None) -> float:
    """Half the vertical extent of the rotated box (m); ``rot``: its rotation, when known already."""
    if rot is None:
        rot = body_rotation(body.yaw_deg, body.pitch_deg, body.roll_deg)
    return float(np.sum(np.abs(rot[2, :]) * np.asarray(body.size_m) / 2.0))


def box_corners(centre: Sequence[float], rot: np.ndarray, size: Sequence[float]) -> np.ndarray:
    """The 8 corners (8 x 3) of a box given its centre, body->scene rotation and full sizes."""
    half = np.asarray(size, dtype=float) / 2.0
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    return np.asarray(centre, dtype=float) + (signs * half) @ rot.T


def boxes_overlap(
    c1: Sequence[float], r1: np.ndarray, s1: Sequence[float],
    c2: Sequence[float], r2: np.ndarray, s2: Sequence[float],
    tol: float = TOLERANCE_M,
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
