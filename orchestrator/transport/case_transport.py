"""A one-way case's bodies carried through its recorded flow, written as a coupled run writes them.

After the flow run of a one-way case (``plan.debris_coupling == "one-way"``: interFoam without
the bodies, recording alpha.water and U), :func:`transport_case`:

1. reads the record into a :class:`~orchestrator.transport.flow.FlowField`
   (:func:`~orchestrator.transport.flow_record.read_flow_record`, kept as results/flow_record.npz);
2. builds every scene body as it starts (size, mass, wall thickness, centre and orientation from
   the resolved scene, start velocity, its contact law and its bed friction coefficient), the
   flume's bed and side walls, end walls at the record's ends, and the column;
3. runs the MuJoCo engine (:func:`~orchestrator.transport.engine.run_transport`) from t = 0 to
   the run's end time;
4. writes what the coupled runner writes, so that post-processing, sweeps and reports read both
   paths alike: ``bodies.csv`` (the tracks), ``contacts.json`` with one impact event per column
   or wall strike and its pulse under ``contacts/`` (from the same contact law, column model and
   rigid wall the coupled path resolves strikes with), and run.json's ``transport`` record with
   ``transport_wall_s``. A strike left without a pulse (an ensemble's later strikes) is a
   contact event of type ``transport_contact``; ``transport/body_contacts.csv`` lists the
   body-body strikes with their pulses' peak force, duration and impulse.

A body that leaves the recorded region stops the transport with a FlowCoverageError naming the
coordinate; the end walls at the record's ends keep bodies inside it, so the record's region
(plan.flow_record) should reach past where the bodies can go in the run's time.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from orchestrator.core.errors import InputError
from orchestrator.case.folder import CaseFolder
from orchestrator.contact.events import write_events, write_pulse_files
from orchestrator.contact.resolution import body_contact_law
from orchestrator.core.files import write_text_atomic
from orchestrator.plan.scale import time_scale
from orchestrator.scene.schema import DebrisBody, Scene, column_for_analysis
from orchestrator.transport.engine import TransportResult, TransportSettings, run_transport
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn
from orchestrator.transport.flow import FlowField
from orchestrator.transport.flow_record import read_flow_record

__all__ = ["TRANSPORT_DIR", "TransportSummary", "case_flow", "contact_laws", "scene_bodies", "scene_settings",
           "transport_case"]

#: The transport's own files in the case folder.
TRANSPORT_DIR = "transport"


@dataclass(frozen=True)
class TransportSummary:
    """What :func:`transport_case` did: the engine's result and what it wrote."""

    result: TransportResult
    column_impacts: int
    other_contacts: int
    flow_record: Path
    flow_record_bytes: int
    wall_s: float


def contact_laws(scene: Scene) -> dict[str, dict[str, float]]:
    """Each body's contact law as the tool resolves it today (its stiffness and damping), as run.json's
    transport record keeps it: a case carried with another law (a scene's or the shipped one) is
    carried again (:func:`orchestrator.pipeline.carry_debris`)."""
    return {b.name: {k: float(v) for k, v in body_contact_law(b.contact).to_dict().items() if k != "law"}
            for b in scene.debris}


def scene_bodies(scene: Scene) -> list[DebrisBody]:
    """The scene's bodies as they start (the resolved scene's centres: on the bed, afloat or given)."""
    return list(scene.debris)


#: TransportSettings' times and speeds that are set at the study's 0.40 m flume: a deeper scene
#: gets them x sqrt(lambda) where they are left at their defaults (orchestrator.plan.scale).
FROUDE_SCALED_SETTINGS = ("output_interval_s", "hydro_interval_s", "max_timestep_s", "separation_s",
                          "min_impact_velocity_m_s")


def froude_settings(scene: Scene, settings: TransportSettings) -> TransportSettings:
    """``settings`` with each of :data:`FROUDE_SCALED_SETTINGS` still at its default multiplied by
    sqrt(lambda), lambda the scene's Froude factor over the study's flume (1 for a scene at most
    0.40 m deep): a scene 40 times larger is carried through the same number of forcing updates
    and outputs per bore passage, and counts the same strikes."""
    factor = time_scale(scene.reservoir.depth_m)
    if factor == 1.0:
        return settings
    defaults = TransportSettings()
    changes = {name: getattr(settings, name) * factor for name in FROUDE_SCALED_SETTINGS
               if getattr(settings, name) == getattr(defaults, name)}
    return dataclasses.replace(settings, **changes)


def scene_settings(scene: Scene, settings: TransportSettings | None = None) -> TransportSettings:
    """``settings`` (the defaults when None) with the scene's hydrodynamic coefficients (its
    ``transport`` section), and Froude-scaled to the scene's size (:func:`froude_settings`)."""
    settings = froude_settings(scene, TransportSettings() if settings is None else settings)
    hydro = dataclasses.replace(settings.hydro, drag_coefficient=scene.transport.drag_coefficient,
                                added_mass_coefficient=scene.transport.added_mass_coefficient,
                                sub_volumes=tuple(scene.transport.sub_volumes),
                                drag_area=scene.transport.drag_area, munk_moment=scene.transport.munk_moment)
    return dataclasses.replace(settings, hydro=hydro)


def open_record_ends(scene: Scene, record_x_m: tuple[float, float], cell_m: float) -> tuple[bool, bool]:
    """Which ends of the flow record are no walls for the bodies: an end short of the flume's
    own (the model was trimmed to the region of interest; the real flume goes on) and a free
    outfall (``flume.downstream_end: open``). An end within two record spacings ``cell_m`` of
    the flume's closed end is its wall (the record's points are cell centres)."""
    upstream_wall = -scene.reservoir.length_m
    downstream_end = scene.flume.length_m - scene.reservoir.length_m
    tolerance = 2.0 * max(float(cell_m), 1e-9)
    upstream_open = record_x_m[0] > upstream_wall + tolerance
    downstream_open = scene.flume.downstream_end == "open" or record_x_m[1] < downstream_end - tolerance
    return upstream_open, downstream_open


def transport_setup(scene: Scene, flow: FlowField) -> tuple[list[DebrisBody], FlumeBounds, PlacedColumn | None]:
    """The scene's bodies, the flume the record bounds (the flume's side walls, end walls at the
    record's ends, the bed at the record's) and the column standing on the bed."""
    (x0, x1), (y0, y1), _ = flow.extent_m
    half = scene.flume.width_m / 2
    flume = FlumeBounds(x_m=(x0, x1), y_m=(max(y0, -half), min(y1, half)), bed_z_m=flow.bed_z_m,
                        open_ends=open_record_ends(scene, (x0, x1), float(flow.x_m[1] - flow.x_m[0])))
    column = None
    if scene.column is not None:
        column = PlacedColumn(scene.column.x_m, scene.column.y_m, column_for_analysis(scene))
    return scene_bodies(scene), flume, column


def _event(row: dict[str, Any], number: int, kind_type: str) -> dict[str, Any]:
    """A contacts.json event from a row of the engine's impacts table."""
    n = [row["normal_x"], row["normal_y"], row["normal_z"]]
    rebound = [row["rebound_u_m_s"], row["rebound_v_m_s"], row["rebound_w_m_s"]]
    vn = float(row["normal_velocity_in_m_s"])
    tangential = float(row["tangential_velocity_in_m_s"])
    # the engine's table keeps the approach's normal part per axis and the tangential part's size
    v_in = [float(-vn * n[i]) for i in range(3)]
    event = {
        "event": number, "type": kind_type, "time_s": float(row["time_s"]), "body": row["body"],
        "other": row["other"], "kind": row["kind"], "point_m": [row["point_x_m"], row["point_y_m"], row["point_z_m"]],
        "normal": n, "velocity_in_m_s": v_in, "velocity_out_m_s": rebound,
        "normal_velocity_in_m_s": -vn, "normal_velocity_out_m_s": float(row["rebound_normal_velocity_m_s"]),
        "tangential_velocity_in_m_s": tangential,
        "restitution": float(row["restitution"]), "obliquity_deg": float(row["obliquity_deg"]),
        "height_m": float(row["height_m"]), "face_water_level_m": float(row["face_water_level_m"]),
        "body_clearance_m": float(row["body_clearance_m"]), "afloat": bool(row["afloat"]),
        "time_since_front_s": float(row.get("time_since_front_s", math.nan)),
        "source": "one-way transport",
    }
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in event.items()}


def _write_events(folder: CaseFolder, result: TransportResult) -> tuple[int, int]:
    """contacts.json and the pulse files: (column impacts, other contacts)."""
    events: list[dict[str, Any]] = []
    strikes = others = 0
    for row in result.impacts.sort_values("time_s", kind="stable").to_dict("records"):
        number = len(events) + 1
        pulse = result.pulses.get(int(row["event"]))
        if pulse is None:
            events.append(_event(row, number, "transport_contact"))
            others += 1
            continue
        event = _event(row, number, "impact")
        event.update(peak_force_N=float(pulse.peak_force_N), duration_s=float(pulse.duration_s),
                     impulse_Ns=float(pulse.impulse_Ns), pulse_restitution=float(pulse.restitution),
                     effective_mass_kg=float(pulse.effective_mass_kg),
                     added_mass_along_normal_kg=float(row["added_mass_along_normal_kg"]),
                     force_history=str(write_pulse_files(folder.path, number, pulse)))
        events.append(event)
        strikes += 1
    write_events(folder.path, events)
    if not result.body_contacts.empty:
        (folder.path / TRANSPORT_DIR).mkdir(exist_ok=True)
        write_text_atomic(folder.path / TRANSPORT_DIR / "body_contacts.csv",
                          result.body_contacts.to_csv(index=False, float_format="%.10g"))
    return strikes, others + len(result.body_contacts)


def case_flow(case_dir: str | Path, say: Callable[[str], None] = print) -> tuple[FlowField, Path]:
    """The one-way case's recorded flow and its .npz: converted from the function object's text
    (which is then deleted: about 6 MB a frame for the study's scene, against 0.5 MB in the .npz)
    or, once converted, loaded from results/flow_record.npz."""
    record = read_flow_record(case_dir, delete_raw=True)
    say(f"debrisfoam: flow record: {record.frames} frames of {record.points:,} points, "
        f"{record.bytes_total / 1e6:.1f} MB in {record.path.name} (from {record.raw_bytes / 1e6:.0f} MB of text, "
        "removed once converted)")
    return record.field, record.path


def transport_case(case_dir: str | Path, *, settings: TransportSettings | None = None,
                   say: Callable[[str], None] = print) -> TransportSummary:
    """Carry the one-way case's bodies through its recorded flow and write the results a
    coupled run writes (module notes). Raises InputError when the case is not one-way or its
    record does not cover the run."""
    folder = CaseFolder(case_dir)
    coupling = folder.debris_coupling()
    if coupling != "one-way":
        raise InputError(str(folder.plan_path), f"debris_coupling is {coupling!r}: only a one-way "
                                                "case carries its bodies through a recorded flow")
    scene = folder.scene()
    flow, npz = case_flow(folder.path, say=say)
    bodies, flume, column = transport_setup(scene, flow)
    t_end = float(folder.require_plan().end_time_s)  # a one-way plan reads typed: case_flow has read it
    result = run_transport(bodies, flume, t_end, flow=flow, column=column,
                           settings=scene_settings(scene, settings))
    write_text_atomic(folder.path / "bodies.csv", result.tracks.to_csv(index=False, float_format="%.10g"))
    strikes, others = _write_events(folder, result)
    departures = result.departures.to_dict("records")
    if departures:
        (folder.path / TRANSPORT_DIR).mkdir(exist_ok=True)
        write_text_atomic(folder.path / TRANSPORT_DIR / "departures.csv",
                          result.departures.to_csv(index=False, float_format="%.10g"))
    run = folder.run_record() or {}
    run["transport"] = {"engine": "mujoco", "bodies": len(scene.debris), "end_time_s": t_end,
                        "timestep_s": result.timestep_s, "steps": result.steps, "wall_s": round(result.wall_s, 3),
                        "pulse_wall_s": round(result.pulse_wall_s, 3), "column_impacts": strikes,
                        "other_contacts": others, "open_ends": list(flume.open_ends),
                        "departures": [{k: (round(v, 6) if isinstance(v, float) else v) for k, v in d.items()}
                                       for d in departures],
                        "flow_record": str(npz.relative_to(folder.path)),
                        "flow_record_bytes": npz.stat().st_size, "contact_laws": contact_laws(scene)}
    run["transport_wall_s"] = round(result.wall_s + result.pulse_wall_s, 3)
    folder.write_run_record(run)
    say(f"debrisfoam: transport: {len(scene.debris)} bod{'y' if len(scene.debris) == 1 else 'ies'} over "
        f"{t_end:g} s in {result.wall_s:.1f} s (+ {result.pulse_wall_s:.1f} s of column pulses): "
        f"{strikes} column strike(s), {others} other contact(s)"
        + "".join(f"; {d['body']} left the record's {d['end']} end at {d['time_s']:.3f} s, {d['speed_m_s']:.2f} m/s"
                  for d in departures))
    return TransportSummary(result, strikes, others, npz, npz.stat().st_size, result.wall_s + result.pulse_wall_s)
