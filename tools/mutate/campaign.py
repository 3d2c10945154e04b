"""The campaign: per block, draw the mutations, build their one netlist and its benches, run
every mutant through the stages in parallel, keep every result in a database that a later run
resumes from.

Database: ``build/mutate/<block>/results.json``: the campaign's settings, the design's hash, the
mutations in ``mutsel`` order and one result per mutation key. A result is reused by
``--resume`` when the design (``design.il``), the stimulus seed and the stages are unchanged.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import hashlib
import json
import multiprocessing
import os
import random
import signal
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

from .blocks import BLOCKS, Block
from .keys import StaleKeyError
from .netlist import (
    ROOT,
    BlockNetlist,
    Mutation,
    mutsel_width,
    worth_a_probe,
    wrapper,
    write_formal_mutant,
    write_invariant_probe,
)
from .registry import Proof, reading
from .stages import (
    KILLED,
    UNDECIDED,
    MutantBench,
    cocotb_build,
    mutated_bits,
    run_cocotb,
    run_equivalence,
    run_formal,
    run_invariant,
    run_reading,
    run_vectors,
)

__all__ = [
    "BUILD", "DEFAULT_COUNTS", "EQ_DEPTH", "FOCUS", "KILLED_BY", "PROVEN_BY", "STAGES",
    "BlockCampaign", "Settings", "check_reading", "counts", "evaluate", "inner_checks",
    "inner_key", "kept_records", "merged", "run", "stimulus_hash", "stimulus_sources",
    "summary_line",
]

BUILD = ROOT / "build" / "mutate"
STAGES = ("vector", "cocotb", "formal", "equivalence")
#: mutations drawn per block by default: the whole campaign in about an hour on two cores
DEFAULT_COUNTS = {"core": 150, "generator": 120, "driver": 150, "top_wb": 150, "top_axi": 100}
#: extra mutations per region with a 100 % target (the fault path, the register write decode)
#: drawn in the blocks that hold them (:meth:`BlockCampaign._focused`)
FOCUS = {"driver": 10, "top_wb": 20, "top_axi": 10}
#: depth (clocks after reset) of the equivalence check's bounded part, per block
EQ_DEPTH = {"core": 24, "generator": 24, "driver": 24, "top_wb": 20, "top_axi": 20}


@dataclass
class Settings:
    """What one run does (the command line of ``python -m tools.mutate``)."""

    blocks: tuple[str, ...] = tuple(BLOCKS)
    counts: dict = field(default_factory=lambda: dict(DEFAULT_COUNTS))
    seed: int = 1
    jobs: int = 2
    resume: bool = False
    only: tuple[str, ...] = ()
    stages: tuple[str, ...] = STAGES
    eq_timeout: float = 90.0
    cocotb_timeout: float = 900.0
    progress: bool = True
    #: with resume: run the equivalence stage again on the survivors and undecided mutants
    recheck: bool = False
    #: with resume: run every mutant not killed through every stage again (the tests changed)
    retry: bool = False
    #: with resume: run the survivors only through every stage again (a test closed their
    #: hole); undecided mutants keep their records
    retry_survived: bool = False


def kept_records(results: dict, settings: Settings) -> dict:
    """The earlier records a resumed run keeps: all of them, or with ``retry`` (the tests
    changed) the killed and proven-equivalent ones only, or with ``retry_survived`` (a test
    closed a hole) all but the survivors."""
    if settings.retry:
        return {key: r for key, r in results.items() if r["status"] in ("killed", "equivalent")}
    if settings.retry_survived:
        return {key: r for key, r in results.items() if r["status"] != "survived"}
    return dict(results)


class BlockCampaign:
    """One block's share: netlists, benches, the database (parent process only)."""

    def __init__(self, block: Block, settings: Settings, directory: Path | None = None):
        """``directory``: where an outer block's mutations run through this block's stages
        (:func:`inner_checks`; with ``settings.only``, the keys as this block names them): a
        key that names no cell here is left out, not an error."""
        from mdfqm_testkit.vectors import ports_of

        self.block, self.settings = block, settings
        # a run of chosen keys (--only) works apart: a campaign may be running meanwhile
        self.directory = directory or BUILD / (f"{block.name}-only" if settings.only
                                               else block.name)
        self.netlist = BlockNetlist(block.build(True), self.directory)
        self.design_hash = hashlib.sha256(
            (self.directory / "design.il").read_bytes()).hexdigest()[:16]
        component = block.build(False)
        self.ports = ports_of(component)
        if settings.only and directory is not None:
            self.mutations = []
            for key in settings.only:
                with contextlib.suppress(StaleKeyError):
                    self.mutations += self.netlist.resolve([key])
        elif settings.only:
            self.mutations = self.netlist.resolve(settings.only)
        else:
            count = settings.counts[block.name]
            if block.exclude:        # the even sample of the rest: a larger draw, filtered
                self.mutations = [m for m in self.netlist.sample(8 * count, settings.seed)
                                  if self._kept(m)][:count]
            else:
                self.mutations = self.netlist.sample(count, settings.seed)
            self.mutations += self._focused(settings.seed, count)
        self.db_path = self.directory / "results.json"
        self.results = self._load()
        self.baseline = self._loaded_baseline
        #: whether this run evaluated anything of the block (a block resumed with nothing to run
        #: keeps its database, and with it the campaign time of the run that filled it)
        self.ran = False
        self.module = f"{block.name}_mutants"
        self.width = mutsel_width(len(self.mutations))

    def _kept(self, mutation: Mutation) -> bool:
        """Whether ``mutation`` is in a scope this block measures (``Block.exclude``)."""
        scope = mutation.key.split(" ")[1]
        return not any(scope == s or scope.startswith(s + ".") for s in self.block.exclude)

    def _focused(self, seed: int, count: int) -> list[Mutation]:
        """Mutations of the logic with a 100 % target (:func:`report.regions`: the fault path,
        the register file's write decode) beyond the even sample's share of them:
        ``FOCUS[block]`` per region, a seeded choice among every mutation ``mutate`` knows
        there, scaled with ``count`` as the sample is."""
        from .report import in_region, regions

        per_region = FOCUS.get(self.block.name, 0) * count // DEFAULT_COUNTS[self.block.name]
        if not per_region:
            return []
        drawn = {m.key for m in self.mutations}
        every = self.netlist.sample(100000, seed)
        rng = random.Random(f"{seed}-focus-{self.block.name}")
        extra = []
        for _, lines in sorted(regions().items()):
            pool = [m for m in every if m.key not in drawn and self._kept(m)
                    and in_region({"src": m.src}, lines)]
            chosen = rng.sample(pool, min(per_region, len(pool)))
            extra += chosen
            drawn |= {m.key for m in chosen}
        return extra

    # ---------------------------------------------------------------- database
    def _load(self) -> dict:
        self._loaded_baseline = None
        self.rechecked = {}
        #: the campaign time of the earlier run resumed (read here, before this run saves)
        self._seconds_before = 0.0
        if not self.settings.resume or not self.db_path.exists():
            return {}
        db = json.loads(self.db_path.read_text())
        if db.get("design") != self.design_hash or db.get("seed") != self.settings.seed:
            return {}
        self._seconds_before = db.get("seconds", 0.0)
        self._loaded_baseline = db.get("baseline")
        drawn = {m.key for m in self.mutations}
        results = {key: r for key, r in db.get("results", {}).items()
                   if tuple(r.get("stages", ())) == tuple(self.settings.stages) and key in drawn}
        results = kept_records(results, self.settings)
        #: the earlier records of the mutants --recheck runs through stage 3 again
        self.rechecked = {key: r for key, r in results.items()
                          if self.settings.recheck and r["status"] in ("survived", "undecided")}
        return {key: r for key, r in results.items() if key not in self.rechecked}

    def save(self, started: float) -> None:
        db = {"block": self.block.name, "title": self.block.title, "design": self.design_hash,
              "seed": self.settings.seed, "jobs": self.settings.jobs,
              # the day the results were last added to, for the report (which may be written
              # later from the databases alone)
              "date": time.strftime("%Y-%m-%d"),
              "count": len(self.mutations),
              "stages": list(self.settings.stages),
              "seconds": round(time.time() - started + self._seconds_before, 1),
              "baseline": self.baseline,
              "mutations": [m.as_dict() for m in self.mutations], "results": self.results}
        tmp = self.db_path.with_suffix(".tmp")
        tmp.write_text(json.dumps(db, indent=1))
        os.replace(tmp, self.db_path)

    # ---------------------------------------------------------------- builds
    def prepare(self) -> dict:
        """Build the mutants' netlist, the vector bench, the stimulus; check the original
        passes stage 1. Returns the job context the workers need."""
        self.netlist.write_mutants(self.mutations, self.module)
        net = (self.directory / "mutants.net.v").read_text()
        sources = {}
        for toplevel in {self.block.toplevel, *(t.toplevel for t in self.block.cocotb)}:
            path = self.directory / f"mutants-{toplevel}.v"
            text = net + wrapper(toplevel, self.module, self.ports, self.width)
            if not path.exists() or path.read_text() != text:
                path.write_text(text)
            sources[toplevel] = str(path)
        component = self.block.build(False)
        bench = MutantBench(component, self.block.toplevel, f"mutants-{self.directory.name}",
                            source=Path(sources[self.block.toplevel]))
        prepared = self._stimulus(bench, "stimulus", [self.settings.seed])
        deeper = (self._stimulus(bench, "deeper", [self.settings.seed + 1000 * i
                                                   for i in (1, 2)])
                  if "equivalence" in self.settings.stages else [])
        for runs, what in ((prepared, "vector stage"), (deeper, "deeper simulation")):
            baseline = run_vectors(str(bench.binary), runs, 0)
            if baseline["killed"]:
                raise RuntimeError(f"{self.block.name}: the original fails its own {what} "
                                   f"({baseline['detail']})")
        return {"block": self.block.name, "directory": str(self.directory),
                "binary": str(bench.binary), "prepared": prepared, "deeper": deeper,
                "sources": sources,
                "module": self.module, "width": self.width, "ports": self.ports,
                "seed": self.settings.seed,
                "stages": list(self.settings.stages), "eq_depth": EQ_DEPTH[self.block.name],
                "eq_timeout": self.settings.eq_timeout,
                "cocotb_timeout": self.settings.cocotb_timeout}

    def _stimulus(self, bench: MutantBench, name: str, seeds: list[int]) -> list[dict]:
        """The block's vector runs for ``seeds``, written once (cached by seed)."""
        stamp = bench.directory / f"{name}.json"
        tag = {"seeds": seeds, "block": self.block.name, "sources": stimulus_hash()}
        if stamp.exists():
            saved = json.loads(stamp.read_text())
            if saved.get("tag") == tag and all(Path(r["stim"]).exists()
                                               for r in saved["prepared"]):
                return saved["prepared"]
        runs = []
        for seed in seeds:
            prefix = "" if name == "stimulus" else f"{name}{seed}-"
            runs += [(prefix + run, stim, want) for run, stim, want
                     in self.block.stimulus(seed)]
        prepared = bench.prepare(runs)
        stamp.write_text(json.dumps({"tag": tag, "prepared": prepared}))
        return prepared

    def pending(self) -> list[tuple[int, Mutation]]:
        return [(k, m) for k, m in enumerate(self.mutations, 1) if m.key not in self.results]

    def previous(self, key: str) -> dict | None:
        """The earlier record of a mutant --recheck runs again from stage 3."""
        return self.rechecked.get(key)


def stimulus_hash() -> str:
    """A hash of the sources of the blocks' vector stimulus: cached vector files are redone
    when it changes."""
    digest = hashlib.sha256()
    for path in stimulus_sources():
        digest.update(path.as_posix().encode())
        digest.update((ROOT / path).read_bytes())
    return digest.hexdigest()[:16]


def stimulus_sources() -> list[Path]:
    """The files the vector stimulus of :mod:`.blocks` is made by: the whole test kit (its
    sequences, masters, coverage and models of the stimulus) and the blocks' run lengths."""
    kit = sorted(p.relative_to(ROOT) for p in (ROOT / "tb" / "mdfqm_testkit").glob("*.py"))
    return [*kit, Path("tools/mutate/blocks.py")]


#: why a mutation of a flop's clock port has no formal stage and no equivalence check
OTHER_EDGE = ("a flop clocked on the other edge is outside the one-edge formal model (the "
              "proof's prep refuses it; with clk2fflogic the original's induction no longer "
              "closes)")

#: the mutation of mutant 0, the original
ORIGINAL = {"key": "original", "cell": "", "mode": "none", "port": "", "bit": 0,
            "ctrlbit": None, "wire": "", "src": [], "init": None}


def evaluate(context: dict, mutant: int, mutation: dict, previous: dict | None = None) -> dict:
    """Every stage for one mutant, stopping at the first kill (runs in a worker process);
    ``previous``: an earlier record whose stages 1 and 2 stand (``--recheck``)."""
    block = BLOCKS[context["block"]]
    directory = Path(context["directory"])
    stages = context["stages"]
    started = time.monotonic()
    #: ``undecided``: the stages that ran without a verdict (a proof whose induction no longer
    #: closes, a run out of time): not kills, the mutant went on
    record = {"mutant": mutant, "stages": stages, "log": [], "undecided": []}
    if previous is not None:
        record["log"] = [line for line in previous.get("log", [])
                         if not line.startswith(("equivalence:", "deeper simulation:",
                                                 "invariant:", "reading:"))]
        record["undecided"] = list(previous.get("undecided", []))
        stages = [s for s in stages if s == "equivalence"]

    def done(status, stage, detail):
        record.update(status=status, stage=stage, detail=detail,
                      seconds=round(time.monotonic() - started, 1))
        return record

    if "vector" in stages:
        result = run_vectors(context["binary"], context["prepared"], mutant)
        record["log"].append(f"vector: {result['detail']}")
        if result["killed"]:
            return done("killed", "vector", result["detail"])
    if "cocotb" in stages:
        for test in block.cocotb:
            build_dir = directory / f"cocotb-{test.module}"
            cocotb_build(Path(context["sources"][test.toplevel]), test.toplevel, build_dir)
            result = run_cocotb(build_dir, test.toplevel, test.module, test.params,
                                test.testcase, mutant, directory / "work" / f"{mutant}",
                                context["cocotb_timeout"], context["seed"])
            record["log"].append(f"cocotb: {result['detail']}")
            if result["killed"]:
                return done("killed", "cocotb", result["detail"])
            if result["undecided"]:
                record["undecided"].append("cocotb")
    as_mutation = Mutation(**{**mutation, "src": tuple(mutation["src"])}) if mutant else None
    # a flop moved to the other clock edge is outside the formal model (one edge per step;
    # SymbiYosys's prep refuses it, and Yosys's equiv passes prove a negedge flop equal to a
    # posedge one): only simulation, which runs both edges, judges it
    other_edge = mutation["port"] == "CLK"
    if "formal" in stages and block.formal_depth is not None and other_edge:
        record["log"].append(f"formal: not run: {OTHER_EDGE}")
    elif "formal" in stages and block.formal_depth is not None:
        mutant_il = (write_formal_mutant(directory, as_mutation, f"formal-{mutant}")
                     if mutant else None)
        result = run_formal(block.build(True), f"mutant_{block.name}_{mutant}",
                            block.formal_depth, mutant_il)
        if mutant_il:
            mutant_il.unlink()
        record["log"].append(f"formal: {result['detail']}")
        if result["verdict"] == KILLED:
            return done("killed", "formal", result["detail"])
        if result["verdict"] == UNDECIDED:
            record["undecided"].append("formal")
    if "equivalence" in stages:
        # a longer simulation than the tests run (other seeds of the same stimulus): a
        # mismatch there shows a difference the tests miss
        result = run_vectors(context["binary"], context["deeper"], mutant)
        record["log"].append(f"deeper simulation: {result['detail']}")
        if result["killed"]:
            return done("survived", "equivalence",
                        f"not equivalent: a longer simulation than the tests' (the same "
                        f"stimulus, other seeds) differs: {result['detail']}")
        if other_edge:
            return done("undecided", "equivalence",
                        f"no difference in the longer simulation; {OTHER_EDGE}")
        if mutant and block.formal_depth is not None and worth_a_probe(directory, as_mutation):
            probe = write_invariant_probe(directory, as_mutation, f"probe-{mutant}")
            result = run_invariant(block.build(True), f"probe_{block.name}_{mutant}",
                                   block.formal_depth, probe)
            probe.unlink()
            record["log"].append(f"invariant: {result['detail']}")
            if result["verdict"] == "equivalent":
                record["by"] = "invariant"
                return done("equivalent", "equivalence", result["detail"])
        read = reading(mutation["key"]) if mutant else None
        if read is not None and read.proof is not None and block.formal_depth is not None:
            # a reading counts only through its proof: the prose is no verdict
            result = check_reading(block, directory, as_mutation, read.proof, mutant)
            record["log"].append(f"reading: {result['detail']}")
            if result["verdict"] == "equivalent":
                record["by"] = "reading"
                return done("equivalent", "equivalence", result["detail"])
        result = run_equivalence(directory, directory / "mutants.il", context["module"],
                                 context["ports"], context["width"], mutant,
                                 context["eq_depth"], context["eq_timeout"],
                                 tuple(mutated_bits(directory / "sim.json", mutation["cell"],
                                                    mutation["port"], mutation["bit"])))
        record["log"].append(f"equivalence: {result['detail']}")
        status = {"equivalent": "equivalent", "not equivalent": "survived",
                  "undecided": "undecided"}[result["verdict"]]
        if status == "equivalent":
            record["by"] = "equiv"
        return done(status, "equivalence", result["detail"])
    return done("survived", "", "survived every stage run (no equivalence check)")


def check_reading(block: Block, directory: Path, mutation: Mutation, proof: Proof,
                  mutant: int) -> dict:
    """A reading's :class:`registry.Proof` on one mutant: its lemmas and the mutation's probe
    in the block's proof (:func:`stages.run_reading`). A proof that cannot be built (a lemma
    naming a wire the netlist lacks, a lemma Yosys cannot read) backs nothing: undecided, and
    said so."""
    try:
        probe = write_invariant_probe(directory, mutation, f"reading-{mutant}", proof.asserts)
    except RuntimeError as error:
        return {"verdict": "undecided",
                "detail": f"the reading's proof could not be built: {str(error)[:300]}"}
    try:
        return run_reading(block.build(True), f"reading_{block.name}_{mutant}",
                           proof.depth or block.formal_depth, probe, len(proof.asserts))
    finally:
        probe.unlink()


def _interrupted(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


@contextlib.contextmanager
def _stopping(pool):
    """On an interrupt, end the pool's worker processes (and what they run) and say how to
    resume: the database holds every finished mutant."""
    try:
        yield
    except KeyboardInterrupt:
        # the pool's workers are this process's children (multiprocessing's public view of
        # them, not the pool's private table)
        for process in multiprocessing.active_children():
            for child in _children(process.pid):
                with contextlib.suppress(ProcessLookupError):
                    os.kill(child, signal.SIGTERM)
            process.kill()         # the workers inherit the handler that turns TERM into
            #                        an interrupt: KILL, not TERM
        pool.shutdown(wait=False, cancel_futures=True)
        print("\nmutate: interrupted; the finished mutants are kept: rerun with --resume",
              flush=True)
        raise


def _children(pid: int) -> list[int]:
    """Every descendant of ``pid`` (from /proc), deepest first."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            ppid = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        if ppid == pid:
            found += [*_children(int(entry.name)), int(entry.name)]
    return found


#: how an equivalent mutant was proven (a record's ``by``): the invariant probe, a reading's
#: proof, Yosys ``equiv``, any of them in the inner block (:func:`inner_checks`)
PROVEN_BY = ("invariant", "reading", "equiv", "inner")
#: the stages a kill is recorded by: the block's own, and the inner block's (any of its stages,
#: :func:`inner_checks`)
KILLED_BY = ("vector", "cocotb", "formal", "inner")


def counts(results: dict) -> dict:
    """Tally of a block's results: the statuses, the kills by stage, the equivalent mutants by
    proof (:data:`PROVEN_BY`), and ``went_on``: mutants a stage could not decide (a proof whose
    induction no longer closes, a run out of time), counted by what the later stages found."""
    tally = {"tried": len(results), "killed": 0, **{stage: 0 for stage in KILLED_BY},
             "equivalent": 0, "undecided": 0, "survived": 0, "went_on": 0,
             **{f"proven_{by}": 0 for by in PROVEN_BY}}
    for r in results.values():
        tally[r["status"]] += 1
        if r["status"] == "killed":
            tally[r["stage"]] += 1
        if r["status"] == "equivalent":
            tally["proven_" + r.get("by", "equiv")] += 1
        tally["went_on"] += bool(r.get("undecided"))
    return tally


def summary_line(tallies: dict, seconds: float) -> str:
    total = {k: sum(t[k] for t in tallies.values()) for k in
             ("tried", "killed", *KILLED_BY, "equivalent", "undecided", "survived")}
    relevant = total["tried"] - total["equivalent"]
    rate = 100.0 * total["killed"] / relevant if relevant else 100.0
    by_stage = ", ".join(f"{'inner block' if stage == 'inner' else stage} {total[stage]}"
                         for stage in KILLED_BY)
    return (f"mutate: {len(tallies)} blocks, {total['tried']} mutants: {total['killed']} killed "
            f"({by_stage}), "
            f"{total['equivalent']} equivalent, {total['undecided']} undecided, "
            f"{total['survived']} survived; {rate:.1f} % of the non-equivalent killed; "
            f"{seconds / 60:.1f} min")


def run(settings: Settings) -> dict:
    """The campaign; returns the tally per block."""
    started = time.time()
    campaigns = {}
    for name in settings.blocks:
        campaign = BlockCampaign(BLOCKS[name], settings)
        print(f"mutate {name}: {len(campaign.mutations)} mutations (seed {settings.seed}), "
              f"{len(campaign.pending())} to run", flush=True)
        campaigns[name] = campaign
    evaluate_all(campaigns, settings, started)
    if not settings.only:
        for campaign in campaigns.values():
            inner_checks(campaign, settings, started)
    tallies = {}
    for name, campaign in campaigns.items():
        tallies[name] = counts({k: r for k, r in campaign.results.items()
                                if r["status"] != "error"})
        errors = [r for r in campaign.results.values() if r["status"] == "error"]
        if errors:
            print(f"mutate {name}: {len(errors)} mutants could not be evaluated; first: "
                  f"{errors[0]['detail'][:500]}")
    print(summary_line(tallies, time.time() - started), flush=True)
    return tallies


def evaluate_all(campaigns: dict, settings: Settings, started: float) -> None:
    """Every pending mutant of ``campaigns`` through the stages, in parallel, each result
    saved as it comes; then the original through the cocotb tests and the proof where a kill
    there needs it (a test failing on the original voids those kills)."""
    from tools.analysis.progress import Progress

    contexts = {name: campaign.prepare() for name, campaign in campaigns.items()}
    jobs = [(name, k, m) for name, c in campaigns.items() for k, m in c.pending()]
    # the original through the cocotb tests and the proof: a test failing on it would "kill"
    # every mutant (its vector stage ran in prepare)
    later = [s for s in ("cocotb", "formal") if s in settings.stages]
    # (a run of chosen keys checks the original afterwards, and only if it has to)
    originals = [name for name, c in campaigns.items()
                 if later and c.baseline is None and not settings.only]
    # tqdm's bar on a terminal; one line per mutant in a log
    progress = Progress(enabled=settings.progress, use_tqdm=None if sys.stderr.isatty() else False)
    progress.start(len(jobs) + len(originals))
    signal.signal(signal.SIGTERM, _interrupted)
    with concurrent.futures.ProcessPoolExecutor(max_workers=settings.jobs) as pool, \
            _stopping(pool):
        futures = {pool.submit(evaluate, {**contexts[name], "stages": later}, 0,
                               ORIGINAL): (name, None) for name in originals}
        futures.update({pool.submit(evaluate, contexts[name], k, m.as_dict(),
                                    campaigns[name].previous(m.key)): (name, m)
                        for name, k, m in jobs})
        for future in concurrent.futures.as_completed(futures):
            name, mutation = futures[future]
            campaign = campaigns[name]
            campaign.ran = True
            if mutation is None:
                campaign.baseline = future.result()
                campaign.save(started)
                verdict = ("FAILS ITS TESTS" if campaign.baseline["status"] == "killed"
                           else "passes its tests")
                progress.advance(1, f"{name}: the original {verdict}")
                continue
            try:
                record = future.result()
            except Exception as error:          # a tool broke: recorded, not a kill
                record = {"status": "error", "stage": "", "detail": str(error)[-2000:],
                          "stages": list(settings.stages)}
            record["key"] = mutation.key
            campaign.results[mutation.key] = record
            campaign.save(started)
            t = counts({k: r for k, r in campaign.results.items() if r["status"] != "error"})
            progress.advance(1, f"{name}: {t['killed']} killed, {t['survived']} survived, "
                                f"{t['undecided']} undecided")
    progress.finish()
    for name, campaign in campaigns.items():
        if later and campaign.baseline is None and any(
                r.get("stage") in later for r in campaign.results.values()):
            campaign.baseline = evaluate({**contexts[name], "stages": later}, 0, ORIGINAL)
            campaign.ran = True
        if later and campaign.baseline and campaign.baseline["status"] == "killed":
            print(f"mutate {name}: THE ORIGINAL FAILS ITS TESTS ({campaign.baseline['detail']})"
                  ": its cocotb and formal kills are void")
            for r in campaign.results.values():
                if r["status"] == "killed" and r["stage"] in ("cocotb", "formal"):
                    r.update(status="error", detail="the original fails this stage too")
        if campaign.ran:
            campaign.save(started)


def inner_key(key: str, scope: str) -> str | None:
    """The key of the same mutation in the block an outer block holds as instance ``scope``
    (:attr:`Block.inner`): the instance's name taken off the hierarchy field (its own top
    level is ``top``); None for a mutation outside that instance."""
    source, where, rest = key.split(" ", 2)
    if where == scope:
        return f"{source} top {rest}"
    if where.startswith(scope + "."):
        return f"{source} {where[len(scope) + 1:]} {rest}"
    return None


def merged(outer: dict, inner: dict | None, block: str) -> dict:
    """An outer block's record after its mutation ran through the stages of ``block`` (the
    inner block, its own tests, proof and checks, on its own netlist with the same mutation):
    killed there is killed (a test of the suite fails on the fault); proven equivalent there,
    an undecided mutant is equivalent (the inner block's outputs are the outer's only view of
    it); any other verdict leaves the record as it was, with a line in its log."""
    if inner is None or inner["status"] == "error":
        why = "its key names no cell there" if inner is None else inner["detail"][:300]
        return {**outer, "inner": block,
                "log": [*outer["log"], f"{block}'s stages: not run ({why})"]}
    line = f"{block}'s stages: {inner['status']} ({inner['stage'] or '-'}): {inner['detail']}"
    record = {**outer, "inner": block, "log": [*outer["log"], line]}
    if inner["status"] == "killed":
        record.update(status="killed", stage="inner",
                      detail=f"by {block}'s {inner['stage']} stage: {inner['detail']}")
    elif inner["status"] == "equivalent" and outer["status"] == "undecided":
        record.update(status="equivalent", stage="equivalence", by="inner",
                      detail=f"proven in {block} ({inner.get('by', 'equiv')}): "
                             f"{inner['detail']}")
    return record


def inner_checks(campaign: BlockCampaign, settings: Settings, started: float) -> None:
    """The survivors and undecided mutants of ``campaign`` inside an instance of a block that
    has its own campaign (:attr:`Block.inner`: the same logic, the same parameters) through
    that block's stages, on its netlist with the same mutation; their records updated
    (:func:`merged`). Results are kept in ``build/mutate/<inner>-in-<outer>/`` and resumed
    from there."""
    for scope, inner_name in campaign.block.inner:
        mapped = {}
        for key, record in campaign.results.items():
            inner = inner_key(key, scope)
            if (inner and record["status"] in ("survived", "undecided")
                    and record.get("inner") != inner_name):
                mapped[inner] = key
        if not mapped:
            continue
        # --retry (the tests changed) runs the inner block's undecided records again too
        inner_settings = replace(settings, blocks=(inner_name,), only=tuple(mapped),
                                 resume=True, recheck=False, retry_survived=False)
        inner = BlockCampaign(BLOCKS[inner_name], inner_settings,
                              BUILD / f"{inner_name}-in-{campaign.block.name}")
        print(f"mutate {campaign.block.name}: {len(mapped)} mutants inside {scope} through "
              f"{inner_name}'s stages ({len(inner.pending())} to run)", flush=True)
        if inner.mutations:
            evaluate_all({inner_name: inner}, inner_settings, started)
        for key, outer_key in mapped.items():
            campaign.results[outer_key] = merged(campaign.results[outer_key],
                                                 inner.results.get(key), inner_name)
        campaign.save(started)
