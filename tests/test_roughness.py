"""The bed's Darcy friction factor as a wall function's sand roughness (Colebrook, fully rough),
and the depth the dam-break flow runs at, against their closed forms."""

import math

import pytest

from analytical.dambreak import stoker_state
from analytical.errors import InputError
from analytical.roughness import bore_depth_m, darcy_factor, sand_roughness_m


def test_sand_roughness_is_colebrooks_rough_law_solved_for_ks():
    f, r = 0.0293, 0.112
    ks = sand_roughness_m(f, r)
    # 1/sqrt(f) = 2 log10(14.8 R / ks), written out
    assert 1.0 / math.sqrt(f) == pytest.approx(2.0 * math.log10(14.8 * r / ks), rel=1e-12)
    # the study's f in its bore is a roughness of about 2 mm
    assert 1.5e-3 < ks < 2.5e-3


@pytest.mark.parametrize("f, r", [(0.01, 0.05), (0.0293, 0.112), (0.05, 1.5)])
def test_roughness_and_friction_factor_invert_each_other(f, r):
    assert darcy_factor(sand_roughness_m(f, r), r) == pytest.approx(f, rel=1e-12)


def test_one_roughness_brakes_a_shallow_flow_more_than_a_deep_one():
    ks = sand_roughness_m(0.0293, 0.112)
    assert darcy_factor(ks, 0.03) > 0.0293 > darcy_factor(ks, 0.4)


def test_the_flow_depth_is_stokers_on_a_wet_bed_and_ritters_at_the_gate_on_a_dry_one():
    assert bore_depth_m(0.4, 0.015) == pytest.approx(stoker_state(0.4, 0.015).h2_m, rel=1e-12)
    assert bore_depth_m(0.4, 0.0) == pytest.approx(4 * 0.4 / 9, rel=1e-12)
    assert bore_depth_m(0.4, 0.5) == 0.5  # still water deeper than the reservoir: no dam break


@pytest.mark.parametrize("call, field", [
    (lambda: sand_roughness_m(0.0, 0.1), "friction_factor"),
    (lambda: sand_roughness_m(0.03, -1.0), "hydraulic_radius_m"),
    (lambda: darcy_factor(float("nan"), 0.1), "sand_roughness"),
    (lambda: bore_depth_m(0.0, 0.01), "h0_m"),
])
def test_bad_input_names_the_argument(call, field):
    with pytest.raises(InputError, match=field):
        call()
