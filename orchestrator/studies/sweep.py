"""Parameter sweeps: one base scene, axes over dotted scene keys, one case per member.

A sweep file (YAML; the format is documented in docs/sweeps.md)::

    name: mesh-study                 # optional; default: the file's stem
    base: ../nodebris.yaml           # the scene, relative to this file (or `scenes:`, a list)
    set: {run.end_time_s: 2.0}       # optional overrides applied to every member
    mode: grid                       # grid (cartesian product, default) or zip (parallel lists)
    axes:
      mesh.cell_size_m: [0.08, 0.06, 0.04]
    executor: {kind: local, workers: 1}   # optional defaults; the CLI's options win
    cores_per_member: 2              # optional: MPI ranks of every member (default: its run.cores)

:func:`load_sweep` expands and validates every member before anything runs (each scene
is loaded with the overrides of :mod:`orchestrator.scene.schema` and planned with
:func:`orchestrator.plan.planner.plan_case`): a bad member is an :class:`InputError` naming the
sweep file, the member and the field. A member's id is a short hash of its resolved
scene, so the same scene always lands in the same folder, whatever axes produced it.

:func:`run_sweep` runs the members that are not finished yet, on a thread pool
(``local``) or a Dask cluster (``dask``: a LocalCluster, or an existing scheduler), through
one code path: ``submit`` every member, handle them ``as_completed``. Output, in the sweep
folder (default ``runs/sweeps/<name>``)::

    sweep.json                   the expanded sweep: every member's id, parameters, overrides
    scenes/<id>.yaml             every member's resolved scene (what its case is rendered from)
    <id>/                        the member's case (orchestrator.pipeline.run_full_case):
                                 scene.yaml, plan.json, run.json, logs, results/ ...
    <id>/member.json             the member's status, error, wall time, parameters
    results.sqlite               the results store: table `members`, one row per member

Re-running the same command skips finished members, resumes interrupted ones (the solver
restarts from its latest written time) and retries failed ones only with
``retry_failed=True``. A member that fails is recorded (status, error, log) and never stops
the others; the store is rewritten after every member, so a crash loses nothing.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import datetime as _dt
import hashlib
import itertools
import json
import logging
import math
import os
import re
import signal
import socket
import sqlite3
import threading
import time
import uuid
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, Sequence


from analytical.errors import DebrisfoamError, InputError
from orchestrator.core.jsonio import json_default

__all__ = [
    "MEMBER_JSON",
    "STORE_FILE",
    "STORE_TABLE",
    "Member",
    "Sweep",
    "SweepMemberError",
    "SweepResult",
    "default_sweep_dir",
    "dry_run",
    "load_store",
    "load_sweep",
    "member_id",
    "member_metrics",
    "member_state",
    "run_member",
    "run_sweep",
]

#: The results store (SQLite: pandas + the standard library, no extra dependency).
STORE_FILE = "results.sqlite"
STORE_TABLE = "members"
#: The sweep's record in each member's case folder.
MEMBER_JSON = "member.json"
SWEEP_JSON = "sweep.json"
SCENES_DIR = "scenes"
#: Length of a member id (hex digits of the SHA-256 of the resolved scene).
ID_LENGTH = 12

_SWEEP_KEYS = ("name", "description", "base", "scenes", "set", "mode", "axes", "executor", "cores_per_member")
_EXECUTOR_KEYS = ("kind", "workers", "scheduler")
_EXECUTORS = ("local", "dask")
_MODES = ("grid", "zip")
_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
#: Seconds between the parent's looks for members that have started.
_WATCH_INTERVAL_S = 0.5


# --------------------------------------------------------------------------- the sweep


class SweepMemberError(InputError):
    """A member of a sweep is bad input: names the sweep file, the member and the field."""

    def __init__(self, sweep_file: str, index: int, total: int, label: str, err: InputError):
        self.member = index
        self.label = label
        self.scene_source = err.source
        self.member_text = f"member {index} of {total} ({label or 'the base scene'})"
        scene = f" [scene {err.source}]" if err.source and err.source != sweep_file else ""
        super().__init__(err.field, f"{err.rule}{scene}", sweep_file)

    def _text(self) -> str:
        return f"{self.source}: {self.member_text}: {self.field}: {self.rule}"


@dataclass(frozen=True)
class Member:
    """One member of a sweep: its scene (validated), its plan and where it came from."""

    index: int  # 1-based, in expansion order
    id: str
    base: Path
    overrides: tuple[str, ...]  # every override applied to the base: `set` first, then the axes
    axis_overrides: tuple[str, ...]  # the overrides that differ between members
    params: dict[str, Any]  # axis key -> value (plus "scene" -> file stem with `scenes:`)
    scene: Any  # orchestrator.scene.schema.Scene
    plan: Any  # orchestrator.plan.planner.ModelPlan

    @property
    def label(self) -> str:
        parts = ([f"scene={self.params['scene']}"] if "scene" in self.params else []) + list(self.axis_overrides)
        return ", ".join(parts)

    @property
    def estimated_wall_time_s(self) -> float:
        from orchestrator.plan.planner import estimate_wall_time_s

        return float(self.plan.estimated_wall_time_s or estimate_wall_time_s(self.plan))


@dataclass(frozen=True)
class Sweep:
    """An expanded, validated sweep file."""

    name: str
    description: str
    path: Path
    mode: str
    bases: tuple[Path, ...]
    set: tuple[str, ...]
    axes: dict[str, list]
    members: tuple[Member, ...]
    executor: str | None = None
    workers: int | None = None
    scheduler: str | None = None
    cores_per_member: int | None = None

    @property
    def parameters(self) -> list[str]:
        """The store's parameter columns: "scene" (with `scenes:`) and one per axis key."""
        return (["scene"] if len(self.bases) > 1 else []) + list(self.axes)

    def member_cores(self, member: Member) -> int:
        return int(self.cores_per_member or member.plan.cores)


def default_sweep_dir(sweep: Sweep | str | Path) -> Path:
    """runs/sweeps/<sweep name>, relative to the current directory."""
    name = sweep.name if isinstance(sweep, Sweep) else Path(sweep).stem
    return Path("runs") / "sweeps" / name


#: scene keys added after member ids were first issued: hashed only when set (not None), so
#: that adding a key leaves the ids of existing members, and their finished runs, as they were
LATE_KEYS = (("run", "max_delta_t_s"), ("run", "stall_limit_s"), ("run", "water_balance_limit"))


def member_id(scene) -> str:
    """A short hash of the resolved scene (canonical JSON): the same scene, the same id."""
    from orchestrator.scene.schema import scene_to_dict

    data = scene_to_dict(scene)
    for section, key in LATE_KEYS:
        if isinstance(data.get(section), dict) and data[section].get(key) is None:
            data[section].pop(key, None)
    text = json.dumps(data, sort_keys=True, separators=(",", ":"), default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:ID_LENGTH]


def _override(key: str, value: Any) -> str:
    """`key=value` with the value as JSON (which YAML reads back as the same value)."""
    return f"{key}={json.dumps(value, default=json_default)}"


def _read_mapping(path: Path) -> dict:
    from orchestrator.scene.schema import read_yaml

    source = str(path)
    data = read_yaml(path, "sweep")
    if not isinstance(data, dict):
        raise InputError("sweep", f"must be a mapping (base, axes, ...), got {type(data).__name__}", source)
    return data


def _positive_int(value: Any, field: str, source: str) -> int | None:
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise InputError(field, f"must be a whole number >= 1, got {value!r}", source)
    return value


def _parse_executor(raw: Any, source: str) -> tuple[str | None, int | None, str | None]:
    if raw is None:
        return None, None, None
    if isinstance(raw, str):
        raw = {"kind": raw}
    if not isinstance(raw, dict):
        raise InputError("executor", f"must be local, dask or a mapping ({', '.join(_EXECUTOR_KEYS)})", source)
    unknown = [k for k in raw if k not in _EXECUTOR_KEYS]
    if unknown:
        raise InputError(f"executor.{unknown[0]}", f"unknown key (known: {', '.join(_EXECUTOR_KEYS)})", source)
    kind = raw.get("kind")
    if kind is not None and kind not in _EXECUTORS:
        raise InputError("executor.kind", f"must be one of {', '.join(_EXECUTORS)}, got {kind!r}", source)
    scheduler = raw.get("scheduler")
    if scheduler is not None and not isinstance(scheduler, str):
        raise InputError("executor.scheduler", f"must be an address such as tcp://host:8786, got {scheduler!r}", source)
    return kind, _positive_int(raw.get("workers"), "executor.workers", source), scheduler


def _parse_set(raw: Any, source: str) -> tuple[str, ...]:
    if raw is None:
        return ()
    if isinstance(raw, dict):
        return tuple(_override(str(k), v) for k, v in raw.items())
    if isinstance(raw, list) and all(isinstance(x, str) for x in raw):
        return tuple(raw)
    raise InputError("set", "must be a mapping {dotted.key: value} or a list of 'dotted.key=value' strings", source)


def _parse_axes(raw: Any, mode: str, source: str) -> dict[str, list]:
    if raw is None:
        return {}
    if not isinstance(raw, dict):
        raise InputError("axes", "must be a mapping {dotted.key: [value, ...]}", source)
    axes: dict[str, list] = {}
    for key, values in raw.items():
        key = str(key)
        if not key or any(not part for part in key.split(".")):
            raise InputError(f"axes.{key}", "an axis key must be a dotted scene path such as mesh.cell_size_m", source)
        if not isinstance(values, list) or not values:
            raise InputError(f"axes.{key}", f"must be a non-empty list of values, got {values!r}", source)
        axes[key] = values
    if mode == "zip" and axes:
        lengths = {k: len(v) for k, v in axes.items()}
        if len(set(lengths.values())) > 1:
            text = ", ".join(f"{k}: {n}" for k, n in lengths.items())
            longest = max(lengths, key=lengths.get)
            raise InputError(f"axes.{longest}", f"mode zip needs lists of one length, got {text}", source)
    return axes


def _combinations(axes: dict[str, list], mode: str) -> list[list[tuple[str, Any]]]:
    keys = list(axes)
    if not keys:
        return [[]]
    rows = zip(*axes.values()) if mode == "zip" else itertools.product(*axes.values())
    return [list(zip(keys, row)) for row in rows]


def _resolved_value(scene_dict: dict, key: str, raw: Any) -> Any:
    """The value at a dotted key of the resolved scene (typed as the scene holds it: YAML's
    `1.0e7` is a string, the scene's float is a float); the raw value where the key does not
    survive resolution (e.g. `debris.0.layout`, expanded into bodies)."""
    node: Any = scene_dict
    for part in key.split("."):
        if isinstance(node, dict) and part in node:
            node = node[part]
        elif isinstance(node, list) and part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node):
            node = node[int(part)]
        else:
            return raw
    return node


def load_sweep(path: str | Path) -> Sweep:
    """Read a sweep file, expand every member and validate it (scene and plan).

    Raises InputError naming the sweep file and the field for a bad sweep file, and
    SweepMemberError (an InputError) naming the member and the field for a bad member.
    Nothing is written.
    """
    from orchestrator.plan.planner import plan_case
    from orchestrator.scene.schema import load_scene, scene_to_dict

    path = Path(path)
    source = str(path)
    data = _read_mapping(path)
    unknown = [k for k in data if k not in _SWEEP_KEYS]
    if unknown:
        raise InputError(str(unknown[0]), f"unknown key (known: {', '.join(_SWEEP_KEYS)})", source)
    name = data.get("name", path.stem)
    if not isinstance(name, str) or not _NAME_RE.match(name):
        raise InputError("name", f"must be a folder name (letters, digits, . _ -), got {name!r}", source)
    mode = data.get("mode", "grid")
    if mode not in _MODES:
        raise InputError("mode", f"must be grid or zip, got {mode!r}", source)

    if ("base" in data) == ("scenes" in data):
        raise InputError("base", "give exactly one of base (a scene file) and scenes (a list of scene files)", source)
    raw_bases = [data["base"]] if "base" in data else data["scenes"]
    field_name = "base" if "base" in data else "scenes"
    if not isinstance(raw_bases, list) or not raw_bases or not all(isinstance(b, str) and b for b in raw_bases):
        raise InputError(field_name, "must be a scene file path (base) or a non-empty list of them (scenes)", source)
    bases = tuple(Path(os.path.normpath(path.parent / b)) for b in raw_bases)
    stems = [b.stem for b in bases]
    if len(set(stems)) != len(stems):
        raise InputError("scenes", f"scene files need distinct names (the store's `scene` column), got {stems}", source)

    common = _parse_set(data.get("set"), source)
    axes = _parse_axes(data.get("axes"), mode, source)
    if "scene" in axes and len(bases) > 1:
        raise InputError("axes.scene", "`scene` is the column of the scenes list; it cannot be an axis too", source)
    kind, workers, scheduler = _parse_executor(data.get("executor"), source)
    cores = _positive_int(data.get("cores_per_member"), "cores_per_member", source)

    combos = [(base, combo) for base in bases for combo in _combinations(axes, mode)]
    members: list[Member] = []
    seen: dict[str, int] = {}
    for index, (base, combo) in enumerate(combos, start=1):
        axis_overrides = tuple(_override(k, v) for k, v in combo)
        params: dict[str, Any] = ({"scene": base.stem} if len(bases) > 1 else {}) | dict(combo)
        label = ", ".join(([f"scene={base.stem}"] if len(bases) > 1 else []) + list(axis_overrides))
        try:
            scene = load_scene(base, [*common, *axis_overrides])
            plan = plan_case(scene)
        except SweepMemberError:
            raise
        except InputError as err:
            raise SweepMemberError(source, index, len(combos), label, err) from None
        except (DebrisfoamError, ValueError) as err:  # the planner refused the scene
            raise SweepMemberError(source, index, len(combos), label,
                                   InputError("plan", f"the planner cannot model it: {err}", str(base))) from None
        resolved = scene_to_dict(scene)
        params = {k: (_resolved_value(resolved, k, v) if k != "scene" else v) for k, v in params.items()}
        mid = member_id(scene)
        if mid in seen:
            first = members[seen[mid] - 1]
            raise SweepMemberError(source, index, len(combos), label, InputError(
                "axes", f"resolves to the same scene as member {first.index} ({first.label or 'the base scene'}); "
                        "every member must differ"))
        seen[mid] = index
        members.append(Member(index, mid, base, (*common, *axis_overrides), axis_overrides, params, scene, plan))
    return Sweep(name=name, description=str(data.get("description", "")), path=path, mode=mode, bases=bases,
                 set=common, axes=axes, members=tuple(members), executor=kind, workers=workers,
                 scheduler=scheduler, cores_per_member=cores)


# --------------------------------------------------------------------------- member state on disk


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


def _read_json(path: Path) -> dict | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _write_json(path: Path, data: dict) -> None:
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(json.dumps(data, indent=2, default=json_default))
    os.replace(tmp, path)


def member_state(case_dir: str | Path) -> str:
    """What a member's folder holds: "pending" (nothing yet), "finished", "failed" or
    "incomplete" (started and stopped or interrupted: the next run resumes it)."""
    case = Path(case_dir)
    if not case.is_dir() or not any(case.iterdir()):
        return "pending"
    record = _read_json(case / MEMBER_JSON) or {}
    if record.get("status") == "failed":
        return "failed"
    summary = _read_json(case / "results" / "summary.json") or {}
    run = _read_json(case / "run.json") or {}
    if summary.get("status") == "finished" and run.get("status") == "finished":
        return "finished"
    if record.get("status") == "interrupted":  # even if a step the stop killed left run.json "failed"
        return "incomplete"
    if run.get("status") in ("diverged", "stalled", "failed"):
        return "failed"
    return "incomplete"


def _slug(text: str) -> str:
    text = re.sub(r"\(.*?\)", "", text)
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def _peak_signed(path: Path, column: str) -> float | None:
    """The value of largest magnitude in one column of a results CSV (None when absent)."""
    import numpy as np
    import pandas as pd

    try:
        values = pd.read_csv(path, usecols=[column])[column].to_numpy(float)
    except (OSError, ValueError, KeyError):
        return None
    values = values[np.isfinite(values)]
    return float(values[np.argmax(np.abs(values))]) if values.size else None


def member_metrics(case_dir: str | Path) -> dict[str, Any]:
    """The store's figures for one member, from its results/summary.json (post's headline),
    results/column_forces.csv and, for a run that did not finish, run.json."""
    case = Path(case_dir)
    h = _read_json(case / "results" / "summary.json") or {}
    run = _read_json(case / "run.json") or {}
    cells = run.get("cells") or {}
    wall = h.get("wall_time_s") or {}
    out: dict[str, Any] = {
        "run_status": run.get("status") or h.get("status"),
        "cells": h.get("cells") or cells.get("total") or cells.get("planned"),
        "time_steps": h.get("time_steps", run.get("time_steps")),
        "end_time_s": h.get("end_time_s", run.get("end_time_s")),
        "reached_time_s": h.get("reached_time_s", run.get("reached_time_s")),
        "solver_wall_s": wall.get("solver_s"),
        "mesh_wall_s": wall.get("mesh_s"),
    }
    segments = run.get("segments") or []
    if out["solver_wall_s"] is None and segments:
        out["solver_wall_s"] = round(sum(float(s.get("wall_s", 0.0)) for s in segments), 3)
    if out["reached_time_s"] is None and segments:  # a run stopped early: where its last segment got
        try:
            out["reached_time_s"] = float(segments[-1]["end_time"])
        except (KeyError, TypeError, ValueError):
            pass
    diagnosis = run.get("diagnosis") or {}
    if diagnosis:
        out["diagnosis"] = f"{diagnosis.get('kind')}: {diagnosis.get('cause')} at t = {diagnosis.get('time_s')} s"
    for gauge, g in (h.get("gauges") or {}).items():
        out[f"{gauge}_arrival_s"] = g.get("arrival_s")
        out[f"{gauge}_peak_elevation_m"] = g.get("peak_elevation_m")
    for gauge, errors in ((h.get("comparisons") or {}).get("arrival_errors_s") or {}).items():
        for ref, err in errors.items():
            out[f"{gauge}_arrival_error_{_slug(ref)}_s"] = err
    if h.get("hydro_force"):
        out["peak_hydro_force_x_N"] = h["hydro_force"].get("peak_x_N")
    if h:
        out["peak_column_force_x_N"] = _peak_signed(case / "results" / "column_forces.csv", "total_force_x_N")
    impacts = h.get("impacts") or {}
    if impacts:
        out["impacts"] = impacts.get("count")
        out["impacts_on_column"] = impacts.get("on_column")
        out["peak_impact_force_N"] = impacts.get("peak_force_N")
        first = impacts.get("first") or {}
        if first:
            out["first_impact_time_s"] = first.get("time_s")
            out["first_impact_body"] = first.get("body")
            out["first_impact_other"] = first.get("other")
            out["impact_velocity_m_s"] = first.get("impact_velocity_m_s")
            out["first_impact_peak_force_N"] = first.get("peak_force_N")
            out["impact_duration_s"] = first.get("duration_s")
            out["impact_impulse_Ns"] = first.get("impulse_Ns")
    balance = h.get("water_balance") or {}
    if balance:
        out["water_balance_error"] = balance.get("max_error")
    response = h.get("column_response") or {}
    if response:
        out["peak_base_shear_N"] = response.get("peak_base_shear_N")
        out["peak_impact_base_shear_N"] = response.get("peak_impact_base_shear_N")
    return out


# --------------------------------------------------------------------------- one member (runs on a worker)


def _stop_flag(stop: Any) -> tuple[threading.Event, Callable[[], None]]:
    """A threading.Event for run_case from the sweep's stop handle: a threading.Event
    (local executor) as it is; a distributed.Event (dask) bridged by a watcher thread."""
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


def run_member(task: dict[str, Any], stop: Any = None) -> dict[str, Any]:
    """Render (once), run (resuming) and post-process one member; never raises for a
    member that fails: returns its outcome (status, error, wall time, metrics).

    task: id, index, label, scene_file, case_dir, np, token, record (written to member.json).
    stop: a threading.Event or a distributed.Event; when set the run stops cleanly
    (status "interrupted", resumable), and a member that has not started does not start.
    """
    from orchestrator.pipeline import prepare_case, run_full_case
    from orchestrator.run.runner import RunInterrupted

    case = Path(task["case_dir"])
    flag, release = _stop_flag(stop)
    base = {"id": task["id"], "index": task["index"], "case_dir": str(case), "host": socket.gethostname()}
    try:
        if flag.is_set():
            return {**base, "status": "not started", "error": None, "wall_time_s": None, "metrics": {}}
        t0 = time.perf_counter()
        record = {**task.get("record", {}), "id": task["id"], "status": "running", "started": _now(),
                  "host": base["host"], "pid": os.getpid(), "token": task.get("token")}
        error, ours = None, False
        try:
            prepare_case(task["scene_file"], case)
            _write_json(case / MEMBER_JSON, record)
            ours = True
            run_full_case(task["scene_file"], case, (), np=task.get("np"), quiet=True, stop_event=flag)
            status = "finished"
        except RunInterrupted as exc:
            status, error = "interrupted", str(exc)
        except Exception as exc:  # any failure is this member's only: record it, go on
            # a step killed by the Ctrl-C that stops the sweep is an interruption, not a failure
            status = "interrupted" if flag.is_set() else "failed"
            error = str(exc) if isinstance(exc, DebrisfoamError) else f"{type(exc).__name__}: {exc}"
        wall = round(time.perf_counter() - t0, 2)
        record.update({"status": status, "error": error, "finished": _now(), "wall_time_s": wall})
        metrics = {}
        if ours:  # never write into (or read) a folder that holds another case
            _write_json(case / MEMBER_JSON, record)
            metrics = member_metrics(case)
        return {**base, "status": status, "error": error, "wall_time_s": wall, "started": record["started"],
                "finished": record["finished"], "metrics": metrics}
    finally:
        release()


# --------------------------------------------------------------------------- the results store


def _cell(value: Any) -> Any:
    """A store cell: numbers, strings and NULL as they are; lists and mappings as JSON."""
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value, default=json_default)
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _write_store(out: Path, rows: list[dict[str, Any]]) -> Path:
    """Rewrite results.sqlite (atomically: a reader sees the old or the new table)."""
    import pandas as pd

    columns: list[str] = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    frame = pd.DataFrame([{c: _cell(row.get(c)) for c in columns} for row in rows], columns=columns)
    path = out / STORE_FILE
    tmp = out / f".{STORE_FILE}.tmp"
    tmp.unlink(missing_ok=True)
    with contextlib.closing(sqlite3.connect(tmp)) as con:
        frame.to_sql(STORE_TABLE, con, index=False)
        con.commit()
    os.replace(tmp, path)
    return path


def load_store(sweep_dir: str | Path):
    """The results store of a sweep folder as a pandas DataFrame (one row per member)."""
    import pandas as pd

    path = Path(sweep_dir) / STORE_FILE
    if not path.is_file():
        raise InputError("sweep_dir", f"no results store {path}: run the sweep first", str(sweep_dir))
    with contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as con:
        return pd.read_sql_query(f"SELECT * FROM {STORE_TABLE}", con)


def _row(sweep: Sweep, member: Member, out: Path, status: str, outcome: dict | None = None,
         record: dict | None = None, metrics: dict | None = None) -> dict[str, Any]:
    record = record or {}
    outcome = outcome or {}
    row: dict[str, Any] = {"member": member.index, "member_id": member.id, "status": status}
    for key in sweep.parameters:
        row[key] = member.params.get(key)
    row.update({
        "overrides": " ".join(member.axis_overrides),
        "solver": member.plan.solver,
        "cores": sweep.member_cores(member),
        "planned_cells": member.plan.cell_count,
        "estimated_wall_time_s": round(member.estimated_wall_time_s, 1),
        "wall_time_s": outcome.get("wall_time_s", record.get("wall_time_s")),
        "started": outcome.get("started", record.get("started")),
        "finished": outcome.get("finished", record.get("finished")),
    })
    row.update(metrics if metrics is not None else outcome.get("metrics", {}))
    row["error"] = outcome.get("error", record.get("error"))
    row["case_dir"] = str(out / member.id)
    return row


def _row_from_disk(sweep: Sweep, member: Member, out: Path, status: str) -> dict[str, Any]:
    case = out / member.id
    record = _read_json(case / MEMBER_JSON) or {}
    if status == "failed" and not record.get("error"):
        run = _read_json(case / "run.json") or {}
        record = {**record, "error": run.get("error") or (run.get("diagnosis") or {}).get("cause")}
    if status == "finished" and record.get("wall_time_s") is None:  # run outside the sweep
        summary = _read_json(case / "results" / "summary.json") or {}
        record = {**record, "wall_time_s": (summary.get("wall_time_s") or {}).get("total_s")}
    metrics = member_metrics(case) if (case / "run.json").is_file() else {}
    return _row(sweep, member, out, status, record=record, metrics=metrics)


# --------------------------------------------------------------------------- executors


@dataclass
class _Executor:
    """What the sweep needs of an executor: submit, completions as they come, a stop handle."""

    submit: Callable[..., Any]
    as_completed: Callable[[Iterable[Any]], Iterator[Any]]
    stop: Any
    describe: str


def _default_slots(cores_per_member: int) -> int:
    return max(1, (os.cpu_count() or 1) // max(1, cores_per_member))


@contextlib.contextmanager
def _local_executor(slots: int) -> Iterator[_Executor]:
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=slots, thread_name_prefix="debrisfoam-member")
    try:
        yield _Executor(lambda fn, *args, key: pool.submit(fn, *args),
                        concurrent.futures.as_completed, threading.Event(),
                        f"local, {slots} member(s) at a time")
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


@contextlib.contextmanager
def _signal_handlers(handlers: dict[int, Any]) -> Iterator[None]:
    """`handlers` (signal -> handler) installed for the block, the previous ones restored
    after it; outside the main thread, where Python cannot set handlers, signals are left alone.

    The sweep uses it twice: SIGINT ignored while Dask's worker processes are spawned (they
    inherit it, so a Ctrl-C at the terminal, sent to the whole process group, reaches only the
    parent, which then stops the running members cleanly instead of their workers dying under
    them); and SIGTERM (`kill`, a batch system's stop) and SIGINT raising KeyboardInterrupt
    while the members run, so the sweep stops them cleanly either way, SIGINT too when the
    shell started the sweep with it ignored (`nohup ... &`).
    """
    try:
        previous = {sig: signal.signal(sig, handler) for sig, handler in handlers.items()}
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def _dask_executor(slots: int, scheduler: str | None, cluster_kwargs: dict | None) -> Iterator[_Executor]:
    from distributed import Client, Event, LocalCluster, as_completed

    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as err:
            raise DebrisfoamError(f"cannot reach the Dask scheduler at {scheduler}: {err}") from None
        describe = f"dask scheduler {scheduler}"
    else:
        options = {"n_workers": slots, "threads_per_worker": 1, "processes": True, "dashboard_address": None,
                   "memory_limit": 0, "silence_logs": logging.ERROR}
        options.update(cluster_kwargs or {})
        # Ctrl-C is the parent's: it stops the members through `stop`
        with _signal_handlers({signal.SIGINT: signal.SIG_IGN}):
            cluster = LocalCluster(**options)
        client = Client(cluster)
        describe = f"dask LocalCluster, {options['n_workers']} worker(s)"
    stop = None
    try:
        stop = Event(f"debrisfoam-sweep-stop-{uuid.uuid4().hex}", client=client)
        yield _Executor(lambda fn, *args, key: client.submit(fn, *args, key=key, pure=False),
                        as_completed, stop, describe)
    finally:
        _close_dask(client, cluster, stop)


class _DropCancelled(logging.Filter):
    """Drops log records that carry an asyncio.CancelledError (what a scheduler's close does
    to the requests still pending on it); every other record passes."""

    def filter(self, record: logging.LogRecord) -> bool:
        exc = record.exc_info[1] if record.exc_info else None
        return not isinstance(exc, asyncio.CancelledError)


# the loggers that report a request cancelled by the scheduler's or a worker's close
_SHUTDOWN_LOGGERS = ("distributed.event", "distributed.core", "distributed.utils", "distributed.worker",
                     "distributed.scheduler", "distributed.client")


def _close_dask(client: Any, cluster: Any, stop: Any) -> None:
    """Shut a sweep's Dask executor down in order: the stop event, the client, the cluster.

    Every member's stop bridge (:func:`_stop_flag`) keeps a one-second Event.wait open on the
    scheduler until it notices its member has returned; a scheduler closed under such a wait
    cancels it, and distributed logs that as an ERROR with an asyncio.CancelledError
    traceback, on a sweep whose members all finished. So the stop event is set first (its
    members are done, or stopping because the sweep is ending anyway): the pending waits
    return, and the bridges end. Then the client closes, then the cluster (ours only: an
    existing scheduler is left running). A CancelledError that still reaches the log during
    these closes (a wait sent just before the set) is dropped; errors at any other time, and
    other errors, are logged as ever.
    """
    if stop is not None:
        with contextlib.suppress(Exception):
            stop.set()
    quiet = _DropCancelled()
    loggers = [logging.getLogger(name) for name in _SHUTDOWN_LOGGERS]
    for logger in loggers:
        logger.addFilter(quiet)
    try:
        with contextlib.suppress(asyncio.CancelledError):
            client.close()
        if cluster is not None:
            with contextlib.suppress(asyncio.CancelledError):
                cluster.close()
    finally:
        for logger in loggers:
            logger.removeFilter(quiet)


def _open_executor(kind: str, slots: int, scheduler: str | None, cluster_kwargs: dict | None):
    if kind == "dask":
        return _dask_executor(slots, scheduler, cluster_kwargs)
    return _local_executor(slots)


class _StartWatcher:
    """Tells the parent when members start: each writes member.json (status running, this
    sweep's token) in its case folder when its run begins; this thread looks for them."""

    def __init__(self, members: dict[str, Member], out: Path, token: str, say: Callable[[Member], None]):
        self.waiting = dict(members)
        self.out, self.token, self.say = out, token, say
        self.done = threading.Event()
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self._loop, name="debrisfoam-sweep-watch", daemon=True)
        self.thread.start()

    def _loop(self) -> None:
        while not self.done.wait(_WATCH_INTERVAL_S):
            self.poll()

    def poll(self) -> None:
        with self.lock:
            for mid, member in list(self.waiting.items()):
                record = _read_json(self.out / mid / MEMBER_JSON)
                if record and record.get("token") == self.token:
                    del self.waiting[mid]
                    self.say(member)

    def forget(self, mid: str) -> None:
        with self.lock:
            self.waiting.pop(mid, None)

    def close(self) -> None:
        self.done.set()
        self.thread.join()


# --------------------------------------------------------------------------- running a sweep


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


def _manifest(sweep: Sweep, out: Path) -> None:
    """sweep.json and scenes/<id>.yaml: the expanded sweep, written before anything runs."""
    from orchestrator.scene.schema import dump_scene_yaml

    scenes = out / SCENES_DIR
    scenes.mkdir(parents=True, exist_ok=True)
    for m in sweep.members:
        path = scenes / f"{m.id}.yaml"
        text = (f"# Member {m.id} of sweep {sweep.name} ({sweep.path}): base {m.base}\n"
                + dump_scene_yaml(m.scene, list(m.overrides)))
        if not path.is_file() or path.read_text() != text:
            path.write_text(text)
    _write_json(out / SWEEP_JSON, {
        "name": sweep.name, "description": sweep.description, "sweep_file": str(sweep.path), "mode": sweep.mode,
        "bases": [str(b) for b in sweep.bases], "set": list(sweep.set), "axes": sweep.axes,
        "parameters": sweep.parameters, "cores_per_member": sweep.cores_per_member, "written": _now(),
        "members": [{"member": m.index, "id": m.id, "base": str(m.base), "params": m.params,
                     "overrides": list(m.overrides), "scene": f"{SCENES_DIR}/{m.id}.yaml"} for m in sweep.members],
    })


def _first_line(text: str | None) -> str:
    return (text or "").strip().splitlines()[0] if text and text.strip() else ""


def _resolve_executor(sweep: Sweep, executor: str | None, scheduler: str | None,
                      workers: int | None) -> tuple[str, str | None, int | None]:
    kind = executor or ("dask" if scheduler else None) or sweep.executor or ("dask" if sweep.scheduler else "local")
    if kind not in _EXECUTORS:
        raise InputError("--executor", f"must be one of {', '.join(_EXECUTORS)}, got {kind!r}")
    scheduler = scheduler or sweep.scheduler
    if scheduler and kind != "dask":
        raise InputError("--scheduler", "a scheduler address needs the dask executor (--executor dask)")
    if workers is not None and workers < 1:
        raise InputError("--workers", f"must be >= 1, got {workers}")
    return kind, scheduler, workers or sweep.workers


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
    kind, scheduler, slots = _resolve_executor(sw, executor, scheduler, workers)
    out = Path(out_dir) if out_dir is not None else default_sweep_dir(sw)
    out = out.resolve()
    out.mkdir(parents=True, exist_ok=True)
    _manifest(sw, out)
    lock = threading.Lock()

    def say(text: str) -> None:
        if progress is not None:
            with lock:
                progress(text)

    n = len(sw.members)
    tag = {m.id: f"[{m.index}/{n}] {m.id} {m.label or '(base scene)'}" for m in sw.members}
    rows: dict[str, dict[str, Any]] = {}
    todo: list[Member] = []
    result = SweepResult(sw, out, out / STORE_FILE, [])
    for m in sw.members:
        state = member_state(out / m.id)
        if state == "finished" or (state == "failed" and not retry_failed):
            rows[m.id] = _row_from_disk(sw, m, out, state)
            result.skipped.append(m.id)
            if state == "finished":
                wall = rows[m.id].get("wall_time_s")
                say(f"{tag[m.id]}: finished earlier{f' ({wall:.1f} s)' if wall is not None else ''}; skipped")
            else:
                say(f"{tag[m.id]}: failed earlier ({_first_line(rows[m.id].get('error'))}); "
                    "skipped (--retry-failed runs it again)")
        else:
            rows[m.id] = _row(sw, m, out, "pending" if state == "pending" else "incomplete")
            todo.append(m)

    def store() -> None:
        result.rows = [rows[m.id] for m in sw.members]
        _write_store(out, result.rows)

    store()
    if not todo:
        say(f"sweep {sw.name}: nothing to run ({len(result.finished)} finished, {len(result.failed)} failed)")
        return result

    cores = max(sw.member_cores(m) for m in todo)
    slots = slots or _default_slots(cores)
    token = uuid.uuid4().hex
    by_id = {m.id: m for m in todo}
    with _open_executor(kind, slots, scheduler, cluster_kwargs) as ex:
        say(f"sweep {sw.name}: {len(todo)} of {n} member(s) to run on {ex.describe} -> {out}")
        def started(m: Member) -> None:
            say(f"{tag[m.id]}: {'resumed' if rows[m.id]['status'] == 'incomplete' else 'started'}")

        watcher = _StartWatcher(by_id, out, token, started)
        futures = {}
        for m in todo:
            task = {"id": m.id, "index": m.index, "label": m.label, "token": token,
                    "scene_file": str(out / SCENES_DIR / f"{m.id}.yaml"), "case_dir": str(out / m.id),
                    "np": sw.cores_per_member,
                    "record": {"sweep": sw.name, "sweep_file": str(sw.path), "member": m.index,
                               "base": str(m.base), "overrides": list(m.overrides), "params": m.params}}
            futures[ex.submit(run_member, task, ex.stop, key=f"debrisfoam-member-{m.id}-{token[:8]}")] = m

        def handle(fut) -> None:
            m = futures.pop(fut)
            try:
                outcome = fut.result()
            except BaseException as exc:  # the task itself died (a killed worker, a cancelled future)
                if isinstance(exc, KeyboardInterrupt):
                    raise
                outcome = {"status": "failed", "error": f"{type(exc).__name__}: {exc}".strip(": "),
                           "wall_time_s": None, "metrics": {}}
            watcher.poll()
            watcher.forget(m.id)
            status = outcome["status"]
            if status == "not started":  # its row stays pending (or incomplete)
                say(f"{tag[m.id]}: not started (stopping)")
                return
            rows[m.id] = _row(sw, m, out, status, outcome=outcome)
            result.ran.append(m.id)
            store()
            wall = outcome.get("wall_time_s")
            took = f" in {wall:.1f} s" if wall is not None else ""
            if status == "finished":
                mt = outcome.get("metrics", {})
                say(f"{tag[m.id]}: finished{took} ({mt.get('cells')} cells, {mt.get('time_steps')} time steps)")
            elif status == "interrupted":
                say(f"{tag[m.id]}: interrupted{took}; run the sweep again to resume it")
            else:
                say(f"{tag[m.id]}: failed{took}: {outcome.get('error')}")

        caught: list[int] = []

        def interrupt(signum, frame) -> None:  # noqa: ARG001 - signal API
            caught.append(signum)
            raise KeyboardInterrupt

        try:
            try:
                with _signal_handlers({signal.SIGTERM: interrupt, signal.SIGINT: interrupt}):
                    for fut in ex.as_completed(list(futures)):
                        handle(fut)
            except KeyboardInterrupt:
                result.interrupted = True
                result.signum = caught[0] if caught else signal.SIGINT
                say("interrupted: stopping the running members cleanly (run the sweep again to resume)")
                with contextlib.suppress(Exception):
                    ex.stop.set()
                for fut in ex.as_completed(list(futures)):
                    handle(fut)
        finally:
            watcher.close()
            store()
    done = len(result.finished)
    say(f"sweep {sw.name}: {done} of {n} finished, {len(result.failed)} failed; store {result.store}")
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
    kind, scheduler, slots = _resolve_executor(sw, executor, scheduler, workers)
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
    slots = slots or _default_slots(max((r["cores"] for r in members), default=1))
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
