"""Translational penetration depth on non-convex models at several penetrations, with the ratio
to the best directional depth over sampled directions (dense sampling plus bisection with the
exact collide), as the penetration-depth issue asks.

Per model and penetration fraction f of the bounding radius R: 8 seeded queries. For each, a
random direction u and rotation; the copy is placed touching the model from outside along u
(tocsin's exact continuous query from far out), then pushed back by f R along -u, so the bodies
penetrate by about f R along u. tocsin `penetration_depth` is timed; the reference is the
smallest directional depth over 64 random directions plus u itself (the smallest s >= 0 with the
copy moved by s v not penetrating: 64 samples, then 30 bisection steps, exact collide and the
winding-number inside), an upper bound on the true depth.

    python bench/penetration_grid.py [--queries 8] [--directions N] [--starts K] [--out FILE]
"""

import argparse
import os
import statistics
import time

import numpy as np

import tocsin
from _common import machine_line


def unit(rng):
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


def rotation(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def penetrates(m, p2):
    if tocsin.collide(m, np.eye(4), m, p2):
        return True
    c2 = p2[:3, :3] @ m.vertices[m.triangles[0, 0]] + p2[:3, 3]
    c1 = m.vertices[m.triangles[0, 0]]
    inv = np.linalg.inv(p2)
    return bool(tocsin.contains(m, np.eye(4), c2[None])[0] or tocsin.contains(m, p2, c1[None])[0])


def pushed_in(m, rng, f):
    """A turned copy of `m` touching it from a random direction `u` (tocsin's exact continuous
    query from `far` out), pushed back by `f` of the bounding radius along `-u`: `(pose, u, far)`,
    or None when there is no contact or the copy does not penetrate."""
    R = m.bounding_radius
    u = unit(rng)
    p2 = np.eye(4)
    p2[:3, :3] = rotation(rng)
    far = 4 * R + 1.0
    start, end = p2.copy(), p2.copy()
    start[:3, 3] = far * u
    c = tocsin.time_of_contact(m, tocsin.Motion.stationary(np.eye(4)), m, tocsin.Motion.translation(start, end))
    if c is None:
        return None
    p2[:3, 3] = far * u * (1 - c.time) - f * R * u
    if not penetrates(m, p2):
        return None
    return p2, u, far


def directional(m, p2, v, far):
    def at(s):
        q = p2.copy()
        q[:3, 3] += s * v
        return penetrates(m, q)

    prev = 0.0
    for k in range(1, 65):
        s = far * (k / 64) ** 2
        if not at(s):
            lo, hi = prev, s
            for _ in range(30):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if at(mid) else (lo, mid)
            return hi
        prev = s
    return far


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--queries", type=int, default=8)
    parser.add_argument("--out")
    parser.add_argument("--directions", type=int, help="seed directions on the sphere (default: the library's)")
    parser.add_argument("--starts", type=int, help="seeds refined at deep penetrations (default: the library's)")
    args = parser.parse_args()
    import pybullet_data

    root = pybullet_data.getDataPath()
    models = {
        "knot2.8k": tocsin.Mesh.torus_knot(175, 8),
        "knot11k": tocsin.Mesh.torus_knot(344, 16),
        "knot34k": tocsin.Mesh.torus_knot(680, 25),
        "bunny": tocsin.Mesh.load(os.path.join(root, "bunny.obj")),
        "duck": tocsin.Mesh.load(os.path.join(root, "duck.obj")),
        "panda_link1": tocsin.Mesh.load(os.path.join(root, "franka_panda", "meshes", "collision", "link1.obj")),
    }
    rng = np.random.default_rng(6)
    lines = [
        machine_line(),
        "",
        "| model | triangles | penetration | median ms | p90 ms | median iterations | depth / best sampled directional depth: median, worst | within 1% |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, m in models.items():
        R = m.bounding_radius
        for f in (0.01, 0.05, 0.2):
            times, iters, ratios = [], [], []
            for _ in range(args.queries):
                placed = pushed_in(m, rng, f)
                if placed is None:
                    continue
                p2, u, far = placed
                t = time.perf_counter()
                r = tocsin.penetration_depth(m, np.eye(4), m, p2, directions=args.directions, starts=args.starts)
                times.append(time.perf_counter() - t)
                iters.append(r.iterations)
                best = min(directional(m, p2, v, far) for v in [u] + [unit(rng) for _ in range(64)])
                ratios.append(r.depth / best)
            if not times:
                continue
            ratios = np.array(ratios)
            lines.append(
                f"| {name} | {m.num_triangles} | {f:.0%} R | {statistics.median(times) * 1e3:.2f} | "
                f"{np.percentile(times, 90) * 1e3:.2f} | {statistics.median(iters):.0f} | "
                f"{np.median(ratios):.3f}, {ratios.max():.3f} | {(ratios <= 1.01).sum()}/{len(ratios)} |"
            )
            print(lines[-1], flush=True)
    text = "\n".join(lines)
    print(text)
    if args.out:
        open(args.out, "w").write(text + "\n")


if __name__ == "__main__":
    main()
