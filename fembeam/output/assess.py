"""Output of :func:`fembeam.studies.assess.assess`: the text page, the figures and the Markdown report.

* :func:`page`: the readable page (``fembeam assess``);
* :func:`statics_figure`: the member and its thrust line at ``A_L`` each way, with the hinges of the
  incipient mechanism (:func:`fembeam.output.plotting.draw_paper_figure`);
* :func:`history_figure`: ground acceleration (g) and the largest rotation of any piece or body
  (rad) of the ``auto`` run against time (s), the intervals of the multi-block simulation shaded,
  the first failure of the one-mechanism model and the overturning marked;
* :func:`configuration_figure`: the member at the peak rotation or at overturning (the pieces of
  the mechanism or the bodies of the simulation, :mod:`fembeam.output.motion`'s outline) over its
  outline at rest;
* :func:`write_report`: ``report.md`` with those figures and ``assess.json`` in a directory, written
  as one atomic group (:func:`fembeam.output.files.atomic_dir`): all files or none.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..errors import InputError
from .files import atomic_dir, check_dir

__all__ = ["page", "statics_figure", "history_figure", "configuration_figure", "report_names", "check_report",
           "write_report"]

VERDICT_WORDS = {"survives": "SURVIVES", "overturns": "OVERTURNS", "collapsed_by_sliding": "COLLAPSES BY SLIDING",
                 "cannot_stand": "CANNOT STAND"}


# --------------------------------------------------------------------------- text
def _hinges(hs: list, block: bool = False) -> str:
    if block:       # the base of a block: its right face is the intrados (normal +x)
        return ", ".join(f"{'right' if h['side'] == 'intrados' else 'left'} corner of the base" for h in hs) or "none"
    return ", ".join(f"{h['angle_deg']:.2f} deg {h['side']}" for h in hs) or "none"


def _num(x, fmt: str = ".6g", none: str = "none") -> str:
    return none if x is None else format(x, fmt)


def static_lines(d: dict) -> list[str]:
    """The statics of a :meth:`AssessResult.to_dict`."""
    st = d["static"]
    A, oc = st["A_L"], st["outcome"]
    lines = ["statics"]
    if "cannot_stand" in oc.values():
        lines.append("  the member CANNOT STAND under its own weight: no thrust line fits inside it")
    else:
        def a(k):
            return f"{A[k]:.6f} g" if A[k] is not None else oc[k].replace("_", " ")
        lines.append(f"  A_L = {a('+1')} (+1: inertia to the right, a_g < 0), {a('-1')} (-1: to the left, a_g > 0)")
        for k in ("+1", "-1"):
            lines.append(f"    hinges at A_L ({k}): {_hinges(st['hinges'][k], d['geometry'].get('shape') == 'block')}")
    tr = st.get("thrust_range")
    if tr is not None:
        top = f"{tr['H_max']:.6g} kN/m" if tr["H_max"] is not None else "unbounded"
        lines.append(f"  thrust range under the dead loads: H_min = {tr['H_min']:.6g} kN/m, H_max = {top} "
                     f"(weight {st['weight_kN_per_m']:.6g} kN/m)")
    mt = st["minimum_thickness"]
    if mt["outcome"] == "ok":
        size = ", ".join(f"{k.replace('_', ' ')} {v:.6g} m" for k, v in mt["thickness_min"].items())
        if mt.get("t_min_over_R") is not None:
            size += f", t/R = {mt['t_min_over_R']:.6f}"
        size = f" ({size.lstrip(', ')})" if size else ""
        lines.append(f"  minimum thickness: {mt['thickness_scale']:.6f} x the given{size}; "
                     f"geometric factor of safety t / t_min = {mt['geometric_safety_factor']:.4f}")
    elif mt["outcome"] == "stands_at_any_thickness":
        lines.append("  minimum thickness: 0 (stands at any thickness); geometric factor of safety infinite")
    else:
        lines.append("  minimum thickness: none (no thickness lets it stand)")
    fn = st["friction_needed"]
    if fn["max"] is None:
        lines.append("  friction needed at A_L: n/a (no limit state)")
    else:
        each = ", ".join(f"{k}: {fn[k]['max']:.4f} at {fn[k]['at_deg']:.2f} deg" for k in ("+1", "-1"))
        lines.append(f"  friction needed at A_L: max |S|/N = {fn['max']:.4f} ({each}); with less the joints slide "
                     "before the member rocks")
        if fn["friction"] is not None:
            lines.append(f"    mu = {fn['friction']:g}: " + ("SLIDING RISK (below the friction needed)"
                                                             if fn["sliding_risk"] else "enough (above it)"))
    return lines


def _factor(e: dict) -> str:
    """The margin's factor and PGA (g), or that none was found."""
    return "none found" if e["factor"] is None else f"{e['factor']:.6g} (PGA {e['pga_g']:.4g} g)"


def _claim(e: dict, friction: float | None) -> str:
    """What the margin search of one model claims (:data:`fembeam.studies.assess.MARGIN_KEYS`):
    the smallest at its resolution, or why not."""
    runs = f"{e['runs']} run" + ("" if e["runs"] == 1 else "s")
    reached = f"{100 * e['resolution_reached']:.3g} %"
    stop = "; ".join(f"search stopped at factor {x['factor']:.6g}: {x.get('error') or x['outcome']}"
                     for x in e["errors"])
    if e["budget_exhausted"]:
        stop = "stopped at the run budget: raise --max-runs"
    if e["factor"] is None:
        if e["none_up_to_max"]:
            return (f"no collapse up to factor {e['max_factor']:.6g} ({e['max_factor'] / e['onset_factor']:.3g} x the "
                    f"onset factor {e['onset_factor']:.4g}), factors run at most {reached} apart; {runs}")
        why = stop or ("with friction a joint may slide below A_L, which is not searched" if friction is not None
                       else f"factors run up to {reached} apart")
        return f"no collapse found up to factor {e['max_factor']:.6g} ({why}); {runs}"
    if e["smallest"]:
        return (f"the smallest at resolution {e['resolution']:g}: every factor run below it stands, consecutive "
                f"factors from the onset {e['onset_factor']:.4g} up to it at most {reached} apart; {runs}")
    why = stop or ("with friction a joint may slide below A_L, which is not searched" if friction is not None
                   else f"factors run below it are up to {reached} apart, a collapse may lie between them")
    return f"NOT called the smallest at resolution {e['resolution']:g} ({why}); {runs}"


def motion_lines(m: dict, k: int, friction: float | None = None) -> list[str]:
    """One ground motion of a :meth:`AssessResult.to_dict`; ``friction``: the joints' Coulomb
    coefficient of the ``auto`` model (None: they never slide)."""
    lines = [f"ground motion {k}: {m['name']} (PGA {m['pga_g']:.4g} g, {m['duration_s']:.4g} s)"]
    v = VERDICT_WORDS.get(m["verdict"], m["verdict"])
    if m["verdict"] == "cannot_stand":
        return lines + ["  verdict (auto): CANNOT STAND"]
    if m["t_collapse"] is not None:
        v += f" at t = {m['t_collapse']:.6g} s"
    elif m["outcome"] == "rest":
        v += f" (at rest at t = {m['t_end']:.4g} s)"
    else:
        v += f" (still moving at t = {m['t_end']:.4g} s)"
    lines.append(f"  verdict (auto): {v}")
    if m["t_peak"] is not None:
        lines.append(f"  peak rotation: {m['peak_rotation']:.6g} rad at t = {m['t_peak']:.6g} s")
    else:
        lines.append("  peak rotation: 0 (the member never moved)")
    ff = m["first_failure"]
    lines.append("  one-mechanism model: valid throughout" if ff is None else
                 f"  one-mechanism model first failed at t = {ff['t']:.6g} s: {ff['why']}")
    ti = m["time_in"]
    lines.append(f"  models: rock {ti['rock']:.4g} s, simulate {ti['simulate']:.4g} s; hand-overs {m['handovers']}, "
                 f"impacts {m['n_impacts']}")
    mg = m["margin"]
    if mg["skipped"] is not None:
        lines.append(f"  margin: {mg['skipped']}")
        return lines
    lines.append(f"  margin (first scale factor found to collapse it, hunt and fill at resolution "
                 f"{mg['auto']['resolution']:g}): auto {_factor(mg['auto'])}, rock {_factor(mg['rock'])}")
    for name in ("auto", "rock"):
        lines.append(f"    {name}: {_claim(mg[name], friction if name == 'auto' else None)}")
    if mg["ratio"] is not None:
        r = mg["ratio"]
        what = (f"the one-mechanism model alone overstates the margin {1 / r:.3g} times" if r < 1 else
                f"the one-mechanism model alone understates the margin {r:.3g} times" if r > 1 else
                "the one-mechanism model alone gives the same margin")
        lines.append(f"    auto / rock = {r:.4f}: {what}")
    for name in ("auto", "rock"):
        e = mg[name]
        if e["factor"] is not None and e["safe_above"]:
            lines.append(f"    {name}: safe factors found above it: " + ", ".join(
                f"{x:.4g}" for x in e["safe_factors_above"]) + " (the safe set is not an interval)")
        if e["collapse"] == "collapsed_by_sliding":
            lines.append(f"    {name}: the collapse at its margin is by sliding")
    return lines


def page(d: dict, member: str) -> str:
    """The text of ``fembeam assess`` from :meth:`AssessResult.to_dict`; ``member``: one line
    describing the member."""
    s = d["settings"]
    head = [f"fembeam assess: {member}",
            "  auto model: " + ("joints never slide" if s["friction"] is None else f"Coulomb friction mu = "
                                                                                   f"{s['friction']:g}")
            + f", simulation step {s['dt']:g} s"]
    if s.get("margin"):
        head.append(f"  margins: hunt and fill over the scale factors (as collapse-scale), resolution "
                    f"{s['resolution']:g}, at most {s['max_runs']} runs each, up to {s['span']:g} x the onset factor")
    lines = head + static_lines(d)
    for k, m in enumerate(d["motions"], 1):
        lines += motion_lines(m, k, s["friction"])
    return "\n".join(lines)


# --------------------------------------------------------------------------- figures
def statics_figure(result):
    """The member and its thrust line at ``A_L`` each way (two panels); the caller closes it."""
    from .motion import _pyplot
    from .plotting import draw_paper_figure
    plt = _pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(7.5, 8.4))
    for ax, d in zip(axes, (1, -1)):
        res = result.analyses[d]
        lim = res.limit
        ok = res.outcome in ("rocking", "arrested", "sliding")
        title = (f"direction {d:+d}: A_L = {res.A_L:.4f} g, thrust line at A_L and the hinges" if ok else
                 f"direction {d:+d}: {res.outcome.replace('_', ' ')}")
        draw_paper_figure(ax, lim.disc, res.hinges_before if ok else (), (), None,
                          lim.eccentricity if ok else None, title)
        for line in ax.get_lines():       # the incipient mechanism's hinges: no impact here
            if line.get_label() == "hinges before impact":
                line.set_label("hinges at A_L")
        ax.legend(loc="lower center", ncol=2, frameon=False, fontsize=9, bbox_to_anchor=(0.5, -0.12))
    fig.tight_layout()
    return fig


def history_figure(result, k: int):
    """Ground acceleration and rotation of motion ``k`` (0-based) against time; the caller closes it."""
    from .motion import _pyplot
    plt = _pyplot()
    run, m = result.runs[k], result.motions[k]
    h = run.history
    t = np.asarray(h.get("t", ()), float)
    fig, (ax_a, ax_r) = plt.subplots(2, 1, sharex=True, figsize=(8.0, 5.6))
    if t.size == 0:       # cannot stand: nothing moved
        g = run.ground
        ax_a.plot(g.t, g.a, color="tab:gray", lw=1.0)
    else:
        ax_a.plot(t, h["a_g"], color="tab:gray", lw=1.0)
        ax_r.plot(t, h["max_rotation"], color="tab:blue", lw=1.1, label="largest rotation of a piece or body")
    ax_a.axhline(0.0, color="black", lw=0.5)
    ax_a.set_ylabel(r"ground acceleration $a_g$ (g)")
    shaded = False
    for sg in run.segments:
        if sg.model == "simulate":
            for ax in (ax_a, ax_r):
                ax.axvspan(sg.t_start, sg.t_end, color="tab:orange", alpha=0.18, lw=0,
                           label=None if shaded or ax is ax_a else "multi-block simulation in use")
            shaded = True
    ff = m["first_failure"]
    if ff is not None:
        ax_r.axvline(ff["t"], color="tab:red", lw=1.2, ls="--",
                     label=f"one-mechanism model fails, t = {ff['t']:.3f} s ({ff['reason']})")
    if run.t_overturn is not None:
        ax_r.axvline(run.t_overturn, color="black", lw=1.5, label=f"{m['verdict']}, t = {run.t_overturn:.3f} s")
    elif run.t_peak is not None:
        ax_r.plot([run.t_peak], [run.peak_rotation], "o", color="tab:blue", mfc="none",
                  label=f"peak {run.peak_rotation:.4g} rad, t = {run.t_peak:.3f} s")
    ax_r.set_ylabel("rotation (rad)")
    ax_r.set_xlabel("time t (s)")
    if ax_r.get_legend_handles_labels()[0]:
        ax_r.legend(loc="best", fontsize=8)
    for ax in (ax_a, ax_r):
        ax.grid(True, lw=0.3, alpha=0.5)
    fig.suptitle(f"auto: {m['verdict']} - {m['name']}", fontsize=10)
    fig.tight_layout()
    return fig


def configuration_figure(result, k: int):
    """The member at the peak rotation or at overturning of motion ``k`` over its outline at rest
    (dashed) and the ground; the caller closes it."""
    from .motion import _pyplot, outline
    plt = _pyplot()
    snap, m = result.snapshots[k], result.motions[k]
    rest = outline(result.curve)
    fig, ax = plt.subplots(figsize=(7.0, 4.8))
    closed = np.hstack([rest, rest[:, :1]])
    ax.plot(closed[0], closed[1], color="grey", lw=0.8, ls="--", label="at rest")
    ground_y = float(rest[1].min())
    ax.axhline(ground_y, color="saddlebrown", lw=2.0)
    if snap is None:
        title = "the member never moved"
    else:
        for j, poly in enumerate(snap.polygons):
            ax.fill(poly[0], poly[1], facecolor="lightsteelblue", edgecolor="black", lw=1.0,
                    label=None if j else ("mechanism (rock)" if snap.model == "rock" else "bodies (simulate)"))
        if snap.pivots.size:
            ax.plot(snap.pivots[0], snap.pivots[1], "o", color="tab:red", ms=4, ls="none", label="hinges")
        at = m["configuration"]["at"]
        title = (f"at {at}: t = {snap.t:.4f} s, {snap.model}, largest rotation {snap.max_rotation:.4g} rad")
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=10)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, frameon=False, fontsize=8)
    ax.grid(True, lw=0.3, alpha=0.4)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------- report
REPORT_PATTERNS = ("statics.png", "motion_*_history.png", "motion_*_configuration.png",
                   "assess.json", "report.md")    # the files a report may hold: an earlier one's are replaced


def report_names(n_motions: int) -> list[str]:
    """The files of a report of ``n_motions`` ground motions, ``report.md`` last."""
    names = ["statics.png"]
    for k in range(1, n_motions + 1):
        names += [f"motion_{k:02d}_history.png", f"motion_{k:02d}_configuration.png"]
    return names + ["assess.json", "report.md"]


def check_report(directory, n_motions: int, option: str = "--report") -> Path:
    """Reject a report directory that cannot be written (exit 2), before any computation."""
    p = check_dir(directory, option)
    for name in report_names(n_motions):
        if (p / name).is_dir():
            raise InputError(f"{option}: {str(p / name)!r} is a directory")
    return p


def _markdown(d: dict, member: str, command: str | None) -> str:
    lines = ["# Assessment", "", f"Member: {member}.", ""]
    if command:
        lines += [f"Written by `{command}`.", ""]
    st = d["settings"]
    if st.get("margin"):
        lines += [f"Margins: hunt and fill over the scale factors of each motion (as `fembeam collapse-scale`), "
                  f"resolution {st['resolution']:g} (relative step between factors), at most {st['max_runs']} runs "
                  f"per search, up to {st['span']:g} times the onset factor.", ""]
    lines += ["## Statics", "", "```", *static_lines(d)[1:], "```", "",
              "![The member and its thrust line at A_L each way](statics.png)", ""]
    for k, m in enumerate(d["motions"], 1):
        lines += [f"## Ground motion {k}: {m['name']}", "", "```", *motion_lines(m, k, st["friction"])[1:], "```", "",
                  f"![Time history of the auto run](motion_{k:02d}_history.png)", "",
                  f"![The member at the {m['configuration']['at'] if m['configuration'] else 'start'}]"
                  f"(motion_{k:02d}_configuration.png)", ""]
    lines += ["Each number is explained in docs/assess.md; the full data are in [assess.json](assess.json).", ""]
    return "\n".join(lines)


def write_report(result, directory, member: str, command: str | None = None, dpi: int = 120) -> list[Path]:
    """``report.md``, ``assess.json`` and the figures of ``result`` in ``directory`` (created),
    written together atomically (:func:`~fembeam.output.files.atomic_dir`: an earlier report's
    figures of motions the new one lacks are removed); returns the paths.  ``member``: one line describing the member;
    ``command``: the command line, quoted in the report."""
    from .motion import _pyplot
    plt = _pyplot()
    p = check_report(directory, len(result.motions))
    d = result.to_dict()
    names = report_names(len(result.motions))
    makers = [lambda: statics_figure(result)]
    for k in range(len(result.motions)):
        makers += [lambda k=k: history_figure(result, k), lambda k=k: configuration_figure(result, k)]
    paths = [p / n for n in names]
    with atomic_dir(p, names, stale=REPORT_PATTERNS) as tmps:
        for make, tmp in zip(makers, tmps):
            fig = make()
            try:
                fig.savefig(tmp, dpi=dpi, format="png")
            finally:
                plt.close(fig)
        Path(tmps[-2]).write_text(json.dumps(d, allow_nan=False, indent=1) + "\n", encoding="utf-8")
        Path(tmps[-1]).write_text(_markdown(d, member, command), encoding="utf-8")
    return paths
