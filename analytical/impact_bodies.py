"""The two sides of an impact: a rigid debris body at its contact point, and the obstacle it strikes.

A :class:`Body` is a rigid body at the instant of contact (mass, inverse inertia tensor in the
global frame, velocity and spin, and an added-mass coefficient on its translation). At a
contact point it has a *contact compliance* ``K = I3 / m_t + [r]x^T I^-1 [r]x`` (the velocity
change of the point per unit impulse there) and along a normal ``n`` an **effective mass**

    1 / m_eff = n . M_t^-1 n + (r x n) . I^-1 (r x n),     M_t = m I3 + M_a

(Stronge 2018), ``M_a`` the added-mass tensor of the water the body carries (isotropic
``m C_a`` or anisotropic, :mod:`analytical.added_mass`). The obstacle is a :class:`RigidWall` or the column (:class:`ColumnTarget`);
a body-body impact has another :class:`Body` as its obstacle. :mod:`analytical.impact`
resolves the impact; the reasons for the default coefficients are given there.

References
----------
Stronge, W.J. (2018). Impact Mechanics, 2nd ed. Cambridge University Press (effective mass
    at a contact point).
Matsutomi, H. (2009). Method for estimating collision force of driftwood accompanying
    tsunami inundation flow. J. Disaster Research 4(6), 435-440.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive

__all__ = [
    "DEFAULT_ADDED_MASS_COEFFICIENT",
    "MATSUTOMI_ADDED_MASS_COEFFICIENT",
    "Body",
    "ColumnTarget",
    "RigidWall",
    "effective_mass",
    "inverse_inertia_tensor",
    "unit_vector",
    "vector3",
]

DEFAULT_ADDED_MASS_COEFFICIENT = 0.0
"""Added-mass coefficient ``C_a`` on the body's translation (longitudinal impacts; see :mod:`analytical.impact`)."""

MATSUTOMI_ADDED_MASS_COEFFICIENT = 0.7
"""``C_MA - 1`` for Matsutomi's driftwood-in-a-bore apparent mass ``C_MA = 1.7``: an upper alternative."""


def inverse_inertia_tensor(principal_kg_m2, orientation) -> np.ndarray:
    """Inverse inertia tensor (1/(kg m^2)) in the global frame: ``R diag(1/I) R^T``.

    ``principal_kg_m2``: principal moments about the body axes through the centre of mass
    (three values > 0). ``orientation``: 3x3 rotation from body to global axes (columns are
    the body axes in global coordinates).
    """
    moments = vector3("principal_kg_m2", principal_kg_m2)
    if np.any(moments <= 0.0):
        raise InputError("principal_kg_m2", f"must all be > 0, got {moments.tolist()}")
    rot = _rotation("orientation", orientation)
    return rot @ np.diag(1.0 / moments) @ rot.T


@dataclass(frozen=True)
class Body:
    """A rigid body at the instant of contact (SI units, global frame).

    Attributes
    ----------
    mass_kg:
        Structural mass m (> 0).
    inverse_inertia:
        Inverse inertia tensor about the centre of mass, global frame, 1/(kg m^2) (3x3,
        symmetric, positive semi-definite; zeros = no rotation, a particle). See
        :func:`inverse_inertia_tensor`.
    centre_of_mass_m:
        Centre of mass (m).
    velocity_m_s:
        Velocity of the centre of mass (m/s).
    angular_velocity_rad_s:
        Angular velocity (rad/s).
    added_mass_coefficient:
        ``C_a`` (>= 0): the translational mass is ``m (1 + C_a)`` on every axis. Ignored when
        ``added_mass_kg`` is given.
    added_mass_kg:
        The added-mass tensor on translation, global frame, kg (3x3, symmetric, positive
        semi-definite), or None for the isotropic ``m C_a``. An afloat box carries far less
        water lengthwise than broadside (:mod:`analytical.added_mass`), so a strike's
        effective mass depends on the direction of the normal in the body's axes. A rotational
        added inertia belongs in ``inverse_inertia`` (``(I + I_a)^-1``).
    """

    mass_kg: float
    inverse_inertia: np.ndarray
    centre_of_mass_m: np.ndarray
    velocity_m_s: np.ndarray
    angular_velocity_rad_s: np.ndarray = (0.0, 0.0, 0.0)
    added_mass_coefficient: float = DEFAULT_ADDED_MASS_COEFFICIENT
    added_mass_kg: np.ndarray | None = None

    def __post_init__(self):
        object.__setattr__(self, "mass_kg", require_positive("mass_kg", self.mass_kg))
        inv = _matrix("inverse_inertia", self.inverse_inertia)
        if not np.allclose(inv, inv.T, rtol=1e-9, atol=1e-12 * max(1.0, float(np.abs(inv).max()))):
            raise InputError("inverse_inertia", "must be symmetric")
        if np.linalg.eigvalsh(0.5 * (inv + inv.T)).min() < -1e-9 * max(1.0, float(np.abs(inv).max())):
            raise InputError("inverse_inertia", "must be positive semi-definite")
        _freeze(self, "inverse_inertia", 0.5 * (inv + inv.T))
        for name in ("centre_of_mass_m", "velocity_m_s", "angular_velocity_rad_s"):
            _freeze(self, name, vector3(name, getattr(self, name)))
        ca = require_finite("added_mass_coefficient", self.added_mass_coefficient)
        if ca < 0.0:
            raise InputError("added_mass_coefficient", f"must be >= 0, got {self.added_mass_coefficient!r}")
        object.__setattr__(self, "added_mass_coefficient", ca)
        if self.added_mass_kg is not None:
            ma = _matrix("added_mass_kg", self.added_mass_kg)
            scale = max(1.0, float(np.abs(ma).max()))
            if not np.allclose(ma, ma.T, rtol=1e-9, atol=1e-12 * scale):
                raise InputError("added_mass_kg", "must be symmetric")
            if np.linalg.eigvalsh(0.5 * (ma + ma.T)).min() < -1e-9 * scale:
                raise InputError("added_mass_kg", "must be positive semi-definite")
            _freeze(self, "added_mass_kg", 0.5 * (ma + ma.T))

    @classmethod
    def box(cls, mass_kg: float, principal_inertia_kg_m2, orientation, centre_of_mass_m, velocity_m_s,
            angular_velocity_rad_s=(0.0, 0.0, 0.0), added_mass_kg=(0.0, 0.0, 0.0),
            added_inertia_kg_m2=(0.0, 0.0, 0.0)) -> "Body":
        """A rigid body given in its own axes: principal moments, the added masses along its
        axes and the added moments of inertia about them (:mod:`analytical.added_mass`), all
        turned into the global frame by ``orientation`` (body to global, columns = body axes):
        ``M_a = R diag(m_a) R^T`` and ``I^-1 = R diag(1 / (I + I_a)) R^T``."""
        rot = _rotation("orientation", orientation)
        moments = vector3("principal_inertia_kg_m2", principal_inertia_kg_m2)
        added = vector3("added_mass_kg", added_mass_kg)
        added_inertia = vector3("added_inertia_kg_m2", added_inertia_kg_m2)
        if np.any(added < 0.0) or np.any(added_inertia < 0.0):
            raise InputError("added_mass_kg", f"added masses and inertias must be >= 0, got {added.tolist()}, "
                                              f"{added_inertia.tolist()}")
        return cls(mass_kg, inverse_inertia_tensor(moments + added_inertia, rot), centre_of_mass_m, velocity_m_s,
                   angular_velocity_rad_s, added_mass_kg=rot @ np.diag(added) @ rot.T)

    @classmethod
    def particle(cls, mass_kg: float, velocity_m_s, centre_of_mass_m=(0.0, 0.0, 0.0), **kw) -> "Body":
        """A body without rotational response (zero inverse inertia)."""
        return cls(mass_kg, np.zeros((3, 3)), centre_of_mass_m, velocity_m_s, **kw)

    @property
    def translational_mass_tensor(self) -> np.ndarray:
        """Mass on translation, kg (3x3, global): ``m I3 + M_a`` (``M_a = m C_a I3`` without a tensor)."""
        if self.added_mass_kg is None:
            return np.eye(3) * self.mass_kg * (1.0 + self.added_mass_coefficient)
        return np.eye(3) * self.mass_kg + self.added_mass_kg

    @property
    def inverse_translational_mass(self) -> np.ndarray:
        """``(m I3 + M_a)^-1`` (1/kg, 3x3): the centre's velocity change per unit impulse."""
        return np.linalg.inv(self.translational_mass_tensor)

    def translational_mass_along(self, direction) -> float:
        """``n . (m I3 + M_a) n`` (kg) along the unit vector ``direction``."""
        n = unit_vector("direction", direction)
        return float(n @ self.translational_mass_tensor @ n)

    def momentum(self) -> np.ndarray:
        """Linear momentum of the body and the water it carries, ``(m I3 + M_a) v`` (N s)."""
        return self.translational_mass_tensor @ self.velocity_m_s

    def point_velocity(self, point_m) -> np.ndarray:
        """Velocity (m/s) of the body point at ``point_m``: ``v + omega x r``."""
        r = np.asarray(point_m, float) - self.centre_of_mass_m
        return self.velocity_m_s + np.cross(self.angular_velocity_rad_s, r)

    def compliance(self, point_m) -> np.ndarray:
        """Contact compliance (1/kg, 3x3): velocity change of the point per unit impulse there.

        ``K = (m I3 + M_a)^-1 + [r]x^T I^-1 [r]x`` (``[r]x a = r x a``).
        """
        r = np.asarray(point_m, float) - self.centre_of_mass_m
        rx = _skew(r)
        return self.inverse_translational_mass + rx.T @ self.inverse_inertia @ rx


def effective_mass(body: Body, contact_point_m, normal) -> float:
    """Effective mass (kg) of ``body`` along ``normal`` at ``contact_point_m``.

    ``1 / m_eff = n . M_t^-1 n + (r x n) . I^-1 (r x n)``.
    """
    n = unit_vector("normal", normal)
    return 1.0 / float(n @ body.compliance(vector3("contact_point_m", contact_point_m)) @ n)


@dataclass(frozen=True)
class RigidWall:
    """An immovable, rigid obstacle (a flume wall): the contact spring is grounded."""

    kind: str = dataclasses.field(default="wall", init=False)


@dataclass(frozen=True)
class ColumnTarget:
    """The column's MDOF model, struck at ``height_m`` above its base.

    ``column`` is an :class:`analytical.column.Column` (base ``"rigid"`` or ``"calibrated"``);
    its x-bending model takes the x part of the load; a y part goes to the same column with
    its section turned by 90 degrees (a calibrated base is tuned to the same measured
    frequency in both directions).
    """

    column: Column
    height_m: float
    kind: str = dataclasses.field(default="column", init=False)

    def __post_init__(self):
        if not isinstance(self.column, Column):
            raise InputError("column", f"must be an analytical.column.Column, got {type(self.column).__name__}")
        h = require_finite("height_m", self.height_m)
        if not 0.0 < h <= self.column.height_m * (1.0 + 1e-12):
            raise InputError("height_m", f"must be in (0, {self.column.height_m:g}] m, got {self.height_m!r}")
        object.__setattr__(self, "height_m", min(h, self.column.height_m))

    def axis_column(self, axis: int) -> Column:
        """The analysis column for bending along global x (axis 0) or y (axis 1)."""
        if axis == 0:
            return self.column
        return dataclasses.replace(self.column, size_x_m=self.column.size_y_m, size_y_m=self.column.size_x_m)


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def _freeze(obj, name, arr):
    arr = np.array(arr, dtype=float)
    arr.setflags(write=False)
    object.__setattr__(obj, name, arr)


def vector3(name: str, value) -> np.ndarray:
    """``value`` as a finite 3-vector (InputError naming ``name`` otherwise)."""
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be 3 numbers, got {value!r}") from None
    if arr.shape != (3,):
        raise InputError(name, f"must be 3 numbers, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(name, f"must be finite, got {arr.tolist()}")
    return arr


def _matrix(name: str, value) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, "must be a 3x3 array of numbers") from None
    if arr.shape != (3, 3):
        raise InputError(name, f"must be 3x3, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "must be finite")
    return arr


def unit_vector(name: str, value) -> np.ndarray:
    """``value`` as a unit 3-vector (length within 1e-6 of 1, then normalised)."""
    arr = vector3(name, value)
    norm = float(np.linalg.norm(arr))
    if abs(norm - 1.0) > 1e-6:
        raise InputError(name, f"must be a unit vector, got length {norm:.6g}")
    return arr / norm


def _rotation(name: str, value) -> np.ndarray:
    rot = _matrix(name, value)
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) < 0.0:
        raise InputError(name, "must be a proper rotation matrix (orthonormal, det +1)")
    return rot
