"""Where a snap-through of a voussoir arch on spreading supports ends: the multi-block simulation
held just past the snap against ``fembeam supports`` (its snaps simulated with the supports held
at the event) and the three-hinge state of least potential energy.  For each case it prints the
intrados hinges at which the simulated arch comes to rest (or that it collapsed), those of
``fembeam supports`` at the same displacement, and the potential energy (J/m) of the admissible
symmetric three-hinge states (crown hinge kept) at the held displacement, the least one marked.
Run: ``python benchmarks/supports_snaps.py`` (about a minute of CPU on a warm kernel cache)."""
from __future__ import annotations

import argparse

import numpy as np

from fembeam import CircularArch
from fembeam.analysis.supports import Chain, Movement, _Path, supports
from fembeam.dynamics.ground import GroundMotion
from fembeam.fem import uniform_nodes
from fembeam.simulation.stepper import Simulator
from fembeam.simulation.support_motion import SupportMotion

CASES = ((48, 0.1155), (100, 0.1065), (24, 0.1875))   # voussoirs, displacement held (m)


def simulated(arch, n: int, held: float, rate: float, t_end: float) -> str:
    """The hinges at rest of the simulation held at ``held`` (m), or its outcome."""
    ground = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none", True)
    res = Simulator(arch, voussoirs=n).run(ground, dt=1e-3, t_end=t_end, dt_out=0.05,
                                          support_motion=SupportMotion.of("spread", rate, up_to=held))
    if res.outcome != "rest":
        return f"{res.outcome} at {res.t_collapse:.2f} s" if res.t_collapse else res.outcome
    rel = np.diff(np.r_[0.0, res.q_end[:-1, 2], 0.0])
    return "hinges at joints " + ", ".join(str(j) for j in np.flatnonzero(np.abs(rel) > 1e-4))


def energies(arch, n: int, held: float) -> list[tuple[int, float]]:
    """``(joint k, V)`` of the admissible states with intrados hinges at ``k`` and ``n - k`` and
    the extrados crown hinge, at the spreading ``held`` (m)."""
    ch = Chain(arch, uniform_nodes(arch, n))
    path = _Path(ch, Movement.of("spread"))
    uL, _ = path.supports_at(held)
    out = []
    for k in range(1, n // 2):
        side = np.zeros(ch.J, int)
        side[[k, n - k]], side[n // 2] = 1, -1
        guess = np.zeros(ch.J)
        guess[[k, n - k]], guess[n // 2] = -0.1, 0.2
        sol = path.solve(held, guess, side)
        if sol is None or np.min(path.margins(held, sol[0], side)[0]) < -1e-9:
            continue
        out.append((k, 9.81 * ch.potential(sol[0], side, uL)))
    return out


def dynamic(arch, n: int, held: float) -> str:
    """The hinges at ``held`` (m) of ``fembeam supports`` with its snaps simulated (the default),
    or its collapse."""
    res = supports(arch, Movement.of("spread"), voussoirs=n, up_to=held)
    if res.outcome == "collapsed":
        return f"collapsed at {res.capacity:.4f} m"
    return "hinges at joints " + ", ".join(str(j) for j in np.flatnonzero(res.frames[-1][3]))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rate", type=float, default=0.0025, help="spreading rate (m/s)")
    p.add_argument("--hold", type=float, default=15.0, help="time held after the supports stop (s)")
    a = p.parse_args()
    arch = CircularArch()
    for n, held in CASES:
        print(f"{n} voussoirs held at {held} m: simulation {simulated(arch, n, held, a.rate, held / a.rate + a.hold)}")
        print(f"  fembeam supports (dynamic snaps): {dynamic(arch, n, held)}")
        rows = energies(arch, n, held)
        least = min(rows, key=lambda r: r[1])[0] if rows else None
        print("  admissible states (joint k: V J/m): " + ", ".join(
            f"{k}: {v:.3f}{' (least)' if k == least else ''}" for k, v in rows))


if __name__ == "__main__":
    main()
