"""Mesh-refinement convergence study of ``analyze``.

For a list of meshes (``elements`` of the continuous arch, or ``voussoirs`` of discrete
arches) the study tabulates A_L (hinge-refined value, units of g), the uniform-mesh LP
value A_L_mesh, r, the hinges before/after (deg from the left springing), the main
verification figures and the solve times.  Errors are measured against

* the continuous arch: a Richardson-extrapolated value from the two finest meshes with an
  *assumed* order ``p`` (default 2); the order fitted to all levels is reported beside it;
* discrete arches (voussoirs): the continuous arch's values on ``reference_elements``
  elements (the voussoir arch converges to the continuous one as their number grows).

Observed rates are the least-squares slope ``np.polyfit(np.log(h), np.log(err), 1)``
with ``h`` the element (voussoir) length over R, i.e. beta / N.
"""
from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ..analysis import AnalysisResult, analyze, minimum_thickness
from ..errors import InputError
from ..geometry import MidCurve

__all__ = ["richardson", "observed_order", "fit_order", "rate_fit", "ConvergenceStudy",
           "convergence_study", "ROUNDOFF"]

ROUNDOFF = 1e-9  # relative spread below which a quantity is "exact at every level" (the
#                  continuum A_L is solved to ~1e-11 on every mesh: LP row tolerance 1e-10)
# hinge angles set by the four-hinge optimiser, not by the mesh, scatter by ~3e-5 deg
# (A_L is stationary in them); below this spread a hinge counts as mesh-independent
HINGE_ATOL_DEG = 1e-4
TMIN_TOL = 1e-10   # bisection tolerance of the minimum thickness in a study

# verification figures carried into the table: (group, key) -> column
VERIFICATION_COLUMNS = {
    ("limit", "equilibrium_residual"): "lp_equilibrium_residual",
    ("impact", "equilibrium_residual"): "qp_equilibrium_residual",
    ("impact", "impulse_line_outside"): "impulse_line_outside",
    ("impact", "max_tensile_impulse"): "max_tensile_impulse",
    ("impact", "impulse_work"): "impulse_work",
    ("impact", "max_shear_ratio"): "max_shear_ratio",
}


def _finest(h, x, k: int):
    h, x = np.asarray(h, float), np.asarray(x, float)
    if h.size < k:
        raise ValueError(f"need at least {k} levels, got {h.size}")
    i = np.argsort(h)[:k][::-1]  # the k finest, coarse to fine
    return h[i], x[i]


def richardson(h, x, order: float = 2.0) -> float:
    """Extrapolate ``x(h) = x0 + C h^order`` to ``h = 0`` from the two finest levels."""
    (h1, h2), (x1, x2) = _finest(h, x, 2)
    return float(x2 + (x2 - x1) / ((h1 / h2) ** order - 1.0))


def observed_order(h, x) -> float:
    """Order ``p`` of ``x0 + C h^p`` through the three finest levels (any ratios);
    NaN if the differences are not monotone (no asymptotic power law)."""
    (h1, h2, h3), (x1, x2, x3) = _finest(h, x, 3)
    d12, d23 = x1 - x2, x2 - x3
    if d12 == 0 or d23 == 0 or np.sign(d12) != np.sign(d23):
        return float("nan")
    q = d12 / d23
    if math.isclose(h1 / h2, h2 / h3, rel_tol=1e-12):
        return float(np.log(q) / np.log(h1 / h2))
    from scipy.optimize import brentq

    def g(p):
        return (h1**p - h2**p) / (h2**p - h3**p) - q
    try:
        return float(brentq(g, 1e-3, 20.0))
    except ValueError:
        return float("nan")


def fit_order(h, x) -> tuple[float, float, float]:
    """Fit ``x = x0 + C h^p`` to all levels: ``(x0, C, p)``.

    ``x0`` is chosen beyond the finest value (on the side the sequence moves to) so that
    ``log|x - x0|`` is as straight a line in ``log h`` as possible (largest R^2); ``p``
    and ``C`` are that line's slope and intercept.  Fitting in log space weights every
    level alike, unlike a least-squares fit of ``x`` itself, which the coarsest
    (pre-asymptotic) levels dominate.
    """
    from scipy.optimize import minimize_scalar

    h, x = np.asarray(h, float), np.asarray(x, float)
    o = np.argsort(h)  # fine to coarse
    h, x = h[o], x[o]
    step = x[0] - x[1]  # the finest step points towards the limit
    if h.size < 3 or step == 0:
        return float("nan"), float("nan"), float("nan")

    def line(log_delta):
        x0 = x[0] + np.exp(log_delta) * step
        c, res, *_ = np.polyfit(np.log(h), np.log(np.abs(x - x0)), 1, full=True)
        y = np.log(np.abs(x - x0))
        ss = float(np.sum((y - y.mean()) ** 2))
        return x0, c, (float(res[0]) / ss if res.size and ss > 0 else 0.0)

    best = minimize_scalar(lambda z: line(z)[2], bounds=(np.log(1e-6), np.log(1e3)), method="bounded",
                           options={"xatol": 1e-10})
    x0, c, _ = line(best.x)
    return float(x0), float(np.exp(c[1])), float(c[0])


def rate_fit(h, err) -> float:
    """Observed rate: least-squares slope of ``log(err)`` against ``log(h)`` over the
    levels with a finite, positive error; NaN with fewer than two such levels."""
    h, err = np.asarray(h, float), np.asarray(err, float)
    ok = np.isfinite(err) & (err > 0) & np.isfinite(h) & (h > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0])


def _num(x):
    return None if x is None or not np.isfinite(x) else float(x)


@dataclass
class ConvergenceStudy:
    """What :func:`convergence_study` found: one row per mesh and, per quantity, its limit,
    errors and rates.

    :meth:`to_dict` is its JSON, :meth:`csv_rows` its CSV table.

    Attributes
    ----------
    geometry : dict
        The member's description (its ``describe()``: shape and dimensions in m).
    mode : {"continuous", "voussoirs"}
        Meshes of rigid elements of the continuous arch, or discrete arches of voussoirs.
    levels : list of int
        The meshes: elements or voussoirs, increasing.
    assumed_order : float
        Order ``p`` of the Richardson extrapolation (continuous arch).
    rows : list of dict
        One per mesh: ``n``, the element size ``h_over_R`` (``beta / N``) and ``h_deg``
        (deg) on a circular arch (``h_over_span`` on another shape), ``outcome``, ``A_L``
        (g, hinge-refined), ``A_L_mesh`` (g, the uniform mesh's LP), ``r``, the hinges
        before and after the impact (deg from the left springing), the verification figures
        and the solve times (s).
    quantities : dict
        Per quantity (``A_L``, ``A_L_mesh``, ``r``, ``t_min_factor``, the angle of each
        hinge ``hinges_before_k_deg``): its ``values``, its limit (``extrapolated``, or the
        ``reference`` of discrete arches), ``errors`` against it, the observed ``rate``
        (slope of ``log err`` over ``log h``), ``fitted_order``, ``observed_order_3``, and
        ``exact`` (equal at every level to round-off: no rate).
    reference : dict or None
        Discrete arches: the continuous arch's values on ``reference_elements`` elements.
    wall_time : float
        Wall time of the study (s).
    h : numpy.ndarray
        Element size of each row over R (over the span for another shape than the circle).

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.studies import convergence_study
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> st = convergence_study(arch, elements=[20, 40], progress=False)
    >>> print(st.mode, st.levels, st.h.round(4))
    continuous [20, 40] [0.1374 0.0687]
    >>> for h in st.rows[-1]["hinges_before"]:
    ...     print(f"{h['angle_deg']:6.1f} deg  {h['side']}")
       1.5 deg  intrados
      59.3 deg  extrados
     117.1 deg  intrados
     157.5 deg  extrados
    >>> print(st.to_dict()["study"], len(st.csv_rows()), "CSV rows")
    convergence 2 CSV rows
    """

    geometry: dict
    mode: str                      # "continuous" (elements) or "voussoirs"
    levels: list[int]
    assumed_order: float
    rows: list[dict]
    quantities: dict = field(default_factory=dict)
    reference: dict | None = None  # voussoirs: the continuous arch's values
    wall_time: float = 0.0

    @property
    def h(self) -> np.ndarray:
        """Element size of each row over R (over the span for another shape)."""
        return np.array([_h(r) for r in self.rows])

    def to_dict(self) -> dict:
        """The study as JSON: settings, reference, quantities and rows."""
        return {"study": "convergence", "mode": self.mode, "geometry": self.geometry,
                "levels": self.levels, "assumed_order": self.assumed_order,
                "reference": self.reference, "quantities": self.quantities,
                "rows": self.rows, "wall_time_s": round(self.wall_time, 3)}

    def csv_rows(self) -> list[dict]:
        """Flat rows for CSV: hinge lists as ``;``-separated angles and sides."""
        out = []
        for row in self.rows:
            flat = {k: v for k, v in row.items() if not isinstance(v, (list, dict))}
            for key in ("hinges_before", "hinges_after"):
                flat[f"{key}_deg"] = ";".join(f"{h['angle_deg']:.6f}" for h in row[key])
                flat[f"{key}_side"] = ";".join(h["side"] for h in row[key])
            for name, q in self.quantities.items():
                flat[f"err_{name}"] = q["errors"][len(out)]
            out.append(flat)
        return out


def mesh_size(curve: MidCurve, n: int) -> dict:
    """Size of ``n`` equal elements: ``h/R = beta/N`` (and degrees) on a circular arch,
    else the element's arc length over the span (over the length of a member without one)."""
    beta = getattr(curve, "beta", None)
    if beta is not None:
        return {"h_over_R": float(beta) / n, "h_deg": math.degrees(beta) / n}
    span = (curve.describe() if hasattr(curve, "describe") else {}).get("span") or curve.length
    return {"h_over_span": curve.length / (n * span)}


def _h(row: dict) -> float:
    return row["h_over_R"] if "h_over_R" in row else row["h_over_span"]


def _row(res: AnalysisResult, n: int, size: dict, wall: float) -> dict:
    v = res.verification
    row = {"n": n, **size, "outcome": res.outcome,
           "A_L": _num(res.A_L), "A_L_mesh": _num(res.A_L_mesh), "r": _num(res.r),
           "hinges_before": [h.to_dict() for h in res.hinges_before],
           "hinges_after": [h.to_dict() for h in res.hinges_after],
           "hinge_refinement_gap": _num(v.get("hinge_refinement_gap", float("nan")))}
    for (grp, key), col in VERIFICATION_COLUMNS.items():
        row[col] = _num(v.get(grp, {}).get(key, float("nan")))
    t = res.timings
    row.update({"time_total_s": round(wall, 4), "time_lp_s": round(t.get("limit", 0.0), 4),
                "time_refine_s": round(t.get("continuum", 0.0), 4),
                "time_qp_s": round(t.get("impact", 0.0), 4)})
    return row


def _hinge_series(rows: list[dict], key: str) -> dict[str, list]:
    """Angle of the k-th hinge per level, if every level has the same hinges (sides)."""
    sides = [tuple(h["side"] for h in r[key]) for r in rows]
    if not sides or any(s != sides[-1] for s in sides) or not sides[-1]:
        return {}
    return {f"{key}_{k + 1}_deg": [r[key][k]["angle_deg"] for r in rows] for k in range(len(sides[-1]))}


def _quantity(h, x, order: float, reference: float | None, atol: float = 0.0) -> dict:
    x = np.asarray([np.nan if v is None else v for v in x], float)
    ok = np.isfinite(x)
    q = {"assumed_order": order, "values": [_num(v) for v in x]}
    if reference is None:
        if ok.sum() < 2:
            q.update(extrapolated=None, errors=[None] * x.size, rate=None, fitted_order=None,
                     observed_order_3=None, exact=False)
            return q
        ref = richardson(h[ok], x[ok], order)
        q["extrapolated"] = _num(ref)
    else:
        ref = reference
        q["reference"] = _num(ref)
    err = np.abs(x - ref)
    spread = np.nanmax(np.abs(x[ok] - ref)) if ok.any() else np.nan
    exact = bool(np.isfinite(spread) and spread <= max(atol, ROUNDOFF * max(1.0, abs(ref))))
    q["exact"] = exact  # equal to round-off at every level: no rate to fit
    q["errors"] = [_num(e) for e in err]
    q["rate"] = None if exact else _num(rate_fit(h, err))
    fitted = observed = float("nan")
    if not exact and ok.sum() >= 3:
        with np.errstate(all="ignore"):   # diagnostics only: a level equal to the limit gives log(0)
            observed = observed_order(h[ok], x[ok])
            try:
                fitted = fit_order(h[ok], x[ok])[2]
            except Exception:
                fitted = float("nan")
    q["fitted_order"], q["observed_order_3"] = _num(fitted), _num(observed)
    return q


def convergence_study(curve: MidCurve, elements: list[int] | None = None, voussoirs: list[int] | None = None,
                      order: float = 2.0, reference_elements: int = 1600, direction: int = 1,
                      backend: str = "auto", refine_hinges: bool = True, progress: bool = True,
                      tmin: bool = False) -> ConvergenceStudy:
    """Mesh-refinement convergence of :func:`~fembeam.analyze`: errors and observed rates.

    :func:`~fembeam.analyze` runs on each mesh; the errors of each quantity are measured
    against a Richardson extrapolation of the two finest meshes (continuous arch) or against
    the continuous arch (discrete arches), and its observed rate is the least-squares slope
    of ``log err`` over ``log h``, ``h`` the element (voussoir) length over R. The method is
    that of :mod:`fembeam.studies.convergence`.

    Parameters
    ----------
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    elements : list of int, optional
        Meshes of the continuous arch (rigid elements, hinges refined); errors against the
        Richardson extrapolation with ``order``. Give ``elements`` or ``voussoirs``.
    voussoirs : list of int, optional
        Discrete arches of these numbers of voussoirs; errors against the continuous arch
        on ``reference_elements`` elements.
    order : float, optional
        Assumed order ``p`` of ``x(h) = x0 + C h^p`` in the extrapolation (default 2; the
        order fitted to all levels is reported beside it).
    reference_elements : int, optional
        Elements of the continuous reference of discrete arches (default 1600).
    direction : {1, -1}, optional
        Direction of the inertia load (+1: along ``+x``, a ground acceleration towards
        ``-x``).
    backend : str, optional
        Solver of the impact QP.
    refine_hinges : bool, optional
        Locate the hinges of the continuous arch between the joints (default True).
    progress : bool, optional
        One line per mesh on stderr (default True).
    tmin : bool, optional
        Also the minimum thickness on each mesh (``t_min_factor``, the factor of the
        thickness; every section checked on the continuous arch, the joints of the
        voussoirs).

    Returns
    -------
    ConvergenceStudy
        The rows (one per mesh) and, per quantity, its limit, errors and rates.

    Raises
    ------
    InputError
        Neither or both of ``elements`` and ``voussoirs``, fewer than two distinct meshes,
        or an order that is not a positive number.
    SolverError
        A solve failed its check.

    Examples
    --------
    The paper's arch on 20, 40 and 80 elements: ``A_L`` of the continuum is the same on
    every mesh, ``r`` converges:

    >>> import fembeam
    >>> from fembeam.studies import convergence_study
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> st = convergence_study(arch, elements=[20, 40, 80], progress=False)
    >>> for row in st.rows:
    ...     print(row["n"], f"h/R = {row['h_over_R']:.4f}: A_L = {row['A_L']:.6f} g,",
    ...           f"r = {row['r']:.6f}")
    20 h/R = 0.1374: A_L = 0.353384 g, r = 0.605649
    40 h/R = 0.0687: A_L = 0.353384 g, r = 0.606187
    80 h/R = 0.0344: A_L = 0.353384 g, r = 0.606465
    >>> print(st.quantities["A_L"]["exact"])
    True
    >>> q = st.quantities["r"]
    >>> print(f"r -> {q['extrapolated']:.5f}, observed rate {q['rate']:.2f}")
    r -> 0.60656, observed rate 1.65
    """
    if (elements is None) == (voussoirs is None):
        raise InputError("give either a list of elements (continuous arch) or of voussoirs (discrete arches)")
    levels = sorted(set(int(n) for n in (elements if elements is not None else voussoirs)))
    if len(levels) < 2:
        raise InputError(f"a convergence study needs at least 2 distinct meshes, got {levels}")
    if not (order > 0 and math.isfinite(order)):
        raise InputError(f"the assumed order must be a positive number, got {order!r}")
    mode = "continuous" if elements is not None else "voussoirs"
    clock = time.perf_counter()

    def say(msg):
        if progress:
            print(f"convergence: {msg}", file=sys.stderr, flush=True)

    reference = None
    if mode == "voussoirs":
        t0 = time.perf_counter()
        ref = analyze(curve, elements=reference_elements, direction=direction, backend=backend,
                      refine_hinges=refine_hinges, thrust=False)
        reference = {"elements": reference_elements, "outcome": ref.outcome, "A_L": _num(ref.A_L),
                     "A_L_mesh": _num(ref.A_L_mesh), "r": _num(ref.r),
                     "hinges_before": [h.to_dict() for h in ref.hinges_before],
                     "hinges_after": [h.to_dict() for h in ref.hinges_after]}
        if tmin:
            reference["t_min_factor"] = _num(minimum_thickness(curve, elements=reference_elements,
                                                               tol=TMIN_TOL).scale)
        say(f"continuous reference on {reference_elements} elements: A_L = {ref.A_L:.8f}, r = {ref.r:.8f} "
            f"({time.perf_counter() - t0:.2f} s)")

    rows = []
    for n in levels:
        t0 = time.perf_counter()
        kw = {"elements": n} if mode == "continuous" else {"voussoirs": n}
        res = analyze(curve, direction=direction, backend=backend, refine_hinges=refine_hinges, **kw, thrust=False)
        rows.append(_row(res, n, mesh_size(curve, n), time.perf_counter() - t0))
        if tmin:
            rows[-1]["t_min_factor"] = _num(minimum_thickness(curve, tol=TMIN_TOL, **kw).scale)
        say(f"{n:6d} {'elements' if mode == 'continuous' else 'voussoirs'}: {res.outcome}, "
            f"A_L = {res.A_L:.8f}, r = {res.r:.8f} ({rows[-1]['time_total_s']:.2f} s)")

    h = np.array([_h(r) for r in rows])
    series = {"A_L": [r["A_L"] for r in rows], "A_L_mesh": [r["A_L_mesh"] for r in rows],
              "r": [r["r"] for r in rows]}
    if tmin:
        series["t_min_factor"] = [r["t_min_factor"] for r in rows]
    if mode == "voussoirs":  # no hinge refinement: A_L is the LP on the voussoirs, A_L_mesh the same
        del series["A_L_mesh"]
    series.update(_hinge_series(rows, "hinges_before"))
    series.update(_hinge_series(rows, "hinges_after"))
    quantities = {}
    for name, x in series.items():
        ref_value = None
        if reference is not None:
            if name in ("A_L", "A_L_mesh", "r", "t_min_factor"):
                ref_value = reference[name]
            else:  # hinge angle: compare with the continuous hinge of the same rank and side
                key, k = name.rsplit("_", 2)[0], int(name.rsplit("_", 2)[1]) - 1
                hs = reference[key]
                if len(hs) != len(rows[-1][key]) or any(a["side"] != b["side"] for a, b in zip(hs, rows[-1][key])):
                    continue
                ref_value = hs[k]["angle_deg"]
            if ref_value is None:
                continue
        quantities[name] = _quantity(h, x, order, ref_value, HINGE_ATOL_DEG if name.startswith("hinges_") else 0.0)
    return ConvergenceStudy(curve.describe() if hasattr(curve, "describe") else {}, mode, levels,
                            order, rows, quantities, reference, time.perf_counter() - clock)


def plot_convergence(study: ConvergenceStudy, path: str) -> None:
    """Log-log errors against h/R with the fitted rates in the legend (PNG at ``path``)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    h = study.h
    hinge_q = {k: q for k, q in study.quantities.items() if k.startswith("hinges_") and not q["exact"]}
    main_q = {k: q for k, q in study.quantities.items() if k in ("A_L", "A_L_mesh", "r", "t_min_factor")}
    ncol = 2 if hinge_q else 1
    fig, axes = plt.subplots(1, ncol, figsize=(6.2 * ncol, 4.8), squeeze=False)
    labels = {"A_L": "$A_L$ (hinge-refined)" if study.mode == "continuous" else "$A_L$ (voussoir LP)",
              "A_L_mesh": "$A_L$ uniform-mesh LP", "r": "$r$", "t_min_factor": "$t_{min}$ (factor of $t$)"}
    against = ("Richardson, assumed p = %g" % study.assumed_order if study.mode == "continuous"
               else "continuous arch, %d el." % study.reference["elements"])

    def label(name):
        if name in labels:
            return labels[name]
        key, k, _ = name.rsplit("_", 2)
        return f"hinge {k} {key.split('_')[1]} impact"

    def draw(ax, qs, ylabel, title):
        for name, q in qs.items():
            err = np.array([np.nan if e is None else e for e in q["errors"]], float)
            ok = np.isfinite(err) & (err > 0)
            if q["exact"] or not ok.any():  # nothing to plot on a log scale: say so in the legend
                lim = q.get("extrapolated", q.get("reference"))
                ax.plot([], [], " ", label=f"{label(name)} = {lim:.8g} at every N (spread "
                                           f"{np.nanmax(err) if ok.any() else 0:.0e})")
                continue
            fo = q.get("fitted_order") if study.mode == "continuous" else None
            ax.loglog(h[ok], err[ok], "o-", label=f"{label(name)}: rate {q['rate']:.2f}"
                      + (f" (fitted p = {fo:.2f})" if fo is not None else ""))
            c = np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)
            ax.loglog(h[ok], np.exp(np.polyval(c, np.log(h[ok]))), ":", color=ax.lines[-1].get_color(), lw=1)
        if ax.lines and any(ln.get_xdata().size for ln in ax.lines):
            ys = [y for ln in ax.lines for y in np.atleast_1d(ln.get_ydata()) if np.isfinite(y) and y > 0]
            h2 = np.array([h.min(), h.max()])
            ax.loglog(h2, min(ys) * 0.3 * (h2 / h2[0]) ** 2, "--", color="0.6", lw=1, label="slope 2")
        ax.set_xlabel("h / R = beta / N" if "h_over_R" in study.rows[0] else "h / span (element arc length)")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="major", alpha=0.3)
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.legend(fontsize=8)

    g = study.geometry
    what = "elements" if study.mode == "continuous" else "voussoirs"
    name = (f"beta = {g.get('embrace_deg')} deg, t/R = {g.get('t_over_R')}" if g.get("shape") == "circular"
            else f"{g.get('shape')} arch, span {g.get('span', '?'):g} m, rise {g.get('rise', '?'):g} m")
    draw(axes[0, 0], main_q, f"|error| (against {against})",
         f"{name}: N = {study.levels[0]}..{study.levels[-1]} {what}")
    if hinge_q:
        draw(axes[0, 1], hinge_q, "|error| of hinge angle (deg)", "hinge positions")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
