"""Hydrodynamic forcing of a rigid box in a known flow (one-way coupling): numbers in, forces out.

The body is split into a grid of sub-volumes in its own frame (default 5 x 3 x 3 along its
length, width and height; :func:`sub_volumes`). Each sub-volume ``i`` of volume ``dV`` at
world point ``p_i`` sees the recorded water there: the local free surface ``eta_i``, the
velocity ``u_i`` and the material acceleration ``Du/Dt_i``. Summing its forces over the
sub-volumes, each applied at its centre, gives the force on the body and its moment about
the centre of mass, so heave, pitch and roll answer the surface *across* the body: a body
half in a bore is pushed up and turned by the half that is wet.

Per sub-volume (:func:`hydro_loads`):

* **Submerged fraction** ``f_i``: the sub-volume's vertical extent is its box's (rotated
  extent ``2 h_i = sum_k |R_zk| s_k`` of the sub-box sizes ``s_k``), ``f_i = clip((eta_i -
  (z_i - h_i)) / (2 h_i), 0, 1)``. A level box in a level surface gets exactly the
  submerged volume ``A draft``; tilted, it is the linear (first-order) estimate, continuous
  in the pose. ``V_sub = sum f_i dV``.
* **Buoyancy** (hydrostatic pressure of the local surface) ``rho g f_i dV`` upward at
  ``p_i``. Only its vertical part: the horizontal pressure gradient of the flow comes from the
  next term, which already contains it (in a hydrostatic flow ``Du/Dt = -g grad(eta)``);
  taking it from the slope of ``eta`` as well would count it twice.
* **Froude-Krylov and the fluid part of added mass** ``rho f_i dV (I + R C R^T) Du/Dt_i``: the
  pressure gradient that accelerates the water (``-grad p = rho (Du/Dt + g z)``) acting on
  the displaced volume, plus the water the body must accelerate with it, ``C`` the added-mass
  coefficients along the body's own axes (surge, sway, heave) relative to the displaced
  volume. By default they are the box's own at its current draft (:func:`added_mass_table`,
  from :mod:`analytical.added_mass`: the 1:40 container afloat carries 0.28 of its displaced
  water lengthwise, 0.84 sideways, 1.04 vertically); ``added_mass_coefficient`` set to a number
  makes them that one value on every axis.
* **Body-acceleration part of added mass** ``-M_a a_body``: not evaluated here. An explicit
  (lagged) force of this form is unstable once the added mass exceeds the body's mass, and a
  floating 1:40 container's heave added mass is about its own mass. It is instead an extra
  inertia: :attr:`HydroLoads.added_mass_kg` (along the body axes) and
  :attr:`HydroLoads.added_inertia_kg_m2` (about them) are added to the body's inertia in the
  integrator (MuJoCo's per-degree-of-freedom armature, refreshed as ``V_sub`` changes), which is
  implicit and unconditionally stable. A free joint's translations are along the world axes,
  so the armature holds the world-diagonal of ``R diag(M_a) R^T``: exact for a body whose axes
  are along the world's, and for a container yawed by ``psi`` it leaves out the sway-surge
  coupling ``(A_y - A_x) sin psi cos psi`` (0.066 kg at 45 degrees against 0.37 kg of inertia
  along either axis). The rotations are about the body's axes: exact. A strike uses the full
  tensor (:meth:`analytical.impact_bodies.Body.box`).
* **Drag** ``0.5 rho C_d (A_k / N) f_i |w_i| w_ik`` along each body axis ``k``, with ``w_i =
  u_i - v_body(p_i)`` the relative velocity at the sub-volume (the body's rotation included,
  so rotation is damped too), ``A_k`` the body's projected area normal to axis ``k`` and ``N``
  the number of sub-volumes: a fully submerged body in a uniform stream gets ``0.5 rho C_d
  A |w| w`` on each axis, a partly submerged one the wetted share of it.

Coefficients and their sources: :class:`HydroCoefficients`. Units: SI (kg, m, s, N).

References
----------
Hoerner, S.F. (1965). Fluid-Dynamic Drag. Hoerner Fluid Dynamics (ch. 3: a cube face-on,
    C_D about 1.05; rectangular blocks 1.0-1.2).
DNV (2010). DNV-RP-C205 Environmental conditions and environmental loads, Appendix A
    (added mass: square section across a side, 2-D, C_A = 1.51; cube, 0.68).
Morison, J.R., O'Brien, M.P., Johnson, J.W. & Schaaf, S.A. (1950). The force exerted by
    surface waves on piles. Petroleum Transactions AIME 189, 149-154.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from analytical.added_mass import box_added_mass
from analytical.errors import InputError, require_finite, require_positive

__all__ = [
    "DEFAULT_ADDED_MASS_COEFFICIENT",
    "DEFAULT_DRAG_COEFFICIENT",
    "FREE_STREAM_BOX_DRAG_COEFFICIENT",
    "HydroCoefficients",
    "HydroLoads",
    "SubVolumes",
    "added_mass_table",
    "archimedes_draft",
    "drag_time_constant",
    "heave_period",
    "hydro_loads",
    "munk_moment",
    "sub_volumes",
    "submerged_fraction",
]

FREE_STREAM_BOX_DRAG_COEFFICIENT = 1.05
"""A box face-on in steady, unbounded flow: Hoerner (1965) ch. 3 gives about 1.05 for a cube and
1.0-1.2 for rectangular blocks."""

DEFAULT_DRAG_COEFFICIENT = FREE_STREAM_BOX_DRAG_COEFFICIENT
"""The C_d of a box on the area it shows the relative flow: Hoerner's free-stream value, not a
fitted one. With the box's own added mass (a container carries 0.28 of its displaced water
lengthwise, not 1.0) it carries the study's container to the column at the speed a C_d of 3.0
gave (1.36 against 1.39 m/s, 0.10 s later: docs/one-way.md, "The drag coefficient"); 3.0 stood
in for the inertia an isotropic C_a = 1 added, since afloat the forcing identifies only
C_d / (1 + C_a)."""

DEFAULT_ADDED_MASS_COEFFICIENT = None
"""None: each box's own added mass along and about its axes at its current draft
(:func:`added_mass_table`, :mod:`analytical.added_mass`), not one value on every axis."""

DRAG_AREAS = ("projected", "per_axis")
"""How drag meets a box: ``projected`` (the default), along the relative flow on the box's
area projected normal to it; ``per_axis``, on each body axis with that axis's face (the
cross-flow principle of slender bodies: a yawed box then 'sails' sideways)."""

ADDED_MASS_TABLE_POINTS = 41
"""Submerged fractions (0 to 1 of the box's volume) at which :func:`added_mass_table` tabulates
a box's added mass; the forcing interpolates linearly between them."""


@dataclass(frozen=True)
class HydroCoefficients:
    """Fluid and coefficients of the forcing (module notes).

    ``sub_volumes`` is the grid (length, width, height) the body is split into; 0 for
    ``drag_coefficient`` or ``added_mass_coefficient`` switches that term off; None for
    ``added_mass_coefficient`` (the default) takes each box's own per axis
    (:func:`added_mass_table`).
    """

    water_density_kg_m3: float = 998.0
    gravity_m_s2: float = 9.81
    drag_coefficient: float = DEFAULT_DRAG_COEFFICIENT
    added_mass_coefficient: float | None = DEFAULT_ADDED_MASS_COEFFICIENT
    sub_volumes: tuple[int, int, int] = (5, 3, 3)
    drag_area: str = "projected"
    munk_moment: bool = True

    def __post_init__(self):
        if self.drag_area not in DRAG_AREAS:
            raise InputError("hydro.drag_area", f"must be one of {DRAG_AREAS}, got {self.drag_area!r}")
        object.__setattr__(self, "munk_moment", bool(self.munk_moment))
        object.__setattr__(self, "water_density_kg_m3",
                           require_positive("hydro.water_density_kg_m3", self.water_density_kg_m3))
        object.__setattr__(self, "gravity_m_s2", require_positive("hydro.gravity_m_s2", self.gravity_m_s2))
        for name in ("drag_coefficient", "added_mass_coefficient"):
            if name == "added_mass_coefficient" and self.added_mass_coefficient is None:
                continue
            value = require_finite(f"hydro.{name}", getattr(self, name))
            if value < 0.0:
                raise InputError(f"hydro.{name}", f"must be >= 0, got {value}")
            object.__setattr__(self, name, value)
        counts = tuple(self.sub_volumes)
        if len(counts) != 3 or any(isinstance(n, bool) or int(n) != n or n < 1 for n in counts):
            raise InputError("hydro.sub_volumes", f"must be three integers >= 1, got {self.sub_volumes!r}")
        object.__setattr__(self, "sub_volumes", tuple(int(n) for n in counts))


class SubVolumes(NamedTuple):
    """A box split into sub-boxes: centres in the body frame (N, 3), each one's size (3,) and volume."""

    centres_m: np.ndarray
    size_m: np.ndarray
    volume_m3: float


class HydroLoads(NamedTuple):
    """Forcing of B bodies: ``force_N`` and ``moment_Nm`` (B, 3; moment about the centre of
    mass, world frame), ``submerged_volume_m3`` (B,), the added mass along the body axes
    ``added_mass_kg`` (B, 3) and about them ``added_inertia_kg_m2`` (B, 3), and the
    sub-volumes' submerged fractions ``fraction`` (B, N)."""

    force_N: np.ndarray
    moment_Nm: np.ndarray
    submerged_volume_m3: np.ndarray
    added_mass_kg: np.ndarray
    fraction: np.ndarray
    added_inertia_kg_m2: np.ndarray


def added_mass_table(size_m, water_density_kg_m3: float = 998.0,
                     points: int = ADDED_MASS_TABLE_POINTS) -> np.ndarray:
    """A box's added masses (surge, sway, heave; kg) and inertias (roll, pitch, yaw; kg m^2)
    at ``points`` submerged fractions from 0 to 1 of its volume: (points, 6). Each row is
    :func:`analytical.added_mass.box_added_mass` of the box floating at that draft (the
    impulsive limit, its sources there); none at 0. Kept per (size, density, points): a batch of
    realisations builds one for each of its bodies, and an ensemble's bodies are one size (about
    3 ms a body for 10,000 realisations otherwise); the caller gets its own copy."""
    size = tuple(float(require_positive("size_m", s)) for s in size_m)
    rho = float(require_positive("water_density_kg_m3", water_density_kg_m3))
    return _added_mass_table(size, rho, int(points)).copy()


@lru_cache(maxsize=64)
def _added_mass_table(size: tuple[float, float, float], rho: float, points: int) -> np.ndarray:
    volume = size[0] * size[1] * size[2]
    table = np.zeros((points, 6))
    for k, f in enumerate(np.linspace(0.0, 1.0, points)):
        if f > 0.0:
            table[k] = box_added_mass(size, rho * volume * f, rho).diagonal
    table.setflags(write=False)
    return table


def _interpolate_table(tables: np.ndarray, fraction: np.ndarray) -> np.ndarray:
    """(B, 6) rows of ``tables`` (B, K, 6) at each body's submerged ``fraction`` (B,)."""
    k = tables.shape[1] - 1
    x = np.clip(fraction, 0.0, 1.0) * k
    lo = np.minimum(np.floor(x).astype(int), k - 1)
    w = (x - lo)[:, None]
    rows = np.arange(tables.shape[0])
    return (1.0 - w) * tables[rows, lo] + w * tables[rows, lo + 1]


def archimedes_draft(mass_kg: float, footprint_m2: float, water_density_kg_m3: float = 998.0) -> float:
    """Draft (m) of a level box of ``mass_kg`` floating on ``footprint_m2``: ``m / (rho A)``."""
    return require_positive("mass_kg", mass_kg) / (
        require_positive("water_density_kg_m3", water_density_kg_m3) * require_positive("footprint_m2", footprint_m2))


def sub_volumes(size_m, counts=(5, 3, 3)) -> SubVolumes:
    """Split a box of ``size_m`` (length, width, height) into ``counts`` equal sub-boxes."""
    size = np.array([require_positive("size_m", s) for s in size_m], dtype=float)
    if size.shape != (3,):
        raise InputError("size_m", f"must have three values, got {size_m!r}")
    n = np.array(counts, dtype=int)
    cell = size / n
    axes = [(np.arange(k) + 0.5) * c - s / 2.0 for k, c, s in zip(n, cell, size)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return SubVolumes(grid, cell, float(np.prod(cell)))


def submerged_fraction(z_m, half_height_m, eta_m) -> np.ndarray:
    """Fraction of a sub-volume of vertical half-extent ``half_height_m`` centred at ``z_m``
    below the surface ``eta_m`` (linear over its height; arrays broadcast)."""
    z = np.asarray(z_m, float)
    h = np.asarray(half_height_m, float)
    return np.clip((np.asarray(eta_m, float) - (z - h)) / (2.0 * h), 0.0, 1.0)


def hydro_loads(
    centre_of_mass_m,
    orientation,
    velocity_m_s,
    angular_velocity_rad_s,
    size_m,
    points_m,
    eta_m,
    water_velocity_m_s,
    water_acceleration_m_s2,
    coefficients: HydroCoefficients,
    added_mass_tables: np.ndarray | None = None,
    local_m: np.ndarray | None = None,
) -> HydroLoads:
    """Force and moment on B boxes from the water at their N sub-volume centres.

    Shapes: ``centre_of_mass_m``, ``velocity_m_s``, ``angular_velocity_rad_s``, ``size_m``
    (B, 3); ``orientation`` (B, 3, 3), body to world; ``points_m`` (B, N, 3) the sub-volume
    centres in the world (from :func:`sub_volumes` with ``coefficients.sub_volumes``);
    ``eta_m`` (B, N) the surface above each; ``water_velocity_m_s`` and
    ``water_acceleration_m_s2`` (B, N, 3) there (read only where submerged);
    ``added_mass_tables`` (B, K, 6) each box's :func:`added_mass_table` (made here when not
    given and ``coefficients.added_mass_coefficient`` is None); ``local_m`` (B, N, 3) the
    sub-volume centres in the body frame if known (``R^T (points - centre)`` otherwise: the
    same to rounding). Returns :class:`HydroLoads`; see the module notes for each term.
    """
    c = coefficients
    com = np.asarray(centre_of_mass_m, float).reshape(-1, 3)
    rot = np.asarray(orientation, float).reshape(-1, 3, 3)
    vel = np.asarray(velocity_m_s, float).reshape(-1, 3)
    omega = np.asarray(angular_velocity_rad_s, float).reshape(-1, 3)
    size = np.asarray(size_m, float).reshape(-1, 3)
    pts = np.asarray(points_m, float)
    n_bodies, n_pts = pts.shape[:2]
    cell = size / np.asarray(c.sub_volumes, float)  # (B, 3)
    dv = np.prod(cell, axis=1)  # (B,)
    half_z = 0.5 * np.einsum("bk,bk->b", np.abs(rot[:, 2, :]), cell)  # (B,)
    frac = submerged_fraction(pts[:, :, 2], half_z[:, None], eta_m)  # (B, N)
    wet_volume = frac * dv[:, None]  # (B, N)
    rho = c.water_density_kg_m3

    sub = wet_volume.sum(axis=1)
    if c.added_mass_coefficient is None:
        if added_mass_tables is None:
            added_mass_tables = np.stack([added_mass_table(s, rho) for s in size])
        added = _interpolate_table(np.asarray(added_mass_tables, float), sub / np.prod(size, axis=1))
        added_mass, added_inertia = added[:, :3], added[:, 3:]
        # per unit displaced mass along each body axis
        ratio = np.divide(added_mass, (rho * sub)[:, None], out=np.zeros_like(added_mass), where=sub[:, None] > 0)
    else:
        added_mass = np.repeat((c.added_mass_coefficient * rho * sub)[:, None], 3, axis=1)
        added_inertia = np.zeros_like(added_mass)
        ratio = np.full_like(added_mass, c.added_mass_coefficient)

    # Every term is formed at every sub-volume in its body's frame (where the added mass is
    # diagonal and the drag areas are the faces'), the dry ones contributing nothing (their
    # wet volume and fraction are zero; their water is not read), summed per body and turned
    # into the world once per body: whole (B, N) arrays, each step one array operation.
    force = np.zeros((n_bodies, 3))
    moment = np.zeros((n_bodies, 3))
    wet = frac > 0.0
    if np.any(wet):
        arm = np.matmul(pts - com[:, None, :], rot) if local_m is None else np.asarray(local_m, float)
        world = np.concatenate([np.asarray(water_velocity_m_s, float).reshape(pts.shape),
                                np.asarray(water_acceleration_m_s2, float).reshape(pts.shape)], axis=1)
        world = np.where(np.concatenate([wet, wet], axis=1)[:, :, None], world, 0.0)
        water, accel = np.split(np.matmul(world, rot), 2, axis=1)  # R^T x: body frame, (B, N, 3) each
        v_b, w_b = np.moveaxis(np.matmul(np.stack([vel, omega], axis=1), rot), 1, 0)  # body frame, (B, 3)
        # the body's velocity at each sub-volume, v + omega x r, as r @ S^T + v (S = [omega]x)
        spin = np.zeros((n_bodies, 3, 3))
        spin[:, 0, 1], spin[:, 0, 2], spin[:, 1, 0] = w_b[:, 2], -w_b[:, 1], -w_b[:, 2]
        spin[:, 1, 2], spin[:, 2, 0], spin[:, 2, 1] = w_b[:, 0], w_b[:, 1], -w_b[:, 0]
        rel = water - (np.matmul(arm, spin) + v_b[:, None, :])  # the water past the body
        # buoyancy (world +z is row 2 of R in the body frame) and (I + diag(C)) Du/Dt
        f = (1.0 + ratio[:, None, :]) * accel
        f += c.gravity_m_s2 * rot[:, None, 2, :]
        f *= (rho * wet_volume)[:, :, None]
        if c.drag_coefficient > 0.0:
            area = np.stack([size[:, 1] * size[:, 2], size[:, 0] * size[:, 2], size[:, 0] * size[:, 1]], axis=1)
            if c.drag_area == "projected":
                # the box's area seen along the relative flow: sum_k A_k |w_k| / |w|
                seen = np.matmul(np.abs(rel), area[:, :, None])[:, :, 0]  # A_p |w|
                f += ((0.5 * rho * c.drag_coefficient / n_pts) * (frac * seen))[:, :, None] * rel
            else:
                speed = np.sqrt(np.einsum("bnk,bnk->bn", rel, rel))
                f += (0.5 * rho * c.drag_coefficient / n_pts) * area[:, None, :] * (frac * speed)[:, :, None] * rel
        total = f.sum(axis=1)
        torque = _cross(arm, f).sum(axis=1)
        # the volume-weighted mean of the water past each body (none past a dry one)
        past = np.divide(np.matmul(wet_volume[:, None, :], rel), sub[:, None, None], out=np.zeros((n_bodies, 1, 3)),
                         where=sub[:, None, None] > 0)
        turned = np.matmul(rot, np.stack([total, torque], axis=2))  # (B, 3, 2)
        force, moment = turned[:, :, 0], turned[:, :, 1]
        if c.munk_moment:
            moment += munk_moment(rot, past, sub[:, None], added_mass)
    return HydroLoads(force, moment, sub, added_mass, frac, added_inertia)


def munk_moment(orientation, water_past_body, wet_volume, added_mass_kg) -> np.ndarray:
    """The Munk moment (N m, world frame, (B, 3)) of B boxes translating through water.

    A body with the added masses ``A = diag(A_x, A_y, A_z)`` along its axes moving at ``U``
    relative to the water (body frame) takes the moment ``M = -U x (A U)`` (Kirchhoff's
    equations in steady translation; Newman 1977, Marine Hydrodynamics, sec. 4.13): for a
    container (``A_y > A_x``) moving at an angle to its length it is ``-(A_y - A_x) U_x U_y``
    about the vertical, which turns it broadside to its motion through the water. ``U`` is the
    volume-weighted mean over the wet sub-volumes of the body's velocity relative to the water
    there (``water_past_body`` (B, N, 3) is the water's velocity relative to the body in the
    body frame; ``U`` is its negative, and the moment is even in ``U``).
    """
    volume = np.asarray(wet_volume, float)
    total = volume.sum(axis=1)
    u = np.einsum("bn,bni->bi", volume, np.asarray(water_past_body, float))
    u = np.divide(u, total[:, None], out=np.zeros_like(u), where=total[:, None] > 0)
    body = -_cross(u, np.asarray(added_mass_kg, float) * u)
    return np.einsum("bij,bj->bi", np.asarray(orientation, float), body)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis (numpy's np.cross is several times slower on small arrays)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def drag_time_constant(mass_kg: float, drag_coefficient: float, area_m2: float, current_m_s: float,
                       water_density_kg_m3: float = 998.0) -> float:
    """Time (s) for a body at rest to reach half the current's speed under quadratic drag:
    ``m dv/dt = 0.5 rho C_d A (U - v)^2`` gives ``v = U (t / tau) / (1 + t / tau)`` with
    ``tau = m / (0.5 rho C_d A U)`` (``mass_kg`` includes any added mass)."""
    k = 0.5 * require_positive("water_density_kg_m3", water_density_kg_m3) * require_positive(
        "drag_coefficient", drag_coefficient) * require_positive("area_m2", area_m2)
    return require_positive("mass_kg", mass_kg) / (k * require_positive("current_m_s", current_m_s))


def heave_period(mass_kg: float, added_mass_kg: float, waterplane_area_m2: float, water_density_kg_m3: float = 998.0,
                 gravity_m_s2: float = 9.81) -> float:
    """Natural heave period (s) of a floating box: ``2 pi sqrt((m + m_a) / (rho g A))``."""
    stiffness = require_positive("water_density_kg_m3", water_density_kg_m3) * require_positive(
        "gravity_m_s2", gravity_m_s2) * require_positive("waterplane_area_m2", waterplane_area_m2)
    return 2.0 * math.pi * math.sqrt((require_positive("mass_kg", mass_kg) + float(added_mass_kg)) / stiffness)
