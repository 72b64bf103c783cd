"""Pulse fitting: recovers known pulses from SDOF and MDOF records, with noise and offsets."""

import numpy as np
import pytest

from analytical.column import Column
from analytical.errors import InputError
from analytical.fitting import fit_mdof, fit_sdof, prepare_record
from analytical.mdof import mdof_response
from analytical.pulses import HalfSine
from analytical.sdof import SDOF, sdof_response

T = np.arange(0.0, 0.06, 1e-4)  # 10 kHz, 60 ms


def _noisy(clean, rel_noise, offset, seed=0):
    rng = np.random.default_rng(seed)
    return clean + offset + rng.normal(0.0, rel_noise * np.max(clean), clean.size)


@pytest.mark.parametrize("start", [0.0123, 0.02])
def test_sdof_fit_recovers_sdof_record(start):
    exact = fit_sdof(T, sdof_response(HalfSine(300.0, 0.003, start), SDOF(4.685e5, 69.0, 0.042), T).response_N)
    assert exact.magnitude_N == pytest.approx(300.0, rel=1e-6) and exact.duration_s == pytest.approx(0.003, rel=1e-6)
    truth = HalfSine(300.0, 0.003, start)
    sdof = SDOF(4.685e5, 69.0, 0.042)
    clean = sdof_response(truth, sdof, T).response_N
    fit = fit_sdof(T, _noisy(clean, 0.02, -4.0), column=Column())
    # a 3 ms pulse on a 69 Hz oscillator is nearly impulsive: the record fixes the
    # impulse tightly, magnitude and duration only together (exact without noise)
    assert fit.impulse_Ns == pytest.approx(2 / np.pi * 300 * 0.003, rel=0.01)
    assert fit.magnitude_N == pytest.approx(300.0, rel=0.07)
    assert fit.duration_s == pytest.approx(0.003, rel=0.07)
    assert fit.start_s == pytest.approx(start, abs=2e-4)
    assert fit.natural_frequency_Hz == pytest.approx(69.0, abs=0.3)
    assert fit.offset_N == pytest.approx(-4.0, abs=1.0)
    assert fit.rmse_N == pytest.approx(0.02 * np.max(clean), rel=0.25)  # residual is the noise


@pytest.mark.parametrize("base", ["rigid", "calibrated"])
def test_mdof_fit_recovers_mdof_record(base):
    column = Column(base=base)
    truth = HalfSine(171.0, 0.0047, 0.0155)
    clean = mdof_response(truth, column, 0.40, T).response_N
    fit = fit_mdof(T, _noisy(clean, 0.03, 6.0, seed=3), column=column, height_m=0.40)
    assert fit.magnitude_N == pytest.approx(171.0, rel=0.04)
    assert fit.duration_s == pytest.approx(0.0047, rel=0.04)
    assert fit.peak_model_N == pytest.approx(np.max(clean), rel=0.03)
    assert fit.peak_measured_N > fit.peak_model_N * 0.95


def test_fit_window_starts_before_the_impact_and_ignores_the_lead_in():
    truth = HalfSine(200.0, 0.004, 0.045)
    t = np.arange(0.0, 0.1, 1e-4)
    clean = mdof_response(truth, Column(), 0.3, t).response_N
    prep = prepare_record(t, clean + 10.0)
    assert prep.onset_s == pytest.approx(0.045, abs=1.5e-3)
    assert prep.baseline_N == pytest.approx(10.0, abs=1e-6)
    fit = fit_mdof(t, clean + 10.0, height_m=0.3)
    assert fit.magnitude_N == pytest.approx(200.0, rel=0.01)


def test_no_impact_and_bad_records_raise_input_error():
    rng = np.random.default_rng(5)
    with pytest.raises(InputError) as err:
        fit_sdof(T, rng.normal(0, 1, T.size))
    assert err.value.field == "force_N" and "no impact" in str(err.value)
    with pytest.raises(InputError) as err:
        fit_mdof(T, np.sin(T), height_m=2.0)
    assert err.value.field == "height_m"
    bad = np.sin(T)
    bad[3] = np.nan
    with pytest.raises(InputError):
        fit_sdof(T, bad)
