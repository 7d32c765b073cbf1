"""Property tests over random valid inputs (hypothesis)."""

import math

from hypothesis import given, strategies as st

import viscontact as vc
from laws_util import law_kwargs

alpha_st = st.floats(0.0, 10.0, allow_nan=False)
beta_st = st.floats(0.0, 10.0, allow_nan=False)
end_st = st.sampled_from(["force", "overlap"])
law_st = st.sampled_from(["LH", "Ts", "KK", "Li", "Hunt", "Jian", "power"])
p_st = st.floats(0.0, 3.0, allow_nan=False)


@given(law_st, alpha_st, beta_st, p_st, end_st)
def test_every_call_returns_a_physical_result(model, alpha, beta, p, end):
    r = vc.collide(model, alpha, end=end, history=False, **law_kwargs(model, beta, p))
    assert 0.0 <= r.e <= 1.0 + 1e-12
    if r.separated:
        assert math.isfinite(r.tc) and r.tc > 0
        assert abs(r.energy_error) <= 1e-8
    else:
        assert end == "overlap" and r.e == 0.0 and math.isinf(r.tc)


@given(law_st, alpha_st, alpha_st, beta_st, p_st, end_st)
def test_e_never_rises_with_alpha(model, a1, a2, beta, p, end):
    lo, hi = sorted((a1, a2))
    kw = law_kwargs(model, beta, p)
    assert vc.restitution(model, hi, end=end, **kw) <= vc.restitution(model, lo, end=end, **kw) + 1e-9


@given(alpha_st, beta_st, beta_st, end_st)
def test_e_never_falls_with_beta(alpha, b1, b2, end):
    lo, hi = sorted((b1, b2))
    assert vc.restitution("Jian", alpha, beta=hi, end=end) >= vc.restitution(
        "Jian", alpha, beta=lo, end=end) - 1e-9
