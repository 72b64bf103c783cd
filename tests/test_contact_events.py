"""A case's contact-event files (orchestrator.contact.events): contacts.json and the runner's
impact table, against the files a real tiny run wrote (tests/data/post/tiny-1debris)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from orchestrator.contact.events import (
    IMPACT_EVENTS_CSV,
    append_impact_event,
    forget_impact_events_after,
    impact_events_path,
    read_events,
    write_events,
)

RUN = Path(__file__).resolve().parent / "data" / "post" / "tiny-1debris"


def _event() -> dict:
    (event,) = read_events(RUN)
    return event


def test_the_runners_table_row_is_the_one_the_run_wrote(tmp_path):
    """The run's impact event appended to a new case gives the run's impact_events.csv byte for byte."""
    append_impact_event(tmp_path, _event())
    assert impact_events_path(tmp_path) == tmp_path / IMPACT_EVENTS_CSV
    assert (tmp_path / IMPACT_EVENTS_CSV).read_text() == (RUN / IMPACT_EVENTS_CSV).read_text()
    assert not (tmp_path / "impacts.csv").exists()


def test_a_run_folder_with_the_old_table_name_keeps_its_table(tmp_path):
    """A folder whose runner table is the case root's impacts.csv: a later impact is appended
    there, a restart's forgetting trims it, and no second table appears."""
    shutil.copy(RUN / IMPACT_EVENTS_CSV, tmp_path / "impacts.csv")
    later = {**_event(), "event": 2, "time_s": 0.05}
    append_impact_event(tmp_path, later)
    rows = (tmp_path / "impacts.csv").read_text().splitlines()
    assert len(rows) == 3 and rows[2].startswith("2,0.05,debris1,column")
    assert not (tmp_path / IMPACT_EVENTS_CSV).exists()
    forget_impact_events_after(tmp_path, 0.04)
    assert (tmp_path / "impacts.csv").read_text() == (RUN / IMPACT_EVENTS_CSV).read_text()


def test_the_new_name_wins_when_both_tables_exist(tmp_path):
    for name in (IMPACT_EVENTS_CSV, "impacts.csv"):
        shutil.copy(RUN / IMPACT_EVENTS_CSV, tmp_path / name)
    append_impact_event(tmp_path, {**_event(), "event": 2, "time_s": 0.05})
    assert len((tmp_path / IMPACT_EVENTS_CSV).read_text().splitlines()) == 3
    assert (tmp_path / "impacts.csv").read_text() == (RUN / IMPACT_EVENTS_CSV).read_text()


def test_events_round_trip_and_a_case_without_a_list_has_none(tmp_path):
    assert read_events(tmp_path) == []
    write_events(tmp_path, [_event()])
    assert read_events(tmp_path) == json.loads((RUN / "contacts.json").read_text())
    (tmp_path / "contacts.json").write_text('{"event": 1}')
    assert read_events(tmp_path) == []
