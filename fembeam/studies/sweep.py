"""Parametric study of circular arches (paper Fig. 13): r_max against t/R per beta.

Every (beta, t/R) case is one independent ``analyze`` run (continuous arch, hinge
refinement on) whose *outcome* is always reported: ``rocking`` (r > 0), ``arrested``
(r = 0), ``cannot_stand`` (A_L <= 0, with the t/R it would need), ``no_mechanism`` or
``solver_error`` (the message is kept).  The minimum-thickness envelope has, for each
beta, t_min/R (bisection on the LP on ``tmin_elements`` elements) and r_max of the arch
just above it, at t/R = t_min (1 + ``above``).

Cases run in parallel (:mod:`fembeam.studies.parallel`: local processes or Dask), the envelope
first.  Reuse that pays: t_min is computed once per beta and handed to the cases thinner
than it, which then need one LP instead of ``analyze``'s own bisection.  Warm starts do not: the impact QP takes 2-5 %
of a case (``timing`` in the result says how much), Clarabel cannot warm-start and the
HiGHS LP is not warm-startable through scipy.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..analysis import DEFAULT_ELEMENTS, analyze, minimum_thickness
from ..errors import FembeamError, SolverError
from ..fem import discretize, uniform_nodes
from ..geometry import CircularArch
from ..analysis import limit_analysis
from .parallel import default_workers, run_tasks

__all__ = ["sweep_case", "envelope_case", "SweepResult", "sweep", "plot_sweep", "FIG13_EMBRACE", "FIG13_T_OVER_R"]

FIG13_EMBRACE = [80.0, 100.0, 120.0, 140.0, 160.0, 180.0]
FIG13_T_OVER_R = [round(0.10 + 0.01 * i, 2) for i in range(21)]


def _num(x):
    return None if x is None or not np.isfinite(x) else float(x)


def sweep_case(embrace_deg: float, t_over_r: float, elements: int = DEFAULT_ELEMENTS, backend: str = "clarabel",
               direction: int = 1, t_min_over_r: float | None = None) -> dict:
    """One case of the sweep as a flat dict (never raises on solver trouble: the outcome
    is ``"solver_error"`` with the message in ``error``).

    ``t_min_over_r``: the minimum thickness if already known (envelope).  Below it the
    uniform-mesh LP is tried first and, if the arch cannot stand, that is reported with
    this t_min, saving ``analyze`` its own bisection (0.3-0.5 s)."""
    t0 = time.perf_counter()
    row = {"kind": "case", "embrace_deg": float(embrace_deg), "t_over_R": float(t_over_r)}
    arch = CircularArch.from_ratio(embrace_deg, t_over_r)
    try:
        if t_min_over_r is not None and t_over_r < t_min_over_r:
            lim = limit_analysis(discretize(arch, uniform_nodes(arch, elements)), direction)
            if lim.status == "cannot_stand":
                row.update(outcome="cannot_stand", A_L=None, A_L_mesh=None, r=None, t_min_over_R=float(t_min_over_r),
                           hinges_before=[], hinges_after=[], time_s=time.perf_counter() - t0,
                           time_lp_s=time.perf_counter() - t0, error=None)
                return row
        res = analyze(arch, elements=elements, backend=backend, direction=direction)
    except FembeamError as e:
        row.update(outcome="solver_error", error=f"{type(e).__name__}: {e}", time_s=time.perf_counter() - t0)
        return row
    v = res.verification.get("impact", {})
    row.update(outcome=res.outcome, A_L=_num(res.A_L), A_L_mesh=_num(res.A_L_mesh), r=_num(res.r),
               t_min_over_R=res.t_min_over_R,
               hinges_before=[h.to_dict() for h in res.hinges_before],
               hinges_after=[h.to_dict() for h in res.hinges_after],
               qp_equilibrium_residual=_num(v.get("equilibrium_residual", float("nan"))),
               impulse_line_outside=_num(v.get("impulse_line_outside", float("nan"))),
               time_s=time.perf_counter() - t0,
               time_lp_s=res.timings.get("limit", 0.0), time_refine_s=res.timings.get("continuum", 0.0),
               time_qp_s=res.timings.get("impact", 0.0), error=None)
    return row


def envelope_case(embrace_deg: float, elements: int = DEFAULT_ELEMENTS, tmin_elements: int = 400,
                  tmin_tol: float = 1e-6, above: float = 1e-3, backend: str = "clarabel",
                  direction: int = 1) -> dict:
    """Minimum thickness t_min/R of ``embrace_deg`` and the case at t_min (1 + above).

    t_min from the LP on ``tmin_elements`` elements is >= the value on any coarser
    mesh whose nodes it contains, so the arch analysed just above it stands on
    ``elements`` elements too."""
    t0 = time.perf_counter()
    try:
        tmin = minimum_thickness(CircularArch.from_ratio(embrace_deg, 0.5), elements=tmin_elements, tol=tmin_tol).t_over_R
    except FembeamError as e:
        return {"kind": "envelope", "embrace_deg": float(embrace_deg), "t_over_R": None, "outcome": "solver_error",
                "error": f"{type(e).__name__}: {e}", "time_s": time.perf_counter() - t0}
    row = sweep_case(embrace_deg, tmin * (1.0 + above), elements, backend, direction)
    row.update(kind="envelope", t_min_over_R=float(tmin), time_s=time.perf_counter() - t0)
    return row


@dataclass
class SweepResult:
    """Cases (``kind = "case"``) and envelope points (``kind = "envelope"``)."""

    embrace: list[float]
    t_over_r: list[float]
    cases: list[dict]
    envelope: list[dict]
    settings: dict
    wall_time: float = 0.0
    timing: dict = field(default_factory=dict)

    def case(self, embrace_deg: float, t_over_r: float) -> dict:
        for c in self.cases:
            if math.isclose(c["embrace_deg"], embrace_deg) and math.isclose(c["t_over_R"], t_over_r):
                return c
        raise KeyError((embrace_deg, t_over_r))

    def outcomes(self) -> dict:
        out: dict = {}
        for c in self.cases:
            out[c["outcome"]] = out.get(c["outcome"], 0) + 1
        return out

    def to_dict(self) -> dict:
        return {"study": "sweep", "embrace_deg": self.embrace, "t_over_R": self.t_over_r,
                "settings": self.settings, "outcomes": self.outcomes(), "cases": self.cases,
                "envelope": self.envelope, "wall_time_s": round(self.wall_time, 3), "timing_s": self.timing}

    def csv_rows(self) -> list[dict]:
        cols = ["kind", "embrace_deg", "t_over_R", "outcome", "r", "A_L", "A_L_mesh", "t_min_over_R",
                "hinges_before_deg", "hinges_before_side", "hinges_after_deg", "hinges_after_side",
                "qp_equilibrium_residual", "impulse_line_outside", "time_s", "error"]
        out = []
        for c in self.envelope + self.cases:
            row = {k: c.get(k) for k in cols}
            for key in ("hinges_before", "hinges_after"):
                hs = c.get(key) or []
                row[f"{key}_deg"] = ";".join(f"{h['angle_deg']:.4f}" for h in hs)
                row[f"{key}_side"] = ";".join(h["side"] for h in hs)
            row["time_s"] = round(c.get("time_s", 0.0), 4)
            out.append(row)
        return out


def sweep(embrace: list[float], t_over_r: list[float], elements: int = DEFAULT_ELEMENTS, backend: str = "clarabel",
          direction: int = 1, envelope: bool = True, envelope_embrace: list[float] | None = None,
          tmin_elements: int = 400, tmin_tol: float = 1e-6, above: float = 1e-3, workers: int | None = None,
          scheduler=None, progress: bool = True) -> SweepResult:
    """Every (beta, t/R) case plus, per beta of ``envelope_embrace`` (default
    ``embrace``), the minimum-thickness envelope point; see the module docstring."""
    for b in embrace + (envelope_embrace or []):
        CircularArch.from_ratio(b, 0.1)  # bad input fails here, once, with InputError
    for t in t_over_r:
        CircularArch.from_ratio(90.0, t)
    env_betas = list(envelope_embrace or embrace) if envelope else []
    common = {"elements": elements, "backend": backend, "direction": direction}
    clock = time.perf_counter()
    client = None
    if isinstance(scheduler, str):  # one connection for both phases
        from distributed import Client
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as e:
            raise SolverError(f"cannot connect to the Dask scheduler at {scheduler!r}: {e}") from None
        scheduler = client
    try:
        env = run_tasks([(envelope_case, {"embrace_deg": b, "tmin_elements": tmin_elements, "tmin_tol": tmin_tol,
                                          "above": above, **common}) for b in env_betas],
                        workers=workers, scheduler=scheduler, progress=progress, desc="sweep: t_min envelope")
        tmin = {e["embrace_deg"]: e.get("t_min_over_R") for e in env}
        cases = run_tasks([(sweep_case, {"embrace_deg": b, "t_over_r": t, "t_min_over_r": tmin.get(float(b)),
                                         **common}) for b in embrace for t in t_over_r],
                          workers=workers, scheduler=scheduler, progress=progress, desc="sweep: cases")
    finally:
        if client is not None:
            client.close()
    wall = time.perf_counter() - clock
    timing = {"wall": round(wall, 3),
              "cases_cpu": round(sum(c["time_s"] for c in cases), 3),
              "envelope_cpu": round(sum(e["time_s"] for e in env), 3),
              "lp": round(sum(c.get("time_lp_s", 0.0) for c in cases), 3),
              "hinge_refinement": round(sum(c.get("time_refine_s", 0.0) for c in cases), 3),
              "qp": round(sum(c.get("time_qp_s", 0.0) for c in cases), 3)}
    settings = {"elements": elements, "backend": backend, "direction": direction, "tmin_elements": tmin_elements,
                "tmin_tol": tmin_tol, "above": above,
                "executor": ("dask" if scheduler is not None else
                             f"local ({workers or default_workers()} workers)")}
    return SweepResult(list(embrace), list(t_over_r), cases, env, settings, wall, timing)


OUTCOME_MARKERS = {"arrested": ("x", "arrested (r = 0)"), "cannot_stand": ("v", "cannot stand"),
                   "no_mechanism": ("s", "no mechanism"), "solver_error": ("*", "solver error")}


def plot_sweep(result: SweepResult, path: str) -> None:
    """Fig. 13: r_max against t/R per beta, the other outcomes as markers on r = 0,
    and the minimum-thickness envelope (PNG at ``path``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9.6, 5.2))
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(result.embrace)))
    seen = set()
    for b, col in zip(result.embrace, colors):
        cs = sorted((c for c in result.cases if c["embrace_deg"] == b), key=lambda c: c["t_over_R"])
        t = np.array([c["t_over_R"] for c in cs])
        r = np.array([c["r"] if c["outcome"] in ("rocking", "arrested") else np.nan for c in cs], float)
        ax.plot(t, r, "o-", color=col, ms=3.5, lw=1.4, label=f"beta = {b:g} deg")
        for kind, (mk, lab) in OUTCOME_MARKERS.items():
            sel = [c["t_over_R"] for c in cs if c["outcome"] == kind]
            if sel:
                ax.plot(sel, np.zeros(len(sel)) - (0.0 if kind == "arrested" else 0.03), mk, color=col, ms=6,
                        mfc="none" if kind != "arrested" else col, label=None)
                seen.add(kind)
        for e in result.envelope:
            if e["embrace_deg"] == b and e.get("r") is not None:
                ax.plot([e["t_over_R"]], [e["r"]], "D", color=col, ms=6, mec="k", mew=0.6)
    env = sorted((e for e in result.envelope if e.get("r") is not None), key=lambda e: e["t_over_R"])
    if env:
        ax.plot([e["t_over_R"] for e in env], [e["r"] for e in env], "k--", lw=1.2,
                label="minimum-thickness envelope (diamonds)")
    for kind in seen:  # legend entries for the outcome markers, in black
        mk, lab = OUTCOME_MARKERS[kind]
        ax.plot([], [], mk, color="k", mfc="none" if kind != "arrested" else "k", label=lab)
    ax.axhline(1.0, color="0.5", lw=0.8, ls=":")
    ax.set_xlim(0.0, max(result.t_over_r) * 1.02)
    ax.set_ylim(-0.06, 1.05)
    ax.set_xlabel("t / R")
    ax.set_ylabel("$r_{max}$")
    ax.set_title(f"Continuous circular arches ({result.settings['elements']} elements, hinges refined)", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
