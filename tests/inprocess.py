"""fembeam's command line run in the test's own process, for the tests of what a command answers
(its output, its exit code, its one-line errors); the tests of the process itself (signals, closed
or full streams, the interpreter's exit) start one."""
from __future__ import annotations

import contextlib
import io
import subprocess

from fembeam.cli.main import main


def fembeam(*argv: str) -> subprocess.CompletedProcess:
    """``main(argv)`` as ``subprocess.run(["fembeam", *argv], capture_output=True, text=True)``
    gives it: the exit code (argparse's ``SystemExit`` included), stdout and stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main([str(a) for a in argv])
        except SystemExit as e:
            code = e.code
    return subprocess.CompletedProcess(["fembeam", *argv], code, out.getvalue(), err.getvalue())
