"""The contact law of a debris body: how soft it is and how much energy a strike loses.

A contact law is a compression-only spring ``k`` with a dashpot ``c = 2 zeta sqrt(k m_eff)``
between the debris and what it strikes (a Kelvin-Voigt contact). :func:`analytical.impact.impact`
puts it in series with the column's MDOF model (or against a rigid wall, or between two bodies);
the force history, the rebound and the base shear come out of that integration.

Two laws ship:

* ``container`` (the default, :data:`CONTAINER`): calibrated on the study's 22 impacts, its
  Table 2 MDOF row (171.07 +- 62.91 N, 4.7 +- 0.5 ms, 0.52 +- 0.22 N s at 1.60 +- 0.13 m/s),
  like with like: the law strikes the column over the study's population of speeds, water
  levels and a stated spread of contact geometry, the column's base shear at the load cell is
  fitted with the study's own procedure (:func:`study_fit`: a half-sine on the MDOF column loaded
  at the water level, :func:`analytical.fitting.fit_mdof`), and ``k`` and ``zeta`` are fitted by
  weighted least squares to Table 2's three means through their standard errors
  (:mod:`analytical.contact_calibration`, docs/contact-law.md). ``k`` is the compliance of the
  container's thin polyethylene nose (about 40 times softer than the rigid debris stiffness
  ``k_d`` of the study's ASCE rows); ``zeta`` the energy the strike loses to the wall's
  deformation and to the water squeezed out of the closing gap. The study's Table 1 event
  (236.93 N, 4.7 ms, 0.71 N s at 1.50 m/s, an elastic strike) is the check.
* ``asce7_kd`` (:data:`ASCE7_KD`): ``k_d`` = 3.0e6 N/m, undamped: ASCE 7-22's rigid debris
  (Haehnel & Daly's model). It gives 0.9 ms pulses of 1,100-1,500 N: an upper bound.

Either can be given another stiffness, a damping ratio, or a coefficient of restitution
(turned into the damping ratio that gives it against a rigid wall, :func:`damping_for_restitution`).

A strike (:func:`column_impact`) is resolved on the body's effective mass at its contact point:
its mass plus its added mass along the contact normal (:mod:`analytical.added_mass`; end-on,
the container's lengthwise ``C_a`` = 0.28) and its rotational inertia plus the water's.

Units: N, m, s, kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from analytical.added_mass import box_added_mass
from analytical.column import Column
from analytical.errors import InputError, require_finite, require_positive
from analytical.fitting import PulseFit, fit_mdof
from analytical.impact import (
    DEFAULT_FRICTION_COEFFICIENT,
    Body,
    ColumnTarget,
    ImpactResult,
    impact,
    inverse_inertia_tensor,
)
from analytical.study import (
    STUDY_CONTAINER_SIZE_M,
    STUDY_CONTAINER_WALL_M,
    STUDY_DEBRIS_MASS_KG,
    STUDY_DEBRIS_STIFFNESS_N_M,
    STUDY_IMPACT_HEIGHTS_M,
    STUDY_MEAN_HEIGHT_M,
    STUDY_TABLE1,
    STUDY_TABLE1_VELOCITY_M_S,
    STUDY_TABLE2_MDOF,
)

__all__ = [
    "ASCE7_KD",
    "CONTAINER",
    "LAWS",
    "STUDY_TABLE1_EVENT",
    "STUDY_TABLE2_MDOF",
    "ContactLaw",
    "ImpactEvent",
    "box_inertia",
    "column_impact",
    "contact_law",
    "damping_for_restitution",
    "study_fit",
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


STUDY_TABLE1_EVENT = ImpactEvent(STUDY_TABLE1_VELOCITY_M_S, STUDY_MEAN_HEIGHT_M, STUDY_DEBRIS_MASS_KG,
                                *STUDY_TABLE1["MDOF fit"])
"""The study's Table 1 event: measured velocity 1.50 m/s, MDOF-fitted half-sine (its Fig. 4).
The height is the mean of its 22 impacts (0.40 m); the event's own height is not given."""



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


# Calibrated on STUDY_TABLE2_MDOF by analytical.contact_calibration.calibrate() (docs/contact-law.md,
# `make contact-law`) on the study's column with its base tuned to the measured 70 Hz, from 6
# starts: k = 6.34e4 +- 1.5e4 N/m, zeta = 0.620 +- 0.065 (correlation -1.00), chi-square 1.21 on
# 1 dof. tests/test_contact_law.py checks that they reproduce Table 2 and are the calibration's minimum.
CONTAINER_STIFFNESS_N_M = 6.34e4
CONTAINER_DAMPING_RATIO = 0.620

CONTAINER = ContactLaw(CONTAINER_STIFFNESS_N_M, CONTAINER_DAMPING_RATIO, "container")
"""The 1:40 polyethylene container, calibrated on the study's Table 2 (22 impacts)."""

ASCE7_KD = ContactLaw(STUDY_DEBRIS_STIFFNESS_N_M, 0.0, "asce7_kd")
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
    height_m: float = STUDY_IMPACT_HEIGHTS_M[2],
    *,
    column: Column | None = None,
    obliquity_deg: float = 0.0,
    mass_kg: float = STUDY_DEBRIS_MASS_KG,
    size_m=STUDY_CONTAINER_SIZE_M,
    wall_thickness_m: float | None = STUDY_CONTAINER_WALL_M,
    friction_coefficient: float = DEFAULT_FRICTION_COEFFICIENT,
    added_mass_coefficient: float | None = None,
    lateral_offset_m: float = 0.0,
    vertical_offset_m: float = 0.0,
) -> ImpactResult:
    """A container striking the column's upstream face end-on, its long axis normal to the face.

    Its centre moves at ``velocity_m_s`` at ``obliquity_deg`` from the face's normal (0 head
    on, negative or positive: towards -y or +y), in the horizontal plane. The contact point is
    ``height_m`` above the column's base, on the nose, ``lateral_offset_m`` (across, +y) and
    ``vertical_offset_m`` (up) from the nose's centre: the body's centre of mass lies
    half a length upstream of it, displaced by the opposite offsets. Returns
    :func:`analytical.impact.impact`'s result (pulse, restitution, base shear).

    The body's mass is ``mass_kg`` plus its added mass along the normal: by default the
    floating box's lengthwise added mass (:func:`analytical.added_mass.box_added_mass`,
    ``C_a`` = 0.28 for the study's container), or ``added_mass_coefficient`` when given; its
    rotational inertia is the box's (:func:`box_inertia`) plus the water's added inertia.
    """
    column = Column() if column is None else column
    u = require_positive("--velocity", velocity_m_s)
    h = require_positive("--height", height_m)
    if h > column.height_m:
        raise InputError("--height", f"must be within the column, 0 < height <= {column.height_m} m, got {height_m}")
    theta = require_finite("--obliquity", obliquity_deg)
    if not -90.0 < theta < 90.0:
        raise InputError("--obliquity", f"must be in (-90, 90) degrees, got {obliquity_deg}")
    ey = require_finite("lateral_offset_m", lateral_offset_m)
    ez = require_finite("vertical_offset_m", vertical_offset_m)
    if abs(ey) > 0.5 * float(size_m[1]) or abs(ez) > 0.5 * float(size_m[2]):
        raise InputError("lateral_offset_m", f"the contact point ({ey}, {ez}) m must lie on the nose, within half its "
                                             f"width and height ({size_m[1] / 2}, {size_m[2] / 2}) m")
    half_length = float(size_m[0]) / 2.0
    inertia = np.array(box_inertia(size_m, mass_kg, wall_thickness_m))
    water = box_added_mass(size_m, mass_kg)
    if added_mass_coefficient is None:
        added_mass_coefficient = water.coefficient_along((1.0, 0.0, 0.0))
        inertia = inertia + np.array(water.inertias_kg_m2)
    rad = math.radians(theta)
    body = Body(mass_kg, inverse_inertia_tensor(inertia, np.eye(3)), (-half_length, -ey, h - ez),
                (u * math.cos(rad), u * math.sin(rad), 0.0), added_mass_coefficient=added_mass_coefficient)
    return impact(body, (0.0, 0.0, h), (-1.0, 0.0, 0.0), ColumnTarget(column, h),
                  friction_coefficient=friction_coefficient, **law.options())


#: Sampling interval (s) of the base-shear record handed to the study's fit: 25 kHz. Fits of the
#: container law's records at 100 kHz agree with it to 1e-5 in peak, duration and impulse.
STUDY_FIT_DT_S = 4.0e-5
#: The record starts this long (s) before the contact (quiet), and ends this long after it.
STUDY_FIT_PRE_S, STUDY_FIT_POST_S = 0.01, 0.035


def study_fit(result: ImpactResult, water_level_m: float, column: Column | None = None) -> PulseFit:
    """The study's procedure on a strike's base shear at the load cell (its sec. 3.2.2): a
    half-sine fitted with the MDOF column loaded at ``water_level_m`` (the water surface at
    the column's face, where the study loaded its model), magnitude, duration and start free
    (:func:`analytical.fitting.fit_mdof`). The record is the base shear sampled every
    :data:`STUDY_FIT_DT_S` from :data:`STUDY_FIT_PRE_S` before the contact (at rest) to
    :data:`STUDY_FIT_POST_S` after it."""
    shear = result.base_shear
    if shear is None:
        raise InputError("result", "the strike has no base shear along the column's x axis")
    t = np.arange(-STUDY_FIT_PRE_S, STUDY_FIT_POST_S, STUDY_FIT_DT_S)
    y = np.interp(t, shear.time_s, shear.response_N, left=0.0, right=float(shear.response_N[-1]))
    return fit_mdof(t, y, column=column, height_m=water_level_m)
