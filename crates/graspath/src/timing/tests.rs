//! Closed forms: one joint moving alone under velocity and acceleration limits has the
//! trapezoidal (or, when it never reaches its top speed, triangular) velocity profile.

use super::*;

/// The duration of a rest-to-rest move of `distance` under `|v| ≤ v_max`, `|a| ≤ a_max`.
fn bang_bang(distance: f64, v_max: f64, a_max: f64) -> f64 {
    if distance >= v_max * v_max / a_max {
        distance / v_max + v_max / a_max
    } else {
        2.0 * (distance / a_max).sqrt()
    }
}

/// One joint from 0 to `distance` in `samples` equal steps, timed on the spline's grid.
fn one_joint(distance: f64, samples: usize, v: f64, a: f64, parts: usize) -> TimedPath {
    let q: Vec<Vec<f64>> = (0..samples)
        .map(|k| vec![distance * k as f64 / (samples - 1) as f64])
        .collect();
    let spline = JointSpline::through(&q).unwrap();
    PathLimits {
        velocity: &[Some(v)],
        acceleration: &[Some(a)],
        torque: None,
        object: None,
        subdivisions: parts,
        discretization: Discretization::default(),
    }
    .time(&spline)
    .unwrap()
}

#[test]
fn one_joint_takes_the_trapezoidal_and_the_triangular_profiles_time() {
    // Trapezoid: 2 rad at 1 rad/s, 2 rad/s² (0.25 rad to accelerate); triangle: 0.2 rad.
    for (distance, v, a) in [(2.0, 1.0, 2.0), (0.2, 1.0, 2.0), (1.5, 2.61, 15.0)] {
        let exact = bang_bang(distance, v, a);
        let timed = one_joint(distance, 401, v, a, 2);
        let error = (timed.duration() - exact).abs() / exact;
        // Collocation misses at most one grid interval at each switch of the profile.
        assert!(
            error < 2e-3,
            "{distance} rad: {} s vs {exact} s",
            timed.duration()
        );
        // Refining the grid converges to the closed form.
        let finer = one_joint(distance, 1601, v, a, 2);
        assert!((finer.duration() - exact).abs() < (timed.duration() - exact).abs() + 1e-12);
        // The speed limit holds at every grid point, and the motion is at rest at both ends.
        assert!(timed.sd_squared.iter().all(|x| *x <= v * v * (1.0 + 1e-9)));
        assert_eq!(timed.sd_squared[0], 0.0);
        assert_eq!(*timed.sd_squared.last().unwrap(), 0.0);
    }
}

#[test]
fn the_sampled_trajectory_respects_the_limits_and_ends_at_rest() {
    let q: Vec<Vec<f64>> = (0..30)
        .map(|k| {
            let t = k as f64 / 29.0;
            vec![t.sin(), 0.5 * t * t, -t]
        })
        .collect();
    let spline = JointSpline::through(&q).unwrap();
    let (v, a) = (
        [Some(1.0), Some(0.5), Some(0.8)],
        [Some(3.0), Some(2.0), Some(4.0)],
    );
    let limits = PathLimits {
        velocity: &v,
        acceleration: &a,
        torque: None,
        object: None,
        subdivisions: 3,
        discretization: Discretization::default(),
    };
    let timed = limits.time(&spline).unwrap();
    let names: Vec<String> = ["a", "b", "c"].map(String::from).to_vec();
    let trajectory = TimedTrajectory::sample(&names, &spline, &timed, Some(0.01), None).unwrap();
    assert!((trajectory.duration() - timed.duration()).abs() < 1e-12);
    let first = &trajectory.points[0];
    let last = trajectory.points.last().unwrap();
    assert_eq!(first.positions, q[0]);
    for (j, end) in q[29].iter().enumerate() {
        assert!((last.positions[j] - end).abs() < 1e-9);
        assert!(first.velocities[j].abs() < 1e-12 && last.velocities[j].abs() < 1e-6);
    }
    for p in &trajectory.points {
        for j in 0..3 {
            assert!(
                p.velocities[j].abs() <= v[j].unwrap() * (1.0 + 1e-3),
                "{p:?}"
            );
            // Between grid points the constraints are not imposed (collocation): allow the
            // discretisation's excess.
            assert!(p.accelerations[j].abs() <= a[j].unwrap() * 1.1, "{p:?}");
        }
    }
}

#[test]
fn an_unreachable_limit_is_infeasible_and_names_it() {
    let spline = JointSpline::through(&[vec![0.0], vec![1.0]]).unwrap();
    // A zero acceleration limit is refused as a limit, not as an infeasible path.
    let err = PathLimits {
        velocity: &[Some(1.0)],
        acceleration: &[Some(0.0)],
        torque: None,
        object: None,
        subdivisions: 1,
        discretization: Discretization::default(),
    }
    .time(&spline)
    .unwrap_err();
    assert!(
        matches!(err, TimingError::BadLimit { joint: 0, .. }),
        "{err}"
    );
}

#[test]
fn a_repeated_sample_adds_no_path_and_a_single_one_takes_no_time() {
    let spline = JointSpline::through(&[vec![0.3, 0.1], vec![0.3, 0.1]]).unwrap();
    assert_eq!(spline.knots(), &[0.0]);
    let timed = PathLimits {
        velocity: &[Some(1.0), Some(1.0)],
        acceleration: &[None, None],
        torque: None,
        object: None,
        subdivisions: 2,
        discretization: Discretization::default(),
    }
    .time(&spline)
    .unwrap();
    assert_eq!(timed.duration(), 0.0);
}

#[test]
fn a_spline_through_samples_on_a_limit_overshoots_it_by_the_reported_excursion() {
    // Joint 0 rides its upper limit 1.0 for three samples while joint 1 moves on: the cubic
    // through joint 0's samples bulges above the limit between them.
    let q: Vec<Vec<f64>> = [0.6, 1.0, 1.0, 1.0, 0.6]
        .iter()
        .enumerate()
        .map(|(k, v)| vec![*v, 0.1 * k as f64])
        .collect();
    let spline = JointSpline::through(&q).unwrap();
    let excursion = spline.range_excursion(&[-2.0, -2.0], &[1.0, 2.0]);
    // Oracle: the largest value at the same quarter points, by the general evaluation.
    let (mut p, mut d, mut dd) = (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
    let mut highest = f64::NEG_INFINITY;
    for pair in spline.knots().windows(2) {
        for f in [0.25, 0.5, 0.75] {
            let point = PathPoint {
                q: &mut p,
                dq: &mut d,
                ddq: &mut dd,
            };
            spline.evaluate_into(pair[0] + f * (pair[1] - pair[0]), point);
            highest = highest.max(p[0]);
        }
    }
    assert!(excursion > 0.0, "no overshoot");
    assert!(
        (excursion - (highest - 1.0)).abs() < 1e-12,
        "{excursion} vs {}",
        highest - 1.0
    );
    // Inside a wider range there is none.
    assert_eq!(spline.range_excursion(&[-2.0, -2.0], &[2.0, 2.0]), 0.0);
}

#[test]
fn each_sample_parameter_is_its_knot_where_the_spline_passes_through_it() {
    // Samples 1 and 2 coincide (the object still): they share one knot.
    let q = vec![
        vec![0.0, 0.0],
        vec![3.0, 4.0],
        vec![3.0, 4.0],
        vec![3.0, 6.0],
        vec![0.0, 6.0],
    ];
    let spline = JointSpline::through(&q).unwrap();
    let parameters = JointSpline::sample_parameters(&q);
    // Oracle: the cumulative joint-space distance between the samples, by hand.
    assert_eq!(parameters, vec![0.0, 5.0, 5.0, 7.0, 10.0]);
    assert_eq!(spline.knots(), &[0.0, 5.0, 7.0, 10.0]);
    let (mut p, mut d, mut dd) = (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
    for (sample, s) in q.iter().zip(&parameters) {
        let point = PathPoint {
            q: &mut p,
            dq: &mut d,
            ddq: &mut dd,
        };
        spline.evaluate_into(*s, point);
        assert!(
            p.iter().zip(sample).all(|(a, b)| (a - b).abs() < 1e-12),
            "{p:?} vs {sample:?}"
        );
    }
}

#[test]
fn the_time_at_a_path_parameter_inverts_the_state_at_a_time() {
    let timed = one_joint(1.5, 11, 1.0, 2.0, 3);
    // At the grid points: their times exactly.
    for (s, t) in timed.grid.iter().zip(&timed.times) {
        assert_eq!(timed.time_at(*s), *t);
    }
    // Between them: the motion's path parameter at that time is `s` again (oracle: the
    // forward map `state_at`), and time grows with `s`.
    let mut previous = 0.0;
    for k in 1..300 {
        let s = 1.5 * k as f64 / 300.0;
        let t = timed.time_at(s);
        assert!(t > previous, "time {t} at s = {s} after {previous}");
        let (back, _, _) = timed.state_at(t);
        assert!((back - s).abs() < 1e-9, "s = {s}: state_at({t}) = {back}");
        previous = t;
    }
    // Clamped to the path.
    assert_eq!(timed.time_at(-1.0), 0.0);
    assert_eq!(timed.time_at(2.0), timed.duration());
}

#[test]
fn stacked_constraints_time_the_paths_as_one_path_of_all_their_joints() {
    // Two "arms" (2 and 3 joints) along one parameter; the oracle is the one 5-joint path
    // timed with all the limits.
    let q: Vec<Vec<f64>> = (0..25)
        .map(|k| {
            let t = k as f64 / 24.0;
            vec![t.sin(), 0.5 * t * t, -t, 0.3 * (3.0 * t).cos(), 2.0 * t]
        })
        .collect();
    let whole = JointSpline::through(&q).unwrap();
    let knots = whole.knots().to_vec();
    let split = |range: std::ops::Range<usize>| -> JointSpline {
        let part: Vec<Vec<f64>> = q.iter().map(|s| s[range.clone()].to_vec()).collect();
        JointSpline::with_knots(&knots, &part).unwrap()
    };
    let v = [Some(1.0), Some(0.5), Some(0.8), Some(0.6), Some(1.5)];
    let a = [Some(3.0), Some(2.0), Some(4.0), Some(1.0), Some(5.0)];
    let limits = |range: std::ops::Range<usize>| PathLimits {
        velocity: &v[range.clone()],
        acceleration: &a[range],
        torque: None,
        object: None,
        subdivisions: 2,
        discretization: Discretization::default(),
    };
    let parts = vec![
        limits(0..2).constraints(&split(0..2)).unwrap(),
        limits(2..5).constraints(&split(2..5)).unwrap(),
    ];
    let stacked = Constraints::stacked(parts, &[2, 3]).unwrap();
    let as_one = limits(0..5).constraints(&whole).unwrap();
    let (stacked, as_one) = (
        time_optimal(&stacked).unwrap(),
        time_optimal(&as_one).unwrap(),
    );
    assert_eq!(stacked.grid, as_one.grid);
    for (x, y) in stacked.sd_squared.iter().zip(&as_one.sd_squared) {
        assert!((x - y).abs() <= 1e-12 * y.max(1.0), "{x} vs {y}");
    }
    assert!((stacked.duration() - as_one.duration()).abs() < 1e-12);
    // A limit of the stack names its part and that part's own joint.
    assert_eq!(Limit::Torque(3).in_part(&[2, 3]), (1, Limit::Torque(1)));
    assert_eq!(Limit::Velocity(1).in_part(&[2, 3]), (0, Limit::Velocity(1)));
    assert_eq!(Limit::ObjectSpeed.in_part(&[2, 3]), (0, Limit::ObjectSpeed));
}

#[test]
fn paths_on_different_grids_or_without_their_joint_counts_do_not_stack() {
    let line = |n: usize| -> Vec<Vec<f64>> { (0..n).map(|k| vec![k as f64]).collect() };
    let limits = PathLimits {
        velocity: &[Some(1.0)],
        acceleration: &[Some(1.0)],
        torque: None,
        object: None,
        subdivisions: 1,
        discretization: Discretization::default(),
    };
    let parts = vec![
        limits
            .constraints(&JointSpline::through(&line(3)).unwrap())
            .unwrap(),
        limits
            .constraints(&JointSpline::through(&line(4)).unwrap())
            .unwrap(),
    ];
    assert!(matches!(
        Constraints::stacked(parts.clone(), &[1, 1]),
        Err(TimingError::BadPath(_))
    ));
    // Each path needs its joint count.
    let same = vec![parts[0].clone(), parts[0].clone()];
    assert!(Constraints::stacked(same.clone(), &[1, 1]).is_ok());
    assert!(matches!(
        Constraints::stacked(same, &[1]),
        Err(TimingError::BadPath(_))
    ));
}
