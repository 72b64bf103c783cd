"""Tests of analytical.column: the study's defaults, derived section properties, validation."""

from __future__ import annotations

import dataclasses
import math

import pytest

from analytical.column import BASES, Column
from tests.conftest import input_error


def test_defaults_are_the_study_column():
    c = Column()
    assert (c.size_x_m, c.size_y_m, c.height_m, c.wall_thickness_m) == (0.20, 0.20, 0.80, 0.005)
    assert (c.youngs_modulus_Pa, c.density_kg_m3, c.poisson_ratio, c.shear_coefficient) == (2.5e9, 1200.0, 0.375, 0.5)
    assert (c.natural_frequency_Hz, c.stiffness_N_m, c.damping_ratio) == (70.0, 4.685e5, 0.045)
    assert (c.base, c.elements) == ("rigid", 160)


def test_section_properties_of_the_study_column_by_hand():
    c = Column()
    # 0.2 x 0.2 outer, 0.19 x 0.19 inner.
    assert c.area_m2 == pytest.approx(0.2**2 - 0.19**2, rel=1e-12)  # 3.9e-3 m^2
    assert c.second_moment_m4 == pytest.approx((0.2**4 - 0.19**4) / 12, rel=1e-12)  # 2.47325e-5 m^4
    assert c.shear_modulus_Pa == pytest.approx(2.5e9 / 2.75, rel=1e-12)
    assert c.mass_per_length_kg_m == pytest.approx(1200 * 3.9e-3, rel=1e-12)  # 4.68 kg/m
    assert c.mass_kg == pytest.approx(4.68 * 0.8, rel=1e-12)
    assert c.bending_stiffness_Nm2 == pytest.approx(2.5e9 * 2.47325e-5, rel=1e-12)
    assert c.shear_stiffness_N == pytest.approx(0.5 * 2.5e9 / 2.75 * 3.9e-3, rel=1e-12)
    assert c.rotary_inertia_kg_m == pytest.approx(1200 * 2.47325e-5, rel=1e-12)
    assert c.natural_circular_frequency_rad_s == pytest.approx(2 * math.pi * 70.0)


def test_bending_is_about_y_with_size_x_the_depth_along_the_load():
    c = Column(size_x_m=0.30, size_y_m=0.10, wall_thickness_m=0.01)
    assert c.second_moment_m4 == pytest.approx((0.10 * 0.30**3 - 0.08 * 0.28**3) / 12, rel=1e-12)
    turned = Column(size_x_m=0.10, size_y_m=0.30, wall_thickness_m=0.01)
    assert turned.area_m2 == pytest.approx(c.area_m2)
    assert turned.second_moment_m4 < c.second_moment_m4 / 5


def test_solid_section_when_the_wall_fills_it():
    c = Column(size_x_m=0.1, size_y_m=0.2, wall_thickness_m=0.05)
    assert c.area_m2 == pytest.approx(0.02)
    assert c.second_moment_m4 == pytest.approx(0.2 * 0.1**3 / 12)


def test_frozen_hashable_and_equal_by_value():
    c = Column()
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.height_m = 1.0  # type: ignore[misc]
    assert Column() == c and hash(Column()) == hash(c)
    assert Column(elements=160.0) == c and isinstance(Column(elements=160.0).elements, int)
    assert Column(base="calibrated") != c
    assert set(BASES) == {"rigid", "calibrated", "spring"}


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"size_x_m": 0.0}, "column.size_x_m"),
        ({"size_y_m": -0.2}, "column.size_y_m"),
        ({"height_m": float("nan")}, "column.height_m"),
        ({"height_m": "tall"}, "column.height_m"),
        ({"wall_thickness_m": 0.0}, "column.wall_thickness_m"),
        ({"wall_thickness_m": 0.11}, "column.wall_thickness_m"),
        ({"youngs_modulus_Pa": -1.0}, "column.youngs_modulus_Pa"),
        ({"density_kg_m3": 0.0}, "column.density_kg_m3"),
        ({"poisson_ratio": 0.5}, "column.poisson_ratio"),
        ({"poisson_ratio": -1.0}, "column.poisson_ratio"),
        ({"poisson_ratio": float("inf")}, "column.poisson_ratio"),
        ({"shear_coefficient": 0.0}, "column.shear_coefficient"),
        ({"natural_frequency_Hz": 0.0}, "column.natural_frequency_Hz"),
        ({"stiffness_N_m": -4.685e5}, "column.stiffness_N_m"),
        ({"damping_ratio": 1.0}, "column.damping_ratio"),
        ({"damping_ratio": -0.01}, "column.damping_ratio"),
        ({"base": "fixed"}, "column.base"),
        ({"base": None}, "column.base"),
        ({"elements": 0}, "column.elements"),
        ({"elements": 10.5}, "column.elements"),
        ({"elements": True}, "column.elements"),
        ({"elements": "160"}, "column.elements"),
    ],
)
def test_bad_input_names_the_field(kwargs, field):
    input_error(field, Column, **kwargs)


def test_zero_damping_is_allowed():
    assert Column(damping_ratio=0.0).damping_ratio == 0.0
