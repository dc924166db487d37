# mrexplore: `make demo` and `make test` work on a fresh machine.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: install demo test test-slow lint typecheck bench clean browser-deps

install: $(STAMP)

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[all,dev]'
	touch $(STAMP)

demo: install
	$(BIN)/python -m mrexplore.demo

lint: install
	$(BIN)/ruff check src tests benchmarks tools
	$(BIN)/ruff format --check src tests benchmarks tools

typecheck: install
	$(BIN)/mypy src/mrexplore

test: lint typecheck browser-deps
	OMP_NUM_THREADS=1 $(BIN)/pytest -q -n auto

# Headless Chromium for the replay's browser test (tests/test_replay.py). Installs
# Debian's chromium and chromium-driver when missing; never fails the build: without
# them the browser test is skipped and says why.
browser-deps:
	@if [ -x /usr/bin/chromium ] && [ -x /usr/bin/chromedriver ]; then \
		exit 0; \
	elif ! command -v apt-get >/dev/null 2>&1; then \
		echo "browser-deps: no apt-get here; the browser test will be skipped"; \
	elif [ "$$(id -u)" != 0 ] && ! command -v sudo >/dev/null 2>&1; then \
		echo "browser-deps: not root and no sudo; the browser test will be skipped"; \
	else \
		SUDO=$$([ "$$(id -u)" = 0 ] || echo "sudo -n"); \
		echo "browser-deps: installing chromium and chromium-driver (apt-get)"; \
		export DEBIAN_FRONTEND=noninteractive; \
		$$SUDO apt-get install -y -q --no-install-recommends chromium chromium-driver \
			>/tmp/mrexplore-browser-deps.log 2>&1 \
		|| { $$SUDO apt-get update -q >>/tmp/mrexplore-browser-deps.log 2>&1 \
			&& $$SUDO apt-get install -y -q --no-install-recommends chromium chromium-driver \
			>>/tmp/mrexplore-browser-deps.log 2>&1; } \
		|| echo "browser-deps: could not install chromium (see /tmp/mrexplore-browser-deps.log);" \
			"the browser test will be skipped"; \
	fi

# The slow matrices and full reproductions (about an hour on two cores).
test-slow: install
	OMP_NUM_THREADS=1 $(BIN)/pytest -q -m slow -n auto

# Scenarios S1-S6 and the scaling table (appended to benchmarks/RESULTS.md), then every
# strategy against nearest-frontier on Intel, limited range, and in robots and map side.
bench: install
	OMP_NUM_THREADS=1 $(BIN)/python benchmarks/bench_suite.py --scaling --record
	OMP_NUM_THREADS=1 $(BIN)/python benchmarks/bench_strategies.py --limited --scaling --timeout 600

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info .pytest_cache .mypy_cache .ruff_cache
