"""Output files: checked before any computation, written atomically.

:func:`check_output` rejects, with an :class:`~fembeam.errors.InputError` (exit 2), a path
whose suffix is not allowed, that is a directory, or whose parent is missing or not a
writable directory.  :func:`atomic` yields a temporary name in the same directory and renames
it onto the target only when the writer has finished, so that an error or an interrupt never
leaves a half-written file.
"""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Iterator, Sequence

from ..errors import InputError

__all__ = ["check_output", "check_dir", "atomic", "atomic_group", "PLOT_SUFFIXES"]

PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def check_output(path, option: str, suffixes: Sequence[str] = ()) -> Path | None:
    """``path`` as a :class:`Path` if it can be written (None stays None)."""
    if path is None:
        return None
    p = Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        raise InputError(f"{option}: expected a file name ending in {' or '.join(suffixes)}, got {str(p)!r}")
    if p.is_dir():
        raise InputError(f"{option}: {str(p)!r} is a directory")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: the directory {str(parent)!r} does not exist")
    _probe(parent, option)
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(f"{option}: {str(p)!r} is not writable")
    return p


def check_dir(path, option: str) -> Path | None:
    """``path`` as a :class:`Path` if it is a writable directory or can be created as one
    (its nearest existing ancestor is a writable directory); None stays None."""
    if path is None:
        return None
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"{option}: {str(p)!r} exists and is not a directory")
    a = p
    while not a.exists():
        a = a.parent
    if not a.is_dir():
        raise InputError(f"{option}: {str(a)!r} is not a directory, so {str(p)!r} cannot be created")
    _probe(a, option)
    return p


def _probe(directory: Path, option: str) -> None:
    """Create and remove a file in ``directory``: the only test of writability that also
    holds for the superuser and for special file systems."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=".fembeam-probe-", dir=directory)
        os.close(fd)
        os.remove(tmp)
    except OSError as e:
        raise InputError(f"{option}: cannot write in the directory {str(directory)!r} ({e.strerror})") from None


@contextlib.contextmanager
def atomic_group(paths: Sequence) -> Iterator[list[str]]:
    """:func:`atomic` for several files written together: temporary names for all of
    them, renamed in the order given only once every writer has finished (put an index
    file last); on any failure none of the targets is touched."""
    ps = [Path(p) for p in paths]
    tmps = []
    try:
        for p in ps:
            fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=p.suffix, dir=p.parent if str(p.parent) else ".")
            os.close(fd)
            tmps.append(tmp)
        yield tmps
        umask = os.umask(0)
        os.umask(umask)
        for tmp, p in zip(tmps, ps):
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, p)
    except BaseException:
        for tmp in tmps:
            with contextlib.suppress(OSError):
                os.remove(tmp)
        raise


@contextlib.contextmanager
def atomic(path) -> Iterator[str]:
    """Yield a temporary file name next to ``path``; rename it onto ``path`` on success,
    remove it on any failure (including KeyboardInterrupt)."""
    p = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=p.suffix, dir=p.parent if str(p.parent) else ".")
    os.close(fd)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)      # mkstemp's 0600 would outlive the rename
        os.replace(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.remove(tmp)
        raise
