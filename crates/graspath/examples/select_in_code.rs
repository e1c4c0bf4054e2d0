//! Using graspath as a library: a task built in code (no file) — the paper's cuboid
//! Pick-and-Place for Baxter's left arm — scored, ranked and printed.
//!
//! Run with `cargo run --release -p graspath --example select_in_code`.

use graspath::geometry::shape::Shape;
use graspath::grasp::edge_family;
use graspath::robot::builtin::{baxter, Arm};
use graspath::select::select;
use graspath::task::{Sampling, Step, Task, TimedStep};
use nalgebra::{Isometry3, Vector3};

fn main() -> graspath::Result<()> {
    // The object: a 6 × 40 × 10 cm cuboid 0.75 m in front of Baxter's base frame.
    let shape = Shape::cuboid([0.06, 0.40, 0.10])?;
    let world_from_object = Isometry3::translation(0.75, 0.0, -0.10);
    // 21 top grasps along the top edge, from the left-most (+y) to the right-most (−y) contact.
    let candidates = edge_family(&shape, 21, 0.02, 0.02)?;
    // After the grasp: lift 0.2 m, move 0.3 m to the left, place 0.2 m lower (world frame).
    let step =
        |label: &str, v: [f64; 3]| TimedStep::new(label, Step::translation(Vector3::from(v)));
    let steps = vec![
        step("pick", [0.0, 0.0, 0.2]),
        step("move", [0.0, 0.3, 0.0]),
        step("place", [0.0, 0.0, -0.2]),
    ];
    let task = Task::builder("pick-and-place (in code)")
        .robot_name("baxter")
        .arm("left", baxter(Arm::Left), Isometry3::identity())
        .shape(shape.clone())
        .candidates(candidates)
        .object_motion(world_from_object, steps, Sampling::PerStep(10))
        .build()?;

    let selection = select(&task, &|| {})?;
    let arm = &selection.arms[0];
    println!(
        "{}: {} of {} candidates feasible along {} samples",
        task.source_name(),
        arm.feasible_count(),
        arm.scores.len(),
        task.path().samples.len()
    );
    let mut ranked: Vec<_> = arm
        .scores
        .iter()
        .zip(&arm.rankings)
        .filter(|(_, r)| r.rank.is_some())
        .collect();
    ranked.sort_by_key(|(_, r)| r.rank);
    println!("rank  candidate        mu_l2     mu_linf");
    for (score, ranking) in ranked.iter().take(5) {
        let norms = score.norms.expect("ranked candidates have norms");
        println!(
            "{:>4}  {:<14} {:>8.4} {:>10.4}",
            ranking.rank.unwrap_or(0),
            score.candidate.label,
            norms.l2,
            norms.linf
        );
    }
    for score in arm.scores.iter().filter(|s| !s.feasible()).take(3) {
        if let Some(failure) = &score.failure {
            println!("{}: {failure}", score.candidate.label);
        }
    }
    Ok(())
}
