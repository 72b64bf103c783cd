"""Fit an impact pulse to a measured force-response record (the study's sections 3.2.1-3.2.2).

A record is the force a load cell measured while a column rang after a debris
impact. We look for the pulse p(t) (half-sine by default) whose modelled response
matches it best in the least-squares sense:

* ``fit_sdof``: the response R = k u of a single-degree-of-freedom oscillator; the
  study varied magnitude, duration, damping, stiffness and natural frequency within
  the bounds of Stolle et al. (2019): f1 = 70 +- 2.2 Hz, zeta = 0.045 +- 0.005,
  k = 4.653e5 .. 4.701e5 N/m. We keep the widths of those bounds and centre them
  on the column's measured values (`natural_frequency_Hz`, `damping_ratio`), so a
  column measured at another frequency is fitted around its own. Note that R = k u = omega^2 q depends on omega and
  zeta only (q is the unit-mass response): the stiffness cannot be identified from
  a force record, so it is held at the column's value and reported as such.
* ``fit_mdof``: the base shear of the Timoshenko column (`analytical.mdof`) with the
  load at a given height; magnitude and duration vary, matrices stay fixed.

Method (variable projection): the modelled response is linear in the magnitude and
in a constant offset of the record, so for every trial of the nonlinear parameters
(duration, start time, and for SDOF damping and frequency) those two are solved
exactly by linear least squares; the nonlinear ones are found by a coarse grid
over duration followed by `scipy.optimize.least_squares` with bounds. The impact
start is a fitted parameter, so a record may start well before the impact; the
offset absorbs a load-cell zero error; the grid start keeps the fit out of the
local minima that ringing responses have.

The SDOF pulse may not start before the record, nor while the record still sits at
its baseline: its start is bounded below by the last sample before the impact onset
that lies within one noise standard deviation of the baseline (`_Prepared.quiet_s`).
Without that bound an SDOF fitted to a column with higher modes starts a long, weak
pulse milliseconds before the impact (its slow rise stays hidden in the quiet part)
and trades its duration against its magnitude. Even with it, the duration of a pulse
shorter than the oscillator's period is only weakly fixed by the record (the response
depends mainly on the pulse's Fourier amplitude at the natural frequency): `fit_sdof`
measures this (`DurationIdentifiability`: the objective profiled over duration, the
Jacobian's condition number) and reports it with the fit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import f as f_distribution

from analytical.column import Column
from analytical.errors import InputError, require_positive
from analytical.mdof import mdof_response
from analytical.oscillator import oscillator_response
from analytical.pulses import make_pulse

#: Half-widths of the study's SDOF fit bounds (Stolle et al. 2019 via its section
#: 3.2.1: f1 = 70 +- 2.2 Hz, damping 0.045 +- 0.005, k = 4.653e5 .. 4.701e5 N/m).
SDOF_FREQUENCY_TOL_HZ = 2.2
SDOF_DAMPING_TOL = 0.005
SDOF_STIFFNESS_N_M = (4.653e5, 4.701e5)

#: Pulse durations searched, s (the study's fitted pulses lasted 0.6-7 ms).
DURATION_BOUNDS_S = (2.0e-4, 2.0e-2)


@dataclass(frozen=True)
class PulseFit:
    """A fitted impact pulse and how well its modelled response matches the record.

    Forces in N, times in s. `time_s`/`model_N`/`measured_N` cover the fit window;
    `measured_N` has the fitted offset (`offset_N`) removed. `peak_measured_N` is the
    record's own maximum, as recorded (no baseline or offset removed), the same whichever
    model is fitted; `baseline_N` is the record's level before the impact (its first
    sample when the record starts at the impact). `earliest_start_s` is the lower bound
    the fit put on the pulse's start; `duration_identifiability` (SDOF fits) says how
    well the record fixes the duration apart from the magnitude.
    """

    model: str
    shape: str
    magnitude_N: float
    duration_s: float
    start_s: float
    impulse_Ns: float
    rmse_N: float
    peak_measured_N: float
    peak_model_N: float
    offset_N: float
    natural_frequency_Hz: float | None
    damping_ratio: float | None
    stiffness_N_m: float | None
    height_m: float | None
    time_s: np.ndarray
    model_N: np.ndarray
    measured_N: np.ndarray
    baseline_N: float = 0.0
    earliest_start_s: float = -np.inf
    duration_identifiability: "DurationIdentifiability | None" = None

    @property
    def pulse(self):
        """The fitted pulse (a `analytical.pulses` object)."""
        return make_pulse(self.shape, self.magnitude_N, self.duration_s, self.start_s)


@dataclass(frozen=True, eq=False)
class DurationIdentifiability:
    """How well a record fixes a fitted pulse's duration apart from its magnitude.

    For a pulse much shorter than the oscillator's period the response depends on the
    impulse (more exactly, the pulse's Fourier amplitude at the natural frequency)
    only, so magnitude and duration trade off. Measured two ways:

    * the objective profiled over duration: at each of `durations_s` (s) the duration
      is held and every other parameter re-fitted (`magnitude_N`, `impulse_Ns`: its
      pulse); `excess_cost` is that fit's sum of squared residuals less the best fit's,
      over sigma^2 = the larger of the best fit's residual variance and
      (RESOLUTION_PEAK_FRACTION x the record's peak)^2. `interval_s` is the 95 % profile
      interval, the durations whose excess stays below `threshold` = F(0.95; 1, n - p)
      (n samples, p = 6 parameters with the offset). For a model that cannot match the
      record (an SDOF on a column with higher modes) the residual is not noise and the
      interval says how far the duration moves before the misfit grows, not a sampling
      interval. An end at a searched limit (`DURATION_BOUNDS_S`) means it is open.
    * `condition_number`: of the Jacobian of the modelled record with respect to
      (magnitude, duration, start, damping, frequency, offset) at the fit, its columns
      scaled to unit length; `magnitude_duration_correlation` from its inverse normal
      matrix (-1 or +1: the two cannot be told apart).

    `identifiable` is True when the interval is closed on both sides and no wider than
    half the fitted duration (about +-25 %).
    """

    duration_s: float
    durations_s: np.ndarray
    excess_cost: np.ndarray
    magnitude_N: np.ndarray
    impulse_Ns: np.ndarray
    threshold: float
    interval_s: tuple[float, float]
    condition_number: float
    magnitude_duration_correlation: float
    identifiable: bool


@dataclass(frozen=True)
class _Prepared:
    t: np.ndarray  # fit window times (s)
    y: np.ndarray  # record in the window (N), raw
    onset_s: float  # first clear departure from the baseline
    baseline_N: float
    noise_N: float
    peak_N: float  # peak of (record - baseline) in the window
    record_peak_N: float  # the record's own maximum, as recorded
    quiet_s: float  # last sample before the onset within one noise std of the baseline (or the first sample)


def _baseline_and_noise(y: np.ndarray) -> tuple[float, float]:
    """Median and noise std (from the spread of successive differences) of a quiet stretch."""
    d = np.diff(y)
    noise = float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0)) if d.size else 0.0
    return float(np.median(y)), noise


def prepare_record(time_s, force_N, window_s: float = 0.04, pre_s: float = 0.01) -> _Prepared:
    """Validate a record, find the impact and cut the fit window.

    The baseline and noise come from the quietest stretch before the largest
    excursion; the impact onset is the first sample that leaves the baseline by
    more than 6 noise standard deviations and 5 % of the excursion. When the onset
    falls inside the stretch the baseline came from (a record that starts at or just
    before the impact), the baseline is re-estimated from the samples before the
    onset, or is the first sample when there are fewer than six of them (its noise
    then comes from the second differences of the record's last fifth).
    """
    t = np.asarray(time_s, dtype=float)
    y = np.asarray(force_N, dtype=float)
    if t.ndim != 1 or t.shape != y.shape:
        raise InputError("force_N", f"time and force must be 1-D arrays of equal length, got {t.shape} and {y.shape}")
    if t.size < 20:
        raise InputError("time_s", f"only {t.size} samples; at least 20 are needed")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))):
        raise InputError("force_N", "record contains NaN or infinite values")
    if np.any(np.diff(t) <= 0):
        raise InputError("time_s", "must increase strictly")
    window_s = float(window_s)

    i_peak = int(np.argmax(np.abs(y - np.median(y))))
    quiet = y[: max(i_peak, 1)]
    if quiet.size < 5:  # peak right at the start: take the tail as the quiet part
        quiet = y[-max(5, y.size // 5):]
    n_base = max(5, quiet.size // 2)
    baseline = float(np.median(quiet[:n_base]))
    noise = _baseline_and_noise(quiet[: max(6, quiet.size // 2)])[1]
    for _ in range(3):
        excursion = float(np.max(np.abs(y - baseline)))
        threshold = max(6.0 * noise, 0.05 * excursion)
        if excursion <= 0.0 or excursion < 8.0 * noise:
            raise InputError("force_N", f"no impact found: the largest excursion ({excursion:.3g} N) is within the "
                                        f"noise ({noise:.3g} N rms)")
        i_on = int(np.flatnonzero(np.abs(y - baseline) > threshold)[0])
        if i_on >= n_base or i_peak < 5:  # a record peaking at once took its baseline from its tail
            break
        # the baseline stretch reaches into the impact: re-estimate it from before the onset
        n_base = i_on
        if i_on >= 6:
            baseline, noise = _baseline_and_noise(y[:i_on])
        else:
            tail = y[-max(6, y.size // 5):]
            d2 = np.diff(tail, 2)
            baseline = float(y[0])
            noise = float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0))
    onset = float(t[i_on])
    tol = max(noise, 1e-9 * excursion)
    i_quiet = i_on
    while i_quiet > 0 and abs(y[i_quiet] - baseline) > tol:
        i_quiet -= 1
    if t[-1] - onset < 5e-3:
        raise InputError("time_s", f"the record ends {1e3 * (t[-1] - onset):.1f} ms after the impact onset; "
                                   "at least 5 ms of response are needed")
    keep = (t >= onset - pre_s) & (t <= onset + window_s)
    tw, yw = t[keep], y[keep]
    return _Prepared(tw, yw, onset, baseline, noise, float(np.max(yw - baseline)), float(np.max(y)),
                     float(t[i_quiet]))


def _project(r: np.ndarray, y: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Best a, b with a*r + b ~ y (linear least squares); returns a, b, residual."""
    A = np.column_stack([r, np.ones_like(r)])
    (a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
    return float(a), float(b), a * r + b - y


def _residual(prep: _Prepared, unit_response):
    """Residual of the variable-projection fit and the magnitude, as a function of
    (duration, start, extra)."""
    t, y = prep.t, prep.y

    def residual(duration: float, start: float, extra) -> tuple[np.ndarray, float]:
        a, _, res = _project(unit_response(t, duration, start, extra), y)
        return res, a

    return residual


def _fit(
    prep: _Prepared,
    unit_response: Callable[[np.ndarray, float, float, np.ndarray], np.ndarray],
    extra_x0: list[float],
    extra_bounds: list[tuple[float, float]],
    duration_grid: np.ndarray,
    start_bounds: tuple[float, float] | None = None,
) -> tuple[np.ndarray, float, float, np.ndarray]:
    """Variable-projection least squares; returns (x, magnitude, offset, model).

    The start is searched within `start_bounds` (s), by default from 10 ms before the
    onset to two samples after it."""
    t, y = prep.t, prep.y
    start_lo, start_hi = start_bounds or _start_bounds(prep, None)
    full = _residual(prep, unit_response)

    def residual(x: np.ndarray) -> np.ndarray:
        return full(x[0], x[1], x[2:])[0]

    # coarse grid over duration (and start just before the onset) to avoid the
    # local minima of an oscillating response
    best = None
    for duration in duration_grid:
        for lead in (0.0, 0.25, 0.5):
            x = np.array([duration, max(start_lo, prep.onset_s - lead * duration), *extra_x0])
            cost = float(np.sum(residual(x) ** 2))
            if best is None or cost < best[0]:
                best = (cost, x)
    lo = [DURATION_BOUNDS_S[0], start_lo] + [b[0] for b in extra_bounds]
    hi = [DURATION_BOUNDS_S[1], start_hi] + [b[1] for b in extra_bounds]
    x0 = np.clip(best[1], lo, hi)
    scale = np.array([1e-3, 1e-3] + [max(abs(v), 1e-3) for v in extra_x0])
    sol = least_squares(residual, x0, bounds=(lo, hi), x_scale=scale, xtol=1e-10, ftol=1e-10, max_nfev=200)
    r = unit_response(t, sol.x[0], sol.x[1], sol.x[2:])
    a, b, res = _project(r, y)
    return sol.x, a, b, a * r + b


def _start_bounds(prep: _Prepared, earliest_s: float | None) -> tuple[float, float]:
    """(earliest, latest) pulse start, s: from `earliest_s` (default 10 ms before the onset)
    to two samples after the onset."""
    dt_med = float(np.median(np.diff(prep.t)))
    lo = prep.onset_s - 0.01 if earliest_s is None else float(earliest_s)
    return lo, prep.onset_s + 2 * dt_med


def _result(model, shape, prep, x, a, b, fitted, **structural) -> PulseFit:
    if a <= 0:
        raise InputError("force_N", "the best-fitting pulse has a non-positive magnitude: the record does not look "
                                    "like the response to an impact in the positive direction")
    pulse = make_pulse(shape, a, x[0], x[1])
    measured = prep.y - b
    model_n = fitted - b
    return PulseFit(
        model=model,
        shape=shape,
        magnitude_N=float(a),
        duration_s=float(x[0]),
        start_s=float(x[1]),
        impulse_Ns=float(pulse.impulse_Ns),
        rmse_N=float(np.sqrt(np.mean((fitted - prep.y) ** 2))),
        peak_measured_N=prep.record_peak_N,
        peak_model_N=float(np.max(model_n)),
        offset_N=float(b),
        time_s=prep.t,
        model_N=model_n,
        measured_N=measured,
        baseline_N=prep.baseline_N,
        **structural,
    )


def _sdof_start(time_s, column, prep: "_Prepared", earliest_start_s) -> tuple[float, float, float, float]:
    """The SDOF fit's stiffness, natural frequency and damping ratio (the column's, else the study's)
    and the earliest start a pulse may have (the record's quiet end, or ``earliest_start_s``)."""
    stiffness = float(getattr(column, "stiffness_N_m", 4.685e5))
    freq0 = float(getattr(column, "natural_frequency_Hz", 70.0))
    zeta0 = float(getattr(column, "damping_ratio", 0.045))
    t_first = float(np.asarray(time_s, dtype=float)[0])
    return stiffness, freq0, zeta0, max(t_first, prep.quiet_s if earliest_start_s is None else float(earliest_start_s))


def fit_sdof(time_s, force_N, column=None, shape: str = "half-sine", window_s: float = 0.04,
             mass_kg: float | None = None, earliest_start_s: float | None = None,
             identifiability: bool = True) -> PulseFit:
    """Fit a pulse with the SDOF model R = k u (study eq. [6]) to a force record.

    Varies magnitude (N), duration (s), start (s), damping ratio and natural
    frequency (Hz) within the study's bounds around the column's measured values
    (module constants); the stiffness is the column's (it does not change R, see
    the module docstring).

    No pulse acts before the record, nor while the record still sits at its baseline:
    the start may not precede the record's first sample, nor `earliest_start_s` (s;
    default: the last sample before the impact onset within one noise standard
    deviation of the baseline, `_Prepared.quiet_s`; exact on a noise-free record). On a
    noisy record that bound lags the true start by the time the response takes to rise
    out of the noise, and the fit then shortens the pulse to keep the phase of the
    ringing (docs/fitting.md gives the figures); pass `earliest_start_s` to move it.

    `mass_kg` (default None: m = k / omega^2, a consistent oscillator) holds the mass
    fixed while the frequency is fitted, as a literal reading of the study's eq. [6]
    with k, m_s and omega as separate inputs does: then R = (k / m_s) q.

    `identifiability` (default True) adds `duration_identifiability` to the result
    (about 20 more fits of three parameters each).
    """
    prep = prepare_record(time_s, force_N, window_s=window_s)
    stiffness, freq0, zeta0, earliest = _sdof_start(time_s, column, prep, earliest_start_s)
    f_lo, f_hi = freq0 - SDOF_FREQUENCY_TOL_HZ, freq0 + SDOF_FREQUENCY_TOL_HZ
    z_lo, z_hi = max(1e-4, zeta0 - SDOF_DAMPING_TOL), min(0.99, zeta0 + SDOF_DAMPING_TOL)
    if earliest > prep.onset_s:
        raise InputError("earliest_start_s", f"must not be after the impact onset found in the record "
                                             f"({prep.onset_s:.6g} s), got {earliest_start_s}")
    start_bounds = _start_bounds(prep, earliest)

    fixed_gain = None if mass_kg is None else stiffness / require_positive("mass_kg", mass_kg)

    def unit(t, duration, start, extra):
        zeta, freq = extra
        omega = 2 * np.pi * freq
        q = oscillator_response(make_pulse(shape, 1.0, duration, start), t, omega, zeta)
        return (omega**2 if fixed_gain is None else fixed_gain) * q

    grid = np.geomspace(5e-4, 1.2e-2, 10)
    extra_bounds = [(z_lo, z_hi), (f_lo, f_hi)]
    x, a, b, fitted = _fit(prep, unit, [zeta0, freq0], extra_bounds, grid, start_bounds)
    ident = (duration_identifiability(prep, unit, shape, x, [start_bounds, *extra_bounds])
             if identifiability else None)
    return _result("sdof", shape, prep, x, a, b, fitted, natural_frequency_Hz=float(x[3]),
                   damping_ratio=float(x[2]), stiffness_N_m=stiffness, height_m=None,
                   earliest_start_s=start_bounds[0], duration_identifiability=ident)


def fit_mdof(time_s, force_N, column=None, height_m: float = 0.40, shape: str = "half-sine",
             window_s: float = 0.04) -> PulseFit:
    """Fit a pulse at `height_m` (m above the base) with the MDOF column's base shear.

    Varies magnitude (N), duration (s) and start (s); the column's matrices are fixed
    (the study's section 3.2.2).
    """
    column = column if column is not None else Column()
    if not (0.0 < float(height_m) <= column.height_m):
        raise InputError("height_m", f"must be in (0, {column.height_m}] m, got {height_m}")
    prep = prepare_record(time_s, force_N, window_s=window_s)

    def unit(t, duration, start, extra):
        return mdof_response(make_pulse(shape, 1.0, duration, start), column, height_m, t).response_N

    grid = np.geomspace(5e-4, 1.2e-2, 10)
    x, a, b, fitted = _fit(prep, unit, [], [], grid)
    return _result("mdof", shape, prep, x, a, b, fitted, natural_frequency_Hz=None, damping_ratio=None,
                   stiffness_N_m=None, height_m=float(height_m), earliest_start_s=_start_bounds(prep, None)[0])


#: The reading resolution of a record, as a fraction of its peak: the smallest noise level
#: `duration_identifiability` assumes, so that a noise-free record does not make every
#: parameter look exactly fixed.
RESOLUTION_PEAK_FRACTION = 0.01
#: Durations at which `duration_identifiability` profiles the objective, s.
PROFILE_DURATIONS_S = np.geomspace(DURATION_BOUNDS_S[0], DURATION_BOUNDS_S[1], 21)


def duration_identifiability(prep: _Prepared, unit_response, shape: str, x: np.ndarray,
                             bounds: list[tuple[float, float]]) -> DurationIdentifiability:
    """Profile the fit's objective over duration and condition its Jacobian (see
    `DurationIdentifiability`). `x` = (duration, start, *extra) is the fit; `bounds` the
    (low, high) of start and of each extra parameter."""
    t, y = prep.t, prep.y
    lo, hi = [b[0] for b in bounds], [b[1] for b in bounds]
    scale = np.array([1e-3] + [max(abs(v), 1e-3) for v in x[2:]])
    full = _residual(prep, unit_response)

    def solve(duration: float, x0: np.ndarray):
        sol = least_squares(lambda z: full(duration, z[0], z[1:])[0], np.clip(x0, lo, hi), bounds=(lo, hi),
                            x_scale=scale, xtol=1e-10, ftol=1e-10, max_nfev=100)
        res, a = full(duration, sol.x[0], sol.x[1:])
        if a <= 0.0:  # an impact pushes: the best admissible magnitude is then zero
            return float(np.sum((y - np.mean(y)) ** 2)), 0.0
        return float(np.sum(res**2)), a

    best_cost, best_a = solve(float(x[0]), x[1:])
    durations = np.union1d(PROFILE_DURATIONS_S, [x[0]])
    costs, mags = np.empty(durations.size), np.empty(durations.size)
    for i, d in enumerate(durations):
        # start each from the fit with the pulse's centre kept (what the record fixes best)
        costs[i], mags[i] = solve(float(d), np.concatenate([[x[1] + 0.5 * (x[0] - d)], x[2:]]))
    n, p = t.size, 4 + len(x[2:])
    best_cost = min(best_cost, float(costs.min()))
    sigma2 = max(best_cost / (n - p), (RESOLUTION_PEAK_FRACTION * prep.peak_N) ** 2)
    excess = (costs - best_cost) / sigma2
    threshold = float(f_distribution.ppf(0.95, 1, n - p))
    interval = _interval(np.log(durations), excess, int(np.argmin(np.abs(durations - x[0]))), threshold)
    impulses = np.array([make_pulse(shape, m, d).impulse_Ns for m, d in zip(mags, durations)])

    # Jacobian of a * r(d, s, extra) + b in (a, d, s, *extra, b), central differences
    a = best_a
    cols = [unit_response(t, x[0], x[1], x[2:])]
    for k, step in enumerate([1e-6 * x[0], 1e-7] + [1e-6 * max(abs(v), 1e-3) for v in x[2:]]):
        up, down = x.copy(), x.copy()
        up[k] += step
        down[k] -= step
        cols.append(a * (unit_response(t, up[0], up[1], up[2:]) - unit_response(t, down[0], down[1], down[2:]))
                    / (2 * step))
    cols.append(np.ones_like(t))
    J = np.column_stack(cols)
    norms = np.linalg.norm(J, axis=0)
    cond = float(np.linalg.cond(J / np.where(norms > 0, norms, 1.0)))
    cov = np.linalg.pinv(J.T @ J)
    corr = float(cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1])) if cov[0, 0] > 0 and cov[1, 1] > 0 else float("nan")
    closed = interval[0] > durations[0] and interval[1] < durations[-1]
    return DurationIdentifiability(
        duration_s=float(x[0]), durations_s=durations, excess_cost=excess, magnitude_N=mags, impulse_Ns=impulses,
        threshold=threshold, interval_s=interval, condition_number=cond, magnitude_duration_correlation=corr,
        identifiable=bool(closed and interval[1] - interval[0] <= 0.5 * x[0]))


def _interval(log_d: np.ndarray, ratio: np.ndarray, i0: int, threshold: float) -> tuple[float, float]:
    """The durations (s) around grid point `i0` where `ratio` stays below `threshold`,
    the crossings interpolated in log duration; a grid end if it never crosses."""
    ends = []
    for step in (-1, 1):
        i, end = i0, log_d[0 if step < 0 else -1]
        while 0 <= i + step < log_d.size:
            j = i + step
            if ratio[j] > threshold:
                w = (threshold - ratio[i]) / (ratio[j] - ratio[i]) if ratio[j] != ratio[i] else 0.0
                end = log_d[i] + np.clip(w, 0.0, 1.0) * (log_d[j] - log_d[i])
                break
            i = j
        ends.append(float(np.exp(end)))
    return ends[0], ends[1]


@dataclass(frozen=True)
class StartFit:
    """One optimiser start of :func:`fit_sdof_starts`: where it started (``x0``: duration s,
    start s, damping ratio, frequency Hz) and where it ended (N, s, Hz; ``rmse_N`` over the
    fit window)."""

    x0: tuple[float, float, float, float]
    magnitude_N: float
    duration_s: float
    start_s: float
    damping_ratio: float
    natural_frequency_Hz: float
    impulse_Ns: float
    rmse_N: float
    at_duration_bound: bool


def fit_sdof_starts(time_s, force_N, column=None, starts: int = 12, seed: int = 0, shape: str = "half-sine",
                    window_s: float = 0.04, mass_kg: float | None = None,
                    earliest_start_s: float | None = None) -> list[StartFit]:
    """The bounded SDOF fit of :func:`fit_sdof` run from ``starts`` optimiser starts, none at the
    answer: a Latin hypercube (fixed ``seed``) over the duration (log-uniform in 0.5-12 ms), the
    start (within its bounds), the damping ratio and the frequency (within the study's bounds
    about the column's values). No coarse grid first: each start is one bounded local least
    squares, so the spread of the results shows how far the record fixes the pulse.

    The stiffness bound (4.653-4.701e5 N/m) is not a parameter: with m = k / omega^2 the
    response does not depend on k, and with ``mass_kg`` it scales the magnitude only, by -0.7 to
    +0.3 % (the magnitude is solved linearly).
    """
    from scipy.stats import qmc

    if isinstance(starts, bool) or not isinstance(starts, int) or starts < 1:
        raise InputError("starts", f"must be an integer >= 1, got {starts!r}")
    prep = prepare_record(time_s, force_N, window_s=window_s)
    stiffness, freq0, zeta0, earliest = _sdof_start(time_s, column, prep, earliest_start_s)
    f_lo, f_hi = freq0 - SDOF_FREQUENCY_TOL_HZ, freq0 + SDOF_FREQUENCY_TOL_HZ
    z_lo, z_hi = max(1e-4, zeta0 - SDOF_DAMPING_TOL), min(0.99, zeta0 + SDOF_DAMPING_TOL)
    s_lo, s_hi = _start_bounds(prep, earliest)
    gain = None if mass_kg is None else stiffness / require_positive("mass_kg", mass_kg)

    def unit(t, duration, start, extra):
        omega = 2 * np.pi * extra[1]
        q = oscillator_response(make_pulse(shape, 1.0, duration, start), t, omega, extra[0])
        return (omega**2 if gain is None else gain) * q

    full = _residual(prep, unit)
    lo = [DURATION_BOUNDS_S[0], s_lo, z_lo, f_lo]
    hi = [DURATION_BOUNDS_S[1], s_hi, z_hi, f_hi]
    u = qmc.LatinHypercube(d=4, seed=seed).random(starts)
    out = []
    for row in u:
        x0 = np.array([5e-4 * (12e-3 / 5e-4) ** row[0], s_lo + row[1] * (s_hi - s_lo),
                       z_lo + row[2] * (z_hi - z_lo), f_lo + row[3] * (f_hi - f_lo)])
        sol = least_squares(lambda x: full(x[0], x[1], x[2:])[0], x0, bounds=(lo, hi),
                            x_scale=np.array([1e-3, 1e-3, zeta0, freq0]), xtol=1e-10, ftol=1e-10, max_nfev=200)
        res, a = full(sol.x[0], sol.x[1], sol.x[2:])
        out.append(StartFit(tuple(float(v) for v in x0), float(a), float(sol.x[0]), float(sol.x[1]),
                            float(sol.x[2]), float(sol.x[3]), float(make_pulse(shape, a, sol.x[0]).impulse_Ns),
                            float(np.sqrt(np.mean(res**2))), bool(sol.x[0] <= DURATION_BOUNDS_S[0] * 1.001)))
    return out
