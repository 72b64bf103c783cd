"""Tracks checked against measured spreading: ensembles' tracks, their spreading angles and
lateral spread, beside Goseberg et al. 2016 and the ASCE 7-22 6.11.5.1 envelopes.

``debrisfoam report spreading ENSEMBLE_DIR... -o DIR`` (``make spreading``) reads finished
ensembles (:mod:`orchestrator.studies.ensemble`: ``ensemble.csv``, ``tracks.csv``,
``ensemble.json`` and the flow case's ``flow/scene.yaml``) and writes ``DIR/spreading.csv`` (one
row per track: :func:`track_columns`), ``DIR/summary.json`` and ``DIR/report.md`` with its
figures (:mod:`orchestrator.studies.spreading_report`). Nothing here moves a body: every angle
comes from the tracks the ensemble wrote; the definitions are
:mod:`orchestrator.results.spreading`'s.

Stations
--------
The angles and lateral spreads are read where the tracks cross stations across the flume
(:func:`stations`): by default ``STATION_GAP_M`` (0.3 m) upstream of the column's upstream face
and 0.5 m and 1.0 m further upstream (4.6, 4.1 and 3.6 m for the study's column face at
4.9 m), so that the column's stagnation zone and strikes do not enter them; a scene without a
column takes 0.5, 1.0 and 1.5 m downstream of its most downstream start.

The ASCE areas
--------------
Per track, the largest angle from its realisation's start line
(:func:`orchestrator.results.compare.spreading_angle_deg`, the areas of ASCE 7-22 6.11.5.1 as
the run's own spreading.csv draws them, from the realisation's perturbed starts: the line
across the flow at the most upstream start, spanning the starts' lateral extent), over the
points of the track at least :data:`MIN_RUN_M` downstream of the line (closer, a millimetre of
sideways drift is a large angle), before its first column strike and over all of it; the page
counts the tracks past 16.8 and 22.5 degrees.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.core.files import write_json_atomic, write_text_atomic
from orchestrator.results.compare import SPREADING_ANGLES_DEG, spreading_angle_deg
from orchestrator.results.spreading import (GOSEBERG_2016_BOXES, LATERAL_SPREAD_RATE, box_stats, flow_direction,
                                            lateral_spread, station_crossing, station_key, track_angles)
from orchestrator.scene.schema import Scene
from orchestrator.scene.scenefile import load_scene

__all__ = ["PATH_HALF_WIDTH_M", "STATION_GAP_M", "SceneSpread", "path_flow", "read_ensemble", "scene_summary", "spreading_study",
           "stations", "track_columns", "track_table"]

STATION_GAP_M = 0.3
"""The last station lies this far upstream of the column's upstream face (m)."""

MIN_RUN_M = 0.25
"""An angle needs at least this much streamwise run from the start (m)."""

SMALL_YAW_DEG = 4.0
"""Tracks whose start yaw is within this of the nominal heading: the spread without the yaw draw."""

_ENSEMBLE_FILES = ("ensemble.csv", "tracks.csv", "ensemble.json")


def stations(scene: Scene) -> list[float]:
    """The stations (m) of the module notes for ``scene``, upstream first."""
    if scene.column is not None:
        last = float(scene.column.x_m) - float(scene.column.size_x_m) / 2.0 - STATION_GAP_M
        return [round(last - 1.0, 6), round(last - 0.5, 6), round(last, 6)]
    x0 = max(float(b.centre_m[0]) for b in scene.debris)
    return [round(x0 + d, 6) for d in (0.5, 1.0, 1.5)]


@dataclass
class SceneSpread:
    """One ensemble read back: its scene, summary, tables and the per-track figures."""

    name: str
    folder: Path
    scene: Scene
    summary: dict[str, Any]
    table: pd.DataFrame
    tracks: pd.DataFrame
    stations_m: list[float]
    per_track: pd.DataFrame = field(default_factory=pd.DataFrame)

    @property
    def source_xy(self) -> np.ndarray:
        """The bodies' nominal starts (plan view), where the ASCE areas begin."""
        return np.array([b.centre_m[:2] for b in self.scene.debris], dtype=float)


def read_ensemble(folder: str | Path) -> SceneSpread:
    """A finished ensemble folder read back; InputError naming the file when one is missing or
    lacks its columns."""
    path = Path(folder)
    for name in _ENSEMBLE_FILES:
        if not (path / name).is_file():
            raise InputError("ENSEMBLE_DIR", f"{path} has no {name}: run debrisfoam ensemble into it first", str(path))
    try:
        summary = json.loads((path / "ensemble.json").read_text())
    except json.JSONDecodeError as err:
        raise InputError("ensemble.json", f"is not JSON ({err})", str(path / "ensemble.json")) from None
    table = pd.read_csv(path / "ensemble.csv")
    tracks = pd.read_csv(path / "tracks.csv")
    for name, frame, needed in (("ensemble.csv", table, ("realisation", "body", "start_yaw_deg", "struck",
                                                         "impact_time_s")),
                                ("tracks.csv", tracks, ("realisation", "body", "time_s", "x_m", "y_m"))):
        missing = [c for c in needed if c not in frame.columns]
        if missing:
            raise InputError(missing[0], f"column missing from {name}", str(path / name))
    scene_file = path / "flow" / "scene.yaml"
    scene = load_scene(scene_file if scene_file.is_file() else summary.get("scene", ""))
    return SceneSpread(scene.name, path, scene, summary, table, tracks, stations(scene))


def track_table(spread: SceneSpread) -> pd.DataFrame:
    """One row per (realisation, body) track: its start and start yaw, whether and when it first
    struck the column, its lateral position and angle at each station, its max and rest angles
    (:func:`~orchestrator.results.spreading.track_angles`) and its largest angle from the nominal
    start line before the first strike and over the whole track (module notes: from the
    realisation's own starts when ensemble.csv gives them, else the nominal ones)."""
    info = spread.table.set_index(["realisation", "body"])
    src_nominal = spread.source_xy
    starts = {int(r): g[["start_x_m", "start_y_m"]].to_numpy(float)
              for r, g in spread.table.groupby("realisation")} if "start_x_m" in spread.table else {}
    rows = []
    for (realisation, body), track in spread.tracks.groupby(["realisation", "body"], sort=True):
        track = track.sort_values("time_s", kind="stable")
        x, y = track["x_m"].to_numpy(float), track["y_m"].to_numpy(float)
        row: dict[str, Any] = {"scene": spread.name, "realisation": int(realisation), "body": body}
        meta = info.loc[(realisation, body)] if (realisation, body) in info.index else None
        row["start_yaw_deg"] = float(meta["start_yaw_deg"]) if meta is not None else math.nan
        struck = bool(meta["struck"]) if meta is not None else False
        t_strike = float(meta["impact_time_s"]) if struck else math.nan
        row.update(struck=struck, impact_time_s=t_strike)
        row.update(track_angles(x, y, spread.stations_m, MIN_RUN_M))
        src = starts.get(int(realisation), src_nominal)
        angles = spreading_angle_deg(src, np.column_stack([x, y]))
        angles[x < src[:, 0].min() + MIN_RUN_M] = np.nan
        before = track["time_s"].to_numpy(float) < t_strike if struck else np.ones(x.size, dtype=bool)
        row["asce_angle_pre_strike_deg"] = _finite_max(angles[before])
        row["asce_angle_deg"] = _finite_max(angles)
        rows.append(row)
    return pd.DataFrame(rows, columns=track_columns(spread.stations_m))


def track_columns(stations_m: Sequence[float]) -> list[str]:
    """spreading.csv's columns for these stations."""
    per_station = [c for xs in stations_m for c in (f"y_at_{station_key(xs)}", f"angle_at_{station_key(xs)}")]
    return (["scene", "realisation", "body", "start_yaw_deg", "struck", "impact_time_s", "x0_m", "y0_m"] + per_station
            + ["x_max_m", "y_at_x_max_m", "x_rest_m", "y_rest_m", "angle_max_deg", "angle_rest_deg",
               "asce_angle_pre_strike_deg", "asce_angle_deg"])


def _finite_max(values: np.ndarray) -> float:
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    return float(v.max()) if v.size else math.nan


def spread_profile(spread: SceneSpread, step_m: float = 0.1) -> pd.DataFrame:
    """The lateral spread (:func:`~orchestrator.results.spreading.lateral_spread`) at stations every
    ``step_m`` from the most downstream nominal start plus :data:`MIN_RUN_M` to the last station."""
    x_from = float(spread.source_xy[:, 0].max()) + MIN_RUN_M
    grid = np.arange(x_from, spread.stations_m[-1] + 1e-9, step_m)
    starts = spread.per_track[["x0_m", "y0_m"]].to_numpy(float)
    ys = {xs: [] for xs in grid}
    for (_, _), track in spread.tracks.groupby(["realisation", "body"], sort=True):
        track = track.sort_values("time_s", kind="stable")
        x, y = track["x_m"].to_numpy(float), track["y_m"].to_numpy(float)
        for xs in grid:
            ys[xs].append(station_crossing(x, y, xs))
    rows = [{"station_x_m": float(xs), **lateral_spread(starts[:, 1], np.array(ys[xs]), starts[:, 0], xs)}
            for xs in grid]
    return pd.DataFrame(rows)


def _round(value, digits: int = 4):
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return int(value)
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return round(v, digits) if math.isfinite(v) else None


def scene_summary(spread: SceneSpread) -> dict[str, Any]:
    """The page's figures for one ensemble: realisations, bodies, tracks, strikes; per station the
    lateral spread and the angles' box statistics; the max/rest angles pooled as the measured
    boxes pool them; the tracks past each ASCE envelope; the start yaw's hold on the angles."""
    t = spread.per_track
    last = station_key(spread.stations_m[-1])
    out: dict[str, Any] = {"scene": spread.name, "folder": str(spread.folder),
                           "realisations": int(spread.summary.get("realisations", t["realisation"].nunique())),
                           "bodies": len(spread.scene.debris), "tracks": int(len(t)),
                           "struck_share": _round(t["struck"].mean()) if len(t) else None,
                           "perturbation": spread.summary.get("perturbation"), "seed": spread.summary.get("seed"),
                           "realisations_wall_s": spread.summary.get("realisations_wall_s"),
                           "stations_m": spread.stations_m, "stations": {}}
    for xs in spread.stations_m:
        key = station_key(xs)
        entry = {k: _round(v, 5) for k, v in lateral_spread(t["y0_m"], t[f"y_at_{key}"], t["x0_m"], xs).items()}
        entry["angle_deg"] = {k: _round(v, 3) for k, v in box_stats(t[f"angle_at_{key}"]).items()}
        out["stations"][key] = entry
    dy_last = t[f"y_at_{last}"] - t["y0_m"]
    out["per_body_last_station"] = {
        str(body): {"mean_dy_m": _round(g.mean(), 5), "std_dy_m": _round(g.std(ddof=1), 5), "tracks": int(g.count())}
        for body, g in dy_last.groupby(t["body"])}
    pooled = pd.concat([t["angle_max_deg"], t["angle_rest_deg"]], ignore_index=True)
    out["angle_max_rest_deg"] = {k: _round(v, 3) for k, v in box_stats(pooled).items()}
    out["angle_max_deg"] = {k: _round(v, 3) for k, v in box_stats(t["angle_max_deg"]).items()}
    out["angle_rest_deg"] = {k: _round(v, 3) for k, v in box_stats(t["angle_rest_deg"]).items()}
    out["asce"] = {}
    for name, spec in SPREADING_ANGLES_DEG.items():
        half = float(spec["half_angle_deg"])
        pre, whole = t["asce_angle_pre_strike_deg"] > half + 1e-9, t["asce_angle_deg"] > half + 1e-9
        out["asce"][name] = {"half_angle_deg": half, "outside_pre_strike": int(pre.sum()),
                             "outside_pre_strike_share": _round(pre.mean()), "outside": int(whole.sum()),
                             "outside_share": _round(whole.mean())}
    out["asce_angle_pre_strike_deg_max"] = _round(t["asce_angle_pre_strike_deg"].max(), 3)
    out["asce_angle_deg_max"] = _round(t["asce_angle_deg"].max(), 3)
    angle = t[f"angle_at_{last}"]
    keep = angle.notna() & t["start_yaw_deg"].notna()
    yaw_fit: dict[str, Any] = {"tracks": int(keep.sum()), "slope": None, "r": None}
    if keep.sum() > 2 and t.loc[keep, "start_yaw_deg"].std() > 0:
        yaw = t.loc[keep, "start_yaw_deg"].to_numpy(float) - _nominal_yaw(spread, t.loc[keep, "body"])
        slope, _ = np.polyfit(yaw, angle[keep].to_numpy(float), 1)
        yaw_fit.update(slope=_round(slope), r=_round(np.corrcoef(yaw, angle[keep].to_numpy(float))[0, 1]))
        small = np.abs(yaw) <= SMALL_YAW_DEG
        yaw_fit["small_yaw"] = {"limit_deg": SMALL_YAW_DEG,
                                **{k: _round(v, 3) for k, v in box_stats(angle[keep].to_numpy(float)[small]).items()}}
    out["start_yaw"] = yaw_fit
    return out


def _nominal_yaw(spread: SceneSpread, bodies: pd.Series) -> np.ndarray:
    nominal = {b.name: float(getattr(b, "yaw_deg", 0.0) or 0.0) for b in spread.scene.debris}
    return np.array([nominal.get(b, 0.0) for b in bodies], dtype=float)


PATH_HALF_WIDTH_M = 0.2
"""The flow's direction is read over the starts' lateral extent widened by this on each side (m)."""


def path_flow(spread: SceneSpread) -> dict[str, Any]:
    """The direction of the scene's recorded flow along the bodies' path
    (:func:`~orchestrator.results.spreading.flow_direction`): from the most upstream nominal start to
    the last station, across the starts' extent +- :data:`PATH_HALF_WIDTH_M`, at half the first
    body's height above the bed; empty when the folder has no flow record."""
    from orchestrator.transport.flow import FlowField

    npz = spread.folder / "flow" / "results" / "flow_record.npz"
    if not npz.is_file():
        return {}
    flow = FlowField.load(npz)
    src = spread.source_xy
    level = float(spread.scene.debris[0].size_m[2]) / 2.0
    stats = flow_direction(flow.t_s, flow.x_m, flow.y_m, flow.z_m, flow.bed_z_m, flow.eta_m, flow.velocity_m_s,
                           (float(src[:, 0].min()), spread.stations_m[-1]),
                           (float(src[:, 1].min()) - PATH_HALF_WIDTH_M, float(src[:, 1].max()) + PATH_HALF_WIDTH_M),
                           level)
    return {k: _round(v, 5) for k, v in stats.items()}


def spreading_study(folders: Sequence[str | Path], out_dir: str | Path) -> dict[str, Path]:
    """Read every ensemble folder, write spreading.csv, summary.json, report.md and the figures
    to ``out_dir`` (module notes); the files written, by kind."""
    from orchestrator.studies.spreading_report import write_page

    if not folders:
        raise InputError("ENSEMBLE_DIR", "give at least one ensemble folder")
    spreads = []
    for folder in folders:
        spread = read_ensemble(folder)
        spread.per_track = track_table(spread)
        spreads.append(spread)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summaries = [scene_summary(s) | {"path_flow": path_flow(s)} for s in spreads]
    profiles = {s.name: spread_profile(s) for s in spreads}
    files = {"table": out / "spreading.csv", "summary": out / "summary.json"}
    table = pd.concat([s.per_track for s in spreads], ignore_index=True, sort=False)
    write_text_atomic(files["table"], table.to_csv(index=False, float_format="%.6g"))
    measured = {"goseberg_2016_boxes_deg": GOSEBERG_2016_BOXES, "lateral_spread_rate": LATERAL_SPREAD_RATE,
                "asce_envelopes": SPREADING_ANGLES_DEG}
    write_json_atomic(files["summary"], {"scenes": summaries, "measured": measured})
    files.update(write_page(out, spreads, summaries, profiles))
    return files
