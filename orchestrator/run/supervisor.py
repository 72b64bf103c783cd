"""The supervisor of one run: its steps, its solver segments and what it records of them.

`Supervisor` holds what lives as long as a run: the case (`CaseInfo`), the divergence
limits with the case's defaults filled in, run.json (`RunRecord`), the contact book, the
bed watch, the segment watch and its pacing. For each segment it sets controlDict (the
segment's end and write interval, dated back past the modification skew), rotates the
solver log, gives every body its state at the restart time (`restore_bodies`: v1912 keeps
only the first body's), runs the segment and records it (run.json, bodies.csv). The
order of the segments, and what happens between them, is the runner's
(`orchestrator.run.runner`).
"""

from __future__ import annotations

import sys
from pathlib import Path
from dataclasses import asdict, replace
from typing import Callable, Sequence

from orchestrator.case import bodystate, foam
from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import EPS_T
from orchestrator.case.outputs import WATER_BALANCE_TOLERANCE
from orchestrator.run import held, openfoam
from orchestrator.run.bedwatch import BedWatch
from orchestrator.run.bodypoints import BodyPoints
from orchestrator.run.case_info import CaseInfo
from orchestrator.run.contact_book import ContactBook, ContactSettings
from orchestrator.run.control import TIME_PRECISION, set_control, significant_digits
from orchestrator.run.errors import RunError
from orchestrator.run.monitor import DivergenceLimits, Progress, StepRecord
from orchestrator.run.run_json import (
    RunRecord,
    append_track,
    check_against_state_file,
    now,
    states_in_logs,
    with_accelerations,
)
from orchestrator.run.segments import Pacing, SegmentResult, SegmentWatch, StopFlag
from orchestrator.run.times import MIN_SEGMENT_FRACTION, segment_span

__all__ = ["Supervisor", "case_limits"]


def case_limits(limits: DivergenceLimits, info: CaseInfo) -> DivergenceLimits:
    """`limits` with the case's defaults where unset: a minimum deltaT of 1e-3 of the planned one,
    a body-speed limit of three velocity scales, the plan's stall and water-balance limits."""
    defaults = {}
    if limits.min_delta_t_s is None:
        defaults["min_delta_t_s"] = 1e-3 * info.delta_t_s
    if limits.max_body_speed_m_s is None:
        defaults["max_body_speed_m_s"] = 3.0 * info.velocity_scale_m_s
    if limits.stall_s is None and info.stall_limit_s is not None:
        defaults["stall_s"] = info.stall_limit_s
    if limits.water_balance is None:
        defaults["water_balance"] = info.water_balance_limit or WATER_BALANCE_TOLERANCE
    return DivergenceLimits(**{**asdict(limits), **defaults})


class Supervisor:
    """Drives one run: the steps, the solver segments, run.json and the body tracks; its
    `book` (ContactBook) keeps the contacts, its `watch` (SegmentWatch) runs the segments."""

    def __init__(self, info: CaseInfo, quiet: bool, contact: ContactSettings, limits: DivergenceLimits,
                 stop: StopFlag, poll_interval_s: float, stream, on_step: Callable[[StepRecord], None] | None,
                 record: RunRecord | None = None):
        self.info = info
        self.case = info.case
        self.quiet = quiet
        self.contact = contact
        self.limits = case_limits(limits, info)
        self.stop = stop
        self.end_time_s = info.end_time_s
        self.write_interval_s = info.write_interval_s
        self.stream = stream
        self.record = record if record is not None else RunRecord(self.case)
        self.book = ContactBook(info, contact, self.record.data, self.say)
        self.pacing = Pacing(poll_interval_s, info.delta_t_s)
        self.watch = SegmentWatch(info, self.limits, stop, contact, self.book, self.pacing, on_step)
        self.progress: Progress | None = None
        self.last_steps: list[StepRecord] = []
        #: the bodies' states the next segment starts from (set by the runner at a restart)
        self.start_states: list[BodyState] = []
        #: wall time spent between segments (scene and obstacles, contacts): the runner's cost
        self.between_s = 0.0
        #: the body meshes' points, found at the first restart that has bodies (BodyPoints; False:
        #: the case's meshes do not show them, and restarts leave the points where the solver wrote them)
        self.body_points: BodyPoints | bool | None = None

    @property
    def bedwatch(self) -> BedWatch | None:
        """Bodies on the bed: freed on the measured water depth, their bed friction (set by the runner)."""
        return self.watch.bedwatch

    @bedwatch.setter
    def bedwatch(self, value: BedWatch | None) -> None:
        self.watch.bedwatch = value

    @property
    def stop_horizon_s(self) -> float:
        """How far (simulated s) the solver may run on after a stop request (`Pacing.stop_horizon_s`)."""
        return self.pacing.stop_horizon_s

    def say(self, message: str) -> None:
        if self.quiet:
            return
        if self.progress is not None:
            self.progress.write(message)  # above the bar, not through it
        else:
            print(message, file=self.stream or sys.stderr, flush=True)

    def run_step(self, step: foam.Step, np_: int = 1, extra: Sequence[str] = ()) -> openfoam.StepResult:
        """Run one mesh or utility step (skipped when its outputs exist), recorded in run.json."""
        start = now()
        argv = list(step.argv) + list(extra)
        command = foam.parallel_argv(argv, np_)  # what run.json names, whether the step succeeds or not
        try:
            result = openfoam.run_step(step.name, argv, self.case, np=np_, done=step.done)
        except openfoam.StepError as exc:
            self.record.step(step.name, command, start, 0.0, exc.returncode, False, exc.log_path)
            self.record.data["status"] = "failed"
            self.record.data["error"] = str(exc)
            self.record.save()
            raise
        self.record.step(step.name, command, start, result.wall_s, result.returncode, result.skipped,
                         result.log_path)
        return result

    # ---- the bodies at a restart
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
            before = held.recorded_before(self.case, start_name) if states is None else None
            if before is not None and held.solvers_held(self.case):
                # written while every body was held still (a run resumed after a stop): no solver
                # reported them, and they have not moved since the restart that held them
                states = [held.still_state(replace(b, time_s=float(start_name))) for b in before[0]]
                source = f"held since t = {before[1]} s"
            if states is None:
                raise RunError(f"cannot restore the bodies' states at t = {start_name} s: no solver log reports "
                               f"them (v1912 keeps only the first body's state); restart from an earlier time "
                               f"by deleting the later time directories")
            check_against_state_file(self.case, start_name, states)
        bodystate.prepare_restart(self.case, start_name, states, source)
        return states

    def _reported_states(self, time_name: str) -> list[BodyState] | None:
        steps = self.last_steps
        for i in range(len(steps) - 1, -1, -1):
            if steps[i].time_name == time_name and len(steps[i].bodies) == len(self.info.bodies):
                return with_accelerations(steps[i], steps[i - 1] if i > 0 else None)
        return states_in_logs(self.case, self.info.solver, self.info.body_names, time_name)

    # ---- segments
    def solve_segment(self, start_value: float, start_name: str, progress: Progress) -> SegmentResult:
        """Run the solver from `start_name` to the segment's end (see `segment_span`)."""
        # without the depth watch (no bodies), a body held on the bed would be let go at the
        # planner's release time: a temporary end (closer releases are due now, see run_case)
        soon = MIN_SEGMENT_FRACTION * self.write_interval_s
        holds = [] if self.bedwatch is not None else self.info.holds
        end = min([t for _, t in holds if start_value + soon < t < self.end_time_s - EPS_T]
                  + [self.end_time_s])
        if self.info.adjustable_time_step:
            seg_end, seg_interval = segment_span(start_value, end, self.write_interval_s)
        else:  # a fixed deltaT cannot land on the grid times: run to the end as the case says
            seg_end, seg_interval = end, self.write_interval_s
        max_dt = self.info.max_delta_t_s
        cap = None
        if self.start_states and self.contact.enabled and self.info.adjustable_time_step:
            cap = self.book.step_cap_s(self.start_states, self.pacing.latency_steps, max_dt)
        self.record.data["segment_control"] = {"endTime": seg_end, "writeInterval": seg_interval, "maxDeltaT": max_dt}
        self.record.save()
        # v1912 may write a time with more digits than timePrecision (it raises the precision
        # to tell close times apart) and then, restarting, look for the shorter name
        set_control(self.case, backdate=True, stopAt="endTime", startFrom="latestTime",
                    endTime=seg_end, writeInterval=seg_interval, maxDeltaT=float(f"{cap or max_dt:.6g}"),
                    timePrecision=max(TIME_PRECISION, significant_digits(start_name)))
        try:
            seg = self.watch.run(self._rotate_log(), start_value, start_name, seg_end, progress)
            seg.max_delta_t_s = cap
            self._record_segment(seg, start_value)
            return seg
        finally:  # the case's own controls back, whatever happened
            set_control(self.case, stopAt="endTime", endTime=self.end_time_s, writeInterval=self.write_interval_s,
                        maxDeltaT=max_dt)
            self.record.data.pop("segment_control", None)
            self.record.save()

    def _rotate_log(self) -> Path:
        """log.<solver> for the new segment; an earlier segment's log is kept as log.<solver>.<k>."""
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

    def _record_segment(self, seg: SegmentResult, start_value: float) -> None:
        """The segment in run.json, its steps in bodies.csv; the last deltaT for the next one."""
        data = self.record.data
        data["segments"].append(seg.entry())
        data["time_steps"] = data.get("time_steps", 0) + len(seg.steps)
        if seg.parser.build:
            data["openfoam"] = seg.parser.build
        self.record.save()
        if self.info.bodies and seg.steps:
            append_track(self.case, seg.steps, start_value)
        self.last_steps = seg.steps
        if seg.steps and seg.steps[-1].delta_t_s:
            self.pacing.delta_t_s = seg.steps[-1].delta_t_s
