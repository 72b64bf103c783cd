"""Bodies on the bed: free them once the measured water can carry them, and their bed friction.

v1912 has no contact, so the runner keeps a body on the bed with a sixDoF `plane` constraint:
the planner's initial hold (`holdOnBedPlane`, until the bore arrives) or the contact book's
`rest_on_bed` (a body the flow keeps pulling into the bed). This module decides, from the water
depth measured around each body while the solver runs (`orchestrator.run.waterdepth`), when such a
constraint comes off, and gives a resting body Coulomb friction.

**Free floating.** The water can carry a body once the depth all round it
(`waterdepth.depth_around`: the 10 % quantile over a ring of columns around it) exceeds the
height of its underside above the bed (at least the top of the planner's gap, plan.BedGap) plus
its draft (mass over water density times footprint) plus `ContactSettings.float_margin_m`
(default 5 mm). Then:

- a held body (`holdOnBedPlane`, standing on the gap's top) is freed (the constraint removed at a
  restart) once, besides, the fluid's vertical force on it (`waterdepth.read_lift`: the forces
  function object on its wall, averaged over the last 0.01 s) is at least its weight: the model's
  own word that it can lift the body. In a fast bore the water jets through the gap under a held
  body and sucks it down: at 1-1.8 m/s under 50-58 mm of water the lift was 1.8-2.2 N against the
  container's 2.3 N weight (hydrostatics: about 4 N), and freed on the depth alone it sank 7.3 mm
  through the gap onto the bed in 0.1 s (docs/stability.md);
- a body resting on the bed (`restOnBedPlane`, put there by the contact book) is raised onto the
  gap's top and held there (its constraint becomes `holdOnBedPlane`), then freed as above. On the
  bed its underside faces only overset holes and keeps a stale pressure (260 Pa under 70 mm of
  water, where hydrostatics gives about 700 Pa: 1.5 N up against its 2.3 N weight); on the gap it
  has donors and floats (tests/test_float_off.py).

While the solver runs, a new sample that shows either stops it (writeNow) so that the restart can
act. The bed constraint is put back only by the contact book, on evidence that the body is being
pulled into the bed (lifted out of it more than `max_events` times within `window_s`, or found
sinking faster than `bed_runaway_m_s`); a body put back is raised again only once the depth has
also risen `float_margin_m` above the depth it was put back at (otherwise the same water would
raise it at once). The planner's `hold_until_s` (Ritter's or Chanson's depth at the body reaching
the draft plus the gap) is an estimate only; the runner goes by what it measures.

**Bed friction.** While a body is constrained to the bed it gets a horizontal damping force
-c u on its centre of mass (`body_policy.set_bed_friction`: two zero-stiffness v1912 `linearSpring`
restraints through the centre, along x and y; v1912's `linearDamper` would put the force at the
origin and add a yaw moment c (x u_y - y u_x)). The runner sets
c = mu N / max(|u_h|, `FRICTION_FLOOR_M_S`) at every restart, with mu the scene's
`debris[].contact.bed_friction_coefficient`, u_h the horizontal velocity at the restart and N
the body's weight less its buoyancy in the measured water (N = m g - rho g A min(d - z_b, H),
A its footprint, d the measured depth, z_b its underside, H its height; N >= 0), so that the
force is Coulomb's mu N against the sliding at the restart's speed. While the body slides, the
damper's force follows the speed; the runner stops the solver to set c again whenever the
speed leaves [u0 / `FRICTION_BAND`, u0 * `FRICTION_BAND`] (u0 the speed it was set for), so the
force stays within 25 % of mu N. Limits: N is the one of the last restart (the depth may change
within a segment); below the floor speed the damper acts as a viscous one (time constant
m u_floor / (mu N), 40 ms for the study's container on a 15 mm wet bed), so a sliding body comes
to rest only through the static friction below; each refresh is a solver restart; the yaw is
resisted separately (below).

**Static friction.** A body at rest on the bed does not move until the fluid's load exceeds what
friction can bear. The runner holds such a body still (`body_policy.stick_bodies`: sixDoF `point` and
`orientation` beside its bed constraint) and reads the fluid's horizontal force F and yaw moment M
about its centre (the forces function object on its wall, averaged over the last 0.01 s); it breaks
away (the constraints removed at a restart) once the load leaves the limit surface of a uniformly
loaded footprint, approximated by the ellipse (F / mu N)^2 + (M / (mu N r))^2 >= 1 with r the mean
distance of the footprint from its centre (`footprint_mean_radius`; the limit surface and its
ellipsoidal approximation: Goyal, Ruina & Papadopoulos 1991, Wear 143; Howe & Cutkosky 1996, IJRR
15). A body on the bed slower than `STICK_SPEED_M_S` (at its centre and at r) whose load is inside
the surface sticks again. Without it a resting body turns in still water: v1912's overset
interpolation around a body standing in 7.5 mm of water puts a spurious 1-8e-4 N m yaw moment on it
(measured: the study's container on the 1-debris scene's wet bed yawed 58 degrees in its first 0.2 s,
about 1 s before the bore came; friction can bear about 0.02 N m). Sliding, the yaw is resisted by
a `sphericalAngularDamper` sized like the linear one: mu N r at the yaw rate of the restart (at
least `FRICTION_FLOOR_M_S` / r), the two resisting separately (Coulomb's coupling of sliding and
spinning is not modelled).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from orchestrator.case.bodystate import BodyState
from orchestrator.case.folder import CaseFolder
from orchestrator.plan.model import BodyPlan
from orchestrator.run import body_policy, waterdepth

#: below this horizontal speed the friction damper is sized for it (m/s)
FRICTION_FLOOR_M_S = 0.05
#: the solver is stopped to resize the damper when the speed leaves [u0 / band, u0 * band]
FRICTION_BAND = 1.25
#: simulated seconds between two stops to resize a damper (a body the bore sets moving would
#: otherwise stop the solver every few time steps)
FRICTION_MIN_INTERVAL_S = 0.02
#: a body on the bed slower than this (at its centre and at its footprint's mean radius) is at rest:
#: static friction holds it if it can bear the fluid's load (m/s)
STICK_SPEED_M_S = 0.005
#: what the runner records of every sample it reads (in the case)
DEPTH_CSV = "body_depth.csv"
_FIELDS = ("time_s", "body", "depth_m", "columns", "underside_m", "float_depth_m", "lift_N", "weight_N",
           "constraint", "friction_N_s_m", "stuck")


def footprint_mean_radius(length_m: float, width_m: float) -> float:
    """The mean distance of a rectangle's points from its centre (m): the lever arm of Coulomb
    friction against spinning about the centre on a uniformly loaded footprint (closed form of the
    integral of sqrt(x^2 + y^2) over the rectangle)."""
    p, q = 0.5 * length_m, 0.5 * width_m
    d = math.hypot(p, q)
    quarter = (2 * p * q * d + p ** 3 * math.log((q + d) / p) + q ** 3 * math.log((p + d) / q)) / 6.0
    return quarter / (p * q)


def breakaway_ratio(force_xy: Sequence[float], moment_z: float, mu: float, normal_N: float,
                    radius_m: float) -> float:
    """Where a load sits on static friction's limit surface: (F / mu N)^2 + (M / mu N r)^2, 1 at
    the surface (breaks away at >= 1); inf when friction can bear nothing."""
    limit = mu * normal_N
    if limit <= 0:
        return math.inf
    return (math.hypot(*force_xy[:2]) / limit) ** 2 + (moment_z / (limit * radius_m)) ** 2


def underside_m(state: BodyState, size: Sequence[float], bed_z: float = 0.0) -> float:
    """Height of a body's lowest point above the bed plane."""
    rot = np.asarray(state.orientation, dtype=float).reshape(3, 3)
    half = 0.5 * float(np.abs(rot[2, :]) @ np.asarray(size, dtype=float))
    return float(state.centre_of_mass_m[2]) - half - bed_z


@dataclass
class BedWatch:
    """The runner's watch over bodies on the bed (see the module notes)."""

    case: Path
    #: the planned bodies (mass, size) and each one's Coulomb bed friction (scene contact.bed_friction_coefficient)
    bodies: dict[str, BodyPlan]
    bed_friction: dict[str, float]
    axis: waterdepth.ZAxis | None
    margin_m: float
    rho: float
    g: float
    bed_z: float
    initial_depth_m: dict[str, float]
    say: Callable[[str], None]
    friction: bool = True
    constraints: dict[str, str] = field(default_factory=dict)
    rested_at_depth: dict[str, float] = field(default_factory=dict)
    friction_speed: dict[str, float] = field(default_factory=dict)
    friction_spin: dict[str, float] = field(default_factory=dict)
    #: the bodies static friction holds, and each body's normal force at the last restart (N)
    stuck: set[str] = field(default_factory=set)
    normal_N: dict[str, float] = field(default_factory=dict)
    last_sample_s: float = -math.inf
    last_load_s: float = -math.inf
    gap_m: float = 0.0
    restart_s: float = 0.0
    #: where each body's columns were placed (its centre's x, y at the restart)
    placed: dict[str, tuple[float, float]] = field(default_factory=dict)

    @classmethod
    def for_case(cls, case: Path, margin_m: float, say: Callable[[str], None], friction: bool = True) -> "BedWatch":
        folder = CaseFolder(case)
        plan = folder.require_plan()
        scene = folder.scene()
        rho, g = float(scene.fluids.water_density_kg_m3), float(scene.fluids.gravity_m_s2)
        mu = {d.name: float(d.contact.bed_friction_coefficient) for d in scene.debris}
        bodies = {b.name: b for b in plan.bodies}
        initial = {}
        for b in plan.bodies:
            x, y = (float(v) for v in b.centre_of_mass_m[:2])
            initial[b.name] = max((float(w.max_m[2]) - float(w.min_m[2]) for w in plan.water
                                   if w.min_m[0] <= x <= w.max_m[0] and w.min_m[1] <= y <= w.max_m[1]), default=0.0)
        axis = waterdepth.z_axis(plan, scene.mesh.cell_size_m) if bodies else None
        if axis is not None:
            waterdepth.install(case, axis)  # the lift of every body; columns once a restart needs them
        bed_z = float(plan.domain_m[2][0])
        return cls(case, bodies, {name: mu.get(name, 0.3) for name in bodies}, axis, margin_m, rho, g, bed_z, initial,
                   say, friction,
                   gap_m=float(plan.bed_gap_m or 0.0))

    # ---- the bodies
    def draft_m(self, name: str) -> float:
        """The body's draft afloat in the case's water: its mass over rho times its footprint."""
        body = self.bodies[name]
        return float(body.mass_kg) / (self.rho * float(body.size_m[0]) * float(body.size_m[1]))

    def friction_radius_m(self, name: str) -> float:
        """The mean distance of the body's footprint from its centre (`footprint_mean_radius`)."""
        return footprint_mean_radius(float(self.bodies[name].size_m[0]), float(self.bodies[name].size_m[1]))

    # ---- the measurement
    def depth(self, sample: waterdepth.Sample | None, state: BodyState,
              states: Sequence[BodyState] = ()) -> tuple[float, int] | None:
        """The depth all round `state`'s body (`waterdepth.depth_around`), its ring kept off the
        other bodies among `states` (their overset holes)."""
        if sample is None or self.axis is None:
            return None
        body = self.bodies[state.name]
        others = [(s.centre_of_mass_m, s.orientation, self.bodies[s.name].size_m) for s in states
                  if s.name != state.name and s.name in self.bodies]
        return waterdepth.depth_around(sample, self.axis.ring_m, state.centre_of_mass_m, state.orientation,
                                       body.size_m, others)

    def float_depth_m(self, state: BodyState) -> float:
        """The depth that frees a constrained body: its underside (the gap's top if lower), its
        draft, the margin, and
        after a `rest_on_bed`, the margin above the depth it was put back at."""
        body = self.bodies[state.name]
        # a body below the gap's top is raised onto it when freed (at_restart)
        need = max(underside_m(state, body.size_m, self.bed_z), self.gap_m) + self.draft_m(state.name) + self.margin_m
        rested = self.rested_at_depth.get(state.name)
        return need if rested is None else max(need, rested + self.margin_m)

    def normal_force_N(self, state: BodyState, depth_m: float) -> float:
        """Weight less buoyancy of a body standing with its underside where it is, in `depth_m`."""
        body = self.bodies[state.name]
        immersed = min(max(depth_m - underside_m(state, body.size_m, self.bed_z), 0.0), body.size_m[2])
        return max(body.mass_kg * self.g - self.rho * self.g * body.size_m[0] * body.size_m[1] * immersed, 0.0)

    def lift_N(self, name: str, until_s: float = math.inf) -> float | None:
        return waterdepth.read_lift(self.case, name, until_s)

    def load_ratio(self, state: BodyState, until_s: float = math.inf) -> float | None:
        """Where the fluid's load on a body on the bed sits on its static friction's limit surface
        (`breakaway_ratio`), from the forces on its wall; None before they are written."""
        load = waterdepth.read_load(self.case, state.name, until_s)
        normal = self.normal_N.get(state.name)
        if load is None or normal is None:
            return None
        force, moment = load
        x, y = state.centre_of_mass_m[:2]
        moment_z = float(moment[2]) - (x * float(force[1]) - y * float(force[0]))  # about its centre
        return breakaway_ratio(force, moment_z, self.bed_friction[state.name], normal, self.friction_radius_m(state.name))

    def at_rest(self, state: BodyState) -> bool:
        spin = abs(float(state.angular_velocity_rad_s[2])) * self.friction_radius_m(state.name)
        return math.hypot(*state.velocity_m_s[:2]) < STICK_SPEED_M_S and spin < STICK_SPEED_M_S

    def can_float(self, state: BodyState, measured: tuple[float, int] | None, lift: float | None) -> bool:
        """The water all round is deep enough and the fluid already pushes the body up by its weight."""
        body = self.bodies[state.name]
        return (measured is not None and measured[0] > self.float_depth_m(state)
                and lift is not None and lift >= body.mass_kg * self.g)

    # ---- at a restart
    def at_restart(self, time_name: str, states: Sequence[BodyState]) -> tuple[list[str], list[BodyState]]:
        """Free the constrained bodies the water measured at `time_name` can carry (raising onto
        the gap's top those that lie below it), and size the friction of the bodies still on the
        bed. Returns the bodies freed and every body's state to restart with."""
        self.restart_s = float(time_name)
        if not self.bodies:
            return [], list(states)
        now = body_policy.bed_constraints(self.case)
        sample = waterdepth.read_at(self.case, self.axis, float(time_name)) if self.axis else None
        freed, coeffs, yaw, out = [], {}, {}, []
        self.stuck = body_policy.stuck_bodies(self.case)
        for state in states:
            kind = now.get(state.name, "")
            if kind == "rest" and self.constraints.get(state.name) != "rest":
                measured = self.depth(sample, state, states)
                self.rested_at_depth[state.name] = measured[0] if measured else 0.0
            measured = self.depth(sample, state, states)
            depth = measured[0] if measured else self.initial_depth_m.get(state.name, 0.0)
            lift = self.lift_N(state.name, float(time_name))
            if kind == "rest" and measured is not None and depth > self.float_depth_m(state):
                # deep enough: back onto the gap's top, held there until the water lifts it
                body_policy.rest_to_hold(self.case, [state.name])
                kind = "hold"
                below = self.gap_m - underside_m(state, self.bodies[state.name].size_m, self.bed_z)
                self.say(f"t = {time_name} s: {state.name}: {depth * 1000:.1f} mm of water around it: raised "
                         f"{max(below, 0.0) * 1000:.2f} mm onto the gap's top and held there until the water lifts it")
                if below > 1e-6:
                    x, y, z = state.centre_of_mass_m
                    vx, vy, _ = state.velocity_m_s
                    state = state.with_changes(centre_of_mass_m=(x, y, z + below), velocity_m_s=(vx, vy, 0.0))
                lift = None  # measured on the bed, where the underside is stale
            elif kind == "hold" and self.can_float(state, measured, lift):
                body_policy.release_holds(self.case, [state.name])
                self.say(f"t = {time_name} s: {state.name} freed from the bed: {depth * 1000:.1f} mm of water "
                         f"around it, it floats in {self.float_depth_m(state) * 1000:.1f} mm; the water pushes it "
                         f"up by {lift:.3g} N")
                freed.append(state.name)
                kind = ""
            if kind in ("hold", "rest") and self.friction:
                normal = self.normal_force_N(state, depth)
                state = self._static_friction(time_name, state, normal)
                speed = max(math.hypot(*state.velocity_m_s[:2]), FRICTION_FLOOR_M_S)
                radius = self.friction_radius_m(state.name)
                spin = max(abs(float(state.angular_velocity_rad_s[2])), FRICTION_FLOOR_M_S / radius)
                coeffs[state.name] = self.bed_friction[state.name] * normal / speed
                yaw[state.name] = self.bed_friction[state.name] * normal * radius / spin
                self.friction_speed[state.name], self.friction_spin[state.name] = speed, spin
            else:
                coeffs[state.name] = yaw[state.name] = None
                self.friction_speed.pop(state.name, None)
                self.friction_spin.pop(state.name, None)
                self.stuck.discard(state.name)  # freed: release_holds removed the stick too
            out.append(state)
            now[state.name] = kind
            self._record(float(time_name), state, measured, lift, kind, coeffs[state.name])
        body_policy.set_bed_friction(self.case, coeffs, yaw)
        self.constraints = now
        # columns for the next segment around the bodies kept on the bed and those near it (a body
        # closer to the bed than its own height may be put back on it; body_depth.csv records them)
        near = [s for s in out if now.get(s.name) in ("hold", "rest")
                or underside_m(s, self.bodies[s.name].size_m, self.bed_z) < self.bodies[s.name].size_m[2]]
        if self.axis is not None:
            waterdepth.install(self.case, self.axis, [(s.centre_of_mass_m, s.orientation, self.bodies[s.name].size_m)
                                                      for s in near])
        self.placed = {s.name: (float(s.centre_of_mass_m[0]), float(s.centre_of_mass_m[1])) for s in near}
        return freed, out

    def _static_friction(self, time_name: str, state: BodyState, normal_N: float) -> BodyState:
        """Stick a body at rest whose load friction bears; let a stuck one go once it does not."""
        self.normal_N[state.name] = normal_N
        ratio = self.load_ratio(state, float(time_name))
        if state.name in self.stuck:
            if ratio is not None and ratio >= 1.0:
                body_policy.unstick_bodies(self.case, [state.name])
                self.stuck.discard(state.name)
                self.say(f"t = {time_name} s: {state.name} breaks away: the water's load is {ratio ** 0.5:.2f} "
                         "times what static bed friction bears")
        elif self.at_rest(state) and (ratio is None or ratio < 1.0):
            body_policy.stick_bodies(self.case, [state.name])
            self.stuck.add(state.name)
            self.say(f"t = {time_name} s: {state.name} at rest on the bed: static friction holds it"
                     + ("" if ratio is None else f" (the water's load is {ratio ** 0.5:.2f} of what it bears)"))
            state = state.with_changes(velocity_m_s=(0.0, 0.0, 0.0), angular_velocity_rad_s=(0.0, 0.0, 0.0))
        return state

    # ---- while the solver runs
    def why_stop(self, states: Sequence[BodyState], time_s: float) -> str | None:
        """A reason to stop the solver now, or None: a constrained body the newest sample shows
        afloat, a resting body whose speed has left its friction band, one come to rest, or a stuck
        one the water's load breaks away."""
        loads_due = time_s - self.last_load_s >= waterdepth.SAMPLE_INTERVAL_S  # the forces, every 0.01 s
        if loads_due:
            self.last_load_s = time_s
        for state in states:
            kind = self.constraints.get(state.name, "")
            speed0 = self.friction_speed.get(state.name)
            if (kind not in ("hold", "rest") or speed0 is None or time_s - self.restart_s < FRICTION_MIN_INTERVAL_S
                    or state.name in self.stuck):
                continue
            speed = max(math.hypot(*state.velocity_m_s[:2]), FRICTION_FLOOR_M_S)
            if not speed0 / FRICTION_BAND <= speed <= speed0 * FRICTION_BAND:
                return f"{state.name} slides at {speed:.3g} m/s, its bed friction was set for {speed0:.3g} m/s"
            spin0 = self.friction_spin.get(state.name)
            spin = max(abs(float(state.angular_velocity_rad_s[2])),
                       FRICTION_FLOOR_M_S / self.friction_radius_m(state.name))
            if spin0 is not None and not spin0 / FRICTION_BAND <= spin <= spin0 * FRICTION_BAND:
                return f"{state.name} turns at {spin:.3g} rad/s, its bed friction was set for {spin0:.3g} rad/s"
            if loads_due and self.at_rest(state) and (self.load_ratio(state) or 0.0) < 1.0:
                return f"{state.name} has come to rest on the bed"
        for state in states:
            if loads_due and state.name in self.stuck and time_s - self.restart_s >= FRICTION_MIN_INTERVAL_S:
                ratio = self.load_ratio(state)
                if ratio is not None and ratio >= 1.0:
                    return (f"{state.name}: the water's load is {ratio ** 0.5:.2f} times what static bed "
                            "friction bears")
        for state in states:
            if self.constraints.get(state.name) in ("hold", "rest") and not self._covered(state):
                return f"{state.name} slid off the water columns placed around it"
        if self.axis is None or not self.placed:
            return None
        sample = waterdepth.read_latest(self.case, self.axis, after_s=self.last_sample_s)
        if sample is None:
            return None
        self.last_sample_s = sample.time_s
        waterdepth.prune(self.case)
        why = None
        for state in states:
            kind = self.constraints.get(state.name, "")
            measured = self.depth(sample, state, states) if self._covered(state) else None
            lift = self.lift_N(state.name)
            self._record(sample.time_s, state, measured, lift, kind, None)
            deep = measured is not None and measured[0] > self.float_depth_m(state)
            if why is None and ((kind == "hold" and self.can_float(state, measured, lift)) or (kind == "rest" and deep)):
                why = (f"{state.name}: {measured[0] * 1000:.1f} mm of water around it at t = {sample.time_s:.4g} s, "
                       f"it floats in {self.float_depth_m(state) * 1000:.1f} mm" + (
                           "" if lift is None else f"; the water pushes it up by {lift:.3g} N"))
        return why

    def _covered(self, state: BodyState) -> bool:
        """The columns placed at the last restart still ring the body."""
        placed = self.placed.get(state.name)
        return (placed is not None and self.axis is not None
                and math.dist(placed, state.centre_of_mass_m[:2]) <= waterdepth.TRAVEL_CELLS * self.axis.cell_m)

    def _record(self, t: float, state: BodyState, measured: tuple[float, int] | None, lift: float | None,
                kind: str, coeff: float | None) -> None:
        path = self.case / DEPTH_CSV
        new = not path.is_file()
        with open(path, "a", newline="") as fh:
            w = csv.writer(fh)
            if new:
                w.writerow(_FIELDS)
            body = self.bodies[state.name]
            w.writerow([f"{t:.8g}", state.name, "" if measured is None else f"{measured[0]:.5f}",
                        0 if measured is None else measured[1],
                        f"{underside_m(state, body.size_m, self.bed_z):.5f}", f"{self.float_depth_m(state):.5f}",
                        "" if lift is None else f"{lift:.4f}", f"{body.mass_kg * self.g:.4f}",
                        kind or "free", "" if coeff is None else f"{coeff:.5g}", int(state.name in self.stuck)])
