//! A small element tree of an MJCF file, read with `quick-xml`: names, attributes (unescaped)
//! and the line of each start tag, for error messages. Malformed XML is reported with its line
//! and column; nesting deeper than [`MAX_DEPTH`] is refused (bounded recursion later on).
//! Reading is linear in the file's size: lines are counted in one pass ([`LineCounter`]) and
//! an attribute given twice is found with a hash set, not by comparing every pair.

use crate::robot::error::RobotError;
use crate::robot::urdf_scan::{xml_error, LineCounter};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::HashSet;

/// Up to this many attributes, an element's are compared pairwise for duplicates (cheaper
/// than hashing); beyond it, through a hash set.
const PAIRWISE_ATTRIBUTES: usize = 16;

/// The deepest element nesting accepted.
pub(crate) const MAX_DEPTH: usize = 512;

/// One XML element.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub name: String,
    pub attributes: Vec<(String, String)>,
    /// 1-based line of the start tag.
    pub line: usize,
    pub children: Vec<Element>,
}

impl Element {
    /// The attribute `key` as written on this element.
    pub(super) fn get(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// Parses `text` into its root element.
pub(crate) fn parse(text: &str, source_name: &str) -> Result<Element, RobotError> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    let mut lines = LineCounter::default();
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
        let mut open = |e: &BytesStart<'_>, depth: usize| -> Result<Element, RobotError> {
            let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let fail = |message: String| {
                xml_error(text, source_name, start, format!("in <{name}>: {message}"))
            };
            let mut attributes: Vec<(String, String)> = Vec::new();
            // quick-xml's own duplicate check compares every pair: quadratic in the count.
            for attribute in e.attributes().with_checks(false) {
                let attribute = attribute.map_err(|err| fail(err.to_string()))?;
                let key = String::from_utf8_lossy(attribute.key.as_ref()).into_owned();
                let value = attribute
                    .unescape_value()
                    .map_err(|err| fail(err.to_string()))?
                    .into_owned();
                attributes.push((key, value));
            }
            if let Some(key) = repeated_key(&attributes) {
                return Err(fail(format!("attribute `{key}` is given twice")));
            }
            if depth >= MAX_DEPTH {
                return Err(xml_error(
                    text,
                    source_name,
                    start,
                    format!("elements nested more than {MAX_DEPTH} deep"),
                ));
            }
            Ok(Element {
                name,
                attributes,
                line: lines.line(text, start),
                children: Vec::new(),
            })
        };
        let finished = match event {
            Event::Start(e) | Event::Empty(e) if stack.is_empty() && root.is_some() => {
                return Err(xml_error(
                    text,
                    source_name,
                    start,
                    format!(
                        "a second root element <{}> after the first one ended",
                        String::from_utf8_lossy(e.name().as_ref())
                    ),
                ));
            }
            Event::Start(e) => {
                let element = open(&e, stack.len())?;
                stack.push(element);
                None
            }
            Event::Empty(e) => Some(open(&e, stack.len())?),
            Event::End(_) => stack.pop(),
            Event::Eof => break,
            _ => None,
        };
        if let Some(element) = finished {
            match stack.last_mut() {
                Some(parent) => parent.children.push(element),
                None => root = Some(element),
            }
        }
    }
    if let Some(open) = stack.last() {
        return Err(RobotError::Xml {
            source_name: source_name.to_string(),
            line: open.line,
            column: 1,
            message: format!("element <{}> is never closed", open.name),
        });
    }
    root.ok_or_else(|| xml_error(text, source_name, text.len(), "no root element".into()))
}

/// The first attribute name given twice, if any.
fn repeated_key(attributes: &[(String, String)]) -> Option<&str> {
    if attributes.len() <= PAIRWISE_ATTRIBUTES {
        return attributes.iter().enumerate().find_map(|(i, (key, _))| {
            attributes[..i]
                .iter()
                .any(|(k, _)| k == key)
                .then_some(key.as_str())
        });
    }
    let mut seen = HashSet::with_capacity(attributes.len());
    attributes
        .iter()
        .map(|(key, _)| key.as_str())
        .find(|key| !seen.insert(*key))
}
