"""The audit's formulas (viscontact.audit.formulas): closed forms against published values,
the exact relations against the solver, ``audit_formula``, and properties over e (hypothesis).

Kept to a few dozen exact solves (the reference solver does ~100 collisions/s).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import viscontact as vc
from viscontact.audit import formulas as F
from viscontact.audit.engines import get_preset


# ------------------------------------------------------------------ formulas: closed forms
@pytest.mark.parametrize("name,e,alpha", [
    ("hunt-crossley", 0.5, 0.75),
    ("lee-wang", 0.5, 0.375),
    ("herbert-mcwhannell", 0.5, 1.0),
    ("herbert-mcwhannell", 0.8, 6 * 0.2 / (0.36 + 3)),
    ("lankarani-nikravesh", 0.5, 0.5625),
    ("gonthier", 0.5, 1.5),
    ("zhiying-qishao", 0.5, 0.5625 * math.e),
    ("flores", 0.5, 1.6),
    ("gharib-hurmuzlu", 0.5, 1.0),
    ("hu-guo", 0.5, 1.5),
    ("antypov-elliott", 0.5, math.sqrt(5) * math.log(2) / math.sqrt(math.log(2) ** 2 + math.pi**2)),
    ("tsuji-lammps", 1.0, 0.0003),
    ("tsuji-lammps", 0.0 + 1e-300, 1.2728),
    ("tsuji-lammps-sqrt2", 1.0, 0.0003 * math.sqrt(2)),
])
def test_formula_values(name, e, alpha):
    assert F.FORMULAS[name].alpha(e) == pytest.approx(alpha, rel=1e-9, abs=1e-12)


def test_registry_has_every_formula_of_the_issue():
    names = set(F.FORMULAS)
    for n in ("hunt-crossley", "lee-wang", "herbert-mcwhannell", "lankarani-nikravesh", "gonthier",
              "zhiying-qishao", "flores", "gharib-hurmuzlu", "hu-guo", "carvalho-martins",
              "schwager-poschel", "muller-poschel", "antypov-elliott", "tsuji-lammps",
              "tsuji-lammps-sqrt2", "first-order-lh", "first-order-ts", "first-order-kk",
              "first-order-li", "first-order-hunt"):
        assert n in names
    for f in F.FORMULAS.values():
        assert f.reference and f.model in vc.LAWS
        assert f.alpha(1.0) == pytest.approx(0.0, abs=1e-3)  # no damping for e = 1 (Tsuji curve: 3e-4)


def test_schwager_poschel_roundtrip_and_no_root():
    for e in (0.6, 0.8, 0.95):
        a = F.FORMULAS["schwager-poschel"].alpha(e)
        assert 1 - 1.15344 * a + 0.79827 * a * a == pytest.approx(e, abs=1e-13)
    assert math.isnan(F.FORMULAS["schwager-poschel"].alpha(0.5))  # below 1 - C1^2/(4 C2) = 0.5833


def test_muller_poschel_roundtrip_and_its_criterion():
    for e in (0.1, 0.5, 0.95):
        assert F.muller_poschel_e(F.FORMULAS["muller-poschel"].alpha(e)) == pytest.approx(e, abs=1e-13)
    # the Pade was fitted to the zero-force (delayed recovery) values: closer to them
    pade = F.muller_poschel_e(1.0)
    ef, eo = vc.restitution("KK", 1.0), vc.restitution("KK", 1.0, end="overlap")
    assert abs(pade - ef) < 0.1 * abs(pade - eo)


def test_first_order_coefficient_matches_published_and_the_solver():
    assert F.first_order_coefficient(0.5) == pytest.approx(1.15344, abs=1e-5)  # Schwager-Poschel C1
    assert F.first_order_coefficient(1.5) == pytest.approx(2 / 3, rel=1e-14)  # Hunt: 3(1-e)/2
    a = 1e-4  # slope of e(alpha) at 0 (zero overlap: no early end, the cleanest expansion)
    for model, p in (("LH", 0.0), ("Li", 1.0)):
        slope = (1 - vc.restitution(model, a, end="overlap")) / a
        assert slope == pytest.approx(F.first_order_coefficient(p), rel=2e-4)


def test_first_order_generic_and_errors():
    f = F.get_formula("first-order", model="power", p=0.7)
    assert f.model == "power" and f.p == 0.7
    assert f.alpha(0.8) == pytest.approx(0.2 / F.first_order_coefficient(0.7))
    with pytest.raises(ValueError, match="needs a model"):
        F.get_formula("first-order")
    with pytest.raises(ValueError, match="Jian"):
        F.get_formula("first-order", model="Jian")
    with pytest.raises(ValueError, match="unknown formula"):
        F.get_formula("nope")
    with pytest.raises(ValueError, match="not KK"):
        F.get_formula("gonthier", model="KK")
    for bad in (0.0, -0.1, 1.5, float("nan"), "x"):
        with pytest.raises(ValueError, match=r"\(0, 1\]"):
            F.FORMULAS["gonthier"].alpha(bad)


# ----------------------------------------------------------- exact relations vs the solver
@pytest.mark.parametrize("e", [0.3, 0.9])
def test_hunt_exact_relation_matches_solver_both_ends(e):
    a = F.hunt_exact_alpha(e)
    for end in ("force", "overlap"):
        assert vc.restitution("Hunt", a, end=end) == pytest.approx(e, abs=1e-9)


@pytest.mark.parametrize("e", [0.3, 0.9])
def test_antypov_elliott_exact_for_zero_overlap(e):
    a = F.antypov_elliott_alpha(e)
    assert vc.restitution("Ts", a, end="overlap") == pytest.approx(e, abs=1e-8)
    assert vc.restitution("Ts", a, end="force") > e + 1e-3  # the clamp raises e
    assert F.antypov_elliott_inverse(a) == pytest.approx(e, rel=1e-13)


def test_antypov_elliott_inverse_range():
    with pytest.raises(ValueError, match="sqrt\\(5\\)"):
        F.antypov_elliott_inverse(2.3)


def test_tsuji_polynomial_decreasing():
    v = [F.tsuji_polynomial(x) for x in np.linspace(0, 1, 2001)]
    assert np.all(np.diff(v) < 0)


# ------------------------------------------------------------------------ audit_formula
def test_audit_formula_fields():
    r = F.audit_formula("lankarani-nikravesh", 0.5, "force")
    assert r.alpha == 0.5625
    assert r.error == pytest.approx(r.delivered_e - 0.5)
    assert r.delivered_e == pytest.approx(vc.restitution("Hunt", 0.5625), abs=1e-12)
    assert r.exact_alpha == pytest.approx(vc.alpha_from_e("Hunt", 0.5), abs=1e-9)
    assert r.delivered_e > 0.7  # a well-known overestimate at low e
    none = F.audit_formula("schwager-poschel", 0.3, "force")  # no alpha: None, never NaN
    assert none.alpha is None and none.delivered_e is None and none.error is None
    assert math.isfinite(none.exact_alpha) and "gives no alpha" in none.note
    far = F.audit_formula("flores", 1e-3, "force")  # 8(1-e)/(5e) = 1598.4 > ALPHA_MAX
    assert far.alpha == pytest.approx(8 * 0.999 / 5e-3) and far.delivered_e is None
    assert far.error is None and "outside the domain [0, 1000]" in far.note


def test_audit_formula_exact_alpha_is_exact():
    r = F.audit_formula("antypov-elliott", 0.5, "force")
    assert vc.restitution("Ts", r.exact_alpha) == pytest.approx(0.5, abs=1e-9)
    with pytest.raises(ValueError, match="end"):
        F.audit_formula("antypov-elliott", 0.5, "sideways")


# --------------------------------------------------------- properties (no solves: cheap)
_E = st.floats(min_value=1e-6, max_value=1.0, exclude_max=True, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(_E)
def test_hunt_exact_relation_property(e):
    a = F.hunt_exact_alpha(e)
    assert 0 < a <= 1 / e
    if a * e > 1 - 1e-9:  # small e: the root is 1/e to machine precision
        assert e < 0.05
    else:
        lhs, rhs = (1 + e) * a, math.log1p(a) - math.log1p(-a * e)
        slope = 1 / (1 + a) + e / (1 - a * e)  # d rhs / d alpha: conditioning near 1/e
        assert abs(lhs - rhs) <= 1e-13 * (lhs + a * slope)
    if 1 - e < 1e-6:
        assert a == pytest.approx(1.5 * (1 - e), rel=1e-5)  # Hunt-Crossley is its first order


@settings(max_examples=200, deadline=None)
@given(_E)
def test_every_formula_defined_or_nan_and_inverses(e):
    for f in F.FORMULAS.values():
        a = f.alpha(e)
        assert math.isnan(a) or a >= 0
    assert F.muller_poschel_e(F.FORMULAS["muller-poschel"].alpha(e)) == pytest.approx(e, rel=1e-9)
    a = F.antypov_elliott_alpha(e)
    assert F.antypov_elliott_inverse(a) == pytest.approx(e, rel=1e-9)
    pre = get_preset("lammps", "tsuji")
    assert pre.to_alpha(pre.from_alpha(pre.to_alpha(e, None), None), None) == pytest.approx(
        pre.to_alpha(e, None), rel=1e-9)
