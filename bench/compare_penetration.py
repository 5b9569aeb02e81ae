"""Penetration depth of overlapping boxes: tocsin beside python-fcl, against the exact value.

For two convex polytopes the exact translational penetration depth is the smallest overlap of
their projections over the candidate separating axes (face normals and edge cross products; 15
for two boxes). Random box pairs (seeded) that overlap; per pair:

- tocsin `penetration_depth` (meshes of 12 triangles each): its exact path for convex
  polytopes, and its local search (`exact_convex=False`), and whether the translation each
  returns separates them (exact `collide` false, distance within the tolerance);
- coal's GJK/EPA on random convex polytopes (a second table), both against scipy's hull, and on
  hulls of 20 to 3,000 points (a third table: how the exact path scales), and the distance
  between separated hulls beside coal's GJK (a fourth);
- python-fcl `collide` on the same meshes (BVHModel, OBBRSS) with contacts enabled: the largest
  `penetration_depth` over its contacts (what FCL reports for meshes: a triangle pair's depth),
  and, as FCL would be used for a box primitive pair, `fcl.Box` shapes (GJK/EPA, exact).

Objects built once, outside the timers. Each method is timed as a user's loop calls it
(`_common.sweeps`): one call per pair, pair after pair, the methods' sweeps taking turns, three
rounds with the order turning; a pair's time is the median of its rounds, and the table gives the
median over the pairs in microseconds. (Until the thirty-eighth session the methods ran one after
the other on each pair, each one cold after the others.)

    python bench/compare_penetration.py [--pairs 200] [--out FILE]
"""

import argparse
import statistics
import time

import fcl
import numpy as np

import tocsin
from _common import ellipsoid_hull, fcl_model, machine_line, sweeps


def sat_depth(h1, p1, h2, p2):
    a, b = p1[:3, :3].T, p2[:3, :3].T
    axes = list(a) + list(b)
    for x in a:
        for y in b:
            c = np.cross(x, y)
            if np.linalg.norm(c) > 1e-9:
                axes.append(c / np.linalg.norm(c))
    d = p2[:3, 3] - p1[:3, 3]
    ext = lambda rows, h, u: sum(h[i] * abs(rows[i] @ u) for i in range(3))
    return min(ext(a, h1, u) + ext(b, h2, u) - abs(d @ u) for u in axes)


def random_rotation(rng):
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


def coal_convex(points):
    """coal's convex hull of `points`, as its GJK/EPA takes it."""
    import coal

    v = coal.StdVec_Vec3s()
    for q in points:
        v.append(q)
    return coal.Convex.convexHull(v, False, "")


def ellipsoid_hulls(rng, n):
    """Two hulls of `n` random points on the ellipsoids of semi-axes 1 x 0.7 x 0.5 and
    0.6 x 0.9 x 0.4 (every point a corner): their points, the tocsin meshes and coal's hulls."""
    pts, meshes = zip(*(ellipsoid_hull(rng, n, semi) for semi in ([1.0, 0.7, 0.5], [0.6, 0.9, 0.4])))
    return list(pts), list(meshes), [coal_convex(p) for p in pts]


def convex_polytopes(pairs):
    """Random convex polytopes (hulls of 6 to 20 Gaussian points, some thin): tocsin's exact path
    and coal's GJK/EPA on the same hulls, against scipy's hull of the vertex differences."""
    import coal
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(4)
    calls = {"tocsin": [], "coal EPA": []}
    oracles = []
    req = coal.CollisionRequest(coal.CollisionRequestFlag.CONTACT, 1)
    while len(oracles) < pairs:
        pa = rng.normal(size=(rng.integers(6, 20), 3)) * rng.uniform(0.2, 1.0, 3)
        pb = rng.normal(size=(rng.integers(6, 20), 3)) * rng.uniform(0.05, 1.0, 3)
        shift = rng.normal(size=3) * rng.choice([0.05, 0.3, 0.8])
        diff = (pa[:, None, :] - (pb + shift)[None, :, :]).reshape(-1, 3)
        hull = ConvexHull(diff)
        if (hull.equations[:, 3] >= 0).any():
            continue
        oracles.append((-hull.equations[:, 3]).min())
        ha, hb = ConvexHull(pa), ConvexHull(pb)
        a = tocsin.Mesh(pa, ha.simplices.astype(np.int64))
        b = tocsin.Mesh(pb, hb.simplices.astype(np.int64))
        p2 = np.eye(4)
        p2[:3, 3] = shift
        calls["tocsin"].append(lambda a=a, b=b, p2=p2: tocsin.penetration_depth(a, np.eye(4), b, p2).depth)
        shapes = [coal_convex(pa), coal_convex(pb)]
        ta, tb = coal.Transform3s(), coal.Transform3s(np.eye(3), shift)

        def coal_depth(sa=shapes[0], sb=shapes[1], ta=ta, tb=tb):
            res = coal.CollisionResult()
            coal.collide(sa, ta, sb, tb, req, res)
            return -res.getContact(0).penetration_depth if res.numContacts() else 0.0

        calls["coal EPA"].append(coal_depth)
    n = len(oracles)
    times, answers = sweeps(calls)
    errors = {k: [d / o - 1 for d, o in zip(answers[k], oracles)] for k in calls}
    lines = [
        f"{n} random convex polytope pairs (hulls of 6 to 20 points, thin slabs, deep and shallow overlaps); "
        "error against scipy's hull of all vertex differences.",
        "",
        "| query | median us | median error | worst error |",
        "|---|---:|---:|---:|",
    ]
    for k in times:
        e = np.abs(errors[k])
        lines.append(f"| {k} | {statistics.median(times[k]) * 1e6:.0f} | {np.median(e):.1e} | {e.max():.1e} |")
    return "\n".join(lines)


def hull_sizes(sizes=(20, 100, 300, 1000, 3000), poses=8):
    """Convex hulls of n random points on two ellipsoids (every point a corner), overlapping at
    `poses` seeded poses per size: tocsin (its exact path, unless the work is too much) beside
    coal's GJK/EPA, and their depths
    against scipy's hull of all vertex differences up to 300 points (9e4 differences)."""
    import coal
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(6)
    lines = [
        f"Convex hulls of n points on two ellipsoids (semi-axes 1 x 0.7 x 0.5 and 0.6 x 0.9 x 0.4), {poses} "
        "overlapping poses per size; error against scipy's hull of all vertex differences (up to 300 points), "
        "and tocsin against coal.",
        "",
        "| points (triangles) | tocsin, median us | exact answers | coal EPA, median us | worst error, tocsin | worst error, coal | worst tocsin - coal |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    req = coal.CollisionRequest(coal.CollisionRequestFlag.CONTACT, 1)
    for n in sizes:
        pts, (a, b), shapes = ellipsoid_hulls(rng, n)
        calls = {"tocsin": [], "coal": []}
        oracles = []
        for _ in range(poses):
            r2 = random_rotation(rng)
            shift = rng.normal(size=3) * 0.3
            p2 = np.eye(4)
            p2[:3, :3], p2[:3, 3] = r2, shift
            calls["tocsin"].append(lambda p2=p2: tocsin.penetration_depth(a, np.eye(4), b, p2))
            ta, tb = coal.Transform3s(), coal.Transform3s(r2, shift)

            def coal_depth(ta=ta, tb=tb):
                res = coal.CollisionResult()
                coal.collide(shapes[0], ta, shapes[1], tb, req, res)
                return -res.getContact(0).penetration_depth if res.numContacts() else 0.0

            calls["coal"].append(coal_depth)
            if n <= 300:
                diff = (pts[0][:, None, :] - (pts[1] @ r2.T + shift)[None, :, :]).reshape(-1, 3)
                eq = ConvexHull(diff).equations
                oracles.append(max((-eq[:, 3]).min(), 0.0))
        times, answers = sweeps(calls)
        exact = sum(r.exact for r in answers["tocsin"])
        depths = [r.depth for r in answers["tocsin"]]
        err = lambda got: f"{max(abs(g - o) / max(o, 1e-12) for g, o in zip(got, oracles)):.1e}" if oracles else "-"
        gap = max(abs(d - c) / max(c, 1e-12) for d, c in zip(depths, answers["coal"]))
        lines.append(
            f"| {n} ({a.num_triangles}) | {statistics.median(times['tocsin']) * 1e6:.0f} | {exact}/{poses} | "
            f"{statistics.median(times['coal']) * 1e6:.0f} | {err(depths)} | {err(answers['coal'])} | {gap:.1e} |"
        )
    return "\n".join(lines)


def hull_distances(sizes=(20, 100, 1000), poses=16):
    """The same kind of hulls, separated: `poses` seeded random rotations with the centres 2.2
    apart; tocsin's `distance` (its BVH search, built for soups) beside coal's GJK on `Convex`
    objects, timed as loops, and the largest difference of the distances."""
    import coal

    rng = np.random.default_rng(1)
    lines = [
        f"Separated convex hulls (the same ellipsoids, {poses} random rotations, centres 2.2 apart): distance.",
        "",
        "| points (triangles) | tocsin distance, median us | coal GJK, median us | largest difference |",
        "|---|---:|---:|---:|",
    ]
    req = coal.DistanceRequest()
    for n in sizes:
        _, (a, b), shapes = ellipsoid_hulls(rng, n)
        calls = {"tocsin": [], "coal": []}
        for _ in range(poses):
            p2 = np.eye(4)
            t = rng.normal(size=3)
            p2[:3, :3], p2[:3, 3] = random_rotation(rng), 2.2 * t / np.linalg.norm(t)
            calls["tocsin"].append(lambda p2=p2: tocsin.distance(a, np.eye(4), b, p2).distance)
            ta, tb = coal.Transform3s(), coal.Transform3s(p2[:3, :3], p2[:3, 3])
            calls["coal"].append(
                lambda ta=ta, tb=tb: coal.distance(shapes[0], ta, shapes[1], tb, req, coal.DistanceResult())
            )
        times, answers = sweeps(calls)
        gap = max(abs(x - y) for x, y in zip(answers["tocsin"], answers["coal"]))
        lines.append(
            f"| {n} ({a.num_triangles}) | {statistics.median(times['tocsin']) * 1e6:.1f} | "
            f"{statistics.median(times['coal']) * 1e6:.1f} | {gap:.1e} |"
        )
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--pairs", type=int, default=200)
    parser.add_argument("--out")
    args = parser.parse_args()
    rng = np.random.default_rng(2)
    h1, h2 = np.array([0.5, 0.3, 0.8]), np.array([0.4, 0.6, 0.2])
    m1, m2 = tocsin.Mesh.box(h1), tocsin.Mesh.box(h2)
    f1, f2 = fcl_model(m1), fcl_model(m2)
    s1, s2 = fcl.Box(*(2 * h1)), fcl.Box(*(2 * h2))
    tol = 1e-3 * min(m1.bounding_radius, m2.bounding_radius)
    calls = {"tocsin": [], "tocsin local search": [], "fcl mesh": [], "fcl box": []}
    cases = []
    req = fcl.CollisionRequest(num_max_contacts=100000, enable_contact=True)
    while len(cases) < args.pairs:
        p1, p2 = np.eye(4), np.eye(4)
        p1[:3, :3], p2[:3, :3] = random_rotation(rng), random_rotation(rng)
        p1[:3, 3], p2[:3, 3] = rng.uniform(-0.2, 0.2, 3), rng.uniform(-0.6, 0.6, 3)
        exact = sat_depth(h1, p1, h2, p2)
        if exact < 1e-3:
            continue
        cases.append((p1, p2, exact))
        for name, exact_convex in [("tocsin", True), ("tocsin local search", False)]:
            calls[name].append(
                lambda p1=p1, p2=p2, e=exact_convex: tocsin.penetration_depth(m1, p1, m2, p2, exact_convex=e)
            )
        for name, (g1, g2) in [("fcl mesh", (f1, f2)), ("fcl box", (s1, s2))]:
            o1 = fcl.CollisionObject(g1, fcl.Transform(p1[:3, :3], p1[:3, 3]))
            o2 = fcl.CollisionObject(g2, fcl.Transform(p2[:3, :3], p2[:3, 3]))

            def fcl_depth(o1=o1, o2=o2):
                res = fcl.CollisionResult()
                fcl.collide(o1, o2, req, res)
                return max((c.penetration_depth for c in res.contacts), default=0.0)

            calls[name].append(fcl_depth)
    n = len(cases)
    rows, answers = sweeps(calls)
    errors = {k: [] for k in calls}
    separated = {"tocsin": 0, "tocsin local search": 0}
    for i, (p1, p2, exact) in enumerate(cases):
        for name in calls:
            r = answers[name][i]
            errors[name].append((r.depth if name in separated else r) / exact - 1)
            if name in separated:
                after = p2.copy()
                after[:3, 3] += r.translation
                separated[name] += (not tocsin.collide(m1, p1, m2, after)) and tocsin.distance(
                    m1, p1, m2, after
                ).distance <= tol * (1 + 1e-9)
    lines = [
        machine_line(),
        "",
        f"{n} random overlapping box pairs (half extents 0.5 x 0.3 x 0.8 and 0.4 x 0.6 x 0.2); error of the "
        "depth against the exact separating-axis value, relative.",
        "",
        "| query | median us | median error | worst error | answers that separate the boxes |",
        "|---|---:|---:|---:|---:|",
    ]
    for name in rows:
        e = np.abs(errors[name])
        sep = f"{separated[name]}/{n}" if name in separated else "-"
        lines.append(
            f"| {name} | {statistics.median(rows[name]) * 1e6:.0f} | {np.median(e):.2%} | {e.max():.2%} | {sep} |"
        )
    lines += ["", convex_polytopes(args.pairs), "", hull_sizes(), "", hull_distances()]
    text = "\n".join(lines)
    print(text)
    if args.out:
        open(args.out, "w").write(text + "\n")


if __name__ == "__main__":
    main()
