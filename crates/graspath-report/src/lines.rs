//! Line charts over the candidates: the plot model (axis ranges, legend entries, line styles)
//! and its rendering. The model is what the renderer draws from — [`LinePlot::axes`] is the
//! range of the PNG's and SVG's axes, and each series' legend swatch is drawn with the same
//! [`LineStyle::pattern`] as its line — so tests can read the figure's ranges and styles back
//! from the model.
//!
//! Layout: the title on top, the candidates' secondary labels (ids) in a row above the plotting
//! area, the y range printed at the top right of the plotting area, and the legend in its own
//! band under the x axis (it never hides data).

use crate::style::{DrawResult, PALETTE};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// How a series is stroked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineStyle {
    /// A continuous line.
    Solid,
    /// Dashes of 9 px with 5 px gaps.
    Dashed,
    /// Dots: 2 px dashes with 4 px gaps.
    Dotted,
}

impl LineStyle {
    /// The stroke's (dash, gap) lengths in pixels; `None` for a solid line. Lines and their
    /// legend swatches are both drawn with this pattern.
    pub fn pattern(self) -> Option<(u32, u32)> {
        match self {
            LineStyle::Solid => None,
            LineStyle::Dashed => Some((9, 5)),
            LineStyle::Dotted => Some((2, 4)),
        }
    }
}

/// The style of the vertical markers ([`LinePlot::marks`]).
pub const MARK_STYLE: LineStyle = LineStyle::Dotted;

/// Stroke width of lines and swatches (px).
const STROKE: u32 = 2;

/// One line of a [`LinePlot`].
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Legend text.
    pub name: String,
    /// One value per x; `None` leaves a gap.
    pub values: Vec<Option<f64>>,
    /// How the line is stroked (its legend swatch uses the same style).
    pub style: LineStyle,
}

/// Text labels of the x positions on a second axis above the chart (e.g. candidate ids when
/// the x axis is a family's parameter).
#[derive(Debug, Clone, PartialEq)]
pub struct SecondaryLabels {
    /// What the labels are (`candidate id`).
    pub name: String,
    /// One label per x, in the order of [`LinePlot::x`].
    pub labels: Vec<String>,
}

/// A chart of lines over a shared x axis, with optional vertical markers.
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    /// Title above the chart.
    pub title: String,
    /// X axis description, with its unit.
    pub x_label: String,
    /// Y axis description, with its unit.
    pub y_label: String,
    /// The x coordinates, increasing.
    pub x: Vec<f64>,
    /// Labels of the x positions shown above the chart, if any.
    pub secondary: Option<SecondaryLabels>,
    /// The lines.
    pub lines: Vec<Line>,
    /// Vertical markers `(x, legend text)`, drawn in [`MARK_STYLE`].
    pub marks: Vec<(f64, String)>,
}

/// The ranges of a line chart's axes, as drawn: `(low, high)` in data units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    /// The x axis.
    pub x: (f64, f64),
    /// The y axis.
    pub y: (f64, f64),
}

/// One legend entry: the text, the colour and the stroke its swatch is drawn with.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    /// The legend text.
    pub name: String,
    /// The colour of the series and of its swatch.
    pub colour: RGBColor,
    /// The stroke of the series and of its swatch.
    pub style: LineStyle,
}

impl LinePlot {
    /// The axis ranges drawn. x: the data's range plus half the mean spacing of the x values on
    /// each side. y: the smallest to the largest finite value of the lines, widened by 6 % of
    /// their span below and 10 % above (not forced to include zero, so differences show); a
    /// span under 1e-9 of the values' size is widened to that.
    pub fn axes(&self) -> Axes {
        let x = match (self.x.first(), self.x.last()) {
            (Some(&a), Some(&b)) if b > a => {
                let pad = 0.5 * (b - a) / (self.x.len() - 1) as f64;
                (a - pad, b + pad)
            }
            (Some(&a), _) => (a - 1.0, a + 1.0),
            _ => (0.0, 1.0),
        };
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in self
            .lines
            .iter()
            .flat_map(|l| l.values.iter().flatten())
            .filter(|v| v.is_finite())
        {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
        let y = if lo.is_finite() {
            let span = (hi - lo).max(1e-9 * hi.abs().max(lo.abs()).max(1.0));
            (lo - 0.06 * span, hi + 0.10 * span)
        } else {
            (0.0, 1.0)
        };
        Axes { x, y }
    }

    /// The legend: every line, then every marker, with the colour and stroke it is drawn with.
    pub fn legend(&self) -> Vec<LegendEntry> {
        let lines = self.lines.iter().enumerate().map(|(k, l)| LegendEntry {
            name: l.name.clone(),
            colour: PALETTE[k % PALETTE.len()],
            style: l.style,
        });
        let marks = self
            .marks
            .iter()
            .enumerate()
            .map(|(k, (_, name))| LegendEntry {
                name: name.clone(),
                colour: PALETTE[(self.lines.len() + k) % PALETTE.len()],
                style: MARK_STYLE,
            });
        lines.chain(marks).collect()
    }

    /// The text printed on the chart about the y axis: its range as drawn, with decimals to
    /// a thousandth of the range.
    pub fn range_note(&self) -> String {
        let (lo, hi) = self.axes().y;
        let decimals = (3 - (hi - lo).log10().floor() as i32).clamp(0, 12) as usize;
        format!("y axis: {lo:.decimals$} to {hi:.decimals$}")
    }
}

/// Decimals for ticks over a span: enough to tell ticks a tenth of the span apart.
fn tick_decimals(span: f64) -> usize {
    if span > 0.0 && span.is_finite() {
        (1 - span.log10().floor() as i32).clamp(0, 6) as usize
    } else {
        2
    }
}

/// A tick's text with `decimals` decimals; a value that rounds to zero is `0`, not `-0`.
fn tick(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        format!("{:.decimals$}", 0.0)
    } else {
        text
    }
}

/// Draws a path with a style's pattern (solid, dashed, dotted) in data or pixel coordinates.
macro_rules! stroke {
    ($target:expr, $points:expr, $style:expr, $shape:expr) => {
        match $style.pattern() {
            None => $target.draw(&PathElement::new($points, $shape)),
            Some((on, off)) => $target.draw(&DashedPathElement::new($points, on, off, $shape)),
        }
    };
}

/// Height of the legend band under the chart: one row per two entries (px).
fn legend_height(entries: usize) -> u32 {
    12 + 22 * entries.div_ceil(2) as u32
}

pub(crate) fn draw_lines<DB: DrawingBackend>(
    p: &LinePlot,
    root: &DrawingArea<DB, Shift>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    if p.lines.iter().any(|l| l.values.len() != p.x.len()) {
        return Err("every line needs one value per x".into());
    }
    if let Some(s) = &p.secondary {
        if s.labels.len() != p.x.len() {
            return Err("the secondary labels need one label per x".into());
        }
    }
    if !p.x.iter().all(|v| v.is_finite()) || p.x.windows(2).any(|w| w[1] <= w[0]) {
        return Err("x must be finite and increasing".into());
    }
    let legend = p.legend();
    let (_, height) = root.dim_in_pixel();
    let (upper, legend_area) =
        root.split_vertically(height.saturating_sub(legend_height(legend.len())));
    let Axes {
        x: (x0, x1),
        y: (y0, y1),
    } = p.axes();
    let upper = upper.titled(&p.title, ("sans-serif", 20))?;
    let mut chart = ChartBuilder::on(&upper)
        .margin(12)
        // Room between the title and the chart for the secondary labels.
        .margin_top(if p.secondary.is_some() { 28 } else { 4 })
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let x_decimals = tick_decimals(x1 - x0);
    let y_decimals = tick_decimals(y1 - y0);
    chart
        .configure_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(RGBColor(240, 240, 240))
        .x_label_formatter(&|v| tick(*v, x_decimals))
        .y_label_formatter(&|v| tick(*v, y_decimals))
        .draw()?;
    for (line, entry) in p.lines.iter().zip(&legend) {
        let shape = entry.colour.stroke_width(STROKE);
        // Contiguous runs of values, so a missing value leaves a gap.
        let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for (x, v) in p.x.iter().zip(&line.values) {
            match v {
                Some(v) if v.is_finite() => runs.last_mut().expect("non-empty").push((*x, *v)),
                _ => runs.push(Vec::new()),
            }
        }
        let area = chart.plotting_area();
        for run in runs.iter().filter(|r| r.len() > 1) {
            stroke!(area, run.clone(), entry.style, shape)?;
        }
        let points = runs.into_iter().flatten();
        chart.draw_series(points.map(|(x, y)| Circle::new((x, y), 3, entry.colour.filled())))?;
    }
    for ((x, _), entry) in p.marks.iter().zip(&legend[p.lines.len()..]) {
        let shape = entry.colour.stroke_width(STROKE);
        stroke!(
            chart.plotting_area(),
            vec![(*x, y0), (*x, y1)],
            entry.style,
            shape
        )?;
    }
    // The y range, at the top right of the plotting area.
    let ((left, top), (right, _)) = (
        chart.backend_coord(&(x0, y1)),
        chart.backend_coord(&(x1, y1)),
    );
    let small = ("sans-serif", 13).into_text_style(root);
    let note = p.range_note();
    let (w, _) = root.estimate_text_size(&note, &small)?;
    root.draw_text(&note, &small, (right - w as i32 - 6, top + 4))?;
    // The secondary labels: a tick and the label above each x, thinned to 26 px apart.
    if let Some(s) = &p.secondary {
        let mut last: Option<i32> = None;
        for (x, label) in p.x.iter().zip(&s.labels) {
            let (px, _) = chart.backend_coord(&(*x, y1));
            let (lw, _) = root.estimate_text_size(label, &small)?;
            if last.is_some_and(|last| px - last < 26.max(lw as i32 + 6)) {
                continue;
            }
            last = Some(px);
            root.draw(&PathElement::new(vec![(px, top - 4), (px, top)], BLACK))?;
            root.draw_text(label, &small, (px - lw as i32 / 2, top - 20))?;
        }
        let (nw, _) = root.estimate_text_size(&s.name, &small)?;
        root.draw_text(&s.name, &small, (left - nw as i32 - 8, top - 20))?;
    }
    draw_legend(&legend, &legend_area)
}

/// The legend band: two entries a row, each a 36 px swatch stroked like its series.
fn draw_legend<DB: DrawingBackend>(
    legend: &[LegendEntry],
    area: &DrawingArea<DB, Shift>,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (width, _) = area.dim_in_pixel();
    let text = ("sans-serif", 14).into_text_style(area);
    let column = (width as i32 - 100) / 2;
    for (k, entry) in legend.iter().enumerate() {
        let x = 90 + column * (k as i32 % 2);
        let y = 8 + 22 * (k as i32 / 2) + 8;
        let shape = entry.colour.stroke_width(STROKE);
        stroke!(area, vec![(x, y), (x + 36, y)], entry.style, shape)?;
        area.draw_text(&entry.name, &text, (x + 44, y - 8))?;
    }
    Ok(())
}
