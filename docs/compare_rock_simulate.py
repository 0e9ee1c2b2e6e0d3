"""Overturning of masonry arches: the one-degree-of-freedom model (``fembeam rock``) against the
multi-block Moreau-Jean simulation (``fembeam simulate``), with the simulation's time step
converged and with Coulomb friction at the joints beside no sliding.  Data and figures of
docs/comparison.md.

    python docs/compare_rock_simulate.py            # full study (one process)
    python docs/compare_rock_simulate.py --quick    # one arch, one pulse, one period, coarse
    python docs/compare_rock_simulate.py --tables   # the page's tables, from the committed CSVs

Writes docs/data/comparison_spectra.csv, docs/data/comparison_thrust.csv (rock at simulate's
thresholds), docs/data/comparison_dt_scan.csv (around the thresholds that move with dt),
docs/data/comparison_elcentro.csv, docs/data/comparison_elcentro_scan.csv,
docs/figures/comparison_spectra.png, docs/figures/comparison_elcentro.png (full mode; --quick
writes nothing).  Rows are appended to the spectra CSV as they finish, so an interrupted run
resumes from the finished periods (--fresh starts anew).

Columns of comparison_spectra.csv (amplitudes in g): ``rock_A_g`` (rock's overturning amplitude),
for each time step ``T`` of :data:`DTS` (tag ``1ms``, ``0.5ms``, ``0.25ms``) ``lo_T_g``, ``hi_T_g``
(simulate's final bisection bracket without sliding: lo safe, hi collapses); ``sim_A_g`` =
``hi`` at :data:`DT_REF` (the dt-converged value), ``sim_dt_change`` = ``|hi(0.5ms) - hi(0.25ms)| /
hi(0.25ms)`` (its error estimate) and ``ratio = sim_A_g / rock_A_g``; ``scan_first_g`` the first
amplitude that collapses on a grid from A_L up to ``lo`` (the bisection's check; nan: none);
``demand`` the largest ``|P_t|/N`` of the no-sliding run at ``lo`` (0.25 ms); for each Coulomb coefficient ``MU`` of
:data:`FRICTIONS` (at :data:`DT_REF`) ``lo_muMU_g``, ``hi_muMU_g``, ``collapse_muMU`` (the outcome
at ``hi``: overturned or collapsed_by_sliding), ``slip_lo_muMU_m`` and ``slip_hi_muMU_m`` (the
largest slip of a joint, m, in the runs at ``lo`` and ``hi``), ``ratio_muMU`` (``hi_muMU /
sim_A_g``); ``sim_runs``, ``errors`` (runs the contact solver failed: they end a bisection) and
``time_s``.  Where rock finds no overturning amplitude up to the top of its scan ``rock_top_g``
(``10 A_L``), ``top_outcome`` is simulate's outcome there (0.25 ms, no sliding); if it collapses,
simulate is bisected in ``[A_L, 10 A_L]`` (``ratio`` nan), else its columns are nan.
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
from fembeam.errors import SolverError
from fembeam.simulation import Simulator
from fembeam.studies.runs import onset_amplitude
from fembeam.studies.spectrum import geometric_grid, overturning_amplitude, pulse, pulse_end, spectrum

HERE = Path(__file__).resolve().parent
VOUSSOIRS = 7
RADIUS = 5.0                                   # m
ARCHES = {"paper": (157.5, 0.15), "oppenheim": (150.0, 0.15)}   # embrace (deg), t/R
KINDS = ("rect", "sine")
PERIODS = [0.2, 0.28, 0.4, 0.56, 0.8, 1.13, 1.6, 2.26]            # s (durations for rect)
FREE = 3.0                                     # free time after the pulse, in sqrt(L/g)
DTS = {1e-3: "1ms", 5e-4: "0.5ms", 2.5e-4: "0.25ms"}             # simulate's time steps (s) and their tags
DT_REF = 2.5e-4                                # the dt-converged column and the friction runs
FRICTIONS = (0.6, 0.8)                         # Coulomb coefficients at every joint
ROCK_TOL = 1e-4                                # relative bracket of rock's bisection
SIM_STEPS = 14                                 # bisection steps of simulate on [0.5, 2] x rock
BRACKET = (0.5, 2.0)
COLLAPSE = ("overturned", "collapsed_by_sliding")
RECORD_SECONDS = 15.0                          # El Centro truncated to its first 15 s
SCAN_FROM, SCAN_STEP = 0.6, 0.005              # El Centro: simulate's scan of factors from 0.6 x rock's factor
DT_CHECK = 0.005                               # a threshold moving more than this between two dt: dt_scan
DT_SCAN = (-0.04, 0.0301, 0.002)               # its grid of amplitudes, relative to the dt-converged threshold
SCAN_POINTS = 30                               # check of the bisection: simulate on a grid from A_L up to it
FIELDS = (["arch", "kind", "period_s", "rock_A_g", "rock_top_g"]
          + [f"{e}_{tag}_g" for tag in DTS.values() for e in ("lo", "hi")]
          + ["sim_A_g", "sim_dt_change", "ratio", "demand"]
          + [f"{c}_mu{mu:g}{u}" for mu in FRICTIONS for c, u in
             (("lo", "_g"), ("hi", "_g"), ("collapse", ""), ("slip_lo", "_m"), ("slip_hi", "_m"), ("ratio", ""))]
          + ["scan_first_g", "top_outcome", "sim_runs", "errors", "time_s"])
TEXT = {"arch", "kind", "top_outcome"} | {f"collapse_mu{mu:g}" for mu in FRICTIONS}


def arch(name: str) -> CircularArch:
    beta, t_r = ARCHES[name]
    return CircularArch.from_ratio(beta, t_r, radius=RADIUS)


def free_time(curve) -> float:
    return FREE * math.sqrt(curve.length / 9.81)


def a_limit(curve) -> float:
    """A_L (g): no ground acceleration below it moves the member (joints that do not slide)."""
    return min(Rocker(curve, voussoirs=VOUSSOIRS, qp=False).A.values())


def rock_amplitude(curve, kind: str, period: float) -> tuple[float, float]:
    """Rock's overturning amplitude (g) of one period (fembeam.studies.spectrum: scan of 40
    amplitudes from the onset to 10 x it, bisection) and the top of its scan (g)."""
    res = spectrum(curve, kind, [period], voussoirs=VOUSSOIRS, workers=1, progress=False, bisect_tol=ROCK_TOL,
                   t_end_factor=FREE)
    f = res.rows[0]["first_collapse"]
    return (float("nan") if f is None else float(f)), float(res.amplitudes[-1])


class Runs:
    """simulate's runs of one member at one time step: collapse or not, and the runs' figures."""

    def __init__(self, sim: Simulator, dt: float, t_end: float):
        self.sim, self.dt, self.t_end = sim, dt, t_end
        self.count, self.errors = 0, 0

    def __call__(self, ground: GroundMotion):
        """The result of the run under ``ground`` (stopped at collapse), or None if the contact
        solver failed."""
        self.count += 1
        try:
            return self.sim.run(ground, dt=self.dt, t_end=self.t_end, stop_at_overturn=True)
        except SolverError:
            self.errors += 1
            return None


def sim_bisect(runs: Runs, make_ground, lo: float, hi: float, steps: int, floor: float | None = None,
               floor_safe: bool = True) -> dict:
    """Bisection of simulate's collapse amplitude in [lo, hi] (hi checked to collapse, lo to be safe).
    If lo collapses too, the bracket becomes [floor, lo] with 2 more steps (``floor``: A_L, safe
    without a run when the joints do not slide, ``floor_safe``; else checked by a run).  Returns
    lo, hi (final bracket: nan where not found), ``amplitude`` (hi; nan if hi is safe), ``res_lo``
    and ``res_hi`` (the results of the runs at the final lo and hi; None if not run)."""
    out = {"lo": float("nan"), "hi": float("nan"), "amplitude": float("nan"), "res_lo": None, "res_hi": None}
    r_hi = runs(make_ground(hi))
    if r_hi is None or r_hi.outcome not in COLLAPSE:
        out["lo"], out["res_lo"] = hi, r_hi
        return out
    r_lo = runs(make_ground(lo))
    if r_lo is None:
        return out
    if r_lo.outcome in COLLAPSE:
        if floor is None or floor >= lo:
            out.update(hi=lo, res_hi=r_lo)
            return out
        r_f = None
        if not floor_safe:
            r_f = runs(make_ground(floor))
            if r_f is None or r_f.outcome in COLLAPSE:
                out.update(hi=floor, res_hi=r_f)
                return out
        lo, hi, r_lo, r_hi = floor, lo, r_f, r_lo
        steps += 2
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        r = runs(make_ground(mid))
        if r is None:
            break
        if r.outcome in COLLAPSE:
            hi, r_hi = mid, r
        else:
            lo, r_lo = mid, r
    out.update(lo=lo, hi=hi, amplitude=hi, res_lo=r_lo, res_hi=r_hi)
    return out


def spectrum_row(name: str, kind: str, period: float, steps: int = SIM_STEPS, dts=tuple(DTS),
                 frictions=FRICTIONS) -> dict:
    clock = time.perf_counter()
    curve = arch(name)
    a_rock, top = rock_amplitude(curve, kind, period)
    t_end = pulse_end(kind, period) + free_time(curve)
    row = {k: float("nan") for k in FIELDS}
    row.update(arch=name, kind=kind, period_s=period, rock_A_g=a_rock, top_outcome="", sim_runs=0, errors=0)
    for mu in FRICTIONS:
        row[f"collapse_mu{mu:g}"] = ""

    def make(a):
        return pulse(kind, a, period)

    row["rock_top_g"] = top
    floor = a_limit(curve)
    sim = Simulator(curve, voussoirs=VOUSSOIRS)
    all_runs = [Runs(sim, DT_REF, t_end)]
    if math.isfinite(a_rock):
        lo0, hi0 = BRACKET[0] * a_rock, BRACKET[1] * a_rock
    else:                                        # rock does not overturn up to its scan's top (10 A_L)
        r = all_runs[0](make(top))
        row["top_outcome"] = "solver_error" if r is None else r.outcome
        lo0, hi0 = floor, top
        if row["top_outcome"] not in COLLAPSE:
            dts, frictions = (), ()
    for dt in dts:
        runs = Runs(sim, dt, t_end)
        b = sim_bisect(runs, make, lo0, hi0, steps, floor)
        all_runs.append(runs)
        tag = DTS[dt]
        row[f"lo_{tag}_g"], row[f"hi_{tag}_g"] = b["lo"], b["hi"]
        if dt == DT_REF:
            row["sim_A_g"] = b["amplitude"]
            row["ratio"] = b["amplitude"] / a_rock
            row["demand"] = b["res_lo"].friction_ratio if b["res_lo"] is not None else float("nan")
            # the bisection assumes one boundary: simulate on a grid from A_L up to the bracket
            lo = b["lo"] if math.isfinite(b["lo"]) else hi0
            for a in np.geomspace(floor, lo, SCAN_POINTS + 1)[1:-1]:
                r = all_runs[0](make(a))
                if r is not None and r.outcome in COLLAPSE:
                    row["scan_first_g"] = float(a)
                    break
    if 5e-4 in dts and DT_REF in dts:
        a, c = row["hi_0.5ms_g"], row["hi_0.25ms_g"]
        row["sim_dt_change"] = abs(a - c) / c
    for mu in frictions:
        runs = Runs(Simulator(curve, voussoirs=VOUSSOIRS, friction=mu), DT_REF, t_end)
        b = sim_bisect(runs, make, lo0, hi0, steps, floor, floor_safe=False)
        all_runs.append(runs)
        k = f"{mu:g}"
        row[f"lo_mu{k}_g"], row[f"hi_mu{k}_g"] = b["lo"], b["hi"]
        row[f"collapse_mu{k}"] = b["res_hi"].outcome if b["res_hi"] is not None else ""
        row[f"slip_lo_mu{k}_m"] = b["res_lo"].max_slip if b["res_lo"] is not None else float("nan")
        row[f"slip_hi_mu{k}_m"] = b["res_hi"].max_slip if b["res_hi"] is not None else float("nan")
        row[f"ratio_mu{k}"] = b["amplitude"] / row["sim_A_g"] if DT_REF in dts else float("nan")
    row["sim_runs"] = sum(r.count for r in all_runs)
    row["errors"] = sum(r.errors for r in all_runs)
    row["time_s"] = round(time.perf_counter() - clock, 2)
    return row


def read_csv(path: Path) -> list[dict]:
    if not path.exists():
        return []
    with open(path) as f:
        return [{k: (v if k in TEXT else float(v) if v != "" else float("nan")) for k, v in r.items()}
                for r in csv.DictReader(f)]


def run_spectra(path: Path, arches, kinds, periods, steps: int = SIM_STEPS) -> list[dict]:
    if path.exists():
        with open(path) as f:
            if next(csv.reader(f), None) != FIELDS:
                raise SystemExit(f"{path} has other columns than this script writes: --fresh starts it anew")
    done = {(r["arch"], r["kind"], r["period_s"]) for r in read_csv(path)}
    if not path.exists():
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
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=False)
    styles = {"paper": ("C0", "157.5 deg"), "oppenheim": ("C3", "150 deg (Oppenheim)")}
    mu = FRICTIONS[0]
    for ax, kind in zip(axes, KINDS):
        for name, (col, lab) in styles.items():
            rs = sorted((r for r in rows if r["arch"] == name and r["kind"] == kind), key=lambda r: r["period_s"])
            if not rs:
                continue
            p = [r["period_s"] for r in rs]
            ax.plot(p, [r["rock_A_g"] for r in rs], "-o", color=col, label=f"{lab}: rock")
            ax.plot(p, [r["sim_A_g"] for r in rs], "--s", color=col, mfc="none", label=f"{lab}: simulate, no sliding")
            ax.plot(p, [r[f"hi_mu{mu:g}_g"] for r in rs], ":x", color=col, label=f"{lab}: simulate, mu = {mu:g}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_major_locator(FixedLocator(PERIODS))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.set_xlabel("pulse duration (s)" if kind == "rect" else "pulse period (s)")
        ax.set_ylabel("overturning amplitude (g)")
        ax.set_title("rectangular pulse" if kind == "rect" else "one-sine pulse")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"7 voussoirs, t/R = 0.15, R = {RADIUS:g} m; simulate at dt = {DT_REF:g} s")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# --------------------------------------------------------------------------- El Centro
def rock_collapse_scale(curve, rec: GroundMotion, t_end: float, n_factors: int = 30, span: float = 20.0) -> dict:
    """The smallest factor of ``rec`` that overturns ``curve`` by ``rock`` on a grid: ``n_factors``
    geometric points from the onset factor to ``span`` times it, then a bisection below the first
    overturning point to a relative width ``ROCK_TOL`` (this comparison's own grid search; the
    package searches scale factors by hunt and fill, :mod:`fembeam.studies.collapse`).  The dict
    of :func:`~fembeam.studies.spectrum.overturning_amplitude`, its amplitudes being factors."""
    rk = Rocker(curve, voussoirs=VOUSSOIRS, qp=False)
    f0 = onset_amplitude(rk.A, rec)
    res = overturning_amplitude(rk, rec.scaled, geometric_grid(f0, span, n_factors), t_end=t_end,
                                bisect_tol=ROCK_TOL, onset=f0)
    return res


def elcentro(seconds: float = RECORD_SECONDS) -> GroundMotion:
    g = GroundMotion.record("elcentro")
    keep = g.t <= seconds + 1e-9
    return GroundMotion(g.t[keep], g.a[keep], name=f"El Centro, first {seconds:g} s")


def run_elcentro(csv_path: Path, fig_path: Path, scan_path: Path, below=(0.5, 0.7, 0.9),
                 steps: int = SIM_STEPS) -> dict:
    curve = arch("paper")
    rec = elcentro()
    t_end = float(rec.t[-1]) + free_time(curve)
    clock = time.perf_counter()
    cs = rock_collapse_scale(curve, rec, t_end)
    f_rock = float(cs["first_collapse"])
    t_rock = time.perf_counter() - clock
    lo0, hi0 = BRACKET[0] * f_rock, BRACKET[1] * f_rock
    sim = Simulator(curve, voussoirs=VOUSSOIRS)
    found = {}
    for dt, tag in DTS.items():
        found[tag] = sim_bisect(Runs(sim, dt, t_end), rec.scaled, lo0, hi0, steps)
    for mu in FRICTIONS:
        found[f"mu{mu:g}"] = sim_bisect(Runs(Simulator(curve, voussoirs=VOUSSOIRS, friction=mu), DT_REF, t_end),
                                        rec.scaled, lo0, hi0, steps)
    # the bisection assumes one boundary: every model on a grid of factors up to rock's
    scan = {"factor": [float(f) for f in np.round(np.arange(round(SCAN_FROM * f_rock, 2), f_rock, SCAN_STEP), 3)]}
    for key, s_ in [("no_sliding", sim)] + [(f"mu{mu:g}", Simulator(curve, voussoirs=VOUSSOIRS, friction=mu))
                                             for mu in FRICTIONS]:
        runs = Runs(s_, DT_REF, t_end)
        scan[key] = [getattr(runs(rec.scaled(f)), "outcome", "solver_error") for f in scan["factor"]]
    with open(scan_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(list(scan))
        w.writerows(zip(*scan.values()))
    rk = Rocker(curve, voussoirs=VOUSSOIRS, qp=False)
    rows = []
    for frac in below:
        f = frac * f_rock
        r = rk.run(rec.scaled(f), t_end=t_end)
        s = sim.run(rec.scaled(f), dt=DT_REF, t_end=t_end)
        rows.append({"factor": f, "fraction_of_rock_collapse": frac, "rock_outcome": r.outcome,
                     "rock_peak_rotation": r.peak_rotation, "sim_outcome": s.outcome,
                     "sim_peak_rotation": s.peak_rotation, "sim_t_overturn": s.t_overturn})
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "value"])
        w.writerow(["record_seconds", RECORD_SECONDS])
        w.writerow(["pga_g", rec.pga])
        w.writerow(["rock_collapse_factor", f_rock])
        w.writerow(["rock_safe_factors_above", " ".join(f"{x:.4g}" for x in cs["safe_amplitudes_above"])])
        w.writerow(["sim_collapse_factor", found[DTS[DT_REF]]["amplitude"]])
        for key, b in found.items():
            w.writerow([f"sim_bracket_{key}", f"{b['lo']:.6g} {b['hi']:.6g}"])
            if key.startswith("mu"):
                rh, rl = b["res_hi"], b["res_lo"]
                w.writerow([f"sim_{key}_at_bracket", (f"hi: {rh.outcome if rh else ''}, slip {rh.max_slip if rh else 0:.4g} m;"
                                                      f" lo: {rl.outcome if rl else ''}, slip {rl.max_slip if rl else 0:.4g} m")])
        for r in rows:
            w.writerow([f"peaks_at_{r['fraction_of_rock_collapse']:g}x", f"factor {r['factor']:.4g}; rock "
                        f"{r['rock_outcome']} {r['rock_peak_rotation']:.5g} rad; simulate {r['sim_outcome']} "
                        f"{r['sim_peak_rotation']:.5g} rad"
                        + (f" (t_overturn {r['sim_t_overturn']:.3f} s)" if r["sim_t_overturn"] is not None else "")])
        # the two histories at rock's collapse factor
        r = rk.run(rec.scaled(f_rock), t_end=t_end)
        s = sim.run(rec.scaled(f_rock), dt=DT_REF, t_end=t_end)
        w.writerow(["at_rock_factor", f"rock {r.outcome} t_overturn {r.t_overturn}; simulate {s.outcome} t_overturn {s.t_overturn}"])
        w.writerow(["at_rock_factor_rock_impacts_s", " ".join(f"{e.t:.3f}" for e in r.impacts)])
        for lo, hi in zip([0.0] + [e.t for e in r.impacts], [e.t for e in r.impacts] + [math.inf]):
            th = np.abs(np.asarray(r.history["theta"]))[(r.history["t"] > lo) & (r.history["t"] < hi)]
            if th.size and th.max() > 0.01:
                w.writerow([f"at_rock_factor_rock_peak_{lo:.3f}_{min(hi, r.t_end):.3f}_s", f"{th.max():.4f} rad"])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(9, 3.8))
    ax.plot(r.history["t"], np.abs(r.history["theta"]), label=f"rock: |theta| of the first moving piece ({r.outcome})")
    ax.plot(s.history["t"], s.history["max_rotation"],
            label=f"simulate (dt = {DT_REF:g} s): largest |phi| of any voussoir ({s.outcome})")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("rotation (rad)")
    ax.set_title(f"El Centro (first {RECORD_SECONDS:g} s) x {f_rock:.3f}, paper's arch, 7 voussoirs, R = {RADIUS:g} m")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(fig_path, dpi=120)
    plt.close(fig)
    out = {"rock_collapse_factor": f_rock, "found": {k: (b["lo"], b["hi"]) for k, b in found.items()},
           "rows": rows, "rock_time_s": t_rock, "time_s": time.perf_counter() - clock}
    print(out, flush=True)
    return out


def thrust_check(spectra: list[dict], path: Path) -> list[dict]:
    """``rock`` run at the amplitude where ``simulate`` (no sliding, dt-converged) overturns (same
    pulse and end of run): outcome, first time its thrust line leaves the section, number of impacts."""
    out = []
    for r in spectra:
        if not (math.isfinite(r["sim_A_g"]) and (not r["ratio"] >= 0.9 or r["period_s"] in (0.2, 2.26))):
            continue
        curve = arch(r["arch"])
        res = Rocker(curve, voussoirs=VOUSSOIRS, qp=False).run(
            pulse(r["kind"], r["sim_A_g"], r["period_s"]), t_end=pulse_end(r["kind"], r["period_s"]) + free_time(curve),
            history=False)
        out.append({"arch": r["arch"], "kind": r["kind"], "period_s": r["period_s"], "amplitude_g": r["sim_A_g"],
                    "ratio": r["ratio"], "rock_outcome": res.outcome, "thrust_line_exits_at_s": res.thrust_line_exits_at,
                    "rock_impacts": len(res.impacts)})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, list(out[0]) if out else ["arch"])
        w.writeheader()
        w.writerows(out)
    return out


def dt_scan(spectra: list[dict], path: Path) -> list[dict]:
    """Where the threshold moves by more than :data:`DT_CHECK` between two time steps: simulate (no
    sliding) on a grid of amplitudes around the dt-converged threshold at each step of :data:`DTS`
    and at half the finest; ``pattern``: one character per amplitude, X collapse, . safe."""
    out = []
    for r in spectra:
        changes = [abs(r["hi_1ms_g"] - r["hi_0.5ms_g"]) / r["hi_0.5ms_g"], r["sim_dt_change"]]
        if not any(x > DT_CHECK for x in changes):
            continue
        curve = arch(r["arch"])
        t_end = pulse_end(r["kind"], r["period_s"]) + free_time(curve)
        sim = Simulator(curve, voussoirs=VOUSSOIRS)
        amps = r["sim_A_g"] * (1.0 + np.arange(*DT_SCAN))
        for dt in list(DTS) + [0.5 * min(DTS)]:
            runs = Runs(sim, dt, t_end)
            pattern = "".join("E" if x is None else "X" if x.outcome in COLLAPSE else "."
                              for x in (runs(pulse(r["kind"], a, r["period_s"])) for a in amps))
            out.append({"arch": r["arch"], "kind": r["kind"], "period_s": r["period_s"], "dt_s": dt,
                        "a_first_g": amps[0], "a_last_g": amps[-1], "a_step_g": amps[1] - amps[0], "pattern": pattern})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, ["arch", "kind", "period_s", "dt_s", "a_first_g", "a_last_g", "a_step_g", "pattern"])
        w.writeheader()
        w.writerows(out)
    return out


# --------------------------------------------------------------------------- the page's tables
def _f(x, fmt="{:.3f}"):
    return "-" if not (isinstance(x, float) and math.isfinite(x)) else fmt.format(x)


def _ratio(r) -> str:
    if r is None:
        return ""
    if math.isfinite(r["ratio"]):
        return _f(r["ratio"])
    if math.isfinite(r["sim_A_g"]):         # rock: none up to the top of its scan
        return f"< {r['sim_A_g'] / r['rock_top_g']:.3f}"
    return "-"


def intervals(factors, outcomes) -> str:
    """The runs of consecutive collapsing grid points, as ``first-last`` factors."""
    out, start, prev = [], None, None
    for f, o in zip(factors, outcomes):
        if o in COLLAPSE:
            start = f if start is None else start
            prev = f
        elif start is not None:
            out.append(f"{start:g}-{prev:g}")
            start = None
    if start is not None:
        out.append(f"{start:g}-{prev:g}")
    return ", ".join(out) or "none"


def tables(rows: list[dict]) -> str:
    """The page's tables (markdown) from the spectra CSV."""
    key = {(r["arch"], r["kind"], r["period_s"]): r for r in rows}
    cols = [(a, k) for a in ARCHES for k in KINDS]
    out = ["Ratio simulate / rock (simulate at dt = 0.25 ms, no sliding):", "",
           "| period (s) | " + " | ".join(f"{a}, {k}" for a, k in cols) + " |", "|---" * (len(cols) + 1) + "|"]
    for p in PERIODS:
        out.append(f"| {p:.2f} | " + " | ".join(_ratio(key.get((a, k, p))) for a, k in cols) + " |")
    out += ["", ("Amplitudes (g): rock's; simulate's at 0.25 ms (the upper end of its bracket) with the change from "
                 "0.5 ms as its error estimate; the ratio; simulate's at 1 and 0.5 ms:"), "",
            "| arch, pulse, period (s) | `rock` | `simulate`, 0.25 ms | +- | ratio | `simulate`, 1 ms | 0.5 ms |",
            "|---|---|---|---|---|---|---|"]
    for (a, k, p), r in key.items():
        if not math.isfinite(r["sim_A_g"]):
            continue
        rock = f"{r['rock_A_g']:.4f}" if math.isfinite(r["rock_A_g"]) else f"none up to {r['rock_top_g']:.2f}"
        out.append(f"| {a}, {k} {p:g} | {rock} | {r['sim_A_g']:.4f} | {r['sim_dt_change']:.2%} | {_ratio(r)} | "
                   f"{r['hi_1ms_g']:.4f} | {r['hi_0.5ms_g']:.4f} |")
    bw = [(r["hi_0.25ms_g"] - r["lo_0.25ms_g"]) / r["hi_0.25ms_g"] for r in rows if math.isfinite(r["sim_A_g"])]
    out += ["", f"bracket width at 0.25 ms relative to the threshold: {min(bw):.1e} ... {max(bw):.1e}"]
    out += ["", ("Friction (dt = 0.25 ms): collapse amplitude with mu over that without sliding, outcome at the upper "
                 "end, largest slip (mm) in the runs at the lower (safe) and upper end; friction demand of the "
                 "no-sliding run at its lower end:"), "",
            "| arch, pulse, period | no sliding (g) | demand | " + " | ".join(
                f"mu {m:g}: ratio | outcome | slip safe / collapse (mm)" for m in FRICTIONS) + " |",
            "|---|---|---|" + "---|---|---|" * len(FRICTIONS)]
    for (a, k, p), r in key.items():
        if not math.isfinite(r["sim_A_g"]):
            continue
        cells = []
        for m in FRICTIONS:
            t = f"{m:g}"
            cells += [_f(r[f"ratio_mu{t}"]), r[f"collapse_mu{t}"].replace("collapsed_by_sliding", "**sliding**") or "-",
                      f"{_f(1e3 * r[f'slip_lo_mu{t}_m'], '{:.2f}')} / {_f(1e3 * r[f'slip_hi_mu{t}_m'], '{:.2f}')}"]
        out.append(f"| {a}, {k} {p:g} | {r['sim_A_g']:.4f} | {_f(r['demand'], '{:.2f}')} | " + " | ".join(cells) + " |")
    no = [f"{a}, {k} {p:g}: {r['top_outcome']} (10 A_L = {r['rock_top_g']:.4f} g)" for (a, k, p), r in key.items()
          if r["top_outcome"]]
    out += ["", "Not overturned by rock up to 10 A_L; simulate at 10 A_L: " + "; ".join(no)]
    bad = [f"{a}, {k} {p:g}: {r['scan_first_g']:.4f} g" for (a, k, p), r in key.items()
           if math.isfinite(r["scan_first_g"])]
    out += ["", (f"Scan check ({SCAN_POINTS - 1} amplitudes from A_L to the lower end of the bracket, 0.25 ms): "
                 "collapses below the bracket: ") + ("; ".join(bad) or "none")]
    dts_path = HERE / "data" / "comparison_dt_scan.csv"
    if dts_path.exists():
        with open(dts_path) as f:
            out += ["", "Around the thresholds that move by more than 0.5 % between two dt (X collapse, . safe):", ""]
            out += [f"* {x['arch']}, {x['kind']} {float(x['period_s']):g}, dt {float(x['dt_s']) * 1e3:g} ms, "
                    f"{float(x['a_first_g']):.4f} ... {float(x['a_last_g']):.4f} g step {float(x['a_step_g']):.4f}: "
                    f"`{x['pattern']}`" for x in csv.DictReader(f)]
    scan_path = HERE / "data" / "comparison_elcentro_scan.csv"
    if scan_path.exists():
        with open(scan_path) as f:
            sc = list(csv.DictReader(f))
        fs = [float(x["factor"]) for x in sc]
        out += ["", f"El Centro scan, factors {fs[0]:g} ... {fs[-1]:g} step {SCAN_STEP:g}: collapsing factors"]
        out += [f"* {k}: {intervals(fs, [x[k] for x in sc])}" for k in sc[0] if k != "factor"]
    out += ["", (f"runs: {sum(r['sim_runs'] for r in rows):.0f}, solver errors: {sum(r['errors'] for r in rows):.0f}, "
                 f"sum of row times: {sum(r['time_s'] for r in rows):.0f} s")]
    return "\n".join(out)


def quick() -> dict:
    """One row at a coarse tolerance (for tests): the paper's arch, rectangular pulse of 0.4 s, 6
    bisection steps of simulate at dt = DT_REF without sliding and with the first friction coefficient."""
    return spectrum_row("paper", "rect", 0.4, steps=6, dts=(DT_REF,), frictions=FRICTIONS[:1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one row, coarse; prints it")
    ap.add_argument("--no-elcentro", action="store_true")
    ap.add_argument("--fresh", action="store_true", help="start the spectra CSV anew (default: resume)")
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw the spectra figure and redo the thrust-line check from the CSV")
    ap.add_argument("--tables", action="store_true", help="print the page's tables from the spectra CSV")
    args = ap.parse_args(argv)
    clock = time.perf_counter()
    path = HERE / "data" / "comparison_spectra.csv"
    if args.quick:
        print(quick())
        print(f"quick: {time.perf_counter() - clock:.1f} s")
        return
    if args.tables:
        print(tables(read_csv(path)))
        return
    (HERE / "data").mkdir(exist_ok=True)
    (HERE / "figures").mkdir(exist_ok=True)
    if args.plot_only:
        plot_spectra(read_csv(path), HERE / "figures" / "comparison_spectra.png")
        thrust_check(read_csv(path), HERE / "data" / "comparison_thrust.csv")
        dt_scan(read_csv(path), HERE / "data" / "comparison_dt_scan.csv")
        return
    if args.fresh and path.exists():
        path.unlink()
    rows = run_spectra(path, ARCHES, KINDS, PERIODS)
    plot_spectra(rows, HERE / "figures" / "comparison_spectra.png")
    thrust_check(rows, HERE / "data" / "comparison_thrust.csv")
    dt_scan(rows, HERE / "data" / "comparison_dt_scan.csv")
    print(f"spectra: {time.perf_counter() - clock:.0f} s", flush=True)
    if not args.no_elcentro:
        run_elcentro(HERE / "data" / "comparison_elcentro.csv", HERE / "figures" / "comparison_elcentro.png",
                     HERE / "data" / "comparison_elcentro_scan.csv")
    print(f"total: {time.perf_counter() - clock:.0f} s")


if __name__ == "__main__":
    main()
