"""Running OpenFOAM v1912 applications: argv, cwd, logs, failures.

Every application runs through `run_step`: an argv list (never a shell string),
`cwd` = the case, stdout and stderr to `log.<step>` in the case, and a
`StepError` naming the step, the reason found in its log (the `--> FOAM FATAL
ERROR` block, a floating point exception, ...) and the log path when it fails.
A step given a done-predicate is skipped when its outputs exist, so runs are
idempotent and resumable. What a case's steps are is `orchestrator.case.foam`'s.

A 40-line subprocess wrapper gives the argv/cwd/log/error contract above, `mpirun`
prefixed with our environment (`foam_env`); `check_mesh_summary` parses checkMesh's log.
"""

from __future__ import annotations

import os
import re
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

from orchestrator.case.foam import MESH_OK, WM_PROJECT_DIR, parallel_argv
from orchestrator.core.errors import DebrisfoamError

#: Lines of the log quoted when no specific failure is recognised.
TAIL_LINES = 15
#: How much of the end of a log is searched for the failure.
LOG_TAIL_BYTES = 1 << 20


class StepError(DebrisfoamError, RuntimeError):
    """An OpenFOAM step failed: names the step, the reason from its log, and the log."""

    def __init__(self, step: str, reason: str, log_path: str | Path, returncode: int | None = None):
        self.step = step
        self.reason = reason
        self.log_path = Path(log_path)
        self.returncode = returncode
        code = f" (exit code {returncode})" if returncode not in (None, 0) else ""
        super().__init__(f"step {step!r} failed{code}: {reason}\n  log: {self.log_path}")


def foam_env(base: dict[str, str] | None = None) -> dict[str, str]:
    """The environment OpenFOAM v1912 needs here (docs/openfoam-notes.md, "Environment").

    WM_PROJECT_DIR for the etc/ files (caseDicts, controlDict); mpirun as root
    needs the two OMPI_ALLOW_RUN_AS_ROOT variables. `base` defaults to os.environ.
    """
    env = dict(os.environ if base is None else base)
    env.setdefault("WM_PROJECT_DIR", WM_PROJECT_DIR)
    env["OMPI_ALLOW_RUN_AS_ROOT"] = "1"
    env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    # a run on a workstation must not sit waiting for a slot count it cannot get
    env.setdefault("OMPI_MCA_rmaps_base_oversubscribe", "1")
    # a rank waiting for a message gives its core back instead of spinning on it: on a machine
    # whose cores are busy with other work a small case runs faster (0.78x the wall time beside two
    # busy processes, the same when idle: benchmarks/mpi_yield.md)
    env.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")
    return env


@dataclass(frozen=True)
class StepResult:
    name: str
    argv: tuple[str, ...]
    log_path: Path
    wall_s: float
    skipped: bool
    returncode: int | None


def run_step(name: str, argv: Sequence[str], case_dir: str | Path, np: int = 1,
             done: Callable[[Path], bool] | None = None, env: dict[str, str] | None = None,
             timeout_s: float | None = None) -> StepResult:
    """Run one OpenFOAM application in `case_dir`, output to `case_dir/log.<name>`.

    Skipped (nothing run, log untouched) when `done(case_dir)` is true. Raises
    StepError when the application exits non-zero, prints a FOAM FATAL ERROR, or
    exceeds `timeout_s`.
    """
    case = Path(case_dir)
    log_path = case / f"log.{name}"
    full = parallel_argv(argv, np)
    if done is not None and done(case):
        return StepResult(name, tuple(full), log_path, 0.0, True, None)
    if not case.is_dir():
        raise StepError(name, f"case directory {case} does not exist", log_path)
    run_env = dict(env or foam_env())
    # OpenFOAM compares $PWD with the real cwd and warns when they differ
    run_env["PWD"] = str(case.resolve())
    start = time.perf_counter()
    with open(log_path, "w") as log:
        try:
            proc = subprocess.run(full, cwd=case, stdout=log, stderr=subprocess.STDOUT,
                                  env=run_env, timeout=timeout_s)
        except FileNotFoundError:
            raise StepError(name, f"{full[0]!r} not found: is OpenFOAM v1912 installed (make openfoam)?",
                            log_path) from None
        except subprocess.TimeoutExpired:
            raise StepError(name, f"did not finish within {timeout_s} s", log_path) from None
    wall = time.perf_counter() - start
    # a fatal error ends the run, so it is in the log's tail (solver logs reach GBs)
    text = _tail(log_path, LOG_TAIL_BYTES)
    if proc.returncode != 0 or _FATAL.search(text):
        raise StepError(name, failure_reason(text), log_path, proc.returncode)
    return StepResult(name, tuple(full), log_path, wall, False, proc.returncode)


def _tail(path: Path, max_bytes: int) -> str:
    """The last `max_bytes` of a text file (from the start of a line)."""
    with open(path, "rb") as f:
        f.seek(0, os.SEEK_END)
        size = f.tell()
        f.seek(max(0, size - max_bytes))
        data = f.read()
    text = data.decode(errors="replace")
    if size > max_bytes and "\n" in text:
        text = text.split("\n", 1)[1]
    return text


_FATAL = re.compile(r"^(?:\[\d+\]\s*)?--> FOAM FATAL (?:IO )?ERROR", re.M)
_RANK = re.compile(r"^\[\d+\] ?")


def failure_reason(log_text: str) -> str:
    """Why an OpenFOAM application failed, from its log.

    The first `--> FOAM FATAL (IO) ERROR` block (its message, without the source
    location lines; rank prefixes `[n]` of parallel runs removed), else a floating
    point exception, else the last lines of the log.
    """
    lines = [_RANK.sub("", ln.rstrip()) for ln in log_text.splitlines()]
    for i, line in enumerate(lines):
        if line.startswith("--> FOAM FATAL"):
            message = [line]
            for nxt in lines[i + 1:]:
                if nxt.strip().startswith(("From function", "From ", "FOAM exiting", "FOAM aborting")):
                    break
                if nxt.strip():
                    message.append(nxt.strip())
                if len(message) > 12:
                    break
            return "\n    ".join(message)
    # not the banner every v1912 log prints ("trapFpe: Floating point exception trapping enabled")
    if re.search(r"sigFpe::sigHandler|Signal: Floating point exception|signal 8", log_text):
        where = ""
        times = re.findall(r"^Time = (\S+)", log_text, re.M)
        if times:
            where = f" at simulated time {times[-1]} s"
        return f"floating point exception (solution diverged or invalid operation){where}"
    tail = [ln for ln in lines if ln.strip()][-TAIL_LINES:]
    return "no FOAM FATAL ERROR in the log; its last lines:\n    " + "\n    ".join(tail)


# --------------------------------------------------------------------------- checkMesh


@dataclass(frozen=True)
class MeshSummary:
    """checkMesh's verdict and the figures a user looks at before a long run."""

    ok: bool
    cells: int
    points: int
    faces: int
    regions: int
    failed_checks: int
    max_non_orthogonality_deg: float
    max_skewness: float
    max_aspect_ratio: float
    #: cells by type (hexahedra, prisms, ...), non-zero counts only
    cell_types: dict[str, int]


_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _float(pattern: str, text: str, default: float = float("nan")) -> float:
    m = re.search(pattern, text, re.M)
    return float(m.group(1)) if m else default


def check_mesh_summary(log_path: str | Path) -> MeshSummary:
    """Parse a checkMesh log: verdict (`Mesh OK.` / `Failed n mesh checks.`), counts, quality.

    Raises StepError (step "checkMesh") when the log holds no verdict (checkMesh
    did not finish).
    """
    path = Path(log_path)
    text = path.read_text(errors="replace") if path.is_file() else ""
    ok = MESH_OK.search(text) is not None
    failed = re.search(r"^\s*Failed (\d+) mesh checks\.", text, re.M)
    if not ok and not failed:
        raise StepError("checkMesh", "no verdict in the checkMesh log (did it finish?)" if text
                        else "no checkMesh log", path)
    types = {}
    block = re.search(r"Overall number of cells of each type:\n(.*?)\n\n", text, re.S)
    if block:
        for name, count in re.findall(r"^\s*([\w ]+?):\s+(\d+)", block.group(1), re.M):
            if int(count):
                types[name.strip()] = int(count)
    regions = re.search(r"Number of regions: (\d+)", text)
    return MeshSummary(
        ok=ok,
        cells=int(_float(r"^\s*cells:\s+(\d+)", text, -1)),
        points=int(_float(r"^\s*points:\s+(\d+)", text, -1)),
        faces=int(_float(r"^\s*faces:\s+(\d+)", text, -1)),
        regions=int(regions.group(1)) if regions else 1,
        failed_checks=int(failed.group(1)) if failed else 0,
        max_non_orthogonality_deg=_float(rf"Mesh non-orthogonality Max:\s*({_NUM})", text),
        # "Max skewness = 0.3 OK." or " ***Max skewness = 6.27, 6 highly skew faces ..."
        max_skewness=_float(rf"Max skewness = ({_NUM})", text),
        # "Max aspect ratio = 4.2 OK." or " ***High aspect ratio cells found, Max aspect ratio: 1.2e+03, ..."
        max_aspect_ratio=_float(rf"Max aspect ratio(?: =|:)\s*({_NUM})", text),
        cell_types=types,
    )
