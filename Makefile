# The README's commands. `make demo` runs the main job on built-in models; `make test` installs
# what it needs (a local virtualenv with maturin, numpy, pytest), builds the extension and runs
# every check. `make bench` runs the benchmarks (not part of `make test`).

PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
CARGO ?= cargo

.PHONY: demo test venv develop lint rust-test py-test bench bench-python bench-parry clean

demo:
	$(CARGO) run --release -q -p tocsin --example demo

$(VPY):
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q "maturin>=1.5,<2" "numpy>=1.26" pytest

venv: $(VPY)

develop: venv
	$(VENV)/bin/maturin develop --release -q

lint:
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets --release -- -D warnings

rust-test:
	$(CARGO) test --workspace --release

py-test: develop
	$(VPY) -m pytest -q crates/tocsin-py/tests

test: lint rust-test py-test

bench: bench-python
	$(CARGO) bench -p tocsin
	$(MAKE) bench-parry

# Side-by-side with python-fcl (distance, collide, continuous collision); installs python-fcl
# and pybullet (for its meshes) in the venv.
bench-python: develop
	$(VPY) -m pip install -q python-fcl pybullet
	$(VPY) bench/compare_fcl.py
	$(VPY) bench/compare_fcl_ccd.py

# parry3d-f64's shape casts next to tocsin (its own cargo workspace, not built by `make test`).
bench-parry:
	cd bench/parry && $(CARGO) run --release -q -- 5

clean:
	$(CARGO) clean
	rm -rf $(VENV)
