//! Which triangle pairs a screw can never bring within the tolerance, settled once for the
//! whole query in the plane of the screw's invariants ([`super::helix`]).
//!
//! A pair's helical bound is small work, but there are too many pairs to bound one by one: the
//! invariants forget the angle, so every triangle of a bolt, at whatever angle, faces every
//! triangle of its nut at the same phase, and a bolt of 98K triangles screwed half a turn into
//! a nut of 32K made 16M pairs of the two hierarchies (16 s). In the plane of `(rho, s zeta)`
//! those triangles' images are stacked on two curves, the thread's profiles, and a hierarchy
//! built over the images there groups them: two groups a fraction of the pitch long are
//! separated by one bound of their boxes.
//!
//! Each triangle far enough from the axis ([`Helix::image`]) becomes a flat triangle of that
//! plane and a margin; the still body's images are repeated one period below and above, so
//! that every branch of the phase is met. A dual traversal of the two images' hierarchies
//! finds the pairs whose images are within the tolerance plus their margins; their triangles
//! are unresolved, as are those too near the axis to have an image. Every pair of resolved
//! triangles stays farther apart than the tolerance over the whole motion, so a node pair
//! whose triangles are all resolved needs no bound at all.

use super::helix::Corner;
use super::helix::Helix;
use super::shells::Range;
use crate::math::{Pose, Vec3};
use crate::query::distance::distance_triangle_triangle;
use crate::TriMesh;

/// Image pairs a traversal may test, per image, before it stops and leaves the triangles it has
/// not settled open (a clear fit tests far fewer).
const PAIRS_PER_IMAGE: usize = 64;

/// The resolved triangles of the two bodies (by leaf position in their hierarchies).
pub(crate) struct Quotient {
    /// Running counts of unresolved leaves: `[i]` counts those before position `i`.
    turning: Vec<u32>,
    still: Vec<u32>,
}

/// A triangle's image: corners, margin, and its leaf position.
#[derive(Clone, Copy)]
struct Image {
    corners: [[f64; 2]; 3],
    /// The corners' mean.
    centre: [f64; 2],
    margin: f64,
    leaf: u32,
}

impl Image {
    fn new(corners: [[f64; 2]; 3], margin: f64, leaf: u32) -> Self {
        let mean = |k: usize| (corners[0][k] + corners[1][k] + corners[2][k]) / 3.0;
        Self {
            corners,
            centre: [mean(0), mean(1)],
            margin,
            leaf,
        }
    }
}

/// A node of an images' hierarchy: the oriented box of its images (along their corners'
/// principal direction, so that a stretch of a curved profile, however many images are stacked
/// on it, is a thin box) grown by their largest margin, and either two children or a run of
/// images.
struct Node {
    centre: [f64; 2],
    /// Unit direction of the box's first side; the second is across it.
    axis: [f64; 2],
    half: [f64; 2],
    /// Its images: `count` from `first`.
    first: u32,
    count: u32,
    /// Its children's index (the two are adjacent), once split.
    children: Option<u32>,
}

impl Node {
    /// The box over the images' corners (their principal direction from one pass of sums).
    fn over(images: &[Image]) -> Self {
        // The principal direction of the corners of at most `SAMPLE` images spread over the
        // run (the box is all the corners' whatever the direction; the direction only makes it
        // thin): one pass less over a large node's images. Not of the centres: a few images
        // stacked on each other have nearly one centre, and no direction.
        const SAMPLE: usize = 256;
        let stride = images.len().div_ceil(SAMPLE);
        let origin = images[0].centre;
        let (mut sx, mut sy, mut sxx, mut sxy, mut syy, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for c in images
            .iter()
            .step_by(stride)
            .flat_map(|im| im.corners.iter())
        {
            let (x, y) = (c[0] - origin[0], c[1] - origin[1]);
            sx += x;
            sy += y;
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
            n += 1.0;
        }
        let (mx, my) = (sx / n, sy / n);
        let (cxx, cxy, cyy) = (sxx / n - mx * mx, sxy / n - mx * my, syy / n - my * my);
        let angle = 0.5 * (2.0 * cxy).atan2(cxx - cyy);
        let (e, f) = ([angle.cos(), angle.sin()], [-angle.sin(), angle.cos()]);
        // One pass over the corners (comparisons rather than `min`: the images are finite).
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut margin = 0.0f64;
        for im in images {
            margin = if im.margin > margin {
                im.margin
            } else {
                margin
            };
            for c in &im.corners {
                let (dx, dy) = (c[0] - origin[0], c[1] - origin[1]);
                let (p, q) = (dx * e[0] + dy * e[1], dx * f[0] + dy * f[1]);
                lo[0] = if p < lo[0] { p } else { lo[0] };
                lo[1] = if q < lo[1] { q } else { lo[1] };
                hi[0] = if p > hi[0] { p } else { hi[0] };
                hi[1] = if q > hi[1] { q } else { hi[1] };
            }
        }
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        Node {
            centre: [
                origin[0] + e[0] * mid[0] + f[0] * mid[1],
                origin[1] + e[1] * mid[0] + f[1] * mid[1],
            ],
            axis: e,
            half: [
                0.5 * (hi[0] - lo[0]) + margin,
                0.5 * (hi[1] - lo[1]) + margin,
            ],
            first: 0,
            count: images.len() as u32,
            children: None,
        }
    }

    /// Half its extent along the unit `d`.
    fn reach(&self, d: [f64; 2]) -> f64 {
        let (e, f) = (self.axis, [-self.axis[1], self.axis[0]]);
        self.half[0] * (e[0] * d[0] + e[1] * d[1]).abs()
            + self.half[1] * (f[0] * d[0] + f[1] * d[1]).abs()
    }

    fn size(&self) -> f64 {
        self.half[0].max(self.half[1])
    }
}

/// A hierarchy of boxes over images, split across a box's longer side (at its middle, or at
/// the median where the middle leaves one side under an eighth) when a traversal first needs
/// the node's children: the certificate stops high in the trees, and
/// building them whole took 50 ms of 66 for a bolt and its nut.
struct Tree {
    images: Vec<Image>,
    nodes: Vec<Node>,
}

/// Images per leaf.
const LEAF: usize = 4;

impl Tree {
    fn new(images: Vec<Image>) -> Self {
        let nodes = if images.is_empty() {
            Vec::new()
        } else {
            vec![Node::over(&images)]
        };
        Self { images, nodes }
    }

    /// The node's images.
    fn run(&self, index: usize) -> &[Image] {
        let n = &self.nodes[index];
        &self.images[n.first as usize..(n.first + n.count) as usize]
    }

    fn is_leaf(&self, index: usize) -> bool {
        self.nodes[index].count as usize <= LEAF
    }

    /// The node's children, split now if not yet.
    fn children(&mut self, index: usize) -> usize {
        if let Some(c) = self.nodes[index].children {
            return c as usize;
        }
        let node = &self.nodes[index];
        let (first, count) = (node.first as usize, node.count as usize);
        let d = if node.half[0] >= node.half[1] {
            node.axis
        } else {
            [-node.axis[1], node.axis[0]]
        };
        let key = |im: &Image| im.centre[0] * d[0] + im.centre[1] * d[1];
        let images = &mut self.images[first..first + count];
        // Split at the box's middle across that side: one pass, and images spread along a
        // profile fall about evenly. Where one side would get under an eighth (images bunched
        // at one end, or none), at the median instead.
        let cut = key(&Image::new([node.centre; 3], 0.0, 0));
        let mut mid = 0;
        for i in 0..count {
            if key(&images[i]) < cut {
                images.swap(i, mid);
                mid += 1;
            }
        }
        if mid.min(count - mid) < count.div_ceil(8) {
            mid = count / 2;
            images.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)));
        }
        let (mut a, mut b) = (Node::over(&images[..mid]), Node::over(&images[mid..]));
        a.first = first as u32;
        b.first = (first + mid) as u32;
        let c = self.nodes.len();
        self.nodes.push(a);
        self.nodes.push(b);
        self.nodes[index].children = Some(c as u32);
        c
    }
}

/// A lower bound on the distance between two boxes: the largest gap between their projections
/// on the four directions of their sides.
fn box_gap(a: &Node, b: &Node) -> f64 {
    let rel = [b.centre[0] - a.centre[0], b.centre[1] - a.centre[1]];
    let mut gap = 0.0f64;
    for n in [a, b] {
        for d in [n.axis, [-n.axis[1], n.axis[0]]] {
            let apart = (rel[0] * d[0] + rel[1] * d[1]).abs();
            gap = gap.max(apart - a.reach(d) - b.reach(d));
        }
    }
    gap
}

/// An upper bound on the distance between any two points of two boxes.
fn farthest(a: &Node, b: &Node) -> f64 {
    let rel = [b.centre[0] - a.centre[0], b.centre[1] - a.centre[1]];
    rel[0].hypot(rel[1]) + a.half[0].hypot(a.half[1]) + b.half[0].hypot(b.half[1])
}

/// The distance between two images' flat triangles.
fn image_gap(a: &Image, b: &Image) -> f64 {
    let lift = |c: [[f64; 2]; 3]| c.map(|p| Vec3::new(p[0], p[1], 0.0));
    distance_triangle_triangle(&lift(a.corners), &lift(b.corners)).distance
}

impl Quotient {
    /// The resolved triangles of the turning mesh `turning` and the still one `still`, at the
    /// tolerance `delta`.
    pub(crate) fn build(helix: &Helix, turning: &TriMesh, still: &TriMesh, delta: f64) -> Self {
        // Every vertex's axial coordinate (the angles, which cost an `atan2`, only where an
        // image needs them).
        let axial = |mesh: &TriMesh, pose: &Pose| -> Vec<f64> {
            mesh.vertices()
                .iter()
                .map(|&v| helix.axial(pose.transform_point(v)))
                .collect()
        };
        let (z_t, z_s) = (
            axial(turning, helix.start()),
            axial(still, helix.still_pose()),
        );
        // Along the axis: where the turning body's triangle, over the whole slide, and the
        // still body (or the other way round) are farther apart than the tolerance, no pair
        // of theirs ever comes within it, and the triangle needs no image (most of a bolt
        // longer than its nut).
        let z_range = |zs: &[f64]| zs.iter().fold(Range::EMPTY, |r, &z| r.with(z));
        let travel = helix.travel();
        let slid = |r: Range| Range {
            lo: r.lo + travel.min(0.0),
            hi: r.hi + travel.max(0.0),
        };
        let (reach_t, reach_s) = (slid(z_range(&z_t)), z_range(&z_s));
        // Each body's triangles in its hierarchy's leaf order: whether each is open (too near
        // the axis for an image), and the images of those within the other body's reach along
        // the axis.
        let imaged = |mesh: &TriMesh, pose: &Pose, zs: &[f64], moves: bool, other: Range| {
            let bvh = mesh.bvh();
            let leaf = |i: usize| mesh.triangles()[bvh.triangle_index(i as u32)];
            let count = bvh.leaf_triangles().len();
            let mut needed = vec![false; zs.len()];
            let near: Vec<bool> = (0..count)
                .map(|i| {
                    let tri = leaf(i);
                    let z = tri
                        .iter()
                        .fold(Range::EMPTY, |r, &v| r.with(zs[v as usize]));
                    let z = if moves { slid(z) } else { z };
                    let near = z.gap(other) <= delta;
                    if near {
                        for v in tri {
                            needed[v as usize] = true;
                        }
                    }
                    near
                })
                .collect();
            let mut corners = vec![Corner::default(); zs.len()];
            for ((c, &v), _) in corners
                .iter_mut()
                .zip(mesh.vertices())
                .zip(&needed)
                .filter(|(_, &n)| n)
            {
                *c = helix.vertex(pose.transform_point(v));
            }
            let mut open = vec![false; count];
            let mut images = Vec::with_capacity(near.iter().filter(|&&n| n).count());
            for i in (0..count).filter(|&i| near[i]) {
                match helix.image(leaf(i).map(|v| &corners[v as usize])) {
                    Some((c, margin)) => images.push(Image::new(c, margin, i as u32)),
                    None => open[i] = true,
                }
            }
            (open, images)
        };
        let (mut open_t, images_t) = imaged(turning, helix.start(), &z_t, true, reach_s);
        let (mut open_s, still_images) = imaged(still, helix.still_pose(), &z_s, false, reach_t);
        // The still images are repeated on every branch of the phase (whole periods up or
        // down) that comes within the tolerance and the margins of a turning image: on any
        // other, every pair is farther apart than that in the phase alone.
        let period = helix.period();
        let span = |im: &Image| {
            let r = im.corners.iter().fold(Range::EMPTY, |r, c| r.with(c[1]));
            Range {
                lo: r.lo - im.margin,
                hi: r.hi + im.margin,
            }
        };
        let reach = images_t
            .iter()
            .map(span)
            .fold(Range::EMPTY, |r, s| r.with(s.lo).with(s.hi));
        let mut images_s = Vec::with_capacity(still_images.len() + still_images.len() / 4);
        for image in still_images {
            let own = span(&image);
            let first = ((reach.lo - delta - own.hi) / period).ceil();
            let last = ((reach.hi + delta - own.lo) / period).floor();
            if last - first > 4.0 {
                // Spread over several periods (a triangle across many turns of the thread):
                // left to the per-pair bounds.
                open_s[image.leaf as usize] = true;
                continue;
            }
            let mut m = first;
            while m <= last {
                let shift = m * period;
                images_s.push(Image {
                    corners: image.corners.map(|c| [c[0], c[1] + shift]),
                    centre: [image.centre[0], image.centre[1] + shift],
                    ..image
                });
                m += 1.0;
            }
        }
        let budget = PAIRS_PER_IMAGE * (images_t.len() + images_s.len());
        let (mut tree_t, mut tree_s) = (Tree::new(images_t), Tree::new(images_s));
        if !tree_t.nodes.is_empty() && !tree_s.nodes.is_empty() {
            let mut stack = vec![(0usize, 0usize)];
            let mut tested = 0usize;
            while let Some((a, b)) = stack.pop() {
                let (na, nb) = (&tree_t.nodes[a], &tree_s.nodes[b]);
                if box_gap(na, nb) > delta {
                    continue;
                }
                if farthest(na, nb) <= 2.0 * delta {
                    // Everything in the two boxes is close: leave all their triangles open
                    // rather than test their images pair by pair (a tight fit stacks hundreds
                    // on each other). Leaving a triangle open never claims anything.
                    for im in tree_t.run(a) {
                        open_t[im.leaf as usize] = true;
                    }
                    for im in tree_s.run(b) {
                        open_s[im.leaf as usize] = true;
                    }
                    continue;
                }
                let (leaf_a, leaf_b) = (tree_t.is_leaf(a), tree_s.is_leaf(b));
                if leaf_a && leaf_b {
                    let (na, nb) = (&tree_t.nodes[a], &tree_s.nodes[b]);
                    let ra = na.first as usize..(na.first + na.count) as usize;
                    let rb = nb.first as usize..(nb.first + nb.count) as usize;
                    for ia in &tree_t.images[ra] {
                        for ib in &tree_s.images[rb.clone()] {
                            if open_t[ia.leaf as usize] && open_s[ib.leaf as usize] {
                                continue;
                            }
                            tested += 1;
                            if image_gap(ia, ib) - ia.margin - ib.margin <= delta {
                                open_t[ia.leaf as usize] = true;
                                open_s[ib.leaf as usize] = true;
                            }
                        }
                    }
                    if tested > budget {
                        // Too many images within reach of each other (a tight fit all along, or
                        // a screw at another pitch than the thread's): leave every triangle
                        // still to be tested open, and stop.
                        for &(a, b) in &stack {
                            for im in tree_t.run(a) {
                                open_t[im.leaf as usize] = true;
                            }
                            for im in tree_s.run(b) {
                                open_s[im.leaf as usize] = true;
                            }
                        }
                        break;
                    }
                    continue;
                }
                if !leaf_a && (leaf_b || tree_t.nodes[a].size() >= tree_s.nodes[b].size()) {
                    let c = tree_t.children(a);
                    stack.push((c, b));
                    stack.push((c + 1, b));
                } else {
                    let c = tree_s.children(b);
                    stack.push((a, c));
                    stack.push((a, c + 1));
                }
            }
        }
        let running = |open: &[bool]| {
            let mut counts = Vec::with_capacity(open.len() + 1);
            let mut total = 0u32;
            counts.push(0);
            for &o in open {
                total += u32::from(o);
                counts.push(total);
            }
            counts
        };
        Self {
            turning: running(&open_t),
            still: running(&open_s),
        }
    }

    /// Whether every triangle of the turning leaf run `turning` and the still leaf run `still`
    /// is resolved: no pair of them ever comes within the tolerance.
    pub(crate) fn resolved(
        &self,
        turning: std::ops::Range<usize>,
        still: std::ops::Range<usize>,
    ) -> bool {
        self.turning[turning.end] == self.turning[turning.start]
            && self.still[still.end] == self.still[still.start]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::sampling::unit;
    use crate::motion::Motion;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::f64::consts::TAU;

    /// A bolt in its nut (random threads and tessellations, the nut's thread deeper so that
    /// its clearance varies from about the tolerance to a few, turned by a random phase, with
    /// a few stray triangles in odd cases), at a random pose, screwed about its axis along its
    /// thread or at another pitch: every pair of resolved triangles is farther apart than the
    /// tolerance at every sampled time (the distance between the resolved ones, by the exact
    /// distance query), and the certificate resolves a fifth of them at least where the screw
    /// follows the thread. Counting pairs as apart from half the tolerance fails it (a resolved
    /// pair 0.0044 apart at a tolerance of 0.005).
    #[test]
    fn resolved_triangles_stay_apart() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let (mut resolved, mut total, mut some_open) = (0, 0, 0);
        for case in 0..16 {
            let pitch = rng.random_range(0.2..0.6);
            let depth = rng.random_range(0.02..0.15);
            let delta = [0.005, 0.02][case % 2];
            // The nut's thread a little deeper (by `extra`), so that its clearance varies along
            // the profile, and turned by `phase`: tight spots anywhere on the phase, the branch
            // boundary included.
            let extra = depth * rng.random_range(0.0..0.2);
            let phase = rng.random_range(0.0..TAU);
            let thread = move |c: f64, d: f64, p0: f64| {
                move |a: f64, z: f64| 1.0 + c + d * (TAU * z / pitch - a + p0).sin()
            };
            // Fine threads whose flanks are about 0.4 to 1.6 tolerances apart (the images'
            // margins small: some pairs only just within the tolerance, some only just beyond),
            // and coarse ones whose facets reach inside the surface by about the clearance
            // (where the margins decide).
            let fine = case % 4 < 2;
            let cols = if fine {
                rng.random_range(150..250)
            } else {
                rng.random_range(30..60)
            };
            let rows = (2.0 * rng.random_range(12.0..24.0) / pitch) as usize;
            let reach = 1.2 * (1.0 - (TAU / 2.0 / cols as f64).cos())
                + depth * (1.0 - (TAU / 2.0 * 2.0 / rows as f64 / pitch).cos());
            let slope = depth * TAU / pitch;
            let across = if fine {
                delta * rng.random_range(0.4..1.6)
            } else {
                reach * rng.random_range(0.5..3.0) + 0.5 * delta
            };
            let clearance = across * (1.0 + slope * slope).sqrt() + extra;
            let inner =
                crate::mesh::revolved(thread(0.0, depth, 0.0), 2.0, cols, rows).expect("bolt");
            let nut = thread(clearance, depth + extra, 0.0);
            let mut outer = crate::mesh::revolved(nut, 1.0, cols + 5, rows).expect("nut");
            let turn_nut = Pose::from_axis_angle(Vec3::Z, phase, Vec3::ZERO);
            outer = TriMesh::new(
                outer
                    .vertices()
                    .iter()
                    .map(|&v| turn_nut.transform_point(v))
                    .collect(),
                outer.triangles().to_vec(),
            )
            .expect("turned nut");
            if case % 2 == 1 {
                let strays: Vec<Vec3> = (0..9)
                    .map(|_| unit(&mut rng) * rng.random_range(0.0..1.3))
                    .collect();
                let base = outer.vertices().len() as u32;
                let vertices = [outer.vertices(), &strays].concat();
                let triangles = outer
                    .triangles()
                    .iter()
                    .copied()
                    .chain((0..3).map(|i| [base + 3 * i, base + 3 * i + 1, base + 3 * i + 2]))
                    .collect();
                outer = TriMesh::new(vertices, triangles).expect("nut and strays");
            }
            let follows = case % 4 != 3;
            // The assembly at a random pose; the screw about its axis.
            let place =
                Pose::from_axis_angle(unit(&mut rng), rng.random_range(0.0..3.0), unit(&mut rng));
            let angle = rng.random_range(0.5..3.0);
            let k = if follows {
                pitch / TAU
            } else {
                rng.random_range(-0.1..0.1)
            };
            let turn = Pose::from_axis_angle(Vec3::Z, angle, Vec3::Z * (k * angle));
            let end = place.mul(&turn);
            let motion = Motion::screw(place, end).expect("screw");
            let axis = motion.fixed_axis().expect("axis");
            let helix = Helix::new(&axis, motion.start(), place).expect("helix");
            let q = Quotient::build(&helix, &inner, &outer, delta);
            let mut keep = |mesh: &TriMesh, counts: &[u32]| {
                let bvh = mesh.bvh();
                let tris: Vec<[Vec3; 3]> = (0..bvh.leaf_triangles().len())
                    .filter(|&i| counts[i + 1] == counts[i])
                    .map(|i| bvh.leaf_triangles()[i])
                    .collect();
                if follows {
                    total += bvh.leaf_triangles().len();
                    resolved += tris.len();
                }
                some_open += usize::from(tris.len() < bvh.leaf_triangles().len());
                (!tris.is_empty()).then(|| {
                    let vertices: Vec<Vec3> = tris.iter().flatten().copied().collect();
                    let triangles = (0..tris.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]);
                    TriMesh::new(vertices, triangles.collect()).expect("resolved part")
                })
            };
            let (Some(a), Some(b)) = (keep(&inner, &q.turning), keep(&outer, &q.still)) else {
                continue;
            };
            for i in 0..=64 {
                let pose = motion.pose_at(f64::from(i) / 64.0);
                let d =
                    crate::query::distance::distance(&a, &pose, &b, &place, &Default::default())
                        .expect("distance")
                        .distance;
                assert!(
                    d > delta,
                    "case {case}: resolved triangles {d} apart at step {i}"
                );
            }
        }
        assert!(5 * resolved > total, "{resolved} of {total} resolved");
        // The strays, the tight spots and the screws at another pitch leave triangles open.
        assert!(some_open > 8, "{some_open} bodies with triangles left open");
    }
}
