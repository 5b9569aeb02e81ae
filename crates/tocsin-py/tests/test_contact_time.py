"""time_of_contact and Motion through Python, against dense sampling with tocsin.collide."""

import numpy as np
import pytest

import tocsin
from _geometry import turn


def pose(t=(0, 0, 0), axis=(0, 0, 1), angle=0.0):
    return turn(axis, angle, t)


def first_sampled_collision(m1, mo1, m2, mo2, n=1000):
    for i in range(n + 1):
        t = i / n
        if tocsin.collide(m1, mo1.pose_at(t), m2, mo2.pose_at(t)):
            return t
    return None


@pytest.mark.parametrize("kind", ["translation", "interp", "screw"])
def test_knot_through_knot(kind):
    knot = tocsin.Mesh.torus_knot(100, 8)
    start = pose((-10, 0.3, 0))
    end = pose((10, -0.2, 0.1), (0.2, 1, 0.3), 0.0 if kind == "translation" else 1.2)
    motion = getattr(tocsin.Motion, kind)(start, end)
    still = tocsin.Motion.stationary(np.eye(4))
    r = tocsin.time_of_contact(knot, motion, knot, still, tolerance=1e-3, contact_pair=True)
    t_hit = first_sampled_collision(knot, motion, knot, still)
    assert t_hit is not None and r is not None
    assert r.time <= t_hit
    assert r.status == "converged"
    d = tocsin.distance(knot, motion.pose_at(r.time), knot, np.eye(4)).distance
    # The contact pair's points: as far apart as the distance reported, which is at least the
    # meshes' and within the tolerance.
    assert d <= r.distance * (1 + 1e-9) and r.distance <= 1e-3
    assert np.linalg.norm(r.point2 - r.point1) == pytest.approx(r.distance, rel=1e-9)
    assert np.linalg.norm(r.normal) == pytest.approx(1.0)
    assert np.dot(r.normal, r.point2 - r.point1) > 0
    assert r.point1.shape == (3,) and r.iterations >= 1
    # The default: the same advancement, the meshes' closest points and exact distance.
    c = tocsin.time_of_contact(knot, motion, knot, still, tolerance=1e-3)
    assert (c.time, c.iterations, c.status) == (r.time, r.iterations, r.status)
    assert c.distance == pytest.approx(d, rel=1e-9, abs=1e-15)
    batch = tocsin.time_of_contact_batch(
        knot, [motion.pose_at(0.0)], [motion.pose_at(1.0)], knot, kind=kind, tolerance=1e-3,
        contact_pair=True,
    )
    assert batch.time[0] == r.time and batch.distance[0] == r.distance


def test_miss_and_start_in_contact():
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    still = tocsin.Motion.stationary(np.eye(4))
    miss = tocsin.Motion.translation(pose((-3, 0, 2)), pose((3, 0, 2)))
    assert tocsin.time_of_contact(box, miss, box, still) is None
    inside = tocsin.Motion.translation(pose((0.2, 0, 0)), pose((3, 0, 0)))
    r = tocsin.time_of_contact(box, inside, box, still)
    assert r is not None and r.time == 0.0 and r.status == "started_in_contact"


def test_pose_at_endpoints_and_kind():
    a, b = pose((1, 2, 3), (1, 0, 0), 0.3), pose((-1, 0, 2), (0, 1, 1), 2.0)
    for m in (tocsin.Motion.interp(a, b, center=[0.1, 0.2, 0.3]), tocsin.Motion.screw(a, b)):
        assert np.allclose(m.pose_at(0.0), a) and np.allclose(m.pose_at(1.0), b)
    assert tocsin.Motion.screw(a, b).kind == "screw"


def test_turns_go_round_more_than_once():
    start = pose((1.0, 2.0, -0.5), (0.3, 1, 0.2), 0.7)
    point, axis = np.array([0.4, -1.0, 2.0]), np.array([0.2, 0.5, 1.0])
    m = tocsin.Motion.turn(start, point, axis, -7.5)
    assert m.kind == "turn"
    for t in (0.0, 0.3, 0.71, 1.0):
        # Turned by t * angle about the line: numpy's Rodrigues about the origin, moved there.
        r = turn(axis, -7.5 * t, [0, 0, 0])
        expect = np.eye(4)
        expect[:3, :3] = r[:3, :3] @ start[:3, :3]
        expect[:3, 3] = r[:3, :3] @ (start[:3, 3] - point) + point
        np.testing.assert_allclose(m.pose_at(t), expect, atol=1e-13)
    for bad in ([0, 0, 0], [np.nan, 0, 1]):
        with pytest.raises(tocsin.MotionError, match="axis"):
            tocsin.Motion.turn(start, point, bad, 1.0)
    with pytest.raises(tocsin.MotionError):
        tocsin.Motion.turn(start, point, axis, np.inf)
    with pytest.raises(tocsin.MotionError):
        tocsin.Motion.turn(start, [np.nan, 0, 0], axis, 1.0)
    with pytest.raises(tocsin.PoseError):
        tocsin.Motion.turn(np.diag([1.0, 1.0, -1.0, 1.0]), point, axis, 1.0)


def revolved(radius, length, n_around=64, n_along=4):
    """A surface of revolution about z (open ends), its radius `radius(angle)`."""
    a = np.linspace(0, 2 * np.pi, n_around, endpoint=False)
    z = np.linspace(-length / 2, length / 2, n_along + 1)
    r = np.array([radius(x) for x in a])
    v = np.array([[r[j] * np.cos(a[j]), r[j] * np.sin(a[j]), h] for h in z for j in range(n_around)])
    f = []
    for i in range(n_along):
        for j in range(n_around):
            p, q = i * n_around + j, i * n_around + (j + 1) % n_around
            f += [[p, q, q + n_around], [p, q + n_around, p + n_around]]
    return tocsin.Mesh(v, np.array(f))


@pytest.mark.parametrize("keyed", [False, True])
def test_a_wheel_turning_two_and_a_half_times_on_its_axle(keyed):
    """A 64-sided hub turning 2.5 revolutions about an axle line off the origin inside a bore
    whose faces clear its corners by 0.5% (free), and with a key that meets a stop in a groove
    of the bore (a contact), against dense sampling with collide."""
    bore_r = 1.005 / np.cos(np.pi / 64)
    hub = revolved(lambda a: 1.1 if keyed and a < 0.3 else 1.0, 2.0)
    bore = revolved(lambda a: bore_r if not keyed or np.pi <= a < np.pi + 0.3 else 1.2, 3.0)
    where = pose((3.0, -1.0, 0.5), (1, 0.2, 0), 0.4)
    axis = where[:3, 2]
    wheel = tocsin.Motion.turn(where, where[:3, 3], axis, 5 * np.pi)
    still = tocsin.Motion.stationary(where)
    r = tocsin.time_of_contact(hub, wheel, bore, still, tolerance=1e-3)
    hit = first_sampled_collision(hub, wheel, bore, still, n=4000)
    assert (hit is not None) == keyed
    assert (r is not None) == keyed
    if keyed:
        # Within a sample of the first sampled collision, and never after it. The key meets
        # the stop after turning pi - 0.3 rad of the 5 pi, less a column (0.1 rad) where the
        # faces slope between the key's radius and the hub's.
        assert hit - 1e-3 <= r.time <= hit
        assert abs(hit - (np.pi - 0.3) / (5 * np.pi)) < 0.1 / (5 * np.pi)
        d = tocsin.distance(hub, wheel.pose_at(r.time), bore, where).distance
        assert d <= 1e-3
    assert tocsin.motion_is_free(hub, wheel, bore, still) == (not keyed)


def test_motion_and_option_errors():
    a = pose()
    with pytest.raises(tocsin.MotionError, match="same rotation"):
        tocsin.Motion.translation(a, pose(angle=0.5))
    with pytest.raises(tocsin.PoseError):
        tocsin.Motion.screw(a, np.diag([1.0, 1.0, -1.0, 1.0]))
    box = tocsin.Mesh.box([1, 1, 1])
    still = tocsin.Motion.stationary(a)
    with pytest.raises(tocsin.OptionsError):
        tocsin.time_of_contact(box, still, box, still, tolerance=-1.0)
    with pytest.raises(tocsin.OptionsError):
        tocsin.time_of_contact(box, still, box, still, max_iterations=0)
    assert issubclass(tocsin.MotionError, ValueError)


def test_motion_is_free_agrees_with_time_of_contact():
    knot = tocsin.Mesh.torus_knot(60, 6)
    still = tocsin.Motion.stationary(np.eye(4))
    rng = np.random.default_rng(11)
    answers = set()
    for _ in range(20):
        start, end = np.eye(4), np.eye(4)
        start[:3, 3] = [-12.0, *rng.uniform(-4, 4, 2)]
        end[:3, 3] = [12.0, *rng.uniform(-4, 4, 2)]
        fly = tocsin.Motion.translation(start, end)
        free = tocsin.motion_is_free(knot, fly, knot, still)
        assert free == (tocsin.time_of_contact(knot, fly, knot, still) is None)
        answers.add(free)
    assert answers == {True, False}
    start, end = np.eye(4), np.eye(4)
    start[0, 3], end[0, 3] = -12.0, 12.0
    through = tocsin.Motion.translation(start, end)
    # A motion through the knot collides half way: the collision test there (a probe) answers
    # before the advancement's first iteration, while the time of contact needs its iterations.
    assert tocsin.motion_is_free(knot, through, knot, still, max_iterations=1) is False
    with pytest.raises(tocsin.IterationLimitError):
        tocsin.time_of_contact(knot, through, knot, still, max_iterations=1)
    # A motion that passes by is only known free once the advancement has certified it.
    start[1, 3] = end[1, 3] = 7.0
    by = tocsin.Motion.translation(start, end)
    assert tocsin.time_of_contact(knot, by, knot, still) is None
    with pytest.raises(tocsin.IterationLimitError):
        tocsin.motion_is_free(knot, by, knot, still, max_iterations=1)
