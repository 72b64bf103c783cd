"""The study comparison with the flow's own uncertainty (analytical/flow_uncertainty.py) and its
page (`debrisfoam report flow-pair`)."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from analytical.errors import InputError
from analytical.flow_uncertainty import compare_two_flows
from analytical.study_comparison import compare_with_study
from tests.conftest import run_cli


def test_two_equal_flows_give_the_plain_welch_test():
    a = np.random.default_rng(1).normal(1.7, 0.15, 200)
    c = compare_two_flows(a, a.copy(), 1.60, 0.13, 22)
    plain = compare_with_study(a, 1.60, 0.13, 22)
    assert c.flow_u == 0.0
    assert c.p_value == pytest.approx(plain.p_value, rel=1e-12) and c.dof == pytest.approx(plain.welch_dof, rel=1e-12)
    assert c.p_value == pytest.approx(c.p_without_flow, rel=1e-12)
    assert c.verdict.startswith("differs")


def test_the_flows_difference_enters_with_one_degree_of_freedom():
    """Welch-Satterthwaite by hand: variances s_a^2/n, u^2 (1 dof) and the study's S^2/N."""
    a = np.random.default_rng(2).normal(10.0, 1.0, 100)
    c = compare_two_flows(a, a + 3.0, 10.5, 1.0, 22)
    v = [a.var(ddof=1) / 100, 9.0, 1.0 / 22]
    assert c.flow_u == pytest.approx(3.0, rel=1e-12)
    assert c.t == pytest.approx((a.mean() - 10.5) / math.sqrt(sum(v)), rel=1e-12)
    assert c.dof == pytest.approx(sum(v) ** 2 / (v[0] ** 2 / 99 + v[1] ** 2 / 1 + v[2] ** 2 / 21), rel=1e-12)
    assert c.p_without_flow < 0.05 < c.p_value  # the flow's uncertainty hides the difference
    # the 95 % half-width (about 12 with ~1 dof) exceeds half the study's mean: a test that cannot fail
    assert c.half_width > 5.25 and c.verdict.startswith("cannot tell")


def test_a_small_flow_difference_keeps_a_real_difference():
    a = np.random.default_rng(3).normal(114.0, 48.0, 200)
    c = compare_two_flows(a, a + 2.0, 171.0, 62.9, 22)
    assert c.verdict.startswith("differs") and c.p_value < 0.05


def test_too_few_values_are_refused_naming_the_sample():
    with pytest.raises(InputError) as err:
        compare_two_flows([1.0, 2.0], [1.0], 1.0, 0.1, 22)
    assert err.value.field == "samples_b"


def _ensemble(folder, shift, seed=0):
    folder.mkdir()
    rng = np.random.default_rng(5)
    n = 40
    table = pd.DataFrame({"struck": [True] * n, "impact_speed_m_s": rng.normal(1.7, 0.15, n) + shift,
                          "impact_velocity_m_s": rng.normal(1.65, 0.15, n),
                          "study_fit_peak_N": rng.normal(114, 48, n), "study_fit_duration_s": rng.normal(3.5e-3, 2e-4, n),
                          "study_fit_impulse_Ns": rng.normal(0.26, 0.1, n), "face_water_level_m": rng.normal(0.17, 0.01, n),
                          "time_since_front_s": rng.normal(0.54, 0.01, n), "impact_height_m": rng.normal(0.06, 0.01, n)})
    table.to_csv(folder / "ensemble.csv", index=False)
    meta = {"scene": "cases/1debris.yaml", "seed": seed, "perturbation": {"position_sigma": 0.25},
            "realisations": n, "overrides": []}
    (folder / "ensemble.json").write_text(json.dumps(meta))


def test_the_page_sets_each_figure_beside_the_study_with_the_flows_uncertainty(tmp_path):
    _ensemble(tmp_path / "a", 0.0)
    _ensemble(tmp_path / "b", -0.3)
    proc = run_cli("report", "flow-pair", str(tmp_path / "a"), str(tmp_path / "b"), "-o", str(tmp_path / "out"))
    assert proc.returncode == 0, proc.stderr
    page = (tmp_path / "out" / "report.md").read_text()
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    speed = summary["figures"]["impact_speed_m_s"]
    assert speed["flow_u"] == pytest.approx(0.3, rel=1e-9)
    assert speed["p_value"] > speed["p_without_flow"]
    assert "| speed of the centre (m/s) |" in page and "| study-fit duration (ms) |" in page
    assert "| water level at the face (m) |" in page


def test_two_ensembles_of_other_starts_are_refused_naming_the_file(tmp_path):
    _ensemble(tmp_path / "a", 0.0)
    _ensemble(tmp_path / "b", 0.0, seed=1)
    proc = run_cli("report", "flow-pair", str(tmp_path / "a"), str(tmp_path / "b"), "-o", str(tmp_path / "out"))
    assert proc.returncode == 2 and "ensemble.json" in proc.stderr and "seed" in proc.stderr
    assert not (tmp_path / "out").exists()
    proc = run_cli("report", "flow-pair", str(tmp_path / "a"), str(tmp_path / "nothing"), "-o", str(tmp_path / "out"))
    assert proc.returncode == 2 and "nothing" in proc.stderr
