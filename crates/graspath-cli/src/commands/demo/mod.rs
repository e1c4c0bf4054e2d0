//! `graspath demo [--out DIR]`: the paper's experiments on the built-in Baxter, from task files
//! compiled into the binary (the same files as `examples/`), so no input is needed. Every
//! experiment's folder gets the JSON results, the figures and `report.html`; the whole output
//! folder (every experiment and `findings.json`) is written at once, at the end.
//!
//! Each experiment is read two ways: its norms over every sample of the densely sampled path,
//! as its task file says (the figures and files), and as the paper reads a task — eq. 15 over
//! the waypoints initial / pick / move / place (`index.over: waypoints`; the path is still
//! sampled densely for IK and continuity) — whose findings go beside the dense ones in
//! `findings.json` (`sampling` says which reading is which).

mod evidence;
mod heavy;
mod timing;

use super::select::run_task;
use crate::output::{print_summary_table, OutputArgs};
use anyhow::{Context, Result};
use clap::Args;
use graspath::output_files::{check_folder_target, write_files, Existing};
use graspath::placement::FamilyParameter;
use graspath::select::record::Trajectories;
use graspath::select::{select, Selection};
use graspath::task::Task;
use graspath::task::TaskFile;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Options of `graspath demo`.
#[derive(Debug, Args)]
pub(crate) struct DemoArgs {
    /// Where to write the experiments' results (one folder each).
    #[arg(long, value_name = "DIR", default_value = "graspath-demo")]
    out: PathBuf,
    /// Replace an existing non-empty --out folder as a whole.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    output: OutputArgs,
}

/// One experiment of the paper.
struct Experiment {
    name: &'static str,
    figure: &'static str,
    task_yaml: &'static str,
    paper_finding: &'static str,
}

/// The experiment whose bar is also carried with a mass ([`heavy`]).
const HEAVY_EXPERIMENT: &str = "pick_and_place_left";

const EXPERIMENTS: [Experiment; 6] = [
    Experiment {
        name: "pick_and_place_left",
        figure: "Fig. 5, 6, 8",
        task_yaml: include_str!("../../../../../examples/pick_and_place_left.yaml"),
        paper_finding: "left arm, object moved left: the best contact is the left-most; the classical indices at the grasp pick a different contact",
    },
    Experiment {
        name: "pick_and_place_both",
        figure: "Fig. 7",
        task_yaml: include_str!("../../../../../examples/pick_and_place_both.yaml"),
        paper_finding: "both arms: left hand on the left-most part, right hand at a mid-right contact; extreme right contacts unreachable",
    },
    Experiment {
        name: "pick_rotate_place_both",
        figure: "Fig. 9",
        task_yaml: include_str!("../../../../../examples/pick_rotate_place_both.yaml"),
        paper_finding: "both arms, rotation: still left hand on the left side and right hand on the right side",
    },
    Experiment {
        name: "t_shape_rotate",
        figure: "Fig. 10 c, d",
        task_yaml: include_str!("../../../../../examples/t_shape_rotate.yaml"),
        paper_finding: "T-shape Pick-Rotate-Place: the best of 16 yaw candidates differs from the other tasks' best",
    },
    Experiment {
        name: "t_shape_move",
        figure: "Fig. 10 e, f",
        task_yaml: include_str!("../../../../../examples/t_shape_move.yaml"),
        paper_finding: "T-shape Pick-Move-Place: a different best yaw than for rotation",
    },
    Experiment {
        name: "t_shape_move_rotate",
        figure: "Fig. 10 g, h",
        task_yaml: include_str!("../../../../../examples/t_shape_move_rotate.yaml"),
        paper_finding: "T-shape Pick-Move/Rotate-Place: the Pick-Rotate-Place grasp may not be able to do this task",
    },
];

fn label_of(selection: &Selection, arm: usize, index: usize) -> String {
    selection.arms[arm].scores[index].candidate.label.clone()
}

/// What our run found, in the terms the paper uses.
/// The best candidate's ties and the best pair's (`selection.tie_tolerance`, relative) are
/// named, so that a single "best" that beats the next by less than the tolerance is not read
/// as a finding.
fn our_finding(task: &Task, selection: &Selection) -> Value {
    let arms: Vec<Value> = selection
        .arms
        .iter()
        .enumerate()
        .map(|(k, arm)| {
            let best = arm.best().map(|i| label_of(selection, k, i));
            let tied: Vec<String> = arm
                .best()
                .map(|i| arm.tied_with(i, task.selection()))
                .unwrap_or_default()
                .into_iter()
                .filter_map(|id| arm.scores.iter().find(|s| s.candidate.id == id))
                .map(|s| s.candidate.label.clone())
                .collect();
            let by_yoshikawa = arm
                .best_by(|s| s.yoshikawa_at_grasp)
                .map(|i| label_of(selection, k, i));
            let by_inverse_condition = arm
                .best_by(|s| s.inverse_condition_at_grasp)
                .map(|i| label_of(selection, k, i));
            // The effect size: how far apart the feasible candidates' μ_l2 are, relative to
            // the largest (one decimal, in per cent, as the README quotes it).
            let l2: Vec<f64> = arm
                .scores
                .iter()
                .filter_map(|s| s.norms.map(|n| n.l2))
                .collect();
            let largest = l2.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let smallest = l2.iter().copied().fold(f64::INFINITY, f64::min);
            let spread = (largest > 0.0 && largest.is_finite())
                .then(|| format!("{:.1} %", 100.0 * (largest - smallest) / largest));
            json!({
                "arm": arm.arm,
                "feasible": arm.feasible_count(),
                "mu_l2_spread": spread,
                "candidates": arm.scores.len(),
                "best_task_relevant": best,
                "best_tied_with": tied,
                "best_yoshikawa_at_grasp": by_yoshikawa,
                "best_inverse_condition_at_grasp": by_inverse_condition,
            })
        })
        .collect();
    let pair = selection.pairs.first().map(|p| {
        json!({
            selection.arms[0].arm.clone(): p.first.label,
            selection.arms[1].arm.clone(): p.second.label,
            "score": p.score,
            "tied_with": graspath_report::tied_pairs(selection, task.selection().tie_tolerance).len(),
        })
    });
    json!({ "arms": arms, "best_pair": pair, "tie_tolerance": task.selection().tie_tolerance })
}

/// How a task file samples its path, in words.
fn sampling_of(file: &TaskFile, task: &Task) -> String {
    let t = &file.trajectory;
    let how = match (t.samples_per_step, t.samples, &t.spacing) {
        (Some(k), _, _) => format!("{k} per step"),
        (None, Some(n), _) => format!("{n} over the path"),
        (None, None, Some(_)) => "by spacing".to_string(),
        (None, None, None) => format!(
            "{} per step (default)",
            graspath::defaults::SAMPLES_PER_STEP
        ),
    };
    format!("dense: {} samples, {how}", task.path().samples.len())
}

/// The paper's reading of the task: the same file with its norms over the waypoints only
/// (the initial pose and each step's end), scored and ranked without files.
fn at_waypoints(file: &TaskFile, source: &str) -> Result<Value> {
    let mut file = file.clone();
    file.index.over = Some("waypoints".into());
    let task = Task::from_file(&file, source, Path::new("."))?;
    let selection = select(&task, &|| {})?;
    let mut ours = our_finding(&task, &selection);
    ours["sampling"] = json!(format!(
        "waypoints: {} of {} samples (the initial pose and each step's end; eq. 15 over them)",
        file.trajectory.steps.len() + 1,
        task.path().samples.len()
    ));
    Ok(ours)
}

/// Runs the subcommand.
pub(crate) fn run(args: &DemoArgs) -> Result<()> {
    let existing = Existing::replace_if(args.force);
    check_folder_target(&args.out, existing)?;
    let mut findings = Vec::new();
    let mut files = Vec::new();
    for experiment in &EXPERIMENTS {
        let source = format!("examples/{}.yaml", experiment.name);
        let file = TaskFile::parse(experiment.task_yaml, &source, "yaml")?;
        let task = Task::from_file(&file, &source, Path::new("."))?;
        let title = format!("{} ({})", experiment.name, experiment.figure);
        // With --json the demo prints one document (the findings) at the end, not one summary
        // per experiment.
        let per_run = if args.output.json {
            OutputArgs::silent()
        } else {
            args.output.clone()
        };
        let parameter = FamilyParameter::from_task_file(&file, &task.all_candidates()?);
        let run = run_task(
            &task,
            parameter.as_ref(),
            &per_run,
            &title,
            true,
            Trajectories::All,
        )
        .with_context(|| format!("experiment {}", experiment.name))?;
        if !per_run.quiet {
            print_summary_table(&task, &run.selection, &title, run.elapsed);
        }
        let selection = run.selection;
        files.extend(
            run.files
                .into_iter()
                .map(|(name, bytes)| (format!("{}/{name}", experiment.name), bytes)),
        );
        let mut ours = our_finding(&task, &selection);
        ours["sampling"] = json!(sampling_of(&file, &task));
        let waypoints = at_waypoints(&file, &source)
            .with_context(|| format!("experiment {} at its waypoints", experiment.name))?;
        if !args.output.quiet && !args.output.json {
            crate::say!("  paper: {}", experiment.paper_finding);
            crate::say!("  ours:  {}", summarise(&ours));
            crate::say!("  ours at the four waypoints: {}\n", summarise(&waypoints));
        }
        let mut finding = json!({
            "experiment": experiment.name,
            "figure": experiment.figure,
            "paper": experiment.paper_finding,
            "ours": ours,
            "ours_at_waypoints": waypoints,
        });
        let timed = timing::timing_finding(&selection);
        if !timed.is_null() {
            finding["timing"] = timed;
        }
        if experiment.name == HEAVY_EXPERIMENT {
            let light_best = selection.arms[0].best().map(|i| label_of(&selection, 0, i));
            let heavy = heavy::heavy_finding(&file, &source, light_best)
                .with_context(|| format!("experiment {}: the heavy bar", experiment.name))?;
            if !args.output.quiet && !args.output.json {
                crate::say!(
                    "  ours with the bar heavier: {}\n",
                    heavy::summarise(&heavy)
                );
            }
            finding["heavy"] = heavy;
        }
        if let Some(judge) = evidence::cuboid_judge(experiment.name) {
            finding["where_it_holds"] = evidence::cuboid_where_it_holds(&file, &source, judge)
                .with_context(|| format!("experiment {}: placement map", experiment.name))?;
        }
        findings.push(finding);
    }
    let yaml_of = |name: &'static str| {
        let experiment = EXPERIMENTS.iter().find(|e| e.name == name);
        (name, experiment.map_or("", |e| e.task_yaml))
    };
    let t_shape = evidence::TShapeTasks {
        rotate: yaml_of("t_shape_rotate"),
        moving: yaml_of("t_shape_move"),
        move_rotate: yaml_of("t_shape_move_rotate"),
    };
    let maps = evidence::t_shape_where_it_holds(&t_shape).context("T-shape placement maps")?;
    for (name, map) in maps {
        if let Some(finding) = findings
            .iter_mut()
            .find(|f| f["experiment"] == name.as_str())
        {
            finding["where_it_holds"] = map;
        }
    }
    let findings = Value::Array(findings);
    let mut bytes = serde_json::to_vec_pretty(&findings)?;
    bytes.push(b'\n');
    files.push(("findings.json".to_string(), bytes));
    write_files(&args.out, &files, existing)?;
    if args.output.json {
        crate::say!("{}", serde_json::to_string_pretty(&findings)?);
    } else if !args.output.quiet {
        crate::say!("wrote {}", args.out.display());
    }
    Ok(())
}

fn summarise(ours: &Value) -> String {
    let mut parts = Vec::new();
    for arm in ours["arms"].as_array().into_iter().flatten() {
        let tied = arm["best_tied_with"].as_array().map_or(0, Vec::len);
        let tied = match tied {
            0 => String::new(),
            n => format!(", tied with {n} other{}", if n == 1 { "" } else { "s" }),
        };
        parts.push(format!(
            "{} arm: {}/{} feasible, best {}{tied} (Yoshikawa at grasp: {}, inverse condition: {})",
            arm["arm"].as_str().unwrap_or("?"),
            arm["feasible"],
            arm["candidates"],
            arm["best_task_relevant"].as_str().unwrap_or("none"),
            arm["best_yoshikawa_at_grasp"].as_str().unwrap_or("none"),
            arm["best_inverse_condition_at_grasp"]
                .as_str()
                .unwrap_or("none"),
        ));
    }
    if let Some(pair) = ours["best_pair"].as_object() {
        let text: Vec<String> = pair
            .iter()
            .filter(|(k, _)| *k != "score" && *k != "tied_with")
            .map(|(k, v)| format!("{k} {}", v.as_str().unwrap_or("?")))
            .collect();
        parts.push(format!("best pair: {}", text.join(" + ")));
    }
    parts.join("; ")
}
