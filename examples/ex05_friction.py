"""
Friction: the minimum thickness of the semicircular arch
========================================================

The minimum thickness of the semicircular arch with Coulomb friction at radial joints,
against Cocchetti & Rizzi (2020), who put the weight of each voussoir on the mid-curve
(Heyman's simplification); then the same arch with the true centroids of the voussoirs.
Below the smallest friction coefficient ``mu_min`` no thickness stands: the joints near
the springings slide before any hinge forms.

Run as a script: ``python examples/ex05_friction.py``; the table is the one of the
documentation's friction page.
"""
import numpy as np

from fembeam import CircularArch
from fembeam.analysis.continuum import margin_search
from fembeam.analysis.friction import mass_on_midcurve
from fembeam.analysis.rows import joint_rows
from fembeam.analysis.statics import section_force_rows, statics
from fembeam.analysis.thickness import stands_on, thickness_on
from fembeam.fem import discretize, uniform_nodes

# %%
# The arches and the meshes
# -------------------------
# Friction is imposed at the joints of the rigid elements; the fibres (no tension) at
# every section. ``HEYMAN`` carries each element's weight on the mid-curve, ``TRUE`` at
# its centroid.
ELEMENTS = 400
FINE = 3200
CONVERGENCE = (400, 800, 1600)
HEYMAN = mass_on_midcurve(CircularArch.from_ratio(180.0, 0.15))
TRUE = CircularArch.from_ratio(180.0, 0.15)


# %%
# The smallest friction coefficient, the state at the limit, the minimum thickness
# ---------------------------------------------------------------------------------
# With the weight on the mid-curve the loads do not depend on the thickness, so the
# smallest ``mu`` at which a very thick arch stands is the smallest at which any does (a
# bisection on ``mu``). At the minimum thickness, the most central admissible state
# gives the thrust ``h = H / (w r)``, the intrados hinge and the section that needs the
# most friction.
def mu_min(curve, n: int, tol: float = 1e-9) -> float:
    """Smallest friction coefficient at which a very thick arch stands (with the weight
    on the mid-curve the loads do not depend on the thickness, so no thinner arch
    does)."""
    thick = curve.with_thickness_scaled(1.0 / curve.t_over_r)
    nodes = uniform_nodes(curve, n)
    lo, hi = 0.0, 1.0
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        # fibres slack: the joints only
        lo, hi = (lo, mid) if stands_on(thick, nodes, False, mid) else (mid, hi)
    return hi


def state(curve, n: int, mu=None):
    """Thrust ``h = H / (w r)``, and the angles from the crown (deg) of the intrados
    hinge and of the section needing the most friction (springing excluded), of the most
    central state of ``curve`` (at its minimum thickness: the limit state)."""
    st = statics(discretize(curve, uniform_nodes(curve, n)))
    stand, *_ = margin_search(st, 1, joint_rows(st, 1, mu), np.empty(0),
                              np.empty(0, int), 1e-10, 50)
    z = np.r_[stand.z[:st.k], 0.0, 1.0]
    s = np.linspace(0.0, 0.5 * curve.length, 90_001)[1:]
    S, Np, Nm = section_force_rows(st, s) @ z
    h = np.pi * (Np[-1] + Nm[-1])          # N at the crown in units of w pi r
    phi = 90.0 - np.degrees(s / curve.radius)

    def where(f):                         # parabola through the extreme sample
        i = int(np.clip(np.argmin(f), 1, f.size - 2))
        a, b, c = f[i - 1], f[i], f[i + 1]
        if not np.isfinite([a, b, c]).all() or a - 2 * b + c <= 0:
            return phi[i]
        return phi[i] - 0.5 * (phi[i + 1] - phi[i - 1]) / 2 * (c - a) / (a - 2 * b + c)

    inner = phi > 1.0
    # the thrust line on the intrados: N- = 0
    hinge = where(np.where(inner & (phi < 89.0), Nm, np.inf))
    slide = None if mu is None else \
        where(np.where(inner & (phi < 89.0), -np.abs(S) / (Np + Nm), np.inf))
    return h, hinge, slide


def t_min(curve, n: int, mu=None, tol: float = 1e-10) -> float:
    return thickness_on(curve, uniform_nodes(curve, n), True, tol, friction=mu).t_over_R


# %%
# The table
# ---------
# Each row against Cocchetti & Rizzi's value where they give one (``ref.``), in two
# tables: the thickness and the thrust, then where the hinge and the sliding are; the
# last line is the convergence of ``mu_min`` with the mesh.
def table(n: int = ELEMENTS, n_fine: int = FINE) -> list[tuple]:
    """Rows ``(case, fembeam t/r, reference t/r, fembeam h, reference h, hinge, ref.,
    slide, ref.)``. The limiting ``mu`` is governed by a section between the joints, so
    it is found on the ``n_fine`` mesh (friction is imposed at the joints; the fibres at
    every section)."""
    rows = []
    t0 = t_min(HEYMAN, n)
    h, hinge, _ = state(HEYMAN.with_thickness_scaled(t0 / HEYMAN.t_over_r), n)
    rows.append(("no sliding, weight on the mid-curve", t0, 0.107426, h, 0.621772,
                 hinge, 54.4963))
    mu = 0.35
    t1 = t_min(HEYMAN, n, mu)
    h, hinge, _ = state(HEYMAN.with_thickness_scaled(t1 / HEYMAN.t_over_r), n, mu)
    rows.append((f"mu = {mu}, weight on the mid-curve", t1, None, h, 0.5 * np.pi * mu,
                 hinge, None))
    m = mu_min(HEYMAN, n_fine)
    t2 = t_min(HEYMAN, n_fine, m * (1 + 1e-8))
    h, hinge, slide = state(HEYMAN.with_thickness_scaled(t2 / HEYMAN.t_over_r), n_fine,
                            m * (1 + 1e-8))
    rows.append((f"mu = mu_min = {m:.6f} (ref. 0.309215)", t2, 0.200637, h, 0.485714,
                 hinge, 60.5134, slide, 28.6362))
    t3 = t_min(TRUE, n)
    h, hinge, _ = state(TRUE.with_thickness_scaled(t3 / TRUE.t_over_r), n)
    rows.append(("no sliding, true centroids", t3, 0.107478, h, None, hinge, None))
    return rows


def fmt(x, d=6):
    return "-" if x is None else f"{x:.{d}f}"


def main() -> None:
    print(f"semicircular arch, radial joints: {ELEMENTS} elements ({FINE} at mu_min), "
          "fibres checked\nat every section, friction at the joints")
    rows = [tuple(r) + (None,) * (9 - len(r)) for r in table()]
    print("| case | t/r | ref. | h = H/(w r) | ref. |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {fmt(r[1])} | {fmt(r[2])} | {fmt(r[3])} | {fmt(r[4])} |")
    print()
    print("| case | hinge (deg from crown) | ref. | sliding (deg) | ref. |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r[0]} | {fmt(r[5], 3)} | {fmt(r[6], 4)} | {fmt(r[7], 3)} "
              f"| {fmt(r[8], 4)} |")
    mus = [f"{n} elements {mu_min(HEYMAN, n):.7f}" for n in CONVERGENCE]
    # over two lines: one is wider than the page
    print("mu_min against the mesh: " + ", ".join(mus[:2]) + ",\n    "
          + ", ".join(mus[2:]))


if __name__ == "__main__":
    main()


# %%
# The minimum thickness against the friction coefficient
# -------------------------------------------------------
# Between ``mu_min`` and the coefficient at which no joint slides at the limit, friction
# governs: the arch needs more thickness than its hinges alone ask for.
def figure():
    import matplotlib.pyplot as plt

    mus = np.linspace(0.31, 0.45, 15)
    t = [t_min(HEYMAN, ELEMENTS, mu, tol=1e-6) for mu in mus]   # 1e-6: below a dot
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(mus, t, "o-", ms=3.5,
            label=f"fembeam, weight on the mid-curve ({ELEMENTS} elements)")
    ax.plot([0.309215], [0.200637], "kx", ms=8,
            label="Cocchetti & Rizzi (2020): at mu_min")
    ax.axhline(0.107426, color="k", lw=0.8, ls=":",
               label="Cocchetti & Rizzi (2020): no sliding")
    ax.set_xlabel("friction coefficient mu"), ax.set_ylabel("minimum thickness t / r")
    ax.legend(fontsize=8), ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    figure().savefig("ex05.png", dpi=110)
