"""Several body meshes on several ranks: every body mesh is split across two ranks.

v1912's overset addressing deadlocks when two overlapping body meshes sit whole on one rank
(orchestrator/case/split_bodies.py has the source lines; docs/stability.md the runs): the rank
holding them enters a collective the other ranks never reach. tests/data/scenes/three-debris-two-way.yaml
(the study's 3x1 layout in the tiny flume, body meshes overlapping by 0.06 m) stalled at t = 0 on
2 ranks with every body whole on one rank; with the split it runs.
"""

from __future__ import annotations

import json
from pathlib import Path
import re

import numpy as np
import pytest

from conftest import ROOT, run_cli, solvers_kept
from orchestrator.run.runner import run_case
from orchestrator.case import foam, split_bodies

SCENE = ROOT / "tests" / "data" / "scenes" / "three-debris-two-way.yaml"


def _field(path, values):
    path.parent.mkdir(parents=True, exist_ok=True)
    body = "\n".join(str(v) for v in values)
    path.write_text("FoamFile\n{\n    version 2.0;\n    format ascii;\n    class volScalarField;\n"
                    f"    object {path.name};\n}}\n\ndimensions [0 0 0 0 0 0 0];\n\n"
                    f"internalField nonuniform List<scalar>\n{len(values)}\n(\n{body}\n)\n;\n\n"
                    "boundaryField\n{\n}\n")


def test_split_moves_half_of_each_whole_body_mesh_to_the_next_rank(tmp_path):
    # background 0-5 on ranks 0/1; body 1 whole on rank 1; body 2 whole on rank 0; body 3 split already
    zone = [0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 3, 3]
    dist = [0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 1]
    _field(tmp_path / "0" / "zoneID", zone)
    _field(tmp_path / "0" / "cellDist", dist)
    (tmp_path / "constant").mkdir()
    (tmp_path / "system").mkdir()
    counts = split_bodies.split(tmp_path, 2)
    assert counts == {1: [2, 2], 2: [1, 2], 3: [1, 1]}
    text = (tmp_path / "constant" / "cellDecomposition").read_text()
    procs = [int(v) for v in text.split("(", 1)[1].split(")", 1)[0].split()]
    assert procs == [0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 1, 1, 0, 1]  # background and body 3 untouched
    manual = (tmp_path / split_bodies.DICT).read_text()
    assert re.search(r"method\s+manual;", manual) and "numberOfSubdomains 2;" in manual
    assert not (tmp_path / "0" / "cellDist").exists()


def test_the_split_step_is_a_debrisfoam_verb_that_refuses_a_case_without_cell_dist(tmp_path):
    _field(tmp_path / "0" / "zoneID", [0, 0, 1, 1, 2, 2])
    (tmp_path / "constant").mkdir()
    (tmp_path / "system").mkdir()
    proc = run_cli("split-bodies", ".", "--ranks", "2", cwd=tmp_path)
    assert proc.returncode == 2 and "0/cellDist" in proc.stderr  # decomposePar -cellDist has not run
    assert not (tmp_path / split_bodies.DICT).exists()
    _field(tmp_path / "0" / "cellDist", [0, 1, 0, 0, 1, 1])
    proc = run_cli("split-bodies", ".", "--ranks", "1", cwd=tmp_path)
    assert proc.returncode == 2 and "--ranks" in proc.stderr
    proc = run_cli("split-bodies", ".", "--ranks", "2", "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["body zone 1: cells per rank"] == [1, 1]
    assert (tmp_path / split_bodies.DICT).is_file() and not (tmp_path / "0" / "cellDist").exists()


def _ranks_per_zone(case: Path) -> dict[int, int]:
    """How many ranks hold cells of each body zone, from the case's cellDecomposition and zoneID."""
    table = (case / "constant" / "cellDecomposition").read_text()
    procs = np.array(table.split("(", 1)[1].split(")", 1)[0].split(), dtype=int)
    zone = split_bodies._internal(case / "0" / "zoneID")
    return {int(z): int(np.unique(procs[zone == z]).size) for z in range(1, int(zone.max()) + 1)}


def test_the_split_is_planned_only_for_two_or_more_bodies_on_two_or_more_ranks():
    class Plan:
        decomposition = (2, 1, 1)
        solver = "overInterDyMFoam"

    plan = Plan()
    plan.bodies = ("a", "b")
    names = [s.name for s in foam.solve_steps("case", plan)]
    assert names[:3] == ["decomposePar.cellDist", "splitBodies", "decomposePar"]
    assert [s.name for s in foam.decompose_steps("case", plan)] == names[:3]
    plan.bodies = ("a",)
    assert [s.name for s in foam.solve_steps("case", plan)][0] == "decomposePar"
    plan.bodies = ("a", "b")
    assert "decomposePar" not in [s.name for s in foam.solve_steps("case", plan, np=1)]


def _largest_mesh_flux(field: Path) -> float:
    """The largest |meshPhi| of a processor's internal field (0 for `uniform 0`)."""
    text = field.read_text()
    m = re.search(r"internalField\s+(uniform\s+(\S+);|nonuniform List<scalar>\s*(\d+)\s*\()", text)
    if m.group(2) is not None:
        return abs(float(m.group(2)))
    return float(np.abs(np.array(text[m.end():].split(")")[0].split(), dtype=float)).max())


@pytest.mark.openfoam
@pytest.mark.slow
def test_three_overlapping_body_meshes_get_past_the_first_steps_on_two_ranks(openfoam, tmp_path):
    """Past the addressing, the three body meshes stand still while static friction holds their
    bodies (to 0.24 s): each sixDoF solver moves its own cellZone only. Without the zones v1912
    adds every solver's start points over the other bodies' meshes, and the mesh flux grew about
    x2 a step (1.4e-9 at 0.2 s, the run diverging at 0.35 s)."""
    case = tmp_path / "three"
    proc = run_cli("render", str(SCENE), "-o", str(case), "--set", "run.end_time_s=0.2")
    assert proc.returncode == 0, proc.stderr[-2000:]
    run_case(case, quiet=True, contact=solvers_kept(case))  # the solvers at work on their zones
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "finished"
    assert _ranks_per_zone(case) == {1: 2, 2: 2, 3: 2}
    names = [s["name"] for s in record["steps"]]
    k = names.index("decomposePar.cellDist")
    assert names[k:k + 3] == ["decomposePar.cellDist", "splitBodies", "decomposePar"]
    log = "".join(p.read_text() for p in sorted(case.glob("log.overInterDyMFoam*")))
    steps = len(re.findall(r"^Time = ", log, re.M))
    # 6 zone pairs (background and three bodies) addressed at every step, none left hanging
    assert steps >= 5
    assert len(re.findall("Creating mesh-to-mesh addressing", log)) >= 6 * steps
    overlaps = np.array([float(v) for v in re.findall(r"Overlap volume: (\S+)", log)])
    assert (overlaps > 0).sum() >= 5 * steps  # two body pairs overlap besides the background's three
    assert all(f"Applying solid body motion to cellZone debris{k}" in log for k in (1, 2, 3))
    assert record["reached_time_s"] == pytest.approx(0.2)
    # the three resting bodies' meshes end at the bed: none reaches below it, where two body meshes
    # would take their donors from each other (plan.meshes_stop_at_bed)
    from orchestrator.run.bodypoints import read_points

    for k in (1, 2, 3):
        z = read_points(case / "bodies" / f"debris{k}" / "constant" / "polyMesh" / "points")[:, 2]
        assert z.min() == pytest.approx(0.0, abs=1e-9)
    for rank in (0, 1):
        assert _largest_mesh_flux(case / f"processor{rank}" / "0.2" / "meshPhi") < 1e-15
