"""A native LAMMPS granular word in a viscontact line is answered with its viscontact equivalent
(docs/native.md): the plugin's one ERROR line (``pair_coeff``, ``fix viscontact/wall``) and the
Python writer's ValueError (``dem.contact_law``, ``dem.Normal``, ``viscontact dem coeff``) carry
the hint of ``viscontact_native_hints.h``; a line that is wrong for another reason gets none."""

from __future__ import annotations

import math

import pytest

import viscontact as vc
from dem_util import inprocess_lammps, needs_lammps, sphere_head  # noqa: F401 (fixture lmp)
from viscontact import dem
from viscontact.dem.native import native_hint, native_hints

HEAD = sphere_head("p p f", "0 0.1 0 0.1 0 0.1", 1, plugin=False) + \
    "create_atoms 1 single 0.02 0.02 0.02\nset type * diameter 0.01\n"
TAIL = "tangential mindlin 0.5"
#: the native damping words and the law each names
DAMPING = {"tsuji": "law Ts", "coeff_restitution": "law Ts", "viscoelastic": "law KK",
           "mass_velocity": "law LH", "velocity": "law LH"}

#: name -> (lines after HEAD, words the one ERROR line must contain)
CASES = {
    **{f"damping_{w}": (f"pair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 damping {w} "
                        f"0.5 {TAIL}", [f"unknown damping law '{w}'", law, native_hint(w)])
       for w, law in DAMPING.items()},
    "native_count_nu_out": ("pair_style viscontact\npair_coeff * * hertz/material 1e7 0.9 0.3 "
                            f"damping LH c0 1 {TAIL}",
                            ["nu", "native hertz/material E DAMP NU", "no damping coefficient"]),
    "native_count_extra": ("pair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 0.3 "
                           f"damping LH c0 1 {TAIL}",
                           ["unknown keyword '0.3'", "viscontact's hertz/material takes E NU"]),
    "native_count_jkr": ("pair_style viscontact\npair_coeff * * jkr 1e7 0.3 0.3 10 "
                         f"damping LH c0 1 {TAIL}",
                         ["unknown keyword '10'", "native jkr E DAMP NU W", "takes E NU W"]),
    "normal_hooke": (f"pair_style viscontact\npair_coeff * * hooke 1e5 0.5 damping LH c0 1 {TAIL}",
                     ["'hertz/material E NU'", native_hint("hooke")]),
    "limit_damping": ("pair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 damping LH "
                      f"c0 1 {TAIL} limit_damping", ["unknown keyword 'limit_damping'",
                                                     "'end force'"]),
    "wall_tsuji": ("pair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 damping LH c0 1 "
                   f"{TAIL}\nfix w all viscontact/wall zplane 0 NULL wall_material rigid damping "
                   f"tsuji {TAIL}", ["unknown damping law 'tsuji'", native_hint("tsuji")]),
    "wall_limit_damping": ("pair_style viscontact\npair_coeff * * hertz/material 1e7 0.3 damping "
                           f"LH c0 1 {TAIL}\nfix w all viscontact/wall zplane 0 NULL wall_material "
                           f"rigid damping LH c0 1 {TAIL} limit_damping",
                           ["unknown keyword 'limit_damping'", "'end force'"]),
}

#: wrong for another reason: no hint (the hint must not be appended blindly)
NO_HINT = {
    "nu_out": f"pair_coeff * * hertz/material 1e7 0.7 damping LH c0 1 {TAIL}",
    "law_typo": f"pair_coeff * * hertz/material 1e7 0.3 damping KX c0 1 {TAIL}",
    "keyword_typo": f"pair_coeff * * hertz/material 1e7 0.3 damping LH c0 1 {TAIL} rollin sds",
}


def _error(lmp, lines: str) -> str:
    lmp.command("clear")
    with pytest.raises(Exception) as info:
        lmp.commands_string(HEAD + lines)
    errors = [ln for ln in str(info.value).splitlines() if ln.startswith("ERROR")]
    assert len(errors) == 1, str(info.value)
    return errors[0]


@needs_lammps
@pytest.mark.parametrize("case", list(CASES))
def test_plugin_names_the_equivalent(lmp, case):
    lines, words = CASES[case]
    error = _error(lmp, lines)
    for w in words:
        assert w in error, (w, error)


@needs_lammps
@pytest.mark.parametrize("case", list(NO_HINT))
def test_plugin_adds_no_hint_to_other_errors(lmp, case):
    error = _error(lmp, "pair_style viscontact\n" + NO_HINT[case])
    assert "native" not in error, error


def test_table_covers_the_native_words():
    """Every damping model of native pair granular, its normal models that viscontact lacks and
    limit_damping have a hint; each hint names a viscontact keyword to write."""
    hints = native_hints()
    assert set(DAMPING) | {"hooke", "hooke/stiffness", "hertz", "limit_damping"} <= set(hints)
    for word, law in DAMPING.items():
        assert law in hints[word] and "damping " in hints[word], (word, hints[word])
    assert native_hint("KK") == "" and native_hint(None) == ""


def test_coeff_restitution_hint_is_exact():
    """The hint's claim: native coeff_restitution's alpha, sqrt(5) |ln e| / sqrt(pi^2 + ln^2 e)
    (LAMMPS pair granular docs), is Ts's exact alpha at e with the zero-overlap end."""
    for e in (0.3, 0.6, 0.9):
        native = math.sqrt(5) * abs(math.log(e)) / math.sqrt(math.pi ** 2 + math.log(e) ** 2)
        assert vc.alpha_from_e("Ts", e, end="overlap") == pytest.approx(native, rel=1e-9)


@pytest.mark.parametrize("word", list(DAMPING))
def test_python_writer_names_the_equivalent(word):
    with pytest.raises(ValueError) as info:
        dem.contact_law(word, e=0.8, vref=1.0)
    assert f"unknown model '{word}'" in str(info.value)
    assert str(info.value).endswith(native_hint(word)), str(info.value)


def test_python_normal_model_hint():
    with pytest.raises(ValueError, match="spring is Hertz"):
        dem.Normal("hooke")
    with pytest.raises(ValueError) as info:
        dem.contact_law("KX", e=0.8, vref=1.0)
    assert "native" not in str(info.value)


def test_command_line_hint():
    from conftest import run_cli

    proc = run_cli("dem", "coeff", "--law", "tsuji", "--E", "1e7", "--nu", "0.3", "--e", "0.8",
                   "--vref", "1")
    assert proc.returncode == 2 and len(proc.stderr.splitlines()) == 1, proc.stderr
    assert "law Ts" in proc.stderr


@pytest.mark.parametrize("form", [["--e", "0.8", "--vref", "1"], ["--c0", "2", "--tau", "0.5"]])
def test_lj_comment_names_no_si_unit(form):
    """With --units lj every number is typed and printed in reduced units: the comment line
    names none of SI's (m/s, s, N s/m^...), while --units si keeps them."""
    from conftest import run_cli

    base = ["dem", "coeff", "--law", "Jian" if "--c0" in form else "KK", "--E", "1", "--nu",
            "0.3", *form]
    if "--e" in form:
        base += ["--beta", "0.5"] if base[3] == "Jian" else []
    lj = run_cli(*base, "--units", "lj")
    si = run_cli(*base)
    assert lj.returncode == 0 and si.returncode == 0, (lj.stderr, si.stderr)
    comment, si_comment = lj.stdout.splitlines()[0], si.stdout.splitlines()[0]
    assert "lj" in comment and not any(u in comment for u in ("m/s", " s,", "N s/m")), comment
    assert any(u in si_comment for u in ("m/s", " s,", "N s/m")), si_comment
