"""The `tocsin rain` scene in tocsin, pybullet (CCD on) and MuJoCo: how many bodies pass through
a 1 mm plate, and the time per step.

Rods (0.2 x 0.016 x 0.016 m) and cubes (5 cm) are thrown down at 10.5 to 15 m/s, spinning at
5 to 25 rad/s, through a rack of tilted 1 mm plates into a bin of 1 mm plates
(`tocsin rain --scene` prints the scene; this script builds the same boxes in the other
engines). Every engine is checked the same way: the straight path of each body's centre over
each of the engine's own steps must not pass through any plate's rectangle; a body that does is
counted as tunnelled once. Meshes, not primitives: each plate and body is the same 8-vertex box
mesh in every engine (pybullet: GEOM_MESH, the plates as static triangle meshes, the bodies as
convex hulls; MuJoCo: mesh geoms, which it collides as convex hulls).

pybullet's CCD is switched on as its documentation says: `changeDynamics(body, -1,
ccdSweptSphereRadius=r)` with `r` the body's inscribed radius (its smallest half extent), and
`contactProcessingThreshold=0`. MuJoCo has no continuous collision detection; it runs at the
scene's 1/60 s step and at 2 ms (its default timestep), which is 8.3 times more steps.

Run: `python bench/tunnelling.py [--bodies 40] [--steps 120] [--seeds 1 2 3]`
(needs `pip install pybullet mujoco` and a built `tocsin` command: `cargo build --release`).
"""

import argparse
import json
import platform
import subprocess
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
TOCSIN = ROOT / "target" / "release" / "tocsin"

def box_mesh(half):
    """The box tocsin simulates (`tocsin.Mesh.box`): 8 vertices, 12 outward-wound triangles."""
    import tocsin

    m = tocsin.Mesh.box(list(half))
    return m.vertices.tolist(), m.triangles.tolist()


def quat_xyzw(rot):
    """Rotation matrix to quaternion (x, y, z, w)."""
    m = np.asarray(rot)
    t = np.trace(m)
    if t > 0:
        s = 2.0 * np.sqrt(t + 1.0)
        return [(m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s]
    i = int(np.argmax(np.diag(m)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
    q = [0.0, 0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (m[j, i] + m[i, j]) / s
    q[k] = (m[k, i] + m[i, k]) / s
    q[3] = (m[k, j] - m[j, k]) / s
    return q


class Crossings:
    """The same check as `tocsin rain`: a body's centre path through a plate's rectangle."""

    def __init__(self, plates, n):
        self.plates = [(np.asarray(p["pose"]), np.asarray(p["half_extents"])) for p in plates]
        self.crossed = np.zeros(n, dtype=bool)
        self.count = 0

    def check(self, before, after):
        for pose, half in self.plates:
            r, c = pose[:3, :3], pose[:3, 3]
            a = (before - c) @ r
            b = (after - c) @ r
            hit = a[:, 2] * b[:, 2] < 0
            if not hit.any():
                continue
            s = a[:, 2] / np.where(hit, a[:, 2] - b[:, 2], 1.0)
            q = a + (b - a) * s[:, None]
            inside = hit & (np.abs(q[:, 0]) <= half[0]) & (np.abs(q[:, 1]) <= half[1])
            self.count += int(inside.sum())
            self.crossed |= inside


def in_bin(x):
    return int(((x[:, 2] > 0) & (x[:, 2] < 0.6) & (np.abs(x[:, 0]) < 0.6) & (np.abs(x[:, 1]) < 0.6)).sum())


def run_pybullet(scene, steps, substeps):
    import pybullet as p

    cid = p.connect(p.DIRECT)
    dt = scene["dt"] / substeps
    p.setGravity(0, 0, -scene["gravity"], physicsClientId=cid)
    p.setTimeStep(dt, physicsClientId=cid)
    for plate in scene["plates"]:
        pose = np.asarray(plate["pose"])
        verts, faces = box_mesh(plate["half_extents"])
        shape = p.createCollisionShape(
            p.GEOM_MESH, vertices=verts, indices=[i for f in faces for i in f], physicsClientId=cid
        )
        uid = p.createMultiBody(0, shape, -1, pose[:3, 3].tolist(), quat_xyzw(pose[:3, :3]), physicsClientId=cid)
        p.changeDynamics(uid, -1, restitution=scene["restitution"], lateralFriction=scene["friction"], physicsClientId=cid)
    ids = []
    for body in scene["bodies"]:
        pose = np.asarray(body["pose"])
        shape = p.createCollisionShape(p.GEOM_MESH, vertices=box_mesh(body["half_extents"])[0], physicsClientId=cid)
        uid = p.createMultiBody(body["mass"], shape, -1, pose[:3, 3].tolist(), quat_xyzw(pose[:3, :3]), physicsClientId=cid)
        p.resetBaseVelocity(uid, body["velocity"], body["angular_velocity"], physicsClientId=cid)
        p.changeDynamics(
            uid,
            -1,
            restitution=scene["restitution"],
            lateralFriction=scene["friction"],
            ccdSweptSphereRadius=min(body["half_extents"]),
            contactProcessingThreshold=0.0,
            physicsClientId=cid,
        )
        ids.append(uid)

    def centres():
        return np.array([p.getBasePositionAndOrientation(u, physicsClientId=cid)[0] for u in ids])

    check = Crossings(scene["plates"], len(ids))
    times = []
    x = centres()
    for _ in range(steps * substeps):
        t0 = time.perf_counter()
        p.stepSimulation(physicsClientId=cid)
        times.append(time.perf_counter() - t0)
        y = centres()
        check.check(x, y)
        x = y
    p.disconnect(cid)
    per_frame = np.add.reduceat(np.array(times), np.arange(0, len(times), substeps)) * 1e3
    return check, in_bin(x), per_frame


def run_mujoco(scene, steps, timestep):
    import mujoco

    def placed(name, item):
        """The box mesh asset `name` and the MJCF position and orientation of `item`."""
        pose = np.asarray(item["pose"])
        verts, faces = box_mesh(item["half_extents"])
        v = " ".join(f"{c:.17g}" for c in np.ravel(verts))
        f = " ".join(str(i) for i in np.ravel(faces))
        assets.append(f'<mesh name="{name}" vertex="{v}" face="{f}"/>')
        q = quat_xyzw(pose[:3, :3])
        return f'pos="{" ".join(map(str, pose[:3, 3]))}" quat="{q[3]} {q[0]} {q[1]} {q[2]}"'

    friction = f'friction="{scene["friction"]} 0.005 0.0001"'
    assets, geoms, bodies = [], [], []
    for k, plate in enumerate(scene["plates"]):
        where = placed(f"plate{k}", plate)
        geoms.append(f'<geom type="mesh" mesh="plate{k}" {where} {friction}/>')
    for k, body in enumerate(scene["bodies"]):
        where = placed(f"body{k}", body)
        bodies.append(
            f'<body name="b{k}" {where}><freejoint/><geom type="mesh" mesh="body{k}" '
            f'density="{scene["density"]}" {friction}/></body>'
        )
    xml = (
        f'<mujoco><option timestep="{timestep}" gravity="0 0 {-scene["gravity"]}"/>'
        f"<asset>{''.join(assets)}</asset><worldbody>{''.join(geoms)}{''.join(bodies)}</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    for k, body in enumerate(scene["bodies"]):
        rot = np.asarray(body["pose"])[:3, :3]
        data.qvel[6 * k : 6 * k + 3] = body["velocity"]
        # A free joint's angular velocity is in the body frame.
        data.qvel[6 * k + 3 : 6 * k + 6] = rot.T @ np.asarray(body["angular_velocity"])
    mujoco.mj_forward(model, data)
    n = len(scene["bodies"])
    body_ids = [model.body(f"b{k}").id for k in range(n)]
    substeps = max(1, round(scene["dt"] / timestep))
    check = Crossings(scene["plates"], n)
    times = []
    x = data.xpos[body_ids].copy()
    for _ in range(steps * substeps):
        t0 = time.perf_counter()
        mujoco.mj_step(model, data)
        times.append(time.perf_counter() - t0)
        y = data.xpos[body_ids].copy()
        check.check(x, y)
        x = y
    per_frame = np.add.reduceat(np.array(times), np.arange(0, len(times), substeps)) * 1e3
    return check, in_bin(x), per_frame


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bodies", type=int, default=40)
    ap.add_argument("--steps", type=int, default=120)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--speed", type=float, default=15.0)
    args = ap.parse_args()
    rows = []
    for seed in args.seeds:
        out = subprocess.run(
            [str(TOCSIN), "rain", "--scene", "--bodies", str(args.bodies), "--steps", str(args.steps),
             "--seed", str(seed), "--speed", str(args.speed)],
            check=True, capture_output=True, text=True,
        )
        ours = json.loads(out.stdout)
        scene = ours.pop("scene")
        ms = ours["ms_per_step"]
        rows.append((seed, "tocsin (earliest contact, exact CCD), 1/60 s", ours["tunnelled_bodies"],
                     ours["crossings"], ours["in_bin"], ms["median"], ms["mean"],
                     f"intersecting pairs {ours['intersecting_pairs']}, frozen steps {ours['frozen_steps']}, "
                     f"contacts {ours['contacts_resolved']}"))
        for substeps, label in [(1, "pybullet CCD on, 1/60 s"), (4, "pybullet CCD on, 1/240 s (its default)")]:
            check, kept, ms = run_pybullet(scene, args.steps, substeps)
            rows.append((seed, label, int(check.crossed.sum()), check.count, kept, float(np.median(ms)), float(np.mean(ms)), ""))
        for timestep, label in [(scene["dt"], "MuJoCo, 1/60 s"), (0.002, "MuJoCo, 2 ms (its default)")]:
            check, kept, ms = run_mujoco(scene, args.steps, timestep)
            rows.append((seed, label, int(check.crossed.sum()), check.count, kept, float(np.median(ms)), float(np.mean(ms)), ""))
    print(f"machine: {platform.processor() or platform.machine()}, {args.bodies} bodies, {args.steps} steps of 1/60 s, "
          f"launch speed {args.speed} m/s")
    print("| seed | engine | bodies tunnelled | plate crossings | in the bin at the end | ms per 1/60 s step (median) | (mean) | notes |")
    print("|---:|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]} | {r[5]:.2f} | {r[6]:.2f} | {r[7]} |")


if __name__ == "__main__":
    main()
