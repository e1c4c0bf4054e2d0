//! Tracking branches sample by sample from their initial solutions: one branch alone
//! ([`Tracker::track`]) or the branches of a whole batch four at a time, one per vector lane
//! ([`track_in_lanes`]), with the same results bit for bit. A sample that the warm-started
//! solve does not settle goes to the recovery ladder ([`Tracker::resolve`]).

use super::result::JointPath;
use super::tracker::{max_difference, Tracker};
use crate::failure::Failure;
use crate::robot::chain::MAX_JOINTS;
use crate::robot::ik::kernel::{Budget, Patience, RunEnd, Strategy, Target, Workspace};
use crate::robot::ik::lanes::Lanes;

impl Tracker<'_> {
    /// Follows the trajectory from `start` (a solution at sample 0).
    pub(super) fn track(&self, branch: usize, start: &[f64]) -> Result<JointPath, Failure> {
        let n = self.n();
        let kernel = &self.kernel;
        let step = self.options.max_joint_step;
        let per_sample = self.options.per_sample_iterations;
        let mut path = Vec::with_capacity(self.poses.len());
        path.push(start.to_vec());
        let mut ws = Workspace::new();
        ws.cur_mut().q[..n].copy_from_slice(start);
        kernel.evaluate(&Target::new(&self.poses[0]), ws.cur_mut());
        let mut previous = [0.0f64; MAX_JOINTS];
        for i in 1..self.poses.len() {
            previous[..n].copy_from_slice(&ws.cur().q[..n]);
            let target = Target::new(&self.poses[i]);
            // The warm start: the previous solution's pose and Jacobian are already known.
            kernel.retarget(&target, ws.cur_mut());
            let mut budget = Budget::new(per_sample, None);
            let end = kernel.run(
                &target,
                &mut ws,
                Strategy::Clamped,
                per_sample,
                Patience::TRACKING,
                &mut budget,
            );
            let accepted = end == RunEnd::Converged
                && max_difference(&ws.cur().q[..n], &previous[..n]) <= step;
            if !accepted {
                self.resolve(branch, i, &previous[..n], &target, &mut ws)?;
            }
            path.push(ws.cur().q[..n].to_vec());
        }
        Ok(JointPath { q: path })
    }
}

/// One branch to track: its trajectory's tracker, its number, its start (rad / m).
pub(super) struct Job<'t> {
    pub(super) tracker: &'t Tracker<'t>,
    pub(super) branch: usize,
    pub(super) start: &'t [f64],
}

impl<'t> Job<'t> {
    /// One job per branch of `tracker`'s trajectory, branch `b` from `starts[b]`.
    pub(super) fn branches(
        tracker: &'t Tracker<'t>,
        starts: &'t [Vec<f64>],
    ) -> impl Iterator<Item = Job<'t>> + 't {
        starts.iter().enumerate().map(move |(branch, start)| Job {
            tracker,
            branch,
            start,
        })
    }
}

/// [`Tracker::track`] of every job, four at a time in vector lanes: each lane goes on from one
/// sample to the next as `track` does, and a sample its lane does not settle is resolved
/// alone ([`Tracker::resolve`]), the lane going on from the state found; a lane whose branch
/// ends takes the next job. Bit-identical to `track`, job by job. Every job's tracker has the
/// same kernel and options.
pub(super) fn track_in_lanes(jobs: &[Job<'_>]) -> Vec<Result<JointPath, Failure>> {
    let Some(first_job) = jobs.first() else {
        return Vec::new();
    };
    let kernel = &first_job.tracker.kernel;
    let n = kernel.dof();
    let step = first_job.tracker.options.max_joint_step;
    let per_sample = first_job.tracker.options.per_sample_iterations;
    let mut outcomes: Vec<Option<Result<JointPath, Failure>>> = vec![None; jobs.len()];
    // Each started job's path so far; the sample its lane works on comes next.
    let mut paths: Vec<Vec<Vec<f64>>> = vec![Vec::new(); jobs.len()];
    // The lane each started job runs in, all along.
    let mut job_lane = vec![0; jobs.len()];
    let mut ws = Workspace::new();
    // Every run is resumed towards its own target; the lanes' shared one is never used.
    let mut lanes = Lanes::new(
        *kernel,
        Target::new(&first_job.tracker.poses[0]),
        Patience::TRACKING,
    );
    let mut ended = Vec::with_capacity(4);
    let mut started = 0;
    loop {
        while started < jobs.len() {
            let Some(lane) = lanes.free_lane() else { break };
            let k = started;
            started += 1;
            let job = &jobs[k];
            let poses = job.tracker.poses;
            ws.cur_mut().q[..n].copy_from_slice(job.start);
            kernel.evaluate(&Target::new(&poses[0]), ws.cur_mut());
            paths[k] = Vec::with_capacity(poses.len());
            paths[k].push(job.start.to_vec());
            if poses.len() == 1 {
                outcomes[k] = Some(Ok(JointPath {
                    q: std::mem::take(&mut paths[k]),
                }));
                continue;
            }
            job_lane[k] = lane;
            lanes.load(lane, ws.cur());
            lanes.resume(lane, k, Target::new(&poses[1]), per_sample);
        }
        if !lanes.busy() {
            break;
        }
        lanes.advance(&mut ended);
        for (k, end) in ended.drain(..) {
            let job = &jobs[k];
            let poses = job.tracker.poses;
            let lane = job_lane[k];
            let i = paths[k].len();
            let previous = paths[k].last().expect("a path starts with its start");
            let q = if end.end == RunEnd::Converged && max_difference(&end.q, previous) <= step {
                end.q
            } else {
                let target = Target::new(&poses[i]);
                if let Err(failure) = job
                    .tracker
                    .resolve(job.branch, i, previous, &target, &mut ws)
                {
                    outcomes[k] = Some(Err(failure));
                    continue;
                }
                lanes.load(lane, ws.cur());
                ws.cur().q[..n].to_vec()
            };
            paths[k].push(q);
            if i + 1 == poses.len() {
                outcomes[k] = Some(Ok(JointPath {
                    q: std::mem::take(&mut paths[k]),
                }));
            } else {
                lanes.resume(lane, k, Target::new(&poses[i + 1]), per_sample);
            }
        }
    }
    outcomes
        .into_iter()
        .map(|outcome| outcome.expect("every job is tracked to its end"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::builtin::{baxter, Arm, BuiltinRobot};
    use crate::robot::chain::Chain;
    use crate::robot::ik::kernel::Kernel;
    use crate::robot::ik::trajectory::options::TrajectoryIkOptions;
    use nalgebra::Isometry3;
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};

    /// Poses of a random joint-space path of `samples` samples from a random configuration,
    /// moving `speed` rad per sample in each joint at most; with `jump`, one sample in the
    /// middle jumps far (a resolve, a discontinuity or a limit), and with `away`, the last
    /// samples are pushed out of reach.
    fn random_path(
        chain: &Chain,
        rng: &mut Xoshiro256PlusPlus,
        samples: usize,
        speed: f64,
        jump: bool,
        away: bool,
    ) -> Vec<Isometry3<f64>> {
        let kernel = Kernel::new(chain, 1e-5, 1e-5);
        let n = chain.dof();
        let mut q = vec![0.0; n];
        kernel.random_configuration(rng, &mut q);
        let velocity: Vec<f64> = (0..n)
            .map(|_| speed * rng.random_range(-1.0..=1.0))
            .collect();
        (0..samples)
            .map(|i| {
                let mut at: Vec<f64> = q
                    .iter()
                    .zip(&velocity)
                    .map(|(q, v)| q + v * i as f64)
                    .collect();
                if jump && i >= samples / 2 {
                    at[n / 2] += 1.2;
                }
                let mut pose: Isometry3<f64> =
                    nalgebra::convert(chain.pose(&at).expect("finite configuration"));
                if away && i + 3 >= samples {
                    pose.translation.vector.z += 2.5;
                }
                pose
            })
            .collect()
    }

    /// The outcome of a branch as text: every number printed to its last bit.
    fn exact(outcome: &Result<JointPath, Failure>) -> String {
        format!("{outcome:?}")
    }

    /// Branches tracked four at a time in the lanes follow the same paths and fail at the same
    /// samples for the same reasons, bit for bit, as each tracked alone: several trajectories'
    /// branches mixed in one batch, lanes refilled as branches end, samples resolved alone
    /// (large jumps, samples out of reach), on an arm without and one with joint limits that
    /// bind often.
    #[test]
    fn branches_tracked_in_lanes_are_tracked_alone_bit_for_bit() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(21);
        let panda = BuiltinRobot::Panda.chain_specs().remove(0);
        let panda = Chain::from_spec(&panda).expect("the built-in Panda");
        for chain in [baxter(Arm::Left), panda] {
            let options = TrajectoryIkOptions {
                branches: 3,
                ..TrajectoryIkOptions::default()
            };
            let kernel = Kernel::new(&chain, 1e-5, 1e-5);
            let q_start = chain.mid_configuration();
            for case in 0..12 {
                let trajectories: Vec<Vec<Isometry3<f64>>> = (0..rng.random_range(1..6))
                    .map(|_| {
                        let samples = rng.random_range(1..25);
                        // Some held still: a lane resumed already within tolerance.
                        let speed = if rng.random_range(0..5) == 0 {
                            0.0
                        } else {
                            rng.random_range(0.005..0.12)
                        };
                        let jump = rng.random_range(0..3) == 0;
                        let away = rng.random_range(0..4) == 0;
                        random_path(&chain, &mut rng, samples, speed, jump, away)
                    })
                    .collect();
                let trackers: Vec<Tracker<'_>> = trajectories
                    .iter()
                    .map(|poses| Tracker {
                        kernel,
                        poses,
                        options: &options,
                    })
                    .collect();
                let starts: Vec<Vec<Vec<f64>>> = trackers
                    .iter()
                    .map(|t| t.initial_solutions(&q_start).unwrap_or_default())
                    .collect();
                let jobs: Vec<Job<'_>> = trackers
                    .iter()
                    .zip(&starts)
                    .flat_map(|(tracker, starts)| Job::branches(tracker, starts))
                    .collect();
                let in_lanes = track_in_lanes(&jobs);
                assert_eq!(in_lanes.len(), jobs.len());
                for (k, job) in jobs.iter().enumerate() {
                    let alone = job.tracker.track(job.branch, job.start);
                    assert_eq!(exact(&in_lanes[k]), exact(&alone), "case {case}, job {k}");
                }
            }
        }
    }
}
