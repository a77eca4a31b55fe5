# crslab developer entry points. Every target that needs Python creates or reuses .venv and
# installs the package (editable, with its test extra) first, so a fresh clone needs only
# Python 3.11+, gcc and make.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.crslab-installed
# Anything that changes what the install builds or pulls in.
DEPS   := pyproject.toml setup.py crslab/cheaders.py $(wildcard csrc/*.py csrc/kin/*.c csrc/kin/*.h csrc/board/*.c csrc/board/*.h csrc/plant/*.c csrc/plant/*.h csrc/port/*.c csrc/port/*.h csrc/page/*.c csrc/page/*.h)

.DEFAULT_GOAL := help
.PHONY: help sim test bench mutants lint clean venv

help: ## list the targets
	@echo "crslab targets:"
	@grep -E '^[a-z]+:.*## ' $(MAKEFILE_LIST) | sed -E 's/:.*## /\t/' | awk -F'\t' '{printf "  make %-7s %s\n", $$1, $$2}'

$(STAMP): $(DEPS)
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	$(PY) -m crslab.lab.prepare   # zig's C library for the firmware, once per zig version (1-2 min the first time)
	@touch $@

venv: $(STAMP) ## create .venv and install crslab (editable) with its test tools

sim: $(STAMP) ## run the simulator on its built-in default lab and scenario
	$(VENV)/bin/crslab sim

test: $(STAMP) ## run the whole test suite (C core under -Werror, ASan and UBSan included), two at a time
	$(PY) -m pytest -q -n 2 --dist loadfile

bench: $(STAMP) ## run every benchmark (speed, compile times, serve's capacity), each number beside its target
	$(PY) -m pip install --quiet -e '.[test,bench]'
	$(PY) tools/bench.py

mutants: $(STAMP) ## apply one-line bugs to a copy and check the suite notices each (slow; not in CI)
	$(PY) tools/mutants.py

lint: $(STAMP) ## ruff over the Python sources
	$(VENV)/bin/ruff check crslab tests tools csrc setup.py

clean: ## remove the venv, build products and caches
	rm -rf $(VENV) build *.egg-info crslab/_core.* .pytest_cache .ruff_cache .hypothesis .crslab-cache
	find . -name __pycache__ -type d -prune -exec rm -rf {} +
