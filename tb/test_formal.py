"""Tests of the tests: each safety proof must fail on a design broken on purpose.

The broken dead time is in tb/test_driver.py (a leg that follows its command at once); here the
fault path and the integrator bound are cut in the netlist (Yosys ``connect -set`` on the named
wire) and the same properties must produce a counterexample.
"""

import pytest

from formal import assertion_site, run_sby
from mdfqm_gateware import driver, integrator
from mdfqm_gateware.driver import GateDriver
from mdfqm_gateware.generator import GatingSignalGenerator
from mdfqm_gateware.integrator import Integrator
from mdfqm_gateware.selector import ArgMax, StateDecoder
from mdfqm_gateware.sort import SortNetwork
from mdfqm_model.contract import Contract, sorting_network


def test_sby_finds_an_ungated_fault():
    """With the fault no longer gating the legs, "all off after a fault" has a counterexample."""
    site = assertion_site(driver.__file__, "gates on one clock after the synchronised fault")
    with pytest.raises(AssertionError, match=rf"(?s)BMC failed!.*Assert failed in dut: \S*{site} "):
        run_sby(GateDriver(3, 2, 6, formal=True), "driver_ungated_fault", 12, tasks=("bmc",),
                keep_failed=False, mutation=("cd dut", "connect -set fault_active 1'0", "cd"))


@pytest.mark.parametrize(("phases", "width", "unit_shift"), [
    (3, 16, None), (5, 16, None), (9, 16, None),     # the core's (feedback in units of FULL)
    (3, 16, 6), (5, 16, 6),                         # the generator's (max_bits 8)
])
def test_sby_proves_the_integrator_never_wraps(phases, width, unit_shift):
    """Property 5 per phase (T = X + R exactly after a start, X = T - U exactly or held after a
    commit) for any reference and feedback the ports carry."""
    run_sby(Integrator(phases, width, unit_shift, formal=True, formal_sums=False),
            f"integrator_n{phases}_w{width}_s{unit_shift}", {"prove": 2, "cover": 8})


@pytest.mark.parametrize(("phases", "width"), [(3, 16), (4, 8)])
def test_sby_proves_the_integrators_sum_to_zero(phases, width):
    """Property 5 and sum(X) == 0 for any reference / feedback sequences that each sum to zero.
    The sum follows from the per-phase exactness by linearity; the solver's proof of it is an
    adder-tree rearrangement that did not finish in 7 minutes for five phases (yices, z3 and
    boolector alike), so it runs for three and four."""
    run_sby(Integrator(phases, width, formal=True), f"integrator_sums_n{phases}_w{width}",
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


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_sort1_is_a_stable_descending_sort(phases):
    """For any input sequence: every layer holds a permutation (so the decoder's ``i_perm``
    always is one) and the inputs permuted by it; the output is sorted, ties in input order.
    Width: the core's T at the drop-in size."""
    sort1 = SortNetwork(phases, Contract(phases, 16).t_width, formal=True)
    run_sby(sort1, f"sort1_n{phases}", sort1.latency + 2)


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_sort2_picks_the_first_maximum(phases):
    """For any input sequence: the index is always a candidate (the decoder's ``i_j < N``) and
    a valid one is the first maximum."""
    sort2 = ArgMax(phases, 20, formal=True)
    run_sby(sort2, f"sort2_n{phases}", sort2.latency + 2)


@pytest.mark.parametrize("phases", [3, 5])
def test_sby_proves_the_generator_at_the_drop_in_size(phases):
    """The b-bit generator (max_bits 8): the core's blocks' properties in place, and the mode
    and b in force legal whatever arrives on ``mode`` and ``bits``."""
    run_sby(GatingSignalGenerator(phases, 16, max_bits=8, formal=True), f"generator_n{phases}",
            len(sorting_network(phases)) + 2, ("prove",))


@pytest.mark.parametrize(("phases", "width", "depth"), [
    (3, 8, 24),
    pytest.param(5, 9, 26, marks=pytest.mark.long_proof),    # 389 s: `make prove-long`
])
def test_sby_covers_every_mode_of_the_generator(phases, width, depth):
    """With max_bits 2 (a long update fits the bounded run): an update in every mode (mdfqm,
    svpwm, dpwm0, dpwm1, sector dpwm), the slot layout switching the gates inside an update in
    each gamma mode, both clamps, a saturated commit, every gate state as an update's result."""
    run_sby(GatingSignalGenerator(phases, width, max_bits=2, formal=True),
            f"generator_modes_n{phases}", depth, ("cover",))
