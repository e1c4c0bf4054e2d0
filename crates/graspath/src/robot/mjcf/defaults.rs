//! `<default>` classes with bounded memory. A class holds one slot per attribute this reader
//! looks up through classes (the table [`DEFAULTED`]), like MuJoCo's fixed-size default
//! structures; other attributes are not kept. A nested class starts as a copy of its parent's
//! slots, and the copy shares the values (reference-counted), so a file of thousands of nested
//! classes costs a bounded amount per class, not a copy of everything above it.
//!
//! Orientation (`quat`, `axisangle`, `euler`, `xyaxes`, `zaxis`) is one setting, as in
//! MuJoCo's compiler: a class or element that gives any of them replaces the orientation it
//! inherits, whatever its kind; one element giving two is an error.

use std::rc::Rc;

/// The orientation attributes, of which an element gives at most one.
pub(super) const ORIENTATIONS: [&str; 5] = ["quat", "axisangle", "euler", "xyaxes", "zaxis"];

/// What an actuator element can take from a default class.
const ACTUATOR_KEYS: &[&str] = &["joint", "forcelimited", "forcerange", "gear"];

/// The attributes looked up through default classes, by element.
const DEFAULTED: &[(&str, &[&str])] = &[
    (
        "joint",
        &[
            "type",
            "pos",
            "axis",
            "range",
            "limited",
            "ref",
            "actuatorfrcrange",
        ],
    ),
    (
        "geom",
        &[
            "contype",
            "conaffinity",
            "mesh",
            "type",
            "size",
            "fromto",
            "pos",
            "quat",
            "axisangle",
            "euler",
            "xyaxes",
            "zaxis",
        ],
    ),
    ("mesh", &["file", "scale"]),
    ("general", ACTUATOR_KEYS),
    ("motor", ACTUATOR_KEYS),
    ("position", ACTUATOR_KEYS),
    ("velocity", ACTUATOR_KEYS),
    ("intvelocity", ACTUATOR_KEYS),
    ("damper", ACTUATOR_KEYS),
    ("cylinder", ACTUATOR_KEYS),
    ("muscle", ACTUATOR_KEYS),
    ("adhesion", ACTUATOR_KEYS),
];

/// The number of slots of a class.
fn slot_count() -> usize {
    DEFAULTED.iter().map(|(_, keys)| keys.len()).sum()
}

/// The slot of attribute `key` of element `element`, if classes supply it.
pub(super) fn slot(element: &str, key: &str) -> Option<usize> {
    let mut first = 0;
    for (name, keys) in DEFAULTED {
        if *name == element {
            return keys.iter().position(|k| *k == key).map(|i| first + i);
        }
        first += keys.len();
    }
    None
}

/// Whether classes supply any attribute of `element`.
pub(super) fn is_defaulted(element: &str) -> bool {
    DEFAULTED.iter().any(|(name, _)| *name == element)
}

/// One default class: a value per slot.
#[derive(Debug, Clone)]
pub(super) struct ClassDefaults {
    values: Vec<Option<Rc<str>>>,
}

impl Default for ClassDefaults {
    fn default() -> Self {
        Self {
            values: vec![None; slot_count()],
        }
    }
}

impl ClassDefaults {
    /// The value of `key` for `element`, if the class gives one.
    pub(super) fn get(&self, element: &str, key: &str) -> Option<&str> {
        let index = slot(element, key);
        debug_assert!(
            index.is_some(),
            "<{element} {key}> is looked up through classes but not in DEFAULTED"
        );
        index.and_then(|i| self.values[i].as_deref())
    }

    /// Sets the attributes of one `<element>` child of a `<default>`: those in the table
    /// replace the inherited ones (an orientation replaces the inherited orientation of any
    /// kind); the others are ignored.
    pub(super) fn apply(&mut self, element: &str, attributes: &[(String, String)]) {
        if !is_defaulted(element) {
            return;
        }
        let orients = attributes
            .iter()
            .any(|(k, _)| ORIENTATIONS.contains(&k.as_str()));
        if orients {
            for key in ORIENTATIONS {
                if let Some(i) = slot(element, key) {
                    self.values[i] = None;
                }
            }
        }
        for (key, value) in attributes {
            if let Some(i) = slot(element, key) {
                self.values[i] = Some(Rc::from(value.as_str()));
            }
        }
    }
}
