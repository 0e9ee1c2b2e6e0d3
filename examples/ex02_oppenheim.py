"""Example 2: Oppenheim's arch, 7 voussoirs, t/R = 0.15 (paper Sect. 6.1).

beta = 150 deg: A_L = 0.444 g, r_max = 0.532; beta = 157.5 deg: A_L = 0.370 g, r_max = 0.560
with five hinges open after the impact.
"""
from fembeam import CircularArch, analyze

results = {beta: analyze(CircularArch.from_ratio(beta, 0.15, radius=10.0), voussoirs=7)
           for beta in (150.0, 157.5)}
table = {beta: (res.A_L, res.r, len(res.hinges_after)) for beta, res in results.items()}

if __name__ == "__main__":
    for beta, (A_L, r, n) in table.items():
        print(f"beta = {beta:5.1f} deg: A_L = {A_L:.4f} g, r_max = {r:.4f}, {n} hinges after the impact")
