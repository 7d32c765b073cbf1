"""Table-driven fuzz test of the command line (issue 13): every command, every option.

Each case calls ``viscontact.cli.main`` in-process (stdout and stderr captured, a deadline
against hangs) from a directory that holds the user's own files, and asserts the rules of
README "Command line": exit 0 with valid output (JSON that parses, no nan), or exit 2 with
exactly one line on stderr and no traceback; after every call every user file is byte-identical.
The cases come from the parser itself (``OPTION_TABLE``: every option of every command, so a
new option is fuzzed without editing this file): each numeric option set to every value of
``VALUES``, each flag added, each name option given an unknown name or nothing, each output
option pointed at the user's files and directories, each option repeated or left without its
value; then the conflicting combinations listed in ``NONSENSE`` must exit 2.  Nested
subcommands (``dem plugin|coeff|run``) are commands of their own in the table.  ``dem run``
runs real, tiny LAMMPS inputs in-process (a handful per table: only the calls that pass every
check); its log follows the file rule (a user's ``INPUT.log`` is never overwritten).  A few
subprocess calls check what only a real process shows: the exit status of a closed pipe and
the absence of warnings.  ``scripts/fuzz_cli.py`` runs the same harness on random
combinations at a larger scale.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from conftest import SRC, run_cli
from dem_util import LMP_REASON
from fuzz_cli_harness import (  # scripts/fuzz_cli_harness.py, shared with scripts/fuzz_cli.py
    _NAN, BASES, EXTREMES, NEEDS_LAMMPS, NONSENSE, TINY_INPUT, USER_FILES, call, command_of,
    commands, lost_files, make_user_files, option_table, table_cases,
)

# ------------------------------------------------------------------ the tests

@pytest.fixture
def userdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path, make_user_files(tmp_path)


def test_every_option_of_every_command_is_in_the_table():
    table = option_table()
    names = {o.command for o in table}
    assert names == {"collide", "restitution", "calibrate", "sweep", "reproduce", "audit", "fit",
                     "dem plugin", "dem coeff", "dem run", "dem-study"}
    assert names == set(commands())  # every leaf of the subcommand tree has options
    slow = {"reproduce", "dem-study"}  # minutes per valid call: covered by NONSENSE only
    covered = {command_of(b) for b in BASES.values()} | slow
    assert covered == names
    assert all(o.kind != "number" or o.nargs in (None, "+", 3) for o in table)
    # the nested subcommands' own options are in the table, with their kinds
    kinds = {(o.command, o.flag): o.kind for o in table}
    assert kinds[("dem run", "input")] == "positional" and kinds[("dem run", "--log")] == "file"
    assert kinds[("dem run", "--np")] == kinds[("dem coeff", "--friction")] == "number"
    assert kinds[("dem coeff", "--wall")] == "name" and kinds[("dem plugin", "--rebuild")] == "flag"
    assert kinds[("dem coeff", "--units")] == "choice" and kinds[("dem coeff", "--type")] == "name"
    cases = table_cases()
    for command in names:
        assert sum(command_of(c) == command for c in cases) > 5, command


def test_table_obeys_the_rules(userdir):
    root, files = userdir
    cases = table_cases()
    assert len(cases) > 700
    failures = []
    for argv in cases:
        o = call(argv)
        lost = lost_files(root, files)
        if o.problems or lost:
            failures.append(f"{' '.join(map(repr, argv))}: {'; '.join(o.problems + [f'lost {lost}'] * bool(lost))}")
            make_user_files(root)
        if argv in list(BASES.values()) and o.status != 0 and not (
                LMP_REASON and command_of(argv).startswith(NEEDS_LAMMPS)):
            failures.append(f"{argv}: the valid base call failed: {o.err.strip()}")
    assert not failures, f"{len(failures)} of {len(cases)} calls broke the rules:\n" + "\n".join(
        failures[:40])


@pytest.mark.parametrize("argv", EXTREMES, ids=lambda a: " ".join(a)[:70])
def test_extremes(userdir, argv):
    root, files = userdir
    o = call(argv)
    assert lost_files(root, files) == []
    assert not o.problems, o.problems


def test_dem_run_inputs_that_cannot_be_read(userdir):
    """A FIFO, a dangling link, a file without read permission (readable anyway by root), an
    empty file: one line and exit 2, or a run (exit 0) where LAMMPS can read it; never more."""
    root, files = userdir
    os.mkfifo(root / "in.fifo")
    (root / "in.link").symlink_to(root / "no-such-target.in")
    (root / "in.locked").write_bytes(TINY_INPUT)
    (root / "in.locked").chmod(0)
    (root / "in.empty").write_bytes(b"")
    for name, statuses in (("in.fifo", {2}), ("in.link", {2}), ("in.locked", {0, 2}),
                           ("in.empty", {0})):
        o = call(["dem", "run", name, "--no-progress", "--json"], deadline=60)
        if LMP_REASON and o.status == 2:
            continue  # no LAMMPS: the one line says what to install
        assert o.status in statuses and not o.problems, (name, o.status, o.err, o.problems)
        if o.status == 2:
            assert ("not a file" in o.err or "does not exist" in o.err
                    or "ERROR" in o.err), (name, o.err)
    assert lost_files(root, files) == []


@pytest.mark.parametrize("argv,none", [
    (["audit", "--formula", "flores", "--e", "1e-3"],
     {"delivered_e", "error"}),  # the formula's alpha 1598.4 > 1000
    (["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "1e-3"],
     {"input_for_target"}),  # the LAMMPS Tsuji curve ends at alpha 1.273
    (["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "0.1",
      "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e6", "--value", "1e308"],
     {"delivered_e", "error"}),  # eta_n0 1e308 kg/s is alpha ~ 1.6e306
    (["audit", "--formula", "schwager-poschel", "--e", "0.3"],
     {"alpha", "delivered_e", "error"}),  # the series has no alpha below e = 0.5833
])
def test_audit_value_that_does_not_exist_is_none(userdir, argv, none):
    """No nan: JSON null, "none" in the text with a note line that says why (docs/audit.md)."""
    text = call(argv)
    assert text.status == 0 and not text.problems, (text.err, text.problems)
    assert "none" in text.out and "note: " in text.out and not _NAN.search(text.out)
    doc = json.loads(call(argv + ["--json"]).out)
    assert {k for k, v in doc.items() if v is None} - {"p", "derived_for", "T"} == none
    assert doc["note"] and ("outside the domain [0, 1000]" in doc["note"]
                            or "no alpha" in doc["note"] or "no input gives" in doc["note"])


@pytest.mark.parametrize("argv", NONSENSE, ids=lambda a: " ".join(a)[:60] or "(nothing)")
def test_nonsense_exits_2_with_one_line(userdir, argv):
    root, files = userdir
    o = call(argv)
    assert o.status == 2, (o.status, o.err)
    assert not o.problems, o.problems
    assert lost_files(root, files) == []


def test_outputs_follow_the_file_rule(userdir):
    """The same output twice: the second needs --force, and --force replaces it; the path
    printed is the path written; a user's file under the name is never replaced."""
    root, files = userdir
    runs = [
        (["collide", "--law", "KK", "--alpha", "0.3", "--plot", "c.png"], ["c.png"]),
        (["sweep", "--ball", "OLB", "--law", "KK", "--num", "3", "--plot", "s.png",
          "--csv", "s.csv", "--json-out", "s.json"], ["s.png", "s.csv", "s.json"]),
        (["audit", "--all", "--grid", "0.5", "--no-plots", "--out", "a"], ["a/formulas.csv"]),
        (["fit", "--example", "--mass", "0.1547", "--drop-height", "0.15", "--laws", "KK",
          "--quiet", "--out", "f"], ["f/fit.json", "f/fit_example_drop.png"]),
    ]
    for argv, made in runs:
        first = call(argv)
        assert first.status == 0 and not first.problems, first.err
        for name in made:
            assert (root / name).is_file(), name
        again = call(argv)
        assert again.status == 2 and "--force" in again.err, again.err
        forced = call(argv + ["--force"])
        assert forced.status == 0, forced.err
    out = call(["sweep", "--ball", "OLB", "--law", "KK", "--num", "3", "--plot", "s.png",
                "--force"])
    assert out.err.strip() == "plot written to s.png"
    assert call(["collide", "--law", "KK", "--alpha", "0.3", "--plot", "s.png",
                 "--force"]).status == 2  # sweep's plot is not collide's to replace
    (root / "a" / "formulas.csv").write_text("edited by the user\n")
    edited = call(["audit", "--all", "--grid", "0.5", "--no-plots", "--out", "a", "--force"])
    assert edited.status == 2 and "changed since" in edited.err
    assert (root / "a" / "formulas.csv").read_text() == "edited by the user\n"
    assert lost_files(root, files) == []


def test_markers_are_recognised(tmp_path):
    from viscontact._support import outputs

    png = tmp_path / "x.png"
    outputs.write_png(str(png), "collide", False, "--plot",
                      lambda p: p.write_bytes(_tiny_png()))
    assert outputs.written_by(png) == "collide"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import zlib
    # every chunk's CRC is valid: the stamped file is still a well-formed PNG
    data, i = png.read_bytes(), 8
    while i < len(data):
        n = int.from_bytes(data[i:i + 4], "big")
        assert zlib.crc32(data[i + 4:i + 8 + n]) == int.from_bytes(data[i + 8 + n:i + 12 + n], "big")
        i += 12 + n
    csv_path = tmp_path / "x.csv"
    outputs.write_text(str(csv_path), "sweep", False, "--csv", "a,b\n")
    assert csv_path.read_text().startswith("# written by viscontact sweep ")
    assert outputs.written_by(csv_path) == "sweep"
    js = tmp_path / "x.json"
    outputs.write_json(str(js), "sweep", False, "--json", {"a": 1})
    assert json.loads(js.read_text())["a"] == 1 and outputs.written_by(js) == "sweep"
    (tmp_path / "user.csv").write_text("# written by someone else\n")
    assert outputs.written_by(tmp_path / "user.csv") is None


def _tiny_png() -> bytes:
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return (len(data).to_bytes(4, "big") + kind + data
                + zlib.crc32(kind + data).to_bytes(4, "big"))

    ihdr = (1).to_bytes(4, "big") * 2 + bytes([8, 0, 0, 0, 0])
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(b"\x00\x00")) + chunk(b"IEND", b""))


# ------------------------------------------------------------------ real processes

def test_closed_pipe_is_quiet():
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.run(
        f"'{sys.executable}' -m viscontact collide --law Jian --alpha 0.3 --beta 0.5 --json "
        "--histories | head -1; echo \"status ${PIPESTATUS[0]}\" >&2",
        shell=True, executable="/bin/bash", env=env, capture_output=True, text=True, timeout=120)
    assert proc.stdout == "{\n"
    assert proc.stderr == "status 141\n"  # nothing but the status of the viscontact process


@pytest.mark.parametrize("args", [
    ["collide", "--law", "KK", "--alpha", "0.3", "--plot", "D"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.7", "--value", "nan"],
    ["sweep", "--ball", "OLB", "--speeds", "1", "--num", "5"],
    ["calibrate", "--law", "KK", "--e", "0.5", "--e", "0.6"],
])
def test_one_line_from_a_real_process(tmp_path, args):
    make_user_files(tmp_path)
    proc = run_cli(*args, cwd=tmp_path, timeout=120)
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1, proc.stderr
    assert proc.stdout == ""
    assert lost_files(tmp_path, USER_FILES) == []


def test_audit_then_reproduce_share_the_default_directory(tmp_path, monkeypatch):
    """``audit --all`` writes into viscontact-report/audit by default: a report can still go
    into viscontact-report afterwards (it holds only viscontact output), a user file cannot."""
    from viscontact._support.outputs import OutputDir

    monkeypatch.chdir(tmp_path)
    assert call(["audit", "--all", "--grid", "0.5", "--no-plots"]).status == 0
    with OutputDir("viscontact-report", "reproduce", False) as out:
        (out.staging / "index.html").write_text("report\n")
    assert (tmp_path / "viscontact-report" / "audit" / "formulas.csv").is_file()
    (tmp_path / "viscontact-report" / "audit" / "mine.txt").write_text("mine\n")
    assert call(["audit", "--all", "--grid", "0.5", "--no-plots", "--force"]).status == 0
    assert (tmp_path / "viscontact-report" / "audit" / "mine.txt").read_text() == "mine\n"
