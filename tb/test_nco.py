# amaranth: UnusedElaboratable=no
"""The N-phase sine reference (SineNco), every output on every clock, against
mdfqm_model.nco.NcoModel; quarter and full tables, runtime frequency/amplitude, back-pressure."""

import cocotb
import pytest

from demo.nco import SineNco
from mdfqm_model.nco import NcoModel
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start, unpack

# phases, width, acc_bits, table_bits, sample_width, quarter
CASES = [(3, 16, 32, 8, 16, True), (3, 16, 32, 8, 16, False), (5, 12, 24, 4, 8, True),
         (3, 18, 32, 10, 18, False), (4, 16, 12, 2, 4, True)]


def generate(rng, p, cycles):
    model = NcoModel(p["phases"], p["width"], p["acc_bits"], p["table_bits"], p["sample_width"])
    amp_max = (1 << (p["width"] - 1)) - 1
    freq_max = (1 << p["acc_bits"]) - 1
    freq, amplitude, ready_mode = 0, 0, "always"
    stim = {"freq": [], "amplitude": [], "ref__ready": []}
    expected = {"ref__valid": [], "ref__payload": [], "phase": []}
    for cycle in range(cycles):
        if cycle % 400 == 0:
            freq = rng.choice([0, 1, freq_max, rng.randrange(freq_max + 1),
                               rng.randrange(1 << (p["acc_bits"] - 6))])
            amplitude = rng.choice([0, 1, amp_max, rng.randrange(amp_max + 1)])
            ready_mode = rng.choice(["always", "random", "rare"])
        ready = {"always": 1, "random": int(rng.random() < 0.5),
                 "rare": int(rng.random() < 0.02)}[ready_mode]
        out = model.step(freq=freq, amplitude=amplitude, ready=ready)
        stim["freq"].append(freq)
        stim["amplitude"].append(amplitude)
        stim["ref__ready"].append(ready)
        expected["ref__valid"].append(out["valid"])
        expected["ref__payload"].append(list(out["payload"]) if out["valid"] else None)
        expected["phase"].append(out["phase"])
    return stim, expected


@cocotb.test()
async def nco_every_clock(dut):
    """Random frequency (0, 1, largest, random) and amplitude (0, 1, largest, random) steps
    every 400 clocks, with ready always, random or rare."""
    p = params()
    rng = seeded_rng(dut, "nco_every_clock")
    stim, expected = generate(rng, p, 12000)
    await start(dut)
    checked = await check_cycles(dut, stim, expected, decode={
        "ref__payload": lambda word: unpack(word, p["width"], p["phases"])})
    beats = sum(1 for v, r in zip(expected["ref__valid"], stim["ref__ready"], strict=True)
                if v and r)
    dut._log.info("nco_every_clock: %d cycles, %d beats, every output equal to the model",
                  checked, beats)


@pytest.mark.parametrize(("phases", "width", "acc_bits", "table_bits", "sample_width",
                          "quarter"), CASES)
def test_nco(phases, width, acc_bits, table_bits, sample_width, quarter):
    run_block(lambda: SineNco(phases, width, acc_bits, table_bits, sample_width, quarter),
              "sine_nco", "test_nco",
              {"phases": phases, "width": width, "acc_bits": acc_bits, "table_bits": table_bits,
               "sample_width": sample_width, "quarter": quarter})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer >= 3, not 2"),
    ({"table_bits": 13}, "table_bits must be an integer in [2, 12], not 13"),
    ({"sample_width": 3}, "sample_width must be an integer in [4, 24], not 3"),
    ({"acc_bits": 8}, "acc_bits must be an integer in [10, 32], not 8"),
    ({"quarter": 1}, "quarter must be a bool, not 1"),
])
def test_nco_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        SineNco(**kwargs)
    assert str(info.value) == message
