"""The package's exception classes. Every error tocsin raises is a :class:`TocsinError`."""


class TocsinError(Exception):
    """Base class of every error raised by tocsin."""


class MeshError(TocsinError, ValueError):
    """A mesh is invalid: no triangles, an index out of range, a NaN or infinite coordinate,
    a wrong array shape or dtype, or a file whose content is not a valid mesh."""


class MeshFileError(MeshError, OSError):
    """A mesh file could not be read (missing, unreadable)."""


class PoseError(TocsinError, ValueError):
    """A pose is not a 4x4 rigid transform (within 1e-6): wrong shape, NaN, a reflection,
    a scale or shear, or a last row other than ``[0, 0, 0, 1]``."""


class MotionError(TocsinError, ValueError):
    """A motion is invalid: a start or end pose that is not rigid, a non-finite centre, or a
    translation whose end rotation differs from its start rotation (beyond 1e-9)."""


class OptionsError(TocsinError, ValueError):
    """A query option (tolerance, error bound, threshold) is negative, NaN or infinite."""
