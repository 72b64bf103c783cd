"""One solver segment, watched: start the solver, read its log, stop or kill it, report.

A segment runs the solver from the latest written time until its end time, a stop
request or a contact event. `SegmentWatch.run` starts the solver in its own process group
and polls its log (`monitor.LogTail`, `LogParser`): every new step goes to the health
watch, the progress bar and the caller's `on_step`; the water balance is checked every
`WATER_CHECK_S`. It asks the solver to stop (`control.request_write_now`) for a user's
stop request or a body the bed watch must free, and for a contact the contact book sees
coming either schedules the stop at the time the body reaches the gap
(`control.request_stop_at`) or, too close to schedule, requests `writeNow`. A solver that
does not act on a request is asked again, and killed after `STOP_KILL_TIMEOUT_S` (after
`STOP_SILENT_KILL_S` of silence for a user's stop); a diverged one at once.

`Pacing` is what the runner carries from one segment to the next: how often it reads the
log, and the stop latency (in time steps) it measured, which sets how far ahead it must
look for contacts.
"""

from __future__ import annotations

import math
import os
import resource
import shlex
import signal
import subprocess
import threading
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

from orchestrator.case import foam
from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import EPS_T
from orchestrator.case.outputs import read_water_balance
from orchestrator.run import openfoam
from orchestrator.run.bedwatch import BedWatch
from orchestrator.run.case_info import CaseInfo
from orchestrator.run.contact_book import ContactBook, ContactSettings
from orchestrator.run.contact_geometry import Contact
from orchestrator.run.control import request_stop_at, request_write_now, bump_control_mtime
from orchestrator.run.errors import RunError
from orchestrator.run.monitor import (
    Diagnosis,
    DivergenceLimits,
    HealthWatch,
    LogParser,
    LogTail,
    Progress,
    StepRecord,
    water_balance_diagnosis,
)
from orchestrator.run.run_json import now

__all__ = [
    "STOPPED_REASONS",
    "STOP_ACK_TIMEOUT_S",
    "STOP_KILL_TIMEOUT_S",
    "STOP_SILENT_KILL_S",
    "WATER_CHECK_S",
    "Pacing",
    "SegmentResult",
    "SegmentWatch",
    "StopFlag",
    "kill",
]

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
#: SegmentResult.reason of a segment the user stopped: written on request, killed (a second
#: Ctrl-C or no answer), or stopped before its first time step
STOPPED_REASONS = ("interrupt", "killed", "unstarted")


class StopFlag:
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


@dataclass
class Pacing:
    """How often the runner reads the log (s; faster near an obstacle) and the stop latency it
    measured (time steps), with the last deltaT: they carry over from segment to segment."""

    poll_s: float
    delta_t_s: float
    latency_steps: int = 4
    poll_now_s: float | None = None
    fast_poll_s: float | None = None

    def __post_init__(self) -> None:
        if self.poll_now_s is None:
            self.poll_now_s = self.poll_s
        if self.fast_poll_s is None:
            self.fast_poll_s = min(self.poll_s, 0.02)

    @property
    def stop_horizon_s(self) -> float:
        """How far (simulated s) the solver may run on after a stop request: the last
        deltaT times the stop latency measured in the last segment."""
        return self.delta_t_s * self.latency_steps


@dataclass
class SegmentResult:
    start_name: str
    reason: str  # end, contact, bed, interrupt, killed, unstarted (STOPPED_REASONS), diverged
    returncode: int | None
    steps: list[StepRecord]
    parser: LogParser
    log: Path
    wall_s: float
    runner_cpu_s: float
    diagnosis: Diagnosis | None = None
    contacts: list[Contact] = field(default_factory=list)
    started: str = ""
    command: str = ""
    stopped_for_bed: str | None = None
    #: the runner's lower maxDeltaT for this segment (ContactBook.step_cap_s), None: the case's
    max_delta_t_s: float | None = None

    def entry(self) -> dict[str, Any]:
        """The segment as run.json's `segments` lists it."""
        steps = self.steps
        seg = {"start": self.started, "start_time": self.start_name,
               "end_time": steps[-1].time_name if steps else self.start_name, "time_steps": len(steps),
               "wall_s": round(self.wall_s, 3), "exit_status": self.returncode, "stop_reason": self.reason,
               "command": self.command, "log": self.log.name, "runner_cpu_s": round(self.runner_cpu_s, 3)}
        if self.contacts:
            seg["stopped_for"] = [{"body": c.body, "other": c.other, "gap_m": round(c.distance_m, 6),
                                   "closing_m_s": round(c.approach_m_s, 4)} for c in self.contacts]
        if self.max_delta_t_s is not None:
            seg["max_delta_t_s"] = float(f"{self.max_delta_t_s:.6g}")
        if self.stopped_for_bed is not None:
            seg["stopped_for_bed"] = self.stopped_for_bed
        if self.diagnosis is not None:
            seg["diagnosis"] = self.diagnosis.cause
        return seg


def cpu_s() -> float:
    """CPU seconds this process has used (user and system)."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _set_parent_death_signal() -> None:  # pragma: no cover - runs in the child
    """Linux: the solver gets SIGTERM if the runner dies, instead of running on orphaned."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except Exception:
        pass


def kill(proc: subprocess.Popen) -> None:
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


def slowest_step_s(arrivals: list[tuple[float, int]]) -> float | None:
    """The longest wall time per step between the runner's log reads ((wall clock, steps so
    far) pairs); None before two reads with steps."""
    gaps = [(b[0] - a[0]) / max(1, b[1] - a[1]) for a, b in zip(arrivals, arrivals[1:])]
    return max(gaps) if gaps else None


def silent_kill_s(arrivals: list[tuple[float, int]]) -> float:
    """How long a solver may stay silent after a stop request before it is killed."""
    return max(STOP_SILENT_KILL_S, 20.0 * (slowest_step_s(arrivals) or 0.0))


@dataclass(eq=False)
class SegmentWatch:
    """Runs and watches solver segments of one case (see the module notes).

    The watch asks `book` which contacts are ahead and `bedwatch` (when bodies rest on the
    bed) whether one must be freed; it reports every step to `progress` and `on_step`.
    """

    info: CaseInfo
    limits: DivergenceLimits
    stop: StopFlag
    contact: ContactSettings
    book: ContactBook
    pacing: Pacing
    on_step: Callable[[StepRecord], None] | None
    bedwatch: BedWatch | None = field(default=None, init=False)
    #: the bodies' states while every body is held still and their motion solvers are set
    #: aside (`held.hold_solvers`): the log then reports no body, and each step gets these
    held: tuple[BodyState, ...] | None = field(default=None, init=False)

    def __post_init__(self):
        self.case = self.info.case

    def run(self, log: Path, start_value: float, start_name: str, seg_end: float,
            progress: Progress) -> SegmentResult:
        """Run the solver from `start_name` (controlDict set for the segment) to its end."""
        return _Segment(self, log, start_value, start_name, seg_end, progress).run()


class _Segment:
    """The state of one running segment: the solver process, its log, and the requests made."""

    def __init__(self, watch: SegmentWatch, log: Path, start_value: float, start_name: str, seg_end: float,
                 progress: Progress):
        info = watch.info
        self.w = watch
        self.info = info
        self.pacing = watch.pacing
        self.log = log
        self.start_value = start_value
        self.start_name = start_name
        self.seg_end = seg_end
        self.progress = progress
        self.argv = foam.parallel_argv([info.solver], info.ranks)
        self.parser = LogParser(info.body_names)
        self.health = HealthWatch(watch.limits, info.max_courant, info.domain_m if info.bodies else None)
        self.tail = LogTail(log)
        self.steps: list[StepRecord] = []
        self.arrivals: list[tuple[float, int]] = []
        self.stop_reason: str | None = None
        self.diag: Diagnosis | None = None
        self.pending: list[Contact] = []
        self.bed_why: str | None = None
        self.killed = False
        self.proc: subprocess.Popen | None = None
        self.rereads_at_request = 0
        self.requested_at: float | None = None  # wall clock of the last controlDict request
        self.last_bump = 0.0
        self.scheduled: float | None = None  # simulated time of a scheduled contact stop
        self.last_output = 0.0  # wall clock of the last log line (the stall watch)
        self.water_checked = 0.0  # wall clock of the last water-balance check
        self.last_line = ""

    # ---- the loop
    def run(self) -> SegmentResult:
        started = now()
        t0, cpu0 = time.perf_counter(), cpu_s()
        self._start()
        self.last_output = self.water_checked = time.perf_counter()
        try:
            while True:
                rc = self.proc.poll()
                new, now_ = self._read(rc)
                self._diagnose(rc, now_)
                if rc is not None:
                    break
                if self.diag is not None and not self.killed:
                    self._kill()
                    continue
                self._ask_to_stop(new)
                if self.requested_at is not None:
                    self._follow_up(now_)
                time.sleep(self.pacing.poll_now_s)
        except BaseException:
            if self.proc.poll() is None:
                kill(self.proc)
            raise
        return self._result(started, time.perf_counter() - t0, cpu_s() - cpu0)

    def _start(self) -> None:
        env = openfoam.foam_env()
        env["PWD"] = str(self.w.case)
        with open(self.log, "w") as out:
            try:
                self.proc = subprocess.Popen(self.argv, cwd=self.w.case, stdout=out, stderr=subprocess.STDOUT,
                                             env=env, start_new_session=True,
                                             preexec_fn=_set_parent_death_signal)
            except FileNotFoundError:
                raise RunError(f"{self.argv[0]!r} not found: is OpenFOAM v1912 installed (make openfoam)?") from None

    def _kill(self) -> None:
        kill(self.proc)
        self.killed = True

    def _read(self, rc: int | None) -> tuple[list[StepRecord], float]:
        """The log's new lines: new steps to the health watch, the progress bar and `on_step`."""
        lines = self.tail.read_lines() if rc is None else self.tail.flush()
        now_ = time.perf_counter()
        if lines:
            self.last_output = now_
            self.last_line = next((ln.strip() for ln in reversed(lines) if ln.strip()), self.last_line)
        elif self.diag is None and rc is None and not self.killed:
            self.diag = self._stall(now_ - self.last_output)
        new = self.parser.feed(lines)
        if new and self.w.held:
            new = [s if s.bodies else replace(s, bodies=tuple(replace(b, time_s=s.time_s) for b in self.w.held))
                   for s in new]
        if new:
            self.steps.extend(new)
            self.arrivals.append((time.perf_counter(), len(self.steps)))
            del self.arrivals[:-8]
            if self.w.on_step is not None:
                for s in new:
                    self.w.on_step(s)
            if self.diag is None:
                for s in new:
                    self.diag = self.health.check_step(s)
                    if self.diag:
                        break
            self.progress.update(self.steps[-1], note="stopping" if self.stop_reason else "")
        return new, now_

    def _diagnose(self, rc: int | None, now_: float) -> None:
        """The log's own symptoms (before the first step too), and the water balance."""
        if self.diag is None:
            self.diag = self.health.check_parser(self.parser)
            if self.diag is not None and self.diag.time_s is None:  # before the first step: the start time
                self.diag = replace(self.diag, time_s=self.start_value)
        if self.diag is None and self.steps and (rc is not None or now_ - self.water_checked >= WATER_CHECK_S):
            self.water_checked = now_
            self.diag = self._water_check()

    # ---- stop requests
    def _request_write_now(self, reason: str) -> None:
        self.stop_reason, self.requested_at = reason, time.perf_counter()
        self.rereads_at_request = self.parser.rereads
        request_write_now(self.w.case)

    def _ask_to_stop(self, new: list[StepRecord]) -> None:
        """A user's stop request, a contact ahead, or a body the bed watch must free."""
        stop_requested = self.stop_reason is None and self.w.stop.requested
        if stop_requested and not self.steps:
            # no time step taken yet (reading the mesh, overset addressing: minutes with
            # several bodies): nothing to write and writeNow is only read between steps
            self.stop_reason = "unstarted"
            self._kill()
            self.progress.write("stop requested before the solver's first time step: stopped it at once "
                                "(nothing to write)")
        elif stop_requested:
            self._request_write_now("interrupt")
            self.progress.write("stop requested: the solver will write the current time step and stop "
                                "(press Ctrl-C again to kill it without writing)")
        elif self.stop_reason is None and new and self.w.contact.enabled and self.info.bodies:
            self._contact_stop()
        if self.stop_reason is None and new and self.w.bedwatch is not None and self.steps[-1].bodies:
            # a body on the bed the measured water can carry, or whose friction needs resizing
            why = self.w.bedwatch.why_stop(self.steps[-1].bodies, self.steps[-1].time_s)
            if why is not None:
                self.bed_why = why
                self._request_write_now("bed")

    def _contact_stop(self) -> None:
        """Schedule the stop at the time a body reaches the gap, or request writeNow when too close."""
        info, gap_m = self.info, self.w.contact.gap_m
        ahead = self._contacts_ahead()
        if not ahead:
            return
        contact, soonest = min(ahead, key=lambda x: x[1])
        now_s, dt = self.steps[-1].time_s, self.steps[-1].delta_t_s or info.delta_t_s
        margin = dt * (self.pacing.latency_steps + 1)  # the solver may get this far before it reads
        t_stop = float(f"{now_s + soonest:.8g}")
        late = self.scheduled is None or max(contact.approach_m_s, 0.0) * (self.scheduled - t_stop) > 0.5 * gap_m
        if soonest <= margin and (late or not info.adjustable_time_step):
            # too close to schedule, and nothing scheduled in time: stop at the
            # next step the solver can (writeNow)
            self.pending = [c for c, _ in ahead]
            self._request_write_now("contact")
        elif (soonest > margin and info.adjustable_time_step and t_stop < self.seg_end - EPS_T
              and (self.scheduled is None or t_stop < self.scheduled - EPS_T)):
            # stop where the body reaches the gap: the solver lands on that time and
            # writes it, whatever the runner's latency
            self.scheduled, self.requested_at = t_stop, time.perf_counter()
            self.rereads_at_request = self.parser.rereads
            self.pending = [c for c, _ in ahead]
            request_stop_at(self.w.case, t_stop, self.start_value)

    def _follow_up(self, now_: float) -> None:
        """A request made: a second Ctrl-C kills; no answer: ask again, then kill."""
        if self.stop_reason == "contact" and self.w.stop.requested:
            self.stop_reason = "interrupt"  # the write is requested already
        if self.stop_reason == "interrupt" and self.w.stop.count > 1 and not self.killed:
            self._kill()
        waited = time.perf_counter() - self.requested_at
        if self.parser.rereads <= self.rereads_at_request and waited - self.last_bump > STOP_ACK_TIMEOUT_S:
            bump_control_mtime(self.w.case)  # not seen yet: date it later again
            self.last_bump = waited
        if self.stop_reason is not None and waited > STOP_KILL_TIMEOUT_S and not self.killed:
            self._kill()
        elif (self.stop_reason == "interrupt" and not self.killed
              and now_ - max(self.last_output, self.requested_at) > silent_kill_s(self.arrivals)):
            self._kill()
            self.progress.write(f"the solver wrote nothing for {now_ - self.last_output:.0f} s after the stop "
                                "request (stuck inside a time step): killed it; the run resumes from "
                                "the last written time")

    # ---- checks
    def _water_check(self) -> Diagnosis | None:
        """The water-balance stop (DivergenceLimits.water_balance) on what the solver wrote so far."""
        try:
            balance = read_water_balance(self.w.case)
        except (OSError, ValueError):  # a line being written: next time
            return None
        return water_balance_diagnosis(balance, self.w.limits.water_balance)

    def _stall(self, silent_s: float) -> Diagnosis | None:
        """A stall diagnosis when the solver has written nothing for longer than the limit."""
        slowest_s = slowest_step_s(self.arrivals)
        limit = self.w.limits.stall_limit_s(slowest_s)
        if silent_s <= limit:
            return None
        t = self.steps[-1].time_s if self.steps else self.start_value
        slowest = f"; its slowest time step so far took {slowest_s:.3g} s" if slowest_s is not None else ""
        return Diagnosis("stall", f"the solver stalled: nothing written to its log for {silent_s:.0f} s of wall "
                                  f"time{slowest} (last line: {self.last_line[:120]!r})", t, None)

    def _contacts_ahead(self) -> list[tuple[Contact, float]]:
        """The book's contacts ahead of the last reported step (`ContactBook.contacts_ahead`),
        given the stop latency measured now.

        Stop latency in time steps: the runner sees a step up to one poll interval after
        the solver printed it (the solver may be that many steps further), and the solver
        acts on a controlDict request at the start of its next step. Near an obstacle (a
        contact ahead) the runner polls faster (20 ms) to keep it short.
        """
        last = self.steps[-1]
        if not last.bodies:
            return []
        pacing, arrivals = self.pacing, self.arrivals
        wall_per_step = None
        if len(arrivals) >= 2:
            (w0, n0), (w1, n1) = arrivals[0], arrivals[-1]
            if n1 > n0:
                wall_per_step = (w1 - w0) / (n1 - n0)
        pacing.latency_steps = 2 + (math.ceil((pacing.poll_now_s + 0.05) / wall_per_step) if wall_per_step else 3)
        ahead = self.w.book.contacts_ahead(last, pacing.latency_steps)
        pacing.poll_now_s = pacing.fast_poll_s if ahead else pacing.poll_s
        return ahead

    # ---- the end
    def _result(self, started: str, wall: float, cpu: float) -> SegmentResult:
        steps, stop_reason = self.steps, self.stop_reason
        if (stop_reason is None and self.scheduled is not None and steps
                and abs(steps[-1].time_s - self.scheduled) < 1e-9 + 1e-7 * self.scheduled):
            stop_reason = "contact"
        reason = "diverged" if self.diag else (stop_reason or "end")
        if self.killed and not self.diag and stop_reason == "interrupt":
            reason = "killed"
        return SegmentResult(self.start_name, reason, self.proc.returncode, steps, self.parser, self.log, wall, cpu,
                             self.diag, self.pending, started=started, command=shlex.join(self.argv),
                             stopped_for_bed=self.bed_why)
