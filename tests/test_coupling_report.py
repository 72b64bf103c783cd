"""`debrisfoam report coupling`: one scene run one-way and two-way, side by side
(orchestrator/report/coupling.py).

The runs are the synthetic post-processed folders of tests/test_layouts_report.py; the two-way
one is the same run relabelled, its bodies moved by a known offset, so every difference the
comparison measures is known in closed form.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.errors import InputError
from orchestrator.report.coupling import compare_coupling, write_coupling_report
from tests.conftest import run_cli
from tests.test_layouts_report import plan_json, synthetic_case


def _two_way(case: Path, dx: float = 0.0, dz: float = 0.0, dyaw: float = 0.0, strike_s: float | None = None) -> Path:
    """The synthetic run as a two-way one (the plan of its scene run two-way, on the same background):
    its bodies moved by (dx, 0, dz) and turned by dyaw, its first strike at strike_s (None: as it is)."""
    (case / "plan.json").write_text(plan_json(case, debris_coupling="two-way"))
    bodies = pd.read_csv(case / "results" / "bodies.csv")
    bodies["x_m"] += dx
    bodies["z_m"] += dz
    bodies["yaw_deg"] += dyaw
    bodies.to_csv(case / "results" / "bodies.csv", index=False)
    if strike_s is not None:
        impacts = pd.read_csv(case / "results" / "impacts.csv")
        impacts.loc[impacts["event"] == 1, "time_s"] = strike_s
        impacts.to_csv(case / "results" / "impacts.csv", index=False)
    return case


def _one_way(case: Path) -> Path:
    return case  # synthetic_case's run is one-way


def test_the_tracks_differ_by_the_offset_until_the_first_strike(tmp_path):
    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _two_way(synthetic_case(tmp_path / "two", "pair"), dx=0.03, dz=-0.04, dyaw=10.0, strike_s=0.08)
    cmp = compare_coupling(one, two)
    # the comparison ends at the earlier first strike: the two-way run's, at 0.08 s
    assert cmp.until_s == pytest.approx(0.08)
    assert "two-way" in cmp.until_reason
    assert cmp.tracks["time_s"].max() <= 0.08 + 1e-9
    assert set(cmp.tracks["body"]) == {"debris1", "debris2"}
    # one-way minus two-way: -dx, 0, -dz; the distance is the offset's length throughout
    assert np.allclose(cmp.tracks["dx_m"], -0.03) and np.allclose(cmp.tracks["dy_m"], 0.0)
    assert np.allclose(cmp.tracks["dz_m"], 0.04) and np.allclose(cmp.tracks["distance_m"], 0.05)
    assert np.allclose(cmp.tracks["dyaw_deg"], -10.0)  # debris2's yaw passes +-180 in both runs
    row = cmp.table.set_index("run").loc["one-way"]
    assert row["track_rms_m"] == pytest.approx(0.05) and row["track_max_m"] == pytest.approx(0.05)
    assert row["dx_at_end_m"] == pytest.approx(-0.03)
    assert cmp.same_mesh
    strikes = cmp.table.set_index("run")["strike_time_s"]
    assert strikes.to_dict() == pytest.approx({"one-way": 0.10, "two-way": 0.08})
    # each body alone: the same offset, and its own first strike in each run
    per = cmp.per_body.set_index("body")
    assert list(per.index) == ["debris1", "debris2"]
    assert np.allclose(per["track_rms_m"], 0.05) and np.allclose(per["dx_at_end_m"], -0.03)
    assert np.allclose(per["dyaw_at_end_deg"], -10.0)
    first = pd.read_csv(Path(one) / "results" / "impacts.csv").groupby("body")["time_s"].min()
    for body in per.index:
        assert per.loc[body, "one_way_strike_time_s"] == pytest.approx(first.get(body, np.nan), nan_ok=True)


def test_when_each_body_left_the_bed_and_how_far_apart_the_runs_were_then(tmp_path):
    """A body afloat is one whose centre stands 5 mm above its start; the two-way run's own record
    says when the runner freed a held body; the centres' distance at that time is read off the
    tracks' difference (here the constant offset)."""
    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _two_way(synthetic_case(tmp_path / "two", "pair"), dx=0.03)
    bodies = pd.read_csv(two / "results" / "bodies.csv")
    lifted = (bodies["body"] == "debris1") & (bodies["time_s"] >= 0.05 - 1e-9)
    bodies.loc[lifted, "z_m"] += 0.006  # debris1 rises 6 mm two-way at 0.05 s
    bodies.to_csv(two / "results" / "bodies.csv", index=False)
    run = json.loads((two / "run.json").read_text())
    run["freed"] = [{"body": "debris1", "time_s": 0.04}]
    (two / "run.json").write_text(json.dumps(run))
    per = compare_coupling(one, two).per_body.set_index("body")
    t_up = bodies.loc[lifted, "time_s"].min()
    assert per.loc["debris1", "two_way_afloat_s"] == pytest.approx(t_up)
    assert per.loc["debris1", "two_way_freed_s"] == pytest.approx(0.04)
    assert np.isnan(per.loc["debris2", "two_way_freed_s"]) and np.isnan(per.loc["debris2", "apart_at_freed_m"])
    assert per.loc["debris1", "apart_at_freed_m"] == pytest.approx(0.03)  # before the rise: the x offset alone
    # the one-way bodies stay at their start height: never afloat
    assert per["one_way_afloat_s"].isna().all()
    text = (write_coupling_report(compare_coupling(one, two), tmp_path / "page")["report"]).read_text()
    assert "| debris1 | - | " in text and "| 0.040 s | 0.030 m |" in text


def test_the_page_and_the_verb(tmp_path):
    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _two_way(synthetic_case(tmp_path / "two", "pair"), dx=0.03)
    files = write_coupling_report(compare_coupling(one, two), tmp_path / "page")
    text = files["report"].read_text()
    assert "| centre distance, largest | 0.030 m |" in text
    assert "the same mesh" in text and "![tracks](coupling.png)" in text
    assert "## Each body" in text and "| debris2 | 0.030 m |" in text
    assert (tmp_path / "page" / "bodies.csv").exists()
    assert files["figure"].stat().st_size > 10_000
    proc = run_cli("report", "coupling", str(one), str(two), "-o", str(tmp_path / "cli"), "--json")
    assert proc.returncode == 0, proc.stderr
    assert set(json.loads(proc.stdout)) == {"coupling", "track_difference", "bodies", "figure", "report"}


def test_runs_of_the_wrong_coupling_or_unfinished_are_refused_by_argument(tmp_path):
    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    also_one = _one_way(synthetic_case(tmp_path / "also", "pair"))
    with pytest.raises(InputError, match="TWO_WAY.*'one-way' run, not a two-way one"):
        compare_coupling(one, also_one)
    (tmp_path / "empty").mkdir()
    proc = run_cli("report", "coupling", str(one), str(tmp_path / "empty"), "-o", str(tmp_path / "out"))
    assert proc.returncode == 2 and "TWO_WAY" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_the_drag_scan_finds_the_coefficient_that_carried_the_reference_track(tmp_path):
    """Tracks made by the transport itself at C_d = 2 in a uniform current are the 'two-way' ones:
    the scan measures zero distance at 2 and a growing one away from it."""
    from orchestrator.report.coupling import drag_scan
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.transport.case_transport import scene_settings, transport_setup
    from orchestrator.transport.engine import run_transport
    from orchestrator.transport.flow import FlowField

    scene = load_scene(Path(__file__).parent / "data" / "scenes" / "tiny-oneway-strike.yaml",
                       ["transport.drag_coefficient=2.0"])
    flow = FlowField.uniform_current(0.1, 0.8, x_m=(0.0, 2.4), y_m=(-0.2, 0.2), t_s=(0.0, 2.0))
    bodies, flume, column = transport_setup(scene, flow)
    reference = run_transport(bodies, flume, 0.6, flow=flow, column=column, settings=scene_settings(scene))
    tracks = {b.name: reference.track(b.name) for b in bodies}
    scan = drag_scan(scene, flow, tracks, until_s=0.6, end_s=0.6, coefficients=(1.0, 2.0, 3.0))
    rms = dict(zip(scan["drag_coefficient"], scan["track_rms_m"]))
    assert rms[2.0] < 1e-6 < rms[1.0] and rms[3.0] > 1e-4
    assert scan["scene_default"].tolist() == [False, True, False]
    strikes = reference.impacts[reference.impacts["other"] == "column"] if len(reference.impacts) else []
    at_two = scan.set_index("drag_coefficient").loc[2.0, "strike_time_s"]
    if len(strikes):
        assert at_two == pytest.approx(float(strikes.iloc[0]["time_s"]))
    else:
        assert pd.isna(at_two)


def test_a_stopped_two_way_run_is_compared_up_to_where_it_stopped_only_when_asked(tmp_path):
    """A two-way run interrupted at 0.06 s (before either first strike): refused by default with
    the flag named; with --allow-stopped the tracks are compared to 0.06 s and the page says why."""
    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _two_way(synthetic_case(tmp_path / "two", "pair"), dx=0.02)
    summary = two / "results" / "summary.json"
    summary.write_text(json.dumps({**json.loads(summary.read_text()), "status": "interrupted", "reached_time_s": 0.06}))
    bodies = pd.read_csv(two / "results" / "bodies.csv")
    bodies[bodies["time_s"] <= 0.06 + 1e-9].to_csv(two / "results" / "bodies.csv", index=False)
    impacts = pd.read_csv(two / "results" / "impacts.csv")
    impacts[impacts["time_s"] <= 0.06].to_csv(two / "results" / "impacts.csv", index=False)
    with pytest.raises(InputError, match="TWO_WAY.*interrupted.*--allow-stopped"):
        compare_coupling(one, two)
    cmp = compare_coupling(one, two, allow_stopped=True)
    assert cmp.until_s == pytest.approx(0.06)
    assert "where the two-way run stopped, before its end (interrupted" in cmp.until_reason
    assert cmp.tracks["time_s"].max() == pytest.approx(0.06) and np.allclose(cmp.tracks["distance_m"], 0.02)
    proc = run_cli("report", "coupling", str(one), str(two), "--allow-stopped", "-o", str(tmp_path / "page"))
    assert proc.returncode == 0, proc.stderr
    text = (tmp_path / "page" / "report.md").read_text()
    assert "two-way interrupted at t = 0.060 s" in text and "where the two-way run stopped" in text


def _lift(case: Path, body: str, segments: dict[float, list[tuple[float, float]]]) -> None:
    """postProcessing/lift_<body>/<start>/force.dat of a two-way run: per segment start, (time, x force)."""
    for start, rows in segments.items():
        folder = case / "postProcessing" / f"lift_{body}" / f"{start:g}"
        folder.mkdir(parents=True)
        lines = ["# Force", "# Time\t(total_x total_y total_z)\t(pressure_x pressure_y pressure_z)\t(viscous_x viscous_y viscous_z)"]
        lines += [f"{t:.6f}\t({fx} {-fx / 3} 0.5)\t({fx} {-fx / 3} 0.5)\t(0 0 0)" for t, fx in rows]
        (folder / "force.dat").write_text("\n".join(lines) + "\n")


def test_the_force_history_keeps_each_segment_until_the_next_one_starts(tmp_path):
    """A restart backed up to 0.05 s replaces what the first segment wrote after it; each segment's
    first 5 ms (the restart's own transient) is left out."""
    from orchestrator.run.waterdepth import read_force_history

    _lift(tmp_path, "debris1", {0.0: [(t, 1.0) for t in (0.002, 0.01, 0.04, 0.06, 0.08)],
                                0.05: [(t, 2.0) for t in (0.052, 0.06, 0.07)]})
    history = read_force_history(tmp_path, "debris1")
    assert history[:, 0].tolist() == pytest.approx([0.01, 0.04, 0.06, 0.07])
    assert history[:, 1].tolist() == [1.0, 1.0, 2.0, 2.0]
    assert history[:, 3].tolist() == [0.5] * 4
    assert read_force_history(tmp_path, "debris2").shape == (0, 4)


def _afloat_two_way(case: Path, speeds: dict[str, float]) -> Path:
    """The two-way run's bodies as full tracks (velocity, rotation): each moves along x at its
    constant speed and floats (its centre 6 mm up) from 0.02 s."""
    t = np.linspace(0.0, 0.2, 101)
    rows = []
    for body, y in (("debris1", 0.0), ("debris2", 0.12)):
        for tk in t:
            row = {"time_s": tk, "body": body, "x_m": 0.95 + speeds[body] * tk, "y_m": y,
                   "z_m": 0.03 + (0.006 if tk >= 0.02 else 0.0), "u_m_s": speeds[body], "v_m_s": 0.0, "w_m_s": 0.0,
                   "speed_m_s": speeds[body], "yaw_deg": 0.0, "pitch_deg": 0.0, "roll_deg": 0.0,
                   **{f"omega_{a}_rad_s": 0.0 for a in "xyz"}}
            row.update({f"q_{a}{b}": float(a == b) for a in "xyz" for b in "xyz"})
            rows.append(row)
    pd.DataFrame(rows).to_csv(case / "results" / "bodies.csv", index=False)
    return case


def test_the_drive_sets_the_measured_force_beside_the_one_way_forcing_on_the_same_track(tmp_path):
    """In a steady uniform current the one-way forcing on a body drifting with the water is nil (no
    relative flow, no acceleration) and on a body held still it is quadratic drag (four times as
    much at twice the current); the two-way column is the mean of what the solver wrote."""
    from orchestrator.report.coupling import drive_runs
    from orchestrator.transport.flow import FlowField

    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _afloat_two_way(_two_way(synthetic_case(tmp_path / "two", "pair")), {"debris1": 0.4, "debris2": 0.0})
    _lift(two, "debris1", {0.0: [(t, 0.3) for t in np.arange(0.001, 0.2, 0.002)]})
    _lift(two, "debris2", {0.0: [(t, -0.1) for t in np.arange(0.001, 0.2, 0.002)]})
    cmp = compare_coupling(one, two)
    answers = {c: drive_runs(cmp, FlowField.uniform_current(0.2, c, x_m=(0.5, 1.6), y_m=(-0.2, 0.2), t_s=(0.0, 1.0)))
               for c in (0.4, 0.8)}
    drives = {c: a.table.set_index("body") for c, a in answers.items()}
    d = drives[0.4]
    assert d.loc["debris1", "from_s"] == pytest.approx(0.02 + 0.05)
    assert d.loc["debris1", "to_s"] == pytest.approx(cmp.until_s)
    assert d.loc["debris1", "two_way_fx_N"] == pytest.approx(0.3)
    assert d.loc["all", "two_way_fx_N"] == pytest.approx(0.2)
    assert d.loc["debris1", "two_way_fy_N"] == pytest.approx(-0.1)  # the lift file's y, -x / 3
    assert np.allclose(d["one_way_forcing_fy_N"], 0.0, atol=1e-9)  # the current runs along x
    assert d.loc["debris2", "y_mean_m"] == pytest.approx(0.12)
    # up: wholly under 0.2 m of water, the forcing is the buoyancy of the body's volume; the lift file's z
    flow = FlowField.uniform_current(0.2, 0.4, x_m=(0.5, 1.6), y_m=(-0.2, 0.2), t_s=(0.0, 1.0))
    body = cmp.runs["one-way"].scene.debris[0]
    assert d.loc["debris1", "one_way_forcing_fz_N"] == pytest.approx(
        flow.water_density_kg_m3 * flow.gravity_m_s2 * float(np.prod(body.size_m)), rel=1e-6)
    assert d.loc["debris1", "weight_N"] == pytest.approx(body.mass_kg * flow.gravity_m_s2)
    assert d.loc["debris1", "two_way_fz_N"] == pytest.approx(0.5)
    assert abs(d.loc["debris1", "one_way_forcing_fx_N"]) < 1e-9  # drifting with the current
    held = {c: drives[c].loc["debris2", "one_way_forcing_fx_N"] for c in drives}
    assert held[0.4] > 0.0 and held[0.8] / held[0.4] == pytest.approx(4.0, rel=1e-6)
    assert held[0.8] == pytest.approx(drives[0.8].loc["debris2", "one_way_drag_x_N"], rel=1e-6)
    assert d.loc["all", "one_way_forcing_fx_N"] == pytest.approx(held[0.4])
    series = answers[0.4].series
    assert set(series["body"]) == {"debris1", "debris2"}
    assert series["time_s"].min() >= 0.07 - 1e-9 and series["time_s"].max() <= cmp.until_s + 1e-9
    assert np.allclose(series.loc[series["body"] == "debris1", "two_way_fx_N"], 0.3)
    assert np.allclose(series.loc[series["body"] == "debris2", "one_way_forcing_fx_N"], held[0.4])
    cmp.drive, cmp.drive_series = answers[0.4]
    files = write_coupling_report(cmp, tmp_path / "page")
    text = files["report"].read_text()
    assert "## What drives the bodies afloat" in text and "| debris1 | 0.98 m | 0.40 m/s | +0.30 N |" in text
    assert (tmp_path / "page" / "drive.csv").exists() and "![drive](drive.png)" in text
    assert "Across the flow" in text and "| debris1 | +0.000 m | -0.10 N |" in text
    assert files["drive_figure"].stat().st_size > 10_000


def test_no_drive_when_a_body_never_floats_two_way(tmp_path):
    from orchestrator.report.coupling import drive_runs
    from orchestrator.transport.flow import FlowField

    one = _one_way(synthetic_case(tmp_path / "one", "pair"))
    two = _two_way(synthetic_case(tmp_path / "two", "pair"))  # centres stay at their start height
    flow = FlowField.uniform_current(0.2, 0.4, x_m=(0.5, 1.6), y_m=(-0.2, 0.2), t_s=(0.0, 1.0))
    drive = drive_runs(compare_coupling(one, two), flow)
    assert drive.table.empty and drive.series.empty
