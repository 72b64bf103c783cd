"""The study comparison with the flow's own uncertainty: one set of starts through two meshes' flows.

An ensemble's standard error (:func:`analytical.study_comparison.compare_with_study`) carries the
scatter of its starts through one recorded flow, not the flow's error. The same ensemble carried
through a second mesh's flow measures that error: for each figure the two means differ by
``d = mean_a - mean_b``.

The flow's uncertainty in the first flow's mean is taken as ``u = |d|``: for a figure converging
monotonically at first order with the cell size halved the finer mesh's error equals ``d`` (at
second order it is ``d / 3``), so ``|d|`` is an upper estimate for a refinement ratio of two; it
is one number, counted with one degree of freedom. The test is Welch's with three variance
components, ``t = (mean_a - M) / sqrt(se_a^2 + u^2 + S^2 / N)``, its degrees of freedom by
Welch-Satterthwaite, ``(sum v_i)^2 / sum(v_i^2 / nu_i)`` with ``nu`` = ``n_a - 1``, 1, ``N - 1``.

A test that cannot fail is no test: :attr:`FlowComparison.half_width` is the 95 % half-width of
``mean_a - M``; where it exceeds half the study's mean (a mean 50 % off would pass), the verdict
is "cannot tell" rather than "agrees": the flow is too uncertain for the test to fail.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from analytical.errors import InputError
from analytical.study_comparison import SIGNIFICANCE, JsonFigures

__all__ = ["FlowComparison", "compare_two_flows"]


@dataclass(frozen=True)
class FlowComparison(JsonFigures):
    """One figure of one ensemble through two flows, beside the study's (mean, std, n)."""

    n_a: int
    mean_a: float
    se_a: float
    n_b: int
    mean_b: float
    se_b: float
    flow_u: float
    se_total: float
    study_mean: float
    study_std: float
    study_n: int
    t: float
    dof: float
    p_value: float
    p_without_flow: float
    half_width: float
    verdict: str


def _sample(values, name: str) -> np.ndarray:
    x = np.asarray(values, dtype=float).ravel()
    x = x[np.isfinite(x)]
    if x.size < 2:
        raise InputError(name, f"needs at least 2 finite values for a standard error, got {x.size}")
    return x


def compare_two_flows(samples_a, samples_b, study_mean: float, study_std: float, study_n: int,
                      significance: float = SIGNIFICANCE) -> FlowComparison:
    """``samples_a`` (the ensemble through the first flow) against the study's mean, with the
    flow's uncertainty from ``samples_b`` (the same starts through a second mesh's flow); module
    notes. ``p_without_flow`` is the plain Welch p (the flow taken as exact)."""
    a, b = _sample(samples_a, "samples_a"), _sample(samples_b, "samples_b")
    if study_n < 2 or not study_std >= 0:
        raise InputError("study", f"needs n >= 2 and std >= 0, got n {study_n!r}, std {study_std!r}")
    mean_a, mean_b = float(a.mean()), float(b.mean())
    v_a, v_b = float(a.var(ddof=1)) / a.size, float(b.var(ddof=1)) / b.size
    v_s = study_std * study_std / study_n
    u = abs(mean_a - mean_b)
    parts = [(v_a, a.size - 1), (u * u, 1), (v_s, study_n - 1)]
    total = sum(v for v, _ in parts)
    diff = mean_a - study_mean
    if total == 0.0:
        raise InputError("samples_a", "no scatter anywhere: the test is undefined")
    t = diff / math.sqrt(total)
    dof = total * total / sum(v * v / nu for v, nu in parts if v > 0)
    p = float(2.0 * stats.t.sf(abs(t), dof))
    plain = v_a + v_s
    plain_dof = plain * plain / (v_a * v_a / (a.size - 1) + v_s * v_s / (study_n - 1))
    p0 = float(2.0 * stats.t.sf(abs(diff) / math.sqrt(plain), plain_dof))
    half = float(stats.t.isf(significance / 2, dof) * math.sqrt(total))
    if p > significance:
        verdict = (f"agrees (p > {significance:g})" if half <= 0.5 * abs(study_mean)
                   else f"cannot tell (p > {significance:g}, but a mean half the study's or 1.5 times it would pass too)")
    else:
        verdict = f"differs (p <= {significance:g})"
    return FlowComparison(int(a.size), mean_a, math.sqrt(v_a), int(b.size), mean_b, math.sqrt(v_b), u,
                          math.sqrt(v_a + u * u), float(study_mean), float(study_std), int(study_n),
                          float(t), float(dof), p, p0, half, verdict)
