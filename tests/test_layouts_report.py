"""`debrisfoam report layouts`: several debris layouts side by side (orchestrator/report/layouts.py).

The fast tests build small synthetic result folders (what a post-processed one-way run leaves:
results/*.csv, summary.json, run.json, contacts/, transport/body_contacts.csv) and a sweep
folder holding them; the OpenFOAM test runs the tiny one-way scene and reports it.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from orchestrator.plan.planner import plan_case
from orchestrator.report.layouts import find_runs, flow_agreement, layout_row, load_layout, write_layouts_report
from orchestrator.scene.resolve import scene_from_dict
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parent.parent
TINY = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"
GAUGES = ("WG1", "WG2", "WG3", "WG4")


def _scene(name: str) -> str:
    """The tiny one-way scene renamed, with a second container beside the first and four gauges."""
    scene = yaml.safe_load(TINY.read_text())
    scene["name"] = name
    second = dict(scene["debris"][0], name="debris2", centre_m=[0.95, 0.12])
    scene["debris"].append(second)
    scene["gauges"] = [{"name": g, "x_m": 0.3 + 0.2 * i, "y_m": 0.0} for i, g in enumerate(GAUGES)]
    return yaml.safe_dump(scene)


def plan_json(case: Path, **run) -> str:
    """The plan.json `debrisfoam render` writes for the case's scene.yaml (its run section changed by ``run``)."""
    scene = yaml.safe_load((case / "scene.yaml").read_text())
    scene["run"].update(run)
    return plan_case(scene_from_dict(scene)).to_json()


def _write(path: Path, frame: pd.DataFrame) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=False)


def synthetic_case(case: Path, name: str, wg2_offset_m: float = 0.0, force_offset_N: float = 0.0) -> Path:
    """A post-processed one-way run of two bodies: debris1 strikes the column twice, debris2 once;
    two contacts between the bodies, one with a wall."""
    case.mkdir(parents=True)
    (case / "scene.yaml").write_text(_scene(name))
    (case / "plan.json").write_text(plan_json(case))  # one-way: the flow recorded over x = 0.63 to 1.60 m
    (case / "run.json").write_text(json.dumps({
        "status": "finished", "ranks": 2, "runner": {"solver_wall_s": 300.0},
        "steps": [{"name": "blockMesh", "wall_s": 2.0, "exit_status": 0, "log": "log.blockMesh"}],
        "segments": [{"log": "log.interFoam", "exit_status": 0}],
        "transport": {"engine": "mujoco", "wall_s": 1.5, "pulse_wall_s": 2.0}, "transport_wall_s": 3.5}))
    (case / "log.interFoam").write_text("Time = 0.1\nExecutionTime = 100.5 s  ClockTime = 150 s\n\n"
                                        "Time = 0.2\nExecutionTime = 240 s  ClockTime = 300 s\n")
    results = case / "results"
    results.mkdir()
    (results / "summary.json").write_text(json.dumps({"scene": name, "status": "finished", "cells": 1000,
                                                      "end_time_s": 0.2, "reached_time_s": 0.2}))
    t = np.linspace(0.0, 0.2, 21)
    rows = []
    for body, y, yaw in (("debris1", 0.0, np.linspace(0.0, 90.0, 21)),
                         # through +-180: 170 -> 180 at t = 0.1 -> -170
                         ("debris2", 0.12, np.where(t <= 0.1, 170 + 100 * t, -190 + 100 * t))):
        for k, tk in enumerate(t):
            rows.append({"time_s": tk, "body": body, "x_m": 0.95 + tk, "y_m": y + 0.1 * tk, "z_m": 0.03,
                         "speed_m_s": 1.0, "yaw_deg": yaw[k], "pitch_deg": 2.0, "roll_deg": -1.0})
    _write(results / "bodies.csv", pd.DataFrame(rows))
    strikes = [(1, 0.10, "debris1", 0.9), (3, 0.15, "debris1", 0.4), (4, 0.10, "debris2", 0.7)]
    impacts = []
    for event, time, body, speed in strikes:
        history = f"contacts/event{event:04d}-force.csv"
        tt = np.linspace(0.0, 0.004, 41)
        _write(case / history, pd.DataFrame({"time_s": tt, "force_N": 100 * speed * np.sin(np.pi * tt / 0.004)}))
        _write(case / history.replace("-force", "-base-shear"),
               pd.DataFrame({"time_s": tt, "base_shear_x_N": 3.0 * speed * np.sin(np.pi * tt / 0.004),
                             "base_shear_y_N": 4.0 * speed * np.sin(np.pi * tt / 0.004)}))
        impacts.append({"event": event, "time_s": time, "body": body, "other": "column", "kind": "column",
                        "height_m": 0.05, "face_water_level_m": 0.04, "point_x_m": 1.15, "point_y_m": 0.0,
                        "impact_velocity_m_s": speed, "obliquity_deg": 5.0, "peak_force_N": 100 * speed,
                        "duration_s": 0.004, "impulse_Ns": 0.25 * speed, "force_history": history})
    _write(results / "impacts.csv", pd.DataFrame(impacts))
    (case / "contacts.json").write_text(json.dumps([
        {"event": 1, "type": "impact", "kind": "column"},
        {"event": 2, "type": "impact", "kind": "wall", "body": "debris2", "other": "wall_y1"},
        {"event": 5, "type": "transport_contact", "kind": "wall", "body": "debris1", "other": "wall_x1", "time_s": 0.18,
         "point_m": [1.6, 0.0, 0.03]},
        {"event": 6, "type": "transport_contact", "kind": "wall", "body": "debris1", "other": "wall_x1", "time_s": 0.19,
         "point_m": [1.6, 0.0, 0.03]},
        {"event": 3, "type": "impact", "kind": "column"}, {"event": 4, "type": "impact", "kind": "column"}]))
    _write(case / "transport" / "body_contacts.csv", pd.DataFrame({
        "event": [1, 2], "time_s": [0.05, 0.12], "body": ["debris1", "debris1"], "other": ["debris2", "debris2"],
        "point_x_m": [1.0, 1.05], "point_y_m": [0.06, 0.07], "point_z_m": [0.03, 0.03],
        "normal_x": [0, 0], "normal_y": [1, 1], "normal_z": [0, 0],
        "approach_velocity_m_s": [-0.3, -0.1], "separation_velocity_m_s": [0.1, 0.05], "restitution": [0.33, 0.5]}))
    tg = np.linspace(0.0, 0.2, 41)
    gauges = {"time_s": tg}
    for i, g in enumerate(GAUGES):
        gauges[f"{g}_elevation_m"] = 0.03 + 0.01 * (i + 1) * tg + (wg2_offset_m * tg / 0.2 if g == "WG2" else 0.0)
    _write(results / "gauges.csv", pd.DataFrame(gauges))
    _write(results / "gauge_summary.csv", pd.DataFrame(
        {"gauge": list(GAUGES), "x_m": [0.3, 0.5, 0.7, 0.9], "y_m": [0.0] * 4}))
    hydro = 20.0 * tg + force_offset_N * (tg > 0.1)
    _write(results / "column_forces.csv", pd.DataFrame({"time_s": tg, "hydro_force_x_N": hydro}))
    _write(results / "spreading.csv", pd.DataFrame({
        "body": ["debris1", "debris2"], "track_points": [21, 21], "max_spread_deg": [5.7, 20.0],
        "final_x_m": [1.15, 1.15], "final_y_m": [0.02, 0.14], "inside_naito": [True, True],
        "inside_nistor": [True, False]}))
    return case


def synthetic_sweep(root: Path) -> Path:
    """A sweep folder: two finished members (the second's WG2 2 mm higher at the end, its force 1.5 N
    higher after 0.1 s) and a third that failed in the solver."""
    sweep = root / "sweep"
    sweep.mkdir()
    (sweep / "sweep.json").write_text(json.dumps({"name": "layouts"}))
    for member, (mid, name, dz, df) in enumerate((("bbb", "two-a", 0.0, 0.0), ("aaa", "two-b", 0.002, 1.5)), 1):
        case = synthetic_case(sweep / mid, name, dz, df)
        (case / "member.json").write_text(json.dumps({"member": member, "status": "finished", "wall_time_s": 320}))
    failed = sweep / "ccc"
    failed.mkdir()
    (failed / "scene.yaml").write_text(_scene("two-c"))
    (failed / "plan.json").write_text(plan_json(failed))
    (failed / "run.json").write_text(json.dumps({"status": "failed", "segments": [
        {"log": "log.interFoam", "exit_status": 1}]}))
    (failed / "member.json").write_text(json.dumps({"member": 3, "status": "failed",
                                                    "error": "interFoam exited with status 1 at t = 0.1 s"}))
    return sweep


def test_a_layout_reads_its_strikes_with_the_orientation_and_base_shear_at_each(tmp_path):
    lay = load_layout(synthetic_case(tmp_path / "a", "two"))
    assert lay.ok and lay.body_names == ["debris1", "debris2"]
    s = lay.strikes
    assert list(s["body"]) == ["debris1", "debris2", "debris1"]  # in time order
    assert list(s["strike"]) == [1, 1, 2]
    first = s.iloc[0]
    assert first["yaw_deg"] == pytest.approx(45.0) and first["pitch_deg"] == pytest.approx(2.0)
    assert abs(s.iloc[1]["yaw_deg"]) == pytest.approx(180.0)  # interpolated across +-180, not through 0
    # the base shear's magnitude from its x and y parts (3, 4 -> 5 per unit)
    assert first["peak_base_shear_N"] == pytest.approx(5.0 * 0.9, rel=1e-3)
    assert set(lay.pulses) == {1, 3, 4}


def test_a_layouts_row_counts_strikes_per_body_contacts_and_wall_times(tmp_path):
    row = layout_row(load_layout(synthetic_case(tmp_path / "a", "two")))
    assert row["column_strikes"] == 3 and row["strikes_per_body"] == "debris1:2 debris2:1"
    assert (row["first_strike_body"], row["first_strike_velocity_m_s"], row["first_strike_peak_force_N"]) == \
        ("debris1", 0.9, 90.0)
    assert (row["body_contacts"], row["body_contact_max_approach_m_s"], row["wall_contacts"]) == (2, 0.3, 1)
    # the record's end walls are not the flume's: counted apart, with when each body got there
    assert (row["record_end_contacts"], row["bodies_at_record_end"]) == (2, "debris1:0.180")
    assert (row["flow_wall_s"], row["flow_cpu_s"], row["mesh_wall_s"], row["transport_wall_s"]) == (300.0, 240.0, 2.0, 3.5)
    assert row["max_spread_deg"] == 20.0 and row["inside_naito_all"] and not row["inside_nistor_all"]


def test_flow_agreement_measures_each_layout_against_the_first(tmp_path):
    sweep = synthetic_sweep(tmp_path)
    layouts = [load_layout(c) for c in find_runs([sweep])]
    table = flow_agreement(layouts).set_index(["layout", "quantity"])
    assert table.loc[("two-a", "WG2"), "max_abs_diff"] == 0.0
    assert table.loc[("two-b", "WG2"), "max_abs_diff"] == pytest.approx(0.002)
    assert table.loc[("two-b", "WG1"), "max_abs_diff"] == 0.0
    assert table.loc[("two-b", "hydro_force_x_N"), "max_abs_diff"] == pytest.approx(1.5)
    assert table.loc[("two-a", "hydro_force_x_N"), "peak"] == pytest.approx(4.0)
    assert "two-c" not in table.index.get_level_values("layout")  # no results: not in the overlay


def test_a_sweep_folder_gives_its_members_in_member_order_and_names_a_failure(tmp_path):
    sweep = synthetic_sweep(tmp_path)
    assert [p.name for p in find_runs([sweep])] == ["bbb", "aaa", "ccc"]
    # sweep.json's member list, when it has one, names the members: a folder an earlier form of the
    # sweep left there (its scenes since changed, so its id too) is not read
    listed = [{"member": k, "id": i} for k, i in enumerate(("bbb", "ccc"), 1)]
    (sweep / "sweep.json").write_text(json.dumps({"name": "layouts", "members": listed}))
    assert [p.name for p in find_runs([sweep])] == ["bbb", "ccc"]
    failed = load_layout(sweep / "ccc")
    assert not failed.ok and failed.status == "failed"
    assert "status 1" in failed.error and failed.log.endswith("ccc/log.interFoam")


def test_the_page_states_the_figures_and_links_every_figure_it_draws(tmp_path):
    sweep = synthetic_sweep(tmp_path)
    out = tmp_path / "page"
    files = write_layouts_report([sweep], out)
    text = (out / "report.md").read_text()
    for name in ("flow.png", "impact_summary.png", "two-a-tracks.png", "two-b-impacts.png"):
        assert (out / name).is_file() and f"]({name})" in text, name
    assert "never edited by hand" in text and "the solver's on 2 cores" in text
    assert "| two-a | 2 | 1,000 | 5.0 min (CPU 4.0 min) | 2 s | 3.5 s (1.5 stepping + 2.00 pulses) | " \
        "3 (debris1:2 debris2:1) | debris1, 0.100 s, 0.90 m/s, 90 N" in text
    assert "2 contacts between two bodies, from 0.050 s to 0.120 s" in text
    assert "0.10-0.30 m/s" in text
    assert "1 contacts with the flume's side walls, 2 with the record's end walls" in text
    assert "recorded over x = 0.63 to 1.60 m" in text and "Reached the end: debris1 from 0.180 s (x = 1.60 m)" in text
    assert "| 45 / 2 / -1 deg |" in text  # debris1's first strike: yaw / pitch / roll
    # the one-way statement: the flows coincide but for what the plans make different; the study's finding assumed
    assert "two-a and two-b run the same plan: between them, the gauges by at most 2.0 mm" in text
    assert "the hydrodynamic force by at most 1.50 N" in text
    assert "an assumption of the one-way model, not a result" in text
    # the failed member: its status, its error and its log
    assert "**two-c** did not give results: failed; interFoam exited with status 1 at t = 0.1 s" in text
    assert "ccc/log.interFoam" in text
    impacts = pd.read_csv(files["impacts"])
    assert len(impacts) == 6 and set(impacts["layout"]) == {"two-a", "two-b"}
    assert len(pd.read_csv(files["body_contacts"])) == 4
    assert list(pd.read_csv(files["layouts"])["layout"]) == ["two-a", "two-b", "two-c"]


@pytest.mark.slow
def test_the_cli_verb_writes_the_page_and_refuses_bad_input(tmp_path):
    sweep = synthetic_sweep(tmp_path)
    out = tmp_path / "page"
    proc = run_cli("report", "layouts", str(sweep), "-o", str(out), "--json")
    assert proc.returncode == 0, proc.stderr
    assert Path(json.loads(proc.stdout)["report"]).is_file()
    again = run_cli("report", "layouts", str(sweep), "-o", str(out))
    assert again.returncode == 2 and "--force" in again.stderr
    missing = run_cli("report", "layouts", str(tmp_path / "nowhere"), "-o", str(tmp_path / "x"))
    assert missing.returncode == 2 and "not a folder" in missing.stderr
    assert run_cli("report", "layouts", str(sweep), "-o", str(out), "--force").returncode == 0


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_tiny_one_way_run_reported_as_a_layout(tmp_path, openfoam):
    case = tmp_path / "tiny"
    proc = run_cli("case", str(TINY), "-o", str(case))
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = tmp_path / "page"
    proc = run_cli("report", "layouts", str(case), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    impacts = pd.read_csv(out / "impacts.csv")
    first = impacts.iloc[0]
    assert (first["layout"], first["body"], first["strike"]) == ("tiny-oneway-strike", "debris1", 1)
    # launched along the flume's axis: it strikes nose first, the base shear from its own pulse file
    assert abs(first["yaw_deg"]) < 5 and first["peak_base_shear_N"] > 0
    assert math.isfinite(first["peak_force_N"]) and first["peak_force_N"] > 0
    text = (out / "report.md").read_text()
    assert "| tiny-oneway-strike | 1 |" in text and "No contact between two bodies" in text
    assert (out / "tiny-oneway-strike-tracks.png").is_file()


def test_layouts_on_one_plan_with_equal_records_are_said_to_be_the_same(tmp_path):
    runs = [synthetic_case(tmp_path / name, name) for name in ("one", "two", "three")]
    write_layouts_report(runs, tmp_path / "page")
    text = (tmp_path / "page" / "report.md").read_text()
    assert "one, two and three run the same plan" in text
    assert "(one, two and three: the same plan, records equal to a millionth of their peaks)" in text


def test_every_layout_figure_fits_a_report_page(tmp_path):
    from orchestrator.report import layout_plots
    from orchestrator.report.figures import DPI
    from tests.test_plots import MAX_HEIGHT_PX, MAX_WIDTH_PX, texts_outside

    layouts = [load_layout(c) for c in find_runs([synthetic_sweep(tmp_path)])][:2]
    lay = layouts[0]
    for fig in (layout_plots.figure_flow(layouts), layout_plots.figure_impact_summary(layouts),
                layout_plots.figure_layout_tracks(lay), layout_plots.figure_layout_impacts(lay)):
        fig.canvas.draw()
        width, height = fig.get_size_inches() * DPI
        assert width <= MAX_WIDTH_PX and height <= MAX_HEIGHT_PX, f"{width:.0f} x {height:.0f} px"
        assert not texts_outside(fig), texts_outside(fig)
