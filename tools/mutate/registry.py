"""The one registry of named mutants (keys: tools/mutate/keys.py):

- :data:`SAMPLE`, the mutants ``make test`` runs (tb/test_mutation_sample.py): at least one per
  block, per fault class and per row of docs/robustness.md, each of which its block's vector
  stimulus must kill; the robustness table's last column is written from it
  (``python -m tools.mutate.sample --docs``; tools/tests/test_mutate.py fails when they
  disagree);
- :data:`READINGS`, what the campaign's survivors were read to be (``make mutate``'s report prints
  each beside its mutant). A reading is an explanation, never a verdict: a mutant counts as
  equivalent only when a check proves it, and a reading's :class:`Proof` is such a check (the
  campaign's equivalence stage runs it, :func:`tools.mutate.stages.run_reading`).

:data:`SAMPLE` is written by ``python -m tools.mutate.sample --write`` (keep its markers; the
test of the registry writes it again and compares); :data:`READINGS` by hand, and a proof added
to a reading is run on the campaign's databases by ``python -m tools.mutate --resume --recheck``
(or on one mutant, ``--block <block> --only '<key>'``).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["READINGS", "SAMPLE", "Proof", "Reading", "Sampled", "reading"]


@dataclass(frozen=True)
class Sampled:
    """A mutant of the sample: its block, its key and why it is there (its fault class, or
    ``row: <words of the docs/robustness.md row whose behaviour its logic implements>``)."""

    block: str
    key: str
    why: str

    @property
    def row(self) -> str | None:
        """The words that find its row of docs/robustness.md, if it names one."""
        return self.why.removeprefix("row: ") if self.why.startswith("row: ") else None


@dataclass(frozen=True)
class Proof:
    """A check that backs a reading: ``asserts`` (Verilog expressions over the original design's
    wires, each written ``{name}`` with its flattened name, e.g. ``{core.sequencer.phase}``; a
    Verilog concatenation keeps a space after its commas, ``{2'b00, {x}}``)
    added to the block's own proof with the mutation's probe (the mutated cell computes what
    the original does, in every state: :func:`tools.mutate.netlist.write_reading_probe`),
    proven by k-induction to ``depth`` clocks (None: the block's). Passing, every assertion and
    the probe hold in every reachable state: the mutant is equivalent to the original under
    the proof's assumptions. The assertions are lemmas the induction needs, proven with it, not
    assumed."""

    asserts: tuple[str, ...]
    depth: int | None = None


@dataclass(frozen=True)
class Reading:
    """Why a surviving mutant survives, as read: ``text`` (an explanation) and, when one exists,
    the :class:`Proof` that backs its claim of equivalence."""

    key: str
    text: str
    proof: Proof | None = None


def reading(key: str) -> Reading | None:
    """The reading of a mutation key, if any."""
    return next((r for r in READINGS if r.key == key), None)


# -- sample: written by tools/mutate/sample.py (--write), not by hand; the comments are the
# -- source text each key names
# -- origin: drawn by `python -m tools.mutate.sample --write --seed 7`
SAMPLE: tuple[Sampled, ...] = (
    # m.d.sync += [t_exact_prev[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]
    Sampled("core",
            "rtl/mdfqm_gateware/integrator.py@5e65dc4d integrator $add#0 Y[18] const1",
            "datapath"),
    # m.d.sync += [t_exact_prev[i].eq(self.o_x[i] + self.i_r[i]) for i in range(n)]
    Sampled("core",
            "rtl/mdfqm_gateware/integrator.py@5e65dc4d integrator $add#2 B[6] const0",
            "datapath"),
    # m.d.comb += fits.eq(Cat(*fits_each).all())
    Sampled("core",
            "rtl/mdfqm_gateware/integrator.py@2df87e8d integrator $reduce_and#0 A[2] inv",
            "row: reference beyond the linear range"),
    # m.d.sync += total.eq(total + phase_code)
    Sampled("core",
            "rtl/mdfqm_gateware/reference.py@2fac9afb reference $add#0 A[11] const0",
            "row: common-mode offset"),
    # m.d.sync += pending[n - 1].eq(~(scaled_n + total))
    Sampled("core",
            "rtl/mdfqm_gateware/reference.py@69b7b9e4 reference $add#0 A[7] cnot0/1",
            "row: extreme codes"),
    # next_values[a].eq(Mux(a_first, *[as_held(values[i], inverted[i], next_inverted[a]) fo...
    Sampled("core",
            "rtl/mdfqm_gateware/sort.py@6efaf944 sort1 $mux#1 Y[3] const1",
            "row: equal references (ties)"),
    # clamped = ~at_least(self.period, self.latency)
    Sampled("core",
            "rtl/mdfqm_gateware/sequencer.py@5e47f921 sequencer $not#0 Y[0] const0",
            "row: update period below the loop latency"),
    # osr_now = Mux(self.osr == 0, 1, self.osr)
    Sampled("core",
            "rtl/mdfqm_gateware/sequencer.py@bb6e191d sequencer $mux#0 B[4] const1",
            "row: OSR 0"),
    # 'policy': Out(1)
    Sampled("core",
            "rtl/mdfqm_gateware/sequencer.py@46508772 sequencer $mux#0 B[0] const1",
            "row: runtime changes of period / OSR / zero policy / mode"),
    # ends = ~self.start & late & (self.sync_in | reached)
    Sampled("core",
            "rtl/mdfqm_gateware/sequencer.py@367c7909 sequencer $and#1 A[0] inv",
            "row: `sync_in` at any time"),
    # start_q, tick_q, sub_one = (Signal(init=1), Signal(init=1), Signal(init=1))
    Sampled("core",
            "rtl/mdfqm_gateware/sequencer.py@057fa2e3 sequencer $mux#2 S[0] const1",
            "row: reset in the middle of an update"),
    # m.d.comb += self.ref.ready.eq(~(busy | full))
    Sampled("core",
            "rtl/mdfqm_gateware/reference.py@1ff14b1e reference $or#0 B[0] const1",
            "row: a reference beat while one is pending"),
    # ofs['o2'].eq(self.i_min * 2 + k_tab[2])
    Sampled("generator",
            "rtl/mdfqm_gateware/resolution.py@af2e4d8c quantiser $mul#0 A[16] const0",
            "datapath"),
    # rem.eq(Mux(fits, trial, rem << 1))
    Sampled("generator",
            "rtl/mdfqm_gateware/resolution.py@f6a5e4a9 quantiser $mux#1 B[1] const0",
            "datapath"),
    # bits_now = Mux(self.bits < 1, 1, Mux(self.bits > self.max_bits, self.max_bits, self.b...
    Sampled("generator",
            "rtl/mdfqm_gateware/sequencer.py@f8511c61 sequencer $lt#0 A[3] const1",
            "row: illegal generator `mode`"),
    # 'upper': Out(phases)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@d54a41ba~ top $not#0 Y[1] inv",
            "pin polarity"),
    # 'upper': Out(phases)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@d54a41ba~ top $not#0 Y[2] inv",
            "pin polarity"),
    # 'fault': Out(1)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@95f6e967 top $mux#0 S[0] const1",
            "two events in one clock"),
    # 'fault': Out(1)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@95f6e967 top $mux#2 S[0] const0",
            "two events in one clock"),
    # 'upper': Out(phases)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@d54a41ba~ top $not#0 Y[0] inv",
            "row: any pair of pin polarities"),
    # dt_expr = Mux(dead_seen < self.dead_min, self.dead_min, dead_seen)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@8122c414 leg0 $mux#0 B[8] inv",
            "row: dead time below the elaboration floor"),
    # return ((c >= self.dead) & (c >= self.dead_min) & run_ok, c < self.min_pulse)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@c0cfabdb leg1 $gt#1 A[10] cnot0/0",
            "row: a commanded pulse shorter than the minimum pulse"),
    # m.d.comb += self.short_edge_now.eq(Mux(drive & self.active, (cmd ^ cmd_lat) & ~follow...
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@2cde9ffd top $mux#0 B[1] inv",
            "row: a slot or an update shorter than the dead time plus the minimum pulse"),
    # m.d.comb += fault_active.eq(self.fault_input | self.fault)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@8e432b7f top $or#0 A[0] const1",
            "row: fault input chatter, fault during a dead time"),
    # drive_if_clear.eq(Mux(self.update, self.enable, self.active) & ~self.stop)
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@2c51e235 top $and#0 Y[0] inv",
            "row: enable toggled in the middle of an update"),
    # now_if_fault.eq(Mux(kill_if_fault, 0, Mux(held, self.reaction, f)))
    Sampled("driver",
            "rtl/mdfqm_gateware/driver.py@68c499a9 top $mux#1 Y[1] cnot0/0",
            "row: a fault or a watchdog trip with an active short circuit chosen"),
    # 'lower': Out(1)
    Sampled("top_wb",
            "rtl/mdfqm_gateware/driver.py@08542599 driver.leg1 $dff#0 Q[0] inv",
            "pin polarity"),
    # 'upper': Out(1)
    Sampled("top_wb",
            "rtl/mdfqm_gateware/driver.py@a6cd42bb driver.leg1 $dff#0 Q[0] inv",
            "pin polarity"),
    # request.eq(bus.cyc & bus.stb & ~bus.ack)
    Sampled("top_wb",
            "rtl/mdfqm_gateware/fronts.py@dfe5fe16 front $and#0 A[0] const1",
            "bus handshake (cyc or stb alone)"),
    # request.eq(bus.cyc & bus.stb & ~bus.ack)
    Sampled("top_wb",
            "rtl/mdfqm_gateware/fronts.py@dfe5fe16 front $and#0 B[0] const1",
            "bus handshake (cyc or stb alone)"),
    # m.d.comb += turn_ons.eq(sum((driver.event[i] for i in range(n))))
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@99c051d0 top $add#0 Y[1] const1",
            "two events in one clock"),
    # m.d.comb += turn_ons.eq(sum((driver.event[i] for i in range(n))))
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@99c051d0 top $add#2 Y[0] cnot1/1",
            "two events in one clock"),
    # request.eq(bus.cyc & bus.stb & ~bus.ack)
    Sampled("top_wb",
            "rtl/mdfqm_gateware/fronts.py@dfe5fe16 front $and#1 Y[0] const1",
            "row: Wishbone: `stb` without `cyc`"),
    # m.d.comb += turn_ons.eq(sum((driver.event[i] for i in range(n))))
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@99c051d0 top $add#1 Y[1] const0",
            "row: two events in one clock: a register write"),
    # bits_now = Mux(self.bits < 1, 1, Mux(self.bits > self.max_bits, self.max_bits, self.b...
    Sampled("top_wb",
            "rtl/mdfqm_gateware/sequencer.py@f8511c61 core.sequencer $mux#1 S[0] inv",
            "row: `MODULATION` written with a mode not built in"),
    # status_next = irq_status & ~cleared | irq_events
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@657c67c9 top $and#0 A[0] const1",
            "row: `IRQ_STATUS` written with any value"),
    # m.d.sync += dead.eq(Mux(clamp['below_floor'], self.dead_min, _saturate(word, 65535, c...
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@3f01def9 top $mux#0 B[13] inv",
            "row: any value to any register"),
    # m.d.comb += trip.eq((timeout != 0) & ~tripped & start & ~arrival & ~(timeout + quiet_...
    Sampled("top_wb",
            "rtl/mdfqm_gateware/top.py@bec9afda top $and#3 Y[0] const0",
            "row: the controller stops sending references"),
    # do_write.eq(aw_full & w_full & (~bus.bvalid | bus.bready))
    Sampled("top_axi",
            "rtl/mdfqm_gateware/fronts.py@5c6f86d5 front $or#0 Y[0] const1",
            "bus handshake (cyc or stb alone)"),
    # do_write.eq(aw_full & w_full & (~bus.bvalid | bus.bready))
    Sampled("top_axi",
            "rtl/mdfqm_gateware/fronts.py@5c6f86d5 front $and#1 A[0] const1",
            "bus handshake (cyc or stb alone)"),
    # status_next = irq_status & ~cleared | irq_events
    Sampled("top_axi",
            "rtl/mdfqm_gateware/top.py@657c67c9 top $or#0 Y[3] const0",
            "two events in one clock"),
    # status_next = irq_status & ~cleared | irq_events
    Sampled("top_axi",
            "rtl/mdfqm_gateware/top.py@657c67c9 top $not#0 A[4] const0",
            "two events in one clock"),
    # return Mux(mask.bit_select(address, 1), AXI_RESP_OKAY, AXI_RESP_SLVERR)
    Sampled("top_axi",
            "rtl/mdfqm_gateware/fronts.py@dae2c362 front $shift#1 A[1] inv",
            "row: AXI4-Lite: an access to a word that holds no register"),
)
# -- end of the sample


#: a leg's ``hi`` at 256 (the leg on for the whole update) changed to another value past it
_HI_PAST_LAST = (
    "{what}. `hi = lo + on = floor(m / 2) + 2**B - m` is at least 128, and {when} only at `hi = "
    "256` (m = 0: the leg on for the whole update). The mutant's {value} is past the last slot's "
    "index as 256 is: the turn-off compare at the load (`delta == hi`, delta <= 128) fails "
    "either way, and a match of `after == 256` at the advance into the last slot is never used "
    "(the last slot is held until the next load): the leg stays on.")


READINGS: tuple[Reading, ...] = (
    Reading(
        "rtl/mdfqm_gateware/sequencer.py@a431f61e sequencer $dff#0 Q[10] cnot1/8",
        "not equivalent, out of the tests' reach: `phase` bit 10 is inverted while bit 8 is set "
        "(`phase` >= 256); its only reader, the sync restart's `phase >= latency - 1`, holds "
        "either way, unless the mutated count wraps past 65535 inside one update (an update of "
        "more than about 64,500 clocks) and a sync arrives in the few clocks after the wrap."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@9dbd1841 core.quantiser $dff#0 Q[3] cnot0/7",
        _HI_PAST_LAST.format(what="bit 3 of the quantiser's `hi` of leg 0 is inverted while its "
                                  "bit 7 is clear", when="its bit 7 is clear", value=264)),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@9dbd1841 core.quantiser $mux#1 Y[6] cnot1/8",
        _HI_PAST_LAST.format(what="bit 6 of what the quantiser's `hi` of leg 1 is loaded with "
                                  "is inverted while its bit 8 is set",
                             when="its bit 8 is set", value=320)),
    Reading(
        "rtl/mdfqm_gateware/integrator.py@19408d28 integrator $logic_not#1 A[1] const0",
        "the integrator's fit test `top == 0` ignores bit 1 of `top`, the bits of `X' = T - U` "
        "from the word's sign bit up: it would take as fitting a positive overflow of at least "
        "twice the bound (`X'_i >= 2**18` at width 16). `T_i <= x_max + r_bound < 2**18`, so "
        "that needs `U_i < 0`, leg i off while another is on; but a `T_i` that large is the "
        "largest `T`, and every non-zero state the largest-duty rule can choose turns the leg "
        "of the largest `T` on."),
    Reading(
        "rtl/mdfqm_gateware/arith.py@7a1a5f4d sort1 $sub#1 B[15] const1",
        "sort1's second compare (the first layer's larger value against leg 2) reads that "
        "value with its bit 13 set: it puts it first while leg 2's `T` lies up to 2**13 "
        "above it, so `rho` comes out as (that value, leg 2's, the smaller one). By the "
        "contract's duties that moves the split `delta <= 2**13` between those two legs to "
        "`d_1 = -delta` and adds `delta` to both `d_0` and `d_2`: their order, and the "
        "smallest-j tie-break between them, are unchanged, and the true `d_1 = delta` never "
        "won (the duties sum to `N FULL = 49,152`, so the largest is at least 16,384); `j*` "
        "is 0 or 2 as before and `j* = 2` turns on the same two legs. The state, the feedback "
        "and the integrators are the same (N = 3, largest duty; the core outputs no sorted "
        "value); 3.6 million clocks show no difference."),
    Reading(
        "rtl/mdfqm_gateware/sequencer.py@46508772 sequencer $mux#1 A[0] inv",
        "the latched zero policy is loaded inverted at each update start and then toggles every "
        "clock (the inversion sits on the hold path too); the decoder reads it only in the "
        "clock its valid is high, a fixed number of clocks after the start, where the toggles "
        "have given the loaded value back (as the vector runs show)."),
    Reading(
        "rtl/mdfqm_gateware/selector.py@901d568a sort2 $mux#3 B[0] const1",
        "sort2's index after a reset is 1 instead of 0; it is read only with sort2's valid, "
        "which is low until the first update's result, and that result overwrites it."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@af2e4d8c quantiser $add#0 B[16] const1",
        "bit 16 of the quantiser's offset constant `2 NF + NF / 2**b` (g2 = 2) is forced to 1. "
        "At width 16 (`NF = 3 * 2**14`) that bit is set for every b >= 1 and clear only for "
        "b = 0, and the quantiser's results are used only for a slot-mode update, whose b is "
        "at least 1."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@a1acd3f0 layout $sub#0 A[3] cnot1/2",
        "the slot layout's count of slots still to begin is decremented from a value with bit 3 "
        "inverted while bit 2 is set: the count visits other values, but from every load it "
        "can have (`S - 1 = 2**b - 1`, b = 1..8) it reaches 1, where the last slot begins, "
        "after the same number of slots (the +8 and -8 alternate; checked for the eight loads "
        "by a simulation of the count-down alone, not a proof; from an even load it would "
        "differ)."),
    Reading(
        "rtl/mdfqm_gateware/sequencer.py@e592cfaa sequencer $dff#0 Q[6] inv",
        "bit 6 of the minimum-period count-down `floor` is inverted as read (by its decrement "
        "and its sign test alike): the count runs `r -> (r - 1) xor 64`, whose sign bit turns "
        "on after as many clocks as the plain count's from every load of the table "
        "(`minimum - 3` <= 253; checked for each by a simulation of the count-down alone, "
        "not a proof), and only the sign is read."),
    Reading(
        "rtl/mdfqm_gateware/top.py@73dbe7f4 top $and#0 A[0] const1",
        "the clear of the pending register beat (`ref_pending & core.ref.ready`) no longer "
        "tests `ref_pending`: it then clears a flag that is already 0, which changes nothing."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@096824b8 core.quantiser $dff#1 Q[3] cnot1/4",
        "bit 3 of leg 1's instant `V` is flipped while bit 4 is set; the divider takes `V` "
        "from bit `low` (7 at width 16 and B = 8) up and the top quotient bit compares `V` "
        "with `2 NF = 3 * 2**15`, whose low 15 bits are 0: no reader sees bit 3."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@e304e1b0 core.quantiser $sub#2 Y[10] inv",
        "bit 10 of leg 2's restoring trial `2 rem - 2 NF` is inverted; the trial is 12 bits, "
        "its sign (bit 11) decides, and the remainder it loads is 10 bits wide: no reader sees "
        "bit 10."),
    Reading(
        "rtl/mdfqm_gateware/top.py@b3f43508 top $dff#0 Q[58] cnot1/22",
        "not equivalent, out of any simulation's reach: bit 26 of EVENTS[1] is flipped while "
        "its bit 22 is set, after 2**22 turn-ons of leg 1 (about 4 million)."),
    Reading(
        "rtl/mdfqm_gateware/arith.py@7a1a5f4d core.sort1 $sub#2 B[7] const0",
        "not equivalent, a hole of the top's stimulus: one of sort1's compares reads one leg's "
        "T without its bit 5, which reorders two legs whose T are a few steps apart; the state "
        "moves only when the largest candidates are close at the same update. The top's "
        "SortTies aims at ties (legs equal or one step apart, candidates equal or close), "
        "not at that pair of coincidences."),
    Reading(
        "rtl/mdfqm_gateware/top.py@b3f43508 top $mux#4 A[28] const0",
        "not equivalent, out of any simulation's reach: bit 28 of EVENTS[0] (through the "
        "counters' clear multiplexer) stuck at 0 shows after 2**28 turn-ons of leg 0."),
    Reading(
        "rtl/mdfqm_gateware/top.py@05d7ccc2 top $dff#0 Q[20] const0",
        "not equivalent, out of any simulation's reach: EVENTS_TOTAL bit 20 stuck at 0 shows "
        "after 2**20 turn-ons without a COUNT_CLEAR."),
    Reading(
        "rtl/mdfqm_gateware/top.py@05d7ccc2 top $mux#0 A[1] cnot1/11",
        "not equivalent, out of the runs' reach: EVENTS_TOTAL's next value has bit 1 flipped "
        "while bit 11 is set, after 2,048 turn-ons without a COUNT_CLEAR; the runs clear the "
        "counters long before (a narrower counter_width would bring it in reach)."),
    Reading(
        "rtl/mdfqm_gateware/top.py@4945802d top $and#0 Y[1] const0",
        "not equivalent, out of any simulation's reach: the interrupt ignores IRQ_STATUS bit 1 "
        "(COUNTER_WRAP), which only EVENTS_TOTAL passing 2**32 sets."),
    Reading(
        "rtl/mdfqm_gateware/top.py@199ced1f top $not#0 A[0] const0",
        "not equivalent, out of any simulation's reach: the COUNTER_WRAP event ignores a "
        "COUNT_CLEAR in its clock, which matters only when EVENTS_TOTAL passes 2**32."),
    Reading(
        "rtl/mdfqm_gateware/top.py@5becb77d top $dff#0 D[13] const0",
        "not equivalent, out of the runs' reach: WATCHDOG_TRIPS bit 13 stuck at 0 shows after "
        "8,192 watchdog trips without a COUNT_CLEAR."),
    Reading(
        "rtl/mdfqm_gateware/resolution.py@d841a694 core.quantiser $add#0 B[1] inv",
        "the offset `2 max(T) + NF / 2**b` of a g = 0 update gains 2 (bit 1 of the constant is "
        "0 for every b <= 8), so each instant `V_i = offset - 2 T_i` moves up by 2, its "
        "smallest step. No reachable update has an instant that this moves across a decision "
        "boundary: the legs' `T` stay congruent modulo N (reset empties the integrators; each "
        "update adds `R_i = N c_i - sum c` and takes `U_i = (sum m - N m_i) FULL / 2**B`, the "
        "same for every leg modulo N), so with N = 3 every `V_i = 2 (max T - T_i) + NF / 2**b` "
        "is a multiple of 6, and so is every boundary `j 2 NF / 2**b`: an instant sits on one "
        "or at least 6 (three of its steps) below it."),
    Reading(
        "rtl/mdfqm_gateware/selector.py@e922e0a4 core.candidates $dff#0 Q[17] const0",
        "bit 17 of candidate 0, `NF - (rho_0 - rho_(N-1))`, is forced to 0: a candidate in "
        "[0, NF] (`NF = 49,152 < 2**17`) has it clear already, and a negative one (beyond the "
        "linear range) only becomes more negative. A negative candidate 0 is never sort2's "
        "maximum: the other candidates, the duties `rho_(j-1) - rho_j`, sum to "
        "`rho_0 - rho_(N-1) > NF > 0`, so one of them is positive; sort2's index, all the "
        "candidates give downstream, is the same."),
    Reading(
        "rtl/mdfqm_gateware/sequencer.py@e917680f core.sequencer $dff#0 Q[0] const0",
        "bit 0 of the latched period `P` is forced to 0. Its only reader is the generator's "
        "slot length `P >> b`: a slot-mode update shifts it right b >= 1 times (bit 0 goes "
        "first), and an MDFQM update loads it unused (no slot follows its state)."),
    Reading(
        "rtl/mdfqm_gateware/reference.py@6144722f core.reference $mux#2 B[10] inv",
        "a reset leaves bit 10 of the reference stage's third pending value set instead of "
        "clear. Nothing reads the pending values before a beat has been formed into them (the "
        "stage is not full after a reset), and forming a beat writes all N; a register written "
        "before it is read needs no reset value (the reset could go, and this mutant with it)."),
    Reading(
        "rtl/mdfqm_gateware/generator.py@a1d75b8e core $mux#0 B[3] const1",
        "a reset loads 8 instead of 0 into the slot count `slot_m2` (bit 3 of its reset value "
        "set). The next clock after the reset writes `slot_len - 2` into it, as every clock "
        "does, and the slot layout reads it only when an update commits, at least L clocks "
        "after a reset: its reset value is never read (the reset could go, and this mutant "
        "with it)."),
    Reading(
        "rtl/mdfqm_gateware/top.py@76bb7213 top $pmux#0 B[280] cnot1/150",
        "not equivalent, out of any simulation's reach: a read of WATCHDOG_TRIPS returns bit "
        "24 set while EVENTS_0 holds bit 22, after 4,194,304 turn-ons of leg 0 without a "
        "COUNT_CLEAR (the AXI4-Lite block's 8-bit counters put every counter bit in a run's "
        "reach; the Wishbone one is the drop-in's 32 bits)."),
    Reading(
        "rtl/mdfqm_gateware/top.py@146f00d4 top $add#0 Y[23] cnot1/30",
        "not equivalent, out of any simulation's reach: a switching counter's bit 23 is flipped "
        "while its bit 30 is set, after 2**30 turn-ons of one leg without a COUNT_CLEAR."),
)
