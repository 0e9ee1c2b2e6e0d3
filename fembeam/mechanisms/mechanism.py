"""Four-hinge mechanisms with hinges anywhere on the mid-curve (Sect. 4, Appendix A).

A mechanism is described by its hinges ``C1, C13, C23, C2`` (arc lengths ``s`` and
the edge each pivots on); the rigid segments I = [s1, s13] (rotating about C1 with
``Omega_I = 1``), III = [s13, s23] (about C3, the intersection of lines C1-C13 and
C2-C23) and II = [s23, s2] (about C2); the parts outside [s1, s2] rest on the
abutments.  The angular-velocity coefficients are (A.1) written with dot products
(valid for any orientation of the lines).

The inertia integrals are exact for any :class:`~fembeam.geometry.MidCurve`
(Gauss quadrature of :meth:`MidCurve.inertia_densities`), so the quantities here are
the continuous-arch values: ``lambda`` (load factor of a mechanism), ``Lambda``,
``Gamma`` and ``r = Gamma^2 / (Lambda Lambda')`` of (7), (14) and (17).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from .errors import InputError, SolverError
from .geometry import MidCurve

__all__ = ["Pieces", "FourHinge", "ImpactFigures", "product", "momenta", "load_factor", "restitution",
           "post_impact", "optimise_load_factor", "OPPOSITE"]

SIDE_Y = {"intrados": 0.5, "extrados": -0.5}       # y / t of the pivot (a subset of hinges.PIVOT_Y)
SIDE_SIGN = {"intrados": -1.0, "extrados": 1.0}    # sign of [omega] that opens the hinge
OPPOSITE = {"intrados": "extrados", "extrados": "intrados"}


def pivot_y(curve: MidCurve, s, sides) -> np.ndarray:
    """Offsets ``y`` (m, along n) of the pivot edges ``sides`` of the sections at ``s``."""
    return np.array([SIDE_Y[k] for k in sides]) * curve.thickness_at(np.asarray(s, float))


@dataclass(frozen=True)
class Pieces:
    """Piecewise-rigid field: on ``[breaks[i], breaks[i+1]]`` the velocity is
    ``V_i + Omega_i k x X`` with ``motion[i] = (V_x, V_y, Omega)`` (m/s, rad/s)."""

    breaks: np.ndarray
    motion: np.ndarray

    @classmethod
    def rigid(cls, curve: MidCurve, V=(0.0, 0.0), omega: float = 0.0) -> "Pieces":
        return cls(np.array([0.0, curve.length]), np.array([[V[0], V[1], omega]]))

    def dofs(self, disc) -> np.ndarray:
        """Element DOFs of this field on the rigid-element mesh ``disc``: each element
        takes the motion of the piece containing its midpoint (exact when the breaks are
        nodes of the mesh)."""
        from .fem import rigid_dofs

        k = np.clip(np.searchsorted(self.breaks, disc.frames["s"]) - 1, 0, len(self.motion) - 1)
        Vx, Vy, W = self.motion[k].T
        return rigid_dofs(disc, (Vx, Vy), W)


def product(curve: MidCurve, a: Pieces, b: Pieces) -> float:
    """Momentum pairing ``int rho vel_a . vel_b dA`` (so ``2K = product(a, a)``)."""
    br = np.union1d(a.breaks, b.breaks)
    mid = 0.5 * (br[:-1] + br[1:])
    ma = a.motion[np.clip(np.searchsorted(a.breaks, mid) - 1, 0, len(a.motion) - 1)]
    mb = b.motion[np.clip(np.searchsorted(b.breaks, mid) - 1, 0, len(b.motion) - 1)]
    m, S, J = curve.segment_inertia(br[:-1], br[1:])
    kS = np.array([-S[1], S[0]])
    return float(np.sum(m * (ma[:, 0] * mb[:, 0] + ma[:, 1] * mb[:, 1])
                        + ma[:, 2] * (mb[:, 0] * kS[0] + mb[:, 1] * kS[1])
                        + mb[:, 2] * (ma[:, 0] * kS[0] + ma[:, 1] * kS[1])
                        + ma[:, 2] * mb[:, 2] * J))


def momenta(curve: MidCurve, field: Pieces, breaks: np.ndarray) -> np.ndarray:
    """Linear and angular momenta of ``field`` on the intervals of ``breaks`` (m).

    Returns ``(3, len(breaks) - 1)``: ``p_x, p_y`` (N s per unit depth) and the angular
    momentum ``L_O`` about the origin (N m s), counter-clockwise; for a rigid piece
    ``(V, Omega)``: ``p = m V + Omega k x S`` and ``L_O = S x V + Omega J``.
    """
    br = np.asarray(breaks, float)
    mid = 0.5 * (br[:-1] + br[1:])
    mo = field.motion[np.clip(np.searchsorted(field.breaks, mid) - 1, 0, len(field.motion) - 1)]
    m, S, J = curve.segment_inertia(br[:-1], br[1:])
    Vx, Vy, Om = mo.T
    return np.array([m * Vx - Om * S[1], m * Vy + Om * S[0], S[0] * Vy - S[1] * Vx + Om * J])


@dataclass(frozen=True)
class FourHinge:
    """Hinges ``s = (s1, s13, s23, s2)`` (m, increasing) pivoting on ``sides``."""

    s: tuple[float, float, float, float]
    sides: tuple[str, str, str, str]

    def __post_init__(self):
        if len(self.s) != 4 or len(self.sides) != 4:
            raise InputError("a four-hinge mechanism needs exactly four hinges")
        if any(k not in SIDE_Y for k in self.sides):
            raise InputError(f"hinge sides must be 'intrados' or 'extrados', got {self.sides}")
        if np.any(np.diff(np.asarray(self.s, float)) < 0):
            raise InputError(f"the four hinges must be in increasing order along the arch, got s = {self.s}")

    @classmethod
    def from_hinges(cls, hinges) -> "FourHinge":
        """From four :class:`~fembeam.hinges.Hinge` (e.g. the LP's incipient mechanism)."""
        if len(hinges) != 4:
            raise InputError(f"expected a four-hinge mechanism, got {len(hinges)} hinges")
        return cls(tuple(float(h.s) for h in hinges), tuple(h.side for h in hinges))

    @classmethod
    def from_angles(cls, curve: MidCurve, angles_deg, sides) -> "FourHinge":
        """Hinges at ``angles_deg`` (the curve's reporting coordinate, deg from the left
        springing for arches; linear in ``s``)."""
        scale = curve.length / float(curve.angle_deg(curve.length))
        a = np.asarray(angles_deg, float)
        if np.any(a < -1e-9) or np.any(a * scale > curve.length * (1 + 1e-12)):
            raise InputError(f"hinge angles must lie in [0, {float(curve.angle_deg(curve.length)):g}] deg")
        return cls(tuple(np.clip(a * scale, 0.0, curve.length)), tuple(sides))

    def angles_deg(self, curve: MidCurve) -> np.ndarray:
        return np.asarray(curve.angle_deg(np.asarray(self.s, float)), float)

    def opposite(self) -> "FourHinge":
        """Same sections, pivots on the other edge (the points C-bar of Sect. 3)."""
        return FourHinge(self.s, tuple(OPPOSITE[k] for k in self.sides))

    def mirrored(self, curve: MidCurve) -> "FourHinge":
        """Mirror image about the symmetry axis (s -> L - s; a side stays a side)."""
        return FourHinge(tuple(curve.length - np.asarray(self.s[::-1], float)), self.sides[::-1])

    def to_list(self, curve: MidCurve) -> list[dict]:
        return [{"angle_deg": round(float(a), 6), "side": k} for a, k in zip(self.angles_deg(curve), self.sides)]

    def hinges(self, curve: MidCurve, alpha: float = 1.0) -> list:
        """The four hinges as :class:`~fembeam.hinges.Hinge` (rotation = jump of the
        angular velocity, right minus left, for ``Omega_I = alpha``)."""
        from .hinges import Hinge

        om = alpha * self.omegas(curve)[0]
        jumps = [om[0], om[1] - om[0], om[2] - om[1], -om[2]]
        return [Hinge(float(s), float(curve.angle_deg(s)), k, float(j), ())
                for s, k, j in zip(self.s, self.sides, jumps)]

    def points(self, curve: MidCurve) -> np.ndarray:
        s = np.asarray(self.s, float)
        return curve.point(s, pivot_y(curve, s, self.sides))

    def omegas(self, curve: MidCurve):
        """Angular velocities (I, III, II) for Omega_I = 1 and centres (C1, C3, C2)."""
        C1, C13, C23, C2 = self.points(curve).T
        d1, d2 = C13 - C1, C23 - C2
        det = d1[0] * (-d2[1]) - d1[1] * (-d2[0])
        if abs(det) < 1e-14 * np.dot(d1, d1):
            raise SolverError("degenerate four-hinge mechanism: lines C1-C13 and C2-C23 are parallel")
        a = ((C2 - C1)[0] * (-d2[1]) - (C2 - C1)[1] * (-d2[0])) / det
        C3 = C1 + a * d1
        om3 = np.dot(C13 - C1, C13 - C3) / np.dot(C13 - C3, C13 - C3)
        om2 = om3 * np.dot(C23 - C3, C23 - C2) / np.dot(C23 - C2, C23 - C2)
        return np.array([1.0, om3, om2]), (C1, C3, C2)

    def compatible_sign(self, curve: MidCurve) -> float:
        """+1 or -1: the sign of alpha for which every hinge opens; 0 if none does."""
        om, _ = self.omegas(curve)
        jumps = np.array([om[0], om[1] - om[0], om[2] - om[1], -om[2]])
        q = np.array([SIDE_SIGN[k] for k in self.sides]) * jumps
        return 1.0 if np.all(q >= 0) else (-1.0 if np.all(q <= 0) else 0.0)

    def pieces(self, curve: MidCurve, alpha: float = 1.0) -> Pieces:
        om, centres = self.omegas(curve)
        motion = [[0.0, 0.0, 0.0]]
        for w, C in zip(alpha * om, centres):
            motion.append([w * C[1], -w * C[0], w])   # rotation w about C
        motion.append([0.0, 0.0, 0.0])
        return Pieces(np.array([0.0, *self.s, curve.length]), np.array(motion))


def load_factor(curve: MidCurve, mech: FourHinge, direction: int = 1) -> float:
    """``lambda = A/g`` that makes ``mech`` an equilibrium mechanism (inf if incompatible)."""
    sgn = mech.compatible_sign(curve)
    if sgn == 0:
        return np.inf
    p = mech.pieces(curve, sgn)
    P_h = direction * product(curve, p, Pieces.rigid(curve, V=(1.0, 0.0)))
    P_g = product(curve, p, Pieces.rigid(curve, V=(0.0, 1.0)))
    return P_g / P_h if P_h > 0 else np.inf


def restitution(curve: MidCurve, before: Pieces, after: FourHinge) -> float:
    """``r = Gamma^2 / (Lambda Lambda')`` (17) for ``after`` following ``before``; 0 if
    ``after`` cannot open with the sign of Gamma (no compatible motion)."""
    sgn = after.compatible_sign(curve)
    pa = after.pieces(curve)
    gamma = product(curve, before, pa)
    if sgn == 0 or gamma * sgn <= 0:
        return 0.0
    return gamma**2 / (product(curve, before, before) * product(curve, pa, pa))


@dataclass(frozen=True)
class ImpactFigures:
    """Eqs. (7), (14), (15), (17) for a four-hinge ``after`` following ``before``.

    ``Lambda = 2K`` of ``before`` (its own alpha = 1), ``Lambda_after`` of ``after`` with
    ``Omega_I = 1``, ``Gamma`` their momentum pairing, ``alpha_ratio = alpha'/alpha =
    Gamma / Lambda'`` (15) and ``r = Gamma^2 / (Lambda Lambda')`` (17);
    ``compatible`` is False when ``alpha'`` has not the sign that opens every hinge
    of ``after`` (then no motion along ``after`` follows and ``r`` is reported 0).
    """

    Gamma: float
    Lambda: float
    Lambda_after: float
    alpha_ratio: float
    r: float
    compatible: bool


def post_impact(curve: MidCurve, before: Pieces, after: FourHinge) -> ImpactFigures:
    """Closed-form four-hinge impact (Sect. 4.2): alpha' and r for prescribed hinges."""
    sgn = after.compatible_sign(curve)
    pa = after.pieces(curve)
    gamma = product(curve, before, pa)
    lam, lam_a = product(curve, before, before), product(curve, pa, pa)
    ok = bool(sgn != 0 and gamma * sgn > 0)
    return ImpactFigures(gamma, lam, lam_a, gamma / lam_a, gamma**2 / (lam * lam_a) if ok else 0.0, ok)


def optimise_load_factor(curve: MidCurve, start: FourHinge, direction: int = 1) -> tuple[FourHinge, float]:
    """Minimise ``lambda`` over the four hinge positions (sides fixed), from ``start``.

    ``lambda`` is smooth in the hinge positions and stationary at the optimum, so a
    bounded quasi-Newton search converges to the continuous-arch mechanism."""
    L = curve.length
    sides = start.sides

    def f(x):
        s = np.sort(np.clip(x, 0.0, 1.0)) * L
        lam = load_factor(curve, FourHinge(tuple(s), sides), direction)
        return lam if np.isfinite(lam) else 1e6  # incompatible: out of the feasible set

    x0 = np.asarray(start.s) / L
    f0 = f(x0)
    if f0 >= 1e6:
        raise SolverError("the starting four-hinge mechanism is not compatible")
    res = minimize(f, x0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * 4,
                   options={"ftol": 1e-15, "gtol": 1e-11, "eps": 1e-9, "maxiter": 500})
    best = res.x if res.fun <= f0 else x0
    return FourHinge(tuple(np.sort(best) * L), sides), float(min(res.fun, f0))
