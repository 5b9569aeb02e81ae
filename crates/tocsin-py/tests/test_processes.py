"""tocsin under multiprocessing (fork, forkserver, spawn), process pools and threads.

Regression: after any mesh build in a parent, a child made by os.fork() hung forever on its
first mesh build or batch (rayon's global pool has no threads in the child)."""

import concurrent.futures as cf
import multiprocessing as mp
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import tocsin


def _work(seed: int) -> tuple[float, int]:
    """A mesh build (parallel), a distance batch (parallel), a time of contact and a symmetric
    Hausdorff distance (its two directions run on two threads)."""
    knot = tocsin.Mesh.torus_knot(60 + seed, 8)
    poses = np.tile(np.eye(4), (8, 1, 1))
    poses[:, 0, 3] = np.linspace(7.0, 9.0, 8)
    batch = tocsin.distance_batch(knot, poses, knot, np.eye(4))
    start, end = np.eye(4), np.eye(4)
    start[0, 3], end[0, 3] = -12.0, 12.0
    c = tocsin.time_of_contact(knot, tocsin.Motion.translation(start, end), knot, tocsin.Motion.stationary(np.eye(4)))
    assert c is not None
    h = tocsin.hausdorff_distance(knot, np.eye(4), knot, poses[0], max_error=1e-2, symmetric=True)
    assert h.distance <= h.upper_bound
    return float(batch.distance.sum()) + round(h.distance, 9), knot.num_triangles


def _expected(seeds):
    return [_work(s) for s in seeds]


def _warm_parent():
    # The parent builds (and so starts its thread pool) before forking: the case that hung.
    tocsin.Mesh.torus_knot(100, 10)
    tocsin.distance_batch(tocsin.Mesh.box([1, 1, 1]), np.tile(np.eye(4), (4, 1, 1)), tocsin.Mesh.box([1, 1, 1]), np.eye(4))


@pytest.mark.parametrize("method", ["fork", "forkserver", "spawn"])
def test_multiprocessing_pool(method):
    if method not in mp.get_all_start_methods():
        pytest.fail(f"start method {method} missing on {sys.platform}")
    _warm_parent()
    seeds = [0, 1, 2, 3]
    with mp.get_context(method).Pool(2) as pool:
        got = pool.map_async(_work, seeds).get(timeout=120)
    assert got == _expected(seeds)


def test_process_pool_executor_with_fork():
    _warm_parent()
    with cf.ProcessPoolExecutor(2, mp_context=mp.get_context("fork")) as ex:
        got = list(ex.map(_work, [5, 6], timeout=120))
    assert got == _expected([5, 6])


def _robot_work():
    """A robot loaded from its URDF (its meshes built) and one segment checked."""
    import pybullet_data

    urdf = os.path.join(pybullet_data.getDataPath(), "franka_panda", "panda.urdf")
    robot = tocsin.Robot.from_urdf(urdf)
    lo, hi = robot.joint_limits[:, 0], robot.joint_limits[:, 1]
    q0, q1 = 0.6 * lo + 0.4 * hi, 0.4 * lo + 0.6 * hi
    return robot.dof, bool(robot.path_is_free(q0, q1, tocsin.Scene()))


def _fork_and_wait(work):
    """Runs `work` in a child made by a bare os.fork(); fails the test if the child hangs."""
    pid = os.fork()
    if pid == 0:  # the child: report through the exit status
        try:
            work()
            os._exit(0)
        except BaseException:
            os._exit(3)
    deadline_status = None
    for _ in range(1200):  # up to 120 s
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            deadline_status = status
            break
        import time

        time.sleep(0.1)
    if deadline_status is None:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
        pytest.fail("the forked child hung")
    assert os.waitstatus_to_exitcode(deadline_status) == 0


def test_bare_os_fork_child_builds_and_exits():
    _warm_parent()
    _fork_and_wait(lambda: _work(7))


def test_robot_loads_in_a_forked_child():
    # Regression: robots were loaded on rayon's global pool, so a parent that had loaded one
    # made every forked child hang on its own first robot.
    expected = _robot_work()

    def child():
        assert _robot_work() == expected

    _fork_and_wait(child)


def test_threads_give_the_single_thread_answers():
    seeds = list(range(6))
    expected = _expected(seeds)
    with cf.ThreadPoolExecutor(4) as ex:
        assert list(ex.map(_work, seeds)) == expected


def _world_work(args):
    """A World's first contacts in a child, on a Mesh the parent pickled to it."""
    mesh, seed = args
    world = tocsin.World()
    world.add_static(tocsin.Mesh.plate(40.0, 2), np.eye(4))
    n = 6
    starts = np.tile(np.eye(4), (n, 1, 1))
    ends = starts.copy()
    starts[:, 0, 3] = np.arange(n) * 9.0 - 20.0
    starts[:, 2, 3] = 5.0 + seed
    ends[:, 0, 3] = starts[:, 0, 3]
    ends[:, 2, 3] = -5.0
    ids = [world.add_body(mesh, np.eye(4)) for _ in range(n)]
    world.set_motions(ids, starts, ends, kind="translation")
    return [(c.body1, c.body2, c.time) for c in world.first_contacts()]


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_worlds_in_child_processes_with_pickled_meshes(method):
    _warm_parent()
    knot = tocsin.Mesh.torus_knot(60, 8)
    jobs = [(knot, s) for s in (0, 1, 2)]
    with mp.get_context(method).Pool(2) as pool:
        got = pool.map_async(_world_work, jobs).get(timeout=120)
    expected = [_world_work(j) for j in jobs]
    assert got == expected
    assert all(len(g) >= 4 for g in got)


def test_a_fresh_robots_paths_in_one_batch_do_not_deadlock():
    # Regression (forty-first session): a hull built inside a query, under its mesh's
    # OnceLock, waited for a rayon pool; the waiting worker stole another path of the batch
    # on the same mesh, which waited on the same OnceLock. Run in a child with a deadline, so
    # that a deadlock fails the test instead of hanging the suite.
    code = textwrap.dedent(
        """
        import os, numpy as np, pybullet_data, tocsin
        urdf = os.path.join(pybullet_data.getDataPath(), "franka_panda", "panda.urdf")
        robot = tocsin.Robot.from_urdf(urdf)
        lo, hi = robot.joint_limits[:, 0], robot.joint_limits[:, 1]
        rng = np.random.default_rng(4)
        q0 = lo + (hi - lo) * rng.random((64, robot.dof))
        q1 = np.clip(q0 + rng.normal(0, 0.5, q0.shape), lo, hi)
        free = robot.paths_are_free(q0, q1, tocsin.Scene())
        print(len(free), int(np.sum(free)))
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    count, _ = out.stdout.split()
    assert int(count) == 64
