"""Comparisons of a run with the analytical models and with the study.

:func:`compare` takes the tables of :func:`orchestrator.results.tables.tables` and returns a
:class:`Comparison`; :func:`write_tables` writes its tables to ``DIR/results/``:

``arrivals.csv``
    Bore arrival time at every gauge downstream of the gate against Ritter (dry,
    frictionless), Stoker (the scene's wet-bed depth, frictionless; only with a wet bed),
    Chanson (dry bed, the scene's Darcy f; only with friction), and, at the study's gauge
    positions, the study's measured arrival and its LS-DYNA model's
    (:data:`analytical.study.STUDY_ARRIVALS`); error = simulated - reference (s and %). The
    analytical arrival is the front's tip; the simulated one is the threshold crossing of
    :mod:`orchestrator.results.metrics` (2 % of h0 above the initial level), so a resolved front
    arrives a little after the tip by construction.
``impact_formulas.csv``
    Every impact against ASCE 7-22 6.11 with the debris stiffness k_d and with the column's
    stiffness k_s, Haehnel & Daly (k_d on a rigid obstacle; k_d and k_s in series), Matsutomi
    and Ikeno, all at the simulated impact velocity (the body's centre-of-mass velocity along
    the contact normal) and the body's mass; peak force, duration and impulse where the
    method gives them, and the peak over the simulated (contact model) peak.
``study_fits.csv``, ``table1.csv``
    The study's procedure (its section 3.3) turned on our own output: for each impact on the
    column, the base shear it caused (impact part only: by linearity this is exactly what
    the study's EEMD filtering tried to extract from its records) is fitted with an SDOF and
    an MDOF half-sine pulse (:mod:`analytical.fitting`, the study's bounds); every pulse
    (ASCE k_d, ASCE k_s, SDOF fit, MDOF fit and the contact model's own) is applied to the
    MDOF column at the impact height; ``table1.csv`` is the study's Table 1 regenerated for
    the simulated impact (magnitude, duration, impulse) beside the study's printed rows, with
    the peak base shear each pulse causes and its ratio to the simulated one (study Fig. 7).
``spreading.csv``
    Debris transport against the spreading areas of Naito et al. (2014) and Nistor et al.
    (2017b), started, as the study describes (its 4.2.2, following ASCE 7-22 6.11.5.1), from a
    line through the debris source instead of the debris centroid: the line lies across the
    flow at the most upstream debris centroid and spans the centroids' lateral extent; the
    area is bounded by lines leaving its two ends at the spreading half-angle on either
    side of the flow direction. Per body: the largest spreading angle its track reached and
    whether it stayed inside each area.

Spreading half-angles (:data:`SPREADING_ANGLES_DEG`, either side of the flow direction):

* Naito et al. (2014), 22.5 degrees: from the debris fields of the 2011 Tohoku tsunami; the
  value ASCE 7-16/7-22 6.11.5 adopted for the debris impact hazard region of shipping
  containers (and this package's ``mesh.debris_spread_deg`` default). Naito, C., Cercone,
  C., Riggs, H.R. & Cox, D. (2014). Procedure for site assessment of the potential for
  tsunami debris impact. J. Waterway, Port, Coastal, Ocean Eng. 140(2), 223-232.
* Nistor et al. (2017b), 16.8 degrees: the largest spreading of 1:40 container models in
  the Waseda University wave basin. Nistor, I., Goseberg, N., Stolle, J., Mikami, T.,
  Shibayama, T., Nakamura, R. & Matsuba, S. (2017). Experimental investigations of debris
  dynamics over a horizontal plane. J. Waterway, Port, Coastal, Ocean Eng. 143(3), 04016022.

Neither paper could be retrieved here (the search tool returned only their titles and
abstract pages); the Naito value agrees with ASCE 7's 22.5 degrees, the Nistor value is as
recalled from the literature and is flagged ``verified: False`` until checked against the
paper. The study (4.2.2, Fig. 14) finds the Nistor area the narrower of the two.

Material values not in the study, used by Matsutomi and Ikeno for the polyethylene container
(:data:`CONTAINER_MATERIAL`): E = 1.0 GPa, nu = 0.42, yield stress 25 MPa (typical of
HDPE); the container as a log of equal cross-section area (equivalent diameter) and its
length; apparent-mass coefficient C_MA = 1.7 (bore).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from analytical.asce7 import asce7_impact
from analytical.study import STUDY_ARRIVALS, STUDY_DEBRIS_STIFFNESS_N_M, STUDY_TABLE1
from analytical.dambreak import dam_break
from orchestrator.core.errors import DebrisfoamError
from analytical.fitting import fit_mdof, fit_sdof
from analytical.formulas import haehnel_daly, hertz_effective_modulus, ikeno, matsutomi
from analytical.mdof import column_model, mdof_response
from analytical.pulses import Tabulated
from orchestrator.results.asce_design import SiteFlow, asce_design_table, site_flow_speed
from orchestrator.results.tables import write_table

__all__ = [
    "CONTAINER_MATERIAL",
    "SPREADING_ANGLES_DEG",
    "Comparison",
    "arrival_table",
    "compare",
    "gauge_models",
    "spreading_area",
    "spreading_angle_deg",
    "write_tables",
]

#: How close (m) a gauge must be to one of the study's gauge positions to be compared with it.
STUDY_GAUGE_TOLERANCE_M = 0.02
#: Spreading half-angles (degrees either side of the flow) and their sources; see the module notes.
SPREADING_ANGLES_DEG = {
    "Naito et al. (2014)": {"half_angle_deg": 22.5, "verified": True,
                            "source": "Naito, Cercone, Riggs & Cox (2014), J. Waterway Port Coastal Ocean Eng. "
                                      "140(2): 22.5 deg, as adopted by ASCE 7-16/7-22 6.11.5"},
    "Nistor et al. (2017b)": {"half_angle_deg": 16.8, "verified": False,
                              "source": "Nistor, Goseberg, Stolle et al. (2017), J. Waterway Port Coastal Ocean "
                                        "Eng. 143(3) 04016022: value as recalled, not checked against the paper"},
}
#: Polyethylene container material (assumed, typical HDPE) and the added-mass coefficient.
CONTAINER_MATERIAL = {"youngs_modulus_Pa": 1.0e9, "poisson_ratio": 0.42, "yield_stress_Pa": 25.0e6,
                      "added_mass_coefficient": 1.7}
#: Fits are made for at most this many column impacts (the largest).
MAX_FITTED_IMPACTS = 6
#: The record of an impact that the study's procedure fits: from PRE before to POST after it, sampled at RATE.
RECORD_PRE_S, RECORD_POST_S, RECORD_RATE_HZ = 0.010, 0.040, 10_000.0


@dataclass
class Comparison:
    """Every comparison table, plus the series the plots draw."""

    arrivals: pd.DataFrame
    gauge_models: dict[str, pd.DataFrame]
    impact_formulas: pd.DataFrame
    study_fits: pd.DataFrame
    table1: pd.DataFrame
    spreading: pd.DataFrame
    areas: dict[str, np.ndarray]
    #: event -> {"time_s", "record_N", "sdof_N", "mdof_N", pulses: {method: pulse}, "height_m"}
    fit_records: dict[int, dict[str, Any]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    #: ASCE 7-22 6.11's design force of every column strike (:mod:`orchestrator.results.asce_design`)
    asce: pd.DataFrame = field(default_factory=pd.DataFrame)
    #: u_max of the flow at the column, when the run recorded it
    site_flow: SiteFlow | None = None

    def headline(self) -> dict[str, Any]:
        out: dict[str, Any] = {"arrival_errors_s": {}}
        for r in self.arrivals.itertuples():
            if np.isfinite(r.error_s):
                out["arrival_errors_s"].setdefault(r.gauge, {})[r.reference] = round(float(r.error_s), 4)
        if not self.table1.empty:
            first = self.table1[self.table1["event"] == self.table1["event"].min()]
            out["table1_event"] = int(first["event"].iloc[0])
            out["peak_base_shear_ratio"] = {r.method: _round(r.ratio_to_simulated) for r in first.itertuples()}
        if not self.impact_formulas.empty:
            first = self.impact_formulas[self.impact_formulas["event"] == self.impact_formulas["event"].min()]
            out["impact_peak_ratio"] = {r.method: _round(r.peak_ratio) for r in first.itertuples()}
        if not self.asce.empty:
            a = self.asce.iloc[0]
            out["asce7"] = {"event": int(a["event"]), "design_force_N": _round(a["design_force_N"]),
                            "governing_stiffness": a["governing_stiffness"], "u_max_m_s": _round(a["u_max_m_s"]),
                            "impact_speed_m_s": _round(a["impact_speed_m_s"]), "design_basis": a["design_basis"]}
        if not self.spreading.empty:
            out["spreading"] = {
                r.body: {"max_spread_deg": _round(r.max_spread_deg), **{
                    name: bool(getattr(r, _area_column(name))) for name in SPREADING_ANGLES_DEG}}
                for r in self.spreading.itertuples()
            }
        return out


def _round(value, digits: int = 4):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return round(v, digits) if math.isfinite(v) else None


def _area_column(name: str) -> str:
    return "inside_" + name.split()[0].lower()


# --------------------------------------------------------------------------- dam break


def _solutions(scene) -> dict[str, Any]:

    h0 = float(scene.reservoir.depth_m)
    hr = float(scene.bed.wet_depth_m)
    f = float(scene.bed.friction_factor)
    g = float(scene.fluids.gravity_m_s2)
    out = {"Ritter": dam_break("ritter", h0, g=g)}
    if 0.0 < hr < h0:
        out["Stoker"] = dam_break("stoker", h0, hr_m=hr, g=g)
    if f > 0.0:
        out["Chanson"] = dam_break("chanson", h0, friction=f, g=g)
    return out


def gauge_models(scene, gauge_summary: pd.DataFrame, t_end_s: float, n: int = 400) -> dict[str, pd.DataFrame]:
    """Analytical water depth at every gauge over 0..t_end: gauge -> (time_s, <model>_m ...)."""
    solutions = _solutions(scene)
    t = np.linspace(0.0, max(t_end_s, 1e-6), n)
    out = {}
    for r in gauge_summary.itertuples():
        if not np.isfinite(r.x_m):
            continue
        frame = {"time_s": t}
        for name, sol in solutions.items():
            frame[f"{name.lower()}_m"] = np.array([float(sol.profile(r.x_m, tt).depth_m) for tt in t])
        out[r.gauge] = pd.DataFrame(frame)
    return out


def arrival_table(scene, gauge_summary: pd.DataFrame) -> pd.DataFrame:
    """Arrival times against the dam-break solutions and the study: one row per gauge and reference."""
    rows = []
    solutions = _solutions(scene) if scene is not None else {}
    for r in gauge_summary.itertuples():
        refs: list[tuple[str, float]] = []
        if np.isfinite(r.x_m) and r.x_m > 0:
            refs += [(name, float(sol.arrival_time_s(r.x_m))) for name, sol in solutions.items()]
        for x_study, (study_name, experiment, model) in STUDY_ARRIVALS.items():
            if np.isfinite(r.x_m) and abs(r.x_m - x_study) <= STUDY_GAUGE_TOLERANCE_M:
                refs += [(f"study experiment ({study_name})", experiment), (f"study model ({study_name})", model)]
        for ref, value in refs:
            sim = float(r.arrival_s)
            err = sim - value
            rows.append({"gauge": r.gauge, "x_m": r.x_m, "reference": ref, "reference_arrival_s": value,
                         "simulated_arrival_s": sim, "error_s": err,
                         "error_percent": 100.0 * err / value if value > 0 else np.nan})
    return pd.DataFrame(rows, columns=["gauge", "x_m", "reference", "reference_arrival_s", "simulated_arrival_s",
                                       "error_s", "error_percent"])


# --------------------------------------------------------------------------- impacts


def _body_geometry(data, body: str) -> tuple[float, tuple[float, float, float]] | None:
    for b in data.debris:
        if b.name == body:
            return float(b.mass_kg), tuple(float(v) for v in b.size_m)
    return None


def _formula_rows(results, column) -> pd.DataFrame:

    data = results.data
    rows = []
    for r in results.impacts.itertuples():
        geom = _body_geometry(data, r.body)
        if geom is None:
            continue
        mass, (length, width, height) = geom
        u = float(r.impact_velocity_m_s)
        if not (np.isfinite(u) and u > 0):
            u = float(r.normal_velocity_in_m_s)
        if not (np.isfinite(u) and u > 0):
            continue
        k_d = STUDY_DEBRIS_STIFFNESS_N_M
        # the structure's stiffness only for impacts on the column (walls are rigid here)
        k_s = float(column.stiffness_N_m) if column is not None and r.kind == "column" else None
        diameter = math.sqrt(4.0 * width * height / math.pi)
        gamma = mass * 9.81 / (length * width * height)
        mat = CONTAINER_MATERIAL
        methods: list[tuple[str, float, float, float]] = [
            ("contact model (simulated)", r.peak_force_N, r.duration_s, r.impulse_Ns)]
        a = asce7_impact(u, mass, k_d)
        methods.append(("ASCE 7-22, k_d", a.force_N, a.duration_s, a.impulse_Ns))
        if k_s:
            a = asce7_impact(u, mass, k_s)
            methods.append(("ASCE 7-22, k_s", a.force_N, a.duration_s, a.impulse_Ns))
        methods.append(("Haehnel & Daly, k_d", haehnel_daly(u, mass, k_d), math.pi * math.sqrt(mass / k_d),
                        2.0 * mass * u))
        if k_s:
            k = k_s * k_d / (k_s + k_d)
            methods.append(("Haehnel & Daly, k_d + k_s in series", haehnel_daly(u, mass, k_d, k_s),
                            math.pi * math.sqrt(mass / k), 2.0 * mass * u))
        methods.append(("Matsutomi (C_MA 1.7)", matsutomi(u, diameter, length, gamma, mat["yield_stress_Pa"],
                                                          mat["added_mass_coefficient"]), np.nan, np.nan))
        if column is not None:
            e_star = hertz_effective_modulus(mat["youngs_modulus_Pa"], mat["poisson_ratio"],
                                             column.youngs_modulus_Pa, column.poisson_ratio)
            methods.append(("Ikeno (C_MA 1.7)", ikeno(u, mass, diameter, e_star, mat["added_mass_coefficient"]),
                            np.nan, np.nan))
        for method, peak, duration, impulse in methods:
            rows.append({"event": r.event, "time_s": r.time_s, "body": r.body, "kind": r.kind,
                         "impact_velocity_m_s": u, "mass_kg": mass, "method": method, "peak_force_N": float(peak),
                         "duration_s": float(duration), "impulse_Ns": float(impulse),
                         "peak_ratio": float(peak) / r.peak_force_N if r.peak_force_N > 0 else np.nan})
    return pd.DataFrame(rows, columns=["event", "time_s", "body", "kind", "impact_velocity_m_s", "mass_kg", "method",
                                       "peak_force_N", "duration_s", "impulse_Ns", "peak_ratio"])


def _impact_record(results, column, event: int, t: np.ndarray, direction: np.ndarray, height_of: dict) -> np.ndarray:
    """Base shear along `direction` (horizontal unit) from every column impact pulse, at times t."""

    columns = (column, replace(column, size_x_m=column.size_y_m, size_y_m=column.size_x_m))
    total = np.zeros_like(t)
    for ev, (times, force) in results.pulses.items():
        height = min(max(height_of.get(ev, 0.5 * column.height_m), 1e-6), column.height_m)
        after = t >= times[0]
        if not after.any():
            continue
        for axis in (0, 1):
            if direction[axis] != 0.0 and np.any(force[:, axis] != 0.0):
                shear = mdof_response(Tabulated(times, force[:, axis]), columns[axis], height, t[after]).response_N
                total[after] += direction[axis] * shear
    return total


def _study_procedure(results, column, notes: list[str]):

    impacts = results.impacts
    on_column = impacts[impacts["kind"] == "column"] if len(impacts) else impacts
    fit_rows, table_rows, records = [], [], {}
    if column is None or on_column.empty:
        return pd.DataFrame(), pd.DataFrame(), records
    if len(on_column) > MAX_FITTED_IMPACTS:
        notes.append(f"the study's fits were made for the {MAX_FITTED_IMPACTS} largest of {len(on_column)} column "
                     f"impacts")
        on_column = on_column.nlargest(MAX_FITTED_IMPACTS, "peak_force_N")
    # the simulated base shear rings at the MDOF column's first frequency: the SDOF's frequency
    # bounds centre on it, as on a measured column they centre on the measured frequency
    sdof_column = replace(column, natural_frequency_Hz=float(column_model(column).frequencies_Hz[0]))
    height_of = {int(r.event): float(r.height_m) for r in on_column.itertuples()}
    height_of.update({int(r.event): float(r.height_m) for r in impacts.itertuples() if r.kind == "column"})
    for r in on_column.sort_values("time_s").itertuples():
        event = int(r.event)
        if event not in results.pulses:
            continue
        times, force = results.pulses[event]
        horizontal = np.array([force[:, 0].sum(), force[:, 1].sum()])
        if not np.any(horizontal):
            continue
        direction = horizontal / np.linalg.norm(horizontal)
        t = np.arange(times[0] - RECORD_PRE_S, times[0] + RECORD_POST_S, 1.0 / RECORD_RATE_HZ)
        record = _impact_record(results, column, event, t, direction, height_of)
        height = height_of[event]
        contact = Tabulated(times, force[:, :2] @ direction)
        mass = _body_geometry(results.data, r.body)
        u = float(r.impact_velocity_m_s) if r.impact_velocity_m_s > 0 else float(r.normal_velocity_in_m_s)
        pulses: dict[str, Any] = {"contact model (simulated)": contact}
        if mass is not None and u > 0:
            pulses["ASCE 7-22, k_d"] = asce7_impact(u, mass[0], STUDY_DEBRIS_STIFFNESS_N_M).pulse.shifted(times[0])
            pulses["ASCE 7-22, k_s"] = asce7_impact(u, mass[0], column.stiffness_N_m).pulse.shifted(times[0])
        fits = {}
        for name, fitter in (("SDOF fit", lambda: fit_sdof(t, record, column=sdof_column)),
                             ("MDOF fit", lambda: fit_mdof(t, record, column=column, height_m=height))):
            try:
                fits[name] = fitter()
            except DebrisfoamError as exc:
                notes.append(f"impact event {event}: the {name} failed ({exc})")
                continue
            pulses[name] = fits[name].pulse
            f = fits[name]
            fit_rows.append({"event": event, "model": name, "magnitude_N": f.magnitude_N, "duration_s": f.duration_s,
                             "start_s": f.start_s, "impulse_Ns": f.impulse_Ns, "rmse_N": f.rmse_N,
                             "peak_record_N": f.peak_measured_N, "peak_model_N": f.peak_model_N,
                             "natural_frequency_Hz": f.natural_frequency_Hz, "damping_ratio": f.damping_ratio,
                             "height_m": height})
        t_fine = np.arange(t[0], t[-1], 2e-5)
        sim_peak = float(np.max(_impact_record(results, column, event, t_fine, direction, height_of)))
        order = ["ASCE 7-22, k_d", "ASCE 7-22, k_s", "SDOF fit", "MDOF fit", "contact model (simulated)"]
        for method in order:
            if method not in pulses:
                continue
            pulse = pulses[method]
            peak_shear = float(np.max(mdof_response(pulse, column, height, t_fine).response_N))
            study = STUDY_TABLE1.get(method, (np.nan, np.nan, np.nan))
            table_rows.append({
                "event": event, "method": method, "magnitude_N": float(pulse.peak_N),
                "duration_s": float(pulse.duration_s), "impulse_Ns": float(pulse.impulse_Ns),
                "peak_base_shear_N": peak_shear, "ratio_to_simulated": peak_shear / sim_peak if sim_peak > 0 else np.nan,
                "study_magnitude_N": study[0], "study_duration_s": study[1], "study_impulse_Ns": study[2],
                "impact_velocity_m_s": u, "height_m": height,
            })
        records[event] = {"time_s": t, "record_N": record, "height_m": height, "pulses": pulses,
                          "sdof_N": fits["SDOF fit"].model_N if "SDOF fit" in fits else None,
                          "sdof_time_s": fits["SDOF fit"].time_s if "SDOF fit" in fits else None,
                          "mdof_N": fits["MDOF fit"].model_N if "MDOF fit" in fits else None,
                          "mdof_time_s": fits["MDOF fit"].time_s if "MDOF fit" in fits else None,
                          "simulated_peak_N": sim_peak}
    fit_cols = ["event", "model", "magnitude_N", "duration_s", "start_s", "impulse_Ns", "rmse_N", "peak_record_N",
                "peak_model_N", "natural_frequency_Hz", "damping_ratio", "height_m"]
    table_cols = ["event", "method", "magnitude_N", "duration_s", "impulse_Ns", "peak_base_shear_N",
                  "ratio_to_simulated", "study_magnitude_N", "study_duration_s", "study_impulse_Ns",
                  "impact_velocity_m_s", "height_m"]
    return pd.DataFrame(fit_rows, columns=fit_cols), pd.DataFrame(table_rows, columns=table_cols), records


# --------------------------------------------------------------------------- spreading


def _source_points(data) -> np.ndarray:
    """Initial debris centroids (x, y), m: the plan's bodies, else the scene's."""
    pts = [b.centre_of_mass_m[:2] for b in (data.plan.bodies if data.plan else ())]
    if not pts and data.scene is not None:
        pts = [b.centre_m[:2] for b in data.scene.debris]
    return np.asarray(pts, dtype=float).reshape(-1, 2)


def spreading_area(source_xy, half_angle_deg: float, x_end_m: float) -> np.ndarray:
    """Polygon (x, y) of a debris spreading area, m (see the module notes).

    The start line lies across the flow at the most upstream centroid of ``source_xy``
    (n x 2) and spans the centroids' lateral extent; the area widens from its two ends at
    ``half_angle_deg`` on either side of +x, up to ``x_end_m``. Vertices in order:
    (x0, y_min), (x_end, y_min - w), (x_end, y_max + w), (x0, y_max), w = (x_end - x0) tan.
    """
    src = np.asarray(source_xy, dtype=float).reshape(-1, 2)
    x0 = float(src[:, 0].min())
    y_min, y_max = float(src[:, 1].min()), float(src[:, 1].max())
    w = max(x_end_m - x0, 0.0) * math.tan(math.radians(half_angle_deg))
    return np.array([[x0, y_min], [x_end_m, y_min - w], [x_end_m, y_max + w], [x0, y_max]])


def spreading_angle_deg(source_xy, points_xy) -> np.ndarray:
    """Angle (degrees) from the source's start line to each point: 0 inside the line's
    lateral extent, NaN upstream of the line (see :func:`spreading_area`)."""
    src = np.asarray(source_xy, dtype=float).reshape(-1, 2)
    p = np.asarray(points_xy, dtype=float).reshape(-1, 2)
    x0 = src[:, 0].min()
    y_min, y_max = src[:, 1].min(), src[:, 1].max()
    dx = p[:, 0] - x0
    excess = np.maximum(np.maximum(y_min - p[:, 1], p[:, 1] - y_max), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        angle = np.degrees(np.arctan2(excess, dx))
    return np.where(dx > 0, angle, np.where(excess == 0, 0.0, np.nan))


def _spreading(results) -> tuple[pd.DataFrame, dict[str, np.ndarray]]:
    data = results.data
    src = _source_points(data)
    areas: dict[str, np.ndarray] = {}
    if src.size == 0:
        return pd.DataFrame(), areas
    x_end = float(data.plan.domain_m[0][1]) if data.plan else float(src[:, 0].max() + 5.0)
    for name, spec in SPREADING_ANGLES_DEG.items():
        areas[name] = spreading_area(src, spec["half_angle_deg"], x_end)
    rows = []
    bodies = results.bodies
    for body, track in (bodies.groupby("body") if not bodies.empty else []):
        angles = spreading_angle_deg(src, track[["x_m", "y_m"]].to_numpy(float))
        finite = angles[np.isfinite(angles)]
        max_angle = float(finite.max()) if finite.size else float("nan")
        row = {"body": body, "track_points": len(track), "max_spread_deg": max_angle,
               "final_x_m": float(track["x_m"].iloc[-1]), "final_y_m": float(track["y_m"].iloc[-1])}
        for name, spec in SPREADING_ANGLES_DEG.items():
            row[_area_column(name)] = bool(not finite.size or max_angle <= spec["half_angle_deg"] + 1e-9)
        rows.append(row)
    cols = ["body", "track_points", "max_spread_deg", "final_x_m", "final_y_m"] + [
        _area_column(n) for n in SPREADING_ANGLES_DEG]
    return pd.DataFrame(rows, columns=cols), areas


# --------------------------------------------------------------------------- entry points


def compare(results) -> Comparison:
    """Every comparison of :mod:`orchestrator.results.tables`' tables (see the module docstring)."""
    data = results.data
    notes: list[str] = []
    scene = data.scene
    if scene is None:
        notes.append("no scene: no analytical dam-break comparison")
        arrivals, models = arrival_table(None, results.gauge_summary), {}
    else:
        arrivals = arrival_table(scene, results.gauge_summary)
        t_end = results.reached_time_s or scene.run.end_time_s
        models = gauge_models(scene, results.gauge_summary, float(t_end))
    column = data.column
    formulas = _formula_rows(results, column) if len(results.impacts) else pd.DataFrame()
    if len(results.impacts) == 0:
        notes.append("no impacts: no comparison with ASCE 7-22 and the impact formulas, no SDOF/MDOF fits, "
                     "no Table 1")
    study_fits, table1, records = _study_procedure(results, column, notes)
    spreading, areas = _spreading(results)
    site = site_flow_speed(data.case, scene)
    asce = asce_design_table(results.impacts, data.body_masses_kg, float(column.stiffness_N_m), site) \
        if column is not None and len(results.impacts) else pd.DataFrame()
    return Comparison(arrivals, models, formulas, study_fits, table1, spreading, areas, records, notes, asce, site)


def write_tables(comp: Comparison, out_dir: str | Path) -> dict[str, Path]:
    """arrivals.csv, impact_formulas.csv, study_fits.csv, table1.csv, spreading.csv, asce.csv in out_dir."""
    out = Path(out_dir)
    written = {}
    for name in ("arrivals", "impact_formulas", "study_fits", "table1", "spreading", "asce"):
        written[name] = write_table(getattr(comp, name), out / f"{name}.csv")
    return written
