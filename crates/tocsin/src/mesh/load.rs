//! Reading OBJ (tobj), STL ASCII and binary (stl_io) and PLY ASCII and binary (ply-rs-bw).
//! Each reader returns raw vertices and triangles; validation happens in `TriMesh::new`.

use std::io::Cursor;
use std::path::Path;

use crate::error::MeshError;
use crate::math::Vec3;

type Raw = (Vec<Vec3>, Vec<[u32; 3]>);

pub(super) fn load_file(path: &Path) -> Result<Raw, MeshError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match ext.as_deref() {
        Some("obj") => "OBJ",
        Some("stl") => "STL",
        Some("ply") => "PLY",
        _ => {
            return Err(MeshError::UnknownFormat {
                path: path.to_path_buf(),
            })
        }
    };
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let parse_error = |line, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        format,
        line,
        message,
    };
    match format {
        "OBJ" => read_obj(&bytes).map_err(|(line, m)| parse_error(line, m)),
        "STL" => read_stl(&bytes).map_err(|m| parse_error(None, m)),
        _ => read_ply(&bytes).map_err(|m| parse_error(None, m)),
    }
}

fn index_u32(i: usize) -> Result<u32, String> {
    u32::try_from(i).map_err(|_| format!("vertex index {i} does not fit in 32 bits"))
}

fn read_obj(bytes: &[u8]) -> Result<Raw, (Option<usize>, String)> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let mut reader = Cursor::new(bytes);
    // Materials are irrelevant to geometry: never open .mtl files.
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| (first_bad_obj_line(bytes), e.to_string()))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for model in models {
        let base = vertices.len();
        let m = model.mesh;
        vertices.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        for t in m.indices.chunks_exact(3) {
            let mut tri = [0u32; 3];
            for k in 0..3 {
                tri[k] = index_u32(base + t[k] as usize).map_err(|m| (None, m))?;
            }
            triangles.push(tri);
        }
    }
    Ok((vertices, triangles))
}

/// tobj's errors carry no position: find the first `v` or `f` line that does not parse, so the
/// user is told where to look.
fn first_bad_obj_line(bytes: &[u8]) -> Option<usize> {
    let text = String::from_utf8_lossy(bytes);
    let mut num_vertices: i64 = 0;
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<_> = words.map(str::parse::<f64>).collect();
                if coords.len() < 3 || coords.iter().any(Result::is_err) {
                    return Some(i + 1);
                }
                num_vertices += 1;
            }
            Some("f") => {
                let refs: Vec<&str> = words.collect();
                let ok = refs.len() >= 3
                    && refs.iter().all(|r| {
                        r.split('/')
                            .next()
                            .and_then(|s| s.parse::<i64>().ok())
                            .is_some_and(|k| {
                                (k > 0 && k <= num_vertices) || (k < 0 && -k <= num_vertices)
                            })
                    });
                if !ok {
                    return Some(i + 1);
                }
            }
            _ => {}
        }
    }
    None
}

fn read_stl(bytes: &[u8]) -> Result<Raw, String> {
    let mesh = stl_io::read_stl(&mut Cursor::new(bytes)).map_err(|e| e.to_string())?;
    let vertices = mesh
        .vertices
        .iter()
        .map(|v| Vec3::new(f64::from(v.0[0]), f64::from(v.0[1]), f64::from(v.0[2])))
        .collect();
    let triangles = mesh
        .faces
        .iter()
        .map(|f| {
            Ok([
                index_u32(f.vertices[0])?,
                index_u32(f.vertices[1])?,
                index_u32(f.vertices[2])?,
            ])
        })
        .collect::<Result<_, String>>()?;
    Ok((vertices, triangles))
}

fn read_ply(bytes: &[u8]) -> Result<Raw, String> {
    use ply_rs_bw::ply::{DefaultElement, Property};
    let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
    let ply = parser
        .read_ply(&mut Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let scalar = |p: &Property| -> Option<f64> {
        Some(match p {
            Property::Char(v) => f64::from(*v),
            Property::UChar(v) => f64::from(*v),
            Property::Short(v) => f64::from(*v),
            Property::UShort(v) => f64::from(*v),
            Property::Int(v) => f64::from(*v),
            Property::UInt(v) => f64::from(*v),
            Property::Float(v) => f64::from(*v),
            Property::Double(v) => *v,
            _ => return None,
        })
    };
    let list = |p: &Property| -> Option<Vec<i64>> {
        Some(match p {
            Property::ListChar(v) => v.iter().map(|&x| i64::from(x)).collect(),
            Property::ListUChar(v) => v.iter().map(|&x| i64::from(x)).collect(),
            Property::ListShort(v) => v.iter().map(|&x| i64::from(x)).collect(),
            Property::ListUShort(v) => v.iter().map(|&x| i64::from(x)).collect(),
            Property::ListInt(v) => v.iter().map(|&x| i64::from(x)).collect(),
            Property::ListUInt(v) => v.iter().map(|&x| i64::from(x)).collect(),
            _ => return None,
        })
    };
    let vertex_elements = ply.payload.get("vertex").ok_or("no `vertex` element")?;
    let mut vertices = Vec::with_capacity(vertex_elements.len());
    for (i, v) in vertex_elements.iter().enumerate() {
        let mut c = [0.0; 3];
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            c[k] = v
                .get(*name)
                .and_then(scalar)
                .ok_or_else(|| format!("vertex {i} has no numeric `{name}` property"))?;
        }
        vertices.push(Vec3::from_array(c));
    }
    let faces = ply.payload.get("face").ok_or("no `face` element")?;
    let mut triangles = Vec::with_capacity(faces.len());
    for (i, f) in faces.iter().enumerate() {
        let idx = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| format!("face {i} has no integer list `vertex_indices`"))?;
        if idx.len() < 3 {
            return Err(format!(
                "face {i} has {} vertices, at least 3 are needed",
                idx.len()
            ));
        }
        let to_u32 = |k: i64| {
            u32::try_from(k)
                .ok()
                .filter(|&k| (k as usize) < vertices.len())
                .ok_or_else(|| {
                    format!(
                        "face {i}: vertex index {k} is out of range ({} vertices)",
                        vertices.len()
                    )
                })
        };
        // Fan triangulation of the polygon.
        for j in 1..idx.len() - 1 {
            triangles.push([to_u32(idx[0])?, to_u32(idx[j])?, to_u32(idx[j + 1])?]);
        }
    }
    Ok((vertices, triangles))
}
