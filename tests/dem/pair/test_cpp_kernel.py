"""The C++ force law of the LAMMPS plugin (``viscontact_contact.h``) against the package's own
kernels, through a tiny ctypes library built from the same header (no LAMMPS needed).

Non-dimensional (k = 1, c0 = alpha, tau = beta), ``normal_force(x, x', t, 1, alpha, beta, p)``
must equal ``viscontact.physics.kernels.force(x, x', t, alpha, beta, p)`` to rounding on thousands of
sampled points of every law's exponent and random ones.  Measured: |C++ - kernels| <= 1.94 eps
(|x^1.5| + |alpha g x^p x'|) (eps = 2^-52), i.e. within 4 ulp of the force where spring and
damping add; the bound asserted is 4 eps of that scale (a handful of roundings: x sqrt(x)
against pow, the relaxation factor by expm1 against the kernels' table and series).

``vc_contact_step`` runs THE contact step (``ContactModel::evaluate``, which pair and wall call)
for one contact: Hertz + damping + linear_history over consecutive random steps equals the
formulas written out here to 1e-12 of the force.
"""

from __future__ import annotations

import ctypes
import math

import numpy as np
import pytest

from viscontact import kernels
from viscontact.dem import plugin
from viscontact.physics.pair import damping_coefficient, time_scale

from dem_util import needs_compiler

pytestmark = needs_compiler

EPS = np.finfo(float).eps
LAWS = ("LH", "Ts", "KK", "Li", "Hunt", "Jian", "power")  # enum order of viscontact::Law


@pytest.fixture(scope="module")
def lib():
    lib = ctypes.CDLL(str(plugin.kernel_library_path()))
    dp = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
    lib.vc_normal_force_many.argtypes = [ctypes.c_long] + [dp] * 8
    lib.vc_normal_force_many.restype = None
    lib.vc_relaxation.argtypes = [ctypes.c_double, ctypes.c_double]
    lib.vc_relaxation.restype = ctypes.c_double
    lib.vc_contact_coeffs.argtypes = [ctypes.c_int, ctypes.c_double, ctypes.c_int] + \
        [ctypes.c_double] * 8 + [dp]
    lib.vc_mindlin.argtypes = [dp, dp, dp, ctypes.c_double, ctypes.c_double, ctypes.c_double, dp]
    lib.vc_contact_step.argtypes = [ctypes.c_int, ctypes.c_double, ctypes.c_double, ctypes.c_double,
                                    ctypes.c_int] + [ctypes.c_double] * 4 + [dp, dp, ctypes.c_int, dp]
    lib.vc_contact_step.restype = ctypes.c_int
    lib.vc_law_exponent.argtypes = [ctypes.c_int]
    lib.vc_law_exponent.restype = ctypes.c_double
    return lib


def _cpp_force(lib, x, v, t, alpha, beta, p):
    n = len(x)
    out = np.empty(n)
    arrays = [np.ascontiguousarray(a, dtype=float) for a in (x, v, t, np.ones(n), alpha, beta, p)]
    lib.vc_normal_force_many(n, *arrays, out)
    return out


def test_normal_force_equals_kernels(lib):
    rng = np.random.default_rng(20251124)
    n = 6000
    x = rng.uniform(0.0, 3.0, n)
    x[:50] = 0.0
    x[50:100] = rng.uniform(0, 1e-12, 50)
    v = rng.uniform(-2.0, 2.0, n)
    t = rng.uniform(0.0, 10.0, n)
    alpha = rng.uniform(0.0, 10.0, n)
    beta = np.where(rng.random(n) < 0.5, rng.uniform(0.0, 10.0, n), 0.0)
    p = rng.choice([0.0, 0.25, 0.5, 1.0, 1.5, 0.75, 2.3, rng.uniform(0, 3)], n)
    got = _cpp_force(lib, x, v, t, alpha, beta, p)
    ref = np.array([kernels.force(*z) for z in zip(x, v, t, alpha, beta, p)])
    scale = x**1.5 + np.abs(alpha * x**p * v)
    err = np.abs(got - ref) / np.where(scale > 0, scale, 1.0) / EPS
    worst = int(np.argmax(err))
    assert err.max() <= 4.0, (err.max(), x[worst], v[worst], t[worst], alpha[worst], beta[worst],
                              p[worst], got[worst], ref[worst])
    # and the test can fail: a 1e-12 change in alpha is seen
    bumped = _cpp_force(lib, x, v, t, alpha * (1 + 1e-12), beta, p)
    assert (np.abs(bumped - ref) / np.where(scale > 0, scale, 1.0) / EPS).max() > 4.0


def test_relaxation_factor(lib):
    """g(t) = 1 - exp(-t/tau) against the kernels' g (and 1 for tau = 0: every law but Jian)."""
    rng = np.random.default_rng(3)
    for t, tau in zip(rng.uniform(0, 20, 500), rng.uniform(1e-3, 10, 500)):
        g = lib.vc_relaxation(t, tau)
        assert abs(g - kernels.relaxation(t, tau)) <= 4 * EPS * max(g, 1e-300) + 1e-300
        assert abs(g + math.expm1(-t / tau)) <= EPS * g
    assert lib.vc_relaxation(3.0, 0.0) == 1.0


@pytest.mark.parametrize("law", LAWS)
def test_contact_coefficients_from_alpha(lib, law):
    """c0 = alpha m*^((3-2p)/5) vref^((1-4p)/5) k^((2+2p)/5), tau = beta T_ref
    (docs/pair_viscontact.md), per contact, against viscontact.physics.pair."""
    p = {"LH": 0.0, "Ts": 0.25, "KK": 0.5, "Li": 1.0, "Hunt": 1.5, "Jian": 0.5, "power": 0.8}[law]
    estar, meff, reff, vref, alpha, beta = 3.1e8, 2.7e-3, 4.5e-3, 1.7, 0.37, 0.6
    out = np.empty(3)
    lib.vc_contact_coeffs(LAWS.index(law), p, 1, alpha, vref, beta, 0.0, 0.0, estar, meff, reff, out)
    k = 4.0 / 3.0 * estar * math.sqrt(reff)
    assert out[0] == pytest.approx(k, rel=4 * EPS)
    c0 = damping_coefficient(law, alpha, m_eff=meff, k_hertz=k, v=vref,
                             p=p if law == "power" else None)
    assert out[1] == pytest.approx(c0, rel=1e-14)
    if law == "Jian":
        assert out[2] == pytest.approx(beta * time_scale(meff, k, vref), rel=1e-14)
    else:
        assert out[2] == 0.0
    # physical form: c0 and tau as given
    lib.vc_contact_coeffs(LAWS.index(law), p, 0, 0.0, 0.0, 0.0, 12.5, 0.004, estar, meff, reff, out)
    assert out[1] == 12.5 and out[2] == (0.004 if law == "Jian" else 0.0)


def test_mindlin_stick_and_slip(lib):
    """Stick: xi' = xi + dt vtr (xi already tangential), F_t = -k_t xi'.  Slip: |F_t| = mu F_n
    along -xi', and xi = -F_t / k_t.  A normal component of xi is rotated away, length kept."""
    n = np.array([0.0, 0.0, 1.0])
    vtr = np.array([0.3, -0.1, 0.0])
    dt, kt = 1e-5, 2.0e4
    xi = np.array([1e-6, 2e-6, 0.0])
    ft = np.empty(3)
    lib.vc_mindlin(xi, n, vtr, dt, kt, 1e3, ft)
    expect = np.array([1e-6, 2e-6, 0.0]) + dt * vtr
    np.testing.assert_allclose(xi, expect, rtol=1e-15)
    np.testing.assert_allclose(ft, -kt * expect, rtol=1e-15)
    lim = 0.5 * np.linalg.norm(ft)
    lib.vc_mindlin(xi, n, np.zeros(3), dt, kt, lim, ft)
    assert np.linalg.norm(ft) == pytest.approx(lim, rel=1e-15)
    np.testing.assert_allclose(xi, -ft / kt, rtol=1e-15)
    tilted = np.array([3e-6, 0.0, 4e-6])
    lib.vc_mindlin(tilted, n, np.zeros(3), dt, kt, 1e3, ft)
    np.testing.assert_allclose(tilted, [5e-6, 0.0, 0.0], rtol=1e-15, atol=1e-21)


# ------------------------------------------------------------------------ build and cache
_BUILD = """
import sys
from viscontact.dem import plugin
print(plugin.kernel_library_path())
"""


def test_concurrent_first_builds_share_one_library(tmp_path):
    """Three processes building at once into an empty cache: one library, the same path for
    all, no temporary files left (file lock + atomic rename)."""
    import os
    import subprocess
    import sys

    from conftest import SRC

    env = dict(os.environ, VISCONTACT_CACHE_DIR=str(tmp_path),
               PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    procs = [subprocess.Popen([sys.executable, "-c", _BUILD], env=env, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(3)]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1][-500:] for o in outs]
    paths = {o[0].strip() for o in outs}
    assert len(paths) == 1
    built = [p for p in tmp_path.rglob("*") if p.is_file() and p.name != ".lock"]
    assert [p.name for p in built] == ["viscontact_kernel.so"], built
    ctypes.CDLL(paths.pop()).vc_relaxation  # loads


@needs_compiler
def test_rebuild_replaces_the_library_in_one_rename(tmp_path, monkeypatch):
    """``rebuild`` (``viscontact dem plugin --rebuild``) compiles anew and renames the result
    over the old file: a run loading the library meanwhile (another xdist worker's LAMMPS, a
    user's second terminal) always finds one; the old code unlinked it first."""
    import threading

    monkeypatch.setenv("VISCONTACT_CACHE_DIR", str(tmp_path))
    path = plugin.kernel_library_path()
    before = path.stat().st_ino
    missing, done = [], threading.Event()

    def watch():
        while not done.is_set():
            if not path.is_file():
                missing.append(True)

    watcher = threading.Thread(target=watch)
    watcher.start()
    try:
        again = plugin.kernel_library_path(rebuild=True)
    finally:
        done.set()
        watcher.join()
    assert again == path and path.stat().st_ino != before  # rebuilt, in place
    assert not missing


def test_no_compiler_is_one_line(monkeypatch):
    monkeypatch.setenv("CXX", "/nonexistent/g++")
    with pytest.raises(plugin.PluginError) as info:
        plugin.kernel_library_path(rebuild=True)
    msg = str(info.value)
    assert "\n" not in msg and "install g++" in msg, msg


def test_cache_key_follows_sources(tmp_path):
    a = tmp_path / "a.cpp"
    a.write_text("int x = 1;\n")
    k1 = plugin._key(["20250722", "g++ 12"], [a])
    assert plugin._key(["20250722", "g++ 12"], [a]) == k1
    assert plugin._key(["20250723", "g++ 12"], [a]) != k1  # another LAMMPS
    assert plugin._key(["20250722", "g++ 13"], [a]) != k1  # another compiler
    a.write_text("int x = 2;\n")
    assert plugin._key(["20250722", "g++ 12"], [a]) != k1  # changed source


def test_no_lammps_is_one_line(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "lammps", None)  # import lammps -> ImportError
    with pytest.raises(plugin.PluginError) as info:
        plugin.plugin_path()
    msg = str(info.value)
    assert "\n" not in msg and f"pip install '{plugin.PINNED_LAMMPS}'" in msg, msg


def test_lammps_without_granular_is_one_line():
    text = "Installed packages:\n\nKSPACE MANYBODY PLUGIN\n\nList of individual style options"
    with pytest.raises(plugin.PluginError) as info:
        plugin._check_packages("lmp", text)
    msg = str(info.value)
    assert "\n" not in msg and "GRANULAR" in msg and "pip install" in msg, msg
    plugin._check_packages("lmp", text.replace("KSPACE", "GRANULAR"))  # both present: fine


def test_integer_sizes_macro():
    assert plugin._integer_sizes_define("sizeof(tagint):   32-bit\nsizeof(bigint):   64-bit") == \
        "-DLAMMPS_SMALLBIG"
    assert plugin._integer_sizes_define("sizeof(tagint):   64-bit\nsizeof(bigint):   64-bit") == \
        "-DLAMMPS_BIGBIG"
    assert plugin._integer_sizes_define("sizeof(tagint):   32-bit\nsizeof(bigint):   32-bit") == \
        "-DLAMMPS_SMALLSMALL"


def _reference_step(st: dict, xi: np.ndarray, law_p: float, c0: float, clamp: bool, Estar: float,
                    kt: float, xgamma: float, mu: float) -> tuple[np.ndarray, np.ndarray, float]:
    """One Hertz + damping + linear_history step written out from the formulas (Johnson 1985
    for Hertz; Luding, Granular Matter 10 (2008) 235, eq. 17, for the rotated spring; the
    Coulomb cap as LAMMPS granular's linear_history): returns (F on i, torque on i, F_n) and
    advances xi in place."""
    n, delta, ri, rj = st["n"], st["delta"], st["ri"], st["rj"]
    reff = ri * rj / (ri + rj)
    vr, wi, wj, dt = st["vr"], st["wi"], st["wj"], st["dt"]
    vn = vr @ n
    vtr = vr - vn * n - np.cross(ri * wi + rj * wj, n)
    fne = 4.0 / 3.0 * Estar * np.sqrt(reff) * delta**1.5
    eta = c0 * delta**law_p
    fn = fne + eta * (-vn)
    if clamp:
        fn = max(fn, 0.0)
    fscrit = mu * abs(fn)
    if abs(xi @ n) * kt > 1e-10 * fscrit:    # the spring turns with the contact plane
        length = np.linalg.norm(xi)
        xi -= (xi @ n) * n
        xi *= length / np.linalg.norm(xi)
    xi += dt * vtr
    fdmp = -xgamma * eta * vtr
    ft = -kt * xi + fdmp
    if np.linalg.norm(ft) > fscrit:
        ft *= fscrit / np.linalg.norm(ft)
        xi[:] = -(ft - fdmp) / kt
    force = fn * n + ft
    torque = -(ri - 0.5 * delta) * np.cross(n, ft)
    return force, torque, fn


@pytest.mark.parametrize("law", ["LH", "KK", "Hunt"])
def test_contact_step_equals_formulas(lib, law):
    """vc_contact_step (ContactModel::evaluate, the step pair and wall run) against the Hertz +
    damping + linear_history formulas evaluated here, over a few consecutive steps of random
    contacts (the spring rotates, sticks and slides): force and torque to 1e-12 of their scale."""
    rng = np.random.default_rng(20 + LAWS.index(law))
    p = lib.vc_law_exponent(LAWS.index(law))
    Estar, kt, xgamma = 5e6, 2e4, 0.5
    slid = 0
    for trial in range(8):
        c0 = float(rng.uniform(0.1, 5.0))
        mu = float(rng.uniform(0.05, 0.6))
        clamp = bool(trial % 2)
        h = np.zeros(64)
        xi = np.zeros(3)
        n = rng.normal(size=3)
        for step in range(6):
            n = n + 0.05 * rng.normal(size=3)
            n /= np.linalg.norm(n)
            st = dict(n=n.copy(), delta=float(rng.uniform(1e-6, 1e-4)), ri=0.005, rj=0.004,
                      vr=rng.normal(0, 0.1, 3), wi=rng.normal(0, 10, 3), wj=rng.normal(0, 10, 3),
                      dt=1e-5)
            geo = np.concatenate([st["n"], [st["delta"], st["ri"], st["rj"], 0.001], st["vr"],
                                  st["wi"], st["wj"], [st["dt"], 0.0]])
            out = np.zeros(8)
            size = lib.vc_contact_step(LAWS.index(law), p, c0, 0.0, int(clamp), Estar, kt, xgamma,
                                       mu, geo, h, 1, out)
            assert 4 <= size <= 64
            f_ref, t_ref, fn_ref = _reference_step(st, xi, p, c0, clamp, Estar, kt, xgamma, mu)
            fscale = abs(fn_ref) + np.linalg.norm(f_ref) + 1e-300
            assert np.abs(out[:3] - f_ref).max() <= 1e-12 * fscale, (trial, step, out, f_ref)
            assert np.abs(out[3:6] - t_ref).max() <= 1e-12 * fscale * st["ri"], (trial, step)
            assert out[6] == pytest.approx(fn_ref, rel=1e-12, abs=1e-12 * fscale)
            slid += np.linalg.norm(f_ref - (f_ref @ n) * n) >= mu * abs(fn_ref) * (1 - 1e-12)
    assert slid > 0    # the Coulomb cap was exercised

