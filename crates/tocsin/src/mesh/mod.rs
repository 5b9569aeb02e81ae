//! Triangle meshes as polygon soups.
//!
//! A [`TriMesh`] is any list of triangles over a list of vertices: no closedness, orientation,
//! manifoldness or connectivity is assumed. Duplicated vertices and triangles, zero-area
//! triangles (segments, points), isolated vertices and disconnected pieces are all accepted.
//! Construction validates the input (finite coordinates, indices in range, at least one
//! triangle) and builds the [`Bvh`] used by every query. The caller's data is never modified.

mod collada;
mod generate;
mod load;

pub use generate::{box_mesh, capsule, cylinder, plate, revolved, sphere, torus_knot};

use crate::bvh::Bvh;
use crate::error::MeshError;
use crate::math::Vec3;

/// Largest number of vertices or triangles a mesh may have (indices are stored as `u32`).
const MAX_ELEMENTS: usize = i32::MAX as usize;

/// A triangle mesh (polygon soup) with its bounding volume hierarchy, in its body frame.
#[derive(Clone, Debug)]
pub struct TriMesh {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    bvh: Bvh,
    /// The winding number's far-field data per node, built on first use.
    winding: std::sync::OnceLock<Vec<crate::query::penetration::winding::Cluster>>,
    /// The mesh as a convex polytope (`None` when open or not convex), found on first use.
    polytope: std::sync::OnceLock<Option<crate::query::penetration::convex::Polytope>>,
    /// Per leaf position, the leaf positions of the triangles sharing a vertex with it, found on
    /// first use.
    neighbours: std::sync::OnceLock<Neighbours>,
    /// Balls inside the mesh when it is one closed surface (empty otherwise), found on first
    /// use.
    balls: std::sync::OnceLock<Vec<crate::query::penetration::balls::Ball>>,
    /// The convex hull of the corners, as a convex mesh whose polytope climbs, made on first
    /// use ([`TriMesh::hull`]), and whether every distinct corner is one of its corners.
    hull: std::sync::OnceLock<Option<(Box<TriMesh>, bool)>>,
    /// The per-leaf corner ranges a rotation certificate last worked out about an axis, with
    /// that axis's key ([`AxisMemo`]).
    axis_corners: AxisMemo,
}

/// A mesh's last per-leaf ranges about an axis (`query/contact_time/shells.rs`), keyed by the
/// axis's bits: a wrist's frozen checks ask for the same axis piece after piece. A clone
/// starts empty.
#[derive(Debug, Default)]
pub(crate) struct AxisMemo(std::sync::Mutex<Option<AxisCorners>>);

/// A key (the bits of the axis's point, direction and the query's point along it) and the
/// ranges worked out about it.
pub(crate) type AxisCorners = ([u64; 7], std::sync::Arc<AxisRanges>);

/// Corner ranges about an axis (largest distance from it, the axial range, largest distance
/// from a point on it), per leaf position and per run of leaves.
pub(crate) type AxisRanges = [Vec<[f64; 4]>; 2];

impl Clone for AxisMemo {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl AxisMemo {
    /// The ranges kept under `key`, or those `work` makes, then kept in their place.
    pub(crate) fn get_or(
        &self,
        key: [u64; 7],
        work: impl FnOnce() -> AxisRanges,
    ) -> std::sync::Arc<AxisRanges> {
        if let Ok(kept) = self.0.lock() {
            if let Some((k, r)) = kept.as_ref() {
                if *k == key {
                    return r.clone();
                }
            }
        }
        let r = std::sync::Arc::new(work());
        if let Ok(mut kept) = self.0.lock() {
            *kept = Some((key, r.clone()));
        }
        r
    }
}

/// Leaf positions sharing a vertex with each leaf: `list[offsets[i]..offsets[i + 1]]`.
#[derive(Clone, Debug, Default)]
pub(crate) struct Neighbours {
    offsets: Vec<u32>,
    list: Vec<u32>,
}

impl Neighbours {
    /// The neighbours of leaf position `leaf` (empty where out of range).
    pub(crate) fn of(&self, leaf: u32) -> &[u32] {
        let i = leaf as usize;
        match (self.offsets.get(i), self.offsets.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.list[a as usize..b as usize],
            _ => &[],
        }
    }
}

impl TriMesh {
    /// Builds a mesh from vertex coordinates (body frame, model units) and triangles
    /// (three vertex indices each), validating both and building the hierarchy.
    pub fn new(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        Self::built_by(vertices, triangles, Bvh::build)
    }

    /// A mesh of checked parts and their hierarchy, with nothing worked out yet.
    fn assemble(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>, bvh: Bvh) -> Self {
        Self {
            vertices,
            triangles,
            bvh,
            winding: std::sync::OnceLock::new(),
            polytope: std::sync::OnceLock::new(),
            neighbours: std::sync::OnceLock::new(),
            balls: std::sync::OnceLock::new(),
            hull: std::sync::OnceLock::new(),
            axis_corners: AxisMemo::default(),
        }
    }

    /// [`TriMesh::new`] with the hierarchy built by `build` (a hull's is built unrefined).
    fn built_by(
        vertices: Vec<Vec3>,
        triangles: Vec<[u32; 3]>,
        build: fn(&[Vec3], &[[u32; 3]]) -> Bvh,
    ) -> Result<Self, MeshError> {
        validate(&vertices, triangles.iter().map(|t| t.map(i64::from)))?;
        reserve(vertices.len(), triangles.len())?;
        let bvh = build(&vertices, &triangles);
        Ok(Self::assemble(vertices, triangles, bvh))
    }

    /// Builds a mesh from borrowed arrays, with signed indices so that negative indices are
    /// reported as errors rather than wrapped. The inputs are copied, never modified.
    pub fn from_arrays(vertices: &[[f64; 3]], triangles: &[[i64; 3]]) -> Result<Self, MeshError> {
        validate_count("vertices", vertices.len())?;
        validate_count("triangles", triangles.len())?;
        reserve(vertices.len(), triangles.len())?;
        let verts: Vec<Vec3> = vertices.iter().map(|v| Vec3::from_array(*v)).collect();
        validate(&verts, triangles.iter().copied())?;
        // Every index is now known to be in 0..len <= i32::MAX, so the casts are lossless, and
        // the data is valid: build directly rather than validate again in `new`.
        let triangles: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(|i| i as u32)).collect();
        let bvh = Bvh::build(&verts, &triangles);
        Ok(Self::assemble(verts, triangles, bvh))
    }

    /// Loads a mesh from an OBJ, STL (ASCII or binary), PLY or COLLADA (`.dae`) file, chosen
    /// by extension. Polygons are triangulated; all objects of an OBJ file, and every geometry
    /// a COLLADA file's visual scene places (with its nodes' transforms and the unit), are
    /// merged into one soup.
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Self, MeshError> {
        let path = path.as_ref();
        let (vertices, triangles) = load::load_file(path)?;
        Self::new(vertices, triangles).map_err(|e| MeshError::InFile {
            path: path.to_path_buf(),
            source: Box::new(e),
        })
    }

    /// The far-field data of the winding number (built on first use, then kept).
    pub(crate) fn winding_clusters(&self) -> &[crate::query::penetration::winding::Cluster] {
        self.winding
            .get_or_init(|| crate::query::penetration::winding::clusters(self))
    }

    /// The mesh as a convex polytope, or `None` when it is open or not convex (found on first
    /// use, then kept: the test hashes every edge, 15% of a knot2.8k penetration depth when it
    /// ran on every query).
    pub(crate) fn convex_polytope(&self) -> Option<&crate::query::penetration::convex::Polytope> {
        self.polytope
            .get_or_init(|| crate::query::penetration::convex::polytope(self))
            .as_ref()
    }

    /// Whether the mesh is a closed convex polytope to `1e-12` of its bounding radius (every
    /// corner behind every face's plane to that; coplanar and duplicate corners allowed, no
    /// degenerate triangle). Such meshes, two at a time, take the GJK path of the distance
    /// queries and of the time of contact ([`crate::query::distance::GJK_MAX_VERTICES`]):
    /// the test is made on first use and kept, at about the cost of building the mesh (28 ms for
    /// a sphere of 16,128 triangles); the distance queries make it themselves only for meshes
    /// of at most that many corners, so calling this once lets larger convex meshes take the
    /// path too.
    pub fn is_convex(&self) -> bool {
        self.convex_polytope().is_some_and(|p| p.climbs())
    }

    /// A convex polytope holding the mesh, for the time of contact's hull steps: the mesh's own
    /// when it is convex, else the convex hull of its corners ([`Self::hull`]); `None` for a
    /// mesh of more than [`crate::query::distance::GJK_MAX_VERTICES`] corners (the convexity
    /// test is made on first use, at about the cost of building the mesh), a non-convex one of
    /// more than [`HULL_MAX_VERTICES`] distinct corners, or one whose hull could not be made.
    pub(crate) fn outer_polytope(&self) -> Option<Outer<'_>> {
        if self.num_vertices() > crate::query::distance::GJK_MAX_VERTICES {
            return None;
        }
        if let Some(p) = self.convex_polytope().filter(|p| p.climbs()) {
            return Some(Outer {
                mesh: self,
                polytope: p,
                exact: true,
            });
        }
        let hull = self.hull()?;
        let every_corner = self
            .hull
            .get()
            .and_then(Option::as_ref)
            .is_some_and(|h| h.1);
        Some(Outer {
            mesh: hull,
            polytope: hull.convex_polytope()?,
            exact: every_corner,
        })
    }

    /// The convex hull of the corners the triangles use, as a closed convex mesh whose
    /// polytope climbs (parry3d-f64's quickhull; the hull's corners are the mesh's own, to the
    /// bit), made on first use and kept. `None` for a flat or degenerate set of corners, a
    /// mesh far from convex (fewer than nine in ten of its distinct corners on the hull; a
    /// corner written once per face counts once), one of more than [`HULL_MAX_VERTICES`]
    /// distinct corners, or a hull that fails the strict convexity test. Nothing relies on the
    /// hull holding every corner: it only proposes a direction, and the gap along it is
    /// measured on the mesh's corners (climbed on the hull where it keeps them all,
    /// [`Outer::exact`], else searched by [`crate::bvh::Bvh::support`]).
    pub(crate) fn hull(&self) -> Option<&TriMesh> {
        self.hull
            .get_or_init(|| hull_of(self))
            .as_ref()
            .map(|(h, _)| &**h)
    }

    /// Whether the convex polytope test has been made (by an earlier query).
    pub(crate) fn has_convex_polytope(&self) -> bool {
        self.polytope.get().is_some()
    }

    /// Balls inside the mesh, when its triangles form one closed connected surface (found on
    /// first use, then kept; see [`crate::query::penetration::balls`]).
    pub(crate) fn inscribed_balls(&self) -> &[crate::query::penetration::balls::Ball] {
        self.balls
            .get_or_init(|| crate::query::penetration::balls::inscribed_balls(self))
    }

    /// The last per-leaf ranges worked out about an axis ([`AxisMemo`]).
    pub(crate) fn axis_corners(&self) -> &AxisMemo {
        &self.axis_corners
    }

    /// Per leaf position, the leaf positions of the triangles that share a vertex with it
    /// (built on first use, then kept).
    pub(crate) fn leaf_neighbours(&self) -> &Neighbours {
        self.neighbours.get_or_init(|| {
            let n = self.triangles.len();
            let leaf_corners: Vec<[u32; 3]> = (0..n as u32)
                .map(|leaf| self.triangles[self.bvh.triangle_index(leaf)])
                .collect();
            let corners = |leaf: u32| leaf_corners[leaf as usize];
            // The leaves at each vertex, in one array (counted, then filled).
            let mut start = vec![0u32; self.vertices.len() + 1];
            for leaf in 0..n as u32 {
                for v in corners(leaf) {
                    start[v as usize + 1] += 1;
                }
            }
            for i in 0..self.vertices.len() {
                start[i + 1] += start[i];
            }
            let mut fill = start.clone();
            let mut at_vertex = vec![0u32; start[self.vertices.len()] as usize];
            for leaf in 0..n as u32 {
                for v in corners(leaf) {
                    at_vertex[fill[v as usize] as usize] = leaf;
                    fill[v as usize] += 1;
                }
            }
            let mut offsets = Vec::with_capacity(n + 1);
            let mut list = Vec::with_capacity(at_vertex.len() * 2);
            // The leaf each other leaf was last listed for: each listed once per leaf.
            let mut listed_for = vec![u32::MAX; n];
            offsets.push(0);
            for leaf in 0..n as u32 {
                listed_for[leaf as usize] = leaf;
                for v in corners(leaf) {
                    let (a, b) = (start[v as usize] as usize, start[v as usize + 1] as usize);
                    for &other in &at_vertex[a..b] {
                        if listed_for[other as usize] != leaf {
                            listed_for[other as usize] = leaf;
                            list.push(other);
                        }
                    }
                }
                offsets.push(list.len() as u32);
            }
            Neighbours { offsets, list }
        })
    }

    /// The vertices and triangles of an OBJ, STL, PLY or COLLADA file, without building a
    /// mesh.
    ///
    /// # Errors
    /// As [`TriMesh::load`].
    pub fn load_raw(path: &std::path::Path) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), MeshError> {
        load::load_file(path)
    }

    /// The vertex coordinates, body frame.
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The triangles, as vertex indices.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.triangles.len()
    }

    /// The three corners of triangle `i`, body frame.
    #[inline]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        self.triangles[i].map(|v| self.vertices[v as usize])
    }

    /// The bounding volume hierarchy.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Radius of a ball about the root volume's centre that contains the mesh (model units):
    /// the scale used by relative tolerances.
    pub fn bounding_radius(&self) -> f64 {
        self.bvh.root().bounding_radius()
    }
}

/// Bytes a mesh needs per triangle while it is built and after: the hierarchy's two nodes of
/// 136 bytes, the leaf corners (72) and their `f32` columns (36), distinct vertices (about 40),
/// indices, and the build's temporaries (76), rounded up.
const BYTES_PER_TRIANGLE: usize = 560;
/// Bytes per vertex: its coordinates and the build's per-vertex marks.
const BYTES_PER_VERTEX: usize = 32;

/// Checks, before anything large is allocated, that the memory a mesh of this size needs can
/// be reserved (a failed allocation later would abort the process, and in Python the
/// interpreter): one reservation of the whole estimate, released at once.
pub fn reserve(num_vertices: usize, num_triangles: usize) -> Result<(), MeshError> {
    let bytes = num_triangles
        .saturating_mul(BYTES_PER_TRIANGLE)
        .saturating_add(num_vertices.saturating_mul(BYTES_PER_VERTEX));
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| MeshError::OutOfMemory {
            triangles: num_triangles,
            vertices: num_vertices,
            bytes,
        })
}

fn validate_count(what: &'static str, count: usize) -> Result<(), MeshError> {
    if count > MAX_ELEMENTS {
        return Err(MeshError::TooLarge { what, count });
    }
    Ok(())
}

fn validate(
    vertices: &[Vec3],
    triangles: impl ExactSizeIterator<Item = [i64; 3]>,
) -> Result<(), MeshError> {
    validate_count("vertices", vertices.len())?;
    validate_count("triangles", triangles.len())?;
    if triangles.len() == 0 {
        return Err(MeshError::NoTriangles);
    }
    let mut magnitude: f64 = 0.0;
    for (vertex, v) in vertices.iter().enumerate() {
        for (k, axis) in ['x', 'y', 'z'].into_iter().enumerate() {
            if !v[k].is_finite() {
                return Err(MeshError::NonFiniteCoordinate {
                    vertex,
                    axis,
                    value: v[k],
                });
            }
            if v[k].abs() > crate::math::MAX_COORDINATE {
                return Err(MeshError::CoordinateOutOfRange {
                    vertex,
                    axis,
                    value: v[k],
                });
            }
            magnitude = magnitude.max(v[k].abs());
        }
    }
    if magnitude > 0.0 && magnitude < crate::math::MIN_SCALE {
        return Err(MeshError::TooSmall { magnitude });
    }
    let n = vertices.len() as i64;
    for (triangle, t) in triangles.enumerate() {
        for (corner, &index) in t.iter().enumerate() {
            if index < 0 || index >= n {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    corner,
                    index,
                    num_vertices: vertices.len(),
                });
            }
        }
    }
    Ok(())
}

/// Non-convex meshes with more distinct corners than this get no hull ([`TriMesh::hull`]): the
/// hull is made on a mesh's first time of contact, and quickhull slows on corners in awkward
/// places (a tube's 2,304 corners on rings took 11 ms, and the hull was then refused). Robot
/// collision meshes have a few hundred.
pub(crate) const HULL_MAX_VERTICES: usize = 1024;

/// The share of a mesh's distinct corners its hull must keep for the mesh to have one
/// ([`TriMesh::hull`]): a mesh convex but for its triangulation (robot collision meshes such
/// as MotionBenchMaker's Panda but `link6` and its Fetch keep all of them) is as near its hull as
/// the hull's step needs; one far from convex (MotionBenchMaker's UR5 links keep 30 to 50%)
/// would pay for GJK on a hull whose gap is not the mesh's (docs/BENCHMARKS.md,
/// forty-first session).
const HULL_CORNERS: f64 = 0.9;

/// A convex polytope holding a mesh ([`TriMesh::outer_polytope`]).
pub(crate) struct Outer<'a> {
    /// The mesh itself where it is convex, else its hull.
    pub mesh: &'a TriMesh,
    /// `mesh`'s polytope, which climbs.
    pub polytope: &'a crate::query::penetration::convex::Polytope,
    /// Whether every distinct corner of the mesh is a corner of `mesh` (a convex mesh, or a
    /// hull that kept them all): then a corner of `mesh` farthest along a direction, climbed
    /// on `polytope`, is one of the mesh's farthest too, every corner of `mesh` being one of
    /// the mesh's and every corner of the mesh one of `mesh`'s.
    pub exact: bool,
}

/// The hull of [`TriMesh::hull`], and whether it kept every distinct corner.
fn hull_of(mesh: &TriMesh) -> Option<(Box<TriMesh>, bool)> {
    use parry3d_f64::math::Vector3;
    let mut used = vec![false; mesh.num_vertices()];
    for t in mesh.triangles() {
        t.iter().for_each(|&i| used[i as usize] = true);
    }
    // Distinct positions: a file written with a corner per face (MotionBenchMaker's Panda `link4`
    // repeats each of its 152 corners about six times) is as near its hull as one that shares
    // them, and counted by index it kept 17% of its corners. Sorted on this thread, not by
    // `bvh::same_position`, which sorts on rayon's pool: under this mesh's `OnceLock` a wait
    // on rayon can deadlock (below).
    let distinct = |mut points: Vec<[f64; 3]>| {
        points.sort_unstable_by(|a, b| {
            (a[0].total_cmp(&b[0]))
                .then(a[1].total_cmp(&b[1]))
                .then(a[2].total_cmp(&b[2]))
        });
        points.dedup_by(|a, b| a.map(f64::to_bits) == b.map(f64::to_bits));
        points
    };
    let distinct_corners = distinct(
        mesh.vertices()
            .iter()
            .zip(&used)
            .filter(|(_, &u)| u)
            .map(|(v, _)| v.to_array())
            .collect(),
    );
    if distinct_corners.len() > HULL_MAX_VERTICES {
        return None;
    }
    let points: Vec<Vector3> = distinct_corners
        .iter()
        .map(|&[x, y, z]| Vector3::new(x, y, z))
        .collect();
    // The crate's errors are values; a panic on input it does not foresee is caught, and the
    // mesh is then without a hull.
    let hull = std::panic::catch_unwind(|| parry3d_f64::transformation::try_convex_hull(&points));
    let (corners, triangles) = hull.ok()?.ok()?;
    if (corners.len() as f64) < HULL_CORNERS * points.len() as f64 {
        return None;
    }
    let corners: Vec<Vec3> = corners.iter().map(|c| Vec3::new(c.x, c.y, c.z)).collect();
    // Every distinct corner is a hull corner, to the bit (the hull's supports are then the
    // mesh's: `Outer::exact`).
    let every_corner = distinct(corners.iter().map(|c| c.to_array()).collect()) == distinct_corners;
    // The hull's hierarchy is only read for its root (GJK's scale) and leaf order: it is built
    // without the in-plane refinement that meshes of up to 256 triangles get, which took
    // 4.6 ms of a 200-triangle hull's 5 ms.
    // Built on a thread and a pool of their own. The hull is made inside a query, under this
    // mesh's `OnceLock`. A forked child may run the query where rayon's global pool is gone
    // (the parent's threads do not survive a fork), and the hierarchy's build fills its arrays
    // in parallel: a forked child hung on it. And a rayon worker waiting for another pool
    // steals work meanwhile, such as another query on this mesh that then waits on the same
    // `OnceLock`: `paths_are_free` deadlocked so. A plain thread's join steals nothing.
    let build = || {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .ok()?;
        pool.install(|| TriMesh::built_by(corners, triangles, Bvh::build_unrefined).ok())
    };
    let hull = std::thread::scope(|s| s.spawn(build).join()).ok()??;
    hull.convex_polytope()
        .filter(|p| p.climbs())
        .is_some()
        .then(|| (Box::new(hull), every_corner))
}

#[cfg(test)]
mod neighbour_tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every leaf's neighbours against brute force over all triangle pairs (the leaves whose
    /// triangles share a vertex index with it, itself excluded, each once), on a knot and on
    /// soups of few vertices with repeated corners (segments, points) and duplicated triangles.
    #[test]
    fn leaf_neighbours_match_brute_force() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let mut meshes = vec![crate::mesh::torus_knot(20, 5).expect("knot")];
        for _ in 0..4 {
            let vertices: Vec<Vec3> = (0..30)
                .map(|_| Vec3::new(rng.random(), rng.random(), rng.random()))
                .collect();
            let mut triangles: Vec<[u32; 3]> = (0..60)
                .map(|_| [0; 3].map(|_| rng.random_range(0..30u32)))
                .collect();
            triangles.push(triangles[0]);
            meshes.push(TriMesh::new(vertices, triangles).expect("soup"));
        }
        let mut entries = 0;
        for m in &meshes {
            let bvh = m.bvh();
            let n = m.triangles().len() as u32;
            for leaf in 0..n {
                let t = m.triangles()[bvh.triangle_index(leaf)];
                let mut want: Vec<u32> = (0..n)
                    .filter(|&o| {
                        o != leaf
                            && m.triangles()[bvh.triangle_index(o)]
                                .iter()
                                .any(|v| t.contains(v))
                    })
                    .collect();
                let mut got = m.leaf_neighbours().of(leaf).to_vec();
                assert_eq!(got.len(), want.len(), "leaf {leaf}: duplicates or misses");
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "leaf {leaf}");
                entries += got.len();
            }
            assert!(m.leaf_neighbours().of(n).is_empty());
        }
        assert!(entries > 1000, "{entries} neighbour entries");
    }
}

#[cfg(test)]
pub(crate) mod hull_tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A coarse sphere whose corners are moved along their radius by up to 0.3%: every corner
    /// stays on the hull, but about half of the quads fold the wrong way (a mesh convex but for
    /// its triangulation, as robot collision meshes are).
    pub(crate) fn dented_sphere(seed: u64) -> TriMesh {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let s = crate::mesh::sphere(1.0, 8, 12).expect("sphere");
        let v = s
            .vertices()
            .iter()
            .map(|p| *p * (1.0 + rng.random_range(-0.003..0.003)))
            .collect();
        TriMesh::new(v, s.triangles().to_vec()).expect("dented")
    }

    /// The hull's corners are the mesh's own to the bit, every corner of the mesh lies behind
    /// every face of the hull (to the strict convexity test's allowance), a convex mesh is its
    /// own outer polytope, and a knot (few corners on its hull) has none.
    #[test]
    fn hull_holds_the_corners_and_keeps_them_exact() {
        for seed in 0..6 {
            let m = dented_sphere(seed);
            assert!(
                m.convex_polytope().filter(|p| p.climbs()).is_none(),
                "seed {seed}: the dents should make the sphere non-convex"
            );
            let hull = m.hull().expect("a hull");
            let outer = m.outer_polytope().expect("an outer polytope");
            assert!(std::ptr::eq(outer.mesh, hull));
            for c in hull.vertices() {
                assert!(
                    m.vertices().contains(c),
                    "seed {seed}: corner {c} is not the mesh's"
                );
            }
            let allowance = crate::query::penetration::convex::STRICT * m.bounding_radius();
            for t in hull.triangles() {
                let [a, b, c] = t.map(|i| hull.vertices()[i as usize]);
                let n = (b - a).cross(c - a).normalize();
                // Outward: the hull's centroid is behind it.
                let centre =
                    hull.vertices().iter().copied().sum::<Vec3>() / hull.num_vertices() as f64;
                let n = if n.dot(centre - a) > 0.0 { -n } else { n };
                let beyond = m
                    .vertices()
                    .iter()
                    .map(|p| n.dot(*p - a))
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!(
                    beyond <= allowance,
                    "seed {seed}: a corner {beyond} beyond a face"
                );
            }
        }
        let cube = crate::mesh::box_mesh(Vec3::new(0.5, 0.2, 0.3)).expect("box");
        let outer = cube.outer_polytope().expect("a convex mesh is its own");
        assert!(std::ptr::eq(outer.mesh, &cube) && outer.exact);
        let knot = crate::mesh::torus_knot(40, 6).expect("knot");
        assert!(knot.hull().is_none() && knot.outer_polytope().is_none());
    }

    /// A file that writes each face's corners apart (as MotionBenchMaker's Panda `link4` does)
    /// is as near its hull as one that shares them: the share on the hull counts positions,
    /// not indices. Counted by index, the dented sphere below keeps a sixth of its corners.
    #[test]
    fn corners_written_per_face_count_once() {
        for seed in 0..3 {
            let m = dented_sphere(seed);
            let v: Vec<Vec3> = m
                .triangles()
                .iter()
                .flat_map(|t| t.map(|i| m.vertices()[i as usize]))
                .collect();
            let t: Vec<[u32; 3]> = (0..m.num_triangles() as u32)
                .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
                .collect();
            let apart = TriMesh::new(v, t).expect("corners apart");
            assert!(apart.num_vertices() > 5 * m.hull().expect("a hull").num_vertices());
            let hull = apart.hull().expect("the same hull");
            assert_eq!(
                hull.num_vertices(),
                m.hull().expect("a hull").num_vertices()
            );
            let mut a = hull.vertices().to_vec();
            let mut b = m.hull().expect("a hull").vertices().to_vec();
            let key = |p: &Vec3| p.to_array().map(f64::to_bits);
            a.sort_by_key(key);
            b.sort_by_key(key);
            assert_eq!(a, b, "seed {seed}: the hulls' corners differ");
        }
    }
}
