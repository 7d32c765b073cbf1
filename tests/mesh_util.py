"""Triangle meshes for the mesh-wall tests (flat grids, a polygonal tube, a closed box, a roof
and a pyramid), written as STL files in a test's directory by viscontact.dem.stl.write_stl."""

from __future__ import annotations

import numpy as np

from viscontact.dem.stl import write_stl  # noqa: F401  (the tests' writer)

Tri = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]


def grid(x0: float, y0: float, n: int, a: float, z: float = 0.0) -> list[Tri]:
    """A flat n x n grid of squares of side a from (x0, y0) in the plane z, each split along
    its (+x, +y) diagonal: 2 n^2 triangles, six around every inner vertex."""
    tris: list[Tri] = []
    for i in range(n):
        for j in range(n):
            p = [(x0 + (i + di) * a, y0 + (j + dj) * a, z) for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1))]
            tris += [(p[0], p[1], p[2]), (p[0], p[2], p[3])]
    return tris


def tube(radius: float, n: int, zlo: float, zhi: float) -> list[Tri]:
    """An open polygonal tube about the z axis: n flat faces (2 triangles each) whose corners
    lie on the circle of the radius, rotated so that a face centre sits on the +x axis."""
    ang = 2 * np.pi * (np.arange(n) + 0.5) / n
    xy = [(float(radius * np.cos(a)), float(radius * np.sin(a))) for a in ang]
    tris: list[Tri] = []
    for k in range(n):
        (x1, y1), (x2, y2) = xy[k], xy[(k + 1) % n]    # closed: the same corners
        a, b, c, d = (x1, y1, zlo), (x2, y2, zlo), (x2, y2, zhi), (x1, y1, zhi)
        tris += [(a, b, c), (a, c, d)]
    return tris


def box(lo: float, hi: float) -> list[Tri]:
    """The closed cube [lo, hi]^3: 12 triangles."""
    tris: list[Tri] = []
    for d in range(3):
        for side in (lo, hi):
            u, v = (d + 1) % 3, (d + 2) % 3
            corners = []
            for cu, cv in ((lo, lo), (hi, lo), (hi, hi), (lo, hi)):
                p = [0.0, 0.0, 0.0]
                p[d], p[u], p[v] = side, cu, cv
                corners.append(tuple(p))
            tris += [(corners[0], corners[1], corners[2]), (corners[0], corners[2], corners[3])]
    return tris


def roof(half: float, slope: float, length: float) -> list[Tri]:
    """A ridge along y: two planes z = slope (half - |x|) for |x| <= half, |y| <= length,
    meeting at a convex edge x = 0; four triangles."""
    top, eave = slope * half, 0.0
    a, b = (-half, -length, eave), (-half, length, eave)
    c, d = (0.0, -length, top), (0.0, length, top)
    e, f = (half, -length, eave), (half, length, eave)
    return [(a, c, d), (a, d, b), (c, e, f), (c, f, d)]


def pyramid(half: float, height: float) -> list[Tri]:
    """A square pyramid over [-half, half]^2 with its apex (a convex vertex of four faces) at
    (0, 0, height); four triangles, open below."""
    apex = (0.0, 0.0, height)
    base = [(-half, -half, 0.0), (half, -half, 0.0), (half, half, 0.0), (-half, half, 0.0)]
    return [(base[k], base[(k + 1) % 4], apex) for k in range(4)]


def sphere_lines(first: int, spheres, radius: float, density: float) -> list[str]:
    """LAMMPS lines creating spheres ``(x, v, omega)`` as atoms first, first + 1, ..."""
    cmds = []
    for k, (x, v, w) in enumerate(spheres):
        n = first + k
        cmds += ["create_atoms 1 single {!r} {!r} {!r}".format(*x),
                 f"set atom {n} diameter {2 * radius!r} density {density!r}",
                 "set atom {} vx {!r} vy {!r} vz {!r}".format(n, *v),
                 "set atom {} omega {!r} {!r} {!r}".format(n, *w)]
    return cmds
