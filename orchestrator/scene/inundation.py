"""A scene that states the bore it wants: the reservoir and wet bed sized for it.

A designer knows the inundation at a site (ASCE 7-22 chapter 6: flow depth and speed), not a
reservoir. A scene's ``inundation: {depth_m, speed_m_s}`` is read on the raw scene mapping,
before the scene is validated, and fills in the dam break that makes it
(:func:`analytical.bore_sizing.size_dam_break`, Stoker's frictionless wet-bed solution):

* ``reservoir.depth_m`` = h0 and ``bed.wet_depth_m`` = hr, the two depths whose plateau is
  the requested depth and speed. A scene may state either only at the sized value (a resolved
  scene written back carries them): a wet bed given at another depth makes another Froude
  number at that flow depth, and the request is refused naming ``inundation.speed_m_s``;
* ``reservoir.length_m``, when not given: the shortest reservoir whose reflected negative wave
  reaches the column's upstream face no earlier than ``run.end_time_s``, so the column sees the
  requested state from the bore's arrival to the end of the run (or until the rarefaction's
  tail passes, for a supercritical plateau: the solution's own physics, said in the plan).

Refused with :class:`~orchestrator.core.errors.InputError` (exit 2) naming the field: a scene
without a column (the bore is wanted at it), an impoundment above the flume's walls
(``inundation.depth_m``), a bore that does not reach the column within ``run.end_time_s``, a
flume too short for the sized reservoir and the column (``flume.length_m``).
"""

from __future__ import annotations

import math

from pydantic import ValidationError

from analytical.bore_sizing import BoreSizing, froude_on_wet_bed, reservoir_length_for, size_dam_break
from orchestrator.core.errors import InputError
from orchestrator.scene.schema import Fluids, Inundation

__all__ = ["RELATIVE_TOLERANCE", "apply_inundation", "inundation_reason", "inundation_sizing"]

#: A given reservoir depth or wet bed counts as the sized one within this fraction.
RELATIVE_TOLERANCE = 1e-6


def _section(data: dict, name: str, source: str | None) -> dict:
    value = data.get(name)
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise InputError(name, f"must be a mapping, got {type(value).__name__}", source)
    return dict(value)


def _number(section: dict, key: str, field: str, source: str | None) -> float | None:
    value = section.get(key)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(field, f"must be a number, got {value!r}", source)
    return float(value)


def inundation_sizing(depth_m: float, speed_m_s: float, gravity_m_s2: float = 9.81) -> BoreSizing:
    """The dam break for an inundation (:func:`analytical.bore_sizing.size_dam_break`)."""
    return size_dam_break(depth_m, speed_m_s, gravity_m_s2)


def apply_inundation(data: dict, source: str | None = None) -> dict:
    """``data`` (a raw scene mapping) with its reservoir and wet bed sized for its
    ``inundation`` section; unchanged when it has none (module notes)."""
    raw = data.get("inundation")
    if raw is None:
        return data
    try:
        wanted = Inundation.model_validate(raw)
    except ValidationError as err:
        first = err.errors()[0]
        loc = ".".join(str(p) for p in ("inundation", *first["loc"]))
        raise InputError(loc, first["msg"], source) from None
    from analytical.asce7 import check_flow_speed

    try:  # a plausible speed before the dam break is sized for it (else the sized impoundment is blamed)
        check_flow_speed(wanted.speed_m_s, "inundation.speed_m_s")
    except InputError as err:
        raise InputError(err.field, err.rule, source) from None
    fluids = _section(data, "fluids", source)
    g = _number(fluids, "gravity_m_s2", "fluids.gravity_m_s2", source) or Fluids().gravity_m_s2
    sized = inundation_sizing(wanted.depth_m, wanted.speed_m_s, g)
    reservoir, bed = _section(data, "reservoir", source), _section(data, "bed", source)
    flume, run, column = (_section(data, k, source) for k in ("flume", "run", "column"))
    ask = f"a {wanted.depth_m:g} m deep bore at {wanted.speed_m_s:g} m/s (Froude number {sized.froude:.3g})"

    given_depth = _number(reservoir, "depth_m", "reservoir.depth_m", source)
    if given_depth is not None and abs(given_depth - sized.reservoir_depth_m) > RELATIVE_TOLERANCE * sized.reservoir_depth_m:
        raise InputError("reservoir.depth_m", f"{ask} needs an impoundment {sized.reservoir_depth_m:.6g} m deep: leave "
                         f"reservoir.depth_m out to have it sized (inundation), got {given_depth:g}", source)
    given_bed = _number(bed, "wet_depth_m", "bed.wet_depth_m", source)
    if given_bed is not None and abs(given_bed - sized.wet_bed_depth_m) > RELATIVE_TOLERANCE * sized.wet_bed_depth_m:
        detail = ""
        if 0 < given_bed < wanted.depth_m:
            fr = froude_on_wet_bed(wanted.depth_m, given_bed)
            detail = (f"; on a {given_bed:g} m wet bed a dam break makes Froude number {fr:.3g} at that depth "
                      f"({fr * math.sqrt(g * wanted.depth_m):.3g} m/s)")
        elif given_bed >= wanted.depth_m:
            detail = f"; a {given_bed:g} m wet bed is not below the bore's depth"
        else:
            detail = "; a dry bed has no uniform state behind its front (Ritter), only a speed that changes in time"
        raise InputError("inundation.speed_m_s", f"{ask} needs a wet bed {sized.wet_bed_depth_m:.4g} m deep{detail}: "
                         "leave bed.wet_depth_m out to have it sized", source)

    height = _number(flume, "height_m", "flume.height_m", source)
    if height is not None and sized.reservoir_depth_m > height:
        raise InputError("inundation.depth_m", f"{ask} needs an impoundment {sized.reservoir_depth_m:.4g} m deep, above "
                         f"the flume's walls ({height:g} m, flume.height_m): ask for less, or raise the walls", source)
    if not column:
        raise InputError("inundation", "the bore is asked for at the column: the scene needs a column", source)
    col_x = _number(column, "x_m", "column.x_m", source)
    size_x = _number(column, "size_x_m", "column.size_x_m", source) or 0.0
    if col_x is None:
        raise InputError("column.x_m", "needed: the inundation is asked for at the column", source)
    face = col_x - 0.5 * size_x
    if face <= 0:
        raise InputError("inundation", f"the column's upstream face (x = {face:g} m) must be downstream of the gate "
                         "(x > 0) for a bore to reach it", source)
    total = _number(flume, "length_m", "flume.length_m", source)
    if total is not None and col_x - 0.5 * size_x >= total:
        # past the flume's end whatever the reservoir's length: the column's position is wrong, not the run's end
        raise InputError("column.x_m", f"the column's upstream face (x = {face:g} m) is past the flume's downstream "
                         f"end (at most {total:g} m from the gate, flume.length_m): it cannot stand in the flume",
                         source)
    end = _number(run, "end_time_s", "run.end_time_s", source)
    arrival = sized.bore_arrival_s(face)
    if end is not None and arrival >= end:
        raise InputError("run.end_time_s", f"{ask} reaches the column's face (x = {face:g} m) at {arrival:.4g} s, "
                         f"after the run ends ({end:g} s)", source)

    if reservoir.get("length_m") is None and end is not None:
        reservoir["length_m"] = float(f"{reservoir_length_for(face, end, sized.reservoir_depth_m, sized.wet_bed_depth_m, g):.6g}")
        total = _number(flume, "length_m", "flume.length_m", source)
        if total is not None and total <= reservoir["length_m"] + col_x + 0.5 * size_x:
            raise InputError("flume.length_m", f"{ask} needs a reservoir {reservoir['length_m']:g} m long (its "
                             f"reflection reaches the column after {end:g} s): the flume must be longer than it plus the "
                             f"column's far face ({col_x + 0.5 * size_x:g} m), got {total:g}", source)
    reservoir["depth_m"] = sized.reservoir_depth_m if given_depth is None else given_depth
    bed["wet_depth_m"] = sized.wet_bed_depth_m if given_bed is None else given_bed
    return {**data, "reservoir": reservoir, "bed": bed}


def inundation_reason(scene) -> str:
    """A sentence for plan.json: the sized dam break and how long the column sees the bore."""
    wanted = scene.inundation
    if wanted is None or scene.column is None:
        return ""
    sized = inundation_sizing(wanted.depth_m, wanted.speed_m_s, scene.fluids.gravity_m_s2)
    face = scene.column.x_m - 0.5 * scene.column.size_x_m
    end = sized.plateau_end_s(face, scene.reservoir.length_m)
    why = ("the rarefaction's tail passes (a supercritical plateau)"
           if sized.tail_speed_m_s > 0 and face / sized.tail_speed_m_s <= end + 1e-9 else "the reflected negative wave arrives")
    return (f"sized for inundation {wanted.depth_m:g} m at {wanted.speed_m_s:g} m/s (Froude number {sized.froude:.3g}) at "
            f"the column: Stoker's frictionless wet-bed plateau of h0 = {sized.reservoir_depth_m:.4g} m on a "
            f"{sized.wet_bed_depth_m:.4g} m wet bed; the bore (at {sized.bore_speed_m_s:.3g} m/s) reaches the column's "
            f"face at {sized.bore_arrival_s(face):.3g} s and the state holds there until {end:.3g} s, when {why}; bed "
            "friction makes the real bore lower and slower (docs/prototype.md)")
