"""pytest set-up for the cocotb tests: the venv's tools come first on PATH, so that a single test
runs with `.venv/bin/python -m pytest tb/test_x.py::test_y` as well as through `make`."""

import os
import sys
from pathlib import Path

_bin = str(Path(sys.executable).parent)
if os.environ.get("PATH", "").split(os.pathsep)[0] != _bin:
    os.environ["PATH"] = _bin + os.pathsep + os.environ.get("PATH", "")
