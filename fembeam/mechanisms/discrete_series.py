"""Discrete -> continuous: A_L, r_max and r_4hinge for arches of N voussoirs.

For each N the limit-analysis LP and the impact QP run on N rigid voussoirs
(:func:`fembeam.analysis.analyze`), and, up to ``exhaustive_max`` voussoirs, the
restricted problem is solved exhaustively; the continuous row uses the refined FE
analysis and the smooth four-hinge optimisation.  As N grows A_L decreases
monotonically (about N^-1.8) to the continuous value; r approaches it with a wobble of
~1e-3 because the hinges of ``u`` snap to the joints: each discrete arch is a
different arch, not an approximation of the continuous one.
"""
from __future__ import annotations

import numpy as np

from ..analysis import analyze
from ..errors import InputError
from ..geometry import MidCurve
from .four_hinge_analysis import SIZE_LIMITS
from .hinge import ROCKING_SIDES
from .mechanism import Mechanism
from .restricted import best_four_hinge_continuous, best_four_hinge_discrete, exhaustive_candidates

__all__ = ["discrete_series", "SERIES_ROWS"]

SERIES_ROWS = 100   # voussoir counts of one series (a small analysis takes ~0.1 s)


def _four_hinge(res) -> bool:
    return res.outcome == "rocking" and len(res.hinges_before) == 4 and all(
        h.side in ROCKING_SIDES for h in res.hinges_before)


def _why_not(res) -> str:
    return ("r_4hinge: the incipient mechanism is not four rotating hinges" if res.outcome == "rocking"
            else f"r_4hinge: outcome {res.outcome}")


def _pre(curve: MidCurve, res) -> Mechanism:
    return Mechanism.from_hinges(curve, res.hinges_before).closing()


def _check(voussoirs, exhaustive_max) -> list[int]:
    """The counts and ``exhaustive_max`` within :data:`SIZE_LIMITS`, checked before any
    computation: at most :data:`SERIES_ROWS` counts whose analyses together cost no more
    than one of the largest allowed discrete arch, and exhaustive searches together no
    more than one at the largest allowed size."""
    try:
        counts = [SIZE_LIMITS["voussoirs"].check(n) for n in voussoirs]
    except TypeError:
        raise InputError(f"the series takes a list of voussoir counts, got {voussoirs!r}") from None
    ex = SIZE_LIMITS["exhaustive"]
    if isinstance(exhaustive_max, bool) or not isinstance(exhaustive_max, (int, np.integer)) \
            or not 0 <= exhaustive_max <= ex.highest:
        raise InputError(f"exhaustive_max must be an integer in [0, {ex.highest}] ({ex.basis}), got {exhaustive_max!r}")
    top = SIZE_LIMITS["voussoirs"].highest
    if not 1 <= len(counts) <= SERIES_ROWS or sum(counts) > top:
        raise InputError(f"a series takes 1 to {SERIES_ROWS} voussoir counts adding up to at most {top:,} "
                         f"voussoirs, got {len(counts)} counts adding up to {sum(counts):,}")
    work = sum(exhaustive_candidates(n + 1) for n in counts if 3 <= n <= exhaustive_max)
    if work > exhaustive_candidates(ex.highest + 1):
        raise InputError(f"the exhaustive searches of this series (counts up to exhaustive_max = {exhaustive_max}) "
                         f"try {work:,} candidates, more than one search on {ex.highest} voussoirs "
                         f"({exhaustive_candidates(ex.highest + 1):,}): lower exhaustive_max or drop counts")
    return counts


def _row(n, res, r4, why: str) -> dict:
    """A row of finite numbers; None where undefined, with the ``reason``."""
    num = {k: (float(v) if v is not None and np.isfinite(v) else None)
           for k, v in (("A_L", res.A_L), ("r_max", res.r), ("r_4hinge", r4))}
    row = {"voussoirs": n, "outcome": res.outcome, **num, "qp_hinges": len(res.hinges_after)}
    if num["r_max"] is None or num["A_L"] is None:
        row["reason"] = f"outcome {res.outcome}: no limit state or no impact"
    elif r4 is None:
        row["reason"] = why
    return row


def discrete_series(curve: MidCurve, voussoirs, exhaustive_max: int = 31) -> list[dict]:
    """Rows ``{"voussoirs", "outcome", "A_L", "r_max", "qp_hinges", "r_4hinge"}`` for each
    N of ``voussoirs`` then ``"continuous"``; a number that is undefined or not computed
    is None and the row's ``reason`` says why.  Sizes are checked first (:func:`_check`)."""
    counts = _check(voussoirs, exhaustive_max)
    rows = []
    for n in counts:
        res = analyze(curve, voussoirs=n, thrust=False)
        r4, why = None, ""
        if not _four_hinge(res):
            why = _why_not(res)
        elif n > exhaustive_max:
            why = f"r_4hinge: exhaustive search only up to {exhaustive_max} voussoirs"
        else:
            r4 = best_four_hinge_discrete(res.impact.disc.joint_s, _pre(curve, res)).r
        rows.append(_row(n, res, r4, why))
    res = analyze(curve, thrust=False)
    r4 = best_four_hinge_continuous(_pre(curve, res)).r if _four_hinge(res) else None
    rows.append(_row("continuous", res, r4, _why_not(res)))
    return rows
