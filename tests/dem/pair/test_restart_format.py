"""Restart files of the plugin as it was before the sub-models became types (git commit f0c8c3f,
restart format 2: 30 positional values per type pair) still read, and continue exactly as that
plugin continues them.

The f0c8c3f plugin is built from its sources (``git show f0c8c3f:...``, into a temporary
directory; the build is cached under a hash of those sources like any plugin build).  It runs a
settling pack of two atom types (type pair 1-2 mixed) with ``compute viscontact/energy`` and
writes a restart file; then it reads that file back and runs N steps (the reference), and the
plugin of this checkout reads the same file and runs the same N steps.  Two model lines cover
every sub-model kind of format 2: jkr + KK alpha form + mindlin_rescale + rolling sds +
twisting sds, and dmt + Jian c0 form + linear_history + twisting marshall; a third runs Jian
contacts in progress (tau = 1e-4 s, 20 steps, against 200 steps before the restart) with the
pair and a `fix viscontact/wall` floor: format 2 stored each contact's start time t0 where
format 3 stores the relaxation g = 1 - exp(-t_c/tau), and the first force call after
read_restart converts it (without the conversion this case differs at once).  The wall fix's
energy count has changed since f0c8c3f (a run's setup dissipates nothing): with the plugin's
floor only the trajectory columns (positions to torques) are compared, not the energy columns
(measured with a KK floor, no Jian: one atom's total dissipated energy differs by 0.5 % while
every trajectory column agrees to 1e-12).  Nor does the first step's dissipated energy: the
setup of a run now writes the energy slots (the setup's forces, the first half of the first
step's work; tests/dem/pair/test_runstart_energy.py), where f0c8c3f kept the last regular
step's; so the dissipated columns are compared from the end of the first step on (measured:
over the whole run they differ by up to 2.5e-4 of a column's largest value, 4e-5 for the
total; from the first step's end they agree to 1e-12, the elastic columns throughout).
Both continue on the same history layout, so they agree to the order of force sums (the same
atom order: here exactly, asserted 1e-12 of each column's largest value).  A restart file that
names a format this plugin does not know stops with one ERROR line naming it.
"""

from __future__ import annotations

import os
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from viscontact import dem

from dem_util import (
    SETTLE, assert_ok, drifting_pack, error_lines, needs_lammps, plugin_line, rank_head,
    read_atoms, run_lmp,
)

pytestmark = needs_lammps

BASE = "f0c8c3f"
ROOT = Path(__file__).resolve().parents[3]
SRC_DIR = "src/viscontact/dem/lammps"
TOL = 1e-12

MODELS = {
    "jkr_rescale_rolling_sds": (
        "pair_coeff 1 1 jkr 1e7 0.3 0.05 damping KK alpha 0.3 vref 1.0 tangential mindlin_rescale "
        "NULL 0.5 0.4 rolling sds 200 0.01 0.1 twisting sds 0.001 1e-9 0.05\n"
        "pair_coeff 2 2 jkr 2e7 0.25 0.08 damping KK alpha 0.2 vref 1.0 tangential mindlin_rescale "
        "2e9 0.3 0.5 rolling sds 300 0.02 0.2 twisting sds 0.002 2e-9 0.08\n"),
    "dmt_jian_marshall": (
        "pair_coeff 1 1 dmt 1e7 0.3 0.02 damping Jian c0 0.05 tau 1e-5 tangential linear_history "
        "2e4 0.4 0.5 twisting marshall\n"
        "pair_coeff 2 2 dmt 2e7 0.3 0.03 damping Jian c0 0.08 tau 2e-5 tangential linear_history "
        "3e4 0.2 0.3 twisting marshall\n"),
    "jian_in_progress_wall": (
        "pair_coeff 1 1 hertz/material 1e7 0.3 damping Jian c0 0.05 tau 1e-4 tangential "
        "linear_history 2e4 0.4 0.5\n"
        "pair_coeff 2 2 hertz/material 2e7 0.3 damping Jian c0 0.08 tau 1.5e-4 tangential "
        "linear_history 3e4 0.2 0.3\n"),
}
#: the floor of each model: native's by default, else the plugin's wall (its history restarts too)
FLOORS = {
    "jian_in_progress_wall": (
        "fix floor all viscontact/wall zplane 0.0 NULL wall_material rigid damping Jian c0 0.05 "
        "tau 1e-4 tangential linear_history 2e4 0.4 0.5\n"),
}
_SETUP = "compute e all viscontact/energy\n" + SETTLE + "thermo 50\n"
_DUMP = ("write_dump all custom {out} id xu yu zu vx vy vz omegax omegay omegaz fx fy fz "
         "tqx tqy tqz c_e[*] modify sort id format float %.17g\n")
#: the dissipated columns after the first step (step 201 of 200 + 150)
_FIRST = ("variable nd equal 201+149*(step>=201)+1000*(step>=350)\n"
          "dump first all custom 1 {out} id c_e[*]\n"
          "dump_modify first every v_nd sort id format float %.17g\n")
DISSIPATED = tuple(f"c_e[{k}]" for k in range(1, 8))
COLUMNS = ("xu", "yu", "zu", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz",
           "tqx", "tqy", "tqz") + tuple(f"c_e[{k}]" for k in range(1, 13))


@pytest.fixture(scope="module")
def old_plugin(tmp_path_factory) -> Path:
    """The plugin of commit f0c8c3f, built from its sources (skipped where git or the commit is
    not at hand, e.g. an unpacked source archive)."""
    if shutil.which("git") is None:
        pytest.skip("git is not installed")
    listing = subprocess.run(["git", "ls-tree", "--name-only", BASE, SRC_DIR + "/"], cwd=ROOT,
                             capture_output=True, text=True)
    if listing.returncode != 0 or not listing.stdout.strip():
        pytest.skip(f"commit {BASE} is not in this checkout's history")
    src = tmp_path_factory.mktemp("plugin_f0c8c3f")
    for path in listing.stdout.split():
        text = subprocess.run(["git", "show", f"{BASE}:{path}"], cwd=ROOT, capture_output=True,
                              check=True).stdout
        (src / Path(path).name).write_bytes(text)
    code = ("import sys; from pathlib import Path; from viscontact.dem import plugin; "
            "plugin.source_dir = lambda: Path(sys.argv[1]); print(plugin.plugin_path())")
    proc = subprocess.run([sys.executable, "-c", code, str(src)], capture_output=True, text=True,
                          timeout=900, env=dict(os.environ))
    assert proc.returncode == 0, proc.stderr[-2000:]
    return Path(proc.stdout.strip().splitlines()[-1])


def _setup(model: str) -> str:
    if model not in FLOORS:
        return _SETUP
    native = next(ln for ln in _SETUP.splitlines() if ln.startswith("fix floor"))
    return _SETUP.replace(native + "\n", FLOORS[model])


def _run(d: Path, name: str, plugin: str, body: str):
    proc = run_lmp(body.replace("{plugin}", plugin), d, name=f"in.{name}")
    return proc


@pytest.mark.parametrize("model", list(MODELS))
def test_format_2_restart_continues_as_before(tmp_path, old_plugin, model):
    d = tmp_path
    drifting_pack(d / "pack.data", (6, 4, 4), 0.002, 5, v_sd=0.3, drift=0.0)
    old = f"plugin load {old_plugin}"
    head = rank_head("p p f", "read_data pack.data", newton=False)
    pair = "pair_style viscontact\n" + MODELS[model]
    setup = _setup(model)
    proc = _run(d, "write", old, head + pair + setup + "run 200\nwrite_restart old.restart\n")
    assert_ok(proc)
    cont = "{plugin}\nread_restart old.restart\n" + setup + "{first}run 150\n"
    out = {}
    for name, plugin in (("ref", old), ("new", plugin_line())):
        proc = _run(d, name, plugin, cont.replace("{first}", _FIRST.format(out=f"{name}.first"))
                    + _DUMP.format(out=f"{name}.dump"))
        assert_ok(proc)
        frames = dem.read_dump(d / f"{name}.first")
        assert [fr.step for fr in frames] == [201, 350]
        out[name] = read_atoms(d / f"{name}.dump"), frames[0].columns
    (ref, ref_first), (got, got_first) = out["ref"], out["new"]
    assert (ref["id"] == got["id"]).all()
    for c in (COLUMNS if model not in FLOORS else COLUMNS[:15]):
        if c in DISSIPATED:    # from the first step's end: see the module's docstring
            ref_c, got_c = ref[c] - ref_first[c], got[c] - got_first[c]
        else:
            ref_c, got_c = ref[c], got[c]
        scale = abs(ref_c).max()
        assert abs(ref_c - got_c).max() <= TOL * (scale if scale > 0 else 1.0), c
    # what the comparison covers: normal damping dissipated, and the tangential and twisting
    # springs hold energy at the end (the restored histories are in use)
    assert ref["c_e[2]"].sum() > 0, ref["c_e[2]"]
    assert ref["c_e[10]"].sum() > 0, ref["c_e[10]"]
    assert "twisting" not in MODELS[model] or ref["c_e[12]"].sum() > 0, ref["c_e[12]"]


def test_unknown_format_is_one_error(tmp_path, old_plugin):
    """A restart file of a contact model format this plugin does not read (here format 2
    written with its version number changed to 1) stops with one ERROR naming the format."""
    d = tmp_path
    drifting_pack(d / "pack.data", (2, 2, 2), 0.002, 5, v_sd=0.0, drift=0.0)
    head = rank_head("p p f", "read_data pack.data", newton=False)
    body = (head + "pair_style viscontact\n"
            + MODELS["dmt_jian_marshall"].split("\n")[0].replace("1 1", "* *", 1) + "\n")
    proc = _run(d, "write", f"plugin load {old_plugin}", body + "write_restart old.restart\n")
    assert_ok(proc)
    data = bytearray((d / "old.restart").read_bytes())
    # the pair's part: its style name, then its format version (int 2) and cutoff (-1.0)
    at = data.find(b"viscontact\x00")
    k = data.find(struct.pack("=i", 2) + struct.pack("=d", -1.0), at)
    assert at >= 0 and k >= 0
    data[k:k + 4] = struct.pack("=i", 1)
    (d / "v1.restart").write_bytes(bytes(data))
    proc = _run(d, "read", plugin_line(), "{plugin}\nread_restart v1.restart\nrun 0\n")
    errors = error_lines(proc)
    assert len(errors) == 1 and "contact model format 1" in errors[0], proc.stdout[-2000:]
