"""``fembeam spectrum`` and ``fembeam collapse-scale`` on the multi-block simulation (``--model simulate``).

* a rocking block under rectangular pulses: rock and simulate follow the same Housner dynamics, so
  their overturning amplitudes agree (measured 7.1e-4 relative at dt = 2e-3, 3.6e-4 at 1e-3,
  -1.1e-4 at 5e-4, brackets of 1e-5; docs/studies.md);
* the journal: an interrupted simulate spectrum resumes to the rows of an uninterrupted run
  without recomputing the finished period; a rock journal (or one of another dt) is not read
  for simulate;
* local workers and Dask give the rows of one process, bit for bit;
* collapse-scale: the bracket's ends against direct runs of the Simulator;
* outputs (JSON, CSV, plot) name the model, dt, friction and what counts as collapse;
* bad input (``--dt 0``, ``--friction -1``, ``--dt`` or ``--friction`` with ``--model rock``): exit 2,
  one line.

Small cases only (a block, coarse dt, short runs): nothing here depends on the machine's speed.
"""
import csv
import functools
import json

import pytest

from fembeam import StraightMember
from fembeam.cli import main
from fembeam.dynamics.ground import GroundMotion
from fembeam.errors import InputError
from fembeam.simulation import Simulator
from fembeam.studies import models
from fembeam.studies import spectrum as sp
from fembeam.studies.parallel import Journal, journal_for
from fembeam.studies.collapse import collapse_scale
from fembeam.studies.spectrum import spectrum

BLOCK = StraightMember(height=2.0, width=0.5)        # tan alpha = 0.25: A_L = 0.25 g
ARGS = ["--block", "0.5", "2", "--pulse", "rect", "--periods", "0.3,0.5", "--amplitudes", "0.3,0.4,0.6",
        "--bisect-tol", "0.02", "--t-end-factor", "3", "--quiet"]
SMALL = dict(voussoirs=1, amplitudes=[0.3, 0.4, 0.6], bisect_tol=0.02, t_end_factor=3, progress=False)
DT = 4e-3


def strip(rows):
    return [{k: v for k, v in r.items() if k != "time_s"} for r in rows]


@pytest.fixture(scope="module")
def small():
    return spectrum(BLOCK, "rect", [0.3, 0.5], workers=1, model="simulate", dt=DT, **SMALL)


def test_block_rectangular_pulse_rock_and_simulate_agree():
    """Housner's block under a 0.5 s rectangular pulse: the same threshold (rock 0.339036 g) from
    both models.  Measured with brackets of 1e-5 and this t_end: simulate is above rock by 7.1e-4
    at dt = 2e-3 (1.4e-3 at 4e-3, 3.6e-4 at 1e-3: first order in dt); brackets of 1e-4 add at
    most 1e-4 each.  Asserted: 1.5e-3 (the 1 % asked of the study is met with a margin of 6)."""
    kw = dict(voussoirs=1, amplitudes=[0.33, 0.345], bisect_tol=1e-4, t_end_factor=10, workers=1, progress=False)
    rock = spectrum(BLOCK, "rect", [0.5], **kw).rows[0]
    sim = spectrum(BLOCK, "rect", [0.5], model="simulate", dt=2e-3, **kw).rows[0]
    assert rock["converged"] and sim["converged"] and sim["collapse"] == "overturned"
    assert rock["first_collapse"] == pytest.approx(0.339036, rel=5e-4)
    assert abs(sim["first_collapse"] / rock["first_collapse"] - 1) < 1.5e-3
    assert sim["steps"] > 0 and "steps" not in rock


def test_outcomes_are_the_simulators(small):
    """Every decided amplitude has the outcome of a direct run of the Simulator; below A_L nothing
    is run (no friction: the block cannot move)."""
    sim = Simulator(BLOCK, voussoirs=1)
    for row in small.rows:
        for step in row["scan"] + row["bisection"]:
            a = step["amplitude"]
            if step["outcome"] == "no_motion":
                assert a <= 0.25
                continue
            res = sim.run(GroundMotion.rectangular(a, row["period"]), dt=DT, t_end=row["t_end"], stop_at_overturn=True)
            assert res.outcome == step["outcome"], (row["period"], a)
        lo, hi = row["bracket"]
        assert row["first_collapse"] == hi and hi - lo <= 0.02 * hi and row["collapse"] == "overturned"
    assert small.model == "simulate" and small.settings["dt"] == DT and small.settings["friction"] is None


def test_workers_and_dask_give_the_same_rows(small, patient_dask):
    two = spectrum(BLOCK, "rect", [0.3, 0.5], workers=2, model="simulate", dt=DT, **SMALL)
    assert strip(two.rows) == strip(small.rows)
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None) as cl:
        dask = spectrum(BLOCK, "rect", [0.3, 0.5], scheduler=cl.scheduler_address, model="simulate", dt=DT, **SMALL)
    assert dask.settings["executor"] == "dask" and strip(dask.rows) == strip(small.rows)


def test_interrupted_simulate_spectrum_resumes(tmp_path, monkeypatch, capsys, small):
    """Ctrl-C during the second period: exit 130, the first period kept; the re-run computes
    only the second one and prints the rows of an uninterrupted run."""
    real, calls = sp.spectrum_case, []

    @functools.wraps(real)                 # the same module and name: the same journal keys
    def case(**kw):
        calls.append(kw["period"])
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(**kw)

    monkeypatch.setattr(sp, "spectrum_case", case)
    out = tmp_path / "s.csv"
    argv = ["spectrum", *ARGS, "--model", "simulate", "--dt", str(DT), "--workers", "1", "--json", "--csv", str(out)]
    assert main(argv) == 130
    journal = tmp_path / ".s.csv.spectrum-journal.jsonl"
    assert "1 of 2 cases kept in" in capsys.readouterr().err and len(Journal(journal).done) == 1
    calls.clear()
    assert main(argv) == 0
    assert calls == [0.5] and not journal.exists()
    d = json.loads(capsys.readouterr().out)
    assert strip(d["rows"]) == strip(small.to_dict()["rows"])


def test_a_rock_journal_is_not_read_for_simulate(tmp_path):
    j = journal_for(tmp_path / "s.csv", "spectrum")
    rock = spectrum(BLOCK, "rect", [0.5], workers=1, journal=j, **SMALL)
    assert len(Journal(j.path).done) == 1
    sim = spectrum(BLOCK, "rect", [0.5], workers=1, journal=Journal(j.path), model="simulate", dt=DT, **SMALL)
    other = spectrum(BLOCK, "rect", [0.5], workers=1, journal=Journal(j.path), model="simulate", dt=2 * DT, **SMALL)
    done = Journal(j.path).done
    # each run computed its own period: the keys are digests of the task, its model, dt and friction
    assert len(done) == 3
    assert "steps" not in rock.rows[0] and sim.rows[0]["steps"] > 0 and other.settings["dt"] == 2 * DT
    again = spectrum(BLOCK, "rect", [0.5], workers=1, journal=Journal(j.path), model="simulate", dt=DT, **SMALL)
    assert len(Journal(j.path).done) == 3 and strip(again.rows) == strip(sim.rows)     # read, not recomputed


def test_cli_spectrum_outputs_name_the_model(tmp_path, capsys):
    csv_path, png = tmp_path / "s.csv", tmp_path / "s.png"
    assert main(["spectrum", *ARGS, "--model", "simulate", "--dt", str(DT), "--workers", "1", "--json",
                 "--csv", str(csv_path), "--plot", str(png)]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["model"] == "simulate" and d["settings"]["dt"] == DT and d["settings"]["friction"] is None
    assert d["collapse_outcomes"] == ["overturned", "collapsed_by_sliding"] and d["timing_s"]["steps"] > 0
    assert [r["collapse"] for r in d["rows"]] == ["overturned", "overturned"]
    rows = list(csv.DictReader(csv_path.open()))
    assert [r["collapse"] for r in rows] == ["overturned", "overturned"] and int(rows[0]["steps"]) > 0
    assert png.stat().st_size > 0 and sorted(p.name for p in tmp_path.iterdir()) == ["s.csv", "s.png"]
    assert main(["spectrum", *ARGS, "--model", "simulate", "--dt", str(DT), "--workers", "1"]) == 0
    text = capsys.readouterr().out
    assert "model: simulate (rigid bodies in contact, dt = 0.004 s, joints never slide)" in text
    assert "time steps" in text
    assert main(["spectrum", *ARGS, "--workers", "1", "--json"]) == 0        # rock: the model named, no dt
    d = json.loads(capsys.readouterr().out)
    assert d["model"] == "rock" and "dt" not in d["settings"] and d["collapse_outcomes"] == ["overturned"]


def test_collapse_scale_simulate_against_direct_runs(capsys):
    rec, t_end = GroundMotion.record("elcentro_chopra"), 6.0
    res = collapse_scale(BLOCK, rec, voussoirs=1, resolution=0.05, t_end=t_end, model="simulate", dt=DT)
    lo, hi = res["bracket"]
    assert res["first_collapse"] == hi and res["smallest"] and hi / lo <= 1.05 * (1 + 1e-9)
    assert res["model"] == "simulate" and res["dt"] == DT and res["collapse"] == "overturned" and res["steps"] > 0
    sim = Simulator(BLOCK, voussoirs=1)
    assert sim.run(rec.scaled(hi), dt=DT, t_end=t_end).outcome == "overturned"
    assert sim.run(rec.scaled(lo), dt=DT, t_end=t_end).outcome in ("rest", "survived")
    json.dumps(res, allow_nan=False)
    assert main(["collapse-scale", "--block", "0.5", "2", "--record", "elcentro_chopra", "--resolution", "0.05",
                 "--t-end", str(t_end), "--model", "simulate", "--dt", str(DT), "--json", "--quiet"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["bracket"] == res["bracket"] and d["model"] == "simulate" and d["friction"] is None


def test_friction_reaches_the_simulator(monkeypatch):
    """``friction`` is handed to the Simulator (a stand-in here, whatever the stepper offers) and
    the multi-block model runs every amplitude, A_L or not: a joint may slide below it."""
    made = []

    class Fake:
        def __init__(self, curve, *, voussoirs=None, elements=None, friction=None):
            made.append((voussoirs, elements, friction))

        def run(self, ground, *, dt, t_end, stop_at_overturn):
            class R:
                outcome = "collapsed_by_sliding" if max(abs(ground.a)) > 0.2 else "rest"
                steps = 1
            return R

    import fembeam.simulation as simulation
    monkeypatch.setattr(simulation, "Simulator", Fake)
    monkeypatch.setattr(models, "check_friction", lambda mu, name: float(mu))
    monkeypatch.setattr(models._SIMULATORS, "kept", None, raising=False)
    res = spectrum(BLOCK, "rect", [0.5], voussoirs=1, amplitudes=[0.1, 0.15, 0.3], bisect_tol=0.05, workers=1,
                   progress=False, model="simulate", dt=DT, friction=0.4)
    row = res.rows[0]
    assert made == [(1, None, 0.4)]                         # built once for all the runs of the period
    assert [s["outcome"] for s in row["scan"]] == ["rest", "rest", "collapsed_by_sliding"]     # 0.1, 0.15 g < A_L run
    assert row["collapse"] == "collapsed_by_sliding" and 0.2 <= row["first_collapse"] <= 0.21
    assert res.settings["friction"] == 0.4 and res.to_dict()["settings"]["friction"] == 0.4
    from fembeam.cli.spectrum import table
    assert "collapses by sliding" in table(res) and "friction mu = 0.4" in table(res)


def test_block_sliding_threshold_with_friction():
    """A block on a base with mu = 0.1 < tan alpha slides instead of rocking; a rectangular pulse
    of a > mu (g) for T1 slides it by s = (a - mu) g T1^2 / 2 * a / mu (pushed, then braked at
    mu g), i.e. a (a - mu) = 2 mu s / (g T1^2).  While it slides, the resultant of the base's
    normal force is mu h / 2 = 0.1 m ahead of its centroid, so it starts to tip about the base's
    edge at a slip of w / 2 - mu h / 2 = 0.15 m (a = 0.17138 g); once it stops with its centroid
    beyond the edge, s > w / 2 = 0.25 m (a = 0.20129 g), it falls.  The collapse threshold is
    between the two (measured 0.19644 g, slip 0.232 m, then it tips off the edge: collapsed by
    sliding).  It was 0.201286 g, the half-depth rule on a face line without end (the block then
    slid on over air).  Below A_L (0.25 g) the amplitudes are run."""
    if not models.simulator_has_friction():
        pytest.skip("this Simulator has no Coulomb friction")
    mu, t1, g, w, h = 0.1, 0.5, 9.81, 0.5, 2.0

    def amplitude(slip):
        return 0.5 * (mu + (mu * mu + 4 * 2 * slip * mu / (g * t1 * t1)) ** 0.5)

    res = spectrum(BLOCK, "rect", [t1], voussoirs=1, amplitudes=[0.05, 0.15, 0.3, 0.5], bisect_tol=1e-3,
                   t_end_factor=3, workers=1, progress=False, model="simulate", dt=2e-3, friction=mu)
    row = res.rows[0]
    assert [s["outcome"] for s in row["scan"]] == ["rest", "rest", "collapsed_by_sliding", "collapsed_by_sliding"]
    assert row["collapse"] == "collapsed_by_sliding" and res.settings["friction"] == mu
    assert amplitude(w / 2 - mu * h / 2) < row["first_collapse"] < amplitude(w / 2)


@pytest.mark.parametrize("argv", [
    ["spectrum", *ARGS, "--model", "simulate", "--dt", "0"],
    ["spectrum", *ARGS, "--model", "simulate", "--dt", "0.1"],
    ["spectrum", *ARGS, "--model", "simulate", "--dt", "nan"],
    ["spectrum", *ARGS, "--model", "simulate", "--dt", "1e-6", "--t-end-factor", "1000"],      # > 1e7 steps
    ["spectrum", *ARGS, "--model", "simulate", "--friction", "-1"],
    ["spectrum", *ARGS, "--model", "simulate", "--friction", "nan"],
    ["spectrum", *ARGS, "--dt", "1e-3"],
    ["spectrum", *ARGS, "--model", "rock", "--friction", "0.5"],
    ["spectrum", *ARGS, "--model", "verlet"],
    ["collapse-scale", "--record", "elcentro", "--model", "simulate", "--dt", "0"],
    ["collapse-scale", "--record", "elcentro", "--model", "simulate", "--friction", "-1"],
    ["collapse-scale", "--record", "elcentro", "--dt", "1e-3"],
    ["collapse-scale", "--record", "elcentro", "--model", "simulate", "--dt", "1e-6", "--t-end", "100"],
])
def test_cli_bad_input_exits_2_with_one_line(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as e:      # argparse's own errors
        code = e.code
    assert code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "error" in err


def test_api_refuses_simulate_options_for_rock():
    from fembeam.errors import InputError
    with pytest.raises(InputError, match="dt applies to the multi-block simulation only"):
        spectrum(BLOCK, "rect", [0.5], voussoirs=1, dt=1e-3, progress=False)
    with pytest.raises(InputError, match="friction"):
        collapse_scale(BLOCK, GroundMotion.record("elcentro"), voussoirs=1, friction=0.5)
    with pytest.raises(InputError, match="dt must be in"):
        spectrum(BLOCK, "rect", [0.5], voussoirs=1, model="simulate", dt=0.0, progress=False)


def test_a_singular_system_is_a_recorded_error(monkeypatch, small):
    """A singular dense system met inside the compiled stepper (numba raises numpy's LinAlgError,
    forced here on the first run of the study) is a SolverError with the problem attached (the
    step's time and state); the study records it as an error of that run and goes on: the other
    period's row is that of an undisturbed study (it aborted the study: the hooks catch
    SolverError only)."""
    import numpy as np

    import fembeam.simulation.stepper as stepper
    from fembeam.errors import SolverError
    K = stepper.compiled_kernel()
    real, calls = K.advance, []

    def advance(*args):
        calls.append(1)
        if len(calls) == 1:
            np.linalg.solve(np.zeros((3, 3)), np.ones(3))
        return real(*args)

    monkeypatch.setattr(K, "advance", advance)
    with pytest.raises(SolverError, match="singular") as e:
        Simulator(BLOCK, voussoirs=1).run(GroundMotion.rectangular(0.5, 0.3), dt=DT, t_end=0.5)
    assert e.value.problem["t"] == 0.0 and e.value.problem["q"].shape == (2, 3)
    calls.clear()
    res = spectrum(BLOCK, "rect", [0.3, 0.5], workers=1, model="simulate", dt=DT, **SMALL)
    first, second = res.rows
    assert len(first["errors"]) == 1 and "singular" in first["errors"][0]["error"]
    assert strip([second]) == strip([small.rows[1]])


def test_collapse_scale_auto_is_simulates_on_a_record_with_hand_backs():
    """El Centro's first 4 s on a 7-voussoir arch: ``auto`` hands the motion back to ``rock`` (at
    rest at factor 2, on a mechanism at 6) and still decides every factor of the search as
    ``simulate`` does, so both find the same first collapse (3.3116 measured) with the same
    bracket.  The deprecated keys hold the same values as the new ones."""
    from fembeam import CircularArch
    from fembeam.auto import AutoModel
    import numpy as np
    arch = CircularArch.from_ratio(157.5, 0.15, radius=5.0)
    rec = GroundMotion.record("elcentro")
    n = int(np.searchsorted(rec.t, 4.0))
    excerpt = GroundMotion(rec.t[:n], rec.a[:n], name="elcentro, first 4 s")
    ends = {f: [s.end for s in AutoModel(arch, voussoirs=7, dt=2e-3).run(excerpt.scaled(f), t_end=5.0).segments]
            for f in (2.0, 6.0)}
    assert "rest" in ends[2.0][1:] and "mechanism" in ends[6.0][1:], ends
    kw = dict(voussoirs=7, dt=2e-3, resolution=0.05, t_end=5.0, span=8)
    auto = collapse_scale(arch, excerpt, model="auto", **kw)
    sim = collapse_scale(arch, excerpt, model="simulate", **kw)
    assert [(s["factor"], s["outcome"]) for s in auto["scan"]] == [(s["factor"], s["outcome"]) for s in sim["scan"]]
    assert auto["first_collapse"] == sim["first_collapse"] and auto["bracket"] == sim["bracket"]
    assert auto["smallest"] and auto["collapse"] == "overturned" and 3.2 < auto["first_collapse"] < 3.4
    assert auto["first_overturning"] == auto["first_collapse"]
    assert auto["pga_at_first_overturning"] == auto["pga_at_first_collapse"] == auto["first_collapse"] * excerpt.pga


def test_unlimited_friction_is_spelled_inf():
    """``friction=math.inf`` is unlimited friction, as None: the model check gives None for both,
    and a finite coefficient is kept."""
    import math
    assert models.check_model("simulate", 1e-3, math.inf) == models.check_model("simulate", 1e-3, None) == (1e-3, None)
    assert models.unlimited_friction(math.inf) and models.unlimited_friction(None)
    assert not models.unlimited_friction(0.5)
    with pytest.raises(InputError):
        models.check_model("simulate", 1e-3, -1.0)
