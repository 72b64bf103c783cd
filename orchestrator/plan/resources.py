"""What a plan asks of the machine: cells, memory and wall time, checked before anything is written.

Two kinds of limit (docs/architecture.md, "Resource guard"):

- **Hard** (bad input, exit 2, naming ``mesh.cell_size_m`` and the scene file): more cells than
  OpenFOAM's 32-bit labels can number (:data:`MAX_CELLS_LABELS`, machine-independent, so
  :func:`require_labels` runs inside the planner before it builds anything cell by cell), or more
  memory than this machine has in all (:data:`BYTES_PER_CELL`).
- **Soft** (a warning, and the verb goes ahead only when confirmed: ``--yes``, or yes at a prompt):
  memory over half of what is available now, or an estimated solver time over
  :data:`SOFT_WALL_TIME_S`.

The checks read numbers only (:class:`Demand`, from a plan or a case's plan.json); the machine is
:meth:`Machine.here` (os.cpu_count and /proc/meminfo).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

from orchestrator.core.errors import InputError

__all__ = [
    "BASE_BYTES_PER_RANK",
    "BYTES_PER_CELL",
    "LABEL_MAX",
    "MAX_CELLS_LABELS",
    "SOFT_MEMORY_FRACTION",
    "SOFT_WALL_TIME_S",
    "Demand",
    "LargeRunError",
    "Machine",
    "assess",
    "check_resources",
    "require_labels",
]

#: The largest label of Debian's OpenFOAM v1912 build (WM_LABEL_SIZE=32 in
#: /usr/share/openfoam/etc/bashrc): cells, faces and points are all numbered with it.
LABEL_MAX = 2**31 - 1
#: A hexahedral mesh has about 3 internal faces per cell, so its faces run out of labels at a
#: third of LABEL_MAX cells, well before its cells do.
MAX_CELLS_LABELS = LABEL_MAX // 3
#: Peak resident memory per cell of the solver (bytes), measured here with /usr/bin/time -v on
#: serial runs of rendered cases at two cell sizes (the slope between them): interFoam 1,915 B
#: (nodebris.yaml, 74,145 and 248,492 cells: 251 and 577 MiB); overInterDyMFoam 3,000 B
#: (hard/close-to-column.yaml, 71,076 and 137,931 cells: 318 and 514 MiB). Rounded up.
BYTES_PER_CELL = {"interFoam": 2_000, "overInterDyMFoam": 3_100}
#: The solver's memory that does not grow with the mesh (libraries, dictionaries), per MPI rank:
#: about 115 MB in both measurements above.
BASE_BYTES_PER_RANK = 120_000_000
#: Soft limit on memory: a run may take at most this fraction of the memory available now
#: (other jobs, the post-processing and the page cache need the rest).
SOFT_MEMORY_FRACTION = 0.5
#: Soft limit on the planner's estimated solver time (s): 6 h, five times the longest member of
#: the shipped sweeps (debris-mesh-study at 3 cm, about 1.1 h).
SOFT_WALL_TIME_S = 6 * 3600.0


@dataclass(frozen=True)
class Machine:
    """The machine a run would use: its cores and its memory (bytes), all and available now."""

    cores: int
    total_memory_B: int
    available_memory_B: int

    @classmethod
    def here(cls) -> "Machine":
        """This machine: os.cpu_count() and /proc/meminfo (MemTotal, MemAvailable), else sysconf."""
        total = available = None
        try:
            with open("/proc/meminfo") as fh:
                info = {line.split(":")[0]: int(line.split()[1]) * 1024 for line in fh if line.split()[1:2]}
            total, available = info.get("MemTotal"), info.get("MemAvailable")
        except (OSError, ValueError, IndexError):
            pass
        page = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096
        if total is None:
            total = os.sysconf("SC_PHYS_PAGES") * page
        if available is None:
            available = os.sysconf("SC_AVPHYS_PAGES") * page
        return cls(os.cpu_count() or 1, int(total), int(available))


@dataclass(frozen=True)
class Demand:
    """What a run asks for: cells, solver, MPI ranks and the planner's solver-time estimate (s)."""

    cells: int
    solver: str
    cores: int
    wall_s: float

    @property
    def memory_B(self) -> int:
        """Peak memory of the solver (bytes): :data:`BYTES_PER_CELL` per cell and
        :data:`BASE_BYTES_PER_RANK` per rank."""
        per_cell = BYTES_PER_CELL.get(self.solver, max(BYTES_PER_CELL.values()))
        return int(self.cells) * per_cell + max(1, int(self.cores)) * BASE_BYTES_PER_RANK

    @classmethod
    def of_plan(cls, plan: Any) -> "Demand":
        """The demand of a :class:`~orchestrator.plan.model.ModelPlan`."""
        return cls(int(plan.cell_count), plan.solver, int(plan.cores), float(plan.estimated_wall_time_s or 0.0))

    @classmethod
    def of_plan_json(cls, data: dict, cores: int | None = None) -> "Demand":
        """The demand of a case's plan.json (as a dict), run on ``cores`` ranks (default: its own)."""
        n = data.get("decomposition") or (1, 1, 1)
        n = n.get("n", (1, 1, 1)) if isinstance(n, dict) else n  # plan.json: {"method": ..., "n": [nx, ny, nz]}
        planned = max(1, int(n[0]) * int(n[1]) * int(n[2]))
        wall = float(data.get("estimated_wall_time_s") or 0.0)
        ranks = int(cores or planned)
        return cls(int(data.get("cell_count") or 0), str(data.get("solver")), ranks, wall * planned / ranks)


class LargeRunError(InputError):
    """A plan over a soft limit that nobody confirmed: the warnings in ``messages``."""

    def __init__(self, messages: list[str], source: str | None = None):
        self.messages = list(messages)
        super().__init__("mesh.cell_size_m", "; ".join(self.messages) + ": give --yes to go ahead, or a coarser "
                         "mesh.cell_size_m (or a shorter run.end_time_s)", source)

    def with_source(self, source: str) -> "LargeRunError":
        return LargeRunError(self.messages, source)


def _gb(n: float) -> str:
    return f"{n / 1e9:.3g} GB"


def _hours(s: float) -> str:
    return f"{s / 3600:.3g} h" if s >= 3600 else f"{s / 60:.3g} min"


def require_labels(cells: int, source: str | None = None) -> None:
    """InputError on ``mesh.cell_size_m`` when ``cells`` are more than 32-bit labels can number."""
    if cells > MAX_CELLS_LABELS:
        raise InputError("mesh.cell_size_m", f"{cells:,} planned cells: over the limit of {MAX_CELLS_LABELS:,} "
                         f"(OpenFOAM's 32-bit labels, {LABEL_MAX:,} at most, number about 3 faces per cell); "
                         "choose a coarser cell size", source)


def assess(demand: Demand, machine: Machine) -> tuple[list[str], list[str]]:
    """(hard, soft): the limits ``demand`` breaks on ``machine``, each as a sentence with its numbers."""
    hard: list[str] = []
    soft: list[str] = []
    if demand.cells > MAX_CELLS_LABELS:
        hard.append(f"{demand.cells:,} planned cells: over the limit of {MAX_CELLS_LABELS:,} (OpenFOAM's 32-bit "
                    f"labels, {LABEL_MAX:,} at most, number about 3 faces per cell)")
    per_cell = BYTES_PER_CELL.get(demand.solver, max(BYTES_PER_CELL.values()))
    memory = demand.memory_B
    if memory > machine.total_memory_B:
        fit = max(0, (machine.total_memory_B - max(1, demand.cores) * BASE_BYTES_PER_RANK) // per_cell)
        hard.append(f"{demand.cells:,} planned cells need about {_gb(memory)} of memory ({per_cell:,} bytes per cell "
                    f"for {demand.solver}): over the limit of {fit:,} cells that this machine's "
                    f"{_gb(machine.total_memory_B)} can hold")
    elif memory > SOFT_MEMORY_FRACTION * machine.available_memory_B:
        soft.append(f"{demand.cells:,} planned cells need about {_gb(memory)} of memory, over "
                    f"{SOFT_MEMORY_FRACTION:.0%} of the {_gb(machine.available_memory_B)} available now")
    ranks = min(max(1, demand.cores), machine.cores)
    wall = demand.wall_s * max(1, demand.cores) / ranks
    if wall > SOFT_WALL_TIME_S:
        soft.append(f"{demand.cells:,} planned cells: estimated solver time about {_hours(wall)} on {ranks} core(s) "
                    f"(over {_hours(SOFT_WALL_TIME_S)})")
    return hard, soft


def check_resources(demand: Demand, source: str | None = None, *, confirmed: bool = False,
                    machine: Machine | None = None) -> list[str]:
    """The soft-limit warnings of ``demand`` on ``machine`` (default: this one), when allowed.

    Raises InputError (``mesh.cell_size_m``, the numbers, ``source``) over a hard limit, and
    :class:`LargeRunError` over a soft one unless ``confirmed``.
    """
    hard, soft = assess(demand, machine or Machine.here())
    if hard:
        raise InputError("mesh.cell_size_m", hard[0] + "; choose a coarser cell size", source)
    if soft and not confirmed:
        raise LargeRunError(soft, source)
    return soft
