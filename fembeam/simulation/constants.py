"""The numerical constants of the multi-body simulation, defined once for the compiled kernel
(:mod:`.kernel`), the Python engine (:mod:`.stepper`, :mod:`.projection`, :mod:`.contacts`,
:mod:`.reference`) and the models that follow the simulation's conventions (:mod:`fembeam.auto`).

The kernel reads them as module globals, which numba freezes into the compiled code as
compile-time constants.  Numba's on-disk cache is keyed on the kernel's source file only: a value
changed here is seen by the kernel after its cache is rebuilt.  :func:`.kernel.compiled_constants`
returns the values the loaded code was compiled with, and :func:`.stepper` compares them with
these at the first run (a stale cache is recompiled; a test checks the same).

Tolerances are relative (to the scales named) unless a unit is given.
"""
from __future__ import annotations

__all__ = ["BAND", "OFF_FACE", "REG", "KKT_TOL", "MAX_PIVOTS", "BLOCK_PIVOTS", "IMPACT_PIVOTS", "IPM_ITERATIONS",
           "GAP_TOL", "OPEN_TOL", "REST_KINETIC", "COULOMB_TOL", "LOOSE", "values"]

# --- the contact operators
BAND = 5                 # half-bandwidth of W (three rows per joint, consecutive joints share a body)
OFF_FACE = 1e300         # m: the gap of a joint end whose faces no longer overlap (it never closes)

# --- one step's contact problem (the MLCP of the projection)
REG = 1e-12              # regularisation, relative to the largest diagonal entry of W
KKT_TOL = 1e-8           # KKT residuals, relative to the scales of the velocities and the percussions
MAX_PIVOTS = 1000        # linear solves of one projection
BLOCK_PIVOTS = 8         # block principal pivots tried first on a smooth step
IMPACT_PIVOTS = 2        # block pivots tried on an impact (its many locked joints at rest are degenerate
                         # rows: the pivots seldom converge, the interior point does)
IPM_ITERATIONS = 80      # interior-point iterations (one banded factorisation each) before the active set

# --- friction
COULOMB_TOL = 1e-5       # residual of Coulomb's law at a step with sliding (same scales as KKT_TOL)
LOOSE = 100.0            # a step's frictional problem accepted up to this many times COULOMB_TOL when
                         # every solver stalls above it (counted: SimulationResult.loose_steps)

# --- the state of the joints and of the member
GAP_TOL = 1e-7           # a corner is closed when its gap is at most GAP_TOL x the joint's thickness
OPEN_TOL = 1e-6          # a corner is open (hinge count) when its gap exceeds OPEN_TOL x the thickness
REST_KINETIC = 1e-12     # at rest: kinetic energy below REST_KINETIC x m g L (L: the member's length)


def values() -> tuple:
    """The constants the kernel is compiled with, in the order of
    :func:`.kernel.compiled_constants`."""
    return (BAND, OFF_FACE, REG, KKT_TOL, MAX_PIVOTS, IPM_ITERATIONS, COULOMB_TOL, LOOSE, OPEN_TOL)
