"""The runner: segments, resume, stop, divergence, contact events, body states.

Geometry, segment spans, time directories and dictionary edits are tested without
OpenFOAM; the runner itself on real OpenFOAM v1912 (tests marked `openfoam`), on tiny
cases rendered from the scenes below (2.2 m flume segment, 4 cm cells, 4-5k cells,
2 ranks): a dam break without debris; one body started 2.5 cm from the column at
0.6 m/s towards it; the same with a second body drifting elsewhere; a body 1 mm from the
column in water flowing towards it, which the runner pins there.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from conftest import solvers_kept
from orchestrator.case import bodystate
from orchestrator.run import body_policy
from orchestrator.run import segments as run_module
from orchestrator.case.bodystate import BodyState
from orchestrator.core.errors import InputError
from orchestrator.run.contact_geometry import Geometry, resting_contact
from orchestrator.run.monitor import DivergenceLimits, parse_log
from orchestrator.pipeline import render_from_file
from orchestrator.run.runner import (
    ContactSettings,
    DivergenceError,
    RunInterrupted,
    latest_time,
    load_case_info,
    run_case,
    segment_span,
)

ROOT = Path(__file__).resolve().parent.parent

COLUMN = {"x_m": 1.2, "y_m": 0.0, "size_x_m": 0.1, "size_y_m": 0.1, "height_m": 0.3, "wall_thickness_m": 0.005,
          "youngs_modulus_Pa": 2.5e9, "density_kg_m3": 1200, "poisson_ratio": 0.375, "shear_coefficient": 0.5}
BOX = {"size_m": [0.15, 0.06, 0.06], "mass_kg": 0.236, "wall_thickness_m": 0.005, "placement": "floating"}


def scene(debris=(), end_time_s=0.2, wet_depth_m=0.03) -> dict:
    """A tiny dam break: 2.4 m flume (0.5 m reservoir, 0.16 m deep), 0.4 m wide, column at 1.2 m."""
    return {
        "name": "tiny",
        "flume": {"length_m": 2.4, "width_m": 0.4, "height_m": 0.3, "downstream_end": "closed"},
        "reservoir": {"length_m": 0.5, "depth_m": 0.16},
        "bed": {"wet_depth_m": wet_depth_m, "friction_factor": 0.0},
        "column": COLUMN,
        "debris": [dict(BOX, **d) for d in debris],
        "gauges": [{"name": "WG1", "x_m": 0.5, "y_m": 0.0}],
        # coarse body meshes (2 cells across) keep these runner tests cheap; the physics defaults differ
        "mesh": {"cell_size_m": 0.04, "coarsening_ratio": 1, "body_margin_cells": 1, "body_cells_across": 2},
        "run": {"end_time_s": end_time_s, "cores": 2, "write_interval_s": 0.05, "max_courant": 0.9},
        "outputs": {"probe_interval_s": None, "preview": False},
    }


def render(tmp_path: Path, name: str, data: dict) -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data))
    case = tmp_path / name
    render_from_file(path, case)
    return case


def set_velocities(case: Path, velocities: dict[str, tuple[float, float, float]]) -> None:
    """Start the bodies with these velocities (their t = 0 state in dynamicMeshDict)."""
    poses = {p.name: p for p in bodystate.read_mesh_poses(case)}
    bodystate.write_states(case, [poses[n].with_changes(velocity_m_s=v) for n, v in velocities.items()])


def force_rows(case: Path) -> dict[float, np.ndarray]:
    """columnForces force.dat of every segment: time -> (total, pressure, viscous) x, y, z."""
    rows = {}
    for path in sorted((case / "postProcessing" / "columnForces").glob("*/force.dat")):
        for line in path.read_text().splitlines():
            if line.startswith("#") or not line.strip():
                continue
            parts = line.replace("(", " ").replace(")", " ").split()
            rows[float(parts[0])] = np.array([float(v) for v in parts[1:]])
    return rows


def internal_field(path: Path) -> np.ndarray:
    text = path.read_text()
    body = text[text.index("internalField"):]
    n = body.index("(")
    return np.array(body[n + 1:body.index(")", n)].split(), dtype=float)


def steps_of(case: Path, solver: str, names=()):
    """Every log of the case in segment order: [(log name, steps)]."""
    logs = sorted(case.glob(f"log.{solver}.*"), key=lambda p: int(p.suffix[1:])) + [case / f"log.{solver}"]
    return [(p.name, parse_log(p, names)[0]) for p in logs]


# --------------------------------------------------------------------------- without OpenFOAM


@pytest.mark.parametrize("start, end, interval, expected", [
    (0.0, 3.0, 0.05, (3.0, 0.05)),       # on the grid to the end
    (0.16, 3.0, 0.05, (0.2, 0.04)),      # off the grid (a writeNow): back onto it first
    (0.2, 0.33, 0.05, (0.3, 0.05)),      # end off the grid: to its last grid time...
    (0.3, 0.33, 0.05, (0.33, 0.03)),     # ...then a last short segment, so the end is written
    (0.31, 0.33, 0.05, (0.33, 0.02)),
    (0.15000001, 0.2, 0.05, (0.2, 0.05)),
    (0.099771307, 3.5, 0.1, (0.2, 0.100228693)),  # just short of a grid time: v1912 would take no step
    (0.3497, 0.35, 0.05, (0.35, 0.0003)),          # ...unless that is the end time itself
])
def test_segment_span(start, end, interval, expected):
    assert segment_span(start, end, interval) == pytest.approx(expected)


@pytest.fixture(scope="module")
def body_case(tmp_path_factory) -> Path:
    """A rendered (not meshed) case with two bodies: render needs no OpenFOAM."""
    tmp = tmp_path_factory.mktemp("render")
    return render(tmp, "bodies", scene([{"name": "debris1", "centre_m": [1.05, 0.0]},
                                        {"name": "debris2", "centre_m": [0.7, 0.12], "yaw_deg": 30.0}],
                                       wet_depth_m=0.1))


def test_case_info_from_a_rendered_case(body_case):
    info = load_case_info(body_case)
    assert info.solver == "overInterDyMFoam" and info.ranks == 2
    assert info.body_names == ("debris1", "debris2")
    assert info.end_time_s == 0.2 and info.write_interval_s == 0.05 and info.adjustable_time_step
    assert info.body_sizes_m["debris2"] == (0.15, 0.06, 0.06)
    assert info.domain_m[1] == pytest.approx((-0.2, 0.2))
    assert load_case_info(body_case, np_override=1).ranks == 1


def _state(name, centre, velocity=(0.0, 0.0, 0.0), yaw_deg=0.0, omega=(0.0, 0.0, 0.0)):
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return BodyState(name, 0.1, tuple(centre), (c, -s, 0, s, c, 0, 0, 0, 1), tuple(velocity), tuple(omega))


def test_a_train_of_pressed_bodies_is_set_apart_at_one_restart(tmp_path):
    """Three bodies end to end, both pairs pressed together: one restart sets both pairs the gap
    apart, the train's momentum and centre kept, and leaves no pair to stop the solver at once.
    One contact per body per restart set the middle body into its other neighbour instead."""
    from orchestrator.run.contact_book import ContactBook

    case = render(tmp_path, "train", scene([{"name": f"debris{k}", "centre_m": [0.3 + 0.16 * k, 0.0]}
                                            for k in (1, 2, 3)], wet_depth_m=0.1))
    settings = ContactSettings()
    messages = []
    book = ContactBook(load_case_info(case), settings, {}, messages.append)

    def train(first_gap, second_gap):  # end to end along x, the rear body the fastest
        x2 = 0.5 + 0.15 + first_gap
        return [_state("debris1", (0.5, 0.0, 0.1), (0.9, 0.0, 0.0)), _state("debris2", (x2, 0.0, 0.1), (0.7, 0.0, 0.0)),
                _state("debris3", (x2 + 0.15 + second_gap, 0.0, 0.1), (0.5, 0.0, 0.0))]

    for k in range(1, 2 * settings.max_events + 3):  # the pairs close in turn, until both are pressed
        closer = (0.001, 0.004) if k % 2 else (0.004, 0.001)
        book.resolve_contacts(f"{0.1 + 0.001 * k:g}", train(*closer), 0.001)
    assert sum(m.count("presses") for m in messages) == 2
    train = train(0.001, 0.001)
    _, states = book.resolve_contacts("0.2", train, 0.001)
    gaps = sorted(c.distance_m for c in book.geometry.contacts(states, 0.02, bed=False) if c.kind == "body")
    assert gaps == pytest.approx([settings.gap_m] * 2, abs=0.1 * settings.gap_m)
    assert not book.contacts_now(states, 0.001)  # nothing stops the next segment at once
    u = [s.velocity_m_s[0] for s in states]
    # plastic: what closing motion is left is slower than an impact (0.9, 0.7, 0.5 m/s came in)
    assert max(u[0] - u[1], u[1] - u[2]) < settings.min_impact_speed_m_s, u
    assert sum(u) == pytest.approx(0.9 + 0.7 + 0.5, abs=1e-9)  # equal masses: momentum kept
    assert sum(s.centre_of_mass_m[0] for s in states) == pytest.approx(sum(s.centre_of_mass_m[0] for s in train),
                                                                       abs=1e-12)


def test_a_resumed_run_remembers_which_bodies_the_flow_presses_together(tmp_path):
    """A run resumed by a new process goes on as the uninterrupted one would: its contact book
    reads the pressed pairs and the recent contacts back from contacts.json. Two bodies pressed
    together before the stop stay plastic after it (no rebound), where a book that forgot them
    had impacts with restitution again, and the next restart sets them apart exactly as the
    book that never stopped does."""
    import shutil

    from orchestrator.run.contact_book import ContactBook

    case = render(tmp_path, "train", scene([{"name": f"debris{k}", "centre_m": [0.3 + 0.16 * k, 0.0]}
                                            for k in (1, 2)], wet_depth_m=0.1))
    settings = ContactSettings()
    messages = []
    running = ContactBook(load_case_info(case), settings, {}, messages.append)

    def pair(gap, closing):  # end to end along x, the rear body closing at impact speed
        return [_state("debris1", (0.5, 0.0, 0.1), (0.7 + closing, 0.0, 0.0)),
                _state("debris2", (0.5 + 0.15 + gap, 0.0, 0.1), (0.7, 0.0, 0.0))]

    k = 0
    while not any("presses" in m for m in messages):
        k += 1
        running.resolve_contacts(f"{0.1 + 0.001 * k:g}", pair(0.001, 0.02), 0.001)
    stopped = f"{0.1 + 0.001 * k:g}"
    resumed_case = tmp_path / "resumed"
    shutil.copytree(case, resumed_case)
    resumed = ContactBook(load_case_info(resumed_case), settings, {}, messages.append)
    resumed.forget_events_after(float(stopped))  # what the supervisor does at every restart
    running.forget_events_after(float(stopped))

    # closing at an impact's speed, 4 mm apart: an impact for a book that has seen nothing
    fresh = ContactBook(load_case_info(resumed_case), settings, {}, messages.append)  # has read nothing
    closing = [c for c in fresh.geometry.contacts(pair(0.004, 0.3), 0.01, bed=False) if c.kind == "body"][0]
    assert fresh.classify(closing, 0.001) == "impact"
    assert resumed.classify(closing, 0.001) is None  # pressed: stopped only at a quarter of the gap

    after = f"{float(stopped) + 0.003:g}"
    n_running, states_running = running.resolve_contacts(after, pair(0.001, 0.3), 0.001)
    n_resumed, states_resumed = resumed.resolve_contacts(after, pair(0.001, 0.3), 0.001)
    assert n_running == n_resumed == 0  # plastic, no impact
    assert states_resumed == states_running
    u = [s.velocity_m_s[0] for s in states_resumed]
    assert u[0] == pytest.approx(u[1])  # no rebound
    last = [json.loads((c / "contacts.json").read_text())[-1] for c in (case, resumed_case)]
    assert last[0]["type"] == last[1]["type"] == "resting" and last[0]["pressed"] and last[1]["pressed"]
    assert sum("presses" in m for m in messages) == 1  # found once, before the stop


def test_contacts_carry_closing_speeds(body_case):
    """The runner's view of orchestrator.contact.geometry: distances, normals and closing speeds."""
    geometry = Geometry(load_case_info(body_case))
    # nose 4 mm from the column's upstream face (x = 1.15), closing at 0.5 m/s
    body = _state("debris1", (1.15 - 0.075 - 0.004, 0.0, 0.1), (0.5, 0.0, 0.0))
    c = next(c for c in geometry.contacts([body], 0.01) if c.other == "column")
    assert c.kind == "column" and c.distance_m == pytest.approx(0.004)
    assert c.normal == pytest.approx((-1.0, 0.0, 0.0)) and c.point_m[1:] == pytest.approx((0.0, 0.1))
    assert c.approach_m_s == pytest.approx(0.5)
    # a wall, another body (closing at 0.3 m/s relative), the bed
    near_wall = _state("debris1", (0.5, 0.2 - 0.03 - 0.002, 0.1), (0.0, 0.2, 0.0))
    other = _state("debris2", (0.5, 0.2 - 0.03 - 0.002 - 0.06 - 0.003, 0.1), (0.0, 0.5, -0.1))
    found = {(c.body, c.kind): c for c in geometry.contacts([near_wall, other], 0.01)}
    wall = found[("debris1", "wall")]
    assert wall.distance_m == pytest.approx(0.002) and wall.normal == pytest.approx((0.0, -1.0, 0.0))
    assert wall.approach_m_s == pytest.approx(0.2)
    pair = found[("debris1", "body")]
    assert pair.other == "debris2" and pair.distance_m == pytest.approx(0.003)
    assert pair.normal == pytest.approx((0.0, 1.0, 0.0)) and pair.approach_m_s == pytest.approx(0.3)
    assert ("debris2", "bed") not in found
    low = _state("debris2", (0.5, 0.0, 0.029), (0.0, 0.0, -0.1))
    bed = next(c for c in geometry.contacts([low], 0.01) if c.kind == "bed")
    assert bed.distance_m == pytest.approx(-0.001) and bed.approach_m_s == pytest.approx(0.1)
    assert [c for c in geometry.contacts([low], 0.01, bed=False) if c.kind == "bed"] == []


def test_classification_of_contacts(body_case):
    from orchestrator.run.contact_book import ContactBook
    from orchestrator.run.contact_geometry import Contact

    book = ContactBook(load_case_info(body_case), ContactSettings(gap_m=0.005, min_impact_speed_m_s=0.05), {},
                       print)

    def contact(d, v, kind="column"):
        return Contact("debris1", "column", kind, d, (0, 0, 0), (-1, 0, 0), v)

    horizon = 0.01
    assert book.classify(contact(0.009, 0.5), horizon) == "impact"  # reaches the gap within the horizon
    assert book.classify(contact(0.02, 0.5), horizon) is None
    assert book.classify(contact(0.004, -0.5), horizon) is None  # separating
    assert book.classify(contact(0.001, 0.02), horizon) == "resting"  # slow, within a quarter of the gap
    assert book.classify(contact(0.003, 0.02), horizon) is None
    assert book.classify(contact(-0.001, 0.0, "bed"), horizon) is None  # within the bed tolerance (2.5 mm)
    assert book.classify(contact(-0.002, 0.1, "bed"), horizon) == "bed"


def test_a_runner_that_died_mid_segment_leaves_the_cases_own_controls_back(body_case, tmp_path):
    """A runner killed during a segment left the segment's endTime, writeInterval and its lowered
    maxDeltaT in controlDict; the next run puts the case's own back (run.json's segment_control
    and control say which), and a maxDeltaT the user set in controlDict is the case's own."""
    import shutil

    from orchestrator.run.control import read_control, set_control
    from orchestrator.run.runner import _original_controls

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    set_control(case, maxDeltaT=0.004)  # the user's own step limit
    assert load_case_info(case).max_delta_t_s == pytest.approx(0.004)
    (case / "run.json").write_text(json.dumps({"control": {"endTime": 0.2, "writeInterval": 0.05},
                                               "segment_control": {"endTime": 0.1, "writeInterval": 0.025,
                                                                   "maxDeltaT": 0.004}}))
    set_control(case, endTime=0.1, writeInterval=0.025, maxDeltaT=0.0007)  # a segment's, left behind
    info = _original_controls(load_case_info(case), json.loads((case / "run.json").read_text()))
    control = read_control(case)
    assert (info.end_time_s, info.write_interval_s, info.max_delta_t_s) == (0.2, 0.05, 0.004)
    assert (float(control["endTime"]), float(control["writeInterval"]), float(control["maxDeltaT"])) == (0.2, 0.05,
                                                                                                          0.004)


def test_step_cap_lets_no_corner_cross_the_gap_before_the_runner_acts(body_case):
    """ContactBook.step_cap_s: near the column a body tumbling at 10 rad/s gets steps of
    gap / ((latency + 1) (u_n + |omega| R)); still, or far from everything, it keeps the
    case's own largest step."""
    from orchestrator.run.contact_book import ContactBook

    info = load_case_info(body_case)
    book = ContactBook(info, ContactSettings(gap_m=0.005, min_impact_speed_m_s=0.05), {}, print)
    size = np.asarray(info.body_sizes_m["debris1"])
    radius = 0.5 * float(np.linalg.norm(size))
    near = (1.15 - 0.5 * size[0] - 0.008, 0.0, 0.1)  # nose 8 mm from the column's face
    tumbling = _state("debris1", near, (0.3, 0.0, 0.0), omega=(0.0, -10.0, 0.0))
    cap = book.step_cap_s([tumbling], 3, 0.01)
    assert cap == pytest.approx(0.005 / (4 * (0.3 + 10.0 * radius)), rel=1e-6)
    # the corner's travel in the runner's four steps is the gap itself, not ten times it
    assert 4 * cap * (0.3 + 10.0 * radius) == pytest.approx(0.005)
    assert book.step_cap_s([_state("debris1", near, (0.0, 0.0, 0.0))], 3, 0.01) is None  # at rest
    away = _state("debris1", (0.5, 0.0, 0.1), (0.3, 0.0, 0.0), omega=(0.0, -10.0, 0.0))
    assert book.step_cap_s([away], 3, 0.01) is None  # 0.6 m from the column, mid-channel
    receding = _state("debris1", near, (-0.3, 0.0, 0.0))
    assert book.step_cap_s([receding], 3, 0.01) is None  # moving away, not turning
    fast = _state("debris1", near, (50.0, 0.0, 0.0))
    assert book.step_cap_s([fast], 3, 0.01) == pytest.approx(1e-4)  # the floor: a hundredth of the case's


def test_resting_contact_stops_the_closing_motion(body_case):
    geometry = Geometry(load_case_info(body_case))
    body = _state("debris1", (1.15 - 0.075 + 0.001, 0.02, 0.11), (0.02, 0.01, -0.01), omega=(0.0, 0.3, 0.1))
    c = next(c for c in geometry.contacts([body], 0.01) if c.other == "column")
    assert c.distance_m == pytest.approx(-0.001)
    new, impulse = resting_contact(geometry, c, {"debris1": body})
    after = new["debris1"]
    p = np.asarray(c.point_m)
    v_point = np.asarray(after.velocity_m_s) + np.cross(after.angular_velocity_rad_s, p - np.asarray(body.centre_of_mass_m))
    assert v_point @ np.asarray(c.normal) == pytest.approx(0.0, abs=1e-12)
    assert impulse > 0
    assert after.centre_of_mass_m[0] == pytest.approx(body.centre_of_mass_m[0] - 0.001)  # out of the column
    assert all(x.distance_m >= -1e-12 for x in geometry.contacts([after], 0.0) if x.other == "column")


def test_contact_book_pins_a_body_pressed_against_the_column_again_and_again(body_case, tmp_path):
    """The book alone (no solver): the same slow contact at restarts 3 ms apart is resting
    `max_events` times, then pinned; two bodies pressed together have plastic contacts that set
    them the gap apart and stop the solver only at a quarter of the gap until they are two gaps
    apart, and a ContactError only when even that stops the solver every ms."""
    import shutil

    from orchestrator.run.contact_book import PRESSED_RUNAWAY, ContactBook
    from orchestrator.run.runner import ContactError

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    settings = ContactSettings()
    record, messages = {}, []
    book = ContactBook(load_case_info(case), settings, record, messages.append)
    pressed = _state("debris1", (1.15 - 0.075 - 0.001, 0.0, 0.1), (0.02, 0.0, 0.0))
    elsewhere = _state("debris2", (0.7, 0.12, 0.1), yaw_deg=30.0)
    for k in range(1, settings.max_events + 2):  # the flow closes it again before every restart
        impacts, states = book.resolve_contacts(f"{0.003 * k:g}", [pressed, elsewhere], 0.003)
        assert impacts == 0
    events = json.loads((case / "contacts.json").read_text())
    assert [e["type"] for e in events] == ["resting"] * settings.max_events + ["pinned"]
    assert events[-1]["other"] == "column" and events[-1]["time_s"] == pytest.approx(0.021)
    assert states[0].velocity_m_s == (0.0, 0.0, 0.0) and states[0].centre_of_mass_m == pressed.centre_of_mass_m
    assert states[1] == elsewhere
    assert record["resting_contacts"] == settings.max_events and record["pinned"][0]["body"] == "debris1"
    assert body_policy.pinned_bodies(case) == {"debris1"} and "pinned there" in messages[-1]
    # debris2 still moves: the overset flux adjustment stays off
    assert "overset_adjust_phi_from_s" not in record and _pimple(case)["oversetAdjustPhi"] is False
    book.forget_events_after(0.01)  # a resumed run computing t > 0.01 s again
    assert len(json.loads((case / "contacts.json").read_text())) == 3

    # two bodies the flow presses together: every contact of the pair plastic and the pair set
    # the gap apart, with the pair's momentum kept, even when they close at impact speed
    one = _state("debris1", (0.5, 0.0, 0.1), (0.0, 0.0, 0.0))
    other = _state("debris2", (0.5, 0.06 + 0.001, 0.1), (0.0, -0.3, 0.0))
    for k in range(1, PRESSED_RUNAWAY * settings.max_events + 1):
        impacts, (a, b) = book.resolve_contacts(f"{0.1 + 0.001 * k:g}", [one, other], 0.001)
        if k > settings.max_events:
            assert impacts == 0, k
            gap = min(c.distance_m for c in book.geometry.contacts([a, b], 0.01, bed=False) if c.kind == "body")
            assert gap == pytest.approx(settings.gap_m, abs=1e-9)
            assert b.velocity_m_s[1] == pytest.approx(a.velocity_m_s[1])  # plastic: no rebound
            momentum = a.velocity_m_s[1] + b.velocity_m_s[1]  # equal masses
            assert momentum == pytest.approx(one.velocity_m_s[1] + other.velocity_m_s[1], abs=1e-12)
            assert a.centre_of_mass_m[1] + b.centre_of_mass_m[1] == pytest.approx(
                one.centre_of_mass_m[1] + other.centre_of_mass_m[1], abs=1e-12)
    events = json.loads((case / "contacts.json").read_text())
    pair = [e for e in events if e.get("other") == "debris2" or e.get("body") == "debris2"]
    assert [e.get("pressed", False) for e in pair[settings.max_events:]] == [True] * (
        (PRESSED_RUNAWAY - 1) * settings.max_events)
    assert sum("presses debris" in m for m in messages) == 1
    # pressed, the pair closing at impact speed within the gap needs no stop until a quarter of it
    inside = _state("debris2", (0.5, 0.06 + 0.6 * settings.gap_m, 0.1), (0.0, -0.3, 0.0))
    closing = [c for c in book.geometry.contacts([one, inside], 0.01, bed=False) if c.kind == "body"][0]
    assert closing.approach_m_s == pytest.approx(0.3) and closing.distance_m < settings.gap_m
    assert book.classify(closing, 0.0) is None
    assert book.time_to_act(closing) == pytest.approx(0.35 * settings.gap_m / 0.3)
    with pytest.raises(ContactError, match="pressed together harder than event-driven contact can follow"):
        book.resolve_contacts(f"{0.1 + 0.001 * (k + 1):g}", [one, other], 0.001)
    # two gaps apart at a restart, the pair's contacts are impacts again
    far = _state("debris2", (0.5, 0.06 + 2.5 * settings.gap_m, 0.1), (0.0, -0.3, 0.0))
    book.resolve_contacts("0.5", [one, far], 0.001)
    assert "are apart: their contacts are impacts again" in messages[-1]
    near = [c for c in book.geometry.contacts([one, _state("debris2", (0.5, 0.06 + 0.5 * settings.gap_m, 0.1),
                                                               (0.0, -0.3, 0.0))], 0.01, bed=False)
            if c.kind == "body"][0]
    assert book.classify(near, 0.0) == "impact"


def test_contact_book_keeps_a_body_the_flow_pulls_into_the_bed_on_it(body_case, tmp_path):
    """Lifted out of the bed at every restart (as on the short flume, where each lift pulled the
    body down harder, to a blow-up): after `max_events` lifts within `window_s` the body gets a
    plane constraint and stays on the bed. Lifts far apart (a body settling slowly) do not."""
    import shutil

    from orchestrator.run.contact_book import ContactBook

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    settings = ContactSettings()
    record, messages = {}, []
    book = ContactBook(load_case_info(case), settings, record, messages.append)
    elsewhere = _state("debris2", (0.7, 0.12, 0.1), yaw_deg=30.0)
    sunk = _state("debris1", (0.5, 0.0, 0.03 - 0.004), (0.3, 0.0, -0.5))  # 4 mm into the bed, sinking
    for k in range(1, settings.max_events + 1):  # one lift every window: settling slowly
        impacts, states = book.resolve_contacts(f"{settings.window_s * 1.01 * k:.6g}", [sunk, elsewhere], 0.003)
    assert record["bed_clamps"] == settings.max_events and "rest_on_bed" not in record
    for k in range(1, settings.max_events + 2):  # pulled in again before every restart, 3 ms apart
        impacts, states = book.resolve_contacts(f"{0.5 + 0.003 * k:.6g}", [sunk, elsewhere], 0.003)
        assert impacts == 0
        assert states[0].centre_of_mass_m[2] == pytest.approx(0.03) and states[0].velocity_m_s[2] == 0.0
    assert record["rest_on_bed"] == [{"body": "debris1", "time_s": pytest.approx(0.5 + 0.003 * (settings.max_events + 1))}]
    events = json.loads((case / "contacts.json").read_text())
    assert [e["type"] for e in events] == ["rest_on_bed"] and events[0]["body"] == "debris1"
    assert "kept on the bed" in messages[-1] and "lifted out of the bed 7 times" in messages[-1]
    constraints = bodystate.motion_entries(case, "constraints")
    plane = constraints["debris1"][body_policy.REST_ON_BED]
    assert plane["sixDoFRigidBodyMotionConstraint"] == "plane" and list(plane["normal"]) == [0, 0, 1]
    assert body_policy.REST_ON_BED not in constraints["debris2"]
    assert body_policy.rest_on_bed(case, ["debris1"]) == []  # once
    body_policy.release_holds(case, ["debris1"])  # the planner's hold release leaves it
    assert body_policy.REST_ON_BED in bodystate.motion_entries(case, "constraints")["debris1"]
    # one lift of a body sinking fast (each lift pulling it down harder) is enough
    fast = _state("debris2", (0.7, 0.12, 0.03 - 0.004), (0.0, 0.0, -2.0 * settings.bed_runaway_m_s), yaw_deg=30.0)
    book.resolve_contacts("0.9", [states[0], fast], 0.003)
    assert record["rest_on_bed"][-1]["body"] == "debris2" and "sank into the bed at 2 m/s" in messages[-1]


def test_a_run_resumed_after_a_body_ran_away_into_the_bed_keeps_it_on_the_bed(body_case, tmp_path):
    """The resume gap of the bed runaway: a run the body-speed check stopped restarts from its
    last good time, before the lifts that would show the runaway; run.json's diagnosis (the
    body and its velocity) says it instead. Fast sideways, or slow, is not a runaway."""
    import shutil

    from orchestrator.run.contact_book import ContactBook

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    settings = ContactSettings()
    record, messages = {}, []
    book = ContactBook(load_case_info(case), settings, record, messages.append)
    states = [_state("debris1", (0.5, 0.0, 0.03), (0.3, 0.0, -0.2)), _state("debris2", (0.7, 0.12, 0.1), yaw_deg=30.0)]
    diag = {"kind": "body_speed", "cause": "body debris1 moves at 13.4 m/s", "time_s": 1.9}
    for not_a_runaway in ({**diag, "kind": "courant"},
                          {**diag, "body": "debris1", "velocity_m_s": [13.0, 0.0, -3.0]},  # along the flume
                          {**diag, "body": "debris1", "velocity_m_s": [0.1, 0.0, -0.5 * settings.bed_runaway_m_s]},
                          {**diag, "body": "nobody", "velocity_m_s": [0.0, 0.0, -13.4]},
                          diag):  # a record from before the body was named
        book.after_divergence(not_a_runaway, "1.85", states)
    assert "rest_on_bed" not in record and not (case / "contacts.json").exists()
    book.after_divergence({**diag, "body": "debris1", "velocity_m_s": [1.0, 0.5, -13.4]}, "1.85", states)
    assert record["rest_on_bed"] == [{"body": "debris1", "time_s": 1.85}]
    assert "the last run stopped with it sinking at 13.4 m/s (t = 1.9 s)" in messages[-1]
    assert [e["type"] for e in json.loads((case / "contacts.json").read_text())] == ["rest_on_bed"]


def test_write_and_restore_states_in_dynamic_mesh_dict(body_case, tmp_path):
    import shutil

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    mesh = {pose.name: (pose, inertia) for pose, inertia in bodystate.read_mesh_bodies(case)}
    before = (case / bodystate.DYNAMIC_MESH_DICT).read_text()
    assert "momentOfInertia (0.0002213017544" in before
    q = bodystate.orthonormal([1, 1e-9, 0, -1e-9, 1, 0, 0, 0, 1.0000000001])
    s1 = BodyState("debris1", 0.3, (1.0123456789012, 0.0011, 0.0987654321), q, (0.1, 0.2, -0.3), (0.5, -0.25, 2.0))
    s2 = BodyState("debris2", 0.3, (0.75, 0.125, 0.1), mesh["debris2"][0].orientation, (0.2, 0.0, 0.0))
    # a fake decomposed time with v1912's (first body's) state file in each processor
    for p in ("processor0", "processor1"):
        (case / p / "0.3" / "uniform").mkdir(parents=True)
        (case / p / "0.3" / "uniform" / "sixDoFRigidBodyMotionState").write_text("FoamFile{}\n")
    bodystate.prepare_restart(case, "0.3", [s1, s2], "log")
    assert bodystate.state_file_paths(case, "0.3") == []
    from foamlib import FoamFile

    d = FoamFile(case / bodystate.DYNAMIC_MESH_DICT)
    c1 = d["solvers"]["debris1"]["sixDoFRigidBodyMotionCoeffs"]
    assert list(c1["centreOfMass"]) == [1.0123456789012, 0.0011, 0.0987654321]  # every digit kept
    assert list(c1["initialCentreOfMass"]) == pytest.approx([1.05, 0.0, 0.1037304927])
    assert list(c1["velocity"]) == [0.1, 0.2, -0.3]
    # angularMomentum = I (Q^T omega): back to omega
    pi = np.array(c1["angularMomentum"], dtype=float)
    omega = np.asarray(q).reshape(3, 3) @ (pi / np.asarray(mesh["debris1"][1]))
    assert omega == pytest.approx((0.5, -0.25, 2.0))
    c2 = d["solvers"]["debris2"]["sixDoFRigidBodyMotionCoeffs"]
    assert list(c2["initialOrientation"]) == pytest.approx(list(mesh["debris2"][0].orientation))
    # untouched entries keep their digits and their layout
    after = (case / bodystate.DYNAMIC_MESH_DICT).read_text()
    assert "momentOfInertia (0.0002213017544" in after and "// principal moments about the centre of mass" in after
    # the initial pose is the mesh's, whatever was written since
    assert bodystate.read_mesh_poses(case)[0].centre_of_mass_m == mesh["debris1"][0].centre_of_mass_m
    states, source = bodystate.recorded_states(case, "0.3")
    assert source == "log" and states == [s1, s2]
    with pytest.raises(InputError, match="bodies: no state at t = 0.4 for debris2"):
        bodystate.prepare_restart(case, "0.4", [s1], "log")


def test_latest_time_repairs_an_incomplete_write(tmp_path):
    case = tmp_path / "case"
    field = "FoamFile\n{\n    class volScalarField;\n}\ninternalField nonuniform List<scalar> 2(1 2);\n\n" \
            "// ************************************************************************* //\n"
    for p in ("processor0", "processor1"):
        for t in ("0", "0.05", "0.1", "0.15"):
            d = case / p / t
            (d / "uniform").mkdir(parents=True)
            for f in ("U", "p_rgh", "alpha.water"):
                (d / f).write_text(field)
            if t != "0":
                (d / "uniform" / "time").write_text(field)
    # rank 1 was killed while writing 0.15 (a field cut off mid-list) and before 0.1's last file
    (case / "processor1" / "0.15" / "p_rgh").write_text(field[:70])
    assert latest_time(case, 2, repair=False) == (0.1, "0.1")
    (case / "processor1" / "0.1" / "p_rgh").unlink()
    assert latest_time(case, 2, repair=False) == (0.05, "0.05")
    assert (case / "processor0" / "0.1").is_dir() and (case / "processor0" / "0.15").is_dir()
    assert latest_time(case, 2) == (0.05, "0.05")
    assert not (case / "processor0" / "0.1").exists() and not (case / "processor1" / "0.15").exists()
    assert latest_time(tmp_path / "empty", 2) == (0.0, "0")


def test_stop_request_dates_control_dict_past_the_skew(body_case, tmp_path):
    import shutil

    from orchestrator.run.control import FILE_MODIFICATION_SKEW_S, request_write_now, set_control

    case = tmp_path / "case"
    shutil.copytree(body_case, case)
    set_control(case, backdate=True, stopAt="endTime")
    control = case / "system" / "controlDict"
    before = control.stat().st_mtime
    assert before < time.time() - 3000
    request_write_now(case)
    assert control.stat().st_mtime >= before + FILE_MODIFICATION_SKEW_S + 1
    text = control.read_text()
    assert "stopAt writeNow;" in text
    assert "start   (0.5 0 " in text or "start (0.5 0.0 " in text  # the gauge line kept its digits


def test_missing_case_is_bad_input(tmp_path):
    with pytest.raises(InputError, match="nowhere: case_dir: does not exist"):
        run_case(tmp_path / "nowhere", quiet=True)
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="plan.json: plan.json: missing"):
        run_case(tmp_path / "empty", quiet=True)


# --------------------------------------------------------------------------- with OpenFOAM


@pytest.mark.openfoam
def test_dam_break_runs_to_completion_and_resumes_after_a_stop(tmp_path, openfoam):
    """2 ranks to the end; stopped mid-way (stop_event, as Ctrl-C) and resumed, the same end state."""
    data = scene(end_time_s=0.7)  # the bore reaches the column at about 0.5 s
    whole = render(tmp_path, "whole", data)
    summary = run_case(whole, quiet=True)
    assert summary.status == "finished" and summary.reached_time_s == pytest.approx(0.7)
    assert summary.segments == 1 and summary.time_steps > 20
    record = json.loads((whole / "run.json").read_text())
    assert record["status"] == "finished" and record["openfoam"].startswith("1912")
    assert record["cells"]["total"] == record["cells"]["planned"] > 4000
    names = [s["name"] for s in record["steps"]]
    assert names == ["blockMesh", "setFields", "checkMesh", "decomposePar", "reconstructPar"]
    assert all(s["exit_status"] == 0 and s["wall_s"] > 0 and s["start"] for s in record["steps"])
    assert record["segments"][0]["command"] == "mpirun -np 2 interFoam -parallel"
    assert record["runner"]["overhead_fraction"] < 0.05
    for log in ("log.blockMesh", "log.setFields", "log.checkMesh", "log.decomposePar", "log.interFoam",
                "log.reconstructPar"):
        assert (whole / log).is_file()
    assert (whole / "0.7" / "alpha.water").is_file()  # the latest time, reconstructed
    assert not (whole / "0.5").exists()
    again = run_case(whole, quiet=True)  # idempotent
    assert again.already_finished and again.status == "finished"

    stopped = render(tmp_path, "stopped", data)
    stop = threading.Event()
    with pytest.raises(RunInterrupted) as err:
        run_case(stopped, quiet=True, stop_event=stop, on_step=lambda s: s.time_s >= 0.33 and stop.set())
    assert err.value.clean and f"debrisfoam run {stopped}" in str(err.value)
    written = float(err.value.written_time)
    assert 0.33 <= written < 0.65  # a few steps after the request (the runner reads the log every 0.2 s)
    assert json.loads((stopped / "run.json").read_text())["status"] == "interrupted"
    resumed = run_case(stopped, quiet=True)
    on_grid = abs(written / 0.05 - round(written / 0.05)) < 1e-6
    # the stopped segment, a short one back onto the write grid (unless the stop fell on it), the rest
    assert resumed.status == "finished" and resumed.segments == (2 if on_grid else 3)
    logs = [seg["log"] for seg in json.loads((stopped / "run.json").read_text())["segments"]]
    assert len(set(logs)) == len(logs) and all((stopped / n).is_file() for n in logs)  # each its own, kept
    # the same end state as the uninterrupted run: the column force (the bore hit it at
    # about 0.5 s) and the water fraction in every cell
    a, b = force_rows(whole), force_rows(stopped)
    scale = max(abs(v[0]) for v in a.values())
    assert scale > 0.1  # N; the hydrostatic force of the wet bed before the bore is 3e-4 N
    assert np.abs(a[0.7] - b[0.7]).max() < 0.01 * scale
    assert internal_field(stopped / "0.7" / "alpha.water") == pytest.approx(
        internal_field(whole / "0.7" / "alpha.water"), abs=0.02)
    # after the stop the run wrote at the same times as the uninterrupted one
    times = {p.name for p in (stopped / "processor0").iterdir() if p.name[0].isdigit()}
    assert {"0.65", "0.7", err.value.written_time} <= times


@pytest.mark.openfoam
def test_ctrl_c_on_the_command_line(tmp_path, openfoam):
    """SIGINT to `debrisfoam run`: the solver writes, the message says how to resume, exit 130."""
    case = render(tmp_path, "cli", scene(end_time_s=2.0))
    proc = subprocess.Popen([sys.executable, "-m", "orchestrator.cli", "run", str(case)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    log = case / "log.interFoam"
    deadline = time.time() + 120
    while time.time() < deadline and not (log.is_file() and log.read_text().count("\nTime = ") >= 5):
        time.sleep(0.2)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted" in err and f"Resume with: debrisfoam run {case}" in err
    assert "Re-reading object controlDict" in log.read_text()  # stopped by writeNow, not killed
    t, name = latest_time(case, 2)
    assert 0 < t < 2.0
    assert json.loads((case / "run.json").read_text())["segments"][-1]["stop_reason"] == "interrupt"
    assert "stopAt endTime;" in (case / "system" / "controlDict").read_text()


@pytest.mark.openfoam
def test_unstable_case_stops_with_a_diagnosis(tmp_path, openfoam):
    case = render(tmp_path, "unstable", scene(end_time_s=2.0))
    control = case / "system" / "controlDict"
    text = re.sub(r"^adjustTimeStep .*$", "adjustTimeStep no;", control.read_text(), flags=re.M)
    control.write_text(re.sub(r"^deltaT .*$", "deltaT 0.04;", text, flags=re.M))  # Co 60-80
    with pytest.raises(DivergenceError) as err:
        run_case(case, quiet=True)
    e = err.value
    assert e.kind == "courant" and e.time_s < 1.0
    assert "Courant number runaway" in str(e) and f"t = {e.time_s:.6g} s" in str(e)
    assert str(case / "log.interFoam") in str(e)
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "diverged" and record["diagnosis"]["kind"] == "courant"
    # the last good time is kept, nothing written after the first symptom
    t, name = latest_time(case, 2)
    assert name == e.last_good_time and t < record["diagnosis"]["time_s"]
    assert not any(p.name[0].isdigit() and float(p.name) > t for p in (case / "processor0").iterdir())
    # the CLI's message and exit code
    proc = subprocess.run([sys.executable, "-m", "orchestrator.cli", "run", str(case), "--quiet"], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1 and "solution diverged" in proc.stderr and "log.interFoam" in proc.stderr


def _solver_ranks(case: Path, solver: str) -> list[int]:
    """PIDs of the solver ranks running in ``case`` (by working directory: nothing else is touched)."""
    pids = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            if (proc / "comm").read_text().strip() == solver and Path(os.readlink(proc / "cwd")) == case.resolve():
                pids.append(int(proc.name))
        except OSError:
            continue
    return pids


def _freeze_solver(case: Path, solver: str = "interFoam") -> list[int]:
    """Freeze (SIGSTOP) the solver ranks running in ``case``; their PIDs."""
    pids = _solver_ranks(case, solver)
    for pid in pids:
        os.kill(pid, signal.SIGSTOP)
    return pids


@pytest.mark.openfoam
def test_a_stalled_solver_is_stopped_with_a_diagnosis(tmp_path, openfoam):
    """The solver's ranks frozen (SIGSTOP) mid-run, as a linear solver that never returns or a
    hung rank would leave it: the runner stops it after the stall limit (the scene's
    run.stall_limit_s, through plan.json) and says so."""
    data = scene(end_time_s=2.0)
    data["run"]["stall_limit_s"] = 5.0
    case = render(tmp_path, "stall", data)
    assert load_case_info(case).stall_limit_s == 5.0
    frozen: list[int] = []

    def freeze(step):
        if step.time_s > 0.05 and not frozen:
            frozen.extend(_freeze_solver(case))

    t0 = time.perf_counter()
    with pytest.raises(DivergenceError) as err:
        run_case(case, quiet=True, on_step=freeze, limits=DivergenceLimits(stall_factor=2.0))
    assert len(frozen) == 2  # both ranks
    assert time.perf_counter() - t0 < 90  # stopped, not waited on forever
    e = err.value
    assert e.kind == "stall" and "solver stalled" in str(e) and "nothing written to its log" in str(e)
    assert time.perf_counter() - t0 > 5.0  # not before the scene's limit
    assert 0.05 < e.time_s < 2.0 and str(case / "log.interFoam") in str(e)
    assert not _solver_ranks(case, "interFoam")  # killed
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "stalled" and record["diagnosis"]["kind"] == "stall"
    # the times written before the stall are kept (the frozen ranks may have written past the last
    # step their buffered log showed)
    t, name = latest_time(case, 2)
    assert name == e.last_good_time and t >= 0.05


@pytest.mark.openfoam
def test_a_stop_before_the_first_time_step_kills_the_solver_at_once(tmp_path, openfoam, monkeypatch):
    """A stop request while the solver has not taken a step (reading the mesh; with several
    overset bodies the addressing takes many minutes) cannot be answered by writeNow, which the
    solver reads between steps: the runner stops it at once instead of waiting STOP_KILL_TIMEOUT_S.
    The ranks are held at a known point, so that no step can come first: the `interFoam` mpirun
    finds first on the PATH is a gate that marks its arrival and waits for a file before it runs
    the real solver; the stop is requested once both ranks wait there."""
    case = render(tmp_path, "unstarted", scene(end_time_s=0.1))
    real = shutil.which("interFoam")
    gate = tmp_path / "gate"
    gate.mkdir()
    (gate / "interFoam").write_text(f"#!/bin/sh\ntouch {gate}/held.$$\n"
                                    f"while [ ! -e {gate}/open ]; do sleep 0.02; done\nexec {real} \"$@\"\n")
    (gate / "interFoam").chmod(0o755)
    monkeypatch.setenv("PATH", f"{gate}:{os.environ['PATH']}")
    stop = threading.Event()

    def stop_once_held():
        deadline = time.time() + 120
        while time.time() < deadline and len(list(gate.glob("held.*"))) < 2:
            time.sleep(0.01)
        stop.set()

    watcher = threading.Thread(target=stop_once_held, daemon=True)
    watcher.start()
    t0 = time.perf_counter()
    with pytest.raises(RunInterrupted) as err:
        run_case(case, quiet=True, stop_event=stop)
    watcher.join(5)
    assert len(list(gate.glob("held.*"))) == 2  # both ranks reached the gate, and none went past it
    assert "\nTime = " not in (case / "log.interFoam").read_text()
    assert time.perf_counter() - t0 < 60  # not the 600 s STOP_KILL_TIMEOUT_S
    e = err.value
    assert e.before_first_step and not e.clean
    assert "before its first time step" in str(e) and f"debrisfoam run {case}" in str(e)
    assert not _solver_ranks(case, "interFoam")
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "interrupted" and record["segments"][-1]["stop_reason"] == "unstarted"
    (gate / "open").touch()
    resumed = run_case(case, quiet=True)  # and the run goes on from the start
    assert resumed.status == "finished" and resumed.reached_time_s == pytest.approx(0.1)


@pytest.mark.openfoam
def test_a_stop_while_the_solver_is_stuck_in_a_step_kills_it_without_waiting(tmp_path, openfoam, monkeypatch):
    """A stop request to a solver stuck inside a time step (frozen here with SIGSTOP; seen: the
    overset addressing of six bodies) cannot be answered by writeNow: once the log has been
    silent for STOP_SILENT_KILL_S (or 20 slowest steps) after the request, the runner kills it
    instead of waiting STOP_KILL_TIMEOUT_S (600 s), and the run resumes from its last time."""
    monkeypatch.setattr(run_module, "STOP_SILENT_KILL_S", 3.0)
    # long enough that the solver is still running when the runner reads t > 0.12 s from its log
    # (at 0.3 s it could finish between two of the runner's reads, leaving no rank to freeze)
    case = render(tmp_path, "stuck", scene(end_time_s=1.0))
    stop = threading.Event()
    frozen: list[int] = []

    def freeze_then_stop(step):
        if step.time_s > 0.12 and not frozen:
            frozen.extend(_freeze_solver(case))
            stop.set()

    t0 = time.perf_counter()
    with pytest.raises(RunInterrupted) as err:
        run_case(case, quiet=True, stop_event=stop, on_step=freeze_then_stop)
    assert len(frozen) == 2 and time.perf_counter() - t0 < 120  # not the 600 s
    assert not err.value.clean and not _solver_ranks(case, "interFoam")
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "interrupted" and record["segments"][-1]["stop_reason"] == "killed"
    resumed = run_case(case, quiet=True)
    assert resumed.status == "finished" and resumed.reached_time_s == pytest.approx(1.0)


def _positions_across_restarts(case: Path, names):
    """[(time name, last step before, first step after)] at every restart."""
    segments = steps_of(case, "overInterDyMFoam", names)
    out = []
    for (_, before), (_, after) in zip(segments, segments[1:]):
        if before and after:
            out.append((before[-1].time_name, before[-1], after[0]))
    return out


def _outside_everything(case: Path, names):
    last = steps_of(case, "overInterDyMFoam", names)[-1][1][-1]
    return [c for c in Geometry(load_case_info(case)).contacts(last.bodies, 0.0, bed=False) if c.distance_m < 0]


@pytest.mark.openfoam
def test_body_driven_into_the_column_rebounds(tmp_path, openfoam):
    case = render(tmp_path, "one", scene([{"name": "debris1", "centre_m": [1.05, 0.0]}], end_time_s=0.08,
                                         wet_depth_m=0.1))
    set_velocities(case, {"debris1": (0.6, 0.0, 0.0)})
    summary = run_case(case, quiet=True)
    assert summary.status == "finished" and summary.contacts >= 1
    events = json.loads((case / "contacts.json").read_text())
    impact = next(e for e in events if e["type"] == "impact")
    assert impact["body"] == "debris1" and impact["other"] == "column"
    assert impact["normal"] == pytest.approx([-1.0, 0.0, 0.0])
    assert impact["normal_velocity_in_m_s"] < -0.3 and impact["normal_velocity_out_m_s"] > 0.1  # a rebound
    assert impact["velocity_out_m_s"][0] < 0 < impact["velocity_in_m_s"][0]
    assert impact["peak_force_N"] > 0 and impact["impulse_Ns"] > 0 and 0 < impact["height_m"] < 0.3
    assert (case / impact["force_history"]).is_file()
    header = (case / "impact_events.csv").read_text().splitlines()[0]
    for column in ("time_s", "body", "other", "point_x_m", "normal_x", "u_in_m_s", "u_out_m_s", "obliquity_deg",
                   "height_m", "peak_force_N", "duration_s", "impulse_Ns", "force_history"):
        assert column in header.split(",")
    # the body restarted with its rebound velocity, where it was
    t_event, before, after = _positions_across_restarts(case, ["debris1"])[0]
    assert float(t_event) == pytest.approx(impact["time_s"])
    b0, b1 = before.bodies[0], after.bodies[0]
    assert b1.velocity_m_s[0] == pytest.approx(impact["velocity_out_m_s"][0], abs=0.05)
    assert math.dist(b0.centre_of_mass_m, b1.centre_of_mass_m) < 1.5 * b1.speed_m_s * after.delta_t_s + 1e-4
    assert _outside_everything(case, ["debris1"]) == []
    assert json.loads((case / "run.json").read_text())["runner"]["overhead_fraction"] < 0.05


@pytest.mark.openfoam
def test_two_bodies_keep_their_own_states_across_restarts(tmp_path, openfoam):
    names = ["debris1", "debris2"]
    case = render(tmp_path, "two", scene([{"name": "debris1", "centre_m": [1.05, 0.0]},
                                          {"name": "debris2", "centre_m": [0.6, 0.0]}],
                                         end_time_s=0.06, wet_depth_m=0.1))
    set_velocities(case, {"debris1": (0.6, 0.0, 0.0), "debris2": (0.2, 0.0, 0.0)})
    summary = run_case(case, quiet=True)
    assert summary.status == "finished" and summary.contacts >= 1 and summary.segments >= 2
    segments = steps_of(case, "overInterDyMFoam", names)
    restarts = _positions_across_restarts(case, names)
    assert restarts
    for _, before, after in restarts:
        assert [b.name for b in after.bodies] == names
        for b0, b1 in zip(before.bodies, after.bodies):
            # each body continues from its own place (v1912 alone would give both debris1's)
            moved = math.dist(b0.centre_of_mass_m, b1.centre_of_mass_m)
            assert moved < 1.5 * max(b0.speed_m_s, b1.speed_m_s) * after.delta_t_s + 1e-4, (b0, b1)
    # debris2 took no part in the impact: its velocity and position carry on across the restart
    t_event, before, after = restarts[0]
    first = segments[0][1]
    assert first[-1].time_name == t_event
    prev, last, nxt = first[-2].bodies[1], before.bodies[1], after.bodies[1]
    change_before = np.subtract(last.velocity_m_s, prev.velocity_m_s)
    change_across = np.subtract(nxt.velocity_m_s, last.velocity_m_s)
    assert np.linalg.norm(change_across) < 2 * np.linalg.norm(change_before) + 0.01
    assert nxt.centre_of_mass_m[0] > last.centre_of_mass_m[0] > 0.6
    # debris1 rebounded; debris2 kept going downstream
    assert after.bodies[0].velocity_m_s[0] < 0 < before.bodies[0].velocity_m_s[0]
    assert nxt.velocity_m_s[0] > 0.1
    assert _outside_everything(case, names) == []
    record = json.loads((case / "bodystate.json").read_text())
    assert {e["source"] for e in record.values()} >= {"initial", "contact"}


@pytest.mark.openfoam
def test_body_on_the_bed_does_not_sink_through_it(tmp_path, openfoam):
    """v1912 lets a heavy body sink through the bed; the runner lifts it back at restarts.

    The plan holds such a body until the bore can lift it; this is the fallback for a body
    that sinks anyway (released too early), so the hold is taken off here."""
    # it first sinks through the 15 mm gap it stands on (plan.BedGap), then into the bed
    case = render(tmp_path, "bed", scene([{"name": "debris1", "centre_m": [0.8, 0.0], "placement": "on_bed"}],
                                         end_time_s=0.12, wet_depth_m=0.015))
    assert body_policy.release_holds(case, ["debris1"]) == ["debris1"]
    summary = run_case(case, quiet=True)
    record = json.loads((case / "run.json").read_text())
    assert summary.status == "finished" and record["bed_clamps"] >= 1
    assert any(s.get("stopped_for", [{}])[0].get("other") == "bed" for s in record["segments"])
    geometry = Geometry(load_case_info(case))
    tolerance = ContactSettings().bed_sink_m
    lowest = []
    for _, steps in steps_of(case, "overInterDyMFoam", ["debris1"]):
        for step in steps:
            bed = [c for c in geometry.contacts(step.bodies, 1.0) if c.kind == "bed"]
            lowest.append(bed[0].distance_m)
    # it sinks at most the tolerance plus what it covers while the solver stops (a few steps; it
    # arrives faster after falling through the 15 mm gap: 5.9 mm measured, 1 m/s-ish for ~3 steps)
    assert min(lowest) > -(tolerance + 0.004)


@pytest.mark.openfoam
def test_resumed_after_a_bed_runaway_the_body_stays_on_the_bed(tmp_path, openfoam):
    """The same sinking body, in a run resumed after the body-speed check stopped it sinking
    (run.json's diagnosis, as the runner writes it): from the restart on, the sixDoF plane
    constraint keeps it at the bed's level in the real solver, with no lift needed."""
    case = render(tmp_path, "runaway", scene([{"name": "debris1", "centre_m": [0.8, 0.0], "placement": "on_bed"}],
                                             end_time_s=0.06, wet_depth_m=0.015))
    assert body_policy.release_holds(case, ["debris1"]) == ["debris1"]
    (case / "run.json").write_text(json.dumps({"status": "diverged", "diagnosis": {
        "kind": "body_speed", "cause": "body debris1 moves at 13.4 m/s, faster than any flow here", "time_s": 0.05,
        "last_good_time": "0", "body": "debris1", "velocity_m_s": [0.2, 0.0, -13.4]}}))
    summary = run_case(case, quiet=True, contact=solvers_kept(case))  # v1912's own constraint at work
    record = json.loads((case / "run.json").read_text())
    assert summary.status == "finished" and record["rest_on_bed"] == [{"body": "debris1", "time_s": 0.0}]
    assert not record.get("bed_clamps")  # never lifted: it did not sink
    z0 = json.loads((case / "plan.json").read_text())["bodies"][0]["centre_of_mass_m"][2]
    heights = [b.centre_of_mass_m[2] for _, steps in steps_of(case, "overInterDyMFoam", ["debris1"])
               for step in steps for b in step.bodies]
    assert len(heights) > 5 and max(abs(z - z0) for z in heights) < 1e-6


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_body_on_the_bed_is_held_until_the_measured_water_can_lift_it(tmp_path, openfoam):
    # 0.3 m downstream of the gate, Ritter's depth reaches the container's 26 mm draft plus the
    # 15 mm gap it stands on (plan.BedGap: half a 3 cm body cell) at 0.50 s: the planner's estimate.
    # The runner holds it until the depth it measures all round it exceeds its underside plus its
    # draft plus the 5 mm margin and the water pushes it up by its weight (orchestrator.run.bedwatch)
    data = scene([{"name": "debris1", "centre_m": [0.3, 0.0], "placement": "on_bed"}], end_time_s=0.53,
                 wet_depth_m=0.02)
    # this coarse case (2-cell body standing in a 2 cm wet bed) loses 3.1 % of its water by 0.53 s,
    # with or without the restart projection: the runner's 1 % water stop would end it at 0.37 s
    data["run"]["water_balance_limit"] = 0.05
    case = render(tmp_path, "held", data)
    plan = json.loads((case / "plan.json").read_text())
    hold = plan["bodies"][0]["hold_until_s"]
    assert plan["bed_gap_m"] == pytest.approx(0.015)
    assert 0.47 < hold < 0.52
    run_case(case, quiet=True)
    record = json.loads((case / "run.json").read_text())
    freed = [f["time_s"] for f in record.get("freed", [])]
    depth = pd.read_csv(case / "body_depth.csv").dropna(subset=["depth_m"])
    assert len(depth) > 40  # a reading every 0.01 s
    # held while the water measured all round it could not float it
    assert len(freed) == 1  # measured: freed at 0.418 s (49.0 mm all round, 46.3 mm needed; lift 3.85 N)
    held_until = freed[0]
    shallow = depth[(depth["depth_m"] <= depth["float_depth_m"]) & (depth["time_s"] < held_until)]
    assert shallow["time_s"].max() > 0.3 and all(shallow["constraint"] == "hold")
    tracks = pd.read_csv(case / "bodies.csv")
    held = tracks[tracks["time_s"] < held_until - 1e-9]
    assert len(held) > 10
    assert np.ptp(held["z_m"]) < 1e-9 and np.abs(held["w_m_s"]).max() < 1e-9  # neither sinks nor lifts
    # freed only once the water was deep enough all round and lifted it by its weight; then it rose
    at = depth[np.isclose(depth["time_s"], freed[0])].iloc[-1]
    assert at["depth_m"] > at["float_depth_m"] and at["lift_N"] >= at["weight_N"]
    assert tracks["z_m"].iloc[-1] > held["z_m"].iloc[-1] + 0.005
    bed_stops = [float(seg["end_time"]) for seg in record["segments"]
                 if any(c.get("other") == "bed" for c in seg.get("stopped_for", []))]
    assert all(t > held_until - 0.01 for t in bed_stops)  # no bed clamp while held
    mesh_dict = (case / "constant" / "dynamicMeshDict").read_text()
    assert "holdOnBedPlane" not in mesh_dict and "keepUpright" in mesh_dict  # freed, still upright
    tilt = tracks[["q_xz", "q_yz", "q_zx", "q_zy"]].abs().to_numpy().max()
    assert tilt < 1e-9  # an upright body never pitches or rolls
    written = sorted(float(p.name) for p in (case / "processor0").iterdir() if p.name[0].isdigit())
    for t in (0.05, 0.1, 0.3, 0.45):  # the regular writes are kept
        assert any(abs(w - t) < 1e-9 for w in written), (t, written)
    assert record["status"] == "finished"


@pytest.mark.openfoam
def test_a_pinned_body_stays_where_it_is(tmp_path, openfoam):
    """Debris held against an obstacle by the flow is pinned (point + orientation constraints):
    v1912 must keep it still although the bore pushes it."""
    case = render(tmp_path, "pinned", scene([{"name": "debris1", "centre_m": [0.7, 0.0]}], end_time_s=0.4))
    assert body_policy.pin_bodies(case, ["debris1"]) == ["debris1"]
    assert body_policy.pin_bodies(case, ["debris1"]) == []  # already pinned
    assert body_policy.pinned_bodies(case) == {"debris1"}
    run_case(case, quiet=True)
    tracks = pd.read_csv(case / "bodies.csv")
    start = bodystate.read_mesh_poses(case)[0].centre_of_mass_m
    assert len(tracks) > 10 and tracks["time_s"].max() > 0.39  # the bore passes it from about 0.3 s
    assert np.abs(tracks[["x_m", "y_m", "z_m"]].to_numpy() - np.asarray(start)).max() < 1e-9
    assert np.abs(tracks[["u_m_s", "v_m_s", "w_m_s"]].to_numpy()).max() < 1e-9
    assert json.loads((case / "run.json").read_text())["status"] == "finished"


@pytest.mark.openfoam
@pytest.mark.slow
def test_a_body_the_flow_keeps_pressing_against_the_column_is_pinned(tmp_path, openfoam):
    """A resting contact that comes back more than `max_events` times within `window_s` pins the body.

    debris1 floats with its nose 1 mm upstream of the column's face (x = 1.15 m) in water
    flowing at 0.25 m/s towards it: every restart finds it closing on the column again,
    slowly (a resting contact), until the runner pins it there. maxDeltaT is cut to 1 ms
    (a fine mesh's time step): at the tiny mesh's 6-10 ms steps a segment spans more
    simulated time than the window allows for seven contacts. On an idle machine the pin comes
    at about 0.023 s; the runner's stop latency grows with the load (each segment then spans
    more simulated time), so the run goes on to 0.15 s to leave room for the pin under load."""
    settings = ContactSettings()
    end = 0.15
    case = render(tmp_path, "pressed", scene([{"name": "debris1", "centre_m": [1.15 - 0.075 - 0.001, 0.0]}],
                                             end_time_s=end, wet_depth_m=0.1))
    set_fields = case / "system" / "setFieldsDict"
    text, n = re.subn(r"(// water: wetBed\s*boxToCell\s*\{\s*box [^;]*;\s*fieldValues\s*\()",
                      r"\1 volVectorFieldValue U (0.25 0 0)", set_fields.read_text())
    assert n == 1
    set_fields.write_text(text)
    control = case / "system" / "controlDict"
    text, n = re.subn(r"^maxDeltaT .*$", "maxDeltaT 0.001;", control.read_text(), flags=re.M)
    assert n == 1
    control.write_text(text)

    summary = run_case(case, quiet=True)
    assert summary.status == "finished"
    record = json.loads((case / "run.json").read_text())
    assert record["status"] == "finished"
    events = json.loads((case / "contacts.json").read_text())
    pin = events[-1]
    assert pin["type"] == "pinned" and pin["body"] == "debris1" and pin["other"] == "column"
    assert [e for e in events if e["type"] == "pinned"] == [pin]
    t_pin = pin["time_s"]
    # the contacts that made it: max_events of the same pair within the window before the pin
    before = [e for e in events[:-1] if e["time_s"] > t_pin - settings.window_s]
    assert len(before) == settings.max_events and record["resting_contacts"] >= len(before)
    assert {(e["type"], e["body"], e["other"]) for e in before} == {("resting", "debris1", "column")}
    assert record["pinned"] == [{"body": "debris1", "other": "column", "time_s": t_pin}]
    assert body_policy.pinned_bodies(case) == {"debris1"}
    # its only body pinned, the rest of the run has the overset flux adjustment on
    assert record["overset_adjust_phi_from_s"] == t_pin and _pimple(case)["oversetAdjustPhi"] is True
    # from the pin on the body does not move: its place at the pin, no velocity
    tracks = pd.read_csv(case / "bodies.csv")
    at_pin = tracks[np.isclose(tracks["time_s"], t_pin, rtol=0, atol=1e-9)]
    after = tracks[tracks["time_s"] > t_pin + 1e-9]
    assert len(at_pin) == 1 and len(after) > 10 and after["time_s"].max() == pytest.approx(end)
    position = ["x_m", "y_m", "z_m"]
    assert np.abs(after[position].to_numpy() - at_pin[position].to_numpy()).max() < 1e-9
    assert np.abs(after[["u_m_s", "v_m_s", "w_m_s", "omega_x_rad_s", "omega_y_rad_s",
                         "omega_z_rad_s"]].to_numpy()).max() < 1e-9
    assert _outside_everything(case, ["debris1"]) == []


def _pimple(case: Path) -> dict:
    """The PIMPLE dictionary of the case's system/fvSolution, as the solver reads it (foamlib)."""
    from foamlib import FoamFile

    return FoamFile(case / "system" / "fvSolution")["PIMPLE"].as_dict()


@pytest.mark.parametrize("name, digits", [("1.46272017", 9), ("0.1", 1), ("0", 1), ("1.2e-05", 2), ("3.5", 2)])
def test_significant_digits_of_a_time_name(name, digits):
    """The restart's timePrecision must reproduce the latest time directory's name."""
    from orchestrator.run.control import significant_digits

    assert significant_digits(name) == digits
