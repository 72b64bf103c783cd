"""run.json as its readers see it: :class:`RunState`.

The runner writes run.json (:class:`orchestrator.run.run_json.RunRecord`) and a one-way case's
transport adds its entry to it; every other stage reads it through
:meth:`orchestrator.case.folder.CaseFolder.run_state`, so the record's keys are spelled for
readers here once. A case that has not run, or whose run.json cannot be read, reads as an empty
``RunState`` (``status`` None, no steps, no segments).
"""
from __future__ import annotations

import datetime as _dt
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["RunState"]


def _items(value: Any) -> tuple[Mapping[str, Any], ...]:
    """The mappings of a list in run.json (anything else in it is skipped)."""
    return tuple(v for v in value if isinstance(v, Mapping)) if isinstance(value, list) else ()


def _mapping(value: Any) -> Mapping[str, Any]:
    return value if isinstance(value, Mapping) else {}


def _number(value: Any) -> float | None:
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


@dataclass(frozen=True)
class RunState:
    """What run.json records of a case's run: its status and, when it stopped early, why."""

    #: False: the case has no readable run.json (never run, or its record was lost)
    recorded: bool = False
    #: "running", "finished", "failed", "diverged", "stalled", "interrupted"; None: never run
    status: str | None = None
    #: the message of the error that stopped it (as the runner recorded it)
    error: Any = None
    #: a diverged or stalled run's cause, time and log
    diagnosis: Mapping[str, Any] = field(default_factory=dict)
    #: the solver application it ran
    solver: str | None = None
    #: the mesh and utility steps, each with its argv, wall time, exit status and log
    steps: tuple[Mapping[str, Any], ...] = ()
    #: the solver's segments, each with its start and end time, wall time and log
    segments: tuple[Mapping[str, Any], ...] = ()
    ranks: int | None = None
    #: "planned", and after meshing "total" and "mesh_ok"
    cells: Mapping[str, Any] = field(default_factory=dict)
    time_steps: int | None = None
    end_time_s: float | None = None
    reached_time_s: float | None = None
    #: the runner's own account: solver wall time, its CPU time, time between segments
    runner: Mapping[str, Any] = field(default_factory=dict)
    #: a one-way case's transport through the recorded flow (None: not carried yet)
    transport: Mapping[str, Any] | None = None
    transport_wall_s: float | None = None
    #: bodies the bed watch freed from the bed, with their times
    freed: tuple[Mapping[str, Any], ...] = ()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any] | None) -> "RunState":
        """The state run.json's mapping ``data`` records (None or a non-mapping: never run)."""
        if not isinstance(data, Mapping):
            return cls()
        ranks, steps = _number(data.get("ranks")), _number(data.get("time_steps"))
        transport = data.get("transport")
        return cls(
            recorded=True,
            status=data.get("status") if isinstance(data.get("status"), str) else None,
            error=data.get("error"),
            solver=data.get("solver") if isinstance(data.get("solver"), str) else None,
            diagnosis=_mapping(data.get("diagnosis")),
            steps=_items(data.get("steps")),
            segments=_items(data.get("segments")),
            ranks=int(ranks) if ranks is not None else None,
            cells=_mapping(data.get("cells")),
            time_steps=int(steps) if steps is not None else None,
            end_time_s=_number(data.get("end_time_s")),
            reached_time_s=_number(data.get("reached_time_s")),
            runner=_mapping(data.get("runner")),
            transport=transport if isinstance(transport, Mapping) else None,
            transport_wall_s=_number(data.get("transport_wall_s")),
            freed=_items(data.get("freed")),
        )

    @property
    def finished(self) -> bool:
        return self.status == "finished"

    @property
    def solver_wall_s(self) -> float | None:
        """The solver's wall time (s): the runner's account, else its segments' sum; None if it never ran."""
        recorded = _number(self.runner.get("solver_wall_s"))
        if recorded is not None:
            return recorded
        return sum(_number(s.get("wall_s")) or 0.0 for s in self.segments) or None

    def logs(self, failed_only: bool = False) -> list[str]:
        """The logs its steps and segments wrote, in order (``failed_only``: of those that exited
        non-zero), relative to the case."""
        return [str(s["log"]) for s in (*self.steps, *self.segments)
                if s.get("log") and not (failed_only and s.get("exit_status") in (0, None))]

    def wall_before_s(self, begun) -> float:
        """Wall seconds of its steps and segments that began before ``begun`` (an aware datetime);
        ValueError or TypeError for a start time this version cannot read."""
        return sum(float(s.get("wall_s") or 0.0) for s in (*self.steps, *self.segments)
                   if s.get("start") and _dt.datetime.fromisoformat(s["start"]) < begun)
