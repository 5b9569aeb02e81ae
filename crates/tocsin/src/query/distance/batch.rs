//! Many pose pairs for one mesh pair, in parallel (rayon). Each result is exactly the single
//! query's, in input order, whatever the number of threads.

use super::{distance, DistanceOptions, DistanceResult};
use crate::error::OptionsError;
use crate::math::Pose;
use crate::mesh::TriMesh;
use rayon::prelude::*;

/// [`distance`] for every `(pose1, pose2)` in `poses`, in parallel; results in input order.
pub fn distance_batch(
    mesh1: &TriMesh,
    mesh2: &TriMesh,
    poses: &[(Pose, Pose)],
    options: &DistanceOptions,
) -> Result<Vec<DistanceResult>, OptionsError> {
    options.validate()?;
    poses
        .par_iter()
        .map(|(p1, p2)| distance(mesh1, p1, mesh2, p2, options))
        .collect()
}
