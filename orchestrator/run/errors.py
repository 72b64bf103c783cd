"""Why a run stops early: the errors the run stage raises.

`RunError` is the base (the run could not go on); `DivergenceError` names a diverged or
stalled solution, `RunInterrupted` a run the user stopped (resumable), `ContactError` a
contact the event model cannot resolve. They live below every other run module, so the
runner, the segment watch and the contact book raise the same classes.
"""

from __future__ import annotations

import shlex
import signal
from pathlib import Path

from orchestrator.core.errors import DebrisfoamError

__all__ = ["ContactError", "DivergenceError", "RunError", "RunInterrupted"]


class RunError(DebrisfoamError, RuntimeError):
    """The run could not go on; the message says why and where the log is."""


class DivergenceError(RunError):
    """The solution diverged or stalled: `kind` (nan, courant, delta_t, fpe, left_domain, body_speed, stall, water), `cause`
    in words, the simulated `time_s` it showed at, the `last_good_time` kept and the log."""

    def __init__(self, kind: str, cause: str, time_s: float | None, last_good_time: str | None, log_path: Path):
        self.kind = kind
        self.cause = cause
        self.time_s = time_s
        self.last_good_time = last_good_time
        self.log_path = Path(log_path)
        at = f" at t = {time_s:.6g} s" if time_s is not None else ""
        keep = f"; kept the last good time {last_good_time} s" if last_good_time is not None else ""
        what = {"stall": "solver stalled", "water": "water balance out of bounds"}.get(kind, "solution diverged")
        super().__init__(f"{what}{at}: {cause}{keep}\n  log: {self.log_path}")


class RunInterrupted(RunError):
    """The user stopped the run (Ctrl-C, SIGTERM or a stop request); it can be resumed."""

    def __init__(self, case: Path, signum: int | None, written_time: str | None, clean: bool,
                 before_first_step: bool = False):
        self.case = Path(case)
        self.signum = signum
        self.written_time = written_time
        self.clean = clean
        self.before_first_step = before_first_step
        if before_first_step:
            at = "the solver was stopped before its first time step, so nothing was lost; " + (
                f"the latest written time is t = {written_time} s" if written_time is not None else "it starts again at 0")
        elif written_time is None:
            at = "nothing was written"
        else:
            how = "the solver wrote" if clean else "the solver was killed before writing; the latest written time is"
            at = f"{how} t = {written_time} s"
        super().__init__(f"run interrupted: {at}. Resume with: debrisfoam run {shlex.quote(str(case))}")

    @property
    def exit_code(self) -> int:
        """128 + the signal number (130 for SIGINT), as a shell reports it."""
        return 128 + (self.signum or signal.SIGINT)


class ContactError(RunError):
    """A contact event could not be resolved (e.g. a body pinned against an obstacle)."""
