"""
The paper's arch: from the limit analysis to the impulse line
=============================================================

The continuous circular arch of the paper's Sect. 6.2: embrace ``beta = 157.5`` deg,
thickness over radius ``t/R = 0.15`` (here ``R = 10`` m; ``A_L`` and ``r`` do not depend
on the size), 200 rigid elements. The paper gives ``A_L = 0.353`` g and ``r = 0.606``.

Run as a script: ``python examples/ex01_paper_arch.py`` prints the three lines below and
writes ``ex01.png`` and ``ex01_arch.png``.
"""
from fembeam import CircularArch, analyze

# %%
# Limit analysis, then the impact
# -------------------------------
# :func:`fembeam.analyze` runs the static linear programme (the incipient rocking
# acceleration ``A_L`` in g, the four hinges of the mechanism before the impact, the
# thrust line), then the impact QP (the restitution coefficient ``r = K'/K``, the hinges
# after the impact, the impulse line), and checks both. Angles are measured from the
# left springing; a hinge's side is the edge it pivots on.
arch = CircularArch.from_ratio(157.5, 0.15, radius=10.0)
result = analyze(arch, elements=200)
A_L, r = result.A_L, result.r

print(f"A_L = {A_L:.6f} g, r = {r:.6f}")
print("hinges before:",
      ", ".join(f"{round(h.angle_deg, 2)} {h.side}" for h in result.hinges_before))
print("hinges after: ",
      ", ".join(f"{round(h.angle_deg, 2)} {h.side}" for h in result.hinges_after))


# %%
# The thrust line and the impulse line
# ------------------------------------
# Both lines as eccentricities ``2e/t`` at the joints: ``+1`` on the intrados, ``-1`` on
# the extrados. The thrust line of the limit state touches the edges at the four hinges
# before the impact; the impulse line (the line of action of the internal impulses of
# the impact) at the four hinges after it.
def visualize():
    import matplotlib.pyplot as plt

    imp = result.impact
    phi = imp.disc.joint_angle_deg
    fig, ax = plt.subplots(figsize=(7, 3))
    lim = result.limit
    ax.plot(phi, 2 * imp.eccentricity / imp.disc.joint_thickness,
            label="impulse line 2e/t")
    ax.plot(phi, 2 * lim.eccentricity / lim.disc.joint_thickness, "--",
            label="thrust line 2e/t")
    ax.axhline(1, color="k", lw=0.5), ax.axhline(-1, color="k", lw=0.5)
    ax.set_xlabel("angle from the left springing (deg)")
    ax.set_ylabel("eccentricity / (t/2)")
    ax.set_title(f"A_L = {A_L:.4f} g, r = {r:.4f}"), ax.legend()
    return fig


if __name__ == "__main__":
    visualize().savefig("ex01.png", dpi=120, bbox_inches="tight")

# %%
# The same lines drawn on the arch, as in the paper's figures (``fembeam analyze
# --figure``): hinges before the impact as rings, after it as dots.
if __name__ == "__main__":
    from fembeam.output.plotting import plot_paper_figure

    plot_paper_figure(result, "ex01_arch.png", dpi=100)
