"""The compiled batch solver (issue 4, item 1) against independent references and the
reference solver: accuracy at the default and at a tight tolerance, convergence, shapes,
non-separating contacts, and the vectorised calibration built on it."""

import math

import numpy as np
import pytest
from hypothesis import given, strategies as st

import viscontact as vc
from viscontact.physics.laws import LawParams, resolve
from viscontact.solvers import SOLVERS
from viscontact.solvers.batch import BATCH_RTOL, solve_batch
from viscontact.solvers.reference import solve_reference
from conftest import taylor_params
from references import TC_HERTZ, hunt_e, taylor_reference, tsuji_force_e, tsuji_overlap_alpha
from laws_util import law_kwargs

E_TOL, TC_TOL = 1e-8, 1e-7  # the contract
TIGHT_RTOL, TIGHT_E_TOL = 1e-13, 5e-12  # what the interpolation-table builder relies on
ENDS = ("force", "overlap")
ALPHAS = np.array([0.0, 1e-9, 1e-6, 1e-3, 0.05, 0.3, 1.0, 2.0, 4.0, 7.0, 10.0])


def _lp(model, beta=None):
    kw = law_kwargs(model)
    if beta is not None:
        kw["beta"] = beta
    return resolve(model, **kw)


@pytest.mark.parametrize("rtol, tol", [(BATCH_RTOL, 1e-9), (TIGHT_RTOL, TIGHT_E_TOL)])
@pytest.mark.parametrize("end", ENDS)
def test_hunt_crossley_exact_relation(end, rtol, tol):
    r = solve_batch(_lp("Hunt"), ALPHAS, end, rtol=rtol)
    assert np.all(r.separated)
    assert np.max(np.abs(r.e - [hunt_e(a) for a in ALPHAS])) <= tol


@pytest.mark.parametrize("rtol, tol", [(BATCH_RTOL, 1e-9), (TIGHT_RTOL, TIGHT_E_TOL)])
def test_tsuji_closed_forms_both_ends(rtol, tol):
    r = solve_batch(_lp("Ts"), ALPHAS, "force", rtol=rtol)
    assert np.max(np.abs(r.e - [tsuji_force_e(a) for a in ALPHAS])) <= tol
    e_exact = np.array([0.999, 0.9, 0.5, 0.1, 0.01, 1e-3, 1e-5])
    r = solve_batch(_lp("Ts"), [tsuji_overlap_alpha(e) for e in e_exact], "overlap", rtol=rtol)
    assert np.all(r.separated)
    assert np.max(np.abs(r.e - e_exact)) <= tol


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model", vc.MODELS)
def test_undamped_contact_is_hertz(model, end):
    r = solve_batch(_lp(model), np.zeros(3), end, beta=[0.0, 1e-9, 10.0] if model == "Jian" else None)
    assert np.all(np.abs(r.e - 1.0) <= 1e-9) and np.all(np.abs(r.tc - TC_HERTZ) <= 1e-8)
    assert np.all(np.abs(r.dissipated) <= 1e-12) and np.all(r.residual <= 1e-12)


# (model, beta, alpha): alpha and beta from 1e-9 to 10; Hunt has its exact relation above
# (F = x^(3/2) (1 + alpha x') vanishes too flatly for the reference's root finder)
TAYLOR_CASES = [
    ("LH", 0.0, 1e-9), ("LH", 0.0, 10.0), ("Ts", 0.0, 0.7), ("KK", 0.0, 1e-9), ("Li", 0.0, 4.0),
    ("Jian", 1e-9, 10.0), ("Jian", 10.0, 1e-9), ("Jian", 0.3, 2.0),
    ("power", 0.0, 3.0),
]


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model, beta, alpha", taylor_params(TAYLOR_CASES))
def test_against_high_precision_taylor_solution(model, beta, alpha, end):
    lp = _lp(model, beta if model == "Jian" else None)
    ref = taylor_reference(lp.p, alpha, beta, end, t_stop=20.0)
    default = solve_batch(lp, [alpha], end)
    tight = solve_batch(lp, [alpha], end, rtol=TIGHT_RTOL)
    if ref is None:  # still in contact at t = 20: only the zero-overlap end may do that
        assert end == "overlap"
        assert not default.separated[0] or default.tc[0] > 20
        return
    assert default.separated[0] and tight.separated[0]
    assert abs(default.e[0] - ref[0]) <= 1e-9 and abs(default.tc[0] - ref[1]) <= 1e-8
    assert abs(tight.e[0] - ref[0]) <= TIGHT_E_TOL and abs(tight.tc[0] - ref[1]) <= 1e-10


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("model", vc.MODELS)
def test_agrees_with_reference_solver_on_a_grid(model, end):
    rng = np.random.default_rng(7)
    alpha = np.concatenate([ALPHAS, rng.uniform(0, 10, 12), 10 ** rng.uniform(-9, 1, 6)])
    beta = (np.concatenate([np.full(ALPHAS.size, 0.5), rng.uniform(0, 10, 12),
                            10 ** rng.uniform(-9, 1, 6)]) if model == "Jian" else None)
    lp = _lp(model)
    r = solve_batch(lp, alpha, end, beta=beta)
    for i, a in enumerate(alpha):
        lpi = lp if beta is None else LawParams(lp.law, lp.p, float(beta[i]), lp.m)
        ref = solve_reference(lpi, float(a), end, detail=False)
        assert r.separated[i] == ref.separated
        assert abs(r.e[i] - ref.e) <= E_TOL
        if ref.separated:
            assert abs(r.tc[i] - ref.tc) <= TC_TOL
            assert abs(r.residual[i] - ref.residual) <= 1e-8
            assert abs(r.dissipated[i] - ref.dissipated) <= 1e-8
        else:
            assert r.e[i] == 0.0 and math.isinf(r.tc[i])


@given(st.sampled_from(list(vc.MODELS)), st.floats(0.0, 10.0), st.floats(0.0, 10.0),
       st.floats(0.0, 3.0), st.sampled_from(ENDS))
def test_property_batch_matches_reference(model, alpha, beta, p, end):
    lp = resolve(model, **law_kwargs(model, beta, p))
    r = solve_batch(lp, [alpha], end)
    ref = solve_reference(lp, alpha, end, detail=False)
    assert bool(r.separated[0]) == ref.separated
    assert abs(r.e[0] - ref.e) <= E_TOL
    if ref.separated:
        assert abs(r.tc[0] - ref.tc) <= TC_TOL


@pytest.mark.parametrize("model", ["Hunt", "Ts"])
def test_error_falls_as_tolerance_tightens(model):
    exact = hunt_e if model == "Hunt" else tsuji_force_e
    alphas = np.array([0.05, 0.5, 2.0, 8.0])
    errors = [np.max(np.abs(solve_batch(_lp(model), alphas, rtol=rtol).e - [exact(a) for a in alphas]))
              for rtol in (1e-6, 1e-8, 1e-10, 1e-12)]
    assert all(later < earlier for earlier, later in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-4 * errors[0]


def test_non_separating_contacts_are_flagged_promptly():
    alpha = np.array([math.sqrt(5), 3.0, 10.0, 0.3])
    r = solve_batch(_lp("Ts"), alpha, "overlap")
    assert list(r.separated) == [False, False, False, True]
    assert np.all(r.e[:3] == 0.0) and np.all(np.isinf(r.tc[:3]))
    r = solve_batch(_lp("LH"), np.full(50, 10.0), "overlap")
    assert not r.separated.any()


def test_every_collision_independent_of_its_batch():
    """Slots are refilled and compacted: a result must not depend on its neighbours."""
    rng = np.random.default_rng(3)
    alpha, beta = rng.uniform(0, 10, 5000), rng.uniform(0, 10, 5000)
    whole = solve_batch(_lp("Jian"), alpha, beta=beta)
    pick = rng.choice(5000, 20, replace=False)
    for i in pick:
        one = solve_batch(_lp("Jian"), alpha[i:i + 1], beta=beta[i:i + 1])
        assert abs(one.e[0] - whole.e[i]) <= 1e-15 and abs(one.tc[0] - whole.tc[i]) <= 1e-14
    shuffled = rng.permutation(5000)
    again = solve_batch(_lp("Jian"), alpha[shuffled], beta=beta[shuffled])
    np.testing.assert_allclose(again.e, whole.e[shuffled], rtol=0, atol=1e-15)


def test_shapes_broadcast_empty_and_scalar():
    r = solve_batch(_lp("Jian"), np.array([[0.1], [0.3], [1.0]]), beta=[0.0, 0.5, 1.0, 2.0])
    assert r.e.shape == r.tc.shape == r.separated.shape == (3, 4)
    assert r.e[1, 0] == solve_batch(_lp("KK"), [0.3]).e[0]  # beta = 0 is KK
    assert np.all(np.diff(r.e, axis=0) < 0) and np.all(np.diff(r.e, axis=1) > 0)
    empty = solve_batch(_lp("KK"), np.empty((0, 3)))
    assert empty.e.shape == (0, 3)
    assert vc.restitution("KK", []).shape == (0,)
    assert isinstance(vc.restitution("Li", 0.2), float)
    assert isinstance(vc.alpha_from_e("Li", 0.5), float)


def test_general_power_law_takes_the_general_path():
    lp = resolve("power", p=0.3)  # m p not an integer: |s|^k by pow
    alpha = np.array([0.0, 0.2, 3.0])
    r = solve_batch(lp, alpha)
    for a, e in zip(alpha, r.e):
        assert abs(e - solve_reference(lp, float(a), "force", detail=False).e) <= E_TOL


def test_collide_without_history_uses_the_batch_solver():
    r = vc.collide("Hunt", 0.4, history=False)
    assert abs(r.e - hunt_e(0.4)) <= 1e-9 and r.t.size == 0
    assert SOLVERS["batch"](_lp("Hunt"), 0.4, "force").e == r.e
    with pytest.raises(ValueError, match="no histories"):
        SOLVERS["batch"](_lp("Hunt"), 0.4, "force", detail=True)


def test_restitution_validates_large_arrays_with_the_usual_messages():
    alpha = np.linspace(0.0, 10.0, 100_000)
    alpha[77_777] = -1.0
    with pytest.raises(ValueError, match=r"alpha must be in \[0, 1000\]"):
        vc.restitution("KK", alpha)
    with pytest.raises(ValueError, match="alpha must be a number"):
        vc.restitution("KK", [0.1, "x"])
    with pytest.raises(ValueError, match="end must be one of"):
        solve_batch(_lp("KK"), [0.1], "contact")


@pytest.mark.parametrize("end", ENDS)
def test_alpha_from_e_vectorised_round_trip(end):
    rng = np.random.default_rng(11)
    e = rng.uniform(0.05, 1.0, 400)
    e[:3] = [1.0, 0.999999, 0.05]
    beta = rng.uniform(0.0, 10.0, 400)
    alpha = vc.alpha_from_e("Jian", e, beta=beta, end=end)
    assert alpha.shape == e.shape and alpha[0] == 0.0 and np.all(alpha[1:] > 0)
    back = vc.restitution("Jian", alpha, beta=beta, end=end)
    assert np.max(np.abs(back - e)) <= 1e-9


def test_alpha_from_e_unreachable_in_an_array_names_the_range():
    with pytest.raises(ValueError, match=r"allowed range is \["):
        vc.alpha_from_e("Hunt", [0.5, 1e-6, 0.9])
    with pytest.raises(ValueError, match=r"e must be (in \[1e-06, 1\]|a number)"):
        vc.alpha_from_e("KK", np.array([0.5, 1.5]))


@pytest.mark.parametrize("end", ENDS)
def test_without_dissipated_work_e_and_tc_stay_exact(end):
    """``dissipated=False`` (what ``restitution`` asks) integrates no W: NaN there, and e,
    t_c, separation as accurate as with it."""
    lite = solve_batch(_lp("Hunt"), ALPHAS, end, dissipated=False)
    full = solve_batch(_lp("Hunt"), ALPHAS, end)
    assert np.all(np.isnan(lite.dissipated)) and not np.any(np.isnan(full.dissipated))
    assert np.array_equal(lite.separated, full.separated)
    assert np.max(np.abs(lite.e - [hunt_e(a) for a in ALPHAS])) <= 1e-9
    assert np.max(np.abs(lite.tc - full.tc)) <= 1e-8


def test_generated_step_matches_its_generator():
    """_dop853_lanes.py is generated; an edit by hand or a changed tableau must show."""
    from viscontact.solvers import _codegen

    assert (_codegen.TARGET.read_text() == _codegen.source()), (
        "run python3 -m viscontact.solvers._codegen")


def test_the_solver_is_compiled_before_its_first_call_for_its_types(monkeypatch):
    """solve_batch compiles (or loads) each shape under a lock shared by processes
    (``compile_once``) for the types of the arguments it then calls it with: the call adds
    no compilation (a type that differed would compile a second signature)."""
    from viscontact.solvers import batch

    monkeypatch.setattr(batch, "_SOLVERS", {})  # a fresh solver object: nothing compiled yet
    for end in ENDS:
        solve_batch(_lp("Jian", 0.5), np.linspace(0.0, 3.0, 5), end)
    (solver,) = batch._SOLVERS.values()
    assert len(solver.signatures) == 1
