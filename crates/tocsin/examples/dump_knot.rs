//! Writes a torus knot as OBJ to stdout: `cargo run --example dump_knot -- 680 25 > knot.obj`.
fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let (u, v) = (
        args.first().copied().unwrap_or(680),
        args.get(1).copied().unwrap_or(25),
    );
    let Ok(m) = tocsin::mesh::torus_knot(u, v) else {
        return;
    };
    for p in m.vertices() {
        println!("v {} {} {}", p.x, p.y, p.z);
    }
    for t in m.triangles() {
        println!("f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
}
