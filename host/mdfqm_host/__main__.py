"""``python -m mdfqm_host``: see :mod:`mdfqm_host.cli`."""

import sys

from .cli import main

__all__ = []


sys.exit(main())
