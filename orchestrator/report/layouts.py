"""`debrisfoam report layouts RUNS... -o DIR`: several debris layouts of one scene side by side,
in the manner of the study's Figs. 12-16 (``make results-layouts`` on the four layouts of
``cases/sweeps/debris-layouts.yaml``).

RUNS are post-processed case folders, or sweep folders whose members are read in member order.
Every layout is read from what its run left (``results/*.csv``, ``results/summary.json``,
``run.json``, ``contacts/eventNNNN-*.csv``, ``transport/body_contacts.csv``, ``contacts.json``);
nothing is computed again but what this page adds. DIR receives:

``report.md``
    the page: the runs (cells, wall times, strikes, contacts), the flow of every layout overlaid
    and how far the layouts' flows differ, then per layout its tracks, its strikes and its
    body-body contacts; written by this module, never by hand.
``layouts.csv``
    one row per layout: the figures of the page's first table.
``impacts.csv``
    every strike on the column of every layout: time, body, velocity along the contact normal,
    obliquity, contact height, water level at the column's face, the body's yaw, pitch and roll at
    the strike (interpolated in its track, ``bodies.csv``), the pulse (peak, duration, impulse)
    and the peak base shear the pulse causes at the load cell (``contacts/eventNNNN-base-shear.csv``).
``body_contacts.csv``
    every contact between two bodies: time, pair, approach and separation velocities.
``flow_agreement.csv``
    per layout and gauge (and the column's hydrodynamic force): the peak, and the largest
    difference from the first layout's record on its time axis.
``flow.png``, ``impact_summary.png``, ``<layout>-tracks.png``, ``<layout>-impacts.png``
    the figures (:mod:`orchestrator.report.layout_plots`).

A layout whose run did not finish (no ``results/summary.json``) is listed with its status, its
error and the log to read, and left out of the figures.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.case.folder import CaseFolder
from orchestrator.case.run_state import RunState
from orchestrator.contact.events import read_events
from orchestrator.core.files import read_json_object, write_text_atomic
from orchestrator.plan.model import ModelPlan
from orchestrator.report import layout_plots
from orchestrator.report.layout_page import markdown
from orchestrator.results.compare import SPREADING_ANGLES_DEG, spreading_area
from orchestrator.results.tables import write_table
from orchestrator.transport.case_transport import TRANSPORT_DIR

__all__ = ["IMPACT_TABLE_COLUMNS", "Layout", "find_runs", "flow_agreement", "impact_table", "layout_row", "load_layout",
           "write_layouts_report"]

#: The gauges the study reports (its WG1-WG4), in order.
GAUGES = ("WG1", "WG2", "WG3", "WG4")
#: Columns of the page's impacts.csv, in order.
IMPACT_TABLE_COLUMNS = [
    "layout", "event", "strike", "body", "time_s", "impact_velocity_m_s", "obliquity_deg", "height_m",
    "face_water_level_m", "yaw_deg", "pitch_deg", "roll_deg", "peak_force_N", "duration_s", "impulse_Ns",
    "peak_base_shear_N", "point_x_m", "point_y_m", "force_history"]
#: The transport's planes at the flow record's ends (MuJoCo geoms wall_x0, wall_x1), not the flume's walls.
END_WALLS = ("wall_x",)
#: The file a sweep folder holds (its members are the runs).
SWEEP_JSON = "sweep.json"
MEMBER_JSON = "member.json"


@dataclass
class Layout:
    """One layout's run as the page reads it; the frames are empty when the run has no results."""

    name: str
    case: Path
    status: str
    error: str | None = None
    log: str | None = None
    scene: Any | None = None
    run: RunState = field(default_factory=RunState)
    plan: ModelPlan | None = None
    member: dict = field(default_factory=dict)
    summary: dict = field(default_factory=dict)
    bodies: pd.DataFrame = field(default_factory=pd.DataFrame)
    strikes: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: event -> ((time from contact s, force on the column N), (time s, base shear N) or None)
    pulses: dict[int, tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray] | None]] = field(default_factory=dict)
    body_contacts: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: contacts with the flume's side walls
    wall_contacts: int = 0
    #: contacts with the record's end walls (the transport's planes at the flow record's ends,
    #: plan.json flow_record.region_m: they keep bodies inside the record, they are not the flume's)
    end_contacts: int = 0
    #: body -> (first time it met a record's end wall s, that wall's x m)
    at_record_end: dict[str, tuple[float, float]] = field(default_factory=dict)
    gauges: pd.DataFrame = field(default_factory=pd.DataFrame)
    gauge_summary: pd.DataFrame = field(default_factory=pd.DataFrame)
    hydro: pd.DataFrame = field(default_factory=pd.DataFrame)
    spreading: pd.DataFrame = field(default_factory=pd.DataFrame)

    @property
    def ok(self) -> bool:
        return self.status == "finished" and bool(self.summary)

    @property
    def body_names(self) -> list[str]:
        if self.scene is not None:
            return [b.name for b in self.scene.debris]
        return sorted(self.bodies["body"].unique()) if not self.bodies.empty else []

    @property
    def coupling(self) -> str | None:
        """How the debris met the flow (plan.json debris_coupling); None without a plan."""
        return self.plan.debris_coupling if self.plan else None

    @property
    def domain_m(self) -> tuple | None:
        """((x0, x1), (y0, y1), (z0, z1)) of the modelled flume; None without a plan."""
        return self.plan.domain_m if self.plan else None

    @property
    def record_region_m(self) -> tuple | None:
        """((x0, x1), (y0, y1), (bed, top)) of a one-way run's flow record; None otherwise."""
        return self.plan.flow_record.region_m if self.plan and self.plan.flow_record else None

    @property
    def slug(self) -> str:
        return "".join(c if c.isalnum() or c in "-_" else "-" for c in self.name)

    def areas(self) -> dict[str, np.ndarray]:
        """The spreading areas from the bodies' start line (as post's spreading.csv draws them)."""
        if self.bodies.empty:
            return {}
        start = self.bodies.sort_values("time_s", kind="stable").groupby("body", sort=False).first()
        src = start[["x_m", "y_m"]].to_numpy(float)
        x_end = float(self.domain_m[0][1]) if self.domain_m else float(src[:, 0].max() + 5.0)
        return {name: spreading_area(src, spec["half_angle_deg"], x_end) for name, spec in SPREADING_ANGLES_DEG.items()}


def _csv(path: Path) -> pd.DataFrame:
    try:
        return pd.read_csv(path) if path.is_file() and path.stat().st_size > 0 else pd.DataFrame()
    except pd.errors.EmptyDataError:  # a table post wrote without rows or columns ("\n")
        return pd.DataFrame()
    except (ValueError, pd.errors.ParserError) as exc:
        raise InputError(path.name, f"not a table ({exc}): post-process the run again", str(path.parent)) from None


def find_runs(paths) -> list[Path]:
    """The case folders of RUNS: each path itself, or a sweep folder's members in member order
    (those sweep.json lists, when it lists them: a folder left by an earlier form of the sweep,
    whose scenes have since changed, is not one of its members)."""
    out: list[Path] = []
    for raw in paths:
        path = Path(raw)
        if not path.is_dir():
            raise InputError("RUNS", "not a folder", str(path))
        if (path / SWEEP_JSON).is_file():
            sweep = read_json_object(path / SWEEP_JSON)
            if sweep is None:
                raise InputError("RUNS", f"{SWEEP_JSON} is not a JSON object (a sweep folder's record)", str(path))
            listed = sweep.get("members")
            ids = {str(m["id"]) for m in listed} if listed else None
            members = []
            for m in path.iterdir():
                record = m / MEMBER_JSON
                if record.is_file() and (ids is None or m.name in ids):
                    members.append(((read_json_object(record) or {}).get("member", 0), m))
            if not members:
                raise InputError("RUNS", "a sweep folder without members (run the sweep first)", str(path))
            out += [m for _, m in sorted(members)]
        elif CaseFolder(path).is_case():
            out.append(path)
        else:
            raise InputError("RUNS", "neither a case folder (plan.json) nor a sweep folder (sweep.json)", str(path))
    if not out:
        raise InputError("RUNS", "no runs given")
    return out


def _failure(folder: CaseFolder, run: RunState, member: dict) -> tuple[str, str | None, str | None]:
    """(status, error, log) of a run without results: the sweep's record, else run.json's."""
    status = member.get("status") or run.status or "not run"
    error = member.get("error") or run.error or (dict(run.diagnosis) or None)
    log = (run.logs(failed_only=True) or run.logs() or [None])[-1]
    if status == "finished":
        status, error = "not post-processed", error or "no results/summary.json (run `debrisfoam post` on it)"
    return status, error, str(folder.path / log) if log else None


def _orientation_at(track: pd.DataFrame, t: float) -> tuple[float, float, float]:
    """(yaw, pitch, roll) in degrees at time t, interpolated in the track (yaw unwrapped first)."""
    if track.empty:
        return (np.nan, np.nan, np.nan)
    times = track["time_s"].to_numpy(float)
    out = []
    for name in ("yaw_deg", "pitch_deg", "roll_deg"):
        angle = np.degrees(np.unwrap(np.radians(track[name].to_numpy(float))))
        value = float(np.interp(t, times, angle))
        out.append((value + 180.0) % 360.0 - 180.0)
    return tuple(out)  # type: ignore[return-value]


def _history(path: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """(time from contact, value) of a pulse file: the force, or the base shear's magnitude
    (x and, where the file has it, y)."""
    frame = _csv(path)
    if frame.empty or frame.shape[1] < 2:
        return None
    values = frame.iloc[:, 1:].to_numpy(float)
    return frame.iloc[:, 0].to_numpy(float), np.sqrt((values ** 2).sum(axis=1))


def impact_table(layout: Layout) -> pd.DataFrame:
    """The layout's column strikes with the orientation at the strike and the peak base shear
    (columns: see the module notes); fills ``layout.pulses``."""
    cols = IMPACT_TABLE_COLUMNS
    impacts = _csv(CaseFolder(layout.case).results_dir / "impacts.csv")
    if impacts.empty:
        return pd.DataFrame(columns=cols)
    column = impacts[impacts["kind"] == "column"].sort_values("time_s", kind="stable")
    rows = []
    tracks = {b: t.sort_values("time_s") for b, t in layout.bodies.groupby("body")} if not layout.bodies.empty else {}
    counts: dict[str, int] = {}
    for r in column.to_dict("records"):
        counts[r["body"]] = counts.get(r["body"], 0) + 1
        yaw, pitch, roll = _orientation_at(tracks.get(r["body"], pd.DataFrame()), float(r["time_s"]))
        history = str(r.get("force_history") or "")
        force = _history(layout.case / history) if history else None
        shear = _history(layout.case / history.replace("-force.csv", "-base-shear.csv")) if history else None
        if force is not None:
            layout.pulses[int(r["event"])] = (force, shear)
        rows.append({"layout": layout.name, "event": int(r["event"]), "strike": counts[r["body"]], "body": r["body"],
                     "time_s": r["time_s"], "impact_velocity_m_s": r["impact_velocity_m_s"],
                     "obliquity_deg": r["obliquity_deg"], "height_m": r["height_m"],
                     "face_water_level_m": r["face_water_level_m"], "yaw_deg": yaw, "pitch_deg": pitch,
                     "roll_deg": roll, "peak_force_N": r["peak_force_N"], "duration_s": r["duration_s"],
                     "impulse_Ns": r["impulse_Ns"],
                     "peak_base_shear_N": float(np.max(np.abs(shear[1]))) if shear is not None else np.nan,
                     "point_x_m": r["point_x_m"], "point_y_m": r["point_y_m"], "force_history": history})
    return pd.DataFrame(rows, columns=cols)


def load_layout(case_dir: str | Path) -> Layout:
    """Read one layout's run (see the module notes); a run without results is read as far as it goes."""
    folder = CaseFolder(case_dir)
    plan, run = folder.model_plan(), folder.run_state()
    if plan is None and folder.plan_path.is_file():  # a member folder the sweep never rendered has none
        raise InputError(folder.plan_path.name, "not the plan `debrisfoam render` writes (a JSON object of its "
                         "keys): render the case again", str(folder.path))
    member_path = folder.path / MEMBER_JSON
    member = read_json_object(member_path) or {}
    summary = folder.summary() or {}
    scene = folder.scene() if folder.scene_path.is_file() else None
    name = summary.get("scene") or (scene.name if scene is not None else None) or \
        (member.get("params") or {}).get("scene") or folder.path.name
    if not summary:
        status, error, log = _failure(folder, run, member)
        return Layout(name, folder.path, status, error, log, scene, run, plan, member)
    results = folder.results_dir
    layout = Layout(name, folder.path, summary.get("status") or "unknown", None, None, scene, run, plan, member,
                    summary)
    layout.bodies = _csv(results / "bodies.csv")
    layout.strikes = impact_table(layout)
    layout.body_contacts = _csv(folder.path / TRANSPORT_DIR / "body_contacts.csv")
    for e in read_events(folder.path):
        if e.get("kind") != "wall":  # an impact with its pulse, or a contact without one
            continue
        if str(e.get("other", "")).startswith(END_WALLS):
            layout.end_contacts += 1
            if e.get("body") not in layout.at_record_end:
                layout.at_record_end[e["body"]] = (float(e["time_s"]), float((e.get("point_m") or [np.nan])[0]))
        else:
            layout.wall_contacts += 1
    layout.gauges = _csv(results / "gauges.csv")
    layout.gauge_summary = _csv(results / "gauge_summary.csv")
    forces = _csv(results / "column_forces.csv")
    if not forces.empty and "hydro_force_x_N" in forces:
        layout.hydro = forces[["time_s", "hydro_force_x_N"]].dropna().reset_index(drop=True)
    layout.spreading = _csv(results / "spreading.csv")
    if layout.status != "finished":
        layout.error = f"the run stopped at t = {summary.get('reached_time_s')} s ({layout.status})"
    return layout


_EXECUTION_TIME = re.compile(r"^ExecutionTime = ([0-9.eE+-]+) s", re.MULTILINE)


def _solver_cpu_s(layout: Layout) -> float | None:
    """The solver's CPU time on its master rank (s): the last ``ExecutionTime`` of each segment's
    log, summed (the wall time also counts other jobs' turns on a shared machine; this does not)."""
    total, found = 0.0, False
    for seg in layout.run.segments:
        log = layout.case / str(seg.get("log") or "")
        if seg.get("log") and log.is_file():
            hits = _EXECUTION_TIME.findall(log.read_text(errors="replace"))
            if hits:
                total, found = total + float(hits[-1]), True
    return round(total, 1) if found else None


def _wall(layout: Layout) -> dict[str, float | None]:
    run = layout.run
    mesh = sum(float(s.get("wall_s") or 0.0) for s in run.steps if not s.get("skipped"))
    transport = run.transport or {}
    return {"mesh_wall_s": mesh or None, "flow_wall_s": run.solver_wall_s, "flow_cpu_s": _solver_cpu_s(layout),
            "transport_wall_s": run.transport_wall_s,
            "transport_stepping_s": transport.get("wall_s"), "transport_pulses_s": transport.get("pulse_wall_s"),
            "member_wall_s": layout.member.get("wall_time_s")}


def layout_row(layout: Layout) -> dict[str, Any]:
    """The layout's figures for the page's first table (and layouts.csv)."""
    row: dict[str, Any] = {"layout": layout.name, "status": layout.status, "bodies": len(layout.body_names),
                           "coupling": layout.coupling, "cells": layout.summary.get("cells"),
                           "reached_time_s": layout.summary.get("reached_time_s"), **_wall(layout)}
    strikes = layout.strikes
    per_body = {b: 0 for b in layout.body_names}
    for b in strikes.get("body", []):
        per_body[b] = per_body.get(b, 0) + 1
    row["column_strikes"] = len(strikes)
    row["strikes_per_body"] = " ".join(f"{b}:{n}" for b, n in per_body.items())
    row["bodies_striking"] = sum(1 for n in per_body.values() if n)
    if len(strikes):
        first = strikes.iloc[0]
        row.update(first_strike_body=first["body"], first_strike_time_s=first["time_s"],
                   first_strike_velocity_m_s=first["impact_velocity_m_s"],
                   first_strike_peak_force_N=first["peak_force_N"],
                   max_peak_force_N=float(strikes["peak_force_N"].max()),
                   max_base_shear_N=float(strikes["peak_base_shear_N"].max()))
    bc = layout.body_contacts
    row["body_contacts"] = len(bc)
    row["body_contact_max_approach_m_s"] = float(bc["approach_velocity_m_s"].abs().max()) if len(bc) else None
    row["wall_contacts"] = layout.wall_contacts
    row["record_end_contacts"] = layout.end_contacts
    row["bodies_at_record_end"] = " ".join(f"{b}:{t:.3f}" for b, (t, _) in layout.at_record_end.items())
    sp = layout.spreading
    if not sp.empty:
        row["max_spread_deg"] = float(sp["max_spread_deg"].max())
        for name in SPREADING_ANGLES_DEG:
            key = "inside_" + name.split()[0].lower()
            if key in sp:
                row[f"{key}_all"] = bool(sp[key].astype(str).eq("True").all())
    return row


def _series(layout: Layout, quantity: str) -> tuple[np.ndarray, np.ndarray] | None:
    if quantity == "hydro_force_x_N":
        frame, col = layout.hydro, "hydro_force_x_N"
    else:
        frame, col = layout.gauges, f"{quantity}_elevation_m"
    if frame.empty or col not in frame:
        return None
    data = frame[["time_s", col]].dropna()
    return (data["time_s"].to_numpy(float), data[col].to_numpy(float)) if len(data) else None


def flow_agreement(layouts: list[Layout]) -> pd.DataFrame:
    """Per layout and quantity (WG1-WG4, the column's hydrodynamic force along the flow): the
    peak and the largest difference from the first layout's record (on that record's times,
    over the span both cover); the first layout's own row has difference 0."""
    done = [lay for lay in layouts if lay.ok]
    rows = []
    if not done:
        return pd.DataFrame(columns=["layout", "quantity", "unit", "peak", "time_of_peak_s", "max_abs_diff",
                                     "max_abs_diff_fraction_of_peak"])
    ref = done[0]
    for quantity in (*GAUGES, "hydro_force_x_N"):
        unit = "N" if quantity == "hydro_force_x_N" else "m"
        base = _series(ref, quantity)
        for lay in done:
            s = _series(lay, quantity)
            if s is None:
                continue
            i = int(np.argmax(s[1]))
            diff = np.nan
            if base is not None:
                t0, t1 = max(base[0][0], s[0][0]), min(base[0][-1], s[0][-1])
                inside = (base[0] >= t0) & (base[0] <= t1)
                if inside.any():
                    diff = float(np.max(np.abs(np.interp(base[0][inside], *s) - base[1][inside])))
            peak = float(s[1][i])
            rows.append({"layout": lay.name, "quantity": quantity, "unit": unit, "peak": peak,
                         "time_of_peak_s": float(s[0][i]), "max_abs_diff": diff,
                         "max_abs_diff_fraction_of_peak": diff / abs(peak) if peak else np.nan})
    return pd.DataFrame(rows)


def write_layouts_report(runs, out_dir: str | Path) -> dict[str, Path]:
    """Read the runs (:func:`find_runs`) and write the page, its tables and figures into out_dir
    (see the module notes); returns name -> path."""
    layouts = [load_layout(case) for case in find_runs(runs)]
    seen: dict[str, int] = {}
    for lay in layouts:  # the same scene twice (two folders): told apart by their folders
        seen[lay.name] = seen.get(lay.name, 0) + 1
        if seen[lay.name] > 1:
            lay.name = f"{lay.name} ({lay.case.name})"
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written: dict[str, Path] = {}
    table = pd.DataFrame([layout_row(lay) for lay in layouts])
    written["layouts"] = write_table(table, out / "layouts.csv")
    strikes = [lay.strikes for lay in layouts if len(lay.strikes)]
    impacts = pd.concat(strikes, ignore_index=True) if strikes else pd.DataFrame(columns=IMPACT_TABLE_COLUMNS)
    written["impacts"] = write_table(impacts, out / "impacts.csv")
    contacts = [lay.body_contacts.assign(layout=lay.name) for lay in layouts if len(lay.body_contacts)]
    written["body_contacts"] = write_table(pd.concat(contacts, ignore_index=True) if contacts else
                                           pd.DataFrame(columns=["layout"]), out / "body_contacts.csv")
    agreement = flow_agreement(layouts)
    written["flow_agreement"] = write_table(agreement, out / "flow_agreement.csv")
    figures = layout_plots.draw_all(layouts, out)
    written.update(figures)
    text = markdown(layouts, table, agreement, {k: p.name for k, p in figures.items()}, flow_agreement)
    written["report"] = write_text_atomic(out / "report.md", text)
    return written
