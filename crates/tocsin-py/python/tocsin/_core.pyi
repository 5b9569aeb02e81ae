"""Type stubs of the compiled core. Units are the models'; points are in the world frame."""

from os import PathLike
from typing import Literal, Optional, Sequence, Union, final

import numpy as np
import numpy.typing as npt
from numpy.typing import ArrayLike

__version__: str

__all__ = [
    "_world_from_parts",
    "_motion_from_parts",
    "_robot_from_recipe",
    "_scene_from_parts",
    "__version__",
    "World",
    "WorldContact",
    "ContactResult",
    "DistanceResult",
    "HausdorffResult",
    "Mesh",
    "Motion",
    "PenetrationResult",
    "PointwiseResult",
    "Robot",
    "RobotCache",
    "RobotContact",
    "Scene",
    "_collide_batch",
    "_distance_batch",
    "_motion_is_free_batch",
    "_time_of_contact_batch",
    "collide",
    "collide_pairs",
    "contains",
    "distance",
    "hausdorff_distance",
    "motion_is_free",
    "orthonormalize",
    "penetration_depth",
    "pointwise_penetration",
    "time_of_contact",
    "winding_number",
    "within_distance",
]

@final
class Mesh:
    """A triangle mesh (polygon soup) with its bounding volume hierarchy; immutable.

    No closedness, orientation or connectivity is assumed: duplicated and degenerate triangles
    and isolated vertices are accepted. The caller's arrays are copied, never modified.
    """

    def __new__(cls, vertices: ArrayLike, triangles: ArrayLike) -> Mesh:
        """Builds a mesh from (N, 3) float vertex coordinates (body frame) and (M, 3) integer
        vertex indices. Raises MeshError on bad shapes, dtypes, indices or coordinates."""
    @staticmethod
    def from_trimesh(mesh: object) -> Mesh:
        """A mesh from a trimesh.Trimesh (anything with .vertices (N, 3) and .faces (M, 3))."""
    @staticmethod
    def load(path: Union[str, PathLike[str]]) -> Mesh:
        """Loads an OBJ, STL (ASCII or binary, one or more solids), PLY or COLLADA file;
        polygons are triangulated, points and lines skipped (a COLLADA file: every geometry
        its visual scene places, with the nodes' transforms and the unit; up_axis ignored, as
        ROS and coal do).
        Raises MeshFileError if the file cannot be read, MeshError if its content is bad."""
    @staticmethod
    def torus_knot(n_u: int, n_v: int) -> Mesh:
        """A (2,3) torus-knot tube with 2 * n_u * n_v triangles (knot radius ~3, tube 0.4);
        n_u and n_v are positive integers, raised to at least 3."""
    @staticmethod
    def sphere(radius: float, n_lat: int, n_lon: int) -> Mesh:
        """A UV sphere centred at the origin."""
    @staticmethod
    def cylinder(radius: float, length: float) -> Mesh:
        """A cylinder along z containing the true cylinder (radial slack below 0.5%)."""
    @staticmethod
    def capsule(radius: float, length: float) -> Mesh:
        """A capsule along z containing the true capsule (slack about 2% of the radius)."""
    @staticmethod
    def box(half_extents: Union[Sequence[float], npt.NDArray[np.float64]]) -> Mesh:
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
    def is_convex(self) -> bool:
        """Whether the mesh is a closed convex polytope (to 1e-12 of its size; no degenerate
        triangle). Two such meshes take the GJK path of distance, within_distance and
        time_of_contact (certified against a triangle pair, the same answers). The test runs on
        first use and is kept (about the cost of building the mesh); the queries run it
        themselves only on meshes of at most 4,096 vertices, so reading this property once lets
        a larger convex mesh take the path too."""
    @property
    def vertices(self) -> npt.NDArray[np.float64]:
        """A copy of the (N, 3) vertex coordinates, body frame."""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """A copy of the (M, 3) triangle vertex indices."""

@final
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

    Exact by default (to about 2e-13 of the scene's scale: two meshes one rounding step apart
    may get 0.0 while collide() says False); with error bounds the returned distance d
    satisfies true <= d <= true * (1 + relative_error) + absolute_error. The GIL is released.
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

@final
class Motion:
    """A rigid motion over t in [0, 1] between two 4x4 rigid poses (world frame)."""

    @staticmethod
    def translation(start: ArrayLike, end: ArrayLike) -> Motion:
        """Pure translation: X(t) = R0 x + (1 - t) p0 + t p1. The rotations of start and end
        must agree within 1e-9, else MotionError."""
    @staticmethod
    def interp(start: ArrayLike, end: ArrayLike, center: Optional[Sequence[float]] = None) -> Motion:
        """The body point center (body frame, default origin) moves on a straight line; the body
        turns about it at constant angular velocity, R(t) = exp(t log(R1 R0^T)) R0 (angle in
        [0, pi]). With center = 0 this is FCL's InterpMotion."""
    @staticmethod
    def screw(start: ArrayLike, end: ArrayLike) -> Motion:
        """The SE(3) geodesic T(t) = exp(t log(T1 T0^-1)) T0: rotation about a fixed world axis
        with translation along it. A relative rotation below 1e-15 rad is a translation."""
    @staticmethod
    def turn(start: ArrayLike, point: ArrayLike, axis: ArrayLike, angle: float) -> Motion:
        """A turn by angle radians (any size; its sign gives the sense about axis) about the
        world line through point along axis, from start: pose_at(t) is start turned by
        t * angle about that line. Unlike screw, whose angle stops at pi, it may go round
        several times (a wheel on its axle). MotionError for a zero or non-finite axis, a
        non-finite point or angle."""
    @staticmethod
    def stationary(pose: ArrayLike) -> Motion:
        """A body that does not move."""
    def pose_at(self, t: float) -> npt.NDArray[np.float64]:
        """The pose at time t (a finite real; the motion is defined on [0, 1]) as a 4x4 array,
        within rounding of start at t = 0 and of end at t = 1 for every angle in [0, pi]."""
    @property
    def kind(self) -> Literal["translation", "interp", "screw", "turn"]:
        """Which interpolation the motion follows."""

@final
class ContactResult:
    """When and where two moving meshes first come within the tolerance.

    `time` is no later than the first collision, and the distance there is at most the
    tolerance. point1 and point2 are the meshes' closest points there, or with
    time_of_contact(..., contact_pair=True) the closest points of the triangle pair that ended
    the advancement (within the tolerance; the meshes' distance is at most `distance`). The normal
    points from body 1 to body 2: the direction between the points where that is determined;
    at a distance below rounding (1e-12 of the scene scale), the direction at the last
    advancement step where the meshes were clearly apart; when the meshes start in contact, the
    normal of triangle1 turned towards triangle2 (a convention).
    """

    @property
    def time(self) -> float:
        """Time of contact in [0, 1], no later than the first collision."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """Point of mesh 1 at `time` (the closest, or the contact pair's), world frame, shape (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Point of mesh 2 at `time` (the closest, or the contact pair's), world frame, shape (3,)."""
    @property
    def normal(self) -> npt.NDArray[np.float64]:
        """Unit normal from body 1 to body 2, world frame, shape (3,)."""
    @property
    def distance(self) -> float:
        """Distance between point1 and point2, model units, at most the tolerance: the meshes'
        distance at `time` (with contact_pair=True, at least it)."""
    @property
    def triangle1(self) -> int:
        """Triangle of mesh 1 holding point1."""
    @property
    def triangle2(self) -> int:
        """Triangle of mesh 2 holding point2."""
    @property
    def iterations(self) -> int:
        """Conservative-advancement iterations taken."""
    @property
    def status(self) -> Literal["converged", "started_in_contact"]:
        """How the query ended: 'converged' (within the tolerance at `time`) or
        'started_in_contact' (touching at t = 0)."""

def time_of_contact(
    mesh1: Mesh,
    motion1: Motion,
    mesh2: Mesh,
    motion2: Motion,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    contact_pair: bool = False,
) -> Optional[ContactResult]:
    """First time of contact of mesh1 moving by motion1 and mesh2 moving by motion2 over t in
    [0, 1]. Returns a ContactResult whenever the meshes come within tolerance / 2 of each other
    (always when they collide), None when they stay farther apart than the tolerance, and
    either in between. The tolerance defaults to 1e-3 of the smaller bounding radius (raised
    for degenerate meshes); below the distances' own accuracy (2e-13 of the scene's scale, radii
    plus the farthest start or end position) a pair within that accuracy counts as a contact,
    and the distance returned is at most it. Raises IterationLimitError when max_iterations
    (default 1000) runs out first: that is no contact, and the motion is only known free up to
    its time_reached.
    The points reported are the meshes' closest at that time, with their exact distance;
    contact_pair=True reports those of the triangle pair that ended the advancement instead
    (within the tolerance; their distance is at least the meshes', by up to the tolerance: a
    caller that sets a next tolerance from it needs the default), which saves the final exact
    distance query (15 to 25% of a knot's time of contact).
    The GIL is released."""

def motion_is_free(
    mesh1: Mesh,
    motion1: Motion,
    mesh2: Mesh,
    motion2: Motion,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
) -> bool:
    """Whether mesh1 moving by motion1 and mesh2 moving by motion2 stay free of contact over t
    in [0, 1]: True when they stay farther apart than the tolerance, False whenever they come
    within tolerance / 2 (always when they collide), either in between; the same answer as
    `time_of_contact(...) is None`, but it stops at the first step within the tolerance,
    computes no witnesses, and settles colliding motions by exact collision tests at a few times
    (the end, the middle, then evenly spaced times of the rest when the advancement is slow)
    before the advancement converges to the contact: the question a path planner asks. Raises
    IterationLimitError when max_iterations runs out before the answer is known. The GIL is
    released."""

def orthonormalize(pose: ArrayLike, max_error: float = 1e-3) -> npt.NDArray[np.float64]:
    """A copy of the 4x4 pose with its rotation block replaced by the nearest rotation, for
    input whose rotations were rounded (written to six digits, say), which the 1e-6 rigidity
    check of every query rejects. Raises PoseError when the block is farther than max_error
    from orthonormal (entry-wise |R^T R - I|) or is a reflection. Never called implicitly."""

def _distance_batch(
    mesh1: Mesh, poses1: ArrayLike, mesh2: Mesh, poses2: ArrayLike, relative_error: float = 0.0, absolute_error: float = 0.0
) -> tuple[
    npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]
]: ...
def _collide_batch(mesh1: Mesh, poses1: ArrayLike, mesh2: Mesh, poses2: ArrayLike) -> npt.NDArray[np.bool_]: ...
def _time_of_contact_batch(
    mesh1: Mesh,
    starts1: ArrayLike,
    ends1: ArrayLike,
    mesh2: Mesh,
    starts2: ArrayLike,
    ends2: ArrayLike,
    kind: str,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    contact_pair: bool = False,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.int64],
    npt.NDArray[np.int64],
    npt.NDArray[np.int64],
    npt.NDArray[np.int64],
    npt.NDArray[np.float64],
]: ...

def _motion_is_free_batch(
    mesh1: Mesh,
    starts1: ArrayLike,
    ends1: ArrayLike,
    mesh2: Mesh,
    starts2: ArrayLike,
    ends2: ArrayLike,
    kind: str,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.bool_]]: ...


_Path = Union[str, "PathLike[str]"]

@final
class Robot:
    """An articulated robot from URDF: links merged over fixed joints, revolute, continuous,
    prismatic and mimic joints, each link's collision geometry as one polygon soup (OBJ, STL,
    PLY or COLLADA meshes; primitives as tessellations that contain the true shape), and the
    link pairs checked for self-collision (all but adjacent bodies, SRDF-disabled pairs,
    allowed pairs, attachments).

    Configurations are float arrays of shape (dof,) in the order of `joint_names`.
    """

    @staticmethod
    def from_urdf(path: _Path, package_dirs: Sequence[_Path] = ..., srdf: Optional[_Path] = None) -> Robot:
        """Loads a URDF file, resolving package:// and relative mesh paths (see the docs)."""
    @staticmethod
    def from_urdf_string(xml: str, base_dir: Optional[_Path] = None, package_dirs: Sequence[_Path] = ...) -> Robot:
        """A robot from URDF text; relative mesh paths resolve against base_dir."""
    def apply_srdf(self, path: _Path) -> int:
        """Allows the SRDF's <disable_collisions> pairs; returns how many pairs it removed."""
    def apply_srdf_string(self, xml: str) -> int:
        """As apply_srdf, from SRDF text."""
    def allow_collision(self, link1: str, link2: str) -> None:
        """Allows two links (or attached objects) to touch."""
    def attach(
        self,
        name: str,
        mesh: Mesh,
        link: str,
        pose: Optional[ArrayLike] = None,
        touch_links: Sequence[str] = ...,
    ) -> None:
        """Attaches a mesh to a link (placed by pose in the link's frame)."""
    def detach(self, name: str) -> None:
        """Removes an attached object."""
    @property
    def name(self) -> str:
        """The robot's name."""
    @property
    def dof(self) -> int:
        """Number of configuration entries."""
    @property
    def joint_names(self) -> list[str]:
        """Names of the configuration entries, in order."""
    @property
    def joint_limits(self) -> npt.NDArray[np.float64]:
        """Joint limits, shape (dof, 2)."""
    @property
    def link_names(self) -> list[str]:
        """Every URDF link's name, in the order of link_poses."""
    @property
    def object_names(self) -> list[str]:
        """Names of the collision objects."""
    @property
    def self_pairs(self) -> list[tuple[str, str]]:
        """Object name pairs checked for self-collision."""
    @property
    def base(self) -> npt.NDArray[np.float64]:
        """The root link's world pose (4x4)."""
    @base.setter
    def base(self, pose: ArrayLike) -> None: ...
    def object_mesh(self, name: str) -> Mesh:
        """The collision mesh of an object (vertices in its body's frame)."""
    def link_poses(self, q: ArrayLike) -> npt.NDArray[np.float64]:
        """World pose of every URDF link at q, shape (L, 4, 4)."""
    def object_poses(self, q: ArrayLike) -> npt.NDArray[np.float64]:
        """World pose of every collision object at q, shape (K, 4, 4)."""
    def within_limits(self, q: ArrayLike, tolerance: float = 0.0) -> bool:
        """Whether q lies within the joint limits."""
    def time_of_contact(
        self,
        q0: ArrayLike,
        q1: ArrayLike,
        scene: Optional[Scene] = None,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
        cache: Optional[RobotCache] = None,
        contact_pair: bool = False,
    ) -> Optional[RobotContact]:
        """First time of contact along q0 -> q1 with itself or the scene (exact); the two
        objects' closest points, or with contact_pair=True the contact pair's."""
    def path_is_free(
        self,
        q0: ArrayLike,
        q1: ArrayLike,
        scene: Optional[Scene] = None,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
        cache: Optional[RobotCache] = None,
    ) -> bool:
        """Whether the segment q0 -> q1 is free (exact; stops as soon as it is known)."""
    def last_valid(
        self,
        q0: ArrayLike,
        q1: ArrayLike,
        scene: Optional[Scene] = None,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
    ) -> float:
        """The last time of q0 -> q1 known free: 1.0 when free, else the time of contact."""
    def in_collision(self, q: ArrayLike, scene: Optional[Scene] = None) -> bool:
        """Whether the robot at q collides with itself or the scene."""
    def check_configurations(self, qs: ArrayLike, scene: Optional[Scene] = None) -> npt.NDArray[np.bool_]:
        """in_collision for every row of qs (N, dof), on all cores."""
    def paths_are_free(
        self,
        q0s: ArrayLike,
        q1s: ArrayLike,
        scene: Optional[Scene] = None,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
    ) -> npt.NDArray[np.bool_]:
        """path_is_free for every segment, on all cores."""
    def time_of_contact_batch(
        self,
        q0s: ArrayLike,
        q1s: ArrayLike,
        scene: Optional[Scene] = None,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
        contact_pair: bool = False,
    ) -> list[Optional[RobotContact]]:
        """time_of_contact for every segment, on all cores."""

@final
class Scene:
    """Static obstacles for the robot queries: named meshes at world poses."""

    def __new__(cls) -> Scene: ...
    def add(self, name: str, mesh: Mesh, pose: Optional[ArrayLike] = None) -> None:
        """Adds an obstacle placed by pose (4x4, body to world)."""
    @property
    def names(self) -> list[str]:
        """The obstacles' names, in the order added."""
    def __len__(self) -> int: ...

@final
class RobotContact:
    """When and where the robot first comes within the tolerance along a segment."""

    @property
    def time(self) -> float:
        """Time in [0, 1] along the segment, no later than the first collision."""
    @property
    def object1(self) -> str:
        """The robot object of the pair."""
    @property
    def object2(self) -> str:
        """The other object: a robot link or an obstacle."""
    @property
    def self_collision(self) -> bool:
        """Whether object2 is part of the robot."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """Point of object1 (the closest, or the contact pair's), world frame, shape (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Point of object2 (the closest, or the contact pair's), world frame, shape (3,)."""
    @property
    def normal(self) -> npt.NDArray[np.float64]:
        """Unit normal from object1 to object2, world frame, shape (3,)."""
    @property
    def distance(self) -> float:
        """Distance between point1 and point2 (model units, at most the tolerance): the objects'
        distance at time (with contact_pair=True, at least it)."""
    @property
    def iterations(self) -> int:
        """Advancement iterations of the pair that made the contact."""
    @property
    def status(self) -> Literal["converged", "started_in_contact"]:
        """'converged' or 'started_in_contact'."""

def winding_number(
    mesh: Mesh, pose: ArrayLike, points: ArrayLike, beta: float = 2.0, exact: bool = False
) -> npt.NDArray[np.float64]:
    """Generalized winding number of the placed mesh at each world point (N, 3); OptionsError
    for a point that is not finite or beyond 1e30 in magnitude."""

def contains(mesh: Mesh, pose: ArrayLike, points: ArrayLike) -> npt.NDArray[np.bool_]:
    """Whether each world point (N, 3) is inside the placed mesh (winding number above 1/2);
    OptionsError for a point that is not finite or beyond 1e30 in magnitude."""

@final
class HausdorffResult:
    """The Hausdorff distance found, within the error bound, and where."""

    @property
    def distance(self) -> float:
        """A value attained by a surface point (at most the true distance)."""
    @property
    def upper_bound(self) -> float:
        """An upper bound on the true distance."""
    @property
    def from_first(self) -> bool:
        """Whether point1 is on mesh1."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """The point realising distance, world frame, (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Its closest point on the other mesh, world frame, (3,)."""

def hausdorff_distance(
    mesh1: Mesh,
    pose1: ArrayLike,
    mesh2: Mesh,
    pose2: ArrayLike,
    max_error: Optional[float] = None,
    symmetric: bool = False,
) -> HausdorffResult:
    """Hausdorff distance between two placed meshes' surfaces, exact within max_error (one below
    the distances' accuracy, 2e-13 of the radii plus the poses' distances, is raised to it)."""

@final
class PenetrationResult:
    """A translational penetration depth and the translation that realises it."""

    @property
    def depth(self) -> float:
        """Length of the translation (0 when separated)."""
    @property
    def iterations(self) -> int:
        """Refinement iterations taken."""
    @property
    def status(self) -> Literal["separated", "converged", "iteration_limit"]:
        """How the query ended."""
    @property
    def exact(self) -> bool:
        """Whether depth is exact (both meshes closed convex polytopes)."""
    @property
    def translation(self) -> npt.NDArray[np.float64]:
        """Translation to apply to body 2 (world frame), (3,)."""
    @property
    def direction(self) -> npt.NDArray[np.float64]:
        """Unit direction of the translation, (3,)."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """Closest point on body 1 at the touching configuration, (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Closest point on body 2 there, (3,)."""

def penetration_depth(
    mesh1: Mesh,
    pose1: ArrayLike,
    mesh2: Mesh,
    pose2: ArrayLike,
    tolerance: Optional[float] = None,
    max_iterations: Optional[int] = None,
    directions: Optional[int] = None,
    cached_direction: Optional[ArrayLike] = None,
    exact_convex: bool = True,
    starts: Optional[int] = None,
) -> PenetrationResult:
    """Translational penetration depth of mesh2 into mesh1 (PolyDepth-style local optimum).

    After the translation the bodies do not intersect and are apart by at most
    ``min(tolerance, 1e-3 * depth)``; ``tolerance`` defaults to 1e-3 of the smaller radius, and
    one below twice the distances' accuracy (2e-13 of the radii plus the poses' distances from
    the origin) is raised to that, so that the bodies end apart.
    ``starts`` (default 2, at least 1): how many of the seeds' shortest touching translations
    are refined at deep penetrations (3: sometimes a few percent shallower, slower).
    ``directions`` (default 32, at most 1,000,000): seed directions spread over the sphere.
    """

@final
class PointwiseResult:
    """The deepest interpenetrating points found (pointwise penetration depth)."""

    @property
    def depth(self) -> float:
        """Depth attained."""
    @property
    def upper_bound(self) -> float:
        """Upper bound on the true pointwise depth."""
    @property
    def from_first(self) -> bool:
        """Whether point1 is on mesh1 (inside mesh2)."""
    @property
    def point1(self) -> npt.NDArray[np.float64]:
        """The deepest point found, world frame, (3,)."""
    @property
    def point2(self) -> npt.NDArray[np.float64]:
        """Its closest point on the other surface, world frame, (3,)."""

def pointwise_penetration(
    mesh1: Mesh, pose1: ArrayLike, mesh2: Mesh, pose2: ArrayLike, max_error: Optional[float] = None
) -> PointwiseResult:
    """Pointwise penetration depth of two placed meshes, within max_error (one below the
    distances' accuracy, 2e-13 of the radii plus the poses' distances, is raised to it)."""

@final
class RobotCache:
    """Closest triangle pairs of earlier segment checks, for warm starts (cache=...)."""

    def __new__(cls) -> RobotCache: ...

@final
class World:
    """Bodies, each a Mesh moving by a rigid Motion over the step t in [0, 1], or static; and the
    queries over all of them at once. Bodies given the same Mesh object share its hierarchy."""

    def __new__(cls) -> World: ...
    def add_body(self, mesh: Mesh, motion: Union[Motion, ArrayLike]) -> int:
        """Adds a moving body (a Motion, or a 4x4 pose for a body at rest); returns its index."""
    def add_static(self, mesh: Mesh, pose: ArrayLike) -> int:
        """Adds a static body at pose; static bodies are never checked against each other."""
    def set_motion(self, index: int, motion: Motion) -> None:
        """Sets body index's Motion over the next step."""
    def set_motions(
        self, bodies: Sequence[int], starts: ArrayLike, ends: ArrayLike, kind: str = "screw"
    ) -> None:
        """Sets the motions of the bodies from starts to ends ((K, 4, 4) each), all of one kind:
        "screw", "interp" (about each body's origin) or "translation"."""
    def __len__(self) -> int: ...
    @property
    def num_meshes(self) -> int:
        """Number of distinct meshes (hierarchies) the bodies share."""
    def is_static(self, index: int) -> bool:
        """Whether body index is static."""
    def poses_at(self, t: float) -> npt.NDArray[np.float64]:
        """Every body's pose at time t of the step, shape (N, 4, 4)."""
    def candidate_pairs(self, tolerance: Optional[float] = None) -> npt.NDArray[np.int64]:
        """The broad phase over the step: pairs whose swept boxes meet, shape (K, 2)."""
    def first_contacts(
        self,
        tolerance: Optional[float] = None,
        max_iterations: Optional[int] = None,
        bodies: Optional[Sequence[int]] = None,
    ) -> list[WorldContact]:
        """Every pair that comes within its tolerance during the step, sorted by time; with
        bodies, only the pairs with at least one of them."""
    def earliest_contact(
        self, tolerance: Optional[float] = None, max_iterations: Optional[int] = None
    ) -> Optional[WorldContact]:
        """The earliest of first_contacts (ties by body indices), or None."""
    def colliding_pairs(
        self, poses: Optional[ArrayLike] = None, t: float = 0.0
    ) -> npt.NDArray[np.int64]:
        """Pairs whose meshes touch or intersect at poses (default: the poses at t), (K, 2)."""
    def pairs_within(
        self, distance: float, poses: Optional[ArrayLike] = None, t: float = 0.0
    ) -> npt.NDArray[np.int64]:
        """Pairs whose meshes are at most distance apart at poses (default: at t), (K, 2)."""

@final
class WorldContact:
    """A pair of bodies that comes within its tolerance during the step."""

    @property
    def body1(self) -> int:
        """The smaller body index (mesh 1 of the contact)."""
    @property
    def body2(self) -> int:
        """The larger body index."""
    @property
    def contact(self) -> ContactResult:
        """The pair's first contact: time, world-frame points, normal from body1 to body2."""
    @property
    def time(self) -> float:
        """The contact's time in [0, 1]."""

def _motion_from_parts(
    kind: str, start: ArrayLike, end: ArrayLike, center: Sequence[float], angular: Sequence[float] = ...
) -> Motion:
    """Unpickles a Motion."""

def _robot_from_recipe(recipe: Sequence[tuple], meshes: Optional[dict] = None) -> Robot:
    """Unpickles a Robot: replays its recipe, the URDF's meshes taken from meshes."""

def _scene_from_parts(items: Sequence[tuple[str, Mesh, ArrayLike]]) -> Scene:
    """Unpickles a Scene."""

def _world_from_parts(meshes: Sequence[Mesh], bodies: Sequence[tuple[int, Motion, bool]]) -> World:
    """Unpickles a World."""
