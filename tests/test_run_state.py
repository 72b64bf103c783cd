"""run.json is read through RunState: its keys are spelled for readers in orchestrator/case/run_state.py.

The runner (orchestrator/run/) writes run.json, a one-way case's transport adds its entry
(orchestrator/transport/case_transport.py) and the pipeline drops that entry when the bodies are
to be carried again (orchestrator/pipeline.py); those writers take the raw mapping
(``CaseFolder.run_record()``). Every other module reads ``CaseFolder.run_state()``.
"""
from __future__ import annotations

import ast
import datetime as dt
import json
from pathlib import Path

import pytest

from orchestrator.case.folder import CaseFolder
from orchestrator.case.run_state import RunState
from tests.conftest import package_modules

ROOT = Path(__file__).resolve().parents[1]
#: The writers of run.json and the folder that owns the file: where the raw mapping may be taken.
WRITERS = ("orchestrator/run/", "orchestrator/case/folder.py", "orchestrator/transport/case_transport.py",
           "orchestrator/pipeline.py")


def raw_reads(source: str) -> list[int]:
    """Lines that call a method named ``run_record`` (the raw mapping of run.json)."""
    return [n.lineno for n in ast.walk(ast.parse(source))
            if isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute) and n.func.attr == "run_record"]


@pytest.mark.parametrize("module", package_modules(*WRITERS))
def test_a_reader_takes_run_json_as_a_run_state(module):
    assert not raw_reads((ROOT / module).read_text()), f"{module}: take CaseFolder.run_state(), not run_record()"


def test_the_scan_sees_a_raw_read():
    assert raw_reads("run = CaseFolder(case).run_record() or {}\nx = run.get('status')\n") == [1]
    assert not raw_reads("run = CaseFolder(case).run_state()\nx = run.status\n")


def _record(**changes) -> dict:
    seg = {"start": "2026-12-04T10:00:05+00:00", "wall_s": 12.5, "end_time": 0.5, "log": "log.interFoam",
           "exit_status": 0}
    data = {"status": "diverged", "error": "the solver diverged", "ranks": 2,
            "diagnosis": {"cause": "Courant number 40", "time_s": 0.5},
            "steps": [{"name": "blockMesh", "start": "2026-12-04T10:00:00+00:00", "wall_s": 1.5,
                       "log": "log.blockMesh", "exit_status": 0},
                      {"name": "setFields", "start": "2026-12-04T10:00:02+00:00", "wall_s": 0.5,
                       "log": "log.setFields", "exit_status": 1}],
            "segments": [seg, {**seg, "start": "2026-12-04T11:00:00+00:00", "wall_s": 4.0, "log": "log.interFoam.1"}],
            "cells": {"planned": 1000, "total": 1012}, "time_steps": 321, "end_time_s": 2.0,
            "freed": [{"body": "debris1", "time_s": 0.8}], "transport_wall_s": 3.25}
    return {**data, **changes}


def test_a_run_json_reads_into_its_fields(tmp_path):
    (tmp_path / "run.json").write_text(json.dumps(_record()))
    run = CaseFolder(tmp_path).run_state()
    assert run.recorded and run.status == "diverged" and not run.finished
    assert (run.ranks, run.time_steps, run.end_time_s, run.transport_wall_s) == (2, 321, 2.0, 3.25)
    assert run.cells["total"] == 1012 and run.diagnosis["cause"] == "Courant number 40"
    assert run.freed[0]["body"] == "debris1" and run.transport is None
    assert run.logs() == ["log.blockMesh", "log.setFields", "log.interFoam", "log.interFoam.1"]
    assert run.logs(failed_only=True) == ["log.setFields"]
    assert run.solver_wall_s == pytest.approx(16.5)  # no runner account: the segments' sum
    begun = dt.datetime.fromisoformat("2026-12-04T10:30:00+00:00")
    assert run.wall_before_s(begun) == pytest.approx(1.5 + 0.5 + 12.5)


def test_the_runners_own_solver_time_is_taken_over_the_segments_sum():
    run = RunState.from_dict(_record(runner={"solver_wall_s": 15.0}, status="finished"))
    assert run.finished and run.solver_wall_s == 15.0


@pytest.mark.parametrize("text", [None, "[1, 2]", "{not json"])
def test_a_case_without_a_readable_run_json_reads_as_never_run(tmp_path, text):
    if text is not None:
        (tmp_path / "run.json").write_text(text)
    run = CaseFolder(tmp_path).run_state()
    assert not run.recorded and run.status is None and run.logs() == [] and run.solver_wall_s is None


def test_entries_of_the_wrong_kind_are_skipped_not_raised():
    run = RunState.from_dict(_record(segments="none", steps=[3, {"log": "log.checkMesh"}], ranks="two",
                                     cells=[], end_time_s=float("nan")))
    assert run.segments == () and run.logs() == ["log.checkMesh"]
    assert run.ranks is None and run.cells == {} and run.end_time_s is None
