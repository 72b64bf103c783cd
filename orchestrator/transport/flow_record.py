"""The flow a one-way run recorded, read into a :class:`~orchestrator.transport.flow.FlowField`.

A one-way plan (``plan.debris_coupling == "one-way"``) records alpha.water and U on its
``flow_record`` grid: one ``sets`` function object writes, once in every ``interval_s`` of simulated
time (at the first time step at or past each multiple, so frames are about ``interval_s`` apart),
``postProcessing/<name>/<time>/<name>_alpha.water.xy`` and ``<name>_U.xy``, one line per point
("x y z values", each sample its cell's value). :func:`read_flow_record` grids them:

* every written time is a frame; a restart writes its times again into the same folders, so the
  folders are the run's times whatever the restarts (:func:`~orchestrator.case.outputs.numeric_dirs`);
* t = 0 is not written (v1912's function objects first write one interval after the start): it
  is the plan's initial water (``plan.water``: the boxes setFields filled, whole cells, as their
  faces are cell planes) at rest;
* the free surface per (x, y) is ``bed + sum(alpha dz)`` over the column's cells (z at the cell
  centres between ``z_faces_m``; alpha clipped to [0, 1]), the gauges' integral;
* the levels are the bed, the cell centres and the top face (the FlowField's levels span the bed
  to the highest surface): the bed and the top take their cell's velocity, as a cell sample is
  its cell's value;
* points inside the column's hole are not written: they take the alpha of the nearest recorded
  point along x in the same (y, z) row (the surface beside the face, not a dip to the bed) and
  zero velocity (the wall's);
* velocities are stored as float32.

A record that misses a frame, ends before the run's end time, or lacks a point outside the
column's hole (so the bodies' region is not covered) raises :class:`FlowRecordError` naming
what is missing.

Size on disk (measured). The raw text is about 135 bytes a point a frame (both files, 10
digits); the .npz (``velocity_m_s`` float32, ``eta_m`` float64, compressed) about 11. The
tiny one-way test scene: 2,870 points, 32 kB a frame against 379 kB of text. cases/1debris.yaml
at its 4 cm cells, one-way (480 steps, 2.8 min of interFoam on 2 cores): 84 x 38 x 19 =
60,648 points, 176 frames to 3.5 s; 8.1 MB of text a frame, 1.43 GB in all; the .npz 0.59 MB a
frame, 104 MB in all. :class:`RecordFiles` returns the figures of each conversion.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from orchestrator.core.errors import InputError
from orchestrator.case.folder import EPS_T, CaseFolder
from orchestrator.case.outputs import numeric_dirs
from orchestrator.plan.model import FlowRecordPlan, ModelPlan
from orchestrator.transport.flow import FlowField

__all__ = ["FLOW_RECORD_NPZ", "FlowRecordError", "RecordFiles", "read_flow_record"]

#: The converted record in the case's results folder.
FLOW_RECORD_NPZ = "flow_record.npz"
#: Two sample coordinates closer than this (m) are the same point (the files carry 10 digits).
_TOL_M = 1e-6


class FlowRecordError(InputError):
    """The recorded flow does not cover what the bodies need: names the frames, time or points missing."""


@dataclass(frozen=True)
class RecordFiles:
    """What :func:`read_flow_record` made: the field, its .npz, and the sizes (bytes)."""

    field: FlowField
    path: Path
    frames: int
    points: int
    bytes_total: int
    bytes_per_frame: float
    raw_bytes: int
    raw_deleted: bool


def _one_way_plan(folder: CaseFolder) -> ModelPlan:
    plan = folder.require_plan()
    if plan.flow_record is None:
        raise FlowRecordError("plan.flow_record", f"{folder.path} is a {plan.debris_coupling} case: it records no flow")
    return plan


def _frames(base: Path, record: FlowRecordPlan, end_time_s: float) -> list[tuple[float, Path]]:
    """The written frames, checked against every interval up to the end time.

    The record writes on ``runTime``: v1912 samples at the first time step t with t + dt/2 past
    a multiple t_k of the interval, so frame k lies within half a step of t_k; a step is at most
    the interval (the plan's maxDeltaT), so each t_k has its frame within half an interval."""
    found = [(t, p) for t, p in numeric_dirs(base) if t > EPS_T]
    step = record.interval_s
    expected = np.arange(1, int(np.floor(end_time_s / step + 1e-6)) + 1) * step
    have = np.array([t for t, _ in found])
    tol = 1e-6 * max(1.0, end_time_s)
    missing = [float(t) for t in expected
               if not have.size or not np.any(np.abs(have - t) <= 0.5 * step + tol)]
    if missing:
        last = float(have.max()) if have.size else 0.0
        gaps = [t for t in missing if t < last]
        what = []
        if missing[-1] > last:
            what.append(f"the record ends at {last:g} s, the run's end time is {end_time_s:g} s")
        if gaps:
            what.append(f"{len(gaps)} frame(s) missing, first at {gaps[0]:g} s (one every {step:g} s expected)")
        raise FlowRecordError(f"{base}", "; ".join(what))
    return [(t, p) for t, p in found if t <= end_time_s + 1e-6 * max(1.0, end_time_s)]


def _read_xy(path: Path, width: int) -> np.ndarray:
    if not path.is_file():
        raise FlowRecordError(str(path), "missing")
    table = pd.read_csv(path, sep=r"\s+", header=None, comment="#", dtype=float).to_numpy()
    if table.ndim != 2 or table.shape[1] != width:
        raise FlowRecordError(str(path), f"expected {width} columns (x y z values), got shape {table.shape}")
    return table


def _index(axis: np.ndarray, values: np.ndarray, name: str, path: Path) -> np.ndarray:
    idx = np.clip(np.searchsorted(axis, values), 1, axis.size - 1)
    idx = np.where(np.abs(axis[idx - 1] - values) <= np.abs(axis[idx] - values), idx - 1, idx)
    bad = np.abs(axis[idx] - values) > _TOL_M
    if np.any(bad):
        raise FlowRecordError(str(path), f"point {name} = {values[np.argmax(bad)]:.6g} m is not on the plan's grid")
    return idx


def _in_box(points: np.ndarray, box) -> np.ndarray:
    lo, hi = np.asarray(box[0]) - _TOL_M, np.asarray(box[1]) + _TOL_M
    return np.all((points >= lo) & (points <= hi), axis=-1)


def _fill_hole(alpha: np.ndarray, u: np.ndarray, seen: np.ndarray) -> None:
    """Points not written (the column's hole): the nearest recorded alpha along x, zero velocity."""
    nx = seen.shape[0]
    xi = np.arange(nx)
    for j, m in zip(*np.nonzero(~seen.all(axis=0))):
        row = seen[:, j, m]
        if not row.any():
            continue
        near = np.array([xi[row][np.argmin(np.abs(xi[row] - i))] for i in range(nx)])
        alpha[:, ~row, j, m] = alpha[:, near[~row], j, m]
    u[..., ~seen, :] = 0.0


def read_flow_record(case_dir: str | Path, *, delete_raw: bool = False, end_time_s: float | None = None,
                     out_path: str | Path | None = None) -> RecordFiles:
    """The case's recorded flow as a :class:`FlowField`, saved to ``results/flow_record.npz``.

    ``end_time_s``: the time the record must reach (None: the plan's end time). ``delete_raw``:
    remove ``postProcessing/<name>/`` once the .npz is written; once it is gone, the .npz is read
    back instead. Raises :class:`FlowRecordError`
    when the case is not one-way or the record misses a frame or a point (module docstring).
    """
    folder = CaseFolder(case_dir)
    plan = _one_way_plan(folder)
    record = plan.flow_record
    end = float(plan.end_time_s if end_time_s is None else end_time_s)
    base = folder.path / "postProcessing" / record.name
    npz = Path(out_path) if out_path is not None else folder.results_dir / FLOW_RECORD_NPZ
    if not base.is_dir() and npz.is_file():  # converted before and its text removed
        return _converted(npz, record, end)
    frames = _frames(base, record, end)
    xs, ys, zs = (np.asarray(a, float) for a in (record.x_m, record.y_m, record.z_m))
    shape = (xs.size, ys.size, zs.size)
    grid = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), axis=-1)
    hole = _in_box(grid, plan.column_box_m) if plan.column_box_m is not None else np.zeros(shape, bool)
    alpha = np.zeros((len(frames) + 1,) + shape)
    u = np.zeros((len(frames) + 1,) + shape + (3,), dtype=np.float32)
    for box in plan.water:
        alpha[0][_in_box(grid, (box.min_m, box.max_m))] = 1.0
    seen = np.zeros(shape, bool)
    raw = 0
    for k, (_, path) in enumerate(frames, start=1):
        a_path, u_path = path / f"{record.name}_alpha.water.xy", path / f"{record.name}_U.xy"
        a_tab, u_tab = _read_xy(a_path, 4), _read_xy(u_path, 6)
        raw += a_path.stat().st_size + u_path.stat().st_size
        for tab, p in ((a_tab, a_path), (u_tab, u_path)):
            i, j, m = (_index(ax, tab[:, c], n, p) for c, (ax, n) in enumerate(((xs, "x"), (ys, "y"), (zs, "z"))))
            if k == 1 and p is a_path:
                seen[i, j, m] = True
            elif not np.array_equal(np.sort(np.ravel_multi_index((i, j, m), shape)), np.flatnonzero(seen)):
                raise FlowRecordError(str(p), "holds other points than the first frame's alpha.water")
            if p is a_path:
                alpha[k][i, j, m] = tab[:, 3]
            else:
                u[k][i, j, m] = tab[:, 3:6]
    lost = ~seen & ~hole
    if np.any(lost):
        i, j, m = (int(v[0]) for v in np.nonzero(lost))
        raise FlowRecordError(str(base), f"{int(lost.sum())} point(s) outside the column's hole were not recorded, "
                                         f"first ({xs[i]:.4g}, {ys[j]:.4g}, {zs[m]:.4g}) m")
    (bx0, bx1), (by0, by1) = record.bodies_region_m
    if bx0 < xs[0] - _TOL_M or bx1 > xs[-1] + _TOL_M or by0 < ys[0] - _TOL_M or by1 > ys[-1] + _TOL_M:
        raise FlowRecordError("plan.flow_record", f"the record x {xs[0]:.4g}..{xs[-1]:.4g}, y {ys[0]:.4g}..{ys[-1]:.4g} m "
                                                  f"does not cover the bodies' x {bx0:.4g}..{bx1:.4g}, "
                                                  f"y {by0:.4g}..{by1:.4g} m")
    _fill_hole(alpha, u, seen)
    faces = np.asarray(record.z_faces_m, float)
    bed = float(faces[0])
    eta = bed + np.clip(alpha, 0.0, 1.0) @ np.diff(faces)
    levels = np.concatenate([[bed], zs, [faces[-1]]])
    u = np.concatenate([u[..., :1, :], u, u[..., -1:, :]], axis=-2)
    times = np.concatenate([[0.0], [t for t, _ in frames]])
    held = 0.0
    if times[-1] < end - 1e-6 * max(1.0, end):
        # the last sample fell within half a step before the end (the step to the end began past
        # its t + dt/2): the last frame is held to the end time
        held = end - float(times[-1])
        times = np.append(times, end)
        eta, u = np.concatenate([eta, eta[-1:]]), np.concatenate([u, u[-1:]])
    fluids = _fluids(folder)
    field = FlowField(times, xs, ys, levels, bed, eta, u, *fluids, meta={
        "case": str(folder.path), "solver": plan.solver, "record": record.name, "interval_s": record.interval_s,
        "t0": "the plan's initial water at rest (not written by the function object)",
        "hole_points": int((~seen).sum()), "raw_bytes": int(raw), "last_frame_held_s": held})
    path = npz
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    field.save(tmp)
    tmp.replace(path)
    if delete_raw:
        shutil.rmtree(base)
    total = path.stat().st_size
    return RecordFiles(field, path, times.size, int(np.prod(shape)), total, total / times.size, raw, delete_raw)


def _converted(npz: Path, record: FlowRecordPlan, end_time_s: float) -> RecordFiles:
    """The record as an earlier conversion saved it, checked against the run's end time."""
    field = FlowField.load(npz)
    last = float(field.t_s[-1])
    if last < end_time_s - 1e-6 * max(1.0, end_time_s):
        raise FlowRecordError(str(npz), f"the record ends at {last:g} s, the run's end time is {end_time_s:g} s")
    total = npz.stat().st_size
    points = len(record.x_m) * len(record.y_m) * len(record.z_m)
    return RecordFiles(field, npz, int(field.t_s.size), points, total, total / field.t_s.size,
                       int(field.meta.get("raw_bytes", 0)), True)


def _fluids(folder: CaseFolder) -> tuple[float, float]:
    """(water density, gravity) of the case's scene (the scene's defaults without one)."""
    if folder.scene_path.is_file():
        fluids = folder.scene().fluids
        return fluids.water_density_kg_m3, fluids.gravity_m_s2
    return 998.2, 9.81

