"""Numerical stability of runs: did each finish with sane physics, or stop with a diagnosis?

:func:`assess` looks at one run (a case folder, run by `debrisfoam run`, `case` or a sweep)
and answers, for the hard cases of cases/hard/:

* outcome: finished, or how it stopped (the runner's diagnosis: divergence, contact the
  runner could not resolve, a failed OpenFOAM step) and at what simulated time;
* water conserved: the largest relative error of the water balance over the run
  (:func:`orchestrator.case.outputs.read_water_balance`: the volume of water in the fluid mesh plus
  what left through the open boundaries, against the volume at the start), within
  :data:`MASS_TOLERANCE`;
* no body inside the column, a wall or another body: the smallest signed distance of every
  body (its box, at every solver step of bodies.csv) to each of them (negative: inside);
  a body may not be more than :data:`INSIDE_TOLERANCE_M` inside. How far a body sank into
  the bed is reported too (the runner lifts a body back onto the bed when it sinks);
* forces finite: the column's hydrodynamic force and every impact pulse.

:func:`stability_table` does this for every member of a sweep (``cases/sweeps/hard-cases.yaml``)
and :func:`markdown` writes the table of docs/stability.md (`debrisfoam report stability`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.case.folder import CaseFolder
from orchestrator.case.run_state import RunState
from orchestrator.case.outputs import (
    WATER_BALANCE_TOLERANCE,
    read_force_series,
    read_water_balance,
    water_balance_summary,
)
from orchestrator.contact.events import read_events
from orchestrator.contact.geometry import box_state, find_contacts, scene_obstacles
from orchestrator.core.numbers import finite_or_none
from orchestrator.plan.model import ModelPlan
from orchestrator.studies.sweep.store import load_store, read_member_record

__all__ = ["INSIDE_TOLERANCE_M", "MASS_TOLERANCE", "Assessment", "assess", "markdown", "stability_table"]

#: largest relative water-balance error of a sane run
MASS_TOLERANCE = WATER_BALANCE_TOLERANCE
#: deepest a body may be found inside the column, a wall or another body (m): the runner
#: acts on contacts at the end of a solver step, so a body can overlap by what it moves in
#: one step before it is put back; 2 mm is a few per cent of the container's 60 mm
INSIDE_TOLERANCE_M = 0.002


@dataclass
class Assessment:
    """One run's stability verdict and the figures behind it (lengths m, times s)."""

    case: str
    scene: str | None
    outcome: str                      # "finished", "diverged", "stalled", "contact", "failed", ...
    sane: bool | None                 # finished with every check passed; None when not finished
    reached_time_s: float | None
    end_time_s: float | None
    wall_time_s: float | None
    solver_wall_s: float | None
    cells: int | None
    time_steps: int | None
    water_error: float | None         # largest |relative water-balance error|, signed
    water_outflow_m3: float | None
    deepest_inside_m: float | None    # largest penetration into column / walls / bodies (m, >= 0)
    inside_what: str | None
    bed_sink_m: float | None          # deepest a body went below the bed (m, >= 0)
    min_clearance_m: float | None     # smallest distance to column / walls / bodies (m; < 0 inside)
    forces_finite: bool | None
    contacts: int = 0
    pinned: int = 0
    diagnosis: str = ""
    failed_checks: list[str] = field(default_factory=list)


def _clearances(case: Path, plan: ModelPlan | None, scene) -> tuple[float | None, str | None, float | None, float | None]:
    """(deepest penetration into column/walls/bodies, into what, deepest bed sink, min clearance)
    over every step of the run's bodies.csv, from the bodies' boxes."""
    tracks_path = case / "bodies.csv"
    if not plan or not plan.bodies or not tracks_path.is_file() or scene is None:
        return None, None, None, None
    # a restart repeats the step it starts from: keep the later report of each body and time
    tracks = pd.read_csv(tracks_path).drop_duplicates(["time_s", "body"], keep="last")
    if tracks.empty:
        return None, None, None, None
    bodies = {b.name: b for b in plan.bodies}
    obstacles = scene_obstacles(scene, plan)
    q_cols = [f"q_{a}{b}" for a in "xyz" for b in "xyz"]
    deepest, what, sink, clearance = 0.0, None, 0.0, math.inf
    for _, rows in tracks.groupby("time_s", sort=True):
        states = []
        for r in rows.itertuples(index=False):
            b = bodies.get(r.body)
            if b is None:
                continue
            rot = np.array([getattr(r, c) for c in q_cols], float).reshape(3, 3)
            states.append(box_state(r.body, (r.x_m, r.y_m, r.z_m), rot, (r.u_m_s, r.v_m_s, r.w_m_s), (0, 0, 0),
                                    b.size_m, b.mass_kg, b.moment_of_inertia_kg_m2))
            half = 0.5 * np.abs(rot) @ np.asarray(b.size_m, float)  # the box's half extent in z
            sink = max(sink, -(r.z_m - half[2] - obstacles.bed.point_m[2]))
        for c in find_contacts(states, obstacles, 1.0):
            clearance = min(clearance, c.distance_m)
            if -c.distance_m > deepest:
                deepest, what = -c.distance_m, f"{c.body} in {c.other}"
    return deepest, what, max(sink, 0.0), (clearance if math.isfinite(clearance) else None)


def _forces_finite(case: Path) -> bool | None:
    frame, _ = read_force_series(case)
    checks = []
    if frame is not None and not frame.empty:
        checks.append(bool(np.isfinite(frame.drop(columns="time").to_numpy(float)).all()))
    for e in read_events(case):
        if e.get("type") == "impact":
            checks.append(finite_or_none(e.get("peak_force_N")) is not None)
    return bool(all(checks)) if checks else None


def _outcome(run: RunState, member: dict | None) -> tuple[str, str]:
    """(outcome, diagnosis) from run.json and, in a sweep, the member's record."""
    if not run.recorded:
        error = (member or {}).get("error")
        return ("failed", error) if isinstance(error, str) and error else ("not run", "")
    status = run.status
    diagnosis = run.diagnosis
    error = next((e for e in ((member or {}).get("error"), run.error) if isinstance(e, str) and e), "")
    if status == "finished":
        return "finished", ""
    if status in ("diverged", "stalled"):
        return status, f"{diagnosis.get('cause')} at t = {diagnosis.get('time_s')} s ({diagnosis.get('log')})"
    if "inside" in error or "ContactError" in error or "pressed" in error or "contact" in error.lower():
        return "contact", error
    if status in ("failed", "interrupted"):
        return status, error
    return (status or "unknown"), error


def assess(case_dir: str | Path, member: dict | None = None) -> Assessment:
    """The stability verdict of the run in ``case_dir`` (see the module docstring).

    ``member``: the sweep's record of the run (its member.json), for errors raised outside
    run.json (a contact the runner could not resolve, a failed render).
    """
    case = Path(case_dir)
    if not case.is_dir():
        raise InputError("case_dir", "not a directory", str(case))
    folder = CaseFolder(case)
    run = folder.run_state()
    plan = folder.model_plan()
    scene = folder.scene() if folder.scene_path.is_file() else None
    outcome, diagnosis = _outcome(run, member)
    segments = run.segments
    reached = finite_or_none(segments[-1].get("end_time")) if segments else None
    balance = water_balance_summary(read_water_balance(case))
    deepest, what, sink, clearance = _clearances(case, plan, scene)
    events = read_events(case)
    summary = folder.summary() or {}
    wall = (member or {}).get("wall_time_s") or (summary.get("wall_time_s") or {}).get("total_s")
    a = Assessment(
        case=str(case),
        scene=scene.name if scene is not None else None,
        outcome=outcome,
        sane=None,
        reached_time_s=reached,
        end_time_s=run.end_time_s,
        wall_time_s=finite_or_none(wall),
        solver_wall_s=finite_or_none(sum(float(s.get("wall_s", 0.0)) for s in segments)) if segments else None,
        cells=run.cells.get("total"),
        time_steps=run.time_steps,
        water_error=balance["max_error"] if balance else None,
        water_outflow_m3=balance["outflow_m3"] if balance else None,
        deepest_inside_m=deepest,
        inside_what=what,
        bed_sink_m=float(sink) if sink is not None else None,
        min_clearance_m=clearance,
        forces_finite=_forces_finite(case),
        contacts=sum(1 for e in events if e.get("type") == "impact"),
        pinned=sum(1 for e in events if e.get("type") == "pinned"),
        diagnosis=diagnosis or "",
    )
    checks = []
    if a.water_error is None or abs(a.water_error) > MASS_TOLERANCE:
        checks.append("water not conserved to 1 %" if a.water_error is not None else "no water balance")
    if a.deepest_inside_m is not None and a.deepest_inside_m > INSIDE_TOLERANCE_M:
        checks.append(f"{a.inside_what}: {a.deepest_inside_m * 1000:.1f} mm inside")
    if a.forces_finite is False:
        checks.append("non-finite forces")
    a.failed_checks = checks
    if outcome == "finished":
        a.sane = not checks
    return a


def stability_table(sweep_dir: str | Path) -> pd.DataFrame:
    """:func:`assess` for every member of the sweep in ``sweep_dir``, in member order."""
    store = load_store(sweep_dir)
    rows = []
    for m in store.sort_values("member").itertuples(index=False):
        case = Path(m.case_dir)
        if not case.is_absolute() or not case.is_dir():
            case = Path(sweep_dir) / m.member_id
        member = read_member_record(case) or {}
        member.setdefault("wall_time_s", finite_or_none(getattr(m, "wall_time_s", None)))
        member.setdefault("error", getattr(m, "error", None))
        if case.is_dir():
            row = asdict(assess(case, member))
        else:
            row = asdict(Assessment(str(case), None, "not run", None, *([None] * 13)))
        row["member"] = int(m.member)
        row["member_id"] = m.member_id
        row["scene"] = row["scene"] or getattr(m, "scene", None)
        rows.append(row)
    return pd.DataFrame(rows)


def _fmt(value, spec: str, empty: str = "-") -> str:
    return empty if value is None or (isinstance(value, float) and not math.isfinite(value)) else format(value, spec)


def markdown(table: pd.DataFrame) -> str:
    """The stability table as Markdown: one row per run."""
    lines = [
        "| case | outcome | reached / end (s) | cells | steps | wall (min) | water balance error | deepest inside "
        "(mm) | bed sink (mm) | impacts | forces finite | diagnosis |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|",
    ]
    for r in table.itertuples(index=False):
        verdict = r.outcome if r.sane is None else ("finished, sane" if r.sane else "finished, NOT sane")
        diagnosis = "; ".join([*r.failed_checks, *([r.diagnosis] if r.diagnosis else [])]) or "-"
        water = "-" if r.water_error is None or pd.isna(r.water_error) else f"{r.water_error * 100:+.3f} %"
        inside = "-" if r.deepest_inside_m is None or pd.isna(r.deepest_inside_m) else (
            f"{r.deepest_inside_m * 1000:.2f}" + (f" ({r.inside_what})" if isinstance(r.inside_what, str)
                                                  and r.inside_what else ""))
        sink = "-" if r.bed_sink_m is None or pd.isna(r.bed_sink_m) else f"{r.bed_sink_m * 1000:.1f}"
        reached = f"{_fmt(r.reached_time_s, '.3f')} / {_fmt(r.end_time_s, '.2f')}"
        wall = "-" if r.wall_time_s is None or pd.isna(r.wall_time_s) else f"{r.wall_time_s / 60:.1f}"
        finite = {True: "yes", False: "NO"}.get(r.forces_finite, "-")
        cells = "-" if r.cells is None or pd.isna(r.cells) else f"{int(r.cells):,}"
        steps = "-" if r.time_steps is None or pd.isna(r.time_steps) else f"{int(r.time_steps):,}"
        pinned = f" ({int(r.pinned)} pinned)" if r.pinned else ""
        lines.append(f"| {r.scene} | {verdict} | {reached} | {cells} | {steps} | {wall} | {water} | {inside} | {sink} "
                     f"| {int(r.contacts)}{pinned} | {finite} | {diagnosis.replace('|', '/')} |")
    return "\n".join(lines) + "\n"
