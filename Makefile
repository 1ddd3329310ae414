# rrbody: two set-up commands on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
# extras each target installs (pyproject.toml, [project.optional-dependencies]); the core alone
# (numpy, scipy, numba, tqdm) computes flip times and trajectories
DEMO_EXTRAS := movie
TEST_EXTRAS := test,engine,movie,rerun,dask,data,mujoco,envs
DOCS_EXTRAS := docs,movie,envs

.PHONY: demo test bench scenes docs docs-check clean venv venv-lowest

# Each long step first says what it does and how long it took in the recorded run of a clean clone
# (`==> STEP: ...`; python -m benchmarks.setup_times records every step's time from these lines into
# benchmarks/results/setup.json, and python -m benchmarks.quotes writes the figures below from it).
# unq: a quoted figure without its two markers (the text between them); the markers are spelt here
# with the empty variable E inside, so that only the quoted figures hold them
E :=
unq = $(filter-out <!--q$(E):%,$(subst -->,--> ,$(subst <!--/q$(E)-->,,$(1))))
T_VENV := <!--q:setup.demo.venv-->4 s<!--/q-->
T_REQS := <!--q:setup.demo.build-reqs-->4 s<!--/q-->
T_DEMO_PKGS := <!--q:setup.demo.install-->2 s<!--/q-->
T_TEST_PKGS := <!--q:setup.test.install-->7 s<!--/q-->
T_DEMO_KERNELS := <!--q:setup.demo.kernels-->42 s<!--/q-->
T_LOAD := <!--q:setup.demo.load-->0.3-1.2<!--/q-->
T_KERNELS := <!--q:setup.test.kernels-->137 s<!--/q-->
T_TEST_LOAD := <!--q:setup.test.load-->1.2-2.1<!--/q-->
T_MOVIE := <!--q:setup.demo.demo-->32 s<!--/q-->
T_LOWEST := <!--q:setup.test.lowest-venv-->7 s<!--/q-->
T_SUITE := <!--q:setup.test.suite-->272 s<!--/q-->
T_SUITE_LOWEST := <!--q:setup.test.suite-lowest-->138 s<!--/q-->
T_SUITE_PUBLIC := <!--q:setup.test.suite-public-->114 s<!--/q-->

# The venv's packages are installed by uv (from PyPI, like pip; the test venv's packages in 17 s
# against pip's 35-39 s), itself installed into the venv by the venv's pip: a fresh machine needs
# nothing but python3. Its version is pinned here, and only here (tests/test_install.py uses this
# uv, from the venv it runs in).
UV_VERSION := 0.13.9
UV := $(BIN)/uv
# --compile-bytecode: the packages' .pyc written at install, as pip does (with PYTHONDONTWRITEBYTECODE
# set, no process would ever write them, and each would compile numpy, scipy and numba from source)
UV_PIP = $(UV) pip install --quiet --compile-bytecode --python $(BIN)/python

# the venv, with uv in it and pip (`.venv/bin/pip install -e '.[mujoco]'`, docs/getting-started.md) up to date
$(UV):
	@echo "==> venv: creating $(VENV) with uv in it (about $(call unq,$(T_VENV)) in the recorded run)"
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check 'uv==$(UV_VERSION)'
	$(UV_PIP) --upgrade pip

# rrbody is built in the venv itself (--no-build-isolation): its build compiles the kernels with the
# numba the venv runs (an isolated build environment could hold another), and numba, scipy and pymunk
# are installed once, not twice. So pyproject's build requirements go in first.
BUILD_REQS = $(BIN)/python -c "import subprocess, sys, tomllib; \
	reqs = tomllib.load(open('pyproject.toml', 'rb'))['build-system']['requires']; \
	subprocess.check_call(['$(UV)', 'pip', 'install', '--quiet', '--compile-bytecode', '--python', sys.executable, *reqs])"
# The install compiles no kernel (RRBODY_BUILD_KERNELS=0): through uv or pip a build's output is
# hidden, and the compilation is the longest step; the .venv/.kernels step below runs the same build
# (rrbody.cli.prebuild) where its progress shows. `pip install .` outside the Makefile still compiles
# them at install (setup.py).
INSTALL = RRBODY_BUILD_KERNELS=0 $(UV_PIP) --no-build-isolation -e

$(VENV)/.build-reqs: pyproject.toml | $(UV)
	@echo "==> build-reqs: installing numpy, scipy, numba, pymunk and the other build requirements (about $(call unq,$(T_REQS)) in the recorded run)"
	$(BUILD_REQS)
	touch $@

# one stamp per set of extras: reinstalled only when pyproject.toml changes
$(VENV)/.installed-demo: pyproject.toml | $(VENV)/.build-reqs
	@echo "==> install: installing rrbody and the [$(DEMO_EXTRAS)] extra's packages (about $(call unq,$(T_DEMO_PKGS)) in the recorded run)"
	$(INSTALL) '.[$(DEMO_EXTRAS)]'
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(VENV)/.build-reqs
	@echo "==> install: installing rrbody and the packages of the extras $(TEST_EXTRAS) (about $(call unq,$(T_TEST_PKGS)) in the recorded run)"
	$(INSTALL) '.[$(TEST_EXTRAS)]'
	touch $@

$(VENV)/.installed-docs: pyproject.toml | $(VENV)/.build-reqs
	$(INSTALL) '.[$(DOCS_EXTRAS)]'
	touch $@

# the kernels, compiled once per version of their sources (rrbody.cli.prebuild: a line as each job
# ends); after an edit the targets that run rrbody compile them again (a few seconds when nothing changed)
# (rrbody._cache.KERNEL_LAYERS: the files the kernels are compiled from; the prebuild's own list of work,
# and the scene the demo's part follows)
KERNEL_SOURCES := $(shell find rrbody/model rrbody/physics rrbody/integrate rrbody/contact rrbody/engine rrbody/mujoco_adapter -name '*.py') \
	rrbody/_cache.py rrbody/_private.py rrbody/_version.py rrbody/cli/prebuild.py rrbody/cli/workload.py scenes/movie_s1.py
# every kernel, into the checkout's rrbody/_kernels (an install's): what make test, make bench and make scenes need
$(VENV)/.kernels: $(KERNEL_SOURCES) | $(VENV)/.build-reqs
	@echo "==> kernels: compiling every kernel of rrbody with numba (about $(call unq,$(T_KERNELS)) in the recorded run, on 2 cores shared with load $(call unq,$(T_TEST_LOAD)); once per version of the sources)"
	$(BIN)/python -m rrbody.cli.prebuild --into rrbody/_kernels
	touch $@

# only the kernels `rrbody demo` needs (Movie S1: the part demo of rrbody.cli.prebuild.PARTS), into your
# cache folder, where they serve your own commands too; the others compile where they are first used,
# or all at once in make test (the step above) or with `rrbody cache build`. Nothing when every kernel
# is compiled already (make test ran first)
$(VENV)/.kernels-demo: $(KERNEL_SOURCES) | $(VENV)/.build-reqs
	@echo "==> kernels: compiling the kernels Movie S1 needs with numba (about $(call unq,$(T_DEMO_KERNELS)) in the recorded run, on 2 cores shared with load $(call unq,$(T_LOAD)); the others compile where first used, or in make test)"
	$(BIN)/python -m rrbody.cli.prebuild --part demo
	touch $@

# The targets that need every kernel compiled run on a cache folder of the venv's own, which their first
# use fills from rrbody/_kernels: your cache folder may hold only some (make demo's part, or your own
# first uses), and numba keeps each function's overloads in one file there, so a function begun with
# some overloads would compile the others in the middle of the suite or of a benchmark
MAKE_CACHE = RRBODY_CACHE_DIR=$(CURDIR)/$(VENV)/rrbody-cache

venv: $(VENV)/.installed-test

## make demo: set up (core + movie extra), then run the main job: Movie S1 -> movies/movie_s1.mp4
demo: $(VENV)/.installed-demo $(VENV)/.kernels-demo
	@echo "==> demo: computing Movie S1's run and rendering it to movies/movie_s1.mp4 (about $(call unq,$(T_MOVIE)) in the recorded run)"
	$(BIN)/rrbody demo

# the oldest versions pyproject allows: uv's lowest-direct resolution of the core, the engine (pymunk
# 6.6), mujoco, movie and test extras (not rerun: rerun-sdk 0.41 needs numpy >= 2, which numba 0.59 does not run on;
# the rerun recordings' tests are left out there), in a venv of their own; rrbody runs there from this checkout,
# its kernels compiled by that venv's numba into a cache folder of its own (the checkout's install-time
# kernels are the main venv's numba's: not copied, RRBODY_NO_SEED). make test runs LOWEST_TESTS there
# after the whole suite: the kernels of a flip time, the plugin and its exact references on every route,
# the recorder, the takeovers of private names, the coupled step's two routes to the contacts, the MuJoCo adapter
# and its push, rrbody.envs against the installed
# gym-pusht (docs/versions.md)
LOWEST := .venv-lowest
LOWEST_EXTRAS := test engine mujoco movie envs
# gym-pusht pins pymunk < 7: it lives here, beside pymunk 6.6, for the fidelity checks of rrbody.envs
# against the real package (RRBODY_REQUIRE_PUSHT=1 turns their skip, where it is missing, into a failure)
PUSHT := gym-pusht==0.1.8
LOWEST_TESTS := tests/test_flip.py tests/test_plugin_io.py tests/test_plugin_fused.py tests/test_takeovers.py tests/test_plugin.py \
	tests/test_recorder.py tests/test_mujoco.py tests/test_tableaus.py tests/test_envs_pusht.py tests/test_envs_table.py tests/test_envs_draw.py \
	tests/test_overlap.py tests/test_coupled_routes.py tests/test_mujoco_push.py
LOWEST_RUN = PYTHONPATH=$(CURDIR) RRBODY_REQUIRE_PUSHT=1 RRBODY_CACHE_DIR=$(CURDIR)/$(LOWEST)/cache RRBODY_NO_SEED=1 MPLBACKEND=Agg \
	$(LOWEST)/bin/python

# the takeovers of every private fast path at once (rrbody._private: RRBODY_NO_PRIVATE=1; docs/versions.md):
# the plugin's routes and exact references, the recorder, the drive, the ODE kernels, the MuJoCo adapter
# (the tests that compare a private path with its takeover are marked `private` and skipped there)
PUBLIC_TESTS := tests/test_plugin_io.py tests/test_plugin.py tests/test_takeovers.py tests/test_recorder.py \
	tests/test_flip.py tests/test_mujoco.py tests/test_private_switch.py tests/test_coupled_routes.py

$(LOWEST)/.installed: pyproject.toml | $(UV)
	@echo "==> lowest-venv: installing the oldest versions pyproject allows into $(LOWEST) (about $(call unq,$(T_LOWEST)) in the recorded run)"
	$(UV) venv --quiet --allow-existing --python $(BIN)/python $(LOWEST)
	$(UV) pip install --quiet --compile-bytecode --python $(LOWEST)/bin/python --resolution lowest-direct \
		-r pyproject.toml $(addprefix --extra ,$(LOWEST_EXTRAS)) '$(PUSHT)'
	touch $@

venv-lowest: $(LOWEST)/.installed

## make test: set up (test, engine, movie, rerun, dask, data, mujoco extras), then the whole test suite (2 workers),
## then a stated part of it on the oldest versions pyproject allows (.venv-lowest), and one with every private fast path off
# --dist loadgroup: the tests marked xdist_group (a file that builds costly wrench tables) run in one
# worker, which builds each table once; pytest-xdist hands those groups out first, then every other
# test one at a time in the suite's order (tests/conftest.py: the slow ones first)
test: $(VENV)/.installed-test $(VENV)/.kernels $(LOWEST)/.installed
	@echo "==> lint: ruff check"
	$(BIN)/ruff check rrbody scenes tests benchmarks
	@echo "==> suite: running the test suite on 2 workers (about $(call unq,$(T_SUITE)) in the recorded run)"
	$(MAKE_CACHE) $(BIN)/python -m pytest -n 2 --dist loadgroup --durations=15 tests
	@echo "==> suite-lowest: running part of it on the oldest versions (about $(call unq,$(T_SUITE_LOWEST)) in the recorded run; compiles its kernels)"
	$(LOWEST_RUN) -m pytest -n 2 -q -p no:cacheprovider -k 'not rerun and not film_it' $(LOWEST_TESTS)
	@echo "==> suite-public: running part of it with every private fast path off, RRBODY_NO_PRIVATE=1 (about $(call unq,$(T_SUITE_PUBLIC)) in the recorded run; compiles its kernels)"
	$(MAKE_CACHE) RRBODY_NO_PRIVATE=1 MPLBACKEND=Agg $(BIN)/python -m pytest -n 2 -q -p no:cacheprovider $(PUBLIC_TESTS)


## make bench: work-precision benchmarks -> benchmarks/results/, then every figure the docs quote
bench: $(VENV)/.installed-test $(VENV)/.kernels $(LOWEST)/.installed
	$(MAKE_CACHE) $(BIN)/python -m benchmarks.run --skip pusht
	# Push-T against gym-pusht's own env: where gym-pusht is installed (it pins pymunk < 7)
	$(LOWEST_RUN) -m benchmarks.run --only pusht
	$(BIN)/python -m benchmarks.quotes

## make scenes: every paper figure and the report -> results/
scenes: $(VENV)/.installed-test $(VENV)/.kernels
	$(MAKE_CACHE) $(BIN)/rrbody scene all

## make docs: the documentation site -> docs/_build/html (from the committed results/; warnings are errors)
docs: $(VENV)/.installed-docs
	$(BIN)/python -m sphinx -W --keep-going -q -b html docs docs/_build/html

## make docs-check: load every page of the built site in headless Chromium (needs chromium + chromium-driver)
docs-check: $(VENV)/.installed-docs
	$(BIN)/python docs/check_site.py docs/_build/html

clean:
	rm -rf $(VENV) $(LOWEST) build *.egg-info docs/_build rrbody/_kernels
