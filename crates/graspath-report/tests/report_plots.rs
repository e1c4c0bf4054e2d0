//! Plots: the PNGs decode at their stated size, the bytes are deterministic, a heatmap's
//! brightest cell is where the data's maximum is, and the figures of a real selection carry
//! the values of the selection.

use graspath::select::select;
use graspath::task::Task;
use graspath_report::{
    figures, render_png, render_svg, render_svg_and_png, Cell, Heatmap, Line, LinePlot, LineStyle,
    Plot, HEATMAP_SIZE, LINE_SIZE,
};
use std::path::PathBuf;

/// Decodes a PNG into (width, height, RGB bytes).
fn decode(bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().expect("a PNG header");
    let mut buffer = vec![0; reader.output_buffer_size().expect("a known size")];
    let info = reader.next_frame(&mut buffer).expect("PNG data");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buffer.truncate(info.buffer_size());
    (info.width, info.height, buffer)
}

/// A heatmap of `rows × columns` whose values are small except one cell.
fn synthetic_heatmap(rows: usize, columns: usize, max_at: (usize, usize)) -> Heatmap {
    let cells = (0..rows)
        .flat_map(|r| (0..columns).map(move |c| (r, c)))
        .map(|(r, c)| {
            if (r, c) == max_at {
                Cell::Value(10.0)
            } else {
                Cell::Value(1.0 + 0.1 * ((r * columns + c) % 7) as f64)
            }
        })
        .collect();
    Heatmap {
        title: "synthetic".into(),
        x_label: "column".into(),
        y_label: "row".into(),
        value_label: "value (1)".into(),
        column_ticks: (0..columns).map(|c| c.to_string()).collect(),
        row_ticks: (0..rows).map(|r| r.to_string()).collect(),
        cells,
        note: None,
    }
}

/// The cell (row from the bottom, column from the left) holding the brightest coloured pixel
/// of the chart area. Oracle: the image alone — the chart area is the bounding box of the
/// coloured (saturated) pixels left of the colour bar, which the layout puts in the right-most
/// fifth of the image; brightness is the sum of the channels, which viridis increases.
fn brightest_cell(png: &[u8], rows: usize, columns: usize) -> ((usize, usize), [u8; 3]) {
    let (w, h, rgb) = decode(png);
    let pixel = |x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        [rgb[i], rgb[i + 1], rgb[i + 2]]
    };
    let saturated = |p: [u8; 3]| {
        let (max, min) = (p.iter().max().unwrap(), p.iter().min().unwrap());
        max - min > 40
    };
    let (mut x0, mut x1, mut y0, mut y1) = (u32::MAX, 0, u32::MAX, 0);
    let mut best = (0u32, 0u32, 0u32, [0u8; 3]);
    for y in 0..h {
        for x in 0..(w * 4 / 5) {
            let p = pixel(x, y);
            if !saturated(p) {
                continue;
            }
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
            let brightness = p.iter().map(|&v| v as u32).sum::<u32>();
            if brightness > best.0 {
                best = (brightness, x, y, p);
            }
        }
    }
    let (_, x, y, colour) = best;
    let column = ((x - x0) as usize * columns) / (x1 - x0 + 1) as usize;
    let row = ((y1 - y) as usize * rows) / (y1 - y0 + 1) as usize;
    ((row, column), colour)
}

#[test]
fn heatmap_brightest_cell_is_the_maximum() {
    for (rows, columns, max_at) in [(4, 5, (2, 3)), (6, 3, (0, 0)), (3, 7, (2, 6))] {
        let plot = Plot::Heatmap(synthetic_heatmap(rows, columns, max_at));
        let png = render_png(&plot).unwrap();
        let (w, h, _) = decode(&png);
        assert_eq!((w, h), HEATMAP_SIZE);
        let (cell, colour) = brightest_cell(&png, rows, columns);
        assert_eq!(cell, max_at, "{rows}x{columns}");
        // Viridis' top colour, #fde725 (its published end point).
        let expected = [0xfd, 0xe7, 0x25];
        for k in 0..3 {
            assert!(colour[k].abs_diff(expected[k]) <= 3, "{colour:?}");
        }
    }
}

fn line_plot() -> Plot {
    Plot::Line(LinePlot {
        title: "two lines".into(),
        x_label: "candidate id".into(),
        y_label: "norm / its maximum (1)".into(),
        x: (0..10).map(f64::from).collect(),
        secondary: None,
        lines: vec![
            Line {
                name: "rising".into(),
                values: (0..10).map(|i| Some(i as f64 / 9.0)).collect(),
                style: LineStyle::Solid,
            },
            Line {
                name: "with a gap".into(),
                values: (0..10)
                    .map(|i| (i != 4).then_some(1.0 - i as f64 / 20.0))
                    .collect(),
                style: LineStyle::Dashed,
            },
        ],
        marks: vec![(9.0, "selected: 9".into())],
    })
}

#[test]
fn plots_rendered_together_on_every_core_are_the_ones_rendered_alone() {
    let plots = [
        Plot::Heatmap(synthetic_heatmap(4, 5, (2, 3))),
        line_plot(),
        Plot::Heatmap(synthetic_heatmap(3, 7, (2, 6))),
        line_plot(),
    ];
    let refs: Vec<&Plot> = plots.iter().collect();
    let together = render_svg_and_png(&refs).unwrap();
    assert_eq!(together.len(), plots.len());
    for (plot, (svg, png)) in plots.iter().zip(&together) {
        assert!(*svg == render_svg(plot).unwrap(), "SVG differs");
        assert!(*png == render_png(plot).unwrap(), "PNG differs");
    }
}

#[test]
fn line_plots_render_deterministically_at_their_size() {
    let plot = line_plot();
    let a = render_png(&plot).unwrap();
    let b = render_png(&plot).unwrap();
    assert_eq!(a, b, "PNG bytes differ between two renderings");
    let (w, h, rgb) = decode(&a);
    assert_eq!((w, h), LINE_SIZE);
    // Not blank: dark pixels (axes, text) and both series colours are present.
    let has = |target: [u8; 3]| {
        rgb.chunks(3)
            .any(|p| (0..3).all(|k| p[k].abs_diff(target[k]) <= 2))
    };
    assert!(has([31, 119, 180]), "the first series' blue is missing");
    assert!(has([214, 39, 40]), "the second series' red is missing");
    let svg = render_svg(&plot).unwrap();
    assert_eq!(svg, render_svg(&plot).unwrap());
    for text in [
        "two lines",
        "candidate id",
        "norm / its maximum (1)",
        "selected: 9",
    ] {
        assert!(svg.contains(text), "the SVG lacks '{text}'");
    }
    assert!(svg.starts_with("<svg"));
}

#[test]
fn malformed_plots_are_errors_naming_the_plot() {
    let mut heatmap = synthetic_heatmap(2, 2, (0, 0));
    heatmap.cells.pop();
    let error = render_png(&Plot::Heatmap(heatmap)).unwrap_err();
    assert!(error.to_string().contains("synthetic"), "{error}");
}

fn example(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

#[test]
fn figures_of_a_selection_carry_its_values() {
    let task = Task::load(&example("pick_and_place_left.yaml")).unwrap();
    let selection = select(&task, &|| {}).unwrap();
    let figures = figures(&task, &selection, None);
    let names: Vec<&str> = figures.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        ["norms-left", "mt-heatmap-left", "classical-indices-left"]
    );
    let arm = &selection.arms[0];
    // Fig. 5: μ_l2 normalised by its maximum over the feasible candidates, from the scores.
    let Plot::Line(norms) = &figures[0].plot else {
        panic!("norms is a line plot")
    };
    let l2 = norms
        .lines
        .iter()
        .find(|l| l.name.starts_with("μ_l2"))
        .unwrap();
    let max = arm
        .scores
        .iter()
        .filter_map(|s| s.norms.map(|n| n.l2))
        .fold(0.0, f64::max);
    for (s, v) in arm.scores.iter().zip(&l2.values) {
        match (s.norms, v) {
            (Some(n), Some(v)) => assert!((n.l2 / max - v).abs() < 1e-12),
            (None, None) => {}
            other => panic!("candidate {}: {other:?}", s.candidate.id),
        }
    }
    let best = arm.best().unwrap();
    assert_eq!(
        norms.marks[0].0,
        task.candidates().held().expect("held candidates")[best].id as f64
    );
    // Fig. 6: one row per candidate, one column per sample, M_T where feasible.
    let Plot::Heatmap(m_t) = &figures[1].plot else {
        panic!("M_T is a heatmap")
    };
    assert_eq!(m_t.rows(), task.candidate_count());
    assert_eq!(m_t.columns(), task.path().samples.len());
    for (r, s) in arm.scores.iter().enumerate() {
        for c in 0..m_t.columns() {
            let expected = match (s.feasible(), s.m_t.get(c).copied().flatten()) {
                (true, Some(v)) => Cell::Value(v),
                _ => Cell::Missing,
            };
            assert_eq!(m_t.cells[r * m_t.columns() + c], expected);
        }
    }
    for figure in &figures {
        let png = render_png(&figure.plot).unwrap();
        assert_eq!(decode(&png).0, figure.plot.size().0);
    }
}

#[test]
fn the_pair_heatmap_sums_eligible_norms_and_marks_overlaps() {
    let task = Task::load(&example("pick_and_place_both.yaml")).unwrap();
    let selection = select(&task, &|| {}).unwrap();
    let figures = figures(&task, &selection, None);
    let pairs = figures.iter().find(|f| f.name == "pairs-heatmap").unwrap();
    let Plot::Heatmap(h) = &pairs.plot else {
        panic!("a heatmap")
    };
    let (a, b) = (&selection.arms[0], &selection.arms[1]);
    assert_eq!((h.rows(), h.columns()), (a.scores.len(), b.scores.len()));
    // Oracle: every listed best pair is a valued cell holding its score, and the best pair's
    // cell is the largest value.
    let row = |c: &std::sync::Arc<graspath::grasp::Candidate>| {
        task.candidates()
            .held()
            .expect("held candidates")
            .iter()
            .position(|t| std::sync::Arc::ptr_eq(t, c))
            .expect("a pair's candidates are the task's")
    };
    for p in &selection.pairs {
        match h.cells[row(&p.first) * h.columns() + row(&p.second)] {
            Cell::Value(v) => assert!((v - p.score).abs() < 1e-12),
            other => panic!("pair {p:?} is {other:?}"),
        }
    }
    let largest = h
        .cells
        .iter()
        .filter_map(|c| match c {
            Cell::Value(v) => Some(*v),
            _ => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(largest, selection.pairs[0].score);
    // A candidate paired with itself overlaps when both arms may use it.
    for i in 0..h.rows().min(h.columns()) {
        if a.rankings[i].score.is_some() && b.rankings[i].score.is_some() {
            assert_eq!(h.cells[i * h.columns() + i], Cell::Marked, "candidate {i}");
        }
    }
}
