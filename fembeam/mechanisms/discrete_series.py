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
from ..geometry import MidCurve
from .mechanism import Mechanism
from .restricted import best_four_hinge_continuous, best_four_hinge_discrete

__all__ = ["discrete_series"]


def _pre(curve: MidCurve, res) -> Mechanism:
    return Mechanism.from_hinges(curve, res.hinges_before).closing()


def discrete_series(curve: MidCurve, voussoirs, exhaustive_max: int = 31) -> list[dict]:
    """Rows ``{"voussoirs", "A_L", "r_max", "qp_hinges", "r_4hinge"}`` for each N of
    ``voussoirs`` then ``"continuous"`` (``r_4hinge`` None where not computed)."""
    rows = []
    for n in voussoirs:
        res = analyze(curve, voussoirs=int(n))
        r4 = None
        if res.outcome == "rocking" and int(n) <= exhaustive_max and len(res.hinges_before) == 4:
            r4 = best_four_hinge_discrete(res.impact.disc.joint_s, _pre(curve, res)).r
        rows.append({"voussoirs": int(n), "A_L": res.A_L, "r_max": res.r,
                     "qp_hinges": len(res.hinges_after), "r_4hinge": r4})
    res = analyze(curve)
    r4 = None
    if res.outcome == "rocking" and len(res.hinges_before) == 4:
        r4 = best_four_hinge_continuous(_pre(curve, res)).r
    rows.append({"voussoirs": "continuous", "A_L": res.A_L, "r_max": res.r,
                 "qp_hinges": len(res.hinges_after), "r_4hinge": r4})
    return [{k: (float(v) if isinstance(v, (float, np.floating)) else v) for k, v in r.items()} for r in rows]
