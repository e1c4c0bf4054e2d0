//! Link collision geometry: the shapes a link carries (from URDF `<collision>` elements or a
//! built-in model's published primitives), each placed in its link frame, and the resolution
//! of mesh URIs to files.
//!
//! Mesh URIs: `package://PKG/REL` and `model://PKG/REL` are looked up, in order, under each
//! explicit search path `D` (as `D/PKG/REL` and `D/share/PKG/REL`), under each
//! `ROS_PACKAGE_PATH` entry `R` (`R/PKG/REL`, and `R/REL` when `R` is itself named `PKG`),
//! under each `AMENT_PREFIX_PATH` entry `P` (`P/share/PKG/REL`), and finally in the URDF's own
//! folder and its ancestors (an ancestor named `PKG`, as `ANCESTOR/REL`). `file:///ABS` is the
//! absolute path; a plain relative path is relative to the URDF's folder. Resolving only
//! checks that a file exists; meshes are read on request (`cloud::load_collision_mesh`), never
//! while chains are built.

use super::error::RobotError;
use crate::geometry::shape::Shape;
use nalgebra::Isometry3;
use std::path::{Path, PathBuf};

/// A collision mesh by reference: where it was found and how it is scaled.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRef {
    /// The robot file that names the mesh (for messages).
    pub source_name: String,
    /// The link that carries it.
    pub link: String,
    /// The URI as written in the robot file.
    pub uri: String,
    /// The resolved file (OBJ or STL).
    pub path: PathBuf,
    /// Scale factors along the mesh's `x, y, z` (URDF `scale`; default 1).
    pub scale: [f64; 3],
}

/// The geometry of one collision element.
#[derive(Debug, Clone, PartialEq)]
pub enum CollisionGeometry {
    /// A primitive (box, cylinder, sphere, capsule), in the collision frame.
    Shape(Shape),
    /// A mesh file, read on request.
    Mesh(MeshRef),
}

/// One collision element of a link.
#[derive(Debug, Clone, PartialEq)]
pub struct CollisionShape {
    /// The element's `name` attribute, if any.
    pub name: Option<String>,
    /// The collision frame in the link frame (URDF `<collision><origin>`), m.
    pub link_from_collision: Isometry3<f64>,
    /// The geometry, in the collision frame.
    pub geometry: CollisionGeometry,
}

/// The collision elements of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkCollisions {
    /// The link's name.
    pub link: String,
    /// Its collision elements, in file order.
    pub shapes: Vec<CollisionShape>,
}

/// Where mesh URIs are looked up (see the module documentation for the order).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshResolver {
    /// The folder of the robot file: plain relative paths start here.
    pub base_dir: PathBuf,
    /// Explicit search paths, tried first.
    pub search_paths: Vec<PathBuf>,
    /// `ROS_PACKAGE_PATH` entries.
    pub ros_package_path: Vec<PathBuf>,
    /// `AMENT_PREFIX_PATH` entries.
    pub ament_prefix_path: Vec<PathBuf>,
}

impl MeshResolver {
    /// A resolver for a robot file in `base_dir`, with explicit `search_paths` and the
    /// `ROS_PACKAGE_PATH` and `AMENT_PREFIX_PATH` of the environment.
    pub fn from_env(base_dir: &Path, search_paths: Vec<PathBuf>) -> Self {
        let list = |var: &str| {
            std::env::var_os(var)
                .map(|v| {
                    std::env::split_paths(&v)
                        .filter(|p| !p.as_os_str().is_empty())
                        .collect()
                })
                .unwrap_or_default()
        };
        Self {
            base_dir: base_dir.to_path_buf(),
            search_paths,
            ros_package_path: list("ROS_PACKAGE_PATH"),
            ament_prefix_path: list("AMENT_PREFIX_PATH"),
        }
    }

    /// The files a URI may name, in the order they are tried; `None` for an unsupported
    /// scheme (`http://`, ...). A package URI that would leave its package (a `..`
    /// component, or a package name that is not one folder) names no file.
    pub fn candidates(&self, uri: &str) -> Option<Vec<PathBuf>> {
        if let Some((package, relative)) = package_uri(uri) {
            let mut out = Vec::new();
            if leaves_package(package, relative) {
                return Some(out);
            }
            for d in &self.search_paths {
                out.push(d.join(package).join(relative));
                out.push(d.join("share").join(package).join(relative));
            }
            for r in &self.ros_package_path {
                out.push(r.join(package).join(relative));
                if r.file_name().is_some_and(|n| n == package) {
                    out.push(r.join(relative));
                }
            }
            for p in &self.ament_prefix_path {
                out.push(p.join("share").join(package).join(relative));
            }
            for ancestor in self.base_dir.ancestors() {
                if ancestor.file_name().is_some_and(|n| n == package) {
                    out.push(ancestor.join(relative));
                }
            }
            return Some(out);
        }
        if let Some(path) = uri.strip_prefix("file://") {
            return Some(vec![PathBuf::from(path)]);
        }
        if uri.contains("://") {
            return None;
        }
        Some(vec![self.base_dir.join(uri)])
    }

    /// The first existing file a URI names, for link `link` of robot file `source_name`.
    pub fn resolve(&self, uri: &str, source_name: &str, link: &str) -> Result<PathBuf, RobotError> {
        if let Some((package, relative)) = package_uri(uri) {
            if leaves_package(package, relative) {
                return Err(RobotError::MeshOutsidePackage {
                    source_name: source_name.to_string(),
                    link: link.to_string(),
                    uri: uri.to_string(),
                });
            }
        }
        let candidates = self.candidates(uri).ok_or_else(|| RobotError::MeshScheme {
            source_name: source_name.to_string(),
            link: link.to_string(),
            uri: uri.to_string(),
        })?;
        match candidates.iter().find(|p| p.is_file()) {
            Some(path) => Ok(path.clone()),
            None => Err(RobotError::MeshNotFound {
                source_name: source_name.to_string(),
                link: link.to_string(),
                uri: uri.to_string(),
                tried: candidates,
            }),
        }
    }
}

/// The package and the path inside it of a `package://` or `model://` URI.
fn package_uri(uri: &str) -> Option<(&str, &str)> {
    let rest = uri
        .strip_prefix("package://")
        .or_else(|| uri.strip_prefix("model://"))?;
    Some(rest.split_once('/').unwrap_or((rest, "")))
}

/// Whether `package://package/relative` would name a file outside the package's folder.
fn leaves_package(package: &str, relative: &str) -> bool {
    let not_a_folder_name = package.is_empty() || package == "." || package == "..";
    not_a_folder_name
        || Path::new(relative).components().any(|c| {
            !matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        })
}
