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

/// A binary PLY of `vertices` and triangles, with `extra` header lines before `end_header`.
fn binary_ply(vertices: &[[f64; 3]], faces: &[[u32; 3]], extra: &str) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty double x\n\
         property double y\nproperty double z\nelement face {}\n\
         property list uchar uint vertex_indices\n{extra}end_header\n",
        vertices.len(),
        faces.len()
    )
    .into_bytes();
    for v in vertices {
        bytes.extend(v.map(f64::to_le_bytes).concat());
    }
    for f in faces {
        bytes.push(3);
        bytes.extend(f.map(u32::to_le_bytes).concat());
    }
    bytes
}

/// A binary PLY whose header declares more elements than its payload can hold is refused before
/// it is read. The first case, found by mutating files in the forty-first session, is an
/// element of no properties (its `property` line lost) with a count of 2^32 - 1: such elements
/// take no bytes, so the reader made four billion of them and filled memory until the process
/// was killed.
#[test]
fn binary_ply_whose_header_outgrows_its_payload_is_refused() {
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let good = binary_ply(&v, &[[0, 1, 2]], "");
    // The exact size loads, and so does an element of no properties that fits (one byte each).
    assert_eq!(
        TriMesh::load(tmp("good.ply", &good))
            .unwrap()
            .num_triangles(),
        1
    );
    let mut with_empty = binary_ply(&v, &[[0, 1, 2]], "element empty 3\n");
    with_empty.extend([0u8; 3]);
    assert_eq!(
        TriMesh::load(tmp("empty.ply", &with_empty))
            .unwrap()
            .num_triangles(),
        1
    );
    // The face element's `property` line lost, and with it the face's bytes.
    let face = b"element face 1\nproperty list uchar uint vertex_indices\n";
    let mut no_property = good[..good.len() - 13].to_vec();
    let at = no_property
        .windows(face.len())
        .position(|w| w == face)
        .unwrap();
    no_property.splice(
        at..at + face.len(),
        b"element face 4294967295\n".iter().copied(),
    );
    // Cut inside the vertices: three of 24 bytes do not fit in the 60 left.
    let mut cut = good.clone();
    cut.truncate(good.len() - 13 - 12);
    let mut lying_count = good.clone();
    let at = lying_count
        .windows(14)
        .position(|w| w == b"element face 1")
        .unwrap();
    lying_count.splice(at..at + 14, b"element face 99999999999".iter().copied());
    for (name, bytes, element) in [
        ("no property", no_property, "`face`"),
        ("cut inside the vertices", cut, "`vertex`"),
        ("a count beyond the file", lying_count, "`face`"),
        (
            "an empty element beyond the file",
            binary_ply(&v, &[[0, 1, 2]], "element empty 4000000000\n"),
            "`empty`",
        ),
    ] {
        match TriMesh::load(tmp("outgrown.ply", &bytes)) {
            Err(MeshError::Parse {
                format: "PLY",
                message,
                ..
            }) => {
                assert!(
                    message.contains(element) && message.contains("bytes after the header"),
                    "{name}: {message}"
                )
            }
            other => panic!("{name}: {other:?}"),
        }
    }
}
