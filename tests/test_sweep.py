"""Sweeps: expansion and validation up front, ids, dry run, the results store, and real
runs of a tiny mesh study on the local executor and on a Dask LocalCluster (re-runs skip
finished members, a failing member never stops the others, Ctrl-C stops cleanly and a
re-run resumes)."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from analytical.errors import InputError
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.sweep import (
    MEMBER_JSON,
    SweepMemberError,
    load_store,
    load_sweep,
    member_id,
    run_sweep,
)
from orchestrator.studies.sweep.store import write_store as _write_store
from tests.conftest import ROOT, run_cli

TINY = ROOT / "cases" / "tiny-nodebris.yaml"
TINY_SWEEP = ROOT / "cases" / "sweeps" / "tiny-mesh-study.yaml"
SHORT = {"run.end_time_s": 0.3, "run.write_interval_s": 0.1}


def write_sweep(path: Path, **spec) -> Path:
    spec.setdefault("base", str(TINY))
    path.write_text(json.dumps(spec))  # JSON is YAML
    return path


# --------------------------------------------------------------------------- expansion


def test_grid_is_the_cartesian_product_first_axis_outermost(tmp_path):
    sw = load_sweep(write_sweep(tmp_path / "g.yaml", set=SHORT,
                                axes={"mesh.cell_size_m": [0.05, 0.04], "reservoir.depth_m": [0.2, 0.25, 0.3]}))
    assert sw.name == "g" and sw.mode == "grid" and len(sw.members) == 6
    assert [m.params for m in sw.members[:3]] == [{"mesh.cell_size_m": 0.05, "reservoir.depth_m": d}
                                                  for d in (0.2, 0.25, 0.3)]
    assert sw.members[3].params == {"mesh.cell_size_m": 0.04, "reservoir.depth_m": 0.2}
    first = sw.members[0]
    assert first.overrides == ("run.end_time_s=0.3", "run.write_interval_s=0.1", "mesh.cell_size_m=0.05",
                               "reservoir.depth_m=0.2")
    assert first.scene.run.end_time_s == 0.3 and first.scene.mesh.cell_size_m == 0.05
    assert first.plan.cell_count > 0 and first.estimated_wall_time_s > 0
    ids = [m.id for m in sw.members]
    assert len(set(ids)) == 6 and all(re.fullmatch(r"[0-9a-f]{12}", i) for i in ids)
    assert sw.parameters == ["mesh.cell_size_m", "reservoir.depth_m"]


def test_zip_pairs_the_lists_and_ids_are_the_resolved_scenes_hash(tmp_path):
    path = write_sweep(tmp_path / "z.yaml", mode="zip", set=SHORT,
                       axes={"mesh.cell_size_m": [0.05, 0.04], "reservoir.depth_m": [0.2, 0.3]})
    sw = load_sweep(path)
    assert [m.params for m in sw.members] == [{"mesh.cell_size_m": 0.05, "reservoir.depth_m": 0.2},
                                              {"mesh.cell_size_m": 0.04, "reservoir.depth_m": 0.3}]
    # deterministic: the same file gives the same ids; the id is the hash of the resolved scene,
    # so the same scene reached another way (axes swapped, the value set in `set`) has the same id
    assert [m.id for m in load_sweep(path).members] == [m.id for m in sw.members]
    swapped = load_sweep(write_sweep(tmp_path / "s.yaml", mode="zip", set=SHORT,
                                     axes={"reservoir.depth_m": [0.2, 0.3], "mesh.cell_size_m": [0.05, 0.04]}))
    assert [m.id for m in swapped.members] == [m.id for m in sw.members]
    direct = load_scene(TINY, ["run.end_time_s=0.3", "run.write_interval_s=0.1", "mesh.cell_size_m=0.04",
                               "reservoir.depth_m=0.3"])
    assert member_id(direct) == sw.members[1].id


def test_zip_lists_of_different_lengths_are_bad_input(tmp_path):
    path = write_sweep(tmp_path / "z.yaml", mode="zip", axes={"mesh.cell_size_m": [0.05, 0.04],
                                                              "reservoir.depth_m": [0.2, 0.25, 0.3]})
    with pytest.raises(InputError) as err:
        load_sweep(path)
    assert err.value.source == str(path) and err.value.field.startswith("axes.")
    assert "2" in str(err.value) and "3" in str(err.value)


def test_a_bad_member_fails_the_whole_sweep_naming_member_and_field(tmp_path):
    path = write_sweep(tmp_path / "bad.yaml", axes={"run.cores": [1, 2], "mesh.cell_size_m": [0.05, 0.5]})
    with pytest.raises(SweepMemberError) as err:
        load_sweep(path)
    e = err.value
    assert isinstance(e, InputError) and e.member == 2 and e.field == "mesh.cell_size_m"
    assert str(path) in str(e) and "member 2 of 4" in str(e) and "mesh.cell_size_m=0.5" in str(e)


@pytest.mark.parametrize("spec, field", [
    ({"axes": {"mesh.cell_sise_m": [0.05]}}, "mesh.cell_sise_m"),        # unknown scene key
    ({"axes": {"mesh.cell_size_m": 0.05}}, "axes.mesh.cell_size_m"),     # not a list
    ({"axes": {"mesh.cell_size_m": [0.05, 0.05]}}, "axes"),              # two members, one scene
    ({"mode": "both"}, "mode"),
    ({"scenes": [str(TINY)]}, "base"),                                   # base and scenes
    ({"colour": "red"}, "colour"),
    ({"executor": {"kind": "slurm"}}, "executor.kind"),
])
def test_bad_sweep_files_name_the_field(tmp_path, spec, field):
    path = write_sweep(tmp_path / "bad.yaml", **spec)
    with pytest.raises(InputError) as err:
        load_sweep(path)
    assert err.value.field == field and err.value.source == str(path)


def test_cli_bad_member_exits_2_before_anything_is_written(tmp_path):
    path = write_sweep(tmp_path / "bad.yaml", axes={"mesh.cell_size_m": [0.05, 0.5]})
    out = tmp_path / "out"
    proc = run_cli("sweep", str(path), "-o", str(out))
    assert proc.returncode == 2, proc.stderr
    assert str(path) in proc.stderr and "member 2 of 2" in proc.stderr and "mesh.cell_size_m" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not out.exists()


def test_shipped_sweeps_expand_and_validate():
    sweeps = {p.stem: load_sweep(p) for p in sorted((ROOT / "cases" / "sweeps").glob("*.yaml"))}
    assert {"mesh-study", "impoundment-depths", "debris-layouts", "tiny-mesh-study"} <= set(sweeps)
    mesh = sweeps["mesh-study"]
    sizes = [m.params["mesh.cell_size_m"] for m in mesh.members]
    assert len(sizes) >= 3 and sizes == sorted(sizes, reverse=True)
    assert [m.plan.cell_count for m in mesh.members] == sorted(m.plan.cell_count for m in mesh.members)
    assert [m.params["reservoir.depth_m"] for m in sweeps["impoundment-depths"].members] == [0.3, 0.4, 0.5, 0.7]
    layouts = sweeps["debris-layouts"]
    assert layouts.parameters == ["scene"]
    assert [m.params["scene"] for m in layouts.members] == ["1debris", "3debris-3x1", "3debris-1x3", "6debris-2x3"]
    assert [len(m.scene.debris) for m in layouts.members] == [1, 3, 3, 6]
    # a member whose scene is a file as written has that file's id
    assert layouts.members[0].id == member_id(load_scene(ROOT / "cases" / "1debris.yaml"))
    # the mesh study with debris: overset, the same body mesh in every member, finer background cells
    debris = sweeps["debris-mesh-study"]
    assert all(m.plan.solver == "overInterDyMFoam" and m.scene.run.end_time_s == 2.1 for m in debris.members)
    assert len({tuple(b.cell_size_m for b in m.plan.bodies) for m in debris.members}) == 1
    assert [m.plan.cell_count for m in debris.members] == sorted(m.plan.cell_count for m in debris.members)


def test_dry_run_lists_members_cells_and_times_and_writes_nothing(tmp_path):
    out = tmp_path / "out"
    proc = run_cli("sweep", str(TINY_SWEEP), "-o", str(out), "--dry-run")
    assert proc.returncode == 0, proc.stderr
    sw = load_sweep(TINY_SWEEP)
    for m in sw.members:
        line = next(line for line in proc.stdout.splitlines() if m.id in line)
        assert f"{m.plan.cell_count:,}" in line and "pending" in line and "interFoam" in line
    assert "estimated" in proc.stdout
    plan = json.loads(run_cli("sweep", str(TINY_SWEEP), "-o", str(out), "--dry-run", "--json").stdout)
    assert [r["id"] for r in plan["members"]] == [m.id for m in sw.members]
    assert [r["cells"] for r in plan["members"]] == [m.plan.cell_count for m in sw.members]
    assert all(r["estimated_wall_time_s"] > 0 for r in plan["members"])
    assert plan["estimated_wall_time_s"] == pytest.approx(sum(r["estimated_wall_time_s"] for r in plan["members"]))
    assert not out.exists()


def test_store_round_trip(tmp_path):
    rows = [{"member": 1, "member_id": "a", "status": "finished", "debris.0.size_m": [0.1, 0.2, 0.3], "x_s": 1.5},
            {"member": 2, "member_id": "b", "status": "failed", "error": "boom", "x_s": float("nan")}]
    _write_store(tmp_path, rows)
    frame = load_store(tmp_path)
    assert list(frame.columns) == ["member", "member_id", "status", "debris.0.size_m", "x_s", "error"]
    assert json.loads(frame.loc[0, "debris.0.size_m"]) == [0.1, 0.2, 0.3]
    assert frame.loc[0, "x_s"] == 1.5 and pd.isna(frame.loc[1, "x_s"]) and frame.loc[1, "error"] == "boom"
    with pytest.raises(InputError):
        load_store(tmp_path / "nowhere")


def test_a_resumed_members_wall_time_counts_its_earlier_attempts(tmp_path):
    """A killed attempt never writes its wall time; run.json keeps every step and segment it ran,
    each with its start, and the member's wall adds those that began before this attempt."""
    from orchestrator.studies.sweep.member import earlier_attempts_wall_s
    run = {"steps": [{"name": "blockMesh", "start": "2026-01-01T10:00:00+00:00", "wall_s": 2.0},
                     {"name": "blockMesh", "start": "2026-01-01T12:00:05+00:00", "wall_s": 0.1}],
           "segments": [{"start": "2026-01-01T10:00:03+00:00", "wall_s": 600.0},
                        {"start": "2026-01-01T11:59:00+00:00", "wall_s": 30.0},
                        {"start": "2026-01-01T12:00:06+00:00", "wall_s": 900.0}]}
    (tmp_path / "run.json").write_text(json.dumps(run))
    assert earlier_attempts_wall_s(tmp_path, "2026-01-01T12:00:00+00:00") == pytest.approx(632.0)
    assert earlier_attempts_wall_s(tmp_path, "2026-01-01T09:00:00+00:00") == 0.0
    # the same instant in another offset
    assert earlier_attempts_wall_s(tmp_path, "2026-01-01T13:00:00+01:00") == pytest.approx(632.0)
    assert earlier_attempts_wall_s(tmp_path / "nowhere", "2026-01-01T12:00:00+00:00") == 0.0


# --------------------------------------------------------------------------- real runs


def _mtimes(case: Path) -> dict[str, int]:
    return {name: (case / name).stat().st_mtime_ns for name in ("run.json", MEMBER_JSON, "results/summary.json")}


@pytest.fixture(scope="module")
def local_sweep(tiny_sweep):
    """The shipped tiny mesh study, run by the CLI on the local executor (once per session: conftest)."""
    return tiny_sweep


@pytest.mark.openfoam
def test_local_sweep_runs_every_member_into_the_store(local_sweep, openfoam):
    out, proc = local_sweep
    assert proc.returncode == 0, proc.stderr[-3000:]
    sw = load_sweep(TINY_SWEEP)
    for m in sw.members:
        assert re.search(rf"{m.id} .*: started", proc.stdout) and re.search(rf"{m.id} .*: finished in", proc.stdout)
    store = load_store(out)
    assert list(store["member_id"]) == [m.id for m in sw.members]
    assert list(store["mesh.cell_size_m"]) == [0.05, 0.04]
    assert (store["status"] == "finished").all()
    assert list(store["cells"]) == [m.plan.cell_count for m in sw.members]
    assert (store["time_steps"] > 10).all() and (store["wall_time_s"] > 0).all()
    assert (store["reached_time_s"] == 0.3).all()
    # headline metrics: the bore reaches WG2 (0.40 m) and is compared with Chanson's solution
    assert store["WG2_arrival_s"].between(0.1, 0.3).all()
    assert store["WG2_arrival_error_chanson_s"].notna().all()
    assert (store["peak_hydro_force_x_N"].abs() > 0).all() and store["peak_base_shear_N"].notna().all()
    assert store["error"].isna().all()
    for m in sw.members:
        case = out / m.id
        # the member's folder holds its resolved scene, which reloads to the same id
        assert member_id(load_scene(case / "scene.yaml")) == m.id
        assert json.loads((case / MEMBER_JSON).read_text())["status"] == "finished"
        assert (case / "results" / "summary.json").is_file()


@pytest.mark.openfoam
def test_a_rerun_skips_finished_members(local_sweep, openfoam):
    out, _ = local_sweep
    sw = load_sweep(TINY_SWEEP)
    before = {m.id: _mtimes(out / m.id) for m in sw.members}
    store_before = load_store(out)
    t0 = time.perf_counter()
    proc = run_cli("sweep", str(TINY_SWEEP), "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert time.perf_counter() - t0 < 15  # no solver ran
    assert proc.stdout.count("finished earlier") == 2 and "started" not in proc.stdout
    assert {m.id: _mtimes(out / m.id) for m in sw.members} == before
    after = load_store(out)
    assert list(after["wall_time_s"]) == list(store_before["wall_time_s"])
    assert list(after["status"]) == ["finished", "finished"]


@pytest.mark.openfoam
@pytest.mark.slow
def test_dask_local_cluster_runs_the_same_sweep(local_sweep, tmp_path, openfoam):
    local_out, _ = local_sweep
    out = tmp_path / "dask"
    proc = run_cli("sweep", str(TINY_SWEEP), "-o", str(out), "--executor", "dask", "--json")
    assert proc.returncode == 0, proc.stderr[-3000:]
    result = json.loads(proc.stdout)
    assert result["finished"] == 2 and result["failed"] == 0 and len(result["ran"]) == 2
    assert "dask LocalCluster" in proc.stderr and proc.stderr.count(": finished in") == 2
    assert "Traceback" not in proc.stderr and "CancelledError" not in proc.stderr, proc.stderr[-3000:]
    local, dask = load_store(local_out), load_store(out)
    assert list(dask["member_id"]) == list(local["member_id"])
    assert list(dask["cells"]) == list(local["cells"]) and list(dask["time_steps"]) == list(local["time_steps"])
    assert dask["WG2_arrival_s"].to_numpy() == pytest.approx(local["WG2_arrival_s"].to_numpy(), abs=1e-6)


# Two trivial members on the sweep's own Dask executor (a LocalCluster of worker processes),
# each holding the stop bridge a real member holds while it runs; a separate process, so its
# stderr is exactly what a user's terminal would show.
_TRIVIAL_DASK_SWEEP = """
import time
from orchestrator.studies.sweep.executors import dask_executor as _dask_executor
from orchestrator.studies.sweep.member import stop_flag as _stop_flag

def member(i, stop):
    flag, release = _stop_flag(stop)
    try:
        time.sleep(0.3)
        return i
    finally:
        release()

with _dask_executor(2, None, None) as ex:
    futures = [ex.submit(member, i, ex.stop, key=f"trivial-{i}") for i in range(2)]
    print(sorted(f.result() for f in ex.as_completed(futures)))
"""


@pytest.mark.parametrize("attempt", [0, pytest.param(1, marks=pytest.mark.slow), pytest.param(2, marks=pytest.mark.slow)])
def test_the_dask_executor_shuts_down_without_a_traceback(attempt):
    """Each member's stop bridge keeps an Event.wait open on the scheduler for up to a second
    after its member returns; a cluster closed under it logged `distributed.event - ERROR`
    with an asyncio.CancelledError traceback (5 of 5 runs of this script, exit 0). The
    executor sets the stop event before closing the client, then the cluster: stderr stays
    empty. Three attempts, because a shutdown race need not show on every run."""
    proc = subprocess.run([sys.executable, "-c", _TRIVIAL_DASK_SWEEP], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip() == "[0, 1]"
    assert "Traceback" not in proc.stderr and "CancelledError" not in proc.stderr, proc.stderr[-3000:]
    assert proc.stderr.strip() == "", proc.stderr[-3000:]


@pytest.mark.openfoam
def test_a_failing_member_does_not_stop_the_other_and_is_recorded(tmp_path, openfoam):
    # 1e7 N/m of surface tension: explicit capillary forces blow up at once and interFoam's
    # time step collapses (diverged after ~40 steps, ~2 s); the other member is the tiny flume
    path = write_sweep(tmp_path / "fail.yaml", name="fail", mode="zip", set={**SHORT, "mesh.cell_size_m": 0.05},
                       axes={"fluids.surface_tension_N_m": [1.0e7, 0.07]})
    sw = load_sweep(path)
    bad, good = sw.members
    out = tmp_path / "out"
    lines: list[str] = []
    result = run_sweep(sw, out, executor="dask", cluster_kwargs={"processes": False}, progress=lines.append)
    assert result.failed == [bad.id] and result.finished == [good.id]
    store = load_store(out)
    row = store.set_index("member_id").loc[bad.id]
    assert row["status"] == "failed" and row["run_status"] == "diverged"
    assert "diverged" in row["error"] and "log.interFoam" in row["error"]
    assert row["fluids.surface_tension_N_m"] == 1.0e7
    assert store.set_index("member_id").loc[good.id, "status"] == "finished"
    assert any(bad.id in line and "failed in" in line for line in lines)
    # a re-run leaves the failed member alone (exit 1, naming it and its log), unless asked
    record = (out / bad.id / MEMBER_JSON).stat().st_mtime_ns
    proc = run_cli("sweep", str(path), "-o", str(out))
    assert proc.returncode == 1
    assert bad.id in proc.stderr and "log.interFoam" in proc.stderr and "--retry-failed" in proc.stderr
    assert (out / bad.id / MEMBER_JSON).stat().st_mtime_ns == record
    again = run_sweep(sw, out, retry_failed=True, progress=None)
    assert again.ran == [bad.id] and again.skipped == [good.id] and again.failed == [bad.id]


@pytest.mark.openfoam
@pytest.mark.parametrize("how", [pytest.param("ctrl-c", marks=pytest.mark.slow), "sigterm"])
def test_a_stopped_sweep_stops_cleanly_and_a_rerun_resumes(tmp_path, openfoam, how):
    """ctrl-c: SIGINT to the whole process group, as a terminal sends it; sigterm: `kill PID`
    (or a batch system's stop) to the sweep alone, started as `nohup ... &` starts it (SIGINT
    ignored): both stop the running member cleanly."""
    # the first member runs long enough (2 s of flow, ~300 steps) to be stopped; the second is short
    path = write_sweep(tmp_path / "long.yaml", name="long", mode="zip", set={"run.write_interval_s": 0.1},
                       axes={"mesh.cell_size_m": [0.04, 0.05], "run.end_time_s": [2.0, 0.3]})
    first, second = load_sweep(path).members
    out = tmp_path / "out"
    sigint = signal.SIG_DFL if how == "ctrl-c" else signal.SIG_IGN
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator.cli", "sweep", str(path), "-o", str(out)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, sigint))
    log = out / first.id / "log.interFoam"
    deadline = time.time() + 120
    while time.time() < deadline and not (log.is_file() and log.read_text().count("\nTime = ") >= 20):
        time.sleep(0.2)
    if how == "ctrl-c":
        os.killpg(proc.pid, signal.SIGINT)
    else:
        proc.send_signal(signal.SIGTERM)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == (130 if how == "ctrl-c" else 143), stderr
    assert "interrupted" in stdout and "run the same command again" in stderr
    store = load_store(out).set_index("member_id")
    assert store.loc[first.id, "status"] == "interrupted" and store.loc[second.id, "status"] == "pending"
    stopped_at = store.loc[first.id, "reached_time_s"]
    assert 0 < stopped_at < 2.0
    proc = run_cli("sweep", str(path), "-o", str(out))
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert f"{first.id} mesh.cell_size_m=0.04, run.end_time_s=2.0: resumed" in proc.stdout
    assert (out / first.id / "log.interFoam.1").is_file()  # the first segment's log, kept: resumed, not redone
    store = load_store(out).set_index("member_id")
    assert (store["status"] == "finished").all()
    # the resumed member's wall time covers both attempts: never less than its solver's
    assert store.loc[first.id, "wall_time_s"] >= store.loc[first.id, "solver_wall_s"] > 0


def test_a_late_scene_key_changes_no_id_until_it_is_set():
    """run.max_delta_t_s and run.stall_limit_s came after ids were issued: unset, they are not
    hashed (the mesh study's finished members keep their folders); set, they make a new member."""
    scene = load_scene(ROOT / "cases" / "nodebris.yaml", ["mesh.cell_size_m=0.08"])
    assert scene.run.max_delta_t_s is None and scene.run.stall_limit_s is None
    assert member_id(scene) == "b92a230c1196"  # the id the mesh study's 8 cm member has always had
    for late in ("run.max_delta_t_s=0.05", "run.stall_limit_s=1800"):
        assert member_id(load_scene(ROOT / "cases" / "nodebris.yaml",
                                    ["mesh.cell_size_m=0.08", late])) != "b92a230c1196"


@pytest.mark.parametrize("change, same", [
    ([], True),
    (["mesh.cell_size_m=0.035"], False),
    (["transport.drag_coefficient=2.0"], False),  # a one-way case reads its transport
    (["run.debris_coupling=two-way"], False),
])
@pytest.mark.parametrize("coupling", ["auto", "two-way"])
def test_a_case_folder_and_a_sweep_member_answer_the_same_case_alike(tmp_path, change, same, coupling):
    """`debrisfoam case` resumes a folder when pipeline.holds_case says it holds the scene; a sweep
    gives two scenes one member id when they make the same case: both ask plan.identity, so they agree
    (a two-way case ignores the one-way transport: changing it leaves the case the same)."""
    import json as _json

    from orchestrator.case.folder import CaseFolder
    from orchestrator.pipeline import holds_case
    from orchestrator.plan.planner import plan_case

    sets = [f"run.debris_coupling={coupling}"]
    a = load_scene(ROOT / "cases" / "1debris.yaml", sets)
    b = load_scene(ROOT / "cases" / "1debris.yaml", sets + change)
    plan = plan_case(a, "a")
    folder = CaseFolder(tmp_path)
    folder.write_scene(a)
    folder.write_plan_json(_json.dumps({"debris_coupling": plan.debris_coupling}))
    expected = same or (coupling == "two-way" and change == ["transport.drag_coefficient=2.0"]) \
        or (coupling == "two-way" and change == ["run.debris_coupling=two-way"])
    assert holds_case(tmp_path, b) is expected
    assert (member_id(a) == member_id(b)) is expected


_WORKER_ENV = """
import os
from orchestrator.studies.sweep.executors import dask_executor

def environment(_stop):
    return os.environ.get("MALLOC_TRIM_THRESHOLD_"), os.environ.get("OMP_NUM_THREADS")

if __name__ == "__main__":
    with dask_executor(1, None, None) as ex:
        print(ex.submit(environment, ex.stop, key="env").result())
"""


@pytest.mark.slow
def test_dask_workers_start_without_the_malloc_trim_threshold():
    """Distributed's nannies would start workers with MALLOC_TRIM_THRESHOLD_=65536, which halves
    the transport's speed (orchestrator.studies.sweep.executors.worker_environment); the
    executor's workers start without it, and keep the rest (one BLAS thread)."""
    proc = subprocess.run([sys.executable, "-c", _WORKER_ENV], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip() == "(None, '1')"
