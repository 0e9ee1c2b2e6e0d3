"""examples/ex07 (mesh convergence), ex08 (Fig. 13 sweep) and ex09 (rock against simulate) run
as scripts, and what they print agrees with independent values and with the pages that quote it."""
import pathlib
import re

import numpy as np
import pytest
from test_examples import is_png, run_script

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def test_ex07_convergence(tmp_path, monkeypatch, capsys):
    out, ns = run_script("ex07_convergence", tmp_path, monkeypatch, capsys, namespace=True)
    assert out.count("fembeam convergence: circular arch, embrace 157.5 deg, t/R = 0.15") == 2
    study, vous = ns["study"], ns["voussoirs"]
    A = np.array([row["A_L"] for row in study.rows])
    r = np.array([row["r"] for row in study.rows])
    # paper Sect. 6.2 (3 digits): A_L = 0.353 g on every mesh (hinges on the continuum), r = 0.606
    assert study.quantities["A_L"]["exact"] and np.ptp(A) < 1e-9 and A[0] == pytest.approx(0.353, abs=5e-4)
    assert r[-1] == pytest.approx(0.606, abs=1e-3)
    # rigid elements: the error of r falls like h^2; every refinement by 2 divides it by about 4
    assert 1.8 < ns["r_rate"] < 2.3
    steps = np.abs(np.diff(r))
    assert np.all(steps[1:] < steps[:-1] / 3)
    # a voussoir arch may hinge only at its joints: a subset of the continuous arch's mechanisms,
    # so its A_L is never below the continuous one, and it comes down to it as the joints multiply
    Av = np.array([row["A_L"] for row in vous.rows])
    assert np.all(Av >= A[0] - 1e-9) and np.all(np.diff(Av) < 0) and Av[-1] - A[0] < 1e-4
    assert is_png(tmp_path / "ex07.png") and is_png(tmp_path / "ex07_voussoirs.png")


def test_ex08_fig13_sweep(tmp_path, monkeypatch, capsys):
    out, ns = run_script("ex08_fig13_sweep", tmp_path, monkeypatch, capsys, namespace=True)
    res = ns["result"]
    assert out.startswith("fembeam sweep: 6 embrace angles x 21 thicknesses")
    env = {e["embrace_deg"]: e for e in res.envelope}
    # Milankovitch (1907): the semicircle's minimum thickness is t/R = 0.1075; thinner cannot stand
    assert env[180.0]["t_min_over_R"] == pytest.approx(0.1075, abs=1e-4)
    assert res.case(180.0, 0.10)["outcome"] == "cannot_stand" and res.case(180.0, 0.11)["outcome"] == "rocking"
    # paper Fig. 13: along each curve r_max falls as the arch thickens, and a deeper arch keeps more
    for beta in (120.0, 140.0, 160.0, 180.0):
        r = [c["r"] for c in sorted((c for c in res.cases if c["embrace_deg"] == beta), key=lambda c: c["t_over_R"])
             if c["outcome"] == "rocking"]
        assert len(r) >= 5 and np.all(np.diff(r) < 0), beta
    for t in (0.15, 0.2):
        r = [res.case(beta, t)["r"] for beta in (140.0, 160.0, 180.0)]
        assert np.all(np.diff(r) > 0), t
    assert is_png(tmp_path / "ex08.png")


def test_ex09_rock_vs_simulate(tmp_path, monkeypatch, capsys):
    out = run_script("ex09_rock_vs_simulate", tmp_path, monkeypatch, capsys)
    out = " ".join(out.split())    # the example's long lines go on over a second line
    rock = re.search(r"rock: thrust line exits at (\S+) s; peak piece rotation (\S+) rad at \S+ s; (\d+) impacts", out)
    sim = re.search(r"simulate \(dt = 1e-4 s\): peak rotation (\S+) rad at \S+ s; (\d+) impacts; "
                    r"up to (\d+) hinges", out)
    upto = re.search(r"up to the exit: at most (\d+) hinges; rotation differs from rock by (\S+) rad", out)
    # the rectangular pulse ends at 0.2 s and the thrust line leaves the section then
    assert float(rock[1]) == pytest.approx(0.2, abs=1e-3)
    # two integrators of different models, the same motion while one mechanism holds
    assert int(upto[1]) == 4 and float(upto[2]) < 1e-6
    assert int(sim[3]) > 4
    # the figures quoted in docs/simulate.md are the ones printed
    page = (DOCS / "simulate.md").read_text()
    quoted = re.search(r"peak rotation is (\S+) rad against `rock`'s (\S+) \(.*?\((\d+) impacts against (\d+)\)",
                       " ".join(page.split()))
    assert quoted.groups() == (sim[1], rock[2], sim[2], rock[3])
    assert f"to {float(upto[2]):.0e} rad".replace("e-0", "e-") in " ".join(page.split())
    assert is_png(tmp_path / "simulate_vs_rock.png")
