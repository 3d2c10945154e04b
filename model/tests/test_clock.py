"""Clock-level model: the timing rules of docs/contract.md's "Clock-level timing of the core"."""

import numpy as np
import pytest

from mdfqm_model.clock import CoreModel
from mdfqm_model.update import modulate
from mdfqm_spec.contract import FEWEST_TRANSITIONS, Contract, loop_latency, reference_latency

OUTPUTS6 = ("ref_ready", "sample", "h", "update", "saturated", "period_clamped")


def starts_of(model, cycles, **kw):
    """Run and return (outputs, cycles that were update starts) via trace_state."""
    out = model.simulate({"cycles": cycles, **kw}, trace_state=True)
    return out, np.flatnonzero(out["phase"] == 0)


def test_reset_state_outputs():
    m = CoreModel()
    o = m.step()
    assert {k: o[k] for k in OUTPUTS6} == {
        "ref_ready": 1,
        "sample": 1,
        "h": 0,
        "update": 0,
        "saturated": 0,
        "period_clamped": 0,
    }


@pytest.mark.parametrize(
    "phases,rule", [(3, "largest_duty"), (5, "exact_nearest"), (8, "largest_duty")]
)
@pytest.mark.parametrize("period", [None, 13])
def test_update_strobe_exactly_latency_after_each_start(phases, rule, period):
    m = CoreModel(phases, 16, rule)
    L = loop_latency(phases, rule)
    assert m.latency == L
    p = L if period is None else max(period, L)
    out, starts = starts_of(m, 10 * p + 3, period=p)
    assert (np.diff(starts) == p).all() and starts[0] == 0
    strobes = np.flatnonzero(out["update"])
    assert list(strobes) == [s + L for s in starts if s + L < len(out["update"])]


def test_h_changes_exactly_latency_after_start():
    c = Contract(3, 16)
    f = c.full
    m = CoreModel(3, 16)
    L = m.latency
    # load a reference that makes the first real update output state 001
    ref = (f, 0, 0)
    m.step(ref_valid=1, ref=ref, period=20)  # cycle 0: accepted, also update start 0 (held = 0)
    out = m.simulate({"cycles": 60, "period": 20})
    # starts at 0, 20, 40 (cycle numbers of the whole run); the tick at 20 uses the pending beat
    h = np.concatenate([[0], out["h"]])
    changes = np.flatnonzero(np.diff(h)) + 1
    assert list(changes) == [20 + L]
    assert h[20 + L] == 0b001


def test_period_clamping():
    m = CoreModel(3, 16)
    L = m.latency
    out, starts = starts_of(m, 5 * L, period=3)
    assert (np.diff(starts) == L).all()
    # registered: low in the first start cycle, high from the next cycle on
    assert out["period_clamped"][0] == 0 and (out["period_clamped"][1:] == 1).all()
    # period 0 is clamped too; period == L is not
    m.reset()
    out = m.simulate({"cycles": 3 * L, "period": L})
    assert not out["period_clamped"].any()
    m.reset()
    out = m.simulate({"cycles": 3, "period": 0})
    assert list(out["period_clamped"]) == [0, 1, 1]


def test_period_latched_at_update_start():
    m = CoreModel(3, 16)
    L = m.latency
    # period 12 during the first update, then 30 presented mid-update: the change takes effect
    # only at the next start
    per = np.full(100, 30)
    per[0] = 12
    out = m.simulate({"period": per}, trace_state=True)
    starts = np.flatnonzero(out["phase"] == 0)
    assert list(starts[:4]) == [0, 12, 42, 72]
    # a mid-update change of period does not move the current update's end
    m.reset()
    per = np.full(60, 20)
    per[5] = 9  # not a start cycle: ignored
    out = m.simulate({"period": per}, trace_state=True)
    assert list(np.flatnonzero(out["phase"] == 0)[:3]) == [0, 20, 40]
    assert L <= 12


@pytest.mark.parametrize("osr", [0, 1, 2, 4, 7])
def test_osr_tick_spacing(osr):
    m = CoreModel(3, 16)
    p = 11
    out, starts = starts_of(m, 40 * p, period=p, osr=osr)
    ticks = np.flatnonzero(out["sample"])
    assert set(ticks) <= set(starts)
    assert ticks[0] == 0
    assert (np.diff(ticks) == max(osr, 1) * p).all()


def test_osr_change_applies_at_each_start():
    # sub <- 0 if sub + 1 >= osr else sub + 1, with the osr input of that start
    m = CoreModel(3, 16)
    p = m.latency
    osr = np.full(20 * p, 4)
    osr[3 * p :] = 2  # from the 4th start on (sub == 3 there) osr = 2 -> sub + 1 >= 2 -> 0
    out, _starts = starts_of(m, 20 * p, period=p, osr=osr)
    ticks = list(np.flatnonzero(out["sample"]) // p)  # in units of updates
    assert ticks[:4] == [0, 4, 6, 8]


def test_ready_handshake_timing():
    m = CoreModel(3, 16)
    p = 10
    osr = 3
    k = reference_latency(3)
    ready, accepted = [], []
    for cyc in range(200):
        o = m.step(ref_valid=1, ref=(cyc, -cyc, 0), period=p, osr=osr)
        ready.append(o["ref_ready"])
        if o["ref_ready"]:
            accepted.append(cyc)
    ticks = [t for t in range(200) if t % (p * osr) == 0]
    # first beat accepted at 0; each following one in the cycle of the tick whose previous cycle
    # handed the pending beat over (the ticks at 30, 60, ... all follow a + K)
    assert accepted == [0, *ticks[1:]]
    for a in accepted:
        assert ready[a] == 1
        # low from a + 1 (busy, then full) until the consuming tick, the first at a + K + 1 or later
        nxt = [t for t in ticks if t >= a + k + 1]
        end = nxt[0] if nxt else 200
        assert all(r == 0 for r in ready[a + 1 : end])
        assert end == 200 or ready[end] == 1


def test_a_beat_is_used_by_the_first_tick_one_cycle_after_it_is_pending():
    c = Contract(3, 16)
    f = c.full
    L = loop_latency(3)
    k = reference_latency(3)
    p = L
    assert p > k, "the accept cycles below must be inside the first update"
    ref = (f, 0, 0)

    def run(accepted_at, **kwargs):
        m = CoreModel(3, 16)
        valid = np.zeros(5 * p, dtype=int)
        valid[accepted_at] = 1
        refs = np.zeros((5 * p, 3), dtype=int)
        refs[accepted_at] = ref
        return m.simulate({"ref_valid": valid, "ref": refs, "period": p}, **kwargs)

    # accepted at a = p - K: pending from cycle p, the tick itself: that update uses held (0),
    # the tick at 2p uses the beat
    out = run(p - k, trace_state=True)
    assert out["full"][p - 1] == 0 and out["full"][p] == 1
    assert out["h"][p + L] == 0 and out["h"][2 * p + L] == 0b001
    # accepted at a = p - K - 1: pending in cycle p - 1, the cycle before the tick: handed over
    out = run(p - k - 1, trace_state=True)
    assert out["full"][p - 1] == 1 and out["full"][p] == 0
    assert out["ref_ready"][p - 1] == 0 and out["ref_ready"][p] == 1
    assert out["h"][p + L] == 0b001


def test_reset_mid_run():
    m = CoreModel(3, 16)
    f = m.contract.full
    L = m.latency
    p = L + 4
    for _ in range(3 * p):
        m.step(ref_valid=1, ref=(f // 2, -f // 2, 0), period=p)
    # pick a cycle with an update in flight and a beat pending
    while m.inflight is None:
        m.step(ref_valid=1, ref=(f // 2, -f // 2, 0), period=p)
    before = m.outputs()
    o = m.step(rst=1, ref_valid=1, ref=(f, f, f), period=p)
    assert o == before  # outputs of the rst cycle come from the state before
    after = [m.step(period=p) for _ in range(2 * p)]
    assert {k: after[0][k] for k in OUTPUTS6} == {
        "ref_ready": 1,
        "sample": 1,
        "h": 0,
        "update": 0,
        "saturated": 0,
        "period_clamped": 0,
    }
    # the in-flight update was discarded: the first strobe is L after the post-reset start
    strobes = [i for i, a in enumerate(after) if a["update"]]
    assert strobes[0] == L
    assert m.held == (0, 0, 0)  # the beat presented with rst was not accepted
    assert all(a["h"] == 0 for a in after)  # held = 0 -> zero state


@pytest.mark.parametrize(
    "phases,rule,policy,osr",
    [
        (3, "largest_duty", 0, 4),
        (3, "largest_duty", FEWEST_TRANSITIONS, 2),
        (4, "exact_nearest", FEWEST_TRANSITIONS, 1),
        (6, "largest_duty", 0, 3),
    ],
)
def test_clock_matches_per_update_model(phases, rule, policy, osr, rng):
    """Drive a ready-respecting stream; the update results equal modulate() on the beats."""
    c = Contract(phases, 14)
    k = 25
    beats = rng.integers(-c.full, c.full, size=(k, phases))
    m = CoreModel(phases, 14, rule)
    # a beat taken at a tick is pending in time for the next one when P * osr >= K + 1
    shortest = max(m.latency, -(-(reference_latency(phases) + 1) // osr))
    p = shortest + int(rng.integers(0, 4))
    q = 0
    hs, sats = [], []
    for _ in range((k + 2) * osr * p + m.latency):
        ref = beats[q] if q < k else beats[-1]
        o = m.step(ref_valid=int(q < k), ref=ref, period=p, osr=osr, zero_policy=policy)
        if o["ref_ready"] and q < k:
            q += 1
        if o["update"]:
            hs.append(o["h"])
            sats.append(o["saturated"])
    # tick 0 uses held = 0; tick j >= 1 uses beat j - 1 (a beat is always pending in time)
    samples = np.vstack([np.zeros((1, phases), dtype=np.int64), beats])
    h_ref, _x_ref, s_ref = modulate(samples, c, rule, policy, osr)
    assert len(hs) >= (k + 1) * osr
    nn = (k + 1) * osr
    hs, sats = hs[:nn], sats[:nn]
    assert hs == list(h_ref[:nn]) and sats == list(s_ref[:nn].astype(int))
    assert len(h_ref) == nn


def test_zero_policy_latched_at_start():
    m = CoreModel(3, 16)
    f = m.contract.full
    L = m.latency
    p = 2 * L
    c = 8 * p
    valid = np.zeros(c, dtype=int)
    refs = np.zeros((c, 3), dtype=int)
    valid[0] = 1
    refs[0] = (f, f, 0)  # R = (F, F, -2F): exactly the state 011, X stays 0
    valid[p + 1] = 1  # a zero beat right after the tick at p consumed the first one
    pol = np.zeros(c, dtype=int)
    pol[2 * p] = FEWEST_TRANSITIONS  # only in start cycles does the input matter
    pol[2 * p + 1 : 3 * p] = FEWEST_TRANSITIONS - 1
    pol[3 * p + 1 : 4 * p] = FEWEST_TRANSITIONS  # not start cycles: ignored
    pol[4 * p] = FEWEST_TRANSITIONS
    out = m.simulate({"ref_valid": valid, "ref": refs, "period": p, "zero_policy": pol})
    assert out["ref_ready"][p + 1] == 1
    assert out["h"][p + L] == 0b011
    assert out["h"][2 * p + L] == 0b111  # policy 1 at start 2p, h_prev = 011 -> all on
    assert out["h"][3 * p + L] == 0b000  # policy 0 at start 3p -> all off
    assert out["h"][4 * p + L] == 0b000  # policy 1, h_prev = 000 -> all off


def test_saturated_flag_visible_with_update():
    c = Contract(3, 16)
    m = CoreModel(3, 16)
    L = m.latency
    worst = (c.code_max, c.code_min, c.code_min)
    out = m.simulate({"ref_valid": 1, "ref": worst, "period": L, "cycles": 40 * L})
    upd = np.flatnonzero(out["update"])
    assert out["saturated"].any()
    # the flag only changes at update strobes
    changes = np.flatnonzero(np.diff(out["saturated"])) + 1
    assert set(changes) <= set(upd)


def test_validation_messages():
    m = CoreModel(3, 16)
    with pytest.raises(ValueError, match="period must be an unsigned 16-bit"):
        m.step(period=1 << 16)
    with pytest.raises(ValueError, match="period must be an unsigned 16-bit"):
        m.step(period=-1)
    with pytest.raises(ValueError, match="osr must be an unsigned 8-bit"):
        m.step(osr=256)
    with pytest.raises(ValueError, match="zero_policy must be one of"):
        m.step(zero_policy=3)
    with pytest.raises(ValueError, match="rst must be 0 or 1"):
        m.step(rst=2)
    with pytest.raises(ValueError, match="ref entries must be 16-bit codes"):
        m.step(ref=(1 << 15, 0, 0))
    with pytest.raises(ValueError, match="ref must have 3 entries"):
        m.step(ref=(0, 0))
    with pytest.raises(ValueError, match="rule must be one of"):
        CoreModel(3, 16, "fast")
    with pytest.raises(ValueError, match="latency must be an integer >= 1"):
        CoreModel(3, 16, latency=0)
    with pytest.raises(ValueError, match="width must be an integer"):
        CoreModel(3, 4)
    with pytest.raises(ValueError, match="differ in length"):
        m.simulate({"rst": np.zeros(3), "ref_valid": np.zeros(4)})
    with pytest.raises(ValueError, match="unknown stimulus"):
        m.simulate({"reff": np.zeros(3)})


def test_start_output_marks_update_starts():
    m = CoreModel(3, 16)
    out = m.simulate({"cycles": 100, "period": 13}, trace_state=True)
    assert (out["start"] == (out["phase"] == 0)).all()


def test_sync_in_ignored_before_latency_and_restarts_after():
    L = loop_latency(3)
    p = 3 * L
    for hold in range(1, p):  # sync_in high only in the cycle with phase == hold (first update)
        m = CoreModel(3, 16)
        sync = np.zeros(3 * p, dtype=int)
        sync[hold] = 1
        out = m.simulate({"period": p, "sync_in": sync})
        starts = list(np.flatnonzero(out["start"]))
        if hold + 1 >= L:  # the update in flight has committed by the next cycle
            assert starts[:3] == [0, hold + 1, hold + 1 + p]
        else:  # ignored: it can never cut an update short
            assert starts[:3] == [0, p, 2 * p]
        # every update still sees the previous update's result
        strobes = list(np.flatnonzero(out["update"]))
        assert all(s + L in strobes for s in starts if s + L < 3 * p)


def test_sync_in_aligns_two_instances():
    L = loop_latency(3)
    a, b = CoreModel(3, 16), CoreModel(3, 16)
    pa, pb = 2 * L + 3, 5 * L  # b's own period is longer: a's start drives it
    a_starts, b_starts = [], []
    for cyc in range(40 * pa):
        oa = a.step(period=pa)
        ob = b.step(period=pb, sync_in=oa["start"])  # a's start wired to b's sync_in
        if oa["start"]:
            a_starts.append(cyc)
        if ob["start"]:
            b_starts.append(cyc)
    # a's first start (cycle 0) falls in b's first cycles and is ignored (phase + 1 < L); from
    # then on b starts exactly one clock after each start of a
    assert a_starts[:2] == [0, pa] and b_starts[0] == 0
    assert b_starts[1:] == [s + 1 for s in a_starts[1:]][: len(b_starts) - 1]
    assert len(b_starts) >= len(a_starts) - 1


def test_sync_in_validation():
    m = CoreModel(3, 16)
    with pytest.raises(ValueError, match="sync_in must be 0 or 1"):
        m.step(sync_in=2)
