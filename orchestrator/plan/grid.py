"""Tensor-product block grids with holes: the mesh contract between planner and templates.

A `BoxGrid` cuts a box into blocks by planes along x, y and z (`Segment`s), each
segment with its own cell count and grading. Blocks listed in `holes` are left
out: the column in the background mesh, the debris body in a body mesh. The
planner builds BoxGrids; `templates/blockMeshDict.j2` writes them; nothing else
needs to know how blockMesh numbers vertices.

Coordinates are local to the grid; `origin` and `rotation` place it in the scene
(body meshes are rotated with their body). Lengths in metres.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import product

import numpy as np

from orchestrator.core.errors import InputError

#: The six outer sides, in blockMesh's face-vertex order (outward normals by the
#: right-hand rule for the hex numbering 0..7 used below).
SIDE_FACES: dict[str, tuple[int, int, int, int]] = {
    "xmin": (0, 4, 7, 3),
    "xmax": (2, 6, 5, 1),
    "ymin": (1, 5, 4, 0),
    "ymax": (3, 7, 6, 2),
    "zmin": (0, 3, 2, 1),
    "zmax": (4, 5, 6, 7),
}
_NEIGHBOUR = {
    "xmin": (-1, 0, 0),
    "xmax": (1, 0, 0),
    "ymin": (0, -1, 0),
    "ymax": (0, 1, 0),
    "zmin": (0, 0, -1),
    "zmax": (0, 0, 1),
}


@dataclass(frozen=True)
class Segment:
    """One interval of an axis: [start_m, end_m] cut into `cells` cells.

    `grading` is blockMesh's simpleGrading for this interval: last cell size over
    first cell size (1 = uniform).
    """

    start_m: float
    end_m: float
    cells: int
    grading: float = 1.0

    def __post_init__(self) -> None:
        # A segment is read back from plan.json (plan.model.grid_from_dict) as well as planned: bad input.
        if not self.end_m > self.start_m:
            raise InputError("end_m", f"must exceed start_m ({self.start_m}), got {self.end_m}")
        if self.cells < 1:
            raise InputError("cells", f"must be at least 1, got {self.cells}")
        if not self.grading > 0:
            raise InputError("grading", f"must be > 0, got {self.grading}")

    @property
    def length_m(self) -> float:
        return self.end_m - self.start_m

    def cell_sizes_m(self) -> tuple[float, float]:
        """(first, last) cell size of a geometric progression with this grading."""
        n, r, length = self.cells, self.grading, self.length_m
        if n == 1 or abs(r - 1.0) < 1e-12:
            return length / n, length / n
        q = r ** (1.0 / (n - 1))
        first = length * (1 - q) / (1 - q**n)
        return first, first * r


def graded_segment(start_m: float, end_m: float, first_m: float, last_m: float) -> Segment:
    """A segment whose cells grow geometrically from about `first_m` to about `last_m`.

    The cell count is the smallest that keeps every cell no larger than the larger
    of the two target sizes; used by the planner to coarsen away from where the
    scene needs fine cells.
    """
    length = end_m - start_m
    small, large = min(first_m, last_m), max(first_m, last_m)
    if length <= large or abs(large / small - 1) < 1e-9:
        n = max(1, int(np.ceil(length / large - 1e-9)))
        return Segment(start_m, end_m, n, 1.0)
    # geometric progression small..large: n cells with ratio q, sum = length
    # choose n from the mean size, then grading = last/first
    mean = (large - small) / np.log(large / small)
    n = max(2, int(np.ceil(length / mean - 1e-9)))
    ratio = large / small
    return Segment(start_m, end_m, n, ratio if last_m >= first_m else 1.0 / ratio)


@dataclass(frozen=True)
class BoxGrid:
    """A block-structured box: planes along each axis, some blocks left out.

    `patch_names` maps the sides ("xmin" ... "zmax") and "hole" to OpenFOAM patch
    names; sides mapped to the same name become one patch. A hole listed in
    `hole_sides` has its faces on that side's patch instead of the "hole" patch (the
    flume's sill and the gate's posts are bed and wall; the column is the hole).
    """

    name: str
    x: tuple[Segment, ...]
    y: tuple[Segment, ...]
    z: tuple[Segment, ...]
    holes: frozenset[tuple[int, int, int]] = frozenset()
    patch_names: dict[str, str] = field(default_factory=dict)
    hole_sides: dict[tuple[int, int, int], str] = field(default_factory=dict)
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[tuple[float, float, float], ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))

    def __post_init__(self) -> None:
        for axis in ("x", "y", "z"):
            segs = getattr(self, axis)
            if not segs:
                raise InputError(f"{self.name}.{axis}", "has no segments")
            for a, b in zip(segs, segs[1:]):
                if abs(a.end_m - b.start_m) > 1e-12:
                    raise InputError(f"{self.name}.{axis}", f"segments are not contiguous at {a.end_m} m")
        shape = self.shape
        for h in self.holes:
            if not all(0 <= h[i] < shape[i] for i in range(3)):
                raise InputError(f"{self.name}.holes", f"hole {h} outside the block array {shape}")

    @property
    def shape(self) -> tuple[int, int, int]:
        """Number of segments along x, y, z."""
        return len(self.x), len(self.y), len(self.z)

    def planes(self, axis: str) -> list[float]:
        segs = getattr(self, axis)
        return [segs[0].start_m] + [s.end_m for s in segs]

    def blocks(self) -> list[tuple[int, int, int]]:
        """Indices (i, j, k) of the meshed blocks, in blockMesh order."""
        nx, ny, nz = self.shape
        return [(i, j, k) for k, j, i in product(range(nz), range(ny), range(nx)) if (i, j, k) not in self.holes]

    def cell_count(self) -> int:
        return sum(self.x[i].cells * self.y[j].cells * self.z[k].cells for i, j, k in self.blocks())

    def vertex_index(self, i: int, j: int, k: int) -> int:
        """Index of grid point (i, j, k) (plane indices) in `vertices()`."""
        nx, ny, _ = self.shape
        return i + (nx + 1) * (j + (ny + 1) * k)

    def vertices(self) -> np.ndarray:
        """All plane intersections, placed in the scene: shape (n, 3)."""
        xs, ys, zs = self.planes("x"), self.planes("y"), self.planes("z")
        pts = np.array([(x, y, z) for z, y, x in product(zs, ys, xs)], dtype=float)
        return pts @ np.asarray(self.rotation, dtype=float).T + np.asarray(self.origin, dtype=float)

    def hex_vertices(self, i: int, j: int, k: int) -> tuple[int, ...]:
        """The 8 vertex indices of block (i, j, k) in blockMesh's hex order."""
        v = self.vertex_index
        return (
            v(i, j, k), v(i + 1, j, k), v(i + 1, j + 1, k), v(i, j + 1, k),
            v(i, j, k + 1), v(i + 1, j, k + 1), v(i + 1, j + 1, k + 1), v(i, j + 1, k + 1),
        )

    def boundary_faces(self) -> dict[str, list[tuple[int, int, int, int]]]:
        """Boundary faces grouped by OpenFOAM patch name (outward normals)."""
        meshed = set(self.blocks())
        nx, ny, nz = self.shape
        out: dict[str, list[tuple[int, int, int, int]]] = {}
        for i, j, k in self.blocks():
            hexv = self.hex_vertices(i, j, k)
            for side, (di, dj, dk) in _NEIGHBOUR.items():
                n = (i + di, j + dj, k + dk)
                if n in meshed:
                    continue
                inside = 0 <= n[0] < nx and 0 <= n[1] < ny and 0 <= n[2] < nz
                key = self.hole_sides.get(n, "hole") if inside else side
                patch = self.patch_names.get(key, key)
                out.setdefault(patch, []).append(tuple(hexv[q] for q in SIDE_FACES[side]))
        return out
