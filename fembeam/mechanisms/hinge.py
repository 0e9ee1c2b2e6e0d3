"""Hinges: the edge a joint pivots on, and the hinges of a rigid-element field.

Naming: a hinge is located at the edge about which the joint rotates, i.e. where the
thrust (impulse) line touches the section.  A joint whose **extrados** opens pivots on
the **intrados**: side ``"intrados"``; and vice versa.  A joint whose both edges open
has separated (side ``"separated"``).

:data:`SIDES` is the one table of what a side means: the pivot offset ``y/t`` along
the inward normal ``n`` (intrados ``+1/2``, extrados ``-1/2``), the sign of the
rotation jump ``[omega]`` (right minus left, counter-clockwise) that opens the hinge,
the opposite side and the one-letter initial of text output.  :data:`EDGES` is the order of
the two edges of a section in every array over them (fibre forces ``N+``, ``N-``; opening
rates; the corners of a joint in :mod:`fembeam.simulation`): index 0 the intrados, 1 the
extrados.  :func:`pivot_sides` names the side a joint pivots on from the edges that open,
:func:`side_from_text` reads a side from its name or initial.  Every other module asks these.

:func:`find_hinges` reads the hinges of a DOF vector: openings below ``rel_tol`` times
the largest opening rate are treated as closed (default 1e-5: interior-point solutions
leave inactive openings at ~1e-9 of the active ones).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

import numpy as np

from ..errors import InputError
from ..fem import Discretization

__all__ = ["Side", "SIDES", "EDGES", "ROCKING_SIDES", "side_of", "side_from_text", "pivot_fractions",
           "opening_signs", "pivot_sides", "Hinge", "find_hinges", "hinges_and_slides", "merge_adjacent",
           "HINGE_REL_TOL"]

HINGE_REL_TOL = 1e-5


@dataclass(frozen=True)
class Side:
    """An edge a hinge may pivot on.

    ``pivot``: offset ``y/t`` of the pivot point from the mid-curve along ``n``;
    ``opening``: sign of the rotation jump ``[omega]`` (rad/s, right minus left) that
    opens the hinge (0: no rotation is implied, the joint has separated);
    ``opposite_name``: the side across the thickness.  ``code`` and ``initial`` are derived:
    the sign of the pivot offset and the first letter of the name.
    """

    name: str
    pivot: float
    opening: float
    opposite_name: str

    @property
    def opposite(self) -> "Side":
        return SIDES[self.opposite_name]

    @property
    def code(self) -> int:
        """+1 intrados, -1 extrados, 0 separated (the sign of ``y`` of the pivot)."""
        return int(np.sign(self.pivot))

    @property
    def initial(self) -> str:
        """``"i"``, ``"e"`` or ``"s"``: the side in text output (and on the command line)."""
        return self.name[0]


# A joint pivoting on the intrados (y = +t/2) opens at the extrados: eps_- = -t [omega] > 0.
SIDES: dict[str, Side] = {k.name: k for k in (Side("intrados", 0.5, -1.0, "extrados"),
                                               Side("extrados", -0.5, 1.0, "intrados"),
                                               Side("separated", 0.0, 0.0, "separated"))}
# The edges of a section in the order of every array over them: index 0 the intrados (y = +t/2:
# fibre force N+, opening rate eps+, the simulation's corner 0), index 1 the extrados (y = -t/2).
EDGES = ("intrados", "extrados")
ROCKING_SIDES = EDGES   # the sides a hinge of a mechanism may pivot on


def side_of(name: str) -> Side:
    """The :class:`Side` called ``name``; InputError for an unknown name."""
    try:
        return SIDES[name]
    except (KeyError, TypeError):
        raise InputError(f"unknown hinge side {name!r}: expected one of {', '.join(SIDES)}") from None


def side_from_text(text: str) -> str:
    """The rocking side named ``text`` or by its initial (``"i"``, ``"e"``; any case, spaces
    ignored); InputError otherwise."""
    key = text.strip().lower() if isinstance(text, str) else None
    for name in ROCKING_SIDES:
        if key in (name, SIDES[name].initial):
            return name
    raise InputError(f"unknown hinge side {text!r}: expected one of {', '.join(ROCKING_SIDES)} or their initials")


def pivot_sides(open_intrados: np.ndarray, open_extrados: np.ndarray) -> np.ndarray:
    """Sides the joints pivot on, from which of their edges open (bool arrays): a joint whose
    extrados opens pivots on the intrados and vice versa; both open: ``"separated"``."""
    return np.where(open_intrados & open_extrados, "separated", np.where(open_extrados, "intrados", "extrados"))


def pivot_fractions(sides: Iterable[str]) -> np.ndarray:
    """``y/t`` of the pivot points of ``sides``."""
    return np.array([side_of(k).pivot for k in sides], float)


def opening_signs(sides: Iterable[str]) -> np.ndarray:
    """Signs of ``[omega]`` that open hinges on ``sides``."""
    return np.array([side_of(k).opening for k in sides], float)


@dataclass(frozen=True)
class Hinge:
    """A hinge of a mechanism: an open joint pivoting on one edge.

    Attributes
    ----------
    s : float
        Arc length of the hinge (m, from the left springing).
    angle_deg : float
        Its reporting angle (deg, from the left springing; on a circular arch the angle
        subtended from the left springing).
    side : {"intrados", "extrados"}
        The edge it pivots on.
    rotation : float
        Relative angular velocity across it (rad/s, right minus left element).
    joints : tuple of int
        Indices of the joints of the mesh it stands for.

    Examples
    --------
    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> disc = fembeam.discretize(arch, fembeam.uniform_nodes(arch, 6))
    >>> lim = fembeam.limit_analysis(disc)
    >>> h = lim.hinges[1]
    >>> print(f"{h.s:.4f} m, {h.angle_deg:.2f} deg", h.side, h.joints)
    0.9163 m, 52.50 deg extrados (2,)
    """

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
    j = np.flatnonzero(oi | oe)
    side = pivot_sides(oi[j], oe[j])
    angle = np.atleast_1d(disc.curve.angle_deg(disc.joint_s[j]))
    return [Hinge(float(disc.joint_s[k]), float(a), str(sd), float(rot[k]), (int(k),))
            for k, a, sd in zip(j, angle, side)]


def hinges_and_slides(disc: Discretization, u: np.ndarray, mu: float | None,
                      rel_tol: float = HINGE_REL_TOL) -> tuple[list[Hinge], list[dict]]:
    """Hinges and sliding joints of the field ``u`` whose joints may slide with associative
    dilatancy (Coulomb coefficient ``mu``; None: no sliding): the hinges from the rotation part
    of the openings, ``eps+- - mu |gamma|``, the slides where ``|gamma|`` (``gamma = B_slide u``)
    is above ``rel_tol`` of the largest jump.  A slide is ``{"angle_deg", "s", "rate"}``
    (``rate``: sliding velocity ``gamma``, m/s, + along ``n``)."""
    J = disc.n_joints
    gam = disc.B_slide @ u
    eps = (disc.B_open @ u).reshape(2, J) - (0.0 if mu is None else mu) * np.abs(gam)
    scale = max(np.max(np.abs(eps)), np.max(np.abs(gam)), 1e-300)
    oi, oe = eps[0] > rel_tol * scale, eps[1] > rel_tol * scale
    rot = (eps[0] - eps[1]) / disc.joint_thickness
    j = np.flatnonzero(oi | oe)
    side = pivot_sides(oi[j], oe[j])
    hinges = [Hinge(float(disc.joint_s[k]), float(disc.joint_angle_deg[k]), str(sd), float(rot[k]), (int(k),))
              for k, sd in zip(j, side)]
    sl = np.flatnonzero(np.abs(gam) > rel_tol * scale)
    slides = [{"angle_deg": round(float(disc.joint_angle_deg[k]), 6), "s": float(disc.joint_s[k]),
               "rate": float(gam[k])} for k in sl]
    return hinges, slides


def merge_adjacent(disc: Discretization, hinges: list[Hinge]) -> list[Hinge]:
    """Merge runs of hinges at consecutive joints with the same side into one hinge at
    the rotation-weighted mean position: on a fine mesh of a continuous arch a hinge
    lying between two nodes shows up as two neighbouring partial hinges.  A mean inside
    a crown wedge (no section there) is moved to the nearer of its ends."""
    out: list[Hinge] = []
    for h in hinges:
        last = out[-1] if out else None
        if last is not None and h.side == last.side and h.joints[0] == last.joints[-1] + 1:
            wl, wh = abs(last.rotation), abs(h.rotation)
            s = float(disc.curve.nearest_section((wl * last.s + wh * h.s) / (wl + wh)))
            out[-1] = Hinge(s, float(disc.curve.angle_deg(s)), h.side, last.rotation + h.rotation,
                            last.joints + h.joints)
        else:
            out.append(h)
    return out
