"""
Oppenheim's arch: seven voussoirs
=================================

The discrete arch of the paper's Sect. 6.1: seven voussoirs, ``t/R = 0.15``, embrace 150
and 157.5 deg. Hinges can open only at the eight joints. The paper gives ``A_L = 0.444``
g and ``r_max = 0.532`` at 150 deg, ``A_L = 0.370`` g and ``r_max = 0.560`` at 157.5
deg, with five hinges open after the impact: the impact QP lets the arch choose its
motion after the impact among all the compatible ones, not only among four-hinge
mechanisms.

Run as a script: ``python examples/ex02_oppenheim.py``.
"""
from fembeam import CircularArch, analyze

results = {beta: analyze(CircularArch.from_ratio(beta, 0.15, radius=10.0), voussoirs=7)
           for beta in (150.0, 157.5)}
table = {beta: (res.A_L, res.r, len(res.hinges_after)) for beta, res in results.items()}

for beta, (A_L, r, n) in table.items():
    print(f"beta = {beta:5.1f} deg: A_L = {A_L:.4f} g, r_max = {r:.4f}, "
          f"{n} hinges after the impact")

# %%
# The hinges sit on joints, at multiples of ``beta / 7`` from the left springing:
res = results[157.5]
print("before:",
      ", ".join(f"{round(h.angle_deg, 3)} {h.side}" for h in res.hinges_before))
print("after: ",
      ", ".join(f"{round(h.angle_deg, 3)} {h.side}" for h in res.hinges_after))

# %%
# The paper's Fig. 10, drawn by ``fembeam analyze --embrace 150 --voussoirs 7
# --figure``:
if __name__ == "__main__":
    from fembeam.output.plotting import plot_paper_figure

    plot_paper_figure(results[150.0], "ex02.png", dpi=100)
