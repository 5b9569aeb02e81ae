"""example-robot-data's robots beside Pinocchio + coal: which URDFs load, whether the COLLADA
meshes read the same, and whether self-collision verdicts agree.

The example-robot-data wheel (the pip package, 39 robots, 69 URDFs, 286 COLLADA files) is
downloaded once with `pip download` into ~/.cache/tocsin-bench and unzipped; nothing is
built. Three parts:

1. Every `.dae` file, read by tocsin (`Mesh.load`), by coal (`MeshLoader`, assimp) and by
   trimesh (pycollada): the largest distance from a vertex of one to the nearest vertex of the
   other, relative to the mesh's size (both read `f32`), the triangle counts, and whether
   tocsin's extra triangles are exactly those with a repeated corner (assimp drops them;
   tocsin keeps a soup as written), and trimesh's area against tocsin's.
2. Every URDF loaded by tocsin (with the SRDF of the same name where the package has one).
3. Every URDF both load: `--configs` random configurations within the limits (seeded;
   continuous joints in [-pi, pi]), checked for self-collision by tocsin (`in_collision`) and
   by Pinocchio + coal (`computeCollisions`) on the same pairs (tocsin's `self_pairs`: each
   link's collision elements against the other link's), the two loops taking turns, each call
   made as a planner's loop would make it. Mimic joints follow their source in both. A
   verdict that differs is reported with coal's smallest distance over the pairs: tocsin's
   primitives are tessellations that contain the true shapes (up to 2% of a sphere's radius
   larger), so tocsin may see a contact coal does not within that margin; the other way round
   would be a miss.

    python bench/example_robot_data.py [--configs 200] [--out FILE]
"""

import argparse
import glob
import math
import os
import pathlib
import subprocess
import sys
import time
import warnings
import xml.etree.ElementTree as ET
import zipfile

import numpy as np

import tocsin
from _common import machine_line

CACHE = pathlib.Path(os.environ.get("TOCSIN_BENCH_CACHE", pathlib.Path.home() / ".cache" / "tocsin-bench"))
VERSION = "6.0.0"


def robots_root():
    root = CACHE / f"example_robot_data-{VERSION}"
    robots = root / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
    if not robots.exists():
        CACHE.mkdir(parents=True, exist_ok=True)
        subprocess.run(
            [sys.executable, "-m", "pip", "download", "-q", "--no-deps", "-d", str(CACHE),
             f"example-robot-data=={VERSION}"],
            check=True,
        )
        wheel = next(CACHE.glob(f"example_robot_data-{VERSION}-*.whl"))
        with zipfile.ZipFile(wheel) as z:
            z.extractall(root)
    return robots


def meshes(robots, out):
    import coal
    import trimesh
    from scipy.spatial import cKDTree

    files = sorted(glob.glob(str(robots / "**" / "*.dae"), recursive=True)
                   + glob.glob(str(robots / "**" / "*.DAE"), recursive=True))
    rows = []
    for f in files:
        m = tocsin.Mesh.load(f)
        v, t = np.asarray(m.vertices), np.asarray(m.triangles)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = coal.MeshLoader().load(f, np.ones(3))
        cv = np.array([c.vertices(i) for i in range(c.num_vertices)])
        size = max(np.abs(cv).max(), np.abs(v).max())
        gap = max(cKDTree(cv).query(v)[0].max(), cKDTree(v).query(cv)[0].max()) / size
        repeated = int(((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 0] == t[:, 2])).sum())
        area = np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1).sum() / 2
        s = trimesh.load(f, force="mesh")
        rows.append((os.path.relpath(f, robots), gap, len(t), c.num_tris, repeated, area, s.area, len(s.faces)))
    worst = max(r[1] for r in rows)
    differ = [r for r in rows if r[2] != r[3]]
    explained = [r for r in differ if r[2] - r[3] == r[4]]
    same = [r for r in rows if r[2] == r[7]]
    area_err = max(abs(r[5] - r[6]) / r[5] for r in same)
    faces_same = len(same)
    print(f"\n### COLLADA files: tocsin beside coal and trimesh\n", file=out)
    print(f"{len(rows)} files. Largest vertex distance to coal's nearest vertex, relative to the mesh's size: "
          f"{worst:.1e}. Triangle counts equal to coal's in {len(rows) - len(differ)} files; in the "
          f"{len(differ)} others tocsin's extra triangles are exactly its repeated-corner ones in "
          f"{len(explained)}. Face count equal to trimesh's in {faces_same} files, whose largest "
          f"relative area difference to trimesh is {area_err:.1e}; the others:", file=out)
    for r in rows:
        if r[2] != r[7]:
            print(f"- {r[0]}: tocsin {r[2]} triangles, area {r[5]:.6g}; trimesh {r[7]}, {r[6]:.6g}", file=out)
    print("\nLargest vertex distances to coal's:", file=out)
    for r in sorted(rows, key=lambda r: -r[1])[:5]:
        print(f"- {r[0]}: {r[1]:.1e}, {r[2]} / {r[3]} triangles", file=out)
    return rows


def srdf_for(urdf):
    stem = pathlib.Path(urdf).stem
    for d in (pathlib.Path(urdf).parent.parent / "srdf",):
        p = d / f"{stem}.srdf"
        if p.exists():
            return p
    return None


def mimics(urdf):
    """{mimic joint: (source, multiplier, offset)} from the URDF text."""
    out = {}
    for j in ET.parse(urdf).getroot().iter("joint"):
        m = j.find("mimic")
        if m is not None:
            out[j.get("name")] = (m.get("joint"), float(m.get("multiplier", 1)), float(m.get("offset", 0)))
    return out


class PinRobot:
    def __init__(self, urdf, robots, pairs):
        import pinocchio as pin

        self.pin = pin
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.model, self.cmodel = pin.buildModelsFromUrdf(
                str(urdf), package_dirs=[str(robots.parent.parent)],
                geometry_types=[pin.GeometryType.COLLISION])
        frame_link = lambda g: self.model.frames[g.parentFrame].name
        by_link = {}
        for k, g in enumerate(self.cmodel.geometryObjects):
            by_link.setdefault(frame_link(g), []).append(k)
        for a, b in pairs:
            for i in by_link.get(a, []):
                for j in by_link.get(b, []):
                    self.cmodel.addCollisionPair(pin.CollisionPair(min(i, j), max(i, j)))
        self.data = self.model.createData()
        self.cdata = pin.GeometryData(self.cmodel)

    def q(self, names, values, mimic):
        """Pinocchio's configuration for tocsin's joint values (mimics from their sources)."""
        value = dict(zip(names, values))
        for m, (src, mul, off) in mimic.items():
            if src in value:
                value[m] = mul * value[src] + off
        q = self.pin.neutral(self.model)
        for j, name in zip(self.model.joints[1:], self.model.names[1:]):
            x = value.get(name, 0.0)
            if j.nq == 2:  # continuous: (cos, sin)
                q[j.idx_q : j.idx_q + 2] = [math.cos(x), math.sin(x)]
            elif j.nq == 1:
                q[j.idx_q] = x
        return q

    def collides(self, q):
        return self.pin.computeCollisions(self.model, self.data, self.cmodel, self.cdata, q, True)

    def closest(self, q):
        """coal's closest pair at q: a description and its distance."""
        self.pin.computeDistances(self.model, self.data, self.cmodel, self.cdata, q)
        results = self.cdata.distanceResults
        if len(results) == 0:
            return "no pairs", math.inf
        k = min(range(len(results)), key=lambda i: results[i].min_distance)
        pair = self.cmodel.collisionPairs[k]
        a, b = (self.cmodel.geometryObjects[i] for i in (pair.first, pair.second))
        kind = lambda g: type(g.geometry).__name__.replace("BVHModelOBBRSS", "mesh")
        return f"{a.name} ({kind(a)}) - {b.name} ({kind(b)})", results[k].min_distance


def robots_table(robots, configs, out):
    urdfs = sorted(glob.glob(str(robots / "**" / "*.urdf"), recursive=True))
    print("\n### URDFs: loaded, and self-collision verdicts beside Pinocchio + coal\n", file=out)
    print("| URDF | dof | links | pairs | loads (ms) | colliding (tocsin / coal) | "
          "verdicts that differ (coal's closest pair there) | tocsin config (us) | pin+coal config (us) |",
          file=out)
    print("|---|---:|---:|---:|---:|---:|---|---:|---:|", file=out)
    failed = []
    for u in urdfs:
        name = os.path.relpath(u, robots)
        srdf = srdf_for(u)
        try:
            t0 = time.perf_counter()
            r = tocsin.Robot.from_urdf(
                u, package_dirs=[str(robots.parent.parent)], srdf=str(srdf) if srdf else None)
            load_ms = (time.perf_counter() - t0) * 1e3
        except tocsin.TocsinError as e:
            failed.append((name, "tocsin", f"{type(e).__name__}: {e}"))
            continue
        pairs = [tuple(p) for p in r.self_pairs]
        try:
            p = PinRobot(u, robots, pairs)
        except Exception as e:  # noqa: BLE001 - any failure of the other library is reported
            failed.append((name, "pinocchio", f"{type(e).__name__}: {str(e)[:160]}"))
            continue
        lim = r.joint_limits
        # Continuous joints in [-pi, pi]; limits past 1e3 (iris's rotors) clipped.
        lo = np.maximum(np.where(np.isfinite(lim[:, 0]), lim[:, 0], -math.pi), -1e3)
        hi = np.minimum(np.where(np.isfinite(lim[:, 1]), lim[:, 1], math.pi), 1e3)
        rng = np.random.default_rng(0)
        qs = rng.uniform(lo, hi, size=(configs, r.dof))
        mimic = mimics(u)
        pqs = [p.q(r.joint_names, q, mimic) for q in qs]
        # Two rounds, each checker a loop over the configurations, the order turning.
        ours, theirs, t_ours, t_theirs = [], [], [], []
        for order in (("tocsin", "coal"), ("coal", "tocsin")):
            for who in order:
                t0 = time.perf_counter()
                if who == "tocsin":
                    ours = [r.in_collision(q) for q in qs]
                    t_ours.append((time.perf_counter() - t0) / configs)
                else:
                    theirs = [p.collides(q) for q in pqs]
                    t_theirs.append((time.perf_counter() - t0) / configs)
        differ = [(k, ours[k], theirs[k]) for k in range(configs) if ours[k] != theirs[k]]
        notes = ", ".join(
            "{} only; coal's closest pair {} at {:.1e} m".format('tocsin' if a else 'coal', *p.closest(pqs[k]))
            for k, a, b in differ[:4])
        if len(differ) > 4:
            notes += ", ..."
        print(f"| {name} | {r.dof} | {len(r.link_names)} | {len(pairs)} | {load_ms:.0f} | "
              f"{sum(ours)} / {sum(theirs)} | {len(differ)}{' (' + notes + ')' if differ else ''} | "
              f"{min(t_ours) * 1e6:.1f} | {min(t_theirs) * 1e6:.1f} |", file=out, flush=True)
    print(f"\n{len(urdfs)} URDFs; not compared:", file=out)
    for n, who, why in failed:
        print(f"- {n} ({who}): {why[:200]}", file=out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--configs", type=int, default=200)
    ap.add_argument("--out", type=argparse.FileType("w"), default=sys.stdout)
    args = ap.parse_args()
    robots = robots_root()
    print(machine_line(), file=args.out)
    meshes(robots, args.out)
    robots_table(robots, args.configs, args.out)


if __name__ == "__main__":
    main()
