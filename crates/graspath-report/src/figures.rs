//! The paper's figures built from a selection: the norms over the candidates (Fig. 5), `M_T`
//! over candidate × sample (Fig. 6), the classical indices at the grasp (Fig. 8) and, for two
//! arms, the summed norm over first × second arm candidates (Fig. 7, 9).

use crate::lines::{Line, LinePlot, LineStyle, SecondaryLabels};
use crate::plots::{Cell, Heatmap, Plot};
use graspath::manipulability::{JacobianRows, Norm};
use graspath::placement::FamilyParameter;
use graspath::select::{ArmResult, Selection};
use graspath::task::Task;

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
    match task.selection().norm {
        Norm::Rms => "μ_rms",
        Norm::L2 => "μ_l2",
        Norm::L1 => "μ_l1",
    }
}

/// How the ranked norm is written in a legend.
fn norm_legend(norm: Norm) -> &'static str {
    match norm {
        Norm::Rms => "μ_rms = RMS of M_T over time (maximised)",
        Norm::L2 => "μ_l2 = ‖M_T‖₂ (maximised)",
        Norm::L1 => "μ_l1 = ∫ M_T dt (maximised)",
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

/// The x axis of the line charts over the candidates: the family's parameter when it gives
/// one distinct finite value per candidate (then sorted by it, with the candidate ids as
/// secondary labels), else the candidate id in candidate order.
struct CandidateAxis {
    /// The axis description with its unit.
    label: String,
    /// Candidate indices in the order drawn (increasing x).
    order: Vec<usize>,
    /// The x value of each candidate index.
    x_of: Vec<f64>,
    /// The ids as secondary labels (only with a parameter).
    secondary: bool,
}

impl CandidateAxis {
    fn new(arm: &ArmResult, parameter: Option<&FamilyParameter>) -> Self {
        let n = arm.scores.len();
        let usable = parameter.filter(|p| {
            let mut sorted = p.values.clone();
            sorted.sort_by(f64::total_cmp);
            p.values.len() == n
                && sorted.iter().all(|v| v.is_finite())
                && sorted.windows(2).all(|w| w[1] > w[0])
        });
        match usable {
            Some(p) => {
                let mut order: Vec<usize> = (0..n).collect();
                order.sort_by(|&a, &b| p.values[a].total_cmp(&p.values[b]));
                Self {
                    label: p.name.clone(),
                    order,
                    x_of: p.values.clone(),
                    secondary: true,
                }
            }
            None => {
                let mut order: Vec<usize> = (0..n).collect();
                order.sort_by_key(|&i| arm.scores[i].candidate.id);
                Self {
                    label: "candidate id".into(),
                    order,
                    x_of: arm.scores.iter().map(|s| s.candidate.id as f64).collect(),
                    secondary: false,
                }
            }
        }
    }

    fn x(&self) -> Vec<f64> {
        self.order.iter().map(|&i| self.x_of[i]).collect()
    }

    /// Values given in candidate order, in the drawn order.
    fn arrange(&self, values: Vec<Option<f64>>) -> Vec<Option<f64>> {
        self.order.iter().map(|&i| values[i]).collect()
    }

    fn secondary(&self, arm: &ArmResult) -> Option<SecondaryLabels> {
        self.secondary.then(|| SecondaryLabels {
            name: "candidate id".into(),
            labels: self
                .order
                .iter()
                .map(|&i| arm.scores[i].candidate.id.to_string())
                .collect(),
        })
    }
}

/// How a candidate is named in a legend: its id and label (a family's label gives its
/// parameter).
fn candidate_name(arm: &ArmResult, i: usize) -> String {
    let c = &arm.scores[i].candidate;
    format!("{} ({})", c.id, c.label)
}

/// Row tick text of a heatmap over the candidates: the id, and the parameter's value with one.
fn row_ticks(arm: &ArmResult, parameter: Option<&FamilyParameter>) -> Vec<String> {
    let values = parameter.filter(|p| p.values.len() == arm.scores.len());
    arm.scores
        .iter()
        .enumerate()
        .map(|(i, s)| match values {
            Some(p) => format!("{} · {}", s.candidate.id, short(p.values[i])),
            None => s.candidate.id.to_string(),
        })
        .collect()
}

/// A parameter value in a tick: 3 decimals under 10, else whole.
fn short(v: f64) -> String {
    if v.abs() < 10.0 {
        format!("{v:+.3}")
    } else {
        format!("{v:+.0}")
    }
}

/// The heatmap rows' description: the ids, and the parameter with one.
fn row_label(base: &str, parameter: Option<&FamilyParameter>) -> String {
    match parameter {
        Some(p) => format!("{base} · {}", p.name),
        None => base.to_string(),
    }
}

/// Fig. 5: the norms over the candidates (the constraint and the ranked norm), each
/// normalised to its maximum.
fn norms_figure(norm: Norm, arm: &ArmResult, parameter: Option<&FamilyParameter>) -> Figure {
    let axis = CandidateAxis::new(arm, parameter);
    let ranked: Vec<Option<f64>> = arm
        .scores
        .iter()
        .map(|s| s.norms.map(|n| n.value(norm)))
        .collect();
    let linf: Vec<Option<f64>> = arm.scores.iter().map(|s| s.norms.map(|n| n.linf)).collect();
    let marks = best_mark(arm, &axis, "selected");
    let plot = LinePlot {
        title: format!("Task-relevant norms, {} arm", arm.arm),
        x_label: axis.label.clone(),
        y_label: "norm / its maximum (1)".into(),
        x: axis.x(),
        secondary: axis.secondary(arm),
        lines: vec![
            Line {
                name: "μ_l∞ = max 1/M_T (constraint)".into(),
                values: axis.arrange(normalised(&linf)),
                style: LineStyle::Solid,
            },
            Line {
                name: norm_legend(norm).into(),
                values: axis.arrange(normalised(&ranked)),
                style: LineStyle::Dashed,
            },
        ],
        marks,
    };
    Figure {
        name: format!("norms-{}", arm.arm),
        caption: format!(
            "Arm {}: μ_l2 and μ_l∞ of the task-relevant manipulability over the candidates \
             (x: {}), each divided by its maximum (paper Fig. 5); {} (not from zero). Gaps \
             are infeasible candidates.",
            arm.arm,
            axis.label,
            plot.range_note(),
        ),
        plot: Plot::Line(plot),
    }
}

/// Fig. 6: `M_T` at every sample for every candidate, scaled to the largest value.
fn m_t_figure(task: &Task, arm: &ArmResult, parameter: Option<&FamilyParameter>) -> Figure {
    let samples = task.path().samples.len();
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
    let unit = match task.rows() {
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
            y_label: row_label("candidate id", parameter),
            value_label: unit.into(),
            column_ticks: task
                .path()
                .samples
                .iter()
                .map(|s| format!("{:.1}", s.time))
                .collect(),
            row_ticks: row_ticks(arm, parameter),
            cells,
            note: Some("grey: infeasible candidate, or the object is still".into()),
        }),
    }
}

/// The best-ranked candidate's mark on a line chart (none when nothing is ranked), named
/// `what: candidate`.
fn best_mark(arm: &ArmResult, axis: &CandidateAxis, what: &str) -> Vec<(f64, String)> {
    arm.best()
        .map(|best| {
            (
                axis.x_of[best],
                format!("{what}: {}", candidate_name(arm, best)),
            )
        })
        .into_iter()
        .collect()
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
fn classical_figure(arm: &ArmResult, parameter: Option<&FamilyParameter>) -> Figure {
    let axis = CandidateAxis::new(arm, parameter);
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
    let marks = best_mark(arm, &axis, "task-relevant choice");
    let plot = LinePlot {
        title: format!("Indices at the grasp, {} arm", arm.arm),
        x_label: axis.label.clone(),
        y_label: "index / its maximum (1)".into(),
        x: axis.x(),
        secondary: axis.secondary(arm),
        lines: vec![
            Line {
                name: name("Yoshikawa w at grasp", &yoshikawa),
                values: axis.arrange(normalised(&yoshikawa)),
                style: LineStyle::Dashed,
            },
            Line {
                name: name("inverse condition λmin/λmax at grasp", &inverse),
                values: axis.arrange(normalised(&inverse)),
                style: LineStyle::Solid,
            },
        ],
        marks,
    };
    Figure {
        name: format!("classical-indices-{}", arm.arm),
        caption: format!(
            "Arm {}: the classical indices at the grasp configuration only — Yoshikawa's \
             w = sqrt(det J Jᵀ) and the inverse condition number λmin/λmax of J Jᵀ — each \
             divided by its maximum over the feasible candidates (x: {}), with the \
             task-relevant choice marked (paper Fig. 8); {} (not from zero).",
            arm.arm,
            axis.label,
            plot.range_note(),
        ),
        plot: Plot::Line(plot),
    }
}

/// Fig. 7 and 9: the sum of the two arms' norms over first-arm × second-arm candidates.
fn pairs_figure(
    task: &Task,
    selection: &Selection,
    parameter: Option<&FamilyParameter>,
) -> Option<Figure> {
    let [first, second] = selection.arms.as_slice() else {
        return None;
    };
    let norm = |arm: &ArmResult, i: usize| -> Option<f64> {
        arm.rankings[i].score?;
        arm.scores[i].norms.map(|n| n.value(task.selection().norm))
    };
    // Row-major: rows are the first arm's candidates, columns the second arm's.
    let mut cells = Vec::with_capacity(first.scores.len() * second.scores.len());
    for i in 0..first.scores.len() {
        for j in 0..second.scores.len() {
            let cell = match (norm(first, i), norm(second, j)) {
                (Some(a), Some(b)) => {
                    let pa = first.scores[i].candidate.grasp_point();
                    let pb = second.scores[j].candidate.grasp_point();
                    if (pa - pb).norm() < task.selection().min_separation {
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
            task.selection().min_separation
        ),
        plot: Plot::Heatmap(Heatmap {
            title: format!("Sum of {norm}, {} × {} arm", first.arm, second.arm),
            x_label: format!("{} arm candidate id", second.arm),
            y_label: row_label(&format!("{} arm candidate id", first.arm), parameter),
            value_label: format!(
                "{norm}({}) + {norm}({}), unit of M_T",
                first.arm, second.arm
            ),
            column_ticks: ticks(second),
            row_ticks: row_ticks(first, parameter),
            cells,
            note: Some(
                "light grey: infeasible or rejected; dark grey with a cross: overlap".into(),
            ),
        }),
    })
}

/// Every figure of a selection, in a fixed order: per arm norms, `M_T` heatmap and classical
/// indices, then the pair heatmap for two arms.
///
/// `parameter` is the candidate family's parameter (one value per candidate, in the task's
/// candidate order; see [`FamilyParameter::from_task_file`]): the line charts then use it as
/// their x axis with the candidate ids as secondary labels, and the heatmaps' rows name it.
/// Without one (candidate files, the faces family), or when its values are not one distinct
/// finite value per candidate, the x axis is the candidate id.
pub fn figures(
    task: &Task,
    selection: &Selection,
    parameter: Option<&FamilyParameter>,
) -> Vec<Figure> {
    let parameter = parameter.filter(|p| p.values.len() == task.candidate_count());
    let mut figures = Vec::new();
    for arm in &selection.arms {
        figures.push(norms_figure(task.selection().norm, arm, parameter));
        figures.push(m_t_figure(task, arm, parameter));
        figures.push(classical_figure(arm, parameter));
    }
    figures.extend(pairs_figure(task, selection, parameter));
    figures
}
