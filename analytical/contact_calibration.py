"""The container's contact law calibrated on the study's 22 impacts, and its predicted scatter.

Like with like
--------------
The study's Table 2 MDOF row is not a set of contact pulses: it is the mean and standard
deviation, over 22 impacts, of half-sines fitted to the measured base shear with its MDOF
column loaded at the water level at the column's face. The model is compared through the
same procedure: every model strike (:func:`analytical.contact_law.column_impact`) gives the
base shear at the load cell, and :func:`analytical.contact_law.study_fit` fits it as the study
did. Table 2's means are then matched by weighted least squares, each weighted by its
standard error.

The strike population (:func:`strike_population`, stated assumptions)
----------------------------------------------------------------------
* speed: the study's, normal with mean 1.60 m/s and standard deviation 0.13 m/s (backed out
  of Table 2's ASCE rows, :data:`analytical.study.STUDY_IMPACT_VELOCITY_M_S`);
* water level at the face (the study's load point): 0.16-0.50 m with the study's mean 0.40 m,
  a Beta(2.4, 1) distribution on that range (a uniform one would have a mean of 0.33 m).
  The container's centre of mass floats 3.7 mm above the water line (draft 26.3 mm of 60 mm);
* where on its nose the container meets the column: uniformly over the nose's width
  (+-30 mm: a yawed nose meets the face with a corner, an off-centre one with the overlap's
  middle) and height (+-30 mm: pitch puts the contact on the top or bottom edge);
* the velocity's obliquity from the face's normal: uniform in +-15 degrees.

The geometry is a Latin hypercube sample of fixed seed (each of the four variables stratified
into ``count`` equal-probability bins), so the calibration's objective is a smooth,
deterministic function of the law's parameters.

A linear law makes the pulse, the base shear and the study's fit of it proportional to the
speed (peak and impulse) or independent of it (duration): each geometry is struck once, at
1 m/s, and the speed enters as a factor. The population's means are then the mean speed times
the geometry's mean, exactly; the scatter (:func:`scatter`) pairs drawn speeds with drawn
geometries.

The column
----------
Strikes and fits use :data:`STUDY_COLUMN`, the study's column with a rotational base spring
tuned to its measured 70 Hz (``base="calibrated"``), not the rigid-base cantilever (88.4 Hz):
the study's SDOF row of Table 1, read as a record, is fitted by the 70 Hz model as its MDOF row
(247 N, 4.48 ms, 0.706 N s at 0.50 m, 5.7 % rms), by the rigid one at no load height better
than 35 % rms (docs/fitting.md, :func:`analytical.synthetic.table1_column_models`).

Strikes from a flow (:func:`ensemble_population`)
------------------------------------------------
Instead of the assumed geometry, the first strikes of a transport ensemble: each its effective
mass along the normal (added mass and the contact's eccentricity in it), struck head-on at the
nose's centre at its contact height and obliquity, loaded at its water level at the face. The speed
stays the study's (Table 2's strikes were at its speeds).

Cost and starts
---------------
One evaluation (32 strikes) is 32 coupled integrations (:func:`analytical.contact_law.column_impact`,
about 0.1 s each) and 32 study fits, in closed form (:mod:`analytical.contact_studyfit`, about
0.1 s each against 2-3 s through :func:`analytical.contact_law.study_fit`; ``fast=False`` takes that
reference path). The column keeps its 160 elements: at 80 or 40 the evaluation costs the same (the
integration's cost is per step, not per mode) and one strike's fit may change basin (+1 % in the
mean peak at the shipped law). :func:`calibrate_multistart` fits from every one of :data:`STARTS`;
the best (least chi-square) is the law, the others show where the objective's valley (k and zeta
correlate at about -0.93) stops a start.

Standard errors
---------------
Table 2's mean over n = 22 has the standard error std / sqrt(22) (peak 13.4 N, duration 0.107
ms, impulse 0.047 N s). To it are added in quadrature the table's rounding (a uniform error of
half its last digit: 0.029 ms, 0.0029 N s) and, for peak and impulse (proportional to the mean
speed), the uncertainty of the mean speed: 0.13 / sqrt(22) with the rounding of the 0.49 N s it
is backed out of, 0.029 m/s or 1.8 %.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache, partial

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import beta as beta_dist
from scipy.stats import chi2 as chi2_dist
from scipy.stats import qmc

from analytical.added_mass import box_added_mass
from analytical.asce7 import ORIENTATION_CONTAINER
from analytical.column import Column
from analytical.contact_law import (
    STUDY_TABLE1_EVENT,
    STUDY_FIT_DT_S,
    STUDY_FIT_POST_S,
    STUDY_FIT_PRE_S,
    ContactLaw,
    column_impact,
    study_fit,
)
from analytical.contact_studyfit import HalfSineModes, fast_study_fit
from analytical.errors import InputError
from analytical.study import (
    STUDY_CONTAINER_SIZE_M,
    STUDY_DEBRIS_MASS_KG,
    STUDY_IMPACT_COUNT,
    STUDY_IMPACT_HEIGHTS_M,
    STUDY_IMPACT_VELOCITY_M_S,
    STUDY_TABLE2_MDOF,
)

__all__ = [
    "FIGURES",
    "LawFit",
    "MultiStart",
    "Population",
    "Scatter",
    "UnitFigures",
    "STUDY_COLUMN",
    "VELOCITY_HEAD_M",
    "STARTS",
    "calibrate",
    "calibrate_multistart",
    "ensemble_population",
    "half_sine_modes",
    "contact_drop",
    "lowered",
    "scatter",
    "strike_population",
    "table2_impulse_relation",
    "table2_standard_errors",
    "unit_figures",
]

FIGURES = ("peak_force_N", "duration_s", "impulse_Ns")

STUDY_COLUMN = Column(base="calibrated")
"""The column the calibration strikes and fits on (module notes): the study's, its base spring
tuned to the measured 70 Hz."""

#: Height of the container's centre of mass (= nose centre) above the water line (m).
_CM_ABOVE_WATER_M = STUDY_CONTAINER_SIZE_M[2] / 2.0 - box_added_mass(STUDY_CONTAINER_SIZE_M, STUDY_DEBRIS_MASS_KG).draft_m
#: Beta shape of the water level on [0.16, 0.50] m: mean 0.40 m as the study's.
_HEIGHT_BETA = (2.4, 1.0)
#: Half-range of the velocity's obliquity (degrees).
MAX_OBLIQUITY_DEG = 15.0


def table2_standard_errors(model_means: dict | None = None) -> dict[str, float]:
    """Standard error of each of Table 2's MDOF means (see the module docstring); with
    ``model_means`` the mean-speed term is taken relative to the model's value."""
    n = STUDY_IMPACT_COUNT
    u_mean, u_std = STUDY_IMPACT_VELOCITY_M_S
    # the speed's mean is backed out of 0.49 N s = 2 C_o m u (rounded to 0.01 N s)
    speed_se = math.hypot(u_std / math.sqrt(n), 0.01 / math.sqrt(12) / (2 * ORIENTATION_CONTAINER * STUDY_DEBRIS_MASS_KG))
    rounding = {"peak_force_N": 0.01 / math.sqrt(12), "duration_s": 1e-4 / math.sqrt(12),
                "impulse_Ns": 0.01 / math.sqrt(12)}
    out = {}
    for name in FIGURES:
        mean, std = STUDY_TABLE2_MDOF[name]
        value = (model_means or {}).get(name, mean)
        speed = value * speed_se / u_mean if name != "duration_s" else 0.0
        out[name] = math.sqrt((std / math.sqrt(n)) ** 2 + rounding[name] ** 2 + speed**2)
    return out


# ------------------------------------------------------------------------------ the population
@dataclass(frozen=True)
class Population:
    """Strike geometries: water level at the face (m), contact height on the column (m), the
    contact point's lateral and vertical offsets on the nose (m), the obliquity (degrees)."""

    water_level_m: np.ndarray
    contact_height_m: np.ndarray
    lateral_offset_m: np.ndarray
    vertical_offset_m: np.ndarray
    obliquity_deg: np.ndarray
    effective_mass_kg: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.water_level_m)

    def body(self, i: int) -> dict:
        """:func:`analytical.contact_law.column_impact`'s body keywords of strike ``i``: none (the
        container and its added mass) or, with effective masses given, a body of that mass and no
        added mass (struck at the nose's centre, its normal mass is that mass)."""
        if self.effective_mass_kg is None:
            return {}
        return {"mass_kg": float(self.effective_mass_kg[i]), "added_mass_coefficient": 0.0}


def strike_population(count: int = 32, seed: int = 2019, geometry: bool = True) -> Population:
    """``count`` strike geometries, a Latin hypercube sample of fixed seed (module docstring); with
    ``geometry=False`` every strike is head-on at the nose's centre (the water levels only)."""
    if count < 2:
        raise InputError("count", f"must be >= 2, got {count}")
    u = qmc.LatinHypercube(d=4, seed=seed).random(count)
    lo, hi, _ = STUDY_IMPACT_HEIGHTS_M
    water = lo + (hi - lo) * beta_dist.ppf(u[:, 0], *_HEIGHT_BETA)
    width, height = STUDY_CONTAINER_SIZE_M[1], STUDY_CONTAINER_SIZE_M[2]
    scale = 1.0 if geometry else 0.0
    lateral = scale * width * (u[:, 1] - 0.5)
    vertical = scale * height * (u[:, 2] - 0.5)
    obliquity = scale * MAX_OBLIQUITY_DEG * (2.0 * u[:, 3] - 1.0)
    return Population(water, water + _CM_ABOVE_WATER_M + vertical, lateral, vertical, obliquity)


def ensemble_population(contact_height_m, water_level_m, effective_mass_kg, obliquity_deg=None,
                        column: Column | None = None) -> Population:
    """Strikes as a flow delivered them (a transport ensemble's first strikes): each a body of
    its effective mass along the normal (added mass included) meeting the column head-on at the
    nose's centre at its contact height, at its obliquity (default 0), loaded by the study's fit
    at its water level at the face (where that is NaN: at the contact height, as the ensemble's
    own fit). Heights in m above the column's base, within the column."""
    column = STUDY_COLUMN if column is None else column
    contact = np.asarray(contact_height_m, dtype=float)
    n = contact.size
    level = np.asarray(water_level_m, dtype=float)
    mass = np.asarray(effective_mass_kg, dtype=float)
    angle = np.zeros(n) if obliquity_deg is None else np.asarray(obliquity_deg, dtype=float)
    if n < 2 or contact.ndim != 1 or any(a.shape != (n,) for a in (level, mass, angle)):
        raise InputError("ensemble", f"needs at least 2 strikes, each with a contact height, water level and "
                                     f"effective mass, got {contact.shape}, {level.shape}, {mass.shape}")
    level = np.where(np.isfinite(level), level, contact)
    for name, values in (("impact_height_m", contact), ("face_water_level_m", level)):
        if not np.all(np.isfinite(values) & (values > 0.0) & (values <= column.height_m)):
            raise InputError(name, f"must lie on the column, 0 < height <= {column.height_m} m")
    if not np.all(np.isfinite(mass) & (mass > 0.0)):
        raise InputError("effective_mass_kg", "must be positive and finite")
    if not np.all(np.isfinite(angle) & (np.abs(angle) < 90.0)):
        raise InputError("obliquity_deg", "must be within (-90, 90) degrees")
    zero = np.zeros(n)
    return Population(level, contact, zero, zero.copy(), angle, mass)


@dataclass(frozen=True)
class UnitFigures:
    """Per-strike figures at 1 m/s: the study's fit of the base shear (``fit_*``: peak and
    impulse per m/s, duration), the contact pulse itself (``pulse_*``), its restitution and
    effective mass."""

    law: ContactLaw
    population: Population
    fit_peak_force_N: np.ndarray
    fit_duration_s: np.ndarray
    fit_impulse_Ns: np.ndarray
    fit_start_s: np.ndarray
    pulse_peak_force_N: np.ndarray
    pulse_duration_s: np.ndarray
    pulse_impulse_Ns: np.ndarray
    restitution: np.ndarray
    effective_mass_kg: np.ndarray

    def means(self, mean_speed_m_s: float = STUDY_IMPACT_VELOCITY_M_S[0]) -> dict[str, float]:
        """The population's mean fitted peak, duration and impulse at this mean speed."""
        return {"peak_force_N": mean_speed_m_s * float(np.mean(self.fit_peak_force_N)),
                "duration_s": float(np.mean(self.fit_duration_s)),
                "impulse_Ns": mean_speed_m_s * float(np.mean(self.fit_impulse_Ns))}


def unit_figures(law: ContactLaw, population: Population, column: Column | None = None,
                 fast: bool = True) -> UnitFigures:
    """Strike the column at 1 m/s in each of the population's geometries and fit each base
    shear with the study's procedure (on :data:`STUDY_COLUMN` by default). ``fast``: the fit
    in closed form (:func:`analytical.contact_studyfit.fast_study_fit`, the same fit to about
    1e-5); False: :func:`analytical.contact_law.study_fit` itself, the reference."""
    column = STUDY_COLUMN if column is None else column
    t = np.arange(-STUDY_FIT_PRE_S, STUDY_FIT_POST_S, STUDY_FIT_DT_S)
    rows = []
    for i in range(len(population)):
        level = float(population.water_level_m[i])
        r = column_impact(law, 1.0, float(population.contact_height_m[i]), column=column,
                          obliquity_deg=float(population.obliquity_deg[i]),
                          lateral_offset_m=float(population.lateral_offset_m[i]),
                          vertical_offset_m=float(population.vertical_offset_m[i]), **population.body(i))
        if fast:  # the record study_fit hands to the fit: the base shear on its grid
            shear = r.base_shear
            y = np.interp(t, shear.time_s, shear.response_N, left=0.0, right=float(shear.response_N[-1]))
            f = fast_study_fit(t, y, half_sine_modes(column, level))
        else:
            f = study_fit(r, level, column)
        rows.append((f.magnitude_N, f.duration_s, f.impulse_Ns, f.start_s, r.peak_force_N, r.duration_s,
                     r.impulse_Ns, r.restitution, r.effective_mass_kg))
    a = np.array(rows)
    return UnitFigures(law, population, *(a[:, j] for j in range(a.shape[1])))


@lru_cache(maxsize=512)
def half_sine_modes(column: Column, level_m: float) -> HalfSineModes:
    """The fit's closed-form column at one load height (cached: a population's heights recur at
    every trial law)."""
    return HalfSineModes(column, level_m)


#: The velocity head at the study's mean strike speed, u^2 / (2 g) at 1.60 m/s (m): how far the water
#: stands up at a stagnation point above the approaching free surface (Bernoulli), and so about how far
#: a container afloat in the approaching flow meets the column below the water level at its face.
VELOCITY_HEAD_M = STUDY_IMPACT_VELOCITY_M_S[0] ** 2 / (2.0 * 9.80665)


def lowered(population: Population, drop_m: float) -> Population:
    """The same strikes with every contact ``drop_m`` lower on the column and the load point (the
    water level at the face) where it was: a container carried afloat meets the column at the
    approaching flow's surface, below the run-up at the face. No contact goes below half the
    container's height (a container on the bed)."""
    drop = float(drop_m)
    if not math.isfinite(drop) or drop < 0.0:
        raise InputError("drop_m", f"must be >= 0 m, got {drop_m}")
    floor = STUDY_CONTAINER_SIZE_M[2] / 2.0
    contact = np.maximum(population.contact_height_m - drop, floor)
    return Population(population.water_level_m, contact, population.lateral_offset_m,
                      population.vertical_offset_m, population.obliquity_deg, population.effective_mass_kg)


def contact_drop(law: ContactLaw, population: Population, drops_m=(0.0, 0.05, 0.10, VELOCITY_HEAD_M),
                 column: Column | None = None, level: UnitFigures | None = None) -> list[dict]:
    """What the study's fit of ``law``'s strikes reads when each contact lies ``drop`` below the
    load point (:func:`lowered`): per drop, the population's means at 1.60 m/s, their z-scores
    against Table 2 and the chi-square of the three (the law held, so 3 degrees of freedom).
    ``level``: the same law's figures over ``population`` already struck (used for a drop of 0)."""
    targets = {k: STUDY_TABLE2_MDOF[k][0] for k in FIGURES}
    rows = []
    for drop in drops_m:
        figures = (level if level is not None and drop == 0.0
                   else unit_figures(law, lowered(population, drop), column))
        means = figures.means()
        se = table2_standard_errors(means)
        z = {k: (means[k] - targets[k]) / se[k] for k in FIGURES}
        chi2 = float(sum(v * v for v in z.values()))
        rows.append({"drop_m": float(drop), "means": means, "z": z, "chi2": chi2,
                     "p_value": float(chi2_dist.sf(chi2, len(FIGURES))),
                     "duration_std_s": float(np.std(figures.fit_duration_s, ddof=1))})
    return rows


# ------------------------------------------------------------------------------ the fit
#: The parameter box of the fit: ``k`` (N/m) and ``zeta``.
STIFFNESS_BOUNDS_N_M = (1.0e4, 1.0e6)
DAMPING_BOUNDS = (0.0, 0.9)
#: The multi-start's starts (k in N/m, zeta): spread over the box's middle, ``k`` over a factor of
#: 15 and ``zeta`` over 0.1-0.8, each ``k`` with another ``zeta`` (none at the shipped law).
STARTS = ((2.0e4, 0.5), (3.5e4, 0.1), (6.0e4, 0.8), (1.0e5, 0.3), (1.8e5, 0.65), (3.0e5, 0.2))


@dataclass(frozen=True)
class LawFit:
    """A law fitted to Table 2's means from ``start``: its parameters and their standard errors
    (from the whitened residuals' Jacobian in ``(ln k, zeta)``, whose singular values are
    ``singular_values``), the chi-square and its degrees of freedom, the fitted means and their
    z-scores against Table 2 (``(model - study) / SE``), the optimiser's verdict."""

    law: ContactLaw
    free: tuple[str, ...]
    stiffness_se_N_m: float
    damping_ratio_se: float
    correlation: float
    chi2: float
    dof: int
    p_value: float
    means: dict
    standard_errors: dict
    z: dict
    evaluations: int
    figures: UnitFigures
    start: tuple = ()
    singular_values: tuple = ()
    converged: bool = True

    def to_dict(self) -> dict:
        return {"law": self.law.to_dict(), "free": list(self.free), "stiffness_se_N_m": self.stiffness_se_N_m,
                "damping_ratio_se": self.damping_ratio_se, "correlation": self.correlation, "chi2": self.chi2,
                "dof": self.dof, "p_value": self.p_value, "means": self.means,
                "table2_means": {k: STUDY_TABLE2_MDOF[k][0] for k in FIGURES},
                "standard_errors": self.standard_errors, "z": self.z, "evaluations": self.evaluations,
                "strikes": len(self.figures.population), "start": list(self.start),
                "singular_values": list(self.singular_values), "converged": self.converged}


def calibrate(population: Population | None = None, column: Column | None = None, damped: bool = True,
              start: tuple[float, float] = (7.0e4, 0.3), fast: bool = True, max_nfev: int = 15) -> LawFit:
    """Fit ``k`` (and ``zeta`` when ``damped``) so that the population's mean study-fitted
    peak, duration and impulse at the mean speed match Table 2's: least squares on the three
    ``(model - study) / SE`` (the model's speed term taken at the model's value), from ``start``.
    ``fast``: :func:`unit_figures`' closed-form fit (False: the reference)."""
    population = strike_population() if population is None else population
    column = STUDY_COLUMN if column is None else column
    targets = {k: STUDY_TABLE2_MDOF[k][0] for k in FIGURES}
    cache: dict[tuple, UnitFigures] = {}

    def figures(x) -> UnitFigures:
        key = tuple(np.round(x, 12))
        if key not in cache:
            zeta = float(x[1]) if damped else 0.0
            cache[key] = unit_figures(ContactLaw(math.exp(x[0]), max(zeta, 0.0), "fit"), population, column, fast)
        return cache[key]

    def residual(x):
        means = figures(x).means()
        se = table2_standard_errors(means)
        return np.array([(means[k] - targets[k]) / se[k] for k in FIGURES])

    lo = [math.log(STIFFNESS_BOUNDS_N_M[0])] + ([DAMPING_BOUNDS[0]] if damped else [])
    hi = [math.log(STIFFNESS_BOUNDS_N_M[1])] + ([DAMPING_BOUNDS[1]] if damped else [])
    x0 = np.clip([math.log(start[0])] + ([start[1]] if damped else []), lo, hi)
    # Differences of 1 % in k and 0.02 in zeta, a fifth of their standard errors or less: a strike
    # whose fit changes basin moves a mean by a step, which a finer difference reads as a slope.
    sol = least_squares(residual, x0, bounds=(lo, hi), diff_step=[1e-3] + ([2e-2] if damped else []),
                        x_scale=[0.1] + ([0.05] if damped else []), xtol=1e-3, ftol=1e-4, max_nfev=max_nfev)
    x = sol.x
    k = math.exp(x[0])
    zeta = float(x[1]) if damped else 0.0
    jac = sol.jac
    cov = np.linalg.pinv(jac.T @ jac)
    k_se = k * math.sqrt(cov[0, 0])
    z_se = math.sqrt(cov[1, 1]) if damped else 0.0
    corr = float(cov[0, 1] / math.sqrt(cov[0, 0] * cov[1, 1])) if damped else 0.0
    fig = figures(x)
    means = fig.means()
    se = table2_standard_errors(means)
    z = {name: (means[name] - targets[name]) / se[name] for name in FIGURES}
    chi2 = float(sum(v * v for v in z.values()))
    dof = len(FIGURES) - len(x)
    law = ContactLaw(k, zeta, "calibrated")
    return LawFit(law, ("stiffness_N_m", "damping_ratio") if damped else ("stiffness_N_m",), k_se, z_se, corr,
                  chi2, dof, float(chi2_dist.sf(chi2, dof)), means, se, z, len(cache), fig,
                  tuple(float(v) for v in start[: len(x)]),
                  tuple(float(v) for v in np.linalg.svd(jac, compute_uv=False)), bool(sol.status > 0))


@dataclass(frozen=True)
class MultiStart:
    """The damped law fitted from every start (:data:`STARTS`) and the best of them (least
    chi-square), and what Table 2 constrains (:meth:`constrained`)."""

    fits: tuple[LawFit, ...]

    @property
    def best(self) -> LawFit:
        return min(self.fits, key=lambda f: f.chi2)

    def constrained(self, floor: float = 1.0) -> int:
        """How many independent combinations of the parameters Table 2's three means fix: the
        whitened Jacobian's singular values above ``floor`` (a combination fixed to better than
        one unit of ``ln k`` or ``zeta`` by one standard error of the means)."""
        return int(sum(v > floor for v in self.best.singular_values))

    def to_dict(self) -> dict:
        best = self.best
        return {"starts": [{"start": list(f.start), "stiffness_N_m": f.law.stiffness_N_m,
                            "damping_ratio": f.law.damping_ratio, "chi2": f.chi2, "evaluations": f.evaluations,
                            "converged": f.converged} for f in self.fits],
                "best": best.to_dict(), "constrained": self.constrained(),
                "table2_impulse_from_peak_and_duration_Ns": table2_impulse_relation()}


def table2_impulse_relation() -> float:
    """``(2 / pi) x peak x duration`` of Table 2's means (N s): what its mean impulse would be if
    every fitted half-sine had the mean peak and duration; against its 0.52 N s it says how much
    of the third mean is a number of its own."""
    return 2.0 / math.pi * STUDY_TABLE2_MDOF["peak_force_N"][0] * STUDY_TABLE2_MDOF["duration_s"][0]


def calibrate_multistart(population: Population | None = None, column: Column | None = None,
                         starts=STARTS, mapper=map, max_nfev: int = 15) -> MultiStart:
    """:func:`calibrate` (damped) from each of ``starts``; ``mapper`` maps a one-argument function
    over them (``map``, or a process pool's: the starts are independent)."""
    population = strike_population() if population is None else population
    column = STUDY_COLUMN if column is None else column
    fit = partial(calibrate, population, column, True, fast=True, max_nfev=max_nfev)
    return MultiStart(tuple(mapper(fit, [tuple(s) for s in starts])))


# ------------------------------------------------------------------------------ the scatter
@dataclass(frozen=True)
class Scatter:
    """The law's predicted distribution over the strike population (``draws`` speed-geometry
    pairs) and Table 1's event within it."""

    means: dict
    stds: dict
    quantiles: dict
    table1_percentiles: dict
    table1_percentiles_population: dict
    draws: int

    def to_dict(self) -> dict:
        return {"means": self.means, "stds": self.stds, "quantiles": self.quantiles,
                "table2_stds": {k: STUDY_TABLE2_MDOF[k][1] for k in FIGURES},
                "table1_percentiles_at_its_speed": self.table1_percentiles,
                "table1_percentiles_in_population": self.table1_percentiles_population, "draws": self.draws}


def scatter(figures: UnitFigures, draws: int = 200_000, seed: int = 22) -> Scatter:
    """Pair speeds drawn from N(1.60, 0.13) m/s with geometries drawn from ``figures``'
    population (fixed seed): the predicted means, standard deviations and 5/50/95 %
    quantiles of the study-fitted peak, duration and impulse, and the percentiles of Table 1's
    event (its peak, duration, impulse) among the population's strikes at its own speed,
    1.50 m/s (the geometry varying), and in the whole population."""
    rng = np.random.default_rng(seed)
    speeds = rng.normal(*STUDY_IMPACT_VELOCITY_M_S, size=draws)
    pick = rng.integers(0, len(figures.population), size=draws)
    unit = {"peak_force_N": figures.fit_peak_force_N, "duration_s": figures.fit_duration_s,
            "impulse_Ns": figures.fit_impulse_Ns}
    values = {k: (speeds if k != "duration_s" else 1.0) * unit[k][pick] for k in FIGURES}
    e = STUDY_TABLE1_EVENT
    event = {"peak_force_N": e.peak_force_N, "duration_s": e.duration_s, "impulse_Ns": e.impulse_Ns}
    at_speed = {k: (e.velocity_m_s if k != "duration_s" else 1.0) * unit[k] for k in FIGURES}
    return Scatter(
        means={k: float(np.mean(v)) for k, v in values.items()},
        stds={k: float(np.std(v, ddof=1)) for k, v in values.items()},
        quantiles={k: [float(q) for q in np.quantile(v, (0.05, 0.5, 0.95))] for k, v in values.items()},
        table1_percentiles={k: float(100.0 * np.mean(at_speed[k] < event[k])) for k in FIGURES},
        table1_percentiles_population={k: float(100.0 * np.mean(values[k] < event[k])) for k in FIGURES},
        draws=draws,
    )
