"""Start-up time of the ``viscontact`` command line once the caches are warm.

    python3 benchmarks/bench_startup.py [--repeat 7]

Each command runs in a fresh process (wall clock, best of --repeat, after one warm-up run
that fills the compiled-code and table caches). Printed next to the baseline measured in
the same run, a bare interpreter and ``python -c "import numpy"``, with the ratio to the
numpy baseline and to the target of issue 4: a cached ``viscontact collide ...`` answers
in under 1 s. The load average is printed because the machine is shared.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

TARGET_S = 1.0

#: (label, arguments after ``viscontact``, held to the target)
COMMANDS: list[tuple[str, list[str], bool]] = [
    ("collide Jian force", ["collide", "--law", "Jian", "--alpha", "0.3", "--beta", "0.5"], True),
    ("collide Jian overlap --json",
     ["collide", "--law", "Jian", "--alpha", "0.3", "--beta", "0.5", "--end", "overlap", "--json"],
     True),
    ("collide LH force", ["collide", "--law", "LH", "--alpha", "0.3"], True),
    ("collide Ts overlap", ["collide", "--law", "Ts", "--alpha", "0.3", "--end", "overlap"], True),
    ("collide KK force --json", ["collide", "--law", "KK", "--alpha", "0.3", "--json"], True),
    ("collide Li overlap", ["collide", "--law", "Li", "--alpha", "1.0", "--end", "overlap"], True),
    ("collide Hunt force", ["collide", "--law", "Hunt", "--alpha", "0.3"], True),
    ("collide power force", ["collide", "--law", "power", "--p", "0.75", "--alpha", "0.3"], True),
    ("--help", ["--help"], True),
    ("collide --help", ["collide", "--help"], True),
    ("fit --help", ["fit", "--help"], True),
    ("audit --help", ["audit", "--help"], True),
    ("restitution (tables)", ["restitution", "--law", "KK", "--alpha", "0.3"], False),
    ("calibrate (tables)", ["calibrate", "--law", "Hunt", "--e", "0.463"], False),
]


def viscontact_command() -> list[str]:
    """The installed console script next to this interpreter, else ``python -m viscontact``."""
    script = Path(sys.executable).with_name("viscontact")
    return [str(script)] if script.exists() else [sys.executable, "-m", "viscontact"]


def wall_time(argv: list[str], repeat: int) -> float:
    """Best wall-clock time of ``argv`` over ``repeat`` fresh processes; fails loudly."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        done = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        elapsed = time.perf_counter() - t0
        if done.returncode != 0:
            raise SystemExit(f"{' '.join(argv)} failed ({done.returncode}): {done.stderr.strip()}")
        best = min(best, elapsed)
    return best


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs per command; the best counts")
    args = ap.parse_args()
    cli = viscontact_command()
    for _, rest, _ in COMMANDS:  # warm-up: compile and build tables outside the timing
        wall_time(cli + rest, 1)
    bare = wall_time([sys.executable, "-c", "pass"], args.repeat)
    numpy = wall_time([sys.executable, "-c", "import numpy"], args.repeat)
    print(f"command: {' '.join(cli)}; best of {args.repeat}; load average "
          + " ".join(f"{x:.2f}" for x in os.getloadavg()))
    print(f"baseline: python -c pass {bare:.3f} s, python -c 'import numpy' {numpy:.3f} s")
    print(f"{'command':<30} {'wall [s]':>9} {'/ numpy':>8} {'/ target':>9}")
    over = []
    for label, rest, held in COMMANDS:
        t = wall_time(cli + rest, args.repeat)
        verdict = ("ok" if t < TARGET_S else "OVER") if held else "(no target)"
        if held and t >= TARGET_S:
            over.append(label)
        print(f"{label:<30} {t:9.3f} {t / numpy:8.2f} {t / TARGET_S:9.2f}  {verdict}")
    print(f"target: under {TARGET_S:g} s once cached (issue 4, item 3); "
          + ("all met" if not over else f"over: {', '.join(over)}"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
