"""One-line input errors of ``pair_style viscontact``: a bad ``pair_coeff`` or ``pair_style``
line, an init-time check, or an error in an in-process LAMMPS, each gives one ``ERROR:`` line
that names what is wrong and what is allowed (or one Python exception), never a crash.

Real LAMMPS runs (the ``lmp`` of ``lammps[mpi]==2025.7.22.4.0``; skipped with the reason when
absent).
"""

from __future__ import annotations

import pytest

from dem_util import (  # noqa: F401 (fixture lmp)
    assert_ok, error_lines, inprocess_lammps, needs_lammps, plugin_line, run_lmp, sphere_head,
)

pytestmark = needs_lammps


# ---------------------------------------------------------------------------- input errors
_ERR = """\
{plugin}
units si
atom_style {style}
atom_modify map array
boundary f f f
{comm}
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05
create_box 1 box
create_atoms 1 single 0 0 0
pair_style viscontact
pair_coeff * * {coeff}
run 0
"""


GOOD = "hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1.0 tangential mindlin 0.5"


BAD = [
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1.0 tangential none foo 1",
     "unknown keyword 'foo'"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref", "vref needs a value"),
    ("hertz/material 1e7 0.3 damping KK alpha -0.3 vref 1.0 tangential none",
     "alpha must be a finite number in [0, 1000], got '-0.3'"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1.0 tangential mindlin -1", "MU must be a finite number in [0, 10]"),
    ("hertz/material -1e7 0.3 damping KK alpha 0.3 vref 1.0 tangential none", "E must be a finite number in [1e-10, 1e+20]"),
    ("hertz/material 1e7 0.7 damping KK alpha 0.3 vref 1.0 tangential none",
     "nu must be a finite number in (-1, 0.5], got '0.7'"),
    ("hertz/material 1e7 -1 damping KK alpha 0.3 vref 1.0 tangential none", "nu must be a finite number in (-1, 0.5]"),
    ("hertz/material 1e7 0.3 damping KK p 0.5 alpha 0.3 vref 1.0 tangential none",
     "p is only allowed with damping power"),
    ("hertz/material 1e7 0.3 damping power alpha 0.3 vref 1.0 tangential none", "damping power needs p P"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1.0 beta 0.5 tangential none",
     "beta is only allowed with Jian"),
    ("hertz/material 1e7 0.3 damping KK c0 5 tau 0.001 tangential none", "tau is only allowed with Jian"),
    ("hertz/material 1e7 0.3 damping Jian alpha 0.3 vref 1.0 tangential none", "damping Jian with alpha needs beta B"),
    ("hertz/material 1e7 0.3 damping KK tangential none", "damping KK needs alpha A vref V or c0 C"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 c0 5 vref 1 tangential none", "not both"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1.0", "missing tangential none | mindlin MU"),
    ("hertz/material 1e7 0.3 damping XX alpha 0.3 vref 1.0 tangential none",
     "unknown damping law 'XX'"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 0 tangential none", "vref must be a finite number in (0, 1e+300], got '0'"),
    ("hertz/material 1e7 0.3 damping KK alpha abc vref 1 tangential none",
     "alpha must be a finite number in [0, 1000], got 'abc'"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 end sticky tangential none",
     "end must be followed by force"),
    ("hertz 1e7 0.3 damping KK alpha 0.3 vref 1 tangential none", "expected 'hertz/material E NU'"),
    ("", "expected 'hertz/material E NU'"),
    ("hertz/material 1e7", "hertz/material needs two values, E and NU"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 alpha 0.4 vref 1 tangential none",
     "alpha given twice"),
    ("hertz/material 1e7 0.3 damping Jian c0 5 tangential none", "damping Jian with c0 needs tau S"),
    ("hertz/material 1e7 0.3 damping KK alpha 0.3 vref 1 tangential mindlin", "mindlin needs MU"),
    # issue 18: accepted before, then NaN, atoms lost through a wall, or no repulsion at all
    ("hertz/material 1e7 0.3 damping power p 1e308 c0 1 tangential none",
     "p must be a finite number in [0, 10], got '1e308'"),
    ("hertz/material 1e308 0.3 damping KK alpha 0.3 vref 1 tangential none",
     "E must be a finite number in [1e-10, 1e+20], got '1e308'"),
    ("hertz/material 1e-320 0.3 damping KK alpha 0.3 vref 1 tangential none",
     "E must be a finite number in [1e-10, 1e+20], got '1e-320'"),
]


@pytest.mark.parametrize("coeff,message", BAD, ids=[m for _, m in BAD])
def test_bad_pair_coeff_one_error_line(tmp_path, coeff, message):
    proc = run_lmp(_ERR.format(plugin=plugin_line(), style="sphere", comm="comm_modify vel yes",
                               coeff=coeff), tmp_path)
    errs = error_lines(proc)
    assert 0 < proc.returncode < 128, (proc.returncode, proc.stderr[-500:])  # no crash
    assert len(errs) == 1, errs
    assert errs[0].startswith("ERROR: pair viscontact") and message in errs[0], errs[0]


@pytest.mark.parametrize("style,comm,message", [
    ("atomic", "comm_modify vel yes", "requires atom_style sphere"),
    ("sphere", "", "requires 'comm_modify vel yes'"),
])
def test_init_checks_one_error_line(tmp_path, style, comm, message):
    proc = run_lmp(_ERR.format(plugin=plugin_line(), style=style, comm=comm, coeff=GOOD), tmp_path)
    errs = error_lines(proc)
    assert 0 < proc.returncode < 128 and len(errs) == 1 and message in errs[0], errs


def test_good_line_runs(tmp_path):
    proc = run_lmp(_ERR.format(plugin=plugin_line(), style="sphere", comm="comm_modify vel yes",
                               coeff=GOOD), tmp_path)
    assert_ok(proc)


def test_error_in_process_is_an_exception(tmp_path):
    """In the lammps Python module a bad pair_coeff raises (one ERROR line), and LAMMPS stays
    usable: the corrected line is accepted."""
    from viscontact.dem import plugin

    lmp = plugin.new_lammps(["-log", "none", "-screen", "none", "-nocite"])
    try:
        lmp.commands_string("units si\natom_style sphere\n"
                            "region box block -0.05 0.05 -0.05 0.05 -0.05 0.05\ncreate_box 1 box\n"
                            "pair_style viscontact")
        with pytest.raises(Exception) as info:
            lmp.command("pair_coeff * * hertz/material 1e7 0.7 damping KK alpha 0.3 vref 1 "
                        "tangential none")
        errs = [ln for ln in str(info.value).splitlines() if ln.startswith("ERROR")]
        assert len(errs) == 1 and "nu must be a finite number in (-1, 0.5], got '0.7'" in errs[0], errs
        lmp.command(f"pair_coeff * * {GOOD}")
    finally:
        lmp.close()


def test_bad_pair_style_option_one_error_line(tmp_path):
    script = _ERR.format(plugin=plugin_line(), style="sphere", comm="comm_modify vel yes",
                         coeff=GOOD).replace("pair_style viscontact", "pair_style viscontact 1.0 2.0")
    proc = run_lmp(script, tmp_path)
    errs = error_lines(proc)
    assert 0 < proc.returncode < 128 and len(errs) == 1, errs
    assert "takes at most one value, the cutoff CUT" in errs[0], errs
    # the tests' negative control is not part of the syntax
    proc = run_lmp(script.replace("pair_style viscontact 1.0 2.0", "pair_style viscontact drop_history"),
                   tmp_path)
    errs = error_lines(proc)
    assert len(errs) == 1 and "CUT must be a finite number in (0, 1e+300], got 'drop_history'" in errs[0], errs


# ------------------------------------------------------- every keyword of pair_coeff, in-process
# Every new keyword of ``pair_coeff ... viscontact`` refuses a bad value, a missing value and an
# incompatible combination with one ``ERROR:`` line that names the keyword and what is allowed
# (one in-process LAMMPS runs every case, ``clear`` between them).
HEAD = sphere_head("p p p", "0 0.1 0 0.1 0 0.1", 2, plugin=False) + """\
create_atoms 1 single 0.02 0.02 0.02
create_atoms 2 single 0.04 0.04 0.04
set type * diameter 0.01
"""


OK = "damping LH c0 1 tangential linear_history 1e4 0.5 0.4"


M = "hertz/material 1e7 0.3"


#: name -> (pair lines after HEAD, words the one error line must contain)
CASES = {
    "normal_unknown": (f"pair_coeff * * hertz 1e7 0.3 {OK}", ["'hertz/material E NU'", "'jkr E NU W'"]),
    "jkr_missing_W": ("pair_coeff * * jkr 1e7 0.3 damping LH c0 1 tangential none",
                      ["jkr W must be a finite number"]),
    "dmt_end_force": ("pair_coeff * * dmt 1e7 0.3 1 damping LH c0 1 end force tangential none",
                      ["end force is not allowed", "dmt", "end overlap"]),
    "tangential_unknown": (f"pair_coeff * * {M} damping LH c0 1 tangential linear 1 2",
                           ["tangential must be followed by", "linear_history KT XGAMMA MU"]),
    "linear_history_missing": (f"pair_coeff * * {M} damping LH c0 1 tangential linear_history 1e4 0.5",
                               ["linear_history needs KT XGAMMA MU"]),
    "rescale_short_form": (f"pair_coeff * * {M} damping LH c0 1 tangential mindlin_rescale 0.4",
                           ["mindlin_rescale needs KT|NULL XGAMMA MU"]),
    "xgamma_negative": (f"pair_coeff * * {M} damping LH c0 1 tangential mindlin NULL -1 0.4",
                        ["XGAMMA must be a finite number in [0"]),
    "mu_too_large": (f"pair_coeff * * {M} damping LH c0 1 tangential linear_nohistory 0.5 11",
                     ["MU must be a finite number in [0, 10]"]),
    "rolling_unknown": (f"pair_coeff * * {M} {OK} rolling linear 1 1 1", ["rolling must be followed by sds"]),
    "rolling_kr_zero": (f"pair_coeff * * {M} {OK} rolling sds 0 1 0.1", ["rolling sds KR", "(0,"]),
    "rolling_missing": (f"pair_coeff * * {M} {OK} rolling sds 10 1", ["rolling sds needs KR GAMMAR MUR"]),
    "rolling_twice": (f"pair_coeff * * {M} {OK} rolling sds 10 1 0.1 rolling sds 10 1 0.1",
                      ["rolling given twice"]),
    "twisting_unknown": (f"pair_coeff * * {M} {OK} twisting spring", ["twisting must be followed by marshall"]),
    "twisting_kt_zero": (f"pair_coeff * * {M} {OK} twisting sds 0 1 0.1", ["twisting sds KT", "(0,"]),
    "marshall_no_spring": (f"pair_coeff * * {M} damping LH c0 1 tangential none twisting marshall",
                           ["twisting marshall needs a tangential spring"]),
    "heat_unknown": (f"pair_coeff * * {M} {OK} heat radiative 1", ["heat must be followed by area K"]),
    "heat_negative": (f"pair_coeff * * {M} {OK} heat area -1", ["heat area K must be"]),
    "cutoff_bad": (f"pair_coeff * * {M} {OK} cutoff 0", ["cutoff C must be a finite number in (0"]),
    "cut_global_bad": (f"pair_coeff * * {M} {OK}", ["pair_style viscontact CUT"], "pair_style viscontact -1"),
    "heat_without_property": (f"pair_coeff * * {M} {OK} heat area 1\nrun 0",
                              ["heat area needs per-atom temperature and heatflow",
                               "fix property/atom temperature heatflow"]),
    "heat_not_everywhere": (f"pair_coeff 1 1 {M} {OK} heat area 1\npair_coeff 2 2 {M} {OK}\n"
                            "pair_coeff 1 2 {M} {OK} heat area 1\nrun 0".replace("{M}", M).replace("{OK}", OK),
                            ["heat area must be given for every pair_coeff line or for none"]),
    "mixing_rolling_differs": (f"pair_coeff 1 1 {M} {OK} rolling sds 10 1 0.1\npair_coeff 2 2 {M} {OK}\n"
                               "run 0", ["types 1 and 2 use a different rolling model",
                                         "pair_coeff 1 2"]),
}


@pytest.mark.parametrize("case", list(CASES))
def test_one_error_line(lmp, case):
    """The line fails with exactly one ERROR line from pair viscontact, naming what is allowed."""
    lines, words, *style = CASES[case]
    lmp.command("clear")
    with pytest.raises(Exception) as info:
        lmp.commands_string(HEAD + (style[0] if style else "pair_style viscontact") + "\n" + lines)
    msg = str(info.value)
    errors = [ln for ln in msg.splitlines() if ln.startswith("ERROR")]
    assert len(errors) == 1, msg
    assert errors[0].startswith("ERROR: pair viscontact"), msg
    for w in words:
        assert w in errors[0], (w, errors[0])


def test_valid_lines_are_accepted(lmp):
    """Every sub-model keyword in one accepted line (the negative control of the cases above)."""
    lmp.command("clear")
    lmp.commands_string(HEAD + "pair_style viscontact\n"
                        f"pair_coeff * * jkr 1e7 0.3 0.1 {OK} rolling sds 10 1 0.1 "
                        "twisting sds 1e-4 1e-7 0.02 cutoff 0.02\nrun 0")
