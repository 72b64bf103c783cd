"""Analytical solutions of the instantaneous dam break in a wide horizontal channel.

Three classical solutions of the Saint-Venant (shallow-water) equations, all for a
semi-infinite reservoir of still water of depth ``h0_m`` behind a gate that vanishes at
``t = 0``:

* :class:`RitterSolution`  -- dry, frictionless bed (Ritter 1892);
* :class:`StokerSolution`  -- wet, frictionless bed of still water of depth ``hr_m``
  (Stoker 1957): rarefaction, constant intermediate state, bore;
* :class:`ChansonSolution` -- dry bed with turbulent bed friction (Darcy-Weisbach
  factor ``f``) in the friction-dominated wave tip (Chanson 2006, 2009).

Coordinates and units (SI throughout)
-------------------------------------
``x`` (m) runs along the channel, 0 at the gate, positive downstream; the reservoir
occupies ``x < 0``. ``t`` (s) is measured from the gate removal. Depths ``h`` in m,
depth-averaged velocities ``u`` in m/s (positive downstream), ``g`` in m/s^2.

All solutions share one interface (see :func:`dam_break` and :data:`MODELS`):

``profile(x_m, t_s) -> Profile(depth_m, velocity_m_s)``
    Depth and velocity along ``x_m`` (any shape) at one time ``t_s >= 0``.
``front_position_m(t_s)``
    Position of the leading edge (wet/dry front, or the bore on a wet bed).
``arrival_time_s(x_m)``
    Time at which that leading edge reaches ``x_m``; 0 for ``x_m <= 0`` (wet from the
    start).

References
----------
Ritter, A. (1892). Die Fortpflanzung der Wasserwellen. Zeitschrift des Vereines
    Deutscher Ingenieure 36(33), 947-954.
Stoker, J.J. (1957). Water Waves. Interscience, New York, Section 10.8.
Chanson, H. (2006). Analytical solutions of laminar and turbulent dam break wave.
    River Flow 2006 (Ferreira, Alves, Leal & Cardoso eds), Taylor & Francis, 465-474.
Chanson, H. (2009). Application of the method of characteristics to the dam break wave
    problem. Journal of Hydraulic Research 47(1), 41-49.
Chanson, H. (2005). Applications of the Saint-Venant equations and method of
    characteristics to the dam break wave problem. Report CH55/05, Department of Civil
    Engineering, The University of Queensland.

The Chanson equations used here (celerity cubic, front position, tip shape) are those
restated from Chanson (2005/2006) by the tilupy project's documentation; they were
re-derived independently (Ritter characteristics behind the tip, uniform-velocity
friction balance in the tip, volume balance fixing U) and reproduce the flume values
0.871 s at x = 2.40 m and 1.201 s at x = 3.20 m for h0 = 0.40 m, f = 0.0293.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, NamedTuple

import numpy as np
from scipy.optimize import brentq

from analytical.errors import InputError, require_positive

__all__ = [
    "G_DEFAULT",
    "MODELS",
    "ChansonSolution",
    "Profile",
    "RitterSolution",
    "StokerSolution",
    "StokerState",
    "chanson_front_celerity",
    "dam_break",
    "stoker_state",
]

#: Default gravitational acceleration (m/s^2).
G_DEFAULT = 9.81


class Profile(NamedTuple):
    """Depth (m) and depth-averaged velocity (m/s) along x at one instant.

    A named tuple: ``depth, velocity = sol.profile(x, t)`` works.
    """

    depth_m: np.ndarray | float
    velocity_m_s: np.ndarray | float


# --------------------------------------------------------------------------- checks


def _finite_array(name: str, value, *, nonnegative: bool = False) -> np.ndarray:
    """``value`` as a float array; InputError naming ``name`` if NaN/inf (or < 0)."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number or an array of numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "must be finite (no NaN or inf)")
    if nonnegative and np.any(arr < 0.0):
        raise InputError(name, f"must be >= 0, got min {float(np.min(arr))!r}")
    return arr


def _time(t_s) -> float:
    """One time instant (s), finite and >= 0."""
    arr = _finite_array("t_s", t_s, nonnegative=True)
    if arr.ndim != 0:
        raise InputError("t_s", "profile() takes one time instant (a scalar)")
    return float(arr)


def _positions(x_m) -> tuple[np.ndarray, tuple[int, ...]]:
    """Positions (m) as a flat float array plus the caller's shape."""
    x = _finite_array("x_m", x_m)
    return x.reshape(-1).copy(), x.shape


def _profile(h: np.ndarray, u: np.ndarray, shape: tuple[int, ...]) -> Profile:
    """Package depth/velocity in the caller's shape (floats for a scalar position)."""
    if shape == ():
        return Profile(float(h[0]), float(u[0]))
    return Profile(h.reshape(shape), u.reshape(shape))


def _out(arr: np.ndarray):
    """Return a 0-d result as a Python float, arrays unchanged."""
    return float(arr) if np.ndim(arr) == 0 else arr


# ------------------------------------------------------------------------- Ritter


def _ritter_fan(x: np.ndarray, t: float, c0: float, g: float) -> tuple[np.ndarray, np.ndarray]:
    """Centred rarefaction of Ritter: h = (2 c0 - x/t)^2 / (9 g), u = 2/3 (c0 + x/t)."""
    xi = x / t
    return (2.0 * c0 - xi) ** 2 / (9.0 * g), (2.0 / 3.0) * (c0 + xi)


class _Reservoir:
    """What Ritter's and Chanson's solutions share: a reservoir ``h0_m`` deep under gravity ``g``."""

    h0_m: float
    g: float

    def _require_positive(self, *names: str) -> None:
        for name in names:
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))

    @property
    def c0_m_s(self) -> float:
        """Shallow-water wave celerity of the reservoir, ``sqrt(g h0)`` (m/s)."""
        return math.sqrt(self.g * self.h0_m)

    def _before_the_break(self, x_m, t_s):
        """The positions (flat) and their shape, the time, and the depth and velocity at rest
        there: the reservoir behind the gate (x < 0), dry beyond."""
        x, shape = _positions(x_m)
        return x, shape, _time(t_s), np.where(x < 0.0, self.h0_m, 0.0), np.zeros_like(x)


@dataclass(frozen=True)
class RitterSolution(_Reservoir):
    """Ritter (1892): dam break on a dry, frictionless horizontal bed.

    With ``c0 = sqrt(g h0)``, for ``t > 0``:

    * ``x <= -c0 t``: undisturbed reservoir, ``h = h0``, ``u = 0``;
    * ``-c0 t < x < 2 c0 t``: ``h = (2 c0 - x/t)^2 / (9 g)``, ``u = 2/3 (c0 + x/t)``;
    * ``x >= 2 c0 t``: dry, ``h = 0`` (velocity reported as 0).

    The depth at the gate is ``4/9 h0`` at every ``t > 0``; the front moves at ``2 c0``.

    Parameters
    ----------
    h0_m: reservoir depth (m), > 0.
    g: gravitational acceleration (m/s^2), > 0.
    """

    h0_m: float
    g: float = G_DEFAULT

    def __post_init__(self):
        self._require_positive("h0_m", "g")

    @property
    def front_speed_m_s(self) -> float:
        """Speed of the wet/dry front, ``2 sqrt(g h0)`` (m/s)."""
        return 2.0 * self.c0_m_s

    def profile(self, x_m, t_s) -> Profile:
        """Depth (m) and velocity (m/s) at positions ``x_m`` (m, any shape) at time ``t_s`` (s)."""
        x, shape, t, h, u = self._before_the_break(x_m, t_s)
        if t == 0.0:
            return _profile(h, u, shape)
        c0 = self.c0_m_s
        fan = (x > -c0 * t) & (x < 2.0 * c0 * t)
        hf, uf = _ritter_fan(x[fan], t, c0, self.g)
        h[fan] = hf
        u[fan] = uf
        return _profile(h, u, shape)

    def front_position_m(self, t_s):
        """Front position ``x_f = 2 sqrt(g h0) t`` (m) for ``t_s >= 0`` (s); vectorised."""
        t = _finite_array("t_s", t_s, nonnegative=True)
        return _out(self.front_speed_m_s * t)

    def arrival_time_s(self, x_m):
        """Front arrival time ``x / (2 sqrt(g h0))`` (s) at ``x_m`` (m); 0 where ``x_m <= 0``."""
        x = _finite_array("x_m", x_m)
        return _out(np.maximum(x, 0.0) / self.front_speed_m_s)


# ------------------------------------------------------------------------- Stoker


@dataclass(frozen=True)
class StokerState:
    """The constant intermediate state of Stoker's wet-bed dam break.

    Attributes
    ----------
    h2_m, u2_m_s: depth (m) and velocity (m/s) between the rarefaction and the bore.
    shock_speed_m_s: speed of the bore (m/s), positive downstream.
    rarefaction_tail_speed_m_s: ``u2 - sqrt(g h2)`` (m/s), the speed of the rarefaction's
        downstream end (may be negative for deep tailwater).
    """

    h2_m: float
    u2_m_s: float
    shock_speed_m_s: float
    rarefaction_tail_speed_m_s: float


def stoker_state(h0_m: float, hr_m: float, g: float = G_DEFAULT) -> StokerState:
    """Solve Stoker's (1957) intermediate state for reservoir ``h0_m`` and tailwater ``hr_m``.

    Unknown ``h2`` (hr < h2 < h0) is the root of ``u_R(h2) = u_S(h2)`` where

    * ``u_R = 2 (sqrt(g h0) - sqrt(g h2))``: the Riemann invariant carried through the
      rarefaction from the still reservoir (``u + 2 sqrt(g h)`` constant);
    * ``u_S = (h2 - hr) sqrt(g (h2 + hr) / (2 h2 hr))``: the velocity behind a bore moving
      into still water of depth ``hr`` (Rankine-Hugoniot mass and momentum).

    The bore speed is ``S = h2 u2 / (h2 - hr)``. Solved with ``scipy.optimize.brentq``
    (the difference is monotone in h2 and changes sign on the bracket) for any
    ``0 < hr < h0``.

    Parameters in m, m/s^2; raises InputError for h0 <= 0, hr <= 0, hr >= h0.
    """
    h0 = require_positive("h0_m", h0_m)
    g = require_positive("g", g)
    hr = require_positive("hr_m", hr_m)
    if hr >= h0:
        raise InputError("hr_m", f"must be < h0_m ({h0!r}), got {hr_m!r}")

    c0 = math.sqrt(g * h0)

    def u_rarefaction(h2: float) -> float:
        return 2.0 * (c0 - math.sqrt(g * h2))

    def u_shock(h2: float) -> float:
        return (h2 - hr) * math.sqrt(g * (h2 + hr) / (2.0 * h2 * hr))

    # u_rarefaction - u_shock is > 0 at h2 = hr and < 0 at h2 = h0, strictly decreasing.
    h2 = brentq(
        lambda h: u_rarefaction(h) - u_shock(h),
        hr,
        h0,
        xtol=1e-15 * h0,
        rtol=4.0 * np.finfo(float).eps,
        maxiter=500,
    )
    u2 = u_shock(h2)
    speed = h2 * u2 / (h2 - hr)
    return StokerState(
        h2_m=h2,
        u2_m_s=u2,
        shock_speed_m_s=speed,
        rarefaction_tail_speed_m_s=u2 - math.sqrt(g * h2),
    )


@dataclass(frozen=True)
class StokerSolution:
    """Stoker (1957): dam break on a wet, frictionless horizontal bed of depth ``hr``.

    For ``t > 0`` (``c0 = sqrt(g h0)``, state from :func:`stoker_state`):

    * ``x <= -c0 t``: ``h = h0``, ``u = 0``;
    * ``-c0 t < x < (u2 - sqrt(g h2)) t``: Ritter's rarefaction fan;
    * ``(u2 - sqrt(g h2)) t <= x < S t``: ``h = h2``, ``u = u2``;
    * ``x >= S t``: ``h = hr``, ``u = 0`` (the bore is at ``x = S t``).

    Parameters
    ----------
    h0_m: reservoir depth (m), > 0.
    hr_m: downstream still-water depth (m), 0 < hr < h0.
    g: gravitational acceleration (m/s^2).
    """

    h0_m: float
    hr_m: float
    g: float = G_DEFAULT
    state: StokerState = field(init=False, repr=False)

    def __post_init__(self):
        st = stoker_state(self.h0_m, self.hr_m, self.g)
        object.__setattr__(self, "h0_m", float(self.h0_m))
        object.__setattr__(self, "hr_m", float(self.hr_m))
        object.__setattr__(self, "g", float(self.g))
        object.__setattr__(self, "state", st)

    @property
    def c0_m_s(self) -> float:
        """``sqrt(g h0)`` (m/s)."""
        return math.sqrt(self.g * self.h0_m)

    def profile(self, x_m, t_s) -> Profile:
        """Depth (m) and velocity (m/s) at positions ``x_m`` (m, any shape) at time ``t_s`` (s)."""
        x, shape = _positions(x_m)
        t = _time(t_s)
        h = np.where(x < 0.0, self.h0_m, self.hr_m)
        u = np.zeros_like(x)
        if t == 0.0:
            return _profile(h, u, shape)
        st = self.state
        c0 = self.c0_m_s
        x_tail = st.rarefaction_tail_speed_m_s * t
        x_bore = st.shock_speed_m_s * t
        fan = (x > -c0 * t) & (x < x_tail)
        plateau = (x >= x_tail) & (x < x_bore)
        hf, uf = _ritter_fan(x[fan], t, c0, self.g)
        h[fan] = hf
        u[fan] = uf
        h[plateau] = st.h2_m
        u[plateau] = st.u2_m_s
        h[x >= x_bore] = self.hr_m
        u[x >= x_bore] = 0.0
        return _profile(h, u, shape)

    def front_position_m(self, t_s):
        """Bore position ``S t`` (m) for ``t_s >= 0`` (s); vectorised."""
        t = _finite_array("t_s", t_s, nonnegative=True)
        return _out(self.state.shock_speed_m_s * t)

    def arrival_time_s(self, x_m):
        """Bore arrival time ``x / S`` (s) at ``x_m`` (m); 0 where ``x_m <= 0``."""
        x = _finite_array("x_m", x_m)
        return _out(np.maximum(x, 0.0) / self.state.shock_speed_m_s)


# ------------------------------------------------------------------------ Chanson


def _chanson_time_from_celerity(u_star, friction: float):
    """Dimensionless time ``T = t sqrt(g/h0)`` at which the tip celerity is ``U* = U/sqrt(g h0)``.

    Inverse of Chanson's celerity equation ``(2 - U*)^3 = 3 f T U*^2`` (see
    :func:`chanson_front_celerity`), explicit in T.
    """
    return (2.0 - u_star) ** 3 / (3.0 * friction * u_star**2)


def _chanson_celerity_star(big_t: float, friction: float) -> float:
    """Dimensionless tip celerity U* in (0, 2] at dimensionless time ``T`` (root of the cubic)."""
    if big_t == 0.0:
        return 2.0
    k = 3.0 * friction * big_t
    # (2 - U)^3 - k U^2: +8 at U = 0, -4k < 0 at U = 2, strictly decreasing in between.
    return brentq(
        lambda us: (2.0 - us) ** 3 - k * us * us,
        0.0,
        2.0,
        xtol=1e-15,
        rtol=4.0 * np.finfo(float).eps,
        maxiter=500,
    )


def chanson_front_celerity(t_s, h0_m: float, friction: float, g: float = G_DEFAULT):
    """Wave-front celerity U (m/s) of Chanson's turbulent dam-break wave on a dry bed.

    Chanson (2005, 2006, 2009; horizontal dry bed) obtains the dimensionless
    celerity ``U* = U / sqrt(g h0)`` at ``T = t sqrt(g/h0)`` as the root in (0, 2] of

        U*^3 - 8 (3/4 - 3 f T / 8) U*^2 + 12 U* - 8 = 0,

    i.e. ``(2 - U*)^3 = 3 f T U*^2``. ``f`` is the Darcy-Weisbach friction factor.
    U* = 2 (Ritter) at T = 0 and decreases with time. Vectorised over ``t_s`` (s).
    """
    h0 = require_positive("h0_m", h0_m)
    f = require_positive("friction", friction)
    g = require_positive("g", g)
    t = _finite_array("t_s", t_s, nonnegative=True)
    scale = math.sqrt(g / h0)
    us = np.vectorize(lambda tt: _chanson_celerity_star(tt * scale, f), otypes=[float])(t)
    return _out(us * math.sqrt(g * h0))


@dataclass(frozen=True)
class ChansonSolution(_Reservoir):
    """Chanson (2006, 2009): turbulent dam-break wave on a dry horizontal bed with friction.

    Method of characteristics with two regions (``c0 = sqrt(g h0)``, ``U(t)`` from
    :func:`chanson_front_celerity`, Darcy friction ``f``):

    * ideal-fluid region behind the tip, ``-c0 t < x < x1``: Ritter's solution,
      ``h = (2 c0 - x/t)^2 / (9 g)``, ``u = 2/3 (c0 + x/t)``, ending where the Ritter
      velocity equals the tip celerity, ``x1 = (3/2 U - c0) t``;
    * friction-dominated wave tip, ``x1 <= x <= xs``: the fluid moves at ``U`` and the
      surface follows the uniform-velocity friction balance
      ``h dh/dx = -f U^2 / (8 g)``, i.e.
      ``h/h0 = sqrt( (f/4) (U^2 / (g h0)) (xs - x)/h0 )``;
    * front (Chanson's eq. for x_s):
      ``xs/h0 = (3/2 U/c0 - 1) t sqrt(g/h0) + 4 / (f (U/c0)^2) (1 - U/(2 c0))^4``.

    The celerity equation is exactly the statement that the tip holds the volume the
    Ritter solution would have carried beyond ``x1``, so this solution conserves mass.
    With it the front simplifies to ``xs = (c0/2 + 3 U/4) t``. As ``f -> 0``, ``U -> 2 c0``
    and the solution tends to Ritter's.

    Limitations (of the theory, reported, not corrected): the tip is assumed to move as
    a block at ``U``, which is not exactly ``d xs/dt`` (for h0 = 0.40 m, f = 0.0293 at
    t = 0.871 s: U = 2.35 m/s, d xs/dt = 2.48 m/s); once ``U < 2/3 c0``, i.e.
    ``t sqrt(g/h0) > 16/(9 f)``, the friction-dominated tip reaches back past the gate
    (``x1 < 0``) into the reservoir, outside the theory's intended range (the volume
    balance still holds). See :attr:`validity_limit_s`.

    Parameters
    ----------
    h0_m: reservoir depth (m), > 0.
    friction: Darcy-Weisbach friction factor f (-), > 0.
    g: gravitational acceleration (m/s^2).
    """

    h0_m: float
    friction: float
    g: float = G_DEFAULT

    def __post_init__(self):
        self._require_positive("h0_m", "friction", "g")

    @property
    def time_scale_s(self) -> float:
        """``sqrt(h0/g)`` (s): ``T = t / time_scale_s``."""
        return math.sqrt(self.h0_m / self.g)

    @property
    def validity_limit_s(self) -> float:
        """Time (s) at which the tip region reaches back to the gate (``U = 2/3 c0``)."""
        return float(_chanson_time_from_celerity(2.0 / 3.0, self.friction)) * self.time_scale_s

    def front_celerity_m_s(self, t_s):
        """Tip celerity U (m/s) at ``t_s`` (s); vectorised."""
        return chanson_front_celerity(t_s, self.h0_m, self.friction, self.g)

    def tip_start_position_m(self, t_s):
        """Upstream end of the friction-dominated tip, ``x1 = (3/2 U - c0) t`` (m)."""
        t = _finite_array("t_s", t_s, nonnegative=True)
        u = np.asarray(self.front_celerity_m_s(t))
        return _out((1.5 * u - self.c0_m_s) * t)

    def front_position_m(self, t_s):
        """Front position xs (m) at ``t_s`` (s), Chanson's equation; vectorised."""
        t = _finite_array("t_s", t_s, nonnegative=True)
        us = np.asarray(self.front_celerity_m_s(t)) / self.c0_m_s
        return _out(self._front_star(us, t / self.time_scale_s) * self.h0_m)

    def _front_star(self, us, big_t):
        """Chanson's dimensionless front ``xs/h0`` from U* and T (as printed in the paper)."""
        us = np.asarray(us, dtype=float)
        big_t = np.asarray(big_t, dtype=float)
        ideal = (1.5 * us - 1.0) * big_t
        with np.errstate(divide="ignore", invalid="ignore"):
            tip = 4.0 / (self.friction * us**2) * (1.0 - 0.5 * us) ** 4
        return ideal + np.where(us >= 2.0, 0.0, tip)

    def profile(self, x_m, t_s) -> Profile:
        """Depth (m) and velocity (m/s) at positions ``x_m`` (m, any shape) at time ``t_s`` (s)."""
        x, shape, t, h, u = self._before_the_break(x_m, t_s)
        if t == 0.0:
            return _profile(h, u, shape)
        c0 = self.c0_m_s
        big_u = float(self.front_celerity_m_s(t))
        x1 = (1.5 * big_u - c0) * t
        xs = float(self.front_position_m(t))
        fan = (x > -c0 * t) & (x < x1)
        tip = (x >= x1) & (x < xs)
        hf, uf = _ritter_fan(x[fan], t, c0, self.g)
        h[fan] = hf
        u[fan] = uf
        h[tip] = np.sqrt(self.friction * big_u**2 * (xs - x[tip]) / (4.0 * self.g))
        u[tip] = big_u
        h[x >= xs] = 0.0
        u[x >= xs] = 0.0
        return _profile(h, u, shape)

    def arrival_time_s(self, x_m):
        """Front arrival time (s) at ``x_m`` (m); 0 where ``x_m <= 0``; vectorised.

        Solved in the celerity: for U* in (0, 2), ``T(U*)`` is explicit from the
        celerity equation and ``xs(U*)/h0 = (1/2 + 3/4 U*) T(U*)`` decreases strictly
        with U*, so ``xs = x`` has one root (brentq).
        """
        x = _finite_array("x_m", x_m)
        f = self.friction

        def one(xx: float) -> float:
            if xx <= 0.0:
                return 0.0
            target = xx / self.h0_m

            def resid(us: float) -> float:
                big_t = _chanson_time_from_celerity(us, f)
                return float(self._front_star(us, big_t)) - target

            lo = 1.0
            while resid(lo) < 0.0:  # make sure the bracket holds the root
                lo *= 0.5
            us = brentq(resid, lo, 2.0, xtol=1e-15, rtol=4.0 * np.finfo(float).eps, maxiter=500)
            return float(_chanson_time_from_celerity(us, f)) * self.time_scale_s

        return _out(np.vectorize(one, otypes=[float])(x))


# ---------------------------------------------------------------------- registry


def _make_ritter(h0_m, hr_m, friction, g) -> RitterSolution:
    if hr_m != 0.0:
        raise InputError("hr_m", f"ritter is the dry-bed solution (hr_m = 0); got {hr_m!r}, use 'stoker'")
    if friction is not None:
        raise InputError("friction", f"ritter is frictionless; got {friction!r}, use 'chanson'")
    return RitterSolution(h0_m, g)


def _make_stoker(h0_m, hr_m, friction, g) -> StokerSolution:
    if friction is not None:
        raise InputError("friction", f"stoker is frictionless; got {friction!r}")
    if hr_m == 0.0:
        raise InputError("hr_m", "stoker needs a wet bed, hr_m > 0 (use 'ritter' for a dry bed)")
    return StokerSolution(h0_m, hr_m, g)


def _make_chanson(h0_m, hr_m, friction, g) -> ChansonSolution:
    if friction is None:
        raise InputError("friction", "chanson needs the Darcy friction factor f > 0")
    if hr_m != 0.0:
        raise InputError("hr_m", f"chanson is a dry-bed solution (hr_m = 0); got {hr_m!r}")
    return ChansonSolution(h0_m, friction, g)


#: Model name -> factory ``(h0_m, hr_m, friction, g) -> solution``.
MODELS: dict[str, Callable[..., RitterSolution | StokerSolution | ChansonSolution]] = {
    "ritter": _make_ritter,
    "stoker": _make_stoker,
    "chanson": _make_chanson,
}


def dam_break(
    model: str,
    h0_m: float,
    hr_m: float = 0.0,
    friction: float | None = None,
    g: float = G_DEFAULT,
) -> RitterSolution | StokerSolution | ChansonSolution:
    """Build the dam-break solution ``model`` (one of :data:`MODELS`).

    Parameters
    ----------
    model: ``"ritter"`` (dry, frictionless), ``"stoker"`` (wet bed ``hr_m > 0``) or
        ``"chanson"`` (dry bed, Darcy ``friction`` > 0).
    h0_m: reservoir depth (m).
    hr_m: downstream still-water depth (m); 0 for the dry-bed models.
    friction: Darcy-Weisbach friction factor (-); only for ``"chanson"``.
    g: gravitational acceleration (m/s^2).

    Raises InputError naming ``model``, ``h0_m``, ``hr_m``, ``friction`` or ``g``.

    >>> sol = dam_break("ritter", 0.40)
    >>> round(sol.front_position_m(1.0), 4)
    3.9618
    """
    factory = MODELS.get(model) if isinstance(model, str) else None
    if factory is None:
        raise InputError("model", f"must be one of {sorted(MODELS)}, got {model!r}")
    h0 = require_positive("h0_m", h0_m)
    g = require_positive("g", g)
    try:
        hr = float(hr_m)
    except (TypeError, ValueError):
        raise InputError("hr_m", f"must be a number, got {hr_m!r}") from None
    if not math.isfinite(hr) or hr < 0.0:
        raise InputError("hr_m", f"must be a finite number >= 0, got {hr_m!r}")
    if hr >= h0:
        raise InputError("hr_m", f"must be < h0_m ({h0!r}), got {hr_m!r}")
    return factory(h0, hr, friction, g)
