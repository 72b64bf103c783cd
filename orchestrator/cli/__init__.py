"""The `debrisfoam` command line.

Exit codes (as in the README): 0 success; 2 bad input (the message names the
file and the field); 1 anything else, with a message saying what failed and where
its log is. `--debug` re-raises instead, for a full traceback.

Every verb is a thin shell over a library call; library code raises, only this
package prints messages and chooses exit codes.

The verbs live by group: :mod:`~orchestrator.cli.analytical`, :mod:`~orchestrator.cli.scenes`,
:mod:`~orchestrator.cli.case` and :mod:`~orchestrator.cli.studies`, on the shared parts of
:mod:`~orchestrator.cli.common`. Each verb imports its stage when it runs, so `--help` and
the analytical verbs start without loading OpenFOAM's stages.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.cli.analytical import add_analytical_parser
from orchestrator.cli.case import add_case_parsers
from orchestrator.cli.design import add_design_parser
from orchestrator.cli.common import EXIT_BAD_INPUT, EXIT_FAILURE, EXIT_OK, ArgParser
from orchestrator.cli.scenes import add_scene_parsers
from orchestrator.cli.studies import add_study_parsers

__all__ = ["build_parser", "main"]


def _version() -> str:
    """The installed package's version (pyproject.toml), or 'unknown' when run from a bare tree."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("debrisfoam")
    except PackageNotFoundError:
        return "unknown (not installed)"


def build_parser() -> argparse.ArgumentParser:
    parser = ArgParser(prog="debrisfoam", description=__doc__.splitlines()[0])
    parser.add_argument("--debug", action="store_true", help="re-raise errors with a full traceback")
    parser.add_argument("--version", action="version", version=f"debrisfoam {_version()}")
    verbs = parser.add_subparsers(dest="verb", required=True, parser_class=ArgParser)
    add_analytical_parser(verbs)
    add_scene_parsers(verbs)
    add_case_parsers(verbs)
    add_study_parsers(verbs)
    add_design_parser(verbs)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    if debug:  # accepted anywhere on the line, as the first option or after the verb
        argv = ["--debug", *(a for a in argv if a != "--debug")]
    try:
        args = build_parser().parse_args(argv)
        code = int(args.func(args) or EXIT_OK)
        sys.stdout.flush()  # here, not at exit, so that a closed pipe is met below
        return code
    except BrokenPipeError:
        # the reader went away (`debrisfoam scenes --json | head -1`): say nothing more, and point
        # stdout at /dev/null so that Python's flush at exit does not fail again
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_FAILURE
    except InputError as exc:
        if debug:
            raise
        print(f"debrisfoam: bad input: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except DebrisfoamError as exc:
        if debug:
            raise
        print(f"debrisfoam: error: {exc}", file=sys.stderr)
        return EXIT_FAILURE
    except PermissionError as exc:  # a file or folder the user named that cannot be written (or read)
        if debug:
            raise
        print(f"debrisfoam: bad input: {exc.filename or 'a file'}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("debrisfoam: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # the contract: never a bare traceback without --debug
        if debug:
            raise
        print(f"debrisfoam: unexpected error: {type(exc).__name__}: {exc} (run with --debug for the traceback)",
              file=sys.stderr)
        return EXIT_FAILURE
