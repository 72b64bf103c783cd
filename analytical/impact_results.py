"""What an impact resolution returns: the result, its energy bookkeeping and the integrated history.

:func:`analytical.impact.impact` and :func:`analytical.impact.pair_impact` return an
:class:`ImpactResult`; the coupled integration (:mod:`analytical.contact_integration`)
records an :class:`ImpactHistory`. All frozen, SI units, vectors in the global frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytical.pulses import Tabulated
from analytical.sdof import ForceResponse

__all__ = ["ImpactEnergy", "ImpactHistory", "ImpactResult"]


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
