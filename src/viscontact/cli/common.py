"""Option helpers shared by the commands."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from .._support.outputs import finite_json
from ..physics.laws import MODELS
from ..solvers import END_CRITERIA
from ..physics.domain import range_text as _R


def add_law_option(parser: argparse.ArgumentParser, help: str, required: bool = False) -> None:
    """``--law NAME`` (stored as ``args.model``) and its deprecated spelling ``--model``, which
    still works and adds one deprecation line on stderr.  Both name one option: giving both, or
    either twice, is refused.  ``required``: checked by :func:`viscontact.cli.main` after
    parsing, since argparse cannot require one of two spellings without a group."""
    parser.add_argument("--law", dest="model", metavar="NAME", default=None, help=help)
    parser.add_argument("--model", dest="model", metavar="NAME", default=None,
                        action=_DeprecatedModel, help=argparse.SUPPRESS)
    if required:
        parser.set_defaults(_law_required=True)


def add_model_options(parser: argparse.ArgumentParser, required: bool = True,
                      model_help: str = "") -> None:
    add_law_option(parser, f"contact law: one of {', '.join(MODELS)}{model_help}", required)
    parser.add_argument("--p", type=float, default=None,
                        help=f"damping exponent, only for --law power; {_R('p')}")
    parser.add_argument("--end", choices=END_CRITERIA, default="force",
                        help="end of contact: zero force (default, the study's choice) or zero overlap")


def print_json(obj: Any) -> None:
    json.dump(finite_json(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


def finite_float(text: str) -> float:
    """argparse type of every float option: a finite number (nan and inf never mean anything)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid float value: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def add_force_option(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument("--force", action="store_true",
                        help=f"replace {what} written by an earlier run of this command (never a "
                        "file it did not write)")


def conflict(*pairs: tuple[str, object]) -> None:
    """Refuse options given together that exclude each other: ``(flag, value)`` pairs."""
    given = [flag for flag, v in pairs if v not in (None, False)]
    if len(given) > 1:
        raise ValueError(f"give {' or '.join(given)}, not both")


NOTES: list[str] = []
"""Notes for stderr, printed by :func:`viscontact.cli.main` only once the command succeeded
(an error is one line, with no notes before it)."""


def report_written(out: object, seconds: float, digits: int = 1) -> None:
    """Tell the user on stderr where a report went, how long it took (``digits`` decimals of
    a second) and which page to open."""
    print(f"report written to {out}/ ({seconds:.{digits}f} s); open {out}/index.html",
          file=sys.stderr)


def note(message: str) -> None:
    NOTES.append(message)


def once(cls: type[argparse.Action]) -> type[argparse.Action]:
    """``cls`` refusing a second occurrence of its option: a repeated option would silently
    drop the first value (``--alpha 1 --alpha 2``)."""

    class Once(cls):  # type: ignore[valid-type, misc]
        def __call__(self, parser, namespace, values, option_string=None):
            seen = namespace.__dict__.setdefault("_given", set())
            if self.dest in seen:
                parser.error(f"{'/'.join(self.option_strings) or self.dest} given twice; "
                             "give each option once")
            seen.add(self.dest)
            super().__call__(parser, namespace, values, option_string)

    Once.__name__ = f"Once{cls.__name__}"
    return Once


class _DeprecatedModel(once(argparse._StoreAction)):  # type: ignore[misc]
    """``--model``: the old spelling of ``--law``; same value, one note on stderr.  It shares
    ``--law``'s destination, so ``--law A --model B`` is refused as given twice."""

    def __call__(self, parser, namespace, values, option_string=None):
        super().__call__(parser, namespace, values, option_string)
        note("note: --model is deprecated; use --law (same meaning)")
