"""A container resting on the bed floats up in still water deeper than its draft (Archimedes).

The scene (tests/data/scenes/float-off.yaml) stands the study's container (0.236 kg, 0.15 x
0.06 m footprint: draft 26.3 mm) on the bed under 50 mm of still water. It must rise to the
height where it displaces its own weight, overshoot it and come back (a lightly damped heave
oscillation about that height). Before the planner left a gap under resting bodies
(orchestrator/plan/planner.py, BedGap), the underside carried a stale overset pressure: the container
was pulled into the bed and the run diverged at 0.2 s. The second test lays the container on the
bed itself, kept there by the runner's rest-on-bed constraint: the runner must raise it onto its
gap and free it once it measures the water deep enough all round and lifting it
(orchestrator/run/bedwatch.py).
"""

from __future__ import annotations

import json

import pandas as pd
import pytest

from conftest import ROOT, run_cli, run_container

SCENE = ROOT / "tests" / "data" / "scenes" / "float-off.yaml"


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_resting_container_floats_up_to_its_draft(openfoam, tmp_path):
    case = tmp_path / "float-off"
    plan, height, draft = run_container(SCENE, case)
    wet = 0.05
    z_eq = wet - draft + height / 2  # centre height when afloat at rest
    track = pd.read_csv(case / "bodies.csv").drop_duplicates("time_s", keep="last")
    z0 = track["z_m"].iloc[0]
    assert z0 == pytest.approx(height / 2 + plan["bed_gap_m"], abs=1e-6)  # it starts standing on the gap
    first_rise = track[track["time_s"] <= track.loc[track["z_m"].idxmax(), "time_s"]]
    z_max = first_rise["z_m"].max()
    # it floats above its equilibrium and swings back: the peak is past it, and the swing is
    # centred on it (hydrostatics on the underside, to 2 mm of a 19 mm swing)
    assert z_max > z_eq + 0.5 * (z_eq - z0)
    assert (z0 + z_max) / 2 == pytest.approx(z_eq, abs=0.002)
    assert track["z_m"].iloc[-1] < z_max  # and is on its way back down by 0.25 s


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_container_kept_on_the_bed_is_raised_onto_its_gap_and_freed_once_the_water_can_lift_it(openfoam, tmp_path):
    """The same container lying on the bed itself (its underside 5 mm below the gap's top, where the
    body mesh's cells under it are overset holes and its underside pressure is stale) with the
    runner's rest-on-bed constraint, under 50 mm of still water. The runner must raise it onto the
    gap's top and hold it there once it measures the depth all round (50 mm > 5 + 26.3 + 5 mm), free
    it once the water lifts it by its weight, and the container must then float up."""
    from orchestrator.case import bodystate
    from orchestrator.run import body_policy

    case = tmp_path / "rest-off"
    proc = run_cli("render", str(SCENE), "-o", str(case))
    assert proc.returncode == 0, proc.stderr[-2000:]
    plan = json.loads((case / "plan.json").read_text())
    gap, height = plan["bed_gap_m"], plan["bodies"][0]["size_m"][2]
    start = bodystate.coefficient_states(case)[0]
    x, y, z = start.centre_of_mass_m
    bodystate.write_states(case, [start.with_changes(centre_of_mass_m=(x, y, z - gap))])  # on the bed
    assert body_policy.rest_on_bed(case, ["debris1"]) == ["debris1"]
    proc = run_cli("run", str(case))
    assert proc.returncode == 0, proc.stderr[-2000:]
    record = json.loads((case / "run.json").read_text())
    depth = pd.read_csv(case / "body_depth.csv")
    kinds = depth.drop_duplicates("constraint")["constraint"].tolist()
    assert kinds == ["rest", "hold", "free"]  # on the bed, then held on the gap, then free
    assert len(record.get("freed", [])) == 1 and not record.get("bed_clamps")
    track = pd.read_csv(case / "bodies.csv").drop_duplicates("time_s", keep="last")
    bottom = track["z_m"] - height / 2
    freed = record["freed"][0]["time_s"]
    raised = depth[depth["constraint"] == "hold"]
    assert raised["underside_m"].min() == pytest.approx(gap, abs=1e-6)  # raised onto the gap's top
    assert bottom[track["time_s"] < raised["time_s"].min() - 1e-9].max() < 1e-6  # it lay on the bed till then
    assert bottom[track["time_s"] > freed].max() > gap + 0.005  # and floats up once free
