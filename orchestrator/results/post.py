"""Post-processing a run: what the solver and the runner wrote -> tidy tables in DIR/results/.

:func:`post_case` reads whatever a case holds (a run stopped early, a run without debris or
without contacts is post-processed up to where it got; what is missing is listed in
``summary.json`` and the report, never crashed on) and writes, in ``DIR/results/``:

``gauges.csv``
    ``time_s`` and one ``<gauge>_elevation_m`` column per gauge: the water height on the
    gauge's vertical ``sets`` line, ``integral of alpha.water dz`` from the bed to the top of
    the line (see :func:`gauge_elevation`). Empty (NaN) where the line was obstructed.
``gauge_summary.csv``
    One row per gauge: position, initial level, arrival threshold, bore arrival time, peak
    elevation and its time, samples and obstructed samples.
``column_forces.csv``
    ``time_s``; the hydrodynamic force on the column from the ``forces`` function object,
    ``hydro_force_{x,y,z}_N`` (= ``pressure_force_*`` + ``viscous_force_*``) and its moment
    about the column's base ``hydro_moment_{x,y,z}_Nm``; the impact pulses of the contact
    events on the column ``impact_force_{x,y,z}_N``; their sum ``total_force_{x,y,z}_N``.
    One time axis: the solver's steps plus every sample of every impact pulse.
``bodies.csv``
    One row per body per solver step: ``time_s, body``, centre of mass ``x_m y_m z_m``,
    velocity ``u_m_s v_m_s w_m_s``, ``speed_m_s``, angular velocity ``omega_{x,y,z}_rad_s``,
    orientation as ``yaw_deg pitch_deg roll_deg`` (intrinsic z-y'-x'', as scenes give it) and
    as the rotation matrix ``q_xx .. q_zz`` (body axes -> scene axes, row-major).
``impacts.csv``
    One row per contact event that was an impact (see :data:`IMPACT_COLUMNS`): where
    (``height_m``, the contact point's height on the column), the water level at the column's
    face at that moment (``face_water_level_m``, the study's definition of impact height),
    the body's lowest point above the bed and whether it was ``afloat``, the pulse.
``column_response.csv``
    The total load on the column's MDOF model and the base shear at the load cell it causes
    (the quantity the seed's experiments measured), split into its hydrodynamic and impact
    parts (see :func:`column_response`).
``water_balance.csv``
    Per solver step, the water volume in the fluid mesh, the water leaving through the open
    boundaries (in all and through each: the outlet's, and the atmosphere's over the top of
    the air space) and the balance error (:func:`read_water_balance`): the conservation
    check. Water leaving over the top passing :data:`ATMOSPHERE_LOSS_WARNING` of the initial
    water is a warning (stderr, summary.json's ``missing``, the report).
``fringe_flux.csv``
    Overset runs: per reconstructed time and overset zone (0: the background), the cell
    counts and the net water and volume flux into the fringe cells
    (:mod:`orchestrator.results.fringe`): where the overset loses or makes water.
``summary.json``
    The headline figures, the run's status, wall time and cell count, what is missing.

With ``comparisons=True`` (the default) :func:`post_case` then writes the comparisons with
the analytical models and the seed (:mod:`orchestrator.results.compare`), the plots
(:mod:`orchestrator.report.plots`) and ``report.md`` (:mod:`orchestrator.report.markdown`) beside them.

Definitions (units: s, m, N, N m, m/s, rad/s, degrees):

* Gauge elevation: the integral of the sampled alpha.water over the line, with the first
  and last samples held to the bed and to the top of the line. The gauges sample each
  cell's value (``interpolationScheme cell``), so between two samples that straddle one
  cell face of the background mesh (its z planes, from plan.json) each value holds up to
  the face: the elevation is the water in the cells' column, and a still wet bed reads its
  depth whatever the cells above it (interpolated to the points, ``cellPoint``, a 15 mm
  bed layer under 4 cm cells read 20-21 mm). Elsewhere, and for cases sampled with
  ``cellPoint``, trapezoids between samples. Samples are
  missing where the line runs outside the fluid mesh (inside a debris body's hole, or a
  cell the sampler could not find); a gap longer than :data:`GAP_FACTOR` sample spacings is
  integrated only when its content is clear (water on both sides, air on both sides, water
  below the lowest sample, air above the highest), and a line covered over less than
  :data:`MIN_GAUGE_COVERAGE` of its length gives no elevation (NaN, counted as obstructed).
* Arrival time: the first time the elevation exceeds the gauge's initial level (the scene's
  still water there: the impoundment upstream of the gate, the wet bed downstream) by
  :data:`ARRIVAL_FRACTION` of the impoundment depth (8 mm for the seed's 0.40 m), linearly
  interpolated between samples (from the initial level at t = 0 before the first sample).
  A gauge whose level never rises that much (e.g. upstream of the gate) has none (NaN).
* Impact pulse metrics (:func:`impact_metrics`): peak force; duration from the first
  rise above zero to the last return to it (edges located inside their sample interval);
  impulse, the trapezoidal integral of the force.

Restarts: function objects start a new ``postProcessing/<name>/<start time>/`` folder at
every restart; the pieces are joined in time order and a later piece replaces anything an
earlier one wrote after its start. The solver logs (``log.<solver>.<k>``, then
``log.<solver>``) are joined the same way.
"""

from __future__ import annotations

import json
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import pandas as pd

from analytical.errors import DebrisfoamError, InputError
from orchestrator.case.outputs import (
    numeric_dirs, read_vector_table, read_force_series, WATER_BALANCE_TOLERANCE, ATMOSPHERE_LOSS_WARNING, read_water_balance, atmosphere_loss, water_balance_summary,
)
from orchestrator.core.jsonio import json_default

__all__ = [
    "ARRIVAL_FRACTION",
    "ATMOSPHERE_LOSS_WARNING",
    "GAP_FACTOR",
    "IMPACT_COLUMNS",
    "MIN_GAUGE_COVERAGE",
    "RESULTS_DIR",
    "WATER_BALANCE_TOLERANCE",
    "CaseData",
    "PostSummary",
    "PulseMetrics",
    "Results",
    "arrival_time",
    "atmosphere_loss",
    "column_response",
    "gauge_elevation",
    "impact_metrics",
    "load_case",
    "post_case",
    "read_body_tracks",
    "read_contact_events",
    "read_force_series",
    "read_gauge_samples",
    "read_vector_table",
    "read_water_balance",
    "tables",
    "water_balance_summary",
]

RESULTS_DIR = "results"
#: Bore arrival: a rise of this fraction of the impoundment depth above the initial level.
ARRIVAL_FRACTION = 0.02
#: Arrival threshold (m) when the scene (and so the impoundment depth) is unknown.
ARRIVAL_THRESHOLD_FALLBACK_M = 0.01
#: A gauge line covered over less than this fraction of its length gives no elevation.
MIN_GAUGE_COVERAGE = 0.95
#: Samples further apart than this many sample spacings leave a gap (an obstruction).
GAP_FACTOR = 1.5
#: Time step (s) of the column response around each impact, and the window around it (s).
RESPONSE_DT_S = 1.0e-5
RESPONSE_PRE_S = 2.0e-3
RESPONSE_POST_S = 0.10
#: At most this many samples of the hydrodynamic force go into its (quasi-static) base shear.
HYDRO_RESPONSE_SAMPLES = 1000
#: alpha.water at or above _WET is water, at or below _DRY is air (gauge gaps).
_WET, _DRY = 0.99, 0.01
_EPS = 1e-9

#: Columns of impacts.csv, in order.
IMPACT_COLUMNS = [
    "event", "time_s", "body", "other", "kind", "height_m", "face_water_level_m", "body_clearance_m", "afloat",
    "point_x_m", "point_y_m", "point_z_m",
    "normal_x", "normal_y", "normal_z", "impact_velocity_m_s", "normal_velocity_in_m_s",
    "tangential_velocity_in_m_s", "obliquity_deg", "peak_force_N", "time_of_peak_s", "duration_s",
    "impulse_Ns", "rebound_normal_velocity_m_s", "rebound_u_m_s", "rebound_v_m_s", "rebound_w_m_s",
    "rebound_speed_m_s", "restitution", "force_history",
]


# --------------------------------------------------------------------------- results


@dataclass(frozen=True)
class PostSummary:
    """What :func:`post_case` wrote. Times in s; ``headline`` holds the figures of summary.json."""

    case: Path
    results_dir: Path
    status: str
    reached_time_s: float | None
    end_time_s: float | None
    tables: dict[str, Path]
    plots: dict[str, Path]
    report: Path | None
    missing: tuple[str, ...]
    headline: dict[str, Any]

    def to_dict(self) -> dict[str, Any]:
        return {
            "case": str(self.case),
            "results_dir": str(self.results_dir),
            "status": self.status,
            "reached_time_s": self.reached_time_s,
            "end_time_s": self.end_time_s,
            "tables": {k: str(v) for k, v in self.tables.items()},
            "plots": {k: str(v) for k, v in self.plots.items()},
            "report": str(self.report) if self.report else None,
            "missing": list(self.missing),
            "headline": self.headline,
        }


@dataclass(frozen=True)
class PulseMetrics:
    """Peak (N) and its time (s), start, end and duration (s), impulse (N s) of a force pulse."""

    peak_N: float
    time_of_peak_s: float
    start_s: float
    end_s: float
    duration_s: float
    impulse_Ns: float


@dataclass
class CaseData:
    """What post-processing knows about a case: its plan, scene, run record and column.

    Every part is optional (None when absent or unreadable; ``notes`` says why).
    ``column`` is the scene's column as an :class:`analytical.column.Column`.
    """

    case: Path
    plan: dict | None
    scene: Any | None
    run: dict | None
    solver: str | None
    column: Any | None
    notes: list[str] = field(default_factory=list)

    @property
    def body_names(self) -> list[str]:
        from orchestrator.case.bodystate import read_body_properties

        try:
            names = [b.name for b in read_body_properties(self.case)]
        except Exception:  # an unreadable dictionary: fall back on the plan
            names = []
        if not names and self.plan:
            names = [b["name"] for b in self.plan.get("bodies", [])]
        return names

    @property
    def body_masses_kg(self) -> dict[str, float]:
        if self.plan:
            return {b["name"]: float(b["mass_kg"]) for b in self.plan.get("bodies", [])}
        if self.scene is not None:
            return {b.name: float(b.mass_kg) for b in self.scene.debris}
        return {}

    @property
    def depth_m(self) -> float | None:
        return float(self.scene.reservoir.depth_m) if self.scene is not None else None

    @property
    def bed_z_m(self) -> float:
        if self.plan and self.plan.get("domain_m"):
            return float(self.plan["domain_m"][2][0])
        return 0.0

    def column_base_m(self) -> np.ndarray | None:
        """Centre of the column's footprint on the bed (x, y, z), m."""
        if self.scene is None or self.scene.column is None:
            return None
        return np.array([self.scene.column.x_m, self.scene.column.y_m, self.bed_z_m])


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
    #: per step: water volume, outflow and the balance error (:func:`read_water_balance`)
    water_balance: pd.DataFrame | None = None
    #: overset: per reconstructed time and zone, the flux into the fringe (:mod:`orchestrator.results.fringe`)
    fringe_flux: pd.DataFrame | None = None


# --------------------------------------------------------------------------- the case


def _read_json(path: Path, notes: list[str]) -> dict | list | None:
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        notes.append(f"{path.name} could not be read ({exc}); ignored")
        return None


def load_case(case_dir: str | Path) -> CaseData:
    """Read plan.json, scene.yaml and run.json of a case (whichever exist).

    Raises InputError naming the directory when it is not a case (no plan.json and no
    system/controlDict).
    """
    case = Path(case_dir)
    if not case.is_dir():
        raise InputError("case_dir", "not a directory", str(case))
    if not (case / "plan.json").is_file() and not (case / "system" / "controlDict").is_file():
        raise InputError("case_dir", "not a debrisfoam case: it has neither plan.json nor system/controlDict "
                                     "(render one with `debrisfoam render SCENE -o DIR`)", str(case))
    case = case.resolve()
    notes: list[str] = []
    plan = _read_json(case / "plan.json", notes)
    run = _read_json(case / "run.json", notes)
    scene = None
    if (case / "scene.yaml").is_file():
        from orchestrator.scene.scenefile import load_scene

        try:
            scene = load_scene(case / "scene.yaml")
        except DebrisfoamError as exc:
            notes.append(f"scene.yaml could not be loaded ({exc}): no analytical comparisons")
    else:
        notes.append("no scene.yaml: no initial levels from the scene, no analytical comparisons")
    solver = (run or {}).get("solver") or (plan or {}).get("solver")
    column = None
    if scene is not None and scene.column is not None:
        from orchestrator.scene.schema import column_for_analysis

        column = column_for_analysis(scene)
    return CaseData(case, plan if isinstance(plan, dict) else None, scene,
                    run if isinstance(run, dict) else None, solver, column, notes)


# --------------------------------------------------------------------------- parsers


def _read_xy(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(z, alpha) of a raw `sets` file (axis z: 2 columns; axis xyz: 4)."""
    rows = []
    with open(path, errors="replace") as fh:
        for line in fh:
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            try:
                rows.append([float(v) for v in s])
            except ValueError:
                continue
    if not rows:
        return np.empty(0), np.empty(0)
    width = max(set(len(r) for r in rows), key=[len(r) for r in rows].count)
    data = np.array([r for r in rows if len(r) == width])
    z_col = 2 if width >= 4 else 0
    return data[:, z_col], data[:, -1]


def read_gauge_samples(case_dir: str | Path, function_object: str = "gauges",
                       field_name: str = "alpha.water") -> dict[str, list[tuple[float, np.ndarray, np.ndarray]]]:
    """Every gauge's samples: name -> [(time_s, z_m, alpha), ...] in time order.

    From ``postProcessing/<function_object>/<time>/<gauge>_<field>.xy``; a time written
    twice (a restart) keeps the last folder read.
    """
    base = Path(case_dir) / "postProcessing" / function_object
    suffix = f"_{field_name}.xy"
    out: dict[str, dict[float, tuple[np.ndarray, np.ndarray]]] = {}
    for t, folder in numeric_dirs(base):
        for path in sorted(folder.glob(f"*{suffix}")):
            name = path.name[: -len(suffix)]
            out.setdefault(name, {})[t] = _read_xy(path)
    return {name: [(t, *v) for t, v in sorted(samples.items())] for name, samples in out.items()}


def gauge_elevation(z_m, alpha, bed_m: float, top_m: float,
                    spacing_m: float | None = None, faces_m=None) -> tuple[float, float]:
    """Water height (m) on a vertical gauge line and the fraction of the line covered.

    ``integral of alpha dz`` from ``bed_m`` to ``top_m``: trapezoids between samples, the first
    and last samples held down to the bed and up to the top. A gap wider than
    :data:`GAP_FACTOR` x ``spacing_m`` (default: the smallest sample spacing) is integrated
    only when what it holds is clear: water on both sides (alpha >= 0.99), air on both sides
    (alpha <= 0.01), water below the lowest sample down to the bed, air above the highest
    up to the top; otherwise it is left out. The coverage is the integrated length over
    ``top_m - bed_m``.

    ``faces_m``: the mesh's cell faces along the line, for samples that are cell values (the
    ``cell`` interpolation): between two samples with exactly one face between them each
    value holds up to the face, so the integral is the water in the cells' column, whatever
    the spacing (a trapezoid there is off by up to half a spacing). Elsewhere, trapezoids.
    """
    z = np.asarray(z_m, dtype=float)
    a = np.clip(np.asarray(alpha, dtype=float), 0.0, 1.0)
    length = float(top_m) - float(bed_m)
    if z.size == 0 or length <= 0:
        return float("nan"), 0.0
    order = np.argsort(z, kind="stable")
    z, a = z[order], a[order]
    dz = np.diff(z)
    if spacing_m is None:
        positive = dz[dz > 0]
        spacing_m = float(positive.min()) if positive.size else length
    max_gap = GAP_FACTOR * float(spacing_m)
    wet, dry = a >= _WET, a <= _DRY
    ok = (dz <= max_gap) | (wet[1:] & wet[:-1]) | (dry[1:] & dry[:-1])
    piece = 0.5 * (a[1:] + a[:-1]) * dz
    if faces_m is not None and z.size > 1:
        f = np.sort(np.asarray(faces_m, dtype=float))
        first = np.searchsorted(f, z[:-1], side="right")  # the first face above each sample
        one = np.searchsorted(f, z[1:], side="left") - first == 1  # exactly one face inside
        face = f[np.minimum(first, f.size - 1)] if f.size else z[:-1]
        step = a[:-1] * (face - z[:-1]) + a[1:] * (z[1:] - face)
        piece = np.where(one, step, piece)
    total = float(np.sum(piece * ok))
    covered = float(np.sum(dz * ok))
    below, above = max(z[0] - bed_m, 0.0), max(top_m - z[-1], 0.0)
    if below <= max_gap or wet[0]:
        total += a[0] * below
        covered += below
    if above <= max_gap or dry[-1]:
        total += a[-1] * above
        covered += above
    return total, min(covered / length, 1.0)


def arrival_time(time_s, elevation_m, initial_m: float, threshold_m: float) -> float:
    """First time (s) the elevation exceeds ``initial_m + threshold_m``; NaN if never.

    Interpolated linearly between the samples around the crossing; before the first
    sample the level is taken as ``initial_m`` at t = 0. NaN samples are skipped.
    """
    t = np.asarray(time_s, dtype=float)
    e = np.asarray(elevation_m, dtype=float)
    keep = np.isfinite(t) & np.isfinite(e)
    t, e = t[keep], e[keep]
    level = float(initial_m) + float(threshold_m)
    above = np.flatnonzero(e > level)
    if above.size == 0:
        return float("nan")
    i = int(above[0])
    t0, e0 = (t[i - 1], e[i - 1]) if i > 0 else (0.0, float(initial_m))
    if e[i] == e0 or t[i] <= t0:
        return float(t[i])
    return float(t0 + (level - e0) / (e[i] - e0) * (t[i] - t0))


def impact_metrics(time_s, force_N) -> PulseMetrics:
    """Peak, duration and impulse of a compressive force pulse (force >= 0).

    Duration: from where the force first rises from zero to where it last returns to zero.
    Each edge is found inside its sample interval by extending the line through the pulse's
    first (last) two samples down to zero (exact for a linear edge; a half-sine sampled 44
    times is then within 0.1 %); where that line does not fall inside the interval (a step
    edge), the interval's zero sample is taken. The record's ends count as edges when the
    force is not zero there. Impulse: trapezoidal integral over the whole record.
    """
    t = np.asarray(time_s, dtype=float)
    f = np.asarray(force_N, dtype=float)
    if t.ndim != 1 or t.shape != f.shape or t.size < 2:
        raise InputError("force_N", f"need 1-D time and force of equal length >= 2, got {t.shape}, {f.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
        raise InputError("force_N", "the record holds NaN or infinite values")
    if np.any(np.diff(t) <= 0):
        raise InputError("time_s", "must increase strictly")
    i_peak = int(np.argmax(f))
    peak = float(f[i_peak])
    impulse = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(t)))
    if peak <= 0.0:
        return PulseMetrics(peak, float(t[i_peak]), float("nan"), float("nan"), 0.0, impulse)
    active = np.flatnonzero(f > 1e-9 * peak)
    first, last = int(active[0]), int(active[-1])

    def edge(zero: int, inner: int, next_: int) -> float:
        """Zero of the line through samples inner and next_, kept between zero and inner."""
        lo, hi = sorted((float(t[zero]), float(t[inner])))
        if 0 <= next_ < t.size and f[next_] > f[inner]:
            x = float(t[inner] - f[inner] * (t[next_] - t[inner]) / (f[next_] - f[inner]))
            if lo <= x <= hi:
                return x
        return float(t[zero])

    start = edge(first - 1, first, first + 1) if first > 0 else float(t[0])
    end = edge(last + 1, last, last - 1) if last < t.size - 1 else float(t[-1])
    return PulseMetrics(peak, float(t[i_peak]), start, end, end - start, impulse)


def _solver_logs(case: Path, solver: str) -> list[Path]:
    """log.<solver>.1, .2, ... (older segments) then log.<solver> (the latest)."""
    numbered = []
    for p in case.glob(f"log.{solver}.*"):
        suffix = p.name[len(f"log.{solver}."):]
        if suffix.isdigit():
            numbered.append((int(suffix), p))
    logs = [p for _, p in sorted(numbered)]
    if (case / f"log.{solver}").is_file():
        logs.append(case / f"log.{solver}")
    return logs


def _angles_deg(q: np.ndarray) -> tuple[float, float, float]:
    """(yaw, pitch, roll) of R = Rz(yaw) Ry(pitch) Rx(roll), degrees."""
    pitch = math.asin(max(-1.0, min(1.0, -q[2, 0])))
    yaw = math.atan2(q[1, 0], q[0, 0])
    roll = math.atan2(q[2, 1], q[2, 2])
    return math.degrees(yaw), math.degrees(pitch), math.degrees(roll)


_BODY_COLUMNS = ["time_s", "body", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s", "speed_m_s",
                 "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s", "yaw_deg", "pitch_deg", "roll_deg"] + [
                    f"q_{a}{b}" for a in "xyz" for b in "xyz"]


def _body_row(time_s: float, name: str, centre, velocity, omega, orientation) -> list:
    q = np.asarray(orientation, dtype=float).reshape(3, 3)
    v = [float(x) for x in velocity]
    return [float(time_s), name, *map(float, centre), *v, math.sqrt(sum(x * x for x in v)),
            *map(float, omega), *_angles_deg(q), *map(float, q.ravel())]


def read_body_tracks(case_dir: str | Path, solver: str, names: Sequence[str]) -> pd.DataFrame:
    """bodies.csv rows from the solver logs' per-step six-DoF reports (see the module notes).

    Falls back on the runner's own ``bodies.csv`` in the case when no log reports a body.
    """
    from orchestrator.run.monitor import parse_log

    case = Path(case_dir)
    pieces: list[tuple[float, pd.DataFrame]] = []
    if names:
        for log in _solver_logs(case, solver):
            steps, _ = parse_log(log, names)
            rows = [_body_row(s.time_s, b.name, b.centre_of_mass_m, b.velocity_m_s, b.angular_velocity_rad_s,
                              b.orientation) for s in steps for b in s.bodies]
            if rows:
                start = steps[0].time_s - (steps[0].delta_t_s or 0.0)
                pieces.append((start, pd.DataFrame(rows, columns=_BODY_COLUMNS)))
    if pieces:
        # join restarts by time, body by body (rows of one step share a time)
        joined = None
        for start, frame in pieces:
            if joined is not None:
                joined = joined[joined["time_s"] <= start + _EPS * max(1.0, abs(start))]
                joined = pd.concat([joined, frame], ignore_index=True)
            else:
                joined = frame
        joined = joined.drop_duplicates(subset=["time_s", "body"], keep="last")
        return joined.sort_values(["body", "time_s"], kind="stable").reset_index(drop=True)
    track = case / "bodies.csv"
    if track.is_file():
        raw = pd.read_csv(track)
        rows = []
        for r in raw.itertuples(index=False):
            d = r._asdict()
            q = [d[f"q_{a}{b}"] for a in "xyz" for b in "xyz"]
            rows.append(_body_row(d["time_s"], d["body"], (d["x_m"], d["y_m"], d["z_m"]),
                                  (d["u_m_s"], d["v_m_s"], d["w_m_s"]),
                                  (d["omega_x_rad_s"], d["omega_y_rad_s"], d["omega_z_rad_s"]), q))
        frame = pd.DataFrame(rows, columns=_BODY_COLUMNS)
        return frame.sort_values(["body", "time_s"], kind="stable").reset_index(drop=True)
    return pd.DataFrame(columns=_BODY_COLUMNS)


def read_contact_events(case_dir: str | Path) -> list[dict]:
    """The runner's contact events (contacts.json), [] when there are none."""
    path = Path(case_dir) / "contacts.json"
    if not path.is_file():
        return []
    events = json.loads(path.read_text())
    return events if isinstance(events, list) else []


def _read_history(path: Path) -> tuple[np.ndarray, np.ndarray] | None:
    if not path.is_file():
        return None
    frame = pd.read_csv(path)
    if "time_s" not in frame or "force_N" not in frame or len(frame) < 2:
        return None
    return frame["time_s"].to_numpy(float), frame["force_N"].to_numpy(float)


# --------------------------------------------------------------------------- tables


def _initial_level(data: CaseData, x_m: float, t_first: float, first: float) -> tuple[float, str]:
    """The gauge's level before the bore, and where it came from.

    The first sample, when it was taken before any disturbance could reach the gauge (the
    dry-bed front runs at 2 sqrt(g h0), the negative wave upstream at sqrt(g h0)): this is
    the still water as the mesh represents it. Otherwise the scene's still water there.
    """
    scene = data.scene
    if scene is None:
        return (first, "first sample") if math.isfinite(first) else (0.0, "none (no scene, no sample)")
    c0 = math.sqrt(scene.fluids.gravity_m_s2 * scene.reservoir.depth_m)
    reach_s = (x_m / (2.0 * c0)) if x_m >= 0 else (-x_m / c0)
    if math.isfinite(first) and math.isfinite(t_first) and t_first < reach_s:
        return first, "first sample"
    if -scene.reservoir.length_m <= x_m < 0.0:
        return float(scene.reservoir.depth_m), "scene (impoundment)"
    return float(scene.bed.wet_depth_m), "scene (bed)"


def _gauge_cell_faces(data: CaseData) -> np.ndarray | None:
    """The background mesh's z planes (every cell face a vertical gauge line crosses) when the
    gauges sample cell values (``interpolationScheme cell`` in system/controlDict); None when
    they interpolate (cellPoint: cases rendered before the gauges sampled cells) or the plan
    is missing."""
    try:
        control = (data.case / "system" / "controlDict").read_text(errors="replace")
    except OSError:
        return None
    scheme = re.search(r"\bgauges\s*\{[^}]*?interpolationScheme\s+(\w+)\s*;", control)
    segments = ((data.plan or {}).get("background") or {}).get("z")
    if not scheme or scheme.group(1) != "cell" or not segments:
        return None
    faces = [float(segments[0]["start_m"])]
    for seg in segments:  # blockMesh's simpleGrading: geometric cells, last over first = grading
        a, b, n, r = float(seg["start_m"]), float(seg["end_m"]), int(seg["cells"]), float(seg.get("grading", 1.0))
        sizes = np.ones(n) if n == 1 or abs(r - 1.0) < 1e-12 else (r ** (1.0 / (n - 1))) ** np.arange(n)
        faces += list(a + np.cumsum(sizes) / sizes.sum() * (b - a))
    return np.array(faces)


def _gauge_tables(data: CaseData, threshold_m: float | None) -> tuple[pd.DataFrame, pd.DataFrame]:
    samples = read_gauge_samples(data.case)
    plan_gauges = {g["name"]: g for g in (data.plan or {}).get("gauges", [])}
    bed = data.bed_z_m
    faces = _gauge_cell_faces(data)
    threshold = threshold_m
    if threshold is None:
        threshold = ARRIVAL_FRACTION * data.depth_m if data.depth_m else ARRIVAL_THRESHOLD_FALLBACK_M
    names = sorted(samples, key=lambda n: (list(plan_gauges).index(n) if n in plan_gauges else 1e9, n))
    series: dict[str, pd.Series] = {}
    rows = []
    for name in names:
        records = samples[name]
        diffs = [np.diff(np.sort(z)) for _, z, _ in records if z.size > 1]
        positive = np.concatenate(diffs) if diffs else np.empty(0)
        positive = positive[positive > 0]
        spacing = float(positive.min()) if positive.size else None
        g = plan_gauges.get(name, {})
        top = float(g.get("z_top", max((float(z.max()) for _, z, _ in records if z.size), default=bed)))
        values, obstructed = [], 0
        for _, z, a in records:
            h, coverage = gauge_elevation(z, a, bed, top, spacing, faces)
            if coverage < MIN_GAUGE_COVERAGE:
                h = float("nan")
                obstructed += 1
            values.append(h)
        t = np.array([r[0] for r in records])
        e = np.array(values)
        series[name] = pd.Series(e, index=t)
        x, y = g.get("x", float("nan")), g.get("y", float("nan"))
        finite = np.isfinite(e)
        first = float(e[finite][0]) if finite.any() else float("nan")
        t_first = float(t[finite][0]) if finite.any() else float("nan")
        initial, source = _initial_level(data, float(x) if math.isfinite(x) else 1.0, t_first, first)
        i_peak = int(np.nanargmax(e)) if finite.any() else None
        rows.append({
            "gauge": name, "x_m": x, "y_m": y, "initial_level_m": initial, "initial_level_from": source,
            "threshold_m": threshold,
            "arrival_s": arrival_time(t, e, initial, threshold),
            "peak_elevation_m": float(e[i_peak]) if i_peak is not None else float("nan"),
            "time_of_peak_s": float(t[i_peak]) if i_peak is not None else float("nan"),
            "samples": len(records), "obstructed_samples": obstructed,
        })
    if series:
        wide = pd.DataFrame({f"{n}_elevation_m": s for n, s in series.items()})
        wide.index.name = "time_s"
        wide = wide.sort_index().reset_index()
    else:
        wide = pd.DataFrame(columns=["time_s"])
    summary = pd.DataFrame(rows, columns=["gauge", "x_m", "y_m", "initial_level_m", "initial_level_from",
                                          "threshold_m", "arrival_s",
                                          "peak_elevation_m", "time_of_peak_s", "samples", "obstructed_samples"])
    return wide, summary


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


def _impact_rows(data: CaseData, events: list[dict], missing: list[str]):
    rows, pulses = [], {}
    masses = data.body_masses_kg
    for e in events:
        if e.get("type", "impact") != "impact":
            continue
        n = np.asarray(e.get("normal", (0.0, 0.0, 0.0)), dtype=float)
        point = np.asarray(e.get("point_m", (np.nan,) * 3), dtype=float)
        v_in = np.asarray(e.get("velocity_in_m_s", (np.nan,) * 3), dtype=float)
        v_out = np.asarray(e.get("velocity_out_m_s", (np.nan,) * 3), dtype=float)
        vn_in = abs(float(e.get("normal_velocity_in_m_s", np.nan)))
        obliquity = float(e.get("obliquity_deg", np.nan))
        history_path = data.case / str(e.get("force_history", ""))
        history = _read_history(history_path) if e.get("force_history") else None
        t_event = float(e["time_s"])
        if history is not None:
            metrics = impact_metrics(*history)
        else:
            missing.append(f"impact event {e.get('event')}: no force history ({history_path.name}); a half-sine of "
                           f"the recorded peak and duration stands in for it")
            peak, duration = float(e.get("peak_force_N", 0.0)), float(e.get("duration_s", 0.0))
            if peak > 0 and duration > 0:
                tt = np.linspace(0.0, duration, 201)
                history = (tt, peak * np.sin(np.pi * tt / duration))
                metrics = impact_metrics(*history)
            else:
                metrics = PulseMetrics(peak, 0.0, 0.0, duration, duration, float(e.get("impulse_Ns", 0.0)))
        if history is not None and e.get("kind") == "column":
            # force on the column: along -n (n points from the column into the body)
            pulses[int(e["event"])] = (t_event + history[0], np.outer(history[1], -n))
        rows.append({
            "event": int(e.get("event", len(rows) + 1)), "time_s": t_event, "body": e.get("body"),
            "other": e.get("other"), "kind": e.get("kind"), "height_m": float(e.get("height_m", np.nan)),
            "face_water_level_m": np.nan, "body_clearance_m": np.nan, "afloat": None,
            "point_x_m": point[0], "point_y_m": point[1], "point_z_m": point[2],
            "normal_x": n[0], "normal_y": n[1], "normal_z": n[2],
            "impact_velocity_m_s": float(-(v_in @ n)),
            "normal_velocity_in_m_s": vn_in,
            "tangential_velocity_in_m_s": vn_in * math.tan(math.radians(obliquity)) if obliquity < 90 else np.nan,
            "obliquity_deg": obliquity, "peak_force_N": metrics.peak_N, "time_of_peak_s": metrics.time_of_peak_s,
            "duration_s": metrics.duration_s, "impulse_Ns": metrics.impulse_Ns,
            "rebound_normal_velocity_m_s": float(e.get("normal_velocity_out_m_s", np.nan)),
            "rebound_u_m_s": v_out[0], "rebound_v_m_s": v_out[1], "rebound_w_m_s": v_out[2],
            "rebound_speed_m_s": float(np.linalg.norm(v_out)), "restitution": float(e.get("restitution", np.nan)),
            "force_history": e.get("force_history", ""),
        })
        if e.get("body") not in masses and masses:
            missing.append(f"impact event {e.get('event')}: body {e.get('body')!r} is not in plan.json")
    return pd.DataFrame(rows, columns=IMPACT_COLUMNS), pulses


#: A body is afloat at an impact when its lowest point is this far above the gap it rests on.
AFLOAT_CLEARANCE_M = 0.005
#: The column-face gauge: on the column's width, at most this far upstream of its face (m).
FACE_GAUGE_REACH_M = 0.10


def _face_gauge(data: CaseData) -> str | None:
    """The gauge at the column's upstream face (the study's impact height is its water level)."""
    scene = data.scene
    if scene is None or scene.column is None or not data.plan:
        return None
    col = scene.column
    face = col.x_m - col.size_x_m / 2
    best = None
    for g in data.plan.get("gauges", []):
        dx = face - float(g.get("x", np.nan))
        if 0.0 <= dx <= FACE_GAUGE_REACH_M and abs(float(g.get("y", np.nan)) - col.y_m) <= col.size_y_m / 2:
            if best is None or dx < best[0]:
                best = (dx, g["name"])
    return best[1] if best else None


def _impact_context(data: CaseData, impacts: pd.DataFrame, gauges: pd.DataFrame, bodies: pd.DataFrame,
                    missing: list[str]) -> pd.DataFrame:
    """Each impact's water level at the column's face (its gauge, interpolated at the impact time:
    the study's impact height), the body's lowest point above the bed, and whether it was afloat
    (lowest point more than AFLOAT_CLEARANCE_M above the gap a resting body stands on)."""
    if impacts.empty:
        return impacts
    out = impacts.copy()
    gauge = _face_gauge(data)
    column = f"{gauge}_elevation_m" if gauge else None
    if column and column in gauges:
        g = gauges[["time_s", column]].dropna()
        if len(g):
            out["face_water_level_m"] = np.interp(out["time_s"].to_numpy(float), g["time_s"], g[column])
    elif data.scene is not None and data.scene.column is not None:
        missing.append("no gauge at the column's upstream face: impacts.csv has no water level there "
                       "(add one with `at: column_upstream_face`)")
    sizes = {b["name"]: np.asarray(b["size_m"], float) for b in (data.plan or {}).get("bodies", [])}
    gap = float((data.plan or {}).get("bed_gap_m", 0.0) or 0.0)
    if bodies.empty or not sizes:
        return out
    clearances, afloat = [], []
    for r in out.itertuples():
        track = bodies[bodies["body"] == r.body]
        if r.body not in sizes or track.empty:
            clearances.append(np.nan)
            afloat.append(None)
            continue
        i = int(np.argmin(np.abs(track["time_s"].to_numpy(float) - float(r.time_s))))
        row = track.iloc[i]
        q_z = np.array([row["q_zx"], row["q_zy"], row["q_zz"]], dtype=float)
        low = float(row["z_m"]) - float(np.abs(q_z) @ (sizes[r.body] / 2)) - data.bed_z_m
        clearances.append(low)
        afloat.append(bool(low > gap + AFLOAT_CLEARANCE_M))
    out["body_clearance_m"] = clearances
    out["afloat"] = afloat
    return out


def _pulse_sum(pulses: dict[int, tuple[np.ndarray, np.ndarray]], t: np.ndarray) -> np.ndarray:
    """Sum of the impact pulses' force vectors at times t (zero outside each pulse), (n, 3)."""
    out = np.zeros((t.size, 3))
    for times, force in pulses.values():
        inside = (t >= times[0]) & (t <= times[-1])
        if inside.any():
            for i in range(3):
                out[inside, i] += np.interp(t[inside], times, force[:, i])
    return out


def _column_forces(hydro: pd.DataFrame | None, pulses) -> pd.DataFrame:
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
    impact = _pulse_sum(pulses, t)
    for i, a in enumerate("xyz"):
        out[f"impact_force_{a}_N"] = impact[:, i]
    for i, a in enumerate("xyz"):
        hydro_a = out[f"hydro_force_{a}_N"] if f"hydro_force_{a}_N" in out else 0.0
        out[f"total_force_{a}_N"] = hydro_a + impact[:, i]
    return out


def _effective_height(force: np.ndarray, moment_arm: np.ndarray, column_height: float) -> float:
    """Least-squares height z with moment = z * force, clipped to the column (m above the base)."""
    ok = np.isfinite(force) & np.isfinite(moment_arm)
    denom = float(np.sum(force[ok] ** 2))
    z = float(np.sum(force[ok] * moment_arm[ok]) / denom) if denom > 0 else 0.5 * column_height
    return min(max(z, 1e-3 * column_height), column_height)


def column_response(column, hydro: pd.DataFrame | None, pulses: dict[int, tuple[np.ndarray, np.ndarray]],
                    impact_heights_m: dict[int, float]) -> tuple[pd.DataFrame, dict[str, float]]:
    """Total load on the MDOF column and the base shear at the load cell (N).

    Hydrodynamic force: each horizontal component applied at one effective height, the
    least-squares centre of pressure over the run from the moment about the base
    (``M_y = z F_x``, ``M_x = -z F_y``), clipped to the column; its base shear is computed
    at the solver's output times and interpolated between them (the force varies over
    tenths of a second, the column's period is about 11 ms: quasi-static). Impact pulses:
    each at its own contact height; base shear on a 10 microsecond grid from 2 ms before to
    0.1 s after each impact (the ringing has decayed to about 1 % by then with the seed's
    4.5 % damping at 88 Hz). y loads bend the column with its section turned by 90 degrees.
    Linear superposition: ``base_shear = hydro part + impact part``.

    Returns (table, effective hydrodynamic heights {"x": z, "y": z}).
    """
    from dataclasses import replace

    from analytical.mdof import mdof_response
    from analytical.pulses import Tabulated

    columns = {"x": column, "y": replace(column, size_x_m=column.size_y_m, size_y_m=column.size_x_m)}
    axis_times = []
    if hydro is not None and len(hydro) >= 2:
        axis_times.append(hydro["time_s"].to_numpy(float))
    for event, (times, _) in pulses.items():
        t0 = times[0]
        axis_times.append(np.arange(t0 - RESPONSE_PRE_S, t0 + RESPONSE_POST_S, RESPONSE_DT_S))
    if not axis_times:
        return pd.DataFrame(columns=["time_s"]), {}
    t = np.unique(np.concatenate(axis_times))
    t_last = float(hydro["time_s"].max()) if hydro is not None and len(hydro) else float(t[-1])
    t = t[(t >= 0.0) & (t <= t_last + _EPS)]
    out = pd.DataFrame({"time_s": t})
    heights: dict[str, float] = {}
    impact = _pulse_sum(pulses, t)
    for i, a in enumerate("xy"):
        col = columns[a]
        hydro_force = np.zeros_like(t)
        hydro_shear = np.zeros_like(t)
        if hydro is not None and len(hydro) >= 2 and f"hydro_force_{a}_N" in hydro:
            th = hydro["time_s"].to_numpy(float)
            fh = hydro[f"hydro_force_{a}_N"].to_numpy(float)
            other = "y" if a == "x" else "x"
            sign = 1.0 if a == "x" else -1.0
            if f"hydro_moment_{other}_Nm" in hydro:
                arm = sign * hydro[f"hydro_moment_{other}_Nm"].to_numpy(float)
                z = _effective_height(fh, arm, col.height_m)
            else:
                z = 0.5 * col.height_m
            heights[a] = z
            ok = np.isfinite(fh)
            if ok.sum() >= 2 and np.any(fh[ok] != 0.0):
                ts, fs = th[ok], fh[ok]
                if ts.size > HYDRO_RESPONSE_SAMPLES:  # quasi-static: a coarser copy is enough
                    grid = np.linspace(ts[0], ts[-1], HYDRO_RESPONSE_SAMPLES)
                    ts, fs = grid, np.interp(grid, ts, fs)
                shear = mdof_response(Tabulated(ts, fs), col, z, ts).response_N
                hydro_shear = np.interp(t, ts, shear)
            hydro_force = np.interp(t, th, np.where(np.isfinite(fh), fh, 0.0))
            outside = (t < th[0]) | (t > th[-1])
            hydro_force[outside] = np.nan
            hydro_shear[outside] = np.nan
        impact_shear = np.zeros_like(t)
        for event, (times, force) in pulses.items():
            if np.any(force[:, i] != 0.0):
                height = min(max(impact_heights_m.get(event, 0.5 * col.height_m), 1e-6), col.height_m)
                after = t >= times[0]
                impact_shear[after] += mdof_response(Tabulated(times, force[:, i]), col, height, t[after]).response_N
        out[f"hydro_force_{a}_N"] = hydro_force
        out[f"impact_force_{a}_N"] = impact[:, i]
        out[f"total_force_{a}_N"] = np.where(np.isnan(hydro_force), 0.0, hydro_force) + impact[:, i]
        out[f"hydro_base_shear_{a}_N"] = hydro_shear
        out[f"impact_base_shear_{a}_N"] = impact_shear
        out[f"base_shear_{a}_N"] = np.where(np.isnan(hydro_shear), 0.0, hydro_shear) + impact_shear
    return out, heights


def tables(case_dir: str | Path, arrival_threshold_m: float | None = None) -> Results:
    """Read a case and build every table (nothing written): see the module docstring."""
    data = load_case(case_dir)
    missing = list(data.notes)
    gauges, gauge_summary = _gauge_tables(data, arrival_threshold_m)
    if gauge_summary.empty:
        missing.append("no gauge output (postProcessing/gauges)")
    else:
        blocked = gauge_summary[gauge_summary["obstructed_samples"] > 0]
        for r in blocked.itertuples():
            missing.append(f"gauge {r.gauge}: line obstructed (by a body, or outside the mesh) at "
                           f"{r.obstructed_samples} of {r.samples} samples; no elevation there")
    hydro, note = _hydro_table(data)
    if note:
        missing.append(note)
    if hydro is None and (data.scene is None or data.scene.column is not None):
        missing.append("no column force output (postProcessing/columnForces)")
    events = read_contact_events(data.case)
    impacts, pulses = _impact_rows(data, events, missing)
    forces = _column_forces(hydro, pulses)
    names = data.body_names
    bodies = read_body_tracks(data.case, data.solver, names) if (data.solver and names) else pd.DataFrame(
        columns=_BODY_COLUMNS)
    if names and bodies.empty:
        missing.append("no body reports in the solver logs (and no bodies.csv from the runner)")
    impacts = _impact_context(data, impacts, gauges, bodies, missing)
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
    if balance is None:
        missing.append("no water balance output (postProcessing/waterVolume): rendered before it existed?")
    else:
        b = water_balance_summary(balance)
        if abs(b["max_error"]) > WATER_BALANCE_TOLERANCE:
            missing.append(
                f"water not conserved: {abs(b['max_error']) * 100:.2f} % of the initial water "
                f"{'created' if b['max_error'] > 0 else 'lost'} by t = {b['time_of_max_error_s']:.3g} s "
                f"(over the {WATER_BALANCE_TOLERANCE * 100:g} % bound; results/water_balance.csv; docs/stability.md)"
                + _fringe_note(fringe))
        warning = _atmosphere_warning(data, balance)
        if warning:
            missing.append(warning)
    return Results(data, gauges, gauge_summary, forces, bodies, impacts, response, pulses, heights, missing, reached,
                   balance, fringe)


def _atmosphere_warning(data: CaseData, balance: pd.DataFrame | None) -> str | None:
    """The sentence post warns with when more than :data:`ATMOSPHERE_LOSS_WARNING` of the water
    left through the top of the air space; None otherwise."""
    loss = atmosphere_loss(balance)
    if loss is None or loss[1] is None:
        return None
    top = ((data.plan or {}).get("domain_m") or [None, None, [None, None]])[2][1]
    where = f" at z = {top:.3g} m" if top is not None else ""
    return (f"water left through the top of the air space{where}: {loss[0] * 100:.2f} % of the initial water "
            f"by the end (past {ATMOSPHERE_LOSS_WARNING * 100:g} % at t = {loss[1]:.3g} s); the water balance "
            "books it as outflow. The run-up rose above the modelled air space: raise it with mesh.top_m "
            "(plan.json reasons.domain_top; results/water_balance.csv, outflow_atmosphere_m3)")


def _fringe_flux(data: CaseData, missing: list[str]) -> pd.DataFrame | None:
    """The overset fringe flux of the reconstructed times (None when not overset or none has the fields)."""
    if data.solver != "overInterDyMFoam":
        return None
    from orchestrator.results.fringe import fringe_table

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
    run = data.run or {}
    if run.get("reached_time_s") is not None and run.get("status") == "finished":
        return float(run["reached_time_s"])
    last = [float(f["time_s"].max()) for f in frames if not f.empty and "time_s" in f]
    segs = run.get("segments") or []
    if segs:
        try:
            last.append(float(segs[-1]["end_time"]))
        except (KeyError, ValueError):
            pass
    return max(last) if last else None


# --------------------------------------------------------------------------- summary


def _finite(value) -> float | None:
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _wall_times(run: dict | None) -> dict[str, float | None]:
    if not run:
        return {"solver_s": None, "mesh_s": None, "total_s": None}
    solver = sum(float(s.get("wall_s", 0.0)) for s in run.get("segments", []))
    mesh = sum(float(s.get("wall_s", 0.0)) for s in run.get("steps", []) if not s.get("skipped"))
    between = float((run.get("runner") or {}).get("between_segments_s", 0.0))
    return {"solver_s": round(solver, 3), "mesh_s": round(mesh, 3), "total_s": round(solver + mesh + between, 3)}


def _cells(data: CaseData) -> int | None:
    cells = (data.run or {}).get("cells") or {}
    for key in ("total", "planned"):
        if cells.get(key):
            return int(cells[key])
    if data.plan and data.plan.get("cell_count"):
        return int(data.plan["cell_count"])
    return None


def headline(results: Results) -> dict[str, Any]:
    """The headline figures of summary.json (comparisons add theirs under "comparisons")."""
    data = results.data
    run = data.run or {}
    status = run.get("status") or ("unknown (no run.json: run by hand?)" if not run else "unknown")
    end = _finite((run.get("end_time_s") if run else None) or (data.scene.run.end_time_s if data.scene else None))
    out: dict[str, Any] = {
        "case": str(data.case),
        "scene": data.scene.name if data.scene is not None else None,
        "solver": data.solver,
        "status": status,
        "end_time_s": end,
        "reached_time_s": _finite(results.reached_time_s),
        "complete": status == "finished",
        "cells": _cells(data),
        "wall_time_s": _wall_times(data.run),
        "time_steps": run.get("time_steps"),
    }
    out["gauges"] = {
        r.gauge: {"x_m": _finite(r.x_m), "arrival_s": _finite(r.arrival_s), "peak_elevation_m": _finite(r.peak_elevation_m),
                  "time_of_peak_s": _finite(r.time_of_peak_s)}
        for r in results.gauge_summary.itertuples()
    }
    cf = results.column_forces
    if "hydro_force_x_N" in cf and cf["hydro_force_x_N"].notna().any():
        i = int(cf["hydro_force_x_N"].abs().idxmax())
        out["hydro_force"] = {"peak_x_N": _finite(cf.loc[i, "hydro_force_x_N"]), "time_of_peak_s": _finite(cf.loc[i, "time_s"])}
    imp = results.impacts
    out["impacts"] = {"count": int(len(imp)), "on_column": int((imp["kind"] == "column").sum()) if len(imp) else 0}
    if len(imp):
        first = imp.sort_values("time_s").iloc[0]
        out["impacts"]["first"] = {
            "event": int(first["event"]), "time_s": _finite(first["time_s"]), "body": first["body"],
            "other": first["other"], "impact_velocity_m_s": _finite(first["impact_velocity_m_s"]),
            "peak_force_N": _finite(first["peak_force_N"]), "duration_s": _finite(first["duration_s"]),
            "impulse_Ns": _finite(first["impulse_Ns"]), "height_m": _finite(first["height_m"]),
            "face_water_level_m": _finite(first["face_water_level_m"]),
            "body_clearance_m": _finite(first["body_clearance_m"]),
            "afloat": None if first["afloat"] is None or first["afloat"] != first["afloat"] else bool(first["afloat"]),
        }
        out["impacts"]["peak_force_N"] = _finite(imp["peak_force_N"].max())
    events = read_contact_events(data.case)
    resting = [e for e in events if e.get("type") == "resting"]
    if resting:
        out["impacts"]["resting_contacts"] = len(resting)
    pinned = [{"body": e["body"], "other": e["other"], "time_s": _finite(e["time_s"])}
              for e in events if e.get("type") == "pinned"]
    if pinned:  # held against an obstacle by the flow from then on (the runner froze it there)
        out["impacts"]["pinned"] = pinned
    on_bed = [{"body": e["body"], "time_s": _finite(e["time_s"])} for e in events if e.get("type") == "rest_on_bed"]
    if on_bed:  # kept on the bed's plane from then on (the flow kept pulling it into the bed)
        out["impacts"]["rest_on_bed"] = on_bed
    cr = results.column_response
    if "base_shear_x_N" in cr and len(cr):
        shear = np.hypot(cr["base_shear_x_N"].to_numpy(float), cr["base_shear_y_N"].to_numpy(float))
        i = int(np.nanargmax(shear))
        out["column_response"] = {
            "peak_base_shear_N": _finite(shear[i]), "time_of_peak_s": _finite(cr["time_s"].iloc[i]),
            "peak_impact_base_shear_N": _finite(np.nanmax(np.abs(cr["impact_base_shear_x_N"]))),
            "hydro_load_height_m": {k: round(v, 4) for k, v in results.hydro_heights_m.items()},
            "column_base": data.column.base if data.column is not None else None,
        }
    if not results.bodies.empty:
        out["bodies"] = sorted(results.bodies["body"].unique().tolist())
    balance = water_balance_summary(results.water_balance)
    if balance is not None:
        out["water_balance"] = balance
    return out


# --------------------------------------------------------------------------- entry point


def _write_csv(frame: pd.DataFrame, path: Path) -> Path:
    tmp = path.with_name(f".{path.name}.tmp")
    frame.to_csv(tmp, index=False, float_format="%.10g")
    tmp.replace(path)
    return path


def post_case(case_dir: str | Path, *, comparisons: bool = True, snapshot: bool = True,
              arrival_threshold_m: float | None = None) -> PostSummary:
    """Post-process a case into ``DIR/results/`` (see the module docstring); returns what was written.

    comparisons: also the comparisons with the analytical models and the seed, the plots
    and report.md. snapshot: include the pyvista 3D snapshot (needs fields on disk).
    arrival_threshold_m: rise above the initial level that marks the bore's arrival
    (default :data:`ARRIVAL_FRACTION` of the impoundment depth).

    Raises InputError when ``case_dir`` is not a case.
    """
    results = tables(case_dir, arrival_threshold_m)
    data = results.data
    warning = _atmosphere_warning(data, results.water_balance)
    if warning:
        print(f"debrisfoam: warning: {data.case}: {warning}", file=sys.stderr)
    out_dir = data.case / RESULTS_DIR
    out_dir.mkdir(exist_ok=True)
    written = {
        "gauges": _write_csv(results.gauges, out_dir / "gauges.csv"),
        "gauge_summary": _write_csv(results.gauge_summary, out_dir / "gauge_summary.csv"),
        "column_forces": _write_csv(results.column_forces, out_dir / "column_forces.csv"),
        "bodies": _write_csv(results.bodies, out_dir / "bodies.csv"),
        "impacts": _write_csv(results.impacts, out_dir / "impacts.csv"),
        "column_response": _write_csv(results.column_response, out_dir / "column_response.csv"),
    }
    if results.water_balance is not None:
        written["water_balance"] = _write_csv(results.water_balance, out_dir / "water_balance.csv")
    if results.fringe_flux is not None:
        written["fringe_flux"] = _write_csv(results.fringe_flux, out_dir / "fringe_flux.csv")
    figures = headline(results)
    plots: dict[str, Path] = {}
    report_path = None
    if comparisons:
        from orchestrator.results import compare
        from orchestrator.report import plots as plotting
        from orchestrator.report import markdown as report

        comp = compare.compare(results)
        written.update(compare.write_tables(comp, out_dir))
        figures["comparisons"] = comp.headline()
        plots, plot_notes = plotting.make_plots(results, comp, out_dir, snapshot_3d=snapshot)
        results.missing.extend(comp.notes)
        results.missing.extend(plot_notes)
        report_path = report.write_report(results, comp, figures, written, plots, out_dir / "report.md")
    figures["missing"] = list(dict.fromkeys(results.missing))
    figures["tables"] = {k: p.name for k, p in written.items()}
    figures["plots"] = {k: p.name for k, p in plots.items()}
    summary_path = out_dir / "summary.json"
    tmp = summary_path.with_name(".summary.json.tmp")
    tmp.write_text(json.dumps(figures, indent=2, default=json_default))
    tmp.replace(summary_path)
    written["summary"] = summary_path
    return PostSummary(data.case, out_dir, figures["status"], figures["reached_time_s"], figures["end_time_s"],
                       written, plots, report_path, tuple(figures["missing"]), figures)
