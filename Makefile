# The README's commands. `make demo` runs the main job on built-in models; `make test` installs
# what it needs (a local virtualenv with maturin, numpy, pytest), builds the extension and runs
# every check. `make bench` runs the benchmarks (not part of `make test`).

PYTHON ?= python3
VENV := .venv
VPY := $(VENV)/bin/python
VENV_NP1 := .venv-numpy1
CARGO ?= cargo

.PHONY: demo test soak venv develop wheel lint rust-test py-test bench bench-python bench-robots bench-robot-data bench-parry clean

demo:
	$(CARGO) run --release -q -p tocsin --example demo
	$(CARGO) run --release -q -p tocsin-cli -- render-contact builtin:knot34k builtin:knot34k \
		--motion1 "screw:-14,1,0.5:14,-0.5,0,0,0.3,1.2" --out target/demo-contact.png > /dev/null
	@echo "picture of the first contact (screw motion, knot34k): target/demo-contact.png"
	$(CARGO) run --release -q -p tocsin-cli -- rain --bodies 16 --steps 90 --frames target/rain
	@echo "16 bodies thrown through 1 mm plates (tunnelled_bodies and intersecting_pairs above, checked every step): target/rain/strip.png"

# Build tools live in .venv; the wheel is tested in .venv (numpy 2.x), and a fresh .venv-numpy1
# (numpy 1.26) installs the package with `pip install .` from the clone, as a user would. Both
# get what the tests use (matplotlib, trimesh with pycollada as the second COLLADA reader,
# pybullet for its pybullet_data meshes and as the
# second forward-kinematics implementation, ompl for the planning example, scipy's ConvexHull as
# the penetration-depth oracle, ray for tocsin.distributed on a local cluster): no test
# skips itself.
$(VPY):
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --upgrade pip
	$(VPY) -m pip install -q "maturin>=1.5,<2" "numpy>=2" pytest mypy matplotlib trimesh pycollada pybullet ompl scipy ray tqdm

venv: $(VPY)

# For development: an editable install into .venv.
develop: venv
	$(VENV)/bin/maturin develop --release -q

wheel: venv
	rm -rf target/wheels
	$(VENV)/bin/maturin build --release -q -o target/wheels

# The GPU broad phase (feature tocsin/cuda) is built, linted and tested too: CUDA is loaded at
# run time, so it builds without CUDA. NVRTC (pip's nvidia-cuda-nvrtc, in .venv) lets the tests
# compile the kernels without a GPU; the test that runs them says it skipped where no GPU is.
lint:
	$(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --all-targets --release --features tocsin/cuda -- -D warnings

rust-test: venv
	$(VPY) -m pip install -q "nvidia-cuda-nvrtc>=13,<14"
	LD_LIBRARY_PATH="$$(find $(CURDIR)/$(VENV) -name 'libnvrtc.so.13' -printf '%h' -quit):$$LD_LIBRARY_PATH" \
		$(CARGO) test --workspace --release --features tocsin/cuda

py-test: wheel
	$(VPY) -m pip install -q --force-reinstall --no-deps target/wheels/*.whl
	$(VPY) -m pytest -q crates/tocsin-py/tests
	$(VPY) -m mypy.stubtest tocsin._core --allowlist crates/tocsin-py/stubtest-allowlist.txt
	rm -rf $(VENV_NP1)
	$(PYTHON) -m venv $(VENV_NP1)
	$(VENV_NP1)/bin/python -m pip install -q "numpy>=1.26,<2" pytest matplotlib trimesh pycollada pybullet ompl scipy ray tqdm
	$(VENV_NP1)/bin/python -m pip install -q .
	$(VENV_NP1)/bin/python -c "import numpy, tocsin; assert numpy.__version__.startswith('1.'), numpy.__version__"
	$(VENV_NP1)/bin/python -m pytest -q crates/tocsin-py/tests

test: lint rust-test py-test

# The core crate's tests again on fresh seeds: run k (1..SEEDS) shifts every seed a randomized
# test draws through `tests/common`'s `rng` (`TOCSIN_SOAK=k`), a new sample of the same
# generators against the same oracles. A sample that happens not to mix its outcomes is
# reported, not failed; any wrong answer fails. Not part of `make test`: each run takes the
# integration tests' time again (about three minutes on 2 cores).
SEEDS ?= 4
soak:
	$(CARGO) test --release -p tocsin --tests --no-run -q
	@failed=""; for k in $$(seq 1 $(SEEDS)); do \
		echo "soak $$k of $(SEEDS)"; \
		TOCSIN_SOAK=$$k $(CARGO) test --release -q -p tocsin --tests --no-fail-fast -- --nocapture > target/soak-$$k.log 2>&1 \
			|| { failed="$$failed $$k"; grep -E "panicked|^test .* FAILED" target/soak-$$k.log; }; \
		grep -h "does not mix" target/soak-$$k.log || true; \
	done; \
	if [ -n "$$failed" ]; then echo "soak runs failed:$$failed (logs: target/soak-K.log)"; exit 1; fi; \
	echo "every soak run passed"

bench: bench-python
	$(CARGO) bench -p tocsin
	$(VPY) bench/surface_queries.py
	$(MAKE) bench-parry

# Side-by-side with python-fcl (distance, collide, continuous collision, tied geometry, the
# pathological continuous-collision cases); installs python-fcl and pybullet (for its meshes)
# in the venv.
bench-python: develop
	$(VPY) -m pip install -q python-fcl pybullet
	$(VPY) bench/compare_fcl.py
	$(VPY) bench/compare_fcl_ccd.py
	$(VPY) bench/compare_fcl_ccd_tolerance.py
	$(VPY) bench/compare_fcl_ties.py
	$(VPY) bench/compare_fcl_pathological.py
	$(VPY) bench/ompl_rigid.py

# MotionBenchMaker's Panda beside Pinocchio + coal (OMPL's 1% sampler) and HPP's exact path
# validation (hpp-python); downloads the vamp-planner source distribution from the package
# index once, into ~/.cache/tocsin-bench. Not part of `make bench`.
bench-robots: develop
	$(VPY) -m pip install -q pin coal hpp-python pyyaml
	$(VPY) bench/robot_mbm.py --robots panda

# example-robot-data's 69 URDFs and 286 COLLADA files beside Pinocchio + coal (and trimesh for
# the COLLADA files); downloads the example-robot-data wheel once, into ~/.cache/tocsin-bench.
# Not part of `make bench`.
bench-robot-data: develop
	$(VPY) -m pip install -q pin coal trimesh pycollada scipy
	$(VPY) bench/example_robot_data.py

# parry3d-f64's shape casts next to tocsin (its own cargo workspace, not built by `make test`).
bench-parry:
	cd bench/parry && $(CARGO) run --release -q -- 5

clean:
	$(CARGO) clean
	rm -rf $(VENV) $(VENV_NP1)
