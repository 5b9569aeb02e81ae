//! Reading OBJ (tobj), binary STL (stl_io), ASCII STL (here), PLY (ply-rs-bw) and COLLADA
//! (mesh-loader, checked in `collada.rs`).
//! Each reader returns raw vertices and triangles; validation happens in `TriMesh::new`.
//!
//! Decisions, each from a file seen in the wild:
//! - A UTF-8 byte-order mark is skipped (it swallowed an OBJ's first vertex).
//! - OBJ points (`p`), polylines (`l`) and faces of fewer than three vertices (a truncated last
//!   line included) are not surfaces and are skipped: tobj turned them into zero-area
//!   triangles, 19 of them up to 0.39 mm off pybullet's Panda `link6.obj`.
//! - ASCII STL is read here rather than by stl_io, which rejected `facet normal nan nan nan`
//!   (CAD exporters write it for degenerate facets; normals are ignored anyway) and kept only
//!   the first `solid` of a file with several. All solids are kept; coordinates are read as
//!   `f64`; identical vertices are merged, as stl_io does for binary files.
//! - A binary PLY's header is checked against the payload's length before ply-rs-bw reads it:
//!   the reader takes each element's count from the header and reads element after element,
//!   and an element of no properties takes no bytes, so a corrupted header (`element face
//!   4294967295` with its `property` line lost) filled memory until the process was killed
//!   (found by mutating files, forty-first session). Each element must fit in what follows the
//!   header, counted as at least one byte (as an ASCII element takes at least a line).

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
        Some("dae") => "COLLADA",
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
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&bytes);
    let parse_error = |line, message: String| MeshError::Parse {
        path: path.to_path_buf(),
        format,
        line,
        message,
    };
    match format {
        "OBJ" => read_obj(bytes).map_err(|(line, m)| parse_error(line, m)),
        "STL" if is_binary_stl(bytes) => read_binary_stl(bytes).map_err(|m| parse_error(None, m)),
        "STL" => read_ascii_stl(bytes).map_err(|(line, m)| parse_error(line, m)),
        "PLY" => read_ply(bytes).map_err(|m| parse_error(None, m)),
        _ => super::collada::read_dae(bytes).map_err(|m| parse_error(None, m)),
    }
}

/// Vertices merged by exact position (bit for bit) as they are read: the id of each.
#[derive(Default)]
pub(super) struct VertexIndex {
    vertices: Vec<Vec3>,
    ids: std::collections::HashMap<[u64; 3], u32>,
}

impl VertexIndex {
    /// The id of the vertex at `v`, a new one if no vertex was there yet.
    pub(super) fn id(&mut self, v: Vec3) -> Result<u32, String> {
        let key = [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
        if let Some(&id) = self.ids.get(&key) {
            return Ok(id);
        }
        let id = index_u32(self.vertices.len())?;
        self.vertices.push(v);
        self.ids.insert(key, id);
        Ok(id)
    }

    /// The distinct vertices, in order of their ids.
    pub(super) fn into_vertices(self) -> Vec<Vec3> {
        self.vertices
    }
}

fn index_u32(i: usize) -> Result<u32, String> {
    u32::try_from(i).map_err(|_| format!("vertex index {i} does not fit in 32 bits"))
}

fn read_obj(bytes: &[u8]) -> Result<Raw, (Option<usize>, String)> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // tobj reads `l a b c` as a polygon face: blank out point and line statements first (line
    // numbers stay as they were).
    let surfaces = without_points_and_lines(bytes);
    let mut reader = Cursor::new(&surfaces[..]);
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

/// The OBJ text with every `p` and `l` statement replaced by an empty line.
fn without_points_and_lines(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(bytes.len());
    for line in bytes.split_inclusive(|&b| b == b'\n') {
        let first = line
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty());
        if matches!(first, Some(b"l") | Some(b"p")) {
            out.push(b'\n');
        } else {
            out.extend_from_slice(line);
        }
    }
    out
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
                let ok = refs.iter().all(|r| {
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

/// A binary STL: an 80-byte header, a triangle count, and exactly 50 bytes per triangle. Some
/// binary files begin with "solid" too, so the size decides, not the first word.
fn is_binary_stl(bytes: &[u8]) -> bool {
    match bytes.get(80..84) {
        Some(n) => {
            let n = u32::from_le_bytes([n[0], n[1], n[2], n[3]]) as usize;
            n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len())
        }
        None => false,
    }
}

fn read_binary_stl(bytes: &[u8]) -> Result<Raw, String> {
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

/// ASCII STL: `solid`, then facets of `facet normal`, `outer loop`, three `vertex x y z`,
/// `endloop`, `endfacet`, then `endsolid`; any number of solids. Keywords are matched without
/// case; normals are not read (NaN is common there). A facet of more than three vertices is
/// fanned; one of fewer is an error.
fn read_ascii_stl(bytes: &[u8]) -> Result<Raw, (Option<usize>, String)> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        (
            None,
            format!("neither a binary STL (wrong size) nor ASCII text ({e})"),
        )
    })?;
    let mut index = VertexIndex::default();
    let mut triangles = Vec::new();
    let mut facet: Option<(usize, Vec<u32>)> = None; // (line, vertex indices)
    let mut seen_solid = false;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword.to_ascii_lowercase().as_str() {
            "solid" => seen_solid = true,
            "facet" => {
                if facet.is_some() {
                    return Err((Some(n), "`facet` inside a facet".into()));
                }
                facet = Some((n, Vec::with_capacity(3)));
            }
            "vertex" => {
                let Some((_, corners)) = facet.as_mut() else {
                    return Err((Some(n), "`vertex` outside a facet".into()));
                };
                let coords: Vec<f64> = words
                    .map(str::parse::<f64>)
                    .collect::<Result<_, _>>()
                    .map_err(|e| (Some(n), format!("bad vertex coordinate: {e}")))?;
                let &[x, y, z] = coords.as_slice() else {
                    return Err((
                        Some(n),
                        format!("a vertex needs 3 numbers, got {}", coords.len()),
                    ));
                };
                corners.push(index.id(Vec3::new(x, y, z)).map_err(|m| (Some(n), m))?);
            }
            "endfacet" => {
                let Some((start, corners)) = facet.take() else {
                    return Err((Some(n), "`endfacet` without `facet`".into()));
                };
                if corners.len() < 3 {
                    return Err((
                        Some(start),
                        format!("a facet has {} vertices, 3 are needed", corners.len()),
                    ));
                }
                for j in 1..corners.len() - 1 {
                    triangles.push([corners[0], corners[j], corners[j + 1]]);
                }
            }
            "outer" | "endloop" | "endsolid" => {}
            other => return Err((Some(n), format!("unexpected `{other}`"))),
        }
    }
    if let Some((start, _)) = facet {
        return Err((Some(start), "the file ends inside a facet".into()));
    }
    if !seen_solid {
        return Err((None, "no `solid`: not an ASCII STL".into()));
    }
    Ok((index.into_vertices(), triangles))
}

/// Checks that a binary PLY's payload can hold the elements its header declares (module docs):
/// the sum over elements of count times the smallest size of one (its scalar properties and
/// its lists' counts, at least one byte) is at most the bytes after `end_header`.
fn check_ply_payload(
    parser: &ply_rs_bw::parser::Parser<ply_rs_bw::ply::DefaultElement>,
    bytes: &[u8],
) -> Result<(), String> {
    use ply_rs_bw::ply::{Encoding, PropertyType, ScalarType};
    let mut cursor = Cursor::new(bytes);
    let header = parser
        .read_header(&mut ply_rs_bw::parser::Reader::new(&mut cursor))
        .map_err(|e| e.to_string())?;
    if header.encoding == Encoding::Ascii {
        return Ok(());
    }
    let size = |s: &ScalarType| -> u128 {
        match s {
            ScalarType::Char | ScalarType::UChar => 1,
            ScalarType::Short | ScalarType::UShort => 2,
            ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
            ScalarType::Double => 8,
        }
    };
    let available = bytes.len() as u128 - u128::from(cursor.position());
    let mut needed = 0u128;
    for e in header.elements.values() {
        let one: u128 = e
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(s) | PropertyType::List(s, _) => size(s),
            })
            .sum();
        needed += one.max(1) * e.count as u128;
        if needed > available {
            return Err(format!(
                "the header declares {} `{}` elements of at least {} bytes each, more than the \
                 {available} bytes after the header",
                e.count,
                e.name,
                one.max(1)
            ));
        }
    }
    Ok(())
}

fn read_ply(bytes: &[u8]) -> Result<Raw, String> {
    use ply_rs_bw::ply::{DefaultElement, Property};
    let parser = ply_rs_bw::parser::Parser::<DefaultElement>::new();
    check_ply_payload(&parser, bytes)?;
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
