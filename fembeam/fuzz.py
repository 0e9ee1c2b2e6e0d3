"""Fuzzing of the command line: every sub-command driven from its own argparse definition.

    python -m fembeam.fuzz [--runs 300] [--seed 0] [--timeout 20] [--command analyze ...] [--scenarios 0]

For each run a command is picked, then (after a small problem of :data:`BASE` for the
commands whose defaults are large studies) a random subset of its options, each with a value
drawn for the option's kind (flag, choice, integer, number, list, pair, file name):
mostly plausible values (small meshes, short motions, files in a scratch directory) and
some hostile ones (``nan``, ``inf``, ``-1``, ``1e308``, ``abc``, empty strings, reversed
ranges, unwritable or existing-directory paths), extreme sizes and step counts (a block of
1e-9 m by 1e6 m, ``--t-end 1e300``, ``--dt-out 1e-9``, a million elements, 300 workers),
and hostile input files (a FIFO, ``/dev/zero``, a sparse 5 GB file, a mid-curve with too
many rows, records whose header or values do not parse or are out of range, and corrupt
journals of the studies, rewritten before every run: random bytes, non-UTF-8, a 5 GB
sparse file, a line of the wrong type, a FIFO).  New options are covered without editing
this module: only their kind matters.  Each command runs in a child process forked from
this one (imports once; a run leaves nothing behind for the next), with its stdout and
stderr captured; a child still running after ``timeout`` seconds is killed with every
process it started.  No alarm or signal is ever raised in this process: the outcome of a
run that finishes is the same on any machine, however slow or loaded.

A run **fails** when it breaks the promise of the command line:

* an exception escapes (a traceback), the process crashes, or the exit code is not 0, 2
  or 3 (``report`` may exit 1: a failed check);
* a warning or a traceback reaches stderr, or, on exit 2, stderr is not exactly one line;
  on exit 3 its last line is not fembeam's one-line message;
* on exit 0 with ``--json``, stdout is not one JSON object free of NaN and Infinity.

A run killed at ``timeout`` is counted as ``timeout`` (a long valid computation, not a
failure by itself; the sizes drawn keep them rare).  The summary prints the runs tried,
the exit codes, the failures with their arguments, and exits 1 if any failed.

Before the drawn command lines, one command line of each class of hostile input of the
study commands (:data:`CLASSES`: suite folders holding a FIFO, a looping link, a folder or a
record with bad lines; CSV records with NaN rows, a bad line, two headers, values in m/s^2;
two outputs of a study naming one file; a CSV output in the suite folder; ``--scheduler ''``;
a member that cannot stand in every study command) must also give its exit code (2 refused,
0 answered); the drawn lines meet the same classes now and then (two outputs given one name,
an arch too thin to stand, the suite folders of :data:`SUITES`).

``--scenarios N`` adds N process-level scenarios (:mod:`fembeam.fuzz_scenarios`): signals
early and late, the parent of a study killed, stdout closed, an ASCII locale, re-runs over
complete outputs interrupted.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import os
import pickle
import random
import select
import shutil
import signal
import struct
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field

__all__ = ["FuzzReport", "fuzz", "main", "draw_command"]

HOSTILE = ["nan", "inf", "-inf", "-1", "0", "1e308", "-1e308", "1e-308", "abc", "", " ", "1,2", "0x10", "1e999"]
NUMBERS = ["0.1", "0.15", "0.2", "0.5", "1", "2", "5", "10", "157.5", "120", "180", "90", "0.05", "0.3", "3"]
INTS = ["1", "2", "4", "7", "8", "12", "16", "20"]
LISTS = ["0.5", "0.1,0.2", "0.1:0.3:0.1", "90,150", "1:0:1", "0:1:0", "a,b", "0:1e308:1e-308", "0.2:0.3:1e-300",
         "7,15", "4,8", "-1,2"]
PATHS = ["out.csv", "out.json", "out.png", "out.vtu", "out.pvd", "out.gif", "out.pdf", "out.xyz", "nodir/x.csv",
         "adir", "afile/x.png", "/proc/fembeam.csv", "res"]
# hostile input files: made by _scratch (a FIFO, a sparse 5 GB file, records that do not parse...)
SPECIAL = ["fifo.csv", "/dev/zero", "sparse.csv", "adir", "missing.csv", "bin.pdf"]
RECORDS = ["elcentro", "lomaprieta", "missing.AT2", "afile", "bad.csv", "sparse.AT2", "dt_bad.AT2", "dt_dash.AT2",
           "dt_zero.AT2", "dt_huge.AT2", "npts_huge.AT2", "latin1.AT2", "time_cut.csv", "nan_rows.csv",
           "abc_row.csv", "two_headers.csv", "ms2.csv", *SPECIAL]
# suite folders (fragility --suite, assess --records): a short record, with a FIFO, a looping link,
# a record with bad lines beside it (a FEMA set is a study of minutes: not drawn)
SUITES = ["suite", "suite_fifo", "suite_loop", "suite_bad", "suite_dir", "adir", "missing"]
# outputs a study derives inside --out-dir / --report, named again by another option
DERIVED = ["ida.png", "ida.csv", "fragility.csv", "fragility.json", "report.md", "assess.json", "statics.png"]
OUTPUTS = ("--csv", "--plot", "--ida-plot", "--json-out", "--vtk", "--gif", "--thrust-figure", "--out-dir",
           "--report")
CANNOT_STAND = ["--t-over-r", "0.05", "--embrace", "180"]     # an arch too thin to stand (t/R = 0.05, 180 deg)
BASE_SPECTRUM = ["--voussoirs", "7", "--pulse", "sine", "--periods", "0.3"]
_STUDY = ["--block", "0.4", "1.6", "--model", "rock", "--quiet"]
_ASSESS = ["assess", "--voussoirs", "7", "--t-end", "3", "--pulse", "sine", "--amplitude", "0.5", "--period", "0.3"]
# one command line per class of hostile input of the study commands, with the exit code it must
# give (2: refused with one line; 0: answered), run before the drawn ones
CLASSES = [
    *((["fragility", *_STUDY, "--suite", s], 2) for s in ("suite_fifo", "suite_loop", "suite_bad", "suite_dir")),
    *((["assess", "--block", "0.4", "1.6", "--records", s], 2) for s in ("suite_fifo", "suite_loop", "suite_bad")),
    *((["rock", "--voussoirs", "5", "--t-end", "1", "--record", r], 2) for r in ("nan_rows.csv", "abc_row.csv",
                                                                               "two_headers.csv")),
    (["rock", "--voussoirs", "5", "--t-end", "1", "--record", "ms2.csv"], 0),    # run as given, with a note
    (["fragility", *_STUDY, "--suite", "suite", "--plot", "same.png", "--ida-plot", "same.png"], 2),
    (["fragility", *_STUDY, "--suite", "suite", "--out-dir", "adir", "--plot", "adir/ida.png"], 2),
    (["fragility", *_STUDY, "--suite", "suite", "--out-dir", "adir", "--csv", "adir/ida.csv"], 2),
    (["fragility", *_STUDY, "--suite", "suite", "--out-dir", "suite"], 2),
    *(([c, *b, "--scheduler", ""], 2) for c, b in (("fragility", [*_STUDY, "--suite", "suite"]),
                                                    ("spectrum", BASE_SPECTRUM), ("sweep", ["--embrace", "90"]))),
    *((["fragility", "--voussoirs", "7", "--model", m, "--suite", "suite", "--quiet", *CANNOT_STAND], 0)
      for m in ("rock", "simulate", "auto")),
    ([*_ASSESS, *CANNOT_STAND], 0), (["collapse-scale", "--voussoirs", "7", "--record", "elcentro", *CANNOT_STAND], 0),
    (["spectrum", *BASE_SPECTRUM, *CANNOT_STAND, "--quiet"], 0),
    (["simulate", "--voussoirs", "7", "--pulse", "sine", "--amplitude", "1", "--period", "0.3", *CANNOT_STAND], 0),
]
MIDCURVES = ["midcurve.csv", "mirror.csv", "many.csv", *SPECIAL]
# sizes kept small when valid, so that a valid run is quick
CAPS = {"--elements": INTS, "--voussoirs": INTS, "--sections": ["10", "50", "100"], "--t-end": ["0.5", "1", "2"],
        "--periods": ["0.3", "0.3,0.6", "0.2:0.4:0.2"], "--workers": ["1", "2"], "--frames": ["2", "5"],
        "--record": RECORDS, "--reference-elements": ["16", "32"], "--tmin-elements": ["8", "16"],
        "--midcurve": MIDCURVES, "--suite": SUITES, "--records": SUITES, "--scheduler": ["", " ", "nope"],
        "--resolution": ["0.05", "0.2", "0.5", "1"], "--max-runs": ["1", "4", "10"]}
# extreme sizes and step counts (drawn now and then instead of CAPS): refused before computing, or quick
EXTREME = {"--t-end": ["1e4", "1e5", "1e300"], "--dt": ["1e-6", "0.05", "1e-9"], "--dt-out": ["1e-6", "1e-9", "1e4"],
           "--block": ["1e-9", "1e6", "1e-8", "1e7", "1e-6"], "--elements": ["1000000", "200000", "30000", "3"],
           "--voussoirs": ["2", "200000", "81"], "--workers": ["300", "256", "0"], "--frames": ["100001", "1"],
           "--period": ["1e300", "1e-300"], "--duration": ["1e300"], "--periods": ["1e300", "1e-4,1e300"],
           "--t-over-r": ["1.9999999", "1e-9"], "--embrace": ["359.9", "1e-9"],
           "--resolution": ["1e-4", "9.9e-5", "1.0000001"], "--max-runs": ["100000", "100001"]}


# small problems put before the drawn options (which override them: argparse keeps the last)
BASE = {"sweep": ["--embrace", "90", "--t-over-r", "0.2", "--elements", "8", "--tmin-elements", "8"],
        "report": ["--quick", "--only", "exact"],
        "spectrum": ["--voussoirs", "7", "--periods", "0.3"],
        "collapse-scale": ["--voussoirs", "7", "--t-end", "3"],
        "assess": ["--voussoirs", "7", "--t-end", "3", "--resolution", "0.5", "--max-runs", "6", "--pulse", "sine",
                   "--amplitude", "0.5", "--period", "0.3"],
        "convergence": ["--elements", "8,16"],
        "fragility": ["--block", "0.4", "1.6", "--model", "rock", "--resolution", "0.2", "--bootstrap", "20"]}


@dataclass
class FuzzReport:
    runs: int = 0
    codes: dict = field(default_factory=dict)
    timeouts: list = field(default_factory=list)
    failures: list = field(default_factory=list)   # (argv, reason, stderr tail)
    seconds: float = 0.0

    def summary(self) -> str:
        lines = [f"fembeam fuzz: {self.runs} runs in {self.seconds:.1f} s; exit codes "
                 + ", ".join(f"{k}: {v}" for k, v in sorted(self.codes.items(), key=str))
                 + f"; {len(self.timeouts)} timeouts; {len(self.failures)} failures"]
        for argv, why, tail in self.failures:
            lines.append(f"  FAIL {why}: fembeam {' '.join(map(_quote, argv))}")
            lines += [f"       | {t}" for t in tail.splitlines()[-4:]]
        for argv in self.timeouts[:10]:
            lines.append(f"  timeout: fembeam {' '.join(map(_quote, argv))}")
        return "\n".join(lines)


def _quote(a: str) -> str:
    return repr(a) if (not a or any(c in a for c in " ,;*")) else a


def _commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _values(action: argparse.Action, rng: random.Random) -> list[str]:
    """Command-line words for one option, drawn by its kind."""
    opt = action.option_strings[0]
    hostile = rng.random() < 0.25
    if isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction)):
        return [opt]
    n = action.nargs if isinstance(action.nargs, int) else 1
    if opt in EXTREME and rng.random() < 0.12:
        return [opt] + [rng.choice(EXTREME[opt]) for _ in range(n)]
    if action.choices is not None:
        pool = [str(c) for c in action.choices] + (["nope", "", "0"] if hostile else [])
    elif opt in CAPS and not hostile:
        pool = CAPS[opt]
    else:
        name = getattr(action.type, "__name__", "") if action.type else ""
        kinds = {"int": INTS, "int_list": ["4,8", "7,15"], "float_list": LISTS}
        if name in kinds:
            pool = kinds[name]
        elif name in ("finite_float", "float"):
            pool = NUMBERS
        elif action.type is None or name in ("Path", "str"):
            pool = PATHS
        else:
            pool = NUMBERS + PATHS
        if hostile:
            pool = HOSTILE + (LISTS if name.endswith("list") else [])
    return [opt] + [rng.choice(pool) for _ in range(n)]


def draw(parser: argparse.ArgumentParser, rng: random.Random) -> list[str]:
    """Random arguments for one sub-command ``parser``: its required options always, about
    three others; mutually exclusive options sometimes together (argparse's own error).  Options
    hidden from the help (replaced ones, kept only to refuse them) are not drawn."""
    actions = [a for a in parser._actions if a.option_strings and not isinstance(a, argparse._HelpAction)
               and a.help != argparse.SUPPRESS]      # hidden: a replaced option, refused with one line
    chosen = [a for a in actions if a.required]
    others = [a for a in actions if not a.required]
    chosen += rng.sample(others, k=min(len(others), rng.choice([0, 1, 2, 3, 4, 5])))
    if not any(a.option_strings[0] in ("--quiet",) for a in chosen) and any(
            a.option_strings[0] == "--quiet" for a in actions):
        chosen.append(next(a for a in actions if a.option_strings[0] == "--quiet"))
    argv: list[str] = []
    for a in chosen:
        argv += _values(a, rng)
    names = {a.option_strings[0] for a in actions}
    outputs = [o for o in OUTPUTS if o in names]
    if len(outputs) >= 2 and rng.random() < 0.1:          # two outputs naming one file
        first, second = rng.sample(outputs, 2)
        if first in ("--out-dir", "--report"):
            argv += [first, "od", second, "od/" + rng.choice(DERIVED)]
        else:
            same = rng.choice(["same.png", "same.csv", "same.json"])
            argv += [first, same, second, same]
    if {"--t-over-r", "--embrace"} <= names and rng.random() < 0.08:
        argv += CANNOT_STAND
    return argv


class ChildError(Exception):
    """An exception raised by a command in its child process that could not be sent back as
    itself (it does not pickle): its type's name and message."""

    def __init__(self, type_name: str, message: str):
        super().__init__(type_name, message)
        self.type_name = type_name

    def __str__(self) -> str:
        return ": ".join(self.args)


def exception_name(code: BaseException) -> str:
    return code.type_name if isinstance(code, ChildError) else type(code).__name__


def _in_child(argv: list[str], command) -> bytes:
    """Run ``command(argv)`` with stdout and stderr captured: the pickled (code, out, err)."""
    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code: object = command(argv)
            except SystemExit as e:
                code = e.code if isinstance(e.code, int) else 2
    except BaseException as e:   # a traceback: what the fuzzing is for
        import traceback
        code = e
        err.write(traceback.format_exc())
    try:
        payload = pickle.dumps((code, out.getvalue(), err.getvalue()))
        pickle.loads(payload)
        return payload
    except Exception:   # noqa: BLE001  an exception that does not pickle, or not back
        code = ChildError(type(code).__name__, str(code)) if isinstance(code, BaseException) else repr(code)
        return pickle.dumps((code, out.getvalue(), err.getvalue()))


def _kill_group(pgid: int) -> None:
    try:
        os.killpg(pgid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _received(data: bytearray):
    """The child's (code, out, err) once ``data`` holds all of it, else None."""
    if len(data) < 8 or len(data) < 8 + struct.unpack("<Q", bytes(data[:8]))[0]:
        return None
    return pickle.loads(bytes(data[8:]))


def _died(status: int) -> str:
    code = os.waitstatus_to_exitcode(status)
    return f"killed by signal {-code}" if code < 0 else f"died with exit status {code} and no result"


def run_one(argv: list[str], timeout: float | None, command=None) -> tuple[object, str, str]:
    """``fembeam argv`` in a child process forked from this one: (exit code, or "timeout", or
    the exception), stdout, stderr.

    The child has this process's imports and runs ``command(argv)`` (default: fembeam's
    ``main``) with its stdout and stderr captured, in a process group of its own; the result
    comes back through a pipe.  A child still running after ``timeout`` seconds (None: no
    limit) is killed with every process it started, and the run is "timeout".  No signal
    is sent to this process and nothing is raised in it, whatever the child was doing; a
    child that dies without a result (a crash) is "killed by signal N" or "died with
    exit status N"."""
    if command is None:
        from .cli.main import main as command
    sys.stdout.flush()
    sys.stderr.flush()
    r, w = os.pipe()
    with warnings.catch_warnings():      # Python >= 3.12 warns of fork() with threads running: the
        warnings.simplefilter("ignore", DeprecationWarning)   # child only runs the command and exits
        pid = os.fork()
    if pid == 0:                                   # the child: never returns
        status = 70
        try:
            os.close(r)
            os.setpgid(0, 0)
            payload = _in_child(argv, command)
            view = memoryview(struct.pack("<Q", len(payload)) + payload)
            while view:
                view = view[os.write(w, view):]
            status = 0
        finally:
            os._exit(status)
    os.close(w)
    try:
        os.setpgid(pid, pid)                       # either of us may get there first
    except OSError:
        pass
    deadline = None if timeout is None else time.monotonic() + timeout
    data, result, reaped = bytearray(), None, False
    try:
        while result is None:
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                result = "timeout", "", ""
                break
            # short waits: a child that died without a result is noticed even when a process
            # it started holds the pipe open
            if select.select([r], [], [], 0.2 if left is None else min(left, 0.2))[0]:
                chunk = os.read(r, 1 << 20)
                if chunk:
                    data += chunk
                    result = _received(data)
                    continue
                _, status = os.waitpid(pid, 0)          # end of the pipe: the child has exited
            else:
                done, status = os.waitpid(pid, os.WNOHANG)
                if not done:
                    continue
            reaped = True
            while select.select([r], [], [], 0)[0] and (chunk := os.read(r, 1 << 20)):
                data += chunk
            result = _received(data) or (_died(status), "", "")
    finally:
        os.close(r)
        _kill_group(pid)                               # a child still running, and what it started
        if not reaped:
            os.waitpid(pid, 0)
    return result


def check(command: str, argv: list[str], code, out: str, err: str) -> str | None:
    """Why the run breaks the command line's promise, or None."""
    if isinstance(code, BaseException):
        return f"exception {exception_name(code)}"
    if code == "timeout":
        return None
    if isinstance(code, str):             # the child crashed
        return code
    allowed = {0, 2, 3} | ({1} if command == "report" else set())
    if code not in allowed:
        return f"exit code {code}"
    text = err.replace("\r", "\n")
    if "Traceback" in text or "Warning:" in text:
        return "traceback or warning on stderr"
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    if code == 2 and len(lines) != 1:
        return f"exit 2 with {len(lines)} stderr lines"
    if code == 3 and not (lines and lines[-1].startswith("fembeam")):
        return "exit 3 without fembeam's message"
    if code == 0 and "--json" in argv:
        try:
            obj = json.loads(out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
        except ValueError as e:
            return f"--json output is not strict JSON ({str(e)[:60]})"
        if not isinstance(obj, dict):
            return "--json output is not one JSON object"
    return None


def _scratch() -> str:
    """A scratch directory with the files the drawn options name (see :data:`RECORDS`,
    :data:`MIDCURVES`)."""
    d = tempfile.mkdtemp(prefix="fembeam-fuzz-")
    os.mkdir(os.path.join(d, "adir"))
    files = {"afile": "not a record\n", "bad.csv": "time,acc\n0,nan\n0.01,0.1\n",
             "time_cut.csv": "time,acc\n0,0\n1e-,0.1\n", "midcurve.csv": _midcurve(False),
             "mirror.csv": _midcurve(True), "many.csv": "x,y\n" + "".join(f"{i},{i % 7}\n" for i in range(5002))}
    header = "PEER\nfuzz\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   {}, DT=   {} SEC\n"
    for name, npts, dt in (("dt_bad", 4, "0.01.5"), ("dt_dash", 4, "-"), ("dt_zero", 4, "0"),
                           ("dt_huge", 4, "1e300"), ("npts_huge", 40_000_000_000, "0.01")):
        files[f"{name}.AT2"] = header.format(npts, dt) + "  .1E-01  .2E-01  .1E-01  0.\n"
    for name, text in files.items():
        with open(os.path.join(d, name), "w") as f:
            f.write(text)
    with open(os.path.join(d, "latin1.AT2"), "wb") as f:
        f.write(header.format(4, ".01").encode() + "caf\u00e9 .1 .2 .3\n".encode("latin-1"))
    with open(os.path.join(d, "bin.pdf"), "wb") as f:
        f.write(b"%PDF-1.4\n\xac\xff\xfe\x00 binary")
    for name in ("sparse.csv", "sparse.AT2"):
        with open(os.path.join(d, name), "wb") as f:
            f.truncate(5 * 2 ** 30)
    with contextlib.suppress(OSError, AttributeError):
        os.mkfifo(os.path.join(d, "fifo.csv"))
    _suites(d, files)
    return d


def _suites(d: str, files: dict) -> None:
    """The folders of :data:`SUITES` and the CSV records with bad lines of :data:`RECORDS`."""
    short = "time,acc\n" + "".join(f"{0.01 * i:.2f},{0.3 * math.sin(0.2 * i):.5f}\n" for i in range(300))
    bad = {"nan_rows.csv": short + "NaN,NaN\n" * 3,
           "abc_row.csv": short.replace("\n1.00,", "\nabc,def\n1.00,", 1),
           "two_headers.csv": "time,acc\nunits,g\n" + short.split("\n", 1)[1],
           "ms2.csv": short.replace(",0.", ",3.")}
    for name, text in bad.items():
        with open(os.path.join(d, name), "w") as f:
            f.write(text)
    for suite in ("suite", "suite_fifo", "suite_loop", "suite_bad", "suite_dir"):
        os.mkdir(os.path.join(d, suite))
        with open(os.path.join(d, suite, "short.csv"), "w") as f:
            f.write(short)
    with contextlib.suppress(OSError, AttributeError):
        os.mkfifo(os.path.join(d, "suite_fifo", "fifo.AT2"))
    os.symlink("loop.csv", os.path.join(d, "suite_loop", "loop.csv"))
    shutil.copy(os.path.join(d, "nan_rows.csv"), os.path.join(d, "suite_bad"))
    os.mkdir(os.path.join(d, "suite_dir", "folder.AT2"))


def _midcurve(mirror: bool) -> str:
    """An asymmetric surveyed mid-curve (9 points, springings at different heights), or its
    mirror image given from its right springing."""
    pts = [(10.0 * u, 4.5 * (1.0 - (2.0 * u - 1.0) ** 2) + 0.6 * u) for u in (i / 8 for i in range(9))]
    return "x,y\n" + "".join(f"{-x if mirror else x!r},{y!r}\n" for x, y in pts)


JOURNALED = ("spectrum", "sweep")


def _corrupt_journals(d: str, rng: random.Random) -> None:
    """Corrupt journals where the studies' outputs of :data:`PATHS` keep theirs (rewritten
    before every run: a run that finishes removes its journal)."""
    names = [f".{p}.{c}-journal.jsonl" for p in ("out.csv", "out.png", "out.pdf") for c in JOURNALED]
    names += [os.path.join("res", f".fembeam-{c}-journal.jsonl") for c in JOURNALED]
    os.makedirs(os.path.join(d, "res"), exist_ok=True)
    for name in names:
        path = os.path.join(d, name)
        with contextlib.suppress(FileNotFoundError, IsADirectoryError):
            os.remove(path)
        kind = rng.choice(["random", "latin-1", "wrong type", "sparse", "fifo", "none"])
        if kind == "fifo":
            with contextlib.suppress(OSError, AttributeError):
                os.mkfifo(path)
            continue
        with open(path, "wb") as f:
            if kind == "random":
                f.write(rng.randbytes(2000))
            elif kind == "latin-1":
                f.write("caf\u00e9\n".encode("latin-1"))
            elif kind == "wrong type":
                f.write(b'{"key": "0123", "result": "not a row", "check": "x"}\n{"key": [1], "result": {}}\n')
            elif kind == "sparse":
                f.truncate(5 * 2 ** 30)


def fuzz(runs: int = 300, seed: int = 0, timeout: float | None = 20.0, commands: list[str] | None = None,
         progress: bool = False, classes: bool = False) -> FuzzReport:
    """Run ``runs`` random command lines (reproducible from ``seed``) in a scratch directory;
    with ``classes``, first the command lines of :data:`CLASSES` (each must also give its exit
    code)."""
    import numpy as np

    from .cli.main import build_parser

    rng = random.Random(seed)
    cmds = _commands(build_parser())
    names = sorted(commands or cmds)
    unknown = set(names) - set(cmds)
    if unknown:
        raise SystemExit(f"fembeam.fuzz: unknown commands {sorted(unknown)}; known: {', '.join(sorted(cmds))}")
    rep = FuzzReport()
    here, clock = os.getcwd(), time.perf_counter()
    scratch = _scratch()
    os.chdir(scratch)
    plan = [(argv, expected) for argv, expected in (CLASSES if classes else [])
            if commands is None or argv[0] in commands]
    try:
        for i in range(len(plan) + runs):
            if i < len(plan):
                argv, expected = plan[i]
                name = argv[0]
            else:
                name, expected = rng.choice(names), None
                argv = [name] + BASE.get(name, []) + draw(cmds[name], rng)
            _corrupt_journals(scratch, rng)
            with np.errstate(all="warn"):
                code, out, err = run_one(argv, timeout)
            rep.runs += 1
            key = code if isinstance(code, (int, str)) else "exception"
            rep.codes[key] = rep.codes.get(key, 0) + 1
            if code == "timeout":
                rep.timeouts.append(argv)
            why = check(name, argv, code, out, err)
            if why is None and expected is not None and code != expected:
                why = f"exit {code} where this class of input gives {expected}"
            if why:
                rep.failures.append((argv, why, err[-600:]))
            if progress:
                print(f"\r{i + 1}/{len(plan) + runs} runs, {len(rep.failures)} failures", end="", file=sys.__stderr__,
                      flush=True)
    finally:
        os.chdir(here)
        shutil.rmtree(scratch, ignore_errors=True)
        if progress:
            print(file=sys.__stderr__)
    rep.seconds = time.perf_counter() - clock
    return rep


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m fembeam.fuzz", description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=300, help="command lines to try (default 300)")
    ap.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds after which a run is killed and counted as a timeout (default 20)")
    ap.add_argument("--command", action="append", default=None, help="only this sub-command (repeatable)")
    ap.add_argument("--no-classes", action="store_true",
                    help="skip the fixed command lines of the classes of hostile input (CLASSES) run first")
    ap.add_argument("--scenarios", type=int, default=0,
                    help="process-level scenarios to run after the command lines (default 0; fembeam.fuzz_scenarios)")
    args = ap.parse_args(argv)
    rep = fuzz(args.runs, args.seed, args.timeout, args.command, progress=True, classes=not args.no_classes)
    print(rep.summary())
    failed = bool(rep.failures)
    if args.scenarios > 0:
        from .fuzz_scenarios import run_scenarios
        sc = run_scenarios(args.scenarios, random.Random(args.seed), draw_command, progress=True)
        print(sc.summary())
        failed = failed or bool(sc.failures)
    return 1 if failed else 0


def draw_command(rng: random.Random, commands: list[str] | None = None) -> list[str]:
    """One drawn command line (a command, its :data:`BASE`, drawn options)."""
    from .cli.main import build_parser

    cmds = _commands(build_parser())
    name = rng.choice(sorted(commands or cmds))
    return [name] + BASE.get(name, []) + draw(cmds[name], rng)


if __name__ == "__main__":
    sys.exit(main())
