//! What a map keeps of the selection at one placement.

use super::grid::Placement;
use super::FamilyParameter;
use crate::select::{values_tied, ArmResult, Selection};
use crate::task::Task;
use serde::Serialize;

/// The selected candidate of one arm at a placement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BestAtPlacement {
    /// The candidate's id.
    pub id: usize,
    /// Its label.
    pub label: String,
    /// Its ranking score (the norm combined with the likelihood).
    pub score: f64,
    /// Its `μ_l2` (unit of `M_T`).
    pub mu_l2: f64,
    /// The ids of the other eligible candidates whose score is tied with it (the task's
    /// `selection.tie_tolerance`), increasing.
    pub tied_with: Vec<usize>,
    /// Its family parameter, when the candidates come from a family.
    pub parameter: Option<f64>,
}

/// How `μ_l2` varies along the family's parameter over the feasible candidates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trend {
    /// Pearson's correlation of `μ_l2` with the parameter (−1 … 1): its sign says towards
    /// which end of the family the index grows; `None` with fewer than two feasible candidates
    /// or a constant parameter or index.
    pub correlation: Option<f64>,
    /// The parameter of the feasible candidate with the largest `μ_l2` (the earlier candidate
    /// on equal values).
    pub argmax_parameter: Option<f64>,
}

/// One arm at one placement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ArmAtPlacement {
    /// The arm's name.
    pub arm: String,
    /// Candidates feasible along the whole motion.
    pub feasible: usize,
    /// Candidates ranked (feasible and not rejected by the selection rule).
    pub eligible: usize,
    /// The selected candidate, if any.
    pub best: Option<BestAtPlacement>,
    /// The smallest `μ_l2` among the feasible candidates.
    pub mu_l2_min: Option<f64>,
    /// The largest `μ_l2` among the feasible candidates.
    pub mu_l2_max: Option<f64>,
    /// `(max − min) / max` of `μ_l2` among the feasible candidates: how much the choice of
    /// grasp matters here (0: not at all).
    pub spread: Option<f64>,
    /// The trend along the family's parameter (only when the candidates come from a family).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trend: Option<Trend>,
}

/// The best pair of two arms at a placement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairAtPlacement {
    /// The first arm's candidate id.
    pub first: usize,
    /// The second arm's candidate id.
    pub second: usize,
    /// The sum of the two arms' norms.
    pub score: f64,
    /// How many of the other kept pairs are tied with it (the task's tie tolerance).
    pub tied_with: usize,
}

/// The selection at one placement, in brief.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlacementRecord {
    /// Grid indices (x, y, z, yaw).
    pub index: [usize; 4],
    /// World x of the object's start (m).
    pub x: f64,
    /// World y of the object's start (m).
    pub y: f64,
    /// World z of the object's start (m).
    pub z: f64,
    /// The extra yaw about the world vertical (degrees).
    pub yaw_deg: f64,
    /// Per arm, in the task's order.
    pub arms: Vec<ArmAtPlacement>,
    /// With two arms: the best pair, if any.
    pub best_pair: Option<PairAtPlacement>,
    /// Nothing selected: no eligible candidate (one arm) or no valid pair (two arms).
    pub nothing_selected: bool,
}

impl PlacementRecord {
    /// The record of `selection`, the result of `task` whose object starts at `placement`;
    /// `parameter` gives the trends.
    pub fn from_selection(
        task: &Task,
        selection: &Selection,
        placement: &Placement,
        parameter: Option<&FamilyParameter>,
    ) -> Self {
        let arms: Vec<ArmAtPlacement> = selection
            .arms
            .iter()
            .map(|arm| arm_record(task, arm, parameter))
            .collect();
        let best_pair = selection.pairs.first().map(|best| PairAtPlacement {
            first: best.first.id,
            second: best.second.id,
            score: best.score,
            tied_with: selection.pairs[1..]
                .iter()
                .filter(|p| values_tied(best.score, p.score, task.selection.tie_tolerance))
                .count(),
        });
        let nothing_selected = if selection.arms.len() == 2 {
            selection.pairs.is_empty()
        } else {
            selection.arms.iter().all(|a| a.best().is_none())
        };
        let t = placement.world_from_object.translation.vector;
        Self {
            index: placement.index,
            x: t.x,
            y: t.y,
            z: t.z,
            yaw_deg: placement.yaw.to_degrees(),
            arms,
            best_pair,
            nothing_selected,
        }
    }
}

fn arm_record(task: &Task, arm: &ArmResult, parameter: Option<&FamilyParameter>) -> ArmAtPlacement {
    let parameter = parameter.filter(|p| p.values.len() == arm.scores.len());
    // (candidate index, μ_l2) of the feasible candidates, in candidate order.
    let feasible: Vec<(usize, f64)> = arm
        .scores
        .iter()
        .enumerate()
        .filter(|(_, s)| s.feasible())
        .filter_map(|(i, s)| s.norms.map(|n| (i, n.l2)))
        .collect();
    let min = feasible.iter().map(|f| f.1).reduce(f64::min);
    let max = feasible.iter().map(|f| f.1).reduce(f64::max);
    let spread = match (min, max) {
        (Some(lo), Some(hi)) if hi > 0.0 => Some((hi - lo) / hi),
        _ => None,
    };
    let best = arm.best().map(|i| {
        let s = &arm.scores[i];
        BestAtPlacement {
            id: s.candidate.id,
            label: s.candidate.label.clone(),
            score: arm.rankings[i].score.unwrap_or(f64::NAN),
            mu_l2: s.norms.map_or(f64::NAN, |n| n.l2),
            tied_with: arm.tied_with(i, &task.selection),
            parameter: parameter.map(|p| p.values[i]),
        }
    });
    let trend = parameter.map(|p| {
        let points: Vec<(f64, f64)> = feasible.iter().map(|&(i, m)| (p.values[i], m)).collect();
        Trend {
            correlation: pearson(&points),
            argmax_parameter: feasible
                .iter()
                .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
                .map(|&(i, _)| p.values[i]),
        }
    });
    ArmAtPlacement {
        arm: arm.arm.clone(),
        feasible: arm.feasible_count(),
        eligible: arm.rankings.iter().filter(|r| r.rank.is_some()).count(),
        best,
        mu_l2_min: min,
        mu_l2_max: max,
        spread,
        trend,
    }
}

/// Pearson's correlation of the points' two coordinates (two-pass, centred sums); `None` for
/// fewer than two points or a constant coordinate.
pub fn pearson(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for &(x, y) in points {
        let (dx, dy) = (x - mx, y - my);
        sxy += dx * dy;
        sxx += dx * dx;
        syy += dy * dy;
    }
    (sxx > 0.0 && syy > 0.0).then(|| (sxy / (sxx.sqrt() * syy.sqrt())).clamp(-1.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::pearson;

    #[test]
    fn pearson_matches_closed_forms() {
        // Exact lines: ±1; a symmetric parabola over symmetric x: 0; constants: none.
        let line: Vec<(f64, f64)> = (0..7).map(|k| (k as f64, 3.0 - 2.0 * k as f64)).collect();
        assert!((pearson(&line).unwrap() + 1.0).abs() < 1e-15);
        let up: Vec<(f64, f64)> = (0..7).map(|k| (k as f64, 0.5 * k as f64)).collect();
        assert!((pearson(&up).unwrap() - 1.0).abs() < 1e-15);
        let parabola: Vec<(f64, f64)> = (-3..=3).map(|k| (k as f64, (k * k) as f64)).collect();
        assert!(pearson(&parabola).unwrap().abs() < 1e-15);
        assert_eq!(pearson(&[(1.0, 2.0), (1.0, 3.0)]), None);
        assert_eq!(pearson(&[(1.0, 2.0)]), None);
        // (0,0), (1,1), (2,3): r = 3 / sqrt(2 · 14/3) = 0.9819805060619657.
        let r = pearson(&[(0.0, 0.0), (1.0, 1.0), (2.0, 3.0)]).unwrap();
        assert!((r - 3.0 / (2.0f64 * 14.0 / 3.0).sqrt()).abs() < 1e-15);
    }
}
