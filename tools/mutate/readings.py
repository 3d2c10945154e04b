"""Why a surviving mutant survives, as read from its counterexample and the tests: mutation key
-> a sentence (the report prints it beside the survivor). Keys name source and kind, not cells,
so a reading stays with its mutant when the design is rebuilt; a key that no longer occurs is
simply not printed."""

__all__ = ["READINGS"]

READINGS: dict[str, str] = {
    "rtl/mdfqm_gateware/reference.py:47 reference $mux#0 A[3] const0":
        "equivalent by reading, not proven: the mutation clears bit 3 of `scaled` only while it "
        "holds (no beat in the clock before); `scaled` is read only in the clock after a beat "
        "was taken (`in_scaled`), when it has just been loaded. Yosys's `equiv` pairs `scaled` "
        "and cannot see that the held value is never read.",
    "rtl/mdfqm_gateware/sequencer.py:119 sequencer $dff#0 Q[10] cnot1/8":
        "equivalent in practice, not proven: `phase` bit 10 is inverted while bit 8 is set "
        "(`phase` >= 256); its only reader, the sync restart's `phase >= latency - 1`, holds "
        "either way. The two differ only if the mutated count wraps past 65535 inside one "
        "update (an update of more than about 64,500 clocks) and a sync arrives in the few "
        "clocks after the wrap.",
    "rtl/mdfqm_gateware/sequencer.py:179 sequencer $dff#0 Q[0] const0":
        "equivalent by reading, not proven: bit 0 of the latched period reaches the outputs only "
        "through `slot_len = P >> b`, which only the slot modes read, where b >= 1 drops it "
        "(the clamp `max(P, minimum)` gives the same value either way; the update's end comes "
        "from the count-down of `period` itself). `equiv` cannot see that b >= 1 whenever "
        "`slot_len` is read.",
    "rtl/mdfqm_gateware/sequencer.py:179 core.sequencer $dff#0 Q[0] const0":
        "equivalent by reading, not proven: bit 0 of the latched period reaches the outputs only "
        "through `slot_len = P >> b`, which only the slot modes read, where b >= 1 drops it "
        "(the clamp `max(P, minimum)` gives the same value either way; the update's end comes "
        "from the count-down of `period` itself). `equiv` cannot see that b >= 1 whenever "
        "`slot_len` is read.",
    "rtl/mdfqm_gateware/generator.py:140 top $mux#0 B[9] const1":
        "equivalent by reading, not proven: this is the reset multiplexer of `slot_m2` (select "
        "`rst`, B its reset value 0): the mutation gives it 512 for the one clock after a "
        "reset. `slot_m2` is written every clock and read only when a layout is loaded, which "
        "never happens in the clock after a reset (the pipeline's valid flags are reset too).",
    "rtl/mdfqm_gateware/fronts.py:137 front $mux#2 B[21] const1":
        "equivalent by reading, not proven: the reset multiplexer of the AXI front's held write "
        "data (select `rst`): the mutation sets bit 21 of its reset value; the word is loaded "
        "by the W handshake before any write is issued, so the reset value is never used.",
    "rtl/mdfqm_gateware/top.py:383 top $and#0 A[2] cnot1/1":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
    "rtl/mdfqm_gateware/top.py:435 top $reduce_bool#0 A[6] const0":
        "equivalent by construction, not proven: formal-only logic (a ghost register of the "
        "top's properties, elaborated with `formal=True` as the proofs are); after the "
        "properties are removed nothing reads it, no output can change.",
}
