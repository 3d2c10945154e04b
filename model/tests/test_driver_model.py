"""Gate-driver model: dead time, minimum pulse, enable at update boundaries, fault, polarity.

Expected timings are derived by hand from the rules in :mod:`mdfqm_model.driver`'s docstring.
"""

import numpy as np
import pytest

from mdfqm_model.driver import (
    GateDriverModel,
    LegModel,
    SafetyError,
    check_gate_safety,
)


def run(model, cycles, **stim):
    """Simulate and also return the active-high gates (undoing polarity)."""
    out = model.simulate({"cycles": cycles, **stim})
    mask = model.mask
    out["up"] = out["upper"] ^ (mask if model.upper_active_low else 0)
    out["lo"] = out["lower"] ^ (mask if model.lower_active_low else 0)
    return out


def pulses(stream, value=1):
    """(start, length) of each run of ``value`` in a 0/1 sequence."""
    runs, start = [], None
    for t, v in enumerate([*stream, 1 - value]):
        if v == value and start is None:
            start = t
        elif v != value and start is not None:
            runs.append((start, t - start))
            start = None
    return runs


def updates_at(cycles, times, h_values, enable=1):
    """Stimulus arrays: ``update`` high at ``times`` with ``h`` from ``h_values``, held
    between updates (as the core presents it)."""
    update = np.zeros(cycles, dtype=np.int64)
    h = np.zeros(cycles, dtype=np.int64)
    for t, v in zip(times, h_values, strict=True):
        update[t] = 1
        h[t:] = v
    en = np.full(cycles, enable, dtype=np.int64) if np.isscalar(enable) else enable
    return {"update": update, "h": h, "enable": en}


def test_reset_state_all_off_with_polarity():
    m = GateDriverModel(3, 4, upper_active_low=True)
    o = m.step()
    assert o == {"upper": 0b111, "lower": 0, "event": 0, "fault": 0, "fault_input": 0, "active": 0,
                 "short_edge": 0, "short_edge_now": 0, "reaction": 0, "reaction_fault_acted": 0,
                 "reaction_watchdog_acted": 0}


@pytest.mark.parametrize("asc", [True, False])
def test_reaction_inputs_as_acted_on(asc):
    """Each reaction input as the driver acts on it, in the same cycle: 1 and 2 as they are,
    0 and 3 all off; every code all off without the active short circuit."""
    m = GateDriverModel(3, 4, asc=asc)
    for fault_code in range(4):
        for watchdog_code in range(4):
            o = m.step(reaction_fault=fault_code, reaction_watchdog=watchdog_code)
            assert o["reaction_fault_acted"] == (fault_code if asc and fault_code in (1, 2) else 0)
            assert o["reaction_watchdog_acted"] == (
                watchdog_code if asc and watchdog_code in (1, 2) else 0)


def test_first_turn_on_waits_the_dead_time_after_reset():
    m = GateDriverModel(3, 3)
    out = run(m, 20, dead=3, **updates_at(20, [0], [0b001]))
    # cnt = 0, 1, 2 in cycles 0..2; decided in cycle 2 -> visible in cycle 3
    assert list(out["up"][:5]) == [0, 0, 0, 1, 1]
    assert list(out["lo"][:5]) == [0, 0, 0, 0b110, 0b110]
    assert list(np.flatnonzero(out["event"])) == [3]
    assert out["event"][3] == 0b111
    assert list(out["active"][:3]) == [0, 1, 1]


def test_complementary_switching_with_dead_time():
    m = GateDriverModel(3, 2)
    cycles = 60
    stim = updates_at(cycles, [0, 20, 40], [0b001, 0b010, 0b010])
    out = run(m, cycles, dead=5, **stim)
    # update at 20 (h 001 -> 010): leg 0 upper off at 21, lower on at 26; leg 1 lower off at 21,
    # upper on at 26 (5 off clocks 21..25)
    up, lo = out["up"], out["lo"]
    assert (up[5:21] == 0b001).all() and (up[21:26] == 0).all() and (up[26:] == 0b010).all()
    assert (lo[5:21] == 0b110).all() and (lo[21:26] == 0b100).all() and (lo[26:] == 0b101).all()
    assert out["event"][26] == 0b011 and out["event"][5] == 0b111
    assert check_gate_safety(up, lo, 3, dead=np.full(cycles, 5)) == 5


def test_command_follows_an_edge_inside_an_update():
    """A slot mode's edge (h moves without an update strobe) is followed like an update's,
    under the same dead time."""
    m = GateDriverModel(3, 1)
    cycles = 30
    stim = updates_at(cycles, [0], [0b111])
    stim["h"][10:] = 0b000
    out = run(m, cycles, dead=3, **stim)
    # on at 3 (dead 3 from reset); edge at 10: uppers off at 11, lowers on at 11 + 3
    assert (out["up"][3:11] == 0b111).all() and not out["up"][11:].any()
    assert not out["lo"][:14].any() and (out["lo"][14:] == 0b111).all()
    assert not out["short_edge"].any()


def test_short_edges_are_reported():
    """Leg 0: a pulse shorter than the dead time is swallowed; leg 1: one shorter than the
    minimum pulse is stretched; leg 2 follows at leisure: only the first two are reported, in
    the cycle of the edge that ends the short pulse (``short_edge_now``) and, registered, in the
    cycle after it (``short_edge``)."""
    m = GateDriverModel(3, 1)
    cycles = 60
    h = np.zeros(cycles, dtype=np.int64)
    h[20:22] = 0b001          # leg 0: upper for 2 clocks (< dead 4): swallowed
    h[30:] |= 0b010           # leg 1: upper from 30 (lower off at 31, upper on at 35) ...
    h[36:] &= ~0b010          # ... commanded away after 1 on-clock (< min pulse 5)
    h[45:] |= 0b100           # leg 2: a long pulse, followed
    update = np.zeros(cycles, dtype=np.int64)
    update[0] = 1
    out = run(m, cycles, dead=4, min_pulse=5, h=h, update=update, enable=1)
    assert not (out["up"] & 1).any()                       # swallowed: never on
    assert pulses((out["up"] >> 1) & 1) == [(35, 5)]       # stretched to 5 clocks
    assert [(int(t), int(v)) for t, v in enumerate(out["short_edge_now"]) if v] == \
        [(22, 0b001), (36, 0b010)]
    assert [(int(t), int(v)) for t, v in enumerate(out["short_edge"]) if v] == \
        [(23, 0b001), (37, 0b010)]
    in_force = np.r_[1, np.full(cycles - 1, 4)]             # dead acts a clock late
    assert check_gate_safety(out["up"], out["lo"], 3, dead=in_force) > 0


def test_enable_and_disable_take_effect_at_update_boundaries():
    m = GateDriverModel(3, 2)
    cycles = 80
    en = np.zeros(cycles, dtype=np.int64)
    en[5:45] = 1  # raised mid-update, lowered mid-update
    stim = updates_at(cycles, [0, 20, 40, 60], [0b001] * 4, enable=en)
    out = run(m, cycles, dead=2, **stim)
    on = out["up"] | out["lo"]
    assert not on[:21].any()  # enable taken at the update of cycle 20
    assert (out["active"][21:61] == 1).all() and not out["active"][61:].any()
    assert (on[21:61] == 0b111).all()  # off since reset: no dead time left to wait
    assert not on[61:].any()  # disable taken at 60, off at 61


def test_raising_dead_time_lengthens_a_running_one_lowering_does_not_shorten_it():
    cycles = 60
    stim = updates_at(cycles, [0, 20], [0b001, 0b000])
    # raise from 4 to 9 in the middle of the dead time that starts at 21
    dead = np.full(cycles, 4)
    dead[23:] = 9
    out = run(GateDriverModel(3, 1), cycles, dead=dead, **stim)
    assert pulses(out["lo"] & 1)[-1][0] == 21 + 9
    # lower from 9 to 2 in the middle of the dead time: the 9 latched at the turn-off holds
    dead = np.full(cycles, 9)
    dead[23:] = 2
    out = run(GateDriverModel(3, 1), cycles, dead=dead, **stim)
    assert pulses(out["lo"] & 1)[-1][0] == 21 + 9
    # ... and the next dead time uses the new value
    stim2 = updates_at(cycles, [0, 20, 40], [0b001, 0b000, 0b001])
    out = run(GateDriverModel(3, 1), cycles, dead=dead, **stim2)
    assert pulses(out["up"] & 1)[-1][0] == 41 + 2


def test_dead_time_floor():
    cycles = 40
    stim = updates_at(cycles, [0, 20], [0b001, 0b000])
    out = run(GateDriverModel(3, 6), cycles, dead=0, **stim)
    assert pulses(out["up"] & 1) == [(6, 15)]  # on at 6, off at 21
    assert pulses(out["lo"] & 1)[-1][0] == 21 + 6


@pytest.mark.parametrize("dead", [1, 3, 7])
@pytest.mark.parametrize("min_pulse", [0, 1, 4, 9])
@pytest.mark.parametrize("width", [1, 2, 3, 5, 8, 12, 16])
def test_commanded_pulse_gives_max_of_width_minus_dead_and_min_pulse(dead, min_pulse, width):
    """The documented behaviour: a commanded upper pulse of ``w`` clocks on a leg whose lower
    switch is on gives an upper on-time of ``max(w - dead, min_pulse)`` if ``w > dead``
    (stretched, never dropped) and nothing if ``w <= dead`` (the dead time swallows it)."""
    leg = LegModel(1)
    cmd = [0] * 40 + [1] * width + [0] * 60
    ups = []
    for c in cmd:
        ups.append(leg.step(0, c, 1, dead, min_pulse)["up"])
    runs = pulses(ups)
    if width <= dead:
        assert runs == []
    else:
        assert runs == [(41 + dead, max(width - dead, min_pulse, 1))]


def test_min_pulse_stretch_delays_the_complementary_turn_on():
    leg = LegModel(2)
    cmd = [0] * 20 + [1] * 4 + [0] * 30  # upper commanded 4 clocks, dead 2 -> 2 clocks on
    los, ups = [], []
    for c in cmd:
        o = leg.step(0, c, 1, 2, 6)
        ups.append(o["up"])
        los.append(o["lo"])
    assert pulses(ups) == [(23, 6)]  # stretched to 6
    assert pulses(los)[-1][0] == 23 + 6 + 2  # lower back after the dead time
    assert check_gate_safety(ups, los, 1, dead=[2] * len(cmd)) == 3


def test_fault_turns_off_within_two_clocks_and_latches_until_clear():
    m = GateDriverModel(3, 2)
    cycles = 100
    stim = updates_at(cycles, list(range(0, cycles, 10)), [0b011] * 10)
    fault_in = np.zeros(cycles, dtype=np.int64)
    fault_in[30:33] = 1
    clear = np.zeros(cycles, dtype=np.int64)
    clear[31] = 1  # input still active (synchronised from 32 to 34): ignored
    clear[55] = 1
    out = run(m, cycles, dead=2, fault_in=fault_in, fault_clear=clear, **stim)
    on = out["up"] | out["lo"]
    assert list(out["fault_input"][30:36]) == [0, 0, 1, 1, 1, 0]
    assert on[32] == 0b111
    assert not on[33:61].any()  # off one clock after sync
    assert list(out["fault"][32:57]) == [0] + [1] * 23 + [0]  # latched 33..55
    assert (out["active"][33:61] == 0).all() and out["active"][61] == 1
    assert (on[61:] == 0b111).all()  # resumes after update 60
    check_gate_safety(
        out["up"], out["lo"], 3, dead=np.full(cycles, 2), kill=out["fault_input"] | out["fault"]
    )


def test_fault_synchroniser_and_chatter():
    m = GateDriverModel(3, 1)
    cycles = 60
    fault_in = np.zeros(cycles, dtype=np.int64)
    fault_in[[10, 12, 13, 20]] = 1
    out = run(m, cycles, dead=1, fault_in=fault_in, enable=1, update=1, h=0b101)
    assert list(np.flatnonzero(out["fault_input"])) == [12, 14, 15, 22]
    assert (out["fault"][13:] == 1).all()
    assert not (out["up"] | out["lo"])[13:].any()


def test_fault_during_dead_time_keeps_everything_off():
    m = GateDriverModel(3, 5)
    cycles = 60
    stim = updates_at(cycles, [0, 20], [0b001, 0b110])
    fault_in = np.zeros(cycles, dtype=np.int64)
    fault_in[20] = 1  # synchronised at 22, inside the dead time 21..25
    out = run(m, cycles, dead=5, fault_in=fault_in, **stim)
    assert not (out["up"] | out["lo"])[21:].any()


def test_reset_keeps_the_running_dead_time():
    m = GateDriverModel(3, 2)
    cycles = 60
    stim = updates_at(cycles, [0, 30], [0b001, 0b001])
    rst = np.zeros(cycles, dtype=np.int64)
    dead = np.full(cycles, 12)
    rst[20] = 1
    dead[21:] = 2  # the register file resets the dead time to its floor
    out = run(m, cycles, dead=dead, rst=rst, **stim)
    on = out["up"] | out["lo"]
    assert (on[12:21] == 0b111).all() and not on[21:30].any()
    # cnt restarts at the reset (cycle 21); dt_run = 12 survived: on at 21 + 12
    assert 21 + int(np.argmax(on[21:] != 0)) == 33  # (2 after a reset that forgot it: 31)


def test_polarity_is_a_pure_inversion():
    rng = np.random.default_rng(5)
    cycles = 400
    stim = {
        "update": rng.integers(0, 2, cycles),
        "h": rng.integers(0, 8, cycles),
        "enable": (rng.random(cycles) < 0.9).astype(int),
        "dead": rng.integers(0, 6, cycles),
        "min_pulse": rng.integers(0, 5, cycles),
        "fault_in": (rng.random(cycles) < 0.01).astype(int),
        "fault_clear": rng.integers(0, 2, cycles),
    }
    a = GateDriverModel(3, 2).simulate(stim)
    b = GateDriverModel(3, 2, upper_active_low=True, lower_active_low=True).simulate(stim)
    assert (a["upper"] ^ b["upper"] == 7).all() and (a["lower"] ^ b["lower"] == 7).all()


@pytest.mark.parametrize("phases", [3, 5])
def test_random_stimulus_is_always_safe(phases, rng):
    cycles = 5000
    m = GateDriverModel(phases, 3, time_width=6)
    stim = {
        "rst": (rng.random(cycles) < 0.003).astype(int),
        "update": (rng.random(cycles) < 0.15).astype(int),
        "h": rng.integers(0, 1 << phases, cycles),
        "enable": (rng.random(cycles) < 0.9).astype(int),
        "dead": rng.choice([0, 1, 2, 3, 7, 63], cycles),
        "min_pulse": rng.choice([0, 1, 2, 9, 63], cycles),
        "fault_in": (rng.random(cycles) < 0.005).astype(int),
        "fault_clear": (rng.random(cycles) < 0.05).astype(int),
    }
    out = m.simulate(stim)
    # the dead time in force: the legs act on the clock before's input (power-up 0 -> floor)
    dead = np.maximum(np.concatenate([[0], stim["dead"][:-1]]), 3)
    turn_ons = check_gate_safety(
        out["upper"], out["lower"], phases, dead=dead, kill=out["fault_input"], rst=stim["rst"]
    )
    assert turn_ons == sum(bin(int(e)).count("1") for e in out["event"])
    assert turn_ons > 50


def test_safety_checker_catches_violations():
    with pytest.raises(SafetyError, match="both switches on"):
        check_gate_safety([0, 1], [0, 1], 1)
    with pytest.raises(SafetyError, match="after 2 off clocks, dead time in force 3"):
        check_gate_safety([1, 0, 0, 0, 0], [0, 0, 0, 1, 1], 1, dead=[3, 1, 1, 1, 1])
    with pytest.raises(SafetyError, match="after 2 off clocks, dead time in force 4"):
        check_gate_safety([1, 0, 0, 0, 0], [0, 0, 0, 1, 1], 1, dead=[1, 1, 4, 1, 1])
    with pytest.raises(SafetyError, match="one clock after kill"):
        check_gate_safety([1, 1], [0, 0], 1, kill=[1, 0])
    # under an ASC its switches may stay on after a kill, the others may not
    assert check_gate_safety([0, 0], [1, 1], 1, kill=[1, 0], reaction=[1, 1]) == 0
    assert check_gate_safety([1, 1], [0, 0], 1, kill=[1, 0], reaction=[2, 2]) == 0
    with pytest.raises(SafetyError, match="one clock after kill"):
        check_gate_safety([1, 1], [0, 0], 1, kill=[1, 0], reaction=[1, 1])
    assert check_gate_safety([1, 0, 0, 0, 0], [0, 0, 0, 1, 1], 1, dead=[2, 1, 2, 1, 1]) == 1


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"phases": 0, "dead_min": 1}, "phases must be an integer >= 1, not 0"),
        ({"phases": 3, "dead_min": 0}, "dead_min must be an integer in [1, 65535] (clocks), not 0"),
        (
            {"phases": 3, "dead_min": 8, "time_width": 3},
            "dead_min must be an integer in [1, 7] (clocks), not 8",
        ),
        (
            {"phases": 3, "dead_min": 1, "time_width": 1},
            "time_width must be an integer in [2, 32], not 1",
        ),
        (
            {"phases": 3, "dead_min": 1, "upper_active_low": 1},
            "upper_active_low must be a bool, not 1",
        ),
        (
            {"phases": 3, "dead_min": 1, "lower_active_low": "yes"},
            "lower_active_low must be a bool, not 'yes'",
        ),
        ({"phases": 3, "dead_min": 1, "asc": 1}, "asc must be a bool, not 1"),
    ],
)
def test_rejects_bad_parameters(kwargs, message):
    with pytest.raises(ValueError) as info:
        GateDriverModel(**kwargs)
    assert str(info.value) == message


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"h": 8}, "h must be an unsigned 3-bit integer, not 8"),
        ({"dead": 1 << 16}, "dead must be an unsigned 16-bit integer, not 65536"),
        ({"min_pulse": -1}, "min_pulse must be an unsigned 16-bit integer, not -1"),
        ({"fault_in": 2}, "fault_in must be 0 or 1, not 2"),
    ],
)
def test_rejects_bad_inputs(kwargs, message):
    with pytest.raises(ValueError) as info:
        GateDriverModel(3, 1).step(**kwargs)
    assert str(info.value) == message


def test_dead_and_min_pulse_act_one_clock_after_they_arrive():
    """The legs act on the clock before's ``dead`` / ``min_pulse`` (the driver's input
    register): raising ``dead`` in the clock a turn-on is decided does not stop it, one clock
    earlier it does; likewise ``min_pulse``."""

    def run(dead_at, min_pulse_at):
        m = GateDriverModel(1, 2)
        # the upper on at an update, then commanded off at cycle 20; lower commanded since
        ups, los = [], []
        for t in range(40):
            out = m.step(h=int(t < 20), update=int(t in (0, 20)), enable=1,
                         dead=20 if t >= dead_at else 2,
                         min_pulse=30 if t >= min_pulse_at else 0)
            ups.append(out["upper"])
            los.append(out["lower"])
        return ups, los

    ups, los = run(99, 99)
    turn_off, turn_on = ups.index(0, 3), los.index(1)
    assert (turn_off, turn_on) == (21, 23)        # two clocks off: dead 2
    assert run(turn_on - 1, 99)[1].index(1) == turn_on         # raised in the deciding clock
    assert 1 not in run(turn_on - 2, 99)[1][:turn_on + 1]      # raised the clock before
    assert run(99, turn_off - 1)[0].index(0, 3) == turn_off    # min_pulse in the deciding clock
    assert run(99, turn_off - 2)[0].index(0, 3) > turn_off     # and the clock before


# ------------------------------------------------------------------ the fault reaction
def pulse_at(cycles, *times):
    a = np.zeros(cycles, dtype=np.int64)
    a[list(times)] = 1
    return a


def test_asc_low_on_a_fault_then_all_off_then_clear():
    m = GateDriverModel(3, 2)
    cycles = 80
    stim = updates_at(cycles, list(range(0, cycles, 10)), [0b011] * 8)
    # the fault synchronised at 32: the upper switches off at 33, every lower one on at 35
    # (off since 33: two clocks of dead time); ALL_OFF at 50: all off from 51; the clear at 55
    # and the update at 60 bring the command back at 61 (off for ten clocks already)
    out = run(m, cycles, dead=2, fault_in=pulse_at(cycles, 30), reaction_fault=1,
              all_off=pulse_at(cycles, 50), fault_clear=pulse_at(cycles, 55), **stim)
    assert list(out["up"][31:36]) == [0b011, 0b011, 0, 0, 0]
    assert list(out["lo"][31:36]) == [0b100, 0b100, 0b100, 0b100, 0b111]
    assert (out["lo"][35:51] == 0b111).all() and not out["up"][33:51].any()
    assert list(out["reaction"][31:35]) == [0, 0, 1, 1] and (out["reaction"][33:51] == 1).all()
    assert not (out["up"] | out["lo"])[51:61].any() and not out["reaction"][51:].any()
    assert list(out["fault"][55:58]) == [1, 0, 0]
    assert (out["up"][61:] == 0b011).all() and (out["lo"][61:] == 0b100).all()
    assert list(out["event"][33:36]) == [0, 0, 0b011]   # the ASC turn-ons are events
    check_gate_safety(out["up"], out["lo"], 3, dead=np.full(cycles, 2),
                      kill=out["fault_input"] | out["fault"], reaction=out["reaction"])


def test_asc_ends_on_the_clear_through_all_off_even_at_an_update():
    m = GateDriverModel(3, 2)
    cycles = 80
    stim = updates_at(cycles, list(range(0, cycles, 10)), [0b011] * 8)
    # clear at 59: the latch is clear at 60 (an update, enable high): every switch off at 61
    # and 62, the commanded ones on at 63 after the dead time
    out = run(m, cycles, dead=2, fault_in=pulse_at(cycles, 30), reaction_fault=1,
              fault_clear=pulse_at(cycles, 59), **stim)
    assert (out["lo"][35:61] == 0b111).all() and (out["reaction"][33:61] == 1).all()
    assert list(out["up"][60:64]) == [0, 0, 0, 0b011]
    assert list(out["lo"][60:64]) == [0b111, 0, 0, 0b100]
    assert out["reaction"][61] == 0 and out["active"][61] == 1
    check_gate_safety(out["up"], out["lo"], 3, dead=np.full(cycles, 2))


def test_asc_high_on_the_watchdog_inside_a_minimum_pulse_and_a_dead_time():
    m = GateDriverModel(3, 3)
    cycles = 60
    # leg 0 upper and leg 1 lower commanded from 0; at 20 the reverse; minimum pulse 10
    stim = updates_at(cycles, [0, 20], [0b001, 0b010])
    stop = np.zeros(cycles, dtype=np.int64)
    stop[25:40] = 1
    out = run(m, cycles, dead=3, min_pulse=10, stop=stop, reaction_watchdog=2, **stim)
    # before the stop: leg 0 upper on 4..20, lower on from 24 (dead time 21..23); leg 1 lower
    # on 4..20, upper on from 24; leg 2 lower on from 4. Stop at 25 (ASC high): at 26 every
    # lower switch is off (leg 0's inside its minimum pulse), leg 1's upper stays on; the upper
    # ones of legs 0 and 2 turn on at 29 after three off clocks
    assert list(out["up"][24:30]) == [0b010, 0b010, 0b010, 0b010, 0b010, 0b111]
    assert list(out["lo"][24:30]) == [0b101, 0b101, 0, 0, 0, 0]
    assert (out["reaction"][26:41] == 2).all() and out["reaction"][25] == 0
    # stop low at 40 (the watchdog cleared): all off at 41
    assert not (out["up"] | out["lo"])[41:].any()
    check_gate_safety(out["up"], out["lo"], 3, dead=np.full(cycles, 3))


@pytest.mark.parametrize(("first", "second", "f", "w", "expected"), [
    ("fault", "stop", 1, 0, [1, 0]),      # a later source with all off ends the ASC
    ("fault", "stop", 1, 2, [1, 1]),      # a later ASC does not change the one in force
    ("stop", "fault", 1, 2, [2, 2]),
    ("stop", "fault", 1, 0, [0, 0]),      # all off in force: a later ASC does not start
    ("both", None, 1, 2, [1]),            # both in one clock: the fault's
    ("both", None, 2, 0, [0]),            # ... unless the watchdog's is all off
])
def test_reaction_of_two_sources(first, second, f, w, expected):
    m = GateDriverModel(3, 1)
    cycles = 40
    fault_in = np.zeros(cycles, dtype=np.int64)
    stop = np.zeros(cycles, dtype=np.int64)
    at = {"fault": (fault_in, 8), "stop": (stop, 10)}   # both seen by the driver at 10
    if first == "both":
        fault_in[8:], stop[10:] = 1, 1
    else:
        arr, t = at[first]
        arr[t:] = 1
        arr, t = at[second]
        arr[t + 10:] = 1
    out = run(m, cycles, fault_in=fault_in, stop=stop, reaction_fault=f, reaction_watchdog=w,
              update=1, enable=1, h=0b101)
    assert out["reaction"][11] == expected[0]
    if len(expected) > 1:
        assert out["reaction"][21] == expected[1] and out["reaction"][20] == expected[0]


def test_reaction_writes_and_all_off_while_latched_and_asc_false():
    cycles = 40
    react = np.full(cycles, 1, dtype=np.int64)
    react[15:] = 2                  # a new reaction while the fault is latched: ignored
    out = run(GateDriverModel(3, 1), cycles, fault_in=pulse_at(cycles, 8), reaction_fault=react,
              update=1, enable=1, h=0b101)
    assert (out["reaction"][11:] == 1).all() and (out["lo"][13:] == 0b111).all()
    for kwargs in ({"asc": False, "reaction_fault": 1}, {"asc": True, "reaction_fault": 3}):
        m = GateDriverModel(3, 1, asc=kwargs.pop("asc"))
        out = run(m, cycles, fault_in=pulse_at(cycles, 8), update=1, enable=1, h=0b101,
                  **kwargs)
        assert not out["reaction"].any() and not (out["up"] | out["lo"])[11:].any()


def test_reset_ends_an_asc_and_a_still_active_fault_starts_it_again():
    m = GateDriverModel(3, 2)
    cycles = 40
    fault_in = np.zeros(cycles, dtype=np.int64)
    fault_in[8:] = 1
    out = run(m, cycles, fault_in=fault_in, reaction_fault=1, rst=pulse_at(cycles, 20),
              update=1, enable=1, h=0b101)
    assert (out["lo"][13:21] == 0b111).all() and (out["reaction"][11:21] == 1).all()
    # reset at 20: all off and reaction 0 at 21; the input (not reset) still high rises again
    # at 21: every lower switch on at 23 after the dead time (off from 21: two clocks)
    assert out["reaction"][21] == 0 and not out["lo"][21]
    assert list(out["lo"][21:24]) == [0, 0, 0b111] and out["reaction"][22] == 1
