"""Refresh the recorded real-engine results (tests/data/engine_runs.json) and print the table.

    PYTHONPATH=src python3 scripts/engine_runs.py [liggghts] [yade] [kratos] [--table]

Runs each named engine (default: every installed one) on the full plan of
scripts/engine_harness.py (equal spheres, unlike spheres, sphere on a wall; typed e = 0.3, 0.6,
0.9 at 0.1, 1, 10 m/s; the audit's advised inputs; undamped peak overlaps), stores the
results with the engine's version, and prints what differs from the audit (nothing when the
presets hold).  ``--table``: print the Markdown table of the recorded results (docs/audit.md).
"""

from __future__ import annotations

import sys
import time

import engine_harness as R  # scripts/engine_harness.py, shared with tests/audit/test_engines.py


def table() -> str:
    """engine, version, e typed, delivered (min-max over geometries and speeds), predicted,
    advised input and what it delivers, from the recorded results."""
    lines = ["| engine | version | setting | e typed | delivered (all geometries, speeds) | audit predicts "
             "| advised input | it delivers |", "|---|---|---|---|---|---|---|---|"]
    for eng in ("liggghts", "yade", "kratos"):
        rec = R.recorded(eng)
        if rec is None:
            continue
        version, results = rec
        for clamp in R._clamps(eng):
            for e in R.E_TYPED:
                got = [r.e for r in results if r.case.e == e and r.case.target is None and r.case.clamp == clamp]
                adv = [r for r in results if r.case.target == e and r.case.clamp == clamp]
                a = R._audit(eng, e, clamp, version)
                setting = ("limitForce " + ("on" if clamp else "off")) if eng == "liggghts" else "default"
                adv_in = f"{adv[0].case.e:.5f}" if adv else f"{e:g} (same)"
                adv_got = (f"{min(r.e for r in adv):.5f}-{max(r.e for r in adv):.5f}" if adv
                           else f"{min(got):.5f}-{max(got):.5f}")
                lines.append(f"| {eng} | {version} | {setting} | {e:g} | {min(got):.5f}-{max(got):.5f} | "
                             f"{a.delivered_e:.5f} | {adv_in} | {adv_got} |")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    if "--table" in argv:
        print(table())
        return 0
    engines = [a for a in argv if not a.startswith("-")] or list(R.RUNNERS)
    status = 0
    for eng in engines:
        reason = R.missing_reason(eng)
        if reason:
            print(f"{eng}: skipped ({reason})")
            continue
        t = time.time()
        version, results = R.run_plan(eng)
        R.record(eng, version, results)
        bad = R.check(eng, version, results)
        print(f"{eng} {version}: {len(results)} collisions in {time.time() - t:.1f} s, "
              f"{'all agree with the audit' if not bad else 'DIFFERENCES:'}")
        for b in bad:
            print("  " + b)
        status |= bool(bad)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
