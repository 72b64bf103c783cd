"""system/controlDict as the runner edits it: segment ends, stop requests and their timing.

A running v1912 solver re-reads controlDict (`runTimeModifiable yes`) at the start of a
time step, but ignores a modification that comes less than `fileModificationSkew` (10 s)
after the file's previous modification time. So before a segment the runner dates the
file an hour back (`set_control(..., backdate=True)`), and every request dates it at least
11 s after its previous time: `request_write_now` (write the current step and stop),
`request_stop_at` (land on a time, write it and stop) and `bump_control_mtime` (the same
request again, when the solver has not acted on it).

The file is read and edited through `orchestrator.case.dictionary` (foamlib): an edit keeps
every other entry as rendered and replaces the file at once, so the solver never reads half
of it.
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Any

from orchestrator.case.dictionary import DictionaryError, edit_dictionary, read_dictionary
from orchestrator.core.errors import InputError

__all__ = [
    "FILE_MODIFICATION_SKEW_S",
    "TIME_PRECISION",
    "bump_control_mtime",
    "read_control",
    "request_stop_at",
    "request_write_now",
    "set_control",
    "significant_digits",
]

#: v1912's etc/controlDict OptimisationSwitches fileModificationSkew (s), printed in every log.
FILE_MODIFICATION_SKEW_S = 10.0
#: controlDict timePrecision as rendered (templates/system/controlDict.j2)
TIME_PRECISION = 8

def _control_path(case: Path) -> Path:
    path = case / "system" / "controlDict"
    if not path.is_file():
        raise InputError("system/controlDict", "missing: is it a case rendered by `debrisfoam render`?", str(case))
    return path


def read_control(case: Path) -> dict[str, Any]:
    """system/controlDict's entries (yes/no as booleans, numbers as numbers)."""
    try:
        return read_dictionary(_control_path(case)).as_dict()
    except DictionaryError as exc:
        raise InputError("system/controlDict", f"not an OpenFOAM dictionary ({exc})", str(case)) from None


def significant_digits(time_name: str) -> int:
    """Significant digits of a time directory name ("1.46272017" -> 9, "0.1" -> 1)."""
    mantissa = time_name.lower().split("e")[0].replace("-", "").replace(".", "").lstrip("0")
    return max(1, len(mantissa))


def set_control(case: Path, backdate: bool = False, **entries: Any) -> None:
    """Set top-level controlDict entries; `backdate` dates the file an hour back."""
    path = _control_path(case)
    try:
        with edit_dictionary(path) as control:
            for key, value in entries.items():
                control[key] = value
    except DictionaryError as exc:
        raise InputError("system/controlDict", f"not an OpenFOAM dictionary ({exc})", str(case)) from None
    if backdate:
        past = time.time() - 3600.0
        os.utime(path, (past, past))


def request_write_now(case: Path) -> None:
    """Ask the running solver to write the current time and stop (see the module notes)."""
    path = case / "system" / "controlDict"
    before = path.stat().st_mtime
    set_control(case, stopAt="writeNow")
    stamp = max(time.time(), before + FILE_MODIFICATION_SKEW_S + 1.0)
    os.utime(path, (stamp, stamp))


def request_stop_at(case: Path, t_stop: float, segment_start: float) -> None:
    """Ask the running solver to stop at `t_stop` and write it (measured here, v1912): with
    endTime = t_stop and one write interval from the segment's start to t_stop, the
    solver, re-reading controlDict, adjusts its time step to land on t_stop, writes and
    ends. Regular writes between the request and t_stop are skipped (a few steps)."""
    path = case / "system" / "controlDict"
    before = path.stat().st_mtime
    set_control(case, endTime=t_stop, writeInterval=float(f"{t_stop - segment_start:.12g}"))
    stamp = max(time.time(), before + FILE_MODIFICATION_SKEW_S + 1.0)
    os.utime(path, (stamp, stamp))


def bump_control_mtime(case: Path) -> None:
    """Date controlDict past the skew again: a request the solver has not acted on yet."""
    path = case / "system" / "controlDict"
    stamp = max(time.time(), path.stat().st_mtime) + FILE_MODIFICATION_SKEW_S + 1.0
    os.utime(path, (stamp, stamp))
