"""The ``design`` verb: a scene's design section to a design page (docs/design.md).

The scene's flows run once (reused when finished), then the realisations; ``-o DIR`` holding a
study already is refused without ``--force`` (its flows/ are reused either way, so nothing
computed is lost).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from orchestrator.cli.case import YES_HELP
from orchestrator.cli.common import EXIT_OK, SCENE_HELP, confirm_large, emit, plan_scene, study_folder
from orchestrator.core.errors import InputError
from orchestrator.scene.shipped import resolve_scene

__all__ = ["add_design_parser", "cmd_design"]


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
    from orchestrator.studies.design import design
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
            "asce_force_N": (s["asce"]["values"][s["asce"]["governing"]]["peak_force_N"]
                             if s["asce"]["values"] else None),
            "wall_time_s": s["wall_time_s"]}
    if not args.json:
        head.update({name: str(path) for name, path in result.files.items()})
    emit(head, args.json)
    return EXIT_OK


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
    p.add_argument("--executor", choices=["local", "dask"], default="local",
                   help="local: a process pool here; dask: a Dask LocalCluster")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="batches at once (default: this machine's cores)")
    p.add_argument("--batch-size", type=int, default=None, metavar="B",
                   help="realisations stepped together in one model (default 128)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="scene override (repeatable)")
    p.add_argument("--force", action="store_true", help="replace a study already in DIR (its flows are reused)")
    p.add_argument("--yes", action="store_true", help=YES_HELP)
    p.add_argument("--json", action="store_true", help="print JSON (no progress)")
    p.set_defaults(func=cmd_design)
