"""tocsin.World against the brute force through the single queries, and its errors."""

import threading

import numpy as np
import pytest

import tocsin


def rotation(rng, angle):
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def pose(rng, spread, angle=np.pi):
    p = np.eye(4)
    p[:3, :3] = rotation(rng, rng.uniform(-angle, angle))
    p[:3, 3] = rng.uniform(-spread, spread, size=3)
    return p


def random_world(seed, n):
    rng = np.random.default_rng(seed)
    meshes = [tocsin.Mesh.torus_knot(24, 5), tocsin.Mesh.sphere(0.7, 5, 8), tocsin.Mesh.plate(3.0, 2)]
    world = tocsin.World()
    motions = []
    spread = 2.0 * n ** (1 / 3)
    for k in range(n):
        mesh = meshes[k % 3]
        if k % 7 == 0:
            world.add_static(mesh, pose(rng, spread))
            continue
        start = pose(rng, spread)
        end = start.copy()
        end[:3, :3] = rotation(rng, rng.uniform(0, 2)) @ start[:3, :3]
        end[:3, 3] += rng.normal(size=3) * spread * 0.3
        world.add_body(mesh, tocsin.Motion.screw(start, end))
        motions.append((k, start, end))
    return world, meshes


def brute(world, meshes, tolerance=None):
    n = len(world)
    starts, ends = world.poses_at(0.0), world.poses_at(1.0)
    out = []
    for i in range(n):
        for j in range(i + 1, n):
            if world.is_static(i) and world.is_static(j):
                continue
            mi, mj = meshes[i % 3], meshes[j % 3]
            moi = tocsin.Motion.screw(starts[i], ends[i])
            moj = tocsin.Motion.screw(starts[j], ends[j])
            c = tocsin.time_of_contact(mi, moi, mj, moj, tolerance=tolerance)
            if c is not None:
                out.append((c.time, i, j))
    return sorted(out)


def test_first_contacts_match_every_pair():
    world, meshes = random_world(3, 40)
    assert world.num_meshes == 3
    got = tocsin.first_contacts(world)
    # The brute force rebuilds each motion from the world's end poses; the screw through the
    # same poses is the same motion within rounding, so times agree to 1e-9.
    expected = brute(world, meshes)
    assert len(expected) > 5
    assert [(c.body1, c.body2) for c in got] == [(i, j) for _, i, j in expected]
    for c, (t, _, _) in zip(got, expected):
        assert c.time == pytest.approx(t, abs=1e-9)
        assert c.contact.time == c.time
        assert c.contact.distance <= 1e-3 * max(m.bounding_radius for m in meshes) * (1 + 1e-12)
    some = [c.body2 for c in got[:3]]
    among = world.first_contacts(bodies=some)
    assert [(c.body1, c.body2, c.time) for c in among] == [
        (c.body1, c.body2, c.time) for c in got if c.body1 in some or c.body2 in some
    ]
    with pytest.raises(tocsin.WorldError):
        world.first_contacts(bodies=[len(world)])
    first = tocsin.earliest_contact(world)
    assert (first.body1, first.body2) == (got[0].body1, got[0].body2)
    assert first.time == got[0].time
    assert len(world.candidate_pairs()) >= len(got)


def test_discrete_queries_match_every_pair():
    world, meshes = random_world(8, 30)
    poses = world.poses_at(0.5)
    before = poses.copy()
    colliding, near = [], []
    for i in range(len(world)):
        for j in range(i + 1, len(world)):
            if world.is_static(i) and world.is_static(j):
                continue
            mi, mj = meshes[i % 3], meshes[j % 3]
            if tocsin.collide(mi, poses[i], mj, poses[j]):
                colliding.append([i, j])
            if tocsin.within_distance(mi, poses[i], mj, poses[j], 0.3):
                near.append([i, j])
    assert tocsin.colliding_pairs(world, poses).tolist() == colliding
    assert world.colliding_pairs(t=0.5).tolist() == colliding
    assert tocsin.pairs_within(world, poses, 0.3).tolist() == near
    assert len(near) > len(colliding) > 0
    np.testing.assert_array_equal(poses, before)


def test_set_motions_and_a_thin_plate():
    plate = tocsin.Mesh.plate(2.0, 1)
    cube = tocsin.Mesh.box([0.05, 0.05, 0.05])
    world = tocsin.World()
    world.add_static(plate, np.eye(4))
    ids = [world.add_body(cube, np.eye(4)) for _ in range(3)]
    starts = np.repeat(np.eye(4)[None], 3, axis=0)
    ends = starts.copy()
    for k, x in enumerate([-0.5, 0.0, 0.5]):
        starts[k, :3, 3] = [x, 0, 5.0 + k]
        ends[k, :3, 3] = [x, 0, -5.0]
    world.set_motions(ids, starts, ends, kind="translation")
    contacts = world.first_contacts()
    assert [(c.body1, c.body2) for c in contacts] == [(0, 1), (0, 2), (0, 3)]
    # Body k starts at 5 + k and falls to -5: it reaches the plate (z = 0.05) first for k = 0.
    assert contacts[0].time == pytest.approx(4.95 / 10.0, abs=1e-3)
    assert world.earliest_contact().body2 == 1


def test_bad_input_raises_package_errors():
    world = tocsin.World()
    mesh = tocsin.Mesh.sphere(1.0, 4, 6)
    world.add_body(mesh, np.eye(4))
    with pytest.raises(tocsin.WorldError):
        world.set_motion(5, tocsin.Motion.stationary(np.eye(4)))
    with pytest.raises(tocsin.PoseError):
        world.colliding_pairs(np.zeros((2, 4, 4)))
    with pytest.raises(tocsin.OptionsError):
        world.first_contacts(tolerance=-1.0)
    with pytest.raises(tocsin.OptionsError):
        world.pairs_within(float("nan"))
    with pytest.raises(tocsin.MotionError):
        world.set_motions([0], np.eye(4)[None], np.eye(4)[None], kind="spline")
    with pytest.raises(tocsin.WorldError):
        world.set_motions([3], np.eye(4)[None], np.eye(4)[None])
    with pytest.raises(tocsin.PoseError):
        world.add_static(mesh, np.ones((4, 4)))
    # Indices an index cannot hold are unknown bodies too, not the OverflowError of converting
    # them; numpy's integers are indices; anything else is a TypeError.
    still = tocsin.Motion.stationary(np.eye(4))
    for index in (-1, 2**70):
        with pytest.raises(tocsin.WorldError, match="does not exist"):
            world.set_motion(index, still)
        with pytest.raises(tocsin.WorldError, match="does not exist"):
            world.is_static(index)
        with pytest.raises(tocsin.WorldError, match="does not exist"):
            world.set_motions([0, index], np.tile(np.eye(4), (2, 1, 1)), np.tile(np.eye(4), (2, 1, 1)))
    assert world.is_static(np.int64(0)) is False
    world.set_motion(np.uint8(0), still)
    for index in ("0", 0.0, None):
        with pytest.raises(TypeError, match="body index"):
            world.is_static(index)
    # The module's functions say which argument is wrong, as every other call does.
    for call in (tocsin.first_contacts, tocsin.earliest_contact, tocsin.colliding_pairs):
        with pytest.raises(TypeError, match="must be a tocsin.World"):
            call(mesh)
    with pytest.raises(TypeError, match="must be a tocsin.World"):
        tocsin.pairs_within(mesh, None, 0.1)
    with pytest.raises(TypeError, match="must be a tocsin.Robot"):
        tocsin.path_is_free(world, [0.0], [1.0])
    with pytest.raises(TypeError, match="must be a tocsin.Robot"):
        tocsin.check_configurations(world, [[0.0]])
    assert len(world) == 1


def test_queries_in_threads_while_editing():
    world, _ = random_world(11, 30)
    expected = [(c.body1, c.body2, c.time) for c in world.first_contacts()]
    errors = []

    def query():
        try:
            for _ in range(5):
                got = [(c.body1, c.body2, c.time) for c in world.first_contacts()]
                # A snapshot: bodies added meanwhile are far away, so the answer is the same.
                if got != expected:
                    errors.append(got)
        except Exception as e:  # noqa: BLE001 - collected and asserted below
            errors.append(e)

    threads = [threading.Thread(target=query) for _ in range(3)]
    for t in threads:
        t.start()
    far = np.eye(4)
    for k in range(20):
        far[:3, 3] = [1000.0 + 10 * k, 0, 0]
        world.add_body(tocsin.Mesh.sphere(0.5, 4, 6), far)
    for t in threads:
        t.join()
    assert errors == []
    assert len(world) == 50
