//! Builds a 1,000,000-triangle torus knot a few times, for profiling the hierarchy build.
fn main() {
    let Ok(m) = tocsin::mesh::torus_knot(2000, 250) else {
        return;
    };
    let (v, t) = (m.vertices().to_vec(), m.triangles().to_vec());
    for _ in 0..3 {
        let start = std::time::Instant::now();
        let built = tocsin::TriMesh::new(v.clone(), t.clone());
        println!(
            "{} triangles built in {:?}",
            built.map(|m| m.num_triangles()).unwrap_or(0),
            start.elapsed()
        );
    }
}
