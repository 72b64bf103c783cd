"""Parameter sweeps: one base scene, axes over dotted scene keys, one case per member.

The stages of a sweep, one module each:

* :mod:`.spec`: the sweep file, its members expanded and validated (:func:`load_sweep`);
* :mod:`.store`: the sweep folder's records (member.json, sweep.json) and the results store
  results.sqlite (:func:`load_store`);
* :mod:`.member`: one member rendered, run and post-processed on a worker (:func:`run_member`);
* :mod:`.executors`: where members run (a thread pool, or a Dask cluster);
* :mod:`.run`: :func:`run_sweep` and :func:`dry_run`.

The format of a sweep file and the `debrisfoam sweep` command are documented in docs/sweeps.md.
"""

from orchestrator.studies.sweep.member import run_member
from orchestrator.studies.sweep.run import SweepResult, dry_run, run_sweep
from orchestrator.studies.sweep.spec import Member, Sweep, SweepMemberError, default_sweep_dir, load_sweep, member_id
from orchestrator.studies.sweep.store import (
    MEMBER_JSON,
    STORE_FILE,
    STORE_TABLE,
    load_store,
    member_metrics,
    member_state,
)

__all__ = [
    "MEMBER_JSON",
    "STORE_FILE",
    "STORE_TABLE",
    "Member",
    "Sweep",
    "SweepMemberError",
    "SweepResult",
    "default_sweep_dir",
    "dry_run",
    "load_store",
    "load_sweep",
    "member_id",
    "member_metrics",
    "member_state",
    "run_member",
    "run_sweep",
]
