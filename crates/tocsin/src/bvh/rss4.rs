//! Four RSS pair bounds at once, for the distance search and `collide`.
//!
//! The same four candidate axes as [`super::rss_separation`] (the two normals, the
//! near-points axis and the long edges' perpendicular), evaluated for the four child pairs of an expansion in lanes, without
//! early exits or branches. Lane `2 i + j` pairs `a[i]` with `b[j]`. Each lane's value is the
//! largest gap over the axes, a valid lower bound on the distance between its two volumes by
//! convex duality; each lane also returns its near-points axis (unit, mesh 1's frame), on which
//! the distance search projects the corners of small subtrees.
//!
//! Two paths, chosen at run time by [`Lanes4`]: a portable one written as loops over
//! `[f64; 4]`, and, on x86-64 CPUs with AVX2 and FMA, the same formulas in intrinsics
//! (`rss4_avx2`). Left to itself the compiler packed the portable loops into 2-lane registers
//! and spilled; the intrinsics version was 340 instructions per call (386 since it also
//! returns the axes; the fourth axis added 4%) and made the knot34k distance searches 12 to 15% faster. The two paths
//! agree to rounding (fused multiply-adds), not bit for bit.

// Lane loops index several arrays at once; that is the shape the vectoriser wants.
#![allow(clippy::needless_range_loop)]

use super::{Expansion, Node, Rss};
use crate::math::{Mat3, Vec3};

/// The bounds of the four pairs of an expansion, with the axis each near-points bound used.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneBounds {
    /// Lower bounds on the distances (0 where the volumes may overlap).
    pub gap: [f64; 4],
    /// `axis[i][k]`: component `i` of lane `k`'s near-points axis, a unit vector in mesh 1's
    /// frame (zero where the two rectangles meet).
    pub axis: [[f64; 4]; 3],
}

type L = [f64; 4];

/// The lane kernels, portable or, on x86-64 CPUs with AVX2 and FMA, in intrinsics (chosen at
/// run time).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lanes4 {
    avx2: bool,
}

impl Lanes4 {
    /// Detects the CPU's vector width (a cached test after the first call).
    pub(crate) fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        let avx2 = std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        Self { avx2 }
    }

    /// The portable path even where AVX2 exists (for tests comparing the two).
    #[cfg(test)]
    fn baseline() -> Self {
        Self { avx2: false }
    }

    /// [`Self::bounds`] of the child pairs of an expansion (`e.a` in `nodes1`, `e.b` in
    /// `nodes2`); lane `k` bounds `e.pair(k)`.
    #[inline(always)]
    pub(crate) fn expansion_bounds(
        self,
        e: &Expansion,
        nodes1: &[Node],
        nodes2: &[Node],
        rot12: &Mat3,
        trans12: Vec3,
    ) -> LaneBounds {
        // Indexed one by one: building the references through an array map stored the two
        // u32 indices and read them back as one word, a store-forwarding stall.
        let (a0, a1) = (&nodes1[e.a[0] as usize].rss, &nodes1[e.a[1] as usize].rss);
        let (b0, b1) = (&nodes2[e.b[0] as usize].rss, &nodes2[e.b[1] as usize].rss);
        self.bounds([a0, a1], [b0, b1], rot12, trans12)
    }

    /// The largest `u . p` over the points `p` given by `f32` coordinate columns (the support
    /// function; the smallest is `-max_along(columns, -u)`), computed in `f32` (see
    /// [`super::CornerColumns::error`] for the rounding); `NEG_INFINITY` for no points.
    #[inline]
    pub(crate) fn max_along(self, columns: [&[f32]; 3], u: Vec3) -> f64 {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: needs AVX2 and FMA, which `detect` found on this CPU.
            #[allow(unsafe_code)]
            return unsafe { super::rss4_avx2::max_along(columns, u) };
        }
        max_along(columns, u)
    }

    /// Lower bounds (0 where they may overlap) on the distances of the four pairs
    /// `(a[i], b[j])` in lane `2 i + j`; `a` in mesh 1's frame, `b` in mesh 2's frame, mapped
    /// into mesh 1's by `rot12`, `trans12`. (An expansion splits one node or both, so its child
    /// pairs always have this shape, with repeats where only one side is split.)
    #[inline(always)]
    fn bounds(self, a: [&Rss; 2], b: [&Rss; 2], rot12: &Mat3, trans12: Vec3) -> LaneBounds {
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: needs AVX2 and FMA, which `detect` found on this CPU.
            #[allow(unsafe_code)]
            return unsafe { super::rss4_avx2::bounds(a, b, rot12, trans12) };
        }
        bounds_lanes(a, b, rot12, trans12)
    }
}

#[inline(always)]
fn bounds_lanes(a: [&Rss; 2], b: [&Rss; 2], rot12: &Mat3, trans12: Vec3) -> LaneBounds {
    // b's two volumes carried into mesh 1's frame once each, then spread over the lanes.
    let b0 = Rss {
        axes: *rot12 * b[0].axes,
        center: *rot12 * b[0].center + trans12,
        ..*b[0]
    };
    let b1 = Rss {
        axes: *rot12 * b[1].axes,
        center: *rot12 * b[1].center + trans12,
        ..*b[1]
    };
    rss_separation4(
        &Side4::lanes([a[0], a[0], a[1], a[1]]),
        &Side4::lanes([&b0, &b1, &b0, &b1]),
    )
}

/// One side of the four pairs, in mesh 1's frame: axes columns (x, y, normal), centre, half
/// lengths and radius per lane.
#[derive(Clone, Copy, Debug)]
struct Side4 {
    /// `axes[c][i]`: component `i` of axis `c`.
    axes: [[V; 3]; 3],
    center: [V; 3],
    half: [V; 2],
    radius: V,
}

/// One scalar of each of the four volumes, as lanes (built in registers).
#[inline(always)]
fn gather(v: &[&Rss; 4], f: impl Fn(&Rss) -> f64) -> V {
    V([f(v[0]), f(v[1]), f(v[2]), f(v[3])])
}

impl Side4 {
    /// The four volumes as lanes.
    #[inline(always)]
    fn lanes(v: [&Rss; 4]) -> Self {
        let axis = |c: usize| {
            [
                gather(&v, |r| r.axes.col(c).x),
                gather(&v, |r| r.axes.col(c).y),
                gather(&v, |r| r.axes.col(c).z),
            ]
        };
        Self {
            axes: [axis(0), axis(1), axis(2)],
            center: [
                gather(&v, |r| r.center.x),
                gather(&v, |r| r.center.y),
                gather(&v, |r| r.center.z),
            ],
            half: [
                gather(&v, |r| r.half_lengths[0]),
                gather(&v, |r| r.half_lengths[1]),
            ],
            radius: gather(&v, |r| r.radius),
        }
    }
}

/// Four lanes of `f64`; every operation is a loop over the lanes, which the compiler turns into
/// vector instructions.
#[derive(Clone, Copy, Debug)]
struct V(L);

macro_rules! lanewise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl std::ops::$trait for V {
            type Output = V;
            #[inline(always)]
            fn $method(self, o: V) -> V {
                let mut out = [0.0; 4];
                for k in 0..4 {
                    out[k] = self.0[k] $op o.0[k];
                }
                V(out)
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl V {
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> V {
        let mut out = [0.0; 4];
        for k in 0..4 {
            out[k] = f(self.0[k]);
        }
        V(out)
    }
    #[inline(always)]
    fn abs(self) -> V {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn sqrt(self) -> V {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn max(self, o: V) -> V {
        let mut out = [0.0; 4];
        for k in 0..4 {
            out[k] = if self.0[k] > o.0[k] {
                self.0[k]
            } else {
                o.0[k]
            };
        }
        V(out)
    }
    #[inline(always)]
    fn min(self, o: V) -> V {
        let mut out = [0.0; 4];
        for k in 0..4 {
            out[k] = if self.0[k] < o.0[k] {
                self.0[k]
            } else {
                o.0[k]
            };
        }
        V(out)
    }
    #[inline(always)]
    fn splat(x: f64) -> V {
        V([x; 4])
    }
}

/// Lower bounds on the distances of the four pairs `(a[k], b[k])`, both sides in mesh 1's
/// frame (0 where the volumes may overlap).
#[inline(always)]
fn rss_separation4(a: &Side4, b: &Side4) -> LaneBounds {
    let ax = |c: usize, i: usize| a.axes[c][i];
    let bx = |c: usize, i: usize| b.axes[c][i];
    let dot_ab =
        |i: usize, j: usize| ax(i, 0) * bx(j, 0) + ax(i, 1) * bx(j, 1) + ax(i, 2) * bx(j, 2);
    // r[i][j] = a_i . b_j (so b_j in a's frame is column j), t = b's centre in a's frame.
    let r = [
        [dot_ab(0, 0), dot_ab(0, 1), dot_ab(0, 2)],
        [dot_ab(1, 0), dot_ab(1, 1), dot_ab(1, 2)],
        [dot_ab(2, 0), dot_ab(2, 1), dot_ab(2, 2)],
    ];
    let d = [
        b.center[0] - a.center[0],
        b.center[1] - a.center[1],
        b.center[2] - a.center[2],
    ];
    let dot_ad = |i: usize| ax(i, 0) * d[0] + ax(i, 1) * d[1] + ax(i, 2) * d[2];
    let t = [dot_ad(0), dot_ad(1), dot_ad(2)];
    let (la0, la1) = (a.half[0], a.half[1]);
    let (lb0, lb1) = (b.half[0], b.half[1]);
    // The two normals (unit axes).
    let bt2 = r[0][2] * t[0] + r[1][2] * t[1] + r[2][2] * t[2];
    let normal_a = t[2].abs() - lb0 * r[2][0].abs() - lb1 * r[2][1].abs();
    let normal_b = bt2.abs() - la0 * r[0][2].abs() - la1 * r[1][2].abs();
    // The near-points axis: b's centre clamped to a's rectangle (pa), that point clamped to b's
    // rectangle (pb), pb clamped back to a's rectangle; u runs from there to pb (a's frame).
    let clamp = |x: V, l: V| x.max(V::splat(0.0) - l).min(l);
    let pa = [clamp(t[0], la0), clamp(t[1], la1)];
    let q = [pa[0] - t[0], pa[1] - t[1], V::splat(0.0) - t[2]];
    let in_b = |j: usize| r[0][j] * q[0] + r[1][j] * q[1] + r[2][j] * q[2];
    let pb_local = [clamp(in_b(0), lb0), clamp(in_b(1), lb1)];
    let pb = [
        t[0] + r[0][0] * pb_local[0] + r[0][1] * pb_local[1],
        t[1] + r[1][0] * pb_local[0] + r[1][1] * pb_local[1],
        t[2] + r[2][0] * pb_local[0] + r[2][1] * pb_local[1],
    ];
    let u = [pb[0] - clamp(pb[0], la0), pb[1] - clamp(pb[1], la1), pb[2]];
    let u_dot_b = |j: usize| u[0] * r[0][j] + u[1] * r[1][j] + u[2] * r[2][j];
    let gap_u = (u[0] * t[0] + u[1] * t[1] + u[2] * t[2]).abs()
        - la0 * u[0].abs()
        - la1 * u[1].abs()
        - lb0 * u_dot_b(0).abs()
        - lb1 * u_dot_b(1).abs();
    let ul2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    // gap_u scales with |u| (it is 0 for u = 0); dividing by at least sqrt(MIN_POSITIVE) can
    // only lower a bound.
    let inv = V::splat(1.0) / ul2.max(V::splat(f64::MIN_POSITIVE)).sqrt();
    let near = gap_u * inv;
    // The common perpendicular of the two long edges: e = a_x cross b_x = (0, -r20, r10) in
    // a's frame (a_x . e = b_x . e = 0, a_y . e = -r20).
    let et = r[1][0] * t[2] - r[2][0] * t[1];
    let e_dot_by = r[1][0] * r[2][1] - r[2][0] * r[1][1];
    let el2 = r[1][0] * r[1][0] + r[2][0] * r[2][0];
    let inv_e = V::splat(1.0) / el2.max(V::splat(f64::MIN_POSITIVE)).sqrt();
    let cross = (et.abs() - la1 * r[2][0].abs() - lb1 * e_dot_by.abs()) * inv_e;
    let g = normal_a.max(normal_b).max(near).max(cross);
    let world = |i: usize| (ax(0, i) * u[0] + ax(1, i) * u[1] + ax(2, i) * u[2]) * inv;
    LaneBounds {
        gap: (g - a.radius - b.radius).max(V::splat(0.0)).0,
        axis: [world(0).0, world(1).0, world(2).0],
    }
}

/// The largest `u . p` over the points `p` given by `f32` coordinate columns, in `f32` lanes
/// of eight (which the compiler vectorises).
#[inline]
fn max_along(columns: [&[f32]; 3], u: Vec3) -> f64 {
    let [x, y, z] = columns;
    let (ux, uy, uz) = (u.x as f32, u.y as f32, u.z as f32);
    let mut hi = [f32::NEG_INFINITY; 8];
    let (xs, ys, zs) = (x.chunks_exact(8), y.chunks_exact(8), z.chunks_exact(8));
    let tail = xs.remainder().len();
    for ((x, y), z) in xs.zip(ys).zip(zs) {
        for l in 0..8 {
            let v = z[l].mul_add(uz, y[l].mul_add(uy, x[l] * ux));
            hi[l] = if v > hi[l] { v } else { hi[l] };
        }
    }
    let n = x.len();
    for i in n - tail..n {
        hi[0] = hi[0].max(z[i].mul_add(uz, y[i].mul_add(uy, x[i] * ux)));
    }
    f64::from(hi.iter().fold(f32::NEG_INFINITY, |m, &v| m.max(v)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{rss_separation, RelativeRss};

    // The hierarchy's seeded test generator, with helpers for random volumes added here.
    use crate::bvh::TestRng as Lcg;

    impl Lcg {
        fn unit(&mut self) -> Vec3 {
            loop {
                let v = Vec3::new(self.next(), self.next(), self.next()) * 2.0 - Vec3::ONE;
                if v.length_squared() > 1e-3 && v.length_squared() <= 1.0 {
                    return v.normalize();
                }
            }
        }
        fn rotation(&mut self) -> Mat3 {
            let x = self.unit();
            let y = x.cross(self.unit()).normalize();
            Mat3::from_cols(x, y, x.cross(y))
        }
        /// A random RSS; some flat (radius 0), some degenerate to a segment or a ball.
        fn rss(&mut self, i: usize) -> Rss {
            let s = [1e-3, 1.0, 1e3][i % 3];
            let mut half = [self.next() * s, self.next() * s];
            if i % 5 == 0 {
                half[1] = 0.0;
            }
            if i % 7 == 0 {
                half = [0.0, 0.0];
            }
            Rss {
                axes: self.rotation(),
                center: (Vec3::new(self.next(), self.next(), self.next()) - 0.5) * 4.0 * s,
                half_lengths: half,
                radius: if i % 4 == 0 {
                    0.0
                } else {
                    self.next() * 0.5 * s
                },
            }
        }
        /// A random point of `rss`.
        fn inside(&mut self, rss: &Rss) -> Vec3 {
            let x = (2.0 * self.next() - 1.0) * rss.half_lengths[0];
            let y = (2.0 * self.next() - 1.0) * rss.half_lengths[1];
            let ball = self.unit() * self.next().cbrt() * rss.radius;
            rss.center + rss.axes * Vec3::new(x, y, 0.0) + ball
        }
    }

    /// Same axes, same value as the one-pair bound (without its early exit), on both paths.
    #[test]
    fn lanes_match_the_one_pair_bound() {
        let mut g = Lcg(11);
        for i in 0..4000 {
            let a: [Rss; 2] = [0, 1].map(|k| g.rss(i + k));
            let b: [Rss; 2] = [0, 1].map(|k| g.rss(i + 2 * k + 1));
            let (rot12, trans12) = (g.rotation(), g.unit() * g.next() * 3.0);
            let detected = Lanes4::detect().bounds(a.each_ref(), b.each_ref(), &rot12, trans12);
            let plain = Lanes4::baseline().bounds(a.each_ref(), b.each_ref(), &rot12, trans12);
            for k in 0..4 {
                let (ak, bk) = (&a[k / 2], &b[k % 2]);
                let rel = RelativeRss::new(ak, bk, &rot12, trans12);
                let (one, _) = rss_separation(ak, bk, &rel, f64::INFINITY);
                let scale = 1.0 + ak.center.length() + bk.center.length() + trans12.length();
                for (path, lanes) in [("portable", &plain), ("detected", &detected)] {
                    assert!(
                        (one - lanes.gap[k]).abs() <= 1e-12 * scale,
                        "{path} lane {k}: {} vs {one}",
                        lanes.gap[k]
                    );
                }
                // The axes agree and are unit (or zero, where the rectangles meet).
                let axis = |l: &LaneBounds| Vec3::new(l.axis[0][k], l.axis[1][k], l.axis[2][k]);
                let (u, w) = (axis(&plain), axis(&detected));
                assert!((u - w).length() <= 1e-9, "axes differ: {u} vs {w}");
                assert!(
                    u == Vec3::ZERO || (u.length() - 1.0).abs() <= 1e-12,
                    "axis not unit: {u}"
                );
            }
        }
    }

    /// Every bound is at most the distance between sampled points of the two volumes, and is
    /// attained up to the sampling for separated balls.
    #[test]
    fn lanes_are_lower_bounds() {
        let mut g = Lcg(12);
        for i in 0..3000 {
            let a: [Rss; 2] = [0, 1].map(|k| g.rss(i + k));
            let b: [Rss; 2] = [0, 1].map(|k| g.rss(i + 3 * k + 2));
            let (rot12, trans12) = (g.rotation(), g.unit() * g.next() * 5.0);
            let lb = Lanes4::detect()
                .bounds(a.each_ref(), b.each_ref(), &rot12, trans12)
                .gap;
            for k in 0..4 {
                let (ak, bk) = (&a[k / 2], &b[k % 2]);
                let scale = 1.0 + ak.center.length() + bk.center.length() + trans12.length();
                for _ in 0..40 {
                    let p = g.inside(ak);
                    let q = rot12 * g.inside(bk) + trans12;
                    assert!(
                        lb[k] <= (p - q).length() + 1e-12 * scale,
                        "lane {k} not a bound"
                    );
                }
            }
        }
        // Two balls: the bound is exact.
        let ball = |c: Vec3| Rss {
            axes: Mat3::IDENTITY,
            center: c,
            half_lengths: [0.0, 0.0],
            radius: 0.5,
        };
        let (a, b) = (ball(Vec3::ZERO), ball(Vec3::new(3.0, 4.0, 0.0)));
        let lb = Lanes4::detect()
            .bounds([&a; 2], [&b; 2], &Mat3::IDENTITY, Vec3::ZERO)
            .gap;
        assert!((lb[0] - 4.0).abs() < 1e-12, "{lb:?}");
    }

    /// A rectangle and a ball: the near-points axis runs from the rectangle's closest point, so
    /// the bound is the exact distance, whatever the rotation and offset.
    #[test]
    fn rectangle_and_ball_are_exact() {
        let mut g = Lcg(13);
        for _ in 0..2000 {
            let rect = Rss {
                axes: g.rotation(),
                center: g.unit(),
                half_lengths: [g.next() * 2.0, g.next()],
                radius: 0.0,
            };
            let ball = Rss {
                axes: g.rotation(),
                center: Vec3::ZERO,
                half_lengths: [0.0, 0.0],
                radius: 0.25 * g.next(),
            };
            let (rot12, trans12) = (g.rotation(), g.unit() * (1.0 + 4.0 * g.next()));
            // The ball's centre in the rectangle's frame, and its distance to the rectangle.
            let c = rect.axes.transpose() * (trans12 - rect.center);
            let dx = (c.x.abs() - rect.half_lengths[0]).max(0.0);
            let dy = (c.y.abs() - rect.half_lengths[1]).max(0.0);
            let exact = ((dx * dx + dy * dy + c.z * c.z).sqrt() - ball.radius).max(0.0);
            let lb = Lanes4::detect()
                .bounds([&rect; 2], [&ball; 2], &rot12, trans12)
                .gap;
            assert!(
                (lb[0] - exact).abs() <= 1e-12 * (1.0 + exact),
                "{} vs {exact}",
                lb[0]
            );
        }
    }

    /// Two long thin rectangles crossing (slivers), in general position: long edges along
    /// random directions, planes turned at random about them, the closest points of the long
    /// axes inside both and away from the centres. Their distance is within the widths of the
    /// long axes' distance `h`, and the bound reaches it on both lane paths and in the one-pair
    /// bound. The near-points axis and the normals alone gave a fraction of it: the bound was
    /// 0 on most sliver pairs of a 150:1 knot whose triangles were 15 times the minimum apart.
    #[test]
    fn crossing_slivers_are_exact() {
        let mut g = Lcg(15);
        for i in 0..1000 {
            let long = [1.0, 50.0][i % 2];
            let h = long * (1e-3 + 0.1 * g.next());
            let (ax, bx) = (g.unit(), g.unit());
            let Some(n) = ax.cross(bx).try_normalize() else {
                continue;
            };
            if ax.cross(bx).length() < 0.02 {
                continue;
            }
            // A plane through each long axis, turned at random about it.
            let plane = |x: Vec3, r: Vec3| {
                let y = x.cross(r).normalize();
                Mat3::from_cols(x, y, x.cross(y))
            };
            let (fa, fb) = (plane(ax, g.unit()), plane(bx, g.unit()));
            let width = 1e-6 * long;
            // Closest points of the two axes at up to 0.8 of the half length from each centre.
            let pa = Vec3::new(g.next(), g.next(), g.next()) * long;
            let pb = pa + n * h;
            let (sa, sb) = (0.8 * (2.0 * g.next() - 1.0), 0.8 * (2.0 * g.next() - 1.0));
            let rect = |axes: Mat3, centre: Vec3| Rss {
                axes,
                center: centre,
                half_lengths: [long, width],
                radius: 0.0,
            };
            let a = rect(fa, pa - ax * (sa * long));
            let b = rect(fb, pb - bx * (sb * long));
            let reaches = |lb: f64| lb <= h * (1.0 + 1e-9) && lb >= h * (1.0 - 1e-9) - 4.0 * width;
            for lanes in [Lanes4::baseline(), Lanes4::detect()] {
                let lb = lanes
                    .bounds([&a; 2], [&b; 2], &Mat3::IDENTITY, Vec3::ZERO)
                    .gap;
                assert!(reaches(lb[0]), "{} vs {h}", lb[0]);
            }
            let rel = RelativeRss::new(&a, &b, &Mat3::IDENTITY, Vec3::ZERO);
            let (one, _) = rss_separation(&a, &b, &rel, f64::INFINITY);
            assert!(reaches(one), "one pair: {one} vs {h}");
        }
    }

    /// Both paths of the projection give the extent found by a plain loop, for every length
    /// (the 8-lane body and the tail).
    #[test]
    fn max_along_matches_a_plain_loop() {
        let mut g = Lcg(14);
        for n in 1..40 {
            let cols: [Vec<f32>; 3] =
                [0, 1, 2].map(|_| (0..n).map(|_| ((g.next() - 0.5) * 1e3) as f32).collect());
            let u = g.unit();
            let dots: Vec<f64> = (0..n)
                .map(|i| {
                    let p = Vec3::new(cols[0][i].into(), cols[1][i].into(), cols[2][i].into());
                    p.dot(u)
                })
                .collect();
            let lo = dots.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = dots.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let columns = [&cols[0][..], &cols[1][..], &cols[2][..]];
            // Within the rounding bound of `CornerColumns::error` (coordinates up to 866 from 0).
            let err = 4e-7 * 866.0;
            for lanes in [Lanes4::baseline(), Lanes4::detect()] {
                let (l, h) = (-lanes.max_along(columns, -u), lanes.max_along(columns, u));
                assert!((l - lo).abs() <= err && (h - hi).abs() <= err, "n = {n}");
            }
        }
    }

    /// A projection from the `f32` columns, moved back by the origin, is within the columns'
    /// stated error of the projection of the `f64` corners, at small, large and off-centre
    /// scales; past `1e30` there are no columns.
    #[test]
    fn corner_columns_stay_within_their_error() {
        use crate::bvh::CornerColumns;
        let mut g = Lcg(15);
        for (scale, offset) in [
            (1e-3, 0.0),
            (1.0, 0.0),
            (1e3, 0.0),
            (1e-3, 1e4),
            (1.0, -1e4),
        ] {
            let corners: Vec<[Vec3; 3]> = (0..50)
                .map(|_| {
                    [0, 1, 2].map(|_| {
                        let p = Vec3::new(g.next(), g.next(), g.next()) - 0.5;
                        p * scale + Vec3::splat(offset)
                    })
                })
                .collect();
            let origin = corners[7][1];
            let c = CornerColumns::new(&corners, origin);
            assert!(c.is_some(), "no columns at scale {scale}");
            let Some(c) = c else { return };
            for _ in 0..50 {
                let u = g.unit();
                let dots = corners.iter().flatten().map(|p| u.dot(*p));
                let lo = dots.clone().fold(f64::INFINITY, f64::min);
                let hi = dots.fold(f64::NEG_INFINITY, f64::max);
                for lanes in [Lanes4::baseline(), Lanes4::detect()] {
                    let columns = c.columns(0..corners.len());
                    let (l, h) = (-lanes.max_along(columns, -u), lanes.max_along(columns, u));
                    let (l, h) = (l + u.dot(origin), h + u.dot(origin));
                    // The f64 sums carry their own rounding (the search's slack covers it).
                    let slack = 1e-15 * (offset.abs() + scale);
                    assert!((l - lo).abs() <= c.error + slack, "{l} vs {lo}");
                    assert!((h - hi).abs() <= c.error + slack, "{h} vs {hi}");
                }
            }
        }
        let far = [[Vec3::ZERO, Vec3::X, Vec3::splat(1e31)]];
        assert!(CornerColumns::new(&far, Vec3::ZERO).is_none());
    }

    /// The points kept for a subtree (distinct vertices or corners) are exactly its corners'
    /// positions, and the distinct vertices are used where they save corners: on a mesh that
    /// shares its vertices by index, and on the same mesh written as a soup (each triangle its
    /// own three vertices, as many files store them), where only positions tell them apart.
    #[test]
    fn subtree_points_are_its_corners() {
        use crate::bvh::LARGE_PROJECT_MAX;
        use std::collections::HashSet;
        let knot = crate::mesh::torus_knot(60, 8).unwrap_or_else(|e| unreachable!("{e}"));
        let soup_vertices: Vec<Vec3> = knot
            .triangles()
            .iter()
            .flat_map(|t| t.map(|i| knot.vertices()[i as usize]))
            .collect();
        let soup_triangles = (0..knot.triangles().len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let soup = crate::TriMesh::new(soup_vertices, soup_triangles).expect("soup");
        for mesh in [&knot, &soup] {
            let bvh = mesh.bvh();
            let c = bvh.corner_columns();
            assert!(c.is_some(), "no columns");
            let Some(c) = c else { return };
            let key = |cols: [&[f32]; 3], i: usize| {
                [cols[0][i], cols[1][i], cols[2][i]].map(f32::to_bits)
            };
            let mut used = 0;
            for (i, node) in bvh.nodes().iter().enumerate() {
                if node.leaf_range().len() > LARGE_PROJECT_MAX {
                    continue;
                }
                let corners = c.columns(node.leaf_range());
                let points = c.points(i as u32, node);
                let want: HashSet<_> = (0..corners[0].len()).map(|k| key(corners, k)).collect();
                let got: HashSet<_> = (0..points[0].len()).map(|k| key(points, k)).collect();
                assert_eq!(want, got, "node {i}");
                used += usize::from(points[0].len() < corners[0].len());
            }
            assert!(used > 10, "distinct vertices used for {used} subtrees");
        }
    }

    /// Vertices at one position share the first index there, whatever their order; others
    /// keep their own; `-0.0` and `0.0` are one position.
    #[test]
    fn same_position_groups_equal_vertices() {
        let v = [
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-0.0, 0.0, -0.0),
            Vec3::new(1.0, 2.0, 3.0 + f64::EPSILON * 4.0),
        ];
        assert_eq!(crate::bvh::same_position(&v), vec![0, 1, 0, 1, 4]);
    }
}
