"""The contact law of a debris body: how soft it is and how much energy a strike loses.

A contact law is a compression-only spring ``k`` with a dashpot ``c = 2 zeta sqrt(k m_eff)``
between the debris and what it strikes. :func:`analytical.impact.impact` puts it in series
with the column's MDOF model (or against a rigid wall, or between two bodies); the force
history, the rebound and the base shear come out of that integration.

Two laws ship:

* ``container`` (the default, :data:`CONTAINER`): calibrated on the one impact the study
  reports in full, its Table 1 event (a 0.236 kg 1:40 container at 1.50 m/s, the column
  struck 0.40 m up; the MDOF fit of the measured base shear gave a half-sine of 236.93 N
  over 4.7 ms, 0.71 N s). :func:`calibrate` fits ``k`` and ``zeta`` so that the coupled
  debris-spring-column model reproduces that pulse's magnitude, duration and impulse. The
  calibrated stiffness, about 1.1e5 N/m, is about 30 times softer than the rigid debris
  stiffness ``k_d`` of the study's ASCE 7-22 rows: the container's thin polyethylene wall
  yields, a rigid box would not. The calibrated damping is zero: the event's impulse,
  0.71 N s, is 2.0 times the container's momentum (0.354 N s), the signature of an elastic
  strike; no energy loss can be calibrated from it.
* ``asce7_kd`` (:data:`ASCE7_KD`): ``k_d`` = 3.0e6 N/m, undamped: ASCE 7-22's rigid debris
  (Haehnel & Daly's model). It gives 0.9 ms pulses of 1,100-1,500 N: an upper bound.

Either can be given another stiffness, a damping ratio, or a coefficient of restitution
(turned into the damping ratio that gives it against a rigid wall, :func:`damping_for_restitution`).

The held-out check (:func:`held_out`, docs/contact-law.md) drives the calibrated law with the
22 impact velocities the study's Table 2 implies (1.60 +- 0.13 m/s) at heights spread over its
0.16-0.50 m and compares the mean and spread of magnitude, duration, impulse and base shear
with the study's MDOF row (171 +- 63 N, 4.7 +- 0.5 ms, 0.52 +- 0.22 N s).

Units: N, m, s, kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq, least_squares
from scipy.stats import norm

from analytical.asce7 import SEED_DEBRIS_MASS_KG, SEED_DEBRIS_STIFFNESS_N_M
from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive
from analytical.impact import (
    DEFAULT_FRICTION_COEFFICIENT,
    Body,
    ColumnTarget,
    ImpactResult,
    impact,
    inverse_inertia_tensor,
)

__all__ = [
    "ASCE7_KD",
    "CONTAINER",
    "LAWS",
    "SEED_CONTAINER_SIZE_M",
    "SEED_CONTAINER_WALL_M",
    "SEED_IMPACT_HEIGHTS_M",
    "SEED_IMPACT_VELOCITY_M_S",
    "SEED_TABLE1_EVENT",
    "SEED_TABLE2_MDOF",
    "Calibration",
    "ContactLaw",
    "HeldOut",
    "ImpactEvent",
    "box_inertia",
    "calibrate",
    "column_impact",
    "contact_law",
    "damping_for_restitution",
    "held_out",
    "wall_restitution",
]


# ------------------------------------------------------------------------------ the study's figures
@dataclass(frozen=True)
class ImpactEvent:
    """One measured impact and the pulse fitted to it (half-sine magnitude, duration, impulse)."""

    velocity_m_s: float
    height_m: float
    mass_kg: float
    peak_force_N: float
    duration_s: float
    impulse_Ns: float


SEED_TABLE1_EVENT = ImpactEvent(
    velocity_m_s=1.50, height_m=0.40, mass_kg=SEED_DEBRIS_MASS_KG,
    peak_force_N=236.93, duration_s=0.0047, impulse_Ns=0.71,
)
"""The study's Table 1 event: measured velocity 1.50 m/s, MDOF-fitted half-sine (its Fig. 4).
The height is the mean of its 22 impacts (0.40 m); the event's own height is not given."""

SEED_TABLE2_MDOF = {"peak_force_N": (171.07, 62.91), "duration_s": (0.0047, 0.0005), "impulse_Ns": (0.52, 0.22)}
"""The study's Table 2, MDOF row: (mean, standard deviation) over its 22 impacts."""

SEED_IMPACT_VELOCITY_M_S = (1.60, 0.13)
"""Mean and standard deviation of the 22 impact velocities, backed out of Table 2's ASCE rows
(impulse = 2 C_o m u: 0.49 +- 0.04 N s with C_o = 0.65, m = 0.236 kg)."""

SEED_IMPACT_HEIGHTS_M = (0.16, 0.50, 0.40)
"""Lowest, highest and mean impact height on the column (the water surface at its face)."""

SEED_CONTAINER_SIZE_M = (0.15, 0.06, 0.06)
"""The 1:40 20-ft container: length, width, height."""

SEED_CONTAINER_WALL_M = 0.005
"""Its polyethylene wall thickness."""


# ------------------------------------------------------------------------------ the law
@dataclass(frozen=True)
class ContactLaw:
    """A contact spring ``stiffness_N_m`` with a dashpot of ``damping_ratio`` (fraction of
    ``2 sqrt(k m_eff)``); ``name`` says where it comes from."""

    stiffness_N_m: float
    damping_ratio: float = 0.0
    name: str = "custom"

    def __post_init__(self):
        object.__setattr__(self, "stiffness_N_m", require_positive("contact.stiffness_N_m", self.stiffness_N_m))
        zeta = require_finite("contact.damping_ratio", self.damping_ratio)
        if not 0.0 <= zeta < 1.0:
            raise InputError("contact.damping_ratio", f"must be in [0, 1), got {self.damping_ratio!r}")
        object.__setattr__(self, "damping_ratio", zeta)

    @property
    def wall_restitution(self) -> float:
        """Coefficient of restitution of this law against a rigid wall (mass-independent)."""
        return wall_restitution(self.damping_ratio)

    def options(self) -> dict:
        """Keyword arguments for :func:`analytical.impact.impact` / ``pair_impact``."""
        return {"stiffness_N_m": self.stiffness_N_m, "damping_ratio": self.damping_ratio}

    def pair(self) -> "ContactLaw":
        """Two such bodies striking each other: their two springs in series (``k / 2``)."""
        return replace(self, stiffness_N_m=self.stiffness_N_m / 2.0, name=f"{self.name}, body-body")

    def to_dict(self) -> dict:
        return {"law": self.name, "stiffness_N_m": self.stiffness_N_m, "damping_ratio": self.damping_ratio,
                "wall_restitution": self.wall_restitution}


def wall_restitution(damping_ratio: float) -> float:
    """Restitution of a linear spring-dashpot striking a rigid wall, the contact ending when
    the force ``k x + c x'`` returns to zero (the dashpot cannot pull).

    With ``w0 = sqrt(k/m)``, ``b = zeta w0``, ``w = w0 sqrt(1 - zeta^2)``:
    ``x = (v0/w) e^(-b t) sin(w t)``; the force vanishes at ``w t_s = pi - atan2(2 b w, w0^2 - 2 b^2)``
    and ``e = -x'(t_s) / v0``. Undamped, ``e = 1``.
    """
    zeta = require_finite("damping_ratio", damping_ratio)
    if not 0.0 <= zeta < 1.0:
        raise InputError("damping_ratio", f"must be in [0, 1), got {damping_ratio!r}")
    wd = math.sqrt(1.0 - zeta * zeta)  # w / w0
    phase = math.pi - math.atan2(2.0 * zeta * wd, 1.0 - 2.0 * zeta * zeta)  # w t_s
    decay = math.exp(-zeta * phase / wd)
    return decay * (math.cos(phase) * -1.0 + zeta / wd * math.sin(phase))


def damping_for_restitution(restitution: float) -> float:
    """The damping ratio whose rigid-wall restitution is ``restitution`` (0 < e <= 1)."""
    e = require_finite("contact.restitution", restitution)
    if not 0.0 < e <= 1.0:
        raise InputError("contact.restitution", f"must be in (0, 1], got {restitution!r}")
    if e == 1.0:
        return 0.0
    hi = 0.999
    if wall_restitution(hi) > e:
        raise InputError("contact.restitution", f"must be >= {wall_restitution(hi):.3g} (a damping ratio below 1)")
    return float(brentq(lambda z: wall_restitution(z) - e, 0.0, hi, xtol=1e-12))


# Calibrated on SEED_TABLE1_EVENT by calibrate() (docs/contact-law.md); tests/test_contact_law.py
# repeats the calibration and checks these two numbers.
CONTAINER_STIFFNESS_N_M = 1.08e5
CONTAINER_DAMPING_RATIO = 0.0

CONTAINER = ContactLaw(CONTAINER_STIFFNESS_N_M, CONTAINER_DAMPING_RATIO, "container")
"""The 1:40 polyethylene container, calibrated on the study's Table 1 event."""

ASCE7_KD = ContactLaw(SEED_DEBRIS_STIFFNESS_N_M, 0.0, "asce7_kd")
"""ASCE 7-22's rigid debris: the study's k_d, undamped."""

LAWS = {"container": CONTAINER, "asce7_kd": ASCE7_KD}


def contact_law(law: str = "container", stiffness_N_m: float | None = None, damping_ratio: float | None = None,
                restitution: float | None = None) -> ContactLaw:
    """A named law (``container`` or ``asce7_kd``) with any of its values replaced.

    ``restitution`` (against a rigid wall) sets the damping ratio; give it or
    ``damping_ratio``, not both.
    """
    if law not in LAWS:
        raise InputError("contact.law", f"must be one of {sorted(LAWS)}, got {law!r}")
    if damping_ratio is not None and restitution is not None:
        raise InputError("contact.restitution", "give damping_ratio or restitution, not both")
    base = LAWS[law]
    k = base.stiffness_N_m if stiffness_N_m is None else stiffness_N_m
    zeta = base.damping_ratio if damping_ratio is None else damping_ratio
    if restitution is not None:
        zeta = damping_for_restitution(restitution)
    changed = (stiffness_N_m, damping_ratio, restitution) != (None, None, None)
    return ContactLaw(k, zeta, f"{law} (changed)" if changed else law)


# ------------------------------------------------------------------------------ one strike
def box_inertia(size_m, mass_kg: float, wall_thickness_m: float | None) -> tuple[float, float, float]:
    """Principal moments of inertia (kg m^2) of a closed box about its body axes.

    A closed box of uniform walls ``wall_thickness_m`` thick (the material's density follows
    from the mass and the wall volume), or a solid box when the thickness is None or at
    least half the smallest side.
    """
    a, b, c = (require_positive("size_m", s) for s in size_m)
    mass_kg = require_positive("mass_kg", mass_kg)
    t = wall_thickness_m
    if t is None or 2 * t >= min(a, b, c):
        return (mass_kg * (b * b + c * c) / 12.0, mass_kg * (a * a + c * c) / 12.0, mass_kg * (a * a + b * b) / 12.0)
    ai, bi, ci = a - 2 * t, b - 2 * t, c - 2 * t
    vo, vi = a * b * c, ai * bi * ci
    rho = mass_kg / (vo - vi)
    return (
        rho * (vo * (b * b + c * c) - vi * (bi * bi + ci * ci)) / 12.0,
        rho * (vo * (a * a + c * c) - vi * (ai * ai + ci * ci)) / 12.0,
        rho * (vo * (a * a + b * b) - vi * (ai * ai + bi * bi)) / 12.0,
    )


def column_impact(
    law: ContactLaw,
    velocity_m_s: float,
    height_m: float = SEED_IMPACT_HEIGHTS_M[2],
    *,
    column: Column | None = None,
    obliquity_deg: float = 0.0,
    mass_kg: float = SEED_DEBRIS_MASS_KG,
    size_m=SEED_CONTAINER_SIZE_M,
    wall_thickness_m: float | None = SEED_CONTAINER_WALL_M,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    added_mass_coefficient: float = 0.0,
) -> ImpactResult:
    """A container striking the column's upstream face end-on, its long axis normal to the face.

    Its centre moves at ``velocity_m_s`` at ``obliquity_deg`` from the face's normal (0 head
    on), in the horizontal plane; the contact point is the centre of its nose, ``height_m``
    above the column's base. Returns :func:`analytical.impact.impact`'s result (pulse,
    restitution, base shear).
    """
    column = Column() if column is None else column
    u = require_positive("--velocity", velocity_m_s)
    h = require_positive("--height", height_m)
    if h > column.height_m:
        raise InputError("--height", f"must be within the column, 0 < height <= {column.height_m} m, got {height_m}")
    theta = require_finite("--obliquity", obliquity_deg)
    if not 0.0 <= theta < 90.0:
        raise InputError("--obliquity", f"must be in [0, 90) degrees, got {obliquity_deg}")
    half_length = float(size_m[0]) / 2.0
    inertia = box_inertia(size_m, mass_kg, wall_thickness_m)
    rad = math.radians(theta)
    body = Body(mass_kg, inverse_inertia_tensor(inertia, np.eye(3)), (-half_length, 0.0, h),
                (u * math.cos(rad), u * math.sin(rad), 0.0), added_mass_coefficient=added_mass_coefficient)
    return impact(body, (0.0, 0.0, h), (-1.0, 0.0, 0.0), ColumnTarget(column, h),
                  friction_coefficient=friction_coefficient, **law.options())


def _figures(result: ImpactResult) -> tuple[float, float, float, float]:
    shear = result.base_shear
    return (result.peak_force_N, result.duration_s, result.impulse_Ns, abs(shear.peak_N) if shear else float("nan"))


# ------------------------------------------------------------------------------ calibration
@dataclass(frozen=True)
class Calibration:
    """The law fitted to one event, and how close its pulse comes (relative errors)."""

    law: ContactLaw
    event: ImpactEvent
    peak_force_N: float
    duration_s: float
    impulse_Ns: float
    peak_base_shear_N: float
    restitution: float

    @property
    def errors(self) -> dict[str, float]:
        e = self.event
        return {"peak_force": self.peak_force_N / e.peak_force_N - 1.0,
                "duration": self.duration_s / e.duration_s - 1.0,
                "impulse": self.impulse_Ns / e.impulse_Ns - 1.0}


def calibrate(event: ImpactEvent = SEED_TABLE1_EVENT, column: Column | None = None,
              max_damping_ratio: float = 0.5) -> Calibration:
    """Fit ``k`` and ``zeta`` so that a head-on strike at the event's velocity and height,
    through the column's MDOF model, gives the event's magnitude, duration and impulse
    (least squares on the three relative errors; zeta bounded to [0, max_damping_ratio]).
    The start is Haehnel & Daly's undamped half-sine: ``k = m (pi / T)^2``."""
    column = Column() if column is None else column
    k0 = event.mass_kg * (math.pi / event.duration_s) ** 2
    targets = np.array([event.peak_force_N, event.duration_s, event.impulse_Ns])

    def strike(x):
        law = ContactLaw(math.exp(x[0]), float(x[1]), "fit")
        return column_impact(law, event.velocity_m_s, event.height_m, column=column, mass_kg=event.mass_kg)

    def residual(x):
        return np.array(_figures(strike(x))[:3]) / targets - 1.0

    fit = least_squares(residual, x0=[math.log(k0), 0.01], bounds=([math.log(k0 / 10), 0.0],
                        [math.log(k0 * 10), max_damping_ratio]), diff_step=1e-3, xtol=1e-6)
    zeta = float(fit.x[1]) if fit.x[1] > 1e-6 else 0.0  # at the bound: undamped, not 1e-15
    law = ContactLaw(float(math.exp(fit.x[0])), zeta, "calibrated")
    result = column_impact(law, event.velocity_m_s, event.height_m, column=column, mass_kg=event.mass_kg)
    peak, duration, impulse, shear = _figures(result)
    return Calibration(law, event, peak, duration, impulse, shear, result.restitution)


# ------------------------------------------------------------------------------ held-out check
@dataclass(frozen=True)
class HeldOut:
    """The law driven with the study's 22 impact velocities and heights: per-impact figures
    (arrays, one entry per impact) and their mean and standard deviation."""

    law: ContactLaw
    velocity_m_s: np.ndarray
    height_m: np.ndarray
    peak_force_N: np.ndarray
    duration_s: np.ndarray
    impulse_Ns: np.ndarray
    peak_base_shear_N: np.ndarray

    def stats(self, name: str) -> tuple[float, float]:
        values = getattr(self, name)
        return float(np.mean(values)), float(np.std(values, ddof=1))

    def rows(self) -> list[dict]:
        """Model mean and std beside the study's MDOF row, for each figure."""
        out = []
        for name in ("peak_force_N", "duration_s", "impulse_Ns", "peak_base_shear_N"):
            mean, std = self.stats(name)
            seed = SEED_TABLE2_MDOF.get(name, (float("nan"), float("nan")))
            out.append({"figure": name, "model_mean": mean, "model_std": std, "seed_mean": seed[0],
                        "seed_std": seed[1], "z_of_mean": (mean - seed[0]) / seed[1] if seed[1] == seed[1] else None})
        return out


def seed_impacts(count: int = 22) -> tuple[np.ndarray, np.ndarray]:
    """``count`` impact velocities at the normal quantiles of 1.60 +- 0.13 m/s and heights
    evenly over 0.16-0.50 m, paired so that velocity and height are uncorrelated (a fixed
    shuffle): a deterministic stand-in for the study's 22 impacts, whose individual values
    are not published."""
    if count < 2:
        raise InputError("count", f"must be >= 2, got {count}")
    q = (np.arange(count) + 0.5) / count
    velocity = SEED_IMPACT_VELOCITY_M_S[0] + SEED_IMPACT_VELOCITY_M_S[1] * norm.ppf(q)
    heights = np.linspace(SEED_IMPACT_HEIGHTS_M[0], SEED_IMPACT_HEIGHTS_M[1], count)
    order = np.random.default_rng(2019).permutation(count)
    return velocity, heights[order]


def held_out(law: ContactLaw = CONTAINER, column: Column | None = None, count: int = 22) -> HeldOut:
    """Strike the column head-on at :func:`seed_impacts`' velocities and heights."""
    column = Column() if column is None else column
    velocity, heights = seed_impacts(count)
    figures = np.array([_figures(column_impact(law, u, h, column=column)) for u, h in zip(velocity, heights)])
    return HeldOut(law, velocity, heights, *(figures[:, i] for i in range(4)))
