//! Batch queries: identical to the single queries, in input order, whatever the thread count.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use tocsin::{
    collide, collide_batch, distance, distance_batch, mesh, motion_is_free, motion_is_free_batch,
    time_of_contact, time_of_contact_batch, ContactError, ContactOptions, DistanceOptions, Motion,
    Pose, Vec3,
};

fn with_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn batches_equal_single_queries_on_any_thread_count() {
    let mut rng = rng(60);
    let knot = mesh::torus_knot(80, 8).unwrap();
    let poses: Vec<(Pose, Pose)> = (0..40)
        .map(|_| (random_pose(&mut rng, 3.0), random_pose(&mut rng, 3.0)))
        .collect();
    let opts = DistanceOptions::default();
    let single: Vec<_> = poses
        .iter()
        .map(|(a, b)| distance(&knot, a, &knot, b, &opts).unwrap())
        .collect();
    let hits: Vec<_> = poses
        .iter()
        .map(|(a, b)| collide(&knot, a, &knot, b))
        .collect();
    assert!(hits.iter().any(|&h| h) && hits.iter().any(|&h| !h));
    let motions: Vec<(Motion, Motion)> = poses
        .iter()
        .map(|(a, b)| {
            let far = Pose {
                rotation: a.rotation,
                translation: a.translation + Vec3::new(12.0, 0.0, 0.0),
            };
            (Motion::screw(far, *a).unwrap(), Motion::stationary(*b))
        })
        .collect();
    let copts = ContactOptions::default();
    let toc: Vec<_> = motions
        .iter()
        .map(|(m1, m2)| time_of_contact(&knot, m1, &knot, m2, &copts))
        .collect();
    for threads in [1, 2, 4] {
        assert_eq!(
            with_threads(threads, || distance_batch(&knot, &knot, &poses, &opts)
                .unwrap()),
            single
        );
        assert_eq!(
            with_threads(threads, || collide_batch(&knot, &knot, &poses)),
            hits
        );
        assert_eq!(
            with_threads(threads, || time_of_contact_batch(
                &knot, &knot, &motions, &copts
            )
            .unwrap()),
            toc
        );
    }
    assert!(distance_batch(
        &knot,
        &knot,
        &poses,
        &DistanceOptions {
            relative_error: -1.0,
            absolute_error: 0.0
        }
    )
    .is_err());
    assert!(distance_batch(&knot, &knot, &[], &opts).unwrap().is_empty());
    // Options are checked even when there is nothing to run.
    let bad = DistanceOptions {
        relative_error: f64::NAN,
        absolute_error: 0.0,
    };
    assert!(distance_batch(&knot, &knot, &[], &bad).is_err());
    let bad = ContactOptions {
        tolerance: Some(-1.0),
        ..Default::default()
    };
    assert!(time_of_contact_batch(&knot, &knot, &[], &bad).is_err());
    let bad = ContactOptions {
        max_iterations: 0,
        ..Default::default()
    };
    assert!(time_of_contact_batch(&knot, &knot, &[], &bad).is_err());
}

/// `motion_is_free_batch`: the single `motion_is_free` answers, in input order, on any thread
/// count; free exactly where the time of contact finds none; an iteration cap is the row's own
/// error; bad options are refused before anything runs.
#[test]
fn motion_is_free_batch_equals_single_queries() {
    let mut rng = rng(61);
    let knot = mesh::torus_knot(80, 8).unwrap();
    let motions: Vec<(Motion, Motion)> = (0..40)
        .map(|k| {
            let a = random_pose(&mut rng, 3.0);
            // Every other motion passes well clear of the copy (sideways by 14).
            let side = if k % 2 == 0 { 0.0 } else { 14.0 };
            let shifted = |x: f64| Pose {
                rotation: a.rotation,
                translation: a.translation + Vec3::new(x, side, 0.0),
            };
            (
                Motion::screw(shifted(12.0), shifted(-12.0)).unwrap(),
                Motion::stationary(Pose::IDENTITY),
            )
        })
        .collect();
    let opts = ContactOptions::default();
    let single: Vec<bool> = motions
        .iter()
        .map(|(m1, m2)| motion_is_free(&knot, m1, &knot, m2, &opts).unwrap())
        .collect();
    assert!(single.iter().any(|&f| f) && single.iter().any(|&f| !f));
    for ((m1, m2), free) in motions.iter().zip(&single) {
        let toc = time_of_contact(&knot, m1, &knot, m2, &opts).unwrap();
        assert_eq!(*free, toc.is_none());
    }
    for threads in [1, 2, 4] {
        let batch = with_threads(threads, || {
            motion_is_free_batch(&knot, &knot, &motions, &opts).unwrap()
        });
        let batch: Vec<bool> = batch.into_iter().map(Result::unwrap).collect();
        assert_eq!(batch, single);
    }
    // Capped at one iteration: each row is the single query's answer or its error.
    let capped = ContactOptions {
        max_iterations: 1,
        ..Default::default()
    };
    let rows = motion_is_free_batch(&knot, &knot, &motions, &capped).unwrap();
    let mut limits = 0;
    for ((m1, m2), row) in motions.iter().zip(&rows) {
        let one = motion_is_free(&knot, m1, &knot, m2, &capped);
        assert_eq!(format!("{row:?}"), format!("{one:?}"));
        if matches!(row, Err(ContactError::IterationLimit { .. })) {
            limits += 1;
        }
    }
    assert!(limits > 0, "no row reached the cap of one iteration");
    let bad = ContactOptions {
        tolerance: Some(f64::NAN),
        ..Default::default()
    };
    assert!(motion_is_free_batch(&knot, &knot, &[], &bad).is_err());
    assert!(motion_is_free_batch(&knot, &knot, &[], &opts)
        .unwrap()
        .is_empty());
}
