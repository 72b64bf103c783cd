"""How the runner handles contact: `ContactSettings`, the knobs of the contact book.

The settings say when a body is in contact (the gap), which contacts are impacts and which
resting contacts, how the bed is watched, when a body the flow keeps pressing against an
obstacle is pinned, and the impact model's parameters. `run_case` takes them; the contact
book (`orchestrator.run.contact_book`), the bed watch and the segment watch read them.

Units: seconds, metres, kg, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

from orchestrator.core.errors import InputError

__all__ = ["ContactSettings"]

#: The defaults set at the study's 0.40 m flume that a scene lambda times larger takes x lambda
#: (lengths) and x sqrt(lambda) (times and speeds): :meth:`ContactSettings.froude_scaled`.
_LENGTHS = ("gap_m", "float_margin_m")
_TIMES_AND_SPEEDS = ("min_impact_speed_m_s", "window_s", "bed_runaway_m_s")


@dataclass(frozen=True)
class ContactSettings:
    """When and how the runner handles contact between bodies and obstacles.

    gap_m: a body closer than this to the column, a wall or another body is in contact.
    min_impact_speed_m_s: slower closing speeds are resting contacts: the closing motion
        is stopped (a plastic impulse, no force history), not resolved as an impact.
    bed: watch the bed too. Touching the bed is not an impact (orchestrator.contact.geometry), but
        v1912 lets a body sink through it: a body that sinks more than `bed_tolerance_m`
        (default half the gap) into it is stopped, lifted back onto it and its velocity
        into it removed (`contact.clamp_to_bed`).
    max_events / window_s: more than `max_events` contacts of the same pair within
        `window_s` of simulated time is a resting contact, which this event-driven model
        cannot represent as impacts: the body is pinned where it is for the rest of the run
        (debris held against the column or a wall by the flow); two bodies pressed together
        (a row of containers the bore pushes into each other) have each contact made
        plastic until they are two gaps apart, the pair set the gap apart, and the run goes on. A body
        lifted out of the bed more than `max_events` times within `window_s` is kept on
        the bed's plane (`body_policy.rest_on_bed`) until the water measured around it can carry
        it (`orchestrator.run.bedwatch`).
    bed_runaway_m_s: so is a body found sinking into the bed faster than this. Settling
        bodies closed on the bed at 0.2-0.6 m/s in the hard cases; where each lift pulled
        the body down harder, the speeds went 0.5, 0.8, 2.0, 6.9 m/s to a blow-up.
    impact: keyword arguments for `analytical.impact.impact` / `pair_impact`
        (stiffness_N_m, friction_coefficient, damping_ratio, ...).
    added_mass_coefficient: the water a body carries into a strike: None (the default) its own
        added mass along and about its axes afloat at its draft (analytical.added_mass: the
        1:40 container carries 0.28 of its displaced water lengthwise, 0.84 sideways), the
        same as a one-way strike afloat; a number C_a gives m C_a on every axis (0: none).
    float_margin_m: a body the runner keeps on the bed (the planner's hold, `rest_on_bed`) is
        freed once the water depth measured around it exceeds the height of its underside plus
        its draft plus this margin (`orchestrator.run.bedwatch`). 5 mm: the depth reading's own spread
        on a still 15 mm wet bed at 4 cm cells is under 1 mm, the bore's surface near a body
        moves by a few mm from one sample to the next.
    bed_friction: Coulomb friction (the scene's `debris[].contact.bed_friction_coefficient`)
        on a body while it is kept on the bed (`orchestrator.run.bedwatch`).
    adjust_phi_when_pinned: once every body is pinned, switch the overset flux adjustment
        on (PIMPLE `oversetAdjustPhi yes` in system/fvSolution) for the rest of the run. A
        pinned body loses water into the background's fringe at about 1 % a second; the
        adjustment cut that to 0.4-0.5 % (docs/openfoam-notes.md, "Water balance"). It stays off while
        any body moves: around a body sliding fast along the bed it created water.
    hold_still_solvers: while every body is held still (stuck on the bed by static friction, or
        pinned at an obstacle), set their motion solvers aside (`held.hold_solvers`): v1912
        then builds the overset addressing once a segment instead of at every time step, which
        was 90 % of a step's cost for three containers on the bed (benchmarks/held_solvers.md).
        The flow sees the same still meshes; off only to measure what it saves.
    """

    enabled: bool = True
    gap_m: float = 0.005
    min_impact_speed_m_s: float = 0.05
    bed: bool = True
    bed_tolerance_m: float | None = None
    max_events: int = 6
    window_s: float = 0.05
    bed_runaway_m_s: float = 1.0
    added_mass_coefficient: float | None = None
    adjust_phi_when_pinned: bool = True
    hold_still_solvers: bool = True
    float_margin_m: float = 0.005
    bed_friction: bool = True
    impact: dict = field(default_factory=dict)

    def froude_scaled(self, factor: float) -> "ContactSettings":
        """These settings for a scene ``factor`` (lambda, orchestrator.plan.scale) times larger than
        the study's flume: the lengths still at their defaults x lambda, the times and speeds at
        their defaults x sqrt(lambda); values a caller chose are kept."""
        if factor == 1.0:
            return self
        defaults = {f.name: f.default for f in fields(ContactSettings)}
        changes = {n: getattr(self, n) * factor for n in _LENGTHS if getattr(self, n) == defaults[n]}
        changes |= {n: getattr(self, n) * math.sqrt(factor) for n in _TIMES_AND_SPEEDS
                    if getattr(self, n) == defaults[n]}
        return replace(self, **changes)

    @property
    def bed_sink_m(self) -> float:
        return self.gap_m / 2 if self.bed_tolerance_m is None else self.bed_tolerance_m

    def __post_init__(self) -> None:
        if not self.gap_m > 0:
            raise InputError("gap_m", f"must be > 0, got {self.gap_m}")
