"""The domain decomposition: hierarchical (nx ny nz) over the scene's cores.

decomposePar keeps every body mesh whole on one rank whatever the cuts (a
preserveFaceZones constraint, templates/system/decomposeParDict.j2): it lumps the
body's cells into one point before cutting, which costs balance where a cut would have
crossed the body. With two or more bodies the runner then moves half of each body mesh to
the next rank (orchestrator/case/split_bodies.py), because v1912's overset deadlocks when two
overlapping body meshes share a rank. Cut planes are estimated as cell-count quantiles per axis (hierarchical
balances cell counts). Candidates are scored by the bodies their cuts cross at the
start, then the bodies whose path (to the column) they cross, then the
processor-boundary area.
"""

from __future__ import annotations

import numpy as np

from orchestrator.plan.bodies import BodyLayout
from orchestrator.plan.domain import Domain
from orchestrator.plan.grading import cell_centres
from orchestrator.plan.grid import BoxGrid
from orchestrator.plan.model import BodyPlan

__all__ = ["decompose"]


def _weighted_centres(grid: BoxGrid, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Cell-centre coordinates along ``axis`` and how many cells sit at each."""
    segs = (grid.x, grid.y, grid.z)
    counts: dict[int, float] = {}
    for i, j, k in grid.blocks():
        idx = (i, j, k)
        others = 1
        for d in range(3):
            if d != axis:
                others *= segs[d][idx[d]].cells
        counts[idx[axis]] = counts.get(idx[axis], 0) + others
    pos, wts = [], []
    for s_idx, w in counts.items():
        c = cell_centres(segs[axis][s_idx])
        pos.append(c)
        wts.append(np.full(c.size, float(w)))
    return np.concatenate(pos), np.concatenate(wts)


def _quantile_cuts(pos: np.ndarray, wts: np.ndarray, n: int) -> list[float]:
    order = np.argsort(pos)
    p, w = pos[order], wts[order]
    cum = np.cumsum(w) / w.sum()
    return [float(p[np.searchsorted(cum, k / n)]) for k in range(1, n)]


def _paths(layout: BodyLayout, domain: Domain) -> list[tuple[np.ndarray, np.ndarray]]:
    """The box each body mesh sweeps on its way to the column (or the domain end)."""
    (fy0, fy1), spread = domain.y, domain.tan_spread
    paths = []
    for lo, hi in layout.boxes:
        travel = max(domain.travel_end - lo[0], 0.0)
        paths.append(
            (
                np.array([lo[0], max(lo[1] - spread * travel, fy0), 0.0]),
                np.array([max(hi[0], domain.travel_end), min(hi[1] + spread * travel, fy1),
                          max(domain.fine[2][1], hi[2])]),
            )
        )
    return paths


def _best_split(cores, background, bodies, boxes, paths, two_d):
    """(score, (nx, ny, nz), cuts per axis) of the best-scoring candidate."""
    cands = [
        (nx, ny, cores // (nx * ny))
        for nx in range(1, cores + 1)
        for ny in range(1, cores + 1)
        if cores % (nx * ny) == 0 and (not two_d or ny == 1)
    ]
    (x0, x1), (y0, y1), (z0, z1) = [(g[0].start_m, g[-1].end_m) for g in (background.x, background.y, background.z)]
    dist = []
    for axis in range(3):
        pos, wts = _weighted_centres(background, axis)
        extra_p = [b.centre_of_mass_m[axis] for b in bodies]
        extra_w = [float(b.grid.cell_count()) for b in bodies]
        dist.append((np.concatenate([pos, extra_p]), np.concatenate([wts, extra_w])))
    best = None
    for cand in cands:
        cuts = [_quantile_cuts(*dist[a], cand[a]) for a in range(3)]
        split_now = sum(any(lo[a] < c < hi[a] for a in range(3) for c in cuts[a]) for lo, hi in boxes)
        split_path = sum(any(lo[a] < c < hi[a] for a in range(3) for c in cuts[a]) for lo, hi in paths)
        area = ((cand[0] - 1) * (y1 - y0) * (z1 - z0) + (cand[1] - 1) * (x1 - x0) * (z1 - z0)
                + (cand[2] - 1) * (x1 - x0) * (y1 - y0))
        score = (split_now, split_path, area)
        if best is None or score < best[0]:
            best = (score, cand, cuts)
    return best


def decompose(cores: int, background: BoxGrid, bodies: tuple[BodyPlan, ...], layout: BodyLayout,
              domain: Domain, two_d: bool) -> tuple[tuple[int, int, int], str]:
    """hierarchical (nx ny nz) with nx ny nz = cores, and the reason for it (module docstring)."""
    if cores == 1:
        return (1, 1, 1), "1 core: no decomposition"
    (split_now, split_path, _), cand, cuts = _best_split(
        cores, background, bodies, layout.boxes, _paths(layout, domain), two_d)
    where = "; ".join(
        f"{'xyz'[a]} cut at {', '.join(f'{c:.3g}' for c in cuts[a])} m" for a in range(3) if cuts[a]
    )
    text = f"hierarchical ({cand[0]} {cand[1]} {cand[2]}) over {cores} cores ({where})"
    if len(bodies) >= 2:
        text += (
            ": each body mesh on one rank (decomposePar's preserveFaceZones constraint), then half of each "
            "moved to the next rank (orchestrator/case/split_bodies.py): v1912's overset addressing deadlocks when "
            "two overlapping body meshes share a rank (docs/stability.md); a split body mesh costs about 19 % per "
            "step (docs/openfoam-notes.md)"
        )
    elif bodies:
        text += (
            f": every body mesh on one rank (decomposePar's preserveFaceZones constraint); "
            f"{len(bodies) - split_now} of {len(bodies)} body meshes start clear of the balanced cuts and "
            f"{len(bodies) - split_path} keep their path to the column on one rank (a split body mesh costs about 19 % "
            "per step, docs/openfoam-notes.md)"
        )
    else:
        text += ": the smallest processor boundary"
    return cand, text
