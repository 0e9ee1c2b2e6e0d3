"""Impact: the post-impact field and the impulse line (Sect. 5, Appendix B; docs/theory.md).

The post-impact field is the projection, in the kinetic metric, of the pre-impact
field ``d0`` onto the cone of compatible fields (Moreau's inelastic impact law)::

    minimise 1/2 d^T M d - (M d0)^T d   s.t.  B_slide d = 0,  B_open d >= 0.

Its KKT conditions ``M d' = M d0 + B_open^T mu + B_slide^T lam`` are the impulse and
momentum balance (B.11): the multipliers are the internal impulses at the joints.
The optimum satisfies the virtual-work equality (B.6) and maximises
``r = K'/K = d'^T M d' / d0^T M d0`` among the compatible fields satisfying it.

Impulses follow the paper's convention: ``I(s)`` is the impulse exerted on the part
left of ``s`` by the part on its right, so compression is ``I_t < 0``:
``I_t = -(mu_+ + mu_-)``, ``I_n = -lam``, moment about the mid-curve point
``M = I_t+ y_+ + I_t- y_-`` and impulse-line eccentricity ``e = M / I_t`` (m, along
``n``, + towards the intrados).  Units: N s/m for unit ``d0`` velocities.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..fem import Discretization, dof_scaling
from ..mechanisms.hinge import Hinge, find_hinges
from .active_set import project_chain
from .qp import BACKENDS, solve_qp
from .statics import statics
from .verification import check

__all__ = ["ImpactResult", "impact", "IMPACT_BACKENDS"]

IMPACT_BACKENDS = ("auto",) + BACKENDS + ("active-set",)
AUTO_ELEMENTS = 5000   # "auto": Clarabel up to this many elements, the banded active set above

ARREST_TOL = 1e-9  # r below this: the arch stops dead (no compatible motion does work)
COMPATIBLE_TOL = 1e-9  # d0 closing or sliding no joint by more than this (relative): compatible, r = 1


@dataclass
class ImpactResult:
    """Outcome of :func:`impact`: the post-impact field and the impulse line.

    Impulses are per metre of width, in N s/m for unit pre-impact velocities (N s/m for
    a mean horizontal speed of 1 m/s with the mechanism of :func:`~fembeam.analyze`);
    ``I(s)`` is the impulse on the part left of ``s`` by the part on its right, so
    compression is ``I_t < 0``.

    Attributes
    ----------
    disc : Discretization
        The mesh.
    d0 : ndarray
        Pre-impact element velocities (the DOFs of ``disc``).
    d : ndarray
        Post-impact element velocities ``d'``.
    r : float
        Restitution coefficient ``K'/K`` of the kinetic energy, ``0 <= r <= 1``.
    mu : ndarray
        ``(2, J)`` fibre impulses at the intrados and extrados (N s/m, >= 0 in
        compression).
    lam : ndarray
        ``(J,)`` multipliers of the no-sliding constraints (N s/m).
    hinges : list of Hinge
        Open joints of the post-impact field, left to right.
    backend : str
        Solver used (``"none"`` when ``d0`` is compatible and no QP was solved).
    iterations : int
        Solver iterations.
    solve_time : float
        Time of the solve (s).
    verification : dict
        The checked figures of the solution (KKT residuals, energy balance).

    Examples
    --------
    :func:`impact` returns it: the restitution coefficient, the hinges after the impact
    and the impulses (N s/m) for the mechanism of :func:`~fembeam.limit_analysis`:

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12))
    >>> imp = fembeam.impact(disc, -fembeam.limit_analysis(disc).u)
    >>> print(f"r = {imp.r:.4f},", len(imp.hinges), "hinges after the impact")
    r = 0.6137, 6 hinges after the impact
    >>> print(f"I_t = {imp.I_t[0]:.1f} N s/m at the left springing")
    I_t = -299.7 N s/m at the left springing
    """

    disc: Discretization
    d0: np.ndarray
    d: np.ndarray            # post-impact field d'
    r: float                 # restitution coefficient K'/K
    mu: np.ndarray           # (2, J) fibre impulses (intrados, extrados), >= 0 compressive
    lam: np.ndarray          # (J,) sliding multipliers
    hinges: list[Hinge]
    backend: str
    iterations: int
    solve_time: float
    verification: dict = field(default_factory=dict)

    @property
    def arrested(self) -> bool:
        """Whether the arch stops dead (``r`` below :data:`ARREST_TOL`)."""
        return self.r < ARREST_TOL

    @property
    def I_t(self) -> np.ndarray:
        """Tangential (normal-force) impulse at the joints (N s/m, < 0 in compression)."""
        return -(self.mu[0] + self.mu[1])

    @property
    def I_n(self) -> np.ndarray:
        """Shear impulse at the joints (N s/m)."""
        return -self.lam

    @property
    def moment(self) -> np.ndarray:
        """Moment of the fibre impulses about the mid-curve point (N m s/m)."""
        return -0.5 * self.disc.joint_thickness * (self.mu[0] - self.mu[1])

    @property
    def eccentricity(self) -> np.ndarray:
        """Impulse-line eccentricity at the joints (m, along ``n``, + towards the
        intrados); NaN where the joint carries no impulse."""
        It = self.I_t
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(np.abs(It) > 1e-12 * np.max(np.abs(It), initial=0.0), self.moment / It, np.nan)


def impact(disc: Discretization, d0: np.ndarray, backend: str = "auto", tol: float = 1e-10,
           verify: bool = True) -> ImpactResult:
    """Post-impact field, restitution coefficient and internal impulses.

    The post-impact field is the projection, in the kinetic metric, of the pre-impact
    field ``d0`` onto the cone of compatible fields (Moreau's inelastic impact law);
    the multipliers are the internal impulses at the joints. ``0 <= r <= 1`` always. A
    ``d0`` that is itself compatible (no joint closes or slides, within
    :data:`COMPATIBLE_TOL` of its largest opening rate, e.g. ``+u`` of the limit
    analysis) is its own projection: ``d' = d0``, no impulses, ``r = 1`` exactly and no
    QP solved (``backend`` reported as ``"none"``).

    Parameters
    ----------
    disc : Discretization
        The mesh (:func:`~fembeam.fem.rigid.discretize`).
    d0 : array_like
        Pre-impact element velocities (m/s and rad/s, the DOFs of ``disc``), e.g.
        ``-u`` of :func:`~fembeam.analysis.limit.limit_analysis`: the mechanism
        reversed, as the arch lands on the symmetric hinges.
    backend : {"auto", "clarabel", "osqp", "active-set"}, optional
        ``"clarabel"`` (interior point on the primal QP), ``"osqp"`` (ADMM with
        polishing), ``"active-set"`` (banded interior point and active set on the dual,
        O(N) per iteration, falling back to Clarabel without a certified answer) or
        ``"auto"`` (Clarabel up to ``AUTO_ELEMENTS`` elements, the active set above).
    tol : float, optional
        Solver tolerance (relative).
    verify : bool, optional
        Check the solution's figures against their thresholds.

    Returns
    -------
    ImpactResult
        ``r``, the post-impact field ``d``, the impulses and the hinges after the
        impact.

    Raises
    ------
    InputError
        ``disc`` is no Discretization, or ``d0`` not ``disc``'s number of finite DOFs.
    SolverError
        The solve failed or a figure exceeded its threshold (``verify``).

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 12))
    >>> lim = fembeam.limit_analysis(disc)
    >>> imp = fembeam.impact(disc, -lim.u)
    >>> print(f"r = {imp.r:.4f}", "arrested" if imp.arrested else "rocks on")
    r = 0.6137 rocks on
    """
    if not isinstance(disc, Discretization):
        raise InputError(f"impact needs a Discretization (fembeam.discretize), got {type(disc).__name__}")
    d0 = np.asarray(d0, float)
    if d0.shape != (disc.M.shape[0],) or not np.all(np.isfinite(d0)):
        raise InputError(f"the pre-impact field must be {disc.M.shape[0]} finite element DOFs")
    D = dof_scaling(disc)
    M = disc.M
    two_k = float(d0 @ M @ d0)
    if not two_k > 0:
        raise InputError("the pre-impact field has no kinetic energy")
    m = float(disc.rigid(V=(1.0, 0.0)) @ M @ disc.rigid(V=(1.0, 0.0)))
    sigma = np.sqrt(two_k / m)  # mean velocity of d0 (m/s): scale of the scaled problem
    if backend not in IMPACT_BACKENDS:
        raise InputError(f"unknown QP backend {backend!r}; allowed: {', '.join(IMPACT_BACKENDS)}")
    if backend == "auto":
        backend = "active-set" if disc.n_elements > AUTO_ELEMENTS else "clarabel"
    eps0, slide0 = disc.B_open @ d0, disc.B_slide @ d0
    misfit = max(0.0, -np.min(eps0), np.max(np.abs(slide0), initial=0.0))
    if misfit <= COMPATIBLE_TOL * max(np.max(np.abs(eps0)), sigma):   # d0 is its own projection
        J = disc.n_joints
        res = ImpactResult(disc, d0, d0.copy(), 1.0, np.zeros((2, J)), np.zeros(slide0.size),
                           find_hinges(disc, d0), "none", 0, 0.0)
        res.verification = _verify(res, two_k)
        return res
    chain = None
    if backend == "active-set":
        t0 = time.perf_counter()
        chain = project_chain(disc, d0)
        solve_time = time.perf_counter() - t0
    if chain is not None:
        d, mu, lam, iterations = chain.d, chain.mu, chain.lam, chain.steps
    else:   # the interior-point (or ADMM) QP, also when the active set has no certified answer
        P = (D @ M @ D / m).tocsc()
        q = -(D @ (M @ d0)) / (m * sigma)
        sol = solve_qp(P, q, disc.B_slide @ D, disc.B_open @ D, backend="clarabel" if backend == "active-set"
                       else backend, tol=tol)
        d = sigma * (D @ sol.x)
        mu = m * sigma * sol.mu.reshape(2, disc.n_joints)
        lam = m * sigma * sol.lam
        backend, iterations, solve_time = sol.backend, sol.iterations, sol.solve_time
    r = min(float(d @ M @ d) / two_k, 1.0)
    res = ImpactResult(disc, d0, d, r, mu, lam, find_hinges(disc, d) if r >= ARREST_TOL else [],
                       backend, iterations, solve_time)
    res.verification = _verify(res, two_k)
    if verify:
        check(res.verification, "impact QP")
    return res


def _verify(res: ImpactResult, two_k: float) -> dict:
    """Appendix B's claims, recomputed from the solution (all relative, see docs).

    The impulse line is recomputed from the momentum balance of the elements (the
    impulses of the first joint, then a sparse triangular solve along the chain), not
    read off the multipliers: ``impulse_mismatch`` compares the two, and the
    recomputed line must lie inside every section (``impulse_line_outside``)."""
    disc, d, mu, lam = res.disc, res.d, res.mu, res.lam
    M = disc.M
    p0 = M @ res.d0
    eq = M @ d - p0 - disc.B_open.T @ mu.ravel() - disc.B_slide.T @ lam
    eps = disc.B_open @ d
    mu_max = max(np.max(np.abs(mu)), 1e-300)
    st = statics(disc)
    g = st.particular(M @ d - p0) + st.G_x @ (np.array([lam[0], mu[0, 0], mu[1, 0]])[:st.k] / st.mass)
    g *= st.mass
    Nt = g[1] + g[2]
    carried = Nt > 1e-9 * mu_max
    outside = -np.minimum(g[1], g[2])[carried] / Nt[carried]
    work = float(mu.ravel() @ eps + lam @ (disc.B_slide @ d))
    It = res.I_t
    with np.errstate(divide="ignore", invalid="ignore"):
        shear = np.abs(lam[carried]) / np.abs(It[carried])
    return {
        "equilibrium_residual": float(np.linalg.norm(eq) / np.linalg.norm(p0)),
        "impulse_mismatch": float(np.max(np.abs(g - np.vstack([lam, mu]))) / mu_max),
        "impulse_line_outside": float(max(0.0, np.max(outside, initial=0.0))),
        "max_tensile_impulse": float(max(0.0, -np.min(mu)) / mu_max),
        "impulse_work": float(abs(work) / two_k),
        "incompatibility": float(max(0.0, -np.min(eps), np.max(np.abs(disc.B_slide @ d)))
                                 / max(np.max(np.abs(eps)), np.sqrt(two_k / st.mass))),
        "virtual_work_gap": float(abs(p0 @ d - d @ M @ d) / two_k),
        "max_shear_ratio": float(np.max(shear, initial=0.0)),
    }
