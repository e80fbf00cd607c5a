# RLE-Bench: two commands on a fresh machine, `make demo` and `make test`.
# Each target bootstraps .venv on first use and is idempotent afterwards.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.rle-installed
ROBOSUITE := robosuite==1.5.2
export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: demo test test-full lint format bench clean venv

venv: $(STAMP)

$(STAMP): pyproject.toml Makefile
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev,viz,learn]'
	@# robosuite is an asset source only (arm MJCF and meshes). Its runtime pins an old MuJoCo and
	@# numpy<2 through mink, so it is installed without dependencies and never imported.
	$(PY) -m pip install --quiet --no-deps $(ROBOSUITE)
	$(PY) scripts/check_system.py
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/rle demo

lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

format: $(STAMP)
	$(VENV)/bin/ruff format .
	$(VENV)/bin/ruff check --fix .

test: $(STAMP) lint
	$(PY) -m pytest -q

test-full: $(STAMP) lint
	RLE_FULL_BATTERY=1 $(PY) -m pytest -q

bench: $(STAMP)
	$(PY) -m benchmarks

clean:
	rm -rf $(VENV) out .pytest_cache .ruff_cache
