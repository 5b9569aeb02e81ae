//! Mesh files as exporters write them (hardening issue): OBJ polylines, points and short or
//! truncated faces; byte-order marks; ASCII STL with NaN normals, several solids, upper-case
//! keywords, polygons; binary STL whose header starts with "solid"; scene-relative paths are
//! the CLI's. Each case checks the triangles read against the ones the file describes.

#![allow(clippy::unwrap_used, clippy::panic)]

use tocsin::{MeshError, TriMesh, Vec3};

fn tmp(name: &str, content: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tocsin-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// The mesh's triangles as sorted corner coordinates, for comparing files written differently.
fn corners(m: &TriMesh) -> Vec<[[i64; 3]; 3]> {
    let key = |v: Vec3| [v.x, v.y, v.z].map(|c| (c * 1e6).round() as i64);
    let mut out: Vec<_> = (0..m.num_triangles())
        .map(|i| {
            let mut t = m.triangle(i).map(key);
            t.sort();
            t
        })
        .collect();
    out.sort();
    out
}

const SQUARE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";

#[test]
fn obj_points_lines_and_short_faces_are_not_triangles() {
    let clean = TriMesh::load(tmp("clean.obj", SQUARE_OBJ.as_bytes())).unwrap();
    assert_eq!(clean.num_triangles(), 2);
    let messy = format!("{SQUARE_OBJ}v 5 5 5\nv 6 6 6\nl 1 5 6\nl 2 3\np 6\nf 1 5\nf 2\nf 3 6"); // the last face is truncated (no third vertex, no newline)
    let m = TriMesh::load(tmp("messy.obj", messy.as_bytes())).unwrap();
    assert_eq!(
        corners(&m),
        corners(&clean),
        "extra triangles from lines or short faces"
    );
}

#[test]
fn a_byte_order_mark_is_skipped() {
    let with_bom = [b"\xEF\xBB\xBF".as_slice(), SQUARE_OBJ.as_bytes()].concat();
    let m = TriMesh::load(tmp("bom.obj", &with_bom)).unwrap();
    assert_eq!(m.num_vertices(), 4);
    assert_eq!(m.num_triangles(), 2);
    let stl = "\u{feff}solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
    assert_eq!(
        TriMesh::load(tmp("bom.stl", stl.as_bytes()))
            .unwrap()
            .num_triangles(),
        1
    );
}

fn facet(normal: &str, v: [[f64; 3]; 3]) -> String {
    let mut s = format!("  facet normal {normal}\n    outer loop\n");
    for p in v {
        s += &format!("      vertex {} {} {}\n", p[0], p[1], p[2]);
    }
    s + "    endloop\n  endfacet\n"
}

#[test]
fn ascii_stl_as_cad_exporters_write_it() {
    let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let b = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
    let degenerate = [[2.0, 2.0, 2.0], [2.0, 2.0, 2.0], [3.0, 3.0, 3.0]];
    // NaN normals on a degenerate facet, two solids, upper-case keywords in the second.
    let text = format!(
        "solid first\n{}{}endsolid first\nSOLID second\n{}ENDSOLID second\n",
        facet("0 0 1", a),
        facet("nan nan nan", degenerate),
        facet("0 0 1", b).to_uppercase().replace("E+", "e+"),
    );
    let m = TriMesh::load(tmp("cad.stl", text.as_bytes())).unwrap();
    assert_eq!(m.num_triangles(), 3, "every facet of every solid");
    assert_eq!(m.num_vertices(), 8, "identical vertices merged");
    // The second solid's triangle is really there (at z = 1).
    assert!((0..3).any(|i| m.triangle(i).iter().all(|v| v.z == 1.0)));
    // A quad facet is fanned into two triangles.
    let quad = "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid q\n";
    assert_eq!(
        TriMesh::load(tmp("quad.stl", quad.as_bytes()))
            .unwrap()
            .num_triangles(),
        2
    );
}

#[test]
fn broken_ascii_stl_says_where() {
    for (text, line) in [
        ("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\nendloop\nendfacet\nendsolid\n", 4),
        ("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n", 2),
        ("solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", 2),
        ("solid s\nvertex 0 0 0\n", 2),
        ("solid s\nbanana\n", 2),
    ] {
        match TriMesh::load(tmp("broken.stl", text.as_bytes())) {
            Err(MeshError::Parse { line: Some(l), format: "STL", .. }) => assert_eq!(l, line, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
    }
}

#[test]
fn binary_stl_whose_header_says_solid_is_read_as_binary() {
    let mut bytes = Vec::new();
    let mut header = b"solid exported by a CAD tool".to_vec();
    header.resize(80, b' ');
    bytes.extend_from_slice(&header);
    bytes.extend_from_slice(&2u32.to_le_bytes());
    for z in [0.0f32, 2.0] {
        bytes.extend_from_slice(&[0.0f32, 0.0, 1.0].map(f32::to_le_bytes).concat());
        for v in [[0.0f32, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]] {
            bytes.extend_from_slice(&v.map(f32::to_le_bytes).concat());
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    let m = TriMesh::load(tmp("binary.stl", &bytes)).unwrap();
    assert_eq!(m.num_triangles(), 2);
    assert!((0..2).any(|i| m.triangle(i).iter().all(|v| v.z == 2.0)));
}
