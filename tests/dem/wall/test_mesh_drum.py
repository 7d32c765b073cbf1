"""A rotating drum whose mantle is an STL mesh (``fix viscontact/wall ... mesh ... rotate``)
against the same drum as a rotating ``region cylinder`` (``fix viscontact/wall region``): the
shipped ``in.mesh.drum`` with ``-var wall mesh`` and ``-var wall region``, one seed each, a
short settle and the first 0.25 s of turning at 15 rpm.

Before its first avalanche (the bed rises to about 34 degrees first; docs/fix_viscontact_mesh.md)
the bed turns with the drum as a solid body: the angle of its centre of mass about the axis
grows by omega dt_frame = 4.5 degrees between frames 0.05 s apart (the independent reference;
the first interval lags while the wall's tangential springs load, so it is left out).  The two
walls give the same angle frame by frame.  The 5-seed comparison of the dynamic angle of
repose is a study, not a test (scripts/mesh_drum_study.py).
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np

from dem_util import needs_lammps

from viscontact import dem
from viscontact.dem import stl

pytestmark = needs_lammps

EXAMPLES = Path(dem.__file__).parent / "examples"
SETTLE, TURN, EVERY, RPM = 15000, 12500, 2500, 15


def _com_angles(path) -> np.ndarray:
    """Degrees: the angle about the drum's axis of the bed's centre of mass in every frame
    after the settle (mass ~ radius^3: one density)."""
    out = []
    for f in dem.read_dump(path):
        if f.step >= SETTLE:
            m = f["radius"] ** 3
            out.append(math.degrees(math.atan2((f["y"] * m).sum(), (f["x"] * m).sum())))
    return np.unwrap(np.radians(out)) * 180 / math.pi


def test_mesh_drum_turns_the_bed_as_the_region_drum(tmp_path):
    d = tmp_path / "examples"
    shutil.copytree(EXAMPLES, d)
    header = re.search(r"^#\s+python3 -m viscontact\.dem\.stl (.*)$",
                       (d / "in.mesh.drum").read_text(), re.M).group(1).split()
    shape, out, *opts = header
    assert stl.main([shape, str(d / out), *opts]) == 0
    angles = {}
    for wall in ("mesh", "region"):
        dem.run_input(d / "in.mesh.drum", progress=False, quiet=True, force=True,
                      variables={"wall": wall, "settle": SETTLE, "steps": TURN, "every": EVERY})
        angles[wall] = _com_angles(d / "mesh.drum.dump")
    step = math.degrees(2 * math.pi * RPM / 60 * EVERY * 2e-5)      # 4.5 degrees per frame
    for wall, a in angles.items():
        assert len(a) == TURN // EVERY + 1
        # solid-body rotation with the drum, in its sense (0.1 degree: 2 % of a frame's turn;
        # measured within 0.06 for both walls)
        assert np.all(np.abs(np.diff(a)[1:] - step) < 0.1), (wall, np.diff(a))
    # the same bed motion: the mesh's faces lie within R (1 - cos(pi/128)) = 12 um of the
    # circle; 0.1 degree at the centre of mass (2.3 cm from the axis) is 40 um, three times
    # that (measured 0.02 degree)
    assert np.abs(angles["mesh"] - angles["region"]).max() < 0.1
