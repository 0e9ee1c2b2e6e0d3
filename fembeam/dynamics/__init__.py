"""Dynamics of the rocking arch: ground motions (pulses and recorded accelerograms)."""
from .ground import RECORDS, GroundMotion

__all__ = ["GroundMotion", "RECORDS"]
