"""Dask as the engine: the local threaded scheduler by default, a dask.distributed cluster by
address; progress from dask's own hooks through :mod:`bakeshop.progress`.

Every chunked job of :mod:`bakeshop.huge` is a list of independent block tasks, each reading
its own window of the source (a file path every worker sees, or a zarr store) and returning a
block of the output or a partial sum. The engine runs them and either fills an output array
in place as blocks complete (:meth:`Engine.assemble`), adds partial sums
(:meth:`Engine.reduce`, a tree reduction by dask), or returns every result in order
(:meth:`Engine.gather`). Locally, progress comes from a :class:`dask.callbacks.Callback`; on a
cluster, from the futures as they complete (``distributed.as_completed``). A lost worker's
tasks are run again by dask; outputs are written only by this process, atomically, once every
block is in.
"""

from __future__ import annotations

import os
import pickle
import socket
import threading
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

import numpy as np

from bakeshop import progress
from bakeshop import threads as kernel_threads
from bakeshop.errors import BakeshopError, UnsupportedError
from bakeshop.huge.memory import refuse, resolve_memory
from bakeshop.huge.scheduler import CONNECT_TIMEOUT, LOCAL_SCHEDULERS, scheduler_address
from bakeshop.io.stream import ArrayReader, Reader

T = TypeVar("T")


class InTask:
    """``fn`` as a dask task: the compiled kernels inside it use ``threads`` threads (one per
    task when the scheduler already runs a task per core), restored afterwards. Picklable."""

    def __init__(self, fn: Callable, threads: int):
        self.fn = fn
        self.threads = threads

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        """``fn(*args, **kwargs)`` with the kernels limited to this worker's share of the
        threads and progress silenced."""
        with kernel_threads.limited(self.threads), progress.silenced():
            return self.fn(*args, **kwargs)

    def __repr__(self) -> str:
        return getattr(self.fn, "__name__", repr(self.fn))


class Engine:
    """Where block tasks run, and the memory bound they plan under.

    Parameters
    ----------
    scheduler : str or distributed.Client, optional
        ``"threads"`` (default: dask's local threaded scheduler, one thread per core),
        ``"synchronous"`` (one task at a time, in this thread), the address of a dask.distributed
        scheduler (``tcp://HOST:PORT`` or ``tls://HOST:PORT``, checked by
        :func:`scheduler_address` and reached within :data:`CONNECT_TIMEOUT` seconds), or a
        connected ``distributed.Client``. None reads the BAKESHOP_SCHEDULER environment
        variable, then uses ``"threads"``.
    memory : int or str, optional
        The bound of each process (this one, and each worker's tasks): ``"2GB"``, bytes, or
        None for the default (:func:`bakeshop.huge.memory.resolve_memory`).
    """

    def __init__(self, scheduler: object = None, memory: int | str | None = None) -> None:
        self.memory = resolve_memory(memory)
        #: the dask.distributed Client, or None on this machine's scheduler.
        self.client: Any | None = None
        self._own_client = False
        if scheduler is None:
            scheduler = os.environ.get("BAKESHOP_SCHEDULER") or "threads"
        if isinstance(scheduler, str):
            if scheduler not in LOCAL_SCHEDULERS:
                self.client = _connect(scheduler)
                self._own_client = True
                scheduler = "distributed"
        else:
            self.client = scheduler
            scheduler = "distributed"
        self.scheduler = scheduler

    def close(self) -> None:
        """Disconnect from a cluster this engine connected to."""
        if self._own_client and self.client is not None:
            self.client.close()
        self.client = None

    def __enter__(self) -> Engine:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def distributed(self) -> bool:
        """True on a dask.distributed cluster."""
        return self.client is not None

    @property
    def workers(self) -> int:
        """Tasks that run at once in one process (threads of this machine, or the most threads
        of any worker): what each process's memory bound is shared by."""
        if self.client is not None:
            info = self.client.scheduler_info(n_workers=-1).get("workers", {})
            return max([w.get("nthreads", 1) for w in info.values()] or [1])
        if self.scheduler == "synchronous":
            return 1
        return os.cpu_count() or 1

    @property
    def total_workers(self) -> int:
        """Tasks that run at once in all (for planning enough blocks)."""
        if self.client is not None:
            info = self.client.scheduler_info(n_workers=-1).get("workers", {})
            return max(1, sum(w.get("nthreads", 1) for w in info.values()))
        return self.workers

    def per_task(self, fixed: int = 0, source: Reader | None = None) -> int:
        """Bytes one task may use: what the bound leaves after ``fixed`` (held by this process
        for the whole job: the output, plans), shared by the tasks that run at once, less what
        any read of ``source`` costs beyond its window (:attr:`Reader.read_floor`)."""
        floor = 0 if source is None else source.read_floor
        return max(0, max(0, self.memory - fixed) // self.workers - floor)

    def check_source(self, source: Reader) -> None:
        """Refuse a source whose smallest read (one whole compressed chunk or tile inflated,
        :attr:`Reader.read_floor`) does not fit a task's share of the bound, an in-memory
        source on a cluster (workers read files, not this process's memory), and a reader
        that cannot be sent to them, with its own error (pickling a Radiance reader walks the
        file's scanlines: a corrupt file is refused here, not in dask's serialisation)."""
        if source.read_floor > self.per_task():
            rows, cols = source.block
            error = refuse(
                f"reading one {rows}x{cols} block of the source (its codec inflates a block whole)",
                self.workers * source.read_floor,
                self.memory,
            )
            error.path = source.path
            raise error
        if not self.distributed:
            return
        if isinstance(source, ArrayReader):
            raise UnsupportedError(
                "a cluster's workers read their windows from files: give a file path that every "
                "worker sees (a .zarr store is best), not an array in memory"
            )
        pickle.dumps(source)

    def _task(self, fn: Callable) -> InTask:
        cores = kernel_threads.count()
        return InTask(fn, max(1, cores // self.workers) if not self.distributed else 1)

    def _compute(self, graph_items: Sequence[object], description: str) -> tuple[Any, ...]:
        """Compute dask collections locally with a progress task; returns their results."""
        import dask
        from dask.callbacks import Callback

        with progress.task(description) as t:

            class Hook(Callback):
                def _start_state(self, dsk: object, state: dict) -> None:
                    t.set_total(sum(len(state[k]) for k in ("ready", "waiting", "running")))

                def _posttask(
                    self, key: object, result: object, dsk: object, state: object, worker_id: object
                ) -> None:
                    t.advance()

            with Hook():
                return dask.compute(
                    *graph_items, scheduler=self.scheduler, num_workers=self.workers
                )

    def gather(self, fn: Callable, args: Sequence[tuple], description: str) -> list:
        """``[fn(*a) for a in args]`` as dask tasks, results in order."""
        from dask import delayed

        task = self._task(fn)
        items = [delayed(task, pure=False)(*a) for a in args]
        if not items:
            return []
        if self.client is not None:
            from distributed import as_completed

            futures = self.client.compute(items)
            results: list = [None] * len(futures)
            index = {f.key: i for i, f in enumerate(futures)}
            with progress.task(description, len(futures)) as t:
                for future, result in as_completed(futures, with_results=True):
                    results[index[future.key]] = result
                    t.advance()
            return results
        return list(self._compute(items, description))

    def assemble(
        self,
        fn: Callable,
        regions: Sequence[tuple],
        out: np.ndarray,
        args: tuple,
        description: str,
        origin: tuple[int, int] = (0, 0),
    ) -> np.ndarray:
        """Fill ``out[top:bottom, left:right]`` with ``fn(region, *args)`` for each region
        ``(top, bottom, left, right)`` (less ``origin``, where ``out`` starts); blocks are
        written as they complete (nothing beyond ``out`` and the blocks in flight is held)."""
        from dask import delayed

        task = self._task(fn)
        if self.client is not None:
            from distributed import as_completed

            items = [delayed(task, pure=False)(r, *args) for r in regions]
            futures = self.client.compute(items)
            where = {f.key: r for f, r in zip(futures, regions, strict=True)}
            with progress.task(description, len(futures)) as t:
                for future, block in as_completed(futures, with_results=True):
                    _fill(out, where[future.key], block, origin)
                    future.release()
                    t.advance()
            return out
        items = [
            delayed(_fill, pure=False)(out, r, delayed(task, pure=False)(r, *args), origin)
            for r in regions
        ]
        self._compute(items, description)
        return out

    def reduce(self, fn: Callable[..., T], args: Sequence[tuple], description: str) -> T:
        """``sum(fn(*a) for a in args)``: partial results (arrays, or tuples of arrays) summed
        by dask in a tree (float64 partials stay float64)."""
        from dask import delayed

        task = self._task(fn)
        items = [delayed(task, pure=False)(*a) for a in args]
        if not items:
            raise BakeshopError("nothing to reduce")
        if self.client is not None:
            from distributed import as_completed

            futures = self.client.compute(items)
            with progress.task(description, len(futures)) as t:
                for _ in as_completed(futures):
                    t.advance()
                while len(futures) > 1:  # summed on the workers, pairwise
                    futures = [
                        self.client.submit(_add, *futures[i : i + 2], pure=False)
                        if i + 1 < len(futures)
                        else futures[i]
                        for i in range(0, len(futures), 2)
                    ]
                return futures[0].result()
        while len(items) > 1:  # a tree of pairwise sums: each level halves the partials
            items = [
                delayed(_add, pure=True)(*items[i : i + 2]) if i + 1 < len(items) else items[i]
                for i in range(0, len(items), 2)
            ]
        return self._compute(items, description)[0]


def _fill(
    out: np.ndarray,
    region: tuple[int, int, int, int],
    block: np.ndarray,
    origin: tuple[int, int] = (0, 0),
) -> None:
    top, bottom, left, right = region
    oy, ox = origin
    out[top - oy : bottom - oy, left - ox : right - ox] = block


def _add(a: Any, b: Any) -> Any:
    if isinstance(a, tuple):
        return tuple(_add(x, y) for x, y in zip(a, b, strict=True))
    if a is None:
        return b
    if b is None:
        return a
    return a + b


def _connect(address: str) -> Any:
    """A client of the scheduler at ``address``, reached within :data:`CONNECT_TIMEOUT`
    seconds. distributed bounds the connection but not the handshake that follows (a peer that
    accepts and never answers holds ``Client()`` until it closes), so the client is made in a
    daemon thread that is waited for that long."""
    host, port = scheduler_address(address)
    try:
        import dask
        from distributed import Client
    except ImportError:
        raise UnsupportedError(
            "a dask.distributed scheduler needs the distributed package: install bakeshop[huge]"
        ) from None
    timeout = f"{CONNECT_TIMEOUT}s"
    outcome: list[Any] = []

    def connect() -> None:
        try:
            with dask.config.set({"distributed.comm.timeouts.connect": timeout}):
                outcome.append(Client(address, timeout=timeout))
        except Exception as e:  # whatever distributed raises is the reason it could not
            outcome.append(e)

    try:
        socket.create_connection((host, port), timeout=CONNECT_TIMEOUT).close()
    except OSError as e:
        reason = e.strerror or str(e) or type(e).__name__
        raise BakeshopError(f"cannot reach the dask scheduler: {reason}", address) from None
    thread = threading.Thread(target=connect, name="bakeshop-connect", daemon=True)
    thread.start()
    thread.join(CONNECT_TIMEOUT)
    if not outcome:
        reason = f"no answer within {CONNECT_TIMEOUT} s (is a dask scheduler listening there?)"
    elif isinstance(outcome[0], Exception):
        reason = str(outcome[0]) or type(outcome[0]).__name__
    else:
        return outcome[0]
    raise BakeshopError(f"cannot reach the dask scheduler: {reason}", address)
