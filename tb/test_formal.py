"""Tests of the tests: each safety proof must fail on a design broken on purpose.

The broken dead time is in tb/test_driver.py (a leg that follows its command at once); here the
fault path and the integrator bound are cut in the netlist (Yosys ``connect -set`` on the named
wire) and the same properties must produce a counterexample.
"""

import pytest

from formal import assertion_site, run_sby
from mdfqm_gateware import driver, integrator
from mdfqm_gateware.driver import GateDriver
from mdfqm_gateware.integrator import Integrator
from mdfqm_gateware.selector import StateDecoder


def test_sby_finds_an_ungated_fault():
    """With the fault no longer gating the legs, "all off after a fault" has a counterexample."""
    site = assertion_site(driver.__file__, "gates on one clock after the synchronised fault")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(GateDriver(3, 2, 6, formal=True), "driver_ungated_fault", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fault_active 1'0", "cd"))


@pytest.mark.parametrize(("phases", "width"), [(3, 8), (4, 8)])
def test_sby_proves_the_integrator_never_wraps(phases, width):
    """Properties 5 and sum(X) == 0, for any reference / feedback sequence summing to zero."""
    run_sby(Integrator(phases, width, formal=True), f"integrator_n{phases}_w{width}",
            {"prove": 2, "cover": 8})


def test_sby_finds_an_unbounded_integrator():
    """Integrating although the result does not fit: the wrap is caught."""
    site = assertion_site(integrator.__file__,
                          "integrator differs from T - U after a commit (it wrapped)")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(Integrator(3, 8, formal=True), "integrator_unbounded", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fits 1'1", "cd"))


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_the_state_is_a_candidate_and_the_feedback_its_voltage(phases):
    """Property 6 for any permutation, winner, policy and previous state; the covers reach
    every one of the 2**N gate states."""
    run_sby(StateDecoder(phases, formal=True), f"decoder_n{phases}", {"prove": 2, "cover": 4})


def test_sby_proves_the_five_leg_gate_driver():
    """The driver's safety properties (both-on, dead time, fault, reset) for five legs."""
    run_sby(GateDriver(5, 5, 16, True, False, formal=True), "gate_driver_n5", 20,
            ("prove", "cover"))
