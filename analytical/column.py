"""The impacted column: geometry, material and measured dynamic properties.

A :class:`Column` is a frozen, validated description of a rectangular hollow (or solid)
cantilever column loaded laterally along ``x`` (the flume direction). Its defaults are
the reference study's acrylic column (the study's section 3.1):

* 0.20 x 0.20 x 0.80 m square hollow section, 5 mm wall;
* E = 2.50 GPa, rho = 1200 kg/m^3, nu = 0.375, Timoshenko shear coefficient 0.50
  (thin-walled hollow section);
* measured first natural frequency 70 Hz (+-2.2 Hz), measured lateral stiffness
  4.685e5 N/m (4.653e5-4.701e5), damping ratio 0.045 (+-0.005) (Stolle et al. 2019).

The measured ``natural_frequency_Hz`` and ``stiffness_N_m`` drive the SDOF model and the
ASCE 7-22 stiffness; the geometry and material drive the MDOF beam model
(:mod:`analytical.mdof`). ``base`` chooses the MDOF support: ``"rigid"`` (the study's
MDOF, built from the geometry alone; f1 about 88 Hz), ``"calibrated"`` (a rotational
base spring tuned so the beam's f1 equals ``natural_frequency_Hz``) or ``"spring"`` (a
rotational base spring of the given ``base_spring_Nm_rad``). ``ends`` restrains the member's top:
``"cantilever"`` (free, the default), ``"fixed-fixed"`` (the top held in translation and
rotation, as a floor restrains a column between storeys) or ``"pinned"`` (both ends held in
translation only); a restrained top needs ``base="rigid"``.

Sections other than a rectangular box (solid or circular concrete, steel pipes and W-shapes:
:mod:`analytical.sections`) give their own ``section_area_m2`` and ``section_second_moment_m4``;
the box sizes then describe only the footprint the flow and the debris meet. A cracked
reinforced-concrete section scales its flexural rigidity by ``stiffness_factor`` (ACI 318's
0.70 for columns); its mass and rotary inertia stay the gross section's.

Units are SI throughout and carried in the field names.

References
----------
Stolle, J., Derschum, C., Goseberg, N., Nistor, I. & Petriu, E. (2019). Debris impact
    under extreme hydrodynamic conditions part 2: impact force responses for non-rigid
    debris collisions. Coastal Engineering 141, 107-118.
Cowper, G.R. (1966). The shear coefficient in Timoshenko's beam theory. Journal of
    Applied Mechanics 33(2), 335-340.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytical.errors import InputError, require_finite, require_positive

__all__ = ["BASES", "ENDS", "MAX_ELEMENTS", "Column"]

#: Accepted values of :attr:`Column.base`.
BASES = ("rigid", "calibrated", "spring")
#: Accepted values of :attr:`Column.ends`.
ENDS = ("cantilever", "fixed-fixed", "pinned")
#: Most Timoshenko elements a column model may have. Its modes come from a dense eigenproblem of
#: about 2 x elements degrees of freedom: measured here 0.5 s and 0.1 GB at 160 elements (the
#: study's), 14 s and 0.6 GB at 1,600; time grows with the cube of the count and memory with its
#: square, so 2,000 is about half a minute and a gigabyte, far past where the modes converge.
MAX_ELEMENTS = 2000


@dataclass(frozen=True)
class Column:
    """A laterally loaded cantilever column of rectangular hollow section.

    Attributes
    ----------
    size_x_m:
        Outer section depth in the load (flow, ``x``) direction (m).
    size_y_m:
        Outer section width across the flow (``y``) (m).
    height_m:
        Cantilever length from the base support (load cell) to the free top (m).
    wall_thickness_m:
        Wall thickness (m); ``2 * wall_thickness_m`` equal to the smaller outer size
        gives a solid section.
    youngs_modulus_Pa:
        Young's modulus E (Pa).
    density_kg_m3:
        Material density rho (kg/m^3).
    poisson_ratio:
        Poisson's ratio nu (-), in (-1, 0.5); gives G = E / (2 (1 + nu)).
    shear_coefficient:
        Timoshenko shear coefficient kappa (-), > 0 (0.5 for a thin-walled box, 5/6 for
        a solid rectangle; Cowper 1966).
    natural_frequency_Hz:
        Measured first natural frequency (Hz); the SDOF model's frequency and the
        target of ``base="calibrated"``.
    stiffness_N_m:
        Measured lateral stiffness (N/m); the SDOF model's and ASCE 7-22's stiffness.
    damping_ratio:
        Viscous damping ratio (-), in [0, 1); the SDOF damping and the MDOF Rayleigh
        damping ratio on modes 1 and 2.
    base:
        MDOF base support, ``"rigid"`` or ``"calibrated"`` (see module docstring).
    elements:
        Number of Timoshenko beam elements of the MDOF model (int, 1 to :data:`MAX_ELEMENTS`).
    section_area_m2, section_second_moment_m4:
        The section's area A (m^2) and second moment I (m^4) about the axis the load bends;
        None: the rectangular box's (:attr:`area_m2`, :attr:`second_moment_m4`).
    stiffness_factor:
        Effective-stiffness factor on E I (-), in (0, 1]; 1 for an uncracked section.
    base_spring_Nm_rad:
        Rotational base spring k_theta (N m/rad) of ``base="spring"``; None otherwise.
    ends:
        The member's end conditions, one of :data:`ENDS` (see module docstring); ``height_m``
        is then the length between its supports.
    """

    size_x_m: float = 0.20
    size_y_m: float = 0.20
    height_m: float = 0.80
    wall_thickness_m: float = 0.005
    youngs_modulus_Pa: float = 2.50e9
    density_kg_m3: float = 1200.0
    poisson_ratio: float = 0.375
    shear_coefficient: float = 0.50
    natural_frequency_Hz: float = 70.0
    stiffness_N_m: float = 4.685e5
    damping_ratio: float = 0.045
    base: str = "rigid"
    elements: int = 160
    section_area_m2: float | None = None
    section_second_moment_m4: float | None = None
    stiffness_factor: float = 1.0
    base_spring_Nm_rad: float | None = None
    ends: str = "cantilever"

    def __post_init__(self) -> None:
        positive = (
            "size_x_m",
            "size_y_m",
            "height_m",
            "wall_thickness_m",
            "youngs_modulus_Pa",
            "density_kg_m3",
            "shear_coefficient",
            "natural_frequency_Hz",
            "stiffness_N_m",
        )
        for name in positive:
            value = require_positive(f"column.{name}", getattr(self, name))
            object.__setattr__(self, name, value)

        t = self.wall_thickness_m
        if 2.0 * t > min(self.size_x_m, self.size_y_m) * (1.0 + 1e-12):
            raise InputError(
                "column.wall_thickness_m",
                f"must be <= half the smaller outer size ({min(self.size_x_m, self.size_y_m) / 2:g} m), "
                f"got {t!r}",
            )

        nu = require_finite("column.poisson_ratio", self.poisson_ratio)
        if not -1.0 < nu < 0.5:
            raise InputError("column.poisson_ratio", f"must be in (-1, 0.5), got {self.poisson_ratio!r}")
        object.__setattr__(self, "poisson_ratio", nu)

        zeta = require_finite("column.damping_ratio", self.damping_ratio)
        if not 0.0 <= zeta < 1.0:
            raise InputError("column.damping_ratio", f"must be in [0, 1), got {self.damping_ratio!r}")
        object.__setattr__(self, "damping_ratio", zeta)

        if not isinstance(self.base, str) or self.base not in BASES:
            raise InputError("column.base", f"must be one of {', '.join(BASES)}; got {self.base!r}")

        if not isinstance(self.ends, str) or self.ends not in ENDS:
            raise InputError("column.ends", f"must be one of {', '.join(ENDS)}; got {self.ends!r}")
        if self.ends != "cantilever" and self.base != "rigid":
            raise InputError("column.base", f"must be 'rigid' with ends={self.ends!r} (a base spring is a "
                             f"cantilever's), got {self.base!r}")

        n = self.elements
        if isinstance(n, bool) or not isinstance(n, int):
            if isinstance(n, float) and n.is_integer() and not isinstance(n, bool):
                n = int(n)
            else:
                raise InputError("column.elements", f"must be an integer >= 1, got {self.elements!r}")
        if n < 1:
            raise InputError("column.elements", f"must be an integer >= 1, got {self.elements!r}")
        if n > MAX_ELEMENTS:
            raise InputError("column.elements", f"{n:,} elements is a dense eigenproblem of {2 * n:,} degrees of "
                             f"freedom (about {48 * (2 * n) ** 2 / 1e9:.3g} GB): at most {MAX_ELEMENTS:,}")
        if self.ends == "fixed-fixed" and n < 2:
            raise InputError("column.elements", "must be >= 2 for a fixed-fixed member (one element held at both "
                             f"ends has nothing free to move), got {n}")
        object.__setattr__(self, "elements", n)

        for name in ("section_area_m2", "section_second_moment_m4", "base_spring_Nm_rad"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, require_positive(f"column.{name}", getattr(self, name)))
        factor = require_positive("column.stiffness_factor", self.stiffness_factor)
        if factor > 1.0:
            raise InputError("column.stiffness_factor", f"must be in (0, 1], got {self.stiffness_factor!r}")
        object.__setattr__(self, "stiffness_factor", factor)
        if (self.base == "spring") != (self.base_spring_Nm_rad is not None):
            raise InputError("column.base_spring_Nm_rad", "is required with base='spring' and only with it; got "
                             f"{self.base_spring_Nm_rad!r} with base={self.base!r}")

    # ----------------------------------------------------------------- derived
    @property
    def area_m2(self) -> float:
        """Cross-section area A (m^2): ``section_area_m2`` when given, else the box's."""
        if self.section_area_m2 is not None:
            return self.section_area_m2
        bx, by, t = self.size_x_m, self.size_y_m, self.wall_thickness_m
        return bx * by - max(bx - 2 * t, 0.0) * max(by - 2 * t, 0.0)

    @property
    def second_moment_m4(self) -> float:
        """Second moment of area I (m^4) for bending about ``y`` (load along ``x``).

        ``I = [b_y b_x^3 - (b_y - 2t)(b_x - 2t)^3] / 12``, or ``section_second_moment_m4`` when given.
        """
        if self.section_second_moment_m4 is not None:
            return self.section_second_moment_m4
        bx, by, t = self.size_x_m, self.size_y_m, self.wall_thickness_m
        return (by * bx**3 - max(by - 2 * t, 0.0) * max(bx - 2 * t, 0.0) ** 3) / 12.0

    @property
    def shear_modulus_Pa(self) -> float:
        """Shear modulus G = E / (2 (1 + nu)) (Pa)."""
        return self.youngs_modulus_Pa / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def mass_per_length_kg_m(self) -> float:
        """Mass per unit length rho A (kg/m)."""
        return self.density_kg_m3 * self.area_m2

    @property
    def mass_kg(self) -> float:
        """Total column mass rho A H (kg)."""
        return self.mass_per_length_kg_m * self.height_m

    @property
    def bending_stiffness_Nm2(self) -> float:
        """Flexural rigidity E I (N m^2), times ``stiffness_factor`` (a cracked section's)."""
        return self.youngs_modulus_Pa * self.second_moment_m4 * self.stiffness_factor

    @property
    def shear_stiffness_N(self) -> float:
        """Shear rigidity kappa G A (N)."""
        return self.shear_coefficient * self.shear_modulus_Pa * self.area_m2

    @property
    def rotary_inertia_kg_m(self) -> float:
        """Rotary inertia per unit length rho I (kg m)."""
        return self.density_kg_m3 * self.second_moment_m4

    @property
    def natural_circular_frequency_rad_s(self) -> float:
        """Measured first circular frequency 2 pi f1 (rad/s)."""
        return 2.0 * math.pi * self.natural_frequency_Hz

