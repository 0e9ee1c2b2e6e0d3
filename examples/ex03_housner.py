"""
A rocking block against Housner
===============================

Housner's block is the simplest member the arch model contains: a straight member of
height ``h`` and width ``b`` on a rigid base, one voussoir, free at the top. Its impact
on the opposite corner keeps the fraction ``r = (1 - 1.5 sin^2 a)^2`` of the kinetic
energy, with ``tan a = b/h`` (Housner 1963), and it starts to rock at ``A_L = tan a``.
The impact QP, which knows nothing of blocks, must give the same numbers.

Run as a script: ``python examples/ex03_housner.py``.
"""
import numpy as np

from fembeam import StraightMember, analyze

slenderness = np.array([0.05, 0.1, 0.2, 0.4, 0.8])   # b/h = tan a
r_model = np.array([analyze(StraightMember(height=2.0, width=2.0 * bh), voussoirs=1).r
                    for bh in slenderness])
a = np.arctan(slenderness)
r_housner = (1 - 1.5 * np.sin(a) ** 2) ** 2

for bh, rm, rh in zip(slenderness, r_model, r_housner):
    print(f"b/h = {bh:4.2f}: r = {rm:.10f}  Housner {rh:.10f}  diff {abs(rm - rh):.1e}")

# %%
# Over the whole range of slenderness: above ``tan a = sqrt(2)`` no compatible motion
# does positive work after the impact and the block is arrested (``r = 0``).
if __name__ == "__main__":
    import matplotlib.pyplot as plt

    fine = np.linspace(0.02, 1.6, 60)
    r_fine = [analyze(StraightMember(height=2.0, width=2.0 * bh), voussoirs=1).r
              for bh in fine]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    x = np.linspace(0.0, 1.6, 400)
    housner = np.where(x < np.sqrt(2), (1 - 1.5 * np.sin(np.arctan(x)) ** 2) ** 2, 0.0)
    ax.plot(x, housner, "k-", lw=1,
            label="Housner (1963), 0 beyond tan a = sqrt 2")
    ax.plot(fine, r_fine, "o", ms=3.5, mfc="none",
            label="fembeam: impact QP, one voussoir")
    ax.set_xlabel("b / h = tan a"), ax.set_ylabel("r = K'/K")
    ax.legend(), ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig("ex03.png", dpi=110)
