"""``fembeam simulate``: the non-smooth multi-body time history of the rigid pieces of a member.

Member and ground-motion options are those of ``fembeam rock`` (:func:`~.rock.add_member`,
:func:`~.rock.add_ground`); the computation is :class:`fembeam.simulation.Simulator`; this module
parses, prints and writes.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

from ..dynamics.ground import GroundMotion
from ..errors import InputError
from ..limits import bodies, check_history, check_steps
from ..output.files import atomic, atomic_group, write_table
from .args import (add_ground, add_member, arch_title, coulomb, friction_line, ground_from, member_from,
                   motion_outputs, run_end, time_progress)

HELP = "multi-body time history: Moreau-Jean steps, impact QP at every step, hinges anywhere"


def register(sub) -> None:
    p = sub.add_parser("simulate", help=HELP,
                       description="Non-smooth time stepping of the voussoirs (or rigid elements, or a block) "
                                   "under gravity and a ground motion: at every step the free velocity is "
                                   "projected onto the compatible cone in the kinetic metric (the impact QP of "
                                   "fembeam impact), so hinges open and close anywhere.")
    add_member(p)
    w = add_ground(p)
    w.add_argument("--support-motion", type=_support_kind, default=None, metavar="spread|settle|DX,DY",
                   help="instead of a ground motion: the supports move (as fembeam supports' movements): spread "
                        "(apart horizontally, each by half the span increase D), settle (the right one down by D) or "
                        "DX,DY (the right one along that direction by D); D = --support-rate x t, held after "
                        "--support-up-to")
    sm = p.add_argument_group("support motion (with --support-motion)")
    sm.add_argument("--support-rate", type=float, default=None, metavar="M_PER_S",
                    help="rate of the support displacement D (m/s, > 0; slow enough for a quasi-static path: the "
                         "kinetic energy stays much below the work of the supports)")
    sm.add_argument("--support-up-to", type=float, default=None, metavar="D",
                    help="the displacement (m, > 0) at which the supports stop and are held (default: they move on "
                         "until the end: --t-end, by default the time to reach half the span plus 20 sqrt(L/g))")
    sm.add_argument("--support-left", action="store_true",
                    help="with settle or DX,DY: the left support moves instead of the right one")
    t = p.add_argument_group("time")
    t.add_argument("--dt", type=float, default=1e-3, metavar="S",
                   help="time step (s; default 1e-3, in [1e-6, 0.05]; at most 1e7 steps and 2e7 steps x bodies)")
    t.add_argument("--t-end", type=float, default=None, metavar="S",
                   help="end of the simulation (s; default: end of the ground motion + 20 sqrt(L/g); at most 1e5 s "
                        "after its start)")
    t.add_argument("--dt-out", type=float, default=None, metavar="S",
                   help="sampling step of the history (s; default max(dt, duration/4000); at most 1e6 rows and "
                        "2e7 rows x bodies)")
    t.add_argument("--friction", type=coulomb, default=None, metavar="MU",
                   help="Coulomb friction at the joints, MU in [1e-3, 1e3], or inf (the default: no sliding); the slip is "
                        "reported, a joint that slid has a friction demand of at least MU (sliding_risk), and "
                        "the member has collapsed by sliding when a joint's faces no longer overlap or when it "
                        "falls to the overturning level with its joints slid more than opened")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--history", action="store_true", help="with --json: add the sampled history")
    o.add_argument("--csv", metavar="PATH.csv", help="history: t (s), K, V, W_ground, dissipated (J/m), a_g (g), hinges, "
                                                      "...; with --support-motion also support_displacement (m), "
                                                      "H_left, V_left, H_right, V_right (kN/m)")
    o.add_argument("--plot", metavar="PATH.png", help="figure of a_g, rotations, open hinges and energies")
    o.add_argument("--thrust-plot", metavar="PATH.png",
                   help="with --support-motion: figure of H and V on the supports (kN/m) against the support "
                        "displacement, the simulation's mean forces over the quasi-static path of fembeam supports "
                        "(the same arch, pieces and movement)")
    o.add_argument("--vtk", metavar="PATH.pvd", help="ParaView time series of the bodies' polygons")
    o.add_argument("--gif", metavar="PATH.gif", help="animation of the moving bodies")
    o.add_argument("--frames", type=int, default=None, metavar="N",
                   help="--vtk and --gif: at most N frames of the history (default 200 and 120)")
    p.set_defaults(func=run)


def _support_kind(text: str):
    """``spread``, ``settle`` or ``(dx, dy)`` of ``DX,DY``."""
    import argparse

    from .supports import _vector
    if text in ("spread", "settle"):
        return text
    if "," not in text:
        raise argparse.ArgumentTypeError(f"expected spread, settle or DX,DY, got {text!r}")
    return _vector(text)


def support_motion_from(args):
    """The :class:`~fembeam.simulation.support_motion.SupportMotion` of the options (None without
    ``--support-motion``); InputError on bad input."""
    from ..simulation.support_motion import SupportMotion
    given = [o for o, v in (("--support-rate", args.support_rate is not None),
                            ("--support-up-to", args.support_up_to is not None),
                            ("--support-left", args.support_left)) if v]
    if args.support_motion is None:
        if given:
            raise InputError(f"{given[0]} needs --support-motion spread|settle|DX,DY")
        return None
    if args.support_rate is None:
        raise InputError("--support-motion needs --support-rate M_PER_S (m/s, > 0)")
    kind = args.support_motion
    if kind == "spread" and args.support_left:
        raise InputError("--support-motion spread moves both supports apart: --support-left does not apply")
    if isinstance(kind, tuple):
        return SupportMotion.of("move", args.support_rate, vector=kind, left=args.support_left,
                                up_to=args.support_up_to)
    return SupportMotion.of(kind, args.support_rate, left=args.support_left, up_to=args.support_up_to)


def support_end(args, curve, motion, t0: float) -> float:
    """``--t-end``, or by default the time the supports take to move half the span (to
    ``--support-up-to`` if given) plus ``20 sqrt(L/g)`` (s)."""
    from ..dynamics.equation import GRAVITY
    from ..limits import check_duration
    if args.t_end is not None:
        t_end = args.t_end
    else:
        x = curve.position(np.array([0.0, curve.length]))
        span = float(abs(x[0, 1] - x[0, 0])) or curve.length
        reach = motion.up_to if motion.up_to is not None else 0.5 * span
        t_end = t0 + reach / motion.rate + 20.0 * math.sqrt(curve.length / GRAVITY)
    if not t_end > t0:
        raise InputError(f"--t-end must be after the start ({t0:g} s), got {t_end:g}")
    check_duration(t_end - t0)
    return t_end


def support_lines(res) -> list[str]:
    """The text lines of a prescribed support motion."""
    b = res.support_block()
    mo = res.support_motion
    side = "left" if mo.kind != "spread" and any(mo.left) else "right"
    d = mo.left if side == "left" else mo.right
    what = {"spread": "spreading (each support outward by D/2)", "settle": f"settlement of the {side} support by D",
            "move": f"the {side} support along ({d[0]:.4g}, {d[1]:.4g}) by D",
            "rigid": f"both supports together along ({d[0]:.4g}, {d[1]:.4g}) by D"}[mo.kind]
    lines = [f"  supports moved: {what}, D = {mo.rate:g} m/s x t"
             + (f", held at {mo.up_to:g} m" if mo.up_to is not None else "")]
    if b["displacement_at_collapse"] is not None:
        lines.append(f"  SUPPORT DISPLACEMENT AT COLLAPSE: {b['displacement_at_collapse']:.6g} m")
    else:
        lines.append(f"  support displacement at the end: {b['displacement_end']:.6g} m (no collapse)")
    f = b["last_forces_kN_per_m"]
    if f["H_left"] is not None:
        lines.append(f"  last forces on the supports: H {f['H_left']:.5g} / {f['H_right']:.5g} kN/m (left / right, "
                     f"outward), V {f['V_left']:.5g} / {f['V_right']:.5g} kN/m (downward)")
    return lines


def summary(res) -> str:
    geo = res.to_dict()["geometry"]
    if geo.get("shape") == "block":
        head = f"block {geo['width']:g} m x {geo['height']:g} m on a rigid base"
    else:
        head = (f"circular arch, embrace {geo.get('embrace_deg', 0):g} deg, t/R = {geo.get('t_over_R', 0):g}, "
                f"R = {geo.get('radius', 0):g} m" if "embrace_deg" in geo else arch_title(geo))
        head += f"; {res.n_bodies} {'voussoirs' if res.mode == 'voussoirs' else 'rigid elements'}"
    lines = [f"fembeam simulate: {head}",
             f"  ground motion: {res.ground.name} (PGA {res.ground.pga:.4g} g); dt = {res.dt:g} s, "
             f"simulated to t = {res.t_end:.4g} s ({res.steps} steps, {res.cut_steps} cut at landings)"]
    if res.support_motion is not None:
        lines += support_lines(res)
    if res.outcome == "cannot_stand":
        lines.append("  outcome: cannot_stand (the pieces do not stand under their own weight: fembeam analyze); "
                     "no motion computed")
        return "\n".join(lines)
    if res.outcome == "overturned":
        why = ("the energy released beyond the supports' work that of a fall of a tenth of the thickness"
               if res.support_motion is not None else "centroid a tenth of the thickness below its height at rest")
        lines.append(f"  outcome: OVERTURNED at t = {res.t_overturn:.6g} s ({why})")
    elif res.outcome == "collapsed_by_sliding":
        lines.append(f"  outcome: COLLAPSED BY SLIDING at t = {res.t_overturn:.6g} s (a joint's faces no longer "
                     f"overlap, or the centroid fell a tenth of the thickness with the joints slid more than opened)")
    elif res.outcome == "rest":
        lines.append(f"  outcome: rest (at rest at t = {res.t_end:.4g} s)")
    else:
        lines.append(f"  outcome: survived (still moving at t = {res.t_end:.4g} s)")
    if res.t_peak is not None:
        lines.append(f"  peak rotation: {res.peak_rotation:.6g} rad at t = {res.t_peak:.6g} s")
    lines.append(f"  impacts: {len(res.impacts)}; most hinges open at once: {res.max_hinges}")
    fl = friction_line(res) if res.friction is None else friction_line(res).split(":", 1)[0] + ":" + \
        friction_line(res).split(":", 1)[1].rsplit(": SLIDING RISK", 1)[0].rsplit(" (within mu", 1)[0]
    if fl is not None:
        lines.append(fl)
    if res.friction is not None:
        where = "" if res.s_slip is None else f" at s = {res.s_slip:.6g} m, t = {res.t_slip:.6g} s"
        lines.append(f"  sliding (mu = {res.friction:g}): largest slip {res.max_slip:.4g} m{where}; "
                     f"{res.sliding_steps} steps with sliding joints")
    lines.append(f"  energy: dissipated {res.dissipated:.6g} J/m, ground work {res.ground_work:.6g} J/m, "
                 f"balance error {res.energy_balance_error:.2e} (relative)")
    lines.append(f"  wall time {res.time:.3g} s (compiled loop {res.timings.get('run', res.time):.3g} s)")
    return "\n".join(lines)


def write_csv(res, path) -> None:
    """The history, streamed (:func:`~fembeam.output.files.write_table`)."""
    write_table(path, res.history, integer=("hinges", "separated"))


def _frames(res, frames: int) -> np.ndarray:
    from ..output.motion import frame_rows
    return frame_rows(np.asarray(res.history["t"]), frames)


def placed(res, i: int, outlines) -> list[np.ndarray]:
    """Polygons ``(2, k)`` of the bodies at history row ``i`` (m)."""
    q = res.positions[i]
    out = []
    for (x, y, phi), poly in zip(q, outlines):
        c, s = math.cos(phi), math.sin(phi)
        out.append(np.array([x + c * poly[0] - s * poly[1], y + s * poly[0] + c * poly[1]]))
    return out


def write_pvd(res, path: Path, frames: int = 200) -> int:
    """``path`` (.pvd) and one ``.vtu`` per frame next to it (polygons of the bodies, cell data
    ``body``), replacing the series there as a whole (:func:`~fembeam.output.files.atomic_group`).
    Returns the number of frames."""
    import meshio

    from ..output.motion import _pvd_text, previous_series
    rows = _frames(res, frames)
    outlines = res.bodies.outlines()
    width = max(4, len(str(rows.size - 1)))
    names = [path.with_name(f"{path.stem}_{j:0{width}d}.vtu") for j in range(rows.size)]
    with atomic_group(names + [path], replaces=previous_series(path)) as tmps:
        for j, i in enumerate(rows):
            polys = placed(res, int(i), outlines)
            pts = np.hstack(polys).T
            offsets = np.cumsum([0] + [p.shape[1] for p in polys])
            cells = [("polygon", np.arange(a, b)[None, :]) for a, b in zip(offsets[:-1], offsets[1:])]
            mesh = meshio.Mesh(np.column_stack([pts, np.zeros(len(pts))]), cells,
                               cell_data={"body": [np.array([k], np.int32) for k in range(len(polys))]})
            meshio.write(tmps[j], mesh, file_format="vtu")
        entries = [(float(res.history["t"][i]), n.name) for i, n in zip(rows, names)]
        Path(tmps[-1]).write_text(_pvd_text(entries), encoding="utf-8")
    return rows.size


def history_figure(res):
    from ..output.motion import _pyplot
    plt = _pyplot()
    h = res.history
    fig, ax = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    if res.support_motion is not None:
        ax[0].plot(h["t"], h["H_left"], lw=0.8, label="H left")
        ax[0].plot(h["t"], h["H_right"], lw=0.8, label="H right")
        ax[0].set_ylabel("thrust [kN/m]")
        ax[0].legend(loc="upper left", fontsize=8)
    else:
        ax[0].plot(h["t"], h["a_g"], lw=0.8)
        ax[0].set_ylabel("a_g [g]")
    ax[1].plot(h["t"], h["max_rotation"], lw=0.8)
    ax[1].set_ylabel("max |phi| [rad]")
    ax[2].step(h["t"], h["hinges"], where="post", lw=0.8, label="hinges")
    ax[2].step(h["t"], h["separated"], where="post", lw=0.8, label="separated joints")
    ax[2].set_ylabel("joints")
    ax[2].legend(loc="upper right", fontsize=8)
    ax[3].plot(h["t"], h["K"], lw=0.8, label="K")
    ax[3].plot(h["t"], h["V"], lw=0.8, label="V")
    ax[3].plot(h["t"], h["dissipated"], lw=0.8, label="dissipated")
    ax[3].set_ylabel("energy [J/m]")
    ax[3].set_xlabel("t [s]")
    ax[3].legend(loc="upper right", fontsize=8)
    if res.t_overturn is not None:
        for a in ax:
            a.axvline(res.t_overturn, color="red", lw=0.8, ls="--")
    fig.suptitle(f"fembeam simulate: {res.outcome} - {res.ground.name}", fontsize=10)
    fig.tight_layout()
    return fig


def plot_history(res, path) -> None:
    from ..output.motion import _pyplot
    fig = history_figure(res)
    try:
        with atomic(path) as tmp:
            fig.savefig(tmp, dpi=120, format=Path(path).suffix[1:])
    finally:
        _pyplot().close(fig)


def write_gif(res, path, frames: int = 120, fps: int = 20) -> None:
    """Animation of the bodies' polygons (matplotlib's Pillow writer, headless)."""
    from matplotlib.patches import Polygon

    from ..output.animation import save_gif

    from ..output.motion import _pyplot
    plt = _pyplot()
    rows = _frames(res, frames)
    outlines = res.bodies.outlines()
    allp = np.hstack([p for i in rows for p in placed(res, int(i), outlines)])
    lo, hi = allp.min(axis=1), allp.max(axis=1)
    pad = 0.08 * float(max(hi - lo))
    fig, ax = plt.subplots(figsize=(6.0, 4.5))
    try:
        ax.set_aspect("equal")
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_axis_off()
        patches = [ax.add_patch(Polygon(p.T, closed=True, fc="lightsteelblue", ec="black", lw=0.8))
                   for p in placed(res, int(rows[0]), outlines)]
        text = ax.set_title("")

        def draw(j):
            for patch, p in zip(patches, placed(res, int(rows[j]), outlines)):
                patch.set_xy(p.T)
            text.set_text(f"t = {res.history['t'][rows[j]]:.3f} s   a_g = {res.history['a_g'][rows[j]]:+.3f} g")
            return patches

        save_gif(fig, draw, len(rows), path, fps, 80)
    finally:
        plt.close(fig)


def quasi_static(res, curve, voussoirs, elements):
    """``(SupportsResult or None, note or None)``: the path of ``fembeam supports`` for the
    movement of ``res`` (a run with a support motion) on ``curve``, the same pieces, up to 1.1
    times the largest displacement simulated; None with the reason when there is none."""
    from ..analysis.supports import Movement, supports
    from ..errors import SolverError
    mo = res.support_motion
    if mo.kind == "rigid":
        return None, "no quasi-static path: both supports move together (the arch does not deform)"
    left = mo.kind != "spread" and any(mo.left)
    mv = Movement.of(mo.kind, None if mo.kind != "move" else (mo.left if left else mo.right), left=left)
    reach = float(np.max(res.history["support_displacement"], initial=0.0))
    if not reach > 0:
        return None, "no quasi-static path: the supports did not move"
    kw = {"voussoirs": voussoirs} if voussoirs is not None else {"elements": elements}
    try:
        qs = supports(curve, mv, up_to=1.1 * reach, **kw)
    except (InputError, SolverError) as e:
        return None, f"no quasi-static path: {e}"
    if qs.outcome == "cannot_stand":
        return None, "no quasi-static path: the arch cannot stand at rest"
    return qs, None


def plot_thrust(res, path, curve, voussoirs, elements) -> str:
    """``--thrust-plot``: the figure written; returns the line that names it."""
    from ..output.supports import plot_support_thrust
    qs, note = quasi_static(res, curve, voussoirs, elements)
    plot_support_thrust(res, path, qs, note)
    if qs is None:
        return f"thrust figure: {path} ({note})"
    cap = ("" if qs.capacity is None else f": capacity {qs.capacity:.6g} m")
    return f"thrust figure: {path} (over the quasi-static path{cap})"


def run(args) -> int:
    from ..output.files import PLOT_SUFFIXES, check_distinct, check_output
    from ..simulation import Simulator
    from ..simulation.stepper import check_dt
    outputs = motion_outputs(args)
    outputs["thrust_plot"] = check_output(args.thrust_plot, "--thrust-plot", PLOT_SUFFIXES)
    check_distinct({"--csv": args.csv, "--plot": args.plot, "--vtk": args.vtk, "--gif": args.gif,
                    "--thrust-plot": args.thrust_plot})
    if args.thrust_plot is not None and args.support_motion is None:
        raise InputError("--thrust-plot needs --support-motion spread|settle|DX,DY")
    for name in ("dt", "t_end", "dt_out"):
        x = getattr(args, name)
        if x is not None and not math.isfinite(x):
            raise InputError(f"--{name.replace('_', '-')} must be a finite number, got {x}")
    curve, voussoirs, elements = member_from(args, "simulate")
    motion = support_motion_from(args)
    if motion is None:
        ground = ground_from(args)
        t_end = run_end(args, curve, ground)
    else:
        ground = GroundMotion(np.array([0.0, 1.0]), np.zeros(2), "none (supports moved)", True)
        t_end = support_end(args, curve, motion, 0.0)
    check_dt(args.dt, float(ground.t[0]), t_end)
    n = bodies(voussoirs, elements, args.block is not None)
    check_steps(args.dt, t_end - float(ground.t[0]), n)
    check_history(t_end - float(ground.t[0]), args.dt_out, n)
    kw = {"voussoirs": voussoirs} if voussoirs is not None else {"elements": elements}
    sim = Simulator(curve, friction=args.friction, **kw)
    if not sim.stands:                   # a physical answer, like rock's and analyze's: exit 0
        res = sim.cannot_stand(ground, args.dt)
        if args.json:
            print(json.dumps(res.to_dict(history=args.history), allow_nan=False))
        else:
            print(summary(res))
            if any(outputs.values()):
                print("  no files written: no motion to write")
        sys.stdout.flush()
        return 0
    update, bar = time_progress(t_end)
    try:
        res = sim.run(ground, dt=args.dt, t_end=t_end, dt_out=args.dt_out, progress=update, support_motion=motion)
    finally:
        if bar is not None:
            bar.close()
    written = []
    if outputs["csv"]:
        write_csv(res, outputs["csv"])
        written.append(f"CSV: {outputs['csv']}")
    if outputs["plot"]:
        plot_history(res, outputs["plot"])
        written.append(f"figure: {outputs['plot']}")
    if outputs["vtk"]:
        k = write_pvd(res, outputs["vtk"], frames=args.frames or 200)
        written.append(f"VTK: {outputs['vtk']} ({k} frames)")
    if outputs["gif"]:
        write_gif(res, outputs["gif"], frames=args.frames or 120)
        written.append(f"animation: {outputs['gif']}")
    if outputs["thrust_plot"]:
        written.append(plot_thrust(res, outputs["thrust_plot"], curve, voussoirs, elements))
    if args.json:
        print(json.dumps(res.to_dict(history=args.history), allow_nan=False))
    else:
        print(summary(res))
        for w in written:
            print(f"  {w}")
    sys.stdout.flush()
    return 0
