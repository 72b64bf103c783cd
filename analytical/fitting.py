"""Fit an impact pulse to a measured force-response record (the seed's sections 3.2.1-3.2.2).

A record is the force a load cell measured while a column rang after a debris
impact. We look for the pulse p(t) (half-sine by default) whose modelled response
matches it best in the least-squares sense:

* ``fit_sdof``: the response R = k u of a single-degree-of-freedom oscillator; the
  seed varied magnitude, duration, damping, stiffness and natural frequency within
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
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import least_squares

from analytical.column import Column
from analytical.errors import InputError, require_positive
from analytical.mdof import mdof_response
from analytical.oscillator import oscillator_response
from analytical.pulses import make_pulse

#: Half-widths of the seed's SDOF fit bounds (Stolle et al. 2019 via the seed, section
#: 3.2.1: f1 = 70 +- 2.2 Hz, damping 0.045 +- 0.005, k = 4.653e5 .. 4.701e5 N/m).
SDOF_FREQUENCY_TOL_HZ = 2.2
SDOF_DAMPING_TOL = 0.005
SDOF_STIFFNESS_N_M = (4.653e5, 4.701e5)

#: Pulse durations searched, s (the seed's fitted pulses lasted 0.6-7 ms).
DURATION_BOUNDS_S = (2.0e-4, 2.0e-2)


@dataclass(frozen=True)
class PulseFit:
    """A fitted impact pulse and how well its modelled response matches the record.

    Forces in N, times in s. `time_s`/`model_N`/`measured_N` cover the fit window;
    `measured_N` has the fitted offset (`offset_N`) removed. `peak_measured_N` is the
    record's peak above its own baseline (the quiet stretch before the impact), the same
    whichever model is fitted.
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

    @property
    def pulse(self):
        """The fitted pulse (a `analytical.pulses` object)."""
        return make_pulse(self.shape, self.magnitude_N, self.duration_s, self.start_s)


@dataclass(frozen=True)
class _Prepared:
    t: np.ndarray  # fit window times (s)
    y: np.ndarray  # record in the window (N), raw
    onset_s: float  # first clear departure from the baseline
    baseline_N: float
    noise_N: float
    peak_N: float  # peak of (record - baseline) in the window


def prepare_record(time_s, force_N, window_s: float = 0.04, pre_s: float = 0.01) -> _Prepared:
    """Validate a record, find the impact and cut the fit window.

    The baseline and noise come from the quietest stretch before the largest
    excursion; the impact onset is the first sample that leaves the baseline by
    more than 6 noise standard deviations and 5 % of the excursion.
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
    baseline = float(np.median(quiet[: max(5, quiet.size // 2)]))
    d = np.diff(quiet[: max(6, quiet.size // 2)])
    noise = float(1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0)) if d.size else 0.0
    excursion = float(np.max(np.abs(y - baseline)))
    threshold = max(6.0 * noise, 0.05 * excursion)
    if excursion <= 0.0 or excursion < 8.0 * noise:
        raise InputError("force_N", f"no impact found: the largest excursion ({excursion:.3g} N) is within the "
                                    f"noise ({noise:.3g} N rms)")
    above = np.flatnonzero(np.abs(y - baseline) > threshold)
    onset = float(t[above[0]])
    if t[-1] - onset < 5e-3:
        raise InputError("time_s", f"the record ends {1e3 * (t[-1] - onset):.1f} ms after the impact onset; "
                                   "at least 5 ms of response are needed")
    keep = (t >= onset - pre_s) & (t <= onset + window_s)
    tw, yw = t[keep], y[keep]
    return _Prepared(tw, yw, onset, baseline, noise, float(np.max(yw - baseline)))


def _project(r: np.ndarray, y: np.ndarray) -> tuple[float, float, np.ndarray]:
    """Best a, b with a*r + b ~ y (linear least squares); returns a, b, residual."""
    A = np.column_stack([r, np.ones_like(r)])
    (a, b), *_ = np.linalg.lstsq(A, y, rcond=None)
    return float(a), float(b), a * r + b - y


def _fit(
    prep: _Prepared,
    unit_response: Callable[[np.ndarray, float, float, np.ndarray], np.ndarray],
    extra_x0: list[float],
    extra_bounds: list[tuple[float, float]],
    duration_grid: np.ndarray,
) -> tuple[np.ndarray, float, float, np.ndarray]:
    """Variable-projection least squares; returns (x, magnitude, offset, model)."""
    t, y = prep.t, prep.y
    dt_med = float(np.median(np.diff(t)))
    start_lo, start_hi = prep.onset_s - 0.01, prep.onset_s + 2 * dt_med

    def residual(x: np.ndarray) -> np.ndarray:
        r = unit_response(t, x[0], x[1], x[2:])
        return _project(r, y)[2]

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
        peak_measured_N=float(np.max(prep.y) - prep.baseline_N),  # above the record's own baseline: one value per record
        peak_model_N=float(np.max(model_n)),
        offset_N=float(b),
        time_s=prep.t,
        model_N=model_n,
        measured_N=measured,
        **structural,
    )


def fit_sdof(time_s, force_N, column=None, shape: str = "half-sine", window_s: float = 0.04,
             mass_kg: float | None = None) -> PulseFit:
    """Fit a pulse with the SDOF model R = k u (seed eq. [6]) to a force record.

    Varies magnitude (N), duration (s), start (s), damping ratio and natural
    frequency (Hz) within the seed's bounds around the column's measured values
    (module constants); the stiffness is the column's (it does not change R, see
    the module docstring).

    `mass_kg` (default None: m = k / omega^2, a consistent oscillator) holds the mass
    fixed while the frequency is fitted, as a literal reading of the seed's eq. [6]
    with k, m_s and omega as separate inputs does: then R = (k / m_s) q.
    """
    prep = prepare_record(time_s, force_N, window_s=window_s)
    stiffness = float(getattr(column, "stiffness_N_m", 4.685e5))
    freq0 = float(getattr(column, "natural_frequency_Hz", 70.0))
    zeta0 = float(getattr(column, "damping_ratio", 0.045))
    f_lo, f_hi = freq0 - SDOF_FREQUENCY_TOL_HZ, freq0 + SDOF_FREQUENCY_TOL_HZ
    z_lo, z_hi = max(1e-4, zeta0 - SDOF_DAMPING_TOL), min(0.99, zeta0 + SDOF_DAMPING_TOL)

    fixed_gain = None if mass_kg is None else stiffness / require_positive("mass_kg", mass_kg)

    def unit(t, duration, start, extra):
        zeta, freq = extra
        omega = 2 * np.pi * freq
        q = oscillator_response(make_pulse(shape, 1.0, duration, start), t, omega, zeta)
        return (omega**2 if fixed_gain is None else fixed_gain) * q

    grid = np.geomspace(5e-4, 1.2e-2, 10)
    x, a, b, fitted = _fit(prep, unit, [zeta0, freq0], [(z_lo, z_hi), (f_lo, f_hi)], grid)
    return _result("sdof", shape, prep, x, a, b, fitted, natural_frequency_Hz=float(x[3]),
                   damping_ratio=float(x[2]), stiffness_N_m=stiffness, height_m=None)


def fit_mdof(time_s, force_N, column=None, height_m: float = 0.40, shape: str = "half-sine",
             window_s: float = 0.04) -> PulseFit:
    """Fit a pulse at `height_m` (m above the base) with the MDOF column's base shear.

    Varies magnitude (N), duration (s) and start (s); the column's matrices are fixed
    (the seed's section 3.2.2).
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
                   stiffness_N_m=None, height_m=float(height_m))
