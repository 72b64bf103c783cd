"""Speed against error (orchestrator.studies.speed_error): the Pareto front, RMSE on a common time
base, the solver's CPU time from its logs, and the report on real sweep output: the tiny
mesh study (shared with test_sweep) plus a one-member hand-made baseline of the same flume."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from analytical.errors import InputError
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.speed_error import gauge_rmse, pareto_front, solver_cpu_s, speed_error
from orchestrator.studies.sweep import load_store, load_sweep
from tests.conftest import ROOT, run_cli

TINY = ROOT / "cases" / "tiny-nodebris.yaml"
TINY_SWEEP = ROOT / "cases" / "sweeps" / "tiny-mesh-study.yaml"


# --------------------------------------------------------------------------- pure


def test_pareto_front_keeps_only_the_unbeaten_points():
    cost = [1.0, 2.0, 3.0, 4.0, 2.0, np.nan]
    error = [10.0, 5.0, 6.0, 1.0, 5.0, 0.1]
    # (3, 6) is beaten by (2, 5); the two (2, 5) tie and neither beats the other; NaN is never on it
    assert pareto_front(cost, error).tolist() == [True, True, False, True, True, False]
    assert pareto_front([], []).tolist() == []


def test_gauge_rmse_is_measured_on_the_reference_time_base_over_the_common_window():
    t_ref = np.linspace(0.0, 2.0, 201)
    t = np.linspace(0.0, 1.5, 31)  # coarser and shorter: only 0..1.5 s is compared
    assert gauge_rmse(t, 2.0 * t + 0.1, t_ref, 2.0 * t_ref) == pytest.approx(0.1)  # linear: exact interpolation
    values = np.where(t < 0.5, 0.0, 0.3)  # a step: 0.3 off from 0.5 s on, against zero
    ref = np.zeros_like(t_ref)
    inside = t_ref <= 1.5
    expected = math.sqrt(np.mean(np.interp(t_ref[inside], t, values) ** 2))
    assert gauge_rmse(t, values, t_ref, ref) == pytest.approx(expected)
    with_nan = np.where(t > 1.0, np.nan, 2.0 * t)
    assert gauge_rmse(t, with_nan, t_ref, 2.0 * t_ref) == pytest.approx(0.0, abs=1e-12)  # NaNs dropped
    assert math.isnan(gauge_rmse([5.0, 6.0], [1.0, 1.0], t_ref, ref))  # nothing overlaps


def test_solver_cpu_time_is_the_last_execution_time_of_every_solver_log_counted_once(tmp_path):
    (tmp_path / "log.interFoam.1").write_text("ExecutionTime = 1.5 s  ClockTime = 2 s\n\nTime = 0.1\n"
                                              "ExecutionTime = 12.25 s  ClockTime = 20 s\n")
    (tmp_path / "log.interFoam").write_text("ExecutionTime = 3 s  ClockTime = 9 s\nEnd\n")
    (tmp_path / "log.interFoam.orig").write_text("ExecutionTime = 100 s  ClockTime = 100 s\n")  # not a segment's
    for named in (["log.interFoam.1", "log.interFoam", "missing"],
                  # older records name the live log for every segment: not three times the last
                  ["log.interFoam", "log.interFoam", "log.interFoam"]):
        (tmp_path / "run.json").write_text(json.dumps({"segments": [{"log": n} for n in named]}))
        assert solver_cpu_s(tmp_path) == pytest.approx(15.25)
    assert solver_cpu_s(tmp_path / "nowhere") is None


def test_a_folder_without_a_store_is_bad_input(tmp_path):
    with pytest.raises(InputError):
        speed_error(tmp_path)
    proc = run_cli("report", "speed-error", str(tmp_path))
    assert proc.returncode == 2 and "results.sqlite" in proc.stderr and "Traceback" not in proc.stderr


# --------------------------------------------------------------------------- real sweep output


@pytest.fixture(scope="module")
def hand_baseline(tmp_path_factory):
    """The tiny flume as set up by hand: uniform 5 cm cells over the whole flume, one member."""
    root = tmp_path_factory.mktemp("hand")
    path = root / "tiny-hand.yaml"
    path.write_text(json.dumps({
        "name": "tiny-hand", "base": str(TINY),
        "set": {"run.end_time_s": 0.3, "run.write_interval_s": 0.1, "mesh.trim_domain": False,
                "mesh.coarsening_ratio": 1},
        "axes": {"mesh.cell_size_m": [0.05]},
    }))
    out = root / "out"
    proc = run_cli("sweep", str(path), "-o", str(out))
    return out, proc


@pytest.mark.openfoam
@pytest.mark.slow
def test_speed_error_report_on_a_real_mesh_study(tiny_sweep, hand_baseline, tmp_path, openfoam):
    sweep_dir, proc = tiny_sweep
    assert proc.returncode == 0, proc.stderr[-3000:]
    hand_dir, proc = hand_baseline
    assert proc.returncode == 0, proc.stderr[-3000:]
    coarse, fine = load_sweep(TINY_SWEEP).members
    out = tmp_path / "report"
    proc = run_cli("report", "speed-error", str(sweep_dir), "--baseline", str(hand_dir), "-o", str(out), "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    head = json.loads(proc.stdout)

    # every file, the plot a real PNG
    for name in ("speed_error.csv", "speed_error.md", "speed_error.png", "speed_error.json"):
        assert (out / name).is_file(), name
    assert (out / "speed_error.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (out / "speed_error.png").stat().st_size > 20_000
    assert json.loads((out / "speed_error.json").read_text())["reference"] == head["reference"]

    # the reference is the finest member of the sweep; the baseline joins the table
    assert head["reference"]["member_id"] == fine.id and head["reference"]["cell_size_m"] == 0.04
    rows = {r["label"]: r for r in head["members"]}
    assert set(rows) == {"planner 5 cm", "planner 4 cm", "hand 5 cm"}
    assert rows["planner 4 cm"]["member_id"] == fine.id and rows["planner 5 cm"]["member_id"] == coarse.id
    assert all(r["status"] == "finished" for r in rows.values())
    assert rows["planner 4 cm"]["gauge_rmse_vs_finest_m"] == 0.0  # against itself
    for label in ("planner 5 cm", "hand 5 cm"):
        assert 0.0 < rows[label]["gauge_rmse_vs_finest_m"] < 0.05, label  # mm, not metres, of difference
    for r in rows.values():
        assert r["cells"] > 0 and r["time_steps"] > 10 and r["solver_wall_s"] > 0 and r["solver_cpu_s"] > 0
        assert r["chanson_arrival_mae_s"] is not None and r["chanson_arrival_mae_s"] < 0.2
        assert r["pareto_vs_chanson"] in (True, False)
    assert rows["hand 5 cm"]["cells"] > rows["planner 5 cm"]["cells"]  # the whole flume, uniform cells
    assert not rows["planner 4 cm"]["pareto_vs_finest"]  # the reference is not a point of that front

    # figures agree with the store and the members' own tables
    store = load_store(sweep_dir).set_index("member_id")
    table = (out / "speed_error.csv").read_text()
    assert "WG2_arrival_error_chanson_s" in table and "gauge_rmse_vs_finest_m" in table
    import pandas as pd

    frame = pd.read_csv(out / "speed_error.csv").set_index("member_id")
    for mid in (coarse.id, fine.id):
        # the CSV keeps 6 decimals
        assert frame.loc[mid, "WG2_arrival_s"] == pytest.approx(store.loc[mid, "WG2_arrival_s"], abs=1e-6)
        assert frame.loc[mid, "cells"] == store.loc[mid, "cells"]
    assert frame.loc[coarse.id, "WG2_depth_rmse_vs_chanson_m"] > 0  # WG2 is clear of the column
    assert "WG4_depth_rmse_vs_chanson_m" not in frame or frame["WG4_depth_rmse_vs_chanson_m"].isna().all()

    # the planner against the hand-made set-up, at the same cell size
    (sp,) = head["speedups"]
    assert sp["baseline"] == "hand 5 cm" and sp["planner"] == "planner 5 cm"
    assert sp["cell_ratio"] == pytest.approx(rows["hand 5 cm"]["cells"] / rows["planner 5 cm"]["cells"])
    assert sp["speedup_same_cell"] == pytest.approx(rows["hand 5 cm"]["solver_cpu_s"]
                                                    / rows["planner 5 cm"]["solver_cpu_s"])  # the default time
    assert sp["work_ratio"] == pytest.approx(rows["hand 5 cm"]["cells"] * rows["hand 5 cm"]["time_steps"]
                                             / (rows["planner 5 cm"]["cells"] * rows["planner 5 cm"]["time_steps"]))

    # the extrapolation to 15 mm: the planner's exact cell count, steps scaled from the finest member
    ext = {e["setup"]: e for e in head["extrapolation"]}
    planner = ext["planner"]
    scene = load_scene(sweep_dir / fine.id / "scene.yaml", ["mesh.cell_size_m=0.015"])
    assert planner["cells"] == plan_case(scene).cell_count
    assert planner["steps_extrapolated"] == round(rows["planner 4 cm"]["time_steps"] * 0.04 / 0.015)
    assert planner["time_s_extrapolated"] == pytest.approx(
        planner["cells"] * planner["steps_extrapolated"] * planner["us_per_cell_step"] * 1e-6, rel=1e-2)
    assert ext["hand"]["speedup_of_planner_extrapolated"] > 0 and ext["hand"]["work_ratio_extrapolated"] > 1

    md = (out / "speed_error.md").read_text()
    assert "Extrapolation to 15 mm cells (not measured)" in md and "| hand 5 cm |" in md
    assert "**planner 4 cm**" in md  # the reference, in bold

    # the default output folder is SWEEP_DIR/report, and --reference picks another member
    proc = run_cli("report", "speed-error", str(sweep_dir), "--reference", coarse.id, "--time", "solver",
                   "--extrapolate-to", "0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (Path(sweep_dir) / "report" / "speed_error.png").is_file()
    again = json.loads((Path(sweep_dir) / "report" / "speed_error.json").read_text())
    assert again["reference"]["member_id"] == coarse.id and again["time"] == "solver_wall_s"
    assert again["extrapolation"] == [] and again["speedups"] == []
    proc = run_cli("report", "speed-error", str(sweep_dir), "--reference", "nosuchmember")
    assert proc.returncode == 2 and "--reference" in proc.stderr
