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
    HausdorffResult,
    Mesh,
    Motion,
    PenetrationResult,
    PointwiseResult,
    Robot,
    RobotCache,
    RobotContact,
    Scene,
    World,
    WorldContact,
    collide,
    collide_pairs,
    contains,
    distance,
    hausdorff_distance,
    motion_is_free,
    orthonormalize,
    penetration_depth,
    pointwise_penetration,
    winding_number,
    within_distance,
)
from ._core import time_of_contact as _rigid_time_of_contact
from ._batch import (
    ContactBatch,
    DistanceBatch,
    FreeBatch,
    collide_batch,
    distance_batch,
    motion_is_free_batch,
    time_of_contact_batch,
)
from ._plot import plot_contact
from ._errors import (
    ConfigurationError,
    DistributedError,
    IterationLimitError,
    MeshError,
    MeshFileError,
    MotionError,
    OptionsError,
    OutOfMemoryError,
    PoseError,
    RobotError,
    RobotFileError,
    TocsinError,
    WorldError,
)



def time_of_contact(*args, **kwargs):
    """First time of contact, for two moving meshes or for a robot along a joint-space segment.

    ``time_of_contact(robot, q0, q1, scene=None, tolerance=None, max_iterations=None)``: the
    robot moving along q(t) = q0 + t (q1 - q0) against itself and the scene's obstacles; a
    RobotContact or None (``Robot.time_of_contact``).

    ``time_of_contact(mesh1, motion1, mesh2, motion2, tolerance=None, max_iterations=None)``:
    two rigid bodies over t in [0, 1]:
    """
    if args and isinstance(args[0], Robot):
        return args[0].time_of_contact(*args[1:], **kwargs)
    return _rigid_time_of_contact(*args, **kwargs)


time_of_contact.__doc__ = (time_of_contact.__doc__ or "") + "\n" + (_rigid_time_of_contact.__doc__ or "")


def _expect(value, cls, name):
    """``value`` when it is a ``cls``; else the TypeError a wrong argument gets everywhere else
    in the package (not the AttributeError of calling its method)."""
    if not isinstance(value, cls):
        raise TypeError(f"{name} must be a tocsin.{cls.__name__}, got {type(value).__name__}")
    return value


def path_is_free(robot, q0, q1, scene=None, tolerance=None, max_iterations=None):
    """Whether the robot's joint-space segment q0 -> q1 is free of contact with itself and the
    scene (exact; ``Robot.path_is_free``)."""
    return _expect(robot, Robot, "robot").path_is_free(q0, q1, scene, tolerance=tolerance, max_iterations=max_iterations)


def check_configurations(robot, qs, scene=None):
    """Exact collision of the robot at every row of ``qs`` (N, dof): a bool array
    (``Robot.check_configurations``)."""
    return _expect(robot, Robot, "robot").check_configurations(qs, scene)


def first_contacts(world, tolerance=None, max_iterations=None):
    """Every pair of the world's bodies that comes within its tolerance during the step, each
    with the answer time_of_contact gives for the pair alone, sorted by time
    (``World.first_contacts``)."""
    return _expect(world, World, "world").first_contacts(tolerance=tolerance, max_iterations=max_iterations)


def earliest_contact(world, tolerance=None, max_iterations=None):
    """The earliest of ``first_contacts(world)``, or None (``World.earliest_contact``)."""
    return _expect(world, World, "world").earliest_contact(tolerance=tolerance, max_iterations=max_iterations)


def colliding_pairs(world, poses=None):
    """Pairs of bodies that touch or intersect at ``poses`` ((N, 4, 4); default: the start of
    the step), shape (K, 2) (``World.colliding_pairs``)."""
    return _expect(world, World, "world").colliding_pairs(poses)


def pairs_within(world, poses, distance):
    """Pairs of bodies at most ``distance`` apart at ``poses`` ((N, 4, 4), or None for the start
    of the step), shape (K, 2) (``World.pairs_within``)."""
    return _expect(world, World, "world").pairs_within(distance, poses)


__all__ = [
    "DistributedError",
    "World",
    "WorldContact",
    "WorldError",
    "first_contacts",
    "earliest_contact",
    "colliding_pairs",
    "pairs_within",
    "__version__",
    "ConfigurationError",
    "Robot",
    "RobotCache",
    "RobotContact",
    "RobotError",
    "RobotFileError",
    "Scene",
    "HausdorffResult",
    "PenetrationResult",
    "penetration_depth",
    "PointwiseResult",
    "pointwise_penetration",
    "hausdorff_distance",
    "check_configurations",
    "contains",
    "winding_number",
    "path_is_free",
    "ContactBatch",
    "ContactResult",
    "DistanceBatch",
    "DistanceResult",
    "FreeBatch",
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
    "motion_is_free_batch",
    "orthonormalize",
    "plot_contact",
    "time_of_contact",
    "time_of_contact_batch",
    "within_distance",
]
