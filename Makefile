# `make demo` bakes the embedded default probe (the main job) into ./demo; `make test` runs every
# test, `make test-fast` all but those marked slow (over 5 s each).
# Each creates the virtual environment .venv on first use: the demo installs bakeshop, what the
# main job needs and moderngl for its preview pictures; the tests add the test references (the
# `test` extra).
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test test-fast lint bench sysdeps clean

# Installing ends by compiling the package's bytecode (pip does it for a regular install, not for
# an editable one) and running `bakeshop warm-up`: every command once on small inputs, which
# compiles their numba kernels into their cache beside the package (bakeshop/*/__pycache__), so
# that a command's first real run is as fast as any later one.
$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
	$(BIN)/pip install -q -e '.[preview]'
	$(BIN)/python -m compileall -q bakeshop
	@echo "compiling every command's numba kernels (once: about 5 minutes of CPU, see docs/install.md)"
	$(BIN)/bakeshop warm-up
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

lint: $(BIN)/.installed-test
	$(BIN)/ruff check bakeshop tests benchmarks
	$(BIN)/mypy

bench: $(BIN)/.installed-test
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) demo
