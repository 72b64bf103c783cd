"""The comparison with the study (analytical/study_comparison.py): Welch's test against scipy
and a hand case, the single-value z, and the study's fit of a base-shear history recovering a
known half-sine at the height it is given."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from analytical.column import Column
from analytical.study import STUDY_IMPACT_COUNT, STUDY_IMPACT_VELOCITY_M_S, STUDY_TABLE2_MDOF
from analytical.errors import InputError
from analytical.mdof import mdof_response
from analytical.pulses import make_pulse
from analytical.study_comparison import (
    STUDY_FIGURES,
    compare_table,
    compare_with_study,
    fit_like_the_study,
    strike_component,
)


def test_welch_by_hand():
    # samples 1..5: mean 3, s^2 = 2.5, s^2/n = 0.5; the study 2 +- 1 over 4: 0.25
    c = compare_with_study([1.0, 2.0, 3.0, 4.0, 5.0], 2.0, 1.0, 4)
    assert c.n == 5 and c.mean == 3.0 and c.median == 3.0
    assert c.standard_error == pytest.approx(math.sqrt(0.5))
    assert (c.q05, c.q95) == pytest.approx((1.2, 4.8))  # linear quantiles
    assert c.welch_t == pytest.approx(1.0 / math.sqrt(0.75))
    assert c.welch_dof == pytest.approx(0.75**2 / (0.5**2 / 4 + 0.25**2 / 3))  # 6.75
    assert c.welch_dof == pytest.approx(6.75)
    assert c.p_value == pytest.approx(2 * stats.t.sf(1.0 / math.sqrt(0.75), 6.75))
    assert c.test == "welch" and c.verdict.startswith("agrees")


@pytest.mark.parametrize("seed, shift", [(0, 0.0), (1, 40.0), (2, -25.0), (3, 80.0)])
def test_welch_matches_scipy(seed, shift):
    mean, std = STUDY_TABLE2_MDOF["peak_force_N"]
    x = np.random.default_rng(seed).normal(mean + shift, 38.0, 82)
    c = compare_with_study(x, mean, std, STUDY_IMPACT_COUNT)
    ref = stats.ttest_ind_from_stats(x.mean(), x.std(ddof=1), x.size, mean, std, STUDY_IMPACT_COUNT, equal_var=False)
    assert c.welch_t == pytest.approx(ref.statistic, rel=1e-12)
    assert c.p_value == pytest.approx(ref.pvalue, rel=1e-9)
    assert c.verdict.startswith("agrees" if ref.pvalue > 0.05 else "differs")


def test_the_ensembles_figures_differ_from_the_studys():
    # the figures: 233 +- 38 N over 82 strikes against 171 +- 63 N over 22: t about 4.4
    rng = np.random.default_rng(5)
    x = rng.standard_normal(82)
    x = 233.0 + 38.0 * (x - x.mean()) / x.std(ddof=1)
    c = compare_with_study(x, *STUDY_TABLE2_MDOF["peak_force_N"])
    assert c.welch_t == pytest.approx((233.0 - 171.07) / math.sqrt(38.0**2 / 82 + 62.91**2 / 22))  # 4.41
    assert c.p_value < 1e-3 and c.verdict.startswith("differs")


def test_one_value_gets_a_z_and_none_gets_no_test():
    u, s = STUDY_IMPACT_VELOCITY_M_S
    one = compare_with_study([1.40, math.nan], u, s)
    assert one.n == 1 and one.test == "z" and math.isnan(one.welch_t) and math.isnan(one.standard_error)
    assert one.z == pytest.approx((1.40 - u) / s)
    assert one.p_value == pytest.approx(2 * stats.norm.sf(abs(one.z)))
    assert "inside" in one.verdict  # |z| = 1.54
    far = compare_with_study([1.0], u, s)
    assert "outside" in far.verdict
    none = compare_with_study([], u, s)
    assert none.n == 0 and none.test == "none" and none.to_dict()["mean"] is None


def test_bad_study_figures_are_input_errors():
    with pytest.raises(InputError) as err:
        compare_with_study([1.0, 2.0], 1.0, -0.1)
    assert err.value.field == "study_std"
    with pytest.raises(InputError) as err:
        compare_with_study([1.0, 2.0], 1.0, 0.1, 1)
    assert err.value.field == "study_n"
    with pytest.raises(InputError) as err:
        compare_table({"speed": [1.0]})
    assert err.value.field == "samples"


def test_the_table_holds_the_studys_rows():
    table = compare_table({k: [1.0, 2.0] for k in STUDY_FIGURES})
    assert list(table) == list(STUDY_FIGURES)
    assert table["peak_force_N"].study_mean == 171.07 and table["peak_force_N"].study_n == 22
    assert table["normal_speed_m_s"].study_mean == table["speed_m_s"].study_mean == 1.60


def test_strike_component_is_the_shear_along_the_strike():
    x, y = np.array([1.0, 2.0]), np.array([0.5, 1.0])
    assert strike_component(x, None, (-1.0, 0.0, 0.0)) == pytest.approx(x)
    assert strike_component(-x, None, (1.0, 0.0, 0.0)) == pytest.approx(x)
    n = np.array([-0.6, -0.8, 0.0])  # a load along (0.6, 0.8): base shear (0.6, 0.8) per N
    assert strike_component(0.6 * x, 0.8 * x, n) == pytest.approx(x)
    with pytest.raises(InputError):
        strike_component(x, y, (0.0, 0.0, 1.0))


def _history(peak_N: float, duration_s: float, height_m: float, column: Column):
    """The base shear of a half-sine at ``height_m``, on the tool's clock (0 at first contact)
    and its uneven sampling (finer in the ringing)."""
    t = np.concatenate([np.linspace(0.0, duration_s, 200, endpoint=False),
                        np.arange(duration_s, duration_s + 0.05, 1e-5)])
    return t, mdof_response(make_pulse("half-sine", peak_N, duration_s), column, height_m, t).response_N


@pytest.mark.parametrize("peak, duration, height", [(171.07, 0.0047, 0.40), (236.93, 0.0047, 0.16),
                                                    (120.0, 0.0030, 0.50)])
def test_the_fit_recovers_a_half_sine_at_the_height_given(peak, duration, height):
    column = Column()
    t, shear = _history(peak, duration, height, column)
    fit = fit_like_the_study(t, shear, height, column)
    # tolerance: 0.5 % in peak, duration and impulse; the start within 0.05 ms of the contact
    assert fit.height_m == height
    assert fit.peak_N == pytest.approx(peak, rel=5e-3)
    assert fit.duration_s == pytest.approx(duration, rel=5e-3)
    assert fit.impulse_Ns == pytest.approx(2 * peak * duration / math.pi, rel=5e-3)
    assert abs(fit.start_s) < 5e-5 and fit.nrmse < 0.01
    assert fit.record_peak_N == pytest.approx(np.max(shear), rel=1e-3)


def test_the_height_changes_the_fitted_pulse():
    # the same history fitted at another height is another pulse, with a worse fit
    column = Column()
    t, shear = _history(171.07, 0.0047, 0.40, column)
    right = fit_like_the_study(t, shear, 0.40, column)
    wrong = fit_like_the_study(t, shear, 0.20, column)
    assert wrong.height_m == 0.20
    assert abs(wrong.peak_N / right.peak_N - 1.0) > 0.05 and wrong.nrmse > 5 * right.nrmse


def test_a_history_without_an_impact_is_an_input_error():
    with pytest.raises(InputError):
        fit_like_the_study(np.linspace(0.0, 0.05, 500), np.zeros(500), 0.4)
