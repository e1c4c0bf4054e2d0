//! The seed corpora: small valid inputs of each kind, written with the library's own writers
//! or kept here as text, that the mutators start from.

use super::*;

/// A small box cloud with outward normals (300 points).
pub fn small_cloud(normals: bool) -> PointCloud {
    box_cloud(300, normals)
}

/// The demonstration's box (0.05 × 0.04 × 0.14 m) sampled with `points` points.
pub(super) fn box_cloud(points: usize, normals: bool) -> PointCloud {
    let options = SampleOptions {
        points,
        seed: 2,
        ..SampleOptions::default()
    };
    let sampled = Shape::cuboid([0.05, 0.04, 0.14])
        .map_err(|e| e.to_string())
        .and_then(|shape| sample_shape(&shape, &options).map_err(|e| e.to_string()));
    let mut cloud = sampled.unwrap_or_else(|_| {
        PointCloud::from_points(vec![Point3::origin(), Point3::new(0.01, 0.0, 0.0)])
    });
    if !normals {
        cloud.normals = None;
    }
    cloud
}

pub(super) fn tiny_cloud(normals: bool) -> PointCloud {
    PointCloud {
        points: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(0.01, -0.02, 0.5),
            Point3::new(-1.5, 2.0, 1e-3),
        ],
        normals: normals.then(|| vec![Vector3::z(), Vector3::x(), Vector3::new(0.0, 0.6, 0.8)]),
    }
}

pub(super) fn ply_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for encoding in [
        PlyEncoding::Ascii,
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian,
    ] {
        for normals in [false, true] {
            seeds.extend(ply_bytes(&tiny_cloud(normals), encoding).ok());
        }
    }
    seeds.push(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n3 0 1 1\n".to_vec());
    seeds
}

pub(super) fn pcd_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for encoding in [
        PcdEncoding::Ascii,
        PcdEncoding::Binary,
        PcdEncoding::BinaryCompressed,
    ] {
        for normals in [false, true] {
            seeds.extend(pcd_bytes(&tiny_cloud(normals), encoding).ok());
        }
    }
    // An organised cloud (WIDTH × HEIGHT) with a NaN point, as depth cameras write.
    seeds.push(b"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n0 0 1 255\nnan nan nan 0\n0.1 0 1 255\n0.1 0.1 1 255\n".to_vec());
    seeds
}

pub(super) fn generate_seeds(ctx: &Ctx) -> Vec<Vec<u8>> {
    let cloud = small_cloud(true);
    let mut seeds: Vec<Vec<u8>> = pcd_seeds(ctx);
    seeds.extend(pcd_bytes(&cloud, PcdEncoding::Ascii).ok());
    seeds.extend(ply_bytes(&cloud, PlyEncoding::Ascii).ok());
    seeds.extend(ply_bytes(&cloud, PlyEncoding::BinaryLittleEndian).ok());
    seeds
}

pub(super) fn read_dir_files(dir: &Path, extension: &str) -> Vec<Vec<u8>> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == extension))
        .collect();
    paths.sort();
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

pub(super) fn urdf_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = vec![SMALL_ROBOT_URDF.into(), HAND_URDF.into()];
    seeds.extend(read_dir_files(&shared_robots_dir(), "urdf"));
    let mut rng = Rng::new(0x5eed);
    seeds.extend((0..4).map(|_| draw(&urdf_document(), &mut rng).into_bytes()));
    seeds
}

pub(super) fn task_yaml_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = read_dir_files(&examples_dir(), "yaml");
    let mut rng = Rng::new(0x7a5c);
    seeds.extend((0..4).map(|_| draw(&task_yaml(), &mut rng).into_bytes()));
    seeds
}

/// The example tasks converted to JSON with the library's own parser and serde.
pub(super) fn task_json_seeds(ctx: &Ctx) -> Vec<Vec<u8>> {
    task_yaml_seeds(ctx)
        .iter()
        .filter_map(|yaml| {
            let file = graspath::task::TaskFile::parse(
                std::str::from_utf8(yaml).ok()?,
                "seed.yaml",
                "yaml",
            )
            .ok()?;
            serde_json::to_vec_pretty(&file).ok()
        })
        .collect()
}

pub(super) fn cloud_json_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = read_dir_files(&examples_dir().join("grasp"), "json");
    // Only the cloud sources (the demonstrations are the `demo` target's seeds).
    seeds.retain(|s| !s.windows(13).any(|w| w == b"demonstration"));
    seeds.push(
        br#"{"mesh": {"path": "mesh.obj", "points": 200, "seed": 4, "noise": 0.001}}"#.to_vec(),
    );
    seeds.push(br#"{"mesh": {"path": "mesh.stl", "points": 100, "view": [2, 2, 2]}}"#.to_vec());
    seeds.push(br#"{"file": "cloud.pcd"}"#.to_vec());
    seeds.push(br#"{"file": "cloud.ply"}"#.to_vec());
    seeds.push(br#"{"primitive": {"shape": {"sphere": {"radius": 0.05}}, "points": 300, "view": [0, 0, 1]}}"#.to_vec());
    seeds
}

pub(super) fn demo_seeds(_: &Ctx) -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    if let Ok(text) = std::fs::read(examples_dir().join("grasp/demo_box.json")) {
        seeds.push(text);
    }
    seeds.push(THREE_FINGER_DEMO.into());
    // The same demonstrations with small clouds (cheaper executions reach more of training).
    let small: Vec<Vec<u8>> = seeds
        .iter()
        .map(|s| {
            String::from_utf8_lossy(s)
                .replace("\"points\": 5000", "\"points\": 1500")
                .replace("\"points\": 4000", "\"points\": 1500")
                .into_bytes()
        })
        .collect();
    seeds.extend(small);
    seeds.push(br#"{"format": "graspath-demonstration", "version": 1, "hand": "baxter_electric_gripper",
 "cloud": {"file": "cloud.pcd"},
 "waypoints": [{"object_from_wrist": [[0,1,0,0],[1,0,0,0],[0,0,-1,0.03],[0,0,0,1]], "hand_joints": [0.05]}]}"#.to_vec());
    seeds
}

pub(super) fn candidate_json_seeds() -> Vec<String> {
    vec![
        r#"{"format": "graspath-candidates", "version": 1, "frame": "object", "candidates": [
  {"id": 0, "label": "top", "object_from_wrist": [[1,0,0,0],[0,-1,0,0],[0,0,-1,0.1],[0,0,0,1]], "likelihood": 0.5, "contact": [0, 0, 0.03]},
  {"id": 1, "xyz": [0.02, 0, 0.1], "quaternion": [1, 0, 0, 0], "log_likelihood": -1.5, "contact": null, "hand_joints": [0.04]}
]}"#
        .to_string(),
        r#"[{"xyz": [0, 0, 0.12], "quaternion": [0, 1, 0, 0]}, {"xyz": [0.01, 0, 0.12], "quaternion": [0, 0.7071068, 0.7071068, 0]}]"#.to_string(),
    ]
}

pub(super) const CANDIDATES_CSV: &str = "id,label,x,y,z,qx,qy,qz,qw,likelihood,contact_x,contact_y,contact_z\n0,top,0,0,0.1,1,0,0,0,0.5,0,0,0.03\n1,side,0.05,0,0,0,0.7071068,0,0.7071068,0.25,0.03,0,0\n";
pub(super) const CANDIDATES_CSV_LIKELIHOOD: &str =
    "x,y,z,qx,qy,qz,qw,log_likelihood\n0,0,0.1,0,0,0,1,-2\n0.01,0.02,0.1,0,0,1,0,-3\n";

pub(super) const KINEMATICS_LINES: &str = "{\"q\":[0,0,0,0,0,0,0]}\n{\"q\":[0.1,-0.5,0.3,1.2,-0.4,0.8,0.2]}\n\n{\"q\":[-1.7,-2.1,-3.0,-0.05,-3.0,-1.5,-3.0]}\n";

pub(super) const IK_LINES: &str = "{\"pose\":[[0,0,1,0.7],[0,1,0,0.3],[-1,0,0,0.1],[0,0,0,1]]}\n{\"pose\":[[1,0,0,0.5],[0,-1,0,0.2],[0,0,-1,-0.1],[0,0,0,1]]}\n";

pub(super) const IK_TRAJECTORY: &str = "{\"poses\":[[[1,0,0,0.6],[0,-1,0,0.3],[0,0,-1,0.0],[0,0,0,1]],[[1,0,0,0.6],[0,-1,0,0.32],[0,0,-1,0.0],[0,0,0,1]],[[1,0,0,0.6],[0,-1,0,0.34],[0,0,-1,0.02],[0,0,0,1]]]}\n";

/// The triangles of a simple OBJ text (`v x y z` and `f i j k ...` with 1-based or negative
/// indices, polygons fanned), for the STL seeds.
pub(super) fn obj_triangles(obj: &str) -> Vec<[Point3<f64>; 3]> {
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for line in obj.lines() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => {
                let c: Vec<f64> = tokens.filter_map(|t| t.parse().ok()).collect();
                if c.len() >= 3 {
                    vertices.push(Point3::new(c[0], c[1], c[2]));
                }
            }
            Some("f") => {
                let n = vertices.len() as i64;
                let face: Vec<Point3<f64>> = tokens
                    .filter_map(|t| t.split('/').next()?.parse::<i64>().ok())
                    .filter_map(|i| {
                        vertices
                            .get(if i < 0 { n + i } else { i - 1 } as usize)
                            .copied()
                    })
                    .collect();
                for k in 1..face.len().saturating_sub(1) {
                    triangles.push([face[0], face[k], face[k + 1]]);
                }
            }
            _ => {}
        }
    }
    triangles
}

/// A binary STL (80-byte header, u32 count, 50 bytes per triangle) of an OBJ's triangles.
pub fn binary_stl(obj: &str) -> Vec<u8> {
    let triangles = obj_triangles(obj);
    let mut out = vec![0u8; 80];
    out[..11].copy_from_slice(b"graspath fz");
    out.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in &triangles {
        out.extend_from_slice(&[0u8; 12]);
        for p in t {
            for c in p.iter() {
                out.extend_from_slice(&(*c as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&[0u8; 2]);
    }
    out
}

/// An ascii STL of an OBJ's triangles.
pub fn ascii_stl(obj: &str) -> String {
    let mut out = "solid fuzz\n".to_string();
    for t in obj_triangles(obj) {
        out.push_str("  facet normal 0 0 0\n    outer loop\n");
        for p in t {
            out.push_str(&format!("      vertex {} {} {}\n", p.x, p.y, p.z));
        }
        out.push_str("    endloop\n  endfacet\n");
    }
    out.push_str("endsolid fuzz\n");
    out
}
