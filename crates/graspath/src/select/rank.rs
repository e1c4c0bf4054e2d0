//! Ranking: the paper's rule (maximise the norm subject to `μ_l∞ ≤ μ0`) combined with the grasp
//! likelihood, the Pareto front of (likelihood, norm), and dual-arm pairs.

use super::score::CandidateScore;
use crate::grasp::Candidate;
use crate::task::{LikelihoodRule, Norm, SelectionOptions};
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

fn norm_value(score: &CandidateScore, norm: Norm) -> Option<f64> {
    score.norms.map(|n| match norm {
        Norm::L2 => n.l2,
        Norm::L1 => n.l1,
    })
}

/// Why a feasible candidate fails the constraint, if it does.
fn constraint_violation(score: &CandidateScore, options: &SelectionOptions) -> Option<String> {
    let norms = score.norms?;
    if !norms.linf.is_finite() {
        return Some("singular along the path (mu_linf is infinite)".into());
    }
    if norms.evaluated == 0 {
        return Some("the object never moves: no sample to evaluate".into());
    }
    if let (Some(min), Some(clearance)) = (options.min_clearance, score.clearance) {
        if clearance < min {
            return Some(format!(
                "clearance {clearance:.4} m is below min_clearance = {min} m"
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

/// Ranks one arm's candidates. Ties are broken by candidate order, so the ranking is
/// deterministic.
pub fn rank_candidates(scores: &[CandidateScore], options: &SelectionOptions) -> Vec<Ranking> {
    let max_log = scores
        .iter()
        .map(|s| s.candidate.log_likelihood)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut rankings: Vec<Ranking> = scores
        .iter()
        .map(|s| {
            let rejected = if s.feasible() {
                constraint_violation(s, options)
            } else {
                None
            };
            let score = (s.feasible() && rejected.is_none())
                .then(|| norm_value(s, options.norm))
                .flatten()
                .map(|norm| {
                    let relative_log = s.candidate.log_likelihood - max_log;
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
        })
        .collect();
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
    // Pareto front of (log-likelihood, norm) among the eligible.
    for &i in &order {
        let li = scores[i].candidate.log_likelihood;
        let ni = norm_value(&scores[i], options.norm).unwrap_or(0.0);
        let dominated = order.iter().any(|&j| {
            let lj = scores[j].candidate.log_likelihood;
            let nj = norm_value(&scores[j], options.norm).unwrap_or(0.0);
            lj >= li && nj >= ni && (lj > li || nj > ni)
        });
        rankings[i].pareto = !dominated;
    }
    rankings
}

/// A pair of grasps, one per arm.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmPair {
    /// The first arm's candidate.
    pub first: Arc<Candidate>,
    /// The second arm's candidate.
    pub second: Arc<Candidate>,
    /// The sum of the two arms' norms.
    pub score: f64,
    /// 1-based rank.
    pub rank: usize,
}

/// Every pair of eligible candidates of two arms whose grasps do not overlap (closer than
/// `min_separation`), scored by the sum of the arms' norms; the best `options.pairs`, best
/// first, among those `compatible` accepts (visited best first, so the check runs only until
/// enough pairs are kept). Returns the pairs and how many better pairs `compatible` refused.
pub fn rank_pairs(
    first: (&[CandidateScore], &[Ranking]),
    second: (&[CandidateScore], &[Ranking]),
    options: &SelectionOptions,
    compatible: &(dyn Fn(&CandidateScore, &CandidateScore) -> bool + Sync),
) -> (Vec<ArmPair>, usize) {
    let eligible = |scores: &[CandidateScore], ranks: &[Ranking]| -> Vec<(usize, f64)> {
        scores
            .iter()
            .zip(ranks)
            .enumerate()
            .filter(|(_, (_, r))| r.score.is_some())
            .filter_map(|(i, (s, _))| norm_value(s, options.norm).map(|n| (i, n)))
            .collect()
    };
    let a = eligible(first.0, first.1);
    let b = eligible(second.0, second.1);
    // (first index, second index, score): ordered by score, then by candidate order.
    let mut pairs: Vec<(usize, usize, f64)> = Vec::new();
    for &(i, ni) in &a {
        let pi = first.0[i].candidate.grasp_point();
        for &(j, nj) in &b {
            let pj = second.0[j].candidate.grasp_point();
            if (pi - pj).norm() < options.min_separation {
                continue;
            }
            pairs.push((i, j, ni + nj));
        }
    }
    pairs.sort_by(|x, y| y.2.total_cmp(&x.2).then((x.0, x.1).cmp(&(y.0, y.1))));
    let mut refused = 0;
    let mut kept = Vec::new();
    for (i, j, score) in pairs {
        if kept.len() == options.pairs {
            break;
        }
        if !compatible(&first.0[i], &second.0[j]) {
            refused += 1;
            continue;
        }
        kept.push(ArmPair {
            first: Arc::clone(&first.0[i].candidate),
            second: Arc::clone(&second.0[j].candidate),
            score,
            rank: kept.len() + 1,
        });
    }
    (kept, refused)
}
