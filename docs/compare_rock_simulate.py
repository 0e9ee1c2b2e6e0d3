"""Overturning of masonry arches: the one-degree-of-freedom model (``fembeam rock``) against the
multi-block Moreau-Jean simulation (``fembeam simulate``).  Data and figures of docs/comparison.md.

    python docs/compare_rock_simulate.py            # full study (one process)
    python docs/compare_rock_simulate.py --quick    # one arch, one pulse, one period (< 60 s)

Writes docs/data/comparison_spectra.csv, docs/data/comparison_elcentro.csv, docs/data/comparison_thrust.csv,
docs/figures/comparison_spectra.png, docs/figures/comparison_elcentro.png (full mode; --quick
writes nothing unless --out is given).  Rows are appended to the CSV as they finish, so an
interrupted run leaves the finished periods.
"""
from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

from fembeam import CircularArch
from fembeam.dynamics.ground import GroundMotion
from fembeam.dynamics.rocking import Rocker
from fembeam.simulation import Simulator
from fembeam.studies.spectrum import collapse_scale, pulse, pulse_end, spectrum

HERE = Path(__file__).resolve().parent
VOUSSOIRS = 7
RADIUS = 5.0                                   # m
ARCHES = {"paper": (157.5, 0.15), "oppenheim": (150.0, 0.15)}   # embrace (deg), t/R
KINDS = ("rect", "sine")
PERIODS = [0.2, 0.28, 0.4, 0.56, 0.8, 1.13, 1.6, 2.26]            # s (durations for rect)
FREE = 3.0                                     # free time after the pulse, in sqrt(L/g)
DT = 1e-3                                      # s, simulate's step
ROCK_TOL = 1e-3                                # relative bracket of rock's bisection
SIM_STEPS = 8                                  # bisection steps of simulate on [0.5, 2] x rock
BRACKET = (0.5, 2.0)
RECORD_SECONDS = 15.0                          # El Centro truncated to its first 15 s
FIELDS = ["arch", "kind", "period_s", "rock_A_g", "sim_A_g", "sim_lo_g", "sim_hi_g", "ratio", "sim_runs", "time_s"]


def arch(name: str) -> CircularArch:
    beta, t_r = ARCHES[name]
    return CircularArch.from_ratio(beta, t_r, radius=RADIUS)


def free_time(curve) -> float:
    return FREE * math.sqrt(curve.length / 9.81)


def rock_amplitude(curve, kind: str, period: float) -> float:
    """Rock's overturning amplitude (g) of one period: fembeam.studies.spectrum (scan + bisection)."""
    res = spectrum(curve, kind, [period], voussoirs=VOUSSOIRS, workers=1, progress=False, bisect_tol=ROCK_TOL,
                   t_end_factor=FREE)
    f = res.rows[0]["first_overturning"]
    return float("nan") if f is None else float(f)


def sim_overturns(sim: Simulator, ground: GroundMotion, t_end: float) -> bool:
    return sim.run(ground, dt=DT, t_end=t_end, stop_at_overturn=True).outcome == "overturned"


def sim_bisect(sim: Simulator, make_ground, lo: float, hi: float, t_end: float, steps: int,
               floor: float | None = None) -> dict:
    """Bisection of simulate's overturning amplitude in [lo, hi] (hi checked to overturn, lo to be
    safe).  If lo overturns too, the bracket becomes [floor, lo] (``floor``: an amplitude that
    cannot move the member, safe without a run; the arch's A_L for a pulse of peak ``a``).
    Returns lo, hi (final bracket), amplitude (hi; nan if hi is safe)."""
    runs = 0
    runs += 1
    if not sim_overturns(sim, make_ground(hi), t_end):
        return {"lo": hi, "hi": float("nan"), "amplitude": float("nan"), "runs": runs}
    runs += 1
    if sim_overturns(sim, make_ground(lo), t_end):
        if floor is None or floor >= lo:
            return {"lo": float("nan"), "hi": lo, "amplitude": float("nan"), "runs": runs}
        lo, hi = floor, lo
        steps += 2
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        runs += 1
        if sim_overturns(sim, make_ground(mid), t_end):
            hi = mid
        else:
            lo = mid
    return {"lo": lo, "hi": hi, "amplitude": hi, "runs": runs}


def spectrum_row(name: str, kind: str, period: float, steps: int = SIM_STEPS) -> dict:
    clock = time.perf_counter()
    curve = arch(name)
    a_rock = rock_amplitude(curve, kind, period)
    t_end = pulse_end(kind, period) + free_time(curve)
    sim = Simulator(curve, voussoirs=VOUSSOIRS)
    if math.isfinite(a_rock):
        floor = min(Rocker(curve, voussoirs=VOUSSOIRS, qp=False).A.values())   # A_L: no motion below it
        b = sim_bisect(sim, lambda a: pulse(kind, a, period), BRACKET[0] * a_rock, BRACKET[1] * a_rock, t_end, steps,
                       floor)
    else:
        b = {"lo": float("nan"), "hi": float("nan"), "amplitude": float("nan"), "runs": 0}
    return {"arch": name, "kind": kind, "period_s": period, "rock_A_g": a_rock, "sim_A_g": b["amplitude"],
            "sim_lo_g": b["lo"], "sim_hi_g": b["hi"], "ratio": b["amplitude"] / a_rock, "sim_runs": b["runs"],
            "time_s": round(time.perf_counter() - clock, 1)}


def read_csv(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with open(path) as f:
        return [{k: (v if k in ("arch", "kind") else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]


def run_spectra(path: Path, arches, kinds, periods, steps: int = SIM_STEPS) -> list[dict]:
    done = {(r["arch"], r["kind"], r["period_s"]) for r in read_csv(path)}
    if not done:
        with open(path, "w", newline="") as f:
            csv.DictWriter(f, FIELDS).writeheader()
    for name in arches:
        for kind in kinds:
            for p in periods:
                if (name, kind, float(p)) in done:
                    continue
                row = spectrum_row(name, kind, p, steps)
                print({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
                with open(path, "a", newline="") as f:
                    csv.DictWriter(f, FIELDS).writerow(row)
    return read_csv(path)


def plot_spectra(rows: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=False)
    styles = {"paper": ("C0", "157.5 deg"), "oppenheim": ("C3", "150 deg (Oppenheim)")}
    for ax, kind in zip(axes, KINDS):
        for name, (col, lab) in styles.items():
            rs = sorted((r for r in rows if r["arch"] == name and r["kind"] == kind), key=lambda r: r["period_s"])
            if not rs:
                continue
            p = [r["period_s"] for r in rs]
            ax.plot(p, [r["rock_A_g"] for r in rs], "-o", color=col, label=f"{lab}: rock")
            ax.plot(p, [r["sim_A_g"] for r in rs], "--s", color=col, mfc="none", label=f"{lab}: simulate")
        ax.set_xscale("log")
        ax.set_yscale("log")
        from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter
        ax.xaxis.set_major_locator(FixedLocator(PERIODS))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.set_xlabel("pulse duration (s)" if kind == "rect" else "pulse period (s)")
        ax.set_ylabel("overturning amplitude (g)")
        ax.set_title("rectangular pulse" if kind == "rect" else "one-sine pulse")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"7 voussoirs, t/R = 0.15, R = {RADIUS:g} m; dt = {DT:g} s")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# --------------------------------------------------------------------------- El Centro
def elcentro(seconds: float = RECORD_SECONDS) -> GroundMotion:
    g = GroundMotion.record("elcentro")
    keep = g.t <= seconds + 1e-9
    return GroundMotion(g.t[keep], g.a[keep], name=f"El Centro, first {seconds:g} s")


def run_elcentro(csv_path: Path, fig_path: Path, below=(0.5, 0.7, 0.9), steps: int = SIM_STEPS) -> dict:
    curve = arch("paper")
    rec = elcentro()
    t_end = float(rec.t[-1]) + free_time(curve)
    clock = time.perf_counter()
    cs = collapse_scale(curve, rec, voussoirs=VOUSSOIRS, t_end=t_end, bisect_tol=ROCK_TOL, n_factors=30)
    f_rock = float(cs["first_overturning"])
    t_rock = time.perf_counter() - clock
    sim = Simulator(curve, voussoirs=VOUSSOIRS)
    b = sim_bisect(sim, rec.scaled, BRACKET[0] * f_rock, BRACKET[1] * f_rock, t_end, steps)
    rk = Rocker(curve, voussoirs=VOUSSOIRS, qp=False)
    rows = []
    for frac in below:
        f = frac * f_rock
        r = rk.run(rec.scaled(f), t_end=t_end)
        s = sim.run(rec.scaled(f), dt=DT, t_end=t_end)
        rows.append({"factor": f, "fraction_of_rock_collapse": frac, "rock_outcome": r.outcome,
                     "rock_peak_rotation": r.peak_rotation, "sim_outcome": s.outcome,
                     "sim_peak_rotation": s.peak_rotation})
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "value"])
        w.writerow(["record_seconds", RECORD_SECONDS])
        w.writerow(["pga_g", rec.pga])
        w.writerow(["rock_collapse_factor", f_rock])
        w.writerow(["rock_safe_factors_above", " ".join(f"{x:.4g}" for x in cs["safe_factors_above"])])
        w.writerow(["sim_collapse_factor", b["amplitude"]])
        w.writerow(["sim_bracket", f"{b['lo']:.5g} {b['hi']:.5g}"])
        for r in rows:
            w.writerow([f"peaks_at_{r['fraction_of_rock_collapse']:g}x", f"factor {r['factor']:.4g}; rock "
                        f"{r['rock_outcome']} {r['rock_peak_rotation']:.5g} rad; simulate {r['sim_outcome']} "
                        f"{r['sim_peak_rotation']:.5g} rad"])
    # the two histories at rock's collapse factor
    r = rk.run(rec.scaled(f_rock), t_end=t_end)
    s = sim.run(rec.scaled(f_rock), dt=DT, t_end=t_end)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 3.8))
    ax.plot(r.history["t"], np.abs(r.history["theta"]), label=f"rock: |theta| of the first moving piece ({r.outcome})")
    ax.plot(s.history["t"], s.history["max_rotation"], label=f"simulate: largest |phi| of any voussoir ({s.outcome})")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("rotation (rad)")
    ax.set_title(f"El Centro (first {RECORD_SECONDS:g} s) x {f_rock:.3f}, paper's arch, 7 voussoirs, R = {RADIUS:g} m")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(fig_path, dpi=120)
    plt.close(fig)
    out = {"rock_collapse_factor": f_rock, "sim_collapse_factor": b["amplitude"], "sim_bracket": (b["lo"], b["hi"]),
           "rows": rows, "rock_time_s": t_rock, "time_s": time.perf_counter() - clock}
    print(out, flush=True)
    return out


def thrust_check(spectra: list[dict], path: Path) -> list[dict]:
    """``rock`` run at the amplitude where ``simulate`` overturns (same pulse and end of run):
    outcome, first time its thrust line leaves the section, number of impacts."""
    out = []
    for r in spectra:
        if not (math.isfinite(r["sim_A_g"]) and (r["ratio"] < 0.9 or r["period_s"] in (0.2, 2.26))):
            continue
        curve = arch(r["arch"])
        res = Rocker(curve, voussoirs=VOUSSOIRS, qp=False).run(
            pulse(r["kind"], r["sim_A_g"], r["period_s"]), t_end=pulse_end(r["kind"], r["period_s"]) + free_time(curve),
            history=False)
        out.append({"arch": r["arch"], "kind": r["kind"], "period_s": r["period_s"], "amplitude_g": r["sim_A_g"],
                    "rock_outcome": res.outcome, "thrust_line_exits_at_s": res.thrust_line_exits_at,
                    "rock_impacts": len(res.impacts)})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, list(out[0]) if out else ["arch"])
        w.writeheader()
        w.writerows(out)
    return out


def quick() -> dict:
    """One row at a coarse tolerance (for tests): the paper's arch, rectangular pulse of 0.4 s,
    4 bisection steps of simulate."""
    return spectrum_row("paper", "rect", 0.4, steps=4)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one row, coarse (< 60 s); prints it")
    ap.add_argument("--no-elcentro", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="start the spectra CSV anew (default: resume)")
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw the spectra figure and redo the thrust-line check from the CSV")
    args = ap.parse_args(argv)
    clock = time.perf_counter()
    if args.quick:
        print(quick())
        print(f"quick: {time.perf_counter() - clock:.1f} s")
        return
    (HERE / "data").mkdir(exist_ok=True)
    (HERE / "figures").mkdir(exist_ok=True)
    path = HERE / "data" / "comparison_spectra.csv"
    if args.plot_only:
        plot_spectra(read_csv(path), HERE / "figures" / "comparison_spectra.png")
        thrust_check(read_csv(path), HERE / "data" / "comparison_thrust.csv")
        return
    if args.fresh and path.exists():
        path.unlink()
    rows = run_spectra(path, ARCHES, KINDS, PERIODS)
    plot_spectra(rows, HERE / "figures" / "comparison_spectra.png")
    thrust_check(rows, HERE / "data" / "comparison_thrust.csv")
    print(f"spectra: {time.perf_counter() - clock:.0f} s", flush=True)
    if not args.no_elcentro:
        run_elcentro(HERE / "data" / "comparison_elcentro.csv", HERE / "figures" / "comparison_elcentro.png")
    print(f"total: {time.perf_counter() - clock:.0f} s")


if __name__ == "__main__":
    main()
