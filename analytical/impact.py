"""Impact of a rigid debris body on the column, a rigid wall or another body, over milliseconds.

The runner stops the CFD when a body reaches an obstacle (orchestrator/contact/geometry.py); this module
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
:data:`analytical.study.STUDY_DEBRIS_STIFFNESS_N_M`), optionally with a dashpot (default none),
and the spring acts on the obstacle:

* :class:`RigidWall`: the spring is grounded. Undamped, this is Haehnel & Daly's model: a
  half-sine of peak ``v sqrt(k m_eff)`` and duration ``pi sqrt(m_eff / k)``, restitution 1.
* :class:`ColumnTarget`: the spring is in series with the column's MDOF Timoshenko model
  (:func:`analytical.column_fem.column_model`) at the contact height. The horizontal part of
  ``-n`` loads the column's x-bending model and, if it has a y component, a second model
  of the same column with its section turned by 90 degrees (bending about x). The column is
  axially rigid and its torsion is not modelled. The coupled debris-spring-column system is
  integrated in time; the force history, the rebound (restitution) and the vibration left in
  the column **emerge** from it: no restitution coefficient is assumed.

The coupled system is integrated in time by :mod:`analytical.contact_integration` (Newmark
constant average acceleration, contact switches located inside their step, integration
until re-contact has become impossible), on a column in its modal coordinates
(:mod:`analytical.contact_modal`: the same scheme, a few times cheaper a step); the bodies and obstacles are
:mod:`analytical.impact_bodies`, the results :mod:`analytical.impact_results`.

The base shear at the load cell is the column's response to the resulting force pulse,
computed by :func:`analytical.mdof.mdof_response`: exact modal superposition, each mode carried
over the pulse's samples by an exact recurrence
(:func:`analytical.oscillator.piecewise_linear_response`), so its cost grows as (samples +
times) x modes; an undamped column uses the Newmark option. It is the same quantity the study's
MDOF fits produce. The coupled integration's own base shear is kept in
:attr:`ImpactResult.history` (it agrees with the modal one; a test checks it).

Body-body contacts (:func:`pair_impact`) use the two bodies' combined contact compliance
(two-body effective mass) on one spring with no column; its default stiffness is two of the study's
debris in series, ``k_d / 2``.

*Tangential part (impulse level).* Coulomb friction acts on the total impulse at the contact
point, ``J = J_n n + J_t``: stick (``J_t`` stops the contact point's sliding) when
``|J_t| <= mu J_n``, otherwise slip (``|J_t| = mu J_n``, along the direction the stick
impulse would have); ``dv = J / m_t``, ``d omega = I^-1 (r x J)``. Through the body's
rotation a tangential impulse also changes the contact point's normal velocity, so with
friction the normal dynamics see a different mass than ``m_eff``: the *normal mass*
``J_n / (v_out - v_in)`` of the combined impulse (Stronge's slip or stick effective mass).
The normal integration is repeated with that mass until the two agree to 1e-8 (one pass
without friction or without coupling, two or three otherwise; the first pass takes the mass
the law's rigid-wall rebound implies, which is within about 1e-3 of it), so the force history, the normal
impulse, the restitution and the final velocities are one consistent solution. Guards:
friction may not more than double the normal mass (the rigid-body "jam"), and where the
kinematic normal condition with friction would create kinetic energy (possible in 3-D) the
tangential impulse is reduced until friction dissipates (both reported as
``friction_limited``). The tangential force is not applied to the column.

Defaults and why
----------------
* ``added_mass_coefficient = 0``
  (:data:`~analytical.impact_bodies.DEFAULT_ADDED_MASS_COEFFICIENT`). For debris striking
  end-on (longitudinally), laboratory work found the water adds little to the impact force:
  Haehnel & Daly (2004) for logs, and Ko et al. (2015) for shipping-container models struck
  in water and in air; ASCE 7-16/7-22 Clause 6.11 accordingly has no added-mass term, and the
  study's debris stiffness (:data:`~analytical.study.STUDY_DEBRIS_STIFFNESS_N_M`) was backed out
  of that formula without one, so adding mass on top would double count. (The papers could
  not be retrieved here; these are their findings as widely quoted.) For sensitivity, Matsutomi's
  apparent-mass coefficient for driftwood in a bore, ``C_MA = 1.7``, means ``C_a = 0.7``
  (:data:`~analytical.impact_bodies.MATSUTOMI_ADDED_MASS_COEFFICIENT`). The floating 1:40 container (draft 0.026 m of
  0.06 m) moving lengthwise has a potential-flow ``C_a`` of 0.28 in the impulsive limit (an upper
  bound; :mod:`analytical.added_mass`); :func:`analytical.contact_law.column_impact` gives the
  body its own added mass along the normal by default, the container law being calibrated so.
* ``friction_coefficient = 0.3`` (:data:`DEFAULT_FRICTION_COEFFICIENT`): kinetic friction of
  polyethylene (the study's debris) on a smooth hard surface (acrylic, glass, steel) is
  quoted at 0.2-0.3 in engineering tables; water lubricates it downwards. 0.3, the upper end,
  gives the most rotation from a glancing blow. No measured value exists for the study's pair.
* ``damping_ratio = 0`` (contact dashpot as a fraction of ``2 sqrt(k m_eff)``): the energy a
  column impact loses must come out of the structural model, not from an assumed coefficient;
  Haehnel & Daly (2004) found damping negligible in the impact, and the study's ``k_d`` comes
  from their undamped formula; no damping was measured for the polyethylene containers.
  Give a value to model a lossy debris material; with a dashpot the contact ends when the
  force (spring + dashpot) returns to zero, and the spring energy left then is counted as lost.

Study comparison (Table 1 event: 0.236 kg at 1.5 m/s, column struck at 0.40 m)
-----------------------------------------------------------------------------
With ``k_d`` the coupled model gives 1137 N over 0.86 ms, 0.624 N s, restitution 0.76, base
shear 1004 N (rigid base; 886 N calibrated): between the study's ASCE 7-22 ``k_d`` row
(822 N = 0.65 x Haehnel & Daly's rigid-wall 1270 N, 0.6 ms, 0.46 N s) and the rigid wall,
and far from its MDOF fit (237 N, 4.7 ms, 0.71 N s). The MDOF fit's pulse is what this model
gives with an undamped contact about 30 times softer than ``k_d``: ``k = 1.05e5 N/m`` yields
231 N, 4.70 ms, 0.69 N s (tests/test_impact.py). That event is elastic and atypical; the shipped
container law (:mod:`analytical.contact_law`) is calibrated on the study's 22 impacts instead
(its Table 2), a damped spring, with the Table 1 event as its check.

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
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from analytical.contact_integration import NormalIntegrator
from analytical.contact_modal import ModalIntegrator, modal_blocks
from analytical.errors import InputError, require_finite, require_positive
from analytical.impact_bodies import (
    DEFAULT_ADDED_MASS_COEFFICIENT,
    Body,
    ColumnTarget,
    RigidWall,
    inverse_inertia_tensor,
    unit_vector,
    vector3,
)
from analytical.impact_results import ImpactEnergy, ImpactResult
from analytical.mdof import mdof_response
from analytical.pulses import Tabulated
from analytical.sdof import ForceResponse
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M

__all__ = [
    "DEFAULT_ADDED_MASS_COEFFICIENT",
    "DEFAULT_FRICTION_COEFFICIENT",
    "DEFAULT_CONTACT_DAMPING_RATIO",
    "Body",
    "ColumnTarget",
    "RigidWall",
    "ImpactResult",
    "inverse_inertia_tensor",
    "impact",
    "pair_impact",
    "with_base_shear",
]

DEFAULT_FRICTION_COEFFICIENT = 0.3
"""Coulomb coefficient of polyethylene debris on a smooth hard obstacle (see module doc)."""

DEFAULT_CONTACT_DAMPING_RATIO = 0.0
"""Contact dashpot as a fraction of ``2 sqrt(k m_eff)``: none (see module doc)."""

#: Newmark steps per contact period 2 pi sqrt(m_eff / k) (period error ~ (2 pi / 400)^2 / 12 = 2e-5).
_STEPS_PER_CONTACT_PERIOD = 400
#: Default output spacing of the base shear after the contact (s).
_RESPONSE_DT_S = 1.0e-5
#: The normal mass the integration runs with and the mass its impulse implies agree to this
#: (relative); the pulse then is the consistent one to about the same.
_MASS_TOLERANCE = 1.0e-8


# ------------------------------------------------------------------------------ API
def impact(
    body: Body,
    contact_point_m,
    normal,
    target: RigidWall | ColumnTarget,
    *,
    stiffness_N_m: float = STUDY_DEBRIS_STIFFNESS_N_M,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    damping_ratio: float = DEFAULT_CONTACT_DAMPING_RATIO,
    dt_s: float | None = None,
    max_watch_s: float = 0.5,
    response_s: float = 0.05,
    base_shear: bool = True,
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
        Contact (debris) stiffness k (N/m); default the study's k_d, 3.04e6 N/m.
    friction_coefficient:
        Coulomb mu (>= 0) for the tangential impulse.
    damping_ratio:
        Contact dashpot ``c = 2 zeta sqrt(k m_n)`` (0 <= zeta < 1; ``m_n`` the normal mass).
    dt_s:
        Time step (s); default ``T_c / 400``, ``T_c = 2 pi sqrt(m_n / k)`` (``m_n`` the
        normal mass): the contact's period to 2e-5, and the column's modes below about 6
        times the contact frequency phased to 0.1 % (``omega dt <= 0.1``). The higher modes
        follow the contact force quasi-statically, which the average-acceleration scheme
        gets right whatever ``omega dt``; the base shear is not taken from this integration
        but from the pulse by exact modal superposition. Against steps held to the column's
        modes up to 4 kHz (``omega dt <= 0.1``, 3.9e-6 s), the container law's pulses at
        0.09-0.6 m and 0-45 degrees agree to 2e-4 in peak, duration, impulse, restitution
        and base shear, at a fifth of the steps (tests/test_impact.py).
    max_watch_s:
        Longest time (s) integrated after the first contact while re-contact is possible.
    response_s:
        How long (s) after the pulse the base shear is reported.
    base_shear:
        False: leave the column's base shear out (``base_shear`` None); the pulse, rebound and
        impulse are the same. :func:`with_base_shear` adds it later (a transport run resolves
        every strike while it steps, and computes the base shear only of the strikes it reports).

    Raises
    ------
    InputError
        On bad input, or when the contact point is not approaching the obstacle.
    """
    if not isinstance(body, Body):
        raise InputError("body", f"must be an analytical.impact.Body, got {type(body).__name__}")
    if not isinstance(target, (RigidWall, ColumnTarget)):
        raise InputError("target", f"must be RigidWall() or ColumnTarget(column, height_m), got {target!r}")
    point = vector3("contact_point_m", contact_point_m)
    n = unit_vector("normal", normal)
    compliance = body.compliance(point)
    u0 = body.point_velocity(point)
    blocks = modal_blocks(target, n) if isinstance(target, ColumnTarget) else ()
    res = _resolve(
        n, compliance, u0, blocks, stiffness_N_m, friction_coefficient, damping_ratio, dt_s, max_watch_s
    )
    j = res["impulse"]
    v_out = body.velocity_m_s + body.inverse_translational_mass @ j
    w_out = body.angular_velocity_rad_s + body.inverse_inertia @ np.cross(point - body.centre_of_mass_m, j)
    shear_x = shear_y = None
    height = None
    if isinstance(target, ColumnTarget):
        height = target.height_m
        if base_shear:
            shear_x, shear_y = _base_shears(target, n, res["force"], response_s)
    return _result(target.kind, point, n, height, res, v_out, w_out, None, None, shear_x, shear_y)


def with_base_shear(result: ImpactResult, target: ColumnTarget, response_s: float = 0.05) -> ImpactResult:
    """``result`` (an :func:`impact` on ``target``) with the column's base shear: the same as
    :func:`impact` with ``base_shear=True``."""
    if not isinstance(target, ColumnTarget) or result.target != "column":
        raise InputError("target", "the base shear needs a column strike and its ColumnTarget")
    shear_x, shear_y = _base_shears(target, result.normal, result.force, response_s)
    return dataclasses.replace(result, base_shear=shear_x, base_shear_y=shear_y)


def pair_impact(
    body: Body,
    other: Body,
    contact_point_m,
    normal,
    *,
    stiffness_N_m: float = STUDY_DEBRIS_STIFFNESS_N_M / 2.0,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    damping_ratio: float = DEFAULT_CONTACT_DAMPING_RATIO,
    dt_s: float | None = None,
) -> ImpactResult:
    """Resolve a body-body impact: two-body effective mass on one contact spring, no column.

    ``normal`` points from ``other`` into ``body``; the impulse ``J`` acts on ``body`` and
    ``-J`` on ``other``. ``1 / m_eff = n . (K_body + K_other) n`` with each body's contact
    compliance (:meth:`Body.compliance`). The default stiffness is two of the study's debris in series,
    ``k_d / 2``. Velocities in the result are relative (``body`` minus ``other``) at the
    contact point; ``velocity_out_m_s`` etc. are ``body``'s, ``other_*`` the other's.
    """
    for name, b in (("body", body), ("other", other)):
        if not isinstance(b, Body):
            raise InputError(name, f"must be an analytical.impact.Body, got {type(b).__name__}")
    point = vector3("contact_point_m", contact_point_m)
    n = unit_vector("normal", normal)
    compliance = body.compliance(point) + other.compliance(point)
    u0 = body.point_velocity(point) - other.point_velocity(point)
    res = _resolve(n, compliance, u0, (), stiffness_N_m, friction_coefficient, damping_ratio, dt_s, 1.0)
    j = res["impulse"]
    v_a = body.velocity_m_s + body.inverse_translational_mass @ j
    w_a = body.angular_velocity_rad_s + body.inverse_inertia @ np.cross(point - body.centre_of_mass_m, j)
    v_b = other.velocity_m_s - other.inverse_translational_mass @ j
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

    # The normal dynamics run with the normal mass the contact actually has: m_eff without
    # friction; with friction coupled to the normal through the body's rotation, the mass
    # implied by the combined impulse (Stronge's slip/stick effective mass). A few passes
    # make the two consistent (the mass depends on the restitution only through stick).
    integrator_mass = _first_normal_mass(compliance, n, u0, v_in, m_eff, mu, zeta)
    for _ in range(8):
        c = 2.0 * zeta * math.sqrt(k * integrator_mass)
        step = dt
        if step is None:
            period = 2.0 * math.pi * math.sqrt(integrator_mass / k)
            step = period / _STEPS_PER_CONTACT_PERIOD
        integrator = ModalIntegrator if blocks else NormalIntegrator
        run = integrator(integrator_mass, k, c, blocks).run(-v_in, step, max_watch)
        v_out_n = -run["body_velocity"]  # body velocity along -n, back to along +n
        imp = _contact_impulse(compliance, n, u0, v_out_n, mu)
        mass = imp["j_n"] / (v_out_n - v_in)
        if abs(mass - integrator_mass) <= _MASS_TOLERANCE * integrator_mass:
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


def _first_normal_mass(compliance, n, u0, v_in, m_eff, mu, zeta):
    """The normal mass the first integration pass runs with: the mass the combined impulse
    implies for the rebound of the contact law against a rigid wall (``e = exp(-pi zeta /
    sqrt(1 - zeta^2))``, the linear spring-dashpot's). The normal mass depends on the rebound
    only weakly (through the direction of the stick impulse), so this guess is already close
    to the consistent mass and the passes after it only confirm it; ``m_eff`` without friction."""
    if mu == 0.0:
        return m_eff
    guess = -math.exp(-math.pi * zeta / math.sqrt(1.0 - zeta * zeta)) * v_in
    imp = _contact_impulse(compliance, n, u0, guess, mu)
    mass = imp["j_n"] / (guess - v_in)
    return mass if math.isfinite(mass) and mass > 0.0 else m_eff


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


def _base_shears(target: ColumnTarget, n, pulse: Tabulated, response_s):
    response_s = require_finite("response_s", response_s)
    if response_s < 0.0:
        raise InputError("response_s", f"must be >= 0, got {response_s!r}")
    times = pulse.time_s
    tail = np.arange(times[-1] + _RESPONSE_DT_S, times[-1] + response_s + 0.5 * _RESPONSE_DT_S, _RESPONSE_DT_S)
    t_out = np.concatenate([times, tail])
    out = []
    unit = {}  # the response to the unit-gain pulse, per distinct axis model (it is linear)
    for axis in (0, 1):
        gain = -float(n[axis])
        if abs(gain) <= 1e-12:
            out.append(None)
            continue
        column = target.axis_column(axis)
        if column not in unit:
            # Modal superposition is exact for the piecewise-linear pulse; it needs damped modes.
            method = "modal" if column.damping_ratio > 0.0 else "newmark"
            unit[column] = mdof_response(pulse, column, target.height_m, t_out, method=method).response_N
        direction = -1 if gain * pulse.peak_N < 0.0 else 1
        out.append(ForceResponse(t_out, gain * unit[column], direction=direction))
    return out[0], out[1]
