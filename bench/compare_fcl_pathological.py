"""The continuous-collision issue's pathological cases, tocsin beside python-fcl's naive solver
at 100 samples (objects and requests built outside the timer), in one run, plus knot34k's
median on an ordinary pass for scale. Each case is timed `--repeats` times (median).

- ball: a sphere (16K triangles) turning 90 degrees about its centre in a concentric socket
  at 0.3% clearance;
- shaft: a tube (4K) turning 180 degrees in a bore (4K) at 0.4% clearance;
- slivers: a knot of 30 x 600 rings (150:1 triangles) on the issue's interp pass;
- far screw: knot34k on a half turn about an axis 52 units away, passing the other knot at
  about 1.5 R;
- poles: UV spheres (1,024 triangles per pole fan) meeting pole to pole.

Usage: python bench/compare_fcl_pathological.py [--repeats N] [--out FILE]
"""

import argparse
import statistics
import time

import numpy as np

import tocsin
from _common import fcl_model, machine_line, pose, rotation, write

import fcl


def tube(r, length, n_around=256, n_along=8):
    a = np.linspace(0, 2 * np.pi, n_around, endpoint=False)
    z = np.linspace(-length / 2, length / 2, n_along + 1)
    v = np.array([[r * np.cos(t), r * np.sin(t), h] for h in z for t in a])
    f = []
    for i in range(n_along):
        for j in range(n_around):
            p, q = i * n_around + j, i * n_around + (j + 1) % n_around
            f += [[p, q, q + n_around], [p, q + n_around, p + n_around]]
    return tocsin.Mesh(v, np.array(f))


def turn(axis, degrees, t=(0, 0, 0)):
    return pose(rotation(axis, np.radians(degrees)), t)


def cases():
    still = np.eye(4)
    ball, socket = tocsin.Mesh.sphere(1.0, 64, 128), tocsin.Mesh.sphere(1.003, 64, 128)
    yield "ball in socket", ball, socket, "screw", np.eye(4), turn((0.3, 0.2, 1.0), 90), still
    yield "shaft in bore", tube(1.0, 4.0), tube(1.004, 6.0), "screw", np.eye(4), turn((0, 0, 1), 180), still
    slivers = tocsin.Mesh.torus_knot(30, 600)
    s, e = np.eye(4), turn((1, 1, 0), 60)
    s[:3, 3], e[:3, 3] = [-14, 1, 0.5], [14, -0.5, 0]
    yield "knot of slivers", slivers, slivers, "interp", s, e, still
    knot = tocsin.Mesh.torus_knot(680, 25)
    centre = np.array([0.0, 52.0, 0.0])
    s = pose(np.eye(3), centre + [-40, 0, 0])
    r = rotation((0, 0, 1), np.pi)
    e = pose(r, centre + r @ (s[:3, 3] - centre))
    yield "knot34k, far screw", knot, knot, "screw", s, e, still
    uv = tocsin.Mesh.sphere(1.0, 32, 1024)
    yield "UV spheres pole to pole", uv, uv, "translation", pose(np.eye(3), [0, 0, -3]), pose(np.eye(3), [0, 0, 3]), still
    s, e = np.eye(4), turn((0, 0.3, 1), 75, (14, -0.5, 0))
    s[:3, 3] = [-14, 1, 0.5]
    yield "knot34k ordinary pass (scale)", knot, knot, "interp", s, e, still


KINDS = {"translation": fcl.CCDMotionType.CCDM_TRANS, "interp": fcl.CCDMotionType.CCDM_LINEAR, "screw": fcl.CCDMotionType.CCDM_SCREW}


def tf(p):
    return fcl.Transform(p[:3, :3].copy(), p[:3, 3].copy())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="bench/out/pathological.md")
    args = ap.parse_args()
    rows = []
    for name, m1, m2, kind, start, end, still in cases():
        motion = {"translation": tocsin.Motion.translation, "interp": tocsin.Motion.interp, "screw": tocsin.Motion.screw}[kind](start, end)
        stay = tocsin.Motion.stationary(still)
        o1, o2 = fcl.CollisionObject(fcl_model(m1), tf(start)), fcl.CollisionObject(fcl_model(m2), tf(still))
        req = fcl.ContinuousCollisionRequest(num_max_iterations=100, ccd_motion_type=KINDS[kind], ccd_solver_type=fcl.CCDSolverType.CCDC_NAIVE)
        start_tf, goal_tf, still_tf = tf(start), tf(end), tf(still)

        def ours():
            return tocsin.time_of_contact(m1, motion, m2, stay)

        def theirs():
            o1.setTransform(start_tf)
            res = fcl.ContinuousCollisionResult()
            fcl.continuousCollide(o1, goal_tf, o2, still_tf, req, res)
            return res.time_of_contact if res.is_collide else None

        ta, tb = [], []
        for _ in range(args.repeats):
            for fn, samples in ((ours, ta), (theirs, tb)):
                t0 = time.perf_counter()
                answer = fn()
                samples.append(time.perf_counter() - t0)
                if fn is ours:
                    ours_answer = answer
                else:
                    fcl_answer = answer
        a, b = statistics.median(ta), statistics.median(tb)
        what = "none" if ours_answer is None else f"t = {ours_answer.time:.6f}, {ours_answer.iterations} iterations"
        theirs_what = "none" if fcl_answer is None else f"t = {fcl_answer:.3f}"
        rows.append((name, f"{m1.num_triangles} + {m2.num_triangles}", a, b, what, theirs_what))
        print(rows[-1], flush=True)
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; median of {args.repeats} calls each, "
        "alternating, objects built outside the timer.",
        "",
        "| case | triangles | tocsin (ms) | fcl naive 100 (ms) | tocsin's answer | fcl's answer |",
        "|---|---:|---:|---:|---|---|",
    ]
    for name, n, a, b, what, theirs in rows:
        lines.append(f"| {name} | {n} | {a * 1e3:.2f} | {b * 1e3:.2f} | {what} | {theirs} |")
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
