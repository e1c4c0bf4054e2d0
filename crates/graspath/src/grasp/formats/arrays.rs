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

/// The longest `.npy` header read (bytes). NumPy writes a few hundred, and by default refuses
/// to load one over 10,000 (`np.load`'s `max_header_size`).
pub(crate) const MAX_NPY_HEADER_BYTES: usize = 1 << 16;

/// The deepest nesting of brackets in an `.npy` header (NumPy's deepest, a structured dtype
/// with sub-arrays, nests 4).
const MAX_HEADER_NESTING: usize = 16;

/// The `.npy` signature.
const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// Where an `.npy` image's header starts and ends, from its preamble (signature, version,
/// header length); `None` when the bytes do not hold the whole preamble yet. The declared length is checked
/// against [`MAX_NPY_HEADER_BYTES`] here, before anything is allocated for it.
fn npy_header_end(bytes: &[u8]) -> Result<Option<(usize, usize)>, String> {
    if bytes.len() < 8 {
        return Ok(None);
    }
    if !bytes.starts_with(NPY_MAGIC) {
        return Err("not a NumPy .npy array (no \\x93NUMPY signature)".into());
    }
    let prefix = match bytes[6] {
        1 => 10,
        2 | 3 => 12,
        v => {
            return Err(format!(
                "not a NumPy .npy array (unknown format version {v})"
            ))
        }
    };
    let Some(length) = bytes.get(8..prefix) else {
        return Ok(None);
    };
    let declared = length
        .iter()
        .rev()
        .fold(0usize, |n, &b| (n << 8) | usize::from(b));
    if declared > MAX_NPY_HEADER_BYTES {
        return Err(format!(
            "the .npy header declares {declared} bytes; more than {MAX_NPY_HEADER_BYTES} is \
             refused (NumPy writes a few hundred)"
        ));
    }
    Ok(Some((prefix, prefix + declared)))
}

/// The parsed header of an `.npy` image and where its data start. The header is checked before
/// npyz reads it: its length against the bytes present, its nesting, and its shape's element
/// count against overflow.
pub(crate) fn npy_header(bytes: &[u8]) -> Result<(npyz::NpyHeader, usize), String> {
    let (start, end) =
        npy_header_end(bytes)?.ok_or("not a NumPy .npy array (it ends in its preamble)")?;
    if end > bytes.len() {
        return Err(format!(
            "the .npy header declares {} bytes but only {} follow",
            end - start,
            bytes.len() - start.min(bytes.len())
        ));
    }
    let text = &bytes[start..end];
    let mut depth = 0usize;
    for &b in text {
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        if depth > MAX_HEADER_NESTING {
            return Err(format!(
                "the .npy header nests brackets more than {MAX_HEADER_NESTING} deep"
            ));
        }
    }
    if let Some(dims) = declared_shape(text) {
        if dims
            .iter()
            .try_fold(1u64, |n, &d| n.checked_mul(d))
            .is_none()
        {
            return Err(format!(
                "the .npy header declares shape {}, more elements than can be counted",
                shape_text(&dims)
            ));
        }
    }
    let mut reader = &bytes[..end];
    let header = npyz::NpyHeader::from_reader(&mut reader)
        .map_err(|e| format!("not a NumPy .npy array: {e}"))?;
    Ok((header, end))
}

/// The dimensions of the `shape` entry of an `.npy` header, read as npyz reads it (the header
/// is a Python dict literal; of a repeated key, the last), when every dimension is a whole
/// number that fits 64 bits; `None` otherwise (npyz then refuses the header itself).
fn declared_shape(text: &[u8]) -> Option<Vec<u64>> {
    let text = std::str::from_utf8(text).ok()?;
    let text = text.strip_suffix('\n').unwrap_or(text);
    let py_literal::Value::Dict(entries) = text.parse::<py_literal::Value>().ok()? else {
        return None;
    };
    let shape = entries
        .iter()
        .rev()
        .find(|(key, _)| key.as_string().is_some_and(|k| k == "shape"))?;
    let (py_literal::Value::Tuple(dims) | py_literal::Value::List(dims)) = &shape.1 else {
        return None;
    };
    dims.iter()
        .map(|d| match d {
            py_literal::Value::Integer(n) => u64::try_from(n).ok(),
            _ => None,
        })
        .collect()
}

/// Reads a `.npy` image. Its header is checked before anything is allocated for the data: the
/// header's own length ([`npy_header`]), then the declared shape against the bytes that
/// follow and against [`super::MAX_ARRAY_BYTES`] as `f64` values. Complex, long-double and
/// other non-real types are refused, never converted.
pub(crate) fn parse_npy(bytes: &[u8]) -> Result<Member, String> {
    let (header, data_start) = npy_header(bytes)?;
    let shape: Vec<usize> = header
        .shape()
        .iter()
        .map(|&d| usize::try_from(d).map_err(|_| format!("dimension {d} is too large")))
        .collect::<Result<_, _>>()?;
    let dtype = header.dtype();
    let DType::Plain(type_str) = &dtype else {
        return Err(format!(
            "structured dtype {} is not read (expected an array of numbers)",
            super::excerpt(dtype.descr().as_bytes(), 60)
        ));
    };
    let order = header.order();
    let data = &bytes[data_start..];
    if type_str.type_char() == TypeChar::Object {
        return pickle::parse(data).map(Member::Object);
    }
    let size = type_str.num_bytes().unwrap_or(0);
    let count = shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or_else(|| format!("shape {} is too large", shape_text(&shape)))?;
    let needed = count.checked_mul(size.max(1));
    let available = data.len();
    if needed.is_none_or(|n| n > available) {
        return Err(format!(
            "the header declares shape {} of {} but only {available} bytes of data follow",
            shape_text(&shape),
            type_str
        ));
    }
    if (count as u64).saturating_mul(8) > super::MAX_ARRAY_BYTES {
        return Err(format!(
            "shape {} holds {count} values, more than {} bytes as float64",
            shape_text(&shape),
            super::MAX_ARRAY_BYTES
        ));
    }
    let file = NpyFile::with_header(header, data);
    let values = numeric_values(file, type_str)?;
    let data = match order {
        Order::C => values,
        Order::Fortran => fortran_to_c(&shape, &values),
    };
    Ok(Member::Numeric(Array { shape, data }))
}

fn numeric_values(file: NpyFile<&[u8]>, type_str: &npyz::TypeStr) -> Result<Vec<f64>, String> {
    let short = |e: std::io::Error| format!("the data ends early or is unreadable: {e}");
    let kind = type_str.type_char();
    let size = type_str.num_bytes().unwrap_or(0);
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
        // The same refusals, and words, as for an array inside a pickle.
        _ => {
            let text = type_str.to_string();
            return Err(pickle::number_type(&text)
                .err()
                .unwrap_or_else(|| format!("dtype '{text}' is not a number type this reads")));
        }
    })
}

fn ints<T: Into<i128>>(values: Vec<T>) -> Vec<f64> {
    values.into_iter().map(|v| v.into() as f64).collect()
}

/// What a reader of an `.npz` is told about each member before its data are read: its name
/// (without `.npy`) and its parsed header. An error refuses the archive.
pub(crate) type MemberCheck<'a> = &'a dyn Fn(&str, &npyz::NpyHeader) -> Result<(), String>;

/// Named members of an archive: `(name without .npy, bytes)`.
pub(crate) type Members = Vec<(String, Vec<u8>)>;

/// Members of an archive by name with their declared shapes.
pub(crate) type MemberShapes = Vec<(String, Option<Vec<u64>>)>;

/// The members of an `.npz` archive that `wanted` names, `(name without .npy, bytes)`, in
/// archive order; the others are not decompressed. Each member's `.npy` header is read first
/// and its declared data checked against what the archive may still expand to and by `check`
/// (e.g. a grasp count against a limit), before the data are read. The decompressed total is
/// at most `limit` bytes.
pub(crate) fn read_npz(
    bytes: &[u8],
    limit: u64,
    wanted: &dyn Fn(&str) -> bool,
    check: MemberCheck<'_>,
) -> Result<Members, (String, String)> {
    let file = |m: String| ("file".to_string(), m);
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| file(format!("not an .npz (zip) archive: {e}")))?;
    let mut members = Vec::new();
    let mut total = 0u64;
    for i in 0..archive.len() {
        let mut entry = archive
            .by_index(i)
            .map_err(|e| file(format!("archive member {i} is unreadable: {e}")))?;
        let name = entry
            .name()
            .map_err(|e| file(format!("archive member {i} has no readable name: {e}")))?
            .into_owned();
        let key = name.strip_suffix(".npy").unwrap_or(&name).to_string();
        let shown = super::excerpt(key.as_bytes(), 60);
        if !wanted(&key) {
            continue;
        }
        let unreadable =
            |e: std::io::Error| file(format!("archive member '{shown}' is unreadable: {e}"));
        // The preamble, then the header it announces, then the data that header declares.
        let mut data = Vec::new();
        (&mut entry)
            .take(12)
            .read_to_end(&mut data)
            .map_err(unreadable)?;
        let mut declared = None;
        if let Ok(Some((_, end))) = npy_header_end(&data) {
            (&mut entry)
                .take(end.saturating_sub(data.len()) as u64)
                .read_to_end(&mut data)
                .map_err(unreadable)?;
            if let Ok((header, _)) = npy_header(&data) {
                check(&key, &header).map_err(|m| (key.clone(), m))?;
                let item = header
                    .dtype()
                    .num_bytes()
                    .filter(|_| !header.uses_pickled_array());
                declared = item.and_then(|n| header.len().checked_mul(n as u64));
                if declared.is_none_or(|d| d > limit.saturating_sub(total)) && item.is_some() {
                    return Err((
                        key.clone(),
                        format!(
                            "declares {} values of {} bytes, more than the archive may expand \
                             to ({limit} bytes)",
                            header.len(),
                            item.unwrap_or(0)
                        ),
                    ));
                }
            }
        }
        let rest = limit.saturating_sub(total + data.len() as u64);
        // A member is read to its declared size and a byte more (what follows is never
        // used); one whose size is unknown (a pickle, or not an .npy), to the limit.
        let cap = declared.map_or(rest, |d| d.min(rest)) + 1;
        (&mut entry)
            .take(cap)
            .read_to_end(&mut data)
            .map_err(unreadable)?;
        total += data.len() as u64;
        if total > limit {
            return Err(file(format!(
                "the archive expands to more than {limit} bytes (at member '{shown}')"
            )));
        }
        members.push((key, data));
    }
    Ok(members)
}

/// The members of an `.npz` archive by name (without `.npy`) with the shape their `.npy`
/// header declares (`None` for a pickle or a member that is not an `.npy`). Only the headers
/// are decompressed.
pub(crate) fn npz_shapes(bytes: &[u8]) -> Result<MemberShapes, String> {
    let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
        .map_err(|e| format!("not an .npz (zip) archive: {e}"))?;
    let mut shapes = Vec::new();
    for i in 0..archive.len() {
        let mut entry = archive
            .by_index(i)
            .map_err(|e| format!("archive member {i} is unreadable: {e}"))?;
        let name = entry
            .name()
            .map_err(|e| format!("archive member {i} has no readable name: {e}"))?
            .into_owned();
        let key = name.strip_suffix(".npy").unwrap_or(&name).to_string();
        let mut data = Vec::new();
        let mut shape = None;
        if (&mut entry).take(12).read_to_end(&mut data).is_ok() {
            if let Ok(Some((_, end))) = npy_header_end(&data) {
                let more = (&mut entry)
                    .take(end.saturating_sub(data.len()) as u64)
                    .read_to_end(&mut data);
                if let (Ok(_), Ok((header, _))) = (more, npy_header(&data)) {
                    shape = (!header.uses_pickled_array()).then(|| header.shape().to_vec());
                }
            }
        }
        shapes.push((key, shape));
    }
    Ok(shapes)
}

/// Every member of an `.npz`: the `wanted` of [`read_npz`] that takes them all.
pub(crate) fn every_member(_: &str) -> bool {
    true
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
