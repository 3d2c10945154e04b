"""The b-bit generator: slots, the quantum bound, SVPWM / DPWM layouts, MDFQM as b = 0."""

import itertools

import numpy as np
import pytest

from mdfqm_model.bbit import (
    bbit_update,
    centred_slots,
    ideal_svpwm_edges,
    modulate_bbit,
    quantised_instants,
)
from mdfqm_model.update import modulate, popcount, remove_common_mode, sort1
from mdfqm_spec.contract import FEWEST_TRANSITIONS, Contract

from .test_update import linear_amplitude, sine_refs

GAMMA_MODES = ["svpwm", "dpwm0", "dpwm1", "dpwm"]


def test_hand_case_centred_svpwm():
    c = Contract(3, 16)
    f = c.full
    r = remove_common_mode([f // 4, 0, -f // 4], 3)
    assert r == [3 * f // 4, 0, -3 * f // 4]
    res = bbit_update([0, 0, 0], r, c, "svpwm", 3)
    # C_1 S / NF = 2, C_2 S / NF = 4, C_3 S / NF = 6 exactly
    assert res.q == (0, 2, 4, 6, 8)
    assert res.on_slots == (6, 4, 2)
    assert res.slots == (0b000, 0b001, 0b011, 0b111, 0b111, 0b011, 0b001, 0b000)
    assert res.x_next == (0, 0, 0) and not res.saturated


def test_hand_case_round_half_up():
    c = Contract(3, 16)
    f = c.full
    # R = (F, 0, -F): C_1 = (3F - 2F) / 2 = F/2 -> C_1 S / NF = (F/2) 4 / 3F = 2/3 -> q_1 = 1;
    # C_2 = F/2 + F -> 2 -> q_2 = 2; C_3 = F/2 + 2F -> 10/3 -> q_3 = 3
    rho, _ = sort1([f, 0, -f])
    assert quantised_instants(rho, 1, 4, c) == [0, 1, 2, 3, 4]
    # exactly half a slot rounds up: R = (3F/4, 0, -3F/4), S = 2: C_1 = (3F - 3F/2) / 2 = 3F/4
    # -> C_1 S / NF = 1/2 -> 1; C_2 = 3F/2 -> 1; C_3 = 9F/4 -> 3/2 -> 2
    rho, _ = sort1([3 * f // 4, 0, -3 * f // 4])
    assert quantised_instants(rho, 1, 2, c) == [0, 1, 1, 2, 2]


def test_centred_slots_nesting():
    s = centred_slots([5, 2, 0, 8], 8)
    assert s[0] == 0b1000 and s[7] == 0b1000
    for i, n in enumerate([5, 2, 0, 8]):
        assert sum((v >> i) & 1 for v in s) == n


@pytest.mark.parametrize("mode", GAMMA_MODES)
@pytest.mark.parametrize("n", [3, 4, 6])
def test_slot_bookkeeping_and_linear_bound(mode, n, rng):
    c = Contract(n, 16)
    b = int(rng.integers(1, 9))
    s = 1 << b
    amp = linear_amplitude(n) * rng.uniform(0.05, 0.95)
    refs = sine_refs(c, 150, amp, rng.uniform(0.5, 3), rng.uniform(-0.3, 0.3))
    x = (0,) * n
    bound = (n - 1) * c.full // s
    for row in refs.tolist():
        r = remove_common_mode(row, n)
        res = bbit_update(x, r, c, mode, b)
        q = res.q
        assert q[0] == 0 and q[-1] == s and all(a <= b_ for a, b_ in itertools.pairwise(q))
        assert sorted(res.on_slots, reverse=True) == [res.on_slots[p] for p in res.perm]
        # every slot holds a staircase state of this update's permutation
        for h in res.slots:
            k = popcount(h)
            assert h == sum(1 << res.perm[p] for p in range(k))
        # each leg switches at most twice inside the period
        for i in range(n):
            bits = [(h >> i) & 1 for h in res.slots]
            assert sum(a != b_ for a, b_ in itertools.pairwise(bits)) <= 2
        assert sum(res.x_next) == 0 and not res.saturated
        assert max(abs(v) for v in res.x_next) <= bound, (res.x_next, bound)
        x = res.x_next


@pytest.mark.parametrize("mode", GAMMA_MODES)
def test_mean_output_equals_reference_within_one_quantum(mode, rng):
    n = 3
    c = Contract(n, 16)
    for b in (1, 2, 4, 6):
        s = 1 << b
        amp = linear_amplitude(n) * rng.uniform(0.1, 0.95)
        refs = sine_refs(c, 200, amp, 1.0, rng.uniform(-0.2, 0.2))
        h_slots, x, _ = modulate_bbit(refs, c, mode, b)
        on = np.array([[(h >> i) & 1 for i in range(n)] for h in h_slots]).reshape(-1, s, n)
        v_mean = on.mean(axis=1)  # pole-voltage duty of each leg per update, in Vdc
        v_mean = v_mean - v_mean.mean(axis=1, keepdims=True)  # phase voltage
        ref_v = refs / c.full
        ref_v = ref_v - ref_v.mean(axis=1, keepdims=True)
        # per update: mean output within one quantum (1/S Vdc) of the reference plus the carried
        # error; over the run: within one quantum of the reference, and -> 0 as 1/K
        x_v = x / c.unit
        x_prev = np.vstack([np.zeros((1, n)), x_v[:-1]])
        assert np.abs(v_mean - (ref_v + x_prev)).max() < 1.0 / s
        assert np.abs(v_mean - ref_v).max() < 2.0 / s
        assert np.abs(v_mean.mean(axis=0) - ref_v.mean(axis=0)).max() <= 1.0 / s / len(refs)


def test_dpwm_clamps():
    c = Contract(3, 16)
    f = c.full
    rows = [[f // 3, -f // 5, 0], [-f // 3, f // 5, 0], [f // 7, f // 9, -f // 4]]
    for row in rows:
        r = remove_common_mode(row, 3)
        rho, perm = sort1(r)
        top, bottom = perm[0], perm[-1]
        r0 = bbit_update([0, 0, 0], r, c, "dpwm0", 5)
        assert all((h >> top) & 1 for h in r0.slots)
        r1 = bbit_update([0, 0, 0], r, c, "dpwm1", 5)
        assert not any((h >> bottom) & 1 for h in r1.slots)
        rd = bbit_update([0, 0, 0], r, c, "dpwm", 5)
        if rho[0] >= -rho[-1]:
            assert rd.gamma2 == 0 and rd.on_slots[top] == 32
        else:
            assert rd.gamma2 == 2 and rd.on_slots[bottom] == 0


def test_dpwm_switches_two_thirds_of_svpwm():
    c = Contract(3, 16)
    refs = sine_refs(c, 600, 0.5, 5.0)

    def transitions(h):
        hh = np.concatenate([[0], h])
        return sum(popcount(int(v)) for v in hh[1:] ^ hh[:-1])

    ts = transitions(modulate_bbit(refs, c, "svpwm", 6)[0])
    td = transitions(modulate_bbit(refs, c, "dpwm", 6)[0])
    assert ts == pytest.approx(6 * 600, rel=0.01)
    assert td == pytest.approx(4 * 600, rel=0.03)


@pytest.mark.parametrize("policy", [0, FEWEST_TRANSITIONS])
def test_mdfqm_is_b0(policy):
    c = Contract(4, 16)
    refs = sine_refs(c, 100, 0.4, 2.0)
    h1, x1, s1 = modulate(refs, c, "exact_nearest", policy, osr=3)
    h2, x2, s2 = modulate_bbit(refs, c, "mdfqm", 0, 3, "exact_nearest", policy)
    assert (h1 == h2).all() and (x1 == x2).all() and (s1 == s2).all()


def test_large_b_approaches_ideal_svpwm():
    c = Contract(3, 16)
    refs = sine_refs(c, 50, 0.55, 1.0)
    b = 10
    s = 1 << b
    h, _, _ = modulate_bbit(refs, c, "svpwm", b)
    on = np.array([[(v >> i) & 1 for i in range(3)] for v in h]).reshape(-1, s, 3).mean(axis=1)
    ideal = ideal_svpwm_edges(refs / c.full)
    assert np.abs(on - ideal).max() < 2.0 / s


def test_overmodulation_bounded(rng):
    c = Contract(3, 16)
    refs = sine_refs(c, 300, 2 * linear_amplitude(3), 2.0, 0.3)
    for mode in GAMMA_MODES:
        _, x, sat = modulate_bbit(refs, c, mode, 4)
        assert (x.sum(axis=1) == 0).all() and x.min() >= c.x_min and x.max() <= c.x_max
        assert sat.any()


def test_validation_messages():
    c = Contract(3, 16)
    with pytest.raises(ValueError, match="mode must be one of"):
        bbit_update([0] * 3, [0] * 3, c, "spwm", 4)
    with pytest.raises(ValueError, match="b = 0 generator"):
        bbit_update([0] * 3, [0] * 3, c, "mdfqm", 3)
    with pytest.raises(ValueError, match=r"b must be in \[1, 14\]"):
        bbit_update([0] * 3, [0] * 3, c, "svpwm", 15)
    with pytest.raises(ValueError, match=r"b must be in \[1, 14\]"):
        bbit_update([0] * 3, [0] * 3, c, "svpwm", 0)
    with pytest.raises(ValueError, match="sum to 0"):
        bbit_update([0] * 3, [1, 0, 0], c, "svpwm", 4)
