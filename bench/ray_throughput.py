"""tocsin.distributed beside the local batch: throughput, per-task overhead, chunk size.

1. Continuous collision on knot34k (2,000 screw motions of a knot flying past another):
   the local `time_of_contact_batch` on 1 and 2 threads, and `tocsin.distributed` on a local
   Ray cluster of 1 and 2 CPUs (one worker thread per CPU) at several chunk sizes. Each
   configuration runs 3 times, interleaved; the median is reported. The first distributed call
   of a cluster is timed apart (cold: workers start, unpickle and rebuild the meshes).
2. Per-task overhead: 2,000 collide queries between two 12-triangle boxes (microseconds of
   work each) in chunks of 1, 10, 100 rows.
3. The cost a task would pay without the per-process cache: pickling and rebuilding knot34k.

`--scaling` instead (a machine with many cores): `--queries N` (16,000) knot34k screw motions
through `tocsin.distributed` on one-node clusters of 1, 2, 4, 8, ... CPUs up to the machine's
count (default chunk size; the first call of each cluster, on at most 16,000 rows, timed apart,
then the median of `--repeats R` (3)), beside the local batch on as many threads; the speedup is
against Ray on 1 CPU.

`--threads-per-task` instead: the same batch with tasks of 1, 4 and all of a cluster's CPUs
(`threads_per_task`; `--widths 1,2` to choose), `--per 8` tasks per slot (a slot: a task's
width of the cluster's CPUs), `--counts 1,16` clusters, beside a multiprocessing pool of
single-threaded processes.

`--attribute` instead: where Ray's time goes at the machine's CPU count (`--counts` to choose):
the CPU seconds each process spent during the warm batch (from /proc: Ray's workers, its raylet,
GCS and other daemons, the driver), beside the local batch's CPU seconds on as many threads,
and the idle share (CPUs times wall time less every process's CPU time). Median of `--repeats`.

Run: `python bench/ray_throughput.py [--scaling]` (needs ray: `pip install "tocsin[ray]"`).
"""

import os
import pickle
import platform
import subprocess
import sys
import time

import numpy as np

import tocsin
from _common import pose, rotation


def turn(axis, angle, t):
    return pose(rotation(axis, angle), t)


def motions(n, seed):
    rng = np.random.default_rng(seed)
    starts = np.stack([turn(rng.normal(size=3), rng.uniform(0, 3), [-14, rng.uniform(-3, 3), rng.uniform(-3, 3)]) for _ in range(n)])
    ends = np.stack([turn(rng.normal(size=3), rng.uniform(0, 3), [14, rng.uniform(-3, 3), rng.uniform(-3, 3)]) for _ in range(n)])
    return starts, ends


def local(threads, fn, queries=2000):
    """The local batch's wall time in a child process with RAYON_NUM_THREADS=threads (the pool is
    per process); with fn "cpu", (wall time, the batch's CPU seconds)."""
    code = (
        "import time, pickle, sys; sys.path.insert(0, %r); import ray_throughput as b; import tocsin\n"
        f"knot = tocsin.Mesh.torus_knot(344, 50); s, e = b.motions({queries}, 1)\n"
        "tocsin.time_of_contact_batch(knot, s[:20], e[:20], knot, kind='screw')\n"
        "c = time.process_time(); t = time.perf_counter(); r = tocsin.time_of_contact_batch(knot, s, e, knot, kind='screw')\n"
        "dt, dc = time.perf_counter() - t, time.process_time() - c\n"
        "print(dt, dc)" % os.path.dirname(os.path.abspath(__file__))
    )
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    wall, cpu = (float(x) for x in out.stdout.split())
    return (wall, cpu) if fn == "cpu" else wall


def main():
    import ray
    from tocsin import distributed

    knot = tocsin.Mesh.torus_knot(344, 50)
    starts, ends = motions(2000, 1)
    reference = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind="screw")
    contacts = int(np.isfinite(reference.time).sum())
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs; "
          f"2,000 knot34k screw motions, {contacts} contacts")

    rows = []
    for cpus in (1, 2):
        ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
        t = time.perf_counter()
        cold = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw", chunk_size=250)
        rows.append((f"Ray, {cpus} CPU, chunk 250, first call (cold workers)", cpus, time.perf_counter() - t))
        assert np.array_equal(cold.time, reference.time, equal_nan=True)
        timings = {c: [] for c in (16, 64, 250, 1000, None)}
        for _ in range(3):
            for c in timings:
                t = time.perf_counter()
                r = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw", chunk_size=c)
                timings[c].append(time.perf_counter() - t)
                assert np.array_equal(r.time, reference.time, equal_nan=True)
        for c, ts in timings.items():
            label = "default" if c is None else str(c)
            rows.append((f"Ray, {cpus} CPU, chunk {label}", cpus, float(np.median(ts))))
        if cpus == 2:
            box = tocsin.Mesh.box([0.5, 0.5, 0.5])
            poses = np.stack([turn([0, 0, 1], 0.0, [x, 0, 0]) for x in np.linspace(0.5, 2.5, 2000)])
            for c in (1, 10, 100):
                ts = []
                for _ in range(3):
                    t = time.perf_counter()
                    distributed.collide_batch(box, poses, box, np.eye(4), chunk_size=c)
                    ts.append(time.perf_counter() - t)
                overhead = float(np.median(ts)) / (2000 / c)
                rows.append((f"overhead: collide on boxes, chunk {c} ({2000 // c} tasks): per task", 2, overhead))
        ray.shutdown()
    for threads in (1, 2):
        ts = [local(threads, None) for _ in range(3)]
        rows.append((f"local time_of_contact_batch, {threads} thread(s)", threads, float(np.median(ts))))

    t = time.perf_counter()
    for _ in range(5):
        pickle.loads(pickle.dumps(knot))
    rebuild = (time.perf_counter() - t) / 5

    print("| configuration | CPUs | seconds | queries per second |")
    print("|---|---:|---:|---:|")
    for name, cpus, s in rows:
        if name.startswith("overhead"):
            print(f"| {name} | {cpus} | {s * 1e3:.2f} ms | - |")
        else:
            print(f"| {name} | {cpus} | {s:.3f} | {2000 / s:,.0f} |")
    print(f"pickle + unpickle (hierarchy rebuilt) of knot34k: {rebuild * 1e3:.1f} ms, {len(pickle.dumps(knot)) / 1e6:.2f} MB")


def option(name, default):
    """The value after `name` in the command line, as the type of `default`."""
    if name in sys.argv:
        return type(default)(sys.argv[sys.argv.index(name) + 1])
    return default


def workload():
    """The scaling runs' batch from the command line: (queries, repeats, knot, starts, ends,
    the local batch's answers, the machine's CPU count)."""
    queries = option("--queries", 16000)
    repeats = option("--repeats", 3)
    knot = tocsin.Mesh.torus_knot(344, 50)
    starts, ends = motions(queries, 1)
    reference = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind="screw")
    return queries, repeats, knot, starts, ends, reference, os.cpu_count() or 1


def scaling():
    import ray
    from tocsin import distributed

    queries, repeats, knot, starts, ends, reference, cores = workload()
    counts = [c for c in (1, 2, 4, 8, 16, 32, 64) if c <= cores]
    print(f"machine: {platform.processor() or platform.machine()}, {cores} CPUs; "
          f"{queries:,} knot34k screw motions, {int(np.isfinite(reference.time).sum())} contacts; "
          f"median of {repeats}")
    print("| CPUs | Ray first call (s) | Ray (s) | Ray queries/s | speedup over Ray on 1 CPU | local batch, as many threads (s) | local speedup | Ray / local |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    base = None
    local_base = None
    for cpus in counts:
        ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
        t = time.perf_counter()
        # The first call of a cluster starts its workers: timed apart, on a slice when the
        # batch is large (the workers keep their meshes for the calls that follow).
        cold_rows = min(queries, 16000)
        cold = distributed.time_of_contact_batch(knot, starts[:cold_rows], ends[:cold_rows], knot, kind="screw")
        first = time.perf_counter() - t
        assert np.array_equal(cold.time, reference.time[:cold_rows], equal_nan=True)
        ts = []
        for _ in range(repeats):
            t = time.perf_counter()
            r = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw")
            ts.append(time.perf_counter() - t)
            assert np.array_equal(r.time, reference.time, equal_nan=True)
        if cpus == counts[-1]:
            # Four and sixteen chunks per CPU beside the default eight.
            for per in (4, 16):
                other = []
                for _ in range(repeats):
                    t = time.perf_counter()
                    distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw",
                                                      chunk_size=-(-queries // (per * cpus)))
                    other.append(time.perf_counter() - t)
                print(f"{cpus} CPUs, {per} chunks per CPU: {float(np.median(other)):.3f} s", flush=True)
        ray.shutdown()
        warm = float(np.median(ts))
        base = base or warm
        here = local(cpus, None, queries)
        local_base = local_base or here
        print(f"| {cpus} | {first:.2f} | {warm:.3f} | {queries / warm:,.0f} | {base / warm:.1f}x | {here:.3f} | "
              f"{local_base / here:.1f}x | {warm / here:.2f} |", flush=True)


def _pool_init():
    global _KNOT
    _KNOT = tocsin.Mesh.torus_knot(344, 50)


def _pool_chunk(args):
    s, e = args
    return tocsin.time_of_contact_batch(_KNOT, s, e, _KNOT, kind="screw").time


def threads_per_task():
    """`--threads-per-task`: at each CPU count, tasks of 1, 4 and all the cluster's CPUs (each
    task's rayon pool as wide), beside the local batch and a multiprocessing pool of
    single-threaded processes (each with its own copy of the meshes, as Ray's workers have)."""
    import multiprocessing

    import ray
    from tocsin import distributed

    queries, repeats, knot, starts, ends, reference, cores = workload()
    counts = [int(c) for c in option("--counts", "1,2,4,8,16,32,64").split(",") if int(c) <= cores]
    chosen = option("--widths", "")
    pers = [int(p) for p in option("--per", "8").split(",")]
    print(f"machine: {platform.processor() or platform.machine()}, {cores} CPUs; "
          f"{queries:,} knot34k screw motions; median of {repeats}")
    local_times = {c: local(c, None, queries) for c in (1, cores)}
    print(f"local batch: 1 thread {local_times[1]:.3f} s, {cores} threads {local_times[cores]:.3f} s "
          f"({local_times[1] / local_times[cores]:.1f}x)", flush=True)
    # The same work in a pool of single-threaded processes, eight chunks per process.
    saved = os.environ.get("RAYON_NUM_THREADS")
    os.environ["RAYON_NUM_THREADS"] = "1"
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(cores, initializer=_pool_init) as pool:
        step = -(-queries // (8 * cores))
        chunks = [(starts[a:a + step], ends[a:a + step]) for a in range(0, queries, step)]
        pool.map(_pool_chunk, chunks[:cores])
        ts = []
        for _ in range(repeats):
            t = time.perf_counter()
            got = np.concatenate(pool.map(_pool_chunk, chunks))
            ts.append(time.perf_counter() - t)
            assert np.array_equal(got, reference.time, equal_nan=True)
    if saved is None:
        del os.environ["RAYON_NUM_THREADS"]
    else:
        os.environ["RAYON_NUM_THREADS"] = saved
    pool_time = float(np.median(ts))
    print(f"multiprocessing pool, {cores} single-threaded processes: {pool_time:.3f} s "
          f"({local_times[1] / pool_time:.1f}x the local batch on 1 thread)", flush=True)
    print("| CPUs | threads per task | tasks per slot | Ray first call (s) | Ray (s) | speedup over Ray on 1 CPU | Ray / local batch on as many threads |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    base = None
    for cpus in counts:
        ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
        if chosen:
            widths = [int(w) for w in chosen.split(",") if int(w) <= cpus]
        else:
            widths = sorted({w for w in (1, 2, 4, 8, cpus) if w <= cpus and (w in (1, 4, cpus) or cpus == cores)})
        for w in widths:
            t = time.perf_counter()
            cold = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw", threads_per_task=w)
            first = time.perf_counter() - t
            assert np.array_equal(cold.time, reference.time, equal_nan=True)
            ts = {p: [] for p in pers}
            for _ in range(repeats):
                for p in pers:
                    chunk = -(-queries // (p * max(1, cpus // w)))
                    t = time.perf_counter()
                    r = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw",
                                                          threads_per_task=w, chunk_size=chunk)
                    ts[p].append(time.perf_counter() - t)
                    assert np.array_equal(r.time, reference.time, equal_nan=True)
            for p in pers:
                warm = float(np.median(ts[p]))
                base = base or warm
                ratio = f"{warm / local_times[cpus]:.2f}" if cpus in local_times else "-"
                print(f"| {cpus} | {w} | {p} | {first:.2f} | {warm:.3f} | {base / warm:.1f}x | {ratio} |", flush=True)
        ray.shutdown()


def _cpu_by_process():
    """CPU seconds (user + system) so far of every process on the machine, by pid, with its
    name and command line (Linux /proc; processes that end while read are skipped)."""
    tick = os.sysconf("SC_CLK_TCK")
    out = {}
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat") as f:
                stat = f.read()
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        name = stat[stat.index("(") + 1 : stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2 :].split()
        out[int(pid)] = (name, cmd, (int(fields[11]) + int(fields[12])) / tick)
    return out


def _role(pid, name, cmd):
    """Which part of a Ray run a process is: the driver, a worker, a daemon or other."""
    if pid == os.getpid():
        return "driver"
    # By the executable's name first: the raylet's command line holds the workers' command.
    if name == "raylet":
        return "raylet"
    if name == "gcs_server":
        return "GCS server"
    if name.startswith(("ray::DashboardA", "ray::RuntimeEnv")):
        return "Ray agents (dashboard, runtime env)"
    if name.startswith("ray::") or "default_worker.py" in cmd:
        return "Ray workers"
    if "site-packages/ray/" in cmd:
        return "other Ray processes (monitor, log monitor, dashboard)"
    return "other"


def attribute():
    import ray
    from tocsin import distributed

    queries, repeats, knot, starts, ends, reference, cores = workload()
    counts = [int(c) for c in option("--counts", str(cores)).split(",")]
    tick = 1 / os.sysconf("SC_CLK_TCK")
    print(f"machine: {platform.processor() or platform.machine()}, {cores} CPUs; {queries:,} knot34k "
          f"screw motions; median of {repeats} (CPU seconds from /proc, resolution {tick:.2f} s)")
    for cpus in counts:
        # The local batch in a child process: its wall time and CPU seconds.
        local_runs = [local(cpus, "cpu", queries) for _ in range(repeats)]
        ray.init(num_cpus=cpus, include_dashboard=False, log_to_driver=False)
        distributed.time_of_contact_batch(knot, starts[:2000], ends[:2000], knot, kind="screw")
        runs = []
        for _ in range(repeats):
            before = _cpu_by_process()
            t = time.perf_counter()
            r = distributed.time_of_contact_batch(knot, starts, ends, knot, kind="screw")
            wall = time.perf_counter() - t
            after = _cpu_by_process()
            assert np.array_equal(r.time, reference.time, equal_nan=True)
            roles = {}
            for pid, (name, cmd, cpu) in after.items():
                spent = cpu - before.get(pid, (name, cmd, 0.0))[2]
                role = _role(pid, name, cmd)
                roles[role] = roles.get(role, 0.0) + spent
            runs.append((wall, roles))
        ray.shutdown()
        local_wall = float(np.median([w for w, _ in local_runs]))
        local_cpu = float(np.median([c for _, c in local_runs]))
        wall = float(np.median([w for w, _ in runs]))
        names = sorted({k for _, roles in runs for k in roles})
        print(f"\n{cpus} CPUs: local batch {local_wall:.3f} s wall, {local_cpu:.2f} CPU s "
              f"({local_cpu / (cpus * local_wall):.0%} of {cpus} CPUs); Ray {wall:.3f} s wall")
        print("| process | CPU seconds during Ray's batch (median) | share of CPUs x wall |")
        print("|---|---:|---:|")
        total = 0.0
        for k in names:
            v = float(np.median([roles.get(k, 0.0) for _, roles in runs]))
            total += v
            print(f"| {k} | {v:.2f} | {v / (cpus * wall):.1%} |")
        print(f"| idle (CPUs x wall less all the above) | {max(0.0, cpus * wall - total):.2f} | "
              f"{max(0.0, 1 - total / (cpus * wall)):.1%} |", flush=True)


if __name__ == "__main__":
    if "--scaling" in sys.argv:
        scaling()
    elif "--threads-per-task" in sys.argv:
        threads_per_task()
    elif "--attribute" in sys.argv:
        attribute()
    else:
        main()
