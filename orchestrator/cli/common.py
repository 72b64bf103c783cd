"""What every verb of the command line shares: the argument parser, output paths, printing.

Library code raises; the verbs print. :class:`ArgParser` turns a usage error into an
:class:`~analytical.errors.InputError` (exit 2), :func:`output_path` checks an output before
anything is computed, :class:`Flags` renames a library field to the flag the user typed,
:func:`emit` prints a result as aligned text or JSON and :func:`warn` prints warnings.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from analytical.errors import InputError
from orchestrator.core.errors import MissingFeatureError
from orchestrator.core.jsonio import json_default

__all__ = [
    "EXIT_BAD_INPUT",
    "EXIT_FAILURE",
    "EXIT_OK",
    "ArgParser",
    "Flags",
    "HelpFormatter",
    "emit",
    "missing_feature",
    "output_path",
    "warn",
]

EXIT_OK, EXIT_FAILURE, EXIT_BAD_INPUT = 0, 1, 2


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


def output_path(path: str | Path, flag: str, force: bool, folder: bool) -> Path:
    """Check an output path before anything is computed: a folder that can be made and holds
    nothing yet (or `--force`), or a file whose folder exists and which is not there yet (or
    `--force`). Bad paths are bad input naming the flag: nothing already computed is touched."""
    out = Path(path)
    if folder:
        if out.exists() and not out.is_dir():
            raise InputError(flag, f"{out} is a file, not a folder")
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
    if not out.parent.is_dir():
        try:
            out.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(flag, f"cannot create the folder {out.parent}: {exc.strerror}") from None
    return out


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


def emit(result: dict[str, Any], as_json: bool, out=sys.stdout) -> None:
    """A verb's result: indented JSON, or one aligned ``key  value`` line per item."""
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
