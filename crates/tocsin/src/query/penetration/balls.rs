//! Balls inside a closed mesh, and the lower bound they give on a directional penetration
//! depth.
//!
//! **Where the bound holds.** When a mesh's triangles form a closed, consistently oriented
//! surface (every directed edge, with vertices taken by position, matched by one in the other
//! direction: the triangles form a cycle), its generalized winding number is an integer off
//! the surface and changes only across it, so a point inside (`|w| > 1/2`) at distance `r` from
//! the surface is the centre of an open ball of radius `r` inside the solid. When the surface
//! is also connected, the penetration test of [`super::depth`] (surfaces intersect, or a corner
//! of one inside the other) holds wherever the two solids overlap: if their surfaces do not
//! cross, one solid lies in the other, and then so does that one's corner. So if body 2's ball
//! `j` still overlaps the union of body 1's balls after body 2 moves by `s d` for every `s` in
//! `[0, h)`, every translation of body 2 along `d` shorter than `h` still penetrates: the
//! directional depth along `d`, and any touching translation found along `d`, is at least `h`.
//!
//! **How the balls are found.** Per mesh, once: at up to [`BALLS`] triangles spread over the
//! hierarchy's leaves (every k-th leaf), the largest ball tangent to the surface at the
//! triangle's centroid, on its inner side (Ma, Bai and Tong's shrinking ball, with the exact
//! distance to the mesh), its centre kept when it is inside and its radius the centre's exact
//! distance to the surface.
//! Where the mesh is open, inconsistently oriented or disconnected there are none, and no
//! bound.

use std::collections::HashMap;

use crate::bvh::same_position;
use crate::math::{Pose, Vec3};
use crate::query::penetration::surface::point_to_mesh;
use crate::query::penetration::winding::inside;
use crate::TriMesh;

/// Balls sought per mesh: one per sampled triangle, at most this many, and at most one per 16
/// triangles.
pub(crate) const BALLS: usize = 128;

/// Body 2's balls that bound each direction: those overlapping body 1's deepest (the run of a
/// ball that barely overlaps is short). All of them cost the Panda link (300 triangles) a
/// third more time at 20% of the radius; these are the ones that give the runs.
const MOVED: usize = 8;

/// A ball inside a closed mesh (body frame).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ball {
    pub(crate) center: Vec3,
    pub(crate) radius: f64,
}

/// Whether the triangles form one closed, consistently oriented, connected surface, with
/// vertices taken by position (duplicated vertices at one position are one).
fn closed_and_connected(mesh: &TriMesh) -> bool {
    // Vertex ids by exact position (+0 and -0 alike): the first vertex at each position.
    let id = same_position(mesh.vertices());
    let mut balance: HashMap<(u32, u32), i64> = HashMap::with_capacity(3 * mesh.num_triangles());
    let mut parent: Vec<u32> = (0..id.len() as u32).collect();
    let root = super::union_root;
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| id[i as usize]);
        for (x, y) in [(a, b), (b, c), (c, a)] {
            if x == y {
                continue;
            }
            // +1 for x -> y, -1 for y -> x, keyed by the ordered pair.
            let (k, s) = if x < y { ((x, y), 1) } else { ((y, x), -1) };
            *balance.entry(k).or_insert(0) += s;
            let (rx, ry) = (root(&mut parent, x), root(&mut parent, y));
            parent[rx as usize] = ry;
        }
    }
    if balance.values().any(|&b| b != 0) {
        return false;
    }
    // Connected: every vertex used by a triangle has one root.
    let mut first = None;
    for t in mesh.triangles() {
        for &i in t {
            let r = root(&mut parent, id[i as usize]);
            match first {
                None => first = Some(r),
                Some(f) if f != r => return false,
                _ => {}
            }
        }
    }
    true
}

/// The balls of `mesh` (module docs); empty where the mesh is not one closed connected
/// surface.
pub(crate) fn inscribed_balls(mesh: &TriMesh) -> Vec<Ball> {
    if !closed_and_connected(mesh) {
        return Vec::new();
    }
    let tris = mesh.bvh().leaf_triangles();
    // Outward or inward: the sign of the enclosed volume.
    let volume: f64 = tris.iter().map(|[a, b, c]| a.dot(b.cross(*c))).sum();
    if volume == 0.0 || !volume.is_finite() {
        return Vec::new();
    }
    let inward = if volume > 0.0 { -1.0 } else { 1.0 };
    let r0 = 2.0 * mesh.bounding_radius();
    let stride = tris
        .len()
        .div_ceil(BALLS.min(tris.len() / 16).max(1))
        .max(1);
    let mut out = Vec::new();
    for (leaf, t) in tris.iter().enumerate().step_by(stride) {
        let Some(n) = (t[1] - t[0]).cross(t[2] - t[0]).try_normalize() else {
            continue;
        };
        let n = n * inward;
        let x = (t[0] + t[1] + t[2]) / 3.0;
        let mut r = r0;
        let mut warm = leaf as u32;
        let mut center = x + n * r;
        for _ in 0..16 {
            center = x + n * r;
            let (d, y, l) = point_to_mesh(mesh.bvh(), center, warm);
            warm = l;
            let along = n.dot(y - x);
            if d >= r * (1.0 - 1e-3) || along <= 0.0 {
                break;
            }
            // The ball tangent at x through y.
            r = (y - x).length_squared() / (2.0 * along);
            if !(r > 0.0 && r.is_finite()) {
                break;
            }
        }
        let (d, _, _) = point_to_mesh(mesh.bvh(), center, warm);
        let radius = d * (1.0 - 1e-9);
        if radius > 0.0 && inside(mesh, center) {
            out.push(Ball { center, radius });
        }
    }
    out
}

/// Per unit direction `d` (world), a shift `h >= 0` such that body 2 moved by any `s d` with
/// `0 <= s < h` still penetrates body 1 (module docs): the largest, over the [`MOVED`] balls of
/// body 2 that overlap body 1's most deeply, of the end of the run of shifts from 0 over which
/// the moved ball keeps overlapping the union of body 1's balls. 0 for every direction where
/// either mesh has no balls.
pub(crate) fn penetrating_shifts(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    directions: &[Option<Vec3>],
) -> Vec<f64> {
    let (a, b) = (mesh1.inscribed_balls(), mesh2.inscribed_balls());
    let mut out = vec![0.0; directions.len()];
    if a.is_empty() || b.is_empty() {
        return out;
    }
    // Body 2's balls in body 1's frame that overlap one of body 1's at the pose.
    let to1 = pose1.inv_mul(pose2);
    let mut moved: Vec<(f64, Ball)> = b
        .iter()
        .map(|q| Ball {
            center: to1.transform_point(q.center),
            radius: q.radius,
        })
        .filter_map(|q| {
            let o = a.iter().fold(f64::NEG_INFINITY, |o, p| {
                o.max((p.radius + q.radius) * SHRINK - (q.center - p.center).length())
            });
            (o > 0.0).then_some((o, q))
        })
        .collect();
    moved.sort_by(|x, y| y.0.total_cmp(&x.0));
    moved.truncate(MOVED);
    let moved: Vec<Ball> = moved.into_iter().map(|(_, q)| q).collect();
    if moved.is_empty() {
        return out;
    }
    let mut intervals: Vec<(f64, f64)> = Vec::with_capacity(a.len());
    for (h, d) in out.iter_mut().zip(directions) {
        let Some(d) = d else { continue };
        let d = pose1.rotation.transpose() * *d;
        for q in &moved {
            intervals.clear();
            for p in a {
                // |q + s d - p| < rho for s in (-b - sqrt(D), -b + sqrt(D)).
                let delta = q.center - p.center;
                let rho = (p.radius + q.radius) * SHRINK;
                let along = delta.dot(d);
                let disc = along * along - (delta.length_squared() - rho * rho);
                if disc > 0.0 {
                    let root = disc.sqrt();
                    let (lo, hi) = (-along - root, -along + root);
                    if hi > 0.0 {
                        intervals.push((lo, hi));
                    }
                }
            }
            intervals.sort_by(|x, y| x.0.total_cmp(&y.0));
            // The run of overlapping intervals from 0 (the ball overlaps one at 0).
            let mut end = 0.0;
            for &(lo, hi) in &intervals {
                if lo >= end {
                    break;
                }
                end = f64::max(end, hi);
            }
            // Rounding: a shift just below the run's end is what is claimed.
            *h = f64::max(*h, end * SHRINK);
        }
    }
    out
}

/// Radii and run ends are shrunk by this factor, so that rounding cannot overstate an overlap.
const SHRINK: f64 = 1.0 - 1e-9;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use crate::query::penetration::winding::{winding_number, WindingOptions};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Closed, consistently oriented and connected surfaces have balls; an open plate, two
    /// disjoint boxes, a box with a flipped triangle and a box with one triangle missing have
    /// none.
    #[test]
    fn only_one_closed_surface_has_balls() {
        let knot = mesh::torus_knot(60, 6).expect("knot");
        let cube = mesh::box_mesh(Vec3::splat(1.0)).expect("box");
        assert!(closed_and_connected(&knot) && closed_and_connected(&cube));
        assert!(!inscribed_balls(&knot).is_empty());
        assert!(!inscribed_balls(&cube).is_empty());
        let plate = mesh::plate(1.0, 4).expect("plate");
        assert!(!closed_and_connected(&plate));
        let (v, t) = (cube.vertices().to_vec(), cube.triangles().to_vec());
        let mut two_v = v.clone();
        two_v.extend(v.iter().map(|p| *p + Vec3::new(5.0, 0.0, 0.0)));
        let mut two_t = t.clone();
        two_t.extend(t.iter().map(|x| x.map(|i| i + v.len() as u32)));
        let two = TriMesh::new(two_v, two_t).expect("two boxes");
        assert!(!closed_and_connected(&two));
        assert!(inscribed_balls(&two).is_empty());
        let mut flipped = t.clone();
        flipped[0].swap(1, 2);
        assert!(!closed_and_connected(
            &TriMesh::new(v.clone(), flipped).expect("flipped")
        ));
        let holed = TriMesh::new(v.clone(), t[1..].to_vec()).expect("holed");
        assert!(!closed_and_connected(&holed));
        // Duplicated vertices at one position are one vertex: still closed.
        let mut dv = v.clone();
        dv.extend(v.iter().copied());
        let dt: Vec<[u32; 3]> = t
            .iter()
            .enumerate()
            .map(|(k, x)| {
                if k % 2 == 0 {
                    x.map(|i| i + v.len() as u32)
                } else {
                    *x
                }
            })
            .collect();
        assert!(closed_and_connected(
            &TriMesh::new(dv, dt).expect("duplicated")
        ));
    }

    /// Every ball lies inside its mesh: its centre's exact winding number has magnitude about
    /// 1, and no triangle comes nearer the centre than the radius (brute force over all
    /// triangles), on knots, a sphere and a box, and on a knot scaled by 1e-6 and 1e6.
    #[test]
    fn balls_lie_inside() {
        let knot = mesh::torus_knot(120, 8).expect("knot");
        let scaled = |s: f64| {
            let v: Vec<Vec3> = knot.vertices().iter().map(|p| *p * s).collect();
            TriMesh::new(v, knot.triangles().to_vec()).expect("scaled")
        };
        let meshes = [
            mesh::torus_knot(60, 6).expect("knot"),
            mesh::sphere(1.0, 12, 24).expect("sphere"),
            mesh::box_mesh(Vec3::new(1.0, 0.2, 3.0)).expect("box"),
            scaled(1e-6),
            scaled(1e6),
        ];
        for m in &meshes {
            let balls = inscribed_balls(m);
            assert!(balls.len() >= m.num_triangles().min(16 * BALLS) / 32);
            let centers: Vec<Vec3> = balls.iter().map(|b| b.center).collect();
            let exact = WindingOptions {
                beta: f64::INFINITY,
            };
            let w = winding_number(m, &Pose::IDENTITY, &centers, &exact).expect("winding");
            for (b, w) in balls.iter().zip(w) {
                assert!((w.abs() - 1.0).abs() < 1e-6, "winding {w} at a centre");
                let nearest = (0..m.num_triangles())
                    .map(|i| {
                        crate::query::penetration::surface::tests::oracle_distance(
                            b.center,
                            &m.triangle(i),
                        )
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    b.radius > 0.0 && b.radius <= nearest,
                    "{} > {nearest}",
                    b.radius
                );
            }
        }
    }

    /// The shifts' contract against the penetration test itself: on a knot and a turned copy
    /// overlapping it by 1% to 30% of the radius, with body 1 placed away from the origin, at
    /// 12 random shifts below each direction's answer, the bodies still penetrate; and the
    /// answer is positive for some direction at most poses.
    #[test]
    fn shifts_below_the_answer_penetrate() {
        let m = mesh::torus_knot(80, 8).expect("knot");
        let r = m.bounding_radius();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let pose1 = Pose::from_axis_angle(Vec3::new(0.2, 1.0, 0.3), 0.4, Vec3::new(3.0, -2.0, 1.0));
        let (mut positive, mut poses) = (0, 0);
        while poses < 24 {
            let offset = unit(&mut rng) * r * rng.random_range(0.01..0.3);
            let pose2 = Pose::from_axis_angle(unit(&mut rng), rng.random_range(0.0..3.0), offset);
            let pose2 = pose1.mul(&pose2);
            let mut hint = None;
            if !super::super::depth::penetrating(&m, &pose1, &m, &pose2, &mut hint) {
                continue;
            }
            poses += 1;
            let dirs: Vec<Option<Vec3>> = (0..16).map(|_| Some(unit(&mut rng))).collect();
            let shifts = penetrating_shifts(&m, &pose1, &m, &pose2, &dirs);
            if shifts.iter().any(|&h| h > 0.0) {
                positive += 1;
            }
            for (d, h) in dirs.iter().zip(&shifts) {
                let d = d.expect("unit");
                for _ in 0..12 {
                    let s = h * rng.random::<f64>();
                    let moved = Pose {
                        rotation: pose2.rotation,
                        translation: pose2.translation + d * s,
                    };
                    let mut hint = None;
                    assert!(
                        super::super::depth::penetrating(&m, &pose1, &m, &moved, &mut hint),
                        "free at {s} below {h}"
                    );
                }
            }
        }
        assert!(
            positive >= 12,
            "{positive} of 24 poses with a positive shift"
        );
    }
}
