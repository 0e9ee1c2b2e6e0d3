"""Mesh sizes of the analyses: the default and the limits of the number of rigid elements of
the continuous arch, and of the voussoirs of a discrete arch, checked once for every entry
point (:func:`~fembeam.analysis.pipeline.analyze`,
:func:`~fembeam.analysis.thickness.minimum_thickness`)."""
from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["DEFAULT_ELEMENTS", "MIN_ELEMENTS", "MIN_VOUSSOIRS", "MAX_ELEMENTS", "check_count"]

DEFAULT_ELEMENTS = 200
MIN_ELEMENTS = 4
MIN_VOUSSOIRS = 1
MAX_ELEMENTS = 200_000     # analyze at 2 10^5 elements: 1.1 GB, 5.6 s (fresh process; linear): a run stays under ~1.1 GB


def check_count(n, name: str, lowest: int) -> int:
    """``n`` as an int when it is an integer in ``[lowest, MAX_ELEMENTS]``; InputError naming
    the count (``name``: ``"elements"`` or ``"voussoirs"``) and the range otherwise."""
    if not isinstance(n, (int, np.integer)) or isinstance(n, bool) or not lowest <= n <= MAX_ELEMENTS:
        raise InputError(f"the number of {name} must be an integer in [{lowest}, {MAX_ELEMENTS}], got {n!r}")
    return int(n)
