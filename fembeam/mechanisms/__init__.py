"""Mechanisms of rigid pieces between hinges, and the impact models built on them.

* :mod:`.hinge`: the hinge sides and the order of a section's edges (one table), :class:`Hinge`,
  hinges of a DOF vector;
* :mod:`.mechanism`: :class:`Mechanism` (velocity field, DOFs, finite motion);
* :mod:`.energy`: momenta, kinetic energy, closed-form four-hinge impact (7), (14)-(17);
* :mod:`.impulse_line`, :mod:`.restricted`, :mod:`.classical`: impulse line (8)-(11),
  restricted problem (16)-(17), classical model;
* :mod:`.four_hinge_analysis`, :mod:`.discrete_series`: complete analyses.
"""
from .energy import ImpactFigures, load_factor, momenta, post_impact, product, restitution
from .hinge import (EDGES, HINGE_REL_TOL, ROCKING_SIDES, SIDES, Hinge, Side, find_hinges, hinges_and_slides,
                    merge_adjacent, opening_signs, pivot_fractions, pivot_sides, side_from_text, side_of)
from .mechanism import Configuration, Mechanism

__all__ = ["ImpactFigures", "load_factor", "momenta", "post_impact", "product", "restitution",
           "EDGES", "HINGE_REL_TOL", "ROCKING_SIDES", "SIDES", "Hinge", "Side", "find_hinges", "hinges_and_slides",
           "merge_adjacent", "opening_signs", "pivot_fractions", "pivot_sides", "side_from_text", "side_of",
           "Configuration", "Mechanism"]
