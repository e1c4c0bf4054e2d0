//! Indices at one configuration, from the geometric Jacobian `J` (rows `[v; ω]`).

use crate::spelling::spelled;
use nalgebra::{DMatrix, Dim, Matrix, Storage, Vector3, Vector6, U6};

/// The SVD's convergence tolerance: nalgebra's own default (5 ε), so the values are those of
/// `Matrix::svd` to the last bit.
const SVD_EPSILON: f64 = 5.0 * f64::EPSILON;

/// Iterations after which an SVD is declared not to converge (it takes a few dozen for a 6×7
/// Jacobian).
const SVD_MAX_ITERATIONS: usize = 10_000;

/// Which rows of the Jacobian an index uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianPart {
    /// All six rows (mixed units: m/s and rad/s per unit joint velocity).
    Full,
    /// The linear-velocity rows `Jv` (m/s per unit joint velocity).
    Translation,
    /// The angular-velocity rows `Jω` (rad/s per unit joint velocity).
    Rotation,
}

spelled!(JacobianPart {
    Full => "full",
    Translation => "translation",
    Rotation => "rotation",
});

impl JacobianPart {
    fn rows(self) -> std::ops::Range<usize> {
        match self {
            JacobianPart::Full => 0..6,
            JacobianPart::Translation => 0..3,
            JacobianPart::Rotation => 3..6,
        }
    }
}

fn part_matrix<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> DMatrix<f64> {
    let rows = part.rows();
    DMatrix::from_fn(rows.len(), jacobian.ncols(), |r, c| {
        jacobian[(rows.start + r, c)]
    })
}

/// Singular values of the selected rows of `J`, in descending order (as many as rows, padded
/// with zeros when there are fewer joints than rows).
pub fn singular_values<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> Vec<f64> {
    let m = part_matrix(jacobian, part);
    let rows = m.nrows();
    if m.ncols() == 0 {
        // No joint: every direction is singular.
        return vec![0.0; rows];
    }
    // A non-finite Jacobian (or one whose SVD does not converge, at overflowing magnitudes)
    // has no singular values: NaN, never a panic or an endless loop.
    let svd = m
        .iter()
        .all(|v| v.is_finite())
        .then(|| {
            m.clone()
                .try_svd(false, false, SVD_EPSILON, SVD_MAX_ITERATIONS)
        })
        .flatten();
    let Some(svd) = svd else {
        return vec![f64::NAN; rows];
    };
    let mut values: Vec<f64> = svd.singular_values.iter().copied().collect();
    values.sort_by(|a, b| b.total_cmp(a));
    values.resize(rows, 0.0);
    values
}

/// Yoshikawa's manipulability `sqrt(det(J Jᵀ))` of the selected rows: the product of their
/// singular values (0 at a singularity or with fewer joints than rows).
pub fn yoshikawa<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> f64 {
    product_of(&singular_values(jacobian, part))
}

/// Inverse condition number `σmin / σmax` of the selected rows (0 when `σmax = 0`).
pub fn inverse_condition<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> f64 {
    ratio_of(&singular_values(jacobian, part))
}

/// Inverse condition number of `J Jᵀ`, `λmin / λmax` (the paper's eq. 12): the square of
/// [`inverse_condition`].
pub fn inverse_condition_squared<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> f64 {
    inverse_condition(jacobian, part).powi(2)
}

/// The classical indices of one configuration's selected rows, from one SVD: the values of
/// [`yoshikawa`], [`inverse_condition`] and [`inverse_condition_squared`], bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassicalIndices {
    /// Yoshikawa's manipulability `sqrt(det(J Jᵀ))`.
    pub yoshikawa: f64,
    /// `σmin / σmax` (0 when `σmax = 0`).
    pub inverse_condition: f64,
    /// `λmin / λmax` of `J Jᵀ`.
    pub inverse_condition_squared: f64,
}

/// [`ClassicalIndices`] of the selected rows of `J`.
pub fn classical_indices<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    part: JacobianPart,
) -> ClassicalIndices {
    ClassicalIndices::from_singular_values(&singular_values(jacobian, part))
}

impl ClassicalIndices {
    /// The indices from the selected rows' singular values in descending order, as
    /// [`singular_values`] gives them: bit for bit what [`classical_indices`] computes, without
    /// a second decomposition when the singular values are wanted too. No values give NaN.
    pub fn from_singular_values(values: &[f64]) -> Self {
        if values.is_empty() {
            return ClassicalIndices {
                yoshikawa: f64::NAN,
                inverse_condition: f64::NAN,
                inverse_condition_squared: f64::NAN,
            };
        }
        let inverse_condition = ratio_of(values);
        ClassicalIndices {
            yoshikawa: product_of(values),
            inverse_condition,
            inverse_condition_squared: inverse_condition.powi(2),
        }
    }
}

/// The product of singular values.
fn product_of(values: &[f64]) -> f64 {
    values.iter().product()
}

/// The smallest over the largest of singular values in descending order (NaN stays NaN, 0
/// when the largest is 0).
fn ratio_of(values: &[f64]) -> f64 {
    let (max, min) = (values[0], values[values.len() - 1]);
    if max.is_nan() {
        f64::NAN
    } else if max > 0.0 {
        min / max
    } else {
        0.0
    }
}

/// A direction for the task-relevant index, sized to the rows it is used with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Direction {
    /// A 6-D unit direction `[v; ω]` for the full Jacobian.
    Full(Vector6<f64>),
    /// A 3-D unit direction for `Jv`.
    Translation(Vector3<f64>),
    /// A 3-D unit direction for `Jω`.
    Rotation(Vector3<f64>),
}

impl Direction {
    /// The direction as a 6-vector over the rows `[v; ω]` (zeros on the rows it does not use).
    pub fn as_full(&self) -> Vector6<f64> {
        match self {
            Direction::Full(u) => *u,
            Direction::Translation(u) => Vector6::new(u[0], u[1], u[2], 0.0, 0.0, 0.0),
            Direction::Rotation(u) => Vector6::new(0.0, 0.0, 0.0, u[0], u[1], u[2]),
        }
    }
}

/// Task-relevant manipulability `M_T = uᵀ J Jᵀ u = ‖Jᵀ u‖²` along a unit direction `u`
/// (paper eq. 13; no eigen-decomposition needed). Allocation-free.
pub fn task_relevant<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    direction: &Direction,
) -> f64 {
    let weights = direction.as_full();
    (0..jacobian.ncols())
        .map(|c| {
            let column = jacobian.column(c);
            let projection: f64 = (0..6).map(|r| column[r] * weights[r]).sum();
            projection * projection
        })
        .sum()
}

/// The velocity transmission ratio `1 / sqrt(uᵀ (J Jᵀ)⁻¹ u)` along a unit direction `u`: the
/// tip speed along `u` reached with a unit-norm joint velocity. 0 when `u` leaves the range of
/// `J` (a singular direction).
pub fn velocity_transmission_ratio<C: Dim, S: Storage<f64, U6, C>>(
    jacobian: &Matrix<f64, U6, C, S>,
    direction: &Direction,
) -> f64 {
    let (part, u): (JacobianPart, Vec<f64>) = match direction {
        Direction::Full(u) => (JacobianPart::Full, u.iter().copied().collect()),
        Direction::Translation(u) => (JacobianPart::Translation, u.iter().copied().collect()),
        Direction::Rotation(u) => (JacobianPart::Rotation, u.iter().copied().collect()),
    };
    let m = part_matrix(jacobian, part);
    if m.ncols() == 0 {
        return 0.0;
    }
    if !m.iter().all(|v| v.is_finite()) {
        return f64::NAN;
    }
    let Some(svd) = m.try_svd(true, false, SVD_EPSILON, SVD_MAX_ITERATIONS) else {
        return f64::NAN;
    };
    let Some(left) = svd.u else { return 0.0 };
    let largest = svd.singular_values.max();
    let mut quadratic = 0.0;
    for k in 0..left.ncols() {
        let along: f64 = (0..u.len()).map(|r| left[(r, k)] * u[r]).sum();
        let sigma = svd.singular_values[k];
        if sigma <= largest * 1e-12 {
            if along.abs() > 1e-12 {
                return 0.0;
            }
            continue;
        }
        quadratic += (along / sigma).powi(2);
    }
    // Directions outside the column space of U (fewer joints than rows).
    let covered: f64 = (0..left.ncols())
        .map(|k| {
            (0..u.len())
                .map(|r| left[(r, k)] * u[r])
                .sum::<f64>()
                .powi(2)
        })
        .sum();
    if covered < 1.0 - 1e-9 {
        return 0.0;
    }
    1.0 / quadratic.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix6, Matrix6xX};

    #[test]
    fn degenerate_jacobians_give_values_not_panics() {
        // No joint: every direction is singular (σ = 0), so the indices are 0.
        let none = Matrix6xX::<f64>::zeros(0);
        assert_eq!(singular_values(&none, JacobianPart::Full), vec![0.0; 6]);
        assert_eq!(inverse_condition(&none, JacobianPart::Full), 0.0);
        assert_eq!(yoshikawa(&none, JacobianPart::Translation), 0.0);
        let u = Vector3::x();
        assert_eq!(
            velocity_transmission_ratio(&none, &Direction::Translation(u)),
            0.0
        );
        // A non-finite or overflowing Jacobian has no singular values: NaN, never a panic.
        for bad in [f64::NAN, f64::INFINITY, 1e308] {
            let mut j = Matrix6xX::<f64>::from_element(7, 1.0);
            j[(2, 3)] = bad;
            j[(4, 1)] = -bad;
            let values = singular_values(&j, JacobianPart::Full);
            assert_eq!(values.len(), 6);
            if !bad.is_finite() {
                assert!(values.iter().all(|v| v.is_nan()), "{bad}: {values:?}");
                assert!(inverse_condition(&j, JacobianPart::Full).is_nan());
            }
        }
    }

    fn jacobian() -> Matrix6xX<f64> {
        Matrix6xX::from_fn(7, |r, c| {
            ((r * 7 + c) as f64 * 0.37).sin() + if r == c { 1.0 } else { 0.0 }
        })
    }

    #[test]
    fn classical_indices_from_one_svd_equal_the_separate_functions_bit_for_bit() {
        let mut columns = jacobian()
            .column_iter()
            .map(Matrix::into_owned)
            .collect::<Vec<_>>();
        let full = Matrix6xX::from_columns(&columns);
        columns.truncate(3);
        let short = Matrix6xX::from_columns(&columns);
        let mut singular = full.clone();
        singular.set_column(1, &full.column(0).into_owned());
        let mut nan = full.clone();
        nan[(2, 3)] = f64::NAN;
        let none = Matrix6xX::<f64>::zeros(0);
        let bits = |v: f64| v.to_bits();
        for j in [&full, &short, &singular, &nan, &none] {
            for part in [
                JacobianPart::Full,
                JacobianPart::Translation,
                JacobianPart::Rotation,
            ] {
                let together = classical_indices(j, part);
                assert_eq!(bits(together.yoshikawa), bits(yoshikawa(j, part)));
                assert_eq!(
                    bits(together.inverse_condition),
                    bits(inverse_condition(j, part))
                );
                assert_eq!(
                    bits(together.inverse_condition_squared),
                    bits(inverse_condition_squared(j, part))
                );
            }
        }
    }

    #[test]
    fn transmission_ratio_equals_the_explicit_inverse_form() {
        // Oracle: 1/sqrt(uᵀ (J Jᵀ)⁻¹ u) with (J Jᵀ)⁻¹ from an LU inverse, not the SVD path.
        let j = jacobian();
        let inverse: Matrix6<f64> = (&j * j.transpose()).try_inverse().expect("full rank");
        for k in 0..6 {
            let u = Vector6::from_fn(|r, _| ((r + k) as f64 * 0.9).cos()).normalize();
            let expected = 1.0 / (u.transpose() * inverse * u)[(0, 0)].sqrt();
            let got = velocity_transmission_ratio(&j, &Direction::Full(u));
            assert!(
                (got - expected).abs() < 1e-10 * expected,
                "{got} vs {expected}"
            );
        }
    }

    #[test]
    fn transmission_ratio_is_zero_outside_the_range() {
        // A 6×2 Jacobian cannot move along a direction orthogonal to its columns.
        let j = Matrix6xX::from_column_slice(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0,
        ]);
        let along_z = Direction::Full(Vector6::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0));
        assert_eq!(velocity_transmission_ratio(&j, &along_z), 0.0);
        let along_x = Direction::Full(Vector6::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0));
        assert!((velocity_transmission_ratio(&j, &along_x) - 1.0).abs() < 1e-12);
    }
}
