"""A contact law against a full-scale container test: its peak force at the test's speed and mass.

:func:`compare` strikes a rigid wall end-on with a body of the test's mass at the test's speed,
through the law's spring and dashpot (:func:`analytical.impact.impact`, no friction, no added
mass for a strike in air: the Lehigh tests swung the container into a wall of load cells), and sets
the law's peak force beside the measured one (:attr:`Comparison.ratio`). A test record must pair a
speed, a mass and a peak force (:attr:`analytical.fullscale_sources.FullScaleTest.complete`); one
that does not is refused, naming what it lacks.

:func:`fit_law` fits a full-scale law to one complete record (a linear spring from its peak, or a
spring and dashpot from its peak and duration) and :func:`held_out_check` checks it on another:
the calibration issue 48 asks for. It needs two complete records; the sources found give none
(:mod:`analytical.fullscale_sources`), so :func:`calibration_possible` is False and
:func:`held_out_check` refuses, saying why.

:func:`agreeing_test` says whether a law is within the tolerance of a complete record: the
condition under which a design page may print a probability of exceeding the code's value.

:func:`froude_scaled_design_law` is the stand-in the example scenes state (cases/design-street.yaml:
the study's 1:40 law, :data:`analytical.contact_law.CONTAINER_STIFFNESS_N_M` x 40^2 and
:data:`~analytical.contact_law.CONTAINER_DAMPING_RATIO`; the catalogue's full-size containers carry
no law); :func:`lehigh_series_bound` sets a law beside the only full-scale force figures found: the
speeds of Lehigh's elastic series and the largest force quoted for the programme. That is a bound,
not a test record (the force is tied to no speed).

Units: N, m, s, kg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares

from analytical.catalogue import LAB_SCALE
from analytical.contact_law import CONTAINER_DAMPING_RATIO, CONTAINER_STIFFNESS_N_M, ContactLaw, contact_law
from analytical.errors import InputError, require_finite, require_positive
from analytical.fullscale_sources import FULL_SCALE_TESTS, FullScaleTest, record
from analytical.impact import impact
from analytical.impact_bodies import Body, RigidWall
from analytical.impact_results import ImpactResult

__all__ = [
    "DEFAULT_TOLERANCE",
    "Comparison",
    "agreeing_test",
    "calibration_possible",
    "compare",
    "fit_law",
    "froude_scaled_design_law",
    "held_out_check",
    "law_strike",
    "lehigh_series_bound",
]

DEFAULT_TOLERANCE = 0.30
"""A law agrees with a test when its peak force is within 30 % of the measured one (issue 48)."""


def froude_scaled_design_law(scale: float = LAB_SCALE) -> ContactLaw:
    """The study's 1:40 container law Froude-scaled: ``k x scale^2``, the damping ratio unchanged.

    No full-scale source gives a container's law (docs/fullscale-sources.md) and Froude similarity
    does not scale elasticity, so this is an assumed stand-in, not a full-scale value: what
    cases/design-street.yaml states for its container, with a comment saying so.
    """
    scale = require_positive("scale", scale)
    law = contact_law("container", stiffness_N_m=CONTAINER_STIFFNESS_N_M * scale**2,
                      damping_ratio=CONTAINER_DAMPING_RATIO)
    return replace(law, name=f"the study's 1:40 law x {scale:g}^2 (a stand-in)")


def law_strike(law: ContactLaw, velocity_m_s: float, mass_kg: float,
               added_mass_coefficient: float = 0.0) -> ImpactResult:
    """A body of ``mass_kg`` striking a rigid wall end-on at ``velocity_m_s`` through ``law``.

    The body is a particle (the strike is central: no rotation), frictionless, with
    ``added_mass_coefficient`` (0 in air). Returns the impact's pulse, peak and duration.
    """
    if not isinstance(law, ContactLaw):
        raise InputError("law", f"must be an analytical.contact_law.ContactLaw, got {type(law).__name__}")
    v = require_positive("velocity_m_s", velocity_m_s)
    m = require_positive("mass_kg", mass_kg)
    ca = require_finite("added_mass_coefficient", added_mass_coefficient)
    if ca < 0.0:
        raise InputError("added_mass_coefficient", f"must be >= 0, got {added_mass_coefficient!r}")
    body = Body.particle(m, (-v, 0.0, 0.0), added_mass_coefficient=ca)
    return impact(body, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), RigidWall(), friction_coefficient=0.0,
                  base_shear=False, **law.options())


@dataclass(frozen=True)
class Comparison:
    """A law's strike beside a full-scale test's measurement (N, s)."""

    test: str
    law: ContactLaw
    velocity_m_s: float
    mass_kg: float
    law_peak_N: float
    law_duration_s: float
    measured_peak_N: float
    measured_duration_s: float | None

    @property
    def ratio(self) -> float:
        """The law's peak force over the measured one."""
        return self.law_peak_N / self.measured_peak_N

    def within(self, tolerance: float = DEFAULT_TOLERANCE) -> bool:
        """Whether the law's peak is within ``tolerance`` (a fraction) of the measured one."""
        return abs(self.ratio - 1.0) <= tolerance

    def outcome(self, tolerance: float = DEFAULT_TOLERANCE) -> str:
        """One sentence: the ratio and whether the law agrees with the test."""
        verdict = "agrees" if self.within(tolerance) else "is off"
        return (f"{self.law.name} (k {self.law.stiffness_N_m:.4g} N/m, zeta {self.law.damping_ratio:.3g}) at "
                f"{self.velocity_m_s:.3g} m/s, {self.mass_kg:.5g} kg: peak {self.law_peak_N / 1e3:,.1f} kN against "
                f"{self.measured_peak_N / 1e3:,.1f} kN measured ({self.test}), ratio {self.ratio:.3f}: it {verdict} "
                f"(tolerance {tolerance:.0%})")


def compare(law: ContactLaw, test: FullScaleTest, added_mass_coefficient: float = 0.0) -> Comparison:
    """``law``'s strike at ``test``'s speed and mass beside its measured peak force.

    Raises InputError (field ``test``) when the record lacks a speed, a mass or a peak force.
    """
    if not isinstance(test, FullScaleTest):
        raise InputError("test", f"must be an analytical.fullscale_sources.FullScaleTest, got {type(test).__name__}")
    if not test.complete:
        raise InputError("test", f"{test.name!r} gives no {', '.join(test.missing)}: it cannot check a law "
                                 "(a check needs a speed, a mass and a peak force from the same test)")
    r = law_strike(law, test.velocity_m_s, test.mass_kg, added_mass_coefficient)
    return Comparison(test.name, law, test.velocity_m_s, test.mass_kg, r.peak_force_N, r.duration_s,
                      test.peak_force_N, test.duration_s)


def calibration_possible(tests=FULL_SCALE_TESTS, needed: int = 2) -> bool:
    """Whether ``tests`` hold ``needed`` complete records: one to fit, one to hold out."""
    return sum(1 for t in tests if t.complete) >= needed


def agreeing_test(law: ContactLaw, tests=FULL_SCALE_TESTS, tolerance: float = DEFAULT_TOLERANCE) -> Comparison | None:
    """The first complete record of ``tests`` whose peak force ``law`` gives within ``tolerance`` at
    its speed and mass, or None (always None while no record is complete: :func:`calibration_possible`)."""
    for t in tests:
        if t.complete:
            c = compare(law, t)
            if c.within(tolerance):
                return c
    return None


def fit_law(test: FullScaleTest, damped: bool = False, name: str | None = None,
            added_mass_coefficient: float = 0.0) -> ContactLaw:
    """A full-scale law fitted to one complete record.

    ``damped=False``: an undamped linear spring through the measured peak, ``k = (F / v)^2 / m``
    (a rigid-wall strike's half-sine peak is ``v sqrt(k m)``). ``damped=True``: a spring and a
    dashpot matching both the peak and the contact duration (the record must give a duration).
    """
    if not test.complete:
        raise InputError("test", f"{test.name!r} gives no {', '.join(test.missing)}: nothing to fit")
    v, m, peak = test.velocity_m_s, test.mass_kg * (1.0 + added_mass_coefficient), test.peak_force_N
    k0 = (peak / v) ** 2 / m
    name = name or f"fitted to {test.name}"
    if not damped:
        return ContactLaw(k0, 0.0, name)
    if test.duration_s is None:
        raise InputError("test", f"{test.name!r} gives no duration_s: a spring and dashpot need one")

    def residual(x):
        r = law_strike(ContactLaw(math.exp(x[0]), x[1]), v, test.mass_kg, added_mass_coefficient)
        return [r.peak_force_N / peak - 1.0, r.duration_s / test.duration_s - 1.0]

    sol = least_squares(residual, [math.log(k0), 0.1], bounds=([math.log(k0) - 5, 0.0], [math.log(k0) + 5, 0.95]),
                        xtol=1e-12, ftol=1e-12)
    if np.max(np.abs(sol.fun)) > 1e-3:
        raise InputError("test", f"no spring and dashpot gives {test.name!r}'s peak and duration together "
                                 f"(best misfit {np.max(np.abs(sol.fun)):.2%})")
    return ContactLaw(math.exp(sol.x[0]), float(sol.x[1]), name)


def held_out_check(fit_on: FullScaleTest, check_on: FullScaleTest, damped: bool = False,
                   tolerance: float = DEFAULT_TOLERANCE) -> tuple[ContactLaw, Comparison]:
    """Fit a law to ``fit_on`` (:func:`fit_law`) and compare it with the held-out ``check_on``.

    Returns the law and the comparison; :meth:`Comparison.within` gives the verdict. Refuses
    (InputError, field ``tests``) unless both records are complete and distinct.
    """
    lacking = [f"{t.name!r} gives no {', '.join(t.missing)}" for t in (fit_on, check_on) if not t.complete]
    if lacking:
        raise InputError("tests", "a held-out check needs two complete full-scale records (speed, mass and peak "
                                  "force each): " + "; ".join(lacking))
    if fit_on.name == check_on.name:
        raise InputError("tests", f"the held-out record must differ from the fitted one, both are {fit_on.name!r}")
    law = fit_law(fit_on, damped=damped)
    return law, compare(law, check_on)


def lehigh_series_bound(law: ContactLaw) -> list[dict]:
    """``law`` at the two ends of Lehigh's elastic speed range (2 and 4 mph), for both container masses
    the reports give (5,000 lb; 3.5 short tons), beside the programme's largest quoted force
    (half a million pounds) and duration (a hundredth of a second).

    A bound, not a calibration: the quoted force is the largest of the programme (whose final tests
    pulled the container further back) and is tied to no speed or mass. Rows: ``mass_kg``,
    ``mass_source``, ``velocity_m_s``, ``law_peak_N``, ``law_duration_s``, ``quoted_peak_N``, ``quoted_duration_s``, ``ratio``.
    """
    quoted_peak, quoted_duration = record("nsf_peak_force").si, record("nsf_duration").si
    rows = []
    for mass_key in ("nsf_container_weight", "lehigh_container_weight"):
        for speed_key in ("lehigh_speed_low", "lehigh_speed_high"):
            m, v = record(mass_key).si, record(speed_key).si
            r = law_strike(law, v, m)
            rows.append({"mass_kg": m, "mass_source": mass_key, "velocity_m_s": v, "law_peak_N": r.peak_force_N,
                         "law_duration_s": r.duration_s, "quoted_peak_N": quoted_peak,
                         "quoted_duration_s": quoted_duration, "ratio": r.peak_force_N / quoted_peak})
    return rows
