//! The self-contained HTML report: the template `assets/report.html` with the 3D view's data
//! (JSON), three.js and the figures (inline SVG) put in, so the one file works offline from
//! `file://`. Opening it with `#selftest` runs the page's own checks (see the template).

use crate::figures::{figures, Figure};
use crate::plots::{render_svg_and_png, Plot, PlotError};
use crate::scene::scene_json;
use crate::stage::{stage, stage_json};
use graspath::placement::FamilyParameter;
use graspath::select::Selection;
use graspath::task::Task;

const TEMPLATE: &str = include_str!("../assets/report.html");
/// three.js r170, the single-file module build (MIT; `assets/three-LICENSE.txt`).
const THREE: &str = include_str!("../assets/three.module.min.js");
const THREE_LICENSE: &str = include_str!("../assets/three-LICENSE.txt");

/// Text safe inside HTML element content and attribute values.
fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// JSON safe inside a `<script>` element: `<` is written as `\u003c` (valid JSON, and no
/// `</script>` can end the element early).
fn script_json(value: &serde_json::Value) -> String {
    value.to_string().replace('<', "\\u003c")
}

/// Heatmaps with more cells than this are put in the page as PNG (an SVG of that many
/// rectangles is slow to show and large).
pub const INLINE_SVG_MAX_CELLS: usize = 5000;

/// Standard base64 (RFC 4648, with padding).
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[((n >> (18 - 6 * k)) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// How a figure appears in the page: inline SVG markup, or an `<img>` of its PNG.
pub enum Inline {
    /// The SVG document.
    Svg(String),
    /// The PNG bytes.
    Png(Vec<u8>),
}

/// The HTML page for a selection whose figures are already rendered.
pub fn report_html(task: &Task, selection: &Selection, figures: &[(Figure, Inline)]) -> String {
    let mut plots = String::new();
    let sentences = crate::text::findings_sentences(task, selection);
    if !sentences.is_empty() {
        plots.push_str("<ul id=\"findings\">\n");
        for s in sentences {
            plots.push_str(&format!("<li>{}</li>\n", escape_html(&s)));
        }
        plots.push_str("</ul>\n");
    }
    for (figure, inline) in figures {
        let body = match inline {
            Inline::Svg(svg) => svg.clone(),
            Inline::Png(png) => format!(
                "<img alt=\"{}\" src=\"data:image/png;base64,{}\">",
                escape_html(&figure.caption),
                base64(png)
            ),
        };
        plots.push_str(&format!(
            "<figure id=\"fig-{name}\">\n{body}\n<figcaption>{caption} \
             <a href=\"{name}.png\">PNG</a> · <a href=\"{name}.svg\">SVG</a></figcaption>\n</figure>\n",
            name = escape_html(&figure.name),
            caption = escape_html(&figure.caption),
        ));
    }
    let title = format!("graspath report — {}", task.source_name());
    let licence = format!(
        "/* three.js r170 — {} */",
        THREE_LICENSE
            .replace("*/", "* /")
            .lines()
            .collect::<Vec<_>>()
            .join(" ")
    );
    TEMPLATE
        .replace("@TITLE@", &escape_html(&title))
        .replace("<!--@PLOTS@-->", &plots)
        .replace("/*@DATA@*/", &script_json(&scene_json(task, selection)))
        .replace(
            "/*@STAGE@*/",
            &script_json(&stage_json(&stage(task, selection))),
        )
        .replace("/*@THREE@*/", &format!("{licence}\n{THREE}"))
}

/// Every report file of a selection besides the JSON documents: each figure as `NAME.svg` and
/// `NAME.png`, and `report.html`. Rendered in memory; nothing is written. `parameter` is the
/// candidate family's parameter, the x axis of the line charts (see [`figures`]).
pub fn render_report(
    task: &Task,
    selection: &Selection,
    parameter: Option<&FamilyParameter>,
) -> Result<Vec<(String, Vec<u8>)>, PlotError> {
    let mut files = Vec::new();
    let mut rendered = Vec::new();
    let figures = figures(task, selection, parameter);
    let plots: Vec<&Plot> = figures.iter().map(|figure| &figure.plot).collect();
    let images = render_svg_and_png(&plots)?;
    for (figure, (svg, png)) in figures.into_iter().zip(images) {
        let inline = match &figure.plot {
            Plot::Heatmap(h) if h.cells.len() > INLINE_SVG_MAX_CELLS => Inline::Png(png.clone()),
            _ => Inline::Svg(svg.clone()),
        };
        files.push((format!("{}.svg", figure.name), svg.into_bytes()));
        files.push((format!("{}.png", figure.name), png));
        rendered.push((figure, inline));
    }
    let html = report_html(task, selection, &rendered);
    files.push(("report.html".to_string(), html.into_bytes()));
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (plain, encoded) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(plain.as_bytes()), encoded);
        }
    }

    #[test]
    fn script_json_cannot_close_the_script_element() {
        let v = serde_json::json!({"label": "</script><b>"});
        let s = script_json(&v);
        assert!(!s.contains('<'));
        let back: serde_json::Value = serde_json::from_str(&s).unwrap();
        assert_eq!(back, v);
    }

    #[test]
    fn the_template_has_every_placeholder() {
        for marker in [
            "@TITLE@",
            "<!--@PLOTS@-->",
            "/*@DATA@*/",
            "/*@STAGE@*/",
            "/*@THREE@*/",
        ] {
            assert!(TEMPLATE.contains(marker), "{marker}");
        }
        assert!(!THREE.contains("</script"));
    }
}
