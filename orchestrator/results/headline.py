"""The headline figures of a run, as summary.json holds them: status, reached time, wall time,
cells, each gauge's arrival and peak, the peak hydrodynamic force, the impacts (the first in
full, resting and pinned contacts), the column's peak base shear and the water balance.

Every number is a finite float or None (:func:`orchestrator.core.numbers.finite_or_none`), so
the JSON holds no NaN.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from orchestrator.case.outputs import water_balance_summary
from orchestrator.case.run_state import RunState
from orchestrator.contact.events import read_events
from orchestrator.core.numbers import finite_or_none
from orchestrator.results.readers import CaseData
from orchestrator.results.tables import Results

__all__ = ["headline"]


def _wall_times(run: RunState) -> dict[str, float | None]:
    """Wall time (s) of the solver's segments, the meshing steps, and in all."""
    if not run.recorded:
        return {"solver_s": None, "mesh_s": None, "total_s": None}
    solver = sum(float(s.get("wall_s", 0.0)) for s in run.segments)
    mesh = sum(float(s.get("wall_s", 0.0)) for s in run.steps if not s.get("skipped"))
    between = float(run.runner.get("between_segments_s", 0.0))
    return {"solver_s": round(solver, 3), "mesh_s": round(mesh, 3), "total_s": round(solver + mesh + between, 3)}


def _cells(data: CaseData) -> int | None:
    """The mesh's cell count: as run, else as planned."""
    cells = data.run.cells
    for key in ("total", "planned"):
        if cells.get(key):
            return int(cells[key])
    if data.plan and data.plan.cell_count:
        return int(data.plan.cell_count)
    return None


def headline(results: Results) -> dict[str, Any]:
    """The headline figures of summary.json (comparisons add theirs under "comparisons")."""
    data = results.data
    out = _run_figures(results)
    out["gauges"] = {
        r.gauge: {"x_m": finite_or_none(r.x_m), "arrival_s": finite_or_none(r.arrival_s),
                  "peak_elevation_m": finite_or_none(r.peak_elevation_m),
                  "time_of_peak_s": finite_or_none(r.time_of_peak_s)}
        for r in results.gauge_summary.itertuples()
    }
    cf = results.column_forces
    if "hydro_force_x_N" in cf and cf["hydro_force_x_N"].notna().any():
        i = int(cf["hydro_force_x_N"].abs().idxmax())
        out["hydro_force"] = {"peak_x_N": finite_or_none(cf.loc[i, "hydro_force_x_N"]),
                              "time_of_peak_s": finite_or_none(cf.loc[i, "time_s"])}
    out["impacts"] = _impact_figures(results)
    out["impacts"].update(_contact_figures(read_events(data.case)))
    cr = results.column_response
    if "base_shear_x_N" in cr and len(cr):
        out["column_response"] = _response_figures(results)
    if not results.bodies.empty:
        out["bodies"] = sorted(results.bodies["body"].unique().tolist())
    balance = water_balance_summary(results.water_balance)
    if balance is not None:
        out["water_balance"] = balance
    return out


def _run_figures(results: Results) -> dict[str, Any]:
    """The run as run.json records it: status, end and reached times, cells, wall time, steps."""
    data = results.data
    run = data.run
    status = run.status or ("unknown (no run.json: run by hand?)" if not run.recorded else "unknown")
    end = run.end_time_s or (data.scene.run.end_time_s if data.scene else None)
    return {
        "case": str(data.case),
        "scene": data.scene.name if data.scene is not None else None,
        "solver": data.solver,
        "status": status,
        "end_time_s": finite_or_none(end),
        "reached_time_s": finite_or_none(results.reached_time_s),
        "complete": status == "finished",
        "cells": _cells(data),
        "wall_time_s": _wall_times(data.run),
        "time_steps": run.time_steps,
    }


def _impact_figures(results: Results) -> dict[str, Any]:
    """The number of impacts, those on the column, the first in full and the peak force."""
    imp = results.impacts
    out: dict[str, Any] = {"count": int(len(imp)), "on_column": int((imp["kind"] == "column").sum()) if len(imp) else 0}
    if not len(imp):
        return out
    first = imp.sort_values("time_s").iloc[0]
    out["first"] = {
        "event": int(first["event"]), "time_s": finite_or_none(first["time_s"]), "body": first["body"],
        "other": first["other"], "impact_velocity_m_s": finite_or_none(first["impact_velocity_m_s"]),
        "peak_force_N": finite_or_none(first["peak_force_N"]), "duration_s": finite_or_none(first["duration_s"]),
        "impulse_Ns": finite_or_none(first["impulse_Ns"]), "height_m": finite_or_none(first["height_m"]),
        "face_water_level_m": finite_or_none(first["face_water_level_m"]),
        "time_since_front_s": finite_or_none(first.get("time_since_front_s")),  # a one-way strike's
        "body_clearance_m": finite_or_none(first["body_clearance_m"]),
        "afloat": None if first["afloat"] is None or first["afloat"] != first["afloat"] else bool(first["afloat"]),
    }
    out["peak_force_N"] = finite_or_none(imp["peak_force_N"].max())
    return out


def _contact_figures(events: list[dict]) -> dict[str, Any]:
    """The contacts that were not impacts: resting ones counted, pinned bodies and bodies kept on the bed."""
    out: dict[str, Any] = {}
    resting = [e for e in events if e.get("type") == "resting"]
    if resting:
        out["resting_contacts"] = len(resting)
    pinned = [{"body": e["body"], "other": e["other"], "time_s": finite_or_none(e["time_s"])}
              for e in events if e.get("type") == "pinned"]
    if pinned:  # held against an obstacle by the flow from then on (the runner froze it there)
        out["pinned"] = pinned
    on_bed = [{"body": e["body"], "time_s": finite_or_none(e["time_s"])}
              for e in events if e.get("type") == "rest_on_bed"]
    if on_bed:  # kept on the bed's plane from then on (the flow kept pulling it into the bed)
        out["rest_on_bed"] = on_bed
    return out


def _response_figures(results: Results) -> dict[str, Any]:
    """The column's peak base shear (horizontal magnitude), its time, the impacts' peak part."""
    cr, data = results.column_response, results.data
    shear = np.hypot(cr["base_shear_x_N"].to_numpy(float), cr["base_shear_y_N"].to_numpy(float))
    i = int(np.nanargmax(shear))
    return {
        "peak_base_shear_N": finite_or_none(shear[i]), "time_of_peak_s": finite_or_none(cr["time_s"].iloc[i]),
        "peak_impact_base_shear_N": finite_or_none(np.nanmax(np.abs(cr["impact_base_shear_x_N"]))),
        "hydro_load_height_m": {k: round(v, 4) for k, v in results.hydro_heights_m.items()},
        "column_base": data.column.base if data.column is not None else None,
    }
