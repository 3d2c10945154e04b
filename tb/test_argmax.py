# amaranth: UnusedElaboratable=no
"""sort2 (ArgMax), the first maximum of the candidates, against the model's select(): every
output on every clock, latency argmax_stages(count)."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.selector import ArgMax, values_held_inverted
from mdfqm_model.update import select
from mdfqm_spec.contract import argmax_stages
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start

CASES = [(3, 8), (17, 6)]            # one stage; two stages with a partial group


@cocotb.test()
async def argmax_ties_and_extremes(dut):
    p = params()
    count, width, latency = p["count"], p["width"], p["latency"]
    rng = seeded_rng(dut, "argmax_ties_and_extremes")
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    vectors = []
    for cycle in range(2000):
        kind = cycle % 4
        if kind == 0:
            vec = [rng.randint(lo, hi) for _ in range(count)]
        elif kind == 1:          # the maximum several times: the first one wins
            few = [rng.randint(lo, hi) for _ in range(2)]
            vec = [rng.choice(few) for _ in range(count)]
        elif kind == 2:
            vec = [rng.choice([lo, hi, 0, -1]) for _ in range(count)]
        else:
            vec = [rng.randint(lo, hi)] * count
        vectors.append(vec)
    valid = [rng.randint(0, 1) for _ in vectors]
    want = [0] * latency + [select(v) for v in vectors[:len(vectors) - latency]]
    # the positions the port takes inverted (the candidates give them so)
    inverted = values_held_inverted(count)
    given = [[~x if i in inverted else x for i, x in enumerate(v)] for v in vectors]
    await start(dut)
    await check_cycles(
        dut, {"i_values": [pack(v, width) for v in given], "i_valid": valid},
        {"o_index": want, "o_valid": [0] * latency + valid[:len(valid) - latency]})


@pytest.mark.parametrize(("count", "width"), CASES)
def test_argmax(count, width):
    latency = ArgMax(count, width).latency
    assert latency == argmax_stages(count)
    run_block(lambda: ArgMax(count, width), "argmax", "test_argmax",
              {"count": count, "width": width, "latency": latency})


@pytest.mark.parametrize(("count", "width", "message"), [
    (1, 16, "count must be an integer >= 2, not 1"),
    (3, 1, "width must be an integer in [2, 64], not 1"),
    (3, 65, "width must be an integer in [2, 64], not 65"),
])
def test_argmax_rejects_bad_parameters(count, width, message):
    with pytest.raises(ValueError) as info:
        ArgMax(count, width)
    assert str(info.value) == message
