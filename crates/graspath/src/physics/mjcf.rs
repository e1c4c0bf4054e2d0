//! A small MJCF writer: elements with attributes, numbers written so that they read back to the
//! same `f64` (Rust's shortest round-trip form), names escaped.

use nalgebra::{Isometry3, Matrix3, UnitQuaternion, Vector3};
use std::fmt::Write;

/// An XML document written element by element, indented two spaces per level.
#[derive(Debug, Default)]
pub(super) struct Xml {
    text: String,
    depth: usize,
}

/// One attribute value.
pub(super) enum Value<'a> {
    /// Text, escaped.
    Text(&'a str),
    /// Numbers separated by spaces, each in its shortest round-trip form.
    Numbers(Vec<f64>),
}

impl From<&'static str> for Value<'_> {
    fn from(text: &'static str) -> Self {
        Value::Text(text)
    }
}

impl From<f64> for Value<'_> {
    fn from(value: f64) -> Self {
        Value::Numbers(vec![value])
    }
}

impl From<Vec<f64>> for Value<'_> {
    fn from(values: Vec<f64>) -> Self {
        Value::Numbers(values)
    }
}

/// A name attribute's value.
pub(super) fn name(text: &str) -> Value<'_> {
    Value::Text(text)
}

/// `pos` and `quat` (`w x y z`) of a pose.
pub(super) fn placement(pose: &Isometry3<f64>) -> [(&'static str, Value<'static>); 2] {
    let t = pose.translation.vector;
    let q = pose.rotation.quaternion();
    [
        ("pos", Value::Numbers(vec![t.x, t.y, t.z])),
        ("quat", Value::Numbers(vec![q.w, q.i, q.j, q.k])),
    ]
}

/// The pose with rotation `rotation` (a rotation matrix) and translation `translation`.
pub(super) fn pose_of(rotation: &Matrix3<f64>, translation: &Vector3<f64>) -> Isometry3<f64> {
    Isometry3::from_parts((*translation).into(), UnitQuaternion::from_matrix(rotation))
}

impl Xml {
    /// An empty document.
    pub(super) fn new() -> Self {
        Self::default()
    }

    fn start(&mut self, tag: &str, attributes: &[(&str, Value<'_>)]) {
        for _ in 0..self.depth {
            self.text.push_str("  ");
        }
        self.text.push('<');
        self.text.push_str(tag);
        for (key, value) in attributes {
            self.text.push(' ');
            self.text.push_str(key);
            self.text.push_str("=\"");
            match value {
                Value::Text(text) => escape_into(&mut self.text, text),
                Value::Numbers(values) => {
                    for (i, v) in values.iter().enumerate() {
                        if i > 0 {
                            self.text.push(' ');
                        }
                        // Exact zeros are written as 0 (no "-0").
                        let v = if *v == 0.0 { 0.0 } else { *v };
                        write!(self.text, "{v}").expect("writing to a String");
                    }
                }
            }
            self.text.push('"');
        }
    }

    /// `<tag attributes/>`.
    pub(super) fn leaf(&mut self, tag: &str, attributes: &[(&str, Value<'_>)]) {
        self.start(tag, attributes);
        self.text.push_str("/>\n");
    }

    /// `<tag attributes>` — close it with [`Xml::close`].
    pub(super) fn open(&mut self, tag: &str, attributes: &[(&str, Value<'_>)]) {
        self.start(tag, attributes);
        self.text.push_str(">\n");
        self.depth += 1;
    }

    /// `</tag>`.
    pub(super) fn close(&mut self, tag: &str) {
        self.depth -= 1;
        for _ in 0..self.depth {
            self.text.push_str("  ");
        }
        self.text.push_str("</");
        self.text.push_str(tag);
        self.text.push_str(">\n");
    }

    /// A comment line (`--` inside is replaced, as XML forbids it).
    pub(super) fn comment(&mut self, text: &str) {
        for _ in 0..self.depth {
            self.text.push_str("  ");
        }
        self.text.push_str("<!-- ");
        escape_into(&mut self.text, &text.replace("--", "- -"));
        self.text.push_str(" -->\n");
    }

    /// The document.
    pub(super) fn finish(self) -> String {
        self.text
    }
}

fn escape_into(out: &mut String, text: &str) {
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly_and_names_are_escaped() {
        let mut xml = Xml::new();
        let values = vec![0.1, -1e-300, 1.0 / 3.0, 123456.789e10, -0.0];
        xml.leaf(
            "geom",
            &[
                ("name", name("a<b>&\"c\"")),
                ("size", values.clone().into()),
            ],
        );
        let text = xml.finish();
        assert!(text.starts_with("<geom name=\"a&lt;b&gt;&amp;&quot;c&quot;\" size=\""));
        let inner = text
            .split("size=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let read: Vec<f64> = inner.split(' ').map(|v| v.parse().unwrap()).collect();
        assert_eq!(read[..4], values[..4]);
        assert_eq!(inner.split(' ').nth(4), Some("0"));
    }
}
