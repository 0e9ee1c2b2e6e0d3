"""The model that decides each run of a collapse search, chosen by name through one hook.

:data:`RUNNERS` maps a model's name to a factory ``make(curve, *, voussoirs, elements, thresholds,
dt, friction, backend)`` of a runner: a callable ``runner(ground, t_end)`` returning a dict with

* ``outcome``: the model's own (``rest``, ``survived``, ``overturned``, ``collapsed_by_sliding``, or
  ``solver_error`` with the message in ``error`` when a solve fails its check);
* ``peak_rotation``: the largest ``|rotation|`` of any piece over the run (rad), the damage measure of
  the IDA curves (at overturning, the rotation reached when the run stopped);
* ``steps``: time steps taken (0 for ``rock``, which integrates its one degree of freedom with
  adaptive steps).

``rock`` follows one mechanism between impacts (:class:`~fembeam.dynamics.Rocker`, built once per
runner, run to ``t_end`` without the free-decay shortcut so that the peak rotation is the whole
run's); ``simulate`` moves the pieces as rigid bodies in contact
(:class:`~fembeam.simulation.Simulator`, built once per worker thread and member, time step ``dt``,
stopped at overturning; ``friction``: Coulomb's coefficient at the joints, ``math.inf`` (or None,
its synonym) for joints that never slide); ``auto`` is ``rock`` while its mechanism is admissible
and ``simulate`` from the first violation (:class:`~fembeam.auto.AutoModel`, built once per worker
thread and member; its time steps are not counted).  :class:`MultiBody` is the member of a
simulate or auto search, :func:`simulator` and :func:`auto_model` the models kept per thread.  :data:`MODELS` are the names the commands know; a name without a runner is
refused by :func:`check_model` ("not available"), and a new model is one entry of :data:`RUNNERS`.
"""
from __future__ import annotations

import math
import sys
import threading
from typing import Callable

import numpy as np

from ..dynamics.ground import GroundMotion
from ..errors import InputError, SolverError
from ..geometry import MidCurve
from .runs import DT

__all__ = ["MODELS", "RUNNERS", "DEFAULT_MODEL", "check_model", "runner", "MultiBody", "unlimited_friction"]

MODELS = ("rock", "simulate", "auto")
DEFAULT_MODEL = "simulate"       # hinges anywhere: the safe one when rock's single mechanism is in doubt


def check_friction(mu, name: str) -> float | None:
    """A Coulomb coefficient checked by the Simulator's own rule.

    Parameters
    ----------
    mu : float or None
        The coefficient (>= 0); ``math.inf`` (or None, its synonym) for joints that never slide.
    name : str
        What the messages call it (the CLI's option).

    Returns
    -------
    float or None
        The coefficient, or None for unlimited friction (the Simulator's spelling of it).

    Raises
    ------
    InputError
        ``mu`` is not a number >= 0, or this fembeam's Simulator has no Coulomb friction.
    """
    if unlimited_friction(mu):
        return None
    try:
        mu = float(mu)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {mu!r}") from None
    if not (math.isfinite(mu) and mu >= 0):
        raise InputError(f"{name} must be a friction coefficient (a number >= 0; inf, or omit it, for joints that "
                         f"never slide), got {mu:g}")
    if not simulator_has_friction():
        raise InputError(f"{name}: this fembeam's Simulator has no Coulomb friction")
    from ..simulation.stepper import check_friction as simulator_check
    try:
        return simulator_check(mu)
    except InputError as e:
        raise InputError(f"{name}: {e}") from None


def unlimited_friction(mu) -> bool:
    """Whether ``mu`` spells unlimited friction (joints that never slide).

    Parameters
    ----------
    mu : object
        A friction coefficient as given.

    Returns
    -------
    bool
        True for ``math.inf`` (the documented spelling) and None (its synonym).
    """
    if mu is None:
        return True
    try:
        return float(mu) == math.inf
    except (TypeError, ValueError):
        return False


def simulator_has_friction() -> bool:
    """Whether this fembeam's :class:`~fembeam.simulation.Simulator` takes ``friction``."""
    import inspect

    from ..simulation import Simulator
    return "friction" in inspect.signature(Simulator).parameters


_SIMULATORS = threading.local()


def simulator(curve: MidCurve, voussoirs: int | None, elements: int | None, friction: float | None):
    """This thread's :class:`~fembeam.simulation.Simulator` of the member, built on first use and
    kept for the next tasks on the same member (one at a time: a worker runs one study)."""
    from ..simulation import Simulator
    with np.printoptions(threshold=sys.maxsize, precision=17):
        key = (repr(curve), voussoirs, elements, friction)
    kept = getattr(_SIMULATORS, "kept", None)
    if kept is not None and kept[0] == key:
        return kept[1]
    kw = {"voussoirs": voussoirs} if voussoirs is not None else {"elements": elements}
    if friction is not None:
        kw["friction"] = friction
    sim = Simulator(curve, **kw)
    _SIMULATORS.kept = (key, sim)
    return sim


def auto_model(curve: MidCurve, voussoirs: int | None, elements: int, friction: float | None, dt: float):
    """This thread's :class:`~fembeam.auto.AutoModel` of the member (kept for the next tasks, as
    :func:`simulator`)."""
    from ..auto import AutoModel
    with np.printoptions(threshold=sys.maxsize, precision=17):
        key = ("auto", repr(curve), voussoirs, elements, friction, dt)
    kept = getattr(_SIMULATORS, "auto", None)
    if kept is not None and kept[0] == key:
        return kept[1]
    am = AutoModel(curve, voussoirs=voussoirs, elements=elements, friction=friction, dt=dt)
    _SIMULATORS.auto = (key, am)
    return am


class MultiBody:
    """The member as ``fembeam simulate`` moves it, or as ``--model auto``, for a search.

    Parameters
    ----------
    curve : MidCurve
        The member.
    A : dict
        The onset thresholds (g), ``{1: A_L(+1), -1: A_L(-1)}``, from the limit analysis; NaN for
        a member that cannot stand.
    voussoirs, elements : int or None
        Its pieces.
    dt : float
        The time step (s).
    friction : float or None
        Coulomb's coefficient at the joints; ``math.inf`` (or None, its synonym) for joints that
        never slide.
    model : str
        ``"simulate"`` (this worker thread's :class:`~fembeam.simulation.Simulator`, reused) or
        ``"auto"`` (this thread's :class:`~fembeam.auto.AutoModel`: the one-mechanism model while
        it holds, the simulation from the first violation).

    Attributes
    ----------
    steps : int
        The time steps of its ``simulate`` runs.
    """

    def __init__(self, curve: MidCurve, A: dict, *, voussoirs: int | None = None, elements: int = 200,
                 dt: float = DT, friction: float | None = None, model: str = "simulate"):
        friction = None if unlimited_friction(friction) else friction
        self.curve, self.dt, self.friction, self.model = curve, float(dt), friction, model
        self.A = {1: float(A[1]), -1: float(A[-1])}
        self.stands = not any(math.isnan(x) for x in self.A.values())
        if model == "auto":
            self.sim = auto_model(curve, voussoirs, elements, friction, self.dt)
        else:
            self.sim = simulator(curve, voussoirs, None if voussoirs is not None else elements, friction)
        self.steps = 0

    @property
    def still_below_onset(self) -> bool:
        """A ground motion below ``A_L`` both ways leaves the member at rest (no sliding joints)."""
        return self.friction is None

    def outcome(self, ground: GroundMotion, t_end: float | None) -> str:
        """The outcome of one run under ``ground`` (g) to ``t_end`` (s; None: the model's default)."""
        if self.model == "auto":
            return self.sim.run(ground, t_end=t_end, history=False).outcome
        res = self.sim.run(ground, dt=self.dt, t_end=t_end, stop_at_overturn=True)
        self.steps += int(res.steps)
        return res.outcome


def _rock(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    from ..dynamics.rocking import Rocker
    rk = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)

    def run(ground: GroundMotion, t_end: float | None) -> dict:
        res = rk.run(ground, t_end=t_end, thrust_check=False, history=False, settle=False)
        return {"outcome": res.outcome, "peak_rotation": float(res.peak_rotation), "steps": 0}
    return run


def _simulate(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    sim = MultiBody(curve, {1: thresholds[0], -1: thresholds[1]}, voussoirs=voussoirs,
                             elements=elements, dt=dt, friction=friction).sim

    def run(ground: GroundMotion, t_end: float | None) -> dict:
        res = sim.run(ground, dt=dt, t_end=t_end, stop_at_overturn=True)
        return {"outcome": res.outcome, "peak_rotation": float(res.peak_rotation), "steps": int(res.steps)}
    return run


def _auto(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    am = MultiBody(curve, {1: thresholds[0], -1: thresholds[1]}, voussoirs=voussoirs,
                            elements=elements, dt=dt, friction=friction, model="auto").sim

    def run(ground: GroundMotion, t_end: float | None) -> dict:
        res = am.run(ground, t_end=t_end, history=False)
        return {"outcome": res.outcome, "peak_rotation": float(res.peak_rotation), "steps": 0}
    return run


RUNNERS: dict[str, Callable] = {
    "rock": _rock,
    "simulate": _simulate,
    "auto": _auto,
}


def check_model(model: str, dt: float | None = None, friction: float | None = None,
                names: tuple[str, str, str] = ("model", "dt", "friction")) -> tuple[float | None, float | None]:
    """The time step and friction of ``model``, checked.

    Parameters
    ----------
    model : str
        One of :data:`MODELS` with a runner in :data:`RUNNERS`.
    dt : float or None
        The time step (s) of ``simulate`` and ``auto`` (default :data:`~fembeam.studies.runs.DT`),
        within the simulation's ``DT_RANGE``; rock takes none.
    friction : float or None
        Coulomb's coefficient of ``simulate`` and ``auto``; ``math.inf`` (or None, its synonym)
        for joints that never slide; rock takes none.
    names : tuple of str
        What the messages call the three (the CLI's options).

    Returns
    -------
    tuple
        ``(dt, friction)``: ``(None, None)`` for rock; otherwise the time step and the
        coefficient, None for unlimited friction.

    Raises
    ------
    InputError
        An unknown model, one without a runner, or a ``dt`` or ``friction`` it does not take.
    """
    m, d, f = names
    if model not in MODELS:
        raise InputError(f"{m} must be one of {', '.join(MODELS)}, got {model!r}")
    if model not in RUNNERS:
        raise InputError(f"{m} {model} is not available in this fembeam yet: use "
                         f"{' or '.join(RUNNERS)}")
    if model == "rock":
        given = [n for n, x in ((d, dt), (f, friction)) if x is not None]
        if given:
            raise InputError(f"{' and '.join(given)} appl{'y' if len(given) > 1 else 'ies'} to the multi-block "
                             f"simulation only ({m} simulate or auto), not to rock")
        return None, None
    from ..simulation import DT_RANGE
    lo, hi = DT_RANGE
    if dt is None:
        dt = DT
    try:
        dt = float(dt)
    except (TypeError, ValueError):
        raise InputError(f"{d} must be a number of seconds, got {dt!r}") from None
    if not (math.isfinite(dt) and lo <= dt <= hi):
        raise InputError(f"{d} must be in [{lo:g}, {hi:g}] s, got {dt:g}")
    return dt, check_friction(friction, f)


def runner(model: str, curve: MidCurve, *, voussoirs: int | None, elements: int, thresholds, dt: float | None,
           friction: float | None = None, backend: str = "clarabel") -> Callable[[GroundMotion, float | None], dict]:
    """The function that runs a member under a ground motion with ``model``, for a search.

    The model is built once (a :class:`~fembeam.dynamics.Rocker`, or this worker
    thread's :class:`~fembeam.simulation.Simulator` or :class:`~fembeam.auto.AutoModel`)
    and reused by every call. The models and what their runners return are described in
    :mod:`fembeam.studies.models`.

    Parameters
    ----------
    model : {"rock", "simulate", "auto"}
        The model (a name of :data:`RUNNERS`): one mechanism between impacts, the
        multi-block simulation, or the first until its mechanism fails, then the second.
    curve : MidCurve
        The member (lengths in m, density in kg/m^3).
    voussoirs : int or None
        Discrete arch of this many voussoirs; None: the continuous member on ``elements``.
    elements : int
        Rigid elements of the continuous member (with ``voussoirs`` None).
    thresholds : sequence of float
        ``[A_L(+1), A_L(-1)]`` (g), the onset thresholds of the limit analysis
        (``simulate`` and ``auto``; ``rock`` finds its own).
    dt : float or None
        Time step of ``simulate`` and ``auto`` (s); None for ``rock``.
    friction : float, optional
        Coulomb coefficient of the joints (``simulate`` and ``auto``); None or ``math.inf``:
        joints that never slide (default).
    backend : str, optional
        Solver of the impact QP of ``rock`` (default ``"clarabel"``).

    Returns
    -------
    callable
        ``run(ground, t_end)``: runs the member under ``ground`` (a
        :class:`~fembeam.dynamics.GroundMotion`, g, positive along ``+x``) to ``t_end``
        (s; None: the model's default) and returns a dict with ``outcome`` (``"rest"``,
        ``"survived"``, ``"overturned"``, ``"collapsed_by_sliding"``, or
        ``"solver_error"`` with the message in ``error``: a failed solve is an outcome,
        not an exception), ``peak_rotation`` (rad, the largest of any piece) and
        ``steps`` (time steps of ``simulate``; 0 for the others).

    Raises
    ------
    KeyError
        ``model`` is not a name of :data:`RUNNERS` (:func:`check_model` says so in words).
    InputError
        Bad input when the model is built; bad input of a run raises from ``run``.

    Examples
    --------
    >>> import fembeam
    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.models import runner
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> A_L = fembeam.analyze(arch, voussoirs=12).A_L        # g, the same both ways
    >>> run = runner("rock", arch, voussoirs=12, elements=200, thresholds=[A_L, A_L],
    ...              dt=None)
    >>> for amplitude in (0.4, 0.8):
    ...     out = run(GroundMotion.sine(amplitude, 0.5), 3.0)
    ...     print(f"{amplitude} g:", out["outcome"], f"{out['peak_rotation']:.4f} rad")
    0.4 g: rest 0.0025 rad
    0.8 g: overturned 0.4837 rad
    """
    make = RUNNERS[model]
    run = make(curve, voussoirs=voussoirs, elements=elements, thresholds=thresholds, dt=dt, friction=friction,
               backend=backend)

    def guarded(ground: GroundMotion, t_end: float | None) -> dict:
        try:
            return run(ground, t_end)
        except SolverError as e:
            return {"outcome": "solver_error", "peak_rotation": None, "steps": 0, "error": f"{type(e).__name__}: {e}"}
    return guarded
