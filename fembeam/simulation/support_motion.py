"""A prescribed movement of the supports in the multi-block simulation (``simulate --support-motion``).

The two abutments are kinematic bodies: each moves by a prescribed translation ``u(t)`` (m, no
rotation) at the velocity ``du/dt`` (m/s), whatever the arch does; the contacts of a springing
with its abutment use that velocity in their opening and sliding rates (the impact and smooth
projections) and its position in their gaps.  The displacement is ``delta(t) = rate (t - t_0)``
(m), held at ``up_to`` once reached (a motion :meth:`held` from the start: the supports already
displaced by ``start`` and not moving); the supports move by ``delta`` times the unit vectors of a
:class:`~fembeam.analysis.supports.Movement` (``spread``: each outward by ``delta / 2``;
``settle``: the right one down by ``delta``; ``move``: one of them along a direction), the same
displacement as ``fembeam supports``'s, so the two are compared at equal ``delta``.  The impulses
the arch gives the abutments over the steps, divided by the time, are its mean forces on them:
the thrust ``H`` (positive outward) and the vertical load ``V`` (positive downward), kN/m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["SupportMotion", "SUPPORT_COLUMNS"]

SUPPORT_COLUMNS = ("support_displacement", "H_left", "V_left", "H_right", "V_right")


def _rate(rate) -> float:
    try:
        rate = float(rate)
    except (TypeError, ValueError):
        raise InputError(f"the support rate must be a number of m/s, got {rate!r}") from None
    if not (math.isfinite(rate) and rate > 0):
        raise InputError(f"the support rate must be a finite number of m/s > 0, got {rate!r}")
    return rate


def _up_to(up_to) -> float | None:
    if up_to is None:
        return None
    try:
        up_to = float(up_to)
    except (TypeError, ValueError):
        raise InputError(f"the support displacement limit must be a number of m, got {up_to!r}") from None
    if not (math.isfinite(up_to) and up_to > 0):
        raise InputError(f"the support displacement limit must be a finite number of m > 0, got {up_to!r}")
    return up_to


@dataclass(frozen=True)
class SupportMotion:
    """The displacements of the left and right supports per unit ``delta`` (``left``, ``right``:
    (2,) m/m), the ``rate`` of ``delta`` (m/s) and the displacement ``up_to`` (m; None: never
    held) at which it stops; ``kind`` names it (``spread``, ``settle``, ``move`` or ``rigid``).

    Parameters
    ----------
    kind : str
        ``"spread"``, ``"settle"``, ``"move"`` (as :class:`~fembeam.analysis.supports.Movement`)
        or ``"rigid"`` (both supports together along ``direction``: a translation of the ground).
    left, right : tuple of float
        Unit displacements of the supports (m per m of ``delta``).
    rate : float
        ``d delta / dt`` (m/s), > 0.
    up_to : float or None
        ``delta`` (m) held from ``(up_to - start) / rate`` after the start on.
    start : float
        ``delta`` (m) at the start (0: from the supports' places at rest).
    """

    kind: str
    left: tuple
    right: tuple
    rate: float
    up_to: float | None = None
    start: float = 0.0

    @classmethod
    def of(cls, kind: str, rate: float, *, vector=None, left: bool = False,
           up_to: float | None = None) -> "SupportMotion":
        """The movement ``kind`` of ``fembeam supports`` (``"spread"``, ``"settle"``, ``"move"``
        with ``vector`` ``(dx, dy)``, only its direction counts; ``left``: the left support moves)
        at ``rate`` (m/s) up to ``up_to`` (m); InputError on bad input."""
        from ..analysis.supports import Movement
        mv = Movement.of(kind, vector, left=left)
        vL, vR = mv.velocities
        return cls(kind, tuple(map(float, vL)), tuple(map(float, vR)), _rate(rate), _up_to(up_to))

    @classmethod
    def rigid(cls, direction, rate: float, up_to: float | None = None) -> "SupportMotion":
        """Both supports moved together along the unit vector of ``direction`` ``(dx, dy)``: the
        ground translated (equivalent to a ground motion)."""
        d = np.asarray(direction, float)
        size = float(np.hypot(*d)) if d.shape == (2,) else math.nan
        if not (math.isfinite(size) and size > 0):
            raise InputError(f"the direction must be two finite numbers, not both zero, got {direction!r}")
        d = tuple(map(float, d / size))
        return cls("rigid", d, d, _rate(rate), _up_to(up_to))

    def __post_init__(self):
        if not (math.isfinite(self.start) and 0.0 <= self.start
                and (self.up_to is None or self.start <= self.up_to)):
            raise InputError(f"the support displacement at the start must be a finite number of m in "
                             f"[0, up_to], got {self.start!r}")

    @classmethod
    def held(cls, kind: str, at: float, *, vector=None, left: bool = False) -> "SupportMotion":
        """The supports of the movement ``kind`` (as :meth:`of`) displaced by ``at`` (m) from the
        start on and held there: a run from a state on displaced supports (``q0``), whose
        potential energy and overturning are measured from that state (``rate`` is then
        irrelevant: 1 m/s)."""
        m = cls.of(kind, 1.0, vector=vector, left=left, up_to=at)
        return cls(m.kind, m.left, m.right, m.rate, m.up_to, m.up_to)

    @property
    def is_held(self) -> bool:
        """The supports displaced from the start and not moving."""
        return self.up_to is not None and self.start == self.up_to

    @property
    def hold_after(self) -> float:
        """Time (s) after the start at which ``delta`` reaches ``up_to`` (inf: never)."""
        return math.inf if self.up_to is None else (self.up_to - self.start) / self.rate

    def displacement(self, elapsed) -> np.ndarray:
        """``delta`` (m) at the times ``elapsed`` (s) after the start."""
        e = np.maximum(np.asarray(elapsed, float), 0.0)
        return self.start + self.rate * np.minimum(e, self.hold_after)

    def supports_at_start(self) -> np.ndarray:
        """``(2, 2)``: the displacements (m) of the left and right supports at the start."""
        return self.start * np.array([self.left, self.right])

    def velocities(self) -> np.ndarray:
        """``(2, 3)``: the velocities ``vx, vy, omega`` (m/s, rad/s) of the left and right supports
        while they move."""
        out = np.zeros((2, 3))
        out[0, :2] = self.left
        out[1, :2] = self.right
        return self.rate * out

    def describe(self) -> dict:
        return {"kind": self.kind, "left_per_m": list(self.left), "right_per_m": list(self.right),
                "rate_m_per_s": None if self.is_held else self.rate, "up_to_m": self.up_to,
                "start_m": self.start}
