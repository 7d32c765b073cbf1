"""The ``viscontact`` command line: a thin layer over the library.

Each command lives in its own module exposing ``register(subparsers)``; ``COMMANDS`` lists
them.  A user mistake (bad option, bad value, a ValueError from the library) prints one
line on stderr and exits 2; success exits 0.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from . import audit, core, dem, demstudy, fit, physical

__all__ = ["main", "COMMANDS", "UserError"]

COMMANDS = (core, physical, fit, audit, dem, demstudy)


class UserError(Exception):
    """A mistake the user can fix; its message is shown as is."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump) and exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

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


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.handler(args) or 0)
    except (UserError, ValueError) as exc:
        print(f"viscontact {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"viscontact {args.command}: error: {exc.strerror or exc}: {exc.filename or ''}".rstrip(": "),
              file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
