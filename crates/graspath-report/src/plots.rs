//! Rendering plots to SVG and PNG with `plotters`: line charts over the candidates (see
//! `lines`) and heatmaps with a colour bar. Text uses DejaVu Sans compiled into the binary (no system font is read),
//! and the output bytes depend only on the input.
//!
//! Heatmap layout (a contract the tests rely on): column `c` of the data is drawn at the `c`-th
//! cell from the left, row `r` at the `r`-th cell from the bottom; the colour bar is on the right.

use crate::lines::LinePlot;
use crate::style::DrawResult;
use plotters::coord::types::{RangedCoordf64, RangedCoordi32};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// The font every plot uses (DejaVu Sans; licence in `assets/DejaVuSans-LICENSE.txt`).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Size in pixels of a line chart's PNG (width, height); the SVG has the same size in px.
pub const LINE_SIZE: (u32, u32) = (800, 560);
/// Size in pixels of a heatmap's PNG (width, height).
pub const HEATMAP_SIZE: (u32, u32) = (900, 600);

/// Heatmap cells without a value (infeasible, rejected).
pub const MISSING_COLOUR: RGBColor = RGBColor(225, 225, 225);
/// Heatmap cells that are marked (e.g. two grasps that overlap).
pub const MARKED_COLOUR: RGBColor = RGBColor(110, 110, 110);

/// One cell of a [`Heatmap`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell {
    /// A value, coloured by the colour map scaled to the largest value.
    Value(f64),
    /// No value (drawn light grey).
    Missing,
    /// A marked cell (drawn dark grey with a cross).
    Marked,
}

/// A grid of values, `rows × columns`, with a colour bar.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// Title above the chart.
    pub title: String,
    /// X axis description, with its unit.
    pub x_label: String,
    /// Y axis description, with its unit.
    pub y_label: String,
    /// Colour bar description, with its unit.
    pub value_label: String,
    /// Tick text per column.
    pub column_ticks: Vec<String>,
    /// Tick text per row.
    pub row_ticks: Vec<String>,
    /// Row-major cells, `cells[r * columns + c]`; row 0 is drawn at the bottom.
    pub cells: Vec<Cell>,
    /// What the grey cells mean (shown under the chart), if any are used.
    pub note: Option<String>,
}

impl Heatmap {
    /// The number of columns.
    pub fn columns(&self) -> usize {
        self.column_ticks.len()
    }

    /// The number of rows.
    pub fn rows(&self) -> usize {
        self.row_ticks.len()
    }
}

/// A plot of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum Plot {
    /// Lines over the candidates.
    Line(LinePlot),
    /// A grid of values.
    Heatmap(Heatmap),
}

impl Plot {
    /// The size in pixels, (width, height).
    pub fn size(&self) -> (u32, u32) {
        match self {
            Plot::Line(_) => LINE_SIZE,
            Plot::Heatmap(_) => HEATMAP_SIZE,
        }
    }
}

/// Rendering a plot failed (a malformed plot, or the encoder failed).
#[derive(Debug, thiserror::Error)]
#[error("plot '{title}': {message}")]
pub struct PlotError {
    /// The plot's title.
    pub title: String,
    /// What went wrong.
    pub message: String,
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in and known to parse; a failure would leave text undrawn, and
        // the rendering then reports it.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// The viridis colour map at `t ∈ [0, 1]` (dark purple → yellow; brightness increases with `t`).
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * f).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Each plot rendered as SVG ([`render_svg`]) and as PNG ([`render_png`]), on every core, in
/// the plots' order: the same bytes as rendering them one at a time.
pub fn render_svg_and_png(plots: &[&Plot]) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    use rayon::prelude::*;
    plots
        .par_iter()
        .map(|plot| {
            let (svg, png) = rayon::join(|| render_svg(plot), || render_png(plot));
            Ok((svg?, png?))
        })
        .collect()
}

/// Renders a plot as an SVG document.
pub fn render_svg(plot: &Plot) -> Result<String, PlotError> {
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, plot.size()).into_drawing_area();
        draw(plot, &root).map_err(|e| plot_error(plot, e.to_string()))?;
        root.present()
            .map_err(|e| plot_error(plot, e.to_string()))?;
    }
    Ok(text)
}

/// Renders a plot as a PNG image (8-bit RGB, [`Plot::size`] pixels).
pub fn render_png(plot: &Plot) -> Result<Vec<u8>, PlotError> {
    register_font();
    let (w, h) = plot.size();
    let mut pixels = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (w, h)).into_drawing_area();
        draw(plot, &root).map_err(|e| plot_error(plot, e.to_string()))?;
        root.present()
            .map_err(|e| plot_error(plot, e.to_string()))?;
    }
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder
        .write_header()
        .and_then(|mut writer| writer.write_image_data(&pixels))
        .map_err(|e| plot_error(plot, format!("PNG encoding: {e}")))?;
    Ok(bytes)
}

fn plot_error(plot: &Plot, message: String) -> PlotError {
    let title = match plot {
        Plot::Line(p) => p.title.clone(),
        Plot::Heatmap(p) => p.title.clone(),
    };
    PlotError { title, message }
}

fn draw<DB: DrawingBackend>(plot: &Plot, root: &DrawingArea<DB, Shift>) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    match plot {
        Plot::Line(p) => crate::lines::draw_lines(p, root),
        Plot::Heatmap(p) => draw_heatmap(p, root),
    }
}

fn segment_label(ticks: &[String], v: &SegmentValue<i32>) -> String {
    match v {
        SegmentValue::CenterOf(i) => usize::try_from(*i)
            .ok()
            .and_then(|i| ticks.get(i))
            .cloned()
            .unwrap_or_default(),
        _ => String::new(),
    }
}

fn draw_heatmap<DB: DrawingBackend>(p: &Heatmap, root: &DrawingArea<DB, Shift>) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (columns, rows) = (p.columns(), p.rows());
    if columns == 0 || rows == 0 || p.cells.len() != columns * rows {
        return Err(format!(
            "{} cells do not fill {rows} rows x {columns} columns (none may be empty)",
            p.cells.len()
        )
        .into());
    }
    let max = p
        .cells
        .iter()
        .filter_map(|c| match c {
            Cell::Value(v) if v.is_finite() => Some(*v),
            _ => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    let min = p
        .cells
        .iter()
        .filter_map(|c| match c {
            Cell::Value(v) if v.is_finite() => Some(*v),
            _ => None,
        })
        .fold(f64::INFINITY, f64::min);
    let (width, height) = root.dim_in_pixel();
    let (main, side) = root.split_horizontally(width.saturating_sub(130));
    let (main, note_area) = main.split_vertically(height.saturating_sub(26));
    // Room for the longest row tick (about 8 px a character at 13 px) and the description.
    let longest = p
        .row_ticks
        .iter()
        .map(|t| t.chars().count())
        .max()
        .unwrap_or(0);
    let mut chart = ChartBuilder::on(&main)
        .caption(&p.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size((30 + 8 * longest as u32).max(70))
        .build_cartesian_2d(
            // Segmented ranges include their end: one segment per column and row.
            (0..columns as i32 - 1).into_segmented(),
            (0..rows as i32 - 1).into_segmented(),
        )?;
    let x_format = |v: &SegmentValue<i32>| segment_label(&p.column_ticks, v);
    let y_format = |v: &SegmentValue<i32>| segment_label(&p.row_ticks, v);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .x_labels(columns.min(16))
        .y_labels(rows.min(22))
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .draw()?;
    let cell_rect = |c: usize, r: usize| {
        [
            (
                SegmentValue::Exact(c as i32),
                SegmentValue::Exact(r as i32 + 1),
            ),
            (
                SegmentValue::Exact(c as i32 + 1),
                SegmentValue::Exact(r as i32),
            ),
        ]
    };
    let span = (max - min).max(f64::MIN_POSITIVE);
    let unit = |v: f64| {
        if max.is_finite() {
            (v - min) / span
        } else {
            0.0
        }
    };
    chart.draw_series(
        (0..rows)
            .flat_map(|r| (0..columns).map(move |c| (r, c)))
            .map(|(r, c)| {
                let colour = match p.cells[r * columns + c] {
                    Cell::Value(v) if v.is_finite() => viridis(unit(v)),
                    Cell::Value(_) | Cell::Missing => MISSING_COLOUR,
                    Cell::Marked => MARKED_COLOUR,
                };
                Rectangle::new(cell_rect(c, r), colour.filled())
            }),
    )?;
    // A cross over each marked cell.
    let cross = |c: usize, r: usize| {
        let (x0, x1) = (
            SegmentValue::Exact(c as i32),
            SegmentValue::Exact(c as i32 + 1),
        );
        let (y0, y1) = (
            SegmentValue::Exact(r as i32),
            SegmentValue::Exact(r as i32 + 1),
        );
        [
            PathElement::new(
                vec![(x0.clone(), y0.clone()), (x1.clone(), y1.clone())],
                WHITE,
            ),
            PathElement::new(vec![(x0, y1), (x1, y0)], WHITE),
        ]
    };
    chart.draw_series(
        (0..rows)
            .flat_map(|r| (0..columns).map(move |c| (r, c)))
            .filter(|&(r, c)| p.cells[r * columns + c] == Cell::Marked)
            .flat_map(|(r, c)| cross(c, r)),
    )?;
    if let Some(note) = &p.note {
        note_area.draw_text(
            note,
            &("sans-serif", 13).into_text_style(&note_area),
            (80, 4),
        )?;
    }
    draw_colour_bar(p, &side, min, max)
}

/// The colour bar: the colour map from the smallest to the largest value, labelled.
fn draw_colour_bar<DB: DrawingBackend>(
    p: &Heatmap,
    area: &DrawingArea<DB, Shift>,
    min: f64,
    max: f64,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (lo, hi) = if min.is_finite() && max > min {
        (min, max)
    } else if max.is_finite() {
        (max - 0.5, max + 0.5)
    } else {
        (0.0, 1.0)
    };
    let mut bar: ChartContext<DB, Cartesian2d<RangedCoordi32, RangedCoordf64>> =
        ChartBuilder::on(area)
            .margin_top(50)
            .margin_bottom(86)
            .margin_right(70)
            .y_label_area_size(0)
            .right_y_label_area_size(8)
            .build_cartesian_2d(0..1, lo..hi)?;
    const STEPS: usize = 200;
    bar.draw_series((0..STEPS).map(|k| {
        let a = lo + (hi - lo) * k as f64 / STEPS as f64;
        let b = lo + (hi - lo) * (k + 1) as f64 / STEPS as f64;
        let colour = viridis((k as f64 + 0.5) / STEPS as f64);
        Rectangle::new([(0, b), (1, a)], colour.filled())
    }))?;
    let ticks = 5;
    let text = ("sans-serif", 13).into_text_style(area);
    for k in 0..=ticks {
        let v = lo + (hi - lo) * k as f64 / ticks as f64;
        let (x, y) = bar.backend_coord(&(1, v));
        let (ox, oy) = area.get_base_pixel();
        area.draw(&PathElement::new(
            vec![(x - ox, y - oy), (x - ox + 5, y - oy)],
            BLACK,
        ))?;
        area.draw_text(&format_tick(v), &text, (x - ox + 8, y - oy - 7))?;
    }
    let desc = ("sans-serif", 14)
        .into_text_style(area)
        .transform(FontTransform::Rotate270);
    let (w, h) = area.dim_in_pixel();
    area.draw_text(&p.value_label, &desc, (w as i32 - 22, h as i32 / 2 + 80))?;
    Ok(())
}

fn format_tick(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e4).contains(&a) {
        format!("{v:.2e}")
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
    }
}
