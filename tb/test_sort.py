# amaranth: UnusedElaboratable=no
"""sort1, the N-input sorting network, against the model's stable descending sort."""

# (line 1: components built only to be refused or measured are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.sort import SortNetwork
from mdfqm_model.update import sort1
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack

CASES = [(n, 16, ()) for n in (3, 4, 5, 6, 9)] + [(3, 12, ()), (3, 18, ()), (5, 12, ())]
#: outputs given inverted, as the candidates take them (selector.rho_held_inverted), and others
INVERTED_CASES = [(3, 18, (1,)), (6, 16, (1, 3)), (5, 12, (0, 4))]


def make_stimulus(rng, count, width, cycles):
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    pool = [lo, hi, 0, -1, 1]
    vectors = []
    for cycle in range(cycles):
        kind = cycle % 4
        if kind == 0:      # uniform random
            vec = [rng.randint(lo, hi) for _ in range(count)]
        elif kind == 1:    # few distinct values: ties everywhere
            few = [rng.randint(lo, hi) for _ in range(2)]
            vec = [rng.choice(few) for _ in range(count)]
        elif kind == 2:    # extreme codes
            vec = [rng.choice(pool) for _ in range(count)]
        else:              # all equal
            vec = [rng.randint(lo, hi)] * count
        vectors.append(vec)
    return vectors


@cocotb.test()
async def sort_random_and_ties(dut):
    p = params()
    count, width, latency = p["count"], p["width"], p["latency"]
    inverted = {int(x) for x in p.get("inverted", "").split("_") if x}   # given as ~value
    rng = seeded_rng(dut, "sort_random_and_ties")
    vectors = make_stimulus(rng, count, width, 2000)
    valid = [rng.randint(0, 1) for _ in vectors]
    index_width = max(1, (count - 1).bit_length())
    want_values, want_index, want_valid = [], [], []
    for cycle in range(len(vectors)):
        if cycle < latency:     # the reset contents: unspecified, and not valid
            want_values.append(None)
            want_index.append(None)
            want_valid.append(0)
            continue
        rho, perm = sort1(vectors[cycle - latency])
        want_values.append([~v if pos in inverted else v for pos, v in enumerate(rho)])
        want_index.append(list(perm))
        want_valid.append(valid[cycle - latency])
    await start(dut)
    await check_cycles(
        dut,
        {"i_values": [pack(v, width) for v in vectors], "i_valid": valid},
        {"o_values": want_values, "o_index": want_index, "o_valid": want_valid},
        decode={"o_values": lambda w: unpack(w, width, count),
                "o_index": lambda w: unpack(w, index_width, count, signed=False)},
    )


@pytest.mark.parametrize(("count", "width", "inverted"), CASES + INVERTED_CASES)
def test_sort(count, width, inverted):
    latency = SortNetwork(count, width).latency
    params = {"count": count, "width": width, "latency": latency}
    if inverted:
        params["inverted"] = "_".join(map(str, inverted))      # a build folder's name
    run_block(lambda: SortNetwork(count, width, inverted_outputs=inverted), "sort_network",
              "test_sort", params)


@pytest.mark.parametrize(("count", "width", "message"), [
    (1, 16, "count must be an integer >= 2, not 1"),
    (3, 1, "width must be an integer in [2, 64], not 1"),
    (3.0, 16, "count must be an integer >= 2, not 3.0"),
])
def test_sort_rejects_bad_parameters(count, width, message):
    with pytest.raises(ValueError) as info:
        SortNetwork(count, width)
    assert str(info.value) == message


def test_sort_rejects_an_inverted_output_it_does_not_have():
    with pytest.raises(ValueError) as info:
        SortNetwork(3, 16, inverted_outputs=(3,))
    assert str(info.value) == "inverted_outputs must be positions in [0, 2], not [3]"
