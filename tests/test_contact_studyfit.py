"""The study's fit in closed form (analytical.contact_studyfit) against the reference path
(analytical.contact_law.study_fit through analytical.fitting.fit_mdof), and the calibration's
pieces on small inputs: the fast evaluation, the multi-start's bookkeeping, strikes from an
ensemble."""

import math

import numpy as np
import pytest

from analytical.contact_calibration import (
    STARTS,
    STUDY_COLUMN,
    LawFit,
    MultiStart,
    calibrate_multistart,
    ensemble_population,
    strike_population,
    table2_impulse_relation,
    unit_figures,
)
from analytical.contact_law import CONTAINER, ContactLaw, column_impact, study_fit
from analytical.contact_studyfit import HalfSineModes, fast_study_fit
from analytical.errors import InputError
from analytical.mdof import mdof_response
from analytical.pulses import make_pulse

TIMES = np.arange(-0.01, 0.035, 4e-5)


@pytest.mark.parametrize("height", [0.2, 0.4])
@pytest.mark.parametrize("duration, start, tol", [(1e-3, 0.002, 4e-3), (4.7e-3, 0.0, 1e-3), (1.2e-2, -0.005, 3e-4)])
def test_the_closed_form_half_sine_response_is_the_adaptive_modal_one(height, duration, start, tol):
    modes = HalfSineModes(STUDY_COLUMN, height)
    ref = mdof_response(make_pulse("half-sine", 1.0, duration, start), STUDY_COLUMN, height, TIMES).response_N
    fast = modes.response(TIMES, [duration], [start])[0]
    assert np.max(np.abs(fast - ref)) <= tol * np.max(np.abs(ref))


def test_the_response_is_vectorised_over_trials():
    modes = HalfSineModes(STUDY_COLUMN, 0.4)
    d, s = np.array([1e-3, 4.7e-3, 8e-3]), np.array([0.0, -0.002, 0.001])
    both = modes.response(TIMES, d, s)
    for i in range(3):
        np.testing.assert_allclose(both[i], modes.response(TIMES, d[i:i + 1], s[i:i + 1])[0], rtol=0, atol=1e-12)


def test_a_long_record_takes_the_direct_path_and_agrees():
    modes = HalfSineModes(STUDY_COLUMN, 0.4)
    long = np.arange(-0.01, 0.4, 1e-4)  # beyond the kept basis's range
    ref = mdof_response(make_pulse("half-sine", 1.0, 4.7e-3, 0.0), STUDY_COLUMN, 0.4, long).response_N
    fast = modes.response(long, [4.7e-3], [0.0])[0]
    assert np.max(np.abs(fast - ref)) <= 1e-3 * np.max(np.abs(ref))


def test_the_fast_fit_of_a_strikes_base_shear_is_the_studys_fit():
    r = column_impact(CONTAINER, 1.0, 0.43, column=STUDY_COLUMN, obliquity_deg=5.0, lateral_offset_m=0.01)
    ref = study_fit(r, 0.40, STUDY_COLUMN)
    y = np.interp(TIMES, r.base_shear.time_s, r.base_shear.response_N, left=0.0,
                  right=float(r.base_shear.response_N[-1]))
    fast = fast_study_fit(TIMES, y, HalfSineModes(STUDY_COLUMN, 0.40))
    assert fast.magnitude_N == pytest.approx(ref.magnitude_N, rel=1e-4)
    assert fast.duration_s == pytest.approx(ref.duration_s, rel=1e-4)
    assert fast.impulse_Ns == pytest.approx(ref.impulse_Ns, rel=1e-4)
    assert fast.start_s == pytest.approx(ref.start_s, abs=1e-6)


def test_a_fit_of_nothing_is_refused():
    with pytest.raises(InputError):
        fast_study_fit(TIMES, np.zeros_like(TIMES), HalfSineModes(STUDY_COLUMN, 0.4))
    with pytest.raises(InputError, match="height_m"):
        HalfSineModes(STUDY_COLUMN, 0.0)


@pytest.mark.parametrize("law", [CONTAINER, ContactLaw(3.0e4, 0.2)])
def test_one_evaluation_fast_and_reference_agree_within_a_percent(law):
    _fast_agrees_with_reference(law, strike_population(2))


@pytest.mark.slow
@pytest.mark.parametrize("law", [ContactLaw(7.07e4, 0.565), ContactLaw(1.5e5, 0.7), ContactLaw(2.5e4, 0.1)])
def test_one_evaluation_over_eight_strikes_agrees_within_a_percent(law):
    _fast_agrees_with_reference(law, strike_population(8))


def _fast_agrees_with_reference(law, population):
    """The fast evaluation's mean figures within 1 % of the reference's."""
    fast = unit_figures(law, population).means()
    ref = unit_figures(law, population, fast=False).means()
    for name, value in ref.items():
        assert fast[name] == pytest.approx(value, rel=0.01), name


def test_the_starts_are_spread_and_none_is_the_shipped_law():
    k = np.array([s[0] for s in STARTS])
    zeta = np.array([s[1] for s in STARTS])
    assert len(STARTS) >= 6 and len(set(k)) == len(k)
    assert k.max() / k.min() >= 10 and zeta.max() - zeta.min() >= 0.6
    assert not any(math.isclose(a, CONTAINER.stiffness_N_m, rel_tol=0.05) and math.isclose(b, CONTAINER.damping_ratio,
                                                                                            abs_tol=0.05)
                   for a, b in STARTS)


def _fake_fit(start, chi2, values):
    return LawFit(ContactLaw(start[0] * 1.1, start[1]), ("stiffness_N_m", "damping_ratio"), 1.0, 0.1, -0.9, chi2, 1,
                  0.5, {}, {}, {}, 3, None, start, values)


def test_the_multistart_keeps_every_start_and_picks_the_least_chi_square():
    def fake_calibrate(start):
        return _fake_fit(start, abs(math.log(start[0] / 7e4)), (12.0, 0.4))

    fits = MultiStart(tuple(map(fake_calibrate, STARTS)))
    assert fits.best.start == min(STARTS, key=lambda s: abs(math.log(s[0] / 7e4)))
    assert fits.constrained() == 1 and fits.constrained(floor=0.1) == 2
    assert table2_impulse_relation() == pytest.approx(0.512, abs=5e-4)


def test_a_multistart_maps_every_start():
    seen = []

    def mapper(fn, starts):
        seen.extend(starts)
        return [_fake_fit(s, 1.0, (1.0, 1.0)) for s in starts]

    out = calibrate_multistart(strike_population(2), starts=STARTS[:2], mapper=mapper)
    assert seen == list(STARTS[:2]) and len(out.fits) == 2


def test_ensemble_strikes_are_struck_with_their_effective_mass():
    population = ensemble_population([0.30, 0.12], [0.38, float("nan")], [0.14, 0.26], [5.0, -10.0])
    assert population.water_level_m[1] == pytest.approx(0.12)  # no level: at the contact
    figures = unit_figures(ContactLaw(7e4, 0.5), population)
    np.testing.assert_allclose(figures.effective_mass_kg, [0.14, 0.26], rtol=1e-9)
    assert figures.fit_duration_s[1] > figures.fit_duration_s[0]  # heavier: longer


@pytest.mark.parametrize("args, field", [
    (([0.3], [0.3], [0.1]), "ensemble"),
    (([0.3, 0.9], [0.3, 0.3], [0.1, 0.1]), "impact_height_m"),
    (([0.3, 0.3], [0.3, -0.1], [0.1, 0.1]), "face_water_level_m"),
    (([0.3, 0.3], [0.3, 0.3], [0.1, 0.0]), "effective_mass_kg"),
])
def test_bad_ensemble_strikes_are_refused_naming_the_column(args, field):
    with pytest.raises(InputError) as err:
        ensemble_population(*args)
    assert err.value.field == field
