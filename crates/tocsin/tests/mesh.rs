//! Mesh construction and loading: soups accepted, every bad input a typed error.

#![allow(clippy::unwrap_used, clippy::panic)]

use std::io::Write;
use tocsin::{mesh, MeshError, TriMesh, Vec3};

fn tmp(name: &str, content: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tocsin-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::File::create(&p)
        .unwrap()
        .write_all(content)
        .unwrap();
    p
}

#[test]
fn soups_are_accepted() {
    let v = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::X,
        Vec3::new(5.0, 5.0, 5.0),
    ]; // duplicate + isolated
    let t = vec![[0, 1, 2], [0, 1, 2], [0, 0, 0], [0, 1, 3], [2, 1, 0]];
    let m = TriMesh::new(v, t).unwrap();
    assert_eq!((m.num_vertices(), m.num_triangles()), (5, 5));
}

#[test]
fn bad_arrays_are_typed_errors() {
    let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(matches!(
        TriMesh::from_arrays(&v, &[]),
        Err(MeshError::NoTriangles)
    ));
    let e = TriMesh::from_arrays(&v, &[[0, 1, 2], [0, 3, 1]]).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::IndexOutOfRange {
                triangle: 1,
                corner: 1,
                index: 3,
                num_vertices: 3
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("triangle 1"));
    let e = TriMesh::from_arrays(&v, &[[0, -1, 2]]).unwrap_err();
    assert!(matches!(e, MeshError::IndexOutOfRange { index: -1, .. }));
    let bad = [[0.0, 0.0, 0.0], [1.0, f64::NAN, 0.0], [0.0, 1.0, 0.0]];
    let e = TriMesh::from_arrays(&bad, &[[0, 1, 2]]).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::NonFiniteCoordinate {
                vertex: 1,
                axis: 'y',
                ..
            }
        ),
        "{e}"
    );
    let bad = [[0.0, 0.0, f64::INFINITY], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert!(matches!(
        TriMesh::from_arrays(&bad, &[[0, 1, 2]]),
        Err(MeshError::NonFiniteCoordinate {
            vertex: 0,
            axis: 'z',
            ..
        })
    ));
    assert!(TriMesh::from_arrays(&[], &[[0, 0, 0]]).is_err());
    assert!(mesh::sphere(f64::NAN, 4, 4).is_err());
}

#[test]
fn obj_with_polygons_and_objects() {
    let obj = b"o a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\no b\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 5/1 6/1 7/1\nf -1 -2 -3\n";
    let m = TriMesh::load(tmp("quad.obj", obj)).unwrap();
    assert_eq!((m.num_vertices(), m.num_triangles()), (7, 4));
}

#[test]
fn stl_ascii_and_binary_and_ply() {
    let ascii = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
    let m = TriMesh::load(tmp("t.stl", ascii)).unwrap();
    assert_eq!(m.num_triangles(), 1);
    let mut bin = vec![0u8; 80];
    bin.extend(2u32.to_le_bytes());
    for tri in [
        [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]],
        [[0., 0., 1.], [1., 0., 1.], [0., 1., 1.]],
    ] {
        bin.extend([0u8; 12]);
        tri.iter()
            .flatten()
            .for_each(|c| bin.extend(c.to_le_bytes()));
        bin.extend([0u8; 2]);
    }
    assert_eq!(
        TriMesh::load(tmp("b.stl", &bin)).unwrap().num_triangles(),
        2
    );
    let e = TriMesh::load(tmp("trunc.stl", &bin[..bin.len() - 20])).unwrap_err();
    assert!(matches!(e, MeshError::Parse { format: "STL", .. }), "{e}");
    let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    assert_eq!(TriMesh::load(tmp("q.ply", ply)).unwrap().num_triangles(), 2);
    let bad_ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n3 0 1 7\n";
    let e = TriMesh::load(tmp("bad.ply", bad_ply)).unwrap_err();
    assert!(e.to_string().contains("out of range"), "{e}");
}

#[test]
fn bad_files_are_typed_errors() {
    let e = TriMesh::load("/nonexistent/x.obj").unwrap_err();
    assert!(matches!(e, MeshError::Io { .. }), "{e}");
    let e = TriMesh::load(tmp("x.fbx", b"<xml/>")).unwrap_err();
    assert!(matches!(e, MeshError::UnknownFormat { .. }), "{e}");
    let e = TriMesh::load(tmp("x.dae", b"<xml/>")).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::Parse {
                format: "COLLADA",
                ..
            }
        ),
        "{e}"
    );
    let e = TriMesh::load(tmp("bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n")).unwrap_err();
    assert!(
        matches!(
            e,
            MeshError::Parse {
                format: "OBJ",
                line: Some(3),
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("line 3"));
    let e = TriMesh::load(tmp("range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")).unwrap_err();
    assert!(matches!(e, MeshError::Parse { line: Some(4), .. }), "{e}");
    let e = TriMesh::load(tmp("empty.obj", b"# nothing\n")).unwrap_err();
    assert!(e.to_string().contains("no triangles"), "{e}");
    let e = TriMesh::load(tmp("nan.obj", b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n")).unwrap_err();
    assert!(e.to_string().contains("vertex 1"), "{e}");
    let e = TriMesh::load(tmp("garbage.ply", b"not a ply file at all")).unwrap_err();
    assert!(matches!(e, MeshError::Parse { format: "PLY", .. }), "{e}");
}

#[test]
fn generators_have_the_standard_sizes() {
    assert_eq!(mesh::torus_knot(175, 8).unwrap().num_triangles(), 2_800);
    assert_eq!(mesh::torus_knot(344, 16).unwrap().num_triangles(), 11_008);
    assert_eq!(mesh::torus_knot(680, 25).unwrap().num_triangles(), 34_000);
    assert_eq!(mesh::box_mesh(Vec3::ONE).unwrap().num_triangles(), 12);
    assert_eq!(mesh::plate(1.0, 3).unwrap().num_triangles(), 18);
    assert!(mesh::sphere(1.0, 8, 16).unwrap().num_triangles() > 100);
}

#[test]
fn huge_generator_sizes_are_errors_not_panics() {
    assert!(matches!(
        mesh::torus_knot(1 << 20, 1 << 20),
        Err(MeshError::TooLarge { .. })
    ));
    assert!(matches!(
        mesh::sphere(1.0, usize::MAX, 3),
        Err(MeshError::TooLarge { .. })
    ));
    assert!(matches!(
        mesh::plate(1.0, 1 << 40),
        Err(MeshError::TooLarge { .. })
    ));
}
