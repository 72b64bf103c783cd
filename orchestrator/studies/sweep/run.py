"""Running a sweep, or planning one: :func:`run_sweep` and :func:`dry_run`.

:func:`run_sweep` runs the members that are not finished yet, on a thread pool (``local``)
or a Dask cluster (``dask``: a LocalCluster, or an existing scheduler), through one code
path: ``submit`` every member, handle them ``as_completed``. Re-running the same command
skips finished members, resumes interrupted ones (the solver restarts from its latest written
time) and retries failed ones only with ``retry_failed=True``. A member that fails is
recorded (status, error, log) and never stops the others; the store is rewritten after every
member, so a crash loses nothing. Ctrl-C or SIGTERM stops the running members cleanly.

:func:`dry_run` lists the members with their planned cells and estimated wall times and
runs nothing.
"""

from __future__ import annotations

import contextlib
import signal
import threading
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

from orchestrator.core.errors import InputError
from orchestrator.studies.sweep.executors import (
    Executor,
    StartWatcher,
    default_slots,
    open_executor,
    signal_handlers,
)
from orchestrator.studies.sweep.member import run_member
from orchestrator.studies.sweep.spec import EXECUTORS, Member, Sweep, default_sweep_dir, load_sweep
from orchestrator.studies.sweep.store import (
    SCENES_DIR,
    STORE_FILE,
    member_row,
    member_row_from_disk,
    member_state,
    write_manifest,
    write_store,
)


@dataclass
class SweepResult:
    """What run_sweep did: the store's rows, and which members ended how."""

    sweep: Sweep
    out_dir: Path
    store: Path
    rows: list[dict[str, Any]]
    ran: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    interrupted: bool = False
    #: the signal that stopped the sweep (SIGINT, SIGTERM), None when not interrupted by one
    signum: int | None = None

    def _ids(self, status: str) -> list[str]:
        return [r["member_id"] for r in self.rows if r["status"] == status]

    @property
    def finished(self) -> list[str]:
        return self._ids("finished")

    @property
    def failed(self) -> list[str]:
        return self._ids("failed")

    @property
    def unfinished(self) -> list[str]:
        return [r["member_id"] for r in self.rows if r["status"] not in ("finished", "failed")]

    @property
    def ok(self) -> bool:
        return len(self.finished) == len(self.rows)

    def failures(self) -> list[dict[str, Any]]:
        return [r for r in self.rows if r["status"] == "failed"]

    def to_dict(self) -> dict[str, Any]:
        keep = ("member", "member_id", "status", *self.sweep.parameters, "wall_time_s", "cells", "time_steps",
                "error", "case_dir")
        return {
            "sweep": self.sweep.name, "sweep_file": str(self.sweep.path), "out_dir": str(self.out_dir),
            "store": str(self.store), "members": len(self.rows), "finished": len(self.finished),
            "failed": len(self.failed), "unfinished": len(self.unfinished), "ran": self.ran,
            "skipped": self.skipped, "interrupted": self.interrupted,
            "rows": [{k: r.get(k) for k in keep} for r in self.rows],
        }


def _first_line(text: str | None) -> str:
    return (text or "").strip().splitlines()[0] if text and text.strip() else ""


def resolve_executor(sweep: Sweep, executor: str | None, scheduler: str | None,
                     workers: int | None) -> tuple[str, str | None, int | None]:
    """(kind, scheduler, members at once): the caller's choice, else the sweep file's, else local."""
    kind = executor or ("dask" if scheduler else None) or sweep.executor or ("dask" if sweep.scheduler else "local")
    if kind not in EXECUTORS:
        raise InputError("--executor", f"must be one of {', '.join(EXECUTORS)}, got {kind!r}")
    scheduler = scheduler or sweep.scheduler
    if scheduler and kind != "dask":
        raise InputError("--scheduler", "a scheduler address needs the dask executor (--executor dask)")
    if workers is not None and workers < 1:
        raise InputError("--workers", f"must be >= 1, got {workers}")
    return kind, scheduler, workers or sweep.workers


class _SweepRun:
    """One call of run_sweep: every member's row as it changes, the progress lines, and the
    store rewritten after every member."""

    def __init__(self, sweep: Sweep, out: Path, progress: Callable[[str], None] | None):
        self.sweep, self.out, self.progress = sweep, out, progress
        self.lock = threading.Lock()
        n = len(sweep.members)
        self.tag = {m.id: f"[{m.index}/{n}] {m.id} {m.label or '(base scene)'}" for m in sweep.members}
        self.rows: dict[str, dict[str, Any]] = {}
        self.result = SweepResult(sweep, out, out / STORE_FILE, [])

    def say(self, text: str) -> None:
        if self.progress is not None:
            with self.lock:
                self.progress(text)

    def store(self) -> None:
        self.result.rows = [self.rows[m.id] for m in self.sweep.members]
        write_store(self.out, self.result.rows)

    def triage(self, retry_failed: bool) -> list[Member]:
        """Rows for every member from its folder; the members still to run."""
        todo = []
        for m in self.sweep.members:
            state = member_state(self.out / m.id)
            if state == "finished" or (state == "failed" and not retry_failed):
                self.rows[m.id] = member_row_from_disk(self.sweep, m, self.out, state)
                self.result.skipped.append(m.id)
                if state == "finished":
                    wall = self.rows[m.id].get("wall_time_s")
                    self.say(f"{self.tag[m.id]}: finished earlier{f' ({wall:.1f} s)' if wall is not None else ''}; "
                             "skipped")
                else:
                    self.say(f"{self.tag[m.id]}: failed earlier ({_first_line(self.rows[m.id].get('error'))}); "
                             "skipped (--retry-failed runs it again)")
            else:
                self.rows[m.id] = member_row(self.sweep, m, self.out, "pending" if state == "pending" else "incomplete")
                todo.append(m)
        return todo

    def task(self, m: Member, token: str) -> dict[str, Any]:
        """What :func:`run_member` gets on its worker (plain data: it may cross to another process)."""
        sw = self.sweep
        return {"id": m.id, "index": m.index, "label": m.label, "token": token,
                "scene_file": str(self.out / SCENES_DIR / f"{m.id}.yaml"), "case_dir": str(self.out / m.id),
                "np": sw.cores_per_member,
                "record": {"sweep": sw.name, "sweep_file": str(sw.path), "member": m.index,
                           "base": str(m.base), "overrides": list(m.overrides), "params": m.params}}

    def started(self, m: Member) -> None:
        self.say(f"{self.tag[m.id]}: {'resumed' if self.rows[m.id]['status'] == 'incomplete' else 'started'}")

    def execute(self, todo: list[Member], kind: str, slots: int, scheduler: str | None,
                cluster_kwargs: dict | None) -> None:
        token = uuid.uuid4().hex
        with open_executor(kind, slots, scheduler, cluster_kwargs) as ex:
            self.say(f"sweep {self.sweep.name}: {len(todo)} of {len(self.sweep.members)} member(s) to run on "
                     f"{ex.describe} -> {self.out}")
            watcher = StartWatcher({m.id: m for m in todo}, self.out, token, self.started)
            futures = {ex.submit(run_member, self.task(m, token), ex.stop,
                                 key=f"debrisfoam-member-{m.id}-{token[:8]}"): m for m in todo}
            try:
                self.collect(ex, futures, watcher)
            finally:
                watcher.close()
                self.store()

    def collect(self, ex: Executor, futures: dict, watcher: StartWatcher) -> None:
        """Handle the members as they complete; on Ctrl-C or SIGTERM stop the rest cleanly
        and handle them as they stop."""
        caught: list[int] = []

        def interrupt(signum, frame) -> None:  # noqa: ARG001 - signal API
            caught.append(signum)
            raise KeyboardInterrupt

        try:
            with signal_handlers({signal.SIGTERM: interrupt, signal.SIGINT: interrupt}):
                for fut in ex.as_completed(list(futures)):
                    self.finish(futures.pop(fut), fut, watcher)
        except KeyboardInterrupt:
            self.result.interrupted = True
            self.result.signum = caught[0] if caught else signal.SIGINT
            self.say("interrupted: stopping the running members cleanly (run the sweep again to resume)")
            with contextlib.suppress(Exception):
                ex.stop.set()
            for fut in ex.as_completed(list(futures)):
                self.finish(futures.pop(fut), fut, watcher)

    def finish(self, m: Member, fut: Any, watcher: StartWatcher) -> None:
        try:
            outcome = fut.result()
        except BaseException as exc:  # the task itself died (a killed worker, a cancelled future)
            if isinstance(exc, KeyboardInterrupt):
                raise
            outcome = {"status": "failed", "error": f"{type(exc).__name__}: {exc}".strip(": "),
                       "wall_time_s": None, "metrics": {}}
        watcher.poll()
        watcher.forget(m.id)
        self.record(m, outcome)

    def record(self, m: Member, outcome: dict[str, Any]) -> None:
        """The member's outcome into its row, the store and a progress line."""
        status = outcome["status"]
        if status == "not started":  # its row stays pending (or incomplete)
            self.say(f"{self.tag[m.id]}: not started (stopping)")
            return
        self.rows[m.id] = member_row(self.sweep, m, self.out, status, outcome=outcome)
        self.result.ran.append(m.id)
        self.store()
        wall = outcome.get("wall_time_s")
        took = f" in {wall:.1f} s" if wall is not None else ""
        if status == "finished":
            mt = outcome.get("metrics", {})
            self.say(f"{self.tag[m.id]}: finished{took} ({mt.get('cells')} cells, {mt.get('time_steps')} time steps)")
        elif status == "interrupted":
            self.say(f"{self.tag[m.id]}: interrupted{took}; run the sweep again to resume it")
        else:
            self.say(f"{self.tag[m.id]}: failed{took}: {outcome.get('error')}")


def run_sweep(sweep: Sweep | str | Path, out_dir: str | Path | None = None, *, executor: str | None = None,
              scheduler: str | None = None, workers: int | None = None, retry_failed: bool = False,
              progress: Callable[[str], None] | None = print, cluster_kwargs: dict | None = None) -> SweepResult:
    """Run every member of a sweep that is not finished yet; returns the store's rows.

    executor: "local" (a thread pool; members run on their own MPI ranks) or "dask" (a
    LocalCluster, or the scheduler at `scheduler`); default: the sweep file's, else local.
    workers: members at once (local, and the LocalCluster's workers); default: the sweep
    file's, else cores // cores per member. retry_failed: run failed members again (they
    resume from their last good time). progress: called with one line per event (None: quiet).
    cluster_kwargs: extra LocalCluster arguments (e.g. processes=False).

    Raises InputError for a bad sweep (before anything runs). A member that fails is a row
    with status "failed", never an exception. Ctrl-C stops the running members cleanly
    (their rows say "interrupted"; run again to resume) and sets `interrupted`.
    """
    sw = sweep if isinstance(sweep, Sweep) else load_sweep(sweep)
    kind, scheduler, slots = resolve_executor(sw, executor, scheduler, workers)
    out = Path(out_dir) if out_dir is not None else default_sweep_dir(sw)
    out = out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    write_manifest(sw, out)
    run = _SweepRun(sw, out, progress)
    todo = run.triage(retry_failed)
    run.store()
    result = run.result
    if not todo:
        run.say(f"sweep {sw.name}: nothing to run ({len(result.finished)} finished, {len(result.failed)} failed)")
        return result
    slots = slots or default_slots(max(sw.member_cores(m) for m in todo))
    run.execute(todo, kind, slots, scheduler, cluster_kwargs)
    run.say(f"sweep {sw.name}: {len(result.finished)} of {len(sw.members)} finished, {len(result.failed)} failed; "
            f"store {result.store}")
    return result


# --------------------------------------------------------------------------- dry run


def _makespan(durations: Sequence[float], slots: int) -> float:
    """Wall time of running `durations` in order on `slots` slots, each taken when free."""
    ends = [0.0] * max(1, slots)
    for d in durations:
        i = ends.index(min(ends))
        ends[i] += d
    return max(ends)


def dry_run(sweep: Sweep | str | Path, out_dir: str | Path | None = None, *, executor: str | None = None,
            scheduler: str | None = None, workers: int | None = None) -> dict[str, Any]:
    """The members, their planned cell counts and estimated solver wall times; runs nothing,
    writes nothing. `state` says what the sweep folder already holds for each member."""
    sw = sweep if isinstance(sweep, Sweep) else load_sweep(sweep)
    kind, scheduler, slots = resolve_executor(sw, executor, scheduler, workers)
    out = Path(out_dir) if out_dir is not None else default_sweep_dir(sw)
    members = []
    for m in sw.members:
        members.append({
            "member": m.index, "id": m.id, "params": m.params, "overrides": list(m.axis_overrides),
            "solver": m.plan.solver, "two_d": m.plan.two_d, "cores": sw.member_cores(m),
            "cells": m.plan.cell_count, "estimated_wall_time_s": round(m.estimated_wall_time_s, 1),
            "state": member_state(out / m.id),
            "warnings": list(m.plan.warnings),
        })
    todo = [r for r in members if r["state"] != "finished"]
    slots = slots or default_slots(max((r["cores"] for r in members), default=1))
    total = sum(r["estimated_wall_time_s"] for r in todo)
    return {
        "sweep": sw.name, "sweep_file": str(sw.path), "out_dir": str(out), "mode": sw.mode,
        "parameters": sw.parameters, "executor": kind, "scheduler": scheduler, "workers": slots,
        "members": members, "total_cells": sum(r["cells"] for r in members),
        "estimated_wall_time_s": round(total, 1),
        # `workers` members at a time, each started when one ends; unknown on an existing scheduler
        "estimated_sweep_wall_time_s": None if scheduler else round(
            _makespan([r["estimated_wall_time_s"] for r in todo], slots), 1),
        "note": "estimates are solver time only (docs/openfoam-notes.md, Cost: costs per cell-step); meshing and "
                "post-processing add seconds to minutes per member",
    }
