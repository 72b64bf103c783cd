"""The flume-as-built page: every member's arrivals against the measured ones and the first
member's, the front's speed between the gauges, bad sweeps named."""

from __future__ import annotations

import pandas as pd
import pytest
import yaml

from orchestrator.core.errors import InputError
from orchestrator.studies.flume_report import flume_members, write_flume_report
from tests.conftest import check_report_verb

FACE_X = 4.89


def _member(folder, arrivals, sill=0.0, depth=0.40, opening=None, column_x=5.0, closure="laminar", opening_s=0.0):
    (folder / "results").mkdir(parents=True)
    scene = {"name": "nodebris", "flume": {"width_m": 1.5 if column_x else 0.1}, "fluids": {"turbulence": closure},
             "reservoir": {"depth_m": depth, "sill_height_m": sill, "opening_width_m": opening,
                           "opening_time_s": opening_s},
             "bed": {"wet_depth_m": 0.015}, "column": None if column_x is None else {"x_m": column_x},
             "mesh": {"cell_size_m": 0.04 if column_x else 0.02}, "run": {"end_time_s": 2.0}}
    (folder / "scene.yaml").write_text(yaml.safe_dump(scene))
    rows = [{"gauge": name, "x_m": x, "arrival_s": t}
            for (name, x), t in zip((("WG2", 2.40), ("WG3", 3.20), ("WG4", FACE_X)), arrivals)]
    pd.DataFrame(rows).to_csv(folder / "results" / "gauge_summary.csv", index=False)


def test_each_member_is_set_beside_the_measured_arrivals_and_the_scene_as_shipped(tmp_path):
    sweep = tmp_path / "sweep"
    _member(sweep / "a", (0.876, 1.186, 1.708))
    _member(sweep / "b", (0.932, 1.265, 1.910), sill=0.05, depth=0.35)
    _member(sweep / "c", (0.910, 1.204, 1.735), opening_s=0.2)
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
    assert len(pd.read_csv(files["table"])) == 3 and files["figure"].stat().st_size > 10_000


def test_a_member_without_a_gauge_and_an_empty_sweep_are_named(tmp_path):
    with pytest.raises(InputError, match="no post-processed member"):
        flume_members(tmp_path)
    _member(tmp_path / "a", (0.9, 1.2, 1.7))
    table = pd.read_csv(tmp_path / "a" / "results" / "gauge_summary.csv")
    table[table["gauge"] != "WG3"].to_csv(tmp_path / "a" / "results" / "gauge_summary.csv", index=False)
    with pytest.raises(InputError, match="has no gauge WG3"):
        flume_members(tmp_path)


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
