"""Ground motions: pulses against their closed forms, the shipped PEER and CSV records against
their published headers and peaks, scaling, and bad files."""
import numpy as np
import pytest

from fembeam.dynamics import RECORDS, GroundMotion
from fembeam.errors import InputError


def test_pulses_are_their_closed_forms():
    r = GroundMotion.rectangular(0.3, 0.5)
    assert r(0.0) == 0.3 and r(0.4999) == 0.3 and r(0.5) == 0.0 and r(0.7) == 0.0 and r(-0.1) == 0.0
    s = GroundMotion.sine(0.4, 0.8)
    t = np.linspace(0, 0.8, 1237)
    assert np.max(np.abs(s(t) - 0.4 * np.sin(2 * np.pi * t / 0.8))) < 1e-7 * 0.4
    assert s.pga == pytest.approx(0.4, rel=1e-9) and s.t_pga == pytest.approx(0.2, abs=1e-4)
    k = GroundMotion.ricker(0.5, 0.6)
    assert k(0.9) == pytest.approx(0.5, rel=1e-12) and k.pga == pytest.approx(0.5, rel=1e-12)
    u2 = (np.pi * (t - 0.9) / 0.6) ** 2
    assert np.max(np.abs(k(t) - 0.5 * (1 - 2 * u2) * np.exp(-u2))) < 1e-7
    assert abs(k.a[0]) < 1e-8 * 0.5 and abs(k.a[-1]) < 1e-8 * 0.5   # cut where it has died out


@pytest.mark.parametrize("name, npts, dt, first", [("elcentro", 5372, 0.01, 0.9984852e-3),
                                                   ("lomaprieta", 7997, 0.005, 0.1394908e-2)])
def test_peer_at2_records(name, npts, dt, first):
    g = GroundMotion.record(name)
    assert g.t.size == npts and g.t[1] - g.t[0] == pytest.approx(dt) and g.a[0] == pytest.approx(first)
    assert g.duration == pytest.approx((npts - 1) * dt)
    assert 0.05 < g.pga < 1.0   # a strong-motion record, in g


def test_chopra_el_centro_peak():
    """Chopra, Dynamics of Structures, App. 6: PGA 0.319 g at 2.04 s."""
    g = GroundMotion.record("elcentro_chopra")
    assert g.t.size == 1560 and g.pga == pytest.approx(0.319, abs=5e-4) and g.t_pga == pytest.approx(2.04, abs=1e-9)


def test_scaling():
    g = GroundMotion.record("elcentro_chopra")
    assert g.to_pga(0.5).pga == pytest.approx(0.5, rel=1e-12)
    assert np.allclose(g.scaled(2.0).a, 2.0 * g.a)


def test_every_shipped_record_reads():
    for name in RECORDS:
        assert GroundMotion.record(name).t.size > 1000


@pytest.mark.parametrize("text, words", [("PEER\nno header\n1 2 3\n", "NPTS"),
                                         ("a\nb\nc\nNPTS=  10, DT= .01 SEC\n1 2 3\n", "announces 10"),
                                         ("a\nb\nc\nNPTS=  2, DT= .01 SEC\n1 x\n", "not all numbers")])
def test_bad_at2_files_say_what_is_wrong(tmp_path, text, words):
    f = tmp_path / "bad.AT2"
    f.write_text(text)
    with pytest.raises(InputError, match=words):
        GroundMotion.record(f)


def test_bad_inputs():
    with pytest.raises(InputError, match="no ground-motion file"):
        GroundMotion.record("nowhere.csv")
    with pytest.raises(InputError, match="positive"):
        GroundMotion.sine(0.3, 0.0)
    with pytest.raises(InputError, match="increasing"):
        GroundMotion(np.array([0.0, 0.0]), np.array([1.0, 2.0]))


@pytest.mark.parametrize("argv, words", [
    (["rock", "--record", "elcentro", "--scale", "1e300"], "at most 100 g"),
    (["rock", "--record", "elcentro", "--pga", "1e5"], "at most 100 g"),
    (["rock", "--pulse", "ricker", "--amplitude", "1e9", "--period", "1"], "at most 100 g"),
    (["rock", "--pulse", "sine", "--amplitude", "1", "--period", "1e-300"], "[0.0001, 10000] s"),
    (["rock", "--pulse", "rect", "--amplitude", "1", "--duration", "1e300"], "[0.0001, 10000] s"),
    (["collapse-scale", "--record", "elcentro", "--factor-span", "1000"], "at most 100 g"),
    (["spectrum", "--pulse", "sine", "--periods", "1e-300", "--quiet"], "[0.0001, 10000] s"),
])
def test_ground_motions_out_of_range_exit_2(capsys, argv, words):
    """Accelerations beyond 100 g (a unit mistake) and pulse periods outside [1e-4, 1e4] s are
    refused before any run, with one line."""
    from fembeam.cli.main import main

    code = main(argv + ["--voussoirs", "7"])
    err = capsys.readouterr().err
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err
