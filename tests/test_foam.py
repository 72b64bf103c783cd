"""Running OpenFOAM steps: environment, logs, failures, checkMesh, and short solver runs.

Log parsers are tested on real v1912 logs committed under tests/golden/logs/; the
runner on real OpenFOAM (tests marked `openfoam`), including a few time steps of
interFoam and of overInterDyMFoam (one and two bodies) on 2 cores.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import time
from pathlib import Path

import pytest

from analytical.errors import DebrisfoamError
from orchestrator.case import foam
from orchestrator.case.render import render_case
from orchestrator.run import openfoam as run_openfoam
from orchestrator.run.openfoam import StepError, check_mesh_summary, failure_reason, run_step

from regenerate_golden import GOLDEN_DIR, flume_plan

LOGS = GOLDEN_DIR / "logs"


# --------------------------------------------------------------------------- environment


def test_foam_env_sets_project_dir_and_mpi_as_root():
    env = run_openfoam.foam_env({"PATH": "/usr/bin"})
    assert env["WM_PROJECT_DIR"] == "/usr/share/openfoam"
    assert env["OMPI_ALLOW_RUN_AS_ROOT"] == env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] == "1"
    assert env["PATH"] == "/usr/bin"
    assert env["OMPI_MCA_rmaps_base_oversubscribe"] == "1"
    assert run_openfoam.foam_env({"WM_PROJECT_DIR": "/opt/of"})["WM_PROJECT_DIR"] == "/opt/of"
    # waiting ranks yield their core (benchmarks/mpi_yield.md); a user's own setting wins
    assert env["OMPI_MCA_mpi_yield_when_idle"] == "1"
    assert run_openfoam.foam_env({"OMPI_MCA_mpi_yield_when_idle": "0"})["OMPI_MCA_mpi_yield_when_idle"] == "0"


def test_parallel_argv():
    assert foam.parallel_argv(["interFoam"], 1) == ["interFoam"]
    assert foam.parallel_argv(["interFoam"], 2) == ["mpirun", "-np", "2", "interFoam", "-parallel"]


# --------------------------------------------------------------------------- log parsing


def test_failure_reason_quotes_the_fatal_error_of_a_parallel_run():
    reason = failure_reason((LOGS / "overInterDyMFoam-gamg-parallel.log").read_text())
    assert reason.startswith("--> FOAM FATAL ERROR")
    assert "field does not correspond to level 0 sizes" in reason
    assert "[0]" not in reason and "From function" not in reason


def test_failure_reason_names_a_floating_point_exception_and_the_time():
    reason = failure_reason((LOGS / "overInterDyMFoam-fpe-parallel.log").read_text())
    assert "floating point exception" in reason and "0.0205642" in reason


def test_failure_reason_falls_back_to_the_tail():
    text = "\n".join(f"line {i}" for i in range(40)) + "\nSegmentation fault\n"
    reason = failure_reason(text)
    assert "Segmentation fault" in reason and "line 39" in reason and "line 10" not in reason


def test_check_mesh_summary_of_a_good_overset_mesh():
    s = check_mesh_summary(LOGS / "checkMesh-overset-ok.log")
    assert s.ok and s.failed_checks == 0
    assert (s.cells, s.points, s.faces, s.regions) == (14032, 17608, 45550, 3)
    assert s.cell_types == {"hexahedra": 14032}
    assert s.max_aspect_ratio == pytest.approx(1.281712772)
    assert s.max_non_orthogonality_deg < 1e-5 and s.max_skewness < 1e-7


def test_check_mesh_summary_of_a_failed_mesh():
    s = check_mesh_summary(LOGS / "checkMesh-failed.log")
    assert not s.ok and s.failed_checks == 1
    assert s.cells == 125
    assert s.max_non_orthogonality_deg == pytest.approx(81.665801)
    assert s.max_skewness == pytest.approx(6.2665102)  # from " ***Max skewness = 6.27, 6 highly skew faces"
    assert s.max_aspect_ratio == pytest.approx(7.2651934)


def test_check_mesh_summary_without_a_verdict(tmp_path):
    log = tmp_path / "log.checkMesh"
    log.write_text("Create time\n\nCreate polyMesh for time = 0\n")
    with pytest.raises(StepError, match="no verdict") as err:
        check_mesh_summary(log)
    assert err.value.log_path == log


def test_the_checkmesh_step_is_done_only_for_a_passed_mesh_checked_after_meshing(tmp_path):
    """The case's checkMesh step is done when log.checkMesh, newer than the mesh, says `Mesh OK.`;
    a failed verdict, a log without one (checkMesh stopped) or an older log run it again."""
    done = foam.mesh_steps(tmp_path, flume_plan(0, friction=0.0))[-1].done
    (tmp_path / "constant" / "polyMesh").mkdir(parents=True)
    owner, log = tmp_path / "constant" / "polyMesh" / "owner", tmp_path / "log.checkMesh"
    owner.write_text("")
    assert not done(tmp_path)
    for text, ok in [((LOGS / "checkMesh-overset-ok.log").read_text(), True),
                     ((LOGS / "checkMesh-failed.log").read_text(), False), ("Create time\n", False)]:
        log.write_text(text)
        os.utime(owner, (1, 1))
        assert done(tmp_path) is ok
    log.write_text((LOGS / "checkMesh-overset-ok.log").read_text())
    os.utime(log, (0, 0))  # checked before this mesh was made
    assert not done(tmp_path)


# --------------------------------------------------------------------------- steps


def test_mesh_steps_for_interfoam_and_overset(tmp_path):
    names = [s.name for s in foam.mesh_steps(tmp_path, flume_plan(0, friction=0.0))]
    assert names == ["blockMesh", "setFields", "checkMesh"]
    names = [s.name for s in foam.mesh_steps(tmp_path, flume_plan(0))]  # bed friction needs the bed layer
    assert names == ["blockMesh", "topoSet", "setFields", "checkMesh"]
    steps = foam.mesh_steps(tmp_path, flume_plan(2))
    assert [s.name for s in steps] == [
        "blockMesh", "blockMesh.debris1", "blockMesh.debris2", "mergeMeshes.debris1", "mergeMeshes.debris2",
        "topoSet", "setFields", "checkMesh"]
    merge = steps[3]
    assert merge.argv == ("mergeMeshes", ".", "bodies/debris1", "-overwrite")
    assert merge.shell() == "mergeMeshes . bodies/debris1 -overwrite"
    assert all(s.done is not None for s in steps)


def test_solve_steps_follow_the_decomposition(tmp_path):
    steps = foam.solve_steps(tmp_path, flume_plan(1, decomposition=(1, 2, 1)))
    assert [s.name for s in steps] == ["decomposePar", "overInterDyMFoam", "reconstructPar"]
    assert steps[1].shell() == "mpirun -np 2 overInterDyMFoam -parallel"
    assert [s.name for s in foam.solve_steps(tmp_path, flume_plan(0), np=1)] == ["interFoam"]


def test_missing_case_directory_is_a_step_error(tmp_path):
    with pytest.raises(StepError, match="does not exist"):
        run_step("blockMesh", ["blockMesh"], tmp_path / "nowhere")


@pytest.mark.openfoam
def test_failing_step_raises_step_error_quoting_the_log(tmp_path, openfoam):
    """blockMesh without a blockMeshDict: the error quotes FOAM FATAL ERROR and names the log."""
    case = render_case({}, flume_plan(0), tmp_path / "case")
    (case / "system" / "blockMeshDict").unlink()
    with pytest.raises(StepError) as err:
        run_step("blockMesh", ["blockMesh"], case)
    e = err.value
    assert isinstance(e, DebrisfoamError)
    assert e.step == "blockMesh" and e.log_path == case / "log.blockMesh" and e.returncode == 1
    assert "--> FOAM FATAL" in str(e) and "blockMeshDict" in str(e)
    assert str(case / "log.blockMesh") in str(e)
    assert "FOAM FATAL" in (case / "log.blockMesh").read_text()


@pytest.mark.openfoam
def test_done_predicate_skips_and_logs_are_written(tmp_path, openfoam):
    plan = flume_plan(0)
    case = render_case({}, plan, tmp_path / "case")
    first = foam.mesh_steps(case, plan)[0]
    assert not first.done(case)
    result = run_step(first.name, first.argv, case, done=first.done)
    assert not result.skipped and result.returncode == 0 and result.wall_s > 0
    log = (case / "log.blockMesh").read_text()
    assert log.rstrip().endswith("End") and "PWD is not the cwd" not in log
    again = run_step(first.name, first.argv, case, done=first.done)
    assert again.skipped and again.wall_s == 0


# --------------------------------------------------------------------------- solver runs


def _run_all(case: Path, plan) -> dict[str, float]:
    """Every step in order, as the runner takes them (with several bodies, the split of their
    meshes across the ranks is one of them: orchestrator/case/split_bodies.py)."""
    timings = {}
    for step in foam.mesh_steps(case, plan) + foam.solve_steps(case, plan):
        start = time.perf_counter()
        run_step(step.name, step.argv, case, np=step.np, done=step.done, timeout_s=300)
        timings[step.name] = time.perf_counter() - start
    return timings


def _time_steps(log: Path) -> list[float]:
    return [float(t) for t in re.findall(r"^Time = (\S+)", log.read_text(), re.M)]


@pytest.mark.openfoam
def test_interfoam_runs_a_few_steps_on_two_cores(tmp_path, openfoam):
    plan = flume_plan(0, h=0.04, end_time_s=0.02)
    case = render_case({}, plan, tmp_path / "case")
    _run_all(case, plan)
    times = _time_steps(case / "log.interFoam")
    assert len(times) >= 5 and times[-1] == pytest.approx(0.02)
    log = (case / "log.interFoam").read_text()
    assert "Finalising parallel run" in log
    assert "creating porous zone: bedLayer" in log  # the bed friction is active
    assert (case / "0.02" / "alpha.water").is_file()  # reconstructed
    force = (case / "postProcessing" / "columnForces" / "0" / "force.dat").read_text()
    rows = [ln for ln in force.splitlines() if ln and not ln.startswith("#")]
    assert rows and "(pressure_x pressure_y pressure_z)" in force
    gauges = sorted((case / "postProcessing" / "gauges").iterdir())
    assert {p.name for p in gauges[-1].iterdir()} == {"WG1_alpha.water.xy", "WG2_alpha.water.xy",
                                                      "WG4_alpha.water.xy"}
    # WG1 stands in the 0.3 m reservoir: the integral of alpha along its line is the depth
    z, alpha = zip(*(map(float, ln.split()) for ln in (gauges[0] / "WG1_alpha.water.xy").read_text().splitlines()))
    depth = sum((z[i + 1] - z[i]) * (alpha[i] + alpha[i + 1]) / 2 for i in range(len(z) - 1))
    assert depth == pytest.approx(0.3, abs=0.03)


@pytest.mark.openfoam
def test_sampling_every_step_or_so_keeps_the_solvers_courant_step(tmp_path, openfoam):
    """Gauges and column forces every 0.01 s while the Courant-limited step is 4-6 ms (the 2-D
    flume, maxCo 0.25). On adjustableRunTime v1912 rounds the steps left to each sample to the
    nearest whole number and so lengthened steps to Co 0.336 (1.34 maxCo); the samples write on
    runTime, and the largest Courant number stays within 20 % of maxCo (0.280 measured: the
    solver sets each step from the last step's Courant number)."""
    plan = dataclasses.replace(flume_plan(0, h=0.04, two_d=True, end_time_s=0.6, decomposition=(1, 1, 1)),
                               max_delta_t_s=0.01, max_courant=0.25, write_interval_s=0.1)
    case = render_case({}, plan, tmp_path / "case")
    _run_all(case, plan)
    log = (case / "log.interFoam").read_text()
    courant = [float(c) for c in re.findall(r"^Courant Number mean: \S+ max: (\S+)", log, re.M)]
    steps = [float(d) for d in re.findall(r"^deltaT = (\S+)", log, re.M)]
    assert max(steps) > 0.004  # fewer than three steps between samples: where the rounding bites
    assert max(courant) > 0.9 * 0.25  # the step is Courant-limited
    assert max(courant) <= 1.2 * 0.25


@pytest.mark.openfoam
@pytest.mark.parametrize("n_bodies", [pytest.param(1, marks=pytest.mark.slow), 2])
def test_overset_runs_a_few_steps_on_two_cores(tmp_path, openfoam, n_bodies):
    plan = flume_plan(n_bodies, h=0.04, end_time_s=0.01, decomposition=(2, 1, 1))
    case = render_case({}, plan, tmp_path / "case")
    _run_all(case, plan)
    log = (case / "log.overInterDyMFoam").read_text()
    times = _time_steps(case / "log.overInterDyMFoam")
    assert len(times) >= 3 and times[-1] == pytest.approx(0.01)
    assert f"detected {n_bodies + 1} mesh regions" in log
    assert "creating porous zone: bedLayer" in log
    centres = re.findall(r"Centre of mass: \(([^)]*)\)", log)
    last = [tuple(map(float, c.split())) for c in centres[-n_bodies:]]
    # each body reported separately, near where it started (no body took another's state)
    for body, c in zip(plan.bodies, last):
        assert math.dist(body.centre_of_mass_m, c) < 0.01


def test_only_the_tail_of_a_long_log_is_read(tmp_path):
    log = tmp_path / "log.x"
    log.write_text("Time = 1\n" * 200_000 + "--> FOAM FATAL ERROR: \nboom\n\n    From function f\n")
    assert len(log.read_bytes()) > run_openfoam.LOG_TAIL_BYTES
    tail = run_openfoam._tail(log, run_openfoam.LOG_TAIL_BYTES)
    assert len(tail) <= run_openfoam.LOG_TAIL_BYTES and tail.startswith("Time = 1\n")
    assert failure_reason(tail) == "--> FOAM FATAL ERROR:\n    boom"


def test_set_subdomains_splits_along_x_and_names_the_planned_count(tmp_path):
    """--np other than the plan's: decomposeParDict for that many subdomains along x; the planned
    count comes back (None when it already matched)."""
    (tmp_path / "system").mkdir()
    path = tmp_path / "system" / "decomposeParDict"
    path.write_text("FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
                    "    object decomposeParDict;\n}\n\nnumberOfSubdomains 4;\nmethod hierarchical;\n"
                    "hierarchicalCoeffs\n{\n    n (2 2 1);\n}\n")
    assert foam.set_subdomains(tmp_path, 4) is None
    assert foam.set_subdomains(tmp_path, 3) == 4
    text = path.read_text()
    assert re.search(r"numberOfSubdomains\s+3;", text) and re.search(r"n\s+\(3 1 1\);", text)
    assert foam.set_subdomains(tmp_path, 3) is None
