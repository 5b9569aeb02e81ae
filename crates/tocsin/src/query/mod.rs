//! Queries, one folder each. Public functions take world poses; the traversals and kernels
//! work in the first mesh's frame with `pos12` (mesh 2's frame seen from mesh 1's).

pub mod collide;
pub mod contact_time;
pub mod distance;
pub mod penetration;
