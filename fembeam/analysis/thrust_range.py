"""The range of horizontal thrust an arch can stand in under its dead loads.

By the safe theorem (Heyman) any state of the joint forces in equilibrium with the dead
loads (self weight, fill, point masses) and inside every section proves the arch safe.
Among those states the horizontal thrust ``H`` on the springings ranges over an interval
``[H_min, H_max]``: the passive and the active state, the first numbers an assessor asks
for.  Both ends are linear programmes in the redundants ``x`` of the chain
(:mod:`~fembeam.analysis.statics`)::

    H_min = min H(x),  H_max = max H(x)   s.t.  N+_j(x, 0) >= 0,  N-_j(x, 0) >= 0

with ``H`` the horizontal force of the left abutment on the arch (that of the right one is
``-H``: no horizontal load).  On the continuous member the fibre rows of the weakest
sections between the joints are added round after round (the exchange method of
:mod:`~fembeam.analysis.continuum`) until the state lies inside every section to ``tol``.
The LP's duals are opening rates: a compatible mechanism (three hinges) whose virtual work
certifies each bound (duality gap and dual residual are checked).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, SolverError
from ..fem import Discretization
from ..units import kN
from .continuum import weakest_sections
from .lp import maximise
from .rows import STAND_TOL, XBOX, append_section_rows, joint_rows
from .statics import abutment_rows, statics

__all__ = ["ThrustRange", "thrust_range"]

MAX_ROUNDS = 50


@dataclass
class ThrustRange:
    """``H_min``, ``H_max`` (kN per metre of width) and their states: joint forces ``N_min``,
    ``N_max`` (2, J) (intrados, extrados fibre forces, kg/m per unit g) on the joints of
    ``disc``; ``cuts`` the sections between joints added (continuous member).  ``H_max`` is
    infinite (``N_max`` None) when an admissible ray of self-stress makes the thrust grow
    without bound (a straight line of thrust fits inside a flat arch).

    Examples
    --------
    :func:`thrust_range` of a mesh returns it (:func:`~fembeam.analyze` reports it as
    ``thrust``): the passive and active thrusts (kN/m) and the eccentricity (m) of the
    passive thrust line at the left springing:

    >>> import fembeam
    >>> from fembeam.analysis.thrust_range import thrust_range
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> tr = thrust_range(fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12)))
    >>> print(f"H_min = {tr.H_min:.3f} kN/m, H_max = {tr.H_max:.3f} kN/m")
    H_min = 1.612 kN/m, H_max = 2.643 kN/m
    >>> print(f"e = {tr.eccentricity('min')[0]:.4f} m")
    e = 0.0409 m
    """

    disc: Discretization
    H_min: float
    H_max: float
    N_min: np.ndarray
    N_max: np.ndarray
    cuts: tuple = (np.empty(0), np.empty(0))
    verification: dict = field(default_factory=dict)

    def eccentricity(self, which: str) -> np.ndarray:
        """Eccentricity (m, + towards the intrados) of the ``"min"`` or ``"max"`` thrust line at
        the joints; NaN where a joint carries no force."""
        N = self.N_min if which == "min" else self.N_max
        Nt = N[0] + N[1]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(Nt > 1e-12 * np.max(Nt), 0.5 * self.disc.joint_thickness * (N[0] - N[1]) / Nt, np.nan)

    def to_dict(self) -> dict:
        def line(which):
            e = self.eccentricity(which)
            return {"angle_deg": self.disc.joint_angle_deg.tolist(), "s": self.disc.joint_s.tolist(),
                    "eccentricity": [None if not np.isfinite(v) else float(v) for v in e]}
        bounded = math.isfinite(self.H_max)
        return {"H_min": self.H_min, "H_max": self.H_max if bounded else None, "H_max_unbounded": not bounded,
                "unit": "kN/m", "min_line": line("min"), "max_line": line("max") if bounded else None,
                "verification": {k: float(v) for k, v in self.verification.items()}}


def thrust_range(disc: Discretization, continuum: bool = False, tol: float = 1e-10) -> ThrustRange:
    """``[H_min, H_max]`` of ``disc``'s member under its dead loads (module docstring);
    ``continuum``: also inside every section between the joints.  InputError for a member
    without two abutments (its thrust is determinate) or one that cannot stand."""
    st = statics(disc)
    k = st.k
    if k != 3:
        raise InputError("the thrust range needs an arch on two abutments (a member with a free end has a "
                         "determinate thrust)")
    R = joint_rows(st, 1)
    F0, _ = abutment_rows(st)
    h = F0[0]                                   # H = h . (x, lambda, 1), units of weight
    ends, ver = {}, {}
    for sign, name in ((-1.0, "min"), (1.0, "max")):
        cuts, fib = np.empty(0), np.empty(0, int)
        for _ in range(MAX_ROUNDS):
            Rc = append_section_rows(R, st, 1, cuts, fib)
            lp = _solve(sign * h[:k], Rc, k)
            if lp is None:
                if not continuum:
                    break
                # unbounded on these rows: the sections between the joints may still bound it; take
                # the state far along the ray (largest box) and add the sections it violates
                z = np.r_[_solve(sign * h[:k], Rc, k, boxed=True).z, 0.0, 1.0]
            else:
                z = np.r_[lp.z, 0.0, 1.0]
            if not continuum:
                break
            s_new, f_new, v = weakest_sections(st, z)
            bad = v < -tol
            if not bad.any():
                break
            cuts, fib = np.concatenate([cuts, s_new[bad]]), np.concatenate([fib, f_new[bad]])
        else:
            raise SolverError(f"thrust range: sections still outside the {name}imum thrust line after "
                              f"{MAX_ROUNDS} rounds")
        if lp is None:                          # unbounded: H_min = -inf cannot happen (no tension)
            ends[name] = (sign * math.inf, None, (cuts, fib))
            ver[f"{name}_unbounded_ray"] = 1.0
            continue
        rows = Rc @ np.r_[lp.z, 0.0, 1.0]
        if rows.min() < -max(tol, 1e-9 * max(1.0, float(np.max(np.abs(rows))))):   # the LP's tolerance, relative
            raise SolverError(f"thrust range: the {name}imum thrust state is not admissible "
                              f"(fibre force {rows.min():.2e} weights)")
        H = float(h @ z)
        # dual certificate: A^T y = -c and c.x = b.y (A = Rc[:, :k], b = Rc[:, k+1], c = sign h_x)
        c = sign * h[:k]
        dual_residual = float(np.max(np.abs(Rc[:, :k].T @ lp.y + c)) / max(np.max(np.abs(c)), 1e-300))
        gap = abs(float(c @ lp.z) - float(Rc[:, k + 1] @ lp.y)) / (1.0 + abs(H))
        g = st.forces(lp.z, 0.0)
        p = st.f_dead
        B = disc.B_open.T @ g[1:].ravel() + disc.B_slide.T @ g[0]
        ends[name] = (kN(H * st.mass), st.mass * g[1:], (cuts, fib))
        ver[f"{name}_duality_gap"] = gap
        ver[f"{name}_dual_residual"] = dual_residual
        ver[f"{name}_equilibrium_residual"] = float(np.linalg.norm(st.mass * B - p) / np.linalg.norm(p))
        ver[f"{name}_outside"] = max(0.0, -float(rows.min())) / max(1.0, float(np.max(np.abs(rows))))
    limits = {"duality_gap": 1e-7, "dual_residual": 1e-7, "equilibrium_residual": 1e-6, "outside": 1e-6}
    for key in [f"{w}_{q}" for w in ("min", "max") for q in limits]:
        if key in ver and not ver[key] <= limits[key.split("_", 1)[1]]:
            raise SolverError(f"thrust range: failed verification ({key} = {ver[key]:.2e})")
    (H_min, N_min, c_min), (H_max, N_max, c_max) = ends["min"], ends["max"]
    if N_min is None:
        raise SolverError("thrust range: no finite minimum thrust")
    if H_min > H_max + 1e-9 * max(abs(H_max), 1e-300):
        raise SolverError(f"thrust range: H_min {H_min:g} > H_max {H_max:g}")
    return ThrustRange(disc, H_min, max(H_min, H_max), N_min, N_max, (c_min, c_max), ver)


def _solve(c: np.ndarray, R: np.ndarray, k: int, boxed: bool = False):
    """``max c.x s.t. R_x x + R_1 >= 0`` with the redundants boxed, the box enlarged while it
    binds; InputError when the rows admit no state (the member cannot stand); None when the
    thrust is unbounded (an admissible ray), or with ``boxed`` the optimum in the largest box."""
    for xbox in (XBOX, 1e6 * XBOX, 1e12 * XBOX):
        # feasibility first: the largest margin (a member that cannot stand has none)
        A = np.column_stack([R[:, :k], -np.ones(R.shape[0])])
        stand = maximise(np.r_[np.zeros(k), 1.0], A, R[:, k + 1], [(-xbox, xbox)] * k + [(None, 1.0)],
                         seq=R.shape[0] // 2)
        if stand.value < -STAND_TOL:
            if not stand.at_bound[:k].any():
                raise InputError("the member cannot stand under its dead loads: it has no thrust range")
            continue
        lp = maximise(c, R[:, :k], R[:, k + 1], [(-xbox, xbox)] * k, seq=R.shape[0] // 2)
        if not lp.at_bound.any() or (boxed and xbox == 1e12 * XBOX):
            return lp
    # certificate of an unbounded thrust: a ray of self-stress dx, admissible on every row
    # (R_x dx >= 0), along which the thrust grows (c.dx > 0): e.g. a straight line of thrust
    # inside a flat arch carries any thrust
    ray = maximise(c, R[:, :k], np.zeros(R.shape[0]), [(-1.0, 1.0)] * k, seq=R.shape[0] // 2)
    if ray.value > 1e-9 * max(np.max(np.abs(c)), 1e-300) and np.min(R[:, :k] @ ray.z) >= -1e-12:
        return None
    raise SolverError("thrust range: the thrust exceeds 1e15 weights and no admissible ray was found")
