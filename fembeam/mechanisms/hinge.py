"""Hinges of a rigid-element field: which joints open, and on which edge they pivot.

Naming: a hinge is located at the edge about which the joint rotates, i.e. where the
thrust (impulse) line touches the section.  A joint whose **extrados** opens pivots on
the **intrados**: side ``"intrados"``; and vice versa.  A joint whose both edges open
has separated (side ``"separated"``).  Openings below ``rel_tol`` times the largest
opening rate are treated as closed (default 1e-5: interior-point solutions leave
inactive openings at ~1e-9 of the active ones).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fem import Discretization

__all__ = ["Hinge", "find_hinges", "merge_adjacent", "HINGE_REL_TOL", "PIVOT_Y"]

HINGE_REL_TOL = 1e-5
PIVOT_Y = {"intrados": 0.5, "extrados": -0.5, "separated": 0.0}  # y / t of the pivot point


@dataclass(frozen=True)
class Hinge:
    """A hinge at arc length ``s`` (m), reported at ``angle_deg`` (from the left
    springing), pivoting on ``side``; ``rotation`` is the relative angular velocity
    (rad/s, right minus left element) across it; ``joints`` the joint indices."""

    s: float
    angle_deg: float
    side: str
    rotation: float
    joints: tuple[int, ...]

    def to_dict(self) -> dict:
        return {"angle_deg": round(float(self.angle_deg), 6), "side": self.side}


def find_hinges(disc: Discretization, d: np.ndarray, rel_tol: float = HINGE_REL_TOL) -> list[Hinge]:
    """Open joints of the field ``d``, one :class:`Hinge` per joint, left to right."""
    eps = disc.B_open @ d
    J = disc.n_joints
    ei, ee = eps[:J], eps[J:]
    scale = max(np.max(np.abs(eps)), 1e-300)
    oi, oe = ei > rel_tol * scale, ee > rel_tol * scale
    rot = (ei - ee) / disc.joint_thickness  # [omega] = (eps_+ - eps_-) / t
    out = []
    for j in np.flatnonzero(oi | oe):
        side = "separated" if (oi[j] and oe[j]) else ("intrados" if oe[j] else "extrados")
        out.append(Hinge(float(disc.joint_s[j]), float(disc.joint_angle_deg[j]), side, float(rot[j]), (int(j),)))
    return out


def merge_adjacent(disc: Discretization, hinges: list[Hinge]) -> list[Hinge]:
    """Merge runs of hinges at consecutive joints with the same side into one hinge at
    the rotation-weighted mean position: on a fine mesh of a continuous arch a hinge
    lying between two nodes shows up as two neighbouring partial hinges."""
    out: list[Hinge] = []
    for h in hinges:
        last = out[-1] if out else None
        if last is not None and h.side == last.side and h.joints[0] == last.joints[-1] + 1:
            wl, wh = abs(last.rotation), abs(h.rotation)
            s = (wl * last.s + wh * h.s) / (wl + wh)
            out[-1] = Hinge(s, float(disc.curve.angle_deg(s)), h.side, last.rotation + h.rotation,
                            last.joints + h.joints)
        else:
            out.append(h)
    return out
