"""
Arches on spreading supports
============================

The paper's arch (embrace ``157.5`` deg, ``t/R = 0.15``, ``R = 1`` m) and a semicircle
of the same ring, on supports that move apart. Each is followed quasi-statically, with
finite displacements of its rigid pieces, from rest to collapse (``fembeam supports
--spread``): three hinges form at once (the minimum-thrust state), the crown drops, the
thrust on the supports rises, hinges migrate on the way, and the arch collapses when its
pieces form a mechanism under gravity alone. On voussoirs a hinge that jumps to another
joint (a snap-through) is followed by the rigid-body simulation with the supports held:
where the pieces come to rest, or that they fall. The method is in the documentation's
page "Moving supports".

Run as a script: ``python examples/ex11_supports.py`` prints the numbers below and
writes ``ex11_thrust.png`` and ``ex11_arch.png``.
"""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from fembeam import CircularArch  # noqa: E402
from fembeam.analysis.supports import Movement, supports  # noqa: E402
from fembeam.output.supports import plot_supports  # noqa: E402

ARCHES = {"paper's arch, 157.5 deg": CircularArch.from_ratio(157.5, 0.15),
          "semicircle, 180 deg": CircularArch.from_ratio(180.0, 0.15)}

# %%
# Capacity on voussoirs and on the continuous arch
# ------------------------------------------------
# 24 voussoirs (hinges only at their joints: exact for that arch) and the continuous
# arch on 200 rigid elements (hinges at the element joints, rolling from joint to
# joint).
results = {}
for name, arch in ARCHES.items():
    for mesh in ({"voussoirs": 24}, {"elements": 200}):
        r = supports(arch, Movement.of("spread"), **mesh)
        results[name, next(iter(mesh))] = r
        kind, n = next(iter(mesh.items()))
        print(f"{name}, {n} {kind}: capacity {r.capacity:.4f} m"
              f" = {100 * r.capacity_over_span:.2f} % of the span")
        print(f"    H {r.path[0][1]:.3f} -> {r.path[-1][1]:.3f} kN/m,"
              f" {len(r.migrations)} migrations")

# %%
# The hinges and their migrations
# -------------------------------
for (name, mesh), r in results.items():
    print(f"{name}, {mesh}: hinges at rest")
    print("    " + ", ".join(f"{h['angle_deg']:.2f} deg {h['side']}" for h in r.hinges))
    for m in r.migrations[:6]:
        print(f"    at {m['displacement']:.4f} m: hinge to {m['angle_deg']:.2f} deg"
              f" ({m['side']})")
    for sn in r.snaps:      # voussoirs: each snap-through simulated, supports held
        print(f"    snap-through at {sn['displacement']:.4f} m: {sn['ended']},"
              f" {sn['dissipated']:.3f} J/m dissipated")
    e = r.last_edge
    if e is not None:
        print(f"    collapse: edge reached last at {e['angle_deg']:.2f} deg"
              f" ({e['side']})")

# %%
# Thrust against spreading
# ------------------------
fig, ax = plt.subplots(figsize=(7, 4))
for (name, mesh), r in results.items():
    d = [row[0] / r.span * 100 for row in r.path]
    H = [row[1] for row in r.path]
    ax.plot(d, H, "-" if mesh == "elements" else "--", label=f"{name}, {mesh}")
ax.set_xlabel("span increase [% of the span]")
ax.set_ylabel("H [kN/m]")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig("ex11_thrust.png", dpi=120)

# %%
# The paper's arch at rest and at collapse
# ----------------------------------------
plot_supports(results["paper's arch, 157.5 deg", "voussoirs"], "ex11_arch.png")
