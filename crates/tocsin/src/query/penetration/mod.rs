//! Penetration: what lies inside a polygon soup, and how far surfaces are from each other. So
//! far the generalized winding number and the inside test built on it ([`winding`]), the
//! Hausdorff distance within an error bound ([`hausdorff`]), translational penetration depth
//! after PolyDepth ([`depth`]) and pointwise penetration depth ([`pointwise`]).
//!
//! How this relates to the rest of the library: `distance` and `collide` keep treating a soup
//! as a surface with no inside (one closed mesh strictly inside another is apart from it).
//! Penetration is a separate question that needs an inside, and it uses the winding number's:
//! a point is inside where the generalized winding number's magnitude exceeds 1/2, which is the
//! usual inside for closed, consistently oriented meshes, degrades gracefully on soups with
//! holes, duplicated or flipped triangles, and is the same for inside-out meshes (winding -1
//! inside: a soup has no reliable orientation). It does assume the triangles are oriented
//! alike, as a whole: a closed mesh whose triangles face both ways at random (a convex hull's
//! simplices as scipy lists them) gets fractional values inside, and may be taken for empty.

pub(crate) mod balls;
pub mod convex;
pub mod depth;
pub(crate) mod epa;
pub mod hausdorff;
pub mod pointwise;
pub(crate) mod surface;
pub mod winding;

pub use depth::{penetration_depth, DepthOptions, DepthStatus, PenetrationDepth};
pub use hausdorff::{hausdorff_distance, HausdorffResult};
pub use pointwise::{pointwise_penetration, PointwisePenetration};
pub use winding::{contains, winding_number, WindingOptions};

/// The root of `i` in a union-find forest (`parent[i] == i` at a root), halving the path on the
/// way (the closed-surface test of [`balls`], the coplanar faces of [`convex`]).
pub(crate) fn union_root(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[parent[i as usize] as usize];
        parent[i as usize] = p;
        i = p;
    }
    i
}

/// The default error bound of the Hausdorff and pointwise-depth queries: `1e-4` of the smaller
/// bounding radius (model units).
pub fn default_max_error(mesh1: &crate::TriMesh, mesh2: &crate::TriMesh) -> f64 {
    1e-4 * mesh1
        .bounding_radius()
        .min(mesh2.bounding_radius())
        .max(f64::MIN_POSITIVE)
}

/// The error bound the Hausdorff and pointwise-depth searches use: `max_error`, raised to the
/// distances' own accuracy ([`crate::query::contact_time::DISTANCE_RESOLUTION`] of the radii
/// plus the poses' distances from the origin). Below it a piece's upper bound cannot come
/// within the bound of the best found, whose sum rounds to the best itself: with a bound of
/// 1e-16 on a depth of 0.37, the pointwise search subdivided for minutes.
pub(crate) fn resolved_error(
    max_error: f64,
    placed1: (&crate::TriMesh, &crate::Pose),
    placed2: (&crate::TriMesh, &crate::Pose),
) -> f64 {
    max_error.max(distance_accuracy(placed1, placed2))
}

/// The accuracy of a distance between two placed meshes:
/// [`crate::query::contact_time::DISTANCE_RESOLUTION`] of their radii plus the poses' distances
/// from the origin.
pub(crate) fn distance_accuracy(
    (mesh1, pose1): (&crate::TriMesh, &crate::Pose),
    (mesh2, pose2): (&crate::TriMesh, &crate::Pose),
) -> f64 {
    use crate::motion::Motion;
    use crate::query::contact_time::{scene_scale, DISTANCE_RESOLUTION};
    let (still1, still2) = (Motion::stationary(*pose1), Motion::stationary(*pose2));
    DISTANCE_RESOLUTION * scene_scale(mesh1, &still1, mesh2, &still2)
}
