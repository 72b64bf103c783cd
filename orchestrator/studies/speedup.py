"""The planner against the hand-made set-up: speed-ups, and both extrapolated to finer cells.

Given the speed-against-error table of :func:`orchestrator.studies.speed_error.speed_error`
(one row per member: its set-up, cell size, cells, time steps, times and errors),
:func:`speedups` compares every hand-made (baseline) member with the planner's member of
the same cell size, and with the planner's time at the baseline's error (log-log
interpolation along the planner's members); :func:`extrapolate` carries both set-ups to a
finer cell size than was run (cells planned exactly, time steps and the cost per cell-step
scaled from the finest measured member). Extrapolated figures are labelled as such.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
import pandas as pd

from orchestrator.case.folder import CaseFolder
from orchestrator.core.numbers import finite_or_none
from orchestrator.plan.planner import plan_case
from orchestrator.scene.scenefile import load_scene

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


def speedups(table: pd.DataFrame, tcol: str, ref_id: str | None) -> list[dict[str, Any]]:
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
                entry[f"baseline_{metric}"] = finite_or_none(b.get(metric))
                entry[f"planner_{metric}"] = finite_or_none(p.get(metric))
        # equal error: the planner's time at the baseline's gauge error, along the planner's members
        # (the reference itself, at zero error against itself, is left out)
        curve = planner[(planner["member_id"] != ref_id)]
        err = finite_or_none(b.get("gauge_rmse_vs_finest_m"))
        if err is not None and len(curve) >= 2:
            t_eq, extrapolated = _interp_loglog(err, curve["gauge_rmse_vs_finest_m"].astype(float).tolist(),
                                                curve[tcol].astype(float).tolist(), reach=EQUAL_ERROR_REACH)
            entry["planner_time_at_equal_error_s"] = t_eq
            entry["equal_error_extrapolated"] = extrapolated
            if t_eq and b.get(tcol):
                entry["speedup_equal_error"] = b[tcol] / t_eq
        out.append(entry)
    return out


def extrapolate(members: list[dict], table: pd.DataFrame, tcol: str, cell_m: float) -> list[dict[str, Any]]:
    """Each set-up at `cell_m`: planned cells (exact); time steps from the finest measured member
    of that set-up, scaled as 1 / cell size (a Courant-limited step is proportional to the cell
    size: a lower bound where the step was capped by maxDeltaT on the measured member); the cost
    per cell-step of the finest member. The local exponent of the steps between the set-up's two
    finest members is reported beside it. An extrapolation, labelled as such."""
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
            scene = load_scene(CaseFolder(m["case"]).scene_path, [f"mesh.cell_size_m={cell_m}"])
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
