"""Contact bookkeeping of a run: which contacts stop the solver, how each is resolved, and the event record.

The runner (`orchestrator.run.runner`) drives the solver; after every batch of log lines and
at every restart it asks a `ContactBook` about the bodies' states. Geometry and impacts
are `orchestrator.contact.geometry`'s (the scene's column, walls and bed, exact box-box
distances, `clamp_to_bed`) and `orchestrator.contact.resolution`'s (`resolve`: the MDOF
column, rigid walls, two-body impacts, from `analytical.impact`), seen through
`orchestrator.run.contact_geometry` (`Geometry`: the case's obstacles and bodies, and each
contact's closing speed, `Contact`). This module adds what the runner needs on top:

- while the solver runs (`ContactBook.contacts_ahead`, `time_to_act`): the contacts
  the bodies will reach within a few stop latencies, and the simulated time until each
  needs the solver stopped: an impact when the body reaches `ContactSettings.gap_m`, a
  slow (resting) contact at a quarter of the gap, the bed once a body has sunk the bed
  tolerance into it;
- at a restart (`ContactBook.resolve_contacts`): every contact that would stop the
  solver at once is resolved: impacts by `orchestrator.contact.resolution.resolve`, slow contacts
  (closing slower than `min_impact_speed_m_s`) by a plastic impulse (`resting_contact`),
  a body the flow keeps pressing against an obstacle (more than `max_events` contacts
  within `window_s`) is pinned there (`body_policy.pin_bodies`), two bodies it keeps
  pressing together have every contact made plastic until they are two gaps apart (such a
  pair is set the whole gap apart and stops the solver again only at a quarter of it); two
  bodies in any other resting contact are set half the gap apart (a position correction that
  keeps their momentum); bodies are lifted out of the bed and any overlap left is removed along the
  contact normal;
- the record: `contacts.json` (every event: impacts, resting contacts, pins),
  `impact_events.csv` (one row per impact) and `contacts/event<n>-force.csv` (and
  `-base-shear.csv` for the column), in the case, written through
  `orchestrator.contact.events`; counts in run.json's data
  (`resting_contacts`, `bed_clamps`, `pinned`), which the runner saves. Events later
  than a restart's time are forgotten (`forget_events_after`): that stretch is
  computed again. A run resumed by a new process reads the book's memory (each pair's recent
  contacts, the pairs pressed together) back from `contacts.json`.

The book knows nothing of the solver: the runner gives it the case (`CaseInfo`), the
settings (`ContactSettings`), run.json's data, a `say` callable for messages and, with
each question, how far the solver may run on after a stop request (the stop horizon,
simulated seconds).

Units: seconds, metres, kg, N.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable, Sequence

import numpy as np

from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import EPS_T
from orchestrator.contact.events import (
    append_impact_event,
    forget_impact_events_after,
    read_events,
    write_events,
    write_pulse_files,
)
from orchestrator.contact.settings import ContactSettings
from orchestrator.run import body_policy
from orchestrator.run.case_info import CaseInfo
from orchestrator.run.contact_geometry import Contact, Geometry, resting_contact
from orchestrator.run.errors import ContactError
from orchestrator.run.monitor import StepRecord

__all__ = ["ContactBook", "PRESSED_PASSES", "PRESSED_RUNAWAY"]

#: two bodies in contact more than this many times `max_events` within `window_s`, each
#: contact already plastic and the pair set apart: a ContactError (see `_resting_too_often`)
PRESSED_RUNAWAY = 4
#: pressed pairs of a train set apart at one restart, at most (`ContactBook._separate_pressed`)
PRESSED_PASSES = 8


# --------------------------------------------------------------------------- the book


def _pair(c: Contact) -> tuple[str, str]:
    """The two names of a contact, sorted: a pair whichever body the contact names first."""
    return (c.body, c.other) if c.body <= c.other else (c.other, c.body)


class ContactBook:
    """The contact bookkeeping of one run (see the module notes).

    info: the case. settings: ContactSettings. run_record: run.json's data, where the
    book counts resting contacts, bed clamps and pins (the runner saves it). say: prints
    a message for the user (the runner's, above its progress bar).
    """

    def __init__(self, info: CaseInfo, settings: ContactSettings, run_record: dict[str, Any],
                 say: Callable[[str], None]):
        self.info = info
        self.case = info.case
        self.settings = settings
        self.run_record = run_record
        self.say = say
        self._geometry: Geometry | None = None
        #: simulated times of the contacts of each (body, other) pair, within the window
        self._pair_events: dict[tuple[str, str], list[float]] = {}
        #: body pairs found pressed together (names sorted): their contacts are plastic and
        #: stop the solver only at a quarter of the gap, until they are two gaps apart again
        self._pressed_pairs: set[tuple[str, str]] = set()
        #: a book made for a run that resumes reads the two above back from the record at its
        #: first restart (`forget_events_after`), so that the resumed run goes on as it would have
        self._fresh = True

    @property
    def geometry(self) -> Geometry:
        """The scene's obstacles and the case's bodies, built on first use (scene, imports)."""
        if self._geometry is None:
            self._geometry = Geometry(self.info)
        return self._geometry

    # ---- while the solver runs
    def contacts_ahead(self, step: StepRecord, latency_steps: int) -> list[tuple[Contact, float]]:
        """Contacts the bodies of `step` will need within three stop latencies (`latency_steps`
        time steps each), each with the simulated time from `step` until it needs the
        solver stopped (linear in the present closing speed)."""
        dt = step.delta_t_s or self.info.delta_t_s
        horizon = dt * latency_steps
        speed = max(b.speed_m_s for b in step.bodies)
        near = self.geometry.contacts(step.bodies, self.settings.gap_m + 2 * speed * 4 * horizon + 1e-9,
                                      bed=self.settings.bed)
        ahead = []
        for c in near:
            wait = self.time_to_act(c)
            if wait is not None and wait <= 3 * (horizon + dt):
                ahead.append((c, wait))
        return ahead

    def time_to_act(self, c: Contact) -> float | None:
        """Simulated time until `c` needs the solver stopped (0: now), None if never at this speed:
        an impact when the gap is reached, a resting contact at a quarter of the gap, the bed
        when the body has sunk the bed tolerance into it."""
        closing = c.approach_m_s
        if c.kind == "bed":
            limit = -self.settings.bed_sink_m
        elif closing >= self.settings.min_impact_speed_m_s and not self._held_pressed(c):
            limit = self.settings.gap_m
        else:
            limit = 0.25 * self.settings.gap_m
        if c.distance_m <= limit:
            return 0.0 if closing > 0 or c.kind == "bed" else None
        if closing <= 0:
            return None
        return (c.distance_m - limit) / closing

    def classify(self, c: Contact, horizon_s: float) -> str | None:
        """What a contact needs before the solver could next stop (`horizon_s`):

        "impact": closing at >= min_impact_speed and within the gap; "resting": closing
        slower (or a pair pressed together, at any speed), within a quarter of the gap; "bed":
        sunk more than the bed tolerance into the bed; None: nothing yet."""
        closing = max(c.approach_m_s, 0.0)
        ahead = c.distance_m - closing * horizon_s
        if c.kind == "bed":
            return "bed" if ahead <= -self.settings.bed_sink_m else None
        if closing <= 0:
            return None
        if (closing >= self.settings.min_impact_speed_m_s and ahead <= self.settings.gap_m
                and not self._held_pressed(c)):
            return "impact"
        if ahead <= 0.25 * self.settings.gap_m:
            return "resting"
        return None

    def step_cap_s(self, states: Sequence[BodyState], latency_steps: int, max_delta_t_s: float) -> float | None:
        """The largest deltaT (s) with which the watch sees every contact of `states` in time,
        or None when the case's own `max_delta_t_s` does.

        The runner acts on a contact `latency_steps` steps after the step that shows it, and
        sees only the closest point of each pair: a turning body can bring another corner in
        while that point is still at rest or receding. Within reach of an obstacle, a point of
        a body moves at most ``u_n + |omega| R`` towards it (``u_n`` the closing speed of the
        closest point, ``R`` the body's half-diagonal; for two bodies, both), so steps of
        ``gap / ((latency + 1) (u_n + |omega| R))`` keep every corner out of the obstacle
        until the runner has stopped the solver: the gap is crossed in no fewer steps than
        the runner needs. `max_delta_t_s` / 100 is the floor (a stuck body must not stall
        the run)."""
        if not states:
            return None
        geometry, gap = self.geometry, self.settings.gap_m
        by_name = {s.name: s for s in states}

        def sweep(name: str) -> float:  # |omega| R of a body (m/s)
            s = by_name[name]
            return float(np.linalg.norm(s.angular_velocity_rad_s)) * 0.5 * float(np.linalg.norm(geometry.sizes[name]))

        window = (latency_steps + 1) * max_delta_t_s
        reach = gap + window * max(s.speed_m_s + sweep(s.name) for s in states)
        cap = math.inf
        for c in geometry.contacts(states, reach, bed=False):
            bound = max(c.approach_m_s, 0.0) + sweep(c.body) + (sweep(c.other) if c.kind == "body" else 0.0)
            if bound > 0.0 and c.distance_m - gap <= window * bound:  # could reach the gap in one window
                cap = min(cap, gap / ((latency_steps + 1) * bound))
        if not cap < max_delta_t_s:
            return None
        return max(cap, max_delta_t_s / 100.0)

    # ---- at a restart
    def contacts_now(self, states: Sequence[BodyState], horizon_s: float) -> list[Contact]:
        """Contacts at a restart that would stop the solver at once (the rule used while
        running, with the stop horizon `horizon_s` of the last segment), closest first."""
        speed = max(s.speed_m_s for s in states)
        near = self.geometry.contacts(states, self.settings.gap_m + 2 * speed * horizon_s + 1e-9, bed=False)
        return sorted((c for c in near if self.classify(c, horizon_s)), key=lambda c: c.distance_m)

    def resolve_contacts(self, time_name: str, states: list[BodyState],
                         horizon_s: float) -> tuple[int, list[BodyState]]:
        """At a restart: resolve every contact that would stop the solver at once (impacts
        with orchestrator.contact.resolution.resolve, slow ones as resting contacts, pins), lift bodies
        out of the bed, and move any body still overlapping an obstacle out of it. Records
        the events; returns (impacts, the states to restart with). `horizon_s`: how far the
        solver ran on after a stop request (the last deltaT times the stop latency)."""
        geometry = self.geometry
        self._fresh = False
        by_name = {s.name: s for s in states}
        events = 0
        done: set[str] = set()
        for c in self.contacts_now(states, horizon_s):
            if c.body in done or c.other in done:
                continue  # one impact per body per restart; a second one is found at the next
            pressed = self._resting_too_often(c, float(time_name))
            if pressed and c.kind != "body":
                by_name[c.body] = self._pin(time_name, c, by_name[c.body])
                done.add(c.body)
                continue
            pressed = pressed or self._held_pressed(c)
            if pressed or self.classify(c, horizon_s) == "resting":
                # two bodies are set apart: left where they touch, the next closing motion would
                # stop the solver again within a step or two. A pressed pair is set the whole gap
                # apart and stops the solver again only at a quarter of it (`classify`): the
                # flow closes 0.75 of the gap between restarts, not a fraction of a millimetre
                if c.kind == "body":
                    apart = self.settings.gap_m if pressed else 0.5 * self.settings.gap_m
                else:
                    apart = 0.0
                new, impulse = resting_contact(geometry, c, by_name, separation_m=apart)
                before = {k: by_name[k] for k in new}
                by_name.update(new)
                done.update({c.body, c.other})
                self._record_resting(time_name, c, before, new, impulse, pressed=pressed)
                if pressed and _pair(c) not in self._pressed_pairs:
                    self._pressed_pairs.add(_pair(c))
                    self.say(f"t = {time_name} s: the flow presses {c.body} and {c.other} together "
                             f"({self.settings.max_events + 1} contacts within {self.settings.window_s:g} s): "
                             "their contacts are plastic until they are two gaps apart, not impacts")
                continue
            result, new = geometry.resolve(c, by_name, self.settings)
            before = {k: by_name[k] for k in new}
            by_name.update(new)
            if result is None:  # separating after all: only an overlap was removed
                continue
            events += 1
            done.update({c.body, c.other})
            self._record_event(time_name, c, before, new, result)
        if self.settings.bed:
            for name in list(by_name):
                sunk = by_name[name]
                lifted = geometry.clamp_to_bed(sunk)
                if lifted is not sunk:
                    by_name[name] = lifted
                    self.run_record["bed_clamps"] = self.run_record.get("bed_clamps", 0) + 1
                    lifts = self._count_in_window((name, "bed"), float(time_name))
                    sinking = -float(sunk.velocity_m_s[2])
                    if sinking > self.settings.bed_runaway_m_s:
                        self._rest_on_bed(time_name, lifted, f"it sank into the bed at {sinking:.3g} m/s")
                    elif lifts > self.settings.max_events:
                        self._rest_on_bed(time_name, lifted, f"it was lifted out of the bed {lifts} times within "
                                                             f"{self.settings.window_s:g} s")
        self._separate_pressed(time_name, by_name)
        for c in geometry.contacts(list(by_name.values()), 0.0, bed=False):
            if c.distance_m < 0:  # never restart a body inside the column, a wall or another body
                new, _ = resting_contact(geometry, dataclasses.replace(c, approach_m_s=0.0), by_name)
                by_name.update(new)
                self.say(f"{c.body} overlapped {c.other} by {-c.distance_m * 1000:.3g} mm at t = {time_name} s: "
                         "moved out along the contact normal")
        self._release_pressed(time_name, list(by_name.values()))
        return events, [by_name[n] for n in self.info.body_names]

    def _separate_pressed(self, time_name: str, by_name: dict[str, BodyState]) -> None:
        """Pressed pairs that share a body, set apart together: a train of bodies the flow presses
        end to end. Setting one pair the gap apart moves their shared body into its other
        neighbour, which one contact per body per restart would leave for the next restart,
        three steps later (the 3x1 layout two-way: each restart set one pair apart and closed
        the other). Up to `PRESSED_PASSES` times, the closest pressed pair nearer than 0.9 of the gap
        is made plastic and set the gap apart, and the distances are measured again (Gauss-Seidel
        over the chain: the closing motions end in the train's common velocity along each normal)."""
        if not self._pressed_pairs:
            return
        for _ in range(PRESSED_PASSES):
            close = [c for c in self.geometry.contacts(list(by_name.values()), 0.9 * self.settings.gap_m, bed=False)
                     if self._held_pressed(c)]
            if not close:
                return
            c = min(close, key=lambda c: c.distance_m)  # then measured again: it moves a neighbour
            new, impulse = resting_contact(self.geometry, c, by_name, separation_m=self.settings.gap_m)
            before = {k: by_name[k] for k in new}
            by_name.update(new)
            self._record_resting(time_name, c, before, new, impulse, pressed=True)

    def _held_pressed(self, c: Contact) -> bool:
        """Whether `c` is between two bodies found pressed together and not yet apart."""
        return c.kind == "body" and _pair(c) in self._pressed_pairs

    def _release_pressed(self, time_name: str, states: Sequence[BodyState]) -> None:
        """Pressed pairs more than two gaps apart at a restart have impacts again."""
        if not self._pressed_pairs:
            return
        near = {_pair(c) for c in self.geometry.contacts(states, 2.0 * self.settings.gap_m, bed=False)
                if c.kind == "body"}
        for pair in sorted(self._pressed_pairs - near):
            self._pressed_pairs.discard(pair)
            self.say(f"t = {time_name} s: {pair[0]} and {pair[1]} are apart: their contacts are impacts again")

    def after_divergence(self, diagnosis: dict[str, Any], time_name: str, states: Sequence[BodyState]) -> None:
        """Resuming a run the body-speed check stopped (run.json's last `diagnosis`): if the
        body was going mostly straight down, faster than `bed_runaway_m_s`, it was being pulled
        into the bed (see `_rest_on_bed`), so it rests on the bed from the restart on. The lifts
        that would show it at a restart are not seen again when the run restarts from the
        last good time, before them."""
        if diagnosis.get("kind") != "body_speed" or not self.settings.bed:
            return
        name, velocity = diagnosis.get("body"), diagnosis.get("velocity_m_s")
        by_name = {s.name: s for s in states}
        if name not in by_name or not velocity or len(velocity) != 3:
            return
        vx, vy, vz = (float(v) for v in velocity)
        if -vz > self.settings.bed_runaway_m_s and -vz >= math.hypot(vx, vy):
            self._rest_on_bed(time_name, by_name[name], f"the last run stopped with it sinking at {-vz:.3g} m/s "
                                                        f"(t = {diagnosis.get('time_s')} s)")

    def _resting_too_often(self, c: Contact, t: float) -> bool:
        """More than `max_events` contacts of this pair within `window_s`: the flow holds the
        body against the obstacle or the other body (a resting contact the event model cannot
        represent as impacts). Against an obstacle the body is then pinned; two bodies are
        pressed together: each of their contacts is plastic (`resolve_contacts`) while it lasts.
        More than `PRESSED_RUNAWAY` times `max_events` within the window is a ContactError: the
        pair would stop the solver every step or two."""
        n = self._count_in_window((c.body, c.other), t)
        if n <= self.settings.max_events:
            return False
        if c.kind == "body" and n > PRESSED_RUNAWAY * self.settings.max_events:
            raise ContactError(
                f"{c.body} and {c.other} stopped the solver {n} times within {self.settings.window_s:g} s of "
                f"simulated time (t = {t:.6g} s) although each contact was made plastic and the pair set "
                f"{self.settings.gap_m * 1000:g} mm apart: two bodies pressed together harder than "
                "event-driven contact can follow")
        return True

    def _count_in_window(self, key: tuple[str, str], t: float) -> int:
        """Record a contact of the pair `key` at `t`; how many it had within `window_s` up to `t`."""
        times = [x for x in self._pair_events.get(key, []) if x > t - self.settings.window_s]
        times.append(t)
        self._pair_events[key] = times
        return len(times)

    def _rest_on_bed(self, time_name: str, state: BodyState, why: str) -> None:
        """Keep a body the flow keeps pulling into the bed on it (`body_policy.rest_on_bed`).

        Each lift out of the bed moves the body mesh at the next step, and the flux of that
        jump pulls the body down harder: on the short flume the closing speed doubled from
        lift to lift (0.7, 1.4, 3.4, 7.5 m/s) until the body-speed check stopped the run.
        Constrained to the bed's plane the body still slides and yaws (with bed friction), but
        cannot sink; `orchestrator.run.bedwatch` raises it onto the gap's top and frees it once the water
        measured around it can carry it (recorded, and said)."""
        if not body_policy.rest_on_bed(self.case, [state.name]):
            return
        events = read_events(self.case)
        events.append({"event": len(events) + 1, "type": "rest_on_bed", "time_s": float(time_name),
                       "body": state.name, "other": "bed", "kind": "bed", "why": why,
                       "point_m": list(state.centre_of_mass_m), "normal": [0.0, 0.0, 1.0],
                       "velocity_in_m_s": list(state.velocity_m_s)})
        write_events(self.case, events)
        self.run_record.setdefault("rest_on_bed", []).append({"body": state.name, "time_s": float(time_name)})
        self.say(f"t = {time_name} s: {state.name}: {why}: kept on the bed (it slides and yaws, but cannot "
                 "sink) until the water measured around it can carry it")

    def _pin(self, time_name: str, c: Contact, state: BodyState) -> BodyState:
        """Freeze a body the flow keeps pressing against an obstacle (debris damming), record it."""
        body_policy.pin_bodies(self.case, [c.body])
        pinned = state.with_changes(velocity_m_s=(0.0, 0.0, 0.0), angular_velocity_rad_s=(0.0, 0.0, 0.0),
                                    acceleration_m_s2=(0.0, 0.0, 0.0))
        events = read_events(self.case)
        events.append({"event": len(events) + 1, "type": "pinned", "time_s": float(time_name), "body": c.body,
                       "other": c.other, "kind": c.kind, "gap_m": c.distance_m, "point_m": list(c.point_m),
                       "normal": list(c.normal), "velocity_in_m_s": list(state.velocity_m_s)})
        write_events(self.case, events)
        self.run_record.setdefault("pinned", []).append({"body": c.body, "other": c.other, "time_s": float(time_name)})
        self.say(f"t = {time_name} s: {c.body} is held against {c.other} by the flow "
                 f"({self.settings.max_events + 1} contacts within {self.settings.window_s:g} s): pinned there for the "
                 "rest of the run (debris damming; its hydrodynamic load then reaches the column through it, "
                 "which the column's force history does not include)")
        if self.settings.adjust_phi_when_pinned:
            self._adjust_phi_if_all_pinned(time_name)
        return pinned

    def _adjust_phi_if_all_pinned(self, time_name: str) -> None:
        """Every body pinned: the overset flux adjustment on from this restart (see ContactSettings)."""
        bodies = set(self.info.body_names)
        if not bodies or body_policy.pinned_bodies(self.case) != bodies:
            return
        if not body_policy.set_pimple_entry(self.case, "oversetAdjustPhi", "yes"):
            return
        self.run_record["overset_adjust_phi_from_s"] = float(time_name)
        self.say(f"t = {time_name} s: every body is pinned: the overset flux adjustment (oversetAdjustPhi) is on "
                 "from now on, to keep the water lost into the fringe around the pinned bodies small")

    # ---- the record
    def _record_resting(self, time_name: str, c: Contact, before: dict[str, BodyState],
                        after: dict[str, BodyState], impulse_Ns: float, pressed: bool = False) -> None:
        events = read_events(self.case)
        event = {"event": len(events) + 1, "type": "resting", "time_s": float(time_name), "body": c.body,
                 "pressed": pressed,
                 "other": c.other, "kind": c.kind, "gap_m": c.distance_m, "point_m": list(c.point_m),
                 "normal": list(c.normal), "approach_m_s": c.approach_m_s, "impulse_Ns": impulse_Ns,
                 "velocity_in_m_s": list(before[c.body].velocity_m_s),
                 "velocity_out_m_s": list(after[c.body].velocity_m_s)}
        write_events(self.case, events + [event])
        self.run_record["resting_contacts"] = self.run_record.get("resting_contacts", 0) + 1

    def forget_events_after(self, time_s: float) -> None:
        """Contact events later than `time_s` belong to a stretch being computed again; so do the
        contacts the book counts after it. A fresh book (a run resumed by a new process) first
        reads its memory back from the events it keeps (`_recall`)."""

        events = read_events(self.case)
        keep = [e for e in events if e["time_s"] <= time_s + EPS_T]
        if len(keep) != len(events):
            forget_impact_events_after(self.case, time_s + EPS_T)
            write_events(self.case, keep)
        if self._fresh:
            self._recall(keep, time_s)
            self._fresh = False
        for key, times in list(self._pair_events.items()):
            self._pair_events[key] = [t for t in times if t <= time_s + EPS_T]

    def _recall(self, events: Sequence[dict], time_s: float) -> None:
        """The book's memory at `time_s` from the record: each pair's contacts within `window_s`
        (one a restart: the extra records of `_separate_pressed` share their restart's time), and
        the body pairs pressed together (whose latest event is a pressed resting contact;
        `_release_pressed` frees those found apart at the restart). A book that starts empty treats
        a pressed train's contacts as impacts (the 3x1 layout two-way resumed at 2.214 s:
        restitution 0.27 where the uninterrupted run's contacts are plastic). The bed's lifts are
        not in the record; their count starts again at a resume."""
        seen: set[tuple[str, str, float]] = set()
        latest: dict[tuple[str, str], dict] = {}
        for e in events:
            other = e.get("other")
            if not other or e.get("type") not in ("impact", "resting", "pinned"):
                continue
            t = float(e["time_s"])
            key = (e["body"], other)
            if t > time_s - self.settings.window_s and (*key, t) not in seen:
                seen.add((*key, t))
                self._pair_events.setdefault(key, []).append(t)
            if e.get("kind") == "body":
                latest[(key if key[0] <= key[1] else (other, e["body"]))] = e
        self._pressed_pairs |= {pair for pair, e in latest.items()
                                if e.get("type") == "resting" and e.get("pressed")}

    def _record_event(self, time_name: str, c: Contact, before: dict[str, BodyState], after: dict[str, BodyState],
                      result) -> None:
        events = read_events(self.case)
        number = len(events) + 1
        history = write_pulse_files(self.case, number, result)
        b0, b1 = before[c.body], after[c.body]
        event = {
            "event": number,
            "type": "impact",
            "time_s": float(time_name),
            "body": c.body,
            "other": c.other,
            "kind": c.kind,
            "gap_m": c.distance_m,
            "point_m": list(c.point_m),
            "normal": list(c.normal),
            "velocity_in_m_s": list(b0.velocity_m_s),
            "velocity_out_m_s": list(b1.velocity_m_s),
            "angular_velocity_in_rad_s": list(b0.angular_velocity_rad_s),
            "angular_velocity_out_rad_s": list(b1.angular_velocity_rad_s),
            "normal_velocity_in_m_s": float(result.normal_velocity_in_m_s),
            "normal_velocity_out_m_s": float(result.normal_velocity_out_m_s),
            "restitution": float(result.restitution),
            "obliquity_deg": float(result.obliquity_deg),
            "height_m": float(result.contact_height_m) if result.contact_height_m is not None else float(c.point_m[2]),
            "peak_force_N": float(result.peak_force_N),
            "duration_s": float(result.duration_s),
            "impulse_Ns": float(result.impulse_Ns),
            "effective_mass_kg": float(result.effective_mass_kg),
            "force_history": str(history),
        }
        if c.kind == "body":
            event["other_velocity_in_m_s"] = list(before[c.other].velocity_m_s)
            event["other_velocity_out_m_s"] = list(after[c.other].velocity_m_s)
        write_events(self.case, events + [event])
        append_impact_event(self.case, event)
        self.say(f"contact event {number}: {c.body} hit {c.other} at t = {float(time_name):.6g} s, "
                 f"{abs(result.normal_velocity_in_m_s):.3g} m/s in, {result.normal_velocity_out_m_s:.3g} m/s out, "
                 f"peak {result.peak_force_N:.4g} N")

