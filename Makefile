# rrbody: two set-up commands on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
# extras each target installs (pyproject.toml, [project.optional-dependencies]); the core alone
# (numpy, scipy, numba, tqdm) computes flip times and trajectories
DEMO_EXTRAS := movie
TEST_EXTRAS := test,engine,movie,rerun,dask,data,mujoco
DOCS_EXTRAS := docs,movie

.PHONY: demo test bench scenes docs docs-check clean venv venv-lowest

# The venv's packages are installed by uv (from PyPI, like pip; the test venv's packages in 17 s
# against pip's 35-39 s), itself installed into the venv by the venv's pip: a fresh machine needs
# nothing but python3. Its version is pinned here, and only here (tests/test_install.py uses this
# uv, from the venv it runs in).
UV_VERSION := 0.13.9
UV := $(BIN)/uv
# --compile-bytecode: the packages' .pyc written at install, as pip does (with PYTHONDONTWRITEBYTECODE
# set, no process would ever write them, and each would compile numpy, scipy and numba from source)
UV_PIP = $(UV) pip install --quiet --compile-bytecode --python $(BIN)/python

# the venv, with uv in it and pip (`.venv/bin/pip install -e '.[engine]'`, README) up to date
$(UV):
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check 'uv==$(UV_VERSION)'
	$(UV_PIP) --upgrade pip

# rrbody is built in the venv itself (--no-build-isolation): its build compiles the kernels with the
# numba the venv runs (an isolated build environment could hold another), and numba, scipy and pymunk
# are installed once, not twice. So pyproject's build requirements go in first.
BUILD_REQS = $(BIN)/python -c "import subprocess, sys, tomllib; \
	reqs = tomllib.load(open('pyproject.toml', 'rb'))['build-system']['requires']; \
	subprocess.check_call(['$(UV)', 'pip', 'install', '--quiet', '--compile-bytecode', '--python', sys.executable, *reqs])"
INSTALL = $(UV_PIP) --no-build-isolation -e

# one stamp per set of extras: reinstalled only when pyproject.toml changes
$(VENV)/.installed-demo: pyproject.toml | $(UV)
	$(BUILD_REQS)
	$(INSTALL) '.[$(DEMO_EXTRAS)]'
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(UV)
	$(BUILD_REQS)
	$(INSTALL) '.[$(TEST_EXTRAS)]'
	touch $@

$(VENV)/.installed-docs: pyproject.toml | $(UV)
	$(BUILD_REQS)
	$(INSTALL) '.[$(DOCS_EXTRAS)]'
	touch $@

# the kernels compiled at install (setup.py) are those of the sources at install time; after an edit
# the suite's own targets compile them again (a few seconds when nothing changed: rrbody.cli.prebuild)
# (rrbody._cache.KERNEL_LAYERS: the files the kernels are compiled from; the prebuild's own list of work)
KERNEL_SOURCES := $(shell find rrbody/model rrbody/physics rrbody/integrate rrbody/engine -name '*.py') \
	rrbody/_cache.py rrbody/_version.py rrbody/cli/prebuild.py rrbody/cli/workload.py
$(VENV)/.kernels: $(KERNEL_SOURCES) | $(VENV)/.installed-test
	$(BIN)/python -m rrbody.cli.prebuild --into rrbody/_kernels
	touch $@

venv: $(VENV)/.installed-test

## make demo: set up (core + movie extra), then run the main job: Movie S1 -> movies/movie_s1.mp4
demo: $(VENV)/.installed-demo
	$(BIN)/rrbody demo

# the oldest versions pyproject allows: uv's lowest-direct resolution of the core, the engine (pymunk
# 6.6), mujoco, movie and test extras (not rerun: rerun-sdk 0.41 needs numpy >= 2, which numba 0.59 does not run on;
# the rerun recordings' tests are left out there), in a venv of their own; rrbody runs there from this checkout,
# its kernels compiled by that venv's numba into a cache folder of its own (the checkout's install-time
# kernels are the main venv's numba's: not copied, RRBODY_NO_SEED). make test runs LOWEST_TESTS there
# after the whole suite: the kernels of a flip time, the plugin and its exact references on every route,
# the recorder, the takeovers of private names, the MuJoCo adapter (docs/versions.md)
LOWEST := .venv-lowest
LOWEST_EXTRAS := test engine mujoco movie
LOWEST_TESTS := tests/test_flip.py tests/test_plugin_io.py tests/test_takeovers.py tests/test_plugin.py \
	tests/test_recorder.py tests/test_mujoco.py
LOWEST_RUN = PYTHONPATH=$(CURDIR) RRBODY_CACHE_DIR=$(CURDIR)/$(LOWEST)/cache RRBODY_NO_SEED=1 MPLBACKEND=Agg \
	$(LOWEST)/bin/python

$(LOWEST)/.installed: pyproject.toml | $(UV)
	$(UV) venv --quiet --allow-existing --python $(BIN)/python $(LOWEST)
	$(UV) pip install --quiet --compile-bytecode --python $(LOWEST)/bin/python --resolution lowest-direct \
		-r pyproject.toml $(addprefix --extra ,$(LOWEST_EXTRAS))
	touch $@

venv-lowest: $(LOWEST)/.installed

## make test: set up (test, engine, movie, rerun, dask, data, mujoco extras), then the whole test suite (2 workers),
## then a stated part of it on the oldest versions pyproject allows (.venv-lowest)
# --dist loadgroup: the tests marked xdist_group (a file that builds costly wrench tables) run in one
# worker, which builds each table once; pytest-xdist hands those groups out first, then every other
# test one at a time in the suite's order (tests/conftest.py: the slow ones first)
test: $(VENV)/.installed-test $(VENV)/.kernels $(LOWEST)/.installed
	$(BIN)/python -m pytest -n 2 --dist loadgroup --durations=15 tests
	$(LOWEST_RUN) -m pytest -n 2 -q -p no:cacheprovider -k 'not rerun and not film_it' $(LOWEST_TESTS)


## make bench: work-precision benchmarks -> benchmarks/results/, then every figure the README and docs quote
bench: $(VENV)/.installed-test $(VENV)/.kernels
	$(BIN)/python -m benchmarks.run
	$(BIN)/python -m benchmarks.quotes

## make scenes: every paper figure and the report -> results/
scenes: $(VENV)/.installed-test
	$(BIN)/rrbody scene all

## make docs: the documentation site -> docs/_build/html (from the committed results/; warnings are errors)
docs: $(VENV)/.installed-docs
	$(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html

## make docs-check: load every page of the built site in headless Chromium (needs chromium + chromium-driver)
docs-check: $(VENV)/.installed-docs
	$(BIN)/python docs/check_site.py docs/_build/html

clean:
	rm -rf $(VENV) $(LOWEST) build *.egg-info docs/_build rrbody/_kernels
