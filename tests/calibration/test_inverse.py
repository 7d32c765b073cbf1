"""restitution() and alpha_from_e(): broadcasting, round trips, errors (issue 2)."""

import numpy as np
import pytest

import viscontact as vc
from references import hunt_e, tsuji_overlap_alpha


def test_restitution_scalar_and_shapes():
    assert isinstance(vc.restitution("KK", 0.3), float)
    e = vc.restitution("KK", [[0.1, 0.2], [0.3, 0.4]])
    assert e.shape == (2, 2) and np.all(np.diff(e.ravel()) < 0)
    e = vc.restitution("Jian", 0.3, beta=[0.0, 0.5, 2.0])
    assert e.shape == (3,) and np.all(np.diff(e) > 0)
    assert e[0] == vc.restitution("KK", 0.3)
    e = vc.restitution("Jian", [[0.1], [0.3]], beta=[0.5, 1.0, 2.0])
    assert e.shape == (2, 3)


def test_restitution_matches_closed_forms():
    alphas = np.array([0.0, 0.2, 1.0, 5.0])
    np.testing.assert_allclose(vc.restitution("Hunt", alphas), [hunt_e(a) for a in alphas], atol=1e-8)


@pytest.mark.parametrize("end", ["force", "overlap"])
@pytest.mark.parametrize("model, kwargs", [("LH", {}), ("Ts", {}), ("KK", {}), ("Li", {}),
                                           ("Hunt", {}), ("Jian", {"beta": 1.0}),
                                           ("power", {"p": 2.0})])
def test_alpha_from_e_round_trip(model, kwargs, end):
    targets = np.array([0.95, 0.6, 0.2])
    alpha = vc.alpha_from_e(model, targets, end=end, **kwargs)
    assert alpha.shape == targets.shape and np.all(alpha > 0)
    back = vc.restitution(model, alpha, end=end, **kwargs)
    assert np.max(np.abs(back - targets)) <= 1e-9


def test_alpha_from_e_known_inverse():
    for e in (0.9, 0.5, 0.1):
        assert abs(vc.alpha_from_e("Ts", e, end="overlap") - tsuji_overlap_alpha(e)) < 1e-8


def test_alpha_from_e_of_one_is_zero():
    assert vc.alpha_from_e("LH", 1.0) == 0.0
    assert vc.alpha_from_e("Jian", 1, beta=2.0) == 0.0


def test_alpha_from_e_broadcasts_against_beta():
    a = vc.alpha_from_e("Jian", 0.7, beta=[0.0, 1.0])
    assert a.shape == (2,) and a[1] > a[0]
    assert abs(a[0] - vc.alpha_from_e("KK", 0.7)) < 1e-10


@pytest.mark.parametrize("bad", [0.0, -0.1, 1.5, float("nan"), float("inf"), "x"])
def test_alpha_from_e_rejects_e_outside_range(bad):
    with pytest.raises(ValueError, match=r"e must be (in \[1e-06, 1\]|a number)"):
        vc.alpha_from_e("KK", bad)


def test_alpha_from_e_unreachable_names_the_range():
    with pytest.raises(ValueError, match=r"allowed range is \["):
        vc.alpha_from_e("Hunt", 1e-6)


def test_restitution_rejects_bad_alpha():
    with pytest.raises(ValueError, match=r"alpha must be in \[0, 1000\]"):
        vc.restitution("KK", [0.1, -1.0])
    with pytest.raises(ValueError, match=r"beta must be in \[0, 1000\]"):
        vc.restitution("Jian", 0.1, beta=[0.1, float("nan")])
