"""GeneratorModel: the timing rules of the contract's "b-bit pulse-width resolution" section."""

import numpy as np
import pytest

from mdfqm_model.bbit import modulate_bbit
from mdfqm_model.clock import GENERATOR_OUTPUTS, OUTPUTS, CoreModel, GeneratorModel
from mdfqm_spec.contract import (
    FEWEST_TRANSITIONS,
    MODES,
    Contract,
    loop_latency,
    resolution_latency,
)

GAMMA = {name: MODES.index(name) for name in MODES[1:]}


def run(model, cycles, **stim):
    return model.simulate({"cycles": cycles, **stim}, trace_state=True)


@pytest.mark.parametrize(("phases", "rule"), [(3, "largest_duty"), (5, "exact_nearest")])
def test_mode_mdfqm_is_the_core(phases, rule, rng):
    """mode held at 0 (bits anything): every output of every cycle equals CoreModel's."""
    c = Contract(phases, 14)
    core, gen = CoreModel(phases, 14, rule), GeneratorModel(phases, 14, rule, 6)
    cycles = 6000
    stim = {
        "ref_valid": rng.integers(0, 2, cycles),
        "ref": rng.integers(-c.full, c.full, size=(cycles, phases)),
        "period": rng.choice([0, 3, core.latency, core.latency + 5], cycles),
        "osr": rng.integers(0, 4, cycles),
        "zero_policy": rng.integers(0, 2, cycles),
        "sync_in": (rng.random(cycles) < 0.05).astype(int),
        "rst": (rng.random(cycles) < 0.002).astype(int),
    }
    a = core.simulate(stim)
    b = gen.simulate({**stim, "mode": 0, "bits": rng.integers(0, 16, cycles)})
    for k in OUTPUTS:
        assert (a[k] == b[k]).all(), k
    assert not b["mode_clamped"].any()
    assert set(GENERATOR_OUTPUTS) == {*OUTPUTS, "mode_clamped", "mode_in_force", "bits_in_force"}


@pytest.mark.parametrize("mode", list(GAMMA))
@pytest.mark.parametrize(("b", "period"), [(1, 20), (3, 24), (3, 29), (6, 64), (6, 131)])
def test_layout_timing_and_results(mode, b, period, rng):
    """Presentations L_b after each start; slots of floor(P/S) clocks, the remainder in the
    last; the slot states and the update results are modulate_bbit's on the beats."""
    n = 3
    c = Contract(n, 16)
    g = GeneratorModel(n, 16, max_bits=8)
    lb, s = g.long_latency, 1 << b
    p = max(period, lb, s)
    osr, k = 2, 12
    beats = rng.integers(-c.full // 2, c.full // 2, size=(k, n))
    q, hs, ups, starts = 0, [], [], []
    for cyc in range((k + 2) * osr * p + lb):
        ref = beats[min(q, k - 1)]
        o = g.step(ref_valid=int(q < k), ref=ref, period=period, osr=osr, mode=GAMMA[mode],
                   bits=b)
        if o["ref_ready"] and q < k:
            q += 1
        hs.append(o["h"])
        if o["update"]:
            ups.append(cyc)
        if o["start"]:
            starts.append(cyc)
        assert not o["mode_clamped"]
        assert o["period_clamped"] == (cyc > 0 and period < max(lb, s))
    assert ups == [st + lb for st in starts if st + lb < len(hs)]
    assert all(np.diff(starts) == p)
    slot = p // s
    samples = np.vstack([np.zeros((1, n), dtype=np.int64), beats])
    h_ref, _, _ = modulate_bbit(samples, c, mode, b, osr)
    h_ref = h_ref.reshape(-1, s)
    assert len(ups) - 1 >= len(h_ref) == (k + 1) * osr
    for u, expected in zip(ups, h_ref, strict=False):
        per_clock = [expected[min(j // slot, s - 1)] for j in range(p)]
        assert hs[u:u + p] == per_clock


def test_period_and_mode_clamps():
    g = GeneratorModel(3, 16, max_bits=6)
    lb = g.long_latency
    assert lb == resolution_latency(3, 6)
    # b = 6 needs 64 clocks; period 30 is clamped to 64 and flagged
    out = run(g, 400, period=30, mode=1, bits=6)
    starts = np.flatnonzero(out["start"])
    assert (np.diff(starts) == 64).all()
    assert out["period_clamped"][1:].all() and not out["mode_clamped"].any()
    # bits 0 with a gamma mode acts as b = 1 (flagged); bits 9 > max_bits acts as 6 (flagged)
    for bits, b, step in ((0, 1, lb), (9, 6, 64), (15, 6, 64)):
        g.reset()
        out = run(g, 300, period=0, mode=2, bits=bits)
        assert (np.diff(np.flatnonzero(out["start"])) == step).all()
        assert out["mode_clamped"][1:].all() and out["mode_clamped"][0] == 0
        assert g.bits_lat == b
    # an illegal mode code acts as mdfqm (short updates), flagged
    for code in (5, 6, 7):
        g.reset()
        out = run(g, 100, period=0, mode=code, bits=3)
        assert (np.diff(np.flatnonzero(out["start"])) == g.latency).all()
        assert out["mode_clamped"][1:].all() and g.mode_lat == 0
    # mdfqm ignores bits: never flagged
    g.reset()
    out = run(g, 100, period=0, mode=0, bits=15)
    assert not out["mode_clamped"].any()


def test_switches_never_cut_a_layout():
    """mdfqm -> svpwm -> mdfqm -> mdfqm: presented at s + L, s + L_b, s + L_b (long: after a
    b-bit update), s + L; each layout lasts its whole period, the mdfqm state after the long
    one P - (L_b - L) clocks."""
    g = GeneratorModel(3, 16, max_bits=4)
    L, lb = g.latency, g.long_latency
    p = 40
    modes = [0, 1, 0, 0, 0]
    mode_in, starts, ups, hs = 0, [], [], []
    for cyc in range(len(modes) * p + lb + 2):
        k = cyc // p
        mode_in = modes[k] if k < len(modes) else 0
        o = g.step(period=p, mode=mode_in, bits=3, ref_valid=1, ref=(4000, -1000, -3000))
        if o["start"]:
            starts.append(cyc)
        if o["update"]:
            ups.append(cyc)
        hs.append(o["h"])
    assert starts[:5] == [0, p, 2 * p, 3 * p, 4 * p]
    assert ups[:5] == [L, p + lb, 2 * p + lb, 3 * p + L, 4 * p + L]
    # the layout of the svpwm update runs its whole period: P clocks from its presentation
    assert ups[2] - ups[1] == p
    assert ups[3] - ups[2] == p - (lb - L) >= L


def test_long_update_sync_threshold():
    g = GeneratorModel(3, 16, max_bits=4)
    lb = g.long_latency
    p = 3 * lb
    for hold in (lb - 2, lb - 1):
        g.reset()
        sync = np.zeros(3 * p, dtype=int)
        sync[hold] = 1
        out = g.simulate({"period": p, "mode": 1, "bits": 2, "sync_in": sync})
        starts = list(np.flatnonzero(out["start"]))
        assert starts[:2] == ([0, hold + 1] if hold + 1 >= lb else [0, p])


def test_zero_policy_after_a_layout_uses_its_last_slot():
    """h_prev of an mdfqm update after a layout is the layout's last slot."""
    g = GeneratorModel(3, 16, max_bits=4)
    lb = g.long_latency
    p = 2 * lb
    # a zero reference: svpwm b = 2 gives slots 0, 7, 7, 0 (the last slot all-off);
    # dpwm0 gives all-on in every slot (the top leg clamped on, zero reference: all legs on)
    for mode, last in ((1, 0b000), (2, 0b111)):
        g.reset()
        out = g.simulate({"cycles": 4 * p, "period": p, "zero_policy": FEWEST_TRANSITIONS,
                          "mode": np.array([mode] * p + [0] * 3 * p), "bits": 2})
        ups = np.flatnonzero(out["update"])
        assert ups[0] == lb and ups[1] == p + lb
        assert out["h"][ups[0] + p - 1] == last       # the last slot of the layout
        assert out["h"][ups[1]] == last               # mdfqm zero state: fewest transitions


def test_validation_messages():
    g = GeneratorModel(3, 16)
    with pytest.raises(ValueError, match="mode must be an unsigned 3-bit integer"):
        g.step(mode=8)
    with pytest.raises(ValueError, match="bits must be an unsigned 4-bit integer"):
        g.step(bits=16)
    with pytest.raises(TypeError, match="unexpected inputs"):
        g.step(modes=1)
    with pytest.raises(TypeError, match="unexpected inputs"):
        CoreModel().step(mode=1)
    with pytest.raises(ValueError, match=r"max_bits must be an integer in \[1, 12\]"):
        GeneratorModel(3, 16, max_bits=0)
    with pytest.raises(ValueError, match="long_latency must be an integer >= 2"):
        GeneratorModel(3, 16, long_latency=1)
    assert GeneratorModel(3, 16).long_latency == resolution_latency(3, 8)
    assert GeneratorModel(3, 16).latency == loop_latency(3)
