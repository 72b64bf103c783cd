"""Every table of a run, built in memory: :func:`tables` reads a case and returns
:class:`Results` (the frames post-processing writes as CSV, and what could not be made).

The tables (see :mod:`orchestrator.report.postprocess` for the files): the gauges'
elevations and summary (:mod:`orchestrator.results.gauge_table`), the forces on the column
(hydrodynamic, from the ``forces`` function object, plus the impact pulses, on one time axis:
the solver's steps and every sample of every pulse), the bodies' tracks, the impacts
(:mod:`orchestrator.results.impact_table`, each column strike's base shear fitted as the study
fitted its records: :mod:`orchestrator.results.study_fit`), the column's response
(:func:`orchestrator.results.metrics.column_response`), the water balance and, for overset
runs, the flux into the fringe (:mod:`orchestrator.results.fringe`). Whatever a case lacks (a
run stopped early, no debris, no contacts) becomes a line of ``Results.missing``, never an
error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.case.outputs import (
    ATMOSPHERE_LOSS_WARNING,
    WATER_BALANCE_TOLERANCE,
    atmosphere_loss,
    read_force_series,
    read_water_balance,
    water_balance_summary,
)
from orchestrator.contact.events import read_events
from orchestrator.core.files import write_text_atomic
from orchestrator.results.fringe import fringe_table
from orchestrator.results.gauge_table import gauge_tables
from orchestrator.results.impact_table import impact_context, impact_rows
from orchestrator.results.metrics import column_response, pulse_sum
from orchestrator.results.readers import BODY_COLUMNS, CaseData, load_case, read_body_tracks
from orchestrator.results.study_fit import add_study_fits

__all__ = ["Results", "atmosphere_warning", "tables", "write_table"]

#: How the tables' numbers are written to CSV (ten significant digits).
CSV_FLOAT_FORMAT = "%.10g"


@dataclass
class Results:
    """The tables of a case as DataFrames, and what could not be made."""

    data: CaseData
    gauges: pd.DataFrame
    gauge_summary: pd.DataFrame
    column_forces: pd.DataFrame
    bodies: pd.DataFrame
    impacts: pd.DataFrame
    column_response: pd.DataFrame
    #: event number -> (time_s, force on the column (n, 3) N) of each column impact
    pulses: dict[int, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    #: effective heights (m above the base) of the hydrodynamic load, per direction
    hydro_heights_m: dict[str, float] = field(default_factory=dict)
    missing: list[str] = field(default_factory=list)
    reached_time_s: float | None = None
    #: per step: water volume, outflow and the balance error (:func:`orchestrator.case.outputs.read_water_balance`)
    water_balance: pd.DataFrame | None = None
    #: overset: per reconstructed time and zone, the flux into the fringe (:mod:`orchestrator.results.fringe`)
    fringe_flux: pd.DataFrame | None = None


def tables(case_dir: str | Path, arrival_threshold_m: float | None = None) -> Results:
    """Read a case and build every table (nothing written): see the module docstring."""
    data = load_case(case_dir)
    missing = list(data.notes)
    gauges, gauge_summary = gauge_tables(data, arrival_threshold_m)
    _note_gauges(gauge_summary, missing)
    hydro, note = _hydro_table(data)
    if note:
        missing.append(note)
    if hydro is None and (data.scene is None or data.scene.column is not None):
        missing.append("no column force output (postProcessing/columnForces)")
    events = read_events(data.case)
    impacts, pulses = impact_rows(data, events, missing)
    forces = _column_forces(hydro, pulses)
    names = data.body_names
    bodies = read_body_tracks(data.case, data.solver, names) if (data.solver and names) else pd.DataFrame(
        columns=BODY_COLUMNS)
    if names and bodies.empty:
        missing.append("no body reports in the solver logs (and no bodies.csv from the runner)")
    impacts = impact_context(data, impacts, gauges, bodies, missing)
    impacts = add_study_fits(data, impacts, events, missing)
    if names and not events:
        missing.append("no contact events (contacts.json): no impact pulses")
    response, heights = pd.DataFrame(columns=["time_s"]), {}
    if data.column is not None and (hydro is not None or pulses):
        height_of = {int(r.event): float(r.height_m) for r in impacts.itertuples() if r.kind == "column"}
        response, heights = column_response(data.column, hydro, pulses, height_of)
    elif data.column is None:
        missing.append("no column in the scene: no column forces or response")
    reached = _reached_time(data, gauges, forces, bodies)
    balance = read_water_balance(data.case)
    fringe = _fringe_flux(data, missing)
    _note_balance(data, balance, fringe, missing)
    return Results(data, gauges, gauge_summary, forces, bodies, impacts, response, pulses, heights, missing, reached,
                   balance, fringe)


def write_table(frame: pd.DataFrame, path: Path) -> Path:
    """One table as CSV (no index, :data:`CSV_FLOAT_FORMAT`), written atomically; returns its path."""
    return write_text_atomic(path, frame.to_csv(index=False, float_format=CSV_FLOAT_FORMAT))


def _note_gauges(gauge_summary: pd.DataFrame, missing: list[str]) -> None:
    """No gauge output at all, or the gauges whose line was obstructed."""
    if gauge_summary.empty:
        missing.append("no gauge output (postProcessing/gauges)")
        return
    blocked = gauge_summary[gauge_summary["obstructed_samples"] > 0]
    for r in blocked.itertuples():
        missing.append(f"gauge {r.gauge}: line obstructed (by a body, or outside the mesh) at "
                       f"{r.obstructed_samples} of {r.samples} samples; no elevation there")


def _note_balance(data: CaseData, balance: pd.DataFrame | None, fringe: pd.DataFrame | None,
                  missing: list[str]) -> None:
    """No water balance output, water not conserved, or water lost over the top of the air space."""
    if balance is None:
        missing.append("no water balance output (postProcessing/waterVolume): rendered before it existed?")
        return
    b = water_balance_summary(balance)
    if abs(b["max_error"]) > WATER_BALANCE_TOLERANCE:
        missing.append(
            f"water not conserved: {abs(b['max_error']) * 100:.2f} % of the initial water "
            f"{'created' if b['max_error'] > 0 else 'lost'} by t = {b['time_of_max_error_s']:.3g} s "
            f"(over the {WATER_BALANCE_TOLERANCE * 100:g} % bound; results/water_balance.csv; docs/stability.md)"
            + _fringe_note(fringe))
    warning = atmosphere_warning(data, balance)
    if warning:
        missing.append(warning)


# --------------------------------------------------------------------------- column forces


_PART = {"total": "hydro", "pressure": "pressure", "viscous": "viscous"}


def _hydro_table(data: CaseData) -> tuple[pd.DataFrame | None, str | None]:
    """hydro_force_*, pressure_force_*, viscous_force_*, hydro_moment_* about the column's base."""
    forces, meta = read_force_series(data.case, "columnForces", "force")
    if forces is None or forces.empty:
        return None, None
    out = pd.DataFrame({"time_s": forces["time"].to_numpy(float)})
    for name in forces.columns[1:]:
        part, _, axis = name.rpartition("_")
        if part in _PART and axis in "xyz":
            out[f"{_PART[part]}_force_{axis}_N"] = forces[name].to_numpy(float)
    moments, mmeta = read_force_series(data.case, "columnForces", "moment")
    note = None
    if moments is not None and not moments.empty:
        m = moments.set_index("time").reindex(out["time_s"])
        cols = {a: f"total_{a}" for a in "xyz"}
        if all(c in m.columns for c in cols.values()) and all(f"hydro_force_{a}_N" in out for a in "xyz"):
            moment = m[[cols[a] for a in "xyz"]].to_numpy(float)
            base = data.column_base_m()
            cofr = np.asarray(mmeta.get("CofR", meta.get("CofR", (0.0, 0.0, 0.0))), dtype=float)
            if base is not None and cofr.shape == (3,):
                # M_base = M_cofr + (cofr - base) x F
                force = out[[f"hydro_force_{a}_N" for a in "xyz"]].to_numpy(float)
                moment = moment + np.cross(cofr - base, force)
            elif base is None:
                note = "the moment is about the forces function object's CofR (no column in the scene)"
            for i, a in enumerate("xyz"):
                out[f"hydro_moment_{a}_Nm"] = moment[:, i]
    return out, note


def _column_forces(hydro: pd.DataFrame | None, pulses) -> pd.DataFrame:
    """column_forces.csv: the hydrodynamic force (NaN outside the solver's output times), the
    impact pulses and their sum, on the solver's steps plus every sample of every pulse."""
    times = [hydro["time_s"].to_numpy(float)] if hydro is not None else []
    times += [p[0] for p in pulses.values()]
    if not times:
        return pd.DataFrame(columns=["time_s"])
    t = np.unique(np.concatenate(times))
    out = pd.DataFrame({"time_s": t})
    if hydro is not None:
        th = hydro["time_s"].to_numpy(float)
        for name in hydro.columns[1:]:
            values = np.interp(t, th, hydro[name].to_numpy(float))
            values[(t < th[0]) | (t > th[-1])] = np.nan
            out[name] = values
    impact = pulse_sum(pulses, t)
    for i, a in enumerate("xyz"):
        out[f"impact_force_{a}_N"] = impact[:, i]
    for i, a in enumerate("xyz"):
        hydro_a = out[f"hydro_force_{a}_N"] if f"hydro_force_{a}_N" in out else 0.0
        out[f"total_force_{a}_N"] = hydro_a + impact[:, i]
    return out


# --------------------------------------------------------------------------- water and time


def atmosphere_warning(data: CaseData, balance: pd.DataFrame | None) -> str | None:
    """The sentence post-processing warns with when more than :data:`ATMOSPHERE_LOSS_WARNING` of the water
    left through the top of the air space; None otherwise."""
    loss = atmosphere_loss(balance)
    if loss is None or loss[1] is None:
        return None
    top = data.plan.domain_m[2][1] if data.plan else None
    where = f" at z = {top:.3g} m" if top is not None else ""
    return (f"water left through the top of the air space{where}: {loss[0] * 100:.2f} % of the initial water "
            f"by the end (past {ATMOSPHERE_LOSS_WARNING * 100:g} % at t = {loss[1]:.3g} s); the water balance "
            "books it as outflow. The run-up rose above the modelled air space: raise it with mesh.top_m "
            "(plan.json reasons.domain_top; results/water_balance.csv, outflow_atmosphere_m3)")


def _fringe_flux(data: CaseData, missing: list[str]) -> pd.DataFrame | None:
    """The overset fringe flux of the reconstructed times (None when not overset or none has the fields)."""
    if data.solver != "overInterDyMFoam":
        return None
    try:
        return fringe_table(data.case)
    except (OSError, ValueError) as exc:
        missing.append(f"no fringe flux: {exc}")
        return None


def _fringe_note(fringe: pd.DataFrame | None) -> str:
    """What the background's fringe took in at the last reconstructed time, for the balance's message."""
    if fringe is None or fringe.empty:
        return ""
    last = fringe[(fringe["zone"] == 0) & (fringe["time_s"] == fringe["time_s"].max())]
    if last.empty:
        return ""
    row = last.iloc[0]
    return (f"; at t = {row.time_s:g} s {row.water_into_fringe_m3_s:.3g} m3/s of water flowed into the "
            f"background's {int(row.fringe)} overset fringe cells, which v1912 overwrites by interpolation "
            f"(results/fringe_flux.csv; docs/openfoam-notes.md)")


def _reached_time(data: CaseData, *frames: pd.DataFrame) -> float | None:
    """The time the run reached: run.json's when it finished, else the latest time any table or segment holds."""
    run = data.run
    if run.reached_time_s is not None and run.finished:
        return run.reached_time_s
    last = [float(f["time_s"].max()) for f in frames if not f.empty and "time_s" in f]
    segs = run.segments
    if segs:
        try:
            last.append(float(segs[-1]["end_time"]))
        except (KeyError, ValueError):
            pass
    return max(last) if last else None
