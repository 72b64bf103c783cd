"""Impact force pulses: half-sine, rectangular, triangular and tabulated loads.

Every pulse is a small frozen dataclass. Forces are in N, times in s; a pulse is zero outside
its support ``[start_s, end_s)`` (closed at the start, open at the end, so a rectangular pulse
is ``F`` on ``start <= t < end``).

Besides evaluating the load, each pulse gives an *exact* decomposition of itself into
switched-on terms (:class:`Atom`): steps, ramps and sinusoids that start at a time ``t0`` and
go on for ever. Adding the atoms back up reproduces :meth:`force` to rounding. The structural
solutions in :mod:`analytical.sdof` (and the modal MDOF solution) superpose the closed-form
response of a linear oscillator to each atom, which is Duhamel's integral evaluated exactly.

Magnitudes are signed: a negative magnitude is a load in the negative axis direction.

References
----------
Chopra, A. K. (2017). *Dynamics of Structures*, 5th ed., Pearson, ch. 4 (pulse excitations).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Iterable

import numpy as np

from analytical.errors import InputError, require_finite, require_positive

__all__ = [
    "Atom",
    "HalfSine",
    "Rectangular",
    "Triangular",
    "Tabulated",
    "PULSES",
    "make_pulse",
    "atoms_force",
]



def _as_time_array(t) -> tuple[np.ndarray, bool]:
    """``t`` as a float array and whether it was a scalar."""
    arr = np.asarray(t, dtype=float)
    return arr, arr.ndim == 0


def _out(values: np.ndarray, scalar: bool):
    return float(values) if scalar else values


# --------------------------------------------------------------------------------------------
# Atoms
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Atom:
    """A switched-on load term.

    For ``t >= t0`` the load gains ``a + b*(t - t0) + c*sin(omega*(t - t0)) + d*cos(omega*(t - t0))``;
    before ``t0`` the term is zero.

    Attributes
    ----------
    t0:
        Switch-on time, s.
    a:
        Step, N.
    b:
        Ramp slope, N/s.
    c, d:
        Sine and cosine amplitudes, N (used only when ``omega > 0``).
    omega:
        Circular frequency of the sinusoid, rad/s (``0`` = no sinusoid).
    """

    t0: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0
    d: float = 0.0
    omega: float = 0.0

    def __post_init__(self):
        for name in ("t0", "a", "b", "c", "d", "omega"):
            require_finite(name, getattr(self, name))
        if self.omega < 0.0:
            raise InputError("omega", f"must be >= 0, got {self.omega!r}")

    def force(self, t):
        """The term's contribution at ``t`` (s), in N; vectorised."""
        arr, scalar = _as_time_array(t)
        tau = arr - self.t0
        on = tau >= 0.0
        tau = np.where(on, tau, 0.0)
        value = self.a + self.b * tau
        if self.omega > 0.0 and (self.c != 0.0 or self.d != 0.0):
            value = value + self.c * np.sin(self.omega * tau) + self.d * np.cos(self.omega * tau)
        return _out(np.where(on, value, 0.0), scalar)

    def shifted(self, dt: float) -> "Atom":
        """The same term switched on ``dt`` seconds later."""
        return replace(self, t0=self.t0 + require_finite("dt", dt))

    def scaled(self, factor: float) -> "Atom":
        """The term multiplied by ``factor``."""
        f = require_finite("factor", factor)
        return replace(self, a=self.a * f, b=self.b * f, c=self.c * f, d=self.d * f)


def atoms_force(atoms: Iterable[Atom], t):
    """Sum of the atoms' contributions at ``t`` (s), in N; vectorised."""
    arr, scalar = _as_time_array(t)
    total = np.zeros(arr.shape)
    for atom in atoms:
        total = total + atom.force(arr)
    return _out(total, scalar)


def _piecewise_linear_atoms(time_s: np.ndarray, force_N: np.ndarray) -> tuple[Atom, ...]:
    """Atoms of the load that is linear between the knots and zero outside ``[t[0], t[-1])``.

    A jump from/to zero at the ends becomes a step; every change of slope becomes a ramp.
    """
    slopes = np.diff(force_N) / np.diff(time_s)
    atoms: list[Atom] = []
    n = len(time_s)
    for k in range(n):
        step = 0.0
        if k == 0:
            step = float(force_N[0])
            ramp = float(slopes[0])
        elif k == n - 1:
            step = -float(force_N[-1])
            ramp = -float(slopes[-1])
        else:
            ramp = float(slopes[k] - slopes[k - 1])
        if step != 0.0 or ramp != 0.0:
            atoms.append(Atom(float(time_s[k]), a=step, b=ramp))
    return tuple(atoms)


# --------------------------------------------------------------------------------------------
# Pulses
# --------------------------------------------------------------------------------------------


class _ShapedPulse:
    """Shared behaviour of the analytic pulses (magnitude, duration, start)."""

    magnitude_N: float
    duration_s: float
    start_s: float

    def _validate_common(self) -> None:
        object.__setattr__(self, "magnitude_N", require_finite("magnitude_N", self.magnitude_N))
        object.__setattr__(self, "duration_s", require_positive("duration_s", self.duration_s))
        object.__setattr__(self, "start_s", require_finite("start_s", self.start_s))

    @property
    def end_s(self) -> float:
        """End of the pulse (exclusive), s."""
        return self.start_s + self.duration_s

    @property
    def peak_N(self) -> float:
        """Signed peak of the load, N (the magnitude)."""
        return self.magnitude_N

    def _support(self, arr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        tau = arr - self.start_s
        inside = (tau >= 0.0) & (arr < self.end_s)
        return np.where(inside, tau, 0.0), inside

    def scaled(self, factor: float):
        """The same pulse with its force multiplied by ``factor`` (may be negative)."""
        return replace(self, magnitude_N=self.magnitude_N * require_finite("factor", factor))

    def shifted(self, dt: float):
        """The same pulse starting ``dt`` seconds later."""
        return replace(self, start_s=self.start_s + require_finite("dt", dt))


@dataclass(frozen=True)
class _SimplePulse(_ShapedPulse):
    """A pulse given by its force ``F`` (N, signed; the peak), duration ``t_d`` (s, > 0) and
    start ``t_s`` (s)."""

    magnitude_N: float
    duration_s: float
    start_s: float = 0.0

    def __post_init__(self):
        self._validate_common()


@dataclass(frozen=True)
class HalfSine(_SimplePulse):
    """Half-sine pulse ``F sin(pi (t - t_s)/t_d)`` on ``t_s <= t < t_s + t_d``."""

    @property
    def omega_rad_s(self) -> float:
        """Circular frequency of the sine, ``pi / t_d``, rad/s.

        Computed as ``pi / (end_s - start_s)`` (equal to ``pi / duration_s`` up to the rounding of
        ``end_s``) so that the two atoms cancel exactly after the end.
        """
        return math.pi / (self.end_s - self.start_s)

    @property
    def impulse_Ns(self) -> float:
        """Impulse ``2 F t_d / pi``, N s."""
        return 2.0 * self.magnitude_N * self.duration_s / math.pi

    def force(self, t):
        """Load at ``t`` (s), N; vectorised."""
        arr, scalar = _as_time_array(t)
        tau, inside = self._support(arr)
        value = self.magnitude_N * np.sin(self.omega_rad_s * tau)
        return _out(np.where(inside, value, 0.0), scalar)

    def atoms(self) -> tuple[Atom, ...]:
        """Two switched-on sines: ``F sin(w (t - t_s))`` from ``t_s`` and the same from ``t_s + t_d``.

        Since ``sin(w (t - t_s - t_d)) = -sin(w (t - t_s))`` for ``w t_d = pi``, they cancel after the end.
        """
        w = self.omega_rad_s
        return (
            Atom(self.start_s, c=self.magnitude_N, omega=w),
            Atom(self.end_s, c=self.magnitude_N, omega=w),
        )


@dataclass(frozen=True)
class Rectangular(_SimplePulse):
    """Rectangular pulse: ``F`` on ``t_s <= t < t_s + t_d`` (ASCE 7-22 Section 6.11 shape)."""

    @property
    def impulse_Ns(self) -> float:
        """Impulse ``F t_d``, N s."""
        return self.magnitude_N * self.duration_s

    def force(self, t):
        """Load at ``t`` (s), N; vectorised."""
        arr, scalar = _as_time_array(t)
        _, inside = self._support(arr)
        return _out(np.where(inside, self.magnitude_N, 0.0), scalar)

    def atoms(self) -> tuple[Atom, ...]:
        """A step ``+F`` at the start and a step ``-F`` at the end."""
        return (Atom(self.start_s, a=self.magnitude_N), Atom(self.end_s, a=-self.magnitude_N))


@dataclass(frozen=True)
class Triangular(_ShapedPulse):
    """Triangular pulse rising linearly from 0 to ``F`` and falling back to 0.

    Parameters
    ----------
    magnitude_N:
        Peak force ``F``, N (signed).
    duration_s:
        Duration ``t_d``, s (> 0).
    peak_fraction:
        Time of the peak as a fraction of ``t_d``, in ``[0, 1]`` (0.5 = symmetric; 0 = a vertical
        rise then a linear decay; 1 = a linear rise then a drop).
    start_s:
        Start time, s.
    """

    magnitude_N: float
    duration_s: float
    peak_fraction: float = 0.5
    start_s: float = 0.0

    def __post_init__(self):
        self._validate_common()
        p = require_finite("peak_fraction", self.peak_fraction)
        if not 0.0 <= p <= 1.0:
            raise InputError("peak_fraction", f"must be in [0, 1], got {self.peak_fraction!r}")
        object.__setattr__(self, "peak_fraction", p)

    @property
    def peak_time_s(self) -> float:
        """Time of the peak, s."""
        return self.start_s + self.peak_fraction * self.duration_s

    @property
    def impulse_Ns(self) -> float:
        """Impulse ``F t_d / 2``, N s."""
        return 0.5 * self.magnitude_N * self.duration_s

    def _knots(self) -> tuple[np.ndarray, np.ndarray]:
        f, p = self.magnitude_N, self.peak_fraction
        if p == 0.0:
            return np.array([self.start_s, self.end_s]), np.array([f, 0.0])
        if p == 1.0:
            return np.array([self.start_s, self.end_s]), np.array([0.0, f])
        return np.array([self.start_s, self.peak_time_s, self.end_s]), np.array([0.0, f, 0.0])

    def force(self, t):
        """Load at ``t`` (s), N; vectorised."""
        arr, scalar = _as_time_array(t)
        tau, inside = self._support(arr)
        td, p, f = self.duration_s, self.peak_fraction, self.magnitude_N
        rise_len, fall_len = p * td, (1.0 - p) * td
        rising = tau < rise_len
        with np.errstate(divide="ignore", invalid="ignore"):
            up = f * tau / rise_len if rise_len > 0.0 else np.full(arr.shape, f)
            down = f * (td - tau) / fall_len if fall_len > 0.0 else np.full(arr.shape, f)
        value = np.where(rising, up, down)
        return _out(np.where(inside, value, 0.0), scalar)

    def atoms(self) -> tuple[Atom, ...]:
        """Three ramps (0 < peak_fraction < 1); a step and two ramps at the extremes."""
        return _piecewise_linear_atoms(*self._knots())


@dataclass(frozen=True, eq=False)
class Tabulated:
    """A load given by samples, linear between them and zero outside ``[time_s[0], time_s[-1])``.

    A non-zero first or last sample is a jump from/to zero (a step in :meth:`atoms`).

    Parameters
    ----------
    time_s:
        Sample times, s: at least 2, finite, strictly increasing.
    force_N:
        Forces at those times, N (finite, same length).
    """

    time_s: np.ndarray
    force_N: np.ndarray

    def __post_init__(self):
        try:
            t = np.array(self.time_s, dtype=float)
            f = np.array(self.force_N, dtype=float)
        except (TypeError, ValueError):
            raise InputError("time_s/force_N", "must be sequences of numbers") from None
        if t.ndim != 1 or t.size < 2:
            raise InputError("time_s", f"must be a 1-D sequence of >= 2 samples, got shape {t.shape}")
        if f.shape != t.shape:
            raise InputError("force_N", f"must have the same shape as time_s {t.shape}, got {f.shape}")
        if not np.all(np.isfinite(t)):
            raise InputError("time_s", "must be finite")
        if not np.all(np.isfinite(f)):
            raise InputError("force_N", "must be finite")
        if not np.all(np.diff(t) > 0.0):
            raise InputError("time_s", "must be strictly increasing")
        t.setflags(write=False)
        f.setflags(write=False)
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "force_N", f)

    def __eq__(self, other):
        if not isinstance(other, Tabulated):
            return NotImplemented
        return np.array_equal(self.time_s, other.time_s) and np.array_equal(self.force_N, other.force_N)

    __hash__ = None  # arrays are not hashable

    def __repr__(self) -> str:
        return (
            f"Tabulated(n={self.time_s.size}, start_s={self.start_s!r}, end_s={self.end_s!r}, "
            f"peak_N={self.peak_N!r})"
        )

    @property
    def start_s(self) -> float:
        """First sample time, s."""
        return float(self.time_s[0])

    @property
    def end_s(self) -> float:
        """Last sample time (exclusive end of the load), s."""
        return float(self.time_s[-1])

    @property
    def duration_s(self) -> float:
        """``end_s - start_s``, s."""
        return self.end_s - self.start_s

    @property
    def peak_N(self) -> float:
        """Signed sample of largest magnitude, N."""
        return float(self.force_N[int(np.argmax(np.abs(self.force_N)))])

    @property
    def impulse_Ns(self) -> float:
        """Exact integral of the piecewise-linear load (trapezoids), N s."""
        f = self.force_N
        return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(self.time_s)))

    def force(self, t):
        """Load at ``t`` (s), N; vectorised."""
        arr, scalar = _as_time_array(t)
        inside = (arr >= self.time_s[0]) & (arr < self.time_s[-1])
        value = np.interp(arr, self.time_s, self.force_N)
        return _out(np.where(inside, value, 0.0), scalar)

    def atoms(self) -> tuple[Atom, ...]:
        """Steps for the end jumps and a ramp at every change of slope."""
        return _piecewise_linear_atoms(self.time_s, self.force_N)

    def scaled(self, factor: float) -> "Tabulated":
        """The same load multiplied by ``factor``."""
        return Tabulated(self.time_s, self.force_N * require_finite("factor", factor))

    def shifted(self, dt: float) -> "Tabulated":
        """The same load ``dt`` seconds later."""
        return Tabulated(self.time_s + require_finite("dt", dt), self.force_N)


# --------------------------------------------------------------------------------------------
# Registry
# --------------------------------------------------------------------------------------------

PULSES: dict[str, type] = {
    "half-sine": HalfSine,
    "rectangular": Rectangular,
    "triangular": Triangular,
}
"""Pulse shapes by name (the names used in scenes, sweeps and the CLI)."""


def make_pulse(shape: str, magnitude_N: float, duration_s: float, start_s: float = 0.0):
    """Build a pulse by shape name (see :data:`PULSES`).

    ``shape`` is matched case-insensitively, with ``_`` accepted for ``-`` (``"half_sine"``).
    Unknown shapes raise ``InputError("pulse", ...)``.
    """
    key = str(shape).strip().lower().replace("_", "-")
    cls = PULSES.get(key)
    if cls is None:
        raise InputError("pulse", f"unknown shape {shape!r}; expected one of {sorted(PULSES)}")
    return cls(magnitude_N=magnitude_N, duration_s=duration_s, start_s=start_s)
