"""The drive distribution depends on the hardware library, never the reverse."""

import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_model_spec_and_gateware_never_import_the_drive():
    code = (
        "import sys, pkgutil, importlib\n"
        "for name in ('mdfqm_spec', 'mdfqm_model', 'mdfqm_gateware'):\n"
        "    pkg = importlib.import_module(name)\n"
        "    for m in pkgutil.walk_packages(pkg.__path__, name + '.'):\n"
        "        importlib.import_module(m.name)\n"
        "bad = sorted(m for m in sys.modules if m.startswith('mdfqm_drive') or m == 'motulator')\n"
        "print(bad)\n"
        "sys.exit(1 if bad else 0)\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    for folder in ("spec", "rtl", "model"):
        for path in (ROOT / folder).rglob("*.py"):
            text = path.read_text()
            assert "mdfqm_drive" not in text and "motulator" not in text, path
