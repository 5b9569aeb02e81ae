//! The hierarchy's invariant: every triangle lies inside the RSS of its leaf and of every
//! ancestor, and the tree covers each triangle exactly once.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use tocsin::bvh::Rss;
use tocsin::{mesh, TriMesh, Vec3};

/// Whether `p` is inside the volume, allowing only this check's own rounding (a few units in
/// the last place of the coordinates), not a relative slack on the radius: flat volumes have
/// radii of rounding size, and their margin is what is being tested.
fn inside(rss: &Rss, p: Vec3) -> bool {
    let q = rss.axes.transpose() * (p - rss.center);
    let dx = (q.x.abs() - rss.half_lengths[0]).max(0.0);
    let dy = (q.y.abs() - rss.half_lengths[1]).max(0.0);
    let own_rounding = 1e-15 * (p.length() + rss.center.length());
    (dx * dx + dy * dy + q.z * q.z).sqrt() <= rss.radius + own_rounding
}

fn check(m: &TriMesh) {
    let bvh = m.bvh();
    let nodes = bvh.nodes();
    assert_eq!(nodes.len(), 2 * m.num_triangles() - 1);
    // The separating-axis bounds take the axes as an orthonormal right-handed frame; a
    // degenerate axis would still "contain" every point (its coordinate is always 0).
    for (k, node) in nodes.iter().enumerate() {
        let a = node.rss.axes;
        let gram = a.transpose() * a;
        let off = (gram - tocsin::Mat3::IDENTITY).to_cols_array();
        assert!(
            off.iter().all(|x| x.abs() < 1e-12) && a.determinant() > 0.0,
            "node {k}: axes {a:?} are not a rotation"
        );
    }
    let mut seen = vec![0; m.num_triangles()];
    // (node index, ancestors)
    let mut stack = vec![(0u32, Vec::<u32>::new())];
    while let Some((i, mut path)) = stack.pop() {
        let node = &nodes[i as usize];
        path.push(i);
        if node.is_leaf() {
            let tri = bvh.triangle_index(node.leaf_position());
            seen[tri] += 1;
            assert_eq!(
                bvh.leaf_triangles()[node.leaf_position() as usize],
                m.triangle(tri)
            );
            for &a in &path {
                for p in m.triangle(tri) {
                    assert!(
                        inside(&nodes[a as usize].rss, p),
                        "vertex {p} outside node {a}"
                    );
                }
            }
        } else {
            let (l, r) = node.children(i);
            stack.push((l, path.clone()));
            stack.push((r, path));
        }
    }
    assert!(seen.iter().all(|&c| c == 1));
}

#[test]
fn volumes_contain_their_triangles() {
    let mut rng = rng(30);
    for scale in [1e-3, 1.0, 1e4] {
        for n in [1, 2, 3, 17, 64] {
            check(&random_soup(&mut rng, n, scale));
        }
    }
    // Flat and far from the origin: radii are the margin alone.
    for offset in [1.0, 1e3, 1e6] {
        let plate = mesh::plate(2.0, 12).unwrap();
        let turn =
            tocsin::Pose::from_axis_angle(Vec3::new(0.3, -0.7, 0.2), 0.9, Vec3::splat(offset));
        let moved: Vec<Vec3> = plate
            .vertices()
            .iter()
            .map(|&v| turn.transform_point(v))
            .collect();
        check(&TriMesh::new(moved, plate.triangles().to_vec()).unwrap());
    }
    check(&mesh::torus_knot(175, 8).unwrap());
    check(&mesh::plate(2.0, 10).unwrap());
    // Small meshes get their rectangles turned to an edge direction (boxes, primitives): a box
    // whose faces' edges run along the normal once gave a zero axis.
    for h in [
        [0.02, 0.4, 0.4],
        [0.6, 1.0, 0.02],
        [1.0, 1.0, 1.0],
        [0.5, 0.3, 1e-9],
    ] {
        check(&mesh::box_mesh(Vec3::from_array(h)).unwrap());
    }
    check(&mesh::cylinder(0.05, 0.3).unwrap());
    check(&mesh::capsule(0.2, 0.0).unwrap());
    for n in [5, 40, 200] {
        check(&random_soup(&mut rng, n, 1.0));
    }
    // All triangles identical: the split must still terminate and cover each once.
    let v = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    check(&TriMesh::new(v, vec![[0, 1, 2]; 50]).unwrap());
}

#[test]
fn build_is_deterministic() {
    let a = mesh::torus_knot(344, 16).unwrap();
    let b = mesh::torus_knot(344, 16).unwrap();
    let key = |m: &TriMesh| {
        m.bvh()
            .nodes()
            .iter()
            .map(|n| (n.rss.center.to_array(), n.rss.radius))
            .collect::<Vec<_>>()
    };
    assert_eq!(key(&a), key(&b));
}

/// A tube of slivers that each span its whole length (`n_around` quads, one ring).
fn sliver_tube(n_around: usize, length: f64) -> TriMesh {
    let mut v = Vec::new();
    for h in [-0.5 * length, 0.5 * length] {
        for j in 0..n_around {
            let a = std::f64::consts::TAU * j as f64 / n_around as f64;
            v.push(Vec3::new(a.cos(), a.sin(), h));
        }
    }
    let n = n_around as u32;
    let f = (0..n)
        .flat_map(|j| {
            let q = (j + 1) % n;
            [[j, q, q + n], [j, q + n, j + n]]
        })
        .collect();
    TriMesh::new(v, f).unwrap()
}

#[test]
fn slivers_spanning_a_tube_are_split_across_it() {
    // Split at the mean centroid along the tube (its first principal axis), each child would
    // again hold a triangle of every quad and span the whole tube; the build must split across.
    for n_around in [16, 64, 600] {
        let m = sliver_tube(n_around, 40.0);
        check(&m);
        let nodes = m.bvh().nodes();
        let (l, r) = nodes[0].children(0);
        let (a, b) = (nodes[l as usize].rss, nodes[r as usize].rss);
        let apart = (a.center - b.center).truncate();
        assert!(
            apart.length() > 0.5,
            "{n_around} slivers: children centred {} and {} (not split across the tube)",
            a.center,
            b.center
        );
    }
    // Ordinary meshes and fans of long thin triangles keep their containment.
    check(&mesh::torus_knot(12, 240).unwrap());
    check(&mesh::sphere(1.0, 64, 128).unwrap());
}
