"""The thrust line between the joints: where does a static solution leave the section?

A limit LP on a mesh constrains the fibre forces at the joints only, so its optimum is
the load factor of a mechanism with hinges at joints: an upper bound of the continuous
member's ``A_L``.  Between the joints the same forces follow from the equilibrium of
the part left of each section (:func:`~fembeam.analysis.statics.section_forces`); this
module finds, in every element, the sections where a fibre force is smallest: samples
inside every element, then a bracketed golden-section search (vectorised over the
elements) around the smallest sample of those that come close to zero.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .statics import Statics, section_force_rows, statics

__all__ = ["weakest_sections", "ContinuumLimit", "continuum_limit"]

SAMPLES = 4          # interior samples per element
GOLDEN_STEPS = 45    # bracket shrinks by 0.618^45 ~ 4e-10 of an element
NEAR = 0.05          # elements whose sampled fibre force is below this (units of weight) are searched


def _fibres(st: Statics, s: np.ndarray, z: np.ndarray) -> np.ndarray:
    return (section_force_rows(st, s)[1:] @ z)            # (2, ns): N+, N-


def weakest_sections(st: Statics, z: np.ndarray, near: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local minima of the fibre forces inside the elements for ``z = (x, lambda, 1)``.

    Returns ``(s, fibre, value)`` for every (element, fibre) whose sampled minimum is
    below ``near`` (units of weight): section (m), fibre index (0 intrados, 1 extrados)
    and the minimum force there.
    """
    nodes = st.disc.nodes_s
    ne = nodes.size - 1
    q = (np.arange(1, SAMPLES + 1) / (SAMPLES + 1))
    s = (nodes[:-1, None] + np.diff(nodes)[:, None] * q[None, :]).ravel()
    f = _fibres(st, s, z).reshape(2, ne, SAMPLES)
    fmin = f.min(2)
    fib, el = np.nonzero(fmin < near)
    if el.size == 0:
        return np.empty(0), np.empty(0, int), np.empty(0)
    k = np.argmin(f[fib, el], 1)
    h = np.diff(nodes)[el]
    a = nodes[el] + h * np.where(k == 0, 0.0, q[np.maximum(k - 1, 0)])
    b = nodes[el] + h * np.where(k == SAMPLES - 1, 1.0, q[np.minimum(k + 1, SAMPLES - 1)])
    g = 0.5 * (np.sqrt(5.0) - 1.0)
    c, d = b - g * (b - a), a + g * (b - a)

    def val(x):
        return _fibres(st, x, z)[fib, np.arange(fib.size)]

    fc, fd = val(c), val(d)
    for _ in range(GOLDEN_STEPS):
        left = fc < fd                       # the minimum lies in [a, d]: drop (d, b]
        b = np.where(left, d, b)
        a = np.where(left, a, c)
        x = np.where(left, b - g * (b - a), a + g * (b - a))
        fx = val(x)
        c, d, fd, fc = (np.where(left, x, d), np.where(left, c, x),
                        np.where(left, fc, fx), np.where(left, fx, fd))
    sm = np.where(fc < fd, c, d)
    return sm, fib, np.minimum(fc, fd)


@dataclass
class ContinuumLimit:
    """The continuous member's limit state, bracketed: ``A_L`` (upper bound: a mechanism
    with hinges at ``hinge_s``) and ``A_L_lower`` (lower bound: an admissible thrust line
    everywhere); ``status`` as :class:`~fembeam.analysis.limit.LimitResult`."""

    status: str
    A_L: float
    A_L_lower: float
    margin: float                 # standing margin (units of weight), lower bound on the continuum
    hinge_s: np.ndarray           # sections (m) of the mechanism's hinges (joints or cuts)
    cuts: np.ndarray              # sections between the joints added as constraints (m)
    violation: float              # thrust line outside between the joints at A_L (units of weight)
    rounds: int

    @property
    def gap(self) -> float:
        return (self.A_L - self.A_L_lower) / self.A_L if self.A_L > 0 else 0.0


def _rows(st: Statics, direction: int, R: np.ndarray, cuts: np.ndarray, fib: np.ndarray) -> np.ndarray:
    if cuts.size == 0:
        return R
    C = section_force_rows(st, cuts)                      # (3, nc, k + 2)
    C = C[1 + fib, np.arange(cuts.size)]
    C[:, st.k] *= direction
    return np.concatenate([R, C])


def continuum_limit(disc, direction: int = 1, tol: float = 1e-10, max_rounds: int = 50) -> ContinuumLimit:
    """Limit analysis of the continuous member meshed by ``disc``: the joints of ``disc``
    plus, round after round, the weakest sections between them (the exchange method of
    semi-infinite linear programming), until the thrust line at the optimum lies inside
    the section everywhere to ``tol`` (units of weight).  The bounds bracket ``A_L``:
    the convex combination ``theta z* + (1 - theta) z_c`` of the optimum and of the
    most central state under gravity ``z_c`` (margin ``m_c > 0``) is admissible for
    ``theta = m_c / (m_c + violation)``, so ``A_L >= theta A_L*``."""
    from .limit import STAND_TOL, joint_rows, main_lp

    st = statics(disc)
    k, J = st.k, disc.n_joints
    R = joint_rows(st, direction)
    stand, margin, cuts, fib, rounds = _stand(st, direction, R, np.empty(0), np.empty(0, int), tol, max_rounds)
    if stand.value < -STAND_TOL:
        return ContinuumLimit("cannot_stand", float("nan"), float("nan"), stand.value,
                              _support(disc, cuts, stand.y, J), cuts, float("nan"), rounds)
    for _ in range(max_rounds):
        rounds += 1
        main = main_lp(_rows(st, direction, R, cuts, fib), k)
        if main.at_bound.any():
            return ContinuumLimit("no_mechanism", float("inf"), float("inf"), margin, np.empty(0), cuts, 0.0, rounds)
        s_new, f_new, v = weakest_sections(st, np.r_[main.z[:k], direction * main.z[k], 1.0], NEAR)
        violation = max(0.0, -float(np.min(v, initial=0.0)))
        keep = v < -tol
        if not keep.any():
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    lam = float(main.z[k])
    lower = lam * margin / (margin + violation) if margin > 0 else 0.0
    return ContinuumLimit("ok", lam, min(lam, lower), margin, _support(disc, cuts, main.y, J), cuts, violation, rounds)


def _stand(st: Statics, direction: int, R, cuts, fib, tol: float, max_rounds: int):
    """Largest margin under gravity on the continuum: the LP's value bounds it from above,
    the smallest fibre force of the LP's state along the whole member from below."""
    from .limit import STAND_TOL, stand_lp

    k = st.k
    for rounds in range(1, max_rounds + 1):
        stand = stand_lp(_rows(st, direction, R, cuts, fib), k)
        z_c = np.r_[stand.z[:k], 0.0, 1.0]
        s_new, f_new, v = weakest_sections(st, z_c, NEAR)
        margin = min(stand.value, float(np.min(v, initial=np.inf)))
        keep = v < stand.value - tol
        if margin >= -STAND_TOL or stand.value < -STAND_TOL or not keep.any():
            break
        cuts, fib = np.concatenate([cuts, s_new[keep]]), np.concatenate([fib, f_new[keep]])
    return stand, margin, cuts, fib, rounds


def continuum_stands(disc, tol: float = 1e-10, max_rounds: int = 50) -> tuple[bool, float]:
    """Whether the continuous member meshed by ``disc`` stands under gravity, and the
    margin (units of weight; a lower bound when it stands, the LP's bound when not)."""
    from .limit import STAND_TOL, joint_rows

    st = statics(disc)
    stand, margin, *_ = _stand(st, 1, joint_rows(st, 1), np.empty(0), np.empty(0, int), tol, max_rounds)
    if stand.value < -STAND_TOL:
        return False, stand.value
    return margin >= -STAND_TOL, margin


def _support(disc, cuts: np.ndarray, y: np.ndarray, J: int) -> np.ndarray:
    """Sections carrying the LP's duals (the hinges): joints and cuts, sorted."""
    s_all = np.concatenate([disc.joint_s, disc.joint_s, cuts])
    w = np.abs(y)
    return np.unique(s_all[w > 1e-6 * max(np.max(w), 1e-300)])
