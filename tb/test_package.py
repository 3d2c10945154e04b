"""The hardware package as a user installs it: its wheel holds the specification, the gateware and
the model only (no host CLI, no board demo, no tools), installs into an empty venv with the exact
versions of requirements.lock, elaborates the core there, and ``import mdfqm_gateware`` loads
neither NumPy nor the golden model."""

import os
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"mdfqm_spec", "mdfqm_gateware", "mdfqm_model"}


def _python(tmp_path: Path) -> Path:
    return tmp_path / "venv" / "bin" / "python"


def test_import_mdfqm_gateware_loads_no_numpy():
    code = ("import sys, mdfqm_gateware\n"
            "from mdfqm_gateware import (GateDriver, GatingSignalGenerator, InverseClarke,\n"
            "                            MdfqmCore, MdfqmTop)\n"
            "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('numpy', 'mdfqm_model'))\n"
            "print(bad)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout


def test_every_module_declares_all():
    missing = [str(p.relative_to(ROOT)) for folder in ("spec", "rtl", "model/mdfqm_model",
                                                       "host/mdfqm_host", "drive/mdfqm_drive",
                                                       "demo", "tools")
               for p in sorted((ROOT / folder).rglob("*.py"))
               if "tests" not in p.parts and "__all__" not in p.read_text()]
    assert missing == []


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", str(out),
                    str(ROOT)], check=True)
    (path,) = out.glob("mdfqm-*.whl")
    return path


def test_wheel_holds_hardware_only(wheel):
    with zipfile.ZipFile(wheel) as archive:
        names = archive.namelist()
        entry_points = next(archive.read(n).decode() for n in names
                            if n.endswith(".dist-info/entry_points.txt"))
    top = {n.split("/")[0] for n in names if not n.split("/")[0].endswith(".dist-info")}
    assert top == PACKAGES
    assert not [n for n in names if any(word in n for word in ("host", "demo", "perf", "tools"))]
    assert "mdfqm-dropin = mdfqm_gateware.dropin:main" in entry_points
    assert "mdfqm-host" not in entry_points


def test_wheel_installs_and_elaborates_in_an_empty_venv(wheel, tmp_path):
    venv.create(tmp_path / "venv", with_pip=True)
    python = _python(tmp_path)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    subprocess.run([str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
                    "-c", str(ROOT / "requirements.lock"), str(wheel)], check=True, env=env)
    code = ("import sys\n"
            "from amaranth.back import verilog\n"
            "from mdfqm_gateware import MdfqmCore\n"
            "assert 'numpy' not in sys.modules\n"
            "text = verilog.convert(MdfqmCore(3, 16), name='mdfqm_core_n3_w16')\n"
            "assert 'module mdfqm_core_n3_w16' in text\n"
            "import mdfqm_model, numpy\n"
            "print(mdfqm_model.CoreModel(3, 16).latency, numpy.__version__)\n")
    out = subprocess.run([str(python), "-c", code], capture_output=True, text=True, cwd=tmp_path,
                         env=env)
    assert out.returncode == 0, out.stderr
    latency, numpy_version = out.stdout.split()
    assert latency == "8"
    lock = (ROOT / "requirements.lock").read_text().splitlines()
    assert f"numpy=={numpy_version}" in lock
    dropin = tmp_path / "venv" / "bin" / "mdfqm-dropin"
    done = subprocess.run([str(dropin), "--out", str(tmp_path / "out")], capture_output=True,
                          text=True, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "mdfqm_top_n3_w16.v").read_text().startswith("/*")
