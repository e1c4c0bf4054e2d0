//! A strict pass over URDF text before `urdf-rs` reads it: malformed XML is reported with its
//! line and column, and the facts `urdf-rs` loses (whether a joint has a `<limit>` element,
//! the line of each joint) are collected.

use super::error::RobotError;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::{HashMap, HashSet};

/// What the pass found about each top-level `<joint>`.
#[derive(Debug, Default)]
pub(crate) struct Scan {
    /// Joint name → (line of its start tag, whether it has a `<limit>` child).
    pub joints: HashMap<String, (usize, bool)>,
    /// The first xacro markup outside comments: its line and what it is (an element in the
    /// xacro namespace, or a `${...}` / `$(...)` substitution in an attribute).
    pub xacro_markup: Option<(usize, String)>,
    /// Byte ranges of `<texture>` elements without a `filename` (iCub and Romeo write
    /// `<texture/>`): urdfdom and Pinocchio ignore them, `urdf-rs` refuses them, and a texture
    /// plays no part in kinematics or collision, so [`Scan::without_blank_textures`] blanks them.
    pub blank_textures: Vec<std::ops::Range<usize>>,
    /// The links that have an `<inertial>` child (`urdf-rs` gives the others a zero mass).
    pub inertial_links: HashSet<String>,
    /// The first link or joint whose name an earlier one already has (`urdf-rs` keeps both;
    /// urdfdom refuses the file): what it is and the message naming both lines.
    pub duplicate_name: Option<String>,
}

impl Scan {
    /// `text` with the [`Scan::blank_textures`] replaced by spaces (line breaks kept, so every
    /// line and column stays where it was).
    pub(super) fn without_blank_textures<'a>(&self, text: &'a str) -> std::borrow::Cow<'a, str> {
        if self.blank_textures.is_empty() {
            return std::borrow::Cow::Borrowed(text);
        }
        let mut bytes = text.as_bytes().to_vec();
        for range in &self.blank_textures {
            for b in &mut bytes[range.clone()] {
                if *b != b'\n' {
                    *b = b' ';
                }
            }
        }
        // Only whole elements, which start and end at ASCII '<' and '>', were blanked.
        std::borrow::Cow::Owned(String::from_utf8_lossy(&bytes).into_owned())
    }
}

/// The namespace URIs that xacro's documentation and ROS descriptions bind the xacro prefix
/// to (`ros.org/wiki/xacro` with and without `www.`, and `wiki.ros.org/xacro`; over http and
/// https).
fn is_xacro_namespace(uri: &[u8]) -> bool {
    let uri = uri
        .strip_prefix(b"https://")
        .or_else(|| uri.strip_prefix(b"http://"));
    uri.is_some_and(|rest| {
        let rest = rest.strip_prefix(b"www.").unwrap_or(rest);
        let rest = rest.strip_suffix(b"/").unwrap_or(rest);
        rest == b"ros.org/wiki/xacro" || rest == b"wiki.ros.org/xacro"
    })
}

/// 1-based line and column of byte `offset` in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text.as_bytes()[..offset];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    (line, column)
}

/// 1-based line numbers of increasing byte offsets in one text, counted incrementally: a
/// whole pass costs one count over the text, not one per element.
#[derive(Debug, Default)]
pub(crate) struct LineCounter {
    offset: usize,
    line: usize,
}

impl LineCounter {
    /// The line of byte `offset` of `text`; offsets before the previous one are counted from
    /// the start again.
    pub(crate) fn line(&mut self, text: &str, offset: usize) -> usize {
        let offset = offset.min(text.len());
        if offset < self.offset || self.line == 0 {
            *self = Self { offset: 0, line: 1 };
        }
        let newlines = text.as_bytes()[self.offset..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        self.line += newlines;
        self.offset = offset;
        self.line
    }
}

/// A malformed-XML error at byte `offset` of `text`, with its line and column.
pub(crate) fn xml_error(
    text: &str,
    source_name: &str,
    offset: usize,
    message: String,
) -> RobotError {
    let (line, column) = line_column(text, offset);
    RobotError::Xml {
        source_name: source_name.to_string(),
        line,
        column,
        message,
    }
}

/// The attributes of element `name` (below the open elements `stack`, root first) that
/// `urdf-rs` reads as numbers: a value that is not whitespace-separated numbers is reported
/// here, with its line and element, rather than as the reader's bare `invalid float literal`.
fn numeric_attributes(stack: &[(String, usize, bool)], name: &str) -> &'static [&'static str] {
    let at = |i: usize| stack.get(i).map_or("", |(n, _, _)| n.as_str());
    match (stack.len(), at(1), at(2), at(3), name) {
        (2, "joint", _, _, "origin")
        | (3, "link", "inertial" | "visual" | "collision", _, "origin") => &["xyz", "rpy"],
        (2, "joint", _, _, "axis") => &["xyz"],
        (2, "joint", _, _, "limit") => &["lower", "upper", "effort", "velocity"],
        (3, "link", "inertial", _, "mass") => &["value"],
        (3, "link", "inertial", _, "inertia") => &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"],
        (4, "link", "visual" | "collision", "geometry", "box") => &["size"],
        (4, "link", "visual" | "collision", "geometry", "cylinder" | "capsule") => {
            &["radius", "length"]
        }
        (4, "link", "visual" | "collision", "geometry", "sphere") => &["radius"],
        (4, "link", "visual" | "collision", "geometry", "mesh") => &["scale"],
        _ => &[],
    }
}

/// Records the first name given twice: `kind` (`link` or `joint`) `name`, first on line
/// `first`, again on line `line`.
fn note_duplicate(found: &mut Option<String>, kind: &str, name: &str, first: usize, line: usize) {
    if found.is_none() {
        *found = Some(format!(
            "line {line}: a second {kind} named {} (the first is on line {first}); every {kind} needs a name of its own",
            excerpt(name)
        ));
    }
}

/// Whether an attribute value holds a xacro substitution, `${...}` or `$(...)`.
fn attribute_has_substitution(value: &[u8]) -> bool {
    value.windows(2).any(|w| w == b"${" || w == b"$(")
}

/// A short, printable excerpt of a file's value for a message: quoted, at most 32
/// characters, control characters escaped.
fn excerpt(value: &str) -> String {
    let mut short: String = value.chars().take(32).collect();
    if short.len() < value.len() {
        short.push('…');
    }
    format!("{:?}", short)
}

/// Checks that `text` is well-formed XML and collects the joints' facts.
pub(crate) fn scan(text: &str, source_name: &str) -> Result<Scan, RobotError> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    // Open elements: name, start offset, whether the element is a blank texture.
    let mut stack: Vec<(String, usize, bool)> = Vec::new();
    let mut current_joint: Option<String> = None;
    let mut current_link: Option<String> = None;
    let mut out = Scan::default();
    // Link name → the line of its start tag.
    let mut link_lines: HashMap<String, usize> = HashMap::new();
    let mut seen_root = false;
    let mut lines = LineCounter::default();
    // Prefixes bound to the xacro namespace (`xacro` by convention, whether declared or not).
    let mut xacro_prefixes: Vec<Vec<u8>> = vec![b"xacro".to_vec()];
    loop {
        let start = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            xml_error(
                text,
                source_name,
                reader.error_position() as usize,
                e.to_string(),
            )
        })?;
        let end = reader.buffer_position() as usize;
        let mut element = |e: &BytesStart<'_>, empty: bool| -> Result<(), RobotError> {
            let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let mut element_name = None;
            let mut substitution = false;
            let mut has_filename = false;
            let numeric = numeric_attributes(&stack, &name);
            for attribute in e.attributes().with_checks(true) {
                let attribute = attribute.map_err(|err| {
                    xml_error(text, source_name, start, format!("in <{name}>: {err}"))
                })?;
                if let Some(prefix) = attribute.key.as_ref().strip_prefix(b"xmlns:") {
                    if is_xacro_namespace(&attribute.value) {
                        xacro_prefixes.push(prefix.to_vec());
                    }
                }
                has_filename |= attribute.key.as_ref() == b"filename";
                let key = String::from_utf8_lossy(attribute.key.as_ref());
                // A xacro substitution is reported as such (`Scan::xacro_markup`), not as a
                // number.
                if numeric.contains(&key.as_ref()) && !attribute_has_substitution(&attribute.value)
                {
                    let value = String::from_utf8_lossy(&attribute.value);
                    if let Some(bad) = value.split_whitespace().find(|t| t.parse::<f64>().is_err())
                    {
                        let owner = match (&current_joint, &current_link) {
                            (Some(joint), _) => format!("joint '{joint}', "),
                            (None, Some(link)) => format!("link '{link}', "),
                            (None, None) => String::new(),
                        };
                        return Err(RobotError::Parse {
                            source_name: source_name.to_string(),
                            message: format!(
                                "line {}: {owner}<{name} {key}>: {} is not a number",
                                lines.line(text, start),
                                excerpt(bad)
                            ),
                        });
                    }
                }
                let value = attribute.value.as_ref();
                substitution |= attribute_has_substitution(value);
                if (name == "joint" || name == "link") && attribute.key.as_ref() == b"name" {
                    element_name = Some(
                        attribute
                            .unescape_value()
                            .map_err(|err| {
                                xml_error(text, source_name, start, format!("in <{name}>: {err}"))
                            })?
                            .into_owned(),
                    );
                }
            }
            if stack.is_empty() && seen_root {
                return Err(xml_error(
                    text,
                    source_name,
                    start,
                    format!("a second root element <{name}> after the first one ended"),
                ));
            }
            seen_root = true;
            if out.xacro_markup.is_none() {
                let in_xacro_namespace = e
                    .name()
                    .prefix()
                    .is_some_and(|p| xacro_prefixes.iter().any(|x| x == p.as_ref()));
                if in_xacro_namespace {
                    out.xacro_markup =
                        Some((lines.line(text, start), format!("the element <{name}>")));
                } else if substitution {
                    out.xacro_markup = Some((
                        lines.line(text, start),
                        format!("a ${{...}} or $(...) substitution in an attribute of <{name}>"),
                    ));
                }
            }
            let depth = stack.len();
            if depth == 1 && name == "joint" {
                let joint = element_name.unwrap_or_default();
                let line = lines.line(text, start);
                if let Some((first, _)) = out.joints.get(&joint) {
                    note_duplicate(&mut out.duplicate_name, "joint", &joint, *first, line);
                } else {
                    out.joints.insert(joint.clone(), (line, false));
                }
                if !empty {
                    current_joint = Some(joint);
                }
            } else if depth == 1 && name == "link" {
                let link = element_name.clone().unwrap_or_default();
                let line = lines.line(text, start);
                if let Some(first) = link_lines.get(&link) {
                    note_duplicate(&mut out.duplicate_name, "link", &link, *first, line);
                } else {
                    link_lines.insert(link, line);
                }
                current_link = (!empty).then(|| element_name.clone().unwrap_or_default());
            } else if depth == 2 && name == "inertial" && stack[1].0 == "link" {
                if let Some(link) = &current_link {
                    out.inertial_links.insert(link.clone());
                }
            } else if depth == 2 && name == "limit" && stack[1].0 == "joint" {
                if let Some(joint) = &current_joint {
                    if let Some(entry) = out.joints.get_mut(joint) {
                        entry.1 = true;
                    }
                }
            }
            let blank_texture = name == "texture" && !has_filename;
            if empty {
                if blank_texture {
                    out.blank_textures.push(start..end);
                }
            } else {
                stack.push((name, start, blank_texture));
            }
            Ok(())
        };
        match event {
            Event::Start(e) => element(&e, false)?,
            Event::Empty(e) => element(&e, true)?,
            Event::End(_) => {
                if stack.len() == 2 && stack[1].0 == "joint" {
                    current_joint = None;
                }
                if stack.len() == 2 && stack[1].0 == "link" {
                    current_link = None;
                }
                if let Some((_, open, true)) = stack.pop() {
                    out.blank_textures.push(open..end);
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if let Some((name, start, _)) = stack.last() {
        return Err(xml_error(
            text,
            source_name,
            *start,
            format!("element <{name}> is never closed"),
        ));
    }
    if !seen_root {
        return Err(xml_error(
            text,
            source_name,
            text.len(),
            "no root element".into(),
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_value_that_is_not_a_number_is_named_with_its_line_and_element() {
        let urdf = |limit: &str| {
            format!(
                "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n\
                 <joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\n\
                 <limit {limit} upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n\
                 <gazebo><limit lower=\"anything\"/></gazebo>\n</robot>"
            )
        };
        let message = scan(&urdf("lower=\"x\""), "r.urdf")
            .unwrap_err()
            .to_string();
        assert_eq!(
            message,
            "r.urdf: not a valid URDF: line 5: joint 'j', <limit lower>: \"x\" is not a number"
        );
        let long = format!("lower=\"1 {}\"", "y".repeat(100));
        let message = scan(&urdf(&long), "r.urdf").unwrap_err().to_string();
        assert!(message.ends_with(&format!("\"{}…\" is not a number", "y".repeat(32))));
        // Numbers in every spelling Rust reads, and elements urdf-rs does not read (here a
        // <limit> inside <gazebo>), pass.
        for good in ["lower=\"-1e-3\"", "lower=\" +.5 \"", "lower=\"inf\""] {
            assert!(scan(&urdf(good), "r.urdf").is_ok(), "{good}");
        }
    }

    #[test]
    fn counted_lines_equal_lines_counted_from_the_start() {
        let text = "a\n\nbc\r\nd\n\n\nef\ng";
        let mut lines = LineCounter::default();
        // Increasing offsets, repeated ones, then one that goes back.
        for offset in (0..=text.len()).chain([3, 3, 9]).chain([1, text.len() + 5]) {
            assert_eq!(
                lines.line(text, offset),
                line_column(text, offset).0,
                "offset {offset}"
            );
        }
    }
}
