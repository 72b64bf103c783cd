"""Speed against error: what each member of a sweep costs and how wrong it is.

:func:`speed_error` reads a sweep folder (its results store and every member's
``results/``), optionally baseline sweep folders (e.g. the hand-made set-up: uniform
cells, the whole reservoir and flume, ``mesh.trim_domain: false``), and measures for
every finished member:

* **cost**: cells, time steps, cells x steps (the work), the member's wall time (render +
  mesh + solve + post), the solver's wall time and the solver's CPU time (``ExecutionTime``
  of the master rank in the solver logs, summed over restarts). The plot and the speed-ups
  use the CPU time by default: on an idle machine it equals the solver's wall time, and on a
  shared one the wall time also measures the other jobs;
* **errors against the finest member** (the reference: the smallest ``mesh.cell_size_m``
  of the first sweep, most cells on a tie; or ``reference=``): gauge elevation RMSE on
  the reference's time base (per gauge, and their root mean square), bore arrival time
  at each gauge, the peak column force (x), and with debris the first impact's time and
  velocity;
* **errors against the analytical dam-break solutions**: arrival time at each gauge
  against Ritter, Stoker (wet bed) and Chanson (friction), from the store, and the gauge
  depth RMSE against Chanson where that is meaningful: gauges downstream of the gate and
  clear of the column (more than :data:`COLUMN_CLEARANCE` column widths upstream of its
  face), from Chanson's arrival at the gauge to the end of the run (before it Chanson's
  bed is dry while the run's wet bed holds still water);
* **errors against the study's figures**: arrival at WG2 and WG3 against the experiment and
  the study's LS-DYNA model (:data:`analytical.study.STUDY_ARRIVALS`).

It then marks the Pareto front (no other member is both cheaper and closer), works out
the planner's speed-up over each baseline member (at the same cell size, and at equal
error by log-log interpolation along the planner's members) and extrapolates both
set-ups to a finer cell size (default the study's 15 mm): cells from the planner (exact),
time steps scaled as 1/cell size from the finest measured member of that set-up
(Courant-limited steps), cost per cell-step as measured on that member. Extrapolated
figures are labelled as such everywhere.

:func:`orchestrator.studies.speedup.speedups` and :func:`~orchestrator.studies.speedup.extrapolate`
work out the speed-ups and the extrapolation; :mod:`orchestrator.studies.speed_error_report`
writes the study (:func:`~orchestrator.studies.speed_error_report.write_report`), in
``SWEEP_DIR/report/``:

``speed_error.csv``   one row per member, every figure above (units in the column names);
``speed_error.md``    the tables, the speed-ups and the extrapolation, with the definitions;
``speed_error.png``   the Pareto plot: time against error (log axes), every member
                      labelled, the front drawn; left against the finest member, right
                      against Chanson's arrival times;
``speed_error.json``  the headline: reference, speed-ups, extrapolation, notes.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import pandas as pd

from analytical.dambreak import dam_break
from orchestrator.core.errors import InputError
from orchestrator.case.folder import RESULTS_DIR, CaseFolder
from orchestrator.core.files import read_json_object
from orchestrator.core.numbers import finite_or_none
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.speedup import extrapolate, speedups
from orchestrator.studies.sweep.store import SWEEP_JSON, load_store

__all__ = [
    "COLUMN_CLEARANCE",
    "REPORT_DIR",
    "TIME_COLUMNS",
    "TIME_LABELS",
    "SpeedError",
    "gauge_rmse",
    "pareto_front",
    "solver_cpu_s",
    "speed_error",
]


#: Report folder inside the sweep folder.
REPORT_DIR = "report"
#: Which time the plot and the speed-ups use: option name -> table column.
TIME_COLUMNS = {"solver": "solver_wall_s", "wall": "wall_time_s", "cpu": "solver_cpu_s"}
#: How the report names each time.
TIME_LABELS = {"solver_wall_s": "solver wall time (s)", "wall_time_s": "member wall time (s)",
                "solver_cpu_s": "solver CPU time (s)"}
#: A gauge is compared with Chanson only if it lies this many column widths (x) upstream of the column's face.
COLUMN_CLEARANCE = 5.0
#: The study's gauges (the store's arrival-error columns are named after the reference).
STUDY_REFS = {"study_experiment": "experiment", "study_model": "study model"}
_EXEC_RE = re.compile(r"^ExecutionTime = ([0-9.eE+-]+) s\s+ClockTime = ([0-9.eE+-]+) s", re.M)


# --------------------------------------------------------------------------- small helpers


def solver_cpu_s(case_dir: str | Path) -> float | None:
    """CPU time of the solver's master rank (s): the last ``ExecutionTime`` of every solver
    log in the case, summed. Each segment writes ``log.<solver>`` and the next one moves it
    to ``log.<solver>.N``, so every log is one solver process (restarts that were later
    undone included: they cost CPU too). None when no log says."""
    case = Path(case_dir)
    bases = {str(seg["log"]) for seg in CaseFolder(case).run_state().segments if seg.get("log")}
    logs = {p for base in bases for p in [case / base, *case.glob(f"{base}.*")]
            if p.is_file() and (p.name == base or p.suffix[1:].isdigit())}
    total, found = 0.0, False
    for log in sorted(logs):
        hits = _EXEC_RE.findall(log.read_text(errors="replace"))
        if hits:
            total += float(hits[-1][0])
            found = True
    return round(total, 2) if found else None


def pareto_front(cost: Sequence[float], error: Sequence[float]) -> np.ndarray:
    """Boolean mask of the points no other point beats: cheaper-or-equal and closer-or-equal,
    one of them strictly. NaN points are never on the front."""
    c = np.asarray(cost, dtype=float)
    e = np.asarray(error, dtype=float)
    ok = np.isfinite(c) & np.isfinite(e)
    front = np.zeros(c.size, dtype=bool)
    for i in np.flatnonzero(ok):
        others = ok.copy()
        others[i] = False
        beaten = others & (c <= c[i]) & (e <= e[i]) & ((c < c[i]) | (e < e[i]))
        front[i] = not beaten.any()
    return front


def gauge_rmse(time_s, values, ref_time_s, ref_values) -> float:
    """RMSE of a series against a reference, on the reference's time base over the window
    both cover (the series linearly interpolated); NaN samples are dropped. NaN if nothing
    overlaps."""
    t = np.asarray(time_s, dtype=float)
    v = np.asarray(values, dtype=float)
    tr = np.asarray(ref_time_s, dtype=float)
    vr = np.asarray(ref_values, dtype=float)
    keep = np.isfinite(t) & np.isfinite(v)
    t, v = t[keep], v[keep]
    if t.size < 2:
        return float("nan")
    order = np.argsort(t)
    t, v = t[order], v[order]
    inside = np.isfinite(tr) & np.isfinite(vr) & (tr >= t[0] - 1e-9) & (tr <= t[-1] + 1e-9)
    if not inside.any():
        return float("nan")
    diff = np.interp(tr[inside], t, v) - vr[inside]
    return float(np.sqrt(np.mean(diff**2)))


# --------------------------------------------------------------------------- members


def _case_dir(sweep_dir: Path, row: dict) -> Path:
    """The member's folder: in the sweep folder (which may have moved), else the store's path."""
    local = sweep_dir / str(row.get("member_id"))
    return local if local.is_dir() else Path(str(row.get("case_dir") or local))


def _setup(scene) -> str:
    """planner (graded cells, trimmed domain), hand (uniform cells, whole flume) or custom."""
    if scene is None:
        return "unknown"
    uniform = scene.mesh.coarsening_ratio <= 1.0
    trimmed = getattr(scene.mesh, "trim_domain", True)
    if trimmed and not uniform:
        return "planner"
    if not trimmed and uniform:
        return "hand"
    return "custom"


def _label(setup: str, cell_m: float | None, taken: set[str]) -> str:
    size = f"{100 * cell_m:.3g} cm" if cell_m else "?"
    label = f"{setup} {size}"
    n = 2
    while label in taken:
        label = f"{setup} {size} ({n})"
        n += 1
    taken.add(label)
    return label


def _load_members(sweep_dir: Path, role: str) -> list[dict[str, Any]]:
    store = load_store(sweep_dir)
    sweep_name = (read_json_object(sweep_dir / SWEEP_JSON) or {}).get("name") or sweep_dir.name
    members = []
    for row in store.to_dict("records"):
        row = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}
        case = _case_dir(sweep_dir, row)
        scene = None
        scene_path = CaseFolder(case).scene_path
        if scene_path.is_file():
            try:
                scene = load_scene(scene_path)
            except Exception:  # a member folder from an older scene schema: keep its row, no scene
                scene = None
        members.append({"row": row, "case": case, "scene": scene, "sweep": sweep_name, "role": role})
    return members


def _gauges(case: Path) -> pd.DataFrame | None:
    try:
        frame = pd.read_csv(case / RESULTS_DIR / "gauges.csv")
    except (OSError, ValueError):
        return None
    return frame if "time_s" in frame else None


def _gauge_positions(scene) -> dict[str, float]:
    """Gauge name -> x (m) from the scene (gauges placed at the column's face included)."""
    if scene is None:
        return {}
    try:
        return {g.name: float(g.x) for g in plan_case(scene).gauges}
    except Exception:
        return {}


def _chanson_gauges(scene, positions: dict[str, float]) -> list[str]:
    """Gauges where a comparison with Chanson's dry-bed solution is meaningful."""
    if scene is None or scene.bed.friction_factor <= 0:
        return []
    col = scene.column
    limit = math.inf if col is None else col.x_m - col.size_x_m / 2 - COLUMN_CLEARANCE * col.size_x_m
    return [g for g, x in positions.items() if 0.0 < x < limit]


def _chanson_rmse(scene, gauges: pd.DataFrame, names: list[str], positions: dict[str, float]) -> dict[str, float]:
    """Gauge elevation RMSE (m) against Chanson's depth, from Chanson's arrival at the gauge on."""
    sol = dam_break("chanson", float(scene.reservoir.depth_m), friction=float(scene.bed.friction_factor),
                    g=float(scene.fluids.gravity_m_s2))
    out = {}
    t = gauges["time_s"].to_numpy(float)
    for name in names:
        col = f"{name}_elevation_m"
        if col not in gauges:
            continue
        x = positions[name]
        t_arr = float(sol.arrival_time_s(x))
        sel = (t >= t_arr) & np.isfinite(gauges[col].to_numpy(float))
        if not sel.any():
            continue
        model = np.array([float(sol.profile(np.array([x]), tt).depth_m[0]) for tt in t[sel]])
        diff = gauges[col].to_numpy(float)[sel] - model
        out[name] = float(np.sqrt(np.mean(diff**2)))
    return out


def _peak_force(row: dict) -> float | None:
    value = finite_or_none(row.get("peak_column_force_x_N"))
    return value if value is not None else finite_or_none(row.get("peak_hydro_force_x_N"))


def _rel(value: float | None, ref: float | None) -> float | None:
    if value is None or ref is None or ref == 0:
        return None
    return 100.0 * (value - ref) / abs(ref)


def _mean_abs(values: Sequence[float | None]) -> float | None:
    vals = [abs(v) for v in values if v is not None]
    return float(np.mean(vals)) if vals else None


def _rms(values: Sequence[float | None]) -> float | None:
    vals = [v for v in values if v is not None and math.isfinite(v)]
    return float(np.sqrt(np.mean(np.square(vals)))) if vals else None


# --------------------------------------------------------------------------- the study


@dataclass
class SpeedError:
    """The speed-against-error study of one sweep (plus baselines)."""

    sweep_dir: Path
    table: pd.DataFrame
    reference: dict[str, Any] | None
    time_column: str
    speedups: list[dict[str, Any]] = field(default_factory=list)
    extrapolation: list[dict[str, Any]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    files: dict[str, Path] = field(default_factory=dict)

    def headline(self) -> dict[str, Any]:
        cols = ["label", "setup", "sweep", "member_id", "status", "cell_size_m", "cells", "time_steps", "wall_time_s",
                "solver_wall_s", "solver_cpu_s", "gauge_rmse_vs_finest_m", "peak_force_error_vs_finest_percent",
                "chanson_arrival_mae_s", "study_experiment_arrival_mae_s", "pareto_vs_finest", "pareto_vs_chanson"]
        rows = self.table[[c for c in cols if c in self.table]].to_dict("records")
        return {
            "sweep_dir": str(self.sweep_dir), "time": self.time_column, "reference": self.reference,
            "members": [{k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in r.items()}
                        for r in rows],
            "speedups": self.speedups, "extrapolation": self.extrapolation, "notes": self.notes,
            "files": {k: str(v) for k, v in self.files.items()},
        }


def _pick_reference(members: list[dict], reference: str | None) -> dict | None:
    done = [m for m in members if m["row"].get("status") == "finished" and m["scene"] is not None]
    if reference is not None:
        for m in members:
            if m["row"].get("member_id") == reference:
                if m not in done:
                    raise InputError("--reference", f"member {reference} has not finished: it cannot be the reference")
                return m
        raise InputError("--reference", f"no member {reference} in the sweep(s)")
    primary = [m for m in done if m["role"] == "sweep"] or done
    if not primary:
        return None
    return min(primary, key=lambda m: (m["scene"].mesh.cell_size_m, -(finite_or_none(m["row"].get("cells")) or 0)))


def _cost(m: dict) -> dict[str, Any]:
    """The member's identity, size, times and work (and the domain the planner gave it)."""
    row, scene, case = m["row"], m["scene"], m["case"]
    out: dict[str, Any] = {
        "label": m["label"], "setup": m["setup"], "sweep": m["sweep"], "member_id": row.get("member_id"),
        "status": row.get("status"),
        "cell_size_m": scene.mesh.cell_size_m if scene is not None else None,
        "cells": finite_or_none(row.get("cells")), "time_steps": finite_or_none(row.get("time_steps")),
        "end_time_s": finite_or_none(row.get("end_time_s")),
        "reached_time_s": finite_or_none(row.get("reached_time_s")),
        "wall_time_s": finite_or_none(row.get("wall_time_s")),
        "solver_wall_s": finite_or_none(row.get("solver_wall_s")),
        "solver_cpu_s": solver_cpu_s(case) if row.get("status") == "finished" else None,
    }
    if out["cells"] and out["time_steps"]:
        out["cell_steps"] = out["cells"] * out["time_steps"]  # the work: independent of the machine's load
        if out["solver_wall_s"]:
            out["us_per_cell_step"] = 1e6 * out["solver_wall_s"] / out["cell_steps"]
    if scene is not None:
        out["domain_x_m"] = None
        try:
            (x0, x1), _, (_, z1) = plan_case(scene).domain_m
            out["domain_x_m"] = f"{x0:.2f}..{x1:.2f}"
            out["domain_top_m"] = round(z1, 3)
        except Exception:
            pass
    return out


def _vs_finest(row: dict, positions: dict[str, float], gauges: pd.DataFrame | None, ref: dict,
               ref_gauges: pd.DataFrame | None) -> dict[str, Any]:
    """Gauge RMSE and arrivals, peak force and the first impact against the reference member."""
    out: dict[str, Any] = {}
    rr = ref["row"]
    rmses = []
    ref_pos = _gauge_positions(ref["scene"])
    for name in positions:
        col = f"{name}_elevation_m"
        same_place = name in ref_pos and abs(ref_pos[name] - positions[name]) < 1e-6
        if gauges is not None and ref_gauges is not None and col in gauges and col in ref_gauges and same_place:
            e = gauge_rmse(gauges["time_s"], gauges[col], ref_gauges["time_s"], ref_gauges[col])
            out[f"{name}_rmse_vs_finest_m"] = e if math.isfinite(e) else None
            rmses.append(out[f"{name}_rmse_vs_finest_m"])
        a, ar = finite_or_none(row.get(f"{name}_arrival_s")), finite_or_none(rr.get(f"{name}_arrival_s"))
        out[f"{name}_arrival_vs_finest_s"] = a - ar if a is not None and ar is not None else None
    out["gauge_rmse_vs_finest_m"] = _rms(rmses)
    f, fr = _peak_force(row), _peak_force(rr)
    out["peak_column_force_x_N"] = f
    out["peak_force_error_vs_finest_percent"] = _rel(f, fr)
    ti, tir = finite_or_none(row.get("first_impact_time_s")), finite_or_none(rr.get("first_impact_time_s"))
    vi, vir = finite_or_none(row.get("impact_velocity_m_s")), finite_or_none(rr.get("impact_velocity_m_s"))
    out["first_impact_time_s"] = ti
    out["impact_time_error_vs_finest_s"] = ti - tir if ti is not None and tir is not None else None
    out["impact_velocity_m_s"] = vi
    out["impact_velocity_error_vs_finest_percent"] = _rel(vi, vir)
    return out


def _vs_analytical(row: dict, scene, positions: dict[str, float], gauges: pd.DataFrame | None) -> dict[str, Any]:
    """Arrivals against the dam-break solutions (the store's, from post's comparisons) and the
    depth RMSE against Chanson's."""
    out: dict[str, Any] = {}
    chanson_names = _chanson_gauges(scene, positions)
    for name in positions:
        out[f"{name}_arrival_s"] = finite_or_none(row.get(f"{name}_arrival_s"))
        for ref_name in ("ritter", "stoker", "chanson"):
            out[f"{name}_arrival_error_{ref_name}_s"] = finite_or_none(row.get(f"{name}_arrival_error_{ref_name}_s"))
    out["chanson_arrival_mae_s"] = _mean_abs([out.get(f"{n}_arrival_error_chanson_s") for n in chanson_names])
    if gauges is not None and chanson_names:
        depth = _chanson_rmse(scene, gauges, chanson_names, positions)
        for name, e in depth.items():
            out[f"{name}_depth_rmse_vs_chanson_m"] = e
        out["depth_rmse_vs_chanson_m"] = _rms(list(depth.values()))
    return out


def _vs_study(row: dict, positions: dict[str, float]) -> dict[str, Any]:
    """Arrivals against the study's experiment and model."""
    out: dict[str, Any] = {}
    for key in STUDY_REFS:
        errs = []
        for name in positions:
            e = finite_or_none(row.get(f"{name}_arrival_error_{key}_s"))
            if e is not None:
                out[f"{name}_arrival_error_{key}_s"] = e
                errs.append(e)
        out[f"{key}_arrival_mae_s"] = _mean_abs(errs)
    return out


def _member_row(m: dict, ref: dict | None, ref_gauges: pd.DataFrame | None) -> dict[str, Any]:
    """The member's row of the table: its cost and, once finished, its errors."""
    out = _cost(m)
    if m["row"].get("status") != "finished":
        return out
    positions = _gauge_positions(m["scene"])
    gauges = _gauges(m["case"])
    if ref is not None:
        out.update(_vs_finest(m["row"], positions, gauges, ref, ref_gauges))
    out.update(_vs_analytical(m["row"], m["scene"], positions, gauges))
    out.update(_vs_study(m["row"], positions))
    return out


def speed_error(sweep_dir: str | Path, baselines: Sequence[str | Path] = (), *, reference: str | None = None,
                time: str = "cpu", extrapolate_to_m: float | None = 0.015) -> SpeedError:
    """Measure every member's cost and errors (see the module docstring); writes nothing.

    sweep_dir: a sweep folder (its results.sqlite and member folders). baselines: more sweep
    folders whose members join the table (the hand-made set-up). reference: the member id to
    measure against (default: the finest finished member of `sweep_dir`). time: the time of
    the plot and the speed-ups: "cpu" (the solver's CPU time, default: on an idle machine it
    equals the solver's wall time, and unlike it it does not count other jobs' turns on a
    shared one), "solver" (the solver's wall time) or "wall" (the member's whole session). extrapolate_to_m: cell size to extrapolate both
    set-ups to (None: no extrapolation).
    """
    if time not in TIME_COLUMNS:
        raise InputError("--time", f"must be one of {', '.join(TIME_COLUMNS)}, got {time!r}")
    tcol = TIME_COLUMNS[time]
    sweep_dir = Path(sweep_dir)
    members = _load_members(sweep_dir, "sweep")
    for b in baselines:
        members += _load_members(Path(b), "baseline")
    if not members:
        raise InputError("sweep_dir", "the results store has no members", str(sweep_dir))
    taken: set[str] = set()
    for m in sorted(members, key=lambda m: (m["role"] != "sweep",)):
        m["setup"] = _setup(m["scene"])
        m["label"] = _label(m["setup"], m["scene"].mesh.cell_size_m if m["scene"] else None, taken)
    ref = _pick_reference(members, reference)
    notes: list[str] = []
    ref_gauges = _gauges(ref["case"]) if ref else None
    if ref is None:
        notes.append("no finished member: no reference, no errors against the finest member")
    rows = [_member_row(m, ref, ref_gauges) for m in members]
    table = pd.DataFrame(rows)
    table.insert(4, "reference", [bool(ref) and r["member_id"] == ref["row"]["member_id"] for r in rows])
    ref_id = ref["row"]["member_id"] if ref else None
    done = (table["status"] == "finished").to_numpy()
    not_ref = (table["member_id"] != ref_id).to_numpy()
    for col, metric in (("pareto_vs_finest", "gauge_rmse_vs_finest_m"), ("pareto_vs_chanson", "chanson_arrival_mae_s")):
        if metric not in table:
            table[col] = False
            continue
        # the reference is at zero error against itself: it is not a point of the first front
        eligible = done & not_ref if metric == "gauge_rmse_vs_finest_m" else done
        table[col] = pareto_front(table[tcol].astype(float), table[metric].astype(float).where(eligible))
    sp = speedups(table, tcol, ref_id)
    ext = extrapolate(members, table, tcol, extrapolate_to_m) if extrapolate_to_m else []
    unfinished = table[~done]
    if len(unfinished):
        notes.append("not finished (no errors): " + ", ".join(f"{r.label} ({r.status})" for r in unfinished.itertuples()))
    reference_info = None
    if ref is not None:
        reference_info = {"member_id": ref_id, "label": ref["label"], "sweep": ref["sweep"],
                          "cell_size_m": ref["scene"].mesh.cell_size_m, "cells": finite_or_none(ref["row"].get("cells"))}
    return SpeedError(sweep_dir, table, reference_info, tcol, sp, ext, notes)
