//! The bounding volume hierarchy: a binary tree of [`Rss`] volumes in one flat array.
//!
//! Layout (preorder): node `i` with `n` triangles owns the `2n - 1` entries from `i`; its left
//! child is `i + 1` and its right child is `node.right`. Each leaf holds exactly one triangle,
//! stored by its position in [`Bvh::leaf_triangles`] (the triangles' corners are copied there in
//! leaf order, so traversal never chases vertex indices). Everything is in the mesh's frame.

mod build;
mod eigen;
mod rss;
mod rss4;

pub use rss::Rss;
pub(crate) use rss::{rss_separation, ASide, BSide, RelativeRss};
pub(crate) use rss4::Lanes4;

use crate::math::Vec3;

/// One node of the hierarchy.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    /// The bounding volume, mesh frame.
    pub rss: Rss,
    /// Index of the right child, or 0 for a leaf (the root is never a right child).
    right: u32,
    /// For a leaf: the position of its triangle in leaf order.
    leaf: u32,
}

impl Node {
    /// Whether the node is a leaf (holds one triangle).
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.right == 0
    }

    /// The two children, for an internal node at index `index`.
    #[inline]
    pub fn children(&self, index: u32) -> (u32, u32) {
        (index + 1, self.right)
    }

    /// For a leaf, the position of its triangle in [`Bvh::leaf_triangles`].
    #[inline]
    pub fn leaf_position(&self) -> u32 {
        self.leaf
    }
}

/// A bounding volume hierarchy of rectangle swept spheres over a mesh's triangles.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Corners of the triangles in leaf order (mesh frame).
    leaf_corners: Vec<[Vec3; 3]>,
    /// Original index of each triangle in leaf order.
    leaf_ids: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy top-down (principal-axis split at the mean of the centroids).
    /// `triangles` must be non-empty with indices in range (checked by `TriMesh`).
    pub(crate) fn build(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        build::build(vertices, triangles)
    }

    /// All nodes, root first.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The root node.
    pub fn root(&self) -> &Rss {
        &self.nodes[0].rss
    }

    /// The triangles' corners in leaf order (mesh frame).
    pub fn leaf_triangles(&self) -> &[[Vec3; 3]] {
        &self.leaf_corners
    }

    /// The original triangle index of the triangle at leaf position `position`.
    #[inline]
    pub fn triangle_index(&self, position: u32) -> usize {
        self.leaf_ids[position as usize] as usize
    }
}
