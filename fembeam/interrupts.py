"""Ctrl-C, SIGTERM and SIGHUP as exceptions that cannot be lost.

A signal handler's exception is raised wherever the main thread happens to be.  When that
is a callback whose errors Python ignores (the at-fork hooks run when a worker process is
started, a finaliser, a weakref callback) the exception is printed as "Exception ignored"
and the program goes on as if nothing had happened.  So the handlers installed by
:func:`handled` also remember the signal, :func:`check` raises it again at the next safe
point (a finished task of a study, the end of a command), and the interpreter's report of
the ignored exception is suppressed.  Outside :func:`handled` (a library call, another
thread) nothing is remembered and :func:`check` does nothing.  Inside :func:`deferred` (a
step that must not be cut in the middle, such as a pool forking its worker processes) a
signal is only remembered, and raised when the block ends.
"""
from __future__ import annotations

import signal
import sys
import threading
from contextlib import contextmanager

__all__ = ["Terminated", "HungUp", "handled", "check", "reset", "deferred"]

_SIGNALS = (signal.SIGINT, signal.SIGTERM) + ((signal.SIGHUP,) if hasattr(signal, "SIGHUP") else ())


class Terminated(BaseException):
    """SIGTERM, turned into an exception so that open outputs are cleaned up."""


class HungUp(Terminated):
    """SIGHUP (the terminal went away), handled as a termination."""


_pending: type[BaseException] | None = None
_active = False
_deferred = 0


def _exception(signum: int) -> type[BaseException]:
    if signum == signal.SIGINT:
        return KeyboardInterrupt
    return Terminated if signum == signal.SIGTERM else HungUp


def _handler(signum, frame):
    global _pending
    _pending = _exception(signum)
    if not _deferred:
        raise _pending()


def _unraisable(info) -> None:
    if isinstance(info.exc_value, (KeyboardInterrupt, Terminated)) and _pending is not None:
        return                                      # remembered: check() raises it again
    sys.__unraisablehook__(info)


@contextmanager
def handled():
    """SIGINT, SIGTERM and SIGHUP raise KeyboardInterrupt, :class:`Terminated` and
    :class:`HungUp` inside the block (enter it from the main thread).  On leaving, the
    previous handlers are restored with the signals blocked, and one that arrived meanwhile
    is raised after the restore (so it is never lost, and never left to a handler of this
    module)."""
    global _active
    reset()
    old = [signal.getsignal(s) for s in _SIGNALS], sys.unraisablehook
    for s in _SIGNALS:
        signal.signal(s, _handler)
    sys.unraisablehook = _unraisable
    _active = True
    try:
        yield
    finally:
        late, mask = None, None
        try:
            if hasattr(signal, "pthread_sigmask"):
                mask = signal.pthread_sigmask(signal.SIG_BLOCK, _SIGNALS)
        finally:
            for s, h in zip(_SIGNALS, old[0]):
                signal.signal(s, h)
            sys.unraisablehook = old[1]
            _active = False
            reset()
            if mask is not None:
                while (info := signal.sigtimedwait(_SIGNALS, 0)) is not None:   # arrived while leaving
                    late = _exception(info.si_signo)
                signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        if late is not None:
            raise late()


@contextmanager
def deferred():
    """Inside :func:`handled`, on the main thread: a signal arriving in the block is raised
    when it ends (normally), not in the middle of it.  For a step that would leave a mess if
    cut, e.g. a process pool forking its workers: raised between a fork and the pool's
    record of the new process, the exception would leave a worker that nobody stops."""
    global _deferred
    if threading.current_thread() is not threading.main_thread():   # signals never run there
        yield
        return
    _deferred += 1
    try:
        yield
    finally:
        _deferred -= 1
    if not _deferred:
        check()


def check() -> None:
    """Inside :func:`handled`, on the main thread: raise the interrupt received in the
    block, if any (lost or not)."""
    if _active and _pending is not None and threading.current_thread() is threading.main_thread():
        raise _pending()


def reset() -> None:
    """Forget a received interrupt (it has been reported)."""
    global _pending
    _pending = None
