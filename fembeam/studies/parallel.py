"""Run independent tasks on local cores or on a Dask distributed cluster.

A task is ``(func, kwargs)`` with ``func`` a module-level (picklable) function.  Results
come back in task order whatever the completion order, so a study gives the same table
(bit for bit: every task is computed independently) on any executor.
"""
from __future__ import annotations

import os
import sys
from typing import Any, Callable

__all__ = ["run_tasks", "default_workers"]

Task = tuple[Callable[..., Any], dict]


def default_workers() -> int:
    """Local worker processes: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _call(func, kwargs):
    """``func(**kwargs)`` with single-threaded BLAS: the tasks are small, and BLAS
    threads only fight the other workers for the cores (measured on the Fig. 13 sweep,
    2 cores: 58.6 s with the default 2 OpenBLAS threads per worker, 18.7 s with 1)."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover - threadpoolctl is a dependency
        return func(**kwargs)
    with threadpool_limits(limits=1):
        return func(**kwargs)


def run_tasks(tasks: list[Task], workers: int | None = None, scheduler=None, progress: bool = True,
              desc: str = "tasks") -> list:
    """Results of ``func(**kwargs)`` for every task, in order.

    ``scheduler``: None (local), a Dask scheduler address (``"tcp://host:8786"``, or the
    ``inproc://`` address of an in-process ``LocalCluster``) or a ``distributed.Client``.
    ``workers``: local worker processes (default :func:`default_workers`; 1 runs in
    this process, without a pool).  ``progress``: a tqdm bar on stderr.
    """
    from tqdm import tqdm

    bar = tqdm(total=len(tasks), desc=desc, file=sys.stderr, disable=not progress, unit="case",
               dynamic_ncols=True)
    out: list = [None] * len(tasks)
    try:
        if scheduler is not None:
            _run_dask(tasks, scheduler, out, bar)
        elif (workers or default_workers()) == 1 or len(tasks) <= 1:
            for i, (f, kw) in enumerate(tasks):
                out[i] = _call(f, kw)
                bar.update()
        else:
            from concurrent.futures import ProcessPoolExecutor, as_completed

            pool = ProcessPoolExecutor(max_workers=workers or default_workers())
            try:
                futs = {pool.submit(_call, f, kw): i for i, (f, kw) in enumerate(tasks)}
                for fut in as_completed(futs):
                    out[futs[fut]] = fut.result()
                    bar.update()
            except BaseException:   # an error, Ctrl-C or SIGTERM: stop the workers now, queue dropped
                for proc in list((getattr(pool, "_processes", None) or {}).values()):
                    proc.kill()          # SIGKILL: the workers inherit our SIGTERM handler
                pool.shutdown(wait=False, cancel_futures=True)
                raise
            pool.shutdown()
    finally:
        bar.close()
    return out


def _run_dask(tasks: list[Task], scheduler, out: list, bar) -> None:
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futs = [client.submit(_call, f, kw, pure=False) for f, kw in tasks]
        index = {fut.key: i for i, fut in enumerate(futs)}
        for fut in as_completed(futs):
            out[index[fut.key]] = fut.result()
            bar.update()
    finally:
        if own:
            client.close()
