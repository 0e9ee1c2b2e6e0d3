"""Example 1: the continuous arch of the paper's Sect. 6.2 (beta = 157.5 deg, t/R = 0.15).

Limit analysis then impact; prints A_L (paper: 0.353 g) and r (paper: 0.606).
"""
from fembeam import CircularArch, analyze

arch = CircularArch.from_ratio(157.5, 0.15, radius=10.0)
result = analyze(arch, elements=200)
A_L, r = result.A_L, result.r


def visualize():
    import matplotlib.pyplot as plt
    import numpy as np

    imp = result.impact
    phi = imp.disc.joint_angle_deg
    fig, ax = plt.subplots(figsize=(7, 3))
    ax.plot(phi, 2 * imp.eccentricity / imp.disc.joint_thickness, label="impulse line 2e/t")
    ax.plot(phi, 2 * result.limit.eccentricity / result.limit.disc.joint_thickness, "--", label="thrust line 2e/t")
    ax.axhline(1, color="k", lw=0.5), ax.axhline(-1, color="k", lw=0.5)
    ax.set_xlabel("angle from the left springing (deg)"), ax.set_ylabel("eccentricity / (t/2)")
    ax.set_title(f"A_L = {A_L:.4f} g, r = {r:.4f}"), ax.legend()
    return fig


if __name__ == "__main__":
    print(f"A_L = {A_L:.6f} g, r = {r:.6f}")
    print("hinges before:", [(round(h.angle_deg, 2), h.side) for h in result.hinges_before])
    print("hinges after: ", [(round(h.angle_deg, 2), h.side) for h in result.hinges_after])
    visualize().savefig("ex01.png", dpi=120)
