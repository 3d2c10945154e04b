"""The README's cocotb-test snippet, run as the README prints it: taken from README.md, run from
a folder laid out as the repository (``tb``, ``.venv`` and the Verilog a run writes, built here
with the harness for the snippet's toplevel and parameters) under the environment its comment
names. The snippet's Verilog path must be the one the harness writes for those parameters, and
its parameters the ones the block's own test passes."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

from mdfqm_gateware.sort import SortNetwork
from mdfqm_testkit.harness import PARAMS_ENV, ROOT, TB_DIR, param_tag, write_verilog

#: the blocks a README snippet may name: toplevel -> the component its test builds
FACTORIES = {"sort_network": lambda p: SortNetwork(p["count"], p["width"])}


def readme_snippet() -> str:
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    [snippet] = [b for b in blocks if "cocotb_test" in b]
    return snippet


def test_readme_cocotb_test_snippet_runs(tmp_path):
    snippet = readme_snippet()
    toplevel = re.search(r'toplevel="(\w+)"', snippet).group(1)
    [source] = re.search(r"verilog_sources=\[([^]]*)\]", snippet).group(1).strip('"').split('", "')
    params = json.loads(re.search(rf"\"{PARAMS_ENV}\": '([^']*)'", snippet).group(1))
    component = FACTORIES[toplevel](params)
    assert params["latency"] == component.latency, "the snippet's latency is not the block's"
    directory = Path("build", "sim", f"{toplevel}-{param_tag(params)}")
    assert Path(source) == directory / f"{toplevel}.v", "not the path a run writes"
    write_verilog(component, toplevel, tmp_path / directory)
    (tmp_path / "tb").symlink_to(TB_DIR)
    (tmp_path / ".venv").symlink_to(Path(sys.executable).parents[1])
    (tmp_path / "snippet.py").write_text(snippet)
    # the environment of the snippet's comment: NAME=VALUE, $NAME expanded as a shell in the
    # folder would ($PWD the folder)
    comment = re.search(r"#\s*(\w+=.*)$", snippet, re.M).group(1)
    env = {k: v for k, v in os.environ.items()
           if k not in ("SIM", "COCOTB_RESULTS_FILE") and not k.startswith("PYTEST")}
    env["PWD"] = str(tmp_path)
    for name, value in (item.split("=", 1) for item in comment.split()):
        env[name] = re.sub(r"\$(\w+)", lambda m: env.get(m.group(1), ""), value)
    result = subprocess.run([sys.executable, "snippet.py"], cwd=tmp_path, env=env,
                            capture_output=True, text=True)
    log = result.stdout + result.stderr
    assert result.returncode == 0, log[-4000:]
    ran = re.findall(r"test_sort\.(\w+)\s+PASS", log)
    assert ran == ["sort_random_and_ties"], log[-4000:]
