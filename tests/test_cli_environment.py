"""The command line in a hostile environment: stdout closed, an ASCII locale, a signal
right after the handlers are installed (while NumPy is still loading), SIGHUP."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading

import pytest

HANG_GUARD_S = 600.0      # a hang guard, not a time limit: each run takes about a second
ROCK = ["rock", "--voussoirs", "7", "--pulse", "sine", "--amplitude", "1", "--period", "0.5"]


def _env():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return dict(os.environ, PYTHONPATH=root + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _fembeam(argv, **kw):
    return subprocess.run([sys.executable, "-m", "fembeam", *argv], capture_output=True, text=True,
                          timeout=HANG_GUARD_S, env=kw.pop("env", _env()), **kw)


@pytest.mark.parametrize("argv", [["--help"], ["rock", "--help"], ROCK])
def test_closed_stdout_is_one_line_and_exit_2(argv):
    p = subprocess.run([sys.executable, "-m", "fembeam", *argv], stderr=subprocess.PIPE, text=True, env=_env(),
                       timeout=HANG_GUARD_S, preexec_fn=lambda: os.close(1))
    assert p.returncode == 2 and p.stderr.strip() == (
        "fembeam: error: stdout is closed: the output cannot be written (redirect it to a file or /dev/null)")


def test_a_non_ascii_path_under_an_ascii_encoding_is_escaped(tmp_path):
    env = dict(_env(), PYTHONIOENCODING="ascii", LC_ALL="C")
    p = _fembeam(ROCK + ["--csv", "h\u00e9.csv"], env=env, cwd=tmp_path)
    assert p.returncode == 0 and p.stderr == "" and "CSV: h\\xe9.csv" in p.stdout
    assert os.listdir(tmp_path) == ["h\u00e9.csv"]


def _caught(pid: int) -> bool:
    """Whether the process catches SIGTERM and SIGHUP (fembeam's handlers are installed)."""
    with open(f"/proc/{pid}/status") as f:
        mask = int(next(line for line in f if line.startswith("SigCgt:")).split()[1], 16)
    return all(mask >> (s - 1) & 1 for s in (signal.SIGTERM, signal.SIGHUP))


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads /proc/PID/status")
@pytest.mark.parametrize("sig, code, word", [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated"),
                                             (signal.SIGHUP, 129, "hung up")])
def test_a_signal_as_soon_as_the_handlers_are_in_place(sig, code, word):
    """The handlers come before NumPy and the command's modules are imported: a signal right
    then (the imports run for another 0.1-0.3 s) is one line and 128 + the signal number;
    never a traceback, nor an ImportError that NumPy made of the KeyboardInterrupt."""
    p = subprocess.Popen([sys.executable, "-m", "fembeam", *ROCK], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, env=_env())
    stop = threading.Timer(HANG_GUARD_S, p.kill)
    stop.start()
    try:
        while p.poll() is None and not _caught(p.pid):
            threading.Event().wait(0.0005)
        assert p.returncode is None, "the command ended before its handlers were seen"
        p.send_signal(sig)
        out, err = p.communicate()
    finally:
        stop.cancel()
    assert p.returncode == code and err == f"fembeam: {word}\n" and out == ""
