"""Design studies: from a scene to the distribution of a column's debris demands, beside ASCE 7-22.

``debrisfoam design SCENE -o DIR`` (docs/design.md) reads the scene's ``design`` section
(:class:`~orchestrator.scene.schema.Design`) and:

1. **The flows once.** Each inundation case (the scene with the case's overrides) is a one-way
   flow rendered and run into ``DIR/flows/<case>`` by
   :func:`~orchestrator.studies.ensemble.ensemble_flow`: a finished flow of the same scene is
   reused (a changed ``design`` section never makes another case), a folder holding another
   case is bad input. ``u_max``, the flow's maximum speed at the site, is read from each
   record (:func:`~orchestrator.results.asce_design.site_flow_speed`).
2. **Realisations.** ``design.realisations`` are shared among the cases in proportion to their
   weights (largest remainders, at least one each), so the pooled sample is a stratified sample
   of the weighted mixture. Realisation ``r`` of case ``c`` draws from
   ``numpy.random.default_rng([seed, c, r])`` (:func:`design_starts`), the same whatever the
   number of realisations or the executor: every body's mass (uniform in ``mass_kg``, else its
   own; its inertia is the scene's box at that mass), heading (uniform in ``heading_deg``, else
   the ensemble's tolerance: normal, 12 degrees, clipped at 2 standard deviations) and start
   (uniform in ``start_x_m`` x ``start_y_m``, else the ensemble's tolerance: normal, a quarter
   of the length), drawn again while it comes within 2 mm of a wall, the column or another body.
   A body's start height is the scene's (a floating body starts at its own mass's draft).
3. **Carried or grounded.** A body whose draft ``m / (rho_w L W)`` is not less than the deepest
   water at its start cannot float there: it is not carried (no transport), its row says so
   and its demands are 0 (:mod:`~orchestrator.studies.design_strikes`).
4. **Demands.** Realisations are stepped together in batches
   (:func:`~orchestrator.transport.batch.run_batch`); every column strike of every body gets its
   contact force (the contact law in series with the MDOF column) and from that pulse the
   column's peak base shear, base moment and largest displacement along the member
   (:func:`analytical.column_demand.strike_demands`, resultants of the two bending directions),
   one row of design.csv each, with its face, obliquity, eccentricity and torsion and the water
   the body came in with. An unstable engine (:mod:`~orchestrator.studies.engine_watch`) ends
   the study with an error naming the realisation, before any page is written. A realisation's
   demand is its largest strike (each demand's largest over its bodies' strikes); a
   realisation that never strikes has demand 0 and stays in the sample (the page states
   P(strike), and the quantiles given a strike beside the unconditional ones).

The exceedance curves, quantiles and intervals are :mod:`analytical.exceedance`'s; the page,
the figure and design.json are :mod:`orchestrator.studies.design_report`'s. Everything here
is conditional on the scene's inundation cases: it is not a probabilistic tsunami hazard
analysis.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import multiprocessing
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np
import pandas as pd

from analytical.column_demand import strike_demands
from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.core.files import write_text_atomic
from orchestrator.results.asce_design import SiteFlow, site_flow_speed
from orchestrator.scene.schema import DebrisBody, Design, Scene
from orchestrator.scene.scenefile import load_scene
from orchestrator.studies.design_table import DEMANDS, DESIGN_COLUMNS, allocate, case_names, debris_types, mass_range, \
    realisation_demands
from orchestrator.studies.engine_watch import engine_watch, raise_if_unstable
from orchestrator.studies.design_strikes import carried, front_celerity, strike_rows
from orchestrator.studies.ensemble import DEFAULT_BATCH_SIZE, Perturbation, ensemble_flow, forget_flow, \
    keep_flow, start_clash
from orchestrator.studies.sweep.executors import check_pool, dask_executor
from orchestrator.transport.batch import run_batch
from orchestrator.transport.case_transport import scene_settings, transport_setup
from orchestrator.transport.engine import TransportSettings, ensemble_settings, run_transport
from orchestrator.transport.flow import FlowField
from orchestrator.transport.mujoco_model import FlumeBounds, PlacedColumn, with_start

__all__ = ["DEMANDS", "DESIGN_COLUMNS", "DesignCase", "DesignResult", "allocate", "case_names", "design", "design_cases",
           "design_batch", "design_starts", "mass_range", "realisation_demands"]

@dataclass
class DesignCase:
    """One inundation case: its name, overrides, normalised weight, realisations, flow and site
    (and the front's speed on the column's line, :func:`~orchestrator.studies.design_strikes.front_celerity`)."""

    name: str
    sets: list[str]
    weight: float
    realisations: int
    scene: Scene | None = None
    flow_case: Path | None = None
    npz: Path | None = None
    site: SiteFlow | None = None
    flow_wall_s: float = 0.0
    front_celerity_m_s: float | None = None


@dataclass
class DesignResult:
    """A design study: its table, cases, summary and where it wrote them."""

    table: pd.DataFrame
    cases: list[DesignCase]
    summary: dict[str, Any]
    files: dict[str, Path] = field(default_factory=dict)


def design_starts(bodies: Sequence[DebrisBody], flume: FlumeBounds, column: PlacedColumn | None, spec: Design,
                  case: int, realisation: int, perturbation: Perturbation | None = None,
                  types: dict[str, str | None] | None = None) -> list[DebrisBody]:
    """Realisation ``realisation`` of case ``case``: every body's mass, heading and start (module
    notes); raises InputError naming the design key when a body finds no free start."""
    p = perturbation or Perturbation()
    rng = np.random.default_rng([int(spec.seed), int(case), int(realisation)])
    placed: list[DebrisBody] = []
    for body in bodies:
        lo, hi = mass_range(body, spec, (types or {}).get(body.name))
        mass = float(rng.uniform(lo, hi)) if hi > lo else lo
        sigma = p.position_sigma_fraction * body.size_m[0]
        clash = None
        for _ in range(int(p.max_tries)):
            nx, ny, nyaw = np.clip(rng.standard_normal(3), -p.clip_sigmas, p.clip_sigmas)
            ux, uy, uyaw = rng.uniform(size=3)
            x, y, z = body.centre_m
            if spec.start_x_m is None and spec.start_y_m is None:
                x, y = x + float(nx) * sigma, y + float(ny) * sigma
            else:
                if spec.start_x_m is not None:
                    x = spec.start_x_m[0] + float(ux) * (spec.start_x_m[1] - spec.start_x_m[0])
                if spec.start_y_m is not None:
                    y = spec.start_y_m[0] + float(uy) * (spec.start_y_m[1] - spec.start_y_m[0])
            yaw = (body.yaw_deg + float(nyaw) * p.yaw_sigma_deg if spec.heading_deg is None
                   else spec.heading_deg[0] + float(uyaw) * (spec.heading_deg[1] - spec.heading_deg[0]))
            moved = with_start(body, centre_m=(x, y, z), yaw_deg=yaw, mass_kg=mass)
            clash = start_clash(moved, placed, flume, column, p.min_gap_m)
            if clash is None:
                placed.append(moved)
                break
        else:
            key = "design.start_x_m" if spec.start_x_m is not None or spec.start_y_m is not None else \
                f"debris.{body.name}.centre_m"
            raise InputError(key, f"body {body.name}: no start in {p.max_tries} draws keeps {p.min_gap_m:g} m from "
                                  f"the walls, the column and the other bodies (case {case + 1}, realisation "
                                  f"{realisation}; the last came within the gap of {clash}): move or widen the area")
    return placed


# --------------------------------------------------------------------------- the realisations
def design_batch(numbers: Sequence[int], starts: Sequence[list[DebrisBody]], flume: FlumeBounds,
                 column: PlacedColumn, t_end_s: float, npz: str, settings: TransportSettings) -> list[dict[str, Any]]:
    """Rows of design.csv (without the case's columns) for realisations ``numbers`` of one case:
    the bodies that float at their start (:func:`~orchestrator.studies.design_strikes.carried`)
    stepped together in one model, every column strike a row with its demands (module notes)."""
    flow = keep_flow(npz)
    settings = dataclasses.replace(settings, first_pulse_only=True, every_column_pulse=True)
    t0 = float(flow.t_s[0]) if settings.flow_start_s is None else float(settings.flow_start_s)
    floats = carried(starts, flow, t0, t_end_s)
    moving = [k for k, f in enumerate(floats) if any(ok for _, _, ok in f)]
    bodies_in = [[b for b, (_, _, ok) in zip(starts[k], floats[k]) if ok] for k in moving]
    results: dict[int, Any] = {}
    if moving:
        with engine_watch() as caught:
            if len(moving) == 1:
                runs = [run_transport(bodies_in[0], flume, t_end_s, flow=flow, column=column, settings=settings)]
            else:
                runs = run_batch(bodies_in, flume, t_end_s, flow=flow, column=column, settings=settings)
        # an error, not a data point
        raise_if_unstable(caught, [numbers[k] for k in moving], [len(b) for b in bodies_in])
        results = dict(zip(moving, runs))
    rows = []
    for k, (number, bodies) in enumerate(zip(numbers, starts)):
        result = results.get(k)
        wall = result.wall_s + result.pulse_wall_s if result is not None else 0.0
        start = time.perf_counter()
        first = len(rows)
        for body, (draft, depth, ok) in zip(bodies, floats[k]):
            base = {"realisation": number, "body": body.name, "mass_kg": body.mass_kg, "draft_m": draft,
                    "start_depth_m": depth, "carried": ok, "start_x_m": body.centre_m[0],
                    "start_y_m": body.centre_m[1], "start_yaw_deg": body.yaw_deg}
            strikes = strike_rows(result, body, column, flow, t0) if ok and result is not None else []
            base.update(struck=bool(strikes), strikes=len(strikes))
            if not strikes:
                rows.append({**base, "strike": 0, **{key: 0.0 for key in DEMANDS}})
            for strike in strikes:
                pulse = strike.pop("pulse")
                out = {**base, **strike, **{key: 0.0 for key in DEMANDS}}
                if pulse is not None:
                    loads = strike_demands(pulse.force, pulse.normal, column.column, float(pulse.contact_height_m))
                    out.update(peak_force_N=float(pulse.peak_force_N), **loads)
                rows.append(out)
        wall += time.perf_counter() - start
        for out in rows[first:]:
            out["wall_time_s"] = round(float(wall), 4)
    return rows


def _run_case(case: DesignCase, starts: list[list[DebrisBody]], flume: FlumeBounds, column: PlacedColumn,
              flow: FlowField, executor: str, workers: int, batch_size: int,
              progress: Callable[[int], None] | None) -> list[dict[str, Any]]:
    """Every realisation of one case, in batches, on ``executor``; rows in realisation order."""
    settings = ensemble_settings(scene_settings(case.scene))
    npz = str(case.npz)
    keep_flow(npz, flow)
    t_end = float(case.scene.run.end_time_s)
    tasks = [(list(range(lo, min(lo + batch_size, len(starts)))), starts[lo:lo + batch_size], flume, column, t_end,
              npz, settings) for lo in range(0, len(starts), batch_size)]
    done: dict[int, list[dict[str, Any]]] = {}

    def finished(first: int, rows: list[dict[str, Any]]) -> None:
        done[first] = rows
        if progress is not None:
            progress(len({r["realisation"] for r in rows}))

    def collect(first: int, future) -> None:
        try:
            rows = future.result()
        except InputError:
            raise
        except DebrisfoamError as err:
            raise type(err)(f"case {case.name}, realisations from {first}: {err}") from err
        finished(first, rows)

    if executor == "local" and workers == 1:
        for task in tasks:
            finished(task[0][0], design_batch(*task))
    elif executor == "local":
        with concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                                                    initializer=keep_flow, initargs=(npz, flow)) as pool:
            futures = {pool.submit(design_batch, *task): task[0][0] for task in tasks}
            for future in concurrent.futures.as_completed(futures):
                collect(futures[future], future)
    else:
        with dask_executor(workers, None, None) as ex:
            futures = {ex.submit(design_batch, *task, key=f"debrisfoam-design-{case.name}-{task[0][0]}"): task[0][0]
                       for task in tasks}
            for future in ex.as_completed(list(futures)):
                collect(futures[future], future)
    return [row for first in sorted(done) for row in done[first]]


# --------------------------------------------------------------------------- the verb
def design_cases(scene_path: str | Path, sets: Sequence[str], spec: Design) -> list[DesignCase]:
    """The inundation cases, each checked as a scene (its overrides named on bad input)."""
    names = case_names(spec)
    weights = np.array([c.weight for c in spec.inundation], dtype=float)
    counts = allocate(int(spec.realisations), weights)
    cases = []
    for k, (inundation, name, n) in enumerate(zip(spec.inundation, names, counts)):
        case_sets = list(sets) + list(inundation.set)
        try:
            scene = load_scene(scene_path, case_sets)
        except InputError as err:
            raise InputError(f"design.inundation.{k}.set: {err.field}", err.rule, str(scene_path)) from None
        if scene.column is None:
            raise InputError("column", "a design study needs a column to load", str(scene_path))
        cases.append(DesignCase(name, case_sets, float(weights[k] / weights.sum()), n, scene))
    return cases


def design(scene_path: str | Path, out_dir: str | Path, sets: Sequence[str] = (), executor: str = "local",
           workers: int | None = None, batch_size: int = DEFAULT_BATCH_SIZE,
           progress: Callable[[int, int], None] | None = None, quiet: bool = False,
           say: Callable[[str], None] = print, confirmed: bool = False) -> DesignResult:
    """``debrisfoam design``: the flows into ``out_dir/flows`` (or reused), the realisations, then
    design.csv, design.json, exceedance.png and design.md in ``out_dir`` (module notes)."""
    from orchestrator.studies.design_report import write_report

    check_pool(executor, workers, batch_size)
    t0 = time.perf_counter()
    out = Path(out_dir)
    spec = load_scene(scene_path, list(sets)).design
    cases = design_cases(scene_path, sets, spec)
    workers = max(1, int(workers or os.cpu_count() or 1))
    prepared = []
    for k, case in enumerate(cases):
        start = time.perf_counter()
        say(f"debrisfoam: inundation case {case.name} ({k + 1} of {len(cases)}): "
            f"{', '.join(case.sets[len(sets):]) or 'the scene as it is'}")
        case.scene, case.flow_case, flow, case.npz = ensemble_flow(
            scene_path, out / "flows" / case.name, case.sets, quiet=quiet, stream=sys.stderr if quiet else None,
            say=say, confirmed=confirmed)
        case.site = site_flow_speed(case.flow_case, case.scene)
        bodies, flume, column = transport_setup(case.scene, flow)
        case.front_celerity_m_s = front_celerity(flow, column)
        types = debris_types(case.scene)
        starts = [design_starts(bodies, flume, column, case.scene.design, k, r, types=types)
                  for r in range(case.realisations)]
        case.flow_wall_s = time.perf_counter() - start
        prepared.append((case, starts, flume, column, flow))
    total = sum(c.realisations for c in cases)
    say(f"debrisfoam: {total} realisation(s) over {len(cases)} inundation case(s) on {executor}")
    count = [0]

    def advance(n: int) -> None:
        count[0] += n
        if progress is not None:
            progress(count[0], total)

    rows = []
    for case, starts, flume, column, flow in prepared:
        for row in _run_case(case, starts, flume, column, flow, executor, workers, int(batch_size), advance):
            rows.append({**row, "case": case.name, "case_weight": case.weight,
                         "sample_weight": case.weight / case.realisations})
        forget_flow(str(case.npz))  # one flow held at a time
    table = pd.DataFrame(rows, columns=DESIGN_COLUMNS)
    table["struck"] = table["struck"].astype(bool)
    table["carried"] = table["carried"].astype(bool)
    files = {"table": out / "design.csv"}
    write_text_atomic(files["table"], table.to_csv(index=False, float_format="%.10g"))
    result = DesignResult(table, cases, {}, files)
    wall = {"wall_time_s": round(time.perf_counter() - t0, 2),
            "flow_phase_wall_s": round(sum(c.flow_wall_s for c in cases), 2),
            "workers": workers, "executor": executor, "batch_size": int(batch_size)}
    files.update(write_report(out, result, scene_path, list(sets), spec, wall))
    return result

