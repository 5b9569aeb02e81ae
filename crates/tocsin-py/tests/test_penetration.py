"""Inside and outside of a soup from Python: contains against an independent ray-parity count
on a watertight torus, the winding number's exact and fast modes, errors."""

import numpy as np
import pytest
import trimesh

import tocsin

from _geometry import ray_parity_inside


def test_contains_matches_ray_parity_on_a_watertight_torus():
    m = trimesh.creation.torus(1.0, 0.3)
    assert m.is_watertight
    mesh = tocsin.Mesh.from_trimesh(m)
    pose = np.eye(4)
    pose[:3, :3] = trimesh.transformations.rotation_matrix(0.7, [0.3, 1.0, 0.2])[:3, :3]
    pose[:3, 3] = [3.0, -1.0, 0.5]
    rng = np.random.default_rng(3)
    local = rng.uniform(-1.5, 1.5, size=(1500, 3))
    world = local @ pose[:3, :3].T + pose[:3, 3]
    oracle = ray_parity_inside(np.asarray(m.vertices), np.asarray(m.faces), local)
    got = tocsin.contains(mesh, pose, world)
    # Away from the surface (the oracle's rays can graze an edge there), the answers agree.
    point = tocsin.Mesh(np.zeros((1, 3)), np.zeros((1, 3), dtype=np.int64))
    far = []
    for p in world:
        at = np.eye(4)
        at[:3, 3] = p
        far.append(tocsin.distance(mesh, pose, point, at).distance > 1e-3)
    far = np.array(far)
    assert far.sum() > 1400 and oracle.sum() > 100
    np.testing.assert_array_equal(got[far], oracle[far])
    exact = tocsin.winding_number(mesh, pose, world, exact=True)
    np.testing.assert_allclose(exact[far], oracle[far].astype(float), atol=1e-9)
    fast = tocsin.winding_number(mesh, pose, world)
    assert np.abs(fast - exact).max() < 0.05
    assert world.flags.writeable and np.allclose(world, local @ pose[:3, :3].T + pose[:3, 3])


def test_bad_input_raises_the_packages_errors():
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    with pytest.raises(tocsin.OptionsError):
        tocsin.winding_number(box, np.eye(4), np.zeros((3, 3)), beta=0.5)
    with pytest.raises(tocsin.OptionsError):
        tocsin.contains(box, np.eye(4), np.zeros((3, 2)))
    with pytest.raises(tocsin.PoseError):
        tocsin.contains(box, np.eye(3), np.zeros((3, 3)))
    assert tocsin.contains(box, np.eye(4), np.zeros((0, 3))).shape == (0,)


def test_hausdorff_of_offset_plates_and_a_sphere_in_a_bigger_one():
    box = tocsin.Mesh.box([1.0, 1.0, 1.0])
    moved = np.eye(4)
    moved[:3, 3] = [0.0, 0.0, 0.25]
    r = tocsin.hausdorff_distance(box, np.eye(4), box, moved, max_error=1e-9, symmetric=True)
    assert abs(r.distance - 0.25) < 1e-9 and r.upper_bound - r.distance <= 1e-9
    assert abs(np.linalg.norm(r.point2 - r.point1) - r.distance) < 1e-12
    # A sphere of radius 1 inside a concentric one of radius 2: every point of the small one
    # is about 1 from the big one (tessellation: chords within 2% of the radius).
    small, big = tocsin.Mesh.sphere(1.0, 16, 32), tocsin.Mesh.sphere(2.0, 16, 32)
    one = tocsin.hausdorff_distance(small, np.eye(4), big, np.eye(4), max_error=1e-4)
    assert 0.95 < one.distance <= one.upper_bound < 1.01 and one.from_first
    with pytest.raises(tocsin.OptionsError):
        tocsin.hausdorff_distance(box, np.eye(4), box, moved, max_error=-1.0)


def box_sat_depth(h1, p1, h2, p2):
    """Exact penetration depth of two boxes: the smallest overlap over the 15 SAT axes."""
    a, b = p1[:3, :3].T, p2[:3, :3].T
    axes = list(a) + list(b)
    for x in a:
        for y in b:
            c = np.cross(x, y)
            if np.linalg.norm(c) > 1e-9:
                axes.append(c / np.linalg.norm(c))
    d = p2[:3, 3] - p1[:3, 3]
    ext = lambda rows, h, u: sum(h[i] * abs(rows[i] @ u) for i in range(3))
    return min(ext(a, h1, u) + ext(b, h2, u) - abs(d @ u) for u in axes)


def test_penetration_depth_of_boxes_and_its_guarantee():
    rng = np.random.default_rng(5)
    h1, h2 = np.array([0.5, 0.3, 0.8]), np.array([0.4, 0.6, 0.2])
    b1, b2 = tocsin.Mesh.box(h1), tocsin.Mesh.box(h2)
    checked = 0
    for _ in range(30):
        p1, p2 = np.eye(4), np.eye(4)
        for p, s in [(p1, 0.2), (p2, 0.6)]:
            p[:3, :3] = trimesh.transformations.random_rotation_matrix(rng.random(3))[:3, :3]
            p[:3, 3] = rng.uniform(-s, s, 3)
        exact = box_sat_depth(h1, p1, h2, p2)
        if exact < 1e-3:
            continue
        checked += 1
        tol = 1e-3 * min(b1.bounding_radius, b2.bounding_radius)
        r = tocsin.penetration_depth(b1, p1, b2, p2)
        assert r.status == "converged" and r.exact
        assert abs(r.depth - exact) <= 1e-9 * exact
        local = tocsin.penetration_depth(b1, p1, b2, p2, exact_convex=False)
        assert not local.exact and exact - 2 * tol <= local.depth <= 1.03 * exact + 2 * tol
        for res in (r, local):
            after = p2.copy()
            after[:3, 3] += res.translation
            assert not tocsin.collide(b1, p1, b2, after)
            assert tocsin.distance(b1, p1, b2, after).distance <= tol * (1 + 1e-9)
    assert checked >= 15
    apart = np.eye(4)
    apart[0, 3] = 5.0
    s = tocsin.penetration_depth(b1, np.eye(4), b2, apart)
    assert s.status == "separated" and s.depth == 0.0
    with pytest.raises(tocsin.OptionsError):
        tocsin.penetration_depth(b1, np.eye(4), b2, np.eye(4), tolerance=-1.0)
    for starts in (0, -1, 1.5):
        with pytest.raises(tocsin.OptionsError):
            tocsin.penetration_depth(b1, np.eye(4), b2, np.eye(4), exact_convex=False, starts=starts)


def test_more_starts_never_give_a_deeper_answer():
    knot = tocsin.Mesh.torus_knot(100, 8)
    rng = np.random.default_rng(8)
    shallower = 0
    for _ in range(12):
        pose = np.eye(4)
        pose[:3, :3] = trimesh.transformations.random_rotation_matrix(rng.random(3))[:3, :3]
        pose[:3, 3] = rng.normal(size=3) * 0.3 * knot.bounding_radius
        if not tocsin.collide(knot, np.eye(4), knot, pose):
            continue
        depths = []
        for starts in (1, 2, 3):
            r = tocsin.penetration_depth(knot, np.eye(4), knot, pose, starts=starts)
            after = pose.copy()
            after[:3, 3] += r.translation
            assert not tocsin.collide(knot, np.eye(4), knot, after)
            depths.append(r.depth)
        assert depths[2] <= depths[1] * (1 + 1e-12) and depths[1] <= depths[0] * (1 + 1e-12)
        shallower += depths[2] < depths[0] * (1 - 1e-12)
    assert shallower > 0


def test_pointwise_penetration_of_overlapping_cubes():
    cube = tocsin.Mesh.box([0.5, 0.5, 0.5])
    shifted = np.eye(4)
    shifted[0, 3] = 0.8
    r = tocsin.pointwise_penetration(cube, np.eye(4), cube, shifted, max_error=1e-6)
    assert abs(r.depth - 0.2) < 1e-6 and r.upper_bound - r.depth <= 1e-6 + 1e-12
    apart = np.eye(4)
    apart[0, 3] = 3.0
    assert tocsin.pointwise_penetration(cube, np.eye(4), cube, apart).depth == 0.0


def test_convex_polytopes_against_the_minkowski_difference_hull():
    """The exact depth of two convex polytopes is the distance from the origin to the boundary of
    the convex hull of all vertex differences (scipy's ConvexHull as the independent oracle)."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(9)
    checked = 0
    for case in range(40):
        pts_a = rng.normal(size=(rng.integers(6, 20), 3)) * rng.uniform(0.2, 1.0, 3)
        pts_b = rng.normal(size=(rng.integers(6, 20), 3)) * rng.uniform(0.05, 1.0, 3)  # thin slabs too
        ha, hb = ConvexHull(pts_a), ConvexHull(pts_b)
        a = tocsin.Mesh(pts_a, ha.simplices.astype(np.int64))
        b = tocsin.Mesh(pts_b, hb.simplices.astype(np.int64))
        p2 = np.eye(4)
        p2[:3, 3] = rng.normal(size=3) * rng.choice([0.05, 0.3, 0.8])  # deep and shallow
        moved_b = pts_b + p2[:3, 3]
        diff = (pts_a[:, None, :] - moved_b[None, :, :]).reshape(-1, 3)
        hull = ConvexHull(diff)
        # Inside the hull when every facet's n . x + d <= 0; the depth is min(-d) at the origin.
        if (hull.equations[:, 3] >= 0).any():
            continue  # separated: the origin is outside the difference
        oracle = (-hull.equations[:, 3]).min()
        r = tocsin.penetration_depth(a, np.eye(4), b, p2)
        checked += 1
        assert r.status == "converged", (case, r.status, oracle)
        assert r.exact
        assert abs(r.depth - oracle) <= 1e-9 * max(oracle, 1e-12), (case, r.depth, oracle)
    assert checked >= 20


def test_large_convex_hulls_against_the_minkowski_difference_hull():
    """Hulls of 200 points on two ellipsoids (about 400 faces and 600 edges each: the Gauss-map
    path's grid, climbs and bounds all at work) at random rotations and shifts: the exact depth
    equals the distance from the origin to the boundary of scipy's hull of all 40,000 vertex
    differences."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(12)
    pts = []
    for semi in ([1.0, 0.7, 0.5], [0.6, 0.9, 0.4]):
        p = rng.normal(size=(200, 3))
        pts.append(p / np.linalg.norm(p, axis=1)[:, None] * semi)
    a, b = (tocsin.Mesh(p, ConvexHull(p).simplices.astype(np.int64)) for p in pts)
    checked = 0
    for case in range(12):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        q *= np.sign(np.linalg.det(q))
        p2 = np.eye(4)
        p2[:3, :3], p2[:3, 3] = q, rng.normal(size=3) * 0.4
        diff = (pts[0][:, None, :] - (pts[1] @ q.T + p2[:3, 3])[None, :, :]).reshape(-1, 3)
        eq = ConvexHull(diff).equations
        r = tocsin.penetration_depth(a, np.eye(4), b, p2)
        assert r.exact, case
        if (eq[:, 3] >= 0).any():
            assert r.status == "separated", (case, r.depth)
            continue
        oracle = (-eq[:, 3]).min()
        checked += 1
        assert abs(r.depth - oracle) <= 1e-9 * oracle, (case, r.depth, oracle)
        assert abs(np.linalg.norm(r.direction) - 1.0) < 1e-12
    assert checked >= 8
