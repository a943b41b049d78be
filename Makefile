# Quick start: `make demo` and `make test` work on a machine with only Python >= 3.11, pip and make.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.filmscale-installed

.PHONY: install demo test test-all notebooks benchmark clean

install: $(STAMP)

# Reinstalled when pyproject.toml changes; the install is editable, so code edits need none.
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV) || \
	  { $(PYTHON) -m pip install --user -q virtualenv && $(PYTHON) -m virtualenv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -e '.[test]'
	@touch $@

# The whole chain on examples/demo_scene.toml: MD indentation (quick preset) -> calibration of
# the film -> depth profile -> impact map -> HTML report. A second `make demo` reuses every unit.
demo: $(STAMP)
	$(BIN)/filmscale run examples/demo_scene.toml --store demo_output/runs \
	  --out demo_output/demo.h5 --report
	$(BIN)/filmscale report demo_output/demo.h5 --figure demo_output/demo.png

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest

# Each example notebook executed from top to bottom (nbmake, in the test extra), in place of
# a Jupyter server: the notebooks stay unchanged; open them in Jupyter to read the outputs.
notebooks: $(STAMP)
	$(BIN)/python -m pytest -q -p no:cacheprovider tests/workflows/test_notebook.py

test-all: $(STAMP)
	$(BIN)/python -m pytest -m ""

benchmark: $(STAMP)
	$(BIN)/python benchmarks/startup.py
	$(BIN)/python benchmarks/impact_speed_vs_error.py
	$(BIN)/python benchmarks/indentation_speed.py
	$(BIN)/python benchmarks/instrument_peer.py
	$(BIN)/python benchmarks/md_overhead.py
	$(BIN)/python benchmarks/particles_convergence.py
	$(BIN)/python benchmarks/joint_calibration.py
	$(BIN)/python benchmarks/coated_accuracy.py
	$(BIN)/python benchmarks/sneddon_bias.py
	$(BIN)/python benchmarks/md_closure.py
	$(BIN)/python benchmarks/md_speed_vs_error.py

clean:
	rm -rf demo_output .pytest_cache
