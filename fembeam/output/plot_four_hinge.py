"""Figure: the optimal four-hinge impulse line versus the QP's hinge zones.

``python -m fembeam.output.plot_four_hinge OUT.png [EMBRACE T_OVER_R]`` draws, around the two
inner post-impact hinges of a continuous arch, (top) the eccentricity e/t of the
optimal four-hinge impulse line and of the QP's impulse line, (bottom) the QP's
relative rotation per unit angle at the open joints for several meshes: a converged
distribution of rotation over a zone, not a point hinge (docs/four_hinge.md).
"""
from __future__ import annotations

import sys

import numpy as np

from ..analysis import analyze
from ..geometry import CircularArch
from ..mechanisms.hinge import side_of
from ..mechanisms.impulse_line import four_hinge_impulse_line
from ..mechanisms.mechanism import Mechanism
from ..mechanisms.restricted import best_four_hinge_continuous

__all__ = ["plot_hinge_zone"]


def plot_hinge_zone(out: str, embrace: float = 157.5, t_over_r: float = 0.15, meshes=(200, 800, 3200)):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = CircularArch.from_ratio(embrace, t_over_r)
    res = {n: analyze(c, elements=n, thrust=False) for n in meshes}
    fine = res[meshes[-1]]
    pre = Mechanism.from_hinges(c, fine.hinges_before).closing()
    best = best_four_hinge_continuous(pre)
    line = four_hinge_impulse_line(pre, best.after, np.linspace(0, c.length, 4001))
    ang4 = best.after.angles_deg()
    fig, ax = plt.subplots(2, 2, figsize=(10, 6), sharex="col")
    for col, (a0, side) in enumerate(zip(ang4[1:3], best.after.sides[1:3])):
        lo, hi = a0 - 10, a0 + 10
        m = (line.angle_deg >= lo) & (line.angle_deg <= hi)
        sgn = float(side_of(side).code)
        axe = ax[0, col]
        axe.axhline(0.5, color="k", lw=0.8)
        axe.plot(line.angle_deg[m], sgn * line.eccentricity[m] / line.thickness[m], "C3",
                 label=f"four-hinge optimum, r = {best.r:.6f}")
        imp = fine.impact
        mm = (imp.disc.joint_angle_deg >= lo) & (imp.disc.joint_angle_deg <= hi)
        axe.plot(imp.disc.joint_angle_deg[mm], sgn * imp.eccentricity[mm] / imp.disc.joint_thickness[mm], "C0--",
                 label=f"QP, {meshes[-1]} elements, r = {fine.r:.6f}")
        axe.axvline(a0, color="C3", lw=0.6, ls=":")
        axe.set_ylim(0.44, 0.506)
        axe.set_ylabel(f"e/t toward the {side}")
        axe.set_title(f"C'{'13' if col == 0 else '23'}: {side} hinge at {a0:.2f} deg")
        axe.legend(fontsize=8, loc="lower center")
        axr = ax[1, col]
        for n, r in res.items():
            h = [x for x in r.impact.hinges if lo <= x.angle_deg <= hi and x.side == side]
            dphi = float(c.angle_deg(c.length)) / n
            a = np.array([x.angle_deg for x in h])
            w = np.array([abs(x.rotation) for x in h]) / dphi
            total = sum(abs(x.rotation) for x in r.impact.hinges if x.side == side and lo <= x.angle_deg <= hi)
            axr.step(a, w / total, where="mid", label=f"{n} elements ({len(h)} open joints)")
        axr.set_xlabel("angle from the left springing (deg)")
        axr.set_ylabel("QP rotation density / zone total (1/deg)")
        axr.legend(fontsize=8)
    fig.suptitle(f"Continuous arch {embrace:g} deg, t/R = {t_over_r:g}: the QP spreads C'13 and C'23 "
                 f"over zones; the four-hinge line leaves the thickness beside them", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    plot_hinge_zone(args[0] if args else "four_hinge_zone.png", *[float(x) for x in args[1:3]])
