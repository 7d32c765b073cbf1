"""Start-up: what the command line loads, and the plain-Python kernels behind a lone collision.

Timing belongs in benchmarks/bench_startup.py; these tests check what makes start-up fast
(the modules a command loads) and that the fast path gives the same numbers.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import viscontact as vc
from viscontact.physics import kernels
from viscontact.collision.single import collide_params
from viscontact.physics.kernels_py import python_kernels
from viscontact.physics.laws import resolve
from viscontact.solvers import reference

PLAIN = python_kernels()

#: (model, beta, p) covering every law, with Jian's beta small and large
LAW_CASES = [("LH", None, None), ("Ts", None, None), ("KK", None, None), ("Li", None, None),
             ("Hunt", None, None), ("Jian", 0.5, None), ("Jian", 1e-6, None), ("Jian", 5.0, None),
             ("power", None, 0.75), ("power", None, 2.5)]


def loaded_modules(code: str) -> set[str]:
    """The modules a fresh interpreter has loaded after running ``code``."""
    probe = f"{code}\nimport sys, json\nprint(json.dumps(sorted(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.splitlines()[-1]))


def test_plain_kernels_do_not_import_numba():
    mods = loaded_modules("from viscontact.physics.kernels_py import python_kernels\n"
                          "python_kernels().rhs_sigma(0.5, 0.2, 1.0, 0.3, 0.5, 0.5, 2)")
    assert "numba" not in mods
    assert "viscontact.physics.kernels" not in mods


def test_plain_kernels_are_the_kernels_source():
    for name in kernels.__all__:
        plain, compiled = getattr(PLAIN, name), getattr(kernels, name)
        if hasattr(compiled, "py_func"):
            assert plain.__code__ == compiled.py_func.__code__, name
        else:
            assert plain == compiled, name


@settings(max_examples=300, deadline=None)
@given(s=st.floats(-2.0, 3.0), v=st.floats(-2.0, 2.0), t=st.floats(0.0, 50.0),
       alpha=st.one_of(st.just(0.0), st.floats(1e-12, 100.0)),
       beta=st.one_of(st.just(0.0), st.floats(1e-12, 100.0)),
       p=st.sampled_from([0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.5, 1.0 / 3.0]))
def test_plain_kernels_equal_compiled_bit_for_bit(s, v, t, alpha, beta, p):
    m = 4 if p == 0.25 else 2
    q = min(m * p, 1.5 * m)
    calls = [("rhs_sigma", (s, v, t, alpha, beta, p, m)),
             ("force_s", (s, v, t, alpha, beta, p, m)),
             ("force_s", (s, v, t, alpha, beta, p, m, q)),
             ("end_force_event", (s, v, t, alpha, beta, p, m, q)),
             ("force", (abs(s), v, t, alpha, beta, p)),
             ("relaxation", (t, beta)),
             ("spow", (s, m * p))]
    for name, args in calls:
        assert getattr(PLAIN, name)(*args) == getattr(kernels, name)(*args), (name, args)


def _solve_with(which, monkeypatch, lp, alpha, end):
    monkeypatch.setattr(reference, "kernels", lambda: which)
    return collide_params(lp, alpha, end)


@pytest.mark.parametrize("end", ["force", "overlap"])
@pytest.mark.parametrize("model,beta,p", LAW_CASES)
def test_reference_solve_same_with_plain_and_compiled_kernels(model, beta, p, end, monkeypatch):
    lp = resolve(model, beta=beta, p=p)
    for alpha in (0.0, 1e-6, 0.3, 4.0):
        plain = _solve_with(PLAIN, monkeypatch, lp, alpha, end)
        compiled = _solve_with(kernels, monkeypatch, lp, alpha, end)
        for key in ("e", "tc", "fmax", "t_fmax", "xmax", "t_xmax", "residual", "dissipated",
                    "separated"):
            a, b = getattr(plain, key), getattr(compiled, key)
            assert a == b or (math.isnan(a) and math.isnan(b)), (model, alpha, end, key, a, b)
        for key in ("t", "x", "v", "f"):
            np.testing.assert_array_equal(getattr(plain, key), getattr(compiled, key))


def test_compiled_kernels_after_a_few_plain_solves():
    code = ("import sys, viscontact as vc\n"
            "from viscontact.solvers.reference import PLAIN_SOLVES\n"
            "loaded = []\n"
            "for _ in range(PLAIN_SOLVES + 1):\n"
            "    vc.collide('KK', 0.3)\n"
            "    loaded.append('viscontact.physics.kernels' in sys.modules)\n"
            "assert loaded == [False] * PLAIN_SOLVES + [True], loaded\n")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_collide_command_loads_neither_numba_nor_matplotlib():
    mods = loaded_modules("from viscontact.cli import main\n"
                          "main(['collide', '--law', 'Jian', '--alpha', '0.3', '--beta', '0.5'])")
    assert not {"numba", "matplotlib", "viscontact.calibration.tables", "viscontact.solvers.batch"} & mods


@pytest.mark.parametrize("argv", [[], ["collide"], ["restitution"], ["calibrate"], ["sweep"],
                                  ["fit"], ["audit"], ["reproduce"]])
def test_help_loads_no_solver(argv):
    mods = loaded_modules("from viscontact.cli import main\n"
                          f"try:\n    main({argv + ['--help']!r})\nexcept SystemExit:\n    pass")
    assert not {"numba", "scipy", "matplotlib", "viscontact.calibration.tables"} & mods


def test_import_viscontact_is_light_and_complete():
    mods = loaded_modules("import viscontact")
    assert not {"numba", "scipy", "matplotlib"} & mods
    for name in vc.__all__:
        assert getattr(vc, name) is not None, name
    assert set(vc.__all__) <= set(dir(vc))
    assert vc.experiment.ball("ILB") in vc.load_balls().values()  # submodules on access
    with pytest.raises(AttributeError, match="no attribute 'not_there'"):
        vc.not_there


@pytest.mark.parametrize("args", [["--law", "Jian", "--alpha", "0.3", "--beta", "0.5"],
                                  ["--law", "Ts", "--alpha", "0.7", "--end", "overlap"],
                                  ["--law", "power", "--p", "0.75", "--alpha", "2"]])
def test_collide_command_in_a_fresh_process_matches_the_library(args):
    """The fresh process solves with the plain kernels; this one has the compiled loaded."""
    out = subprocess.run([sys.executable, "-m", "viscontact", "collide", *args, "--json"],
                         capture_output=True, text=True, check=True)
    got = json.loads(out.stdout)
    opts = dict(zip(args[::2], args[1::2]))
    r = vc.collide(opts["--law"], float(opts["--alpha"]),
                   beta=float(opts["--beta"]) if "--beta" in opts else None,
                   p=float(opts["--p"]) if "--p" in opts else None,
                   end=opts.get("--end", "force"))
    assert "viscontact.physics.kernels" in sys.modules
    assert got == r.to_dict()


def test_importing_viscontact_keeps_the_users_matplotlib_backend():
    """Every viscontact module imported after the user chose a backend (here the non-Agg 'svg')
    leaves it chosen: figures are bare Figure objects, no backend is set at import."""
    import pkgutil

    import viscontact

    names = sorted(m.name for m in pkgutil.walk_packages(viscontact.__path__, "viscontact.")
                   if not m.name.endswith("__main__"))  # running it would run the CLI
    assert "viscontact.collision.plots" in names and "viscontact.audit.report" in names
    code = ("import importlib, matplotlib, sys\n"
            "matplotlib.use('svg')\n"
            "for name in sys.argv[1:]:\n"
            "    importlib.import_module(name)\n"
            "    assert matplotlib.get_backend() == 'svg', (name, matplotlib.get_backend())\n"
            "print('ok')\n")
    proc = subprocess.run([sys.executable, "-c", code, *names], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0 and proc.stdout == "ok\n", proc.stderr[-2000:]
