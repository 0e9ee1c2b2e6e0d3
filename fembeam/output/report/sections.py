"""The five sections of the report: each ``section_*(cfg, say)`` computes its numbers and
returns ``(checks, data)``; :func:`build_report` runs them in order."""
from __future__ import annotations

import math
import sys
import time

import numpy as np

from ...analysis import THRESHOLDS, analyze, minimum_thickness
from ...geometry import CircularArch
from ...errors import FembeamError
from ...mechanisms.hinge import side_of
from .checks import (SECTIONS, TOLERANCES, Check, Report, ReportSettings, _against, _at_least, _at_most, _close,
                     _holds, _info)


# ---------------------------------------------------------------------------- 1. exact
def section_exact(cfg: ReportSettings, say) -> tuple[list[Check], dict]:
    from ...fem import discretize, uniform_nodes
    from ...geometry import CircularArch, StraightMember

    S, checks, data = "exact", [], {}
    # rigid motions: no opening, no sliding at the interior joints of an irregular mesh
    c = CircularArch.from_ratio(157.5, 0.15, radius=2.0)
    nodes = np.sort(np.concatenate([[0.0, c.length], np.random.default_rng(0).uniform(0.0, c.length, 29)]))
    disc = discretize(c, nodes)
    J = disc.n_joints
    inner = np.r_[1:J - 1]
    motions = {"translation x": ((1, 0), 0, (0, 0)), "translation y": ((0, 1), 0, (0, 0)),
               "rotation about (0.4, -1.1)": ((0.3, -2.0), 1.7, (0.4, -1.1)), "rotation about (5, 5)": ((0, 0), 1, (5, 5))}
    worst = {}
    for label, (V, om, about) in motions.items():
        d = disc.rigid(V, om, about)
        eps = disc.B_open @ d
        res = max(np.abs(eps[inner]).max(), np.abs(eps[J + inner]).max(), np.abs((disc.B_slide @ d)[inner]).max())
        worst[label] = float(res / np.abs(d).max())
    data["kernel"] = {"elements": disc.n_elements, "mesh": "irregular (31 random nodes)", "residual": worst}
    checks.append(_at_most(S, "rigid motions in the kernel of B_open, B_slide (max |B d|/max|d|)",
                           max(worst.values()), TOLERANCES["kernel"][0], TOLERANCES["kernel"][1],
                           f"{len(motions)} rigid motions, {disc.n_elements} irregular elements, 157.5 deg, t/R 0.15"))

    # annular sector: d^T M d of rigid motions = exact mass, static moment, polar inertia
    R, t, beta_deg, rho = 2.0, 0.3, 157.5, 1.7
    c = CircularArch(radius=R, thickness=t, embrace_deg=beta_deg, density=rho)
    disc = discretize(c, uniform_nodes(c, 9))
    a, b, B = R - t / 2, R + t / 2, math.radians(beta_deg)
    exact = {"mass": rho * 0.5 * (b**2 - a**2) * B, "static moment about x": rho * (b**3 - a**3) / 3 * 2 * math.sin(B / 2),
             "polar inertia about the centre": rho * (b**4 - a**4) / 4 * B}
    tx, rot = disc.rigid((1, 0)), disc.rigid(omega=1.0)
    M = disc.M
    fem = {"mass": float(tx @ M @ tx), "static moment about x": float(-(tx @ M @ rot)),
           "polar inertia about the centre": float(rot @ M @ rot)}
    data["sector"] = {"R": R, "t": t, "embrace_deg": beta_deg, "density": rho, "exact": exact, "fembeam": fem}
    formulas = {"mass": "rho (b^2 - a^2) beta / 2", "static moment about x": "rho (b^3 - a^3) 2 sin(beta/2) / 3",
                "polar inertia about the centre": "rho (b^4 - a^4) beta / 4"}
    for k in exact:
        checks.append(_close(S, f"annular sector {k}", fem[k], exact[k], "sector", rel=True,
                             source=f"closed form {formulas[k]} (a, b = R -+ t/2)"))

    # Housner's block
    say("exact: Housner's block")
    rows = []
    for tan_a in cfg.housner_tan_a + cfg.stocky_tan_a:
        res = analyze(StraightMember(height=2.0, width=2.0 * tan_a), voussoirs=1, thrust=False)
        s2 = math.sin(math.atan(tan_a)) ** 2
        rows.append({"tan_a": tan_a, "r": res.r, "A_L": res.A_L, "outcome": res.outcome,
                     "r_exact": (1 - 1.5 * s2) ** 2 if tan_a < math.sqrt(2) else 0.0,
                     "housner_alpha_ratio": 1 - 1.5 * s2})
    data["housner"] = rows
    slender = [r for r in rows if r["tan_a"] < math.sqrt(2)]
    stocky = [r for r in rows if r["tan_a"] >= math.sqrt(2)]
    worst_r = max(slender, key=lambda r: abs(r["r"] - r["r_exact"]))
    checks.append(_close(S, f"Housner r = (1 - 1.5 sin^2 a)^2, worst of {len(slender)} slender blocks "
                            f"(tan a = {worst_r['tan_a']:g})", worst_r["r"], worst_r["r_exact"], "housner_r",
                         source="Housner (1963): r = (1 - 1.5 sin^2 a)^2",
                         detail=f"tan a = {min(r['tan_a'] for r in slender):g} .. {max(r['tan_a'] for r in slender):g}"))
    worst_a = max(slender, key=lambda r: abs(r["A_L"] / r["tan_a"] - 1))
    checks.append(_close(S, f"Housner A_L = tan a, worst (tan a = {worst_a['tan_a']:g})", worst_a["A_L"],
                         worst_a["tan_a"], "housner_A_L", rel=True, source="Housner (1963): incipient rocking at A_L = tan a"))
    stocky_list = ", ".join(f"{r['tan_a']:g}" for r in stocky)
    checks.append(_holds(S, f"stocky blocks (tan a = {stocky_list} > sqrt 2) arrested, r = 0",
                         all(r["outcome"] == "arrested" and r["r"] == 0.0 for r in stocky),
                         max(r["r"] for r in stocky), "r = 0 (arrested)",
                         "tests/test_housner.py: 1 - 1.5 sin^2 a < 0, no compatible motion does work"))

    # Milankovitch
    say("exact: Milankovitch minimum thickness")
    tmin = minimum_thickness(CircularArch.from_ratio(180.0, 0.5), elements=cfg.tmin_elements, tol=cfg.tmin_tol).t_over_R
    data["milankovitch"] = {"t_min_over_R": tmin, "elements": cfg.tmin_elements, "bisection_tol": cfg.tmin_tol}
    checks.append(_against(S, f"Milankovitch: semicircle t_min/R ({cfg.tmin_elements} el., bisection {cfg.tmin_tol:g})",
                           tmin, "milankovitch.t_min"))
    return checks, data


# ---------------------------------------------------------------------------- 2. paper
def _oppenheim(beta: float) -> dict:
    from ...geometry import CircularArch
    from ...mechanisms import Mechanism
    from ...mechanisms.classical import classical_impact
    from ...mechanisms.impulse_line import four_hinge_impulse_line
    from ...mechanisms.restricted import best_four_hinge_discrete

    c = CircularArch.from_ratio(beta, 0.15, radius=10.0)
    res = analyze(c, voussoirs=7, thrust=False)
    fb = Mechanism.from_hinges(c, res.hinges_before)
    pre = fb.closing()
    joints = res.impact.disc.joint_s
    best = best_four_hinge_discrete(joints, pre)
    line = four_hinge_impulse_line(pre, best.after, joints).admissibility()
    cl = classical_impact(fb, joints)
    return {"curve": c, "res": res, "before": fb, "best": best, "line": line, "classical": cl,
            "out": {"A_L": res.A_L, "r_max": res.r, "qp_hinges_after": [h.to_dict() for h in res.hinges_after],
                    "hinges_before": fb.to_list(), "r_4hinge": best.r, "hinges_after_4hinge": best.after.to_list(),
                    "four_hinge_line": line, "r_classical": cl.r, "classical_hinges_after": cl.after.to_list(),
                    "classical_line": cl.line.admissibility(), "classical_r_energy": cl.r_energy}}


def _same(curve, a, b) -> bool:
    return a.sides == b.sides and np.allclose(a.angles_deg(), b.angles_deg(), atol=1e-9)


def section_paper(cfg: ReportSettings, say) -> tuple[list[Check], dict]:
    from ...geometry import CircularArch
    from ...mechanisms import Mechanism
    from ...mechanisms.impulse_line import four_hinge_impulse_line
    from ...mechanisms.restricted import best_four_hinge_continuous

    S, checks, data = "paper", [], {}
    say("paper: Oppenheim's arch, 150 deg")
    o = _oppenheim(150.0)
    data["oppenheim_150"] = o["out"]
    c, fb = o["curve"], o["before"]
    checks += [_against(S, "Oppenheim 150: A_L", o["res"].A_L, "oppenheim150.A_L"),
               _against(S, "Oppenheim 150: r_max (QP)", o["res"].r, "oppenheim150.r",
                        f"{len(o['res'].hinges_after)} hinges after"),
               _against(S, "Oppenheim 150: best four-hinge r (restricted problem)", o["best"].r, "oppenheim150.r",
                        f"{o['best'].candidates} candidates, {o['best'].compatible} compatible"),
               _against(S, "Oppenheim 150: classical model r", o["classical"].r, "oppenheim150.r"),
               _holds(S, "Oppenheim 150: best new hinges = points C-bar opposite u's = mirror of u's",
                      _same(c, o["best"].after, fb.opposite()) and _same(c, fb.opposite(), fb.mirrored()),
                      " ".join(f"{h['angle_deg']:.2f}{side_of(h['side']).initial}" for h in o["best"].after.to_list()),
                      "opposite = mirrored", "paper Sect. 6.1, Fig. 10 caption")]

    say("paper: Oppenheim's arch, 157.5 deg")
    o = _oppenheim(157.5)
    data["oppenheim_157.5"] = o["out"]
    c, fb, res = o["curve"], o["before"], o["res"]
    line = o["line"]
    out_at = [f["angle_deg"] for f in line["failures"] if f["check"] == "inside_thickness"]
    c13 = float(fb.angles_deg()[1])
    cl_line = o["classical"].line.admissibility()
    missed = sorted(f["angle_deg"] for f in cl_line["failures"] if f["check"] == "through_hinge")
    new_inner = sorted(float(a) for a in o["classical"].after.angles_deg()[1:3])
    checks += [_against(S, "Oppenheim 157.5: A_L", res.A_L, "oppenheim157.A_L"),
               _against(S, "Oppenheim 157.5: best four-hinge r (restricted problem)", o["best"].r,
                        "oppenheim157.r_4hinge"),
               _against(S, "Oppenheim 157.5: r_max (QP)", res.r, "oppenheim157.r_max"),
               _holds(S, "Oppenheim 157.5: QP opens five hinges", len(res.hinges_after) == 5, len(res.hinges_after),
                      "5", "paper Sect. 6.1: five hinges, Fig. 11c"),
               _holds(S, "Oppenheim 157.5: four-hinge line leaves the thickness only at the joint of C13",
                      line["passes_through_hinges"] and len(out_at) == 1 and abs(out_at[0] - c13) < 1e-9,
                      ", ".join(f"{a:.2f} deg" for a in out_at) or "nowhere", f"{c13:.2f} deg",
                      "paper Sect. 6.1, Fig. 11b"),
               _holds(S, "Oppenheim 157.5: classical line misses the new hinges C'13, C'23",
                      not cl_line["passes_through_hinges"] and np.allclose(missed, new_inner, atol=1e-9),
                      ", ".join(f"{a:.2f}" for a in missed) + " deg", ", ".join(f"{a:.2f}" for a in new_inner) + " deg",
                      "paper Sect. 6.1, Fig. 11a (not kinematically admissible)"),
               _info(S, "Oppenheim 157.5: classical model r", o["classical"].r,
                     "not published; > r_max because the model's impulses work against u' (docs/four_hinge.md)",
                     f"energy principle on the same hinges: r = {o['classical'].r_energy:.6f}")]

    say("paper: continuous arch, 157.5 deg")
    c = CircularArch.from_ratio(157.5, 0.15)
    res = analyze(c, thrust=False)
    pre = Mechanism.from_hinges(c, res.hinges_before).closing()
    qh = res.hinges_after
    starts = [Mechanism.from_hinges(c, qh)] if len(qh) == 4 else []
    best = best_four_hinge_continuous(pre, starts=starts)
    adm = four_hinge_impulse_line(pre, best.after, np.linspace(0.0, c.length, 721)).admissibility()
    data["continuous_157.5"] = {"elements": res.n, "A_L": res.A_L, "r_max": res.r,
                                "hinges_before": [h.to_dict() for h in res.hinges_before],
                                "hinges_after_qp": [h.to_dict() for h in qh], "r_4hinge": best.r,
                                "hinges_after_4hinge": best.after.to_list(),
                                "four_hinge_line": {k: v for k, v in adm.items() if k != "failures"},
                                "qp_impulse_line_outside": res.verification["impact"]["impulse_line_outside"]}
    checks += [_against(S, f"continuous 157.5: A_L ({res.n} el., hinges refined)", res.A_L, "continuous157.A_L"),
               _against(S, f"continuous 157.5: r_max (QP, {res.n} el.)", res.r, "continuous157.r"),
               _against(S, "continuous 157.5: best four-hinge r (smooth restricted problem)", best.r, "continuous157.r"),
               _at_least(S, "continuous 157.5: r_max - r_4hinge", res.r - best.r, 0.0,
                         "the general QP maximises r over all compatible fields, four-hinge ones included"),
               _info(S, "continuous 157.5: four-hinge line max (|e| - t/2)/t", adm["max_outside"],
                     "paper Fig. 12 calls it admissible; the QP's hinge zones fix this (docs/four_hinge.md)",
                     f"QP impulse line outside: {res.verification['impact']['impulse_line_outside']:.1e}")]
    return checks, data


# ---------------------------------------------------------------------------- 3. KKT
KKT_FIGURES = (("limit", "equilibrium_residual", "(B.11) analogue: equilibrium of the thrust"),
               ("limit", "thrust_line_outside", "thrust line inside the thickness"),
               ("limit", "max_tensile_force", "no tension"),
               ("limit", "complementarity", "N eps = 0"),
               ("limit", "incompatibility", "u compatible"),
               ("impact", "equilibrium_residual", "(B.8)1-3 = (B.11) impulse-momentum balance"),
               ("impact", "impulse_line_outside", "(B.8)6 = (B.12) impulse line inside the thickness"),
               ("impact", "max_tensile_impulse", "(B.8)6 compressive impulses"),
               ("impact", "impulse_work", "(B.8)7 impulses do no work on u' (complementarity)"),
               ("impact", "incompatibility", "(B.5), (B.8)4-5 gamma' = 0, eps' >= 0"),
               ("impact", "virtual_work_gap", "(B.6) virtual-work equality"),
               ("", "hinge_refinement_gap", "LP through refined hinges = four-hinge optimum"))


def _kkt_case(kind: str, a: float, b, n: int):
    from ...geometry import CircularArch, StraightMember

    if kind == "block":
        return f"Housner block tan a = {a:g}", analyze(StraightMember(height=2.0, width=2.0 * a), voussoirs=1,
                                                        verify=False, thrust=False)
    c = CircularArch.from_ratio(a, b)
    if kind == "voussoirs":
        return f"{a:g} deg, t/R {b:g}, {n} voussoirs", analyze(c, voussoirs=n, verify=False, thrust=False)
    return f"{a:g} deg, t/R {b:g}, {n} el.", analyze(c, elements=n, verify=False, thrust=False)


def section_kkt(cfg: ReportSettings, say) -> tuple[list[Check], dict]:
    S, checks, rows = "kkt", [], []
    for case in cfg.kkt_cases:
        label, res = _kkt_case(*case)
        say(f"kkt: {label}: {res.outcome}")
        v = res.verification
        figs = {}
        for grp, key, _ in KKT_FIGURES:
            x = (v.get(grp, {}) if grp else v).get(key)
            if isinstance(x, (int, float)):
                figs[f"{grp}.{key}" if grp else key] = float(x)
        ratios = {k: x / THRESHOLDS[k.split(".")[-1]] for k, x in figs.items()}
        worst = max(ratios, key=ratios.get)
        rows.append({"case": label, "outcome": res.outcome, "A_L": res.A_L, "r": res.r, "figures": figs,
                     "max_shear_ratio": v.get("impact", {}).get("max_shear_ratio"), "worst": worst,
                     "worst_ratio": ratios[worst]})
        checks.append(_at_most(S, f"{label} ({res.outcome}): worst figure / threshold", ratios[worst], 1.0,
                               "fembeam.analysis.THRESHOLDS (docs/verification.md)",
                               f"{len(figs)} figures, worst {worst} = {figs[worst]:.1e}"))
    return checks, {"cases": rows, "figures": [{"group": g, "key": k, "meaning": m} for g, k, m in KKT_FIGURES]}


# ---------------------------------------------------------------------------- 4. convergence
def section_convergence(cfg: ReportSettings, say) -> tuple[list[Check], dict]:
    from ...studies.convergence import convergence_study
    from ...geometry import CircularArch

    S, checks = "convergence", []
    c = CircularArch.from_ratio(157.5, 0.15)
    say(f"convergence: elements {','.join(map(str, cfg.elements))}")
    st = convergence_study(c, elements=list(cfg.elements), progress=False)
    q = st.quantities
    rate_tol, rate_src = TOLERANCES["rate"]
    A = np.array([r["A_L"] for r in st.rows])
    Am = np.array([r["A_L_mesh"] for r in st.rows])
    levels = f"N = {cfg.elements[0]}..{cfg.elements[-1]}"
    checks += [_at_least(S, f"r: fitted rate ({levels})", q["r"]["rate"], rate_tol, rate_src,
                         f"fitted p = {q['r']['fitted_order']:.2f}, Richardson limit {q['r']['extrapolated']:.7f}"),
               _at_least(S, f"A_L_mesh (uniform-mesh LP): fitted rate ({levels})", q["A_L_mesh"]["rate"], rate_tol,
                         rate_src, f"fitted p = {q['A_L_mesh']['fitted_order']:.2f}"),
               _holds(S, "A_L_mesh > refined A_L on every mesh (an LP over fewer mechanisms)",
                      bool(np.all(Am > A)), float(np.min(Am - A)), "> 0", "A_L is a minimum over mechanisms (kinematic theorem)"),
               _at_most(S, "refined A_L: relative spread over the meshes", float(np.ptp(A) / A[-1]),
                        TOLERANCES["mesh_independent"][0], TOLERANCES["mesh_independent"][1]),
               _against(S, "r: Richardson limit", q["r"]["extrapolated"], "continuous157.r")]
    data = {"continuous": st.to_dict()}
    say(f"convergence: voussoirs {','.join(map(str, cfg.voussoirs))}")
    sv = convergence_study(c, voussoirs=list(cfg.voussoirs), reference_elements=cfg.reference_elements, progress=False)
    qa = sv.quantities["A_L"]
    err = np.array(qa["errors"], float)
    checks += [_at_least(S, f"voussoirs -> continuous: A_L fitted rate (N = {cfg.voussoirs[0]}..{cfg.voussoirs[-1]})",
                         qa["rate"], rate_tol, "tests/test_discrete.py: joints every beta/N, A_L stationary in the "
                         "hinge positions, second order", f"against {cfg.reference_elements} elements"),
               _holds(S, "voussoirs: A_L decreases monotonically to the continuous value",
                      bool(np.all(err > 0) and np.all(np.diff(err) < 0)), float(err[-1]), "errors > 0, decreasing",
                      "the discrete arch tends to the continuous one"),
               _info(S, f"voussoirs: |r - r_continuous| at N = {cfg.voussoirs[-1]}", sv.quantities["r"]["errors"][-1],
                     "r wobbles ~1e-3 with the voussoir joints (hinges snap to them)")]
    data["voussoirs"] = sv.to_dict()
    return checks, {"_studies": (st, sv), **data}


# ---------------------------------------------------------------------------- 5. Fig. 13
def section_fig13(cfg: ReportSettings, say) -> tuple[list[Check], dict]:
    from ...studies.sweep import sweep

    S, checks = "fig13", []
    say(f"fig13: beta {','.join(f'{b:g}' for b in cfg.fig13_embrace)} x t/R {','.join(f'{t:g}' for t in cfg.fig13_t_over_r)}")
    res = sweep(list(cfg.fig13_embrace), list(cfg.fig13_t_over_r), tmin_elements=cfg.sweep_tmin_elements,
                workers=cfg.workers, progress=False)
    slack, slack_src = TOLERANCES["monotone"]
    bad = [f"{c['embrace_deg']:g}/{c['t_over_R']:g}: {c['outcome']}" for c in res.cases
           if c["outcome"] in ("solver_error", "no_mechanism")]
    checks.append(_holds(S, "every case rocks, is arrested or cannot stand (none lost)", not bad,
                         len(res.cases) - len(bad), f"{len(res.cases)} of {len(res.cases)}",
                         "every case is reported, none dropped", "; ".join(bad)))
    rvals = {(c["embrace_deg"], c["t_over_R"]): c["r"] for c in res.cases if c["outcome"] in ("rocking", "arrested")}
    worst_t, worst_b = -np.inf, -np.inf
    for b in res.embrace:
        r = [rvals[(b, t)] for t in res.t_over_r if (b, t) in rvals]
        if len(r) > 1:
            worst_t = max(worst_t, float(np.max(np.diff(r))))
    for t in res.t_over_r:
        r = [rvals[(b, t)] for b in res.embrace if (b, t) in rvals]
        if len(r) > 1:
            worst_b = max(worst_b, float(np.max(-np.diff(r))))
    checks += [_at_most(S, "r_max falls with t/R (largest step against the trend)", worst_t, slack,
                        "paper Sect. 6.2 on Fig. 13: r_max decreases with t/R; " + slack_src),
               _at_most(S, "r_max rises with beta (largest step against the trend)", worst_b, slack,
                        "paper Sect. 6.2 on Fig. 13: r_max increases with beta; " + slack_src)]
    env = [e for e in res.envelope if e.get("r") is not None]
    checks.append(_holds(S, "envelope computed for every beta", len(env) == len(res.embrace), len(env),
                         str(len(res.embrace)), "paper Sect. 6.2 (envelope at minimum thickness)"))
    if env:
        emax = max(env, key=lambda e: e["r"])
        checks.append(_at_most(S, f"envelope below 1 (max at beta = {emax['embrace_deg']:g})", emax["r"], 1.0,
                               "paper Sect. 6.2 and Remark 1: r <= 1"))
        above = [e["r"] - max([rvals[(e["embrace_deg"], t)] for t in res.t_over_r if (e["embrace_deg"], t) in rvals]
                              or [0.0]) for e in env]
        checks.append(_at_least(S, "envelope above every case of its beta (min margin)", float(min(above)), -slack,
                                "paper Sect. 6.2: all curves lie under the envelope"))
    return checks, {"_sweep": res, **res.to_dict()}


SECTION_FUNCS = {"exact": section_exact, "paper": section_paper, "kkt": section_kkt,
                 "convergence": section_convergence, "fig13": section_fig13}


def build_report(settings: ReportSettings, only=SECTIONS, progress: bool = True) -> Report:
    """Run the sections in ``only``; a solver error in a section becomes a FAIL check."""
    def say(msg):
        if progress:
            print(f"report: {msg}", file=sys.stderr, flush=True)

    rep = Report(settings)
    clock = time.perf_counter()
    for name in SECTIONS:
        if name not in only:
            continue
        t0 = time.perf_counter()
        try:
            checks, data = SECTION_FUNCS[name](settings, say)
        except FembeamError as e:
            checks, data = [Check(name, f"section {name} ran", f"{type(e).__name__}: {e}", "no error", "FAIL",
                                  "fembeam raised")], {}
        rep.checks += checks
        rep.data[name] = data
        rep.timings[name] = time.perf_counter() - t0
        n_fail = sum(c.status == "FAIL" for c in checks)
        say(f"{name}: {len(checks)} checks, {n_fail} FAIL ({rep.timings[name]:.1f} s)")
    rep.timings["total"] = time.perf_counter() - clock
    return rep
