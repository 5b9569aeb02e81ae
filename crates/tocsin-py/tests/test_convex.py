"""Convex polytopes take the GJK path of distance and time_of_contact: the same answers as the
general path on the same surface (a degenerate triangle added makes it a soup), checked against
scipy's hull of the vertex differences and against sampled collision tests."""

import numpy as np
import pytest

import tocsin

ConvexHull = pytest.importorskip("scipy.spatial").ConvexHull


def hull(rng, n, semi):
    p = rng.normal(size=(n, 3))
    p = p / np.linalg.norm(p, axis=1)[:, None] * np.asarray(semi)
    return p, tocsin.Mesh(p, ConvexHull(p).simplices.astype(np.int64))


def as_soup(mesh):
    return tocsin.Mesh(mesh.vertices, np.vstack([mesh.triangles, [[0, 0, 0]]]))


def random_pose(rng, shift):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    p = np.eye(4)
    p[:3, :3], p[:3, 3] = q, shift
    return p


def test_is_convex():
    assert tocsin.Mesh.box([0.5, 0.3, 0.2]).is_convex
    assert tocsin.Mesh.sphere(1.0, 8, 16).is_convex
    _, h = hull(np.random.default_rng(0), 60, [1.0, 0.5, 0.3])
    assert h.is_convex
    assert not as_soup(h).is_convex
    assert not tocsin.Mesh.torus_knot(100, 8).is_convex
    assert not tocsin.Mesh.plate(1.0, 4).is_convex
    assert "GJK" in tocsin.Mesh.is_convex.__doc__


def test_distance_against_the_general_path_and_scipy():
    """Hulls of 20 to 300 points apart (centres 1.2 to 3 apart): the distance equals the general
    path's to 1e-12 and is never below scipy's lower bound (the largest facet offset of the hull
    of all vertex differences), and within_distance agrees on both sides of it."""
    rng = np.random.default_rng(4)
    checked = 0
    for case in range(60):
        n = int(rng.choice([20, 60, 300]))
        pa, a = hull(rng, n, [1.0, 0.7, 0.5])
        pb, b = hull(rng, n, [0.6, 0.9, 0.4])
        d = rng.normal(size=3)
        p2 = random_pose(rng, d / np.linalg.norm(d) * rng.uniform(1.2, 3.0))
        fast = tocsin.distance(a, np.eye(4), b, p2)
        slow = tocsin.distance(as_soup(a), np.eye(4), as_soup(b), p2)
        assert abs(fast.distance - slow.distance) <= 1e-12, (case, fast.distance, slow.distance)
        if fast.distance == 0.0:
            continue
        checked += 1
        diff = (pa[:, None, :] - (pb @ p2[:3, :3].T + p2[:3, 3])[None, :, :]).reshape(-1, 3)
        lower = ConvexHull(diff).equations[:, 3].max()
        assert fast.distance >= lower - 1e-12, (case, fast.distance, lower)
        assert abs(np.linalg.norm(np.subtract(fast.point2, fast.point1)) - fast.distance) < 1e-12
        assert tocsin.within_distance(a, np.eye(4), b, p2, fast.distance * (1 + 1e-9))
        assert not tocsin.within_distance(a, np.eye(4), b, p2, fast.distance * (1 - 1e-9))
    assert checked >= 30


@pytest.mark.parametrize("kind", ["translation", "interp", "screw"])
def test_time_of_contact_against_sampling(kind):
    """Passes and near misses of two hulls of 100 points: the GJK path reports a contact exactly
    where the general path does (away from the band between half the tolerance and the
    tolerance), never after the first sampled collision, and where the meshes are within the
    tolerance."""
    rng = np.random.default_rng(["translation", "interp", "screw"].index(kind))
    _, a = hull(rng, 100, [1.0, 0.7, 0.5])
    _, b = hull(rng, 100, [0.6, 0.9, 0.4])
    sa, sb = as_soup(a), as_soup(b)
    still = tocsin.Motion.stationary(np.eye(4))
    contacts = 0
    for case in range(25):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        side = np.cross(d, rng.normal(size=3))
        side *= rng.uniform(0.0, 2.2) / np.linalg.norm(side)
        start, end = random_pose(rng, -3 * d + side), random_pose(rng, 3 * d + side)
        if kind == "translation":
            end[:3, :3] = start[:3, :3]
            motion = tocsin.Motion.translation(start, end)
        elif kind == "interp":
            motion = tocsin.Motion.interp(start, end)
        else:
            motion = tocsin.Motion.screw(start, end)
        fast = tocsin.time_of_contact(a, motion, b, still)
        slow = tocsin.time_of_contact(sa, motion, sb, still)
        delta = 1e-3 * min(a.bounding_radius, b.bounding_radius)
        ts = np.linspace(0.0, 1.0, 401)
        hits = [t for t in ts if tocsin.collide(a, motion.pose_at(t), b, np.eye(4))]
        closest = min(tocsin.distance(a, motion.pose_at(t), b, np.eye(4)).distance for t in ts)
        if hits:
            assert fast is not None, (case, hits[0])
            assert fast.time <= hits[0], (case, fast.time, hits[0])
        if fast is not None:
            contacts += 1
            assert fast.distance <= delta * (1 + 1e-9)
            assert tocsin.distance(a, motion.pose_at(fast.time), b, np.eye(4)).distance <= delta * (1 + 1e-9)
        if closest < 0.4 * delta or closest > 1.1 * delta:
            assert (fast is None) == (slow is None), (case, closest, delta)
    assert 5 <= contacts <= 22, contacts
