# `make demo` bakes the embedded default probe (the main job) into ./demo; `make test` runs every
# test, `make test-fast` all but those marked slow (over 5 s each), `make sanitize` the codec
# tests on a sanitizer build of the compiled core.
# Each creates the virtual environment .venv on first use: the demo installs bakeshop, what the
# main job needs and moderngl for its preview pictures; the tests add the test references (the
# `test` extra).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test test-fast sanitize lint bench sysdeps clean

# Installing builds the compiled core (src/, C++ through CMake and nanobind, a minute or two on
# two cores) into the editable install; a change under src/ installs again, which rebuilds only
# what changed (the build folder build/<wheel tag> is kept).
NATIVE := CMakeLists.txt $(shell find src -name '*.cpp' -o -name '*.hpp')

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)

$(BIN)/.installed: $(VENV)/bin/python pyproject.toml $(NATIVE)
	$(BIN)/pip install -q -e '.[preview]'
	$(BIN)/python -m compileall -q bakeshop
	touch $@

$(BIN)/.installed-test: $(BIN)/.installed
	$(BIN)/pip install -q -e '.[test]'
	touch $@

# System libraries for the OpenGL conformance tests (EGL + Mesa's llvmpipe) and Debian's Chromium
# for the browser viewer's tests (WebGL2 on SwiftShader), installed when missing.
sysdeps:
	@dpkg -s libegl1 libgl1-mesa-dri libegl-mesa0 >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	      apt-get install -y -qq libegl1 libgl1-mesa-dri libegl-mesa0 >/dev/null; \
	  else echo "note: install libegl1 libgl1-mesa-dri libegl-mesa0 (as root) for the OpenGL tests"; fi; }
	@command -v chromium >/dev/null 2>&1 || { \
	  if [ "$$(id -u)" = 0 ]; then \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; \
	  else echo "note: install chromium (as root) for the browser viewer's tests"; fi; }

demo: $(BIN)/.installed
	$(BIN)/bakeshop bake-probe -o demo
	$(BIN)/bakeshop preview demo --scene all || echo "note: no preview pictures (bakeshop preview needs libEGL and Mesa: make sysdeps)"

test: $(BIN)/.installed-test sysdeps
	$(BIN)/python -m pytest -n 2 -q

test-fast: $(BIN)/.installed-test sysdeps
	$(BIN)/python -m pytest -n 2 -q -m "not slow"

# The compiled core again with AddressSanitizer and UndefinedBehaviorSanitizer, under the codec
# fuzz tests and the bad-file corpus (CI runs it after the tests; a report fails it).
sanitize: $(BIN)/.installed-test
	PYTHON=$(abspath $(BIN)/python) .ci/sanitize

lint: $(BIN)/.installed-test
	$(BIN)/ruff check bakeshop tests benchmarks
	$(BIN)/mypy

bench: $(BIN)/.installed-test
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) demo build
