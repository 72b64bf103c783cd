"""The gate as the flume was built: a sill under it and walls beside its opening, as holes of the
background grid.

``reservoir.sill_height_m`` (s) puts the reservoir's floor at z = -s: the grid reaches down to it
and every block downstream of the gate below z = 0 is a hole whose faces join the bed patch, so
the released water climbs a step at x = 0 (a false floor downstream of the gate, a sill).
``reservoir.opening_width_m`` leaves the gate a clear opening centred at ``opening_y_m``: the
blocks beside it from the gate to ``opening_length_m`` downstream are holes whose faces join the
side walls' patch (the gate's posts, or the sides of a partial breach). The bed stays z = 0
downstream of the gate: gauges, the column and the bodies do not move.
"""

from __future__ import annotations

from orchestrator.core.errors import InputError
from orchestrator.plan.grid import Segment
from orchestrator.scene.schema import Scene

__all__ = ["gate_holes", "gate_planes", "opening_span_m", "reservoir_floor_m"]

#: The grid side whose patch a hole's faces join: the bed (sill) and the side walls (posts).
SILL_SIDE = "zmin"
POST_SIDE = "ymin"


def reservoir_floor_m(scene: Scene) -> float:
    """z of the reservoir's floor: 0, or -sill_height_m below the bed downstream."""
    sill = float(scene.reservoir.sill_height_m)
    return -sill if sill > 0 else 0.0


def opening_span_m(scene: Scene) -> tuple[float, float] | None:
    """(y0, y1) of the gate's clear opening, None when it spans the flume."""
    res, width = scene.reservoir, scene.flume.width_m
    if res.opening_width_m is None or res.opening_width_m >= width - 1e-9:
        return None
    return res.opening_y_m - res.opening_width_m / 2, res.opening_y_m + res.opening_width_m / 2


def gate_planes(scene: Scene, two_d: bool) -> tuple[list[tuple[float, int]], list[tuple[float, int]],
                                                  list[tuple[float, int]]]:
    """The hard planes (x, y, z) the sill and the opening need."""
    wx: list[tuple[float, int]] = []
    wy: list[tuple[float, int]] = []
    wz: list[tuple[float, int]] = []
    if scene.reservoir.sill_height_m > 0:
        wz.append((0.0, 2))
    span = opening_span_m(scene)
    if span is not None:
        if two_d:
            raise InputError("reservoir.opening_width_m",
                             "a gate opening narrower than the flume needs a 3D flow; this scene plans a 2D one "
                             "(a flume one cell wide): drop the key or widen the flume")
        wx.append((scene.reservoir.opening_length_m, 2))
        wy += [(span[0], 2), (span[1], 2)]
    return wx, wy, wz


def _centres(segs: tuple[Segment, ...]) -> list[float]:
    return [0.5 * (s.start_m + s.end_m) for s in segs]


def gate_holes(scene: Scene, xs: tuple[Segment, ...], ys: tuple[Segment, ...],
               zs: tuple[Segment, ...]) -> dict[tuple[int, int, int], str]:
    """The grid's blocks the sill and the gate's walls fill, each with the side whose patch its
    faces join."""
    cx, cy, cz = _centres(xs), _centres(ys), _centres(zs)
    holes: dict[tuple[int, int, int], str] = {}
    if scene.reservoir.sill_height_m > 0:
        for i, x in enumerate(cx):
            for k, z in enumerate(cz):
                if x > 0 and z < 0:
                    holes.update({(i, j, k): SILL_SIDE for j in range(len(cy))})
    span = opening_span_m(scene)
    if span is not None:
        length = scene.reservoir.opening_length_m
        for i, x in enumerate(cx):
            if not 0 < x < length:
                continue
            for j, y in enumerate(cy):
                if span[0] < y < span[1]:
                    continue
                holes.update({(i, j, k): POST_SIDE for k in range(len(cz)) if (i, j, k) not in holes})
    return holes
