"""`debrisfoam case`: render + run + post on a tiny 1-debris scene, end to end, real OpenFOAM."""

import json

import pandas as pd
import pytest

from tests.conftest import ROOT, run_cli

SCENE = ROOT / "tests" / "data" / "post" / "tiny-1debris.yaml"
# the container starts 2.5 cm from the column's face; 0.6 m/s towards it makes it strike at once
PUSH = ["--set", "debris.0.velocity_m_s=[0.6, 0, 0]"]


@pytest.fixture(scope="module")
def finished_case(tmp_path_factory):
    out = tmp_path_factory.mktemp("case") / "tiny"
    proc = run_cli("case", str(SCENE), "-o", str(out), *PUSH, "--quiet", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out, json.loads(proc.stdout)


@pytest.mark.openfoam
def test_case_produces_every_table_plot_and_a_contact_event(finished_case, openfoam):
    out, summary = finished_case
    results = out / "results"
    for table in ("gauges", "gauge_summary", "column_forces", "bodies", "impacts", "column_response"):
        assert (results / f"{table}.csv").is_file(), table
    for plot in ("gauges", "column_forces", "impacts", "study_fits", "tracks"):
        assert (results / f"{plot}.png").stat().st_size > 10_000, plot
    assert (results / "report.md").is_file() and (results / "summary.json").is_file()
    impacts = pd.read_csv(results / "impacts.csv")
    assert len(impacts) >= 1 and (impacts["other"] == "column").any()
    first = impacts.iloc[0]
    assert first["peak_force_N"] > 0 and first["duration_s"] > 0
    assert first["rebound_normal_velocity_m_s"] > 0  # it bounced off
    assert summary["status"] == "finished"
    assert summary["peak_impact_force_N"] == pytest.approx(first["peak_force_N"], rel=1e-6)


@pytest.mark.openfoam
def test_body_ends_outside_the_column(finished_case, openfoam):
    out, _ = finished_case
    bodies = pd.read_csv(out / "results" / "bodies.csv")
    last = bodies.iloc[-1]
    column_face_x = 1.2 - 0.05
    half_length = 0.15 / 2
    assert last["x_m"] + half_length <= column_face_x + 1e-3


@pytest.mark.openfoam
def test_case_again_resumes_and_a_different_scene_is_refused(finished_case, openfoam):
    out, summary = finished_case
    again = run_cli("case", str(SCENE), "-o", str(out), *PUSH, "--quiet", "--json")
    assert again.returncode == 0, again.stderr[-2000:]
    assert json.loads(again.stdout)["peak_impact_force_N"] == pytest.approx(summary["peak_impact_force_N"])
    other = run_cli("case", str(SCENE), "-o", str(out), "--quiet")
    assert other.returncode == 2 and "different case" in other.stderr
