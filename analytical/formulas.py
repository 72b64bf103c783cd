"""Empirical and semi-analytical debris impact force formulas (study Sec. 2.1, eqs. [1]-[5]).

Each function returns the maximum impact force in N. Inputs are SI; scalars give a float,
arrays (NumPy broadcasting) give an array. Bad input raises ``InputError`` naming the argument.

Scaling with the impact velocity u: Haehnel and Daly F ~ u (a linear spring, energy
conservation); Matsutomi and Ikeno F ~ u^1.2 (Hertz-type contact, force ~ (kinetic energy)^0.6).

Added-mass coefficients used by default (the original papers could not be retrieved here, so
these are the values as commonly quoted from them; override them as needed):

* Matsutomi (1999, 2009): apparent-mass coefficient C_MA = 1.7 for impacts in a bore or surge
  (the dam-break case), 1.9 in steady flow (:data:`MATSUTOMI_CMA_BORE`, :data:`MATSUTOMI_CMA_STEADY`).
* Ikeno et al. (2013, 2016): the same bore value 1.7 is used by default (an assumption of this
  package); ``added_mass_coefficient=1.0`` gives the in-air (no added mass) impact.
"""

from __future__ import annotations

import numpy as np

from analytical.errors import InputError

__all__ = [
    "haehnel_daly",
    "matsutomi",
    "ikeno",
    "hertz_effective_modulus",
    "MATSUTOMI_CMA_BORE",
    "MATSUTOMI_CMA_STEADY",
    "IKENO_KAPPA",
    "GRAVITY_M_S2",
]

MATSUTOMI_CMA_BORE = 1.7
"""Matsutomi's apparent-mass coefficient for driftwood in a bore/surge (as commonly quoted)."""

MATSUTOMI_CMA_STEADY = 1.9
"""Matsutomi's apparent-mass coefficient for driftwood in steady flow (as commonly quoted)."""

IKENO_KAPPA = 0.243
"""Ikeno et al. (2013) dimensionless coefficient kappa (study eq. [5])."""

GRAVITY_M_S2 = 9.81


def _positive(name: str, value) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a number or an array of numbers, got {value!r}") from None
    if arr.size == 0:
        raise InputError(name, "must not be empty")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise InputError(name, f"must be finite and > 0, got {value!r}")
    return arr


def _result(value: np.ndarray, *inputs: np.ndarray):
    return float(value) if all(np.ndim(x) == 0 for x in inputs) else value


def haehnel_daly(velocity_m_s, mass_kg, stiffness_N_m, structure_stiffness_N_m=None):
    """Maximum impact force of a debris item, ``F = u sqrt(k m)`` (Haehnel and Daly 2004; study eq. [1]).

    The debris (mass ``m``) strikes through a linear contact spring ``k`` and stops; all its
    kinetic energy goes into the spring: ``k x^2 / 2 = m u^2 / 2``, ``F = k x = u sqrt(k m)``.
    This is ASCE 7-22's nominal force F_ni (Clause 6.11.2).

    Parameters
    ----------
    velocity_m_s:
        Impact velocity ``u``, m/s (> 0).
    mass_kg:
        Debris mass ``m``, kg (> 0) (with added mass, if wanted).
    stiffness_N_m:
        Debris (contact) stiffness ``k_d``, N/m (> 0); the effective stiffness when
        ``structure_stiffness_N_m`` is not given.
    structure_stiffness_N_m:
        Optional structure stiffness ``k_s``, N/m: then ``k = k_s k_d / (k_s + k_d)`` (study eq. [2]).

    Returns
    -------
    float or numpy.ndarray
        Maximum force, N.

    Notes
    -----
    Valid range (per the authors): elastic debris, rigid structure (or the series spring),
    negligible damping, head-on (longitudinal) impact; calibrated on woody debris (logs) in
    floodplain flows. ASCE 7-22 multiplies by ``I_tsu C_o`` for orientation and importance.
    """
    u = _positive("velocity_m_s", velocity_m_s)
    m = _positive("mass_kg", mass_kg)
    k = _positive("stiffness_N_m", stiffness_N_m)
    if structure_stiffness_N_m is None:
        return _result(u * np.sqrt(k * m), u, m, k)
    ks = _positive("structure_stiffness_N_m", structure_stiffness_N_m)
    k_eff = ks * k / (ks + k)  # series springs, study eq. [2] (as asce7.effective_stiffness)
    return _result(u * np.sqrt(k_eff * m), u, m, k, ks)


def matsutomi(
    velocity_m_s,
    diameter_m,
    length_m,
    unit_weight_N_m3,
    yield_stress_Pa,
    added_mass_coefficient=MATSUTOMI_CMA_BORE,
    g=GRAVITY_M_S2,
):
    """Maximum collision force of driftwood (Matsutomi 2009; study eq. [4]).

    ``F = 1.6 C_MA (v / sqrt(g D))^1.2 (sigma_f / (gamma L))^0.4 gamma D^2 L``

    Parameters
    ----------
    velocity_m_s:
        Collision velocity ``v_A0``, m/s (> 0).
    diameter_m:
        Log diameter ``D_w``, m (> 0).
    length_m:
        Log length ``L_w``, m (> 0).
    unit_weight_N_m3:
        Unit weight of the debris ``gamma_d = rho_d g``, N/m^3 (> 0).
    yield_stress_Pa:
        Yield stress of the wood ``sigma_f``, Pa (> 0).
    added_mass_coefficient:
        Apparent-mass coefficient ``C_MA`` (1.7 in a bore or surge, 1.9 in steady flow, as
        commonly quoted from Matsutomi; 1.7 by default, the dam-break case).
    g:
        Gravitational acceleration, m/s^2.

    Returns
    -------
    float or numpy.ndarray
        Maximum force, N. ``F ~ v^1.2``.

    Notes
    -----
    Dimensionally consistent: ``gamma D^2 L`` is the log's weight (N) and the two brackets are
    dimensionless. Valid range: end-on collisions of cylindrical wooden logs with a rigid
    structure, in air, bores or steady flow, as in the author's experiments (laboratory and
    larger-scale wooden logs). The original parameter ranges could not be verified here; treat
    any non-log debris (e.g. the study's 1:40 polyethylene container) as an extrapolation.

    References
    ----------
    Matsutomi, H. (2009). Method for estimating collision force of driftwood accompanying tsunami
    inundation flow. *J. Disaster Research* 4(6), 435-440. Matsutomi, H. (1999), JSCE
    No. 621/II-47, 111-127 (the original formula, in Japanese).
    """
    v = _positive("velocity_m_s", velocity_m_s)
    D = _positive("diameter_m", diameter_m)
    L = _positive("length_m", length_m)
    gam = _positive("unit_weight_N_m3", unit_weight_N_m3)
    sig = _positive("yield_stress_Pa", yield_stress_Pa)
    cma = _positive("added_mass_coefficient", added_mass_coefficient)
    gg = _positive("g", g)
    froude = v / np.sqrt(gg * D)
    strength = sig / (gam * L)
    force = 1.6 * cma * froude**1.2 * strength**0.4 * gam * D**2 * L
    return _result(force, v, D, L, gam, sig, cma, gg)


def ikeno(
    velocity_m_s,
    mass_kg,
    diameter_m,
    effective_modulus_Pa,
    added_mass_coefficient=MATSUTOMI_CMA_BORE,
    kappa=IKENO_KAPPA,
):
    """Maximum collision force, Hertz-contact type (Ikeno et al. 2013, 2016; study eq. [5]).

    ``F = kappa (C_MA m)^0.6 V_H^1.2 D^0.2 E~^0.4``

    Parameters
    ----------
    velocity_m_s:
        Collision speed ``V_H``, m/s (> 0).
    mass_kg:
        Debris mass ``m``, kg (> 0).
    diameter_m:
        Debris diameter ``D``, m (> 0).
    effective_modulus_Pa:
        Effective Young's modulus ``E~``, Pa (> 0); for two elastic bodies see
        :func:`hertz_effective_modulus`.
    added_mass_coefficient:
        ``C_MA`` multiplying the mass (1.0 = in air; 1.7 by default, the bore value quoted from
        Matsutomi: an assumption of this package).
    kappa:
        Dimensionless coefficient, 0.243 (Ikeno et al. 2013).

    Returns
    -------
    float or numpy.ndarray
        Maximum force, N. ``F ~ V^1.2`` and ``(C_MA m)^0.6``: force ~ (kinetic energy)^0.6.

    Notes
    -----
    Dimensions: kg^0.6 (m/s)^1.2 m^0.2 Pa^0.4 = N. Valid range: the in-air and in-water
    experiments of the authors on woody (cylindrical) debris impacting end-on; Ikeno et al.
    (2016) add the collision angle (not modelled here). Parameter ranges could not be verified
    here; container debris is an extrapolation.

    References
    ----------
    Ikeno, M. et al. (2013): Hertz-type collision force formula for woody debris, validated by
    in-air and in-water experiments; Ikeno, M. et al. (2016): the same with the collision angle.
    Both as cited by the study, Sec. 2.1 (full references in the study's bibliography).
    """
    v = _positive("velocity_m_s", velocity_m_s)
    m = _positive("mass_kg", mass_kg)
    D = _positive("diameter_m", diameter_m)
    E = _positive("effective_modulus_Pa", effective_modulus_Pa)
    cma = _positive("added_mass_coefficient", added_mass_coefficient)
    kap = _positive("kappa", kappa)
    force = kap * (cma * m) ** 0.6 * v**1.2 * D**0.2 * E**0.4
    return _result(force, v, m, D, E, cma, kap)


def hertz_effective_modulus(E1_Pa, nu1, E2_Pa, nu2) -> float:
    """Hertz contact modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``, Pa.

    Parameters
    ----------
    E1_Pa, E2_Pa:
        Young's moduli of the two bodies, Pa (> 0).
    nu1, nu2:
        Poisson's ratios, in [0, 0.5).

    Returns
    -------
    float
        ``E*``, Pa (Johnson 1985, *Contact Mechanics*, eq. 4.22).
    """
    e1 = float(_positive("E1_Pa", E1_Pa))
    e2 = float(_positive("E2_Pa", E2_Pa))
    out = 0.0
    for name, nu, e in (("nu1", nu1, e1), ("nu2", nu2, e2)):
        try:
            n = float(nu)
        except (TypeError, ValueError):
            raise InputError(name, f"must be a number, got {nu!r}") from None
        if not (0.0 <= n < 0.5):
            raise InputError(name, f"must be in [0, 0.5), got {nu!r}")
        out += (1.0 - n * n) / e
    return 1.0 / out
