//! Error types. Bad input is a typed error that says what was wrong and where; outcomes of
//! queries (no contact, an iteration cap) are data, not errors.

use std::path::PathBuf;

/// A mesh could not be built or loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The mesh has no triangles.
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle}, corner {corner}: vertex index {index} is out of range (the mesh has {num_vertices} vertices)")]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// Which corner of the triangle (0, 1 or 2).
        corner: usize,
        /// The offending vertex index (as given, may be negative in the caller's type).
        index: i64,
        /// Number of vertices of the mesh.
        num_vertices: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex}, coordinate {axis}: {value} is not finite")]
    NonFiniteCoordinate {
        /// Index of the offending vertex.
        vertex: usize,
        /// Which coordinate: 'x', 'y' or 'z'.
        axis: char,
        /// The offending value.
        value: f64,
    },
    /// A vertex coordinate lies outside the supported range (magnitude above
    /// [`crate::math::MAX_COORDINATE`]: the kernels' products of lengths would overflow).
    #[error("vertex {vertex}, coordinate {axis}: {value:e} is outside the supported range (magnitude at most {max:e})", max = crate::math::MAX_COORDINATE)]
    CoordinateOutOfRange {
        /// Index of the offending vertex.
        vertex: usize,
        /// Which coordinate: 'x', 'y' or 'z'.
        axis: char,
        /// The offending value.
        value: f64,
    },
    /// Every coordinate of the mesh is tiny but not all are zero (largest magnitude below
    /// [`crate::math::MIN_SCALE`]): squared distances would underflow. Rescale the model.
    #[error("the mesh's largest coordinate magnitude is {magnitude:e}, below the supported {min:e} (rescale the model)", min = crate::math::MIN_SCALE)]
    TooSmall {
        /// The largest coordinate magnitude found.
        magnitude: f64,
    },
    /// Memory for the mesh and its hierarchy could not be reserved.
    #[error("out of memory: a mesh of {triangles} triangles and {vertices} vertices needs about {bytes} bytes")]
    OutOfMemory {
        /// Triangles asked for.
        triangles: usize,
        /// Vertices asked for.
        vertices: usize,
        /// Estimated bytes (mesh, hierarchy and build).
        bytes: usize,
    },
    /// The mesh is too large for 32-bit indices.
    #[error("the mesh has {count} {what}, more than the supported 2^31 - 1")]
    TooLarge {
        /// What is too many ("vertices" or "triangles").
        what: &'static str,
        /// How many there are.
        count: usize,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A file was read but its content is not a valid mesh of its format.
    #[error("{path}: {format} parse error{}: {message}", line.map(|l| format!(" at line {l}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The format it was read as ("OBJ", "STL", "PLY").
        format: &'static str,
        /// The 1-based line of the problem, where known.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The file extension is not one of the supported formats.
    #[error("{path}: unknown mesh format (expected .obj, .stl, .ply or .dae)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A generator's size parameter (a radius, a length) is not positive and finite.
    #[error("{name} must be positive and finite, got {value:?}")]
    BadSize {
        /// The parameter.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A file's mesh is invalid (for example an out-of-range index in a face).
    #[error("{path}: {source}")]
    InFile {
        /// The file.
        path: PathBuf,
        /// What is wrong with the mesh it holds.
        source: Box<MeshError>,
    },
}

/// A pose (rigid transform) is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PoseError {
    /// An entry is NaN or infinite.
    #[error("the pose has a NaN or infinite entry")]
    NonFinite,
    /// A translation is outside the supported range (magnitude above
    /// [`crate::math::MAX_COORDINATE`]).
    #[error("the translation {value:e} is outside the supported range (magnitude at most {max:e})", max = crate::math::MAX_COORDINATE)]
    OutOfRange {
        /// The offending entry.
        value: f64,
    },
    /// The last row of a 4x4 matrix is not `0 0 0 1`.
    #[error("the last row of the 4x4 pose is {last_row:?}, expected [0, 0, 0, 1]")]
    NotHomogeneous {
        /// The last row found.
        last_row: [f64; 4],
    },
    /// The rotation block is not orthonormal.
    #[error("the rotation block is not orthonormal (max |R^T R - I| = {error:.3e})")]
    NotOrthonormal {
        /// The largest entry of `|R^T R - I|`.
        error: f64,
    },
    /// The rotation block is a reflection or has a wrong scale.
    #[error("the rotation block has determinant {determinant}, expected +1 (a reflection or scale is not rigid)")]
    NotProperRotation {
        /// The determinant found.
        determinant: f64,
    },
}

/// An option of a query is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum OptionsError {
    /// A tolerance or bound is negative, NaN or infinite.
    #[error("option `{name}` must be finite and non-negative, got {value:?}")]
    Invalid {
        /// The option's name.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// An option is out of its range (the message says which range).
    #[error("option `{name}` {requirement}, got {value:?}")]
    OutOfRange {
        /// The option's name.
        name: &'static str,
        /// What it must be, as a phrase ("must be positive").
        requirement: &'static str,
        /// The value given.
        value: f64,
    },
}

/// A time-of-contact query failed: bad options, or no answer within the iteration cap.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContactError {
    /// An option is invalid.
    #[error(transparent)]
    Options(#[from] OptionsError),
    /// The iteration cap was reached before the query could say whether the meshes come within
    /// the tolerance. This is not a contact: the motion is only known to be free of contact on
    /// `[0, time_reached]`.
    #[error("no answer within {iterations} iterations: the motion is free of contact up to t = {time_reached}, undecided after (raise max_iterations)")]
    IterationLimit {
        /// The cap that was reached.
        iterations: usize,
        /// The motion is free of contact on `[0, time_reached]`.
        time_reached: f64,
    },
}

/// A motion is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MotionError {
    /// A start or end pose is not a rigid transform.
    #[error("invalid pose: {0}")]
    Pose(PoseError),
    /// A coordinate of a pose or of the centre is NaN or infinite.
    #[error("the motion has a NaN or infinite coordinate")]
    NonFinite,
    /// A translation was asked for but the rotation changes.
    #[error("a translation needs the same rotation at start and end (entries differ by up to {difference:.3e}, tolerance 1e-9)")]
    RotationChanges {
        /// Largest entry-wise difference of the two rotations.
        difference: f64,
    },
}
