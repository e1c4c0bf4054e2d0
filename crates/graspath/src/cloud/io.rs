//! Reading and writing clouds by file extension, and cloud sources described in JSON (a file,
//! a mesh to sample, or a primitive to sample).

use super::{
    mesh::read_mesh, pcd, ply, CloudError, CloudReport, CloudShape, OutlierOptions, PointCloud,
    SampleOptions,
};
use std::path::{Path, PathBuf};

/// A point cloud file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CloudFormat {
    /// Stanford PLY.
    Ply,
    /// PCL's PCD.
    Pcd,
}

impl CloudFormat {
    /// The format named by a path's extension (`.ply` or `.pcd`, any case).
    pub fn from_path(path: &Path) -> Result<Self, CloudError> {
        match path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .as_deref()
        {
            Some("ply") => Ok(Self::Ply),
            Some("pcd") => Ok(Self::Pcd),
            _ => Err(CloudError::UnknownFormat {
                source_name: path.display().to_string(),
                expected: "ply or .pcd".into(),
            }),
        }
    }
}

/// Reads a `.ply` or `.pcd` cloud (NaN points dropped; an error if none is left).
pub fn read_cloud(path: &Path) -> Result<PointCloud, CloudError> {
    read_cloud_counted(path).map(|(cloud, _)| cloud)
}

/// [`read_cloud`], also returning how many points were skipped for a NaN or infinite
/// coordinate.
fn read_cloud_counted(path: &Path) -> Result<(PointCloud, usize), CloudError> {
    let format = CloudFormat::from_path(path)?;
    let name = path.display().to_string();
    let bytes = crate::input::read(path, crate::input::MAX_CLOUD_FILE_BYTES)
        .map_err(|e| CloudError::io(&name, e))?;
    match format {
        CloudFormat::Ply => ply::read_ply_counted(&bytes, &name),
        CloudFormat::Pcd => pcd::read_pcd_counted(&bytes, &name),
    }
}

/// Writes a cloud as binary little-endian PLY or binary PCD, by extension, atomically.
pub fn write_cloud(path: &Path, cloud: &PointCloud) -> Result<(), CloudError> {
    match CloudFormat::from_path(path)? {
        CloudFormat::Ply => ply::write_ply(path, cloud, ply::PlyEncoding::BinaryLittleEndian),
        CloudFormat::Pcd => pcd::write_pcd(path, cloud, pcd::PcdEncoding::Binary),
    }
}

/// Where a cloud comes from, as written in demonstration and cloud-spec JSON files.
///
/// Paths are relative to the JSON file that names them.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum CloudSource {
    /// A `.ply` or `.pcd` file.
    File(PathBuf),
    /// A `.obj` or `.stl` mesh (metres) sampled area-weighted.
    Mesh {
        /// The mesh file.
        path: PathBuf,
        /// Sampling options.
        #[serde(flatten)]
        sampling: SampleOptions,
    },
    /// A shape in its own frame (the object frame), sampled on its surface:
    /// `{primitive: {shape: {cylinder: {radius, length}}, points, seed, ...}}` with any
    /// [`crate::geometry::shape::Shape`] spelling (old spellings read: see [`CloudShape`]).
    Primitive {
        /// The shape.
        shape: CloudShape,
        /// Sampling options.
        #[serde(flatten)]
        sampling: SampleOptions,
    },
}

impl CloudSource {
    /// Loads or samples the cloud; relative paths are taken from `base_dir`.
    pub fn load(&self, base_dir: &Path) -> Result<PointCloud, CloudError> {
        match self {
            Self::File(path) => read_cloud(&base_dir.join(path)),
            Self::Mesh { path, sampling } => {
                let path = base_dir.join(path);
                read_mesh(&path)?.sample(sampling, &path.display().to_string())
            }
            Self::Primitive { shape, sampling } => shape.sample(sampling),
        }
    }

    /// A short description for messages.
    pub fn describe(&self, base_dir: &Path) -> String {
        match self {
            Self::File(path) => base_dir.join(path).display().to_string(),
            Self::Mesh { path, .. } => format!("mesh {}", base_dir.join(path).display()),
            Self::Primitive { shape, .. } => match shape {
                CloudShape::Shape(s) => format!("primitive {}", s.kind()),
                CloudShape::LegacyT(_) => "primitive t_shape (upright)".into(),
            },
        }
    }
}

/// Loads a cloud named on the command line: a `.ply`/`.pcd` file, or a `.json` file holding a
/// [`CloudSource`] (paths in it relative to the JSON file). Errors in the JSON's options name
/// the JSON file and the option.
pub fn load_cloud_argument(path: &Path) -> Result<PointCloud, CloudError> {
    load_counted(path).map(|(cloud, _)| cloud)
}

fn load_counted(path: &Path) -> Result<(PointCloud, usize), CloudError> {
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if !is_json {
        return read_cloud_counted(path);
    }
    let name = path.display().to_string();
    let text = crate::input::read_to_string(path, crate::input::MAX_CLOUD_FILE_BYTES)
        .map_err(|e| CloudError::io(&name, e))?;
    let source: CloudSource = serde_json::from_str(&text).map_err(|e| {
        CloudError::parse(
            &name,
            format!("line {}", e.line()),
            crate::input::plain_serde_message(&e.to_string()),
        )
    })?;
    let cloud = source
        .load(path.parent().unwrap_or(Path::new(".")))
        .map_err(|e| e.in_file(&name, ""))?;
    Ok((cloud, 0))
}

/// [`load_cloud_argument`] followed by outlier removal ([`OutlierOptions::apply`]): the cloud
/// and the counts of what was skipped (NaN or infinite points) and removed. The options are
/// checked before the file is read.
pub fn load_cloud_filtered(
    path: &Path,
    options: &OutlierOptions,
) -> Result<(PointCloud, CloudReport), CloudError> {
    options.check()?;
    let (cloud, invalid) = load_counted(path)?;
    let mut report = CloudReport {
        read: cloud.len() + invalid,
        invalid,
        ..CloudReport::default()
    };
    let cloud = options.apply(cloud, &mut report, &path.display().to_string())?;
    Ok((cloud, report))
}
