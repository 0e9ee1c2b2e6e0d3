"""The bounds of the motion commands and studies, checked before anything is computed.

Every input accepted by ``rock``, ``simulate``, ``spectrum`` and ``collapse-scale`` leads to a
bounded amount of work and memory; an input beyond a bound is an
:class:`~fembeam.errors.InputError` (exit 2, one line) naming the bound.  The bounds are
documented in docs/user_guide.md ("Limits") and in ``--help``:

* :data:`BLOCK_ASPECT_RANGE`: width / height of a ``--block``.  A slenderer block makes the
  impact QP lose its precision (impulses verified to 1e-6 fail from width / height 1e-5), a
  squatter one needs more than :data:`~fembeam.dynamics.ground.MAX_PGA` to move at all (its
  limit LP fails from 1e6);
* :data:`ROCK_VOUSSOIRS`, :data:`ROCK_MAX_ELEMENTS`: the one-mechanism model follows
  four-hinge mechanisms (at least four joints), chosen after each impact by an exhaustive
  search over the joints (81 at most); each impact of a continuous arch solves a QP on its
  mesh (about 0.6 s at 20000 elements);
* :data:`SIMULATE_MAX_BODIES`, :data:`MAX_BODY_STEPS`, :data:`MAX_STEPS`: the multi-body
  simulation's contact problem keeps its KKT check up to about 1000 bodies, and a step
  costs more than linearly in the bodies (1.4 ms at 200 moving elements, 9-120 ms at 1000),
  so the steps of one run times its bodies are bounded (the default 200 elements through
  El Centro: 1.3e7);
* :data:`MAX_DURATION`: the simulated time of one run (s);
* :data:`MAX_HISTORY_ROWS`, :data:`MAX_HISTORY_POSITIONS`: the sampled history (about 0.5 GB
  at the bound with ``--json --history``); ``simulate`` keeps every body's position per row;
* :data:`MAX_WORKERS`: local worker processes of a study (never more than its tasks);
* :data:`MAX_COMMAND_RUNS`: the time histories one study command may make at most (its searches
  times their run budget ``--max-runs``), so that a large suite or budget is refused before
  computing rather than running for days.
"""
from __future__ import annotations

import math

from .errors import InputError

__all__ = ["BLOCK_ASPECT_RANGE", "ROCK_VOUSSOIRS", "ROCK_MAX_ELEMENTS", "SIMULATE_MAX_BODIES", "MAX_BODY_STEPS",
           "MAX_STEPS", "DT_RANGE", "MAX_DURATION", "MAX_HISTORY_ROWS", "MAX_HISTORY_POSITIONS", "MAX_WORKERS",
           "check_block", "check_discretisation", "bodies", "check_steps", "check_duration", "check_history",
           "check_workers", "MAX_COMMAND_RUNS", "check_run_count"]

BLOCK_ASPECT_RANGE = (1e-3, 1e3)     # width / height of a rocking block
ROCK_VOUSSOIRS = (3, 80)             # voussoirs of rock: 4 joints at least, 81 at most (the exhaustive search)
ROCK_MAX_ELEMENTS = 20_000           # rigid elements of a continuous arch in rock
SIMULATE_MAX_BODIES = 1000           # voussoirs or rigid elements of simulate
DT_RANGE = (1e-6, 0.05)              # s: time steps of the multi-body simulation
MAX_STEPS = 10_000_000               # time steps of one simulate run
MAX_BODY_STEPS = 20_000_000          # time steps x bodies of one simulate run
MAX_DURATION = 1e5                   # s: simulated time of one run (t_end - start of the ground motion)
MAX_HISTORY_ROWS = 1_000_000         # rows of the sampled history
MAX_HISTORY_POSITIONS = 20_000_000   # simulate: history rows x bodies
MAX_WORKERS = 256                    # local worker processes of a study
MAX_COMMAND_RUNS = 100_000           # time histories of one study command at most (searches x --max-runs)


def check_block(width: float, height: float) -> None:
    """``width / height`` of a rocking block in :data:`BLOCK_ASPECT_RANGE`."""
    lo, hi = BLOCK_ASPECT_RANGE
    ratio = width / height if height > 0 else math.inf
    if not lo <= ratio <= hi:
        raise InputError(f"--block: width / height must be in [{lo:g}, {hi:g}], got {width:g} / {height:g} = "
                         f"{ratio:.3g}")


def check_discretisation(model: str, voussoirs: int | None, elements: int | None, block: bool = False) -> None:
    """``--voussoirs`` / ``--elements`` within the bounds of ``model``: ``"rock"``,
    ``"simulate"``, or ``"auto"`` (rock, then simulate: the bounds of both)."""
    if block:
        return
    if model == "auto":
        check_discretisation("rock", voussoirs, elements)
        check_discretisation("simulate", voussoirs, elements)
        return
    if model == "rock":
        lo, hi = ROCK_VOUSSOIRS
        if voussoirs is not None and not lo <= voussoirs <= hi:
            raise InputError(f"--voussoirs must be in [{lo}, {hi}] for the one-mechanism model (it follows four-hinge "
                             f"mechanisms on {lo + 1} to {hi + 1} joints), got {voussoirs}")
        if elements is not None and not 4 <= elements <= ROCK_MAX_ELEMENTS:
            raise InputError(f"--elements must be in [4, {ROCK_MAX_ELEMENTS}] for the one-mechanism model, got "
                             f"{elements}")
        return
    n = voussoirs if voussoirs is not None else elements
    lo = 1 if voussoirs is not None else 4
    if n is not None and not lo <= n <= SIMULATE_MAX_BODIES:
        what = "--voussoirs" if voussoirs is not None else "--elements"
        raise InputError(f"{what} must be in [{lo}, {SIMULATE_MAX_BODIES}] for the multi-body simulation, got {n}")


def bodies(voussoirs: int | None, elements: int | None, block: bool = False) -> int:
    """Rigid bodies of the multi-body simulation of the member."""
    return 1 if block else int(voussoirs if voussoirs is not None else elements)


def check_duration(duration: float, what: str = "--t-end") -> None:
    """A simulated time (s) of at most :data:`MAX_DURATION`."""
    if not duration <= MAX_DURATION:
        raise InputError(f"{what}: a run simulates at most {MAX_DURATION:g} s after the start of the ground motion, "
                         f"got {duration:.4g} s")


def check_steps(dt: float, duration: float, n_bodies: int, what: str = "--dt") -> int:
    """The steps of one simulate run of ``duration`` s at ``dt`` s: at most :data:`MAX_STEPS`,
    and times ``n_bodies`` at most :data:`MAX_BODY_STEPS`.  Returns the number of steps."""
    check_duration(duration, "--t-end")
    lo, hi = DT_RANGE
    if not (math.isfinite(dt) and lo <= dt <= hi):
        raise InputError(f"{what} must be in [{lo:g}, {hi:g}] s, got {dt:g}")
    steps = duration / dt
    if not steps <= MAX_STEPS:
        raise InputError(f"{what}: {steps:.3g} steps of {dt:g} s to simulate {duration:.4g} s; at most {MAX_STEPS:g} "
                         "(a larger time step or a shorter run)")
    if not steps * n_bodies <= MAX_BODY_STEPS:
        raise InputError(f"{what}: {steps:.3g} steps of {dt:g} s x {n_bodies} bodies = {steps * n_bodies:.3g}; at most "
                         f"{MAX_BODY_STEPS:g} (a larger time step, a shorter run or fewer bodies)")
    return int(math.ceil(steps))


def check_history(duration: float, dt_out: float | None, n_bodies: int = 0) -> None:
    """History rows ``duration / dt_out`` (the intervals) at most :data:`MAX_HISTORY_ROWS` (and times
    ``n_bodies``, the positions kept by simulate, at most :data:`MAX_HISTORY_POSITIONS`)."""
    if dt_out is None:
        return
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"--dt-out must be a positive number of seconds, got {dt_out:g}")
    rows = duration / dt_out
    if not rows <= MAX_HISTORY_ROWS:
        raise InputError(f"--dt-out: {rows:.3g} history rows of {dt_out:g} s over {duration:.4g} s; at most "
                         f"{MAX_HISTORY_ROWS:g} (a larger --dt-out or an earlier --t-end)")
    if n_bodies and not rows * n_bodies <= MAX_HISTORY_POSITIONS:
        raise InputError(f"--dt-out: {rows:.3g} history rows x {n_bodies} bodies = {rows * n_bodies:.3g} positions; at "
                         f"most {MAX_HISTORY_POSITIONS:g} (a larger --dt-out)")


def check_workers(workers: int | None) -> None:
    """``--workers`` in [1, :data:`MAX_WORKERS`] (None: one per core)."""
    if workers is not None and not 1 <= workers <= MAX_WORKERS:
        raise InputError(f"--workers must be in [1, {MAX_WORKERS}], got {workers}")


def check_run_count(searches: int, max_runs: int, what: str) -> None:
    """InputError unless ``searches`` searches of at most ``max_runs`` time histories each stay
    within :data:`MAX_COMMAND_RUNS`; ``what`` names the searches ("44 records x 2 signs")."""
    total = int(searches) * int(max_runs)
    if total > MAX_COMMAND_RUNS:
        fit = max(1, MAX_COMMAND_RUNS // max(int(searches), 1))
        raise InputError(f"{what} x --max-runs {max_runs} = {total} time histories at most: a command makes at most "
                         f"{MAX_COMMAND_RUNS} (give --max-runs {fit} or fewer, or split the study)")
