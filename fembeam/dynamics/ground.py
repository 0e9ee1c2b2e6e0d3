"""Horizontal ground accelerations ``a_g(t)`` in units of g: pulses and recorded accelerograms.

A :class:`GroundMotion` is a sampled signal (times in s, accelerations in g, zero outside the
samples) with linear interpolation between samples.  Pulses are sampled finely enough that the
interpolation error is below 1e-10 of the amplitude for the smooth ones (sine, Ricker); the
rectangular pulse is exact with a jump at its ends.  Records come from PEER NGA ``.AT2`` files
or two-column CSV (time, acceleration in g); they can be scaled by a factor or to a peak.
"""
from __future__ import annotations

import io
import itertools
import math
import re
from bisect import bisect_right
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..readers import read_text

__all__ = ["GroundMotion", "Pulse", "RECORDS", "check_record", "MAX_RECORD_SAMPLES", "MAX_RECORD_DURATION",
           "RECORD_DT_RANGE", "PERIOD_RANGE", "PLAUSIBLE_PGA", "unit_note"]

RECORDS = {   # records shipped with fembeam (fembeam/data/ground_motions/README.md)
    "elcentro": "RSN6_IMPVALL.I_I-ELC180.AT2",
    "lomaprieta": "RSN753_LOMAP_CLS000.AT2",
    "elcentro_chopra": "elcentro_1940_ns_chopra.csv",
}
MAX_RECORD_SAMPLES = 1_000_000   # samples of a record (PEER records have up to ~10^5)
MAX_RECORD_DURATION = 1e4         # s: the longest record, and the latest start of a CSV record
RECORD_DT_RANGE = (1e-5, 1.0)     # s: the time step of a record (PEER: 0.001 to 0.02 s)
MAX_RECORD_BYTES = 24 * 2 ** 20   # 24 MiB: 10^6 samples of an AT2 file take ~16 MB
MAX_PGA = 100.0           # g: a ground acceleration above it is a unit mistake, not an earthquake
PLAUSIBLE_PGA = 2.5       # g: above the largest horizontal peaks recorded (about 2-3 g): a note


def unit_note(ground: "GroundMotion") -> str | None:
    """A note when the peak of a record exceeds :data:`PLAUSIBLE_PGA` (values in m/s^2 rather
    than g are the usual cause), else None.  Such a record is run as given."""
    if ground.pga > PLAUSIBLE_PGA:
        return (f"{ground.name}: peak ground acceleration {ground.pga:.4g} g, above {PLAUSIBLE_PGA:g} g (about the "
                f"largest recorded); fembeam reads records in g: if its values are m/s^2, divide them by 9.81")
    return None


def _positive(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    return v


PERIOD_RANGE = (1e-4, 1e4)   # s: pulse periods and durations admitted


def _period(name: str, value) -> float:
    v = _positive(name, value)
    lo, hi = PERIOD_RANGE
    if not lo <= v <= hi:
        raise InputError(f"{name} must be in [{lo:g}, {hi:g}] s, got {value!r}")
    return v


@dataclass(frozen=True)
class Pulse:
    """The exact formula of a pulse (``kind``: ``"rect"``, ``"sine"``, ``"ricker"``), in g;
    zero outside ``[0, end]``.  ``period`` is the duration of a rectangular pulse."""

    kind: str
    amplitude: float
    period: float

    @property
    def end(self) -> float:
        return 3.0 * self.period if self.kind == "ricker" else self.period

    def at(self, time: float) -> float:
        """``a_g`` at one time (plain floats: the integrator's hot path)."""
        if time < 0.0 or time > self.end or (self.kind == "rect" and time >= self.period):
            return 0.0
        if self.kind == "rect":
            return self.amplitude
        if self.kind == "sine":
            return self.amplitude * math.sin(2.0 * math.pi * time / self.period)
        u2 = (math.pi * (time - 1.5 * self.period) / self.period) ** 2
        return self.amplitude * (1.0 - 2.0 * u2) * math.exp(-u2)

    def scaled(self, factor: float) -> "Pulse":
        return Pulse(self.kind, self.amplitude * factor, self.period)


@dataclass(frozen=True)
class GroundMotion:
    """A ground acceleration ``a_g(t)``, linear between samples.

    Parameters
    ----------
    t : array_like
        Times (s), strictly increasing.
    a : array_like
        Ground accelerations (g), positive along ``+x`` (the inertia load on the member
        is ``-a_g``).
    name : str, optional
        Name for the reports.
    smooth : bool, optional
        The signal is smooth between its first and last samples (a pulse sampled
        finely, or a rectangular pulse whose only jumps are at its ends), so an
        integrator may step across samples; otherwise (records) every sample is a kink
        and steps stay within one sample interval.
    exact : Pulse, optional
        The formula of a pulse, evaluated by the integrator instead of the samples
        (which then serve the onset scan and the plots).

    Raises
    ------
    InputError
        Fewer than two samples, times not increasing, or a peak above ``MAX_PGA`` (g).

    See Also
    --------
    GroundMotion.sine, GroundMotion.ricker, GroundMotion.rectangular,
    GroundMotion.record

    Examples
    --------
    >>> from fembeam.dynamics import GroundMotion
    >>> pulse = GroundMotion.sine(0.4, 0.5)
    >>> print(f"{pulse.duration:.2f} s, PGA {pulse.pga:.2f} g, a = {pulse(0.125):.4f} g")
    0.50 s, PGA 0.40 g, a = 0.4000 g
    >>> triangle = GroundMotion([0.0, 0.1, 0.2], [0.0, 0.3, 0.0], name="triangle")
    >>> print(f"{triangle(0.05):.4f} g")
    0.1500 g
    """

    t: np.ndarray
    a: np.ndarray
    name: str = "ground motion"
    smooth: bool = False
    exact: Pulse | None = None

    def __post_init__(self):
        t, a = np.asarray(self.t, float), np.asarray(self.a, float)
        if t.ndim != 1 or t.shape != a.shape or t.size < 2:
            raise InputError("a ground motion needs at least two samples of time and acceleration")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(a))):
            raise InputError(f"{self.name}: times and accelerations must be finite numbers")
        if np.any(np.diff(t) <= 0):
            raise InputError(f"{self.name}: times must be strictly increasing")
        if np.max(np.abs(a)) > MAX_PGA:
            raise InputError(f"{self.name}: peak ground acceleration {np.max(np.abs(a)):.4g} g; at most {MAX_PGA:g} g "
                             "is admitted (accelerations are in g)")
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "a", a)

    # -- values -----------------------------------------------------------------------------
    def __call__(self, time) -> np.ndarray:
        """``a_g`` (g) at ``time`` (s): linear between samples, zero outside them."""
        return np.interp(time, self.t, self.a, left=0.0, right=0.0)

    def scalar(self):
        """A fast scalar ``a_g(time)`` for integrators: the pulse's formula, or the same
        piecewise-linear signal."""
        if self.exact is not None:
            return self.exact.at
        ts, av = self.t.tolist(), self.a.tolist()
        n, t0, t1 = len(ts), ts[0], ts[-1]

        def at(time: float) -> float:
            if time < t0 or time > t1:
                return 0.0
            i = min(bisect_right(ts, time), n - 1)
            ta, tb = ts[i - 1], ts[i]
            return av[i - 1] + (av[i] - av[i - 1]) * (time - ta) / (tb - ta)
        return at

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    @property
    def pga(self) -> float:
        """Peak ground acceleration (g), the largest ``|a|``."""
        return float(np.max(np.abs(self.a)))

    @property
    def t_pga(self) -> float:
        return float(self.t[int(np.argmax(np.abs(self.a)))])

    def scaled(self, factor: float) -> "GroundMotion":
        f = float(factor)
        if not math.isfinite(f):
            raise InputError(f"the scale factor must be a finite number, got {factor!r}")
        return GroundMotion(self.t, f * self.a, f"{self.name} x {f:g}", self.smooth,
                            None if self.exact is None else self.exact.scaled(f))

    def to_pga(self, target: float) -> "GroundMotion":
        """Scaled so that its peak ground acceleration is ``target`` (g)."""
        target = _positive("the target peak acceleration", target)
        if self.pga == 0:
            raise InputError(f"{self.name} is zero everywhere: it cannot be scaled to a peak")
        f = target / self.pga
        return GroundMotion(self.t, self.a * f, f"{self.name} to PGA {target:g} g", self.smooth,
                            None if self.exact is None else self.exact.scaled(f))

    # -- pulses -----------------------------------------------------------------------------
    @classmethod
    def rectangular(cls, amplitude: float, duration: float) -> "GroundMotion":
        """``a_g = amplitude`` on ``[0, duration)``, zero after (a jump at both ends)."""
        amplitude, duration = float(amplitude), _period("the pulse duration", duration)
        eps = 1e-12 * duration
        t = np.array([0.0, duration - eps, duration])
        return cls(t, np.array([amplitude, amplitude, 0.0]), f"rectangular pulse {amplitude:g} g, {duration:g} s",
                   True, Pulse("rect", amplitude, duration))

    @classmethod
    def sine(cls, amplitude: float, period: float, samples: int = 20001) -> "GroundMotion":
        """One period of ``amplitude sin(2 pi t / period)``."""
        period = _period("the pulse period", period)
        t = np.linspace(0.0, period, samples)
        return cls(t, float(amplitude) * np.sin(2 * np.pi * t / period), f"one-sine pulse {amplitude:g} g, {period:g} s",
                   True, Pulse("sine", float(amplitude), period))

    @classmethod
    def ricker(cls, amplitude: float, period: float, samples: int = 20001) -> "GroundMotion":
        """Ricker wavelet ``amplitude (1 - 2 u^2) exp(-u^2)``, ``u = pi (t - t0) / period``,
        centred at ``t0 = 1.5 period`` and cut at ``3 period`` (``|a| < 1e-8`` amplitude there)."""
        period = _period("the wavelet period", period)
        t = np.linspace(0.0, 3.0 * period, samples)
        u2 = (np.pi * (t - 1.5 * period) / period) ** 2
        return cls(t, float(amplitude) * (1 - 2 * u2) * np.exp(-u2), f"Ricker wavelet {amplitude:g} g, {period:g} s",
                   True, Pulse("ricker", float(amplitude), period))

    # -- records ----------------------------------------------------------------------------
    @classmethod
    def record(cls, path_or_name: str | Path) -> "GroundMotion":
        """A PEER ``.AT2`` file or a two-column CSV (time s, acceleration g); the names of
        :data:`RECORDS` load the records shipped with fembeam.  The file is read by
        :func:`fembeam.readers.read_text` (a regular file of at most :data:`MAX_RECORD_BYTES`);
        the record is checked by :func:`check_record` before its samples are allocated."""
        key = str(path_or_name)
        if key in RECORDS:
            path = resources.files("fembeam") / "data" / "ground_motions" / RECORDS[key]
            text = path.read_text(errors="replace")
        else:
            path = Path(key)
            if not (path.exists() or path.is_symlink()):      # a broken link is said by read_text
                raise InputError(f"no ground-motion file {key!r} (or one of the shipped records: "
                                 f"{', '.join(RECORDS)})")
            text = read_text(path, "the ground-motion file", MAX_RECORD_BYTES, errors="replace")
        name = Path(str(path)).name
        if name.lower().endswith(".at2"):
            return cls._from_at2(text, name)
        return cls._from_csv(text, name)

    @classmethod
    def _from_at2(cls, text: str, name: str) -> "GroundMotion":
        header = "".join(itertools.islice(io.StringIO(text), 6))
        m = re.search(r"NPTS\s*=\s*(\S+?)\s*,?\s*DT\s*=\s*([^\s,]+)", header)
        if m is None:
            raise InputError(f"{name}: not a PEER AT2 file (no 'NPTS= n, DT= dt' in its header)")
        try:
            npts = int(m.group(1))
            dt = float(m.group(2))
        except ValueError:
            raise InputError(f"{name}: the header's NPTS must be an integer and DT a number of seconds, got "
                             f"{m.group(1)!r} and {m.group(2)!r}") from None
        check_record(npts, dt, (npts - 1) * dt if npts > 1 else 0.0, name)
        body = text[text.index(m.group(0)):]
        body = body[body.find("\n") + 1:] if "\n" in body else ""
        words = list(itertools.islice(re.finditer(r"\S+", body), npts))    # the values, no more
        if len(words) < npts:
            raise InputError(f"{name}: the header announces {npts} values, the file has {len(words)}")
        try:
            values = np.array([w.group(0) for w in words], dtype=float)
        except ValueError:
            raise InputError(f"{name}: the values after the header are not all numbers") from None
        return cls(dt * np.arange(npts), values, name)

    @classmethod
    def _from_csv(cls, text: str, name: str) -> "GroundMotion":
        """Two columns ``time,acceleration`` (s, g).  Blank lines and lines starting with ``#``
        are skipped; one header line (a line with a letter that is not a number) may precede the
        data; every other line must hold two finite numbers, or the error names it."""
        rows: list[tuple[int, str]] = []
        header_allowed = True
        for number, raw in enumerate(io.StringIO(text), start=1):
            line = raw.strip()
            if not line or line.startswith("#"):
                continue
            cells = [c.strip() for c in line.split(",")]
            if header_allowed and not _numbers(cells) and re.search(r"[A-Za-z]", line):
                header_allowed = False                   # the header: names of the columns
                continue
            header_allowed = False
            rows.append((number, line))
            if len(rows) > MAX_RECORD_SAMPLES:
                raise InputError(f"{name}: more than {MAX_RECORD_SAMPLES} samples; a record has at most "
                                 f"{MAX_RECORD_SAMPLES}")
        data = np.empty((len(rows), 2))
        for i, (number, line) in enumerate(rows):
            cells = [c.strip() for c in line.split(",")]
            if len(cells) != 2 or not _numbers(cells):
                raise InputError(f"{name}, line {number}: a data line is 'time,acceleration' (two numbers, s "
                                 f"and g), got {line[:40]!r}")
            data[i] = float(cells[0]), float(cells[1])
            if not np.all(np.isfinite(data[i])):
                raise InputError(f"{name}, line {number}: times and accelerations must be finite numbers, "
                                 f"got {line[:40]!r}")
        if len(rows) < 2:
            raise InputError(f"{name}: expected at least two lines 'time,acceleration' (s, g)")
        t = data[:, 0]
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.argmax(steps <= 0)) + 1
            raise InputError(f"{name}, line {rows[k][0]}: times must be strictly increasing, got "
                             f"{t[k]:g} s after {t[k - 1]:g} s")
        check_record(len(rows), (float(np.min(steps)), float(np.max(steps))), float(t[-1] - t[0]), name,
                     start=float(t[0]))
        return cls(t, data[:, 1], name)


def _numbers(cells: list[str]) -> bool:
    """True if every cell is a number (``float`` accepts it; 'nan' and 'inf' included)."""
    try:
        for c in cells:
            float(c)
    except ValueError:
        return False
    return True


def check_record(npts: int, dt, duration: float, name: str, start: float = 0.0) -> None:
    """A record of ``npts`` samples ``dt`` (s; or the (smallest, largest) interval of an
    uneven record) apart, lasting ``duration`` (s) from ``start`` (s): InputError unless
    ``2 <= npts <= MAX_RECORD_SAMPLES``, the intervals lie in :data:`RECORD_DT_RANGE`, the
    duration is at most :data:`MAX_RECORD_DURATION` and ``|start|`` too."""
    lo, hi = RECORD_DT_RANGE
    dmin, dmax = (dt, dt) if isinstance(dt, (int, float)) else dt
    if not 2 <= npts <= MAX_RECORD_SAMPLES:
        raise InputError(f"{name}: a record has from 2 to {MAX_RECORD_SAMPLES} samples, got {npts}")
    if not (math.isfinite(dmin) and math.isfinite(dmax) and lo <= dmin and dmax <= hi):
        what = f"{dmin:g} s" if dmin == dmax else f"from {dmin:g} to {dmax:g} s"
        raise InputError(f"{name}: the time step of a record must be in [{lo:g}, {hi:g}] s, got {what}")
    if not (duration <= MAX_RECORD_DURATION and abs(start) <= MAX_RECORD_DURATION):
        raise InputError(f"{name}: a record starts and ends within {MAX_RECORD_DURATION:g} s of t = 0, got "
                         f"{start:g} to {start + duration:g} s")
