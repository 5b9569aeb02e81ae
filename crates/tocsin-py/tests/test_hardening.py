"""Edges a new user hits, each with the case that was reported (hardening issue)."""

import pydoc
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import tocsin


def rotvec(v):
    """Rotation matrix of a rotation vector (Rodrigues), without scipy."""
    v = np.asarray(v, float)
    t = np.linalg.norm(v)
    if t == 0:
        return np.eye(3)
    k = v / t
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K


def test_tiny_screw_meets_its_start_and_is_not_late():
    r0 = rotvec([0.2, 0.1, -0.3])
    start = np.eye(4)
    start[:3, :3], start[:3, 3] = r0, [1, 2, 3]
    end = np.eye(4)
    end[:3, :3], end[:3, 3] = rotvec([0, 0, 3e-12]) @ r0, [7, 2, 3]
    m = tocsin.Motion.screw(start, end)
    assert abs(m.pose_at(0) - start).max() < 1e-14  # was 7.3e-4
    assert abs(m.pose_at(np.nextafter(1.0, 0.0)) - end).max() < 1e-13
    box = tocsin.Mesh.box([0.5] * 3)
    obst = np.eye(4)
    obst[:3, 3] = [4, 2, 3]
    c = tocsin.time_of_contact(box, m, box, tocsin.Motion.stationary(obst), tolerance=1e-9)
    assert c is not None
    # The motion at the returned time does not overlap the obstacle.
    assert not tocsin.collide(box, m.pose_at(c.time), box, obst)
    assert c.distance <= 1e-9


def test_rounded_rotations_are_orthonormalized_on_request():
    pose = np.eye(4)
    pose[:3, :3] = np.round(rotvec([0.3, -1.2, 0.8]), 5)  # five digits: beyond the 1e-6 check
    pose[:3, 3] = [1, 2, 3]
    with pytest.raises(tocsin.PoseError):
        tocsin.distance(tocsin.Mesh.box([1, 1, 1]), pose, tocsin.Mesh.box([1, 1, 1]), np.eye(4))
    before = pose.copy()
    fixed = tocsin.orthonormalize(pose)
    assert np.array_equal(pose, before)  # the caller's array is untouched
    assert abs(fixed[:3, :3].T @ fixed[:3, :3] - np.eye(3)).max() < 1e-15
    assert abs(fixed - pose).max() < 2e-5
    tocsin.distance(tocsin.Mesh.box([1, 1, 1]), fixed, tocsin.Mesh.box([1, 1, 1]), np.eye(4))
    with pytest.raises(tocsin.PoseError):
        tocsin.orthonormalize(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(tocsin.PoseError, match=r"\(4, 4\)"):
        tocsin.orthonormalize(np.eye(3))


def test_normal_at_rounding_level_tolerance_is_the_approach_direction():
    box = tocsin.Mesh.box([0.5] * 3)
    start, end = np.eye(4), np.eye(4)
    start[0, 3], end[0, 3] = -3.0, 3.0
    c = tocsin.time_of_contact(box, tocsin.Motion.translation(start, end), box, tocsin.Motion.stationary(np.eye(4)), tolerance=1e-300)
    assert c is not None
    assert np.allclose(c.normal, [1, 0, 0], atol=1e-6), c.normal  # was [0, 0, 1]


def test_tolerance_below_the_distance_accuracy_is_a_contact_not_a_crawl():
    # A box a million units wide turning past a small one: with a tolerance of 1e-300 the
    # steps shrank with the distances' rounding and the query ran into IterationLimitError.
    # A pair within the distances' accuracy (2e-13 of the scene's scale) now ends it.
    size = 1e6
    big, small = tocsin.Mesh.box([0.5 * size] * 3), tocsin.Mesh.box([0.01 * size] * 3)
    axis = np.array([0.2, 0.3, 1.0]) / np.linalg.norm([0.2, 0.3, 1.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    start, end = np.eye(4), np.eye(4)
    end[:3, :3] = np.eye(3) + np.sin(np.pi / 3) * k + (1 - np.cos(np.pi / 3)) * k @ k
    start[:3, 3], end[:3, 3] = [-2 * size, 0.1 * size, 0.05 * size], [2 * size, -0.1 * size, 0]
    turn, still = tocsin.Motion.screw(start, end), tocsin.Motion.stationary(np.eye(4))
    c = tocsin.time_of_contact(big, turn, small, still, tolerance=1e-300)
    scale = big.bounding_radius + small.bounding_radius + np.linalg.norm(end[:3, 3])
    assert c is not None and c.iterations < 100 and c.distance <= 2e-13 * scale
    assert not any(tocsin.collide(big, turn.pose_at(t), small, np.eye(4)) for t in np.linspace(0, c.time, 400, endpoint=False))
    assert not tocsin.motion_is_free(big, turn, small, still, tolerance=1e-300)


def test_depth_with_a_tolerance_below_the_distance_accuracy_still_separates():
    # With tolerance=1e-300 the touching translations ended at rounding level and the bodies
    # still touched afterwards (collide True), on the exact convex path and the local search.
    rng = np.random.default_rng(7)
    for size in (1.0, 1e6):
        knot = tocsin.Mesh(np.asarray(tocsin.Mesh.torus_knot(100, 8).vertices) * size, tocsin.Mesh.torus_knot(100, 8).triangles)
        box = tocsin.Mesh.box([0.4 * size, 0.3 * size, 0.2 * size])
        for mesh in (knot, box):
            for _ in range(4):
                q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
                pose = np.eye(4)
                pose[:3, :3], pose[:3, 3] = q * np.sign(np.linalg.det(q)), rng.normal(size=3) * 0.1 * size
                r = tocsin.penetration_depth(mesh, np.eye(4), mesh, pose, tolerance=1e-300)
                moved = pose.copy()
                moved[:3, 3] += np.asarray(r.translation)
                assert r.status != "separated" and not tocsin.collide(mesh, np.eye(4), mesh, moved)


def test_point_mesh_default_tolerance_and_normal():
    point = tocsin.Mesh(np.zeros((1, 3)), np.zeros((1, 3), dtype=int))
    box = tocsin.Mesh.box([0.5] * 3)
    start, end = np.eye(4), np.eye(4)
    start[:3, 3], end[:3, 3] = [-3, 0.1, 0.2], [3, 0.1, 0.2]
    c = tocsin.time_of_contact(point, tocsin.Motion.translation(start, end), box, tocsin.Motion.stationary(np.eye(4)))
    assert c is not None and np.allclose(c.normal, [1, 0, 0], atol=1e-6)


def _far_knot_motion():
    knot = tocsin.Mesh.torus_knot(60, 6)
    start, end = np.eye(4), np.eye(4)
    start[0, 3], end[0, 3] = -12.0, 12.0
    return knot, tocsin.Motion.interp(start, end), tocsin.Motion.stationary(np.eye(4))


def test_iteration_limit_is_an_error_not_a_contact():
    knot, fly, still = _far_knot_motion()
    full = tocsin.time_of_contact(knot, fly, knot, still)
    assert full is not None and full.iterations > 2
    with pytest.raises(tocsin.IterationLimitError) as info:
        tocsin.time_of_contact(knot, fly, knot, still, max_iterations=2)
    err = info.value
    assert isinstance(err, tocsin.TocsinError) and isinstance(err, RuntimeError)
    assert err.iterations == 2 and 0 < err.time_reached < full.time
    assert not tocsin.collide(knot, fly.pose_at(err.time_reached), knot, np.eye(4))
    # The batch says it per row: no time, a status that is not a contact, how far it is free.
    starts = np.tile(fly.pose_at(0), (2, 1, 1))
    ends = np.tile(fly.pose_at(1), (2, 1, 1))
    b = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind="interp", max_iterations=2)
    assert list(b.status) == ["iteration_limit"] * 2
    assert np.isnan(b.time).all() and (b.iterations == 2).all()
    assert np.allclose(b.free_until, err.time_reached)
    ok = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind="interp")
    assert list(ok.status) == ["converged"] * 2 and np.allclose(ok.free_until, ok.time)


@pytest.mark.parametrize(
    "call, cls, match",
    [
        (lambda k, f, s: tocsin.time_of_contact(k, f, k, s, max_iterations=-1), tocsin.OptionsError, "at least 1"),
        (lambda k, f, s: tocsin.time_of_contact(k, f, k, s, max_iterations=0), tocsin.OptionsError, "at least 1"),
        (lambda k, f, s: tocsin.time_of_contact(k, f, k, s, max_iterations=10**30), tocsin.OptionsError, "max_iterations"),
        (lambda k, f, s: tocsin.time_of_contact(k, f, k, s, tolerance=0.0), tocsin.OptionsError, "positive"),
        (lambda k, f, s: tocsin.Mesh.torus_knot(-1, 5), tocsin.MeshError, "n_u"),
        (lambda k, f, s: tocsin.Mesh.sphere(1.0, 4, -2), tocsin.MeshError, "n_lon"),
        (lambda k, f, s: tocsin.Mesh.box([1, 1]), tocsin.MeshError, "3 elements"),
        (lambda k, f, s: tocsin.Mesh.box("abc"), tocsin.MeshError, "half_extents"),
        (lambda k, f, s: tocsin.Motion.interp(np.eye(4), np.eye(4), center=[1, 2]), tocsin.MotionError, "3 elements"),
        (lambda k, f, s: tocsin.distance(k, np.eye(3), k, np.eye(4)), tocsin.PoseError, r"shape \(4, 4\)"),
        (lambda k, f, s: tocsin.distance(k, np.zeros((4, 5)), k, np.eye(4)), tocsin.PoseError, r"shape \(4, 4\)"),
        (
            lambda k, f, s: tocsin.time_of_contact_batch(k, np.zeros((0, 4, 4)), np.zeros((0, 4, 4)), k, tolerance=-1.0),
            tocsin.OptionsError,
            "tolerance",
        ),
        (
            lambda k, f, s: tocsin.distance_batch(k, np.zeros((0, 4, 4)), k, np.eye(4), relative_error=-1.0),
            tocsin.OptionsError,
            "relative_error",
        ),
        (
            lambda k, f, s: tocsin.time_of_contact_batch(k, np.zeros((0, 4, 4)), np.zeros((0, 4, 4)), k, max_iterations=0),
            tocsin.OptionsError,
            "max_iterations",
        ),
    ],
)
def test_every_bad_argument_is_a_tocsin_error(call, cls, match):
    knot, fly, still = _far_knot_motion()
    with pytest.raises(cls, match=match):
        call(knot, fly, still)


@pytest.mark.parametrize(
    "vertices, match",
    [
        ([[0, 0, 0], [1e200, 0, 0], [0, 1, 0]], "supported range"),
        ([[0, 0, 0], [2e30, 0, 0], [0, 1, 0]], "supported range"),
        ([[0, 0, 0], [1e-200, 0, 0], [0, 1e-200, 0]], "below the supported"),
    ],
)
def test_extreme_scales_are_rejected(vertices, match):
    with pytest.raises(tocsin.MeshError, match=match):
        tocsin.Mesh(np.array(vertices, float), np.array([[0, 1, 2]]))


def test_extreme_translations_are_rejected_and_the_range_edges_work():
    box = tocsin.Mesh.box([1, 1, 1])
    far = np.eye(4)
    far[0, 3] = 1e200
    with pytest.raises(tocsin.PoseError, match="supported range"):
        tocsin.distance(box, np.eye(4), box, far)
    with pytest.raises(tocsin.PoseError):
        tocsin.Motion.translation(np.eye(4), far)
    # At the edges of the range distances are still right, and agree with collide.
    # (1e-30 to 1e30; past it meshes are refused: tests/supported_range.rs has every query.)
    for scale in (1e-30, 1e29):
        m = tocsin.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]) * scale, np.array([[0, 1, 2]]))
        pose = np.eye(4)
        pose[2, 3] = 2 * scale
        d = tocsin.distance(m, np.eye(4), m, pose)
        assert d.distance == pytest.approx(2 * scale, rel=1e-12)
        assert np.allclose(d.point2 - d.point1, [0, 0, 2 * scale], rtol=1e-12, atol=1e-12 * scale)
        assert not tocsin.collide(m, np.eye(4), m, pose)
        assert tocsin.within_distance(m, np.eye(4), m, pose, 2.5 * scale)


def test_out_of_memory_is_a_memory_error_not_an_abort():
    # Under a 4 GiB address-space limit, 1e9 triangles cannot fit: the interpreter must live.
    script = textwrap.dedent(
        """
        import resource, sys
        resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
        import tocsin
        try:
            tocsin.Mesh.torus_knot(25000, 20000)
        except MemoryError as e:
            assert isinstance(e, tocsin.OutOfMemoryError) and isinstance(e, tocsin.TocsinError)
            print("memory error:", e)
        knot = tocsin.Mesh.torus_knot(50, 8)  # still usable afterwards
        print("alive", knot.num_triangles)
        """
    )
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "memory error:" in out.stdout and "alive 800" in out.stdout


def test_version_and_help_show_signatures():
    from importlib.metadata import version

    assert tocsin.__version__ == version("tocsin")
    text = pydoc.render_doc(tocsin.distance, renderer=pydoc.plaintext)
    assert "relative_error=0.0" in text and "Exact by default" in text
    text = pydoc.render_doc(tocsin.Mesh, renderer=pydoc.plaintext)
    assert "Mesh(vertices, triangles)" in text and "(N, 3)" in text
    text = pydoc.render_doc(tocsin.time_of_contact, renderer=pydoc.plaintext)
    assert "max_iterations=None" in text and "IterationLimitError" in text


def test_package_metadata_promises_only_what_exists():
    from importlib.metadata import metadata

    summary = metadata("tocsin")["Summary"].lower()
    # Every capability the summary names exists in the package.
    assert "penetration" in summary and hasattr(tocsin, "penetration_depth")
    assert "robots" in summary and hasattr(tocsin, "Robot")


def test_plot_to_a_file_leaves_the_backend_alone(tmp_path):
    import matplotlib
    before = matplotlib.get_backend()
    box = tocsin.Mesh.box([0.5] * 3)
    pose = np.eye(4)
    pose[0, 3] = 2.0
    tocsin.plot_contact(box, np.eye(4), box, pose, path=str(tmp_path / "c.png"))
    assert (tmp_path / "c.png").stat().st_size > 1000
    assert matplotlib.get_backend() == before


def test_pybullet_meshes_load_like_trimesh():
    """pybullet's Panda link6.obj has 19 `l` polylines that became zero-area triangles up to
    0.39 mm off the surface; now the triangles are trimesh's, and so are the distances."""
    import os

    import pybullet_data
    import trimesh

    root = pybullet_data.getDataPath()
    rng = np.random.default_rng(5)
    box = tocsin.Mesh.box([0.01, 0.01, 0.01])
    for rel in ("franka_panda/meshes/collision/link6.obj", "franka_panda/meshes/collision/link0.obj", "cube.obj"):
        path = os.path.join(root, rel)
        ours = tocsin.Mesh.load(path)
        ref = trimesh.load(path, force="mesh", process=False)
        theirs = tocsin.Mesh(ref.vertices, ref.faces)
        assert ours.num_triangles == theirs.num_triangles, rel
        for _ in range(20):
            pose = np.eye(4)
            pose[:3, :3] = rotvec(rng.normal(size=3))
            pose[:3, 3] = rng.normal(size=3) * 0.1
            a = tocsin.distance(ours, np.eye(4), box, pose).distance
            b = tocsin.distance(theirs, np.eye(4), box, pose).distance
            assert a == pytest.approx(b, rel=1e-12, abs=1e-15), rel


def test_pointwise_and_hausdorff_with_an_error_bound_below_the_distance_accuracy_answer():
    # max_error=1e-16 on a knot's pointwise depth of 0.37 subdivided for minutes (a bound that
    # rounds away can never be met); it is now raised to the distances' accuracy.
    knot = tocsin.Mesh.torus_knot(100, 8)
    rng = np.random.default_rng(3)

    def turned(shift):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        p = np.eye(4)
        p[:3, :3], p[:3, 3] = q * np.sign(np.linalg.det(q)), shift
        return p

    p1 = turned(np.zeros(3))
    p2 = turned(rng.normal(size=3) * 0.3)
    scale = 2 * knot.bounding_radius + np.linalg.norm(p2[:3, 3])
    for bound in (1e-16, 1e-300):
        r = tocsin.pointwise_penetration(knot, p1, knot, p2, max_error=bound)
        assert r.depth > 0 and r.upper_bound - r.depth <= 2e-13 * scale * (1 + 1e-9)
        h = tocsin.hausdorff_distance(knot, p1, knot, p2, max_error=bound, symmetric=True)
        assert h.upper_bound - h.distance <= 2e-13 * scale * (1 + 1e-9)


def test_too_many_depth_directions_is_an_options_error_not_an_abort():
    # directions=10**10 asked for 240 GB at once and aborted the interpreter.
    knot = tocsin.Mesh.torus_knot(100, 8)
    pose = np.eye(4)
    pose[:3, 3] = [0.2, 0.1, 0.0]
    for directions in (1_000_001, 10**10):
        with pytest.raises(tocsin.OptionsError, match="directions"):
            tocsin.penetration_depth(knot, np.eye(4), knot, pose, directions=directions)


def test_query_points_and_huge_counts_are_options_errors():
    # A NaN point had a winding number of NaN and an infinite one was "outside"; an int beyond
    # the machine's range was said to need to be "at least 1".
    knot = tocsin.Mesh.torus_knot(60, 6)
    for bad in ([np.nan, 0, 0], [0, np.inf, 0], [0, 0, 1e31]):
        points = np.array([[0.0, 0.0, 0.0], bad])
        with pytest.raises(tocsin.OptionsError, match="points row 1"):
            tocsin.winding_number(knot, np.eye(4), points)
        with pytest.raises(tocsin.OptionsError, match="points row 1"):
            tocsin.contains(knot, np.eye(4), points)
    start = np.eye(4)
    start[0, 3] = 5.0
    motion, still = tocsin.Motion.translation(start, np.eye(4)), tocsin.Motion.stationary(np.eye(4))
    for huge in (2**70, 2**200):
        with pytest.raises(tocsin.OptionsError, match="at most"):
            tocsin.time_of_contact(knot, motion, knot, still, max_iterations=huge)


def test_huge_values_in_messages_are_written_with_an_exponent():
    # A configuration of 1e300 was reported as a 301-digit number, as were a tolerance of
    # -1e300 and a generator size of -1e300.
    import os

    import pybullet_data

    knot = tocsin.Mesh.torus_knot(60, 6)
    motion, still = tocsin.Motion.translation(np.eye(4), np.eye(4)), tocsin.Motion.stationary(np.eye(4))
    robot = tocsin.Robot.from_urdf(os.path.join(pybullet_data.getDataPath(), "franka_panda/panda.urdf"))
    world = tocsin.World()
    world.add_body(knot, motion)
    calls = [
        (tocsin.OptionsError, lambda: tocsin.time_of_contact(knot, motion, knot, still, tolerance=-1e300)),
        (tocsin.OptionsError, lambda: world.earliest_contact(tolerance=-1e300)),
        (tocsin.OptionsError, lambda: tocsin.orthonormalize(np.eye(4), max_error=-1e300)),
        (tocsin.MeshError, lambda: tocsin.Mesh.sphere(-1e300, 8, 8)),
        (tocsin.ConfigurationError, lambda: robot.in_collision(np.full(robot.dof, 1e300))),
    ]
    for cls, call in calls:
        with pytest.raises(cls) as info:
            call()
        message = str(info.value)
        assert "1e300" in message and not any(len(w) > 30 for w in message.split()), message
