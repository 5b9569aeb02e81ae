//! Separation certificates that a rotation cannot change: a body turning about an axis fixed in
//! the world (a screw, or an interp whose centre stays on the axis) past a body that does not
//! move.
//!
//! The directional bound charges a node pair the full tangential speed `|w x n| rho`, so a ball
//! turning in a socket, or a shaft in a bore, at small clearance took hundreds of iterations
//! (16 s and 12 s), though no point ever comes closer. But each point of the turning body keeps
//! its distance `rho` from the axis line, its axial coordinate `z` relative to the axis point,
//! and its distance from any body point `O` on the axis. For two points `p`, `q` in cylindrical
//! coordinates, `|p - q|^2 = rho_p^2 + rho_q^2 - 2 rho_p rho_q cos(dphi) + dz^2 >=
//! (rho_p - rho_q)^2 + dz^2`, and `|p - q| >= | |p - O| - |q - O| |`. So if the turning node's
//! `rho` and `z` ranges (fixed for all time) and the still node's ranges (at time `t`, widened
//! by the axial slide over the window) are apart by `g_rho` and `g_z`, or their distances from
//! `O` by `g_s`, the pair stays at least `max(sqrt(g_rho^2 + g_z^2), g_s)` apart over the whole
//! window, whatever the angle turned.
//!
//! Ranges over an RSS (centre `c`, rectangle axes `e0`, `e1` with half lengths `l0`, `l1`,
//! radius `r`): a point is `c + d` with `d = a e0 + b e1 + g u`, `|a| <= l0`, `|b| <= l1`,
//! `|g| <= r`, `u` unit. Along a unit `v`, `|d . v| <= l0 |e0 . v| + l1 |e1 . v| + r`. For the
//! distance from a line (or a point) with `c` at distance `k` in direction `v`, the distance
//! of `c + d` is at least `k - ext(v)` and at most `sqrt((k + ext(v))^2 + ext(t)^2)` where
//! `t` spans the remaining directions (one across the axis for `rho`, bounded by `|d|` for the
//! distance from `O`). The point `O` is taken where the turning node's normal line passes
//! closest to the axis: the centre of a spherical patch, the foot of a cylindrical one, so
//! that curved patches get ranges of second order in their size.
//!
//! Triangle pairs get exact ranges where that is cheap: `z` and the largest distance from the
//! line or from `O` over the three corners (convex functions peak at corners), the smallest
//! distance from `O` as a point-triangle distance; `O` is taken on the normal line through the
//! turning triangle's circumcentre, which passes through the centre of any sphere through its
//! corners (so a ball's triangles are measured from the ball's centre).

use super::helix::{Direction, Helix, Ranges};
use super::quotient::Quotient;
use crate::bvh::{Bvh, Rss};
use crate::math::{Pose, Vec3};
use crate::mesh::AxisRanges;
use crate::motion::{FixedAxis, Motion};
use crate::query::distance::distance_triangle_triangle;
use crate::TriMesh;

/// The certificate's data for one query, when one body turns about a fixed axis and the other
/// is still.
pub(crate) struct AxisShells {
    axis: FixedAxis,
    /// Whether mesh 1 is the turning body (else mesh 2 is).
    turning_is_1: bool,
    /// The still body's pose (body to world).
    still: Pose,
    /// The query's point `O` on the axis: `body_point + body_dir * lambda`, the foot of the
    /// turning mesh's root centre (a ball's centre for a ball turning about its centre).
    lambda: f64,
    /// Exact ranges over a turning node's triangle corners, computed on first use: largest
    /// `rho`, smallest and largest `z`, largest distance from `O`.
    corners: std::cell::RefCell<NodeMap<[f64; 4]>>,
    /// The same ranges over each leaf's triangle and over each run of [`RUN`] leaves (by leaf
    /// position), worked out together on first use, from which a node's are merged.
    leaf_corners: std::cell::OnceCell<std::sync::Arc<AxisRanges>>,
    /// A turning node's meridian direction (its volume's normal, [`Meridian::of_normal`]) and
    /// the exact range of `h` over its triangles (each triangle's own tangent form), computed
    /// on first use; `None` where the normal has no meridian part.
    meridians: std::cell::RefCell<NodeMap<Option<(Meridian, Range)>>>,
    /// Where the turning body slides along the axis as it turns, the helical certificate
    /// ([`Helix`]), and a turning node's direction and exact ranges for it, computed on first
    /// use.
    helix: Option<Helix>,
    helices: std::cell::RefCell<NodeMap<Option<(Direction, Ranges)>>>,
    /// The triangles that the screw's invariants settle for the whole query ([`Quotient`]),
    /// worked out on first use once allowed ([`Self::allow_quotient`]).
    quotient: std::cell::OnceCell<Quotient>,
    quotient_allowed: std::cell::Cell<bool>,
    /// The smallest distance from the axis line over a still node's triangles, exact,
    /// computed on first use with its subtree's (the still body and the line do not move: the
    /// axis slides along itself).
    /// The planes across the axis in the turning body's frame and in the world
    /// ([`plane_across`]).
    across: ((Vec3, Vec3), (Vec3, Vec3)),
    /// By node index, NaN where not yet worked out (allocated on first use; a hash map's
    /// hashing cost more than the distances: the 256-sided shaft took 0.75 ms instead of 0.4).
    still_rho: std::cell::RefCell<Vec<f64>>,
    /// The exact range of the axial coordinate (from the axis point at `t = 0`) over a still
    /// node's triangles, by node index, NaN where not yet worked out (allocated on first use).
    still_z: std::cell::RefCell<Vec<[f64; 2]>>,
    /// A turning node's profile ([`Self::turning_profile`]), computed on first use.
    profiles: std::cell::RefCell<NodeMap<[f64; PROFILE_BINS]>>,
}

/// A map by node index, hashed by one multiplication: the standard library's SipHash was among
/// the certificates' costliest lines in callgrind (a tapered shaft in its bore; a node's ranges
/// are asked once per pair visited).
type NodeMap<V> = std::collections::HashMap<u32, V, std::hash::BuildHasherDefault<NodeHasher>>;

/// The hasher of [`NodeMap`]: a node index times the golden ratio's 64-bit fraction (the
/// table takes its bucket from the low bits, which stay distinct for indices distinct in
/// theirs, and its tags from the high bits, which the multiplication mixes).
#[derive(Default)]
struct NodeHasher(u64);

impl std::hash::Hasher for NodeHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }

    fn write_u32(&mut self, i: u32) {
        self.0 = (u64::from(i) ^ self.0).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// Ranges of a volume's distances from a line and along it, or from a point.
#[derive(Clone, Copy, Debug)]
pub(super) struct Range {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Range {
    /// The empty range, which [`Self::with`] grows.
    pub(super) const EMPTY: Range = Range {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };

    /// The smallest range holding this one and `v`.
    pub(super) fn with(self, v: f64) -> Range {
        Range {
            lo: self.lo.min(v),
            hi: self.hi.max(v),
        }
    }

    /// How far apart the two ranges are (0 where they overlap).
    pub(super) fn gap(self, other: Range) -> f64 {
        (other.lo - self.hi).max(self.lo - other.hi).max(0.0)
    }
}

/// `|d . v|` over the volume's offsets `d` from its centre.
#[inline]
fn extent(e0: Vec3, e1: Vec3, l0: f64, l1: f64, r: f64, v: Vec3) -> f64 {
    l0 * e0.dot(v).abs() + l1 * e1.dot(v).abs() + r
}

/// The point `x`'s axial coordinate along the line through `p` with unit direction `d`, its
/// distance `k` from the line and the radial unit towards it (any unit across the line where
/// `x` is on it).
#[inline]
fn radial_frame(x: Vec3, p: Vec3, d: Vec3) -> (f64, f64, Vec3) {
    let rel = x - p;
    let z = rel.dot(d);
    let mut radial = rel - d * z;
    let mut k2 = radial.length_squared();
    if k2 <= 1e-12 * (z * z + k2) {
        // Within a millionth of the distance from the line's point: the difference may be
        // mostly rounding along `d` (`d` a unit to within an ulp), and the unit from it would
        // point along the axis; the ranges across it then lost the volume's width (a node
        // 0.0427 from the axis at most was certified 0.0354 from it, and a contact was
        // missed). `d x (rel x d)` is the part across exact to its own rounding, and nothing
        // where `x` is on the line. (Everywhere, it made a tapered shaft's turn 10% slower.)
        radial = across_line(rel, d);
        k2 = radial.length_squared();
    }
    let k = k2.sqrt();
    let u = if k > 0.0 {
        radial / k
    } else {
        any_orthogonal(d)
    };
    (z, k, u)
}

/// `d x (rel x d)`: the part of `rel` across the line along `d` ([`radial_frame`]'s rare case,
/// kept out of its hot path).
#[cold]
#[inline(never)]
fn across_line(rel: Vec3, d: Vec3) -> Vec3 {
    d.cross(rel.cross(d))
}

/// A unit vector orthogonal to the unit `d`.
fn any_orthogonal(d: Vec3) -> Vec3 {
    let helper = if d.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    d.cross(helper).normalize()
}

/// The volume (centre `c`, axes `e0`, `e1`, half lengths, radius; all in one frame) against a
/// line through `p` with unit direction `d` in that frame: its range of distances from the
/// line and of axial coordinates `(x - p) . d`.
fn cylinder(c: Vec3, e0: Vec3, e1: Vec3, l: [f64; 2], r: f64, p: Vec3, d: Vec3) -> (Range, Range) {
    let (z, k, u) = radial_frame(c, p, d);
    let across = d.cross(u);
    let (eu, et, ez) = (
        extent(e0, e1, l[0], l[1], r, u),
        extent(e0, e1, l[0], l[1], r, across),
        extent(e0, e1, l[0], l[1], r, d),
    );
    (
        Range {
            lo: (k - eu).max(0.0),
            hi: ((k + eu) * (k + eu) + et * et).sqrt(),
        },
        Range {
            lo: z - ez,
            hi: z + ez,
        },
    )
}

/// A unit direction `(rho, z)` in the meridian half-plane of an axis: radial and axial parts.
///
/// The quotient of space by turning about the axis maps a point to its distance `rho` from the
/// line and its axial coordinate `z`, and two points can come no closer under any turn than
/// their images are apart in that half-plane. So for any unit `n` there, a turning set and a
/// still set whose values of `h_n = n.rho rho + n.z z` are apart by `g` stay `g` apart over the
/// whole turn: this certifies the sloped profiles (a tapered shaft in its bore, a valve on its
/// seat) that the axis-aligned ranges (`g_rho`, `g_z`) do not, their nodes' `rho` and `z`
/// ranges overlapping along the slope.
#[derive(Clone, Copy)]
struct Meridian {
    rho: f64,
    z: f64,
}

impl Meridian {
    /// The meridian part of the unit normal `nrm` at `x` (frame of the axis through `p` with
    /// unit direction `d`), normalised; `None` on the axis or where the normal is mostly
    /// tangential (a plane through the axis), where no meridian direction separates anything.
    fn of_normal(nrm: Vec3, x: Vec3, p: Vec3, d: Vec3) -> Option<Self> {
        let rel = x - p;
        let radial = rel - d * rel.dot(d);
        let k = radial.length();
        if k.is_nan() || k <= 0.0 {
            return None;
        }
        let (rho, z) = (nrm.dot(radial / k), nrm.dot(d));
        let len = rho.hypot(z);
        (len > 0.5).then(|| Self {
            rho: rho / len,
            z: z / len,
        })
    }

    /// The range of `h` over the volume (centre `c`, axes `e0`, `e1`, half lengths `l`, radius
    /// `r`) against the axis through `p` with unit direction `d`, all in one frame. With `u` the
    /// radial unit at the centre (distance `k` from the line), `rho >= u . x_perp` everywhere
    /// (the tangent plane of the convex `rho` through the line), and `rho - u . x_perp <=
    /// b^2 / (2a)` where `a = u . x_perp >= k - ext(u) > 0` and `|b| <= ext(t)` is the part
    /// across `u` (`sqrt(a^2 + b^2) - a <= b^2 / 2a`), or at most the largest `rho` less
    /// `k - ext(u)`. So `h` lies within the linear `n.rho u . x + n.z z`, whose range over the
    /// volume is its value at the centre plus or minus `ext`, and that plus `n.rho` times the
    /// gap `eps` between `rho` and its tangent.
    fn volume_range(
        self,
        c: Vec3,
        (e0, e1): (Vec3, Vec3),
        l: [f64; 2],
        r: f64,
        p: Vec3,
        d: Vec3,
    ) -> Range {
        let (z, k, u) = radial_frame(c, p, d);
        let w = u * self.rho + d * self.z;
        let (centre, ext) = (k * self.rho + z * self.z, extent(e0, e1, l[0], l[1], r, w));
        let (eu, et) = (
            extent(e0, e1, l[0], l[1], r, u),
            extent(e0, e1, l[0], l[1], r, d.cross(u)),
        );
        let (near, rho_hi) = (k - eu, ((k + eu) * (k + eu) + et * et).sqrt());
        let mut eps = rho_hi - near;
        if near > 0.0 {
            eps = eps.min(et * et / (2.0 * near));
        }
        Range {
            lo: centre - ext + (self.rho * eps).min(0.0),
            hi: centre + ext + (self.rho * eps).max(0.0),
        }
    }

    /// The range of `h` over a triangle against the axis through `p` with unit direction `d`,
    /// all in one frame: where `n.rho >= 0`, `h` is convex (its largest value at a corner) and
    /// at least its tangent-plane form `n.rho u . x + n.z z` (linear, its smallest at a
    /// corner), `u` the radial unit at the centroid; where `n.rho < 0`, the reverse.
    fn triangle_range(self, tri: &[Vec3; 3], p: Vec3, d: Vec3) -> Range {
        let (_, _, u) = radial_frame((tri[0] + tri[1] + tri[2]) / 3.0, p, d);
        let mut exact = Range::EMPTY;
        let mut tangent = exact;
        for &v in tri {
            let rel = v - p;
            let z = rel.dot(d);
            let perp = rel - d * z;
            let h = self.rho * perp.length() + self.z * z;
            let lin = self.rho * perp.dot(u) + self.z * z;
            exact = exact.with(h);
            tangent = tangent.with(lin);
        }
        if self.rho >= 0.0 {
            Range {
                lo: tangent.lo,
                hi: exact.hi,
            }
        } else {
            Range {
                lo: exact.lo,
                hi: tangent.hi,
            }
        }
    }

    /// The gap between a turning set's range and a still set's, the still one widened by the
    /// axial slide over the window (`slide` along `z`), taking `n` or `-n` (both bound).
    fn gap(self, turning: Range, still: Range, slide: f64) -> f64 {
        let widen = self.z.abs() * slide;
        turning.gap(Range {
            lo: still.lo - widen,
            hi: still.hi + widen,
        })
    }
}

/// The mean of unit directions in a plane (`None` for a set without one), each turned to
/// agree with the first (a soup's orientation being arbitrary), normalised; `None` where they
/// disagree (the mean under half as long as their count, those without a direction counted).
pub(super) fn mean_direction(dirs: impl Iterator<Item = Option<[f64; 2]>>) -> Option<[f64; 2]> {
    let (mut sum, mut count) = ([0.0f64; 2], 0.0);
    for d in dirs {
        if let Some(d) = d {
            let sign = if count == 0.0 || d[0] * sum[0] + d[1] * sum[1] >= 0.0 {
                1.0
            } else {
                -1.0
            };
            sum = [sum[0] + sign * d[0], sum[1] + sign * d[1]];
        }
        count += 1.0;
    }
    let len = sum[0].hypot(sum[1]);
    (len > 0.5 * count).then(|| [sum[0] / len, sum[1] / len])
}

/// The volume's range of distances from the point `o` (all in one frame).
fn sphere(c: Vec3, e0: Vec3, e1: Vec3, l: [f64; 2], r: f64, o: Vec3) -> Range {
    let rel = c - o;
    let k = rel.length();
    let v = if k > 0.0 { rel / k } else { e0.cross(e1) };
    let ev = extent(e0, e1, l[0], l[1], r, v);
    let whole = l[0].hypot(l[1]) + r;
    Range {
        lo: (k - ev).max(0.0),
        hi: ((k + ev) * (k + ev) + whole * whole).sqrt(),
    }
}

/// A screw whose slide over the motion is below this fraction of the scene's scale (the
/// turning body's size and how far it and its axis are from the origin) is taken as a pure
/// turn by the helical certificates: the slide is rounding.
const SLIDE_RESOLUTION: f64 = 1e-12;

/// Leaves per run whose corner ranges are kept merged ([`AxisShells::turning_corners`]).
const RUN: usize = 32;

/// Corner ranges merged: the largest `rho`, the `z` range, the largest distance from `O`
/// (empty: `rho` and the distance 0, `z` inverted).
fn merged(ranges: &[[f64; 4]]) -> [f64; 4] {
    let mut r = [0.0, f64::INFINITY, f64::NEG_INFINITY, 0.0];
    for x in ranges {
        r[0] = if x[0] > r[0] { x[0] } else { r[0] };
        r[1] = if x[1] < r[1] { x[1] } else { r[1] };
        r[2] = if x[2] > r[2] { x[2] } else { r[2] };
        r[3] = if x[3] > r[3] { x[3] } else { r[3] };
    }
    r
}

impl AxisShells {
    /// The certificate for this pair of motions, when it applies.
    pub(crate) fn new(
        motion1: &Motion,
        motion2: &Motion,
        root1: &Rss,
        root2: &Rss,
    ) -> Option<Self> {
        let (turning, still, turning_is_1, root) = if motion2.is_stationary() {
            (motion1, motion2, true, root1)
        } else if motion1.is_stationary() {
            (motion2, motion1, false, root2)
        } else {
            return None;
        };
        let axis = turning.fixed_axis()?;
        // A screw between two poses of a pure turn slides by rounding (4e-16 for a robot
        // wrist's half turn): a helix of that pitch only costs (its quotient took 80% of the
        // query's instructions), and the meridian bounds, widened by the slide, serve it.
        let scale = root.bounding_radius()
            + axis.world_point.length()
            + turning.start().translation.length();
        let slides = axis.along.abs() > SLIDE_RESOLUTION * scale;
        Some(Self {
            axis,
            turning_is_1,
            still: still.start(),
            lambda: (root.center - axis.body_point).dot(axis.body_dir),
            corners: Default::default(),
            leaf_corners: Default::default(),
            meridians: Default::default(),
            helix: Helix::new(&axis, turning.start(), still.start()).filter(|_| slides),
            helices: Default::default(),
            quotient: Default::default(),
            quotient_allowed: Default::default(),
            across: (plane_across(axis.body_dir), plane_across(axis.world_dir)),
            still_rho: Default::default(),
            still_z: Default::default(),
            profiles: Default::default(),
        })
    }

    /// Exact corner ranges of the turning mesh's node `index` (see [`Self::corners`]; body
    /// frame).
    fn turning_corners(&self, mesh: &TriMesh, index: u32) -> [f64; 4] {
        if let Some(r) = self.corners.borrow().get(&index) {
            return *r;
        }
        // Merged from its leaves' ranges, and whole runs of them where it covers one: a
        // traversal asks for nodes at every level over the same triangles, and a pass over each
        // one's corners (two roots of 43K triangles and their subtrees) cost 44% of a wrist
        // turning beside a board. The leaves' from their vertices' (a closed mesh has half as
        // many vertices as triangles: a sixth of the square roots).
        let [leaves, runs] = &**self.leaf_corners.get_or_init(|| {
            // The mesh keeps the last axis's: a wrist's frozen checks ask for the same one
            // piece after piece.
            let ax = &self.axis;
            let (p, d) = (ax.body_point.to_array(), ax.body_dir.to_array());
            let key = [p[0], p[1], p[2], d[0], d[1], d[2], self.lambda].map(f64::to_bits);
            mesh.axis_corners().get_or(key, || self.work_corners(mesh))
        });
        let range = mesh.bvh().nodes()[index as usize].leaf_range();
        let (first, last) = (range.start.div_ceil(RUN), range.end / RUN);
        let r = if first >= last {
            merged(&leaves[range])
        } else {
            merged(&[
                merged(&leaves[range.start..first * RUN]),
                merged(&runs[first..last]),
                merged(&leaves[last * RUN..range.end]),
            ])
        };
        self.corners.borrow_mut().insert(index, r);
        r
    }

    /// The turning node `index`'s profile over its axial range `z` (body frame, from the axis
    /// point): over each of [`PROFILE_BINS`] equal slabs of it, the largest distance from the
    /// axis over the corners of the leaves whose axial range overlaps the slab (by more than a
    /// point, or holds it where the leaf is flat across the axis: the slabs so given cover
    /// each leaf's range), or -1 where no leaf is given to it. From the leaves' corner ranges
    /// ([`Self::turning_corners`], asked first).
    fn turning_profile(&self, mesh: &TriMesh, index: u32, z: (f64, f64)) -> [f64; PROFILE_BINS] {
        if let Some(p) = self.profiles.borrow().get(&index) {
            return *p;
        }
        // Always there (`turning_corners`, asked first, works them out); were they not, an
        // empty profile would certify every pair, so each slab is taken to reach infinitely far.
        let Some([leaves, _]) = self.leaf_corners.get().map(|a| &**a) else {
            return [f64::INFINITY; PROFILE_BINS];
        };
        let mut profile = [-1.0f64; PROFILE_BINS];
        for &[rho, lo, hi, _] in &leaves[mesh.bvh().nodes()[index as usize].leaf_range()] {
            for (b, reach) in profile.iter_mut().enumerate() {
                let (s_lo, s_hi) = profile_slab(z, b);
                let given = if lo < hi {
                    s_lo < hi && s_hi > lo
                } else {
                    s_lo <= lo && lo <= s_hi
                };
                if given {
                    *reach = reach.max(rho);
                }
            }
        }
        self.profiles.borrow_mut().insert(index, profile);
        profile
    }

    /// The per-leaf and per-run corner ranges of the turning mesh about this axis
    /// ([`Self::turning_corners`]).
    fn work_corners(&self, mesh: &TriMesh) -> AxisRanges {
        let (ax, bvh) = (&self.axis, mesh.bvh());
        let o = ax.body_point + ax.body_dir * self.lambda;
        let vertices: Vec<[f64; 4]> = mesh
            .vertices()
            .iter()
            .map(|&v| {
                let rel = v - ax.body_point;
                let z = rel.dot(ax.body_dir);
                [(rel - ax.body_dir * z).length(), z, z, (v - o).length()]
            })
            .collect();
        let leaves: Vec<[f64; 4]> = (0..bvh.leaf_triangles().len())
            .map(|i| {
                let tri = mesh.triangles()[bvh.triangle_index(i as u32)];
                merged(&tri.map(|v| vertices[v as usize]))
            })
            .collect();
        let runs = leaves.chunks(RUN).map(merged).collect();
        [leaves, runs]
    }

    /// The meridian direction and range of the turning mesh's node `index` ([`Self::meridians`]),
    /// whose triangles are `triangles` (body frame). The direction is the mean of the
    /// triangles' normals' meridian parts (each turned to agree with the first, a soup's
    /// orientation being arbitrary): on a surface of revolution it is the profile's normal
    /// however far round the node reaches, where the volume's own normal is not. `None` where
    /// the triangles disagree (their mean is under half as long as their count) or have no
    /// meridian part.
    fn turning_meridian(&self, index: u32, triangles: &[[Vec3; 3]]) -> Option<(Meridian, Range)> {
        if let Some(r) = self.meridians.borrow().get(&index) {
            return *r;
        }
        let ax = &self.axis;
        let direction = |tri: &[Vec3; 3]| {
            let nrm = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
            let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
            Meridian::of_normal(nrm, centroid, ax.body_point, ax.body_dir)
        };
        // Three triangles first (the first, the middle and the last): where their meridian
        // normals are more than 8 degrees apart (a ball's patch), no one direction makes the
        // node's range thin, and the pass over its triangles is not worth its cost (a ball in
        // its socket: 8.3 ms without the passes, 9.8 with them).
        let probe = [0, triangles.len() / 2, triangles.len() - 1].map(|i| direction(&triangles[i]));
        let agree = |a: Option<Meridian>, b: Option<Meridian>| match (a, b) {
            (Some(a), Some(b)) => (a.rho * b.rho + a.z * b.z).abs() >= 0.99,
            _ => false,
        };
        if !agree(probe[0], probe[1]) || !agree(probe[0], probe[2]) {
            self.meridians.borrow_mut().insert(index, None);
            return None;
        }
        let mean = mean_direction(triangles.iter().map(|t| direction(t).map(|m| [m.rho, m.z])));
        let r = mean.map(|[rho, z]| {
            let n = Meridian { rho, z };
            let mut range = Range::EMPTY;
            for tri in triangles {
                let r = n.triangle_range(tri, ax.body_point, ax.body_dir);
                range = Range {
                    lo: range.lo.min(r.lo),
                    hi: range.hi.max(r.hi),
                };
            }
            (n, range)
        });
        self.meridians.borrow_mut().insert(index, r);
        r
    }

    /// The helical direction and ranges of the turning mesh's node `index`
    /// ([`Self::helices`]), whose triangles are `triangles` (body frame).
    fn turning_helix(
        &self,
        helix: &Helix,
        index: u32,
        triangles: &[[Vec3; 3]],
    ) -> Option<(Direction, Ranges)> {
        if let Some(r) = self.helices.borrow().get(&index) {
            return *r;
        }
        let world = || {
            triangles
                .iter()
                .map(|t| t.map(|p| helix.start().transform_point(p)))
        };
        let r = helix
            .mean_direction(world())
            .and_then(|n| Some((n, helix.triangles(world(), n)?)));
        self.helices.borrow_mut().insert(index, r);
        r
    }

    /// The exact smallest distance from the axis line over the still mesh's node `index` of
    /// hierarchy `bvh` ([`Self::still_rho`]): the smaller of its children's, a leaf's its
    /// triangle's ([`line_distance`]).
    fn still_rho_lo(&self, bvh: &Bvh, index: u32) -> f64 {
        {
            let mut cache = self.still_rho.borrow_mut();
            if cache.is_empty() {
                cache.resize(bvh.nodes().len(), f64::NAN);
            }
            let r = cache[index as usize];
            if !r.is_nan() {
                return r;
            }
        }
        let node = &bvh.nodes()[index as usize];
        let r = if node.is_leaf() {
            let ax = &self.axis;
            let (pose, t) = (
                self.still,
                &bvh.leaf_triangles()[node.leaf_position() as usize],
            );
            let tri = [
                pose.transform_point(t[0]),
                pose.transform_point(t[1]),
                pose.transform_point(t[2]),
            ];
            line_distance(&tri, ax.world_point, self.across.1)
        } else {
            let (l, r) = node.children(index);
            self.still_rho_lo(bvh, l).min(self.still_rho_lo(bvh, r))
        };
        self.still_rho.borrow_mut()[index as usize] = r;
        r
    }

    /// The exact range of the axial coordinate over the still mesh's node `index` of hierarchy
    /// `bvh` ([`Self::still_z`]): its children's merged, a leaf's its triangle's corners'.
    fn still_z_range(&self, bvh: &Bvh, index: u32) -> [f64; 2] {
        {
            let mut cache = self.still_z.borrow_mut();
            if cache.is_empty() {
                cache.resize(bvh.nodes().len(), [f64::NAN; 2]);
            }
            let r = cache[index as usize];
            if !r[0].is_nan() {
                return r;
            }
        }
        let node = &bvh.nodes()[index as usize];
        let r = if node.is_leaf() {
            // Written out, the pose and the axis copied out of `self`: as an array `map` whose
            // closure read them through it, the compiler stopped inlining it and reloaded them
            // for every corner (a shaft in its bore 0.30 -> 0.39 ms).
            let (pose, point, dir) = (self.still, self.axis.world_point, self.axis.world_dir);
            let t = &bvh.leaf_triangles()[node.leaf_position() as usize];
            let z0 = (pose.transform_point(t[0]) - point).dot(dir);
            let z1 = (pose.transform_point(t[1]) - point).dot(dir);
            let z2 = (pose.transform_point(t[2]) - point).dot(dir);
            [z0.min(z1).min(z2), z0.max(z1).max(z2)]
        } else {
            let (l, r) = node.children(index);
            let (a, b) = (self.still_z_range(bvh, l), self.still_z_range(bvh, r));
            [a[0].min(b[0]), a[1].max(b[1])]
        };
        self.still_z.borrow_mut()[index as usize] = r;
        r
    }

    /// A lower bound on the distance between the turning node `index` (triangles given) and
    /// the still mesh's node `still_index` over `[t, t + h]`, from the turning node's exact
    /// corner ranges (its largest `rho` and distance from `O`; both `z` ends) against the
    /// still volume's ranges, and where that bound is not above `need`, against the still
    /// node's exact smallest distance from the line ([`Self::still_rho_lo`]). It certifies a
    /// turning body inside a still one (a ball in its socket, a shaft in its bore) high in the
    /// trees: only the still side's ranges loosen with the size of its volume.
    pub(crate) fn lower_bound_inner(
        &self,
        (turning, index): (&TriMesh, u32),
        (still_bvh, still_index): (&Bvh, u32),
        (t, h): (f64, f64),
        need: f64,
    ) -> f64 {
        let still = &still_bvh.nodes()[still_index as usize].rss;
        let [rho_hi, z_lo, z_hi, s_hi] = self.turning_corners(turning, index);
        let turning_bvh = turning.bvh();
        let triangles =
            &turning_bvh.leaf_triangles()[turning_bvh.nodes()[index as usize].leaf_range()];
        let ax = &self.axis;
        let slide = ax.along.abs() * h;
        let axis_point = ax.world_point + ax.world_dir * (ax.along * t);
        let c = self.still.transform_point(still.center);
        let (f0, f1) = (
            self.still.rotation * still.axes.x_axis,
            self.still.rotation * still.axes.y_axis,
        );
        let (rho_s, z_s) = cylinder(
            c,
            f0,
            f1,
            still.half_lengths,
            still.radius,
            axis_point,
            ax.world_dir,
        );
        let gap_z = |z_s: Range| (z_s.lo - slide - z_hi).max(z_lo - z_s.hi - slide).max(0.0);
        let mut g_z = gap_z(z_s);
        let o_world = axis_point + ax.world_dir * self.lambda;
        let s_s = sphere(c, f0, f1, still.half_lengths, still.radius, o_world);
        let g_s = (s_s.lo - slide - s_hi).max(0.0);
        let bound = |rho_s_lo: f64, g_z: f64| {
            let g_rho = (rho_s_lo - rho_hi).max(0.0);
            (g_rho * g_rho + g_z * g_z).sqrt().max(g_s)
        };
        let mut lb = bound(rho_s.lo, g_z);
        if lb > need {
            return lb;
        }
        // The still node's exact axial range, where a corner of its first triangle lies
        // outside the turning node's: a volume's range overhangs by its radius, and a board
        // whose end stops 4 mm short of a gripper turning past it was not told apart from the
        // gripper's nodes until the leaves (its corners at every level: 80% of the query).
        let node = &still_bvh.nodes()[still_index as usize];
        let first = still_bvh.leaf_triangles()[node.leaf_range().start][0];
        let shift = ax.along * t;
        let corner_z = (self.still.transform_point(first) - ax.world_point).dot(ax.world_dir);
        if gap_z(Range::EMPTY.with(corner_z - shift)) > need {
            let [lo, hi] = self.still_z_range(still_bvh, still_index);
            g_z = g_z.max(gap_z(Range {
                lo: lo - shift,
                hi: hi - shift,
            }));
            lb = lb.max(bound(rho_s.lo, g_z));
            if lb > need {
                return lb;
            }
        }
        // Not enough: the still side's exact smallest distance from the line (a volume over a
        // bore's faces reaches inside them by its chord's sagitta), worked out once per node,
        // unless a corner of the node's first triangle, whose distance from the line is at
        // least that smallest one, shows that it cannot be enough either (a socket around a
        // ball: there the distances from `O` decide, and the work cost the ball 20%).
        let corner = self.still.transform_point(first);
        let rel = corner - ax.world_point;
        let mut rho_s_lo = rho_s.lo;
        let corner_rho = (rel - ax.world_dir * rel.dot(ax.world_dir)).length();
        if bound(corner_rho, g_z) > need {
            rho_s_lo = rho_s_lo.max(self.still_rho_lo(still_bvh, still_index));
            lb = lb.max(bound(rho_s_lo, g_z));
            if lb > need {
                return lb;
            }
        }
        // The meridian projection across the turning node's plane, its range exact over its
        // triangles ([`Self::turning_meridian`]): a tapered shaft in its bore. After the
        // distances from the line, which settle a straight shaft without the pass over the
        // node's triangles.
        if let Some((n, range)) = self.turning_meridian(index, triangles) {
            lb = lb.max(self.meridian_gap(n, range, still, (t, h)));
            if lb > need {
                return lb;
            }
        }
        // The helical ranges of the turning node, exact over its triangles, where it slides.
        if let Some(helix) = self.helix_on() {
            if let Some((n, ranges)) = self.turning_helix(helix, index, triangles) {
                lb = lb.max(helix.against_volume(Some(ranges), still, n));
                if lb > need {
                    return lb;
                }
            }
        }
        // The turning node's profile: its largest distance from the line over each of
        // [`PROFILE_BINS`] slabs of its axial range, against a still triangle's parts beside
        // each slab ([`profile_triangle_gap`]), or against a still node's exact smallest
        // distance from the line and exact axial range ([`profile_gap`]). A keyed shaft's key
        // widens the whole shaft's largest distance past the narrow part of its bore, and past
        // the triangles stepping from it to the groove, which the profile's other slabs clear:
        // the search, which splits the still side first, had failed each of those triangles
        // against the whole shaft (a keyed lever's contact 45 ms). Asked last, and only where
        // it may pay: where the still node's axial range does not cover the turning node's
        // (else the slab at its widest point fails), and for a node, where a child of the
        // turning node is nearer the line than the still node, by its first corner and then
        // exactly (without these tests, a ball in its socket failed 9,520 profiles in its one
        // search, and certified none).
        let turning_node = &turning_bvh.nodes()[index as usize];
        let covered = z_s.lo - slide <= z_lo && z_s.hi + slide >= z_hi;
        if !covered && !turning_node.is_leaf() && node.is_leaf() && rho_hi > rho_s_lo {
            let profile = self.turning_profile(turning, index, (z_lo, z_hi));
            let tri = still_bvh.leaf_triangles()[node.leaf_position() as usize]
                .map(|p| self.still.transform_point(p));
            let s = axis_coords(&tri, axis_point, ax.world_dir, self.across.1);
            return lb.max(profile_triangle_gap(
                &profile,
                (z_lo, z_hi),
                &s,
                slide,
                need,
            ));
        }
        if !covered && !turning_node.is_leaf() && !node.is_leaf() && rho_hi > rho_s_lo {
            let (l, r) = turning_node.children(index);
            let (a, b) = (
                self.turning_corners(turning, l),
                self.turning_corners(turning, r),
            );
            let thinner = a[0].min(b[0]);
            if thinner >= corner_rho {
                return lb;
            }
            let rho_s_lo = rho_s_lo.max(self.still_rho_lo(still_bvh, still_index));
            if thinner >= rho_s_lo {
                return lb;
            }
            let profile = self.turning_profile(turning, index, (z_lo, z_hi));
            let [lo, hi] = self.still_z_range(still_bvh, still_index);
            let z_s = Range {
                lo: lo - shift - slide,
                hi: hi - shift + slide,
            };
            lb = lb.max(profile_gap(&profile, (z_lo, z_hi), (rho_s_lo, z_s), need));
        }
        lb
    }

    /// Whether a pair the certificates did not separate should split its turning node first
    /// (the still one otherwise, whose ranges loosen with its size): where the turning body
    /// slides along the axis and this node, `index` with triangles `triangles`, has no helical
    /// ranges (its faces spread over both flanks of a thread, or over half a pitch), no still
    /// node however small is certified against it.
    pub(crate) fn split_turning(&self, index: u32, triangles: &[[Vec3; 3]], still: &Rss) -> bool {
        let Some(helix) = self.helix_on() else {
            return false;
        };
        let Some((n, turning)) = self.turning_helix(helix, index, triangles) else {
            return true;
        };
        match helix.still_volume(still, n) {
            Some(s) => turning.width() > s.width(),
            None => false,
        }
    }

    /// The gap in the meridian direction `n` between a turning set's range `turning` and the
    /// still volume `still` (its body frame) over the window `[t, t + h]`.
    fn meridian_gap(&self, n: Meridian, turning: Range, still: &Rss, (t, h): (f64, f64)) -> f64 {
        let ax = &self.axis;
        let axis_point = ax.world_point + ax.world_dir * (ax.along * t);
        let rs = n.volume_range(
            self.still.transform_point(still.center),
            (
                self.still.rotation * still.axes.x_axis,
                self.still.rotation * still.axes.y_axis,
            ),
            still.half_lengths,
            still.radius,
            axis_point,
            ax.world_dir,
        );
        n.gap(turning, rs, ax.along.abs() * h)
    }

    /// The helical certificate, where the screw slides and the bodies started in a close fit
    /// ([`Self::allow_quotient`]): an ordinary screw's pass that turns the shells on near its
    /// contact would pay for the helical ranges' passes over its nodes' triangles (the Panda
    /// link's screws, 3% more time).
    fn helix_on(&self) -> Option<&Helix> {
        self.helix.as_ref().filter(|_| self.quotient_allowed.get())
    }

    /// Allows the whole-query certificate ([`Quotient`]): its cost (a hierarchy over every
    /// triangle's image) is paid only where the bodies start in a close fit.
    pub(crate) fn allow_quotient(&self) {
        self.quotient_allowed.set(true);
    }

    /// Whether no triangle of mesh 1's leaf run `range1` and none of mesh 2's `range2` can ever
    /// come within `delta` of each other under the screw ([`Quotient::resolved`]); `false`
    /// where the certificate does not apply.
    pub(crate) fn resolved(
        &self,
        (mesh1, range1): (&TriMesh, std::ops::Range<usize>),
        (mesh2, range2): (&TriMesh, std::ops::Range<usize>),
        delta: f64,
    ) -> bool {
        let Some(helix) = &self.helix else {
            return false;
        };
        if !self.quotient_allowed.get() {
            return false;
        }
        let (turning, still) = if self.turning_is_1 {
            ((mesh1, range1), (mesh2, range2))
        } else {
            ((mesh2, range2), (mesh1, range1))
        };
        self.quotient
            .get_or_init(|| Quotient::build(helix, turning.0, still.0, delta))
            .resolved(turning.1, still.1)
    }

    /// Whether mesh 1 is the turning body.
    pub(crate) fn turning_is_1(&self) -> bool {
        self.turning_is_1
    }

    /// A lower bound on the distance between node volumes `a` (mesh 1, its body frame) and `b`
    /// (mesh 2) over the window `[t, t + h]`.
    /// Beyond `need` it stops refining (the meridian bound is not tried).
    pub(crate) fn lower_bound(&self, a: &Rss, b: &Rss, (t, h): (f64, f64), need: f64) -> f64 {
        let (turning, still) = if self.turning_is_1 { (a, b) } else { (b, a) };
        let ax = &self.axis;
        // The turning volume, in its body frame, against the body-frame axis.
        let (e0, e1) = (turning.axes.x_axis, turning.axes.y_axis);
        let (rho_t, z_t) = cylinder(
            turning.center,
            e0,
            e1,
            turning.half_lengths,
            turning.radius,
            ax.body_point,
            ax.body_dir,
        );
        // The still volume in the world, against the axis where it is at time t; over the
        // window the axis point slides by |along| h, which widens the axial and spherical
        // ranges by as much.
        let slide = ax.along.abs() * h;
        let axis_point = ax.world_point + ax.world_dir * (ax.along * t);
        let c = self.still.transform_point(still.center);
        let (f0, f1) = (
            self.still.rotation * still.axes.x_axis,
            self.still.rotation * still.axes.y_axis,
        );
        let (rho_s, z_s) = cylinder(
            c,
            f0,
            f1,
            still.half_lengths,
            still.radius,
            axis_point,
            ax.world_dir,
        );
        let z_s = Range {
            lo: z_s.lo - slide,
            hi: z_s.hi + slide,
        };
        let (g_rho, g_z) = (rho_t.gap(rho_s), z_t.gap(z_s));
        let cylindrical = (g_rho * g_rho + g_z * g_z).sqrt();
        // O: where the turning volume's normal line passes closest to the axis.
        let lambda = closest_on_axis(
            ax.body_point,
            ax.body_dir,
            turning.center,
            turning.axes.z_axis,
        );
        let s_t = sphere(
            turning.center,
            e0,
            e1,
            turning.half_lengths,
            turning.radius,
            ax.body_point + ax.body_dir * lambda,
        );
        let o_world = axis_point + ax.world_dir * lambda;
        let s_s = sphere(c, f0, f1, still.half_lengths, still.radius, o_world);
        let s_s = Range {
            lo: (s_s.lo - slide).max(0.0),
            hi: s_s.hi + slide,
        };
        let mut lb = cylindrical.max(s_t.gap(s_s));
        if lb <= need {
            // The meridian projection across the turning volume's plane ([`Meridian`]).
            let n = Meridian::of_normal(
                turning.axes.z_axis,
                turning.center,
                ax.body_point,
                ax.body_dir,
            );
            if let Some(n) = n {
                let rt = n.volume_range(
                    turning.center,
                    (e0, e1),
                    turning.half_lengths,
                    turning.radius,
                    ax.body_point,
                    ax.body_dir,
                );
                lb = lb.max(self.meridian_gap(n, rt, still, (t, h)));
            }
        }
        if let (true, Some(helix)) = (lb <= need, self.helix_on()) {
            lb = lb.max(helix.volumes(turning, still));
        }
        lb
    }

    /// [`Self::lower_bound`] for two triangles (mesh 1's in its body frame, mesh 2's in its).
    pub(crate) fn lower_bound_triangles(
        &self,
        t1: &[Vec3; 3],
        t2: &[Vec3; 3],
        (t, h): (f64, f64),
        need: f64,
    ) -> f64 {
        let (turning, still) = if self.turning_is_1 {
            (t1, t2)
        } else {
            (t2, t1)
        };
        let ax = &self.axis;
        let still = still.map(|p| self.still.transform_point(p));
        let slide = ax.along.abs() * h;
        let axis_point = ax.world_point + ax.world_dir * (ax.along * t);
        // Axial coordinates and distances from the line, over the corners.
        let corners = |tri: &[Vec3; 3], p: Vec3, d: Vec3| {
            let mut z = Range::EMPTY;
            let mut rho_hi: f64 = 0.0;
            for &v in tri {
                let rel = v - p;
                let zz = rel.dot(d);
                z.lo = z.lo.min(zz);
                z.hi = z.hi.max(zz);
                rho_hi = rho_hi.max((rel - d * zz).length());
            }
            (z, rho_hi)
        };
        let (z_t, rho_t_hi) = corners(turning, ax.body_point, ax.body_dir);
        let (z_s, rho_s_hi) = corners(&still, axis_point, ax.world_dir);
        let z_s = Range {
            lo: z_s.lo - slide,
            hi: z_s.hi + slide,
        };
        // Smallest distances from the line, exact ([`line_distance`]). The centroid's distance
        // less the corners' spread, used before, lost a long triangle's length: a 128-sided
        // shaft turning 180 degrees in a bore at 1.65 tolerances of clearance took 6 s.
        let rho_t = Range {
            lo: line_distance(turning, ax.body_point, self.across.0),
            hi: rho_t_hi,
        };
        let rho_s = Range {
            lo: line_distance(&still, axis_point, self.across.1),
            hi: rho_s_hi,
        };
        let (g_rho, g_z) = (rho_t.gap(rho_s), z_t.gap(z_s));
        let cylindrical = (g_rho * g_rho + g_z * g_z).sqrt();
        let cylindrical = if cylindrical > need {
            cylindrical
        } else {
            cylindrical.max(self.plane_gap(turning, &still, axis_point, slide))
        };
        // O on the axis, nearest the normal line through the turning triangle's circumcentre.
        let slabs = |lb: f64| {
            if lb > need {
                lb
            } else {
                lb.max(self.slab_gap(turning, &still, (z_t, axis_point, slide), need))
            }
        };
        let Some(centre) = circumcentre(turning) else {
            return slabs(cylindrical);
        };
        let n = (turning[1] - turning[0])
            .cross(turning[2] - turning[0])
            .normalize();
        let lambda = closest_on_axis(ax.body_point, ax.body_dir, centre, n);
        let o_body = ax.body_point + ax.body_dir * lambda;
        let o_world = axis_point + ax.world_dir * lambda;
        let from = |tri: &[Vec3; 3], o: Vec3| Range {
            lo: distance_triangle_triangle(tri, &[o, o, o]).distance,
            hi: tri.iter().fold(0.0_f64, |m, &v| m.max((v - o).length())),
        };
        let s_t = from(turning, o_body);
        let s_s = from(&still, o_world);
        let s_s = Range {
            lo: (s_s.lo - slide).max(0.0),
            hi: s_s.hi + slide,
        };
        let lb = cylindrical.max(s_t.gap(s_s));
        if lb > need {
            return lb;
        }
        // The meridian projection across the turning triangle's plane ([`Meridian`]).
        let centroid = (turning[0] + turning[1] + turning[2]) / 3.0;
        let lb = match Meridian::of_normal(n, centroid, ax.body_point, ax.body_dir) {
            Some(m) => {
                let rt = m.triangle_range(turning, ax.body_point, ax.body_dir);
                let rs = m.triangle_range(&still, axis_point, ax.world_dir);
                lb.max(m.gap(rt, rs, slide))
            }
            None => lb,
        };
        let lb = slabs(lb);
        match (self.helix_on(), lb > need) {
            (Some(helix), false) => {
                let body_still = if self.turning_is_1 { t2 } else { t1 };
                lb.max(helix.triangle_pair(turning, body_still, need))
            }
            _ => lb,
        }
    }

    /// The still triangle's plane against the turning triangle turned by any angle: a turning
    /// point at distance `rho` from the axis and axial coordinate `z` lies, whatever the
    /// angle, where `n . x` is `n . a + n_d z` plus at most `|n_perp| rho` either way (`n` the
    /// plane's unit normal, `n_d` its part along the axis, `n_perp` across it, `a` the axis
    /// point), and the turning triangle's largest (smallest) value of `n_d z + |n_perp| rho`
    /// (`n_d z - |n_perp| rho`) is at a corner (convex, concave). So the gap between the still
    /// corners' range of `n . x` (the plane, to rounding) and that range, less the axis point's
    /// slide along `n`, bounds the pair's distance from below, for any unit `n`. A barrel turning beside a plate's face 1.01 tolerances away: the ranges in the
    /// half-plane of `rho` and `z`, slabs or not, lose the plane's slope across the axis, and
    /// a robot's spinning barrel crawled to the iteration cap.
    fn plane_gap(&self, turning: &[Vec3; 3], still: &[Vec3; 3], a: Vec3, slide: f64) -> f64 {
        let ax = &self.axis;
        let n = (still[1] - still[0]).cross(still[2] - still[0]);
        let len = n.length();
        // A degenerate (or non-finite) still triangle: no plane.
        if len.is_nan() || len <= 0.0 {
            return 0.0;
        }
        let n = n / len;
        let n_d = n.dot(ax.world_dir);
        let n_perp = (n - ax.world_dir * n_d).length();
        // The still corners' range along `n`, not one corner's value: a sliver's normal is
        // off by rounding, and the range keeps the bound sound for any unit `n`.
        let along = still.map(|v| n.dot(v - a));
        let (c_lo, c_hi) = (
            along[0].min(along[1]).min(along[2]),
            along[0].max(along[1]).max(along[2]),
        );
        let (mut hi, mut lo) = (f64::NEG_INFINITY, f64::INFINITY);
        for &v in turning {
            let rel = v - ax.body_point;
            let z = rel.dot(ax.body_dir);
            let rho = (rel - ax.body_dir * z).length();
            hi = hi.max(n_d * z + n_perp * rho);
            lo = lo.min(n_d * z - n_perp * rho);
        }
        ((c_lo - hi).max(lo - c_hi) - n_d.abs() * slide).max(0.0)
    }

    /// The slabs' bound ([`slab_bound`]) on a turning triangle (body frame, its axial range
    /// `z_t`) and a still one (world frame), the axis point at the window's start and its
    /// slide over it: where the ranges over whole triangles fail, they lose the way a turning
    /// triangle's distance from the axis changes along it (a barrel's face, widest at its end,
    /// beside an edge tangent to the barrel at the face's middle: a robot's spinning barrel
    /// 1.04 tolerances from a soup's edge crawled to the iteration cap). Tried last: it halves
    /// the axial range up to [`SLAB_DEPTH`] times.
    fn slab_gap(
        &self,
        turning: &[Vec3; 3],
        still: &[Vec3; 3],
        (z_t, axis_point, slide): (Range, Vec3, f64),
        need: f64,
    ) -> f64 {
        let ax = &self.axis;
        let w = slab_width(need);
        let pair = (
            axis_coords(turning, ax.body_point, ax.body_dir, self.across.0),
            axis_coords(still, axis_point, ax.world_dir, self.across.1),
        );
        // The hopeless test of `slab_bound` on the whole triangles first, without clipping:
        // most pairs that reach here are about to touch.
        let (rho_s, z_s) = nearest_to_axis(&pair.1, 0.5 * (z_t.lo + z_t.hi));
        if (z_t.lo - w - slide..=z_t.hi + w + slide).contains(&z_s)
            && rho_s - section_reach(&pair.0, z_s.clamp(z_t.lo, z_t.hi)) < w
        {
            // Not a certificate (ties within rounding chose the point): at most `need`.
            return (rho_s - farthest(&pair.0)).min(need);
        }
        slab_bound(&pair, (z_t.lo, z_t.hi, SLAB_DEPTH), (w, slide))
    }
}

/// The smallest distance from the line through `p` over the triangle `tri`, the unit `u` and
/// `v` spanning the plane across the line ([`plane_across`]), exact: the distance from the
/// origin to the triangle projected on the plane across the line (the projection is linear,
/// and a point's distance from the line is the length of its part across it): 0 where the
/// projection holds the origin, else the nearest of its edges.
///
/// Inlined always: it is the still side's work per triangle (a still node's smallest distance
/// from the line passes over every triangle under it), and left a call, as the compiler did
/// once the profile's checks were added, it cost the shaft in its 4,096-triangle bore 7% more
/// instructions.
#[inline(always)]
fn line_distance(tri: &[Vec3; 3], p: Vec3, (u, v): (Vec3, Vec3)) -> f64 {
    nearest_to_axis(&axis_coords(tri, p, Vec3::ZERO, (u, v)), 0.0).0
}

/// The triangle's corners as `[across u, across v, along d]` from the point `p`: the frame of
/// an axis through `p` along the unit `d`, `u` and `v` spanning the plane across it (a zero `d`
/// leaves the axial coordinate 0).
fn axis_coords(tri: &[Vec3; 3], p: Vec3, d: Vec3, (u, v): (Vec3, Vec3)) -> [[f64; 3]; 3] {
    tri.map(|c| {
        let rel = c - p;
        [rel.dot(u), rel.dot(v), rel.dot(d)]
    })
}

/// The width beside a slab within which a still part is bounded by its distance from the axis
/// ([`slab_bound`], [`profile_triangle_gap`]): just over `need`, so that a bound of `w`
/// certifies it.
fn slab_width(need: f64) -> f64 {
    need * (1.0 + 1e-6) + f64::MIN_POSITIVE
}

/// How many slabs a turning node's profile has ([`AxisShells::turning_profile`]).
const PROFILE_BINS: usize = 8;

/// The axial range of slab `b` of a profile over `(lo, hi)`: the same numbers wherever asked.
fn profile_slab((lo, hi): (f64, f64), b: usize) -> (f64, f64) {
    let w = (hi - lo) / PROFILE_BINS as f64;
    let s_hi = if b + 1 == PROFILE_BINS {
        hi
    } else {
        lo + w * (b + 1) as f64
    };
    (lo + w * b as f64, s_hi)
}

/// A lower bound on the distance between a turning node whose profile over the axial range
/// `z` is `profile` and a still set at least `rho_s` from the axis over the axial range `z_s`
/// (slide included), whatever the angle: two points are at least as far apart as their
/// distances from the axis differ, and as their axial coordinates do, so a slab's part is at
/// least the root of the sum of those gaps' squares away. The smallest over the slabs; 0 (a
/// bound too) as soon as one slab's is at most `need`, which then cannot be certified.
fn profile_gap(
    profile: &[f64; PROFILE_BINS],
    z: (f64, f64),
    (rho_s, z_s): (f64, Range),
    need: f64,
) -> f64 {
    let mut lb = f64::INFINITY;
    for (b, &reach) in profile.iter().enumerate() {
        if reach < 0.0 {
            continue;
        }
        let (lo, hi) = profile_slab(z, b);
        let g_z = Range { lo, hi }.gap(z_s);
        let g_rho = (rho_s - reach).max(0.0);
        lb = lb.min((g_rho * g_rho + g_z * g_z).sqrt());
        if lb <= need {
            return 0.0;
        }
    }
    lb
}

/// A lower bound on the distance between a turning node whose profile over the axial range
/// `z` is `profile` and a still triangle (corners as `[across u, across v, along the axis]`
/// from the axis point at the window's start; the axis point slides by up to `slide`),
/// whatever the angle: the still triangle's part within `w` (just over `need`) of a slab along
/// the axis, widened by the slide, is at least its exact smallest distance from the axis
/// ([`nearest_to_axis`] of the part clipped) from the axis, and the rest is more than `w` away
/// along it; so each slab's points are at least `min(w, rho_s - reach)` from the triangle. The
/// smallest over the slabs; 0 as soon as one slab's is at most `need`. A bore's triangle whose
/// distance from the axis grows with its height (the step from a bore's narrow part to its
/// groove) fails the triangle's smallest distance against the key's slab, and not its part
/// beside that slab.
fn profile_triangle_gap(
    profile: &[f64; PROFILE_BINS],
    z: (f64, f64),
    still: &[[f64; 3]; 3],
    slide: f64,
    need: f64,
) -> f64 {
    let w = slab_width(need);
    let mut lb = w;
    for (b, &reach) in profile.iter().enumerate() {
        if reach < 0.0 {
            continue;
        }
        let (lo, hi) = profile_slab(z, b);
        if let Some((part, n)) = clip_to_slab(still, (lo - w - slide, hi + w + slide)) {
            let (rho_s, _) = nearest_to_axis(&part[..n], 0.5 * (lo + hi));
            lb = lb.min(rho_s - reach);
            if lb <= need {
                return 0.0;
            }
        }
    }
    lb
}

/// How many times [`slab_bound`] may halve a turning triangle's axial range.
const SLAB_DEPTH: u32 = 8;

/// A lower bound on the distance between a turning triangle and a still one (corners as
/// `[across u, across v, along the axis]`, each from its own axis point) whatever the angle
/// turned, up to `w`, from slabs across the axis: over the slab `[lo, hi]`, the turning
/// triangle's part is at most `rho_t` from the axis (its clipped corners', exact: the distance
/// from a line is convex), and the still triangle's part within `w + slide` of the slab at
/// least `rho_s` ([`nearest_to_axis`]); its other points are more than `w` away along
/// the axis. So each pair of points is at least `min(w, rho_s - rho_t)` apart. A slab that
/// does not certify `w` is halved, `depth` times at most; the bound is the smallest found.
fn slab_bound(
    (turning, still): &([[f64; 3]; 3], [[f64; 3]; 3]),
    (lo, hi, depth): (f64, f64, u32),
    (w, slide): (f64, f64),
) -> f64 {
    let Some((t, nt)) = clip_to_slab(turning, (lo, hi)) else {
        return w;
    };
    let Some((s, ns)) = clip_to_slab(still, (lo - w - slide, hi + w + slide)) else {
        return w;
    };
    let (rho_s, z_s) = nearest_to_axis(&s[..ns], 0.5 * (lo + hi));
    let bound = w.min(rho_s - farthest(&t[..nt]));
    if bound >= w || depth == 0 {
        return bound;
    }
    // Hopeless: every slab whose widened range holds the still part's nearest point to the
    // axis (at `z_s`; the slab holding `z_s` clamped to the range) meets the turning part's
    // section there, so no halving certifies it. A pair about to touch (a shaft's corner
    // coming onto its bore's face) stops here instead of halving 8 times: the 32-sided shaft
    // 0.3 tolerances from its bore took 25 ms instead of 12.8 with the halvings.
    if rho_s - section_reach(turning, z_s.clamp(lo, hi)) < w {
        return bound;
    }
    let mid = 0.5 * (lo + hi);
    let first = slab_bound(&(*turning, *still), (lo, mid, depth - 1), (w, slide));
    if first < w {
        // A failing half fails the slab; its own bound still holds.
        return bound;
    }
    slab_bound(&(*turning, *still), (mid, hi, depth - 1), (w, slide)).max(bound)
}

/// The largest distance from the axis (the third coordinate's line) over the corners.
fn farthest(corners: &[[f64; 3]]) -> f64 {
    corners
        .iter()
        .fold(0.0_f64, |m, c| m.max(c[0] * c[0] + c[1] * c[1]))
        .sqrt()
}

/// The largest distance from the axis (the third coordinate's line) over the triangle's
/// section at axial coordinate `z` (corners as `[x, y, z]`): over the points where its edges
/// cross `z` (the section is a segment between two of them; the distance is convex); 0 where
/// the triangle does not reach `z`.
fn section_reach(tri: &[[f64; 3]; 3], z: f64) -> f64 {
    let mut m2 = 0.0_f64;
    for i in 0..3 {
        let (a, b) = (tri[i], tri[(i + 1) % 3]);
        if a[2] == z {
            m2 = m2.max(a[0] * a[0] + a[1] * a[1]);
        }
        if (a[2] < z) != (b[2] < z) && a[2] != b[2] {
            let f = (z - a[2]) / (b[2] - a[2]);
            let (x, y) = (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]));
            m2 = m2.max(x * x + y * y);
        }
    }
    m2.sqrt()
}

/// The triangle (corners as `[x, y, z]`) clipped to `lo <= z <= hi`: a convex polygon of up
/// to five corners in order (room for eight, should rounding make a cut cross it more than
/// twice), with their count; `None` where nothing is left.
fn clip_to_slab(tri: &[[f64; 3]; 3], (lo, hi): (f64, f64)) -> Option<([[f64; 3]; 8], usize)> {
    let mut poly = [[0.0; 3]; 8];
    poly[..3].copy_from_slice(tri);
    let mut n = 3;
    for (bound, above) in [(lo, true), (hi, false)] {
        let inside = |q: &[f64; 3]| if above { q[2] >= bound } else { q[2] <= bound };
        let mut out = [[0.0; 3]; 8];
        let mut m = 0;
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            if inside(&a) {
                out[m] = a;
                m += 1;
            }
            if inside(&a) != inside(&b) {
                let f = (bound - a[2]) / (b[2] - a[2]);
                out[m] = [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), bound];
                m += 1;
            }
        }
        if m == 0 {
            return None;
        }
        (poly, n) = (out, m);
    }
    Some((poly, n))
}

/// The smallest distance from the axis (the third coordinate's line) over the convex polygon
/// `poly` (corners as `[x, y, z]`, in order), and the axial coordinate of a point where it is
/// reached, the nearest to `target` (a face parallel to the axis reaches it along a segment):
/// on an edge at the parameter of its nearest point in projection (the projection is linear),
/// ties within rounding spanning the range the point is taken in. Where the projection holds
/// the origin, 0 and `target` clamped to the polygon's axial range (any point then does for
/// [`slab_bound`], whose test fails with a distance of 0).
fn nearest_to_axis(poly: &[[f64; 3]], target: f64) -> (f64, f64) {
    let n = poly.len();
    let cross = |a: &[f64; 3], b: &[f64; 3]| a[0] * b[1] - a[1] * b[0];
    let (mut pos, mut neg) = (true, true);
    let (mut zlo, mut zhi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let c = cross(&poly[i], &poly[(i + 1) % n]);
        pos &= c >= 0.0;
        neg &= c <= 0.0;
        zlo = zlo.min(poly[i][2]);
        zhi = zhi.max(poly[i][2]);
    }
    if pos || neg {
        return (0.0, target.clamp(zlo, zhi));
    }
    // Squared distances, one root at the end (`hypot` in the loop cost as much as the rest).
    let (mut best, mut range) = (f64::INFINITY, (0.0, 0.0));
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let len2 = ex * ex + ey * ey;
        // An edge along the axis projects to a point: all of it is as near.
        let (f0, f1) = if len2 > 0.0 {
            let f = (-(a[0] * ex + a[1] * ey) / len2).clamp(0.0, 1.0);
            (f, f)
        } else {
            (0.0, 1.0)
        };
        let (x, y) = (a[0] + f0 * ex, a[1] + f0 * ey);
        let d2 = x * x + y * y;
        let (za, zb) = (a[2] + f0 * (b[2] - a[2]), a[2] + f1 * (b[2] - a[2]));
        let (za, zb) = (za.min(zb), za.max(zb));
        if d2 < best * (1.0 - 1e-12) {
            (best, range) = (d2, (za, zb));
        } else if d2 <= best * (1.0 + 1e-12) {
            range = (range.0.min(za), range.1.max(zb));
        }
    }
    (best.sqrt(), target.clamp(range.0, range.1))
}

/// Two unit vectors spanning the plane across the unit `d`.
fn plane_across(d: Vec3) -> (Vec3, Vec3) {
    let u = any_orthogonal(d);
    (u, d.cross(u))
}

/// The parameter `lambda` of the point `p + lambda d` of the axis (unit `d`) nearest the line
/// through `c` with unit direction `n`; the foot of `c` when the two are parallel.
fn closest_on_axis(p: Vec3, d: Vec3, c: Vec3, n: Vec3) -> f64 {
    let rel = c - p;
    let (dn, dd) = (d.dot(n), d.dot(rel));
    let denom = 1.0 - dn * dn;
    if denom > 1e-9 {
        (dd - dn * n.dot(rel)) / denom
    } else {
        dd
    }
}

/// The centre of the circle through a triangle's corners; `None` when it is degenerate.
fn circumcentre(t: &[Vec3; 3]) -> Option<Vec3> {
    let (a, b) = (t[1] - t[0], t[2] - t[0]);
    let n = a.cross(b);
    let nn = n.length_squared();
    let degenerate = nn.is_nan() || nn <= 1e-30 * a.length_squared() * b.length_squared();
    if degenerate {
        return None;
    }
    Some(t[0] + (b.length_squared() * n.cross(a) + a.length_squared() * b.cross(n)) / (2.0 * nn))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::query::contact_time::test_support::assert_below_sampled;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Asserts that `v` lies in `range`, to `slack`.
    pub(super) fn assert_in(v: f64, range: Range, slack: f64, what: &str) {
        assert!(
            v >= range.lo - slack && v <= range.hi + slack,
            "{what} {v} outside [{}, {}]",
            range.lo,
            range.hi
        );
    }

    /// A screw between two poses of a pure turn about an axis off the origin slides by
    /// rounding only: no helical certificate (its quotient cost 80% of a robot wrist's query).
    /// A real slide keeps it, however small against the turn.
    #[test]
    fn a_turn_that_slides_by_rounding_gets_no_helix() {
        let root = *crate::mesh::box_mesh(Vec3::splat(0.05))
            .expect("a box")
            .bvh()
            .root();
        let start =
            Pose::from_axis_angle(Vec3::new(0.3, -0.2, 0.9), 0.7, Vec3::new(-0.1, 0.6, 1.3));
        let still = Motion::stationary(Pose::IDENTITY);
        let dir = Vec3::new(-0.001, 0.03, -1.0).normalize();
        let point = Vec3::new(-0.11, 0.66, 0.02);
        for (slide, helix) in [(0.0, false), (1e-6, true), (0.1, true)] {
            let turn = Pose::from_axis_angle(dir, 3.1, Vec3::ZERO);
            let end = Pose {
                rotation: turn.rotation * start.rotation,
                translation: turn.rotation * (start.translation - point) + point + dir * slide,
            };
            let screw = Motion::screw(start, end).expect("a screw");
            let axis = screw.fixed_axis().expect("a fixed axis");
            assert!(
                slide > 0.0 || axis.along != 0.0,
                "the case should slide by rounding"
            );
            let shells = AxisShells::new(&screw, &still, &root, &root).expect("shells");
            assert_eq!(
                shells.helix.is_some(),
                helix,
                "slide {slide}: {}",
                axis.along
            );
        }
    }

    /// Triangles of a 128-sided shaft turning half a turn about its axis inside a bore of
    /// 1.004 times its radius, along the tubes' length (long and thin, as `tube` makes them):
    /// the triangle pair's bound holds (below the distance at every sampled angle) and is
    /// tight (at least the radial gap between the shaft's corners and the bore's flat faces).
    /// Its smallest distance from the axis was the centroid's less the corners' spread, which
    /// for these triangles fell below the axis (0), and the query took 6 s.
    #[test]
    fn long_triangles_of_a_shaft_in_a_bore_are_certified_by_their_radial_gap() {
        let step = std::f64::consts::TAU / 128.0;
        let gap = 1.004 * (step / 2.0).cos() - 1.0;
        check_faces_of_revolution(128, (|_| 1.0, |_| 1.004), (-2.0, 1.5, 0.5, 0.75), gap);
    }

    /// Random face pairs of two surfaces of revolution about z with `n` columns, the turning
    /// one's radius `radii.0(z)`, the still one's `radii.1(z)`, faces from heights in
    /// `z.0..z.1` and `z.2` (turning) and `z.3` (still) long: the bound of each pair under a
    /// half turn is at least `gap` and at most its distance at every sampled angle.
    pub(super) fn check_faces_of_revolution(
        n: u32,
        radii: (impl Fn(f64) -> f64, impl Fn(f64) -> f64),
        z: (f64, f64, f64, f64),
        gap: f64,
    ) {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let turn = Pose::from_axis_angle(Vec3::Z, std::f64::consts::PI, Vec3::ZERO);
        let motion = Motion::screw(Pose::IDENTITY, turn).expect("screw");
        let still = Motion::stationary(Pose::IDENTITY);
        let root = *crate::mesh::box_mesh(Vec3::ONE).expect("box").bvh().root();
        let shells = AxisShells::new(&motion, &still, &root, &root).expect("a fixed axis");
        let step = std::f64::consts::TAU / f64::from(n);
        let face = |r: &dyn Fn(f64) -> f64, k: u32, z0: f64, z1: f64, upper: bool| {
            let (a0, a1) = (step * f64::from(k), step * f64::from(k + 1));
            let p = |a: f64, z: f64| Vec3::new(r(z) * a.cos(), r(z) * a.sin(), z);
            if upper {
                [p(a0, z0), p(a1, z1), p(a0, z1)]
            } else {
                [p(a0, z0), p(a1, z0), p(a1, z1)]
            }
        };
        for case in 0..200 {
            let h = rng.random_range(z.0..z.1);
            let t1 = face(&radii.0, rng.random_range(0..n), h, h + z.2, case % 2 == 0);
            let h = rng.random_range(z.0..z.1);
            let t2 = face(&radii.1, rng.random_range(0..n), h, h + z.3, case % 3 == 0);
            let lb = shells.lower_bound_triangles(&t1, &t2, (0.0, 1.0), f64::INFINITY);
            assert!(
                lb >= gap * (1.0 - 1e-9),
                "case {case}: bound {lb} below the gap {gap}"
            );
            let label = format!("case {case}");
            assert_below_sampled(lb, &motion, (&t1, &t2), 64, &label);
        }
    }

    /// A keyed shaft (radius 0.05, 64 sides, 0.06 over its upper quarter and 0.3 rad) turning
    /// in its bore: a narrow part below the key (12.5 tolerances of 2e-5 clear of the shaft's
    /// body), a groove of radius 0.07 above, triangles stepping from one to the other between.
    /// Every node of the narrow part and every triangle of the bore is certified against the
    /// whole shaft by the shaft's profile (`profile_gap`, `profile_triangle_gap`), which its
    /// largest distance from the axis (the key's) and its axial range (overlapping the bore's)
    /// did not; at every sampled angle the profile's bounds stay below the distances. The
    /// search split the bore first and failed each of the narrow part's 768 triangles, and
    /// each stepping one, against the whole shaft (a keyed lever's contact: 45 ms).
    #[test]
    fn a_keyed_shafts_profile_clears_its_bore() {
        let half = std::f64::consts::PI / 64.0;
        let key = |a: f64, z: f64| {
            if z >= 0.05 - 1e-12 && a < 0.3 {
                0.06
            } else {
                0.05
            }
        };
        let shaft = crate::mesh::revolved(key, 0.2, 64, 8).expect("shaft");
        let narrow = 0.05 * 1.005 / half.cos();
        let bore = crate::mesh::revolved(|_, z| if z <= 0.0 { narrow } else { 0.07 }, 0.3, 64, 12)
            .expect("bore");
        let (motion, _) = whole_turn();
        let still = Motion::stationary(Pose::IDENTITY);
        let (bs, bb) = (shaft.bvh(), bore.bvh());
        let shells = AxisShells::new(&motion, &still, bs.root(), bb.root()).expect("an axis");
        let need = 1e-5;
        let mut narrow_nodes = 0;
        for (j, node) in bb.nodes().iter().enumerate() {
            let tris = &bb.leaf_triangles()[node.leaf_range()];
            let in_narrow = tris.iter().flatten().all(|p| p.z <= 0.0);
            if node.is_leaf() || in_narrow {
                let lb = shells.lower_bound_inner((&shaft, 0), (bb, j as u32), (0.0, 1.0), need);
                assert!(lb > need, "bore node {j}: bound {lb}");
                narrow_nodes += usize::from(!node.is_leaf());
            }
        }
        assert!(
            narrow_nodes > 100,
            "{narrow_nodes} nodes of the narrow part"
        );
        // The profile's bounds against the bore's triangles, below the sampled distances.
        let [_, z_lo, z_hi, _] = shells.turning_corners(&shaft, 0);
        let profile = shells.turning_profile(&shaft, 0, (z_lo, z_hi));
        for (i, t2) in bb.leaf_triangles().iter().enumerate().step_by(29) {
            let rho = line_distance(t2, Vec3::ZERO, shells.across.1);
            let z = t2.iter().fold(Range::EMPTY, |r, p| r.with(p.z));
            let s = axis_coords(t2, Vec3::ZERO, Vec3::Z, shells.across.1);
            let lbs = [
                profile_gap(&profile, (z_lo, z_hi), (rho, z), -1.0),
                profile_triangle_gap(&profile, (z_lo, z_hi), &s, 0.0, need),
            ];
            assert!(lbs[1] > need, "bore triangle {i}: bound {}", lbs[1]);
            for t1 in bs.leaf_triangles().iter().step_by(11) {
                for lb in lbs {
                    assert_below_sampled(lb, &motion, (t1, t2), 16, &format!("triangle {i}"));
                }
            }
        }
    }

    /// A whole turn about z, and the certificates' data for it past a still body.
    fn whole_turn() -> (Motion, AxisShells) {
        let whole = Vec3::Z * std::f64::consts::TAU;
        let motion = Motion::turn(Pose::IDENTITY, Vec3::ZERO, whole).expect("a turn");
        let still = Motion::stationary(Pose::IDENTITY);
        let root = *crate::mesh::box_mesh(Vec3::ONE).expect("box").bvh().root();
        let shells = AxisShells::new(&motion, &still, &root, &root).expect("a fixed axis");
        (motion, shells)
    }

    /// Faces of a barrel-shaped shaft (radius `0.05 (1 + 0.03 sin 10z)`, widest at the face's
    /// upper end) turning a whole turn about z beside long still triangles whose edge passes
    /// the face's corners tangentially at height 0.08, slanted up to 0.6 rad, `clearance`
    /// beyond the corners' circle there: at 1.5 `need` the bound certifies `need`; at every
    /// clearance (down to overlapping) it stays below the distance at every sampled angle.
    /// The ranges over whole triangles certified nothing here: the face's
    /// widest corner lies farther out than its points at the edge's height, and a shaft of a
    /// random soup's robot crawled to the iteration cap.
    #[test]
    fn barrel_faces_beside_tangent_edges_are_certified_slab_by_slab() {
        let mut rng = ChaCha8Rng::seed_from_u64(48);
        let (motion, shells) = whole_turn();
        let radius = |z: f64| 0.05 * (1.0 + 0.03 * (10.0 * z).sin());
        let at = |a: f64, r: f64, z: f64| Vec3::new(r * a.cos(), r * a.sin(), z);
        let need = 1e-5;
        let (z0, z1, zc) = (0.05, 0.1, 0.08);
        for case in 0..60 {
            let a0: f64 = rng.random_range(0.0..6.0);
            let a1 = a0 + std::f64::consts::TAU / 32.0;
            let face = [
                at(a0, radius(z0), z0),
                at(a1, radius(z0), z0),
                at(a0, radius(z1), z1),
            ];
            // The face's farthest point from the axis at height zc: on its edge at angle a0.
            let f = (zc - z0) / (z1 - z0);
            let r_c = radius(z0) + f * (radius(z1) - radius(z0));
            let clearance = if case < 20 {
                1.5 * need
            } else {
                rng.random_range(-2.0..4.0) * need
            };
            let phi = a0 + rng.random_range(-0.5..0.5);
            let beta: f64 = rng.random_range(-0.6..0.6);
            let centre = at(phi, r_c + clearance, zc);
            let along = Vec3::new(-phi.sin(), phi.cos(), 0.0) * beta.cos() + Vec3::Z * beta.sin();
            let out = at(phi, 0.4, zc + rng.random_range(-0.2..0.2));
            let edge = [centre - along * 0.3, centre + along * 0.3, out];
            let lb = shells.lower_bound_triangles(&face, &edge, (0.0, 1.0), need);
            if case < 20 {
                assert!(lb > need, "case {case}: bound {lb} does not certify {need}");
            }
            // At 4,000 angles of the whole turn the sampled distance is within 2e-8 of the
            // least (a corner at 0.05 from the axis passing the edge).
            let label = format!("case {case}, clearance {clearance:e}");
            assert_below_sampled(lb, &motion, (&face, &edge), 4000, &label);
        }
    }

    /// A turning triangle beside a still one's plane, a whole turn: the plane's bound stays
    /// below the distance at every one of 4,000 sampled angles, for random triangles about
    /// the axis and random still triangles on either side, tilted any way; and a barrel's
    /// face beside a large plate tilted 0.3 to 1.2 rad from the axis, 1.5 `need` from the
    /// face's corners' nearest approach, is certified (the ranges in the half-plane of `rho`
    /// and `z`, slabs included, were not: a robot's spinning barrel crawled to the cap).
    #[test]
    fn a_turning_triangle_beside_a_plane_is_bounded_by_the_plane() {
        use crate::motion::sampling::unit;
        let mut rng = ChaCha8Rng::seed_from_u64(4803);
        let (motion, shells) = whole_turn();
        let need = 1e-5;
        for case in 0..80 {
            let (turning, plate) = if case < 40 {
                let turning = [0; 3].map(|_| unit(&mut rng) * rng.random_range(0.0..0.1));
                let c = unit(&mut rng) * rng.random_range(0.05..0.3);
                (
                    turning,
                    [0; 3].map(|_| c + unit(&mut rng) * rng.random_range(0.0..0.3)),
                )
            } else {
                // A barrel's face, and a plate whose normal leans `tilt` from the radial
                // direction towards the axis, touching the corners' nearest reach plus 1.5
                // need.
                let r = |z: f64| 0.05 * (1.0 + 0.03 * (10.0 * z).sin());
                let a0: f64 = rng.random_range(0.0..6.0);
                let a1 = a0 + std::f64::consts::TAU / 32.0;
                let at = |a: f64, z: f64| Vec3::new(r(z) * a.cos(), r(z) * a.sin(), z);
                let face = [at(a0, 0.05), at(a1, 0.05), at(a0, 0.1)];
                let tilt: f64 = rng.random_range(0.3..1.2);
                let phi: f64 = rng.random_range(0.0..6.3);
                let n = Vec3::new(phi.cos(), phi.sin(), 0.0) * tilt.cos() + Vec3::Z * tilt.sin();
                let reach = face
                    .iter()
                    .map(|v| n.z * v.z + (n.x.hypot(n.y)) * v.x.hypot(v.y))
                    .fold(f64::NEG_INFINITY, f64::max);
                let c = reach + 1.5 * need;
                let (u, v) = plane_across(n);
                let o = n * c;
                let plate = [
                    o + u * 0.5,
                    o - u * 0.25 + v * 0.45,
                    o - u * 0.25 - v * 0.45,
                ];
                (face, plate)
            };
            let lb = shells.lower_bound_triangles(&turning, &plate, (0.0, 1.0), need);
            if case >= 40 {
                assert!(lb > need, "case {case}: bound {lb} does not certify {need}");
            }
            assert_below_sampled(
                lb,
                &motion,
                (&turning, &plate),
                4000,
                &format!("case {case}"),
            );
        }
    }

    /// A volume whose centre lies on the line (to rounding) keeps its width across it: every
    /// sampled point's distance from the line and axial coordinate lie in the ranges. The
    /// first case is the one a robot's spinning barrel met (its axis a unit to within an ulp,
    /// a node centred on it): the ranges were taken across a unit that pointed along the line,
    /// 0.0354 from it at most for a node reaching 0.0427, and a contact was missed.
    #[test]
    fn a_volume_centred_on_the_line_keeps_its_width_across_it() {
        use crate::motion::sampling::{rss_point, unit};
        let mut rng = ChaCha8Rng::seed_from_u64(4802);
        for case in 0..400 {
            let (p, d, c, e0, e1, l, r) = if case == 0 {
                let e0 = Vec3::new(0.9135454576426006, -0.4067366430758004, 0.0);
                (
                    Vec3::ZERO,
                    Vec3::new(0.0, 0.0, 0.9999999999999999),
                    Vec3::new(0.0, 0.0, -0.07500000000000001),
                    e0,
                    Vec3::Z.cross(e0),
                    [0.04270139768861504, 0.04246747496415584],
                    0.025000000000001,
                )
            } else {
                let (p, d) = (unit(&mut rng) * rng.random_range(0.0..2.0), unit(&mut rng));
                let c = p + d * rng.random_range(-1.0..1.0);
                let e0 = unit(&mut rng);
                let e1 = e0.cross(unit(&mut rng)).normalize();
                let size = [1e-3, 0.1, 1.0][case % 3];
                let l = [size * rng.random::<f64>(), size * rng.random::<f64>()];
                (p, d, c, e0, e1, l, size * 0.2 * rng.random::<f64>())
            };
            let (rho, z) = cylinder(c, e0, e1, l, r, p, d);
            for _ in 0..400 {
                let x = rss_point(&mut rng, c, (e0, e1), (l[0], l[1]), r);
                let rel = x - p;
                let (xz, xrho) = (rel.dot(d), rel.cross(d).length());
                let slack = 1e-12 * (1.0 + rel.length());
                assert_in(
                    xrho,
                    rho,
                    slack,
                    &format!("case {case}: distance from the line"),
                );
                assert_in(xz, z, slack, &format!("case {case}: axial coordinate"));
            }
        }
    }

    /// A still node's smallest distance from the axis line is its triangles' smallest, each
    /// exact: no point sampled on a triangle is nearer the line, and the nearest sample is
    /// within the sampling's resolution of it; on a random soup, every node.
    #[test]
    fn a_still_nodes_distance_from_the_axis_is_its_triangles_smallest() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let axis_dir = Vec3::new(0.3, -0.2, 1.0).normalize();
        let turn = Pose::from_axis_angle(axis_dir, 2.0, Vec3::ZERO);
        let motion = Motion::screw(Pose::IDENTITY, turn).expect("screw");
        let still_pose = Pose::from_axis_angle(Vec3::X, 0.4, Vec3::new(0.2, 0.1, 0.0));
        let still = Motion::stationary(still_pose);
        let vertices: Vec<Vec3> = (0..60)
            .map(|_| Vec3::new(rng.random(), rng.random(), rng.random()) * 3.0 - Vec3::ONE)
            .collect();
        let triangles: Vec<[u32; 3]> = (0..80)
            .map(|_| [0; 3].map(|_| rng.random_range(0..60u32)))
            .collect();
        let soup = crate::TriMesh::new(vertices, triangles).expect("soup");
        let root = *soup.bvh().root();
        let shells = AxisShells::new(&motion, &still, &root, &root).expect("a fixed axis");
        let ax = shells.axis;
        let bvh = soup.bvh();
        let exact: Vec<f64> = bvh
            .leaf_triangles()
            .iter()
            .map(|t| {
                let w = t.map(|p| still_pose.transform_point(p));
                line_distance(&w, ax.world_point, shells.across.1)
            })
            .collect();
        for (k, t) in bvh.leaf_triangles().iter().enumerate() {
            let w = t.map(|p| still_pose.transform_point(p));
            let mut nearest = f64::INFINITY;
            for i in 0..=40 {
                for j in 0..=(40 - i) {
                    let (a, b) = (f64::from(i) / 40.0, f64::from(j) / 40.0);
                    let p = w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * b - ax.world_point;
                    let rho = (p - ax.world_dir * p.dot(ax.world_dir)).length();
                    assert!(rho >= exact[k] - 1e-12, "triangle {k}: a sample at {rho}");
                    nearest = nearest.min(rho);
                }
            }
            let size = (w[1] - w[0]).length().max((w[2] - w[0]).length());
            assert!(
                nearest <= exact[k] + size / 20.0,
                "triangle {k}: {nearest} vs {}",
                exact[k]
            );
        }
        for (index, node) in bvh.nodes().iter().enumerate() {
            let want = exact[node.leaf_range()]
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            assert_eq!(shells.still_rho_lo(bvh, index as u32), want, "node {index}");
        }
    }
}

#[cfg(test)]
mod meridian_tests {
    use super::tests::assert_in;
    use super::*;
    use crate::motion::sampling::{rss_point, unit};
    use crate::query::contact_time::test_support::point_on;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The meridian value `h` of a point: `n.rho` times its distance from the line plus `n.z`
    /// times its axial coordinate.
    fn h(n: Meridian, x: Vec3, p: Vec3, d: Vec3) -> f64 {
        let rel = x - p;
        let z = rel.dot(d);
        n.rho * (rel - d * z).length() + n.z * z
    }

    /// Every sampled point of random triangles and swept rectangles has its `h` within the
    /// range the certificate takes, for random axes and meridian directions of either sign,
    /// the sets far from the axis, near it and across it.
    #[test]
    fn meridian_ranges_hold_every_sampled_point() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        for case in 0..400 {
            let (p, d) = (unit(&mut rng) * 2.0, unit(&mut rng));
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let n = Meridian {
                rho: angle.cos(),
                z: angle.sin(),
            };
            let centre = p + unit(&mut rng) * [0.05, 0.5, 3.0][case % 3];
            let size = [0.01, 0.3, 2.0][case / 3 % 3];
            let tri = [0; 3].map(|_| centre + unit(&mut rng) * size * rng.random::<f64>());
            let range = n.triangle_range(&tri, p, d);
            for _ in 0..200 {
                let x = point_on(&mut rng, &tri);
                let v = h(n, x, p, d);
                let slack = 1e-12 * (1.0 + v.abs());
                assert_in(v, range, slack, &format!("case {case}: triangle point's h"));
            }
            let e0 = unit(&mut rng);
            let e1 = e0.cross(unit(&mut rng)).normalize();
            let l = [size * rng.random::<f64>(), size * rng.random::<f64>()];
            let r = size * 0.2 * rng.random::<f64>();
            let range = n.volume_range(centre, (e0, e1), l, r, p, d);
            for _ in 0..200 {
                let x = rss_point(&mut rng, centre, (e0, e1), (l[0], l[1]), r);
                let v = h(n, x, p, d);
                let slack = 1e-12 * (1.0 + v.abs());
                assert_in(v, range, slack, &format!("case {case}: volume point's h"));
            }
        }
    }

    /// A 256-sided shaft tapering from radius 1 to 0.5, turning half a turn in a bore of the
    /// same taper 0.004 wider (its faces 0.00388 apart across the slope): every triangle pair
    /// is certified by at least that gap less the facets' curvature, and no more than the
    /// distance at any sampled angle. The axis-aligned ranges overlap along the slope, and the
    /// query took 6.7 s.
    #[test]
    fn tapered_triangles_are_certified_by_their_meridian_gap() {
        let step = std::f64::consts::TAU / 256.0;
        // The faces' distance across the slope, less what the tangent form at a bore
        // triangle's centroid loses at its farthest corner (two thirds of a column round).
        let gap = 0.004 / 1.0625f64.sqrt() - 1.004 * (1.0 - (2.0 * step / 3.0).cos());
        let taper = |c: f64| move |z: f64| 0.75 + c - 0.25 * z;
        super::tests::check_faces_of_revolution(
            256,
            (taper(0.0), taper(0.004)),
            (-1.0, 0.75, 0.25, 0.25),
            gap,
        );
    }

    /// Node pairs of two random soups, one turning (and sliding along the axis) past the
    /// other: the volumes' bound, the turning node's exact ranges against the still volume
    /// (refined to the end, and stopping at the first positive bound, which takes the still
    /// node's exact ranges where a corner allows), and the triangles' bound are each at most
    /// the distance between the two nodes' triangles at every sampled time of the window. In
    /// half the cases the still soup sits along the axis, its nodes' axial ranges deciding.
    #[test]
    fn node_bounds_are_below_the_sampled_distances() {
        let mut rng = ChaCha8Rng::seed_from_u64(34);
        let soup = |rng: &mut ChaCha8Rng, centre: Vec3| {
            let vertices: Vec<Vec3> = (0..40)
                .map(|_| centre + unit(rng) * rng.random_range(0.2..1.5))
                .collect();
            let triangles: Vec<[u32; 3]> = (0..40)
                .map(|_| [0; 3].map(|_| rng.random_range(0..40u32)))
                .collect();
            crate::TriMesh::new(vertices, triangles).expect("soup")
        };
        for case in 0..24 {
            let axis = unit(&mut rng);
            let slide = if case % 2 == 0 { 0.0 } else { 0.7 };
            let end = Pose::from_axis_angle(axis, 2.5, axis * slide);
            let motion = Motion::screw(Pose::IDENTITY, end).expect("screw");
            let still_pose = Pose::from_axis_angle(unit(&mut rng), 0.7, unit(&mut rng) * 0.3);
            let still = Motion::stationary(still_pose);
            let offset = if case % 4 < 2 {
                unit(&mut rng)
            } else {
                axis * rng.random_range(2.0..3.2) + unit(&mut rng) * 0.2
            };
            let (m1, m2) = (soup(&mut rng, Vec3::ZERO), soup(&mut rng, offset));
            let (b1, b2) = (m1.bvh(), m2.bvh());
            let shells =
                AxisShells::new(&motion, &still, b1.root(), b2.root()).expect("a fixed axis");
            // The helical bounds too, for the screws that slide (as after a close fit at t = 0).
            shells.allow_quotient();
            let (t, h) = (rng.random_range(0.0..0.5), rng.random_range(0.05..0.5));
            for (i, a) in b1.nodes().iter().enumerate() {
                for (j, b) in b2.nodes().iter().enumerate() {
                    let tris1 = &b1.leaf_triangles()[a.leaf_range()];
                    let tris2 = &b2.leaf_triangles()[b.leaf_range()];
                    let mut lb = shells.lower_bound(&a.rss, &b.rss, (t, h), f64::INFINITY);
                    for need in [1e9, 0.3, 0.05, 0.0] {
                        let inner =
                            shells.lower_bound_inner((&m1, i as u32), (b2, j as u32), (t, h), need);
                        lb = lb.max(inner);
                    }
                    if a.is_leaf() && b.is_leaf() {
                        let tri = shells.lower_bound_triangles(&tris1[0], &tris2[0], (t, h), 1e9);
                        lb = lb.max(tri);
                    }
                    let still_tris: Vec<[Vec3; 3]> = tris2
                        .iter()
                        .map(|tri| tri.map(|p| still_pose.transform_point(p)))
                        .collect();
                    for k in 0..=8 {
                        let pose = motion.pose_at(t + h * f64::from(k) / 8.0);
                        for t1 in tris1 {
                            let moved = t1.map(|p| pose.transform_point(p));
                            for t2 in &still_tris {
                                let d = distance_triangle_triangle(&moved, t2).distance;
                                assert!(
                                    lb <= d + 1e-12,
                                    "case {case}, nodes {i} and {j}: bound {lb} above {d}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
