# amaranth: UnusedElaboratable=no
"""Candidates, the staircase values of sort1's output, against the model's candidates() for both
rules: every output on every clock, one clock of latency."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.selector import Candidates, values_held_inverted
from mdfqm_model.update import candidates
from mdfqm_spec.contract import Contract
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack

CASES = [(3, 16, "largest_duty"), (5, 12, "exact_nearest"), (6, 16, "largest_duty")]


def sorted_vectors(rng, contract, cycles):
    """Descending vectors of T: random, all equal, extremes of the t_width word, one gap."""
    lo, hi = -(1 << (contract.t_width - 1)), (1 << (contract.t_width - 1)) - 1
    n, out = contract.phases, []
    for cycle in range(cycles):
        kind = cycle % 4
        if kind == 0:
            vec = [rng.randint(lo, hi) for _ in range(n)]
        elif kind == 1:
            vec = [rng.randint(lo, hi)] * n
        elif kind == 2:
            vec = [rng.choice([lo, hi, 0, -1]) for _ in range(n)]
        else:
            v = rng.randint(-contract.unit, contract.unit)
            vec = [v + rng.choice([0, contract.unit]) for _ in range(n)]
        out.append(sorted(vec, reverse=True))
    return out


@cocotb.test()
async def candidates_random_and_extremes(dut):
    p = params()
    c = Contract(p["phases"], p["width"])
    rng = seeded_rng(dut, "candidates_random_and_extremes")
    rhos = sorted_vectors(rng, c, 1500)
    valid = [rng.randint(0, 1) for _ in rhos]
    # the values sort2 takes inverted are given so; every register is 0 (as given) after reset
    inverted = values_held_inverted(c.phases)
    want = [[0] * c.phases] + [[~v if j in inverted else v
                                for j, v in enumerate(candidates(rho, c, p["rule"]))]
                               for rho in rhos[:-1]]
    # the positions the port takes inverted (sort1 gives them so)
    rho_inverted = {int(x) for x in p["rho_inverted"].split("_") if x}
    given = [[~v if j in rho_inverted else v for j, v in enumerate(rho)] for rho in rhos]
    await start(dut)
    await check_cycles(
        dut, {"i_rho": [pack(r, c.t_width) for r in given], "i_valid": valid},
        {"o_values": want, "o_valid": [0, *valid[:-1]]},
        decode={"o_values": lambda w: unpack(w, p["value_width"], c.phases)})


@pytest.mark.parametrize(("phases", "width", "rule"), CASES)
def test_candidates(phases, width, rule):
    block = Candidates(phases, width, rule)
    run_block(lambda: Candidates(phases, width, rule), "candidates", "test_candidates",
              {"phases": phases, "width": width, "rule": rule, "value_width": block.value_width,
               "rho_inverted": "_".join(map(str, sorted(block.rho_inverted)))})


@pytest.mark.parametrize(("phases", "rule", "inverted"), [
    (3, "largest_duty", {1}), (6, "largest_duty", {1, 3}), (7, "largest_duty", {1, 3, 5}),
    (5, "exact_nearest", set())])
def test_candidates_take_every_other_rho_inverted_for_the_duties(phases, rule, inverted):
    # each duty rho_(j-1) - rho_j with one operand inverted; the first and last rho as they are
    assert Candidates(phases, 16, rule).rho_inverted == inverted


def test_candidates_latency():
    assert Candidates(3, 16).latency == 1


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2, "width": 16}, "phases must be an integer >= 3, not 2"),
    ({"phases": 13, "width": 16},
     "rule 'largest_duty' is offered for at most 12 phases (its integrators outgrow their bound "
     "beyond); use 'exact_nearest' for 13 phases"),
    ({"phases": 3, "width": 16, "rule": "nearest"},
     "rule must be one of ('largest_duty', 'exact_nearest'), not 'nearest'"),
])
def test_candidates_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        Candidates(**kwargs)
    assert str(info.value) == message
