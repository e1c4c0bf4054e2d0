//! The shape a cloud source samples (`{primitive: {shape: ...}}` in cloud and demonstration
//! files): any [`Shape`] in its own frame, in the spelling of [`crate::geometry::shape`], plus
//! the deprecated spellings of earlier cloud files, still read:
//!
//! * `{cylinder: {radius, height}}`: `height` is the cylinder's `length`;
//! * `{t_shape: {stem: [x, y, z], bar: [x, y, z]}}`: the **upright T** ([`LegacyTShape`]), a box
//!   stem standing on `z` with the bar on top, centred on its bounding box. It is not the T of
//!   [`crate::geometry::shape::TShape`] in that T's own frame (bar at the origin, stem along
//!   `+z`) but that T turned upside down and shifted ([`LegacyTShape::to_shape`]); it is sampled
//!   exactly as before, so its clouds are unchanged to the bit.

use super::sample::{sample_parts, sample_shape, Part};
use super::{CloudError, PointCloud, SampleOptions};
use crate::geometry::shape::{
    Capsule, ConvexMesh, Cuboid, Cylinder, Shape, ShapeError, Sphere, Stem, TShape, TriMesh,
};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// The upright T of earlier cloud files (`{t_shape: {stem: [x, y, z], bar: [x, y, z]}}`,
/// deprecated): a box `stem` standing on `z` with a box `bar` on top of it, both centred on the
/// `z` axis, the whole shifted so that its bounding box is centred on the origin (m).
///
/// The same solid is [`TShape`] `{bar, stem: {box: {size: stem}}}` placed upside down:
/// see [`LegacyTShape::to_shape`]. New files should write that T and place it by a pose.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "LegacyTFile", into = "LegacyTFile")]
pub struct LegacyTShape {
    stem: Cuboid,
    bar: Cuboid,
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct LegacyTFile {
    stem: [f64; 3],
    bar: [f64; 3],
}

impl TryFrom<LegacyTFile> for LegacyTShape {
    type Error = ShapeError;
    fn try_from(f: LegacyTFile) -> Result<Self, ShapeError> {
        LegacyTShape::new(f.stem, f.bar)
    }
}

impl From<LegacyTShape> for LegacyTFile {
    fn from(t: LegacyTShape) -> Self {
        LegacyTFile {
            stem: t.stem.size(),
            bar: t.bar.size(),
        }
    }
}

impl LegacyTShape {
    /// An upright T of stem and bar edge lengths (m), each positive and finite.
    pub fn new(stem: [f64; 3], bar: [f64; 3]) -> Result<Self, ShapeError> {
        let named = |what: &str, size: [f64; 3]| {
            Cuboid::new(size).map_err(|e| match e {
                ShapeError::NotPositive { field, value } => ShapeError::NotPositive {
                    field: field.replace("box.size", &format!("t_shape.{what}")),
                    value,
                },
                other => other,
            })
        };
        Ok(Self {
            stem: named("stem", stem)?,
            bar: named("bar", bar)?,
        })
    }

    /// The stem's edge lengths (m).
    pub fn stem(&self) -> [f64; 3] {
        self.stem.size()
    }

    /// The bar's edge lengths (m).
    pub fn bar(&self) -> [f64; 3] {
        self.bar.size()
    }

    /// The same solid as a [`TShape`] (bar at its origin, stem along its `+z`) and the pose
    /// `object_from_shape` that places it: half a turn about `x` (the stem now points down),
    /// then `stem_z / 2` up along `z`.
    pub fn to_shape(&self) -> (Shape, Isometry3<f64>) {
        // Both sizes were checked when `self` was built, so the T is valid.
        let t = TShape::new(self.bar.size(), Stem::Box(self.stem));
        let shape = Shape::TShape(t.expect("sizes checked on construction"));
        let object_from_shape = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, self.stem.half_extents().z),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI),
        );
        (shape, object_from_shape)
    }

    /// The two boxes in the object frame, exactly as earlier versions built them (stem first).
    fn parts(&self) -> [Part; 2] {
        let hs = self.stem.half_extents();
        let hb = self.bar.half_extents();
        let total = 2.0 * (hs.z + hb.z);
        let shift = -total / 2.0;
        [
            Part::Box {
                centre: Vector3::new(0.0, 0.0, shift + hs.z),
                half: hs,
            },
            Part::Box {
                centre: Vector3::new(0.0, 0.0, shift + 2.0 * hs.z + hb.z),
                half: hb,
            },
        ]
    }

    /// Samples the T's outer surface (object frame) as [`sample_shape`] does a shape; the
    /// points are those of earlier versions to the bit.
    pub fn sample(&self, options: &SampleOptions) -> Result<PointCloud, CloudError> {
        sample_parts(&self.parts(), options)
    }
}

/// What a cloud source samples: a [`Shape`] in its own frame or the deprecated upright T. Reads
/// every [`Shape`] spelling, plus `height` for a cylinder's `length` and the upright T's
/// `{t_shape: {stem: [x, y, z], bar: [x, y, z]}}` (deprecated).
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(try_from = "CloudShapeFile")]
pub enum CloudShape {
    /// A shape in its own frame.
    Shape(Shape),
    /// The upright T of earlier cloud files.
    LegacyT(LegacyTShape),
}

impl CloudShape {
    /// Samples the shape's surface (see [`sample_shape`]).
    pub fn sample(&self, options: &SampleOptions) -> Result<PointCloud, CloudError> {
        match self {
            CloudShape::Shape(shape) => sample_shape(shape, options),
            CloudShape::LegacyT(t) => t.sample(options),
        }
    }
}

impl From<Shape> for CloudShape {
    fn from(shape: Shape) -> Self {
        CloudShape::Shape(shape)
    }
}

impl serde::Serialize for CloudShape {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(serde::Serialize)]
        #[serde(rename_all = "snake_case")]
        enum Legacy<'a> {
            TShape(&'a LegacyTShape),
        }
        match self {
            CloudShape::Shape(shape) => shape.serialize(serializer),
            CloudShape::LegacyT(t) => Legacy::TShape(t).serialize(serializer),
        }
    }
}

/// The file form: [`Shape`]'s variants, with the cylinder and the T widened to the old
/// spellings.
#[derive(serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum CloudShapeFile {
    Box(Cuboid),
    Cylinder(CylinderFile),
    Sphere(Sphere),
    Capsule(Capsule),
    TShape(TShapeFile),
    ConvexMesh(ConvexMesh),
    TriangleMesh(TriMesh),
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CylinderFile {
    radius: f64,
    #[serde(alias = "height")]
    length: f64,
}

/// A T in either spelling: `{bar, stem: {cylinder | box}}` or the upright
/// `{stem: [x, y, z], bar}`.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TShapeFile {
    bar: [f64; 3],
    stem: serde_json::Value,
}

impl TryFrom<CloudShapeFile> for CloudShape {
    type Error = String;
    fn try_from(f: CloudShapeFile) -> Result<Self, String> {
        let shape = match f {
            CloudShapeFile::Box(b) => Shape::Box(b),
            CloudShapeFile::Cylinder(c) => {
                Shape::Cylinder(Cylinder::new(c.radius, c.length).map_err(|e| e.to_string())?)
            }
            CloudShapeFile::Sphere(s) => Shape::Sphere(s),
            CloudShapeFile::Capsule(c) => Shape::Capsule(c),
            CloudShapeFile::ConvexMesh(m) => Shape::ConvexMesh(m),
            CloudShapeFile::TriangleMesh(m) => Shape::TriangleMesh(m),
            CloudShapeFile::TShape(t) => {
                return t_shape(t).map_err(|e| e.to_string());
            }
        };
        Ok(CloudShape::Shape(shape))
    }
}

fn t_shape(t: TShapeFile) -> Result<CloudShape, ShapeError> {
    let malformed = |message: String| ShapeError::Malformed {
        field: "t_shape.stem".into(),
        message,
    };
    match t.stem {
        stem @ serde_json::Value::Array(_) => {
            let stem: [f64; 3] = serde_json::from_value(stem).map_err(|e| {
                malformed(format!(
                    "the upright T's stem [x, y, z] (m): {}",
                    crate::input::plain_serde_message(&e.to_string())
                ))
            })?;
            Ok(CloudShape::LegacyT(LegacyTShape::new(stem, t.bar)?))
        }
        stem => {
            let stem: Stem = serde_json::from_value(stem)
                .map_err(|e| malformed(crate::input::plain_serde_message(&e.to_string())))?;
            Ok(CloudShape::Shape(Shape::TShape(TShape::new(t.bar, stem)?)))
        }
    }
}
