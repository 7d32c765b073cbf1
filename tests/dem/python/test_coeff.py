"""viscontact.dem's lines written from what a user knows (``contact_law``, ``coeff_lines``, the
sub-model keywords of the pair and the wall), and their one-line errors; no LAMMPS needed.

Independent expectations: the exact solver (``restitution(exact=True)``, ``impact``) for the
calibrated lines and the closed form of c0 and tau (docs/pair_viscontact.md, "Damping
prefactor c0"; Jian et al., Powder Technol. 356 (2019) 735).  Running these lines is in test_run.py.
"""

from __future__ import annotations

import pytest

import viscontact as vc
from viscontact import dem


PLUGIN = "/opt/plugins/viscontact.so"  # a stand-in path where no build is wanted


def _words(line: str) -> dict[str, str]:
    """keyword -> the word after it, for the keyword/value pairs of a pair_coeff line."""
    w = line.split()
    return {w[i]: w[i + 1] for i in range(len(w) - 1)}


# ------------------------------------------------------------------------ the coefficients
@pytest.mark.parametrize("law,e,beta,end", [
    ("LH", 0.5, None, "force"), ("Ts", 0.8, None, "overlap"), ("KK", 0.9, None, "force"),
    ("Li", 0.6, None, "force"), ("Hunt", 0.7, None, "overlap"), ("Jian", 0.75, 0.5, "force"),
])
def test_alpha_in_the_line_gives_e_at_vref(law, e, beta, end):
    """The alpha written into the pair_coeff line, read back as LAMMPS reads it, gives the
    target e at vref through the exact solver; a physical pair at vref (c0 and tau from the closed
    form)
    gives the same e through impact()."""
    dl = dem.contact_law(law, e=e, vref=1.7, beta=beta, end=end)
    lines = dem.coeff_lines(dl, E=2.0e7, nu=0.25, plugin=PLUGIN)
    w = _words(lines.pair_coeff)
    assert w["damping"] == law and w["end"] == end and w["vref"] == "1.7"
    alpha = float(w["alpha"])
    assert alpha == dl.alpha  # repr round-trips exactly
    b = None if beta is None else float(w["beta"])
    assert b == beta
    assert vc.restitution(law, alpha, beta=b, end=end, exact=True) == pytest.approx(e, abs=1e-9)
    # one contact of two equal spheres of that material, meeting at vref
    pair = vc.contact_pair(0.01, radius=0.02, modulus=2.0e7, poisson=0.25, mass2=0.01,
                           radius2=0.02, modulus2=2.0e7, poisson2=0.25)
    c0, tau = dl.physical(pair)
    hit = vc.impact(law, m_eff=pair.m_eff, k_hertz=pair.k_hertz, v=1.7, c=c0, tau=tau, end=end,
                    history=False)
    assert hit.e == pytest.approx(e, abs=1e-8)


def test_physical_coefficients_follow_the_closed_form():
    """c0 = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5), tau = beta (m*^2/(k^2 vref))^(1/5)."""
    m, k, v = 0.0123, 4.56e5, 0.8
    pair = vc.ContactPair(m_eff=m, k_hertz=k)
    for law, p in (("LH", 0.0), ("Ts", 0.25), ("KK", 0.5), ("Li", 1.0), ("Hunt", 1.5)):
        c0, tau = dem.contact_law(law, alpha=0.37, vref=v).physical(pair)
        assert tau is None
        assert c0 == pytest.approx(0.37 * m ** ((3 - 2 * p) / 5) * v ** ((1 - 4 * p) / 5)
                                   * k ** ((2 + 2 * p) / 5), rel=1e-13)
    c0, tau = dem.contact_law("power", alpha=0.37, vref=v, p=0.75).physical(pair)
    assert c0 == pytest.approx(0.37 * m ** 0.3 * v ** -0.4 * k ** 0.7, rel=1e-13)
    c0, tau = dem.contact_law("Jian", alpha=0.37, vref=v, beta=0.6).physical(pair)
    assert tau == pytest.approx(0.6 * (m * m / (k * k * v)) ** 0.2, rel=1e-13)
    assert c0 == pytest.approx(0.37 * m ** 0.4 * v ** -0.2 * k ** 0.6, rel=1e-13)


def test_keyword_forms():
    jian = dem.contact_law("jian", alpha=0.3, vref=2.0, beta=0.5, end="overlap")
    assert jian.keywords() == "damping Jian alpha 0.3 vref 2.0 beta 0.5 end overlap"
    c0 = dem.contact_law("Jian", c0=2253.4, tau=6.87e-4)
    assert c0.keywords() == "damping Jian c0 2253.4 tau 0.000687 end force"
    assert c0.physical(vc.ContactPair(m_eff=1.0, k_hertz=1.0)) == (2253.4, 6.87e-4)
    assert dem.contact_law("LH", c0=0.0).keywords() == "damping LH c0 0.0 end force"
    pw = dem.contact_law("power", alpha=0.1, vref=1.0, p=0.75)
    assert pw.keywords() == "damping power p 0.75 alpha 0.1 vref 1.0 end force"
    assert dem.contact_law("KK", e=1.0, vref=1.0).alpha == 0.0
    x = 0.1 + 0.2  # 0.30000000000000004: every digit LAMMPS needs
    assert float(_words(dem.contact_law("KK", alpha=x, vref=1.0).keywords())["alpha"]) == x


def test_coeff_lines_pair_and_wall():
    dl = dem.contact_law("KK", alpha=0.3, vref=1.5)
    smooth = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN)
    assert smooth.lines() == [
        f"plugin load '{PLUGIN}'", "pair_style viscontact",
        "pair_coeff * * hertz/material 10000000.0 0.3 damping KK alpha 0.3 vref 1.5 end force "
        "tangential none"]
    assert smooth.wall_fix is None and str(smooth) == "\n".join(smooth.lines())
    rough = dem.coeff_lines(dl, E=1e7, nu=0.3, friction=0.5, wall="rigid", types="1 2", plugin=PLUGIN)
    assert rough.pair_coeff.startswith("pair_coeff 1 2 hertz/material")
    assert rough.pair_coeff.endswith("tangential mindlin 0.5")
    assert rough.wall_fix == ("fix vcwall all viscontact/wall zplane 0.0 NULL wall_material rigid "
                              "damping KK alpha 0.3 vref 1.5 end force tangential mindlin 0.5")
    same = dem.coeff_lines(dl, E=1e7, nu=0.3, wall="same", plugin=PLUGIN).wall_fix
    assert "wall_material 10000000.0 0.3 damping KK" in same
    other = dem.coeff_lines(dl, E=1e7, nu=0.3, wall=(7e10, 0.22), plugin=PLUGIN).wall_fix
    assert "wall_material 70000000000.0 0.22 damping" in other
    spaced = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin="/a b/viscontact.so").plugin_load
    assert spaced == "plugin load '/a b/viscontact.so'"


@pytest.mark.parametrize("kwargs,match", [
    (dict(law="KK"), "exactly one of e"),
    (dict(law="KK", e=0.5, c0=1.0, vref=1.0), "exactly one of e"),
    (dict(law="Stokes", e=0.5, vref=1.0), "unknown model"),
    (dict(law="KK", e=0.5), "needs vref"),
    (dict(law="KK", e=1.5, vref=1.0), r"e must be in \[1e-06, 1\], got 1.5"),
    (dict(law="KK", e=0.0, vref=1.0), r"e must be in \[1e-06, 1\], got 0.0"),
    (dict(law="KK", e=float("nan"), vref=1.0), r"e must be in \[1e-06, 1\], got nan"),
    (dict(law="KK", e="0.5", vref=1.0), "e must be a number"),
    (dict(law="Hunt", e=1e-4, vref=1.0), "below what Hunt reaches"),
    (dict(law="KK", e=0.5, vref=0.0), r"vref must be in \[1e-06, 10000\] m/s, got 0.0"),
    (dict(law="KK", e=0.5, vref=float("inf")), r"vref must be in \[1e-06, 10000\] m/s"),
    (dict(law="KK", alpha=-0.1, vref=1.0), r"alpha must be in \[0, 1000\], got -0.1"),
    (dict(law="KK", alpha=1e4, vref=1.0), r"alpha must be in \[0, 1000\], got 10000.0"),
    (dict(law="KK", c0=-1.0), r"c0 must be in \[0, 1e\+300\] N s/m\^\(1\+p\), got -1.0"),
    (dict(law="KK", c0=float("inf")), r"c0 must be in \[0, 1e\+300\]"),
    (dict(law="KK", c0=1.0, vref=1.0), "vref goes with e or alpha"),
    (dict(law="Jian", e=0.5, vref=1.0), "needs beta"),
    (dict(law="Jian", e=0.5, vref=1.0, beta=-1.0), r"beta must be in \[0, 1000\], got -1.0"),
    (dict(law="Jian", e=0.5, vref=1.0, beta=1e4), r"beta must be in \[0, 1000\]"),
    (dict(law="KK", e=0.5, vref=1.0, beta=0.5), "takes no beta"),
    (dict(law="Jian", c0=1.0), "needs tau"),
    (dict(law="Jian", c0=1.0, tau=-1e-3), r"tau must be in \[0, 1e\+300\] s, got -0.001"),
    (dict(law="Jian", c0=1.0, beta=0.5, tau=1e-3), "beta goes with e or alpha"),
    (dict(law="Jian", alpha=0.3, vref=1.0, beta=0.5, tau=1e-3), "tau goes with c0"),
    (dict(law="KK", c0=1.0, tau=1e-3), "takes no tau"),
    (dict(law="power", alpha=0.3, vref=1.0), "needs the exponent p"),
    (dict(law="power", alpha=0.3, vref=1.0, p=-0.5), r"p must be in \[0, 10\], got -0.5"),
    (dict(law="power", alpha=0.3, vref=1.0, p=681.0), r"p must be in \[0, 10\], got 681.0"),
    (dict(law="KK", alpha=0.3, vref=1.0, p=0.5), "p is only for 'power'"),
    (dict(law="KK", alpha=0.3, vref=1.0, end="sideways"), "end must be one of"),
])
def test_contact_law_validation(kwargs, match):
    law = kwargs.pop("law")
    with pytest.raises(ValueError, match=match):
        dem.contact_law(law, **kwargs)


@pytest.mark.parametrize("kwargs,match", [
    (dict(E=0.0, nu=0.3), r"E .* must be in \[1, 1e\+13\] Pa, got 0.0"),
    (dict(E=float("inf"), nu=0.3), r"E .* must be in \[1, 1e\+13\] Pa, got inf"),
    (dict(E=1e7, nu=0.7), r"nu .* must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=-1.0), r"nu .* must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=0.3, friction=-0.1), r"friction coefficient mu must be in \[0, 10\], got -0.1"),
    (dict(E=1e7, nu=0.3, friction=1e3), r"friction coefficient mu must be in \[0, 10\]"),
    (dict(E=1e7, nu=0.3, wall="glass"), "wall material must be 'same', 'rigid' or"),
    (dict(E=1e7, nu=0.3, wall=(1e9, 0.6)), r"wall nu must be in \(-1, 0.5\]"),
    (dict(E=1e7, nu=0.3, wall=(-1e9, 0.2)), r"wall E must be in \[1, 1e\+13\] Pa, got -1000000000.0"),
    (dict(E=1e7, nu=0.3, types="1"), "types must be two atom types"),
    (dict(E=1e7, nu=0.3, types="a b"), "types must be two atom types"),
])
def test_coeff_lines_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dem.coeff_lines(dem.contact_law("KK", alpha=0.3, vref=1.0), plugin=PLUGIN, **kwargs)
    with pytest.raises(ValueError, match="DemLaw"):
        dem.coeff_lines("KK", E=1e7, nu=0.3, plugin=PLUGIN)


# ------------------------------------------------------------------ the other sub-models
def _after(line: str, key: str, n: int) -> list[str]:
    w = line.split()
    k = w.index(key)
    return w[k + 1:k + 1 + n]


def test_sub_model_keywords_pair_and_wall_from_one_writer():
    """Every sub-model's keywords on the pair line and, identically, on the wall line (one
    writer); numbers converted per unit style by their dimensions (cgs: N/m = 1e3 dyn/cm,
    N m = 1e7 dyn cm, J/m^2 = 1e3 erg/cm^2, W/(m^2 K) = 1e3 erg/(s cm^2 K))."""
    dl = dem.contact_law("KK", c0=100.0, end="overlap")
    kw = dict(normal=("jkr", 0.05), tangential=("mindlin_rescale", None, 0.5, 0.4),
              rolling=(1e3, 0.1, 0.2), twisting=("sds", 1e-3, 1e-6, 1e-3), heat=10.0, cutoff=0.02)
    cl = dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN, units="cgs", **kw)
    pair = cl.pair_coeff
    assert _after(pair, "jkr", 3) == ["100000000.0", "0.3", "50.0"]
    assert _after(pair, "tangential", 4) == ["mindlin_rescale", "NULL", "0.5", "0.4"]
    assert [float(x) for x in _after(pair, "rolling", 4)[1:]] == pytest.approx([1e6, 100.0, 0.2])
    assert [float(x) for x in _after(pair, "twisting", 4)[1:]] == pytest.approx([1e4, 10.0, 0.1])
    assert float(_after(pair, "area", 1)[0]) == pytest.approx(1e4)
    assert _after(pair, "cutoff", 1) == ["2.0"]
    cs = dem.coeff_set("KK", [dict(E=1e7, nu=0.3)], c0=100.0, end="overlap", plugin=PLUGIN,
                       units="cgs", walls=[dem.Wall("region", ("drum",), temperature=300.0)], **kw)
    wall = cs.wall_lines[0]
    assert wall.startswith("fix vcwall all viscontact/wall region drum wall_material rigid "
                           "normal jkr 50.0 damping KK")
    tail = pair[pair.index("damping"):pair.index(" cutoff")]
    assert tail in wall and "cutoff" not in wall and wall.endswith("temperature 300.0")
    assert cs.pairs[0].line.split()[3:] == pair.split()[3:]


@pytest.mark.parametrize("spec,words", [
    ("none", "tangential none"),
    (("mindlin", 0.5), "tangential mindlin 0.5"),
    (("mindlin", "NULL", 0.0, 0.5), "tangential mindlin 0.5"),
    (("mindlin", 2e3, 0.0, 0.5), "tangential mindlin 2000.0 0.0 0.5"),
    (("linear_nohistory", 0.3, 0.5), "tangential linear_nohistory 0.3 0.5"),
    (("linear_history", 1e4, 0.3, 0.5), "tangential linear_history 10000.0 0.3 0.5"),
    (("mindlin/force", None, 0.2, 0.5), "tangential mindlin/force NULL 0.2 0.5"),
    (("mindlin_rescale/force", None, 0.2, 0.5), "tangential mindlin_rescale/force NULL 0.2 0.5"),
])
def test_tangential_forms(spec, words):
    assert dem.Tangential.from_any(spec).words("si") == words


@pytest.mark.parametrize("kwargs,match", [
    (dict(normal=("jkr", 1.0)), "normal jkr needs end overlap"),
    (dict(normal="jkr"), "needs the surface energy W"),
    (dict(normal=("hertz", 1.0)), "takes no surface energy"),
    (dict(normal=("dmt", -1.0)), "W must be a finite number >= 0"),
    (dict(normal="bond"), "normal model must be one of hertz, dmt, jkr"),
    (dict(tangential=("linear_history", 0.3, 0.5)), "takes KT XGAMMA MU"),
    (dict(tangential=("mindlin", 1.0, 2.0)), r"or the short form: mindlin MU"),
    (dict(tangential=("linear_nohistory", -1.0, 0.5)), "XGAMMA must be a finite number >= 0"),
    (dict(tangential=("mindlin_rescale", None, 0.0, 20.0)), r"MU must be in \[0, 10\]"),
    (dict(tangential="spring"), "tangential model must be one of none, linear_nohistory"),
    (dict(tangential="none", friction=0.5), "not both"),
    (dict(rolling=(0.0, 1.0, 0.1)), "KR must be > 0"),
    (dict(rolling=(1.0, 1.0)), "rolling must be sds KR GAMMAR MUR"),
    (dict(twisting="marshall"), "twisting marshall needs a tangential spring"),
    (dict(twisting=("sds", 0.0, 1.0, 1.0)), "twisting sds KT must be > 0"),
    (dict(twisting=("sds", 1.0, 1.0)), "twisting must be marshall or sds"),
    (dict(heat=-1.0), "heat area K must be"),
    (dict(cutoff=0.0), "cutoff must be > 0"),
    (dict(heat=1.0, wall="rigid"), "needs its temperature"),
])
def test_sub_model_errors_are_one_line(kwargs, match):
    dl = dem.contact_law("LH", c0=1.0)
    with pytest.raises(ValueError, match=match) as err:
        dem.coeff_lines(dl, E=1e7, nu=0.3, plugin=PLUGIN, **kwargs)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("kwargs,match", [
    (dict(style="region", args=("a b",)), "region ID"),
    (dict(style="region", args=("drum",), shear=("x", 1.0)), "move a region wall"),
    (dict(style="zplane", args=(0.0, None), shear=("z", 1.0)), "DIM must not be z"),
    (dict(style="zcylinder", args=(0.1,), wiggle=("x", 0.01, 0.1)), "wiggles only along z"),
    (dict(style="zplane", args=(0.0, None), wiggle=("z", 0.01, 0.0)), "PERIOD must be a finite number > 0"),
    (dict(style="zplane", args=(0.0, None), wiggle=("z", 0.01, 0.1), shear=("x", 1.0)), "not both"),
    (dict(style="zplane", args=(0.0, None), temperature="T"), "v_NAME"),
])
def test_wall_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dem.Wall(**kwargs)


def test_wall_motion_words():
    w = dem.Wall("zplane", (0.0, None), wiggle=("z", 0.001, 0.01))
    cs = dem.coeff_set("LH", [dict(E=1e7, nu=0.3)], c0=1.0, plugin=PLUGIN, walls=[w], units="cgs")
    assert cs.wall_lines[0].endswith("tangential none wiggle z 0.1 0.01")
    w = dem.Wall("zcylinder", (0.05,), shear=("x", 0.2), temperature="v_Tw")
    cs = dem.coeff_set("LH", [dict(E=1e7, nu=0.3)], c0=1.0, plugin=PLUGIN, walls=[w], heat=5.0)
    assert cs.wall_lines[0].endswith("heat area 5.0 temperature v_Tw shear x 0.2")
