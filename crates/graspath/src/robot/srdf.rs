//! SRDF, the semantic description beside a URDF (MoveIt's format): planning groups given as
//! chains, end effectors, and the link pairs never checked for collision
//! (`<disable_collisions>`). Malformed XML is reported with its line and column; a link the
//! robot does not have is an error naming the element ([`Srdf::check_links`]). Reading and
//! checking are linear in the file's size (MoveIt's setup assistant writes SRDFs of tens of
//! thousands of `<disable_collisions>` pairs): lines are counted in one pass, attribute and
//! link names are looked up in hash sets.

use super::error::RobotError;
use super::urdf_scan::{xml_error, LineCounter};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::{BTreeMap, HashSet};
use std::path::Path;

/// A planning group: its chains (`base_link → tip_link`), links and joints as listed.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SrdfGroup {
    /// The group's name.
    pub name: String,
    /// `<chain base_link tip_link/>` elements.
    pub chains: Vec<(String, String)>,
    /// `<link name/>` elements.
    pub links: Vec<String>,
    /// `<joint name/>` elements.
    pub joints: Vec<String>,
}

/// A link pair never checked for collision.
#[derive(Debug, Clone, PartialEq)]
pub struct DisabledPair {
    /// The first link.
    pub link1: String,
    /// The second link.
    pub link2: String,
    /// The stated reason (`Adjacent`, `Never`, `Default`, ...), empty when none.
    pub reason: String,
    /// 1-based line of the element.
    pub line: usize,
}

/// An end effector: its group, and the link of the arm it hangs on.
#[derive(Debug, Clone, PartialEq)]
pub struct EndEffector {
    /// Its name.
    pub name: String,
    /// The group of its links.
    pub group: String,
    /// The arm link it is attached to.
    pub parent_link: String,
}

/// The parts of an SRDF graspath uses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Srdf {
    /// The file (for messages).
    pub source_name: String,
    /// The robot name the SRDF is for.
    pub robot: String,
    /// Planning groups, in file order.
    pub groups: Vec<SrdfGroup>,
    /// End effectors, in file order.
    pub end_effectors: Vec<EndEffector>,
    /// `<disable_collisions>` pairs, in file order.
    pub disabled: Vec<DisabledPair>,
}

impl Srdf {
    /// Reads an SRDF file.
    pub fn read(path: &Path) -> Result<Self, RobotError> {
        let name = path.display().to_string();
        let text = crate::input::read_to_string(path, crate::input::MAX_ROBOT_FILE_BYTES).map_err(
            |source| RobotError::Io {
                source_name: name.clone(),
                source,
            },
        )?;
        Self::parse(&text, &name)
    }

    /// Parses SRDF text; `source_name` names it in errors.
    pub fn parse(text: &str, source_name: &str) -> Result<Self, RobotError> {
        let xml_error =
            |offset: usize, message: String| xml_error(text, source_name, offset, message);
        let mut reader = Reader::from_str(text);
        reader.config_mut().check_end_names = true;
        let mut out = Srdf {
            source_name: source_name.to_string(),
            ..Srdf::default()
        };
        let mut stack: Vec<String> = Vec::new();
        let mut seen_root = false;
        let mut lines = LineCounter::default();
        loop {
            let start = reader.buffer_position() as usize;
            let event = reader
                .read_event()
                .map_err(|e| xml_error(reader.error_position() as usize, e.to_string()))?;
            let (element, empty) = match &event {
                Event::Start(e) => (Some(e.clone()), false),
                Event::Empty(e) => (Some(e.clone()), true),
                Event::End(_) => {
                    stack.pop();
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let Some(e) = element else { continue };
            let tag = String::from_utf8_lossy(e.name().as_ref()).into_owned();
            let attributes =
                attributes_of(&e).map_err(|m| xml_error(start, format!("in <{tag}>: {m}")))?;
            let need = |key: &str| -> Result<String, RobotError> {
                attributes
                    .get(key)
                    .cloned()
                    .ok_or_else(|| xml_error(start, format!("<{tag}> needs the attribute `{key}`")))
            };
            match (stack.len(), stack.last().map(String::as_str), tag.as_str()) {
                (0, _, "robot") => {
                    if seen_root {
                        return Err(xml_error(start, "a second <robot> element".into()));
                    }
                    seen_root = true;
                    out.robot = attributes.get("name").cloned().unwrap_or_default();
                }
                (0, _, other) => {
                    return Err(xml_error(
                        start,
                        format!("the root element is <{other}>, not <robot>: not an SRDF"),
                    ))
                }
                (1, _, "group") => out.groups.push(SrdfGroup {
                    name: need("name")?,
                    ..SrdfGroup::default()
                }),
                (2, Some("group"), "chain") => {
                    let chain = (need("base_link")?, need("tip_link")?);
                    if let Some(group) = out.groups.last_mut() {
                        group.chains.push(chain);
                    }
                }
                (2, Some("group"), "link") => {
                    let link = need("name")?;
                    if let Some(group) = out.groups.last_mut() {
                        group.links.push(link);
                    }
                }
                (2, Some("group"), "joint") => {
                    let joint = need("name")?;
                    if let Some(group) = out.groups.last_mut() {
                        group.joints.push(joint);
                    }
                }
                (1, _, "end_effector") => out.end_effectors.push(EndEffector {
                    name: need("name")?,
                    group: need("group")?,
                    parent_link: need("parent_link")?,
                }),
                (1, _, "disable_collisions") => out.disabled.push(DisabledPair {
                    link1: need("link1")?,
                    link2: need("link2")?,
                    reason: attributes.get("reason").cloned().unwrap_or_default(),
                    line: lines.line(text, start),
                }),
                (1, _, "link" | "joint") => {
                    return Err(xml_error(
                        start,
                        format!("<{tag}> is a URDF element: this is a URDF, not an SRDF (an SRDF holds <group>, <disable_collisions>, ...)"),
                    ))
                }
                // Group states, virtual joints, passive joints, sphere approximations, ...:
                // not used here.
                _ => {}
            }
            if !empty {
                stack.push(tag);
            }
        }
        if !seen_root {
            return Err(xml_error(text.len(), "no <robot> element".into()));
        }
        Ok(out)
    }

    /// Checks that every link the SRDF names (disabled pairs, chains, end-effector parents)
    /// is one of `links`; the error names the element and its line.
    pub fn check_links(&self, links: &[String]) -> Result<(), RobotError> {
        let known: HashSet<&str> = links.iter().map(String::as_str).collect();
        let unknown = |link: &str, role: &'static str| RobotError::UnknownLink {
            source_name: self.source_name.clone(),
            element: "link",
            link: link.to_string(),
            role,
            suggestions: super::error::closest_names(
                link,
                links.iter().map(String::as_str).collect(),
            ),
        };
        for pair in &self.disabled {
            for link in [&pair.link1, &pair.link2] {
                if !known.contains(link.as_str()) {
                    return Err(unknown(link, "disable_collisions"));
                }
            }
        }
        for group in &self.groups {
            for (base, tip) in &group.chains {
                if !known.contains(base.as_str()) {
                    return Err(unknown(base, "group chain base"));
                }
                if !known.contains(tip.as_str()) {
                    return Err(unknown(tip, "group chain tip"));
                }
            }
        }
        for ee in &self.end_effectors {
            if !known.contains(ee.parent_link.as_str()) {
                return Err(unknown(&ee.parent_link, "end effector parent"));
            }
        }
        Ok(())
    }
}

fn attributes_of(e: &BytesStart<'_>) -> Result<BTreeMap<String, String>, String> {
    let mut out = BTreeMap::new();
    // quick-xml's own duplicate check compares every pair (quadratic in the count); the map
    // finds a repeated name as it is inserted.
    for attribute in e.attributes().with_checks(false) {
        let attribute = attribute.map_err(|err| err.to_string())?;
        let key = String::from_utf8_lossy(attribute.key.as_ref()).into_owned();
        let value = attribute
            .unescape_value()
            .map_err(|err| err.to_string())?
            .into_owned();
        if let Some(key) = out.insert(key.clone(), value).map(|_| key) {
            return Err(format!("attribute `{key}` is given twice"));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const PANDA_LIKE: &str = r#"<?xml version="1.0"?>
<robot name="panda">
  <group name="arm">
    <chain base_link="link0" tip_link="link8"/>
  </group>
  <group name="hand">
    <link name="hand"/>
    <link name="finger"/>
    <joint name="finger_joint"/>
  </group>
  <end_effector name="hand" parent_link="link8" group="hand"/>
  <disable_collisions link1="link0" link2="link1" reason="Adjacent"/>
  <disable_collisions link1="link5" link2="link7" reason="Never"/>
</robot>
"#;

    #[test]
    fn groups_end_effectors_and_disabled_pairs_are_read() {
        // The two <disable_collisions> elements are on lines 12 and 13 of the text.
        let srdf = Srdf::parse(PANDA_LIKE, "panda.srdf").unwrap();
        assert_eq!(srdf.robot, "panda");
        assert_eq!(srdf.groups.len(), 2);
        assert_eq!(
            srdf.groups[0].chains,
            vec![("link0".into(), "link8".into())]
        );
        assert_eq!(srdf.groups[1].links, vec!["hand", "finger"]);
        assert_eq!(srdf.end_effectors[0].parent_link, "link8");
        let pairs: Vec<_> = srdf
            .disabled
            .iter()
            .map(|p| {
                (
                    p.link1.as_str(),
                    p.link2.as_str(),
                    p.reason.as_str(),
                    p.line,
                )
            })
            .collect();
        assert_eq!(
            pairs,
            vec![
                ("link0", "link1", "Adjacent", 12),
                ("link5", "link7", "Never", 13)
            ]
        );
    }

    #[test]
    fn unknown_links_and_broken_files_name_the_element() {
        let srdf = Srdf::parse(PANDA_LIKE, "panda.srdf").unwrap();
        let links: Vec<String> = ["link0", "link1", "link5", "link7", "link8"]
            .map(String::from)
            .to_vec();
        assert!(srdf.check_links(&links).is_ok());
        let error = srdf.check_links(&links[..4]).unwrap_err().to_string();
        assert!(
            error.contains("link8") && error.contains("panda.srdf"),
            "{error}"
        );
        for (text, fragment) in [
            ("<robot><disable_collisions link1=\"a\"/></robot>", "link2"),
            ("<robot><group name=\"g\"></robot>", "panda.srdf:1"),
            ("<urdf/>", "not an SRDF"),
            (
                "<robot name=\"r\">\n<link name=\"a\"/>\n</robot>",
                "panda.srdf:2:1: malformed XML: <link> is a URDF element: this is a URDF, not an SRDF",
            ),
            ("", "no <robot>"),
        ] {
            let error = Srdf::parse(text, "panda.srdf").unwrap_err().to_string();
            assert!(error.contains(fragment), "{text}: {error}");
        }
    }
}
