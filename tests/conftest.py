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
