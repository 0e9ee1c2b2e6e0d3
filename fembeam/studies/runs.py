"""What every study shares about its runs: default times, the onset of motion, bounds, JSON.

* :data:`DT`: the default time step of the multi-block simulation (s), that of ``fembeam simulate``;
* :data:`T_END_FACTOR`: the default free time after a ground motion, in ``sqrt(L/g)``;
* :func:`onset_amplitude`: the smallest scale of a ground motion that can set the member moving;
* :func:`check_runs`: the bounds of :mod:`fembeam.limits` on the longest run of a study;
* :func:`json_safe`: a result as JSON can hold it (null for undefined or non-finite numbers).

Units: accelerations in g (positive along +x), times in s.
"""
from __future__ import annotations

import math

import numpy as np

from ..dynamics.ground import GroundMotion
from ..geometry import MidCurve

__all__ = ["DT", "T_END_FACTOR", "onset_amplitude", "check_runs", "json_safe"]

DT = 1e-3               # default time step of the multi-block simulation (s), that of fembeam simulate
T_END_FACTOR = 20.0     # default free time after a ground motion, in sqrt(L/g)


def onset_amplitude(A: dict, unit: GroundMotion) -> float:
    """The smallest factor that lets ``unit`` set the member moving.

    Parameters
    ----------
    A : dict
        ``A_L`` of the member (g), keyed by direction ``1`` and ``-1``.
    unit : GroundMotion
        The ground motion at factor 1 (accelerations in g).

    Returns
    -------
    float
        ``min(A_L(-1) / max(a), A_L(+1) / max(-a))`` over the signs present in ``unit``; inf if
        none.
    """
    pos, neg = float(np.max(unit.a)), float(np.max(-unit.a))
    cands = [A[-1] / pos if pos > 0 else math.inf, A[1] / neg if neg > 0 else math.inf]
    return float(min(cands))


def check_runs(model: str, dt: float | None, duration: float, curve: MidCurve, voussoirs: int | None,
               elements: int | None) -> None:
    """Refuse a study whose longest run exceeds the bounds of :mod:`fembeam.limits`.

    Parameters
    ----------
    model : str
        ``"rock"``, ``"simulate"`` or ``"auto"``; the last two are bounded in steps too.
    dt : float or None
        The time step (s) of the multi-block simulation (None for rock).
    duration : float
        The longest run's simulated time (s), at most ``MAX_DURATION``.
    curve : MidCurve
        The member.
    voussoirs, elements : int or None
        Its pieces.

    Raises
    ------
    InputError
        A bound is exceeded.
    """
    from ..geometry import StraightMember
    from ..limits import bodies, check_duration, check_steps
    check_duration(duration, "t_end")
    if model != "rock":
        check_steps(dt, duration, bodies(voussoirs, elements, isinstance(curve, StraightMember)), "dt")


def json_safe(x):
    """``x`` with dict keys as strings, sequences as lists, NumPy scalars as Python's.

    Parameters
    ----------
    x : object
        A result (nested dicts, lists, tuples, arrays, numbers).

    Returns
    -------
    object
        The same with non-finite floats as None (JSON's null).
    """
    if isinstance(x, dict):
        return {str(k): json_safe(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [json_safe(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x
