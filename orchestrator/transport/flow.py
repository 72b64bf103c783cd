"""The recorded flow a one-way transport run carries its bodies through.

A :class:`FlowField` is the water of one flow-only run on a regular grid: frame times ``t_k``
(s), plan positions ``x_i``, ``y_j`` (m) and levels ``z_l`` (m, absolute), the flat bed's
elevation, the free-surface elevation ``eta[k, i, j]`` (m, absolute z) and the water velocity
``u[k, i, j, l, :]`` (m/s). Velocities above the surface are stored (the recorder writes the
grid as it is) but never read: a sample point above the local surface is sampled at the
surface (see :meth:`FlowField.sample`).

Why this shape
--------------
* A regular grid keeps sampling a gather of 8 (space) x 2 (time) corners per point: no search
  tree, no mesh connectivity, and the cost of a step does not depend on the CFD mesh.
* Trilinear in space, linear in time: the sampled field is continuous, so the forcing on a
  body moving through it is continuous, and its derivatives exist cell by cell; the
  material acceleration ``Du/Dt = du/dt + (u . grad) u`` that the added-mass and
  Froude-Krylov forces need comes from the same interpolant (the time derivative between
  frames, the gradient of the trilinear cell), so no second field is stored.
* The bed is one flat plane (the study flume's bed is): the engine models it as a MuJoCo
  plane. A sloped or stepped bed would need a heightfield in the engine as well.
* Outside the recorded box or time span nothing is made up: :class:`FlowCoverageError` (an
  :class:`~orchestrator.core.errors.InputError`) names the coordinate, the value and the range.
  Along z a point below the surface is inside by construction (the levels must span the
  bed to the highest surface; :class:`FlowField` checks it).
* One compressed ``.npz`` holds the arrays and the metadata (a JSON string under
  ``meta``), so a record is one file that :meth:`FlowField.load` reads back exactly.

Synthetic fields for the tests and the benchmark: still water, a uniform current, a
sloped still surface and Ritter's dam break (:mod:`analytical.dambreak`, depth-averaged
velocity taken uniform over the depth).

Units: m, s, m/s, kg/m^3.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import numpy as np

from analytical.dambreak import RitterSolution
from orchestrator.core.errors import InputError

__all__ = ["FORMAT_VERSION", "FRONT_RISE_M", "FlowCoverageError", "FlowField", "FlowSample"]

FORMAT_VERSION = 1
"""Version of the ``.npz`` layout written by :meth:`FlowField.save`."""

FRONT_RISE_M = 0.01
"""The front has reached a point when the surface there stands this far above its first level
(:meth:`FlowField.front_arrival_s`): the gauges' arrival threshold when the impoundment is unknown
(orchestrator.results.metrics.ARRIVAL_THRESHOLD_FALLBACK_M), 2.5 % of the study's 0.40 m."""

#: Relative slack (times the axis span) on the bounds of the record: a point on the edge is inside.
_EDGE = 1e-9


class FlowCoverageError(InputError):
    """A point or time outside what the record covers (names the coordinate and its range)."""


class FlowSample(NamedTuple):
    """The flow at a set of points at one time.

    ``eta_m`` (P,): the free surface above each point; ``velocity_m_s`` (P, 3); ``material_
    acceleration_m_s2`` (P, 3): ``du/dt + (u . grad) u`` (zeros when not asked for).
    """

    eta_m: np.ndarray
    velocity_m_s: np.ndarray
    material_acceleration_m_s2: np.ndarray


def _axis(name: str, values, minimum: int = 2) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1 or arr.size < minimum:
        raise InputError(f"flow.{name}", f"must be a 1-D array of at least {minimum} values, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"flow.{name}", "must be finite")
    if np.any(np.diff(arr) <= 0.0):
        raise InputError(f"flow.{name}", "must be strictly increasing")
    arr = arr.copy()
    arr.flags.writeable = False
    return arr


def _uniform_step(axis: np.ndarray) -> float | None:
    """The spacing of an evenly spaced axis, None otherwise."""
    step = (float(axis[-1]) - float(axis[0])) / (axis.size - 1)
    return step if np.allclose(np.diff(axis), step, rtol=1e-9, atol=0.0) else None


def _locate(axis: np.ndarray, values: np.ndarray, name: str, unit: str = "m",
            step: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Cell index (lower corner) and fraction along ``axis`` for each value; raises outside.

    A uniform axis (the usual record) is located by arithmetic, any other by bisection."""
    lo, hi = float(axis[0]), float(axis[-1])
    slack = _EDGE * (hi - lo)
    if values.size and (values.min() < lo - slack or values.max() > hi + slack):
        outside = (values < lo - slack) | (values > hi + slack)
        bad = float(values[np.argmax(outside)])
        raise FlowCoverageError(f"flow.{name}", f"{bad:.6g} {unit} is outside the recorded {name} range "
                                                f"[{lo:.6g}, {hi:.6g}] {unit}")
    n = axis.size
    if step is not None:
        pos = (values - lo) / step
        idx = np.minimum(np.maximum(pos.astype(np.intp), 0), n - 2)
        frac = np.minimum(np.maximum(pos - idx, 0.0), 1.0)
        return idx, frac
    idx = np.minimum(np.maximum(np.searchsorted(axis, values, side="right") - 1, 0), n - 2)
    frac = np.minimum(np.maximum((values - axis[idx]) / (axis[idx + 1] - axis[idx]), 0.0), 1.0)
    return idx, frac


#: Corner offsets (a, b, c) of a grid cell, x slowest.
_CORNERS = np.array([(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)], dtype=np.intp)


@dataclass(frozen=True, eq=False)
class FlowField:
    """The recorded flow (see the module notes). Arrays are read-only after construction.

    Attributes
    ----------
    t_s (K,), x_m (I,), y_m (J,), z_m (L,):
        Frame times and grid axes, strictly increasing (at least 2 values each).
    bed_z_m:
        Elevation of the flat bed (m); ``z_m[0] <= bed_z_m``.
    eta_m (K, I, J):
        Free-surface elevation (m, absolute); ``bed_z_m <= eta <= z_m[-1]`` (a dry cell has
        ``eta = bed_z_m``).
    velocity_m_s (K, I, J, L, 3):
        Water velocity (m/s); float32 or float64.
    water_density_kg_m3, gravity_m_s2:
        The fluid the record was made with.
    meta:
        Free-form provenance (JSON-serialisable: case, solver, sampling notes).
    """

    t_s: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    z_m: np.ndarray
    bed_z_m: float
    eta_m: np.ndarray
    velocity_m_s: np.ndarray
    water_density_kg_m3: float = 998.0
    gravity_m_s2: float = 9.81
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        for name in ("t_s", "x_m", "y_m", "z_m"):
            object.__setattr__(self, name, _axis(name, getattr(self, name)))
        shape = (self.t_s.size, self.x_m.size, self.y_m.size)
        eta = np.asarray(self.eta_m, dtype=float)
        if eta.shape != shape:
            raise InputError("flow.eta_m", f"must have shape (t, x, y) = {shape}, got {eta.shape}")
        u = np.asarray(self.velocity_m_s)
        if u.dtype not in (np.float32, np.float64):
            u = u.astype(float)
        if u.shape != shape + (self.z_m.size, 3):
            raise InputError("flow.velocity_m_s", f"must have shape {shape + (self.z_m.size, 3)}, got {u.shape}")
        if not (np.all(np.isfinite(eta)) and np.all(np.isfinite(u))):
            raise InputError("flow", "eta_m and velocity_m_s must be finite")
        bed = float(self.bed_z_m)
        if not math.isfinite(bed) or bed < self.z_m[0] - 1e-12:
            raise InputError("flow.bed_z_m", f"must be finite and >= the lowest level {self.z_m[0]:.6g} m, got {bed}")
        tol = 1e-9 * max(1.0, float(self.z_m[-1] - self.z_m[0]))
        if np.any(eta < bed - tol) or np.any(eta > self.z_m[-1] + tol):
            raise InputError("flow.eta_m", f"must lie between the bed ({bed:.6g} m) and the highest level "
                                           f"({self.z_m[-1]:.6g} m): the levels must span the water")
        for name in ("water_density_kg_m3", "gravity_m_s2"):
            value = float(getattr(self, name))
            if not math.isfinite(value) or value <= 0.0:
                raise InputError(f"flow.{name}", f"must be > 0, got {value}")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "bed_z_m", bed)
        eta = np.array(eta, dtype=float)
        # The velocities are held component by component, (t, 3, x y z): sample() gathers the
        # corners of each component as one np.take (numpy's multi-index fancy indexing is many
        # times slower) and blends them with one einsum. ``velocity_m_s`` is a view of it.
        planes = np.ascontiguousarray(u.reshape(self.t_s.size, -1, 3).transpose(0, 2, 1))
        u = planes.transpose(0, 2, 1).reshape(u.shape)
        for a in (eta, planes, u):
            a.flags.writeable = False
        object.__setattr__(self, "eta_m", eta)
        object.__setattr__(self, "velocity_m_s", u)
        object.__setattr__(self, "meta", dict(self.meta))
        object.__setattr__(self, "_steps", {n: _uniform_step(getattr(self, n)) for n in ("t_s", "x_m", "y_m", "z_m")})
        object.__setattr__(self, "_eta_flat", eta.reshape(self.t_s.size, -1))
        object.__setattr__(self, "_planes", planes)

    # ------------------------------------------------------------------ extent
    @property
    def nbytes(self) -> int:
        """Bytes held by the arrays (in memory; the .npz is compressed)."""
        return int(sum(a.nbytes for a in (self.t_s, self.x_m, self.y_m, self.z_m, self.eta_m, self.velocity_m_s)))

    @property
    def time_span_s(self) -> tuple[float, float]:
        return float(self.t_s[0]), float(self.t_s[-1])

    @property
    def extent_m(self) -> tuple[tuple[float, float], tuple[float, float], tuple[float, float]]:
        """((x0, x1), (y0, y1), (z0, z1)) of the record."""
        return tuple((float(a[0]), float(a[-1])) for a in (self.x_m, self.y_m, self.z_m))  # type: ignore[return-value]

    # ------------------------------------------------------------------ sampling
    def _time(self, t_s: float) -> tuple[int, float, float]:
        k, frac = _locate(self.t_s, np.array([float(t_s)]), "t", "s", self._steps["t_s"])
        k0 = int(k[0])
        return k0, float(frac[0]), float(self.t_s[k0 + 1] - self.t_s[k0])

    def locate(self, x_m, y_m, t_s: float) -> tuple:
        """Where plan points ``(x_m, y_m)`` (1-D) and ``t_s`` are in the record: ``(k, ft, dt, i,
        fx, j, fy)``, frame, fraction and frame spacing, then the x and y cells and fractions.
        :meth:`surface` and :meth:`sample` take it (``located``) instead of finding it again:
        a caller that reads the surface and then samples below it locates its points once."""
        i, fx = _locate(self.x_m, np.asarray(x_m, dtype=float), "x", step=self._steps["x_m"])
        j, fy = _locate(self.y_m, np.asarray(y_m, dtype=float), "y", step=self._steps["y_m"])
        return (*self._time(t_s), i, fx, j, fy)

    def surface(self, x_m, y_m, t_s: float, located=None) -> np.ndarray:
        """Free-surface elevation (m) at plan points ``(x_m, y_m)`` (same shape) at ``t_s``
        (``located``: :meth:`locate` of them, flattened)."""
        x = np.asarray(x_m, dtype=float)
        y = np.asarray(y_m, dtype=float)
        k, ft, _, i, fx, j, fy = located or self.locate(x.reshape(-1), y.reshape(-1), t_s)
        nj = self.y_m.size
        q = np.take(self._eta_flat[k:k + 2], (i * nj + j)[None, :] + np.array([0, nj, 1, nj + 1])[:, None], axis=1)
        gx = 1.0 - fx
        corners = (q[:, 0] * gx + q[:, 1] * fx) * (1.0 - fy) + (q[:, 2] * gx + q[:, 3] * fx) * fy
        return (corners[0] * (1.0 - ft) + corners[1] * ft).reshape(x.shape)

    def front_arrival_s(self, x_m: float, y_m: float, rise_m: float = FRONT_RISE_M) -> float:
        """First record time (s) at which the surface at plan point ``(x_m, y_m)`` stands ``rise_m``
        above its level in the record's first frame, interpolated between frames; NaN if it never
        does (the front has not reached the point within the record)."""
        located = self.locate(np.array([float(x_m)]), np.array([float(y_m)]), float(self.t_s[0]))
        _, _, _, i, fx, j, fy = located
        nj = self.y_m.size
        q = self._eta_flat[:, (i * nj + j)[0] + np.array([0, nj, 1, nj + 1])]
        gx, gy = 1.0 - float(fx[0]), float(fy[0])
        level = (q[:, 0] * gx + q[:, 1] * (1.0 - gx)) * (1.0 - gy) + (q[:, 2] * gx + q[:, 3] * (1.0 - gx)) * gy
        target = level[0] + float(rise_m)
        above = np.flatnonzero(level > target)
        if above.size == 0:
            return math.nan
        k = int(above[0])
        if k == 0:
            return float(self.t_s[0])
        e0, e1 = level[k - 1], level[k]
        return float(self.t_s[k - 1] + (target - e0) / (e1 - e0) * (self.t_s[k] - self.t_s[k - 1]))

    def sample(self, points_m, t_s: float, acceleration: bool = True, eta_m=None, located=None) -> FlowSample:
        """Surface, velocity and (with ``acceleration``) material acceleration at ``points_m`` (P, 3).

        A point above the local surface is sampled at the surface (z clamped to ``eta``),
        so a partly submerged sub-volume sees the water at the surface. ``eta_m`` (P,): the
        surface there if already known; ``located``: :meth:`locate` of the points if known.
        Raises :class:`FlowCoverageError` for x, y or t outside the record.

        The trilinear interpolant is a weighted sum of the cell's 8 corners at both frames (16
        weights a point, blended linearly in time); the material acceleration is a second
        weighted sum of the same corners, its weights the interpolant's derivatives in time and
        along x, y and z (each times the velocity along it), in float64 whatever the record's type.
        """
        p = np.asarray(points_m, dtype=float).reshape(-1, 3)
        located = located or self.locate(p[:, 0], p[:, 1], t_s)
        eta = self.surface(p[:, 0], p[:, 1], t_s, located) if eta_m is None else np.asarray(eta_m, float).reshape(-1)
        k, ft, dt, i, fx, j, fy = located
        z = np.minimum(np.maximum(np.minimum(p[:, 2], eta), max(self.z_m[0], self.bed_z_m)), self.z_m[-1])
        l_, fz = _locate(self.z_m, z, "z", step=self._steps["z_m"])
        nj, nl = self.y_m.size, self.z_m.size
        offsets = (_CORNERS[:, 0] * nj + _CORNERS[:, 1]) * nl + _CORNERS[:, 2]  # (8,)
        # (frame, component, corner, P), corners in _CORNERS' order (x slowest)
        c = np.take(self._planes[k:k + 2], ((i * nj + j) * nl + l_)[None, :] + offsets[:, None], axis=2)
        gx, gy, gz = 1.0 - fx, 1.0 - fy, 1.0 - fz
        w_yz = np.stack([gy * gz, gy * fz, fy * gz, fy * fz])  # the (y, z) corners' weights
        w = np.concatenate([gx * w_yz, fx * w_yz])  # (8, P)
        u_t = np.einsum("fcp,fkcp->pk", np.stack([(1.0 - ft) * w, ft * w]), c)
        if not acceleration:
            return FlowSample(eta, u_t, np.zeros_like(u_t))
        # d/dt + (u . grad): the corners' weights differentiated along t, x, y and z
        ax = u_t[:, 0] / (self.x_m[i + 1] - self.x_m[i])
        ay = u_t[:, 1] / (self.y_m[j + 1] - self.y_m[j])
        az = u_t[:, 2] / (self.z_m[l_ + 1] - self.z_m[l_])
        d_yz = np.stack([-gz * ay - gy * az, -fz * ay + gy * az, gz * ay - fy * az, fz * ay + fy * az])
        d_x = ax * w_yz
        space = np.concatenate([gx * d_yz - d_x, fx * d_yz + d_x])  # (8, P)
        w_t = w / dt
        accel = np.einsum("fcp,fkcp->pk", np.stack([(1.0 - ft) * space - w_t, ft * space + w_t]), c)
        return FlowSample(eta, u_t, accel)

    # ------------------------------------------------------------------ files
    def save(self, path) -> Path:
        """Write one compressed ``.npz`` (arrays + JSON metadata under ``meta``); returns the path."""
        path = Path(path)
        meta = {"format_version": FORMAT_VERSION, "bed_z_m": self.bed_z_m,
                "water_density_kg_m3": self.water_density_kg_m3, "gravity_m_s2": self.gravity_m_s2,
                "meta": self.meta}
        with open(path, "wb") as fh:
            np.savez_compressed(fh, t_s=self.t_s, x_m=self.x_m, y_m=self.y_m, z_m=self.z_m, eta_m=self.eta_m,
                                velocity_m_s=self.velocity_m_s, meta=np.array(json.dumps(meta)))
        return path

    @classmethod
    def load(cls, path) -> "FlowField":
        """Read a record written by :meth:`save`."""
        path = Path(path)
        if not path.is_file():
            raise InputError("flow", f"no flow record at {path}")
        with np.load(path, allow_pickle=False) as data:
            missing = {"t_s", "x_m", "y_m", "z_m", "eta_m", "velocity_m_s", "meta"} - set(data.files)
            if missing:
                raise InputError("flow", f"{path} is not a flow record (missing {sorted(missing)})")
            meta = json.loads(str(data["meta"]))
            if meta.get("format_version") != FORMAT_VERSION:
                raise InputError("flow", f"{path}: format version {meta.get('format_version')!r}, "
                                         f"this reader takes {FORMAT_VERSION}")
            return cls(data["t_s"], data["x_m"], data["y_m"], data["z_m"], meta["bed_z_m"], data["eta_m"],
                       data["velocity_m_s"], meta["water_density_kg_m3"], meta["gravity_m_s2"], meta["meta"])

    # ------------------------------------------------------------------ synthetic fields
    @classmethod
    def uniform_current(cls, depth_m: float, velocity_m_s, x_m=(-1.0, 1.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0),
                        bed_z_m: float = 0.0, levels: int = 3, **kw) -> "FlowField":
        """Water of ``depth_m`` moving at the constant ``velocity_m_s`` (3-vector or scalar along x)."""
        if depth_m <= 0.0:
            raise InputError("depth_m", f"must be > 0, got {depth_m}")
        vel = np.asarray(velocity_m_s, float)
        vel = np.array([float(vel), 0.0, 0.0]) if vel.ndim == 0 else vel.reshape(3)
        x, y, t = (np.asarray(a, float) for a in (x_m, y_m, t_s))
        z = np.linspace(bed_z_m, bed_z_m + depth_m, max(int(levels), 2))
        eta = np.full((t.size, x.size, y.size), bed_z_m + depth_m)
        u = np.broadcast_to(vel, (t.size, x.size, y.size, z.size, 3)).copy()
        return cls(t, x, y, z, bed_z_m, eta, u, meta={"synthetic": "uniform_current", "depth_m": depth_m,
                                                      "velocity_m_s": vel.tolist()}, **kw)

    @classmethod
    def still_water(cls, depth_m: float, **kw) -> "FlowField":
        """Still water of ``depth_m`` (m) over the bed."""
        out = cls.uniform_current(depth_m, (0.0, 0.0, 0.0), **kw)
        out.meta.update(synthetic="still_water")
        return out

    @classmethod
    def sloped_surface(cls, depth_m: float, slope: float, x_m=(-1.0, 1.0), y_m=(-0.5, 0.5), t_s=(0.0, 10.0),
                       bed_z_m: float = 0.0, **kw) -> "FlowField":
        """A still surface ``eta = bed + depth + slope x`` (no velocity): a static test of the
        buoyancy's moment, not a flow in equilibrium."""
        x, y, t = (np.asarray(a, float) for a in (x_m, y_m, t_s))
        eta_x = bed_z_m + depth_m + slope * x
        if np.any(eta_x <= bed_z_m):
            raise InputError("slope", "the surface must stay above the bed over the x range")
        z = np.linspace(bed_z_m, float(eta_x.max()), 3)
        eta = np.broadcast_to(eta_x[None, :, None], (t.size, x.size, y.size)).copy()
        u = np.zeros((t.size, x.size, y.size, z.size, 3))
        return cls(t, x, y, z, bed_z_m, eta, u, meta={"synthetic": "sloped_surface", "depth_m": depth_m,
                                                      "slope": slope}, **kw)

    @classmethod
    def ritter(cls, reservoir_depth_m: float, x_m, t_s, y_m=(-0.75, 0.75), levels: int = 4, bed_z_m: float = 0.0,
               gravity_m_s2: float = 9.81, **kw) -> "FlowField":
        """Ritter's dam break (gate at x = 0 at t = 0, dry frictionless bed) sampled on
        ``x_m`` x ``t_s`` (arrays), uniform across ``y_m`` and over the depth (its velocity
        is depth-averaged); a realistic bore for the benchmark, not a measured flow."""
        sol = RitterSolution(reservoir_depth_m, gravity_m_s2)
        x, y, t = (np.asarray(a, float) for a in (x_m, y_m, t_s))
        depth = np.empty((t.size, x.size))
        speed = np.empty((t.size, x.size))
        for k, tk in enumerate(t):
            prof = sol.profile(x, max(float(tk), 0.0))
            depth[k], speed[k] = prof.depth_m, prof.velocity_m_s
        z = np.linspace(bed_z_m, bed_z_m + reservoir_depth_m, max(int(levels), 2))
        eta = np.broadcast_to((bed_z_m + depth)[:, :, None], (t.size, x.size, y.size)).copy()
        u = np.zeros((t.size, x.size, y.size, z.size, 3), dtype=np.float32)
        u[..., 0] = speed[:, :, None, None]
        return cls(t, x, y, z, bed_z_m, eta, u, gravity_m_s2=gravity_m_s2,
                   meta={"synthetic": "ritter", "reservoir_depth_m": reservoir_depth_m}, **kw)
