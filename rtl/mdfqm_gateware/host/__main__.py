"""``python -m mdfqm_gateware.host``: see :mod:`mdfqm_gateware.host.cli`."""

import sys

from .cli import main

sys.exit(main())
