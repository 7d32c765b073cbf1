"""``fix viscontact/wall ... mesh FILE`` with bad input: a degenerate, non-manifold or duplicated
mesh, a file that is not STL and bad mesh keywords each stop LAMMPS with one ERROR line naming
what is wrong; the Python wall writer's mesh style and its one-line errors."""

from __future__ import annotations

import os

import pytest

from dem_util import needs_lammps
from mesh_util import grid, write_stl

pytestmark = needs_lammps

from test_mesh import _head, _line  # noqa: E402  (the same LAMMPS head and wall line)
from viscontact.dem import plugin as _plugin  # noqa: E402

# ---- bad meshes and keywords: one ERROR line each ----------------------------------------------

BAD_MESHES = {
    "degenerate": ([((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (2.0, 0.0, 0.0))], "is degenerate"),
    "non-manifold": ([((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
                      ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
                      ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0))], "not manifold"),
    "duplicate": ([((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
                   ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 0.0))], "same corners"),
}
BAD_LINES = {
    "missing file": ("mesh nofile.stl", "cannot open mesh file nofile.stl"),
    "not stl": ("mesh notstl.stl", "neither a binary STL"),
    "bad scale": ("mesh ok.stl scale -1", "mesh scale must be"),
    "bad move": ("mesh ok.stl move 1 NULL NULL", "v_NAME or NULL"),
    "zero axis": ("mesh ok.stl rotate v_t 0 0 0 0 0 0", "axis R cannot be zero"),
    "wiggle": ("mesh ok.stl", "cannot be used with a mesh wall"),
    "undefined variable": ("mesh ok.stl move v_nothere NULL NULL", "'nothere' does not exist"),
}


def test_bad_meshes_and_keywords(tmp_path):
    """Each bad mesh or keyword: LAMMPS stops with one ERROR line naming what is wrong."""
    for name, (tris, _) in BAD_MESHES.items():
        write_stl(tmp_path / f"{name}.stl", tris, binary=False)
    write_stl(tmp_path / "ok.stl", grid(-0.0625, -0.0625, 1, 0.125))
    (tmp_path / "notstl.stl").write_text("hello\n")
    cases = {k: (f"mesh {k}.stl", msg) for k, (_, msg) in BAD_MESHES.items()} | BAD_LINES
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for name, (geom, msg) in cases.items():
            tail = " wiggle z 0.001 0.01" if name == "wiggle" else ""
            lmp = _plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
            try:
                for c in [*_head(), "create_atoms 1 single 0 0 0.01"]:
                    lmp.command(c)
                with pytest.raises(Exception) as err:
                    lmp.command(_line(geom, "damping LH c0 0.05 tangential none")
                                .format(id="w", g="all") + tail)
                    lmp.command("run 1")
            finally:
                lmp.close()
            text = str(err.value)
            assert text.startswith("ERROR") and msg in text and text.count("ERROR") == 1, (name, text)
    finally:
        os.chdir(cwd)


def test_python_wall_writes_the_mesh_style():
    """``Wall("mesh", (FILE, KEYWORDS))`` writes ``mesh FILE KEYWORDS`` (the file's lengths);
    a file name with spaces, no file, or wiggle/shear: one ValueError naming what is allowed."""
    from viscontact.dem.materials import Wall

    assert Wall("mesh", ("hop.stl", "scale 0.001")).geometry("si") == "mesh hop.stl scale 0.001"
    assert Wall("mesh", "hop.stl").geometry("cgs") == "mesh hop.stl"
    for kwargs in (dict(args=("a b.stl",)), dict(args=()),
                   dict(args=("h.stl",), wiggle=("z", 0.001, 0.01))):
        with pytest.raises(ValueError, match="mesh"):
            Wall("mesh", **kwargs)
