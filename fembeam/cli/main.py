"""The parser and the entry point: one sub-command per module of this package."""
from __future__ import annotations

import argparse
import os
import signal
import sys
import threading

from ..errors import FembeamError, InputError


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, no usage dump
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    from . import analyze, collapse_scale, convergence, impact, min_thickness, report, rock, spectrum, sweep

    p = _Parser(prog="fembeam", description="Rocking masonry arches: limit analysis, impact, impulse line.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for mod in (analyze, min_thickness, convergence, sweep, impact, report, rock, spectrum, collapse_scale):
        mod.register(sub)
    return p


class Terminated(BaseException):
    """SIGTERM, turned into an exception so that open outputs are cleaned up."""


def _terminate(signum, frame):
    raise Terminated()


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _terminate)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("fembeam: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("fembeam: terminated", file=sys.stderr)
        return 143
    except InputError as e:
        print(f"fembeam: error: {e}", file=sys.stderr)
        return 2
    except FembeamError as e:
        print(f"fembeam: {type(e).__name__}: {e}", file=sys.stderr)
        return 3
    except BrokenPipeError:  # e.g. `fembeam analyze | head`: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
