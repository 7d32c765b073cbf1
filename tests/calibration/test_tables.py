"""Interpolation tables of e(alpha), e(alpha, beta) (issue 4, item 2).

References: the exact batch solver at the tables' node tolerance (``tables.exact_e``, rtol
1e-14, independent of the interpolation), and the closed forms of scripts/references.py for
Hunt-Crossley and Tsuji.  Tables are built into the test session's temporary cache
(conftest.py sets VISCONTACT_CACHE_DIR); building them relies on the compiled batch solver.
"""

import math
import warnings

import numpy as np
import pytest

import viscontact as vc
from viscontact.calibration import _interp, build, tables
from viscontact.calibration import table as table_mod
from references import hunt_e, tsuji_force_e, tsuji_overlap_alpha

LAWS_1D = ["LH", "Ts", "KK", "Li", "Hunt"]
ENDS = ["force", "overlap"]
TOL = 1e-10  # table against exact (issue 4)
TRIP_TOL = 1e-9  # e_exact(alpha_from_e(e)) against e


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache directory and no table in memory (restored afterwards)."""
    saved = dict(tables._MEMORY)
    monkeypatch.setenv("VISCONTACT_CACHE_DIR", str(tmp_path))
    tables.clear_memory()
    yield tmp_path
    tables.clear_memory()
    tables._MEMORY.update(saved)


def probe_alphas(table, rng, n=600):
    """Held-out alpha: random over [0, 10] and log-uniform down to 1e-9, the piece boundaries
    and points a hair either side of them."""
    breaks = table.alpha_axis[0]
    near = np.concatenate([breaks, breaks * (1 + 1e-9), breaks * (1 - 1e-9)])
    pts = np.concatenate([rng.uniform(0, 10, n), 10 ** rng.uniform(-9, 1, n), near,
                          [0.0, 1e-9, 1e-6, 10.0]])
    return np.clip(pts, 0.0, 10.0)


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("law", LAWS_1D)
def test_table_matches_exact_solver(law, end):
    table = tables.get_table(law, end)
    assert table is not None and table.max_error <= TOL
    a = probe_alphas(table, np.random.default_rng(sum(map(ord, law + end))))
    err = np.abs(table.e(a) - tables.exact_e(law, end, a))
    assert err.max() <= TOL, (a[err.argmax()], err.max())


def test_tables_match_closed_forms():
    rng = np.random.default_rng(7)
    a = np.concatenate([rng.uniform(0, 10, 300), 10 ** rng.uniform(-9, 1, 300)])
    e_hunt = np.array([hunt_e(x) for x in a])
    for end in ENDS:  # Hunt's force vanishes only with the overlap: one relation for both
        assert np.max(np.abs(vc.restitution("Hunt", a, end=end) - e_hunt)) <= TOL
    e_ts = np.array([tsuji_force_e(x) for x in a])
    assert np.max(np.abs(vc.restitution("Ts", a) - e_ts)) <= TOL
    e_ov = np.array([math.exp(-math.pi * x / math.sqrt(5 - x * x)) if x * x < 5 else 0.0 for x in a])
    assert np.max(np.abs(vc.restitution("Ts", a, end="overlap") - e_ov)) <= TOL


@pytest.mark.parametrize("end", ENDS)
def test_jian_table_matches_exact_solver(end):
    table = tables.get_table("Jian", end)
    assert table is not None and table.beta_axis is not None
    rng = np.random.default_rng(11)
    n = 1500
    a = np.concatenate([rng.uniform(0, 10, n), 10 ** rng.uniform(-9, 1, n),
                        rng.choice(table.alpha_axis[0], n)])
    b = np.concatenate([rng.uniform(0, 10, n), rng.choice(table.beta_axis[0], n),
                        10 ** rng.uniform(-9, 1, n)])
    err = np.abs(table.e(a, b) - tables.exact_e("Jian", end, a, b))
    assert err.max() <= TOL, (a[err.argmax()], b[err.argmax()], err.max())


def test_jian_with_beta_zero_is_kk_exactly():
    a = np.random.default_rng(3).uniform(0, 10, 200)
    for end in ENDS:
        kk = vc.restitution("KK", a, end=end)
        assert np.array_equal(vc.restitution("Jian", a, beta=0.0, end=end), kk)
        e = kk[kk > 1e-3]
        assert np.array_equal(vc.alpha_from_e("Jian", e, beta=0.0, end=end),
                              vc.alpha_from_e("KK", e, end=end))


def reachable_targets(law, end, rng, n=400, beta=None):
    """Targets e spread over what the table reaches (for Jian: at each beta)."""
    table = tables.get_table(law, end)
    args = [] if beta is None else [beta]
    floor = np.maximum(table.e(np.full(n, 10.0), *args), 1e-6)
    floor = np.where(np.isnan(floor) | (floor <= 0), 1e-6, floor)
    return floor + (1 - floor) * rng.uniform(0, 1, n) ** 2


@pytest.mark.parametrize("end", ENDS)
@pytest.mark.parametrize("law", LAWS_1D + ["Jian"])
def test_inversion_round_trip(law, end):
    rng = np.random.default_rng(5)
    beta = rng.uniform(0, 10, 400) if law == "Jian" else None
    kw = {} if beta is None else {"beta": beta}
    e = reachable_targets(law, end, rng, beta=beta)
    e[:3] = [1.0, 1 - 1e-12, 0.999]
    alpha = vc.alpha_from_e(law, e, end=end, **kw)
    assert alpha[0] == 0.0 and np.all(alpha >= 0)
    back = tables.exact_e(law, end, alpha, beta)
    assert np.max(np.abs(back - e)) <= TRIP_TOL


def test_inversion_matches_tsuji_closed_form():
    e = np.random.default_rng(9).uniform(1e-6, 1, 500)
    alpha = vc.alpha_from_e("Ts", e, end="overlap")
    assert np.max(np.abs(alpha - [tsuji_overlap_alpha(x) for x in e])) <= 1e-8


def test_outside_the_tables_the_exact_solver_answers():
    a = np.array([0.5, 12.0, 250.0])
    e = vc.restitution("KK", a)
    assert np.array_equal(e[1:], vc.restitution("KK", a[1:], exact=True))
    assert abs(e[0] - tables.exact_e("KK", "force", [0.5])[0]) <= TOL
    eb = vc.restitution("Jian", 2.0, beta=[0.5, 30.0])
    assert eb[1] == vc.restitution("Jian", 2.0, beta=30.0, exact=True)
    low = vc.restitution("Hunt", 50.0)  # below the table's e range
    assert vc.alpha_from_e("Hunt", low) == vc.alpha_from_e("Hunt", low, exact=True)
    with pytest.raises(ValueError, match=r"allowed range is \["):
        vc.alpha_from_e("Hunt", 1e-6)


def test_power_law_and_switch_use_the_exact_solver(monkeypatch):
    a = np.linspace(0, 5, 7)
    assert np.array_equal(vc.restitution("power", a, p=0.75),
                          vc.restitution("power", a, p=0.75, exact=True))
    monkeypatch.setattr(tables, "enabled", False)
    assert np.array_equal(vc.restitution("KK", a), vc.restitution("KK", a, exact=True))


def test_shapes_and_scalars_through_tables():
    assert isinstance(vc.restitution("LH", 0.3), float)
    assert isinstance(vc.alpha_from_e("LH", 0.6), float)
    e = vc.restitution("Jian", [[0.1], [0.3]], beta=[0.5, 1.0, 2.0])
    assert e.shape == (2, 3) and np.all(np.diff(e, axis=1) > 0)
    a = vc.alpha_from_e("Jian", [[0.9], [0.6]], beta=[0.5, 1.0, 2.0])
    assert a.shape == (2, 3)


# --- cache -----------------------------------------------------------------------------------


def test_cache_second_load_reads_the_file(fresh_cache, monkeypatch):
    first = tables.get_table("LH", "force")
    path = tables.table_path("LH", "force")
    assert path.exists() and path.parent == fresh_cache
    tables.clear_memory()
    monkeypatch.setattr(tables, "_build", lambda *a: pytest.fail("rebuilt instead of loading"))
    second = tables.get_table("LH", "force")
    assert np.array_equal(first.coef, second.coef)
    assert second.max_error == first.max_error


def test_cache_changed_code_rebuilds(fresh_cache, monkeypatch):
    tables.get_table("LH", "force")
    old = tables.table_path("LH", "force")
    built = []
    real_build = tables._build
    monkeypatch.setattr(tables, "_build", lambda *a: built.append(a) or real_build(*a))
    tables.clear_memory()
    monkeypatch.setattr(tables, "code_key", lambda: "0" * 64)
    tables.get_table("LH", "force")
    assert built == [("LH", "force")]
    assert tables.table_path("LH", "force").exists() and not old.exists()


def test_cache_corrupt_file_is_rebuilt(fresh_cache):
    tables.get_table("LH", "force")
    path = tables.table_path("LH", "force")
    path.write_bytes(b"not a table")
    tables.clear_memory()
    with pytest.warns(RuntimeWarning, match="rebuilding"):
        table = tables.get_table("LH", "force")
    assert table is not None and table.max_error <= TOL
    with np.load(path) as d:
        assert d["coef"].shape == table.coef.shape


# a first use that counts its builds: "_build" returns the session's table (from the file
# argv[1]) after a pause long enough for the other processes to find the cache empty
_COUNTED_BUILD = """
import sys, time
import numpy as np
from viscontact.calibration import tables
def build(law, end):
    print("built", flush=True)
    time.sleep(1.0)
    with np.load(sys.argv[1]) as d:
        return tables.Table.from_arrays(law, end, d)
tables._build = build
print("table", tables.get_table("Li", "force") is not None, flush=True)
"""


def test_concurrent_first_uses_build_a_table_once(tmp_path):
    """Three processes sharing an empty cache (parallel test workers, a command and its
    subprocesses) ask for one table at once: one builds it, the others wait for its file
    (file lock, checked again after the wait); one table file, no temporary files left."""
    import os
    import subprocess
    import sys

    from conftest import SRC

    tables.get_table("Li", "force")
    source = tables.table_path("Li", "force")
    cache = tmp_path / "cache"
    env = dict(os.environ, VISCONTACT_CACHE_DIR=str(cache),
               PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    procs = [subprocess.Popen([sys.executable, "-c", _COUNTED_BUILD, str(source)], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(3)]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-500:] for o in outs]
    lines = [ln for out, _ in outs for ln in out.split()]
    assert lines.count("built") == 1 and lines.count("True") == 3, outs
    assert sorted(p.name for p in cache.glob("*.npz")) == [source.name]
    assert not list(cache.glob("*.tmp"))


def test_build_refuses_a_table_that_misses_the_exact_solver(fresh_cache, monkeypatch):
    monkeypatch.setattr(build, "VERIFY_TOL", 1e-30)  # the check that refuses a table
    with pytest.warns(RuntimeWarning, match="misses the exact solver"):
        assert tables.get_table("Li", "force") is None
    assert not tables.table_path("Li", "force").exists()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        e = vc.restitution("Li", [0.3, 1.0])  # the exact solver answers, no second build
    assert np.array_equal(e, vc.restitution("Li", [0.3, 1.0], exact=True))


def test_build_all_covers_every_table():
    built = tables.build_all()
    assert set(built) == {(law, end) for law in tables.TABLE_LAWS for end in ENDS}
    assert all(t is not None and t.max_error <= TOL for t in built.values())


# --- Jian (2D): the fast kernels' pieces, against brute force --------------------------------


def test_lookup_finds_the_same_piece_as_a_search():
    rng = np.random.default_rng(13)
    for law, end in [("Jian", "overlap"), ("Jian", "force"), ("KK", "force")]:
        table = tables.get_table(law, end)
        axes = [table.alpha_axis[0]] if table.beta_axis is None else [table.beta_axis[0]]
        for breaks in axes:
            lut, scale = table_mod._lookup(breaks, 64)  # few cells: several pieces share one
            x = np.concatenate([rng.uniform(0, breaks[-1], 2000), breaks,
                                np.nextafter(breaks, 0), np.nextafter(breaks, np.inf)])
            x = x[(x >= 0) & (x <= breaks[-1])]
            want = np.minimum(np.searchsorted(breaks, x, side="right") - 1, breaks.size - 2)
            got = np.array([_interp._find(breaks, lut, scale, v) for v in x])
            assert np.array_equal(got, want)


@pytest.mark.parametrize("end", ENDS)
def test_jian_block_cells_bracket_every_block_search(end):
    """The (certain, possible) counts of each e cell contain the brute-force count of blocks
    whose left end lies at or above e, at every beta of the row."""
    table = tables.get_table("Jian", end)
    rng = np.random.default_rng(17)
    left = table._left
    for j in range(table.rows.size - 1):
        g0, g1 = table.rows[j], table.rows[j + 1]
        xb = rng.uniform(-1, 1, 300)
        e = rng.uniform(0, 1, 300)
        values = np.polynomial.chebyshev.chebval(xb, left[g0:g1].T)  # (blocks, points)
        count = np.count_nonzero(values >= e, axis=0)
        cell = table._cells[j][np.minimum((e * _interp._E_CELLS).astype(int), _interp._E_CELLS - 1)]
        assert np.all(cell[:, 0] <= count) and np.all(count <= cell[:, 1])


@pytest.mark.parametrize("end", ENDS)
def test_jian_inversion_round_trip_at_the_edges(end):
    """Round trips where the fast path has its special cases: beta near 0 and near 10, e near
    1 (alpha near 0), e at alpha = 10 (the table's end), e at alpha piece boundaries."""
    table = tables.get_table("Jian", end)
    rng = np.random.default_rng(19)
    beta = np.concatenate([10 ** rng.uniform(-9, -2, 60), 10 - 10 ** rng.uniform(-9, -1, 60),
                           [10.0, 1e-300], rng.choice(table.beta_axis[0][1:], 40),
                           rng.uniform(0, 10, 200)])
    n = beta.size
    breaks = table.alpha_axis[0]
    alpha = np.concatenate([np.full(n // 4, 10.0), rng.choice(breaks[breaks > 0], n // 4),
                            10 ** rng.uniform(-9, -3, n // 4)])
    alpha = np.concatenate([alpha, rng.uniform(0, 10, n - alpha.size)])
    e = tables.exact_e("Jian", end, alpha, beta)
    e = np.concatenate([e, np.minimum(e + 1e-12, 1.0), 1 - 10 ** rng.uniform(-12, -6, n)])
    beta = np.tile(beta, 3)
    keep = e > 0
    got = vc.alpha_from_e("Jian", e[keep], beta=beta[keep], end=end)
    assert np.all(got >= 0) and np.all(np.isfinite(got))  # e(10) a hair below the table's: beyond 10
    back = tables.exact_e("Jian", end, got, beta[keep])
    assert np.max(np.abs(back - e[keep])) <= TRIP_TOL


def test_jian_beyond_the_table_the_exact_solver_inverts():
    e = np.array([0.7, 0.5])
    for beta in (12.0, 250.0):
        assert np.array_equal(vc.alpha_from_e("Jian", e, beta=beta),
                              vc.alpha_from_e("Jian", e, beta=beta, exact=True))
    low = vc.restitution("Jian", 40.0, beta=0.5)  # below the table's e range at this beta
    assert vc.alpha_from_e("Jian", low, beta=0.5) == vc.alpha_from_e("Jian", low, beta=0.5,
                                                                       exact=True)


def test_newton_finish_falls_back_from_a_poor_start():
    """_finish takes two Newton steps from its start and, if they leave the root unfinished,
    the safeguarded iteration: a start far from the root still ends on it."""
    c = np.polynomial.chebyshev.poly2cheb([0.6, -0.3, -0.05, 0.01])  # decreasing on [-1, 1]
    s = np.polynomial.chebyshev.chebval(np.linspace(-1, 1, _interp._SAMPLES_2D), c)
    target = float(np.polynomial.chebyshev.chebval(0.37, c))
    a = int(np.count_nonzero(s[1:-1] >= target))
    curvature = float(np.sum(np.abs(np.polynomial.chebyshev.chebder(c, 2))))
    for start in (0.37, -0.99, 0.99, math.nan):
        xi = _interp._finish(c, s, a, target, curvature, start)
        assert abs(np.polynomial.chebyshev.chebval(xi, c) - target) <= 1e-12
