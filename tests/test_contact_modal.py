"""The modal contact integration (analytical.contact_modal) against the banded one it replaces
in analytical.impact: the same Newmark scheme on the same system, so the same steps, switches,
pulse, rebound, energies and base shear to rounding."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytical.column import Column
from analytical.contact_integration import NormalIntegrator, column_blocks
from analytical.contact_law import CONTAINER
from analytical.contact_modal import ModalIntegrator, modal_blocks
from analytical.impact_bodies import ColumnTarget

SCALARS = ("body_velocity", "column_energy", "column_damping", "contact_damping", "duration")
HISTORY = ("force_N", "compression_m", "approach_m", "obstacle_m", "base_shear_x_N", "base_shear_y_N")


def both(column, mass_kg, height_m, angle_deg, speed_m_s, stiffness_N_m, damping_ratio):
    n = np.array([-math.cos(math.radians(angle_deg)), -math.sin(math.radians(angle_deg)), 0.0])
    target = ColumnTarget(column, height_m)
    c = 2.0 * damping_ratio * math.sqrt(stiffness_N_m * mass_kg)
    dt = 2.0 * math.pi * math.sqrt(mass_kg / stiffness_N_m) / 400
    banded = NormalIntegrator(mass_kg, stiffness_N_m, c, column_blocks(target, n)).run(speed_m_s, dt, 0.5)
    modal = ModalIntegrator(mass_kg, stiffness_N_m, c, modal_blocks(target, n)).run(speed_m_s, dt, 0.5)
    return banded, modal


def assert_same(banded, modal, rel=1e-9):
    assert modal["contacts"] == banded["contacts"]
    assert modal["settled"] == banded["settled"]
    assert modal["history"].time_s.shape == banded["history"].time_s.shape
    np.testing.assert_allclose(modal["history"].time_s, banded["history"].time_s, rtol=rel, atol=0)
    for name in SCALARS:
        assert modal[name] == pytest.approx(banded[name], rel=rel, abs=1e-15), name
    for name in HISTORY:
        a, b = getattr(modal["history"], name), getattr(banded["history"], name)
        np.testing.assert_allclose(a, b, rtol=0, atol=rel * max(np.max(np.abs(b)), 1e-300), err_msg=name)
    assert modal["pulse"].peak_N == pytest.approx(banded["pulse"].peak_N, rel=rel)
    assert modal["pulse"].impulse_Ns == pytest.approx(banded["pulse"].impulse_Ns, rel=rel)


@pytest.mark.parametrize("mass_kg, height_m, angle_deg", [(0.3, 0.03, 0.0), (0.25, 0.09, 30.0),
                                                           (0.4, 0.3, 60.0), (0.3, 0.6, 45.0)])
def test_modal_equals_banded_on_the_damped_container_law(mass_kg, height_m, angle_deg):
    banded, modal = both(Column(), mass_kg, height_m, angle_deg, 1.4, CONTAINER.stiffness_N_m,
                         CONTAINER.damping_ratio)
    assert banded["pulse"].peak_N > 10.0
    assert_same(banded, modal)


def test_modal_equals_banded_when_the_column_catches_the_body_again():
    # undamped contact, a heavy body at the top: the ringing column strikes it again
    banded, modal = both(Column(elements=40), 2.0, 0.8, 0.0, 1.5, 3.04e6, 0.0)
    assert banded["contacts"] >= 2
    assert_same(banded, modal)


def test_modal_equals_banded_on_a_rectangular_column_struck_obliquely():
    # two bending models of their own (not merged): the modes of both side by side
    column = Column(size_x_m=0.2, size_y_m=0.12, elements=40)
    target = ColumnTarget(column, 0.3)
    assert target.axis_column(0) != target.axis_column(1)
    banded, modal = both(column, 0.3, 0.3, 35.0, 1.2, CONTAINER.stiffness_N_m, CONTAINER.damping_ratio)
    assert np.max(np.abs(banded["history"].base_shear_y_N)) > 1.0
    assert_same(banded, modal)
