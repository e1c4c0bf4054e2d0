//! Triangle meshes from OBJ and STL (ascii or binary) files, and area-weighted surface
//! sampling.

use super::{CloudError, PointCloud, SampleOptions, MAX_MESH_TRIANGLES};
use crate::geometry::shape::TriMesh;
use crate::robot::{MeshRef, RobotError};
use nalgebra::{Point3, Vector3};
use rand::{rngs::StdRng, RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::path::Path;

/// A triangle mesh (metres). Triangles list vertex indices counter-clockwise seen from
/// outside, so `(b − a) × (c − a)` is the outward normal.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct TriangleMesh {
    /// Vertex positions (m).
    pub vertices: Vec<Point3<f64>>,
    /// Vertex indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// The corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [Point3<f64>; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }

    /// Total surface area (m²).
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }

    fn triangle_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.corners(t);
        0.5 * (b - a).cross(&(c - a)).norm()
    }

    /// `options.points` points drawn uniformly over the surface (triangles chosen by area,
    /// then uniform barycentric coordinates), each with its triangle's unit normal. With a
    /// `view`, only points whose normal faces the viewpoint are kept (back-face culling; mesh
    /// self-occlusion is not traced). `source_name` names the mesh in errors.
    pub fn sample(
        &self,
        options: &SampleOptions,
        source_name: &str,
    ) -> Result<PointCloud, CloudError> {
        options.check()?;
        let mut cumulative = Vec::with_capacity(self.triangles.len());
        let mut total = 0.0;
        for t in 0..self.triangles.len() {
            total += self.triangle_area(t);
            cumulative.push(total);
        }
        if !(total > 0.0 && total.is_finite()) {
            return Err(CloudError::Empty {
                source_name: source_name.to_string(),
            });
        }
        let mut rng = StdRng::seed_from_u64(options.seed);
        let noise = Normal::new(0.0, options.noise).map_err(|e| CloudError::BadOption {
            field: "noise".into(),
            message: e.to_string(),
        })?;
        let mut cloud = PointCloud {
            points: Vec::with_capacity(options.points),
            normals: Some(Vec::with_capacity(options.points)),
        };
        let mut attempts = 0usize;
        while cloud.points.len() < options.points {
            attempts += 1;
            // Fewer than one draw in 200 facing the viewpoint: give up early, not after
            // 200 × points draws.
            if attempts > 200 * cloud.points.len() + 1000 {
                return Err(CloudError::BadOption {
                    field: "view".into(),
                    message: format!("{source_name}: almost no surface faces the viewpoint"),
                });
            }
            let u: f64 = rng.random::<f64>() * total;
            let t = cumulative
                .partition_point(|&c| c < u)
                .min(self.triangles.len() - 1);
            let [a, b, c] = self.corners(t);
            let normal = (b - a).cross(&(c - a));
            if normal.norm() == 0.0 {
                continue;
            }
            let normal = normal.normalize();
            let (mut r1, mut r2): (f64, f64) = (rng.random(), rng.random());
            if r1 + r2 > 1.0 {
                r1 = 1.0 - r1;
                r2 = 1.0 - r2;
            }
            let p = a + (b - a) * r1 + (c - a) * r2;
            if let Some(v) = options.view {
                if normal.dot(&(Point3::from(v) - p)) <= 0.0 {
                    continue;
                }
            }
            let jitter = if options.noise > 0.0 {
                Vector3::new(
                    noise.sample(&mut rng),
                    noise.sample(&mut rng),
                    noise.sample(&mut rng),
                )
            } else {
                Vector3::zeros()
            };
            cloud.points.push(p + jitter);
            if let Some(ns) = cloud.normals.as_mut() {
                ns.push(normal);
            }
        }
        Ok(cloud)
    }
}

/// A robot link's collision mesh ([`MeshRef`], resolved from its URDF) read and scaled: a
/// triangle mesh in the collision frame (m). Errors name the robot file, the link and the mesh.
pub fn load_collision_mesh(mesh: &MeshRef) -> Result<TriMesh, RobotError> {
    let fail = |source: Box<dyn std::error::Error + Send + Sync>| RobotError::MeshLoad {
        source_name: mesh.source_name.clone(),
        link: mesh.link.clone(),
        path: mesh.path.clone(),
        source,
    };
    let read = read_mesh(&mesh.path).map_err(|e| fail(Box::new(e)))?;
    let s = mesh.scale;
    let vertices = read
        .vertices
        .iter()
        .map(|v| Point3::new(v.x * s[0], v.y * s[1], v.z * s[2]))
        .collect();
    TriMesh::new(vertices, read.triangles).map_err(|e| fail(Box::new(e)))
}

/// Reads an `.obj` or `.stl` (ascii or binary) mesh.
pub fn read_mesh(path: &Path) -> Result<TriangleMesh, CloudError> {
    let name = path.display().to_string();
    let bytes = crate::input::read(path, crate::input::MAX_CLOUD_FILE_BYTES)
        .map_err(|e| CloudError::io(&name, e))?;
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let mesh = match ext.as_deref() {
        Some("obj") => parse_obj(&String::from_utf8_lossy(&bytes), &name)?,
        Some("stl") => parse_stl(&bytes, &name)?,
        _ => {
            return Err(CloudError::UnknownFormat {
                source_name: name,
                expected: "obj or .stl".into(),
            })
        }
    };
    if mesh.triangles.is_empty() {
        return Err(CloudError::Empty { source_name: name });
    }
    Ok(mesh)
}

/// The three finite coordinates that follow a vertex keyword on text line `index` (0-based).
fn vertex_coordinates<'a>(
    tokens: &mut impl Iterator<Item = &'a str>,
    source_name: &str,
    index: usize,
) -> Result<[f64; 3], CloudError> {
    let mut xyz = [0.0; 3];
    for slot in &mut xyz {
        *slot = tokens
            .next()
            .and_then(|t| t.parse::<f64>().ok())
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                CloudError::parse(
                    source_name,
                    format!("line {}", index + 1),
                    "a vertex needs three finite numbers",
                )
            })?;
    }
    Ok(xyz)
}

/// Parses Wavefront OBJ text: `v x y z` and `f i j k ...` lines (polygons fanned into
/// triangles; `i/t/n` forms and negative indices accepted). Other lines are ignored.
pub(super) fn parse_obj(text: &str, source_name: &str) -> Result<TriangleMesh, CloudError> {
    let mut mesh = TriangleMesh::default();
    for (number, line) in text.lines().enumerate() {
        let at = || format!("line {}", number + 1);
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let xyz = vertex_coordinates(&mut tokens, source_name, number)?;
                mesh.vertices.push(Point3::from(xyz));
            }
            Some("f") => {
                let mut indices = Vec::new();
                for token in tokens {
                    let first = token.split('/').next().unwrap_or("");
                    let i: i64 = first.parse().map_err(|_| {
                        CloudError::parse(source_name, at(), format!("bad vertex index '{token}'"))
                    })?;
                    let n = mesh.vertices.len() as i64;
                    let resolved = if i < 0 { n + i } else { i - 1 };
                    if resolved < 0 || resolved >= n {
                        return Err(CloudError::parse(
                            source_name,
                            at(),
                            format!("vertex index {i} is out of range (1..={n})"),
                        ));
                    }
                    indices.push(resolved as u32);
                }
                if indices.len() < 3 {
                    return Err(CloudError::parse(
                        source_name,
                        at(),
                        "a face needs three vertices",
                    ));
                }
                if mesh.triangles.len() + indices.len() - 2 > MAX_MESH_TRIANGLES {
                    return Err(CloudError::TooLarge {
                        source_name: source_name.to_string(),
                        field: format!("{}: triangles", at()),
                        count: (mesh.triangles.len() + indices.len() - 2) as u64,
                        limit: MAX_MESH_TRIANGLES,
                    });
                }
                for k in 1..indices.len() - 1 {
                    mesh.triangles
                        .push([indices[0], indices[k], indices[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}

/// Parses an STL file, binary (80-byte header, u32 count, 50 bytes per triangle) or ascii
/// (`solid ... facet ... vertex x y z ...`). Triangle winding is kept as stored. At most
/// [`MAX_MESH_TRIANGLES`] triangles.
pub(super) fn parse_stl(bytes: &[u8], source_name: &str) -> Result<TriangleMesh, CloudError> {
    let looks_ascii = bytes.trim_ascii_start().starts_with(b"solid");
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        let expected = 84 + 50 * count as u64;
        if expected == bytes.len() as u64 && count > MAX_MESH_TRIANGLES {
            return Err(CloudError::TooLarge {
                source_name: source_name.to_string(),
                field: "triangle count".into(),
                count: count as u64,
                limit: MAX_MESH_TRIANGLES,
            });
        }
        if !looks_ascii && expected != bytes.len() as u64 {
            return Err(CloudError::parse(
                source_name,
                "triangle count",
                format!(
                    "the binary STL header announces {count} triangles ({expected} bytes) but the file has {} bytes",
                    bytes.len()
                ),
            ));
        }
        if bytes.len() as u64 == expected {
            let mut mesh = TriangleMesh::default();
            for t in 0..count {
                let base = 84 + 50 * t + 12;
                let mut corner = |k: usize| {
                    let f = |j: usize| {
                        let o = base + 12 * k + 4 * j;
                        f64::from(f32::from_le_bytes([
                            bytes[o],
                            bytes[o + 1],
                            bytes[o + 2],
                            bytes[o + 3],
                        ]))
                    };
                    mesh.vertices.push(Point3::new(f(0), f(1), f(2)));
                    (mesh.vertices.len() - 1) as u32
                };
                let tri = [corner(0), corner(1), corner(2)];
                mesh.triangles.push(tri);
            }
            if mesh
                .vertices
                .iter()
                .any(|v| v.iter().any(|c| !c.is_finite()))
            {
                return Err(CloudError::parse(
                    source_name,
                    "vertex",
                    "not a finite number",
                ));
            }
            return Ok(mesh);
        }
    }
    let text = String::from_utf8_lossy(bytes);
    if !looks_ascii {
        return Err(CloudError::parse(
            source_name,
            "header",
            "neither a binary STL (size does not match the triangle count) nor an ascii one ('solid')",
        ));
    }
    let mut mesh = TriangleMesh::default();
    let mut pending = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("vertex") => {
                let xyz = vertex_coordinates(&mut tokens, source_name, number)?;
                mesh.vertices.push(Point3::from(xyz));
                pending.push((mesh.vertices.len() - 1) as u32);
            }
            Some("endfacet") => {
                if pending.len() != 3 {
                    return Err(CloudError::parse(
                        source_name,
                        format!("line {}", number + 1),
                        format!("a facet has {} vertices, expected 3", pending.len()),
                    ));
                }
                if mesh.triangles.len() >= MAX_MESH_TRIANGLES {
                    return Err(CloudError::TooLarge {
                        source_name: source_name.to_string(),
                        field: format!("line {}: triangles", number + 1),
                        count: mesh.triangles.len() as u64 + 1,
                        limit: MAX_MESH_TRIANGLES,
                    });
                }
                mesh.triangles.push([pending[0], pending[1], pending[2]]);
                pending.clear();
            }
            _ => {}
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE_OBJ: &str =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

    #[test]
    fn obj_cube_has_unit_faces_and_outward_normals() {
        let mesh = parse_obj(CUBE_OBJ, "cube.obj").expect("parse");
        assert_eq!(mesh.triangles.len(), 12);
        assert!((mesh.area() - 6.0).abs() < 1e-12);
        let options = SampleOptions {
            points: 3000,
            seed: 4,
            view: None,
            noise: 0.0,
        };
        let cloud = mesh.sample(&options, "cube").expect("sample");
        let normals = cloud.normals.expect("normals");
        let centre = Point3::new(0.5, 0.5, 0.5);
        let mut per_face = [0usize; 6];
        for (p, n) in cloud.points.iter().zip(&normals) {
            assert!(n.dot(&(p - centre)) > 0.0, "inward normal at {p}");
            let axis = n.iamax();
            per_face[2 * axis + usize::from(n[axis] > 0.0)] += 1;
        }
        // Equal areas get equal shares (binomial sd ≈ 20 for 500 expected).
        for count in per_face {
            assert!((count as i64 - 500).abs() < 100, "{per_face:?}");
        }
    }

    #[test]
    fn stl_binary_and_ascii_agree() {
        let mesh = parse_obj(CUBE_OBJ, "cube.obj").expect("parse");
        let mut binary = vec![0u8; 80];
        binary.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
        let mut ascii = String::from("solid cube\n");
        for t in 0..mesh.triangles.len() {
            binary.extend_from_slice(&[0u8; 12]);
            ascii.push_str("facet normal 0 0 0\nouter loop\n");
            for c in mesh.corners(t) {
                for v in c.iter() {
                    binary.extend_from_slice(&(*v as f32).to_le_bytes());
                }
                ascii.push_str(&format!("vertex {} {} {}\n", c.x, c.y, c.z));
            }
            binary.extend_from_slice(&[0u8; 2]);
            ascii.push_str("endloop\nendfacet\n");
        }
        ascii.push_str("endsolid cube\n");
        let a = parse_stl(&binary, "b.stl").expect("binary");
        let b = parse_stl(ascii.as_bytes(), "a.stl").expect("ascii");
        assert_eq!(a.triangles.len(), 12);
        assert!((a.area() - 6.0).abs() < 1e-9 && (b.area() - 6.0).abs() < 1e-9);
    }

    #[test]
    fn obj_errors_name_the_line() {
        let err = parse_obj("v 0 0 0\nf 1 2 3\n", "bad.obj")
            .unwrap_err()
            .to_string();
        assert!(err.contains("bad.obj") && err.contains("line 2"), "{err}");
    }
}
