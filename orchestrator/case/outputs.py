"""What OpenFOAM's function objects write into a case's postProcessing/ folder, read back.

Each function object writes one folder per (re)start time, ``postProcessing/<name>/<start>/``;
a restart's piece replaces what an earlier piece wrote after that start. The readers here join
the pieces into one table per function object. The runner reads the water balance while a run
goes on; post-processing reads everything after it.
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from orchestrator.case.folder import EPS_T


def numeric_dirs(base: Path) -> list[tuple[float, Path]]:
    out = []
    if base.is_dir():
        for p in base.iterdir():
            if p.is_dir():
                try:
                    out.append((float(p.name), p))
                except ValueError:
                    continue
    return sorted(out, key=lambda item: item[0])


def read_vector_table(path: str | Path) -> tuple[pd.DataFrame, dict[str, Any]]:
    """A v1912 function-object table (force.dat, moment.dat): rows of a time and vectors.

    Returns the table with the header's names (``time`` and e.g. ``total_x``, ...,
    ``viscous_z``) and the header's ``key: value`` entries (e.g. ``CofR``). Lines that do
    not parse (a line cut short when the solver was killed) are skipped.
    """
    path = Path(path)
    names: list[str] | None = None
    meta: dict[str, Any] = {}
    rows: list[list[float]] = []
    with open(path, errors="replace") as fh:
        for line in fh:
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                body = s[1:].strip()
                if body.startswith("Time"):
                    names = ["time"] + re.findall(r"[A-Za-z][A-Za-z0-9_]*", body)[1:]
                elif ":" in body:
                    key, _, value = body.partition(":")
                    nums = re.findall(r"[-+0-9.eE]+", value)
                    try:
                        meta[key.strip()] = tuple(float(v) for v in nums) if nums else value.strip()
                    except ValueError:
                        meta[key.strip()] = value.strip()
                continue
            try:
                rows.append([float(v) for v in s.replace("(", " ").replace(")", " ").split()])
            except ValueError:
                continue
    if not rows:
        return pd.DataFrame(columns=names or ["time"]), meta
    width = max(set(len(r) for r in rows), key=[len(r) for r in rows].count)
    rows = [r for r in rows if len(r) == width]
    if names is None or len(names) != width:
        names = ["time"] + [f"c{i}" for i in range(1, width)]
    return pd.DataFrame(rows, columns=names), meta


def join_pieces(pieces: list[tuple[float, pd.DataFrame]], time_col: str) -> pd.DataFrame | None:
    """Join restart pieces in start order; a later piece replaces what came after its start."""
    combined: pd.DataFrame | None = None
    for start, frame in sorted(pieces, key=lambda p: p[0]):
        if frame.empty:
            continue
        if combined is not None:
            combined = combined[combined[time_col] <= start + EPS_T * max(1.0, abs(start))]
            combined = pd.concat([combined, frame], ignore_index=True)
        else:
            combined = frame.copy()
    if combined is None:
        return None
    combined = combined.drop_duplicates(subset=time_col, keep="last")
    return combined.sort_values(time_col, kind="stable").reset_index(drop=True)


def read_force_series(case_dir: str | Path, function_object: str = "columnForces",
                      stem: str = "force") -> tuple[pd.DataFrame | None, dict[str, Any]]:
    """Every piece of ``postProcessing/<function_object>/<start>/<stem>*.dat`` joined over restarts.

    Returns (table or None, header entries of the first piece).
    """
    base = Path(case_dir) / "postProcessing" / function_object
    pieces: list[tuple[float, pd.DataFrame]] = []
    meta: dict[str, Any] = {}
    pattern = re.compile(rf"{re.escape(stem)}(?:_([-+0-9.eE]+))?\.dat")
    for start, folder in numeric_dirs(base):
        for path in sorted(folder.iterdir()):
            m = pattern.fullmatch(path.name)
            if not m:
                continue
            frame, header = read_vector_table(path)
            meta = meta or header
            pieces.append((float(m.group(1)) if m.group(1) else start, frame))
    return join_pieces(pieces, "time"), meta


#: the water balance's bound: a run that creates or loses more than this fraction of its
#: water is flagged in summary.json and report.md
WATER_BALANCE_TOLERANCE = 0.01

#: function objects of the water balance (templates/system/controlDict.j2)
WATER_VOLUME_FO = "waterVolume"
WATER_OUTFLOW_FO_PREFIX = "waterOut_"
#: the open top of the air space (render.BACKGROUND_PATCH_KINDS)
ATMOSPHERE_PATCH = "atmosphere"
#: water that left through the top of the air space, as a fraction of the initial water, above
#: which post warns (stderr, summary.json, report.md): a flume's water leaves through its outlet,
#: not its top, so more than this says the air space was cut below the run-up (plan.json
#: reasons.domain_top; mesh.top_m raises it). The water balance books it as outflow and stays
#: closed, so nothing else would say so.
ATMOSPHERE_LOSS_WARNING = 0.001


def scalar_series(case: Path, function_object: str, stem: str) -> pd.DataFrame | None:
    """``postProcessing/<function_object>/<start>/<stem>.dat`` (time and one value) over restarts."""
    pieces = []
    for start, folder in numeric_dirs(case / "postProcessing" / function_object):
        path = folder / f"{stem}.dat"
        if path.is_file():
            frame, _ = read_vector_table(path)
            if frame.shape[1] >= 2:
                pieces.append((start, pd.DataFrame({"time": frame.iloc[:, 0], "value": frame.iloc[:, 1]})))
    return join_pieces(pieces, "time")


def read_water_balance(case_dir: str | Path) -> pd.DataFrame | None:
    """The water balance of a run, per solver step (None when the case has no such output).

    From the ``waterVolume`` (alpha.water integrated over the fluid mesh; the background
    mesh when overset) and ``waterOut_<patch>`` (the MULES water flux ``alphaPhi0.water``
    summed over each open patch) function objects. Columns: ``time_s``, ``volume_m3``,
    ``outflow_m3_s`` (all open patches; > 0 leaving), ``outflow_m3`` (cumulative, the
    step's flux times its step), ``outflow_<patch>_m3`` (cumulative, each open patch on its
    own: ``outflow_atmosphere_m3`` is what left through the top of the air space,
    ``outflow_downstream_m3`` through the outlet), ``initial_m3`` and ``error`` = (volume +
    outflow - initial) / initial: the water created (> 0) or lost (< 0) as a fraction of what
    there was.

    ``initial_m3`` is the volume before the first step: the first step's volume plus what it
    let out. On restarts a later piece replaces what an earlier one wrote after its start.
    """
    case = Path(case_dir)
    volume = scalar_series(case, WATER_VOLUME_FO, "volFieldValue")
    if volume is None or volume.empty:
        return None
    t = volume["time"].to_numpy(float)
    outflow = np.zeros_like(t)
    dt = np.diff(np.concatenate([[0.0], t]))
    by_patch: dict[str, np.ndarray] = {}
    base = case / "postProcessing"
    for folder in sorted(base.glob(f"{WATER_OUTFLOW_FO_PREFIX}*")):
        flux = scalar_series(case, folder.name, "surfaceFieldValue")
        if flux is not None and not flux.empty:
            rate = np.interp(t, flux["time"].to_numpy(float), flux["value"].to_numpy(float), left=0.0, right=0.0)
            outflow += rate
            by_patch[folder.name[len(WATER_OUTFLOW_FO_PREFIX):]] = np.cumsum(rate * dt)
    cumulative = np.cumsum(outflow * dt)
    v = volume["value"].to_numpy(float)
    initial = v[0] + cumulative[0]
    error = (v + cumulative - initial) / initial if initial > 0 else np.full_like(v, np.nan)
    return pd.DataFrame({"time_s": t, "volume_m3": v, "outflow_m3_s": outflow, "outflow_m3": cumulative,
                         **{f"outflow_{patch}_m3": out for patch, out in by_patch.items()},
                         "initial_m3": initial, "error": error})


def atmosphere_loss(balance: pd.DataFrame | None) -> tuple[float, float | None] | None:
    """The water that left through the top of the air space by the end, as a fraction of the
    initial water, and the first time it passed :data:`ATMOSPHERE_LOSS_WARNING` (None: it
    never did). None when the balance has no atmosphere patch."""
    column = f"outflow_{ATMOSPHERE_PATCH}_m3"
    if balance is None or balance.empty or column not in balance:
        return None
    initial = float(balance["initial_m3"].iloc[0])
    if not initial > 0:
        return None
    fraction = balance[column].to_numpy(float) / initial
    over = np.flatnonzero(fraction > ATMOSPHERE_LOSS_WARNING)
    return float(fraction[-1]), (float(balance["time_s"].iloc[over[0]]) if over.size else None)


def water_balance_summary(balance: pd.DataFrame | None) -> dict[str, float] | None:
    """Headline of :func:`read_water_balance`: initial, final and outflow volumes (m3) and the
    largest and final relative errors (signed; the largest by magnitude)."""
    if balance is None or balance.empty:
        return None
    err = balance["error"].to_numpy(float)
    worst = int(np.nanargmax(np.abs(err))) if np.isfinite(err).any() else 0
    out = {
        "initial_m3": float(balance["initial_m3"].iloc[0]),
        "final_m3": float(balance["volume_m3"].iloc[-1]),
        "outflow_m3": float(balance["outflow_m3"].iloc[-1]),
        # each open patch apart: the outlet's is the flume's; the atmosphere's left over the top
        "outflow_by_patch_m3": {c[len("outflow_"):-len("_m3")]: float(balance[c].iloc[-1])
                                for c in balance.columns if c.startswith("outflow_") and c.endswith("_m3")
                                and c != "outflow_m3"},
        "max_error": float(err[worst]),
        "time_of_max_error_s": float(balance["time_s"].iloc[worst]),
        "final_error": float(err[-1]),
    }
    loss = atmosphere_loss(balance)
    if loss is not None:
        out["atmosphere_outflow_fraction"] = loss[0]
        out["atmosphere_warning_time_s"] = loss[1]
    return out
