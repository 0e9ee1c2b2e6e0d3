"""One mechanism type: rigid pieces between hinges (Sect. 4, Appendix A).

A :class:`Mechanism` of a member is given by its hinges (arc lengths ``s``, m,
increasing, and the side each pivots on, see :data:`~fembeam.mechanisms.hinge.SIDES`)
and moves with one free parameter ``alpha`` (rad/s, the angular velocity of the
first moving piece). Two kinds exist:

* **four hinges** ``C1, C13, C23, C2`` between two abutments (both ends of the member
  are joints): piece I = [s1, s13] rotates about C1 with ``Omega_I = alpha``, piece
  III = [s13, s23] about C3, the intersection of lines C1-C13 and C2-C23, and piece
  II = [s23, s2] about C2; the parts outside [s1, s2] rest on the abutments. The
  ratios ``Omega_III / Omega_I`` and ``Omega_II / Omega_I`` are (A.1) written with
  dot products (valid for any orientation of the lines);
* **one hinge** when one end of the member is free (Housner's block): the piece
  between the hinge and the free end rotates about the hinge with ``Omega = alpha``.

The velocity of a piece is the rigid field ``V + Omega k x X`` (``V``: velocity of
the material point at the origin, m/s; ``Omega`` counter-clockwise, rad/s).  The
jump of ``Omega`` (right minus left) across a hinge opens it when its sign is the
side's ``opening`` sign.  :meth:`Mechanism.configuration` moves the pieces by a
finite rotation ``theta`` of the free parameter (exact four-bar linkage).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError, SolverError
from ..fem import Discretization, rigid_dofs
from ..geometry import MidCurve
from .hinge import HINGE_REL_TOL, ROCKING_SIDES, Hinge, find_hinges, merge_adjacent, opening_signs, \
    pivot_fractions, side_of

__all__ = ["Mechanism", "Configuration", "END_TOL"]

END_TOL = 1e-10     # relative to the member's length: a hinge this close past an end is at the end


def _rot(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def _cross(a: np.ndarray, b: np.ndarray):
    return a[0] * b[1] - a[1] * b[0]


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """Counter-clockwise angle (rad, in (-pi, pi]) from vector ``a`` to vector ``b``."""
    return float(np.arctan2(_cross(a, b), np.dot(a, b)))


@dataclass(frozen=True)
class Mechanism:
    """A one-degree-of-freedom mechanism: rigid pieces of a member between hinges.

    Four hinges when both ends of ``curve`` are joints, one hinge when one end is free.
    A hinge past an end of the member by at most :data:`END_TOL` of its length (round-off:
    the end's arc length computed along the other direction) is put at that end.

    Parameters
    ----------
    curve : MidCurve
        The member.
    s : sequence of float
        Arc lengths of the hinges (m, from the left springing), increasing.
    sides : sequence of {"intrados", "extrados"}
        The edge each hinge pivots on.
    alpha : float, optional
        Rate of the free parameter (rad/s): the angular velocity ``Omega`` of the first
        moving piece (counter-clockwise > 0).

    Raises
    ------
    InputError
        The wrong number of hinges, an unknown side, or hinges off the member or out of
        order.

    Examples
    --------
    The paper's four-hinge mechanism, hinges at angles from the left springing:

    >>> import fembeam
    >>> arch = fembeam.CircularArch(radius=1.0, thickness=0.15, embrace_deg=157.5)
    >>> sides = ["intrados", "extrados", "intrados", "extrados"]
    >>> mech = fembeam.Mechanism.from_angles(arch, [0.0, 52.5, 118.125, 157.5], sides)
    >>> print(mech.n_hinges, [f"{s:.4f}" for s in mech.s])
    4 ['0.0000', '0.9163', '2.0617', '2.7489']
    """

    curve: MidCurve
    s: tuple[float, ...]
    sides: tuple[str, ...]
    alpha: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "s", tuple(float(x) for x in self.s))
        object.__setattr__(self, "sides", tuple(str(k) for k in self.sides))
        n = self.n_hinges_expected(self.curve)
        if len(self.s) != n or len(self.sides) != n:
            raise InputError(f"a mechanism of a member with ends {self.curve.ends} needs exactly {n} hinge"
                             f"{'s' if n > 1 else ''}, got {len(self.s)}")
        if any(k not in ROCKING_SIDES for k in self.sides):
            raise InputError(f"hinge sides must be 'intrados' or 'extrados', got {self.sides}")
        s = self.s                  # a few floats: checked in Python (the hinge searches build thousands)
        if not all(math.isfinite(x) for x in s):
            raise InputError(f"hinge positions must be finite numbers, got s = {self.s}")
        if any(b < a for a, b in zip(s, s[1:])):
            raise InputError(f"the hinges must be in increasing order along the member, got s = {self.s}")
        L = float(self.curve.length)
        lo, hi = -END_TOL * L, (1 + END_TOL) * L
        if any(x < lo or x > hi for x in s):
            raise InputError(f"hinges must lie on the member, s in [0, {L:g}] m, got {self.s}")
        if any(x < 0 or x > L for x in s):        # past an end by round-off (a length summed another way)
            object.__setattr__(self, "s", tuple(float(x) for x in np.clip(np.asarray(s), 0.0, L)))

    # ------------------------------------------------------------------ construction
    @staticmethod
    def n_hinges_expected(curve: MidCurve) -> int:
        """4 between two abutments, 1 with a free end."""
        ends = tuple(curve.ends)
        if ends == ("joint", "joint"):
            return 4
        if sorted(ends) == ["free", "joint"]:
            return 1
        raise InputError(f"no one-parameter mechanism for a member with ends {ends}")

    @classmethod
    def from_hinges(cls, curve: MidCurve, hinges, alpha: float = 1.0) -> "Mechanism":
        """From :class:`~fembeam.mechanisms.hinge.Hinge` objects (e.g. a limit analysis's)."""
        hinges = list(hinges)
        n = cls.n_hinges_expected(curve)
        if len(hinges) != n:
            raise InputError(f"expected a {n}-hinge mechanism, got {len(hinges)} hinges: the mechanisms followed here "
                             f"have {n} distinct hinges, and this member's collapse mechanism has fewer (hinges "
                             "merged: an arch of 2 voussoirs, or so thick, t/R near 2, that hinges meet; fembeam "
                             f"analyze shows them); give a member whose collapse mechanism has {n}")
        return cls(curve, tuple(float(h.s) for h in hinges), tuple(h.side for h in hinges), alpha)

    @classmethod
    def from_angles(cls, curve: MidCurve, angles_deg, sides, alpha: float = 1.0, joints=None,
                    what: str = "hinges") -> "Mechanism":
        """Hinges at ``angles_deg`` (the curve's reporting coordinate, deg from the left
        springing for arches), placed by :meth:`MidCurve.s_at_angle` and checked by
        :meth:`checked` (``joints``: arc lengths the hinges must sit at, e.g. voussoir joints)."""
        n = cls.n_hinges_expected(curve)
        try:
            a = np.asarray(angles_deg, float).ravel()
        except (TypeError, ValueError):
            raise InputError(f"{what}: angles must be numbers (deg), got {angles_deg!r}") from None
        sides = [sides] if isinstance(sides, str) else list(sides)
        if a.size != n or len(sides) != n:
            raise InputError(f"{what}: give exactly {n} hinge{'s' if n > 1 else ''} (angle and side each), "
                             f"got {a.size} angles and {len(sides)} sides")
        lo, hi = float(curve.angle_deg(0.0)), float(curve.angle_deg(curve.length))
        shown = ", ".join(f"{x:g}" for x in a)
        if not np.all(np.isfinite(a)):
            raise InputError(f"{what}: angles must be finite numbers in [{lo:g}, {hi:g}] deg, got {shown}")
        if np.any(a < lo - 1e-9) or np.any(a > hi * (1 + 1e-12)):
            raise InputError(f"{what}: angles must lie in [{lo:g}, {hi:g}] deg, got {shown}")
        if np.any(np.diff(a) <= 0):
            raise InputError(f"{what}: angles must be distinct and strictly increasing from the left "
                             f"springing, got {shown} deg")
        s = np.clip(np.asarray(curve.s_at_angle(a), float), 0.0, curve.length)
        return cls.checked(curve, s, sides, alpha, joints, what)

    @classmethod
    def checked(cls, curve: MidCurve, s, sides, alpha: float = 1.0, joints=None,
                what: str = "hinges") -> "Mechanism":
        """The one check of a prescribed hinge list (InputError saying what is allowed):
        arc lengths ``s`` (m) finite, on the member and strictly increasing; sides
        ``"intrados"``/``"extrados"``; with ``joints`` (m) every hinge at a joint (within
        1e-4 of the joint spacing; snapped onto it); and a non-degenerate one-parameter
        mechanism (:meth:`check_four_bar`)."""
        s = np.asarray(s, float).ravel()
        bad = [k for k in sides if k not in ROCKING_SIDES]
        if bad:
            raise InputError(f"{what}: a hinge side is intrados (i) or extrados (e), got {bad[0]!r}")
        L = curve.length
        if not np.all(np.isfinite(s)) or np.any(s < 0) or np.any(s > L):
            raise InputError(f"{what}: hinges must lie on the member, s in [0, {L:g}] m, got {s.tolist()}")
        deg = np.asarray(curve.angle_deg(s), float)
        inside = np.flatnonzero(~curve.admissible(s))
        if inside.size:
            i = int(inside[0])
            a, b = next((a, b) for a, b in curve.solid_spans if a < s[i] < b)
            lo, hi = (float(x) for x in curve.angle_deg(np.array([a, b])))
            raise InputError(f"{what}: {deg[i]:g} deg lies inside a crown wedge, between the last radial section "
                             f"({min(lo, hi):.10g} deg) and the crown joint ({max(lo, hi):.10g} deg): the member has "
                             f"no section there")
        if joints is not None:
            js = np.asarray(joints, float)
            k = np.abs(js[None, :] - s[:, None]).argmin(1)
            tol = 1e-4 * float(np.min(np.diff(js)))
            off = np.flatnonzero(np.abs(js[k] - s) > tol)
            if off.size:
                i = int(off[0])
                ja = np.asarray(curve.angle_deg(js), float)
                near = np.searchsorted(js, s[i])
                pair = ja[max(near - 1, 0)], ja[min(near, js.size - 1)]
                step = np.diff(ja)
                every = f"; joints every {step[0]:.10g} deg" if np.allclose(step, step[0]) else ""
                raise InputError(f"{what}: {deg[i]:g} deg is not at a voussoir joint (nearest joints "
                                 f"{pair[0]:.10g} and {pair[1]:.10g} deg{every})")
            s = js[k]
        if np.any(np.diff(s) <= 1e-12 * L):
            i = int(np.flatnonzero(np.diff(s) <= 1e-12 * L)[0])
            raise InputError(f"{what}: hinges must be at distinct sections, strictly increasing from the left "
                             f"springing; {deg[i]:g} and {deg[i + 1]:g} deg are the same section or out of order")
        mech = cls(curve, tuple(s), tuple(sides), alpha)
        mech.check_four_bar(what)
        return mech

    def check_four_bar(self, what: str = "hinges") -> None:
        """InputError unless the mechanism moves with one parameter and every hinge turns:
        the lines C1-C13 and C2-C23 must cross (else the middle piece would translate)
        and no three pivots may be aligned so that a hinge locks or stays still."""
        if self.n_hinges != 4:
            return
        C1, C13, C23, C2 = self.points().T
        d1, d2 = C13 - C1, C23 - C2
        if abs(_cross(d1, d2)) <= 1e-9 * np.linalg.norm(d1) * np.linalg.norm(d2):
            raise InputError(f"{what}: degenerate four-hinge mechanism: the lines through the first two and "
                             "the last two pivots are parallel (the middle piece could only translate)")
        P, deg = self.points().T, self.angles_deg()
        for i, j, k in ((0, 1, 2), (1, 2, 3), (0, 1, 3), (0, 2, 3)):
            u, v = P[j] - P[i], P[k] - P[i]
            if abs(_cross(u, v)) <= 1e-9 * np.linalg.norm(u) * np.linalg.norm(v):
                raise InputError(f"{what}: degenerate four-hinge mechanism: the pivots at {deg[i]:g}, {deg[j]:g} "
                                 f"and {deg[k]:g} deg are aligned, so the four-bar locks or a hinge cannot turn")
        with np.errstate(all="ignore"):
            jumps = self.jumps()
        dead = ~np.isfinite(jumps) | (np.abs(jumps) <= 1e-9 * np.max(np.abs(np.nan_to_num(jumps))))
        if dead.any():
            at = float(self.curve.angle_deg(self.s[int(np.flatnonzero(dead)[0])]))
            raise InputError(f"{what}: degenerate four-hinge mechanism: the hinge at {at:g} deg cannot turn "
                             "(three pivots are aligned), so this is not a one-degree-of-freedom four-bar")

    @classmethod
    def from_dofs(cls, disc: Discretization, d: np.ndarray, rel_tol: float = HINGE_REL_TOL) -> "Mechanism":
        """The mechanism of the element DOFs ``d``: its open joints
        (:func:`~fembeam.mechanisms.hinge.find_hinges`, neighbours on one side merged)
        and the rate ``alpha`` fitting their rotations (least squares)."""
        hs = merge_adjacent(disc, find_hinges(disc, d, rel_tol))
        if any(h.side not in ROCKING_SIDES for h in hs):
            raise InputError("a joint of the field has separated: not a mechanism of rotating pieces")
        unit = cls.from_hinges(disc.curve, hs)
        jumps = unit.jumps()
        rot = np.array([h.rotation for h in hs])
        return unit.with_alpha(float(jumps @ rot / (jumps @ jumps)))

    def with_alpha(self, alpha: float) -> "Mechanism":
        """The same hinges moving with free-parameter rate ``alpha`` (rad/s)."""
        out = replace(self, alpha=float(alpha))
        for name in ("_breaks_cache", "_moving_cache", "_omegas_cache", "_sign_cache"):   # the same hinges:
            if name in self.__dict__:                                                     # the same pieces
                object.__setattr__(out, name, self.__dict__[name])
        return out

    def closing(self) -> "Mechanism":
        """The same hinges moving in the sense that closes them (rate ``-compatible_sign``,
        0 if incompatible): the field of an arch returning along ``-u`` to an impact."""
        return self.with_alpha(-self.compatible_sign())

    def opposite(self) -> "Mechanism":
        """Same sections, pivots on the other edge (the points C-bar of Sect. 3)."""
        return replace(self, sides=tuple(side_of(k).opposite_name for k in self.sides))

    def mirrored(self) -> "Mechanism":
        """Mirror image about the vertical axis of the member: ``s -> L - s`` with the
        same sides for a symmetric arch; the other face at the same ``s`` for a member
        with a free end (a vertical block)."""
        if self.n_hinges == 1:
            return self.opposite()
        L = self.curve.length
        return replace(self, s=tuple(L - np.asarray(self.s[::-1], float)), sides=self.sides[::-1])

    @property
    def key(self) -> tuple:
        """The canonical key of the mechanism's hinges (its rate aside): the positions as fractions
        of the length rounded to 12 digits, and the sides.  Two mechanisms with one key are one
        mechanism: the impact model's cache and the whole motion's numbering use this key only."""
        L = self.curve.length
        return tuple(round(float(s) / L, 12) for s in self.s), self.sides

    def canonical(self) -> "Mechanism":
        """The mechanism of :attr:`key` (hinges at the key's positions, rate 1): what is computed
        for every mechanism of that key, so that a result does not depend on which of them was
        met first."""
        fr, sides = self.key
        return replace(self, s=tuple(f * self.curve.length for f in fr), sides=sides, alpha=1.0)

    # ------------------------------------------------------------------ geometry
    @property
    def n_hinges(self) -> int:
        return len(self.s)

    @property
    def breaks(self) -> np.ndarray:
        """Ends of the pieces (m): ``[0, *s, L]``."""
        return self._breaks().copy()

    def _breaks(self) -> np.ndarray:
        return self._cached("_breaks_cache", lambda: np.array([0.0, *self.s, self.curve.length]))

    @property
    def moving(self) -> np.ndarray:
        """Booleans: which pieces (between consecutive ``breaks``) move."""
        return self._moving().copy()

    def _moving(self) -> np.ndarray:
        def moving():
            if self.n_hinges == 4:
                return np.array([False, True, True, True, False])
            return np.array([False, True]) if self.curve.ends[1] == "free" else np.array([True, False])
        return self._cached("_moving_cache", moving)

    def _cached(self, name: str, compute):
        # the fields are frozen, so what depends on them alone is computed once per mechanism
        # (the hinge searches ask for it thousands of times); never handed out without a copy
        cached = self.__dict__.get(name)
        if cached is None:
            cached = compute()
            object.__setattr__(self, name, cached)
        return cached

    def angles_deg(self) -> np.ndarray:
        return np.asarray(self.curve.angle_deg(np.asarray(self.s, float)), float)

    def pivot_y(self) -> np.ndarray:
        """Offsets ``y`` (m, along ``n``) of the pivot points of the hinges."""
        s = np.asarray(self.s, float)
        return pivot_fractions(self.sides) * self.curve.thickness_at(s)

    def points(self) -> np.ndarray:
        """(2, n_hinges) pivot points ``X(s) + y n(s)`` (m)."""
        return self.curve.point(np.asarray(self.s, float), self.pivot_y())

    def to_list(self) -> list[dict]:
        return [{"angle_deg": round(float(a), 6), "side": k} for a, k in zip(self.angles_deg(), self.sides)]

    # ------------------------------------------------------------------ kinematics
    def omegas(self) -> tuple[np.ndarray, np.ndarray]:
        """Angular velocities of the moving pieces for ``alpha = 1`` and their centres
        (2, k): for four hinges ``(1, Omega_III, Omega_II)`` about ``(C1, C3, C2)``."""
        om, C = self._omegas()
        return om.copy(), C.copy()

    def _omegas(self) -> tuple[np.ndarray, np.ndarray]:
        return self._cached("_omegas_cache", self._compute_omegas)

    def _compute_omegas(self) -> tuple[np.ndarray, np.ndarray]:
        P = self.points()
        if self.n_hinges == 1:
            return np.array([1.0]), P
        C1, C13, C23, C2 = P.T
        d1, d2 = C13 - C1, C23 - C2
        det = d1[0] * (-d2[1]) - d1[1] * (-d2[0])
        if abs(det) < 1e-14 * np.dot(d1, d1):
            raise SolverError("degenerate four-hinge mechanism: lines C1-C13 and C2-C23 are parallel")
        a = ((C2 - C1)[0] * (-d2[1]) - (C2 - C1)[1] * (-d2[0])) / det
        C3 = C1 + a * d1
        om3 = np.dot(C13 - C1, C13 - C3) / np.dot(C13 - C3, C13 - C3)
        om2 = om3 * np.dot(C23 - C3, C23 - C2) / np.dot(C23 - C2, C23 - C2)
        return np.array([1.0, om3, om2]), np.array([C1, C3, C2]).T

    def piece_omegas(self) -> np.ndarray:
        """Angular velocity of every piece (rad/s) for ``alpha = 1`` (0 at rest)."""
        moving = self._moving()
        out = np.zeros(moving.size)
        out[moving] = self._omegas()[0]
        return out

    def jumps(self) -> np.ndarray:
        """Rotation jumps ``[Omega]`` (right minus left) at the hinges for ``alpha = 1``."""
        return np.diff(self.piece_omegas())

    def compatible_sign(self) -> float:
        """+1 or -1: the sign of ``alpha`` for which every hinge opens; 0 if none does."""
        def sign():
            q = (opening_signs(self.sides) * self.jumps()).tolist()
            return 1.0 if all(v >= 0 for v in q) else (-1.0 if all(v <= 0 for v in q) else 0.0)
        return self._cached("_sign_cache", sign)

    def motion(self) -> np.ndarray:
        """(pieces, 3): ``(V_x, V_y, Omega)`` of each piece (m/s, rad/s) at rate ``alpha``."""
        return self._motion().copy()

    def _motion(self) -> np.ndarray:
        # computed once per mechanism (the fields are frozen): the impact's pairings and the
        # hinge searches ask for it thousands of times
        def motion():
            om, C = self._omegas()
            w = self.alpha * om
            moving = self._moving()
            out = np.zeros((moving.size, 3))
            out[moving] = np.column_stack([w * C[1], -w * C[0], w])   # rotation w about C
            return out
        return self._cached("_motion_cache", motion)

    def piece_of(self, s) -> np.ndarray:
        """Index of the piece containing each section ``s`` (left piece at a hinge)."""
        i = np.searchsorted(self._breaks(), s) - 1
        return np.minimum(np.maximum(i, 0), self._moving().size - 1)   # np.clip, without its overhead

    def motion_at(self, s) -> np.ndarray:
        """(n, 3) motion of the piece containing each ``s``."""
        return self._motion()[np.atleast_1d(self.piece_of(np.asarray(s, float)))].reshape(
            np.shape(s) + (3,))

    def velocity(self, s, y=0.0) -> np.ndarray:
        """(2, n) velocity (m/s) of the material points ``X(s) + y n(s)``."""
        s = np.atleast_1d(np.asarray(s, float))
        X = self.curve.point(s, y)
        Vx, Vy, omega = self.motion_at(s).T
        return np.array([Vx - omega * X[1], Vy + omega * X[0]])

    def dofs(self, disc: Discretization) -> np.ndarray:
        """Element DOFs of the field on ``disc``: each element takes the motion of the
        piece containing its midpoint (exact when the hinges are nodes of the mesh; an
        element too short for its midpoint to differ from its ends, e.g. one ulp at a
        kink's one-sided cut, takes the piece right of its left node)."""
        sm, nodes = disc.frames["s"], disc.nodes_s
        piece = self.piece_of(sm)
        short = (sm <= nodes[:-1]) | (sm >= nodes[1:])
        if short.any():
            right_of = np.searchsorted(self.breaks, nodes[:-1][short], side="right") - 1
            piece[short] = np.clip(right_of, 0, self.moving.size - 1)
        Vx, Vy, omega = self.motion()[piece].T
        return rigid_dofs(disc, (Vx, Vy), omega)

    def hinges(self) -> list[Hinge]:
        """The hinges as :class:`~fembeam.mechanisms.hinge.Hinge` (rotation = jump of the
        angular velocity at rate ``alpha``, right minus left)."""
        return [Hinge(float(s), float(self.curve.angle_deg(s)), k, float(j), ())
                for s, k, j in zip(self.s, self.sides, self.alpha * self.jumps())]

    def configuration(self, theta: float) -> "Configuration":
        """The pieces after a finite rotation ``theta`` (rad, counter-clockwise) of the
        free parameter: the first moving piece rotates by ``theta`` about its hinge.

        Four hinges: the exact four-bar linkage C1-C13-C23-C2; C13 turns about C1, C23
        stays on its circle about C2 at the fixed length ``|C23 - C13|``, on the branch
        continuous from ``theta = 0``; ``locked`` when the loop cannot close.
        """
        n = self.moving.size
        rotation, anchor, moved = np.zeros(n), np.zeros((2, n)), np.zeros((2, n))
        P = self.points()
        k = np.flatnonzero(self.moving)
        if self.n_hinges == 1:
            rotation[k] = theta
            anchor[:, k] = moved[:, k] = P
            return Configuration(self, float(theta), False, rotation, anchor, moved)
        C1, C13, C23, C2 = P.T
        l2, l3 = np.linalg.norm(C23 - C2), np.linalg.norm(C23 - C13)
        B = C1 + _rot(theta) @ (C13 - C1)                         # C13 after the rotation
        sigma = 1.0 if _cross(C13 - C2, C23 - C2) >= 0 else -1.0  # branch at theta = 0
        dv = B - C2
        d = np.linalg.norm(dv)
        e = dv / d
        a = (l2**2 - l3**2 + d**2) / (2 * d)
        h2 = l2**2 - a**2
        if h2 < -1e-12 * l2**2:
            nan = np.full(n, np.nan)
            return Configuration(self, float(theta), True, nan, np.full((2, n), np.nan), np.full((2, n), np.nan))
        D = C2 + a * e + sigma * np.sqrt(max(h2, 0.0)) * np.array([-e[1], e[0]])   # C23 after
        rotation[k] = theta, _angle(C23 - C13, D - B), _angle(C23 - C2, D - C2)
        anchor[:, k] = np.array([C1, C13, C2]).T
        moved[:, k] = np.array([C1, B, C2]).T
        return Configuration(self, float(theta), False, rotation, anchor, moved)


@dataclass(frozen=True)
class Configuration:
    """A mechanism's pieces after a finite motion: piece ``i`` is turned by
    ``rotation[i]`` (rad, counter-clockwise) and moved so that its material point
    ``anchor[:, i]`` is at ``moved[:, i]`` (m). ``locked``: the motion is impossible
    (the four-bar loop cannot close); then every array is NaN."""

    mechanism: Mechanism
    theta: float
    locked: bool
    rotation: np.ndarray
    anchor: np.ndarray
    moved: np.ndarray

    def displace(self, s, y=0.0, piece=None) -> np.ndarray:
        """(2, n) positions of the material points ``X(s) + y n(s)`` (m); ``piece``
        forces the piece (default: the one containing ``s``, the left one at a hinge)."""
        s = np.atleast_1d(np.asarray(s, float))
        k = self.mechanism.piece_of(s) if piece is None else np.full(s.shape, int(piece))
        X = self.mechanism.curve.point(s, y)
        c, sn = np.cos(self.rotation[k]), np.sin(self.rotation[k])
        r = X - self.anchor[:, k]
        return self.moved[:, k] + np.array([c * r[0] - sn * r[1], sn * r[0] + c * r[1]])

    def hinge_points(self) -> np.ndarray:
        """(2, n_hinges) pivot points after the motion (shared by both pieces)."""
        m = self.mechanism
        return np.column_stack([self.displace(s, y, piece=i)[:, 0]
                                for i, (s, y) in enumerate(zip(m.s, m.pivot_y()))]) \
            if m.n_hinges else np.zeros((2, 0))

    def hinge_rotations(self) -> np.ndarray:
        """Relative rotations (rad, right minus left) at the hinges."""
        return np.diff(self.rotation)

    @property
    def opens(self) -> bool:
        """Every hinge is turned in its opening sense (or not at all)."""
        q = opening_signs(self.mechanism.sides) * self.hinge_rotations()
        return bool(not self.locked and np.all(q >= 0))
