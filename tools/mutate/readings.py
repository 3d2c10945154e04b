"""Why a surviving mutant survives, as read from its counterexample and the tests: mutation key
-> a sentence (the report prints it beside the survivor). Keys name source and kind, not cells,
so a reading stays with its mutant when the design is rebuilt; a key that no longer occurs is
simply not printed."""

__all__ = ["READINGS"]

#: a register bit that toggles every clock while the register holds, read at one clock of the
#: update
_TOGGLED_WHILE_HELD = (
    "equivalent by reading, not proven: {what} toggles every clock while the register holds "
    "(the mutation sits on its output, which the hold path feeds back: what is read alternates "
    "between the loaded value and the mutated one); it is loaded at an update start and read "
    "(through `p_lat`, `slot_len`, `slot_m2`) only when the layout loads, a fixed number of "
    "clocks after the start, where the vector runs show it holding its loaded value.")

#: a bit of the minimum-period count-down ``floor`` cleared
_FLOOR_CLEARED = (
    "equivalent by reading, not proven: {what}. Only the sign of `floor` (18 bits, signed) is "
    "read. It is loaded with `minimum - 3` <= 253, below 2**{bit}, so nothing changes until it "
    "is negative; from -1 on, it stays negative for 65,536 clocks (counted on the mutant's "
    "arithmetic), and every update (at most 65,535 clocks) reloads it first.")
#: a leg's ``hi`` at 256 (the leg on for the whole update) changed to another value past it
_HI_PAST_LAST = (
    "equivalent by reading, not proven: {what}. `hi = lo + on = floor(m / 2) + 2**B - m` is "
    "at least 128, and {when} only at `hi = 256` (m = 0: the leg on for the whole update). The "
    "mutant's {value} is past the last slot's index as 256 is: the turn-off compare at the load"
    " (`delta == hi`, delta <= 128) fails either way, and a match of `after == 256` at the "
    "advance into the last slot is never used (the last slot is held until the next load): "
    "the leg stays on.")


def _minimum_bit_cleared(b: int) -> str:
    """Bit b of ``minimum``, set only by the minimum ``2**b`` of that b, read as 0."""
    return (
        f"equivalent by reading, not proven: bit {b} of `minimum` reads 0 (the hold path feeds "
        f"the 0 back), so the minimum of b = {b}, {1 << b}, reads 0 and `P = max(period, "
        "minimum)` is the period itself when that is shorter. P is read only as `slot_len = P "
        ">> b`, then 0 instead of 1, and slots of 0 or 1 clocks are the same one-clock slots: "
        "the layout's count-down is loaded with `slot_len - 2`, negative either way, and "
        "advances every clock. The update's length comes from the `floor` count-down, loaded "
        "from the table, not from `minimum`.")


READINGS: dict[str, str] = {
    "rtl/mdfqm_gateware/sequencer.py:119 sequencer $dff#0 Q[10] cnot1/8":
        "equivalent in practice, not proven: `phase` bit 10 is inverted while bit 8 is set "
        "(`phase` >= 256); its only reader, the sync restart's `phase >= latency - 1`, holds "
        "either way. The two differ only if the mutated count wraps past 65535 inside one "
        "update (an update of more than about 64,500 clocks) and a sync arrives in the few "
        "clocks after the wrap.",
    "rtl/mdfqm_gateware/sequencer.py:178 sequencer $dff#0 Q[6] inv":
        _TOGGLED_WHILE_HELD.format(what="bit 6 of `minimum` (the minimum period)"),
    "rtl/mdfqm_gateware/sequencer.py:179 sequencer $dff#0 Q[5] cnot1/1":
        _TOGGLED_WHILE_HELD.format(what="bit 5 of `period_lat` (the latched period), while its "
                                        "bit 1 is set,"),
    "rtl/mdfqm_gateware/resolution.py:263 quantiser $and#0 B[0] cnot0/2":
        "equivalent by reading, not proven: bit 0 of the slot-grid mask `lo_mask` (set only for "
        "b = 8) is inverted while its bit 2 is clear (b < 6), so `lo = (m >> 1) & lo_mask` takes "
        "bit 1 of the quotient `m` too. At b < 6 the quotient's low B - b >= 3 bits are 0 (after "
        "its b-th step the divider shifts in zeros: `fits & (want != 0)`), so that bit is 0 and "
        "`lo` is unchanged.",
    "rtl/mdfqm_gateware/sequencer.py:191 sequencer $sub#0 A[15] const0":
        _FLOOR_CLEARED.format(what="the minimum-period count-down `floor` is decremented with "
                                   "its bit 15 cleared", bit=15),
    "rtl/mdfqm_gateware/sequencer.py:188 core.sequencer $mux#0 Y[13] const0":
        _FLOOR_CLEARED.format(what="bit 13 of every value written to the minimum-period "
                                   "count-down `floor` is cleared, loads included", bit=13),
    "rtl/mdfqm_gateware/sequencer.py:178 core.sequencer $dff#0 Q[8] cnot0/15":
        _TOGGLED_WHILE_HELD.format(what="bit 8 of `minimum` (the minimum period; the mutation "
                                        "inverts it while bit 15, always clear, is clear)"),
    "rtl/mdfqm_gateware/resolution.py:260 core.quantiser $dff#0 Q[3] cnot0/7":
        _HI_PAST_LAST.format(what="bit 3 of the quantiser's `hi` of leg 0 is inverted while its "
                                  "bit 7 is clear", when="its bit 7 is clear", value=264),
    "rtl/mdfqm_gateware/resolution.py:260 core.quantiser $mux#1 Y[6] cnot1/8":
        _HI_PAST_LAST.format(what="bit 6 of what the quantiser's `hi` of leg 1 is loaded with "
                                  "is inverted while its bit 8 is set",
                             when="its bit 8 is set", value=320),
    "rtl/mdfqm_gateware/sequencer.py:178 core.sequencer $dff#0 Q[5] const0":
        _minimum_bit_cleared(5),
    "rtl/mdfqm_gateware/sequencer.py:178 core.sequencer $dff#0 Q[6] const0":
        _minimum_bit_cleared(6),
    "rtl/mdfqm_gateware/top.py:217 top $dff#0 Q[4] cnot1/16":
        "equivalent by reading, not proven: bit 4 of the ADC trigger counter (17 bits) is "
        "inverted while its bit 16 is set, and bit 16 is never set: the count restarts at every "
        "update start (`elapsed` is 0 in a start clock) and no update lasts more than 65,535 "
        "clocks (PERIOD is 16 bits, every minimum period is below it), so the count stays below "
        "2**16.",
}
