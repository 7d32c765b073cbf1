"""Independent pieces of work in forked processes, one per core."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

__all__ = ["forked_map"]

T = TypeVar("T")


def forked_map(fn: Callable[[T], Any], items: Sequence[T], *, workers: int | None = None,
               done: Callable[[T], None] | None = None) -> list[Any]:
    """[fn(item) for item in items], computed in ``workers`` forked processes (default one
    per core, at most one per item); ``done(item)`` is called as each one finishes.

    ``fn`` must be a module-level function (or a ``functools.partial`` of one) and its
    results picklable.  Where ``fork`` is not available, or with one worker, the items are
    done one after another in this process.  Fork, not spawn: the children inherit the
    loaded modules and compiled code, so they start in milliseconds.
    """
    done = done or (lambda _item: None)
    workers = min(os.cpu_count() or 1, len(items)) if workers is None else workers
    if workers <= 1 or "fork" not in multiprocessing.get_all_start_methods():
        results = []
        for item in items:
            results.append(fn(item))
            done(item)
        return results
    out: list[Any] = [None] * len(items)
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
        futures = {pool.submit(fn, item): i for i, item in enumerate(items)}
        for fut in as_completed(futures):
            i = futures[fut]
            out[i] = fut.result()
            done(items[i])
    return out
