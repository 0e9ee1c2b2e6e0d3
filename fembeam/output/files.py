"""Output files: checked before any computation, written atomically, replaced as a whole.

:func:`check_output` rejects, with an :class:`~fembeam.errors.InputError` (exit 2), a path
whose suffix is not allowed, that is a directory, whose name is longer than the file system
allows (:func:`check_name`, also for the names a writer derives from it), or whose parent is
missing or not a writable directory; :func:`check_distinct` two options naming one file.
:func:`atomic` yields a temporary name in the same directory and renames it onto the target
only when the writer has finished, so that an error or an interrupt never leaves a
half-written file; :func:`atomic_group` does it for a set of files (a ParaView series: the
frames and their index) and swaps the whole set in at the end, the renames shielded from
Ctrl-C and SIGTERM (:func:`fembeam.interrupts.deferred`), the files of the set it replaces
that the new one lacks removed after it.  So an interrupted re-run leaves the previous
complete set untouched, never an index pointing at files it deleted.  :func:`atomic_dir` does
it for the files of an output folder (a report, a study's ``--out-dir``): a folder that does
not exist yet is written whole under a temporary name beside it and renamed in at the end, so
an interrupt leaves no empty or partial folder; in an existing folder the set is swapped in
and the files of an earlier set that the new one lacks (``stale``) are removed.

A path that is a symbolic link is written through: the file it points to is replaced and
the link stays.  Temporary names are short (``.NAME.XXXXXXXX.SUF`` with NAME cut to 64
bytes), so a target name the file system accepts always has a temporary name it accepts.
"""
from __future__ import annotations

import contextlib
import fnmatch
import os
import shutil
import tempfile
from pathlib import Path
from typing import Iterator, Mapping, Sequence

from .. import interrupts
from ..errors import InputError

__all__ = ["check_output", "check_dir", "check_name", "check_distinct", "target", "atomic", "atomic_group",
           "atomic_dir",
           "write_table", "PLOT_SUFFIXES"]

PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def check_output(path, option: str, suffixes: Sequence[str] = ()) -> Path | None:
    """``path`` as a :class:`Path` if it can be written (None stays None)."""
    if path is None:
        return None
    p = Path(path)
    if suffixes and p.suffix.lower() not in suffixes:
        raise InputError(f"{option}: expected a file name ending in {' or '.join(suffixes)}, got {str(p)!r}")
    check_name(p, option)
    if p.is_dir():
        raise InputError(f"{option}: {str(p)!r} is a directory")
    t = target(p)
    parent = t.parent if str(t.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{option}: the directory {str(parent)!r} does not exist")
    _probe(parent, option)
    if t.exists() and not os.access(t, os.W_OK):
        raise InputError(f"{option}: {str(p)!r} is not writable")
    return p


def check_name(path, option: str) -> None:
    """InputError if the last part of ``path`` has more bytes than the file system of its
    directory allows in a name (NAME_MAX, 255 on most), or the whole path more than PATH_MAX."""
    p = Path(path)
    parent = p.parent if str(p.parent) else Path(".")
    name_max, path_max = _limit(parent, "PC_NAME_MAX", 255), _limit(parent, "PC_PATH_MAX", 4096)
    n = len(os.fsencode(p.name))
    if n > name_max:
        raise InputError(f"{option}: the file name {_short(p.name)!r} has {n} bytes; at most {name_max} are allowed")
    if len(os.fsencode(os.path.abspath(p))) >= path_max:
        raise InputError(f"{option}: the path {_short(str(p))!r} is longer than the {path_max} bytes allowed")


def _short(text: str) -> str:
    return text if len(text) <= 60 else text[:28] + "..." + text[-28:]


def _limit(directory: Path, name: str, default: int) -> int:
    """``os.pathconf`` of the nearest existing ancestor of ``directory`` (``default`` when unknown)."""
    d = directory
    while not d.exists() and d != d.parent:
        d = d.parent
    try:
        value = os.pathconf(d, name)
    except (OSError, ValueError, AttributeError):
        return default
    return value if value and value > 0 else default


def check_distinct(outputs: Mapping[str, object]) -> None:
    """InputError if two options of ``outputs`` (option -> path, None ignored) name the same
    file: the same path after following links, or one existing file (hard links)."""
    seen: dict = {}
    for option, path in outputs.items():
        if path is None:
            continue
        keys = [os.path.realpath(path)]
        with contextlib.suppress(OSError):
            st = os.stat(path)
            keys.append((st.st_dev, st.st_ino))
        for key in keys:
            if key in seen and seen[key] != option:
                raise InputError(f"{seen[key]} and {option} name the same file {str(path)!r}: give each its own")
            seen.setdefault(key, option)


def target(path) -> Path:
    """The file written for ``path``: the file a symbolic link points to (the link stays), else ``path``."""
    p = Path(path)
    return Path(os.path.realpath(p)) if p.is_symlink() else p


def check_dir(path, option: str) -> Path | None:
    """``path`` as a :class:`Path` if it is a writable directory or can be created as one
    (its nearest existing ancestor is a writable directory); None stays None."""
    if path is None:
        return None
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"{option}: {str(p)!r} exists and is not a directory")
    for part in (p, *p.parents):
        if str(part) not in ("", ".", "/") and not part.exists():
            check_name(part, option)
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


def _temporary(p: Path) -> str:
    """A new empty file next to ``p``, named ``.NAME.XXXXXXXX.SUF`` (NAME cut to 64 bytes: the
    name stays short however long the target's is; the suffix kept for writers that read it)."""
    name = os.fsencode(p.name)[:64].decode(errors="ignore")
    suffix = p.suffix if len(p.suffix) <= 16 else ""
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=suffix, dir=p.parent if str(p.parent) else ".")
    os.close(fd)
    return tmp


@contextlib.contextmanager
def atomic_group(paths: Sequence, replaces: Sequence = ()) -> Iterator[list[str]]:
    """:func:`atomic` for a set of files written together: temporary names for all of them,
    swapped in (renamed in the order given: put an index file last) only once every writer
    has finished, with Ctrl-C and SIGTERM held back until the swap is done; then the files of
    ``replaces`` (the previous set) that are not in the new one are removed.  On any failure
    before the swap none of the targets is touched and the temporary files are removed."""
    ps = [target(p) for p in paths]
    tmps: list[str] = []
    try:
        for p in ps:
            tmps.append(_temporary(p))
        yield tmps
        umask = os.umask(0)
        os.umask(umask)
        with interrupts.deferred():
            for tmp in tmps:
                os.chmod(tmp, 0o666 & ~umask)      # mkstemp's 0600 would outlive the rename
            for i, (tmp, p) in enumerate(zip(tmps, ps)):
                os.replace(tmp, p)
                tmps[i] = None
            kept = {os.path.realpath(p) for p in ps}
            for old in replaces:
                if os.path.realpath(old) not in kept:
                    with contextlib.suppress(OSError):
                        os.remove(old)
    except BaseException:
        for tmp in tmps:
            if tmp is not None:
                with contextlib.suppress(OSError):
                    os.remove(tmp)
        raise


@contextlib.contextmanager
def atomic(path) -> Iterator[str]:
    """Yield a temporary file name next to ``path`` (next to the file it links to, for a
    symbolic link); rename it onto that file on success, remove it on any failure
    (including KeyboardInterrupt)."""
    with atomic_group([path]) as (tmp,):
        yield tmp


@contextlib.contextmanager
def atomic_dir(directory, names: Sequence[str], stale: Sequence[str] = ()) -> Iterator[list[str]]:
    """Temporary paths for the files ``names`` of the folder ``directory``, swapped in together
    once the writer has finished (see the module docstring); ``stale``: glob patterns of the
    files an earlier set may have left there (``motion_*.png``), removed after the swap unless
    the new set has them.  Nothing is left behind on any failure before the swap."""
    d = Path(directory)
    if d.is_dir():
        new = set(names)
        old = [str(d / n) for n in sorted(os.listdir(d))
               if n not in new and any(fnmatch.fnmatchcase(n, pat) for pat in stale)]
        with atomic_group([d / n for n in names], replaces=old) as tmps:
            yield tmps
        return
    d.parent.mkdir(parents=True, exist_ok=True)
    tmpdir = tempfile.mkdtemp(prefix=f".{os.fsencode(d.name)[:64].decode(errors='ignore')}.",
                              dir=d.parent if str(d.parent) else ".")
    try:
        yield [os.path.join(tmpdir, n) for n in names]
        umask = os.umask(0)
        os.umask(umask)
        with interrupts.deferred():
            os.chmod(tmpdir, 0o777 & ~umask)       # mkdtemp's 0700 would outlive the rename
            for n in names:
                os.chmod(os.path.join(tmpdir, n), 0o666 & ~umask)
            os.rename(tmpdir, d)
    except BaseException:
        shutil.rmtree(tmpdir, ignore_errors=True)
        raise


def write_table(path, columns: Mapping[str, Sequence], integer: Sequence[str] = (), chunk: int = 50_000) -> None:
    """CSV of equal-length ``columns`` (header: their names; the ``integer`` ones written as
    integers, the others as floats), written atomically and streamed ``chunk`` rows at a
    time: memory does not grow with the number of rows (a 10^6-row history)."""
    import csv

    import numpy as np

    names = list(columns)
    arrays = {k: np.asarray(columns[k]) for k in names}
    n = len(arrays[names[0]]) if names else 0
    with atomic(path) as tmp, open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(names)
        for a in range(0, n, chunk):
            cols = [(arrays[k][a:a + chunk].astype(int) if k in integer else arrays[k][a:a + chunk].astype(float))
                    .tolist() for k in names]
            w.writerows(zip(*cols))
