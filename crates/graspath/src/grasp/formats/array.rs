//! The numeric array every grasp-file reader produces: shape and row-major `f64` values.

/// A numeric array in C (row-major) order, its values as `f64`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Array {
    /// The dimensions.
    pub shape: Vec<usize>,
    /// The values, row-major.
    pub data: Vec<f64>,
}

impl Array {
    /// `[a, b, ...]` as written in messages.
    pub(super) fn shape_text(&self) -> String {
        shape_text(&self.shape)
    }
}

/// `(a, b, …)` as NumPy prints a shape.
pub(crate) fn shape_text<T: ToString>(shape: &[T]) -> String {
    let parts: Vec<String> = shape.iter().map(ToString::to_string).collect();
    if parts.len() == 1 {
        format!("({},)", parts[0])
    } else {
        format!("({})", parts.join(", "))
    }
}

/// Reorders column-major (Fortran) values into row-major order.
pub(crate) fn fortran_to_c(shape: &[usize], values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let mut out = vec![0.0; n];
    let mut index = vec![0usize; shape.len()];
    for slot in out.iter_mut() {
        // `index` walks C order; its Fortran offset is Σ index[k] · Π_{j<k} shape[j].
        let mut offset = 0;
        let mut stride = 1;
        for (k, &i) in index.iter().enumerate() {
            offset += i * stride;
            stride *= shape[k];
        }
        *slot = values[offset];
        for k in (0..shape.len()).rev() {
            index[k] += 1;
            if index[k] < shape[k] {
                break;
            }
            index[k] = 0;
        }
    }
    out
}
