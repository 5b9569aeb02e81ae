//! Many-body benchmarks (docs/BENCHMARKS.md, "Many bodies"):
//!
//! 1. broad phase alone: random boxes in a unit cube, sized for about two overlapping pairs per
//!    box, sort and sweep on the principal axis and on the largest-variance coordinate axis,
//!    beside the all-pairs test and a BVH over the boxes (built and queried here, for the
//!    comparison only), on 1 and 2 threads; configurations interleaved, median of
//!    the repetitions;
//! 2. a whole step: N non-convex bodies (torus knots, the bunny when its OBJ is given, plates;
//!    three shared meshes) turning and moving by screw motions; the broad phase
//!    (`World::candidate_pairs`), `first_contacts` and `earliest_contact`, on 1 and 2 threads.
//!
//! 3. `pairs`: the single query on every broad-phase pair of the 10,000-body step, timed one by
//!    one and grouped by outcome (no contact, contact at the start, later) and mesh pair.
//!
//! 4. `gpu` (feature `cuda`, on a machine with a CUDA GPU): the broad phase of 1. on the GPU
//!    beside the CPU's on 1, 2 and all threads, the pairs checked equal; the GPU timed with the
//!    boxes already there (pairs found, left there), with the pairs copied back, and as the
//!    whole call from host boxes; interleaved, median of the repetitions.
//!
//! `cargo run --release --example bench_world [--features cuda] -- [broad|step|pairs|gpu|all]
//! [bunny.obj]`

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use std::time::Instant;
use tocsin::world::broad::{all_pairs, sweep_and_prune, SweepAxis};
use tocsin::world::swept::Aabb;
use tocsin::{
    earliest_contact, first_contacts, Mat3, Motion, Pose, TriMesh, Vec3, World, WorldOptions,
};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn boxes(n: usize, seed: u64) -> Vec<Aabb> {
    // Two boxes of half size s overlap with probability about (4 s)^3: N^2 / 2 (4 s)^3 = 2 N.
    let s = (1.0 / (16.0 * n as f64)).cbrt();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let c = Vec3::new(rng.random(), rng.random(), rng.random());
            Aabb {
                min: c - Vec3::splat(s),
                max: c + Vec3::splat(s),
            }
        })
        .collect()
}

/// A bounding volume hierarchy over the boxes (the other candidate for the broad
/// phase), for comparison only: median splits on the longest axis of the centres, leaves of up
/// to 4 boxes, then every box queried against the tree in parallel.
struct BoxTree {
    /// (box, first child or leaf start, count: 0 for an inner node)
    nodes: Vec<(Aabb, u32, u32)>,
    order: Vec<u32>,
}

impl BoxTree {
    fn build(boxes: &[Aabb]) -> Self {
        let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut nodes = Vec::with_capacity(boxes.len() / 2 + 1);
        nodes.push((
            boxes.first().copied().unwrap_or(Aabb {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
            }),
            0,
            0,
        ));
        let mut stack = vec![(0usize, 0usize, boxes.len())];
        while let Some((node, lo, hi)) = stack.pop() {
            let slice = &mut order[lo..hi];
            let bound = slice.iter().fold(boxes[slice[0] as usize], |a, &i| {
                a.union(&boxes[i as usize])
            });
            if hi - lo <= 4 {
                nodes[node] = (bound, lo as u32, (hi - lo) as u32);
                continue;
            }
            let e = bound.max - bound.min;
            let axis = if e.x >= e.y && e.x >= e.z {
                0
            } else if e.y >= e.z {
                1
            } else {
                2
            };
            let mid = (hi - lo) / 2;
            slice.select_nth_unstable_by(mid, |&a, &b| {
                boxes[a as usize].center()[axis].total_cmp(&boxes[b as usize].center()[axis])
            });
            let left = nodes.len();
            nodes.push((bound, 0, 0));
            nodes.push((bound, 0, 0));
            nodes[node] = (bound, left as u32, 0);
            stack.push((left, lo, lo + mid));
            stack.push((left + 1, lo + mid, hi));
        }
        Self { nodes, order }
    }

    fn pairs(&self, boxes: &[Aabb]) -> Vec<(u32, u32)> {
        use rayon::prelude::*;
        let mut out: Vec<(u32, u32)> = (0..boxes.len())
            .into_par_iter()
            .flat_map_iter(|i| {
                let b = boxes[i];
                let mut found = Vec::new();
                let mut stack = vec![0usize];
                while let Some(n) = stack.pop() {
                    let (bound, first, count) = self.nodes[n];
                    if !bound.overlaps(&b) {
                        continue;
                    }
                    if count == 0 {
                        stack.push(first as usize);
                        stack.push(first as usize + 1);
                    } else {
                        for &j in &self.order[first as usize..(first + count) as usize] {
                            if j as usize > i && boxes[j as usize].overlaps(&b) {
                                found.push((i as u32, j));
                            }
                        }
                    }
                }
                found
            })
            .collect();
        out.par_sort_unstable();
        out
    }
}

fn broad() {
    println!("| bodies | pairs | threads | sort and sweep, principal axis (ms) | largest-variance axis (ms) | all pairs (ms) | BVH over the boxes (ms) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for n in [500, 1_000, 2_000, 5_000, 10_000, 100_000, 1_000_000] {
        let b = boxes(n, n as u64);
        let reps = if n >= 1_000_000 { 5 } else { 11 };
        let pools = [pool(1), pool(2)];
        let mut t = vec![[Vec::new(), Vec::new(), Vec::new(), Vec::new()]; 2];
        let mut pairs = 0;
        for _ in 0..reps {
            for (k, p) in pools.iter().enumerate() {
                let clock = Instant::now();
                pairs = p
                    .install(|| sweep_and_prune(&b, SweepAxis::Principal))
                    .len();
                t[k][0].push(clock.elapsed().as_secs_f64() * 1e3);
                let clock = Instant::now();
                p.install(|| sweep_and_prune(&b, SweepAxis::LargestVariance));
                t[k][1].push(clock.elapsed().as_secs_f64() * 1e3);
                if n <= 10_000 {
                    let clock = Instant::now();
                    let all = p.install(|| all_pairs(&b)).len();
                    t[k][2].push(clock.elapsed().as_secs_f64() * 1e3);
                    assert_eq!(all, pairs);
                }
                let clock = Instant::now();
                let tree = p.install(|| BoxTree::build(&b).pairs(&b)).len();
                t[k][3].push(clock.elapsed().as_secs_f64() * 1e3);
                assert_eq!(tree, pairs);
            }
        }
        for (k, threads) in [1, 2].into_iter().enumerate() {
            let [a, v, all, tree] = t[k].clone();
            let all = if all.is_empty() {
                "-".to_string()
            } else {
                format!("{:.3}", median(all))
            };
            println!(
                "| {n} | {pairs} | {threads} | {:.3} | {:.3} | {all} | {:.3} |",
                median(a),
                median(v),
                median(tree)
            );
        }
    }
}

/// The three-axis grid beside the sweep in the coordinate frame (the pairs checked equal), on
/// random boxes and on the step's 10,000-body world (its candidate pairs and `first_contacts`).
fn grid_broad(bunny: Option<&str>) {
    println!("| boxes | pairs | threads | sort and sweep, largest-variance axis (ms) | three-axis grid (ms) |");
    println!("|---:|---:|---:|---:|---:|");
    for n in [500, 2_000, 10_000, 100_000, 1_000_000] {
        let b = boxes(n, n as u64);
        let reps = if n >= 1_000_000 { 7 } else { 21 };
        let pools = [pool(1), pool(2)];
        let mut t = vec![[Vec::new(), Vec::new()]; 2];
        let reference = sweep_and_prune(&b, SweepAxis::LargestVariance);
        assert_eq!(sweep_and_prune(&b, SweepAxis::Grid3), reference);
        for _ in 0..reps {
            for (k, p) in pools.iter().enumerate() {
                for (m, axis) in [SweepAxis::LargestVariance, SweepAxis::Grid3]
                    .into_iter()
                    .enumerate()
                {
                    let clock = Instant::now();
                    p.install(|| sweep_and_prune(&b, axis));
                    t[k][m].push(clock.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
        for (k, threads) in [1, 2].into_iter().enumerate() {
            let [v, g] = t[k].clone();
            println!(
                "| {n} | {} | {threads} | {:.3} | {:.3} |",
                reference.len(),
                median(v),
                median(g)
            );
        }
    }
    let meshes = step_meshes(bunny);
    let w = world(10_000, &meshes, 10_000);
    println!("| 10,000-body step | threads | candidates, sweep (ms) | candidates, grid (ms) | first_contacts, sweep (ms) | first_contacts, grid (ms) |");
    println!("|---|---:|---:|---:|---:|---:|");
    let axes = [SweepAxis::LargestVariance, SweepAxis::Grid3];
    let opts = axes.map(|axis| WorldOptions {
        axis,
        ..WorldOptions::default()
    });
    for (k, p) in [pool(1), pool(2)].iter().enumerate() {
        let mut t = vec![Vec::new(); 4];
        for _ in 0..7 {
            for (m, o) in opts.iter().enumerate() {
                let clock = Instant::now();
                p.install(|| w.candidate_pairs(o)).expect("broad");
                t[m].push(clock.elapsed().as_secs_f64() * 1e3);
                let clock = Instant::now();
                p.install(|| first_contacts(&w, o)).expect("contacts");
                t[2 + m].push(clock.elapsed().as_secs_f64() * 1e3);
            }
        }
        let m: Vec<f64> = t.into_iter().map(median).collect();
        println!(
            "| | {} | {:.2} | {:.2} | {:.2} | {:.2} |",
            k + 1,
            m[0],
            m[1],
            m[2],
            m[3]
        );
    }
}

#[cfg(feature = "cuda")]
fn gpu_broad() {
    use tocsin::world::gpu::GpuBroadPhase;
    let clock = Instant::now();
    let gpu = GpuBroadPhase::new().expect("a CUDA GPU");
    println!(
        "device: {}; kernels compiled and loaded in {:.0} ms",
        gpu.device_name().expect("name"),
        clock.elapsed().as_secs_f64() * 1e3
    );
    let all = std::thread::available_parallelism().map_or(2, |n| n.get());
    println!(
        "| boxes | pairs | CPU 1 thread (ms) | CPU 2 threads (ms) | CPU {all} threads (ms) | GPU, boxes there (ms) | + pairs to the host (ms) | GPU whole call (ms) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    let pools = [pool(1), pool(2), pool(all)];
    for n in [10_000, 100_000, 1_000_000, 4_000_000] {
        let b = boxes(n, n as u64);
        let cpu = pools[2].install(|| sweep_and_prune(&b, SweepAxis::LargestVariance));
        let on_gpu = pools[2]
            .install(|| gpu.sweep_and_prune(&b))
            .expect("gpu pairs");
        assert_eq!(
            cpu, on_gpu,
            "{n} boxes: the GPU's pairs differ from the CPU's"
        );
        let reps = if n >= 1_000_000 { 7 } else { 21 };
        let mut t = vec![Vec::new(); 6];
        let up = gpu.upload(&b).expect("upload");
        for _ in 0..reps {
            for (k, p) in pools.iter().enumerate() {
                if n >= 4_000_000 && k == 0 {
                    continue;
                }
                let clock = Instant::now();
                p.install(|| sweep_and_prune(&b, SweepAxis::LargestVariance));
                t[k].push(clock.elapsed().as_secs_f64() * 1e3);
            }
            let clock = Instant::now();
            let pairs = gpu.pairs(&up).expect("pairs").expect("a GPU plan");
            t[3].push(clock.elapsed().as_secs_f64() * 1e3);
            let v = pools[2].install(|| pairs.to_vec()).expect("to host");
            t[4].push(clock.elapsed().as_secs_f64() * 1e3);
            assert_eq!(v.len(), cpu.len());
            let clock = Instant::now();
            pools[2].install(|| gpu.sweep_and_prune(&b)).expect("gpu");
            t[5].push(clock.elapsed().as_secs_f64() * 1e3);
        }
        let m = |v: &Vec<f64>| {
            if v.is_empty() {
                "-".to_string()
            } else {
                format!("{:.2}", median(v.clone()))
            }
        };
        println!(
            "| {n} | {} | {} | {} | {} | {} | {} | {} |",
            cpu.len(),
            m(&t[0]),
            m(&t[1]),
            m(&t[2]),
            m(&t[3]),
            m(&t[4]),
            m(&t[5])
        );
    }
}

fn scaled(mesh: TriMesh, radius: f64) -> Arc<TriMesh> {
    let s = radius / mesh.bounding_radius();
    let c = mesh.vertices().iter().fold(Vec3::ZERO, |a, v| a + *v) / mesh.num_vertices() as f64;
    let v: Vec<Vec3> = mesh.vertices().iter().map(|v| (*v - c) * s).collect();
    Arc::new(TriMesh::new(v, mesh.triangles().to_vec()).expect("mesh"))
}

fn world(n: usize, meshes: &[Arc<TriMesh>], seed: u64) -> World {
    // Unit-radius bodies, 40 cubic units each: a body moves about half its radius and turns up
    // to 1 rad per step.
    let side = (40.0 * n as f64).cbrt();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut w = World::new();
    for k in 0..n {
        let axis = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .normalize();
        let start = Pose::from_axis_angle(
            axis,
            rng.random_range(0.0..3.0),
            Vec3::new(rng.random(), rng.random(), rng.random()) * side,
        );
        let turn = Mat3::from_axis_angle(axis.any_orthonormal_vector(), rng.random_range(0.0..1.0));
        let shift = Vec3::new(
            rng.random_range(-0.5..0.5),
            rng.random_range(-0.5..0.5),
            rng.random_range(-0.5..0.5),
        );
        let end = Pose::new(turn * start.rotation, start.translation + shift).expect("pose");
        let motion = Motion::screw(start, end).expect("motion");
        w.add_body(&meshes[k % meshes.len()], motion);
    }
    w
}

/// The step's three shared meshes: a knot, a plate, and the bunny (a smaller knot without it).
fn step_meshes(bunny: Option<&str>) -> Vec<Arc<TriMesh>> {
    let mut meshes = vec![
        scaled(tocsin::mesh::torus_knot(120, 12).expect("knot"), 1.0),
        scaled(tocsin::mesh::plate(1.0, 8).expect("plate"), 1.0),
    ];
    match bunny.map(TriMesh::load) {
        Some(Ok(b)) => meshes.push(scaled(b, 1.0)),
        _ => meshes.push(scaled(tocsin::mesh::torus_knot(60, 8).expect("knot"), 1.0)),
    }
    meshes
}

fn step(bunny: Option<&str>) {
    let meshes = step_meshes(bunny);
    let tris: Vec<usize> = meshes.iter().map(|m| m.num_triangles()).collect();
    println!("meshes (triangles): {tris:?}, bunny: {}", bunny.is_some());
    println!("| bodies | threads | candidates | narrow | contacts | broad phase (ms) | first_contacts (ms) | narrow phase (ms) | earliest_contact (ms) |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let opts = WorldOptions::default();
    for n in [1_000, 10_000] {
        let w = world(n, &meshes, n as u64);
        let pools = [pool(1), pool(2)];
        let mut t = vec![[Vec::new(), Vec::new(), Vec::new()]; 2];
        let mut counts = (0, 0, 0);
        for _ in 0..7 {
            for (k, p) in pools.iter().enumerate() {
                let clock = Instant::now();
                let c = p.install(|| w.candidate_pairs(&opts)).expect("broad");
                t[k][0].push(clock.elapsed().as_secs_f64() * 1e3);
                let clock = Instant::now();
                let f = p.install(|| first_contacts(&w, &opts)).expect("contacts");
                t[k][1].push(clock.elapsed().as_secs_f64() * 1e3);
                let clock = Instant::now();
                let e = p.install(|| earliest_contact(&w, &opts)).expect("earliest");
                t[k][2].push(clock.elapsed().as_secs_f64() * 1e3);
                assert_eq!(e.as_ref(), f.contacts.first());
                assert!(f.undecided.is_empty());
                counts = (c.len(), f.narrow, f.contacts.len());
            }
        }
        for (k, threads) in [1, 2].into_iter().enumerate() {
            let [b, f, e] = t[k].clone();
            let (b, f, e) = (median(b), median(f), median(e));
            println!(
                "| {n} | {threads} | {} | {} | {} | {b:.2} | {f:.2} | {:.2} | {e:.2} |",
                counts.0,
                counts.1,
                counts.2,
                f - b
            );
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let what = args.get(1).map_or("all", String::as_str);
    if what == "broad" || what == "all" {
        broad();
    }
    if what == "grid" {
        grid_broad(args.get(2).map(String::as_str));
    }
    #[cfg(feature = "cuda")]
    if what == "gpu" {
        gpu_broad();
    }
    if what == "one" {
        let n: usize = args
            .get(2)
            .and_then(|s| s.parse().ok())
            .unwrap_or(1_000_000);
        let b = boxes(n, n as u64);
        for _ in 0..5 {
            let clock = Instant::now();
            let p = sweep_and_prune(&b, SweepAxis::LargestVariance).len();
            println!(
                "{n} boxes, {p} pairs: {:.1} ms",
                clock.elapsed().as_secs_f64() * 1e3
            );
        }
    }
    if what == "pairs" {
        let meshes = vec![
            scaled(tocsin::mesh::torus_knot(120, 12).expect("knot"), 1.0),
            scaled(tocsin::mesh::plate(1.0, 8).expect("plate"), 1.0),
            scaled(
                TriMesh::load(args.get(2).expect("pairs needs the bunny's OBJ")).expect("bunny"),
                1.0,
            ),
        ];
        let w = world(10_000, &meshes, 10_000);
        let f = first_contacts(&w, &WorldOptions::default()).expect("contacts");
        let pairs = w.candidate_pairs(&WorldOptions::default()).expect("broad");
        let mut stats = std::collections::BTreeMap::new();
        for &(i, j) in &pairs {
            let (i, j) = (i as usize, j as usize);
            let clock = Instant::now();
            let c = tocsin::time_of_contact(
                w.mesh(i),
                w.motion(i),
                w.mesh(j),
                w.motion(j),
                &Default::default(),
            )
            .expect("toc");
            let dt = clock.elapsed().as_secs_f64() * 1e6;
            let key = match c {
                None => "none",
                Some(c) if c.time == 0.0 => "start",
                Some(_) => "later",
            };
            let kinds = (i % 3).min(j % 3) * 10 + (i % 3).max(j % 3);
            let e = stats.entry((key, kinds)).or_insert((0usize, 0.0f64));
            e.0 += 1;
            e.1 += dt;
        }
        println!("narrow {} of {} candidates", f.narrow, pairs.len());
        for ((k, kinds), (n, t)) in stats {
            println!(
                "{k} meshes {kinds:02}: {n} pairs, {:.1} ms total, {:.1} us each",
                t / 1e3,
                t / n as f64
            );
        }
    }
    if what == "step" || what == "all" {
        step(args.get(2).map(String::as_str));
    }
}
