"""Geometry for the tests, independent of tocsin: poses (a rotation about an axis with a
translation, as a 4x4 array), inside by ray parity, and brute-force point-to-mesh distances."""

import numpy as np


def turn(axis, angle, t):
    """The pose turning by `angle` (radians) about `axis` (any length), then moved by `t`."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    p = np.eye(4)
    p[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    p[:3, 3] = t
    return p


def ray_parity_inside(vertices, faces, points):
    """Inside by counting crossings of a ray along (1, 0.3, 0.17) (Moller-Trumbore), numpy."""
    d = np.array([1.0, 0.3, 0.17])
    d /= np.linalg.norm(d)
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    e1, e2 = b - a, c - a
    h = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, h)
    inside = np.zeros(len(points), bool)
    ok = np.abs(det) > 1e-14
    for k, p in enumerate(points):
        s = p - a
        u = np.einsum("ij,ij->i", s, h) / np.where(ok, det, 1.0)
        q = np.cross(s, e1)
        v = (q @ d) / np.where(ok, det, 1.0)
        t = np.einsum("ij,ij->i", e2, q) / np.where(ok, det, 1.0)
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
        inside[k] = hit.sum() % 2 == 1
    return inside


def point_triangle_distances(points, a, b, c):
    """Distances (P, T) from each point (P, 3) to each triangle (corners a, b, c: (T, 3) each):
    the closest point by Voronoi regions of the corners, edges and face (Ericson's test),
    vectorised; a degenerate triangle (a segment or a point) by its three edges."""
    p = points[:, None, :]
    ab, ac = (b - a)[None], (c - a)[None]
    a, b, c = a[None], b[None], c[None]
    d1, d2 = (ab * (p - a)).sum(-1), (ac * (p - a)).sum(-1)
    d3, d4 = (ab * (p - b)).sum(-1), (ac * (p - b)).sum(-1)
    d5, d6 = (ab * (p - c)).sum(-1), (ac * (p - c)).sum(-1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        face = a + ab * (vb / (va + vb + vc))[..., None] + ac * (vc / (va + vb + vc))[..., None]
        on_ab = a + ab * (d1 / (d1 - d3))[..., None]
        on_ac = a + ac * (d2 / (d2 - d6))[..., None]
        on_bc = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))[..., None]
    x = face
    for region, q in [
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), on_ab),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), on_ac),
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), on_bc),
        ((d1 <= 0) & (d2 <= 0), np.broadcast_to(a, x.shape)),
        ((d3 >= 0) & (d4 <= d3), np.broadcast_to(b, x.shape)),
        ((d6 >= 0) & (d5 <= d6), np.broadcast_to(c, x.shape)),
    ]:
        x = np.where(region[..., None], q, x)
    dist = np.sqrt(((p - x) ** 2).sum(-1))
    degenerate = ~np.isfinite(x).all(-1)
    if degenerate.any():

        def segment(q0, q1):
            d = q1 - q0
            dd = (d * d).sum(-1)
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.where(dd > 0, np.clip(((p - q0) * d).sum(-1) / dd, 0, 1), 0.0)
            return np.sqrt(((p - q0 - d * t[..., None]) ** 2).sum(-1))

        edges = np.minimum(np.minimum(segment(a, b), segment(b, c)), segment(c, a))
        dist = np.where(degenerate, edges, dist)
    return dist


def mesh_distances(points, vertices, faces, chunk=256):
    """Distance from each point (P, 3) to the nearest triangle of the mesh, brute force."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    out = np.empty(len(points))
    for i in range(0, len(points), chunk):
        out[i : i + chunk] = point_triangle_distances(points[i : i + chunk], a, b, c).min(1)
    return out


def surface_grid(vertices, faces, k):
    """Points of every triangle on a barycentric grid of k steps per edge (corners included)."""
    w = np.array([(1 - i / k - j / k, i / k, j / k) for i in range(k + 1) for j in range(k + 1 - i)])
    return np.einsum("kw,twj->tkj", w, vertices[faces]).reshape(-1, 3)
