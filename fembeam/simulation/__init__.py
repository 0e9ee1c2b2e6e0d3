"""Non-smooth multi-body simulation of a member's rigid pieces (``fembeam simulate``): Moreau-Jean
time stepping whose every step projects the free velocity onto the compatible cone in the kinetic
metric (the impact QP of ``fembeam impact``, in the current configuration)."""
from .bodies import Bodies
from .contacts import Contacts, Geometry
from .projection import MLCPSolution, solve_mlcp
from .result import HISTORY_COLUMNS, OUTCOMES, SimulationResult
from .stepper import DT_RANGE, MAX_STEPS, Simulator, simulate

__all__ = ["Bodies", "Contacts", "Geometry", "MLCPSolution", "solve_mlcp", "SimulationResult", "OUTCOMES",
           "HISTORY_COLUMNS", "Simulator", "simulate", "DT_RANGE", "MAX_STEPS"]
