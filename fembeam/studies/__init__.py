"""Studies that repeat the pipeline: mesh-refinement convergence with observed rates and
Richardson extrapolation, parametric sweeps over embrace and thickness (the paper's Fig. 13)
with the minimum-thickness envelope, on local processes or a Dask cluster."""
from .convergence import ConvergenceStudy, convergence_study, fit_order, observed_order, rate_fit, richardson
from .sweep import SweepResult, sweep, sweep_case

__all__ = ["ConvergenceStudy", "convergence_study", "fit_order", "observed_order", "rate_fit", "richardson",
           "SweepResult", "sweep", "sweep_case"]
