"""The background mesh: planes where the scene needs them, fine cells in the fine region,
cells growing geometrically away from it.

Cell sizes: ``mesh.cell_size_m`` (h) inside the fine region, then growing by at most
``mesh.growth_ratio`` per cell up to ``h x mesh.coarsening_ratio``. setFields fills whole
cells by their centres (boxToCell), so the water is the scene's only where every face of
its boxes is a cell face: the gate, the impoundment level, the wet-bed surface and the
layers of the gap under resting bodies are planes whatever their thickness. The column is
a hole of blocks.

Also here: the cell-size readings of a grid that the rest of the plan uses (smallest cell,
cell faces, cell centres).
"""

from __future__ import annotations

import math
from itertools import product

import numpy as np

from orchestrator.plan.bodies import BedGap
from orchestrator.plan.domain import Domain, column_spans_width
from orchestrator.plan.gate import gate_holes, gate_planes, reservoir_floor_m
from orchestrator.plan.grid import BoxGrid, Segment, graded_segment
from orchestrator.plan.refine import refine_axis, refine_span, refinement
from orchestrator.scene.schema import Scene

__all__ = [
    "BACKGROUND_PATCHES",
    "COLUMN_PATCH",
    "axis_segments",
    "background_grid",
    "cell_centres",
    "cell_edges",
    "min_cell_m",
]

#: The patch the column's hole becomes.
COLUMN_PATCH = "column"
#: Patch names of the background's sides (and of its hole, the column).
BACKGROUND_PATCHES = {
    "xmin": "upstreamWall",
    "xmax": "downstream",
    "ymin": "sideWalls",
    "ymax": "sideWalls",
    "zmin": "bed",
    "zmax": "atmosphere",
    "hole": COLUMN_PATCH,
}


def min_cell_m(segments: tuple[Segment, ...]) -> float:
    """The smallest cell along one axis of a grid."""
    return min(min(s.cell_sizes_m()) for s in segments)


def cell_edges(segments: tuple[Segment, ...]) -> np.ndarray:
    """Cell faces along one axis of a BoxGrid (the segments' geometric progressions)."""
    edges = [segments[0].start_m]
    for seg in segments:
        n, r = seg.cells, seg.grading
        q = 1.0 if n == 1 or abs(r - 1.0) < 1e-12 else r ** (1.0 / (n - 1))
        sizes = q ** np.arange(n)
        edges += list(seg.start_m + np.cumsum(sizes)[:-1] / sizes.sum() * seg.length_m) + [seg.end_m]
    return np.asarray(edges, dtype=float)


def cell_centres(seg: Segment) -> np.ndarray:
    """Cell-centre coordinates of one segment."""
    n, r = seg.cells, seg.grading
    if n == 1 or abs(r - 1.0) < 1e-12:
        edges = np.linspace(seg.start_m, seg.end_m, n + 1)
    else:
        q = r ** (1.0 / (n - 1))
        sizes = q ** np.arange(n)
        edges = seg.start_m + np.concatenate([[0.0], np.cumsum(sizes)]) / sizes.sum() * seg.length_m
    return 0.5 * (edges[:-1] + edges[1:])


def pick_planes(lo: float, hi: float, wanted: list[tuple[float, int]], h: float) -> list[float]:
    """Planes lo..hi plus the wanted ones, by priority (2 hard, 1 useful, 0 soft).

    A useful plane closer than h/2 to a kept one, or a soft plane closer than one cell,
    is dropped (no slivers); hard planes are always kept.
    """
    kept = [lo, hi]
    gaps = {2: 1e-9, 1: 0.5 * h, 0: h}
    for pos, prio in sorted(wanted, key=lambda p: -p[1]):
        if not lo < pos < hi:
            continue
        if all(abs(pos - k) >= gaps[prio] for k in kept):
            kept.append(pos)
    return sorted(kept)


def axis_segments(
    lo: float,
    hi: float,
    fine: tuple[float, float],
    wanted: list[tuple[float, int]],
    h: float,
    h_max: float,
    growth: float,
) -> tuple[Segment, ...]:
    """Segments lo..hi: cells h inside ``fine``, growing by ``growth`` per cell outside, to h_max."""
    planes = pick_planes(lo, hi, wanted + [(fine[0], 0), (fine[1], 0)], h)
    s_sat = (h_max - h) / (growth - 1.0) if h_max > h else 0.0

    def dist(x: float) -> float:
        return max(fine[0] - x, x - fine[1], 0.0)

    def size(s: float) -> float:
        return min(h_max, h + (growth - 1.0) * s)

    segs: list[Segment] = []
    for a, b in zip(planes, planes[1:]):
        if a >= fine[0] - 1.01 * h and b <= fine[1] + 1.01 * h:
            segs.append(Segment(a, b, max(1, math.ceil((b - a) / h - 1e-9))))
            continue
        sa, sb = dist(a), dist(b)
        if min(sa, sb) >= s_sat - 1e-12:
            segs.append(Segment(a, b, max(1, math.ceil((b - a) / h_max - 1e-9))))
            continue
        if max(sa, sb) <= s_sat + 1e-12:
            segs.append(graded_segment(a, b, size(sa), size(sb)))
            continue
        # split where the cells reach h_max: graded near the fine region, uniform beyond
        cut = fine[1] + s_sat if sa < sb else fine[0] - s_sat
        if cut - a < 0.5 * h_max or b - cut < 0.5 * h_max:
            segs.append(graded_segment(a, b, size(sa), size(sb)))
        else:
            segs.append(graded_segment(a, cut, size(sa), size(dist(cut))))
            segs.append(graded_segment(cut, b, size(dist(cut)), size(sb)))
    return tuple(segs)


def resolve_wet_bed(zs: tuple[Segment, ...], wet_m: float, cells: int, growth: float) -> tuple[Segment, ...]:
    """The z segments with at least ``cells`` cells across the wet bed (0..``wet_m``, a plane of the
    grid) and cells growing by ``growth`` a cell from the wet bed's top cell to the size of the
    segment above it, so that no cell above the bed is more than ``growth`` times its neighbour."""
    h_bed = wet_m / cells
    out: list[Segment] = []
    top = h_bed
    for i, seg in enumerate(zs):
        if seg.end_m <= wet_m + 1e-12:
            n = max(seg.cells, math.ceil(seg.length_m / h_bed - 1e-9))
            out.append(Segment(seg.start_m, seg.end_m, n, seg.grading if n == seg.cells else 1.0))
            top = out[-1].cell_sizes_m()[1]
            continue
        if seg.start_m < wet_m - 1e-12 or (out and out[-1].end_m < wet_m - 1e-12):
            return zs  # the wet bed's surface is not a plane of this grid: leave it as planned
        if abs(seg.start_m - wet_m) > 1e-12:
            out.append(seg)
            continue
        target = seg.cell_sizes_m()[0]
        if target <= top * growth:
            out.extend(zs[i:])
            break
        m = max(1, math.ceil(math.log(target / top) / math.log(growth) - 1e-9))
        q = (target / top) ** (1.0 / m)
        graded_len = top * q * (q**m - 1.0) / (q - 1.0)
        if graded_len + 0.5 * target < seg.length_m:
            cut = seg.start_m + graded_len
            out.append(Segment(seg.start_m, cut, m, q ** (m - 1)))
            rest = Segment(cut, seg.end_m, max(1, math.ceil((seg.end_m - cut) / target - 1e-9)), seg.grading)
            out.append(rest)
        else:
            out.append(graded_segment(seg.start_m, seg.end_m, top * growth, target))
        out.extend(zs[i + 1:])
        break
    return tuple(out)


def _indices_within(segs: tuple[Segment, ...], lo: float, hi: float) -> list[int]:
    return [i for i, s in enumerate(segs) if lo - 1e-9 <= 0.5 * (s.start_m + s.end_m) <= hi + 1e-9]


def _wanted_planes(scene: Scene, domain: Domain, gap: BedGap | None, warnings: list[str], one_way: bool):
    """The planes the water boxes and the column need, by axis (all hard)."""
    h0, h, col = scene.reservoir.depth_m, scene.mesh.cell_size_m, scene.column
    bed_layer = scene.bed.wet_depth_m if scene.bed.wet_depth_m > 0 else None
    # a plane of the column's top 1 cm above a 0.39 m impoundment would otherwise drop the
    # impoundment's and fill the reservoir to 0.40 m, 2.6 % too much water
    wx: list[tuple[float, int]] = [(0.0, 2)]
    wy: list[tuple[float, int]] = []
    wz: list[tuple[float, int]] = [(h0, 2)]
    if bed_layer is not None:
        wz.append((bed_layer, 2))
    if gap is not None:
        wz += [(z, 2) for z in gap.planes()]
    thinnest = min([bed_layer or h] + ([gap.layer_m] if gap else []))
    if thinnest < 0.2 * h:
        warnings.append(
            f"bed layer {thinnest:.3g} m thick under {h:g} m cells ({h / thinnest:.0f} times thinner): "
            + (f"the {gap.layers} layers of the gap under resting bodies" if gap else "the wet bed's own layer")
            + (" (kept in a one-way flow, which has no bodies, so that its mesh is a two-way run's cell for cell)"
               if gap and one_way else "")
        )
    if col:
        wx += [(col.x_m - col.size_x_m / 2, 2), (col.x_m + col.size_x_m / 2, 2)]
        if not column_spans_width(scene):
            wy += [(col.y_m - col.size_y_m / 2, 2), (col.y_m + col.size_y_m / 2, 2)]
        if col.height_m < domain.z_hi:
            wz.append((col.height_m, 2))
    return wx, wy, wz


def _refined(scene: Scene, fine, axes, two_d: bool, reasons: dict[str, str]):
    """The three axes' segments with the scene's refinement box, if any (:mod:`orchestrator.plan.refine`)."""
    mesh = scene.mesh
    refined = refinement(scene)
    if refined is None:
        return axes
    b, h_fine, field = refined
    out = []
    for i, (name, segs) in enumerate(zip("xyz", axes)):
        if name == "y" and two_d:
            out.append(segs)
            continue
        out.append(refine_axis(segs, refine_span(b, i), fine[i], mesh.cell_size_m, h_fine, mesh.growth_ratio,
                               name, field))
    reasons["refine_box"] = (
        f"cells of {h_fine:g} m in x {b[0]:g}..{b[1]:g}, y {b[2]:g}..{b[3]:g}, z {b[4]:g}..{b[5]:g} m "
        f"({field}), growing by {mesh.growth_ratio:g} a cell to {mesh.cell_size_m:g} m around it; the "
        "block grid refines the slabs through the box along each axis")
    return tuple(out)


def background_grid(scene: Scene, domain: Domain, gap: BedGap | None, two_d: bool,
                    reasons: dict[str, str], warnings: list[str], *, one_way: bool = False) -> BoxGrid:
    """The background BoxGrid of ``domain``, the column a hole in it."""
    h, col = scene.mesh.cell_size_m, scene.column
    h_max = h * scene.mesh.coarsening_ratio
    growth = scene.mesh.growth_ratio
    (fy0, fy1), fine = domain.y, domain.fine
    wx, wy, wz = _wanted_planes(scene, domain, gap, warnings, one_way)
    gx, gy, gz = gate_planes(scene, two_d)
    z_lo = reservoir_floor_m(scene)
    fine = (fine[0], fine[1], (min(z_lo, fine[2][0]), fine[2][1]))
    xs = axis_segments(domain.x_lo, domain.x_hi, fine[0], wx + gx, h, h_max, growth)
    ysegs = (Segment(fy0, fy1, 1),) if two_d else axis_segments(fy0, fy1, fine[1], wy + gy, h, h_max, growth)
    zs = axis_segments(z_lo, domain.z_hi, fine[2], wz + gz, h, h_max, growth)
    xs, ysegs, zs = _refined(scene, fine, (xs, ysegs, zs), two_d, reasons)
    if scene.bed.wet_depth_m > 0 and scene.mesh.wet_bed_cells > 1:
        below = tuple(s for s in zs if s.end_m <= 1e-12)  # the reservoir below the bed downstream
        zs = below + resolve_wet_bed(zs[len(below):], scene.bed.wet_depth_m, scene.mesh.wet_bed_cells, growth)
        reasons["wet_bed"] = (
            f"{scene.mesh.wet_bed_cells} or more cells across the {scene.bed.wet_depth_m:g} m wet bed, growing by "
            f"{growth:g} a cell above it: the bore meets the still water in cells that can carry it along")
    holes: frozenset = frozenset()
    if col:
        ii = _indices_within(xs, col.x_m - col.size_x_m / 2, col.x_m + col.size_x_m / 2)
        jj = list(range(len(ysegs))) if (two_d or column_spans_width(scene)) else _indices_within(
            ysegs, col.y_m - col.size_y_m / 2, col.y_m + col.size_y_m / 2
        )
        kk = _indices_within(zs, 0.0, min(col.height_m, domain.z_hi))
        holes = frozenset(product(ii, jj, kk))
    gate = gate_holes(scene, xs, ysegs, zs)
    holes = holes | frozenset(gate)
    if gate:
        res = scene.reservoir
        reasons["gate"] = reasons.get("gate", "gate") + "; " + (
            (f"the reservoir's floor {res.sill_height_m:g} m below the bed downstream: a step at the gate; "
             if res.sill_height_m > 0 else "")
            + (f"the gate's opening {res.opening_width_m:g} m wide at y = {res.opening_y_m:g} m, walls beside it "
               f"to x = {res.opening_length_m:g} m" if res.opening_width_m is not None else ""))
    patches = dict(BACKGROUND_PATCHES)
    if two_d:
        patches["ymin"] = patches["ymax"] = "frontAndBack"
    reasons["grading"] = (
        f"outside the fine region cells grow by at most {growth:g} per cell up to {h_max:.3g} m "
        f"({scene.mesh.coarsening_ratio:g} x the finest); planes kept at the gate (x = 0), the impoundment level"
        + (", the wet-bed surface" if scene.bed.wet_depth_m > 0 else "")
        + (f", {gap.layers} layers of {gap.layer_m:.3g} m at the bed (the gap under resting bodies)" if gap else "")
        + (" and the column's faces" if col else "")
        + f"; background {len(xs)} x {len(ysegs)} x {len(zs)} blocks"
    )
    return BoxGrid("background", xs, ysegs, zs, holes, patches, hole_sides=gate)
