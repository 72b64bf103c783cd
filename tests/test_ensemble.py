"""Ensembles (orchestrator/studies/ensemble.py): the perturbed starts (reproducible, inside their
clip, never within the gap of a wall, the column or another body; an impossible layout is bad
input naming the body), the table and the summary on a synthetic flow, the report, the verb's bad
input, and the verb end to end on the tiny one-way scene with OpenFOAM on both executors."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.column import Column
from analytical.study import STUDY_IMPACT_VELOCITY_M_S
from analytical.errors import InputError
from orchestrator.studies.ensemble import (
    TABLE_COLUMNS,
    EnsembleResult,
    Perturbation,
    ensemble_starts,
    perturbed_starts,
    plan_footprint,
    run_ensemble,
    start_clash,
    summarise,
)
from orchestrator.studies.ensemble_report import write_report
from orchestrator.transport.engine import TransportSettings, run_transport
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn, rotation
from orchestrator.scene.schema import DebrisBody
from tests.conftest import debris
from tests.conftest import run_cli

ROOT = Path(__file__).resolve().parent.parent
TINY = ROOT / "tests" / "data" / "scenes" / "tiny-oneway-strike.yaml"
HEADLINE_KEYS = {"realisations", "impact_probability", "impact_velocity_m_s", "peak_force_N", "wall_time_s"}

FLUME = FlumeBounds((0.0, 2.0), (-0.3, 0.3), 0.0)
COLUMN = PlacedColumn(1.0, 0.0, Column(size_x_m=0.1, size_y_m=0.1, height_m=0.3, wall_thickness_m=0.005))


def container(name: str = "debris1", x: float = 0.6, y: float = 0.0, yaw: float = 0.0) -> DebrisBody:
    return debris(name, (0.15, 0.06, 0.06), 0.236, (x, y, 0.03), yaw_deg=yaw, wall_thickness_m=0.005)


def _inside(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Points strictly inside a counter-clockwise convex polygon."""
    inside = np.ones(len(points), bool)
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        inside &= (b[0] - a[0]) * (points[:, 1] - a[1]) - (b[1] - a[1]) * (points[:, 0] - a[0]) > 1e-12
    return inside


def _footprint_points(body: DebrisBody, n: int = 15) -> np.ndarray:
    """A grid over the body's footprint, from its own axes (independent of plan_footprint)."""
    u = np.linspace(-0.5, 0.5, n)
    local = np.array([[a * body.size_m[0], b * body.size_m[1], 0.0] for a in u for b in u])
    return (local @ rotation(body).T)[:, :2] + np.asarray(body.centre_m[:2])


# --------------------------------------------------------------------------- starts
def test_starts_are_reproducible_from_the_seed_and_independent_of_n():
    bodies = [container()]
    a = ensemble_starts(bodies, FLUME, COLUMN, Perturbation(), seed=7, n=5)
    b = ensemble_starts(bodies, FLUME, COLUMN, Perturbation(), seed=7, n=3)
    assert a[:3] == b
    assert perturbed_starts(bodies, FLUME, COLUMN, Perturbation(), 7, 4) == a[4]
    assert ensemble_starts(bodies, FLUME, COLUMN, Perturbation(), seed=8, n=3) != b
    assert len({s[0].centre_m for s in a}) == 5  # every realisation its own start


def test_starts_follow_the_documented_clipped_normal_draws():
    p = Perturbation()
    body = container()
    starts = ensemble_starts([body], FLUME, None, p, seed=1, n=600)
    dx = np.array([s[0].centre_m[0] - body.centre_m[0] for s in starts])
    dy = np.array([s[0].centre_m[1] - body.centre_m[1] for s in starts])
    dyaw = np.array([s[0].yaw_deg for s in starts])
    sigma = p.position_sigma_fraction * body.size_m[0]  # 37.5 mm for the container
    assert sigma == pytest.approx(0.0375)
    assert np.abs(dx).max() <= p.clip_sigmas * sigma + 1e-12 and np.abs(dy).max() <= p.clip_sigmas * sigma + 1e-12
    assert np.abs(dyaw).max() <= p.clip_sigmas * p.yaw_sigma_deg + 1e-12
    # a normal clipped at 2 sigma keeps 0.96 of its standard deviation
    for draws, scale in ((dx, sigma), (dy, sigma), (dyaw, p.yaw_sigma_deg)):
        assert abs(draws.mean()) < 0.12 * scale
        assert 0.85 * scale < draws.std() < 1.05 * scale
    assert {s[0].centre_m[2] for s in starts} == {body.centre_m[2]}  # the height is kept


def test_starts_never_come_within_the_gap_of_walls_column_or_another_body():
    # two containers side by side 1 cm apart, 3 cm from a side wall and 5 cm from the column
    bodies = [container("a", x=0.80, y=0.20), container("b", x=0.80, y=0.13), container("c", x=0.87, y=0.02)]
    flume = FlumeBounds((0.0, 2.0), (-0.3, 0.3))
    p = Perturbation()
    starts = ensemble_starts(bodies, flume, COLUMN, p, seed=3, n=150)
    col = COLUMN.column
    for placed in starts:
        for i, body in enumerate(placed):
            assert start_clash(body, placed[:i], flume, COLUMN, p.min_gap_m) is None
            pts = _footprint_points(body)
            assert pts[:, 1].max() <= 0.3 - p.min_gap_m and pts[:, 1].min() >= -0.3 + p.min_gap_m
            assert not np.any((np.abs(pts[:, 0] - COLUMN.x_m) < col.size_x_m / 2)
                              & (np.abs(pts[:, 1] - COLUMN.y_m) < col.size_y_m / 2))
            for other in placed[:i]:
                assert not _inside(pts, plan_footprint(other)).any()
                assert not _inside(_footprint_points(other), plan_footprint(body)).any()


def test_an_impossible_layout_is_bad_input_naming_the_body():
    narrow = FlumeBounds((0.0, 2.0), (-0.02, 0.02))  # narrower than the container's 0.06 m
    with pytest.raises(InputError) as err:
        perturbed_starts([container()], narrow, None, Perturbation(max_tries=20), 0, 0)
    assert err.value.field == "debris.debris1.centre_m" and "side wall" in str(err.value)
    twins = [container("a"), container("b")]  # the same place, no room to move
    with pytest.raises(InputError) as err:
        perturbed_starts(twins, FLUME, None, Perturbation(position_sigma_fraction=0.0, yaw_sigma_deg=0.0), 0, 0)
    assert err.value.field == "debris.b.centre_m" and "body a" in str(err.value)
    with pytest.raises(InputError) as err:
        Perturbation(yaw_sigma_deg=-1.0)
    assert err.value.field == "yaw_sigma_deg"


# --------------------------------------------------------------------------- table and summary
@pytest.mark.slow
def test_a_study_fit_height_loads_every_fit_there_and_the_same_base_shear_then_reads_another_pulse(current):
    """--study-fit-height: the fit loaded at the height given, not at the face's water level; the
    same base shear fitted elsewhere on the column reads another peak (this short test column's base
    shear per newton loaded differs by more than 5 % between 0.1 and 0.25 m)."""
    flow, npz = current
    starts = ensemble_starts([container()], FLUME, COLUMN, Perturbation(), seed=0, n=2)
    tables = [pd.DataFrame([row for r in run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=1,
                                                      study_fit=fit) for row in r.rows], columns=TABLE_COLUMNS)
              for fit in (True, 0.25, "contact")]
    face, high, contact = (t[t["struck"]] for t in tables)
    assert (contact["study_fit_height_source"] == "contact height").all()
    assert contact["study_fit_height_m"].to_numpy() == pytest.approx(contact["impact_height_m"].to_numpy())
    assert len(face) >= 1 and list(face["realisation"]) == list(high["realisation"])
    assert (high["study_fit_height_source"] == "set by --study-fit-height").all()
    assert high["study_fit_height_m"].to_numpy() == pytest.approx(0.25)
    assert face["study_fit_height_m"].to_numpy() == pytest.approx(0.1)
    ratio = high["study_fit_peak_N"].to_numpy() / face["study_fit_peak_N"].to_numpy()
    assert (np.abs(ratio - 1.0) > 0.05).all()
    assert high["peak_base_shear_N"].to_numpy() == pytest.approx(face["peak_base_shear_N"].to_numpy())


def test_the_table_holds_each_bodys_first_strike_and_its_pulse(current):
    flow, npz = current
    starts = ensemble_starts([container()], FLUME, COLUMN, Perturbation(), seed=0, n=3)
    runs = run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=1)
    table = pd.DataFrame([row for r in runs for row in r.rows], columns=TABLE_COLUMNS)
    assert list(table["realisation"]) == [0, 1, 2] and list(table.columns) == TABLE_COLUMNS
    assert (table["start_x_m"].to_numpy() == [s[0].centre_m[0] for s in starts]).all()
    struck = table[table["struck"]]
    assert len(struck) >= 1
    assert struck[["impact_time_s", "impact_velocity_m_s", "peak_force_N", "duration_s", "impulse_Ns",
                   "peak_base_shear_N", "study_fit_peak_N", "study_fit_duration_s", "study_fit_impulse_Ns"]
                  ].notna().all().all()
    # the study's fit loads the column at the flow's level at the face (the current's 0.1 m), not at the contact
    assert (struck["study_fit_height_source"] == "flow at the face").all()
    assert struck["study_fit_height_m"].to_numpy() == pytest.approx(0.1)
    assert (struck["impact_speed_m_s"] >= struck["impact_velocity_m_s"] - 1e-12).all()
    assert (struck["strikes"] >= 1).all() and (table.loc[~table["struck"], "strikes"] == 0).all()
    # the same realisation run alone: the same first strike, and later strikes without a pulse
    r = int(struck.iloc[0]["realisation"])
    alone = run_transport(starts[r], FLUME, 1.3, flow=flow, column=COLUMN,
                          settings=TransportSettings(first_pulse_only=True))
    column = alone.impacts[alone.impacts["kind"] == "column"]
    assert column.iloc[0]["peak_force_N"] == pytest.approx(struck.iloc[0]["peak_force_N"])
    assert column.iloc[1:]["peak_force_N"].isna().all()
    # a process pool gives the same table as this process
    pooled = run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=2)
    pooled_table = pd.DataFrame([row for r in pooled for row in r.rows], columns=TABLE_COLUMNS)
    timings = ["wall_time_s", "study_fit_wall_s"]
    pd.testing.assert_frame_equal(pooled_table.drop(columns=timings), table.drop(columns=timings))


def test_tracks_are_kept_for_the_first_realisations_only(current, monkeypatch):
    """tracks.csv keeps the first TRACKED_REALISATIONS (2,000) realisations' tracks; the table keeps all."""
    import orchestrator.studies.ensemble as ens

    flow, npz = current
    monkeypatch.setattr(ens, "TRACKED_REALISATIONS", 2)
    starts = ensemble_starts([container()], FLUME, COLUMN, Perturbation(), seed=0, n=3)
    runs = run_ensemble(starts, FLUME, COLUMN, 0.3, flow, npz, "local", workers=1, study_fit=False)
    assert [len(r.rows) for r in runs] == [1, 1, 1]
    assert len(runs[0].tracks) > 10 and len(runs[1].tracks) == len(runs[0].tracks) and runs[2].tracks.empty
    assert list(runs[2].tracks.columns) == list(runs[0].tracks.columns)


def _rows(runs) -> pd.DataFrame:
    return pd.DataFrame([row for r in runs for row in r.rows], columns=TABLE_COLUMNS)


@pytest.mark.slow
def test_batched_realisations_give_the_one_at_a_time_table(current):
    """Realisations stepped together in one model (batches of 4: one of 4 and one of 2) against
    one model each, for the same seeds: the same strikes, first strikes to rounding."""
    flow, npz = current
    starts = ensemble_starts([container()], FLUME, COLUMN, Perturbation(), seed=4, n=6)
    alone = _rows(run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=1, batch_size=1,
                               study_fit=False))
    batched = _rows(run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=1, batch_size=4,
                                 study_fit=False))
    assert alone["struck"].sum() >= 3  # the comparison compares strikes
    assert list(batched["struck"]) == list(alone["struck"]) and list(batched["body"]) == ["debris1"] * 6
    first = ["impact_time_s", "impact_velocity_m_s", "impact_speed_m_s", "impact_height_m", "peak_force_N",
             "duration_s", "impulse_Ns", "peak_base_shear_N", "face_water_level_m"]
    # each body's constraint solve starts from its own state (MuJoCo's whole-model warm start
    # is off), so a batch differs from the realisation alone only by rounding (arrays of other
    # lengths): 1e-13 on the 1-debris record (benchmarks/ensemble.md)
    np.testing.assert_allclose(batched[first].to_numpy(float), alone[first].to_numpy(float), rtol=1e-9, atol=1e-12)
    # without the study's fit its columns are empty, the level at the face is still read
    assert batched["study_fit_peak_N"].isna().all() and batched.loc[batched["struck"], "face_water_level_m"].notna().all()
    # the rebound sequences after the first strike are chaotic: rounding can add or drop a late
    # rebound (here one realisation of six counts 4 strikes batched, 5 alone), not change more
    counts = np.abs(batched["strikes"].to_numpy() - alone["strikes"].to_numpy())
    assert counts.max() <= 1 and (counts == 0).sum() >= 5


def test_realisations_in_one_model_never_touch_each_other():
    """Two realisations at the very same start share one model: no contact pair joins them, so
    each moves as it would alone (here: identical runs); bodies of one realisation keep theirs."""
    from orchestrator.transport.batch import batch_bodies, run_batch
    from orchestrator.transport.mujoco_model import build_model

    pair = [container("a", x=0.6, y=0.1), container("b", x=0.6, y=-0.1)]
    bodies, groups, _ = batch_bodies([pair, pair, pair])
    built = build_model(bodies, FLUME, COLUMN, groups=groups)
    between = built.pair_bodies[built.pair_bodies[:, 1] >= 0]
    assert sorted(map(tuple, between)) == [(0, 1), (2, 3), (4, 5)]  # within each realisation only
    assert len(built.pair_bodies) == 6 * 6 + 3  # bed, 4 walls and the column per body
    start = [container(x=0.6, yaw=10.0)]
    twins = run_batch([start, start], FLUME, 0.4, column=COLUMN,
                      settings=TransportSettings(first_pulse_only=True))
    alone = run_transport(start, FLUME, 0.4, column=COLUMN, settings=TransportSettings(first_pulse_only=True))
    for result in twins:
        pd.testing.assert_frame_equal(result.tracks, alone.tracks)


def _table(struck_velocities, misses: int) -> pd.DataFrame:
    rows = []
    for i, v in enumerate([*struck_velocities, *[math.nan] * misses]):
        hit = not math.isnan(v)
        rows.append({"realisation": i, "body": "debris1", "start_x_m": 3.2, "start_y_m": 0.0, "start_yaw_deg": 0.0,
                     "struck": hit, "impact_time_s": 2.5 if hit else math.nan, "impact_velocity_m_s": v,
                     "impact_height_m": 0.02 if hit else math.nan, "obliquity_deg": 0.0 if hit else math.nan,
                     "peak_force_N": 100 * v, "duration_s": 0.0047 if hit else math.nan,
                     "impulse_Ns": 0.3 * v, "peak_base_shear_N": 110 * v, "strikes": 2 if hit else 0,
                     "wall_time_s": 1.5, "impact_speed_m_s": v + 0.1 if hit else math.nan,
                     "study_fit_peak_N": 90 * v, "study_fit_duration_s": 0.0045 + 0.0002 * v if hit else math.nan,
                     "study_fit_impulse_Ns": 0.25 * v, "study_fit_wall_s": 0.2 if hit else 0.0})
    return pd.DataFrame(rows, columns=TABLE_COLUMNS)


def test_the_summary_counts_strikes_and_states_sample_statistics():
    table = _table([1.5, 1.6, 1.7], misses=1)
    s = summarise(table, 4, wall_time_s=12.3)
    assert s["realisations"] == 4 and s["bodies"] == 1 and s["impact_probability"] == 0.75
    assert s["impact_velocity_m_s"]["mean"] == pytest.approx(1.6)
    assert s["impact_velocity_m_s"]["std"] == pytest.approx(0.1)  # ddof 1
    assert s["peak_force_N"] == pytest.approx({"count": 3, "mean": 160.0, "std": 10.0, "min": 150.0, "max": 170.0})
    assert s["strikes_per_struck_body"]["mean"] == 2 and s["transport_wall_time_s"] == 6.0
    assert s["study"]["impact_velocity_m_s"] == dict(zip(("mean", "std"), STUDY_IMPACT_VELOCITY_M_S))
    assert s["study"]["peak_force_N"]["mean"] == pytest.approx(171.07)
    head = EnsembleResult(table, pd.DataFrame(), s).headline()
    assert set(head) == HEADLINE_KEYS and set(head["impact_velocity_m_s"]) == {"mean", "std"}
    one = summarise(_table([1.4], misses=3), 4, 1.0)
    assert one["impact_probability"] == 0.25 and one["impact_velocity_m_s"]["std"] is None
    none = summarise(_table([], misses=2), 2, 1.0)
    assert none["impact_probability"] == 0.0 and none["peak_force_N"]["mean"] is None
    json.dumps(none, allow_nan=False)  # no NaN in ensemble.json


def test_the_summary_compares_like_with_like_by_welch():
    from scipy import stats

    from orchestrator.results.study_fit import COMPARISON_ROWS

    s = summarise(_table([1.5, 1.6, 1.7], misses=1), 4, 1.0)
    comparison = s["comparison"]
    assert list(comparison) == [column for column, _, _ in COMPARISON_ROWS]
    assert set(comparison["study_fit_peak_N"]) >= {"n", "mean", "standard_error", "median", "q05", "q95", "study_mean",
                                                   "study_std", "study_n", "welch_t", "welch_dof", "p_value", "verdict"}
    peak = comparison["study_fit_peak_N"]  # 135, 144, 153 N against 171.07 +- 62.91 N (22)
    ref = stats.ttest_ind_from_stats(144.0, 9.0, 3, 171.07, 62.91, 22, equal_var=False)
    assert peak["n"] == 3 and peak["mean"] == pytest.approx(144.0) and peak["study_n"] == 22
    assert peak["welch_t"] == pytest.approx(ref.statistic) and peak["p_value"] == pytest.approx(ref.pvalue)
    assert comparison["impact_speed_m_s"]["mean"] == pytest.approx(1.7)  # the total speed
    assert comparison["impact_velocity_m_s"]["mean"] == pytest.approx(1.6)  # its normal part
    assert comparison["study_fit_duration_s"]["study_mean"] == 0.0047
    # 4.82 +- 0.02 ms against 4.7 +- 0.5 ms: the study's mean is known to 0.5 / sqrt(22) = 0.11 ms
    assert comparison["study_fit_duration_s"]["welch_t"] == pytest.approx(
        0.12e-3 / math.sqrt(0.02e-3**2 / 3 + 0.5e-3**2 / 22), rel=1e-6)
    assert comparison["study_fit_duration_s"]["verdict"].startswith("agrees")
    one = summarise(_table([1.4], misses=1), 2, 1.0)["comparison"]["study_fit_peak_N"]
    assert one["n"] == 1 and one["welch_t"] is None and one["z"] == pytest.approx((126.0 - 171.07) / 62.91)
    json.dumps(s, allow_nan=False)


def test_the_report_draws_the_histograms_and_the_envelope(tmp_path):
    table = _table([1.5, 1.6, 1.7], misses=1)
    t = np.linspace(0.0, 2.0, 21)
    tracks = pd.concat([pd.DataFrame({"realisation": r, "body": "debris1", "time_s": t, "x_m": 3.2 + 0.8 * t,
                                      "y_m": 0.02 * r * t, "speed_m_s": 0.8}) for r in range(4)])
    summary = summarise(table, 4, 3.0) | {"scene": "cases/1debris.yaml", "perturbation": Perturbation().to_dict(),
                                          "pulses": "first"}
    result = EnsembleResult(table, tracks, summary)
    from orchestrator.scene.scenefile import load_scene

    scene = load_scene(ROOT / "cases" / "1debris.yaml")
    column = PlacedColumn(5.0, 0.0, Column())
    files = write_report(tmp_path, result, scene, [container(x=3.2)], column)
    assert {p.name for p in files.values()} == {"histograms.png", "envelope.png", "report.md"}
    text = (tmp_path / "report.md").read_text()
    assert "Impact probability: 75 %" in text
    assert "| the contact law's peak force (N) | 160 +- 10 (3) | 171 +- 62.9 |" in text
    peak = summary["comparison"]["study_fit_peak_N"]
    assert (f"| study-fit peak force (N) | 3 | 144 | 5.2 | 144 | 136-152 | 171 | 62.9 | 22 | {peak['welch_t']:+.2f} | "
            f"{peak['welch_dof']:.0f} | {peak['p_value']:.2g} | {peak['verdict']} |") in text
    assert "| study-fit duration (ms) | 3 | 4.82 |" in text and "Welch's unequal-variance t test" in text
    assert "The flow's scene" not in text  # no overrides, no line
    summary["overrides"] = ["fluids.turbulence=kOmegaSST", "reservoir.sill_height_m=0.05"]
    write_report(tmp_path, result, scene, [container(x=3.2)], column)
    assert ("The flow's scene: 1debris.yaml with `fluids.turbulence=kOmegaSST`, `reservoir.sill_height_m=0.05`."
            in (tmp_path / "report.md").read_text())


# --------------------------------------------------------------------------- the verb
@pytest.mark.parametrize("args, flag", [
    (["-n", "0"], "-n"),
    (["-n", "2", "--executor", "ray"], "--executor"),
    (["-n", "2", "--workers", "0"], "--workers"),
    (["-n", "2", "--yaw-sigma", "-3"], "--yaw-sigma"),
    (["-n", "2", "--set", "run.debris_coupling=two-way"], "run.debris_coupling"),
    (["-n", "2", "--study-fit-height", "0"], "--study-fit-height"),
    (["-n", "2", "--study-fit-height", "top"], "--study-fit-height"),
    (["-n", "2", "--study-fit-height", "0.4", "--no-study-fit"], "--study-fit-height"),
])
def test_bad_input_is_exit_2_naming_the_flag(tmp_path, args, flag):
    proc = run_cli("ensemble", str(TINY), "-o", str(tmp_path / "ens"), *args)
    assert proc.returncode == 2, proc.stderr
    assert flag in proc.stderr
    assert not (tmp_path / "ens" / "flow").exists()  # nothing rendered


def test_a_scene_without_debris_is_exit_2_naming_debris(tmp_path):
    proc = run_cli("ensemble", str(ROOT / "cases" / "nodebris.yaml"), "-n", "2", "-o", str(tmp_path / "ens"))
    assert proc.returncode == 2 and "debris" in proc.stderr, proc.stderr


def test_an_ensemble_folder_is_not_replaced_without_force(tmp_path):
    out = tmp_path / "ens"
    out.mkdir()
    (out / "ensemble.csv").write_text("x\n")
    proc = run_cli("ensemble", str(TINY), "-n", "2", "-o", str(out))
    assert proc.returncode == 2 and "-o/--out" in proc.stderr and "--force" in proc.stderr


@pytest.mark.openfoam
def test_the_verb_runs_the_flow_once_and_realisations_on_both_executors(tmp_path, openfoam):
    out = tmp_path / "ens"
    proc = run_cli("ensemble", str(TINY), "-n", "4", "-o", str(out), "--seed", "5", "--executor", "local", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    head = json.loads(proc.stdout)
    assert set(head) == HEADLINE_KEYS and head["realisations"] == 4
    local = pd.read_csv(out / "ensemble.csv")
    assert list(local.columns) == TABLE_COLUMNS and list(local["realisation"]) == [0, 1, 2, 3]
    assert head["impact_probability"] == pytest.approx(local["struck"].mean())
    assert local["struck"].any()  # launched at the column at 0.8 m/s: most starts strike it
    struck = local[local["struck"]]
    assert head["peak_force_N"]["mean"] == pytest.approx(struck["peak_force_N"].mean())
    summary = json.loads((out / "ensemble.json").read_text())
    assert summary["executor"] == "local" and summary["seed"] == 5
    for name in ("report.md", "histograms.png", "envelope.png", "tracks.csv"):
        assert (out / name).is_file(), name
    run_json = (out / "flow" / "run.json").read_text()
    # again on Dask with 2 realisations: the flow is reused, and realisations 0 and 1 are the same
    proc = run_cli("ensemble", str(TINY), "-n", "2", "-o", str(out), "--seed", "5", "--executor", "dask", "--force",
                   "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert json.loads(proc.stdout)["realisations"] == 2
    assert (out / "flow" / "run.json").read_text() == run_json
    on_dask = pd.read_csv(out / "ensemble.csv")
    timings = ["wall_time_s", "study_fit_wall_s"]  # wall-clock costs differ from run to run
    pd.testing.assert_frame_equal(on_dask.drop(columns=timings), local.iloc[:2].drop(columns=timings))
    assert json.loads((out / "ensemble.json").read_text())["executor"] == "dask"


def test_the_same_seed_gives_the_same_ensemble_csv_with_the_added_mass_tables_kept(current, monkeypatch):
    """A batch keeps one added-mass table per body size (analytical.hydrodynamics.added_mass_table)
    instead of building it for every body of every batch: the same seed gives the same ensemble.csv,
    byte for byte, as with a table built afresh for each body, and a caller's copy is its own."""
    import orchestrator.transport.engine as engine
    from analytical.added_mass import box_added_mass
    from analytical.hydrodynamics import ADDED_MASS_TABLE_POINTS, added_mass_table

    def afresh(size_m, water_density_kg_m3=998.0, points=ADDED_MASS_TABLE_POINTS):
        volume = size_m[0] * size_m[1] * size_m[2]
        table = np.zeros((points, 6))
        for k, f in enumerate(np.linspace(0.0, 1.0, points)):
            if f > 0.0:
                table[k] = box_added_mass(size_m, water_density_kg_m3 * volume * f, water_density_kg_m3).diagonal
        return table

    size = container().size_m
    mine = added_mass_table(size)
    np.testing.assert_array_equal(mine, afresh(size))
    mine[:] = 0.0  # the caller's copy
    np.testing.assert_array_equal(added_mass_table(size), afresh(size))

    flow, npz = current
    starts = ensemble_starts([container(), container("debris2", x=0.3, y=0.15)], FLUME, COLUMN, Perturbation(),
                             seed=11, n=3)

    def csv() -> str:
        table = _rows(run_ensemble(starts, FLUME, COLUMN, 1.3, flow, npz, "local", workers=1, batch_size=3,
                                   study_fit=False))
        return table.drop(columns=["wall_time_s", "study_fit_wall_s"]).to_csv(index=False, float_format="%.10g")

    kept, again = csv(), csv()
    monkeypatch.setattr(engine, "added_mass_table", afresh)
    assert kept == again == csv() and "True" in kept
