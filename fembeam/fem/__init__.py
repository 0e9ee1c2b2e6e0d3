"""Discretisation of the mid-curve: scikit-fem meshes in the arc length, rigid curved-beam
elements (the default) and continuous P1 fields, assembled into the sparse kinetic-energy
matrix ``M`` and strain operators ``B_open``, ``B_slide`` of Appendix B."""
from .mesh import nodes_through, uniform_nodes
from .p1 import discretize_p1
from .rigid import NDOF, Discretization, discretize, dof_scaling, rigid_dofs

__all__ = ["uniform_nodes", "nodes_through", "Discretization", "discretize", "discretize_p1", "rigid_dofs",
           "dof_scaling", "NDOF"]
