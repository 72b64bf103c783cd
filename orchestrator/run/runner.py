"""Running a rendered case: mesh, decompose, solve with live progress, stop, resume, contact events.

`run_case(case_dir)` takes a case written by `render` to a finished run:

1. the mesh steps of `foam.mesh_steps` (blockMesh, bodies, mergeMeshes, topoSet,
   setFields, checkMesh), each skipped when its outputs exist;
2. `decomposePar` (hierarchical, from system/decomposeParDict) when running on more
   than one rank; with two or more body meshes, that split goes through
   `orchestrator.case.split_bodies` first, so that no body mesh is whole on one rank;
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
`orchestrator.run.contact_book`'s (`ContactBook`, which the supervisor owns). After every
batch of log lines the runner asks the book which bodies will be within
`ContactSettings.gap_m` of the column, a flume wall, another body, or sink into the
bed, before the solver can stop (their closing speeds times the stop latency, a few
time steps, which the runner measures; it polls faster near an obstacle), and
schedules the stop or requests `writeNow`. From the written state the book resolves
the contacts and records them: impacts (`orchestrator.contact.resolution.resolve`: the MDOF
column, rigid walls, two-body impacts), slow "resting" contacts (a plastic impulse),
bodies the flow keeps pressing against an obstacle (pinned there), bodies sunk into
the bed (lifted back), overlaps (removed along the contact normal). The runner then
writes every body's new state (`bodystate.prepare_restart`: v1912 keeps one body's
state only) and resumes.

Bodies held still: while every body is stuck on the bed by static friction or pinned at an
obstacle, the runner sets their motion solvers aside for the segment (`held.hold_solvers`,
`ContactSettings.hold_still_solvers`): v1912 then builds the overset addressing once instead of
at every step. The log then reports no body; each step is given the held states (so bodies.csv,
the bed watch and the contact book see them as before), and the times such a segment wrote get
the motion files v1912 did not write (`held.fill_motion_files`) before the solvers come back.

Files the runner writes in the case: `run.json`; `log.<step>` (and `log.<solver>.<k>`
for earlier segments); `bodies.csv` (every body's state at every time step: time_s,
body, x_m.., u_m_s.., omega_*_rad_s, the orientation q_xx..q_zz); `bodystate.json`
(the states every restart used, and their source); through the contact book,
`contacts.json` (every event: impacts, resting contacts and pins), `impact_events.csv`
(one row per impact: time, bodies, point, normal, velocities in and out, obliquity, height,
peak force, duration, impulse, force history file) and `contacts/event<n>-force.csv`
(and `-base-shear.csv` for the column).
The function objects write `postProcessing/<name>/<start time>/`: one folder per
segment, to be read in time order.

Where the parts live: this module orders the steps and the segments and decides between
them (`run_case`); `orchestrator.run.supervisor` holds what lasts a run (run.json, the
contact book, the bed watch) and runs each segment through `orchestrator.run.segments`
(the solver process, its log, stop requests and kills); `orchestrator.run.control` edits
controlDict, `orchestrator.run.times` finds the written times and the write grid,
`orchestrator.run.run_json` keeps run.json and bodies.csv, `orchestrator.run.case_info`
reads the case, `orchestrator.run.errors` names the ways a run ends early, and
`orchestrator.run.openfoam` runs each mesh and utility application (its log, its failure).

Dictionaries (controlDict, decomposeParDict, dynamicMeshDict) are read and edited through
`orchestrator.case.dictionary` (foamlib): in place, at full precision, the file replaced at
once. What the runner does to the bodies is `orchestrator.run.body_policy` (through
dynamicMeshDict), `orchestrator.run.held` (their motion solvers set aside) and
`orchestrator.run.bodypoints` (their mesh points at a restart).

Units: seconds, metres, kg, N.
"""

from __future__ import annotations

import fcntl
import math
import signal
import threading
import time
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, Callable

from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.case import bodystate, foam
from orchestrator.case.folder import EPS_T, PLAN_JSON, SCENE_YAML, processor_dirs
from orchestrator.contact.settings import ContactSettings
from orchestrator.plan.scale import froude_factor
from orchestrator.run import body_policy, held, openfoam
from orchestrator.run.bedwatch import BedWatch
from orchestrator.run.bodypoints import BodyPoints
from orchestrator.run.case_info import CaseInfo, load_case_info
from orchestrator.run.contact_geometry import Contact
from orchestrator.run.control import set_control
from orchestrator.run.errors import ContactError, DivergenceError, RunError, RunInterrupted
from orchestrator.run.held import still_state
from orchestrator.run.monitor import Diagnosis, DivergenceLimits, Progress, StepRecord
from orchestrator.run.run_json import RunRecord, now, states_in_logs, versions
from orchestrator.run.segments import STOPPED_REASONS, SegmentResult, StopFlag
from orchestrator.run.supervisor import Supervisor
from orchestrator.run.times import MIN_SEGMENT_FRACTION, latest_time, remove_times_from, segment_span

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
    openfoam.StepError (a step failed), all DebrisfoamError.
    """
    if reconstruct not in ("latest", "all", "none"):
        raise InputError("reconstruct", f"must be 'latest', 'all' or 'none', got {reconstruct!r}")
    wall0 = time.perf_counter()
    lock = _lock_case(Path(case_dir))
    try:
        return _run_locked(case_dir, np, quiet, reconstruct, contact, limits, stop_event, poll_interval_s, stream,
                           on_step, wall0)
    finally:
        lock.close()


def _lock_case(case: Path):
    """An exclusive lock on the case (two runners on one case would corrupt it)."""
    if not case.is_dir():
        raise InputError("case_dir", "does not exist: render a case into it first", str(case))
    fh = open(case / ".debrisfoam-run.lock", "a+")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        fh.close()
        raise RunError(f"{case} is being run by another debrisfoam process; wait for it or stop it") from None
    return fh


def _run_locked(case_dir, np, quiet, reconstruct, contact, limits, stop_event, poll_interval_s, stream, on_step,
                wall0) -> RunSummary:
    rec = RunRecord(Path(case_dir).resolve())  # run.json, read once: the controls a dead runner left, the record
    info = _original_controls(load_case_info(case_dir, np), rec.data)
    case = info.case
    stop = StopFlag(stop_event)
    if contact is None:  # the defaults, at the case's scale (they were set on the study's 0.40 m flume)
        contact = ContactSettings().froude_scaled(froude_factor(info.water_depth_m) if info.water_depth_m > 0 else 1.0)
    sup = Supervisor(info, quiet, contact, limits or DivergenceLimits(), stop,
                     poll_interval_s, stream, on_step, rec)
    data = rec.data
    data.update({"case": str(case), "solver": info.solver, "ranks": info.ranks, "end_time_s": info.end_time_s,
                 "scene": SCENE_YAML, "plan": PLAN_JSON, "versions": versions()})
    data["control"] = {"endTime": info.end_time_s, "writeInterval": info.write_interval_s}
    data.setdefault("cells", {})["planned"] = info.planned_cells
    data.setdefault("started", now())
    _check_decomposition(case, info.ranks)

    reached, name = latest_time(case, info.ranks)
    if data.get("status") == "finished" and reached >= info.end_time_s - EPS_T:
        return _summary(info, rec, True, reached, time.perf_counter() - wall0)

    data["status"] = "running"
    data.pop("error", None)
    previous = data.pop("diagnosis", None)  # why the last run stopped, if it diverged
    rec.save()
    try:
        return _run_steps(info, sup, stop, quiet, reconstruct, stream, wall0, previous)
    except RunInterrupted:
        raise
    except DebrisfoamError as exc:  # recorded, then raised for the CLI to report
        if data.get("status") == "running":
            data["status"], data["error"] = "failed", str(exc)
            rec.save()
        raise


def _run_steps(info: CaseInfo, sup: Supervisor, stop: StopFlag, quiet: bool, reconstruct: str, stream,
               wall0: float, previous: dict[str, Any] | None = None) -> RunSummary:
    """The mesh and decomposition steps, the solver's segments to the end time, reconstructPar."""
    _prepare(info, sup)
    handlers = _install_handlers(stop)
    progress = None
    try:
        reached, name = latest_time(info.case, info.ranks)
        progress = Progress(info.end_time_s, reached, quiet, label=f"{info.solver} {info.case.name}", stream=stream)
        sup.progress = progress
        while reached < info.end_time_s - EPS_T:
            _before_segment(info, sup, reached, name, previous)
            previous = None
            seg = sup.solve_segment(reached, name, progress)
            after = _after_segment(info, sup, stop, seg, reached, name)
            if after is None:
                break
            reached, name = after
    finally:
        if progress is not None:
            progress.close()
        sup.progress = None
        _restore_handlers(handlers)
    return _finish(info, sup, reconstruct, reached, name, wall0)


def _prepare(info: CaseInfo, sup: Supervisor) -> None:
    """The split for --np, mesh, checkMesh's cell count, decomposePar; the scene's obstacles and the bed watch."""
    case, data = info.case, sup.record.data
    steps = foam.decompose_steps(case, info.plan, info.ranks)
    # the planned split follows --np: decomposeParDict along x when --np differs (noted in run.json)
    planned = foam.set_subdomains(case, info.ranks) if steps and not steps[0].done(case) else None
    if planned is not None:
        data["decomposition_note"] = (f"--np {info.ranks} instead of the planned {planned}: hierarchical "
                                      f"({info.ranks} 1 1); decomposePar still keeps each body mesh on one rank "
                                      "(preserveFaceZones), at some cost in balance")
    for step in foam.mesh_steps(case, info.plan):
        sup.run_step(step)
    mesh_log = case / "log.checkMesh"
    if mesh_log.is_file():
        try:
            summary = openfoam.check_mesh_summary(mesh_log)
            data["cells"].update({"total": summary.cells, "mesh_ok": summary.ok})
        except openfoam.StepError:
            pass
    for step in steps:
        sup.run_step(step)

    if info.bodies:  # scene, obstacles, imports: once, before the solver competes for the cores
        t_setup = time.perf_counter()
        sup.book.geometry
        sup.bedwatch = BedWatch.for_case(case, sup.contact.float_margin_m, sup.say,
                                         friction=sup.contact.bed_friction)
        sup.between_s += time.perf_counter() - t_setup


def _before_segment(info: CaseInfo, sup: Supervisor, reached: float, name: str,
                    previous: dict[str, Any] | None) -> None:
    """At a restart: holds due, the bodies' states, contacts resolved, bodies on the bed freed."""
    case, data = info.case, sup.record.data
    # a release closer than a tenth of a write interval is due now: a stop lands on a
    # written time name (rounded), and v1912 may not take a step over what remains
    due = [] if sup.bedwatch is not None else [
        b for b, t in info.holds if t <= reached + MIN_SEGMENT_FRACTION * info.write_interval_s]
    for body in body_policy.release_holds(case, due):
        sup.say(f"t = {name} s: {body} released from the bed (the bore is deep enough to lift it)")
    states = sup.restore_bodies(name)
    if states and sup.contact.enabled:
        t_between = time.perf_counter()
        if previous is not None:  # resumed after a divergence: mend its cause if the book can
            sup.book.after_divergence(previous, name, states)
        events, resolved = sup.book.resolve_contacts(name, states, sup.stop_horizon_s)
        if resolved != states:
            bodystate.prepare_restart(case, name, resolved, "contact")
        if events:
            data["contacts"] = data.get("contacts", 0) + events
        states = resolved
        sup.between_s += time.perf_counter() - t_between
    if states and sup.bedwatch is not None:  # after the book: it may have put a body to rest
        freed, raised = sup.bedwatch.at_restart(name, states)
        if raised != states:
            bodystate.prepare_restart(case, name, raised, "freed")
        for body in freed:
            data.setdefault("freed", []).append({"body": body, "time_s": float(name)})
        sup.record.save()
        states = raised
    if states:
        _points_follow(info, sup, name, states)
    sup.start_states = states
    _hold_still(info, sup, states, name)


def _points_follow(info: CaseInfo, sup: Supervisor, name: str, states: list) -> None:
    """The body meshes' points written at `name` put where the restart's states put the bodies
    (`BodyPoints.follow`): a body the contact book or the bed watch moved would otherwise make
    the whole move in the solver's first step, as mesh motion the water answers."""
    t_between = time.perf_counter()
    if sup.body_points is None:
        try:
            sup.body_points = BodyPoints.for_case(info.case)
        except (OSError, ValueError) as exc:
            sup.body_points = False
            sup.say(f"the body meshes' points cannot follow their bodies ({exc}): a body the runner moves at a "
                    "restart makes that move in the solver's first step")
    if not sup.body_points:
        return
    moved = sup.body_points.follow(name, states)
    if moved:
        data = sup.record.data
        data["points_moved"] = data.get("points_moved", 0) + len(moved)
    sup.between_s += time.perf_counter() - t_between


def _hold_still(info: CaseInfo, sup: Supervisor, states: list, name: str) -> None:
    """Every body held still (stuck on the bed or pinned at an obstacle): set their motion
    solvers aside for the segment (`held.hold_solvers`: v1912 then builds the overset
    addressing once instead of every step) and report their states to the watch; otherwise put
    the solvers back."""
    if not info.bodies:
        return
    all_held = (sup.contact.hold_still_solvers and bool(states)
                and body_policy.still_bodies(info.case) >= {s.name for s in states})
    if sup.watch.held is not None or held.solvers_held(info.case):  # (or resumed while held)
        held.fill_motion_files(info.case)  # the times written while held lack the motion files
    if held.hold_solvers(info.case, all_held):
        sup.say(f"t = {name} s: " + ("every body held still: their motion solvers set aside until one moves"
                                     if all_held else "a body moves again: motion solvers back"))
    sup.watch.held = tuple(still_state(s) for s in states) if all_held else None
    sup.record.data["held_segments"] = sup.record.data.get("held_segments", 0) + int(all_held)


#: how many times a segment from one written time may end on a missed contact stop before the run fails
MAX_MISSED_STOPS = 3


def missed_contact_stop(seg: SegmentResult) -> bool:
    """The solver ended by itself (exit 0, no stop of the runner's own) with a contact stop pending:
    it read the stop the runner scheduled for the contact only once it had passed, or come within
    half a step of, that time, and v1912 then ends the run there without writing (its half-step
    rule). Seen once in the 1x3 layout two-way: a second, earlier contact stop requested while the
    solver's step grew from 2.3e-3 to 3.4e-3 s; the solver ended at 2.2429 s, 0.022 s past its last
    write."""
    return seg.reason == "end" and seg.returncode == 0 and bool(seg.contacts) and bool(seg.steps)


def retries_left(misses: list[dict], name: str) -> bool:
    """Whether a segment from the written time `name` may run again after a missed contact stop:
    fewer than MAX_MISSED_STOPS of the recorded `misses` (run.json `missed_stops`) started there."""
    return sum(1 for m in misses if m["from"] == name) < MAX_MISSED_STOPS


def _retry_missed_stop(sup: Supervisor, name: str, seg: SegmentResult) -> bool:
    """Run again from the last written time after a missed contact stop (what the segment ran is
    lost, the contact is found again from the written states), at most MAX_MISSED_STOPS times
    from one written time; recorded in run.json `missed_stops`. False: give up."""
    misses = sup.record.data.setdefault("missed_stops", [])
    if not retries_left(misses, name):
        return False
    misses.append({"from": name, "solver_ended_s": seg.steps[-1].time_s,
                   "pending": [f"{c.body}-{c.other}" for c in seg.contacts]})
    sup.record.save()
    sup.say(f"t = {name} s: the solver passed the contact stop scheduled for {seg.contacts[0].body} and "
            f"{seg.contacts[0].other} and ended at {seg.steps[-1].time_s:.6g} s without writing; running "
            "again from the last written time")
    return True


def _after_segment(info: CaseInfo, sup: Supervisor, stop: StopFlag, seg: SegmentResult, reached: float,
                   name: str) -> tuple[float, str] | None:
    """The latest written time after `seg`, or None when the end is reached (v1912's half-step
    rule); raises for a diverged, failed or stopped segment and for one that wrote nothing."""
    case, data = info.case, sup.record.data
    if seg.diagnosis is not None or (seg.returncode not in (0, None) and
                                     (seg.parser.fpe or seg.returncode == 136)):
        _fail_diverged(sup, seg, reached)
    if seg.returncode != 0 and seg.reason not in STOPPED_REASONS:
        text = seg.log.read_text(errors="replace")
        err = openfoam.StepError(info.solver, openfoam.failure_reason(text), seg.log, seg.returncode)
        data["status"], data["error"] = "failed", str(err)
        sup.record.save()
        raise err
    new_reached, new_name = latest_time(case, info.ranks)
    if seg.reason in STOPPED_REASONS and new_reached < info.end_time_s - EPS_T:
        data["status"] = "interrupted"
        sup.record.save()
        raise RunInterrupted(case, stop.signum, new_name if new_reached > 0 else None,
                             clean=seg.reason == "interrupt" and seg.returncode == 0,
                             before_first_step=seg.reason == "unstarted")
    if new_reached <= reached + EPS_T:
        if not seg.steps and info.end_time_s - reached < MIN_SEGMENT_FRACTION * sup.write_interval_s:
            # v1912's half-step rule: what remains of the end time is less than a step
            return None
        if missed_contact_stop(seg) and _retry_missed_stop(sup, name, seg):
            return reached, name
        raise RunError(f"the solver ended without writing beyond t = {name} s; see {seg.log}")
    return new_reached, new_name


def _finish(info: CaseInfo, sup: Supervisor, reconstruct: str, reached: float, name: str,
            wall0: float) -> RunSummary:
    """No body left inside an obstacle, reconstructPar, and the run recorded as finished."""
    case, data = info.case, sup.record.data
    if info.bodies:
        _assert_outside(info, case, name, sup)
        if sup.watch.held is not None:  # the last segment held every body still: the case as a moving one again
            held.fill_motion_files(case)
            held.hold_solvers(case, False)
    if info.ranks > 1 and reconstruct != "none":
        step = foam.Step("reconstructPar", ("reconstructPar",), "gather the time directories")
        extra = ["-latestTime"] if reconstruct == "latest" else []
        sup.run_step(step, 1, extra + ["-newTimes"])
    data["status"] = "finished"
    data["reached_time_s"] = reached
    data["finished"] = now()
    solver_wall = sum(s["wall_s"] for s in data["segments"])
    cpu = sum(s.get("runner_cpu_s", 0.0) for s in data["segments"])
    data.setdefault("runner", {}).update({"solver_wall_s": round(solver_wall, 3), "cpu_s": round(cpu, 3),
                                          "between_segments_s": round(sup.between_s, 3),
                                          "overhead_fraction": round(cpu / solver_wall, 5) if solver_wall else 0.0})
    sup.record.save()
    return _summary(info, sup.record, False, reached, time.perf_counter() - wall0)


def _original_controls(info: CaseInfo, data: dict[str, Any]) -> CaseInfo:
    """The case's own endTime/writeInterval/maxDeltaT: a runner that died during a segment left the
    segment's values in controlDict (``data``, run.json, says which); otherwise controlDict's (a user
    may have changed endTime to extend a run)."""
    seg, own = data.get("segment_control"), data.get("control")
    if seg and own and math.isclose(seg["endTime"], info.end_time_s) and math.isclose(
            seg["writeInterval"], info.write_interval_s):
        max_dt = float(seg.get("maxDeltaT", info.max_delta_t_s))  # the case's own, not a segment's cap
        set_control(info.case, stopAt="endTime", endTime=own["endTime"], writeInterval=own["writeInterval"],
                    maxDeltaT=max_dt)
        return replace(info, end_time_s=float(own["endTime"]), write_interval_s=float(own["writeInterval"]),
                       max_delta_t_s=max_dt)
    return info


def _summary(info: CaseInfo, rec: RunRecord, already: bool, reached: float, wall: float) -> RunSummary:
    data = rec.data
    segs = data.get("segments", [])
    solver_wall = sum(s["wall_s"] for s in segs)
    cpu = sum(s.get("runner_cpu_s", 0.0) for s in segs)
    return RunSummary(
        case=info.case, status=data.get("status", "unknown"), already_finished=already, end_time_s=info.end_time_s,
        reached_time_s=reached, time_steps=int(data.get("time_steps", 0)), segments=len(segs),
        contacts=int(data.get("contacts", 0)), wall_s=wall, solver_wall_s=solver_wall, runner_cpu_s=cpu,
        overhead_fraction=cpu / solver_wall if solver_wall else 0.0, run_json=rec.path)


def _check_decomposition(case: Path, ranks: int) -> None:
    procs = processor_dirs(case)
    if ranks > 1 and procs and len(procs) != ranks:
        raise RunError(f"{case} is decomposed for {len(procs)} ranks, not {ranks}: run with --np {len(procs)} "
                       f"(or delete the processor* directories to start again)")
    if ranks == 1 and procs:
        raise RunError(f"{case} is decomposed for {len(procs)} ranks: run with --np {len(procs)}")


def _fail_diverged(sup: Supervisor, seg: SegmentResult, start_value: float) -> None:
    info, case, data = sup.info, sup.case, sup.record.data
    diag = seg.diagnosis
    if diag is None:  # the solver died of a floating point exception itself
        t = seg.parser.current_time_s
        diag = Diagnosis("fpe", "floating point exception (sigFpe) in the solver", t, t)
    if diag.since_s is not None:
        remove_times_from(case, info.ranks, diag.since_s, start_value)
    _, good = latest_time(case, info.ranks)
    data["status"] = "stalled" if diag.kind == "stall" else "diverged"
    data["diagnosis"] = {"kind": diag.kind, "cause": diag.cause, "time_s": diag.time_s, "last_good_time": good,
                         "log": seg.log.name}
    if diag.body is not None:
        data["diagnosis"].update(body=diag.body, velocity_m_s=list(diag.velocity_m_s or ()))
    sup.record.save()
    raise DivergenceError(diag.kind, diag.cause, diag.time_s, good, seg.log)


def _assert_outside(info: CaseInfo, case: Path, name: str, sup: Supervisor) -> None:
    """A finished run must not leave a body inside the column, a wall or another body."""
    states = states_in_logs(case, info.solver, info.body_names, name)
    if states is None:
        return
    inside = [c for c in sup.book.geometry.contacts(states, 0.0, bed=False) if c.distance_m < 0]
    if inside:
        c = inside[0]
        raise ContactError(f"{c.body} ends the run {-c.distance_m * 1000:.3g} mm inside {c.other} at t = {name} s")


def _install_handlers(stop: StopFlag):
    if threading.current_thread() is not threading.main_thread():
        return None
    return {sig: signal.signal(sig, stop.handler) for sig in (signal.SIGINT, signal.SIGTERM)}


def _restore_handlers(handlers) -> None:
    if handlers:
        for sig, old in handlers.items():
            signal.signal(sig, old)
