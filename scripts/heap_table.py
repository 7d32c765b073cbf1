"""The angle of repose of the shipped heap example for every law, with and without rolling
resistance, and native granular for reference.

    python3 scripts/heap_table.py [--laws LH Ts ...] [--mur 0.5] [--np 1] [--no-native]
                                  [--var NAME VALUE ...]

Each law runs ``viscontact/dem/examples/in.heap`` (a 2D bed of 8-12 mm discs collapsing into a
heap on a bumpy floor; e = 0.8 at 1 m/s, tangential mindlin_rescale mu = 0.5) twice: with
``-var mur 0`` (no rolling resistance) and with ``-var mur MUR`` (rolling sds). The angle is
:func:`viscontact.dem.measure.repose_angle` of the last dump frame (mean of the two flanks,
each fitted between 15 % and 85 % of the height). Native reference: the same input with
``pair_style granular`` (``hertz/material`` with ``damping coeff_restitution`` e = 0.8, the
same tangential and rolling models; walls ``wall/gran``).
"""

from __future__ import annotations

import argparse
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

from viscontact import dem
from viscontact.dem.measure import repose_angle

LAWS = ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")
EXAMPLES = Path(dem.__file__).parent / "examples"

_NATIVE_LAW = """pair_style granular
variable damping string "native"
variable wall_pre string "wall/gran granular hertz/material 2e7 0.8 0.3 tangential mindlin NULL 0.0 0.5 damping coeff_restitution limit_damping"
variable wall_post string ""
"""


def native_input(text: str) -> str:
    """in.heap with native granular's pair line (the same E, nu, tangential and rolling)."""
    line = ("pair_coeff      * * hertz/material 1e9 0.8 0.3 damping coeff_restitution "
            "tangential mindlin_rescale NULL 0.0 0.5 ${rolling} limit_damping")
    return re.sub(r"^pair_coeff .*$", line, text, flags=re.M)


def run(directory: Path, law: str, mur: float, np_: int, variables: dict) -> tuple[float, float, float]:
    """(angle, left, right) of one run of in.heap in ``directory``."""
    res = dem.run_input(directory / "in.heap", np=np_, progress=False, quiet=True, force=True,
                        variables={**variables, "law": law, "mur": mur})
    frame = dem.read_dump(directory / "heap.dump")[-1]
    assert frame.natoms == res.thermo["Atoms"][-1]
    a = repose_angle(frame)
    return a.angle, a.left, a.right


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--laws", nargs="*", default=list(LAWS))
    ap.add_argument("--mur", type=float, default=0.5, help="rolling friction MUR (default 0.5)")
    ap.add_argument("--np", type=int, default=1)
    ap.add_argument("--no-native", action="store_true")
    ap.add_argument("--var", nargs=2, action="append", default=[], metavar=("NAME", "VALUE"))
    args = ap.parse_args()
    variables = dict(args.var)
    rows = []
    with tempfile.TemporaryDirectory(prefix="viscontact-heap-") as tmp:
        d = Path(tmp) / "examples"
        shutil.copytree(EXAMPLES, d)
        todo = list(args.laws)
        if not args.no_native:
            (d / "law.native").write_text(_NATIVE_LAW)
            todo.append("native")
        for law in todo:
            src = d / "in.heap"
            text = (EXAMPLES / "in.heap").read_text()
            src.write_text(native_input(text) if law == "native" else text)
            t0 = time.perf_counter()
            off = run(d, law, 0.0, args.np, variables)
            on = run(d, law, args.mur, args.np, variables)
            rows.append((law, off, on, time.perf_counter() - t0))
            print(f"  {law}: {off[0]:.1f} -> {on[0]:.1f} degrees ({rows[-1][3]:.0f} s)",
                  file=sys.stderr)
    print(f"angle of repose (degrees; mean of the flanks, left/right), in.heap, rolling sds MUR "
          f"{args.mur} vs none")
    print("| law | no rolling resistance | rolling sds | rise |")
    print("|---|---|---|---|")
    for law, off, on, _ in rows:
        print(f"| {law} | {off[0]:.1f} ({off[1]:.1f}/{off[2]:.1f}) | {on[0]:.1f} "
              f"({on[1]:.1f}/{on[2]:.1f}) | {on[0] - off[0]:+.1f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
