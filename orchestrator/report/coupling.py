"""One-way against two-way: the same scene run both ways, side by side.

``debrisfoam report coupling ONE_WAY TWO_WAY -o DIR`` (``make compare-coupling``) reads a
one-way run (the flow without the bodies, then the bodies carried through its record) and a
two-way run (the bodies on overset meshes in the flow) of the same scene on the same background
mesh, and writes into DIR:

``track_difference.csv``
    Per body and time step of the two-way run up to the comparison's end: the one-way centre
    (interpolated to that time) minus the two-way one along x, y and z, their distance, and the
    yaw difference.
``coupling.csv``
    The two runs' figures, a row each: the track difference up to the first strike (RMS, largest,
    at the strike), the first strike on the column (time, body, velocity, obliquity, height, the
    water level at the column's face, pulse, base shear), cells and wall times.
``bodies.csv``
    Per body: its track difference up to the comparison's end (RMS, largest, at the end, the yaw
    apart there) and its own first column strike in each run (time, velocity): how one-way
    multi-body transport follows each coupled body, not only the first to strike.
``drag_scan.csv``
    The one-way transport carried again through the one-way run's own record at several drag
    coefficients (``transport.drag_coefficient``), each against the two-way track up to the
    two-way run's first strike (RMS and largest centre distance) and its own first strike: the
    evidence for the coefficient's default (docs/one-way.md).
``drive.csv``
    With the one-way record read (``--drag-scan``): per body, once every body is afloat two-way,
    the mean fluid force (along, across, up) the two-way solver measures on it against the
    one-way forcing on the same body moving along the same track (:func:`~orchestrator.report.coupling_drive.fluid_drive`): what
    one-way transport leaves out (a body in another's wake, the water it pushes ahead of it near
    the column, how deep it floats); ``drive.png`` draws the streamwise ones against time.
``coupling.png``
    The tracks' x and z against time, both runs, and the centres' distance, up to the end of the
    shorter run; the first strikes marked.
``report.md``
    The page: the table and the figure, and what they say.

The comparison ends at the first strike on the column of either run (after it the bodies
rebound differently by construction), or at the shorter run's end when neither strikes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.core.files import write_text_atomic
from orchestrator.report.figures import legend, pyplot, save_figure
from orchestrator.report.layout_page import figure_text, minutes_text
from orchestrator.report.layouts import Layout, layout_row, load_layout
from orchestrator.results.tables import write_table
from orchestrator.report.coupling_drive import (AFLOAT_RISE_M, Drive, afloat_s, body_track, drive_figure, drive_lines,
                                                fluid_drive)
from orchestrator.transport.case_transport import case_flow, scene_settings, transport_setup
from orchestrator.transport.engine import run_transport
from orchestrator.transport.flow import FlowField

__all__ = ["CouplingComparison", "compare_coupling", "drag_scan", "drive_runs", "one_way_record", "scan_runs",
           "write_coupling_report"]

RUNS = ("one-way", "two-way")
#: drag coefficients the scan carries the bodies through the one-way record with
SCAN_DRAG_COEFFICIENTS = (1.05, 2.0, 2.5, 3.0, 3.5, 4.0)
@dataclass
class CouplingComparison:
    """The two runs, the time the comparison ends at, and the tracks' difference until then."""

    runs: dict[str, Layout]
    until_s: float
    #: why the comparison ends at until_s
    until_reason: str
    tracks: pd.DataFrame
    table: pd.DataFrame
    same_mesh: bool
    #: per body: track difference and each run's first column strike (:func:`_per_body`)
    per_body: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: the drag-coefficient scan (:func:`drag_scan`); empty until run
    scan: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: the fluid's force on each body afloat, measured two-way and as the one-way forcing gives it on
    #: the same track (:func:`~orchestrator.report.coupling_drive.fluid_drive`); empty until run
    drive: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: the series the drive's means are taken over (:class:`Drive`)
    drive_series: pd.DataFrame = field(default_factory=pd.DataFrame)


def _checked(path: str | Path, coupling: str, argument: str, allow_stopped: bool = False) -> Layout:
    lay = load_layout(path)
    stopped = allow_stopped and bool(lay.summary) and not lay.bodies.empty
    if not (lay.ok or stopped):
        hint = "; --allow-stopped compares it up to where it stopped" if lay.summary and not allow_stopped else ""
        raise InputError(argument, f"{path} has no finished, post-processed run ({lay.status}: "
                                   f"{lay.error or 'run `debrisfoam post` on it'}{hint})")
    if lay.coupling != coupling:
        raise InputError(argument, f"{path} is a {lay.coupling!r} run, not a {coupling} one")
    return lay


def _first_strike(lay: Layout) -> dict[str, Any] | None:
    return None if lay.strikes.empty else lay.strikes.iloc[0].to_dict()


def _track_differences(one: pd.DataFrame, two: pd.DataFrame, body: str, until_s: float) -> pd.DataFrame:
    """One body's one-way centre (interpolated) minus its two-way one at the two-way times up to until_s."""
    two = two[two["time_s"] <= until_s + 1e-9]
    t = two["time_s"].to_numpy(float)
    d = {a: np.interp(t, one["time_s"], one[f"{a}_m"]) - two[f"{a}_m"].to_numpy(float) for a in "xyz"}
    yaw = np.interp(t, one["time_s"], np.unwrap(np.radians(one["yaw_deg"])))
    dyaw = np.degrees(yaw - np.unwrap(np.radians(two["yaw_deg"].to_numpy(float))))
    return pd.DataFrame({"time_s": t, "body": body, "dx_m": d["x"], "dy_m": d["y"], "dz_m": d["z"],
                         "distance_m": np.sqrt(d["x"] ** 2 + d["y"] ** 2 + d["z"] ** 2), "dyaw_deg": dyaw})


def _differences(runs: dict[str, Layout], until_s: float) -> pd.DataFrame:
    rows = []
    for body in runs["two-way"].body_names:
        two, one = body_track(runs["two-way"], body), body_track(runs["one-way"], body)
        if not (two.empty or one.empty):
            rows.append(_track_differences(one, two, body, until_s))
    return pd.concat(rows, ignore_index=True) if rows else pd.DataFrame(
        columns=["time_s", "body", "dx_m", "dy_m", "dz_m", "distance_m", "dyaw_deg"])


def _freed_s(lay: Layout, body: str) -> float:
    """When the runner first let a body held on the bed float (run.json `freed`; NaN: never held or
    never freed). The runner holds a resting body until the water it measures all round the body is
    deep enough and the fluid lifts it by its weight (orchestrator/run/bedwatch.py)."""
    times = [float(f["time_s"]) for f in lay.run.freed if f.get("body") == body]
    return min(times) if times else float("nan")


def _per_body(runs: dict[str, Layout], tracks: pd.DataFrame) -> pd.DataFrame:
    """A row per body: its one-way centre's distance from the two-way one up to the comparison's
    end (RMS, largest, at the end), the x and yaw apart there, and its own first column strike
    in each run (time and impact velocity; NaN when it did not strike); when it left the bed in
    each run (`_afloat_s`; two-way also when the runner freed it, `_freed_s`) and how far apart
    the two were then."""
    rows = []
    for body, d in tracks.groupby("body", sort=False):
        d = d.sort_values("time_s")
        last = d.iloc[-1]
        row: dict[str, Any] = {"body": body, "track_rms_m": float(np.sqrt(np.mean(d["distance_m"] ** 2))),
                               "track_max_m": float(d["distance_m"].max()), "track_at_end_m": float(last["distance_m"]),
                               "dx_at_end_m": float(last["dx_m"]), "dyaw_at_end_deg": float(last["dyaw_deg"])}
        for kind, lay in runs.items():
            row[f"{kind.replace('-', '_')}_afloat_s"] = afloat_s(body_track(lay, body))
        freed = _freed_s(runs["two-way"], body)
        row["two_way_freed_s"] = freed
        inside = np.isfinite(freed) and freed <= float(d["time_s"].iloc[-1]) + 1e-9
        row["apart_at_freed_m"] = float(np.interp(freed, d["time_s"], d["distance_m"])) if inside else float("nan")
        for kind, lay in runs.items():
            strikes = lay.strikes
            own = strikes[strikes["body"] == body] if "body" in strikes else strikes.iloc[0:0]
            tag = kind.replace("-", "_")
            row[f"{tag}_strike_time_s"] = float(own["time_s"].iloc[0]) if len(own) else float("nan")
            row[f"{tag}_strike_velocity_m_s"] = (float(own["impact_velocity_m_s"].iloc[0]) if len(own)
                                                 else float("nan"))
        rows.append(row)
    return pd.DataFrame(rows)


def drag_scan(scene, flow: FlowField, two_way_tracks: dict[str, pd.DataFrame], until_s: float, end_s: float,
              coefficients=SCAN_DRAG_COEFFICIENTS) -> pd.DataFrame:
    """The scene's bodies carried through ``flow`` to ``end_s`` once per drag coefficient; per
    coefficient the centre distance to the two-way tracks up to ``until_s`` (RMS over bodies and
    times, largest) and the first strike on the column (time, body, velocity)."""
    rows = []
    for cd in coefficients:
        changed = scene.model_copy(update={"transport": scene.transport.model_copy(update={"drag_coefficient": cd})})
        bodies, flume, column = transport_setup(changed, flow)
        result = run_transport(bodies, flume, end_s, flow=flow, column=column, settings=scene_settings(changed))
        diffs = [_track_differences(result.track(b), t, b, until_s) for b, t in two_way_tracks.items() if not t.empty]
        dist = np.concatenate([d["distance_m"].to_numpy(float) for d in diffs]) if diffs else np.array([np.nan])
        impacts = result.impacts
        strikes = impacts[impacts["other"] == "column"] if len(impacts) else impacts
        first = strikes.iloc[0] if len(strikes) else None
        rows.append({"drag_coefficient": cd, "scene_default": cd == scene.transport.drag_coefficient,
                     "track_rms_m": float(np.sqrt(np.mean(dist ** 2))), "track_max_m": float(np.max(dist)),
                     "strike_time_s": None if first is None else float(first["time_s"]),
                     "strike_body": None if first is None else first["body"],
                     "strike_velocity_m_s": None if first is None else float(first["impact_velocity_m_s"])})
    return pd.DataFrame(rows)


def one_way_record(cmp: CouplingComparison) -> FlowField:
    """The one-way run's recorded flow (the flow without the bodies)."""
    return case_flow(cmp.runs["one-way"].case, say=lambda _: None)[0]


def scan_runs(cmp: CouplingComparison, coefficients=SCAN_DRAG_COEFFICIENTS, flow: FlowField | None = None) -> pd.DataFrame:
    """:func:`drag_scan` on the one-way run's own record (``flow``, read when None) against the
    two-way run, up to the two-way run's first strike (its end when it has none); fills ``cmp.scan``."""
    one, two = cmp.runs["one-way"], cmp.runs["two-way"]
    flow = one_way_record(cmp) if flow is None else flow
    strike = _first_strike(two)
    until = float(strike["time_s"]) if strike else float(two.summary.get("reached_time_s") or cmp.until_s)
    end = float(one.summary.get("reached_time_s") or until)
    cmp.scan = drag_scan(one.scene, flow, {b: body_track(two, b) for b in two.body_names}, until, end, coefficients)
    return cmp.scan


def drive_runs(cmp: CouplingComparison, flow: FlowField | None = None) -> Drive:
    """:func:`~orchestrator.report.coupling_drive.fluid_drive` up to the comparison's end with the
    one-way run's own record (``flow``, read when None); fills ``cmp.drive`` and ``cmp.drive_series``."""
    drive = fluid_drive(cmp.runs["one-way"], cmp.runs["two-way"], cmp.until_s,
                        one_way_record(cmp) if flow is None else flow)
    cmp.drive, cmp.drive_series = drive
    return drive


def _background_cells(lay: Layout) -> int | None:
    return lay.plan.background.cell_count() if lay.plan else None


def compare_coupling(one_way: str | Path, two_way: str | Path, allow_stopped: bool = False) -> CouplingComparison:
    """Read both runs and measure the one-way run against the two-way one (module notes).
    InputError naming the argument when a run is missing, unfinished (unless `allow_stopped`
    and post-processed as far as it got: then the comparison ends where it stopped), of the
    other coupling, or of other bodies."""
    runs = {"one-way": _checked(one_way, "one-way", "ONE_WAY", allow_stopped),
            "two-way": _checked(two_way, "two-way", "TWO_WAY", allow_stopped)}
    if sorted(runs["one-way"].body_names) != sorted(runs["two-way"].body_names):
        raise InputError("TWO_WAY", f"its bodies {runs['two-way'].body_names} are not the one-way run's "
                                    f"{runs['one-way'].body_names}")
    ends = {k: float(lay.summary.get("reached_time_s") or 0.0) for k, lay in runs.items()}
    strikes = {k: _first_strike(lay) for k, lay in runs.items()}
    struck = {k: float(s["time_s"]) for k, s in strikes.items() if s is not None}
    if struck:
        until_s = min(min(struck.values()), min(ends.values()))
        first = min(struck, key=struck.get)
        reason = f"the first strike on the column ({first}, t = {struck[first]:.3f} s)"
    else:
        until_s, reason = min(ends.values()), "the shorter run's end (neither run struck the column)"
    stopped = {k: lay for k, lay in runs.items() if not lay.ok}
    if stopped and until_s >= min(ends[k] for k in stopped) - 1e-9:
        k = min(stopped, key=lambda k: ends[k])
        reason = (f"where the {k} run stopped, before its end ({stopped[k].status}: "
                  f"{_stop_reason(stopped[k])})")
    tracks = _differences(runs, until_s)
    cells = [_background_cells(lay) for lay in runs.values()]
    same_mesh = cells[0] is not None and cells[0] == cells[1]
    table = pd.DataFrame([_row(k, lay, strikes[k], tracks) for k, lay in runs.items()])
    return CouplingComparison(runs, until_s, reason, tracks, table, same_mesh, _per_body(runs, tracks))


def _stop_reason(lay: Layout) -> str:
    """Why a run stopped before its end: its runner's error, else the reached time."""
    error = lay.run.error
    message = error.get("message") if isinstance(error, dict) else error
    if not message:
        return f"reached t = {figure_text(lay.summary.get('reached_time_s'), '.4g', ' s')}"
    return str(message).splitlines()[0]


def _text(value: Any) -> str:
    """A table cell's text: '-' for a missing value (None or NaN, as pandas gives it)."""
    return "-" if value is None or (isinstance(value, float) and np.isnan(value)) else str(value)


def _row(kind: str, lay: Layout, strike: dict | None, tracks: pd.DataFrame) -> dict[str, Any]:
    base = layout_row(lay)
    row: dict[str, Any] = {"run": kind, "case": str(lay.case), "status": lay.status, "cells": lay.summary.get("cells"),
                           "background_cells": _background_cells(lay), "reached_time_s": lay.summary.get("reached_time_s"),
                           "flow_wall_s": base.get("flow_wall_s"), "flow_cpu_s": base.get("flow_cpu_s"),
                           "transport_wall_s": base.get("transport_wall_s"), "column_strikes": base.get("column_strikes")}
    if kind == "one-way" and not tracks.empty:
        last = tracks.sort_values("time_s").groupby("body").last()
        row.update(track_rms_m=float(np.sqrt(np.mean(tracks["distance_m"] ** 2))),
                   track_max_m=float(tracks["distance_m"].max()), track_at_end_m=float(last["distance_m"].max()),
                   dx_at_end_m=float(last["dx_m"].iloc[0]), dyaw_at_end_deg=float(last["dyaw_deg"].iloc[0]))
    if strike:
        row.update({f"strike_{k}": strike.get(k) for k in (
            "body", "time_s", "impact_velocity_m_s", "obliquity_deg", "height_m", "face_water_level_m", "peak_force_N",
            "duration_s", "impulse_Ns", "peak_base_shear_N")})
    return row


# --------------------------------------------------------------------------- the page


STRIKE_ROWS = (
    ("time of the first strike", "strike_time_s", ".3f", " s"),
    ("impact velocity", "strike_impact_velocity_m_s", ".2f", " m/s"),
    ("obliquity", "strike_obliquity_deg", ".0f", " deg"),
    ("contact height above the bed", "strike_height_m", ".3f", " m"),
    ("water level at the column's face", "strike_face_water_level_m", ".3f", " m"),
    ("pulse: peak force", "strike_peak_force_N", ".0f", " N"),
    ("pulse: duration", "strike_duration_s", ".4f", " s"),
    ("pulse: impulse", "strike_impulse_Ns", ".3f", " N s"),
    ("peak base shear of the strike", "strike_peak_base_shear_N", ".0f", " N"),
    ("strikes on the column", "column_strikes", ".0f", ""),
)


def _per_body_lines(cmp: CouplingComparison) -> list[str]:
    """The per-body table (several bodies only)."""
    lines = ["## Each body", "",
             f"Each body's one-way centre against its two-way one up to t = {cmp.until_s:.3f} s (the comparison's "
             "end), and its own first strike on the column in each run (`bodies.csv`).", "",
             "| body | centre distance, RMS | largest | at the end | x apart at the end (+: one-way ahead) | "
             "yaw apart at the end | first strike, one-way | first strike, two-way |",
             "|---|---|---|---|---|---|---|---|"]
    for r in cmp.per_body.to_dict("records"):
        strikes = []
        for tag in ("one_way", "two_way"):
            t = figure_text(r[f"{tag}_strike_time_s"], ".3f", " s")
            strikes.append(t if t == "-" else f"{t} at {figure_text(r[f'{tag}_strike_velocity_m_s'], '.2f', ' m/s')}")
        lines.append(f"| {r['body']} | {figure_text(r['track_rms_m'], '.3f', ' m')} | "
                     f"{figure_text(r['track_max_m'], '.3f', ' m')} | {figure_text(r['track_at_end_m'], '.3f', ' m')} | "
                     f"{figure_text(r['dx_at_end_m'], '+.3f', ' m')} | {figure_text(r['dyaw_at_end_deg'], '+.1f', ' deg')} | "
                     f"{strikes[0]} | {strikes[1]} |")
    lines += ["", "When each body left the bed: afloat is when its centre first stood "
              f"{AFLOAT_RISE_M * 1000:g} mm above where it started; two-way, the runner holds a body resting on the "
              "bed until the water it measures all round the body is deep enough and the fluid lifts it by its "
              "weight (freed; v1912 has no contact, and a body freed earlier sank through the bed gap: "
              "docs/stability.md). One-way, the body floats when the recorded water lifts it.", "",
              "| body | afloat, one-way | afloat, two-way | freed, two-way | centres apart when freed |",
              "|---|---|---|---|---|"]
    for r in cmp.per_body.to_dict("records"):
        lines.append(f"| {r['body']} | {figure_text(r['one_way_afloat_s'], '.3f', ' s')} | "
                     f"{figure_text(r['two_way_afloat_s'], '.3f', ' s')} | {figure_text(r['two_way_freed_s'], '.3f', ' s')} | "
                     f"{figure_text(r['apart_at_freed_m'], '.3f', ' m')} |")
    return lines + [""]


def markdown(cmp: CouplingComparison, figure: str | None) -> str:
    one, two = (cmp.table.set_index("run").loc[k].to_dict() for k in RUNS)
    lines = ["# One-way against two-way", "",
             "Generated by `debrisfoam report coupling` (`make compare-coupling`) from the two runs; never edited by "
             "hand. Tables: `coupling.csv`, `track_difference.csv`.", "",
             f"- one-way: `{one['case']}`; two-way: `{two['case']}`.",
             f"- Background mesh: {figure_text(one.get('background_cells'), ',.0f')} cells one-way, "
             f"{figure_text(two.get('background_cells'), ',.0f')} two-way ("
             + ("the same mesh" if cmp.same_mesh else "different meshes: the comparison mixes mesh and coupling") + ").",
             f"- Runs: one-way {one.get('status')} at t = {figure_text(one.get('reached_time_s'), '.3f', ' s')}, "
             f"two-way {two.get('status')} at t = {figure_text(two.get('reached_time_s'), '.3f', ' s')}.",
             f"- The tracks are compared from the start to {cmp.until_reason}: t = {cmp.until_s:.3f} s.", "",
             "## The track until the first strike", "",
             "| | one-way minus two-way |", "|---|---|",
             f"| centre distance, RMS | {figure_text(one.get('track_rms_m'), '.3f', ' m')} |",
             f"| centre distance, largest | {figure_text(one.get('track_max_m'), '.3f', ' m')} |",
             f"| centre distance at t = {cmp.until_s:.3f} s | {figure_text(one.get('track_at_end_m'), '.3f', ' m')} |",
             f"| x difference at t = {cmp.until_s:.3f} s (+: one-way ahead) | {figure_text(one.get('dx_at_end_m'), '+.3f', ' m')} |",
             f"| yaw difference at t = {cmp.until_s:.3f} s | {figure_text(one.get('dyaw_at_end_deg'), '+.1f', ' deg')} |", "",
             "## The first strike and the cost", "",
             "| | one-way | two-way |", "|---|---|---|",
             f"| striking body | {_text(one.get('strike_body'))} | {_text(two.get('strike_body'))} |"]
    for label, key, fmt, unit in STRIKE_ROWS:
        lines.append(f"| {label} | {figure_text(one.get(key), fmt, unit)} | {figure_text(two.get(key), fmt, unit)} |")
    lines += [f"| cells | {figure_text(one.get('cells'), ',.0f')} | {figure_text(two.get('cells'), ',.0f')} |",
              f"| flow solver wall time (master rank's CPU) | {minutes_text(one.get('flow_wall_s'))} "
              f"({minutes_text(one.get('flow_cpu_s'))}) | {minutes_text(two.get('flow_wall_s'))} ({minutes_text(two.get('flow_cpu_s'))}) |",
              f"| transport wall time | {figure_text(one.get('transport_wall_s'), '.1f', ' s')} | - |", ""]
    if len(cmp.per_body) > 1:
        lines += _per_body_lines(cmp)
    if not cmp.scan.empty:
        lines += ["## The drag coefficient", "",
                  "The one-way transport carried again through the same record at other drag coefficients "
                  "(`transport.drag_coefficient`; the scene's value marked), each against the two-way track up to the "
                  "two-way run's first strike; `drag_scan.csv`.", "",
                  "| C_d | centre distance, RMS | largest | first strike | its velocity |", "|---|---|---|---|---|"]
        for r in cmp.scan.to_dict("records"):
            cd = f"**{r['drag_coefficient']:g}** (the scene's)" if r["scene_default"] else f"{r['drag_coefficient']:g}"
            lines.append(f"| {cd} | {figure_text(r['track_rms_m'], '.3f', ' m')} | {figure_text(r['track_max_m'], '.3f', ' m')} | "
                         f"{figure_text(r['strike_time_s'], '.3f', ' s')} | {figure_text(r['strike_velocity_m_s'], '.2f', ' m/s')} |")
        two_strike = two.get("strike_time_s")
        if figure_text(two_strike) == "-":
            lines += ["", f"The two-way run did not strike the column up to t = {cmp.until_s:.3f} s: the scan "
                          "measures the tracks to there.", ""]
        else:
            lines += ["", f"The two-way run's first strike: {figure_text(two_strike, '.3f', ' s')} at "
                          f"{figure_text(two.get('strike_impact_velocity_m_s'), '.2f', ' m/s')}.", ""]
    if not cmp.drive.empty:
        lines += drive_lines(cmp.drive, cmp.drive_series)
    if figure:
        lines += [f"![tracks]({figure})", "",
                  "The bodies' x and z against time in both runs and the distance between their centres; the "
                  "dotted line marks the end of the comparison.", ""]
    return "\n".join(lines)


def _figure(cmp: CouplingComparison, path: Path) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
    styles = {"one-way": "-", "two-way": "--"}
    for kind, lay in cmp.runs.items():
        for body in lay.body_names:
            t = body_track(lay, body)
            axes[0].plot(t["time_s"], t["x_m"], styles[kind], label=f"{body}, {kind}")
            axes[1].plot(t["time_s"], t["z_m"], styles[kind], label=f"{body}, {kind}")
    for body, d in cmp.tracks.groupby("body"):
        axes[2].plot(d["time_s"], d["distance_m"], label=body)
    for ax in axes:
        ax.axvline(cmp.until_s, color="0.4", linestyle=":")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("x of the centre (m)")
    axes[1].set_ylabel("z of the centre (m)")
    axes[2].set_ylabel("one-way to two-way\ncentre distance (m)")
    axes[2].set_xlabel("time (s)")
    legend(axes[0], fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def write_coupling_report(cmp: CouplingComparison, out_dir: str | Path) -> dict[str, Path]:
    """The page, its tables and its figure into out_dir (module notes); name -> path."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = {"coupling": write_table(cmp.table, out / "coupling.csv"),
               "track_difference": write_table(cmp.tracks, out / "track_difference.csv"),
               **({"bodies": write_table(cmp.per_body, out / "bodies.csv")} if len(cmp.per_body) > 1 else {}),
               **({"drag_scan": write_table(cmp.scan, out / "drag_scan.csv")} if not cmp.scan.empty else {}),
               **({"drive": write_table(cmp.drive, out / "drive.csv")} if not cmp.drive.empty else {}),
               "figure": _figure(cmp, out / "coupling.png")}
    if not cmp.drive_series.empty:
        written["drive_figure"] = drive_figure(cmp.drive_series, out / "drive.png")
    written["report"] = write_text_atomic(out / "report.md", markdown(cmp, written["figure"].name))
    return written
