"""The dam break that makes a given bore: reservoir and wet-bed depths from the inundation a
designer knows (flow depth and speed at a site, as ASCE 7-22 chapter 6 gives them).

Stoker's (1957) wet-bed dam break (:func:`analytical.dambreak.stoker_state`) leaves a uniform
state ``(h2, u2)`` between the rarefaction and the bore. Read backwards:

* the bore's Rankine-Hugoniot relation ``u2 = (h2 - hr) sqrt(g (h2 + hr) / (2 h2 hr))`` makes the
  plateau's Froude number ``Fr = u2 / sqrt(g h2) = (1 - r) sqrt((1 + r) / (2 r))`` a function of
  ``r = hr / h2`` alone, strictly decreasing from infinity (r -> 0) to 0 (r -> 1): a requested
  ``(h2, u2)`` fixes ``r`` and so the wet bed ``hr = r h2``;
* the Riemann invariant through the rarefaction, ``u2 + 2 sqrt(g h2) = 2 sqrt(g h0)``, fixes the
  reservoir: ``h0 = h2 (1 + Fr / 2)^2``.

Both are exact for the frictionless shallow-water equations (no root-finding error beyond
``brentq``'s). A given wet bed allows one Froude number at a given depth; a request that does
not match it is refused by the caller (:func:`froude_on_wet_bed`).

How long the state lasts at a point ``x`` downstream of the gate: from the bore's arrival
``x / S`` until the rarefaction's tail passes (only when the plateau is supercritical, its tail
moving downstream at ``u2 - c2 > 0``) or the head of the negative wave reflected from the
reservoir's upstream wall arrives. That head runs on the C+ characteristic of the undisturbed
flow: through Ritter's fan ``x(t) = 2 c0 t - 3 L^(2/3) c0^(1/3) t^(1/3)`` (from ``x = -L`` at
``t = L / c0``; Stoker 1957, 10.8), then through the plateau at ``u2 + c2``.
:func:`reflection_arrival_s` is that time and :func:`reservoir_length_for` its inverse.

Units: m, s, m/s; ``g`` in m/s^2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from scipy.optimize import brentq

from analytical.dambreak import G_DEFAULT, stoker_state
from analytical.errors import InputError, require_positive

__all__ = [
    "BoreSizing",
    "froude_on_wet_bed",
    "plateau_froude",
    "reflection_arrival_s",
    "reservoir_length_for",
    "size_dam_break",
]


def plateau_froude(r: float) -> float:
    """Froude number ``u2 / sqrt(g h2)`` behind a bore into still water of depth ``r h2``
    (0 < r < 1): ``(1 - r) sqrt((1 + r) / (2 r))``."""
    if not 0.0 < r < 1.0:
        raise InputError("r", f"must be between 0 and 1 (wet bed over flow depth), got {r!r}")
    return (1.0 - r) * math.sqrt((1.0 + r) / (2.0 * r))


def _ratio_for_froude(froude: float) -> float:
    """The r = hr / h2 with plateau_froude(r) = froude (> 0)."""
    # plateau_froude falls strictly from +inf to 0 on (0, 1): solve for ln r, which spans any Froude
    # number a float can hold; log(Fr) keeps the residual's scale even
    def gap(s: float) -> float:
        return math.log(plateau_froude(math.exp(s))) - math.log(froude)
    return math.exp(brentq(gap, -690.0, math.log1p(-1e-15), xtol=1e-15, maxiter=500))


@dataclass(frozen=True)
class BoreSizing:
    """The dam break that makes the plateau ``(depth_m, speed_m_s)``.

    ``reservoir_depth_m`` h0, ``wet_bed_depth_m`` hr, ``froude`` of the plateau,
    ``bore_speed_m_s`` S, ``tail_speed_m_s`` u2 - c2 (the rarefaction's downstream end; > 0:
    the plateau is supercritical and passes a point in finite time), ``g``.
    """

    depth_m: float
    speed_m_s: float
    reservoir_depth_m: float
    wet_bed_depth_m: float
    froude: float
    bore_speed_m_s: float
    tail_speed_m_s: float
    g: float = G_DEFAULT

    def bore_arrival_s(self, x_m: float) -> float:
        """When the bore reaches ``x_m`` (> 0) downstream of the gate (s)."""
        return require_positive("x_m", x_m) / self.bore_speed_m_s

    def plateau_end_s(self, x_m: float, reservoir_length_m: float) -> float:
        """When the plateau ends at ``x_m`` (s): the rarefaction's tail passing (a supercritical
        plateau) or the reflected negative wave arriving, whichever is first."""
        reflected = reflection_arrival_s(x_m, reservoir_length_m, self.reservoir_depth_m, self.wet_bed_depth_m, self.g)
        tail = x_m / self.tail_speed_m_s if self.tail_speed_m_s > 0 else math.inf
        return min(reflected, tail)


def size_dam_break(depth_m: float, speed_m_s: float, g: float = G_DEFAULT) -> BoreSizing:
    """Reservoir and wet-bed depths whose Stoker plateau is ``depth_m`` deep at ``speed_m_s``
    (module notes). Checked against :func:`analytical.dambreak.stoker_state` by the tests."""
    h2 = require_positive("depth_m", depth_m)
    u2 = require_positive("speed_m_s", speed_m_s)
    g = require_positive("g", g)
    froude = u2 / math.sqrt(g * h2)
    r = _ratio_for_froude(froude)
    hr = r * h2
    h0 = h2 * (1.0 + 0.5 * froude) ** 2
    bore = h2 * u2 / (h2 - hr)
    return BoreSizing(h2, u2, h0, hr, froude, bore, u2 - math.sqrt(g * h2), g)


def froude_on_wet_bed(depth_m: float, wet_bed_depth_m: float) -> float:
    """The only plateau Froude number a dam break makes at ``depth_m`` on a wet bed
    ``wet_bed_depth_m`` deep (0 < wet bed < depth)."""
    h2 = require_positive("depth_m", depth_m)
    hr = require_positive("wet_bed_depth_m", wet_bed_depth_m)
    if hr >= h2:
        raise InputError("wet_bed_depth_m", f"must be shallower than the bore's depth {h2!r}, got {hr!r}")
    return plateau_froude(hr / h2)


def reflection_arrival_s(x_m: float, reservoir_length_m: float, h0_m: float, hr_m: float,
                         g: float = G_DEFAULT) -> float:
    """When the head of the negative wave reflected from the upstream wall (``reservoir_length_m``
    behind the gate) reaches ``x_m`` >= 0 downstream of the gate (s), on Stoker's solution for
    ``h0_m``, ``hr_m`` (module notes)."""
    length = require_positive("reservoir_length_m", reservoir_length_m)
    x = float(x_m)
    if not math.isfinite(x) or x < 0:
        raise InputError("x_m", f"must be a finite position at or downstream of the gate, got {x_m!r}")
    st = stoker_state(h0_m, hr_m, g)
    c0 = math.sqrt(g * h0_m)
    c2 = math.sqrt(g * st.h2_m)
    tail = st.rarefaction_tail_speed_m_s
    k = 3.0 * length ** (2.0 / 3.0) * c0 ** (1.0 / 3.0)
    # leaving the fan: x(t) / t = tail  <=>  2 c0 - k t^(-2/3) = tail
    t_exit = (k / (2.0 * c0 - tail)) ** 1.5
    x_exit = tail * t_exit
    if x <= x_exit:  # still in the fan: solve x(t) = x on t >= L / c0 (x(t) increases there)
        t0 = length / c0
        hi = max(2 * t0, t_exit)
        return brentq(lambda t: 2 * c0 * t - k * t ** (1.0 / 3.0) - x, t0, hi, xtol=1e-12 * hi)
    return t_exit + (x - x_exit) / (st.u2_m_s + c2)


def reservoir_length_for(x_m: float, until_s: float, h0_m: float, hr_m: float, g: float = G_DEFAULT) -> float:
    """The shortest reservoir whose reflected negative wave reaches ``x_m`` no earlier than
    ``until_s`` (m): the inverse of :func:`reflection_arrival_s` in the reservoir's length
    (which the arrival time increases with)."""
    require_positive("until_s", until_s)
    c0 = math.sqrt(g * require_positive("h0_m", h0_m))
    lo, hi = 1e-9, max(until_s * c0, 1.0)
    while reflection_arrival_s(x_m, hi, h0_m, hr_m, g) < until_s:
        hi *= 2.0
    return brentq(lambda L: reflection_arrival_s(x_m, L, h0_m, hr_m, g) - until_s, lo, hi, xtol=1e-10 * hi)
