"""Intensity measures of a ground motion: PGA, PGV and the 5 %-damped pseudo-spectral acceleration.

The record is the piecewise-linear signal of :class:`~fembeam.dynamics.GroundMotion` (accelerations
in g, zero outside the samples), and each measure is exact for it:

* ``pga`` (g): the largest ``|a|`` of the samples;
* ``pgv`` (m/s): the largest ``|v|`` of ``v(t) = g * integral of a`` from rest at the first sample
  (``v`` is quadratic between samples: its values at the samples by the trapezoidal rule, and its
  extremum inside each interval where ``a`` changes sign);
* ``sa:T`` (g): ``omega^2 max |u|`` of the linear oscillator ``u'' + 2 zeta omega u' + omega^2 u =
  -a(t)`` at rest at the first sample, ``omega = 2 pi / T``, ``zeta = 0.05``; the state is advanced
  exactly over each step of a grid (the input is linear over a step: the matrix exponential of the
  oscillator augmented with the input and its slope) of at most ``T / 100`` (so a peak between grid
  points is missed by at most ``1 - cos(pi / 100) = 5e-4``), and through ``2 T`` of free
  vibration after the record.  It needs uniformly sampled records.

Each measure is proportional to the scale factor and blind to the sign of the record.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..dynamics.equation import GRAVITY
from ..dynamics.ground import GroundMotion
from ..errors import InputError

__all__ = ["IntensityMeasure", "parse_im", "pga", "pgv", "pseudo_acceleration", "DAMPING", "SA_PERIODS"]

DAMPING = 0.05                    # critical damping ratio of the spectral acceleration
SA_PERIODS = (0.01, 10.0)         # s: periods admitted for sa:T
GRID_PER_PERIOD = 100             # output points per period at least


@dataclass(frozen=True)
class IntensityMeasure:
    """``kind`` ``"pga"`` (g), ``"pgv"`` (m/s) or ``"sa"`` (g, at ``period`` s, 5 % damping).

    Calling it with a :class:`~fembeam.dynamics.GroundMotion` gives the measure of that
    motion.

    Examples
    --------
    :func:`parse_im` returns it:

    >>> import numpy as np
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.intensity import parse_im
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> record = GroundMotion(t, 0.3 * np.sin(2.0 * np.pi * t), name="sine")
    >>> for text in ("pga", "sa:1"):
    ...     im = parse_im(text)
    ...     print(im.name, im.label, f"{im(record):.3f}", im.unit)
    pga PGA 0.300 g
    sa:1 Sa(1 s, 5 %) 0.810 g
    """

    kind: str
    period: float | None = None

    @property
    def name(self) -> str:
        return f"sa:{self.period:g}" if self.kind == "sa" else self.kind

    @property
    def unit(self) -> str:
        return "m/s" if self.kind == "pgv" else "g"

    @property
    def label(self) -> str:
        return f"Sa({self.period:g} s, 5 %)" if self.kind == "sa" else self.kind.upper()

    def __call__(self, ground: GroundMotion) -> float:
        if self.kind == "pga":
            return pga(ground)
        if self.kind == "pgv":
            return pgv(ground)
        return pseudo_acceleration(ground, self.period)


def parse_im(text: str) -> IntensityMeasure:
    """The intensity measure named by a string.

    Parameters
    ----------
    text : str
        ``"pga"`` (g), ``"pgv"`` (m/s) or ``"sa:T"``: the 5 %-damped pseudo-spectral
        acceleration (g) at the period ``T`` (s, in ``SA_PERIODS``).

    Returns
    -------
    IntensityMeasure
        Callable on a ground motion; ``name``, ``unit`` and ``label`` for reports.

    Raises
    ------
    InputError
        Another name, or a period out of range.

    Examples
    --------
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.intensity import parse_im
    >>> im = parse_im("pgv")
    >>> print(im.label, f"{im(GroundMotion.sine(0.3, 0.5)):.4f}", im.unit)
    PGV 0.4684 m/s
    """
    t = str(text).strip().lower()
    if t in ("pga", "pgv"):
        return IntensityMeasure(t)
    if t.startswith("sa:"):
        try:
            T = float(t[3:])
        except ValueError:
            T = math.nan
        lo, hi = SA_PERIODS
        if not (math.isfinite(T) and lo <= T <= hi):
            raise InputError(f"sa:T needs a period T in [{lo:g}, {hi:g}] s, got {text!r}")
        return IntensityMeasure("sa", T)
    raise InputError(f"the intensity measure must be pga, pgv or sa:T (T in s), got {text!r}")


def pga(ground: GroundMotion) -> float:
    """Peak ground acceleration (g)."""
    return float(np.max(np.abs(ground.a)))


def pgv(ground: GroundMotion) -> float:
    """Peak ground velocity (m/s) of the piecewise-linear record, from rest at its first sample."""
    t, a = ground.t, ground.a * GRAVITY
    h = np.diff(t)
    v = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[1:] + a[:-1]))])
    peak = float(np.max(np.abs(v)))
    cross = np.nonzero(a[:-1] * a[1:] < 0)[0]            # a changes sign inside: v has an extremum there
    if cross.size:
        s = a[cross] / (a[cross] - a[cross + 1])          # fraction of the interval where a = 0
        inner = v[cross] + 0.5 * a[cross] * s * h[cross]
        peak = max(peak, float(np.max(np.abs(inner))))
    return peak


def _uniform_step(ground: GroundMotion) -> float:
    h = np.diff(ground.t)
    if not np.allclose(h, h[0], rtol=1e-6, atol=0.0):
        raise InputError(f"{ground.name}: sa:T needs a uniformly sampled record (steps from {h.min():g} to "
                         f"{h.max():g} s)")
    return float(h[0])


def pseudo_acceleration(ground: GroundMotion, period: float, damping: float = DAMPING) -> float:
    """Pseudo-spectral acceleration of a record: ``omega^2 max |u|`` (g).

    ``u`` is the response of the linear oscillator ``u'' + 2 zeta omega u' + omega^2 u =
    -a(t)`` at rest at the first sample, ``omega = 2 pi / T``, advanced exactly over a
    grid of at most ``T / 100`` (the input is linear between samples) and through
    ``2 T`` of free vibration after the record.

    Parameters
    ----------
    ground : GroundMotion
        A uniformly sampled record (g).
    period : float
        The oscillator's period ``T`` (s).
    damping : float, optional
        Its critical damping ratio ``zeta`` (default 0.05).

    Returns
    -------
    float
        The pseudo-spectral acceleration (g), proportional to the record's scale.

    Raises
    ------
    InputError
        A pulse given by its formula (not sampled) or a record not uniformly sampled.

    Examples
    --------
    One cycle of a 0.3 g sine of 1 s, sampled every 5 ms, excites an oscillator of 1 s
    more than a stiffer one of 0.5 s:

    >>> import numpy as np
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.intensity import pseudo_acceleration
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> record = GroundMotion(t, 0.3 * np.sin(2.0 * np.pi * t), name="sine")
    >>> for T in (0.5, 1.0):
    ...     print(f"Sa({T} s) = {pseudo_acceleration(record, T):.3f} g")
    Sa(0.5 s) = 0.486 g
    Sa(1.0 s) = 0.810 g
    """
    from scipy.linalg import expm
    from scipy.signal import lfilter, ss2tf

    if ground.exact is not None and ground.t.size < 10:
        raise InputError(f"{ground.name}: sa:T needs a sampled record, not a pulse of {ground.t.size} samples")
    dt = _uniform_step(ground)
    w = 2.0 * math.pi / float(period)
    sub = max(1, math.ceil(dt * GRID_PER_PERIOD / period))
    h = dt / sub
    a = ground.a
    fine = np.interp(np.arange((a.size - 1) * sub + 1) * h, np.arange(a.size) * dt, a)   # exact: linear
    pad = np.zeros(math.ceil(2.0 * period / h) + 1)
    left, right = np.concatenate([fine[:-1], pad]), np.concatenate([fine[1:], pad])     # a at each step's ends
    # x' = A x + b a(t), a linear over a step: x_(k+1) = Phi x_k + B0 a_left + B1 a_right, exactly
    M = np.zeros((4, 4))
    M[:2, :2] = [[0.0, 1.0], [-w * w, -2.0 * damping * w]]
    M[:2, 2] = [0.0, -1.0]
    M[2, 3] = 1.0
    E = expm(M * h)
    Phi, G1, G2 = E[:2, :2], E[:2, 2:3], E[:2, 3:4] / h
    C, D = np.array([[1.0, 0.0]]), np.zeros((1, 1))
    u = np.zeros(left.size)             # u_k = C x_k, k = 0 .. (x_0 = 0: at rest at the first sample)
    for B, inp in ((G1 - G2, left), (G2, right)):
        num, den = ss2tf(Phi, B, C, D)      # strictly proper: u_k takes the inputs of steps 0 .. k-1
        u += lfilter(num[0], den, inp)
    return float(w * w * np.max(np.abs(u)))
