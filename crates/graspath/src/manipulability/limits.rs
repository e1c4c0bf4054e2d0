//! How close a configuration is to the joint limits, and the joint-limit penalty that scales an
//! index down near them (Tsai 1986, as used by Vahrenkamp et al. 2012 and Simox).

/// The distance of the joint nearest to one of its limits (rad or m): `min_i min(q_i − l_i,
/// u_i − q_i)`. Joints without limits (continuous, `±∞`) do not count; `+∞` when no joint has
/// limits. Negative when a joint is outside its limits.
pub fn limit_distance(q: &[f64], lower: &[f64], upper: &[f64]) -> f64 {
    q.iter()
        .zip(lower.iter().zip(upper))
        .filter(|(_, (l, u))| l.is_finite() && u.is_finite())
        .map(|(q, (l, u))| (q - l).min(u - q))
        .fold(f64::INFINITY, f64::min)
}

/// Tsai's joint-limit penalty `P(q) = 1 − exp(−k Π_i (q_i − l_i)(u_i − q_i) / (u_i − l_i)²)`
/// over the joints with finite limits: 0 at any limit, rising towards `1 − exp(−k / 4ⁿ)` with
/// every joint at mid-range. A measure multiplied by it keeps its ranking away from the limits
/// and falls to 0 at them. `k > 0` (50 in Simox); 1 when no joint has limits.
pub fn joint_limit_penalty(q: &[f64], lower: &[f64], upper: &[f64], k: f64) -> f64 {
    let mut product = 1.0;
    let mut limited = false;
    for (q, (l, u)) in q.iter().zip(lower.iter().zip(upper)) {
        if !(l.is_finite() && u.is_finite()) || u <= l {
            continue;
        }
        limited = true;
        let range = u - l;
        product *= ((q - l) * (u - q) / (range * range)).max(0.0);
    }
    if limited {
        -(-k * product).exp_m1()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_is_to_the_nearest_limit_of_the_limited_joints() {
        let lower = [-1.0, f64::NEG_INFINITY, 0.0];
        let upper = [1.0, f64::INFINITY, 0.5];
        assert!((limit_distance(&[0.9, 100.0, 0.25], &lower, &upper) - 0.1).abs() < 1e-12);
        assert!((limit_distance(&[0.0, 0.0, 0.45], &lower, &upper) - 0.05).abs() < 1e-12);
        assert_eq!(
            limit_distance(&[0.0], &[f64::NEG_INFINITY], &[f64::INFINITY]),
            f64::INFINITY
        );
        assert!(limit_distance(&[1.2, 0.0, 0.2], &lower, &upper) < 0.0);
    }

    #[test]
    fn penalty_matches_its_closed_form_and_vanishes_at_the_limits() {
        let lower = [-2.0, -1.0];
        let upper = [2.0, 3.0];
        // Oracle written out for two joints.
        let q = [0.5, 0.2];
        let product = ((0.5 + 2.0) * (2.0 - 0.5) / 16.0) * ((0.2 + 1.0) * (3.0 - 0.2) / 16.0);
        let expected = 1.0 - (-50.0_f64 * product).exp();
        let got = joint_limit_penalty(&q, &lower, &upper, 50.0);
        assert!((got - expected).abs() < 1e-15, "{got} vs {expected}");
        assert_eq!(joint_limit_penalty(&[2.0, 0.2], &lower, &upper, 50.0), 0.0);
        assert_eq!(joint_limit_penalty(&[0.0, -1.0], &lower, &upper, 50.0), 0.0);
        // Largest with every joint at mid-range.
        let mid = joint_limit_penalty(&[0.0, 1.0], &lower, &upper, 50.0);
        assert!((mid - (1.0 - (-50.0f64 / 16.0).exp())).abs() < 1e-15);
        assert!(got < mid);
        // Continuous joints do not count.
        assert_eq!(
            joint_limit_penalty(&[7.0], &[f64::NEG_INFINITY], &[f64::INFINITY], 50.0),
            1.0
        );
    }
}
