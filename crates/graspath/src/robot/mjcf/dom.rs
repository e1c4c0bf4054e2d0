//! A small element tree of an MJCF file, read with `quick-xml`: names, attributes (unescaped)
//! and the line of each start tag, for error messages. Malformed XML is reported with its line
//! and column; nesting deeper than [`MAX_DEPTH`] is refused (bounded recursion later on).

use crate::robot::error::RobotError;
use crate::robot::urdf_scan::{line_column, xml_error};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;

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
    pub fn get(&self, key: &str) -> Option<&str> {
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
        let open = |e: &BytesStart<'_>| -> Result<Element, RobotError> {
            let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let mut attributes = Vec::new();
            for attribute in e.attributes().with_checks(true) {
                let fail = |message: String| {
                    xml_error(text, source_name, start, format!("in <{name}>: {message}"))
                };
                let attribute = attribute.map_err(|err| fail(err.to_string()))?;
                let key = String::from_utf8_lossy(attribute.key.as_ref()).into_owned();
                let value = attribute
                    .unescape_value()
                    .map_err(|err| fail(err.to_string()))?
                    .into_owned();
                attributes.push((key, value));
            }
            if stack.len() >= MAX_DEPTH {
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
                line: line_column(text, start).0,
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
                stack.push(open(&e)?);
                None
            }
            Event::Empty(e) => Some(open(&e)?),
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
