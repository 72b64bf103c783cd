"""One member of a sweep, run on whichever worker the executor gives it.

:func:`run_member` renders the member's case (once), runs it (resuming) and post-processes
it, through :func:`orchestrator.pipeline.run_full_case`, and returns its outcome: a member
that fails never raises, so it never stops the others. It writes member.json (status
"running" and the sweep's token) as it starts, which is how the parent learns it has begun.
"""

from __future__ import annotations

import asyncio
import datetime as _dt
import os
import socket
import threading
import time
from pathlib import Path
from typing import Any, Callable

from orchestrator.core.errors import DebrisfoamError
from orchestrator.case.folder import CaseFolder
from orchestrator.pipeline import prepare_case, run_full_case
from orchestrator.plan.planner import load_and_plan
from orchestrator.run.runner import RunInterrupted
from orchestrator.studies.sweep.store import member_metrics, timestamp, write_member_record


def stop_flag(stop: Any) -> tuple[threading.Event, Callable[[], None]]:
    """A threading.Event for run_case from the sweep's stop handle, and the call that
    releases it: a threading.Event (local executor) as it is; a distributed.Event (dask)
    bridged by a watcher thread."""
    if stop is None:
        return threading.Event(), lambda: None
    if isinstance(stop, threading.Event):
        return stop, lambda: None
    local, done = threading.Event(), threading.Event()
    try:
        _ = stop.client  # resolve the worker's client here, in the task's thread
        if stop.is_set():
            local.set()
    except Exception:  # no scheduler to ask: nothing will ask us to stop
        return local, lambda: None

    def bridge() -> None:
        while not done.is_set():
            try:
                if stop.wait(timeout=1.0):
                    local.set()
                    return
            except (Exception, asyncio.CancelledError):  # the scheduler is gone: nothing will ask us to stop
                return

    threading.Thread(target=bridge, name="debrisfoam-stop-bridge", daemon=True).start()
    return local, done.set


def _run(task: dict[str, Any], case: Path, flag: threading.Event, record: dict[str, Any]) -> tuple[str, str | None, bool]:
    """Render (unless the folder holds it already) and run the member: (status, error, ours?).
    ``ours`` is False when the folder holds another case: nothing may be written there."""
    error, ours = None, False
    try:
        # the sweep's soft resource limits were confirmed (or refused) for every member at its start
        scene, plan = load_and_plan(task["scene_file"])
        prepare_case(scene, plan, task["scene_file"], case, confirmed=True)
        write_member_record(case, record)
        ours = True
        run_full_case(scene, plan, task["scene_file"], case, (), np=task.get("np"), quiet=True, stop_event=flag)
        status = "finished"
    except RunInterrupted as exc:
        status, error = "interrupted", str(exc)
    except Exception as exc:  # any failure is this member's only: record it, go on
        # a step killed by the Ctrl-C that stops the sweep is an interruption, not a failure
        status = "interrupted" if flag.is_set() else "failed"
        error = str(exc) if isinstance(exc, DebrisfoamError) else f"{type(exc).__name__}: {exc}"
    return status, error, ours


def earlier_attempts_wall_s(case: str | Path, started: str) -> float:
    """Wall seconds of the run's steps and solver segments (run.json) that began before
    ``started`` (an ISO time with its offset): what earlier attempts of a resumed member ran."""
    try:
        begun = _dt.datetime.fromisoformat(started)
        return CaseFolder(case).run_state().wall_before_s(begun)
    except (TypeError, ValueError):  # a record this version cannot read: count this attempt alone
        return 0.0


def run_member(task: dict[str, Any], stop: Any = None) -> dict[str, Any]:
    """Render (once), run (resuming) and post-process one member; never raises for a
    member that fails: returns its outcome (status, error, wall time, metrics).

    task: id, index, label, scene_file, case_dir, np, token, record (written to member.json).
    stop: a threading.Event or a distributed.Event; when set the run stops cleanly
    (status "interrupted", resumable), and a member that has not started does not start.
    """
    case = Path(task["case_dir"])
    flag, release = stop_flag(stop)
    base = {"id": task["id"], "index": task["index"], "case_dir": str(case), "host": socket.gethostname()}
    try:
        if flag.is_set():
            return {**base, "status": "not started", "error": None, "wall_time_s": None, "metrics": {}}
        t0 = time.perf_counter()
        record = {**task.get("record", {}), "id": task["id"], "status": "running", "started": timestamp(),
                  "host": base["host"], "pid": os.getpid(), "token": task.get("token")}
        status, error, ours = _run(task, case, flag, record)
        # a resumed member's wall time includes what its earlier attempts ran (a killed attempt
        # never wrote its own): a member's wall is never less than its solver's
        earlier = earlier_attempts_wall_s(case, record["started"]) if ours else 0.0
        wall = round(time.perf_counter() - t0 + earlier, 2)
        record.update({"status": status, "error": error, "finished": timestamp(), "wall_time_s": wall})
        if earlier:
            record["earlier_attempts_wall_s"] = round(earlier, 2)
        metrics = {}
        if ours:  # never write into (or read) a folder that holds another case
            write_member_record(case, record)
            metrics = member_metrics(case)
        return {**base, "status": status, "error": error, "wall_time_s": wall, "started": record["started"],
                "finished": record["finished"], "metrics": metrics}
    finally:
        release()
