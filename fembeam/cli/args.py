"""Argument types and option groups shared by the sub-commands."""
from __future__ import annotations

import argparse
import csv
import json
import math
import os

from ..analysis import DEFAULT_ELEMENTS
from ..geometry import CircularArch
from ..analysis.qp import BACKENDS


def finite_float(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return x


def float_list(text: str) -> list[float]:
    """``"a,b,c"`` or a range ``"start:stop:step"`` (stop included)."""
    if ":" in text:
        parts = [finite_float(p) for p in text.split(":")]
        if len(parts) != 3 or parts[2] <= 0 or parts[1] < parts[0]:
            raise argparse.ArgumentTypeError(f"a range is start:stop:step with step > 0, got {text!r}")
        n = int(math.floor((parts[1] - parts[0]) / parts[2] + 1e-9)) + 1
        return [round(parts[0] + i * parts[2], 12) for i in range(n)]
    return [finite_float(p) for p in text.split(",") if p.strip()]


def int_list(text: str) -> list[int]:
    try:
        return [int(p) for p in text.split(",") if p.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated integers, got {text!r}") from None


def add_arch(p: argparse.ArgumentParser, many: bool = False) -> None:
    """Options describing a circular arch (``many``: lists for studies)."""
    g = p.add_argument_group("arch")
    if many:
        g.add_argument("--embrace", type=float_list, default=[157.5], metavar="DEG[,DEG..|A:B:STEP]",
                       help="embrace angle(s) beta in degrees, in (0, 360) (default 157.5)")
        g.add_argument("--t-over-r", type=float_list, default=[0.15], metavar="X[,X..|A:B:STEP]",
                       help="thickness over mid-curve radius, in (0, 2) (default 0.15)")
    else:
        g.add_argument("--embrace", type=finite_float, default=157.5, metavar="DEG",
                       help="embrace angle beta in degrees, in (0, 360) (default 157.5)")
        g.add_argument("--t-over-r", type=finite_float, default=0.15, metavar="X",
                       help="thickness over mid-curve radius t/R, in (0, 2) (default 0.15)")
    g.add_argument("--radius", type=finite_float, default=1.0, metavar="M",
                   help="mid-curve radius R in metres (default 1; r and A_L/g do not depend on it)")
    g.add_argument("--density", type=finite_float, default=1.0, metavar="RHO",
                   help="density (default 1; only scales the impulses)")


def add_solver(p: argparse.ArgumentParser, elements_default: int | None = DEFAULT_ELEMENTS) -> None:
    g = p.add_argument_group("discretisation and solver")
    m = g.add_mutually_exclusive_group()
    m.add_argument("--elements", type=int, default=None, metavar="N",
                   help=f"rigid elements on the continuous arch (default {elements_default})")
    m.add_argument("--voussoirs", type=int, default=None, metavar="N",
                   help="discrete arch of N rigid voussoirs, hinges only at the N+1 joints")
    g.add_argument("--direction", type=int, choices=(1, -1), default=1,
                   help="+1: ground pulse from right to left, arch starts moving left to right (default); -1: mirrored")
    g.add_argument("--backend", choices=BACKENDS, default="clarabel",
                   help="QP solver for the impact (default clarabel: interior point, see docs/solvers.md)")
    g.add_argument("--no-refine", action="store_true",
                   help="keep the incipient mechanism's hinges on the uniform mesh (no continuous refinement)")


def arch_from(args) -> CircularArch:
    return CircularArch.from_ratio(args.embrace, args.t_over_r, radius=args.radius, density=args.density)


def write_outputs(result, args, stem: str, plot) -> None:
    """Write ``result`` (with ``to_dict()`` and ``csv_rows()``) where ``--csv``, ``--plot``
    and ``--out-dir`` (``stem``.csv/.json/.png) ask; ``plot(result, path)`` draws the PNG."""
    csv_path, plot_path, json_path = args.csv, args.plot, None
    if args.out_dir:
        os.makedirs(args.out_dir, exist_ok=True)
        csv_path = csv_path or os.path.join(args.out_dir, f"{stem}.csv")
        plot_path = plot_path or os.path.join(args.out_dir, f"{stem}.png")
        json_path = os.path.join(args.out_dir, f"{stem}.json")
    if csv_path:
        rows = result.csv_rows()
        with open(csv_path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    if json_path:
        with open(json_path, "w") as f:
            json.dump(result.to_dict(), f, indent=1)
    if plot_path:
        plot(result, plot_path)
