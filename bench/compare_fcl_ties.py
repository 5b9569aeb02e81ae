"""Side-by-side on tied geometry: many triangle pairs at exactly the minimum distance.

Parallel plates, coincident copies of one triangle, and a plate dropped flat onto a floor
(continuous collision, whose last step is a distance query between parallel faces). Before
the hardening issue tocsin visited every tied pair (0.6 s for two 180K-triangle plates,
quadratic in the copies). Each case is posed `POSES` ways (shifted in the plane and in height,
every pose still tied); objects are built once, outside the timer, and each library runs a
loop over the poses, the loops taking turns (`_common.sweeps`); a case's time is the median
over its poses. Usage: python bench/compare_fcl_ties.py [--quick] [--out FILE]
"""

import argparse
import statistics
import sys

import numpy as np

import tocsin
from _common import fcl_model, machine_line, sweeps, write

try:
    import fcl
except ImportError:  # pragma: no cover
    sys.exit("python-fcl is not installed: pip install python-fcl (make bench-python does)")


POSES = 8


def lifted(z, x=0.0, y=0.0):
    p = np.eye(4)
    p[:3, 3] = x, y, z
    return p


def posed(z, k):
    """The `k`-th of `POSES` poses at about height `z`: shifted up to 5% of a unit in the plane
    and up to 10% in height, so that each pose's tied pairs are the same kind."""
    rng = np.random.default_rng(k)
    x, y = rng.uniform(-0.05, 0.05, 2)
    return lifted(z * (1 + 0.1 * k / POSES), x, y)


def copies(n):
    """One triangle, n times."""
    return tocsin.Mesh(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.zeros((n, 3), dtype=np.int64))


def distance_row(name, m1, m2, z, rounds):
    poses = [posed(z, k) for k in range(POSES)]
    req = fcl.DistanceRequest(enable_nearest_points=True)
    f1, f2 = fcl_model(m1), fcl_model(m2)
    o1 = fcl.CollisionObject(f1, fcl.Transform())
    o2s = [fcl.CollisionObject(f2, fcl.Transform(p[:3, :3], p[:3, 3])) for p in poses]
    times, answers = sweeps(
        {
            "tocsin": [lambda p=p: tocsin.distance(m1, np.eye(4), m2, p).distance for p in poses],
            "fcl": [lambda o2=o2: fcl.distance(o1, o2, req, fcl.DistanceResult()) for o2 in o2s],
        },
        rounds=rounds,
    )
    worst = max(abs(a - b) for a, b in zip(answers["tocsin"], answers["fcl"]))
    check = f"largest difference {worst:.1e}"
    a, b = (statistics.median(times[k]) for k in ("tocsin", "fcl"))
    return (name, f"{m1.num_triangles} + {m2.num_triangles}", "distance", a, b, check)


def drop_row(n_plate, n_floor, rounds):
    """A plate dropped flat onto a larger floor: tocsin's time of contact, and FCL's distance
    at the pose where tocsin stops (the query that dominated tocsin's time)."""
    plate, floor = tocsin.Mesh.plate(1.0, n_plate), tocsin.Mesh.plate(2.0, n_floor)
    still = tocsin.Motion.stationary(np.eye(4))
    falls = [tocsin.Motion.translation(posed(1.0, k), posed(-1.0, k)) for k in range(POSES)]
    contacts = [tocsin.time_of_contact(plate, fall, floor, still) for fall in falls]
    fp, ff = fcl_model(plate), fcl_model(floor)
    o2 = fcl.CollisionObject(ff, fcl.Transform())
    o1s = []
    for fall, c in zip(falls, contacts):
        at = fall.pose_at(c.time)
        o1s.append(fcl.CollisionObject(fp, fcl.Transform(at[:3, :3], at[:3, 3])))
    req = fcl.DistanceRequest(enable_nearest_points=True)
    times, _ = sweeps(
        {
            "tocsin": [lambda f=f: tocsin.time_of_contact(plate, f, floor, still) for f in falls],
            "fcl": [lambda o1=o1: fcl.distance(o1, o2, req, fcl.DistanceResult()) for o1 in o1s],
        },
        rounds=rounds,
    )
    iterations = sorted({c.iterations for c in contacts})
    check = f"t = {min(c.time for c in contacts):.4f} to {max(c.time for c in contacts):.4f}, {iterations} iterations"
    name = "plate dropped on a floor (tocsin time_of_contact; fcl: one distance at its end)"
    a, b = (statistics.median(times[k]) for k in ("tocsin", "fcl"))
    return (name, f"{plate.num_triangles} + {floor.num_triangles}", "contact time", a, b, check)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="bench/out/ties.md")
    args = ap.parse_args()
    rounds = 3 if args.quick else 9
    plates = tocsin.Mesh.plate(1.0, 60 if args.quick else 300)
    rows = [distance_row("parallel plates 0.1 to 0.11 apart", plates, plates, 0.1, rounds)]
    for n in (1000,) if args.quick else (4000, 16000):
        c = copies(n)
        rows.append(distance_row(f"{n} coincident copies of one triangle, 0.5 to 0.55 apart", c, c, 0.5, rounds))
    for sizes in ((16, 32),) if args.quick else ((64, 128), (128, 256)):
        rows.append(drop_row(*sizes, rounds))
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; {POSES} poses per case, "
        f"each library a loop over them, the loops taking turns, {rounds} rounds; a pose's time is "
        "its rounds' median, a case's the median over its poses; objects built outside the timer.",
        "",
        "| case | triangles | query | tocsin (us) | python-fcl (us) | fcl / tocsin | check |",
        "|---|---:|---|---:|---:|---:|---|",
    ]
    for name, n, q, a, b, check in rows:
        lines.append(f"| {name} | {n} | {q} | {a * 1e6:.1f} | {b * 1e6:.1f} | {b / a:.2f}x | {check} |")
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
