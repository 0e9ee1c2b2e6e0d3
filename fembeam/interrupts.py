"""Ctrl-C and SIGTERM as exceptions that cannot be lost.

A signal handler's exception is raised wherever the main thread happens to be.  When that
is a callback whose errors Python ignores (the at-fork hooks run when a worker process is
started, a finaliser, a weakref callback) the exception is printed as "Exception ignored"
and the program goes on as if nothing had happened.  So the handlers here also remember
the signal, :func:`check` raises it again at the next safe point (a finished task of a
study, the end of a command), and the interpreter's report of the ignored exception is
suppressed.
"""
from __future__ import annotations

import signal
import sys
from contextlib import contextmanager

__all__ = ["Terminated", "handled", "check", "reset"]


class Terminated(BaseException):
    """SIGTERM, turned into an exception so that open outputs are cleaned up."""


_pending: type[BaseException] | None = None


def _handler(signum, frame):
    global _pending
    _pending = KeyboardInterrupt if signum == signal.SIGINT else Terminated
    raise _pending()


def _unraisable(info) -> None:
    if isinstance(info.exc_value, (KeyboardInterrupt, Terminated)) and _pending is not None:
        return                                      # remembered: check() raises it again
    sys.__unraisablehook__(info)


@contextmanager
def handled():
    """SIGINT and SIGTERM raise KeyboardInterrupt and :class:`Terminated` inside the block
    (enter it from the main thread); the previous handlers are restored on leaving."""
    reset()
    old = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM), sys.unraisablehook
    signal.signal(signal.SIGINT, _handler)
    signal.signal(signal.SIGTERM, _handler)
    sys.unraisablehook = _unraisable
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old[0])
        signal.signal(signal.SIGTERM, old[1])
        sys.unraisablehook = old[2]


def check() -> None:
    """Raise the interrupt received since :func:`install`, if any (lost or not)."""
    if _pending is not None:
        raise _pending()


def reset() -> None:
    """Forget a received interrupt (it has been reported)."""
    global _pending
    _pending = None
