"""Watching a running OpenFOAM v1912 solver through its log: steps, bodies, health, progress.

The runner tails `log.<solver>` (`LogTail`: reads only the bytes appended since
the last look, keeps a partial last line for the next read) and feeds the lines to
a `LogParser`, which turns them into one `StepRecord` per time step: simulated
time, deltaT, the Courant numbers, the solver's own execution time and, for
overInterDyMFoam, every six-DoF body's state from its per-step report. A
`HealthWatch` looks at each step (and at every line, for NaN) and names a
divergence as soon as one shows; `Progress` draws the bar.

Log layout of one v1912 time step (interFoam and overInterDyMFoam)::

    Courant Number mean: 0.0186 max: 0.658          <- with the previous deltaT
    Interface Courant Number mean: 0.0007 max: 0.26
    deltaT = 0.00163
    Time = 0.00426                                  <- the step starts
    PIMPLE: iteration 1
    6-DoF rigid body motion                         <- one block per body, in the
        Centre of rotation: (x y z)                    order of dynamicMeshDict's
        Centre of mass: (x y z)                        `solvers`, naming no body;
        Orientation: (xx xy xz yx yy yz zx zy zz)      the state at the end of
        Linear velocity: (u v w)                       this step
        Angular velocity: (p q r)
    ...
    ExecutionTime = 0.34 s  ClockTime = 1 s         <- the step ends

With several PIMPLE outer correctors (and the mesh moved in each) the body blocks
repeat per iteration; the last one of a step is the step's state.

Why not PyFoam's log analysis: its analyzers (`BoundingLogAnalyzer` and the
`LineAnalyzer`s behind it) have no notion of the six-DoF blocks (which name no body
and must be counted in `solvers` order) and no NaN watch; they keep timelines of
every residual and write them to files. Measured on the two-body log of the tests
(17.5k lines): 4.9 us per line for BoundingLogAnalyzer, 1.6 us here (this parser
looks at a line's first characters before any regular expression). Both are far
below the 5 % budget; the six-DoF blocks decide.

Units: seconds, metres, m/s, rad/s.
"""

from __future__ import annotations

import math
import os
import re
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np

from orchestrator.case.bodystate import BodyState
from orchestrator.core.errors import InputError

__all__ = [
    "Diagnosis",
    "DivergenceLimits",
    "HealthWatch",
    "LogParser",
    "LogTail",
    "Progress",
    "StepRecord",
    "foam_build",
    "parse_log",
    "water_balance_diagnosis",
]

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?nan|[-+]?inf"
_VEC = re.compile(r"\(([^()]*)\)")
_COURANT = re.compile(rf"mean: ({_NUM}) max: ({_NUM})", re.I)
_EXEC = re.compile(rf"ExecutionTime = ({_NUM}) s\s+ClockTime = ({_NUM}) s")
_FINAL_RESIDUAL = re.compile(rf"Final residual = ({_NUM})")
_ITERATIONS = re.compile(r"No Iterations (\d+)")
#: a NaN or an infinity as OpenFOAM prints them (nan, -nan, inf, -inf), as whole words
_NONFINITE = re.compile(r"(?<![\w.])[-+]?(?:nan|inf)(?![\w])", re.I)
_RANK = re.compile(r"^\[\d+\] ?")
_BODY_FIELDS = {
    "Centre of rotation": "centre_of_rotation_m",
    "Centre of mass": "centre_of_mass_m",
    "Orientation": "orientation",
    "Linear velocity": "velocity_m_s",
    "Angular velocity": "angular_velocity_rad_s",
}


def _floats(text: str) -> tuple[float, ...]:
    m = _VEC.search(text)
    return tuple(float(v) for v in (m.group(1) if m else text).split())


def foam_build(log_text: str) -> str | None:
    """The OpenFOAM build from a log header: `Build  : OPENFOAM=1912 patch=200626` -> "1912 patch=200626"."""
    m = re.search(r"^Build\s*:\s*(.+)$", log_text, re.M)
    if not m:
        return None
    build = m.group(1).strip()
    return build.replace("OPENFOAM=", "").strip()


# --------------------------------------------------------------------------- records


@dataclass(frozen=True)
class StepRecord:
    """One solver time step, from the log.

    `time_name` is the time as the solver prints it (the name of the time directory
    it would write); `delta_t_s` the step's deltaT; `max_courant` and
    `max_alpha_courant` as printed before the step (with the previous deltaT);
    `execution_time_s` the solver's cumulative CPU time at the end of the step;
    `bodies` the state of every body at the end of the step (empty without bodies).
    """

    index: int
    time_s: float
    time_name: str
    delta_t_s: float | None
    max_courant: float | None
    max_alpha_courant: float | None
    execution_time_s: float | None
    clock_time_s: float | None
    bodies: tuple[BodyState, ...] = ()


@dataclass
class _Partial:
    """A step being read: its record as far as the step's head tells it, and its bodies' fields by slot."""

    head: StepRecord
    bodies: dict[int, dict] = field(default_factory=dict)


class LogParser:
    """Incremental parser of an interFoam/overInterDyMFoam log.

    Feed it lines (`feed`); it returns the steps completed by them. Besides the
    steps it records: `build` (OpenFOAM build from the header), `nonfinite_line`
    (the first line holding a NaN or inf, and the simulated time it came at),
    `fatal` (a FOAM FATAL ERROR seen), `fpe` (a floating point exception seen),
    `finished` (`End` printed), `control_dict_reread` (how many times the solver
    re-read a run-time modified file: the acknowledgement of a stop request).

    `body_names` are the bodies in the order of dynamicMeshDict's `solvers`.
    """

    def __init__(self, body_names: Sequence[str] = ()):
        self.body_names = tuple(body_names)
        self.build: str | None = None
        self.steps_seen = 0
        self.last_step: StepRecord | None = None
        self.nonfinite_line: str | None = None
        self.nonfinite_time_s: float | None = None
        self.fatal = False
        self.fpe = False
        self.finished = False
        self.rereads = 0
        #: the line of a pcorr solve (overset flux correction) that diverged, if any
        self.pcorr_failure: str | None = None
        self._courant: float | None = None
        self._alpha_courant: float | None = None
        self._delta_t: float | None = None
        self._step: _Partial | None = None
        self._block = -1  # index of the body block being read in this iteration
        self._in_block = False

    @property
    def current_time_s(self) -> float | None:
        """The simulated time of the step in progress (or of the last one)."""
        if self._step is not None:
            return self._step.head.time_s
        return self.last_step.time_s if self.last_step else None

    # ---- parsing

    def feed(self, lines: Iterable[str]) -> list[StepRecord]:
        """Consume complete lines (without newlines); return the steps they completed."""
        done: list[StepRecord] = []
        for raw in lines:
            line = raw.strip()
            if not line:
                continue
            if line[0] == "[":  # rank-prefixed lines of parallel runs (errors, stack traces)
                line = _RANK.sub("", line)
                if not line:
                    continue
            c = line[0]
            # cheap first-character dispatch; regular expressions only on candidate lines
            if c == "T" and line.startswith("Time = "):
                self._close_step(done)
                name = line[7:].split()[0]
                try:
                    t = float(name)
                except ValueError:
                    continue
                self.steps_seen += 1
                self._step = _Partial(StepRecord(self.steps_seen, t, name, self._delta_t, self._courant,
                                                 self._alpha_courant, None, None))
                self._block = -1
                self._in_block = False
                continue
            if c == "C" and line.startswith("Courant Number"):
                m = _COURANT.search(line)
                if m:
                    self._courant = float(m.group(2))
            elif c == "I" and line.startswith("Interface Courant Number"):
                m = _COURANT.search(line)
                if m:
                    self._alpha_courant = float(m.group(2))
            elif c == "d" and line.startswith("deltaT = "):
                try:
                    self._delta_t = float(line[9:].split()[0])
                except (ValueError, IndexError):
                    pass
            elif c == "P" and line.startswith("PIMPLE: iteration"):
                self._block = -1
                self._in_block = False
            elif c == "6" and line.startswith("6-DoF rigid body motion"):
                self._block += 1
                self._in_block = True
                if self._step is not None:
                    self._step.bodies[self._slot()] = {}
                continue
            elif self._in_block and ":" in line and line.split(":", 1)[0] in _BODY_FIELDS:
                key, rest = line.split(":", 1)
                if self._step is not None:
                    try:
                        self._step.bodies.setdefault(self._slot(), {})[_BODY_FIELDS[key]] = _floats(rest)
                    except ValueError:  # a NaN in a body report is caught below
                        pass
            elif c == "E" and line.startswith("ExecutionTime"):
                m = _EXEC.search(line)
                if self._step is not None:
                    done.append(self._finish(float(m.group(1)) if m else None, float(m.group(2)) if m else None))
            elif c == "E" and line == "End":
                self._close_step(done)
                self.finished = True
            elif c == "B" and self.build is None and line.startswith("Build"):
                self.build = foam_build(line)
            elif c == "-" and "FOAM FATAL" in line:
                self.fatal = True
            elif "sigFpe::sigHandler" in line or line.startswith("Signal: Floating point exception"):
                self.fpe = True
            elif c == "R" and line.startswith("Re-reading object"):
                self.rereads += 1
            elif self.pcorr_failure is None and "Solving for pcorr" in line:
                m = _FINAL_RESIDUAL.search(line)
                n = _ITERATIONS.search(line)
                skipped = n is not None and int(n.group(1)) == 0  # the start-up projection, switched off
                if m and not skipped and not float(m.group(1)) < 1.0:  # grew instead of falling: no solution
                    self.pcorr_failure = line
            if self._in_block and not line.startswith(tuple(_BODY_FIELDS)):
                self._in_block = False
            if self.nonfinite_line is None and _has_nonfinite(line):
                self.nonfinite_line = line
                self.nonfinite_time_s = self._step.head.time_s if self._step else None
        return done

    def _slot(self) -> int:
        n = len(self.body_names)
        return self._block % n if n else self._block

    def _finish(self, exec_s: float | None, clock_s: float | None) -> StepRecord:
        step = self._step
        assert step is not None
        bodies = []
        for slot in sorted(step.bodies):
            values = step.bodies[slot]
            if "centre_of_mass_m" not in values:
                continue
            name = self.body_names[slot] if slot < len(self.body_names) else f"body{slot + 1}"
            orientation = values.get("orientation", (1.0, 0, 0, 0, 1.0, 0, 0, 0, 1.0))
            bodies.append(BodyState(
                name=name,
                time_s=step.head.time_s,
                centre_of_mass_m=values["centre_of_mass_m"],
                orientation=orientation,
                velocity_m_s=values.get("velocity_m_s", (0.0, 0.0, 0.0)),
                angular_velocity_rad_s=values.get("angular_velocity_rad_s", (0.0, 0.0, 0.0)),
                centre_of_rotation_m=values.get("centre_of_rotation_m"),
            ))
        record = replace(step.head, execution_time_s=exec_s, clock_time_s=clock_s, bodies=tuple(bodies))
        self._step = None
        self.last_step = record
        return record

    def _close_step(self, done: list[StepRecord]) -> None:
        """A step that ended without an ExecutionTime line (e.g. the log stopped) is dropped."""
        self._step = None


def _has_nonfinite(line: str) -> bool:
    low = line.lower()
    if "nan" not in low and "inf" not in low:
        return False
    return _NONFINITE.search(line) is not None


def parse_log(path: str | Path, body_names: Sequence[str] = ()) -> tuple[list[StepRecord], LogParser]:
    """Every completed step of a whole log file, and the parser (for build, errors, End)."""
    parser = LogParser(body_names)
    text = Path(path).read_text(errors="replace")
    steps = parser.feed(text.splitlines())
    return steps, parser


# --------------------------------------------------------------------------- tail


class LogTail:
    """New complete lines of a growing log file, read from where the last call stopped.

    One `os.stat` per call when nothing was appended; no re-reading of old bytes.
    """

    def __init__(self, path: str | Path, offset: int = 0):
        self.path = Path(path)
        self.offset = offset
        self._rest = b""

    def read_lines(self, max_bytes: int = 8 << 20) -> list[str]:
        try:
            size = os.stat(self.path).st_size
        except FileNotFoundError:
            return []
        if size <= self.offset:
            return []
        with open(self.path, "rb") as fh:
            fh.seek(self.offset)
            chunk = fh.read(min(size - self.offset, max_bytes))
        self.offset += len(chunk)
        data = self._rest + chunk
        cut = data.rfind(b"\n")
        if cut < 0:
            self._rest = data
            return []
        self._rest = data[cut + 1:]
        return data[:cut].decode("utf-8", errors="replace").split("\n")

    def flush(self) -> list[str]:
        """The partial last line too (after the process has ended)."""
        lines = self.read_lines()
        if self._rest:
            lines.append(self._rest.decode("utf-8", errors="replace"))
            self._rest = b""
        return lines


# --------------------------------------------------------------------------- health


#: default stall limit: wall seconds without solver output (scene run.stall_limit_s overrides it)
STALL_S = 600.0


@dataclass(frozen=True)
class DivergenceLimits:
    """When a run counts as diverged (the runner stops it and keeps the last good time).

    - any NaN or inf in the log;
    - max Courant above `courant_factor` x maxCo for `courant_steps` steps in a row;
    - deltaT below `min_delta_t_s` for `delta_t_steps` steps in a row (None: a
      thousandth of the controlDict's initial deltaT, set by the runner);
    - a body's centre of mass more than `domain_margin_m` outside the domain box;
    - a body faster than `max_body_speed_m_s` (None: three times the plan's velocity
      scale 2 sqrt(g h0), Ritter's front speed, set by the runner): debris cannot
      outrun the flow that carries it, so such a speed is a numerical blow-up;
    - a stall: the solver writes nothing to its log for `stall_s` seconds of wall time
      (None: the scene's run.stall_limit_s, set by the runner, else STALL_S), or for
      `stall_factor` times its slowest time step so far when that is longer (a linear
      solver that never converges, a hung MPI rank: without this a run waits forever);
    - water created or lost beyond `water_balance` of the initial volume (None: the scene's
      run.water_balance_limit, set by the runner, else post.WATER_BALANCE_TOLERANCE, the
      stability check's 1 %): the run can no longer be sane, so it stops instead of running on
      (:func:`water_balance_diagnosis`).
    """

    courant_factor: float = 10.0
    courant_steps: int = 5
    min_delta_t_s: float | None = None
    delta_t_steps: int = 3
    domain_margin_m: float = 0.0
    max_body_speed_m_s: float | None = None
    stall_s: float | None = None
    stall_factor: float = 20.0
    water_balance: float | None = None

    def stall_limit_s(self, slowest_step_s: float | None) -> float:
        """Wall seconds without log output after which the solver counts as stalled."""
        base = STALL_S if self.stall_s is None else self.stall_s
        return max(base, self.stall_factor * (slowest_step_s or 0.0))

    def __post_init__(self) -> None:
        if not self.courant_factor > 1:
            raise InputError("courant_factor", f"must be > 1, got {self.courant_factor}")
        if self.courant_steps < 1 or self.delta_t_steps < 1:
            raise InputError("courant_steps, delta_t_steps", "must be >= 1, got "
                                                             f"{self.courant_steps}, {self.delta_t_steps}")
        if self.min_delta_t_s is not None and not self.min_delta_t_s > 0:
            raise InputError("min_delta_t_s", f"must be > 0, got {self.min_delta_t_s}")
        if (self.stall_s is not None and not self.stall_s > 0) or not self.stall_factor > 0:
            raise InputError("stall_s, stall_factor", f"must be > 0, got {self.stall_s}, {self.stall_factor}")
        if self.water_balance is not None and not self.water_balance > 0:
            raise InputError("water_balance", f"must be > 0, got {self.water_balance}")


@dataclass(frozen=True)
class Diagnosis:
    """Why a run is being stopped as diverged: `cause` in words, the simulated
    time it showed at and `since_s`, the time of the first step of the symptom
    (time directories from there on are not trusted)."""

    kind: str
    cause: str
    time_s: float | None
    since_s: float | None
    #: body_speed: the body and its velocity (m/s) when it was caught
    body: str | None = None
    velocity_m_s: tuple[float, float, float] | None = None


def water_balance_diagnosis(balance, limit: float) -> Diagnosis | None:
    """A diagnosis when the run's water balance (post.read_water_balance: ``time_s``,
    ``initial_m3``, ``error``) first went beyond ``limit``, else None. The fields stay: the
    run is not numerically broken, it has stopped being sane (its results up to there hold)."""
    if balance is None or len(balance) == 0:
        return None
    err = np.asarray(balance["error"], float)
    over = np.flatnonzero(np.isfinite(err) & (np.abs(err) > limit))
    if not over.size:
        return None
    i = int(over[0])
    t = float(balance["time_s"].iloc[i])
    initial = float(balance["initial_m3"].iloc[0])
    what = "created" if err[i] > 0 else "lost"
    return Diagnosis(
        "water", f"the water balance went beyond {100 * limit:.3g} % of the initial {initial:.4g} m3: {err[i]:+.2%} "
        f"{what} by t = {t:.6g} s, so the run can no longer be sane (the overset makes and loses water at "
        "the body meshes' fringes; docs/stability.md); the scene's run.water_balance_limit sets the limit",
        t, None)


def _run_reaches(run: list[float], past_limit: bool, time_s: float, steps: int) -> bool:
    """Keep ``run``, the times of the consecutive steps past a limit (a step within it clears
    it); True once it holds ``steps`` of them."""
    if not past_limit:
        run.clear()
        return False
    run.append(time_s)
    return len(run) >= steps


class HealthWatch:
    """Looks at every step (and the parser's NaN flag) and names a divergence."""

    def __init__(self, limits: DivergenceLimits, max_courant: float,
                 domain_m: Sequence[Sequence[float]] | None = None):
        self.limits = limits
        self.max_courant = float(max_courant)
        self.domain = domain_m
        self._co_run: list[float] = []
        self._dt_run: list[float] = []

    def check_parser(self, parser: LogParser) -> Diagnosis | None:
        if parser.pcorr_failure is not None:
            t = parser.current_time_s
            return Diagnosis(
                "pcorr", "the overset flux correction (pcorr) diverged "
                f"({parser.pcorr_failure.strip()[:100]!r}): some cells have no valid donor, typically where an "
                "overset body mesh reaches a wall, the column or another body's mesh (docs/stability.md)", t, None)
        if parser.nonfinite_line is not None:
            t = parser.nonfinite_time_s
            return Diagnosis("nan", f"NaN/inf in the solver output: {parser.nonfinite_line.strip()[:120]!r}", t, t)
        return None

    def check_step(self, step: StepRecord) -> Diagnosis | None:
        lim = self.limits
        co = step.max_courant
        if _run_reaches(self._co_run, co is not None and co > lim.courant_factor * self.max_courant, step.time_s,
                        lim.courant_steps):
            return Diagnosis(
                "courant",
                f"Courant number runaway: max Co {co:.3g} > {lim.courant_factor:g} x maxCo "
                f"({self.max_courant:g}) for {len(self._co_run)} steps",
                step.time_s, self._co_run[0])
        dt = step.delta_t_s
        if _run_reaches(self._dt_run, dt is not None and lim.min_delta_t_s is not None and dt < lim.min_delta_t_s,
                        step.time_s, lim.delta_t_steps):
            return Diagnosis(
                "delta_t",
                f"time step collapsed: deltaT {dt:.3g} s < {lim.min_delta_t_s:.3g} s for "
                f"{len(self._dt_run)} steps",
                step.time_s, self._dt_run[0])
        if lim.max_body_speed_m_s is not None:
            for body in step.bodies:
                if not body.speed_m_s <= lim.max_body_speed_m_s:
                    return Diagnosis("body_speed", f"body {body.name} moves at {body.speed_m_s:.3g} m/s, faster than "
                                     f"any flow here ({lim.max_body_speed_m_s:.3g} m/s)", step.time_s, step.time_s,
                                     body.name, tuple(float(v) for v in body.velocity_m_s))
        if self.domain is not None:
            for body in step.bodies:
                out = _outside(body.centre_of_mass_m, self.domain, lim.domain_margin_m)
                if out:
                    return Diagnosis("left_domain", f"body {body.name} left the domain ({out})",
                                     step.time_s, step.time_s)
        return None


def _outside(p: Sequence[float], domain: Sequence[Sequence[float]], margin: float) -> str:
    for axis, (lo, hi), v in zip("xyz", domain, p):
        if not math.isfinite(v):
            return f"{axis} = {v}"
        if v < lo - margin:
            return f"{axis} = {v:.4g} m < {lo:.4g} m"
        if v > hi + margin:
            return f"{axis} = {v:.4g} m > {hi:.4g} m"
    return ""


# --------------------------------------------------------------------------- progress


class Progress:
    """A tqdm bar over simulated time: t / end, ETA, dt, max Co, each body's position and speed.

    `quiet`: nothing is drawn (CI, sweeps). Redraws are throttled by tqdm
    (`mininterval`), so calling `update` after every log read costs little.
    """

    def __init__(self, end_time_s: float, start_time_s: float = 0.0, quiet: bool = False,
                 label: str = "solver", stream=None):
        self.quiet = quiet
        self._bar = None
        if quiet:
            return
        from tqdm import tqdm

        self._bar = tqdm(
            total=float(end_time_s), initial=float(start_time_s), desc=label, unit="s",
            unit_scale=False, dynamic_ncols=True, mininterval=0.5, leave=True, file=stream or sys.stderr,
            bar_format="{desc}: {percentage:3.0f}%|{bar}| t={n:.4g}/{total:.4g} s [{elapsed}<{remaining}]{postfix}",
        )

    def update(self, step: StepRecord | None, note: str = "") -> None:
        if self._bar is None or step is None:
            return
        parts = []
        if step.delta_t_s is not None:
            parts.append(f"dt={step.delta_t_s:.2e}")
        if step.max_courant is not None:
            parts.append(f"Co={step.max_courant:.2f}")
        for b in step.bodies:
            x, y, z = b.centre_of_mass_m
            parts.append(f"{b.name}=({x:.3f},{y:.3f},{z:.3f}) {b.speed_m_s:.2f}m/s")
        if note:
            parts.append(note)
        self._bar.set_postfix_str(" ".join(parts), refresh=False)
        self._bar.update(max(0.0, step.time_s - self._bar.n))

    def write(self, message: str) -> None:
        """A message above the bar (on the bar's stream)."""
        if self._bar is not None:
            self._bar.write(message, file=self._bar.fp)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None
