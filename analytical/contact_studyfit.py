"""The study's fit of a strike's base shear (:func:`analytical.contact_law.study_fit`) in closed form.

:func:`analytical.contact_law.study_fit` hands the record to :func:`analytical.fitting.fit_mdof`:
a half-sine ``a sin(pi (t - t0) / T)`` on the MDOF column loaded at the water level, ``a`` and a
constant offset solved by linear least squares for every trial ``(T, t0)`` (variable
projection), the trials a coarse grid over ``T`` and then ``scipy.optimize.least_squares``. Each
trial there is an adaptive modal superposition (:func:`analytical.mdof.mdof_response`), some
30 ms; a fit takes about 90 of them, and the calibration fits every strike at every trial law.

:func:`fast_study_fit` is the same fit (the same record preparation
:func:`analytical.fitting.prepare_record`, grid, bounds, scales and tolerances) with the trial
response in closed form, vectorised over trials and modes:

* a half-sine is a sine switched on at ``t0`` plus the same sine switched on at ``t0 + T``
  (``sin(W tau) = -sin(W (tau - T))`` past ``T``), so each mode's response is two copies of its
  exact response to a switched-on sine, steady part ``Im(H e^{i W tau})``, ``H = 1 / (w^2 - W^2 + i
  c W)``, plus the free vibration that starts it from rest;
* the base shear is the mode-acceleration form of :mod:`analytical.mdof`,
  ``V = s(h) P - sum_n c_n (q''_n + a0 q'_n)``; a left-out mode keeps its static share through
  ``P``, so the modes up to :data:`FIT_MODES_HZ` carry a smooth pulse. Against the adaptive
  superposition (all the modes it needs) a trial response on the study's column differs by at most
  1e-3 (4.7 ms pulse) to 4e-3 (1 ms) of its peak at 0.2-0.4 m, the fitted peak, duration and
  impulse by about 1e-5 (tests/test_contact_studyfit.py). At 0.2 m, 1 / 4.7 ms: 2 kHz (10 modes)
  7e-3 / 1.5e-3, 4 kHz (15) 1.7e-3 / 3.2e-4, 8 kHz (30) 6e-4 / 1.6e-4.

A trial costs about 0.6 ms instead of 30 ms, a fit about 0.1 s instead of 2-3 s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from analytical.column import Column
from analytical.column_fem import column_model
from analytical.errors import InputError
from analytical.fitting import DURATION_BOUNDS_S, prepare_record

__all__ = ["FIT_MODES_HZ", "FitFigures", "HalfSineModes", "fast_study_fit"]

#: Modes of the column kept in the fit's trial responses: those below this frequency (Hz), at
#: least :data:`MIN_FIT_MODES` of them (the adaptive superposition's first band and floor).
FIT_MODES_HZ = 4000.0
MIN_FIT_MODES = 10
#: The fit's duration grid and lead fractions (:func:`analytical.fitting.fit_mdof`'s).
DURATION_GRID_S = np.geomspace(5e-4, 1.2e-2, 10)
LEADS = (0.0, 0.25, 0.5)
#: Largest decay exponent ``-Re(r) x span`` the kept basis ``e^{r (t - t0)}`` may span.
_MAX_DECAY_EXPONENT = 600.0
#: The finite-difference step of scipy's 2-point Jacobian, relative to max(1, |x|).
_STEP = float(np.finfo(float).eps) ** 0.5


class HalfSineModes:
    """The column's base shear under a unit half-sine at ``height_m``, in closed form for many
    trials at once (module notes)."""

    def __init__(self, column: Column, height_m: float, max_frequency_Hz: float = FIT_MODES_HZ):
        model = column_model(column)
        if not 0.0 < float(height_m) <= column.height_m:
            raise InputError("height_m", f"must be in (0, {column.height_m}] m, got {height_m}")
        freq = model.frequencies_Hz
        n = min(max(int(np.searchsorted(freq, max_frequency_Hz, side="right")), MIN_FIT_MODES), len(freq))
        if np.any(model.damping_ratios[:n] >= 1.0):
            raise InputError("max_frequency_Hz", "the kept modes must be underdamped")
        f = model.load_vector(float(height_m))[model.free_dofs]
        weights = (model.inertia_vector @ model.mode_shapes) * (f @ model.mode_shapes)
        omega = model.circular_frequencies_rad_s[:n]
        self.modes = n
        self.weights = weights[:n]
        self.w2 = omega * omega
        self.c = 2.0 * model.damping_ratios[:n] * omega
        self.a0 = model.rayleigh_a0_1_s
        self.static = model.base_shear_factor(float(height_m))
        root = np.sqrt((0.25 * self.c * self.c - self.w2).astype(complex))
        self.r = -0.5 * self.c + root  # the underdamped root (its conjugate is the other)
        self.r_other = -0.5 * self.c - root
        self._grid = None

    def _basis(self, t: np.ndarray):
        """``[Re; Im] e^{r_n (t - t[0])}`` (2N, M), kept for the last grid of times; None where it
        would leave the floating-point range (a span over :data:`_MAX_DECAY_EXPONENT` decay times)."""
        key = (t.size, float(t[0]), float(t[-1]))
        if self._grid is None or self._grid[0] != key:
            basis = None
            if float(t[-1] - t[0]) * float(np.max(-self.r.real)) <= _MAX_DECAY_EXPONENT:
                e = np.exp(self.r[:, None] * (t - t[0])[None, :])
                basis = np.ascontiguousarray(np.vstack([e.real, e.imag]))
            self._grid = (key, basis)
        return self._grid[1]

    def _free(self, t: np.ndarray, coef: np.ndarray, on_s: np.ndarray) -> np.ndarray:
        """``2 Re sum_n coef_n e^{r_n (t - on)}`` (P, M) for ``t > on``, else 0."""
        tau = t[None, :] - on_s[:, None]
        on = tau > 0.0
        basis = self._basis(t)
        if basis is not None:  # e^{r (t - on)} = e^{-r (on - t0)} e^{r (t - t0)}: one real product
            c = coef * np.exp(-self.r[None, :] * (on_s[:, None] - t[0]))
            c = np.hstack([c.real, -c.imag])
            # one trial: a matrix-vector product; many: einsum, which a busy machine's threaded
            # matrix product (20 ms for 30 trials against 1 ms) does not slow down
            y = (c[0] @ basis)[None, :] if len(c) == 1 else np.einsum("pn,nm->pm", c, basis)
        else:
            y = np.einsum("pn,pnm->pm", coef, np.exp(self.r[None, :, None] * np.where(on, tau, 0.0)[:, None, :])).real
        return np.where(on, 2.0 * y, 0.0)

    def response(self, t: np.ndarray, durations, starts) -> np.ndarray:
        """Base shear (N) at times ``t`` (M,, increasing) of unit half-sines of ``durations`` (s)
        starting at ``starts`` (s), both (P,): shape (P, M).

        Per mode, a sine ``sin(W tau)`` switched on at ``tau = 0`` gives ``q'' + a0 q'`` =
        ``Im(S e^{i W tau}) + 2 Re(F e^{r tau})`` (steady part, free vibration from rest; ``r`` the
        underdamped root); the half-sine adds the same switched on at ``T``, whose steady part
        cancels the first's from ``T`` on."""
        t = np.asarray(t, dtype=float)
        d = np.atleast_1d(np.asarray(durations, dtype=float))
        s = np.atleast_1d(np.asarray(starts, dtype=float))
        ww = (np.pi / d)[:, None]  # (P, 1)
        h = 1.0 / (self.w2[None, :] - ww * ww + 1j * self.c[None, :] * ww)  # (P, N)
        q0, v0 = -h.imag, -ww * h.real  # the free vibration starts the sine's mode from rest
        r, r2 = self.r[None, :], self.r_other[None, :]
        free = self.weights[None, :] * (v0 - r2 * q0) / (r - r2) * (r * r + self.a0 * r)  # (P, N)
        steady = (self.weights[None, :] * (-ww * ww + 1j * self.a0 * ww) * h).sum(axis=1)[:, None]  # (P, 1)
        tau = t[None, :] - s[:, None]
        inside = (tau >= 0.0) & (tau < d[:, None])
        phase = ww * tau
        sin, cos = np.sin(phase), np.cos(phase)
        shear = np.where(inside, self.static * sin - (steady.real * sin + steady.imag * cos), 0.0)
        return shear - self._free(t, free, s) - self._free(t, free, s + d)


@dataclass(frozen=True)
class FitFigures:
    """The fitted half-sine: magnitude (N), duration (s), its impulse (N s), start (s), the
    rms of the fit's residual (N)."""

    magnitude_N: float
    duration_s: float
    impulse_Ns: float
    start_s: float
    rmse_N: float


def _project(r: np.ndarray, y: np.ndarray):
    """Per row of ``r`` (P, M): the best ``a r + b ~ y``; returns (a, b, residual (P, M))."""
    rm = r.mean(axis=1, keepdims=True)
    ym = y.mean()
    rc = r - rm
    var = np.einsum("pm,pm->p", rc, rc)
    a = np.einsum("pm,m->p", rc, y - ym) / np.where(var > 0.0, var, 1.0)
    b = ym - a * rm[:, 0]
    return a, b, a[:, None] * r + b[:, None] - y[None, :]


def fast_study_fit(time_s, force_N, modes: HalfSineModes, window_s: float = 0.04) -> FitFigures:
    """:func:`analytical.fitting.fit_mdof` on a base-shear record with ``modes``' closed-form
    trial responses (module notes): the same preparation, grid, bounds and least squares."""
    prep = prepare_record(time_s, force_N, window_s=window_s)
    t, y = prep.t, prep.y
    dt_med = float(np.median(np.diff(t)))
    lo, hi = [DURATION_BOUNDS_S[0], prep.onset_s - 0.01], [DURATION_BOUNDS_S[1], prep.onset_s + 2 * dt_med]
    grid_d = np.repeat(DURATION_GRID_S, len(LEADS))
    grid_s = np.maximum(lo[1], prep.onset_s - np.tile(LEADS, len(DURATION_GRID_S)) * grid_d)
    _, _, res = _project(modes.response(t, grid_d, grid_s), y)
    best = int(np.argmin(np.einsum("pm,pm->p", res, res)))
    x0 = np.clip([grid_d[best], grid_s[best]], lo, hi)

    last = {}

    def residual(x):
        res = _project(modes.response(t, x[:1], x[1:]), y)[2][0]
        last["x"], last["res"] = x.copy(), res
        return res

    def jacobian(x):
        """scipy's 2-point differences (its steps, turned back at a bound), both trials in one
        call; the residual at ``x`` is the one just computed."""
        h = _STEP * np.where(x >= 0.0, 1.0, -1.0) * np.maximum(1.0, np.abs(x))
        h = np.where((x + h < np.asarray(lo)) | (x + h > np.asarray(hi)), -h, h)
        trial = x[None, :] + np.diag(h)
        f0 = last["res"] if "x" in last and np.array_equal(last["x"], x) else residual(x)
        df = _project(modes.response(t, trial[:, 0], trial[:, 1]), y)[2] - f0[None, :]
        return (df / (trial - x[None, :]).diagonal()[:, None]).T

    sol = least_squares(residual, x0, jac=jacobian, bounds=(lo, hi), x_scale=np.array([1e-3, 1e-3]), xtol=1e-10,
                        ftol=1e-10, max_nfev=200)
    a, _, res = _project(modes.response(t, sol.x[:1], sol.x[1:]), y)
    magnitude, duration = float(a[0]), float(sol.x[0])
    if magnitude <= 0.0:
        raise InputError("force_N", "the best-fitting pulse has a non-positive magnitude")
    return FitFigures(magnitude, duration, 2.0 * magnitude * duration / np.pi, float(sol.x[1]),
                      float(np.sqrt(np.mean(res[0] ** 2))))
