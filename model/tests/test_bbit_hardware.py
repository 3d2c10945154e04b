"""The identities the gateware's quantiser relies on (contract, "b-bit pulse-width resolution"),
checked against the model written from the algorithm (bbit.py), and the runtime clamps."""

import itertools

import numpy as np
import pytest

from mdfqm_model.bbit import bbit_update, centred_slots, gamma2_for, quantised_instants
from mdfqm_model.update import remove_common_mode, sort1
from mdfqm_spec.contract import (
    MODES,
    Contract,
    latch_mode,
    loop_latency,
    min_period,
    resolution_latency,
    sorting_network,
    validate_max_bits,
)

GAMMA_MODES = MODES[1:]


def restoring_quotient(vc, divisor, steps):
    """Quotient bits of ``vc * 2**steps / divisor`` for ``0 <= vc <= divisor``, as the gateware
    computes them: the top bit by compare, then one shift-subtract step per bit."""
    top = int(vc >= divisor)
    rem = 0 if top else vc
    q = 0
    for _ in range(steps):
        trial = 2 * rem - divisor
        bit = int(trial >= 0)
        rem = trial if bit else 2 * rem
        q = 2 * q + bit
    return (top << steps) | q


def hardware_q(t, mode, b, bmax, c):
    """Per-leg slot counts q_i the way the gateware computes them (telescoped instants, clamp,
    (B+1)-bit quotient by the constant 2 NF, the last B - b bits dropped)."""
    nf = c.unit
    hi, lo = max(t), min(t)
    g2 = {"svpwm": 1, "dpwm0": 0, "dpwm1": 2}.get(mode, 0 if hi + lo >= 0 else 2)
    out = []
    for ti in t:
        v = g2 * nf + (2 - g2) * hi + g2 * lo - 2 * ti + (nf >> b)
        vc = min(max(v, 0), 2 * nf)
        bmax_q = restoring_quotient(vc, 2 * nf, bmax)
        assert bmax_q == vc * (1 << bmax) // (2 * nf)
        out.append(bmax_q >> (bmax - b))
    return out, g2


@pytest.mark.parametrize("n", [3, 4, 5, 7])
def test_per_leg_instants_equal_the_cumulative_duties(n, rng):
    c = Contract(n, 16)
    bmax = 8
    for _ in range(400):
        scale = rng.choice([0.3, 1.0, 2.5])  # inside, at and far outside the linear range
        t = rng.integers(-int(scale * c.unit), int(scale * c.unit), size=n)
        t[-1] -= t.sum()  # T = X + R has sum 0
        t = [int(v) for v in t]
        rho, perm = sort1(t)
        for mode in GAMMA_MODES:
            b = int(rng.integers(1, bmax + 1))
            g2 = gamma2_for(mode, rho)
            q = quantised_instants(rho, g2, 1 << b, c)
            model_q = [0] * n
            for p in range(n):
                model_q[perm[p]] = q[p + 1]
            hw_q, hw_g2 = hardware_q(t, mode, b, bmax, c)
            assert hw_g2 == g2
            assert hw_q == model_q, (t, mode, b)


@pytest.mark.parametrize("mode", GAMMA_MODES)
def test_feedback_in_units_of_full_over_2_to_the_b(mode, rng):
    """U_i = (FULL / 2**B) (sum m - N m_i), m_i = q_i 2**(B - b): bbit's mean feedback."""
    n, bmax = 5, 8
    c = Contract(n, 16)
    for _ in range(100):
        b = int(rng.integers(1, bmax + 1))
        codes = rng.integers(-c.full, c.full, size=n)
        r = remove_common_mode(codes, n)
        res = bbit_update([0] * n, r, c, mode, b)
        q, _ = hardware_q(list(res.t), mode, b, bmax, c)
        m = [qi << (bmax - b) for qi in q]
        u = [(c.full >> bmax) * (sum(m) - n * mi) for mi in m]
        if not res.saturated:
            assert tuple(ti - ui for ti, ui in zip(res.t, u, strict=True)) == res.x_next
        assert [(1 << b) - qi for qi in q] == list(res.on_slots)


@pytest.mark.parametrize("b", [1, 2, 3, 6])
def test_layout_bounds_first_and_last_slot(b, rng):
    """Leg i is on in slots floor(q/2) <= j < S - ceil(q/2); the first slot holds the legs with
    floor(q/2) == 0, the last the legs with q == 0 (the zero policy's h_prev)."""
    s = 1 << b
    bmax = 8
    delta = 1 << (bmax - b)
    for q in range(s + 1):  # legs are laid out independently: one leg at a time
        slots = centred_slots([s - q], s)
        lo, hi = q // 2, s - (q + 1) // 2
        assert slots == [int(lo <= j < hi) for j in range(s)]
        # the scaled bounds the gateware registers, m = q 2**(B - b)
        m = q * delta
        lo_s = (m >> 1) & ~(delta - 1)
        assert lo_s == lo * delta and lo_s + (1 << bmax) - m == hi * delta
    triples = itertools.product(range(s + 1), repeat=3) if b <= 3 else (
        tuple(int(v) for v in rng.integers(0, s + 1, size=3)) for _ in range(3000))
    for qs in triples:
        slots = centred_slots([s - q for q in qs], s)
        assert slots[0] == sum(1 << i for i, q in enumerate(qs) if q // 2 == 0 and q < s)
        assert slots[-1] == sum(1 << i for i, q in enumerate(qs) if q == 0)


def test_latch_mode_every_code():
    bmax = 6
    for mode, bits in itertools.product(range(8), range(16)):
        got = latch_mode(mode, bits, bmax)
        if mode >= len(MODES):
            assert got == (0, 0, True)
        elif mode == 0:
            assert got == (0, 0, False)
        else:
            b = min(max(bits, 1), bmax)
            assert got == (mode, b, b != bits)
            assert (not got[2]) == (1 <= bits <= bmax)
    with pytest.raises(ValueError, match="mode must be a 3-bit and bits a 4-bit code"):
        latch_mode(8, 0, bmax)
    with pytest.raises(ValueError, match="mode must be a 3-bit and bits a 4-bit code"):
        latch_mode(1, 16, bmax)


def test_latencies_and_minimum_periods():
    assert resolution_latency(3, 8) == 20
    assert resolution_latency(5, 6) == 7 + len(sorting_network(5)) + 3 + 6 == 21
    for n in (3, 4, 5, 9):
        for bmax in (1, 8, 12):
            assert resolution_latency(n, bmax) > loop_latency(n)
    lat, long = loop_latency(3), resolution_latency(3, 8)
    assert min_period(False, 0, lat, long) == 8
    assert min_period(True, 0, lat, long) == 20
    assert min_period(True, 4, lat, long) == 20
    assert min_period(True, 5, lat, long) == 32
    assert min_period(True, 8, lat, long) == 256
    with pytest.raises(ValueError, match="max_bits must be an integer >= 1, not 0"):
        resolution_latency(3, 0)
    with pytest.raises(ValueError, match="phases must be an integer >= 3, not 2"):
        resolution_latency(2, 4)


@pytest.mark.parametrize(("max_bits", "width", "message"), [
    (0, 16, "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots "
            "<= FULL, at most 12), not 0"),
    (13, 16, "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots "
             "<= FULL, at most 12), not 13"),
    (9, 10, "max_bits must be an integer in [1, 8] for a 10-bit reference (2**max_bits slots "
            "<= FULL, at most 12), not 9"),
    (2.0, 16, "max_bits must be an integer in [1, 12] for a 16-bit reference (2**max_bits slots "
              "<= FULL, at most 12), not 2.0"),
])
def test_validate_max_bits(max_bits, width, message):
    with pytest.raises(ValueError) as info:
        validate_max_bits(max_bits, width)
    assert str(info.value) == message
    assert validate_max_bits(min(12, width - 2), width) == min(12, width - 2)


def test_restoring_division_is_the_floor():
    for divisor in (2 * 3 * (1 << 14), 2 * 5 * (1 << 14), 2 * 7 * (1 << 6)):
        for vc in [*range(0, divisor + 1, max(1, divisor // 997)), divisor - 1, divisor]:
            for steps in (1, 4, 8):
                assert restoring_quotient(vc, divisor, steps) == vc * (1 << steps) // divisor
    assert np.all(np.array([restoring_quotient(v, 6, 3) for v in range(7)])
                  == np.arange(7) * 8 // 6)
