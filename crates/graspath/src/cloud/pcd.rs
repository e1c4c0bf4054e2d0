//! PCD files (PCL's format; `DATA ascii`, `binary` and `binary_compressed`) through `pcd-rs`.
//!
//! `pcd-rs` 0.13 decodes `binary_compressed` itself: after the header come the compressed and
//! raw sizes (u32 each), then an LZF stream whose decompressed bytes are field-major (all `x`,
//! then all `y`, ...); the crate transposes them back to records. Fields `x y z` are required;
//! `normal_x normal_y normal_z` (PCL's names) are read as normals when all three are present.
//! Invalid (NaN) points, as in organised clouds, are dropped.

use super::{finish_read, CloudError, PointCloud, MAX_CLOUD_POINTS};
use nalgebra::{Point3, Vector3};
use pcd_rs::{
    DataKind, DynRecord, DynWriter, Field, FieldDef, PcdMeta, Schema, ValueKind, WriterInit,
};
use std::path::Path;

/// How a PCD file is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PcdEncoding {
    /// `DATA ascii`.
    Ascii,
    /// `DATA binary` (little-endian records).
    Binary,
    /// `DATA binary_compressed` (LZF, field-major).
    BinaryCompressed,
}

fn first_value(field: &Field) -> Option<f64> {
    Some(match field {
        Field::I8(v) => f64::from(*v.first()?),
        Field::I16(v) => f64::from(*v.first()?),
        Field::I32(v) => f64::from(*v.first()?),
        Field::I64(v) => *v.first()? as f64,
        Field::U8(v) => f64::from(*v.first()?),
        Field::U16(v) => f64::from(*v.first()?),
        Field::U32(v) => f64::from(*v.first()?),
        Field::U64(v) => *v.first()? as f64,
        Field::F32(v) => f64::from(*v.first()?),
        Field::F64(v) => *v.first()?,
    })
}

/// The byte size of one record, or `None` when it overflows.
fn record_bytes(meta: &PcdMeta) -> Option<u64> {
    meta.field_defs.iter().try_fold(0u64, |total, f| {
        (f.kind.byte_size() as u64)
            .checked_mul(f.count)
            .and_then(|b| total.checked_add(b))
    })
}

/// Largest ratio of decompressed to compressed bytes an LZF stream can reach: a three-byte
/// back reference expands to at most 264 bytes.
const LZF_MAX_EXPANSION: u64 = 88;

/// The most bytes a PCD payload may decode to (1 GiB): points × the record size, checked before
/// anything is decompressed or allocated (a record may hold many fields).
pub(super) const MAX_PCD_PAYLOAD_BYTES: u64 = 1 << 30;

/// Checks the header's counts against each other, against [`MAX_CLOUD_POINTS`] and against
/// the bytes that follow the header, before anything is allocated for the points.
/// `data` is everything after the `DATA` line.
fn check_layout(meta: &PcdMeta, data: &[u8], source_name: &str) -> Result<(), CloudError> {
    let fail = |location: &str, message: String| CloudError::parse(source_name, location, message);
    let points = meta.num_points;
    match meta.width.checked_mul(meta.height) {
        Some(n) if n == points => {}
        product => {
            return Err(fail(
                "WIDTH",
                format!(
                    "WIDTH × HEIGHT = {} × {} = {} but POINTS is {points}; they must agree",
                    meta.width,
                    meta.height,
                    product.map_or("more than 2^64".to_string(), |n| n.to_string()),
                ),
            ))
        }
    }
    if points > MAX_CLOUD_POINTS as u64 {
        return Err(CloudError::TooLarge {
            source_name: source_name.to_string(),
            field: "POINTS".into(),
            count: points,
            limit: MAX_CLOUD_POINTS,
        });
    }
    if points == 0 {
        // Nothing to decode, and a cloud needs points: refuse here, before the payload
        // decoder trusts a size field.
        return Err(fail("POINTS", "the cloud has no points (POINTS 0)".into()));
    }
    let record = record_bytes(meta).ok_or_else(|| {
        fail(
            "COUNT",
            "the sizes × counts of one point overflow 64 bits".into(),
        )
    })?;
    let needed = points.checked_mul(record).ok_or_else(|| {
        fail(
            "POINTS",
            format!("{points} points of {record} bytes overflow 64 bits"),
        )
    })?;
    if needed > MAX_PCD_PAYLOAD_BYTES {
        return Err(fail(
            "POINTS",
            format!(
                "{points} points of {record} bytes are {needed} bytes, more than the limit of {MAX_PCD_PAYLOAD_BYTES} bytes"
            ),
        ));
    }
    match meta.data {
        DataKind::Ascii => {
            let values = meta
                .field_defs
                .iter()
                .fold(0u64, |n, f| n.saturating_add(f.count));
            if values > data.len() as u64 {
                return Err(fail(
                    "COUNT",
                    format!(
                        "one point has {values} values but only {} bytes of data follow",
                        data.len()
                    ),
                ));
            }
            let lines = data
                .split(|b| *b == b'\n')
                .filter(|l| !l.is_empty())
                .count() as u64;
            if lines < points {
                return Err(fail(
                    "POINTS",
                    format!("the header announces {points} points but only {lines} lines of data follow"),
                ));
            }
        }
        DataKind::Binary => {
            if (data.len() as u64) < needed {
                return Err(fail(
                    "data",
                    format!(
                        "the header announces {points} points of {record} bytes ({needed} bytes) but only {} bytes follow the header",
                        data.len()
                    ),
                ));
            }
        }
        DataKind::BinaryCompressed => {
            let Some(sizes) = data.get(..8) else {
                return Err(fail(
                    "compressed data",
                    "the file ends before the compressed and uncompressed sizes (8 bytes after DATA)".into(),
                ));
            };
            let compressed =
                u64::from(u32::from_le_bytes([sizes[0], sizes[1], sizes[2], sizes[3]]));
            let uncompressed =
                u64::from(u32::from_le_bytes([sizes[4], sizes[5], sizes[6], sizes[7]]));
            let present = data.len() as u64 - 8;
            if compressed > present {
                return Err(fail(
                    "compressed size",
                    format!("the compressed size field says {compressed} bytes but only {present} bytes follow it (a truncated file?)"),
                ));
            }
            if uncompressed != needed {
                return Err(fail(
                    "uncompressed size",
                    format!(
                        "the uncompressed size field says {uncompressed} bytes but {points} points of {record} bytes need {needed}"
                    ),
                ));
            }
            if uncompressed > compressed.saturating_mul(LZF_MAX_EXPANSION) {
                return Err(fail(
                    "compressed size",
                    format!(
                        "{compressed} compressed bytes cannot hold {uncompressed} bytes (LZF expands at most {LZF_MAX_EXPANSION}×)"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Reads a PCD point cloud from bytes; `source_name` names it in errors. Counts in the
/// header are checked against the data before anything is allocated (see [`MAX_CLOUD_POINTS`]).
pub fn read_pcd_bytes(bytes: &[u8], source_name: &str) -> Result<PointCloud, CloudError> {
    read_pcd_counted(bytes, source_name).map(|(cloud, _)| cloud)
}

/// [`read_pcd_bytes`], also returning how many points were skipped for a NaN or infinite
/// coordinate (the invalid points of an organised cloud).
pub(crate) fn read_pcd_counted(
    bytes: &[u8],
    source_name: &str,
) -> Result<(PointCloud, usize), CloudError> {
    let header_error = |e: pcd_rs::Error| match e {
        pcd_rs::Error::ParseError { line, desc } => {
            CloudError::parse(source_name, format!("line {line}"), desc)
        }
        other => CloudError::parse(source_name, "header", other.to_string()),
    };
    let mut cursor = std::io::Cursor::new(bytes);
    let meta = PcdMeta::from_reader(&mut cursor).map_err(header_error)?;
    let data_offset = cursor.position() as usize;
    check_layout(&meta, &bytes[data_offset..], source_name)?;
    let data_start = bytes[..data_offset].iter().filter(|b| **b == b'\n').count();
    let reader = pcd_rs::DynReader::from_bytes(bytes).map_err(|e| match e {
        pcd_rs::Error::ParseError { line: 0, desc } => {
            CloudError::parse(source_name, "compressed data", desc)
        }
        other => header_error(other),
    })?;
    let meta = reader.meta().clone();
    let names: Vec<&str> = meta.field_defs.iter().map(|f| f.name.as_str()).collect();
    let find = |name: &str| names.iter().position(|n| *n == name);
    let mut xyz = [0usize; 3];
    for (slot, field) in xyz.iter_mut().zip(["x", "y", "z"]) {
        *slot = find(field).ok_or_else(|| CloudError::MissingField {
            source_name: source_name.to_string(),
            field: field.to_string(),
            present: names.join(", "),
        })?;
    }
    let normal_index = match (find("normal_x"), find("normal_y"), find("normal_z")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        _ => None,
    };
    let mut points = Vec::with_capacity(meta.num_points as usize);
    let mut normals = Vec::new();
    for (index, record) in reader.enumerate() {
        let location = || match meta.data {
            DataKind::Ascii => format!("line {}", data_start + index + 1),
            _ => format!("point {index}"),
        };
        let record =
            record.map_err(|e| CloudError::parse(source_name, location(), e.to_string()))?;
        let value = |i: usize| -> Result<f64, CloudError> {
            record.0.get(i).and_then(first_value).ok_or_else(|| {
                CloudError::parse(
                    source_name,
                    format!("{}, field '{}'", location(), names[i]),
                    "missing value",
                )
            })
        };
        points.push(Point3::new(value(xyz[0])?, value(xyz[1])?, value(xyz[2])?));
        if let Some([a, b, c]) = normal_index {
            normals.push(Vector3::new(value(a)?, value(b)?, value(c)?));
        }
    }
    if points.len() != meta.num_points as usize {
        return Err(CloudError::parse(
            source_name,
            "POINTS",
            format!(
                "the header announces {} points but the data holds {}",
                meta.num_points,
                points.len()
            ),
        ));
    }
    let cloud = PointCloud {
        points,
        normals: normal_index.map(|_| normals),
    };
    finish_read(cloud, source_name)
}

/// Reads a PCD point cloud file.
pub fn read_pcd(path: &Path) -> Result<PointCloud, CloudError> {
    let name = path.display().to_string();
    let bytes = crate::input::read(path, crate::input::MAX_CLOUD_FILE_BYTES)
        .map_err(|e| CloudError::io(&name, e))?;
    read_pcd_bytes(&bytes, &name)
}

/// The bytes of a PCD v0.7 file holding `cloud` as `float` fields (`x y z`, plus
/// `normal_x normal_y normal_z` when the cloud has normals), unorganised (`HEIGHT 1`).
pub fn pcd_bytes(cloud: &PointCloud, encoding: PcdEncoding) -> Result<Vec<u8>, CloudError> {
    let names: &[&str] = if cloud.normals.is_some() {
        &["x", "y", "z", "normal_x", "normal_y", "normal_z"]
    } else {
        &["x", "y", "z"]
    };
    let schema = Schema {
        fields: names
            .iter()
            .map(|n| FieldDef {
                name: n.to_string(),
                kind: ValueKind::F32,
                count: 1,
            })
            .collect(),
    };
    let fail = |e: pcd_rs::Error| CloudError::Encode {
        what: "<pcd writer>",
        source: Box::new(e),
    };
    let mut out = Vec::new();
    {
        let mut writer: DynWriter<_> = WriterInit {
            width: cloud.len() as u64,
            height: 1,
            viewpoint: Default::default(),
            data_kind: match encoding {
                PcdEncoding::Ascii => DataKind::Ascii,
                PcdEncoding::Binary => DataKind::Binary,
                PcdEncoding::BinaryCompressed => DataKind::BinaryCompressed,
            },
            schema: Some(schema),
            version: None,
        }
        .build_from_writer(std::io::Cursor::new(&mut out))
        .map_err(fail)?;
        for (i, p) in cloud.points.iter().enumerate() {
            let mut fields = vec![
                Field::F32(vec![p.x as f32]),
                Field::F32(vec![p.y as f32]),
                Field::F32(vec![p.z as f32]),
            ];
            if let Some(n) = cloud.normals.as_ref().map(|ns| ns[i]) {
                fields.push(Field::F32(vec![n.x as f32]));
                fields.push(Field::F32(vec![n.y as f32]));
                fields.push(Field::F32(vec![n.z as f32]));
            }
            writer.push(&DynRecord(fields)).map_err(fail)?;
        }
        writer.finish().map_err(fail)?;
    }
    Ok(out)
}

/// Writes `cloud` to a PCD file (through a temporary file renamed at the end).
pub fn write_pcd(path: &Path, cloud: &PointCloud, encoding: PcdEncoding) -> Result<(), CloudError> {
    let bytes = pcd_bytes(cloud, encoding)?;
    crate::output_files::write_file(path, &bytes, crate::output_files::Existing::Replace)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> PointCloud {
        PointCloud {
            points: (0..40)
                .map(|i| Point3::new(i as f64 * 0.01, 0.5, -0.25 + i as f64 * 1e-3))
                .collect(),
            normals: Some((0..40).map(|_| Vector3::new(0.0, 0.6, 0.8)).collect()),
        }
    }

    #[test]
    fn round_trips_in_every_encoding() {
        for encoding in [
            PcdEncoding::Ascii,
            PcdEncoding::Binary,
            PcdEncoding::BinaryCompressed,
        ] {
            let bytes = pcd_bytes(&sample(), encoding).expect("write");
            let back = read_pcd_bytes(&bytes, "t.pcd").expect("read");
            assert_eq!(back.len(), 40, "{encoding:?}");
            for (a, b) in back.points.iter().zip(&sample().points) {
                assert!((a - b).norm() < 1e-6, "{encoding:?}");
            }
            let normals = back.normals.expect("normals");
            assert!((normals[3] - Vector3::new(0.0, 0.6, 0.8)).norm() < 1e-6);
        }
    }

    /// A hand-built binary_compressed file: one LZF literal run holding field-major data.
    #[test]
    fn decodes_field_major_binary_compressed() {
        let xs = [1.0f32, 2.0];
        let ys = [3.0f32, 4.0];
        let zs = [5.0f32, f32::NAN];
        let mut raw = Vec::new();
        for v in xs.iter().chain(&ys).chain(&zs) {
            raw.extend_from_slice(&v.to_le_bytes());
        }
        // LZF literal run: control byte = length − 1 (< 32).
        let mut lzf = vec![(raw.len() - 1) as u8];
        lzf.extend_from_slice(&raw);
        let mut bytes = b"# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary_compressed\n".to_vec();
        bytes.extend_from_slice(&(lzf.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&(raw.len() as u32).to_le_bytes());
        bytes.extend_from_slice(&lzf);
        let cloud = read_pcd_bytes(&bytes, "c.pcd").expect("read");
        // The second point has a NaN z and is dropped.
        assert_eq!(cloud.points, vec![Point3::new(1.0, 3.0, 5.0)]);
    }

    #[test]
    fn errors_name_the_file_and_line_or_field() {
        let text = "VERSION 0.7\nFIELDS x y\nSIZE 4 4\nTYPE F F\nCOUNT 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2\n";
        let err = read_pcd_bytes(text.as_bytes(), "f.pcd")
            .unwrap_err()
            .to_string();
        assert!(err.contains("f.pcd") && err.contains("'z'"), "{err}");
        let text = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n1 2\n";
        let err = read_pcd_bytes(text.as_bytes(), "g.pcd")
            .unwrap_err()
            .to_string();
        assert!(err.contains("g.pcd") && err.contains("line 11"), "{err}");
        let text = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\nnan nan nan\nnan 0 0\n";
        let err = read_pcd_bytes(text.as_bytes(), "n.pcd").unwrap_err();
        assert!(
            matches!(err, CloudError::AllInvalid { count: 2, .. }),
            "{err}"
        );
    }
}
