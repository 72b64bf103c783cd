"""The single-degree-of-freedom structure of the study and its force response to impact pulses.

The study's SDOF model (its eq. [6]) is :class:`SDOF` with :func:`sdof_response`,
``R(t) = k u(t)``: the spring force of a damped oscillator, evaluated exactly by
:func:`analytical.oscillator.oscillator_response`. :func:`max_force_response` finds the largest
response over all time (response spectra, dynamic load factors), undamped and resonant cases
included. Independent closed forms (Chopra 2017, ch. 3-4) for the half-sine and rectangular
pulses are given as references for testing.

References: Chopra (2017), *Dynamics of Structures*, the sections :mod:`analytical.oscillator` lists.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from analytical.errors import InputError, require_finite, require_positive
from analytical.oscillator import as_times, atoms_response, oscillator_modes, oscillator_response, pulse_atoms
from analytical.pulses import atoms_force

__all__ = [
    "SDOF",
    "ForceResponse",
    "load_direction",
    "sdof_response",
    "PeakResponse",
    "max_force_response",
    "half_sine_closed_form",
    "rectangular_closed_form",
]

_EPS = float(np.finfo(float).eps)

# --------------------------------------------------------------------------------------------
# The SDOF model and its force response
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SDOF:
    """Linear single-degree-of-freedom structure (study Sec. 3.2.1).

    Parameters
    ----------
    stiffness_N_m:
        Lateral stiffness ``k``, N/m (> 0).
    natural_frequency_Hz:
        Undamped natural frequency ``f_n``, Hz (> 0).
    damping_ratio:
        Viscous damping ratio ``zeta``, ``0 <= zeta < 1`` (0: undamped, the textbook reference).
    """

    stiffness_N_m: float
    natural_frequency_Hz: float
    damping_ratio: float

    def __post_init__(self):
        object.__setattr__(self, "stiffness_N_m", require_positive("stiffness_N_m", self.stiffness_N_m))
        object.__setattr__(
            self, "natural_frequency_Hz", require_positive("natural_frequency_Hz", self.natural_frequency_Hz)
        )
        z = require_finite("damping_ratio", self.damping_ratio)
        if not 0.0 <= z < 1.0:
            raise InputError("damping_ratio", f"must be in [0, 1) (undamped or underdamped), got {self.damping_ratio!r}")
        object.__setattr__(self, "damping_ratio", z)

    @classmethod
    def study(cls) -> "SDOF":
        """The study's column (Stolle et al. 2019): k = 4.685e5 N/m, 70 Hz, zeta = 0.045."""
        return cls(stiffness_N_m=4.685e5, natural_frequency_Hz=70.0, damping_ratio=0.045)

    @property
    def omega_rad_s(self) -> float:
        """Undamped circular frequency ``2 pi f_n``, rad/s."""
        return 2.0 * math.pi * self.natural_frequency_Hz

    @property
    def natural_period_s(self) -> float:
        """Undamped natural period ``1/f_n``, s."""
        return 1.0 / self.natural_frequency_Hz

    @property
    def mass_kg(self) -> float:
        """Mass ``k / omega^2``, kg."""
        return self.stiffness_N_m / self.omega_rad_s**2

    @property
    def damping_N_s_m(self) -> float:
        """Viscous damping coefficient ``2 zeta m omega``, N s/m."""
        return 2.0 * self.damping_ratio * self.mass_kg * self.omega_rad_s


@dataclass(frozen=True, eq=False)
class ForceResponse:
    """A force response history (base shear / spring force), e.g. ``R(t) = k u(t)``.

    Parameters
    ----------
    time_s:
        Times, s (1-D).
    response_N:
        Response at those times, N (same shape).
    direction:
        +1 or -1: the direction of the load. ``peak_N`` is the extreme in this direction and
        ``min_N`` the extreme in the opposite one (rebound).
    """

    time_s: np.ndarray
    response_N: np.ndarray
    direction: int = 1

    def __post_init__(self):
        t = np.array(self.time_s, dtype=float)
        r = np.array(self.response_N, dtype=float)
        if t.ndim != 1 or t.size == 0:
            raise InputError("time_s", f"must be a non-empty 1-D array, got shape {t.shape}")
        if r.shape != t.shape:
            raise InputError("response_N", f"must have the shape of time_s {t.shape}, got {r.shape}")
        if self.direction not in (1, -1):
            raise InputError("direction", f"must be +1 or -1, got {self.direction!r}")
        t.setflags(write=False)
        r.setflags(write=False)
        object.__setattr__(self, "time_s", t)
        object.__setattr__(self, "response_N", r)

    def __repr__(self) -> str:
        return f"ForceResponse(n={self.time_s.size}, peak_N={self.peak_N:.6g}, min_N={self.min_N:.6g})"

    @property
    def _i_peak(self) -> int:
        return int(np.argmax(self.direction * self.response_N))

    @property
    def peak_N(self) -> float:
        """Largest response in the load's direction (signed), N."""
        return float(self.response_N[self._i_peak])

    @property
    def time_of_peak_s(self) -> float:
        """Time of :attr:`peak_N`, s."""
        return float(self.time_s[self._i_peak])

    @property
    def min_N(self) -> float:
        """Largest response against the load's direction (signed; the minimum for a positive load), N."""
        return float(self.response_N[int(np.argmin(self.direction * self.response_N))])


def load_direction(pulse) -> int:
    """+1, or -1 for a pulse whose peak is negative (a load against the axis)."""
    peak = getattr(pulse, "peak_N", None)
    return -1 if (peak is not None and peak < 0.0) else 1


def sdof_response(pulse, sdof: SDOF, t) -> ForceResponse:
    """Force response ``R(t) = k u(t)`` of an SDOF structure to a pulse (study eq. [6]).

    Parameters
    ----------
    pulse:
        Load, N (a pulse or a sequence of atoms).
    sdof:
        The structure.
    t:
        Times, s (1-D).

    Returns
    -------
    ForceResponse
        ``R = k u = omega^2 q`` in N; independent of ``k`` for given ``f_n``.
    """
    if not isinstance(sdof, SDOF):
        raise InputError("sdof", f"must be an SDOF, got {type(sdof).__name__}")
    w = sdof.omega_rad_s
    q = oscillator_response(pulse, t, w, sdof.damping_ratio)
    return ForceResponse(np.asarray(t, dtype=float), w * w * q, load_direction(pulse))


@dataclass(frozen=True)
class PeakResponse:
    """The largest force response to a pulse over all time.

    Attributes
    ----------
    peak_N:
        Largest ``R = k u`` in the load's direction (signed), N.
    time_s:
        When it occurs, s.
    """

    peak_N: float
    time_s: float


def max_force_response(pulse, natural_frequency_Hz: float, damping_ratio: float = 0.0) -> PeakResponse:
    """Largest force response ``R = k u`` of an SDOF structure to a pulse, over all time.

    Unlike :func:`oscillator_response` this accepts ``damping_ratio = 0`` (undamped), including
    exact resonance of a sine pulse with the structure (secular solution). The maximum is found
    on a dense grid over the pulse and the first damped period after it (where the largest
    free-vibration peak lies), then refined to machine precision by root-finding on the
    velocity. For response spectra / dynamic load factors: ``peak_N / pulse.peak_N``.

    Parameters
    ----------
    pulse:
        Load, N: a pulse or a sequence of atoms that vanishes after its last switch-on time.
    natural_frequency_Hz:
        ``f_n``, Hz (> 0).
    damping_ratio:
        ``0 <= zeta < 1``.

    Returns
    -------
    PeakResponse
        In the load's direction (the sign of ``pulse.peak_N``; positive for atom sequences).
    """
    atoms = pulse_atoms(pulse)
    if not atoms:
        raise InputError("pulse", "has no load")
    fn = require_positive("natural_frequency_Hz", natural_frequency_Hz)
    w_arr, z_arr, _ = oscillator_modes(2.0 * math.pi * fn, damping_ratio, allow_undamped=True)
    w, z = float(w_arr[0]), float(z_arr[0])
    sign = load_direction(pulse)
    t_first = min(a.t0 for a in atoms)
    t_last = max(a.t0 for a in atoms)
    Td = 2.0 * math.pi / (w * math.sqrt(1.0 - z * z))

    scale = sum(abs(a.a) + abs(a.c) + abs(a.d) for a in atoms) + sum(abs(a.b) for a in atoms) * (t_last - t_first)
    probe = np.array([t_last, t_last + 0.37 * Td, t_last + 1.7 * Td])
    if np.any(np.abs(atoms_force(atoms, probe)) > 1e-9 * scale):
        raise InputError("pulse", "must vanish after its last switch-on time (a pulse, not a sustained load)")

    t_end = t_last + 1.05 * Td
    n_grid = int(min(2_000_000, 400 + 200 * (t_end - t_first) / (2.0 * math.pi / w)))
    grid = np.union1d(np.linspace(t_first, t_end, n_grid), [a.t0 for a in atoms])

    def R(tt):
        return sign * w * w * atoms_response(atoms, np.atleast_1d(tt), w_arr, z_arr, False)[0][0]

    def V(tt):
        return sign * atoms_response(atoms, np.atleast_1d(np.asarray(tt, dtype=float)), w_arr, z_arr, True)[1][0]

    values = R(grid)
    i = int(np.argmax(values))
    best_t, best = float(grid[i]), float(values[i])
    lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
    v = V(np.array([lo, hi]))
    if v[0] > 0.0 > v[1]:
        t_star = brentq(lambda s: float(V(np.array([s]))[0]), lo, hi, xtol=1e-15 * max(1.0, abs(hi)), rtol=4 * _EPS)
        r_star = float(R(np.array([t_star]))[0])
        if r_star > best:
            best_t, best = t_star, r_star
    return PeakResponse(peak_N=sign * best, time_s=best_t)


# --------------------------------------------------------------------------------------------
# Independent closed forms (Chopra 2017), for reference and tests
# --------------------------------------------------------------------------------------------


def _check_closed_form_args(t, magnitude_N, duration_s, natural_frequency_Hz, damping_ratio, start_s):
    tt = as_times(t)
    f = float(magnitude_N)
    if not math.isfinite(f):
        raise InputError("magnitude_N", f"must be finite, got {magnitude_N!r}")
    td = require_positive("duration_s", duration_s)
    fn = require_positive("natural_frequency_Hz", natural_frequency_Hz)
    z = float(damping_ratio)
    if not (0.0 <= z < 1.0):
        raise InputError("damping_ratio", f"must satisfy 0 <= zeta < 1, got {damping_ratio!r}")
    ts = float(start_s)
    if not math.isfinite(ts):
        raise InputError("start_s", f"must be finite, got {start_s!r}")
    return tt, f, td, 2.0 * math.pi * fn, z, ts


def _free_vibration(s, r0, v0, w, z):
    """Damped free vibration from value ``r0`` and velocity ``v0`` (Chopra eq. 2.2.4)."""
    wd = w * math.sqrt(1.0 - z * z)
    return np.exp(-z * w * s) * (r0 * np.cos(wd * s) + (v0 + z * w * r0) / wd * np.sin(wd * s))


def _forced_then_free(tau, td, forced, forced_velocity, w, z):
    """Unit-load response of a closed-form solution: `forced` while the pulse acts
    (0 <= tau < td), damped free vibration from the state at td afterwards, 0 before."""
    r = np.zeros_like(tau)
    during = (tau >= 0.0) & (tau < td)
    after = tau >= td
    r[during] = forced(tau[during])
    r0 = float(forced(np.array(td)))
    v0 = float(forced_velocity(np.array(td)))
    r[after] = _free_vibration(tau[after] - td, r0, v0, w, z)
    return r


def half_sine_closed_form(t, magnitude_N, duration_s, natural_frequency_Hz, damping_ratio, start_s=0.0):
    """Force response ``R(t) = k u(t)`` of a damped (or undamped) SDOF to a half-sine pulse.

    Classical solution (Chopra 2017, Sec. 3.2 and 4.8), written independently of the atom
    superposition: during the pulse, the harmonic steady state ``C sin(W t) + D cos(W t)``
    (Chopra eq. 3.2.3-3.2.4) plus the damped transient that starts the system from rest; after
    the pulse, damped free vibration from the state at ``t_d`` (Chopra eq. 2.2.4). For
    ``zeta = 0`` and ``t_d = T_n / 2`` (resonance) ``R/F = (sin w t - w t cos w t)/2``.

    Parameters
    ----------
    t:
        Times, s (1-D).
    magnitude_N:
        Peak force ``F``, N.
    duration_s:
        Pulse duration ``t_d``, s.
    natural_frequency_Hz:
        ``f_n``, Hz.
    damping_ratio:
        ``0 <= zeta < 1``.
    start_s:
        Pulse start time, s.

    Returns
    -------
    numpy.ndarray
        ``R(t)`` in N (``k`` cancels: ``R = F x`` a function of ``t``, ``f_n``, ``zeta``, ``t_d``).
    """
    tt, f, td, w, z, ts = _check_closed_form_args(t, magnitude_N, duration_s, natural_frequency_Hz, damping_ratio, start_s)
    W = math.pi / td
    wd = w * math.sqrt(1.0 - z * z)
    beta = W / w

    resonant = z == 0.0 and abs(beta - 1.0) < 1e-12
    if resonant:
        def forced(tau):
            return 0.5 * (np.sin(w * tau) - w * tau * np.cos(w * tau))

        def forced_velocity(tau):
            return 0.5 * w * w * tau * np.sin(w * tau)
    else:
        den = (1.0 - beta**2) ** 2 + (2.0 * z * beta) ** 2
        C = (1.0 - beta**2) / den
        D = -2.0 * z * beta / den
        A = -D
        B = (z * w * A - C * W) / wd

        def forced(tau):
            e = np.exp(-z * w * tau)
            return e * (A * np.cos(wd * tau) + B * np.sin(wd * tau)) + C * np.sin(W * tau) + D * np.cos(W * tau)

        def forced_velocity(tau):
            e = np.exp(-z * w * tau)
            return (
                e * ((-z * w * A + wd * B) * np.cos(wd * tau) + (-z * w * B - wd * A) * np.sin(wd * tau))
                + C * W * np.cos(W * tau)
                - D * W * np.sin(W * tau)
            )

    return f * _forced_then_free(tt - ts, td, forced, forced_velocity, w, z)


def rectangular_closed_form(t, magnitude_N, duration_s, natural_frequency_Hz, damping_ratio, start_s=0.0):
    """Force response ``R(t) = k u(t)`` of a damped (or undamped) SDOF to a rectangular pulse.

    Classical solution (Chopra 2017, Sec. 4.3 and 4.7), independent of the atom superposition:
    during the pulse the step-force response
    ``R/F = 1 - exp(-zeta w t) [cos(w_D t) + zeta/sqrt(1-zeta^2) sin(w_D t)]`` (Chopra eq. 4.3.6),
    with velocity ``w/sqrt(1-zeta^2) exp(-zeta w t) sin(w_D t)``; after the pulse, damped free
    vibration from the state at ``t_d`` (Chopra eq. 2.2.4).

    Parameters and return value as :func:`half_sine_closed_form`.
    """
    tt, f, td, w, z, ts = _check_closed_form_args(t, magnitude_N, duration_s, natural_frequency_Hz, damping_ratio, start_s)
    wd = w * math.sqrt(1.0 - z * z)
    zr = z / math.sqrt(1.0 - z * z)

    def forced(tau):
        return 1.0 - np.exp(-z * w * tau) * (np.cos(wd * tau) + zr * np.sin(wd * tau))

    def forced_velocity(tau):
        return w / math.sqrt(1.0 - z * z) * np.exp(-z * w * tau) * np.sin(wd * tau)

    return f * _forced_then_free(tt - ts, td, forced, forced_velocity, w, z)
