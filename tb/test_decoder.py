# amaranth: UnusedElaboratable=no
"""The state decoder against the model's decode() and feedback(): the staircase state of the
winner un-permuted, the zero policy against the previous state, and the feedback in units of
FULL, every output on every clock, one clock of latency."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.selector import StateDecoder
from mdfqm_model.update import decode, feedback
from mdfqm_spec.contract import Contract
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack


@cocotb.test()
async def decoder_every_winner_and_policy(dut):
    n = params()["phases"]
    c = Contract(n, 16)
    rng = seeded_rng(dut, "decoder_every_winner_and_policy")
    index_width = max(1, (n - 1).bit_length())
    perms, js, policies, prevs = [], [], [], []
    for cycle in range(2000):
        perm = list(range(n))
        if cycle % 5:
            rng.shuffle(perm)
        perms.append(perm)
        js.append(0 if cycle % 3 == 0 else rng.randrange(n))     # the zero class often
        policies.append(rng.randint(0, 1))
        k = rng.choice([0, n // 2, n // 2 + 1, n, rng.randrange(n + 1)])   # around half on
        legs = rng.sample(range(n), k)
        prevs.append(sum(1 << leg for leg in legs))
    valid = [rng.randint(0, 1) for _ in perms]
    states = [decode(p, j, pol, prev, n) for p, j, pol, prev in zip(perms, js, policies, prevs,
                                                                      strict=True)]
    units_n = [[~(u // c.full) for u in feedback(h, c)] for h in states]     # given inverted
    await start(dut)
    await check_cycles(
        dut, {"i_perm": [pack(p, index_width) for p in perms], "i_j": js,
              "i_policy": policies, "i_h_prev": prevs, "i_valid": valid},
        {"o_h": [0, *states[:-1]], "o_units_n": [[0] * n, *units_n[:-1]],
         "o_valid": [0, *valid[:-1]]},
        decode={"o_units_n": lambda w: unpack(w, params()["units_width"], n)})


@pytest.mark.parametrize("phases", [3, 4])          # odd and even: the zero policy's half
def test_decoder(phases):
    run_block(lambda: StateDecoder(phases), "state_decoder", "test_decoder",
              {"phases": phases, "units_width": StateDecoder(phases).units_width})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer >= 3, not 2"),
    ({"phases": 3, "formal": 1}, "formal must be a bool, not 1"),
    ({"phases": 3, "assume_inputs": None}, "assume_inputs must be a bool, not None"),
])
def test_decoder_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        StateDecoder(**kwargs)
    assert str(info.value) == message
