"""Process-level scenarios of the command-line fuzzer (``python -m fembeam.fuzz --scenarios N``).

Each scenario runs ``python -m fembeam`` as a real process in a session of its own, in a
fresh scratch directory, and judges what a user would see:

* ``signal-early``: SIGINT, SIGTERM or SIGHUP as soon as fembeam's handlers are installed
  (seen in ``/proc/PID/status``; NumPy and the command's modules still loading);
* ``signal-late``: the same after a random 0-3 s (a computation, a study's workers, the
  writing of CSV, figure, ParaView series and GIF, an assessment's report folder, a
  fragility study's output folder);
* ``kill-parent``: SIGKILL to a study's parent process (``spectrum``/``sweep`` with two
  workers): its workers must end with it;
* ``closed-stdout``: a drawn command line with descriptor 1 closed;
* ``ascii``: a command writing to non-ASCII file names under ``PYTHONIOENCODING=ascii`` and
  ``LC_ALL=C``;
* ``rerun``: a command run to completion, then run again over its complete outputs and
  interrupted at a random time: each output is the old file or a complete new one.

A scenario **fails** when: an interrupted command does not exit with 128 + the signal and
exactly one line (or 0, if it had finished), a traceback or warning reaches stderr, a
temporary file is left, a ParaView index names a file that is missing, an output is
half-written, or a process of the session is still alive after :data:`HANG_GUARD_S`.  The
time from the signal to the exit is measured and reported (``slow``: above 1 s), never
judged: it depends on the machine's load.
"""
from __future__ import annotations

import csv
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

__all__ = ["SCENARIOS", "ScenarioReport", "run_scenarios"]

HANG_GUARD_S = 120.0      # a process still there after this long is stuck (each run takes seconds)
SLOW_S = 1.0              # the promise: an interrupted command exits within 1 s (reported, not judged)

ROCK = ["rock", "--voussoirs", "7", "--pulse", "sine", "--period", "1"]
# valid command lines that run for seconds and write outputs (AMP: the amplitude, varied on a re-run)
LONG = {
    "rock": ROCK + ["--amplitude", "AMP", "--csv", "h.csv", "--plot", "h.png", "--vtk", "h.pvd", "--gif", "h.gif",
                    "--frames", "40"],
    "simulate": ["simulate", "--voussoirs", "7", "--pulse", "sine", "--period", "1", "--amplitude", "AMP",
                 "--csv", "s.csv", "--plot", "s.png", "--vtk", "s.pvd", "--gif", "s.gif", "--frames", "40"],
    "spectrum": ["spectrum", "--voussoirs", "7", "--pulse", "sine", "--periods", "0.2:0.9:0.1", "--workers", "2",
                 "--csv", "sp.csv", "--plot", "sp.png", "--quiet", "--bisect-tol", "AMP"],
    "sweep": ["sweep", "--embrace", "90,150", "--t-over-r", "0.1:0.3:0.02", "--elements", "16", "--tmin-elements",
              "16", "--workers", "2", "--out-dir", "sw", "--quiet", "--above", "AMP"],
    "assess": ["assess", "--voussoirs", "7", "--t-end", "3", "--pulse", "sine", "--period", "0.3", "--amplitude", "AMP",
               "--report", "rep"],
    "fragility": ["fragility", "--block", "0.4", "1.6", "--model", "rock", "--suite", "suite", "--out-dir", "fr",
                  "--quiet", "--bootstrap", "50", "--resolution", "AMP"],
}
AMPLITUDES = {"rock": ("0.45", "0.5"), "simulate": ("0.45", "0.5"), "spectrum": ("0.01", "0.02"),
              "sweep": ("0.001", "0.002"), "assess": ("0.5", "0.45"), "fragility": ("0.1", "0.2")}
SIGNALS = {signal.SIGINT: "interrupted", signal.SIGTERM: "terminated", signal.SIGHUP: "hung up"}
SCENARIOS = ("signal-early", "signal-late", "kill-parent", "closed-stdout", "ascii", "rerun")
_TEMPORARY = re.compile(r"^\.(?!.*-journal\.jsonl$).+")     # a hidden file that is not a study's journal


@dataclass
class ScenarioReport:
    counts: dict = field(default_factory=dict)     # scenario -> runs
    codes: dict = field(default_factory=dict)      # exit codes seen
    failures: list = field(default_factory=list)   # (scenario, argv, why, stderr tail)
    latencies: list = field(default_factory=list)  # seconds from a signal to the exit

    def summary(self) -> str:
        slow = [x for x in self.latencies if x > SLOW_S]
        lat = (f"; signal to exit: median {sorted(self.latencies)[len(self.latencies) // 2]:.2f} s, max "
               f"{max(self.latencies):.2f} s, {len(slow)} above {SLOW_S:g} s") if self.latencies else ""
        lines = [f"fembeam fuzz scenarios: {sum(self.counts.values())} runs ("
                 + ", ".join(f"{k}: {v}" for k, v in sorted(self.counts.items())) + "); exit codes "
                 + ", ".join(f"{k}: {v}" for k, v in sorted(self.codes.items(), key=str))
                 + f"{lat}; {len(self.failures)} failures"]
        for kind, argv, why, tail in self.failures:
            lines.append(f"  FAIL {kind}: {why}: fembeam {' '.join(argv)}")
            lines += [f"       | {t}" for t in tail.splitlines()[-4:]]
        return "\n".join(lines)


def _env(**extra) -> dict:
    import fembeam
    root = os.path.dirname(os.path.dirname(os.path.abspath(fembeam.__file__)))
    env = dict(os.environ, PYTHONPATH=root + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.update(extra)
    return env


def _spawn(argv, cwd, env=None, close_stdout=False) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "fembeam", *argv], cwd=cwd, env=env or _env(), text=True,
                            errors="backslashreplace",
                            stdout=subprocess.DEVNULL if close_stdout else subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True, preexec_fn=(lambda: os.close(1)) if close_stdout else None)


def _caught(pid: int) -> bool:
    """fembeam's handlers are installed in ``pid`` (it catches SIGTERM and SIGHUP)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            mask = int(next(line for line in f if line.startswith("SigCgt:")).split()[1], 16)
    except (OSError, StopIteration):
        return False
    return all(mask >> (s - 1) & 1 for s in (signal.SIGTERM, signal.SIGHUP))


def _children(pid: int) -> list[int]:
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(x) for x in f.read().split()]
    except OSError:
        return []


def _alive_in_group(pgid: int) -> list[int]:
    """Processes of the process group ``pgid`` that are not zombies."""
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == pgid and fields[0] not in "ZX":
                out.append(int(d))
    return out


def _wait_gone(pgid: int) -> list[int]:
    """Wait (hang guard) until no process of the group is alive; returns those still alive."""
    deadline = time.monotonic() + HANG_GUARD_S
    while (left := _alive_in_group(pgid)) and time.monotonic() < deadline:
        time.sleep(0.05)
    return left


def _wait(pred, p: subprocess.Popen) -> bool:
    """Wait (hang guard) until ``pred()`` or the process ends; whether ``pred()`` came first."""
    deadline = time.monotonic() + HANG_GUARD_S
    while p.poll() is None and time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.0005)
    return False


def _finish(p: subprocess.Popen) -> tuple[str, str]:
    try:
        out, err = p.communicate(timeout=HANG_GUARD_S)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        err += f"\n(killed: still running {HANG_GUARD_S:.0f} s after)"
    return out or "", err or ""


def _leftovers(d: str) -> list[str]:
    """Temporary files left in ``d`` (any depth), and ParaView indexes naming missing files."""
    bad = []
    for root, dirs, files in os.walk(d):
        for name in files + dirs:
            if _TEMPORARY.match(name):
                bad.append(os.path.relpath(os.path.join(root, name), d))
        for name in files:
            if name.endswith(".pvd"):
                with open(os.path.join(root, name), errors="replace") as f:
                    listed = re.findall(r'file="([^"]+)"', f.read())
                bad += [f"{name} -> {n} (missing)" for n in listed if not os.path.exists(os.path.join(root, n))]
    return bad


def _complete(path: str) -> str | None:
    """Why the output ``path`` is not a complete file of its kind, or None."""
    try:
        if path.endswith(".csv"):
            with open(path, newline="") as f:
                rows = list(csv.reader(f))
            if not rows or len({len(r) for r in rows}) != 1:
                return "a CSV with rows of different lengths"
        elif path.endswith((".png", ".gif")):
            from PIL import Image
            with Image.open(path) as im:
                im.verify()
        elif path.endswith(".json"):
            import json
            with open(path) as f:
                json.load(f)
    except Exception as e:      # noqa: BLE001  any failure to read it back is the finding
        return f"cannot be read back ({type(e).__name__}: {e})"
    return None


def _snapshot(d: str) -> dict[str, bytes]:
    out = {}
    for root, _, files in os.walk(d):
        for name in files:
            p = os.path.join(root, name)
            with open(p, "rb") as f:
                out[os.path.relpath(p, d)] = f.read()
    return out


def _judge_signal(p, argv, sig, sent: bool, out: str, err: str, d: str) -> str | None:
    """Why an interrupted (or finished) run broke the promise, or None."""
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    if "Traceback" in err or "Warning:" in err:
        return "traceback or warning on stderr"
    if not sent or p.returncode == 0:
        if p.returncode != 0:
            return f"exit {p.returncode} before any signal"
    elif p.returncode != 128 + sig:
        return f"exit {p.returncode} after {sig.name} (expected {128 + sig})"
    elif len(lines) != 1 or not lines[0].startswith(f"fembeam: {SIGNALS[sig]}"):
        return f"{len(lines)} stderr lines after {sig.name}"
    bad = _leftovers(d)
    return f"left behind: {', '.join(bad[:4])}" if bad else None


def _prepare(d: str) -> None:
    """The inputs of :data:`LONG` in the scenario's folder: a suite of one short record."""
    from importlib import resources
    os.mkdir(os.path.join(d, "suite"))
    src = resources.files("fembeam") / "data" / "ground_motions" / "elcentro_1940_ns_chopra.csv"
    with open(os.path.join(d, "suite", "elcentro.csv"), "w") as f:
        f.write("".join(src.read_text().splitlines(keepends=True)[:400]))     # the first 8 s


def _signal(kind: str, rng: random.Random, d: str, rep: ScenarioReport):
    name = rng.choice(sorted(LONG))
    argv = [a if a != "AMP" else AMPLITUDES[name][0] for a in LONG[name]]
    sig = rng.choice(sorted(SIGNALS))
    p = _spawn(argv, d)
    ready = _wait(lambda: _caught(p.pid), p)
    if ready and kind == "signal-late":
        time.sleep(rng.uniform(0.0, 3.0))
    sent = ready and p.poll() is None
    t0 = time.monotonic()
    if sent:
        (os.killpg if sig != signal.SIGTERM else os.kill)(p.pid, sig)      # a terminal signals the group
    out, err = _finish(p)
    if sent:
        rep.latencies.append(time.monotonic() - t0)
    left = _wait_gone(p.pid)
    why = _judge_signal(p, argv, sig, sent, out, err, d)
    if left:
        why = (why + "; " if why else "") + f"processes alive: {left}"
    return argv + [f"({sig.name})"], p.returncode, why, err


def _kill_parent(rng: random.Random, d: str, rep: ScenarioReport):
    name = rng.choice(["spectrum", "sweep"])
    argv = [a if a != "AMP" else AMPLITUDES[name][0] for a in LONG[name]]
    p = _spawn(argv, d)
    started = _wait(lambda: len(_children(p.pid)) >= 2, p)
    if started:
        time.sleep(rng.uniform(0.0, 1.0))
        os.kill(p.pid, signal.SIGKILL)
    out, err = _finish(p)
    left = _wait_gone(p.pid)
    why = f"workers alive after their parent was killed: {left}" if left else None
    if not started and p.returncode != 0:
        why = f"exit {p.returncode} before its workers started"
    return argv + ["(SIGKILL)"], p.returncode, why, err


def _closed_stdout(rng: random.Random, d: str, rep: ScenarioReport, draw_argv):
    argv = draw_argv(rng)
    p = _spawn(argv, d, close_stdout=True)
    _, err = _finish(p)
    expected = "fembeam: error: stdout is closed: the output cannot be written (redirect it to a file or /dev/null)"
    why = None if p.returncode == 2 and err.strip() == expected else f"exit {p.returncode}, stderr {err[-80:]!r}"
    return argv, p.returncode, why, err


def _ascii(rng: random.Random, d: str, rep: ScenarioReport):
    stem = rng.choice(["r\u00e9sum\u00e9", "\u6570\u636e", "caf\u00e9 \u00fcber", "\u00e5"])
    argv = ROCK + ["--amplitude", "0.45", "--csv", f"{stem}.csv", "--plot", f"{stem}.png"]
    p = _spawn(argv, d, env=_env(PYTHONIOENCODING="ascii", LC_ALL="C"))
    out, err = _finish(p)
    why = None
    if p.returncode != 0 or err.strip():
        why = f"exit {p.returncode} with stderr"
    elif "\\x" not in out and "\\u" not in out:
        why = "the non-ASCII file names are not escaped on stdout"
    else:
        why = next((f"{n}: {w}" for n in (f"{stem}.csv", f"{stem}.png") if (w := _complete(os.path.join(d, n)))),
                   None) or (", ".join(_leftovers(d)) or None)
    return argv, p.returncode, why, err


def _rerun(rng: random.Random, d: str, rep: ScenarioReport):
    name = rng.choice(sorted(LONG))
    first = [a if a != "AMP" else AMPLITUDES[name][0] for a in LONG[name]]
    again = [a if a != "AMP" else AMPLITUDES[name][1] for a in LONG[name]]
    p = _spawn(first, d)
    _, err = _finish(p)
    if p.returncode != 0:
        return first, p.returncode, f"the first run exited {p.returncode}", err
    before = _snapshot(d)
    p = _spawn(again, d)
    ready = _wait(lambda: _caught(p.pid), p)
    if ready:
        time.sleep(rng.uniform(0.0, 4.0))
    sig = rng.choice(sorted(SIGNALS))
    sent = ready and p.poll() is None
    t0 = time.monotonic()
    if sent:
        (os.killpg if sig != signal.SIGTERM else os.kill)(p.pid, sig)
    out, err = _finish(p)
    if sent:
        rep.latencies.append(time.monotonic() - t0)
    why = _judge_signal(p, again, sig, sent, out, err, d)
    if why is None:
        after = _snapshot(d)
        lost = [f for f in before if f not in after and not f.endswith(".vtu")]
        broken = [f"{f}: {w}" for f in after if (w := _complete(os.path.join(d, f)))]
        if lost or broken:
            why = f"lost {lost[:3]}; broken {broken[:3]}"
    return again + [f"({sig.name})"], p.returncode, why, err


def run_scenarios(n: int, rng: random.Random, draw_argv, kinds=SCENARIOS, progress: bool = False,
                  plan: list[str] | None = None) -> ScenarioReport:
    """``n`` scenarios drawn from ``kinds`` (or the scenarios of ``plan``, in order),
    reproducible from ``rng``; ``draw_argv(rng)`` draws a command line (for ``closed-stdout``)."""
    rep = ScenarioReport()
    if not os.path.exists("/proc/self/status"):
        kinds = [k for k in kinds if k in ("closed-stdout", "ascii")]      # the others read /proc
        plan = None if plan is None else [k for k in plan if k in kinds]
    todo = list(plan) if plan is not None else [rng.choice(list(kinds)) for _ in range(n)]
    for i, kind in enumerate(todo):
        d = tempfile.mkdtemp(prefix="fembeam-fuzz-scenario-")
        _prepare(d)
        try:
            if kind.startswith("signal"):
                argv, code, why, err = _signal(kind, rng, d, rep)
            elif kind == "kill-parent":
                argv, code, why, err = _kill_parent(rng, d, rep)
            elif kind == "closed-stdout":
                argv, code, why, err = _closed_stdout(rng, d, rep, draw_argv)
            elif kind == "ascii":
                argv, code, why, err = _ascii(rng, d, rep)
            else:
                argv, code, why, err = _rerun(rng, d, rep)
        finally:
            shutil.rmtree(d, ignore_errors=True)
        rep.counts[kind] = rep.counts.get(kind, 0) + 1
        rep.codes[code] = rep.codes.get(code, 0) + 1
        if why:
            rep.failures.append((kind, argv, why, err[-600:]))
        if progress:
            print(f"\r{i + 1}/{len(todo)} scenarios, {len(rep.failures)} failures", end="", file=sys.__stderr__,
                  flush=True)
    if progress:
        print(file=sys.__stderr__)
    return rep

