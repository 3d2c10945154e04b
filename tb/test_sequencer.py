# amaranth: UnusedElaboratable=no
"""The update sequencer against the clock-level models' own sequencer (mdfqm_model.clock:
CoreModel for the core's variant, GeneratorModel for the generator's), every output on every
clock: update starts, sampling ticks, the clocks elapsed since the start, the latched
period / OSR / policy / mode / b, the clamps (each minimum period and the one below it aimed),
sync_in at every phase, long and short updates, resets mid-run."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.sequencer import UpdateSequencer
from mdfqm_model.clock import CoreModel, GeneratorModel
from mdfqm_spec.contract import MODES, loop_latency, min_period, resolution_latency
from mdfqm_testkit.harness import check_cycles, params, run_block, seeded_rng, start

# (phases, max_bits or None for the core's sequencer)
CASES = [(3, None), (3, 4)]


@cocotb.test()
async def sequencer_against_the_clock_model(dut):
    p = params()
    generator = p["max_bits"] is not None
    model = (GeneratorModel(p["phases"], 16, max_bits=p["max_bits"]) if generator
             else CoreModel(p["phases"], 16))
    latency = model.latency
    rng = seeded_rng(dut, "sequencer_against_the_clock_model")
    names = ["rst", "period", "osr", "zero_policy", "sync_in", *(["mode", "bits"] * generator)]
    inputs = {name: [] for name in names}
    outs = ["start", "tick", "policy", "period_clamped", "elapsed"]
    if generator:
        outs += ["mode_lat", "bits_lat", "long", "p_lat", "mode_clamped"]
    want = {name: [] for name in outs}
    period = osr = 0
    mode = bits = 0
    # the clamp's edges: each minimum period and the one below it (a long update's for every b)
    edges = [latency - 1, latency]
    if generator:
        edges += sorted({min_period(True, b, latency, model.long_latency) + below
                         for b in range(1, p["max_bits"] + 1) for below in (-1, 0)})
    at_long_minimum = 0     # starts of a long update with the period at its minimum, unclamped
    for _ in range(4000):
        if rng.random() < 0.03:             # runtime changes, mostly small periods
            period = rng.choice([0, 1, *edges, latency + 3, rng.randrange(80),
                                 0xFFFF if rng.random() < 0.05 else 20])
            osr = rng.choice([0, 1, 2, 3, 255 if rng.random() < 0.05 else 4])
            mode, bits = rng.randrange(8), rng.randrange(16)
            if generator and rng.random() < 0.25:   # a slot mode at its b's minimum, aimed
                mode, bits = rng.randint(1, len(MODES) - 1), rng.randint(1, p["max_bits"])
                period = min_period(True, bits, latency, model.long_latency)
        stim = {"rst": int(rng.random() < 0.002), "period": period, "osr": osr,
                "zero_policy": rng.randint(0, 1), "sync_in": int(rng.random() < 0.08)}
        if generator:
            stim.update(mode=mode if rng.random() < 0.7 else 0, bits=bits)
        for name in names:
            inputs[name].append(stim[name])
        visible = {"policy": model.policy_lat}
        if generator:
            visible.update(mode_lat=model.mode_lat, bits_lat=model.bits_lat, long=model.long_lat,
                           p_lat=model.p_lat if model.phase >= 2 else None)
        out = model.step(**{k: v for k, v in stim.items() if k not in ("mode", "bits")},
                         **({"mode": stim["mode"], "bits": stim["bits"]} if generator else {}))
        visible.update(start=out["start"], tick=out["sample"],
                       period_clamped=out["period_clamped"], elapsed=out["elapsed"])
        if generator:
            visible["mode_clamped"] = out["mode_clamped"]
            at_long_minimum += bool(out["start"] and model.long_lat and period == min_period(
                True, model.bits_lat, latency, model.long_latency))
        for name in outs:
            want[name].append(visible[name])
    assert sum(want["start"]) > 200 and sum(want["tick"]) > 50
    assert not generator or at_long_minimum > 5, f"{at_long_minimum} long starts at the minimum"
    await start(dut)
    await check_cycles(dut, inputs, want)


@pytest.mark.parametrize(("phases", "max_bits"), CASES)
def test_sequencer(phases, max_bits):
    latency = loop_latency(phases)
    extra = ({} if max_bits is None else
             {"long_latency": resolution_latency(phases, max_bits), "max_bits": max_bits})
    run_block(lambda: UpdateSequencer(latency, **extra), "update_sequencer", "test_sequencer",
              {"phases": phases, "max_bits": max_bits})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"latency": 1}, "latency must be an integer >= 2, not 1"),
    ({"latency": 8, "osr_width": 17}, "osr_width must be an integer in [1, 16], not 17"),
    ({"latency": 8, "long_latency": 7}, "long_latency must be an integer >= 8, not 7"),
    ({"latency": 8, "long_latency": 20, "max_bits": 12, "period_width": 10},
     "period_width must hold the longest minimum period 4096, not 10"),
])
def test_sequencer_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        UpdateSequencer(**kwargs)
    assert str(info.value) == message
