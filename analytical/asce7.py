"""Debris impact load of ASCE/SEI 7-22 Section 6.11 (tsunami loads: debris impact).

The standard's impact model (Clauses 6.11.2, 6.11.6 and 6.11.8, as applied by the study,
Sec. 3.2.3, eqs. [8]-[10]):

    F_ni = u_max sqrt(k m_d)              nominal maximum instantaneous impact force, N
    F_i  = I_tsu C_o F_ni                 design impact force, N
    t_d  = 2 m_d u_max / F_ni             impact duration, s
    load = rectangular pulse of F_i over t_d   (Clause 6.11.8)

with ``u_max`` the maximum flow velocity at the site (m/s), ``m_d`` the debris mass (kg), ``k``
the lesser of the effective stiffness of the impacting debris and the lateral stiffness of the
impacted structural element (N/m), ``I_tsu`` the tsunami importance factor and ``C_o`` the
orientation coefficient. The impulse ``F_i t_d = 2 I_tsu C_o m_d u_max`` does not depend on
``k``: the study's observation that the k_d and k_s load histories carry the same impulse.

Everything here is pure: numbers in, frozen result objects out.

References
----------
ASCE/SEI 7-22, *Minimum Design Loads and Associated Criteria for Buildings and Other
Structures*, Chapter 6 (Tsunami Loads and Effects), Sections 6.8.3 and 6.11.
Haehnel, R. B. and Daly, S. F. (2004). Maximum impact force of woody debris on floodplain
structures. *J. Hydraulic Engineering* 130(2), 112-120.
The study: Joynt, Nistor, Palermo & Stolle (analytical/study.py), Sec. 2.1 (eqs. [1]-[3]), 3.2.3, 3.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytical.errors import InputError, require_positive
from analytical.pulses import Rectangular, make_pulse
from analytical.sdof import max_force_response
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M, STUDY_STRUCTURE_STIFFNESS_N_M

__all__ = [
    "ORIENTATION_CONTAINER",
    "ORIENTATION_LOGS_POLES",
    "IMPORTANCE_FACTORS",
    "importance_factor",
    "effective_stiffness",
    "AsceImpact",
    "AsceDesign",
    "asce7_impact",
    "asce7_design",
    "SIMPLIFIED_STATIC_LOAD_N",
    "dynamic_response_ratio",
    "STUDY_STRUCTURE_STIFFNESS_N_M",
    "STUDY_DEBRIS_STIFFNESS_N_M",
    "FULL_SCALE_MIN_MASS_KG",
    "MAX_FLOW_SPEED_M_S",
    "DEBRIS_STIFFNESS_RANGE_N_M",
    "check_flow_speed",
    "check_debris_stiffness",
    "check_full_scale_mass",
    "STRUCTURE_STIFFNESS_RANGE_N_M",
    "MAX_DEBRIS_MASS_KG",
    "check_structure_stiffness",
    "check_debris_mass",
]

ORIENTATION_CONTAINER = 0.65
"""Orientation coefficient C_o for shipping containers (ASCE 7-22 Clause 6.11.6; study Sec. 3.2.3)."""

ORIENTATION_LOGS_POLES = 0.65
"""Orientation coefficient C_o for wood logs and poles (ASCE 7-22 Clause 6.11.2)."""

IMPORTANCE_FACTORS: dict[str, float] = {
    "II": 1.0,
    "III": 1.25,
    "IV": 1.25,
    "vertical-evacuation-refuge": 1.25,
}
"""Tsunami importance factor I_tsu by Tsunami Risk Category, for hydrodynamic and impact loads.

ASCE/SEI 7-16 and 7-22, Table 6.8-1 (Section 6.8.3): Tsunami Risk Category II 1.0; III 1.25;
IV, Tsunami Vertical Evacuation Refuge Structures (and TRC III critical facilities) 1.25.
The study (Sec. 3.2.3) confirms I_tsu = 1.0 for Risk Category II. No online copy of the table
could be retrieved when this was written: check the III/IV values against the printed standard.
"""


def importance_factor(risk_category: str) -> float:
    """``I_tsu`` for a Tsunami Risk Category (``"II"``, ``"III"``, ``"IV"``,
    ``"vertical-evacuation-refuge"``; case-insensitive, ``2``/``3``/``4`` also accepted)."""
    key = str(risk_category).strip()
    key = {"2": "II", "3": "III", "4": "IV"}.get(key, key)
    key = key.upper() if key.upper() in ("II", "III", "IV") else key.lower().replace("_", "-")
    if key not in IMPORTANCE_FACTORS:
        raise InputError(
            "risk_category",
            f"unknown Tsunami Risk Category {risk_category!r}; expected one of {sorted(IMPORTANCE_FACTORS)}",
        )
    return IMPORTANCE_FACTORS[key]


def effective_stiffness(structure_stiffness_N_m: float, debris_stiffness_N_m: float) -> float:
    """Structure and debris stiffness in series, ``1/k = 1/k_s + 1/k_d`` (study eq. [2]).

    Parameters
    ----------
    structure_stiffness_N_m:
        ``k_s``, N/m (> 0).
    debris_stiffness_N_m:
        ``k_d``, N/m (> 0).

    Returns
    -------
    float
        ``k = k_s k_d / (k_s + k_d)``, N/m (Haehnel and Daly 2004).
    """
    ks = require_positive("structure_stiffness_N_m", structure_stiffness_N_m)
    kd = require_positive("debris_stiffness_N_m", debris_stiffness_N_m)
    return ks * kd / (ks + kd)


@dataclass(frozen=True)
class AsceImpact:
    """An ASCE 7-22 Section 6.11 debris impact (inputs; results as properties).

    Parameters
    ----------
    velocity_m_s:
        Maximum flow (impact) velocity ``u_max``, m/s (> 0).
    mass_kg:
        Debris mass ``m_d``, kg (> 0).
    stiffness_N_m:
        Stiffness ``k``, N/m (> 0): the lesser of the debris' effective stiffness and the
        impacted element's lateral stiffness.
    importance:
        ``I_tsu`` (> 0); see :data:`IMPORTANCE_FACTORS`.
    orientation:
        ``C_o``, in (0, 1]; see :data:`ORIENTATION_CONTAINER`.
    """

    velocity_m_s: float
    mass_kg: float
    stiffness_N_m: float
    importance: float = 1.0
    orientation: float = ORIENTATION_CONTAINER

    def __post_init__(self):
        for name in ("velocity_m_s", "mass_kg", "stiffness_N_m", "importance", "orientation"):
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))
        if self.orientation > 1.0:
            raise InputError("orientation", f"must be in (0, 1], got {self.orientation!r}")

    @property
    def nominal_force_N(self) -> float:
        """``F_ni = u_max sqrt(k m_d)``, N (study eq. [9]; Haehnel and Daly 2004)."""
        return self.velocity_m_s * math.sqrt(self.stiffness_N_m * self.mass_kg)

    @property
    def force_N(self) -> float:
        """``F_i = I_tsu C_o F_ni``, N (study eq. [8])."""
        return self.importance * self.orientation * self.nominal_force_N

    @property
    def duration_s(self) -> float:
        """``t_d = 2 m_d u_max / F_ni = 2 sqrt(m_d / k)``, s (study eq. [10]); independent of u."""
        return 2.0 * self.mass_kg * self.velocity_m_s / self.nominal_force_N

    @property
    def impulse_Ns(self) -> float:
        """``F_i t_d = 2 I_tsu C_o m_d u_max``, N s; independent of ``k``."""
        return self.force_N * self.duration_s

    @property
    def pulse(self) -> Rectangular:
        """The design load history: a rectangular pulse of ``F_i`` over ``t_d``, from t = 0."""
        return Rectangular(self.force_N, self.duration_s)

    def to_dict(self) -> dict[str, float]:
        """Inputs and results as plain floats (for JSON/CSV), keys with units."""
        return {
            "velocity_m_s": self.velocity_m_s,
            "mass_kg": self.mass_kg,
            "stiffness_N_m": self.stiffness_N_m,
            "importance": self.importance,
            "orientation": self.orientation,
            "nominal_force_N": self.nominal_force_N,
            "force_N": self.force_N,
            "duration_s": self.duration_s,
            "impulse_Ns": self.impulse_Ns,
        }


def asce7_impact(
    velocity_m_s: float,
    mass_kg: float,
    stiffness_N_m: float,
    importance: float = 1.0,
    orientation: float = ORIENTATION_CONTAINER,
) -> AsceImpact:
    """Debris impact force, duration and pulse per ASCE 7-22 Section 6.11 (study eqs. [8]-[10]).

    Parameters
    ----------
    velocity_m_s:
        ``u_max``, m/s.
    mass_kg:
        ``m_d``, kg.
    stiffness_N_m:
        ``k``, N/m (use :func:`effective_stiffness` for debris and structure in series).
    importance:
        ``I_tsu`` (1.0 = Tsunami Risk Category II).
    orientation:
        ``C_o`` (0.65 for containers, logs and poles).

    Returns
    -------
    AsceImpact
        With ``nominal_force_N``, ``force_N``, ``duration_s``, ``impulse_Ns`` and ``pulse``.

    Examples
    --------
    >>> imp = asce7_impact(1.50, 0.236, 4.685e5)
    >>> round(imp.force_N, 1), round(imp.duration_s, 4), round(imp.impulse_Ns, 2)
    (324.2, 0.0014, 0.46)
    """
    return AsceImpact(velocity_m_s, mass_kg, stiffness_N_m, importance, orientation)


def dynamic_response_ratio(
    duration_s: float,
    natural_period_s: float,
    shape: str = "rectangular",
    damping_ratio: float = 0.0,
) -> float:
    """Maximum dynamic response over the static response of an SDOF structure to a pulse.

    ``R_max = max_t k u(t) / F`` for a pulse of peak ``F`` and duration ``t_d`` on an oscillator
    of natural period ``T_n``: the shock spectrum, computed exactly with the SDOF solution
    (:func:`analytical.sdof.max_force_response`), not read from a digitised table. Undamped
    (the default) and damped structures are both exact. Known undamped values: rectangular
    ``2 sin(pi t_d/T_n)`` for ``t_d/T_n <= 1/2`` and 2 beyond; half-sine ``pi/2`` at
    ``t_d/T_n = 1/2`` and a maximum of about 1.77 near 0.8 (Chopra 2017, Sec. 4.7-4.8).

    Parameters
    ----------
    duration_s:
        Pulse duration ``t_d``, s (> 0).
    natural_period_s:
        ``T_n``, s (> 0).
    shape:
        A name from :data:`analytical.pulses.PULSES`.
    damping_ratio:
        ``0 <= zeta < 1``.

    Returns
    -------
    float
        ``R_max`` (dimensionless).
    """
    td = require_positive("duration_s", duration_s)
    tn = require_positive("natural_period_s", natural_period_s)
    pulse = make_pulse(shape, 1.0, td)
    return max_force_response(pulse, 1.0 / tn, damping_ratio).peak_N


FULL_SCALE_MIN_MASS_KG = 100.0
"""The least mass of full-scale debris, kg: a body this heavy or heavier is at full scale, and a
full-scale (``--prototype``) body lighter than this is refused as a slip of units (tonnes for kg).

Why 100 kg: the lightest debris ASCE 7-22 6.11 designs for is a wood log or pole, whose debris
weight 6.11.2 takes as 1,000 lb (454 kg; check against the printed clause); shipping containers
start at about 2,300 kg empty (analytical.catalogue). No laboratory flume's debris comes near it:
the study's 1:40 container is 0.236 kg, and a loaded 20-ft container at 1:5 (a large-scale model)
is 30,480 kg / 125 = 244 kg. A scene with a body this heavy is treated as full scale
(orchestrator/studies/design_asce.py): its simplified static load applies.
"""

MAX_FLOW_SPEED_M_S = 30.0
"""The fastest flow (or strike) speed any verb accepts, m/s: well above any tsunami inundation speed.

The fastest onshore tsunami flows measured are about 11 m/s (Fritz et al. 2012, GRL 39, L00G23:
the 2011 Tohoku tsunami at Kesennuma Bay, from survivor videos); a bore's long-wave speed
``sqrt(g h)`` over the deepest onshore inundation recorded (about 40 m of run-up, Tohoku 2011) is
about 20 m/s. 30 m/s is half again above that: a speed beyond it is a slip of units (mm/s, km/h)
or of digits, not a flow.
"""

DEBRIS_STIFFNESS_RANGE_N_M = (1.0e5, 1.0e11)
"""The debris stiffness k_d a scene or verb may state, N/m (inclusive).

Low end 1e5 N/m: below the softest debris in the tool by 30x (the study's 1:40 polyethylene model
container, k_d 3.04e6 N/m) and below any full-scale value by more (ASCE 7-22 Table 6.11-2's
containers and logs are of order 1e7-1e8 N/m; a 20-ft container's 245 kip/in is 4.29e7 N/m, check
it against the printed table): a value under it is in the wrong unit (MN/m or kip/in given as N/m).
High end 1e11 N/m: 20 times the stiffest value here (the study's k_d Froude-scaled to full size,
4.86e9 N/m), beyond what any body in series with a column can present.
"""


STRUCTURE_STIFFNESS_RANGE_N_M = (1.0e3, 1.0e12)
"""The lateral stiffness k_s of a struck element a verb accepts, N/m (inclusive): from a slender
laboratory model (the study's acrylic column is 4.685e5 N/m) to a massive pier (the 1-debris scene
at 40:1 has 7.5e8 N/m, the street's 1 m RC column 3.4e7 N/m) with three decades either side;
outside it a unit is wrong (kN/mm, kip/in) or a digit slipped."""

MAX_DEBRIS_MASS_KG = 1.0e9
"""The heaviest debris a verb accepts, kg: ten times the displacement of the largest ships in port
(about 1.2e8 kg at 100,000 DWT) and far above the heaviest body a tsunami is known to have carried
ashore (the 2,600 t power barge PLTD Apung 1, Banda Aceh 2004)."""


def check_structure_stiffness(stiffness_N_m: float, field: str = "structure_stiffness_N_m") -> float:
    """``stiffness_N_m`` within :data:`STRUCTURE_STIFFNESS_RANGE_N_M`, else InputError on ``field``."""
    return _stiffness_within(stiffness_N_m, field, STRUCTURE_STIFFNESS_RANGE_N_M, "lateral stiffness of a struck element",
                             "the study's acrylic column 4.685e5, a 1 m RC column 3.4e7 N/m); a value in another unit?")


def check_debris_mass(mass_kg: float, field: str = "mass_kg") -> float:
    """``mass_kg`` (> 0, at most :data:`MAX_DEBRIS_MASS_KG`), else InputError on ``field``."""
    m = require_positive(field, mass_kg)
    if m > MAX_DEBRIS_MASS_KG:
        raise InputError(field, f"{m:g} kg is heavier than any debris: at most {MAX_DEBRIS_MASS_KG:.0e} kg (ten times "
                                "the largest ships' displacement); a mass in grams?")
    return m


def check_flow_speed(velocity_m_s: float, field: str = "velocity_m_s") -> float:
    """``velocity_m_s`` (> 0 and at most :data:`MAX_FLOW_SPEED_M_S`), else InputError on ``field``."""
    v = require_positive(field, velocity_m_s)
    if v > MAX_FLOW_SPEED_M_S:
        raise InputError(field, f"{v:g} m/s is faster than any tsunami flow: the bound is {MAX_FLOW_SPEED_M_S:g} m/s "
                                "(the fastest onshore flows measured are about 11 m/s, Fritz et al. 2012; sqrt(g h) "
                                "over a 40 m inundation is 20 m/s); a speed in m/s?")
    return v


def check_debris_stiffness(stiffness_N_m: float, field: str = "debris_stiffness_N_m") -> float:
    """``stiffness_N_m`` within :data:`DEBRIS_STIFFNESS_RANGE_N_M`, else InputError on ``field``."""
    return _stiffness_within(stiffness_N_m, field, DEBRIS_STIFFNESS_RANGE_N_M, "debris stiffness",
                             "the study's 1:40 model container 3.04e6 N/m; full-scale containers and logs 1e7-1e8 "
                             "N/m); a value in MN/m or kip/in given as N/m?")


def _stiffness_within(stiffness_N_m: float, field: str, bounds: tuple[float, float], what: str, examples: str) -> float:
    """``stiffness_N_m`` (> 0) within ``bounds``, else InputError on ``field`` naming ``what`` it
    is not and ``examples`` (the bracket's text and its hint) of what it may be."""
    k = require_positive(field, stiffness_N_m)
    lo, hi = bounds
    if not lo <= k <= hi:
        raise InputError(field, f"{k:g} N/m is no {what}: the plausible range is {lo:.0e}-{hi:.0e} N/m ({examples}")
    return k


def check_full_scale_mass(mass_kg: float, field: str = "mass_kg") -> float:
    """A full-scale debris mass: at least :data:`FULL_SCALE_MIN_MASS_KG`, else InputError on ``field``."""
    m = require_positive(field, mass_kg)
    if m < FULL_SCALE_MIN_MASS_KG:
        raise InputError(field, f"{m:g} kg is no full-scale debris: full scale starts at {FULL_SCALE_MIN_MASS_KG:g} kg "
                                "(the lightest debris ASCE 7-22 6.11 designs for, a log, is about 454 kg; a 20-ft "
                                "container 2,300 kg empty); a mass in tonnes?")
    return m


SIMPLIFIED_STATIC_LOAD_N = 1.47e6
"""The alternative simplified debris impact static load of ASCE 7-16/7-22 Section 6.11, before
``C_o I_tsu``: ``F_i = 330 C_o I_tsu`` kips (``1,470 C_o I_tsu`` kN), the bound the detailed impact
force of 6.11.2 need not exceed. A full-scale (prototype) force: see :class:`AsceDesign`.

Source: ASCE/SEI 7-16 and 7-22, Chapter 6, Section 6.11 (the simplified static load's clause);
the figure 330 kips / 1,470 kN is the standard's. The printed clause could not be retrieved
while this was written: check its number and wording against the standard before citing it
in a design.
"""


@dataclass(frozen=True)
class AsceDesign:
    """The design impact force of ASCE 7-22 6.11.2 from both stiffnesses: the lesser governs.

    6.11.2 takes ``k`` as the lesser of the impacting debris' effective stiffness ``k_d`` and the
    lateral stiffness ``k_s`` of the structural element the impact deforms. :attr:`design` is the
    impact with the governing (lesser) stiffness: its ``force_N`` is THE design value. :attr:`other`
    is the impact with the other stiffness, context only (the study tabulated both).

    ``velocity_m_s`` is the standard's ``u_max``, the flow's maximum velocity at the site (where
    the water is deep enough to float the debris); the study put each record's measured impact
    speed there instead. Either is a number the caller chooses; the result says which it holds
    (``velocity_basis``).

    The simplified static load (:data:`SIMPLIFIED_STATIC_LOAD_N`, ``1,470 C_o I_tsu`` kN) bounds
    the design force only at prototype scale (``prototype=True``). A laboratory model is not
    capped by it: the bound is a full-scale force for full-scale containers and structures, so
    in newtons it never binds a 1:40 model's hundreds of newtons, and Froude-scaled by the length
    scale cubed (``1,470 C_o kN / 40^3 = 14.9 N`` at 1:40 with C_o = 0.65) it would cap every
    laboratory impact, though the model column's stiffness (acrylic, 4.685e5 N/m) is no scaled
    prototype stiffness, so a laboratory impact force is no scaled prototype force either.
    """

    velocity_m_s: float
    mass_kg: float
    debris_stiffness_N_m: float
    structure_stiffness_N_m: float
    importance: float = 1.0
    orientation: float = ORIENTATION_CONTAINER
    prototype: bool = False
    velocity_basis: str = "u_max"

    def __post_init__(self):
        for name in ("debris_stiffness_N_m", "structure_stiffness_N_m"):
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))
        self.design  # checks the remaining inputs (AsceImpact)

    @property
    def governing(self) -> str:
        """``"k_s"`` (the structure's lateral stiffness) or ``"k_d"`` (the debris'): the lesser."""
        return "k_s" if self.structure_stiffness_N_m <= self.debris_stiffness_N_m else "k_d"

    def _impact(self, stiffness_N_m: float) -> AsceImpact:
        return AsceImpact(self.velocity_m_s, self.mass_kg, stiffness_N_m, self.importance, self.orientation)

    @property
    def design(self) -> AsceImpact:
        """The impact with the governing (lesser) stiffness."""
        return self._impact(min(self.structure_stiffness_N_m, self.debris_stiffness_N_m))

    @property
    def other(self) -> AsceImpact:
        """The impact with the other (greater) stiffness: context, not a design value."""
        return self._impact(max(self.structure_stiffness_N_m, self.debris_stiffness_N_m))

    @property
    def cap_N(self) -> float:
        """``1,470 C_o I_tsu`` kN in newtons (a prototype-scale force)."""
        return SIMPLIFIED_STATIC_LOAD_N * self.orientation * self.importance

    @property
    def capped(self) -> bool:
        """Whether the cap bounds the design force (only at prototype scale)."""
        return self.prototype and self.design.force_N > self.cap_N

    @property
    def force_N(self) -> float:
        """THE design impact force F_i, N: the governing stiffness's, bounded by the cap at prototype scale."""
        return min(self.design.force_N, self.cap_N) if self.capped else self.design.force_N

    @property
    def binding(self) -> str:
        """What sets F_i: ``"k_s"`` or ``"k_d"`` (the governing stiffness's force), or
        ``"simplified static load"`` (the cap, at full scale, when the stiffness's force exceeds it)."""
        return "simplified static load" if self.capped else self.governing

    def cap_note(self) -> str:
        """One sentence: the cap, whether it applies, and what binds F_i."""
        cap = f"the simplified static load 1,470 C_o I_tsu kN = {self.cap_N / 1e3:,.1f} kN"
        if self.prototype:
            if self.capped:
                return (f"full scale: {cap} bounds F_i and is applied: it binds (the {self.governing} line's "
                        f"{self.design.force_N / 1e3:,.1f} kN exceeds it)")
            return (f"full scale: {cap} bounds F_i, not reached: the {self.governing} line binds "
                    f"({self.design.force_N / 1e3:,.1f} kN)")
        return (f"{cap} is a full-scale bound: not applied to these laboratory-scale inputs (neither in newtons, "
                "where it never binds, nor Froude-scaled, where it would cap every model impact although the "
                "model column's stiffness is not scaled)")

    def to_dict(self) -> dict[str, float | str | bool]:
        """The design value with its basis, and the other stiffness's force as context (keys with units)."""
        d, o = self.design, self.other
        return {
            "force_N": self.force_N,
            "governing_stiffness": self.governing,
            "stiffness_N_m": d.stiffness_N_m,
            "velocity_m_s": self.velocity_m_s,
            "velocity_basis": self.velocity_basis,
            "mass_kg": self.mass_kg,
            "nominal_force_N": d.nominal_force_N,
            "duration_s": d.duration_s,
            "impulse_Ns": d.impulse_Ns,
            "debris_stiffness_N_m": self.debris_stiffness_N_m,
            "structure_stiffness_N_m": self.structure_stiffness_N_m,
            "other_stiffness": "k_d" if self.governing == "k_s" else "k_s",
            "other_force_N": o.force_N,
            "other_duration_s": o.duration_s,
            "importance_I_tsu": self.importance,
            "orientation_C_o": self.orientation,
            "cap_N": self.cap_N,
            "capped": self.capped,
            "binding": self.binding,
            "prototype": self.prototype,
        }


def asce7_design(velocity_m_s: float, mass_kg: float, debris_stiffness_N_m: float = STUDY_DEBRIS_STIFFNESS_N_M,
                 structure_stiffness_N_m: float = STUDY_STRUCTURE_STIFFNESS_N_M, importance: float = 1.0,
                 orientation: float = ORIENTATION_CONTAINER, prototype: bool = False,
                 velocity_basis: str = "u_max") -> AsceDesign:
    """The ASCE 7-22 6.11.2 design impact force with the governing (lesser) stiffness (:class:`AsceDesign`).

    Examples
    --------
    >>> d = asce7_design(1.50, 0.236)        # the study's container and column, Table 1's speed
    >>> d.governing, round(d.force_N, 1), round(d.other.force_N, 1)
    ('k_s', 324.2, 825.8)
    """
    return AsceDesign(velocity_m_s, mass_kg, debris_stiffness_N_m, structure_stiffness_N_m, importance, orientation,
                      prototype, velocity_basis)
