# mrexplore: `make demo` and `make test` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: install demo test test-slow lint typecheck bench clean

install: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[all,dev]'
	touch $(STAMP)

demo: install
	$(BIN)/python -m mrexplore.demo

lint: install
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/ruff format --check src tests benchmarks

typecheck: install
	$(BIN)/mypy src/mrexplore

test: lint typecheck
	OMP_NUM_THREADS=1 $(BIN)/pytest -q

# The slow matrices and full reproductions (about an hour on two cores).
test-slow: install
	OMP_NUM_THREADS=1 $(BIN)/pytest -q -m slow -n auto

# Scenarios S1-S6 and the scaling table; appends to benchmarks/RESULTS.md.
bench: install
	OMP_NUM_THREADS=1 $(BIN)/python benchmarks/bench_suite.py --scaling --record

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info .pytest_cache .mypy_cache .ruff_cache
