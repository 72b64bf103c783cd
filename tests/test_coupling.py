"""The coupling choice (run.debris_coupling) and the one-way plan's flow record.

The criterion (orchestrator/plan/coupling.py): one-way when the bodies displace under 0.1 % of
the reservoir's water and block under 40 % of the flume's width. The study's four layouts go
one-way (0.0042-0.025 % and 4-24 %); a body across 60 % of the width goes two-way.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from orchestrator.case.render import build_context, render_files
from orchestrator.plan.coupling import (
    BLOCKAGE_LIMIT,
    ONE_WAY_MAX_COURANT,
    RECORD_MAX_POINTS,
    VOLUME_LIMIT,
    debris_load,
)
from orchestrator.plan.facts import scene_facts
from orchestrator.plan.model import ModelPlan
from orchestrator.plan.planner import plan_case
from orchestrator.scene.resolve import scene_from_dict
from orchestrator.scene.scenefile import load_scene

from tests.conftest import CASES, ROOT, run_cli

#: layout -> (displaced volume as % of the reservoir, blockage %), as the reasons state them
STUDY_LAYOUTS = {
    "1debris": ("0.0042 %", "4 %"),
    "3debris-3x1": ("0.013 %", "12 %"),
    "3debris-1x3": ("0.013 %", "12 %"),
    "6debris-2x3": ("0.025 %", "24 %"),
}


def _blocking_scene(coupling: str = "auto"):
    """cases/1debris.yaml with its container turned into a 0.9 m wide plate across the flow (60 %)."""
    data = yaml.safe_load((CASES / "1debris.yaml").read_text())
    data["debris"][0]["size_m"] = [0.10, 0.90, 0.06]
    data["run"]["debris_coupling"] = coupling
    return scene_from_dict(data)


@pytest.mark.parametrize("name", sorted(STUDY_LAYOUTS))
def test_the_study_layouts_go_one_way_and_say_why(name):
    scene = load_scene(CASES / f"{name}.yaml")
    load = debris_load(scene, scene_facts(scene).rotations)
    assert load.volume_fraction < VOLUME_LIMIT and load.blockage < BLOCKAGE_LIMIT
    plan = plan_case(scene)
    volume, blockage = STUDY_LAYOUTS[name]
    reason = plan.reasons["debris_coupling"]
    assert plan.debris_coupling == "one-way" and reason.startswith("one-way (run.debris_coupling auto)")
    assert f"{volume} of the reservoir" in reason and f"block {blockage}" in reason.replace("blocks", "block")
    assert plan.solver == "interFoam" and not plan.two_d and plan.bodies == ()
    assert plan.max_courant == ONE_WAY_MAX_COURANT and "max_courant" in plan.reasons
    assert plan.flow_record is not None and "flowRecord" in plan.reasons["flow_record"]
    data = json.loads(plan.to_json())
    assert data["debris_coupling"] == "one-way" and data["flow_record"]["points"] == plan.flow_record.points


def test_one_way_keeps_the_two_way_background_mesh():
    scene = load_scene(CASES / "1debris.yaml")
    one = plan_case(scene)
    two = plan_case(load_scene(CASES / "1debris.yaml", ["run.debris_coupling=two-way"]))
    assert one.background == two.background and one.domain_m == two.domain_m
    assert one.cell_count == two.background.cell_count() < two.cell_count
    assert one.bed_gap_m == 0.0 < two.bed_gap_m


def test_two_way_on_request_is_the_overset_path():
    plan = plan_case(load_scene(CASES / "1debris.yaml", ["run.debris_coupling=two-way"]))
    assert plan.debris_coupling == "two-way" and plan.solver == "overInterDyMFoam" and len(plan.bodies) == 1
    assert plan.flow_record is None and plan.max_courant == 2.5
    assert "auto would choose one-way" in plan.reasons["debris_coupling"]


def test_a_body_blocking_most_of_the_width_goes_two_way():
    scene = _blocking_scene()
    assert debris_load(scene, scene_facts(scene).rotations).blockage == pytest.approx(0.6)
    plan = plan_case(scene)
    assert plan.debris_coupling == "two-way" and plan.solver == "overInterDyMFoam"
    reason = plan.reasons["debris_coupling"]
    assert "block 60 %" in reason.replace("blocks", "block") and "not under 40 %" in reason
    assert "may change the flow" in reason


def test_one_way_forced_on_a_blocking_body_is_warned():
    plan = plan_case(_blocking_scene("one-way"))
    assert plan.debris_coupling == "one-way"
    assert any("one-way although" in w for w in plan.warnings)
    assert "auto would choose two-way" in plan.reasons["debris_coupling"]


def test_one_way_warns_of_each_body_that_starts_in_another_ones_lee():
    """The 3x1 layout (three containers 0.10 m apart along the flow) puts debris2 behind debris1 and
    debris3 behind debris2; the 1x3 layout (abreast, 0.09 m apart across the flow) puts none in
    another's lane; turned 90 degrees, a 1x3 layout's containers (0.15 m long across the flow,
    0.15 m apart) touch lanes only at their ends, which do not overlap; and two-way has a wake."""
    line = plan_case(load_scene(CASES / "3debris-3x1.yaml"))
    lee = [w for w in line.warnings if "lane" in w]
    assert [w.split(" starts in ")[0] for w in lee] == ["debris2", "debris3"]
    assert "debris1's lane 0.1 m downstream" in lee[0] and "no wake" in lee[0]
    abreast = plan_case(load_scene(CASES / "3debris-1x3.yaml"))
    assert not [w for w in abreast.warnings if "lane" in w]
    turned = plan_case(load_scene(CASES / "3debris-1x3.yaml", ["debris.0.body.yaw_deg=90"]))
    assert not [w for w in turned.warnings if "lane" in w]
    coupled = plan_case(load_scene(CASES / "3debris-3x1.yaml", ["run.debris_coupling=two-way"]))
    assert not [w for w in coupled.warnings if "lane" in w]


def test_no_debris_is_none():
    plan = plan_case(load_scene(CASES / "nodebris.yaml"))
    assert plan.debris_coupling == "none" and plan.flow_record is None
    assert plan.reasons["debris_coupling"] == "none: the scene has no debris"


def test_the_tiny_test_flumes_stay_two_way():
    """One container in a 0.4 m wide flume's small reservoir displaces 1-1.7 % of its water."""
    for path in (ROOT / "tests/data/post/tiny-1debris.yaml", CASES / "hard/small/tiny-flume.yaml"):
        plan = plan_case(load_scene(path))
        assert plan.debris_coupling == "two-way", path


def test_flow_record_grid_covers_the_bodies_and_integrates_the_cells():
    """Without a refinement box (which samples its own cell centres, tests/test_approach.py)."""
    scene = load_scene(CASES / "1debris.yaml", ["mesh.column_approach_cell_size_m=null"])
    record = plan_case(scene).flow_record
    h = scene.mesh.cell_size_m
    x, y, z, faces = (np.asarray(a) for a in (record.x_m, record.y_m, record.z_m, record.z_faces_m))
    # from the bodies' footprints less a margin to the domain's downstream end (bodies pass the
    # column and go on: the record's ends are walls for them), the full width
    plan = plan_case(scene)
    assert x[0] < 3.125 - 0.2 and x[-1] == pytest.approx(plan.domain_m[0][1]) and x[-1] > 5.1 + 1.0
    assert y[0] == pytest.approx(-0.75, abs=1e-3) and y[-1] == pytest.approx(0.75, abs=1e-3)
    # evenly spaced at the finest cell size or coarser
    for axis in (x, y):
        steps = np.diff(axis)
        assert np.allclose(steps, steps[0]) and h - 1e-9 <= steps[0] < 1.1 * h
    # z: the background's cell centres from the bed to the domain's top
    assert faces[0] == 0.0 and faces[-1] == pytest.approx(0.6) and np.allclose(z, 0.5 * (faces[1:] + faces[:-1]))
    assert record.interval_s == 0.02 and record.points == 84 * 38 * 19 <= RECORD_MAX_POINTS
    (bx0, bx1), (by0, by1) = record.bodies_region_m
    assert (bx0, bx1, by0, by1) == pytest.approx((3.125, 3.275, -0.03, 0.03))


def test_the_record_rate_and_size_bound():
    fast = plan_case(load_scene(CASES / "1debris.yaml", ["outputs.flow_record_hz=100"])).flow_record
    assert fast.interval_s == 0.01
    fine = load_scene(CASES / "1debris.yaml", ["mesh.cell_size_m=0.02"])
    record = plan_case(fine).flow_record
    assert record.points <= RECORD_MAX_POINTS
    assert np.diff(record.x_m)[0] >= 2 * 0.02 - 1e-9  # coarser than the cells to bound the size


def test_plan_json_round_trip_and_older_plans():
    plan = plan_case(load_scene(CASES / "1debris.yaml"))
    assert ModelPlan.from_json(plan.to_json()).to_json() == plan.to_json()
    old = json.loads(plan_case(load_scene(CASES / "1debris.yaml", ["run.debris_coupling=two-way"])).to_json())
    del old["debris_coupling"], old["flow_record"]
    assert ModelPlan.from_dict(old).debris_coupling == "two-way"


def test_one_way_renders_interfoam_without_bodies_and_a_flow_record():
    scene = load_scene(CASES / "1debris.yaml")
    plan = plan_case(scene)
    files = render_files(build_context(scene, plan))
    assert not any(p.startswith("bodies/") for p in files) and "constant/dynamicMeshDict" not in files
    control = files["system/controlDict"]
    assert "application     interFoam;" in control and "overset" not in control
    assert '#include "flowRecord"' in control
    block = files["system/flowRecord"]
    assert block.startswith("/*") and "\nflowRecord\n{" in block
    assert "type    cloud;" in block and "axis    xyz;" in block and "fields          (alpha.water U);" in block
    assert "interpolationScheme cell;" in block and "writeInterval   0.02;" in block
    assert block.count("\n                (") == plan.flow_record.points
    assert "maxCo           1;" in control


@pytest.mark.parametrize("value", ["sideways", "oneway"])
def test_a_bad_coupling_exits_2_naming_the_field(tmp_path, value):
    proc = run_cli("render", "cases/1debris.yaml", "-o", str(tmp_path / "c"), "--set", f"run.debris_coupling={value}")
    assert proc.returncode == 2, proc.stderr
    assert "run.debris_coupling" in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "c").exists()


def test_a_record_rate_of_zero_exits_2_naming_the_field(tmp_path):
    # any positive rate is a record (a 40:1 scene's Froude-scaled 50 Hz is 7.9 Hz); zero is none
    proc = run_cli("render", "cases/1debris.yaml", "-o", str(tmp_path / "c"), "--set", "outputs.flow_record_hz=0")
    assert proc.returncode == 2 and "outputs.flow_record_hz" in proc.stderr
