# amaranth: UnusedElaboratable=no
"""The reference stage (sampling switch and exact common-mode removal) against the contract's
"Reference stage" rules, every output on every clock: a beat accepted in cycle a is pending from
a + K (K = reference_latency(N) = 2N + 1; R = N c - sum c, the model's remove_common_mode), ready
is low from a + 1 until the cycle before a sampling tick hands it over, the held reference (r)
changes only in a tick's cycle, a tick without a pending beat keeps it; resets mid-run."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.reference import ReferenceStage
from mdfqm_model.update import remove_common_mode
from mdfqm_spec.contract import Contract, reference_latency
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack

CASES = [(3, 16), (5, 12)]


def expected_outputs(stim, phases):
    """The contract's rules, clock by clock (registers reset to zero)."""
    in_flight, held = None, [0] * phases         # in_flight: (accept cycle, R)
    ready, r = [], []
    for cycle, (rst, valid, codes, tick_next) in enumerate(zip(*stim, strict=True)):
        full = in_flight is not None and cycle >= in_flight[0] + reference_latency(phases)
        ready.append(int(in_flight is None))
        r.append(list(held))
        if rst:
            in_flight, held = None, [0] * phases
            continue
        if tick_next and full:
            held, in_flight = in_flight[1], None
        elif valid and in_flight is None:
            in_flight = (cycle, remove_common_mode(codes, phases))
    return ready, r


@cocotb.test()
async def reference_beats_ticks_and_resets(dut):
    p = params()
    c = Contract(p["phases"], p["width"])
    rng = seeded_rng(dut, "reference_beats_ticks_and_resets")
    cycles = 3000
    rst = [int(rng.random() < 0.004) for _ in range(cycles)]
    valid = [int(rng.random() < 0.5) for _ in range(cycles)]
    codes = [[rng.choice([c.code_min, c.code_max, 0, rng.randint(c.code_min, c.code_max)])
              for _ in range(c.phases)] for _ in range(cycles)]
    tick_next = [int(rng.random() < rng.choice([0.05, 0.3])) for _ in range(cycles)]
    ready, r = expected_outputs((rst, valid, codes, tick_next), c.phases)
    assert sum(ready) < cycles - 500, "beats are never held"
    await start(dut)
    await check_cycles(
        dut, {"rst": rst, "ref__valid": valid, "ref__payload": [pack(v, c.width) for v in codes],
              "tick_next": tick_next},
        {"ref__ready": ready, "r": r}, decode={"r": lambda w: unpack(w, c.r_width, c.phases)})


@pytest.mark.parametrize(("phases", "width"), CASES)
def test_reference(phases, width):
    run_block(lambda: ReferenceStage(phases, width), "reference_stage", "test_reference",
              {"phases": phases, "width": width})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2, "width": 16}, "phases must be an integer >= 3, not 2"),
    ({"phases": 3, "width": 7},
     "width must be an integer in [8, 32] for 3 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 7"),
])
def test_reference_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        ReferenceStage(**kwargs)
    assert str(info.value) == message
