"""Side-by-side on tied geometry: many triangle pairs at exactly the minimum distance.

Parallel plates, coincident copies of one triangle, and a plate dropped flat onto a floor
(continuous collision, whose last step is a distance query between parallel faces). Before
the hardening issue tocsin visited every tied pair (0.6 s for two 180K-triangle plates,
quadratic in the copies). Objects are built once, outside the timer; the libraries alternate
in blocks of calls. Usage: python bench/compare_fcl_ties.py [--quick] [--out FILE]
"""

import argparse
import sys

import numpy as np

import tocsin
from _common import fcl_model, machine_line, timed_pair, write

try:
    import fcl
except ImportError:  # pragma: no cover
    sys.exit("python-fcl is not installed: pip install python-fcl (make bench-python does)")


def lifted(z):
    p = np.eye(4)
    p[2, 3] = z
    return p


def copies(n):
    """One triangle, n times."""
    return tocsin.Mesh(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.zeros((n, 3), dtype=np.int64))


def distance_row(name, m1, m2, p2, repeats):
    f1, f2 = fcl_model(m1), fcl_model(m2)
    o1 = fcl.CollisionObject(f1, fcl.Transform())
    o2 = fcl.CollisionObject(f2, fcl.Transform(p2[:3, :3], p2[:3, 3]))
    req = fcl.DistanceRequest(enable_nearest_points=True)
    ours = tocsin.distance(m1, np.eye(4), m2, p2).distance
    theirs = fcl.distance(o1, o2, req, fcl.DistanceResult())
    a, b = timed_pair(
        lambda: tocsin.distance(m1, np.eye(4), m2, p2),
        lambda: fcl.distance(o1, o2, req, fcl.DistanceResult()),
        repeats,
        block=5,
    )
    check = f"|diff| {abs(ours - theirs):.1e}"
    return (name, f"{m1.num_triangles} + {m2.num_triangles}", "distance", a, b, check)


def drop_row(n_plate, n_floor, repeats):
    """A plate dropped flat onto a larger floor: tocsin's time of contact, and FCL's distance
    at the pose where tocsin stops (the query that dominated tocsin's time)."""
    plate, floor = tocsin.Mesh.plate(1.0, n_plate), tocsin.Mesh.plate(2.0, n_floor)
    fall = tocsin.Motion.translation(lifted(1.0), lifted(-1.0))
    still = tocsin.Motion.stationary(np.eye(4))
    c = tocsin.time_of_contact(plate, fall, floor, still)
    at = fall.pose_at(c.time)
    fp, ff = fcl_model(plate), fcl_model(floor)
    o1 = fcl.CollisionObject(fp, fcl.Transform(at[:3, :3], at[:3, 3]))
    o2 = fcl.CollisionObject(ff, fcl.Transform())
    req = fcl.DistanceRequest(enable_nearest_points=True)
    a, b = timed_pair(
        lambda: tocsin.time_of_contact(plate, fall, floor, still),
        lambda: fcl.distance(o1, o2, req, fcl.DistanceResult()),
        repeats,
        block=5,
    )
    check = f"t = {c.time:.6f}, {c.iterations} iterations"
    name = "plate dropped on a floor (tocsin time_of_contact; fcl: one distance at its end)"
    return (name, f"{plate.num_triangles} + {floor.num_triangles}", "contact time", a, b, check)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="bench/out/ties.md")
    args = ap.parse_args()
    repeats = 5 if args.quick else 20
    plates = tocsin.Mesh.plate(1.0, 60 if args.quick else 300)
    rows = [distance_row("parallel plates 0.1 apart", plates, plates, lifted(0.1), repeats)]
    for n in (1000,) if args.quick else (4000, 16000):
        c = copies(n)
        rows.append(distance_row(f"{n} coincident copies of one triangle, 0.5 apart", c, c, lifted(0.5), repeats))
    for sizes in ((16, 32),) if args.quick else ((64, 128), (128, 256)):
        rows.append(drop_row(*sizes, repeats))
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; median of {repeats} "
        "calls each, alternating in blocks of 5, objects built outside the timer.",
        "",
        "| case | triangles | query | tocsin (us) | python-fcl (us) | fcl / tocsin | check |",
        "|---|---:|---|---:|---:|---:|---|",
    ]
    for name, n, q, a, b, check in rows:
        lines.append(f"| {name} | {n} | {q} | {a * 1e6:.1f} | {b * 1e6:.1f} | {b / a:.2f}x | {check} |")
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
