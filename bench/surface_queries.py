"""Hausdorff distance and pointwise penetration depth through Python, the tables of
docs/BENCHMARKS.md: meshes built once, outside the timer, on `--threads` threads (1 by default).
The single queries of the default tables: median of `--repeats` calls after one warm-up call. The
`--grid` tables: each cell's queries timed as loops (`_common.sweeps`, `--repeats` rounds; one
round where a call takes over 20 ms), so that no query is timed right after itself. No other installed
library computes either exactly, so there is no second column; the tests compare both with
dense sampling and brute-force distances.

Hausdorff: symmetric, a mesh against a copy moved by (0.3, 0.1, 0.05), error bounds of 1e-2,
1e-3 and 1e-4 of the bounding radius (the hard case: the distance is nearly the same over the
whole surface). Pointwise depth (error 1e-4 of the radius): two overlapping cubes, and the
knots against copies overlapping everywhere or in part.

`--grid`: pointwise depth (error 1e-4 of the radius) at the poses of
`bench/penetration_grid.py` instead: per model and penetration f (1%, 5%, 20% of the bounding
radius R), 8 seeded queries, each a turned copy touching the model from a random direction u
(tocsin's exact continuous query from far out) pushed back by f R along -u (shallow contacts,
as in a simulation's penetrations), also on a 50,000-triangle knot (the issue's largest size);
median and 90th percentile over the queries of each query's median time. Then the symmetric Hausdorff distance of each model against 8 copies
turned by random rotations and moved by 5% of R, at three error bounds (median over the copies).

    python bench/surface_queries.py [--repeats 3] [--threads 1] [--grid [--models knot50k,...] [--dump-poses DIR]] [--out bench/out/surface_queries.md]
"""

import argparse
import os
import statistics
import time

import numpy as np

import tocsin
from _common import machine_line, models, pose, sweeps, write


def median_ms(fn, repeats):
    fn()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def moved(t):
    """A pose that only translates by `t`."""
    return pose(np.eye(3), t)


def grid(args):
    from penetration_grid import pushed_in, rotation, unit

    meshes = models(["knot2.8k", "knot11k", "knot34k", "bunny"])
    import pybullet_data

    meshes["duck"] = tocsin.Mesh.load(os.path.join(pybullet_data.getDataPath(), "duck.obj"))
    # The 50K size: a knot of 1000 x 25 rings.
    meshes["knot50k"] = tocsin.Mesh.torus_knot(1000, 25)
    if args.models:
        meshes = {k: m for k, m in meshes.items() if k in args.models.split(",")}
    lines = [
        machine_line() + f"; {args.threads} thread(s); each cell's queries timed as loops ({args.repeats} rounds, "
        "a query's time the median of its rounds, one round where a call takes over 20 ms), times in ms.",
        "",
    ]
    lines += ["| model | triangles | penetration | queries | median ms | p90 ms | depth / R, median |", "|---|---:|---:|---:|---:|---:|---:|"]
    rng = np.random.default_rng(6)
    for name, m in meshes.items():
        R = m.bounding_radius
        for f in (0.01, 0.05, 0.2):
            calls = []
            for _ in range(8):
                placed = pushed_in(m, rng, f)
                if placed is None:
                    continue
                p2 = placed[0]
                if args.dump_poses:
                    os.makedirs(args.dump_poses, exist_ok=True)
                    with open(os.path.join(args.dump_poses, f"{name}_{round(100 * f)}.txt"), "a") as out:
                        out.write(" ".join(f"{x:.17e}" for x in p2[:3, :4].ravel()) + "\n")
                calls.append(lambda p2=p2: tocsin.pointwise_penetration(m, np.eye(4), m, p2, max_error=1e-4 * R))
            if calls:
                got, answers = sweeps({"pointwise": calls}, rounds=args.repeats)
                times = [1e3 * t for t in got["pointwise"]]
                depths = [r.depth / R for r in answers["pointwise"]]
                lines.append(
                    f"| {name} | {m.num_triangles} | {f:.0%} R | {len(times)} | {statistics.median(times):.2f} | "
                    f"{np.percentile(times, 90):.2f} | {statistics.median(depths):.4f} |"
                )
                print(lines[-1], flush=True)
    # Hausdorff distance, symmetric, against turned copies: the same models, each against 8
    # copies turned by a random rotation about the origin and moved by 5% of R.
    lines += ["", "| model | triangles | Hausdorff vs turned copies: error 1e-2 R | 1e-3 R | 1e-4 R | distance / R, median |", "|---|---:|---:|---:|---:|---:|"]
    for name, m in meshes.items():
        R = m.bounding_radius
        poses = []
        for _ in range(8):
            p2 = np.eye(4)
            p2[:3, :3] = rotation(rng)
            p2[:3, 3] = 0.05 * R * unit(rng)
            poses.append(p2)
        cells, values = [], []
        for rel in (1e-2, 1e-3, 1e-4):
            calls = [
                lambda p2=p2, rel=rel: tocsin.hausdorff_distance(m, np.eye(4), m, p2, max_error=rel * R, symmetric=True)
                for p2 in poses
            ]
            got, answers = sweeps({"hausdorff": calls}, rounds=args.repeats)
            values += [r.distance / R for r in answers["hausdorff"]]
            cells.append(f"{1e3 * statistics.median(got['hausdorff']):.2f}")
        lines.append(f"| {name} | {m.num_triangles} | " + " | ".join(cells) + f" | {statistics.median(values):.4f} |")
        print(lines[-1], flush=True)
    write(args.out, "\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1, help="threads of tocsin's pool (the two directions of a symmetric query run in parallel)")
    ap.add_argument("--out", default=os.path.join("bench", "out", "surface_queries.md"))
    ap.add_argument("--grid", action="store_true", help="pointwise depth at the penetration grid's poses")
    ap.add_argument("--models", help="with --grid, only these models (comma-separated names)")
    ap.add_argument("--dump-poses", help="with --grid, append each query's pose of the copy to DIR/model_percent.txt (12 numbers a line, rows of [R | t]) for `POSES=file examples/profile_depth`")
    args = ap.parse_args()
    # Read when tocsin's pool starts, at the first mesh build below.
    os.environ["RAYON_NUM_THREADS"] = str(args.threads)
    if args.grid:
        return grid(args)
    meshes = models(["bunny", "knot2.8k", "knot34k"])
    lines = [machine_line() + f"; {args.threads} thread(s); median of {args.repeats} calls after a warm-up, times in ms.", ""]
    lines += ["| mesh | triangles | error 1e-2 R | 1e-3 R | 1e-4 R | distance |", "|---|---:|---:|---:|---:|---:|"]
    offset = moved([0.3, 0.1, 0.05])
    for name, m in meshes.items():
        cells, value = [], None
        for rel in (1e-2, 1e-3, 1e-4):
            e = rel * m.bounding_radius
            run = lambda: tocsin.hausdorff_distance(m, np.eye(4), m, offset, max_error=e, symmetric=True)
            cells.append(f"{median_ms(run, args.repeats):.1f}")
            value = run().distance
        lines.append(f"| {name} | {m.num_triangles} | " + " | ".join(cells) + f" | {value:.4f} |")
    lines += ["", "| pair | pointwise depth | time (ms) |", "|---|---:|---:|"]
    cube = tocsin.Mesh.box([0.5, 0.5, 0.5])
    pairs = [("two unit cubes overlapping by 0.2", cube, moved([0.8, 0.0, 0.0]))]
    for name in ("knot2.8k", "knot34k"):
        m = meshes[name]
        pairs += [
            (f"{name}, copy moved by (0.3, 0.1, 0) (overlapping everywhere)", m, moved([0.3, 0.1, 0.0])),
            (f"{name}, copy moved by 4.6 along x (partial overlap)", m, moved([4.6, 0.0, 0.0])),
            (f"{name}, copy moved by 4.0 along x", m, moved([4.0, 0.0, 0.0])),
        ]
    for label, m, p in pairs:
        run = lambda: tocsin.pointwise_penetration(m, np.eye(4), m, p)
        ms = median_ms(run, args.repeats)
        lines.append(f"| {label} | {run().depth:.4f} | {ms:.1f} |")
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
