"""A lock shared by the processes of one machine (a POSIX ``flock`` on a file), and numba's
compilation under it."""

from __future__ import annotations

import hashlib
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["compile_once", "file_lock"]


@contextmanager
def file_lock(path: Path) -> Iterator[None]:
    """Hold an exclusive lock on ``path`` (created, with its directory, if missing) while the
    block runs, so that processes sharing the file take turns.  Without a writable place for
    the file, or without ``fcntl`` (not POSIX), the block runs unlocked: the lock saves
    repeated work, it guards nothing that would break."""
    try:
        import fcntl

        path.parent.mkdir(parents=True, exist_ok=True)
        fh = open(path, "w")
    except (ImportError, OSError):
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def compile_once(dispatcher, args: tuple, tag: str = "") -> None:
    """Compile the numba function ``dispatcher`` for the types of ``args`` (what a call with
    them would compile), or load it from numba's on-disk cache, under a lock shared by the
    processes of this machine: processes that start together (parallel test workers, a
    command and its subprocesses) compile each specialization once, the others wait and load
    it.  ``tag`` tells apart functions of one name (closures over different constants).
    Returns at once (no typing of ``args``: ~70 us a call) when this process has compiled
    the function already, for any types: other types then compile at their call, unlocked,
    which costs no more than before."""
    if dispatcher.signatures:
        return
    import numba

    sig = tuple(numba.typeof(x) for x in args)
    fn = dispatcher.py_func
    name = hashlib.sha256(f"{fn.__code__.co_filename}|{fn.__qualname__}|{tag}|{sig}".encode())
    with file_lock(Path(tempfile.gettempdir()) / f"viscontact-numba-{name.hexdigest()[:20]}.lock"):
        dispatcher.compile(sig)
