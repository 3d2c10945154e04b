"""The project's test kit: the cocotb harness, the vector benches, the stimulus generators, the
SymbiYosys runner and the models of the demo's blocks, shared by the tests in tb/, the mutation
campaign (tools/mutate) and the reports. A development distribution (tb/pyproject.toml,
installed by ``make setup``); never part of what a user installs to build hardware."""
