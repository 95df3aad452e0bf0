# `make demo` bakes the embedded default probe (the main job) into ./demo; `make test` runs every test.
# Each creates its own virtual environment in .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test lint bench sysdeps clean

$(BIN)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install -q --upgrade pip
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

test: $(BIN)/.installed sysdeps
	$(BIN)/python -m pytest -n 2 -q

lint: $(BIN)/.installed
	$(BIN)/ruff check bakeshop tests benchmarks
	$(BIN)/mypy

bench: $(BIN)/.installed
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

clean:
	rm -rf $(VENV) demo
