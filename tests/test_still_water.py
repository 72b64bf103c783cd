"""A container resting on the wet bed of a flume of still water stays where it is, two-way.

tests/data/scenes/still-water-resting.yaml stands the seed's container on the planner's gap over
15 mm of still water (its draft, 26 mm, exceeds it). v1912's overset interpolation puts a spurious
yaw moment of up to 6e-4 N m on it; without static friction it turned 131 degrees in 1 s. Static
bed friction (orchestrator.run.bedwatch) holds it: the load it measured stays at about a tenth of
what friction bears (mu N = 0.50 N, mu N r = 0.021 N m), so the body must not move at all.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from conftest import ROOT, render_and_run

SCENE = ROOT / "tests" / "data" / "scenes" / "still-water-resting.yaml"


@pytest.mark.openfoam
def test_a_container_resting_in_still_water_keeps_its_place_and_heading_two_way(openfoam, tmp_path):
    case = tmp_path / "still"
    render_and_run(SCENE, case)
    track = pd.read_csv(case / "bodies.csv")
    assert track["time_s"].max() == pytest.approx(1.0, abs=0.02)
    yaw = np.degrees(np.arctan2(track["q_yx"], track["q_xx"]))
    moved = np.hypot(track["x_m"] - 1.2, track["y_m"])
    assert np.abs(yaw).max() < 1.0  # degrees, the bound; held, it is exactly 0
    assert moved.max() < 1e-3  # m
    depth = pd.read_csv(case / "body_depth.csv")
    assert (depth["stuck"] == 1).all()  # static friction held it from the first step to the last
