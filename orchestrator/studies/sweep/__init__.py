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

import importlib

#: Where each public name lives. They are loaded when first asked for, so that reading a sweep
#: file (:mod:`.spec`) does not load the stages that run its members: a sweep refused at once is
#: refused in a fraction of a second.
_HOMES = {
    "run_member": "member",
    "SweepResult": "run", "dry_run": "run", "run_sweep": "run",
    "Member": "spec", "Sweep": "spec", "SweepMemberError": "spec", "default_sweep_dir": "spec",
    "load_sweep": "spec", "member_id": "spec",
    "MEMBER_JSON": "store", "STORE_FILE": "store", "STORE_TABLE": "store", "load_store": "store",
    "member_metrics": "store", "member_state": "store",
}


def __getattr__(name: str):
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")  # internal: the module __getattr__ protocol
    return getattr(importlib.import_module(f"{__name__}.{_HOMES[name]}"), name)


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
