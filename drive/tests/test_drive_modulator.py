"""The fast edge source against the clock-level golden model: the drop-in top's pins and ADC
trigger, clock for clock, programmed through its Wishbone registers as firmware would."""

import numpy as np
import pytest

from mdfqm_drive.modulator import IpModulator, IpSettings
from mdfqm_spec.contract import ALL_OFF, FEWEST_TRANSITIONS
from topreplay import run_top


def run_fast(settings: IpSettings, refs, updates):
    """The same run through :class:`IpModulator`: per-clock pins rebuilt from its edges."""
    mod = IpModulator(settings)
    upper = np.zeros(updates * mod.period + 1, dtype=np.int64)
    lower = np.zeros_like(upper)
    adc = np.zeros_like(upper)
    edges = []
    if settings.adc_offset == mod.period - 1:
        adc[0] = 1  # the pulse of the update before the first, in this one's first cycle
    for k in range(updates):
        if k % mod.osr == 0 and k // mod.osr < len(refs):
            mod.write_reference(refs[k // mod.osr])
        upd = mod.next_update()
        edges += upd.edges
        if upd.adc is not None:
            adc[upd.adc] = 1
    for cycle, up, lo in edges:
        if cycle < len(upper):
            upper[cycle:] = up
            lower[cycle:] = lo
    return upper[:-1], lower[:-1], adc[:-1], mod


CASES = [
    # mode, bits, period, osr, dead, min_pulse, adc_offset, zero policy
    ("mdfqm", 0, 96, 4, 64, 0, 5, ALL_OFF),
    ("mdfqm", 0, 80, 2, 70, 90, 79, FEWEST_TRANSITIONS),
    ("svpwm", 3, 1100, 1, 64, 0, 20, ALL_OFF),
    ("dpwm0", 2, 700, 2, 100, 30, 0, ALL_OFF),
    ("dpwm1", 3, 900, 1, 64, 0, 899, ALL_OFF),
    ("dpwm", 4, 1200, 1, 64, 120, 1500, ALL_OFF),
]


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-b{c[1]}-P{c[2]}" for c in CASES])
def test_pins_equal_the_clock_level_model(case, rng):
    mode, bits, period, osr, dead, min_pulse, adc_offset, zero_policy = case
    settings = IpSettings(period=period, osr=osr, dead=dead, min_pulse=min_pulse,
                          adc_offset=adc_offset, mode=mode, bits=bits, zero_policy=zero_policy)
    updates = 48 if mode == "mdfqm" else 16
    samples = updates // osr + 1
    # a rotating reference of random amplitude (some past the linear range) plus noise
    full = 1 << 14
    amp = rng.uniform(0.1, 0.7) * full
    phase = np.arange(samples) * rng.uniform(0.2, 0.9)
    refs = np.stack([amp * np.cos(phase - k * 2 * np.pi / 3) for k in range(3)], axis=1)
    refs = np.round(refs + rng.normal(0, 0.05 * full, refs.shape)).astype(int)
    top_pins, _ = run_top(settings, refs, updates)
    upper, lower, adc, mod = run_fast(settings, refs, updates)
    assert len(top_pins) == len(upper)
    for cycle, (up, lo, trig, _) in enumerate(top_pins):
        assert (up, lo, trig) == (upper[cycle], lower[cycle], adc[cycle]), (
            f"cycle {cycle} of update {cycle // mod.period}: top {up:03b}/{lo:03b}/{trig}, "
            f"fast {upper[cycle]:03b}/{lower[cycle]:03b}/{adc[cycle]}")
    # the run switched, with both gates of a leg never on together
    assert np.count_nonzero(np.diff(upper)) > 3
    assert not np.any(upper & lower)
