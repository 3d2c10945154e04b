"""Tests of the tests: each safety proof must fail on a design broken on purpose.

The broken dead time is in tb/test_driver.py (a leg that follows its command at once); here the
fault path and the integrator bound are cut in the netlist (Yosys ``connect -set`` on the named
wire) and the same properties must produce a counterexample.
"""

import pytest

from formal import assertion_site, run_sby
from mdfqm_gateware import driver
from mdfqm_gateware.driver import GateDriver


def test_sby_finds_an_ungated_fault():
    """With the fault no longer gating the legs, "all off after a fault" has a counterexample."""
    site = assertion_site(driver.__file__, "gates on one clock after the synchronised fault")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(GateDriver(3, 2, 6, formal=True), "driver_ungated_fault", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fault_active 1'0", "cd"))
