# slam_predict — the two commands that do everything on a fresh machine: `make demo`, `make test`.
SHELL := /bin/bash
ROOT := $(CURDIR)
VENV := $(ROOT)/.venv
PY := $(VENV)/bin/python
DEMO_OUT ?= $(ROOT)/out/demo
export NUMBA_CACHE_DIR ?= $(ROOT)/.numba_cache
# Tests marked `slow` (full end-to-end sweeps) only run with `make test-full` or as benchmarks.
PYTEST_ARGS ?= -m "not slow"

.PHONY: setup demo test test-full lint pytest rostest bench clean

setup:
	@bash tools/setup.sh

demo: setup
	@bash tools/demo.sh "$(DEMO_OUT)"

test: setup
	@$(MAKE) --no-print-directory lint pytest rostest

# ruff (rules and line length in ruff.toml) over the whole repository, before any test runs.
lint:
	@$(VENV)/bin/ruff check --no-cache $(ROOT)

pytest:
	@set +u; source setup.bash; set -u; $(PY) -m pytest tests $(PYTEST_ARGS)

rostest:
	@bash tools/run_rostests.sh

test-full: setup
	@$(MAKE) --no-print-directory lint pytest rostest PYTEST_ARGS=

# The quick benchmarks (no arguments, no upstream checkout); the others: docs/benchmarks.md.
bench: setup
	@bash tools/run_benches.sh

clean:
	[ -f .workspace_path ] && rm -rf "$$(cat .workspace_path)"; rm -rf out .numba_cache setup.bash .workspace_path
