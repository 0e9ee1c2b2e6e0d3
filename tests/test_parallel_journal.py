"""Local task runner: finished tasks kept in a journal (an interrupted study resumes),
a lost worker's tasks retried once in processes of their own, then reported as failed."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from fembeam.studies.parallel import Journal, journal_for, run_tasks


def square(i: int) -> int:
    return i * i


def die_once(i: int, flag: str) -> int:
    if i == 3 and not os.path.exists(flag):
        open(flag, "w").close()
        os._exit(1)                      # the worker process dies: the pool breaks
    return i * i


def die_always(i: int) -> int:
    if i == 3:
        os._exit(1)
    return i * i


def must_not_run(i: int) -> int:
    raise AssertionError(f"task {i} was recomputed")


def test_lost_worker_tasks_are_retried(tmp_path):
    flag = str(tmp_path / "died")
    out = run_tasks([(die_once, {"i": i, "flag": flag}) for i in range(8)], workers=2, progress=False)
    assert out == [i * i for i in range(8)] and os.path.exists(flag)


def test_a_lost_task_is_not_kept_in_the_journal(tmp_path):
    """A task that lost its process twice is a failed case of this run only: a re-run
    tries it again."""
    j = journal_for(tmp_path / "s.csv", "test")
    out = run_tasks([(die_always, {"i": i}) for i in range(5)], workers=2, progress=False, journal=j,
                    lost=lambda task, msg: None)
    assert out == [0, 1, 4, None, 16] and len(Journal(j.path).done) == 4


def test_a_task_that_always_kills_its_worker_is_a_failed_case():
    out = run_tasks([(die_always, {"i": i}) for i in range(6)], workers=2, progress=False,
                    lost=lambda task, msg: ("lost", task[1]["i"]))
    assert out == [0, 1, 4, ("lost", 3), 16, 25]
    from fembeam.errors import SolverError
    with pytest.raises(SolverError, match="died twice"):
        run_tasks([(die_always, {"i": i}) for i in range(6)], workers=2, progress=False)


@pytest.mark.parametrize("workers", [1, 2])
def test_journal_keeps_and_resumes(tmp_path, workers):
    j = journal_for(tmp_path / "study.csv", "sweep")
    assert j.path == tmp_path / ".study.csv.sweep-journal.jsonl"
    tasks = [(square, {"i": i}) for i in range(5)]
    assert run_tasks(tasks, workers=workers, progress=False, journal=j) == [0, 1, 4, 9, 16]
    with open(j.path, "a") as fh:
        fh.write('{"key": "cut sh')          # a line cut short by a kill is ignored
    again = Journal(j.path)
    assert len(again.done) == 5
    # the same tasks under a function that would fail: every result comes from the journal
    keyed = {Journal.key(t): again.done[Journal.key(t)] for t in tasks}
    again.done = {Journal.key((must_not_run, t[1])): v for t, v in zip(tasks, keyed.values())}
    assert run_tasks([(must_not_run, t[1]) for t in tasks], workers=workers, progress=False,
                     journal=again) == [0, 1, 4, 9, 16]
    again.remove()
    assert not j.path.exists()


# A hang guard, not a time limit: what it waits for takes a few seconds on an idle machine.
HANG_GUARD_S = 600.0


def wait_until(condition, what: str) -> None:
    """Poll ``condition`` until it holds; fail saying ``what`` did not happen if it has not
    after :data:`HANG_GUARD_S` (stuck, whatever the load)."""
    end = time.monotonic() + HANG_GUARD_S
    while not condition():
        if time.monotonic() > end:
            pytest.fail(f"{what}: not after {HANG_GUARD_S:.0f} s")
        time.sleep(0.05)


def test_interrupted_sweep_resumes_to_the_same_result(tmp_path):
    """SIGINT and SIGTERM end the sweep at once with 130 / 143, one stderr line, no worker
    left: at most one case per worker is finished after the signal, the queue is dropped.
    The cases finished are in the journal and a re-run completes from them to the result
    of an uninterrupted run."""
    # 33 cases (3 embraces, 11 ratios, standing and not): each interruption finishes at most a few
    # of them, so both signals land mid-sweep and the re-run has cases left to complete; a finer
    # grid only repeats the same check on more cases, in two full sweeps
    cmd = [sys.executable, "-m", "fembeam", "sweep", "--embrace", "90,150,180", "--t-over-r", "0.1:0.3:0.02",
           "--elements", "24", "--tmin-elements", "24", "--workers", "2", "--quiet"]
    journal = tmp_path / "a" / ".fembeam-sweep-journal.jsonl"

    def lines() -> int:
        return journal.read_text().count("\n") if journal.exists() else 0

    for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
        n0 = lines()
        p = subprocess.Popen(cmd + ["--out-dir", str(tmp_path / "a")], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, start_new_session=True)
        try:
            # a case finished by this run: it computes, its handlers are set
            wait_until(lambda: lines() > n0 or p.poll() is not None, "a case of the sweep finished")
            assert p.poll() is None, "the sweep ended before it could be interrupted"
            # the sweep and its workers stopped while the journal is counted and the signal sent:
            # what is finished after the count is finished after the signal, on any machine
            os.killpg(p.pid, signal.SIGSTOP)
            os.waitpid(p.pid, os.WUNTRACED)
            n1 = lines()
            p.send_signal(sig)
            os.killpg(p.pid, signal.SIGCONT)
            try:
                _, err = p.communicate(timeout=HANG_GUARD_S)
            except subprocess.TimeoutExpired:
                left = subprocess.run(["pgrep", "-a", "-s", str(p.pid)], capture_output=True, text=True).stdout
                pytest.fail(f"{HANG_GUARD_S:.0f} s after {sig.name} the sweep (exit {p.poll()}) or processes it "
                            f"started still hold its output:\n{left}")
        finally:
            try:
                if p.poll() is None or p.stdout and not p.stdout.closed:      # only on a failure
                    os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait()
        assert p.returncode == code, err
        assert lines() - n1 <= 2, f"{lines() - n1} cases finished after {sig.name} with 2 workers"
        assert len(err.strip().splitlines()) == 1 and "fembeam:" in err
        assert subprocess.run(["pgrep", "-s", str(p.pid)], capture_output=True).stdout == b""   # no orphans
    subprocess.run(cmd + ["--out-dir", str(tmp_path / "a")], check=True, capture_output=True)
    subprocess.run(cmd + ["--out-dir", str(tmp_path / "b")], check=True, capture_output=True)
    assert not journal.exists()
    import json
    a, b = (json.loads((tmp_path / d / "sweep.json").read_text()) for d in "ab")
    strip = (lambda rows: [{k: v for k, v in r.items() if not k.startswith("time")} for r in rows])  # noqa: E731
    assert strip(a["cases"]) == strip(b["cases"]) and strip(a["envelope"]) == strip(b["envelope"])


def test_spectrum_resumes_from_its_journal(tmp_path):
    """Periods found in the journal are not run again (the journal does not grow) and give
    the same rows."""
    from fembeam import CircularArch
    from fembeam.studies.spectrum import spectrum

    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    j = journal_for(tmp_path / "s.csv", "spectrum")
    kw = dict(voussoirs=7, workers=1, progress=False, n_amplitudes=6)
    first = spectrum(arch, "sine", [0.3, 0.5], journal=j, **kw)
    lines = j.path.read_text().count("\n")
    assert lines == 2
    again = spectrum(arch, "sine", [0.3, 0.5], journal=Journal(j.path), **kw)
    assert j.path.read_text().count("\n") == lines
    strip = (lambda rows: [{k: v for k, v in r.items() if k != "time_s"} for r in rows])  # noqa: E731
    assert strip(again.rows) == strip(first.rows)


def test_interrupt_names_what_was_kept(tmp_path, monkeypatch, capsys):
    """The one stderr line of an interrupted study says where its finished cases are."""
    import importlib

    from fembeam.cli.main import main
    sw = importlib.import_module("fembeam.studies.sweep")

    real, calls = sw.sweep_case, {"n": 0}

    def case(**kw):
        calls["n"] += 1
        if calls["n"] == 3:
            raise KeyboardInterrupt
        return real(**kw)

    monkeypatch.setattr(sw, "sweep_case", case)
    code = main(["sweep", "--embrace", "90", "--t-over-r", "0.1,0.2,0.3", "--elements", "8", "--tmin-elements", "8",
                 "--workers", "1", "--quiet", "--no-envelope", "--csv", str(tmp_path / "s.csv")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 130 and len(err) == 1
    assert "2 of 3 cases kept in" in err[0] and ".s.csv.sweep-journal.jsonl" in err[0] and "resume" in err[0]


class _SignalInFinaliser:
    """Receives SIGTERM while Python runs its finaliser, where an exception is dropped (as in
    the at-fork hook that runs when a worker process starts)."""

    def __del__(self):
        from fembeam import interrupts
        interrupts._handler(signal.SIGTERM, None)


def signal_dropped_then_square(i: int) -> int:
    if i == 1:
        _SignalInFinaliser()            # created and finalised at once: the exception is dropped
    return i * i


def test_an_interrupt_python_drops_still_stops_the_study(tmp_path, capsys):
    """A signal whose exception is raised where Python ignores exceptions stops the study at
    the next finished task, with the task kept, and nothing about it on stderr."""
    from fembeam import interrupts

    j = journal_for(tmp_path / "s.csv", "test")
    with interrupts.handled():
        with pytest.raises(interrupts.Terminated) as e:
            run_tasks([(signal_dropped_then_square, {"i": i}) for i in range(5)], workers=1,
                      progress=False, journal=j)
    assert "2 of 5 cases kept" in "".join(e.value.__notes__)
    assert len(Journal(j.path).done) == 2 and capsys.readouterr().err == ""
    assert signal.getsignal(signal.SIGTERM) is not interrupts._handler          # restored
    assert sys.unraisablehook is not interrupts._unraisable


def test_a_command_that_lost_its_interrupt_exits_143(monkeypatch, capsys):
    """The end of a command is a safe point too: 143 and one line, not 0."""
    import fembeam.cli.analyze as analyze
    from fembeam.cli.main import main

    real = analyze.run
    monkeypatch.setattr(analyze, "run", lambda args: (_SignalInFinaliser(), real(args))[1])
    assert main(["analyze", "--elements", "24"]) == 143
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "terminated" in err


def test_a_remembered_interrupt_ends_with_its_block(tmp_path):
    """Outside ``handled()`` nothing is remembered: a later study (or a library call) is
    not stopped by an interrupt already reported."""
    from fembeam import interrupts

    with interrupts.handled():
        _SignalInFinaliser()
        with pytest.raises(interrupts.Terminated):
            interrupts.check()
    interrupts.check()                                           # nothing pending any more
    assert run_tasks([(square, {"i": i}) for i in range(3)], workers=1, progress=False) == [0, 1, 4]


def test_a_command_in_another_thread_leaves_the_main_threads_interrupt():
    import threading

    from fembeam import interrupts
    from fembeam.cli.main import main

    codes = []
    with interrupts.handled():
        _SignalInFinaliser()
        t = threading.Thread(target=lambda: codes.append(main(["analyze", "--elements", "8", "--json"])))
        t.start()
        t.join()
        assert codes == [0]
        with pytest.raises(interrupts.Terminated):
            interrupts.check()


def test_a_signal_arriving_while_the_handlers_are_restored_is_raised_after():
    """A signal delivered while ``handled()`` restores the previous handlers (simulated by
    blocking it in the block) is raised once they are back, not lost and not left to this
    module's handler; the signal mask is restored."""
    import threading

    from fembeam import interrupts

    before = signal.getsignal(signal.SIGTERM), signal.pthread_sigmask(signal.SIG_BLOCK, [])
    try:
        with pytest.raises(interrupts.Terminated):
            with interrupts.handled():
                signal.pthread_sigmask(signal.SIG_BLOCK, [signal.SIGTERM])
                # to this thread (a signal to the process may go to another thread, e.g. a
                # pool's manager, whose C handler would not wait for the block's end)
                signal.pthread_kill(threading.main_thread().ident, signal.SIGTERM)   # pending until then
        assert signal.getsignal(signal.SIGTERM) == before[0]
        assert signal.SIGTERM in signal.pthread_sigmask(signal.SIG_BLOCK, [])   # the mask as it was left
        assert signal.sigpending() == set()                  # consumed, not delivered again
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, before[1])


def pid(i: int) -> int:
    return os.getpid()


def test_a_signal_while_the_workers_start_leaves_none_behind(monkeypatch):
    """SIGTERM landing between the fork of a worker and the pool's record of it (made certain
    here by raising it right after each fork) stops the study with every worker killed: none
    is left waiting for work for ever, holding the caller's stdout and stderr open."""
    import multiprocessing
    from multiprocessing.process import BaseProcess

    from fembeam import interrupts

    real_start = BaseProcess.start

    def start(self):
        real_start(self)
        interrupts._handler(signal.SIGTERM, None)          # the signal arrives here

    before = set(multiprocessing.active_children())
    monkeypatch.setattr(BaseProcess, "start", start)
    with interrupts.handled():
        with pytest.raises(interrupts.Terminated):
            run_tasks([(square, {"i": i}) for i in range(6)], workers=2, progress=False)
    monkeypatch.undo()
    started = set(multiprocessing.active_children()) - before
    for proc in started:
        wait_until(lambda: not proc.is_alive(), f"worker {proc.pid}, started as the signal came, killed")


def test_a_shared_pool_serves_every_phase(tmp_path):
    """Inside shared_pool() the calls of run_tasks use the same worker processes; a pool
    broken by a lost worker (during a call, or killed while idle between calls) is
    replaced by one that the next calls share; another thread's calls use their own
    workers; the block's end stops the pool."""
    import threading

    from fembeam.studies import parallel

    def pids(n=8):
        return set(run_tasks([(pid, {"i": i}) for i in range(n)], workers=2, progress=False))

    def workers():          # the processes of this thread's shared pool
        return {p.pid for p in parallel._shared_pools()[2]._processes.values()}

    with parallel.shared_pool(2):
        first = pids() | pids()
        assert first <= workers() and os.getpid() not in first and len(workers()) <= 2
        out = run_tasks([(die_once, {"i": i, "flag": str(tmp_path / "died")}) for i in range(8)], workers=2,
                        progress=False)
        assert out == [i * i for i in range(8)]
        second = pids() | pids()
        assert second.isdisjoint(first) and second <= workers()       # replaced, and shared again
        lost, pool = workers(), parallel._shared_pools()[2]
        for p in lost:
            os.kill(p, signal.SIGKILL)                                 # workers lost while idle
        # the pool has seen it (its manager thread marks it broken): the next call replaces it
        wait_until(lambda: pool._broken, "the pool whose workers were killed marked broken")
        third = pids() | pids()
        assert third.isdisjoint(lost) and third <= workers()
        other = []
        t = threading.Thread(target=lambda: other.append(pids(4)))
        t.start()
        t.join()
        assert other[0].isdisjoint(workers())                         # not this thread's pool
        last = workers()
    assert parallel._shared_pools() == {}
    assert pids(4).isdisjoint(last)


def sleepy(i: int) -> int:
    time.sleep(0.3)
    return i


def sleepy_pid(i: int) -> int:
    time.sleep(0.05)
    return os.getpid()


def test_workers_leave_ctrl_c_to_the_parent():
    """A terminal's Ctrl-C reaches the whole process group: the workers ignore it (no
    traceback of theirs), the parent stops them."""
    from fembeam.studies.parallel import _new_pool

    pool = _new_pool(2)
    try:
        # every worker has run a task (its initialiser, which ignores SIGINT, has finished): a
        # worker still starting up when the signal lands would die of it, as any process would
        seen: set = set()
        for _ in range(200):
            seen |= {f.result() for f in [pool.submit(sleepy_pid, 0) for _ in range(4)]}
            if len(pool._processes) == 2 and seen >= set(pool._processes):
                break
        else:
            raise AssertionError("the pool's two workers did not both run a task")
        workers = list(pool._processes.values())
        for w in workers:
            os.kill(w.pid, signal.SIGINT)
        assert set(pool.map(sleepy, range(4))) == set(range(4))       # still alive, still working
        assert all(w.is_alive() for w in workers)
    finally:
        pool.shutdown(wait=True)


def test_a_client_that_cannot_start_is_an_input_error(monkeypatch):
    """distributed reports an IO loop that did not start (a loaded machine) as an
    AssertionError: still 'cannot connect', one line, exit 2, not a traceback."""
    import distributed

    from fembeam.cli.main import main
    from fembeam.errors import InputError
    from fembeam.studies.parallel import connect

    def refuse(*a, **k):
        raise AssertionError()

    monkeypatch.setattr(distributed, "Client", refuse)
    with pytest.raises(InputError, match="cannot connect to the Dask scheduler at 'tcp://x:1': AssertionError"):
        connect("tcp://x:1")
    assert main(["sweep", "--embrace", "90", "--t-over-r", "0.2", "--scheduler", "tcp://x:1", "--quiet"]) == 2


# ------------------------------------------------------------------ corrupt journals
def _corrupt(path, kind: str, good: bytes) -> None:
    """Replace the journal at ``path`` by a corrupt one of ``kind`` (``good``: a valid line)."""
    import json
    import random

    if kind == "random":
        path.write_bytes(random.Random(1).randbytes(5000) + b"\n" + good)
    elif kind == "latin-1":
        path.write_bytes("caf\u00e9 au lait\n".encode("latin-1") + good)
    elif kind == "sparse":
        with open(path, "wb") as f:
            f.truncate(5 * 2 ** 30)
    elif kind == "wrong type":           # the right key, a result of another type, no valid check
        rec = json.loads(good)
        rec["result"] = "not a number"
        path.write_bytes(json.dumps(rec).encode() + b"\n" + good)
    elif kind == "cut":
        path.write_bytes(good[:-10] + b"\n" + good)
    elif kind == "fifo":
        os.mkfifo(path)
    elif kind == "dir":
        path.mkdir()


@pytest.mark.parametrize("kind, ignored", [("random", "lines of the journal"), ("latin-1", "1 line of the journal"),
                                           ("sparse", "it is ignored and started afresh"),
                                           ("wrong type", "1 line of the journal"), ("cut", "1 line of the journal"),
                                           ("fifo", "not a regular file"), ("dir", "not a regular file")])
def test_a_corrupt_journal_is_ignored_line_by_line_never_fatal(tmp_path, kind, ignored):
    """Lines that do not parse or fail their check are ignored (their cases run again), a
    journal too large is started afresh, a journal path that is not a file disables it: the
    study's result is the same, and ``note`` says what was ignored in one line."""
    j = journal_for(tmp_path / "s.csv", "test")
    tasks = [(square, {"i": i}) for i in range(4)]
    assert run_tasks(tasks, workers=1, progress=False, journal=j) == [0, 1, 4, 9]
    good = j.path.read_bytes().splitlines(keepends=True)[2]            # the task i = 2
    j.path.unlink()
    _corrupt(j.path, kind, good)
    again = Journal(j.path)
    assert ignored in again.note and "\n" not in again.note
    kept = [t for t in tasks if Journal.key(t) in again.done]
    assert kept == ([tasks[2]] if kind not in ("sparse", "fifo", "dir") else [])
    assert run_tasks(tasks, workers=1, progress=False, journal=again) == [0, 1, 4, 9]
    again.remove()
    assert j.path.exists() == (kind in ("fifo", "dir"))                  # never removes what is not its file


def test_a_study_with_a_corrupt_journal_says_so_in_one_line(tmp_path, capsys):
    from fembeam.cli.main import main

    argv = ["sweep", "--embrace", "90", "--t-over-r", "0.2,0.3", "--elements", "8", "--tmin-elements", "8",
            "--workers", "1", "--quiet", "--no-envelope", "--csv", str(tmp_path / "s.csv")]
    (tmp_path / ".s.csv.sweep-journal.jsonl").write_bytes(b"\xff\xfe{\"key\": 1}\n\x00\x01")
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("fembeam: note: 2 lines of the journal") and "run again" in err
    assert not (tmp_path / ".s.csv.sweep-journal.jsonl").exists()
