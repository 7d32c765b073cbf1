"""STL files for the mesh walls of ``fix viscontact/wall ... mesh FILE`` (docs/fix_viscontact_mesh.md):
a writer (binary or ASCII) and the shapes of the examples: a flat-bottomed silo with a
central orifice, a conical hopper, a mixer's blade and a drum's mantle (an open tube).

    python3 -m viscontact.dem.stl silo OUT.stl [--radius R] [--height H] [--orifice D] [--faces N]
    python3 -m viscontact.dem.stl hopper OUT.stl [--outlet R0] [--radius R] [--height H] [--faces N]
    python3 -m viscontact.dem.stl blade OUT.stl [--half L] [--zlo Z0] [--zhi Z1]
    python3 -m viscontact.dem.stl drum OUT.stl [--radius R] [--zlo Z0] [--zhi Z1] [--faces N]

Lengths in metres; an existing OUT is kept unless ``--force``.  Shared corners are written with
the same numbers, so the fix welds them into closed seams.
"""

from __future__ import annotations

import argparse
import math
import struct
import sys
from pathlib import Path

Point = tuple[float, float, float]
Triangle = tuple[Point, Point, Point]


def write_stl(path: Path, tris: list[Triangle], *, binary: bool = True) -> Path:
    """Write triangles (three corners each) as a binary (float32) or ASCII STL file.  Binary
    rounds the corners to float32: choose them exact in float32 where exactness matters."""
    path = Path(path)
    if binary:
        out = bytearray(b"viscontact mesh".ljust(80, b" "))
        out += struct.pack("<I", len(tris))
        for t in tris:
            out += struct.pack("<12fH", 0.0, 0.0, 0.0, *(c for v in t for c in v), 0)
        path.write_bytes(bytes(out))
    else:
        lines = ["solid viscontact"]
        for t in tris:
            lines += ["  facet normal 0 0 0", "    outer loop"]
            lines += ["      vertex {!r} {!r} {!r}".format(*map(float, v)) for v in t]
            lines += ["    endloop", "  endfacet"]
        lines.append("endsolid viscontact")
        path.write_text("\n".join(lines) + "\n")
    return path


def _ring(radius: float, z: float, n: int) -> list[Point]:
    return [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n), z)
            for k in range(n)]


def _band(lower: list[Point], upper: list[Point]) -> list[Triangle]:
    """The closed band of quads (two triangles each) between two rings of equal length."""
    n = len(lower)
    tris: list[Triangle] = []
    for k in range(n):
        a, b, c, d = lower[k], lower[(k + 1) % n], upper[(k + 1) % n], upper[k]
        tris += [(a, b, c), (a, c, d)]
    return tris


def silo(radius: float = 0.05, height: float = 0.25, orifice: float = 0.02,
         faces: int = 64) -> list[Triangle]:
    """A flat-bottomed cylindrical silo about the z axis, floor at z = 0 with a central
    circular orifice of diameter ``orifice``, open at the top: the wall and the floor share
    their corners (a concave crease)."""
    if not 0 < orifice < 2 * radius:
        raise ValueError(f"the orifice diameter must lie in (0, 2 radius), got {orifice}")
    floor_out = _ring(radius, 0.0, faces)
    return _band(_ring(orifice / 2, 0.0, faces), floor_out) + _band(floor_out,
                                                                   _ring(radius, height, faces))


def hopper(outlet: float = 0.01, radius: float = 0.05, height: float = 0.07,
           faces: int = 64) -> list[Triangle]:
    """A conical hopper about the z axis: radius ``outlet`` at z = 0, ``radius`` at z = height,
    open at both ends."""
    return _band(_ring(outlet, 0.0, faces), _ring(radius, height, faces))


def blade(half: float = 0.04, zlo: float = 0.005, zhi: float = 0.03) -> list[Triangle]:
    """A flat paddle in the x-z plane, |x| <= half, zlo <= z <= zhi: one open sheet of two
    triangles (turn it with the fix's ``rotate``)."""
    a, b, c, d = (-half, 0.0, zlo), (half, 0.0, zlo), (half, 0.0, zhi), (-half, 0.0, zhi)
    return [(a, b, c), (a, c, d)]


def drum(radius: float = 0.04, zlo: float = -0.01, zhi: float = 0.022,
         faces: int = 128) -> list[Triangle]:
    """A drum's mantle: an open polygonal tube about the z axis from ``zlo`` to ``zhi``, its
    ``faces`` corners on the circle of ``radius`` (the faces lie inside it by at most
    radius (1 - cos(pi / faces)), 12 um for the defaults).  Turn it with the fix's ``rotate``."""
    if not (radius > 0 and zlo < zhi and faces >= 3):
        raise ValueError(f"a drum needs radius > 0, zlo < zhi and faces >= 3, got radius "
                         f"{radius}, zlo {zlo}, zhi {zhi}, faces {faces}")
    return _band(_ring(radius, zlo, faces), _ring(radius, zhi, faces))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m viscontact.dem.stl",
                                 description="write the STL file of an example mesh wall")
    ap.add_argument("shape", choices=("silo", "hopper", "blade", "drum"))
    ap.add_argument("out", type=Path)
    ap.add_argument("--radius", type=float, help="silo/hopper/drum radius [m] (top of the hopper)")
    ap.add_argument("--height", type=float, help="silo/hopper height [m]")
    ap.add_argument("--orifice", type=float, help="silo orifice diameter [m]")
    ap.add_argument("--outlet", type=float, help="hopper outlet radius [m]")
    ap.add_argument("--faces", type=int, help="segments around the axis")
    ap.add_argument("--half", type=float, help="blade half-width [m]")
    ap.add_argument("--zlo", type=float, help="blade/drum bottom [m]")
    ap.add_argument("--zhi", type=float, help="blade/drum top [m]")
    ap.add_argument("--ascii", action="store_true", help="ASCII instead of binary STL")
    ap.add_argument("--force", action="store_true", help="overwrite OUT")
    args = ap.parse_args(argv)
    if args.out.exists() and not args.force:
        print(f"error: {args.out} exists; give --force to overwrite it", file=sys.stderr)
        return 2
    keys = {"silo": ("radius", "height", "orifice", "faces"),
            "hopper": ("outlet", "radius", "height", "faces"),
            "blade": ("half", "zlo", "zhi"),
            "drum": ("radius", "zlo", "zhi", "faces")}[args.shape]
    kwargs = {k: getattr(args, k) for k in keys if getattr(args, k) is not None}
    try:
        tris = {"silo": silo, "hopper": hopper, "blade": blade, "drum": drum}[args.shape](**kwargs)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    write_stl(args.out, tris, binary=not args.ascii)
    print(f"{args.out}: {len(tris)} triangles")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
