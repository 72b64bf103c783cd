"""The written times of a case and the write grid a solver segment runs on.

`latest_time` finds the latest time every rank wrote completely (and removes a write a
kill cut short); `remove_times_from` deletes the times a diverged segment wrote;
`segment_span` gives a segment's endTime and writeInterval so that a run stopped and
resumed off the write grid writes at the same times as an uninterrupted one.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path
from typing import Sequence

from orchestrator.case.folder import EPS_T, processor_dirs, time_names

__all__ = ["MIN_SEGMENT_FRACTION", "latest_time", "remove_times_from", "segment_span"]

#: A segment back onto the write grid shorter than this fraction of the write interval is
#: extended to the next grid time (see `segment_span`).
MIN_SEGMENT_FRACTION = 0.1


#: the last line OpenFOAM writes into every field file (IOobject::writeEndDivider), ascii and binary
_END_DIVIDER = b"// ****"


def _written_to_the_end(path: Path) -> bool:
    """Whether a field file ends with OpenFOAM's closing divider line: a kill during the write
    leaves it cut off mid-list (then the solver stops on "Bad token" when it reads it back).
    Compressed files are taken as they are (their tail would need the whole file inflated)."""
    if path.suffix == ".gz":
        return True
    with open(path, "rb") as f:
        f.seek(0, 2)
        f.seek(max(0, f.tell() - 512))
        tail = f.read().rstrip()
    return tail.rsplit(b"\n", 1)[-1].lstrip().startswith(_END_DIVIDER)


def _complete(dirs: Sequence[Path]) -> bool:
    """A written time is complete when every rank wrote it with the same files and uniform/time,
    each field file written to its end."""
    names = None
    for d in dirs:
        if not (d / "uniform" / "time").is_file() and d.name != "0" and float(d.name) != 0.0:
            return False
        files = sorted(p.name for p in d.iterdir() if p.is_file())
        if names is None:
            names = files
        elif files != names:
            return False
        if not all(_written_to_the_end(d / name) for name in files):
            return False
    return True


def latest_time(case_dir: str | Path, ranks: int, repair: bool = True) -> tuple[float, str]:
    """The latest time every rank wrote completely, (value, name); (0.0, "0") at the start.

    With `repair`, an incomplete latest time (a write cut short by a kill) is deleted.
    """
    case = Path(case_dir)
    bases = processor_dirs(case) if ranks > 1 else [case]
    if not bases:
        return 0.0, "0"
    times = time_names(bases[0])
    while times:
        value, name = times[-1]
        dirs = [b / name for b in bases]
        if all(d.is_dir() for d in dirs) and _complete(dirs):
            return value, name
        if not repair:
            times.pop()
            continue
        for d in dirs:
            if d.is_dir():
                shutil.rmtree(d, ignore_errors=True)
        times.pop()
    return 0.0, "0"


def remove_times_from(case: Path, ranks: int, t_from: float, keep: float) -> None:
    """Delete written times >= t_from (never `keep`, the segment's start)."""
    bases = processor_dirs(case) if ranks > 1 else [case]
    for base in bases:
        for value, name in time_names(base):
            if value >= t_from - EPS_T and value > keep + EPS_T:
                shutil.rmtree(base / name, ignore_errors=True)


def _on_grid(t: float, interval: float) -> bool:
    k = t / interval
    return abs(k - round(k)) < 1e-6


def segment_span(start_s: float, end_s: float, interval_s: float) -> tuple[float, float]:
    """(endTime, writeInterval) of a solver segment starting at `start_s`.

    v1912 counts write times from the time a run starts (`startTime + k writeInterval`)
    and does not write at endTime unless it is a write time. So a segment from a time
    off the case's write grid (a stop for Ctrl-C or a contact) runs only to the next grid
    time, with one write interval spanning it exactly; the following segment is on the
    grid again and writes at the same times as an uninterrupted run. An end time off
    the grid gets a last short segment of its own, so the end is always written.
    """
    span = _exact_segment_span(start_s, end_s, interval_s)
    return tuple(float(f"{v:.12g}") for v in span)


def _exact_segment_span(start_s: float, end_s: float, interval_s: float) -> tuple[float, float]:
    eps = 1e-9 * max(1.0, abs(end_s))
    if not _on_grid(start_s, interval_s):
        target = math.ceil(start_s / interval_s - 1e-6) * interval_s
        if target - start_s < MIN_SEGMENT_FRACTION * interval_s:
            # v1912 stops a run once less than half a time step remains: a segment this short
            # may take no step at all (seen: 0.09977 -> 0.1 s did nothing), so aim one further
            target += interval_s
        target = min(target, end_s)
        return target, target - start_s
    if _on_grid(end_s, interval_s):
        return end_s, interval_s
    last = math.floor(end_s / interval_s + 1e-6) * interval_s
    if last > start_s + eps:
        return last, interval_s
    return end_s, end_s - start_s
