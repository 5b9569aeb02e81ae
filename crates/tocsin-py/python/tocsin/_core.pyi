"""Type stubs of the compiled core. Units are the models'; points are in the world frame."""

from os import PathLike
from typing import Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike

class Mesh:
    """A triangle mesh (polygon soup) with its bounding volume hierarchy; immutable.

    No closedness, orientation or connectivity is assumed: duplicated and degenerate triangles
    and isolated vertices are accepted. The caller's arrays are copied, never modified.
    """

    def __init__(self, vertices: ArrayLike, triangles: ArrayLike) -> None:
        """Builds a mesh from (N, 3) float vertex coordinates (body frame) and (M, 3) integer
        vertex indices. Raises MeshError on bad shapes, dtypes, indices or coordinates."""
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Mesh:
        """Loads an OBJ, STL (ASCII or binary) or PLY file; polygons are triangulated.
        Raises MeshFileError if the file cannot be read, MeshError if its content is bad."""
    @staticmethod
    def torus_knot(n_u: int, n_v: int) -> Mesh:
        """A (2,3) torus-knot tube with 2 * n_u * n_v triangles (knot radius ~3, tube 0.4)."""
    @staticmethod
    def sphere(radius: float, n_lat: int, n_lon: int) -> Mesh:
        """A UV sphere centred at the origin."""
    @staticmethod
    def box(half_extents: tuple[float, float, float] | list[float]) -> Mesh:
        """An axis-aligned box centred at the origin (12 triangles)."""
    @staticmethod
    def plate(size: float, n: int) -> Mesh:
        """A zero-thickness square plate in z = 0, size wide, 2 * n * n triangles."""
    @property
    def num_vertices(self) -> int:
        """Number of vertices."""
    @property
    def num_triangles(self) -> int:
        """Number of triangles."""
    @property
    def bounding_radius(self) -> float:
        """Radius of a ball containing the mesh (model units)."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """A copy of the (N, 3) vertex coordinates, body frame."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """A copy of the (M, 3) triangle vertex indices."""

class DistanceResult:
    """The closest pair of points between two meshes."""

    @property
    def distance(self) -> float:
        """Minimum distance, model units, >= 0 (0 when the meshes touch or intersect)."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """Closest point on mesh 1, world frame, shape (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Closest point on mesh 2, world frame, shape (3,)."""
    @property
    def triangle1(self) -> int:
        """Index of the triangle of mesh 1 holding point1."""
    @property
    def triangle2(self) -> int:
        """Index of the triangle of mesh 2 holding point2."""

def distance(
    mesh1: Mesh,
    pose1: ArrayLike,
    mesh2: Mesh,
    pose2: ArrayLike,
    relative_error: float = 0.0,
    absolute_error: float = 0.0,
) -> DistanceResult:
    """Minimum distance between mesh1 at pose1 and mesh2 at pose2 (4x4 rigid transforms).

    Exact by default; with error bounds the returned distance d satisfies
    true <= d <= true * (1 + relative_error) + absolute_error. The GIL is released.
    """

def collide(mesh1: Mesh, pose1: ArrayLike, mesh2: Mesh, pose2: ArrayLike) -> bool:
    """Whether the meshes intersect or touch (coplanar overlaps included)."""

def collide_pairs(
    mesh1: Mesh, pose1: ArrayLike, mesh2: Mesh, pose2: ArrayLike
) -> npt.NDArray[np.int64]:
    """All intersecting triangle pairs as a sorted (K, 2) array [triangle of mesh1, of mesh2]."""

def within_distance(
    mesh1: Mesh, pose1: ArrayLike, mesh2: Mesh, pose2: ArrayLike, threshold: float
) -> bool:
    """Whether the distance is at most threshold (model units); stops early."""
