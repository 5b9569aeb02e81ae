"""The continuous-collision issue's pathological cases, tocsin beside python-fcl's naive solver
at 100 samples (objects and requests built outside the timer), in one run, plus knot34k's
median over ordinary passes for scale.

- ball: a sphere (16K triangles) turning 90 degrees about its centre in a concentric socket
  at 0.3% clearance;
- shaft: a tube (4K) turning 180 degrees in a bore (4K) at 0.4% clearance; the same with 128
  sides (2K each), whose corners come within 1.65 tolerances of the bore's faces;
- tapered shaft: a shaft tapering from radius 1 to 0.5 (4K) turning 180 degrees in a bore of
  the same taper 0.004 wider (4K);
- band: a 32-sided shaft (256) turning 180 degrees in a bore (256) whose faces clear its
  corners by 0.84 tolerances (the contract allows either answer) or 0.3 (a contact);
- bolt: a bolt with a sinusoidal thread (pitch 0.5, depth 0.1; 98K) screwed 170 degrees along
  its thread into a nut 0.01 wider (32K);
- slivers: a knot of 30 x 600 rings (150:1 triangles) on the issue's interp pass;
- far screw: knot34k on a half turn about an axis 52 units away, passing the other knot at
  about 1.5 R;
- poles: UV spheres (1,024 triangles per pole fan) meeting pole to pole;
- scale: knot34k on 16 ordinary interp passes (the issue's yardstick is knot34k's median).

A second table takes the class to a robot ("robot wrists in narrow shelves"): the
MotionBenchMaker UR5 (vamp-planner's URDF, SRDF and meshes, downloaded once by
`robot_mbm.vamp_resources`) turns its last joint by 179 degrees while a shelf board stands
0.15 mm beside its force-torque sensor (a 43K-triangle cylinder about that joint's axis; the
board ends 4 mm short of the gripper along the axis). Rows: the wrist alone (the rigid query's
rotation certificates); the wrist with `wrist_1_joint` moving 0.0001, 0.001 or 0.01 rad too
(the turning axis then moves: the frozen checks of `robot/query/frozen.rs`, where the drift
allows); the wrist alone with the board 5 cm away. tocsin's `Robot.time_of_contact` and
`Robot.path_is_free` (self-collision included) beside Pinocchio + coal `computeCollisions` at
101 states (a 1% resolution, FCL's naive solver's 100 samples), on the same triangles and pairs
(`robot_mbm.Pinocchio`).

A third table (tocsin only) spins a shaft one and a half turns on a lever that swings 1e-5 or
1e-4 rad, its bore an obstacle that drifts across the clearance (a URDF written here): a plain
shaft 1.05 tolerances clear, and a keyed one past a bump of the bore 1.15 tolerances away.

Each library runs a loop over a case's queries (one query, or the 16 passes), the loops taking
turns for `--repeats` rounds (`_common.sweeps`; a loop whose first round had a call over 20 ms
is timed once); a case's time is the median over its queries of their rounds' medians.

Usage: python bench/compare_fcl_pathological.py [--repeats N] [--out FILE]
"""

import argparse
import os
import statistics
import tempfile

import numpy as np

import tocsin
from _common import fcl_model, machine_line, pose, rotation, sweeps, write
from compare_fcl_ccd import KINDS, fcl_call, make_motion, tf

import fcl


def revolved(radius, length, n_around=256, n_along=8):
    """A surface of revolution about z (open ends), its radius `radius(angle, z)` (numpy)."""
    a = np.linspace(0, 2 * np.pi, n_around, endpoint=False)
    z = np.linspace(-length / 2, length / 2, n_along + 1)
    za, aa = np.meshgrid(z, a, indexing="ij")
    r = np.broadcast_to(radius(aa, za), aa.shape)
    v = np.stack([r * np.cos(aa), r * np.sin(aa), za], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_along), np.arange(n_around), indexing="ij")
    p, q = i * n_around + j, i * n_around + (j + 1) % n_around
    f = np.stack([np.stack([p, q, q + n_around], -1), np.stack([p, q + n_around, p + n_around], -1)], -2)
    return tocsin.Mesh(v, f.reshape(-1, 3))


def tube(r, length, n_around=256, n_along=8):
    return revolved(lambda a, z: np.full_like(a, r), length, n_around, n_along)


def thread(c, pitch=0.5, depth=0.1):
    return lambda a, z: 1.0 + c + depth * np.sin(2 * np.pi * z / pitch - a)


def turn(axis, degrees, t=(0, 0, 0)):
    return pose(rotation(axis, np.radians(degrees)), t)


def cases():
    still = np.eye(4)
    ball, socket = tocsin.Mesh.sphere(1.0, 64, 128), tocsin.Mesh.sphere(1.003, 64, 128)
    yield "ball in socket", ball, socket, "screw", [(np.eye(4), turn((0.3, 0.2, 1.0), 90))], still
    yield "shaft in bore", tube(1.0, 4.0), tube(1.004, 6.0), "screw", [(np.eye(4), turn((0, 0, 1), 180))], still
    # The same fit with 128 sides: the shaft's corners pass the bore's flat faces at 0.0037,
    # 1.65 tolerances (the 256-sided one's 0.0039 are 1.75).
    yield (
        "shaft in bore, 128 sides",
        tube(1.0, 4.0, 128),
        tube(1.004, 6.0, 128),
        "screw",
        [(np.eye(4), turn((0, 0, 1), 180))],
        still,
    )
    # A shaft tapering from radius 1 to 0.5 over its length 2 in a bore of the same taper
    # 0.004 wider, turning half a turn.
    yield (
        "tapered shaft in bore",
        revolved(lambda a, z: 0.75 - 0.25 * z + 0 * a, 2.0),
        revolved(lambda a, z: 0.754 - 0.25 * z + 0 * a, 2.0),
        "screw",
        [(np.eye(4), turn((0, 0, 1), 180))],
        still,
    )
    # A 32-sided shaft turning half a turn in a bore whose faces clear its corners by 0.84
    # tolerances (either answer allowed: the certificates prove it never within half the
    # tolerance) and by 0.3 (a contact: the corners come onto the faces as it turns).
    tol = 1e-3 * np.hypot(1.0, 2.0)  # the default: 1e-3 of the shaft's bounding radius
    for c in (0.84, 0.3):
        yield (
            f"shaft in bore, 32 sides, corners {c:g} tolerances from the faces",
            tube(1.0, 4.0, 32, 4),
            tube((1.0 + c * tol) / np.cos(np.pi / 32), 6.0, 32, 4),
            "screw",
            [(np.eye(4), turn((0, 0, 1), 180))],
            still,
        )
    # A 32-sided barrel whose faces widen along their length (radius 0.05 (1 + 0.03 sin 10z))
    # turning 170 degrees beside a long triangle whose edge, slanted 0.4 rad, passes its
    # corners tangentially 1.04 tolerances away at height 0.08 (the triangles' ranges over
    # their whole length never certified it; a robot's spinning barrel crawled to the cap).
    radius = lambda a, z: 0.05 * (1 + 0.03 * np.sin(10 * z)) + 0 * a
    barrel = revolved(radius, 0.2, 32, 4)
    tol = 1e-3 * barrel.bounding_radius  # the default: the smaller mesh's
    corner = radius(0, 0.05) + 0.6 * (radius(0, 0.1) - radius(0, 0.05))  # at 0.08, between rows
    phi, slant = 0.3, 0.4
    radial = np.array([np.cos(phi), np.sin(phi), 0.0])
    centre = radial * (corner + 1.04 * tol) + [0, 0, 0.08]
    along = np.array([-np.sin(phi), np.cos(phi), 0.0]) * np.cos(slant) + [0, 0, np.sin(slant)]
    edge = tocsin.Mesh(np.array([centre - 0.3 * along, centre + 0.3 * along, radial * 0.4 + [0, 0, 0.18]]), np.array([[0, 1, 2]]))
    yield "barrel past a tangent edge 1.04 tolerances away", barrel, edge, "screw", [(np.eye(4), turn((0, 0, 1), 170))], still
    # A bolt (sinusoidal thread: pitch 0.5, depth 0.1) screwed 170 degrees along its thread
    # into a nut 0.01 wider (not 180: a half turn's sense, and so the thread's hand, would be
    # rounding's choice).
    yield (
        "bolt screwed into nut",
        revolved(thread(0.0), 3.0, 256, 192),
        revolved(thread(0.01), 1.0, 256, 64),
        "screw",
        [(np.eye(4), turn((0, 0, 1), 170, (0, 0, 0.5 * 170 / 360)))],
        still,
    )
    slivers = tocsin.Mesh.torus_knot(30, 600)
    s, e = np.eye(4), turn((1, 1, 0), 60)
    s[:3, 3], e[:3, 3] = [-14, 1, 0.5], [14, -0.5, 0]
    yield "knot of slivers", slivers, slivers, "interp", [(s, e)], still
    knot = tocsin.Mesh.torus_knot(680, 25)
    centre = np.array([0.0, 52.0, 0.0])
    s = pose(np.eye(3), centre + [-40, 0, 0])
    r = rotation((0, 0, 1), np.pi)
    e = pose(r, centre + r @ (s[:3, 3] - centre))
    yield "knot34k, far screw", knot, knot, "screw", [(s, e)], still
    uv = tocsin.Mesh.sphere(1.0, 32, 1024)
    yield "UV spheres pole to pole", uv, uv, "translation", [(pose(np.eye(3), [0, 0, -3]), pose(np.eye(3), [0, 0, 3]))], still
    rng = np.random.default_rng(7)
    passes = []
    for _ in range(16):
        # The pass (75 degrees about (0, 0.3, 1), from (-14, 1, 0.5) to (14, -0.5, 0)),
        # its axis, angle and offsets varied.
        axis = np.array([0.0, 0.3, 1.0]) + rng.uniform(-0.3, 0.3, 3)
        s, e = np.eye(4), turn(axis, rng.uniform(45, 105), (14, -0.5, 0) + rng.uniform(-1, 1, 3))
        s[:3, 3] = np.array([-14, 1, 0.5]) + rng.uniform(-1, 1, 3)
        passes.append((s, e))
    yield "knot34k, 16 ordinary passes (scale)", knot, knot, "interp", passes, still


WRIST_Q0 = np.array([0.0, -1.2, 1.5, -1.9, -1.57, 0.0])


def wrist_cases():
    """(name, robot, q0, q1, tocsin scene, MotionBenchMaker-style scene dict) for the robot
    table (module docs)."""
    from robot_mbm import vamp_resources

    res = vamp_resources() / "ur5"
    robot = tocsin.Robot.from_urdf(res / "ur5.urdf", srdf=res / "ur5.srdf")
    names = robot.object_names
    fts = robot.object_poses(WRIST_Q0)[names.index("fts_robotside")]
    v = robot.object_mesh("fts_robotside").vertices
    rho = np.hypot(v[:, 0], v[:, 2]).max()  # the sensor's axis is its frame's y

    def board(gap):
        half = np.array([0.01, 0.015, 0.1])
        at = fts.copy()
        at[:3, 3] = fts[:3, :3] @ np.array([rho + gap + half[0], 0.095, 0.0]) + fts[:3, 3]
        scene = tocsin.Scene()
        scene.add("board", tocsin.Mesh.box(half), at)
        w, x, y, z = quaternion(at[:3, :3])
        mbm = {
            "world": {
                "collision_objects": [
                    {
                        "id": "board",
                        "primitives": [{"type": "box", "dimensions": list(2 * half)}],
                        "primitive_poses": [{"position": list(at[:3, 3]), "orientation": [x, y, z, w]}],
                    }
                ]
            }
        }
        return scene, mbm

    turn = WRIST_Q0.copy()
    turn[5] += np.radians(179)
    yield "UR5 wrist turning 179 deg, board 0.15 mm away", robot, res, turn, *board(1.5e-4)
    for drift in (1e-4, 1e-3, 1e-2):
        both = turn.copy()
        both[3] += drift
        yield f"the same, wrist_1 moving {drift:g} rad too", robot, res, both, *board(1.5e-4)
    yield "UR5 wrist turning 179 deg, board 5 cm away", robot, res, turn, *board(0.05)


LEVER_URDF = """<robot name="lever">
  <link name="base"/>
  <link name="lever"/>
  <link name="shaft"><collision><geometry><mesh filename="{mesh}"/></geometry></collision></link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="lever"/>
    <origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="spin" type="continuous"><parent link="lever"/><child link="shaft"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/></joint>
</robot>"""

LEVER_TOL = 2e-5


def write_obj(path, mesh):
    v, f = mesh.vertices, mesh.triangles
    with open(path, "w") as out:
        out.writelines(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in v)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in f)


def lever_cases(tmp):
    """(name, robot, q1, scene): a shaft (radius 0.05, 64 sides) spun one and a half turns
    backwards by the last joint of a lever that swings a little about the base (its bore, an
    obstacle, drifts across the clearance): plain in a bore 1.05 tolerances (20 um) clear of its
    corners, and keyed (radius 0.06 over its upper part, 0.3 rad wide) past a bump of the
    bore's groove (0.4 rad wide) 1.15 tolerances away. Both are clear."""
    r, n = 0.05, 64
    half = np.pi / n
    for keyed in (False, True):
        key = (lambda a, z: np.where((z >= 0.05) & (a < 0.3), r + 0.01, r)) if keyed else (lambda a, z: np.full_like(a, r))
        shaft = revolved(key, 0.2, n, 8)
        path = os.path.join(tmp, f"shaft{int(keyed)}.obj")
        write_obj(path, shaft)
        robot = tocsin.Robot.from_urdf_string(LEVER_URDF.format(mesh=path))
        if keyed:
            bump = (r + 0.01 + 1.15 * LEVER_TOL) / np.cos(half)
            bore = revolved(
                lambda a, z: np.where(z <= 0.0, r * 1.005 / np.cos(half), np.where(np.abs(a - 2.1) < 0.2, bump, 0.07)),
                0.3,
                n,
                12,
            )
            what = "keyed shaft past a bump 1.15 tolerances away"
        else:
            bore = tube((r + 1.05 * LEVER_TOL) / np.cos(half), 0.3, n, 12)
            what = "shaft in a bore 1.05 tolerances clear"
        scene = tocsin.Scene()
        scene.add("bore", bore, pose(np.eye(3), [0.3, 0.0, 0.0]))
        for swing in (1e-5, 1e-4):
            yield f"{what}, lever swinging {swing:g} rad", robot, np.array([swing, -3 * np.pi]), scene


def lever_rows(repeats):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, robot, q1, scene in lever_cases(tmp):
            q0 = np.zeros(2)

            def answer(call):
                try:
                    return call(q0, q1, scene, tolerance=LEVER_TOL)
                except tocsin.TocsinError as e:  # the session before this table's: the cap
                    return type(e).__name__

            times, answers = sweeps(
                {
                    "toc": [lambda: answer(robot.time_of_contact)],
                    "free": [lambda: answer(robot.path_is_free)],
                },
                rounds=repeats,
            )
            toc = answers["toc"][0]
            what = "free" if toc is None else toc if isinstance(toc, str) else f"t = {toc.time:.6f}"
            rows.append((name, times["toc"][0], times["free"][0], what, answers["free"][0]))
            print(rows[-1], flush=True)
    return rows


def quaternion(r):
    """(w, x, y, z) of a rotation matrix (its trace is above -1 for the boards here)."""
    w = np.sqrt(max(1.0 + np.trace(r), 1e-300)) / 2
    return w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)


def wrist_rows(repeats):
    from robot_mbm import Pinocchio

    rows = []
    for name, robot, res, q1, scene, mbm in wrist_cases():
        pin = Pinocchio(res / "ur5.urdf", robot)
        geom = pin.scene(mbm)
        states = [WRIST_Q0 + (q1 - WRIST_Q0) * k / 100 for k in range(101)]

        def sampled():
            return not any(pin.in_collision(geom, q) for q in states)

        times, answers = sweeps(
            {
                "toc": [lambda: robot.time_of_contact(WRIST_Q0, q1, scene)],
                "free": [lambda: robot.path_is_free(WRIST_Q0, q1, scene)],
                "pin": [sampled],
            },
            rounds=repeats,
        )
        toc = answers["toc"][0]
        rows.append(
            (
                name,
                times["toc"][0],
                times["free"][0],
                times["pin"][0],
                "free" if toc is None else f"t = {toc.time:.6f} ({toc.object1}, {toc.object2})",
                answers["free"][0],
                answers["pin"][0],
            )
        )
        print(rows[-1], flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="bench/out/pathological.md")
    args = ap.parse_args()
    rows = []
    for name, m1, m2, kind, motions, still in cases():
        stay = tocsin.Motion.stationary(still)
        fm, o2 = fcl_model(m1), fcl.CollisionObject(fcl_model(m2), tf(still))
        req = fcl.ContinuousCollisionRequest(num_max_iterations=100, ccd_motion_type=KINDS[kind], ccd_solver_type=fcl.CCDSolverType.CCDC_NAIVE)
        times, answers = sweeps(
            {
                "tocsin": [
                    lambda m=make_motion(kind, start, end)[0]: tocsin.time_of_contact(m1, m, m2, stay)
                    for start, end in motions
                ],
                "fcl": [fcl_call(fm, o2, req, start, end) for start, end in motions],
            },
            rounds=args.repeats,
        )
        a, b = (statistics.median(times[k]) for k in ("tocsin", "fcl"))
        if len(motions) == 1:
            c, theirs_t = answers["tocsin"][0], answers["fcl"][0]
            what = "none" if c is None else f"t = {c.time:.6f}, {c.iterations} iterations"
            theirs_what = "none" if theirs_t is None else f"t = {theirs_t:.3f}"
        else:
            hits = [c for c in answers["tocsin"] if c is not None]
            what = f"{len(hits)} contacts, median {statistics.median(c.iterations for c in hits):.0f} iterations"
            theirs_what = f"{sum(t is not None for t in answers['fcl'])} contacts"
        rows.append((name, f"{m1.num_triangles} + {m2.num_triangles}", a, b, what, theirs_what))
        print(rows[-1], flush=True)
    lines = [
        f"{machine_line()}, python-fcl {getattr(fcl, '__version__', '?')}; each library a loop over a case's "
        f"queries, the loops taking turns, {args.repeats} rounds (one for a loop with a call over 20 ms); "
        "objects built outside the timer.",
        "",
        "| case | triangles | tocsin (ms) | fcl naive 100 (ms) | tocsin's answer | fcl's answer |",
        "|---|---:|---:|---:|---|---|",
    ]
    for name, n, a, b, what, theirs in rows:
        lines.append(f"| {name} | {n} | {a * 1e3:.2f} | {b * 1e3:.2f} | {what} | {theirs} |")
    lines += [
        "",
        "| robot case | tocsin time_of_contact (ms) | tocsin path_is_free (ms) | pin+coal 101 states (ms) "
        "| tocsin's answer | path_is_free | sampler: free |",
        "|---|---:|---:|---:|---|---|---|",
    ]
    for name, a, b, c, what, free, theirs in wrist_rows(args.repeats):
        lines.append(f"| {name} | {a * 1e3:.2f} | {b * 1e3:.2f} | {c * 1e3:.2f} | {what} | {free} | {theirs} |")
    lines += [
        "",
        f"| lever robot case (tolerance {LEVER_TOL:g}) | tocsin time_of_contact (ms) | tocsin path_is_free (ms) "
        "| tocsin's answer | path_is_free |",
        "|---|---:|---:|---|---|",
    ]
    for name, a, b, what, free in lever_rows(args.repeats):
        lines.append(f"| {name} | {a * 1e3:.2f} | {b * 1e3:.2f} | {what} | {free} |")
    write(args.out, "\n".join(lines))


if __name__ == "__main__":
    main()
