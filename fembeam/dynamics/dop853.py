"""DOP853: the explicit Runge-Kutta method of order 8(5,3) of Dormand and Prince with its
dense output of order 7, as a stepper in plain floats for small systems.

Tableau: Hairer's ``dop853.f`` (E. Hairer, S. P. Norsett, G. Wanner, *Solving Ordinary
Differential Equations I: Nonstiff Problems*, 2nd ed., Springer 1993, Section II.10; the
coefficients of J. R. Dormand and P. J. Prince, *A family of embedded Runge-Kutta formulae*,
J. Comp. Appl. Math. 6 (1980) 19-26, and P. J. Prince and J. R. Dormand, *High order embedded
Runge-Kutta formulae*, J. Comp. Appl. Math. 7 (1981) 67-75), rounded to doubles; the same
numbers as SciPy's ``solve_ivp(method="DOP853")``.  Step control and error norm are SciPy's
(safety 0.9, factors in [0.2, 10], exponent -1/8, the 5th/3rd-order error blend of Hairer's
code), so that a step of :class:`Dop853` is a step of ``solve_ivp``.

:class:`Dop853` is generic in its right-hand side ``fun(t, y) -> y'`` (tuples of floats); its
interpolant on a step ``[t, t + h]`` is ``y(t + x h) = y + poly(F, x)`` per component with seven
coefficients ``F`` (:func:`poly`).  ``tests/test_dop853.py`` checks the order conditions of the
tableau, the orders of the step and of the interpolant, and steps against ``solve_ivp``.
"""
from __future__ import annotations

import math
from bisect import bisect_right
from operator import mul
from typing import Callable, Sequence

__all__ = ["Dop853", "Dense", "poly", "N_STAGES", "C", "A", "B", "E3", "E5", "D"]

N_STAGES = 12           # stages of a step; 4 more for the dense output (C[12] = 1: the step's end)
SAFETY, MIN_FACTOR, MAX_FACTOR, EXPONENT = 0.9, 0.2, 10.0, -1.0 / 8.0

C = (0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726, 0.3333333333333333,
     0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0, 0.1, 0.2,
     0.7777777777777778)
A = (   # row s: the coefficients a_sj, j < s, of stage s = 1 .. 15
    (0.05260015195876773,),
    (0.0197250569845379, 0.0591751709536137),
    (0.02958758547680685, 0.0, 0.08876275643042054),
    (0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792),
    (0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242),
    (0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125),
    (0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402,
     0.008273789163814023),
    (0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671,
     20.154067550477894, -43.48988418106996),
    (0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193,
     15.279233632882423, -33.28821096898486, -0.020331201708508627),
    (-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927,
     -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196),
    (2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188,
     27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636),
    (0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
     0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259),
    (0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025,
     -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298),
    (0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099,
     0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456, 0.1413124436746325),
    (-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711,
     0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987),
)
B = (0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
     0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259)
E3 = (-0.18980075407240762, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
      -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082, 0.0)
E5 = (0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864,
      -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294, 0.0)
D = (   # dense output: the interpolant's coefficients F3 .. F6 from the 16 stages
    (-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207,
     2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331,
     18.148505520854727, -9.194632392478356, -4.436036387594894),
    (10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902,
     -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845,
     -31.139403219565178, -9.35292435884448, 35.81684148639408),
    (19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236,
     -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508,
     -60.19669523126412, 84.32040550667716, 11.99229113618279),
    (-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141,
     93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114,
     96.32455395918828, -39.17726167561544, -149.72683625798564),
)
STAGES = tuple(zip(A[:N_STAGES - 1], C[1:N_STAGES]))     # (a_s, c_s) of the stages 1 .. 11 of a step
DENSE_STAGES = tuple(zip(A[N_STAGES:], C[N_STAGES + 1:]))     # ... and of the dense output's 3


def poly(F: Sequence[float], x: float) -> float:
    """The interpolant's increment ``y(t + x h) - y(t)`` at ``x`` in [0, 1] of a step, from its
    coefficients ``F`` (SciPy's nested form in ``x`` and ``u = 1 - x``)."""
    F0, F1, F2, F3, F4, F5, F6 = F
    u = 1.0 - x
    return x * (F0 + u * (F1 + x * (F2 + u * (F3 + x * (F4 + u * (F5 + x * F6))))))


class Dop853:
    """DOP853 steps of ``y' = fun(t, y)`` (``y`` a tuple of ``n`` floats) with relative
    tolerance ``rtol`` and absolute tolerances ``atol`` (one per component)."""

    def __init__(self, fun: Callable[[float, tuple], tuple], atol: Sequence[float], rtol: float):
        self.fun, self.atol, self.rtol = fun, tuple(atol), float(rtol)

    def first_step(self, t: float, y: tuple, f: tuple, span: float) -> float:
        """Hairer's starting step (SciPy's ``select_initial_step``, order 7), at most ``span``."""
        sc = [a + abs(v) * self.rtol for a, v in zip(self.atol, y)]
        n = len(y)
        d0 = math.sqrt(sum((v / s) ** 2 for v, s in zip(y, sc)) / n)
        d1 = math.sqrt(sum((v / s) ** 2 for v, s in zip(f, sc)) / n)
        h0 = min(1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1, span)
        f1 = self.fun(t + h0, tuple(v + h0 * d for v, d in zip(y, f)))
        d2 = math.sqrt(sum(((b - a) / s) ** 2 for a, b, s in zip(f, f1, sc)) / n) / h0
        h1 = max(1e-6, h0 * 1e-3) if max(d1, d2) <= 1e-15 else (0.01 / max(d1, d2)) ** (1 / 8)
        return min(100 * h0, h1, span)

    def _stage(self, t: float, y: tuple, K: tuple, h: float, a: Sequence[float], c: float) -> None:
        """Append to each component's ``K`` the derivative of the stage ``(a, c)``:
        ``fun(t + c h, y + h sum_j a_j K_j)``; written out for three components (the
        one-mechanism motion: rotation, rate, ground work), the same operations in the same
        order."""
        if len(y) == 3:
            (u0, u1, u2), (K0, K1, K2) = y, K
            v0, v1, v2 = self.fun(t + c * h, (u0 + h * sum(map(mul, a, K0)), u1 + h * sum(map(mul, a, K1)),
                                              u2 + h * sum(map(mul, a, K2))))
            K0.append(v0)
            K1.append(v1)
            K2.append(v2)
        else:
            for Ki, v in zip(K, self.fun(t + c * h, tuple([u + h * sum(map(mul, a, Ki)) for u, Ki in zip(y, K)]))):
                Ki.append(v)

    def step(self, t: float, y: tuple, f: tuple, h: float):
        """One step ``h`` from ``(t, y)`` (``f = fun(t, y)``): ``(y_new, K, error norm)`` with
        ``K`` the 13 stage derivatives of each component (the last: ``fun`` at ``t + h``).  The
        step is accepted where the norm is below 1."""
        K = tuple([v] for v in f)
        for a, c in STAGES:
            self._stage(t, y, K, h, a, c)
        y1 = tuple([u + h * sum(map(mul, B, Ki)) for u, Ki in zip(y, K)])
        for Ki, v in zip(K, self.fun(t + h, y1)):
            Ki.append(v)
        e5 = e3 = 0.0
        for Ki, a, u, v in zip(K, self.atol, y, y1):
            sc = a + max(abs(u), abs(v)) * self.rtol
            e5 += (sum(map(mul, E5, Ki)) / sc) ** 2
            e3 += (sum(map(mul, E3, Ki)) / sc) ** 2
        err = 0.0 if e5 == 0.0 and e3 == 0.0 else abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * len(y))
        return y1, K, err

    @staticmethod
    def next_step(h: float, err: float, rejected: bool) -> float:
        """The next step size after a step ``h`` of error norm ``err`` (SciPy's control: no
        growth after a rejection)."""
        if err >= 1.0:
            return h * max(MIN_FACTOR, SAFETY * err ** EXPONENT)
        factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** EXPONENT)
        return h * (min(1.0, factor) if rejected else factor)

    def dense(self, t: float, h: float, y: tuple, y1: tuple, K: tuple) -> tuple:
        """The interpolant's coefficients on the step (7 per component, :func:`poly`): three
        more evaluations of ``fun`` (SciPy's ``Dop853DenseOutput``)."""
        K = tuple([list(k) for k in K])
        for a, c in DENSE_STAGES:
            self._stage(t, y, K, h, a, c)
        out = []
        for Ki, u, v in zip(K, y, y1):
            dy = v - u
            out.append((dy, h * Ki[0] - dy, 2 * dy - h * (Ki[N_STAGES] + Ki[0]),
                        *(h * sum(map(mul, d, Ki)) for d in D)))
        return tuple(out)


class Dense:
    """The dense output of consecutive steps: ``sol(t) -> y`` (the steps' interpolants)."""

    def __init__(self):
        self.t: list[float] = []
        self.steps: list[tuple] = []

    def add(self, t: float, h: float, y: tuple, F: tuple) -> None:
        """The step ``[t, t + h]`` from ``y`` with interpolant ``F`` (:meth:`Dop853.dense`)."""
        self.t.append(t)
        self.steps.append((t, h, y, F))

    def __call__(self, t: float) -> tuple:
        t0, h, y, F = self.steps[max(bisect_right(self.t, t) - 1, 0)]
        x = (t - t0) / h
        return tuple(u + poly(f, x) for u, f in zip(y, F))
