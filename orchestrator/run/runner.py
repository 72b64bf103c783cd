"""Running a rendered case: mesh, decompose, solve with live progress, stop, resume, contact events.

`run_case(case_dir)` takes a case written by `render` to a finished run:

1. the mesh steps of `foam.mesh_steps` (blockMesh, bodies, mergeMeshes, topoSet,
   setFields, checkMesh), each skipped when its outputs exist;
2. `decomposePar` (hierarchical, from system/decomposeParDict) when running on more
   than one rank;
3. the solver, `mpirun -np N <solver> -parallel`, in *segments*: a segment runs
   from the latest written time until the end time, a stop request (Ctrl-C,
   SIGTERM, `stop_event`) or a contact event. The solver's output goes to
   `log.<solver>`; the log of an earlier segment is kept as `log.<solver>.<k>`
   (k = 1, 2, ... in order);
4. `reconstructPar -latestTime -newTimes`: post-processing reads the function
   objects' output (`postProcessing/`: gauges, column forces, probes), which the
   master rank writes in the case itself, the body tracks (`bodies.csv`, written by
   this runner from the solver's report) and contact events; it needs fields only for
   the final state (plots, checks), so only the latest time is gathered
   (`reconstruct="all"` gathers every written time, `"none"` none).

Every step writes `log.<step>`; `run.json` records each step's command, start, wall
time and exit status, the solver segments, the OpenFOAM build, the cell count, the
time steps taken, the status (`running`, `finished`, `interrupted`, `diverged`,
`failed`) and the runner's own cost. A finished run returns at once; any other
resumes from the latest written time (controlDict `startFrom latestTime`).

Stopping a running solver (v1912, measured here): the runner writes `stopAt
writeNow` into system/controlDict; with `runTimeModifiable yes` the solver re-reads
it at the start of its next time step (the log says `Re-reading object controlDict`),
runs that one step, writes it and ends normally, also in parallel (the master reads
and broadcasts, `timeStampMaster`). v1912 ignores a modification that comes less
than `fileModificationSkew` (10 s) after the file's previous modification time, so
before each segment the runner sets the controlDict's modification time an hour
back, and a stop request dates the file at least 11 s after it. For a contact seen
coming, the runner instead sets `endTime` to the time the body reaches the gap (and
one write interval from the segment's start to it): the solver adjusts its step to
land on that time, writes and ends, so the event time does not depend on how fast
the runner noticed; `writeNow` remains for stops that cannot wait.

Divergence (NaN/inf in the log, Courant runaway, deltaT collapse, a floating point
exception, a body leaving the domain): the solver is killed, time directories from
the first symptom on are deleted, and `DivergenceError` names the cause, the
simulated time, the last good time and the log.

Contact (v1912 has none; bodies pass through walls silently): the bookkeeping is
`orchestrator.run.contact_book`'s (`ContactBook`, which the runner owns). After every
batch of log lines the runner asks the book which bodies will be within
`ContactSettings.gap_m` of the column, a flume wall, another body, or sink into the
bed, before the solver can stop (their closing speeds times the stop latency, a few
time steps, which the runner measures; it polls faster near an obstacle), and
schedules the stop or requests `writeNow`. From the written state the book resolves
the contacts and records them: impacts (`orchestrator.run.contact.resolve`: the MDOF
column, rigid walls, two-body impacts), slow "resting" contacts (a plastic impulse),
bodies the flow keeps pressing against an obstacle (pinned there), bodies sunk into
the bed (lifted back), overlaps (removed along the contact normal). The runner then
writes every body's new state (`bodystate.prepare_restart`: v1912 keeps one body's
state only) and resumes.

Files the runner writes in the case: `run.json`; `log.<step>` (and `log.<solver>.<k>`
for earlier segments); `bodies.csv` (every body's state at every time step: time_s,
body, x_m.., u_m_s.., omega_*_rad_s, the orientation q_xx..q_zz); `bodystate.json`
(the states every restart used, and their source); through the contact book,
`contacts.json` (every event: impacts, resting contacts and pins), `impacts.csv` (one
row per impact: time, bodies, point, normal, velocities in and out, obliquity, height,
peak force, duration, impulse, force history file) and `contacts/event<n>-force.csv`
(and `-base-shear.csv` for the column).
The function objects write `postProcessing/<name>/<start time>/`: one folder per
segment, to be read in time order.

PyFoam: `ParsedParameterFile` reads and edits controlDict and dynamicMeshDict
(written back atomically and at full precision by `bodystate.write_dictionary`). Not
used: its runners (`BasicRunner` runs in the current directory, splits a command
string, names logs `PyFoam.<app>.logfile`, blocks until the end and cannot be asked
to stop the solver cleanly; `foam.run_step` and the segment loop here do what is
needed) and its log analysers (see `orchestrator.run.monitor`).

Units: seconds, metres, kg, N.
"""

from __future__ import annotations

import csv
import datetime as _dt
import json
import math
import os
import platform
import resource
import shlex
import signal
import subprocess
import sys
import threading
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Callable, Sequence

from analytical.errors import DebrisfoamError
from orchestrator.case import bodystate
from orchestrator.case import foam
from orchestrator.run.bedwatch import BedWatch
from orchestrator.run.contact_book import Contact, ContactBook, ContactSettings
from orchestrator.core.jsonio import json_default
from orchestrator.case.folder import EPS_T, processor_dirs, time_names
from orchestrator.case.outputs import WATER_BALANCE_TOLERANCE, read_water_balance
from orchestrator.case.bodystate import BodyProperties, BodyState
from orchestrator.run.monitor import (
    Diagnosis,
    DivergenceLimits,
    HealthWatch,
    LogParser,
    LogTail,
    Progress,
    StepRecord,
    parse_log,
    water_balance_diagnosis,
)

__all__ = [
    "CaseInfo",
    "Contact",
    "ContactError",
    "ContactSettings",
    "DivergenceError",
    "RunError",
    "RunInterrupted",
    "RunSummary",
    "latest_time",
    "load_case_info",
    "run_case",
    "segment_span",
]

RUN_JSON = "run.json"
BODY_TRACK_CSV = "bodies.csv"
#: v1912's etc/controlDict OptimisationSwitches fileModificationSkew (s), printed in every log.
FILE_MODIFICATION_SKEW_S = 10.0
#: How long the solver has to act on a stop request (re-read controlDict) before the
#: runner dates the file later again, and how long in all before it kills the solver.
STOP_ACK_TIMEOUT_S = 30.0
STOP_KILL_TIMEOUT_S = 600.0
#: ... unless the solver writes nothing at all for this long (or 20 times its slowest step,
#: if longer) after a user's stop request: it is stuck inside a time step (seen: the overset
#: addressing of six bodies), and a writeNow is only read between steps, so it is killed.
STOP_SILENT_KILL_S = 60.0
#: wall seconds between two checks of the water balance while a segment runs (and one at its end)
WATER_CHECK_S = 5.0
#: _SegmentResult.reason of a segment the user stopped: written on request, killed (a second
#: Ctrl-C or no answer), or stopped before its first time step
STOPPED_REASONS = ("interrupt", "killed", "unstarted")


# --------------------------------------------------------------------------- errors


class RunError(DebrisfoamError):
    """The run could not go on; the message says why and where the log is."""


class DivergenceError(RunError):
    """The solution diverged or stalled: `kind` (nan, courant, delta_t, fpe, left_domain, body_speed, stall, water), `cause`
    in words, the simulated `time_s` it showed at, the `last_good_time` kept and the log."""

    def __init__(self, kind: str, cause: str, time_s: float | None, last_good_time: str | None, log_path: Path):
        self.kind = kind
        self.cause = cause
        self.time_s = time_s
        self.last_good_time = last_good_time
        self.log_path = Path(log_path)
        at = f" at t = {time_s:.6g} s" if time_s is not None else ""
        keep = f"; kept the last good time {last_good_time} s" if last_good_time is not None else ""
        what = {"stall": "solver stalled", "water": "water balance out of bounds"}.get(kind, "solution diverged")
        super().__init__(f"{what}{at}: {cause}{keep}\n  log: {self.log_path}")


class RunInterrupted(RunError):
    """The user stopped the run (Ctrl-C, SIGTERM or a stop request); it can be resumed."""

    def __init__(self, case: Path, signum: int | None, written_time: str | None, clean: bool,
                 before_first_step: bool = False):
        self.case = Path(case)
        self.signum = signum
        self.written_time = written_time
        self.clean = clean
        self.before_first_step = before_first_step
        if before_first_step:
            at = "the solver was stopped before its first time step, so nothing was lost; " + (
                f"the latest written time is t = {written_time} s" if written_time is not None else "it starts again at 0")
        elif written_time is None:
            at = "nothing was written"
        else:
            how = "the solver wrote" if clean else "the solver was killed before writing; the latest written time is"
            at = f"{how} t = {written_time} s"
        super().__init__(f"run interrupted: {at}. Resume with: debrisfoam run {shlex.quote(str(case))}")

    @property
    def exit_code(self) -> int:
        """128 + the signal number (130 for SIGINT), as a shell reports it."""
        return 128 + (self.signum or signal.SIGINT)


class ContactError(RunError):
    """A contact event could not be resolved (e.g. a body pinned against an obstacle)."""


# --------------------------------------------------------------------------- results


@dataclass(frozen=True)
class RunSummary:
    """What `run_case` did. Times in s; `overhead_fraction` = runner CPU / solver wall time."""

    case: Path
    status: str
    already_finished: bool
    end_time_s: float
    reached_time_s: float
    time_steps: int
    segments: int
    contacts: int
    wall_s: float
    solver_wall_s: float
    runner_cpu_s: float
    overhead_fraction: float
    run_json: Path

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["case"], d["run_json"] = str(self.case), str(self.run_json)
        return d


# --------------------------------------------------------------------------- the case


@dataclass(frozen=True)
class CaseInfo:
    """What the runner needs to know of a rendered case (plan.json, controlDict, dynamicMeshDict);
    `domain_m` and `downstream_type` say where the modelled flume has walls.
    """

    case: Path
    solver: str
    plan: Any  # what foam.mesh_steps / solve_steps read: bodies, bed_friction_factor, decomposition, solver
    ranks: int
    planned_cells: int
    end_time_s: float
    write_interval_s: float
    velocity_scale_m_s: float
    adjustable_time_step: bool
    max_courant: float
    delta_t_s: float
    domain_m: tuple[tuple[float, float], ...]
    two_d: bool
    downstream_type: str
    bodies: tuple[BodyProperties, ...]
    body_sizes_m: dict[str, tuple[float, float, float]]
    #: (body, time) of bodies held on the bed until that time (plan.json hold_until_s)
    holds: tuple[tuple[str, float], ...] = ()
    #: plan.json stall_limit_s (scene run.stall_limit_s): None = the runner's default
    stall_limit_s: float | None = None
    #: plan.json water_balance_limit (scene run.water_balance_limit): None = the runner's default
    water_balance_limit: float | None = None

    @property
    def body_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.bodies)


def _read_control(case: Path) -> Any:
    from PyFoam.RunDictionary.ParsedParameterFile import ParsedParameterFile

    path = case / "system" / "controlDict"
    if not path.is_file():
        raise RunError(f"{path} is missing: is {case} a case rendered by `debrisfoam render`?")
    return ParsedParameterFile(str(path))


def load_case_info(case_dir: str | Path, np_override: int | None = None) -> CaseInfo:
    """Read plan.json, system/controlDict and constant/dynamicMeshDict of a rendered case."""
    case = Path(case_dir).resolve()
    plan_path = case / "plan.json"
    if not plan_path.is_file():
        raise RunError(f"{plan_path} is missing: render the case first (debrisfoam render SCENE -o {case})")
    plan = json.loads(plan_path.read_text())
    try:
        solver = plan["solver"]
        n = tuple(int(v) for v in plan["decomposition"]["n"])
        domain = tuple(tuple(float(v) for v in a) for a in plan["domain_m"])
    except (KeyError, TypeError) as exc:
        raise RunError(f"{plan_path}: not a debrisfoam plan (missing {exc})") from None
    control = _read_control(case)
    ranks = int(np_override) if np_override else n[0] * n[1] * n[2]
    if ranks < 1:
        raise RunError(f"--np must be >= 1, got {ranks}")
    bodies = tuple(bodystate.read_body_properties(case))
    sizes = {b["name"]: tuple(float(v) for v in b["size_m"]) for b in plan.get("bodies", [])}
    missing = [b.name for b in bodies if b.name not in sizes]
    if missing:
        raise RunError(f"{plan_path}: no size for bodies {missing} of constant/dynamicMeshDict")
    steps_plan = SimpleNamespace(
        solver=solver,
        decomposition=n,
        bed_friction_factor=float(plan.get("bed_friction_factor", 0.0)),
        bodies=[SimpleNamespace(name=b.name) for b in bodies],
    )
    return CaseInfo(
        case=case,
        solver=solver,
        plan=steps_plan,
        ranks=ranks,
        planned_cells=int(plan.get("cell_count", 0)),
        end_time_s=float(control["endTime"]),
        write_interval_s=float(control["writeInterval"]),
        velocity_scale_m_s=float(plan.get("velocity_scale_m_s") or 5.0),
        adjustable_time_step=str(control["adjustTimeStep"]).lower() in ("yes", "on", "true", "1")
        if "adjustTimeStep" in control else False,
        max_courant=float(control["maxCo"]) if "maxCo" in control else 1.0,
        delta_t_s=float(control["deltaT"]),
        domain_m=domain,
        two_d=bool(plan.get("two_d", False)),
        downstream_type=str(plan.get("downstream_type", "wall")),
        bodies=bodies,
        body_sizes_m=sizes,
        holds=tuple((str(b["name"]), float(b["hold_until_s"])) for b in plan.get("bodies", [])
                    if float(b.get("hold_until_s") or 0.0) > 0.0),
        stall_limit_s=float(plan["stall_limit_s"]) if plan.get("stall_limit_s") else None,
        water_balance_limit=float(plan["water_balance_limit"]) if plan.get("water_balance_limit") else None,
    )


# --------------------------------------------------------------------------- time directories


def _complete(dirs: Sequence[Path]) -> bool:
    """A written time is complete when every rank wrote it with the same files and uniform/time."""
    names = None
    for d in dirs:
        if not (d / "uniform" / "time").is_file() and d.name != "0" and float(d.name) != 0.0:
            return False
        files = sorted(p.name for p in d.iterdir() if p.is_file())
        if names is None:
            names = files
        elif files != names:
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
                _rmtree(d)
        times.pop()
    return 0.0, "0"


def _rmtree(path: Path) -> None:
    import shutil

    shutil.rmtree(path, ignore_errors=True)


def _remove_times_from(case: Path, ranks: int, t_from: float, keep: float) -> None:
    """Delete written times >= t_from (never `keep`, the segment's start)."""
    bases = processor_dirs(case) if ranks > 1 else [case]
    for base in bases:
        for value, name in time_names(base):
            if value >= t_from - EPS_T and value > keep + EPS_T:
                _rmtree(base / name)


# --------------------------------------------------------------------------- controlDict


#: controlDict as last parsed and written here: (text written, the parsed object). PyFoam
#: builds its parser tables on every ParsedParameterFile (about 25 ms of CPU each), which
#: would count against the solver at every stop request.
_CONTROL_CACHE: dict[Path, tuple[str, Any]] = {}


#: controlDict timePrecision as rendered (templates/system/controlDict.j2)
_TIME_PRECISION = 8


def _significant_digits(time_name: str) -> int:
    """Significant digits of a time directory name ("1.46272017" -> 9, "0.1" -> 1)."""
    mantissa = time_name.lower().split("e")[0].replace("-", "").replace(".", "").lstrip("0")
    return max(1, len(mantissa))


def _set_control(case: Path, backdate: bool = False, **entries: Any) -> None:
    """Set top-level controlDict entries (PyFoam); `backdate` dates the file an hour back."""
    path = case / "system" / "controlDict"
    cached = _CONTROL_CACHE.get(path)
    if cached is not None and path.is_file() and path.read_text() == cached[0]:
        control = cached[1]
    else:
        control = _read_control(case)
    for key, value in entries.items():
        control[key] = value
    bodystate.write_dictionary(control, path)
    _CONTROL_CACHE[path] = (path.read_text(), control)
    if backdate:
        past = time.time() - 3600.0
        os.utime(path, (past, past))


def _request_write_now(case: Path) -> None:
    """Ask the running solver to write the current time and stop (see the module notes)."""
    path = case / "system" / "controlDict"
    before = path.stat().st_mtime
    _set_control(case, stopAt="writeNow")
    stamp = max(time.time(), before + FILE_MODIFICATION_SKEW_S + 1.0)
    os.utime(path, (stamp, stamp))


def _request_stop_at(case: Path, t_stop: float, segment_start: float) -> None:
    """Ask the running solver to stop at `t_stop` and write it (measured here, v1912): with
    endTime = t_stop and one write interval from the segment's start to t_stop, the
    solver, re-reading controlDict, adjusts its time step to land on t_stop, writes and
    ends. Regular writes between the request and t_stop are skipped (a few steps)."""
    path = case / "system" / "controlDict"
    before = path.stat().st_mtime
    _set_control(case, endTime=t_stop, writeInterval=float(f"{t_stop - segment_start:.12g}"))
    stamp = max(time.time(), before + FILE_MODIFICATION_SKEW_S + 1.0)
    os.utime(path, (stamp, stamp))


def _bump_control_mtime(case: Path) -> None:
    path = case / "system" / "controlDict"
    stamp = max(time.time(), path.stat().st_mtime) + FILE_MODIFICATION_SKEW_S + 1.0
    os.utime(path, (stamp, stamp))


# --------------------------------------------------------------------------- records


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")


class _Record:
    """run.json, rewritten atomically after every change."""

    def __init__(self, case: Path):
        self.path = case / RUN_JSON
        self.data: dict[str, Any] = json.loads(self.path.read_text()) if self.path.is_file() else {}
        self.data.setdefault("steps", [])
        self.data.setdefault("segments", [])

    def save(self) -> None:
        self.data["updated"] = _now()
        tmp = self.path.with_suffix(".json.tmp")
        tmp.write_text(json.dumps(self.data, indent=2, default=json_default))
        os.replace(tmp, self.path)

    def step(self, name: str, argv: Sequence[str], start: str, wall_s: float, exit_status: int | None,
             skipped: bool, log: Path) -> None:
        self.data["steps"].append({"name": name, "command": shlex.join(argv), "start": start,
                                   "wall_s": round(wall_s, 3), "exit_status": exit_status,
                                   "skipped": skipped, "log": log.name})
        self.save()



def _versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    from orchestrator import __version__

    out = {"debrisfoam": __version__, "python": platform.python_version()}
    for pkg in ("PyFoam", "numpy"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:  # pragma: no cover
            pass
    return out


# --------------------------------------------------------------------------- body tracks


_TRACK_FIELDS = ["time_s", "body", "x_m", "y_m", "z_m", "u_m_s", "v_m_s", "w_m_s",
                 "omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s"] + [f"q_{a}{b}" for a in "xyz" for b in "xyz"]


def _append_track(case: Path, steps: Sequence[StepRecord], start_s: float) -> None:
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
    tmp = path.with_suffix(".csv.tmp")
    with open(tmp, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=_TRACK_FIELDS)
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def _states_in_logs(case: Path, solver: str, names: Sequence[str], time_name: str) -> list[BodyState] | None:
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
                return _with_accelerations(steps[i], steps[i - 1] if i > 0 else None)
    return None


def _with_accelerations(step: StepRecord, previous: StepRecord | None) -> list[BodyState]:
    if previous is None or len(previous.bodies) != len(step.bodies) or not step.delta_t_s:
        return list(step.bodies)
    out = []
    for b, p in zip(step.bodies, previous.bodies):
        acc = tuple((v1 - v0) / step.delta_t_s for v1, v0 in zip(b.velocity_m_s, p.velocity_m_s))
        out.append(b.with_changes(acceleration_m_s2=acc))
    return out


#: A segment back onto the write grid shorter than this fraction of the write interval is
#: extended to the next grid time (see `_segment_span`).
_MIN_SEGMENT_FRACTION = 0.1


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
    span = _segment_span(start_s, end_s, interval_s)
    return tuple(float(f"{v:.12g}") for v in span)


def _segment_span(start_s: float, end_s: float, interval_s: float) -> tuple[float, float]:
    eps = 1e-9 * max(1.0, abs(end_s))
    if not _on_grid(start_s, interval_s):
        target = math.ceil(start_s / interval_s - 1e-6) * interval_s
        if target - start_s < _MIN_SEGMENT_FRACTION * interval_s:
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


# --------------------------------------------------------------------------- the runner


@dataclass
class _SegmentResult:
    start_name: str
    reason: str  # end, contact, interrupt, killed, unstarted (STOPPED_REASONS), diverged
    returncode: int | None
    steps: list[StepRecord]
    parser: LogParser
    log: Path
    wall_s: float
    runner_cpu_s: float
    diagnosis: Diagnosis | None = None
    contacts: list[Contact] = field(default_factory=list)


class _StopFlag:
    """Set by SIGINT/SIGTERM handlers or a caller's threading.Event."""

    def __init__(self, event: threading.Event | None):
        self.event = event
        self.signum: int | None = None
        self.count = 0

    def handler(self, signum, frame) -> None:  # noqa: ARG002 - signal API
        self.signum = signum
        self.count += 1

    @property
    def requested(self) -> bool:
        return self.count > 0 or (self.event is not None and self.event.is_set())


def _cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _set_parent_death_signal() -> None:  # pragma: no cover - runs in the child
    """Linux: the solver gets SIGTERM if the runner dies, instead of running on orphaned."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except Exception:
        pass


class _Runner:
    """Drives one run: the steps, the solver segments (log tailing, stop requests, kills,
    divergence), run.json and the body tracks; its `book` (ContactBook) keeps the contacts."""

    def __init__(self, info: CaseInfo, quiet: bool, contact: ContactSettings, limits: DivergenceLimits,
                 stop: _StopFlag, poll_interval_s: float, stream, on_step: Callable[[StepRecord], None] | None):
        self.info = info
        self.case = info.case
        self.quiet = quiet
        self.contact = contact
        defaults = {}
        if limits.min_delta_t_s is None:
            defaults["min_delta_t_s"] = 1e-3 * info.delta_t_s
        if limits.max_body_speed_m_s is None:
            defaults["max_body_speed_m_s"] = 3.0 * info.velocity_scale_m_s
        if limits.stall_s is None and info.stall_limit_s is not None:
            defaults["stall_s"] = info.stall_limit_s
        if limits.water_balance is None:
            defaults["water_balance"] = info.water_balance_limit or WATER_BALANCE_TOLERANCE
        self.limits = DivergenceLimits(**{**asdict(limits), **defaults})
        self.stop = stop
        self.end_time_s = info.end_time_s
        self.write_interval_s = info.write_interval_s
        self.poll = poll_interval_s
        self.poll_now = poll_interval_s
        self.fast_poll = min(poll_interval_s, 0.02)
        self.stream = stream
        self.on_step = on_step
        self.record = _Record(self.case)
        self.book = ContactBook(info, contact, self.record.data, self.say)
        #: bodies on the bed: freed on the measured water depth, their bed friction (set in _run_steps)
        self.bedwatch: BedWatch | None = None
        self.progress: Progress | None = None
        self.last_steps: list[StepRecord] = []
        #: stop latency in time steps (measured while a segment runs) and the last deltaT
        self.latency_steps = 4
        self.last_delta_t_s = info.delta_t_s
        self.between_s = 0.0

    # ---- helpers
    def say(self, message: str) -> None:
        if self.quiet:
            return
        if self.progress is not None:
            self.progress.write(message)  # above the bar, not through it
        else:
            print(message, file=self.stream or sys.stderr, flush=True)

    def run_step(self, step: foam.Step, np_: int = 1, extra: Sequence[str] = ()) -> foam.StepResult:
        start = _now()
        argv = list(step.argv) + list(extra)
        try:
            result = foam.run_step(step.name, argv, self.case, np=np_, done=step.done)
        except foam.StepError as exc:
            self.record.step(step.name, foam.parallel_argv(argv, np_), start, 0.0, exc.returncode, False,
                             exc.log_path)
            self.record.data["status"] = "failed"
            self.record.data["error"] = str(exc)
            self.record.save()
            raise
        self.record.step(step.name, result.argv, start, result.wall_s, result.returncode, result.skipped,
                         result.log_path)
        return result

    @property
    def stop_horizon_s(self) -> float:
        """How far (simulated s) the solver may run on after a stop request: the last
        deltaT times the stop latency measured in the last segment."""
        return self.last_delta_t_s * self.latency_steps

    # ---- segments
    def _rotate_log(self) -> Path:
        log = self.case / f"log.{self.info.solver}"
        if log.is_file() and log.stat().st_size > 0:
            k = 1 + max([int(p.suffix[1:]) for p in self.case.glob(f"log.{self.info.solver}.*")
                         if p.suffix[1:].isdigit()] or [0])
            kept = self.case / f"log.{self.info.solver}.{k}"
            log.rename(kept)
            # run.json names the log of every segment: the earlier ones now live under `kept`
            for seg in self.record.data["segments"]:
                if seg.get("log") == log.name:
                    seg["log"] = kept.name
            self.record.save()
        return log

    def restore_bodies(self, start_name: str) -> list[BodyState]:
        """Before a segment: give every body its state at `start_name` (the v1912 recipe of
        `bodystate`); returns the states. Sources, in order: the states recorded for that
        time (a contact's rebound, or an earlier restart), the last segment's steps, the
        solver logs."""
        if not self.info.bodies:
            return []
        bodystate.forget_after(self.case, float(start_name))
        self.book.forget_events_after(float(start_name))
        recorded = bodystate.recorded_states(self.case, start_name)
        if float(start_name) == 0.0 and recorded is None:
            states = bodystate.coefficient_states(self.case)
            bodystate.record_states(self.case, start_name, states, "initial")
            return states
        if recorded is not None:
            states, source = recorded
        else:
            states, source = self._reported_states(start_name), "log"
            if states is None:
                raise RunError(f"cannot restore the bodies' states at t = {start_name} s: no solver log reports "
                               f"them (v1912 keeps only the first body's state); restart from an earlier time "
                               f"by deleting the later time directories")
            _check_against_state_file(self.case, start_name, states)
        bodystate.prepare_restart(self.case, start_name, states, source)
        return states

    def _reported_states(self, time_name: str) -> list[BodyState] | None:
        steps = self.last_steps
        for i in range(len(steps) - 1, -1, -1):
            if steps[i].time_name == time_name and len(steps[i].bodies) == len(self.info.bodies):
                return _with_accelerations(steps[i], steps[i - 1] if i > 0 else None)
        return _states_in_logs(self.case, self.info.solver, self.info.body_names, time_name)

    def solve_segment(self, start_value: float, start_name: str, progress: Progress) -> _SegmentResult:
        """Run the solver from `start_name` to the segment's end (see `segment_span`)."""
        # without the depth watch (no bodies), a body held on the bed would be let go at the
        # planner's release time: a temporary end (closer releases are due now, see run_case)
        soon = _MIN_SEGMENT_FRACTION * self.write_interval_s
        holds = [] if self.bedwatch is not None else self.info.holds
        end = min([t for _, t in holds if start_value + soon < t < self.end_time_s - EPS_T]
                  + [self.end_time_s])
        if self.info.adjustable_time_step:
            seg_end, seg_interval = segment_span(start_value, end, self.write_interval_s)
        else:  # a fixed deltaT cannot land on the grid times: run to the end as the case says
            seg_end, seg_interval = end, self.write_interval_s
        self.record.data["segment_control"] = {"endTime": seg_end, "writeInterval": seg_interval}
        self.record.save()
        # v1912 may write a time with more digits than timePrecision (it raises the precision
        # to tell close times apart) and then, restarting, look for the shorter name
        _set_control(self.case, backdate=True, stopAt="endTime", startFrom="latestTime",
                     endTime=seg_end, writeInterval=seg_interval,
                     timePrecision=max(_TIME_PRECISION, _significant_digits(start_name)))
        try:
            return self._solve(start_value, start_name, seg_end, progress)
        finally:  # the case's own controls back, whatever happened
            _set_control(self.case, stopAt="endTime", endTime=self.end_time_s, writeInterval=self.write_interval_s)
            self.record.data.pop("segment_control", None)
            self.record.save()

    def _solve(self, start_value: float, start_name: str, seg_end: float, progress: Progress) -> _SegmentResult:
        info = self.info
        log = self._rotate_log()
        argv = foam.parallel_argv([info.solver], info.ranks)
        env = foam.foam_env()
        env["PWD"] = str(self.case)
        parser = LogParser(info.body_names)
        health = HealthWatch(self.limits, info.max_courant, info.domain_m if info.bodies else None)
        tail = LogTail(log)
        steps: list[StepRecord] = []
        arrivals: list[tuple[float, int]] = []
        stop_reason: str | None = None
        diag: Diagnosis | None = None
        pending: list[Contact] = []
        bed_why: str | None = None
        killed = False
        started = _now()
        t0, cpu0 = time.perf_counter(), _cpu_s()
        with open(log, "w") as out:
            try:
                proc = subprocess.Popen(argv, cwd=self.case, stdout=out, stderr=subprocess.STDOUT, env=env,
                                        start_new_session=True, preexec_fn=_set_parent_death_signal)
            except FileNotFoundError:
                raise RunError(f"{argv[0]!r} not found: is OpenFOAM v1912 installed (make openfoam)?") from None
        rereads_at_request = 0
        requested_at: float | None = None  # wall clock of the last controlDict request
        last_bump = 0.0
        scheduled: float | None = None  # simulated time of a scheduled contact stop
        last_output = time.perf_counter()  # wall clock of the last log line (the stall watch)
        water_checked = last_output  # wall clock of the last water-balance check
        last_line = ""
        try:
            while True:
                rc = proc.poll()
                lines = tail.read_lines() if rc is None else tail.flush()
                now = time.perf_counter()
                if lines:
                    last_output = now
                    last_line = next((ln.strip() for ln in reversed(lines) if ln.strip()), last_line)
                elif diag is None and rc is None and not killed:
                    diag = self._stall(now - last_output, arrivals, steps, start_value, last_line)
                new = parser.feed(lines)
                if new:
                    steps.extend(new)
                    arrivals.append((time.perf_counter(), len(steps)))
                    del arrivals[:-8]
                    if self.on_step is not None:
                        for s in new:
                            self.on_step(s)
                    if diag is None:
                        for s in new:
                            diag = health.check_step(s)
                            if diag:
                                break
                    progress.update(steps[-1], note="stopping" if stop_reason else "")
                if diag is None:
                    diag = health.check_parser(parser)
                    if diag is not None and diag.time_s is None:  # before the first step: the start time
                        diag = replace(diag, time_s=start_value)
                if diag is None and steps and (rc is not None or now - water_checked >= WATER_CHECK_S):
                    water_checked = now
                    diag = self._water_check()
                if rc is not None:
                    break
                if diag is not None and not killed:
                    self._kill(proc)
                    killed = True
                    continue
                if stop_reason is None and self.stop.requested and not steps:
                    # no time step taken yet (reading the mesh, overset addressing: minutes with
                    # several bodies): nothing to write and writeNow is only read between steps
                    stop_reason = "unstarted"
                    self._kill(proc)
                    killed = True
                    progress.write("stop requested before the solver's first time step: stopped it at once "
                                   "(nothing to write)")
                elif stop_reason is None and self.stop.requested:
                    stop_reason, requested_at = "interrupt", time.perf_counter()
                    rereads_at_request = parser.rereads
                    _request_write_now(self.case)
                    progress.write("stop requested: the solver will write the current time step and stop "
                                   "(press Ctrl-C again to kill it without writing)")
                elif stop_reason is None and new and self.contact.enabled and info.bodies:
                    ahead = self._contacts_ahead(steps, arrivals)
                    if ahead:
                        contact, soonest = min(ahead, key=lambda x: x[1])
                        now_s, dt = steps[-1].time_s, steps[-1].delta_t_s or info.delta_t_s
                        margin = dt * (self.latency_steps + 1)  # the solver may get this far before it reads
                        t_stop = float(f"{now_s + soonest:.8g}")
                        late = scheduled is None or max(contact.approach_m_s, 0.0) * (
                            scheduled - t_stop) > 0.5 * self.contact.gap_m
                        if soonest <= margin and (late or not info.adjustable_time_step):
                            # too close to schedule, and nothing scheduled in time: stop at the
                            # next step the solver can (writeNow)
                            stop_reason, requested_at = "contact", time.perf_counter()
                            rereads_at_request = parser.rereads
                            pending = [c for c, _ in ahead]
                            _request_write_now(self.case)
                        elif (soonest > margin and info.adjustable_time_step and t_stop < seg_end - EPS_T
                              and (scheduled is None or t_stop < scheduled - EPS_T)):
                            # stop where the body reaches the gap: the solver lands on that time and
                            # writes it, whatever the runner's latency
                            scheduled, requested_at = t_stop, time.perf_counter()
                            rereads_at_request = parser.rereads
                            pending = [c for c, _ in ahead]
                            _request_stop_at(self.case, t_stop, start_value)
                if stop_reason is None and new and self.bedwatch is not None and steps[-1].bodies:
                    # a body on the bed the measured water can carry, or whose friction needs resizing
                    why = self.bedwatch.why_stop(steps[-1].bodies, steps[-1].time_s)
                    if why is not None:
                        stop_reason, requested_at = "bed", time.perf_counter()
                        rereads_at_request = parser.rereads
                        bed_why = why
                        _request_write_now(self.case)
                if requested_at is not None:
                    if stop_reason == "contact" and self.stop.requested:
                        stop_reason = "interrupt"  # the write is requested already
                    if stop_reason == "interrupt" and self.stop.count > 1 and not killed:
                        self._kill(proc)
                        killed = True
                    waited = time.perf_counter() - requested_at
                    if parser.rereads <= rereads_at_request and waited - last_bump > STOP_ACK_TIMEOUT_S:
                        _bump_control_mtime(self.case)  # not seen yet: date it later again
                        last_bump = waited
                    if stop_reason is not None and waited > STOP_KILL_TIMEOUT_S and not killed:
                        self._kill(proc)
                        killed = True
                    elif (stop_reason == "interrupt" and not killed
                          and now - max(last_output, requested_at) > self._silent_kill_s(arrivals)):
                        self._kill(proc)
                        killed = True
                        progress.write(f"the solver wrote nothing for {now - last_output:.0f} s after the stop "
                                       "request (stuck inside a time step): killed it; the run resumes from "
                                       "the last written time")
                time.sleep(self.poll_now)
        except BaseException:
            if proc.poll() is None:
                self._kill(proc)
            raise
        if stop_reason is None and scheduled is not None and steps and abs(steps[-1].time_s - scheduled) < 1e-9 + 1e-7 * scheduled:
            stop_reason = "contact"
        wall = time.perf_counter() - t0
        cpu = _cpu_s() - cpu0
        rc = proc.returncode
        reason = "diverged" if diag else (stop_reason or "end")
        if killed and not diag and stop_reason == "interrupt":
            reason = "killed"
        seg = {"start": started, "start_time": start_name, "end_time": steps[-1].time_name if steps else start_name,
               "time_steps": len(steps), "wall_s": round(wall, 3), "exit_status": rc, "stop_reason": reason,
               "command": shlex.join(argv), "log": log.name, "runner_cpu_s": round(cpu, 3)}
        if pending:
            seg["stopped_for"] = [{"body": c.body, "other": c.other, "gap_m": round(c.distance_m, 6),
                                   "closing_m_s": round(c.approach_m_s, 4)} for c in pending]
        if bed_why is not None:
            seg["stopped_for_bed"] = bed_why
        if diag is not None:
            seg["diagnosis"] = diag.cause
        self.record.data["segments"].append(seg)
        self.record.data["time_steps"] = self.record.data.get("time_steps", 0) + len(steps)
        if parser.build:
            self.record.data["openfoam"] = parser.build
        self.record.save()
        if info.bodies and steps:
            _append_track(self.case, steps, start_value)
        self.last_steps = steps
        if steps and steps[-1].delta_t_s:
            self.last_delta_t_s = steps[-1].delta_t_s
        return _SegmentResult(start_name, reason, rc, steps, parser, log, wall, cpu, diag, pending)

    def _water_check(self) -> Diagnosis | None:
        """The water-balance stop (DivergenceLimits.water_balance) on what the solver wrote so far."""
        try:
            balance = read_water_balance(self.case)
        except (OSError, ValueError):  # a line being written: next time
            return None
        return water_balance_diagnosis(balance, self.limits.water_balance)

    @staticmethod
    def _silent_kill_s(arrivals: list[tuple[float, int]]) -> float:
        """How long a solver may stay silent after a stop request before it is killed."""
        return max(STOP_SILENT_KILL_S, 20.0 * (_slowest_step_s(arrivals) or 0.0))

    def _stall(self, silent_s: float, arrivals: list[tuple[float, int]], steps: list[StepRecord],
               start_value: float, last_line: str) -> Diagnosis | None:
        """A stall diagnosis when the solver has written nothing for longer than the limit."""
        slowest_s = _slowest_step_s(arrivals)
        limit = self.limits.stall_limit_s(slowest_s)
        if silent_s <= limit:
            return None
        t = steps[-1].time_s if steps else start_value
        slowest = f"; its slowest time step so far took {slowest_s:.3g} s" if slowest_s is not None else ""
        return Diagnosis("stall", f"the solver stalled: nothing written to its log for {silent_s:.0f} s of wall "
                                  f"time{slowest} (last line: {last_line[:120]!r})", t, None)

    def _kill(self, proc: subprocess.Popen) -> None:
        """SIGTERM to the solver's process group (mpirun and its ranks), then SIGKILL."""
        for sig, wait in ((signal.SIGTERM, 10.0), (signal.SIGKILL, 10.0)):
            try:
                os.killpg(proc.pid, sig)
            except ProcessLookupError:
                return
            try:
                proc.wait(timeout=wait)
                return
            except subprocess.TimeoutExpired:
                continue

    def _contacts_ahead(self, steps: list[StepRecord],
                        arrivals: list[tuple[float, int]]) -> list[tuple[Contact, float]]:
        """The book's contacts ahead of the last reported step (`ContactBook.contacts_ahead`),
        given the stop latency measured now.

        Stop latency in time steps: the runner sees a step up to one poll interval after
        the solver printed it (the solver may be that many steps further), and the solver
        acts on a controlDict request at the start of its next step. Near an obstacle (a
        contact ahead) the runner polls faster (20 ms) to keep it short.
        """
        last = steps[-1]
        if not last.bodies:
            return []
        wall_per_step = None
        if len(arrivals) >= 2:
            (w0, n0), (w1, n1) = arrivals[0], arrivals[-1]
            if n1 > n0:
                wall_per_step = (w1 - w0) / (n1 - n0)
        self.latency_steps = 2 + (math.ceil((self.poll_now + 0.05) / wall_per_step) if wall_per_step else 3)
        ahead = self.book.contacts_ahead(last, self.latency_steps)
        self.poll_now = self.fast_poll if ahead else self.poll
        return ahead


def _check_against_state_file(case: Path, time_name: str, states: Sequence[BodyState]) -> None:
    """The first body's state in v1912's own file must match the report used for it."""
    files = bodystate.state_file_paths(case, time_name)
    if not files or not states:
        return
    saved = bodystate.read_state_file(files[0])
    centre = saved.get("centreOfRotation")
    if centre is None:
        return
    if math.dist(centre, states[0].centre_of_mass_m) > 1e-6:
        raise RunError(f"the first body's state in {files[0]} ({centre}) does not match the solver log's report "
                       f"at t = {time_name} s ({states[0].centre_of_mass_m}); the logs and time directories "
                       f"disagree (was a log deleted or a time directory copied in?)")


# --------------------------------------------------------------------------- public entry


def run_case(case_dir: str | Path, np: int | None = None, quiet: bool = False, *,
             reconstruct: str = "latest", contact: ContactSettings | None = None,
             limits: DivergenceLimits | None = None, stop_event: threading.Event | None = None,
             poll_interval_s: float = 0.2, stream=None,
             on_step: Callable[[StepRecord], None] | None = None) -> RunSummary:
    """Run a rendered case to its end time; resumable and idempotent (see the module notes).

    np: MPI ranks (default: the plan's decomposition). quiet: no progress bar, no messages.
    reconstruct: "latest" (default), "all" or "none" written times gathered by reconstructPar.
    contact: ContactSettings (default on, 5 mm gap). limits: DivergenceLimits.
    stop_event: set it to stop the run as Ctrl-C would (from another thread).
    on_step: called with every StepRecord as the log is read (tests, custom monitors).

    Raises RunInterrupted (stopped; resumable), DivergenceError, ContactError, RunError,
    foam.StepError (a step failed), all DebrisfoamError.
    """
    if reconstruct not in ("latest", "all", "none"):
        raise ValueError(f"reconstruct must be 'latest', 'all' or 'none', got {reconstruct!r}")
    wall0 = time.perf_counter()
    lock = _lock_case(Path(case_dir))
    try:
        return _run_locked(case_dir, np, quiet, reconstruct, contact, limits, stop_event, poll_interval_s, stream,
                           on_step, wall0)
    finally:
        lock.close()


def _lock_case(case: Path):
    """An exclusive lock on the case (two runners on one case would corrupt it)."""
    import fcntl

    if not case.is_dir():
        raise RunError(f"case directory {case} does not exist")
    fh = open(case / ".debrisfoam-run.lock", "a+")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        fh.close()
        raise RunError(f"{case} is being run by another debrisfoam process; wait for it or stop it") from None
    return fh


def _run_locked(case_dir, np, quiet, reconstruct, contact, limits, stop_event, poll_interval_s, stream, on_step,
                wall0) -> RunSummary:
    info = _original_controls(load_case_info(case_dir, np))
    case = info.case
    stop = _StopFlag(stop_event)
    runner = _Runner(info, quiet, contact or ContactSettings(), limits or DivergenceLimits(), stop,
                     poll_interval_s, stream, on_step)
    rec = runner.record
    data = rec.data
    data.update({"case": str(case), "solver": info.solver, "ranks": info.ranks, "end_time_s": info.end_time_s,
                 "scene": "scene.yaml", "plan": "plan.json", "versions": _versions()})
    data["control"] = {"endTime": info.end_time_s, "writeInterval": info.write_interval_s}
    data.setdefault("cells", {})["planned"] = info.planned_cells
    data.setdefault("started", _now())
    _check_decomposition(case, info.ranks)

    reached, name = latest_time(case, info.ranks)
    if data.get("status") == "finished" and reached >= info.end_time_s - EPS_T:
        return _summary(info, data, True, reached, time.perf_counter() - wall0)

    data["status"] = "running"
    data.pop("error", None)
    previous = data.pop("diagnosis", None)  # why the last run stopped, if it diverged
    rec.save()
    try:
        return _run_steps(info, runner, stop, quiet, reconstruct, stream, wall0, previous)
    except RunInterrupted:
        raise
    except DebrisfoamError as exc:  # recorded, then raised for the CLI to report
        if data.get("status") == "running":
            data["status"], data["error"] = "failed", str(exc)
            rec.save()
        raise


def _run_steps(info: CaseInfo, runner: _Runner, stop: _StopFlag, quiet: bool, reconstruct: str, stream,
               wall0: float, previous: dict[str, Any] | None = None) -> RunSummary:
    case, rec = info.case, runner.record
    data = rec.data

    for step in foam.mesh_steps(case, info.plan):
        runner.run_step(step)
    mesh_log = case / "log.checkMesh"
    if mesh_log.is_file():
        try:
            summary = foam.check_mesh_summary(mesh_log)
            data["cells"].update({"total": summary.cells, "mesh_ok": summary.ok})
        except foam.StepError:
            pass
    for step in foam.solve_steps(case, info.plan, info.ranks):
        if step.name == "decomposePar":
            if not step.done(case):
                _match_decomposition(case, info.ranks, data)
            runner.run_step(step)

    if info.bodies:  # scene, obstacles, imports: once, before the solver competes for the cores
        t_setup = time.perf_counter()
        runner.book.geometry
        runner.bedwatch = BedWatch.for_case(case, runner.contact.float_margin_m, runner.say,
                                            friction=runner.contact.bed_friction)
        runner.between_s += time.perf_counter() - t_setup
    handlers = _install_handlers(stop)
    progress = None
    try:
        reached, name = latest_time(case, info.ranks)
        progress = Progress(info.end_time_s, reached, quiet, label=f"{info.solver} {case.name}", stream=stream)
        runner.progress = progress
        while reached < info.end_time_s - EPS_T:
            # a release closer than a tenth of a write interval is due now: a stop lands on a
            # written time name (rounded), and v1912 may not take a step over what remains
            due = [] if runner.bedwatch is not None else [
                b for b, t in info.holds if t <= reached + _MIN_SEGMENT_FRACTION * info.write_interval_s]
            for body in bodystate.release_holds(case, due):
                runner.say(f"t = {name} s: {body} released from the bed (the bore is deep enough to lift it)")
            states = runner.restore_bodies(name)
            if states and runner.contact.enabled:
                t_between = time.perf_counter()
                if previous is not None:  # resumed after a divergence: mend its cause if the book can
                    runner.book.after_divergence(previous, name, states)
                    previous = None
                events, resolved = runner.book.resolve_contacts(name, states, runner.stop_horizon_s)
                if resolved != states:
                    bodystate.prepare_restart(case, name, resolved, "contact")
                if events:
                    data["contacts"] = data.get("contacts", 0) + events
                states = resolved
                runner.between_s += time.perf_counter() - t_between
            if states and runner.bedwatch is not None:  # after the book: it may have put a body to rest
                freed, raised = runner.bedwatch.at_restart(name, states)
                if raised != states:
                    bodystate.prepare_restart(case, name, raised, "freed")
                for body in freed:
                    data.setdefault("freed", []).append({"body": body, "time_s": float(name)})
                rec.save()
            seg = runner.solve_segment(reached, name, progress)
            if seg.diagnosis is not None or (seg.returncode not in (0, None) and
                                             (seg.parser.fpe or seg.returncode == 136)):
                _fail_diverged(runner, seg, reached)
            if seg.returncode != 0 and seg.reason not in STOPPED_REASONS:
                text = seg.log.read_text(errors="replace")
                err = foam.StepError(info.solver, foam.failure_reason(text), seg.log, seg.returncode)
                data["status"], data["error"] = "failed", str(err)
                rec.save()
                raise err
            new_reached, new_name = latest_time(case, info.ranks)
            if seg.reason in STOPPED_REASONS and new_reached < info.end_time_s - EPS_T:
                data["status"] = "interrupted"
                rec.save()
                raise RunInterrupted(case, stop.signum, new_name if new_reached > 0 else None,
                                     clean=seg.reason == "interrupt" and seg.returncode == 0,
                                     before_first_step=seg.reason == "unstarted")
            if new_reached <= reached + EPS_T:
                if not seg.steps and info.end_time_s - reached < _MIN_SEGMENT_FRACTION * runner.write_interval_s:
                    # v1912's half-step rule: what remains of the end time is less than a step
                    break
                raise RunError(f"the solver ended without writing beyond t = {name} s; see {seg.log}")
            reached, name = new_reached, new_name
    finally:
        if progress is not None:
            progress.close()
        runner.progress = None
        _restore_handlers(handlers)

    if info.bodies:
        _assert_outside(info, case, name, runner)
    if info.ranks > 1 and reconstruct != "none":
        step = foam.Step("reconstructPar", ("reconstructPar",), "gather the time directories")
        extra = ["-latestTime"] if reconstruct == "latest" else []
        runner.run_step(step, 1, extra + ["-newTimes"])
    data["status"] = "finished"
    data["reached_time_s"] = reached
    data["finished"] = _now()
    solver_wall = sum(s["wall_s"] for s in data["segments"])
    cpu = sum(s.get("runner_cpu_s", 0.0) for s in data["segments"])
    data.setdefault("runner", {}).update({"solver_wall_s": round(solver_wall, 3), "cpu_s": round(cpu, 3),
                                          "between_segments_s": round(runner.between_s, 3),
                                          "overhead_fraction": round(cpu / solver_wall, 5) if solver_wall else 0.0})
    rec.save()
    return _summary(info, data, False, reached, time.perf_counter() - wall0)


def _original_controls(info: CaseInfo) -> CaseInfo:
    """The case's own endTime/writeInterval: a runner that died during a segment left the
    segment's values in controlDict (run.json says which); otherwise controlDict's (a user
    may have changed endTime to extend a run)."""
    from dataclasses import replace

    path = info.case / RUN_JSON
    if not path.is_file():
        return info
    data = json.loads(path.read_text())
    seg, own = data.get("segment_control"), data.get("control")
    if seg and own and math.isclose(seg["endTime"], info.end_time_s) and math.isclose(
            seg["writeInterval"], info.write_interval_s):
        _set_control(info.case, stopAt="endTime", endTime=own["endTime"], writeInterval=own["writeInterval"])
        return replace(info, end_time_s=float(own["endTime"]), write_interval_s=float(own["writeInterval"]))
    return info


def _summary(info: CaseInfo, data: dict, already: bool, reached: float, wall: float) -> RunSummary:
    segs = data.get("segments", [])
    solver_wall = sum(s["wall_s"] for s in segs)
    cpu = sum(s.get("runner_cpu_s", 0.0) for s in segs)
    return RunSummary(
        case=info.case, status=data.get("status", "unknown"), already_finished=already, end_time_s=info.end_time_s,
        reached_time_s=reached, time_steps=int(data.get("time_steps", 0)), segments=len(segs),
        contacts=int(data.get("contacts", 0)), wall_s=wall, solver_wall_s=solver_wall, runner_cpu_s=cpu,
        overhead_fraction=cpu / solver_wall if solver_wall else 0.0, run_json=info.case / RUN_JSON)


def _check_decomposition(case: Path, ranks: int) -> None:
    procs = processor_dirs(case)
    if ranks > 1 and procs and len(procs) != ranks:
        raise RunError(f"{case} is decomposed for {len(procs)} ranks, not {ranks}: run with --np {len(procs)} "
                       f"(or delete the processor* directories to start again)")
    if ranks == 1 and procs:
        raise RunError(f"{case} is decomposed for {len(procs)} ranks: run with --np {len(procs)}")


def _match_decomposition(case: Path, ranks: int, data: dict) -> None:
    """decomposeParDict for `ranks` when --np differs from the plan (split along x, noted in run.json)."""
    from PyFoam.RunDictionary.ParsedParameterFile import ParsedParameterFile

    path = case / "system" / "decomposeParDict"
    parsed = ParsedParameterFile(str(path))
    if int(parsed["numberOfSubdomains"]) == ranks:
        return
    planned = parsed["numberOfSubdomains"]
    parsed["numberOfSubdomains"] = ranks
    coeffs = parsed["coeffs"] if "coeffs" in parsed else parsed["hierarchicalCoeffs"]
    coeffs["n"] = f"({ranks} 1 1)"
    bodystate.write_dictionary(parsed, path)
    data["decomposition_note"] = (f"--np {ranks} instead of the planned {planned}: hierarchical ({ranks} 1 1); "
                                  "decomposePar still keeps each body mesh on one rank (preserveFaceZones), at some cost in balance")


def _slowest_step_s(arrivals: list[tuple[float, int]]) -> float | None:
    """The longest wall time per step between the runner's log reads ((wall clock, steps so
    far) pairs); None before two reads with steps."""
    gaps = [(b[0] - a[0]) / max(1, b[1] - a[1]) for a, b in zip(arrivals, arrivals[1:])]
    return max(gaps) if gaps else None


def _fail_diverged(runner: _Runner, seg: _SegmentResult, start_value: float) -> None:
    info, case, data = runner.info, runner.case, runner.record.data
    diag = seg.diagnosis
    if diag is None:  # the solver died of a floating point exception itself
        t = seg.parser.current_time_s
        diag = Diagnosis("fpe", "floating point exception (sigFpe) in the solver", t, t)
    if diag.since_s is not None:
        _remove_times_from(case, info.ranks, diag.since_s, start_value)
    _, good = latest_time(case, info.ranks)
    data["status"] = "stalled" if diag.kind == "stall" else "diverged"
    data["diagnosis"] = {"kind": diag.kind, "cause": diag.cause, "time_s": diag.time_s, "last_good_time": good,
                         "log": seg.log.name}
    if diag.body is not None:
        data["diagnosis"].update(body=diag.body, velocity_m_s=list(diag.velocity_m_s or ()))
    runner.record.save()
    raise DivergenceError(diag.kind, diag.cause, diag.time_s, good, seg.log)


def _assert_outside(info: CaseInfo, case: Path, name: str, runner: _Runner) -> None:
    """A finished run must not leave a body inside the column, a wall or another body."""
    states = _states_in_logs(case, info.solver, info.body_names, name)
    if states is None:
        return
    inside = [c for c in runner.book.geometry.contacts(states, 0.0, bed=False) if c.distance_m < 0]
    if inside:
        c = inside[0]
        raise ContactError(f"{c.body} ends the run {-c.distance_m * 1000:.3g} mm inside {c.other} at t = {name} s")


def _install_handlers(stop: _StopFlag):
    if threading.current_thread() is not threading.main_thread():
        return None
    return {sig: signal.signal(sig, stop.handler) for sig in (signal.SIGINT, signal.SIGTERM)}


def _restore_handlers(handlers) -> None:
    if handlers:
        for sig, old in handlers.items():
            signal.signal(sig, old)
