# rrbody: two set-up commands on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test bench scenes clean venv

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,dask]'
	touch $(STAMP)

venv: $(STAMP)

## make demo: set up, then run the main job: Movie S1 -> movies/movie_s1.mp4
demo: $(STAMP)
	$(BIN)/rrbody demo

## make test: set up, then the whole test suite (2 workers)
test: $(STAMP)
	$(BIN)/python -m pytest -n 2 --durations=15 tests

## make bench: work-precision benchmarks -> benchmarks/results/
bench: $(STAMP)
	$(BIN)/python -m benchmarks.run

## make scenes: every paper figure and the report -> results/
scenes: $(STAMP)
	$(BIN)/rrbody scene all

clean:
	rm -rf $(VENV) build *.egg-info
