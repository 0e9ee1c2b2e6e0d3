"""Input files read with bounds: one regular file, its size checked before a byte is read.

Every file fembeam reads on a user's word (a surveyed mid-curve, a ground-motion record, a
study's journal) goes through :func:`read_bytes` or :func:`read_text`:

* only a regular file is read (a FIFO, a device such as ``/dev/zero``, a directory or a
  socket is refused: it could block for ever or never end); the file is opened without
  blocking and checked again once open, so it cannot be swapped for a FIFO in between;
* its size is checked against a cap *before* reading (a sparse file of several GB is
  refused at once, nothing is allocated), and at most ``cap + 1`` bytes are read, so a file
  growing meanwhile cannot exceed the cap either;
* :func:`read_text` decodes UTF-8, strictly or with replacement characters.

Errors are :class:`~fembeam.errors.InputError` (exit 2, one line) naming the file and what
is allowed.  The caps per kind of file are the callers' (:data:`MAX_INPUT_BYTES` by default).
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import InputError

__all__ = ["MAX_INPUT_BYTES", "read_bytes", "read_text", "megabytes"]

MAX_INPUT_BYTES = 64 * 2 ** 20   # 64 MiB: a mid-curve or a record file (a record of 10^6 samples is ~16 MB)


def megabytes(n: int) -> str:
    """``n`` bytes as MB for messages (``64 MB``)."""
    mb = n / 2 ** 20
    return f"{mb:.0f} MB" if mb >= 10 else f"{mb:.3g} MB"


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def read_bytes(path, what: str, cap: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of the regular file ``path`` (``what`` names it in messages: "the mid-curve
    file"), at most ``cap`` of them; InputError otherwise."""
    name = str(path)
    try:
        st = os.stat(path)
    except FileNotFoundError:
        raise InputError(f"cannot read {what} {name!r}: no such file") from None
    except OSError as e:
        raise InputError(f"cannot read {what} {name!r}: {e.strerror or e}") from None
    _check(st, what, name, cap)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except OSError as e:
        raise InputError(f"cannot read {what} {name!r}: {e.strerror or e}") from None
    try:
        _check(os.fstat(fd), what, name, cap)          # the file opened is the file checked
        chunks, size = [], 0
        while size <= cap:
            chunk = os.read(fd, min(1 << 20, cap + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise InputError(f"cannot read {what} {name!r}: {e.strerror or e}") from None
    finally:
        os.close(fd)
    if size > cap:
        raise InputError(f"{what} {name!r} grew past {megabytes(cap)} while it was read; at most {megabytes(cap)}")
    return b"".join(chunks)


def _check(st: os.stat_result, what: str, name: str, cap: int) -> None:
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{what} {name!r} is {_kind(st.st_mode)}: give a regular file")
    if st.st_size > cap:
        raise InputError(f"{what} {name!r} has {megabytes(st.st_size)}; at most {megabytes(cap)} is read")


def read_text(path, what: str, cap: int = MAX_INPUT_BYTES, errors: str = "strict", kind: str = "",
              expect: str = "") -> str:
    """:func:`read_bytes` decoded as UTF-8 (``errors="replace"``: undecodable bytes become
    U+FFFD); with ``errors="strict"`` a file that is not UTF-8 text (or holds NUL bytes) is
    an InputError: "is not a text ``kind`` file (expected ``expect``)"."""
    data = read_bytes(path, what, cap)
    try:
        text = data.decode("utf-8", errors=errors)
        binary = errors == "strict" and "\x00" in text
    except UnicodeDecodeError:
        binary = True
    if binary:
        raise InputError(f"{what} {str(path)!r} is not a text {kind + ' ' if kind else ''}file"
                         f"{' (expected ' + expect + ')' if expect else ''}")
    return text


def is_regular(path) -> bool:
    """Whether ``path`` names a regular file (following links), without opening it."""
    try:
        return stat.S_ISREG(os.stat(Path(path)).st_mode)
    except OSError:
        return False
