"""Exceedance curves of a demand from weighted groups of samples, with confidence intervals.

A design study draws its realisations in groups (one group per inundation case), each group a
simple random sample of its case, and the cases weighted by the user: the demand's distribution
is the mixture ``S(x) = P(X > x) = sum_c w_c S_c(x)`` (weights normalised to 1). Its estimate is
the weighted count ``S^(x) = sum_c w_c k_c(x) / n_c``, ``k_c(x)`` the case's samples above ``x``:
each sample weighs ``w_c / n_c``. Realisations that never strike are samples too (demand 0).

Intervals
---------
* **Each exceedance probability** (pointwise): Clopper-Pearson's exact binomial interval
  (Clopper and Pearson 1934) on ``k`` exceedances in ``n`` samples. For a mixture, on the
  effective counts ``n_eff = 1 / sum_c (w_c^2 / n_c)`` and ``k_eff = S^ n_eff`` (the
  effective-sample-size form of Korn and Graubard 1998, with the stratified design effect at
  equal case probabilities): one group gives the exact interval; groups sized in proportion to
  their weights give ``n_eff = n``, the pooled sample then being a stratified sample of the
  mixture. The interval holds at each level separately, not for the whole curve at once.
* **The whole curve** (simultaneous): the Dvoretzky-Kiefer-Wolfowitz band ``S^ -+ eps``,
  ``eps = sqrt(ln(2 / alpha) / (2 n_eff))`` (Massart 1990's constant): covers the whole curve
  with probability at least ``1 - alpha``. Of constant width, it says nothing about
  probabilities below ``eps``: the tail is read with the pointwise intervals.
* **Quantiles** (P50, P90, ...): the point is the weighted sample's ``p``-quantile (the least
  sample whose weighted share at or below it reaches ``p``); the interval inverts the pointwise
  band on the distribution function ``F = 1 - S``: the least samples at which its upper and its
  lower bound reach ``p``. An upper end the sample cannot give (the lower bound never reaches
  ``p``: too few samples for that quantile) is None.

References
----------
Clopper, C.J. and Pearson, E.S. (1934). The use of confidence or fiducial limits illustrated in
    the case of the binomial. Biometrika 26(4), 404-413.
Korn, E.L. and Graubard, B.I. (1998). Confidence intervals for proportions with small expected
    number of positive counts estimated from survey data. Survey Methodology 24(2), 193-201.
Massart, P. (1990). The tight constant in the Dvoretzky-Kiefer-Wolfowitz inequality. Annals of
    Probability 18(3), 1269-1283.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import stats

from analytical.errors import InputError

__all__ = ["Exceedance", "Quantile", "clopper_pearson", "dkw_halfwidth", "exceedance", "normalised_weights"]


def normalised_weights(weights: Sequence[float]) -> np.ndarray:
    """Weights (each > 0, finite) scaled to sum to 1."""
    w = np.asarray(weights, dtype=float)
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        raise InputError("weight", f"must be one finite weight > 0 per case, got {list(np.atleast_1d(w))}")
    return w / w.sum()


def clopper_pearson(k, n, confidence: float = 0.95) -> tuple[np.ndarray, np.ndarray]:
    """Clopper-Pearson interval of a proportion from ``k`` successes in ``n`` trials (arrays;
    ``k`` may be an effective, non-integer count): (lower, upper)."""
    if not 0.0 < confidence < 1.0:
        raise InputError("confidence", f"must be in (0, 1), got {confidence!r}")
    k = np.asarray(k, dtype=float)
    n = np.broadcast_to(np.asarray(n, dtype=float), k.shape)
    if np.any(n <= 0) or np.any(k < 0) or np.any(k > n * (1 + 1e-12)):
        raise InputError("k", "must satisfy 0 <= k <= n, n > 0")
    k = np.minimum(k, n)
    alpha = 1.0 - confidence
    with np.errstate(invalid="ignore"):
        lo = np.where(k > 0, stats.beta.ppf(alpha / 2, np.maximum(k, 1e-300), n - k + 1), 0.0)
        hi = np.where(k < n, stats.beta.ppf(1 - alpha / 2, k + 1, np.maximum(n - k, 1e-300)), 1.0)
    return np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)


def dkw_halfwidth(n: float, confidence: float = 0.95) -> float:
    """Half-width of the DKW band (Massart's constant) for ``n`` samples."""
    return math.sqrt(math.log(2.0 / (1.0 - confidence)) / (2.0 * float(n)))


@dataclass(frozen=True)
class Quantile:
    """The ``p``-quantile of a demand and its interval (upper None: beyond what the sample gives)."""

    p: float
    value: float
    lower: float
    upper: float | None

    def to_dict(self) -> dict:
        return {"p": self.p, "value": self.value, "lower": self.lower, "upper": self.upper}


@dataclass(frozen=True)
class Exceedance:
    """A demand's weighted sample (sorted) and what it gives (module notes).

    ``values`` sorted ascending with their weights ``sample_weights`` (sum 1); ``n_eff`` the
    effective sample size; ``confidence`` the intervals' level."""

    values: np.ndarray
    sample_weights: np.ndarray
    n_eff: float
    samples: int
    confidence: float = 0.95

    def probability(self, x) -> np.ndarray:
        """``S^(x) = P(X > x)``: the weighted share of samples above ``x``."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        tail = np.concatenate([np.cumsum(self.sample_weights[::-1])[::-1], [0.0]])
        return np.clip(tail[np.searchsorted(self.values, x, side="right")], 0.0, 1.0)

    def interval(self, probability) -> tuple[np.ndarray, np.ndarray]:
        """Pointwise interval of exceedance probabilities (Clopper-Pearson on effective counts)."""
        p = np.clip(np.asarray(probability, dtype=float), 0.0, 1.0)
        return clopper_pearson(p * self.n_eff, self.n_eff, self.confidence)

    def exceeds(self, x: float) -> dict:
        """``P(X > x)`` with its interval."""
        p = float(self.probability(x)[0])
        lo, hi = self.interval(p)
        return {"value": float(x), "probability": p, "lower": float(lo), "upper": float(hi)}

    def curve(self) -> dict[str, np.ndarray]:
        """The curve at each distinct sample value ``x > 0``: ``P(X >= x)`` (the step's top,
        so the largest sample's probability is its weight, not 0) with its pointwise interval."""
        levels = np.unique(self.values[self.values > 0.0])
        head = np.concatenate([[0.0], np.cumsum(self.sample_weights)])
        p = np.clip(1.0 - head[np.searchsorted(self.values, levels, side="left")], 0.0, 1.0)
        lo, hi = self.interval(p)
        return {"level": levels, "probability": p, "lower": lo, "upper": hi}

    def dkw(self) -> float:
        """Half-width of the simultaneous band."""
        return dkw_halfwidth(self.n_eff, self.confidence)

    def quantile(self, p: float) -> Quantile:
        """The ``p``-quantile and its interval (module notes)."""
        if not 0.0 < p < 1.0:
            raise InputError("p", f"must be in (0, 1), got {p!r}")
        cdf = np.clip(np.cumsum(self.sample_weights), 0.0, 1.0)
        tol = 1e-12
        # F's interval at each sample: 1 - (S's interval), S = 1 - F
        s_lo, s_hi = self.interval(1.0 - cdf)
        f_lo, f_hi = 1.0 - s_hi, 1.0 - s_lo

        def first(reached: np.ndarray) -> float | None:
            hit = np.flatnonzero(reached)
            return float(self.values[hit[0]]) if hit.size else None

        value = first(cdf >= p - tol)
        lower = first(f_hi >= p - tol)
        return Quantile(float(p), float(value), float(lower if lower is not None else self.values[0]),
                        first(f_lo >= p - tol))


def exceedance(groups: Sequence[Sequence[float]], weights: Sequence[float] | None = None,
               confidence: float = 0.95) -> Exceedance:
    """The exceedance of a demand sampled in ``groups`` (one array per case) of ``weights``
    (None: one group, or equal weights); every value finite and >= 0 (module notes)."""
    groups = [np.asarray(g, dtype=float).ravel() for g in groups]
    if not groups or any(g.size == 0 for g in groups):
        raise InputError("samples", "every case needs at least one sample")
    if any(not np.all(np.isfinite(g)) for g in groups):
        raise InputError("samples", "must be finite (a realisation that never strikes is a demand of 0)")
    w = normalised_weights(np.ones(len(groups)) if weights is None else weights)
    if w.size != len(groups):
        raise InputError("weight", f"one per case: {len(groups)} case(s), {w.size} weight(s)")
    values = np.concatenate(groups)
    each = np.concatenate([np.full(g.size, wc / g.size) for g, wc in zip(groups, w)])
    order = np.argsort(values, kind="stable")
    n_eff = 1.0 / float(sum(wc * wc / g.size for g, wc in zip(groups, w)))
    return Exceedance(values[order], each[order], n_eff, int(values.size), float(confidence))
