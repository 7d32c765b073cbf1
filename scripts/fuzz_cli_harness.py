"""The harness of the command-line fuzz: the values, the user's files, one guarded call, the
rules a result must obey and the table of every option of every command (read from the parser
itself).  Used by tests/cli/test_fuzz_cli.py and scripts/fuzz_cli.py.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
import json
import re
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path

from viscontact.cli import build_parser, main

#: values every numeric option is given
VALUES = ("nan", "inf", "-inf", "-1", "0", "1e-320", "1e308", "", "abc", "1e-3")
#: a LAMMPS input of one sphere, ten steps (the plugin loaded by dem run)
TINY_INPUT = b"""units si
atom_style sphere
region box block 0 1 0 1 0 1
create_box 1 box
create_atoms 1 single 0.5 0.5 0.5
set type 1 diameter 0.1 density 1000
comm_modify vel yes
pair_style viscontact
pair_coeff * * hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 end force tangential none
thermo 5
run 10
"""
#: the user's own files in the working directory: never to be touched
USER_FILES = {
    "mine.csv": b"time [ms],force [N]\n0,0\n",
    "mine.png": b"\x89PNG\r\n\x1a\n a user's picture",
    "plot.png": b"a user's plot.png",
    "out.csv": b"a user's out.csv",
    "out.json": b'{"mine": true}',
    "D.png": b"beside the directory D",
    "D/data.txt": b"a user's data",
    "D/fit.json": b"a user's fit.json",
    "D/formulas.csv": b"a user's formulas.csv",
    "viscontact-report/notes.txt": b"a user's notes in the default report directory",
    # LAMMPS inputs for dem run: a tiny valid one, one with a LAMMPS error, one whose log
    # (INPUT.log, where dem run writes by default) is the user's own
    "in.tiny": TINY_INPUT,
    "in.bad": b"units si\nfrobnicate 3\n",
    "in.var": b"units si\nprint ${undefined_variable}\n",
    "in.user": TINY_INPUT,
    "in.user.log": b"the user's own log of in.user",
}
USER_DIRS = ("empty",)
#: values of output options: the user's files and directories, odd names, a new name
PATHS = {
    "file": ("plot.png", "mine.png", "mine.csv", "D", "D.png", "empty", "", "-", "x", "/",
             "no/such/dir/x.png", "new.png", "new.png/"),
    "dir": ("D", "D.png", "mine.csv", "", "/", ".", "viscontact-report", "empty/sub"),
}
#: a valid, quick call of each command (the fuzzed options are changed or added to these)
BASES = {
    "collide": ["collide", "--law", "KK", "--alpha", "0.3"],
    "collide Jian": ["collide", "--law", "Jian", "--alpha", "0.3", "--beta", "0.5", "--json"],
    "collide power": ["collide", "--law", "power", "--p", "0.75", "--alpha", "0.3"],
    "restitution": ["restitution", "--law", "KK", "--alpha", "0.1", "0.2"],
    "restitution Jian": ["restitution", "--law", "Jian", "--alpha", "0.1", "--beta", "0.5",
                         "--json"],
    "calibrate": ["calibrate", "--law", "Hunt", "--e", "0.5"],
    "calibrate physical": ["calibrate", "--law", "KK", "--mass", "0.1547", "--k-hertz",
                           "1.688e6", "--v", "1.716", "--e", "0.463"],
    "calibrate E nu": ["calibrate", "--law", "Li", "--mass", "0.1", "--radius", "0.03", "--E",
                       "1e7", "--nu", "0.4", "--drop-height", "0.1", "--e", "0.6", "--json"],
    "sweep c": ["sweep", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1.688e6", "--c", "500",
                "--num", "3"],
    "sweep e": ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "0.5", "1"],
    "audit formula": ["audit", "--formula", "flores", "--e", "0.5"],
    "audit engine": ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.7"],
    "audit physical": ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7",
                       "--m-eff", "0.1", "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e6"],
    "audit all": ["audit", "--all", "--grid", "0.5", "--no-plots", "--out", "audits/new"],
    "fit": ["fit", "--example", "--mass", "0.1547", "--drop-height", "0.15", "--laws", "KK",
            "--no-progress", "--json"],
    "dem plugin": ["dem", "plugin", "--json"],
    "dem coeff e": ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8",
                    "--vref", "1"],
    "dem coeff Jian c0": ["dem", "coeff", "--law", "Jian", "--E", "1e7", "--nu", "0.3", "--c0",
                          "100", "--tau", "1e-4", "--friction", "0.5", "--wall-E", "1e9",
                          "--wall-nu", "0.2", "--json"],
    "dem coeff power": ["dem", "coeff", "--law", "power", "--p", "0.75", "--E", "1e7", "--nu",
                        "0.3", "--alpha", "0.3", "--vref", "1", "--wall", "rigid", "--types",
                        "1 2"],
    "dem coeff types": ["dem", "coeff", "--law", "Ts", "--e", "0.8", "--vref", "1", "--type",
                        "E=1e7,nu=0.3,density=2500,d=0.002:0.004", "--type", "E=2e8,nu=0.2",
                        "--e-pair", "1", "2", "0.7", "--e-wall", "2", "0.6", "--wall", "zcylinder",
                        "0.05", "rigid", "--units", "cgs"],
    "dem run": ["dem", "run", "in.tiny", "--no-progress", "--json", "--force"],
}
#: the commands that need LAMMPS and a C++ compiler (without them: one line, exit 2)
NEEDS_LAMMPS = ("dem plugin", "dem coeff", "dem run")
#: option combinations that mean nothing or conflict: each must exit 2 with one line
NONSENSE = [
    ["calibrate", "--mass", "0.1547", "--k-hertz", "1.688e6", "--v", "1.716", "--e", "0.463",
     "--law", "KK", "--beta", "0.5"],
    ["calibrate", "--law", "KK", "--e", "0.5", "--beta", "0.5"],
    ["calibrate", "--mass", "0.1", "--k-hertz", "1e6", "--radius", "0.03", "--v", "1", "--e", "0.5"],
    ["sweep", "--ball", "OLB", "--speeds", "1", "--num", "5"],
    ["sweep", "--ball", "OLB", "--speeds", "1", "--v-min", "0.5"],
    ["sweep", "--ball", "OLB", "--num", "1", "--v-min", "0.5", "--v-max", "1"],
    ["sweep", "--law", "KK", "--mass", "0.1", "--k-hertz", "1e6", "--c", "5", "--beta", "0.5"],
    ["sweep", "--ball", "OLB", "--csv", "-", "--json", "-"],
    ["sweep", "--law", "KK", "--mass", "0.1", "--k-hertz", "1e6", "--c", "5", "--v", "1"],
    ["audit", "--formula", "flores", "--e", "0.5", "--p", "0.5"],
    ["sweep", "--ball", "OLB", "--csv", "same.out", "--json-out", "same.out"],
    ["sweep", "--ball", "OLB", "--force"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--histories"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--force"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--plot", ""],
    ["collide", "--law", "KK", "--alpha", "0.3", "--plot", "D"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--plot", "plot.png", "--force"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--alpha", "0.4"],
    ["collide", "--law", "KK", "--alpha", "0.3", "--beta", "1"],
    ["restitution", "--law", "KK", "--alpha", "0.3", "--csv", "--json"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.7", "--value", "nan"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "0.7", "--out", "x"],
    ["audit", "--formula", "flores", "--e", "0.5", "--no-plots"],
    ["audit", "--all", "--law", "KK"],
    ["audit", "--all", "--out", "D"],
    ["fit", "--example", "--mass", "0.1547", "--drop-height", "0.15", "--force"],
    ["fit", "--example", "--mass", "0.1547", "--drop-height", "0.15", "--out", "D"],
    ["fit", "--example", "--mass", "0.1547", "--drop-height", "0.15", "--laws", "KK", "--laws", "Li"],
    ["fit", "mine.csv", "--mass", "0.1547", "--drop-height", "0.15"],
    ["reproduce", "--out", "/"],
    ["reproduce", "--out", "D", "--force"],
    ["reproduce", "--out", "viscontact-report"],
    ["reproduce", "--out", ""],
    ["reproduce", "--out", "mine.csv"],
    ["reproduce", "--no-progress", "--quiet"],
    ["reproduce", "--bogus"],
    # dem-study runs for minutes: only calls that must stop before any work
    ["dem-study", "--out", "/"],
    ["dem-study", "--out", "D", "--force"],
    ["dem-study", "--out", ""],
    ["dem-study", "--out", "mine.csv"],
    ["dem-study", "--out", "viscontact-report"],
    ["dem-study", "--np", "0"],
    ["dem-study", "--np", "257"],
    ["dem-study", "--np", "two"],
    ["dem-study", "--np", "2.5"],
    ["dem-study", "--quick", "--quick"],
    ["dem-study", "--bogus"],
    ["frobnicate"],
    [],
    ["dem"],
    ["dem", "frobnicate"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1",
     "--c0", "5"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1",
     "--beta", "0.5"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--tau", "1"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--vref", "1"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--p", "1"],
    ["dem", "coeff", "--law", "power", "--E", "1e7", "--nu", "0.3", "--c0", "5"],
    ["dem", "coeff", "--law", "power", "--p", "681", "--E", "1e7", "--nu", "0.3", "--alpha",
     "12", "--vref", "1"],
    ["dem", "coeff", "--law", "Jian", "--E", "1e7", "--nu", "0.3", "--e", "0.8", "--vref", "1"],
    ["dem", "coeff", "--law", "Hunt", "--E", "1e7", "--nu", "0.3", "--e", "1e-4", "--vref", "1"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--wall-E", "1e9"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--wall", "same",
     "--wall-E", "1e9", "--wall-nu", "0.2"],
    ["dem", "coeff", "--law", "KK", "--E", "1e7", "--nu", "0.3", "--c0", "5", "--friction",
     "11"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3", "--E", "1e7"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3,E=2"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3,d=1:"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3,d=2:1,density=1"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3",
     "--types", "1 2"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3",
     "--e-pair", "1", "2", "0.7"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3",
     "--e-pair", "1", "1", "0.7", "--e-pair", "1", "1", "0.6"],
    ["dem", "coeff", "--law", "KK", "--alpha", "0.3", "--vref", "1", "--type", "E=1e7,nu=0.3",
     "--e-pair", "1", "1", "0.7"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--e-wall", "1", "0.5"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--type", "E=1e7,nu=0.3",
     "--type", "E=1e8,nu=0.2", "--wall", "same"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--wall", "zplane", "1", "0"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--wall", "zplane", "NULL", "NULL"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--wall", "zcylinder", "nan"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--wall", "zcylinder", "-1"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--wall", "sphere", "1"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--types", "0 0"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--types", "2*1 *"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--types", "\uff11 \uff11"],
    ["dem", "coeff", "--law", "KK", "--e", "0.8", "--vref", "1", "--E", "1e7", "--nu", "0.3",
     "--types", "12345678901234567890 1"],
    ["dem", "plugin", "--bogus"],
    ["dem", "run"],
    ["dem", "run", "in.user"],  # its log in.user.log is the user's
    ["dem", "run", "in.user", "--force"],  # ... not even with --force
    ["dem", "run", "in.tiny", "--log", "in.user.log", "--force"],
    ["dem", "run", "in.tiny", "--log", "mine.csv"],
    ["dem", "run", "in.tiny", "--log", "no/such/dir/x.log"],
    ["dem", "run", "in.tiny", "--log", "/proc/x.log"],  # unwritable: one line naming it
    ["dem", "run", "in.bad", "--force"],  # a LAMMPS error: one line
    ["dem", "run", "in.var", "--force"],  # an undefined variable: one line
    ["dem", "run", "mine.png", "--force"],  # not a LAMMPS input (not even text)
    ["dem", "run", "mine.csv", "--force"],
    ["dem", "run", "D"],
    ["dem", "run", "missing.in"],
    ["dem", "run", "in.tiny", "--np", "0", "--force"],
    ["dem", "run", "in.tiny", "--np", "-2", "--force"],
    ["dem", "run", "in.tiny", "--np", "257", "--force"],
    ["dem", "run", "in.tiny", "--np", "99999999999999999999", "--force"],
    ["dem", "run", "in.tiny", "--np", "2.5", "--force"],
    ["dem", "run", "in.tiny", "--np", "two", "--force"],
    ["dem", "run", "in.tiny", "--var", "1x", "3", "--force"],
    ["dem", "run", "in.tiny", "--var", "x", "a b", "--force"],
    ["dem", "run", "in.tiny", "--var", "x", "", "--force"],
    ["dem", "run", "in.tiny", "--var", "x", "1", "--var", "x", "2", "--force"],
    ["dem", "run", "in.tiny", "--var", "x", "--force"],
]
#: extreme values found by the first fuzz runs to break the rules inside the library (issue 13:
#: now refused by the parameter domain, or answered with "none" where a value does not exist);
#: ordinary cases of the table, kept because the table's own values do not all reach them
EXTREMES = [
    ["collide", "--law", "KK", "--alpha", "1e308"],
    ["collide", "--law", "power", "--p", "1e308", "--alpha", "0.3"],
    ["collide", "--law", "power", "--p", "0.75", "--alpha", "1e308"],
    ["calibrate", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1e-320", "--v", "1.716",
     "--e", "0.463"],
    ["sweep", "--law", "KK", "--mass", "1e-320", "--k-hertz", "1.688e6", "--c", "500", "--num", "3"],
    ["sweep", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1e-320", "--c", "500", "--num", "3"],
    ["sweep", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1e308", "--c", "500", "--num", "3"],
    ["sweep", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1.688e6", "--c", "500", "--num",
     "3", "--mass2", "1e-320"],
    ["sweep", "--law", "KK", "--mass", "0.1547", "--k-hertz", "1.688e6", "--c", "500", "--num",
     "3", "--v-max", "1e308"],
    ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "0.5", "1", "--mass", "1e-320"],
    ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "0.5", "1", "--k-hertz", "1e-320"],
    ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "0.5", "1", "--k-hertz", "1e308"],
    ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "0.5", "1", "--mass2", "1e-320"],
    ["sweep", "--law", "Jian", "--ball", "OLB", "--speeds", "1e308"],
    ["audit", "--formula", "flores", "--e", "1e-320"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "1e-320"],
    ["audit", "--engine", "lammps", "--damping", "tsuji", "--e", "1e-3"],
    ["audit", "--formula", "flores", "--e", "1e-3"],  # nan once alpha has a domain (1598 > max)
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "0.1",
     "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e6", "--value", "1e308"],  # likewise
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "1e-320",
     "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e6"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "1e308",
     "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e6"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "0.1",
     "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e-320"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "0.1",
     "--r-eff", "0.01", "--v", "1", "--k-hertz", "1e308"],
    ["audit", "--engine", "lammps", "--damping", "velocity", "--e", "0.7", "--m-eff", "0.1",
     "--r-eff", "0.01", "--v", "1e308", "--k-hertz", "1e6"],
    ["fit", "--example", "--mass", "1e-320", "--drop-height", "0.15", "--laws", "KK", "--no-progress",
     "--json"],
    ["fit", "--example", "--mass", "0.1547", "--drop-height", "1e-320", "--laws", "KK", "--no-progress",
     "--json"],
]
#: a deadline per call against hangs (generous: the first call of a kind may compile)
DEADLINE_S = 120.0


class Deadline(BaseException):
    """A call ran past its deadline (BaseException: the command line must not catch it)."""


@dataclass
class Outcome:
    argv: list[str]
    status: int | None
    out: str
    err: str
    seconds: float
    problems: list[str] = field(default_factory=list)


def _on_alarm(signum, frame):
    raise Deadline()


def call(argv: list[str], deadline: float = DEADLINE_S) -> Outcome:
    """``main(argv)`` in-process with captured output and a deadline; the rules checked."""
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _on_alarm)
    signal.setitimer(signal.ITIMER_REAL, deadline)
    t0 = time.perf_counter()
    status: int | None
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(list(argv))
            except SystemExit as exc:  # argparse: usage errors, --help
                status = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    except Deadline:
        status = None
    except BaseException as exc:  # noqa: BLE001 - any escape is a finding, reported below
        status = -1
        err.write(f"Traceback (escaped main): {type(exc).__name__}: {exc}\n")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    o = Outcome(list(argv), status, out.getvalue(), err.getvalue(), time.perf_counter() - t0)
    o.problems = rule_problems(o, deadline)
    return o


_NAN = re.compile(r"(?<![\w.])nan(?![\w])", re.IGNORECASE)


def rule_problems(o: Outcome, deadline: float = DEADLINE_S) -> list[str]:
    """What in one outcome breaks the rules (empty: it obeys them)."""
    if o.status is None:
        return [f"hang: still running after {deadline:g} s"]
    bad = []
    lines = o.err.splitlines()
    if "Traceback" in o.err:
        bad.append("traceback")
    if o.status == 2:
        if len(lines) != 1:
            bad.append(f"error in {len(lines)} lines on stderr")
        elif not lines[0].startswith("viscontact"):
            bad.append("error line does not start with 'viscontact'")
    elif o.status == 0:
        if "--help" not in o.argv and _NAN.search(o.out):
            bad.append("nan in the output")
        if "--json" in o.argv and o.out.lstrip().startswith("{"):
            try:
                doc = json.loads(o.out, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
            except ValueError as exc:
                bad.append(f"invalid JSON on stdout: {exc}")
            else:
                bad += [f"{k} = {v!r} outside [0, 1]" for k, v in _restitutions(doc)
                        if not 0.0 <= v <= 1.0]
    else:
        bad.append(f"exit status {o.status}" + (f": {lines[-1]}" if lines else ""))
    return bad


def _restitutions(doc) -> list[tuple[str, float]]:
    """Every restitution coefficient in a JSON document (keys e, delivered_e, e_fit)."""
    found = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            if k in ("e", "delivered_e", "e_fit") and isinstance(v, (int, float)):
                found.append((k, float(v)))
            elif k in ("e", "e_fit") and isinstance(v, list):
                found += [(k, float(x)) for x in v if isinstance(x, (int, float))]
            else:
                found += _restitutions(v)
    elif isinstance(doc, list):
        for v in doc:
            found += _restitutions(v)
    return found


# ------------------------------------------------------------------ the user's files

def make_user_files(root: Path) -> dict[str, bytes]:
    for name, data in USER_FILES.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_bytes(data)
    for d in USER_DIRS:
        (root / d).mkdir(exist_ok=True)
    return dict(USER_FILES)


def lost_files(root: Path, files: dict[str, bytes]) -> list[str]:
    """User files changed or gone, and user directories gone."""
    lost = [n for n, data in files.items()
            if not (root / n).is_file() or (root / n).read_bytes() != data]
    return lost + [d + "/" for d in USER_DIRS if not (root / d).is_dir()]


# ------------------------------------------------------------------ the table

@dataclass(frozen=True)
class Option:
    command: str
    flag: str
    kind: str  # "number", "flag", "choice", "name", "file", "dir", "positional"
    nargs: int | str | None
    choices: tuple[str, ...] = ()


def _option_kind(command: str, a: argparse.Action) -> str:
    if a.nargs == 0:
        return "flag"
    if a.type in (float, int):
        return "number"
    if a.choices:
        return "choice"
    if a.dest in ("plot", "log") or (command == "sweep" and a.dest in ("csv", "json", "json_out")):
        return "file"
    if a.dest == "out":
        return "dir"
    return "name"


@functools.lru_cache(maxsize=1)
def commands() -> dict[str, argparse.ArgumentParser]:
    """Every command, by its words ("collide", "dem run"), with its parser: the leaves of the
    tree of subcommands, nested ones included."""
    found: dict[str, argparse.ArgumentParser] = {}

    def walk(words: str, p: argparse.ArgumentParser) -> None:
        sub = next((a for a in p._actions if isinstance(a, argparse._SubParsersAction)), None)
        if sub is None:
            found[words] = p
            return
        for name, child in sub.choices.items():
            walk(f"{words} {name}".strip(), child)

    walk("", build_parser())
    return found


def command_of(argv: list[str]) -> str:
    """The command words at the start of ``argv`` ("dem run" for ``dem run in.x ...``)."""
    known = commands()
    for n in range(len(argv), 0, -1):
        if " ".join(argv[:n]) in known:
            return " ".join(argv[:n])
    return argv[0] if argv else ""


def option_table() -> list[Option]:
    """Every option of every command, from the parser (help and version excluded)."""
    table = []
    for command, p in commands().items():
        for a in p._actions:
            if isinstance(a, (argparse._HelpAction, argparse._VersionAction)):
                continue
            if not a.option_strings:
                table.append(Option(command, a.dest, "positional", a.nargs))
                continue
            table.append(Option(command, a.option_strings[0], _option_kind(command, a), a.nargs,
                                tuple(a.choices or ())))
    return table


def _count(nargs) -> int:
    return nargs if isinstance(nargs, int) else 1


def with_option(base: list[str], flag: str, values: list[str]) -> list[str]:
    """``base`` with ``flag`` set to ``values`` (replacing its values there, or appended)."""
    argv = list(base)
    if flag in argv:
        i = argv.index(flag) + 1
        j = i
        while j < len(argv) and not argv[j].startswith("--"):
            j += 1
        return argv[:i] + values + argv[j:]
    return argv + [flag] + values


def table_cases() -> list[list[str]]:
    """The cases: the bases, every option of their command fuzzed, and the nonsense."""
    cases: list[list[str]] = [list(b) for b in BASES.values()]
    options = option_table()
    for base in BASES.values():
        command = command_of(base)
        words = len(command.split())
        for opt in (o for o in options if o.command == command):
            if opt.kind == "positional":
                # the base's own positional (dem run INPUT) is replaced, else one is added
                has = len(base) > words and not base[words].startswith("-")
                rest = base[words + 1:] if has else base[words:]
                cases += [base[:words] + [v] + rest for v in ("mine.csv", "D", "", "missing.csv")]
                continue
            if opt.kind == "flag":
                cases.append(base + [opt.flag])
                continue
            n = _count(opt.nargs)
            if opt.kind == "number":
                cases += [with_option(base, opt.flag, [v] * n) for v in VALUES]
            elif opt.kind == "choice":
                cases += [with_option(base, opt.flag, [v]) for v in (*opt.choices, "bogus", "")]
            elif opt.kind in ("file", "dir"):
                for v in PATHS[opt.kind]:
                    if command == "dem run" and v == "/":
                        continue  # a directory: the log would really go to /in.tiny.log
                    cases += [with_option(base, opt.flag, [v]),
                              with_option(base, opt.flag, [v]) + ["--force"]]
            else:
                cases += [with_option(base, opt.flag, [v] * n) for v in ("Foo", "")]
            cases.append(base + [opt.flag])  # no value
            if opt.flag in base:
                i = base.index(opt.flag)
                cases.append(base + base[i: i + 1 + n])  # repeated
    cases += [list(b) + ["--bogus"] for b in BASES.values()]
    cases += [command_of(b).split() + ["--help"] for b in BASES.values()]
    cases += NONSENSE + EXTREMES
    unique = {tuple(c): c for c in cases}
    return list(unique.values())
