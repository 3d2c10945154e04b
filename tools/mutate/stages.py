"""The three stages a mutant goes through, stopping at the first kill:

1. ``vector``: the block's vector stimulus in the compiled Verilator bench of
   tb/mdfqm_testkit/vectors.py (:class:`MutantBench`, built once per block on the netlist of
   every mutant, ``+mutsel=k``), every output every clock against the model's expected outputs;
2. ``cocotb`` then ``formal``: the block's cocotb test modules (cocotb's runner on the same
   netlist, built once per test module, ``+mutsel=k``), then the block's SymbiYosys proof
   (:func:`formal.run_sby`, the one mutation applied to the proof's own netlist with its
   properties kept);
3. ``equivalence`` for the survivors: a longer simulation; the block's proof with one more
   assertion, that the mutated bit always equals the original (:func:`run_invariant`); the
   check of a reading of the registry, when it has one (:func:`run_reading`); Yosys ``equiv``
   passes by induction, then a bounded miter from reset (:func:`run_equivalence`). A
   difference: *not equivalent* (a hole in the tests); a proof: *equivalent*; neither within
   the time limits: *undecided*.

A kill is a failure that shows the mutant wrong: a vector mismatch (or a simulation stopped on a
one-hot case the mutant breaks), a failing cocotb test, a counterexample from reset. A stage
that stops short of a verdict -- a proof whose induction no longer closes without a
counterexample from reset, a proof or a cocotb run out of time -- is *undecided* there and the
mutant goes on (:func:`run_formal`, :func:`run_cocotb`).
"""

from __future__ import annotations

import fcntl
import json
import re
import shutil
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

from mdfqm_testkit.harness import PARAMS_ENV, SEED_ENV, verilator_build_env
from mdfqm_testkit.vectors import VectorBench, pack_words
from mdfqm_testkit.vectors import verilog_name as v

from .netlist import FORMAL_PREFIX, ROOT, YOSYS, environment, short_src

__all__ = [
    "BMC_SECONDS",
    "MutantBench",
    "cocotb_build",
    "miter_verilog",
    "mutated_bits",
    "run_cocotb",
    "run_equivalence",
    "run_formal",
    "run_invariant",
    "run_reading",
    "run_vectors",
]

_RESULT = re.compile(r"RESULT cycles (\d+) mismatches (\d+)")


@contextmanager
def locked(path: Path):
    """An exclusive lock on ``path`` (one builder of a shared directory at a time)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


# -------------------------------------------------------------------------------------------
# stage 1: the vector-file path


class MutantBench(VectorBench):
    """tb/mdfqm_testkit/vectors.py's bench built once on a netlist of mutants (``source``: the
    mutants and the wrapper that reads ``+mutsel``); :meth:`prepare` writes a block's vector files
    once, :meth:`run_mutant` runs them on one mutant."""

    def prepare(self, runs) -> list[dict]:
        """Write the hex files of ``runs`` ((name, stimulus, expected) each), return what
        :meth:`run_mutant` needs of each."""
        prepared = []
        for name, stim, expected in runs:
            cycles = len(next(iter(stim.values())))
            stim_path = self.directory / f"{name}.stim.hex"
            want_path = self.directory / f"{name}.want.hex"
            stim_path.write_text("\n".join(pack_words(stim, self.inputs, cycles)) + "\n")
            want_path.write_text("\n".join(pack_words(expected, self.outputs, cycles)) + "\n")
            prepared.append({"name": name, "cycles": cycles, "stim": str(stim_path),
                             "want": str(want_path)})
        return prepared


def run_vectors(binary: str, prepared: list[dict], mutant: int) -> dict:
    """Stage 1 for mutant ``mutant`` (0: the original): the runs in order, stopping at the
    first with a mismatch. ``{"killed": bool, "detail": str, "cycles": checked}``."""
    checked = 0
    for run in prepared:
        result = subprocess.run([binary, f"+stim={run['stim']}", f"+want={run['want']}",
                                 f"+cycles={run['cycles']}", f"+mutsel={mutant}"],
                                capture_output=True, text=True, cwd=Path(binary).parent)
        match = _RESULT.search(result.stdout)
        stop = re.search(r"%Error: \S+ Assertion failed in [^:]+: (.*)", result.stdout)
        if match is None and stop is not None:
            # a one-hot case (``parallel_case``) with two matches: the mutant's netlist has
            # no defined behaviour there and its simulation stops: the run fails
            return {"killed": True, "cycles": checked,
                    "detail": f"{run['name']}: the simulation stops: {stop.group(1)[:160]}"}
        if result.returncode != 0 or match is None:
            raise RuntimeError(f"vector simulation failed (mutant {mutant}):\n"
                               f"{result.stdout[-2000:]}\n{result.stderr[-2000:]}")
        checked += int(match.group(1))
        if int(match.group(2)):
            first = next((line for line in result.stdout.splitlines()
                          if line.startswith("MISMATCH")), "")
            return {"killed": True, "cycles": checked,
                    "detail": f"{run['name']}: {match.group(2)} mismatches; {first}"}
    return {"killed": False, "cycles": checked, "detail": f"{checked} clocks equal"}


# -------------------------------------------------------------------------------------------
# stage 2: cocotb tests and the proof


def cocotb_build(source: Path, toplevel: str, build_dir: Path) -> None:
    """Build the cocotb simulation of ``source`` (top ``toplevel``) once (locked; its output
    in ``<build_dir>.log``)."""
    stamp = build_dir / "built.stamp"
    with locked(build_dir.parent / f"{build_dir.name}.lock"):
        if stamp.exists() and stamp.read_text() == str(source.stat().st_mtime_ns):
            return
        spec = {"action": "build", "source": str(source), "toplevel": toplevel,
                "build_dir": str(build_dir)}
        build_dir.mkdir(parents=True, exist_ok=True)
        result = subprocess.run([sys.executable, "-m", "tools.mutate.stages", json.dumps(spec)],
                                capture_output=True, text=True, cwd=ROOT)
        (build_dir.parent / f"{build_dir.name}.log").write_text(result.stdout + result.stderr)
        if result.returncode != 0:
            raise RuntimeError(f"cocotb build of {source} failed:\n{result.stderr[-3000:]}")
        stamp.write_text(str(source.stat().st_mtime_ns))


def run_cocotb(build_dir: Path, toplevel: str, module: str, params: dict,
               testcase, mutant: int, work: Path, timeout: float, seed: int) -> dict:
    """One cocotb test module on mutant ``mutant``, in a subprocess (a mutant can hang a
    test). ``{"killed": bool, "undecided": bool, "detail": str}``: a failing test kills; a run
    that does not end within ``timeout`` is undecided, as a proof out of time is (a slow machine
    looks the same as a hang), and the mutant goes on to the next stage."""
    work.mkdir(parents=True, exist_ok=True)
    spec = {"build_dir": str(build_dir), "toplevel": toplevel, "module": module,
            "params": params, "testcase": list(testcase) if testcase else None,
            "mutant": mutant, "work": str(work), "seed": seed}
    started = time.monotonic()
    try:
        result = subprocess.run([sys.executable, "-m", "tools.mutate.stages", json.dumps(spec)],
                                capture_output=True, text=True, cwd=ROOT, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"killed": False, "undecided": True,
                "detail": f"{module}: no end within {timeout:.0f} s (undecided, not a kill)"}
    seconds = time.monotonic() - started
    match = re.search(r"COCOTB-MUTANT (\d+) (\d+)", result.stdout)
    if match is None:
        raise RuntimeError(f"cocotb run of mutant {mutant} ({module}) did not report:\n"
                           f"{result.stdout[-3000:]}\n{result.stderr[-3000:]}")
    total, failed = int(match.group(1)), int(match.group(2))
    if total == 0:
        raise RuntimeError(f"{module}: no cocotb test ran on mutant {mutant}")
    if failed:
        names = re.findall(r"(\w+) +FAIL", result.stdout)
        return {"killed": True, "undecided": False,
                "detail": f"{module}: {failed} of {total} tests failed "
                                          f"({', '.join(names[:4])})"}
    shutil.rmtree(work, ignore_errors=True)
    return {"killed": False, "undecided": False,
            "detail": f"{module}: {total} tests pass ({seconds:.0f} s)"}


def _cocotb_child(spec: dict) -> None:
    """The subprocess of :func:`run_cocotb` and :func:`cocotb_build`."""
    from cocotb_tools.check_results import get_results
    from cocotb_tools.runner import get_runner

    verilator_build_env()
    if spec.get("action") == "build":
        get_runner("verilator").build(sources=[spec["source"]], hdl_toplevel=spec["toplevel"],
                                      build_dir=spec["build_dir"], build_args=["-Wno-fatal"],
                                      timescale=("1ns", "1ps"))
        return
    work = Path(spec["work"])
    runner = get_runner("verilator")
    runner.build_dir = Path(spec["build_dir"])
    results = runner.test(test_module=f"tb.{spec['module']}", hdl_toplevel=spec["toplevel"],
                          hdl_toplevel_lang="verilog",
                          build_dir=spec["build_dir"], test_dir=work,
                          testcase=spec["testcase"], plusargs=[f"+mutsel={spec['mutant']}"],
                          extra_env={PARAMS_ENV: json.dumps(spec["params"]),
                                     SEED_ENV: str(spec["seed"])},
                          seed=spec["seed"],
                          results_xml=str(work / "results.xml"))
    total, failed = get_results(results)
    print(f"COCOTB-MUTANT {total} {failed}", flush=True)


#: what a run of the block's proof found: a counterexample from reset fails the mutant; a proof
#: that stops short of a verdict (its induction no longer closes, or it runs out of time) says
#: nothing about the mutant, which goes on to the next stage
KILLED, UNDECIDED, PASSED = "killed", "undecided", "passed"


def run_formal(component, name: str, depth: int, mutant_il: Path | None) -> dict:
    """The block's proof (``prove`` task, tb/mdfqm_testkit/formal.py ``run_sby``) on
    ``mutant_il`` (the proof's own netlist with the mutation,
    :func:`netlist.write_formal_mutant`; it replaces the design after run_sby's ``prep``), or on
    the original flattened (None). ``{"verdict": ..., "killed": bool, "detail": str}``:

    - :data:`KILLED`: the base case (a bounded check from reset, ``depth`` clocks) fails an
      assertion: a counterexample from reset, a trace the mutant really runs;
    - :data:`UNDECIDED`: the base case holds but the induction step fails (SymbiYosys's
      ``UNKNOWN``: a state the induction cannot rule out, maybe unreachable), or the run did not
      end within run_sby's time limit: the test fails, but nothing shows the mutant wrong;
    - :data:`PASSED`: proven."""
    from mdfqm_testkit.formal import run_sby

    mutation = (("design -reset", f"read_rtlil {mutant_il}", "hierarchy -top dut")
                if mutant_il else FORMAL_PREFIX)
    try:
        run_sby(component, name, depth, ("prove",), keep_failed=False, mutation=mutation)
    except subprocess.TimeoutExpired as expired:
        return {"verdict": UNDECIDED, "killed": False,
                "detail": f"proof: no end within {expired.timeout:.0f} s (run_sby's limit): "
                          "undecided, not a kill"}
    except AssertionError as error:
        return formal_verdict(str(error), name)
    return {"verdict": PASSED, "killed": False, "detail": "proof passes"}


def formal_verdict(text: str, name: str) -> dict:
    """The verdict of a failed ``prove`` run from SymbiYosys's output ``text`` (see
    :func:`run_formal`); an output that says neither raises (a broken run is no verdict)."""
    if "DONE (ERROR" in text:
        raise RuntimeError(f"the proof of {name} did not run:\n{text[-3000:]}")
    if "FAIL for basecase" in text or "DONE (FAIL" in text:
        site = re.search(r"failed assertion \S+ at (\S+):(\d+) step (\d+)", text)
        if site is None:        # an assertion without a source line (a probe's, a lemma's)
            named = re.search(r"failed assertion (\S+)(?: at\s*\S*?)?(?:\s+step (\d+))?$", text,
                              re.M)
            return {"verdict": KILLED, "killed": True,
                    "detail": "proof: counterexample" + (
                        "" if named is None else f" ({named.group(1).rpartition('.')[2]}"
                        + (f", step {named.group(2)})" if named.group(2) else ")"))}
        return {"verdict": KILLED, "killed": True,
                "detail": f"proof: counterexample at step {site.group(3)}, "
                          f"\"{assertion_message(site.group(1), int(site.group(2)))}\" "
                          f"({short_src(site.group(1) + ':' + site.group(2))})"}
    if "FAIL for induction" in text or "DONE (UNKNOWN" in text:
        return {"verdict": UNDECIDED, "killed": False,
                "detail": "proof: the induction no longer closes, no counterexample from reset "
                          "(undecided, not a kill)"}
    if "DONE (TIMEOUT" in text:
        return {"verdict": UNDECIDED, "killed": False,
                "detail": "proof: SymbiYosys's time limit (undecided, not a kill)"}
    raise RuntimeError(f"the proof of {name} ended without a verdict:\n{text[-3000:]}")


def run_invariant(component, name: str, depth: int, probe_il: Path) -> dict:
    """The first step of stage 3: the block's proof on ``probe_il``
    (:func:`netlist.write_invariant_probe`: the original, and an assertion that what the
    mutation changes -- the mutated bit, or the outputs of the cell it feeds -- always equals
    the original). Passing, it proves the mutant *equivalent*: in every state reachable from
    power-up the mutation changes nothing. Otherwise *undecided* (a mutated bit that differs
    somewhere may still never reach an output: the next steps try).
    ``{"verdict": ..., "detail": str}``."""
    result = run_formal(component, name, depth, probe_il)
    if result["verdict"] == PASSED:
        return {"verdict": "equivalent",
                "detail": "proven (the block's proof, k-induction to depth "
                          f"{depth}: what the mutation changes equals the original in every "
                          "reachable state)"}
    if result["verdict"] == KILLED:
        return {"verdict": "undecided",
                "detail": "the mutated bit can differ from the original (a "
                          + result["detail"].removeprefix("proof: ") + ")"}
    return {"verdict": "undecided",
            "detail": "not proven: " + _without_verdict(result["detail"])}


def run_reading(component, name: str, depth: int, probe_il: Path, lemmas: int) -> dict:
    """The check of a reading (:class:`registry.Proof`): the block's proof on ``probe_il``, the
    invariant probe with the reading's ``lemmas`` assertions. Passing, the lemmas and the probe
    hold in every reachable state: *equivalent*. Otherwise the reading stays an explanation and
    the mutant *undecided* (a counterexample from reset to a lemma or the probe says the
    reading is wrong). ``{"verdict": ..., "detail": str}``."""
    result = run_formal(component, name, depth, probe_il)
    if result["verdict"] == PASSED:
        return {"verdict": "equivalent",
                "detail": f"proven by the reading's proof (its {lemmas} lemma(s) and the "
                          f"probe, the block's proof, k-induction to depth {depth})"}
    if result["verdict"] == KILLED:
        return {"verdict": "undecided",
                "detail": "the reading's proof fails from reset (the reading is wrong: "
                          + result["detail"].removeprefix("proof: ") + ")"}
    return {"verdict": "undecided",
            "detail": "the reading's proof does not close: " + _without_verdict(result["detail"])}


def _without_verdict(detail: str) -> str:
    """A proof's undecided detail without the formal stage's words about kills."""
    return detail.removeprefix("proof: ").replace(" (undecided, not a kill)", "").replace(
        ": undecided, not a kill", "")


def assertion_message(path: str, line: int) -> str:
    """The message of the ``Assert`` whose call starts at ``path:line``."""
    lines = Path(path).read_text().splitlines()
    text = " ".join(lines[line - 1:line + 3])
    match = re.search(r'"([^"]+)"', text)
    return match.group(1) if match else "?"


# -------------------------------------------------------------------------------------------
# stage 3: equivalence


def miter_verilog(module: str, ports, width: int, mutant: int) -> str:
    """The miter (as mcy's): ``gold`` (mutsel 0) and ``gate`` (mutsel ``mutant``) on the same
    inputs, reset in the first clock (as every test starts), every output compared in every
    clock."""
    inputs, outputs = ports
    decl = ["input clk", *(f"input [{w - 1}:0] {v(n)}" for n, w in inputs)]
    wires, checks, cells = [], [], []
    for cell, value in (("gold", 0), ("gate", mutant)):
        conns = [f".{v(n)}({v(n)})" for n in ["clk", *(n for n, _ in inputs)]]
        for n, w in outputs:
            wires.append(f"    wire [{w - 1}:0] {cell}_{n};")
            conns.append(f".{v(n)}({cell}_{n})")
        conns.append(f".mutsel({width}'d{value})")
        cells.append(f"    {module} {cell}({', '.join(conns)});")
    checks = [f"        assert (gold_{n} == gate_{n});" for n, _ in outputs]
    return (f"module miter({', '.join(decl)});\n" + "\n".join(wires) + "\n"
            + "\n".join(cells) + "\n"
            "    reg first = 1'b1;\n"
            "    always @(posedge clk) first <= 1'b0;\n"
            "    always @* begin\n"
            "        if (first) assume (rst);\n" + "\n".join(checks) + "\n"
            "    end\nendmodule\n")


#: seconds of the bounded check (it reaches 10-20 clocks after reset on the tops in that time;
#: a longer one rarely finds what the longer simulation before it did not)
BMC_SECONDS = 20

#: Yosys's ``$equiv`` cell as an assertion (the base case of the equivalence proof)
EQUIV_AS_ASSERT = """module \\$equiv (A, B, Y);
    input A, B;
    output Y;
    assign Y = A;
    always @* assert (A == B);
endmodule
"""


#: cells whose output bit ``i`` reads input bit ``i`` only (``$mux``: of ``A`` and ``B``)
BITWISE = {"$not", "$pos", "$and", "$or", "$xor", "$xnor", "$mux"}


def mutated_bits(netlist_json: Path, cell: str, port: str, bit: int) -> list[str]:
    """The public wire bits (``name[i]``) of ``netlist_json`` (``write_json`` of ``sim.il``)
    where a mutation of ``cell``'s ``port`` bit ``bit`` first shows: the bit itself on an output
    port, else the cell's outputs, followed through logic with internal (``$``) names only,
    bit by bit through flip-flops and bitwise cells. The equivalence check leaves these
    unpaired: pairing them would assume away the very difference."""
    module = json.loads(Path(netlist_json).read_text())["modules"]["dut"]
    public = {}
    for name, net in module["netnames"].items():
        if not name.startswith("$"):
            for i, b in enumerate(net["bits"]):
                if isinstance(b, int):
                    public.setdefault(b, f"{name}[{i}]")
    readers = {}
    for name, info in module["cells"].items():
        for p, bits in info["connections"].items():
            if info.get("port_directions", {}).get(p) == "input":
                for i, b in enumerate(bits):
                    readers.setdefault(b, []).append((name, p, i))

    def outputs(name: str, p: str, i: int) -> list[int]:
        info = module["cells"][name]
        kind, conns = info["type"], info["connections"]
        if "dff" in kind and "Q" in conns:
            return [conns["Q"][i]] if p == "D" else list(conns["Q"])
        outs = [b for q, bits in conns.items()
                if info.get("port_directions", {}).get(q) == "output" for b in bits]
        if kind in BITWISE and p in ("A", "B") and len(conns.get("Y", [])) == len(conns[p]):
            return [conns["Y"][i]]
        return outs

    info = module["cells"][cell]
    start = ([info["connections"][port][bit]]
             if info.get("port_directions", {}).get(port) == "output"
             else outputs(cell, port, bit))
    found, seen, todo = set(), set(), [b for b in start if isinstance(b, int)]
    while todo:
        b = todo.pop()
        if b in seen:
            continue
        seen.add(b)
        if b in public:
            found.add(public[b])
            continue
        for name, p, i in readers.get(b, []):
            todo += [o for o in outputs(name, p, i) if isinstance(o, int)]
    return sorted(found)


#: at most this many ``equiv`` proofs per mutant (each unpairs what the one before could not
#: prove)
EQUIV_ROUNDS = 12
#: clocks each ``equiv_induct`` step assumes every pair equal (and the base case checks from
#: reset, one more): a value differing only in the clock after a reset needs more than one
#: (the generator's ``slot_m2`` reset value: undecided with 1, proven with 3)
EQUIV_SEQ = 3
_UNPROVEN = re.compile(r"Unproven \$equiv \S+: \\(\S+)_gold ")


def run_equivalence(directory: Path, netlist_il: Path, module: str, ports, width: int,
                    mutant: int, depth: int, timeout: float, changed: tuple[str, ...] = ()
                    ) -> dict:
    """Stage 3 after :func:`run_invariant` (see the module docstring), each step one process:

    1. a proof of equivalence with Yosys's ``equiv`` passes: the original (mutsel 0) and the
       mutant, each flattened and optimised, the signals of one name in both paired
       (``equiv_make``, the wires split into bits); every pair equal in the first
       :data:`EQUIV_SEQ` + 1 clocks from power-up with reset in the first (``sat``, the base
       case) and every pair proven to stay equal after :data:`EQUIV_SEQ` clocks in which all
       pairs are (``equiv_simple``, ``equiv_induct``: the induction step): the outputs,
       paired too, are then equal in every clock: *equivalent*. First
       every pair (a mutated register whose copies stay equal is proven only while paired),
       then without the bits where the mutation shows (``changed``, from
       :func:`mutated_bits`), then, round after round, without every pair the round before
       could not prove (a difference that stays inside: ``count[15]`` differs once
       ``slot_m2[15]`` does), the greatest set of pairs that holds by induction (as van
       Eijk's method; a round whose base case fails goes on without the pairs its
       induction could not prove). A round that cannot prove an output pair ends the proof:
       the outputs are never unpaired. Every round's proof is sound on its own;
    2. otherwise a bounded check from reset, SymbiYosys ``bmc`` (the miter's two copies
       combined by ``fmcombine``, yices) to ``depth`` clocks within :data:`BMC_SECONDS`: a
       counterexample is *not equivalent*, none is *undecided*.

    ``timeout``: seconds of each ``equiv`` proof; at most :data:`EQUIV_ROUNDS` of them and
    three timeouts in all.

    ``{"verdict": ..., "detail": str}``."""
    work = Path(directory).resolve() / f"eq-{mutant}"
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    netlist = Path(netlist_il).resolve()
    (work / "pair.v").write_text(plain_pair(module, ports, width, mutant))
    (work / "equiv_assert.v").write_text(EQUIV_AS_ASSERT)
    outputs = {f"u.{n}" for n, _ in ports[1]}
    budget = time.monotonic() + 3 * timeout
    unpaired: tuple[str, ...] = ()
    for step in range(EQUIV_ROUNDS):
        left = min(timeout, budget - time.monotonic())
        if left <= 0:
            break
        (work / f"unpaired{step}.txt").write_text("".join(f"{n}\n" for n in unpaired))
        (work / f"equiv{step}.ys").write_text("\n".join([
            "read_verilog -formal equiv_assert.v", "proc", "design -stash equivmap",
            f"read_rtlil {netlist}", "read_verilog pair.v", "flatten gold gate",
            f"delete {module}", "memory_map", "opt -full", "opt_clean -purge", "splitnets",
            f"equiv_make -blacklist unpaired{step}.txt gold gate equiv",
            "hierarchy -top equiv", "design -save paired",
            "techmap -map %equivmap t:$equiv", "chformal -lower", "opt_clean",
            f"sat -seq {EQUIV_SEQ + 1} -prove-asserts -set-at 1 rst 1 equiv",
            "design -load paired",
            f"equiv_simple -seq {EQUIV_SEQ}", f"equiv_induct -seq {EQUIV_SEQ}",
            "equiv_status -assert"]) + "\n")
        try:
            subprocess.run([YOSYS, "-q", "-l", f"equiv{step}.log", "-s", f"equiv{step}.ys"],
                           cwd=work, capture_output=True, text=True, timeout=left)
            log = (work / f"equiv{step}.log").read_text()
        except subprocess.TimeoutExpired:
            if step:
                break
            log = ""                # every pair was too much: on without the mutated bits
        if ("SAT proof finished - no model found: SUCCESS!" in log
                and "Equivalence successfully proven!" in log):
            shutil.rmtree(work, ignore_errors=True)
            how = ("every signal paired" if not unpaired
                   else f"{len(unpaired)} bits unpaired, round {step + 1}")
            return {"verdict": "equivalent",
                    "detail": f"proven (Yosys equiv_make/equiv_simple/equiv_induct, {how}; "
                              "base case by sat)"}
        based = "SAT proof finished - no model found: SUCCESS!" in log
        # a failing base case does not say which pair: go on without the pairs the induction
        # could not prove (the same pairs, mostly: followers of an unpaired register), or
        # without the mutated bits in the first round; nothing left to drop ends the proof
        unproven = set(_UNPROVEN.findall(log)) if step or based else set()
        if step == 0:
            unproven |= {f"u.{n}" for n in changed}
        if not unproven or any(not n.startswith("u.") or n.split("[")[0] in outputs
                               for n in unproven):
            break
        unpaired = tuple(sorted(set(unpaired) | unproven))
    (work / "miter.sv").write_text(miter_verilog(module, ports, width, mutant))
    prep = [f"read_rtlil {netlist}", "read_verilog -formal -sv miter.sv", "prep -top miter",
            f"memory_map {module}", "opt -fast", "fmcombine -initeq miter gold gate",
            "flatten", "opt -fast"]
    (work / "eq.sby").write_text("\n".join([
        "[options]", "mode bmc", f"depth {depth}", f"timeout {int(BMC_SECONDS)}", "",
        "[engines]", "smtbmc --stbv yices", "", "[script]", *prep, "", "[files]",
        "miter.sv", ""]))
    started = time.monotonic()
    try:
        result = subprocess.run(["yowasp-sby", "-f", "eq.sby"], cwd=work, env=environment(),
                                capture_output=True, text=True, timeout=BMC_SECONDS + 60)
        text = result.stdout
    except subprocess.TimeoutExpired as expired:
        text = expired.stdout or ""
        text = text.decode() if isinstance(text, bytes) else text
    seconds = time.monotonic() - started
    steps = [int(x) for x in re.findall(r"Checking assertions in step (\d+)", text)]
    reached = max(steps, default=-1)
    if "DONE (FAIL" in text:
        trace = next(iter(sorted(work.glob("eq/engine_0/trace*.vcd"))), None)
        where = trace.relative_to(ROOT) if trace else work.relative_to(ROOT)
        return {"verdict": "not equivalent",
                "detail": f"an output differs {reached} clocks after reset ({where})"}
    if "DONE (PASS" in text:
        return {"verdict": "undecided",
                "detail": f"no difference within {depth} clocks of reset; not proven "
                          "equivalent"}
    return {"verdict": "undecided",
            "detail": f"no difference within {max(reached, 0)} clocks of reset (the bounded "
                      f"check stopped at {seconds:.0f} s); not proven equivalent"}


def plain_pair(module: str, ports, width: int, mutant: int) -> str:
    """``gold`` (mutsel 0) and ``gate`` (mutsel ``mutant``) with the block's ports, for Yosys
    ``miter``."""
    inputs, outputs = ports
    out = []
    for name, value in (("gold", 0), ("gate", mutant)):
        decl = ["input clk", *(f"input [{w - 1}:0] {v(n)}" for n, w in inputs),
                *(f"output [{w - 1}:0] {v(n)}" for n, w in outputs)]
        conns = [f".{v(n)}({v(n)})" for n in ["clk", *(n for n, _ in inputs),
                                                 *(n for n, _ in outputs)]]
        out.append(f"module {name}({', '.join(decl)});\n"
                   f"    {module} u({', '.join(conns)}, .mutsel({width}'d{value}));\n"
                   "endmodule\n")
    return "\n".join(out)


if __name__ == "__main__":
    _cocotb_child(json.loads(sys.argv[1]))
