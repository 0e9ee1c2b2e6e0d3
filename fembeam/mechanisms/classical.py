"""The classical impact model of De Lorenzis, DeJong and Ochsendorf (2007), ref. [27].

Two assumptions (Sect. 1 and Fig. 11a of the paper): (i) the hinges after the impact
are the mirror image, about the vertical symmetry axis, of those closing at the
impact; (ii) the resultant impulses at the sections of the closing hinges ``C`` pass
through the points ``C-bar`` opposite them across the thickness.  (ii) is four
conditions on the impulse line, which fix ``alpha'`` and the impulses
(:func:`fembeam.mechanisms.impulse_line.impulse_line_through`), hence ``r = Lambda'/Lambda
(alpha'/alpha)^2``.  The line need not pass through the new hinges: where it does not,
compressive impulses act inside those sections and resist their opening (not
kinematically admissible; the paper's green crosses).  When the mirrored hinges are
the points ``C-bar`` themselves (Oppenheim's arch at 150 deg) the model coincides
with the four-hinge model of Sect. 4.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .energy import post_impact
from .impulse_line import ImpulseLine, impulse_line_through, sections_union
from .mechanism import Mechanism

__all__ = ["ClassicalResult", "classical_impact"]


@dataclass
class ClassicalResult:
    """``after`` (mirrored hinges), ``alpha_ratio = alpha'/alpha``, ``r`` and the line.

    Examples
    --------
    :func:`classical_impact` returns it; the paper's mechanism closing, its impulse
    line checked at 200 sections, goes on along the mirrored hinges (deg):

    >>> from fembeam.mechanisms.classical import classical_impact
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> before = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> res = classical_impact(before, 200)
    >>> print([f"{a:g}" for a in res.after.angles_deg()])
    ['0', '39.375', '105', '157.5']
    >>> print(f"r = {res.r:.4f} (energy model {res.r_energy:.4f}),",
    ...       f"alpha'/alpha = {res.alpha_ratio:.4f}")
    r = 0.6587 (energy model 0.6012), alpha'/alpha = 1.8152
    """

    after: Mechanism
    alpha_ratio: float
    r: float
    line: ImpulseLine
    r_energy: float     # the energy model's r (15)-(17) for the same mirrored hinges


def classical_impact(before: Mechanism, sections, alpha: float | None = None) -> ClassicalResult:
    """Classical model for an arch arriving along ``-before`` (``alpha``: the pre-impact
    rate, default the closing sense ``-compatible_sign``)."""
    if alpha is None:
        alpha = -before.compatible_sign()
    pre = before.with_alpha(alpha)
    after = before.mirrored().with_alpha(1.0)
    bar = before.opposite()
    hs = np.asarray(bar.s, float)
    sec = sections_union(before.curve, hs, after.s, sections)
    line = impulse_line_through(pre, after, hs, bar.pivot_y(), sec)
    fig = post_impact(pre, after)
    r = fig.Lambda_after * line.alpha_ratio**2 / fig.Lambda
    # the model assumes motion along the mirrored mechanism: report whether alpha'
    # has the sign that opens its hinges
    sgn = after.compatible_sign()
    line.extra = {"opens_mirrored_hinges": bool(sgn != 0 and line.alpha_ratio * sgn > 0),
                  "Lambda": fig.Lambda, "Lambda_after": fig.Lambda_after}
    return ClassicalResult(after, line.alpha_ratio, float(r), line, fig.r)
