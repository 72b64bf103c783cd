"""A refinement box: finer cells in one box inside the fine region (``mesh.refine_box_m``).

The background is a tensor-product block grid, so a box refined along x is refined along x over
the whole width and height (a slab), and likewise for y and z: the cells inside the box are
``mesh.refine_cell_size_m`` along all three axes, the slabs through it are fine along one or two.
Each axis gets the box's two faces as planes (dropped when closer than half a fine cell to a
plane the grid already has, which then bounds the box), uniform fine cells between them, and on
either side a transition in which the cells grow by ``mesh.growth_ratio`` a cell from the fine
size back to ``mesh.cell_size_m``: its length is the geometric series' sum, ``(h - h_r) / (r - 1)``
plus one fine cell. Every plane the grid had stays (the gate, the water levels, the bed layers,
the column's faces), so the water setFields fills and the column's hole are unchanged.

The box and its transitions must lie inside the fine region, whose cells are uniform at
``mesh.cell_size_m``: the transitions then split only uniform segments, and a box outside the
region (where cells already grow) is an input error naming ``mesh.refine_box_m``.

``mesh.column_approach_cell_size_m`` places the box at the column instead (:func:`refinement`), so it
follows the column when the column moves and scales with the scene: from four lengths of the
longest body upstream of the column's upstream face (the strike speed is decided over the last
0.1 m before the face, docs/results/approach/, and the box's transition starts upstream of that) to a
quarter of the column's depth past its centre (the box ends inside the column's hole), across the
column's width and the widest body's width either side (a body that strikes it passes there), from
the bed to 0.6 of the impoundment depth (above the bore and the body). For the 1-debris scene that is
x 4.3..5.05, y -0.16..0.16, z 0..0.24 m.

The one-way flow record follows the box: its x and y samples inside the box's span are the
background's cell centres there, so a finer flow is recorded at its own resolution
(:func:`record_axis`).
"""

from __future__ import annotations

import math

import numpy as np

from orchestrator.core.errors import InputError
from orchestrator.plan.grid import Segment, graded_segment

__all__ = ["record_axis", "refine_axis", "refine_span", "refinement", "transition_m"]

_FIELD = "mesh.refine_box_m"


#: The column-approach box: body lengths upstream of the face, share of the impoundment depth.
APPROACH_BODY_LENGTHS = 4.0
APPROACH_DEPTH_SHARE = 0.6


def refinement(scene) -> tuple[tuple[float, ...], float, str] | None:
    """The scene's refinement box, its cell size and the field that set it; None without one (or
    with a column-approach cell size no finer than the mesh's, a warning at validation)."""
    mesh = scene.mesh
    if mesh.refine_box_m is not None and mesh.refine_cell_size_m is not None:
        return tuple(mesh.refine_box_m), mesh.refine_cell_size_m, _FIELD
    h = mesh.column_approach_cell_size_m
    col = scene.column
    if h is None or h >= mesh.cell_size_m or col is None:
        return None
    length = max((max(b.size_m) for b in scene.debris), default=0.0)
    width = max((min(b.size_m[:2]) for b in scene.debris), default=0.0)
    face = col.x_m - col.size_x_m / 2
    box = (face - APPROACH_BODY_LENGTHS * length, col.x_m + col.size_x_m / 4,
           col.y_m - col.size_y_m / 2 - width, col.y_m + col.size_y_m / 2 + width,
           0.0, APPROACH_DEPTH_SHARE * scene.reservoir.depth_m)
    return tuple(round(v, 9) for v in box), h, "mesh.column_approach_cell_size_m"


def transition_m(h: float, h_fine: float, growth: float) -> float:
    """Length over which cells grow from ``h_fine`` to ``h`` by ``growth`` a cell (m)."""
    return (h - h_fine) / (growth - 1.0) + h_fine


def refine_span(box: tuple[float, ...] | None, axis: int) -> tuple[float, float] | None:
    """(lo, hi) of the box along axis 0, 1 or 2 (``box`` is x0, x1, y0, y1, z0, z1); None without a box."""
    if box is None:
        return None
    return float(box[2 * axis]), float(box[2 * axis + 1])


def refine_axis(segs: tuple[Segment, ...], span: tuple[float, float], fine: tuple[float, float],
                h: float, h_fine: float, growth: float, axis_name: str = "x",
                field: str = _FIELD) -> tuple[Segment, ...]:
    """``segs`` with cells of ``h_fine`` in ``span`` and graded transitions to ``h`` either side.

    ``fine`` is the fine region along this axis (cells of ``h``); the span and its transitions
    must lie inside it, except where they reach the grid's own ends."""
    lo, hi = span
    g_lo, g_hi = segs[0].start_m, segs[-1].end_m
    if not (h_fine < h):
        raise InputError("mesh.refine_cell_size_m", f"{h_fine:g} m must be finer than mesh.cell_size_m ({h:g} m)")
    if not lo < hi:
        raise InputError(field, f"along {axis_name} the box's end {hi:g} m must exceed its start {lo:g} m")
    lo, hi = max(lo, g_lo), min(hi, g_hi)
    if not lo < hi:
        raise InputError(field, f"along {axis_name} the box lies outside the domain ({g_lo:g}..{g_hi:g} m)")
    tr = transition_m(h, h_fine, growth)
    t_lo, t_hi = max(g_lo, lo - tr), min(g_hi, hi + tr)
    tol = 1e-9
    if (t_lo < fine[0] - tol and t_lo > g_lo + tol) or (t_hi > fine[1] + tol and t_hi < g_hi - tol):
        raise InputError(
            field, f"along {axis_name} the box {span[0]:g}..{span[1]:g} m with its {tr:.3g} m transitions "
            f"({t_lo:.4g}..{t_hi:.4g} m) must lie inside the fine region {fine[0]:.4g}..{fine[1]:.4g} m")
    old = [segs[0].start_m] + [s.end_m for s in segs]
    planes = list(old)
    for p in (t_lo, lo, hi, t_hi):
        if all(abs(p - q) >= 0.5 * h_fine for q in planes):
            planes.append(p)
    planes.sort()

    def size(x: float) -> float:
        d = max(lo - x, x - hi, 0.0)
        return min(h, h_fine + (growth - 1.0) * max(0.0, d - h_fine))

    out: list[Segment] = []
    for a, b in zip(planes, planes[1:]):
        mid = 0.5 * (a + b)
        if lo - tol <= mid <= hi + tol or (lo - 0.5 * h_fine < a and b < hi + 0.5 * h_fine):
            out.append(Segment(a, b, max(1, math.ceil((b - a) / h_fine - 1e-9))))
        elif t_lo - tol <= mid <= t_hi + tol:
            sa, sb = size(a), size(b)
            piece = graded_segment(a, b, sa, sb)
            # never coarser than the cells it replaces
            out.append(piece if (b - a) / piece.cells <= h + tol else Segment(a, b, math.ceil((b - a) / h - 1e-9)))
        else:
            parent = next(s for s in segs if s.start_m - tol <= a and b <= s.end_m + tol)
            if abs(parent.start_m - a) < tol and abs(parent.end_m - b) < tol:
                out.append(parent)
            else:  # a uniform segment of the fine region cut by a transition's outer plane
                out.append(Segment(a, b, max(1, math.ceil((b - a) / h - 1e-9))))
    return tuple(out)


def record_axis(base: np.ndarray, centres: np.ndarray, span: tuple[float, float] | None) -> np.ndarray:
    """Record samples along one axis: ``base`` outside ``span``, the mesh's cell ``centres`` inside it."""
    if span is None:
        return base
    lo, hi = span
    inside = centres[(centres >= lo) & (centres <= hi)]
    if inside.size == 0:
        return base
    gap = 0.5 * float(np.min(np.diff(inside))) if inside.size > 1 else 0.0
    outside = base[(base < inside[0] - gap) | (base > inside[-1] + gap)]
    return np.unique(np.concatenate([outside, inside]))
