"""Accuracy of the single-collision solver against independent references (issue 2)."""

import math

import numpy as np
import pytest

import viscontact as vc
from viscontact.physics.kernels import force
from conftest import taylor_params
from laws_util import law_kwargs
from references import (TC_HERTZ, XMAX_HERTZ, hunt_e, taylor_reference, tsuji_force_e,
                        tsuji_overlap_alpha)

E_TOL, TC_TOL = 1e-8, 1e-7
ENDS = ("force", "overlap")
ALPHAS = [1e-9, 1e-4, 0.01, 0.1, 0.3, 0.7, 1.0, 2.0, 4.0, 7.0, 10.0]


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model", vc.MODELS)
def test_undamped_contact_is_hertz(model, end):
    r = vc.collide(model, 0.0, end=end, **law_kwargs(model))
    assert r.separated
    assert abs(r.e - 1.0) <= E_TOL
    assert abs(r.tc - TC_HERTZ) <= TC_TOL
    assert abs(r.xmax - XMAX_HERTZ) <= 1e-9
    assert abs(r.t_xmax - TC_HERTZ / 2) <= 1e-9
    assert r.residual <= 1e-12 and abs(r.dissipated) <= 1e-12


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("alpha", ALPHAS)
def test_hunt_crossley_exact_relation(alpha, end):
    r = vc.collide("Hunt", alpha, end=end, history=False)
    assert abs(r.e - hunt_e(alpha)) <= E_TOL


@pytest.mark.parametrize("e_exact", [0.999, 0.9, 0.7, 0.5, 0.3, 0.1, 0.03, 0.01, 1e-3, 1e-5])
def test_tsuji_zero_overlap_closed_form(e_exact):
    alpha = tsuji_overlap_alpha(e_exact)
    r = vc.collide("Ts", alpha, end="overlap", history=False)
    assert r.separated and r.tc < 100
    assert abs(r.e - e_exact) <= E_TOL


@pytest.mark.parametrize("alpha", [math.sqrt(5), 2.3, 3.0, 10.0])
def test_tsuji_zero_overlap_never_separates_beyond_sqrt5(alpha):
    r = vc.collide("Ts", alpha, end="overlap")
    assert not r.separated and r.e == 0.0 and math.isinf(r.tc)
    assert "no rebound" in r.status


@pytest.mark.parametrize(
    "alpha", [1e-9, 1e-3, 0.1, 0.3, 1.0, 1.5, 1.58, 1.59, 2.0, 2.236, 2.237, 3.0, 5.0, 10.0]
)
def test_tsuji_zero_force_closed_form(alpha):
    r = vc.collide("Ts", alpha, end="force", history=False)
    assert abs(r.e - tsuji_force_e(alpha)) <= E_TOL


TAYLOR_CASES = [
    ("LH", 0.0, 0.3), ("LH", 0.0, 1.0), ("LH", 0.0, 4.0), ("LH", 0.0, 10.0),
    ("KK", 0.0, 1e-6), ("KK", 0.0, 0.3), ("KK", 0.0, 2.0), ("KK", 0.0, 10.0),
    ("Li", 0.0, 0.3), ("Li", 0.0, 3.0), ("Li", 0.0, 10.0),
    ("Jian", 1e-9, 0.3), ("Jian", 0.1, 1.0), ("Jian", 0.5, 0.3), ("Jian", 3.2, 2.0),
    ("Jian", 10.0, 10.0), ("Jian", 2.0, 1e-9),
    ("power", 0.0, 0.5), ("power", 0.0, 5.0),
]


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model, beta, alpha", taylor_params(TAYLOR_CASES))
def test_against_high_precision_taylor_solution(model, beta, alpha, end):
    p = 0.75 if model == "power" else vc.LAWS[model].p
    ref = taylor_reference(p, alpha, beta, end, t_stop=20.0)
    r = vc.collide(model, alpha, end=end, history=False, **law_kwargs(model, beta, p))
    if ref is None:  # still in contact at t = 20: only the zero-overlap end may do that
        assert end == "overlap"
        assert not r.separated or r.tc > 20
        return
    assert r.separated
    assert abs(r.e - ref[0]) <= E_TOL
    assert abs(r.tc - ref[1]) <= TC_TOL


PUBLISHED = {"LH": 0.6207, "Ts": 0.6778, "KK": 0.7221, "Li": 0.7890, "Hunt": 0.8329, "Jian": 0.7622}


@pytest.mark.parametrize("model", list(PUBLISHED))
def test_published_restitution_at_alpha_03(model):
    r = vc.collide(model, 0.3, beta=0.5 if model == "Jian" else None, history=False)
    assert round(r.e, 4) == PUBLISHED[model]


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model", vc.MODELS)
@pytest.mark.parametrize("alpha", [0.05, 0.3, 1.5, 6.0])
def test_energy_balance_closes(model, alpha, end):
    r = vc.collide(model, alpha, end=end, history=False, **law_kwargs(model))
    if r.separated:
        assert abs(r.energy_error) <= 1e-8


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("alpha", [0.01, 0.3, 3.0])
def test_jian_with_zero_beta_is_kk(alpha, end):
    a = vc.collide("Jian", alpha, beta=0.0, end=end)
    b = vc.collide("KK", alpha, end=end)
    assert a.e == b.e and a.tc == b.tc and a.fmax == b.fmax


def test_error_falls_as_tolerance_tightens():
    alphas = [0.1, 0.5, 2.0]
    errors = []
    for rtol in (1e-5, 1e-7, 1e-9, 1e-11):
        errors.append(max(abs(vc.collide("Hunt", a, rtol=rtol, history=False).e - hunt_e(a))
                          for a in alphas))
    assert all(later < earlier for earlier, later in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-3 * errors[0]


@pytest.mark.parametrize("model", ["LH", "Ts", "Jian"])
def test_histories_are_consistent(model):
    r = vc.collide(model, 0.8, **law_kwargs(model))
    assert r.t[0] == 0 and r.t[-1] == pytest.approx(r.tc, abs=1e-12)
    assert np.all(np.diff(r.t) > 0) and np.all(r.x >= 0)
    assert r.v[0] == 1 and r.v[-1] == pytest.approx(-r.e, abs=1e-12)
    g = 1 - np.exp(-r.t / r.beta) if r.beta else 1.0
    expected = r.x**1.5 + 0.8 * g * r.x ** r.p * r.v
    np.testing.assert_allclose(r.f, expected, atol=1e-9)
    assert r.fmax >= r.f.max() - 1e-12 and r.fmax <= r.f.max() + 1e-3
    assert r.xmax >= r.x.max() - 1e-12
    # F^ = -x'': the histories satisfy Newton's law (finite differences)
    accel = np.gradient(r.v, r.t)
    np.testing.assert_allclose(-accel[5:-5], r.f[5:-5], atol=5e-3)


def test_lee_herrmann_starts_with_force_alpha():
    r = vc.collide("LH", 2.5)
    assert r.f[0] == pytest.approx(2.5) and r.fmax >= 2.5


def test_kernel_force_matches_law_definition():
    assert force(0.25, -0.5, 1.0, 0.3, 0.0, 0.5) == pytest.approx(0.125 + 0.3 * 0.5 * -0.5)
    assert force(0.25, -0.5, 1.0, 0.3, 2.0, 0.5) == pytest.approx(
        0.125 + 0.3 * (1 - math.exp(-0.5)) * 0.5 * -0.5)


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"alpha": -0.1}, r"alpha must be in \[0, 1000\]"),
        ({"alpha": float("nan")}, r"alpha must be in \[0, 1000\]"),
        ({"alpha": "abc"}, "alpha must be a number"),
        ({"alpha": 0.3, "end": "contact"}, "end must be one of force, overlap"),
    ],
)
def test_collide_bad_input(kwargs, fragment):
    with pytest.raises(ValueError, match=fragment):
        vc.collide("KK", **kwargs)


def test_heavily_damped_overlap_end_returns_promptly_flagged():
    r = vc.collide("LH", 10.0, end="overlap")
    assert not r.separated and r.e == 0.0 and math.isinf(r.tc)
    d = r.to_dict()
    assert d["tc"] is None and d["separated"] is False
