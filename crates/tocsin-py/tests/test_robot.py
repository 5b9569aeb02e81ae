"""Robots from Python: forward kinematics against pybullet (a second implementation), segment
checks against dense sampling on the Panda and the KUKA iiwa of pybullet_data, errors, batches,
and OMPL planning with tocsin as the validity checker and the exact motion validator."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pybullet
import pybullet_data
import pytest

import tocsin

DATA = pybullet_data.getDataPath()
PANDA = os.path.join(DATA, "franka_panda", "panda.urdf")
KUKA = os.path.join(DATA, "kuka_iiwa", "model.urdf")
ROOT = pathlib.Path(__file__).resolve().parents[3]


def quat_to_matrix(q):
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


@pytest.mark.parametrize("urdf", [PANDA, KUKA])
def test_forward_kinematics_matches_pybullet(urdf):
    robot = tocsin.Robot.from_urdf(urdf)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(urdf, useFixedBase=True, physicsClientId=client)
        joints = {}
        for j in range(pybullet.getNumJoints(body, physicsClientId=client)):
            info = pybullet.getJointInfo(body, j, physicsClientId=client)
            joints[info[1].decode()] = (j, info[12].decode())
        names = robot.link_names
        rng = np.random.default_rng(3)
        limits = robot.joint_limits
        for _ in range(20):
            q = rng.uniform(np.maximum(limits[:, 0], -3), np.minimum(limits[:, 1], 3))
            values = dict(zip(robot.joint_names, q))
            if "panda_finger_joint2" in joints:  # the URDF's mimic of finger_joint1
                values["panda_finger_joint2"] = values["panda_finger_joint1"]
            for name, v in values.items():
                pybullet.resetJointState(body, joints[name][0], v, physicsClientId=client)
            poses = robot.link_poses(q)
            for _, (j, link) in joints.items():
                state = pybullet.getLinkState(body, j, computeForwardKinematics=True, physicsClientId=client)
                pose = poses[names.index(link)]
                np.testing.assert_allclose(pose[:3, 3], state[4], atol=1e-6)
                np.testing.assert_allclose(pose[:3, :3], quat_to_matrix(state[5]), atol=1e-6)
    finally:
        pybullet.disconnect(client)


def box_scene(rng, count, base=None):
    """A scene of random boxes around the robot's base (the identity when None), and its
    obstacles by name (mesh, pose)."""
    base = np.eye(4) if base is None else base
    scene, obstacles = tocsin.Scene(), {}
    for k in range(count):
        pose = np.eye(4)
        pose[:3, 3] = rng.uniform([-0.7, -0.7, 0.0], [0.7, 0.7, 1.0])
        pose = base @ pose
        mesh = tocsin.Mesh.box(rng.uniform(0.03, 0.2, size=3))
        scene.add(f"box{k}", mesh, pose)
        obstacles[f"box{k}"] = (mesh, pose)
    return scene, obstacles


def lerp(q0, q1, t):
    return q0 + t * (q1 - q0)


def first_sampled_collision(robot, q0, q1, scene, samples=2000):
    qs = np.array([lerp(q0, q1, t) for t in np.linspace(0, 1, samples + 1)])
    hits = robot.check_configurations(qs, scene)
    if not hits.any():
        return None
    k = int(np.argmax(hits))
    if k == 0:
        return 0.0
    lo, hi = (k - 1) / samples, k / samples
    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        if robot.in_collision(lerp(q0, q1, mid), scene):
            hi = mid
        else:
            lo = mid
    return hi


def far_base(offset):
    """A base turned about a tilted axis and moved `offset` from the origin along (1, -2, 0.5)."""
    axis = np.array([0.3, -0.5, 1.0]) / np.linalg.norm([0.3, -0.5, 1.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    base = np.eye(4)
    base[:3, :3] = np.eye(3) + np.sin(2.1) * k + (1 - np.cos(2.1)) * k @ k
    base[:3, 3] = offset * np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    return base


@pytest.mark.parametrize(
    "urdf,srdf,offset", [(PANDA, True, 0.0), (KUKA, False, 0.0), (PANDA, True, 1e4), (KUKA, False, 1e5)]
)
def test_segments_against_dense_sampling(urdf, srdf, offset):
    """Segments against dense sampling plus bisection, at the origin and on a turned base far
    from it (the scene moved with it: the same geometry in large coordinates)."""
    robot = tocsin.Robot.from_urdf(urdf)
    base = far_base(offset)
    robot.base = base
    if srdf:  # the Panda's hand and fingers touch by design
        robot.allow_collision("panda_hand", "panda_leftfinger")
        robot.allow_collision("panda_hand", "panda_rightfinger")
        robot.allow_collision("panda_leftfinger", "panda_rightfinger")
    rng = np.random.default_rng(11)
    limits = robot.joint_limits
    lo, hi = np.maximum(limits[:, 0], -3), np.minimum(limits[:, 1], 3)
    counts = {"free": 0, "contact": 0, "self": 0}
    checked = 0
    while checked < 25:
        scene, obstacles = box_scene(rng, 6, base)
        q0 = rng.uniform(lo, hi)
        if robot.in_collision(q0, scene):
            continue
        q1 = np.clip(q0 + rng.normal(size=robot.dof) * 0.6, lo, hi)
        checked += 1
        got = robot.time_of_contact(q0, q1, scene, contact_pair=True)
        assert robot.path_is_free(q0, q1, scene) == (got is None)
        assert robot.last_valid(q0, q1, scene) == (1.0 if got is None else got.time)
        first = first_sampled_collision(robot, q0, q1, scene)
        if got is None:
            assert first is None, f"missed a collision at t = {first}"
            counts["free"] += 1
            continue
        counts["contact"] += 1
        counts["self"] += got.self_collision
        if first is not None:
            assert got.time <= first + 1e-12, f"late: {got.time} > {first}"
        q = lerp(q0, q1, got.time)
        # The contact pair's distance is at least the named objects' there; the default, the
        # same contact at their exact distance.
        exact = robot.time_of_contact(q0, q1, scene)
        assert (exact.time, exact.object1, exact.object2) == (got.time, got.object1, got.object2)
        poses = dict(zip(robot.object_names, robot.object_poses(q)))
        m1 = robot.object_mesh(got.object1)
        if got.self_collision:
            m2, p2 = robot.object_mesh(got.object2), poses[got.object2]
        else:
            m2, p2 = obstacles[got.object2]
        d = tocsin.distance(m1, poses[got.object1], m2, p2).distance
        assert abs(d - exact.distance) < 1e-9 * (1 + offset)
        assert got.distance >= d - 1e-9 * (1 + offset)
        assert np.linalg.norm(got.point2 - got.point1) == pytest.approx(got.distance, abs=1e-9 * (1 + offset))
        tolerance = 1e-3 * min(robot.object_mesh(n).bounding_radius for n in robot.object_names)
        assert got.distance <= tolerance * (1 + 1e-9)
    print(counts)
    assert counts["free"] >= 3 and counts["contact"] >= 3, counts


def test_thin_plate_missed_by_a_one_percent_sampler_is_found():
    """The demo's case: the Panda's hand sweeps through a 1 mm plate between two free
    configurations; checking 101 samples (OMPL's default 1% resolution) calls it free."""
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "robot_plate.py")], capture_output=True, text=True, timeout=300
    )
    assert out.returncode == 0, out.stderr
    assert "sampler at 1%: free" in out.stdout and "tocsin: contact" in out.stdout, out.stdout


def test_batches_match_single_calls():
    robot = tocsin.Robot.from_urdf(PANDA)
    rng = np.random.default_rng(2)
    scene, _ = box_scene(rng, 5)
    limits = robot.joint_limits
    q0s = rng.uniform(limits[:, 0], limits[:, 1], size=(30, robot.dof))
    q1s = np.clip(q0s + rng.normal(size=q0s.shape) * 0.3, limits[:, 0], limits[:, 1])
    before = (q0s.copy(), q1s.copy())
    free = robot.paths_are_free(q0s, q1s, scene)
    contacts = robot.time_of_contact_batch(q0s, q1s, scene)
    pairs = robot.time_of_contact_batch(q0s, q1s, scene, contact_pair=True)
    cache = tocsin.RobotCache()
    for i in range(len(q0s)):
        single = robot.time_of_contact(q0s[i], q1s[i], scene)
        assert free[i] == (single is None)
        # A warm start changes nothing in the answers.
        assert robot.path_is_free(q0s[i], q1s[i], scene, cache=cache) == free[i]
        warm = robot.time_of_contact(q0s[i], q1s[i], scene, cache=cache)
        assert (warm is None) == (single is None)
        assert (contacts[i] is None) == (single is None)
        if single is not None:
            assert contacts[i].time == single.time and contacts[i].object2 == single.object2
            assert contacts[i].distance == single.distance
            assert pairs[i].time == single.time and pairs[i].distance >= single.distance
    np.testing.assert_array_equal(robot.check_configurations(q0s, scene), [robot.in_collision(q, scene) for q in q0s])
    np.testing.assert_array_equal(before[0], q0s)  # the caller's arrays are not modified
    np.testing.assert_array_equal(before[1], q1s)


def test_errors_are_the_packages_own(tmp_path):
    with pytest.raises(tocsin.RobotFileError):
        tocsin.Robot.from_urdf(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='r'><link name='a'><collision><geometry><mesh filename='package://nope/x.obj'/></geometry></collision></link></robot>")
    with pytest.raises(tocsin.RobotFileError, match="not found"):
        tocsin.Robot.from_urdf(bad)
    with pytest.raises(tocsin.RobotError, match="not supported"):
        tocsin.Robot.from_urdf_string(
            "<robot name='r'><link name='a'/><link name='b'/><joint name='j' type='floating'>"
            "<parent link='a'/><child link='b'/></joint></robot>"
        )
    robot = tocsin.Robot.from_urdf(PANDA)
    with pytest.raises(tocsin.ConfigurationError):
        robot.link_poses(np.zeros(3))
    with pytest.raises(tocsin.ConfigurationError):
        robot.path_is_free(np.zeros(robot.dof), np.full(robot.dof, np.nan))
    with pytest.raises(tocsin.OptionsError):
        robot.time_of_contact(np.zeros(robot.dof), np.ones(robot.dof), tolerance=-1.0)
    with pytest.raises(tocsin.RobotError):
        robot.allow_collision("panda_hand", "no_such_link")
    assert isinstance(tocsin.RobotFileError("x"), OSError)


def test_attached_object_is_checked_against_the_arm():
    robot = tocsin.Robot.from_urdf(PANDA)
    part = tocsin.Mesh.box([0.02, 0.02, 0.25])
    pose = np.eye(4)
    pose[2, 3] = 0.1
    robot.attach("rod", part, "panda_hand", pose, touch_links=["panda_leftfinger", "panda_rightfinger"])
    assert "rod" in robot.object_names
    assert ("panda_link5", "rod") in robot.self_pairs or ("rod", "panda_link5") in robot.self_pairs
    # Folding the arm brings the rod back into it at some point of a long sweep.
    q0 = np.array([0, 0, 0, -0.3, 0, 0.5, 0, 0.02])
    q1 = np.array([0, 0, 0, -2.8, 0, 3.6, 0, 0.02])
    got = robot.time_of_contact(q0, q1)
    first = first_sampled_collision(robot, q0, q1, tocsin.Scene())
    if first is not None:
        assert got is not None and got.time <= first + 1e-12
    robot.detach("rod")
    assert "rod" not in robot.object_names


def test_ompl_rrt_connect_with_the_exact_motion_validator():
    out = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "ompl_planning.py")], capture_output=True, text=True, timeout=600
    )
    assert out.returncode == 0, out.stderr[-3000:]
    assert "every edge of the path is free: True" in out.stdout, out.stdout


def test_threads_query_while_another_edits_and_the_base_moves_the_robot():
    import threading

    robot = tocsin.Robot.from_urdf(PANDA)
    scene, _ = box_scene(np.random.default_rng(4), 4)
    q0 = np.array([0.0, 0.3, 0.0, -2.0, 0.0, 2.4, 0.8, 0.04])
    q1 = q0 + 0.5
    expected = robot.path_is_free(q0, q1, scene)
    errors, results = [], []

    def query():
        try:
            for _ in range(30):
                results.append(robot.path_is_free(q0, q1, scene))
        except Exception as e:  # any error here is a failure, reported below
            errors.append(e)

    def edit():
        try:
            for k in range(30):
                robot.allow_collision("panda_link0", "panda_link5")
                scene.add(f"far{k}", tocsin.Mesh.box([0.01] * 3), np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 50)
        except Exception as e:
            errors.append(e)

    threads = [threading.Thread(target=query) for _ in range(3)] + [threading.Thread(target=edit)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert results == [expected] * 90  # far obstacles and an allowed pair do not change it
    base = np.eye(4)
    base[:3, 3] = [1.0, 2.0, 3.0]
    before = robot.link_poses(q0)
    robot.base = base
    np.testing.assert_allclose(robot.base, base)
    np.testing.assert_allclose(robot.link_poses(q0)[:, :3, 3], before[:, :3, 3] + [1.0, 2.0, 3.0], atol=1e-12)


def test_panda_near_miss_at_one_millimetre_is_free_and_a_graze_is_not():
    """The first joint turns about the vertical axis, so every point keeps its height: a square
    frame of slabs (clear of the base) whose top is 1 mm below the arm's lowest point misses it
    by exactly 1 mm all along the sweep (about 1% of a link's size), and one 1 mm higher cuts
    the fingers."""
    robot = tocsin.Robot.from_urdf(ROOT / "data" / "franka_panda" / "panda.urdf")
    q0 = np.array([-2.8, 0.3, 0.0, -2.0, 0.0, 2.4, 0.8, 0.04])
    q1 = q0.copy()
    q1[0] = 2.8
    names = robot.object_names
    poses = robot.object_poses(0.5 * (q0 + q1))
    world = np.vstack(
        [robot.object_mesh(n).vertices @ poses[names.index(n)][:3, :3].T + poses[names.index(n)][:3, 3] for n in names]
    )
    # The lowest point at a horizontal radius the frame can be under (its hole is 0.4 wide).
    lowest = world[np.hypot(world[:, 0], world[:, 1]) >= 0.4, 2].min()
    for offset, free in [(-0.001, True), (0.001, False)]:
        scene = tocsin.Scene()
        top = lowest + offset
        # Four slabs forming a square frame: inner half width 0.4, outer 0.9, 0.1 thick.
        for k, (half, centre) in enumerate(
            [([0.9, 0.25, 0.05], [0.0, 0.65, 0.0]), ([0.9, 0.25, 0.05], [0.0, -0.65, 0.0]),
             ([0.25, 0.4, 0.05], [0.65, 0.0, 0.0]), ([0.25, 0.4, 0.05], [-0.65, 0.0, 0.0])]
        ):
            pose = np.eye(4)
            pose[:3, 3] = [centre[0], centre[1], top - 0.05]
            scene.add(f"slab{k}", tocsin.Mesh.box(half), pose)
        assert not robot.in_collision(q0, scene) or not free
        assert robot.path_is_free(q0, q1, scene) == free, offset
        got = robot.time_of_contact(q0, q1, scene)
        assert (got is None) == free
        if not free:
            assert got.object2.startswith("slab") and got.object1.endswith("finger")


def test_robots_without_joints_or_geometry():
    fixed = tocsin.Robot.from_urdf_string(
        "<robot name='r'><link name='a'><collision><geometry><box size='1 1 1'/></geometry></collision></link></robot>"
    )
    assert fixed.dof == 0 and fixed.link_poses(np.zeros(0)).shape == (1, 4, 4)
    scene = tocsin.Scene()
    far = np.eye(4)
    far[0, 3] = 5.0
    scene.add("o", tocsin.Mesh.box([0.1] * 3), far)
    assert fixed.path_is_free(np.zeros(0), np.zeros(0), scene)
    assert fixed.check_configurations(np.zeros((3, 0)), scene).tolist() == [False] * 3
    assert fixed.paths_are_free(np.zeros((2, 0)), np.zeros((2, 0)), scene).tolist() == [True] * 2
    bare = tocsin.Robot.from_urdf_string(
        "<robot name='r'><link name='a'/><link name='b'/><joint name='j' type='revolute'><parent link='a'/>"
        "<child link='b'/><axis xyz='0 0 1'/><limit lower='-1' upper='1' effort='1' velocity='1'/></joint></robot>"
    )
    assert bare.path_is_free([0.0], [1.0]) and bare.time_of_contact([0.0], [1.0]) is None
