"""Every new keyword of ``pair_coeff ... viscontact`` refuses a bad value, a missing value and an
incompatible combination with one ``ERROR:`` line that names the keyword and what is allowed
(one in-process LAMMPS runs every case, ``clear`` between them)."""

from __future__ import annotations

import pytest

from dem_util import inprocess_lammps, needs_lammps, sphere_head  # noqa: F401 (fixture lmp)

pytestmark = needs_lammps

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
