"""Example 3: Housner's rocking block as a special case of the arch model.

A straight member on a rigid base with a free top end; r must equal (1 - 1.5 sin^2 a)^2.
"""
import numpy as np

from fembeam import StraightMember, analyze

slenderness = np.array([0.05, 0.1, 0.2, 0.4, 0.8])   # b/h = tan a
r_model = np.array([analyze(StraightMember(height=2.0, width=2.0 * bh), voussoirs=1).r for bh in slenderness])
a = np.arctan(slenderness)
r_housner = (1 - 1.5 * np.sin(a) ** 2) ** 2

if __name__ == "__main__":
    for bh, rm, rh in zip(slenderness, r_model, r_housner):
        print(f"b/h = {bh:4.2f}: r = {rm:.10f}  Housner {rh:.10f}  diff {abs(rm - rh):.1e}")
