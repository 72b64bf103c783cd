"""A contact stop the solver passes before it reads it (orchestrator/run/runner.py): v1912 ends the
run within half a step of its endTime without writing; the runner runs the segment again from the
last written time, a bounded number of times, instead of failing the run."""

from __future__ import annotations

from pathlib import Path

from orchestrator.run.contact_geometry import Contact
from orchestrator.run.monitor import LogParser, StepRecord
from orchestrator.run.runner import MAX_MISSED_STOPS, missed_contact_stop, retries_left
from orchestrator.run.segments import SegmentResult

PAIR = Contact("debris2", "debris3", "body", 0.0036, (4.45, -0.04, 0.04), (0.0, 1.0, 0.0), 0.17)


def _segment(reason: str, returncode: int | None, contacts: list[Contact], steps: int = 3) -> SegmentResult:
    records = [StepRecord(k, 2.2205 + 0.003 * (k + 1), f"{2.2205 + 0.003 * (k + 1):.6g}", 0.003, 1.9, 0.4, None, None)
               for k in range(steps)]
    return SegmentResult("2.2205", reason, returncode, records, LogParser(), Path("log.overInterDyMFoam"), 88.0, 4.4,
                         contacts=contacts)


def test_only_a_solver_that_ended_by_itself_with_a_contact_stop_pending_missed_it():
    assert missed_contact_stop(_segment("end", 0, [PAIR]))
    assert not missed_contact_stop(_segment("end", 0, []))  # nothing pending: a plain end
    assert not missed_contact_stop(_segment("end", 1, [PAIR]))  # the solver failed
    assert not missed_contact_stop(_segment("contact", 0, [PAIR]))  # it landed on the stop
    assert not missed_contact_stop(_segment("interrupt", 0, [PAIR]))
    assert not missed_contact_stop(_segment("end", 0, [PAIR], steps=0))  # it never stepped


def test_a_written_time_is_run_again_a_bounded_number_of_times():
    misses: list[dict] = []
    for _ in range(MAX_MISSED_STOPS):
        assert retries_left(misses, "2.2205")
        misses.append({"from": "2.2205"})
    assert not retries_left(misses, "2.2205")
    assert retries_left(misses, "2.25")  # a later written time starts afresh
