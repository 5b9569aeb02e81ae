"""Batch queries equal K single queries, in order; NaN where there is no contact."""

import numpy as np
import pytest

import tocsin


def poses(k, seed, spread=3.0):
    rng = np.random.default_rng(seed)
    out = np.tile(np.eye(4), (k, 1, 1))
    for p in out:
        a = rng.normal(size=3)
        a /= np.linalg.norm(a)
        th = rng.uniform(0, np.pi)
        kk = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        p[:3, :3] = np.eye(3) + np.sin(th) * kk + (1 - np.cos(th)) * kk @ kk
        p[:3, 3] = rng.uniform(-spread, spread, 3)
    return out


def test_distance_and_collide_batches_match_singles():
    knot = tocsin.Mesh.torus_knot(80, 8)
    p1, p2 = poses(30, 1), poses(30, 2)
    b = tocsin.distance_batch(knot, p1, knot, p2)
    assert b.distance.shape == (30,) and b.point1.shape == (30, 3)
    for k in range(30):
        r = tocsin.distance(knot, p1[k], knot, p2[k])
        assert b.distance[k] == r.distance and b.triangle2[k] == r.triangle2
        assert np.array_equal(b.point1[k], r.point1)
    hits = tocsin.collide_batch(knot, p1, knot, p2)
    assert hits.dtype == bool
    assert list(hits) == [tocsin.collide(knot, p1[k], knot, p2[k]) for k in range(30)]
    # A single pose for body 2 is broadcast.
    b2 = tocsin.distance_batch(knot, p1, knot, np.eye(4))
    assert b2.distance[3] == tocsin.distance(knot, p1[3], knot, np.eye(4)).distance


def test_time_of_contact_batch_matches_singles():
    knot = tocsin.Mesh.torus_knot(80, 8)
    ends = poses(12, 3, spread=1.0)
    ends[6:, 1, 3] += 12.0  # these six pass far away: no contact
    starts = ends.copy()
    starts[:, 0, 3] += 12.0
    b = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind="screw")
    for k in range(12):
        r = tocsin.time_of_contact(knot, tocsin.Motion.screw(starts[k], ends[k]), knot, tocsin.Motion.stationary(np.eye(4)))
        if r is None:
            assert np.isnan(b.time[k]) and b.status[k] == "none" and b.triangle1[k] == -1
            assert np.isnan(b.point1[k]).all()
        else:
            assert b.time[k] == r.time and b.status[k] == r.status
            assert np.array_equal(b.normal[k], r.normal)
    assert (b.status != "none").any() and (b.status == "none").any()


def test_motion_is_free_batch_matches_singles():
    knot = tocsin.Mesh.torus_knot(80, 8)
    ends = poses(16, 4, spread=1.0)
    ends[8:, 1, 3] += 12.0  # these eight pass far away: free
    starts = ends.copy()
    starts[:, 0, 3] += 12.0
    still = tocsin.Motion.stationary(np.eye(4))
    for kind, make in [("screw", tocsin.Motion.screw), ("interp", tocsin.Motion.interp)]:
        b = tocsin.motion_is_free_batch(knot, starts, ends, knot, kind=kind)
        assert isinstance(b, tocsin.FreeBatch)
        assert b.free.dtype == bool and b.decided.dtype == bool and b.free.shape == (16,)
        assert b.decided.all()
        singles = [tocsin.motion_is_free(knot, make(starts[k], ends[k]), knot, still) for k in range(16)]
        assert list(b.free) == singles
        assert b.free[8:].all() and not b.free[:8].all()
        # The same yes/no as the time of contact's.
        toc = tocsin.time_of_contact_batch(knot, starts, ends, knot, kind=kind)
        assert list(b.free) == list(toc.status == "none")
    # Body 2 moving instead, body 1 still at the identity.
    eye = np.tile(np.eye(4), (16, 1, 1))
    b2 = tocsin.motion_is_free_batch(knot, eye, eye, knot, starts2=starts, ends2=ends, kind="screw")
    singles = [tocsin.motion_is_free(knot, still, knot, tocsin.Motion.screw(starts[k], ends[k])) for k in range(16)]
    assert list(b2.free) == singles and b2.free.any() and not b2.free.all()


def test_motion_is_free_batch_undecided_rows():
    knot = tocsin.Mesh.torus_knot(60, 6)
    start, end = np.eye(4), np.eye(4)
    start[0, 3], end[0, 3] = -12.0, 12.0
    start[1, 3] = end[1, 3] = 7.5  # passes beside the copy: free, after several iterations
    b = tocsin.motion_is_free_batch(knot, start[None], end[None], knot, kind="interp", max_iterations=1)
    assert list(b.decided) == [False] and list(b.free) == [False]
    with pytest.raises(tocsin.IterationLimitError):
        tocsin.motion_is_free(knot, tocsin.Motion.interp(start, end), knot, tocsin.Motion.stationary(np.eye(4)), max_iterations=1)
    ok = tocsin.motion_is_free_batch(knot, start[None], end[None], knot, kind="interp")
    assert list(ok.decided) == [True] and list(ok.free) == [True]
    with pytest.raises(tocsin.OptionsError, match="tolerance"):
        tocsin.motion_is_free_batch(knot, np.zeros((0, 4, 4)), np.zeros((0, 4, 4)), knot, tolerance=-1.0)
    with pytest.raises(tocsin.MotionError, match="unknown motion kind"):
        tocsin.motion_is_free_batch(knot, poses(2, 1), poses(2, 2), knot, kind="wobble")
    empty = tocsin.motion_is_free_batch(knot, np.zeros((0, 4, 4)), np.zeros((0, 4, 4)), knot)
    assert empty.free.shape == (0,) and empty.decided.shape == (0,)


def test_batch_errors():
    knot = tocsin.Mesh.torus_knot(40, 6)
    with pytest.raises(tocsin.PoseError, match="expected 3"):
        tocsin.distance_batch(knot, poses(3, 1), knot, poses(4, 1))
    bad = poses(3, 1)
    bad[1, 0, 0] = 2.0
    with pytest.raises(tocsin.PoseError, match=r"poses1\[1\]"):
        tocsin.collide_batch(knot, bad, knot, np.eye(4))
    with pytest.raises(tocsin.MotionError, match="unknown motion kind"):
        tocsin.time_of_contact_batch(knot, poses(2, 1), poses(2, 2), knot, kind="wobble")
    with pytest.raises(tocsin.PoseError, match="shape"):
        tocsin.collide_batch(knot, np.eye(3), knot, np.eye(4))
