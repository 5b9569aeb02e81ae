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
