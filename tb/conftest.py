"""pytest set-up for the cocotb tests: the venv's tools come first on PATH, so that a single test
runs with `.venv/bin/python -m pytest tb/test_x.py::test_y` as well as through `make`; and at the
end of a session the traceability and coverage summary of the vector runs it recorded
(build/traceability.md, mdfqm_testkit.spec_trace) is written by the controlling process (the
xdist workers each record their own runs under build/trace)."""

import time

from mdfqm_testkit import spec_trace
from mdfqm_testkit.harness import verilator_build_env

verilator_build_env()

#: when this session began: the summary takes the runs recorded since
SESSION_START = time.time()


def pytest_sessionfinish(session):
    if hasattr(session.config, "workerinput"):     # an xdist worker: the controller writes it
        return
    path = spec_trace.write_summary(since=SESSION_START)
    if path is not None:
        print(f"\ntraceability and coverage summary: {path}")
