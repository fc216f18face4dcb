"""Reading ground-acceleration records: two-column text files and PEER NGA ``.AT2`` files."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from pframe.yamltext import read_bounded

G = 9.80665  # standard gravity (m/s^2): PEER records are in g
#: the largest record file read: a PEER record is under 1 MiB; an hour at 200 Hz in two text
#: columns is about 16 MiB. Larger files are refused before they are read
MAX_RECORD_BYTES = 16 * 2**20
#: the largest magnitude of a time or acceleration (as in a scene, pframe.model.load.LARGEST)
LARGEST = 1e100


def _read_at2(text: str, name: str) -> tuple[np.ndarray, np.ndarray]:
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
                             f"got {header.strip()!r}")
        n, step = int(float(numbers[0])), float(numbers[1])
    else:
        try:
            n, step = int(npts.group(1)), float(dt.group(1))
        except ValueError:
            raise ValueError(f"{name}, line 4: DT is not a number in {header.strip()!r}") from None
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
                    raise ValueError(f"{name}, line {number}: {token!r} is not a number (an "
                                     "acceleration value after the header)") from None
        raise
    if values.size != n:
        raise ValueError(f"{name}, line 4: the header says NPTS={n} but {values.size} values "
                         "follow it")
    return np.arange(n) * step, values


def _read_columns(text: str, name: str) -> tuple[np.ndarray, np.ndarray]:
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].replace(",", " ").strip()
        if not stripped:
            continue
        parts = stripped.split()
        try:
            values = [float(p) for p in parts]
        except ValueError:
            if not rows:  # a header line before the data
                continue
            raise ValueError(f"{name}, line {number}: expected two numbers (time, "
                             f"acceleration), got {line.strip()!r}") from None
        if len(values) != 2:
            raise ValueError(f"{name}, line {number}: expected two columns (time, "
                             f"acceleration), got {len(values)}")
        rows.append(values)
    if len(rows) < 2:
        raise ValueError(f"{name}: expected at least two rows of (time, acceleration)")
    data = np.array(rows)
    if np.any(np.diff(data[:, 0]) <= 0):
        raise ValueError(f"{name}: times must increase strictly")
    return data[:, 0], data[:, 1]


def read_record(path: str | Path, format: str = "auto", units: str | None = None):
    """Times (s) and ground accelerations (m/s^2) of a record file.

    ``format`` is ``columns`` (time, acceleration per line), ``at2`` (PEER NGA) or ``auto``
    (by the file suffix). ``units`` defaults to g for AT2 files and m/s^2 otherwise.
    Raises ``ValueError`` with the file and line on malformed input, ``FileNotFoundError``.
    """
    path = Path(path)
    # a regular file of at most MAX_RECORD_BYTES (a PEER record is well under 1 MiB), read at
    # once: a device or a FIFO is refused, never read
    text = read_bounded(path, "record", MAX_RECORD_BYTES, errors="replace")
    is_at2 = format == "at2" or (format == "auto" and path.suffix.lower() == ".at2")
    times, acc = (_read_at2 if is_at2 else _read_columns)(text, str(path))
    if not (np.all(np.isfinite(times)) and np.all(np.isfinite(acc))):
        bad = int(np.flatnonzero(~(np.isfinite(times) & np.isfinite(acc)))[0])
        raise ValueError(f"{path}: value {bad + 1} of the record (time {times[bad]!r}) is not "
                         "a finite number")
    if np.max(np.abs(acc), initial=0.0) > LARGEST or np.max(np.abs(times), initial=0.0) > LARGEST:
        raise ValueError(f"{path}: the record holds values larger than {LARGEST:g}: not a "
                         "ground acceleration in m/s^2 or g")
    if (units or ("g" if is_at2 else "m/s2")) == "g":
        acc = acc * G
    return times, acc
