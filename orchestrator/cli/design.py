"""The ``design`` verb: a scene's design section to a design page (docs/design.md).

The scene's flows run once (reused when finished), then the realisations; ``-o DIR`` holding a
study already is refused without ``--force`` (its flows/ are reused either way, so nothing
computed is lost).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from orchestrator.cli.common import (EXIT_OK, SCENE_HELP, closing_options, confirm_large, emit, plan_scene,
                                     pool_options, study_folder)
from orchestrator.core.errors import InputError
from orchestrator.scene.shipped import resolve_scene

__all__ = ["REALISATION_LIMIT_S", "STEP_CPU_S", "add_design_parser", "cmd_design", "confirm_realisations",
           "realisation_seconds", "recommended_head"]

#: CPU seconds one body's transport step costs, batched (128 realisations a model), measured on
#: idle cores: 8.5e-6 s for cases/design-street.yaml (2,000 realisations of 13 s at 0.68 ms steps in
#: 2.7 min of wall on 2 cores, docs/design.md) and 7.2e-6 s for the 1-debris scene (10,000 of 3.5 s
#: at 0.23 ms in 1,092 s of CPU, benchmarks/ensemble.md); the larger is taken.
STEP_CPU_S = 8.5e-6
#: CPU seconds of the study's fit of one first strike (an ensemble's, unless --no-study-fit).
FIT_CPU_S = 0.27
#: Realisations estimated to take longer than this (wall seconds) need --yes (or a terminal's yes).
REALISATION_LIMIT_S = 3600.0


def realisation_seconds(scene, n: int, fit_strikes: bool = False) -> tuple[float, str]:
    """(CPU seconds, how) of ``n`` realisations of ``scene`` carried through its flow: each body
    stepped at the engine's time step (40 steps a contact period of its lightest drawn mass,
    at most the Froude-scaled largest step) to ``run.end_time_s``, at :data:`STEP_CPU_S` a
    body-step; with ``fit_strikes``, :data:`FIT_CPU_S` a body for the study's fit."""
    from orchestrator.contact.resolution import body_contact_law
    from orchestrator.plan.scale import time_scale
    from orchestrator.studies.design_table import debris_types, mass_range
    from orchestrator.transport.mujoco_model import contact_period_s

    if not scene.debris:
        return 0.0, "no debris body"
    types = debris_types(scene)
    dt = 1e-3 * time_scale(scene.reservoir.depth_m)  # the engine's largest step, Froude-scaled
    for b in scene.debris:
        lightest = mass_range(b, scene.design, types.get(b.name))[0]
        dt = min(dt, contact_period_s(body_contact_law(b.contact), lightest) / 40.0)
    steps = float(scene.run.end_time_s) / dt
    bodies = len(scene.debris)
    cpu = n * bodies * steps * STEP_CPU_S + (n * bodies * FIT_CPU_S if fit_strikes else 0.0)
    return cpu, f"{bodies} body(ies) x {steps:,.0f} steps of {dt * 1e3:.3g} ms"


def _duration(seconds: float) -> str:
    return f"{seconds / 3600:.3g} h" if seconds >= 3600 else f"{seconds / 60:.3g} min" if seconds >= 60 \
        else f"{seconds:.3g} s"


def confirm_realisations(cases, workers: int | None, yes: bool, source, fit_strikes: bool = False) -> float:
    """Print the realisations' estimated wall time (``cases``: (scene, realisations) pairs) before
    they start; above :data:`REALISATION_LIMIT_S` ask (a terminal) or refuse (exit 2, naming -n)
    unless ``yes``. The estimate (seconds)."""
    from orchestrator.cli.common import confirm_large
    from orchestrator.plan.resources import LargeRunError

    workers = max(1, int(workers or os.cpu_count() or 1))
    cpu, how, total = 0.0, [], 0
    for scene, n in cases:
        c, h = realisation_seconds(scene, n, fit_strikes)
        cpu += c
        total += n
        how.append(h)
    wall = cpu / workers
    text = (f"{total:,} realisation(s): about {_duration(wall)} of wall time on {workers} worker(s), the flows "
            f"aside (estimated: {'; '.join(dict.fromkeys(how))}, {STEP_CPU_S:.2g} CPU s a body-step as measured on "
            "idle cores, benchmarks/ensemble.md)")
    print(f"debrisfoam: {text}", file=sys.stderr, flush=True)

    class LongRealisations(LargeRunError):
        def __init__(self, messages, where=None):
            self.messages = list(messages)
            InputError.__init__(self, "-n", "; ".join(self.messages) + f": over the limit of "
                                f"{_duration(REALISATION_LIMIT_S)}; give --yes to go ahead, or fewer realisations", where)

        def with_source(self, where):
            return LongRealisations(self.messages, where)

    def check(confirmed: bool) -> None:
        if wall > REALISATION_LIMIT_S and not confirmed:
            raise LongRealisations([text], str(source) if source is not None else None)

    confirm_large(check, yes)
    return wall


def _design_out(path: str, force: bool) -> Path:
    """The study's folder: new, or holding only its flows/ (reused), or anything with --force."""
    return study_folder(path, force, "flows", "study")


def cmd_design(args: argparse.Namespace) -> int:
    if args.workers is not None and args.workers <= 0:
        raise InputError("--workers", f"must be > 0, got {args.workers}")
    if args.batch_size is not None and args.batch_size <= 0:
        raise InputError("--batch-size", f"must be a whole number > 0, got {args.batch_size}")
    sets = list(args.set or [])
    if args.n is not None:
        if args.n <= 0:
            raise InputError("-n", f"must be a whole number > 0 of realisations, got {args.n}")
        sets.append(f"design.realisations={args.n}")
    plan_scene(args.scene, sets)  # the scene and its design section checked before anything runs
    out = _design_out(args.out or str(Path("runs") / f"design-{Path(args.scene).stem}"), args.force)
    from orchestrator.scene.scenefile import load_scene
    from orchestrator.studies.design import design_cases, design
    from orchestrator.studies.design_asce import scene_asce_inputs

    base = load_scene(args.scene, sets)
    cases = design_cases(args.scene, sets, base.design)
    for case in cases:  # the code's inputs: a full-scale scene names what it lacks before any flow runs
        scene_asce_inputs(case.scene, source=str(args.scene))
    confirm_realisations([(c.scene, c.realisations) for c in cases], args.workers, args.yes, args.scene)
    from orchestrator.studies.ensemble import DEFAULT_BATCH_SIZE

    bar = []

    def progress(done: int, total: int) -> None:
        if args.json:
            return
        if not bar:
            from tqdm import tqdm

            bar.append(tqdm(total=total, desc="realisations", unit="run", file=sys.stderr))
        bar[0].update(done - bar[0].n)

    say = (lambda _: None) if args.json else (lambda m: print(m, flush=True))
    try:
        result = confirm_large(lambda yes: design(
            args.scene, out, sets, executor=args.executor, workers=args.workers,
            batch_size=args.batch_size or DEFAULT_BATCH_SIZE, progress=progress, quiet=args.json, say=say,
            confirmed=yes), args.yes)
    finally:
        if bar:
            bar[0].close()
    s = result.summary
    head = {"realisations": s["realisations"], "strike_probability": s["strike_probability"]["probability"],
            **{f"{k}_P90": d["quantiles"]["P90"]["value"] for k, d in s["demands"].items()},
            "asce_force_N": s["asce"]["force_N"] if s["asce"]["values"] else None,
            "asce_binds": s["asce"]["binding"] if s["asce"]["values"] else None,
            "recommended": recommended_head(s.get("recommended")), "wall_time_s": s["wall_time_s"]}
    if not args.json:
        head.update({name: str(path) for name, path in result.files.items()})
    emit(head, args.json)
    return EXIT_OK


def recommended_head(rec: dict | None) -> dict | None:
    """--json's design value: design.json's ``recommended`` without the band's parts (None: no strike)."""
    if rec is None:
        return None
    keys = ("fractile", "given", "importance_I_tsu", "strikes", "striking_realisations", "asce_binds", "asce_force_N")
    return {**{k: rec.get(k) for k in keys},
            "demands": {k: {n: d[n] for n in ("value", "lower", "upper", "unit")} for k, d in rec["demands"].items()}}


def add_design_parser(verbs) -> None:
    """The ``design`` verb, on the top parser's ``verbs``."""
    p = verbs.add_parser("design", help="the scene's flows once, then realisations over its design section "
                                        "(debris start, heading, mass, inundation cases): exceedance curves of the "
                                        "column's demands beside ASCE 7-22 (docs/design.md)")
    p.add_argument("scene", type=resolve_scene, help=SCENE_HELP + "; it must plan one-way")
    p.add_argument("-o", "--out", default=None, metavar="DIR",
                   help="study folder (default runs/design-<scene>): flows/<case>/ (reused when finished), "
                        "design.csv, design.json, exceedance.png, design.md")
    p.add_argument("-n", type=int, default=None, metavar="N", help="realisations (default: design.realisations)")
    pool_options(p, workers="batches at once (default: this machine's cores)",
                 batch_size="realisations stepped together in one model (default 128)")
    closing_options(p, cmd_design, overrides="scene override (repeatable)",
                    force="replace a study already in DIR (its flows are reused)", yes=True,
                    json="print JSON (no progress)")
