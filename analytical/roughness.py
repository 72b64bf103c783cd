"""A bed's Darcy friction factor as the equivalent sand roughness a wall function takes.

A turbulent flow over a rough bed feels its roughness through the wall function's Nikuradse
sand-grain height k_s; the study gives the bed's friction as a Darcy factor f (0.0293). The two
are tied by Colebrook's law for fully rough flow in an open channel of hydraulic radius R
(wide channel: R = the flow depth), as Chanson (2004, The Hydraulics of Open Channel Flow,
section 3.2) writes it::

    1 / sqrt(f) = 2 log10(14.8 R / k_s)     so    k_s = 14.8 R 10^(-1 / (2 sqrt(f)))

f depends on the depth through R: a rough bed has one k_s and a friction factor that falls as
the flow deepens. This module takes the depth the bore runs at (:func:`bore_depth_m`) as R, so
that the roughness gives the study's f where the study measured it, in the bore.
"""

from __future__ import annotations

import math

from analytical.dambreak import stoker_state
from analytical.errors import require_positive

__all__ = ["bore_depth_m", "darcy_factor", "sand_roughness_m"]

#: Colebrook's constant for a wide open channel (14.8 = 4 x 3.7: R = D / 4).
COLEBROOK_OPEN_CHANNEL = 14.8


def sand_roughness_m(friction_factor: float, hydraulic_radius_m: float) -> float:
    """Nikuradse sand roughness k_s (m) that gives Darcy ``friction_factor`` in fully rough
    flow of hydraulic radius ``hydraulic_radius_m`` (m): Colebrook's rough-wall law."""
    f = require_positive("friction_factor", friction_factor)
    r = require_positive("hydraulic_radius_m", hydraulic_radius_m)
    return COLEBROOK_OPEN_CHANNEL * r * 10.0 ** (-1.0 / (2.0 * math.sqrt(f)))


def darcy_factor(sand_roughness: float, hydraulic_radius_m: float) -> float:
    """Darcy f of fully rough flow over sand roughness ``sand_roughness`` (m) at hydraulic radius
    ``hydraulic_radius_m`` (m): the inverse of :func:`sand_roughness_m`."""
    ks = require_positive("sand_roughness", sand_roughness)
    r = require_positive("hydraulic_radius_m", hydraulic_radius_m)
    return (2.0 * math.log10(COLEBROOK_OPEN_CHANNEL * r / ks)) ** -2


def bore_depth_m(h0_m: float, wet_depth_m: float, g: float = 9.81) -> float:
    """The depth a dam-break flow runs at downstream of the gate (m): Stoker's depth behind the
    bore on a wet bed, Ritter's depth at the gate (4 h0 / 9) on a dry one."""
    h0 = require_positive("h0_m", h0_m)
    if wet_depth_m <= 0.0:
        return 4.0 * h0 / 9.0
    if wet_depth_m >= h0:
        return float(wet_depth_m)
    return stoker_state(h0, wet_depth_m, g).h2_m
