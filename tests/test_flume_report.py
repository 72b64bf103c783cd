"""The flume-as-built page: every member's arrivals against the measured ones and the first
member's, the front's speed between the gauges, bad sweeps named."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
from orchestrator.core.errors import InputError
from orchestrator.scene.scenefile import dump_scene_yaml, load_scene
from orchestrator.studies.flume_report import flume_members, write_flume_report
from tests.conftest import check_report_verb

FACE_X = 4.89
CASES = Path(__file__).resolve().parents[1] / "cases"


def _member(folder, arrivals, sill=0.0, depth=0.40, opening=None, column_x=5.0, closure="laminar", opening_s=0.0,
            cell=None, drag=None, interval=None, refine=None):
    """A post-processed member: the shipped flume scene (its 2D centreline strip without a column)
    with these changes, and its gauges' arrivals."""
    (folder / "results").mkdir(parents=True)
    base = CASES / ("flume-centreline-2d.yaml" if column_x is None else "nodebris.yaml")
    sets = [f"fluids.turbulence={closure}", f"reservoir.depth_m={depth}", f"reservoir.sill_height_m={sill}",
            f"reservoir.opening_time_s={opening_s}", f"mesh.cell_size_m={cell or (0.02 if column_x is None else 0.04)}",
            "run.end_time_s=2.0"]
    sets += [] if column_x is None else [f"column.x_m={column_x}"]
    sets += [] if opening is None else [f"reservoir.opening_width_m={opening}"]
    sets += [] if drag is None else [f"bed.friction_calibration={drag}"]
    sets += [] if interval is None else [f"outputs.probe_interval_s={interval}"]
    sets += [] if refine is None else [f"mesh.refine_box_m={list(refine)}", "mesh.refine_cell_size_m=0.02"]
    (folder / "scene.yaml").write_text(dump_scene_yaml(load_scene(base, sets)))
    rows = [{"gauge": name, "x_m": x, "arrival_s": t}
            for (name, x), t in zip((("WG2", 2.40), ("WG3", 3.20), ("WG4", FACE_X)), arrivals)]
    pd.DataFrame(rows).to_csv(folder / "results" / "gauge_summary.csv", index=False)


def test_each_member_is_set_beside_the_measured_arrivals_and_the_scene_as_shipped(tmp_path):
    sweep = tmp_path / "sweep"
    _member(sweep / "a", (0.876, 1.186, 1.708))
    _member(sweep / "b", (0.932, 1.265, 1.910), sill=0.05, depth=0.35)
    _member(sweep / "c", (0.910, 1.204, 1.735), opening_s=0.2)
    _member(sweep / "d", (0.890, 1.250, 1.800), cell=0.02)
    _member(sweep / "e", (0.903, 1.231, 1.719), drag=3.0)
    members = flume_members(sweep)
    # the front's speed over each reach: distance over the difference of the arrivals
    assert members[1].speed_wg2_wg3_m_s == pytest.approx(0.80 / (1.265 - 0.932))
    assert members[1].speed_wg3_face_m_s == pytest.approx((FACE_X - 3.20) / (1.910 - 1.265))
    files = write_flume_report(sweep, tmp_path / "page")
    text = files["report"].read_text()
    assert "| the scene as shipped | 0.876 | +0.000 |" in text
    assert ("the scene `nodebris` (laminar, 4 cm cells, a 1.5 m wide flume, the column, 2 s)" in text
            and "`debrisfoam sweep cases/sweeps/sweep.yaml`" in text)
    assert "| sill 5 cm, level 0.35 m above the bed (0.4 m deep) | 0.932 | +0.056 | 1.265 | +0.079 |" in text
    assert "+0.022, -0.125" in text  # against the measured 0.91 and 1.39 s
    assert "| gate opening over 0.2 s | 0.910 | +0.034 | 1.204 | +0.018 |" in text
    assert "| 2 cm cells | 0.890 | +0.014 |" in text  # a finer mesh is named as the change
    assert "| bed drag calibration 3 | 0.903 | +0.027 |" in text  # the drag layer's coefficient is named
    assert len(pd.read_csv(files["table"])) == 5 and files["figure"].stat().st_size > 10_000


def test_a_member_without_a_gauge_and_an_empty_sweep_are_named(tmp_path):
    with pytest.raises(InputError, match="no post-processed member"):
        flume_members(tmp_path)
    _member(tmp_path / "a", (0.9, 1.2, 1.7))
    table = pd.read_csv(tmp_path / "a" / "results" / "gauge_summary.csv")
    table[table["gauge"] != "WG3"].to_csv(tmp_path / "a" / "results" / "gauge_summary.csv", index=False)
    with pytest.raises(InputError, match="has no gauge WG3"):
        flume_members(tmp_path)


def test_a_folder_the_sweep_no_longer_lists_is_left_off_the_page(tmp_path):
    import json

    sweep = tmp_path / "sweep"
    for name, arrivals in {"new2": (0.9, 1.2, 1.7), "new1": (0.876, 1.186, 1.708), "old": (0.8, 1.1, 1.6)}.items():
        _member(sweep / name, arrivals)
    assert [m.member for m in flume_members(sweep)] == ["new1", "new2", "old"]  # no sweep.json: every folder
    (sweep / "sweep.json").write_text(json.dumps({"members": [{"member": 1, "id": "new2"}, {"member": 2, "id": "new1"}]}))
    assert [m.member for m in flume_members(sweep)] == ["new2", "new1"]  # the sweep's members, in its order


def test_the_verb_writes_the_page_and_refuses_an_empty_sweep(tmp_path):
    _member(tmp_path / "sweep" / "a", (0.876, 1.186, 1.708))
    check_report_verb("flume", tmp_path / "sweep", tmp_path)


def test_a_flume_without_a_column_reads_its_wg4_as_a_plain_gauge(tmp_path):
    sweep = tmp_path / "sweep"
    _member(sweep / "a", (0.865, 1.202, 2.039), column_x=None, closure="kOmegaSST")
    _member(sweep / "b", (0.981, 1.401, 2.165), sill=0.05, depth=0.35, column_x=None, closure="kOmegaSST")
    text = write_flume_report(sweep, tmp_path / "page")["report"].read_text()
    assert "(kOmegaSST, 2 cm cells, a 0.1 m wide flume, no column, 2 s)" in text
    assert "| the scene as shipped | 0.865 |" in text
    assert "| sill 5 cm, level 0.35 m above the bed (0.4 m deep) | 0.981 |" in text and "column at" not in text
    assert "The water at the column's face" not in text  # no column: no face section


# ---------------------------------------------------------------- the face and the reaches, from gauge records

def _profiles(folder, gauge, times, wet_tops, step=0.01, top=0.6):
    """Raw `sets` profiles of one gauge (z, alpha.water), water up to ``wet_tops`` at ``times``, as v1912
    writes them (postProcessing/gauges/<time>/<gauge>_alpha.water.xy)."""
    import numpy as np

    z = np.arange(step / 2, top, step)
    for t, h in zip(times, wet_tops):
        d = folder / "postProcessing" / "gauges" / f"{t:g}"
        d.mkdir(parents=True, exist_ok=True)
        alpha = np.where(z < h, 1.0, 0.0)
        (d / f"{gauge}_alpha.water.xy").write_text("".join(f"{a:g} {b:g}\n" for a, b in zip(z, alpha)))


def _flow_member(folder, arrivals, centreline, interval=0.01, refine=None):
    """A member with WG2-WG4 (:func:`_member`), centreline gauges {x: arrival}, a probe interval,
    a gauges.csv for WG4 and raw WG4 profiles with a splash above the integral."""
    _member(folder, arrivals, interval=interval, refine=refine)
    summary = pd.read_csv(folder / "results" / "gauge_summary.csv")
    summary["y_m"] = 0.0
    extra = [{"gauge": f"CL{round(x * 100)}", "x_m": x, "y_m": 0.0, "arrival_s": t} for x, t in centreline.items()]
    pd.concat([summary, pd.DataFrame(extra)]).to_csv(folder / "results" / "gauge_summary.csv", index=False)
    face = arrivals[2]
    times = [face - 0.1, face, face + 0.1, face + 0.2, face + 0.3, face + 0.4]
    pd.DataFrame({"time_s": times, "WG4_elevation_m": [0.015, 0.02, 0.10, 0.30, 0.20, 0.25]}).to_csv(
        folder / "results" / "gauges.csv", index=False)
    _profiles(folder, "WG4", times, [0.015, 0.02, 0.12, 0.45, 0.22, 0.26])


def test_the_face_is_read_at_its_peaks_and_after_the_front_from_the_records(tmp_path):
    from orchestrator.studies.face_reach import face_reading, face_series, value_at

    case = tmp_path / "a"
    _flow_member(case, (0.876, 1.186, 1.70), {1.0: 0.40, 1.5: 0.60})
    reading = face_reading(face_series(case, "WG4"), 1.70)
    assert reading.elevation_peak_m == pytest.approx(0.30) and reading.elevation_peak_s == pytest.approx(1.90)
    assert reading.elevation_after_m == pytest.approx((0.10, 0.20))
    # the highest sample with alpha above 0.5: the cell centre below 0.45 m (0.445), not the integral's 0.30
    assert reading.wet_peak_m == pytest.approx(0.445) and reading.wet_peak_s == pytest.approx(1.90)
    assert reading.wet_after_m == pytest.approx((0.115, 0.215))
    assert value_at([0.0, 1.0], [0.0, 2.0], 0.25) == pytest.approx(0.5)
    assert value_at([0.0, 1.0], [0.0, 2.0], 1.5) != value_at([0.0, 1.0], [0.0, 2.0], 1.5)  # past the record: nan


def test_reach_speeds_and_a_front_that_falls_or_holds_or_speeds_up(tmp_path):
    from orchestrator.studies.face_reach import reach_speeds, reach_verdict

    def summary(arrivals):
        rows = [{"gauge": f"CL{round(x * 100)}", "x_m": x, "y_m": 0.0, "arrival_s": t} for x, t in arrivals.items()]
        rows += [{"gauge": "WG3", "x_m": 3.2, "y_m": 0.5, "arrival_s": 0.3},  # off the centreline
                 {"gauge": "WG2", "x_m": 1.2, "y_m": 0.0, "arrival_s": 0.45},  # the study's: left out
                 {"gauge": "WG4", "x_m": 4.89, "y_m": 0.0, "arrival_s": 9.0}]  # the face: left out
        return pd.DataFrame(rows)

    skip = ("WG2", "WG4")
    falling = reach_speeds(summary({1.0: 0.40, 1.5: 0.60, 2.0: 0.81}), 4.89, 0.01, skip)
    assert [(r.x0_m, r.x1_m) for r in falling] == [(1.0, 1.5), (1.5, 2.0)]
    assert falling[0].speed_m_s == pytest.approx(2.5) and falling[1].speed_m_s == pytest.approx(0.5 / 0.21)
    # arrivals read 0.01 s apart: a speed v over a time T uncertain by v dt / T
    assert falling[0].uncertainty_m_s == pytest.approx(2.5 * 0.01 / 0.20)
    assert reach_verdict(falling) == "falls or holds"
    # faster by less than both uncertainties (0.125 + 0.132): holds
    assert reach_verdict(reach_speeds(summary({1.0: 0.40, 1.5: 0.60, 2.0: 0.79}), 4.89, 0.01, skip)) == "falls or holds"
    # 2.5 then 3.33 m/s: faster by more than both: named as speeding up, with its reach
    up = reach_speeds(summary({1.0: 0.40, 1.5: 0.60, 2.0: 0.75}), 4.89, 0.01, skip)
    assert reach_verdict(up) == "speeds up (1.5-2 m)"
    # the same gain read from coarse samples (0.05 s) is within the uncertainty
    assert reach_verdict(reach_speeds(summary({1.0: 0.40, 1.5: 0.60, 2.0: 0.75}), 4.89, 0.05, skip)) == "falls or holds"
    assert reach_verdict(falling[:1]) == "-"


def test_the_page_sets_the_face_beside_the_study_s_load_points_and_names_a_speed_up(tmp_path):
    sweep = tmp_path / "sweep"
    _flow_member(sweep / "a", (0.876, 1.186, 1.70), {1.0: 0.40, 1.5: 0.60, 2.0: 0.81})
    _flow_member(sweep / "b", (0.876, 1.186, 1.72), {1.0: 0.40, 1.5: 0.60, 2.0: 0.75},
                 refine=[4.7, 4.95, -0.06, 0.06, 0.0, 0.55])
    files = write_flume_report(sweep, tmp_path / "page")
    text = files["report"].read_text()
    assert "0.16-0.5 m above the base, mean 0.4 m" in text
    assert "| the scene as shipped | 1.700 | 0.300 (+0.20) | 0.100 | 0.200 | 0.445 (+0.20) | 0.115 | 0.215 |" in text
    assert "| 2 cm cells in x 4.7-4.95, y -0.06..0.06, z 0-0.55 m | 1.720 |" in text
    assert "| the scene as shipped | 2.50 +- 0.13 | 2.38 +- 0.11 | falls or holds |" in text
    assert "| 3.33 +- 0.22 | speeds up (1.5-2 m) |" in text
    face = pd.read_csv(files["face_table"])
    assert list(face["reach_verdict"]) == ["falls or holds", "speeds up (1.5-2 m)"]
    assert files["face_figure"].stat().st_size > 10_000


# ---------------------------------------------------------------- arrivals read at other rises

def _toe(x, t, c=2.0, height=0.10, length=0.5, start=0.015):
    """The level at x of a front moving at c whose toe rises linearly over ``length`` (m) behind its tip."""
    import numpy as np

    return start + height * np.clip((c * np.asarray(t) - x) / length, 0.0, 1.0)


def test_a_toe_of_one_shape_reads_one_speed_at_every_rise_and_the_fitted_rise_is_found():
    import numpy as np

    from orchestrator.studies.gauge_reading import rise_for_arrival

    t = np.linspace(0.0, 3.0, 3001)
    # the tip reaches x = 2.4 m at 1.2 s; a rise r is reached length * r / height / c later
    assert rise_for_arrival(t, _toe(2.4, t), 1.2 + 0.5 * 0.02 / 0.10 / 2.0) == pytest.approx(0.02, abs=1e-5)
    assert rise_for_arrival(t, _toe(2.4, t), 1.0) != rise_for_arrival(t, _toe(2.4, t), 1.0)  # before the tip: nan
    assert rise_for_arrival(t, _toe(2.4, t), 2.0) != rise_for_arrival(t, _toe(2.4, t), 2.0)  # after the crest: nan


def test_the_page_reads_the_front_at_other_rises_and_checks_the_wg2_rise_on_wg3(tmp_path):
    import numpy as np

    sweep = tmp_path / "sweep"
    t = np.linspace(0.0, 2.5, 2501)
    # a: one toe shape (2 m/s at every rise); b: the toe stretches from 0.2 m at WG2 to 0.8 m at WG3;
    # c: a faster front whose tip reaches WG2 at 0.85 s, so a rise puts WG2 on the measured 0.91 s
    for name, (l2, l3, c) in {"a": (0.5, 0.5, 2.0), "b": (0.2, 0.8, 2.0), "c": (0.5, 0.5, 2.4 / 0.85)}.items():
        _member(sweep / name, (1.2, 1.6, 2.0))
        pd.DataFrame({"time_s": t, "WG2_elevation_m": _toe(2.4, t, c=c, length=l2),
                      "WG3_elevation_m": _toe(3.2, t, c=c, length=l3)}).to_csv(
            sweep / name / "results" / "gauges.csv", index=False)
    files = write_flume_report(sweep, tmp_path / "page")
    text = files["report"].read_text()
    assert "| the scene as shipped | 2.00 | 2.00 | 2.00 | 2.00 | 2.00 | - | - | - | - |" in text  # WG2 after 0.91 s
    assert files["gauge_figure"].stat().st_size > 10_000 and "![WG2 and WG3](gauges.png)" in text
    rises = pd.read_csv(files["rise_table"]).set_index("member")
    # b at 40 mm: WG2 at 1.2 + 0.2 * 0.4 / 2 = 1.24 s, WG3 at 1.6 + 0.8 * 0.4 / 2 = 1.76 s
    assert rises.loc["b", "speed_at_40mm_m_s"] == pytest.approx(0.8 / 0.52, rel=1e-3)
    assert np.isnan(rises.loc["a", "fitted_rise_m"])
    # c: 0.06 s after the tip the toe stands 0.06 c 0.10 / 0.5 = 33.9 mm; WG3 reads it 0.06 s after its tip, 3.2 / c
    assert "| 33.9 | 1.193 | -0.197 | 2.82 |" in text


def test_a_step_in_the_front_is_read_as_a_shelf_and_a_plain_ramp_as_none():
    import numpy as np

    from orchestrator.studies.gauge_reading import front_shelf

    t = np.linspace(0.0, 2.5, 2501)
    # 15 mm, up to 40 mm over 0.1 s from 1.0 s (0.25 m/s), held to 1.6 s, then up to 120 mm over 0.2 s (0.4 m/s)
    step = np.interp(t, [0.0, 1.0, 1.1, 1.6, 1.8, 2.5], [0.015, 0.015, 0.04, 0.04, 0.12, 0.12])
    shelf = front_shelf(t, step, 1.0, 0.056)
    # 56 mm is reached 0.016 / 0.4 s into the second rise; the 10 mm band best takes in the slower ramp below
    assert shelf.rise_s == pytest.approx(0.64, abs=2e-3)
    assert shelf.held_s == pytest.approx(0.5 + 0.01 / 0.25, abs=3e-3)
    assert 0.035 < shelf.level_m < 0.041
    ramp = np.interp(t, [0.0, 1.0, 1.5, 2.5], [0.015, 0.015, 0.12, 0.12])  # 0.21 m/s without a pause
    assert front_shelf(t, ramp, 1.0, 0.056).held_s == pytest.approx(0.01 / 0.21, abs=3e-3)
    assert np.isnan(front_shelf(t, step, 1.0, 0.5).rise_s)  # never reaches 0.5 m: no rise time
