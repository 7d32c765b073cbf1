"""A fuzz campaign over the Python API (issue 13): many malformed and extreme calls, counted.

    python3 scripts/fuzz_api.py [--calls 5000] [--seed 1] [--heavy 0.01] [--timeout 60]

Each call takes a public function (``scripts/fuzz_api_targets.py``: every function of
``viscontact.__all__``, ``viscontact.fit`` and ``viscontact.audit``) with a valid set of
arguments and replaces one or two of them by an unusual value (subnormal to 1e308, NaN, inf,
wrong types, odd shapes) or a random float of random sign and magnitude.  It prints the
calls, the outcomes (valid result, ValueError, any other exception = a traceback), the
slowest calls, NaN results and values outside their range, and the calls that ran past
``--timeout`` seconds (hangs).  Exit status 1 if any call broke the rules.
"""

from __future__ import annotations

import argparse
import collections
import math
import signal
import sys
import time
import traceback

import numpy as np

import fuzz_api_targets as F  # shared with tests/physics/test_domain_fuzz.py


class _Hang(Exception):
    pass


def _alarm(_sig, _frame):
    raise _Hang()


def random_value(rng: np.random.Generator):
    """A value from the pool, a moderate float (1e-3 ... 1e3: mostly inside the domain), or a
    random float: sign, magnitude 1e-320 ... 1e308."""
    u = rng.random()
    if u < 0.4:
        return F.VALUES[int(rng.integers(len(F.VALUES)))]
    if u < 0.7:
        return float(10.0 ** rng.uniform(-3, 3))
    mag = 10.0 ** rng.uniform(-320, 308.25)
    return float(mag if rng.random() < 0.8 else -mag)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--heavy", type=float, default=0.01,
                    help="share of calls to the fit targets (each valid call fits: seconds)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds before a call is a hang")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    targets = F.targets()
    light = [t for t in targets if not t.heavy]
    heavy = [t for t in targets if t.heavy]
    signal.signal(signal.SIGALRM, _alarm)

    outcomes: collections.Counter[str] = collections.Counter()
    per_target: dict[str, collections.Counter[str]] = collections.defaultdict(collections.Counter)
    slow: list[tuple[float, str]] = []
    broken: list[str] = []
    nan_count = out_of_range = hangs = 0
    t_start = time.perf_counter()
    for _ in range(args.calls):
        pool = heavy if heavy and rng.random() < args.heavy else light
        target = pool[int(rng.integers(len(pool)))]
        slots = target.slots()
        k = 1 if len(slots) == 1 or rng.random() < 0.7 else 2
        chosen = rng.choice(len(slots), size=k, replace=False)
        replace = {slots[int(i)]: random_value(rng) for i in chosen}
        label = f"{target.name}({F.describe(replace)})"
        t0 = time.perf_counter()
        signal.setitimer(signal.ITIMER_REAL, args.timeout)
        try:
            result = target.call(replace)
            signal.setitimer(signal.ITIMER_REAL, 0)
            try:
                F.check_result(result, target.returns, target.rtol(replace))
                kind = "valid result"
            except F.Invalid as exc:
                kind = "INVALID result"
                text = str(exc)
                if "NaN" in text:
                    nan_count += 1
                else:
                    out_of_range += 1
                broken.append(f"{label}: {text}")
        except _Hang:
            kind = "HANG"
            hangs += 1
            broken.append(f"{label}: ran past {args.timeout:g} s")
        except ValueError as exc:
            signal.setitimer(signal.ITIMER_REAL, 0)
            kind = "ValueError" if str(exc).strip() else "ValueError WITHOUT MESSAGE"
            if kind != "ValueError":
                broken.append(f"{label}: ValueError without a message")
        except Exception as exc:  # noqa: BLE001 - counting them is the point
            signal.setitimer(signal.ITIMER_REAL, 0)
            kind = f"TRACEBACK {type(exc).__name__}"
            broken.append(f"{label}: {type(exc).__name__}: {exc}\n"
                          + "".join(traceback.format_exc(limit=-3)))
        dt = time.perf_counter() - t0
        outcomes[kind] += 1
        per_target[target.name][kind] += 1
        slow.append((dt, label))
    wall = time.perf_counter() - t_start

    slow.sort(reverse=True)
    tracebacks = sum(n for k, n in outcomes.items() if k.startswith("TRACEBACK"))
    print(f"calls: {args.calls} over {len(targets)} targets (seed {args.seed}), {wall:.1f} s")
    for kind, n in outcomes.most_common():
        print(f"  {kind:<28} {n}")
    print(f"tracebacks (exceptions other than ValueError): {tracebacks}")
    print(f"hangs (> {args.timeout:g} s): {hangs}")
    print(f"NaN in a result: {nan_count}")
    print(f"values outside their range: {out_of_range}")
    print("slowest calls:")
    for dt, label in slow[:5]:
        print(f"  {dt:7.3f} s  {label[:150]}")
    median = sorted(d for d, _ in slow)[len(slow) // 2] if slow else math.nan
    print(f"median call: {median * 1e3:.2f} ms")
    print("per target (valid / ValueError / other):")
    for name, c in sorted(per_target.items()):
        other = sum(n for k, n in c.items() if k not in ("valid result", "ValueError"))
        print(f"  {name:<26} {c['valid result']:5d} {c['ValueError']:5d} {other:5d}")
    if broken:
        print("\nbroken calls:")
        for b in broken[:30]:
            print("  " + b.replace("\n", "\n    "))
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
