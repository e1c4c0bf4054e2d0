//! A joint path through IK samples: the natural cubic spline `q(s)` through them, in a
//! chord-length path parameter.
//!
//! Why this path: the TOPP-RA constraints need `q'(s)` and `q''(s)` everywhere along the path,
//! and a cubic spline is the smoothest curve through the samples (twice continuously
//! differentiable, so the joint accelerations of a timed motion never jump). The parameter is
//! the cumulative joint-space distance between samples (`s_{i+1} = s_i + ‖q_{i+1} − q_i‖₂`,
//! rad for revolute joints): with it `‖q'(s)‖ ≈ 1` along the whole path, so a stretch where
//! the IK samples lie close in joint space (the object still, or a slow part of the task) does
//! not make the spline overshoot between them. "Natural" sets `q'' = 0` at both ends; with the
//! motion at rest there (`ṡ = 0`) the ends' accelerations do not depend on it.
//! This is SciPy's `CubicSpline(knots, samples, bc_type="natural")`, which the tests use as
//! the oracle.

use super::TimingError;

/// Consecutive samples closer than this in joint space (rad or m) are one sample: a repeated
/// configuration adds no path (the object still on the path, a stroke of zero length).
pub const REPEATED_SAMPLE: f64 = 1e-12;

/// A natural cubic spline through joint configurations, in a scalar path parameter `s`.
#[derive(Debug, Clone, PartialEq)]
pub struct JointSpline {
    dof: usize,
    /// The parameter at each sample, strictly increasing (`knots[0]` first).
    knots: Vec<f64>,
    /// Per interval `i` and joint `j`, at `[i * dof + j]`: `[q, q', q''/2, q'''/6]` at
    /// `knots[i]`, so that `q(s) = c0 + c1 t + c2 t² + c3 t³` with `t = s − knots[i]`.
    coefficients: Vec<[f64; 4]>,
}

/// A joint path's configuration and its first two derivatives with respect to `s` at one
/// parameter value, in caller buffers (one entry per joint).
pub struct PathPoint<'a> {
    /// `q(s)` (rad or m).
    pub q: &'a mut [f64],
    /// `q'(s)` (rad or m per unit of `s`).
    pub dq: &'a mut [f64],
    /// `q''(s)`.
    pub ddq: &'a mut [f64],
}

impl JointSpline {
    /// The spline through `samples` (one configuration each, all of one length) in the
    /// chord-length parameter (see the module documentation), after merging consecutive
    /// samples closer than [`REPEATED_SAMPLE`]. A single distinct sample gives a path of
    /// length zero.
    pub fn through(samples: &[Vec<f64>]) -> Result<Self, TimingError> {
        let dof = check_samples(samples)?;
        let (kept, knots): (Vec<&[f64]>, Vec<f64>) = samples
            .iter()
            .zip(chord_parameters(samples))
            .filter(|(_, (_, new))| *new)
            .map(|(q, (s, _))| (q.as_slice(), s))
            .unzip();
        Self::build(dof, knots, &kept)
    }

    /// The path parameter `s` (rad or m) at which the spline [`JointSpline::through`] builds
    /// from `samples` passes each of them: its knot, the joint-space distance along the
    /// samples from the first. A sample within [`REPEATED_SAMPLE`] of the last distinct one
    /// shares that sample's knot.
    pub fn sample_parameters(samples: &[Vec<f64>]) -> Vec<f64> {
        chord_parameters(samples)
            .into_iter()
            .map(|(s, _)| s)
            .collect()
    }

    /// The spline through `samples` at the given strictly increasing `knots` (one per sample).
    pub fn with_knots(knots: &[f64], samples: &[Vec<f64>]) -> Result<Self, TimingError> {
        let dof = check_samples(samples)?;
        if knots.len() != samples.len() {
            return Err(TimingError::BadPath(format!(
                "{} knots for {} samples",
                knots.len(),
                samples.len()
            )));
        }
        if let Some(i) = (1..knots.len())
            .find(|&i| knots[i].partial_cmp(&knots[i - 1]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(TimingError::BadPath(format!(
                "knot {i} ({}) does not follow knot {} ({})",
                knots[i],
                i - 1,
                knots[i - 1]
            )));
        }
        if knots.iter().any(|s| !s.is_finite()) {
            return Err(TimingError::BadPath("a knot is not finite".into()));
        }
        let rows: Vec<&[f64]> = samples.iter().map(Vec::as_slice).collect();
        Self::build(dof, knots.to_vec(), &rows)
    }

    /// Solves the natural spline's tridiagonal system for the second derivatives at the knots
    /// (one factorisation shared by every joint) and stores each interval's coefficients.
    fn build(dof: usize, knots: Vec<f64>, samples: &[&[f64]]) -> Result<Self, TimingError> {
        let n = knots.len();
        let intervals = n.saturating_sub(1);
        // Second derivatives at the knots, `[knot * dof + joint]`; zero at both ends.
        let mut second = vec![0.0; n * dof];
        if n > 2 {
            let h: Vec<f64> = knots.windows(2).map(|w| w[1] - w[0]).collect();
            // Interior unknowns 1..n-1: h[i-1] m[i-1] + 2 (h[i-1] + h[i]) m[i] + h[i] m[i+1]
            // = 6 (slope[i] − slope[i-1]); the Thomas algorithm, forward sweep then back
            // substitution, with the right-hand sides of all joints at once.
            let interior = n - 2;
            let mut upper = vec![0.0; interior];
            let mut rhs = vec![0.0; interior * dof];
            let mut previous_upper = 0.0;
            for k in 0..interior {
                let i = k + 1;
                let diagonal = 2.0 * (h[i - 1] + h[i]) - h[i - 1] * previous_upper;
                upper[k] = h[i] / diagonal;
                for j in 0..dof {
                    let slope_after = (samples[i + 1][j] - samples[i][j]) / h[i];
                    let slope_before = (samples[i][j] - samples[i - 1][j]) / h[i - 1];
                    let carried = if k > 0 { rhs[(k - 1) * dof + j] } else { 0.0 };
                    rhs[k * dof + j] =
                        (6.0 * (slope_after - slope_before) - h[i - 1] * carried) / diagonal;
                }
                previous_upper = upper[k];
            }
            for k in (0..interior).rev() {
                for j in 0..dof {
                    let next = second[(k + 2) * dof + j];
                    second[(k + 1) * dof + j] = rhs[k * dof + j] - upper[k] * next;
                }
            }
        }
        let mut coefficients = Vec::with_capacity(intervals * dof);
        for i in 0..intervals {
            let h = knots[i + 1] - knots[i];
            for j in 0..dof {
                let (y0, y1) = (samples[i][j], samples[i + 1][j]);
                let (m0, m1) = (second[i * dof + j], second[(i + 1) * dof + j]);
                coefficients.push([
                    y0,
                    (y1 - y0) / h - h * (2.0 * m0 + m1) / 6.0,
                    m0 / 2.0,
                    (m1 - m0) / (6.0 * h),
                ]);
            }
        }
        if coefficients.iter().flatten().any(|c| !c.is_finite()) {
            return Err(TimingError::BadPath(
                "the spline through the samples is not finite (knots too close)".into(),
            ));
        }
        let single = (n == 1).then(|| samples[0].iter().map(|&q| [q, 0.0, 0.0, 0.0]));
        if let Some(constant) = single {
            coefficients.extend(constant);
        }
        Ok(Self {
            dof,
            knots,
            coefficients,
        })
    }

    /// Joints per configuration.
    pub fn dof(&self) -> usize {
        self.dof
    }

    /// The parameter at each (distinct) sample, from `0` for [`JointSpline::through`].
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The parameter's range `[first knot, last knot]`.
    pub fn range(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// The configuration and its derivatives at `s` (clamped to [`JointSpline::range`]), into
    /// `point`'s buffers (each `dof` long).
    pub fn evaluate_into(&self, s: f64, point: PathPoint<'_>) {
        let (first, last) = self.range();
        let s = s.clamp(first, last);
        let intervals = self.knots.len().saturating_sub(1).max(1);
        // The interval whose start is the last knot at or before `s`.
        let i = self
            .knots
            .partition_point(|&k| k <= s)
            .saturating_sub(1)
            .min(intervals - 1);
        let t = s - self.knots[i];
        let row = &self.coefficients[i * self.dof..(i + 1) * self.dof];
        let outputs = point
            .q
            .iter_mut()
            .zip(point.dq.iter_mut())
            .zip(point.ddq.iter_mut());
        for ([c0, c1, c2, c3], ((q, dq), ddq)) in row.iter().zip(outputs) {
            *q = c0 + t * (c1 + t * (c2 + t * c3));
            *dq = c1 + t * (2.0 * c2 + t * 3.0 * c3);
            *ddq = 2.0 * c2 + 6.0 * c3 * t;
        }
    }
}

impl JointSpline {
    /// The largest distance (rad or m, over the joints) between the spline and the straight
    /// joint-space segment between consecutive samples, taken at each interval's middle: how
    /// far the smooth motion departs from the piecewise-linear one the IK samples and the
    /// collision checks between samples describe.
    pub fn deviation_from_chords(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for (i, pair) in self.knots.windows(2).enumerate() {
            let t = 0.5 * (pair[1] - pair[0]);
            let row = &self.coefficients[i * self.dof..(i + 1) * self.dof];
            for [c0, c1, c2, c3] in row {
                let end = c0 + 2.0 * t * (c1 + 2.0 * t * (c2 + 2.0 * t * c3));
                let middle = c0 + t * (c1 + t * (c2 + t * c3));
                worst = worst.max((middle - 0.5 * (c0 + end)).abs());
            }
        }
        worst
    }
}

impl JointSpline {
    /// How far (rad or m) the spline leaves the range `[lower, upper]` of any joint at the
    /// quarter points of its intervals (0 when it stays inside): where IK samples ride a joint
    /// limit, the smooth curve through them can overshoot it between them.
    pub fn range_excursion(&self, lower: &[f64], upper: &[f64]) -> f64 {
        let mut worst: f64 = 0.0;
        for (i, pair) in self.knots.windows(2).enumerate() {
            let h = pair[1] - pair[0];
            let row = &self.coefficients[i * self.dof..(i + 1) * self.dof];
            for fraction in [0.25, 0.5, 0.75] {
                let t = fraction * h;
                for (j, [c0, c1, c2, c3]) in row.iter().enumerate() {
                    let q = c0 + t * (c1 + t * (c2 + t * c3));
                    worst = worst.max(lower[j] - q).max(q - upper[j]);
                }
            }
        }
        worst
    }
}

/// The joint count of `samples`, which must be non-empty, equally long and finite.
fn check_samples(samples: &[Vec<f64>]) -> Result<usize, TimingError> {
    let dof = samples
        .first()
        .map(Vec::len)
        .ok_or_else(|| TimingError::BadPath("no samples".into()))?;
    for (i, q) in samples.iter().enumerate() {
        if q.len() != dof {
            return Err(TimingError::BadPath(format!(
                "sample {i} has {} joints, sample 0 has {dof}",
                q.len()
            )));
        }
        if q.iter().any(|v| !v.is_finite()) {
            return Err(TimingError::BadPath(format!("sample {i} is not finite")));
        }
    }
    Ok(dof)
}

/// Per sample, its chord-length parameter and whether it is a knot of its own (the first
/// sample, and each farther than [`REPEATED_SAMPLE`] from the last such sample; the others
/// share that sample's parameter).
fn chord_parameters(samples: &[Vec<f64>]) -> Vec<(f64, bool)> {
    let mut out = Vec::with_capacity(samples.len());
    let mut last: Option<(&[f64], f64)> = None;
    for q in samples {
        let s = match last {
            None => 0.0,
            Some((previous, s)) => {
                let step = distance(previous, q);
                if step <= REPEATED_SAMPLE {
                    out.push((s, false));
                    continue;
                }
                s + step
            }
        };
        out.push((s, true));
        last = Some((q, s));
    }
    out
}

/// The Euclidean distance between two configurations.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}
