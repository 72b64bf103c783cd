"""Added mass and added inertia of a floating rectangular box, per body axis.

A box of length ``L`` (body ``x``), beam ``B`` (``y``) and height ``H`` (``z``) floating upright
in water of density ``rho`` sinks to the draft ``d = m / (rho L B)``. Accelerating it moves water;
the water's reaction is an added mass ``A_i`` per translation (surge ``x``, sway ``y``, heave
``z``) and an added moment of inertia per rotation (roll about ``x``, pitch about ``y``, yaw
about ``z``). :func:`box_added_mass` returns the six diagonal terms (the box's symmetry makes
the translational block diagonal; the couplings between, e.g., sway and roll through the
centre of the wetted part are left out) as an :class:`AddedMass`, both as masses / inertias
and as coefficients: ``C_a = A / (rho V)`` with ``V = L B d`` the displaced volume (equal to
the body mass for a floating body), and ``A_rot / I_fluid`` with ``I_fluid`` the displaced
water's own moment of inertia about that axis.

The free surface (impulsive limit)
----------------------------------
An impact lasts a few milliseconds; over such times gravity cannot raise waves
(``omega^2 L / g`` is about 3e3 for a 5 ms pulse on a 0.15 m body), so the free surface is
an equipotential, ``phi = 0`` (the infinite-frequency limit; Newman 1977, ch. 6). The
body and its mirror image in the free surface form a *double body* ``L x B x 2d`` in an
unbounded fluid, and the floating body's added mass is half the double body's when the
double body moves as one rigid piece. That is:

* exact (in this limit) for heave, roll and pitch: the mirror image moves so that
  ``phi`` is odd across the surface;
* the rigid-lid value (``d phi / d z = 0`` on the surface, the free surface treated as a
  rigid symmetry plane) for surge, sway and yaw. It is an **upper bound** on the impulsive
  value: with ``phi = 0`` water may cross the surface plane, and Kelvin's minimum-energy
  theorem gives the less constrained flow the smaller kinetic energy.

A body that would sink (``m >= rho L B H``) is treated as fully submerged far from the
surface: the box itself in an unbounded fluid.

Translation (DNV)
-----------------
DNV-RP-H103 (2011), sec. 4.6.3.3 (the same in DNV-RP-C205 (2010), App. A): a body with
straight sides parallel to the motion, of extent ``h`` along it and projected area
``A_p = p q`` (``p <= q``) normal to it, has

    A = [1 + sqrt((1 - lambda^2) / (2 (1 + lambda^2)))] A_o,   lambda = sqrt(A_p) / (h + sqrt(A_p))

with ``A_o = C_A (pi / 4) rho p^2 q`` the added mass of the flat plate ``p x q``
(:data:`DNV_PLATE_TABLE`, DNV-RP-C205 Table A-2, "rectangular plates"). The formula is checked
against DNV's own tabulated square prisms (:data:`DNV_SQUARE_PRISM_TABLE`, ``A = C_A rho a^2 b``
along the prism's axis ``b``): within 6 % for ``b/a`` = 1 to 10 (tests/test_added_mass.py);
a cube gives 0.704 against the table's 0.68.

Rotation (Lamb's ellipsoid)
---------------------------
No table for a rotating box was found to cite. The rotational coefficients are those of the
ellipsoid with the (double) box's half-sides as semi-axes, in an unbounded fluid (Lamb 1932,
sec. 114-115; Newman 1977, ch. 4): with ``alpha_0, beta_0, gamma_0`` the ellipsoid's
integrals (:func:`ellipsoid_integrals`),

    A_roll / I_fluid = (b^2 - c^2)^2 (gamma_0 - beta_0) / [(b^2 + c^2) (2 (b^2 - c^2) + (b^2 + c^2) (beta_0 - gamma_0))]

(and the cyclic permutations), applied to the box's displaced water's moment of inertia
(about the double body's centre, on the waterline). A sphere gives 0; a prolate spheroid of
axis ratio 2 gives Lamb's tabulated 0.240 (a test). The substitution is an approximation: for
translation the same ellipsoid gives a cube 0.50 against the box's 0.68, so the box's
rotational values are probably low by about a quarter.

The study's 1:40 container
--------------------------
0.15 x 0.06 x 0.06 m, 0.236 kg, in fresh water (998 kg/m^3): draft 0.0263 m (double body
0.15 x 0.06 x 0.0526 m); :data:`STUDY_CONTAINER_ADDED_MASS`:

========  ======  =============  ==========================
axis      C_a     added mass     source
========  ======  =============  ==========================
surge x   0.280   0.066 kg       DNV-RP-H103 4.6.3.3, upper bound
sway y    0.840   0.198 kg       DNV-RP-H103 4.6.3.3, upper bound
heave z   1.045   0.247 kg       DNV-RP-H103 4.6.3.3
roll x    0.016   2.0e-6 kg m^2  Lamb's ellipsoid
pitch y   0.481   2.4e-4 kg m^2  Lamb's ellipsoid
yaw z     0.333   1.7e-4 kg m^2  Lamb's ellipsoid, upper bound
========  ======  =============  ==========================

(rotational ``C`` relative to the displaced water's moment of inertia). Moving lengthwise the
container carries about a quarter of its mass of water; broadside nearly its whole mass.

References
----------
DNV (2011). Recommended Practice DNV-RP-H103, Modelling and Analysis of Marine Operations,
    sec. 4.6.3.3 and Appendix A.
DNV (2010). Recommended Practice DNV-RP-C205, Environmental Conditions and Environmental
    Loads, Appendix A (Tables A-1, A-2).
Lamb, H. (1932). Hydrodynamics, 6th ed. Cambridge University Press, sec. 114-115 (the
    ellipsoid's added masses and added moments of inertia; the prolate spheroid's table).
Newman, J.N. (1977). Marine Hydrodynamics. MIT Press, ch. 4 (added mass of ellipsoids),
    ch. 6 (the infinite-frequency limit of a floating body).
Carlson, B.C. (1995). Numerical computation of real or complex elliptic integrals. Numerical
    Algorithms 10, 13-26 (``R_D``, used for the ellipsoid integrals).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import elliprd

from analytical.errors import InputError, require_positive
from analytical.study import STUDY_CONTAINER_SIZE_M, STUDY_DEBRIS_MASS_KG

__all__ = [
    "AXES",
    "DNV_PLATE_TABLE",
    "DNV_SQUARE_PRISM_TABLE",
    "STUDY_CONTAINER_ADDED_MASS",
    "WATER_DENSITY_KG_M3",
    "AddedMass",
    "box_added_mass",
    "dnv_block_added_mass",
    "ellipsoid_coefficients",
    "ellipsoid_integrals",
]

WATER_DENSITY_KG_M3 = 998.0
"""Fresh water at 20 C (the density analytical.hydrodynamics uses)."""

AXES = ("surge", "sway", "heave", "roll", "pitch", "yaw")

DNV_PLATE_TABLE = (
    (1.0, 1.25, 1.5, 1.59, 2.0, 2.5, 3.0, 3.17, 4.0, 5.0, 6.25, 8.0, 10.0, math.inf),
    (0.579, 0.642, 0.690, 0.704, 0.757, 0.801, 0.830, 0.840, 0.872, 0.897, 0.917, 0.934, 0.947, 1.000),
)
"""DNV-RP-C205 Table A-2, rectangular flat plate ``a x b`` (``b >= a``) moving normal to itself:
(``b / a``, ``C_A``) with added mass ``C_A (pi / 4) rho a^2 b``."""

DNV_SQUARE_PRISM_TABLE = (
    (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 10.0),
    (0.68, 0.36, 0.24, 0.19, 0.15, 0.13, 0.11, 0.08),
)
"""DNV-RP-C205 Table A-2, square prism ``a x a x b`` moving along ``b``: (``b / a``, ``C_A``)
with added mass ``C_A rho a^2 b``. Used here as a check of :func:`dnv_block_added_mass`."""


def _plate_coefficient(ratio: float) -> float:
    """``C_A`` of a rectangular plate of side ratio ``ratio`` >= 1 (DNV Table A-2, interpolated;
    beyond 10 towards the strip's 1.0 as ``1 - 0.53 / ratio``, which meets the table at 10)."""
    ratios, values = DNV_PLATE_TABLE
    if ratio <= ratios[-2]:
        return float(np.interp(ratio, ratios[:-1], values[:-1]))
    return 1.0 - (1.0 - values[-2]) * ratios[-2] / ratio


def dnv_block_added_mass(along_m: float, across_m: tuple[float, float], density_kg_m3: float) -> float:
    """Added mass (kg) of a rectangular block in an unbounded fluid moving along one of its
    edges: ``along_m`` its extent along the motion, ``across_m`` the two sides normal to it
    (DNV-RP-H103 sec. 4.6.3.3 with the plate table; see the module docstring)."""
    h = require_positive("along_m", along_m)
    p, q = sorted(require_positive("across_m", s) for s in across_m)
    rho = require_positive("water_density_kg_m3", density_kg_m3)
    plate = _plate_coefficient(q / p) * math.pi / 4.0 * rho * p * p * q
    root = math.sqrt(p * q)
    lam = root / (h + root)
    return plate * (1.0 + math.sqrt((1.0 - lam * lam) / (2.0 * (1.0 + lam * lam))))


def ellipsoid_integrals(a: float, b: float, c: float) -> tuple[float, float, float]:
    """Lamb's ``alpha_0, beta_0, gamma_0`` of the ellipsoid with semi-axes ``a, b, c``:
    ``alpha_0 = a b c int_0^inf dl / ((a^2 + l) D)``, ``D = sqrt((a^2 + l)(b^2 + l)(c^2 + l))``,
    which is ``(2/3) a b c R_D(b^2, c^2, a^2)`` (Carlson's symmetric integral). They sum to 2."""
    a, b, c = (require_positive("semi_axis_m", s) for s in (a, b, c))
    abc = a * b * c
    return (2.0 / 3.0 * abc * float(elliprd(b * b, c * c, a * a)),
            2.0 / 3.0 * abc * float(elliprd(c * c, a * a, b * b)),
            2.0 / 3.0 * abc * float(elliprd(a * a, b * b, c * c)))


def ellipsoid_coefficients(a: float, b: float, c: float) -> tuple[float, ...]:
    """The six added-mass coefficients of an ellipsoid in an unbounded fluid (Lamb 1932, sec.
    114-115): translations ``alpha_0 / (2 - alpha_0)`` etc. (relative to the displaced mass),
    rotations about ``x, y, z`` relative to the displaced fluid's moment of inertia."""
    al, be, ga = ellipsoid_integrals(a, b, c)

    def rotation(p2, q2, g_p, g_q):
        # about the axis normal to the semi-axes p, q; Lamb's (b^2-c^2)^2 (g0-b0) / [2(b^2-c^2) + (b^2+c^2)(b0-g0)]
        # over the fluid's (p^2 + q^2) / 5
        diff = p2 - q2
        if abs(diff) <= 1e-12 * (p2 + q2):
            return 0.0
        return diff * diff * (g_q - g_p) / ((p2 + q2) * (2.0 * diff + (p2 + q2) * (g_p - g_q)))

    a2, b2, c2 = a * a, b * b, c * c
    return (al / (2.0 - al), be / (2.0 - be), ga / (2.0 - ga),
            rotation(b2, c2, be, ga), rotation(c2, a2, ga, al), rotation(a2, b2, al, be))


@dataclass(frozen=True)
class AddedMass:
    """The diagonal added-mass tensor of a box in its body axes (x along its length, z up).

    ``masses_kg`` (surge, sway, heave), ``inertias_kg_m2`` (roll, pitch, yaw),
    ``coefficients`` (the six ``C_a``: translations relative to ``displaced_mass_kg``,
    rotations relative to the displaced water's moment of inertia about the same axis).
    ``floating`` is False for a body that would sink (treated as deep-submerged).
    """

    size_m: tuple[float, float, float]
    mass_kg: float
    draft_m: float
    displaced_mass_kg: float
    floating: bool
    coefficients: tuple[float, float, float, float, float, float]
    masses_kg: tuple[float, float, float]
    inertias_kg_m2: tuple[float, float, float]

    @property
    def diagonal(self) -> np.ndarray:
        """The six diagonal terms (kg, kg, kg, kg m^2, kg m^2, kg m^2), surge to yaw."""
        return np.array(self.masses_kg + self.inertias_kg_m2)

    def along(self, direction_body) -> float:
        """Added mass (kg) for a translation along ``direction_body`` (body frame; normalised):
        ``n^T diag(A) n``."""
        n = np.asarray(direction_body, dtype=float).reshape(-1)
        norm = float(np.linalg.norm(n)) if n.shape == (3,) else 0.0
        if not (norm > 0.0 and math.isfinite(norm)):
            raise InputError("direction_body", f"must be a finite non-zero 3-vector, got {direction_body!r}")
        n = n / norm
        return float(n @ (np.array(self.masses_kg) * n))

    def coefficient_along(self, direction_body) -> float:
        """``along(direction) / mass_kg``: the ``C_a`` a body with a scalar added-mass
        coefficient (:class:`analytical.impact_bodies.Body`) needs for that direction."""
        return self.along(direction_body) / self.mass_kg

    def to_dict(self) -> dict:
        return {"size_m": list(self.size_m), "mass_kg": self.mass_kg, "draft_m": self.draft_m,
                "floating": self.floating, **{f"C_a_{a}": c for a, c in zip(AXES, self.coefficients)},
                "added_masses_kg": list(self.masses_kg), "added_inertias_kg_m2": list(self.inertias_kg_m2)}


def box_added_mass(size_m, mass_kg: float, water_density_kg_m3: float = WATER_DENSITY_KG_M3) -> AddedMass:
    """The added mass of a box ``size_m = (L, B, H)`` (m) of ``mass_kg`` floating upright, in the
    impulsive limit (module docstring: double body; surge, sway and yaw rigid-lid upper bounds)."""
    if len(tuple(size_m)) != 3:
        raise InputError("size_m", f"must be (length, beam, height), got {size_m!r}")
    length, beam, height = (require_positive("size_m", s) for s in size_m)
    m = require_positive("mass_kg", mass_kg)
    rho = require_positive("water_density_kg_m3", water_density_kg_m3)
    draft = m / (rho * length * beam)
    floating = draft < height
    # the double body (floating) or the body itself (sunk, deep); its half or its whole
    depth, share = (2.0 * draft, 0.5) if floating else (height, 1.0)
    draft = min(draft, height)
    displaced = rho * length * beam * draft
    masses = (share * dnv_block_added_mass(length, (beam, depth), rho),
              share * dnv_block_added_mass(beam, (length, depth), rho),
              share * dnv_block_added_mass(depth, (length, beam), rho))
    fluid_inertia = (displaced * (beam**2 + depth**2) / 12.0, displaced * (length**2 + depth**2) / 12.0,
                     displaced * (length**2 + beam**2) / 12.0)
    rot = ellipsoid_coefficients(length / 2.0, beam / 2.0, depth / 2.0)[3:]
    inertias = tuple(c * i for c, i in zip(rot, fluid_inertia))
    coefficients = tuple(a / displaced for a in masses) + tuple(rot)
    return AddedMass((length, beam, height), m, draft, displaced, floating, coefficients, masses, inertias)


STUDY_CONTAINER_ADDED_MASS = box_added_mass(STUDY_CONTAINER_SIZE_M, STUDY_DEBRIS_MASS_KG)
"""The study's 1:40 container afloat in fresh water (see the module docstring's table)."""
