"""Output of solutions: VTK files (:mod:`.export`), off-screen renderings (:mod:`.render`),
paper-style figures (:mod:`.plotting`) and the hinge-zone figure (:mod:`.plot_four_hinge`).

The modules are imported on demand (matplotlib, meshio and pyvista load slowly).
"""
