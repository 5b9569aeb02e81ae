"""The package's exception classes. Every error tocsin raises is a :class:`TocsinError`."""


class TocsinError(Exception):
    """Base class of every error raised by tocsin."""


class MeshError(TocsinError, ValueError):
    """A mesh is invalid: no triangles, an index out of range, a NaN or infinite coordinate, a
    coordinate beyond 1e30 (or a whole mesh below 1e-30), a wrong array shape or dtype, a bad
    generator size, or a file whose content is not a valid mesh."""


class MeshFileError(MeshError, OSError):
    """A mesh file could not be read (missing, unreadable)."""


class PoseError(TocsinError, ValueError):
    """A pose is not a 4x4 rigid transform (within 1e-6): wrong shape, NaN, a reflection,
    a scale or shear, or a last row other than ``[0, 0, 0, 1]``."""


class MotionError(TocsinError, ValueError):
    """A motion is invalid: a start or end pose that is not rigid, a non-finite centre, or a
    translation whose end rotation differs from its start rotation (beyond 1e-9)."""


class OptionsError(TocsinError, ValueError):
    """A query option is out of its range or of the wrong type: a negative, NaN or infinite
    tolerance, error bound or threshold, a non-positive max_iterations."""


class IterationLimitError(TocsinError, RuntimeError):
    """time_of_contact reached max_iterations before it could say whether the meshes come
    within the tolerance. This is not a contact: the motion is only known to be free of contact
    on [0, time_reached]. Raise max_iterations, or a larger tolerance, to get an answer.

    Attributes: ``iterations`` (the cap reached), ``time_reached`` (float in [0, 1])."""

    iterations: int
    time_reached: float


class OutOfMemoryError(TocsinError, MemoryError):
    """Memory for a mesh and its hierarchy could not be reserved (the process is left intact)."""


class RobotError(TocsinError, ValueError):
    """A robot model is invalid or unsupported (an unknown joint type, a cycle, several roots,
    a joint axis of zero length, a bad mimic, an invalid collision mesh), or a
    name (link, object) is unknown."""


class RobotFileError(RobotError, OSError):
    """A URDF or SRDF file could not be read or parsed, or a collision mesh it names was not
    found (the message lists every path tried)."""


class ConfigurationError(TocsinError, ValueError):
    """A joint configuration has the wrong length or shape, or a NaN or infinite value."""


class WorldError(TocsinError, ValueError):
    """A world query got a body index out of range, or a number of poses other than one per
    body."""


class DistributedError(TocsinError, RuntimeError):
    """A tocsin.distributed call failed: ray is not installed, the cluster cannot be reached, or
    a chunk failed (its query raised, or its worker kept dying past the retries). ``chunk`` is
    the failing chunk's index (None when no chunk ran); the original error is ``__cause__``."""

    chunk: "int | None"

    def __init__(self, message: str, chunk: "int | None" = None) -> None:
        super().__init__(message)
        self.chunk = chunk
