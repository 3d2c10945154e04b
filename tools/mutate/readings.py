"""Why a surviving mutant survives, as read from its counterexample and the tests: mutation key
-> a sentence (the report prints it beside the survivor). Keys name source and kind, not cells,
so a reading stays with its mutant when the design is rebuilt; a key that no longer occurs is
simply not printed."""

__all__ = ["READINGS"]

#: a small constant added to the svpwm offset (``k1``: its low bits are always 0)
_SVPWM_LATTICE = (
    "equivalent by reading, not proven: {what}, so the svpwm offset and every `V_i` are "
    "{delta} larger. `V_i = (max - T_i) + (min - T_i) + NF + NF / S` is a multiple of 3 (every "
    "`T_i - T_j` is a multiple of N = 3: the reference stage gives `R_i = N c_i - sum c`, every "
    "feedback `U_i - U_j` is N times a whole number of units, the integrators start at 0 and a "
    "saturated update holds them all), as is every decision boundary `j 2 NF / S` and the "
    "clamp's ends 0 and `2 NF`: +{delta} never reaches one from below, so no quotient, clamp or "
    "output changes.")
#: a register that toggles a bit every clock while it holds, read at one clock of the update
_TOGGLED_WHILE_HELD = (
    "equivalent by reading, not proven: {what} toggles every clock while the register holds "
    "({how}); it is loaded at an update start and read (through `p_lat`, `slot_len`, "
    "`slot_m2`) only when the layout loads, a fixed number of clocks after the start, where the"
    " vector runs show it holding its loaded value.")
#: where the mutation sits, for _TOGGLED_WHILE_HELD
_ON_NEXT_STATE = "the mutation sits on its next-state path"
_ON_OUTPUT = ("the mutation sits on its output, which the hold path feeds back: what is read "
              "alternates between the loaded value and the mutated one")

#: the AXI front's held write data, a bit of its reset value changed
_RESET_WRITE_DATA = (
    "equivalent by reading, not proven: the reset multiplexer of the AXI front's held write "
    "data (select `rst`): the mutation {change} bit {bit} of its reset value; the word is loaded"
    " by the W handshake before any write is issued (`do_write` needs `w_full`), and the "
    "register file reads `w_data` only with `w_en`, so the reset value is never used.")
#: what the AXI front's held write data keeps in a write's clock, a bit changed
_KEPT_WRITE_DATA = (
    "equivalent by reading, not proven: the AXI front's held write data keeps its value in a "
    "write's clock (B, selected by the write); the mutation changes bit {bit} of what it keeps. "
    "After a write the W slot is empty, and the next write cannot issue before a W handshake "
    "reloads the word: the changed value is never written.")
#: a bit of the dpwm0 offset constant ``k0`` (always 0) set high above the divider's operand
_K0_HIGH_BIT = (
    "equivalent by reading, not proven: bit {bit} of the {where}dpwm0 offset constant `k0 = NF"
    " >> b` (always 0) is set{when}, so the max-clamped zero split's `V_i` grow by 2**{bit}. "
    "`V_i = 2 (max - T_i) + NF / S` is positive whenever that split is used and below 2**21 "
    "while it is below `2 NF` (the only case the divider takes it), so the clamp does not "
    "change; the divider takes `V_i >> 7` in 10 bits (its operand narrowed to the bits a "
    "quotient depends on), where 2**{bit} >> 7 falls off; the top quotient bit comes from "
    "`V_i - 2 NF` (the other constant), unchanged.")

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
    "rtl/mdfqm_gateware/top.py:383 top $and#0 A[2] cnot1/1":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/top.py:435 top $reduce_bool#0 A[6] const0":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/resolution.py:181 quantiser $add#0 B[1] cnot0/14":
        "equivalent by reading, not proven: the offset of the max-clamped zero split (`o0`, "
        "used by dpwm0 and by dpwm when `max + min >= 0`) is 2 larger for b >= 2 (`NF >> b` has"
        " bit 14 clear). `V_i = 2 (max - T_i) + NF / S` is then a multiple of 6 (every `T_i - "
        "T_j` is a multiple of N: the reference stage gives `R_i = N c_i - sum c`, every "
        "feedback `U_i - U_j` is N times a whole number of units, and the integrators start at "
        "0), as is every decision boundary `j 2 NF / S` (b <= 8): +2 never crosses one, so no "
        "quotient changes.",
    "rtl/mdfqm_gateware/resolution.py:193 quantiser $mux#0 B[12] inv":
        "equivalent by reading, not proven: the reset multiplexer of `offset`/`offset_m` (B is "
        "the reset value): the mutation sets bit 12 of the value held in the clock after a "
        "reset. Both are recomputed every clock, and the divider loads them only with `valid3`,"
        " which a reset clears: the reset value is never loaded.",
    "rtl/mdfqm_gateware/resolution.py:343 layout $dff#0 Q[7] const0":
        "equivalent by reading, not proven: bit 7 of the slot step `delta` (`2**(8 - b)`) is "
        "set only for b = 1, whose layout has two slots: `after + delta` is taken once, at the "
        "one slot boundary, and its result is never compared again (no slot follows).",
    "rtl/mdfqm_gateware/resolution.py:347 layout $dff#0 Q[10] cnot1/14":
        "equivalent by reading, not proven: the held slot length `slot_m2` has bit 14 set only "
        "for slots of 16,386 clocks or more, so b = 1 (the period is at most 65,535 clocks); "
        "there it is reloaded into the count only for the last slot, which is held until the "
        "next load (`more` is 0, the count is not read).",
    "rtl/mdfqm_gateware/resolution.py:359 layout $reduce_bool#0 A[5] const1":
        "equivalent by reading, not proven: `more` becomes `i_bbit` alone; it differs only when"
        " a layout has one slot (`i_slots == 0`, b = 0), and a layout is loaded only in a slot "
        "mode, whose b the clamp keeps in 1..max_bits (docs/contract.md; `latch_mode`).",
    "rtl/mdfqm_gateware/top.py:435 top $reduce_bool#0 A[10] const0":
        "equivalent by construction, not proven: formal-only logic (the watchdog's ghost count "
        "of the top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/resolution.py:183 core.quantiser $add#0 B[2] const1":
        "equivalent by reading, not proven: the offset of the min-clamped zero split (`o2`, "
        "used by dpwm1 and by dpwm when `max + min < 0`) is 4 larger (bit 2 of `2 NF + NF >> b`"
        " is clear for b <= 8). `V_i = 2 (min - T_i) + 2 NF + NF / S` is a multiple of 6 (every"
        " `T_i - T_j` is a multiple of N: the reference stage gives `R_i = N c_i - sum c`, "
        "every feedback `U_i - U_j` is N times a whole number of units, and the integrators "
        "start at 0), as is every decision boundary `j 2 NF / S`: +4 never crosses one, nor the"
        " sign.",
    "rtl/mdfqm_gateware/resolution.py:256 core.quantiser $and#2 B[4] cnot0/6":
        "equivalent by reading, not proven: bit 6 of `lo_mask` is clear only for b = 0 and b = "
        "1. For b = 1 every quotient is a multiple of 2**7, so bit 4 of `quotient / 2` is 0 and"
        " the extra mask bit changes nothing; for b = 0 (MDFQM) the layout's bounds are loaded "
        "but never used (no slot boundary follows).",
    "rtl/mdfqm_gateware/top.py:217 top $mux#0 A[11] cnot1/16":
        "equivalent by reading, not proven: bit 16 of the ADC trigger counter is set only "
        "65,536 clocks after an update start, and an update lasts at most 65,535 clocks (PERIOD"
        " has 16 bits, and a slot-mode update is PERIOD clocks long too), so the mutation never"
        " acts.",
    "rtl/mdfqm_gateware/top.py:409 top $or#2 B[0] const0":
        "equivalent by reading, not proven: the mutation drops `trip` from the conditions that "
        "zero the watchdog's quiet count, so in the tripping clock (always an update start) the"
        " count goes up by one instead. From the next clock the latch is set, which zeroes the "
        "count again and holds it there until a clear; the count is read only by `trip`, which "
        "needs the latch clear, and it is not on the bus: the extra count is never read.",
    "rtl/mdfqm_gateware/resolution.py:195 quantiser $add#0 B[0] cnot1/7":
        _SVPWM_LATTICE.format(what="bit 0 of `k1 = NF + NF >> b` (always 0) follows bit 7, "
                                   "set for b = 7 and 8", delta=1),
    "rtl/mdfqm_gateware/resolution.py:37 quantiser $dff#1 Q[1] inv":
        _SVPWM_LATTICE.format(what="bit 1 of the registered `k1 = NF + NF >> b` (always 0) "
                                   "is inverted", delta=2),
    "rtl/mdfqm_gateware/sequencer.py:178 sequencer $dff#0 D[9] cnot0/11":
        _TOGGLED_WHILE_HELD.format(what="bit 9 of `minimum` (the minimum period; bit 11 is "
                                        "always clear: it is at most 2**B)",
                                   how=_ON_NEXT_STATE),
    "rtl/mdfqm_gateware/sequencer.py:178 sequencer $dff#0 Q[6] inv":
        _TOGGLED_WHILE_HELD.format(what="bit 6 of `minimum` (the minimum period)",
                                   how=_ON_OUTPUT),
    "rtl/mdfqm_gateware/sequencer.py:179 sequencer $dff#0 Q[5] cnot1/1":
        _TOGGLED_WHILE_HELD.format(what="bit 5 of `period_lat` (the latched period), while its "
                                        "bit 1 is set,", how=_ON_OUTPUT),
    "rtl/mdfqm_gateware/resolution.py:263 quantiser $and#0 B[0] cnot0/2":
        "equivalent by reading, not proven: bit 0 of the slot-grid mask `lo_mask` (set only for "
        "b = 8) is inverted while its bit 2 is clear (b < 6), so `lo = (m >> 1) & lo_mask` takes "
        "bit 1 of the quotient `m` too. At b < 6 the quotient's low B - b >= 3 bits are 0 (after "
        "its b-th step the divider shifts in zeros: `fits & (want != 0)`), so that bit is 0 and "
        "`lo` is unchanged.",
    "rtl/mdfqm_gateware/resolution.py:335 layout $mux#0 Y[7] const0":
        "equivalent by reading, not proven: the layout's `lo` of a leg never has bit 7 set. `lo ="
        " floor(m / 2)` on the slot grid is at most `2**(B - 1)` = 128, and 128 only for `m = "
        "2**B`: a leg off for the whole update, whose `hi = lo + 0` is 128 too. At that boundary "
        "the original turns the leg on and off at once (off wins); the mutant's `lo = 0` is never"
        " compared true (`after` >= 2 delta). Either way the leg stays off.",
    "rtl/mdfqm_gateware/resolution.py:251 quantiser $dff#1 Q[0] cnot1/7":
        "equivalent by reading, not proven: bit 0 of the quantiser's `lo` of leg 1 follows bit 7,"
        " which is set only for `lo = 128` (`m = 2**B`: the leg off for the whole update, `on = "
        "0`). The mutant's `lo` and `hi = lo + on` are both 129: the layout turns the leg on and "
        "off in the same slot (off wins) or, for b < 8, never (129 is off the slot grid), and "
        "`first` is `lo == 0` either way: the leg stays off.",
    "rtl/mdfqm_gateware/resolution.py:216 quantiser $sub#0 A[3] const0":
        "equivalent by reading, not proven: the divider's step count `run` (B = 8 at the load) "
        "counts 8 -> 15 instead of 8 -> 7 (bit 3 cleared before the decrement), so the divider "
        "runs 16 steps, not 8. The layout bounds and the sum trees take the quotient in the clock"
        " after the 8th step (the valid pipeline, not `run`, says when), and the extra steps only"
        " shift bits through `q` and `rem` after that, until the next load (which sets `run`).",
    "rtl/mdfqm_gateware/sequencer.py:188 sequencer $mux#0 A[10] const0":
        "equivalent by reading, not proven: bit 10 of the minimum-period count-down `floor` is "
        "cleared after each decrement. Only its sign is read. It starts at `minimum - 3` <= 253, "
        "below 1024, so it turns negative in the same clock; then it falls twice as fast (each "
        "value with bit 10 set is skipped) but stays negative: it would wrap only after 65,536 "
        "clocks of negative values, and every update (at most 65,535 clocks) reloads it first.",
    "rtl/mdfqm_gateware/sequencer.py:191 sequencer $sub#0 A[15] const0":
        "equivalent by reading, not proven: the minimum-period count-down `floor` (18 bits, "
        "signed) is decremented with its bit 15 cleared. Only its sign is read. It starts at "
        "`minimum - 3` <= 253, below 2**15, so nothing changes until it is negative; from -1 on, "
        "each value with bit 15 set falls by 2**15 more, but it stays negative for 65,536 clocks "
        "(counted on the mutant's arithmetic), and every update (at most 65,535 clocks) reloads "
        "it first.",
    "rtl/mdfqm_gateware/sequencer.py:193 sequencer $lt#0 B[3] cnot1/7":
        "equivalent by reading, not proven: `period_lat < minimum` compares against `minimum + 8`"
        " when bit 7 of the minimum is set (b = 7, 8: the minimum is `2**b`). A period in `[2**b,"
        " 2**b + 8)` then gives `P = 2**b` instead of the period; P is read only as `slot_len = P"
        " >> b`, which is 1 either way.",
    "rtl/mdfqm_gateware/resolution.py:375 core.layout $sub#0 Y[6] cnot1/15":
        "equivalent by reading, not proven: the layout's slot count-down decrements only while it"
        " is not negative, and a slot is at most 32,767 clocks (b >= 1, P <= 65,535), so bit 15 "
        "of `count - 1` is set only for -1; the mutation makes that -65, still negative, and a "
        "negative count is only tested for its sign (and reloaded at the slot's end).",
    "rtl/mdfqm_gateware/sequencer.py:188 core.sequencer $mux#0 Y[10] inv":
        "equivalent by reading, not proven: bit 10 of the minimum-period count-down `floor` is "
        "inverted on every write, loads included, so the register alternates between the true "
        "count and the true count xor 1024. Only its sign is read: the true count starts at "
        "`minimum - 3` <= 253, and a value in [0, 1023] xor 1024 is still positive, a negative "
        "one still negative (no wrap within an update): the sign is the true one in every clock.",
    "rtl/mdfqm_gateware/resolution.py:219 core.quantiser $mul#2 A[0] const1":
        "a hole in the top's stimulus (the generator's `boundaries` scenario covers it): `2 T_i` "
        "is taken with bit 0 of `T_i` set, so an even `T_i` gives `V_i` 2 smaller. That changes a"
        " quotient only when `V_i` sits exactly on a decision boundary (a multiple of `2 NF / "
        "S`), which the top's closed-loop runs reach only by chance (the deeper run of seed 2001 "
        "does: 141 mismatches); the top has no trials from reset on the boundary grid in a "
        "slot mode.",
    "rtl/mdfqm_gateware/sequencer.py:178 core.sequencer $dff#0 D[7] inv":
        _TOGGLED_WHILE_HELD.format(what="bit 7 of `minimum` (the minimum period)",
                                   how=_ON_NEXT_STATE),
    "rtl/mdfqm_gateware/resolution.py:364 core.layout $eq#1 A[8] const0":
        "equivalent by reading, not proven: the layout's turn-off compare of leg 1 takes `after` "
        "with bit 8 cleared. `after` (the scaled index of the slot after the next) has bit 8 set "
        "only from 2**B on, the index of a slot past the last one: that compare is made at the "
        "advance into the last slot and its result is never used (the last slot is held until the"
        " next load, which sets the toggles afresh). Below 2**B the compare is unchanged.",
    "rtl/mdfqm_gateware/sequencer.py:178 core.sequencer $dff#0 Q[3] cnot1/4":
        "a hole in the top's stimulus, not read as equivalent: `minimum` is read as 28 instead of"
        " 20 (bit 3 follows bit 4, set only in the minimum 20 of b <= 4). P = max(period, "
        "minimum) then differs for periods of 20 to 27 clocks in a slot mode at b <= 4, which the"
        " top's runs never write (their periods are 90, 130, 170 or 4400-6000 clocks, or a random"
        " word); the generator's runs have such periods.",
    "rtl/mdfqm_gateware/top.py:462 top $not#0 A[0] const0":
        "equivalent by reading, not proven: the inverter is the `~tripped` of the watchdog's trip"
        " test (top.py:408; Yosys merged it with the same inverter of a cover at line 462 and "
        "kept that line as its source); the mutation reads the latch as clear there. While the "
        "latch is set, `quiet` is held at 0 (the latch is in its clearing condition, and the trip"
        " clock zeroes it too), so `quiet >= TIMEOUT` (TIMEOUT not 0) is false and no trip "
        "follows either way.",
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
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[19] inv":
        _RESET_WRITE_DATA.format(change="inverts", bit=19),
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[1] inv":
        _RESET_WRITE_DATA.format(change="inverts", bit=1),
    "rtl/mdfqm_gateware/top.py:371 top $mux#0 A[3] cnot1/14":
        "not equivalent by reading, not killed by this block's runs: bit 3 of the ADC trigger "
        "counter toggles once it is past 16,384, so a trigger at an offset past 16,384 comes at "
        "the wrong clock. The AXI4-Lite top's runs (50k clocks) have no update that long; the "
        "Wishbone top's long runs have one (the same logic, killed there).",
    "rtl/mdfqm_gateware/top.py:437 top $logic_not#0 A[3] const0":
        "a hole, not equivalent by reading: the `TIMEOUT == 0` test of the watchdog (top.py:409; "
        "Yosys merged it with the same test in the formal ghost at line 437, whose source it "
        "kept, so the proof sees the mutation too) ignores bit 3: a TIMEOUT of 8 acts as off. The"
        " top's runs trip the watchdog with TIMEOUT 2 and 4 only, and write 8 only in the limit "
        "writes (gates off, never long enough to trip).",
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[21] const1":
        _RESET_WRITE_DATA.format(change="sets", bit=21),
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#1 B[10] cnot1/23": _KEPT_WRITE_DATA.format(bit=10),
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#1 B[7] cnot0/30": _KEPT_WRITE_DATA.format(bit=7),
    "rtl/mdfqm_gateware/resolution.py:181 core.quantiser $add#0 B[17] cnot0/9":
        _K0_HIGH_BIT.format(bit=17, where="", when=" unless bit 9 is (b = 5, 6)"),
    "rtl/mdfqm_gateware/resolution.py:37 core.quantiser $dff#0 Q[20] const1":
        _K0_HIGH_BIT.format(bit=20, where="registered ", when=""),
}
