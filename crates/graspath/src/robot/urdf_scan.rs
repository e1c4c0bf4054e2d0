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
    /// The links that have an `<inertial>` child (`urdf-rs` gives the others a zero mass).
    pub inertial_links: HashSet<String>,
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

/// Checks that `text` is well-formed XML and collects the joints' facts.
pub(crate) fn scan(text: &str, source_name: &str) -> Result<Scan, RobotError> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    let mut stack: Vec<(String, usize)> = Vec::new();
    let mut current_joint: Option<String> = None;
    let mut current_link: Option<String> = None;
    let mut out = Scan::default();
    let mut seen_root = false;
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
        let mut element = |e: &BytesStart<'_>, empty: bool| -> Result<(), RobotError> {
            let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let mut element_name = None;
            for attribute in e.attributes().with_checks(true) {
                let attribute = attribute.map_err(|err| {
                    xml_error(text, source_name, start, format!("in <{name}>: {err}"))
                })?;
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
            let depth = stack.len();
            if depth == 1 && name == "joint" {
                let joint = element_name.unwrap_or_default();
                out.joints
                    .insert(joint.clone(), (line_column(text, start).0, false));
                if !empty {
                    current_joint = Some(joint);
                }
            } else if depth == 1 && name == "link" {
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
            if !empty {
                stack.push((name, start));
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
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if let Some((name, start)) = stack.last() {
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
