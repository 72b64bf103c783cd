"""Where a sweep's members run: a thread pool on this machine, or a Dask cluster.

Both executors give the sweep the same three things (:class:`Executor`): ``submit`` a task,
its futures ``as_completed``, and a ``stop`` handle the members watch (a threading.Event
locally, a distributed.Event on Dask), so :func:`orchestrator.studies.sweep.run.run_sweep`
has one code path for either. :class:`StartWatcher` tells the parent when a member has
started on its worker (members say so in their member.json).

Signals are handled here too (:func:`signal_handlers`): Dask's worker processes are spawned
with SIGINT ignored, so a Ctrl-C reaches the parent only and it stops its members cleanly.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import logging
import os
import signal
import threading
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator

from orchestrator.core.errors import DebrisfoamError, InputError
from orchestrator.studies.sweep.spec import EXECUTORS, Member
from orchestrator.studies.sweep.store import read_member_record

#: Seconds between the parent's looks for members that have started.
WATCH_INTERVAL_S = 0.5


@dataclass
class Executor:
    """What the sweep needs of an executor: submit, completions as they come, a stop handle."""

    submit: Callable[..., Any]
    as_completed: Callable[[Iterable[Any]], Iterator[Any]]
    stop: Any
    describe: str


def default_slots(cores_per_member: int) -> int:
    """Members at once when the user does not say: this machine's cores over a member's."""
    return max(1, (os.cpu_count() or 1) // max(1, cores_per_member))


def check_pool(executor: str, workers: int | None, batch_size: int) -> None:
    """InputError naming the flag unless ``executor`` is one of :data:`EXECUTORS`, ``workers`` (when
    given) > 0 and ``batch_size`` >= 1: the pool of realisations ``ensemble`` and ``design`` run."""
    if executor not in EXECUTORS:
        raise InputError("--executor", f"must be one of {', '.join(EXECUTORS)}, got {executor!r}")
    if workers is not None and int(workers) <= 0:
        raise InputError("--workers", f"must be > 0, got {workers}")
    if int(batch_size) < 1:
        raise InputError("--batch-size", f"must be a whole number >= 1, got {batch_size}")


@contextlib.contextmanager
def local_executor(slots: int) -> Iterator[Executor]:
    """A thread pool of ``slots`` threads; each member runs its own MPI ranks."""
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=slots, thread_name_prefix="debrisfoam-member")
    try:
        yield Executor(lambda fn, *args, key: pool.submit(fn, *args),
                       concurrent.futures.as_completed, threading.Event(),
                       f"local, {slots} member(s) at a time")
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


@contextlib.contextmanager
def signal_handlers(handlers: dict[int, Any]) -> Iterator[None]:
    """`handlers` (signal -> handler) installed for the block, the previous ones restored
    after it; outside the main thread, where Python cannot set handlers, signals are left alone.

    The sweep uses it twice: SIGINT ignored while Dask's worker processes are spawned (they
    inherit it, so a Ctrl-C at the terminal, sent to the whole process group, reaches only the
    parent, which then stops the running members cleanly instead of their workers dying under
    them); and SIGTERM (`kill`, a batch system's stop) and SIGINT raising KeyboardInterrupt
    while the members run, so the sweep stops them cleanly either way, SIGINT too when the
    shell started the sweep with it ignored (`nohup ... &`).
    """
    try:
        previous = {sig: signal.signal(sig, handler) for sig, handler in handlers.items()}
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


@contextlib.contextmanager
def dask_executor(slots: int, scheduler: str | None, cluster_kwargs: dict | None) -> Iterator[Executor]:
    """The Dask scheduler at ``scheduler``, or a LocalCluster of ``slots`` single-threaded
    worker processes (``cluster_kwargs`` override its options)."""
    import dask
    from distributed import Client, Event, LocalCluster, as_completed

    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError) as err:
            raise DebrisfoamError(f"cannot reach the Dask scheduler at {scheduler}: {err}") from None
        describe = f"dask scheduler {scheduler}"
    else:
        # the dashboard on a free port: two clusters at once (two sweeps, a test run beside a
        # study) would otherwise contend for 8787 and warn on stderr
        options = {"n_workers": slots, "threads_per_worker": 1, "processes": True, "dashboard_address": ":0",
                   "memory_limit": 0, "silence_logs": logging.ERROR}
        options.update(cluster_kwargs or {})
        # Ctrl-C is the parent's: it stops the members through `stop`
        with signal_handlers({signal.SIGINT: signal.SIG_IGN}), dask.config.set(worker_environment()):
            cluster = LocalCluster(**options)
        client = Client(cluster)
        describe = f"dask LocalCluster, {options['n_workers']} worker(s)"
    stop = None
    try:
        stop = Event(f"debrisfoam-sweep-stop-{uuid.uuid4().hex}", client=client)
        yield Executor(lambda fn, *args, key: client.submit(fn, *args, key=key, pure=False),
                       as_completed, stop, describe)
    finally:
        _close_dask(client, cluster, stop)


def worker_environment() -> dict[str, Any]:
    """Dask's configuration for the environment its nannies start workers in, without
    ``MALLOC_TRIM_THRESHOLD_``. Distributed sets it to 64 KiB to hand freed memory back to the
    system at once; set at all, it also fixes glibc's mmap threshold at its 128 KiB start
    value, so every temporary array over that size is mapped and unmapped again, page by page.
    The transport's forcing makes such arrays at every update: measured on the 1-debris
    record (1,024 realisations, 2 workers), 8.3 realisations a second with it, 17.1 without
    (the local process pool's rate), the same with it set in a local pool (8.4)."""
    import dask

    environ = dict(dask.config.get("distributed.nanny.pre-spawn-environ", default={}) or {})
    environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    return {"distributed.nanny.pre-spawn-environ": environ}


class _DropCancelled(logging.Filter):
    """Drops log records that carry an asyncio.CancelledError (what a scheduler's close does
    to the requests still pending on it); every other record passes."""

    def filter(self, record: logging.LogRecord) -> bool:
        exc = record.exc_info[1] if record.exc_info else None
        return not isinstance(exc, asyncio.CancelledError)


# the loggers that report a request cancelled by the scheduler's or a worker's close
_SHUTDOWN_LOGGERS = ("distributed.event", "distributed.core", "distributed.utils", "distributed.worker",
                     "distributed.scheduler", "distributed.client")


def _close_dask(client: Any, cluster: Any, stop: Any) -> None:
    """Shut a sweep's Dask executor down in order: the stop event, the client, the cluster.

    Every member's stop bridge (:func:`orchestrator.studies.sweep.member.stop_flag`) keeps a
    one-second Event.wait open on the scheduler until it notices its member has returned; a
    scheduler closed under such a wait cancels it, and distributed logs that as an ERROR with
    an asyncio.CancelledError traceback, on a sweep whose members all finished. So the stop
    event is set first (its members are done, or stopping because the sweep is ending anyway):
    the pending waits return, and the bridges end. Then the client closes, then the cluster
    (ours only: an existing scheduler is left running). A CancelledError that still reaches
    the log during these closes (a wait sent just before the set) is dropped; errors at any
    other time, and other errors, are logged as ever.
    """
    if stop is not None:
        with contextlib.suppress(Exception):
            stop.set()
    quiet = _DropCancelled()
    loggers = [logging.getLogger(name) for name in _SHUTDOWN_LOGGERS]
    for logger in loggers:
        logger.addFilter(quiet)
    try:
        with contextlib.suppress(asyncio.CancelledError):
            client.close()
        if cluster is not None:
            with contextlib.suppress(asyncio.CancelledError):
                cluster.close()
    finally:
        for logger in loggers:
            logger.removeFilter(quiet)


def open_executor(kind: str, slots: int, scheduler: str | None,
                  cluster_kwargs: dict | None) -> contextlib.AbstractContextManager[Executor]:
    """The executor of ``kind`` ("local" or "dask"), as a context manager."""
    if kind == "dask":
        return dask_executor(slots, scheduler, cluster_kwargs)
    return local_executor(slots)


class StartWatcher:
    """Tells the parent when members start: each writes member.json (status running, this
    sweep's token) in its case folder when its run begins; this thread looks for them."""

    def __init__(self, members: dict[str, Member], out: Path, token: str, say: Callable[[Member], None]):
        self.waiting = dict(members)
        self.out, self.token, self.say = out, token, say
        self.done = threading.Event()
        self.lock = threading.Lock()
        self.thread = threading.Thread(target=self._loop, name="debrisfoam-sweep-watch", daemon=True)
        self.thread.start()

    def _loop(self) -> None:
        while not self.done.wait(WATCH_INTERVAL_S):
            self.poll()

    def poll(self) -> None:
        with self.lock:
            for mid, member in list(self.waiting.items()):
                record = read_member_record(self.out / mid)
                if record and record.get("token") == self.token:
                    del self.waiting[mid]
                    self.say(member)

    def forget(self, mid: str) -> None:
        with self.lock:
            self.waiting.pop(mid, None)

    def close(self) -> None:
        self.done.set()
        self.thread.join()
