"""Why a surviving mutant survives, as read from its counterexample and the tests: mutation key
-> a sentence (the report prints it beside the survivor). Keys name source and kind, not cells,
so a reading stays with its mutant when the design is rebuilt; a key that no longer occurs is
simply not printed."""

__all__ = ["READINGS"]

#: the AXI front's held write data, a bit of its reset value inverted
_HELD_WRITE_DATA = (
    "equivalent by reading, not proven: the reset multiplexer of the AXI front's held write "
    "data (select `rst`): the mutation inverts bit {bit} of its reset value; the word is loaded"
    " by the W handshake before any write is issued (`do_write` needs `w_full`), and the "
    "register file reads `w_data` only with `w_en`, so the reset value is never used.")

READINGS: dict[str, str] = {
    "rtl/mdfqm_gateware/reference.py:47 reference $mux#0 A[3] const0":
        "equivalent by reading, not proven: the mutation clears bit 3 of `scaled` only while it"
        " holds (no beat in the clock before); `scaled` is read only in the clock after a beat "
        "was taken (`in_scaled`), when it has just been loaded. Yosys's `equiv` pairs `scaled` "
        "and cannot see that the held value is never read.",
    "rtl/mdfqm_gateware/sequencer.py:119 sequencer $dff#0 Q[10] cnot1/8":
        "equivalent in practice, not proven: `phase` bit 10 is inverted while bit 8 is set "
        "(`phase` >= 256); its only reader, the sync restart's `phase >= latency - 1`, holds "
        "either way. The two differ only if the mutated count wraps past 65535 inside one "
        "update (an update of more than about 64,500 clocks) and a sync arrives in the few "
        "clocks after the wrap.",
    "rtl/mdfqm_gateware/sequencer.py:179 sequencer $dff#0 Q[0] const0":
        "equivalent by reading, not proven: bit 0 of the latched period reaches the outputs "
        "only through `slot_len = P >> b`, which only the slot modes read, where b >= 1 drops "
        "it (the clamp `max(P, minimum)` gives the same value either way; the update's end "
        "comes from the count-down of `period` itself). `equiv` cannot see that b >= 1 whenever"
        " `slot_len` is read.",
    "rtl/mdfqm_gateware/sequencer.py:179 core.sequencer $dff#0 Q[0] const0":
        "equivalent by reading, not proven: bit 0 of the latched period reaches the outputs "
        "only through `slot_len = P >> b`, which only the slot modes read, where b >= 1 drops "
        "it (the clamp `max(P, minimum)` gives the same value either way; the update's end "
        "comes from the count-down of `period` itself). `equiv` cannot see that b >= 1 whenever"
        " `slot_len` is read.",
    "rtl/mdfqm_gateware/generator.py:140 top $mux#0 B[9] const1":
        "equivalent by reading, not proven: this is the reset multiplexer of `slot_m2` (select "
        "`rst`, B its reset value 0): the mutation gives it 512 for the one clock after a "
        "reset. `slot_m2` is written every clock and read only when a layout is loaded, which "
        "never happens in the clock after a reset (the pipeline's valid flags are reset too).",
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[21] const1":
        "equivalent by reading, not proven: the reset multiplexer of the AXI front's held write"
        " data (select `rst`): the mutation sets bit 21 of its reset value; the word is loaded "
        "by the W handshake before any write is issued, so the reset value is never used.",
    "rtl/mdfqm_gateware/top.py:383 top $and#0 A[2] cnot1/1":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/top.py:435 top $reduce_bool#0 A[6] const0":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/resolution.py:179 quantiser $add#0 B[1] cnot0/14":
        "equivalent by reading, not proven: the offset of the max-clamped zero split (`o0`, "
        "used by dpwm0 and by dpwm when `max + min >= 0`) is 2 larger for b >= 2 (`NF >> b` has"
        " bit 14 clear). `V_i = 2 (max - T_i) + NF / S` is then a multiple of 6 (every `T_i - "
        "T_j` is a multiple of N: the reference stage gives `R_i = N c_i - sum c`, every "
        "feedback `U_i - U_j` is N times a whole number of units, and the integrators start at "
        "0), as is every decision boundary `j 2 NF / S` (b <= 8): +2 never crosses one, so no "
        "quotient changes.",
    "rtl/mdfqm_gateware/resolution.py:191 quantiser $mux#0 B[12] inv":
        "equivalent by reading, not proven: the reset multiplexer of `offset`/`offset_m` (B is "
        "the reset value): the mutation sets bit 12 of the value held in the clock after a "
        "reset. Both are recomputed every clock, and the divider loads them only with `valid3`,"
        " which a reset clears: the reset value is never loaded.",
    "rtl/mdfqm_gateware/resolution.py:218 quantiser $mux#5 Y[0] inv":
        "equivalent by reading, not proven: the divider's remainder register gets bit 0 "
        "inverted on every write. Its true value after k restoring steps is `2**k V` less a "
        "multiple of `2 NF = 3 * 2**15`, so the error (+1 growing to `2**(k+1) - 1` for an even"
        " V, a constant -1 for an odd one) never moves `2 rem` across `2 NF` within the B = 8 "
        "steps: every quotient bit, hence every output, is the same.",
    "rtl/mdfqm_gateware/resolution.py:219 quantiser $mux#4 B[2] inv":
        "equivalent by reading, not proven: the load multiplexer of the quotient `q` (B is the "
        "0 it is loaded with): the mutation loads 4. The B = 8 shifts of the division that "
        "follow (`run` counts 8 down) push every loaded bit out of the 8-bit `q` before stage 6"
        " reads it.",
    "rtl/mdfqm_gateware/resolution.py:227 quantiser $mux#0 Y[3] inv":
        "equivalent by reading, not proven: the value loaded into the divider (`V_i`, or 0 when"
        " clamped) has bit 3 inverted: +8 when bit 3 is clear, -8 when set. A clamped 0 becomes"
        " 8, still quotient 0. Otherwise the quotient changes only if `V_i` moves across a "
        "boundary `j 2 NF / S`, a multiple of 384 for b <= 8 (so of 16): +8 from a value with "
        "bit 3 clear and -8 from one with bit 3 set stay inside the same block of 16, never "
        "across.",
    "rtl/mdfqm_gateware/resolution.py:337 layout $dff#0 Q[7] const0":
        "equivalent by reading, not proven: bit 7 of the slot step `delta` (`2**(8 - b)`) is "
        "set only for b = 1, whose layout has two slots: `after + delta` is taken once, at the "
        "one slot boundary, and its result is never compared again (no slot follows).",
    "rtl/mdfqm_gateware/resolution.py:341 layout $dff#0 Q[10] cnot1/14":
        "equivalent by reading, not proven: the held slot length `slot_m2` has bit 14 set only "
        "for slots of 16,386 clocks or more, so b = 1 (the period is at most 65,535 clocks); "
        "there it is reloaded into the count only for the last slot, which is held until the "
        "next load (`more` is 0, the count is not read).",
    "rtl/mdfqm_gateware/resolution.py:353 layout $reduce_bool#0 A[5] const1":
        "equivalent by reading, not proven: `more` becomes `i_bbit` alone; it differs only when"
        " a layout has one slot (`i_slots == 0`, b = 0), and a layout is loaded only in a slot "
        "mode, whose b the clamp keeps in 1..max_bits (docs/contract.md; `latch_mode`).",
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#1 B[10] cnot1/23":
        "equivalent by reading, not proven: the AXI front's held write data keeps its value in "
        "a write's clock (B, selected by the write); the mutation changes bit 10 of what it "
        "keeps. After a write the W slot is empty, and the next write cannot issue before a W "
        "handshake reloads the word: the changed value is never written.",
    "rtl/mdfqm_gateware/fronts.py:136 front $mux#4 B[5] inv":
        "equivalent by reading, not proven: the AXI front's held write address keeps its value "
        "in a write's clock; the mutation inverts bit 5 of what it keeps. After a write the AW "
        "slot is empty, and the next write cannot issue before an AW handshake reloads the "
        "address.",
    "rtl/mdfqm_gateware/fronts.py:136 front $mux#2 B[4] const1":
        "equivalent by reading, not proven: the reset value of an AXI front's held address (B, "
        "selected by `rst`) gets bit 4 set; an address is used only once its slot is full, and "
        "a handshake loads it in the same clock the slot fills, so the reset value is never "
        "read (the read address feeds only the register read multiplexer, without side "
        "effects).",
    "rtl/mdfqm_gateware/top.py:435 top $reduce_bool#0 A[10] const0":
        "equivalent by construction, not proven: formal-only logic (the watchdog's ghost count "
        "of the top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/resolution.py:181 core.quantiser $add#0 B[2] const1":
        "equivalent by reading, not proven: the offset of the min-clamped zero split (`o2`, "
        "used by dpwm1 and by dpwm when `max + min < 0`) is 4 larger (bit 2 of `2 NF + NF >> b`"
        " is clear for b <= 8). `V_i = 2 (min - T_i) + 2 NF + NF / S` is a multiple of 6 (every"
        " `T_i - T_j` is a multiple of N: the reference stage gives `R_i = N c_i - sum c`, "
        "every feedback `U_i - U_j` is N times a whole number of units, and the integrators "
        "start at 0), as is every decision boundary `j 2 NF / S`: +4 never crosses one, nor the"
        " sign.",
    "rtl/mdfqm_gateware/resolution.py:250 core.quantiser $and#2 B[4] cnot0/6":
        "equivalent by reading, not proven: bit 6 of `lo_mask` is clear only for b = 0 and b = "
        "1. For b = 1 every quotient is a multiple of 2**7, so bit 4 of `quotient / 2` is 0 and"
        " the extra mask bit changes nothing; for b = 0 (MDFQM) the layout's bounds are loaded "
        "but never used (no slot boundary follows).",
    "rtl/mdfqm_gateware/top.py:217 top $mux#0 A[11] cnot1/16":
        "equivalent by reading, not proven: bit 16 of the ADC trigger counter is set only "
        "65,536 clocks after an update start, and an update lasts at most 65,535 clocks (PERIOD"
        " has 16 bits, and a slot-mode update is PERIOD clocks long too), so the mutation never"
        " acts.",
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[19] inv": _HELD_WRITE_DATA.format(bit=19),
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[1] inv": _HELD_WRITE_DATA.format(bit=1),
    "rtl/mdfqm_gateware/top.py:409 top $or#2 B[0] const0":
        "equivalent by reading, not proven: the mutation drops `trip` from the conditions that "
        "zero the watchdog's quiet count, so in the tripping clock (always an update start) the"
        " count goes up by one instead. From the next clock the latch is set, which zeroes the "
        "count again and holds it there until a clear; the count is read only by `trip`, which "
        "needs the latch clear, and it is not on the bus: the extra count is never read.",
}
