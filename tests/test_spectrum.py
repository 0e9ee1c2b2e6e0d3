"""Overturning spectra and collapse scale factors against closed forms and direct runs.

* Housner's slender block under rectangular pulses: the bisected overturning amplitude matches
  ``a/(g alpha) = 1/(1 - exp(-p t1))`` to the O(alpha^2) nonlinear deviation (1.4e-4 at alpha = 0.02);
* the spectrum (parallel tasks, the block's energy shortcut) gives the bracket of an independent
  scan-and-bisect written with plain :meth:`Rocker.run`, float for float;
* safe regions above the first overturning amplitude: a stocky block (tan alpha = 0.5) under a
  one-sine pulse of 0.68 s overturns at 3.1 A_L and survives 3.5, 3.6, 4.0 and 4.5 A_L (found by
  scanning; Housner's equation integrated independently gives the same, and with the former
  overturning rule, at the unstable equilibrium, 4.0 and 4.5 A_L overturn);
* collapse-scale (hunt and fill) on a shipped record: the bracket's ends and the safe factors
  above it against direct runs;
* JSON without NaN, CLI errors as one line with exit 2, CSV written atomically.
"""
import csv
import json
import math

import pytest

from fembeam import CircularArch, StraightMember
from fembeam.cli import main
from fembeam.dynamics.equation import GRAVITY
from fembeam.dynamics.ground import GroundMotion
from fembeam.dynamics.rocking import Rocker
from fembeam.studies.collapse import collapse_scale
from fembeam.studies.spectrum import geometric_grid, overturning_amplitude, spectrum

STOCKY = StraightMember(height=2.0, width=1.0)      # tan alpha = 0.5, Housner r = 0.49
ISLAND_T = 0.68                                     # one-sine period with a safe window above
T_REC = 10.0                                        # s: the strong part of the El Centro record
ISLAND_GRID = [r * 0.5 for r in (2.0, 2.5, 2.9, 3.1, 3.5, 3.6, 4.0, 4.5)]


def overturns(rk, ground, **kw) -> bool:
    return rk.run(ground, thrust_check=False, **kw).outcome == "overturned"


@pytest.mark.parametrize("p_t1", [0.5, 2.0])
def test_housner_rectangular_pulse(p_t1):
    width = 0.04
    alpha, R = math.atan(width / 2.0), 0.5 * math.hypot(width, 2.0)
    p = math.sqrt(3 * GRAVITY / (4 * R))
    t1 = p_t1 / p
    formula = alpha / (1 - math.exp(-p * t1))
    rk = Rocker(StraightMember(height=2.0, width=width), voussoirs=1, qp=False)
    res = overturning_amplitude(rk, lambda a: GroundMotion.rectangular(a, t1), geometric_grid(rk.A[1], 10.0, 40),
                                bisect_tol=1e-6)
    lo, hi = res["bracket"]
    assert res["converged"] and hi - lo <= 1e-6 * hi and res["first_collapse"] == hi
    dev = hi / formula - 1
    assert 5e-5 < dev < 3e-4                     # the nonlinear O(alpha^2) excess, ~1.4e-4
    assert not res["safe_above"] and res["runs"] < 70
    assert res["scan"][0]["outcome"] == "no_motion"          # the onset itself is not run
    # the ends of the bracket with full runs (no shortcut), long enough to decide
    t_end = t1 + 30 / p
    assert overturns(rk, GroundMotion.rectangular(hi, t1), t_end=t_end)
    assert not overturns(rk, GroundMotion.rectangular(lo, t1), t_end=t_end)


def independent_bracket(curve, period, grid, voussoirs, tol):
    """Scan-and-bisect with plain Rocker.run (default t_end: pulse end + 20 sqrt(L/g))."""
    rk = Rocker(curve, voussoirs=voussoirs, qp=False)
    over = [overturns(rk, GroundMotion.sine(a, period)) for a in grid]
    if True not in over:
        return None, []
    i = over.index(True)
    lo, hi = max([a for a, o in zip(grid[:i], over[:i]) if not o], default=min(rk.A.values())), grid[i]
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if overturns(rk, GroundMotion.sine(mid, period)) else (mid, hi)
    return [lo, hi], [a for a, o in zip(grid[i + 1:], over[i + 1:]) if not o]


@pytest.fixture(scope="module")
def island():
    return spectrum(STOCKY, "sine", [ISLAND_T, 1.0], voussoirs=1, amplitudes=ISLAND_GRID, workers=2, progress=False,
                    bisect_tol=1e-3)


def test_spectrum_equals_independent_bisection(island):
    for row in island.rows:
        bracket, above = independent_bracket(STOCKY, row["period"], ISLAND_GRID, 1, 1e-3)
        assert row["bracket"] == bracket and row["first_collapse"] == bracket[1]
        assert row["safe_amplitudes_above"] == above
    assert island.rows[1]["first_collapse"] < island.rows[0]["first_collapse"]


def housner_sine_overturns(A, period, width, height, angle, t_end):
    """Housner's block under one sine pulse ``a_g = A sin(2 pi t / T)`` (g) by an independent
    route: ``theta'' = p^2 (-a_g cos(alpha - |theta|) - sgn sin(alpha - |theta|))`` about the corner
    of sign ``sgn``, ``p^2 = 3 g / (4 R)``, from the onset ``|a_g| = tan alpha``; at each impact the
    rate times ``1 - 1.5 sin^2 alpha`` about the other corner; at rest when the kinetic energy
    left after an impact past the pulse is below 1e-12 of the barrier.  True when ``|theta|``
    reaches ``angle`` before ``t_end``."""
    from scipy.integrate import solve_ivp

    alpha, R = math.atan(width / height), 0.5 * math.hypot(width, height)
    p2, rv = 3 * GRAVITY / (4 * R), 1 - 1.5 * math.sin(alpha) ** 2
    if abs(A) <= math.tan(alpha):
        return False
    sgn = -1.0 if A > 0 else 1.0                 # the inertia load -a_g tips the block towards -x first

    def f(t, y):
        a = A * math.sin(2 * math.pi * t / period) if t <= period else 0.0
        return [y[1], p2 * (-a * math.cos(alpha - sgn * y[0]) - sgn * math.sin(alpha - sgn * y[0]))]

    def out(t, y):
        return abs(y[0]) - angle

    def impact(t, y):
        return sgn * y[0]
    out.terminal, out.direction, impact.terminal, impact.direction = True, 1, True, -1
    t, y = period / (2 * math.pi) * math.asin(math.tan(alpha) / abs(A)), [0.0, 0.0]
    while t < t_end:
        tb = period if t < period else t_end
        sol = solve_ivp(f, (t, tb), y, events=(out, impact), method="DOP853", rtol=1e-12, atol=1e-14)
        if sol.t_events[0].size:
            return True
        if sol.t_events[1].size:
            t, w = sol.t_events[1][0], rv * sol.y_events[1][0][1]
            if t > period and 0.5 * w * w < 1e-12 * p2 * (1 - math.cos(alpha)):
                return False
            sgn, y = -sgn, [0.0, w]
        else:
            t, y = tb, sol.y[:, -1]
    return False


def test_safe_region_above_the_first_overturning_amplitude(island):
    """The scan's outcomes against Housner's equation integrated independently (the overturning
    rule: the centroid 0.1 w below its height at rest, ``R cos(theta - alpha) = h/2 - 0.1 w``);
    with the former rule (``|theta|`` reaches ``alpha``) 4.0 and 4.5 A_L would overturn: the end
    of the pulse pushes the block back after it has passed its unstable equilibrium."""
    row = island.rows[0]
    assert row["period"] == ISLAND_T
    assert 2.9 * 0.5 <= row["first_collapse"] <= 3.1 * 0.5
    w, h = STOCKY.width, STOCKY.height
    alpha, R = math.atan(w / h), 0.5 * math.hypot(w, h)
    t_end = ISLAND_T + 20 * math.sqrt(h / GRAVITY)                      # the spectrum's default
    level = alpha + math.acos((h / 2 - 0.1 * w) / R)
    ref = {a: housner_sine_overturns(a, ISLAND_T, w, h, level, t_end) for a in ISLAND_GRID}
    former = {a: housner_sine_overturns(a, ISLAND_T, w, h, alpha, t_end) for a in ISLAND_GRID}
    assert [a for a in ISLAND_GRID if a > row["first_collapse"] and not ref[a]] == row["safe_amplitudes_above"]
    assert row["safe_above"] and row["safe_amplitudes_above"] == [3.5 * 0.5, 3.6 * 0.5, 4.0 * 0.5, 4.5 * 0.5]
    assert [a for a in ISLAND_GRID if a > row["first_collapse"] and not former[a]] == [3.5 * 0.5, 3.6 * 0.5]
    rk = Rocker(STOCKY, voussoirs=1, qp=False)
    outcome = {a: overturns(rk, GroundMotion.sine(a, ISLAND_T)) for a in ISLAND_GRID}
    assert outcome == ref
    assert outcome[3.1 * 0.5] and not outcome[4.0 * 0.5] and not outcome[2.9 * 0.5]
    # at 1 s too, one amplitude is pushed back past the unstable equilibrium (none by the former rule)
    row1, t_end1 = island.rows[1], 1.0 + 20 * math.sqrt(h / GRAVITY)
    above = [a for a in ISLAND_GRID if a > row1["first_collapse"]]
    assert row1["safe_amplitudes_above"] == [a for a in above
                                             if not housner_sine_overturns(a, 1.0, w, h, level, t_end1)]
    assert row1["safe_amplitudes_above"] == [2.9 * 0.5]
    assert all(housner_sine_overturns(a, 1.0, w, h, alpha, t_end1) for a in above)
    d = island.to_dict()
    json.dumps(d, allow_nan=False)
    assert d["rows"][0]["safe_above"] is True and d["onset_g"] == pytest.approx(0.5)


def test_arch_spectrum_equals_independent_bisection():
    arch = CircularArch.from_ratio(157.5, 0.15)
    grid = [0.5, 0.6, 0.8, 1.0]
    res = spectrum(arch, "sine", [0.8], voussoirs=7, amplitudes=grid, workers=1, progress=False, bisect_tol=1e-2)
    bracket, above = independent_bracket(arch, 0.8, grid, 7, 1e-2)
    assert res.rows[0]["bracket"] == bracket and res.rows[0]["safe_amplitudes_above"] == above


def test_collapse_scale_against_direct_runs():
    block, rec = StraightMember(height=2.0, width=0.5), GroundMotion.record("elcentro_chopra")
    res = collapse_scale(block, rec, voussoirs=1, resolution=0.02, t_end=T_REC)
    f = res["first_collapse"]
    lo, hi = res["bracket"]
    assert f == hi and res["smallest"] and hi / lo <= 1.02 * (1 + 1e-9) and res["resolution_reached"] <= 0.02
    assert res["pga_at_first_collapse"] == pytest.approx(f * rec.pga)
    assert res["onset_factor"] == pytest.approx(0.25 / rec.pga)
    rk = Rocker(block, voussoirs=1, qp=False)
    assert overturns(rk, rec.scaled(hi), t_end=T_REC) and not overturns(rk, rec.scaled(lo), t_end=T_REC)
    assert all(not overturns(rk, rec.scaled(x), t_end=T_REC) for x in res["safe_factors_above"])
    json.dumps(res, allow_nan=False)


def test_cli_spectrum_json_csv_and_no_overturning(tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert main(["spectrum", "--block", "0.5", "2", "--pulse", "rect", "--periods", "0.05,0.5",
                 "--amplitudes", "0.3,0.5,1.0", "--bisect-tol", "0.01", "--workers", "1", "--json", "--quiet",
                 "--csv", str(out)]) == 0
    d = json.loads(capsys.readouterr().out)
    json.dumps(d, allow_nan=False)
    first = [r["first_collapse"] for r in d["rows"]]
    assert first[0] is None and d["rows"][0]["bracket"] == [1.0, None]      # too short a pulse: no overturning
    assert 0.3 < first[1] <= 0.5
    rows = list(csv.DictReader(out.open()))
    assert [r["period_s"] for r in rows] == ["0.05", "0.5"] and rows[0]["first_overturning_g"] == ""
    assert [p.name for p in tmp_path.iterdir()] == ["s.csv"]                  # no temporary left


def test_csv_is_written_atomically(tmp_path, monkeypatch, capsys):
    out = tmp_path / "s.csv"
    out.write_text("old\n")

    def fail(*a, **k):
        raise KeyboardInterrupt
    monkeypatch.setattr(csv.DictWriter, "writerows", fail)
    assert main(["spectrum", "--block", "0.5", "2", "--pulse", "rect", "--periods", "0.5", "--amplitudes", "0.3",
                 "--workers", "1", "--quiet", "--csv", str(out)]) == 130
    # no temporary file left; the journal keeps the finished period for a re-run
    assert out.read_text() == "old\n" and sorted(p.name for p in tmp_path.iterdir()) == [".s.csv.spectrum-journal.jsonl",
                                                                                         "s.csv"]


@pytest.mark.parametrize("argv", [
    ["spectrum", "--pulse", "sine", "--periods", "0,1"],
    ["spectrum", "--pulse", "sine", "--periods", ","],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--amplitudes", "0.5,0.4"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--amplitudes", "-0.5"],
    ["spectrum", "--pulse", "sine", "--periods", "0.01:100:0.001"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--bisect-tol", "0"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--t-end-factor", "-1"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--workers", "0"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--csv", "out.txt"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--plot", "/no/such/dir/s.png"],
    ["spectrum", "--pulse", "sine", "--periods", "1", "--voussoirs", "0"],
    ["spectrum", "--pulse", "square", "--periods", "1"],
    ["spectrum", "--pulse", "sine", "--periods", "nan"],
    ["collapse-scale", "--record", "no_such_record"],
    ["collapse-scale", "--record", "elcentro", "--resolution", "0"],
    ["collapse-scale", "--record", "elcentro", "--t-end", "-1"],
    ["collapse-scale", "--record", "elcentro", "--max-runs", "0"],
    ["collapse-scale", "--record", "elcentro", "--factor-span", "1"],
    ["collapse-scale", "--record", "elcentro", "--model", "verlet"],
])
def test_cli_bad_input_exits_2_with_one_line(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as e:      # argparse's own errors (bad choice, not a number)
        code = e.code
    assert code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "error" in err


def test_cli_collapse_scale_json(capsys):
    assert main(["collapse-scale", "--block", "0.5", "2", "--record", "elcentro_chopra", "--resolution", "0.05",
                 "--t-end", "10", "--json", "--quiet"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["command"] == "collapse-scale" and d["first_collapse"] is not None
    assert d["bracket"][1] == d["first_collapse"] and isinstance(d["smallest"], bool)
    assert d["scan"][0].keys() == {"factor", "outcome", "peak_rotation", "steps", "order"}
    assert d["runs"] == len(d["scan"]) and "converged" not in d and d["smallest"] in (True, False)
    assert main(["collapse-scale", "--block", "0.5", "2", "--record", "elcentro_chopra", "--resolution", "0.05",
                 "--t-end", "10", "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "hunt and fill: resolution 0.05" in text and "the smallest at resolution 0.05" in text


def test_free_decay_shortcut_against_full_runs():
    """Amplitudes decided at the end of the pulse by the free decay (``below_barrier``:
    Rocker.settles) do not overturn in full runs, and the others get the full run's outcome."""
    rk = Rocker(CircularArch.from_ratio(157.5, 0.15), voussoirs=7, qp=False)
    res = overturning_amplitude(rk, lambda a: GroundMotion.sine(a, 0.45), geometric_grid(rk.A[1], 3.0, 8),
                                bisect_tol=1e-2)
    steps = [s for s in res["scan"] + res["bisection"] if s["outcome"] != "no_motion"]
    assert {"below_barrier", "overturned"} <= {s["outcome"] for s in steps}
    for s in steps:
        full = rk.run(GroundMotion.sine(s["amplitude"], 0.45), thrust_check=False).outcome
        assert full == s["outcome"] or (s["outcome"] == "below_barrier" and full in ("rest", "survived"))
