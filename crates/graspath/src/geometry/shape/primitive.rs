//! The primitive solids: box, cylinder, sphere, capsule and T-shape, with closed-form signed
//! distances and support points. Each checks its sizes when built or read from a file.

use super::{positive, Proximity, ShapeError};
use nalgebra::{Point3, Vector2, Vector3};

/// `+h` for a non-negative direction component, `−h` otherwise.
#[inline]
fn signed(h: f64, d: f64) -> f64 {
    if d >= 0.0 {
        h
    } else {
        -h
    }
}

/// The signed distance of `p` to a box of half edge lengths `half` centred on the origin.
#[inline]
fn box_distance(p: &Vector3<f64>, half: &Vector3<f64>) -> f64 {
    let q = p.abs() - half;
    q.sup(&Vector3::zeros()).norm() + q.max().min(0.0)
}

/// The signed distance of `p` to a capped cylinder along `z`, centred on the origin.
#[inline]
fn cylinder_distance(p: &Vector3<f64>, radius: f64, half_length: f64) -> f64 {
    let radial = p.x.hypot(p.y) - radius;
    let axial = p.z.abs() - half_length;
    Vector2::new(radial.max(0.0), axial.max(0.0)).norm() + radial.max(axial).min(0.0)
}

/// A box centred on the origin with edge lengths `size` along `x, y, z` (m).
/// File: `{box: {size: [x, y, z]}}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "CuboidFile", into = "CuboidFile")]
pub struct Cuboid {
    half: Vector3<f64>,
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CuboidFile {
    size: [f64; 3],
}

impl TryFrom<CuboidFile> for Cuboid {
    type Error = ShapeError;
    fn try_from(f: CuboidFile) -> Result<Self, ShapeError> {
        Cuboid::new(f.size)
    }
}

impl From<Cuboid> for CuboidFile {
    fn from(c: Cuboid) -> Self {
        CuboidFile { size: c.size() }
    }
}

impl Cuboid {
    /// A box of edge lengths `size` (m), each positive and finite.
    pub fn new(size: [f64; 3]) -> Result<Self, ShapeError> {
        for (k, &v) in size.iter().enumerate() {
            positive(|| format!("box.size[{k}]"), v)?;
        }
        Ok(Self {
            half: Vector3::from(size) / 2.0,
        })
    }

    /// Edge lengths along `x, y, z` (m).
    pub fn size(&self) -> [f64; 3] {
        (self.half * 2.0).into()
    }

    /// Half edge lengths along `x, y, z` (m).
    pub fn half_extents(&self) -> Vector3<f64> {
        self.half
    }

    /// Signed distance (m) from `p` (box frame); negative inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        box_distance(&p.coords, &self.half)
    }

    /// Signed distance and closest surface point of `p` (box frame). Inside, the closest
    /// point is on the nearest face.
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let half = &self.half;
        let q = p.coords.abs() - half;
        if q.max() > 0.0 {
            let closest = Point3::from(p.coords.zip_map(half, |c, h| c.clamp(-h, h)));
            // |p − clamp(p)| has the components max(q, 0) up to sign: the same bits as
            // `box_distance`.
            Proximity {
                signed_distance: (p - closest).norm(),
                closest,
            }
        } else {
            let axis = q.imax();
            let mut closest = *p;
            closest[axis] = half[axis].copysign(p[axis]);
            Proximity {
                signed_distance: q[axis],
                closest,
            }
        }
    }

    /// The corner farthest along `d` (box frame).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        Point3::new(
            signed(self.half.x, d.x),
            signed(self.half.y, d.y),
            signed(self.half.z, d.z),
        )
    }
}

/// A capped cylinder along `z`, centred on the origin: `radius` and `length` (m).
/// File: `{cylinder: {radius, length}}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "CylinderFile", into = "CylinderFile")]
pub struct Cylinder {
    radius: f64,
    half_length: f64,
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CylinderFile {
    radius: f64,
    length: f64,
}

impl TryFrom<CylinderFile> for Cylinder {
    type Error = ShapeError;
    fn try_from(f: CylinderFile) -> Result<Self, ShapeError> {
        Cylinder::new(f.radius, f.length)
    }
}

impl From<Cylinder> for CylinderFile {
    fn from(c: Cylinder) -> Self {
        CylinderFile {
            radius: c.radius,
            length: c.length(),
        }
    }
}

impl Cylinder {
    /// A cylinder of `radius` and `length` along `z` (m), both positive and finite.
    pub fn new(radius: f64, length: f64) -> Result<Self, ShapeError> {
        Self::named(radius, length, "cylinder")
    }

    fn named(radius: f64, length: f64, prefix: &str) -> Result<Self, ShapeError> {
        positive(|| format!("{prefix}.radius"), radius)?;
        positive(|| format!("{prefix}.length"), length)?;
        Ok(Self {
            radius,
            half_length: length / 2.0,
        })
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Length along `z` (m).
    pub fn length(&self) -> f64 {
        2.0 * self.half_length
    }

    /// Signed distance (m) from `p` (cylinder frame); negative inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        cylinder_distance(&p.coords, self.radius, self.half_length)
    }

    /// Signed distance and closest surface point of `p` (cylinder frame). Inside, the closest
    /// point is on the side or on a cap, whichever is nearer; on the axis the side point is
    /// taken along `+x`.
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let (radius, half_length) = (self.radius, self.half_length);
        let radial = Vector2::new(p.x, p.y);
        let r = radial.norm();
        let dir = if r > 1e-15 { radial / r } else { Vector2::x() };
        let dr = r - radius;
        let dz = p.z.abs() - half_length;
        let closest = if dr <= 0.0 && dz <= 0.0 {
            if dr > dz {
                let c = dir * radius;
                Point3::new(c.x, c.y, p.z)
            } else {
                Point3::new(p.x, p.y, half_length.copysign(p.z))
            }
        } else {
            let cr = r.min(radius);
            Point3::new(dir.x * cr, dir.y * cr, p.z.clamp(-half_length, half_length))
        };
        Proximity {
            signed_distance: self.signed_distance(p),
            closest,
        }
    }

    /// A point of the rim farthest along `d` (cylinder frame).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        let radial = d.x.hypot(d.y);
        let (x, y) = if radial > 0.0 {
            (self.radius * d.x / radial, self.radius * d.y / radial)
        } else {
            (self.radius, 0.0)
        };
        Point3::new(x, y, signed(self.half_length, d.z))
    }
}

/// A sphere of `radius` (m) about the origin. File: `{sphere: {radius}}`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "SphereFile", into = "SphereFile")]
pub struct Sphere {
    radius: f64,
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereFile {
    radius: f64,
}

impl TryFrom<SphereFile> for Sphere {
    type Error = ShapeError;
    fn try_from(f: SphereFile) -> Result<Self, ShapeError> {
        Sphere::new(f.radius)
    }
}

impl From<Sphere> for SphereFile {
    fn from(s: Sphere) -> Self {
        SphereFile { radius: s.radius }
    }
}

impl Sphere {
    /// A sphere of `radius` (m), positive and finite.
    pub fn new(radius: f64) -> Result<Self, ShapeError> {
        Ok(Self {
            radius: positive(|| "sphere.radius".into(), radius)?,
        })
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// Signed distance (m) from `p` (sphere frame); negative inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        p.coords.norm() - self.radius
    }

    /// Signed distance and closest surface point of `p` (sphere frame; the `+z` pole for the
    /// centre).
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let r = p.coords.norm();
        let dir = if r > 1e-15 {
            p.coords / r
        } else {
            Vector3::z()
        };
        Proximity {
            signed_distance: r - self.radius,
            closest: Point3::from(dir * self.radius),
        }
    }

    /// The surface point along `d` (the `+z` pole for a zero direction).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        Point3::from(unit_or_z(d) * self.radius)
    }
}

fn unit_or_z(d: &Vector3<f64>) -> Vector3<f64> {
    let n = d.norm();
    if n > 0.0 && n.is_finite() {
        d / n
    } else {
        Vector3::z()
    }
}

/// A capsule: every point within `radius` of the segment from `(0, 0, −length/2)` to
/// `(0, 0, length/2)` (m). File: `{capsule: {radius, length}}` (`length` is the segment's,
/// without the caps; URDF 1.2's `<capsule>` uses the same convention).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "CapsuleFile", into = "CapsuleFile")]
pub struct Capsule {
    radius: f64,
    half_length: f64,
}

#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CapsuleFile {
    radius: f64,
    length: f64,
}

impl TryFrom<CapsuleFile> for Capsule {
    type Error = ShapeError;
    fn try_from(f: CapsuleFile) -> Result<Self, ShapeError> {
        Capsule::new(f.radius, f.length)
    }
}

impl From<Capsule> for CapsuleFile {
    fn from(c: Capsule) -> Self {
        CapsuleFile {
            radius: c.radius,
            length: c.length(),
        }
    }
}

impl Capsule {
    /// A capsule of `radius` (positive) about a segment of `length` (m, zero allowed: a
    /// sphere) along `z`.
    pub fn new(radius: f64, length: f64) -> Result<Self, ShapeError> {
        positive(|| "capsule.radius".into(), radius)?;
        if !(length.is_finite() && length >= 0.0) {
            return Err(ShapeError::NotPositive {
                field: "capsule.length".into(),
                value: length,
            });
        }
        Ok(Self {
            radius,
            half_length: length / 2.0,
        })
    }

    /// Radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The segment's length along `z` (m), without the caps.
    pub fn length(&self) -> f64 {
        2.0 * self.half_length
    }

    /// Signed distance (m) from `p` (capsule frame); negative inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        let axis = Vector3::new(0.0, 0.0, p.z.clamp(-self.half_length, self.half_length));
        (p.coords - axis).norm() - self.radius
    }

    /// Signed distance and closest surface point of `p` (capsule frame; on the segment
    /// itself, the surface point along `+x`).
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let axis = Point3::new(0.0, 0.0, p.z.clamp(-self.half_length, self.half_length));
        let v = p - axis;
        let r = v.norm();
        let dir = if r > 1e-15 { v / r } else { Vector3::x() };
        Proximity {
            signed_distance: r - self.radius,
            closest: axis + dir * self.radius,
        }
    }

    /// The point of the surface farthest along `d` (capsule frame).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        Point3::new(0.0, 0.0, signed(self.half_length, d.z)) + unit_or_z(d) * self.radius
    }
}

/// The stem of a [`TShape`]: a cylinder (`{cylinder: {radius, length}}`) or a box
/// (`{box: {size: [x, y, length]}}`), its length along `z`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Stem {
    /// A round stem.
    Cylinder(Cylinder),
    /// A square stem; its `z` edge is the stem's length.
    Box(Cuboid),
}

impl Stem {
    /// The stem's length along `z` (m).
    pub fn length(&self) -> f64 {
        match self {
            Stem::Cylinder(c) => c.length(),
            Stem::Box(b) => b.size()[2],
        }
    }
}

/// A T-shaped object: a **bar** (a box of edge lengths `bar`, centred on the origin) and a
/// **stem** (a cylinder or a box, see [`Stem`]) standing on the centre of the bar's top face
/// along `+z`, from `z = bar_z/2` to `z = bar_z/2 + stem length`. The object frame is the bar's
/// centre, with `z` along the stem.
///
/// File: `{t_shape: {bar: [x, y, z], stem: {cylinder: {radius, length}}}}` or
/// `stem: {box: {size: [x, y, length]}}`.
///
/// Signed distance: outside and on the surface, the exact distance to the union; inside,
/// `min(d_bar, d_stem)`, whose sign is exact and whose depth is never larger than the true
/// depth (a point in the bar under the stem is deeper than its distance to the bar's top
/// face says).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "TShapeFile", into = "TShapeFile")]
pub struct TShape {
    bar: Cuboid,
    stem: Stem,
    /// The stem's centre on `z` (m).
    stem_centre: f64,
}

/// The file form of a T-shape: `{bar, stem}`.
#[derive(Clone, Copy, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct TShapeFile {
    bar: [f64; 3],
    stem: Stem,
}

impl TryFrom<TShapeFile> for TShape {
    type Error = ShapeError;
    fn try_from(f: TShapeFile) -> Result<Self, ShapeError> {
        TShape::new(f.bar, f.stem)
    }
}

impl From<TShape> for TShapeFile {
    fn from(t: TShape) -> Self {
        TShapeFile {
            bar: t.bar.size(),
            stem: t.stem,
        }
    }
}

impl TShape {
    /// A T-shape of bar edge lengths `bar` (m) and a stem.
    pub fn new(bar: [f64; 3], stem: Stem) -> Result<Self, ShapeError> {
        for (k, &v) in bar.iter().enumerate() {
            positive(|| format!("t_shape.bar[{k}]"), v)?;
        }
        let bar = Cuboid::new(bar)?;
        Ok(Self {
            bar,
            stem,
            stem_centre: bar.half.z + stem.length() / 2.0,
        })
    }

    /// A T-shape with a round stem of `stem_radius` and `stem_length` (m): a task file's
    /// `{bar, stem: {cylinder: {radius, length}}}`.
    pub fn with_round_stem(
        bar: [f64; 3],
        stem_radius: f64,
        stem_length: f64,
    ) -> Result<Self, ShapeError> {
        let stem = Cylinder::named(stem_radius, stem_length, "t_shape.stem.cylinder")?;
        Self::new(bar, Stem::Cylinder(stem))
    }

    /// The bar.
    pub fn bar(&self) -> &Cuboid {
        &self.bar
    }

    /// The stem (in its own frame, centred; see [`TShape::stem_centre`]).
    pub fn stem(&self) -> &Stem {
        &self.stem
    }

    /// The `z` of the stem's centre in the T's frame (m).
    pub fn stem_centre(&self) -> f64 {
        self.stem_centre
    }

    fn stem_point(&self, p: &Point3<f64>) -> Point3<f64> {
        Point3::new(p.x, p.y, p.z - self.stem_centre)
    }

    fn stem_distance(&self, p: &Point3<f64>) -> f64 {
        let q = self.stem_point(p);
        match &self.stem {
            Stem::Cylinder(c) => c.signed_distance(&q),
            Stem::Box(b) => b.signed_distance(&q),
        }
    }

    /// Signed distance (m) from `p` (T frame); see [`TShape`] for the inside.
    pub fn signed_distance(&self, p: &Point3<f64>) -> f64 {
        self.bar.signed_distance(p).min(self.stem_distance(p))
    }

    /// Signed distance and closest surface point of `p` (T frame): those of the part (bar or
    /// stem) with the smaller signed distance; see [`super::Shape::proximity`].
    pub fn proximity(&self, p: &Point3<f64>) -> Proximity {
        let bar = self.bar.proximity(p);
        let q = self.stem_point(p);
        let local = match &self.stem {
            Stem::Cylinder(c) => c.proximity(&q),
            Stem::Box(b) => b.proximity(&q),
        };
        let stem = Proximity {
            signed_distance: local.signed_distance,
            closest: Point3::new(
                local.closest.x,
                local.closest.y,
                local.closest.z + self.stem_centre,
            ),
        };
        if stem.signed_distance < bar.signed_distance {
            stem
        } else {
            bar
        }
    }

    /// The largest distance (m) of a point of the T from its origin.
    pub fn bounding_radius(&self) -> f64 {
        let top = self.stem_centre + self.stem.length() / 2.0;
        let stem = match &self.stem {
            Stem::Cylinder(c) => c.radius.hypot(top),
            Stem::Box(b) => Vector3::new(b.half.x, b.half.y, top).norm(),
        };
        self.bar.half.norm().max(stem)
    }

    /// The point farthest along `d` (T frame).
    pub fn support(&self, d: &Vector3<f64>) -> Point3<f64> {
        let a = self.bar.support(d);
        let local = match &self.stem {
            Stem::Cylinder(c) => c.support(d),
            Stem::Box(b) => b.support(d),
        };
        let b = Point3::new(local.x, local.y, local.z + self.stem_centre);
        if b.coords.dot(d) > a.coords.dot(d) {
            b
        } else {
            a
        }
    }
}
