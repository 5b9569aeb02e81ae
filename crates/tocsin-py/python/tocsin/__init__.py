"""tocsin: exact distance, collision and continuous collision detection between polygon soups.

Units are the models' own; every point and normal is in the world frame; poses are 4x4
homogeneous rigid transforms (numpy arrays or anything array-like), mapping body coordinates
to world coordinates (the convention of trimesh and robotics).

>>> import numpy as np, tocsin
>>> a = tocsin.Mesh.box([0.5, 0.5, 0.5])
>>> pose = np.eye(4); pose[0, 3] = 2.0
>>> round(tocsin.distance(a, np.eye(4), a, pose).distance, 12)
1.0
"""

from ._core import (
    __version__,
    ContactResult,
    DistanceResult,
    Mesh,
    Motion,
    collide,
    collide_pairs,
    distance,
    motion_is_free,
    orthonormalize,
    time_of_contact,
    within_distance,
)
from ._batch import ContactBatch, DistanceBatch, collide_batch, distance_batch, time_of_contact_batch
from ._plot import plot_contact
from ._errors import (
    IterationLimitError,
    MeshError,
    MeshFileError,
    MotionError,
    OptionsError,
    OutOfMemoryError,
    PoseError,
    TocsinError,
)

__all__ = [
    "__version__",
    "ContactBatch",
    "ContactResult",
    "DistanceBatch",
    "DistanceResult",
    "IterationLimitError",
    "Mesh",
    "MeshError",
    "MeshFileError",
    "Motion",
    "MotionError",
    "OptionsError",
    "OutOfMemoryError",
    "PoseError",
    "TocsinError",
    "collide",
    "collide_batch",
    "collide_pairs",
    "distance",
    "distance_batch",
    "motion_is_free",
    "orthonormalize",
    "plot_contact",
    "time_of_contact",
    "time_of_contact_batch",
    "within_distance",
]
