"""Independent LAMMPS runs of the DEM study at the same time.

The study's runs form a small tree (a gas is thermalised once and then cooled with every law,
a column is built once and then collapsed with every law; the bounces, the gas, Haff's check
and the collapse do not depend on each other).  Inside :func:`concurrent` every branch of that
tree runs in a thread of its own (:func:`pmap`) and :func:`viscontact.demstudy.engine.run_lammps`
takes one of ``jobs`` slots for each LAMMPS process, so that at most ``jobs`` of them run at a
time.  LAMMPS runs in processes of its own, so the threads mostly wait; the Python analysis
between runs is short.  Results come back in the order of the inputs, so the report does not
depend on ``jobs``.

When one run fails, or the main thread is interrupted (Ctrl-C, SIGTERM), every other running
LAMMPS is stopped (each run's poll loop sees :func:`cancelled`) before the first error is raised.
"""

from __future__ import annotations

import contextvars
import heapq
import itertools
import threading
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import FIRST_EXCEPTION, Future, ThreadPoolExecutor, wait
from contextlib import contextmanager
from typing import TypeVar

__all__ = ["concurrent", "pmap", "run_each", "first", "slot", "cancelled", "Cancelled", "default_jobs"]

T = TypeVar("T")
R = TypeVar("R")

_cancel = threading.Event()
#: the order in which waiting runs get a free slot (lower first), set per branch by
#: :func:`first`; threads started by :func:`pmap` inherit it
_priority: contextvars.ContextVar[int] = contextvars.ContextVar("dem_study_priority", default=0)


class _Slots:
    """``n`` slots for LAMMPS processes; a freed slot goes to the waiting run of lowest
    (priority, arrival), so that the long branches start early and short runs fill the end."""

    def __init__(self, n: int):
        self.free = n
        self.cond = threading.Condition()
        self.waiting: list[tuple[int, int]] = []  # heap of tickets
        self.seq = itertools.count()

    def acquire(self) -> None:
        with self.cond:
            ticket = (_priority.get(), next(self.seq))
            heapq.heappush(self.waiting, ticket)
            try:
                while not (self.free > 0 and self.waiting[0] == ticket):
                    if _cancel.is_set():
                        raise Cancelled()
                    self.cond.wait(0.2)
            except BaseException:
                self.waiting.remove(ticket)
                heapq.heapify(self.waiting)
                self.cond.notify_all()
                raise
            heapq.heappop(self.waiting)
            self.free -= 1
            self.cond.notify_all()  # the next ticket may take another free slot

    def release(self) -> None:
        with self.cond:
            self.free += 1
            self.cond.notify_all()


_slots: _Slots | None = None


class Cancelled(Exception):
    """A run stopped because another one failed or the study was interrupted."""


def default_jobs(np_: int = 1) -> int:
    """LAMMPS runs at a time that fill this machine's cores with ``np_`` ranks each (>= 1)."""
    from ..dem.run import available_cores

    return max(1, available_cores() // max(1, np_))


@contextmanager
def concurrent(jobs: int) -> Iterator[None]:
    """Inside the block, :func:`pmap` runs its items at the same time and at most ``jobs``
    LAMMPS processes run at once (``jobs`` = 1: one after the other, as without the block)."""
    global _slots
    prev = _slots
    _slots = _Slots(jobs) if jobs > 1 else None
    _cancel.clear()
    try:
        yield
    finally:
        _slots = prev
        _cancel.clear()


def cancelled() -> bool:
    """Whether the runs of the current :func:`concurrent` block are being stopped."""
    return _cancel.is_set()


@contextmanager
def slot() -> Iterator[None]:
    """Hold one of the LAMMPS slots of :func:`concurrent` (nothing outside it)."""
    slots = _slots
    if slots is None:
        yield
        return
    slots.acquire()
    try:
        if _cancel.is_set():
            raise Cancelled()
        yield
    except BaseException:
        _cancel.set()  # before the slot is free: no other run starts after a failure
        raise
    finally:
        slots.release()


def first(priority: int, fn: Callable[[], R]) -> Callable[[], R]:
    """``fn`` whose LAMMPS runs (and those of the threads it starts) wait for a slot with
    ``priority`` (lower: sooner; default 0)."""

    def run() -> R:
        _priority.set(priority)
        return fn()

    return run


def pmap(fn: Callable[[T], R], items: Iterable[T]) -> list[R]:
    """``[fn(x) for x in items]``, each item in a thread of its own inside :func:`concurrent`.

    The first exception (an interruption of the calling thread included) stops the other
    items' LAMMPS runs; it is raised once all of them have ended.
    """
    items = list(items)
    if _slots is None or len(items) <= 1:
        return [fn(x) for x in items]
    ex = ThreadPoolExecutor(max_workers=len(items), thread_name_prefix="dem-study")
    # each thread runs in a copy of the caller's context: it inherits the priority
    futs: list[Future] = [ex.submit(contextvars.copy_context().run, fn, x) for x in items]
    try:
        while True:  # short waits: a signal handler in the main thread runs between them
            done, pending = wait(futs, timeout=0.5, return_when=FIRST_EXCEPTION)
            if not pending or any(f.exception() is not None for f in done):
                break
    except BaseException:
        _cancel.set()
        ex.shutdown(wait=True)
        raise
    errors = [f.exception() for f in futs if f.done() and f.exception() is not None]
    if errors:
        _cancel.set()
    ex.shutdown(wait=True)
    if errors:
        errors = [f.exception() for f in futs if f.exception() is not None]
        real = [e for e in errors if not isinstance(e, Cancelled)]
        raise (real or errors)[0]
    return [f.result() for f in futs]


def run_each(*fns: Callable[[], object]) -> list[object]:
    """Call each function (independent branches of the study) as :func:`pmap` does."""
    return pmap(lambda f: f(), fns)
