//! COLLADA (`.dae`) files, the format many ROS robots ship their collision meshes in (in
//! example-robot-data: Tiago, Baxter, Romeo, HyQ, Kinova, the A1, Go1 and Solo; 286 files).
//! mesh-loader parses each geometry's triangles; the scene (which geometry goes where) is
//! walked here, because mesh-loader composes nested nodes' transforms in the wrong order, scales
//! node translations and geometry differently by the unit, and misses some nodes' matrices
//! (found against coal on example-robot-data's files; forty-third session).
//!
//! Decisions:
//! - Read: every `<instance_geometry>` of the visual scene (`<scene><instance_visual_scene>`),
//!   through its nodes and the `<instance_node>`s they use (from `<library_nodes>`), each
//!   placed by its nodes' `matrix` (written row by row), `translate`, `rotate` (axis, degrees;
//!   the axis normalised, as OpenGL's `glRotate`, which the specification cites, does: assimp
//!   and pycollada take it as written, and a long axis then scales too) and `scale` elements,
//!   composed in document order, parents first; a geometry instanced twice is read twice. A
//!   geometry the scene does not place is not read (nor does assimp, coal's loader, read it).
//!   Of a geometry, its triangles, polygons and polylists (fanned); lines and points are not
//!   surfaces and are skipped.
//! - The document's `<asset><unit meter>` (not one nested in a geometry or node) scales the
//!   whole scene, as ROS does (RViz and MoveIt rescale by it); coal (assimp without its
//!   global-scale step) ignores it, so the two agree only on metre files, every file of
//!   example-robot-data.
//! - `<up_axis>` is ignored: a `Y_UP` file's coordinates are taken as written, in the link's
//!   frame, as ROS (which resets the root rotation assimp adds) and coal do.
//! - mesh-loader reads coordinates as `f32`; the transforms are applied in `f64`. A position
//!   is within about 6e-8 of its own size of the written decimal (STL stores `f32` too).
//!   Identical positions are merged.
//! - Refused with an error that says why: `<instance_controller>` (skinned geometry),
//!   `<trifans>` (mesh-loader reads fans as strips), `lookat` and `skew` transforms, a URL
//!   outside the file, an instanced node or geometry the file lacks, nodes instanced more than
//!   64 deep (a cycle), elements nested more than 256 deep, more than 100,000 placements or
//!   100 million placed triangles (library nodes instancing each other twice over multiply
//!   them), and a file without a visual scene.
//! - mesh-loader panics on some malformed geometry (an index past its array, missing normals);
//!   the panic is caught, quietly (no message on stderr), and becomes a parse error.

use std::collections::HashMap;

use super::load::VertexIndex;
use crate::math::{Mat4, Vec3};

type Raw = (Vec<Vec3>, Vec<[u32; 3]>);

/// Deepest chain of `<instance_node>` followed (a deeper one is taken for a cycle).
const MAX_DEPTH: usize = 64;

/// Most placements of geometry read: library nodes instancing each other twice over, 64 deep,
/// would place a geometry 2^64 times. Robot files place a few.
const MAX_PLACEMENTS: usize = 100_000;

/// Most triangles placed in all (each placement copies its geometry's).
const MAX_TRIANGLES: usize = 100_000_000;

/// Deepest nesting of XML elements read: mesh-loader parses nested elements by recursion, and
/// 100,000 nested `<node>`s overflowed the stack (forty-third session). COLLADA files nest a
/// few levels per articulated part.
const MAX_NESTING: usize = 256;

/// A geometry's local triangles, as mesh-loader reads them: corner positions and faces.
type Local = (Vec<[f32; 3]>, Vec<[u32; 3]>);

/// The numbers of an element's text.
fn numbers(node: roxmltree::Node<'_, '_>) -> Result<Vec<f64>, String> {
    node.text()
        .unwrap_or("")
        .split_whitespace()
        .map(|w| {
            w.parse::<f64>()
                .map_err(|e| format!("<{}>: {w:?} is not a number ({e})", node.tag_name().name()))
        })
        .collect()
}

/// The transform of one `matrix`, `translate`, `rotate` or `scale` element (`None`: not a
/// transform element).
fn transform_of(node: roxmltree::Node<'_, '_>) -> Result<Option<Mat4>, String> {
    let name = node.tag_name().name();
    let want = match name {
        "matrix" => 16,
        "translate" | "scale" => 3,
        "rotate" => 4,
        "lookat" | "skew" => return Err(format!("<{name}> transforms are not supported")),
        _ => return Ok(None),
    };
    let v = numbers(node)?;
    if v.len() != want {
        return Err(format!("<{name}> needs {want} numbers, has {}", v.len()));
    }
    Ok(Some(match name {
        // Written row by row; glam takes columns.
        "matrix" => Mat4::from_cols_array(&std::array::from_fn(|k| v[(k % 4) * 4 + k / 4])),
        "translate" => Mat4::from_translation(Vec3::new(v[0], v[1], v[2])),
        "scale" => Mat4::from_scale(Vec3::new(v[0], v[1], v[2])),
        _ => {
            let axis = Vec3::new(v[0], v[1], v[2]);
            if v[3] == 0.0 {
                Mat4::IDENTITY
            } else {
                let axis = axis
                    .try_normalize()
                    .ok_or_else(|| "<rotate> about a zero axis".to_string())?;
                Mat4::from_axis_angle(axis, v[3].to_radians())
            }
        }
    }))
}

/// The element of `id` among `elements` (a local URL `#id`).
fn by_url<'a, 'i>(
    url: Option<&str>,
    what: &str,
    elements: &HashMap<&str, roxmltree::Node<'a, 'i>>,
) -> Result<roxmltree::Node<'a, 'i>, String> {
    let url = url.unwrap_or("");
    let id = url
        .strip_prefix('#')
        .ok_or_else(|| format!("{what} URL {url:?} is not in this file (only \"#id\" is read)"))?;
    elements
        .get(id)
        .copied()
        .ok_or_else(|| format!("the scene instances {what} {id:?}, which the file lacks"))
}

/// Every geometry the scene places, by id, with the transform of each placement (module docs).
struct Placements<'a, 'i> {
    nodes: HashMap<&'a str, roxmltree::Node<'a, 'i>>,
    geometries: HashMap<&'a str, roxmltree::Node<'a, 'i>>,
    found: Vec<(&'a str, Mat4)>,
}

impl<'a, 'i> Placements<'a, 'i> {
    /// Walks `node` (a `<node>` or the `<visual_scene>`) under the transform `parent`.
    fn walk(
        &mut self,
        node: roxmltree::Node<'a, 'i>,
        parent: Mat4,
        depth: usize,
    ) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err(format!(
                "nodes instanced more than {MAX_DEPTH} deep (a cycle?)"
            ));
        }
        let mut m = parent;
        for child in node.children().filter(roxmltree::Node::is_element) {
            if let Some(t) = transform_of(child)? {
                m *= t;
            }
        }
        for child in node.children().filter(roxmltree::Node::is_element) {
            match child.tag_name().name() {
                "node" => self.walk(child, m, depth)?,
                "instance_node" => {
                    let target = by_url(child.attribute("url"), "node", &self.nodes)?;
                    self.walk(target, m, depth + 1)?;
                }
                "instance_geometry" => {
                    let g = by_url(child.attribute("url"), "geometry", &self.geometries)?;
                    let id = g.attribute("id").unwrap_or("");
                    if self.found.len() == MAX_PLACEMENTS {
                        return Err(format!(
                            "the scene places geometry more than {MAX_PLACEMENTS} times"
                        ));
                    }
                    self.found.push((id, m));
                }
                "instance_controller" => {
                    return Err("<instance_controller> (skinned geometry) is not supported".into())
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The text without the elements that place geometry, so that mesh-loader reads each geometry
/// in its own frame (its placement is wrong; module docs).
fn without_scene(text: &str, doc: &roxmltree::Document<'_>) -> String {
    let cut = doc
        .descendants()
        .filter(|n| n.has_tag_name("library_visual_scenes") || n.has_tag_name("scene"))
        .filter(|n| n.parent() == Some(doc.root_element()))
        .map(|n| n.range())
        .collect();
    crate::xml::without(text, cut)
}

/// Each geometry's local triangles, by id, as mesh-loader reads them.
fn local_geometries(text: &str) -> Result<HashMap<String, Local>, String> {
    let scene = catch_quietly(|| mesh_loader::collada::from_str(text))
        .map_err(|_| "the COLLADA reader failed on this file (malformed geometry)".to_string())?
        .map_err(|e| e.to_string())?;
    Ok(scene
        .meshes
        .into_iter()
        .map(|m| (m.name, (m.vertices, m.faces)))
        .collect())
}

thread_local! {
    /// Whether a panic on this thread is being caught by [`catch_quietly`].
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// `catch_unwind`, without the panic's message on stderr: a malformed file is an error the
/// caller gets, not a crash report. The process's panic hook is wrapped once, and the previous
/// hook still reports every other panic (another thread's, or one outside such a call).
fn catch_quietly<R>(f: impl FnOnce() -> R) -> std::thread::Result<R> {
    static WRAP: std::sync::Once = std::sync::Once::new();
    WRAP.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    r
}

/// A COLLADA file's vertices and triangles (module docs).
pub(super) fn read_dae(bytes: &[u8]) -> Result<Raw, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not UTF-8 text ({e})"))?;
    let doc = crate::xml::parse(text).map_err(|e| e.to_string())?;
    // Each node's depth from its parent's, in document order (parents come first).
    let mut depth = vec![0usize; doc.descendants().count()];
    for node in doc.descendants() {
        if let Some(parent) = node.parent() {
            let d = depth[parent.id().get_usize()] + 1;
            if d > MAX_NESTING {
                return Err(format!("elements nested more than {MAX_NESTING} deep"));
            }
            depth[node.id().get_usize()] = d;
        }
    }
    if doc.descendants().any(|n| n.has_tag_name("trifans")) {
        return Err("<trifans> is not supported".into());
    }
    let with_id = |tag: &'static str| {
        doc.descendants()
            .filter(move |n| n.has_tag_name(tag))
            .filter_map(|n| Some((n.attribute("id")?, n)))
            .collect::<HashMap<_, _>>()
    };
    let mut placements = Placements {
        nodes: with_id("node"),
        geometries: with_id("geometry"),
        found: Vec::new(),
    };
    let scenes = with_id("visual_scene");
    let instance = doc
        .descendants()
        .find(|n| n.has_tag_name("instance_visual_scene"))
        .ok_or_else(|| "no <instance_visual_scene>: nothing places the geometry".to_string())?;
    let scene = by_url(instance.attribute("url"), "visual scene", &scenes)?;
    // The document's own `<asset>` (assets nested in geometry or nodes describe those only).
    let root_unit = doc
        .root_element()
        .children()
        .find(|n| n.has_tag_name("asset"))
        .and_then(|a| a.children().find(|n| n.has_tag_name("unit")));
    let unit = match root_unit {
        Some(u) => match u.attribute("meter") {
            Some(m) => m
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|m| m.is_finite() && *m > 0.0)
                .ok_or_else(|| format!("<unit meter={m:?}> is not a positive number"))?,
            None => 1.0,
        },
        None => 1.0,
    };
    placements.walk(scene, Mat4::from_scale(Vec3::splat(unit)), 0)?;
    let local = local_geometries(&without_scene(text, &doc))?;
    let placed: usize = placements
        .found
        .iter()
        .map(|(id, _)| local.get(*id).map_or(0, |(_, faces)| faces.len()))
        .sum();
    if placed > MAX_TRIANGLES {
        return Err(format!(
            "the scene places {placed} triangles, more than {MAX_TRIANGLES}"
        ));
    }
    let mut index = VertexIndex::default();
    let mut triangles = Vec::new();
    for (id, m) in &placements.found {
        let Some((vertices, faces)) = local.get(*id) else {
            continue; // a geometry without triangles (lines only)
        };
        for face in faces {
            let mut tri = [0u32; 3];
            for (corner, &k) in tri.iter_mut().zip(face) {
                let p = vertices
                    .get(k as usize)
                    .ok_or_else(|| format!("a face refers to vertex {k}, which is missing"))?;
                let local = Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
                *corner = index.id(m.transform_point3(local))?;
            }
            triangles.push(tri);
        }
    }
    Ok((index.into_vertices(), triangles))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Geometry `g`: the right triangle (0,0,0), (1,0,0), (0,1,0); geometry `q`: a 2 x 2
    /// square as one polylist quad, and a line.
    const GEOMETRIES: &str = r##"<library_geometries>
<geometry id="g"><mesh>
<source id="gp"><float_array id="gpa" count="9">0 0 0 1 0 0 0 1 0</float_array>
<technique_common><accessor source="#gpa" count="3" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="gv"><input semantic="POSITION" source="#gp"/></vertices>
<triangles count="1"><input semantic="VERTEX" source="#gv" offset="0"/><p>0 1 2</p></triangles>
</mesh></geometry>
<geometry id="q"><mesh>
<source id="qp"><float_array id="qpa" count="12">0 0 0 2 0 0 2 2 0 0 2 0</float_array>
<technique_common><accessor source="#qpa" count="4" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="qv"><input semantic="POSITION" source="#qp"/></vertices>
<polylist count="1"><input semantic="VERTEX" source="#qv" offset="0"/><vcount>4</vcount>
<p>0 1 2 3</p></polylist>
<lines count="1"><input semantic="VERTEX" source="#qv" offset="0"/><p>0 2</p></lines>
</mesh></geometry>
</library_geometries>"##;

    fn dae(unit: &str, extra: &str, scene: &str) -> String {
        format!(
            r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="u" meter="{unit}"/><up_axis>Y_UP</up_axis></asset>
{GEOMETRIES}{extra}
<library_visual_scenes><visual_scene id="S">{scene}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#S"/></scene>
</COLLADA>"##
        )
    }

    fn read(text: &str) -> Raw {
        read_dae(text.as_bytes()).unwrap()
    }

    /// The triangles of a read file as corner positions, each triangle's corners in order.
    fn corners((v, t): &Raw) -> Vec<[Vec3; 3]> {
        t.iter().map(|t| t.map(|k| v[k as usize])).collect()
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() <= 1e-6 * (1.0 + b.length())
    }

    #[test]
    fn nested_nodes_compose_parents_first_in_document_order() {
        // Parent: translate then rotate 90 degrees about z; child: a row-major matrix with a
        // translation (0, 0, 5), then scale 2. A point p lands at T R M S p.
        let scene = r##"<node id="a"><translate>10 0 0</translate><rotate>0 0 1 90</rotate>
<node id="b"><matrix>1 0 0 0 0 1 0 0 0 0 1 5 0 0 0 1</matrix><scale>2 2 2</scale>
<instance_geometry url="#g"/></node></node>"##;
        let got = corners(&read(&dae("1", "", scene)));
        let m = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0))
            * Mat4::from_rotation_z(std::f64::consts::FRAC_PI_2)
            * Mat4::from_translation(Vec3::new(0.0, 0.0, 5.0))
            * Mat4::from_scale(Vec3::splat(2.0));
        let want = [Vec3::ZERO, Vec3::X, Vec3::Y].map(|p| m.transform_point3(p));
        assert_eq!(got.len(), 1);
        for k in 0..3 {
            assert!(close(got[0][k], want[k]), "{got:?} vs {want:?}");
        }
        // (1, 0, 0) -> scaled (2, 0, 0) -> (2, 0, 5) -> rotated (0, 2, 5) -> (10, 2, 5).
        assert!(close(got[0][1], Vec3::new(10.0, 2.0, 5.0)));
        // The axis is normalised (OpenGL's glRotate, which the specification follows; assimp
        // and pycollada use it as written, which scales as well as turns).
        let long = scene.replace("0 0 1 90", "0 0 3 90");
        assert_eq!(corners(&read(&dae("1", "", &long))), got);
    }

    #[test]
    fn the_unit_scales_the_whole_scene_and_up_axis_is_ignored() {
        let scene =
            r##"<node><translate>10 20 30</translate><instance_geometry url="#g"/></node>"##;
        let metre = corners(&read(&dae("1", "", scene)));
        let milli = corners(&read(&dae("0.001", "", scene)));
        // A unit in a geometry's own asset is not the document's (which has none here: metres).
        let nested = dae("1", "", scene)
            .replace("<unit name=\"u\" meter=\"1\"/>", "")
            .replace(
                "<geometry id=\"g\">",
                "<geometry id=\"g\"><asset><unit meter=\"0.5\"/></asset>",
            );
        assert!(!nested.contains("meter=\"1\""));
        assert_eq!(corners(&read(&nested)), metre);
        for (a, b) in metre[0].iter().zip(&milli[0]) {
            assert!(close(*b, *a * 0.001), "{a} {b}");
        }
        // Y_UP in the asset: coordinates as written (the corner (0, 1, 0) stays on y).
        assert!(close(metre[0][2], Vec3::new(10.0, 21.0, 30.0)));
        assert!(read_dae(dae("-1", "", scene).as_bytes())
            .unwrap_err()
            .contains("unit"));
    }

    #[test]
    fn instances_nodes_polylists_and_what_is_left_out() {
        // g twice (once through a library node), q once; q's quad is fanned into two
        // triangles and its line skipped; nothing places a third copy.
        let library = r##"<library_nodes><node id="lib"><translate>0 0 7</translate>
<instance_geometry url="#g"/></node></library_nodes>"##;
        let scene = r##"<node><instance_geometry url="#g"/><instance_geometry url="#q"/></node>
<node><translate>0 0 1</translate><instance_node url="#lib"/></node>"##;
        let raw = read(&dae("1", library, scene));
        let tris = corners(&raw);
        assert_eq!(tris.len(), 1 + 2 + 1, "{tris:?}");
        let area: f64 = tris
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .sum();
        assert!((area - (0.5 + 4.0 + 0.5)).abs() < 1e-9, "{area}");
        assert!(tris.iter().any(|t| close(t[0], Vec3::new(0.0, 0.0, 8.0))));
        // Shared corners are merged: g at the origin and q share (0, 0, 0).
        assert_eq!(raw.0.len(), 3 + 3 + 3);
        // Only q placed: g is not read.
        let only_q = read(&dae(
            "1",
            "",
            r##"<node><instance_geometry url="#q"/></node>"##,
        ));
        assert_eq!(only_q.1.len(), 2);
    }

    #[test]
    fn unsupported_or_broken_structure_is_an_error_not_a_panic() {
        let cases = [
            (
                dae(
                    "1",
                    "",
                    r##"<node><instance_geometry url="#nope"/></node>"##,
                ),
                "lacks",
            ),
            (
                dae(
                    "1",
                    "",
                    r##"<node><instance_geometry url="x.dae#g"/></node>"##,
                ),
                "not in this file",
            ),
            (
                dae("1", "", r##"<node><instance_controller url="#c"/></node>"##),
                "instance_controller",
            ),
            (
                dae(
                    "1",
                    "",
                    r##"<node><lookat>0 0 1 0 0 0 0 1 0</lookat></node>"##,
                ),
                "lookat",
            ),
            (
                dae("1", "", r##"<node><translate>1 2</translate></node>"##),
                "3 numbers",
            ),
            (
                dae("1", "", r##"<node><rotate>0 0 0 30</rotate></node>"##),
                "zero axis",
            ),
            (
                dae(
                    "1",
                    concat!(
                        r##"<library_nodes><node id="c"><instance_node url="#c"/>"##,
                        "</node></library_nodes>"
                    ),
                    r##"<node><instance_node url="#c"/></node>"##,
                ),
                "deep",
            ),
            ("<COLLADA/>".to_string(), "instance_visual_scene"),
            (
                // Each library node instances the next twice: 2^40 placements.
                dae(
                    "1",
                    &format!(
                        "<library_nodes>{}<node id='n40'><instance_geometry url='#g'/></node>\
                         </library_nodes>",
                        (0..40)
                            .map(|k| format!(
                                "<node id='n{k}'><instance_node url='#n{0}'/>\
                                 <instance_node url='#n{0}'/></node>",
                                k + 1
                            ))
                            .collect::<String>()
                    ),
                    "<node><instance_node url='#n0'/></node>",
                ),
                "100000 times",
            ),
            (
                format!(
                    "<COLLADA>{}{}</COLLADA>",
                    "<node>".repeat(100_000),
                    "</node>".repeat(100_000)
                ),
                "nested",
            ),
            ("<COLLADA".to_string(), ""),
            (
                dae("1", "", r##"<node><instance_geometry url="#g"/></node>"##)
                    .replace("0 1 2</p>", "0 1 9</p>"),
                "",
            ),
            (
                dae("1", "", "")
                    .replace("<triangles", "<trifans")
                    .replace("</triangles", "</trifans"),
                "trifans",
            ),
        ];
        for (text, needle) in cases {
            let r = std::panic::catch_unwind(|| read_dae(text.as_bytes()));
            let e = r.expect("no panic").expect_err(&text);
            assert!(e.contains(needle), "{e:?} should mention {needle:?}");
        }
        assert!(read_dae(b"\xff\xfe").unwrap_err().contains("UTF-8"));
    }
}
