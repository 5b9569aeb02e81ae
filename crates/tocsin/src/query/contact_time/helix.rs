//! Separation certificates that a screw motion cannot change: a body turning about an axis
//! fixed in the world while it slides along it (a bolt screwed into its nut) past a still body.
//!
//! The rotation certificates ([`super::shells`]) bound a pair by the ranges of the invariants of
//! a turn (distance `rho` from the axis, axial coordinate `z`), widening `z` by the slide over
//! the window; along a thread the slide is as large as the clearance after a few degrees, and
//! a bolt screwed half a turn into its nut at 0.5% clearance took 46 s. A screw that advances
//! `k` per radian keeps, for each point of the turning body, its `rho` and its phase `zeta = z -
//! k phi` (`phi` its angle about the axis; `zeta` is defined modulo the pitch `P = 2 pi |k|`).
//!
//! For a turning point `p` and a still point `q` whose angles differ by `Delta = D0 + 2 pi m`,
//! `D0` in `[-pi, pi]`: `|p - q|^2 = (rho_p - rho_q)^2 + 2 rho_p rho_q (1 - cos D0) + (z_p -
//! z_q)^2`, `z_p - z_q = (zeta_p - zeta_q + m' P) + k D0` for an integer `m'`, and `1 - cos D0
//! >= 2 D0^2 / pi^2`. With `a = 4 rho_p rho_q / pi^2`, the smallest of `a x^2 + (c + k x)^2` over
//! all `x` is `c^2 a / (a + k^2)`, so
//!
//! `|p - q|^2 >= (rho_p - rho_q)^2 + s^2 (zeta_p - zeta_q + m' P)^2`, `s^2 = a / (a + k^2)`,
//!
//! whatever the screw has turned: the distance between the points' images in the plane of
//! `(rho, s zeta)`, on the nearest branch of the phase. Where both points are at least one
//! pitch from the axis, `a >= 16 k^2` and `s >= sqrt(16 / 17)`, the `s` this module takes. As in
//! the meridian plane of a turn, any unit direction `n` there gives a lower bound: a turning
//! set and a still set whose values of `h = n.rho rho + n.eta s zeta` are apart by `g`, on one
//! branch, stay `g` apart, and on any other branch the phases alone are apart by at least the
//! pitch less the phases' spread.
//!
//! Ranges over a set (a triangle or a volume) come from a linear form about a radial unit `u`
//! at its centre (`t = dir x u` across it, the set at least `a_lo > 0` along `u`): `rho` lies
//! between `u . x` and that plus `eps` (as in the meridian plane), and the angle `phi = phi_u +
//! atan(b / a)` (`a = u . x`, `b = t . x`) is within `E = |b| |k_c - a| / (a k_c) + |b / a|^3 /
//! 3` of `phi_u + b / k_c` (`k_c` the centre's distance from the axis; `|atan y - y| <= |y|^3 /
//! 3`). Over a triangle the linear form's extremes are at its corners, as are `eps` and the
//! largest `|b|` and `|k_c - a|` (convex functions); over a volume they are its centre's value
//! plus or minus its extent along the form.

use super::shells::{mean_direction, Range};
use crate::bvh::Rss;
use crate::math::{Pose, Vec3};
use crate::motion::FixedAxis;

/// The certificate's data for one query: the axis and phase in the world at `t = 0`.
pub(crate) struct Helix {
    /// A point of the axis (the turning body's axis point at `t = 0`), world frame.
    point: Vec3,
    /// Unit direction of the axis, world frame (the sense of the rotation).
    dir: Vec3,
    /// World directions across the axis from which angles are measured (`e2 = dir x e1`).
    e1: Vec3,
    e2: Vec3,
    /// Advance along `dir` per radian turned (signed).
    k: f64,
    /// The phase's period, `2 pi |k|`.
    pitch: f64,
    /// How far the turning body slides along `dir` over the whole motion (signed).
    travel: f64,
    /// The phase's scale in the metric, valid for points at least `pitch` from the axis.
    s: f64,
    /// The turning body's pose at `t = 0`, and the still body's.
    start: Pose,
    still: Pose,
}

/// A unit direction `(rho, eta)` in the plane of `(rho, s zeta)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Direction {
    rho: f64,
    eta: f64,
}

/// A set's range of `h` and of its phase `zeta`, on one branch of the phase.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ranges {
    h: Range,
    zeta: Range,
}

impl Ranges {
    /// The width of the range of `h`.
    pub(crate) fn width(&self) -> f64 {
        self.h.hi - self.h.lo
    }

    /// The midpoint of the phase's range.
    fn zeta_mid(&self) -> f64 {
        0.5 * (self.zeta.lo + self.zeta.hi)
    }

    /// The same set on the branch `shift` further along the phase.
    fn shifted(self, shift: f64, n: Direction, s: f64) -> Self {
        let dh = n.eta * s * shift;
        Self {
            h: Range {
                lo: self.h.lo + dh,
                hi: self.h.hi + dh,
            },
            zeta: Range {
                lo: self.zeta.lo + shift,
                hi: self.zeta.hi + shift,
            },
        }
    }

    /// The smallest range holding both (on one branch).
    fn union(self, other: Self) -> Self {
        let join = |a: Range, b: Range| Range {
            lo: a.lo.min(b.lo),
            hi: a.hi.max(b.hi),
        };
        Self {
            h: join(self.h, other.h),
            zeta: join(self.zeta, other.zeta),
        }
    }
}

/// A vertex as [`Helix::image`] needs it ([`Helix::vertex`]); the default is a placeholder for
/// a vertex no image needs.
#[derive(Clone, Copy, Default)]
pub(crate) struct Corner {
    perp: Vec3,
    /// `|perp|`, its distance from the axis.
    rho: f64,
    z: f64,
    phi: f64,
}

/// A set's linear frame about the radial unit at its centre `c` (relative to the axis point).
struct Local {
    u: Vec3,
    t: Vec3,
    /// The centre's distance from the axis.
    k_c: f64,
    /// The centre's axial coordinate and the angle of `u`.
    z_c: f64,
    phi_u: f64,
}

impl Helix {
    /// The certificate for a screw about `axis` that slides along it (`along != 0`), the
    /// turning body at `start` at `t = 0` and the still one at `still`; `None` for a turn that
    /// does not slide.
    pub(crate) fn new(axis: &FixedAxis, start: Pose, still: Pose) -> Option<Self> {
        let k = axis.along / axis.angular_speed;
        if !k.is_finite() || k == 0.0 {
            return None;
        }
        let dir = axis.world_dir;
        let helper = if dir.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
        let e1 = dir.cross(helper).normalize();
        Some(Self {
            point: axis.world_point,
            dir,
            e1,
            e2: dir.cross(e1),
            k,
            pitch: std::f64::consts::TAU * k.abs(),
            travel: axis.along,
            s: (16.0f64 / 17.0).sqrt(),
            start,
            still,
        })
    }

    /// The turning body's pose at `t = 0`.
    pub(crate) fn start(&self) -> &Pose {
        &self.start
    }

    /// The still body's pose.
    pub(crate) fn still_pose(&self) -> &Pose {
        &self.still
    }

    /// How far the turning body slides along the axis over the whole motion (signed).
    pub(crate) fn travel(&self) -> f64 {
        self.travel
    }

    /// The frame about the world point `c`; `None` on the axis.
    fn local(&self, c: Vec3) -> Option<Local> {
        let rel = c - self.point;
        let z_c = rel.dot(self.dir);
        let perp = rel - self.dir * z_c;
        let k_c = perp.length();
        if k_c.is_nan() || k_c <= 0.0 {
            return None;
        }
        let u = perp / k_c;
        Some(Local {
            u,
            t: self.dir.cross(u),
            k_c,
            z_c,
            phi_u: u.dot(self.e2).atan2(u.dot(self.e1)),
        })
    }

    /// The direction in the plane of `(rho, s zeta)` of the unit normal `nrm` of a surface at
    /// the world point `x`: a surface that the screw maps onto itself is a curve `F(rho, zeta)
    /// = 0` there, its normal `F_rho u + F_zeta (dir - k t / rho)`, so `nrm . u` and `nrm .
    /// dir` give `F`'s gradient, `(F_rho, F_zeta / s)` in the scaled plane. `None` on the axis
    /// or where the normal is mostly across both (`|(nrm . u, nrm . dir)| <= 1/2`).
    pub(crate) fn direction(&self, nrm: Vec3, x: Vec3) -> Option<Direction> {
        let l = self.local(x)?;
        let (rho, z) = (nrm.dot(l.u), nrm.dot(self.dir));
        if rho.hypot(z) <= 0.5 {
            return None;
        }
        let eta = z / self.s;
        let len = rho.hypot(eta);
        Some(Direction {
            rho: rho / len,
            eta: eta / len,
        })
    }

    /// A triangle's ranges (world corners); `None` where it reaches within a pitch of the axis.
    pub(crate) fn triangle(&self, tri: &[Vec3; 3], n: Direction) -> Option<Ranges> {
        let l = self.local((tri[0] + tri[1] + tri[2]) / 3.0)?;
        let (mut a_lo, mut eps, mut b_max, mut dev) = (f64::INFINITY, 0.0f64, 0.0f64, 0.0f64);
        let mut lin = Range::EMPTY;
        let mut zeta = lin;
        for &x in tri {
            let rel = x - self.point;
            let z = rel.dot(self.dir);
            let perp = rel - self.dir * z;
            let (a, b) = (perp.dot(l.u), perp.dot(l.t));
            a_lo = a_lo.min(a);
            eps = eps.max(perp.length() - a);
            b_max = b_max.max(b.abs());
            dev = dev.max((l.k_c - a).abs());
            let zl = z - self.k * (l.phi_u + b / l.k_c);
            let hl = n.rho * a + n.eta * self.s * zl;
            zeta = zeta.with(zl);
            lin = lin.with(hl);
        }
        self.finish(n, (lin, zeta), (a_lo, eps), (b_max, dev, l.k_c))
    }

    /// A volume's ranges (centre, axes, half lengths and radius in the world); `None` where it
    /// reaches within a pitch of the axis.
    pub(crate) fn volume(
        &self,
        c: Vec3,
        (e0, e1): (Vec3, Vec3),
        half: [f64; 2],
        r: f64,
        n: Direction,
    ) -> Option<Ranges> {
        let l = self.local(c)?;
        let ext = |w: Vec3| half[0] * e0.dot(w).abs() + half[1] * e1.dot(w).abs() + r * w.length();
        let (eu, et) = (ext(l.u), ext(l.t));
        let a_lo = l.k_c - eu;
        let rho_hi = ((l.k_c + eu) * (l.k_c + eu) + et * et).sqrt();
        let mut eps = rho_hi - a_lo;
        if a_lo > 0.0 {
            eps = eps.min(et * et / (2.0 * a_lo));
        }
        // The phase's linear form `z - k (phi_u + t . x / k_c)` and `h`'s, at the centre and
        // along their gradients.
        let g_zeta = self.dir - l.t * (self.k / l.k_c);
        let z0 = l.z_c - self.k * l.phi_u;
        let (ez, eh) = (ext(g_zeta), ext(l.u * n.rho + g_zeta * (n.eta * self.s)));
        let h0 = n.rho * l.k_c + n.eta * self.s * z0;
        let lin = Range {
            lo: h0 - eh,
            hi: h0 + eh,
        };
        let zeta = Range {
            lo: z0 - ez,
            hi: z0 + ez,
        };
        self.finish(n, (lin, zeta), (a_lo, eps), (et, eu, l.k_c))
    }

    /// A set's ranges from its linear forms' ranges (`lin` for `h`, `zeta`), its least
    /// distance along `u` and `rho`'s excess over it, and for the angle's error the largest
    /// `|b|` and `|k_c - a|` and `k_c`.
    fn finish(
        &self,
        n: Direction,
        (lin, zeta): (Range, Range),
        (a_lo, eps): (f64, f64),
        (b_max, dev, k_c): (f64, f64, f64),
    ) -> Option<Ranges> {
        // At least a pitch from the axis (for `s`); this also keeps `a > 0` over the set.
        if a_lo.is_nan() || a_lo < self.pitch {
            return None;
        }
        let y = b_max / a_lo;
        let angle = b_max * dev / (a_lo * k_c) + y * y * y / 3.0;
        let zeta_err = self.k.abs() * angle;
        let h_err = (n.eta * self.s).abs() * zeta_err;
        Some(Ranges {
            h: Range {
                lo: lin.lo + (n.rho * eps).min(0.0) - h_err,
                hi: lin.hi + (n.rho * eps).max(0.0) + h_err,
            },
            zeta: Range {
                lo: zeta.lo - zeta_err,
                hi: zeta.hi + zeta_err,
            },
        })
    }

    /// A vertex's part across the axis, its axial coordinate and its angle about the axis (world
    /// point `x`): what [`Self::image`] needs of each corner, worked out once per vertex.
    pub(crate) fn vertex(&self, x: Vec3) -> Corner {
        let z = self.axial(x);
        let perp = x - self.point - self.dir * z;
        Corner {
            perp,
            rho: perp.length(),
            z,
            phi: perp.dot(self.e2).atan2(perp.dot(self.e1)),
        }
    }

    /// The world point `x`'s axial coordinate (from the axis point), as [`Self::vertex`] has it.
    pub(crate) fn axial(&self, x: Vec3) -> f64 {
        (x - self.point).dot(self.dir)
    }

    /// The triangle's image in the plane of `(rho, s zeta)`, from its corners
    /// ([`Self::vertex`]): its corners' images, their angles taken on the first corner's branch
    /// and the phase's branch put where the centroid's is in `[0, P)`, and how far the image of
    /// any of its points can be from the flat triangle they span (`rho` within `eps` of its
    /// interpolation, both lying between the tangent form and `eps` above it; the phase within
    /// twice the angle's error `E`, the forms being linear). `None` where it reaches within a
    /// pitch of the axis.
    pub(crate) fn image(&self, corners: [&Corner; 3]) -> Option<([[f64; 2]; 3], f64)> {
        let cp = (corners[0].perp + corners[1].perp + corners[2].perp) / 3.0;
        let k_c = cp.length();
        if k_c.is_nan() || k_c < self.pitch {
            return None;
        }
        let u = cp / k_c;
        let t = self.dir.cross(u);
        let (mut a_lo, mut eps, mut b_max, mut dev) = (f64::INFINITY, 0.0f64, 0.0f64, 0.0f64);
        let mut out = [[0.0; 2]; 3];
        let tau = std::f64::consts::TAU;
        for (o, c) in out.iter_mut().zip(corners) {
            let (a, b) = (c.perp.dot(u), c.perp.dot(t));
            a_lo = a_lo.min(a);
            eps = eps.max(c.rho - a);
            b_max = b_max.max(b.abs());
            dev = dev.max((k_c - a).abs());
            // The angle on the first corner's branch: both angles are in `[-pi, pi]`, so the
            // whole turns between them are -1, 0 or 1 (never half a turn apart, the triangle
            // being a pitch from the axis).
            let apart = corners[0].phi - c.phi;
            let phi = if apart >= std::f64::consts::PI {
                c.phi + tau
            } else if apart <= -std::f64::consts::PI {
                c.phi - tau
            } else {
                c.phi
            };
            *o = [c.rho, c.z - self.k * phi];
        }
        if a_lo.is_nan() || a_lo < self.pitch {
            return None;
        }
        let y = b_max / a_lo;
        let angle = b_max * dev / (a_lo * k_c) + y * y * y / 3.0;
        let centroid = (out[0][1] + out[1][1] + out[2][1]) / 3.0;
        let shift = -(centroid / self.pitch).floor() * self.pitch;
        for o in &mut out {
            o[1] = self.s * (o[1] + shift);
        }
        let across = self.s * 2.0 * self.k.abs() * angle;
        let margin = (eps * eps + across * across).sqrt();
        margin.is_finite().then_some((out, margin))
    }

    /// The period of the phase in the plane of `(rho, s zeta)`: `s P`.
    pub(crate) fn period(&self) -> f64 {
        self.s * self.pitch
    }

    /// The union of the triangles' ranges (world corners), each moved to the first one's branch
    /// of the phase; `None` where one has none or the phases spread over half a pitch.
    pub(crate) fn triangles(
        &self,
        tris: impl Iterator<Item = [Vec3; 3]>,
        n: Direction,
    ) -> Option<Ranges> {
        let mut all: Option<Ranges> = None;
        for tri in tris {
            let r = self.triangle(&tri, n)?;
            all = Some(match all {
                None => r,
                Some(a) => a.union(self.on_branch_of(r, &a, n)),
            });
        }
        let all = all?;
        (all.zeta.hi - all.zeta.lo <= 0.5 * self.pitch).then_some(all)
    }

    /// `r` moved by whole pitches to the branch nearest `of`'s.
    fn on_branch_of(&self, r: Ranges, of: &Ranges, n: Direction) -> Ranges {
        let m = ((of.zeta_mid() - r.zeta_mid()) / self.pitch).round();
        r.shifted(m * self.pitch, n, self.s)
    }

    /// A lower bound on the distance between the turning set and the still set, over the whole
    /// motion, from their ranges in the direction `n` ([`Self`]'s docs): the gap between
    /// their `h` ranges on the nearest branch, or, on any other, the phases' distance.
    pub(crate) fn gap(&self, turning: &Ranges, still: &Ranges, n: Direction) -> f64 {
        let still = self.on_branch_of(*still, turning, n);
        let on_branch = turning.h.gap(still.h);
        let spread = (still.zeta.lo - turning.zeta.hi)
            .abs()
            .max((still.zeta.hi - turning.zeta.lo).abs());
        on_branch.min(self.s * (self.pitch - spread)).max(0.0)
    }

    /// The mean of the triangles' (world corners) directions, each turned to agree with the
    /// first; `None` where they disagree (the mean under half as long as their count).
    pub(crate) fn mean_direction(
        &self,
        tris: impl Iterator<Item = [Vec3; 3]>,
    ) -> Option<Direction> {
        let dirs = tris.map(|tri| {
            let nrm = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
            let d = self.direction(nrm, (tri[0] + tri[1] + tri[2]) / 3.0)?;
            Some([d.rho, d.eta])
        });
        mean_direction(dirs).map(|[rho, eta]| Direction { rho, eta })
    }

    /// The turning volume `a` (its body frame) against the still volume `b` (its body frame).
    pub(crate) fn volumes(&self, turning: &Rss, still: &Rss) -> f64 {
        let (c, axes) = (
            self.start.transform_point(turning.center),
            self.start.rotation * turning.axes,
        );
        let Some(n) = self.direction(axes.z_axis, c) else {
            return 0.0;
        };
        let rt = self.volume(
            c,
            (axes.x_axis, axes.y_axis),
            turning.half_lengths,
            turning.radius,
            n,
        );
        self.against_volume(rt, still, n)
    }

    /// A turning set's ranges (direction `n`) against the still volume `b` (its body frame).
    pub(crate) fn against_volume(&self, turning: Option<Ranges>, still: &Rss, n: Direction) -> f64 {
        match (turning, self.still_volume(still, n)) {
            (Some(rt), Some(rs)) => self.gap(&rt, &rs, n),
            _ => 0.0,
        }
    }

    /// The still volume's ranges (its body frame) in the direction `n`.
    pub(crate) fn still_volume(&self, still: &Rss, n: Direction) -> Option<Ranges> {
        let (c, axes) = (
            self.still.transform_point(still.center),
            self.still.rotation * still.axes,
        );
        self.volume(
            c,
            (axes.x_axis, axes.y_axis),
            still.half_lengths,
            still.radius,
            n,
        )
    }

    /// A lower bound on the distance between the turning triangle `turning` and the still
    /// triangle `still` (each in its body frame) over the whole motion. Beyond `need` it stops
    /// refining.
    pub(crate) fn triangle_pair(&self, turning: &[Vec3; 3], still: &[Vec3; 3], need: f64) -> f64 {
        let (a, b) = (
            turning.map(|p| self.start.transform_point(p)),
            still.map(|p| self.still.transform_point(p)),
        );
        let nrm = (a[1] - a[0]).cross(a[2] - a[0]).normalize_or_zero();
        let (ca, cb) = ((a[0] + a[1] + a[2]) / 3.0, (b[0] + b[1] + b[2]) / 3.0);
        let bound = |n: Direction| match (self.triangle(&a, n), self.triangle(&b, n)) {
            (Some(ra), Some(rb)) => self.gap(&ra, &rb, n),
            _ => 0.0,
        };
        let across = self.direction(nrm, ca).map_or(0.0, bound);
        if across > need {
            return across;
        }
        // Farther apart along a curved profile than its curvature allows one direction to
        // separate (a thread's crest): the direction between their centroids' images.
        across.max(self.between(ca, cb).map_or(0.0, bound))
    }

    /// The unit direction from the image of the world point `a` to that of `b` in the plane of
    /// `(rho, s zeta)`, on the nearest branch of the phase; `None` where they coincide.
    pub(crate) fn between(&self, a: Vec3, b: Vec3) -> Option<Direction> {
        let image = |x: Vec3| {
            let c = self.vertex(x);
            (c.rho, c.z - self.k * c.phi)
        };
        let ((ra, za), (rb, zb)) = (image(a), image(b));
        let mut dz = zb - za;
        dz -= (dz / self.pitch).round() * self.pitch;
        let (rho, eta) = (rb - ra, self.s * dz);
        let len = rho.hypot(eta);
        (len > 0.0).then(|| Direction {
            rho: rho / len,
            eta: eta / len,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::sampling::{rss_point, unit};
    use crate::motion::Motion;
    use crate::query::contact_time::test_support::{assert_below_sampled, point_on};
    use crate::query::distance::distance_triangle_triangle;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random screw (axis through a random point, up to 6 radians, advancing up to 0.3 per
    /// radian either way) and its certificate against a still body at a random pose.
    fn random_helix(rng: &mut ChaCha8Rng) -> (Motion, Pose, Helix) {
        let dir = unit(rng);
        let point = unit(rng) * rng.random_range(0.0..2.0);
        let angle = rng.random_range(0.5..6.0);
        let k = rng.random_range(0.02..0.3) * if rng.random::<bool>() { 1.0 } else { -1.0 };
        let start = Pose::from_axis_angle(unit(rng), rng.random_range(0.0..3.0), unit(rng));
        let turn = Pose::from_axis_angle(dir, angle, Vec3::ZERO);
        // The screw about the line through `point` along `dir`, applied after `start`.
        let end = Pose {
            rotation: turn.rotation * start.rotation,
            translation: point + turn.rotation * (start.translation - point) + dir * (k * angle),
        };
        let motion = Motion::screw(start, end).expect("screw");
        let still = Pose::from_axis_angle(unit(rng), rng.random_range(0.0..3.0), unit(rng));
        let axis = motion.fixed_axis().expect("a fixed axis");
        let helix = Helix::new(&axis, motion.start(), still).expect("a helix");
        (motion, still, helix)
    }

    /// A random triangle a few units from the axis of `h`, `size` across.
    fn triangle_near(rng: &mut ChaCha8Rng, h: &Helix, size: f64) -> [Vec3; 3] {
        let radial = unit(rng).cross(h.dir).normalize();
        let centre =
            h.point + radial * rng.random_range(0.5..3.0) + h.dir * rng.random_range(-1.0..1.0);
        [0; 3].map(|_| centre + unit(rng) * size * rng.random::<f64>())
    }

    /// The exact invariants of points sampled on random triangles lie within the image's
    /// margin of its flat triangle, on the nearest branch of the phase.
    #[test]
    fn images_hold_their_triangles_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut imaged = 0;
        for case in 0..300 {
            let (_, _, h) = random_helix(&mut rng);
            let tri = triangle_near(&mut rng, &h, [0.01, 0.1, 0.5][case % 3]);
            let corners = tri.map(|x| h.vertex(x));
            let Some((image, margin)) = h.image([&corners[0], &corners[1], &corners[2]]) else {
                continue;
            };
            imaged += 1;
            let flat = image.map(|p| Vec3::new(p[0], p[1], 0.0));
            // The image's branch: the phase continued from its first corner's.
            let tau = std::f64::consts::TAU;
            let continued = |x: Vec3| {
                let c = h.vertex(x);
                let phi = c.phi + ((corners[0].phi - c.phi) / tau).round() * tau;
                (c.perp.length(), c.z - h.k * phi)
            };
            let shift = image[0][1] / h.s - continued(tri[0]).1;
            for _ in 0..100 {
                let x = point_on(&mut rng, &tri);
                let (rho, zeta) = continued(x);
                let p = Vec3::new(rho, h.s * (zeta + shift), 0.0);
                let d = distance_triangle_triangle(&flat, &[p, p, p]).distance;
                assert!(
                    d <= margin * (1.0 + 1e-9) + 1e-12,
                    "case {case}: a point {d} from the image, margin {margin}"
                );
            }
        }
        assert!(imaged > 150, "{imaged} triangles imaged");
    }

    /// Every sampled point of random triangles and swept rectangles has its `h` and phase
    /// within the ranges the certificate takes (on the ranges' branch), for random directions.
    #[test]
    fn ranges_hold_every_sampled_point() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        let mut ranged = 0;
        for case in 0..300 {
            let (_, _, h) = random_helix(&mut rng);
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let n = Direction {
                rho: angle.cos(),
                eta: angle.sin(),
            };
            let size = [0.01, 0.1, 0.5][case % 3];
            let tri = triangle_near(&mut rng, &h, size);
            let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
            // The sets' branch: the angle continued from their centre's (within a quarter
            // turn of it, where the certificate ranges a set).
            let check = |r: Ranges, x: Vec3| {
                let tau = std::f64::consts::TAU;
                let (c, here) = (h.vertex(centre), h.vertex(x));
                let phi = here.phi + ((c.phi - here.phi) / tau).round() * tau;
                let (rho, zeta) = (here.perp.length(), here.z - h.k * phi);
                let v = n.rho * rho + n.eta * h.s * zeta;
                let slack = 1e-12 * (1.0 + v.abs());
                assert!(
                    v >= r.h.lo - slack && v <= r.h.hi + slack,
                    "case {case}: h {v} in {r:?}"
                );
                assert!(
                    zeta >= r.zeta.lo - slack && zeta <= r.zeta.hi + slack,
                    "case {case}: zeta {zeta} in {r:?}"
                );
            };
            if let Some(r) = h.triangle(&tri, n) {
                ranged += 1;
                for _ in 0..100 {
                    check(r, point_on(&mut rng, &tri));
                }
            }
            let e0 = unit(&mut rng);
            let e1 = e0.cross(unit(&mut rng)).normalize();
            let l = [size * rng.random::<f64>(), size * rng.random::<f64>()];
            let r = size * 0.2 * rng.random::<f64>();
            if let Some(range) = h.volume(centre, (e0, e1), l, r, n) {
                ranged += 1;
                for _ in 0..100 {
                    check(
                        range,
                        rss_point(&mut rng, centre, (e0, e1), (l[0], l[1]), r),
                    );
                }
            }
        }
        assert!(ranged > 300, "{ranged} sets ranged");
    }

    /// Random triangle pairs near the axis of random screws: the pair's bound is at most
    /// their distance at every sampled time.
    #[test]
    fn triangle_bounds_are_below_the_sampled_distances() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        let mut positive = 0;
        for case in 0..300 {
            let (motion, still, h) = random_helix(&mut rng);
            let size = [0.02, 0.1, 0.4][case % 3];
            // Body frames: the turning triangle from the world at t = 0, the still one from
            // the still pose.
            let w1 = triangle_near(&mut rng, &h, size);
            let w2 = w1.map(|p| p + unit(&mut rng) * size * rng.random_range(0.0..3.0));
            let t1 = w1.map(|p| motion.start().inverse().transform_point(p));
            let t2 = w2.map(|p| still.inverse().transform_point(p));
            let lb = h.triangle_pair(&t1, &t2, f64::INFINITY);
            positive += usize::from(lb > 0.0);
            let label = format!("case {case}");
            assert_below_sampled(lb, &motion, (&t1, &w2), 256, &label);
        }
        assert!(positive > 20, "{positive} pairs bounded above 0");
    }

    /// A bolt's thread (radius `1 + 0.1 sin(2 pi z / 0.5 - angle)`) screwed half a turn along
    /// it in a nut 0.01 wider: every pair of nearby triangles is bounded by at least 0.0048
    /// (the flanks' distance across the slope, 0.0062, less the facets' curvature), and by no
    /// more than their distance at any sampled time.
    #[test]
    fn thread_triangles_are_certified_by_their_helical_gap() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let pitch = 0.5;
        let end = Pose::from_axis_angle(
            Vec3::Z,
            std::f64::consts::PI,
            Vec3::new(0.0, 0.0, pitch / 2.0),
        );
        let motion = Motion::screw(Pose::IDENTITY, end).expect("screw");
        let axis = motion.fixed_axis().expect("axis");
        let helix = Helix::new(&axis, motion.start(), Pose::IDENTITY).expect("helix");
        let cols = 256;
        let step = std::f64::consts::TAU / f64::from(cols);
        let face = |c: f64, k: u32, z0: f64, upper: bool| {
            let (a0, a1) = (step * f64::from(k), step * f64::from(k + 1));
            let p = |a: f64, z: f64| {
                let r = 1.0 + c + 0.1 * (std::f64::consts::TAU * z / pitch - a).sin();
                Vec3::new(r * a.cos(), r * a.sin(), z)
            };
            let z1 = z0 + 1.0 / 64.0;
            if upper {
                [p(a0, z0), p(a1, z1), p(a0, z1)]
            } else {
                [p(a0, z0), p(a1, z0), p(a1, z1)]
            }
        };
        for case in 0..200 {
            let z = rng.random_range(-0.5..0.5);
            let k1 = rng.random_range(0..cols);
            let t1 = face(0.0, k1, z, case % 2 == 0);
            let k2 = (k1 + rng.random_range(0..3)) % cols;
            let t2 = face(0.01, k2, z + rng.random_range(-0.03..0.03), case % 3 == 0);
            let lb = helix.triangle_pair(&t1, &t2, f64::INFINITY);
            assert!(lb >= 0.0048, "case {case}: bound {lb}");
            let label = format!("case {case}");
            assert_below_sampled(lb, &motion, (&t1, &t2), 64, &label);
        }
    }
}
