"""The N-phase sine reference model (mdfqm_model.nco) against its specification in floats."""

import numpy as np
import pytest

from mdfqm_model.nco import NcoModel, reference_codes
from mdfqm_spec.nco import phase_offsets, sine_quarter, sine_table, validate_nco


@pytest.mark.parametrize(("table_bits", "sample_width"), [(2, 4), (8, 16), (10, 18), (12, 24)])
def test_table_is_the_sine_half_a_step_off_the_axes(table_bits, sample_width):
    table = np.array(sine_table(table_bits, sample_width))
    k = np.arange(4 << table_bits)
    amp = (1 << (sample_width - 1)) - 1
    exact = amp * np.sin(2 * np.pi * (k + 0.5) / (4 << table_bits))
    assert np.max(np.abs(table - exact)) <= 0.5 + 1e-9
    assert table.sum() == 0                               # odd and half-wave symmetric
    assert min(sine_quarter(table_bits, sample_width)) > 0
    assert np.max(np.abs(table)) <= amp


def test_phase_offsets():
    assert phase_offsets(3, 32) == [0, (1 << 32) - 1431655765, (1 << 32) - 2863311530]
    assert phase_offsets(4, 8) == [0, 192, 128, 64]


@pytest.mark.parametrize("phases", [3, 5, 9])
def test_codes_are_a_balanced_sine(rng, phases):
    acc_bits, table_bits, sample_width, width = 32, 8, 16, 16
    amplitude = int(rng.integers(1000, (1 << (width - 1)) - 1))
    base = rng.integers(0, 1 << acc_bits, size=2000)
    codes = reference_codes(base, amplitude, phases, acc_bits, table_bits, sample_width)
    assert codes.shape == (2000, phases)
    angle = 2 * np.pi * base / (1 << acc_bits)
    for i in range(phases):
        want = amplitude * np.sin(angle - 2 * np.pi * i / phases)
        # table resolution (2 pi / 1024 rad of phase) + rounding of the table and truncation
        assert np.max(np.abs(codes[:, i] - want)) <= amplitude * 2 * np.pi / 1024 + 2
    assert np.all(np.abs(codes) < 1 << (width - 1))
    # the phases index the table at different fractions of a step: a small common mode (the
    # core removes it) but nothing else
    assert np.max(np.abs(codes.sum(axis=1))) <= phases * (amplitude * 2 * np.pi / 1024 + 2)


def test_codes_truncate_toward_zero_and_respect_extremes():
    # amplitude 0 gives 0; the largest amplitude gives a peak below 2**(width-1)
    assert np.all(reference_codes(np.arange(0, 1 << 32, 1 << 24), 0, 3) == 0)
    peak = reference_codes(np.arange(0, 1 << 32, 1 << 22), (1 << 15) - 1, 3)
    assert peak.max() == -peak.min() and peak.max() < 1 << 15
    # sign symmetry: half a turn later every code is negated exactly
    base = np.arange(0, 1 << 31, 7919 << 12)
    assert np.array_equal(reference_codes(base + (1 << 31), 12345, 3),
                          -reference_codes(base, 12345, 3))


def test_model_timing_and_frequency():
    model = NcoModel(3, 16, acc_bits=32, table_bits=8, sample_width=16)
    assert model.beat_clocks == 1 + 3 * 18     # capture; per phase 2 + 15 + 1 clocks
    freq, amplitude = 123_456_789, 20_000
    beats = []
    for cycle in range(20 * (model.beat_clocks + 1)):
        out = model.step(freq=freq, amplitude=amplitude, ready=1)
        if out["valid"]:
            beats.append((cycle, out["payload"]))
    cycles = [c for c, _ in beats]
    # ready held high: a beat every beat_clocks + 1 clocks, the first one beat_clocks in
    assert cycles[0] == model.beat_clocks
    assert set(np.diff(cycles)) == {model.beat_clocks + 1}
    for cycle, payload in beats:       # captured beat_clocks clocks before it is offered
        base = (freq * (cycle - model.beat_clocks)) % (1 << 32)
        assert payload == tuple(reference_codes(base, amplitude, 3).tolist())


def test_model_holds_until_ready():
    model = NcoModel(3, 16)
    outs = [model.step(freq=1 << 20, amplitude=1000, ready=0) for _ in range(200)]
    valid = [o["valid"] for o in outs]
    assert valid.index(1) == model.beat_clocks and all(valid[model.beat_clocks:])
    assert len({o["payload"] for o in outs[model.beat_clocks:]}) == 1


@pytest.mark.parametrize(("args", "message"), [
    ((32, 1, 16), "table_bits must be an integer in [2, 12], not 1"),
    ((32, 8, 25), "sample_width must be an integer in [4, 24], not 25"),
    ((9, 8, 16), "acc_bits must be an integer in [10, 32], not 9"),
    ((33, 8, 16), "acc_bits must be an integer in [10, 32], not 33"),
    ((32.0, 8, 16), "acc_bits must be an integer in [10, 32], not 32.0"),
])
def test_validate_nco(args, message):
    with pytest.raises(ValueError) as info:
        validate_nco(*args)
    assert str(info.value) == message
