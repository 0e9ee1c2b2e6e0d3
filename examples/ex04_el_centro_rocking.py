"""Example 4: does the paper's arch (beta = 157.5 deg, t/R = 0.15, R = 5 m) survive El Centro?

The 1940 El Centro record (shipped with fembeam), scaled to peak ground accelerations of
0.4 ... 1.0 g: the outcome, the number of impacts, the peak rotation and when the thrust line
first leaves the section (from then on the one-mechanism model is no longer valid).  The
member is set up once (limit analyses, impact transitions) and run under every scaling.
"""
from fembeam import CircularArch
from fembeam.dynamics import GroundMotion, Rocker

arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
rocker = Rocker(arch, qp=False)
record = GroundMotion.record("elcentro")
runs = {pga: rocker.run(record.to_pga(pga)) for pga in (0.4, 0.6, 0.8, 1.0)}


def visualize(path="ex04.png"):
    from fembeam.output.motion import plot_history

    plot_history(runs[1.0], path)


if __name__ == "__main__":
    print(f"A_L = {rocker.A[1]:.6f} g; El Centro 1940 (PGA {record.pga:.3f} g) scaled to:")
    for pga, res in runs.items():
        when = f"at t = {res.t_overturn:.3f} s" if res.outcome == "overturned" else ""
        exit_ = "never" if res.thrust_line_exits_at is None else f"{res.thrust_line_exits_at:.3f} s"
        print(f"  PGA {pga:.1f} g: {res.outcome} {when}".rstrip()
              + f"; {len(res.impacts)} impacts, peak rotation {res.peak_rotation:.5f} rad, thrust line exits {exit_}")
    visualize()
