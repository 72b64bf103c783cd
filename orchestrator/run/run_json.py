"""What a run leaves on record: run.json and the bodies' tracks (bodies.csv).

`RunRecord` holds run.json's data (status, steps, segments, wall times, diagnosis) and
rewrites the file atomically after every change, so a run stopped at any moment leaves a
readable record to resume from. `append_track` keeps bodies.csv: every body's state at
every time step the solver reported. v1912 keeps only the first body's state in its time
folders, so the states a restart needs come from the solver's logs (`states_in_logs`).
"""

from __future__ import annotations

import csv
import datetime as _dt
import io
import math
import platform
import shlex
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Sequence

from orchestrator import __version__
from orchestrator.case import bodystate
from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import EPS_T, CaseFolder
from orchestrator.core.files import write_text_atomic
from orchestrator.run.errors import RunError
from orchestrator.run.monitor import StepRecord, parse_log

__all__ = [
    "BODY_TRACK_CSV",
    "RunRecord",
    "append_track",
    "check_against_state_file",
    "now",
    "states_in_logs",
    "versions",
    "with_accelerations",
]

BODY_TRACK_CSV = "bodies.csv"

_TRACK_FIELDS = ["time_s", "body", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s",
                 "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s"] + [f"q_{a}{b}" for a in "xyz" for b in "xyz"]


def now() -> str:
    """The local time now, ISO 8601 to the second (run.json's timestamps)."""
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


class RunRecord:
    """run.json, rewritten atomically after every change."""

    def __init__(self, case: Path):
        self.folder = CaseFolder(case)
        self.path = self.folder.run_path
        notes: list[str] = []
        data = self.folder.run_record(notes)
        if data is None and notes:
            raise RunError(f"{notes[0]}: repair or delete {self.path}")
        self.data: dict[str, Any] = data or {}
        self.data.setdefault("steps", [])
        self.data.setdefault("segments", [])

    def save(self) -> None:
        self.data["updated"] = now()
        self.folder.write_run_record(self.data)

    def step(self, name: str, argv: Sequence[str], start: str, wall_s: float, exit_status: int | None,
             skipped: bool, log: Path) -> None:
        self.data["steps"].append({"name": name, "command": shlex.join(argv), "start": start,
                                   "wall_s": round(wall_s, 3), "exit_status": exit_status,
                                   "skipped": skipped, "log": log.name})
        self.save()


def versions() -> dict[str, str]:
    """The versions of debrisfoam, Python and the packages a run depends on."""
    out = {"debrisfoam": __version__, "python": platform.python_version()}
    for pkg in ("foamlib", "numpy"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:  # pragma: no cover
            pass
    return out


# --------------------------------------------------------------------------- body tracks


def append_track(case: Path, steps: Sequence[StepRecord], start_s: float) -> None:
    """bodies.csv: one row per body per time step; rows after `start_s` (a previous attempt
    of the same stretch of time) are replaced."""
    path = case / BODY_TRACK_CSV
    rows = []
    if path.is_file():
        with open(path, newline="") as fh:
            rows = [r for r in csv.DictReader(fh) if float(r["time_s"]) <= start_s + EPS_T]
    for step in steps:
        for b in step.bodies:
            rows.append(dict(zip(_TRACK_FIELDS, [repr(step.time_s), b.name, *map(repr, b.centre_of_mass_m),
                                                 *map(repr, b.velocity_m_s), *map(repr, b.angular_velocity_rad_s),
                                                 *map(repr, b.orientation)])))
    if not rows:
        return
    text = io.StringIO(newline="")
    w = csv.DictWriter(text, fieldnames=_TRACK_FIELDS)
    w.writeheader()
    w.writerows(rows)
    write_text_atomic(path, text.getvalue())


def states_in_logs(case: Path, solver: str, names: Sequence[str], time_name: str) -> list[BodyState] | None:
    """The bodies' states reported in the step `time_name` of the newest log that has it,
    with accelerations from the two last steps' velocities."""
    logs = sorted(case.glob(f"log.{solver}.*"), key=lambda p: int(p.suffix[1:]) if p.suffix[1:].isdigit() else -1)
    logs = [case / f"log.{solver}"] + logs[::-1]
    for log in logs:
        if not log.is_file():
            continue
        steps, _ = parse_log(log, names)
        for i in range(len(steps) - 1, -1, -1):
            if steps[i].time_name == time_name and len(steps[i].bodies) == len(names):
                return with_accelerations(steps[i], steps[i - 1] if i > 0 else None)
    return None


def with_accelerations(step: StepRecord, previous: StepRecord | None) -> list[BodyState]:
    """The bodies of `step`, with accelerations from `previous`'s velocities (when it has them)."""
    if previous is None or len(previous.bodies) != len(step.bodies) or not step.delta_t_s:
        return list(step.bodies)
    out = []
    for b, p in zip(step.bodies, previous.bodies):
        acc = tuple((v1 - v0) / step.delta_t_s for v1, v0 in zip(b.velocity_m_s, p.velocity_m_s))
        out.append(b.with_changes(acceleration_m_s2=acc))
    return out


def check_against_state_file(case: Path, time_name: str, states: Sequence[BodyState]) -> None:
    """The body state in v1912's own file (one body's: the first's, or with each solver on its own
    cellZone another's) must match one of the reports used for the bodies."""
    files = bodystate.state_file_paths(case, time_name)
    if not files or not states:
        return
    saved = bodystate.read_state_file(files[0])
    centre = saved.get("centreOfRotation")
    if centre is None:
        return
    if all(math.dist(centre, s.centre_of_mass_m) > 1e-6 for s in states):
        raise RunError(f"the body state in {files[0]} ({centre}) matches none of the solver log's reports "
                       f"at t = {time_name} s ({[s.centre_of_mass_m for s in states]}); the logs and time "
                       f"directories disagree (was a log deleted or a time directory copied in?)")
