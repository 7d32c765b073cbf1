"""A fuzz campaign over the command line: the test table plus random option combinations.

    python3 scripts/fuzz_cli.py [--n 1500] [--seed 0] [--deadline 30] [--no-table] [--show 20]

Runs every case of ``tests/cli/test_fuzz_cli.py`` (every option of every command with extreme,
malformed and conflicting values) and ``--n`` random calls (a quick valid call of a command
with one to four random changes: an option set to a random value from subnormal to 1e308,
nan, inf, negative, empty or non-numeric, a flag added, a name misspelt, an output pointed at
the user's files, an option repeated, removed or left without its value), in-process in a
scratch directory that holds user files, with the same checks as the test.  Prints the counts:
calls, exit statuses, errors by kind, tracebacks (internal errors), hangs, the slowest calls,
nan or e outside [0, 1] in the outputs, user files lost, and the calls that broke a rule.
Exit status 1 when any call broke a rule.
"""

from __future__ import annotations

import argparse
import collections
import os
import random
import re
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

import fuzz_cli_harness as T  # the harness and the option table (scripts/fuzz_cli_harness.py)

_WORDS = ("Foo", "", "kk", "KK ", "jian", "all", "-", "--", "é", "1", "x" * 300)


def random_number(rng: random.Random) -> str:
    kind = rng.random()
    if kind < 0.25:
        return rng.choice(T.VALUES)
    if kind < 0.35:
        return rng.choice(("1e-310", "5e-324", "1.7976931348623157e308", "-0", "+1", "1_0",
                           " 1", "0x10", "1e", "--1", "1,5"))
    sign = "-" if rng.random() < 0.15 else ""
    return f"{sign}{10 ** rng.uniform(-12, 12):.6g}" if rng.random() < 0.7 else \
        f"{sign}1e{rng.randint(-330, 308)}"


def _type_spec(rng: random.Random) -> str:
    """A random ``--type`` value: known and unknown keys, odd numbers, ranges, separators."""
    keys = rng.sample(("E", "nu", "density", "d", "rho", "e", ""), rng.randint(0, 4))
    parts = []
    for k in keys:
        v = random_number(rng) if rng.random() < 0.8 else f"{random_number(rng)}:{random_number(rng)}"
        parts.append(f"{k}={v}" if rng.random() < 0.9 else k)
    return ",".join(parts)


def _wall_words(rng: random.Random) -> list[str]:
    """Random ``--wall`` words: a geometry (or an unknown one) and a material."""
    style = rng.choice(("zplane", "xplane", "yplane", "zcylinder", "sphere", ""))
    words = [style] if style else []
    words += [rng.choice(("NULL", random_number(rng))) for _ in range(rng.choice((0, 1, 2, 3)))]
    words += rng.choice(([], ["rigid"], ["same"], [random_number(rng), random_number(rng)], ["glass"]))
    return words


#: LAMMPS type specs, valid and not (full-width digits, 20 digits, reversed ranges)
_TYPE_SPECS = ("* *", "1 2", "2 1", "1*3 *", "0 0", "2*1 *", "\uff11 \uff11",
               "12345678901234567890 1", "1** 1", "* ", "1 2 3", "-1 1")
#: option -> a generator of its values (the options whose values have a syntax of their own)
_SPECIAL = {
    "--type": lambda rng: [_type_spec(rng)],
    "--wall": _wall_words,
    "--types": lambda rng: [rng.choice(_TYPE_SPECS)],
    "--e-pair": lambda rng: [rng.choice(("1", "2", "3", "0", "\uff11")) for _ in range(2)] + [random_number(rng)],
    "--e-wall": lambda rng: [rng.choice(("1", "2", "3", "0", "-1")), random_number(rng)],
}


def mutate(rng: random.Random, argv: list[str], options: list[T.Option]) -> list[str]:
    """One random change of ``argv`` (its command's options only)."""
    opts = [o for o in options if o.command == T.command_of(argv) and o.kind != "positional"]
    opt = rng.choice(opts)
    n = T._count(opt.nargs) if opt.nargs not in ("+", "*") else rng.choice((1, 1, 2, 3))
    r = rng.random()
    if r < 0.06 and opt.flag in argv:  # remove the option
        i = argv.index(opt.flag) + 1
        j = i
        while j < len(argv) and not argv[j].startswith("--"):
            j += 1
        return argv[:i - 1] + argv[j:]
    if r < 0.10:
        return argv + [opt.flag]  # no value (or a flag)
    if r < 0.14:
        return argv + [rng.choice(("--bogus", "--alph", "-x", "extra", "--"))]
    if opt.kind == "flag":
        return argv + [opt.flag]
    if opt.command == "dem coeff" and opt.flag in _SPECIAL:
        return argv + [opt.flag] + _SPECIAL[opt.flag](rng)  # these options repeat
    old = _number_after(argv, opt.flag)
    if opt.kind == "number" and old is not None and rng.random() < 0.5:
        # near the valid value: the solvers' range, rather than the parser's refusals
        values = [f"{old * 10 ** rng.uniform(-4, 4):.6g}" for _ in range(n)]
    elif opt.kind == "number":
        values = [random_number(rng) for _ in range(n)]
    elif opt.kind == "choice":
        values = [rng.choice((*opt.choices, "bogus", ""))]
    elif opt.kind in ("file", "dir"):
        values = [rng.choice([v for v in T.PATHS[opt.kind] if v != "/" or opt.command != "dem run"])]
        if rng.random() < 0.5:
            argv = argv + ["--force"]
    else:
        values = [rng.choice(_WORDS) for _ in range(n)]
    if rng.random() < 0.1 and opt.flag in argv:
        return argv + [opt.flag] + values  # repeated
    return T.with_option(argv, opt.flag, values)


def _number_after(argv: list[str], flag: str) -> float | None:
    try:
        return float(argv[argv.index(flag) + 1])
    except (ValueError, IndexError):
        return None


def random_cases(rng: random.Random, n: int) -> list[list[str]]:
    options = T.option_table()
    bases = list(T.BASES.values())
    cases = []
    for _ in range(n):
        argv = list(rng.choice(bases))
        for _ in range(rng.choice((1, 1, 2, 3, 4))):
            argv = mutate(rng, argv, options)
        cases.append(argv)
    return cases


def _kind(err: str) -> str:
    """An error line reduced to its kind: the message without numbers, names and paths."""
    line = err.strip().splitlines()[-1] if err.strip() else ""
    msg = line.split("error:", 1)[-1]
    msg = re.sub(r"'[^']*'|\"[^\"]*\"", "'…'", msg)
    msg = re.sub(r"[-+]?\d[\w.+-]*", "N", msg)
    return " ".join(msg.split()[:9])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=1500, help="random calls (besides the table)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--deadline", type=float, default=30.0, help="seconds per call")
    ap.add_argument("--no-table", action="store_true", help="random calls only")
    ap.add_argument("--show", type=int, default=25, help="rule breakers to list")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    cases = ([] if a.no_table else T.table_cases()) + random_cases(rng, a.n)
    statuses: collections.Counter = collections.Counter()
    kinds: collections.Counter = collections.Counter()
    problems: collections.Counter = collections.Counter()
    breakers: list[tuple[list[str], list[str]]] = []
    slow: list[tuple[float, list[str]]] = []
    lost_total = 0
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="viscontact-fuzz-") as scratch:
        root = Path(scratch)
        os.chdir(root)
        files = T.make_user_files(root)
        for i, argv in enumerate(cases):
            o = T.call(argv, deadline=a.deadline)
            lost = T.lost_files(root, files)
            statuses["hang" if o.status is None else o.status] += 1
            if o.status == 2:
                kinds[_kind(o.err)] += 1
            slow.append((o.seconds, argv))
            found = list(o.problems)
            if lost:
                lost_total += len(lost)
                found.append(f"lost {lost}")
                T.make_user_files(root)
            for p in found:
                problems[p.split(":")[0] if not p.startswith("lost") else "file lost"] += 1
            if found:
                breakers.append((argv, found))
            if (i + 1) % 500 == 0:
                print(f"... {i + 1} calls, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
        os.chdir(Path.home())
    total = time.perf_counter() - t0
    slow.sort(key=lambda s: -s[0])
    print(f"calls: {len(cases)} ({'' if a.no_table else 'table + '}{a.n} random, seed {a.seed}) "
          f"in {total:.1f} s")
    print("exit statuses: " + ", ".join(f"{k}: {v}" for k, v in sorted(
        statuses.items(), key=lambda kv: str(kv[0]))))
    print(f"tracebacks / internal errors (exit 1 or an escape): "
          f"{statuses.get(1, 0) + statuses.get(-1, 0)}")
    print(f"hangs (over {a.deadline:g} s): {statuses.get('hang', 0)}")
    print(f"nan in outputs: {problems.get('nan in the output', 0)}; e outside [0, 1]: "
          f"{sum(v for k, v in problems.items() if 'outside [0, 1]' in k)}; "
          f"files lost: {lost_total}")
    print("slowest calls: " + "; ".join(f"{s:.2f} s {' '.join(argv)}" for s, argv in slow[:3]))
    print(f"errors by kind (exit 2; {len(kinds)} kinds, most frequent first):")
    for k, v in kinds.most_common(20):
        print(f"  {v:5d}  {k}")
    print(f"rule breakers: {len(breakers)} calls ({dict(problems)})")
    for argv, found in breakers[:a.show]:
        print(f"  {' '.join(repr(x) if not x or ' ' in x else x for x in argv)}: {'; '.join(found)[:200]}")
    return 1 if breakers else 0


if __name__ == "__main__":
    raise SystemExit(main())
