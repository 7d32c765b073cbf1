"""Option helpers shared by the commands."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..laws import MODELS
from ..solvers import END_CRITERIA
from ..domain import range_text as _R


def add_model_options(parser: argparse.ArgumentParser, required: bool = True,
                      model_help: str = "") -> None:
    parser.add_argument("--model", required=required, metavar="NAME",
                        help=f"contact law: one of {', '.join(MODELS)}{model_help}")
    parser.add_argument("--p", type=float, default=None,
                        help=f"damping exponent, only for --model power; {_R('p')}")
    parser.add_argument("--end", choices=END_CRITERIA, default="force",
                        help="end of contact: zero force (default, the study's choice) or zero overlap")


def finite_json(obj: Any) -> Any:
    """Replace non-finite floats by None so the output is strict JSON."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: finite_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_json(v) for v in obj]
    return obj


def print_json(obj: Any) -> None:
    json.dump(finite_json(obj), sys.stdout, indent=2)
    sys.stdout.write("\n")


def write_atomic(path: str, write: Callable[[Path], None]) -> None:
    """Write a file through a temporary sibling so a failure leaves no partial file.

    ``write(tmp_path)`` creates the content; the temporary file keeps ``path``'s suffix.
    """
    target = Path(path)
    if target.is_dir():
        raise ValueError(f"{path} is a directory; give a file name")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=target.suffix,
                                   dir=target.parent if str(target.parent) else ".")
    except OSError as exc:
        raise ValueError(f"cannot write {path}: {exc.strerror or exc}") from None
    os.close(fd)
    try:
        write(Path(tmp))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
