"""The bore check reads Stoker's own solution back as Stoker's, a faster front as faster, and
writes its page from a sweep's folders."""

from __future__ import annotations

import functools
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analytical.dambreak import StokerSolution
from orchestrator.core.errors import InputError
from orchestrator.plan.model import ModelPlan
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene
from orchestrator.studies.bore_check import bore_check, check_run, write_bore_report
from tests.conftest import check_report_verb, render_and_run, run_cli

ROOT = Path(__file__).resolve().parent.parent

H0, H1 = 0.40, 0.015
GAUGES = {f"G{i}": float(i) for i in range(2, 8)}


def _records(h1=H1, stretch=1.0, t_end=3.5):
    """Stoker's levels at the gauges; ``stretch`` > 1 runs the same wave that much faster."""
    stoker = StokerSolution(H0, h1)
    t = np.arange(0.0, t_end, 0.005)
    return t, {name: np.array([float(stoker.profile(x / stretch, tt)[0]) for tt in t]) for name, x in GAUGES.items()}


@pytest.mark.parametrize("h1", [0.015, 0.04])
def test_stokers_own_solution_reads_as_stokers(h1):
    t, levels = _records(h1)
    check = bore_check(t, levels, GAUGES, H0, h1)
    assert abs(check.speed_error_pct) < 0.5 and abs(check.mid_speed_error_pct) < 0.5  # a step: any level
    assert abs(check.depth_error_pct) < 0.1
    assert not check.front_speeds_up
    assert check.gauges_used == tuple(f"G{i}" for i in range(2, 8))  # 5 h0 = 2 m past the gate and on


def test_a_front_half_as_fast_again_reads_fifty_percent_fast():
    t, levels = _records(stretch=1.5)
    check = bore_check(t, levels, GAUGES, H0, H1)
    assert check.speed_error_pct == pytest.approx(50.0, abs=1.0)


def test_a_front_that_rises_over_a_time_reads_slower_at_its_mid_height():
    # Stoker's wave, its front spread over a ramp that lengthens by 0.05 s a metre: the toe keeps
    # Stoker's arrival and speed, the mid-height arrives 0.025 s a metre later
    stoker = StokerSolution(H0, H1)
    t = np.arange(0.0, 3.5, 0.005)
    levels = {}
    for name, x in GAUGES.items():
        toe = x / stoker.state.shock_speed_m_s
        ramp = np.clip((t - toe) / (0.05 * x), 0.0, 1.0)
        levels[name] = H1 + (stoker.state.h2_m - H1) * ramp
    check = bore_check(t, levels, GAUGES, H0, H1)
    expected = 1.0 / (1.0 / stoker.state.shock_speed_m_s + 0.025)
    assert check.mid_speed_m_s == pytest.approx(expected, rel=0.01)
    assert abs(check.speed_error_pct) < 2.0 and check.mid_speed_error_pct < -4.0


def test_the_bore_depth_is_read_only_where_the_run_holds_stokers_plateau_half_a_second():
    # up to 3.5 s Stoker's plateau lasts 0.47 s past the settling at G6 and none at G7: levels 30 %
    # low there (a front still rising) leave the depth alone; 10 % low at G5 (0.93 s) moves it by a quarter
    t, levels = _records()
    for name in ("G6", "G7"):
        levels[name] = 0.7 * levels[name]
    check = bore_check(t, levels, GAUGES, H0, H1)
    assert abs(check.depth_error_pct) < 0.1
    assert [np.isfinite(v) for v in check.gauge_depth_errors_pct] == [True] * 4 + [False] * 2
    levels["G5"] = 0.9 * levels["G5"]
    assert bore_check(t, levels, GAUGES, H0, H1).depth_error_pct == pytest.approx(-2.5, abs=0.1)


def test_a_front_that_speeds_up_is_said_to():
    t, levels = _records()
    t2, fast = _records(stretch=1.6)
    levels["G6"], levels["G7"] = fast["G6"], fast["G7"]
    assert bore_check(t, levels, GAUGES, H0, H1).front_speeds_up


@pytest.mark.parametrize("h1, gauges, field", [(0.0, GAUGES, "bed.wet_depth_m"), (0.5, GAUGES, "bed.wet_depth_m"),
                                               (H1, {"G1": 1.0, "G2": 2.0}, "gauges")])
def test_bad_input_names_the_field(h1, gauges, field):
    t, levels = _records()
    levels["G1"] = levels["G2"]
    with pytest.raises(InputError, match=field):
        bore_check(t, levels, gauges, H0, h1)


@functools.cache
def _plan() -> ModelPlan:
    """A plan as `debrisfoam render` writes it (the members' own closure and cell count set over it)."""
    return plan_case(load_scene(ROOT / "cases" / "tiny-nodebris.yaml"))


def _member(folder, turbulence, cells, stretch):
    t, levels = _records(stretch=stretch)
    (folder / "results").mkdir(parents=True)
    pd.DataFrame({"time_s": t, **{f"{n}_elevation_m": v for n, v in levels.items()}}).to_csv(
        folder / "results" / "gauges.csv", index=False)
    scene = load_scene(ROOT / "cases" / "stoker-wet-bed.yaml", [f"mesh.wet_bed_cells={cells}"])  # G2-G7, H0 over H1
    assert {g.name: g.x_m for g in scene.gauges} == GAUGES and scene.bed.wet_depth_m == H1
    (folder / "scene.yaml").write_text(dump_scene_yaml(scene))
    (folder / "plan.json").write_text(replace(_plan(), turbulence=turbulence, cell_count=1000).to_json())
    (folder / "run.json").write_text(json.dumps({"runner": {"solver_wall_s": 12.5}}))


def test_the_page_lists_every_member_beside_stoker(tmp_path):
    sweep = tmp_path / "sweep"
    _member(sweep / "a", "laminar", 1, 1.56)
    _member(sweep / "b", "kOmegaSST", 6, 1.0)
    assert check_run(sweep / "a").speed_error_pct == pytest.approx(56.0, abs=1.0)
    files = write_bore_report(sweep, tmp_path / "page")
    text = files["report"].read_text()
    assert "| 0.0375 | laminar | 1 |" in text and "| 0.0375 | kOmegaSST | 6 |" in text
    assert files["gauges-h1-15mm.png"].stat().st_size > 10_000
    table = pd.read_csv(files["table"])
    assert len(table) == 2


def test_an_empty_sweep_and_an_unposted_run_are_named(tmp_path):
    with pytest.raises(InputError, match="no post-processed member"):
        write_bore_report(tmp_path, tmp_path / "page")
    with pytest.raises(InputError, match="gauges.csv"):
        check_run(tmp_path)


def test_the_verb_writes_the_page_and_an_empty_sweep_is_bad_input(tmp_path):
    _member(tmp_path / "sweep" / "a", "kOmegaSST", 6, 1.0)
    check_report_verb("bore", tmp_path / "sweep", tmp_path)


#: RANS k-omega SST over a wet bed six cells deep and a slip bed, 1 cm cells, against Stoker
#: (docs/results/wet-bed/, docs/bed-friction.md). At the study's h1/h0 = 0.0375 and at 0.05 the front
#: (read at a 2 % h0 rise and at its mid-height) and the bore depth are within 3 % (measured -1.7,
#: -0.6, +0.4 % and +0.5, +0.4, 0.0 %; at 2 cm the mid-height reads -7.9 %). At h1/h0 = 0.1 the front
#: is (+0.6 %) and the bore is not: it stands 7.0 % below h2 (-5.7 % at 2 cm), so that test names a
#: bore 3-10 % shallow. (At 0.2 the front is +5.1 %, the bore -2.9 %: no test.)
STOKER_TOLERANCE_PCT = 3.0
STOKER_CELLS = ("fluids.turbulence=kOmegaSST", "mesh.wet_bed_cells=6", "mesh.cell_size_m=0.01")


def _stoker_run(tmp_path, *sets):
    case = tmp_path / "stoker"
    render_and_run(ROOT / "cases" / "stoker-wet-bed.yaml", case, *STOKER_CELLS, *sets)
    proc = run_cli("post", str(case))
    assert proc.returncode == 0, proc.stderr[-2000:]
    return check_run(case)


@pytest.mark.openfoam
@pytest.mark.slow
@pytest.mark.parametrize("wet_depth_m", [0.015, 0.02])
def test_a_frictionless_wet_bed_dam_break_runs_at_stokers_bore_speed_and_depth(openfoam, tmp_path, wet_depth_m):
    """cases/stoker-wet-bed.yaml (2D, 0.40 m over 15 mm or 20 mm on a slip bed), RANS on a resolved wet
    bed at 1 cm: the front speed over the gauges 2-7 m past the gate, read at its toe and at its
    mid-height, and the bore depth each within 3 % of Stoker's (about 2-2.5 min of solver on 2 cores)."""
    check = _stoker_run(tmp_path, f"bed.wet_depth_m={wet_depth_m}")
    assert abs(check.speed_error_pct) <= STOKER_TOLERANCE_PCT, check
    assert abs(check.mid_speed_error_pct) <= STOKER_TOLERANCE_PCT, check
    assert abs(check.depth_error_pct) <= STOKER_TOLERANCE_PCT, check


@pytest.mark.openfoam
@pytest.mark.slow
def test_over_a_deeper_wet_bed_the_front_runs_at_stokers_speed_and_the_bore_stands_shallow(openfoam, tmp_path):
    """The same at h1/h0 = 0.1 (40 mm): the front within 3 % of Stoker's speed, the bore 3-10 % below
    his h2 (no resolution tried brings it within 3 %: -5.7 % at 2 cm, -7.0 % at 1 cm)."""
    check = _stoker_run(tmp_path, "bed.wet_depth_m=0.04")
    assert abs(check.speed_error_pct) <= STOKER_TOLERANCE_PCT, check
    assert -10.0 <= check.depth_error_pct <= -STOKER_TOLERANCE_PCT, check


def test_a_member_without_its_plan_is_named(tmp_path):
    """A folder with gauges but no plan.json (a copy gone wrong) is bad input naming the file."""
    (tmp_path / "m" / "results").mkdir(parents=True)
    (tmp_path / "m" / "results" / "gauges.csv").write_text("time_s\n0\n")
    (tmp_path / "m" / "scene.yaml").write_text("name: x\n")
    with pytest.raises(InputError, match="plan.json"):
        check_run(tmp_path / "m")
