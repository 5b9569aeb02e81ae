//! `tocsin rain`: a simulation that never tunnels. Rods and cubes are thrown down at high speed,
//! spinning, through a rack of tilted 1 mm plates into a bin of 1 mm plates; each step advances
//! every body to the world's earliest contact ([`tocsin::world::first_contacts`]), resolves it
//! with impulses, and goes on with the rest of the step, asking again only about the pairs of
//! the bodies the impulses moved ([`tocsin::world::first_contacts_among`]) and the pairs due at
//! that instant: within a piece of a step the others keep their paths, so their answers hold.
//!
//! Physics (simple on purpose; the point is the collision detection):
//! - bodies are boxes of density 1000 kg/m^3, their origin at the centre of mass; gravity
//!   9.81 m/s^2 is added to the velocity at the start of each 1/60 s step (semi-implicit
//!   Euler), and within the step every body moves by `Motion::interp` about its centre: a
//!   straight line at constant velocity while turning at constant angular velocity, the exact
//!   free flight of a body without gravity; a piece of a step never turns a body by more than
//!   [`MAX_TURN`] (the interpolation's rotation must stay below pi);
//! - a contact is the pair's first time within [`TOLERANCE`] (0.1 mm). A pair already within
//!   it at the start of a piece that is approaching gets its impulses at once; one that is
//!   separating is checked for the rest of the piece with half its present distance as the
//!   tolerance, so that no pair is ever excused from the check (bodies never touch);
//! - impulses on the contacts' manifolds (the witness point and every box corner within
//!   [`MANIFOLD`] of the other box) along each contact's normal, by sequential impulses over
//!   every contact of the instant together (a body pressed between two others or wedged
//!   between a plate and a wall gets impulses that satisfy all its contacts at once; solved
//!   pair by pair, each pair's impulses undid the other's and the step froze): a point
//!   within the tolerance gets a normal velocity of at least
//!   `max(-e vn, SEPARATION, (TOLERANCE - gap) / RESTORE)`, with restitution `e` =
//!   [`RESTITUTION`], a small separation speed [`SEPARATION`] (2 cm/s) that keeps resting
//!   bodies from contacting again within the same instant, and a correction that brings a
//!   point closer than the tolerance back to it in [`RESTORE`] (2 ms), so that gaps do not
//!   shrink towards rounding in resting contact; farther points are speculative contacts;
//!   Coulomb friction with coefficient [`FRICTION`] clamps each point's tangential impulse to
//!   `mu` times its normal one. Where the passes do not settle (friction locks a wedge whose
//!   contacts all ask the body to leave), the instant is solved again without friction
//!   (`jams` in the JSON);
//! - a body rocking on an edge stops turning: a manifold along a line (a corner, or an edge on
//!   a face) pushes at one point, the body turns about it and another point of the edge comes
//!   down, and the separating check with half the distance finds it again, closer each time,
//!   down to [`MIN_GAP`], where the step could only freeze. A contact on such a manifold closer
//!   than [`ROCKING`] of the tolerance (no contact is reported that close: it is such a return)
//!   sets both bodies' angular velocities to zero and holds them there through the instant's
//!   impulses, which then move the bodies apart along the normal without turning them
//!   (`spins_stopped` in the JSON). Until the thirty-ninth session the continuous queries of
//!   such pairs mostly reached their iteration cap first, and the capped query stopped the
//!   bodies for the piece instead; two convex polytopes' queries now answer them. Until the
//!   forty-third session the impulses gave the spin back and 8 of 100 seeds of 40 bodies froze
//!   (1 to 66 steps of 90), some in wedges; none of those 100 does now;
//! - after [`MAX_EVENTS`] contacts in one step, or [`EVENTS_PER_BODY`] per body if that is
//!   more, the rest of that step is skipped (bodies keep their velocities but do not move:
//!   never unsafe), and the step is counted as frozen. (A fixed 400 froze 37 of 90 steps of
//!   160 bodies settling in the bin, spread over hundreds of pairs and instants: a budget,
//!   not a loop.)
//!
//! Checked every step: no pair of meshes intersects ([`tocsin::world::colliding_pairs`], exact),
//! and no body's centre crossed a plate: the straight path of the centre over each piece of the
//! step must not pass through any plate's rectangle. The JSON out says both counts (0 expected),
//! the time per step, and with `--scene` the whole scene so that other engines can run it
//! (`bench/tunnelling.py`).

use crate::render::{Canvas, View};
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use tocsin::motion::rotation_exp;
use tocsin::world::{
    colliding_pairs, first_contacts, first_contacts_among, World, WorldContact, WorldOptions,
};
use tocsin::{time_of_contact, ContactError, ContactOptions, Mat3, Motion, Pose, TriMesh, Vec3};

/// Step length, seconds.
pub const DT: f64 = 1.0 / 60.0;
/// Gravity, m/s^2 (along -z).
pub const GRAVITY: f64 = 9.81;
/// Coefficient of restitution.
pub const RESTITUTION: f64 = 0.3;
/// Coefficient of Coulomb friction.
pub const FRICTION: f64 = 0.5;
/// Contact tolerance, metres.
pub const TOLERANCE: f64 = 1e-4;
/// Smallest normal speed after an impulse, m/s.
pub const SEPARATION: f64 = 0.02;
/// A pair closer than this that no impulse can separate further stops the piece where it is
/// (metres): below it, half the distance would be a tolerance near rounding.
pub const MIN_GAP: f64 = 1e-9;
/// A point closer than the tolerance separates at least fast enough to reach it again in this
/// time, seconds (a position correction by velocity, as Baumgarte's).
pub const RESTORE: f64 = 2e-3;
/// Fewest and most passes of the impulse solver over one instant's contact points.
pub const MIN_PASSES: usize = 8;
/// See [`MIN_PASSES`].
pub const PASSES: usize = 256;
/// The solver has settled when every point's normal velocity is within this fraction of
/// [`SEPARATION`] of its target (below the quarter that asks for impulses again).
pub const SETTLED: f64 = 0.2;
/// Contacts resolved per step before the rest of it is skipped (at least; see
/// [`EVENTS_PER_BODY`]).
pub const MAX_EVENTS: usize = 400;
/// Contacts resolved per step and per body before the rest of the step is skipped, where that
/// allows more than [`MAX_EVENTS`].
pub const EVENTS_PER_BODY: usize = 10;
/// Largest turn of a body in one piece of a step, radians.
pub const MAX_TURN: f64 = 3.0;
/// A contact closer than this fraction of the tolerance on a manifold along a line (a point or
/// an edge: [`on_a_line`]) is a body rocking on an edge (module docs).
pub const ROCKING: f64 = 0.25;
/// Corners of a box within this of the other box join a contact's manifold, metres.
pub const MANIFOLD: f64 = 5e-3;
/// Plate thickness, metres.
pub const PLATE: f64 = 1e-3;
/// Size of a picture frame, pixels.
const FRAME_W: usize = 220;
const FRAME_H: usize = 480;

/// Body density, kg/m^3.
pub const DENSITY: f64 = 1000.0;

/// Options of `tocsin rain`.
#[derive(clap::Args)]
pub struct RainArgs {
    /// Number of falling bodies (rods and cubes, alternating).
    #[arg(long, default_value_t = 40)]
    bodies: usize,
    /// Number of steps of 1/60 s.
    #[arg(long, default_value_t = 90)]
    steps: usize,
    /// Seed of the bodies' start states.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Downward launch speed, m/s.
    #[arg(long, default_value_t = 15.0)]
    speed: f64,
    /// A folder to write eight PNG frames (first step to last) and a strip of them into.
    #[arg(long)]
    frames: Option<PathBuf>,
    /// Put the scene (plates, bodies' start states, constants) in the JSON out.
    #[arg(long)]
    scene: bool,
}

/// A static plate: a box of these half extents at this pose.
struct Plate {
    half: Vec3,
    pose: Pose,
}

/// A falling body's state; its mesh is a box of half extents `half` centred at its origin.
struct Body {
    half: Vec3,
    x: Vec3,
    r: Mat3,
    v: Vec3,
    w: Vec3,
    inv_mass: f64,
    /// Inverse principal inertia, body frame.
    inv_inertia: Vec3,
}

impl Body {
    fn pose(&self) -> Pose {
        Pose {
            rotation: self.r,
            translation: self.x,
        }
    }

    fn inv_inertia_world(&self) -> Mat3 {
        self.r * Mat3::from_diagonal(self.inv_inertia) * self.r.transpose()
    }

    fn velocity_at(&self, p: Vec3) -> Vec3 {
        self.v + self.w.cross(p - self.x)
    }
}

/// SplitMix64: a small seeded generator, enough for start states.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// The rack of tilted plates (three layers of three), and the bin: a floor and four walls.
fn plates() -> Vec<Plate> {
    let mut out = Vec::new();
    let t = 0.5 * PLATE;
    for (layer, z) in [0.8, 1.25, 1.7].into_iter().enumerate() {
        let offset = if layer % 2 == 0 { -0.08 } else { 0.08 };
        for (k, x) in [-0.38, 0.0, 0.38].into_iter().enumerate() {
            let tilt = if (k + layer) % 2 == 0 { 0.6 } else { -0.6 };
            out.push(Plate {
                half: Vec3::new(0.13, 0.45, t),
                pose: Pose::from_axis_angle(Vec3::Y, tilt, Vec3::new(x + offset, 0.0, z)),
            });
        }
    }
    // The bin's floor, and four walls up past the rack and the launch height: a closed chute.
    let (w, h) = (0.6, 1.5);
    out.push(Plate {
        half: Vec3::new(w, w, t),
        pose: Pose::from_translation(Vec3::new(0.0, 0.0, -t)),
    });
    for s in [-1.0, 1.0] {
        out.push(Plate {
            half: Vec3::new(w, t, h),
            pose: Pose::from_translation(Vec3::new(0.0, s * (w + t), h)),
        });
        out.push(Plate {
            half: Vec3::new(t, w, h),
            pose: Pose::from_translation(Vec3::new(s * (w + t), 0.0, h)),
        });
    }
    out
}

/// Rods and cubes on a grid above the rack, thrown down and spinning.
fn bodies(n: usize, seed: u64, speed: f64) -> Vec<Body> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|k| {
            let half = if k % 2 == 0 {
                Vec3::new(0.1, 0.008, 0.008)
            } else {
                Vec3::splat(0.025)
            };
            let (i, j, layer) = (k % 4, (k / 4) % 4, k / 16);
            let x = Vec3::new(
                -0.36 + 0.24 * i as f64,
                -0.36 + 0.24 * j as f64,
                2.3 + 0.25 * layer as f64,
            );
            let axis = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .try_normalize()
            .unwrap_or(Vec3::Z);
            let r = Mat3::from_axis_angle(axis, rng.uniform(0.0, 3.0));
            let v = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                -speed * rng.uniform(0.7, 1.0),
            );
            let w = axis.any_orthonormal_vector() * rng.uniform(5.0, 25.0);
            let mass = DENSITY * 8.0 * half.x * half.y * half.z;
            let (a, b, c) = (
                (2.0 * half.x).powi(2),
                (2.0 * half.y).powi(2),
                (2.0 * half.z).powi(2),
            );
            let inertia = Vec3::new(b + c, a + c, a + b) * (mass / 12.0);
            Body {
                half,
                x,
                r,
                v,
                w,
                inv_mass: 1.0 / mass,
                inv_inertia: inertia.recip(),
            }
        })
        .collect()
}

/// A point of a contact manifold: where, and the gap there (metres).
#[derive(Clone, Copy, Debug)]
struct ContactPoint {
    p: Vec3,
    gap: f64,
}

/// Distance from `p` to the solid box of half extents `half` at `pose`.
fn box_distance(half: Vec3, pose: &Pose, p: Vec3) -> f64 {
    let local = pose.inverse().transform_point(p);
    (local - local.clamp(-half, half)).length()
}

fn corners(half: Vec3, pose: &Pose) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        let s = Vec3::new(
            if k & 1 == 0 { -1.0 } else { 1.0 },
            if k & 2 == 0 { -1.0 } else { 1.0 },
            if k & 4 == 0 { -1.0 } else { 1.0 },
        );
        pose.transform_point(s * half)
    })
}

/// The contact manifold of two boxes `(half, pose)` at a contact: the witness midpoint, and
/// every corner of either box within [`MANIFOLD`] of the other box, placed half its gap along
/// the normal `n` (from `a` to `b`).
fn manifold(a: (Vec3, Pose), b: (Vec3, Pose), n: Vec3, witness: ContactPoint) -> Vec<ContactPoint> {
    let mut out = vec![witness];
    for (from, to, sign) in [(a, b, 1.0), (b, a, -1.0)] {
        for c in corners(from.0, &from.1) {
            let gap = box_distance(to.0, &to.1, c);
            if gap < MANIFOLD {
                out.push(ContactPoint {
                    p: c + n * (sign * 0.5 * gap),
                    gap,
                });
            }
        }
    }
    out
}

/// One contact's manifold for [`resolve`]: the bodies (`None`: a plate), the normal `n` from
/// the first to the second, and the points.
struct Manifold {
    pair: (Option<usize>, Option<usize>),
    n: Vec3,
    points: Vec<ContactPoint>,
}

/// Whether a manifold's points lie within [`PLATE`] of one line: a box's corner or edge, not
/// a face (the bodies are at least 16 mm thick). The witness point of an edge on a face lies
/// on the edge beside its corners, so counting points (two at most, until the forty-third
/// session) missed such edges and they rocked down to [`MIN_GAP`].
fn on_a_line(points: &[ContactPoint]) -> bool {
    let Some(first) = points.first() else {
        return true;
    };
    let far = points
        .iter()
        .map(|c| c.p)
        .max_by(|a, b| (*a - first.p).length().total_cmp(&(*b - first.p).length()))
        .unwrap_or(first.p);
    let Some(along) = (far - first.p).try_normalize() else {
        return true;
    };
    points.iter().all(|c| {
        let d = c.p - first.p;
        (d - along * d.dot(along)).length() <= PLATE
    })
}

/// Impulses at the points of every manifold of one instant, solved together by sequential
/// impulses with accumulated clamping ([`MIN_PASSES`] to [`PASSES`] passes over all the points,
/// until every point is within [`SETTLED`] of [`SEPARATION`] of its target): a body pressed between
/// two others, or wedged between two plates, gets the impulses that satisfy both contacts at
/// once (solved pair by pair, each pair's impulses undid the other's, and the step froze). A
/// point within the tolerance gets a normal velocity of at least `max(-e vn, SEPARATION,
/// (TOLERANCE - gap) / RESTORE)`; a point farther away (a speculative contact) may approach,
/// but only as fast as closes its gap to the tolerance in the `left` seconds of the step.
/// Friction at each point is clamped to `mu` times its normal impulse; where friction keeps the
/// points from settling (a jam: a body wedged between a plate's edge and a wall, whose contacts
/// ask it to leave both), they are solved again without it. Nothing is applied unless some
/// point falls short of its target by more than a quarter of [`SEPARATION`]. Returns the bodies
/// whose velocities changed, and whether the contacts jammed. The bodies in `locked` (rocking
/// on an edge, module docs) do not turn: their inverse inertia counts as zero.
fn resolve(
    bodies: &mut [Body],
    manifolds: &[Manifold],
    locked: &[usize],
    left: f64,
) -> (Vec<usize>, bool) {
    let turns = |k: usize| !locked.contains(&k);
    let relative = |bodies: &[Body], (a, b): (Option<usize>, Option<usize>), p: Vec3| {
        let vel = |k: Option<usize>| k.map_or(Vec3::ZERO, |k| bodies[k].velocity_at(p));
        vel(b) - vel(a)
    };
    let mass = |bodies: &[Body], k: Option<usize>, p: Vec3| {
        k.map_or((0.0, Mat3::ZERO, Vec3::ZERO), |k| {
            let s = &bodies[k];
            let iw = if turns(k) {
                s.inv_inertia_world()
            } else {
                Mat3::ZERO
            };
            (s.inv_mass, iw, p - s.x)
        })
    };
    // Every point with its manifold: (manifold, point, target normal velocity).
    let mut rows = Vec::new();
    for (m, f) in manifolds.iter().enumerate() {
        for c in &f.points {
            let target = if c.gap <= TOLERANCE {
                (-RESTITUTION * relative(bodies, f.pair, c.p).dot(f.n))
                    .max(SEPARATION)
                    .max((TOLERANCE - c.gap) / RESTORE)
            } else {
                -(c.gap - TOLERANCE) / left.max(1e-9)
            };
            rows.push((m, c.p, target));
        }
    }
    // Nothing to do unless a point falls short of its target by a quarter of the separation
    // speed (the passes leave small residuals; chasing them would never end).
    let short = rows.iter().any(|&(m, p, t)| {
        let f = &manifolds[m];
        relative(bodies, f.pair, p).dot(f.n) < t - 0.25 * SEPARATION
    });
    if !short {
        return (Vec::new(), false);
    }
    let before: Vec<(Vec3, Vec3)> = bodies.iter().map(|s| (s.v, s.w)).collect();
    let apply = |bodies: &mut [Body], (a, b): (Option<usize>, Option<usize>), p: Vec3, j: Vec3| {
        for (k, sign) in [(a, -1.0), (b, 1.0)] {
            if let Some(i) = k {
                let s = &mut bodies[i];
                s.v += j * (sign * s.inv_mass);
                if turns(i) {
                    s.w += s.inv_inertia_world() * (p - s.x).cross(j * sign);
                }
            }
        }
    };
    // The passes, with or without friction; whether every point settled near its target.
    let solve = |bodies: &mut [Body], mu: f64| {
        let mut normal = vec![0.0_f64; rows.len()];
        let mut friction = vec![Vec3::ZERO; rows.len()];
        for pass in 0..PASSES {
            for (k, &(m, p, target)) in rows.iter().enumerate() {
                let Manifold { pair, n, .. } = manifolds[m];
                let (ma, ia, ra) = mass(bodies, pair.0, p);
                let (mb, ib, rb) = mass(bodies, pair.1, p);
                let eff = |d: Vec3| {
                    ma + mb + d.dot((ia * ra.cross(d)).cross(ra) + (ib * rb.cross(d)).cross(rb))
                };
                let rel = relative(bodies, pair, p);
                let total = (normal[k] + (target - rel.dot(n)) / eff(n)).max(0.0);
                let dj = total - normal[k];
                normal[k] = total;
                apply(bodies, pair, p, n * dj);
                let rel = relative(bodies, pair, p);
                let tangential = rel - n * rel.dot(n);
                if let Some(t) = tangential.try_normalize().filter(|_| mu > 0.0) {
                    let wanted = friction[k] - t * (tangential.length() / eff(t));
                    let limit = mu * normal[k];
                    let clamped = if wanted.length() > limit {
                        wanted * (limit / wanted.length())
                    } else {
                        wanted
                    };
                    apply(bodies, pair, p, clamped - friction[k]);
                    friction[k] = clamped;
                }
            }
            let settled = rows.iter().all(|&(m, p, t)| {
                let f = &manifolds[m];
                relative(bodies, f.pair, p).dot(f.n) >= t - SETTLED * SEPARATION
            });
            if settled && pass + 1 >= MIN_PASSES {
                return true;
            }
        }
        false
    };
    let jammed = !solve(bodies, FRICTION);
    if jammed {
        // Friction holds the bodies where the contacts ask them to leave (a box wedged between
        // a plate's edge and a wall): the points are solved again from the velocities before,
        // without friction, and the bodies slide out of the wedge.
        for (s, &(v, w)) in bodies.iter_mut().zip(&before) {
            (s.v, s.w) = (v, w);
        }
        solve(bodies, 0.0);
    }
    let moved = (0..bodies.len())
        .filter(|&k| (bodies[k].v, bodies[k].w) != before[k])
        .collect();
    (moved, jammed)
}

/// The single query on bodies `i`, `j` over the piece: `Some((time, Some(contact)))` for a
/// contact, `Some((time_reached, None))` when it reached its iteration cap (free up to then
/// only), `None` when the pair stays apart.
fn ask_pair(
    world: &World,
    i: usize,
    j: usize,
    options: &ContactOptions,
) -> Result<Option<(f64, Option<tocsin::ContactTime>)>, String> {
    let c = time_of_contact(
        world.mesh(i),
        world.motion(i),
        world.mesh(j),
        world.motion(j),
        options,
    );
    match c {
        Ok(Some(contact)) => Ok(Some((contact.time, Some(contact)))),
        Ok(None) => Ok(None),
        Err(ContactError::IterationLimit { time_reached, .. }) => Ok(Some((time_reached, None))),
        Err(e) => Err(world_error(e)),
    }
}

/// Whether the straight path of a point from `p0` to `p1` passes through the plate's rectangle.
fn crosses(plate: &Plate, p0: Vec3, p1: Vec3) -> bool {
    let inv = plate.pose.inverse();
    let (a, b) = (inv.transform_point(p0), inv.transform_point(p1));
    if a.z * b.z >= 0.0 {
        return false;
    }
    let q = a + (b - a) * (a.z / (a.z - b.z));
    q.x.abs() <= plate.half.x && q.y.abs() <= plate.half.y
}

fn world_error(e: impl std::fmt::Display) -> String {
    format!("simulation: {e}")
}

/// The counters of a run.
#[derive(Default)]
struct Tally {
    events: usize,
    frozen_steps: usize,
    /// Bodies whose spin was stopped while rocking on an edge (module docs).
    spins_stopped: usize,
    /// Instants whose contacts friction jammed, solved again without it ([`resolve`]).
    jams: usize,
    /// Pair queries that reached their iteration cap (the piece then stops where they did).
    capped: usize,
    intersections: usize,
    crossings: usize,
    crossed: Vec<bool>,
    step_ms: Vec<f64>,
}

/// Runs `tocsin rain`.
pub fn run(args: &RainArgs) -> Result<Value, String> {
    if !(args.speed.is_finite() && args.speed >= 0.0) {
        return Err("--speed must be finite and at least 0".into());
    }
    let plates = plates();
    let mut bodies = bodies(args.bodies, args.seed, args.speed);
    let box_mesh = |half: Vec3| tocsin::mesh::box_mesh(half).map(Arc::new);
    let mut world = World::new();
    let mut shared: Vec<(Vec3, Arc<TriMesh>)> = Vec::new();
    let mut mesh_for = |half: Vec3| -> Result<Arc<TriMesh>, String> {
        if let Some((_, m)) = shared.iter().find(|(h, _)| *h == half) {
            return Ok(m.clone());
        }
        let m = box_mesh(half).map_err(world_error)?;
        shared.push((half, m.clone()));
        Ok(m)
    };
    for p in &plates {
        world.add_static(&mesh_for(p.half)?, p.pose);
    }
    let first = plates.len();
    for b in &bodies {
        world.add_body(&mesh_for(b.half)?, Motion::stationary(b.pose()));
    }
    let scene = args.scene.then(|| scene_json(&plates, &bodies));
    let options = WorldOptions {
        contact: ContactOptions {
            tolerance: Some(TOLERANCE),
            ..Default::default()
        },
        ..Default::default()
    };
    let mut tally = Tally {
        crossed: vec![false; bodies.len()],
        ..Default::default()
    };
    // Eight frames from the first step to the last, evenly spaced.
    let marks: Vec<usize> = (0..8)
        .map(|k| k * args.steps.saturating_sub(1) / 7)
        .collect();
    let mut frames = Vec::new();
    for step in 0..args.steps {
        let clock = Instant::now();
        for b in &mut bodies {
            b.v.z -= GRAVITY * DT;
        }
        step_once(
            &mut world,
            &mut bodies,
            &plates,
            first,
            &options,
            &mut tally,
        )?;
        let poses = world.poses_at(1.0);
        tally.intersections += colliding_pairs(&world, &poses).map_err(world_error)?.len();
        tally.step_ms.push(clock.elapsed().as_secs_f64() * 1e3);
        if args.frames.is_some() && marks.contains(&step) && frames.len() < 8 {
            frames.push(draw(&world, first));
        }
    }
    if let Some(dir) = &args.frames {
        write_frames(dir, &frames)?;
    }
    let in_bin = bodies
        .iter()
        .filter(|b| b.x.z > 0.0 && b.x.z < 0.6 && b.x.x.abs() < 0.6 && b.x.y.abs() < 0.6)
        .count();
    let mut ms = tally.step_ms.clone();
    ms.sort_by(f64::total_cmp);
    let pick = |q: f64| {
        ms.get(((ms.len() as f64 - 1.0) * q).round() as usize)
            .copied()
    };
    let mut out = json!({
        "engine": "tocsin",
        "bodies": bodies.len(),
        "steps": args.steps,
        "dt": DT,
        "tunnelled_bodies": tally.crossed.iter().filter(|&&c| c).count(),
        "crossings": tally.crossings,
        "intersecting_pairs": tally.intersections,
        "contacts_resolved": tally.events,
        "frozen_steps": tally.frozen_steps,
        "jams": tally.jams,
        "spins_stopped": tally.spins_stopped,
        "capped_queries": tally.capped,
        "in_bin": in_bin,
        "ms_per_step": {
            "median": pick(0.5),
            "p90": pick(0.9),
            "max": ms.last(),
            "mean": ms.iter().sum::<f64>() / ms.len().max(1) as f64,
        },
    });
    if let Some(s) = scene {
        out["scene"] = s;
    }
    Ok(out)
}

/// What is known about one pair over the current piece: the absolute time (seconds from the
/// step's start) up to which it is free, and its contact there when it has one (`None`: free
/// up to the piece's end, or undecided after the time).
type Known = (f64, Option<WorldContact>);

/// One step of length [`DT`] (module docs). The step is cut into pieces; within a piece every
/// body keeps its motion's path (constant velocities), re-based to start at each event, so a
/// pair neither of whose bodies got an impulse keeps its answer: only the pairs of the bodies
/// that did, and the pairs at the event, are asked again ([`first_contacts_among`]).
fn step_once(
    world: &mut World,
    bodies: &mut [Body],
    plates: &[Plate],
    first: usize,
    options: &WorldOptions,
    tally: &mut Tally,
) -> Result<(), String> {
    let mut now = 0.0_f64;
    let mut events = 0;
    let max_events = MAX_EVENTS.max(EVENTS_PER_BODY * bodies.len());
    // `None`: plan a new piece and ask about every pair.
    let mut changed: Option<Vec<usize>> = None;
    let mut end = 0.0_f64;
    let mut known: BTreeMap<(usize, usize), Known> = BTreeMap::new();
    while now < DT {
        if changed.is_some() {
            let spin = bodies.iter().map(|b| b.w.length()).fold(0.0, f64::max);
            if spin * (end - now) > MAX_TURN || end <= now {
                changed = None;
            }
        }
        if changed.is_none() {
            let spin = bodies.iter().map(|b| b.w.length()).fold(0.0, f64::max);
            let left = DT - now;
            end = now
                + if spin * left > MAX_TURN {
                    MAX_TURN / spin
                } else {
                    left
                };
        }
        let h = end - now;
        for (k, b) in bodies.iter().enumerate() {
            let stop = Pose {
                rotation: rotation_exp(b.w * h) * b.r,
                translation: b.x + b.v * h,
            };
            let m = Motion::interp(b.pose(), stop, Vec3::ZERO).map_err(world_error)?;
            world.set_motion(first + k, m).map_err(world_error)?;
        }
        let found = match &changed {
            None => {
                known.clear();
                first_contacts(world, options).map_err(world_error)?
            }
            Some(moved) => {
                // The moved bodies, and every pair whose answer is due now.
                let ask: Vec<usize> = moved.iter().map(|&k| first + k).collect();
                let due: Vec<(usize, usize)> = known
                    .iter()
                    .filter(|(_, (t, _))| *t <= now)
                    .map(|(p, _)| *p)
                    .collect();
                for p in &due {
                    known.remove(p);
                }
                known.retain(|&(i, j), _| !ask.contains(&i) && !ask.contains(&j));
                let mut found = first_contacts_among(world, options, &ask).map_err(world_error)?;
                // Due pairs of two unmoved bodies: asked on their own.
                for (i, j) in due {
                    if ask.contains(&i) || ask.contains(&j) {
                        continue;
                    }
                    match ask_pair(world, i, j, &options.contact)? {
                        Some((_, Some(contact))) => found.contacts.push(WorldContact {
                            body1: i,
                            body2: j,
                            contact,
                        }),
                        Some((time_reached, None)) => {
                            found.undecided.push(tocsin::world::Undecided {
                                body1: i,
                                body2: j,
                                time_reached,
                            });
                        }
                        None => {}
                    }
                }
                found
            }
        };
        tally.capped += found.undecided.len();
        for u in &found.undecided {
            known.insert((u.body1, u.body2), (now + u.time_reached * h, None));
        }
        for c in found.contacts {
            known.insert((c.body1, c.body2), (now + c.contact.time * h, Some(c)));
        }
        // Pairs within the tolerance now: impulses on their manifolds first.
        let boxes = |bodies: &[Body], i: usize| -> (Vec3, Pose) {
            if i < first {
                (plates[i].half, plates[i].pose)
            } else {
                (bodies[i - first].half, bodies[i - first].pose())
            }
        };
        let at_now: Vec<WorldContact> = known
            .values()
            .filter(|(t, c)| *t <= now && c.is_some())
            .filter_map(|(_, c)| *c)
            .collect();
        let mut moved = Vec::new();
        let mut manifolds = Vec::with_capacity(at_now.len());
        let mut locked = Vec::new();
        for c in &at_now {
            let (a, b) = (boxes(bodies, c.body1), boxes(bodies, c.body2));
            let points = manifold(a, b, c.contact.normal, witness(c));
            let pair = (c.body1.checked_sub(first), c.body2.checked_sub(first));
            if c.contact.distance < ROCKING * TOLERANCE && on_a_line(&points) {
                // Closer than a contact is ever reported, on a point or an edge: the
                // pair came back after its impulses (module docs); its bodies stop turning.
                for k in pair.0.into_iter().chain(pair.1) {
                    locked.push(k);
                    if bodies[k].w != Vec3::ZERO {
                        bodies[k].w = Vec3::ZERO;
                        moved.push(k);
                        tally.spins_stopped += 1;
                    }
                }
            }
            manifolds.push(Manifold {
                pair,
                n: c.contact.normal,
                points,
            });
        }
        let (pushed, jammed) = resolve(bodies, &manifolds, &locked, DT - now);
        moved.extend(pushed);
        tally.jams += usize::from(jammed);
        if !moved.is_empty() {
            moved.sort_unstable();
            moved.dedup();
            tally.events += 1;
            events += 1;
            if events >= max_events {
                tally.frozen_steps += 1;
                break;
            }
            changed = Some(moved);
            continue;
        }
        // Within the tolerance and separating everywhere: checked with half its distance.
        for c in at_now {
            let key = (c.body1, c.body2);
            if c.contact.distance < MIN_GAP {
                known.insert(key, (now, None));
                continue;
            }
            let tight = ContactOptions {
                tolerance: Some(0.5 * c.contact.distance),
                ..options.contact
            };
            match ask_pair(world, key.0, key.1, &tight)? {
                Some((t, Some(contact))) => {
                    known.insert(key, (now + t * h, Some(WorldContact { contact, ..c })));
                }
                Some((time_reached, None)) => {
                    tally.capped += 1;
                    known.insert(key, (now + time_reached * h, None));
                }
                None => {
                    known.remove(&key);
                }
            }
        }
        let next = known.values().map(|(t, _)| *t).fold(end, f64::min);
        // Move everyone to the event (or to the end of the piece), along the checked motions.
        let param = if h > 0.0 {
            ((next - now) / h).clamp(0.0, 1.0)
        } else {
            1.0
        };
        for (k, b) in bodies.iter_mut().enumerate() {
            let p = world.motion(first + k).pose_at(param);
            let before = b.x;
            b.x = p.translation;
            b.r = p.rotation;
            for plate in plates {
                if crosses(plate, before, b.x) {
                    tally.crossings += 1;
                    tally.crossed[k] = true;
                }
            }
        }
        if next >= end {
            now = end;
            changed = None;
            continue;
        }
        now = next;
        changed = Some(Vec::new());
        tally.events += 1;
        events += 1;
        if events >= max_events {
            tally.frozen_steps += 1;
            break;
        }
    }
    // The world's motions end where the bodies are, for the checks and the pictures.
    for (k, b) in bodies.iter().enumerate() {
        world
            .set_motion(first + k, Motion::stationary(b.pose()))
            .map_err(world_error)?;
    }
    Ok(())
}

/// The witness midpoint of a contact, with its distance as the gap.
fn witness(c: &WorldContact) -> ContactPoint {
    ContactPoint {
        p: 0.5 * (c.contact.point1 + c.contact.point2),
        gap: c.contact.distance,
    }
}

/// A side view of the world as it stands.
fn draw(world: &World, first: usize) -> Canvas {
    let (w, h) = (FRAME_W, FRAME_H);
    let view = View {
        right: Vec3::X,
        up: Vec3::Z,
        center: Vec3::new(0.0, 0.0, 1.45),
        scale: h as f64 / 3.1,
    };
    let mut canvas = Canvas::new(w, h);
    let poses = world.poses_at(0.0);
    for (i, pose) in poses.iter().enumerate() {
        // The walls facing the viewer would hide everything: drawn as glass (not at all).
        let facing = world.mesh(i).vertices().iter().all(|v| v.y.abs() < PLATE);
        if i < first && facing && pose.translation.y.abs() > 0.5 {
            continue;
        }
        let color = if i < first {
            [150.0, 150.0, 150.0]
        } else if (i - first) % 2 == 0 {
            [70.0, 120.0, 200.0]
        } else {
            [230.0, 140.0, 50.0]
        };
        canvas.draw_mesh(world.mesh(i), pose, color, &view);
    }
    canvas
}

fn write_frames(dir: &std::path::Path, frames: &[Canvas]) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut strip = Canvas::new(FRAME_W * frames.len().min(8), FRAME_H);
    for (k, f) in frames.iter().enumerate() {
        let path = dir.join(format!("frame_{k:02}.png"));
        f.write_png(&path.to_string_lossy())?;
        if k < 8 {
            strip.blit(f, FRAME_W * k, 0);
        }
    }
    strip.write_png(&dir.join("strip.png").to_string_lossy())
}

/// The scene for other engines: plates and bodies as boxes (half extents, 4x4 row-major pose),
/// bodies' mass, velocity and angular velocity (world frame), and the constants.
fn scene_json(plates: &[Plate], bodies: &[Body]) -> Value {
    let matrix = |p: &Pose| {
        let m = p.to_matrix().transpose().to_cols_array();
        m.chunks(4).map(|r| r.to_vec()).collect::<Vec<_>>()
    };
    json!({
        "dt": DT,
        "gravity": GRAVITY,
        "restitution": RESTITUTION,
        "friction": FRICTION,
        "density": DENSITY,
        "plates": plates.iter().map(|p| json!({
            "half_extents": p.half.to_array(),
            "pose": matrix(&p.pose),
        })).collect::<Vec<_>>(),
        "bodies": bodies.iter().map(|b| json!({
            "half_extents": b.half.to_array(),
            "pose": matrix(&b.pose()),
            "mass": 1.0 / b.inv_mass,
            "velocity": b.v.to_array(),
            "angular_velocity": b.w.to_array(),
        })).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_centre_path_through_a_plate_crosses_it_and_one_beside_it_does_not() {
        let plate = Plate {
            half: Vec3::new(0.5, 0.5, 0.0005),
            pose: Pose::from_axis_angle(Vec3::Y, 0.6, Vec3::new(0.0, 0.0, 1.0)),
        };
        let through = crosses(&plate, Vec3::new(0.0, 0.0, 1.2), Vec3::new(0.1, 0.0, 0.8));
        let beside = crosses(&plate, Vec3::new(0.0, 0.8, 1.2), Vec3::new(0.0, 0.8, 0.8));
        let above = crosses(&plate, Vec3::new(0.0, 0.0, 1.4), Vec3::new(0.0, 0.0, 1.2));
        assert!(through && !beside && !above);
    }

    #[test]
    fn an_impulse_reverses_an_approach_and_a_resting_box_gets_both_corners() {
        let mut b = bodies(1, 3, 10.0);
        b[0].w = Vec3::ZERO;
        b[0].v = Vec3::new(1.0, 0.0, -10.0);
        let p = b[0].x - Vec3::new(0.0, 0.0, 0.01);
        let point = [ContactPoint { p, gap: 0.0 }];
        // The plate is body 1 (`None`), the box body 2, the normal from the plate up.
        let on_plate = |points: &[ContactPoint]| Manifold {
            pair: (None, Some(0)),
            n: Vec3::Z,
            points: points.to_vec(),
        };
        assert_eq!(
            resolve(&mut b, &[on_plate(&point)], &[], DT),
            (vec![0], false)
        );
        let vn = b[0].velocity_at(p).z;
        assert!((vn - RESTITUTION * 10.0).abs() < 1e-9, "{vn}");
        // Friction took tangential speed off, within the cone.
        assert!(b[0].velocity_at(p).x < 1.0);
        // Separating now: no second impulse.
        assert!(resolve(&mut b, &[on_plate(&point)], &[], DT).0.is_empty());

        // A cube resting flat on a plate: four corners in the manifold; after the impulses no
        // corner approaches the plate.
        let plate = (Vec3::new(1.0, 1.0, 0.0005), Pose::IDENTITY);
        let half = Vec3::splat(0.025);
        let mut cube = bodies(2, 5, 0.0);
        cube[1].r = Mat3::IDENTITY;
        cube[1].x = Vec3::new(0.0, 0.0, 0.0005 + 0.025 + 5e-5);
        cube[1].v = Vec3::new(0.0, 0.0, -1.0);
        cube[1].w = Vec3::new(3.0, 0.0, 0.0);
        let witness = ContactPoint {
            p: cube[1].x - Vec3::new(0.0, 0.0, 0.025),
            gap: 5e-5,
        };
        let points = manifold(plate, (half, cube[1].pose()), Vec3::Z, witness);
        assert_eq!(points.len(), 5);
        let flat = Manifold {
            pair: (None, Some(1)),
            n: Vec3::Z,
            points,
        };
        assert_eq!(resolve(&mut cube, &[flat], &[], DT), (vec![1], false));
        for c in corners(half, &cube[1].pose())
            .into_iter()
            .filter(|c| c.z < 0.01)
        {
            assert!(cube[1].velocity_at(c).z > 0.5 * SEPARATION, "{c}");
        }
    }

    #[test]
    fn a_box_wedged_between_two_plates_leaves_both_at_once() {
        // A cube sinking into a V of two plates (normals up and inwards): each contact solved on
        // its own undid the other's impulses and the pair came back forever (seed 35 froze 32
        // of 90 steps); solved together, one call satisfies both and a second has nothing to do.
        let mut cube = bodies(2, 7, 0.0);
        cube[1].r = Mat3::IDENTITY;
        cube[1].v = Vec3::new(0.3, 0.0, -0.5);
        cube[1].w = Vec3::new(0.0, 4.0, 0.0);
        let (left, right) = (Vec3::new(-0.76, 0.0, 0.65), Vec3::new(1.0, 0.0, 0.0));
        let at = |n: Vec3, gap: f64| ContactPoint {
            p: cube[1].x - n.normalize() * 0.025,
            gap,
        };
        let wedge = [
            Manifold {
                pair: (None, Some(1)),
                n: left.normalize(),
                points: vec![at(left, 9.6e-5)],
            },
            Manifold {
                pair: (None, Some(1)),
                n: right,
                points: vec![at(right, 1.8e-5), at(right + Vec3::Y * 0.5, 1.8e-5)],
            },
        ];
        // Friction jams it (mu 0.5): it is freed without friction.
        assert_eq!(resolve(&mut cube, &wedge, &[], DT), (vec![1], true));
        for m in &wedge {
            for c in &m.points {
                let vn = cube[1].velocity_at(c.p).dot(m.n);
                assert!(vn > 0.75 * SEPARATION, "{vn} at {:?}", c.p);
            }
        }
        assert!(resolve(&mut cube, &wedge, &[], DT).0.is_empty());
        // Each alone, in turn (until the forty-third session): the second undoes the first, and
        // fifty rounds do not settle them.
        let mut alone = bodies(2, 7, 0.0);
        alone[1].r = Mat3::IDENTITY;
        alone[1].v = Vec3::new(0.3, 0.0, -0.5);
        alone[1].w = Vec3::new(0.0, 4.0, 0.0);
        let mut rounds = 0;
        while rounds < 50
            && wedge.iter().any(|m| {
                !resolve(&mut alone, std::slice::from_ref(m), &[], DT)
                    .0
                    .is_empty()
            })
        {
            rounds += 1;
        }
        assert_eq!(rounds, 50);
    }

    #[test]
    fn an_edge_with_its_witness_is_on_a_line_and_a_face_is_not() {
        let at = |x: f64, y: f64, z: f64| ContactPoint {
            p: Vec3::new(x, y, z),
            gap: 0.0,
        };
        // A rod's edge on a plate: two corners and the witness between them, a little off.
        assert!(on_a_line(&[
            at(0.03, 0.0, 2e-5),
            at(-0.1, 0.0, 0.0),
            at(0.1, 0.0, 0.0)
        ]));
        assert!(on_a_line(&[at(0.0, 0.0, 0.0)]));
        assert!(on_a_line(&[]));
        // A rod's face: its corners 16 mm apart across the edge.
        assert!(!on_a_line(&[
            at(0.0, 0.0, 0.0),
            at(-0.1, -0.008, 0.0),
            at(0.1, -0.008, 0.0),
            at(-0.1, 0.008, 0.0),
        ]));
    }
}
