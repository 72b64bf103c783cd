"""Ensembles of one-way transports: the flow once, many perturbed starts carried through it.

``debrisfoam ensemble SCENE -n N -o DIR`` (docs/ensembles.md):

1. **The flow once.** The scene must go one-way (``plan.debris_coupling``; ``auto`` picks it for
   the shipped layouts). Its case is rendered and run into ``DIR/flow``
   (:func:`~orchestrator.pipeline.prepare_case`, :func:`~orchestrator.run.runner.run_case`): a
   finished flow of the same scene is reused, a folder holding another case is bad input. Its
   record is read once (:func:`~orchestrator.transport.case_transport.case_flow`).
2. **N realisations.** Realisation ``r`` draws every body's start from a
   :class:`numpy.random.Generator` seeded by ``(seed, r)`` (:func:`perturbed_starts`), so a
   realisation is the same whatever N, the executor or the order the workers finish in. Each is
   carried through the one FlowField by :func:`~orchestrator.transport.engine.run_transport`.
3. **Tables.** ``ensemble.csv`` (one row per realisation and body, :data:`TABLE_COLUMNS`: the
   start, the first column strike and its loads, the number of strikes, the wall time),
   ``tracks.csv`` (plan positions), ``ensemble.json`` (:func:`summarise`), ``report.md`` and figures.

The perturbation (:class:`Perturbation`)
----------------------------------------
Each body is moved in x and in y by independent normal draws of standard deviation
``position_sigma_fraction`` (0.25) times its length, clipped at ``clip_sigmas`` (2) standard
deviations, and turned about the vertical by a normal draw of ``yaw_sigma_deg`` (12 deg),
clipped at two standard deviations too; its height, pitch, roll and start velocity are kept.
Why these: the study's container was set by hand on the centreline before each release, so its
start scatters by a few centimetres and by the eye's alignment of a 0.15 m box, 10-15 deg; a
quarter of the length (37.5 mm for the container) keeps a body within the same part of the
bore, and the clip keeps rare draws from putting it somewhere the scene does not describe. The
study's impact velocities scatter by 0.13 m/s about 1.60 m/s over 22 releases; the ensemble
asks how much of that the start alone explains.

A start must keep ``min_gap_m`` (2 mm) from the side walls, the end walls at the record's ends,
the column and every body placed before it (plan footprints, the convex hull of the box's
corners, separated along an axis; two bodies whose height ranges do not overlap never clash).
A draw that does not is drawn again (rejection sampling) up to ``max_tries`` (200) times a body;
past that the ensemble stops before any run with an InputError naming the body's
``debris.<name>.centre_m``.

Column pulses and the study's fit
---------------------------------
The ensemble reports each body's first column strike, so it runs the engine with
``first_pulse_only``: later strikes of a body (its rebound sequence) are counted and tabled
without a pulse. Nothing is rounded: every first strike's pulse is the contact law's at that
strike's own velocity, height and obliquity. Its base-shear history is then fitted as the
study fitted its records (:func:`first_strike_fit`: a half-sine on the MDOF column loaded at
the water level the engine read beside the face; about 0.27 s of CPU a strike, against about
20 ms for the law's pulse), and :func:`summarise` sets the first strikes against the study's
22 with Welch's test (docs/ensembles.md, "Beside the study, like for like").

Batches
-------
:func:`run_realisations` carries ``batch_size`` realisations in one MuJoCo model
(:mod:`orchestrator.transport.batch`: no contact pair between realisations), so the engine's
per-step work is paid once for all of them; the table is the one-at-a-time one for the same
seeds, first strikes to rounding (tests/test_ensemble.py). ``study_fit`` False leaves the study's
fit out (a design-scale ensemble reads the law's pulse; the fit costs more than the transport).

Executors
---------
Each task is one batch. ``local``: a process pool (``fork``, so the workers share the parent's FlowField without
copying or pickling it), ``workers`` processes (default: the machine's cores); one worker runs in
this process. Processes, not threads: the engine steps MuJoCo from a Python loop (forcing,
contact bookkeeping, array copies every step) that holds the GIL most of the time, so threads
would carry the realisations one at a time. ``dask``: a Dask LocalCluster of ``workers``
single-threaded processes (:func:`~orchestrator.studies.sweep.executors.dask_executor`); each
worker process loads the record's .npz once.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import multiprocessing
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np
import pandas as pd

from analytical.study import STUDY_IMPACT_COUNT, STUDY_IMPACT_VELOCITY_M_S, STUDY_TABLE2_MDOF
from analytical.contact_modal import column_modes
from analytical.impact_bodies import ColumnTarget
from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.core.files import write_json_atomic, write_text_atomic
from orchestrator.pipeline import prepare_case
from orchestrator.results.study_fit import HEIGHT_SOURCES, compare_strikes, study_fit_figures
from orchestrator.plan.planner import plan_case
from orchestrator.run.runner import run_case
from orchestrator.scene.schema import DebrisBody, Scene
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.sweep.executors import check_pool, dask_executor
from orchestrator.studies.engine_watch import engine_watch, raise_if_unstable
from orchestrator.transport.batch import run_batch
from orchestrator.transport.case_transport import case_flow, scene_settings, transport_setup
from orchestrator.transport.engine import TransportResult, TransportSettings, ensemble_settings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn, rotation, with_start

__all__ = [
    "DEFAULT_BATCH_SIZE",
    "TABLE_COLUMNS",
    "TRACK_COLUMNS",
    "EnsembleResult",
    "Perturbation",
    "Realisation",
    "body_rows",
    "ensemble",
    "ensemble_flow",
    "ensemble_starts",
    "first_strike_fit",
    "forget_flow", "keep_flow",
    "perturbed_starts",
    "plan_footprint",
    "run_ensemble",
    "run_realisation",
    "run_realisations",
    "start_clash",
    "summarise",
]

DEFAULT_BATCH_SIZE = 128
"""Realisations carried in one model (:func:`run_realisations`; measured in docs/ensembles.md)."""

TABLE_COLUMNS = [
    "realisation", "body", "start_x_m", "start_y_m", "start_yaw_deg", "struck", "impact_time_s",
    "impact_velocity_m_s", "impact_speed_m_s", "impact_height_m", "obliquity_deg", "peak_force_N", "duration_s",
    "impulse_Ns", "peak_base_shear_N", "effective_mass_kg", "face_water_level_m", "time_since_front_s",
    "study_fit_peak_N", "study_fit_duration_s", "study_fit_impulse_Ns", "study_fit_start_s", "study_fit_height_m",
    "study_fit_height_source", "study_fit_nrmse", "strikes", "wall_time_s", "study_fit_wall_s",
]
"""ensemble.csv: the start; the first column strike (time, normal velocity of the centre and its speed,
contact height above the bed, obliquity from the face's normal), the law's pulse (peak force, duration,
impulse, the column's peak base shear, the effective mass at the contact along the normal, added mass
included), the water level at the face, the time since the flow's front reached the face (negative: ahead
of it) and the study's fit of the base shear (:mod:`orchestrator.results.study_fit`), NaN when not
struck; all column strikes; the wall time."""

TRACK_COLUMNS = ["realisation", "body", "time_s", "x_m", "y_m", "speed_m_s"]
"""tracks.csv: every body's centre in plan view, every output interval (0.01 s), for the first
:data:`TRACKED_REALISATIONS` realisations (100,000 tracks would be some 30 million rows)."""
TRACKED_REALISATIONS = 2000

#: The figures ensemble.json states for every struck body (mean, std, min, max, count).
STATISTICS = tuple(c for c in TABLE_COLUMNS[TABLE_COLUMNS.index("impact_time_s"):TABLE_COLUMNS.index("strikes")]
                   if c not in ("study_fit_height_source", "study_fit_wall_s"))


@dataclass(frozen=True)
class Perturbation:
    """How starts are drawn (module notes): normal position offsets of standard deviation
    ``position_sigma_fraction`` x the body's length in x and in y, a normal yaw offset of
    ``yaw_sigma_deg``, both clipped at ``clip_sigmas``; a start keeps ``min_gap_m`` from walls,
    column and bodies, drawn again up to ``max_tries`` times a body."""

    position_sigma_fraction: float = 0.25
    yaw_sigma_deg: float = 12.0
    clip_sigmas: float = 2.0
    min_gap_m: float = 0.002
    max_tries: int = 200

    def __post_init__(self):
        for name in ("position_sigma_fraction", "yaw_sigma_deg", "clip_sigmas", "min_gap_m"):
            value = float(getattr(self, name))
            if not math.isfinite(value) or value < 0.0:
                raise InputError(name, f"must be a finite number >= 0, got {getattr(self, name)!r}")
        if int(self.max_tries) < 1:
            raise InputError("max_tries", f"must be >= 1, got {self.max_tries!r}")

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


# --------------------------------------------------------------------------- starts
def plan_footprint(body: DebrisBody) -> np.ndarray:
    """The body's plan footprint at its start: the convex hull (counter-clockwise) of its corners on the bed."""
    half = np.asarray(body.size_m) / 2.0
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
    pts = (corners @ rotation(body).T)[:, :2] + np.asarray(body.centre_m[:2])
    return _hull(pts)


def _hull(points: np.ndarray) -> np.ndarray:
    """Andrew's monotone chain: the convex hull of 2-D points, counter-clockwise."""
    pts = sorted({(round(float(x), 12), round(float(y), 12)) for x, y in points})
    if len(pts) < 3:
        return np.array(pts)

    def half(seq):
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(half(pts) + half(reversed(pts)))


def _separated(a: np.ndarray, b: np.ndarray, gap: float) -> bool:
    """Are two convex polygons at least ``gap`` apart along one of their edges' normals?"""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        for e in edges:
            n = np.array([e[1], -e[0]])
            length = float(np.hypot(*n))
            if length == 0.0:
                continue
            n /= length
            pa, pb = a @ n, b @ n
            if pa.min() >= pb.max() + gap or pb.min() >= pa.max() + gap:
                return True
    return False


def _z_range(body: DebrisBody) -> tuple[float, float]:
    reach = float(np.abs(rotation(body)[2, :]) @ (np.asarray(body.size_m) / 2.0))
    return body.centre_m[2] - reach, body.centre_m[2] + reach


def start_clash(body: DebrisBody, placed: Sequence[DebrisBody], flume: FlumeBounds,
                column: PlacedColumn | None, gap_m: float = 0.0) -> str | None:
    """What ``body``'s start comes within ``gap_m`` of (a wall, the column, a placed body), or None."""
    foot = plan_footprint(body)
    (x0, x1), (y0, y1) = flume.x_m, flume.y_m
    if foot[:, 1].min() < y0 + gap_m or foot[:, 1].max() > y1 - gap_m:
        return f"a side wall (y = {y0:g} or {y1:g} m)"
    if foot[:, 0].min() < x0 + gap_m or foot[:, 0].max() > x1 - gap_m:
        return f"an end wall of the flow record (x = {x0:g} or {x1:g} m)"
    if column is not None:
        hx, hy = column.column.size_x_m / 2.0, column.column.size_y_m / 2.0
        box = np.array([[column.x_m - hx, column.y_m - hy], [column.x_m + hx, column.y_m - hy],
                        [column.x_m + hx, column.y_m + hy], [column.x_m - hx, column.y_m + hy]])
        if not _separated(foot, box, gap_m):
            return "the column"
    lo, hi = _z_range(body)
    for other in placed:
        olo, ohi = _z_range(other)
        if lo < ohi + gap_m and olo < hi + gap_m and not _separated(foot, plan_footprint(other), gap_m):
            return f"body {other.name}"
    return None


def perturbed_starts(bodies: Sequence[DebrisBody], flume: FlumeBounds, column: PlacedColumn | None,
                     perturbation: Perturbation, seed: int, realisation: int) -> list[DebrisBody]:
    """Realisation ``realisation``'s bodies: each start drawn about its nominal one (module notes)
    from ``numpy.random.default_rng([seed, realisation])``, in the bodies' order; raises
    InputError naming ``debris.<name>.centre_m`` when a body finds no free start."""
    rng = np.random.default_rng([int(seed), int(realisation)])
    p = perturbation
    placed: list[DebrisBody] = []
    for body in bodies:
        sigma = p.position_sigma_fraction * body.size_m[0]
        clash = None
        for _ in range(int(p.max_tries)):
            dx, dy, dyaw = np.clip(rng.standard_normal(3), -p.clip_sigmas, p.clip_sigmas) * [sigma, sigma,
                                                                                               p.yaw_sigma_deg]
            x, y, z = body.centre_m
            moved = with_start(body, centre_m=(x + float(dx), y + float(dy), z),
                                        yaw_deg=body.yaw_deg + float(dyaw))
            clash = start_clash(moved, placed, flume, column, p.min_gap_m)
            if clash is None:
                placed.append(moved)
                break
        else:
            raise InputError(f"debris.{body.name}.centre_m",
                             f"no start within {p.clip_sigmas:g} x {sigma:.3g} m and {p.clip_sigmas:g} x "
                             f"{p.yaw_sigma_deg:g} deg of ({body.centre_m[0]:g}, {body.centre_m[1]:g}) m keeps "
                             f"{p.min_gap_m:g} m from the walls, the column and the other bodies in {p.max_tries} "
                             f"draws (realisation {realisation}; the last came within the gap of {clash}): move "
                             "the body or narrow the perturbation")
    return placed


def ensemble_starts(bodies: Sequence[DebrisBody], flume: FlumeBounds, column: PlacedColumn | None,
                    perturbation: Perturbation, seed: int, n: int) -> list[list[DebrisBody]]:
    """The starts of realisations 0 .. n - 1."""
    return [perturbed_starts(bodies, flume, column, perturbation, seed, r) for r in range(n)]


# --------------------------------------------------------------------------- one realisation
@dataclass
class Realisation:
    """What one realisation gives back: its rows of ensemble.csv and of tracks.csv."""

    number: int
    rows: list[dict[str, Any]]
    tracks: pd.DataFrame
    wall_s: float


def body_rows(result: TransportResult, bodies: Sequence[DebrisBody], realisation: int, wall_s: float,
              column: PlacedColumn | None = None, bed_z_m: float = 0.0, study_fit: bool = True) -> list[dict[str, Any]]:
    """ensemble.csv's rows of one realisation (:data:`TABLE_COLUMNS`) from its transport: with
    ``column``, each first strike's base shear fitted as the study fitted its records
    (:func:`first_strike_fit`, ``bed_z_m`` the bed's elevation; ``study_fit`` False: the water
    level at the face only, the fit's columns empty)."""
    imp = result.impacts
    on_column = imp[imp["kind"] == "column"].sort_values("time_s", kind="stable") if len(imp) else imp
    rows = []
    for b in bodies:
        strikes = on_column[on_column["body"] == b.name] if len(on_column) else on_column
        row = {"realisation": realisation, "body": b.name, "start_x_m": b.centre_m[0], "start_y_m": b.centre_m[1],
               "start_yaw_deg": b.yaw_deg, "struck": bool(len(strikes)), "strikes": int(len(strikes)),
               "wall_time_s": round(float(wall_s), 4)}
        first = strikes.iloc[0] if len(strikes) else None
        for name, source in (("impact_time_s", "time_s"), ("impact_velocity_m_s", "impact_velocity_m_s"),
                             ("impact_height_m", "height_m"), ("obliquity_deg", "obliquity_deg"),
                             ("peak_force_N", "peak_force_N"), ("duration_s", "duration_s"),
                             ("impulse_Ns", "impulse_Ns"), ("peak_base_shear_N", "peak_base_shear_N"),
                             ("effective_mass_kg", "effective_mass_kg"), ("time_since_front_s", "time_since_front_s")):
            row[name] = float(first[source]) if first is not None else math.nan
        row["impact_speed_m_s"] = (math.hypot(float(first["normal_velocity_in_m_s"]),
                                              float(first["tangential_velocity_in_m_s"]))
                                   if first is not None else math.nan)
        start = time.perf_counter()
        row.update(first_strike_fit(result, first, column, bed_z_m, fit=study_fit))
        row["study_fit_wall_s"] = round(time.perf_counter() - start, 4)
        rows.append(row)
    return rows


def first_strike_fit(result: TransportResult, first, column: PlacedColumn | None, bed_z_m: float,
                     fit: bool | float | str = True) -> dict[str, Any]:
    """The water level at the face and the study's fit of a first strike's (a row of the engine's
    impacts table, or None) base shear (contacts/eventNNNN-base-shear.csv one-way) loaded at that
    level, else at the contact height (:func:`~orchestrator.results.study_fit.study_fit_figures`);
    ``fit`` False: the level only; a height (m) or "contact" (``--study-fit-height``): loaded there."""
    out = {"face_water_level_m": math.nan, "study_fit_height_source": ""}
    pulse = result.pulses.get(int(first["event"])) if first is not None else None
    if pulse is None or pulse.base_shear is None or column is None:
        return out
    level = float(first["face_water_level_m"]) - bed_z_m
    height, source = (level, HEIGHT_SOURCES[1]) if math.isfinite(level) else (float(first["height_m"]), HEIGHT_SOURCES[2])
    out["face_water_level_m"] = level if math.isfinite(level) else math.nan
    if fit is False:
        return out
    if fit is not True:  # --study-fit-height
        height, source = (float(first["height_m"]), HEIGHT_SOURCES[2]) if fit == "contact" else (fit, HEIGHT_SOURCES[3])
    shear = pulse.base_shear
    shear_y = pulse.base_shear_y.response_N if pulse.base_shear_y is not None else None
    normal = (float(first["normal_x"]), float(first["normal_y"]), float(first["normal_z"]))
    figures = study_fit_figures(shear.time_s, shear.response_N, shear_y, normal, column.column, height, source)
    return {**out, **{k: v for k, v in figures.items() if k in TABLE_COLUMNS}}


#: The flow each process carries its realisations through, by its .npz path.
_FLOWS: dict[str, FlowField] = {}


def keep_flow(npz: str, flow: FlowField | None = None) -> FlowField:
    """The flow of ``npz`` in this process: given (the local pool's initializer), or loaded once."""
    if flow is not None:
        _FLOWS[npz] = flow
    if npz not in _FLOWS:
        _FLOWS[npz] = FlowField.load(npz)
    return _FLOWS[npz]


def forget_flow(npz: str) -> None:  # a study that holds one flow at a time
    _FLOWS.pop(npz, None)


def run_realisation(number: int, bodies: list[DebrisBody], flume: FlumeBounds, column: PlacedColumn | None,
                    t_end_s: float, npz: str, settings: TransportSettings, study_fit: bool = True) -> Realisation:
    """Carry one realisation's bodies through the flow of ``npz`` (loaded once per process)."""
    flow = keep_flow(npz)
    with engine_watch() as caught:
        result = run_transport(bodies, flume, t_end_s, flow=flow, column=column, settings=settings)
    raise_if_unstable(caught, [number], [len(bodies)])
    return _realisation(number, result, bodies, column, flume, study_fit)


def _realisation(number: int, result: TransportResult, bodies: Sequence[DebrisBody], column: PlacedColumn | None,
                 flume: FlumeBounds, study_fit: bool) -> Realisation:
    rows = body_rows(result, bodies, number, 0.0, column, flume.bed_z_m, study_fit)
    wall = result.wall_s + result.pulse_wall_s + sum(r["study_fit_wall_s"] for r in rows)
    for r in rows:
        r["wall_time_s"] = round(float(wall), 4)
    tracks = result.tracks[["body", "time_s", "x_m", "y_m", "speed_m_s"]]
    tracks = (tracks if number < TRACKED_REALISATIONS else tracks.iloc[:0]).copy()
    tracks.insert(0, "realisation", number)
    return Realisation(number, rows, tracks, wall)


def run_realisations(numbers: Sequence[int], starts: Sequence[list[DebrisBody]], flume: FlumeBounds,
                     column: PlacedColumn | None, t_end_s: float, npz: str, settings: TransportSettings,
                     study_fit: bool = True) -> list[Realisation]:
    """Realisations ``numbers`` (their ``starts``) as one batch (:func:`~orchestrator.transport.batch.run_batch`;
    one alone: :func:`run_realisation`); each one's wall time is its share of the batch's plus its fits."""
    if len(numbers) == 1:
        return [run_realisation(numbers[0], list(starts[0]), flume, column, t_end_s, npz, settings, study_fit)]
    with engine_watch() as caught:
        results = run_batch(starts, flume, t_end_s, flow=keep_flow(npz), column=column, settings=settings)
    raise_if_unstable(caught, list(numbers), [len(s) for s in starts])
    return [_realisation(number, result, bodies, column, flume, study_fit)
            for number, result, bodies in zip(numbers, results, starts)]


# --------------------------------------------------------------------------- the ensemble
@dataclass
class EnsembleResult:
    """An ensemble: its table, tracks, summary, and where it wrote them."""

    table: pd.DataFrame
    tracks: pd.DataFrame
    summary: dict[str, Any]
    files: dict[str, Path] = field(default_factory=dict)

    def headline(self) -> dict[str, Any]:
        """What ``--json`` prints (these key names exactly)."""
        s = self.summary
        return {"realisations": s["realisations"], "impact_probability": s["impact_probability"],
                "impact_velocity_m_s": {k: s["impact_velocity_m_s"][k] for k in ("mean", "std")},
                "peak_force_N": {k: s["peak_force_N"][k] for k in ("mean", "std")},
                "wall_time_s": s["wall_time_s"]}


def _open_local(workers: int, npz: str, flow: FlowField):
    """A fork process pool whose workers start with ``flow`` (inherited, not pickled)."""
    return concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                                                  initializer=keep_flow, initargs=(npz, flow))


def run_ensemble(starts: Sequence[list[DebrisBody]], flume: FlumeBounds, column: PlacedColumn | None, t_end_s: float,
                 flow: FlowField, npz: str | Path, executor: str = "local", workers: int | None = None,
                 settings: TransportSettings | None = None,
                 progress: Callable[[int, int], None] | None = None, batch_size: int = DEFAULT_BATCH_SIZE,
                 study_fit: bool = True) -> list[Realisation]:
    """Carry every realisation's bodies (``starts``) through ``flow`` (saved as ``npz``, which
    Dask's workers load) on ``executor`` with ``workers`` at once, in batches of at most
    ``batch_size`` realisations a model (:func:`run_realisations`; 1: one model each), smaller
    when there are too few realisations to give every worker a batch; ``progress(done,
    total)`` after each batch; the realisations in order."""
    check_pool(executor, None, batch_size)
    workers = max(1, int(workers or os.cpu_count() or 1))
    settings = ensemble_settings(settings or TransportSettings())
    npz = str(npz)
    keep_flow(npz, flow)
    # at most batch_size a model, and no fewer batches than workers (each worker busy)
    size = max(1, min(int(batch_size), math.ceil(len(starts) / workers)))
    tasks = [(list(range(lo, min(lo + size, len(starts)))), [list(b) for b in starts[lo:lo + size]], flume, column,
              float(t_end_s), npz, settings, study_fit) for lo in range(0, len(starts), size)]
    done: dict[int, Realisation] = {}

    def finished(numbers: list[int], future) -> None:
        try:
            runs = future.result()
        except InputError:
            raise
        except DebrisfoamError as err:
            which = f"realisation {numbers[0]}" if len(numbers) == 1 else f"realisations {numbers[0]}-{numbers[-1]}"
            raise type(err)(f"{which}: {err}") from err
        done.update((r.number, r) for r in runs)
        if progress is not None:
            progress(len(done), len(starts))

    if executor == "local" and workers == 1:
        for task in tasks:
            done.update((r.number, r) for r in run_realisations(*task))
            if progress is not None:
                progress(len(done), len(starts))
    elif executor == "local":
        if column is not None:  # the column's modes once, inherited by the forked workers
            for axis in (0, 1):
                column_modes(ColumnTarget(column.column, column.column.height_m).axis_column(axis))
        with _open_local(workers, npz, flow) as pool:
            futures = {pool.submit(run_realisations, *task): task[0] for task in tasks}
            for future in concurrent.futures.as_completed(futures):
                finished(futures[future], future)
    else:
        with dask_executor(workers, None, None) as ex:
            futures = {ex.submit(run_realisations, *task, key=f"debrisfoam-ensemble-{task[0][0]}"): task[0]
                       for task in tasks}
            for future in ex.as_completed(list(futures)):
                finished(futures[future], future)
    return [done[r] for r in sorted(done)]


def _stats(values: pd.Series) -> dict[str, Any]:
    v = pd.to_numeric(values, errors="coerce").dropna().to_numpy(float)
    out: dict[str, Any] = {"count": int(v.size), "mean": None, "std": None, "min": None, "max": None}
    if v.size:
        out.update(mean=float(v.mean()), min=float(v.min()), max=float(v.max()))
    if v.size > 1:
        out["std"] = float(v.std(ddof=1))
    return out


def summarise(table: pd.DataFrame, realisations: int, wall_time_s: float) -> dict[str, Any]:
    """ensemble.json's figures: the share of (realisation, body) rows that struck the column, and
    for the struck ones the mean, sample standard deviation (ddof 1), extremes and count of each
    first-strike figure; the strikes per struck body; the wall times; the study's figures beside,
    and ``comparison``: the first strikes against the study's 22, like for like, with Welch's test
    (:func:`~orchestrator.results.study_fit.compare_strikes`, one entry per row of
    :data:`~orchestrator.results.study_fit.COMPARISON_ROWS`)."""
    struck = table[table["struck"].astype(bool)] if len(table) else table
    out: dict[str, Any] = {"realisations": int(realisations), "bodies": int(table["body"].nunique()) if len(table)
                           else 0, "impact_probability": float(len(struck) / len(table)) if len(table) else None}
    for name in STATISTICS:
        out[name] = _stats(struck[name] if len(struck) else pd.Series(dtype=float))
    out["strikes_per_struck_body"] = _stats(struck["strikes"] if len(struck) else pd.Series(dtype=float))
    out["wall_time_s"] = round(float(wall_time_s), 2)
    walls = table.drop_duplicates("realisation")["wall_time_s"] if len(table) else pd.Series(dtype=float)
    out["realisation_wall_time_s"] = _stats(walls)
    out["transport_wall_time_s"] = round(float(walls.sum()), 2)
    out["study"] = {"impact_velocity_m_s": dict(zip(("mean", "std"), STUDY_IMPACT_VELOCITY_M_S)),
                         **{k: dict(zip(("mean", "std"), v)) for k, v in STUDY_TABLE2_MDOF.items()},
                         "impacts": STUDY_IMPACT_COUNT,
                         "source": "the study's 22 single-container impacts; Table 2's MDOF row"}
    out["comparison"] = {k: c.to_dict() for k, c in compare_strikes(struck).items()}
    out["study_fit_wall_s"] = _stats(struck["study_fit_wall_s"] if len(struck) and "study_fit_wall_s" in struck
                                     else pd.Series(dtype=float))
    return out


# --------------------------------------------------------------------------- the verb
def ensemble_flow(scene_path: str | Path, flow_dir: str | Path, sets: Sequence[str] = (), quiet: bool = False,
                  stream=None, say: Callable[[str], None] = print,
                  confirmed: bool = False) -> tuple[Scene, Path, FlowField, Path]:
    """The scene's one-way flow in ``flow_dir``: rendered and run, or reused when finished
    (module notes); (scene, case folder, flow, its .npz). Raises InputError for a scene without
    debris (``debris``) or one that does not go one-way (``run.debris_coupling``)."""
    scene = load_scene(scene_path, list(sets))
    if not scene.debris:
        raise InputError("debris", "the scene has no debris: an ensemble perturbs the bodies' starts", str(scene_path))
    plan = plan_case(scene, str(scene_path))
    coupling = plan.debris_coupling
    if coupling != "one-way":
        raise InputError("run.debris_coupling", f"the scene plans {coupling} (run.debris_coupling "
                                                f"{scene.run.debris_coupling}): an ensemble carries its bodies through "
                                                "one recorded flow; set run.debris_coupling=one-way", str(scene_path))
    case, rendered = prepare_case(scene, plan, scene_path, flow_dir, sets, confirmed=confirmed)
    say(f"debrisfoam: flow: {'rendered' if rendered else 'reusing'} {case}")
    run_case(case, quiet=quiet, stream=stream)
    flow, npz = case_flow(case, say=say)
    return scene, case, flow, npz


def ensemble(scene_path: str | Path, out_dir: str | Path, n: int, seed: int = 0, executor: str = "local",
             sets: Sequence[str] = (), workers: int | None = None, perturbation: Perturbation | None = None,
             settings: TransportSettings | None = None, progress: Callable[[int, int], None] | None = None,
             quiet: bool = False, say: Callable[[str], None] = print, confirmed: bool = False,
             batch_size: int = DEFAULT_BATCH_SIZE, study_fit: bool | float | str = True) -> EnsembleResult:
    """``debrisfoam ensemble``: the flow into ``out_dir/flow`` (or reused), ``n`` realisations,
    then ensemble.csv, tracks.csv, ensemble.json and report.md in ``out_dir`` (module notes).
    ``confirmed``: render the flow even over the resource guard's soft limits
    (:func:`~orchestrator.pipeline.render_from_file`). ``batch_size`` realisations share a model
    (:func:`run_realisations`); ``study_fit`` False leaves the study's fit out, a height loads it there."""
    from orchestrator.studies.ensemble_report import write_report

    if int(n) <= 0:
        raise InputError("-n", f"must be a whole number > 0 of realisations, got {n}")
    check_pool(executor, workers, batch_size)
    perturbation = perturbation or Perturbation()
    t0 = time.perf_counter()
    out = Path(out_dir)
    scene, case, flow, npz = ensemble_flow(scene_path, out / "flow", sets, quiet=quiet,
                                           stream=sys.stderr if quiet else None, say=say, confirmed=confirmed)
    flow_wall_s = time.perf_counter() - t0
    bodies, flume, column = transport_setup(scene, flow)
    t_end = float(scene.run.end_time_s)
    starts = ensemble_starts(bodies, flume, column, perturbation, seed, int(n))
    say(f"debrisfoam: {n} realisation(s) of {len(bodies)} bod{'y' if len(bodies) == 1 else 'ies'} over {t_end:g} s "
        f"on {executor}")
    runs = run_ensemble(starts, flume, column, t_end, flow, npz, executor, workers, scene_settings(scene, settings),
                        progress, batch_size, study_fit)
    table = pd.DataFrame([row for r in runs for row in r.rows], columns=TABLE_COLUMNS)
    tracks = pd.concat([r.tracks for r in runs], ignore_index=True)[TRACK_COLUMNS]
    summary = summarise(table, int(n), time.perf_counter() - t0)
    # the flow phase (run, or a finished flow and its record loaded) and the realisations after it
    summary.update(flow_phase_wall_s=round(flow_wall_s, 2),
                   realisations_wall_s=round(float(summary["wall_time_s"]) - flow_wall_s, 2))
    summary.update(scene=str(scene_path), overrides=list(sets), flow_case=str(case), flow_record=str(npz),
                   end_time_s=t_end, seed=int(seed), executor=executor,
                   workers=int(workers or os.cpu_count() or 1), batch_size=int(batch_size), study_fit=study_fit,
                   perturbation=perturbation.to_dict(),
                   pulses="the first column strike of each body (later strikes counted, without a pulse)")
    files = {"table": out / "ensemble.csv", "tracks": out / "tracks.csv", "summary": out / "ensemble.json"}
    write_text_atomic(files["table"], table.to_csv(index=False, float_format="%.10g"))
    write_text_atomic(files["tracks"], tracks.to_csv(index=False, float_format="%.6g"))
    result = EnsembleResult(table, tracks, summary, files)
    files.update(write_report(out, result, scene, bodies, column))
    write_json_atomic(files["summary"], summary)
    return result
