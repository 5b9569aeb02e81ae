//! Minimum distance between two meshes: exact, approximate within error bounds, or a
//! threshold test (`within_distance`) that stops early.
//!
//! Branch and bound over the two hierarchies (PQP-style, Larsen et al. 1999): node pairs are
//! bounded below by [`crate::bvh::Rss`] separation, visited closest first, and pruned when their
//! bound cannot improve the best triangle pair found so far. An optional [`DistanceCache`]
//! starts from the last closest triangle pair (motion coherence).

mod batch;
mod distance_point_triangle;
mod distance_segment_segment;
mod distance_triangle_triangle;
pub(crate) mod gjk;
pub(crate) mod traverse;

pub use batch::distance_batch;
pub use distance_point_triangle::{inside_triangle, project_inside_triangle, triangle_normal};
pub use distance_segment_segment::closest_points_segment_segment;
pub use distance_triangle_triangle::{
    distance_triangle_triangle, intersect_triangle_triangle, TrianglePairDistance,
};
pub use gjk::{GJK_MAX_VERTICES, ROUNDING as GJK_ROUNDING};

use crate::error::OptionsError;
use crate::math::{Pose, Vec3};
use crate::mesh::TriMesh;
use traverse::{DistanceSearch, Stop};

/// Options of [`distance`]. The default asks for the exact distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceOptions {
    /// Allowed relative error: the returned distance `d` satisfies
    /// `true <= d <= true * (1 + relative_error) + absolute_error`. Default 0.
    pub relative_error: f64,
    /// Allowed absolute error (model units), see `relative_error`. Default 0.
    pub absolute_error: f64,
}

impl Default for DistanceOptions {
    fn default() -> Self {
        Self {
            relative_error: 0.0,
            absolute_error: 0.0,
        }
    }
}

impl DistanceOptions {
    fn validate(&self) -> Result<(), OptionsError> {
        check_non_negative("relative_error", self.relative_error)?;
        check_non_negative("absolute_error", self.absolute_error)
    }
}

pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<(), OptionsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(OptionsError::Invalid { name, value })
    }
}

/// The closest pair of points between two meshes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceResult {
    /// Minimum distance (model units, >= 0; 0 when the meshes touch or intersect).
    pub distance: f64,
    /// Closest point on mesh 1, world frame.
    pub point1: Vec3,
    /// Closest point on mesh 2, world frame.
    pub point2: Vec3,
    /// Index of the triangle of mesh 1 holding `point1`.
    pub triangle1: usize,
    /// Index of the triangle of mesh 2 holding `point2`.
    pub triangle2: usize,
}

/// Remembers the closest triangle pair of the last query on a mesh pair, so that the next
/// query on nearby poses starts from it (motion coherence). Use one cache per mesh pair; a cache
/// used with other meshes is harmless (it is only a starting guess, checked for range).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DistanceCache {
    /// Leaf positions (in each hierarchy) of the last closest triangle pair.
    pub(crate) pair: Option<(u32, u32)>,
    /// Where GJK ended, for two convex meshes.
    pub(crate) simplex: gjk::WarmSimplex,
}

/// Exact (or, with error bounds in `options`, approximate) minimum distance between `mesh1` at
/// `pose1` and `mesh2` at `pose2`, with witness points in the world frame.
pub fn distance(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    options: &DistanceOptions,
) -> Result<DistanceResult, OptionsError> {
    distance_with_cache(
        mesh1,
        pose1,
        mesh2,
        pose2,
        options,
        &mut DistanceCache::default(),
    )
}

/// [`distance`] warm-started from, and updating, `cache`.
pub fn distance_with_cache(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    options: &DistanceOptions,
    cache: &mut DistanceCache,
) -> Result<DistanceResult, OptionsError> {
    options.validate()?;
    Ok(search_distance(mesh1, pose1, mesh2, pose2, options, cache))
}

/// The search behind [`distance_with_cache`], for options already validated.
pub(crate) fn search_distance(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    options: &DistanceOptions,
    cache: &mut DistanceCache,
) -> DistanceResult {
    let pos12 = pose1.inv_mul(pose2);
    if let Some((s, simplex)) = convex_separation(mesh1, mesh2, &pos12, cache) {
        cache.simplex = simplex;
        let allowed = options.absolute_error + options.relative_error * s.gap.max(0.0);
        if s.certifies(allowed) {
            cache.pair = Some(s.leaves);
            return DistanceResult {
                distance: s.pair.distance,
                point1: pose1.transform_point(s.pair.point1),
                point2: pose1.transform_point(s.pair.point2),
                triangle1: mesh1.bvh().triangle_index(s.leaves.0),
                triangle2: mesh2.bvh().triangle_index(s.leaves.1),
            };
        }
    }
    let mut search = DistanceSearch::new(mesh1, mesh2, &pos12, options, Stop::Never);
    search.run(cache.pair);
    let best = search.best();
    cache.pair = Some((best.leaf1, best.leaf2));
    search.result(pose1)
}

/// Whether the distance between the meshes is at most `threshold` (model units). Stops as
/// soon as one triangle pair within the threshold is found.
pub fn within_distance(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    threshold: f64,
) -> Result<bool, OptionsError> {
    check_non_negative("threshold", threshold)?;
    let pos12 = pose1.inv_mul(pose2);
    if let Some((s, _)) = convex_separation(mesh1, mesh2, &pos12, &DistanceCache::default()) {
        if s.certifies(0.0) && s.pair.distance <= threshold {
            return Ok(true);
        }
        if s.safe_gap() > threshold {
            return Ok(false);
        }
    }
    let options = DistanceOptions::default();
    let mut search =
        DistanceSearch::new(mesh1, mesh2, &pos12, &options, Stop::AtOrBelow(threshold));
    search.run(None);
    Ok(search.best().distance <= threshold)
}

/// GJK's separation of two convex meshes ([`gjk`]), mesh 2 placed by `pos12` in mesh 1's
/// frame, warm-started from `cache`, and where GJK ended; `None` where either mesh is not a
/// convex polytope the path takes or the solids overlap.
fn convex_separation(
    mesh1: &TriMesh,
    mesh2: &TriMesh,
    pos12: &Pose,
    cache: &DistanceCache,
) -> Option<(gjk::Separation, gjk::WarmSimplex)> {
    let (p1, p2) = gjk::polytopes(mesh1, mesh2)?;
    let mut g = gjk::Gjk::new(mesh1, p1, mesh2, p2, cache.pair, cache.simplex);
    let s = g.separation(&pos12.rotation, pos12.translation)?;
    Some((s, g.warm()))
}
