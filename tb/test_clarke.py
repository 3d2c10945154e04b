# amaranth: UnusedElaboratable=no
"""Inverse Clarke stream stage: every output every cycle against InverseClarkeModel, with idle
gaps on the input and back-pressure on the output."""

import cocotb
import pytest

from mdfqm_gateware.clarke import InverseClarke
from mdfqm_model.clarke import InverseClarkeModel, inverse_clarke
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack


def stimulus(rng, width, cycles, gaps, backpressure):
    """A producer that holds valid and payload until accepted, a consumer that stalls."""
    lo, hi = -(1 << (width - 1)), (1 << (width - 1)) - 1
    model = InverseClarkeModel(width)
    stim = {"i__valid": [], "i__payload": [], "o__ready": []}
    want = {"i__ready": [], "o__valid": [], "o__payload": [], "clamped": []}
    offered = None
    for _ in range(cycles):
        if offered is None and rng.random() >= gaps:
            kind = rng.random()
            if kind < 0.2:
                offered = (rng.choice([lo, hi, 0, -1]), rng.choice([lo, hi, 0, 1]))
            else:
                amplitude = rng.randint(0, hi)
                offered = (rng.randint(-amplitude, amplitude), rng.randint(-amplitude, amplitude))
        ready = int(rng.random() >= backpressure)
        valid = int(offered is not None)
        alpha, beta = offered or (0, 0)
        out = model.step(in_valid=valid, alpha=alpha, beta=beta, out_ready=ready)
        if valid and out["in_ready"]:
            offered = None
        stim["i__valid"].append(valid)
        stim["i__payload"].append(pack([alpha, beta], width))
        stim["o__ready"].append(ready)
        want["i__ready"].append(out["in_ready"])
        want["o__valid"].append(out["out_valid"])
        want["o__payload"].append(list(out["codes"]))
        want["clamped"].append(out["clamped"])
    return stim, want


@cocotb.test()
async def clarke_gaps_and_backpressure(dut):
    width = params()["width"]
    rng = seeded_rng(dut, "clarke")
    await start(dut)
    for gaps in (0.0, 0.5):
        for backpressure in (0.0, 0.6):
            stim, want = stimulus(rng, width, 3000, gaps, backpressure)
            await check_cycles(dut, stim, want,
                               decode={"o__payload": lambda word: unpack(word, width, 3)})
            # restart from the reset state for the next combination
            dut.rst.value = 1
            await start(dut, reset_cycles=1)


@pytest.mark.parametrize("width", [12, 16, 18])
def test_clarke(width):
    run_block(lambda: InverseClarke(width), "inverse_clarke", "test_clarke", {"width": width})


def test_clarke_model_is_the_transform():
    """Against floating point: at most half a code plus |beta| 2**-FRAC away, when unclamped."""
    import math

    for alpha, beta in [(1000, 0), (0, 1000), (-32768, 32767), (12345, -23456), (7, -7)]:
        (a, b, c), clamped = inverse_clarke(alpha, beta, 16)
        exact = (alpha, -alpha / 2 + math.sqrt(3) / 2 * beta, -alpha / 2 - math.sqrt(3) / 2 * beta)
        if not clamped:
            for got, real in zip((a, b, c), exact, strict=True):
                assert abs(got - real) <= 0.5 + abs(beta) * 2**-17 + 1e-9


def test_clarke_rejects_bad_width():
    with pytest.raises(ValueError, match=r"^width must be an integer in \[8, 32\], not 7$"):
        InverseClarke(7)
