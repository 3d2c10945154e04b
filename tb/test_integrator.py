# amaranth: UnusedElaboratable=no
"""The integrators against the model's integrate(): T = X + R registered at a start, X' = T - U
at a commit or, when any phase would leave the signed x_width-bit word, every phase held and
saturated set; starts and commits in any clocks (also together), references and feedback up to
their extremes, for the core's feedback unit (FULL) and the generator's (FULL / 2**max_bits)."""

# (line 1: components built only to be refused are never elaborated, on purpose)

import cocotb
import pytest

from mdfqm_gateware.integrator import Integrator
from mdfqm_model.update import integrate
from mdfqm_spec.contract import Contract
from mdfqm_testkit.harness import check_cycles, pack, params, run_block, seeded_rng, start, unpack

# (phases, width, unit_shift, kept_copy): the core's unit and register, the generator's at
# max_bits 8 (with the kept copy), and the core's unit with the kept copy
CASES = [(3, 16, 14, False), (5, 16, 6, True), (3, 16, 14, True)]


@cocotb.test()
async def integrator_starts_commits_and_bound(dut):
    p = params()
    c, shift = Contract(p["phases"], p["width"]), p["unit_shift"]
    n, units_max, units_width = c.phases, p["units_max"], p["units_width"]
    rng = seeded_rng(dut, "integrator_starts_commits_and_bound")
    x, t, saturated = [0] * n, [0] * n, 0
    inputs = {"rst": [], "i_start": [], "i_r": [], "i_commit": [], "i_units_n": []}
    want = {"o_t": [], "o_x": [], "o_saturated": []}
    for cycle in range(3000):
        big = cycle % 600 > 400                    # overmodulated stretches: the bound is hit
        r = [rng.randint(-c.r_bound, c.r_bound) if big else
             rng.randint(-c.unit // 2, c.unit // 2) for _ in range(n)]
        r = [v - sum(r) // n for v in r]           # the stage's R sums to zero (nearly, here)
        r = [max(-c.r_bound, min(c.r_bound, v)) for v in r]
        units = [rng.choice([-units_max, units_max, 0, rng.randint(-units_max, units_max)])
                 for _ in range(n)]
        start_, commit = int(rng.random() < 0.3), int(rng.random() < 0.3)
        rst = int(rng.random() < 0.002)
        units_n = pack([~u for u in units], units_width)       # the port takes it inverted
        for name, value in (("rst", rst), ("i_start", start_), ("i_r", pack(r, c.r_width)),
                            ("i_commit", commit), ("i_units_n", units_n)):
            inputs[name].append(value)
        want["o_t"].append(list(t))
        want["o_x"].append(list(x))
        want["o_saturated"].append(saturated)
        if rst:
            x, t, saturated = [0] * n, [0] * n, 0
            continue
        next_t = [xi + ri for xi, ri in zip(x, r, strict=True)] if start_ else t
        if commit:
            x, held = integrate(x, t, [u << shift for u in units], c)
            saturated = int(held)
        t = next_t
    assert 50 < sum(want["o_saturated"]) < 2500, "the bound is never (or always) hit"
    await start(dut)
    await check_cycles(dut, inputs, want, decode={
        "o_t": lambda w: unpack(w, c.t_width, n), "o_x": lambda w: unpack(w, c.x_width, n)})


@pytest.mark.parametrize(("phases", "width", "unit_shift", "kept_copy"), CASES)
def test_integrator(phases, width, unit_shift, kept_copy):
    block = Integrator(phases, width, unit_shift=unit_shift)
    units_max = (phases - 1) << (width - 2 - unit_shift)
    run_block(lambda: Integrator(phases, width, unit_shift=unit_shift, kept_copy=kept_copy),
              "integrator", "test_integrator",
              {"phases": phases, "width": width, "unit_shift": unit_shift,
               "kept_copy": kept_copy, "units_max": units_max,
               "units_width": block.units_width})


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"phases": 3, "width": 16, "unit_shift": 15},
     "unit_shift must be an integer in [0, 14], not 15"),
    ({"phases": 3, "width": 16, "formal": 1}, "formal must be a bool, not 1"),
])
def test_integrator_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        Integrator(**kwargs)
    assert str(info.value) == message
