#!/bin/bash
# The checks the twenty-fifth and thirty-third sessions ran on the lent device machine (H100, 16 cores), kept so a
# later session with a device can run them again at once. Prepare here, on the development
# machine (the device has no Rust, no ray and no network):
#
#   echo /.dev/ >> .git/info/exclude; echo /.whl/ >> .git/info/exclude; mkdir -p .dev .whl
#   cargo build --release --features cuda -p tocsin --example bench_world
#   cargo test --release --features cuda -p tocsin --test world --no-run   # prints the binary
#   cargo test --release --features cuda -p tocsin --lib --no-run          # prints the binary
#   cp target/release/examples/bench_world .dev/bench_world
#   cp <world test binary> .dev/world_test; cp <lib test binary> .dev/lib_test; strip .dev/*
#   .venv/bin/maturin build --release -o .whl -m crates/tocsin-py/Cargo.toml   # abi3 wheel
#   ray for Python 3.12 without its jars and dashboard (the whole wheel is over the 64 MiB a
#   call may carry), as .whl/ray_stripped.zip, and its missing dependencies as wheels:
#   jsonschema, jsonschema-specifications, referencing, rpds-py (cp312, manylinux).
#
# Then call the device with carry [".dev", ".whl"] and `bash bench/device_checks.sh`
# (SKIP_GPU=1 or SKIP_RAY=1 to run one half; RAY_RUNS, a subset of "scaling big threads
# attribute", for
# the Ray runs; RAY_LIMIT, RAY_BIG_LIMIT, RAY_THREADS_LIMIT seconds for each). Results go to
# $OUT (the device tool's folder) and to the output.
R=$(pwd)
O=${OUT:-/tmp/out}; mkdir -p $O
{ nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv; nproc; lscpu | grep "Model name"; } 2>&1 | tee $O/machine.txt
for d in /usr/local/cuda/lib64 /usr/local/cuda/targets/x86_64-linux/lib; do [ -e $d/libnvrtc.so.13 ] && export LD_LIBRARY_PATH=$d:$LD_LIBRARY_PATH; done
echo "LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
if [ "${SKIP_GPU:-0}" != 1 ]; then
  (timeout 60 .dev/lib_test gpu --nocapture; timeout 120 .dev/world_test gpu --nocapture) 2>&1 | tee $O/gpu_test.txt
  timeout 150 .dev/bench_world gpu 2>&1 | tee $O/gpu_bench.txt
fi
if [ "${SKIP_RAY:-0}" = 1 ]; then exit 0; fi
mkdir -p /tmp/site
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target /tmp/site .whl/*.whl 2>&1 | tail -3
python3 - <<'P'
import zipfile, os
z = zipfile.ZipFile('.whl/ray_stripped.zip')
z.extractall('/tmp/site')
for i in z.infolist():
    m = (i.external_attr >> 16) & 0o777
    if m: os.chmod(os.path.join('/tmp/site', i.filename), m)
P
# The Python sources of the checkout, over the wheel's (the wheel may be older).
cp crates/tocsin-py/python/tocsin/*.py /tmp/site/tocsin/
export PYTHONPATH=/tmp/site RAY_AUTH_MODE=disabled PYTHONUNBUFFERED=1
python3 -c "import ray, tocsin, numpy; print('ray', ray.__version__, 'numpy', numpy.__version__)" 2>&1 | tail -2
RUNS=${RAY_RUNS:-scaling big threads attribute}
case " $RUNS " in *" scaling "*)
timeout ${RAY_LIMIT:-260} python3 bench/ray_throughput.py --scaling 2>&1 | grep -v WARNING | tee $O/ray.txt ;; esac
# The same with a batch four times as large, one timed call per CPU count: the per-call cost of
# Ray (its tasks' start and the results' return) spread over more work.
case " $RUNS " in *" big "*)
timeout ${RAY_BIG_LIMIT:-200} python3 bench/ray_throughput.py --scaling --queries 64000 --repeats 1 2>&1 | grep -v WARNING | tee $O/ray_big.txt ;; esac
# Where Ray's time goes: CPU seconds by process (workers, raylet, GCS, agents, driver) during
# the warm batch, beside the local batch's, and the idle share (RAY_ATTRIBUTE_ARGS, e.g.
# "--counts 8,16 --repeats 3").
case " $RUNS " in *" attribute "*)
timeout ${RAY_ATTRIBUTE_LIMIT:-300} python3 bench/ray_throughput.py --attribute ${RAY_ATTRIBUTE_ARGS:-} 2>&1 | grep -v WARNING | tee $O/ray_attribute.txt ;; esac
# Tasks as wide as 1, 4 or all of a cluster's CPUs, and a pool of single-threaded processes.
case " $RUNS " in *" threads "*)
timeout ${RAY_THREADS_LIMIT:-240} python3 bench/ray_throughput.py --threads-per-task ${RAY_THREADS_ARGS:-} 2>&1 | grep -v WARNING | tee $O/ray_threads.txt ;; esac
