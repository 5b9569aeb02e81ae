//! tocsin: exact distance, collision and continuous collision detection between polygon soups.
//!
//! Meshes are [`TriMesh`] polygon soups (no topology assumed) with an RSS bounding volume
//! hierarchy. Every query takes each mesh with its world [`Pose`].
//!
//! ```
//! use tocsin::{distance, mesh, DistanceOptions, Pose, Vec3};
//! let a = mesh::sphere(1.0, 16, 32).unwrap();
//! let b = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
//! let pose_b = Pose::from_translation(Vec3::new(3.0, 0.0, 0.0));
//! let d = distance(&a, &Pose::IDENTITY, &b, &pose_b, &DistanceOptions::default()).unwrap();
//! assert!((d.distance - 1.5).abs() < 1e-9);
//! ```

pub mod bvh;
pub mod error;
pub mod math;
pub mod mesh;
pub mod motion;
pub mod query;
pub mod robot;
pub mod world;
mod xml;

pub use error::{ContactError, MeshError, MotionError, OptionsError, PoseError};
pub use math::{Mat3, Mat4, Pose, Vec3};
pub use mesh::TriMesh;
pub use motion::{Motion, MotionKind};
pub use query::collide::{collide, collide_batch, collide_pairs};
pub use query::contact_time::{
    motion_is_free, motion_is_free_batch, time_of_contact, time_of_contact_batch,
    time_of_contact_with_cache, ContactCache, ContactOptions, ContactStatus, ContactTime,
    Witnesses,
};
pub use query::distance::{
    distance, distance_batch, distance_with_cache, within_distance, DistanceCache, DistanceOptions,
    DistanceResult,
};
pub use query::penetration::{
    contains, hausdorff_distance, penetration_depth, pointwise_penetration, winding_number,
    DepthOptions, DepthStatus, HausdorffResult, PenetrationDepth, PointwisePenetration,
    WindingOptions,
};
pub use robot::{Robot, RobotError};
pub use world::{
    colliding_pairs, earliest_contact, first_contacts, first_contacts_among, pairs_within,
    FirstContacts, Undecided, World, WorldContact, WorldError, WorldOptions,
};

/// The README's Rust quickstart, compiled and run as a doctest.
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
