"""Every law fitted to e(v): constants recovered from exact e(v), 1-sigma coverage and the
ranking over 100 synthetic data sets per law, the replicate and residual uncertainties, the
reader, too few points to rank, and the shipped real bounce timings."""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from viscontact.calibration import restitution
from viscontact.fit.bounces import drag_constant, read_drops, reduce_bounces
from viscontact.fit.recording import RecordingError
from viscontact.fit.restitution import (RES_LAWS, fit_restitution, fit_restitution_sets,
                                        model_e, read_restitution, restitution_data)
from viscontact.physics.laws import lookup

#: the generating constants: alpha_ref at vref = 1 m/s, and beta_ref (Jian) or p (power)
TRUTH = {"LH": (0.3, None), "Ts": (0.3, None), "KK": (0.3, None), "Li": (0.3, None),
         "Hunt": (0.3, None), "Jian": (0.6, 0.5), "power": (0.3, 0.8)}
V = np.geomspace(0.3, 3.0, 10)  # a decade of impact speed
SEEDS = 100


def true_e(law, v, exact=False):
    a, second = TRUTH[law]
    spec = lookup(law)
    if not exact:
        return model_e(law, v, 1.0, a, beta=second if spec.needs_beta else None,
                       p=second if spec.p is None else None)
    q = (4 * (second if spec.p is None else spec.p) - 1) / 5
    kw = {"beta": second * v ** 0.2} if spec.needs_beta else {"p": second} if spec.p is None else {}
    return restitution(law, a * v ** q, exact=True, **kw)


def sigma_of(v, e):
    """Drop tests' scatter (0.008 in e) with a phone's timing (0.1 ms on each of the two
    flights 2v/g that give e)."""
    timing = e * math.sqrt(2) * 1e-4 / (2 * v / 9.81)
    return np.sqrt(0.008 ** 2 + timing ** 2)


@pytest.mark.parametrize("law", RES_LAWS)
def test_exact_e_gives_back_the_constants(law):
    """e(v) from the exact solver (not the tables the fit uses): alpha_ref (and beta_ref or p)
    back to 1e-6."""
    e = true_e(law, V, exact=True)
    f = fit_restitution(restitution_data(V, e), [law], vref=1.0).laws[lookup(law).name]
    a, second = TRUTH[law]
    assert f.alpha == pytest.approx(a, rel=1e-6)
    if f.beta is not None:
        assert f.beta == pytest.approx(second, rel=1e-6)
    if lookup(law).p is None:
        assert f.p == pytest.approx(second, abs=1e-6)
    assert f.rms < 1e-8


@pytest.mark.parametrize("law", RES_LAWS)
def test_coverage_and_ranking_over_100_seeds(law):
    """The stated 1-sigma intervals cover the true constants in 68 % +- 10 % of the seeds; the
    generating law is first or within AICc 2 of the first in at least 90 % of them."""
    e0 = true_e(law, V)
    sig = sigma_of(V, e0)
    E = e0 + sig * np.random.default_rng(27).standard_normal((SEEDS, V.size))
    fits = {other: fit_restitution_sets(V, E, law=other, sigma=sig, vref=1.0)
            for other in RES_LAWS}
    mine = fits[lookup(law).name]
    a, second = TRUTH[law]
    cover = [np.mean(np.abs(mine.alpha - a) <= mine.alpha_err)]
    if second is not None:
        cover.append(np.mean(np.abs(mine.second - second) <= mine.second_err))
    for c in cover:
        assert 0.58 <= c <= 0.78, (law, cover)
    aicc = np.array([fits[o].aicc for o in RES_LAWS])
    near = np.mean(mine.aicc - aicc.min(axis=0) < 2.0)
    assert near >= 0.90, (law, near)


def test_uncertainty_from_residuals_and_from_replicates():
    rng = np.random.default_rng(5)
    e0 = true_e("KK", V)
    E = e0 + 0.01 * rng.standard_normal((SEEDS, V.size))
    sf = fit_restitution_sets(V, E, law="KK", vref=1.0)  # no sigma: from the residuals
    assert 0.58 <= np.mean(np.abs(sf.alpha - 0.3) <= sf.alpha_err) <= 0.78
    v = np.repeat(V[::3], 5)  # five drops at each of four speeds
    e = true_e("KK", v) + 0.01 * rng.standard_normal(v.size)
    fit = fit_restitution(restitution_data(v, e), ["KK", "Ts"], vref=1.0)
    assert fit.sigma_source == "replicates"
    f = fit.laws["KK"]
    assert abs(f.alpha - 0.3) < 4 * f.alpha_err
    assert f.loo is not None and f.loo > f.rms


def test_zero_overlap_end():
    """--end overlap: e(v) of KK under the zero-overlap end (exact solver) fitted with it gives
    alpha back; fitted with the zero-force end it does not."""
    e = restitution("KK", 0.3 * V ** 0.2, end="overlap", exact=True)
    data = restitution_data(V, e)
    assert fit_restitution(data, ["KK"], vref=1.0, end="overlap").laws["KK"].alpha == \
        pytest.approx(0.3, rel=1e-6)
    assert abs(fit_restitution(data, ["KK"], vref=1.0).laws["KK"].alpha - 0.3) > 1e-3


def test_too_few_points_fit_without_a_ranking():
    v = np.array([0.5, 1.0, 2.0])
    fit = fit_restitution(restitution_data(v, true_e("Jian", v)), vref=1.0)
    assert fit.ranking == [] and "too few points to rank" in fit.verdict
    assert fit.laws["KK"].aicc is not None and fit.laws["Jian"].aicc is None
    assert fit.laws["Jian"].alpha == pytest.approx(0.6, rel=1e-5)
    two = fit_restitution(restitution_data(v[:2], true_e("KK", v[:2])), vref=1.0)
    assert two.best.n_params == 1 and two.laws["power"].rms < 1e-9  # power fits any 2 points


def test_physical_constants_with_the_pair():
    """c = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5), tau = beta T(vref)."""
    m, k = 0.1547, 1.688e6
    fit = fit_restitution(restitution_data(V, true_e("Jian", V) + 1e-3 * np.sin(7 * V)),
                          ["Jian"], vref=1.0, mass=m, k_hertz=k)
    f = fit.laws["Jian"]
    assert f.c == pytest.approx(f.alpha * m ** 0.4 * k ** 0.6, rel=1e-12)
    assert f.tau == pytest.approx(f.beta * (m / k) ** 0.4, rel=1e-12)
    assert f.c_err == pytest.approx(f.c * f.alpha_err / f.alpha, rel=1e-9)


def test_read_restitution(tmp_path):
    f = tmp_path / "e.csv"
    f.write_text("# drop tests\nv [cm/s],e,sigma_e\n50,0.8,0.01\n100,0.75,0.01\n200,0.7,0.02\n")
    d = read_restitution(f)
    np.testing.assert_allclose(d.v, [0.5, 1.0, 2.0])
    np.testing.assert_allclose(d.sigma, [0.01, 0.01, 0.02])
    g = tmp_path / "plain.txt"
    g.write_text("0.5 0.8\n1.0 0.75\n")
    assert read_restitution(g).n == 2 and read_restitution(g).sigma is None


@pytest.mark.parametrize("text, msg", [
    ("", "no rows of numbers"),
    ("v,e\n1.0,0.8\n", "1 point"),
    ("v,e\n1.0,0.8\n2.0,1.2\n", r"e must lie in \(0, 1\]"),
    ("v,e\n1.0,0.8\n-2.0,0.7\n", "finite number > 0"),
    ("v,e\n1.0,0.8\nnan,0.7\n", "finite number > 0"),
    ("v,e\n1.0,0.8\n2.0,0\n", "finite number > 0"),
    ("speed [km/h],e\n1,0.8\n2,0.7\n", r"unit \[km/h\]"),
    ("v,foo\n1,0.8\n2,0.7\n", "header column 'foo'"),
    ("v,e\n1,0.8\n2\n", "every row needs 2 numbers"),
])
def test_bad_restitution_files(tmp_path, text, msg):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(RecordingError, match=msg):
        read_restitution(f)


def _shipped(name, mass, radius):
    path = resources.files("viscontact") / "data" / name
    red = reduce_bounces(read_drops(path), k_drag=drag_constant(mass, radius))
    return red, fit_restitution(red.data, rejected=red.rejected)


def test_shipped_table_tennis_ball():
    """25 drops of a table-tennis ball (docs/fit-restitution.md): no glitch; e falls with v
    weakly, so LH (e rising with v), Li and Hunt (falling fast) are out by AICc > 20, and
    KK, Ts, Jian and power cannot be told apart."""
    red, fit = _shipped("bounces_pingpong.csv", 2.7e-3, 0.02)
    assert red.data.n == 175 and not red.rejected
    best = fit.laws[fit.ranking[0]].aicc
    tied = {k for k in fit.ranking if fit.laws[k].aicc - best < 2}
    assert {"KK", "power"} <= tied and "cannot tell" in fit.verdict
    for k in ("LH", "Li", "Hunt"):
        assert fit.laws[k].aicc - best > 20
    assert 0.9 < fit.data.e.mean() < 0.99


def test_shipped_golf_ball():
    """20 drops of a golf ball: the one repeated reading is named and its two points left
    out; e is nearly constant over 1.7-4.1 m/s: Ts (constant e) and power (p near 1/4) lead,
    KK is out by AICc > 20."""
    red, fit = _shipped("bounces_golf.csv", 45.93e-3, 0.021335)
    assert len(red.rejected) == 2 and all("repeated reading" in r["reason"]
                                          for r in red.rejected)
    best = fit.laws[fit.ranking[0]].aicc
    assert fit.laws["Ts"].aicc - best < 2 and fit.laws["KK"].aicc - best > 20
    assert abs(fit.laws["power"].p - 0.25) < 3 * fit.laws["power"].p_err


def test_k_hertz_from_measured_contact_times():
    """Contact times of exact impacts (viscontact.impact, one c for all speeds) give k_Hertz
    back through the law's own t_c / T, and with it c."""
    import viscontact as vc

    m, k, c = 0.1547, 1.688e6, 600.0
    hits = [vc.impact("KK", m_eff=m, k_hertz=k, v=float(v), c=c, history=False) for v in V]
    data = restitution_data(V, [h.e for h in hits], tc=[h.tc for h in hits])
    f = fit_restitution(data, ["KK"], mass=m).laws["KK"]
    assert f.k_hertz == pytest.approx(k, rel=1e-6)
    assert f.c == pytest.approx(c, rel=1e-6)
