"""Units of the reported quantities, in one place.

Everything is per metre of barrel width (the out-of-plane depth of the arch): lengths in m,
densities in kg/m^3, masses in kg/m, forces in kN/m, energies in J/m, impulses in N s/m;
accelerations, ``A_L`` and thresholds in g.  Inside the analyses forces are per unit g in
kg/m (a mass); :func:`kN` turns them into kN/m.
"""
from __future__ import annotations

__all__ = ["GRAVITY", "kN", "per_g"]

GRAVITY = 9.81   # m/s^2


def kN(force_per_g):
    """A force per unit g (kg/m, the analyses' unit) in kN per metre of width."""
    return force_per_g * (GRAVITY / 1000.0)


def per_g(force_kN):
    """A force in kN per metre of width as a force per unit g (kg/m)."""
    return force_kN * (1000.0 / GRAVITY)
