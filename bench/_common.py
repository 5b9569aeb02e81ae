"""Helpers shared by the comparison runners: poses, models, the machine line, timing."""

import os
import platform
import statistics
import sys
import time

import numpy as np

import tocsin


def rotation(axis, angle):
    """Rotation matrix of `angle` radians about `axis` (Rodrigues)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def pose(rot, t):
    """4x4 pose from a rotation matrix and a translation."""
    p = np.eye(4)
    p[:3, :3] = rot
    p[:3, 3] = t
    return p


def ellipsoid_hull(rng, n, semi=(1.0, 0.7, 0.5)):
    """The convex hull (scipy's) of `n` random points on the ellipsoid of semi-axes `semi`, every
    point a corner: the points and the tocsin mesh."""
    from scipy.spatial import ConvexHull

    p = rng.normal(size=(n, 3))
    p = p / np.linalg.norm(p, axis=1)[:, None] * np.asarray(semi)
    return p, tocsin.Mesh(p, ConvexHull(p).simplices.astype(np.int64))


def as_soup(mesh):
    """The same surface with a degenerate triangle added at a corner: to the library no longer
    a convex polytope, so its queries take the general path (the hierarchy's)."""
    return tocsin.Mesh(mesh.vertices, np.vstack([mesh.triangles, [[0, 0, 0]]]))


def models(names=None):
    """The generated knots, convex hulls of 100 and 1,000 points on an ellipsoid (seeded) and,
    when pybullet_data is installed, its bunny and Panda links."""
    out = {
        "knot2.8k": lambda: tocsin.Mesh.torus_knot(175, 8),
        "knot11k": lambda: tocsin.Mesh.torus_knot(344, 16),
        "knot34k": lambda: tocsin.Mesh.torus_knot(680, 25),
        "hull100": lambda: ellipsoid_hull(np.random.default_rng(100), 100)[1],
        "hull1k": lambda: ellipsoid_hull(np.random.default_rng(1000), 1000)[1],
    }
    try:
        import pybullet_data

        root = pybullet_data.getDataPath()
        out["bunny"] = lambda: tocsin.Mesh.load(os.path.join(root, "bunny.obj"))
        out["panda_link0"] = lambda: tocsin.Mesh.load(os.path.join(root, "franka_panda", "meshes", "collision", "link0.obj"))
        out["panda_link1"] = lambda: tocsin.Mesh.load(os.path.join(root, "franka_panda", "meshes", "visual", "link1.obj"))
    except ImportError:
        print("pybullet_data not installed: real meshes skipped", file=sys.stderr)
    return {k: f() for k, f in out.items() if names is None or k in names}


def fcl_model(mesh):
    """The mesh as a python-fcl BVHModel (OBBRSS, FCL's default for meshes)."""
    import fcl

    m = fcl.BVHModel()
    m.beginModel(mesh.num_vertices, mesh.num_triangles)
    m.addSubModel(mesh.vertices, mesh.triangles)
    m.endModel()
    return m


def machine_line():
    """CPU, cores and versions, for the tables."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"Machine: {cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"


def write(path, text):
    """Prints `text` and writes it to `path`."""
    print(text)
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write(text + "\n")


def sweeps(calls, rounds=3, turn=0):
    """Each method's calls timed as a user's loop makes them: one call per query, query after
    query (a sweep), the methods' sweeps taking turns, `rounds` times, the order of the methods
    turning by one each round; a query's time is the median of its rounds (one round for a
    method whose first sweep had a call over 20 ms). Timing each query's methods one after
    the other instead (the thirty-fifth session's runs and before) gave the second of two
    methods that share the advancement (the contact pair after the default) the first one's
    warm caches and branch history: 5 to 18% less time than when it ran first
    (docs/BENCHMARKS.md, thirty-sixth session). `calls` maps each method to its calls, one per
    query; `turn` rotates the first round's order (a caller timing several sets of queries, such
    as scenes, passes its index so that no method always runs first). Returns each method's
    per-query times and its first round's answers."""
    labels = list(calls)
    samples = {label: [[] for _ in calls[label]] for label in labels}
    answers = {}
    slow = set()
    for r in range(rounds):
        k = (r + turn) % len(labels)
        for label in labels[k:] + labels[:k]:
            if r > 0 and label in slow:
                continue
            got = []
            for qi, fn in enumerate(calls[label]):
                t0 = time.perf_counter()
                got.append(fn())
                samples[label][qi].append(time.perf_counter() - t0)
            if r == 0:
                answers[label] = got
                if max(ts[0] for ts in samples[label]) > 0.02:
                    slow.add(label)
    return {label: [statistics.median(ts) for ts in samples[label]] for label in labels}, answers
