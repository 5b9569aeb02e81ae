//! Bounding a pair of small subtrees by projecting their points on an axis, from both meshes'
//! `f32` corner columns: shared by the distance search and the time-of-contact step search.
//!
//! For any unit axis `u` (mesh 1's frame), `min over q in b of u . q - max over p in a of u . p`
//! is a lower bound on the distance between the two subtrees' triangles along `u` (triangles are
//! the convex hulls of their corners), less the columns' rounding bound.

use super::{Bvh, CornerColumns, Lanes4, Node};
use crate::math::{Mat3, Pose, Vec3};

/// The two meshes' corner columns for one query.
pub(crate) struct ColumnPair<'a> {
    c1: &'a CornerColumns,
    c2: &'a CornerColumns,
    /// Origin of `c2`'s coordinates less `c1`'s, in mesh 1's frame.
    origins: Vec3,
    /// The two columns' rounding bounds, summed.
    error: f64,
    /// Mesh 1's frame into mesh 2's.
    rot21: Mat3,
}

impl<'a> ColumnPair<'a> {
    /// `None` when either mesh has no columns (coordinates past 1e30 from its centre).
    pub(crate) fn new(bvh1: &'a Bvh, bvh2: &'a Bvh, pos12: &Pose) -> Option<Self> {
        let (c1, c2) = (bvh1.corner_columns()?, bvh2.corner_columns()?);
        Some(Self {
            c1,
            c2,
            origins: pos12.transform_point(c2.origin) - c1.origin,
            error: c1.error + c2.error,
            rot21: pos12.rotation.transpose(),
        })
    }

    /// The projected gap along the unit `axis` (mesh 1's frame, running from `a` towards `b`)
    /// of node `i` (`a`) of mesh 1 and node `j` (`b`) of mesh 2. One-sided: only the side of
    /// each subtree facing the other is computed.
    #[inline]
    pub(crate) fn gap(
        &self,
        lanes: Lanes4,
        (i, a): (u32, &Node),
        (j, b): (u32, &Node),
        axis: Vec3,
    ) -> f64 {
        let hi1 = lanes.max_along(self.c1.points(i, a), axis);
        let lo2 = -lanes.max_along(self.c2.points(j, b), -(self.rot21 * axis));
        lo2 - hi1 + axis.dot(self.origins) - self.error
    }
}
