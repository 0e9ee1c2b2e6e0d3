"""Run independent tasks on local cores or on a Dask distributed cluster.

A task is ``(func, kwargs)`` with ``func`` a module-level (picklable) function.  Results
come back in task order whatever the completion order, so a study gives the same table
(bit for bit: every task is computed independently) on any executor.

Nothing finished is lost:

* with a ``journal`` file every finished task is appended to it at once (one JSON line,
  flushed and synced), keyed by the function and its arguments; a later run with the same
  journal takes those results instead of recomputing them, so an interrupted study
  resumes where it stopped.  The caller removes the journal once its outputs are written.
* an error, Ctrl-C or SIGTERM kills the worker processes at once and drops the queue;
  the exception carries a note saying how many tasks were kept (``add_note``).  A signal
  whose exception Python dropped (see :mod:`fembeam.interrupts`) is raised again when the
  next task finishes.
* a worker process that dies (killed, out of memory) breaks the local pool: the tasks it
  took with it are run again, each in a process of its own; a task that loses its
  process a second time gets ``lost(task, message)`` as its result (a failed case), or
  raises :class:`~fembeam.errors.SolverError` without ``lost``.
"""
from __future__ import annotations

import hashlib
import json
import os
import sys
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable

from .. import interrupts
from ..errors import InputError, SolverError

__all__ = ["run_tasks", "default_workers", "Journal", "journal_for", "shared_pool", "connect"]

Task = tuple[Callable[..., Any], dict]
MAX_JOURNAL_BYTES = 256 * 2 ** 20     # a journal larger than this is ignored (10^4 periods of a spectrum: ~50 MB)


def default_workers() -> int:
    """Local worker processes: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


def _tty(stream) -> bool:
    """Whether ``stream`` is a terminal (a progress bar is drawn only there: in a log or a pipe
    its carriage returns are noise)."""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def executor_label(workers: int | None, scheduler, tasks: int) -> str:
    """What runs ``tasks`` tasks: ``"dask"`` or ``"local (n workers)"`` with ``n`` the processes a
    local pool starts (never more than the tasks, 1 without a pool)."""
    if scheduler is not None:
        return "dask"
    n = max(1, min(workers or default_workers(), tasks))
    return f"local ({n} worker{'s' if n != 1 else ''})"


def _call(func, kwargs):
    """``func(**kwargs)`` with single-threaded BLAS and no warnings: the tasks are small, and BLAS
    threads only fight the other workers for the cores (measured on the Fig. 13 sweep,
    2 cores: 58.6 s with the default 2 OpenBLAS threads per worker, 18.7 s with 1)."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1):
        return _quiet_call(func, kwargs)


def _quiet_call(func, kwargs):
    """``func(**kwargs)`` without warnings (forked workers inherit the filters, spawned do not)."""
    import warnings

    import numpy as np

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return func(**kwargs)


_LIMITS = []


def _single_threaded_worker(parent: int | None = None) -> None:
    """Initialiser of a local worker process: BLAS on one thread for the process's life
    (once, instead of around every task: 1.3 ms a task); Ctrl-C and SIGHUP ignored (a
    terminal sends them to the whole process group: the parent stops the workers) and
    SIGTERM back to its default (a worker terminated is a lost worker, not an exception
    raised in it); and the worker dies with its ``parent`` (:func:`_die_with_parent`)."""
    import signal

    from threadpoolctl import threadpool_limits

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if hasattr(signal, "SIGHUP"):
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if parent is not None:
        _die_with_parent(parent)
    _LIMITS.append(threadpool_limits(limits=1))


def _die_with_parent(parent: int) -> None:
    """End this worker when the process ``parent`` that started it dies, however it dies
    (SIGKILL included: nothing runs in the parent then).  On Linux the kernel sends the
    worker SIGKILL (``prctl(PR_SET_PDEATHSIG)``; the pool forks its workers from the thread
    that runs the study); elsewhere a daemon thread checks the parent every 0.5 s.  A parent
    already gone when this runs ends the worker at once."""
    import signal

    armed = False
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            libc = ctypes.CDLL(None, use_errno=True)
            armed = libc.prctl(1, int(signal.SIGKILL), 0, 0, 0) == 0      # 1: PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            armed = False
    if os.getppid() != parent:
        os._exit(1)
    if not armed:
        def watch():
            while os.getppid() == parent:
                threading.Event().wait(0.5)
            os._exit(1)
        threading.Thread(target=watch, daemon=True, name="fembeam-parent-watch").start()


def _new_pool(workers: int):
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(max_workers=workers, initializer=_single_threaded_worker, initargs=(os.getpid(),))


class Journal:
    """Finished tasks of a study, one JSON line each, appended as they finish:
    ``{"key": K, "result": R, "check": C}`` with ``K`` the digest of the task
    (:meth:`key`) and ``C`` the digest of ``K`` and ``R``.

    Reading never fails: the file is read with a bound (:data:`MAX_JOURNAL_BYTES`,
    :func:`fembeam.readers.read_bytes`); a line that is not UTF-8, not JSON, not an object
    with a string key, or whose check digest does not match (a line cut short by a kill, a
    corrupted or hand-edited one) is ignored, and so is the whole file when it is too large
    (it is then started afresh); a path that is not a regular file (a FIFO, a directory)
    disables the journal.  ``note`` says in one line what was ignored (None: nothing)."""

    def __init__(self, path: str | Path):
        from ..readers import read_bytes

        self.path = Path(path)
        self.done: dict[str, Any] = {}
        self.note: str | None = None
        self.usable, self._fresh = True, False
        if not self.path.exists() and not self.path.is_symlink():
            return
        if not self.path.is_file():
            self.usable = False
            self.note = f"{self.path} is not a regular file: finished cases are not kept"
            return
        try:
            data = read_bytes(self.path, "the journal", MAX_JOURNAL_BYTES)
        except InputError as e:
            self._fresh = True
            self.note = f"{e}; it is ignored and started afresh"
            return
        bad = 0
        for line in data.split(b"\n"):
            if not line.strip():
                continue
            rec = self._record(line)
            if rec is None:
                bad += 1
            else:
                self.done[rec[0]] = rec[1]
        if bad:
            self.note = (f"{bad} line{'s' if bad > 1 else ''} of the journal {self.path} did not parse or failed "
                         "its check and {} ignored (those cases are run again)".format("were" if bad > 1 else "was"))

    @staticmethod
    def _record(line: bytes):
        """``(key, result)`` of one line, or None if it does not parse or fails its check."""
        try:
            rec = json.loads(line.decode("utf-8"))
            key, result, check = rec["key"], rec["result"], rec["check"]
        except (ValueError, KeyError, TypeError, RecursionError):
            return None
        if not (isinstance(key, str) and isinstance(check, str) and check == Journal._check(key, result)):
            return None
        return key, result

    @staticmethod
    def _check(key: str, result: Any) -> str:
        text = json.dumps([key, result], sort_keys=True, allow_nan=True)
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    @staticmethod
    def key(task: Task) -> str:
        """The digest of fembeam's version, the function and its arguments; objects (a
        member) by their full ``repr``, the dataclass fields that define them (arrays
        printed in full)."""
        import numpy as np

        from .. import __version__

        f, kw = task
        with np.printoptions(threshold=sys.maxsize, precision=17):
            text = json.dumps([__version__, f.__module__, f.__qualname__, kw], sort_keys=True, default=repr)
        return hashlib.sha256(text.encode()).hexdigest()

    def add(self, key: str, result: Any) -> None:
        if not self.usable:
            self.done[key] = result
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        line = json.dumps({"key": key, "result": result, "check": self._check(key, result)}) + "\n"
        with open(self.path, "w" if self._fresh else "a+") as fh:
            self._fresh = False
            fh.seek(0, os.SEEK_END)
            if fh.tell():                      # a line cut short by a kill: start a new one
                fh.seek(fh.tell() - 1)
                last = fh.read(1)
                fh.seek(0, os.SEEK_END)
                if last != "\n":
                    fh.write("\n")
            fh.write(line)
            fh.flush()
            os.fsync(fh.fileno())
        self.done[key] = result

    def remove(self) -> None:
        if self.usable and self.path.is_file():
            self.path.unlink(missing_ok=True)


def journal_for(output: str | Path | None, command: str, directory: bool = False) -> Journal | None:
    """The journal of ``command`` kept beside a study's ``output`` file, or in its output
    ``directory`` (``DIR/.fembeam-COMMAND-journal.jsonl``, ``.NAME.COMMAND-journal.jsonl``,
    NAME cut to 100 bytes and followed by its digest when longer, so that the journal's name
    is never too long where the output's fits; None: no journal).  Nothing is created before
    the first task finishes."""
    if output is None:
        return None
    p = Path(output)
    if directory:
        return Journal(p / f".fembeam-{command}-journal.jsonl")
    name = p.name
    if len(os.fsencode(name)) > 100:
        name = os.fsencode(name)[:80].decode(errors="ignore") + "-" + hashlib.sha256(os.fsencode(name)).hexdigest()[:16]
    return Journal(p.with_name(f".{name}.{command}-journal.jsonl"))


def run_tasks(tasks: list[Task], workers: int | None = None, scheduler=None, progress: bool = True,
              desc: str = "tasks", journal: Journal | None = None,
              lost: Callable[[Task, str], Any] | None = None) -> list:
    """Results of ``func(**kwargs)`` for every task, in order.

    ``scheduler``: None (local), a Dask scheduler address (``"tcp://host:8786"``, or the
    ``inproc://`` address of an in-process ``LocalCluster``) or a ``distributed.Client``.
    ``workers``: local worker processes (default :func:`default_workers`, at most
    :data:`~fembeam.limits.MAX_WORKERS`; 1 runs in this process, without a pool; a new pool
    never has more processes than tasks to run).  ``progress``: a tqdm bar on stderr, when it
    is a terminal.
    ``journal`` and ``lost``: see the module docstring.
    """
    from tqdm import tqdm

    from ..limits import check_workers
    check_workers(workers)
    keys = [Journal.key(t) for t in tasks] if journal is not None else []
    out: list = [None] * len(tasks)
    todo = list(range(len(tasks)))
    if journal is not None:
        todo = [i for i in todo if keys[i] not in journal.done]
        for i in set(range(len(tasks))) - set(todo):
            out[i] = journal.done[keys[i]]
    bar = tqdm(total=len(tasks), initial=len(tasks) - len(todo), desc=desc, file=sys.stderr,
               disable=not (progress and _tty(sys.stderr)), unit="case", dynamic_ncols=True)
    finished = [len(tasks) - len(todo)]

    def done(i: int, result: Any, keep: bool = True) -> None:
        out[i] = result
        if journal is not None and keep:      # a lost task is not kept: a re-run tries it again
            journal.add(keys[i], result)
        finished[0] += 1
        bar.update()
        interrupts.check()    # an interrupt whose exception Python dropped (in a worker's at-fork hook)

    try:
        sub = [tasks[i] for i in todo]
        if scheduler is not None:
            _run_dask(sub, scheduler, lambda j, r: done(todo[j], r))
        elif (workers or default_workers()) == 1 or len(todo) <= 1:
            for i in todo:
                done(i, _call(*tasks[i]))
        else:
            broken = _run_pool(sub, workers or default_workers(), lambda j, r: done(todo[j], r))
            for j, res in _run_isolated([sub[j] for j in broken], workers or default_workers()):
                if isinstance(res, _Lost):
                    if lost is None:
                        raise SolverError(f"{desc}: a worker process died twice running {sub[broken[j]][0].__name__}"
                                          f"({sub[broken[j]][1]}): {res.message}")
                    done(todo[broken[j]], lost(sub[broken[j]], res.message), keep=False)
                else:
                    done(todo[broken[j]], res)
    except BaseException as e:
        kept = f"; {finished[0]} of {len(tasks)} cases kept in {journal.path}, re-run the same command to resume" \
            if journal is not None else f"; {finished[0]} of {len(tasks)} cases had finished"
        if hasattr(e, "add_note"):
            e.add_note(kept)
        raise
    finally:
        bar.close()
    return out


class _Lost:
    def __init__(self, message: str):
        self.message = message


def _kill(pool) -> None:
    """SIGKILL to the pool's workers (they inherit our SIGTERM handler), then wait until they
    are gone (milliseconds; 5 s at most): an interrupted command exits without waiting for
    anything else, and leaves no process behind."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    for proc in procs:
        proc.kill()
    for proc in procs:
        proc.join(5.0)
    pool.shutdown(wait=False, cancel_futures=True)


def _run_pool(tasks: list[Task], workers: int, done) -> list[int]:
    """Tasks on a process pool (the shared one of a :func:`shared_pool` block, else a new
    one), ``done(j, result)`` as each finishes; returns the indices of the tasks lost with
    a broken pool (a worker process died)."""
    from concurrent.futures import as_completed
    from concurrent.futures.process import BrokenProcessPool

    shared = _shared_pools()
    pool = shared.get(workers) or _new_pool(min(workers, len(tasks)))
    broken = []
    try:
        # the first submit forks the workers: a signal then is raised once the pool knows them all
        with interrupts.deferred():
            try:
                futs = {pool.submit(_quiet_call, f, kw): j for j, (f, kw) in enumerate(tasks)}
            except BrokenProcessPool:                            # a shared pool's worker died while idle
                if shared.get(workers) is not pool:
                    raise
                shared[workers] = pool = _replace(pool, workers)
                futs = {pool.submit(_quiet_call, f, kw): j for j, (f, kw) in enumerate(tasks)}
        for fut in as_completed(futs):
            try:
                res = fut.result()
            except BrokenProcessPool:
                broken.append(futs[fut])
                continue
            done(futs[fut], res)
    except BaseException:   # an error, Ctrl-C or SIGTERM: stop the workers now, queue dropped
        if shared.get(workers) is pool:
            del shared[workers]
        _kill(pool)
        raise
    if shared.get(workers) is not pool:
        pool.shutdown(wait=not broken)
    elif broken:                       # the next call of the block gets a new shared pool
        shared[workers] = _replace(pool, workers)
    return sorted(broken)


def _replace(pool, workers: int):
    pool.shutdown(wait=False, cancel_futures=True)
    return _new_pool(workers)


_LOCAL = threading.local()


def _shared_pools() -> dict:
    """This thread's shared pools (workers -> pool) of its outermost :func:`shared_pool`
    blocks: another thread's calls never use them."""
    pools = getattr(_LOCAL, "pools", None)
    if pools is None:
        pools = _LOCAL.pools = {}
    return pools


@contextmanager
def shared_pool(workers: int | None = None):
    """Local worker processes shared by the :func:`run_tasks` calls made inside the block
    by this thread with the same number of workers: a study in phases (the sweep's
    envelope, then its cases) starts its workers once.  A worker starts cold after the
    fork (its first task takes 100-150 ms more on this machine), so each new pool costs
    that again.  A pool broken by a worker that died is replaced for the next call; an
    error or interrupt kills the workers as outside a block."""
    n = workers or default_workers()
    pools = _shared_pools()
    if n <= 1 or n in pools:                       # one process, or an outer block's pool
        yield
        return
    pools[n] = _new_pool(n)
    try:
        yield
    finally:
        pool = pools.pop(n, None)
        if pool is not None:
            pool.shutdown(wait=True)


def _run_isolated(tasks: list[Task], workers: int):
    """Each task in a process of its own, ``workers`` at a time: yields ``(j, result)``,
    the result a :class:`_Lost` if that process died too."""
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    pending = list(range(len(tasks)))
    running: dict = {}
    try:
        while pending or running:
            while pending and len(running) < workers:
                j = pending.pop(0)
                with interrupts.deferred():                     # the worker forked and recorded
                    pool = _new_pool(1)
                    running[pool.submit(_quiet_call, *tasks[j])] = (j, pool)
            finished, _ = wait(list(running), return_when=FIRST_COMPLETED)
            for fut in finished:
                j, pool = running.pop(fut)
                try:
                    res = fut.result()
                except BrokenProcessPool as e:
                    res = _Lost(str(e) or "the worker process died")
                pool.shutdown(wait=False)
                yield j, res
    except BaseException:
        for _, pool in running.values():
            _kill(pool)
        raise


CONNECT_TIMEOUT_S = 10.0
"""Seconds :func:`connect` tries to reach a Dask scheduler (a refused port is retried until
then) before it reports that it cannot."""


def connect(scheduler: str):
    """A ``distributed.Client`` of the scheduler at the address ``scheduler``, or an
    :class:`InputError` saying it cannot be reached (any failure to build the client: a
    refused or unknown address, no answer within :data:`CONNECT_TIMEOUT_S`, or
    distributed's own IO loop not starting, which it reports as an AssertionError on a
    loaded machine)."""
    import gc

    from distributed import Client

    # a client that failed to connect earlier is finalised here, not by a garbage collection that
    # happens to run inside the next Client's start-up: its __del__ then waits for the IO loop's
    # lock that the start-up holds (a deadlock, seen with two refused addresses in one process)
    gc.collect()
    try:
        return Client(scheduler, timeout=CONNECT_TIMEOUT_S)
    except Exception as e:     # noqa: BLE001  third-party client: every failure is "cannot connect"
        why = str(e) or type(e).__name__
    gc.collect()                # the half-built client, held by that traceback until here
    raise InputError(f"cannot connect to the Dask scheduler at {scheduler!r}: {why}")


def _run_dask(tasks: list[Task], scheduler, done) -> None:
    from distributed import Client, as_completed

    own = not isinstance(scheduler, Client)
    client = connect(scheduler) if own else scheduler
    try:
        futs = [client.submit(_call, f, kw, pure=False) for f, kw in tasks]
        index = {fut.key: i for i, fut in enumerate(futs)}
        for fut in as_completed(futs):
            done(index[fut.key], fut.result())
    finally:
        if own:
            client.close()
