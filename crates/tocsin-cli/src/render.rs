//! A picture of two meshes at a contact: orthographic view across the contact normal (body 1
//! below, body 2 above), flat-shaded triangles with a depth buffer, the witness points as
//! discs and the normal as a short line; written as PNG. Software rendering, no GPU needed.

use tocsin::{Pose, TriMesh, Vec3};

/// What to mark on the picture: the witness points and the unit normal (world frame).
pub struct Marks {
    /// Closest point on body 1.
    pub point1: Vec3,
    /// Closest point on body 2.
    pub point2: Vec3,
    /// Unit normal from body 1 to body 2.
    pub normal: Vec3,
}

/// An RGB image with a depth buffer (larger depth is nearer the viewer).
pub struct Canvas {
    w: usize,
    h: usize,
    rgb: Vec<u8>,
    depth: Vec<f64>,
}

/// An orthographic view: image x along `right`, image y along `up`, depth along `toward` (the
/// viewer), `scale` pixels per model unit around the world point `center`.
pub struct View {
    /// Unit world direction of the image's x axis.
    pub right: Vec3,
    /// Unit world direction of the image's y axis (up on the picture).
    pub up: Vec3,
    /// World point at the middle of the image.
    pub center: Vec3,
    /// Pixels per model unit.
    pub scale: f64,
}

impl View {
    fn project(&self, v: Vec3, (w, h): (usize, usize)) -> (f64, f64, f64) {
        let d = v - self.center;
        (
            d.dot(self.right) * self.scale + 0.5 * w as f64,
            0.5 * h as f64 - d.dot(self.up) * self.scale,
            d.dot(self.right.cross(self.up)),
        )
    }
}

impl Canvas {
    /// A white `width x height` image.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            w: width,
            h: height,
            rgb: vec![255; 3 * width * height],
            depth: vec![f64::NEG_INFINITY; width * height],
        }
    }

    fn put(&mut self, x: i64, y: i64, z: f64, c: [u8; 3]) {
        if x < 0 || y < 0 || x >= self.w as i64 || y >= self.h as i64 {
            return;
        }
        let i = y as usize * self.w + x as usize;
        if z >= self.depth[i] {
            self.depth[i] = z;
            self.rgb[3 * i..3 * i + 3].copy_from_slice(&c);
        }
    }

    /// Draws `mesh` at `pose`, flat-shaded from `base` colour, with the depth test.
    pub fn draw_mesh(&mut self, mesh: &TriMesh, pose: &Pose, base: [f64; 3], view: &View) {
        let toward = view.right.cross(view.up);
        let size = (self.w, self.h);
        let verts: Vec<Vec3> = mesh
            .vertices()
            .iter()
            .map(|v| pose.transform_point(*v))
            .collect();
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|i| verts[i as usize]);
            let shade = 0.35 + 0.65 * (b - a).cross(c - a).normalize_or_zero().dot(toward).abs();
            let color = base.map(|ch| (ch * shade).min(255.0) as u8);
            let [pa, pb, pc] = [a, b, c].map(|v| view.project(v, size));
            let area = (pb.0 - pa.0) * (pc.1 - pa.1) - (pc.0 - pa.0) * (pb.1 - pa.1);
            if area.abs() < 1e-12 {
                // Seen edge-on: a line, so that thin plates stay visible.
                self.line((pa.0, pa.1), (pb.0.max(pc.0), pb.1.max(pc.1)), pa.2, color);
                continue;
            }
            let x0 = pa.0.min(pb.0).min(pc.0).floor().max(0.0) as i64;
            let x1 = pa.0.max(pb.0).max(pc.0).ceil().min(self.w as f64 - 1.0) as i64;
            let y0 = pa.1.min(pb.1).min(pc.1).floor().max(0.0) as i64;
            let y1 = pa.1.max(pb.1).max(pc.1).ceil().min(self.h as f64 - 1.0) as i64;
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    let w0 = ((pb.0 - px) * (pc.1 - py) - (pc.0 - px) * (pb.1 - py)) / area;
                    let w1 = ((pc.0 - px) * (pa.1 - py) - (pa.0 - px) * (pc.1 - py)) / area;
                    let w2 = 1.0 - w0 - w1;
                    if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
                        self.put(x, y, w0 * pa.2 + w1 * pb.2 + w2 * pc.2, color);
                    }
                }
            }
        }
    }

    /// A one-pixel line at depth `z`.
    fn line(&mut self, a: (f64, f64), b: (f64, f64), z: f64, c: [u8; 3]) {
        let n = (b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil().min(1e5) as i64;
        for k in 0..=n {
            let s = if n == 0 { 0.0 } else { k as f64 / n as f64 };
            let (x, y) = (a.0 + s * (b.0 - a.0), a.1 + s * (b.1 - a.1));
            self.put(x as i64, y as i64, z, c);
        }
    }

    /// Copies `other` into this image with its top left corner at `(x, y)`.
    pub fn blit(&mut self, other: &Canvas, x: usize, y: usize) {
        for row in 0..other.h.min(self.h.saturating_sub(y)) {
            let n = other.w.min(self.w.saturating_sub(x));
            let src = &other.rgb[3 * row * other.w..3 * (row * other.w + n)];
            let at = 3 * ((y + row) * self.w + x);
            self.rgb[at..at + 3 * n].copy_from_slice(src);
        }
    }

    /// Writes the image as PNG. Encoded in memory, then written in one call whose every error
    /// is reported (a buffered file writer dropped at the end lost "no space left on device").
    pub fn write_png(&self, path: &str) -> Result<(), String> {
        let mut bytes = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut bytes, self.w as u32, self.h as u32);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            let mut writer = enc.write_header().map_err(|e| format!("{path}: {e}"))?;
            writer
                .write_image_data(&self.rgb)
                .map_err(|e| format!("{path}: {e}"))?;
            writer.finish().map_err(|e| format!("{path}: {e}"))?;
        }
        std::fs::write(path, &bytes).map_err(|e| format!("cannot write {path}: {e}"))
    }
}

/// Renders `mesh1` at `pose1` and `mesh2` at `pose2` to a `width x height` PNG at `path`.
pub fn render(
    path: &str,
    (mesh1, pose1): (&TriMesh, &Pose),
    (mesh2, pose2): (&TriMesh, &Pose),
    marks: &Marks,
    (width, height): (usize, usize),
) -> Result<(), String> {
    // Image axes: y along the normal, x across it; we look along x cross y.
    let up = marks.normal.try_normalize().unwrap_or(Vec3::Z);
    let right = up.any_orthonormal_vector();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (m, p) in [(mesh1, pose1), (mesh2, pose2)] {
        for v in m.vertices() {
            let v = p.transform_point(*v);
            let q = [v.dot(right), v.dot(up)];
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-300);
    let view = View {
        right,
        up,
        center: right * 0.5 * (lo[0] + hi[0]) + up * 0.5 * (lo[1] + hi[1]),
        scale: 0.9 * (width.min(height) as f64) / span,
    };
    let mut canvas = Canvas::new(width, height);
    canvas.draw_mesh(mesh1, pose1, [70.0, 120.0, 200.0], &view);
    canvas.draw_mesh(mesh2, pose2, [230.0, 140.0, 50.0], &view);
    // Marks on top of everything: the normal as a line from point 1, the witnesses as discs.
    let size = (width, height);
    let (p1, p2) = (
        view.project(marks.point1, size),
        view.project(marks.point2, size),
    );
    let len = 0.15 * height as f64;
    for k in 0..=(len as i64) {
        let (x, y) = (p1.0, p1.1 - k as f64);
        for dx in -1..=1 {
            canvas.put(x as i64 + dx, y as i64, f64::INFINITY, [200, 0, 0]);
        }
    }
    for (p, c) in [(p1, [0, 0, 0]), (p2, [200, 0, 0])] {
        for dy in -5i64..=5 {
            for dx in -5i64..=5 {
                if dx * dx + dy * dy <= 25 {
                    canvas.put(p.0 as i64 + dx, p.1 as i64 + dy, f64::INFINITY, c);
                }
            }
        }
    }
    canvas.write_png(path)
}
