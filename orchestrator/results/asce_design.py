"""A run's ASCE 7-22 6.11 answer: the design impact force with the governing stiffness, at u_max.

ASCE 7-22 6.11.2 gives ``F_i = I_tsu C_o u_max sqrt(k m_d)`` with ``k`` the lesser of the debris'
stiffness ``k_d`` and the struck element's lateral stiffness ``k_s``, and ``u_max`` the flow's
maximum velocity at the site "at depths sufficient to float the debris". The study (its 3.2.3)
put each record's measured impact speed in place of ``u_max``. A run gives both, so each column
strike gets one row (:func:`asce_design_table`):

* ``u_max`` (:func:`site_flow_speed`): the largest depth-averaged horizontal flow speed two
  column widths upstream of the column's face (:data:`UPSTREAM_WIDTHS`), over the run, among the
  moments the water there is at least as deep as the lightest body's draft (it floats). The
  standard means the site's flow without the structure; at the face itself the column stops
  the water (its stagnation zone), while two widths upstream a column slows the flow by a few
  per cent (potential flow past a cylinder: (R / r)^2 = 4 % at two diameters from its face). It comes from the flow a one-way run records
  (``results/flow_record.npz``, :mod:`orchestrator.transport.flow`); a run without that record
  (two-way, no debris) gives none and says so.
* the body's impact speed (its centre's speed at the strike): the study's way, kept beside it.

The design value (``design_force_N``) is the governing stiffness's force at ``u_max`` (at the
impact speed when the run recorded no flow, said in ``design_basis``); the other stiffness's
force is context. Laboratory scale: the simplified static load of 6.11 is not applied
(:class:`analytical.asce7.AsceDesign` says why).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from analytical.asce7 import asce7_design
from analytical.study import STUDY_DEBRIS_STIFFNESS_N_M
from orchestrator.transport.flow import FlowField
from orchestrator.transport.flow_record import FLOW_RECORD_NPZ

__all__ = ["ASCE_COLUMNS", "SiteFlow", "asce_design_table", "float_depth_m", "site_flow_speed"]

#: Least water depth (m) counted as flow at the column when no body says how deep it must be.
MIN_DEPTH_M = 0.005

#: Where u_max is read: this many column widths upstream of its face, out of its stagnation zone.
UPSTREAM_WIDTHS = 2.0

ASCE_COLUMNS = ["event", "time_s", "body", "mass_kg", "impact_speed_m_s", "u_max_m_s", "design_basis",
                "governing_stiffness", "stiffness_N_m", "design_force_N", "duration_s", "impulse_Ns",
                "other_stiffness", "other_force_N", "force_at_impact_speed_N", "cap_N", "capped"]


@dataclass(frozen=True)
class SiteFlow:
    """The flow's maximum speed at the column (:func:`site_flow_speed`)."""

    u_max_m_s: float
    time_s: float
    depth_m: float
    x_m: float
    min_depth_m: float
    source: str

    def describe(self) -> str:
        return (f"{self.u_max_m_s:.2f} m/s at t = {self.time_s:.3f} s, depth {self.depth_m:.3f} m, x = {self.x_m:.3f} m "
                f"(the largest depth-averaged speed {UPSTREAM_WIDTHS:g} column widths upstream of its face, out of "
                f"its stagnation zone, where the water is at least {self.min_depth_m * 1e3:.0f} mm deep, enough to "
                f"float the debris; {self.source})")


def float_depth_m(bodies: list[tuple[float, float, float]], density_kg_m3: float = 998.0) -> float:
    """The least depth that floats one of ``bodies`` ((mass kg, length m, width m) each): the
    smallest draft m / (rho L W); :data:`MIN_DEPTH_M` without bodies."""
    drafts = [m / (density_kg_m3 * length * width) for m, length, width in bodies if length > 0 and width > 0]
    return max(min(drafts), MIN_DEPTH_M) if drafts else MIN_DEPTH_M


def flow_speed_at(field: FlowField, x_face_m: float, y_span_m: tuple[float, float],
                  min_depth_m: float) -> SiteFlow | None:
    """The largest depth-averaged horizontal speed of ``field`` on the grid line just upstream of
    ``x_face_m`` (the last x below it), across ``y_span_m``, where the depth is >= ``min_depth_m``."""
    i = int(np.searchsorted(field.x_m, x_face_m, side="left")) - 1
    if i < 0:
        return None
    y_lo, y_hi = y_span_m
    js = np.flatnonzero((field.y_m >= y_lo) & (field.y_m <= y_hi))
    if js.size == 0:
        js = np.array([int(np.argmin(np.abs(field.y_m - 0.5 * (y_lo + y_hi))))])
    best: SiteFlow | None = None
    for k in range(field.t_s.size):
        for j in js:
            depth = float(field.eta_m[k, i, j] - field.bed_z_m)
            if depth < min_depth_m:
                continue
            speed = _depth_averaged_speed(field.z_m, field.velocity_m_s[k, i, j, :, :2], float(field.bed_z_m),
                                          float(field.eta_m[k, i, j]))
            if best is None or speed > best.u_max_m_s:
                best = SiteFlow(speed, float(field.t_s[k]), depth, float(field.x_m[i]), min_depth_m,
                                "the one-way run's flow record")
    return best


def _depth_averaged_speed(z_m: np.ndarray, velocity_h: np.ndarray, bed_z_m: float, eta_m: float) -> float:
    """(1 / h) * integral of the horizontal speed from the bed to the surface (trapezoids over the
    record's levels, which are dense near the bed and sparse above it, the highest wet level's
    speed held up to the surface: the level above it is air): each level weighs by the water it
    stands for, not one level one vote."""
    speed = np.hypot(velocity_h[:, 0], velocity_h[:, 1])
    depth = eta_m - bed_z_m
    wet = z_m <= eta_m
    if depth <= 0.0 or not wet.any():
        return 0.0
    z = np.concatenate([[bed_z_m], z_m[wet & (z_m > bed_z_m)], [eta_m]])
    u = np.interp(z, z_m[wet], speed[wet])  # held at the ends: no air in the average
    return float(np.trapezoid(u, z) / depth) if hasattr(np, "trapezoid") else float(np.trapz(u, z) / depth)


def site_flow_speed(case_dir: str | Path, scene) -> SiteFlow | None:
    """``u_max`` of a run at its column (module notes), or None: no column, or no flow record."""
    if scene is None or scene.column is None:
        return None
    path = Path(case_dir) / "results" / FLOW_RECORD_NPZ
    if not path.is_file():
        return None
    field = FlowField.load(path)
    col = scene.column
    x_face = float(col.x_m - col.size_x_m / 2)
    x_read = x_face - UPSTREAM_WIDTHS * float(col.size_y_m)
    span = (float(col.y_m - col.size_y_m / 2), float(col.y_m + col.size_y_m / 2))
    bodies = [(float(b.mass_kg), float(b.size_m[0]), float(b.size_m[1])) for b in scene.debris]
    return flow_speed_at(field, x_read, span, float_depth_m(bodies, field.water_density_kg_m3))


def _speed(row: dict) -> float:
    for key in ("impact_speed_m_s", "impact_velocity_m_s", "normal_velocity_in_m_s"):
        value = row.get(key)
        if value is not None and np.isfinite(value) and value > 0:
            return float(value)
    return math.nan


def asce_design_table(impacts: pd.DataFrame, masses_kg: dict[str, float], structure_stiffness_N_m: float,
                      site: SiteFlow | None) -> pd.DataFrame:
    """One row per column strike in ``impacts`` (impacts.csv's rows): the design force F_i with the
    governing stiffness at ``u_max`` (or at the impact speed without a flow record), the other
    stiffness's force as context, and the governing force at the body's impact speed (the study's way)."""
    rows = []
    column = impacts[impacts["kind"] == "column"] if "kind" in impacts else impacts
    for row in column.to_dict("records"):
        mass = masses_kg.get(row.get("body"))
        speed = _speed(row)
        if mass is None or not mass > 0:
            continue
        u = site.u_max_m_s if site is not None else speed
        if not (np.isfinite(u) and u > 0):
            continue
        basis = "u_max of the flow at the column" if site is not None else \
            "the body's impact speed (this run recorded no flow velocity at the column)"
        design = asce7_design(u, mass, STUDY_DEBRIS_STIFFNESS_N_M, structure_stiffness_N_m)
        at_speed = asce7_design(speed, mass, STUDY_DEBRIS_STIFFNESS_N_M, structure_stiffness_N_m) \
            if np.isfinite(speed) and speed > 0 else None
        d = design.to_dict()
        rows.append({"event": row.get("event"), "time_s": row.get("time_s"), "body": row.get("body"), "mass_kg": mass,
                     "impact_speed_m_s": speed, "u_max_m_s": site.u_max_m_s if site is not None else math.nan,
                     "design_basis": basis, "governing_stiffness": d["governing_stiffness"],
                     "stiffness_N_m": d["stiffness_N_m"], "design_force_N": d["force_N"],
                     "duration_s": d["duration_s"], "impulse_Ns": d["impulse_Ns"],
                     "other_stiffness": d["other_stiffness"], "other_force_N": d["other_force_N"],
                     "force_at_impact_speed_N": at_speed.force_N if at_speed else math.nan,
                     "cap_N": d["cap_N"], "capped": d["capped"]})
    return pd.DataFrame(rows, columns=ASCE_COLUMNS)
