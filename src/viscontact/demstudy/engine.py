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

import os
import shutil
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from . import jobs
from ..dem.coeff import contact_words
from ..dem.io import read_dump, read_log as read_thermo
from ..dem.materials import Wall as DemWall
from ..dem.submodels import SubModels
from ..dem.run import LammpsError, run_in_dir, stop_on_signals
from ..physics.laws import Jian, KK, LH, Ts

__all__ = ["LawSpec", "Material", "Wall", "coeff_text", "backend", "run_lammps", "read_thermo",
           "read_dump", "input_path", "LammpsError", "NATIVE_MODELS"]

#: laws LAMMPS's own pair_style granular can stand in for (dev fallback only)
NATIVE_MODELS = (LH.name, Ts.name, KK.name)


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

    def geometry(self) -> DemWall:
        """The wall as :class:`viscontact.dem.Wall` (rigid, no motion), for the one writer of
        wall lines; ``style`` ``zplane 0.0 NULL`` is read as the style and its LO HI."""
        kind, *args = self.style.split()
        return DemWall(kind, tuple(None if a == "NULL" else float(a) for a in args))


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
                         beta=law.beta if law.model == Jian.name else None)
    lines = dem.coeff_lines(dl, E=mat.E, nu=mat.nu, friction=mat.mu)
    sub = SubModels.build(friction=mat.mu)
    out = [str(lines).rstrip()]
    for w in walls:
        out.append(f"fix {w.fix_id} all viscontact/wall " + contact_words(
            dl, sub, "si", wall=w.geometry(), wall_material=None, particle=(mat.E, mat.nu)))
    return "\n".join(out) + "\n"


def _native_text(law: LawSpec, mat: Material, walls: Sequence[Wall], m_eff: float, r_eff: float
                 ) -> str:
    """pair_style granular lines equal to our law for contacts of effective mass m_eff and
    radius r_eff (exact for any contact with Ts; for LH and KK only for that m*, R*)."""
    from ..audit.engines import get_preset
    from ..physics.pair import ContactPair, effective_modulus, hertz_stiffness
    from ..calibration.inverse import alpha_from_e

    if law.model not in NATIVE_MODELS:
        raise ValueError(f"law {law.model} needs the viscontact LAMMPS plugin "
                         f"(LAMMPS's pair_style granular has only {', '.join(NATIVE_MODELS)})")
    alpha = float(alpha_from_e(law.model, law.e, end="force", exact=True))
    # hertz/material, two equal bodies
    k = hertz_stiffness(effective_modulus(mat.E, mat.nu, mat.E, mat.nu), r_eff)
    option = {LH.name: "velocity", Ts.name: "tsuji", KK.name: "viscoelastic"}[law.model]
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
        kw = hertz_stiffness(effective_modulus(mat.E, mat.nu), 2.0 * r_eff)  # rigid wall
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

    A copy of the input goes into ``workdir`` and :func:`viscontact.dem.run.run_in_dir` runs it
    (np_ > 1 under ``mpirun -np``) once one of the study's slots is free
    (:func:`viscontact.demstudy.jobs.concurrent`); ``start()`` is called when LAMMPS starts,
    ``tick(seconds)`` about every half second while it runs (see :func:`sim_time_ticker`).  It
    stops when another run failed or the study was interrupted.  Raises LammpsError with
    LAMMPS's ERROR line when it fails.
    """
    workdir.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(input_path(name), workdir / name)

    def watch(seconds: float) -> None:
        if jobs.cancelled():  # another run failed, or the study was interrupted
            raise jobs.Cancelled()
        if tick is not None:
            tick(seconds)

    with stop_on_signals(), jobs.slot():
        return run_in_dir(name, workdir, variables, np_=np_, log=log, tick=watch,
                          timeout=timeout, start=start)
