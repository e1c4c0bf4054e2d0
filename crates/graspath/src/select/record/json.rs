//! A candidate's JSON record (`candidates.json`, `candidates.jsonl`): its fields, read off
//! [`COLUMNS`], in the byte order of their names, and how cells are written there.

use super::outputs::JSON;
use super::*;
use std::sync::OnceLock;

/// A field of a JSON record: a column, or a group of columns.
#[derive(Debug, Clone, Copy)]
pub enum JsonField {
    /// A column at the top of the record.
    Column(&'static Column),
    /// A nested group and its columns, in the byte order of their names there.
    Group(Group, &'static [&'static Column]),
}

impl JsonField {
    /// The field's name in the record.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Column(c) => c.name,
            Self::Group(g, _) => g.name(),
        }
    }
}

/// The fields of a JSON record in the byte order of their names (how `candidates.json` has
/// always listed them, and `candidates.jsonl` too), with the columns of `output`
/// ([`outputs::JSON`]; any other output is taken as [`outputs::JSON_LINES`]).
pub fn json_fields(output: u8) -> &'static [JsonField] {
    static DOCUMENT: OnceLock<Vec<JsonField>> = OnceLock::new();
    static LINES: OnceLock<Vec<JsonField>> = OnceLock::new();
    let (cell, output) = if output == JSON {
        (&DOCUMENT, JSON)
    } else {
        (&LINES, outputs::JSON_LINES)
    };
    cell.get_or_init(|| {
        let columns = || COLUMNS.iter().filter(|c| c.in_output(output));
        let mut fields: Vec<JsonField> = columns()
            .filter(|c| c.json == JsonPlace::Top)
            .map(JsonField::Column)
            .collect();
        for group in [Group::Failure, Group::SelfMotion] {
            let mut members: Vec<&'static Column> = columns()
                .filter(|c| matches!(c.json, JsonPlace::In(g, _) if g == group))
                .collect();
            members.sort_by_key(|c| json_name(c));
            if !members.is_empty() {
                fields.push(JsonField::Group(group, Vec::leak(members)));
            }
        }
        fields.sort_by_key(JsonField::name);
        fields
    })
}

/// A column's field name in its JSON record (inside its group for a grouped one).
pub fn json_name(column: &Column) -> &'static str {
    match column.json {
        JsonPlace::Top => column.name,
        JsonPlace::In(_, name) => name,
    }
}

impl Cell<'_> {
    /// Whether the cell is absent for a JSON record (`empty` lists too, when `absent` says so).
    pub fn absent_in_json(&self, absent: WhenAbsent) -> bool {
        let missing = match self {
            Self::Float(v) => v.is_none(),
            Self::Count(v) => v.is_none(),
            Self::Flag(v) => v.is_none(),
            Self::Text(v) => v.is_none(),
            Self::Point(v) => v.is_none(),
            Self::Pose(_) => false,
            Self::Bodies(v) => v.is_none(),
            Self::Samples(v) => v.is_none(),
            Self::Floats(v) => absent == WhenAbsent::OmitEmpty && v.is_empty(),
            Self::Motion(v) => {
                v.is_none() || (absent == WhenAbsent::OmitEmpty && v.is_some_and(<[_]>::is_empty))
            }
        };
        missing && absent != WhenAbsent::Null
    }
}

impl serde::Serialize for Cell<'_> {
    /// The cell as JSON: a value that is not finite as `null`.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let finite_or_null = |v: &f64| finite(*v);
        match self {
            Self::Float(v) => v.and_then(finite).serialize(serializer),
            Self::Count(v) => v.serialize(serializer),
            Self::Flag(v) => v.serialize(serializer),
            Self::Text(v) => v.serialize(serializer),
            Self::Point(v) => v
                .map(|p| p.map(|x| finite_or_null(&x)))
                .serialize(serializer),
            Self::Pose(m) => m.serialize(serializer),
            Self::Bodies(v) => v.serialize(serializer),
            Self::Samples(v) => {
                serializer.collect_seq(v.unwrap_or_default().iter().map(|x| x.and_then(finite)))
            }
            Self::Floats(v) => serializer.collect_seq(v.iter().map(finite_or_null)),
            Self::Motion(v) => v.unwrap_or_default().serialize(serializer),
        }
    }
}

/// One candidate's JSON record for `output` ([`outputs::JSON`] or [`outputs::JSON_LINES`]):
/// serialised, the fields of [`json_fields`] with their cells.
#[derive(Debug, Clone, Copy)]
pub struct JsonRecord<'a> {
    /// The candidate's row.
    pub row: Row<'a>,
    /// Which JSON output.
    pub output: u8,
}

/// The present fields of one group, serialised as a JSON object.
struct JsonGroup<'a> {
    row: Row<'a>,
    members: &'static [&'static Column],
}

impl serde::Serialize for JsonGroup<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let cells: Vec<(&str, Cell<'_>)> = self
            .members
            .iter()
            .map(|c| (json_name(c), (c.value)(&self.row), c.json_absent))
            .filter(|(_, cell, absent)| !cell.absent_in_json(*absent))
            .map(|(name, cell, _)| (name, cell))
            .collect();
        let mut map = serializer.serialize_map(Some(cells.len()))?;
        for (name, cell) in &cells {
            map.serialize_entry(name, cell)?;
        }
        map.end()
    }
}

impl serde::Serialize for JsonRecord<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let fields = json_fields(self.output);
        let mut map = serializer.serialize_map(None)?;
        for field in fields {
            match field {
                JsonField::Column(c) => {
                    let cell = (c.value)(&self.row);
                    if !cell.absent_in_json(c.json_absent) {
                        map.serialize_entry(c.name, &cell)?;
                    }
                }
                JsonField::Group(group, members) => {
                    if group.present(&self.row) {
                        let value = JsonGroup {
                            row: self.row,
                            members,
                        };
                        map.serialize_entry(group.name(), &value)?;
                    } else if group.when_absent() == WhenAbsent::Null {
                        map.serialize_entry(group.name(), &())?;
                    }
                }
            }
        }
        map.end()
    }
}
