"""The sweep folder's records: each member's state and figures, and the results store.

A sweep folder (default ``runs/sweeps/<name>``) holds::

    sweep.json                   the expanded sweep: every member's id, parameters, overrides
    scenes/<id>.yaml             every member's resolved scene (what its case is rendered from)
    <id>/                        the member's case (orchestrator.pipeline.run_full_case):
                                 scene.yaml, plan.json, run.json, logs, results/ ...
    <id>/member.json             the member's status, error, wall time, parameters
    results.sqlite               the results store: table `members`, one row per member

The store is rewritten whole after every member (:func:`write_store`), atomically, so a crash
loses nothing and a reader never sees half a table; :func:`load_store` reads it back as a
pandas DataFrame. What a member's folder holds (:func:`member_state`) decides whether a
re-run skips, resumes or retries it.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import math
import re
import sqlite3
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.case.folder import CaseFolder
from orchestrator.case.run_state import RunState
from orchestrator.core.files import read_json_object, write_bytes_atomic, write_json_atomic, write_text_atomic
from orchestrator.core.jsonio import json_default
from orchestrator.scene.scenefile import dump_scene_yaml
from orchestrator.studies.sweep.spec import Member, Sweep

#: The results store (SQLite: pandas + the standard library, no extra dependency).
STORE_FILE = "results.sqlite"
STORE_TABLE = "members"
#: The sweep's record in each member's case folder.
MEMBER_JSON = "member.json"
SWEEP_JSON = "sweep.json"
SCENES_DIR = "scenes"


def timestamp() -> str:
    """Now, in local time with its offset, to the second (the records' started / finished)."""
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


def read_member_record(case_dir: str | Path) -> dict | None:
    """The member's member.json, or None when it is missing or unreadable."""
    return read_json_object(Path(case_dir) / MEMBER_JSON)


def write_member_record(case_dir: str | Path, record: dict[str, Any]) -> Path:
    return write_json_atomic(Path(case_dir) / MEMBER_JSON, record)


def member_dirs(sweep_dir: str | Path, holding: str) -> list[Path]:
    """The member folders of a sweep that hold ``holding`` (a path inside a member, such as
    ``results/gauges.csv``), in the sweep's order.

    With a sweep.json, only the members it lists: a folder left by an earlier version of the sweep
    file (its scene, and so its id, since changed) is not one of this sweep's members. Without one,
    every such folder, by name.
    """
    sweep = Path(sweep_dir)
    found = {p.relative_to(sweep).parts[0]: sweep / p.relative_to(sweep).parts[0] for p in sweep.glob(f"*/{holding}")}
    manifest = read_json_object(sweep / SWEEP_JSON)
    if manifest is None:
        return [found[k] for k in sorted(found)]
    ids = [str(m.get("id")) for m in manifest.get("members") or [] if isinstance(m, dict)]
    return [found[i] for i in ids if i in found]


def write_manifest(sweep: Sweep, out: Path) -> None:
    """sweep.json and scenes/<id>.yaml: the expanded sweep, written before anything runs."""
    scenes = out / SCENES_DIR
    scenes.mkdir(parents=True, exist_ok=True)
    for m in sweep.members:
        path = scenes / f"{m.id}.yaml"
        text = (f"# Member {m.id} of sweep {sweep.name} ({sweep.path}): base {m.base}\n"
                + dump_scene_yaml(m.scene, list(m.overrides)))
        if not path.is_file() or path.read_text() != text:
            write_text_atomic(path, text)
    write_json_atomic(out / SWEEP_JSON, {
        "name": sweep.name, "description": sweep.description, "sweep_file": str(sweep.path), "mode": sweep.mode,
        "bases": [str(b) for b in sweep.bases], "set": list(sweep.set), "axes": sweep.axes,
        "parameters": sweep.parameters, "cores_per_member": sweep.cores_per_member, "written": timestamp(),
        "members": [{"member": m.index, "id": m.id, "base": str(m.base), "params": m.params,
                     "overrides": list(m.overrides), "scene": f"{SCENES_DIR}/{m.id}.yaml"} for m in sweep.members],
    })


# --------------------------------------------------------------------------- one member's folder


def member_state(case_dir: str | Path) -> str:
    """What a member's folder holds: "pending" (nothing yet), "finished", "failed" or
    "incomplete" (started and stopped or interrupted: the next run resumes it)."""
    case = Path(case_dir)
    if not case.is_dir() or not any(case.iterdir()):
        return "pending"
    record = read_member_record(case) or {}
    if record.get("status") == "failed":
        return "failed"
    folder = CaseFolder(case)
    summary = folder.summary() or {}
    run = folder.run_state()
    if summary.get("status") == "finished" and run.finished:
        return "finished"
    if record.get("status") == "interrupted":  # even if a step the stop killed left run.json "failed"
        return "incomplete"
    if run.status in ("diverged", "stalled", "failed"):
        return "failed"
    return "incomplete"


def _slug(text: str) -> str:
    text = re.sub(r"\(.*?\)", "", text)
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def _peak_signed(path: Path, column: str) -> float | None:
    """The value of largest magnitude in one column of a results CSV (None when absent)."""
    try:
        values = pd.read_csv(path, usecols=[column])[column].to_numpy(float)
    except (OSError, ValueError, KeyError):
        return None
    values = values[np.isfinite(values)]
    return float(values[np.argmax(np.abs(values))]) if values.size else None


def _run_metrics(h: dict, run: RunState) -> dict[str, Any]:
    """Size, times and how far the run got: from the headline, else from run.json."""
    cells = run.cells
    wall = h.get("wall_time_s") or {}
    out: dict[str, Any] = {
        "run_status": run.status or h.get("status"),
        "cells": h.get("cells") or cells.get("total") or cells.get("planned"),
        "time_steps": h.get("time_steps", run.time_steps),
        "end_time_s": h.get("end_time_s", run.end_time_s),
        "reached_time_s": h.get("reached_time_s", run.reached_time_s),
        "solver_wall_s": wall.get("solver_s"),
        "mesh_wall_s": wall.get("mesh_s"),
    }
    segments = run.segments
    if out["solver_wall_s"] is None and segments:
        out["solver_wall_s"] = round(sum(float(s.get("wall_s", 0.0)) for s in segments), 3)
    if out["reached_time_s"] is None and segments:  # a run stopped early: where its last segment got
        try:
            out["reached_time_s"] = float(segments[-1]["end_time"])
        except (KeyError, TypeError, ValueError):
            pass
    diagnosis = run.diagnosis
    if diagnosis:
        out["diagnosis"] = f"{diagnosis.get('kind')}: {diagnosis.get('cause')} at t = {diagnosis.get('time_s')} s"
    return out


def _impact_metrics(impacts: dict) -> dict[str, Any]:
    out = {"impacts": impacts.get("count"), "impacts_on_column": impacts.get("on_column"),
           "peak_impact_force_N": impacts.get("peak_force_N")}
    first = impacts.get("first") or {}
    if first:
        out.update({
            "first_impact_time_s": first.get("time_s"), "first_impact_body": first.get("body"),
            "first_impact_other": first.get("other"), "impact_velocity_m_s": first.get("impact_velocity_m_s"),
            "first_impact_peak_force_N": first.get("peak_force_N"), "impact_duration_s": first.get("duration_s"),
            "impact_impulse_Ns": first.get("impulse_Ns"),
        })
    return out


def member_metrics(case_dir: str | Path) -> dict[str, Any]:
    """The store's figures for one member, from its results/summary.json (post's headline),
    results/column_forces.csv and, for a run that did not finish, run.json."""
    folder = CaseFolder(case_dir)
    h = folder.summary() or {}
    out = _run_metrics(h, folder.run_state())
    for gauge, g in (h.get("gauges") or {}).items():
        out[f"{gauge}_arrival_s"] = g.get("arrival_s")
        out[f"{gauge}_peak_elevation_m"] = g.get("peak_elevation_m")
    for gauge, errors in ((h.get("comparisons") or {}).get("arrival_errors_s") or {}).items():
        for ref, err in errors.items():
            out[f"{gauge}_arrival_error_{_slug(ref)}_s"] = err
    if h.get("hydro_force"):
        out["peak_hydro_force_x_N"] = h["hydro_force"].get("peak_x_N")
    if h:
        out["peak_column_force_x_N"] = _peak_signed(folder.results_dir / "column_forces.csv", "total_force_x_N")
    impacts = h.get("impacts") or {}
    if impacts:
        out.update(_impact_metrics(impacts))
    balance = h.get("water_balance") or {}
    if balance:
        out["water_balance_error"] = balance.get("max_error")
    response = h.get("column_response") or {}
    if response:
        out["peak_base_shear_N"] = response.get("peak_base_shear_N")
        out["peak_impact_base_shear_N"] = response.get("peak_impact_base_shear_N")
    return out


# --------------------------------------------------------------------------- the store's rows


def member_row(sweep: Sweep, member: Member, out: Path, status: str, outcome: dict | None = None,
               record: dict | None = None, metrics: dict | None = None) -> dict[str, Any]:
    """The member's row of the store: its parameters and plan, then the run's outcome (from
    the worker's ``outcome``, else its member.json ``record``) and figures."""
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


def member_row_from_disk(sweep: Sweep, member: Member, out: Path, status: str) -> dict[str, Any]:
    """The row of a member run earlier (finished or failed), from what its folder holds."""
    folder = CaseFolder(out / member.id)
    record = read_member_record(folder.path) or {}
    if status == "failed" and not record.get("error"):
        run = folder.run_state()
        record = {**record, "error": run.error or run.diagnosis.get("cause")}
    if status == "finished" and record.get("wall_time_s") is None:  # run outside the sweep
        summary = folder.summary() or {}
        record = {**record, "wall_time_s": (summary.get("wall_time_s") or {}).get("total_s")}
    metrics = member_metrics(folder.path) if folder.run_path.is_file() else {}
    return member_row(sweep, member, out, status, record=record, metrics=metrics)


# --------------------------------------------------------------------------- the results store


def _cell(value: Any) -> Any:
    """A store cell: numbers, strings and NULL as they are; lists and mappings as JSON."""
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value, default=json_default)
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_store(out: Path, rows: list[dict[str, Any]]) -> Path:
    """Rewrite results.sqlite (atomically: a reader sees the old or the new table)."""
    columns: list[str] = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    frame = pd.DataFrame([{c: _cell(row.get(c)) for c in columns} for row in rows], columns=columns)
    with contextlib.closing(sqlite3.connect(":memory:")) as con:
        frame.to_sql(STORE_TABLE, con, index=False)
        con.commit()
        data = con.serialize()
    return write_bytes_atomic(Path(out) / STORE_FILE, data)


def load_store(sweep_dir: str | Path) -> pd.DataFrame:
    """The results store of a sweep folder as a pandas DataFrame (one row per member)."""
    path = Path(sweep_dir) / STORE_FILE
    if not path.is_file():
        raise InputError("sweep_dir", f"no results store {path}: run the sweep first", str(sweep_dir))
    with contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as con:
        try:
            return pd.read_sql_query(f"SELECT * FROM {STORE_TABLE}", con)
        except (sqlite3.Error, pd.errors.DatabaseError) as exc:
            raise InputError("sweep_dir", f"{path.name} is not a sweep's results store ({exc})", str(sweep_dir)) from None
