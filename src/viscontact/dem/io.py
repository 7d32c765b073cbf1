"""Read LAMMPS output back: thermo columns from a log file, frames from a text dump.

Thermo: the default columnar format (``thermo_style one`` or ``custom``; not ``multi`` or
``yaml``).  A run's table starts after LAMMPS's ``Per MPI rank memory allocation`` line (the
next line names the columns) and ends at ``Loop time of``; lines in between that are not a row
of numbers of the right width (warnings) are skipped.  A run that stopped early (an error) keeps
the rows it printed.

Dumps: the text format of ``dump atom`` / ``dump custom`` (``ITEM: TIMESTEP``, ``ITEM: NUMBER
OF ATOMS``, ``ITEM: BOX BOUNDS``, ``ITEM: ATOMS <columns>``), orthogonal or triclinic boxes.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Frame", "read_log", "read_log_runs", "read_dump", "INT_COLUMNS"]

#: dump columns returned as integer arrays
INT_COLUMNS = frozenset({"id", "type", "mol", "proc", "procp1", "ix", "iy", "iz"})


def _numbers(tokens: list[str]) -> list[float] | None:
    try:
        return [float(t) for t in tokens]
    except ValueError:
        return None


def _path(path: object, what: str) -> Path:
    """``path`` as a Path; TypeError for anything but str / os.PathLike (an int would be taken
    as a file descriptor by open() and closed afterwards)."""
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"{what} needs a file path (str or os.PathLike), got {type(path).__name__}")
    return Path(path)


#: the first line LAMMPS writes into every log (its version banner)
_LOG_BANNER = "LAMMPS ("


def read_log_runs(path: str | os.PathLike) -> list[dict[str, np.ndarray]]:
    """Thermo output of every run in a LAMMPS log, one dict (column name -> array) per run.

    TypeError unless ``path`` is a path; ValueError when the file is not a LAMMPS log (its
    first line is not LAMMPS's banner ``LAMMPS (version)``)."""
    p = _path(path, "read_log")
    runs: list[dict[str, np.ndarray]] = []
    header: list[str] | None = None
    rows: list[list[float]] = []
    expect_header = False

    def close() -> None:
        if header is not None:
            arr = np.array(rows, dtype=float).reshape(len(rows), len(header))
            runs.append({name: arr[:, i].copy() for i, name in enumerate(header)})

    with open(p, encoding="utf-8", errors="replace") as fh:
        first = fh.readline()
        if not first.startswith(_LOG_BANNER):
            raise ValueError(f"{p} is not a LAMMPS log (its first line is not 'LAMMPS (version)')")
        for line in fh:
            if line.startswith("Per MPI rank memory allocation"):
                close()
                header, rows, expect_header = None, [], True
                continue
            tokens = line.split()
            if expect_header:
                if tokens:
                    header, expect_header = tokens, False
                continue
            if header is None:
                continue
            if line.startswith("Loop time of"):
                close()
                header, rows = None, []
                continue
            if len(tokens) == len(header):
                values = _numbers(tokens)
                if values is not None:
                    rows.append(values)
    close()  # a run cut short by an error
    return runs


def read_log(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """Thermo output of a LAMMPS log as column name -> array, all runs one after another.

    One row per thermo line, in order (a run's first row repeats the step where the previous
    run ended).  A column that only some runs print is NaN in the others.  No thermo output
    gives an empty dict; a file that is not a LAMMPS log is a ValueError.
    """
    runs = read_log_runs(path)
    names: list[str] = []
    for run in runs:
        names += [n for n in run if n not in names]
    out: dict[str, np.ndarray] = {}
    for name in names:
        parts = [run[name] if name in run else np.full(len(next(iter(run.values()))), np.nan)
                 for run in runs]
        out[name] = np.concatenate(parts) if parts else np.empty(0)
    return out


@dataclass
class Frame:
    """One snapshot of a text dump.

    Attributes:
        step: the timestep; natoms: number of atoms in the frame.
        box: 3 x 2 array of (lo, hi) bounds per axis (triclinic: 3 x 3, the tilt factors
            xy, xz, yz in the third column, as LAMMPS writes them).
        boundary: the boundary flags LAMMPS writes (e.g. ``pp pp ff``).
        columns: column name -> array (``id``, ``type`` ... as int, the rest float).
    """

    step: int
    natoms: int
    box: np.ndarray
    boundary: str
    columns: dict[str, np.ndarray] = field(repr=False)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]


def read_dump(path: str | os.PathLike, *, sort: bool = True) -> list[Frame]:
    """Every frame of a LAMMPS text dump (``dump atom`` / ``dump custom``).

    ``sort``: order each frame's rows by atom ``id`` when there is an id column (dumps from
    several MPI ranks come in rank order).  ValueError names the line of a malformed file.
    """
    p = _path(path, "read_dump")
    lines = p.read_text(encoding="utf-8", errors="replace").splitlines()
    frames: list[Frame] = []
    i, n = 0, len(lines)

    def bad(k: int, what: str) -> ValueError:
        return ValueError(f"{p}: line {k + 1}: {what}; not a LAMMPS text dump")

    def expect(k: int, prefix: str) -> None:
        if k >= n or not lines[k].startswith(prefix):
            raise bad(k, f"expected '{prefix}'")

    while i < n:
        if not lines[i].strip():
            i += 1
            continue
        expect(i, "ITEM: TIMESTEP")
        try:
            step = int(lines[i + 1].split()[0])
        except (IndexError, ValueError):
            raise bad(i + 1, "expected a timestep") from None
        expect(i + 2, "ITEM: NUMBER OF ATOMS")
        try:
            natoms = int(lines[i + 3].split()[0])
        except (IndexError, ValueError):
            raise bad(i + 3, "expected the number of atoms") from None
        expect(i + 4, "ITEM: BOX BOUNDS")
        words = lines[i + 4].split()[3:]
        triclinic = words[:3] == ["xy", "xz", "yz"]
        boundary = " ".join(words[3:] if triclinic else words)
        box_rows = [_numbers(lines[k].split()) if k < n else None for k in range(i + 5, i + 8)]
        width = 3 if triclinic else 2
        if any(r is None or len(r) != width for r in box_rows):
            raise bad(i + 5, f"expected three lines of {width} box numbers")
        expect(i + 8, "ITEM: ATOMS")
        names = lines[i + 8].split()[2:]
        start, stop = i + 9, i + 9 + natoms
        if stop > n:
            raise bad(n - 1, f"the frame at step {step} has fewer than {natoms} atom lines")
        flat = " ".join(lines[start:stop]).split()
        if len(flat) != natoms * len(names):
            raise bad(start, f"expected {natoms} rows of {len(names)} columns at step {step}")
        try:
            data = np.array(flat, dtype=float).reshape(natoms, len(names))
        except ValueError:
            raise bad(start, f"non-numeric atom data at step {step}") from None
        if sort and "id" in names:
            data = data[np.argsort(data[:, names.index("id")], kind="stable")]
        cols = {name: (data[:, j].astype(np.int64) if name in INT_COLUMNS else data[:, j].copy())
                for j, name in enumerate(names)}
        frames.append(Frame(step=step, natoms=natoms, box=np.array(box_rows, dtype=float),
                            boundary=boundary, columns=cols))
        i = stop
    return frames
