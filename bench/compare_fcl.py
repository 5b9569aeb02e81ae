"""Side-by-side: tocsin vs python-fcl (OBBRSS BVHModel) on the same mesh pairs and poses.

Distance at separations of 1%, 10% and 100% of the bounding radius, and collide on
overlapping and near poses, 32 random poses each; each library is called in a loop over the
poses, as a user's loop would (the loops take turns, nine rounds, a pose's time the median of
its rounds), in one run, with the ratio fcl / tocsin of the medians over the poses. Until the
thirty-sixth session each pose was timed 30 times, 10 calls in a row per library, which kept
that query warm. Distances are checked identical to 1e-9 relative and collide answers equal.
Models: the torus knots (generated) and real meshes shipped by pybullet_data (bunny, Franka
Panda link). Usage: python bench/compare_fcl.py [--quick] [--out FILE] [--poses-out FILE]
"""

import argparse
import statistics
import sys

import numpy as np

import tocsin
from _common import fcl_model, machine_line, models, pose, rotation, sweeps, write

try:
    import fcl
except ImportError:  # pragma: no cover
    sys.exit("python-fcl is not installed: pip install python-fcl (make bench-python does)")


def selected_models(quick):
    out = models(["knot2.8k", "knot11k", "knot34k", "bunny", "panda_link0"])
    return {k: out[k] for k in list(out)[:1]} if quick else out


def random_turn(rng):
    """A random rotation (0.3 to pi rad) and a random unit direction."""
    rot = rotation(rng.normal(size=3), rng.uniform(0.3, np.pi))
    d = rng.normal(size=3)
    return rot, d / np.linalg.norm(d)


def loop_medians(calls, rounds):
    """tocsin's and FCL's median times over the poses, each library called in a loop over them
    (`sweeps`: one call per pose, the two loops taking turns, `rounds` rounds)."""
    times, _ = sweeps(calls, rounds)
    return statistics.median(times["tocsin"]), statistics.median(times["fcl"])


def place(mesh, rot, direction, target):
    """Offset along direction at which tocsin's distance is target (bisection)."""
    lo, hi = 0.0, 6.0 * mesh.bounding_radius + target
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if tocsin.distance(mesh, np.eye(4), mesh, pose(rot, direction * mid)).distance < target:
            lo = mid
        else:
            hi = mid
    return pose(rot, direction * hi)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="one model, few poses (smoke test)")
    ap.add_argument("--out", default="bench/out/fcl.md")
    ap.add_argument(
        "--poses-out",
        help="also write knot34k's distance poses here, for crates/tocsin/examples/profile_poses.rs",
    )
    args = ap.parse_args()
    rng = np.random.default_rng(2026)
    n_poses, rounds = (4, 3) if args.quick else (32, 9)
    rows, knot_poses = [], []
    for name, mesh in selected_models(args.quick).items():
        fm = fcl_model(mesh)
        radius = float(np.linalg.norm(mesh.vertices - mesh.vertices.mean(0), axis=1).max())
        o1 = fcl.CollisionObject(fm, fcl.Transform())
        for frac in (0.01, 0.1, 1.0):
            calls, worst = {"tocsin": [], "fcl": []}, 0.0
            for _ in range(n_poses):
                rot, d = random_turn(rng)
                p2 = place(mesh, rot, d, frac * radius)
                if name == "knot34k":
                    knot_poses.append(f"{frac:g} " + " ".join(repr(float(x)) for x in p2.ravel()))
                o2 = fcl.CollisionObject(fm, fcl.Transform(p2[:3, :3], p2[:3, 3]))
                req = fcl.DistanceRequest(enable_nearest_points=True)
                ours = tocsin.distance(mesh, np.eye(4), mesh, p2).distance
                theirs = fcl.distance(o1, o2, req, fcl.DistanceResult())
                worst = max(worst, abs(ours - theirs) / max(abs(theirs), 1e-300))
                calls["tocsin"].append(lambda p2=p2: tocsin.distance(mesh, np.eye(4), mesh, p2))
                calls["fcl"].append(lambda o2=o2, req=req: fcl.distance(o1, o2, req, fcl.DistanceResult()))
            a, b = loop_medians(calls, rounds)
            rows.append((name, mesh.num_triangles, f"distance {frac:g}R", a, b, f"{worst:.1e}"))
        for label, frac in (("collide overlap", -1.0), ("collide near 0.01R", 0.01)):
            calls, agree = {"tocsin": [], "fcl": []}, 0
            for _ in range(n_poses):
                rot, d = random_turn(rng)
                p2 = place(mesh, rot, d, frac * radius) if frac > 0 else pose(rot, d * 0.3 * radius)
                o2 = fcl.CollisionObject(fm, fcl.Transform(p2[:3, :3], p2[:3, 3]))
                creq = fcl.CollisionRequest()
                ours = tocsin.collide(mesh, np.eye(4), mesh, p2)
                theirs = fcl.collide(o1, o2, creq, fcl.CollisionResult()) > 0
                agree += ours == theirs
                calls["tocsin"].append(lambda p2=p2: tocsin.collide(mesh, np.eye(4), mesh, p2))
                calls["fcl"].append(lambda o2=o2, creq=creq: fcl.collide(o1, o2, creq, fcl.CollisionResult()))
            a, b = loop_medians(calls, rounds)
            rows.append((name, mesh.num_triangles, label, a, b, f"{agree}/{n_poses} agree"))
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; "
        f"median over {n_poses} poses, each library called in a loop over them, {rounds} rounds "
        "(the loops take turns; a pose's time is the median of its rounds), "
        "single thread, through Python for both.",
        "",
        "| model | triangles | query | tocsin (us) | python-fcl (us) | fcl / tocsin | check |",
        "|---|---:|---|---:|---:|---:|---|",
    ]
    for name, n, q, a, b, check in rows:
        lines.append(f"| {name} | {n} | {q} | {a * 1e6:.1f} | {b * 1e6:.1f} | {b / a:.2f}x | {check} |")
    write(args.out, "\n".join(lines))
    if args.poses_out and knot_poses:
        with open(args.poses_out, "w") as f:
            f.write("\n".join(knot_poses) + "\n")


if __name__ == "__main__":
    main()
