//! The two lane kernels of [`super::rss4`] written with AVX2 and FMA intrinsics: the 4-lane
//! RSS pair bound, and the projection of `f32` point columns on an axis.
//!
//! The portable lane loops leave the vectorising to the compiler, which packs unrelated
//! operations into 2-lane registers and spills; here each `__m256d` is one quantity over the
//! four pairs. Same axes and the same formulas as `rss_separation4`; fused multiply-adds round
//! differently, so the lanes agree with the portable path to rounding, not bit for bit.

use super::{LaneBounds, Rss};
use crate::math::{Mat3, Vec3};
use std::arch::x86_64::*;

/// `[f(0), f(1), f(2)]` written out: `array::map` with these closures was left out of line
/// once the kernel grew (its instructions doubled, with copies of the arrays).
macro_rules! three {
    (|$i:ident| $e:expr) => {
        [
            {
                let $i = 0;
                $e
            },
            {
                let $i = 1;
                $e
            },
            {
                let $i = 2;
                $e
            },
        ]
    };
}

/// Lower bounds on the distances of the pairs `(a[i], b[j])` in lane `2 i + j` (0 where they
/// may overlap); `a` in mesh 1's frame, `b` in mesh 2's, mapped into mesh 1's by `rot12`,
/// `trans12`. Needs a CPU with AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(super) fn bounds(a: [&Rss; 2], b: [&Rss; 2], rot12: &Mat3, trans12: Vec3) -> LaneBounds {
    // a's volume i in lanes 2i and 2i + 1, b's volume j in lanes j and j + 2.
    let sa = |f: fn(&Rss) -> f64| {
        let (x, y) = (f(a[0]), f(a[1]));
        _mm256_setr_pd(x, x, y, y)
    };
    let sb = |f: fn(&Rss) -> f64| {
        let (x, y) = (f(b[0]), f(b[1]));
        _mm256_setr_pd(x, y, x, y)
    };
    // The volumes' axes as lanes of one side: `[c][i]` is component `i` of axis `c`.
    macro_rules! axes {
        ($side:ident) => {
            [
                [
                    $side(|r| r.axes.x_axis.x),
                    $side(|r| r.axes.x_axis.y),
                    $side(|r| r.axes.x_axis.z),
                ],
                [
                    $side(|r| r.axes.y_axis.x),
                    $side(|r| r.axes.y_axis.y),
                    $side(|r| r.axes.y_axis.z),
                ],
                [
                    $side(|r| r.axes.z_axis.x),
                    $side(|r| r.axes.z_axis.y),
                    $side(|r| r.axes.z_axis.z),
                ],
            ]
        };
    }
    let ax: [[__m256d; 3]; 3] = axes!(sa);
    let braw: [[__m256d; 3]; 3] = axes!(sb);
    let bc_raw = [sb(|r| r.center.x), sb(|r| r.center.y), sb(|r| r.center.z)];
    let ac = [sa(|r| r.center.x), sa(|r| r.center.y), sa(|r| r.center.z)];
    // b carried into mesh 1's frame: m(i, k) is entry (i, k) of rot12.
    let m = |i: usize, k: usize| _mm256_set1_pd(rot12.col(k)[i]);
    let carry = |v: &[__m256d; 3], i: usize| {
        _mm256_fmadd_pd(
            m(i, 2),
            v[2],
            _mm256_fmadd_pd(m(i, 1), v[1], _mm256_mul_pd(m(i, 0), v[0])),
        )
    };
    let bx: [[__m256d; 3]; 3] = three!(|c| three!(|i| carry(&braw[c], i)));
    let tr = [trans12.x, trans12.y, trans12.z];
    let d: [__m256d; 3] = three!(|i| {
        _mm256_sub_pd(
            _mm256_add_pd(carry(&bc_raw, i), _mm256_set1_pd(tr[i])),
            ac[i],
        )
    });
    let dot = |u: &[__m256d; 3], v: &[__m256d; 3]| {
        _mm256_fmadd_pd(
            u[2],
            v[2],
            _mm256_fmadd_pd(u[1], v[1], _mm256_mul_pd(u[0], v[0])),
        )
    };
    // r[i][j] = a_i . b_j; t = b's centre in a's frame.
    let r: [[__m256d; 3]; 3] = three!(|i| three!(|j| dot(&ax[i], &bx[j])));
    let t = [dot(&ax[0], &d), dot(&ax[1], &d), dot(&ax[2], &d)];
    let sign = _mm256_set1_pd(-0.0);
    let abs = |x: __m256d| _mm256_andnot_pd(sign, x);
    let neg = |x: __m256d| _mm256_xor_pd(sign, x);
    // c - a * b
    let fnma = |x: __m256d, y: __m256d, c: __m256d| _mm256_fnmadd_pd(x, y, c);
    let (la0, la1) = (sa(|r| r.half_lengths[0]), sa(|r| r.half_lengths[1]));
    let (lb0, lb1) = (sb(|r| r.half_lengths[0]), sb(|r| r.half_lengths[1]));
    // The two normals (unit axes).
    let bt2 = dot(&[r[0][2], r[1][2], r[2][2]], &t);
    let normal_a = fnma(lb1, abs(r[2][1]), fnma(lb0, abs(r[2][0]), abs(t[2])));
    let normal_b = fnma(la1, abs(r[1][2]), fnma(la0, abs(r[0][2]), abs(bt2)));
    // The near-points axis, as in `rss_separation4`.
    let clamp = |x: __m256d, l: __m256d| _mm256_min_pd(_mm256_max_pd(x, neg(l)), l);
    let pa = [clamp(t[0], la0), clamp(t[1], la1)];
    let q = [
        _mm256_sub_pd(pa[0], t[0]),
        _mm256_sub_pd(pa[1], t[1]),
        neg(t[2]),
    ];
    let in_b = |j: usize| dot(&[r[0][j], r[1][j], r[2][j]], &q);
    let pbl = [clamp(in_b(0), lb0), clamp(in_b(1), lb1)];
    let pb: [__m256d; 3] =
        three!(|i| _mm256_fmadd_pd(r[i][1], pbl[1], _mm256_fmadd_pd(r[i][0], pbl[0], t[i])));
    let u = [
        _mm256_sub_pd(pb[0], clamp(pb[0], la0)),
        _mm256_sub_pd(pb[1], clamp(pb[1], la1)),
        pb[2],
    ];
    let u_dot_b = |j: usize| dot(&u, &[r[0][j], r[1][j], r[2][j]]);
    let gap_a = fnma(la1, abs(u[1]), fnma(la0, abs(u[0]), abs(dot(&u, &t))));
    let gap_u = fnma(lb1, abs(u_dot_b(1)), fnma(lb0, abs(u_dot_b(0)), gap_a));
    let ul2 = _mm256_max_pd(dot(&u, &u), _mm256_set1_pd(f64::MIN_POSITIVE));
    let inv = _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(ul2));
    let near = _mm256_mul_pd(gap_u, inv);
    // The common perpendicular of the long edges, e = (0, -r20, r10) in a's frame, as in
    // `rss_separation4`.
    let et = _mm256_fmsub_pd(r[1][0], t[2], _mm256_mul_pd(r[2][0], t[1]));
    let e_dot_by = _mm256_fmsub_pd(r[1][0], r[2][1], _mm256_mul_pd(r[2][0], r[1][1]));
    let el2 = _mm256_fmadd_pd(r[1][0], r[1][0], _mm256_mul_pd(r[2][0], r[2][0]));
    let inv_e = _mm256_div_pd(
        _mm256_set1_pd(1.0),
        _mm256_sqrt_pd(_mm256_max_pd(el2, _mm256_set1_pd(f64::MIN_POSITIVE))),
    );
    let cross = _mm256_mul_pd(
        fnma(lb1, abs(e_dot_by), fnma(la1, abs(r[2][0]), abs(et))),
        inv_e,
    );
    let g = _mm256_max_pd(
        _mm256_max_pd(normal_a, normal_b),
        _mm256_max_pd(near, cross),
    );
    let radii = _mm256_add_pd(sa(|r| r.radius), sb(|r| r.radius));
    let gap = _mm256_max_pd(_mm256_sub_pd(g, radii), _mm256_setzero_pd());
    // The near-points axis in mesh 1's frame, unit length.
    let axis: [__m256d; 3] = three!(|i| {
        _mm256_mul_pd(
            _mm256_fmadd_pd(
                ax[2][i],
                u[2],
                _mm256_fmadd_pd(ax[1][i], u[1], _mm256_mul_pd(ax[0][i], u[0])),
            ),
            inv,
        )
    });
    LaneBounds {
        gap: lanes(gap),
        axis: [lanes(axis[0]), lanes(axis[1]), lanes(axis[2])],
    }
}

/// The four lanes as an array.
#[target_feature(enable = "avx2")]
fn lanes(v: __m256d) -> [f64; 4] {
    let (lo, hi) = (_mm256_castpd256_pd128(v), _mm256_extractf128_pd::<1>(v));
    [
        _mm_cvtsd_f64(lo),
        _mm_cvtsd_f64(_mm_unpackhi_pd(lo, lo)),
        _mm_cvtsd_f64(hi),
        _mm_cvtsd_f64(_mm_unpackhi_pd(hi, hi)),
    ]
}

/// [`super::rss4::max_along`] in AVX2 lanes: the largest `u . p` over the points given by
/// `f32` coordinate columns, eight per instruction.
#[target_feature(enable = "avx2,fma")]
pub(super) fn max_along(columns: [&[f32]; 3], u: Vec3) -> f64 {
    let [x, y, z] = columns;
    let n = x.len().min(y.len()).min(z.len());
    if n < 8 {
        // A leaf's three corners, two triangles' six: one point at a time. (Padding them to
        // eight lanes took 24 scalar loads and inserts; a third of the calls are this short.)
        let (ux, uy, uz) = (u.x as f32, u.y as f32, u.z as f32);
        let mut m = f32::NEG_INFINITY;
        for i in 0..n {
            let v = z[i].mul_add(uz, y[i].mul_add(uy, x[i] * ux));
            if v > m {
                m = v;
            }
        }
        return f64::from(m);
    }
    let (vx, vy, vz) = (
        _mm256_set1_ps(u.x as f32),
        _mm256_set1_ps(u.y as f32),
        _mm256_set1_ps(u.z as f32),
    );
    let mut hi = _mm256_set1_ps(f32::NEG_INFINITY);
    // Eight points from index `$s`. (Macros: written as a closure, the load was compiled as
    // a call per load, 5x slower.)
    macro_rules! load {
        ($c:expr, $s:expr) => {{
            let c: &[f32] = &$c[$s..$s + 8];
            _mm256_setr_ps(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7])
        }};
    }
    macro_rules! step {
        ($x:expr, $y:expr, $z:expr) => {{
            let v = _mm256_fmadd_ps($z, vz, _mm256_fmadd_ps($y, vy, _mm256_mul_ps($x, vx)));
            hi = _mm256_max_ps(hi, v);
        }};
    }
    let mut s = 0;
    while s + 8 <= n {
        step!(load!(x, s), load!(y, s), load!(z, s));
        s += 8;
    }
    // The rest: the last eight again (the maximum does not mind the overlap).
    if s < n {
        let s = n - 8;
        step!(load!(x, s), load!(y, s), load!(z, s));
    }
    // Fold eight lanes to one.
    let h = _mm_max_ps(_mm256_castps256_ps128(hi), _mm256_extractf128_ps::<1>(hi));
    let h = _mm_max_ps(h, _mm_movehl_ps(h, h));
    f64::from(_mm_cvtss_f32(_mm_max_ps(h, _mm_shuffle_ps::<1>(h, h))))
}
