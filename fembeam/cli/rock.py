"""``fembeam rock``: the time history of an arch or a block under a ground motion.

Member options are those of ``analyze`` (and ``--voussoirs``), or ``--block WIDTH HEIGHT``;
the ground motion is a pulse (``--pulse rect|sine|ricker``) or a record (``--record``).  The
computation is :class:`fembeam.dynamics.rocking.Rocker`; this module parses, prints and writes.
"""
from __future__ import annotations


from ..dynamics.rocking import Rocker, RockingResult
from ..errors import InputError
from ..limits import bodies, check_history, check_steps
from ..output.files import write_table
from .args import (add_ground, add_member, arch_title, coulomb, finite_float, friction_line, ground_from, member_from,
                   motion_outputs, print_result, run_end, time_progress)

REASONS = {"below_rest": "centroid a tenth of the thickness below its height at rest",
           "linkage_locked": "the four-bar linkage locks"}


def register(sub) -> None:
    p = sub.add_parser("rock", help="time history under a ground motion: impacts, rest or overturning",
                       description="The whole motion of an arch (or a block) under a ground motion: onset at "
                                   "A_L, rocking along one mechanism at finite rotation, the impact model at "
                                   "every impact, rest, overturning; the first time the thrust line leaves "
                                   "the section.")
    add_member(p)
    add_ground(p)
    t = p.add_argument_group("time")
    t.add_argument("--t-end", type=finite_float, default=None, metavar="S",
                   help="end of the simulation (s; default: end of the ground motion + 20 sqrt(L/g); at most 1e5 s "
                        "after its start)")
    t.add_argument("--dt-out", type=finite_float, default=None, metavar="S",
                   help="sampling step of the history (s; default: 1/4000 of the simulated time; at most 1e6 rows)")
    t.add_argument("--no-thrust-check", action="store_true",
                   help="skip the thrust-line check along the motion (and with it the friction demand)")
    t.add_argument("--friction", type=coulomb, default=None, metavar="MU",
                   help="Coulomb coefficient MU > 0 at the joints: friction_demand's sliding_risk when the largest "
                        "|S|/N of the motion or |P_t|/P_n of an impact exceeds it (the motion itself never slides); "
                        "with --model auto (MU in [0.001, 1000]) a demand above MU hands the motion over to the "
                        "multi-block simulation, whose joints slide by Coulomb's law")
    t.add_argument("--model", choices=("rock", "auto"), default="rock",
                   help="rock: one mechanism between impacts (the paper's model); auto: rock while its mechanism "
                        "is admissible (thrust line inside every section, friction demand within MU), the "
                        "multi-block simulation (fembeam simulate) from the first violation, back to rock at rest "
                        "or on a mechanism (docs/dynamics.md, 'The hand-over')")
    t.add_argument("--dt", type=finite_float, default=None, metavar="S",
                   help="--model auto: time step of the simulation (s; default 1e-3, in [1e-6, 0.05])")
    o = p.add_argument_group("output")
    o.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    o.add_argument("--history", action="store_true", help="with --json: add the sampled history")
    o.add_argument("--csv", metavar="PATH.csv", help="history: t (s), mechanism, theta (rad), rate (rad/s), K, V (J/m), a_g (g)")
    o.add_argument("--plot", metavar="PATH.png", help="figure of a_g, rotation and energy with the impacts")
    o.add_argument("--vtk", metavar="PATH.pvd", help="ParaView time series of the moving member")
    o.add_argument("--gif", metavar="PATH.gif", help="animation of the moving member")
    o.add_argument("--frames", type=int, default=None, metavar="N",
                   help="--vtk and --gif: at most N frames, taken from the history (default 200 and 120)")
    p.set_defaults(func=run)


def hinges_text(m) -> str:
    return " ".join(f"{a:.2f}{k[0]}" for a, k in zip(m.angles_deg(), m.sides))


def summary(res: RockingResult, max_impacts: int = 12) -> str:
    geo = res.to_dict()["geometry"]
    if geo.get("shape") == "block":
        head = f"block {geo['width']:g} m x {geo['height']:g} m on a rigid base"
    else:
        head = (f"{geo.get('shape', 'member')} arch, embrace {geo.get('embrace_deg', 0):g} deg, "
                f"t/R = {geo.get('t_over_R', 0):g}, R = {geo.get('radius', 0):g} m" if "embrace_deg" in geo
                else arch_title(geo)) + (f"; {res.mode}, {res.n} "
                                         f"{'voussoirs' if res.mode == 'voussoirs' else 'elements'}")
    lines = [f"fembeam rock: {head}",
             f"  ground motion: {res.ground.name} (PGA {res.ground.pga:.4g} g), simulated to t = {res.t_end:.4g} s"]
    if res.outcome == "cannot_stand":
        lines.append("  outcome: cannot_stand (the member does not stand under its own weight: fembeam analyze)")
        return "\n".join(lines)
    A = res.A_L
    lines.append(f"  onset: inertia load above A_L = {A[1]:.6g} g to the right (a_g < 0) or "
                 f"{A[-1]:.6g} g to the left (a_g > 0)")
    if res.outcome == "overturned":
        lines.append(f"  outcome: OVERTURNED at t = {res.t_overturn:.6g} s ({REASONS[res.overturn_reason]})")
    elif res.outcome == "rest":
        lines.append(f"  outcome: rest (the member is at rest at t = {res.t_end:.4g} s)")
    else:
        lines.append(f"  outcome: survived (still moving at t = {res.t_end:.4g} s)")
    if res.t_peak is not None:
        lines.append(f"  peak rotation: {res.peak_rotation:.6g} rad at t = {res.t_peak:.6g} s (largest of any piece; "
                     f"theta {res.peak_theta:.6g} rad at t = {res.t_peak_theta:.6g} s)")
    if res.thrust_line_exits_at is not None:
        lines.append(f"  thrust line leaves the section at t = {res.thrust_line_exits_at:.6g} s: from then on other "
                     f"hinges would open (the one-mechanism model is not valid)")
    elif res.onsets and res.thrust_checked:
        lines.append("  thrust line inside the section throughout the motion")
    if friction_line(res) is not None:
        lines.append(friction_line(res))
    lines.append(f"  energy: ground work {res.ground_work:.6g} J/m, dissipated by the impacts "
                 f"{res.dissipated:.6g} J/m; balance error {res.energy_balance_error:.2e} (relative)")
    lines.append(f"  impacts: {len(res.impacts)}; mechanisms met: {len(res.mechanisms)}")
    if res.impacts:
        lines.append("      t [s]          r       r_qp  hinges before -> after (deg, i/e)")
        for e in res.impacts[:max_impacts]:
            after = hinges_text(res.mechanisms[e.after]) if e.after is not None else "arrested"
            rq = f"{e.r_qp:10.6f}" if e.r_qp is not None else "         -"
            lines.append(f"  {e.t:9.5f} {e.r:10.6f} {rq}  {hinges_text(res.mechanisms[e.before])} -> {after}"
                         + ("  (rest)" if e.at_rest and e.after is not None else ""))
        if len(res.impacts) > max_impacts:
            lines.append(f"  ... {len(res.impacts) - max_impacts} more (--json lists them all)")
    return "\n".join(lines)


def write_csv(res: RockingResult, path) -> None:
    """The history, streamed (:func:`~fembeam.output.files.write_table`)."""
    write_table(path, res.history)


def run(args) -> int:
    if args.model == "auto":
        return run_auto(args)
    if args.dt is not None:
        raise InputError("--dt is the time step of the multi-block simulation: it applies to --model auto only")
    outputs = motion_outputs(args)
    if args.friction is not None and args.no_thrust_check:
        raise InputError("--friction is checked against the friction demand, which comes with the thrust-line "
                         "check: drop --no-thrust-check")
    curve, voussoirs, elements = member_from(args)
    ground = ground_from(args)
    end = run_end(args, curve, ground)
    check_history(end - float(ground.t[0]), args.dt_out)
    rocker = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=args.backend, qp=not args.no_qp)
    t_end = args.t_end if args.t_end is not None else None
    update, bar = time_progress(end)
    try:
        res = rocker.run(ground, t_end=t_end, dt_out=args.dt_out, thrust_check=not args.no_thrust_check,
                         progress=update, friction=args.friction)
    finally:
        if bar is not None:
            bar.close()
    written = []
    if outputs["csv"]:
        write_csv(res, outputs["csv"])
        written.append(f"CSV: {outputs['csv']}")
    if outputs["plot"] or outputs["vtk"] or outputs["gif"]:
        from ..output import motion
        if outputs["plot"]:
            motion.plot_history(res, outputs["plot"])
            written.append(f"figure: {outputs['plot']}")
        if outputs["vtk"]:
            files = motion.write_pvd(res, outputs["vtk"], frames=args.frames or 200)
            written.append(f"VTK: {outputs['vtk']} ({len(files) - 1} frames)")
        if outputs["gif"]:
            motion.write_gif(res, outputs["gif"], frames=args.frames or 120)
            written.append(f"animation: {outputs['gif']}")
    return _emit(args, res, summary, written)


def run_auto(args) -> int:
    """``fembeam rock --model auto`` (:class:`fembeam.auto.AutoModel`)."""
    from ..auto import AutoModel
    from ..auto.model import DT
    outputs = motion_outputs(args)
    if outputs["vtk"] or outputs["gif"]:
        raise InputError("--vtk and --gif draw one mechanism's motion: use them with --model rock, or fembeam "
                         "simulate for the multi-block motion")
    if args.no_thrust_check:
        raise InputError("--model auto checks the thrust line to decide when to hand over: drop --no-thrust-check")
    curve, voussoirs, elements = member_from(args, "auto")
    ground = ground_from(args)
    end = run_end(args, curve, ground)
    dt = DT if args.dt is None else args.dt
    n = bodies(voussoirs, elements, args.block is not None)
    check_steps(dt, end - float(ground.t[0]), n)      # the simulation may take over at the start
    check_history(end - float(ground.t[0]), args.dt_out, n)
    model = AutoModel(curve, voussoirs=voussoirs, elements=elements, friction=args.friction, dt=dt,
                      backend=args.backend)
    t_end = args.t_end
    update, bar = time_progress(end)
    try:
        res = model.run(ground, t_end=t_end, dt_out=args.dt_out, progress=update)
    finally:
        if bar is not None:
            bar.close()
    written = []
    if outputs["csv"]:
        write_table(outputs["csv"], res.history)
        written.append(f"CSV: {outputs['csv']}")
    if outputs["plot"]:
        from ..output.motion import plot_auto
        plot_auto(res, outputs["plot"])
        written.append(f"figure: {outputs['plot']}")
    return _emit(args, res, auto_summary, written)


def _emit(args, res, page, written: list[str]) -> int:
    """Print ``res`` as JSON (``--json``, with ``--history``) or as its text ``page(res)`` followed by
    the files written."""
    return print_result(args.json, lambda: res.to_dict(history=args.history), lambda: page(res), written)


def auto_summary(res) -> str:
    """The text page of ``rock --model auto``."""
    geo = res.to_dict()["geometry"]
    head = (f"block {geo['width']:g} m x {geo['height']:g} m on a rigid base" if geo.get("shape") == "block"
            else arch_title(geo) + f"; {res.mode}, {res.n} {'voussoirs' if res.mode == 'voussoirs' else 'elements'}")
    mu = "joints never slide" if res.friction is None else f"Coulomb friction mu = {res.friction:g}"
    lines = [f"fembeam rock --model auto: {head}",
             f"  ground motion: {res.ground.name} (PGA {res.ground.pga:.4g} g), simulated to t = {res.t_end:.4g} s",
             f"  models: rock while its mechanism is admissible, simulate (dt = {res.dt:g} s, {mu}) after"]
    if res.outcome == "cannot_stand":
        lines.append("  outcome: cannot_stand (the member does not stand under its own weight: fembeam analyze)")
        return "\n".join(lines)
    if res.outcome in ("overturned", "collapsed_by_sliding"):
        what = "OVERTURNED" if res.outcome == "overturned" else "COLLAPSED BY SLIDING"
        lines.append(f"  outcome: {what} at t = {res.t_overturn:.6g} s")
    else:
        lines.append(f"  outcome: {res.outcome} at t = {res.t_end:.4g} s")
    if res.t_peak is not None:
        lines.append(f"  peak rotation: {res.peak_rotation:.6g} rad at t = {res.t_peak:.6g} s "
                     f"(largest of any piece or body)")
    if res.first_failure is None:
        lines.append("  the one-mechanism model held throughout: this is rock's answer")
    else:
        from ..auto.model import REASONS
        t, why = res.first_failure
        lines.append(f"  the one-mechanism model first failed at t = {t:.6g} s: {REASONS[why]}")
    if res.no_handback is not None:
        t, why = res.no_handback
        lines.append(f"  not handed back at rest (t = {t:.6g} s): {why}")
    lines.append(f"  segments ({res.handovers} hand-overs):")
    for sg in res.segments[:20]:
        lines.append(f"    {sg.model:8s} {sg.t_start:10.5f} -> {sg.t_end:10.5f} s  ended: {sg.end}")
    if len(res.segments) > 20:
        lines.append(f"    ... {len(res.segments) - 20} more (--json lists them all)")
    fd = res.to_dict()["friction_demand"]
    if fd["t"] is not None:
        line = f"  friction demand: largest |S|/N = {fd['max_ratio']:.4f} at t = {fd['t']:.6g} s"
        if fd["mu"] is not None:
            line += f" (mu = {fd['mu']:g})"
        lines.append(line)
    return "\n".join(lines)
