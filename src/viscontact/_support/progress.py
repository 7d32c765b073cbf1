"""The one progress reporter of the long commands (reproduce, dem-study, fit, dem run).

A tqdm bar on stderr when stderr is a terminal; otherwise, where the command logs its steps,
one line per step (``viscontact reproduce: [  3.2 s] figure e_alpha done``), else nothing;
nothing at all under ``--no-progress`` (``stream=None``).  tqdm is imported only when a bar is
drawn.
"""

from __future__ import annotations

import shutil
import sys
import threading
import time
from typing import Any, TextIO

__all__ = ["Progress"]


class Progress:
    """Steps of one command, shown on ``stream``.

    ``total``: the length of the bar (None: unknown until :meth:`reset`); ``log``: the prefix of
    the one-line-per-step log written when ``stream`` is not a terminal (None: silent there);
    ``unit``, ``leave`` and ``delay`` (seconds before the bar appears) as tqdm's.
    """

    def __init__(self, total: int | None, *, stream: TextIO | None = sys.stderr,
                 log: str | None = None, unit: str = "step", leave: bool = True,
                 delay: float = 0.0, bar_format: str | None = None) -> None:
        self.stream = stream
        self.log = log if stream is not None else None
        self.bar: Any = None
        self.t0 = time.perf_counter()
        self._pending = 0
        self._total = total
        self._lock = threading.Lock()  # steps may begin in threads of their own (dem-study)
        if stream is not None and stream.isatty():
            from tqdm import tqdm

            columns = shutil.get_terminal_size((100, 20)).columns
            self.bar = tqdm(total=total, file=stream, unit=unit, leave=leave, delay=delay,
                            ncols=min(columns, 110) if columns >= 40 else 100,
                            bar_format=bar_format)
            self.log = None

    @property
    def total(self) -> int | None:
        return self.bar.total if self.bar is not None else self._total

    @total.setter
    def total(self, value: int | None) -> None:
        self._total = value
        if self.bar is not None:
            self.bar.total = value

    @property
    def n(self) -> int:
        return self.bar.n if self.bar is not None else 0

    @n.setter
    def n(self, value: int) -> None:
        if self.bar is not None:
            self.bar.n = value

    def step(self, name: str, weight: int = 1) -> None:
        """Step ``name`` begins: the bar moves by the weight of the step before and shows
        ``name``; off a terminal, one log line (elapsed time and ``name``)."""
        with self._lock:
            self.update(self._pending)
            self._pending = weight
            self.describe(name)
            if self.log is not None:
                print(f"{self.log}: [{time.perf_counter() - self.t0:6.1f} s] {name}",
                      file=self.stream, flush=True)

    def describe(self, text: str, refresh: bool = True) -> None:
        """What the bar is doing now (the bar only)."""
        if self.bar is not None:
            self.bar.set_description_str(text, refresh=refresh)

    set_description = describe  # tqdm's name: a parser of LAMMPS output drives either

    def refresh(self) -> None:
        if self.bar is not None:
            self.bar.refresh()

    def update(self, n: int = 1) -> None:
        """``n`` more units done (the bar only; tqdm redraws at most every mininterval)."""
        if self.bar is not None and n:
            self.bar.update(n)

    def reset(self, total: int | None = None) -> None:
        """A fresh bar of ``total`` units (the next LAMMPS ``run``, say)."""
        if self.bar is not None:
            self.bar.reset(total=total)

    def close(self, text: str | None = None) -> None:
        """The command is done: the bar is filled (with ``text``) and closed."""
        if self.bar is not None:
            if text is not None:
                self.bar.set_description_str(text)
                if self.bar.total:
                    self.bar.update(self.bar.total - self.bar.n)
            self.bar.close()
