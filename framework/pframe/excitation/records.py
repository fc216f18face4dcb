"""Reading ground-acceleration records: two-column text files and PEER NGA ``.AT2`` files.

A record's acceleration units are read from the file when its header states them (PEER NGA:
``ACCELERATION TIME SERIES IN UNITS OF G``; older files ``UNITS OF CM/SEC/SEC``; a comment
line ``# units: cm/s2`` of a two-column file), else taken from the scene (``units``), else the
default (g for ``.AT2``, m/s^2 for two columns). A header and a scene that disagree are refused
(:class:`RecordUnitsError`): one of them is wrong, and a factor of 981 between them is a
silent wrong answer.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pframe.units import STANDARD_GRAVITY as G  # PEER records are in g
from pframe.yamltext import read_bounded

#: the largest record file read: a PEER record is under 1 MiB; an hour at 200 Hz in two text
#: columns is about 16 MiB. Larger files are refused before they are read
MAX_RECORD_BYTES = 16 * 2**20
#: the largest magnitude of a time or acceleration (as in a scene, pframe.model.load.LARGEST)
LARGEST = 1e100
#: acceleration units pframe reads (the scene's ``units``) and their value in m/s^2
UNITS = {"g": G, "m/s2": 1.0, "cm/s2": 0.01, "gal": 0.01, "mm/s2": 0.001, "in/s2": 0.0254,
         "ft/s2": 0.3048}
#: how each is printed
UNIT_NAMES = {"g": "g", "m/s2": "m/s^2", "cm/s2": "cm/s^2", "gal": "gal (cm/s^2)",
              "mm/s2": "mm/s^2", "in/s2": "in/s^2", "ft/s2": "ft/s^2"}
#: "units of X", "units are (X)", "units: X", "in units X" in a header line
_UNITS_PHRASE = re.compile(r"\bUNITS?\b\s*(?:OF|ARE|IS|IN|:|=)?\s*[:=]?\s*\(?\s*"
                           r"([A-Za-z][A-Za-z0-9/*^\u00b2 ]*?)\s*(?:[).,;\]]|$|\s{2,}|\s-)",
                           re.I)


class RecordUnitsError(ValueError):
    """The units a record file states and the units the scene gives for it disagree, or the
    file states units pframe does not read and the scene gives none."""


def canonical_units(text: str) -> str | None:
    """The name in :data:`UNITS` of a units text as headers write it (``G``, ``CM/SEC/SEC``,
    ``cm/s^2``, ``GAL``, ``M/S**2``, ``in/sec2`` ...); None when it is not an acceleration
    unit pframe reads."""
    s = text.strip().upper().replace(" ", "").replace("\u00b2", "2")
    s = s.replace("SECONDS", "S").replace("SECOND", "S").replace("SEC", "S")
    s = s.replace("**", "").replace("^", "")
    s = s.replace("/S/S", "/S2").replace("/(S*S)", "/S2").replace("/SS", "/S2")
    s = s.replace("METERS", "M").replace("METRES", "M").replace("INCHES", "IN")
    s = s.replace("FEET", "FT").replace("INCH", "IN")
    aliases = {"G": "g", "GS": "g", "GAL": "gal", "GALS": "gal", "CM/S2": "cm/s2",
               "M/S2": "m/s2", "MM/S2": "mm/s2", "IN/S2": "in/s2", "FT/S2": "ft/s2"}
    return aliases.get(s)


def header_units(lines: list[str]) -> tuple[str, int, str] | None:
    """The units a header states: (canonical name or "" when not one pframe reads, line
    number from 1, the text as written); None when no line names units."""
    for number, line in enumerate(lines, start=1):
        match = _UNITS_PHRASE.search(line)
        if match:
            written = match.group(1).strip()
            return canonical_units(written) or "", number, written
    return None


def same_units(a: str, b: str) -> bool:
    return UNITS[a] == UNITS[b]


@dataclass(frozen=True)
class RecordFile:
    """A record file as read: times (s), accelerations (m/s^2) and where its units came from.

    ``units`` is a name of :data:`UNITS`; ``units_from`` says where it was found:
    ``"header, line 3"`` (the file states it), ``"scene"`` (the scene's ``units``; the file
    states none) or ``"default"`` (neither states units: g for .AT2, m/s^2 for columns);
    ``header`` is the units text the file writes, if any."""

    times: np.ndarray
    acceleration: np.ndarray
    units: str
    units_from: str
    header: str | None = None


#: what a message says instead of a line of a record outside the folder it was named from
HIDDEN = "(its text is not shown: the file is outside the folder of the file that names it)"


def _quoted(text: str, shown: bool) -> str:
    """``text`` as a message quotes it, or :data:`HIDDEN` when the file it comes from is not
    to be shown (a record path that leaves its scene's folder: ``../../etc/passwd``)."""
    return repr(text.strip()[:80]) if shown else HIDDEN


def _inside(path: Path, folder) -> bool:
    """Whether ``path`` resolves to a file inside ``folder`` (links followed); True without
    a folder (the caller named the file itself)."""
    if folder is None:
        return True
    try:
        return Path(path).resolve().is_relative_to(Path(folder).resolve())
    except (OSError, RuntimeError):
        return False


def _read_at2(text: str, name: str, shown: bool = True
              ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    lines = text.splitlines()
    if len(lines) < 5:
        raise ValueError(f"{name}: a PEER .AT2 file has 4 header lines then values; "
                         f"this one has {len(lines)} lines")
    header = lines[3]
    npts = re.search(r"NPTS\s*=\s*(\d+)", header, re.I)
    dt = re.search(r"DT\s*=\s*([0-9.eE+-]+)", header, re.I)
    if not (npts and dt):
        numbers = re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", header)
        if len(numbers) < 2:
            raise ValueError(f"{name}, line 4: expected 'NPTS= n, DT= dt' (PEER NGA header), "
                             f"got {_quoted(header, shown)}")
        n, step = int(float(numbers[0])), float(numbers[1])
    else:
        try:
            n, step = int(npts.group(1)), float(dt.group(1))
        except ValueError:
            raise ValueError(f"{name}, line 4: DT is not a number in "
                             f"{_quoted(header, shown)}") from None
    if not (math.isfinite(step) and n <= MAX_RECORD_BYTES):
        raise ValueError(f"{name}, line 4: NPTS={n} and DT={step} cannot describe this file")
    if step <= 0 or n < 2:
        raise ValueError(f"{name}, line 4: NPTS must be >= 2 and DT > 0, got {n} and {step}")
    try:
        values = np.array(" ".join(lines[4:]).replace(",", " ").split(), dtype=float)
    except ValueError:
        for number, line in enumerate(lines[4:], start=5):
            for token in line.replace(",", " ").split():
                try:
                    float(token)
                except ValueError:
                    raise ValueError(f"{name}, line {number}: {_quoted(token, shown)} is not a "
                                     "number (an acceleration value after the header)") from None
        raise
    if values.size != n:
        raise ValueError(f"{name}, line 4: the header says NPTS={n} but {values.size} values "
                         "follow it")
    return np.arange(n) * step, values, lines[:3]


def _read_columns(text: str, name: str, shown: bool = True
                  ) -> tuple[np.ndarray, np.ndarray, list[str]]:
    rows = []
    header = []  # comments anywhere and text lines before the data: where units are stated
    for number, line in enumerate(text.splitlines(), start=1):
        if "#" in line:
            header.append(line.split("#", 1)[1])
        else:
            header.append("")
        stripped = line.split("#", 1)[0].replace(",", " ").strip()
        if not stripped:
            continue
        parts = stripped.split()
        try:
            values = [float(p) for p in parts]
        except ValueError:
            if not rows:  # a header line before the data
                header[-1] = line
                continue
            raise ValueError(f"{name}, line {number}: expected two numbers (time, "
                             f"acceleration), got {_quoted(line, shown)}") from None
        if len(values) != 2:
            raise ValueError(f"{name}, line {number}: expected two columns (time, "
                             f"acceleration), got {len(values)}")
        rows.append(values)
    if len(rows) < 2:
        raise ValueError(f"{name}: expected at least two rows of (time, acceleration)")
    data = np.array(rows)
    if np.any(np.diff(data[:, 0]) <= 0):
        raise ValueError(f"{name}: times must increase strictly")
    return data[:, 0], data[:, 1], header


def read_record(path: str | Path, format: str = "auto", units: str | None = None,
                within=None):
    """Times (s) and ground accelerations (m/s^2) of a record file.

    ``format`` is ``columns`` (time, acceleration per line), ``at2`` (PEER NGA) or ``auto``
    (by the file suffix). The units are those the file's header states, else ``units``, else
    g for AT2 files and m/s^2 otherwise (:func:`read_record_file` says which).
    Raises ``ValueError`` with the file and line on malformed input (:class:`RecordUnitsError`
    when the header and ``units`` disagree), ``FileNotFoundError``. A message quotes the
    file's text only when it lies inside the folder ``within`` (the scene's, the suite's),
    when one is given: a record path that leaves it (``../../etc/passwd``) must not print
    another file.
    """
    record = read_record_file(path, format, units, within)
    return record.times, record.acceleration


def read_record_file(path: str | Path, format: str = "auto",
                     units: str | None = None, within=None) -> RecordFile:
    """A record file read as :func:`read_record` reads it, with the units it was read in and
    where they came from (:class:`RecordFile`)."""
    path = Path(path)
    # a regular file of at most MAX_RECORD_BYTES (a PEER record is well under 1 MiB), read at
    # once: a device or a FIFO is refused, never read
    text = read_bounded(path, "record", MAX_RECORD_BYTES, errors="replace")
    is_at2 = format == "at2" or (format == "auto" and path.suffix.lower() == ".at2")
    shown = _inside(path, within)
    times, acc, header = (_read_at2 if is_at2 else _read_columns)(text, str(path), shown)
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(acc))):
        bad = int(np.flatnonzero(~(np.isfinite(times) & np.isfinite(acc)))[0])
        raise ValueError(f"{path}: value {bad + 1} of the record (time {times[bad]!r}) is not "
                         "a finite number")
    if np.max(np.abs(acc), initial=0.0) > LARGEST or np.max(np.abs(times), initial=0.0) > LARGEST:
        raise ValueError(f"{path}: the record holds values larger than {LARGEST:g}: not a "
                         "ground acceleration in m/s^2 or g")
    chosen, where, written = _units(path, header, units, is_at2, shown)
    if UNITS[chosen] != 1.0:
        acc = acc * UNITS[chosen]
    return RecordFile(times, acc, chosen, where, written)


def _units(path: Path, header: list[str], units: str | None, is_at2: bool,
           shown: bool = True):
    """(units, where from, the header's text) of a record, or RecordUnitsError."""
    if units is not None and units not in UNITS:
        raise RecordUnitsError(f"{path}: units {units!r} are not one of "
                               f"{', '.join(UNITS)}")
    stated = header_units(header)
    if stated is None:
        if units is not None:
            return units, "scene", None
        return ("g" if is_at2 else "m/s2"), "default", None
    found, line, written = stated
    if not found:
        if units is not None:
            return units, "scene", written
        raise RecordUnitsError(
            f"{path}, line {line}: the header states the units {_quoted(written, shown)}, "
            "which are not an "
            f"acceleration unit pframe reads ({', '.join(UNITS)}): give the record's units in "
            "the scene (excitation.units) if the values are accelerations")
    if units is not None and not same_units(found, units):
        raise RecordUnitsError(
            f"{path}, line {line}: the header states the accelerations in "
            f"{UNIT_NAMES[found]} ({_quoted(written, shown)}) but the scene gives units "
            f"{units!r}: a factor "
            f"of {UNITS[found] / UNITS[units]:.6g} between them. Remove excitation.units to "
            "read the file as its header says, or correct the one that is wrong")
    return found, f"header, line {line}", written


#: the units of a record's displacement and velocity files in m and m/s (PEER NGA's .DT2 and
#: .VT2 files state cm and cm/s: DISPLACEMENT TIME SERIES IN UNITS OF CM)
SERIES_UNITS = {"displacement": {"M": 1.0, "CM": 0.01, "MM": 0.001, "IN": 0.0254,
                                 "FT": 0.3048},
                "velocity": {"M/S": 1.0, "CM/S": 0.01, "MM/S": 0.001, "IN/S": 0.0254,
                             "FT/S": 0.3048}}
#: the suffixes of PEER's displacement and velocity files
SERIES_SUFFIXES = {"displacement": ".dt2", "velocity": ".vt2"}


def read_series(path: str | Path, quantity: str, within=None) -> tuple[np.ndarray, np.ndarray,
                                                                       str]:
    """Times (s), values (m or m/s) and the units read of a record's ``quantity`` file
    ('displacement': PEER .DT2, 'velocity': .VT2, or two columns), read as
    :func:`read_record` reads an acceleration: PEER's header (NPTS, DT) for its suffix in any
    case, else two columns; the units its header states (PEER: cm, cm/s), else m or m/s for
    two columns and cm or cm/s for PEER's. Raises ValueError naming the file and line,
    FileNotFoundError."""
    path = Path(path)
    text = read_bounded(path, "record", MAX_RECORD_BYTES, errors="replace")
    peer = path.suffix.lower() == SERIES_SUFFIXES[quantity]
    shown = _inside(path, within)
    times, values, header = (_read_at2 if peer else _read_columns)(text, str(path), shown)
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(values))):
        raise ValueError(f"{path}: a value of the {quantity} is not a finite number")
    known = SERIES_UNITS[quantity]
    stated = header_units(header)
    if stated is None:
        units = ("CM" if quantity == "displacement" else "CM/S") if peer else \
            ("M" if quantity == "displacement" else "M/S")
    else:
        written = stated[2].upper().replace(" ", "").replace("SECOND", "S").replace("SEC", "S")
        units = written.rstrip("S") if written.rstrip("S") in known else written
        if units not in known:
            raise ValueError(f"{path}, line {stated[1]}: the header states the units "
                             f"{_quoted(stated[2], shown)}, which are not units of {quantity} "
                             f"pframe reads ({', '.join(u.lower() for u in known)})")
    return times, values * known[units], units.lower()
