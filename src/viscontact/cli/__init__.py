"""The ``viscontact`` command line: a thin layer over the library (the top layer: it may
import every package; nothing imports it).

Each command lives in its own module exposing ``register(subparsers)``; ``COMMANDS`` lists
them.  Exit statuses: 0 success; 2 a user mistake (bad or repeated option, bad value, a
ValueError from the library, a file that must not be written), shown as exactly one line on
stderr; 141 (128 + SIGPIPE) when the reader of stdout went away (``... | head -1``), silently;
130 on Ctrl-C; 1 an internal error (a bug), also one line (``VISCONTACT_DEBUG=1`` shows the
traceback).  Warnings of numpy, scipy and matplotlib are silenced: every result is checked
by the library instead.  Notes (``common.note``) are printed on stderr only after a success.
"""

from __future__ import annotations

import argparse
import functools
import logging
import os
import sys
import warnings
from collections.abc import Sequence

from . import audit, common, core, dem, demstudy, fit, physical

__all__ = ["main", "COMMANDS", "UserError"]

COMMANDS = (core, physical, fit, audit, dem, demstudy)


class UserError(Exception):
    """A mistake the user can fix; its message is shown as is."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump) and exit status 2."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        for name, cls in (("store", argparse._StoreAction),
                          ("store_true", argparse._StoreTrueAction)):
            self.register("action", name, common.once(cls))
        self.register("action", None, common.once(argparse._StoreAction))
        self.register("type", float, common.finite_float)

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    from .._version import __version__

    parser = _Parser(
        prog="viscontact",
        description="Viscoelastic contact force models for DEM: exact collisions, calibration, "
        "and the Jian et al. (2019) comparison.",
    )
    parser.add_argument("--version", action="version", version=f"viscontact {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for module in COMMANDS:
        module.register(sub)
    return parser


@functools.lru_cache(maxsize=1)
def _parser() -> argparse.ArgumentParser:
    """:func:`build_parser`, built once per process (about 20 ms: a few hundred options).
    Parsing leaves the parser as it was (a call's state lives in its namespace, e.g. the
    options already given), so in-process callers that run many command lines (the tests, the
    fuzzer) share it."""
    return build_parser()


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit status (see the module docstring)."""
    common.NOTES.clear()
    logging.getLogger("matplotlib").setLevel(logging.ERROR)  # its font notes go to stderr
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return _run(argv)
        except BrokenPipeError:
            return _closed_pipe()


def _run(argv: Sequence[str] | None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)  # --help, --version, usage errors: SystemExit (0 or 2)
    name = f"viscontact {args.command}"
    if getattr(args, "_law_required", False) and args.model is None:
        return _fail(name, f"the following arguments are required: --law (see {name} --help)")
    try:
        status = int(args.handler(args) or 0)
        sys.stdout.flush()
    except BrokenPipeError:
        raise
    except (UserError, ValueError) as exc:
        return _fail(name, str(exc))
    except OSError as exc:
        where = f": {exc.filename}" if exc.filename else ""
        return _fail(name, f"{exc.strerror or exc}{where}")
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - a bug: one line, not a traceback
        if os.environ.get("VISCONTACT_DEBUG"):
            raise
        return _fail(name, f"internal error ({type(exc).__name__}: {exc}); this is a bug, please "
                     "report it with the command line", status=1)
    for line in common.NOTES:
        print(line, file=sys.stderr)
    return status


def _fail(name: str, message: str, status: int = 2) -> int:
    """The one line of an error: the message, its line breaks folded."""
    text = " ".join(str(message).split()) or "failed"
    print(f"{name}: error: {text}", file=sys.stderr)
    return status


def _closed_pipe() -> int:
    """stdout's reader went away: quiet exit 141 (128 + SIGPIPE) like a Unix filter killed by
    SIGPIPE; stdout is pointed at /dev/null so the interpreter's final flush stays quiet."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass  # not a real file (captured output in tests)
    return 141
