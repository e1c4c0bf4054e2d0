//! Conversions between numpy arrays / Python objects and the library's types, and the mapping
//! of library errors to the exceptions of `graspath/_errors.py` by their kind.
//!
//! Arrays come in as anything numpy can turn into `float64` (lists, int arrays, views). A
//! C-contiguous float64 array is read where it lies; any other layout (Fortran order, strided
//! views) is read through its strides into a row-major copy, so that the heavy work can run on
//! row-major values without the GIL. A copy larger than [`MAX_COPY_BYTES`] (1 GiB) is refused
//! before it is made: a broadcast view (zero strides, `np.broadcast_to`) of a billion rows takes
//! no memory itself but would be copied whole. Complex, date, string and record arrays are
//! refused, never converted (numpy's cast would drop an imaginary part, or pass counts of time
//! units or parsed text as numbers).

use graspath::geometry::{pose_from_rows, pose_to_rows};
use graspath::manipulability::JacobianRows;
use graspath::spelling::Spelled;
use graspath::ErrorKind;
use nalgebra::Isometry3;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{
    AllowTypeChange, IntoPyArray, PyArrayDescrMethods, PyArrayDyn, PyArrayLikeDyn, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use std::borrow::Cow;

/// The largest row-major copy made of an array that is not C-contiguous `float64` (bytes).
pub const MAX_COPY_BYTES: usize = 1 << 30;

/// Any array-like that numpy can convert to `float64` without losing what the values mean:
/// complex, date, duration, string and record arrays (and lists of them) are refused with a
/// `GraspathError` ([`refused_kind`]).
pub struct FloatArray<'py>(PyArrayLikeDyn<'py, f64, AllowTypeChange>);

impl<'py> std::ops::Deref for FloatArray<'py> {
    type Target = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

    fn deref(&self) -> &Self::Target {
        &self.0
    }
}

impl<'a, 'py> FromPyObject<'a, 'py> for FloatArray<'py> {
    type Error = PyErr;

    fn extract(ob: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let kind = match ob.cast::<PyUntypedArray>() {
            Ok(array) => Some(array.dtype().kind()),
            // Lists and scalars: what numpy makes of them.
            Err(_) => ob
                .py()
                .import("numpy")?
                .call_method1("asarray", (ob.to_owned(),))
                .and_then(|a| a.getattr("dtype")?.getattr("kind")?.extract::<char>())
                .ok()
                .and_then(|kind| u8::try_from(kind).ok()),
        };
        if let Some(reason) = kind.and_then(refused_kind) {
            return Err(error(reason));
        }
        PyArrayLikeDyn::<f64, AllowTypeChange>::extract(ob).map(Self)
    }
}

/// Why values of numpy dtype kind `kind` are refused, for the kinds whose cast to `float64`
/// would not keep the values meant: complex numbers (the imaginary part dropped), dates and
/// durations (their counts of time units), strings and raw bytes (parsed as text), structured
/// records. `None` for numbers, booleans and Python objects (converted one by one, a number
/// each, or refused by numpy).
fn refused_kind(kind: u8) -> Option<&'static str> {
    match kind {
        b'c' => Some(
            "complex values are refused (their imaginary part would be lost); pass the real \
             part (np.real) if that is what is meant",
        ),
        b'M' | b'm' => Some(
            "dates and durations are refused (numpy would pass their counts of time units as \
             numbers); pass numbers in the documented units",
        ),
        b'U' | b'S' => Some("strings are refused: pass numbers (np.asarray(x, dtype=float))"),
        b'V' => Some("structured and raw records are refused: pass an array of numbers"),
        _ => None,
    }
}

/// Parses an index mode (`mode`, `length_scale` of `Task.from_arrays` and
/// `Robot.optimize_self_motion`), as a task file's `index`.
pub fn index_mode(mode: &str, length_scale: f64) -> PyResult<JacobianRows> {
    JacobianRows::from_mode(mode, length_scale).map_err(|m| error(format!("mode: {m}")))
}

/// Reads the setting `name` (`norm`, `measure`, `redundancy`, …) spelled `value`, with the
/// library's spelling table; a bad value names the argument and every spelling.
pub fn spelled<T: Spelled>(name: &str, value: &str) -> PyResult<T> {
    T::parse(value).map_err(|m| error(format!("{name}: {m}")))
}

/// A message of the bindings themselves (an argument with a bad value, type or shape) as a
/// `graspath.GraspathValueError`.
pub fn error(message: impl Into<String>) -> PyErr {
    raise("GraspathValueError", message.into(), None, None, None)
}

/// A library error as the exception of its kind (`graspath/_errors.py`): the library's whole
/// message with its causes, the `file` and `field` at fault, and `errno` for a file error that
/// has one.
pub fn lib_error(e: impl Into<graspath::Error>) -> PyErr {
    let e = e.into();
    let fault = e.fault();
    let class = match fault.kind {
        ErrorKind::File if fault.io == Some(std::io::ErrorKind::NotFound) => {
            "GraspathFileNotFoundError"
        }
        ErrorKind::File => "GraspathFileError",
        ErrorKind::Content | ErrorKind::Limit => "GraspathValueError",
        _ if fault.io.is_some() => "GraspathFileError",
        _ => "GraspathError",
    };
    let errno = std::iter::successors(Some(&e as &(dyn std::error::Error + 'static)), |e| {
        e.source()
    })
    .find_map(|e| e.downcast_ref::<std::io::Error>()?.raw_os_error());
    raise(
        class,
        graspath::Chain(&e).to_string(),
        fault.file,
        fault.field,
        errno,
    )
}

/// An instance of `graspath._errors.<class>` with `message`, `file`, `field` and (when given)
/// `errno`, as a `PyErr`.
fn raise(
    class: &str,
    message: String,
    file: Option<&str>,
    field: Option<&str>,
    errno: Option<i32>,
) -> PyErr {
    Python::attach(|py| {
        let made = || -> PyResult<Bound<'_, PyAny>> {
            let exception = py
                .import("graspath._errors")?
                .getattr(class)?
                .call1((message.as_str(),))?;
            exception.setattr("file", file)?;
            exception.setattr("field", field)?;
            if let Some(errno) = errno {
                exception.setattr("errno", errno)?;
            }
            Ok(exception)
        };
        match made() {
            Ok(exception) => PyErr::from_value(exception),
            Err(e) => e,
        }
    })
}

/// A contiguous row-major copy of an array and its shape.
pub struct Buffer {
    /// The values, row-major.
    pub data: Vec<f64>,
    /// The array's shape.
    pub shape: Vec<usize>,
}

impl Buffer {
    /// Copies `array` (any layout) into a row-major buffer; `what` names it in errors.
    pub fn from_array(array: &FloatArray<'_>, what: &str) -> PyResult<Self> {
        Ok(Self {
            shape: array.shape().to_vec(),
            data: row_major(array, what)?.into_owned(),
        })
    }

    /// The shape as Python prints it, e.g. `(3, 7)`.
    pub fn shape_text(&self) -> String {
        shape_text(&self.shape)
    }
}

/// The values of `array` in row-major (C) order: the array's own memory when it is
/// C-contiguous, else a copy read through its strides in index order (Fortran-ordered and
/// strided arrays give the same values as their C-ordered copies).
/// A copy larger than [`MAX_COPY_BYTES`] is refused before it is made; `what` names the array.
pub fn row_major<'a>(array: &'a FloatArray<'_>, what: &str) -> PyResult<Cow<'a, [f64]>> {
    // `as_slice` also accepts Fortran-contiguous arrays, whose memory order is not row-major:
    // only C order is borrowed as it lies.
    if array.is_c_contiguous() {
        if let Ok(slice) = array.as_slice() {
            return Ok(Cow::Borrowed(slice));
        }
    }
    let values = array
        .shape()
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d));
    if values.is_none_or(|n| n > MAX_COPY_BYTES / size_of::<f64>()) {
        let strides = array.strides();
        return Err(error(format!(
            "{what} has shape {} with strides {strides:?} (bytes): a row-major copy would take more \
             than {MAX_COPY_BYTES} bytes (a broadcast view is copied whole); pass a smaller batch \
             or a C-contiguous float64 array",
            shape_text(array.shape())
        )));
    }
    Ok(Cow::Owned(array.as_array().iter().copied().collect()))
}

/// A shape as Python prints it.
pub fn shape_text(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Rows of a fixed width: one row from shape `(width,)`, or `n` rows from `(n, width)`.
/// Returns the buffer and `Some(n)` for the batch form, `None` for a single row.
pub fn rows(
    array: &FloatArray<'_>,
    width: usize,
    what: &str,
) -> PyResult<(Vec<f64>, Option<usize>)> {
    let buffer = Buffer::from_array(array, what)?;
    match buffer.shape.as_slice() {
        [w] if *w == width => Ok((buffer.data, None)),
        [n, w] if *w == width => Ok((buffer.data, Some(*n))),
        _ => Err(error(format!(
            "{what} has shape {} but ({width},) or (n, {width}) is expected",
            buffer.shape_text()
        ))),
    }
}

/// Checks that every value is finite; names the first offending entry.
pub fn check_finite(data: &[f64], width: usize, what: &str, batch: bool) -> PyResult<()> {
    match data.iter().position(|v| !v.is_finite()) {
        Some(k) => Err(non_finite_error(k, width, what, batch)),
        None => Ok(()),
    }
}

/// The error for the value at `index` of row-major rows of `width` values that is not finite,
/// named by its position in the array (`q[row, col]`, or `q[col]` for one row).
pub fn non_finite_error(index: usize, width: usize, what: &str, batch: bool) -> PyErr {
    let (row, col) = (index / width.max(1), index % width.max(1));
    let place = if batch {
        format!("{what}[{row}, {col}]")
    } else {
        format!("{what}[{col}]")
    };
    error(format!("{place} is not a finite number"))
}

/// A pose from 16 row-major values of a 4×4 homogeneous matrix.
pub fn pose_from_slice(values: &[f64], what: &str) -> PyResult<Isometry3<f64>> {
    let rows: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| values[4 * i + j]));
    pose_from_rows(&rows).map_err(|e| error(format!("{what}: {e}")))
}

/// Poses from shape `(4, 4)` (`None` batch) or `(n, 4, 4)` (`Some(n)`).
pub fn poses(array: &FloatArray<'_>, what: &str) -> PyResult<(Vec<Isometry3<f64>>, Option<usize>)> {
    let buffer = Buffer::from_array(array, what)?;
    match buffer.shape.as_slice() {
        [4, 4] => Ok((vec![pose_from_slice(&buffer.data, what)?], None)),
        [n, 4, 4] => {
            let poses = buffer
                .data
                .chunks_exact(16)
                .enumerate()
                .map(|(i, m)| pose_from_slice(m, &format!("{what}[{i}]")))
                .collect::<PyResult<Vec<_>>>()?;
            Ok((poses, Some(*n)))
        }
        _ => Err(error(format!(
            "{what} has shape {} but (4, 4) or (n, 4, 4) is expected",
            buffer.shape_text()
        ))),
    }
}

/// A trajectory's poses, in order.
pub type Trajectory = Vec<Isometry3<f64>>;

/// Trajectories of poses: one from shape `(n, 4, 4)` or `(4, 4)` (`None` batch), or `b` of `n`
/// poses each from `(b, n, 4, 4)` (`Some(b)`). A bad pose is named by its indices.
pub fn trajectories(
    array: &FloatArray<'_>,
    what: &str,
) -> PyResult<(Vec<Trajectory>, Option<usize>)> {
    let buffer = Buffer::from_array(array, what)?;
    let (batch, n) = match buffer.shape.as_slice() {
        [4, 4] => (None, 1),
        [n, 4, 4] => (None, *n),
        [b, n, 4, 4] => (Some(*b), *n),
        _ => {
            return Err(error(format!(
                "{what} has shape {} but (n, 4, 4), (4, 4) or (b, n, 4, 4) is expected",
                buffer.shape_text()
            )))
        }
    };
    let trajectories = (0..batch.unwrap_or(1))
        .map(|k| {
            (0..n)
                .map(|i| {
                    let name = match batch {
                        None => format!("{what}[{i}]"),
                        Some(_) => format!("{what}[{k}, {i}]"),
                    };
                    let at = 16 * (k * n + i);
                    pose_from_slice(&buffer.data[at..at + 16], &name)
                })
                .collect()
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok((trajectories, batch))
}

/// One pose from shape `(4, 4)`.
pub fn single_pose(array: &FloatArray<'_>, what: &str) -> PyResult<Isometry3<f64>> {
    match poses(array, what)? {
        (mut one, None) => Ok(one.remove(0)),
        (_, Some(n)) => Err(error(format!(
            "{what} has shape ({n}, 4, 4) but one (4, 4) pose is expected"
        ))),
    }
}

/// The 16 row-major values of a pose.
pub fn push_isometry(out: &mut Vec<f64>, pose: &Isometry3<f64>) {
    for row in pose_to_rows(pose) {
        out.extend_from_slice(&row);
    }
}

/// A new float64 array of the given shape from row-major data (no copy).
pub fn array<'py>(
    py: Python<'py>,
    data: Vec<f64>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let array = ArrayD::from_shape_vec(IxDyn(shape), data).map_err(|e| error(e.to_string()))?;
    Ok(array.into_pyarray(py))
}

/// Checks the dimensions of an array argument against an expected shape pattern (`None` = any).
pub fn check_shape(array: &FloatArray<'_>, expected: &[Option<usize>], what: &str) -> PyResult<()> {
    let shape = array.shape();
    let fits = shape.len() == expected.len()
        && shape
            .iter()
            .zip(expected)
            .all(|(s, e)| e.is_none_or(|e| e == *s));
    if fits {
        return Ok(());
    }
    let pattern: Vec<String> = expected
        .iter()
        .map(|e| e.map_or("n".to_string(), |v| v.to_string()))
        .collect();
    let pattern = if pattern.len() == 1 {
        format!("({},)", pattern[0])
    } else {
        format!("({})", pattern.join(", "))
    };
    Err(error(format!(
        "{what} has shape {} but {pattern} is expected",
        shape_text(shape)
    )))
}

/// A JSON value as the equal Python object (`json.loads` of its text gives the same object).
pub fn json_to_py<'py>(py: Python<'py>, value: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(json_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, v) in map {
                dict.set_item(k, json_to_py(py, v)?)?;
            }
            dict.into_any()
        }
    })
}
