"""Impact of a rigid debris body on the column, a rigid wall or another body, over milliseconds.

The runner stops the CFD when a body reaches an obstacle (orchestrator/run/contact.py); this module
resolves the contact: the force history, the rebound and the column's response. It is pure:
numbers and arrays in, frozen results out.

Model
-----
*Normal part (time-resolved).* Along the contact normal ``n`` (unit, pointing from the
obstacle into the body) the body is a single mass, its **effective mass at the contact point**

    1 / m_eff = 1 / m_t + (r x n) . I^-1 (r x n),     m_t = m (1 + C_a),

(``r`` from the centre of mass to the contact point, ``I^-1`` the inverse inertia tensor in
the global frame, ``C_a`` the added-mass coefficient on the translational part). The body
presses on a **compression-only linear contact spring** ``k`` (the debris stiffness, default
:data:`analytical.asce7.SEED_DEBRIS_STIFFNESS_N_M`), optionally with a dashpot (default none),
and the spring acts on the obstacle:

* :class:`RigidWall`: the spring is grounded. Undamped, this is Haehnel & Daly's model: a
  half-sine of peak ``v sqrt(k m_eff)`` and duration ``pi sqrt(m_eff / k)``, restitution 1.
* :class:`ColumnTarget`: the spring is in series with the column's MDOF Timoshenko model
  (:func:`analytical.mdof.column_model`) at the contact height. The horizontal part of
  ``-n`` loads the column's x-bending model and, if it has a y component, a second model
  of the same column with its section turned by 90 degrees (bending about x). The column is
  axially rigid and its torsion is not modelled. The coupled debris-spring-column system is
  integrated in time; the force history, the rebound (restitution) and the vibration left in
  the column **emerge** from it: no restitution coefficient is assumed.

Time integration: Newmark constant average acceleration on the whole coupled system (the
column's banded matrices plus the body DOF; the contact spring is a rank-one term handled by
Sherman-Morrison). On a linear system this scheme conserves ``1/2 v'Mv + 1/2 u'Ku`` exactly
apart from the damping work, and its velocity update is the trapezoidal rule, so the
impulse of the recorded force equals the body's momentum change to rounding. The contact
switches on when the spring's compression reaches zero from below and off when its force
returns to zero; each switch is located inside its time step by Brent's method on a
fractional step, so no spring energy is lost or created at a switch. After the body leaves,
the column keeps ringing; the integration watches for the column catching up with the body
(re-contact) and stops when that has become impossible: the column's
contact point can never move further than ``sqrt(2 E_col c)`` (``E_col`` its mechanical
energy, ``c`` its static compliance there), so once the body is further away than that the
impact is over.

The base shear at the load cell is the column's response to the resulting force pulse,
computed by :func:`analytical.mdof.mdof_response` (exact modal superposition for pulses of up
to 600 samples, its Newmark option for longer ones, whose modal cost grows as samples x
modes x times; the two agree to about 1e-4 of the peak), so it is the same quantity the
seed's MDOF fits produce. The coupled integration's own base shear is kept in
:attr:`ImpactResult.history` (it agrees with the modal one; a test checks it).

Body-body contacts (:func:`pair_impact`) use the two bodies' combined contact compliance
(two-body effective mass) on one spring with no column; its default stiffness is two seed
debris in series, ``k_d / 2``.

*Tangential part (impulse level).* Coulomb friction acts on the total impulse at the contact
point, ``J = J_n n + J_t``: stick (``J_t`` stops the contact point's sliding) when
``|J_t| <= mu J_n``, otherwise slip (``|J_t| = mu J_n``, along the direction the stick
impulse would have); ``dv = J / m_t``, ``d omega = I^-1 (r x J)``. Through the body's
rotation a tangential impulse also changes the contact point's normal velocity, so with
friction the normal dynamics see a different mass than ``m_eff``: the *normal mass*
``J_n / (v_out - v_in)`` of the combined impulse (Stronge's slip or stick effective mass).
The normal integration is repeated with that mass until the two agree (one pass without
friction or without coupling, two or three otherwise), so the force history, the normal
impulse, the restitution and the final velocities are one consistent solution. Guards:
friction may not more than double the normal mass (the rigid-body "jam"), and where the
kinematic normal condition with friction would create kinetic energy (possible in 3-D) the
tangential impulse is reduced until friction dissipates (both reported as
``friction_limited``). The tangential force is not applied to the column.

Defaults and why
----------------
* ``added_mass_coefficient = 0`` (:data:`DEFAULT_ADDED_MASS_COEFFICIENT`). For debris striking
  end-on (longitudinally), laboratory work found the water adds little to the impact force:
  Haehnel & Daly (2004) for logs, and Ko et al. (2015) for shipping-container models struck
  in water and in air; ASCE 7-16/7-22 Clause 6.11 accordingly has no added-mass term, and the
  seed's debris stiffness (:data:`~analytical.asce7.SEED_DEBRIS_STIFFNESS_N_M`) was backed out
  of that formula without one, so adding mass on top would double count. (The papers could
  not be retrieved here; these are their findings as widely quoted.) For sensitivity, Matsutomi's
  apparent-mass coefficient for driftwood in a bore, ``C_MA = 1.7``, means ``C_a = 0.7``
  (:data:`MATSUTOMI_ADDED_MASS_COEFFICIENT`). A partly submerged 1:40 container (draft about
  0.026 m of 0.06 m) moving lengthwise has a potential-flow ``C_a`` of order 0.1.
* ``friction_coefficient = 0.3`` (:data:`DEFAULT_FRICTION_COEFFICIENT`): kinetic friction of
  polyethylene (the seed's debris) on a smooth hard surface (acrylic, glass, steel) is
  quoted at 0.2-0.3 in engineering tables; water lubricates it downwards. 0.3, the upper end,
  gives the most rotation from a glancing blow. No measured value exists for the seed's pair.
* ``damping_ratio = 0`` (contact dashpot as a fraction of ``2 sqrt(k m_eff)``): the energy a
  column impact loses must come out of the structural model, not from an assumed coefficient;
  Haehnel & Daly (2004) found damping negligible in the impact, and the seed's ``k_d`` comes
  from their undamped formula; no damping was measured for the polyethylene containers.
  Give a value to model a lossy debris material; with a dashpot the contact ends when the
  force (spring + dashpot) returns to zero, and the spring energy left then is counted as lost.

Seed comparison (Table 1 event: 0.236 kg at 1.5 m/s, column struck at 0.40 m)
-----------------------------------------------------------------------------
With ``k_d`` the coupled model gives 1137 N over 0.86 ms, 0.624 N s, restitution 0.76, base
shear 1004 N (rigid base; 886 N calibrated): between the seed's ASCE 7-22 ``k_d`` row
(822 N = 0.65 x Haehnel & Daly's rigid-wall 1270 N, 0.6 ms, 0.46 N s) and the rigid wall,
and far from its MDOF fit (237 N, 4.7 ms, 0.71 N s). The MDOF fit's pulse is what this model
gives with a contact about 30 times softer than ``k_d``: ``k = 1.05e5 N/m`` yields 231 N,
4.70 ms, 0.69 N s (tests/test_impact.py).

References
----------
Haehnel, R.B. & Daly, S.F. (2004). Maximum impact force of woody debris on floodplain
    structures. J. Hydraulic Engineering 130(2), 112-120.
Ko, H.T.-S., Cox, D.T., Riggs, H.R. & Naito, C.J. (2015). Hydraulic experiments on impact
    forces from tsunami-driven debris. J. Waterway, Port, Coastal, Ocean Eng. 141(3), 04014043.
Matsutomi, H. (2009). Method for estimating collision force of driftwood accompanying
    tsunami inundation flow. J. Disaster Research 4(6), 435-440.
Stronge, W.J. (2018). Impact Mechanics, 2nd ed. Cambridge University Press (effective mass
    at a contact point, impulse-level friction).
Kane, T.R. & Levinson, D.A. (1985). Dynamics: Theory and Applications. McGraw-Hill
    (energy gain of Newton's restitution with friction).
Chopra, A.K. (2017). Dynamics of Structures, 5th ed. (Newmark's method, 5.4 and 15.3).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg
from scipy.optimize import brentq

from analytical.asce7 import SEED_DEBRIS_STIFFNESS_N_M
from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive
from analytical.banded import upper_band
from analytical.column_fem import column_model
from analytical.mdof import mdof_response
from analytical.pulses import Tabulated
from analytical.sdof import ForceResponse

__all__ = [
    "DEFAULT_ADDED_MASS_COEFFICIENT",
    "DEFAULT_FRICTION_COEFFICIENT",
    "DEFAULT_CONTACT_DAMPING_RATIO",
    "MATSUTOMI_ADDED_MASS_COEFFICIENT",
    "Body",
    "ColumnTarget",
    "RigidWall",
    "ImpactEnergy",
    "ImpactHistory",
    "ImpactResult",
    "impact",
    "pair_impact",
    "inverse_inertia_tensor",
    "effective_mass",
]

DEFAULT_ADDED_MASS_COEFFICIENT = 0.0
"""Added-mass coefficient ``C_a`` on the body's translation (longitudinal impacts; see module doc)."""

MATSUTOMI_ADDED_MASS_COEFFICIENT = 0.7
"""``C_MA - 1`` for Matsutomi's driftwood-in-a-bore apparent mass ``C_MA = 1.7``: an upper alternative."""

DEFAULT_FRICTION_COEFFICIENT = 0.3
"""Coulomb coefficient of polyethylene debris on a smooth hard obstacle (see module doc)."""

DEFAULT_CONTACT_DAMPING_RATIO = 0.0
"""Contact dashpot as a fraction of ``2 sqrt(k m_eff)``: none (see module doc)."""

#: Newmark steps per contact period 2 pi sqrt(m_eff / k) (period error ~ (2 pi / 400)^2 / 12 = 2e-5).
_STEPS_PER_CONTACT_PERIOD = 400
#: omega dt <= 0.1 up to the first column mode above this frequency (as analytical.mdof).
_DT_BAND_HZ = 4000.0
_DT_PHASE = 0.1
#: Default output spacing of the base shear after the contact (s).
_RESPONSE_DT_S = 1.0e-5
#: Longest force pulse (samples) whose base shear uses exact modal superposition.
_MODAL_MAX_SAMPLES = 600


# ------------------------------------------------------------------------------ inputs
def inverse_inertia_tensor(principal_kg_m2, orientation) -> np.ndarray:
    """Inverse inertia tensor (1/(kg m^2)) in the global frame: ``R diag(1/I) R^T``.

    ``principal_kg_m2``: principal moments about the body axes through the centre of mass
    (three values > 0). ``orientation``: 3x3 rotation from body to global axes (columns are
    the body axes in global coordinates).
    """
    moments = _vector("principal_kg_m2", principal_kg_m2)
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
        ``C_a`` (>= 0): the translational mass is ``m (1 + C_a)``.
    """

    mass_kg: float
    inverse_inertia: np.ndarray
    centre_of_mass_m: np.ndarray
    velocity_m_s: np.ndarray
    angular_velocity_rad_s: np.ndarray = (0.0, 0.0, 0.0)
    added_mass_coefficient: float = DEFAULT_ADDED_MASS_COEFFICIENT

    def __post_init__(self):
        object.__setattr__(self, "mass_kg", require_positive("mass_kg", self.mass_kg))
        inv = _matrix("inverse_inertia", self.inverse_inertia)
        if not np.allclose(inv, inv.T, rtol=1e-9, atol=1e-12 * max(1.0, float(np.abs(inv).max()))):
            raise InputError("inverse_inertia", "must be symmetric")
        if np.linalg.eigvalsh(0.5 * (inv + inv.T)).min() < -1e-9 * max(1.0, float(np.abs(inv).max())):
            raise InputError("inverse_inertia", "must be positive semi-definite")
        _freeze(self, "inverse_inertia", 0.5 * (inv + inv.T))
        for name in ("centre_of_mass_m", "velocity_m_s", "angular_velocity_rad_s"):
            _freeze(self, name, _vector(name, getattr(self, name)))
        ca = require_finite("added_mass_coefficient", self.added_mass_coefficient)
        if ca < 0.0:
            raise InputError("added_mass_coefficient", f"must be >= 0, got {self.added_mass_coefficient!r}")
        object.__setattr__(self, "added_mass_coefficient", ca)

    @classmethod
    def particle(cls, mass_kg: float, velocity_m_s, centre_of_mass_m=(0.0, 0.0, 0.0), **kw) -> "Body":
        """A body without rotational response (zero inverse inertia)."""
        return cls(mass_kg, np.zeros((3, 3)), centre_of_mass_m, velocity_m_s, **kw)

    @property
    def translational_mass_kg(self) -> float:
        """``m (1 + C_a)`` (kg)."""
        return self.mass_kg * (1.0 + self.added_mass_coefficient)

    def point_velocity(self, point_m) -> np.ndarray:
        """Velocity (m/s) of the body point at ``point_m``: ``v + omega x r``."""
        r = np.asarray(point_m, float) - self.centre_of_mass_m
        return self.velocity_m_s + np.cross(self.angular_velocity_rad_s, r)

    def compliance(self, point_m) -> np.ndarray:
        """Contact compliance (1/kg, 3x3): velocity change of the point per unit impulse there.

        ``K = I3 / m_t + [r]x^T I^-1 [r]x`` (``[r]x a = r x a``).
        """
        r = np.asarray(point_m, float) - self.centre_of_mass_m
        rx = _skew(r)
        return np.eye(3) / self.translational_mass_kg + rx.T @ self.inverse_inertia @ rx


def effective_mass(body: Body, contact_point_m, normal) -> float:
    """Effective mass (kg) of ``body`` along ``normal`` at ``contact_point_m``.

    ``1 / m_eff = 1 / m_t + (r x n) . I^-1 (r x n)``.
    """
    n = _unit("normal", normal)
    return 1.0 / float(n @ body.compliance(_vector("contact_point_m", contact_point_m)) @ n)


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


# ------------------------------------------------------------------------------ results
@dataclass(frozen=True)
class ImpactEnergy:
    """Energy bookkeeping of the normal part (J) and the friction loss.

    ``normal_in_J = normal_out_J + column_J + column_damping_J + contact_damping_J`` up to the
    integration's rounding (:attr:`balance_error_J`). ``normal_in_J`` and ``normal_out_J``
    are ``1/2 m_n v_n^2`` before and after (``m_n`` the normal mass); ``column_J`` the
    column's kinetic + strain energy at the end; ``column_damping_J`` the Rayleigh damping
    work; ``contact_damping_J``
    the dashpot work plus the spring energy left when a damped contact opens;
    ``friction_J`` the rest of the bodies' kinetic-energy loss, the friction work (>= 0).
    """

    normal_in_J: float
    normal_out_J: float
    column_J: float
    column_damping_J: float
    contact_damping_J: float
    friction_J: float

    @property
    def balance_error_J(self) -> float:
        """``normal_in - (normal_out + column + column_damping + contact_damping)`` (J)."""
        return self.normal_in_J - (self.normal_out_J + self.column_J + self.column_damping_J + self.contact_damping_J)


@dataclass(frozen=True)
class ImpactHistory:
    """The coupled integration, sample by sample (read-only arrays, time from first contact).

    ``force_N``: contact force magnitude (>= 0; on the body along ``+n``, on the obstacle
    along ``-n``); ``compression_m``: spring compression (negative = gap); ``approach_m``:
    body displacement along ``-n``; ``obstacle_m``: the column's displacement along ``-n`` at
    the contact point; ``base_shear_x_N``/``base_shear_y_N``: the column's base shear from
    the coupled integration (zeros for a wall or a body).
    """

    time_s: np.ndarray
    force_N: np.ndarray
    compression_m: np.ndarray
    approach_m: np.ndarray
    obstacle_m: np.ndarray
    base_shear_x_N: np.ndarray
    base_shear_y_N: np.ndarray


@dataclass(frozen=True)
class ImpactResult:
    """Outcome of one impact. SI units; vectors in the global frame; ``n`` = contact normal.

    Attributes
    ----------
    target:
        ``"column"``, ``"wall"`` or ``"body"``.
    contact_point_m, normal:
        Where, and the unit normal from the obstacle (or other body) into the body.
    contact_height_m:
        Height of the contact on the column (column targets), else None.
    force:
        Contact force history (``Tabulated``, N, time from first contact, s).
    peak_force_N, duration_s, impulse_Ns:
        Peak force; time from first contact to the final separation; integral of the force.
    contacts:
        Number of separate contact phases (> 1 when the ringing column catches the body again).
    effective_mass_kg:
        ``m_eff`` along ``n`` at the contact point (two-body value for bodies), no friction.
    normal_mass_kg:
        The mass the normal dynamics were integrated with: ``m_eff``, or with friction
        coupled through rotation the combined impulse's ``J_n / (out - in)`` (module doc).
    stiffness_N_m, damping_N_s_m:
        Contact spring and dashpot.
    normal_velocity_in_m_s, normal_velocity_out_m_s:
        Relative contact-point velocity along ``n`` before (< 0, approaching) and after the
        impact (> 0, separating). ``normal_impulse_Ns = normal_mass_kg (out - in)``.
    restitution:
        ``-out / in``: emergent (1 for an undamped rigid wall).
    base_shear, base_shear_y:
        Column base shear along global x (and y, when the load has a y part) from
        :func:`~analytical.mdof.mdof_response` of the force pulse, over the pulse and
        ``response_s`` after it; None when not applicable.
    normal_impulse_Ns, tangential_impulse_Ns, impulse_vector_Ns:
        ``J_n``, ``|J_t|`` and ``J = J_n n + J_t`` (the impulse on the body).
    sticking, friction_limited:
        Whether the tangential impulse stopped the sliding; whether a guard reduced friction
        (see module doc).
    obliquity_deg:
        Angle between the incoming relative contact-point velocity and the inward normal
        ``-n``: 0 head-on, 90 grazing.
    velocity_out_m_s, angular_velocity_out_rad_s:
        The body's state after the impact (with the friction impulse).
    contact_velocity_out_m_s:
        Relative contact-point velocity after the impact (3-vector).
    other_velocity_out_m_s, other_angular_velocity_out_rad_s:
        The other body's state after a body-body impact, else None.
    settled:
        True when the integration stopped because re-contact had become impossible; False
        when it hit ``max_watch_s``.
    energy, history:
        :class:`ImpactEnergy` and :class:`ImpactHistory`.
    """

    target: str
    contact_point_m: np.ndarray
    normal: np.ndarray
    contact_height_m: float | None
    force: Tabulated
    peak_force_N: float
    duration_s: float
    impulse_Ns: float
    contacts: int
    effective_mass_kg: float
    normal_mass_kg: float
    stiffness_N_m: float
    damping_N_s_m: float
    normal_velocity_in_m_s: float
    normal_velocity_out_m_s: float
    restitution: float
    base_shear: ForceResponse | None
    base_shear_y: ForceResponse | None
    normal_impulse_Ns: float
    tangential_impulse_Ns: float
    impulse_vector_Ns: np.ndarray
    sticking: bool
    friction_limited: bool
    obliquity_deg: float
    velocity_out_m_s: np.ndarray
    angular_velocity_out_rad_s: np.ndarray
    contact_velocity_out_m_s: np.ndarray
    other_velocity_out_m_s: np.ndarray | None
    other_angular_velocity_out_rad_s: np.ndarray | None
    settled: bool
    energy: ImpactEnergy
    history: ImpactHistory

    def __repr__(self) -> str:
        return (
            f"ImpactResult(target={self.target!r}, peak_force_N={self.peak_force_N:.6g}, "
            f"duration_s={self.duration_s:.6g}, impulse_Ns={self.impulse_Ns:.6g}, "
            f"restitution={self.restitution:.4g}, contacts={self.contacts})"
        )


# ------------------------------------------------------------------------------ API
def impact(
    body: Body,
    contact_point_m,
    normal,
    target: RigidWall | ColumnTarget,
    *,
    stiffness_N_m: float = SEED_DEBRIS_STIFFNESS_N_M,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    damping_ratio: float = DEFAULT_CONTACT_DAMPING_RATIO,
    dt_s: float | None = None,
    max_watch_s: float = 0.5,
    response_s: float = 0.05,
) -> ImpactResult:
    """Resolve the impact of ``body`` on a fixed obstacle (a rigid wall or the column).

    Parameters
    ----------
    body:
        The body at first contact (:class:`Body`).
    contact_point_m:
        Contact point (m).
    normal:
        Unit normal from the obstacle into the body.
    target:
        :class:`RigidWall` or :class:`ColumnTarget`.
    stiffness_N_m:
        Contact (debris) stiffness k (N/m); default the seed's k_d, 3.04e6 N/m.
    friction_coefficient:
        Coulomb mu (>= 0) for the tangential impulse.
    damping_ratio:
        Contact dashpot ``c = 2 zeta sqrt(k m_n)`` (0 <= zeta < 1; ``m_n`` the normal mass).
    dt_s:
        Time step (s); default ``min(T_c / 400, 0.1 / omega)``, ``T_c = 2 pi sqrt(m_n / k)``
        (``m_n`` the normal mass) and omega the first column mode above 4 kHz (about
        3.9e-6 s for the seed's column).
    max_watch_s:
        Longest time (s) integrated after the first contact while re-contact is possible.
    response_s:
        How long (s) after the pulse the base shear is reported.

    Raises
    ------
    InputError
        On bad input, or when the contact point is not approaching the obstacle.
    """
    if not isinstance(body, Body):
        raise InputError("body", f"must be an analytical.impact.Body, got {type(body).__name__}")
    if not isinstance(target, (RigidWall, ColumnTarget)):
        raise InputError("target", f"must be RigidWall() or ColumnTarget(column, height_m), got {target!r}")
    point = _vector("contact_point_m", contact_point_m)
    n = _unit("normal", normal)
    compliance = body.compliance(point)
    u0 = body.point_velocity(point)
    blocks = _column_blocks(target, n) if isinstance(target, ColumnTarget) else ()
    res = _resolve(
        n, compliance, u0, blocks, stiffness_N_m, friction_coefficient, damping_ratio, dt_s, max_watch_s
    )
    j = res["impulse"]
    v_out = body.velocity_m_s + j / body.translational_mass_kg
    w_out = body.angular_velocity_rad_s + body.inverse_inertia @ np.cross(point - body.centre_of_mass_m, j)
    shear_x = shear_y = None
    height = None
    if isinstance(target, ColumnTarget):
        height = target.height_m
        shear_x, shear_y = _base_shears(target, n, res["force"], response_s)
    return _result(target.kind, point, n, height, res, v_out, w_out, None, None, shear_x, shear_y)


def pair_impact(
    body: Body,
    other: Body,
    contact_point_m,
    normal,
    *,
    stiffness_N_m: float = SEED_DEBRIS_STIFFNESS_N_M / 2.0,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    damping_ratio: float = DEFAULT_CONTACT_DAMPING_RATIO,
    dt_s: float | None = None,
) -> ImpactResult:
    """Resolve a body-body impact: two-body effective mass on one contact spring, no column.

    ``normal`` points from ``other`` into ``body``; the impulse ``J`` acts on ``body`` and
    ``-J`` on ``other``. ``1 / m_eff = n . (K_body + K_other) n`` with each body's contact
    compliance (:meth:`Body.compliance`). The default stiffness is two seed debris in series,
    ``k_d / 2``. Velocities in the result are relative (``body`` minus ``other``) at the
    contact point; ``velocity_out_m_s`` etc. are ``body``'s, ``other_*`` the other's.
    """
    for name, b in (("body", body), ("other", other)):
        if not isinstance(b, Body):
            raise InputError(name, f"must be an analytical.impact.Body, got {type(b).__name__}")
    point = _vector("contact_point_m", contact_point_m)
    n = _unit("normal", normal)
    compliance = body.compliance(point) + other.compliance(point)
    u0 = body.point_velocity(point) - other.point_velocity(point)
    res = _resolve(n, compliance, u0, (), stiffness_N_m, friction_coefficient, damping_ratio, dt_s, 1.0)
    j = res["impulse"]
    v_a = body.velocity_m_s + j / body.translational_mass_kg
    w_a = body.angular_velocity_rad_s + body.inverse_inertia @ np.cross(point - body.centre_of_mass_m, j)
    v_b = other.velocity_m_s - j / other.translational_mass_kg
    w_b = other.angular_velocity_rad_s - other.inverse_inertia @ np.cross(point - other.centre_of_mass_m, j)
    return _result("body", point, n, None, res, v_a, w_a, v_b, w_b, None, None)


# ------------------------------------------------------------------------------ core
def _resolve(n, compliance, u0, blocks, stiffness, mu, zeta, dt, max_watch):
    k = require_positive("stiffness_N_m", stiffness)
    mu = require_finite("friction_coefficient", mu)
    if mu < 0.0:
        raise InputError("friction_coefficient", f"must be >= 0, got {mu!r}")
    zeta = require_finite("damping_ratio", zeta)
    if not 0.0 <= zeta < 1.0:
        raise InputError("damping_ratio", f"must be in [0, 1), got {zeta!r}")
    max_watch = require_positive("max_watch_s", max_watch)
    knn = float(n @ compliance @ n)
    m_eff = 1.0 / knn
    v_in = float(n @ u0)
    if not v_in < 0.0:
        raise InputError(
            "velocity_m_s",
            f"the contact point is not approaching the obstacle (normal velocity {v_in:.6g} m/s >= 0)",
        )
    if dt is not None:
        dt = require_positive("dt_s", dt)
    column_dt = min([b.dt_limit for b in blocks if b is not None], default=math.inf)

    # The normal dynamics run with the normal mass the contact actually has: m_eff without
    # friction; with friction coupled to the normal through the body's rotation, the mass
    # implied by the combined impulse (Stronge's slip/stick effective mass). A few passes
    # make the two consistent (the mass depends on the restitution only through stick).
    integrator_mass = m_eff
    for _ in range(8):
        c = 2.0 * zeta * math.sqrt(k * integrator_mass)
        step = dt
        if step is None:
            period = 2.0 * math.pi * math.sqrt(integrator_mass / k)
            step = min(period / _STEPS_PER_CONTACT_PERIOD, column_dt)
        run = _NormalIntegrator(integrator_mass, k, c, blocks).run(-v_in, step, max_watch)
        v_out_n = -run["body_velocity"]  # body velocity along -n, back to along +n
        imp = _contact_impulse(compliance, n, u0, v_out_n, mu)
        mass = imp["j_n"] / (v_out_n - v_in)
        if abs(mass - integrator_mass) <= 1e-10 * integrator_mass:
            break
        integrator_mass = mass
    j = imp["j"]
    u_out = u0 + compliance @ j
    kinetic_loss = -(float(j @ u0) + 0.5 * float(j @ compliance @ j))
    normal_loss = 0.5 * integrator_mass * (v_in**2 - v_out_n**2)
    speed = float(np.linalg.norm(u0))
    obliquity = math.degrees(math.acos(min(1.0, max(-1.0, -v_in / speed))))
    return dict(
        run=run, m_eff=m_eff, normal_mass=integrator_mass, k=k, c=c, v_in=v_in, v_out=v_out_n,
        j_n=imp["j_n"], j_t=imp["j_t"], impulse=j, sticking=imp["sticking"], limited=imp["limited"],
        friction_loss=kinetic_loss - normal_loss, u_out=u_out, obliquity=obliquity, force=run["pulse"],
    )


def _contact_impulse(compliance, n, u0, v_target, mu):
    """Impulse ``J = J_n n + J_t`` at one contact: normal velocity to ``v_target``, Coulomb.

    Stick: ``K J = (v_target - u0.n) n - u0_t`` (all sliding stopped), accepted when
    ``|J_t| <= mu J_n``. Slip: ``J = J_n (n + mu d)``, ``d`` the direction of the stick
    impulse's tangential part (friction opposes the sliding it would stop), ``J_n`` from the
    normal condition ``n . (u0 + K J) = v_target``. Two guards (``limited``):

    * if friction would make the normal mass more than twice ``m_eff``
      (``n . K (n + mu d) < K_nn / 2``, the Painleve-type jam of rigid-body friction) mu is
      reduced to that bound;
    * a kinematic (Newton-type) normal condition with friction can *create* kinetic energy
      in 3-D (Kane & Levinson 1985; Stronge 2018, ch. 5): the tangential impulse is then
      scaled by the largest ``lambda`` in [0, 1] for which friction dissipates (``J_n``
      re-solved for the normal condition; the Coulomb cone holds for every such lambda).
    """
    knn = float(n @ compliance @ n)
    u0_n = float(n @ u0)
    u0_t = u0 - u0_n * n
    dv = v_target - u0_n

    def frictionless():
        j_n = dv / knn
        return {"j_n": j_n, "j_t": np.zeros(3), "j": j_n * n, "sticking": False, "limited": False}

    if mu == 0.0:
        return frictionless()
    j_stick = np.linalg.solve(compliance, dv * n - u0_t)
    jn_stick = float(n @ j_stick)
    jt_stick = j_stick - jn_stick * n
    jt_norm = float(np.linalg.norm(jt_stick))
    if jt_norm <= 1e-14 * max(abs(jn_stick), 1e-300):
        return frictionless()
    sticking = jn_stick > 0.0 and jt_norm <= mu * jn_stick * (1.0 + 1e-12)
    limited = False
    if sticking:
        j_t = jt_stick
    else:
        d = jt_stick / jt_norm
        nkd = float(n @ compliance @ d)
        if knn + mu * nkd < 0.5 * knn:
            mu = -0.5 * knn / nkd
            limited = True
        j_t = mu * dv / (knn + mu * nkd) * d

    def candidate(lam):
        jt = lam * j_t
        j_n = (dv - float(n @ compliance @ jt)) / knn
        return j_n, jt, j_n * n + jt

    def friction_work(lam):
        # kinetic energy lost minus the share taken by the normal force, -J_n (u0_n + v_target) / 2
        j_n, _, j = candidate(lam)
        return -(float(j @ u0) + 0.5 * float(j @ compliance @ j)) + 0.5 * j_n * (u0_n + v_target)

    lam = 1.0
    q1 = friction_work(1.0)
    if q1 < 0.0:
        q_half = friction_work(0.5)
        a = 2.0 * (q1 - 2.0 * q_half)
        b = q1 - a
        lam = min(max(-b / a * (1.0 - 1e-12), 0.0), 1.0) if a < 0.0 and b > 0.0 else 0.0
        limited = True
        sticking = False
    j_n, jt, j = candidate(lam)
    return {"j_n": j_n, "j_t": jt, "j": j, "sticking": bool(sticking), "limited": limited}


def _result(kind, point, n, height, res, v_out, w_out, v_other, w_other, shear_x, shear_y) -> ImpactResult:
    run = res["run"]
    m_n = res["normal_mass"]
    energy = ImpactEnergy(
        normal_in_J=float(0.5 * m_n * res["v_in"] ** 2),
        normal_out_J=float(0.5 * m_n * res["v_out"] ** 2),
        column_J=float(run["column_energy"]),
        column_damping_J=float(run["column_damping"]),
        contact_damping_J=float(run["contact_damping"]),
        friction_J=float(res["friction_loss"]),
    )
    pulse = res["force"]
    arrays = [point, n, res["impulse"], v_out, w_out, res["u_out"]] + [a for a in (v_other, w_other) if a is not None]
    for a in arrays:
        a.setflags(write=False)
    return ImpactResult(
        target=kind,
        contact_point_m=point,
        normal=n,
        contact_height_m=height,
        force=pulse,
        peak_force_N=float(np.max(pulse.force_N)),
        duration_s=run["duration"],
        impulse_Ns=pulse.impulse_Ns,
        contacts=run["contacts"],
        effective_mass_kg=float(res["m_eff"]),
        normal_mass_kg=float(m_n),
        stiffness_N_m=float(res["k"]),
        damping_N_s_m=float(res["c"]),
        normal_velocity_in_m_s=float(res["v_in"]),
        normal_velocity_out_m_s=float(res["v_out"]),
        restitution=float(-res["v_out"] / res["v_in"]),
        base_shear=shear_x,
        base_shear_y=shear_y,
        normal_impulse_Ns=float(res["j_n"]),
        tangential_impulse_Ns=float(np.linalg.norm(res["j_t"])),
        impulse_vector_Ns=res["impulse"],
        sticking=res["sticking"],
        friction_limited=res["limited"],
        obliquity_deg=res["obliquity"],
        velocity_out_m_s=v_out,
        angular_velocity_out_rad_s=w_out,
        contact_velocity_out_m_s=res["u_out"],
        other_velocity_out_m_s=v_other,
        other_angular_velocity_out_rad_s=w_other,
        settled=run["settled"],
        energy=energy,
        history=run["history"],
    )


class _Block:
    """One bending direction of the column: banded matrices and the contact coupling vector.

    ``b = g f``: ``f`` the consistent load vector of a unit force at the contact height,
    ``g`` the component of ``-n`` along this direction; the column's displacement along
    ``-n`` at the contact point is ``b . u`` and the contact force F loads it as ``b F``.
    """

    def __init__(self, column: Column, height_m: float, gain: float):
        model = column_model(column)
        self.gain = gain
        self.k = model.stiffness
        self.m = model.mass
        self.c = model.damping
        self.a0 = model.rayleigh_a0_1_s
        self.inertia = np.asarray(model.inertia_vector)
        self.b = gain * model.load_vector(height_m)[model.free_dofs]
        self.k_band = upper_band(self.k)
        self.m_band = upper_band(self.m)
        self.c_band = upper_band(self.c)
        self.m_chol = linalg.cholesky_banded(self.m_band)
        k_chol = linalg.cholesky_banded(self.k_band)
        self.compliance = float(self.b @ linalg.cho_solve_banded((k_chol, False), self.b))
        freq = model.frequencies_Hz
        f_hi = freq[min(int(np.searchsorted(freq, _DT_BAND_HZ, side="right")), len(freq) - 1)]
        self.dt_limit = _DT_PHASE / (2.0 * math.pi * f_hi)
        self.size = len(self.b)

    def effective_chol(self, dt: float) -> np.ndarray:
        return linalg.cholesky_banded(self.k_band + (2.0 / dt) * self.c_band + (4.0 / dt**2) * self.m_band)

    def energy(self, u, v) -> float:
        return 0.5 * float(v @ (self.m @ v) + u @ (self.k @ u))


def _column_blocks(target: ColumnTarget, n: np.ndarray) -> tuple[_Block, ...]:
    blocks = []
    for axis in (0, 1):
        gain = -float(n[axis])
        if abs(gain) > 1e-12:
            blocks.append(_Block(target.axis_column(axis), target.height_m, gain))
        else:
            blocks.append(None)
    return tuple(blocks)


class _NormalIntegrator:
    """Newmark (average acceleration) on [column blocks..., body], contact on/off.

    Coordinates: ``u_i`` per column block, ``s`` the body's displacement along ``-n`` (into
    the obstacle). Compression ``delta = s - sum b_i . u_i = w . q`` with ``w = (-b_1, ...,
    1)``; contact force ``F = k delta + c delta'`` while in contact (F >= 0).
    """

    def __init__(self, m_eff, k, c, blocks):
        self.m = m_eff
        self.k = k
        self.c = c
        self.slots = blocks  # per axis: _Block or None
        self.blocks = [b for b in blocks if b is not None]
        self._factors = {}

    # -- linear algebra for one dt
    def _factor(self, dt):
        key = float(dt)
        fac = self._factors.get(key)
        if fac is None:
            chols = [b.effective_chol(dt) for b in self.blocks]
            z_blocks = [-linalg.cho_solve_banded((ch, False), b.b) for ch, b in zip(chols, self.blocks)]
            z_s = 1.0 / (4.0 * self.m / dt**2)
            w_dw = sum(float(-b.b @ z) for b, z in zip(self.blocks, z_blocks)) + z_s
            fac = (chols, z_blocks, z_s, w_dw)
            if len(self._factors) < 4:
                self._factors[key] = fac
        return fac

    def _step(self, state, dt, contact):
        """One Newmark step of length dt from ``state`` (a dict) in the given contact mode."""
        chols, z_blocks, z_s, w_dw = self._factor(dt)
        c44, c4, c2 = 4.0 / dt**2, 4.0 / dt, 2.0 / dt
        rhs = []
        for blk, u, v, a in zip(self.blocks, state["u"], state["v"], state["a"]):
            rhs.append(blk.m @ (c44 * u + c4 * v + a) + blk.c @ (c2 * u + v))
        rhs_s = self.m * (c44 * state["s"] + c4 * state["vs"] + state["as"])
        if contact and self.c > 0.0:
            wq = c2 * state["s"] + state["vs"] - sum(
                float(b.b @ (c2 * u + v)) for b, u, v in zip(self.blocks, state["u"], state["v"])
            )
            for i, blk in enumerate(self.blocks):
                rhs[i] = rhs[i] - self.c * wq * blk.b
            rhs_s += self.c * wq
        y = [linalg.cho_solve_banded((ch, False), r) for ch, r in zip(chols, rhs)]
        y_s = z_s * rhs_s
        if contact:
            alpha = self.k + c2 * self.c
            w_y = y_s - sum(float(b.b @ yy) for b, yy in zip(self.blocks, y))
            scale = alpha * w_y / (1.0 + alpha * w_dw)
            y = [yy - scale * z for yy, z in zip(y, z_blocks)]
            y_s = y_s - scale * z_s
        new = {"u": [], "v": [], "a": []}
        for u, v, a, un in zip(state["u"], state["v"], state["a"], y):
            du = un - u
            new["u"].append(un)
            new["v"].append(c2 * du - v)
            new["a"].append(c44 * du - c4 * v - a)
        ds = y_s - state["s"]
        new["s"] = y_s
        new["vs"] = c2 * ds - state["vs"]
        new["as"] = c44 * ds - c4 * state["vs"] - state["as"]
        return new

    def _delta(self, st):
        return st["s"] - sum(float(b.b @ u) for b, u in zip(self.blocks, st["u"]))

    def _delta_rate(self, st):
        return st["vs"] - sum(float(b.b @ v) for b, v in zip(self.blocks, st["v"]))

    def _force(self, st, contact):
        if not contact:
            return 0.0
        return self.k * self._delta(st) + self.c * self._delta_rate(st)

    def _equilibrate(self, st, contact):
        """Accelerations from the equations of motion (after a switch of the contact mode)."""
        f = self._force(st, contact)
        st["a"] = [
            linalg.cho_solve_banded((b.m_chol, False), b.b * f - b.c @ v - b.k @ u)
            for b, u, v in zip(self.blocks, st["u"], st["v"])
        ]
        st["as"] = -f / self.m
        return f

    def _column_energy(self, st):
        return sum(b.energy(u, v) for b, u, v in zip(self.blocks, st["u"], st["v"]))

    def _damping_work(self, old, new, dt, contact):
        col = 0.0
        for b, v0, v1 in zip(self.blocks, old["v"], new["v"]):
            va = 0.5 * (v0 + v1)
            col += dt * float(va @ (b.c @ va))
        con = 0.0
        if contact and self.c > 0.0:
            rate = 0.5 * (self._delta_rate(old) + self._delta_rate(new))
            con = dt * self.c * rate * rate
        return col, con

    def _base_shear(self, st, f):
        out = []
        it = iter(zip(self.blocks, st["u"], st["v"], st["a"]))
        for slot in self.slots:
            if slot is None:
                out.append(0.0)
                continue
            b, _, v, a = next(it)
            out.append(b.gain * f - float(b.inertia @ (a + b.a0 * v)))
        while len(out) < 2:
            out.append(0.0)
        return out

    def run(self, approach_speed, dt, max_watch):
        st = {
            "u": [np.zeros(b.size) for b in self.blocks],
            "v": [np.zeros(b.size) for b in self.blocks],
            "a": [np.zeros(b.size) for b in self.blocks],
            "s": 0.0,
            "vs": float(approach_speed),
            "as": 0.0,
        }
        contact = True
        f = self._equilibrate(st, contact)
        t = 0.0
        rec = {"t": [], "f": [], "d": [], "s": [], "o": [], "vx": [], "vy": []}

        def record(time, state, force):
            rec["t"].append(time)
            rec["f"].append(force)
            d = self._delta(state)
            rec["d"].append(d)
            rec["s"].append(state["s"])
            rec["o"].append(state["s"] - d)
            vx, vy = self._base_shear(state, force)
            rec["vx"].append(vx)
            rec["vy"].append(vy)

        record(t, st, f)
        col_damp = 0.0
        con_damp = 0.0
        contacts = 1
        last_separation = None
        settled = False
        compliance = sum(b.compliance for b in self.blocks)
        rigid = not self.blocks
        scale_f = max(self.k * approach_speed * math.sqrt(self.m / self.k), 1e-300)
        scale_d = approach_speed * math.sqrt(self.m / self.k)
        # After a damped contact opens, the massless spring-dashpot relaxes freely
        # (k x + c x' = 0) from the compression it had: the body touches it again when the
        # overlap reaches x(t). Undamped, x = 0 at once.
        sep_delta, sep_time = 0.0, 0.0

        def rest(time):
            if self.c <= 0.0 or sep_delta <= 0.0:
                return 0.0
            return sep_delta * math.exp(-(self.k / self.c) * (time - sep_time))

        while t < max_watch:
            trial = self._step(st, dt, contact)
            if contact:
                switch = self._force(trial, True) < 0.0
            else:
                switch = self._delta(trial) - rest(t + dt) > 0.0
            h = dt
            if switch:
                theta = self._crossing(st, t, dt, contact, rest, scale_f if contact else scale_d)
                if theta is None:  # a touch shorter than rounding: no switch
                    switch = False
                else:
                    h = theta * dt
                    trial = self._step(st, h, contact)
            cd, kd = self._damping_work(st, trial, h, contact)
            col_damp += cd
            con_damp += kd
            st = trial
            t += h
            if switch:
                if contact:  # the contact opens: F = 0 here
                    delta = self._delta(st)
                    # (Undamped, the force is k delta = 0 here: delta is zero to rounding.)
                    sep_delta, sep_time = (max(delta, 0.0) if self.c > 0.0 else 0.0), t
                    # The spring energy left is dissipated by the free dashpot (returned
                    # below if the body meets the spring again before it has relaxed).
                    con_damp += 0.5 * self.k * sep_delta * sep_delta
                    contact = False
                    f = self._equilibrate(st, contact)
                    last_separation = t
                    record(t, st, 0.0)
                else:  # the column caught the body again
                    x = rest(t)
                    con_damp -= 0.5 * self.k * x * x
                    contact = True
                    record(t, st, 0.0)
                    f = self._equilibrate(st, contact)
                    contacts += 1
                    if f != 0.0:  # a force jump (dashpot): keep the sample times increasing
                        t += 1e-9 * dt
                        record(t, st, f)
                continue
            f = self._force(st, contact)
            record(t, st, f)
            if not contact:
                if rigid:
                    settled = True
                    break
                # The column's contact point can never move further than `reach`.
                reach = math.sqrt(2.0 * max(self._column_energy(st), 0.0) * compliance)
                if st["s"] < -reach and st["vs"] <= 0.0:
                    settled = True
                    break
        column_energy = self._column_energy(st)
        duration = last_separation if (last_separation is not None and not contact) else t
        times = np.asarray(rec["t"])
        forces = np.asarray(rec["f"])
        end = int(np.searchsorted(times, duration, side="right"))
        end = max(end, 2)
        pulse = Tabulated(times[:end], np.maximum(forces[:end], 0.0))
        hist = ImpactHistory(
            time_s=times,
            force_N=forces,
            compression_m=np.asarray(rec["d"]),
            approach_m=np.asarray(rec["s"]),
            obstacle_m=np.asarray(rec["o"]),
            base_shear_x_N=np.asarray(rec["vx"]),
            base_shear_y_N=np.asarray(rec["vy"]),
        )
        for a in dataclasses.astuple(hist):
            a.setflags(write=False)
        return dict(
            pulse=pulse,
            history=hist,
            body_velocity=st["vs"],
            column_energy=column_energy,
            column_damping=col_damp,
            contact_damping=con_damp,
            contacts=contacts,
            duration=float(duration),
            settled=settled,
        )

    def _crossing(self, st, t, dt, contact, rest, scale):
        """Fraction of the step at which the contact switches (Brent), or None."""

        def g(theta):
            trial = self._step(st, theta * dt, contact)
            if contact:
                return self._force(trial, True)
            return self._delta(trial) - rest(t + theta * dt)

        lo = 1e-9
        g_lo = g(lo)
        if (contact and g_lo <= 0.0) or (not contact and g_lo >= 0.0):
            return lo if abs(g_lo) > 1e-12 * scale else None
        return brentq(g, lo, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)


def _base_shears(target: ColumnTarget, n, pulse: Tabulated, response_s):
    response_s = require_finite("response_s", response_s)
    if response_s < 0.0:
        raise InputError("response_s", f"must be >= 0, got {response_s!r}")
    times = pulse.time_s
    tail = np.arange(times[-1] + _RESPONSE_DT_S, times[-1] + response_s + 0.5 * _RESPONSE_DT_S, _RESPONSE_DT_S)
    t_out = np.concatenate([times, tail])
    out = []
    for axis in (0, 1):
        gain = -float(n[axis])
        if abs(gain) <= 1e-12:
            out.append(None)
            continue
        column = target.axis_column(axis)
        load = pulse.scaled(gain)
        # Modal superposition is exact for the piecewise-linear pulse but costs about
        # samples x modes x times; long pulses go to Newmark (agreement ~1e-4 of the peak).
        modal = column.damping_ratio > 0.0 and len(times) <= _MODAL_MAX_SAMPLES
        method = "modal" if modal else "newmark"
        out.append(mdof_response(load, column, target.height_m, t_out, method=method))
    return out[0], out[1]


# ------------------------------------------------------------------------------ helpers
def _tangent_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def _freeze(obj, name, arr):
    arr = np.array(arr, dtype=float)
    arr.setflags(write=False)
    object.__setattr__(obj, name, arr)


def _vector(name: str, value) -> np.ndarray:
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


def _unit(name: str, value) -> np.ndarray:
    arr = _vector(name, value)
    norm = float(np.linalg.norm(arr))
    if abs(norm - 1.0) > 1e-6:
        raise InputError(name, f"must be a unit vector, got length {norm:.6g}")
    return arr / norm


def _rotation(name: str, value) -> np.ndarray:
    rot = _matrix(name, value)
    if not np.allclose(rot.T @ rot, np.eye(3), atol=1e-6) or np.linalg.det(rot) < 0.0:
        raise InputError(name, "must be a proper rotation matrix (orthonormal, det +1)")
    return rot
