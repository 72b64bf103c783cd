"""What every verb of the command line shares: the argument parser, output paths, printing.

Library code raises; the verbs print. :class:`ArgParser` turns a usage error into an
:class:`~orchestrator.core.errors.InputError` (exit 2), :func:`output_path` checks an output before
anything is computed, :class:`Flags` renames a library field to the flag the user typed,
:func:`emit` prints a result as aligned text or JSON and :func:`warn` prints warnings.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from orchestrator.core.errors import InputError
from orchestrator.core.errors import MissingFeatureError
from orchestrator.core.jsonio import json_default

__all__ = [
    "study_folder",
    "EXIT_BAD_INPUT",
    "EXIT_FAILURE",
    "EXIT_OK",
    "SCENE_HELP",
    "FOLDER_FORCE_HELP",
    "YES_HELP",
    "ArgParser",
    "Flags",
    "HelpFormatter",
    "closing_options",
    "pool_options",
    "confirm_large",
    "emit",
    "missing_feature",
    "output_path",
    "plan_scene",
    "planned_scene",
    "warn",
    "writable_folder",
]

EXIT_OK, EXIT_FAILURE, EXIT_BAD_INPUT = 0, 1, 2

#: The help of every scene argument (each parsed by :func:`orchestrator.scene.shipped.resolve_scene`).
SCENE_HELP = ("scene YAML, or a shipped scene by name (e.g. 1debris; `debrisfoam scenes` lists them; "
              "docs/scene.md)")

#: The help of every verb's --yes (the resource guard's soft limits, docs/architecture.md).
YES_HELP = ("go ahead when the plan is over a soft resource limit (memory over half of what is free, or an "
            "estimated solver time over 6 h); without it a terminal is asked, and anything else refused (exit 2)")

#: The help of --force on a verb that writes a folder of results.
FOLDER_FORCE_HELP = "overwrite a folder that holds files already"


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Help that states every option's default (unless it is None or the help says it already)."""

    def _get_help_string(self, action):
        text = action.help or ""
        if action.default in (None, False, argparse.SUPPRESS) or "default" in text:
            return text
        return super()._get_help_string(action)


class ArgParser(argparse.ArgumentParser):
    """argparse that reports usage errors as InputError (exit 2 through our handler)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", HelpFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> None:  # noqa: D401 - argparse API
        raise InputError("arguments", f"{message} (see `{self.prog} --help`)")


def closing_options(p: argparse.ArgumentParser, func: Callable[[argparse.Namespace], int], *,
                    out: str | None = None, out_required: bool = True, overrides: str | None = None,
                    force: str | None = None, yes: bool = False, json: str | None = "print JSON") -> None:
    """Add the options most verbs end with, each whose help is given, then the verb's ``func``.

    In this order: ``-o/--out`` (help ``out``; required unless ``out_required`` is false),
    ``--set KEY=VALUE`` (help ``overrides``), ``--force``, ``--yes`` (:data:`YES_HELP`) and ``--json``.
    """
    if out is not None:
        p.add_argument("-o", "--out", required=out_required, help=out)
    if overrides is not None:
        p.add_argument("--set", action="append", metavar="KEY=VALUE", help=overrides)
    if force is not None:
        p.add_argument("--force", action="store_true", help=force)
    if yes:
        p.add_argument("--yes", action="store_true", help=YES_HELP)
    if json is not None:
        p.add_argument("--json", action="store_true", help=json)
    p.set_defaults(func=func)


def pool_options(p: argparse.ArgumentParser, workers: str, batch_size: str) -> None:
    """Add ``--executor``, ``--workers`` and ``--batch-size`` of a verb that steps realisations in batches
    over a process pool (``ensemble``, ``design``); ``workers`` and ``batch_size`` are their helps."""
    p.add_argument("--executor", choices=["local", "dask"], default="local",
                   help="local: a process pool here; dask: a Dask LocalCluster")
    p.add_argument("--workers", type=int, default=None, metavar="N", help=workers)
    p.add_argument("--batch-size", type=int, default=None, metavar="B", help=batch_size)


def _existing_ancestor(path: Path) -> Path:
    """``path`` itself or its nearest ancestor that exists."""
    path = Path(path).absolute()
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def writable_folder(path: str | Path, flag: str, named: str | Path | None = None) -> Path:
    """Check that a folder can be written (made, if it is not there yet) without making it.

    A write is tried in the folder, or in its nearest existing ancestor (a temporary file, removed
    at once): the only test that tells a read-only file system, an immutable folder or missing
    permissions apart for every user, root included. InputError naming ``flag`` and the path
    (``named``, when the folder is checked for a file in it).
    """
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise InputError(flag, f"{out} is a file, not a folder")
    base = _existing_ancestor(out)
    if not base.is_dir():
        raise InputError(flag, f"cannot make {out}: {base} is a file, not a folder")
    try:
        with tempfile.TemporaryFile(dir=base):
            pass
    except OSError as exc:
        raise InputError(flag, f"cannot write in {base}: {exc.strerror or exc}", str(named or out)) from None
    return out


def output_path(path: str | Path, flag: str, force: bool, folder: bool) -> Path:
    """Check an output path before anything is computed: a folder that can be made and holds
    nothing yet (or `--force`), or a file whose folder can be written and which is not there yet
    (or `--force`). Bad paths are bad input naming the flag: nothing already computed is touched.

    A folder output is made here; a file's missing folders are not (the writer makes them once
    there is something to write), so a refused input leaves no empty folders behind."""
    out = Path(path)
    if folder:
        writable_folder(out, flag)
        if out.is_dir() and any(out.iterdir()) and not force:
            raise InputError(flag, f"{out} holds files already: give --force to overwrite them, or another folder")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(flag, f"cannot create the folder {out}: {exc.strerror}") from None
        return out
    if out.is_dir():
        raise InputError(flag, f"{out} is a folder; give a file name")
    if out.exists() and not force:
        raise InputError(flag, f"{out} exists: give --force to overwrite it, or another name")
    writable_folder(out.parent, flag, named=out)
    return out


def planned_scene(scene_path: str | Path, sets: list[str] | None):
    """(scene, plan) of the scene file, loaded and planned with the light modules only: a verb
    refuses a bad scene or an impossible mesh (the planner's label limit) before it loads the
    stages that render and run (a second or more of imports) and before it writes anything."""
    from orchestrator.plan.planner import load_and_plan

    return load_and_plan(scene_path, sets)


def plan_scene(scene_path: str | Path, sets: list[str] | None):
    """The plan of :func:`planned_scene`."""
    return planned_scene(scene_path, sets)[1]


_T = TypeVar("_T")


def confirm_large(call: Callable[[bool], _T], yes: bool) -> _T:
    """``call(confirmed)``, asking first when the plan is over a soft resource limit.

    ``call`` raises :class:`~orchestrator.plan.resources.LargeRunError` before writing anything
    when the plan is over a soft limit and ``confirmed`` is False. With ``--yes`` (``yes``) it is
    called confirmed; otherwise a terminal is asked, and without one the refusal stands (exit 2).
    """
    from orchestrator.plan.resources import LargeRunError

    try:
        return call(yes)
    except LargeRunError as exc:
        if not sys.stdin.isatty():
            raise
        warn(exc.messages, f"{exc.source}: " if exc.source else "")
        print("debrisfoam: go ahead anyway? [y/N] ", end="", file=sys.stderr, flush=True)  # stdout may be JSON
        answer = sys.stdin.readline().strip().lower()
        if answer not in ("y", "yes"):
            raise InputError(exc.field, "not confirmed: " + "; ".join(exc.messages), exc.source) from None
        return call(True)


class Flags:
    """Rename the fields of InputErrors raised inside to the flags the user typed."""

    def __init__(self, **flags: str):
        self.flags = flags

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and exc.field in self.flags:
            raise InputError(self.flags[exc.field], exc.rule, exc.source) from None
        return False


def warn(messages, where: str = "") -> None:
    """Each planner or check warning on stderr, one line each (also in --json output)."""
    for message in messages or ():
        print(f"debrisfoam: warning: {where}{message}", file=sys.stderr)


def emit(result: dict[str, Any], as_json: bool, out=None) -> None:
    """A verb's result: indented JSON, or one aligned ``key  value`` line per item, on ``out``
    (None: the current ``sys.stdout``, not the one there when this module was imported)."""
    out = sys.stdout if out is None else out
    if as_json:
        json.dump(result, out, indent=2, default=json_default)
        out.write("\n")
    else:
        width = max(len(k) for k in result) if result else 0
        for key, value in result.items():
            if isinstance(value, float):
                value = f"{value:.6g}"
            elif isinstance(value, list):
                value = ", ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in value)
            elif isinstance(value, dict):
                value = json.dumps(value, default=json_default)
            out.write(f"{key:<{width}}  {value}\n")


def missing_feature(what: str, issue: int) -> int:
    """Raise the error of a verb whose stage is not installed (exit 1, naming the tracking issue)."""
    raise MissingFeatureError(f"{what} is not built yet (tracked in issue {issue}); the analytical verbs work today")


def study_folder(path: str, force: bool, reused: str, what: str) -> Path:
    """A study's output folder: new, or holding only its ``reused`` sub-folder (the flows a study
    runs once and reuses), or anything with --force (the study's files are replaced; ``reused``
    is still reused where it holds the scene's cases). ``what`` names the study in the message."""
    out = writable_folder(path, "-o/--out")
    others = sorted(p.name for p in out.iterdir() if p.name != reused) if out.is_dir() else []
    if others and not force:
        raise InputError("-o/--out", f"{out} holds files already ({', '.join(others[:4])}"
                                     f"{', ...' if len(others) > 4 else ''}): give --force to replace the {what} "
                                     f"(its {reused}/ is reused), or another folder")
    return out
