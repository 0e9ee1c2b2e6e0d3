"""Momenta, kinetic energy and the closed-form four-hinge impact (Sect. 4.2, (7), (14)-(17)).

The inertia integrals are exact for any :class:`~fembeam.geometry.MidCurve` (Gauss
quadrature of :meth:`MidCurve.inertia_densities` over each piece), so the figures
here are the continuous-arch values: ``lambda`` (load factor of a mechanism),
``Lambda``, ``Gamma`` and ``r = Gamma^2 / (Lambda Lambda')``.  Every field is a
:class:`~fembeam.mechanisms.mechanism.Mechanism` moving at its rate ``alpha``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, SolverError
from .mechanism import Mechanism

__all__ = ["product", "momenta", "load_factor", "restitution", "ImpactFigures", "post_impact",
           "optimise_load_factor"]

MOMENTA_CHUNK = 50_000   # pieces per quadrature call of :func:`momenta` (bounds its memory)


def _same_curve(a: Mechanism, b: Mechanism):
    if a.curve is not b.curve and a.curve != b.curve:
        raise InputError("the two mechanisms belong to different members")
    return a.curve


def product(a: Mechanism, b: Mechanism) -> float:
    """Momentum pairing ``int rho vel_a . vel_b dA`` (so ``2K = product(a, a)``)."""
    curve = _same_curve(a, b)
    br = np.unique(a._breaks()) if a is b else np.union1d(a._breaks(), b._breaks())
    mid = 0.5 * (br[:-1] + br[1:])
    ma = a.motion_at(mid)
    mb = ma if a is b else b.motion_at(mid)
    m, S, J = curve.segment_inertia(br[:-1], br[1:])
    kS = np.array([-S[1], S[0]])
    return float(np.sum(m * (ma[:, 0] * mb[:, 0] + ma[:, 1] * mb[:, 1])
                        + ma[:, 2] * (mb[:, 0] * kS[0] + mb[:, 1] * kS[1])
                        + mb[:, 2] * (ma[:, 0] * kS[0] + ma[:, 1] * kS[1])
                        + ma[:, 2] * mb[:, 2] * J))


def momenta(field: Mechanism, breaks: np.ndarray) -> np.ndarray:
    """Linear and angular momenta of ``field`` on the intervals of ``breaks`` (m).

    Returns ``(3, len(breaks) - 1)``: ``p_x, p_y`` (N s/m) and the angular
    momentum ``L_O`` about the origin (N m s/m), counter-clockwise; for a rigid piece
    ``(V, Omega)``: ``p = m V + Omega k x S`` and ``L_O = S x V + Omega J``.
    """
    br = np.asarray(breaks, float)
    out = np.empty((3, max(br.size - 1, 0)))
    for a in range(0, out.shape[1], MOMENTA_CHUNK):   # the quadrature needs ~3 kB per piece
        b = min(a + MOMENTA_CHUNK, out.shape[1])
        mo = field.motion_at(0.5 * (br[a:b] + br[a + 1:b + 1]))
        m, S, J = field.curve.segment_inertia(br[a:b], br[a + 1:b + 1])
        Vx, Vy, Om = mo.T
        out[:, a:b] = m * Vx - Om * S[1], m * Vy + Om * S[0], S[0] * Vy - S[1] * Vx + Om * J
    return out


def load_factor(mech: Mechanism, direction: int = 1) -> float:
    """``lambda = A/g`` that makes ``mech`` an equilibrium mechanism under a horizontal
    ground acceleration (inertia along ``direction`` x); inf if incompatible."""
    sgn = mech.compatible_sign()
    if sgn == 0:
        return np.inf
    p = momenta(mech.with_alpha(sgn), np.union1d(mech.breaks, []))
    P_h, P_g = direction * float(np.sum(p[0])), float(np.sum(p[1]))
    return P_g / P_h if P_h > 0 else np.inf


def restitution(before: Mechanism, after: Mechanism) -> float:
    """``r = Gamma^2 / (Lambda Lambda')`` (17) for ``after`` following the field
    ``before``; 0 if ``after`` cannot open with the sign of Gamma (no compatible motion)."""
    return post_impact(before, after).r


@dataclass(frozen=True)
class ImpactFigures:
    """Eqs. (7), (14), (15), (17) for a mechanism ``after`` following the field ``before``.

    ``Lambda = 2K`` of ``before`` (at its rate), ``Lambda_after`` of ``after`` at
    ``alpha = 1``, ``Gamma`` their momentum pairing, ``alpha_ratio = alpha'/alpha =
    Gamma / Lambda'`` (15) and ``r = Gamma^2 / (Lambda Lambda')`` (17); ``compatible``
    is False when ``alpha'`` has not the sign that opens every hinge of ``after``
    (then no motion along ``after`` follows and ``r`` is reported 0).

    Examples
    --------
    :func:`post_impact` returns it; the paper's mechanism closing at unit rate (rad/s),
    followed by the one of hinges at 0, 52.5, 105 and 157.5 deg (``Lambda`` in
    kg m^2/m):

    >>> from fembeam.mechanisms import post_impact
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> before = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> after = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 105.0, 157.5],
    ...                                       sides[::-1])
    >>> fig = post_impact(before.with_alpha(-before.compatible_sign()), after)
    >>> print(fig.compatible, f"r = {fig.r:.4f}, alpha'/alpha = {fig.alpha_ratio:.4f}")
    True r = 0.6071, alpha'/alpha = 1.3298
    >>> print(f"Lambda = {fig.Lambda:.1f}, Lambda' = {fig.Lambda_after:.1f}")
    Lambda = 597.5, Lambda' = 205.2
    """

    Gamma: float
    Lambda: float
    Lambda_after: float
    alpha_ratio: float
    r: float
    compatible: bool


def post_impact(before: Mechanism, after: Mechanism, Lambda: float | None = None) -> ImpactFigures:
    """Closed-form impact (Sect. 4.2): alpha' and r for prescribed hinges ``after``;
    ``Lambda``: ``product(before, before)`` when known (a search over ``after``)."""
    sgn = after.compatible_sign()
    pa = after if after.alpha == 1.0 else after.with_alpha(1.0)
    gamma = product(before, pa)
    lam = product(before, before) if Lambda is None else Lambda
    lam_a = product(pa, pa)
    ok = bool(sgn != 0 and gamma * sgn > 0)
    return ImpactFigures(gamma, lam, lam_a, gamma / lam_a, gamma**2 / (lam * lam_a) if ok else 0.0, ok)


def optimise_load_factor(start: Mechanism, direction: int = 1) -> tuple[Mechanism, float]:
    """Minimise ``lambda`` over the four hinge positions (sides fixed), from ``start``.

    ``lambda`` is smooth in the hinge positions and stationary at the optimum, so a
    bounded quasi-Newton search converges to the continuous-arch mechanism."""
    L = start.curve.length

    def f(x):
        s = start.curve.nearest_section(np.sort(np.clip(x, 0.0, 1.0)) * L)    # no hinge inside a crown wedge
        lam = load_factor(Mechanism(start.curve, tuple(s), start.sides), direction)
        return lam if np.isfinite(lam) else 1e6  # incompatible: out of the feasible set

    x0 = np.asarray(start.s) / L
    f0 = f(x0)
    if f0 >= 1e6:
        raise SolverError("the starting mechanism is not compatible")
    from scipy.optimize import minimize   # imported here: scipy.optimize takes 0.2 s to import

    res = minimize(f, x0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * start.n_hinges,
                   options={"ftol": 1e-15, "gtol": 1e-11, "eps": 1e-9, "maxiter": 500})
    best = res.x if res.fun <= f0 else x0
    s = start.curve.nearest_section(np.sort(np.clip(best, 0.0, 1.0)) * L)
    return Mechanism(start.curve, tuple(s), start.sides), float(min(res.fun, f0))
