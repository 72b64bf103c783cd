"""The still water a case starts with: what setFields puts in and what the gauges read.

A small 2D flume (interFoam, 4 cm cells: the seed's default resolution) with a 15 mm wet
bed, the 1-debris scene's, under a 0.16 m impoundment; the gauges stand far enough
downstream that the bore cannot reach them during the 0.03 s run (Stoker's front, 1.25 m/s,
needs 0.8 s to reach x = 1.0 m), so every sample they take is of the still wet bed. The
bed layer (0..15 mm) lies under 36 mm cells: a gauge that interpolates alpha.water
between cell centres and points (cellPoint) spreads the surface over the coarse cell above
and reads 20.4 mm here (20.5, 19.9 and 20.9 mm on the 1-debris scene's 3D mesh); sampled
per cell and integrated cell by cell, it reads the 15 mm the mesh holds.
"""

from __future__ import annotations

import math
from pathlib import Path

import pandas as pd
import pytest
import yaml

from orchestrator.case.outputs import read_water_balance
from orchestrator.report.postprocess import post_case
from orchestrator.plan.planner import plan_case
from orchestrator.pipeline import render_from_file
from orchestrator.run.runner import run_case
from orchestrator.scene.scenefile import load_scene

WET = 0.015
DEPTH = 0.16
WIDTH = 0.3


def still_scene(**mesh) -> dict:
    return {
        "name": "still-water",
        "flume": {"length_m": 2.0, "width_m": WIDTH, "height_m": 0.3, "downstream_end": "open"},
        "reservoir": {"length_m": 0.3, "depth_m": DEPTH, "gate": "instant"},
        "bed": {"wet_depth_m": WET, "friction_factor": 0.0},
        "debris": [],
        "gauges": [{"name": "WGa", "x_m": 1.0, "y_m": 0.0}, {"name": "WGb", "x_m": 1.2, "y_m": 0.0}],
        "mesh": {"cell_size_m": 0.04, "coarsening_ratio": 1, **mesh},
        "run": {"end_time_s": 0.03, "cores": 1, "write_interval_s": 0.03, "max_courant": 0.9},
        "outputs": {"probe_interval_s": 0.01, "preview": False},
    }


def scene_volume_m3(plan) -> float:
    """The water the scene asks for inside the modelled domain: the impoundment behind the
    gate and the wet bed in front of it (no column: nothing is cut out)."""
    (x0, x1), (y0, y1), _ = plan.domain_m
    return (0.0 - x0) * (y1 - y0) * DEPTH + (x1 - 0.0) * (y1 - y0) * WET


@pytest.fixture(scope="module")
def still_case(tmp_path_factory) -> Path:
    tmp = tmp_path_factory.mktemp("still")
    path = tmp / "still.yaml"
    path.write_text(yaml.safe_dump(still_scene()))
    case = tmp / "case"
    render_from_file(path, case)
    summary = run_case(case, np=1, quiet=True)
    assert summary.status == "finished"
    post_case(case, comparisons=False, snapshot=False)
    return case


@pytest.mark.openfoam
def test_the_still_wet_bed_reads_its_depth(still_case, openfoam):
    """Expected: every sample of both gauges within 1 mm of the 15 mm wet bed (the gauges
    are out of the bore's reach for the whole run)."""
    plan = plan_case(load_scene(still_case / "scene.yaml"))
    assert plan.two_d and WET in [round(z, 12) for z in plan.background.planes("z")]  # a face at the surface
    gauges = pd.read_csv(still_case / "results" / "gauges.csv")
    assert len(gauges) >= 3
    for name in ("WGa", "WGb"):
        level = gauges[f"{name}_elevation_m"].to_numpy()
        assert abs(level - WET).max() < 1e-3, f"{name}: {level * 1000} mm"
    summary = pd.read_csv(still_case / "results" / "gauge_summary.csv").set_index("gauge")
    assert summary.loc["WGa", "initial_level_m"] == pytest.approx(WET, abs=1e-3)
    assert math.isnan(summary.loc["WGa", "arrival_s"])  # nothing arrived


@pytest.mark.openfoam
def test_the_water_put_in_is_the_scenes(still_case, openfoam):
    """Expected: the water volume before the first step within 0.5 % of the impoundment
    plus the wet bed over the modelled domain (setFields fills whole cells by their centres:
    exact only where every box face is a cell face)."""
    plan = plan_case(load_scene(still_case / "scene.yaml"))
    balance = read_water_balance(still_case)
    initial = float(balance["initial_m3"].iloc[0])
    assert initial == pytest.approx(scene_volume_m3(plan), rel=5e-3)
