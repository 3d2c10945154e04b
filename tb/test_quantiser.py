# amaranth: UnusedElaboratable=no
"""The b-bit quantiser against the model's gamma-mode arithmetic (mdfqm_model.bbit): for every
gamma mode and every b in [1, max_bits], the feedback in units of FULL / 2**max_bits, the centred
layout's bounds, its first and last slot, S - 1 and one slot in scaled units, at o_valid, which
is i_valid delayed by the block's latency."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.resolution import Quantiser
from mdfqm_model.bbit import _gamma_update, centred_slots
from mdfqm_model.update import remove_common_mode
from mdfqm_spec.contract import MODES, Contract
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack

CASES = [(3, 16, 4), (5, 12, 3)]


def expected(t, mode, b, contract, big):
    """What the quantiser presents for an update with optimum signal ``t`` (sum 0)."""
    n, slots = contract.phases, 1 << b
    on, *_ = _gamma_update(t, [0] * n, contract, MODES[mode], b)
    scale = contract.full // slots
    units = [scale * (n * on[i] - sum(on)) // (contract.full >> big) for i in range(n)]
    delta = 1 << (big - b)
    lo = [((slots - on[i]) // 2) * delta for i in range(n)]
    hi = [lo[i] + on[i] * delta for i in range(n)]
    layout = centred_slots(on, slots)
    return {"o_units_n": [~u for u in units], "o_lo": lo, "o_hi": hi, "o_first": layout[0],
            "o_last": layout[-1], "o_slots": slots - 1, "o_delta": delta}


@cocotb.test()
async def quantiser_every_mode_and_b(dut):
    p = params()
    c, big, latency = Contract(p["phases"], p["width"]), p["max_bits"], p["latency"]
    n = c.phases
    rng = seeded_rng(dut, "quantiser_every_mode_and_b")
    index = big + 1
    inputs = {k: [] for k in ("i_t", "i_max", "i_min", "i_valid", "i_mode", "i_bits")}
    outs = ("o_units_n", "o_lo", "o_hi", "o_first", "o_last", "o_slots", "o_delta")
    want = {k: [] for k in (*outs, "o_valid")}
    window = latency + 3
    updates = [(mode, b) for mode in range(1, len(MODES)) for b in range(1, big + 1)] * 6
    rng.shuffle(updates)
    for mode, b in updates:
        codes = [rng.choice([c.code_min, c.code_max, rng.randint(c.code_min // 2, c.code_max // 2)])
                 for _ in range(n)]
        r = remove_common_mode(codes, n)
        x = [rng.randint(-c.unit, c.unit) for _ in range(n - 1)]
        t = [ri + xi for ri, xi in zip(r, [*x, -sum(x)], strict=True)]
        result = expected(t, mode, b, c, big)
        for k in range(window):
            inputs["i_t"].append(pack(t, c.t_width))
            inputs["i_max"].append(max(t) & ((1 << c.t_width) - 1))
            inputs["i_min"].append(min(t) & ((1 << c.t_width) - 1))
            inputs["i_valid"].append(int(k == 1))
            inputs["i_mode"].append(mode)
            inputs["i_bits"].append(b)
            present = k == 1 + latency
            want["o_valid"].append(int(present))
            for name in outs:
                want[name].append(result[name] if present else None)
    await start(dut)
    await check_cycles(dut, inputs, want, decode={
        "o_units_n": lambda w: unpack(w, p["units_width"], n),
        "o_lo": lambda w: unpack(w, index, n, signed=False),
        "o_hi": lambda w: unpack(w, index, n, signed=False)})


@pytest.mark.parametrize(("phases", "width", "max_bits"), CASES)
def test_quantiser(phases, width, max_bits):
    block = Quantiser(phases, width, max_bits)
    run_block(lambda: Quantiser(phases, width, max_bits), "quantiser", "test_quantiser",
              {"phases": phases, "width": width, "max_bits": max_bits, "latency": block.latency,
               "units_width": block.units_width})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 3, "width": 16, "max_bits": 0},
     "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 0"),
    ({"phases": 3, "width": 8, "max_bits": 7},
     "max_bits must be an integer in [1, 6] for a 8-bit reference (2**max_bits slots <= FULL, "
     "at most 12), not 7"),
])
def test_quantiser_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        Quantiser(**kwargs)
    assert str(info.value) == message
