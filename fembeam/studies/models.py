"""The model that decides each run of a collapse search, chosen by name through one hook.

:data:`RUNNERS` maps a model's name to a factory ``make(curve, *, voussoirs, elements, thresholds,
dt, friction, backend)`` of a runner: a callable ``runner(ground, t_end)`` returning a dict with

* ``outcome``: the model's own (``rest``, ``survived``, ``overturned``, ``collapsed_by_sliding``, or
  ``solver_error`` with the message in ``error`` when a solve fails its check);
* ``peak_rotation``: the largest |rotation| of any piece over the run (rad), the damage measure of
  the IDA curves (at overturning, the rotation reached when the run stopped);
* ``steps``: time steps taken (0 for ``rock``, which integrates its one degree of freedom with
  adaptive steps).

``rock`` follows one mechanism between impacts (:class:`~fembeam.dynamics.Rocker`, built once per
runner, run to ``t_end`` without the free-decay shortcut so that the peak rotation is the whole
run's); ``simulate`` moves the pieces as rigid bodies in contact
(:class:`~fembeam.simulation.Simulator`, built once per worker thread and member, time step ``dt``,
stopped at overturning; ``friction``: Coulomb's coefficient at the joints, None for joints that
never slide); ``auto`` is ``rock`` while its mechanism is admissible and ``simulate`` from the first
violation (:class:`~fembeam.auto.AutoModel`, built once per worker thread and member; its time
steps are not counted).  :data:`MODELS` are the names the commands know; a name without a runner is
refused by :func:`check_model` ("not available"), and a new model is one entry of :data:`RUNNERS`.
"""
from __future__ import annotations

from typing import Callable

from ..dynamics.ground import GroundMotion
from ..errors import InputError, SolverError
from ..geometry import MidCurve
from . import spectrum

__all__ = ["MODELS", "RUNNERS", "DEFAULT_MODEL", "check_model", "runner"]

MODELS = ("rock", "simulate", "auto")
DEFAULT_MODEL = "simulate"       # hinges anywhere: the safe one when rock's single mechanism is in doubt


def _rock(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    from ..dynamics.rocking import Rocker
    rk = Rocker(curve, voussoirs=voussoirs, elements=elements, backend=backend, qp=False)

    def run(ground: GroundMotion, t_end: float | None) -> dict:
        res = rk.run(ground, t_end=t_end, thrust_check=False, history=False, settle=False)
        return {"outcome": res.outcome, "peak_rotation": float(res.peak_rotation), "steps": 0}
    return run


def _simulate(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    sim = spectrum.MultiBody(curve, {1: thresholds[0], -1: thresholds[1]}, voussoirs=voussoirs,
                             elements=elements, dt=dt, friction=friction).sim

    def run(ground: GroundMotion, t_end: float | None) -> dict:
        res = sim.run(ground, dt=dt, t_end=t_end, stop_at_overturn=True)
        return {"outcome": res.outcome, "peak_rotation": float(res.peak_rotation), "steps": int(res.steps)}
    return run


def _auto(curve: MidCurve, *, voussoirs, elements, thresholds, dt, friction, backend) -> Callable:
    am = spectrum.MultiBody(curve, {1: thresholds[0], -1: thresholds[1]}, voussoirs=voussoirs,
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


def check_model(model: str, dt: float | None, friction: float | None = None,
                names: tuple[str, str, str] = ("model", "dt", "friction")) -> tuple[float | None, float | None]:
    """``(dt, friction)`` of ``model`` (None for rock; simulate's and auto's default ``dt``
    :data:`fembeam.studies.spectrum.DT`); :class:`InputError` for an unknown model, one without a
    runner, or a ``dt`` or ``friction`` it does not take."""
    m = names[0]
    if model not in MODELS:
        raise InputError(f"{m} must be one of {', '.join(MODELS)}, got {model!r}")
    if model not in RUNNERS:
        raise InputError(f"{m} {model} is not available in this fembeam yet: use "
                         f"{' or '.join(RUNNERS)}")
    return spectrum.check_model(model, dt, friction, names=names)


def runner(model: str, curve: MidCurve, *, voussoirs: int | None, elements: int, thresholds, dt: float | None,
           friction: float | None = None, backend: str = "clarabel") -> Callable[[GroundMotion, float | None], dict]:
    """The runner of ``model`` (see the module docstring); a failed solve becomes the outcome
    ``solver_error``, bad input still raises."""
    make = RUNNERS[model]
    run = make(curve, voussoirs=voussoirs, elements=elements, thresholds=thresholds, dt=dt, friction=friction,
               backend=backend)

    def guarded(ground: GroundMotion, t_end: float | None) -> dict:
        try:
            return run(ground, t_end)
        except SolverError as e:
            return {"outcome": "solver_error", "peak_rotation": None, "steps": 0, "error": f"{type(e).__name__}: {e}"}
    return guarded
