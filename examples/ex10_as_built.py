"""
A 10 m semicircular bridge arch with fill
=========================================

A semicircular masonry arch of 10 m span (mid-curve radius ``R = 5`` m, ring
``t = 0.70`` m, masonry 2000 kg/m^3) filled with soil of 1800 kg/m^3 up to a road 0.5 m
above the crown. Everything is per metre of barrel width. Three questions an assessor
asks of such a bridge:

* where does one axle load do the most harm, and what multiple of it collapses the arch
  (``fembeam load-scan``)?
* what horizontal thrust can the arch exert on its abutments under its dead loads
  (the thrust range of ``fembeam analyze``)?
* how does the fill change the arch's response to an earthquake (``fembeam rock`` and
  ``fembeam rock --model auto`` with and without the fill)?

The fill model (columns of fill carried by the voussoir under them, moving with it) is
in the documentation's page "Arches as built".

Run as a script: ``python examples/ex10_as_built.py`` prints the numbers below and
writes ``ex10_load_scan.png``, ``ex10_thrust.png`` and ``ex10_rocking.png``.
"""
from fembeam import CircularArch, analyze
from fembeam.analysis.load_factor import load_factor
from fembeam.auto import AutoModel
from fembeam.dynamics import GroundMotion, Rocker
from fembeam.geometry.asbuilt import build
from fembeam.studies.load_scan import load_scan

R, T_OVER_R, RHO = 5.0, 0.14, 2000.0           # m, -, kg/m^3: t = 0.70 m
RHO_FILL, ROAD = 1800.0, 0.5                    # kg/m^3, m above the crown's extrados
P = 50.0                                        # kN/m: one axle load per metre of width

# %%
# The arch as built
# -----------------
# :func:`~fembeam.geometry.asbuilt.build` returns the arch carrying its fill: the same
# member for every model (statics, impact, rocking, simulation), whose pieces carry the
# column of fill above their extrados. The fill more than doubles the mass.
bare = CircularArch.from_ratio(180.0, T_OVER_R, radius=R, density=RHO)
built = build(bare, fill_density=RHO_FILL, fill_depth=ROAD)


def mass(curve):
    """kg per metre of width."""
    return float(curve.segment_inertia(0.0, curve.length)[0][0])


print(f"span {2 * R:g} m, ring t = {T_OVER_R * R:.2f} m, "
      f"road at y = {built.road_level:.2f} m")
print(f"masonry {mass(bare):.0f} kg/m, fill {mass(built) - mass(bare):.0f} kg/m, "
      f"weight as built {mass(built) * 9.81 / 1000:.2f} kN/m")

# %%
# One axle load moved across the span
# -----------------------------------
# The load factor of one downward load ``P`` (the multiple of ``P`` that collapses the
# arch, the self weight and the fill at their values) at 41 positions on an arch of 24
# voussoirs. Each position is one small linear programme on the same equilibrium
# operator. Near the springings no multiple of the load collapses the arch
# (``no_mechanism``). On voussoirs the curve is a saw-tooth: a load beside a joint can
# open a hinge right under it. The continuous arch (every section checked, the mesh
# through the load), which may hinge anywhere, gives a smaller factor at the same
# position, bracketed between a mechanism and an admissible thrust line.
scan = load_scan(built, P, positions=41, voussoirs=24)
i = scan.critical
x_crit = float(scan.x[i])
hinges = ", ".join(f"{h.angle_deg:.1f} deg {h.side}" for h in scan.results[i].hinges)
print(f"load {P:g} kN/m: smallest load factor {scan.min_factor:.4f} "
      f"at x = {x_crit:g} m (collapse load {scan.min_factor * P:.1f} kN/m)")
print(f"  mechanism:\n    {hinges}")
n_none = sum(s == "no_mechanism" for s in scan.status)
print(f"  positions without a mechanism: {n_none} of {scan.x.size}")
cont = load_factor(built, [(x_crit, P)])
print(f"  continuous arch, load at x = {x_crit:g} m: load factor {cont.value:.4f}\n"
      f"    (admissible lower bound {cont.lower:.4f})")
bare_factor = load_factor(bare, [(x_crit, P)], voussoirs=24).value
print(f"  the bare ring (no fill), 24 voussoirs, same position: {bare_factor:.4f}")

# %%
# The curve and the mechanism at the critical position (``fembeam load-scan ...
# --plot``).
if __name__ == "__main__":
    from fembeam.output.load_scan import plot_load_scan

    plot_load_scan(scan, "ex10_load_scan.png", dpi=110)

# %%
# The thrust range
# ----------------
# Under the dead loads alone the horizontal thrust on the springings can take any value
# in ``[H_min, H_max]`` (two linear programmes in the three redundants; every state in
# between proves the arch safe). The fill raises both ends; ``analyze`` with the axle at
# its critical position also gives the collapse under it.
res = analyze(built, voussoirs=24, loads=[(x_crit, P)])
ref = analyze(bare, voussoirs=24)
print(f"thrust range as built: H_min = {res.thrust.H_min:.2f} kN/m, "
      f"H_max = {res.thrust.H_max:.2f} kN/m")
print(f"thrust range bare:     H_min = {ref.thrust.H_min:.2f} kN/m, "
      f"H_max = {ref.thrust.H_max:.2f} kN/m")
print(f"load factor at x = {x_crit:g} m: {res.load_factor:.4f} ({res.load.status})")

# %%
# The two extreme thrust lines under the dead loads, and the collapse under the factored
# axle load (``fembeam analyze ... --thrust-figure``).
if __name__ == "__main__":
    from fembeam.output.asbuilt import plot_thrust_range

    plot_thrust_range(res, "ex10_thrust.png", dpi=110)

# %%
# El Centro, with and without the fill's mass
# -------------------------------------------
# The same ring of 9 voussoirs, bare and as built, under the 1940 El Centro record
# scaled to peak ground accelerations of 0.3 and 0.4 g. ``Rocker`` is ``fembeam rock``
# (one mechanism between impacts); the fill's columns move with their voussoirs, so the
# fill changes the onset ``A_L``, the restitution ``r`` of every impact and the
# energies, which are in J per metre of width (``W_ground``: the work of the ground on
# the arch; ``dissip.``: the energy lost in the impacts). Once the dynamic thrust line
# of the one-mechanism model leaves a section (column ``exit``, in s) other hinges would
# open and ``rock``'s verdict is outside its model; ``AutoModel`` (``fembeam rock
# --model auto``) then hands the motion over to the multi-block simulation, each body
# carrying its columns of fill. Its joints do not slide here; ``AutoModel(arch,
# voussoirs=9, friction=0.6)`` would let them slide by Coulomb's law.
VOUSSOIRS = 9
record = GroundMotion.record("elcentro")
print(f"El Centro 1940: PGA {record.pga:.3f} g as recorded")
runs = {}
for name, arch in (("bare", bare), ("as built", built)):
    rocker = Rocker(arch, voussoirs=VOUSSOIRS, qp=False)
    auto = AutoModel(arch, voussoirs=VOUSSOIRS)
    r = analyze(arch, voussoirs=VOUSSOIRS).r
    print(f"{name:>9}: mass {mass(arch):.0f} kg/m, A_L = {rocker.A[1]:.4f} g, "
          f"r = {r:.4f}")
    for pga in (0.3, 0.4):
        gm = record.to_pga(pga)
        runs[name, pga] = rocker.run(gm), auto.run(gm)

print(f"{'':8} {'PGA':>3} {'rock':>10} {'peak rad':>8} {'impacts':>7} {'W_ground':>8} "
      f"{'dissip.':>7} {'exit s':>6}  {'auto':>10} {'peak rad':>8}")
for (name, pga), (rk, au) in runs.items():
    exit_ = "-" if rk.thrust_line_exits_at is None else f"{rk.thrust_line_exits_at:.2f}"
    print(f"{name:>8} {pga:3.1f} {rk.outcome:>10} {rk.peak_rotation:8.4f} "
          f"{len(rk.impacts):7d} {rk.ground_work:8.0f} {rk.dissipated:7.0f} "
          f"{exit_:>6}  "
          f"{au.outcome:>10} {au.peak_rotation:8.4f}")


# %%
# The histories at 0.4 g: the ground acceleration, the rotation ``theta`` of the first
# moving voussoir along ``rock``'s mechanisms, and the largest rotation of any voussoir
# in the ``auto`` model (simulation intervals included). A run that overturns ends
# there.
def visualize(pga=0.4, path="ex10_rocking.png"):
    import matplotlib.pyplot as plt

    fig, (ax_a, ax_r, ax_s) = plt.subplots(3, 1, sharex=True, figsize=(8.0, 7.0))
    t_max = 15.0
    gm = record.to_pga(pga)
    shown = gm.t <= t_max
    ax_a.plot(gm.t[shown], gm.a[shown], color="black", lw=0.6)
    for (name, level), (rk, au) in runs.items():
        if level != pga:
            continue
        color = "tab:grey" if name == "bare" else "tab:brown"
        h, a = rk.history, au.history
        keep, kept = h["t"] <= t_max, a["t"] <= t_max
        ax_r.plot(h["t"][keep], h["theta"][keep], color=color, lw=1.0,
                  label=f"{name}: {rk.outcome}")
        ax_s.plot(a["t"][kept], a["max_rotation"][kept], color=color, lw=1.0,
                  label=f"{name}: {au.outcome}")
    ax_a.set_ylabel("a_g (g)")
    ax_r.set_ylabel("rock: theta (rad)")
    ax_s.set_ylabel("auto: max rotation (rad)")
    ax_s.set_xlabel("t (s)")
    for ax in (ax_r, ax_s):
        ax.set_ylim(-0.45, 0.45) if ax is ax_r else ax.set_ylim(0.0, 0.45)
        ax.legend(frameon=False, fontsize=8, loc="upper left")
    for ax in (ax_a, ax_r, ax_s):
        ax.grid(alpha=0.3)
    ax_a.set_title(f"El Centro at PGA {pga:g} g, {VOUSSOIRS} voussoirs")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    visualize()
