"""The parser and the entry point: one sub-command per module of this package.

This module imports only the standard library (and fembeam's light :mod:`~fembeam.errors`
and :mod:`~fembeam.interrupts`), so that :func:`main` installs its signal handlers a few
milliseconds after the interpreter starts, before NumPy and the command's modules load:
a Ctrl-C or SIGTERM from then on exits 130 or 143 with one line, never a traceback.
"""
from __future__ import annotations

import argparse
import os
import sys
import threading
import warnings

from .. import interrupts
from ..errors import FembeamError, InputError
from ..interrupts import HungUp, Terminated

# sub-command -> (module of fembeam.cli, one-line help); a module is imported only when its
# command runs (or for a full parser), so that ``fembeam --help`` stays quick
COMMANDS = {
    "analyze": ("analyze", "A_L, mechanism before the impact, r and the impulse line"),
    "min-thickness": ("min_thickness", "smallest thickness at which the arch stands, and its mechanism"),
    "load-scan": ("load_scan", "one point load moved across the span: smallest load factor and where"),
    "convergence": ("convergence", "mesh-refinement study: A_L, r, hinges, errors and observed rates"),
    "sweep": ("sweep", "parametric study: r_max vs t/R per embrace angle (or t/span per rise/span of another "
                       "--shape), minimum-thickness envelope"),
    "impact": ("impact", "four-hinge impact: r, alpha', impulse line and its admissibility"),
    "report": ("report", "verification report: tables and plots against exact solutions and the paper"),
    "rock": ("rock", "time history under a ground motion: impacts, rest or overturning"),
    "spectrum": ("spectrum", "overturning amplitude against pulse period (safe regions above it too)"),
    "collapse-scale": ("collapse_scale", "scale factor at which a record first collapses the member (hunt and fill)"),
    "fragility": ("fragility", "collapse fragility over a record suite: IDA of every record and sign, lognormal fit, "
                               "collapse margin ratio"),
    "simulate": ("simulate", "multi-body time history: Moreau-Jean steps, impact QP at every step, hinges anywhere"),
    "supports": ("supports", "supports that spread, settle or move, followed to collapse: capacity, thrust against "
                             "displacement, hinge migrations"),
    "assess": ("assess", "one page: A_L, minimum thickness, friction needed, auto verdict and margin"),
}


def one_line(text: str) -> str:
    """``text`` with its unprintable characters (newlines included) escaped."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


# an argument that starts with a negative number is a value, not an option: "-0.5", "-1e-3",
# and lists "-1,0.5" (``--move -1,0.5``; argparse's own pattern takes only single numbers)
NEGATIVE_VALUE = r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?(,.*)?$"


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        import re
        self._negative_number_matcher = re.compile(NEGATIVE_VALUE)

    def error(self, message):  # one line, no usage dump
        print(f"{self.prog}: error: {one_line(message)}", file=sys.stderr)
        raise SystemExit(2)

    def _print_message(self, message, file=None):  # argparse's drops write errors: --help > /dev/full
        if message:
            (file or sys.stderr).write(message)


def build_parser(only: str | None = None, full: bool = True) -> argparse.ArgumentParser:
    """The parser of every sub-command (``full``), or of the sub-command ``only`` with the
    others as names and help lines (``fembeam --help``: nothing imported)."""
    import importlib

    p = _Parser(prog="fembeam", description="Rocking masonry arches: limit analysis, impact, impulse line.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name, (module, help_line) in COMMANDS.items():
        if full or name == only:
            importlib.import_module(f".{module}", __package__).register(sub)
        else:
            sub.add_parser(name, help=help_line)
    if full or only in COMMANDS:
        from .args import note_list_limits
        note_list_limits(p)
    return p


def _parser_for(argv: list[str] | None) -> argparse.ArgumentParser:
    """Only the sub-command named in ``argv`` is built in full."""
    words = sys.argv[1:] if argv is None else argv
    command = next((w for w in words if not w.startswith("-")), None)
    return build_parser(only=command, full=False)


def main(argv: list[str] | None = None) -> int:
    """Run one sub-command; the exit code:

    * 0: done (physical outcomes such as "cannot stand" included);
    * 1: the reader of stdout went away (``fembeam analyze | head``): stop quietly;
    * 2: bad input (argparse errors raise ``SystemExit(2)``), or the output cannot be
      written (stdout closed or on a full device, an unwritable file): it is the invocation
      that asks for an impossible output, nothing was computed wrongly;
    * 3: a solve failed or failed its verification;
    * 130 / 143 / 129: interrupted (Ctrl-C) / terminated (SIGTERM) / hung up (SIGHUP).

    Every error is one line on stderr.  Warnings (numpy RuntimeWarnings, scipy's,
    scikit-fem's) are never shown: every result is verified independently, so a silenced
    overflow that matters still ends as a verification failure (exit 3).  The signal
    handlers come first, then the checks of the standard streams, then everything else."""
    if threading.current_thread() is not threading.main_thread():   # no signals there
        try:
            return _guarded(argv)
        except (KeyboardInterrupt, Terminated) as e:
            return _interrupted(e)
    try:
        with interrupts.handled():
            try:
                code = _guarded(argv)
            except (KeyboardInterrupt, Terminated) as e:
                code = _interrupted(e, argv is None)
            except BaseException:
                interrupts.check()      # a signal that another exception hid (NumPy's import makes it an ImportError)
                raise
            if argv is None:            # the program: done, leave with the handlers still in place
                with interrupts.deferred():
                    _leave(code)
            return code
    except (KeyboardInterrupt, Terminated) as e:    # while the handlers were put back
        return _interrupted(e, argv is None)


def _leave(code: int) -> None:
    """Exit the process at once with ``code`` (the program itself, ``argv`` None).  Whatever
    the command wrote is complete and closed, interrupted or not (temporary files removed,
    worker processes killed and waited for); the interpreter's own finalisation would only
    delay the exit (0.3-0.7 s once matplotlib and numba are loaded) and leave a window where
    Ctrl-C, with the handlers put back, would print a traceback from a finaliser."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):
            pass
    os._exit(code)


def _guarded(argv: list[str] | None) -> int:
    closed = _standard_streams()
    if closed:
        print(f"fembeam: error: {closed} is closed: the output cannot be written (redirect it to a file or "
              "/dev/null)", file=sys.stderr)
        return 2
    import numpy as np

    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return _command(argv)


def _standard_streams() -> str | None:
    """Make the standard streams safe to use: a closed descriptor 0, 1 or 2 is opened on
    /dev/null (else the first file fembeam opens would take its number, and whatever is
    printed would land in it); stdout and stderr escape what their encoding cannot show
    (an ASCII locale and a non-ASCII file name).  Returns "stdout" when it was closed
    (nothing could be printed), else None."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            try:
                os.open(os.devnull, os.O_RDWR)      # the lowest free descriptor: this one
            except OSError:
                pass
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w")
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.reconfigure(errors="backslashreplace")
        except (AttributeError, ValueError, OSError):    # not a text stream of a file (a test's capture)
            pass
    return "stdout" if sys.stdout is None else None


def _interrupted(e: BaseException, leave: bool = False) -> int:
    """One line (with what a study kept: its journal, from the exception's notes) and 130
    for Ctrl-C, 143 for SIGTERM, 129 for SIGHUP; with ``leave``, the process exits with it
    (a second signal meanwhile waits: the first is being reported)."""
    what, code = (("interrupted", 130) if isinstance(e, KeyboardInterrupt) else
                  ("hung up", 129) if isinstance(e, HungUp) else ("terminated", 143))
    with interrupts.deferred():
        # CPython remembers a KeyboardInterrupt that escaped code run from a string (exec or eval:
        # a dataclass being defined during an import), even when it was caught later, and then kills
        # itself with SIGINT at exit (-2 instead of 130); any later exec of a string clears that mark
        exec("pass")
        if sys.stderr is not None:
            try:
                print(f"fembeam: {what}" + one_line("".join(getattr(e, "__notes__", []))), file=sys.stderr)
            except (OSError, ValueError):
                pass
        if leave:
            _leave(code)
        interrupts.reset()          # reported: neither it nor a second signal meanwhile is raised again
    return code


def _command(argv: list[str] | None) -> int:
    try:
        try:
            args = _parser_for(argv).parse_args(argv)
            code = int(args.func(args) or 0)
            interrupts.check()        # a signal whose exception Python dropped (raised in an at-fork hook)
        except SystemExit as e:       # --help, or an argparse error
            code = e
        sys.stdout.flush()            # a full device fails here rather than at exit
        if isinstance(code, SystemExit):
            raise code
        return code
    except InputError as e:
        interrupts.check()   # (here and below) an error caused by a signal is the signal's
        print(f"fembeam: error: {one_line(e)}", file=sys.stderr)
        return 2
    except FembeamError as e:
        interrupts.check()
        print(f"fembeam: {type(e).__name__}: {one_line(e)}", file=sys.stderr)
        return 3
    except BrokenPipeError:  # e.g. `fembeam analyze | head`: stop quietly
        interrupts.check()
        _drop_stdout()
        return 1
    except OSError as e:     # e.g. `fembeam analyze > /dev/full`
        interrupts.check()
        _drop_stdout()
        what = "the output" if e.filename is None else repr(str(e.filename))
        print(f"fembeam: error: cannot write {what}: {one_line(e.strerror or e)}", file=sys.stderr)
        return 2


def _drop_stdout() -> None:
    """Point stdout at /dev/null, so that the interpreter's last flush of what is still
    buffered does not fail again."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):   # no file descriptor (e.g. captured by a test)
        pass
