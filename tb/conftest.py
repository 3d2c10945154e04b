"""pytest set-up for the cocotb tests: the venv's tools come first on PATH, so that a single test
runs with `.venv/bin/python -m pytest tb/test_x.py::test_y` as well as through `make`."""

from mdfqm_testkit.harness import verilator_build_env

verilator_build_env()
