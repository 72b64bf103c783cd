"""An unstable rigid-body engine is an error naming its realisation, not a data point.

MuJoCo meets a NaN, an Inf or a huge acceleration (``Nan, Inf or huge value in QACC at DOF n.
The simulation is unstable.``) by printing that warning, resetting the whole model to its
initial state and going on: the run ends normally, with bodies thrown back to their starts and
strikes at absurd speeds (a 2.3 kg container in a 20-ft box struck a column at 1,711 m/s and
894 MN, issue 48). :func:`engine_watch` catches MuJoCo's warnings while a batch steps; the
ensemble and design studies call :func:`raise_if_unstable` after it, which raises
:class:`UnstableEngineError` naming the realisation whose body the warning names (DOF ``n``
belongs to the body ``n // 6``: every body is one free joint, six DOFs, in the batch's order),
so the verb ends with exit 1 and writes no page.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from orchestrator.core.errors import DebrisfoamError

__all__ = ["UnstableEngineError", "engine_watch", "raise_if_unstable"]

_DOF_RE = re.compile(r"at DOF (\d+)")


class UnstableEngineError(DebrisfoamError, RuntimeError):
    """The rigid-body engine became unstable in a realisation (exit 1)."""


@contextmanager
def engine_watch() -> Iterator[list[str]]:
    """MuJoCo's warnings while the block runs, in a list (the process's handler restored after)."""
    import mujoco

    caught: list[str] = []
    previous = mujoco.get_mju_user_warning()
    mujoco.set_mju_user_warning(caught.append)
    try:
        yield caught
    finally:
        mujoco.set_mju_user_warning(previous)


def raise_if_unstable(warnings: Sequence[str], numbers: Sequence[int], bodies_per_realisation: Sequence[int],
                      what: str = "realisation") -> None:
    """UnstableEngineError when MuJoCo warned that the simulation is unstable, naming the
    realisation (of ``numbers``, with ``bodies_per_realisation`` bodies each, in the batch's
    order) whose degree of freedom the warning names; the whole batch when it names none."""
    bad = [w for w in warnings if "unstable" in w.lower() or "nan" in w.lower()]
    if not bad:
        return
    which = f"{what}s {numbers[0]}-{numbers[-1]} (one model)" if len(numbers) > 1 else f"{what} {numbers[0]}"
    match = _DOF_RE.search(bad[0])
    if match is not None:
        body, first = int(match.group(1)) // 6, 0
        for number, count in zip(numbers, bodies_per_realisation):
            if first <= body < first + count:
                which = f"{what} {number}"
                break
            first += count
    raise UnstableEngineError(f"{which}: the rigid-body engine (MuJoCo) became unstable: {bad[0].strip()} "
                              "MuJoCo resets the model and goes on, so nothing after it is a result: no page is "
                              "written. Check the realisation's draws (a mass far below its box's, a stiffness or "
                              "speed out of range)")
