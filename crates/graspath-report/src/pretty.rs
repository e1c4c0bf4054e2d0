//! serde_json's pretty layout (two spaces a level), written a line at a time.
//!
//! `serde_json::ser::PrettyFormatter` writes a line break, then the indentation one level per
//! call; on `candidates.json`, where every number of a joint trajectory has a line of its own,
//! those small writes cost more than the numbers. [`LineFormatter`] writes the separator, the
//! line break and the whole indentation with one call. The bytes are the same.

use serde::Serialize;
use serde_json::ser::Formatter;
use std::io::{self, Write};

/// The deepest indentation written with one call; deeper levels take one more call per
/// [`MAX_ONE_CALL_DEPTH`] levels.
const MAX_ONE_CALL_DEPTH: usize = 32;

/// `,` then a line break then the indentation of [`MAX_ONE_CALL_DEPTH`] levels.
const LINE: [u8; 2 + 2 * MAX_ONE_CALL_DEPTH] = {
    let mut line = [b' '; 2 + 2 * MAX_ONE_CALL_DEPTH];
    line[0] = b',';
    line[1] = b'\n';
    line
};

/// A formatter with serde_json's pretty layout and two-space indentation, starting `depth`
/// levels in.
#[derive(Debug, Clone)]
pub(crate) struct LineFormatter {
    depth: usize,
    has_value: bool,
}

impl LineFormatter {
    /// Formats a value that sits `depth` levels in (0: a whole document).
    pub(crate) fn at_depth(depth: usize) -> Self {
        Self {
            depth,
            has_value: false,
        }
    }
}

/// Writes a line break (after a `,` unless `first`) and the indentation of `depth` levels.
fn new_line<W: ?Sized + Write>(writer: &mut W, first: bool, depth: usize) -> io::Result<()> {
    let start = usize::from(first);
    let one_call = depth.min(MAX_ONE_CALL_DEPTH);
    writer.write_all(&LINE[start..2 + 2 * one_call])?;
    let mut left = depth - one_call;
    while left > 0 {
        let now = left.min(MAX_ONE_CALL_DEPTH);
        writer.write_all(&LINE[2..2 + 2 * now])?;
        left -= now;
    }
    Ok(())
}

impl LineFormatter {
    /// Opens an array or an object (`bracket`): one level deeper, nothing in it yet.
    fn open<W: ?Sized + Write>(&mut self, writer: &mut W, bracket: &[u8]) -> io::Result<()> {
        self.depth += 1;
        self.has_value = false;
        writer.write_all(bracket)
    }

    /// Closes an array or an object (`bracket`), on a line of its own when it holds values.
    fn close<W: ?Sized + Write>(&mut self, writer: &mut W, bracket: &[u8]) -> io::Result<()> {
        self.depth -= 1;
        if self.has_value {
            new_line(writer, true, self.depth)?;
        }
        writer.write_all(bracket)
    }
}

impl Formatter for LineFormatter {
    fn begin_array<W: ?Sized + Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.open(writer, b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.close(writer, b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> io::Result<()> {
        new_line(writer, first, self.depth)
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _writer: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.open(writer, b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, writer: &mut W) -> io::Result<()> {
        self.close(writer, b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(
        &mut self,
        writer: &mut W,
        first: bool,
    ) -> io::Result<()> {
        new_line(writer, first, self.depth)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, writer: &mut W) -> io::Result<()> {
        writer.write_all(b": ")
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, _writer: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

/// Appends `value` to `out` in serde_json's pretty layout, as a value `depth` levels in.
pub(crate) fn write_pretty_at<T: Serialize + ?Sized>(
    out: &mut Vec<u8>,
    value: &T,
    depth: usize,
) -> serde_json::Result<()> {
    let mut serializer =
        serde_json::Serializer::with_formatter(out, LineFormatter::at_depth(depth));
    value.serialize(&mut serializer)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::{json, Value};

    fn nested(depth: usize) -> Value {
        (0..depth).fold(
            json!([1.5, -0.0, "x", null]),
            |inner, i| json!({"a": [], "b": {}, "c": [inner, i], "d": {"e": true}}),
        )
    }

    #[test]
    fn the_bytes_are_serde_json_s_pretty_ones() {
        let documents = [
            json!(null),
            json!([]),
            json!({}),
            json!([[]]),
            json!({"k": {}}),
            json!([1, 2.5, 1e300, -0.0, "é\n\"", true, null]),
            nested(3),
            // Deeper than one call's indentation.
            nested(MAX_ONE_CALL_DEPTH + 5),
            nested(3 * MAX_ONE_CALL_DEPTH),
        ];
        for document in &documents {
            let mut ours = Vec::new();
            write_pretty_at(&mut ours, document, 0).unwrap();
            assert_eq!(
                String::from_utf8(ours).unwrap(),
                serde_json::to_string_pretty(document).unwrap()
            );
        }
    }

    #[test]
    fn a_value_deeper_in_is_indented_as_an_element_of_its_parent() {
        for depth in [1, 2, MAX_ONE_CALL_DEPTH + 1] {
            let element = nested(2);
            // The element inside `depth` one-element arrays, pretty-printed whole.
            let wrapped = (0..depth).fold(element.clone(), |inner, _| json!([inner]));
            let whole = serde_json::to_string_pretty(&wrapped).unwrap();
            let mut ours = Vec::new();
            write_pretty_at(&mut ours, &element, depth).unwrap();
            let ours = String::from_utf8(ours).unwrap();
            // `[`, a line break and the next level's indentation for each level opened.
            let opened: String = (1..=depth)
                .map(|k| format!("[\n{}", "  ".repeat(k)))
                .collect();
            assert!(whole.starts_with(&(opened + &ours)), "depth {depth}");
        }
    }
}
