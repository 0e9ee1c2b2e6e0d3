"""Dynamics of the rocking arch: ground motions, the equation of motion of a mechanism at
finite rotation, the impact transitions and the whole motion (rest, onset, impacts,
overturning)."""
from .equation import GRAVITY, EquationOfMotion
from .ground import RECORDS, GroundMotion
from .rocking import OUTCOMES, ImpactEvent, Rocker, RockingResult, rock
from .transitions import ImpactModel, Transition

__all__ = ["GroundMotion", "RECORDS", "GRAVITY", "EquationOfMotion", "ImpactModel", "Transition", "Rocker",
           "RockingResult", "ImpactEvent", "rock", "OUTCOMES"]
