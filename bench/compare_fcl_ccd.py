"""Time of contact: tocsin vs python-fcl on the same seeded queries, in one run.

Models: the knots, the bunny and a Panda link, and two convex hulls (100 and 1,000 points on
an ellipsoid), whose time of contact steps by GJK's separation of the whole bodies; for those
the same surface as a soup (a degenerate triangle added) shows the general path beside it.
Per model and motion kind: body 1 driven through body 2 (fixed at the identity) with a 30 to 90
degree rotation (none for translations), and near misses with a closest approach of about 1%
of the bounding radius. Methods: tocsin.time_of_contact (the closest points at the time, the default) and with
contact_pair=True (the points of the triangle pair that ended the advancement, without the final
exact distance query); tocsin.distance at the start pose (the issue's yardstick: a
time of contact at most 3 of them); fcl.continuousCollide with
conservative advancement and with the naive solver at 100 samples (motion types CCDM_TRANS,
CCDM_LINEAR = interp with centre 0, CCDM_SCREW); tocsin.motion_is_free (the yes/no question,
no witnesses); and a conservative-advancement loop written
over fcl.distance with an undirected motion bound (translation and interp only). The oracle
samples tocsin.collide (exact, tested against brute force) at 1,000 times and bisects; the
distance at a reported time comes from tocsin.distance (identical to fcl.distance to 1e-9).
A miss: the oracle collides, the method says no. Late: the method's time is after the first
collision. False positive: a reported time where the meshes are farther apart than the
tolerance (1e-3 of the bounding radius).

Timing as a user's loop would call each library: every object (tocsin motions, FCL collision
objects, requests) is built before the timer starts; each method runs through the cell's
queries one call each (a sweep), the methods' sweeps take turns, three rounds with the order
turning, and a query's time is the median of its three (one when a call takes over 20 ms). Until
the hardening issue FCL's objects and request were built inside the timed call, about 130 us of
each FCL naive query. Usage: python bench/compare_fcl_ccd.py [--quick]
"""

import argparse
import statistics
import time
import zlib

import numpy as np

import tocsin
from _common import as_soup, fcl_model, machine_line, models, pose, rotation, sweeps, write

import fcl

KINDS = {"translation": fcl.CCDMotionType.CCDM_TRANS, "interp": fcl.CCDMotionType.CCDM_LINEAR, "screw": fcl.CCDMotionType.CCDM_SCREW}


def tf(p):
    return fcl.Transform(p[:3, :3].copy(), p[:3, 3].copy())


def make_motion(kind, start, end):
    if kind == "translation":
        end = end.copy()
        end[:3, :3] = start[:3, :3]
        return tocsin.Motion.translation(start, end), end
    return (tocsin.Motion.interp(start, end) if kind == "interp" else tocsin.Motion.screw(start, end)), end


def queries(mesh, kind, n_through, n_near, rng):
    """(motion, start pose, end pose) triples."""
    r = mesh.bounding_radius
    still = np.eye(4)
    out = []
    for q in range(n_through + n_near):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        axis = rng.normal(size=3)
        angle = 0.0 if kind == "translation" else np.radians(rng.uniform(30, 90))
        r0 = rotation(rng.normal(size=3), 0.4)
        side = np.cross(rng.normal(size=3), d)
        side /= np.linalg.norm(side)

        def shifted(o):
            start = pose(r0, -2.5 * r * d + side * o)
            end = pose(rotation(axis, angle) @ r0, 2.5 * r * d + side * o)
            return make_motion(kind, start, end)[0], start, make_motion(kind, start, end)[1]

        if q < n_through:
            out.append(shifted(rng.uniform(0, 0.2) * r))
            continue
        lo, hi = 0.0, 3.0 * r
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            mo = shifted(mid)[0]
            if any(tocsin.collide(mesh, mo.pose_at(k / 200), mesh, still) for k in range(201)):
                lo = mid
            else:
                hi = mid
        out.append(shifted(hi + 0.01 * r))
    return out


def fcl_call(fm, o2, req, start, end):
    """FCL's continuous collision of model `fm` from `start` to `end` against `o2` (still), as a
    call with every object built beforehand: the time of contact, or None."""
    o1, start_tf, goal_tf, still_tf = fcl.CollisionObject(fm, tf(start)), tf(start), tf(end), fcl.Transform()

    def run():
        o1.setTransform(start_tf)
        res = fcl.ContinuousCollisionResult()
        fcl.continuousCollide(o1, goal_tf, o2, still_tf, req, res)
        return res.time_of_contact if res.is_collide else None

    return run


def oracle(mesh, motion):
    hit = lambda t: tocsin.collide(mesh, motion.pose_at(t), mesh, np.eye(4))  # noqa: E731
    n = 1000
    for i in range(n + 1):
        t = i / n
        if hit(t):
            lo, hi = t - 1 / n, t
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if hit(mid) else (mid, hi)
            return hi
    return None


def ca_loop_over_fcl_distance(o1, o2, mesh, motion, start, end, delta):
    """Conservative advancement with FCL's distance and an undirected bound |v| + |w| r."""
    v = np.linalg.norm(end[:3, 3] - start[:3, 3])
    rel = end[:3, :3] @ start[:3, :3].T
    w = np.arccos(np.clip((np.trace(rel) - 1) / 2, -1, 1))
    rmax = float(np.linalg.norm(mesh.vertices, axis=1).max())
    mu = v + w * rmax
    t = 0.0
    req = fcl.DistanceRequest()
    for _ in range(100000):
        o1.setTransform(tf(motion.pose_at(t)))
        d = fcl.distance(o1, o2, req, fcl.DistanceResult())
        if d <= delta:
            return t
        t += (d - 0.5 * delta) / mu
        if t >= 1.0:
            return None
    return t


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="bench/out/fcl_ccd.md")
    ap.add_argument("--models", default="knot2.8k,knot34k,bunny,panda_link1,hull100,hull1k")
    args = ap.parse_args()
    n_through, n_near = (3, 2) if args.quick else (30, 20)
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; {n_through} pass-through + {n_near} near-miss queries per cell.",
        "",
        "| model | motion | method | median (us) | p90 (us) | contacts | misses | late | false positives |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    # Per cell: tocsin's time of contact against its own distance at the start pose, against
    # FCL's 100-sample sampler, and its 90th percentile against its median (the targets).
    ratios = []
    still = np.eye(4)
    for name, mesh in models(args.models.split(",")).items():
        fm = fcl_model(mesh)
        delta = 1e-3 * mesh.bounding_radius
        for kind, fcl_kind in KINDS.items():
            # A stable seed per cell (Python's str hash changes from run to run).
            rng = np.random.default_rng(zlib.crc32(f"{name}/{kind}".encode()))
            qs = queries(mesh, kind, n_through, n_near, rng)
            firsts = [oracle(mesh, mo) for mo, _, _ in qs]
            stay = tocsin.Motion.stationary(still)

            def ours(mo, s, e):
                return lambda: (lambda r: None if r is None else r.time)(tocsin.time_of_contact(mesh, mo, mesh, stay))

            def contact_pair(mo, s, e):
                return lambda: (lambda r: None if r is None else r.time)(
                    tocsin.time_of_contact(mesh, mo, mesh, stay, contact_pair=True)
                )

            def is_free(mo, s, e):
                return lambda: tocsin.motion_is_free(mesh, mo, mesh, stay)

            def start_distance(mo, s, e):
                return lambda: tocsin.distance(mesh, s, mesh, still).distance

            methods = {"tocsin": ours, "tocsin contact pair": contact_pair, "tocsin motion_is_free": is_free, "tocsin distance at the start": start_distance}
            if name.startswith("hull"):
                # The convex hulls' time of contact steps by GJK's separation of the whole
                # bodies; the same surface as a soup takes the general path.
                soup = as_soup(mesh)

                def general(mo, s, e, soup=soup):
                    return lambda: (lambda r: None if r is None else r.time)(tocsin.time_of_contact(soup, mo, soup, stay))

                methods["tocsin general path (as a soup)"] = general
            for label, solver, iters in (("fcl CA", fcl.CCDSolverType.CCDC_CONSERVATIVE_ADVANCEMENT, 100), ("fcl naive 100", fcl.CCDSolverType.CCDC_NAIVE, 100)):
                req = fcl.ContinuousCollisionRequest(num_max_iterations=iters, ccd_motion_type=fcl_kind, ccd_solver_type=solver)
                o2 = fcl.CollisionObject(fm, fcl.Transform())

                methods[label] = lambda mo, s, e, req=req, o2=o2: fcl_call(fm, o2, req, s, e)
            if kind != "screw":

                def prepare_loop(mo, s, e):
                    o1, o2 = fcl.CollisionObject(fm, tf(s)), fcl.CollisionObject(fm, fcl.Transform())
                    return lambda: ca_loop_over_fcl_distance(o1, o2, mesh, mo, s, e, delta)

                methods["CA loop over fcl.distance"] = prepare_loop
            calls = {label: [prep(mo, s, e) for mo, s, e in qs] for label, prep in methods.items()}
            times, answers = sweeps(calls)
            med = {label: statistics.median(ts) for label, ts in times.items()}
            p90 = {label: float(np.percentile(ts, 90)) for label, ts in times.items()}
            ratios.append((name, kind, med["tocsin"] / med["tocsin distance at the start"], med["tocsin"] / med["fcl naive 100"], p90["tocsin"] / med["tocsin"]))
            for label in methods:
                contacts, misses, late, fps = 0, 0, 0, 0
                timing = f"{med[label] * 1e6:.0f} | {p90[label] * 1e6:.0f}"
                if label == "tocsin distance at the start":
                    lines.append(f"| {name} | {kind} | {label} | {timing} | - | - | - | - |")
                    print(lines[-1], flush=True)
                    continue
                if label == "tocsin motion_is_free":
                    # A yes/no answer: contacts are "not free"; there is no time to be late.
                    contacts = sum(not free for free in answers[label])
                    misses = sum(free and first is not None for free, first in zip(answers[label], firsts))
                    lines.append(
                        f"| {name} | {kind} | {label} | {timing} | {contacts}/{len(qs)} | {misses} | - | - |"
                    )
                    print(lines[-1], flush=True)
                    continue
                for (mo, s, e), first, t in zip(qs, firsts, answers[label]):
                    if t is None:
                        misses += first is not None
                        continue
                    contacts += 1
                    late += first is not None and t > first + 1e-9
                    fps += tocsin.distance(mesh, mo.pose_at(t), mesh, still).distance > delta * (1 + 1e-9)
                lines.append(
                    f"| {name} | {kind} | {label} | {timing} | {contacts}/{len(qs)} | {misses} | {late} | {fps} |"
                )
                print(lines[-1], flush=True)
            # The yes/no answers apart on the colliding motions (which motion_is_free's probes
            # and the sampler's first colliding sample settle early) and the free ones.
            for label in ("tocsin motion_is_free", "fcl naive 100"):
                parts = [[t for t, first in zip(times[label], firsts) if (first is None) == free] for free in (False, True)]
                med_p90 = [
                    (f"{statistics.median(ts) * 1e6:.0f}", f"{np.percentile(ts, 90) * 1e6:.0f}") if ts else ("-", "-")
                    for ts in parts
                ]
                lines.append(
                    f"| {name} | {kind} | {label}: colliding / free motions | {med_p90[0][0]} / {med_p90[1][0]} | "
                    f"{med_p90[0][1]} / {med_p90[1][1]} | {len(parts[0])} / {len(parts[1])} | - | - | - |"
                )
                print(lines[-1], flush=True)
    lines += [
        "",
        "| model | motion | time of contact / own distance at the start (median) | / fcl naive 100 (median) | p90 / median |",
        "|---|---|---:|---:|---:|",
    ]
    lines += [f"| {n} | {k} | {a:.1f}x | {b:.1f}x | {c:.1f} |" for n, k, a, b, c in ratios]
    print("\n".join(lines[-len(ratios) - 3:]), flush=True)
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
