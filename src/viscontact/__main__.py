"""``python -m viscontact``: the command line."""

from .cli import main

raise SystemExit(main())
