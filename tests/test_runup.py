"""Run-up over the top of the air space: a 2D closed tank on real OpenFOAM.

The tank of tests/test_plan.py's run-up tests: a 0.4 m reservoir 0.2 m deep, a 15 mm wet bed,
the end wall 0.8 m past the gate, 0.6 m walls, 2 cm cells (about 2k cells, a few seconds on
one core), 1 s: the bore strikes the end wall at about 0.55 s and runs up it. The planner keeps
the air space up to the walls (run-up estimate 2 h0 = 0.4 m over the 1.5 h0 = 0.3 m trim); the
same tank with the air space cut at 0.3 m (mesh.top_m) lets water out over the top, which post
reports apart from the outlet's and warns about on stderr.
"""

from __future__ import annotations

import json
from pathlib import Path

import pandas as pd
import pytest
import yaml

from orchestrator.pipeline import render_from_file
from orchestrator.run.runner import run_case
from tests.conftest import closed_tank, run_cli


def tank(**mesh) -> dict:
    return closed_tank(("WGend", 0.77), mesh, {"write_interval_s": 0.5, "max_courant": 0.9},
                       outputs={"probe_interval_s": 0.02, "preview": False})


def _run(tmp: Path, name: str, data: dict) -> Path:
    path = tmp / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data))
    case = tmp / name
    render_from_file(path, case)
    assert run_case(case, np=1, quiet=True).status == "finished"
    return case


@pytest.fixture(scope="module")
def tanks(tmp_path_factory) -> dict[str, Path]:
    tmp = tmp_path_factory.mktemp("runup")
    return {"walls": _run(tmp, "walls", tank()), "trimmed": _run(tmp, "trimmed", tank(top_m=0.3))}


def _post(case: Path):
    proc = run_cli("post", str(case), "--tables-only")
    assert proc.returncode == 0, proc.stderr[-3000:]
    summary = json.loads((case / "results" / "summary.json").read_text())
    balance = pd.read_csv(case / "results" / "water_balance.csv")
    return proc, summary, balance


@pytest.mark.openfoam
def test_the_planner_keeps_the_run_up_inside_the_air_space(tanks, openfoam):
    """Expected: the air space goes up to the walls (0.6 m); the water that leaves over the top
    stays under 0.1 % of the initial water (measured: 7e-9 of it) and post does not warn."""
    case = tanks["walls"]
    plan = json.loads((case / "plan.json").read_text())
    assert plan["domain_m"][2][1] == pytest.approx(0.6) and "up to the walls" in plan["reasons"]["domain_top"]
    proc, summary, balance = _post(case)
    assert "warning" not in proc.stderr, proc.stderr
    wb = summary["water_balance"]
    assert wb["atmosphere_outflow_fraction"] < 1e-3 and wb["atmosphere_warning_time_s"] is None
    assert set(wb["outflow_by_patch_m3"]) == {"atmosphere"}  # a closed tank: no outlet
    assert balance["outflow_atmosphere_m3"].iloc[-1] / balance["initial_m3"].iloc[0] < 1e-3
    assert not any("top of the air space" in m for m in summary["missing"])


@pytest.mark.openfoam
def test_water_over_a_trimmed_top_is_reported_apart_and_warned_about(tanks, openfoam):
    """The air space cut at 1.5 h0 = 0.3 m. Expected: more than 0.1 % of the water leaves over
    the top (measured: 1.3 %), after the bore reaches the end wall (about 0.55 s); water_balance.csv
    and summary.json book it as the atmosphere's outflow, and post warns on stderr, once."""
    case = tanks["trimmed"]
    plan = json.loads((case / "plan.json").read_text())
    assert plan["domain_m"][2][1] == pytest.approx(0.3)
    assert any("below the run-up" in w for w in plan["warnings"])
    proc, summary, balance = _post(case)
    fraction = balance["outflow_atmosphere_m3"].iloc[-1] / balance["initial_m3"].iloc[0]
    assert fraction > 1e-3
    assert balance["outflow_m3"].iloc[-1] == pytest.approx(balance["outflow_atmosphere_m3"].iloc[-1])
    wb = summary["water_balance"]
    assert wb["atmosphere_outflow_fraction"] == pytest.approx(fraction, rel=1e-6)
    assert 0.3 < wb["atmosphere_warning_time_s"] < 1.0
    assert abs(wb["final_error"]) < 0.01  # the balance itself closes: the water left, it was not lost
    assert proc.stderr.count("debrisfoam: warning:") == 1 and "top of the air space at z = 0.3 m" in proc.stderr
    assert any("top of the air space" in m for m in summary["missing"])
