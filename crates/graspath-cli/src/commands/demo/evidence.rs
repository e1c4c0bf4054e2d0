//! The demo's evidence beyond the default placement: where each paper finding holds over a
//! grid of object placements, the placement where it is reproduced with the largest effect,
//! and the measured mechanism behind the cuboid findings (how the index's terms change with
//! the grasp's horizontal distance from the arm's shoulder).
//!
//! All positions are world-frame metres (Baxter's base frame); contacts `y` are in the object
//! frame (m); yaws in degrees.

use anyhow::Result;
use graspath::placement::{
    pearson, placement_map_with, FamilyParameter, GridAxis, PlacementGrid, PlacementMap,
};
use graspath::select::Selection;
use graspath::task::{builder_from_file, Task, TaskFile};
use serde_json::{json, Value};
use std::collections::BTreeSet;
use std::path::Path;

/// A quarter of the cuboid's edge (m): a contact this far from the middle is on the left
/// (`y ≥ +QUARTER`) or the right (`y ≤ −QUARTER`) part.
const QUARTER: f64 = 0.09;

/// The task files' own placement of the cuboid (world x, y, m), a node of the cuboid grid.
const CUBOID_DEFAULT: [f64; 2] = [0.75, 0.0];

/// The task files' own placement of the T-shaped object (world x, y, m), a node of the
/// T-shape grid.
const T_SHAPE_DEFAULT: [f64; 2] = [0.70, 0.25];

/// Whether a paper finding holds at a placement, from the contacts `y` (object frame, m) of
/// the best candidate (one arm) or the best pair (left, right): `Some(true)` holds,
/// `Some(false)` reverses, `None` neither (or nothing selected).
type Judge = fn(&[f64]) -> Option<bool>;

/// The judges of the cuboid experiments' findings, by experiment.
pub(super) fn cuboid_judge(experiment: &str) -> Option<Judge> {
    match experiment {
        // Fig. 5, 6: the left arm's best contact on the left part.
        "pick_and_place_left" => Some(|y| match y {
            [y] if *y >= QUARTER => Some(true),
            [y] if *y <= -QUARTER => Some(false),
            _ => None,
        }),
        // Fig. 7: the left hand on the left part, the right hand on the right half.
        "pick_and_place_both" => Some(|y| match y {
            [l, r] if *l >= QUARTER && *r < 0.0 => Some(true),
            [l, _] if *l <= -QUARTER => Some(false),
            _ => None,
        }),
        // Fig. 9: the left hand on the left half, the right hand on the right half.
        "pick_rotate_place_both" => Some(|y| match y {
            [l, r] if *l > 0.0 && *r < 0.0 => Some(true),
            [l, r] if *l < 0.0 && *r > 0.0 => Some(false),
            _ => None,
        }),
        _ => None,
    }
}

/// Millimetres: a grid value without the rounding of its arithmetic.
fn mm(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// Hundredths, for correlations.
fn hundredths(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

/// A 5 × 5 grid of object starts: x over `x`, y over `y` (world, m).
fn grid_5x5(x: (f64, f64), y: (f64, f64)) -> Result<PlacementGrid> {
    Ok(PlacementGrid {
        x: GridAxis::new(x.0, x.1, 5, "x")?,
        y: GridAxis::new(y.0, y.1, 5, "y")?,
        z: None,
        yaw: None,
    })
}

fn grid_json(grid: &PlacementGrid) -> Value {
    json!({
        "x": grid.x.values().into_iter().map(mm).collect::<Vec<_>>(),
        "y": grid.y.values().into_iter().map(mm).collect::<Vec<_>>(),
    })
}

/// Where a cuboid experiment's finding holds: the object's start swept over a 5 × 5 grid in
/// front of the robot (world x 0.55 … 0.95 m, y −0.40 … 0.40 m; the task's own placement is
/// on the grid), the best contacts at each placement (the best candidate with one arm, the
/// best pair with two), the placements where `judge` says the finding holds or reverses, the
/// placement where it holds with the largest μ_l2 spread (the effect size), the verdict at
/// the task's own placement, and the measured [`mechanism`].
pub(super) fn cuboid_where_it_holds(file: &TaskFile, source: &str, judge: Judge) -> Result<Value> {
    let builder = builder_from_file(file, source, Path::new("."))?;
    let task = builder.clone().build()?;
    let candidates = task.all_candidates()?;
    let parameter = FamilyParameter::from_task_file(file, &candidates);
    let contact_of: Vec<(usize, f64)> = candidates
        .iter()
        .zip(parameter.iter().flat_map(|p| p.values.iter()))
        .map(|(c, v)| (c.id, *v))
        .collect();
    let contact = |id: usize| contact_of.iter().find(|(c, _)| *c == id).map(|(_, v)| *v);
    let grid = grid_5x5((0.55, 0.95), (-0.40, 0.40))?;
    let (map, measured) = placement_map_with(&builder, &grid, parameter, &|| {}, &|t, s, _| {
        distance_terms(t, s)
    })?;
    let mut holds = Vec::new();
    let mut reverses = Vec::new();
    let mut placements = Vec::new();
    // (first arm's spread, placement) of the placements where the finding holds.
    let mut strongest: Option<(f64, Value)> = None;
    let mut at_default = "neither";
    for (record, terms) in map.records.iter().zip(&measured) {
        let at = json!([mm(record.x), mm(record.y)]);
        let contacts: Option<Vec<f64>> = if record.arms.len() == 2 {
            record
                .best_pair
                .as_ref()
                .and_then(|p| Some(vec![contact(p.first)?, contact(p.second)?]))
        } else {
            record.arms[0]
                .best
                .as_ref()
                .and_then(|b| b.parameter)
                .map(|y| vec![y])
        };
        let verdict = contacts.as_deref().and_then(judge);
        let spreads: Vec<Option<f64>> = record
            .arms
            .iter()
            .map(|a| a.spread.map(|s| (s * 1000.0).round() / 10.0))
            .collect();
        let contacts: Option<Vec<f64>> = contacts.map(|c| c.into_iter().map(mm).collect());
        let entry = json!({
            "at": at,
            "best_contacts_y": contacts,
            "mu_l2_spread_percent": spreads,
            "mu_l2_vs_distance_r": terms.iter().map(|t| {
                let points: Vec<(f64, f64)> = t.iter().map(|c| (c.distance, c.mu_l2)).collect();
                pearson(&points).map(hundredths)
            }).collect::<Vec<_>>(),
        });
        match verdict {
            Some(true) => {
                holds.push(at.clone());
                let effect = spreads.first().copied().flatten().unwrap_or(0.0);
                if strongest.as_ref().is_none_or(|(e, _)| effect > *e) {
                    strongest = Some((effect, entry.clone()));
                }
            }
            Some(false) => reverses.push(at.clone()),
            None => {}
        }
        if [mm(record.x), mm(record.y)] == CUBOID_DEFAULT {
            at_default = match verdict {
                Some(true) => "holds",
                Some(false) => "reverses",
                None => "neither",
            };
        }
        placements.push(entry);
    }
    Ok(json!({
        "grid": grid_json(&grid),
        "holds_at": holds,
        "reverses_at": reverses,
        "reproduced_at": strongest.map(|(_, entry)| entry),
        "at_the_task_placement": { "at": CUBOID_DEFAULT, "finding": at_default },
        "placements": placements,
        "mechanism": mechanism(&map, &measured),
    }))
}

/// One feasible candidate at one placement: the grasp's horizontal distance from the arm's
/// shoulder (m), the mean `M_T` over the samples where the object moves vertically (lift,
/// place) and over the other samples, and μ_l2.
#[derive(Debug, Clone, Copy)]
struct DistanceTerms {
    distance: f64,
    vertical: Option<f64>,
    other: Option<f64>,
    mu_l2: f64,
    best: bool,
}

/// Whether the object moves mostly vertically (|Δz| ≥ 0.9 |Δp|) into each sample of the
/// task's path (the first sample, which no motion leads into, is `false`).
fn vertical_samples(task: &Task) -> Vec<bool> {
    let samples = &task.path().samples;
    let mut vertical = vec![false; samples.len()];
    for (k, pair) in samples.windows(2).enumerate() {
        let step = pair[1].world_from_object.translation.vector
            - pair[0].world_from_object.translation.vector;
        vertical[k + 1] = step.norm() > 0.0 && step.z.abs() >= 0.9 * step.norm();
    }
    vertical
}

/// The arm's shoulder in the world (m): the origin of its second joint at the mid
/// configuration (Baxter's `s1`, the pitch joint that raises the arm).
fn shoulder(task: &Task, arm: usize) -> Option<nalgebra::Point3<f64>> {
    let setup = &task.arms()[arm];
    let origins = setup
        .chain
        .joint_origins(&setup.chain.mid_configuration())
        .ok()?;
    origins.get(2).map(|p| setup.world_from_base * p)
}

/// Every arm's feasible candidates at one placement, as [`DistanceTerms`].
fn distance_terms(task: &Task, selection: &Selection) -> Vec<Vec<DistanceTerms>> {
    let vertical = vertical_samples(task);
    let grasp_pose = task.path().samples[0].world_from_object;
    let mean = |values: Vec<f64>| {
        (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
    };
    selection
        .arms
        .iter()
        .enumerate()
        .map(|(k, arm)| {
            let Some(shoulder) = shoulder(task, k) else {
                return Vec::new();
            };
            let best = arm.best();
            arm.scores
                .iter()
                .enumerate()
                .filter(|(_, s)| s.feasible())
                .filter_map(|(i, s)| {
                    let grasp = grasp_pose * s.candidate.grasp_point();
                    let terms = |want: bool| {
                        let values: Vec<f64> = s
                            .m_t
                            .iter()
                            .zip(&vertical)
                            .skip(1)
                            .filter(|(_, v)| **v == want)
                            .filter_map(|(m, _)| *m)
                            .collect();
                        mean(values)
                    };
                    Some(DistanceTerms {
                        distance: (grasp - shoulder).xy().norm(),
                        vertical: terms(true),
                        other: terms(false),
                        mu_l2: s.norms?.l2,
                        best: best == Some(i),
                    })
                })
                .collect()
        })
        .collect()
}

/// The median of `values` (the mean of the middle two for an even count); `None` if empty.
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    (n > 0).then(|| 0.5 * (values[(n - 1) / 2] + values[n / 2]))
}

/// The least-squares slope of the points' second coordinate on the first, relative to the
/// second's mean; `None` for fewer than two points, a constant first coordinate or a zero mean.
fn relative_slope(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(sxy, sxx), &(x, y)| {
        (sxy + (x - mx) * (y - my), sxx + (x - mx) * (x - mx))
    });
    (sxx > 0.0 && my != 0.0).then(|| sxy / sxx / my)
}

/// One arm's mechanism, measured over the placements of a map (see [`mechanism`]).
struct ArmMechanism<'a> {
    arm: &'a str,
    /// Placements with at least three feasible candidates.
    placements: usize,
    /// At how many of them the vertical terms change with the distance in the direction of
    /// the median (r of the median's sign).
    agreeing: usize,
    /// Median r of the vertical terms against the distance.
    r_vertical: Option<f64>,
    /// Median relative growth of the vertical terms per 10 cm (%).
    growth_per_10cm: Option<f64>,
    /// Median r of the other terms against the distance.
    r_other: Option<f64>,
    /// Median r of μ_l2 against the distance.
    r_mu_l2: Option<f64>,
    /// At how many placements the best candidate is on the far half.
    far_half: usize,
    /// Placements where a best candidate is among the measured ones.
    with_best: usize,
}

impl ArmMechanism<'_> {
    fn measure<'a>(
        arm: &'a str,
        at_placements: impl Iterator<Item = &'a [DistanceTerms]>,
    ) -> ArmMechanism<'a> {
        let (mut r_vertical, mut r_other, mut r_mu_l2, mut growth) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut placements, mut far_half, mut with_best) = (0, 0, 0);
        for terms in at_placements.filter(|t| t.len() >= 3) {
            placements += 1;
            let points = |f: fn(&DistanceTerms) -> Option<f64>| -> Vec<(f64, f64)> {
                terms
                    .iter()
                    .filter_map(|t| Some((t.distance, f(t)?)))
                    .collect()
            };
            let vertical = points(|t| t.vertical);
            r_vertical.extend(pearson(&vertical));
            growth.extend(relative_slope(&vertical).map(|s| 0.1 * s * 100.0));
            r_other.extend(pearson(&points(|t| t.other)));
            r_mu_l2.extend(pearson(&points(|t| Some(t.mu_l2))));
            let distances: Vec<f64> = terms.iter().map(|t| t.distance).collect();
            if let (Some(best), Some(mid)) = (terms.iter().find(|t| t.best), median(distances)) {
                with_best += 1;
                far_half += usize::from(best.distance >= mid);
            }
        }
        ArmMechanism {
            arm,
            placements,
            agreeing: {
                let overall = median(r_vertical.clone()).unwrap_or(0.0);
                r_vertical
                    .iter()
                    .filter(|r| r.signum() == overall.signum())
                    .count()
            },
            r_vertical: median(r_vertical).map(hundredths),
            growth_per_10cm: median(growth).map(|g| (g * 10.0).round() / 10.0),
            r_other: median(r_other).map(hundredths),
            r_mu_l2: median(r_mu_l2).map(hundredths),
            far_half,
            with_best,
        }
    }

    /// The mechanism in plain words, from the measured values.
    fn in_words(&self) -> String {
        let arm = self.arm;
        let (Some(r_vertical), Some(growth), Some(r_other), Some(r_mu_l2)) = (
            self.r_vertical,
            self.growth_per_10cm,
            self.r_other,
            self.r_mu_l2,
        ) else {
            return format!(
                "{arm} arm: too few placements with three feasible candidates to measure"
            );
        };
        let trend = |r: f64| if r > 0.0 { "grow" } else { "fall" };
        format!(
            "{arm} arm: the lift and place terms {} with the grasp's horizontal distance from the \
             shoulder at {} of {} placements (median r = {r_vertical:.2}, {growth:+.1} % per 10 cm), \
             the move/rotate terms {} with it (median r = {r_other:.2}) and μ_l2 {}s with it \
             (median r = {r_mu_l2:.2}); the best candidate is on the far half from the shoulder at \
             {} of {} placements",
            trend(r_vertical),
            self.agreeing,
            self.placements,
            trend(r_other),
            trend(r_mu_l2),
            self.far_half,
            self.with_best,
        )
    }

    fn to_json(&self) -> Value {
        json!({
            "arm": self.arm,
            "placements": self.placements,
            "vertical_terms_vs_distance_r": self.r_vertical,
            "vertical_terms_trend_as_the_median_at": self.agreeing,
            "vertical_terms_growth_per_10cm_percent": self.growth_per_10cm,
            "other_terms_vs_distance_r": self.r_other,
            "mu_l2_vs_distance_r": self.r_mu_l2,
            "best_on_far_half_at": self.far_half,
            "placements_with_a_best": self.with_best,
            "in_words": self.in_words(),
        })
    }
}

/// The mechanism behind the cuboid findings, measured at every placement of `map` with at
/// least three feasible candidates, per arm: how the vertical terms (lift, place), the other
/// terms and μ_l2 correlate with the grasp's horizontal distance from the shoulder across the
/// candidates (median Pearson r over the placements; at how many placements the vertical
/// terms grow with it; their median growth per 10 cm), and at how many placements the best
/// candidate is on the far half (its distance at least the median of the feasible ones).
fn mechanism(map: &PlacementMap, measured: &[Vec<Vec<DistanceTerms>>]) -> Value {
    let arms: Vec<Value> = map
        .arms
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let at_placements = measured
                .iter()
                .filter_map(|arms| arms.get(k))
                .map(Vec::as_slice);
            ArmMechanism::measure(name, at_placements).to_json()
        })
        .collect();
    json!({
        "distance": "horizontal distance (m) from the arm's shoulder (its second joint at the mid configuration) to the grasp point at the grasp",
        "vertical_terms": "mean M_T over the samples where the object moves vertically (lift, place)",
        "other_terms": "mean M_T over the other samples after the grasp (move, rotate)",
        "r": "Pearson's r across the feasible candidates of one placement; the median over the placements with at least three",
        "arms": arms,
    })
}

/// The T-shape experiments, their task files (name, YAML text) in the order rotate, move,
/// move and rotate.
pub(super) struct TShapeTasks<'a> {
    pub rotate: (&'a str, &'a str),
    pub moving: (&'a str, &'a str),
    pub move_rotate: (&'a str, &'a str),
}

/// One T-shape task's results at every placement: the best candidate's id, the ids tied with
/// it, and the feasible ids.
struct TShapeAt {
    /// The object's start (world x, y, m, to the millimetre).
    at: [f64; 2],
    best: Option<usize>,
    tied: BTreeSet<usize>,
    feasible: BTreeSet<usize>,
    label: Option<String>,
}

fn t_shape_map(name: &str, yaml: &str, grid: &PlacementGrid) -> Result<Vec<TShapeAt>> {
    let source = format!("examples/{name}.yaml");
    let file = TaskFile::parse(yaml, &source, "yaml")?;
    let builder = builder_from_file(&file, &source, Path::new("."))?;
    let (map, feasible) = placement_map_with(&builder, grid, None, &|| {}, &|_, s, _| {
        s.arms[0]
            .scores
            .iter()
            .filter(|c| c.feasible())
            .map(|c| c.candidate.id)
            .collect::<BTreeSet<usize>>()
    })?;
    Ok(map
        .records
        .iter()
        .zip(feasible)
        .map(|(record, feasible)| {
            let best = record.arms[0].best.as_ref();
            TShapeAt {
                at: [mm(record.x), mm(record.y)],
                best: best.map(|b| b.id),
                tied: best
                    .map(|b| b.tied_with.iter().copied().collect())
                    .unwrap_or_default(),
                feasible,
                label: best.map(|b| b.label.clone()),
            }
        })
        .collect())
}

/// Whether two tasks' best grasps differ at a placement: both selected something and neither
/// best is the other's or tied with it.
fn bests_differ(a: &TShapeAt, b: &TShapeAt) -> Option<bool> {
    let (x, y) = (a.best?, b.best?);
    Some(x != y && !a.tied.contains(&y) && !b.tied.contains(&x))
}

/// Where the T-shape findings (Fig. 10) hold: the three tasks' maps over a 5 × 5 grid around
/// the files' own placement (world x 0.50 … 0.90 m, y −0.35 … 0.45 m), judged per placement:
/// Fig. 10 c, d — the rotate task's best yaw is not the best of one of the other two tasks
/// (reversed: all three agree); e, f — the move task's best differs from the rotate task's
/// (reversed: the same); g, h — the rotate task's best is infeasible for the move-and-rotate
/// task (reversed: feasible). Returns one `where_it_holds` per experiment, by name.
pub(super) fn t_shape_where_it_holds(tasks: &TShapeTasks) -> Result<Vec<(String, Value)>> {
    let grid = grid_5x5((0.50, 0.90), (-0.35, 0.45))?;
    let rotate = t_shape_map(tasks.rotate.0, tasks.rotate.1, &grid)?;
    let moving = t_shape_map(tasks.moving.0, tasks.moving.1, &grid)?;
    let move_rotate = t_shape_map(tasks.move_rotate.0, tasks.move_rotate.1, &grid)?;
    type TJudge = fn(&TShapeAt, &TShapeAt, &TShapeAt) -> Option<bool>;
    let judges: [(&str, TJudge); 3] = [
        (tasks.rotate.0, |r, m, mr| {
            let differs = [bests_differ(r, m)?, bests_differ(r, mr)?];
            Some(differs.contains(&true))
        }),
        (tasks.moving.0, |r, m, _| bests_differ(r, m)),
        (tasks.move_rotate.0, |r, _, mr| {
            mr.best?;
            Some(!mr.feasible.contains(&r.best?))
        }),
    ];
    let mut out = Vec::new();
    for (name, judge) in judges {
        let mut holds = Vec::new();
        let mut reverses = Vec::new();
        let mut placements = Vec::new();
        let mut at_default = "neither";
        for k in 0..rotate.len() {
            let at = rotate[k].at;
            let verdict = judge(&rotate[k], &moving[k], &move_rotate[k]);
            match verdict {
                Some(true) => holds.push(at),
                Some(false) => reverses.push(at),
                None => {}
            }
            if at == T_SHAPE_DEFAULT {
                at_default = match verdict {
                    Some(true) => "holds",
                    Some(false) => "reverses",
                    None => "neither",
                };
            }
            placements.push(json!({
                "at": at,
                "best_rotate": rotate[k].label,
                "best_move": moving[k].label,
                "best_move_rotate": move_rotate[k].label,
            }));
        }
        out.push((
            name.to_string(),
            json!({
                "grid": grid_json(&grid),
                "holds_at": holds,
                "reverses_at": reverses,
                "at_the_task_placement": { "at": T_SHAPE_DEFAULT, "finding": at_default },
                "placements": placements,
            }),
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::{median, relative_slope};

    #[test]
    fn median_and_relative_slope_match_closed_forms() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(Vec::new()), None);
        // y = 2 + 0.5 x over x = 0, 1, 2: slope 0.5, mean 2.5.
        let line = [(0.0, 2.0), (1.0, 2.5), (2.0, 3.0)];
        assert!((relative_slope(&line).unwrap() - 0.2).abs() < 1e-15);
        assert_eq!(relative_slope(&[(1.0, 1.0), (1.0, 2.0)]), None);
    }
}
