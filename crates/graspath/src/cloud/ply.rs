//! PLY files (ascii, binary little endian, binary big endian) through `ply-rs-bw`.
//!
//! The `vertex` element must have scalar properties `x`, `y`, `z`; `nx`, `ny`, `nz` are read
//! as normals when all three are present. Any scalar type is accepted.

use super::{finish_read, CloudError, PointCloud, MAX_CLOUD_POINTS};
use nalgebra::{Point3, Vector3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{
    Addable, DefaultElement, ElementDef, Encoding, Ply, Property, PropertyDef, PropertyType,
    ScalarType,
};
use std::path::Path;

/// How a PLY file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    /// Text, one vertex per line.
    Ascii,
    /// Binary, little-endian.
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

fn scalar(p: &Property) -> Option<f64> {
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
}

/// The byte size of a PLY scalar type name, `None` for an unknown name.
fn type_size(name: &str) -> Option<u64> {
    Some(match name {
        "char" | "uchar" | "int8" | "uint8" => 1,
        "short" | "ushort" | "int16" | "uint16" => 2,
        "int" | "uint" | "int32" | "uint32" | "float" | "float32" => 4,
        "double" | "float64" => 8,
        _ => return None,
    })
}

/// Checks every element count of the header against [`MAX_CLOUD_POINTS`] and against the
/// bytes after `end_header` (binary: count × the element's smallest size; ascii: one line
/// per element at least), before the parser allocates anything. Headers this cannot read
/// are left to the parser's own errors.
fn check_layout(bytes: &[u8], source_name: &str) -> Result<(), CloudError> {
    // A PLY file's first line is `ply`: anything else is named plainly here, not in the
    // parser's terms (an empty file read as "end of file while reading magic number").
    let first_line = bytes.split(|b| *b == b'\n').next().unwrap_or(&[]);
    if first_line.trim_ascii() != b"ply" {
        let found = if bytes.is_empty() {
            "the file is empty".to_string()
        } else {
            "its first line is not 'ply'".to_string()
        };
        return Err(CloudError::parse(
            source_name,
            "line 1",
            format!("not a PLY file: {found}"),
        ));
    }
    let mut binary = None;
    // (name, count, smallest bytes per element)
    let mut elements: Vec<(String, u64, u64)> = Vec::new();
    let mut offset = 0;
    let mut payload = None;
    for line in bytes.split(|b| *b == b'\n') {
        offset += line.len() + 1;
        let text = String::from_utf8_lossy(line);
        let mut tokens = text.split_ascii_whitespace();
        match tokens.next() {
            Some("format") => binary = Some(tokens.next() != Some("ascii")),
            Some("element") => {
                let name = tokens.next().unwrap_or("").to_string();
                let Some(count) = tokens.next().and_then(|t| t.parse::<u64>().ok()) else {
                    return Ok(());
                };
                elements.push((name, count, 0));
            }
            Some("property") => {
                let size = match tokens.next() {
                    // A list holds at least its count.
                    Some("list") => tokens.next().and_then(type_size),
                    other => other.and_then(type_size),
                };
                // A type this does not know: the parser reports it.
                let Some(size) = size else { return Ok(()) };
                if let Some(last) = elements.last_mut() {
                    last.2 += size;
                }
            }
            Some("end_header") => {
                payload = Some(bytes.get(offset..).unwrap_or(&[]));
                break;
            }
            _ => {}
        }
    }
    let (Some(payload), Some(binary)) = (payload, binary) else {
        return Ok(());
    };
    for (name, count, _) in &elements {
        if *count > MAX_CLOUD_POINTS as u64 {
            return Err(CloudError::TooLarge {
                source_name: source_name.to_string(),
                field: format!("element {name}"),
                count: *count,
                limit: MAX_CLOUD_POINTS,
            });
        }
    }
    if binary {
        let mut needed: u64 = 0;
        for (name, count, size) in &elements {
            // count ≤ MAX_CLOUD_POINTS and size ≤ 8 per property: no overflow in practice;
            // saturate anyway.
            needed = needed.saturating_add(count.saturating_mul((*size).max(1)));
            if needed > payload.len() as u64 {
                return Err(CloudError::parse(
                    source_name,
                    format!("element {name}"),
                    format!(
                        "the header announces {count} elements of at least {size} bytes, but only {} bytes of data follow the header",
                        payload.len()
                    ),
                ));
            }
        }
    } else {
        let lines = payload
            .split(|b| *b == b'\n')
            .filter(|l| !l.trim_ascii().is_empty())
            .count() as u64;
        let announced = elements.iter().fold(0u64, |n, e| n.saturating_add(e.1));
        if announced > lines {
            let (name, count, _) = elements
                .iter()
                .max_by_key(|e| e.1)
                .cloned()
                .unwrap_or_default();
            return Err(CloudError::parse(
                source_name,
                format!("element {name}"),
                format!(
                    "the header announces {announced} elements ({count} of '{name}') but only {lines} lines of data follow"
                ),
            ));
        }
    }
    Ok(())
}

/// Reads a PLY point cloud from bytes; `source_name` names it in errors. Element counts in
/// the header are checked against the data before parsing (see [`MAX_CLOUD_POINTS`]).
pub fn read_ply_bytes(bytes: &[u8], source_name: &str) -> Result<PointCloud, CloudError> {
    read_ply_counted(bytes, source_name).map(|(cloud, _)| cloud)
}

/// [`read_ply_bytes`], also returning how many points were skipped for a NaN or infinite
/// coordinate.
pub(crate) fn read_ply_counted(
    bytes: &[u8],
    source_name: &str,
) -> Result<(PointCloud, usize), CloudError> {
    check_layout(bytes, source_name)?;
    let parser = Parser::<DefaultElement>::new();
    let mut cursor = std::io::Cursor::new(bytes);
    let ply = parser.read_ply(&mut cursor).map_err(|e| {
        let location = match e.line() {
            Some(line) => format!("line {line}"),
            None => "payload".to_string(),
        };
        let message = e.to_string();
        let message = message
            .strip_prefix(&format!("Line {}: ", e.line().unwrap_or(0)))
            .unwrap_or(&message)
            .lines()
            .next()
            .unwrap_or("")
            .to_string();
        CloudError::parse(source_name, location, message)
    })?;
    let Some(def) = ply.header.elements.get("vertex") else {
        return Err(CloudError::parse(
            source_name,
            "header",
            "no 'vertex' element",
        ));
    };
    let present = def
        .properties
        .keys()
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    for field in ["x", "y", "z"] {
        if !def.properties.contains_key(field) {
            return Err(CloudError::MissingField {
                source_name: source_name.to_string(),
                field: format!("vertex.{field}"),
                present,
            });
        }
    }
    let has_normals = ["nx", "ny", "nz"]
        .iter()
        .all(|f| def.properties.contains_key(*f));
    let vertices = ply.payload.get("vertex").map(Vec::as_slice).unwrap_or(&[]);
    let mut points = Vec::with_capacity(vertices.len());
    let mut normals = Vec::with_capacity(if has_normals { vertices.len() } else { 0 });
    for (index, v) in vertices.iter().enumerate() {
        let get = |field: &str| -> Result<f64, CloudError> {
            v.get(field).and_then(scalar).ok_or_else(|| {
                CloudError::parse(
                    source_name,
                    format!("vertex {index}, field '{field}'"),
                    "not a scalar number",
                )
            })
        };
        points.push(Point3::new(get("x")?, get("y")?, get("z")?));
        if has_normals {
            normals.push(Vector3::new(get("nx")?, get("ny")?, get("nz")?));
        }
    }
    let cloud = PointCloud {
        points,
        normals: has_normals.then_some(normals),
    };
    finish_read(cloud, source_name)
}

/// Reads a PLY point cloud file.
pub fn read_ply(path: &Path) -> Result<PointCloud, CloudError> {
    let name = path.display().to_string();
    let bytes = crate::input::read(path, crate::input::MAX_CLOUD_FILE_BYTES)
        .map_err(|e| CloudError::io(&name, e))?;
    read_ply_bytes(&bytes, &name)
}

/// The bytes of a PLY file holding `cloud` (`double` properties; normals when present).
pub fn ply_bytes(cloud: &PointCloud, encoding: PlyEncoding) -> Result<Vec<u8>, CloudError> {
    let mut ply = Ply::<DefaultElement>::new();
    ply.header.encoding = match encoding {
        PlyEncoding::Ascii => Encoding::Ascii,
        PlyEncoding::BinaryLittleEndian => Encoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian => Encoding::BinaryBigEndian,
    };
    let mut element = ElementDef::new("vertex".to_string());
    let names: &[&str] = if cloud.normals.is_some() {
        &["x", "y", "z", "nx", "ny", "nz"]
    } else {
        &["x", "y", "z"]
    };
    for name in names {
        element.properties.add(PropertyDef::new(
            name.to_string(),
            PropertyType::Scalar(ScalarType::Double),
        ));
    }
    ply.header.elements.add(element);
    let mut vertices = Vec::with_capacity(cloud.len());
    for (i, p) in cloud.points.iter().enumerate() {
        let mut v = DefaultElement::new();
        v.insert("x".into(), Property::Double(p.x));
        v.insert("y".into(), Property::Double(p.y));
        v.insert("z".into(), Property::Double(p.z));
        if let Some(n) = cloud.normals.as_ref().map(|ns| ns[i]) {
            v.insert("nx".into(), Property::Double(n.x));
            v.insert("ny".into(), Property::Double(n.y));
            v.insert("nz".into(), Property::Double(n.z));
        }
        vertices.push(v);
    }
    ply.payload.insert("vertex".into(), vertices);
    let mut out = Vec::new();
    ply_rs_bw::writer::Writer::new()
        .write_ply(&mut out, &mut ply)
        .map_err(|e| CloudError::Encode {
            what: "<ply writer>",
            source: Box::new(e),
        })?;
    Ok(out)
}

/// Writes `cloud` to a PLY file (through a temporary file in the same directory, renamed at
/// the end, so no partial file is left behind).
pub fn write_ply(path: &Path, cloud: &PointCloud, encoding: PlyEncoding) -> Result<(), CloudError> {
    let bytes = ply_bytes(cloud, encoding)?;
    crate::output_files::write_file(path, &bytes, crate::output_files::Existing::Replace)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PointCloud {
        PointCloud {
            points: vec![Point3::new(0.1, -0.2, 0.3), Point3::new(1e-3, 2.5, -7.0)],
            normals: Some(vec![Vector3::x(), Vector3::new(0.0, 0.6, 0.8)]),
        }
    }

    #[test]
    fn round_trips_in_every_encoding() {
        for encoding in [
            PlyEncoding::Ascii,
            PlyEncoding::BinaryLittleEndian,
            PlyEncoding::BinaryBigEndian,
        ] {
            let bytes = ply_bytes(&sample(), encoding).expect("write");
            let back = read_ply_bytes(&bytes, "t.ply").expect("read");
            assert_eq!(back, sample(), "{encoding:?}");
        }
    }

    #[test]
    fn reads_float_ascii_without_normals() {
        let text = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 2 3\n";
        let cloud = read_ply_bytes(text.as_bytes(), "a.ply").expect("read");
        assert_eq!(cloud.len(), 2);
        assert!(cloud.normals.is_none());
        assert_eq!(cloud.points[1], Point3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn binary_nan_points_are_dropped() {
        let mut cloud = sample();
        cloud.points[0].y = f64::NAN;
        let bytes = ply_bytes(&cloud, PlyEncoding::BinaryLittleEndian).expect("write");
        let back = read_ply_bytes(&bytes, "n.ply").expect("read");
        assert_eq!(back.points, vec![sample().points[1]]);
    }

    #[test]
    fn hand_written_big_endian_float_file() {
        let mut bytes = b"ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
        for v in [1.5f32, -2.0, 0.25] {
            bytes.extend_from_slice(&v.to_be_bytes());
        }
        let cloud = read_ply_bytes(&bytes, "b.ply").expect("read");
        assert_eq!(cloud.points, vec![Point3::new(1.5, -2.0, 0.25)]);
    }

    #[test]
    fn errors_name_the_file_and_the_field_or_line() {
        let text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n";
        let err = read_ply_bytes(text.as_bytes(), "m.ply")
            .unwrap_err()
            .to_string();
        assert!(err.contains("m.ply") && err.contains("vertex.z"), "{err}");
        let text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty flaot x\nend_header\n";
        let err = read_ply_bytes(text.as_bytes(), "h.ply")
            .unwrap_err()
            .to_string();
        assert!(err.contains("h.ply") && err.contains("line 4"), "{err}");
        let text = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        let err = read_ply_bytes(text.as_bytes(), "e.ply").unwrap_err();
        assert!(matches!(err, CloudError::Empty { .. }), "{err}");
    }

    #[test]
    fn a_file_that_is_not_ply_is_named_so_not_in_the_parsers_terms() {
        for (bytes, says) in [
            (&b""[..], "not a PLY file: the file is empty"),
            (
                &b"OFF\n3 1 0\n"[..],
                "not a PLY file: its first line is not 'ply'",
            ),
        ] {
            let err = read_ply_bytes(bytes, "x.ply").unwrap_err().to_string();
            assert!(err.starts_with("x.ply") && err.contains("line 1"), "{err}");
            assert!(err.contains(says), "{err}");
            assert!(!err.contains("magic"), "{err}");
        }
        let crlf = "ply\r\nformat ascii 1.0\r\nelement vertex 1\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\nend_header\r\n1 2 3\r\n";
        assert!(
            read_ply_bytes(crlf.as_bytes(), "w.ply")
                .map_or_else(|e| !e.to_string().contains("not a PLY file"), |_| true),
            "a CRLF file's first line is 'ply'"
        );
    }
}
