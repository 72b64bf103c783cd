"""Speed against error: what each member of a sweep costs and how wrong it is (issue 6).

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
* **errors against the seed's figures**: arrival at WG2 (x = 2.40 m) and WG3 (3.20 m)
  against the experiment (0.91 s, 1.39 s) and the seed's LS-DYNA model (0.88 s, 1.20 s).

It then marks the Pareto front (no other member is both cheaper and closer), works out
the planner's speed-up over each baseline member (at the same cell size, and at equal
error by log-log interpolation along the planner's members) and extrapolates both
set-ups to a finer cell size (default the seed's 15 mm): cells from the planner (exact),
time steps scaled as 1/cell size from the finest measured member of that set-up
(Courant-limited steps), cost per cell-step as measured on that member. Extrapolated
figures are labelled as such everywhere.

:func:`write_report` writes, in ``SWEEP_DIR/report/``:

``speed_error.csv``   one row per member, every figure above (units in the column names);
``speed_error.md``    the tables, the speed-ups and the extrapolation, with the definitions;
``speed_error.png``   the Pareto plot: time against error (log axes), every member
                      labelled, the front drawn; left against the finest member, right
                      against Chanson's arrival times;
``speed_error.json``  the headline: reference, speed-ups, extrapolation, notes.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import pandas as pd

from analytical.errors import InputError
from orchestrator.core.jsonio import json_default

__all__ = [
    "COLUMN_CLEARANCE",
    "REPORT_DIR",
    "TIME_COLUMNS",
    "SpeedError",
    "gauge_rmse",
    "pareto_front",
    "solver_cpu_s",
    "speed_error",
    "write_report",
]

#: Report folder inside the sweep folder.
REPORT_DIR = "report"
#: Which time the plot and the speed-ups use: option name -> table column.
TIME_COLUMNS = {"solver": "solver_wall_s", "wall": "wall_time_s", "cpu": "solver_cpu_s"}
_TIME_LABELS = {"solver_wall_s": "solver wall time (s)", "wall_time_s": "member wall time (s)",
                "solver_cpu_s": "solver CPU time (s)"}
#: A gauge is compared with Chanson only if it lies this many column widths (x) upstream of the column's face.
COLUMN_CLEARANCE = 5.0
#: The seed's gauges (the store's arrival-error columns are named after the reference).
SEED_REFS = {"seed_experiment": "experiment", "seed_model": "seed model"}
_EXEC_RE = re.compile(r"^ExecutionTime = ([0-9.eE+-]+) s\s+ClockTime = ([0-9.eE+-]+) s", re.M)


# --------------------------------------------------------------------------- small helpers


def _num(value: Any) -> float | None:
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _read_json(path: Path) -> dict:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def solver_cpu_s(case_dir: str | Path) -> float | None:
    """CPU time of the solver's master rank (s): the last ``ExecutionTime`` of every solver
    log in the case, summed. Each segment writes ``log.<solver>`` and the next one moves it
    to ``log.<solver>.N``, so every log is one solver process (restarts that were later
    undone included: they cost CPU too). None when no log says."""
    case = Path(case_dir)
    run = _read_json(case / "run.json")
    bases = {str(seg.get("log")) for seg in run.get("segments") or [] if seg.get("log")}
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
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.studies.sweep import load_store

    store = load_store(sweep_dir)
    sweep_name = _read_json(sweep_dir / "sweep.json").get("name") or sweep_dir.name
    members = []
    for row in store.to_dict("records"):
        row = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()}
        case = _case_dir(sweep_dir, row)
        scene = None
        if (case / "scene.yaml").is_file():
            try:
                scene = load_scene(case / "scene.yaml")
            except Exception:  # a member folder from an older scene schema: keep its row, no scene
                scene = None
        members.append({"row": row, "case": case, "scene": scene, "sweep": sweep_name, "role": role})
    return members


def _gauges(case: Path) -> pd.DataFrame | None:
    try:
        frame = pd.read_csv(case / "results" / "gauges.csv")
    except (OSError, ValueError):
        return None
    return frame if "time_s" in frame else None


def _gauge_positions(scene) -> dict[str, float]:
    """Gauge name -> x (m) from the scene (gauges placed at the column's face included)."""
    if scene is None:
        return {}
    try:
        from orchestrator.plan.planner import plan_case

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
    from analytical.dambreak import dam_break

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
    value = _num(row.get("peak_column_force_x_N"))
    return value if value is not None else _num(row.get("peak_hydro_force_x_N"))


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


# --------------------------------------------------------------------------- the report


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
                "chanson_arrival_mae_s", "seed_experiment_arrival_mae_s", "pareto_vs_finest", "pareto_vs_chanson"]
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
    return min(primary, key=lambda m: (m["scene"].mesh.cell_size_m, -(_num(m["row"].get("cells")) or 0)))


def _member_row(m: dict, ref: dict | None, ref_gauges: pd.DataFrame | None) -> dict[str, Any]:
    row, scene, case = m["row"], m["scene"], m["case"]
    out: dict[str, Any] = {
        "label": m["label"], "setup": m["setup"], "sweep": m["sweep"], "member_id": row.get("member_id"),
        "status": row.get("status"),
        "cell_size_m": scene.mesh.cell_size_m if scene is not None else None,
        "cells": _num(row.get("cells")), "time_steps": _num(row.get("time_steps")),
        "end_time_s": _num(row.get("end_time_s")), "reached_time_s": _num(row.get("reached_time_s")),
        "wall_time_s": _num(row.get("wall_time_s")), "solver_wall_s": _num(row.get("solver_wall_s")),
        "solver_cpu_s": solver_cpu_s(case) if row.get("status") == "finished" else None,
    }
    if out["cells"] and out["time_steps"]:
        out["cell_steps"] = out["cells"] * out["time_steps"]  # the work: independent of the machine's load
        if out["solver_wall_s"]:
            out["us_per_cell_step"] = 1e6 * out["solver_wall_s"] / out["cell_steps"]
    if scene is not None:
        out["domain_x_m"] = None
        try:
            from orchestrator.plan.planner import plan_case

            (x0, x1), _, (_, z1) = plan_case(scene).domain_m
            out["domain_x_m"] = f"{x0:.2f}..{x1:.2f}"
            out["domain_top_m"] = round(z1, 3)
        except Exception:
            pass
    if row.get("status") != "finished":
        return out
    positions = _gauge_positions(scene)
    gauges = _gauges(case)

    # against the finest member
    if ref is not None:
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
            a, ar = _num(row.get(f"{name}_arrival_s")), _num(rr.get(f"{name}_arrival_s"))
            out[f"{name}_arrival_vs_finest_s"] = a - ar if a is not None and ar is not None else None
        out["gauge_rmse_vs_finest_m"] = _rms(rmses)
        f, fr = _peak_force(row), _peak_force(rr)
        out["peak_column_force_x_N"] = f
        out["peak_force_error_vs_finest_percent"] = _rel(f, fr)
        ti, tir = _num(row.get("first_impact_time_s")), _num(rr.get("first_impact_time_s"))
        vi, vir = _num(row.get("impact_velocity_m_s")), _num(rr.get("impact_velocity_m_s"))
        out["first_impact_time_s"] = ti
        out["impact_time_error_vs_finest_s"] = ti - tir if ti is not None and tir is not None else None
        out["impact_velocity_m_s"] = vi
        out["impact_velocity_error_vs_finest_percent"] = _rel(vi, vir)

    # against the analytical solutions: arrivals (the store's, from post's comparisons) and Chanson's depth
    chanson_names = _chanson_gauges(scene, positions)
    for name in positions:
        out[f"{name}_arrival_s"] = _num(row.get(f"{name}_arrival_s"))
        for ref_name in ("ritter", "stoker", "chanson"):
            out[f"{name}_arrival_error_{ref_name}_s"] = _num(row.get(f"{name}_arrival_error_{ref_name}_s"))
    out["chanson_arrival_mae_s"] = _mean_abs([out.get(f"{n}_arrival_error_chanson_s") for n in chanson_names])
    if gauges is not None and chanson_names:
        depth = _chanson_rmse(scene, gauges, chanson_names, positions)
        for name, e in depth.items():
            out[f"{name}_depth_rmse_vs_chanson_m"] = e
        out["depth_rmse_vs_chanson_m"] = _rms(list(depth.values()))

    # against the seed
    for key in SEED_REFS:
        errs = []
        for name in positions:
            e = _num(row.get(f"{name}_arrival_error_{key}_s"))
            if e is not None:
                out[f"{name}_arrival_error_{key}_s"] = e
                errs.append(e)
        out[f"{key}_arrival_mae_s"] = _mean_abs(errs)
    return out


#: How far (a factor on x) the equal-error interpolation may extend the planner's end segments.
EQUAL_ERROR_REACH = 1.5


def _interp_loglog(x: float, xs: Sequence[float], ys: Sequence[float],
                   reach: float = 1.0) -> tuple[float | None, bool]:
    """(y at x on the piecewise log-log line through (xs, ys), extrapolated?). Beyond the end
    points the end segments are extended up to a factor `reach` on x; further out: (None, False)."""
    pts = sorted((a, b) for a, b in zip(xs, ys) if a and b and a > 0 and b > 0)

    def on(p0, p1) -> float:
        (x0, y0), (x1, y1) = p0, p1
        if x1 == x0:
            return y0
        w = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
        return math.exp(math.log(y0) + w * (math.log(y1) - math.log(y0)))

    for p0, p1 in zip(pts, pts[1:]):
        if p0[0] <= x <= p1[0]:
            return on(p0, p1), False
    if len(pts) >= 2 and x > 0:
        if pts[0][0] / reach <= x < pts[0][0]:
            return on(pts[0], pts[1]), True
        if pts[-1][0] < x <= pts[-1][0] * reach:
            return on(pts[-2], pts[-1]), True
    return None, False


def _speedups(table: pd.DataFrame, tcol: str, ref_id: str | None) -> list[dict[str, Any]]:
    """The planner against each hand-made (baseline) member: same cell size, and equal error."""
    done = table[table["status"] == "finished"]
    planner = done[(done["setup"] == "planner")]
    out = []
    for b in done[done["setup"] == "hand"].to_dict("records"):
        entry: dict[str, Any] = {"baseline": b["label"], "baseline_id": b["member_id"], "cell_size_m": b["cell_size_m"],
                                 "baseline_time_s": b.get(tcol), "baseline_cells": b.get("cells"),
                                 "baseline_steps": b.get("time_steps")}
        same = planner[np.isclose(planner["cell_size_m"].astype(float), float(b["cell_size_m"]))]
        if len(same):
            p = same.iloc[0]
            entry.update({"planner": p["label"], "planner_time_s": p.get(tcol), "planner_cells": p.get("cells"),
                          "planner_steps": p.get("time_steps")})
            if p.get(tcol) and b.get(tcol):
                entry["speedup_same_cell"] = b[tcol] / p[tcol]
            if p.get("cells") and b.get("cells"):
                entry["cell_ratio"] = b["cells"] / p["cells"]
            if p.get("cell_steps") and b.get("cell_steps"):
                entry["work_ratio"] = b["cell_steps"] / p["cell_steps"]
            for metric in ("gauge_rmse_vs_finest_m", "chanson_arrival_mae_s", "peak_force_error_vs_finest_percent"):
                entry[f"baseline_{metric}"] = _num(b.get(metric))
                entry[f"planner_{metric}"] = _num(p.get(metric))
        # equal error: the planner's time at the baseline's gauge error, along the planner's members
        # (the reference itself, at zero error against itself, is left out)
        curve = planner[(planner["member_id"] != ref_id)]
        err = _num(b.get("gauge_rmse_vs_finest_m"))
        if err is not None and len(curve) >= 2:
            t_eq, extrapolated = _interp_loglog(err, curve["gauge_rmse_vs_finest_m"].astype(float).tolist(),
                                                curve[tcol].astype(float).tolist(), reach=EQUAL_ERROR_REACH)
            entry["planner_time_at_equal_error_s"] = t_eq
            entry["equal_error_extrapolated"] = extrapolated
            if t_eq and b.get(tcol):
                entry["speedup_equal_error"] = b[tcol] / t_eq
        out.append(entry)
    return out


def _extrapolate(members: list[dict], table: pd.DataFrame, tcol: str, cell_m: float) -> list[dict[str, Any]]:
    """Each set-up at `cell_m`: planned cells (exact); time steps from the finest measured member
    of that set-up, scaled as 1 / cell size (a Courant-limited step is proportional to the cell
    size: a lower bound where the step was capped by maxDeltaT on the measured member); the cost
    per cell-step of the finest member. The local exponent of the steps between the set-up's two
    finest members is reported beside it. An extrapolation, labelled as such."""
    from orchestrator.plan.planner import plan_case
    from orchestrator.scene.scenefile import load_scene

    out = []
    by_id = {m["row"].get("member_id"): m for m in members}
    done = table[(table["status"] == "finished") & table[tcol].notna() & table["time_steps"].notna()]
    for setup in ("planner", "hand"):
        rows = done[done["setup"] == setup]
        if rows.empty:
            continue
        ranked = rows.sort_values(["cell_size_m", "cells"], ascending=[True, False])
        finest = ranked.iloc[0]
        m = by_id[finest["member_id"]]
        local = None
        coarser = ranked[ranked["cell_size_m"] > finest["cell_size_m"] * (1 + 1e-9)]
        if len(coarser):
            nxt = coarser.iloc[0]
            local = (math.log(float(finest["time_steps"]) / float(nxt["time_steps"]))
                     / math.log(float(nxt["cell_size_m"]) / float(finest["cell_size_m"])))
        try:
            scene = load_scene(m["case"] / "scene.yaml", [f"mesh.cell_size_m={cell_m}"])
            plan = plan_case(scene)
        except Exception as err:  # the scene cannot be planned that fine
            out.append({"setup": setup, "cell_size_m": cell_m, "error": str(err)})
            continue
        steps = float(finest["time_steps"]) * float(finest["cell_size_m"]) / cell_m
        per = float(finest[tcol]) / (float(finest["cells"]) * float(finest["time_steps"]))
        out.append({
            "setup": setup, "cell_size_m": cell_m, "cells": int(plan.cell_count),
            "steps_extrapolated": round(steps), "steps_local_exponent": None if local is None else round(local, 2),
            "from_member": finest["label"], "cell_steps_extrapolated": plan.cell_count * round(steps),
            "us_per_cell_step": 1e6 * per, "time_s_extrapolated": plan.cell_count * steps * per,
            "domain_m": [list(a) for a in plan.domain_m],
        })
    planner = next((e for e in out if e["setup"] == "planner" and "time_s_extrapolated" in e), None)
    hand = next((e for e in out if e["setup"] == "hand" and "time_s_extrapolated" in e), None)
    if planner and hand:
        hand["speedup_of_planner_extrapolated"] = hand["time_s_extrapolated"] / planner["time_s_extrapolated"]
        hand["work_ratio_extrapolated"] = hand["cell_steps_extrapolated"] / planner["cell_steps_extrapolated"]
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
    sp = _speedups(table, tcol, ref_id)
    ext = _extrapolate(members, table, tcol, extrapolate_to_m) if extrapolate_to_m else []
    unfinished = table[~done]
    if len(unfinished):
        notes.append("not finished (no errors): " + ", ".join(f"{r.label} ({r.status})" for r in unfinished.itertuples()))
    reference_info = None
    if ref is not None:
        reference_info = {"member_id": ref_id, "label": ref["label"], "sweep": ref["sweep"],
                          "cell_size_m": ref["scene"].mesh.cell_size_m, "cells": _num(ref["row"].get("cells"))}
    return SpeedError(sweep_dir, table, reference_info, tcol, sp, ext, notes)


# --------------------------------------------------------------------------- output


def _fmt(value: Any, fmt: str) -> str:
    v = _num(value)
    return "-" if v is None else format(v, fmt)


def _duration(seconds: Any) -> str:
    s = _num(seconds)
    if s is None:
        return "-"
    if s < 100:
        return f"{s:.0f} s"
    if s < 6000:
        return f"{s / 60:.1f} min"
    return f"{s / 3600:.1f} h"


def _markdown_table(head: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def _impact_cells(r: dict) -> list[str]:
    """The first impact's time and velocity, and their errors against the reference."""
    ref = bool(r.get("reference"))
    err_v = _num(r.get("impact_velocity_error_vs_finest_percent"))
    return [
        _fmt(r.get("first_impact_time_s"), ".3f"),
        "reference" if ref else _fmt(r.get("impact_time_error_vs_finest_s"), "+.3f"),
        _fmt(r.get("impact_velocity_m_s"), ".2f"),
        "reference" if ref else (_fmt(err_v, "+.1f") + " %" if err_v is not None else "-"),
    ]


def markdown(study: SpeedError) -> str:
    """speed_error.md: the tables, the speed-ups and the extrapolation."""
    t = study.table
    tcol = study.time_column
    ref = study.reference
    seed_gauges = [g for g in ("WG2", "WG3") if f"{g}_arrival_s" in t]
    impacts = "first_impact_time_s" in t and t["first_impact_time_s"].notna().any()
    head = ["member", "cell", "cells", "steps", "cell-steps (M)", "wall", "solver", "solver CPU",
            "gauge RMSE vs finest (mm)", "peak force vs finest", *[f"{g} arrival (s)" for g in seed_gauges],
            *[f"{g} vs Chanson (s)" for g in seed_gauges], *[f"{g} vs experiment (s)" for g in seed_gauges],
            "depth RMSE vs Chanson (mm)",
            *(["first impact (s)", "vs finest (s)", "impact velocity (m/s)", "vs finest"] if impacts else []),
            "Pareto"]
    rows = []
    for r in t.to_dict("records"):
        pareto = ", ".join(n for n, c in (("finest", "pareto_vs_finest"), ("Chanson", "pareto_vs_chanson")) if r.get(c))
        name = f"**{r['label']}**" if r.get("reference") else r["label"]
        if r.get("status") != "finished":
            name += f" ({r.get('status')})"
        rows.append([
            name, _fmt(r.get("cell_size_m"), ".3g"), _fmt(r.get("cells"), ",.0f"), _fmt(r.get("time_steps"), ".0f"),
            _fmt(r["cell_steps"] / 1e6, ".1f") if _num(r.get("cell_steps")) is not None else "-",
            _duration(r.get("wall_time_s")), _duration(r.get("solver_wall_s")), _duration(r.get("solver_cpu_s")),
            "reference" if r.get("reference") else _fmt(1e3 * r["gauge_rmse_vs_finest_m"], ".2f")
            if _num(r.get("gauge_rmse_vs_finest_m")) is not None else "-",
            "reference" if r.get("reference") else (_fmt(r.get("peak_force_error_vs_finest_percent"), "+.1f") + " %"
                                                    if _num(r.get("peak_force_error_vs_finest_percent")) is not None
                                                    else "-"),
            *[_fmt(r.get(f"{g}_arrival_s"), ".3f") for g in seed_gauges],
            *[_fmt(r.get(f"{g}_arrival_error_chanson_s"), "+.3f") for g in seed_gauges],
            *[_fmt(r.get(f"{g}_arrival_error_seed_experiment_s"), "+.3f") for g in seed_gauges],
            _fmt(1e3 * r["depth_rmse_vs_chanson_m"], ".1f") if _num(r.get("depth_rmse_vs_chanson_m")) is not None else "-",
            *(_impact_cells(r) if impacts else []),
            pareto or "-",
        ])
    out = [f"# Speed against error: {study.sweep_dir.name}", ""]
    if ref:
        out.append(f"Reference (the finest member): **{ref['label']}** ({ref['member_id']}, "
                   f"{_fmt(ref['cells'], ',.0f')} cells). Times: {_TIME_LABELS[tcol]} for the plot and the speed-ups.")
        out.append("")
    out += [_markdown_table(head, rows), ""]
    out += [
        "- *cell*: finest cell (m); *planner*: the planner's graded cells and trimmed domain; *hand*: uniform "
        "cells, the whole reservoir and flume (`mesh.trim_domain: false`, `mesh.coarsening_ratio: 1`).",
        "- *cell-steps*: cells x time steps, the work (independent of the machine's load); *wall*: the member's "
        "whole session (render, mesh, solve, post); *solver*: the solver's wall time; *solver CPU*: the master "
        "rank's CPU time (`ExecutionTime`), less sensitive to other jobs on the machine.",
        "- *gauge RMSE vs finest*: water level at every gauge against the reference on its time base, RMS over "
        "the gauges; *peak force*: the peak column force along the flume against the reference's.",
        "- *vs Chanson*: simulated minus Chanson's (f = the scene's) arrival time; *vs experiment*: minus the "
        "seed's measured arrivals (0.91 s at WG2, 1.39 s at WG3). Arrival = the level rising 2 % of h0 above "
        "its initial value.",
        f"- *depth RMSE vs Chanson*: gauges downstream of the gate and more than {COLUMN_CLEARANCE:g} column widths "
        "upstream of the column, from Chanson's arrival to the end of the run.",
        "- *Pareto*: on the front of time against gauge RMSE vs finest (*finest*) or against the mean |arrival "
        "error| vs Chanson (*Chanson*).",
        "",
    ]
    if study.speedups:
        out += ["## The planner against the hand-made set-up", "",
                f"Times: {_TIME_LABELS[tcol]}. *Work ratio*: the cell-steps of the hand-made set-up over the "
                "planner's. *At equal error*: the planner's time at the baseline's gauge RMSE, interpolated "
                "(log-log) between the planner's members other than the reference (its end segments extended "
                f"up to a factor {EQUAL_ERROR_REACH:g} in error, marked *extrapolated*).", ""]
        head = ["baseline", "cells (hand / planner)", "steps (hand / planner)", "time (hand / planner)",
                "speed-up, same cell", "work ratio, same cell", "gauge RMSE vs finest, mm (hand / planner)",
                "planner time at equal error", "speed-up at equal error"]
        rows = []
        for s in study.speedups:
            rows.append([
                s["baseline"], f"{_fmt(s.get('baseline_cells'), ',.0f')} / {_fmt(s.get('planner_cells'), ',.0f')}",
                f"{_fmt(s.get('baseline_steps'), '.0f')} / {_fmt(s.get('planner_steps'), '.0f')}",
                f"{_duration(s.get('baseline_time_s'))} / {_duration(s.get('planner_time_s'))}",
                _fmt(s.get("speedup_same_cell"), ".1f") + "x" if s.get("speedup_same_cell") else "-",
                _fmt(s.get("work_ratio"), ".1f") + "x" if s.get("work_ratio") else "-",
                f"{_fmt(1e3 * s['baseline_gauge_rmse_vs_finest_m'], '.2f') if s.get('baseline_gauge_rmse_vs_finest_m') is not None else '-'}"
                f" / {_fmt(1e3 * s['planner_gauge_rmse_vs_finest_m'], '.2f') if s.get('planner_gauge_rmse_vs_finest_m') is not None else '-'}",
                _duration(s.get("planner_time_at_equal_error_s"))
                + (" (extrapolated)" if s.get("equal_error_extrapolated") else ""),
                _fmt(s.get("speedup_equal_error"), ".1f") + "x" if s.get("speedup_equal_error") else
                "- (outside the planner's range)",
            ])
        out += [_markdown_table(head, rows), ""]
    if study.extrapolation:
        cell = study.extrapolation[0]["cell_size_m"]
        out += [f"## Extrapolation to {1000 * cell:g} mm cells (not measured)", "",
                "Cells from the planner (exact). Time steps from the finest measured member of each set-up, "
                "scaled as 1 / cell size (a Courant-limited step): a lower bound where that member's step was "
                "still capped by maxDeltaT; *p* is the measured exponent of the steps (steps ~ cell size^-p) "
                f"between the set-up's two finest members. Cost per cell-step ({_TIME_LABELS[tcol]}) as "
                "measured on that member. **An extrapolation, not a measurement.**", ""]
        head = ["set-up", "cells", "steps (extrapolated; measured p)", "cell-steps (extrapolated)",
                "us per cell-step (from)", "time (extrapolated)", "planner speed-up: work / time (extrapolated)"]
        rows = []
        for e in study.extrapolation:
            if "error" in e:
                rows.append([e["setup"], "-", "-", "-", "-", f"cannot plan: {e['error']}", "-"])
                continue
            p_text = "" if e.get("steps_local_exponent") is None else f"; p = {e['steps_local_exponent']:.2f}"
            speedup = "-"
            if e.get("speedup_of_planner_extrapolated"):
                speedup = f"{e['work_ratio_extrapolated']:.1f}x / {e['speedup_of_planner_extrapolated']:.1f}x"
            rows.append([e["setup"], f"{e['cells']:,}", f"{e['steps_extrapolated']:,}{p_text}",
                         f"{e['cell_steps_extrapolated'] / 1e9:.2f} G",
                         f"{e['us_per_cell_step']:.2f} ({e['from_member']})", _duration(e["time_s_extrapolated"]),
                         speedup])
        out += [_markdown_table(head, rows), ""]
    if study.notes:
        out += ["## Notes", ""] + [f"- {n}" for n in study.notes] + [""]
    return "\n".join(out)


def plot(study: SpeedError, path: str | Path) -> Path:
    """The Pareto plot: time against error, log axes, every member labelled, the front drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = study.table
    tcol = study.time_column
    ref_id = (study.reference or {}).get("member_id")
    panels = [("gauge_rmse_vs_finest_m", 1e3, "gauge RMSE against the finest member (mm)", "pareto_vs_finest"),
              ("chanson_arrival_mae_s", 1.0, "mean |arrival error| against Chanson (s)", "pareto_vs_chanson")]
    styles = {"planner": ("o", "#2c7bb6"), "hand": ("s", "#d7191c"), "custom": ("^", "#1a9641"),
              "unknown": ("x", "grey")}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    for ax, (metric, scale, ylabel, front_col) in zip(axes, panels):
        done = t[(t["status"] == "finished")]
        if metric not in t:
            ax.text(0.5, 0.5, "no data", ha="center", va="center", transform=ax.transAxes)
            continue
        pts = done[done[tcol].notna() & done[metric].notna()]
        pts = pts[(pts[tcol].astype(float) > 0) & (pts[metric].astype(float) > 0)]
        for setup, group in pts.groupby("setup"):
            marker, colour = styles.get(setup, styles["unknown"])
            ax.scatter(group[tcol].astype(float), scale * group[metric].astype(float), marker=marker, s=50,
                       color=colour, label=setup, zorder=3)
        for r in pts.itertuples():
            ax.annotate(r.label, (float(getattr(r, tcol)), scale * float(getattr(r, metric))),
                        textcoords="offset points", xytext=(6, 4), fontsize=8)
        front = pts[pts[front_col].astype(bool)].sort_values(tcol)
        if len(front):
            xs = front[tcol].astype(float).to_numpy()
            ys = scale * front[metric].astype(float).to_numpy()
            # the front as a staircase: each member holds until a costlier one is closer
            sx, sy = [xs[0]], [ys[0]]
            for x, y in zip(xs[1:], ys[1:]):
                sx += [x, x]
                sy += [sy[-1], y]
            ax.plot(sx, sy, "k--", lw=1, label="Pareto front", zorder=2)
        if metric.endswith("finest_m") and ref_id is not None:
            rr = t[t["member_id"] == ref_id]
            if len(rr) and _num(rr[tcol].iloc[0]):
                ax.axvline(float(rr[tcol].iloc[0]), color="grey", ls=":", lw=1)
                ax.annotate(f"reference: {rr['label'].iloc[0]}", (float(rr[tcol].iloc[0]), 0.02),
                            xycoords=("data", "axes fraction"), rotation=90, fontsize=8, color="grey",
                            xytext=(-10, 0), textcoords="offset points")
        if len(pts):
            from matplotlib.ticker import FuncFormatter

            ax.set_xscale("log")
            ax.set_yscale("log")
            def label(v: float, _pos) -> str:  # 1, 2, 3, 5 of each decade: readable, never crowded
                lead = round(v / 10 ** math.floor(math.log10(v) + 1e-9), 6) if v > 0 else 0
                return f"{v:g}" if lead in (1.0, 2.0, 3.0, 5.0) else ""

            for axis in (ax.xaxis, ax.yaxis):
                axis.set_major_formatter(FuncFormatter(label))
                axis.set_minor_formatter(FuncFormatter(label))
            ax.margins(x=0.12, y=0.08)
        else:
            ax.text(0.5, 0.5, "no finished member with this error", ha="center", va="center", transform=ax.transAxes)
        ax.set_xlabel(_TIME_LABELS[tcol])
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle(f"Speed against error: {study.sweep_dir.name}")
    fig.tight_layout()
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    tmp.replace(path)
    return path


def write_report(study: SpeedError, out_dir: str | Path | None = None) -> dict[str, Path]:
    """speed_error.csv, .md, .png and .json in out_dir (default SWEEP_DIR/report/)."""
    out = Path(out_dir) if out_dir is not None else study.sweep_dir / REPORT_DIR
    out.mkdir(parents=True, exist_ok=True)
    files = {"csv": out / "speed_error.csv", "markdown": out / "speed_error.md", "plot": out / "speed_error.png",
             "json": out / "speed_error.json"}
    study.table.to_csv(files["csv"], index=False, float_format="%.10g")
    files["markdown"].write_text(markdown(study))
    plot(study, files["plot"])
    study.files = files
    files["json"].write_text(json.dumps(study.headline(), indent=2, default=json_default))
    return files
