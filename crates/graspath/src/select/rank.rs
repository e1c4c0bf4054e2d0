//! Ranking: the paper's rule (maximise the norm subject to `μ_l∞ ≤ μ0`) combined with the grasp
//! likelihood, the Pareto front of (likelihood, norm), and dual-arm pairs.

use super::scalars::Scored;
use super::score::CandidateScore;
use crate::grasp::Candidate;
use crate::task::{LikelihoodRule, SelectionOptions};
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::Arc;

/// A candidate's place in the ranking of one arm.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranking {
    /// 1-based rank among eligible candidates (`None` when not eligible).
    pub rank: Option<usize>,
    /// The combined score (`None` when not eligible).
    pub score: Option<f64>,
    /// Why a feasible candidate is not eligible (the `μ0` constraint, a singular path).
    pub rejected: Option<String>,
    /// On the Pareto front of (likelihood, norm) among eligible candidates.
    pub pareto: bool,
}

/// The value ranked: the chosen norm, or with `by_duration` the task's rate (1 / duration,
/// 1/s).
fn norm_value(score: &impl Scored, options: &SelectionOptions) -> Option<f64> {
    if options.by_duration {
        return score.duration().filter(|d| *d > 0.0).map(|d| 1.0 / d);
    }
    score.norms().map(|n| n.value(options.norm))
}

/// Why a feasible candidate fails the constraint, if it does.
fn constraint_violation(score: &impl Scored, options: &SelectionOptions) -> Option<String> {
    let norms = score.norms()?;
    if !norms.linf.is_finite() {
        return Some("singular along the path (mu_linf is infinite)".into());
    }
    if norms.evaluated == 0 {
        return Some("the object never moves: no sample to evaluate".into());
    }
    if let (Some(min), Some(clearance)) = (options.min_clearance, score.clearance()) {
        if clearance < min {
            return Some(format!(
                "clearance {clearance:.4} m is below min_clearance = {min} m"
            ));
        }
    }
    if let (Some(min), Some(margin)) = (options.min_torque_margin, score.torque_margin()) {
        if margin < min {
            return Some(format!(
                "torque margin {margin:.4} is below min_torque_margin = {min}"
            ));
        }
    }
    if let (Some(max), Some(duration)) = (options.max_duration, score.duration()) {
        if duration > max {
            return Some(format!(
                "the motion takes {duration:.3} s, more than max_duration = {max} s"
            ));
        }
    }
    match options.mu0 {
        Some(mu0) if norms.linf > mu0 => {
            Some(format!("mu_linf = {:.4} exceeds mu0 = {mu0}", norms.linf))
        }
        _ => None,
    }
}

/// The part of a candidate's [`Ranking`] that needs no other candidate: its combined score
/// and why it is rejected (`rank: None`, `pareto: false`). `max_log_likelihood` is the largest
/// `log_likelihood` of the arm's candidates (the likelihood enters the score relative to it).
/// [`rank_candidates`] gives every candidate this score and rejection, then ranks them.
pub fn ranking_alone(
    s: &impl Scored,
    options: &SelectionOptions,
    max_log_likelihood: f64,
) -> Ranking {
    let rejected = if s.feasible() {
        constraint_violation(s, options)
    } else {
        None
    };
    let score = (s.feasible() && rejected.is_none())
        .then(|| norm_value(s, options))
        .flatten()
        .map(|norm| {
            let relative_log = s.log_likelihood() - max_log_likelihood;
            match options.likelihood {
                LikelihoodRule::Product => norm * relative_log.exp(),
                LikelihoodRule::Ignore => norm,
                LikelihoodRule::Weighted { weight } => norm.ln() + weight * relative_log,
            }
        });
    Ranking {
        rank: None,
        score,
        rejected,
        pareto: false,
    }
}

/// Ranks one arm's candidates. Ties are broken by candidate order, so the ranking is
/// deterministic.
pub fn rank_candidates<S: Scored>(scores: &[S], options: &SelectionOptions) -> Vec<Ranking> {
    let max_log = scores
        .iter()
        .map(Scored::log_likelihood)
        .fold(f64::NEG_INFINITY, f64::max);
    rank_against(scores, options, max_log)
}

/// [`rank_candidates`] with the likelihoods relative to `max_log_likelihood` (the largest
/// natural log-likelihood of a whole task, of which `scores` may be a slice): each candidate's
/// [`ranking_alone`], then [`assign_ranks`] — the one ranking order.
pub fn rank_against<S: Scored>(
    scores: &[S],
    options: &SelectionOptions,
    max_log_likelihood: f64,
) -> Vec<Ranking> {
    let mut rankings: Vec<Ranking> = scores
        .iter()
        .map(|s| ranking_alone(s, options, max_log_likelihood))
        .collect();
    assign_ranks(scores, &mut rankings, options);
    rankings
}

/// Completes rankings made by [`ranking_alone`] (`rankings[i]` of `scores[i]`, every one with
/// the same largest log-likelihood): the 1-based `rank` of each candidate that has a score,
/// best first (ties by candidate order), and the `pareto` flag. [`rank_candidates`] is
/// `ranking_alone` of every candidate, then this.
pub fn assign_ranks<S: Scored>(scores: &[S], rankings: &mut [Ranking], options: &SelectionOptions) {
    let mut order: Vec<usize> = (0..rankings.len())
        .filter(|&i| rankings[i].score.is_some())
        .collect();
    order.sort_by(|&a, &b| {
        rankings[b]
            .score
            .unwrap()
            .total_cmp(&rankings[a].score.unwrap())
            .then(a.cmp(&b))
    });
    for (r, &i) in order.iter().enumerate() {
        rankings[i].rank = Some(r + 1);
    }
    for i in pareto_front(&order, |i| {
        (
            scores[i].log_likelihood(),
            norm_value(&scores[i], options).unwrap_or(0.0),
        )
    }) {
        rankings[i].pareto = true;
    }
}

/// The items of `items` on the Pareto front of `(likelihood, norm)` (both maximised): no
/// other item is at least as good in both and better in one. O(n log n): sorted by likelihood
/// (best first), an item is dominated when an item of strictly greater likelihood has at
/// least its norm, or one of equal likelihood a greater norm.
fn pareto_front(items: &[usize], value: impl Fn(usize) -> (f64, f64)) -> Vec<usize> {
    let mut sorted: Vec<(f64, f64, usize)> = items
        .iter()
        .map(|&i| {
            let (l, n) = value(i);
            (l, n, i)
        })
        .collect();
    sorted.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.total_cmp(&a.1)));
    let mut front = Vec::new();
    let mut best_above = f64::NEG_INFINITY;
    let mut start = 0;
    while start < sorted.len() {
        let l = sorted[start].0;
        let end = start + sorted[start..].iter().take_while(|x| x.0 == l).count();
        // Sorted by norm within the group: its first has the group's largest norm.
        let group_best = sorted[start].1;
        for &(_, n, i) in &sorted[start..end] {
            if n == group_best && n > best_above {
                front.push(i);
            }
        }
        best_above = best_above.max(group_best);
        start = end;
    }
    front.sort_unstable();
    front
}

/// Whether two ranking scores are tied: they differ by at most `options.tie_tolerance` relative
/// to the larger magnitude (`|a − b| ≤ t · max(|a|, |b|)`), or, for the weighted likelihood
/// rule whose score is `ln(norm) + …`, by at most `t` absolutely (a difference of logarithms
/// is already relative). Symmetric in `a` and `b`; equal scores are always tied.
pub fn scores_tied(a: f64, b: f64, options: &SelectionOptions) -> bool {
    let t = options.tie_tolerance;
    a == b
        || match options.likelihood {
            LikelihoodRule::Weighted { .. } => (a - b).abs() <= t,
            _ => values_tied(a, b, t),
        }
}

/// `|a − b| ≤ tolerance · max(|a|, |b|)`: the relative tie of two sums of norms (pairs).
pub fn values_tied(a: f64, b: f64, tolerance: f64) -> bool {
    a == b || (a - b).abs() <= tolerance * a.abs().max(b.abs())
}

/// The ids of the other eligible candidates whose score is tied with candidate `i`'s (see
/// [`scores_tied`]), in increasing id order; empty when `i` is not eligible. The relation
/// depends only on the two scores, so the answer is symmetric (`j` is tied with `i` exactly
/// when `i` is tied with `j`) and the same in any candidate order. O(n).
pub fn tied_with<S: Scored>(
    scores: &[S],
    rankings: &[Ranking],
    i: usize,
    options: &SelectionOptions,
) -> Vec<usize> {
    let Some(own) = rankings.get(i).and_then(|r| r.score) else {
        return Vec::new();
    };
    let mut ids: Vec<usize> = scores
        .iter()
        .zip(rankings)
        .enumerate()
        .filter(|&(j, (_, r))| j != i && r.score.is_some_and(|v| scores_tied(own, v, options)))
        .map(|(_, (s, _))| s.id())
        .collect();
    ids.sort_unstable();
    ids
}

/// A pair of grasps, one per arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmPair {
    /// The first arm's candidate.
    pub first: Arc<Candidate>,
    /// The second arm's candidate.
    pub second: Arc<Candidate>,
    /// The pair's score ([`PairScore`]): the sum of the two arms' norms, or with
    /// `index.measure: duration` the slower arm's rate (1/s).
    pub score: f64,
    /// 1-based rank.
    pub rank: usize,
}

/// The best `options.pairs` pairs of eligible candidates of two arms, scored by the sum of the
/// arms' norms (the slower arm's rate when ranked by duration, [`PairScore`]), best first (ties: the earlier first-arm candidate, then the earlier second-arm
/// one), among those whose grasps do not overlap (closer than `min_separation`) and that
/// `compatible` accepts. Returns the pairs and how many better pairs `compatible` refused.
/// [`best_pairs`] on the full scores, with each pair's candidates.
pub fn rank_pairs(
    first: (&[CandidateScore], &[Ranking]),
    second: (&[CandidateScore], &[Ranking]),
    options: &SelectionOptions,
    compatible: &(dyn Fn(&CandidateScore, &CandidateScore) -> bool + Sync),
) -> (Vec<ArmPair>, usize) {
    let compatible = |i: usize, j: usize| compatible(&first.0[i], &second.0[j]);
    let (best, refused) = best_pairs(first, second, options, &compatible);
    let pairs = best
        .into_iter()
        .enumerate()
        .map(|(k, (i, j, score))| ArmPair {
            first: Arc::clone(&first.0[i].candidate),
            second: Arc::clone(&second.0[j].candidate),
            score,
            rank: k + 1,
        })
        .collect();
    (pairs, refused)
}

/// The pairs of [`rank_pairs`] as `(first-arm index, second-arm index, score)`, best first,
/// and how many better pairs `compatible` (given the two indices) refused: [`best_pairs_of`]
/// over the eligible candidates of `first` and `second`, with `options.pairs` and
/// `options.min_separation`.
pub fn best_pairs<S: Scored>(
    first: (&[S], &[Ranking]),
    second: (&[S], &[Ranking]),
    options: &SelectionOptions,
    compatible: &(dyn Fn(usize, usize) -> bool + Sync),
) -> (Vec<PositionPair>, usize) {
    // Each arm's eligible candidates with the norm pairs are scored by.
    let eligible = |scores: &[S], ranks: &[Ranking]| -> Vec<(usize, f64)> {
        scores
            .iter()
            .zip(ranks)
            .enumerate()
            .filter(|(_, (_, r))| r.score.is_some())
            .filter_map(|(i, (s, _))| norm_value(s, options).map(|n| (i, n)))
            .collect()
    };
    best_pairs_of(
        PairArm {
            eligible: eligible(first.0, first.1),
            grasp_point: &|i| first.0[i].grasp_point(),
        },
        PairArm {
            eligible: eligible(second.0, second.1),
            grasp_point: &|j| second.0[j].grasp_point(),
        },
        (options.min_separation, options.pairs),
        PairScore::of_options(options),
        compatible,
    )
}

/// A pair found by [`best_pairs`] or [`best_pairs_of`]: `(first-arm position, second-arm
/// position, score)`, positions in the task's candidates, the score as [`PairScore`] says.
pub type PositionPair = (usize, usize, f64);

/// How a pair's score comes from its two arms' values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairScore {
    /// The sum of the two arms' norms (the paper's two-arm score).
    Sum,
    /// The slower arm's: the smaller of the two rates (1 / duration) when candidates are ranked
    /// by the duration of their motion. Two arms carrying one object share one timeline that
    /// waits for the slower arm; an estimate of the pair's time, since the written motions
    /// time the carry as one path of both arms' joints
    /// ([`timed_together`](crate::select::timed_together)).
    Slower,
}

impl PairScore {
    /// The score of a pair whose arms have the values `a` and `b`.
    pub fn of(self, a: f64, b: f64) -> f64 {
        match self {
            PairScore::Sum => a + b,
            PairScore::Slower => a.min(b),
        }
    }

    /// The pair score of a task ranked with `options`: [`PairScore::Slower`] when it ranks by
    /// the duration, else [`PairScore::Sum`].
    pub fn of_options(options: &SelectionOptions) -> Self {
        if options.by_duration {
            PairScore::Slower
        } else {
            PairScore::Sum
        }
    }
}

/// One arm's side of a pair search ([`best_pairs_of`]).
pub struct PairArm<'a> {
    /// The arm's eligible candidates (ranked: feasible and within the constraints), each as
    /// `(position in the task's candidates, norm)`, the norm being the one the task ranks by
    /// (`μ_l2`, or `μ_l1` with `norm: l1`); in any order, each position once.
    pub eligible: Vec<(usize, f64)>,
    /// The grasp point (object frame, m; see [`Candidate::grasp_point`]) of the candidate at
    /// a position.
    pub grasp_point: &'a dyn Fn(usize) -> nalgebra::Point3<f64>,
}

/// The best `count` pairs of one eligible candidate of each arm, as `(first-arm position,
/// second-arm position, score)` with the score `pair_score` of the two values, best first (ties:
/// with [`PairScore::Sum`] the earlier first-arm candidate, then the earlier second-arm one;
/// with [`PairScore::Slower`] the first-arm candidate with the larger value, then the
/// second-arm one, candidate order among equal values), among the pairs whose
/// grasp points are at least `min_separation` (m) apart and that `compatible` (given the two
/// positions) accepts; and how many better pairs `compatible` refused.
///
/// Best-first over each arm's candidates sorted by norm (both scores grow with each arm's
/// value): a pair is visited only after the pairs that beat it in both arms, so the work grows with the pairs visited, not with the product
/// of the two candidate counts, and `compatible` is asked only about the pairs visited (in
/// parallel, a batch of the next ones at a time: it may be asked about a few pairs after the
/// last one kept). The pairs depend only on the sets given, not on their order, nor on the
/// thread count.
pub fn best_pairs_of(
    first: PairArm<'_>,
    second: PairArm<'_>,
    (min_separation, count): (f64, usize),
    pair_score: PairScore,
    compatible: &(dyn Fn(usize, usize) -> bool + Sync),
) -> (Vec<PositionPair>, usize) {
    // Each arm's eligible candidates, by norm (best first), then candidate order.
    let by_norm = |mut list: Vec<(usize, f64)>| {
        list.sort_by(|x, y| y.1.total_cmp(&x.1).then(x.0.cmp(&y.0)));
        list
    };
    let a = by_norm(first.eligible);
    let b = by_norm(second.eligible);
    let mut kept = Vec::new();
    let mut refused = 0;
    if a.is_empty() || b.is_empty() || count == 0 {
        return (kept, refused);
    }
    // The frontier holds at most one pair per first-arm candidate: popping `(x, y)` queues
    // `(x, y + 1)`, and popping `(x, 0)` also queues `(x + 1, 0)`. Every pair is queued once,
    // after a pair that precedes it, so the pairs come out in order with memory linear in the
    // candidates, not in the pairs visited (a search that finds no valid pair visits them all).
    let mut frontier = BinaryHeap::new();
    let push = |frontier: &mut BinaryHeap<Frontier>, x: usize, y: usize| {
        if x < a.len() && y < b.len() {
            // Ties: by candidate order for sums (rare, and every tied pair is then in the
            // frontier together); by the arms' own order for the slower arm's minimum, whose
            // many ties reach the frontier one after the other along each arm's list.
            let tie = match pair_score {
                PairScore::Sum => (a[x].0, b[y].0),
                PairScore::Slower => (x, y),
            };
            frontier.push(Frontier {
                score: pair_score.of(a[x].1, b[y].1),
                tie,
                first: a[x].0,
                second: b[y].0,
                at: (x, y),
            });
        }
    };
    push(&mut frontier, 0, 0);
    // The pairs come out of the frontier in the same order whatever `compatible` answers, so
    // the next ones are asked about together, in parallel, and their answers taken in order:
    // as many as pairs are still wanted (at least one per thread), twice as many after a
    // batch with a refusal. Pairs asked about after the last kept one change nothing.
    let threads = rayon::current_num_threads();
    let mut growth = 1;
    while kept.len() < count {
        let wanted = (count - kept.len()).max(threads).saturating_mul(growth);
        let mut batch = Vec::with_capacity(wanted.min(MAX_PAIR_BATCH));
        while batch.len() < wanted.min(MAX_PAIR_BATCH) {
            let Some(next) = frontier.pop() else {
                break;
            };
            let (x, y) = next.at;
            if y == 0 {
                push(&mut frontier, x + 1, 0);
            }
            push(&mut frontier, x, y + 1);
            let (pi, pj) = (
                (first.grasp_point)(next.first),
                (second.grasp_point)(next.second),
            );
            if (pi - pj).norm() >= min_separation {
                batch.push(next);
            }
        }
        if batch.is_empty() {
            break;
        }
        let answers: Vec<bool> = batch
            .par_iter()
            .map(|pair| compatible(pair.first, pair.second))
            .collect();
        let refused_before = refused;
        for (pair, compatible) in batch.iter().zip(answers) {
            if !compatible {
                refused += 1;
                continue;
            }
            kept.push((pair.first, pair.second, pair.score));
            if kept.len() == count {
                break;
            }
        }
        if refused > refused_before {
            growth = (growth * 2).min(MAX_PAIR_BATCH);
        }
    }
    (kept, refused)
}

/// The most pairs [`best_pairs_of`] asks `compatible` about at once.
const MAX_PAIR_BATCH: usize = 1024;

/// A pair waiting in the best-first search: ordered by score, then by `tie` (the smaller is
/// the greater, so the max-heap yields it first).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Frontier {
    score: f64,
    tie: (usize, usize),
    first: usize,
    second: usize,
    /// Positions in the two sorted lists.
    at: (usize, usize),
}

impl Eq for Frontier {}

impl PartialOrd for Frontier {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Frontier {
    fn cmp(&self, other: &Self) -> Ordering {
        self.score
            .total_cmp(&other.score)
            .then(other.tie.cmp(&self.tie))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grasp::Candidate;
    use crate::manipulability::PathNorms;
    use nalgebra::{Isometry3, Point3};

    fn scored(id: usize, norm: f64, log_likelihood: f64, y: f64) -> CandidateScore {
        CandidateScore {
            norms: Some(PathNorms {
                l2: norm,
                rms: norm,
                linf: 1.0,
                l1: norm,
                evaluated: 1,
                skipped: 0,
            }),
            feasible_branches: 1,
            ..CandidateScore::unscored(Arc::new(Candidate {
                id,
                label: format!("c{id}"),
                object_from_wrist: Isometry3::identity(),
                log_likelihood,
                contact: Some(Point3::new(0.0, y, 0.0)),
                hand_joints: Vec::new(),
                width: None,
            }))
        }
    }

    /// A small generator of norms with many ties (quarter steps), seeded.
    fn arm(n: usize, seed: u64) -> Vec<CandidateScore> {
        (0..n)
            .map(|i| {
                let r = crate::random::derive_seed(seed, 1, i as u64);
                let norm = 1.0 + (r % 8) as f64 * 0.25;
                let log = -(((r >> 8) % 5) as f64);
                scored(i, norm, log, ((r >> 16) % 50) as f64 * 0.01)
            })
            .collect()
    }

    /// The oracle's last step: the first `count` pairs of `sorted` (every pair, best first)
    /// that `compatible` accepts, and how many it refused before the last one kept.
    fn taken_in_order(
        sorted: Vec<(usize, usize, f64)>,
        count: usize,
        compatible: impl Fn(usize, usize) -> bool,
    ) -> (Vec<(usize, usize, f64)>, usize) {
        let (mut kept, mut refused) = (Vec::new(), 0);
        for (i, j, score) in sorted {
            if kept.len() == count {
                break;
            }
            if compatible(i, j) {
                kept.push((i, j, score));
            } else {
                refused += 1;
            }
        }
        (kept, refused)
    }

    #[test]
    fn best_first_pairs_equal_sorting_every_pair() {
        // Oracle: every pair materialised, filtered and sorted by (score desc, first, second).
        for seed in 0..20 {
            let (sa, sb) = (arm(17, seed), arm(23, seed + 100));
            let options = SelectionOptions {
                pairs: 12,
                min_separation: 0.1,
                ..SelectionOptions::default()
            };
            let (ra, rb) = (
                rank_candidates(&sa, &options),
                rank_candidates(&sb, &options),
            );
            // Refuse pairs whose ids sum to a multiple of 5.
            let compatible = |x: &CandidateScore, y: &CandidateScore| {
                !(x.candidate.id + y.candidate.id).is_multiple_of(5)
            };
            let (pairs, refused) = rank_pairs((&sa, &ra), (&sb, &rb), &options, &compatible);
            let mut all = Vec::new();
            for (i, x) in sa.iter().enumerate() {
                for (j, y) in sb.iter().enumerate() {
                    let d = (x.candidate.grasp_point() - y.candidate.grasp_point()).norm();
                    if d >= options.min_separation {
                        all.push((i, j, x.norms.unwrap().l2 + y.norms.unwrap().l2));
                    }
                }
            }
            all.sort_by(|p, q| q.2.total_cmp(&p.2).then((p.0, p.1).cmp(&(q.0, q.1))));
            let (expected, expected_refused) =
                taken_in_order(all, options.pairs, |i, j| !(i + j).is_multiple_of(5));
            let got: Vec<(usize, usize, f64)> = pairs
                .iter()
                .map(|p| (p.first.id, p.second.id, p.score))
                .collect();
            assert_eq!(got, expected, "seed {seed}");
            assert_eq!(refused, expected_refused, "seed {seed}");
        }
    }

    #[test]
    fn the_slower_arm_s_pairs_equal_sorting_every_pair() {
        // Oracle: every pair materialised and sorted by (min of the two values desc, the first
        // arm's order, the second arm's order), each arm's order by value then candidate.
        for seed in 0..20 {
            let values = |n: usize, stream: u64| -> Vec<(usize, f64)> {
                (0..n)
                    .map(|i| {
                        let r = crate::random::derive_seed(seed, stream, i as u64);
                        (i, 0.2 + (r % 7) as f64 * 0.05)
                    })
                    .collect()
            };
            let (a, b) = (values(13, 1), values(9, 2));
            let point = |i: usize| Point3::new(0.0, (i % 4) as f64 * 0.05, 0.0);
            let compatible = |i: usize, j: usize| !(i + j).is_multiple_of(4);
            let (got, refused) = best_pairs_of(
                PairArm {
                    eligible: a.clone(),
                    grasp_point: &point,
                },
                PairArm {
                    eligible: b.clone(),
                    grasp_point: &point,
                },
                (0.04, 10),
                PairScore::Slower,
                &compatible,
            );
            // Each arm's order: larger value first, then candidate order.
            let order = |list: &[(usize, f64)], i: usize| {
                list.iter()
                    .filter(|(k, v)| *v > list[i].1 || (*v == list[i].1 && *k < i))
                    .count()
            };
            let mut all = Vec::new();
            for &(i, x) in &a {
                for &(j, y) in &b {
                    if (point(i) - point(j)).norm() >= 0.04 {
                        all.push((i, j, x.min(y)));
                    }
                }
            }
            all.sort_by(|p, q| {
                q.2.total_cmp(&p.2)
                    .then((order(&a, p.0), order(&b, p.1)).cmp(&(order(&a, q.0), order(&b, q.1))))
            });
            let (expected, expected_refused) = taken_in_order(all, 10, compatible);
            assert_eq!(got, expected, "seed {seed}");
            assert_eq!(refused, expected_refused, "seed {seed}");
        }
    }

    #[test]
    fn pairs_checked_in_parallel_are_the_sequential_ones_at_any_thread_count() {
        // Oracle: every pair materialised, sorted by (sum desc, first, second) and taken in
        // order; most pairs are refused, so the batches grow and end past the last kept pair.
        for seed in 0..10 {
            let values = |n: usize, stream: u64| -> Vec<(usize, f64)> {
                (0..n)
                    .map(|i| {
                        let r = crate::random::derive_seed(seed, stream, i as u64);
                        (i, 0.5 + (r % 6) as f64 * 0.125)
                    })
                    .collect()
            };
            let (a, b) = (values(40, 3), values(31, 4));
            let point = |i: usize| Point3::new((i % 3) as f64 * 0.05, 0.0, 0.0);
            let compatible = |i: usize, j: usize| (i * 31 + j).is_multiple_of(7);
            let mut all = Vec::new();
            for &(i, x) in &a {
                for &(j, y) in &b {
                    if (point(i) - point(j)).norm() >= 0.04 {
                        all.push((i, j, x + y));
                    }
                }
            }
            all.sort_by(|p, q| q.2.total_cmp(&p.2).then((p.0, p.1).cmp(&(q.0, q.1))));
            let (expected, expected_refused) = taken_in_order(all, 15, compatible);
            for threads in [1, 2, 5] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (got, refused) = pool.install(|| {
                    best_pairs_of(
                        PairArm {
                            eligible: a.clone(),
                            grasp_point: &point,
                        },
                        PairArm {
                            eligible: b.clone(),
                            grasp_point: &point,
                        },
                        (0.04, 15),
                        PairScore::Sum,
                        &compatible,
                    )
                });
                assert_eq!(got, expected, "seed {seed}, {threads} threads");
                assert_eq!(refused, expected_refused, "seed {seed}, {threads} threads");
            }
        }
    }

    #[test]
    fn the_pareto_front_equals_the_pairwise_definition() {
        for seed in 0..20 {
            let scores = arm(40, seed);
            let options = SelectionOptions::default();
            let rankings = rank_candidates(&scores, &options);
            for (i, r) in rankings.iter().enumerate() {
                let (li, ni) = (
                    scores[i].candidate.log_likelihood,
                    scores[i].norms.unwrap().l2,
                );
                let dominated = scores.iter().any(|s| {
                    let (lj, nj) = (s.candidate.log_likelihood, s.norms.unwrap().l2);
                    lj >= li && nj >= ni && (lj > li || nj > ni)
                });
                assert_eq!(r.pareto, !dominated, "seed {seed} candidate {i}");
            }
        }
    }

    /// Candidates whose norms are `base · (1 + k · step)`: closed-form tie groups.
    fn spaced(factors: &[f64]) -> Vec<CandidateScore> {
        factors
            .iter()
            .enumerate()
            .map(|(i, &f)| scored(i, 2.0 * f, 0.0, i as f64))
            .collect()
    }

    #[test]
    fn ties_follow_the_relative_tolerance_in_closed_form() {
        // t = 1e-4: 1 and 1 + 0.5e-4 differ by 5e-5 relative (tied); 1 + 2e-4 is 2e-4 from 1
        // and 1.5e-4 from 1 + 0.5e-4 (not tied); 1 + 2.9e-4 is 0.9e-4 from 1 + 2e-4 (tied).
        let scores = spaced(&[1.0, 1.0 + 0.5e-4, 1.0 + 2e-4, 1.0 + 2.9e-4, 1.5]);
        let options = SelectionOptions {
            likelihood: LikelihoodRule::Ignore,
            ..SelectionOptions::default()
        };
        let rankings = rank_candidates(&scores, &options);
        let ties: Vec<Vec<usize>> = (0..scores.len())
            .map(|i| tied_with(&scores, &rankings, i, &options))
            .collect();
        assert_eq!(ties, vec![vec![1], vec![0], vec![3], vec![2], vec![]]);
        // Tolerance zero: only equal scores tie.
        let exact = SelectionOptions {
            tie_tolerance: 0.0,
            ..options
        };
        let equal = spaced(&[1.0, 1.0, 1.0 + 1e-12]);
        let r = rank_candidates(&equal, &exact);
        assert_eq!(tied_with(&equal, &r, 0, &exact), vec![1]);
        assert_eq!(tied_with(&equal, &r, 2, &exact), Vec::<usize>::new());
        // The weighted rule's score is ln(norm): a relative norm difference d is a log
        // difference ln(1 + d).
        let weighted = SelectionOptions {
            likelihood: LikelihoodRule::Weighted { weight: 1.0 },
            ..SelectionOptions::default()
        };
        let r = rank_candidates(&scores, &weighted);
        assert_eq!(tied_with(&scores, &r, 0, &weighted), vec![1]);
        assert_eq!(tied_with(&scores, &r, 2, &weighted), vec![3]);
    }

    #[test]
    fn ties_are_symmetric_and_the_same_in_any_candidate_order() {
        for seed in 0..20 {
            // Norms on a grid of 3e-5 steps: many ties and many near misses.
            let scores: Vec<CandidateScore> = (0..40)
                .map(|i| {
                    let r = crate::random::derive_seed(seed, 7, i as u64);
                    scored(i, 1.0 + (r % 12) as f64 * 3e-5, 0.0, i as f64)
                })
                .collect();
            let options = SelectionOptions::default();
            let rankings = rank_candidates(&scores, &options);
            let groups = |scores: &[CandidateScore], rankings: &[Ranking]| {
                let mut by_id: Vec<(usize, Vec<usize>)> = (0..scores.len())
                    .map(|i| {
                        (
                            scores[i].candidate.id,
                            tied_with(scores, rankings, i, &options),
                        )
                    })
                    .collect();
                by_id.sort();
                by_id
            };
            let original = groups(&scores, &rankings);
            for (id, tied) in &original {
                for other in tied {
                    let back = &original[*other].1;
                    assert!(
                        back.contains(id),
                        "seed {seed}: {id} ~ {other} not symmetric"
                    );
                }
                // Oracle: the definition, pair by pair, on the norms themselves.
                let own = scores[*id].norms.unwrap().l2;
                let expected: Vec<usize> = scores
                    .iter()
                    .filter(|s| s.candidate.id != *id)
                    .filter(|s| {
                        let v = s.norms.unwrap().l2;
                        (v - own).abs() <= 1e-4 * v.max(own)
                    })
                    .map(|s| s.candidate.id)
                    .collect();
                assert_eq!(tied, &expected, "seed {seed} candidate {id}");
            }
            // Shuffle (seeded Fisher–Yates) and rank again: the same tie sets by id.
            let mut shuffled = scores.clone();
            for k in (1..shuffled.len()).rev() {
                let j = (crate::random::derive_seed(seed, 8, k as u64) % (k as u64 + 1)) as usize;
                shuffled.swap(k, j);
            }
            let shuffled_rankings = rank_candidates(&shuffled, &options);
            assert_eq!(
                groups(&shuffled, &shuffled_rankings),
                original,
                "seed {seed}"
            );
        }
    }
}
