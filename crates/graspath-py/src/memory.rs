//! Result arrays of batch calls: new numpy arrays or the caller's `out=` arrays, written once,
//! in place, in parallel.
//!
//! New memory is expensive: the operating system maps and zeroes every page of a new
//! allocation on its first write (on a virtual machine its host may map it as well), and
//! unmaps it when it is freed. For the tens to hundreds of megabytes of a large batch's result
//! that costs about as much as computing it. So large result arrays (1 MiB and more) take their
//! memory from a cache: when such an array is garbage-collected its buffer goes back to the
//! cache, and a later call that needs a buffer of about that size writes into it directly. The
//! cache holds at most [`DEFAULT_CACHE_BYTES`] (set with `graspath.result_cache`); beyond it the
//! oldest buffers are freed.
//!
//! A buffer that is really new is allocated with transparent huge pages asked for and has its
//! pages mapped (`MADV_POPULATE_WRITE`, Linux ≥ 5.14) block by block, by the threads that then
//! write the block ([`kinematics_into`]). Best effort: on other systems, or when the kernel
//! refuses, nothing happens and the pages are mapped as they are written.

use crate::convert::{error, shape_text};
use graspath::robot::{Chain, RobotError};
use numpy::ndarray::{ArrayView, IxDyn};
use numpy::{PyArrayDyn, PyArrayMethods, PyReadwriteArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::collections::VecDeque;
use std::sync::{Mutex, MutexGuard};

/// Result arrays of at least this many bytes take their memory from the cache.
const CACHED_FROM_BYTES: usize = 1 << 20;

/// The cache's default size: two sets of poses and Jacobians of a million 7-joint
/// configurations (464 MB each).
pub const DEFAULT_CACHE_BYTES: usize = 1 << 30;

/// Freed result buffers kept for reuse, oldest first.
struct Cache {
    buffers: VecDeque<Vec<f64>>,
    bytes: usize,
    limit: usize,
}

static CACHE: Mutex<Cache> = Mutex::new(Cache {
    buffers: VecDeque::new(),
    bytes: 0,
    limit: DEFAULT_CACHE_BYTES,
});

fn cache() -> MutexGuard<'static, Cache> {
    // A panic while the lock was held cannot leave the cache inconsistent (every update is
    // one push or remove with its byte count): keep using it.
    CACHE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Cache {
    /// Evicts the oldest buffers until the cache fits its limit; returns them, to be freed
    /// after the lock is released.
    fn trim(&mut self) -> Vec<Vec<f64>> {
        let mut evicted = Vec::new();
        while self.bytes > self.limit {
            let Some(buffer) = self.buffers.pop_front() else {
                break;
            };
            self.bytes -= size_of_val(buffer.as_slice());
            evicted.push(buffer);
        }
        evicted
    }
}

/// A cached buffer of at least `len` values and at most twice that (the smallest such), if
/// any.
fn take_cached(len: usize) -> Option<Vec<f64>> {
    let mut cache = cache();
    let (at, _) = cache
        .buffers
        .iter()
        .enumerate()
        .filter(|(_, b)| b.len() >= len && b.len() / 2 <= len)
        .min_by_key(|(_, b)| b.len())?;
    let buffer = cache.buffers.remove(at)?;
    cache.bytes -= size_of_val(buffer.as_slice());
    Some(buffer)
}

/// Puts a freed result buffer into the cache (or frees it when it does not fit).
fn give_back(buffer: Vec<f64>) {
    let evicted = {
        let mut cache = cache();
        cache.bytes += size_of_val(buffer.as_slice());
        cache.buffers.push_back(buffer);
        cache.trim()
    };
    drop(evicted);
}

/// The memory of a large result array; back to the cache when the array is freed.
#[pyclass(module = "graspath", name = "_ResultBuffer", frozen)]
struct ResultBuffer {
    data: Vec<f64>,
}

impl Drop for ResultBuffer {
    fn drop(&mut self) {
        give_back(std::mem::take(&mut self.data));
    }
}

/// A new zeroed buffer of `len` values, asking for transparent huge pages (its pages are
/// mapped when first written).
fn new_buffer(len: usize) -> Vec<f64> {
    // `vec![0.0; len]` comes from calloc: a large one is fresh zero pages, not yet mapped.
    #[allow(unused_mut)]
    let mut buffer = vec![0.0; len];
    #[cfg(target_os = "linux")]
    advise(&mut buffer, libc::MADV_HUGEPAGE);
    buffer
}

/// A new float64 array of `shape` whose values the caller will all write (large ones come
/// from the cache: their contents are those of an earlier result until then).
pub fn new_float_array<'py>(
    py: Python<'py>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    Ok(new_array(py, shape)?.0)
}

/// A new float64 array of `shape` whose values will all be written, and whether its pages are
/// mapped already (memory reused from the cache). Small arrays come from numpy, large ones
/// from the cache or a new buffer.
fn new_array<'py>(
    py: Python<'py>,
    shape: &[usize],
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, bool)> {
    let len: usize = shape.iter().product();
    if size_of::<f64>() * len < CACHED_FROM_BYTES {
        return Ok((PyArrayDyn::<f64>::zeros(py, shape, false), true));
    }
    let (data, mapped) = match take_cached(len) {
        Some(buffer) => (buffer, true),
        None => (new_buffer(len), false),
    };
    let owner = Bound::new(py, ResultBuffer { data })?;
    let view = ArrayView::from_shape(IxDyn(shape), &owner.get().data[..len])
        .map_err(|e| error(e.to_string()))?;
    // SAFETY: the array's base is `owner`, which holds the buffer and never touches or
    // reallocates it while it lives; the buffer goes back to the cache only when `owner` is
    // dropped, after every array on it. The array is the only writer of the buffer.
    let array = unsafe { PyArrayDyn::borrow_from_array(&view, owner.clone().into_any()) };
    Ok((array, mapped))
}

/// `graspath.result_cache`: the cache of large result arrays' memory. Returns a dict
/// ``max_bytes`` (the limit), ``bytes`` (held now) and ``buffers``; ``max_bytes``, when given,
/// sets the limit first (0 frees every cached buffer and turns the cache off).
///
/// Batch calls write their large results (1 MiB and more) into memory that earlier results
/// freed, instead of new memory that the system must map and zero first. The cache holds at
/// most ``max_bytes`` (default 1 GiB) of freed buffers; beyond it the oldest are freed.
#[pyfunction]
#[pyo3(signature = (max_bytes = None))]
pub fn result_cache(py: Python<'_>, max_bytes: Option<usize>) -> PyResult<Bound<'_, PyDict>> {
    let (limit, bytes, buffers, evicted) = {
        let mut cache = cache();
        if let Some(limit) = max_bytes {
            cache.limit = limit;
        }
        let evicted = cache.trim();
        (cache.limit, cache.bytes, cache.buffers.len(), evicted)
    };
    py.detach(|| drop(evicted));
    let dict = PyDict::new(py);
    dict.set_item("max_bytes", limit)?;
    dict.set_item("bytes", bytes)?;
    dict.set_item("buffers", buffers)?;
    Ok(dict)
}

/// A float64 result array: new, or the caller's (checked: float64, C-contiguous, writeable,
/// of the expected shape).
pub struct ResultArray<'py> {
    array: Bound<'py, PyArrayDyn<f64>>,
    /// Whether the array's memory is new (its pages are not mapped yet).
    pub fresh: bool,
}

impl<'py> ResultArray<'py> {
    /// The caller's `out` array, checked, or a new array of `shape`.
    pub fn new(
        py: Python<'py>,
        out: Option<Bound<'py, PyAny>>,
        shape: &[usize],
        what: &str,
    ) -> PyResult<Self> {
        let Some(out) = out else {
            let (array, mapped) = new_array(py, shape)?;
            return Ok(Self {
                array,
                fresh: !mapped,
            });
        };
        let array = out
            .cast_into::<PyArrayDyn<f64>>()
            .map_err(|_| error(format!("{what} must be a numpy float64 array")))?;
        if array.shape() != shape {
            return Err(error(format!(
                "{what} has shape {} but {} is expected",
                shape_text(array.shape()),
                shape_text(shape)
            )));
        }
        if !array.is_c_contiguous() {
            return Err(error(format!("{what} must be C-contiguous")));
        }
        Ok(Self {
            array,
            fresh: false,
        })
    }

    /// Borrows the array for writing (refused when it is read-only or borrowed elsewhere).
    pub fn writer(&self) -> PyResult<PyReadwriteArrayDyn<'py, f64>> {
        self.array
            .try_readwrite()
            .map_err(|e| error(format!("the result array cannot be written: {e}")))
    }

    /// The array, for Python.
    pub fn unbind(self) -> Py<PyAny> {
        self.array.into_any().unbind()
    }
}

/// Configurations per block whose new result pages are mapped together, by the thread that
/// then writes the block (about 1.9 MB of a 7-joint chain's poses and Jacobians: one huge
/// page).
const BLOCK: usize = 4096;

/// Poses and Jacobians (row-major, see `Chain::batch_into`) of the configurations `q` into
/// the buffers given, in parallel. `fresh` buffers (new memory) are cut into blocks whose
/// pages are mapped in one go by the thread that writes the block, just before writing it:
/// mapping in parallel, and the pages still in cache when they are written. (Mapping the
/// whole result first, or faulting pages in one by one as they are written, measured slower
/// and far more variable; see BENCHMARKS.md.)
pub fn kinematics_into(
    chain: &Chain,
    q: &[f64],
    poses: Option<&mut [f64]>,
    jacobians: Option<&mut [f64]>,
    fresh: bool,
) -> Result<(), RobotError> {
    let dof = chain.dof();
    let n = q.len() / dof.max(1);
    let sizes_fit = poses.as_deref().is_none_or(|p| p.len() == 16 * n)
        && jacobians.as_deref().is_none_or(|j| j.len() == 6 * dof * n);
    if !fresh || dof == 0 || !sizes_fit || n <= BLOCK {
        return chain.batch_into(q, poses, jacobians);
    }
    let result = split_blocks(q, dof, poses, jacobians)
        .into_par_iter()
        .try_for_each(|(q, mut poses, mut jacobians)| {
            if let Some(p) = poses.as_deref_mut() {
                populate(p);
            }
            if let Some(j) = jacobians.as_deref_mut() {
                populate(j);
            }
            chain.batch_into(q, poses, jacobians)
        });
    // A block names its own first non-finite value: name the first of all.
    result.map_err(|e| match e {
        RobotError::NonFiniteJoint { .. } => RobotError::NonFiniteJoint {
            index: q.iter().position(|v| !v.is_finite()).unwrap_or(0),
        },
        e => e,
    })
}

/// A block of configurations with its share of each buffer.
type Block<'a> = (&'a [f64], Option<&'a mut [f64]>, Option<&'a mut [f64]>);

/// Cuts `q` and the buffers into blocks of [`BLOCK`] configurations.
fn split_blocks<'a>(
    q: &'a [f64],
    dof: usize,
    poses: Option<&'a mut [f64]>,
    jacobians: Option<&'a mut [f64]>,
) -> Vec<Block<'a>> {
    let n = q.len() / dof.max(1);
    let count = n.div_ceil(BLOCK);
    let mut poses = poses.map(|p| split_rows(p, 16, n, BLOCK).into_iter());
    let mut jacobians = jacobians.map(|j| split_rows(j, 6 * dof, n, BLOCK).into_iter());
    split_rows_ref(q, dof, n, BLOCK)
        .into_iter()
        .take(count)
        .map(|rows| {
            let p = poses.as_mut().and_then(Iterator::next);
            let j = jacobians.as_mut().and_then(Iterator::next);
            (rows, p, j)
        })
        .collect()
}

/// `buffer`, holding `n` rows of `width` values, cut into pieces of `chunk` rows (the last
/// one shorter): one piece per task of a parallel loop over the rows.
pub fn split_rows<T>(buffer: &mut [T], width: usize, n: usize, chunk: usize) -> Vec<&mut [T]> {
    let mut pieces = Vec::with_capacity(n.div_ceil(chunk.max(1)));
    let mut rest = buffer;
    let mut start = 0;
    while start < n {
        let k = chunk.max(1).min(n - start);
        let at = (width * k).min(rest.len());
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(at);
        pieces.push(head);
        rest = tail;
        start += k;
    }
    pieces
}

/// [`split_rows`] for a buffer that is only read.
pub fn split_rows_ref<T>(buffer: &[T], width: usize, n: usize, chunk: usize) -> Vec<&[T]> {
    let mut pieces = Vec::with_capacity(n.div_ceil(chunk.max(1)));
    let mut rest = buffer;
    let mut start = 0;
    while start < n {
        let k = chunk.max(1).min(n - start);
        let (head, tail) = rest.split_at((width * k).min(rest.len()));
        pieces.push(head);
        rest = tail;
        start += k;
    }
    pieces
}

/// Maps every whole page of `buffer` (contents unchanged).
pub fn populate(buffer: &mut [f64]) {
    #[cfg(target_os = "linux")]
    advise(buffer, libc::MADV_POPULATE_WRITE);
    #[cfg(not(target_os = "linux"))]
    let _ = buffer;
}

/// `madvise(advice)` on every whole page of `buffer`. The result is ignored: the advice only
/// changes when and how pages are mapped, never the contents.
#[cfg(target_os = "linux")]
fn advise(buffer: &mut [f64], advice: libc::c_int) {
    // SAFETY: sysconf has no preconditions.
    let page = match unsafe { libc::sysconf(libc::_SC_PAGESIZE) } {
        size if size > 0 => size as usize,
        _ => return,
    };
    let start = buffer.as_mut_ptr() as usize;
    let first = start.next_multiple_of(page);
    let end = (start + size_of_val(buffer)) / page * page;
    if end > first {
        // SAFETY: [first, end) lies inside `buffer`, which is borrowed mutably here; the
        // advices used (huge pages, populate) keep the contents.
        unsafe { libc::madvise(first as *mut libc::c_void, end - first, advice) };
    }
}
