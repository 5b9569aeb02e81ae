"""Pointwise depth and the Hausdorff distance against dense sampling at huge and tiny scales and
far from the origin: surface points on a barycentric grid, inside by ray parity and distances by
brute force over every triangle (numpy, `_geometry`), none of it tocsin's code."""

import numpy as np

import tocsin

from _geometry import mesh_distances, ray_parity_inside, surface_grid, turn


def closed_meshes(rng):
    """Two watertight meshes of the library's generators, sizes drawn."""
    makers = [
        lambda: tocsin.Mesh.sphere(1.0, int(rng.integers(4, 10)), int(rng.integers(6, 14))),
        lambda: tocsin.Mesh.box(rng.uniform(0.2, 1.5, 3)),
        lambda: tocsin.Mesh.torus_knot(int(rng.integers(24, 40)), 5),
        lambda: tocsin.Mesh.cylinder(rng.uniform(0.2, 0.8), rng.uniform(0.3, 2.0)),
    ]
    return makers[rng.integers(0, len(makers))](), makers[rng.integers(0, len(makers))]()


def placed_cases(seed, count):
    """(mesh1, pose1, world vertices 1, mesh2, pose2, world vertices 2, scale, offset): the
    meshes scaled by 1e-6 to 1e6, overlapping or near, every other case 1e2 to 1e6 sizes from
    the origin."""
    rng = np.random.default_rng(seed)
    for case in range(count):
        m1, m2 = closed_meshes(rng)
        scale = 10.0 ** rng.uniform(-6, 6)
        offset = rng.normal(size=3) * scale * 10.0 ** rng.uniform(2, 6) if case % 2 else np.zeros(3)
        m1 = tocsin.Mesh(m1.vertices * scale, m1.triangles)
        m2 = tocsin.Mesh(m2.vertices * scale, m2.triangles)
        p1 = turn(rng.normal(size=3), rng.uniform(0, np.pi), offset)
        p2 = turn(rng.normal(size=3), rng.uniform(0, np.pi), offset + rng.normal(size=3) * scale * 0.8)
        w1 = m1.vertices @ p1[:3, :3].T + p1[:3, 3]
        w2 = m2.vertices @ p2[:3, :3].T + p2[:3, 3]
        yield m1, p1, w1, m2, p2, w2, scale, float(np.abs(offset).max())


def test_pointwise_depth_against_dense_sampling_at_extreme_scales():
    """Every sampled surface point inside the other mesh is no deeper than the upper bound, the
    depth is within the error of the deepest sample or above it, and the witness point is at
    the depth from the other surface."""
    deep = 0
    for m1, p1, w1, m2, p2, w2, scale, offset in placed_cases(5, 24):
        error = 1e-3 * min(m1.bounding_radius, m2.bounding_radius)
        got = tocsin.pointwise_penetration(m1, p1, m2, p2, max_error=error)
        rounding = 1e-9 * (scale + offset)
        sampled = 0.0
        for wa, fa, wb, fb in [(w1, m1.triangles, w2, m2.triangles), (w2, m2.triangles, w1, m1.triangles)]:
            points = surface_grid(wa, fa, 2)
            inside = ray_parity_inside(wb, fb, points)
            if inside.any():
                sampled = max(sampled, float(mesh_distances(points[inside], wb, fb).max()))
        assert sampled <= got.upper_bound + rounding, (scale, offset, sampled, got.upper_bound)
        assert got.depth >= sampled - error - rounding, (scale, offset, sampled, got.depth)
        assert got.depth <= got.upper_bound <= got.depth + error * (1 + 1e-9) + rounding
        if got.depth > 0:
            deep += 1
            other = (w2, m2.triangles) if got.from_first else (w1, m1.triangles)
            at = float(mesh_distances(got.point1[None], *other)[0])
            assert abs(at - got.depth) <= 1e-7 * got.depth + rounding, (at, got.depth)
            assert abs(np.linalg.norm(got.point2 - got.point1) - got.depth) <= 1e-7 * got.depth + rounding
    assert deep >= 12, deep


def test_hausdorff_distance_against_dense_sampling_at_extreme_scales():
    """One-sided and symmetric: no sampled point is farther from the other surface than the
    upper bound, and the distance is within the error of the farthest sample or above it."""
    for m1, p1, w1, m2, p2, w2, scale, offset in placed_cases(6, 24):
        error = 1e-3 * max(m1.bounding_radius, m2.bounding_radius)
        rounding = 1e-9 * (scale + offset)
        one = float(mesh_distances(surface_grid(w1, m1.triangles, 2), w2, m2.triangles).max())
        other = float(mesh_distances(surface_grid(w2, m2.triangles, 2), w1, m1.triangles).max())
        for symmetric, sampled in [(False, one), (True, max(one, other))]:
            got = tocsin.hausdorff_distance(m1, p1, m2, p2, max_error=error, symmetric=symmetric)
            assert sampled <= got.upper_bound + rounding, (symmetric, scale, offset, sampled, got.upper_bound)
            assert got.distance >= sampled - error - rounding, (symmetric, scale, offset, sampled, got.distance)
            assert got.distance <= got.upper_bound <= got.distance + error * (1 + 1e-9) + rounding
