"""Convex polytopes take the GJK path of distance and time_of_contact: the same answers as the
general path on the same surface (a degenerate triangle added makes it a soup), checked against
scipy's hull of the vertex differences and against sampled collision tests."""

import numpy as np
import pytest

import tocsin

from scipy.spatial import ConvexHull  # installed by `make test`


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


def nasty_hull(rng, kind=None, size=None, n=None):
    """A seeded convex hull among the shapes that broke the convex paths or nearly did: needles,
    pancakes, nearly flat caps, gridded boxes with rounding noise, prisms of many sides, sliver
    tetrahedra, at sizes from 1e-6 to 1e6; triangles wound outwards. `kind`, `size` and `n` force
    one shape, size and point count."""
    kind = int(rng.integers(7)) if kind is None else kind
    n = int(rng.choice([4, 8, 20, 100])) if n is None else n
    semi = [(1, 10 ** rng.uniform(-4, -1), 10 ** rng.uniform(-4, -1)), (1, 1, 10 ** rng.uniform(-5, -1))]
    p = rng.normal(size=(n, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    if kind < 2:
        p *= semi[kind]
    elif kind == 2:
        p[:, 2] = np.abs(p[:, 2]) * 1e-3 + 1.0
        p = np.vstack([p, [[0, 0, 0]]])
    elif kind == 3:
        g = np.array(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1])).reshape(3, -1).T.astype(float)
        g = g[np.abs(g).max(axis=1) == 1] * rng.uniform(0.2, 1, 3)
        p = g + rng.normal(size=g.shape) * 1e-9
    elif kind == 4:
        a = np.linspace(0, 2 * np.pi, int(rng.choice([16, 64])), endpoint=False)
        h = 10 ** rng.uniform(-3, 0)
        p = np.vstack([np.c_[np.cos(a), np.sin(a), np.full(a.size, z)] for z in (-h, h)])
    elif kind == 5:
        p = rng.normal(size=(4, 3))
        p[:, 2] *= 10 ** rng.uniform(-8, -3)
    p = p * (10.0 ** rng.choice([0, 0, -6, 6]) if size is None else size)
    t = ConvexHull(p).simplices.astype(np.int64)
    c = p.mean(axis=0)
    n = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    flip = np.einsum("ij,ij->i", n, p[t[:, 0]] - c) < 0
    t[flip] = t[flip][:, ::-1]
    return tocsin.Mesh(p, t)


def brute_depth(a, pa, b, pb):
    """The exact depth of two convex polytopes: the smallest support overlap over every face
    normal of both and every cross product of an edge of each (loops over every corner)."""
    A = np.asarray(a.vertices) @ pa[:3, :3].T + pa[:3, 3]
    B = np.asarray(b.vertices) @ pb[:3, :3].T + pb[:3, 3]

    def normals_edges(V, T):
        T = np.asarray(T)
        e = [V[T[:, (i + 1) % 3]] - V[T[:, i]] for i in range(3)]
        return np.cross(e[0], -e[2]), np.vstack(e)

    na, ea = normals_edges(A, a.triangles)
    nb, eb = normals_edges(B, b.triangles)
    d = np.vstack([na, nb, np.cross(ea[:, None, :], eb[None, :, :]).reshape(-1, 3)])
    length = np.linalg.norm(d, axis=1)
    d = d[length > 0] / length[length > 0, None]
    d = np.vstack([d, -d])
    return ((A @ d.T).max(axis=0) - (B @ d.T).min(axis=0)).min()


def test_nasty_shapes_against_the_general_path_and_brute_force():
    """Seeded pairs of nasty hulls (above), a sixth of them a hull against its own copy, placed
    apart, at gaps of 1e-2 to 1e-11 of their reach, touching and overlapping: distance and
    within_distance equal the general path's, the exact depth equals the brute force over every
    candidate direction (small meshes) and its translation separates, and a time of contact
    (default tolerance, 1e-7 of the smaller radius, or 1e-300) is never late against dense
    samples, within the tolerance or the distances' accuracy where it ends, and agrees with
    motion_is_free. The first ten pairs are the kinds of the two defects the fuzzing of these
    paths found (about 6,900 pairs; docs/BENCHMARKS.md, fortieth session): coincident pancakes
    whose depth was taken as 0, and a box a million wide turning through a micron one with a
    tolerance of 1e-300, which crawled to the iteration cap. The build before the fixes fails
    on both."""
    rng = np.random.default_rng(40)
    depths = contacts = 0
    for case in range(160):
        # The first ten are the two defects' kinds: pancakes a million wide against their own
        # copy, coincident (depth), and a box a million wide turning through a micron one with
        # a tolerance of 1e-300 (time of contact).
        if case < 5:
            a = nasty_hull(rng, kind=1, size=1e6, n=20)
            b = a
        elif case < 10:
            a, b = nasty_hull(rng, kind=3, size=1e-6), nasty_hull(rng, kind=3, size=1e6)
        else:
            a = nasty_hull(rng)
            b = a if case % 6 == 0 else nasty_hull(rng)
        if not (a.is_convex and b.is_convex):
            continue
        sa, sb = as_soup(a), as_soup(b)
        reach = a.bounding_radius + b.bounding_radius
        pa = random_pose(rng, np.zeros(3))
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        pb = random_pose(rng, d * reach * rng.uniform(0.2, 1.5))
        gap = [None, 1e-2, 1e-5, 1e-8, 1e-11, 0.0, -1e-3][case % 7]
        if case < 10:
            gap = None
        if case < 5:
            pb = pa.copy()
        if gap is not None:
            r = tocsin.distance(sa, pa, sb, pb)
            if r.distance > 0:
                n = np.subtract(r.point2, r.point1) / r.distance
                pb[:3, 3] -= n * (r.distance - gap * reach)
        fast, slow = tocsin.distance(a, pa, b, pb), tocsin.distance(sa, pa, sb, pb)
        assert abs(fast.distance - slow.distance) <= 1e-11 * reach, (case, fast.distance, slow.distance)
        for threshold in (slow.distance * (1 - 1e-6), slow.distance * (1 + 1e-6)):
            if abs(threshold - slow.distance) > 1e-10 * reach:
                assert tocsin.within_distance(a, pa, b, pb, threshold) == (slow.distance <= threshold)
        if slow.distance <= 1e-12 * reach and tocsin.collide(sa, pa, sb, pb):
            depth = tocsin.penetration_depth(a, pa, b, pb)
            if a.num_triangles * b.num_triangles <= 20000:
                assert abs(depth.depth - max(brute_depth(a, pa, b, pb), 0.0)) <= 1e-10 * reach, case
            if depth.depth > 1e-12 * reach:
                depths += 1
                assert depth.exact, case
                moved = pb.copy()
                moved[:3, 3] += np.asarray(depth.translation)
                assert not tocsin.collide(sa, pa, sb, moved), case
        if slow.distance > 0:
            end = random_pose(rng, -d * reach * rng.uniform(-0.5, 1.5) + rng.normal(size=3) * reach * 0.3)
            if 5 <= case < 10:
                end[:3, 3] = -pb[:3, 3]  # through the small one
            motion = (tocsin.Motion.interp if case % 2 else tocsin.Motion.screw)(pb, end)
            still = tocsin.Motion.stationary(pa)
            tol = None if case % 3 else 1e-7 * min(a.bounding_radius, b.bounding_radius)
            if 5 <= case < 10:
                tol = 1e-300
            c = tocsin.time_of_contact(a, still, b, motion, tolerance=tol)
            assert tocsin.motion_is_free(a, still, b, motion, tolerance=tol) == (c is None), case
            delta = tol if tol is not None else max(1e-3 * min(a.bounding_radius, b.bounding_radius), 1e-6 * max(a.bounding_radius, b.bounding_radius))
            limit = c.time if c is not None else 1.0
            times = np.linspace(0, limit, 200, endpoint=c is None)
            samples = [tocsin.distance(sa, pa, sb, motion.pose_at(t)).distance for t in times if c is None or t < limit]
            assert min(samples, default=np.inf) >= delta / 2 - 1e-12 * reach, case
            if c is not None:
                contacts += 1
                scene = reach + np.linalg.norm(end[:3, 3]) + np.linalg.norm(pb[:3, 3])
                assert c.distance <= max(delta, 2e-13 * scene) * (1 + 1e-9), (case, c.distance, delta)
    assert depths >= 10 and contacts >= 40, (depths, contacts)
