"""Option helpers shared by the commands."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

from ..laws import MODELS
from ..solvers import END_CRITERIA


def add_model_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--model", required=True, metavar="NAME",
                        help=f"contact law: one of {', '.join(MODELS)}")
    parser.add_argument("--p", type=float, default=None,
                        help="damping exponent, only for --model power (p >= 0)")
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
