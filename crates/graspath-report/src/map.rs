//! Placement maps as JSON (`map.json`) and heatmaps over the placements (x across, y up), one
//! set per (z, yaw) slice of the grid.

use crate::figures::Figure;
use crate::plots::{Cell, Heatmap, Plot};
use graspath::placement::{GridAxis, PlacementMap, PlacementRecord};
use serde_json::{json, Value};

fn axis_json(axis: &GridAxis, scale: f64) -> Value {
    json!({
        "start": axis.start * scale,
        "end": axis.end * scale,
        "count": axis.count,
        "values": axis.values().iter().map(|v| v * scale).collect::<Vec<f64>>(),
    })
}

/// `map.json`: the task, the grid (x, y, z in m of the object's start in the world frame;
/// yaw in degrees about the world vertical, added to the task's orientation), the family
/// parameter the trends follow, and one record per placement in grid order (x fastest, then
/// y, yaw, z). Byte-identical for the same inputs.
pub fn placement_map_json(task_name: &str, map: &PlacementMap) -> Value {
    let g = &map.grid;
    json!({
        "task": task_name,
        "arms": map.arms,
        "grid": {
            "x": axis_json(&g.x, 1.0),
            "y": axis_json(&g.y, 1.0),
            "z": g.z.as_ref().map(|a| axis_json(a, 1.0)),
            "yaw_deg": g.yaw.as_ref().map(|a| axis_json(a, 1f64.to_degrees())),
        },
        "parameter": map.parameter.as_ref().map(|p| p.name.clone()),
        "tie_tolerance": map.tie_tolerance,
        "placements": map.records,
    })
}

fn ticks(axis: &GridAxis) -> Vec<String> {
    axis.values().iter().map(|v| format!("{v:.3}")).collect()
}

/// One quantity over a slice: rows are y (first value at the bottom), columns x.
fn slice_heatmap(
    map: &PlacementMap,
    slice: &[&PlacementRecord],
    title: String,
    value_label: String,
    value: impl Fn(&PlacementRecord) -> Option<f64>,
    note: &str,
) -> Heatmap {
    let (nx, ny) = (map.grid.x.count, map.grid.y.count);
    let mut cells = vec![Cell::Missing; nx * ny];
    for r in slice {
        let [ix, iy, _, _] = r.index;
        cells[iy * nx + ix] = value(r)
            .filter(|v| v.is_finite())
            .map_or(Cell::Missing, Cell::Value);
    }
    Heatmap {
        title,
        x_label: "object x in the world frame (m)".into(),
        y_label: "object y in the world frame (m)".into(),
        value_label,
        column_ticks: ticks(&map.grid.x),
        row_ticks: ticks(&map.grid.y),
        cells,
        note: Some(note.to_string()),
    }
}

/// The heatmaps of a placement map: per (z, yaw) slice and arm, the feasible count, the
/// selected candidate's score, the spread of `μ_l2` over the feasible candidates, the
/// selected candidate's family parameter (else its id) and, with a family, the correlation of
/// `μ_l2` with the parameter; with two arms, the best pair's summed norm. Names end in
/// `-z{iz}-yaw{iyaw}` when the grid has more than one slice.
pub fn placement_figures(map: &PlacementMap) -> Vec<Figure> {
    let nz = map.grid.z.map_or(1, |a| a.count);
    let nyaw = map.grid.yaw.map_or(1, |a| a.count);
    let zs = map.grid.z.map(|a| a.values());
    let yaws = map.grid.yaw.map(|a| a.values());
    let mut figures = Vec::new();
    for iz in 0..nz {
        for iyaw in 0..nyaw {
            let slice: Vec<&PlacementRecord> = map
                .records
                .iter()
                .filter(|r| r.index[2] == iz && r.index[3] == iyaw)
                .collect();
            let (suffix, where_) = if nz * nyaw > 1 {
                let mut at = Vec::new();
                if let Some(z) = &zs {
                    at.push(format!("z = {:.3} m", z[iz]));
                }
                if let Some(y) = &yaws {
                    at.push(format!("yaw {:+.1}°", y[iyaw].to_degrees()));
                }
                (format!("-z{iz}-yaw{iyaw}"), format!(" ({})", at.join(", ")))
            } else {
                (String::new(), String::new())
            };
            for (k, arm) in map.arms.iter().enumerate() {
                let per_arm = |r: &PlacementRecord| r.arms.get(k).cloned();
                let mut push = |name: &str, caption: String, heatmap: Heatmap| {
                    figures.push(Figure {
                        name: format!("map-{name}-{arm}{suffix}"),
                        caption,
                        plot: Plot::Heatmap(heatmap),
                    });
                };
                push(
                    "feasible",
                    format!(
                        "Arm {arm}: how many candidates are feasible along the whole motion \
                         with the object started at each placement{where_}."
                    ),
                    slice_heatmap(
                        map,
                        &slice,
                        format!("Feasible candidates, {arm} arm{where_}"),
                        "feasible candidates (count)".into(),
                        |r| per_arm(r).map(|a| a.feasible as f64),
                        "x, y: the object's start in the world frame",
                    ),
                );
                push(
                    "best-score",
                    format!(
                        "Arm {arm}: the selected candidate's score at each placement{where_}; \
                         grey: nothing eligible."
                    ),
                    slice_heatmap(
                        map,
                        &slice,
                        format!("Best score, {arm} arm{where_}"),
                        "score of the selected candidate (unit of M_T)".into(),
                        |r| per_arm(r).and_then(|a| a.best.map(|b| b.score)),
                        "grey: no eligible candidate",
                    ),
                );
                push(
                    "spread",
                    format!(
                        "Arm {arm}: (max − min) / max of μ_l2 over the feasible candidates at \
                         each placement{where_}: how much the choice of grasp matters there."
                    ),
                    slice_heatmap(
                        map,
                        &slice,
                        format!("Spread of μ_l2 over the grasps, {arm} arm{where_}"),
                        "(max − min) / max of μ_l2 (1)".into(),
                        |r| per_arm(r).and_then(|a| a.spread),
                        "grey: no feasible candidate",
                    ),
                );
                let (name, label) = match &map.parameter {
                    Some(p) => ("best-parameter", format!("selected candidate's {}", p.name)),
                    None => ("best-id", "selected candidate id".to_string()),
                };
                let with_parameter = map.parameter.is_some();
                push(
                    name,
                    format!(
                        "Arm {arm}: the selected candidate at each placement{where_}: {label}."
                    ),
                    slice_heatmap(
                        map,
                        &slice,
                        format!("Selected grasp, {arm} arm{where_}"),
                        label,
                        |r| {
                            per_arm(r).and_then(|a| {
                                a.best.map(|b| match (with_parameter, b.parameter) {
                                    (true, Some(p)) => p,
                                    _ => b.id as f64,
                                })
                            })
                        },
                        "grey: no eligible candidate",
                    ),
                );
                if let Some(p) = &map.parameter {
                    push(
                        "trend",
                        format!(
                            "Arm {arm}: Pearson's correlation of μ_l2 with the family's {} over \
                             the feasible candidates at each placement{where_}: positive where \
                             μ_l2 grows with it.",
                            p.name
                        ),
                        slice_heatmap(
                            map,
                            &slice,
                            format!("Trend of μ_l2 along the family, {arm} arm{where_}"),
                            format!("correlation of μ_l2 with {} (−1 … 1)", p.name),
                            |r| per_arm(r).and_then(|a| a.trend.and_then(|t| t.correlation)),
                            "grey: fewer than two feasible candidates",
                        ),
                    );
                }
            }
            if map.arms.len() == 2 {
                figures.push(Figure {
                    name: format!("map-best-pair{suffix}"),
                    caption: format!(
                        "Both arms: the best pair's summed norm at each placement{where_}; grey: \
                         no valid pair."
                    ),
                    plot: Plot::Heatmap(slice_heatmap(
                        map,
                        &slice,
                        format!("Best pair, {} + {} arm{where_}", map.arms[0], map.arms[1]),
                        "sum of the two arms' norms (unit of M_T)".into(),
                        |r| r.best_pair.as_ref().map(|p| p.score),
                        "grey: no valid pair",
                    )),
                });
            }
        }
    }
    figures
}
