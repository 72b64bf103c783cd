"""The tool's strikes beside the study's 22, like for like: the study's fit of a base-shear
history, and a test of two means that can fail.

The study (its section 3.2.2) turned each measured force response into a pulse by
fitting a half-sine on its MDOF column, loaded at the water level at the column's face
(0.16-0.50 m, mean 0.40 m), varying magnitude and duration; Table 2's MDOF row gives the
mean and standard deviation of those pulses over its 22 impacts (section 3.1: 22 experiments
kept). :func:`fit_like_the_study` does the same to a base-shear history the tool computed
(:func:`analytical.fitting.fit_mdof`, half-sine, at the height given), so that its pulses are
compared with Table 2's as the study made them, not as the contact law made them.

:func:`compare_with_study` compares a sample of the tool's values with the study's
(mean, std, n): the sample's n, mean, standard error, median and 5-95 % quantiles, and
Welch's unequal-variance t test of the two means (t, its Welch-Satterthwaite degrees of
freedom, the two-sided p): "agrees (Welch p > 0.05)" or "differs (Welch p <= 0.05)". A mean
that lies inside the study's scatter can still differ from the study's mean: with n = 22 the
study's mean is known to about std / sqrt(22) (13 N for the peak force), not to its std.
With a single value there is no sample variance and no Welch test; the value's z against the
study's distribution (mean, std) is given instead, with the two-sided normal p.

Units: N, s, m, m/s.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np
from scipy import stats

from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive
from analytical.fitting import fit_mdof
from analytical.study import STUDY_IMPACT_COUNT, STUDY_IMPACT_VELOCITY_M_S, STUDY_TABLE2_MDOF

__all__ = [
    "FIT_PRE_CONTACT_S",
    "JsonFigures",
    "FIT_SAMPLE_S",
    "STUDY_IMPACT_COUNT",
    "SIGNIFICANCE",
    "STUDY_FIGURES",
    "StudyComparison",
    "StudyFit",
    "compare_table",
    "compare_with_study",
    "fit_like_the_study",
    "strike_component",
]

SIGNIFICANCE = 0.05
"""The two-sided level below which the means are said to differ."""

STUDY_FIGURES: dict[str, tuple[float, float, int]] = {
    "speed_m_s": (*STUDY_IMPACT_VELOCITY_M_S, STUDY_IMPACT_COUNT),
    "normal_speed_m_s": (*STUDY_IMPACT_VELOCITY_M_S, STUDY_IMPACT_COUNT),
    "peak_force_N": (*STUDY_TABLE2_MDOF["peak_force_N"], STUDY_IMPACT_COUNT),
    "duration_s": (*STUDY_TABLE2_MDOF["duration_s"], STUDY_IMPACT_COUNT),
    "impulse_Ns": (*STUDY_TABLE2_MDOF["impulse_Ns"], STUDY_IMPACT_COUNT),
}
"""The study's (mean, std, n) of each compared quantity. The study measured the debris's
speed, not its part along the contact normal, so both the tool's total speed and its normal
part are set against the one measured figure (1.60 +- 0.13 m/s, backed out of Table 2's ASCE
rows); the pulse figures are Table 2's MDOF row."""

FIT_SAMPLE_S = 5e-5
"""The uniform sample interval (20 kHz) a base-shear history is resampled onto before the fit:
the tool's histories are sampled unevenly (the pulse at the contact integration's steps, the
ringing after it more finely), and least squares on uneven samples would weight the ringing
more. Against 2e-5 and 1e-4 s the fitted peak, duration and impulse agree to 0.01 %."""

FIT_PRE_CONTACT_S = 0.01
"""The quiet record (zero base shear) put before the first contact, s: the impact's base
shear is zero before it, and the fit (:func:`analytical.fitting.prepare_record`) takes its
baseline from the record before the impact."""


# ------------------------------------------------------------------------------ the comparison
class JsonFigures:
    """A dataclass of figures whose :meth:`to_dict` gives NaN (and infinities) as None, for JSON."""

    def to_dict(self) -> dict:
        """The figures with NaN as None (for JSON)."""
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in asdict(self).items()}


@dataclass(frozen=True)
class StudyComparison(JsonFigures):
    """A sample of the tool's values beside the study's (mean, std, n).

    ``test`` is ``"welch"`` (n >= 2: ``welch_t``, ``welch_dof``, ``p_value``), ``"z"`` (one
    value: ``z`` against the study's distribution, ``p_value`` its two-sided normal p) or
    ``"none"`` (no value). Undefined figures are NaN; :meth:`to_dict` gives them as None.
    """

    n: int
    mean: float
    standard_error: float
    median: float
    q05: float
    q95: float
    study_mean: float
    study_std: float
    study_n: int
    test: str
    welch_t: float
    welch_dof: float
    z: float
    p_value: float
    verdict: str


def compare_with_study(samples, study_mean: float, study_std: float, study_n: int = STUDY_IMPACT_COUNT,
                       significance: float = SIGNIFICANCE) -> StudyComparison:
    """The tool's ``samples`` (NaN dropped) against the study's ``study_mean`` +- ``study_std``
    over ``study_n`` values (module notes): Welch's t test for two or more samples, a z for one.

    Welch: ``t = (m - M) / sqrt(s^2/n + S^2/N)``, ``dof = (s^2/n + S^2/N)^2 / ((s^2/n)^2/(n-1)
    + (S^2/N)^2/(N-1))``, ``p = 2 P(T_dof > |t|)``; s is the sample's std (ddof 1). The
    quantiles are numpy's linear ones.
    """
    x = np.asarray(samples, dtype=float).ravel()
    x = x[np.isfinite(x)]
    mu, sd = require_finite("study_mean", study_mean), require_finite("study_std", study_std)
    if sd < 0:
        raise InputError("study_std", f"must be >= 0, got {study_std!r}")
    big_n = int(study_n)
    if big_n < 2:
        raise InputError("study_n", f"must be >= 2 for a sample variance, got {study_n!r}")
    alpha = require_positive("significance", significance)
    nan = math.nan
    n = int(x.size)
    base = dict(study_mean=mu, study_std=sd, study_n=big_n, welch_t=nan, welch_dof=nan, z=nan, p_value=nan)
    if n == 0:
        return StudyComparison(0, nan, nan, nan, nan, nan, test="none", verdict="no values", **base)
    mean, median = float(x.mean()), float(np.median(x))
    q05, q95 = (float(q) for q in np.percentile(x, [5.0, 95.0]))
    if n == 1:
        if sd == 0:
            return StudyComparison(1, mean, nan, median, q05, q95, test="z", verdict="undefined (the study's std is 0)",
                                   **base)
        z = (mean - mu) / sd
        p = float(2.0 * stats.norm.sf(abs(z)))
        verdict = (f"one value: inside the study's scatter (|z| < {stats.norm.isf(alpha / 2):.2f})" if p > alpha
                   else f"one value: outside the study's scatter (|z| >= {stats.norm.isf(alpha / 2):.2f})")
        return StudyComparison(1, mean, nan, median, q05, q95, test="z",
                               **{**base, "z": float(z), "p_value": p}, verdict=verdict)
    var_a, var_b = float(x.var(ddof=1)) / n, sd * sd / big_n
    se = math.sqrt(var_a)
    if var_a + var_b == 0.0:
        return StudyComparison(n, mean, se, median, q05, q95, test="welch", verdict="undefined (no scatter on either side)",
                               **base)
    t = (mean - mu) / math.sqrt(var_a + var_b)
    dof = (var_a + var_b) ** 2 / (var_a**2 / (n - 1) + var_b**2 / (big_n - 1))
    p = float(2.0 * stats.t.sf(abs(t), dof))
    verdict = f"agrees (Welch p > {alpha:g})" if p > alpha else f"differs (Welch p <= {alpha:g})"
    return StudyComparison(n, mean, se, median, q05, q95, test="welch",
                           **{**base, "welch_t": float(t), "welch_dof": float(dof), "p_value": p}, verdict=verdict)


def compare_table(samples: dict) -> dict[str, StudyComparison]:
    """:func:`compare_with_study` for every quantity of ``samples`` (keys of :data:`STUDY_FIGURES`),
    in :data:`STUDY_FIGURES`' order."""
    unknown = set(samples) - set(STUDY_FIGURES)
    if unknown:
        raise InputError("samples", f"unknown quantities {sorted(unknown)}; expected some of {list(STUDY_FIGURES)}")
    return {k: compare_with_study(samples[k], *STUDY_FIGURES[k]) for k in STUDY_FIGURES if k in samples}


# ------------------------------------------------------------------------------ the study's fit
@dataclass(frozen=True)
class StudyFit:
    """The half-sine the study's MDOF fit finds in a base-shear history.

    ``peak_N``, ``duration_s``, ``impulse_Ns``: the pulse; ``start_s``: its start on the
    history's clock (time from first contact for the tool's histories: a negative start is a
    pulse that begins before the contact); ``height_m``: where the column was loaded;
    ``rmse_N``: the fit's residual; ``record_peak_N``: the history's peak;
    ``nrmse = rmse_N / record_peak_N``.
    """

    peak_N: float
    duration_s: float
    impulse_Ns: float
    start_s: float
    height_m: float
    rmse_N: float
    record_peak_N: float

    @property
    def nrmse(self) -> float:
        return self.rmse_N / self.record_peak_N if self.record_peak_N > 0 else math.nan


def strike_component(shear_x_N, shear_y_N, normal) -> np.ndarray:
    """The base shear along the strike: the history's horizontal vector projected on the
    horizontal direction of ``-normal`` (the normal points from the column into the body).
    ``shear_y_N`` may be None (a load without a y part). For a strike on the upstream face
    (normal -x) this is the along-flume shear the study's load cell gave."""
    n = np.asarray(normal, dtype=float)
    if n.shape != (3,) or not np.all(np.isfinite(n)):
        raise InputError("normal", f"must be a finite 3-vector, got {normal!r}")
    horizontal = math.hypot(n[0], n[1])
    if horizontal == 0.0:
        raise InputError("normal", "is vertical: the strike puts no horizontal load on the column")
    x = np.asarray(shear_x_N, dtype=float)
    y = np.zeros_like(x) if shear_y_N is None else np.asarray(shear_y_N, dtype=float)
    if x.shape != y.shape:
        raise InputError("shear_y_N", f"must match shear_x_N's shape {x.shape}, got {y.shape}")
    return -(x * n[0] + y * n[1]) / horizontal


def fit_like_the_study(time_s, base_shear_N, height_m: float, column: Column | None = None,
                       sample_s: float = FIT_SAMPLE_S, pre_contact_s: float = FIT_PRE_CONTACT_S) -> StudyFit:
    """Fit a half-sine on the MDOF ``column`` loaded at ``height_m`` (m above its base) to a
    base-shear history (``time_s`` from first contact, ``base_shear_N`` along the strike), as
    the study did (module notes).

    The history is resampled by linear interpolation onto a uniform grid of ``sample_s``
    (:data:`FIT_SAMPLE_S`) from ``pre_contact_s`` before its first sample, zero there (the
    column is at rest before the contact). Raises InputError when the history holds no impact
    or the best pulse is not positive (:func:`analytical.fitting.fit_mdof`).
    """
    t = np.asarray(time_s, dtype=float)
    y = np.asarray(base_shear_N, dtype=float)
    if t.ndim != 1 or t.shape != y.shape or t.size < 2:
        raise InputError("base_shear_N", f"time and base shear must be 1-D of equal length >= 2, got {t.shape} and "
                                         f"{y.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))) or np.any(np.diff(t) <= 0):
        raise InputError("time_s", "must be finite and increase strictly, with finite base shears")
    step = require_positive("sample_s", sample_s)
    pre = require_finite("pre_contact_s", pre_contact_s)
    if pre < 0:
        raise InputError("pre_contact_s", f"must be >= 0, got {pre_contact_s!r}")
    grid = t[0] - pre + step * np.arange(int(math.floor((t[-1] - t[0] + pre) / step)) + 1)
    values = np.interp(grid, t, y, left=0.0, right=float(y[-1]))
    fit = fit_mdof(grid, values, column=column, height_m=height_m, shape="half-sine")
    return StudyFit(peak_N=fit.magnitude_N, duration_s=fit.duration_s, impulse_Ns=fit.impulse_Ns,
                    start_s=fit.start_s, height_m=float(height_m), rmse_N=fit.rmse_N,
                    record_peak_N=fit.peak_measured_N)
