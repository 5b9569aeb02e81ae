"""tocsin.distributed on a local Ray cluster (2 CPUs, loopback): the same results as the local
batches, in input order, for any chunk size; failures reported with their chunk, or retried."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import tocsin
from _geometry import turn

import ray  # installed by `make test`

from tocsin import distributed

ROOT = pathlib.Path(__file__).resolve().parents[3]
PANDA = ROOT / "data" / "franka_panda" / "panda.urdf"


@pytest.fixture(scope="module")
def cluster():
    info = ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield info.address_info["address"]
    ray.shutdown()


def knot_poses(n, seed):
    rng = np.random.default_rng(seed)
    return np.stack([turn(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(-6, 6, size=3)) for _ in range(n)])


def same(a, b):
    if isinstance(a, tuple):
        assert a._fields == b._fields
        for f in a._fields:
            np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)
    else:
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("chunk", [1, 7, 65536, None])
def test_same_results_as_the_local_batches(cluster, chunk):
    knot = tocsin.Mesh.torus_knot(120, 10)
    poses = knot_poses(40, 1)
    same(distributed.distance_batch(knot, poses, knot, np.eye(4), chunk_size=chunk),
         tocsin.distance_batch(knot, poses, knot, np.eye(4)))
    other = knot_poses(40, 2)
    collide = distributed.collide_batch(knot, poses, knot, other, chunk_size=chunk)
    same(collide, tocsin.collide_batch(knot, poses, knot, other))
    assert 0 < collide.sum() < 40
    ends = knot_poses(40, 3)
    d = distributed.time_of_contact_batch(knot, poses, ends, knot, kind="screw", chunk_size=chunk)
    same(d, tocsin.time_of_contact_batch(knot, poses, ends, knot, kind="screw"))
    d = distributed.time_of_contact_batch(knot, poses, ends, knot, kind="screw", contact_pair=True, chunk_size=chunk)
    same(d, tocsin.time_of_contact_batch(knot, poses, ends, knot, kind="screw", contact_pair=True))
    assert 0 < np.isfinite(d.time).sum() < 40
    f = distributed.motion_is_free_batch(knot, poses, ends, knot, kind="screw", chunk_size=chunk)
    same(f, tocsin.motion_is_free_batch(knot, poses, ends, knot, kind="screw"))
    assert list(f.free) == list(~np.isfinite(d.time))


def test_a_mesh_is_put_once_across_calls(cluster):
    # The same mesh as both bodies, in two calls: one object-store copy (one token, so each
    # worker rebuilds it once); another mesh object gets its own; the answers stay the same.
    knot = tocsin.Mesh.torus_knot(120, 10)
    poses, other = knot_poses(20, 4), knot_poses(20, 5)
    local = tocsin.collide_batch(knot, poses, knot, other)
    first = distributed._share(ray, knot)
    same(distributed.collide_batch(knot, poses, knot, other, chunk_size=3), local)
    same(distributed.collide_batch(knot, poses, knot, other, chunk_size=5), local)
    assert distributed._share(ray, knot) == first
    copy = tocsin.Mesh(knot.vertices, knot.triangles)
    assert distributed._share(ray, copy)[0] != first[0]
    same(distributed.collide_batch(copy, poses, knot, other, chunk_size=4), local)


def test_a_mesh_put_on_a_cluster_since_shut_down_is_put_again():
    # A new local cluster in the same process numbers its jobs from 1 again: a remembered mesh
    # of the old one must not be passed to it (its reference has no owner there).
    code = (
        "import numpy as np, ray, tocsin\n"
        "from tocsin import distributed\n"
        "knot = tocsin.Mesh.torus_knot(60, 8)\n"
        "poses = np.stack([np.eye(4)] * 3); poses[:, 0, 3] = [0.0, 0.5, 9.0]\n"
        "for _ in range(2):\n"
        "    ray.init(num_cpus=1, include_dashboard=False, log_to_driver=False)\n"
        "    r = distributed.collide_batch(knot, poses, knot, np.eye(4))\n"
        "    assert r.tolist() == [True, True, False], r\n"
        "    ray.shutdown()\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and out.stdout.strip().endswith("ok"), out.stderr[-2000:]


def test_robot_edges_and_configurations(cluster):
    robot = tocsin.Robot.from_urdf(str(PANDA))
    scene = tocsin.Scene()
    scene.add("plate", tocsin.Mesh.box([0.3, 0.3, 0.0005]), turn([1, 0, 0], 0.0, [0.45, 0, 0.3]))
    rng = np.random.default_rng(5)
    lo, hi = robot.joint_limits[:, 0], robot.joint_limits[:, 1]
    q0 = rng.uniform(lo, hi, size=(50, robot.dof))
    q1 = np.clip(q0 + rng.normal(scale=0.4, size=q0.shape), lo, hi)
    for chunk in (1, 7, 65536):
        free = distributed.paths_are_free(robot, q0, q1, scene, chunk_size=chunk)
        same(free, robot.paths_are_free(q0, q1, scene))
        same(distributed.check_configurations(robot, q0, scene, chunk_size=chunk), robot.check_configurations(q0, scene))
    assert 0 < free.sum() < 50


def test_empty_input(cluster):
    knot = tocsin.Mesh.torus_knot(60, 6)
    empty = np.zeros((0, 4, 4))
    same(distributed.distance_batch(knot, empty, knot, np.eye(4)), tocsin.distance_batch(knot, empty, knot, np.eye(4)))
    same(distributed.collide_batch(knot, empty, knot, empty), tocsin.collide_batch(knot, empty, knot, empty))
    same(distributed.time_of_contact_batch(knot, empty, empty, knot), tocsin.time_of_contact_batch(knot, empty, empty, knot))
    same(distributed.motion_is_free_batch(knot, empty, empty, knot), tocsin.motion_is_free_batch(knot, empty, empty, knot))


def test_a_bad_chunk_is_reported_with_its_index(cluster):
    knot = tocsin.Mesh.torus_knot(60, 6)
    poses = knot_poses(20, 4)
    poses[13, 0, 0] = 7.0  # not a rotation: a PoseError in chunk 13 // 5 = 2
    with pytest.raises(tocsin.DistributedError) as err:
        distributed.distance_batch(knot, poses, knot, np.eye(4), chunk_size=5)
    assert err.value.chunk == 2
    assert "rows 10:15" in str(err.value)
    assert isinstance(err.value.__cause__, tocsin.PoseError)
    with pytest.raises(tocsin.DistributedError):
        distributed.distance_batch(knot, poses, knot, np.eye(4), chunk_size=0)


def test_a_failing_worker_is_retried(cluster, tmp_path):
    marker = tmp_path / "crashed"

    def crash_once(poses):
        # The first attempt of the chunk holding row 3 kills its worker process outright.
        if len(poses) and poses[0][0, 3] == 3.0 and not marker.exists():
            marker.write_text("x")
            os._exit(1)
        return poses[:, 0, 3] * 2.0

    def fail_once(poses):
        flag = tmp_path / f"raised{poses[0][0, 3]}"
        if not flag.exists():
            flag.write_text("x")
            raise OSError("transient")
        return poses[:, 0, 3] * 2.0

    rows = np.repeat(np.eye(4)[None], 8, axis=0)
    rows[:, 0, 3] = np.arange(8)
    for fn in (crash_once, fail_once):
        out = distributed._run(fn, {}, {"poses": rows}, {}, 8, 3, None, False, 3)
        np.testing.assert_array_equal(out, np.arange(8) * 2.0)
    assert marker.exists()

    def always(poses):
        raise OSError("broken disk")

    with pytest.raises(tocsin.DistributedError) as err:
        distributed._run(always, {}, {"poses": rows}, {}, 8, 4, None, False, 1)
    assert err.value.chunk == 0


def test_command_line(cluster, tmp_path):
    knot = tocsin.Mesh.torus_knot(60, 6)
    poses = knot_poses(30, 6)
    queries = tmp_path / "q.npz"
    np.savez(queries, query="distance", mesh1_vertices=knot.vertices, mesh1_triangles=knot.triangles,
             mesh2_vertices=knot.vertices, mesh2_triangles=knot.triangles, poses1=poses, poses2=np.eye(4))
    results = tmp_path / "r.npz"
    out = subprocess.run([sys.executable, "-m", "tocsin.distributed", str(queries), str(results),
                          "--address", cluster, "--chunk-size", "4"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    got = np.load(results)
    np.testing.assert_array_equal(got["distance"], tocsin.distance_batch(knot, poses, knot, np.eye(4)).distance)
    bad = subprocess.run([sys.executable, "-m", "tocsin.distributed", str(tmp_path / "missing.npz"), str(results)],
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode == 2 and "tocsin.distributed:" in bad.stderr


def test_the_core_package_never_imports_ray():
    code = "import sys, tocsin; assert 'ray' not in sys.modules; print('ok')"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "ok", out.stderr


def test_an_unreachable_cluster_is_a_clear_error():
    code = (
        "import tocsin, tocsin.distributed as d\n"
        "try:\n    d.connect('127.0.0.1:1')\n"
        "except tocsin.DistributedError as e:\n    print('refused:', e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert "refused: cannot reach the Ray cluster at 127.0.0.1:1" in out.stdout, out.stdout + out.stderr


def test_many_worlds(cluster):
    knot = tocsin.Mesh.torus_knot(60, 8)
    worlds = []
    rng = np.random.default_rng(12)
    for _ in range(9):
        w = tocsin.World()
        w.add_static(tocsin.Mesh.plate(30.0, 2), np.eye(4))
        for _ in range(6):
            start = turn(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(-6, 6, size=3) + [0, 0, 5])
            end = turn(rng.normal(size=3), rng.uniform(0, 3), rng.uniform(-6, 6, size=3) - [0, 0, 5])
            w.add_body(knot, tocsin.Motion.screw(start, end))
        worlds.append(w)
    local = [distributed.WorldContacts.of(w.first_contacts()) for w in worlds]
    for chunk in (1, 4, 65536):
        got = distributed.first_contacts(worlds, chunk_size=chunk)
        assert len(got) == len(local)
        for g, l in zip(got, local):
            same(g, l)
    assert sum(len(l.time) for l in local) > 9
    assert distributed.first_contacts([]) == []


def test_tasks_as_wide_as_threads_per_task(cluster):
    def width(rows):
        """A chunk's view of its task: the CPUs Ray gave it and its pool's width, per row (a
        nested function, so the workers get it by value)."""
        cpus = ray.get_runtime_context().get_assigned_resources().get("CPU")
        return [(cpus, os.environ.get("RAYON_NUM_THREADS"))] * len(rows)

    knot = tocsin.Mesh.torus_knot(120, 10)
    poses, ends = knot_poses(30, 4), knot_poses(30, 5)
    local = tocsin.time_of_contact_batch(knot, poses, ends, knot, kind="screw")
    for threads in (1, 2):
        for chunk in (4, None):
            same(distributed.time_of_contact_batch(knot, poses, ends, knot, kind="screw", chunk_size=chunk,
                                                   threads_per_task=threads), local)
        seen = distributed._run(width, {}, {"rows": np.arange(10)}, {}, 10, 3, None, False, 0, threads)
        assert seen == [(float(threads), str(threads))] * 10


@pytest.mark.parametrize("threads", [0, -1, 1.5, True, "2", 3])
def test_a_bad_or_too_wide_threads_per_task_is_a_clear_error(cluster, threads):
    knot = tocsin.Mesh.torus_knot(120, 10)
    poses = knot_poses(4, 6)
    # 3 is wider than the 2-CPU cluster's only node: Ray would wait for it forever.
    with pytest.raises(distributed.DistributedError, match="threads_per_task"):
        distributed.distance_batch(knot, poses, knot, np.eye(4), threads_per_task=threads)
