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

__all__ = ["check_output", "atomic"]


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
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"{option}: the directory {str(parent)!r} is not writable")
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(f"{option}: {str(p)!r} is not writable")
    return p


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
