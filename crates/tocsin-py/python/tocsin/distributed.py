"""tocsin's batch queries on a Ray cluster, with the same results as the local batches.

Install with ``pip install "tocsin[ray]"``; ``import tocsin`` never imports ray, only this
module does. The batches: :func:`distance_batch`, :func:`collide_batch`,
:func:`time_of_contact_batch`, :func:`motion_is_free_batch`, a robot's :func:`paths_are_free` and
:func:`check_configurations`, and :func:`first_contacts` of many worlds. Each batch is cut into
chunks of rows; each chunk runs as a Ray task calling the local batch function, and the
chunks' results are put back together
in input order: the answer is identical, bit for bit, to the local batch's. A task takes one of
Ray's CPUs and runs its chunk on one thread (``RAYON_NUM_THREADS=1`` in the workers), so a
cluster of N CPUs runs N chunks at once. With ``threads_per_task=k`` a task takes k CPUs and
runs its chunk on k threads (fewer worker processes: on one 16-CPU node, k=2 measured 11.3x
the one-CPU throughput twice, where k=1 gave 7.6x to 12.0x; docs/BENCHMARKS.md); a k larger
than every node's CPU count is an error, since Ray would wait for such a node forever.

Keywords every batch takes, after its own: ``chunk_size`` (rows per task; default an even
split in eight tasks per slot of the cluster, at most :data:`DEFAULT_CHUNK` rows), ``address``
(the cluster, as :func:`connect` takes it), ``progress`` (show the chunks done; tqdm when it is
installed), ``max_retries`` (Ray's retries of a chunk whose worker failed, below) and
``threads_per_task`` (each task's CPUs and threads, default 1; above).

Meshes, robots and scenes go into Ray's object store once per call (``ray.put``), not once per
task; a worker process unpickles each of them (rebuilding a mesh's hierarchy: 34 ms for the
34,000-triangle knot) the first time one of its tasks needs it, then keeps it for the later
tasks of the call (a per-process cache, the benefit of an actor pool without its bookkeeping;
docs/BENCHMARKS.md has the comparison). A :class:`~tocsin.Mesh` cannot change once built, so
the same mesh object, given twice in a call or again in later calls on the same cluster, is
put once and rebuilt once per worker (the last 32 meshes are remembered, with a reference that
keeps them alive); robots and scenes, which can be edited, are put again at every call.

Starting a cluster (shell)::

    ray start --head                       # on the head node; prints its address
    ray start --address HEAD_IP:6379       # on every other node

then ``tocsin.distributed.connect("auto")`` (or ``address="auto"`` on any call) in a script
running on one of its nodes. Without an address, a call joins the Ray runtime already
initialized in this process, or starts a local one. A robot pickles as its recipe (URDF and
SRDF texts, edits) with its collision meshes' contents, so the nodes need no copy of its files.

Failures: a chunk whose worker died, or whose task raised anything but an error of tocsin's (an
out-of-memory, a lost object), is run again, up to ``max_retries`` times (Ray's own retries);
a chunk whose query raised an error of tocsin's (bad input: deterministic, so not retried), or
that still fails after the retries, raises :class:`tocsin.DistributedError` naming the chunk
and its rows, with the original error as ``__cause__``.

Command line: ``python -m tocsin.distributed queries.npz results.npz [--address auto]`` (the
file format is in :func:`main`).
"""

from __future__ import annotations

import argparse
import socket
import sys
import uuid
from collections import OrderedDict
from typing import Any, Callable, NamedTuple, Optional, Sequence

import numpy as np

from . import _batch
from ._core import Mesh, Robot, Scene, World
from ._errors import DistributedError, TocsinError

__all__ = [
    "DistributedError",
    "connect",
    "distance_batch",
    "collide_batch",
    "time_of_contact_batch",
    "motion_is_free_batch",
    "paths_are_free",
    "check_configurations",
    "first_contacts",
    "WorldContacts",
    "main",
]

#: Rows per task when ``chunk_size`` is not given: the smaller of this and an even split in
#: eight tasks per worker CPU (docs/BENCHMARKS.md, "Ray": on 16 CPUs, 8 per CPU measured 0.51 s
#: where 4 took 0.63 s, the tail of unequal chunks being shorter).
DEFAULT_CHUNK = 2048


def _ray():
    try:
        import ray
    except ImportError as e:  # pragma: no cover - exercised only without ray
        raise DistributedError(
            "tocsin.distributed needs ray, which is not installed: pip install 'tocsin[ray]'"
        ) from e
    return ray


def connect(address: Optional[str] = None, **init_kwargs: Any) -> None:
    """Joins the Ray cluster at ``address`` ("auto": the running cluster this node belongs to;
    "ray://host:10001": a remote client), or, with no address, the runtime already running in
    this process or a new local one. Further keywords go to ``ray.init``. Raises
    DistributedError when ray is missing or the cluster cannot be reached."""
    ray = _ray()
    if ray.is_initialized():
        return
    if address and address != "auto" and not address.startswith(("ray://", "local")):
        # Ray retries an unreachable head for minutes; a closed port answers at once.
        host, _, port = address.rpartition(":")
        try:
            socket.create_connection((host or "127.0.0.1", int(port)), timeout=5).close()
        except (OSError, ValueError) as e:
            raise DistributedError(f"cannot reach the Ray cluster at {address}: {e}") from e
    try:
        ray.init(address=address, include_dashboard=False, **init_kwargs)
    except Exception as e:  # ConnectionError, RuntimeError, ValueError from ray.init
        where = address or "a new local cluster"
        raise DistributedError(f"cannot reach the Ray cluster at {where}: {e}") from e


# Objects unpickled in this worker process, by token (the newest kept).
_CACHE: "OrderedDict[str, Any]" = OrderedDict()
_CACHE_SIZE = 32


# Meshes already put, by ((job, node), object identity): (mesh, (token, reference)). The mesh
# is held, so its identity is not reused while it is remembered.
_PUT: "OrderedDict[tuple, tuple]" = OrderedDict()


def _share(ray, obj):
    """A token and the object-store reference of a mesh, robot or scene (a mesh put earlier on
    this cluster: the same ones, module docs)."""
    if not isinstance(obj, Mesh):
        return (uuid.uuid4().hex, ray.put(obj))
    # A new local cluster starts its job numbers again, so the node names the cluster too.
    context = ray.get_runtime_context()
    job = (context.get_job_id(), context.get_node_id())
    for stale in [k for k in _PUT if k[0] != job]:
        del _PUT[stale]  # put in an earlier connection, since shut down
    key = (job, id(obj))
    hit = _PUT.get(key)
    if hit is not None and hit[0] is obj:
        _PUT.move_to_end(key)
        return hit[1]
    shared = (uuid.uuid4().hex, ray.put(obj))
    _PUT[key] = (obj, shared)
    while len(_PUT) > _CACHE_SIZE:
        _PUT.popitem(last=False)
    return shared


def _resolve(shared):
    token, ref = shared
    obj = _CACHE.get(token)
    if obj is None:
        obj = _ray().get(ref)
        _CACHE[token] = obj
        while len(_CACHE) > _CACHE_SIZE:
            _CACHE.popitem(last=False)
    else:
        _CACHE.move_to_end(token)
    return obj


def _call(fn: Callable, shared: dict, rows: dict, fixed: dict, chunk: int):
    """Runs one chunk on a worker: the shared objects from the cache, the chunk's rows."""
    kwargs = {name: _resolve(s) for name, s in shared.items()}
    kwargs.update(rows)
    kwargs.update(fixed)
    try:
        return ("ok", fn(**kwargs))
    except TocsinError as e:
        # Bad input: deterministic, reported (not retried) with the chunk.
        return ("error", e)


_REMOTE = None


def _remote(ray):
    """The chunk task, registered with Ray once per process."""
    global _REMOTE
    if _REMOTE is None:
        _REMOTE = ray.remote(_call)
    return _REMOTE


def _concat(parts: list):
    first = parts[0]
    if isinstance(first, list):
        return [x for p in parts for x in p]
    if isinstance(first, tuple) and hasattr(first, "_fields"):
        return type(first)(*(np.concatenate([getattr(p, f) for p in parts]) for f in first._fields))
    return np.concatenate(parts)


def _run(
    fn: Callable,
    shared: dict,
    rows: dict,
    fixed: dict,
    count: int,
    chunk_size: Optional[int],
    address: Optional[str],
    progress: bool,
    max_retries: int,
    threads_per_task: int = 1,
):
    """The chunked run of ``fn`` (module docs); results in input order."""
    if count == 0:
        kwargs = dict(shared)
        kwargs.update(rows)
        kwargs.update(fixed)
        return fn(**kwargs)
    if chunk_size is not None and (not isinstance(chunk_size, (int, np.integer)) or chunk_size < 1):
        raise DistributedError(f"chunk_size must be a positive integer, got {chunk_size!r}")
    if (
        isinstance(threads_per_task, bool)
        or not isinstance(threads_per_task, (int, np.integer))
        or threads_per_task < 1
    ):
        raise DistributedError(f"threads_per_task must be a positive integer, got {threads_per_task!r}")
    threads = int(threads_per_task)
    connect(address)
    ray = _ray()
    widest = max((n["Resources"].get("CPU", 0) for n in ray.nodes() if n.get("Alive")), default=0)
    if threads > widest:
        # Ray would wait forever for a node with that many CPUs.
        raise DistributedError(
            f"threads_per_task={threads} but the largest node of the cluster has {widest:g} CPUs"
        )
    if chunk_size is None:
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        chunk_size = max(1, min(DEFAULT_CHUNK, -(-count // (8 * max(1, cpus // threads)))))
    chunk_size = int(chunk_size)
    refs = {name: _share(ray, obj) for name, obj in shared.items()}
    # A task takes as many of Ray's CPUs as its worker's own thread pool has threads.
    task = _remote(ray).options(
        num_cpus=threads,
        max_retries=max_retries,
        retry_exceptions=True,
        runtime_env={"env_vars": {"RAYON_NUM_THREADS": str(threads)}},
    )
    bounds = [(a, min(a + chunk_size, count)) for a in range(0, count, chunk_size)]
    futures = [
        task.remote(fn, refs, {k: v[a:b] for k, v in rows.items()}, fixed, i)
        for i, (a, b) in enumerate(bounds)
    ]
    if progress:
        _report_progress(ray, futures)
    parts = []
    for i, (fut, (a, b)) in enumerate(zip(futures, bounds)):
        try:
            status, value = ray.get(fut)
        except Exception as e:
            raise DistributedError(
                f"chunk {i} (rows {a}:{b}) failed after {max_retries} retries: {e}", chunk=i
            ) from e
        if status == "error":
            raise DistributedError(f"chunk {i} (rows {a}:{b}): {value}", chunk=i) from value
        parts.append(value)
    return _concat(parts)


def _report_progress(ray, futures):
    """Waits for the chunks, showing how many are done (tqdm when installed)."""
    try:
        from tqdm import tqdm

        bar = tqdm(total=len(futures), unit="chunk", desc="tocsin")
    except ImportError:
        bar = None
    pending = list(futures)
    done = 0
    while pending:
        ready, pending = ray.wait(pending, num_returns=1)
        done += len(ready)
        if bar is not None:
            bar.update(len(ready))
        else:
            print(f"tocsin: {done}/{len(futures)} chunks", file=sys.stderr)
    if bar is not None:
        bar.close()


def _split(poses: dict) -> tuple:
    """Pose arguments split into per-row arrays ((K, 4, 4): cut into chunks) and fixed ones
    (a single (4, 4): passed whole to every chunk); with the row count K."""
    rows, fixed = {}, {}
    for name, value in poses.items():
        arr = np.asarray(value, dtype=np.float64)
        (rows if arr.ndim == 3 else fixed)[name] = arr
    counts = {n: len(a) for n, a in rows.items()}
    if len(set(counts.values())) > 1:
        raise DistributedError(f"row counts differ: {counts}")
    return rows, fixed, next(iter(counts.values()), 1)


def distance_batch(
    mesh1: Mesh,
    poses1,
    mesh2: Mesh,
    poses2,
    relative_error: float = 0.0,
    absolute_error: float = 0.0,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> _batch.DistanceBatch:
    """``tocsin.distance_batch`` on the Ray cluster: identical results, in input order."""
    rows, fixed, count = _split({"poses1": poses1, "poses2": poses2})
    fixed.update({"relative_error": relative_error, "absolute_error": absolute_error})
    return _run(_batch.distance_batch, {"mesh1": mesh1, "mesh2": mesh2}, rows, fixed, count,
                chunk_size, address, progress, max_retries, threads_per_task)


def collide_batch(
    mesh1: Mesh,
    poses1,
    mesh2: Mesh,
    poses2,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> np.ndarray:
    """``tocsin.collide_batch`` on the Ray cluster: identical results, in input order."""
    rows, fixed, count = _split({"poses1": poses1, "poses2": poses2})
    return _run(_batch.collide_batch, {"mesh1": mesh1, "mesh2": mesh2}, rows, fixed, count,
                chunk_size, address, progress, max_retries, threads_per_task)


def time_of_contact_batch(
    mesh1: Mesh,
    starts1,
    ends1,
    mesh2: Mesh,
    starts2=None,
    ends2=None,
    kind: str = "interp",
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    contact_pair: bool = False,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> _batch.ContactBatch:
    """``tocsin.time_of_contact_batch`` on the Ray cluster: identical results, in input order."""
    options = dict(kind=kind, tolerance=tolerance, max_iterations=max_iterations, contact_pair=contact_pair)
    return _motions_run(_batch.time_of_contact_batch, (mesh1, mesh2), (starts1, ends1), (starts2, ends2),
                        options, (chunk_size, address, progress, max_retries, threads_per_task))


def motion_is_free_batch(
    mesh1: Mesh,
    starts1,
    ends1,
    mesh2: Mesh,
    starts2=None,
    ends2=None,
    kind: str = "interp",
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> _batch.FreeBatch:
    """``tocsin.motion_is_free_batch`` on the Ray cluster: identical results, in input order."""
    options = dict(kind=kind, tolerance=tolerance, max_iterations=max_iterations)
    return _motions_run(_batch.motion_is_free_batch, (mesh1, mesh2), (starts1, ends1), (starts2, ends2),
                        options, (chunk_size, address, progress, max_retries, threads_per_task))


def _motions_run(fn, meshes, body1, body2, options, running):
    """A motion batch (``fn``, the local one) run as chunks of its rows: body 1's and body 2's
    (starts, ends), the batch's keyword options (kind, tolerance, max_iterations, ...), and the
    run's (chunk_size, address, progress, max_retries, threads_per_task)."""
    starts2, ends2 = _batch._body2_motions(*body2)
    rows, fixed, count = _split({"starts1": body1[0], "ends1": body1[1], "starts2": starts2, "ends2": ends2})
    fixed.update(options)
    return _run(fn, {"mesh1": meshes[0], "mesh2": meshes[1]}, rows, fixed, count, *running)


def _robot_paths(robot, q0s, q1s, scene, tolerance, max_iterations):
    return robot.paths_are_free(q0s, q1s, scene, tolerance=tolerance, max_iterations=max_iterations)


def _robot_configurations(robot, qs, scene):
    return robot.check_configurations(qs, scene)


def paths_are_free(
    robot: Robot,
    q0s,
    q1s,
    scene: Optional[Scene] = None,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> np.ndarray:
    """``Robot.paths_are_free`` (exact joint-space edge checks) on the Ray cluster."""
    a, b = np.asarray(q0s, dtype=np.float64), np.asarray(q1s, dtype=np.float64)
    if a.shape != b.shape or a.ndim != 2:
        raise DistributedError(f"q0s and q1s must both be (N, dof), got {a.shape} and {b.shape}")
    shared = {"robot": robot, "scene": scene if scene is not None else Scene()}
    fixed = {"tolerance": tolerance, "max_iterations": max_iterations}
    return _run(_robot_paths, shared, {"q0s": a, "q1s": b}, fixed, len(a), chunk_size, address,
                progress, max_retries, threads_per_task)


def check_configurations(
    robot: Robot,
    qs,
    scene: Optional[Scene] = None,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> np.ndarray:
    """``Robot.check_configurations`` (exact collision of each configuration) on the cluster."""
    q = np.asarray(qs, dtype=np.float64)
    if q.ndim != 2:
        raise DistributedError(f"qs must be (N, dof), got {q.shape}")
    shared = {"robot": robot, "scene": scene if scene is not None else Scene()}
    return _run(_robot_configurations, shared, {"qs": q}, {}, len(q), chunk_size, address,
                progress, max_retries, threads_per_task)


class WorldContacts(NamedTuple):
    """One world's ``first_contacts`` as arrays (K contacts, sorted by time then bodies)."""

    body1: np.ndarray
    """(K,) the smaller body index of each pair."""
    body2: np.ndarray
    """(K,) the larger body index."""
    time: np.ndarray
    """(K,) time of contact in [0, 1]."""
    point1: np.ndarray
    """(K, 3) closest points on body1 at `time`, world frame."""
    point2: np.ndarray
    """(K, 3) closest points on body2 at `time`, world frame."""
    normal: np.ndarray
    """(K, 3) unit normals from body1 to body2, world frame."""
    distance: np.ndarray
    """(K,) distance at `time`, model units."""

    @staticmethod
    def of(contacts) -> "WorldContacts":
        """The arrays of a list of ``WorldContact``."""
        k = len(contacts)
        return WorldContacts(
            np.array([c.body1 for c in contacts], dtype=np.int64),
            np.array([c.body2 for c in contacts], dtype=np.int64),
            np.array([c.time for c in contacts], dtype=np.float64),
            np.array([c.contact.point1 for c in contacts], dtype=np.float64).reshape(k, 3),
            np.array([c.contact.point2 for c in contacts], dtype=np.float64).reshape(k, 3),
            np.array([c.contact.normal for c in contacts], dtype=np.float64).reshape(k, 3),
            np.array([c.contact.distance for c in contacts], dtype=np.float64),
        )


def _worlds(worlds, tolerance, max_iterations):
    return [
        WorldContacts.of(w.first_contacts(tolerance=tolerance, max_iterations=max_iterations))
        for w in worlds
    ]


def first_contacts(
    worlds: Sequence[World],
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    *,
    chunk_size: Optional[int] = None,
    address: Optional[str] = None,
    progress: bool = False,
    max_retries: int = 3,
    threads_per_task: int = 1,
) -> list:
    """``World.first_contacts`` of many worlds (one step each: a dataset of scenes) on the Ray
    cluster: a list of :class:`WorldContacts`, one per world, in input order, identical to
    ``WorldContacts.of(world.first_contacts(...))`` run here. Worlds pickle with their meshes
    (each distinct mesh once per world)."""
    worlds = list(worlds)
    fixed = {"tolerance": tolerance, "max_iterations": max_iterations}
    return _run(_worlds, {}, {"worlds": worlds}, fixed, len(worlds), chunk_size, address,
                progress, max_retries, threads_per_task)


def _mesh_from(data, prefix: str) -> Mesh:
    if f"{prefix}_path" in data:
        return Mesh.load(str(data[f"{prefix}_path"]))
    return Mesh(data[f"{prefix}_vertices"], data[f"{prefix}_triangles"])


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m tocsin.distributed QUERIES.npz RESULTS.npz [--address auto]``.

    QUERIES.npz holds ``query`` (one of "distance", "collide", "time_of_contact",
    "paths_are_free") and its arrays:

    - meshes: ``mesh1_path`` (a mesh file) or ``mesh1_vertices`` (N, 3) and
      ``mesh1_triangles`` (M, 3), the same for ``mesh2``;
    - distance, collide: ``poses1`` (K, 4, 4), ``poses2`` (K, 4, 4) or (4, 4);
    - time_of_contact: ``starts1``, ``ends1``, optional ``starts2``, ``ends2``, ``kind``
      ("interp", "screw", "translation"), optional ``tolerance`` and ``contact_pair`` (the
      contact pair's points rather than the closest);
    - paths_are_free: ``urdf`` (a path), optional ``srdf``, ``q0s`` and ``q1s`` (N, dof), and
      obstacles ``obstacle0_vertices``, ``obstacle0_triangles``, ``obstacle0_pose``, ...

    RESULTS.npz gets the result's fields (distance, point1, ... for distance; ``collide`` or
    ``free`` arrays for the others). Without ``--address`` it runs on a local Ray runtime.
    Exit status 0 on success, 2 with a one-line message on any error.
    """
    ap = argparse.ArgumentParser(prog="python -m tocsin.distributed", description=(main.__doc__ or "").split("\n")[0])
    ap.add_argument("queries")
    ap.add_argument("results")
    ap.add_argument("--address", default=None, help='"auto" for the running cluster; default: local')
    ap.add_argument("--chunk-size", type=int, default=None)
    ap.add_argument("--progress", action="store_true")
    args = ap.parse_args(argv)
    try:
        data = np.load(args.queries, allow_pickle=False)
        query = str(data["query"])
        opts = dict(chunk_size=args.chunk_size, address=args.address, progress=args.progress)
        if query in ("distance", "collide"):
            m1, m2 = _mesh_from(data, "mesh1"), _mesh_from(data, "mesh2")
            if query == "distance":
                out = distance_batch(m1, data["poses1"], m2, data["poses2"], **opts)._asdict()
            else:
                out = {"collide": collide_batch(m1, data["poses1"], m2, data["poses2"], **opts)}
        elif query == "time_of_contact":
            m1, m2 = _mesh_from(data, "mesh1"), _mesh_from(data, "mesh2")
            r = time_of_contact_batch(
                m1, data["starts1"], data["ends1"], m2,
                data["starts2"] if "starts2" in data else None,
                data["ends2"] if "ends2" in data else None,
                kind=str(data["kind"]) if "kind" in data else "interp",
                tolerance=float(data["tolerance"]) if "tolerance" in data else None,
                contact_pair=bool(data["contact_pair"]) if "contact_pair" in data else False,
                **opts,
            )
            out = r._asdict()
        elif query == "paths_are_free":
            robot = Robot.from_urdf(str(data["urdf"]), srdf=str(data["srdf"]) if "srdf" in data else None)
            scene = Scene()
            k = 0
            while f"obstacle{k}_vertices" in data:
                scene.add(f"obstacle{k}", _mesh_from(data, f"obstacle{k}"), data[f"obstacle{k}_pose"])
                k += 1
            out = {"free": paths_are_free(robot, data["q0s"], data["q1s"], scene, **opts)}
        else:
            raise DistributedError(f"unknown query {query!r}")
        arrays: dict = {k: np.asarray(v) for k, v in out.items()}
        np.savez(args.results, **arrays)
    except (TocsinError, OSError, KeyError, ValueError) as e:
        print(f"tocsin.distributed: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
