"""Batch queries: many poses or motions for one mesh pair, in parallel on all cores with the
GIL released. Results are identical to the single queries, in input order, whatever the
thread count. Poses are (K, 4, 4) arrays of rigid transforms (world frame); a single (4, 4)
pose for the second body is used for every query."""

from typing import NamedTuple, Optional

import numpy as np
import numpy.typing as npt

from . import _core
from ._core import Mesh

_STATUS = np.array(["none", "converged", "started_in_contact", "iteration_limit"])


class DistanceBatch(NamedTuple):
    """Distances of K pose pairs (model units, world frame)."""

    distance: npt.NDArray[np.float64]
    """(K,) minimum distances, >= 0."""
    point1: npt.NDArray[np.float64]
    """(K, 3) closest points on mesh 1, world frame."""
    point2: npt.NDArray[np.float64]
    """(K, 3) closest points on mesh 2, world frame."""
    triangle1: npt.NDArray[np.int64]
    """(K,) triangles of mesh 1 holding point1."""
    triangle2: npt.NDArray[np.int64]
    """(K,) triangles of mesh 2 holding point2."""


class ContactBatch(NamedTuple):
    """Times of contact of K motions; NaN (or -1) where there is no contact. A row whose status
    is 'iteration_limit' is not a contact either: its time is NaN, and its motion is only known
    free of contact up to ``free_until``."""

    time: npt.NDArray[np.float64]
    """(K,) time of contact in [0, 1], NaN when none."""
    point1: npt.NDArray[np.float64]
    """(K, 3) closest points on mesh 1 at `time`, world frame (NaN rows when none)."""
    point2: npt.NDArray[np.float64]
    """(K, 3) closest points on mesh 2 at `time`, world frame (NaN rows when none)."""
    normal: npt.NDArray[np.float64]
    """(K, 3) unit normals from body 1 to body 2, world frame (NaN rows when none)."""
    distance: npt.NDArray[np.float64]
    """(K,) distance at `time`, model units (NaN when none)."""
    triangle1: npt.NDArray[np.int64]
    """(K,) triangle of mesh 1 holding point1 (-1 when none)."""
    triangle2: npt.NDArray[np.int64]
    """(K,) triangle of mesh 2 holding point2 (-1 when none)."""
    iterations: npt.NDArray[np.int64]
    """(K,) advancement iterations (0 when none; the cap for 'iteration_limit')."""
    status: npt.NDArray[np.str_]
    """(K,) 'none' (no contact), 'converged', 'started_in_contact' (contacts), or
    'iteration_limit' (undecided: the cap was reached first; not a contact)."""
    free_until: npt.NDArray[np.float64]
    """(K,) the motion is known free of contact on [0, free_until]: 1.0 for 'none', the time
    of contact for contacts, the time reached for 'iteration_limit'."""


class FreeBatch(NamedTuple):
    """Whether K motions are free of contact (``tocsin.motion_is_free`` for each)."""

    free: npt.NDArray[np.bool_]
    """(K,) True where the motion stays farther apart than the tolerance: certified free."""
    decided: npt.NDArray[np.bool_]
    """(K,) False where the iteration cap was reached before the answer was known; such a row
    is not free (``free`` is False), and a planner should treat it as blocked."""


def _body2_motions(starts2: Optional[npt.ArrayLike], ends2: Optional[npt.ArrayLike]) -> tuple:
    """Body 2's start and end poses of a motion batch: at the identity when both are omitted,
    still at its start when only the end is."""
    starts2 = np.eye(4) if starts2 is None else starts2
    return starts2, (starts2 if ends2 is None else ends2)


def distance_batch(
    mesh1: Mesh,
    poses1: npt.ArrayLike,
    mesh2: Mesh,
    poses2: npt.ArrayLike,
    relative_error: float = 0.0,
    absolute_error: float = 0.0,
) -> DistanceBatch:
    """tocsin.distance for each pose pair: poses1 (K, 4, 4), poses2 (K, 4, 4) or (4, 4)."""
    return DistanceBatch(*_core._distance_batch(mesh1, poses1, mesh2, poses2, relative_error, absolute_error))


def collide_batch(mesh1: Mesh, poses1: npt.ArrayLike, mesh2: Mesh, poses2: npt.ArrayLike) -> npt.NDArray[np.bool_]:
    """tocsin.collide for each pose pair: a (K,) boolean array."""
    return _core._collide_batch(mesh1, poses1, mesh2, poses2)


def time_of_contact_batch(
    mesh1: Mesh,
    starts1: npt.ArrayLike,
    ends1: npt.ArrayLike,
    mesh2: Mesh,
    starts2: Optional[npt.ArrayLike] = None,
    ends2: Optional[npt.ArrayLike] = None,
    kind: str = "interp",
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    contact_pair: bool = False,
) -> ContactBatch:
    """tocsin.time_of_contact for K motions of body 1 from starts1[k] to ends1[k] (and of body 2
    from starts2[k] to ends2[k]; body 2 stays at the identity when they are omitted). `kind` is
    'translation', 'interp' (about the body origin) or 'screw', for both bodies. `contact_pair`
    as in tocsin.time_of_contact: the points of the triangle pair that ended the advancement
    rather than the meshes' closest points."""
    starts2, ends2 = _body2_motions(starts2, ends2)
    t, p1, p2, n, d, t1, t2, it, st, free = _core._time_of_contact_batch(
        mesh1, starts1, ends1, mesh2, starts2, ends2, kind, tolerance, max_iterations, contact_pair
    )
    return ContactBatch(t, p1, p2, n, d, t1, t2, it, _STATUS[st], free)


def motion_is_free_batch(
    mesh1: Mesh,
    starts1: npt.ArrayLike,
    ends1: npt.ArrayLike,
    mesh2: Mesh,
    starts2: Optional[npt.ArrayLike] = None,
    ends2: Optional[npt.ArrayLike] = None,
    kind: str = "interp",
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
) -> FreeBatch:
    """tocsin.motion_is_free for K motions, the way time_of_contact_batch takes them: body 1
    from starts1[k] to ends1[k] (and body 2 from starts2[k] to ends2[k]; it stays at the
    identity when they are omitted), `kind` 'translation', 'interp' (about the body origin) or
    'screw' for both. The planner's check of many rigid motions at once: no witnesses, and each
    row stops as soon as its answer is known. A row that reaches the iteration cap is undecided
    (``decided`` False) rather than an error."""
    starts2, ends2 = _body2_motions(starts2, ends2)
    free, decided = _core._motion_is_free_batch(
        mesh1, starts1, ends1, mesh2, starts2, ends2, kind, tolerance, max_iterations
    )
    return FreeBatch(free, decided)
