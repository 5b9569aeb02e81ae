//! Many bodies: a [`World`] of meshes, each moving by a rigid [`Motion`] over the step (or
//! static), and the queries over all of them at once.
//!
//! Pipeline of [`first_contacts`] and [`earliest_contact`]:
//! 1. each body's conservative swept box over the step ([`swept`]), grown by half the largest
//!    tolerance a pair with it can use, so that a pair whose boxes do not meet stays farther
//!    apart than its tolerance over the whole step;
//! 2. the broad phase: sort and sweep over those boxes ([`broad`]), in parallel; pairs of two
//!    static bodies are dropped;
//! 3. each candidate pair's boxes and balls over eight slices of the step: a pair whose boxes
//!    and balls do not both meet in some slice is dropped, and the first slice where they do is
//!    its earliest possible contact;
//! 4. the narrow phase: [`crate::time_of_contact`] on each remaining pair, in parallel, with the
//!    same options a caller would pass for that pair alone, so every pair's answer is the
//!    single query's, bit for bit. [`earliest_contact`] runs the pairs by earliest possible
//!    contact and skips those that cannot beat the best time found.
//!
//! Meshes are shared: bodies added with clones of one `Arc<TriMesh>` use one hierarchy and one
//! box (a thousand copies of a part cost one part).

pub mod broad;
#[cfg(feature = "cuda")]
pub mod gpu;
mod grid;
pub mod swept;

use crate::error::{ContactError, OptionsError};
use crate::math::{Pose, Vec3};
use crate::motion::Motion;
use crate::query::contact_time::{check_options, time_of_contact, ContactOptions, ContactTime};
use crate::TriMesh;
use broad::{sweep_and_prune, SweepAxis};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use swept::{swept_ball, swept_box, Aabb};

/// Slices of the step a candidate pair's boxes are checked over (pipeline step 3).
pub const SLICES: usize = 8;

/// A query over a world failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WorldError {
    /// An option is invalid.
    #[error(transparent)]
    Options(#[from] OptionsError),
    /// A body index is out of range.
    #[error("body {index} does not exist: the world has {len} bodies")]
    UnknownBody {
        /// The index given.
        index: usize,
        /// Number of bodies.
        len: usize,
    },
    /// A list of poses or motions does not have one entry per body.
    #[error("expected {expected} poses, one per body, got {got}")]
    Count {
        /// Number of bodies.
        expected: usize,
        /// Number given.
        got: usize,
    },
    /// A pair's time of contact reached its iteration cap.
    #[error("bodies {body1} and {body2}: {source}")]
    Contact {
        /// First body of the pair.
        body1: usize,
        /// Second body of the pair.
        body2: usize,
        /// What the pair's query said.
        source: ContactError,
    },
}

/// One body: which mesh, how it moves, and whether it is static (two static bodies are never
/// checked against each other).
#[derive(Clone, Copy, Debug)]
struct Body {
    mesh: usize,
    motion: Motion,
    fixed: bool,
}

/// A candidate pair `(slice, i, j)`: the first slice of the step where the boxes of bodies
/// `i < j` meet.
type SlicedPair = (usize, u32, u32);

/// A shared mesh, its box and a ball holding it, in its own frame.
#[derive(Clone, Debug)]
struct SharedMesh {
    mesh: Arc<TriMesh>,
    local: Aabb,
    /// Centre (the box's) and radius of a ball holding every vertex.
    ball: (Vec3, f64),
}

/// Bodies, each a shared mesh with a rigid motion over the step `t in [0, 1]`.
#[derive(Clone, Debug, Default)]
pub struct World {
    meshes: Vec<SharedMesh>,
    by_address: HashMap<usize, usize>,
    bodies: Vec<Body>,
}

/// Options of the world queries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorldOptions {
    /// Each pair's time-of-contact options (the tolerance, when `None`, is each pair's own
    /// default: [`crate::query::contact_time::effective_tolerance`]).
    pub contact: ContactOptions,
    /// The broad phase's sweep axis.
    pub axis: SweepAxis,
}

/// A pair of bodies that comes within its tolerance during the step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldContact {
    /// The smaller body index.
    pub body1: usize,
    /// The larger body index.
    pub body2: usize,
    /// The pair's first contact, as [`crate::time_of_contact`] of `body1` (mesh 1) and `body2`
    /// (mesh 2) gives it: time, world-frame points, normal from `body1` to `body2`.
    pub contact: ContactTime,
}

/// Every pair's first contact in a step, and what the phases did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FirstContacts {
    /// The contacts, sorted by time, then `body1`, then `body2`.
    pub contacts: Vec<WorldContact>,
    /// Pairs whose swept boxes met over the whole step (broad phase output).
    pub candidates: usize,
    /// Pairs whose boxes also met in a slice of the step, each run through the narrow phase.
    pub narrow: usize,
    /// Pairs whose query reached its iteration cap before it could answer, sorted by body
    /// indices: each is only known free of contact up to its `time_reached`.
    pub undecided: Vec<Undecided>,
}

/// A pair whose time-of-contact query reached its iteration cap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Undecided {
    /// The smaller body index.
    pub body1: usize,
    /// The larger body index.
    pub body2: usize,
    /// The pair is free of contact over `[0, time_reached]`; undecided after.
    pub time_reached: f64,
}

impl FirstContacts {
    /// The earliest contact (the first of `contacts`).
    pub fn earliest(&self) -> Option<&WorldContact> {
        self.contacts.first()
    }
}

impl World {
    /// An empty world.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a moving body; returns its index. Bodies given clones of one `Arc` share its
    /// hierarchy.
    pub fn add_body(&mut self, mesh: &Arc<TriMesh>, motion: Motion) -> usize {
        self.push(mesh, motion, false)
    }

    /// Adds a static body at `pose` (never checked against another static body); returns its
    /// index.
    pub fn add_static(&mut self, mesh: &Arc<TriMesh>, pose: Pose) -> usize {
        self.push(mesh, Motion::stationary(pose), true)
    }

    fn push(&mut self, mesh: &Arc<TriMesh>, motion: Motion, fixed: bool) -> usize {
        let address = Arc::as_ptr(mesh) as usize;
        let meshes = &mut self.meshes;
        let index = *self.by_address.entry(address).or_insert_with(|| {
            // A mesh has at least one triangle, hence a vertex.
            let local = Aabb::of_points(mesh.vertices()).unwrap_or(Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            });
            let c = local.center();
            let r = mesh
                .vertices()
                .iter()
                .map(|v| (*v - c).length())
                .fold(0.0, f64::max);
            // The rounding of the distances: a relative allowance.
            let ball = (c, r * (1.0 + 1e-12) + 1e-12 * c.length());
            meshes.push(SharedMesh {
                mesh: Arc::clone(mesh),
                local,
                ball,
            });
            meshes.len() - 1
        });
        self.bodies.push(Body {
            mesh: index,
            motion,
            fixed,
        });
        self.bodies.len() - 1
    }

    /// Sets body `index`'s motion over the next step.
    ///
    /// # Errors
    /// [`WorldError::UnknownBody`] for an index out of range.
    pub fn set_motion(&mut self, index: usize, motion: Motion) -> Result<(), WorldError> {
        let len = self.bodies.len();
        let body = self
            .bodies
            .get_mut(index)
            .ok_or(WorldError::UnknownBody { index, len })?;
        body.motion = motion;
        Ok(())
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Whether the world has no bodies.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Number of distinct meshes (hierarchies) the bodies share.
    pub fn num_meshes(&self) -> usize {
        self.meshes.len()
    }

    /// Body `index`'s mesh.
    ///
    /// # Panics
    /// When `index` is out of range.
    pub fn mesh(&self, index: usize) -> &Arc<TriMesh> {
        &self.meshes[self.bodies[index].mesh].mesh
    }

    /// Body `index`'s motion.
    ///
    /// # Panics
    /// When `index` is out of range.
    pub fn motion(&self, index: usize) -> &Motion {
        &self.bodies[index].motion
    }

    /// Whether body `index` is static.
    ///
    /// # Panics
    /// When `index` is out of range.
    pub fn is_static(&self, index: usize) -> bool {
        self.bodies[index].fixed
    }

    /// Every body's world pose at time `t` of the step.
    pub fn poses_at(&self, t: f64) -> Vec<Pose> {
        self.bodies.iter().map(|b| b.motion.pose_at(t)).collect()
    }

    /// Every body's conservative box over `[t0, t1]` of the step, grown by `margin` (world
    /// frame; [`swept`] says how it is bounded).
    pub fn swept_boxes(&self, t0: f64, t1: f64, margin: f64) -> Vec<Aabb> {
        self.bodies
            .par_iter()
            .map(|b| swept_box(&self.meshes[b.mesh].local, &b.motion, t0, t1, margin))
            .collect()
    }

    /// Each body's box margin: half the largest tolerance any pair with it can use (module
    /// docs), plus a rounding allowance.
    fn margins(&self, options: &ContactOptions) -> Vec<f64> {
        let radius = |b: &Body| self.meshes[b.mesh].mesh.bounding_radius();
        let reach = |b: &Body| {
            b.motion
                .start()
                .translation
                .length()
                .max(b.motion.end().translation.length())
        };
        let r_max = self.bodies.iter().map(radius).fold(0.0, f64::max);
        let reach_max = self.bodies.iter().map(reach).fold(0.0, f64::max);
        let scale = 2.0 * (r_max + reach_max);
        self.bodies
            .iter()
            .map(|b| {
                let delta = options.tolerance.unwrap_or_else(|| {
                    (1e-3 * radius(b))
                        .max(1e-6 * r_max)
                        .max(1e-12 * scale)
                        .max(f64::MIN_POSITIVE)
                });
                0.5 * delta + 1e-12 * (scale + reach(b))
            })
            .collect()
    }

    /// The broad phase over the whole step (pipeline steps 1 and 2): every pair `(i, j)`,
    /// `i < j`, not both static, whose swept boxes meet, sorted.
    ///
    /// # Errors
    /// [`WorldError::Options`] for a bad tolerance.
    pub fn candidate_pairs(&self, options: &WorldOptions) -> Result<Vec<(u32, u32)>, WorldError> {
        check_options(&options.contact)?;
        Ok(self.swept_pairs(options, &self.margins(&options.contact)))
    }

    /// [`World::candidate_pairs`] with the bodies' box margins given.
    fn swept_pairs(&self, options: &WorldOptions, margins: &[f64]) -> Vec<(u32, u32)> {
        let boxes: Vec<Aabb> = self
            .bodies
            .par_iter()
            .zip(margins.par_iter())
            .map(|(b, &m)| swept_box(&self.meshes[b.mesh].local, &b.motion, 0.0, 1.0, m))
            .collect();
        let mut pairs = sweep_and_prune(&boxes, options.axis);
        pairs.retain(|&(i, j)| !(self.bodies[i as usize].fixed && self.bodies[j as usize].fixed));
        pairs
    }

    /// Candidate pairs with the first slice of the step where their boxes meet (pipeline step
    /// 3); pairs meeting in no slice are dropped.
    fn sliced_candidates(
        &self,
        options: &WorldOptions,
        among: Option<&[bool]>,
    ) -> Result<(usize, Vec<SlicedPair>), WorldError> {
        check_options(&options.contact)?;
        let margins = self.margins(&options.contact);
        let mut pairs = self.swept_pairs(options, &margins);
        if let Some(mask) = among {
            pairs.retain(|&(i, j)| mask[i as usize] || mask[j as usize]);
        }
        let mut used = vec![false; self.bodies.len()];
        for &(i, j) in &pairs {
            used[i as usize] = true;
            used[j as usize] = true;
        }
        type Slices = [(Aabb, (Vec3, f64)); SLICES];
        let slices: Vec<Option<Slices>> = (0..self.bodies.len())
            .into_par_iter()
            .map(|i| {
                used[i].then(|| {
                    let b = &self.bodies[i];
                    let shared = &self.meshes[b.mesh];
                    std::array::from_fn(|s| {
                        let (t0, t1) = (s as f64 / SLICES as f64, (s + 1) as f64 / SLICES as f64);
                        let (c, r) = swept_ball(shared.ball.0, shared.ball.1, &b.motion, t0, t1);
                        let rounding = 1e-12 * c.length();
                        (
                            swept_box(&shared.local, &b.motion, t0, t1, margins[i]),
                            (c, r + margins[i] + rounding),
                        )
                    })
                })
            })
            .collect();
        let sliced = pairs
            .par_iter()
            .filter_map(|&(i, j)| {
                let (a, b) = (slices[i as usize]?, slices[j as usize]?);
                (0..SLICES)
                    .find(|&s| {
                        let ((box_a, ball_a), (box_b, ball_b)) = (a[s], b[s]);
                        box_a.overlaps(&box_b)
                            && (ball_a.0 - ball_b.0).length() <= ball_a.1 + ball_b.1
                    })
                    .map(|s| (s, i, j))
            })
            .collect();
        Ok((pairs.len(), sliced))
    }

    /// The single query on bodies `i < j`.
    fn pair_contact(
        &self,
        i: usize,
        j: usize,
        options: &ContactOptions,
    ) -> Result<Option<WorldContact>, WorldError> {
        let (a, b) = (&self.bodies[i], &self.bodies[j]);
        time_of_contact(
            &self.meshes[a.mesh].mesh,
            &a.motion,
            &self.meshes[b.mesh].mesh,
            &b.motion,
            options,
        )
        .map(|c| {
            c.map(|contact| WorldContact {
                body1: i,
                body2: j,
                contact,
            })
        })
        .map_err(|source| WorldError::Contact {
            body1: i,
            body2: j,
            source,
        })
    }

    fn check_poses(&self, poses: &[Pose]) -> Result<(), WorldError> {
        if poses.len() != self.bodies.len() {
            return Err(WorldError::Count {
                expected: self.bodies.len(),
                got: poses.len(),
            });
        }
        Ok(())
    }

    /// Pairs (not both static) whose boxes at `poses`, grown by `margin` each, meet.
    fn static_candidates(&self, poses: &[Pose], margin: f64) -> Vec<(u32, u32)> {
        let boxes: Vec<Aabb> = self
            .bodies
            .par_iter()
            .zip(poses.par_iter())
            .map(|(b, p)| {
                let shared = &self.meshes[b.mesh];
                let rounding = 1e-12 * (p.translation.length() + shared.mesh.bounding_radius());
                shared.local.placed(p).inflated(margin + rounding)
            })
            .collect();
        let mut pairs = sweep_and_prune(&boxes, SweepAxis::Principal);
        pairs.retain(|&(i, j)| !(self.bodies[i as usize].fixed && self.bodies[j as usize].fixed));
        pairs
    }
}

/// Every pair of bodies that comes within its tolerance during the step, each with the first
/// contact the single [`crate::time_of_contact`] reports for it (module docs). A pair whose
/// query reaches its iteration cap is listed in [`FirstContacts::undecided`] with the time up
/// to which it is known free (a simulation can advance that far), not made an error for all.
///
/// # Errors
/// [`WorldError::Options`] for bad options.
pub fn first_contacts(world: &World, options: &WorldOptions) -> Result<FirstContacts, WorldError> {
    contacts_of(world, options, None)
}

/// [`first_contacts`] restricted to the pairs with at least one body in `bodies`: what a
/// simulation asks again after changing the motions of a few bodies (the other pairs' answers
/// still hold). Each pair's answer is the single query's, as in [`first_contacts`].
///
/// # Errors
/// [`WorldError::Options`] for bad options, [`WorldError::UnknownBody`] for an index out of
/// range.
pub fn first_contacts_among(
    world: &World,
    options: &WorldOptions,
    bodies: &[usize],
) -> Result<FirstContacts, WorldError> {
    let len = world.len();
    let mut mask = vec![false; len];
    for &index in bodies {
        *mask
            .get_mut(index)
            .ok_or(WorldError::UnknownBody { index, len })? = true;
    }
    contacts_of(world, options, Some(&mask))
}

fn contacts_of(
    world: &World,
    options: &WorldOptions,
    among: Option<&[bool]>,
) -> Result<FirstContacts, WorldError> {
    let (candidates, sliced) = world.sliced_candidates(options, among)?;
    let found: Vec<Result<Option<WorldContact>, WorldError>> = sliced
        .par_iter()
        .map(|&(_, i, j)| world.pair_contact(i as usize, j as usize, &options.contact))
        .collect();
    let mut contacts = Vec::new();
    let mut undecided = Vec::new();
    for r in found {
        match r {
            Ok(Some(c)) => contacts.push(c),
            Ok(None) => {}
            Err(WorldError::Contact {
                body1,
                body2,
                source: ContactError::IterationLimit { time_reached, .. },
            }) => undecided.push(Undecided {
                body1,
                body2,
                time_reached,
            }),
            Err(e) => return Err(e),
        }
    }
    contacts.sort_by(order);
    undecided.sort_by_key(|u| (u.body1, u.body2));
    Ok(FirstContacts {
        contacts,
        candidates,
        narrow: sliced.len(),
        undecided,
    })
}

/// Order of contacts: time, then body indices.
fn order(a: &WorldContact, b: &WorldContact) -> std::cmp::Ordering {
    a.contact
        .time
        .total_cmp(&b.contact.time)
        .then(a.body1.cmp(&b.body1))
        .then(a.body2.cmp(&b.body2))
}

/// The earliest of [`first_contacts`] (ties by body indices), found without running the pairs
/// whose earliest possible contact comes after the best time already found.
///
/// # Errors
/// [`WorldError::Options`] for bad options; [`WorldError::Contact`] for a pair it ran whose
/// query reached its iteration cap (the earliest contact is then unknown).
pub fn earliest_contact(
    world: &World,
    options: &WorldOptions,
) -> Result<Option<WorldContact>, WorldError> {
    let (_, mut sliced) = world.sliced_candidates(options, None)?;
    sliced.sort_unstable();
    // Times are >= 0, so their bit patterns order as the numbers do.
    let best = AtomicU64::new(f64::INFINITY.to_bits());
    let batch = 4 * rayon::current_num_threads().max(1);
    let mut winner: Option<WorldContact> = None;
    for chunk in sliced.chunks(batch) {
        let slice_start = chunk[0].0 as f64 / SLICES as f64;
        if slice_start > f64::from_bits(best.load(Ordering::Relaxed)) {
            break;
        }
        let found: Vec<Result<Option<WorldContact>, WorldError>> = chunk
            .par_iter()
            .map(|&(s, i, j)| {
                if s as f64 / SLICES as f64 > f64::from_bits(best.load(Ordering::Relaxed)) {
                    return Ok(None);
                }
                let c = world.pair_contact(i as usize, j as usize, &options.contact)?;
                if let Some(c) = &c {
                    best.fetch_min(c.contact.time.to_bits(), Ordering::Relaxed);
                }
                Ok(c)
            })
            .collect();
        for c in found {
            if let Some(c) = c? {
                if winner.is_none_or(|w| order(&c, &w).is_lt()) {
                    winner = Some(c);
                }
            }
        }
    }
    Ok(winner)
}

/// Pairs of bodies (not both static) whose meshes touch or intersect at `poses` (one per
/// body), sorted.
///
/// # Errors
/// [`WorldError::Count`] when `poses` does not have one pose per body.
pub fn colliding_pairs(world: &World, poses: &[Pose]) -> Result<Vec<(usize, usize)>, WorldError> {
    world.check_poses(poses)?;
    let pairs = world.static_candidates(poses, 0.0);
    Ok(pairs
        .par_iter()
        .filter(|&&(i, j)| {
            let (i, j) = (i as usize, j as usize);
            crate::collide(world.mesh(i), &poses[i], world.mesh(j), &poses[j])
        })
        .map(|&(i, j)| (i as usize, j as usize))
        .collect())
}

/// Pairs of bodies (not both static) whose meshes are at most `distance` apart at `poses`,
/// sorted.
///
/// # Errors
/// [`WorldError::Count`] for a wrong number of poses, [`WorldError::Options`] for a negative or
/// non-finite distance.
pub fn pairs_within(
    world: &World,
    poses: &[Pose],
    distance: f64,
) -> Result<Vec<(usize, usize)>, WorldError> {
    world.check_poses(poses)?;
    if !(distance.is_finite() && distance >= 0.0) {
        return Err(OptionsError::OutOfRange {
            name: "distance",
            requirement: "must be finite and at least 0",
            value: distance,
        }
        .into());
    }
    let pairs = world.static_candidates(poses, 0.5 * distance * (1.0 + 1e-12));
    let within: Vec<Result<Option<(usize, usize)>, OptionsError>> = pairs
        .par_iter()
        .map(|&(i, j)| {
            let (i, j) = (i as usize, j as usize);
            crate::within_distance(world.mesh(i), &poses[i], world.mesh(j), &poses[j], distance)
                .map(|w| w.then_some((i, j)))
        })
        .collect();
    let mut out = Vec::new();
    for w in within {
        if let Some(p) = w? {
            out.push(p);
        }
    }
    Ok(out)
}
