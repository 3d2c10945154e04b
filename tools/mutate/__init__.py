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
   simulation; the block's proof with an assertion that the mutated bit never differs; Yosys
   ``equiv`` by induction; a bounded miter): *equivalent*, *not equivalent* (a hole in the
   tests) or *undecided*.

Results go to a database per block (``build/mutate/<block>/results.json``, keyed by mutation
keys that name the source line and the kind of mutation, not netlist cells), which a later run
resumes from (:mod:`.campaign`); :mod:`.report` writes ``reports/MUTATION.md``;
:mod:`.sample` draws the fixed sample ``make test`` runs (tb/test_mutation_sample.py).

    python -m tools.mutate                                  # the campaign (make mutate)
    python -m tools.mutate --block driver --only '<key>'    # one mutant, every stage
    python -m tools.mutate --report-only                    # the report from the databases
"""


__all__: list[str] = []
