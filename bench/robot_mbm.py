"""Robot segment checks on MotionBenchMaker (Panda, UR5, Fetch), side by side in one run with
Pinocchio + coal discrete checks at OMPL's default resolution and with HPP's exact path
validation.

Problems, URDF, SRDF and meshes come from the vamp-planner source distribution on PyPI
(downloaded once into ~/.cache/tocsin-bench; read, never built). Per scenario, for the first
--problems problems: --edges random 0.5 rad edges from the start state (random unit direction in
joint space, clipped to the limits) plus the start-to-goal edge. Each edge is checked by

- tocsin ``Robot.path_is_free`` (exact, self-collision included),
- Pinocchio + coal ``computeCollisions`` at the states OMPL's DiscreteMotionValidator visits
  at its default resolution (1% of the space's extent: ``ceil(|q1 - q0| / (0.01 extent))``
  states after the start, stopping at the first collision), and
- HPP's ``Dichotomy`` continuous path validation (hpp-python; exact, tolerance 0) on the same
  geometry and pairs (``--no-hpp`` leaves it out),

and the start state and the edges' ends by both single-configuration checks. Objects are
built once, outside the timers; every call is made as a planner's loop would make it, one at a
time from Python, each checker running a scene's edges (or configurations) as one loop, the
loops taking turns (`_common.sweeps`), which one runs first turning scene by scene.
Verdicts are compared: an edge the sampler calls free and tocsin does not is checked again with
coal at 20,001 states; a collision found there makes it a confirmed miss of the sampler; HPP's
verdicts are counted where they differ from tocsin's.

    python bench/robot_mbm.py [--problems 10] [--edges 20] [--robots panda,ur5,fetch] [--no-hpp] [--out FILE]
"""

import argparse
import io
import json
import math
import os
import pathlib
import re
import statistics
import tarfile
import time
import urllib.request

import numpy as np
import yaml

import tocsin
from _common import machine_line, sweeps

CACHE = pathlib.Path(os.environ.get("TOCSIN_BENCH_CACHE", pathlib.Path.home() / ".cache" / "tocsin-bench"))
VERSION = "0.6.4"


def vamp_resources():
    root = CACHE / f"vamp_planner-{VERSION}"
    if not (root / "resources").exists():
        CACHE.mkdir(parents=True, exist_ok=True)
        # The simple index (PEP 503): package mirrors serve it where the JSON API is absent.
        page = urllib.request.urlopen("https://pypi.org/simple/vamp-planner/", timeout=60).read().decode()
        url = next(
            m.split("#")[0]
            for m in re.findall(r'href="([^"]+)"', page)
            if m.split("#")[0].endswith((f"vamp_planner-{VERSION}.tar.gz", f"vamp-planner-{VERSION}.tar.gz"))
        )
        data = urllib.request.urlopen(url, timeout=300).read()
        with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
            members = [m for m in tar.getmembers() if "/resources/" in m.name]
            tar.extractall(CACHE, members=members, filter="data")
    return root / "resources"


def problems(resources, robot, limit):
    """(scenario, scene dict, request dict) for the first `limit` problems of each scenario."""
    out = {}
    with tarfile.open(resources / robot / "problems.tar.bz2", mode="r:bz2") as tar:
        names = sorted(m.name for m in tar.getmembers() if m.name.endswith(".yaml"))
        for name in names:
            parts = pathlib.PurePosixPath(name).parts
            scenario, file = parts[-2], parts[-1]
            if not file.startswith("scene"):
                continue
            index = file[len("scene") : -len(".yaml")]
            if int(index) > limit:
                continue
            scene = yaml.safe_load(tar.extractfile(name))
            request_name = str(pathlib.PurePosixPath(name).with_name(f"request{index}.yaml"))
            request = yaml.safe_load(tar.extractfile(request_name))
            out.setdefault(scenario, []).append((scene, request))
    return out


def quat_matrix(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def obstacles(scene):
    for obj in scene["world"]["collision_objects"]:
        for prim, pose in zip(obj["primitives"], obj["primitive_poses"]):
            m = np.eye(4)
            m[:3, :3] = quat_matrix(pose["orientation"])
            m[:3, 3] = pose["position"]
            yield obj["id"], prim["type"], prim["dimensions"], m


def coal_bvh(mesh):
    """A coal BVH (OBBRSS) of a tocsin mesh's triangles."""
    import coal

    bvh = coal.BVHModelOBBRSS()
    bvh.beginModel(mesh.num_triangles, mesh.num_vertices)
    bvh.addVertices(np.ascontiguousarray(mesh.vertices))
    bvh.addTriangles(np.ascontiguousarray(mesh.triangles.astype(np.int64)))
    bvh.endModel()
    return bvh


class Tocsin:
    def __init__(self, urdf, srdf):
        self.robot = tocsin.Robot.from_urdf(urdf, srdf=srdf)

    def scene(self, scene):
        s = tocsin.Scene()
        for k, (name, kind, dims, pose) in enumerate(obstacles(scene)):
            if kind == "box":
                mesh = tocsin.Mesh.box(np.array(dims) / 2)
            elif kind == "cylinder":  # MoveIt: [height, radius]
                mesh = tocsin.Mesh.cylinder(dims[1], dims[0])
            elif kind == "sphere":
                mesh = tocsin.Mesh.sphere(dims[0], 16, 32)
            else:
                raise ValueError(kind)
            s.add(f"{name}#{k}", mesh, pose)
        return s


class Pinocchio:
    """Pinocchio's kinematics from the same URDF, and coal checks on the same triangles as
    tocsin's: assimp (Pinocchio's mesh loader) reads the MotionBenchMaker Panda's link6.obj into
    a different surface (1,177 of its 1,308 triangles differ from the file's faces), so each
    collision object's coal BVH is built from tocsin's mesh of it, attached to the joint of its
    body, and the checked pairs are tocsin's (the SRDF gives both the same 21 on the Panda)."""

    def __init__(self, urdf, robot):
        import pinocchio as pin

        self.pin = pin
        self.model = pin.buildModelFromUrdf(str(urdf))
        self.robot_geom = pin.GeometryModel()
        index = {}
        for name in robot.object_names:
            bvh = coal_bvh(robot.object_mesh(name))
            frame_id = self.model.getFrameId(name)
            joint = self.model.frames[frame_id].parentJoint
            obj = pin.GeometryObject(name, joint, frame_id, pin.SE3.Identity(), bvh)
            index[name] = self.robot_geom.addGeometryObject(obj)
        for a, b in robot.self_pairs:
            self.robot_geom.addCollisionPair(pin.CollisionPair(index[a], index[b]))
        self.data = self.model.createData()

    def scene(self, scene):
        import coal

        pin = self.pin
        geom = self.robot_geom.copy()
        n_robot = len(geom.geometryObjects)
        for k, (name, kind, dims, pose) in enumerate(obstacles(scene)):
            if kind == "box":
                shape = coal.Box(*dims)
            elif kind == "cylinder":
                shape = coal.Cylinder(dims[1], dims[0])
            elif kind == "sphere":
                shape = coal.Sphere(dims[0])
            else:
                raise ValueError(kind)
            placement = pin.SE3(pose[:3, :3], pose[:3, 3])
            obj = pin.GeometryObject(f"{name}#{k}", 0, 0, placement, shape)
            gid = geom.addGeometryObject(obj)
            for r in range(n_robot):
                geom.addCollisionPair(pin.CollisionPair(r, gid))
        return geom, pin.GeometryData(geom)

    def in_collision(self, geom, q):
        return self.pin.computeCollisions(self.model, self.data, geom[0], geom[1], q, True)


def hpp_importable():
    """Whether pyhpp (hpp-python) imports. Its bindings find their libraries only through
    LD_LIBRARY_PATH: when the import fails for that reason, the run starts again with the
    venv's cmeel prefix on it (once)."""
    try:
        import pyhpp.core  # noqa: F401

        return True
    except ImportError:
        pass
    import sys

    libs = [pathlib.Path(p) / "cmeel.prefix" / "lib" for p in sys.path]
    libs = [str(p) for p in libs if (p / "libhpp-core.so").exists()]
    if libs and "TOCSIN_BENCH_HPP_REEXEC" not in os.environ:
        os.environ["LD_LIBRARY_PATH"] = ":".join(libs + [os.environ.get("LD_LIBRARY_PATH", "")])
        os.environ["TOCSIN_BENCH_HPP_REEXEC"] = "1"
        os.execv(sys.executable, [sys.executable] + sys.argv)
    return False


class Hpp:
    """HPP's exact path validation (hpp-core's continuous validation by dichotomy: coal
    distances and a velocity bound through the chain, the CATCH idea), tolerance 0, on the same
    geometry and pairs as tocsin: the robot loads from the URDF and SRDF, then each robot
    collision object's geometry is replaced by a coal BVH of tocsin's mesh of it, placed where
    tocsin places it (found from both kinematics at the start state); the obstacles are coal
    primitives as for Pinocchio; the checked pairs are tocsin's self pairs plus every robot
    object against every obstacle. One device per scene (its obstacles are part of it)."""

    def __init__(self, urdf, srdf, robot):
        urdf = pathlib.Path(urdf)
        # The MotionBenchMaker URDFs name meshes as package://meshes/... or meshes/...: both
        # are the folder beside the URDF (HPP resolves neither against it).
        folder = str(urdf.parent / "meshes") + "/"
        self.urdf_text = (
            urdf.read_text()
            .replace('filename="package://meshes/', 'filename="' + folder)
            .replace('filename="meshes/', 'filename="' + folder)
        )
        self.srdf_text = pathlib.Path(srdf).read_text()
        self.robot = robot
        self.bvhs = {name: coal_bvh(robot.object_mesh(name)) for name in robot.object_names}

    def scene(self, scene, q_ref):
        import pinocchio as pin
        from pyhpp.core import Dichotomy, Problem
        from pyhpp.pinocchio import Device, urdf

        device = Device("robot")
        urdf.loadModelFromString(device, 0, "robot", "anchor", self.urdf_text, self.srdf_text, pin.SE3.Identity())
        links, joints = [], []
        for k, (name, kind, dims, pose) in enumerate(obstacles(scene)):
            if kind == "box":
                geometry = '<box size="{} {} {}"/>'.format(*dims)
            elif kind == "cylinder":  # MoveIt: [height, radius]
                geometry = f'<cylinder radius="{dims[1]}" length="{dims[0]}"/>'
            elif kind == "sphere":
                geometry = f'<sphere radius="{dims[0]}"/>'
            else:
                raise ValueError(kind)
            rpy = pin.rpy.matrixToRpy(pose[:3, :3])
            links.append(f'<link name="o{k}"><collision><geometry>{geometry}</geometry></collision></link>')
            joints.append(
                f'<joint name="j{k}" type="fixed"><parent link="base"/><child link="o{k}"/>'
                f'<origin xyz="{pose[0, 3]} {pose[1, 3]} {pose[2, 3]}" rpy="{rpy[0]} {rpy[1]} {rpy[2]}"/></joint>'
            )
        env = '<robot name="env"><link name="base"/>' + "".join(links + joints) + "</robot>"
        urdf.loadModelFromString(device, 0, "env", "anchor", env, "", pin.SE3.Identity())
        model, geom = device.model(), device.geomModel()
        data = model.createData()
        pin.forwardKinematics(model, data, q_ref)
        ours = dict(zip(self.robot.object_names, self.robot.object_poses(q_ref)))
        index, n_env = {}, 0
        for i, obj in enumerate(geom.geometryObjects):
            if obj.name.startswith("env/"):
                n_env += 1
                continue
            link = obj.name[len("robot/") :].rsplit("_", 1)[0]
            if link not in ours or link in index:
                raise RuntimeError(f"HPP object {obj.name} has no single tocsin object")
            obj.geometry = self.bvhs[link]
            obj.placement = data.oMi[obj.parentJoint].actInv(pin.SE3(ours[link][:3, :3], ours[link][:3, 3]))
            index[link] = i
        if set(index) != set(self.robot.object_names):
            raise RuntimeError("HPP's robot objects differ from tocsin's")
        geom.removeAllCollisionPairs()
        for a, b in self.robot.self_pairs:
            geom.addCollisionPair(pin.CollisionPair(index[a], index[b]))
        for i, obj in enumerate(geom.geometryObjects):
            if obj.name.startswith("env/"):
                for r in index.values():
                    geom.addCollisionPair(pin.CollisionPair(r, i))
        problem = Problem(device)
        # The problem and the device stay referenced: the steering method holds only a weak
        # pointer to them.
        return problem.steeringMethod(), Dichotomy(device, 0.0), problem, device

    @staticmethod
    def path_is_free(checker, q0, q1):
        steer, validation = checker[:2]
        valid, _, _ = validation.validate(steer(q0, q1), False)
        return valid


def plan(robot, q_start, q_goal, valid, motion_free, timeout):
    """RRT-Connect from q_start to q_goal with OMPL: `valid(q)` checks states, `motion_free(a, b)`
    checks edges (None: OMPL's DiscreteMotionValidator at its default resolution, 1% of the
    space's extent). Returns (seconds, waypoints or None)."""
    import ompl.base as ob
    import ompl.geometric as og

    dof = robot.dof
    space = ob.RealVectorStateSpace(dof)
    bounds = ob.RealVectorBounds(dof)
    limits = np.clip(robot.joint_limits, -np.pi, np.pi)  # continuous joints: one turn
    for i in range(dof):
        bounds.setLow(i, float(limits[i, 0]))
        bounds.setHigh(i, float(limits[i, 1]))
    space.setBounds(bounds)
    si = ob.SpaceInformation(space)
    as_q = lambda s: np.array([s[i] for i in range(dof)])
    si.setStateValidityChecker(lambda s: valid(as_q(s)))
    if motion_free is not None:

        class Exact(ob.MotionValidator):
            def checkMotion(self, a, b, *last):
                return motion_free(as_q(a), as_q(b))

        validator = Exact(si)
        si.setMotionValidator(validator)
    si.setup()
    start, goal = space.allocState(), space.allocState()
    for i in range(dof):
        start[i], goal[i] = float(q_start[i]), float(q_goal[i])
    problem = ob.ProblemDefinition(si)
    problem.setStartAndGoalStates(start, goal)
    planner = og.RRTConnect(si)
    planner.setProblemDefinition(problem)
    planner.setup()
    began = time.perf_counter()
    solved = planner.solve(timeout)
    elapsed = time.perf_counter() - began
    if not solved or not problem.hasExactSolution():
        return elapsed, None
    path = problem.getSolutionPath()
    return elapsed, [as_q(path.getState(i)) for i in range(path.getStateCount())]


def plans(args):
    """Per scenario: RRT-Connect plans start -> goal, tocsin (exact motion validator) beside
    Pinocchio + coal (OMPL's discrete validator at 1%); every plan's edges re-checked by tocsin's
    exact segment check, and the edges it rejects by coal at 20,001 states."""
    import ompl.util as ou

    ou.setLogLevel(ou.LOG_NONE)
    resources = vamp_resources()
    rows = []
    for robot_name in args.plan_robots.split(","):
        rows += plans_for(args, resources, robot_name)
    lines = [
        "",
        f"RRT-Connect through OMPL, {args.plans} problems per scenario, timeout {args.plan_timeout} s; "
        "median seconds per plan (solved / tried); plans whose edges tocsin finds in collision.",
        "",
        "| robot | scenario | tocsin (exact validator) | pin+coal (OMPL discrete, 1%) | pin+coal plans tocsin rejects (confirmed by coal at 20,001 states per edge) |",
        "|---|---|---:|---:|---:|",
    ]
    for r in rows:
        n = len(r["t"])
        lines.append(
            f"| {r['robot']} | {r['scenario']} | {statistics.median(r['t']):.3f} ({r['t_ok']}/{n}) | "
            f"{statistics.median(r['p']):.3f} ({r['p_ok']}/{n}) | {r['p_bad']} ({r['p_confirmed']}) |"
        )
    return "\n".join(lines)


def plans_for(args, resources, robot_name):
    base = resources / robot_name
    ours = Tocsin(base / f"{robot_name}.urdf", base / f"{robot_name}.srdf")
    robot = ours.robot
    theirs = Pinocchio(base / f"{robot_name}.urdf", robot=robot)
    rows = []
    for scenario, items in sorted(problems(resources, robot_name, args.plans).items()):
        row = {"robot": robot_name, "scenario": scenario, "t": [], "p": [], "t_ok": 0, "p_ok": 0, "p_bad": 0, "p_confirmed": 0}
        for scene_yaml, request in items:
            scene = ours.scene(scene_yaml)
            geom = theirs.scene(scene_yaml)
            names = request["start_state"]["joint_state"]["name"]
            values = dict(zip(names, request["start_state"]["joint_state"]["position"]))
            q_start = np.array([values[n] for n in robot.joint_names])
            goal = {c["joint_name"]: c["position"] for c in request["goal_constraints"][0]["joint_constraints"]}
            q_goal = np.array([goal[n] for n in robot.joint_names])
            seconds, path = plan(
                robot,
                q_start,
                q_goal,
                lambda q: not robot.in_collision(q, scene),
                lambda a, b: robot.path_is_free(a, b, scene),
                args.plan_timeout,
            )
            row["t"].append(seconds)
            row["t_ok"] += path is not None
            seconds, path = plan(robot, q_start, q_goal, lambda q: not theirs.in_collision(geom, q), None, args.plan_timeout)
            row["p"].append(seconds)
            if path is not None:
                row["p_ok"] += 1
                bad = [(a, b) for a, b in zip(path, path[1:]) if not robot.path_is_free(a, b, scene)]
                if bad:
                    row["p_bad"] += 1
                    # Confirmed by coal itself at 20,001 states along the edges tocsin rejects.
                    row["p_confirmed"] += any(
                        theirs.in_collision(geom, a + t * (b - a)) for a, b in bad for t in np.linspace(0, 1, 20001)
                    )
        rows.append(row)
        print(json.dumps({k: v for k, v in row.items()}))
    return rows


def percentile(values, p):
    if not values:
        return float("nan")
    values = sorted(values)
    return values[min(len(values) - 1, int(p * len(values)))]


def run(args):
    resources = vamp_resources()
    rng = np.random.default_rng(args.seed)
    rows = []
    turn = 0
    for robot_name in args.robots.split(","):
        base = resources / robot_name
        urdf, srdf = base / f"{robot_name}.urdf", base / f"{robot_name}.srdf"
        ours = Tocsin(urdf, srdf)
        theirs = Pinocchio(urdf, robot=ours.robot)
        robot = ours.robot
        hpp = Hpp(urdf, srdf, robot) if args.hpp else None
        limits = robot.joint_limits
        lo, hi = limits[:, 0], limits[:, 1]
        # A continuous joint has infinite limits; a planner bounds it to one turn.
        span = np.where(np.isfinite(hi - lo), hi - lo, 2 * np.pi)
        extent = float(np.linalg.norm(span))
        assert theirs.model.nq == robot.dof, (theirs.model.nq, robot.dof)
        for scenario, items in sorted(problems(resources, robot_name, args.problems).items()):
            stats = {
                k: []
                for k in ("t_free", "t_coll", "p_free", "p_coll", "t_cfg", "p_cfg", "t_goal", "p_goal", "h_free", "h_coll", "h_goal")
            }
            counts = {
                "free": 0, "coll": 0, "miss": 0, "unconfirmed": 0, "extra": 0, "edges": 0, "h_differ": 0, "cfg_differ": 0
            }
            for scene_yaml, request in items:
                scene = ours.scene(scene_yaml)
                geom = theirs.scene(scene_yaml)
                names = request["start_state"]["joint_state"]["name"]
                values = dict(zip(names, request["start_state"]["joint_state"]["position"]))
                q_start = np.array([values[n] for n in robot.joint_names])
                goal = {c["joint_name"]: c["position"] for c in request["goal_constraints"][0]["joint_constraints"]}
                q_goal = np.array([goal[n] for n in robot.joint_names])
                checker = hpp.scene(scene_yaml, q_start) if hpp else None
                edges = []
                for _ in range(args.edges):
                    u = rng.normal(size=robot.dof)
                    edges.append((q_start, np.clip(q_start + 0.5 * u / np.linalg.norm(u), lo, hi), False))
                edges.append((q_start, q_goal, True))
                turn += 1
                # Single configurations: the start state and the edges' ends, each checker a
                # loop over them (a planner's sampler checks one configuration after another),
                # the loops taking turns over three rounds. Calling one configuration five times,
                # the two checkers alternating, had timed a warm repeat (docs/BENCHMARKS.md,
                # thirty-seventh session).
                configs = [q_start] + [q1 for _, q1, _ in edges]
                cfg_times, cfg_answers = sweeps(
                    {
                        "t_cfg": [lambda q=q: robot.in_collision(q, scene) for q in configs],
                        "p_cfg": [lambda q=q: theirs.in_collision(geom, q) for q in configs],
                    },
                    rounds=3,
                    turn=turn,
                )
                for k in cfg_times:
                    stats[k] += [t * 1e6 for t in cfg_times[k]]
                counts["cfg_differ"] += sum(a != b for a, b in zip(cfg_answers["t_cfg"], cfg_answers["p_cfg"]))

                def sampled(q0, q1):
                    n = max(1, math.ceil(np.linalg.norm(q1 - q0) / (0.01 * extent)))
                    return not any(theirs.in_collision(geom, q0 + (k / n) * (q1 - q0)) for k in range(1, n + 1))

                # Each checker runs the scene's edges as a loop, as a planner's would call it
                # (edge by edge the three evict each other's caches: measured, tocsin's
                # free-edge medians rose 1.3 to 2x with HPP's checks between its own); which
                # loop runs first turns scene by scene.
                checkers = {"ours": lambda q0, q1: robot.path_is_free(q0, q1, scene), "sampled": sampled}
                if checker:
                    checkers["hpp"] = lambda q0, q1: Hpp.path_is_free(checker, q0, q1)
                edge_times, edge_answers = sweeps(
                    {k: [lambda q0=q0, q1=q1, c=c: c(q0, q1) for q0, q1, _ in edges] for k, c in checkers.items()},
                    rounds=1,
                    turn=turn,
                )
                ours_out, sampled_out = (
                    list(zip(edge_answers[k], [t * 1e6 for t in edge_times[k]])) for k in ("ours", "sampled")
                )
                hpp_out = list(zip(edge_answers["hpp"], [t * 1e6 for t in edge_times["hpp"]])) if checker else None
                for k, ((q0, q1, is_goal), (free, t_ours), (sampled_free, t_sampled)) in enumerate(
                    zip(edges, ours_out, sampled_out)
                ):
                    counts["edges"] += 1
                    if hpp_out is not None:
                        hpp_free, t_hpp = hpp_out[k]
                        stats["h_goal" if is_goal else "h_free" if hpp_free else "h_coll"].append(t_hpp)
                        counts["h_differ"] += hpp_free != free
                    if is_goal:
                        stats["t_goal"].append(t_ours)
                        stats["p_goal"].append(t_sampled)
                    else:
                        stats["t_free" if free else "t_coll"].append(t_ours)
                        stats["p_free" if sampled_free else "p_coll"].append(t_sampled)
                    counts["free" if free else "coll"] += 1
                    if sampled_free and not free:
                        dense = any(
                            theirs.in_collision(geom, q0 + t * (q1 - q0)) for t in np.linspace(0, 1, 20001)
                        )
                        counts["miss" if dense else "unconfirmed"] += 1
                    if free and not sampled_free:
                        counts["extra"] += 1
            row = {
                "robot": robot_name,
                "scenario": scenario,
                **counts,
                **{k: (statistics.median(v) if v else float("nan"), percentile(v, 0.9)) for k, v in stats.items()},
            }
            rows.append(row)
            print(json.dumps(row))
    return rows


def table(rows, args):
    lines = [
        f"{machine_line()}, tocsin {tocsin.__version__}; {args.problems} problems per "
        f"scenario, {args.edges} random 0.5 rad edges from each start state plus the start-to-goal edge; "
        "times in microseconds through Python, median (90th percentile).",
        "",
        "| robot | scenario | edges free / colliding (tocsin) | tocsin free edge | tocsin colliding edge | "
        "pin+coal 1% free edge | pin+coal 1% colliding edge | tocsin start-goal | pin+coal 1% start-goal | "
        "tocsin config | pin+coal config | config verdicts that differ | "
        "1% sampler wrong: missed (confirmed) / unconfirmed / false alarm |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    f = lambda v: f"{v[0]:.0f} ({v[1]:.0f})" if not math.isnan(v[0]) else "-"
    for r in rows:
        lines.append(
            f"| {r['robot']} | {r['scenario']} | {r['free']} / {r['coll']} | {f(r['t_free'])} | {f(r['t_coll'])} | "
            f"{f(r['p_free'])} | {f(r['p_coll'])} | {f(r['t_goal'])} | {f(r['p_goal'])} | {f(r['t_cfg'])} | "
            f"{f(r['p_cfg'])} | {r['cfg_differ']} | {r['miss']} / {r['unconfirmed']} / {r['extra']} |"
        )
    if args.hpp:
        lines += [
            "",
            "Beside HPP's exact path validation (hpp-core `Dichotomy`, tolerance 0, same geometry and pairs), "
            "the same edges in the same run; HPP's edges are sorted by HPP's own verdict.",
            "",
            "| robot | scenario | tocsin free edge | HPP free edge | HPP / tocsin (free medians) | tocsin colliding edge | "
            "HPP colliding edge | tocsin start-goal | HPP start-goal | verdicts that differ |",
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|",
        ]
        for r in rows:
            ratio = r["h_free"][0] / r["t_free"][0]
            ratio = "-" if math.isnan(ratio) else f"{ratio:.1f}x"
            lines.append(
                f"| {r['robot']} | {r['scenario']} | {f(r['t_free'])} | {f(r['h_free'])} | {ratio} | "
                f"{f(r['t_coll'])} | {f(r['h_coll'])} | {f(r['t_goal'])} | {f(r['h_goal'])} | {r['h_differ']} |"
            )
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--problems", type=int, default=10)
    parser.add_argument("--edges", type=int, default=20)
    parser.add_argument("--robots", default="panda,ur5,fetch")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--plans", type=int, default=0, help="RRT-Connect plans per Panda scenario")
    parser.add_argument("--plan-timeout", type=float, default=10.0)
    parser.add_argument("--plan-robots", default="panda,ur5,fetch")
    parser.add_argument("--out")
    parser.add_argument(
        "--no-hpp", dest="hpp", action="store_false", help="leave out HPP's exact path validation (hpp-python)"
    )
    args = parser.parse_args()
    if args.hpp and not hpp_importable():
        raise SystemExit("pyhpp does not import: pip install hpp-python, or pass --no-hpp")
    text = table(run(args), args) if args.problems > 0 else ""
    if args.plans > 0:
        text += "\n" + plans(args)
    print(text)
    if args.out:
        pathlib.Path(args.out).write_text(text + "\n")


if __name__ == "__main__":
    main()
