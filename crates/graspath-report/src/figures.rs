//! The paper's figures built from a selection: the norms over the candidates (Fig. 5), `M_T`
//! over candidate × sample (Fig. 6), the classical indices at the grasp (Fig. 8) and, for two
//! arms, the summed norm over first × second arm candidates (Fig. 7, 9).

use crate::plots::{Cell, Heatmap, Line, LinePlot, Plot};
use graspath::select::{ArmResult, Selection};
use graspath::task::{JacobianRows, Norm, Task};

/// A figure of a report: a file stem, a caption for people and the plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// File name without extension (`norms-left`); `.svg` and `.png` are added.
    pub name: String,
    /// What the figure shows and which of the paper's figures it corresponds to.
    pub caption: String,
    /// The plot.
    pub plot: Plot,
}

fn norm_name(task: &Task) -> &'static str {
    match task.selection.norm {
        Norm::L2 => "μ_l2",
        Norm::L1 => "μ_l1",
    }
}

/// Values divided by their largest finite value (left as they are when none is positive).
fn normalised(values: &[Option<f64>]) -> Vec<Option<f64>> {
    let max = values
        .iter()
        .flatten()
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
    values
        .iter()
        .map(|v| {
            v.filter(|v| v.is_finite())
                .map(|v| if max > 0.0 { v / max } else { v })
        })
        .collect()
}

fn ids(arm: &ArmResult) -> Vec<f64> {
    arm.scores.iter().map(|s| s.candidate.id as f64).collect()
}

/// Fig. 5: the norms over the candidates, each normalised to its maximum.
fn norms_figure(arm: &ArmResult) -> Figure {
    let l2: Vec<Option<f64>> = arm.scores.iter().map(|s| s.norms.map(|n| n.l2)).collect();
    let linf: Vec<Option<f64>> = arm.scores.iter().map(|s| s.norms.map(|n| n.linf)).collect();
    let mut marks = Vec::new();
    if let Some(best) = arm.best() {
        let c = &arm.scores[best].candidate;
        marks.push((c.id as f64, format!("selected: {} ({})", c.id, c.label)));
    }
    Figure {
        name: format!("norms-{}", arm.arm),
        caption: format!(
            "Arm {}: μ_l2 and μ_l∞ of the task-relevant manipulability over the candidates, each \
             divided by its maximum (paper Fig. 5). Gaps are infeasible candidates.",
            arm.arm
        ),
        plot: Plot::Line(LinePlot {
            title: format!("Task-relevant norms, {} arm", arm.arm),
            x_label: "candidate id".into(),
            y_label: "norm / its maximum (1)".into(),
            x: ids(arm),
            lines: vec![
                Line {
                    name: "μ_l∞ = max 1/M_T (constraint)".into(),
                    values: normalised(&linf),
                    dashed: false,
                },
                Line {
                    name: "μ_l2 = ‖M_T‖₂ (maximised)".into(),
                    values: normalised(&l2),
                    dashed: true,
                },
            ],
            marks,
        }),
    }
}

/// Fig. 6: `M_T` at every sample for every candidate, scaled to the largest value.
fn m_t_figure(task: &Task, arm: &ArmResult) -> Figure {
    let samples = task.path.samples.len();
    let mut cells = Vec::with_capacity(samples * arm.scores.len());
    for s in &arm.scores {
        for i in 0..samples {
            let v = if s.feasible() {
                s.m_t.get(i).copied().flatten()
            } else {
                None
            };
            cells.push(v.map_or(Cell::Missing, Cell::Value));
        }
    }
    let unit = match task.rows {
        JacobianRows::Twist { .. } => "M_T = uᵀ J Jᵀ u (m²/rad², twist)",
        JacobianRows::Translation => "M_T = uᵀ Jv Jvᵀ u (m²/rad²)",
        JacobianRows::Rotation => "M_T = uᵀ Jω Jωᵀ u (1)",
    };
    Figure {
        name: format!("mt-heatmap-{}", arm.arm),
        caption: format!(
            "Arm {}: the task-relevant manipulability M_T at each sample of the object path \
             (columns, time in s) for each candidate (rows) (paper Fig. 6). Grey: infeasible \
             candidate or a sample where the object is still.",
            arm.arm
        ),
        plot: Plot::Heatmap(Heatmap {
            title: format!("M_T along the task, {} arm", arm.arm),
            x_label: "time along the object path (s)".into(),
            y_label: "candidate id".into(),
            value_label: unit.into(),
            column_ticks: task
                .path
                .samples
                .iter()
                .map(|s| format!("{:.1}", s.time))
                .collect(),
            row_ticks: arm
                .scores
                .iter()
                .map(|s| s.candidate.id.to_string())
                .collect(),
            cells,
            note: Some("grey: infeasible candidate, or the object is still".into()),
        }),
    }
}

fn argmax(values: &[Option<f64>]) -> Option<usize> {
    values
        .iter()
        .enumerate()
        .filter_map(|(i, v)| v.filter(|v| v.is_finite()).map(|v| (i, v)))
        .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
        .map(|(i, _)| i)
}

/// Fig. 8: Yoshikawa's index and the inverse condition number at the grasp configuration,
/// normalised, with the task-relevant choice marked.
fn classical_figure(arm: &ArmResult) -> Figure {
    let feasible = |v: Option<f64>, ok: bool| if ok { v } else { None };
    let yoshikawa: Vec<Option<f64>> = arm
        .scores
        .iter()
        .map(|s| feasible(s.yoshikawa_at_grasp, s.feasible()))
        .collect();
    let inverse: Vec<Option<f64>> = arm
        .scores
        .iter()
        .map(|s| feasible(s.inverse_condition_squared_at_grasp, s.feasible()))
        .collect();
    let id_of = |i: usize| arm.scores[i].candidate.id;
    let name = |base: &str, values: &[Option<f64>]| match argmax(values) {
        Some(i) => format!("{base}, best: {}", id_of(i)),
        None => base.to_string(),
    };
    let mut marks = Vec::new();
    if let Some(best) = arm.best() {
        let c = &arm.scores[best].candidate;
        marks.push((
            c.id as f64,
            format!("task-relevant choice: {} ({})", c.id, c.label),
        ));
    }
    Figure {
        name: format!("classical-indices-{}", arm.arm),
        caption: format!(
            "Arm {}: the classical indices at the grasp configuration only — Yoshikawa's \
             w = sqrt(det J Jᵀ) and the inverse condition number λmin/λmax of J Jᵀ — each \
             divided by its maximum over the feasible candidates, with the task-relevant choice \
             marked (paper Fig. 8).",
            arm.arm
        ),
        plot: Plot::Line(LinePlot {
            title: format!("Indices at the grasp, {} arm", arm.arm),
            x_label: "candidate id".into(),
            y_label: "index / its maximum (1)".into(),
            x: ids(arm),
            lines: vec![
                Line {
                    name: name("Yoshikawa w at grasp", &yoshikawa),
                    values: normalised(&yoshikawa),
                    dashed: true,
                },
                Line {
                    name: name("inverse condition λmin/λmax at grasp", &inverse),
                    values: normalised(&inverse),
                    dashed: false,
                },
            ],
            marks,
        }),
    }
}

/// Fig. 7 and 9: the sum of the two arms' norms over first-arm × second-arm candidates.
fn pairs_figure(task: &Task, selection: &Selection) -> Option<Figure> {
    let [first, second] = selection.arms.as_slice() else {
        return None;
    };
    let norm = |arm: &ArmResult, i: usize| -> Option<f64> {
        arm.rankings[i].score?;
        arm.scores[i].norms.map(|n| match task.selection.norm {
            Norm::L2 => n.l2,
            Norm::L1 => n.l1,
        })
    };
    // Row-major: rows are the first arm's candidates, columns the second arm's.
    let mut cells = Vec::with_capacity(first.scores.len() * second.scores.len());
    for i in 0..first.scores.len() {
        for j in 0..second.scores.len() {
            let cell = match (norm(first, i), norm(second, j)) {
                (Some(a), Some(b)) => {
                    let pa = first.scores[i].candidate.grasp_point();
                    let pb = second.scores[j].candidate.grasp_point();
                    if (pa - pb).norm() < task.selection.min_separation {
                        Cell::Marked
                    } else {
                        Cell::Value(a + b)
                    }
                }
                _ => Cell::Missing,
            };
            cells.push(cell);
        }
    }
    let ticks = |arm: &ArmResult| -> Vec<String> {
        arm.scores
            .iter()
            .map(|s| s.candidate.id.to_string())
            .collect()
    };
    let norm = norm_name(task);
    Some(Figure {
        name: "pairs-heatmap".into(),
        caption: format!(
            "Both arms: the sum of the two arms' {norm} for every pair of candidates (paper \
             Fig. 7 and 9). Light grey: one of the grasps is infeasible or rejected; dark grey \
             with a cross: the two grasps overlap (closer than {} m).",
            task.selection.min_separation
        ),
        plot: Plot::Heatmap(Heatmap {
            title: format!("Sum of {norm}, {} × {} arm", first.arm, second.arm),
            x_label: format!("{} arm candidate id", second.arm),
            y_label: format!("{} arm candidate id", first.arm),
            value_label: format!(
                "{norm}({}) + {norm}({}), unit of M_T",
                first.arm, second.arm
            ),
            column_ticks: ticks(second),
            row_ticks: ticks(first),
            cells,
            note: Some(
                "light grey: infeasible or rejected; dark grey with a cross: overlap".into(),
            ),
        }),
    })
}

/// Every figure of a selection, in a fixed order: per arm norms, `M_T` heatmap and classical
/// indices, then the pair heatmap for two arms.
pub fn figures(task: &Task, selection: &Selection) -> Vec<Figure> {
    let mut figures = Vec::new();
    for arm in &selection.arms {
        figures.push(norms_figure(arm));
        figures.push(m_t_figure(task, arm));
        figures.push(classical_figure(arm));
    }
    figures.extend(pairs_figure(task, selection));
    figures
}
