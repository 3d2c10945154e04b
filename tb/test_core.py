# amaranth: UnusedElaboratable=no
"""The whole MDFQM core, every output on every clock, against mdfqm_model.clock.CoreModel."""

# (line 1: components built only to be refused or measured are never elaborated, on purpose)

import math

import cocotb
import pytest

from harness import check_cycles, pack, params, run_block, seeded_rng, start
from mdfqm_gateware.core import MdfqmCore
from mdfqm_model.clock import CoreModel
from mdfqm_model.contract import Contract, loop_latency

CASES = [(3, 16, "largest_duty"), (3, 16, "exact_nearest"), (3, 12, "largest_duty"),
         (3, 18, "largest_duty"), (4, 16, "largest_duty"), (5, 16, "largest_duty"),
         (5, 16, "exact_nearest"), (6, 16, "largest_duty"), (9, 16, "exact_nearest"),
         (9, 12, "largest_duty")]

OUTPUTS = {"ref__ready": "ref_ready", "start": "start", "h": "h", "update": "update",
           "sample": "sample", "saturated": "saturated", "period_clamped": "period_clamped"}


def sine_codes(contract, amplitude, angle, offset=0):
    """Phase references of a balanced N-phase sine, ``amplitude`` in Vdc, plus a common mode."""
    n = contract.phases
    codes = []
    for i in range(n):
        value = amplitude * math.cos(angle - 2 * math.pi * i / n) + offset
        codes.append(max(contract.code_min,
                         min(contract.code_max, round(value * contract.full))))
    return codes


def linear_amplitude(phases):
    """Largest sine amplitude (Vdc) inside the linear range max(v) - min(v) <= 1."""
    spread = max(math.cos(2 * math.pi * i / phases) for i in range(phases)) - min(
        math.cos(2 * math.pi * i / phases) for i in range(phases))
    return 1 / spread


def generate(rng, scenario, contract, rule, cycles):
    """Closed-loop stimulus: a stream source that reacts to the model's ``ready`` like a real
    producer (holds valid and payload until accepted, idles at random) and the runtime settings
    of ``scenario``. Returns (inputs per cycle, expected outputs per cycle)."""
    model = CoreModel(contract.phases, contract.width, rule)
    latency = model.latency
    n = contract.phases
    lin = linear_amplitude(n)
    period, osr, policy = latency, 4, 0
    angle, step = rng.uniform(0, 2 * math.pi), rng.uniform(0.002, 0.05)
    amplitude, offset = 0.9 * lin, 0.0
    offered = None
    stim = {"rst": [], "ref__valid": [], "ref__payload": [], "period": [], "osr": [],
            "zero_policy": [], "sync_in": []}
    expected = {name: [] for name in OUTPUTS}
    for cycle in range(cycles):
        rst = 0
        if cycle % 997 == 0:                              # runtime settings move
            if scenario in ("sine", "runtime"):
                period = rng.choice([latency, latency, latency + 1, 2 * latency + 3])
                osr = rng.choice([1, 2, 4, 4])
                policy = rng.randint(0, 1)
                amplitude = rng.uniform(0.05, 1.0) * lin
            if scenario == "runtime":
                period = rng.choice([0, 1, latency - 1, latency, latency + 5, 65535 % 50])
                osr = rng.choice([0, 1, 3, 255 % 7])
            if scenario == "overmod":
                amplitude = rng.uniform(1.0, 2.0) * lin
                offset = rng.uniform(-0.5, 0.5)
                policy = rng.randint(0, 1)
        if scenario == "runtime" and rng.random() < 0.002:
            rst = 1                                       # reset mid-run
        if offered is None and rng.random() < 0.7:       # idle gaps between beats
            angle += step
            if scenario == "extremes":
                offered = [rng.choice([contract.code_min, contract.code_max, 0, -1, 1])
                           for _ in range(n)]
            elif scenario == "ties":
                level = rng.randint(contract.code_min, contract.code_max)
                offered = [rng.choice([level, -level // 2, 0]) for _ in range(n)]
            else:
                offered = sine_codes(contract, amplitude, angle, offset)
            if scenario in ("ties", "extremes"):
                policy = rng.randint(0, 1)
        sync_in = int(scenario == "runtime" and rng.random() < 0.05)
        valid = int(offered is not None)
        payload = offered or [0] * n
        out = model.step(rst=rst, ref_valid=valid, ref=payload, period=period, osr=osr,
                         zero_policy=policy, sync_in=sync_in)
        if valid and out["ref_ready"] and not rst:
            offered = None
        stim["rst"].append(rst)
        stim["ref__valid"].append(valid)
        stim["ref__payload"].append(pack(payload, contract.width))
        stim["period"].append(period)
        stim["osr"].append(osr)
        stim["zero_policy"].append(policy)
        stim["sync_in"].append(sync_in)
        for port, key in OUTPUTS.items():
            expected[port].append(out[key])
    return stim, expected


async def run_scenario(dut, scenario, cycles):
    p = params()
    contract = Contract(p["phases"], p["width"])
    rng = seeded_rng(dut, f"core_{scenario}")
    stim, expected = generate(rng, scenario, contract, p["rule"], cycles)
    await start(dut)
    checked = await check_cycles(dut, stim, expected)
    dut._log.info("core_%s: %d cycles, every output equal to the model", scenario, checked)


@cocotb.test()
async def core_sine(dut):
    """Sine references inside the linear range, runtime period/OSR/policy changes."""
    await run_scenario(dut, "sine", params().get("cycles", 20000))


@cocotb.test()
async def core_overmodulation(dut):
    """Up to twice the linear range with common-mode offsets: the integrator bound holds."""
    await run_scenario(dut, "overmod", params().get("cycles", 20000) // 2)


@cocotb.test()
async def core_runtime_and_reset(dut):
    """Periods below the loop latency (clamped), OSR 0, resets in the middle of updates, sync."""
    await run_scenario(dut, "runtime", params().get("cycles", 20000) // 2)


@cocotb.test()
async def core_ties(dut):
    """Equal references: sort1 and sort2 tie-breaks and the zero policies."""
    await run_scenario(dut, "ties", params().get("cycles", 20000) // 4)


@cocotb.test()
async def core_extreme_codes(dut):
    """Most negative / most positive codes on every phase."""
    await run_scenario(dut, "extremes", params().get("cycles", 20000) // 4)


@pytest.mark.parametrize(("phases", "width", "rule"), CASES)
def test_core(phases, width, rule):
    run_block(lambda: MdfqmCore(phases, width, rule), "mdfqm_core", "test_core",
              {"phases": phases, "width": width, "rule": rule})


def test_core_latency_is_the_contract():
    assert MdfqmCore(3, 16).latency == loop_latency(3) == 8
    assert MdfqmCore(5, 16).latency == loop_latency(5)


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 2}, "phases must be an integer >= 3, not 2"),
    ({"phases": 3, "width": 7},
     "width must be an integer in [8, 32] for 3 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 7"),
    ({"phases": 9, "width": 9},
     "width must be an integer in [10, 32] for 9 phases (FULL = 2**(width-2) >= 16 * phases), "
     "not 9"),
    ({"phases": 16, "width": 16},
     "rule 'largest_duty' is offered for at most 12 phases (its integrators outgrow their bound "
     "beyond); use 'exact_nearest' for 16 phases"),
    ({"rule": "nearest"},
     "rule must be one of ('largest_duty', 'exact_nearest'), not 'nearest'"),
])
def test_core_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        MdfqmCore(**kwargs)
    assert str(info.value) == message
