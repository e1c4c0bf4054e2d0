//! Line charts read back: the x axis is the candidate family's parameter (checked against the
//! candidates' own geometry), the axis ranges the plot model reports span the data (min and max
//! computed here from the selection's scores) without a forced zero, the range is printed on the
//! figure, each legend swatch is stroked like its series (measured on the PNG's pixels), and
//! every character of the figures' text has a glyph in the font the PNGs are drawn with.

use graspath::placement::FamilyParameter;
use graspath::select::{select, ArmResult};
use graspath::task::{Task, TaskFile};
use graspath_report::{
    figures, render_png, render_svg, Line, LinePlot, LineStyle, Plot, MARK_STYLE,
};
use std::path::PathBuf;

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A task file's task and its family parameter.
fn load(name: &str) -> (Task, Option<FamilyParameter>) {
    let path = example(name);
    let file = TaskFile::load(&path).unwrap();
    let task = Task::from_file(&file, name, path.parent().unwrap()).unwrap();
    let parameter =
        FamilyParameter::from_task_file(&file, task.candidates().held().expect("held candidates"));
    (task, parameter)
}

fn line_plot(plot: &Plot) -> &LinePlot {
    match plot {
        Plot::Line(p) => p,
        Plot::Heatmap(_) => panic!("a line chart"),
    }
}

/// Decodes a PNG into (width, height, RGB bytes).
fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buffer = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buffer).unwrap();
    buffer.truncate(info.buffer_size());
    (info.width, info.height, buffer)
}

/// The smallest and largest finite value of `values`, each divided by the largest.
fn normalised_range(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let finite = values.filter(|v| v.is_finite());
    let max = finite.clone().fold(f64::NEG_INFINITY, f64::max);
    let min = finite.fold(f64::INFINITY, f64::min);
    (min / max, 1.0)
}

/// Checks a chart's axes (from the plot model) against the data's range computed here.
fn check_axes(plot: &LinePlot, (lo, hi): (f64, f64), (x_lo, x_hi): (f64, f64)) {
    let axes = plot.axes();
    let span = hi - lo;
    assert!(span > 0.0, "{}: the data has a spread", plot.title);
    let (y0, y1) = axes.y;
    assert!(
        y0 <= lo && y1 >= hi,
        "{}: {:?} misses [{lo}, {hi}]",
        plot.title,
        axes.y
    );
    // No forced zero: the margins are small against the data's own spread.
    assert!(
        lo - y0 <= 0.1 * span && y1 - hi <= 0.15 * span,
        "{}: y axis {:?} for data [{lo}, {hi}]",
        plot.title,
        axes.y
    );
    let (a, b) = axes.x;
    let spacing = (x_hi - x_lo) / (plot.x.len() - 1) as f64;
    assert!(a < x_lo && b > x_hi && x_lo - a <= spacing && b - x_hi <= spacing);
    // The range is printed on the figure, and the printed numbers are the axis's.
    let note = plot.range_note();
    let svg = render_svg(&Plot::Line(plot.clone())).unwrap();
    assert!(svg.contains(&note), "{}: '{note}' is not drawn", plot.title);
    let numbers: Vec<f64> = note
        .trim_start_matches("y axis: ")
        .split(" to ")
        .map(|t| t.parse().unwrap())
        .collect();
    assert!(
        (numbers[0] - y0).abs() <= 1e-3 * (y1 - y0),
        "{note} vs {y0}"
    );
    assert!(
        (numbers[1] - y1).abs() <= 1e-3 * (y1 - y0),
        "{note} vs {y1}"
    );
}

#[test]
fn edge_family_charts_are_over_the_contact_position_with_ids_above() {
    let (task, parameter) = load("pick_and_place_left.yaml");
    let parameter = parameter.expect("the edge family has a parameter");
    let selection = select(&task, &|| {}).unwrap();
    let figures = figures(&task, &selection, Some(&parameter));
    let arm: &ArmResult = &selection.arms[0];
    // Oracle for x: the wrist's y in the object frame (the edge family's grasps differ only in
    // where along the edge they hold), sorted.
    let y_of = |id: usize| {
        task.candidates()
            .held()
            .expect("held candidates")
            .iter()
            .find(|c| c.id == id)
            .unwrap()
            .object_from_wrist
            .translation
            .y
    };
    let mut xs: Vec<f64> = task
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .map(|c| c.object_from_wrist.translation.y)
        .collect();
    xs.sort_by(f64::total_cmp);
    for name in ["norms-left", "classical-indices-left"] {
        let plot = line_plot(&figures.iter().find(|f| f.name == name).unwrap().plot);
        assert_eq!(plot.x_label, "contact y (m, object frame)");
        assert_eq!(plot.x.len(), xs.len());
        for (a, b) in plot.x.iter().zip(&xs) {
            assert!((a - b).abs() < 1e-12, "{name}: x {a} vs {b}");
        }
        let ids = plot.secondary.as_ref().expect("ids above the chart");
        assert_eq!(ids.name, "candidate id");
        for (x, id) in plot.x.iter().zip(&ids.labels) {
            assert!(
                (y_of(id.parse().unwrap()) - x).abs() < 1e-12,
                "{name}: id {id}"
            );
        }
        // The selected candidate is marked at its contact position.
        let best = &arm.scores[arm.best().unwrap()].candidate;
        assert!((plot.marks[0].0 - best.object_from_wrist.translation.y).abs() < 1e-12);
    }
    // Fig. 5's range from the scores: μ_l2 and μ_l∞ over the candidates with norms, each over
    // its maximum.
    let norms = line_plot(&figures[0].plot);
    let l2 = normalised_range(arm.scores.iter().filter_map(|s| s.norms.map(|n| n.l2)));
    let linf = normalised_range(arm.scores.iter().filter_map(|s| s.norms.map(|n| n.linf)));
    check_axes(norms, (l2.0.min(linf.0), 1.0), (xs[0], xs[xs.len() - 1]));
    // Fig. 8's range: the indices at the grasp of the feasible candidates over their maxima.
    let classical = line_plot(&figures[2].plot);
    let feasible = || arm.scores.iter().filter(|s| s.feasible());
    let w = normalised_range(feasible().filter_map(|s| s.yoshikawa_at_grasp));
    let c = normalised_range(feasible().filter_map(|s| s.inverse_condition_squared_at_grasp));
    check_axes(classical, (w.0.min(c.0), 1.0), (xs[0], xs[xs.len() - 1]));
}

#[test]
fn yaw_family_charts_are_over_the_yaw_in_degrees() {
    let (task, parameter) = load("t_shape_rotate.yaml");
    let parameter = parameter.expect("the yaw family has a parameter");
    let selection = select(&task, &|| {}).unwrap();
    let figures = figures(&task, &selection, Some(&parameter));
    let plot = line_plot(&figures[0].plot);
    assert_eq!(plot.x_label, "yaw (deg)");
    // Oracle: the direction the fingers close along (the wrist's y axis) turned about the
    // object's z from the object's x, in degrees, equal to x modulo a turn.
    let ids = &plot.secondary.as_ref().unwrap().labels;
    for (x, id) in plot.x.iter().zip(ids) {
        let c = task
            .candidates()
            .held()
            .expect("held candidates")
            .iter()
            .find(|c| c.id.to_string() == *id)
            .unwrap();
        let closing = c.object_from_wrist.rotation * nalgebra::Vector3::y();
        let yaw = closing.y.atan2(closing.x).to_degrees();
        let turns = (x - yaw) / 360.0;
        assert!(
            (turns - turns.round()).abs() < 1e-9,
            "id {id}: x {x} vs yaw {yaw}"
        );
    }
    assert!(plot.x.windows(2).all(|w| w[1] > w[0]));
}

#[test]
fn without_a_parameter_the_x_axis_is_the_candidate_id() {
    let (task, _) = load("pick_and_place_left.yaml");
    let selection = select(&task, &|| {}).unwrap();
    let figures = figures(&task, &selection, None);
    let plot = line_plot(&figures[0].plot);
    assert_eq!(plot.x_label, "candidate id");
    assert!(plot.secondary.is_none());
    let mut ids: Vec<f64> = task
        .candidates()
        .held()
        .expect("held candidates")
        .iter()
        .map(|c| c.id as f64)
        .collect();
    ids.sort_by(f64::total_cmp);
    assert_eq!(plot.x, ids);
}

/// Saves an image for people to look at (a test artefact under the target folder).
fn save_artifact(name: &str, bytes: &[u8]) {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    let dir = target.join("test-artifacts");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(name), bytes).unwrap();
}

/// Pixels of `colour` (within 8 per channel) as (x, y).
fn pixels_of(rgb: &[u8], width: u32, colour: [u8; 3]) -> Vec<(u32, u32)> {
    rgb.chunks(3)
        .enumerate()
        .filter(|(_, p)| (0..3).all(|k| p[k].abs_diff(colour[k]) <= 8))
        .map(|(i, _)| (i as u32 % width, i as u32 / width))
        .collect()
}

/// Runs of set cells along a 1-D mask: (lengths of the runs, lengths of the gaps between).
fn runs(mask: &[bool]) -> (Vec<usize>, Vec<usize>) {
    let (mut on, mut off) = (Vec::new(), Vec::new());
    let mut k = 0;
    while k < mask.len() {
        let start = k;
        while k < mask.len() && mask[k] == mask[start] {
            k += 1;
        }
        if mask[start] {
            on.push(k - start);
        } else if start > 0 && k < mask.len() {
            off.push(k - start);
        }
    }
    (on, off)
}

fn median(mut v: Vec<usize>) -> usize {
    v.sort_unstable();
    v.get(v.len() / 2).copied().unwrap_or(0)
}

/// The stroke a 1-D mask shows: solid (one run), dashed (runs of 6 px or more), dotted.
fn stroke_of(mask: &[bool]) -> (LineStyle, usize, usize) {
    let (on, off) = runs(mask);
    let (dash, gap) = (median(on.clone()), median(off));
    let style = if on.len() == 1 {
        LineStyle::Solid
    } else if dash >= 6 {
        LineStyle::Dashed
    } else {
        LineStyle::Dotted
    };
    (style, dash, gap)
}

/// The stroke of a group of pixels: along its longer side, the middle `keep` of it.
fn group_stroke(points: &[(u32, u32)], keep: (f64, f64)) -> (LineStyle, usize, usize) {
    let (x0, x1) = (
        points.iter().map(|p| p.0).min().unwrap(),
        points.iter().map(|p| p.0).max().unwrap(),
    );
    let (y0, y1) = (
        points.iter().map(|p| p.1).min().unwrap(),
        points.iter().map(|p| p.1).max().unwrap(),
    );
    let horizontal = x1 - x0 >= y1 - y0;
    let along = |p: &(u32, u32)| if horizontal { p.0 } else { p.1 };
    let (lo, hi) = if horizontal { (x0, x1) } else { (y0, y1) };
    let mut mask = vec![false; (hi - lo + 1) as usize];
    for p in points {
        mask[(along(p) - lo) as usize] = true;
    }
    let n = mask.len() as f64;
    stroke_of(&mask[(keep.0 * n) as usize..(keep.1 * n) as usize])
}

#[test]
fn each_legend_swatch_is_stroked_like_its_series() {
    // Horizontal lines (two x values) so a line's stroke can be read along a pixel row; the
    // marker is placed right, away from the stretch of the lines that is measured.
    let plot = LinePlot {
        title: "strokes".into(),
        x_label: "x (1)".into(),
        y_label: "y (1)".into(),
        x: vec![0.0, 10.0],
        secondary: None,
        lines: [
            (LineStyle::Solid, 0.2),
            (LineStyle::Dashed, 0.5),
            (LineStyle::Dotted, 0.8),
        ]
        .iter()
        .map(|&(style, y)| Line {
            name: format!("{style:?}"),
            values: vec![Some(y), Some(y)],
            style,
        })
        .collect(),
        marks: vec![(9.0, "mark".into())],
    };
    let png = render_png(&Plot::Line(plot.clone())).unwrap();
    save_artifact("strokes.png", &png);
    let (width, _, rgb) = decode(&png);
    let legend = plot.legend();
    assert_eq!(legend.len(), 4);
    assert_eq!(legend[3].style, MARK_STYLE);
    for entry in &legend {
        let c = entry.colour;
        let points = pixels_of(&rgb, width, [c.0, c.1, c.2]);
        // Two groups of rows separated by more than 10 px: the series above, the swatch in the
        // legend band below the x axis.
        let mut rows: Vec<u32> = points.iter().map(|p| p.1).collect();
        rows.sort_unstable();
        rows.dedup();
        let split = rows
            .windows(2)
            .find(|w| w[1] - w[0] > 10)
            .map(|w| w[1])
            .unwrap_or_else(|| panic!("{}: no swatch apart from the series", entry.name));
        assert!(
            rows.windows(2).filter(|w| w[1] - w[0] > 10).count() == 1,
            "{}: more than two groups of pixels",
            entry.name
        );
        let (series, swatch): (Vec<_>, Vec<_>) = points.iter().partition(|p| p.1 < split);
        // The series: the middle of a line (its end markers left out); the swatch: all of it.
        let keep = if entry.name == "mark" {
            (0.1, 0.9)
        } else {
            (0.15, 0.6)
        };
        let drawn = group_stroke(&series, keep);
        let shown = group_stroke(&swatch, (0.0, 1.0));
        assert_eq!(
            drawn.0, entry.style,
            "{}: the series is drawn {drawn:?}",
            entry.name
        );
        assert_eq!(
            shown.0, entry.style,
            "{}: the swatch is drawn {shown:?}",
            entry.name
        );
        if entry.style != LineStyle::Solid {
            assert!(
                drawn.1.abs_diff(shown.1) <= 2 && drawn.2.abs_diff(shown.2) <= 2,
                "{}: dash/gap {drawn:?} on the series, {shown:?} on the swatch",
                entry.name
            );
        }
    }
}

#[test]
fn small_differences_fill_the_chart_height() {
    // Values within 3 % of each other: with a y axis from zero they would span a few pixels.
    let values: Vec<Option<f64>> = (0..11).map(|i| Some(0.97 + 0.003 * i as f64)).collect();
    let plot = LinePlot {
        title: "small differences".into(),
        x_label: "x (1)".into(),
        y_label: "y (1)".into(),
        x: (0..11).map(f64::from).collect(),
        secondary: None,
        lines: vec![Line {
            name: "close values".into(),
            values,
            style: LineStyle::Solid,
        }],
        marks: Vec::new(),
    };
    let (width, height, rgb) = decode(&render_png(&Plot::Line(plot.clone())).unwrap());
    let c = plot.legend()[0].colour;
    let points = pixels_of(&rgb, width, [c.0, c.1, c.2]);
    // The series' pixels above the legend band (the lowest 60 rows).
    let rows: Vec<u32> = points
        .iter()
        .map(|p| p.1)
        .filter(|&y| y < height - 60)
        .collect();
    let extent = rows.iter().max().unwrap() - rows.iter().min().unwrap();
    assert!(
        extent as f64 > 0.5 * height as f64,
        "the line spans {extent} of {height} px"
    );
}

#[test]
fn every_character_of_the_figures_has_a_glyph_in_the_png_font() {
    use ab_glyph::Font;
    let font = ab_glyph::FontRef::try_from_slice(include_bytes!("../assets/DejaVuSans.ttf"))
        .expect("the embedded font parses");
    let mut texts = Vec::new();
    for (name, _) in [
        ("pick_and_place_both.yaml", ()),
        ("t_shape_rotate.yaml", ()),
    ] {
        let (task, parameter) = load(name);
        let selection = select(&task, &|| {}).unwrap();
        for figure in figures(&task, &selection, parameter.as_ref()) {
            match &figure.plot {
                Plot::Line(p) => {
                    texts.extend([p.title.clone(), p.x_label.clone(), p.y_label.clone()]);
                    texts.push(p.range_note());
                    texts.extend(p.legend().into_iter().map(|e| e.name));
                    texts.extend(p.secondary.iter().flat_map(|s| s.labels.clone()));
                }
                Plot::Heatmap(h) => {
                    texts.extend([h.title.clone(), h.x_label.clone(), h.y_label.clone()]);
                    texts.push(h.value_label.clone());
                    texts.extend(h.note.clone());
                    texts.extend(h.row_ticks.iter().chain(&h.column_ticks).cloned());
                }
            }
        }
    }
    let missing: std::collections::BTreeSet<char> = texts
        .iter()
        .flat_map(|t| t.chars())
        .filter(|&c| !c.is_whitespace() && font.glyph_id(c).0 == 0)
        .collect();
    assert!(missing.is_empty(), "no glyph for {missing:?}");
    // The symbols the figures are known to use are among the texts checked.
    let all: String = texts.concat();
    for symbol in ['μ', '‖', '∞', 'ᵀ', '₂', 'λ', '·'] {
        assert!(all.contains(symbol), "'{symbol}' is not in any figure text");
    }
}
