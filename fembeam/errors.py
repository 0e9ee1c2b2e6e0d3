"""Exceptions: bad input versus a solver that could not be trusted."""

__all__ = ["FembeamError", "InputError", "SolverError", "CannotStandError"]


class FembeamError(Exception):
    """Base class of fembeam's errors."""


class InputError(FembeamError, ValueError):
    """Input outside the allowed range; the message says what is allowed."""


class SolverError(FembeamError, RuntimeError):
    """A solve failed or its solution failed the verification checks."""


class CannotStandError(FembeamError):
    """The arch cannot stand under its own weight (A_L <= 0): physics, not a bug."""
