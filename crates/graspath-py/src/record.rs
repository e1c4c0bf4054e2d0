//! The candidate record's columns as numpy arrays (`Selection.arrays()`, `select_batch`) and
//! the schema itself (`graspath.record_columns()`), all read off
//! [`graspath::select::record::COLUMNS`].

use crate::convert::array;
use graspath::select::record::{
    column_named, outputs, Cell, Column, JsonPlace, Kind, Row, COLUMNS,
};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// One record column's values over the rows, gathered without the GIL.
pub enum ColumnValues<'r> {
    /// float64 values, row-major, and the array's shape.
    Floats(Vec<f64>, Vec<usize>),
    /// int64 values.
    Integers(Vec<i64>),
    /// bool values.
    Flags(Vec<bool>),
    /// Texts: a `str` array, or (`nullable`) an `object` array with `None` where absent.
    Texts(Vec<Option<&'r str>>, bool),
}

/// The record columns of `output` ([`outputs::ARRAYS`] or [`outputs::BATCH`]) over `rows`, by
/// name, in the schema's order; Python is not needed (the values of a large batch are gathered
/// with the GIL released). A float is float64 and a nullable count float64 (NaN where absent; an
/// infinite `mu_linf` stays infinite), a required count int64, a flag bool (false where
/// absent), a required text a str array and a nullable one an object array (`None` where
/// absent), a point `(k, 3)`, a pose `(k, 4, 4)` and a per-sample series `(k, samples)` (NaN
/// where absent, or the values of the column's numpy fallback). Errors name a column of the
/// output that has no numpy form.
pub fn gather_columns<'r>(
    rows: &[Row<'r>],
    output: u8,
    samples: usize,
) -> Result<Vec<(&'static str, ColumnValues<'r>)>, String> {
    COLUMNS
        .iter()
        .filter(|c| c.in_output(output))
        .map(|column| Ok((column.name, column_values(column, rows, samples)?)))
        .collect()
}

/// Turns gathered columns into numpy arrays in `dict` (the GIL held).
pub fn set_gathered_columns<'py>(
    py: Python<'py>,
    dict: &Bound<'py, PyDict>,
    columns: Vec<(&'static str, ColumnValues<'_>)>,
) -> PyResult<()> {
    for (name, values) in columns {
        let array = match values {
            ColumnValues::Floats(flat, shape) => array(py, flat, &shape)?.into_any(),
            ColumnValues::Integers(values) => PyArray1::from_vec(py, values).into_any(),
            ColumnValues::Flags(values) => PyArray1::from_vec(py, values).into_any(),
            ColumnValues::Texts(texts, nullable) => text_array(py, texts, nullable)?,
        };
        dict.set_item(name, array)?;
    }
    Ok(())
}

fn column_values<'r>(
    column: &Column,
    rows: &[Row<'r>],
    samples: usize,
) -> Result<ColumnValues<'r>, String> {
    let k = rows.len();
    let cells = || rows.iter().map(|r| (column.value)(r));
    let nan = f64::NAN;
    Ok(match column.kind {
        Kind::Float => ColumnValues::Floats(
            cells()
                .map(|c| match c {
                    Cell::Float(v) => v.unwrap_or(nan),
                    _ => nan,
                })
                .collect(),
            vec![k],
        ),
        Kind::Count => {
            let counts = cells().map(|c| match c {
                Cell::Count(v) => v,
                _ => None,
            });
            if column.nullable {
                ColumnValues::Floats(
                    counts.map(|v| v.map_or(nan, |v| v as f64)).collect(),
                    vec![k],
                )
            } else {
                ColumnValues::Integers(counts.map(|v| v.unwrap_or(0) as i64).collect())
            }
        }
        Kind::Flag => ColumnValues::Flags(
            cells()
                .map(|c| matches!(c, Cell::Flag(Some(true))))
                .collect(),
        ),
        Kind::Text => ColumnValues::Texts(
            cells()
                .map(|c| match c {
                    Cell::Text(v) => v,
                    _ => None,
                })
                .collect(),
            column.nullable,
        ),
        Kind::Point => ColumnValues::Floats(
            cells()
                .flat_map(|c| match c {
                    Cell::Point(Some(p)) => p,
                    _ => [nan; 3],
                })
                .collect(),
            vec![k, 3],
        ),
        Kind::Pose => ColumnValues::Floats(
            cells()
                .flat_map(|c| match c {
                    Cell::Pose(m) => *m.as_flattened().first_chunk::<16>().expect("4 × 4"),
                    _ => [nan; 16],
                })
                .collect(),
            vec![k, 4, 4],
        ),
        Kind::Series => {
            let fallback = column.numpy_fallback.and_then(column_named);
            let mut flat = vec![nan; k * samples];
            for (row, (r, cell)) in rows.iter().zip(cells()).enumerate() {
                let cell = match (cell, fallback) {
                    (Cell::Samples(None), Some(other)) => (other.value)(r),
                    (cell, _) => cell,
                };
                let out = &mut flat[row * samples..(row + 1) * samples];
                match cell {
                    Cell::Samples(Some(values)) => {
                        for (o, v) in out.iter_mut().zip(values) {
                            *o = v.unwrap_or(nan);
                        }
                    }
                    Cell::Floats(values) => {
                        for (o, v) in out.iter_mut().zip(values) {
                            *o = *v;
                        }
                    }
                    _ => {}
                }
            }
            ColumnValues::Floats(flat, vec![k, samples])
        }
        Kind::Bodies | Kind::Motion => {
            return Err(format!(
                "the record column {} ({}) has no numpy form",
                column.name,
                column.kind.name()
            ))
        }
    })
}

/// Texts as a numpy array: `str` when none is absent (`nullable` false), else `object` with
/// `None` where absent.
fn text_array<'py>(
    py: Python<'py>,
    texts: Vec<Option<&str>>,
    nullable: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = py.import("numpy")?;
    let builtins = py.import("builtins")?;
    let kwargs = PyDict::new(py);
    kwargs.set_item(
        "dtype",
        builtins.getattr(if nullable { "object" } else { "str" })?,
    )?;
    numpy.call_method("array", (PyList::new(py, texts)?,), Some(&kwargs))
}

/// The names of the outputs a column is part of.
fn output_names(column: &Column) -> Vec<&'static str> {
    [
        (outputs::JSON, "json"),
        (outputs::JSON_LINES, "jsonl"),
        (outputs::PARQUET, "parquet"),
        (outputs::ARRAYS, "arrays"),
        (outputs::BATCH, "select_batch"),
    ]
    .into_iter()
    .filter(|(bit, _)| column.in_output(*bit))
    .map(|(_, name)| name)
    .collect()
}

/// The candidate record's columns, in order, as dicts: ``name``, ``type`` (``float64``,
/// ``uint64``, ``bool``, ``string``, …), ``nullable``, ``unit``, ``doc`` and ``outputs`` (the
/// outputs that carry it: ``json``, ``jsonl``, ``parquet``, ``arrays``, ``select_batch``) and
/// ``json_field`` (its place in a JSON record: the name, or ``group.name`` inside a group such
/// as ``failure``; ``None`` when no JSON output carries it). Every per-candidate output is
/// read off this list; see ``docs/candidate-record.md``.
#[pyfunction]
pub fn record_columns(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let list = PyList::empty(py);
    for column in COLUMNS {
        let dict = PyDict::new(py);
        dict.set_item("name", column.name)?;
        dict.set_item("type", column.kind.name())?;
        dict.set_item("nullable", column.nullable)?;
        dict.set_item("unit", column.unit)?;
        dict.set_item("doc", column.doc)?;
        dict.set_item("outputs", output_names(column))?;
        dict.set_item("json_field", json_field(column))?;
        list.append(dict)?;
    }
    Ok(list)
}

/// A column's place in a JSON record (`failure.reason` inside a group), `None` when neither
/// JSON output carries it.
fn json_field(column: &Column) -> Option<String> {
    if !(column.in_output(outputs::JSON) || column.in_output(outputs::JSON_LINES)) {
        return None;
    }
    Some(match column.json {
        JsonPlace::Top => column.name.to_string(),
        JsonPlace::In(group, name) => format!("{}.{name}", group.name()),
    })
}
