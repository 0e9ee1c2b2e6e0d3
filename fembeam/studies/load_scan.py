"""The critical position of a live load: one point load moved across the span.

For each position ``x`` (m from the left springing of the mid-curve) of a single downward
load ``P`` (kN per metre of width) the load factor is computed
(:func:`~fembeam.analysis.load_factor.load_factor`: the multiple of ``P`` at collapse with the
dead loads at their values); the smallest over the positions, and where, is the answer an
assessor asks for first (the critical position of an axle).  On a voussoir arch every
position shares one factorised equilibrium operator: each position costs one small LP.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..analysis.load_factor import LoadFactor, load_factor
from ..analysis.loads import PointLoads
from ..errors import InputError
from ..fem import discretize, uniform_nodes
from ..geometry import MidCurve
from ..geometry.asbuilt import span_of
from ..analysis.sizes import DEFAULT_ELEMENTS, MIN_ELEMENTS, MIN_VOUSSOIRS, check_count

__all__ = ["LoadScan", "load_scan", "MAX_POSITIONS"]

MAX_POSITIONS = 2000


@dataclass
class LoadScan:
    """Load factors of one load ``P`` (kN/m) at the positions ``x`` (m): ``factor`` (NaN where
    ``status`` is not ``"ok"``), the smallest (``critical``: index) and its mechanism.

    Examples
    --------
    :func:`load_scan` returns it; a point load of 1 kN/m at five positions (m) on the
    paper's arch of 12 voussoirs (none collapses it at a springing):

    >>> import fembeam
    >>> from fembeam.studies.load_scan import load_scan
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> scan = load_scan(arch, 1.0, positions=5, voussoirs=12)
    >>> print([f"{x:.3f}" for x in scan.x])
    ['0.000', '0.490', '0.981', '1.471', '1.962']
    >>> i = scan.critical
    >>> print(f"at x = {scan.x[i]:.3f} m: {scan.min_factor:.3f} x {scan.P:g} kN/m;",
    ...       scan.status[0])
    at x = 0.981 m: 3.635 x 1 kN/m; no_mechanism
    """

    geometry: dict
    P: float
    mode: str
    n: int
    x: np.ndarray
    factor: np.ndarray
    status: list
    results: list = field(repr=False, default_factory=list)

    @property
    def critical(self) -> int | None:
        ok = np.isfinite(self.factor)
        return int(np.nanargmin(self.factor)) if ok.any() else None

    @property
    def min_factor(self) -> float | None:
        i = self.critical
        return None if i is None else float(self.factor[i])

    def to_dict(self) -> dict:
        i = self.critical
        res: LoadFactor | None = None if i is None else self.results[i]
        return {
            "geometry": self.geometry, "mode": self.mode, "elements": self.n,
            "load": {"P": self.P, "unit": "kN/m"},
            "min_load_factor": self.min_factor,
            "load_factor": self.min_factor,             # the smallest: the load factor of the moving load
            "critical_x": None if i is None else float(self.x[i]),
            "collapse_load_kN_per_m": None if i is None else float(self.factor[i] * self.P),
            "load_mechanism": [] if res is None else [h.to_dict() for h in res.hinges],
            "positions": [{"x": float(x), "load_factor": None if not np.isfinite(f) else float(f), "outcome": s}
                          for x, f, s in zip(self.x, self.factor, self.status)],
            "units": {"x": "m from the left springing", "P": "kN/m", "load_factor": "multiple of P"},
        }

    def csv_rows(self) -> list[dict]:
        return [{"x_m": float(x), "load_factor": "" if not np.isfinite(f) else repr(float(f)),
                 "collapse_load_kN_per_m": "" if not np.isfinite(f) else repr(float(f * self.P)), "outcome": s}
                for x, f, s in zip(self.x, self.factor, self.status)]


def load_scan(curve: MidCurve, P: float, positions: int = 101, voussoirs: int | None = None,
              elements: int | None = None, continuum: bool | None = None, verify: bool = True,
              progress=None) -> LoadScan:
    """Load factor of a point load ``P`` (kN/m) at ``positions`` equally spaced positions from
    the left springing to the right one (the mid-curve's span), on ``voussoirs`` or
    ``elements`` (default 200; the continuum's sections checked unless ``continuum`` is False).
    ``progress(i, n)``: called after each position."""
    if isinstance(positions, bool) or not isinstance(positions, (int, np.integer)) \
            or not 2 <= positions <= MAX_POSITIONS:
        raise InputError(f"positions must be an integer from 2 to {MAX_POSITIONS}, got {positions!r}")
    if voussoirs is not None and elements is not None:
        raise InputError("give either elements (continuous arch) or voussoirs (discrete arch), not both")
    mode = "voussoirs" if voussoirs is not None else "continuous"
    n = (check_count(voussoirs, "voussoirs", MIN_VOUSSOIRS) if voussoirs is not None
         else check_count(DEFAULT_ELEMENTS if elements is None else elements, "elements", MIN_ELEMENTS))
    if continuum is None:
        continuum = mode == "continuous"
    _, span = span_of(curve)
    xs = np.linspace(0.0, span, positions)
    nodes = uniform_nodes(curve, n)
    disc = None if continuum else discretize(curve, nodes)
    factor, status, results = np.full(positions, np.nan), [], []
    for i, live in enumerate(PointLoads.each(curve, xs, P)):
        lf = load_factor(curve, live, nodes=nodes, continuum=continuum, verify=verify, disc=disc)
        results.append(lf)
        status.append(lf.status)
        if lf.status == "ok":
            factor[i] = lf.value
        if progress is not None:
            progress(i + 1, positions)
    desc = curve.describe() if hasattr(curve, "describe") else {}
    return LoadScan(desc, float(P), mode, n, xs, factor, status, results)
