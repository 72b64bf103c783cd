"""Oriented boxes: exact distance, contact point and normal between boxes, and to a plane.

The contact watch (`orchestrator.contact.geometry`) models every body and the column as an
oriented box and the walls and bed as planes; this module is their geometry.

Box-box geometry. Overlap is decided by the separating-axis test over the 15 axes (the
boxes' face normals and the 9 cross products of their edges). For separated boxes the
distance is exact: the closest points of two convex polyhedra lie on a vertex-face or an
edge-edge pair (degenerate cases such as vertex-vertex are limits of these), so the minimum
over the 16 vertex-to-box distances (vertex clamped into the other box's frame) and the 144
edge-edge segment distances is the distance. The contact point is the midpoint of the
closest pair; when a whole patch is closest (parallel faces, parallel edges) it is the
mean of the closest pairs found at the patch corners. For touching or overlapping boxes the
normal is the axis of least penetration (face axes preferred on ties), the distance is minus
that depth, and the point is the centroid of the vertices of the intersection polytope
(each box's faces clipped by the other's six half-spaces).

Units: m. Normals point from the other box (or the plane) into the box.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from orchestrator.core.errors import InputError

__all__ = [
    "Box",
    "Proximity",
    "box_box",
    "box_box_proximity",
    "box_plane",
    "box_plane_proximity",
    "freeze",
    "sat_axes",
    "sat_lower_bound",
    "vec3",
]

#: Relative tolerance on lengths (times the larger box size) for coincident points.
_REL_TOL = 1e-9
#: Box-plane contacts (bed, walls): corners closer than the nearest by less than this (times
#: the box size) share the contact, so a face within 0.1 % of parallel is a face contact, not
#: a corner contact (a body rolled by 1e-6 rad must not pick up a spurious yaw from one
#: corner). Box-box contacts stay exact (their point lies on both surfaces).
_FEATURE_REL_TOL = 1e-3


@dataclass(frozen=True)
class Proximity:
    """Closest approach of a body to something: signed distance (m; < 0 = penetration
    depth), contact point (m) and unit normal from the other thing into the body."""

    distance_m: float
    point: np.ndarray
    normal: np.ndarray


def box_box_proximity(
    centre_a, orientation_a, size_a, centre_b, orientation_b, size_b
) -> Proximity:
    """Signed distance, contact point and normal (from box b into box a) of two oriented boxes.

    Sizes are full edge lengths along each box's axes (the columns of its orientation).
    """
    return box_box(Box.make(centre_a, orientation_a, size_a), Box.make(centre_b, orientation_b, size_b))


def box_plane_proximity(centre, orientation, size, plane_point, plane_normal) -> Proximity:
    """Signed distance of an oriented box from a plane (normal into the box's side)."""
    n = np.asarray(plane_normal, float)
    n = n / np.linalg.norm(n)
    return box_plane(Box.make(centre, orientation, size), np.asarray(plane_point, float), n)


# Corner i has body signs ((i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1) -> -1/+1.
_SIGNS = np.array([[1.0 if (i >> k) & 1 else -1.0 for k in range(3)] for i in range(8)])
# The 12 edges: corner pairs that differ in one sign.
_EDGES = np.array([(i, i | (1 << k)) for k in range(3) for i in range(8) if not (i >> k) & 1])
# The 6 faces as corner loops (outward normal along axis k, sign s).
_FACES = []
for _k in range(3):
    _a, _b = (_k + 1) % 3, (_k + 2) % 3
    for _s in (0, 1):
        _base = _s << _k
        _loop = [_base, _base | (1 << _a), _base | (1 << _a) | (1 << _b), _base | (1 << _b)]
        _FACES.append(_loop)
_FACES = np.array(_FACES)


@dataclass(frozen=True)
class Box:
    """An oriented box: centre, rotation (columns: the box axes) and half sizes."""

    centre: np.ndarray
    rot: np.ndarray  # columns: the box axes
    half: np.ndarray

    @classmethod
    def make(cls, centre, rot, size) -> "Box":
        c = vec3("centre", centre)
        r = np.array(rot, dtype=float)
        if r.shape != (3, 3):
            raise InputError("orientation", f"must be 3x3, got shape {r.shape}")
        s = vec3("size", size)
        if np.any(s <= 0.0):
            raise InputError("size", f"must all be > 0, got {s.tolist()}")
        return cls(c, r, s / 2.0)

    @classmethod
    def of(cls, state) -> "Box":
        """The box of a body state with its box (a BodyState: centre_of_mass_m, rotation, size_m)."""
        return cls(np.asarray(state.centre_of_mass_m, float), state.rotation, np.asarray(state.size_m, float) / 2.0)

    @classmethod
    def of_obstacle(cls, obs) -> "Box":
        """The box of a box obstacle (its centre_m, orientation and size_m)."""
        return cls.make(obs.centre_m, obs.orientation, obs.size_m)

    def corners(self) -> np.ndarray:
        return self.centre + (_SIGNS * self.half) @ self.rot.T

    def radius(self, axis: np.ndarray) -> float:
        """Half-extent of the box's projection on a unit axis."""
        return float(np.sum(self.half * np.abs(self.rot.T @ axis)))

    def closest_point(self, p: np.ndarray) -> np.ndarray:
        """Closest point of the (solid) box to each row of ``p``."""
        local = (p - self.centre) @ self.rot
        return self.centre + np.clip(local, -self.half, self.half) @ self.rot.T

    def scale(self) -> float:
        return float(2.0 * np.max(self.half))


def sat_axes(a: Box, b: Box) -> list[np.ndarray]:
    axes = [a.rot[:, i] for i in range(3)] + [b.rot[:, i] for i in range(3)]
    for i in range(3):
        for j in range(3):
            cross = np.cross(a.rot[:, i], b.rot[:, j])
            norm = np.linalg.norm(cross)
            if norm > 1e-9:
                axes.append(cross / norm)
    return axes


def _sat_separations(a: Box, b: Box):
    """(axis, separation along it) for the 15 axes; separation > 0 means a separating axis."""
    d = b.centre - a.centre
    out = []
    for k, axis in enumerate(sat_axes(a, b)):
        out.append((k < 6, axis, abs(float(d @ axis)) - a.radius(axis) - b.radius(axis)))
    return out


def sat_lower_bound(a: Box, b: Box) -> float:
    """A lower bound on the distance between the boxes (the largest axis separation)."""
    return max(sep for _, _, sep in _sat_separations(a, b))


def box_plane(box: Box, point: np.ndarray, n: np.ndarray) -> Proximity:
    corners = box.corners()
    dist = (corners - point) @ n
    d = float(dist.min())
    near = dist <= d + _FEATURE_REL_TOL * box.scale()
    feature = corners[near].mean(axis=0)  # a vertex, an edge midpoint or a face centre
    p = feature - 0.5 * d * n
    return _proximity(d, p, n)


def box_box(a: Box, b: Box) -> Proximity:
    """Proximity of box ``a`` (the body) to box ``b``; normal from b into a."""
    scale = max(a.scale(), b.scale())
    tol = _REL_TOL * scale
    seps = _sat_separations(a, b)
    best = max(seps, key=lambda s: s[2])
    if best[2] > tol:
        return _separated(a, b, tol)
    # Touching or overlapping: the axis of least penetration, face axes preferred on ties.
    face = max((s for s in seps if s[0]), key=lambda s: s[2])
    edges = [s for s in seps if not s[0]]
    chosen = face
    if edges:
        edge = max(edges, key=lambda s: s[2])
        if edge[2] > face[2] + tol:
            chosen = edge
    _, axis, sep = chosen
    normal = axis if float((a.centre - b.centre) @ axis) >= 0.0 else -axis
    point = _intersection_centroid(a, b, normal, tol)
    return _proximity(min(sep, 0.0), point, normal)


def _separated(a: Box, b: Box, tol: float) -> Proximity:
    """Exact distance of separated boxes: vertex-box and edge-edge candidates."""
    ca, cb = a.corners(), b.corners()
    pa = [ca, b.closest_point(ca)]  # a's vertices and their closest points on b
    qb = [a.closest_point(cb), cb]  # points on a closest to b's vertices, and the vertices
    p_a = np.vstack([pa[0], qb[0]])
    p_b = np.vstack([pa[1], qb[1]])
    ea, eb = _segment_pairs(ca[_EDGES[:, 0]], ca[_EDGES[:, 1]], cb[_EDGES[:, 0]], cb[_EDGES[:, 1]])
    p_a = np.vstack([p_a, ea])
    p_b = np.vstack([p_b, eb])
    gaps = np.linalg.norm(p_a - p_b, axis=1)
    d = float(gaps.min())
    best = int(np.argmin(gaps))
    normal = (p_a[best] - p_b[best]) / d
    near = gaps <= d + tol
    mids = 0.5 * (p_a[near] + p_b[near])
    point = _unique_rows(mids, tol).mean(axis=0)
    return _proximity(d, point, normal)


def _segment_pairs(p0, p1, q0, q1):
    """Closest points of every segment ``p0[i]-p1[i]`` to every ``q0[j]-q1[j]`` (flattened)."""
    P0 = np.repeat(p0, len(q0), axis=0)
    D1 = np.repeat(p1 - p0, len(q0), axis=0)
    Q0 = np.tile(q0, (len(p0), 1))
    D2 = np.tile(q1 - q0, (len(p0), 1))
    r = P0 - Q0
    a = np.einsum("ij,ij->i", D1, D1)
    e = np.einsum("ij,ij->i", D2, D2)
    b = np.einsum("ij,ij->i", D1, D2)
    c = np.einsum("ij,ij->i", D1, r)
    f = np.einsum("ij,ij->i", D2, r)
    denom = a * e - b * b
    parallel = denom <= 1e-12 * a * e
    # Unconstrained minimiser of |P0 + s D1 - Q0 - t D2|^2 for s, clamped; then t for that s.
    s = np.where(parallel, 0.0, np.clip((b * f - c * e) / np.where(parallel, 1.0, denom), 0.0, 1.0))
    t = (b * s + f) / e
    # t outside [0, 1]: clamp it and recompute s for that t.
    low, high = t < 0.0, t > 1.0
    t = np.clip(t, 0.0, 1.0)
    s = np.where(low, np.clip(-c / a, 0.0, 1.0), s)
    s = np.where(high, np.clip((b - c) / a, 0.0, 1.0), s)
    return P0 + s[:, None] * D1, Q0 + t[:, None] * D2


def _intersection_centroid(a: Box, b: Box, normal: np.ndarray, tol: float) -> np.ndarray:
    """Centroid of the intersection of two touching/overlapping boxes.

    The intersection polytope's vertices come from each box's faces clipped by the other's
    six half-spaces; the centroid is that of its volume, or, when it is flat (touching
    boxes), of its area seen along ``normal``, or of its extent when it is a segment or a point.
    """
    points = []
    for clip, by in ((a, b), (b, a)):
        corners = clip.corners()
        for face in _FACES:
            poly = corners[face]
            for k in range(3):
                axis = by.rot[:, k]
                centre = float(by.centre @ axis)
                poly = _clip(poly, axis, centre + by.half[k] + tol)
                if len(poly) == 0:
                    break
                poly = _clip(poly, -axis, -centre + by.half[k] + tol)
                if len(poly) == 0:
                    break
            if len(poly):
                points.append(poly)
    if not points:  # numerically touching at a point the clipping lost: the closest corner pair
        ca = a.corners()
        pa = b.closest_point(ca)
        ia = int(np.argmin(np.linalg.norm(ca - pa, axis=1)))
        return 0.5 * (ca[ia] + pa[ia])
    pts = _unique_rows(np.vstack(points), tol)
    return _centroid(pts, normal, tol)


def _centroid(pts: np.ndarray, normal: np.ndarray, tol: float) -> np.ndarray:
    """Volume centroid of the convex hull of ``pts``; area centroid across ``normal`` if flat."""
    mean = pts.mean(axis=0)
    heights = pts @ normal
    flat = float(heights.max() - heights.min()) <= 100.0 * tol  # touching: a patch, not a volume
    if len(pts) >= 4 and not flat:
        try:
            hull = ConvexHull(pts)
        except QhullError:
            hull = None
        if hull is not None and hull.volume > tol**3:
            tri = pts[hull.simplices]  # (m, 3, 3) boundary triangles
            # tetrahedra from an interior point (the vertex mean) to each boundary triangle;
            # qhull does not orient its simplices, hence the absolute value
            vols = np.abs(np.einsum("ij,ij->i", tri[:, 0] - mean, np.cross(tri[:, 1] - mean, tri[:, 2] - mean))) / 6.0
            cents = (tri.sum(axis=1) + mean) / 4.0
            return (vols[:, None] * cents).sum(axis=0) / vols.sum()
    if len(pts) >= 3:
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        e1 = np.cross(normal, helper)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        uv = np.column_stack([(pts - mean) @ e1, (pts - mean) @ e2])
        try:
            hull = ConvexHull(uv)
        except QhullError:
            hull = None
        if hull is not None and hull.volume > tol**2:  # in 2-D, volume is the area
            ring = uv[hull.vertices]
            x, y = ring[:, 0], ring[:, 1]
            xn, yn = np.roll(x, -1), np.roll(y, -1)
            cross = x * yn - xn * y
            area = cross.sum() / 2.0
            cx = ((x + xn) * cross).sum() / (6.0 * area)
            cy = ((y + yn) * cross).sum() / (6.0 * area)
            depth = float(((pts - mean) @ normal).mean())
            return mean + cx * e1 + cy * e2 + depth * normal
    # a segment or a point: the middle of its extent
    return 0.5 * (pts.min(axis=0) + pts.max(axis=0)) if len(pts) > 1 else pts[0]


def _clip(poly: np.ndarray, n: np.ndarray, offset: float) -> np.ndarray:
    """Sutherland-Hodgman: the part of polygon ``poly`` with ``x . n <= offset``."""
    out = []
    m = len(poly)
    dist = poly @ n - offset
    for i in range(m):
        cur, nxt = poly[i], poly[(i + 1) % m]
        dc, dn = dist[i], dist[(i + 1) % m]
        if dc <= 0.0:
            out.append(cur)
        if (dc < 0.0 < dn) or (dn < 0.0 < dc):
            out.append(cur + (dc / (dc - dn)) * (nxt - cur))
    return np.array(out).reshape(-1, 3)


def _unique_rows(points: np.ndarray, tol: float) -> np.ndarray:
    kept: list[np.ndarray] = []
    for p in points:
        if not any(np.linalg.norm(p - q) <= tol for q in kept):
            kept.append(p)
    return np.array(kept)


def _proximity(d: float, point: np.ndarray, normal: np.ndarray) -> Proximity:
    point = np.array(point, dtype=float)
    normal = np.array(normal, dtype=float) / np.linalg.norm(normal)
    point.setflags(write=False)
    normal.setflags(write=False)
    return Proximity(float(d), point, normal)


def vec3(name: str, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be 3 numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise InputError(name, f"must be 3 finite numbers, got {value!r}")
    return arr


def freeze(obj, name: str, arr: np.ndarray) -> None:
    arr = np.array(arr, dtype=float)
    arr.setflags(write=False)
    object.__setattr__(obj, name, arr)
