"""Pickled objects (Mesh, Motion, Scene, Robot) answer every query bit for bit as the originals."""

import pathlib
import pickle

import numpy as np
import pytest

import tocsin
from _geometry import turn

ROOT = pathlib.Path(__file__).resolve().parents[3]
PANDA = ROOT / "data" / "franka_panda" / "panda.urdf"


def again(x):
    return pickle.loads(pickle.dumps(x))


def test_meshes_and_motions_round_trip_exactly():
    knot = tocsin.Mesh.torus_knot(120, 10)
    soup = tocsin.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0], [2, 2, 2]], float), [[0, 1, 2], [0, 3, 4], [1, 1, 1]])
    for mesh in (knot, soup):
        copy = again(mesh)
        np.testing.assert_array_equal(copy.vertices, mesh.vertices)
        np.testing.assert_array_equal(copy.triangles, mesh.triangles)
    start, end = turn([0, 0, 1], 0.3, [-14, 1, 0.5]), turn([1, 2, 0.5], 1.4, [14, -0.5, 0])
    motions = [
        tocsin.Motion.screw(start, end),
        tocsin.Motion.screw(start, turn([0, 0, 1], 0.3 + 1e-16, [14, -0.5, 0])),
        tocsin.Motion.interp(start, end, [0.5, -1.0, 2.0]),
        tocsin.Motion.interp(start, start),
        tocsin.Motion.translation(start, turn([0, 0, 1], 0.3, [14, -0.5, 0])),
        tocsin.Motion.stationary(start),
        tocsin.Motion.turn(start, [0.5, -3.0, 0.2], [0.1, 0.3, 1.0], 5.5),
    ]
    still = tocsin.Motion.stationary(np.eye(4))
    hits = 0
    for m in motions:
        m2 = again(m)
        assert m2.kind == m.kind
        for t in (0.0, 0.37, 1.0):
            np.testing.assert_array_equal(m2.pose_at(t), m.pose_at(t))
        a = tocsin.time_of_contact(knot, m, knot, still)
        b = tocsin.time_of_contact(again(knot), m2, knot, again(still))
        assert (a is None) == (b is None)
        if a is not None:
            hits += 1
            assert (a.time, a.distance, a.triangle1, a.triangle2) == (b.time, b.distance, b.triangle1, b.triangle2)
            np.testing.assert_array_equal(a.point1, b.point1)
    assert hits >= 3
    poses = np.stack([turn([1, 1, 0], 0.1 * k, [7 - 0.1 * k, 0.2, 0.1]) for k in range(20)])
    d1 = tocsin.distance_batch(knot, poses, knot, np.eye(4))
    d2 = tocsin.distance_batch(again(knot), poses, again(knot), np.eye(4))
    np.testing.assert_array_equal(d1.distance, d2.distance)
    np.testing.assert_array_equal(d1.point1, d2.point1)


def test_scenes_and_robots_round_trip_exactly():
    robot = tocsin.Robot.from_urdf(str(PANDA))
    robot.allow_collision("panda_link0", "panda_link2")
    robot.attach("part", tocsin.Mesh.box([0.03, 0.03, 0.03]), "panda_hand", pose=turn([0, 0, 1], 0.2, [0, 0, 0.1]))
    robot.attach("gone", tocsin.Mesh.box([0.01, 0.01, 0.01]), "panda_link3")
    robot.detach("gone")
    robot.base = turn([0, 0, 1], 0.1, [0.05, 0, 0])
    scene = tocsin.Scene()
    plate = tocsin.Mesh.box([0.3, 0.3, 0.0005])
    scene.add("plate", plate, turn([1, 0, 0], 0.0, [0.4, 0, 0.25]))
    scene.add("post", tocsin.Mesh.cylinder(0.03, 0.6), turn([1, 0, 0], 0.0, [-0.4, 0.2, 0.3]))
    r2, s2 = again(robot), again(scene)
    assert r2.object_names == robot.object_names
    assert r2.self_pairs == robot.self_pairs
    assert s2.names == scene.names
    np.testing.assert_array_equal(r2.base, robot.base)
    rng = np.random.default_rng(4)
    lo, hi = robot.joint_limits[:, 0], robot.joint_limits[:, 1]
    q0 = rng.uniform(lo, hi, size=(30, robot.dof))
    q1 = np.clip(q0 + rng.normal(scale=0.5, size=q0.shape), lo, hi)
    a = robot.time_of_contact_batch(q0, q1, scene)
    b = r2.time_of_contact_batch(q0, q1, s2)
    assert [None if c is None else (c.time, c.object1, c.object2, c.distance) for c in a] == [
        None if c is None else (c.time, c.object1, c.object2, c.distance) for c in b
    ]
    assert sum(c is not None for c in a) > 3
    np.testing.assert_array_equal(robot.check_configurations(q0, scene), r2.check_configurations(q0, s2))
    np.testing.assert_array_equal(robot.link_poses(q0[0]), r2.link_poses(q0[0]))


def test_a_pickled_robot_needs_no_mesh_file(tmp_path):
    import shutil

    copy = tmp_path / "panda"
    shutil.copytree(PANDA.parent, copy)
    robot = tocsin.Robot.from_urdf(str(copy / PANDA.name))
    robot.allow_collision("panda_link0", "panda_link2")
    data = pickle.dumps(robot)
    shutil.rmtree(copy)
    with pytest.raises(tocsin.RobotFileError):
        tocsin.Robot.from_urdf(str(copy / PANDA.name))
    r2 = pickle.loads(data)
    assert r2.object_names == robot.object_names and r2.self_pairs == robot.self_pairs
    rng = np.random.default_rng(9)
    lo, hi = robot.joint_limits[:, 0], robot.joint_limits[:, 1]
    q = rng.uniform(lo, hi, size=(40, robot.dof))
    np.testing.assert_array_equal(robot.check_configurations(q), r2.check_configurations(q))
    for k in range(5):
        a, b = robot.time_of_contact(q[k], q[k + 1]), r2.time_of_contact(q[k], q[k + 1])
        assert (a is None) == (b is None)
        if a is not None:
            assert (a.time, a.object1, a.object2, a.distance) == (b.time, b.object1, b.object2, b.distance)
    # The copy pickles again, meshes included.
    r3 = pickle.loads(pickle.dumps(r2))
    np.testing.assert_array_equal(r3.check_configurations(q), r2.check_configurations(q))


def test_worlds_round_trip_exactly():
    knot, ball = tocsin.Mesh.torus_knot(60, 8), tocsin.Mesh.sphere(1.0, 6, 8)
    world = tocsin.World()
    world.add_static(tocsin.Mesh.plate(40.0, 2), turn([1, 0, 0], 0.1, [0, 0, -1]))
    rng = np.random.default_rng(3)
    for k in range(12):
        start = turn(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(-8, 8, size=3))
        end = turn(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(-8, 8, size=3))
        world.add_body(knot if k % 2 else ball, tocsin.Motion.screw(start, end))
    copy = again(world)
    assert len(copy) == len(world) and copy.num_meshes == world.num_meshes == 3
    a = [(c.body1, c.body2, c.time, c.contact.distance) for c in world.first_contacts()]
    b = [(c.body1, c.body2, c.time, c.contact.distance) for c in copy.first_contacts()]
    assert a == b and len(a) > 3
    assert copy.is_static(0) and not copy.is_static(1)


def test_a_corrupted_world_pickle_is_a_world_error():
    # A negative or huge mesh index in a pickled world raised OverflowError from the argument
    # conversion, not the package's error.
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    world = tocsin.World()
    world.add_body(box, tocsin.Motion.translation(np.eye(4), np.eye(4)))
    build, (meshes, bodies) = world.__reduce__()
    for index in (-1, 2**64, 1, "0"):
        corrupted = [(index,) + tuple(bodies[0][1:])]
        with pytest.raises(tocsin.WorldError, match="names a mesh it lacks"):
            build(meshes, corrupted)
    assert len(build(meshes, bodies)) == 1
