# amaranth: UnusedElaboratable=no
"""The slot layout against the contract's presentation rule ("b-bit pulse-width resolution"):
after a load (visible the next clock) an MDFQM state is held, or a layout of S slots of l clocks
plays out (leg i on in slot j when lo_i <= j delta < hi_i; the last slot held until the next
load); loads at any time, also before a layout has finished; every output on every clock."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.resolution import SlotLayout
from mdfqm_model.bbit import centred_slots
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start

CASES = [(3, 3), (5, 4)]


@cocotb.test()
async def slot_layout_loads_and_slots(dut):
    p = params()
    n, big = p["phases"], p["max_bits"]
    rng = seeded_rng(dut, "slot_layout_loads_and_slots")
    names = ("rst", "i_load", "i_bbit", "i_h", "i_first", "i_lo", "i_hi", "i_slots", "i_delta",
             "i_slot_m2")
    inputs = {k: [] for k in names}
    want = {"o_h": []}
    state = None            # (kind, payload, load cycle)
    cycle = 0
    held = dict.fromkeys(names, 0)
    while cycle < 4000:
        b = rng.randint(1, big)
        slots, delta = 1 << b, 1 << (big - b)
        on = [rng.choice([0, slots, rng.randint(0, slots)]) for _ in range(n)]
        lo = [((slots - k) // 2) * delta for k in on]
        hi = [lo[i] + on[i] * delta for i in range(n)]
        length = rng.choice([1, 2, 3, rng.randint(1, 9)])
        load = {"i_load": 1, "i_bbit": rng.random() < 0.75, "i_h": rng.randrange(1 << n),
                "i_first": centred_slots(on, slots)[0], "i_lo": pack(lo, big + 1),
                "i_hi": pack(hi, big + 1), "i_slots": slots - 1, "i_delta": delta,
                "i_slot_m2": (length - 2) & ((1 << 16) - 1), "rst": 0}
        # the next load comes when the layout has played out, or cuts it short
        gap = rng.choice([slots * length + rng.randint(0, 5), rng.randint(1, slots * length + 2)])
        for k in range(gap):
            stim = dict(held, **(load if k == 0 else {"i_load": 0, "rst": 0}))
            stim["rst"] = int(k > 0 and rng.random() < 0.001)
            # the output visible in this clock
            if state is None:
                visible = 0
            elif state[0] == "h":
                visible = state[1]
            else:
                lo_, hi_, length_, slots_, delta_, since = state[1]
                j = min((cycle - since) // length_, slots_ - 1)
                visible = sum(1 << i for i in range(n) if lo_[i] <= j * delta_ < hi_[i])
            want["o_h"].append(visible)
            for name in names:
                inputs[name].append(int(stim[name]))
            held = {**stim, "i_load": 0}
            if stim["rst"]:
                state = None
            elif stim["i_load"]:
                state = (("bbit", (lo, hi, length, slots, delta, cycle + 1)) if stim["i_bbit"]
                         else ("h", stim["i_h"]))
            cycle += 1
    await start(dut)
    await check_cycles(dut, inputs, want)


@pytest.mark.parametrize(("phases", "max_bits"), CASES)
def test_slot_layout(phases, max_bits):
    run_block(lambda: SlotLayout(phases, max_bits), "slot_layout", "test_slot_layout",
              {"phases": phases, "max_bits": max_bits})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2, "max_bits": 3}, "phases must be an integer >= 3, not 2"),
    ({"phases": 3, "max_bits": 13}, "max_bits must be an integer in [1, 12], not 13"),
    ({"phases": 3, "max_bits": 3, "period_width": 1},
     "period_width must be an integer in [2, 32], not 1"),
])
def test_slot_layout_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        SlotLayout(**kwargs)
    assert str(info.value) == message
