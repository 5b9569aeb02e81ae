"""The binding end to end: results against a numpy brute force, poses, errors, no mutation."""

import itertools

import numpy as np
import pytest

import tocsin

from _geometry import point_triangle_distances


def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def pose(axis=(0, 0, 1), angle=0.0, t=(0, 0, 0)):
    m = np.eye(4)
    m[:3, :3] = rotation(axis, angle)
    m[:3, 3] = t
    return m


def point_triangle(p, a, b, c):
    """Distance from p to triangle abc (the brute-force kernel of ``_geometry``)."""
    return float(point_triangle_distances(np.asarray(p, float)[None], a[None], b[None], c[None])[0, 0])


def test_distance_matches_vertex_brute_force_on_boxes():
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    rng = np.random.default_rng(5)
    for _ in range(20):
        p2 = pose(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(1.5, 3, size=3) * rng.choice([-1, 1], 3))
        r = tocsin.distance(box, np.eye(4), box, p2)
        assert r.point1.shape == (3,) and r.point2.shape == (3,)
        assert np.isclose(np.linalg.norm(r.point1 - r.point2), r.distance, rtol=1e-9, atol=1e-12)
        # The witness on mesh 2 is on its reported triangle (world frame).
        v2 = box.vertices @ p2[:3, :3].T + p2[:3, 3]
        tri = v2[box.triangles[r.triangle2]]
        assert point_triangle(r.point2, *tri) < 1e-9
        # No vertex of either box is closer to the other's triangles than the result.
        for a_idx, b_idx in itertools.product(range(8), range(12)):
            t = v2[box.triangles[b_idx]]
            assert point_triangle(box.vertices[a_idx], *t) >= r.distance - 1e-9


def test_collide_and_within():
    knot = tocsin.Mesh.torus_knot(100, 8)
    assert knot.num_triangles == 1600
    far = pose(t=(20, 0, 0))
    assert not tocsin.collide(knot, np.eye(4), knot, far)
    assert tocsin.collide(knot, np.eye(4), knot, pose((1, 0, 0), 0.3, (0.2, 0, 0)))
    d = tocsin.distance(knot, np.eye(4), knot, far).distance
    assert tocsin.within_distance(knot, np.eye(4), knot, far, d * 1.0001)
    assert not tocsin.within_distance(knot, np.eye(4), knot, far, d * 0.9999)
    pairs = tocsin.collide_pairs(knot, np.eye(4), knot, pose((1, 0, 0), 0.3, (0.2, 0, 0)))
    assert pairs.ndim == 2 and pairs.shape[1] == 2 and len(pairs) > 0


def test_approximate_distance_bounds():
    knot = tocsin.Mesh.torus_knot(80, 8)
    p2 = pose((0, 1, 0), 0.5, (9, 1, 0))
    exact = tocsin.distance(knot, np.eye(4), knot, p2).distance
    approx = tocsin.distance(knot, np.eye(4), knot, p2, relative_error=0.2).distance
    assert exact <= approx <= exact * 1.2 + 1e-12


def test_mesh_from_arrays_lists_and_dtypes_without_mutation():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    t = np.array([[0, 1, 2]], dtype=np.int32)
    v0, t0 = v.copy(), t.copy()
    m = tocsin.Mesh(v, t)
    assert (m.num_vertices, m.num_triangles) == (3, 1)
    assert np.array_equal(v, v0) and np.array_equal(t, t0)
    m2 = tocsin.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    assert m2.num_triangles == 1
    # Poses: lists are fine, and the caller's pose is untouched.
    p = [[1, 0, 0, 2], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    assert tocsin.distance(m, np.eye(4), m2, p).distance == pytest.approx(1.0)


@pytest.mark.parametrize(
    "vertices, triangles, match",
    [
        (np.zeros((3, 3)), np.zeros((0, 3), dtype=np.int64), "no triangles"),
        (np.zeros((3, 3)), [[0, 1, 3]], "out of range"),
        (np.zeros((3, 3)), [[0, -1, 2]], "out of range"),
        ([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], [[0, 1, 2]], "not finite"),
        ([[0, 0, 0], [1, np.inf, 0], [0, 1, 0]], [[0, 1, 2]], "not finite"),
        (np.zeros((3, 2)), [[0, 1, 2]], "shape"),
        (np.zeros((3, 3)), [[0, 1]], "shape"),
        (np.zeros((3, 3)), [[0.0, 1.0, 2.0]], "integer"),
        ("abc", [[0, 1, 2]], "vertices"),
    ],
)
def test_bad_meshes_raise_mesh_error(vertices, triangles, match):
    with pytest.raises(tocsin.MeshError, match=match) as info:
        tocsin.Mesh(vertices, triangles)
    assert isinstance(info.value, ValueError)
    assert isinstance(info.value, tocsin.TocsinError)


def test_bad_files(tmp_path):
    with pytest.raises(tocsin.MeshFileError) as info:
        tocsin.Mesh.load(tmp_path / "missing.obj")
    assert isinstance(info.value, OSError)
    (tmp_path / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 oops\nf 1 2 3\n")
    with pytest.raises(tocsin.MeshError, match="line 3"):
        tocsin.Mesh.load(tmp_path / "bad.obj")
    (tmp_path / "x.xyz").write_text("hello")
    with pytest.raises(tocsin.MeshError, match="unknown mesh format"):
        tocsin.Mesh.load(tmp_path / "x.xyz")
    (tmp_path / "ok.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n")
    assert tocsin.Mesh.load(str(tmp_path / "ok.obj")).num_triangles == 2


@pytest.mark.parametrize(
    "bad, match",
    [
        (np.eye(3), "shape"),
        (np.diag([1.0, 1.0, -1.0, 1.0]), "determinant"),
        (np.diag([2.0, 1.0, 1.0, 1.0]), "orthonormal"),
        (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]), "last row"),
        (np.full((4, 4), np.nan), "NaN"),
        ("not a pose", "pose2"),
    ],
)
def test_bad_poses_raise_pose_error(bad, match):
    box = tocsin.Mesh.box([1, 1, 1])
    with pytest.raises(tocsin.PoseError, match=match):
        tocsin.distance(box, np.eye(4), box, bad)
    with pytest.raises(tocsin.PoseError):
        tocsin.collide(box, np.eye(4), box, bad)


def test_bad_options_raise_options_error():
    box = tocsin.Mesh.box([1, 1, 1])
    with pytest.raises(tocsin.OptionsError):
        tocsin.distance(box, np.eye(4), box, np.eye(4), relative_error=-1.0)
    with pytest.raises(tocsin.OptionsError):
        tocsin.within_distance(box, np.eye(4), box, np.eye(4), float("nan"))


def test_rigid_within_tolerance_is_accepted():
    box = tocsin.Mesh.box([1, 1, 1])
    p = pose((1, 2, 3), 0.7, (5, 0, 0))
    p[:3, :3] += 1e-8
    assert tocsin.distance(box, np.eye(4), box, p).distance > 0


def test_queries_release_the_gil():
    import threading
    import time

    knot = tocsin.Mesh.torus_knot(344, 16)
    p2 = pose((0, 1, 0), 0.4, (9, 0, 0))
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=ticker)
    th.start()
    start = time.perf_counter()
    while time.perf_counter() - start < 0.3:
        tocsin.distance(knot, np.eye(4), knot, p2)
    stop.set()
    th.join()
    assert len(ticks) > 50, "the other thread should run while queries do"


def test_non_contiguous_and_list_poses_match():
    box = tocsin.Mesh.box([0.5, 0.5, 0.5])
    p = pose((1, 2, 3), 0.7, (3, 0, 0))
    strided = np.asfortranarray(p)
    as_list = p.tolist()
    d = tocsin.distance(box, np.eye(4), box, p).distance
    assert tocsin.distance(box, np.eye(4), box, strided).distance == d
    assert tocsin.distance(box, np.eye(4), box, as_list).distance == d
    assert tocsin.distance(box, np.eye(4), box, p[:, :].T.T).distance == d


def test_from_trimesh_duck_type():
    class FakeTrimesh:
        vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]])
        faces = np.array([[0, 1, 2]])

    m = tocsin.Mesh.from_trimesh(FakeTrimesh())
    assert m.num_triangles == 1
    with pytest.raises(tocsin.MeshError, match="no `vertices`"):
        tocsin.Mesh.from_trimesh(object())


def test_from_real_trimesh():
    import trimesh
    box = trimesh.creation.box(extents=[1.0, 1.0, 1.0])
    m = tocsin.Mesh.from_trimesh(box)
    assert m.num_triangles == len(box.faces)
    p = np.eye(4)
    p[0, 3] = 3.0
    assert tocsin.distance(m, np.eye(4), m, p).distance == pytest.approx(2.0)
