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
  of Table 2's ASCE rows, :data:`analytical.contact_law.SEED_IMPACT_VELOCITY_M_S`);
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

import numpy as np
from scipy.optimize import least_squares
from scipy.stats import beta as beta_dist
from scipy.stats import chi2 as chi2_dist
from scipy.stats import qmc

from analytical.added_mass import box_added_mass
from analytical.asce7 import ORIENTATION_CONTAINER, SEED_DEBRIS_MASS_KG
from analytical.column import Column
from analytical.contact_law import (
    SEED_CONTAINER_SIZE_M,
    SEED_IMPACT_HEIGHTS_M,
    SEED_IMPACT_VELOCITY_M_S,
    SEED_TABLE1_EVENT,
    SEED_TABLE2_MDOF,
    ContactLaw,
    column_impact,
    study_fit,
)
from analytical.errors import InputError

__all__ = [
    "FIGURES",
    "SEED_IMPACT_COUNT",
    "LawFit",
    "Population",
    "Scatter",
    "UnitFigures",
    "STUDY_COLUMN",
    "VELOCITY_HEAD_M",
    "calibrate",
    "contact_drop",
    "lowered",
    "scatter",
    "strike_population",
    "table2_standard_errors",
    "unit_figures",
]

SEED_IMPACT_COUNT = 22
"""The number of impacts behind Table 2."""

FIGURES = ("peak_force_N", "duration_s", "impulse_Ns")

STUDY_COLUMN = Column(base="calibrated")
"""The column the calibration strikes and fits on (module notes): the study's, its base spring
tuned to the measured 70 Hz."""

#: Height of the container's centre of mass (= nose centre) above the water line (m).
_CM_ABOVE_WATER_M = SEED_CONTAINER_SIZE_M[2] / 2.0 - box_added_mass(SEED_CONTAINER_SIZE_M, SEED_DEBRIS_MASS_KG).draft_m
#: Beta shape of the water level on [0.16, 0.50] m: mean 0.40 m as the study's.
_HEIGHT_BETA = (2.4, 1.0)
#: Half-range of the velocity's obliquity (degrees).
MAX_OBLIQUITY_DEG = 15.0


def table2_standard_errors(model_means: dict | None = None) -> dict[str, float]:
    """Standard error of each of Table 2's MDOF means (see the module docstring); with
    ``model_means`` the mean-speed term is taken relative to the model's value."""
    n = SEED_IMPACT_COUNT
    u_mean, u_std = SEED_IMPACT_VELOCITY_M_S
    # the speed's mean is backed out of 0.49 N s = 2 C_o m u (rounded to 0.01 N s)
    speed_se = math.hypot(u_std / math.sqrt(n), 0.01 / math.sqrt(12) / (2 * ORIENTATION_CONTAINER * SEED_DEBRIS_MASS_KG))
    rounding = {"peak_force_N": 0.01 / math.sqrt(12), "duration_s": 1e-4 / math.sqrt(12),
                "impulse_Ns": 0.01 / math.sqrt(12)}
    out = {}
    for name in FIGURES:
        mean, std = SEED_TABLE2_MDOF[name]
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

    def __len__(self) -> int:
        return len(self.water_level_m)


def strike_population(count: int = 32, seed: int = 2019, geometry: bool = True) -> Population:
    """``count`` strike geometries, a Latin hypercube sample of fixed seed (module docstring); with
    ``geometry=False`` every strike is head-on at the nose's centre (the water levels only)."""
    if count < 2:
        raise InputError("count", f"must be >= 2, got {count}")
    u = qmc.LatinHypercube(d=4, seed=seed).random(count)
    lo, hi, _ = SEED_IMPACT_HEIGHTS_M
    water = lo + (hi - lo) * beta_dist.ppf(u[:, 0], *_HEIGHT_BETA)
    width, height = SEED_CONTAINER_SIZE_M[1], SEED_CONTAINER_SIZE_M[2]
    scale = 1.0 if geometry else 0.0
    lateral = scale * width * (u[:, 1] - 0.5)
    vertical = scale * height * (u[:, 2] - 0.5)
    obliquity = scale * MAX_OBLIQUITY_DEG * (2.0 * u[:, 3] - 1.0)
    return Population(water, water + _CM_ABOVE_WATER_M + vertical, lateral, vertical, obliquity)


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

    def means(self, mean_speed_m_s: float = SEED_IMPACT_VELOCITY_M_S[0]) -> dict[str, float]:
        """The population's mean fitted peak, duration and impulse at this mean speed."""
        return {"peak_force_N": mean_speed_m_s * float(np.mean(self.fit_peak_force_N)),
                "duration_s": float(np.mean(self.fit_duration_s)),
                "impulse_Ns": mean_speed_m_s * float(np.mean(self.fit_impulse_Ns))}


def unit_figures(law: ContactLaw, population: Population, column: Column | None = None) -> UnitFigures:
    """Strike the column at 1 m/s in each of the population's geometries and fit each base
    shear with the study's procedure (on :data:`STUDY_COLUMN` by default)."""
    column = STUDY_COLUMN if column is None else column
    rows = []
    for i in range(len(population)):
        r = column_impact(law, 1.0, float(population.contact_height_m[i]), column=column,
                          obliquity_deg=float(population.obliquity_deg[i]),
                          lateral_offset_m=float(population.lateral_offset_m[i]),
                          vertical_offset_m=float(population.vertical_offset_m[i]))
        f = study_fit(r, float(population.water_level_m[i]), column)
        rows.append((f.magnitude_N, f.duration_s, f.impulse_Ns, f.start_s, r.peak_force_N, r.duration_s,
                     r.impulse_Ns, r.restitution, r.effective_mass_kg))
    a = np.array(rows)
    return UnitFigures(law, population, *(a[:, j] for j in range(a.shape[1])))


#: The velocity head at the study's mean strike speed, u^2 / (2 g) at 1.60 m/s (m): how far the water
#: stands up at a stagnation point above the approaching free surface (Bernoulli), and so about how far
#: a container afloat in the approaching flow meets the column below the water level at its face.
VELOCITY_HEAD_M = SEED_IMPACT_VELOCITY_M_S[0] ** 2 / (2.0 * 9.80665)


def lowered(population: Population, drop_m: float) -> Population:
    """The same strikes with every contact ``drop_m`` lower on the column and the load point (the
    water level at the face) where it was: a container carried afloat meets the column at the
    approaching flow's surface, below the run-up at the face. No contact goes below half the
    container's height (a container on the bed)."""
    drop = float(drop_m)
    if not math.isfinite(drop) or drop < 0.0:
        raise InputError("drop_m", f"must be >= 0 m, got {drop_m}")
    floor = SEED_CONTAINER_SIZE_M[2] / 2.0
    contact = np.maximum(population.contact_height_m - drop, floor)
    return Population(population.water_level_m, contact, population.lateral_offset_m,
                      population.vertical_offset_m, population.obliquity_deg)


def contact_drop(law: ContactLaw, population: Population, drops_m=(0.0, 0.05, 0.10, VELOCITY_HEAD_M),
                 column: Column | None = None, level: UnitFigures | None = None) -> list[dict]:
    """What the study's fit of ``law``'s strikes reads when each contact lies ``drop`` below the
    load point (:func:`lowered`): per drop, the population's means at 1.60 m/s, their z-scores
    against Table 2 and the chi-square of the three (the law held, so 3 degrees of freedom).
    ``level``: the same law's figures over ``population`` already struck (used for a drop of 0)."""
    targets = {k: SEED_TABLE2_MDOF[k][0] for k in FIGURES}
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
@dataclass(frozen=True)
class LawFit:
    """A law fitted to Table 2's means: its parameters and their standard errors (from the
    whitened residuals' Jacobian), the chi-square and its degrees of freedom, the fitted
    means and their z-scores against Table 2 (``(model - study) / SE``)."""

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

    def to_dict(self) -> dict:
        return {"law": self.law.to_dict(), "free": list(self.free), "stiffness_se_N_m": self.stiffness_se_N_m,
                "damping_ratio_se": self.damping_ratio_se, "correlation": self.correlation, "chi2": self.chi2,
                "dof": self.dof, "p_value": self.p_value, "means": self.means,
                "table2_means": {k: SEED_TABLE2_MDOF[k][0] for k in FIGURES},
                "standard_errors": self.standard_errors, "z": self.z, "evaluations": self.evaluations,
                "strikes": len(self.figures.population)}


def calibrate(population: Population | None = None, column: Column | None = None, damped: bool = True,
              start: tuple[float, float] = (7.0e4, 0.3)) -> LawFit:
    """Fit ``k`` (and ``zeta`` when ``damped``) so that the population's mean study-fitted
    peak, duration and impulse at the mean speed match Table 2's: least squares on the three
    ``(model - study) / SE`` (the model's speed term taken at the model's value)."""
    population = strike_population() if population is None else population
    column = STUDY_COLUMN if column is None else column
    targets = {k: SEED_TABLE2_MDOF[k][0] for k in FIGURES}
    cache: dict[tuple, UnitFigures] = {}

    def figures(x) -> UnitFigures:
        key = tuple(np.round(x, 12))
        if key not in cache:
            zeta = float(x[1]) if damped else 0.0
            cache[key] = unit_figures(ContactLaw(math.exp(x[0]), max(zeta, 0.0), "fit"), population, column)
        return cache[key]

    def residual(x):
        means = figures(x).means()
        se = table2_standard_errors(means)
        return np.array([(means[k] - targets[k]) / se[k] for k in FIGURES])

    x0 = [math.log(start[0])] + ([start[1]] if damped else [])
    lo = [math.log(1e4)] + ([0.0] if damped else [])
    hi = [math.log(1e6)] + ([0.9] if damped else [])
    sol = least_squares(residual, x0, bounds=(lo, hi), diff_step=1e-3, x_scale=[0.1] + ([0.05] if damped else []),
                        xtol=1e-4, ftol=1e-6, max_nfev=40)
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
                  chi2, dof, float(chi2_dist.sf(chi2, dof)), means, se, z, len(cache), fig)


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
                "table2_stds": {k: SEED_TABLE2_MDOF[k][1] for k in FIGURES},
                "table1_percentiles_at_its_speed": self.table1_percentiles,
                "table1_percentiles_in_population": self.table1_percentiles_population, "draws": self.draws}


def scatter(figures: UnitFigures, draws: int = 200_000, seed: int = 22) -> Scatter:
    """Pair speeds drawn from N(1.60, 0.13) m/s with geometries drawn from ``figures``'
    population (fixed seed): the predicted means, standard deviations and 5/50/95 %
    quantiles of the study-fitted peak, duration and impulse, and the percentiles of Table 1's
    event (its peak, duration, impulse) among the population's strikes at its own speed,
    1.50 m/s (the geometry varying), and in the whole population."""
    rng = np.random.default_rng(seed)
    speeds = rng.normal(*SEED_IMPACT_VELOCITY_M_S, size=draws)
    pick = rng.integers(0, len(figures.population), size=draws)
    unit = {"peak_force_N": figures.fit_peak_force_N, "duration_s": figures.fit_duration_s,
            "impulse_Ns": figures.fit_impulse_Ns}
    values = {k: (speeds if k != "duration_s" else 1.0) * unit[k][pick] for k in FIGURES}
    e = SEED_TABLE1_EVENT
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
