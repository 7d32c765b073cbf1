"""Measures on DEM output: the angle of repose of a heap.

:func:`repose_angle` takes one dump frame (:func:`viscontact.dem.read_dump`) of a heap resting
on a floor and fits a straight line to each flank of its free surface: the surface is the
highest sphere top (y + r in 2D, z + r in 3D) in columns two mean diameters wide; each flank,
walked down from the peak to the first gap, is fitted between ``lo`` and ``hi`` of the heap's height above its base, which leaves out the
rounded top and the feet where loose spheres roll away.  The heap is the run of occupied
columns that holds the most spheres (loose spheres elsewhere do not count).  The angle is the mean of the two
flanks' slopes, atan(|dh/dx|) in degrees (Zhou et al. 2002, Powder Technol. 125, 45 use the
same kind of surface fit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["HeapAngle", "repose_angle"]


@dataclass(frozen=True)
class HeapAngle:
    """Angle of repose [degrees] (mean of the flanks), the left and right flanks' angles, the
    heap's height above its base [length] and the number of surface columns fitted."""

    angle: float
    left: float
    right: float
    height: float
    columns: int


def repose_angle(frame, *, up: str = "y", across: str = "x", grains: int | None = 1,
                 lo: float = 0.15, hi: float = 0.85) -> HeapAngle:
    """The angle of repose of the heap in ``frame`` (columns ``id type radius x y ...``).

    ``up``: the vertical axis (``y`` for a 2D input, ``z`` in 3D); ``across``: the horizontal
    axis the flanks are fitted along (3D: the heap is assumed ridge-like along the third
    axis, or the profile is taken over all of it).  ``grains``: the atom type of the heap (None:
    every atom); the floor is the lowest sphere bottom of those.  ``lo``, ``hi``: the part of
    the height fitted.  ValueError when a flank has fewer than 3 columns in that band.
    """
    if not 0 <= lo < hi <= 1:
        raise ValueError(f"need 0 <= lo < hi <= 1, got lo = {lo!r}, hi = {hi!r}")
    keep = np.ones(frame.natoms, bool) if grains is None else frame["type"] == grains
    x, h, r = frame[across][keep], frame[up][keep], frame["radius"][keep]
    if len(x) < 10:
        raise ValueError(f"a heap needs at least 10 spheres, got {len(x)}")
    width = 4.0 * float(np.mean(r))  # columns two mean diameters wide: one sphere's bumps average out
    base = float(np.min(h - r))
    top = h + r - base
    # the grid is anchored at the heap's centre of mass, so that a sphere rolling away at a
    # foot does not shift every column
    centre = float(np.mean(x))
    cols = np.floor((x - centre) / width).astype(int)
    cols -= cols.min()
    surface = np.full(cols.max() + 1, np.nan)
    np.fmax.at(surface, cols, top)
    centres = centre + (np.arange(len(surface)) + float(np.floor((x - centre) / width).min()) + 0.5) * width
    # the heap: the run of occupied columns holding the most spheres (spheres that rolled away,
    # or piled against a far wall, form runs of their own)
    counts = np.bincount(cols, minlength=len(surface))
    runs, start = [], None
    for k in range(len(surface) + 1):
        filled = k < len(surface) and np.isfinite(surface[k])
        if filled and start is None:
            start = k
        elif not filled and start is not None:
            runs.append((int(counts[start:k].sum()), start, k))
            start = None
    _, first, last = max(runs)
    peak = first + int(np.nanargmax(surface[first:last]))
    height = float(surface[peak])
    angles = []
    for step in (-1, 1):
        # walk down the flank from the peak; stop at the first gap or at the foot (below lo)
        xs, hs = [], []
        k = peak
        while 0 <= k < len(surface) and np.isfinite(surface[k]) and surface[k] >= lo * height:
            if surface[k] <= hi * height:
                xs.append(centres[k])
                hs.append(surface[k])
            k += step
        if len(xs) < 3:
            raise ValueError(f"a flank has {len(xs)} surface columns between {lo:g} and {hi:g} "
                             "of the height: no heap to fit")
        slope = np.polyfit(xs, hs, 1)[0]
        angles.append(math.degrees(math.atan(abs(slope))))
    return HeapAngle(angle=0.5 * (angles[0] + angles[1]), left=angles[0], right=angles[1],
                     height=height, columns=len(surface))
