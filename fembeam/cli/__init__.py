"""``fembeam`` command line: ``fembeam <command> --help`` for each command.  The modules
here parse arguments, call one function of the library and print or write its result.

The commands run BLAS/LAPACK on one thread unless ``OPENBLAS_NUM_THREADS`` says otherwise
(set before NumPy loads OpenBLAS): their dense kernels are small or banded, and a second
thread only spins (measured on ``analyze --elements 100000``, four runs interleaved with
two threads: 2.4-2.8 s of CPU instead of 3.2-4.2 s, the stages 0.2-0.4 s shorter in three)."""
import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from .main import build_parser, main  # noqa: E402  (after the thread count is set)

__all__ = ["main", "build_parser"]
