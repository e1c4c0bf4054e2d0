//! ACRONYM grasp files (HDF5): `grasps/transforms` (N×4×4) and
//! `grasps/qualities/flex/object_in_gripper` (N), read with the pure-Rust `hdf5-reader`.
//! A dataset's declared size is checked against the file length before it is read.

use super::array::{shape_text, Array};
use super::arrays::DEFLATE_MAX_RATIO;
use hdf5_reader::{Datatype, Hdf5File, OpenOptions};

/// The HDF5 signature at the start of a file.
pub(crate) const SIGNATURE: &[u8] = b"\x89HDF\r\n\x1a\n";

/// What a reader is told about each dataset before its values are read: its name and declared
/// shape; an error is `(dataset, message)`.
pub(crate) type DatasetCheck<'a> = &'a dyn Fn(&str, &[u64]) -> Result<(), (String, String)>;

/// Reads the named numeric datasets of an HDF5 image; errors are `(dataset, message)`. Each
/// dataset's declared shape is checked, before its values are read, against what the file can
/// hold and by `check` (e.g. a grasp count against a limit).
pub(crate) fn read_datasets(
    bytes: Vec<u8>,
    names: &[&str],
    check: DatasetCheck<'_>,
) -> Result<Vec<Option<Array>>, (String, String)> {
    let file_len = bytes.len() as u64;
    // No dataset can hold more than the file's bytes expanded by deflate's largest ratio.
    let limit = file_len
        .saturating_mul(DEFLATE_MAX_RATIO)
        .min(super::MAX_ARRAY_BYTES);
    let options = OpenOptions::default()
        .with_max_read_bytes(limit as usize)
        .with_max_chunk_bytes((limit as usize).min(256 << 20));
    let file = Hdf5File::from_vec_with_options(bytes, options)
        .map_err(|e| ("file".to_string(), format!("not a readable HDF5 file: {e}")))?;
    names
        .iter()
        .map(|&name| {
            let err = |m: String| (name.to_string(), m);
            let dataset = match file.dataset(name) {
                Ok(dataset) => dataset,
                Err(e) if is_not_found(&e) => return Ok(None),
                // Present but not readable (a damaged object header): say why, rather than
                // calling it missing. (The reader leaves out links it cannot follow, external
                // or dangling: those read as absent.)
                Err(e) => return Err(err(format!("cannot be opened: {}", innermost(&e)))),
            };
            let shape: Vec<usize> = dataset
                .shape()
                .iter()
                .map(|&d| {
                    usize::try_from(d).map_err(|_| err(format!("dimension {d} is too large")))
                })
                .collect::<Result<_, _>>()?;
            let size = match dataset.dtype() {
                Datatype::FloatingPoint { size, .. } => *size as u64,
                Datatype::FixedPoint { size, .. } => *size as u64,
                other => return Err(err(format!("holds {other:?}, not numbers"))),
            };
            shape
                .iter()
                .try_fold(size, |n, &d| n.checked_mul(d as u64))
                .filter(|&n| n <= limit)
                .map(|_| ())
                .ok_or_else(|| {
                    err(format!(
                        "declares shape {} ({size}-byte values), more than a {file_len}-byte \
                         file can hold",
                        shape_text(&shape)
                    ))
                })?;
            let dims: Vec<u64> = shape.iter().map(|&d| d as u64).collect();
            check(name, &dims)?;
            let read_err = |e: hdf5_reader::error::Error| err(format!("cannot be read: {e}"));
            let data: Vec<f64> = match dataset.dtype() {
                Datatype::FloatingPoint { size: 8, .. } => dataset
                    .read_array::<f64>()
                    .map_err(read_err)?
                    .into_iter()
                    .collect(),
                Datatype::FloatingPoint { size: 4, .. } => dataset
                    .read_array::<f32>()
                    .map_err(read_err)?
                    .into_iter()
                    .map(f64::from)
                    .collect(),
                Datatype::FixedPoint {
                    size: 8,
                    signed: true,
                    ..
                } => dataset
                    .read_array::<i64>()
                    .map_err(read_err)?
                    .into_iter()
                    .map(|v| v as f64)
                    .collect(),
                Datatype::FixedPoint {
                    size: 4,
                    signed: true,
                    ..
                } => dataset
                    .read_array::<i32>()
                    .map_err(read_err)?
                    .into_iter()
                    .map(f64::from)
                    .collect(),
                Datatype::FixedPoint {
                    size: 1,
                    signed: false,
                    ..
                } => dataset
                    .read_array::<u8>()
                    .map_err(read_err)?
                    .into_iter()
                    .map(f64::from)
                    .collect(),
                Datatype::FixedPoint {
                    size: 1,
                    signed: true,
                    ..
                } => dataset
                    .read_array::<i8>()
                    .map_err(read_err)?
                    .into_iter()
                    .map(f64::from)
                    .collect(),
                other => return Err(err(format!("holds {other:?}, not f32/f64/int numbers"))),
            };
            if shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d)) != Some(data.len()) {
                return Err(err(format!(
                    "declares shape {} but holds {} values",
                    shape_text(&shape),
                    data.len()
                )));
            }
            Ok(Some(Array { shape, data }))
        })
        .collect()
}

/// Whether `error` says the object is not in the file (as opposed to present but unreadable).
fn is_not_found(error: &hdf5_reader::error::Error) -> bool {
    use hdf5_reader::error::Error;
    match error {
        Error::DatasetNotFound(_) | Error::GroupNotFound(_) => true,
        Error::Context { source, .. } => is_not_found(source),
        _ => false,
    }
}

/// The error under the reader's path context (the message names the dataset already).
fn innermost(error: &hdf5_reader::error::Error) -> &hdf5_reader::error::Error {
    match error {
        hdf5_reader::error::Error::Context { source, .. } => innermost(source),
        other => other,
    }
}
