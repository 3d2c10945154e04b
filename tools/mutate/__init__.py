"""Mutation campaign over the gateware, in the manner of YosysHQ mcy (``make mutate``).

How strong are the tests? Each block (the core, the generator, the gate driver, the top with
each bus front) is elaborated with its source locations; Yosys's own ``mutate`` draws
single-bit / single-cell mutations from its flattened netlist (seeded, even sampling) and
inserts all of them into one netlist, each selected at run time by a ``mutsel`` input, so the
campaign builds one simulator per block, not one per mutant (:mod:`.netlist`). Every mutant
then runs, stopping at the first failure (:mod:`.stages`):

1. the block's vector stimulus through the compiled bench of tb/mdfqm_testkit/vectors.py (every
   output every clock against the golden model);
2. the block's cocotb tests, then its SymbiYosys proof with the mutation applied to the proof's
   own netlist;
3. for a survivor, an equivalence check of the mutant against the original (a longer
   simulation; the block's proof with a probe, an assertion that what the mutation changes
   never differs; a reading's proof from the registry; Yosys ``equiv`` by induction; a bounded
   miter): *equivalent*, *not equivalent* (a hole in the tests) or *undecided*.

Only a failure that shows the mutant wrong kills it (a vector mismatch, a failing cocotb test,
a counterexample from reset); a proof whose induction no longer closes, or a run out of time,
decides nothing and the mutant goes on (:mod:`.stages`).

Results go to a database per block (``build/mutate/<block>/results.json``, keyed by mutation
keys that name the source text and the kind of mutation, not netlist cells nor lines:
:mod:`.keys`), which a later run resumes from (:mod:`.campaign`); :mod:`.report` writes
``reports/MUTATION.md``. The one registry of named mutants, :mod:`.registry`, holds the fixed
sample ``make test`` runs (tb/test_mutation_sample.py; drawn by :mod:`.sample`, which also
writes docs/robustness.md's mutant column from it) and the readings of the survivors.

    python -m tools.mutate                                  # the campaign (make mutate)
    python -m tools.mutate --block driver --only '<key>'    # one mutant, every stage
    python -m tools.mutate --report-only                    # the report from the databases
"""


__all__: list[str] = []
