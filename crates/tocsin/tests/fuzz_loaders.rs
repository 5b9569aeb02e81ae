//! A seeded fuzzer for the loaders, run by `make test` in bounded time: valid OBJ, STL
//! (ASCII and binary), PLY (ASCII and binary) and COLLADA files, mutated (bytes changed,
//! ranges cut or repeated, tokens that loaders trip on inserted, truncation), must load or
//! fail with a `MeshError`, never panic, abort or hang. A crash it finds is fixed and its file
//! kept as a case in `mesh_files.rs`; 40,000 cases per seed file (`TOCSIN_FUZZ_CASES=40000`)
//! found none after the hardening issue's loader fixes, and 20,000 on the COLLADA seed none
//! (forty-third session; mesh-loader's own panics are caught in `mesh/collada.rs`). The
//! default is 400 per seed file.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use tocsin::TriMesh;

fn seeds() -> Vec<(&'static str, Vec<u8>)> {
    let obj = b"# cube corner\no part\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -1 -2 -3\nl 1 2 3\ng other\nf 1//1 3//1 5//1\n".to_vec();
    let stl = b"solid s\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\nfacet normal nan nan nan\n outer loop\n  vertex 0 0 1\n  vertex 1 0 1\n  vertex 0 1 1\n endloop\nendfacet\nendsolid s\n".to_vec();
    let mut bin = b"solid binary header".to_vec();
    bin.resize(80, 0);
    bin.extend(2u32.to_le_bytes());
    for z in [0.0f32, 1.0] {
        bin.extend([0u8; 12]);
        for v in [[0.0f32, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]] {
            v.iter().for_each(|c| bin.extend(c.to_le_bytes()));
        }
        bin.extend([0u8; 2]);
    }
    let ply = b"ply\nformat ascii 1.0\ncomment c\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 1 2 3\n".to_vec();
    let mut ply_bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
    for v in [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        v.iter().for_each(|c| ply_bin.extend(c.to_le_bytes()));
    }
    ply_bin.push(3);
    [0u32, 1, 2]
        .iter()
        .for_each(|i| ply_bin.extend(i.to_le_bytes()));
    let dae = br##"<?xml version="1.0"?>
<COLLADA version="1.4.1"><asset><unit meter="0.01"/></asset>
<library_geometries><geometry id="g"><mesh>
<source id="p"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 1</float_array>
<technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
</source><source id="n"><float_array id="na" count="3">0 0 1</float_array><technique_common>
<accessor source="#na" count="1" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
</source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<polylist count="2"><input semantic="VERTEX" source="#v" offset="0"/>
<input semantic="NORMAL" source="#n" offset="1"/><vcount>3 4</vcount>
<p>0 0 1 0 2 0 0 0 1 0 2 0 3 0</p></polylist>
<triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>1 2 3</p></triangles>
</mesh></geometry></library_geometries>
<library_nodes><node id="l"><rotate>0 0 1 30</rotate><instance_geometry url="#g"/></node>
</library_nodes><library_visual_scenes><visual_scene id="s"><node><translate>1 2 3</translate>
<matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#g"/>
<node><scale>2 2 2</scale><instance_node url="#l"/></node></node></visual_scene>
</library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>"##
        .to_vec();
    vec![
        ("obj", obj),
        ("stl", stl),
        ("stl", bin),
        ("ply", ply),
        ("ply", ply_bin),
        ("dae", dae),
    ]
}

const TOKENS: &[&[u8]] = &[
    b"nan",
    b"inf",
    b"-inf",
    b"-1",
    b"0",
    b"4294967295",
    b"99999999999999999999",
    b"1e400",
    b"-1e400",
    b"1e-400",
    b"\n",
    b"\r\n",
    b" ",
    b"/",
    b"//",
    b"<",
    b">",
    b"\"",
    b"#",
    b"</node>",
    b"<node>",
    b"f ",
    b"v ",
    b"l ",
    b"p ",
    b"facet normal",
    b"endfacet",
    b"vertex",
    b"outer loop",
    b"endloop",
    b"solid",
    b"endsolid",
    b"element vertex 4294967295\n",
    b"element face 4294967295\n",
    b"property list uint int vertex_indices\n",
    b"property list uchar uchar vertex_indices\n",
    b"end_header\n",
    b"format binary_big_endian 1.0\n",
    b"\xEF\xBB\xBF",
    b"\0",
    b"\xFF\xFF\xFF\xFF",
];

fn mutate(rng: &mut ChaCha8Rng, data: &mut Vec<u8>) {
    for _ in 0..rng.random_range(1..=6) {
        let n = data.len();
        match rng.random_range(0..6) {
            0 if n > 0 => {
                let i = rng.random_range(0..n);
                data[i] = rng.random();
            }
            1 if n > 0 => {
                let a = rng.random_range(0..n);
                let b = (a + rng.random_range(0..=16)).min(n);
                data.drain(a..b);
            }
            2 if n > 0 => {
                let a = rng.random_range(0..n);
                let b = (a + rng.random_range(0..=32)).min(n);
                let piece = data[a..b].to_vec();
                let at = rng.random_range(0..=data.len());
                data.splice(at..at, piece);
            }
            3 => {
                let t = TOKENS[rng.random_range(0..TOKENS.len())];
                let at = rng.random_range(0..=data.len());
                data.splice(at..at, t.iter().copied());
            }
            4 if n > 0 => data.truncate(rng.random_range(0..n)),
            _ => {
                // Replace a number-like word with a token.
                let t = TOKENS[rng.random_range(0..11)];
                if let Some(i) = (0..n).find(|_| rng.random_bool(0.02)) {
                    let end = (i..n).find(|&j| data[j].is_ascii_whitespace()).unwrap_or(n);
                    data.splice(i..end, t.iter().copied());
                }
            }
        }
    }
}

fn load(ext: &str, data: &[u8], dir: &std::path::Path, case: &str) {
    let path = dir.join(format!("case.{ext}"));
    std::fs::write(&path, data).unwrap();
    let r = std::panic::catch_unwind(|| TriMesh::load(&path));
    assert!(
        r.is_ok(),
        "{case}: the loader panicked on {:?}",
        String::from_utf8_lossy(data)
    );
}

#[test]
fn mutated_files_load_or_fail_cleanly() {
    let cases: usize = std::env::var("TOCSIN_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(400);
    let dir = std::env::temp_dir().join(format!("tocsin-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (s, (ext, seed)) in seeds().into_iter().enumerate() {
        // The seed files themselves are valid.
        assert!(
            TriMesh::load({
                let p = dir.join(format!("seed.{ext}"));
                std::fs::write(&p, &seed).unwrap();
                p
            })
            .is_ok(),
            "seed {s} ({ext})"
        );
        let mut rng = common::rng(1000 + s as u64);
        for k in 0..cases {
            let mut data = seed.clone();
            mutate(&mut rng, &mut data);
            load(ext, &data, &dir, &format!("seed {s} ({ext}) case {k}"));
        }
    }
}
