"""Properties of the per-update algorithm (expected values from brute force or by hand)."""

import itertools

import numpy as np
import pytest

from mdfqm_model.update import (
    candidates,
    decode,
    feedback,
    mdfqm_update,
    modulate,
    modulate_batch,
    popcount,
    remove_common_mode,
    select,
    sort1,
)
from mdfqm_spec.contract import ALL_OFF, FEWEST_TRANSITIONS, Contract, loop_latency


def brute_force_distances(t, contract):
    """``||T - U(h)||^2`` for every one of the 2^N states (index = bitmask)."""
    return [
        sum((ti - ui) ** 2 for ti, ui in zip(t, feedback(h, contract), strict=True))
        for h in range(1 << contract.phases)
    ]


def random_t(rng, contract, scale):
    """A random T with sum 0, entries spread over +-scale Vdc (N-scaled domain)."""
    n = contract.phases
    t = rng.integers(-int(scale * contract.unit), int(scale * contract.unit) + 1, size=n)
    t = n * t - t.sum()  # remove the common mode exactly
    return [int(v) for v in t]


def test_remove_common_mode_hand():
    assert remove_common_mode([1, 2, 3], 3) == [-3, 0, 3]
    assert remove_common_mode([5, 5, 5, 5], 4) == [0, 0, 0, 0]
    assert sum(remove_common_mode([7, -2, 11, 0, 3], 5)) == 0


def test_sort1_stable_descending():
    rho, perm = sort1([3, 5, 3, 5])
    assert rho == [5, 5, 3, 3]
    assert perm == [1, 3, 0, 2]  # equal values keep leg order


def test_select_smallest_index_of_max():
    assert select([1, 4, 4, 2]) == 1
    assert select([4, 4, 4]) == 0
    assert select([-3, -1, -2]) == 1


def test_feedback_hand():
    c = Contract(3, 16)
    f = c.full
    assert feedback(0b000, c) == [0, 0, 0]
    assert feedback(0b111, c) == [0, 0, 0]
    assert feedback(0b001, c) == [2 * f, -f, -f]
    assert feedback(0b011, c) == [f, f, -2 * f]


def test_hand_case_n3():
    # c = (FULL, 0, 0): R = (2F, -F, -F) is exactly the state 100 -> X' = 0.
    c = Contract(3, 16)
    f = c.full
    r = remove_common_mode([f, 0, 0], 3)
    assert r == [2 * f, -f, -f]
    for rule in ("largest_duty", "exact_nearest"):
        res = mdfqm_update([0, 0, 0], r, 0, c, rule)
        assert res.h == 0b001 and res.j == 1
        assert res.x_next == (0, 0, 0) and not res.saturated
    # largest-duty values by hand: d0 = 3F - 3F = 0, d1 = 3F, d2 = 0
    assert candidates([2 * f, -f, -f], c, "largest_duty") == [0, 3 * f, 0]
    # exact: S1 = 2 * 2F - F*1*2 = 2F, S2 = 2 * F - F*2*1 = 0
    assert candidates([2 * f, -f, -f], c, "exact_nearest") == [0, 2 * f, 0]


def test_zero_reference_ties_go_to_zero_class():
    c = Contract(4, 16)
    for rule in ("largest_duty", "exact_nearest"):
        res = mdfqm_update([0] * 4, [0] * 4, 0, c, rule, ALL_OFF)
        assert res.j == 0 and res.h == 0 and res.perm == (0, 1, 2, 3)


def test_zero_policy_hand():
    perm = [2, 0, 1]
    assert decode(perm, 0, ALL_OFF, 0b111, 3) == 0
    assert decode(perm, 0, FEWEST_TRANSITIONS, 0b011, 3) == 0b111  # 2 of 3 on -> all on
    assert decode(perm, 0, FEWEST_TRANSITIONS, 0b001, 3) == 0  # 1 of 3 on -> all off
    assert decode([0, 1, 2, 3], 0, FEWEST_TRANSITIONS, 0b0011, 4) == 0  # tie -> all off
    assert decode(perm, 1, FEWEST_TRANSITIONS, 0b111, 3) == 0b100
    assert decode(perm, 2, ALL_OFF, 0, 3) == 0b101


@pytest.mark.parametrize("n", range(3, 9))
def test_exact_nearest_equals_brute_force(n, rng):
    c = Contract(n, 12 if n < 8 else 13)
    for trial in range(300):
        scale = [0.05, 0.3, 0.6, 1.5][trial % 4]
        t = random_t(rng, c, scale)
        if trial % 7 == 0:  # force ties
            t = [t[0]] * (n // 2) + [t[1]] * (n - n // 2)
            t = [n * v - sum(t) for v in t]
        rho, perm = sort1(t)
        j = select(candidates(rho, c, "exact_nearest"))
        dist = brute_force_distances(t, c)
        dmin = min(dist)
        h = decode(perm, j, ALL_OFF, 0, n)
        assert dist[h] == dmin, (t, j)
        # the tie-break: the smallest class (popcount, all-on counted as 0) among the minimisers
        classes = {popcount(s) % n for s in range(1 << n) if dist[s] == dmin}
        assert j == min(classes)
        # the score identity ||T - U||^2 = ||T||^2 - N FULL S_k, checked for every staircase
        s = candidates(rho, c, "exact_nearest")
        tt = sum(v * v for v in t)
        for k in range(n):
            hk = decode(perm, k, ALL_OFF, 0, n)
            assert dist[hk] == tt - n * c.full * s[k]


def test_n3_largest_duty_equals_exact_nearest_random(rng):
    c = Contract(3, 16)
    for trial in range(3000):
        t = random_t(rng, c, [0.02, 0.4, 1.0, 2.0][trial % 4])
        rho, _ = sort1(t)
        assert select(candidates(rho, c, "largest_duty")) == select(
            candidates(rho, c, "exact_nearest")
        ), t


def test_n3_largest_duty_equals_exact_nearest_exhaustive_grid():
    # every T on a grid fine enough to hit all boundaries (ties) of both rules
    c = Contract(3, 8)  # FULL = 64, N FULL = 192
    f = c.full
    for a in range(-2 * 3 * f, 2 * 3 * f + 1, 8):
        for b in range(-2 * 3 * f, 2 * 3 * f + 1, 8):
            t = [3 * a, 3 * b, -3 * a - 3 * b]
            rho, _ = sort1(t)
            jl = select(candidates(rho, c, "largest_duty"))
            je = select(candidates(rho, c, "exact_nearest"))
            assert jl == je, t


def test_n_gt_3_rules_differ_somewhere():
    """The design note says they differ for N > 3; find a witness by search (not a claim)."""
    c = Contract(5, 12)
    rng = np.random.default_rng(1)
    found = False
    for _ in range(5000):
        t = random_t(rng, c, 0.5)
        rho, _ = sort1(t)
        if select(candidates(rho, c, "largest_duty")) != select(
            candidates(rho, c, "exact_nearest")
        ):
            found = True
            break
    assert found


def sine_refs(contract, k, amp_vdc, cycles, common_mode_vdc=0.0, phase0=0.0):
    """K x N codes of a balanced N-phase sine, phase amplitude ``amp_vdc`` (Vdc units)."""
    n = contract.phases
    ang = 2 * np.pi * cycles * np.arange(k) / k + phase0
    shifts = 2 * np.pi * np.arange(n) / n
    v = amp_vdc * np.cos(ang[:, None] - shifts[None, :]) + common_mode_vdc
    codes = np.round(v * contract.full).astype(np.int64)
    return np.clip(codes, contract.code_min, contract.code_max)


def linear_amplitude(n):
    """Largest phase amplitude (Vdc) of a balanced N-phase sine with max - min <= 1 Vdc."""
    ang = np.linspace(0, 2 * np.pi, 20001)
    shifts = 2 * np.pi * np.arange(n) / n
    v = np.cos(ang[:, None] - shifts[None, :])
    return 1.0 / (v.max(axis=1) - v.min(axis=1)).max()


@pytest.mark.parametrize("n", [3, 4, 5, 6, 7])
@pytest.mark.parametrize("rule", ["largest_duty", "exact_nearest"])
def test_sum_zero_and_bound_in_linear_range(n, rule, rng):
    c = Contract(n, 16)
    amp = linear_amplitude(n) * rng.uniform(0.05, 0.999)
    cm = rng.uniform(-0.4, 0.4)
    refs = sine_refs(c, 600, amp, rng.uniform(1, 6), cm, rng.uniform(0, 2 * np.pi))
    for policy in (ALL_OFF, FEWEST_TRANSITIONS):
        _h, x, sat = modulate(refs, c, rule, policy, osr=int(rng.integers(1, 5)))
        assert (x.sum(axis=1) == 0).all()
        assert not sat.any(), "the anti-windup bound must never be reached in the linear range"
        if rule == "exact_nearest":  # the nearest-state loop keeps |X_i| within one Vdc
            assert np.abs(x).max() <= c.unit


def test_largest_duty_n16_outgrows_the_bound_so_the_contract_refuses_it():
    """The finding behind contract.LARGEST_DUTY_MAX_PHASES: at N = 16 the largest-duty loop
    saturates inside the linear range, so the rule is refused there."""
    c = Contract(16, 16)
    refs = sine_refs(c, 2000, 0.97 * linear_amplitude(16), 3.0, 0.0, 0.3)
    _, _, sat = modulate_batch(refs[None], c, "largest_duty", ALL_OFF, 1)
    assert sat.any()
    with pytest.raises(ValueError, match="use 'exact_nearest' for 16 phases"):
        loop_latency(16, "largest_duty")
    loop_latency(12, "largest_duty")


def test_largest_duty_n12_linear_range_never_saturates():
    c = Contract(12, 16)
    refs = sine_refs(c, 2000, 0.999 * linear_amplitude(12), 3.0, 0.0, 0.3)
    _, _, sat = modulate_batch(refs[None], c, "largest_duty", ALL_OFF, 1)
    assert not sat.any()


def test_exact_nearest_n16_linear_range_never_saturates():
    c = Contract(16, 16)
    refs = sine_refs(c, 2000, 0.999 * linear_amplitude(16), 3.0, 0.0, 0.3)
    _, x, sat = modulate_batch(refs[None], c, "exact_nearest", ALL_OFF, 1)
    assert not sat.any() and np.abs(x).max() <= c.unit


@pytest.mark.parametrize("n", [3, 5, 8])
@pytest.mark.parametrize("rule", ["largest_duty", "exact_nearest"])
def test_bound_holds_in_overmodulation_with_common_mode(n, rule, rng):
    c = Contract(n, 16)
    amp = 2.0 * linear_amplitude(n)  # twice the linear range
    cm = rng.uniform(-0.5, 0.5)
    refs = sine_refs(c, 800, amp, 3.0, cm)
    assert refs.min() > c.code_min and refs.max() < c.code_max  # no input clipping
    _h, x, sat = modulate(refs, c, rule, FEWEST_TRANSITIONS, osr=2)
    assert (x.sum(axis=1) == 0).all()
    assert x.min() >= c.x_min and x.max() <= c.x_max
    assert sat.any()  # the hold does fire out there
    # a constant reference far outside the range (worst case: the biggest codes)
    worst = np.tile([c.code_max] + [c.code_min] * (n - 1), (200, 1))
    _h, x, sat = modulate(worst, c, rule, ALL_OFF)
    assert (x.sum(axis=1) == 0).all() and x.min() >= c.x_min and x.max() <= c.x_max


def test_common_mode_offset_does_not_change_output(rng):
    c = Contract(3, 16)
    refs = sine_refs(c, 300, 0.5, 2.0)
    off = refs + int(0.7 * c.full)
    h0, x0, _ = modulate(refs, c, osr=4)
    h1, x1, _ = modulate(off, c, osr=4)
    assert (h0 == h1).all() and (x0 == x1).all()


def test_saturation_holds_integrator():
    c = Contract(3, 8)
    x = [c.x_max - 10, -(c.x_max - 10) // 2, 0]
    x[2] = -x[0] - x[1]
    r = remove_common_mode([c.code_max, c.code_min, c.code_min], 3)
    res = mdfqm_update(x, r, 0, c)
    t = [a + b for a, b in zip(x, r, strict=True)]
    u = feedback(res.h, c)
    outside = any(not c.x_min <= ti - ui <= c.x_max for ti, ui in zip(t, u, strict=True))
    assert res.saturated == outside
    if outside:
        assert res.x_next == tuple(x)
    assert res.h == 0b001  # the nearest state is still output


def test_identical_inputs_identical_outputs(rng):
    c = Contract(6, 16)
    refs = rng.integers(-c.full, c.full, size=(50, 6))
    refs[10:20] = 0  # all ties
    refs[20:30] = refs[20:30, :1]  # all-equal rows: ties everywhere
    for rule in ("largest_duty", "exact_nearest"):
        a = modulate(refs, c, rule, FEWEST_TRANSITIONS, osr=3)
        b = modulate(refs.copy(), c, rule, FEWEST_TRANSITIONS, osr=3)
        for u, v in zip(a, b, strict=True):
            assert (u == v).all()


@pytest.mark.parametrize("n", [3, 4, 7])
@pytest.mark.parametrize("rule", ["largest_duty", "exact_nearest"])
@pytest.mark.parametrize("policy", [ALL_OFF, FEWEST_TRANSITIONS])
def test_modulate_batch_equals_modulate(n, rule, policy, rng):
    c = Contract(n, 14)
    refs = np.stack(
        [sine_refs(c, 120, a, 2.0, cm) for a, cm in ((0.2, 0.0), (0.45, 0.1), (1.1, -0.3))]
    )
    refs[0, :10] = 0  # ties
    hb, xb, sb = modulate_batch(refs, c, rule, policy, osr=2)
    for i in range(refs.shape[0]):
        h, x, s = modulate(refs[i], c, rule, policy, osr=2)
        assert (hb[i] == h).all() and (xb[i] == x).all() and (sb[i] == s).all()


def test_fewest_transitions_never_more_switching(rng):
    c = Contract(3, 16)
    refs = sine_refs(c, 600, 0.2, 3.0)
    counts = []
    for policy in (ALL_OFF, FEWEST_TRANSITIONS):
        h, _, _ = modulate(refs, c, "largest_duty", policy, osr=4)
        hh = np.concatenate([[0], h])
        counts.append(sum(popcount(int(v)) for v in hh[1:] ^ hh[:-1]))
    assert counts[1] < counts[0]


def test_validation_messages():
    c = Contract(3, 16)
    with pytest.raises(ValueError, match="rule must be one of"):
        candidates([0, 0, 0], c, "nearest")
    with pytest.raises(ValueError, match="zero_policy must be one of"):
        decode([0, 1, 2], 0, 2, 0, 3)
    with pytest.raises(ValueError, match="sum 0"):
        mdfqm_update([0, 0, 0], [1, 0, 0], 0, c)
    with pytest.raises(ValueError, match="x must sum to 0"):
        mdfqm_update([1, 0, 0], [0, 0, 0], 0, c)
    with pytest.raises(ValueError, match="one per phase"):
        remove_common_mode([1, 2], 3)
    with pytest.raises(ValueError, match="integers"):
        remove_common_mode([1.5, 2, 3], 3)
    with pytest.raises(ValueError, match="3-bit mask"):
        mdfqm_update([0, 0, 0], [0, 0, 0], 8, c)
    with pytest.raises(ValueError, match="osr must be an integer >= 1"):
        modulate(np.zeros((2, 3), dtype=int), c, osr=0)
    with pytest.raises(ValueError, match="K x 3"):
        modulate(np.zeros((2, 4), dtype=int), c)
    with pytest.raises(ValueError, match="16-bit codes"):
        modulate(np.full((2, 3), 1 << 15), c)
    with pytest.raises(ValueError, match="phases must be an integer >= 3"):
        Contract(2, 16)
    with pytest.raises(ValueError, match="width must be an integer"):
        Contract(3, 40)


def test_all_states_reachable_n4():
    """Every non-zero staircase state is produced for some T (sanity of decode + perm)."""
    c = Contract(4, 12)
    seen = set()
    for t in itertools.product(range(-2, 3), repeat=4):
        t = [4 * v * c.full // 2 - sum(t) * c.full // 2 for v in t]
        res = mdfqm_update([0] * 4, t, 0, c, "exact_nearest")
        seen.add(res.h)
    assert seen == set(range(15))  # all but all-on (policy all-off)
