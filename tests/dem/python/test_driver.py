"""The DEM driver as a command-line tool (issue 18, items 6, 8 and 10).

References are independent of the code under test: LAMMPS itself (what its parser reads back,
which type specs it accepts) and the operating system's process table (what is left after a
signal).  Units styles and several particle types: test_types_units.py.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from viscontact import dem
from viscontact.dem import _text, run as run_mod
from viscontact.physics.pair import ContactPair

from conftest import SRC, run_cli
from dem_util import LMP, needs_lammps, needs_mpirun


# ------------------------------------------------------------------------------ quoting
#: names LAMMPS reads back from a quoted literal, and names no literal can hold
LITERAL = ["with space", "hash#mark", "semi;colon", "back\\slash", "amp&er"]
NOT_LITERAL = ["dollar$b", "quote'one", 'quote"two', "accent\u00e9", "smart\u201dquote"]


def _lmp(tmp_path: Path, text: str, *extra: str) -> str:
    (tmp_path / "in.probe").write_text(text)
    proc = subprocess.run([LMP, "-in", "in.probe", "-log", "none", "-nocite", *extra], cwd=tmp_path,
                          capture_output=True, timeout=60)
    return proc.stdout.decode("utf-8", "replace")


def _included(lmp, line: str, name: str) -> bool:
    """Whether LAMMPS ran ``line`` (an include of a file that defines variable ``name``)."""
    try:
        lmp.command(line)
    except Exception:  # noqa: BLE001 - the lammps module raises plain exceptions
        return False
    return lmp.extract_variable(name) is not None


@needs_lammps
def test_literal_paths_are_exactly_what_lammps_reads_back(tmp_path):
    """Each name quote_path accepts is read back by LAMMPS's include; each it refuses fails in
    LAMMPS under every quote kind (so the refusal is LAMMPS's rule, not ours)."""
    from viscontact.dem.plugin import new_lammps

    lmp = new_lammps(load_plugin=False)
    names = [(name, True) for name in LITERAL] + [(name, False) for name in NOT_LITERAL]
    for k, (name, literal) in enumerate(names):
        d = tmp_path / name
        d.mkdir()
        for j, q in enumerate(("'", '"', '"""')):
            var = f"inc{k}x{j}"
            (d / f"{var}.in").write_text(f"variable {var} string yes\n")
            path = d / f"{var}.in"
            if literal:
                assert _text.quote_path(path) == f"'{path}'"
                assert _included(lmp, f"include {_text.quote_path(path)}", var), name
                break
            with pytest.raises(ValueError, match="cannot hold"):
                _text.quote_path(path)
            assert not _included(lmp, f"include {q}{path}{q}", var), (name, q)
    lmp.close()


@needs_lammps
def test_plugin_load_line_is_quoted_and_loads(tmp_path):
    """`dem plugin` prints a quoted line; LAMMPS loads the plugin from it, also from a copy in a
    directory with a space and a '#' (which an unquoted line would cut)."""
    proc = run_cli("dem", "plugin")
    assert proc.returncode == 0, proc.stderr
    path, line = proc.stdout.splitlines()
    assert line == f"plugin load '{path}'"
    odd = tmp_path / "my plugins #1"
    odd.mkdir()
    (odd / "viscontact.so").write_bytes(Path(path).read_bytes())
    lines = dem.coeff_lines(dem.contact_law("KK", alpha=0.3, vref=1.0), E=1e7, nu=0.3,
                            plugin=odd / "viscontact.so")
    out = _lmp(tmp_path, f"{lines.plugin_load}\nplugin list\n")
    assert "Loading plugin: viscontact" in out, out[-800:]


def _tiny_input(steps: int = 10, natoms: int = 2) -> str:
    return (f"units si\natom_style sphere\ncomm_modify vel yes\nboundary f f f\n"
            f"region box block 0 1 0 1 0 1\ncreate_box 1 box\n"
            f"create_atoms 1 random {natoms} 12345 NULL overlap 0.05\n"
            "set type 1 diameter 0.02\nset type 1 density 2500\n"
            "pair_style viscontact\n"
            "pair_coeff * * hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 tangential none\n"
            "fix 1 all nve/sphere\ntimestep 1e-6\nthermo_style custom step atoms\nthermo 5\n"
            f"run {steps}\n")


@needs_lammps
@pytest.mark.parametrize("nproc", [1, 2])
def test_dem_run_reads_any_input_path(tmp_path, nproc):
    """An input in a directory whose name has every awkward character (non-ASCII, '#', '$',
    both quotes, a space) runs on 1 and 2 ranks; the log lands beside it; no temp file stays."""
    if nproc > 1 and run_mod.available_cores() < 2:
        pytest.skip("one core")
    d = tmp_path / "d\u00e9j\u00e0 #1 $HOME 'a' \"b\""
    d.mkdir()
    (d / "in run").write_text(_tiny_input())
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = {"TMPDIR": str(tmp)}
    proc = run_cli("dem", "run", d / "in run", "--np", nproc, "--json", env=env)
    assert proc.returncode == 0, proc.stderr
    assert (d / "in run.log").is_file() and list(tmp.iterdir()) == []
    thermo = dem.read_log(d / "in run.log")
    assert thermo["Step"].tolist() == [0, 5, 10] and (thermo["Atoms"] == 2).all()


# ---------------------------------------------------------------------------- type specs
ACCEPT = ["* *", "1 2", "2 1", "1*3 *", "2* *3", "3 3"]
REJECT = ["0 0", "2*1 *", "\uff11 \uff11", "12345678901234567890 1", "4 1", "a b", "-1 1", "1.0 1"]


@needs_lammps
def test_type_specs_accepted_exactly_as_lammps_accepts_them():
    """For a box of 3 types, check_type_spec accepts a spec if and only if LAMMPS's pair_coeff
    does (LAMMPS's own bounds rule is the reference)."""
    from viscontact.dem.plugin import new_lammps

    lmp = new_lammps(load_plugin=False)
    for cmd in ("units si", "region b block 0 1 0 1 0 1", "create_box 3 b", "pair_style lj/cut 1.0"):
        lmp.command(cmd)
    for spec in ACCEPT + REJECT:
        try:
            lmp.command(f"pair_coeff {spec} 1.0 1.0")
            lammps_ok = True
        except Exception:  # noqa: BLE001 - the module raises plain exceptions
            lammps_ok = False
        try:
            _text.check_type_spec(spec, ntypes=3)
            ours = True
        except ValueError:
            ours = False
        assert ours == lammps_ok == (spec in ACCEPT), spec
    lmp.close()
    # not two words (lj/cut takes more numbers, so no probe), or '1**' (LAMMPS aborts on it)
    for spec in ("1", "1 2 3", "", "1** 1"):
        with pytest.raises(ValueError, match="types must be two atom types"):
            _text.check_type_spec(spec)
    with pytest.raises(ValueError, match="types must be two atom types"):
        dem.coeff_lines(dem.contact_law("KK", alpha=0.3, vref=1.0), E=1e7, nu=0.3, types="0 1",
                        plugin="/x.so")
    with pytest.raises(TypeError, match="types must be a string"):
        _text.check_type_spec(12)


# ------------------------------------------------------------------- values where they enter
@pytest.mark.parametrize("kwargs,match", [
    (dict(law="KK", p=0.5, alpha=float("nan"), vref=1.0), "alpha must be in"),
    (dict(law="Foo", p=0.5, alpha=0.3, vref=1.0), "unknown model"),
    (dict(law="KK", p=1.0, alpha=0.3, vref=1.0), "fixed exponent"),
    (dict(law="KK", p=0.5, alpha=0.3), "needs vref"),
    (dict(law="KK", p=0.5, alpha=0.3, vref=1.0, c0=2.0), "exactly one"),
    (dict(law="Jian", p=0.5, alpha=0.3, vref=1.0), "needs beta"),
    (dict(law="KK", p=0.5, c0=float("inf")), "c0 must be in"),
    (dict(law="KK", p=0.5, alpha=0.3, vref=1.0, end="both"), "end"),
])
def test_demlaw_checks_every_value_where_built(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dem.DemLaw(**kwargs)


def test_public_arguments_have_typed_errors(tmp_path, capsys):
    law = dem.contact_law("KK", alpha=0.3, vref=1.0)
    with pytest.raises(TypeError, match="ContactPair"):
        law.physical(0.5)
    pair = ContactPair.from_effective(m_eff=1e-3, r_eff=0.005, e_eff=1e7)
    assert law.physical(pair)[0] > 0
    for bad in (1, 1.5, None, b"x.log"):
        with pytest.raises(TypeError, match="file path"):
            dem.read_log(bad)
    print("still open")  # read_log(1) must not have closed fd 1
    assert "still open" in capsys.readouterr().out
    notes = tmp_path / "notes.txt"
    notes.write_text("step 1 2\n1 2 3\n")
    with pytest.raises(ValueError, match="not a LAMMPS log"):
        dem.read_log(notes)
    src = tmp_path / "in.x"
    src.write_text("units si\n")
    with pytest.raises(TypeError, match="mapping NAME -> VALUE"):
        dem.run_input(src, variables=["steps", 10])
    with pytest.raises(TypeError, match="file path"):
        dem.run_input(3)


def test_log_directory_and_unwritable_log(tmp_path):
    src = tmp_path / "in.x"
    src.write_text("units si\n")
    got = run_mod.resolve_log(str(tmp_path / "newdir") + "/", src, False)
    assert got == tmp_path / "newdir" / "in.x.log" and (tmp_path / "newdir").is_dir()
    assert run_mod.resolve_log(tmp_path / "newdir", src, False) == got  # an existing directory
    proc = run_cli("dem", "run", src, "--log", "/proc/viscontact-test.log")
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1, proc.stderr
    assert "cannot write the log /proc/viscontact-test.log" in proc.stderr


@needs_lammps
@needs_mpirun
def test_more_ranks_than_cores_warns_once(tmp_path):
    src = tmp_path / "in.x"
    src.write_text(_tiny_input(steps=5, natoms=4))
    n = run_mod.available_cores() + 1
    proc = run_cli("dem", "run", src, "--np", n, "--no-progress", "--json")
    assert proc.returncode == 0, proc.stderr
    warn = [ln for ln in proc.stderr.splitlines() if "warning" in ln]
    assert len(warn) == 1 and f"{n} ranks on {n - 1} cores" in warn[0]


# ------------------------------------------------------------------------------- signals
def _tree(pid: int) -> set[int]:
    """pid and every descendant, from /proc (the operating system's view)."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(entry))
    out, todo = set(), [pid]
    while todo:
        p = todo.pop()
        out.add(p)
        todo += children.get(p, [])
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


# no output while it runs: a closed pipe (SIGPIPE) must not be what stops LAMMPS
_LONG = _tiny_input(steps=10**9, natoms=50).replace("thermo 5", "thermo 100000000")


def _start(cmd: list[str], tmp: Path, cwd: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""),
               TMPDIR=str(tmp))
    # SIGINT as in a terminal's foreground job: a runner started in the background of a
    # script ignores SIGINT, and the child would inherit that (Python then installs no Ctrl-C
    # handler at all)
    return subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def _wait_for_lammps(proc: subprocess.Popen, want: int, timeout: float = 60) -> set[int]:
    """The process tree once ``want`` real LAMMPS ranks run (their command line has -in)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        tree = _tree(proc.pid)
        ranks = [p for p in tree if p != proc.pid and _is_rank(p)]
        if len(ranks) >= want:
            time.sleep(0.5)  # let LAMMPS get into its run
            return _tree(proc.pid)
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.1)
    raise AssertionError("LAMMPS did not start")


def _cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")[:200]
    except OSError:
        return "?"


def _is_rank(pid: int) -> bool:
    """A real LAMMPS running an input (not the wrapper script, not ``lmp -h``)."""
    try:
        exe = os.readlink(f"/proc/{pid}/exe")
    except OSError:
        return False
    return os.path.basename(exe) == "lmp" and " -in " in _cmdline(pid)


@pytest.fixture(scope="module")
def built_plugin():
    """The plugin built before a signal test starts its clock (a build is not a run)."""
    return dem.plugin_path()


@needs_lammps
@pytest.mark.parametrize("caller,nproc,sig", [
    ("dem run", 1, signal.SIGINT), ("dem run", 2, signal.SIGTERM),
    ("run_input", 1, signal.SIGTERM), ("dem-study", 1, signal.SIGTERM),
    ("dem-study", 2, signal.SIGINT),
])
def test_a_signal_ends_the_whole_tree_and_removes_temp_files(tmp_path, built_plugin, caller, nproc,
                                                            sig):
    """Ctrl-C (SIGINT to the driver, as the terminal sends it) or SIGTERM stops a run within
    2 s on 1 and 2 ranks, from every caller; afterwards no process of the tree is alive (the
    wheel's lmp wrapper, the real lmp, mpirun and its proxies) and TMPDIR is empty."""
    if nproc > 1 and run_mod.available_cores() < 2:
        pytest.skip("one core")
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    src = tmp_path / "in.long"
    # the study's runner loads no plugin (the study's inputs do, in their coeffs file): without
    # the line LAMMPS stops at pair_style, on a quick machine before the signal is sent
    src.write_text((dem.plugin_load_line() + "\n" if caller == "dem-study" else "") + _LONG)
    if caller == "dem run":
        cmd = [sys.executable, "-m", "viscontact", "dem", "run", str(src), "--np", str(nproc),
               "--no-progress", "--json"]
    elif caller == "run_input":
        cmd = [sys.executable, "-c", "import sys; from viscontact import dem; "
               f"dem.run_input(sys.argv[1], np={nproc}, quiet=True)", str(src)]
    else:  # the study's runner, on this input
        cmd = [sys.executable, "-c", "import sys; from pathlib import Path; "
               "from viscontact.demstudy import engine; "
               "engine.input_path = lambda name: Path(sys.argv[1]); "
               f"engine.run_lammps('in.long', Path(sys.argv[2]), {{}}, np_={nproc})",
               str(src), str(tmp_path / "work")]
    proc = _start(cmd, tmp, tmp_path)
    tree = _wait_for_lammps(proc, nproc)
    t0 = time.monotonic()
    os.kill(proc.pid, sig)
    proc.communicate(timeout=30)
    elapsed = time.monotonic() - t0
    time.sleep(0.2)
    left = {p: _cmdline(p) for p in tree if _alive(p)}
    for pid in left:  # never leave an orphan behind, even when the test fails
        os.kill(pid, signal.SIGKILL)
    assert left == {}, f"still running after {sig.name}: {left}"
    print(f"{caller} np={nproc} {sig.name}: stopped in {elapsed:.2f} s")
    assert elapsed < 2.0, elapsed
    assert proc.returncode != 0
    if caller == "dem run":
        assert proc.returncode == (130 if sig == signal.SIGINT else 128 + sig)
    assert list(tmp.iterdir()) == []
