//! NumPy arrays from `.npy` files and `.npz` archives, read with bounded memory: a header's
//! shape is checked against the bytes that follow it before anything is allocated, and an
//! archive member is read through a limit (deflate cannot expand more than 1032:1).

use super::array::{fortran_to_c, shape_text, Array};
use super::pickle;
use npyz::{DType, NpyFile, Order, TypeChar};
use std::io::Read;

/// One array of a `.npy` file or `.npz` member: numbers, or a pickled Python object (what
/// `np.savez` writes for a dictionary, as Contact-GraspNet's per-segment results).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Member {
    /// A numeric array.
    Numeric(Array),
    /// A pickled object: its decoded value.
    Object(pickle::Value),
}

/// The largest expansion of deflate-compressed data (zlib's documented bound).
pub(crate) const DEFLATE_MAX_RATIO: u64 = 1032;

/// Reads a `.npy` image.
pub(crate) fn parse_npy(bytes: &[u8]) -> Result<Member, String> {
    let file = NpyFile::new(bytes).map_err(|e| format!("not a NumPy .npy array: {e}"))?;
    let shape: Vec<usize> = file
        .shape()
        .iter()
        .map(|&d| usize::try_from(d).map_err(|_| format!("dimension {d} is too large")))
        .collect::<Result<_, _>>()?;
    let dtype = file.dtype();
    let DType::Plain(type_str) = &dtype else {
        return Err(format!(
            "structured dtype {} is not read (expected an array of numbers)",
            dtype.descr()
        ));
    };
    let order = file.order();
    if type_str.type_char() == TypeChar::Object {
        let mut rest = Vec::new();
        file.into_inner()
            .read_to_end(&mut rest)
            .map_err(|e| format!("cannot read: {e}"))?;
        return pickle::parse(&rest).map(Member::Object);
    }
    let size = type_str.num_bytes().unwrap_or(0);
    let count = shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or_else(|| format!("shape {} is too large", shape_text(&shape)))?;
    let needed = count.checked_mul(size.max(1));
    let header_len = bytes.len() - remaining_after_header(bytes)?;
    let available = bytes.len() - header_len;
    if needed.is_none_or(|n| n > available) {
        return Err(format!(
            "the header declares shape {} of {} but only {available} bytes of data follow",
            shape_text(&shape),
            type_str
        ));
    }
    let values = numeric_values(file, type_str.type_char(), size, &type_str.to_string())?;
    let data = match order {
        Order::C => values,
        Order::Fortran => fortran_to_c(&shape, &values),
    };
    Ok(Member::Numeric(Array { shape, data }))
}

/// How many bytes follow the `.npy` header.
fn remaining_after_header(bytes: &[u8]) -> Result<usize, String> {
    let mut reader = bytes;
    npyz::NpyHeader::from_reader(&mut reader)
        .map_err(|e| format!("not a NumPy .npy array: {e}"))?;
    Ok(reader.len())
}

fn numeric_values(
    file: NpyFile<&[u8]>,
    kind: TypeChar,
    size: usize,
    descr: &str,
) -> Result<Vec<f64>, String> {
    let short = |e: std::io::Error| format!("the data ends early or is unreadable: {e}");
    // Whole numbers are converted exactly up to 2^53; larger ones are not grasp data.
    Ok(match (kind, size) {
        (TypeChar::Float, 8) => file.into_vec::<f64>().map_err(short)?,
        (TypeChar::Float, 4) => file
            .into_vec::<f32>()
            .map_err(short)?
            .into_iter()
            .map(f64::from)
            .collect(),
        (TypeChar::Int, 8) => ints(file.into_vec::<i64>().map_err(short)?),
        (TypeChar::Int, 4) => ints(file.into_vec::<i32>().map_err(short)?),
        (TypeChar::Int, 2) => ints(file.into_vec::<i16>().map_err(short)?),
        (TypeChar::Int, 1) => ints(file.into_vec::<i8>().map_err(short)?),
        (TypeChar::Uint, 8) => ints(file.into_vec::<u64>().map_err(short)?),
        (TypeChar::Uint, 4) => ints(file.into_vec::<u32>().map_err(short)?),
        (TypeChar::Uint, 2) => ints(file.into_vec::<u16>().map_err(short)?),
        (TypeChar::Uint, 1) => ints(file.into_vec::<u8>().map_err(short)?),
        (TypeChar::Bool, 1) => file
            .into_vec::<bool>()
            .map_err(short)?
            .into_iter()
            .map(|b| if b { 1.0 } else { 0.0 })
            .collect(),
        _ => return Err(format!("dtype {descr} is not a number type this reads")),
    })
}

fn ints<T: Into<i128>>(values: Vec<T>) -> Vec<f64> {
    values.into_iter().map(|v| v.into() as f64).collect()
}

/// The members of an `.npz` archive, `(name without .npy, bytes)`, in archive order. The
/// decompressed total is at most `limit` bytes.
pub(crate) fn read_npz(bytes: &[u8], limit: u64) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not an .npz (zip) archive: {e}"))?;
    let mut members = Vec::new();
    let mut total = 0u64;
    for i in 0..archive.len() {
        let mut entry = archive
            .by_index(i)
            .map_err(|e| format!("archive member {i} is unreadable: {e}"))?;
        let name = entry
            .name()
            .map_err(|e| format!("archive member {i} has no readable name: {e}"))?
            .into_owned();
        let mut data = Vec::new();
        (&mut entry)
            .take(limit - total + 1)
            .read_to_end(&mut data)
            .map_err(|e| format!("archive member '{name}' is unreadable: {e}"))?;
        total += data.len() as u64;
        if total > limit {
            return Err(format!(
                "the archive expands to more than {limit} bytes (at member '{name}')"
            ));
        }
        let key = name.strip_suffix(".npy").unwrap_or(&name).to_string();
        members.push((key, data));
    }
    Ok(members)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_order_is_the_transpose_walk() {
        // A 2×3 matrix [[0,1,2],[3,4,5]] stored column-major is 0,3,1,4,2,5.
        let c = fortran_to_c(&[2, 3], &[0.0, 3.0, 1.0, 4.0, 2.0, 5.0]);
        assert_eq!(c, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    }
}
